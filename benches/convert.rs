//! End-to-end conversion of quad tori of 1k, 10k and 40k faces at resolution 4 (4·4² = 64
//! triangles per four-sided patch), both structures. Prints output vertices per second and the
//! ratio time(40k)/time(10k) (linear growth: ≤ 4.4). A plain `harness = false` main, so it runs
//! with `cargo bench --bench convert`; `-- --quick` runs each size once, `-- --resolution R`
//! changes the resolution.
//! Every size is also converted without the validity checks ([`gbsurf::api::convert_unchecked`])
//! in the same run, and the checks' share (time(with) − time(without)) / time(without) is printed
//! (goal: ≤ 30 %). Two settings are measured, one after the other: the triangle layout at
//! `--resolution R` (default 4; the setting of the rows before the quad layout, whose default
//! was triangles at r = 8: `-- --resolution 8`) and the default options (the quad layout at
//! r = 2, which `--resolution` does not change).
//! Besides wall time it prints the process CPU time of the best run (user + system, from
//! /proc/self/stat on Linux) and the load average, since the machine may be shared.
//! Then the large-n cases, once each, in ns per output vertex next to an ordinary torus: a
//! planar face of 1000 sides, a cone whose apex has valence 1000, a prism with 1000-gon caps
//! and a 100k-face torus, in both settings. An n-sided patch costs O(n) per sample
//! (docs/math.md#cost-per-point); patches of more than 64 sides are split into fans
//! (docs/math.md#high-valence-split), so ns/vertex of the 1000-sided cases should be that of the
//! torus up to a constant (`examples/large_n_scaling` sweeps n = 125 … 2000).

use gbsurf::api::{convert, convert_unchecked, ConvertOptions, Method};
use gbsurf::mesh::generate::{cone, polygon, prism, torus};
use gbsurf::mesh::PolyMesh;
use std::time::Instant;

/// User + system CPU seconds of this process so far (Linux; 0 elsewhere).
fn cpu_seconds() -> f64 {
    stat_seconds("/proc/self/stat")
}

/// CPU seconds of the calling (main) thread: the serial part (rayon's workers are other threads
/// and the main thread sleeps while it waits for them).
fn thread_cpu_seconds() -> f64 {
    stat_seconds("/proc/thread-self/stat")
}

fn stat_seconds(path: &str) -> f64 {
    let Ok(stat) = std::fs::read_to_string(path) else { return 0.0 };
    // Fields after the parenthesized command name; utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<f64> = rest.split_whitespace().skip(11).take(2).filter_map(|x| x.parse().ok()).collect();
    f.iter().sum::<f64>() / 100.0 // clock ticks (USER_HZ = 100)
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg").map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" ")).unwrap_or_default()
}

fn main() {
    println!("load average at start: {}", load_average());
    let quick = std::env::args().any(|a| a == "--quick");
    // `--resolution R` (default 4; the Blender benchmark uses 2).
    let args: Vec<String> = std::env::args().collect();
    let resolution = args.iter().position(|a| a == "--resolution").and_then(|i| args.get(i + 1)?.parse().ok()).unwrap_or(4);
    let sizes = [(40usize, 25usize), (125, 80), (250, 160)];
    // Two settings: the triangle layout at `resolution` (the rows measured before the quad
    // layout) and the default options (quads at r = 2).
    let settings: [(String, ConvertOptions); 2] = [
        (format!("triangles r={resolution}"), ConvertOptions { resolution, ..ConvertOptions::triangles_r8() }),
        (format!("default ({:?} r={})", ConvertOptions::default().layout, ConvertOptions::default().resolution).to_lowercase(), ConvertOptions::default()),
    ];
    for (setting, base) in &settings {
        println!("-- {setting}");
        for method in [Method::Dual, Method::Topology] {
            let mut times = Vec::new();
            for &(a, b) in &sizes {
                let mesh = torus(a, b, 10.0, 3.0).expect("torus");
                // The largest torus (1.6 million output vertices) is above the default memory bound.
                let opts = ConvertOptions { method, max_memory_mb: gbsurf::limits::MAX_MEMORY_MB, ..base.clone() };
                times.push(measure(&mesh, &opts, quick, setting, a * b));
            }
            println!("{method:>8} {setting}: time(40k)/time(10k) = {:.2}   (load average {})", times[2] / times[1], load_average());
        }
    }
    // Only under `cargo bench` (which passes --bench): under `cargo test --all-targets` these
    // would take minutes in the test profile.
    if std::env::args().any(|a| a == "--bench") {
        large_n_cases(resolution);
    }
}

