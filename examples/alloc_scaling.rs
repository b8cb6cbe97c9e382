//! Allocations and time of a conversion without the checks ([`gbsurf::api::convert_unchecked`],
//! default options) for the 10k- and 40k-quad tori of `benches/convert.rs` (125 × 80 and
//! 250 × 160), both structures: the allocation count and peak heap of one run (a counting global
//! allocator), then the median and best wall time of `R` runs and time(40k)/time(10k) of each.
//! `cargo run --release --example alloc_scaling [-- R [dual|topology] [10k|40k]]` (default R = 7,
//! both structures and sizes; one structure and size for a profiler).

use gbsurf::api::{convert_unchecked, ConvertOptions, Method};
use gbsurf::mesh::generate::torus;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

struct Counting;

static COUNT: AtomicUsize = AtomicUsize::new(0);
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grow(size: usize) {
    let now = LIVE.fetch_add(size, Ordering::Relaxed) + size;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        COUNT.fetch_add(1, Ordering::Relaxed);
        grow(layout.size());
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        COUNT.fetch_add(1, Ordering::Relaxed);
        grow(layout.size());
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        COUNT.fetch_add(1, Ordering::Relaxed);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        grow(new_size);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// CPU seconds of all threads of this process so far (the first field of each thread's
/// /proc/self/task/*/schedstat, in ns; Linux, 0 elsewhere): less disturbed by other processes
/// on a shared machine than wall time.
fn cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else { return 0.0 };
    let ns: u64 = tasks
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum();
    ns as f64 * 1e-9
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg").map(|s| s.trim().to_string()).unwrap_or_default()
}

fn main() {
    let repeats: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(7).max(1);
    println!("load average at start: {}", load_average());
    let sizes = [("10k", 125usize, 80usize), ("40k", 250, 160)];
    let only_method: Option<Method> = std::env::args().nth(2).map(|s| s.parse().expect("method"));
    let only_size = std::env::args().nth(3);
    for method in [Method::Dual, Method::Topology] {
        if only_method.is_some_and(|m| m != method) {
            continue;
        }
        let options = ConvertOptions { method, max_memory_mb: 1 << 16, ..ConvertOptions::default() };
        let mut medians = Vec::new();
        let mut bests = Vec::new();
        for (name, a, b) in sizes {
            if only_size.as_ref().is_some_and(|s| s != name) {
                continue;
            }
            let mesh = torus(a, b, 10.0, 3.0).expect("torus");
            let (count0, live0) = (COUNT.load(Ordering::Relaxed), LIVE.load(Ordering::Relaxed));
            PEAK.store(live0, Ordering::Relaxed);
            let conv = convert_unchecked(&mesh, &options).expect("conversion");
            let allocs = COUNT.load(Ordering::Relaxed) - count0;
            let peak = PEAK.load(Ordering::Relaxed) - live0;
            let vertices = conv.mesh.positions.len();
            drop(conv);
            let (mut times, mut cpu): (Vec<f64>, Vec<f64>) = (0..repeats)
                .map(|_| {
                    let (t, c) = (Instant::now(), cpu_seconds());
                    let conv = convert_unchecked(&mesh, &options).expect("conversion");
                    let s = (t.elapsed().as_secs_f64(), cpu_seconds() - c);
                    drop(conv);
                    s
                })
                .unzip();
            times.sort_by(f64::total_cmp);
            cpu.sort_by(f64::total_cmp);
            let (median, best) = (times[times.len() / 2], times[0]);
            let (cpu_median, cpu_best) = (cpu[cpu.len() / 2], cpu[0]);
            println!(
                "{method:>8} {name} ({a}x{b}): {vertices} vertices, {allocs} allocations, peak {:.1} MB; \
                 wall median {median:.4} s best {best:.4} s, cpu median {cpu_median:.4} s best {cpu_best:.4} s \
                 of {repeats}",
                peak as f64 / 1e6
            );
            medians.push([median, cpu_median]);
            bests.push([best, cpu_best]);
        }
        if medians.len() == 2 {
            let r = |x: &[[f64; 2]], i: usize| x[1][i] / x[0][i];
            println!(
                "{method:>8} time(40k)/time(10k): wall median {:.3} best {:.3}; cpu median {:.3} best {:.3}",
                r(&medians, 0),
                r(&bests, 0),
                r(&medians, 1),
                r(&bests, 1)
            );
        }
    }
    println!("load average at end: {}", load_average());
}
