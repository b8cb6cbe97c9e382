//! Where the peak heap memory of a conversion goes: a counting global allocator records the
//! live heap bytes, their peak, and the large blocks (≥ 256 KiB) alive at the peak.
//! `cargo run --release --example memory_peak -- [a b] [dual|topology] [resolution] [obj|ply|none]`
//! (defaults: 200 × 200 quad torus, dual, resolution 2, obj; `cage` after the format keeps the
//! cage maps, the surface and the quality arrays). Converts the torus as the command
//! line does (`convert`, then the output written to a sink), and prints the peak heap bytes per
//! output vertex of each phase and the large blocks alive at the overall peak, by size (so
//! arrays can be told apart: n·24 bytes are `DVec3` per vertex, …).

use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::export::{MeshFormat, WriteMesh};
use gbsurf::mesh::generate::torus;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// Blocks at least this large are listed individually.
const LARGE: usize = 256 << 10;
/// Room for that many live large blocks.
const SLOTS: usize = 4096;

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static TRACK: AtomicBool = AtomicBool::new(false);

/// Live large blocks (address, size) and a copy of them at the last peak.
struct Large {
    live: [(usize, usize); SLOTS],
    at_peak: [(usize, usize); SLOTS],
    /// The last peak at which `at_peak` was copied.
    copied: usize,
}

static BLOCKS: Mutex<Large> = Mutex::new(Large { live: [(0, 0); SLOTS], at_peak: [(0, 0); SLOTS], copied: 0 });

fn grow(size: usize) {
    let now = LIVE.fetch_add(size, Ordering::Relaxed) + size;
    let peak = PEAK.fetch_max(now, Ordering::Relaxed).max(now);
    // Copy the large blocks when the peak rose by more than 1 MiB since the last copy.
    if now == peak && TRACK.load(Ordering::Relaxed) {
        if let Ok(mut b) = BLOCKS.try_lock() {
            if peak > b.copied + (1 << 20) {
                b.copied = peak;
                b.at_peak = b.live;
            }
        }
    }
}

fn note(ptr: *mut u8, size: usize, add: bool) {
    if size < LARGE || !TRACK.load(Ordering::Relaxed) {
        return;
    }
    if let Ok(mut b) = BLOCKS.lock() {
        let key = ptr as usize;
        if add {
            if let Some(s) = b.live.iter_mut().find(|s| s.1 == 0) {
                *s = (key, size);
            }
        } else if let Some(s) = b.live.iter_mut().find(|s| s.0 == key && s.1 != 0) {
            *s = (0, 0);
        }
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            note(p, layout.size(), true);
            grow(layout.size());
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            note(p, layout.size(), true);
            grow(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        note(ptr, layout.size(), false);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            note(ptr, layout.size(), false);
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
            note(p, new_size, true);
            grow(new_size);
        }
        p
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Resets the peak to the live bytes; returns the live bytes.
fn reset_peak() -> usize {
    let now = LIVE.load(Ordering::Relaxed);
    PEAK.store(now, Ordering::Relaxed);
    if let Ok(mut b) = BLOCKS.lock() {
        b.copied = 0;
    }
    now
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: usize| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (a, b) = (num(1, 200), num(2, 200));
    let method: Method = args.get(3).map_or(Method::Dual, |s| s.parse().expect("method"));
    let resolution = num(4, 2);
    let format = args.get(5).map_or("obj", String::as_str);
    // As the command line: no cage maps (none of its outputs reads them), no exact surface (no
    // --curves, --nets, --patches), the quality arrays only for PLY; `cage` as the 6th argument
    // keeps everything (as the C ABI and the Blender add-on).
    let all = args.get(6).is_some_and(|s| s == "cage");
    let options = ConvertOptions {
        method,
        resolution,
        max_memory_mb: 1 << 16,
        cage_maps: all,
        keep_surface: all,
        quality_arrays: all || format == "ply",
        ..Default::default()
    };
    let mesh = torus(a, b, 10.0, 3.0).expect("torus");
    TRACK.store(true, Ordering::Relaxed);
    let before = reset_peak();
    // The live and peak heap at the progress reports where the peak rose by 2 % (stage ends:
    // construction 0.08, tessellation 0.45, mesh check 0.48, self-intersections 0.95).
    let mut last = before;
    let mut stages = Vec::new();
    let mut cb = |f: f32| {
        let (live, peak) = (LIVE.load(Ordering::Relaxed), PEAK.load(Ordering::Relaxed));
        if peak > last + last / 50 {
            stages.push((f, live, peak));
            last = peak;
        }
        true
    };
    let conv = convert(&mesh, &options, Some(&mut cb)).expect("conversion");
    let convert_peak = PEAK.load(Ordering::Relaxed);
    let at_peak: Vec<usize> = {
        let b = BLOCKS.lock().unwrap();
        let mut v: Vec<usize> = b.at_peak.iter().filter(|s| s.1 != 0).map(|s| s.1).collect();
        v.sort_unstable_by(|x, y| y.cmp(x));
        v
    };
    let nv = conv.mesh.positions.len();
    let per = |bytes: usize| bytes as f64 / nv as f64;
    let after = LIVE.load(Ordering::Relaxed);
    println!(
        "torus {a}x{b} {method} r={resolution}: {nv} vertices, {} quads, {} triangles, {} patches",
        conv.mesh.quads.len(),
        conv.mesh.triangles.len(),
        conv.report.patches
    );
    println!(
        "heap before {:.1} MB; convert peak {:.1} MB = {:.1} B/vertex above before; live after {:.1} B/vertex",
        before as f64 / 1e6,
        convert_peak as f64 / 1e6,
        per(convert_peak - before),
        per(after - before)
    );
    for (f, live, peak) in &stages {
        println!("  at progress {f:.3}: live {:.1} B/vertex, peak so far {:.1} B/vertex", per(live - before), per(peak - before));
    }
    let large: usize = at_peak.iter().sum();
    println!("large blocks at the convert peak: {:.1} B/vertex in {} blocks", per(large), at_peak.len());
    let mut grouped: Vec<(usize, usize)> = Vec::new();
    for &s in &at_peak {
        match grouped.last_mut() {
            Some((size, count)) if *size == s => *count += 1,
            _ => grouped.push((s, 1)),
        }
    }
    for (size, count) in grouped.iter().take(40) {
        println!("  {count:5} × {size:>12} B = {:8.2} B/vertex  ({:.2} B per vertex each)", per(size * count), per(*size));
    }
    if format != "none" {
        let f = if format == "ply" { MeshFormat::Ply } else { MeshFormat::Obj };
        let mut out = conv;
        // As the command line's drop_unneeded.
        out.surface = None;
        out.mesh.triangle_patch = Vec::new();
        if f != MeshFormat::Ply {
            out.mesh.patch = Vec::new();
            out.mesh.mean_curvature = Vec::new();
            out.mesh.gaussian_curvature = Vec::new();
            out.mesh.g1_deviation_deg = Vec::new();
        }
        let live = reset_peak();
        out.mesh.write_format(f, &mut std::io::sink()).expect("write");
        let peak = PEAK.load(Ordering::Relaxed);
        println!("write {format}: live before {:.1} B/vertex, peak {:.1} B/vertex", per(live - before), per(peak - before));
    }
}
