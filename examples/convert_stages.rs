//! Where the wall time of one [`gbsurf::api::convert`] goes, stage by stage, read from its
//! progress reports: every stage reports its start (`Ticker::stage`), so the time between the
//! first report at or past one stage's start and the next stage's start is that stage's time.
//! `cargo run --release --example convert_stages -- [a b | model.obj] [dual|topology] [resolution]`
//! (defaults: 200 × 200 quad torus, dual, the default resolution; `MIDDLE=fair` for the fair
//! middle constraint). A warm-up conversion runs
//! first; then `RUNS` (default 3) conversions, and each stage's best wall and CPU time (all
//! threads, from /proc: steadier than wall time on a shared machine) is printed.
//! Stages (the fractions of `GB_STAGES` in src/api/mod.rs): construction (with the half-edge
//! build, the size estimate and the scale normalisation), tessellation (with the in-pass fold
//! test and the G1 measure), the output mesh check, the self-intersection search, the cage's
//! search (only when the output has self-intersections), and the rest (|H|, the report).

use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::mesh::generate::torus;
use std::time::Instant;

/// Stage starts as progress fractions (src/api/mod.rs `GB_STAGES`, with 0 in front) and names.
/// Sub-stages are indented: the construction's preparation, network, twists and patches
/// (src/construct/dual.rs, network.rs), the tessellation's setup, patch evaluation, dense fold
/// pass, and welding with normals (src/tessellate/surface.rs).
const STARTS: [(f32, &str); 12] = [
    (0.0, "construction"),
    (0.008, "  network"),
    (0.032, "  twists"),
    (0.056, "  patches"),
    (0.08, "tessellation"),
    (0.117, "  evaluation"),
    (0.376, "  dense folds"),
    (0.413, "  weld, normals"),
    (0.45, "mesh check"),
    (0.48, "self-intersections"),
    (0.95, "cage"),
    (0.99, "rest"),
];

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let file = args.get(1).filter(|s| s.ends_with(".obj")).cloned();
    let rest = if file.is_some() { 2 } else { 3 };
    let num = |i: usize, d: usize| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let mesh = match &file {
        Some(f) => gbsurf::read_mesh(f).expect("model"),
        None => torus(num(1, 200), num(2, 200), 10.0, 3.0).expect("torus"),
    };
    let mut opts = ConvertOptions::default();
    if args.get(rest).map(String::as_str) == Some("topology") {
        opts.method = Method::Topology;
    }
    opts.resolution = num(rest + 1, opts.resolution);
    // `MIDDLE=fair`: the fair middle constraint (docs/math.md#fair-middle).
    if let Some(m) = std::env::var("MIDDLE").ok().and_then(|s| s.parse().ok()) {
        opts.middle = m;
    }
    drop(convert(&mesh, &opts, None).expect("conversion"));
    let runs = std::env::var("RUNS").ok().and_then(|s| s.parse().ok()).unwrap_or(3usize).max(1);
    let mut best = [f64::INFINITY; STARTS.len()];
    let mut best_total = f64::INFINITY;
    let (mut best_cpu, mut best_total_cpu) = ([f64::INFINITY; STARTS.len()], f64::INFINITY);
    let mut vertices = 0;
    for _ in 0..runs {
        let mut starts: [Option<(f64, f64)>; STARTS.len()] = [None; STARTS.len()];
        let (t0, c0) = (Instant::now(), cpu_seconds());
        let mut cb = |f: f32| {
            for (k, (s, _)) in STARTS.iter().enumerate() {
                if f >= *s && starts[k].is_none() {
                    starts[k] = Some((t0.elapsed().as_secs_f64(), cpu_seconds() - c0));
                }
            }
            true
        };
        let c = convert(&mesh, &opts, Some(&mut cb)).expect("conversion");
        let total = (t0.elapsed().as_secs_f64(), cpu_seconds() - c0);
        vertices = c.report.vertices;
        drop(c);
        let at = |k: usize| starts.get(k).copied().flatten().unwrap_or(total);
        for k in 0..STARTS.len() {
            best[k] = best[k].min(at(k + 1).0 - at(k).0);
            best_cpu[k] = best_cpu[k].min(at(k + 1).1 - at(k).1);
        }
        best_total = best_total.min(total.0);
        best_total_cpu = best_total_cpu.min(total.1);
    }
    let name = file.unwrap_or_else(|| format!("torus {}x{}", num(1, 200), num(2, 200)));
    println!(
        "{name} {} r={}: {vertices} vertices, convert {best_total:.3} s wall, {best_total_cpu:.3} s CPU (best of {runs}; each stage its best)",
        opts.method.name(),
        opts.resolution
    );
    println!("  {:<20} {:>8} {:>7} {:>8} {:>7}", "stage", "wall s", "%", "CPU s", "%");
    for (k, (_, stage)) in STARTS.iter().enumerate() {
        let (w, c) = (best[k], best_cpu[k]);
        println!("  {stage:<20} {w:8.4} {:6.1}% {c:8.4} {:6.1}%", 100.0 * w / best_total, 100.0 * c / best_total_cpu);
    }
}

/// CPU seconds of all threads of this process so far: the sum of the first field of
/// /proc/self/task/*/schedstat (nanoseconds on the CPU; Linux). Threads that ended are not
/// counted, which does not matter here: the thread pool lives as long as the process.
fn cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else { return 0.0 };
    tasks
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum::<u64>() as f64
        * 1e-9
}
