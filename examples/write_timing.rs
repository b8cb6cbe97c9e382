//! Times the mesh writers alone on a converted quad torus and measures the memory they add:
//! `cargo run --release --example write_timing -- [a b] [DIR]` (defaults: 200 × 200 quads, the
//! system temporary directory). For OBJ, PLY and STL: seconds, M output vertices/s, the file
//! size, and the peak resident memory while writing above the resident memory before it (the
//! kernel's peak is reset through `/proc/self/clear_refs`, Linux only), per output vertex.

use gbsurf::api::{convert, ConvertOptions};
use gbsurf::mesh::generate::torus;
use std::time::Instant;

/// `VmRSS` and `VmHWM` of this process in bytes.
fn rss() -> (u64, u64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status.lines().find_map(|l| l.strip_prefix(name)).and_then(|v| v.trim().trim_end_matches(" kB").trim().parse::<u64>().ok()).unwrap_or(0) * 1024
    };
    (field("VmRSS:"), field("VmHWM:"))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: usize| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (a, b) = (num(1, 200), num(2, 200));
    let dir = args.get(3).map(std::path::PathBuf::from).unwrap_or_else(std::env::temp_dir);
    let mesh = torus(a, b, 10.0, 3.0).expect("torus");
    let conv = convert(&mesh, &ConvertOptions::triangles_r8(), None).expect("conversion");
    drop(mesh);
    let out = conv.mesh;
    drop(conv.surface);
    let nv = out.positions.len();
    println!("torus {a}x{b}: {nv} output vertices, {} triangles", out.triangles.len());
    for ext in ["obj", "ply", "stl"] {
        let path = dir.join(format!("gbsurf_write_timing_{}.{ext}", std::process::id()));
        let _ = std::fs::write("/proc/self/clear_refs", "5");
        let (before, _) = rss();
        let t = Instant::now();
        out.write_file(&path).expect("write");
        let s = t.elapsed().as_secs_f64();
        let (_, peak) = rss();
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        let _ = std::fs::remove_file(&path);
        let extra = peak.saturating_sub(before);
        println!(
            "{ext}: {s:.3} s  {:.2} M vertices/s  {:.0} MB file  writer peak +{:.1} MB = {:.1} bytes/vertex (resident before {:.1} bytes/vertex)",
            nv as f64 / s / 1e6,
            size as f64 / 1e6,
            extra as f64 / 1e6,
            extra as f64 / nv as f64,
            before as f64 / nv as f64
        );
    }
}
