//! Time of [`gbsurf::tessellate::SurfaceMesh::cage_loop_values`] (the keep-corners rule that
//! carries UVs to the output, docs/math.md#cage-corners) on the quad torus of `a × b` faces at the
//! default options, 2 values per cage face corner (a UV map): best of `RUNS` (default 5) wall
//! seconds and ns per output loop. `cargo run --release --example cage_values_timing -- [a b]`.

use gbsurf::api::{convert, ConvertOptions};
use std::time::Instant;

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let (a, b) = (args.first().copied().unwrap_or(200), args.get(1).copied().unwrap_or(200));
    let cage = gbsurf::mesh::generate::torus(a, b, 10.0, 3.0).unwrap();
    let c = convert(&cage, &ConvertOptions::default(), None).unwrap();
    let sizes: Vec<u32> = cage.faces.iter().map(|f| f.len() as u32).collect();
    let corners: usize = sizes.iter().map(|&s| s as usize).sum();
    let values: Vec<f32> = (0..2 * corners).map(|i| (i % 97) as f32 / 97.0).collect();
    let runs = std::env::var("RUNS").ok().and_then(|r| r.parse().ok()).unwrap_or(5);
    let mut best = f64::MAX;
    let mut loops = 0;
    for _ in 0..runs {
        let t = Instant::now();
        let out = c.mesh.cage_loop_values(&sizes[..], &values, 2).unwrap();
        best = best.min(t.elapsed().as_secs_f64());
        loops = out.len() / 2;
    }
    println!("torus {a}x{b}: {loops} loops, best {best:.4} s, {:.1} ns per loop", best * 1e9 / loops as f64);
}
