//! The per-point timing harness shared by the evaluation benchmarks (`gb_eval`, `pn_eval`):
//! median wall and CPU ns per point of short repeated runs.

use std::time::{Duration, Instant};

/// CPU time of this thread in ns (Linux `/proc/thread-self/schedstat`), if available: the
/// machine may be shared, so per-core cost is measured in CPU time, not wall time.
pub fn thread_cpu_ns() -> Option<u64> {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// Median (wall, CPU) ns per point of `f` (which evaluates `points` points) over short runs.
pub fn ns_per_point(points: usize, mut f: impl FnMut()) -> (f64, f64) {
    f();
    let mut wall = Vec::new();
    let mut cpu = Vec::new();
    for _ in 0..5 {
        let start = Instant::now();
        let c0 = thread_cpu_ns();
        let mut reps = 0;
        while start.elapsed() < Duration::from_millis(60) {
            f();
            reps += 1;
        }
        let pts = (reps * points) as f64;
        wall.push(start.elapsed().as_nanos() as f64 / pts);
        if let (Some(a), Some(b)) = (c0, thread_cpu_ns()) {
            cpu.push((b - a) as f64 / pts);
        }
    }
    let median = |mut v: Vec<f64>| {
        if v.is_empty() {
            return f64::NAN;
        }
        v.sort_by(|a, b| a.total_cmp(b));
        v[v.len() / 2]
    };
    (median(wall), median(cpu))
}
