//! Seconds and ns per output vertex of the large-n cases (n-gon, cone apex of valence n, prism
//! with n-gon caps) for n = 125..1000, both structures, default options: how the cost grows
//! with n at a fixed resolution. `cargo run --release --example large_n_scaling [-- N...]`.
use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::mesh::generate::{cone, polygon, prism};
use std::time::Instant;

fn main() {
    let ns: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let ns = if ns.is_empty() { vec![125, 250, 500, 1000] } else { ns };
    for method in [Method::Dual, Method::Topology] {
        for &n in &ns {
            for (name, mesh) in [("polygon", polygon(n).unwrap()), ("cone", cone(n).unwrap()), ("prism", prism(n).unwrap())] {
                // `ONLY=topology:polygon` runs one case (for a profiler).
                if let Ok(only) = std::env::var("ONLY") {
                    if only != format!("{method}:{name}") {
                        continue;
                    }
                }
                let opts = ConvertOptions { method, ..ConvertOptions::default() };
                let t = Instant::now();
                let r = convert(&mesh, &opts, None);
                let wall = t.elapsed().as_secs_f64();
                match r {
                    Ok(c) => {
                        if std::env::var("CERT").is_ok() {
                            let cert = gbsurf::quality::Certified::of_mesh(&c.mesh);
                            println!("  certified patches {} of {}, core sectors {}; fold sites {:?}", cert.certified_patches(), cert.patches(), cert.certified_core_sectors(), c.report.fold_sites.iter().take(3).collect::<Vec<_>>());
                        }
                        println!(
                        "{method:>8} {name:<8} n={n:<5} {wall:>8.3} s {:>8} vertices {:>10.0} ns/vertex valid {} folds {} flipped {}",
                        c.report.vertices,
                        wall * 1e9 / c.report.vertices.max(1) as f64,
                        c.report.valid,
                        c.report.folds,
                        c.report.flipped_triangles
                    )},
                    Err(e) => println!("{method:>8} {name:<8} n={n:<5} error {e}"),
                }
            }
        }
    }
}
