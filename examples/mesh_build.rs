//! The cost of reading a cage into the half-edge structure
//! ([`gbsurf::mesh::HalfEdgeMesh::from_polymesh`]: the checks of `check_polymesh` and the build)
//! for quad tori, the first step of every conversion. `cargo run --release --example mesh_build
//! [-- NU NV [R]]` (default 250 × 160, the 40k torus of `benches/convert.rs`, R = 9 runs) prints
//! the median and best wall time per run and per face. For instruction counts, which the noisy
//! shared machine cannot spoil: `valgrind --tool=callgrind --toggle-collect='*from_polymesh*'
//! target/release/examples/mesh_build NU NV 1`.

use gbsurf::mesh::generate::torus;
use gbsurf::mesh::HalfEdgeMesh;
use std::time::Instant;

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let (nu, nv, runs) = (args.first().copied().unwrap_or(250), args.get(1).copied().unwrap_or(160), args.get(2).copied().unwrap_or(9));
    let mesh = torus(nu, nv, 10.0, 3.0).expect("torus sizes");
    let mut times: Vec<f64> = (0..runs.max(1))
        .map(|_| {
            let t = Instant::now();
            let he = HalfEdgeMesh::from_polymesh(&mesh).expect("a valid torus");
            let s = t.elapsed().as_secs_f64();
            std::hint::black_box(he);
            s
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let faces = mesh.faces.len() as f64;
    let (median, best) = (times[times.len() / 2], times[0]);
    println!(
        "{nu}x{nv} ({} faces): from_polymesh median {:.4} s, best {:.4} s ({:.1} ns per face)",
        mesh.faces.len(),
        median,
        best,
        best / faces * 1e9
    );
}