/// Converts `mesh` with and without the validity checks (warm-up, then the best of 3 runs, 1 with
/// `quick`), prints both rows and returns the best time with the checks.
fn measure(mesh: &PolyMesh, opts: &ConvertOptions, quick: bool, setting: &str, faces: usize) -> f64 {
    let method = opts.method;
    // Warm-up (also checks the result), then the best of a few runs.
    let c = convert(mesh, opts, None).expect("conversion");
    assert!(c.report.closed, "{method}: not closed");
    let runs = if quick { 1 } else { 3 };
    let (mut best, mut best_cpu, mut best_serial) = (f64::INFINITY, 0.0, 0.0);
    for _ in 0..runs {
        let (t, cpu, serial) = (Instant::now(), cpu_seconds(), thread_cpu_seconds());
        let c = convert(mesh, opts, None).expect("conversion");
        std::hint::black_box(&c);
        // Timed without dropping the result.
        let (wall, cpu, serial) = (t.elapsed().as_secs_f64(), cpu_seconds() - cpu, thread_cpu_seconds() - serial);
        if wall < best {
            (best, best_cpu, best_serial) = (wall, cpu, serial);
        }
        drop(c);
    }
    let mut bare = f64::INFINITY;
    for _ in 0..runs {
        let t = Instant::now();
        let u = convert_unchecked(mesh, opts).expect("conversion");
        std::hint::black_box(&u);
        bare = bare.min(t.elapsed().as_secs_f64());
        drop(u);
    }
    let verts = c.report.vertices as f64;
    println!(
        "{method:>8} {setting} torus {faces:>6} quads: {:>8} vertices {:>8} triangles  {:>8.3} s (cpu {:.2} s, main thread {:.2} s)  {:>6.2} M vertices/s  (max G1 {:.1e}°, gap {:.1e})",
        c.report.vertices,
        c.report.triangles,
        best,
        best_cpu,
        best_serial,
        verts / best / 1e6,
        c.report.max_g1_deg,
        c.report.max_boundary_gap,
    );
    println!(
        "{method:>8} {setting} torus {faces:>6} quads: without checks {bare:.3} s, with {best:.3} s: checks {:.3} s = {:.1} % of the conversion (folds {}, self-intersections {})",
        best - bare,
        100.0 * (best - bare) / bare,
        c.report.folds,
        c.report.self_intersections,
    );
    best
}

/// The large-n cases (run once each): seconds, output vertices and ns per output vertex.
fn large_n_cases(resolution: usize) {
    let cases: Vec<(&str, PolyMesh)> = vec![
        ("torus 40x25", torus(40, 25, 10.0, 3.0).expect("torus")),
        ("polygon 1000", polygon(1000).expect("polygon")),
        ("cone 1000", cone(1000).expect("cone")),
        ("prism 1000", prism(1000).expect("prism")),
        ("torus 400x250 (100k faces)", torus(400, 250, 10.0, 3.0).expect("torus")),
    ];
    let settings = [
        (format!("triangles r={resolution}"), ConvertOptions { resolution, ..ConvertOptions::triangles_r8() }),
        ("default (quads r=2)".to_string(), ConvertOptions::default()),
    ];
    for (setting, base) in &settings {
        println!("-- large n, {setting}");
        for method in [Method::Dual, Method::Topology] {
            for (name, mesh) in &cases {
                let opts = ConvertOptions { method, max_memory_mb: gbsurf::limits::MAX_MEMORY_MB, ..base.clone() };
                let t = Instant::now();
                let c = convert(mesh, &opts, None).expect("conversion");
                let wall = t.elapsed().as_secs_f64();
                println!(
                    "{method:>8} {name:<28} {:>8.3} s {:>9} vertices {:>9.0} ns/vertex  (valid {})",
                    wall,
                    c.report.vertices,
                    wall * 1e9 / c.report.vertices.max(1) as f64,
                    c.report.valid,
                );
            }
        }
    }
}
