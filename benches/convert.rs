//! End-to-end conversion of quad tori of 1k, 10k and 40k faces at resolution 4 (4·4² = 64
//! triangles per four-sided patch), both structures. Prints output vertices per second and the
//! ratio time(40k)/time(10k) (linear growth: ≤ 4.4). A plain `harness = false` main, so it runs
//! with `cargo bench --bench convert`; `-- --quick` runs each size once.

use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::mesh::generate::torus;
use std::time::Instant;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let sizes = [(40usize, 25usize), (125, 80), (250, 160)];
    for method in [Method::Dual, Method::Topology] {
        let mut times = Vec::new();
        for &(a, b) in &sizes {
            let mesh = torus(a, b, 10.0, 3.0).expect("torus");
            let opts = ConvertOptions { method, resolution: 4, ..Default::default() };
            // Warm-up (also checks the result), then the best of a few runs.
            let c = convert(&mesh, &opts, None).expect("conversion");
            assert!(c.report.closed, "{method}: not closed");
            let runs = if quick { 1 } else { 3 };
            let mut best = f64::INFINITY;
            for _ in 0..runs {
                let t = Instant::now();
                let c = convert(&mesh, &opts, None).expect("conversion");
                best = best.min(t.elapsed().as_secs_f64());
                std::hint::black_box(&c);
            }
            let verts = c.report.vertices as f64;
            println!(
                "{method:>8} torus {:>6} quads: {:>8} vertices {:>8} triangles  {:>8.3} s  {:>6.2} M vertices/s  (max G1 {:.1e}°, gap {:.1e})",
                a * b,
                c.report.vertices,
                c.report.triangles,
                best,
                verts / best / 1e6,
                c.report.max_g1_deg,
                c.report.max_boundary_gap,
            );
            times.push(best);
        }
        println!("{method:>8} time(40k)/time(10k) = {:.2}", times[2] / times[1]);
    }
}
