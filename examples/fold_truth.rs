//! Does the report's fold count tell the truth? `cargo run --release --example fold_truth --
//! CAGE.obj...`. Per cage and structure (default options) it prints:
//! - `report`: the patches the conversion's report counts as folded (its own tessellation samples,
//!   [`gbsurf::quality::validity`]'s rule);
//! - `rule@L`: the patches the same rule flags on the denser triangle layouts of level L = 4, 8, 16,
//!   40 ([`gbsurf::quality::find_folds`]);
//! - `flips`: the patches whose parameterisation really turns over: sampled on 60 steps per radius
//!   in every domain sector, two neighbouring samples have unit normals with a negative dot product
//!   (the normal reverses within 1/60 of the radius), with the first few: patch, cage element,
//!   sides, the smallest dot, where (sector, radius step, step along it) and min/max |S_u × S_v|;
//! - `missed`: patches with a flip where the report found no folded sample (a flipped output
//!   triangle also makes the report count a patch; this leaves those out).
//! A fold rule is right when `rule@L` approaches `flips` as L grows; a report is right when
//! `missed` is 0. This reads no reference normal, so it judges the rule from outside.

use gbsurf::gb::Evaluate;
use gbsurf::{ConvertOptions, DVec3, Method};
use rayon::prelude::*;

/// Per patch: the smallest dot of neighbouring unit normals on the fine grid, where, and
/// min/max |S_u × S_v|.
fn flip(patch: &gbsurf::construct::Patch, form: gbsurf::gb::WeightForm) -> (f64, (usize, usize, usize), f64) {
    let n = patch.sides();
    let Ok(dom) = gbsurf::gb::Domain::regular(n) else { return (1.0, (0, 0, 0), 1.0) };
    let vs = dom.vertices().to_vec();
    let l = 60usize;
    let (mut min_dot, mut at, mut lo, mut hi) = (1.0f64, (0, 0, 0), f64::MAX, 0.0f64);
    for i in 0..n {
        let (a, b) = (vs[(i + n - 1) % n], vs[i]);
        let mut grid = vec![vec![DVec3::ZERO; l + 1]; l + 1];
        for r in 0..=l {
            for t in 0..=r {
                let rr = r as f64 / l as f64;
                let tt = if r == 0 { 0.0 } else { t as f64 / r as f64 };
                let d = patch.eval_derivs(rr * ((1.0 - tt) * a + tt * b) * 0.999, form);
                let j = d.su.cross(d.sv);
                (lo, hi) = (lo.min(j.length()), hi.max(j.length()));
                grid[r][t] = j.normalize_or_zero();
            }
        }
        for r in 1..=l {
            for t in 0..=r {
                let mut take = |d: f64| {
                    if d < min_dot {
                        (min_dot, at) = (d, (i, r, t));
                    }
                };
                if t < r {
                    take(grid[r][t].dot(grid[r][t + 1]));
                }
                take(grid[r][t].dot(grid[r - 1][t.min(r - 1)]));
            }
        }
    }
    (min_dot, at, if hi > 0.0 { lo / hi } else { 0.0 })
}

fn main() {
    for file in std::env::args().skip(1) {
        let name = file.rsplit('/').next().unwrap_or(&file).to_string();
        let poly = match gbsurf::read_mesh(&file) {
            Ok(m) => m,
            Err(e) => {
                println!("{name}: {e}");
                continue;
            }
        };
        for method in [Method::Dual, Method::Topology] {
            let o = ConvertOptions { method, ..Default::default() };
            let c = match gbsurf::api::convert(&poly, &o, None) {
                Ok(c) => c,
                Err(e) => {
                    println!("{name} {}: {e}", method.name());
                    continue;
                }
            };
            let Some(s) = c.surface.as_ref() else { continue };
            let levels: Vec<usize> = [4, 8, 16, 40].iter().map(|&l| gbsurf::quality::find_folds(s, l, o.weights).patches).collect();
            let flips: Vec<(usize, (f64, (usize, usize, usize), f64))> =
                s.patches.par_iter().map(|p| flip(p, o.weights)).enumerate().filter(|(_, f)| f.0 < 0.0).collect();
            let reported: std::collections::HashSet<usize> =
                c.mesh.patch_folds.iter().enumerate().filter(|(_, f)| f.samples > 0).map(|(p, _)| p).collect();
            let missed = flips.iter().filter(|(p, _)| !reported.contains(p)).count();
            println!(
                "{name} {}: report {} rule@4,8,16,40 {:?} flips {} missed {}",
                method.name(),
                c.report.folds,
                levels,
                flips.len(),
                missed
            );
            for (p, (d, at, ratio)) in flips.iter().take(4) {
                println!("    patch {p} ({:?}, {} sides): dot {d:.3} at {at:?}, min/max |Su x Sv| {ratio:.1e}", s.sources[*p], s.patches[*p].sides());
            }
        }
    }
}
