//! `gbsurf offset` (gbsurf::api::offset: GB surface → PN pieces → offset mesh and report) on a
//! 10k-quad torus next to a plain convert of the same mesh with the same options, in one run.
//! A plain `harness = false` main: `cargo bench --bench offset`; `-- --quick` runs each once,
//! `-- --resolution R` changes the resolution (default 4), `-- --grid N` the PN grid (default 4).
//! Prints wall seconds (best of 3), the ratio offset/convert and the report's figures.
//! Under `cargo test --all-targets` (no `--bench` argument: the test profile) it runs once on a
//! 128-quad torus at resolution 2, as a smoke test of the harness.

use gbsurf::api::{convert, offset, ConvertOptions, Method, OffsetOptions};
use gbsurf::mesh::generate::torus;
use std::time::Instant;

fn best_of<T>(runs: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..runs {
        let t = Instant::now();
        let r = f();
        best = best.min(t.elapsed().as_secs_f64());
        last = Some(r);
    }
    (best, last.expect("at least one run"))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str, default: usize| args.iter().position(|a| a == name).and_then(|i| args.get(i + 1)?.parse().ok()).unwrap_or(default);
    let bench = args.iter().any(|a| a == "--bench");
    let runs = if !bench || args.iter().any(|a| a == "--quick") { 1 } else { 3 };
    let resolution = arg("--resolution", if bench { 4 } else { 2 });
    let grid = arg("--grid", gbsurf::limits::DEFAULT_OFFSET_GRID);
    let mesh = if bench { torus(125, 80, 10.0, 3.0) } else { torus(16, 8, 10.0, 3.0) }.expect("torus");
    for method in [Method::Topology, Method::Dual] {
        let opts = ConvertOptions { method, resolution, ..Default::default() };
        let (tc, c) = best_of(runs, || convert(&mesh, &opts, None).expect("convert"));
        let off = OffsetOptions { distance: 0.5, grid, shell: false };
        let (to, o) = best_of(runs, || offset(&mesh, &opts, &off).expect("offset"));
        let r = &o.report;
        println!(
            "{method} torus {} quads, resolution {resolution}, grid {grid}: convert {tc:.3} s ({} vertices), offset {to:.3} s ({} vertices), ratio {:.1}",
            mesh.faces.len(),
            c.report.vertices,
            r.vertices,
            to / tc
        );
        println!(
            "  pieces {} (singular {}), max fit {:.2e}, normal residual {:.2e}, offset error {:.2e}, gap {:.2e} (PN {:.2e}), cusps {}, closed {}",
            r.pieces, r.singular_pieces, r.max_fit_error, r.max_normal_residual, r.max_offset_error, r.max_gap, r.max_gap_pn, r.cusps, r.closed
        );
    }
}
