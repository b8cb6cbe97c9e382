//! Does the report's fold count tell the truth? `cargo run --release --example fold_truth --
//! CAGE.obj...`. Per cage and structure (default options; `MIDDLE=fair` for the fair middle
//! constraint) it prints:
//! - `report`: the patches the conversion's report counts as folded (its own tessellation samples,
//!   [`gbsurf::quality::validity`]'s rule);
//! - `rule@L`: the patches the same rule flags on the denser triangle layouts of level L = 4, 8, 16,
//!   40 ([`gbsurf::quality::find_folds`]);
//! - `flips`: the patches whose parameterisation really turns over: sampled on 60 steps per radius
//!   in every domain sector, two neighbouring samples have unit normals with a negative dot product
//!   (the normal reverses within 1/60 of the radius), with the first few: patch, cage element,
//!   sides, the smallest dot, where (sector, radius step, step along it) and min/max |S_u × S_v|;
//! - `missed`: patches with a flip where the report found no folded sample (a flipped output
//!   triangle also makes the report count a patch; this leaves those out), and which;
//! - `not flipped`: patches with folded samples in the report but no flip;
//! - `dense`: patches the tessellation's samples did not clear, which the dense pass decided.
//! A fold rule is right when `rule@L` approaches `flips` as L grows; a report is right when
//! `missed` is 0. This reads no reference normal, so it judges the rule from outside.

#[path = "common/fine.rs"]
mod fine;

use gbsurf::{ConvertOptions, Method};
use rayon::prelude::*;

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
            let middle: gbsurf::Middle = std::env::var("MIDDLE").ok().and_then(|s| s.parse().ok()).unwrap_or_default();
            let o = ConvertOptions { method, middle, ..Default::default() };
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
                s.patches.par_iter().map(|p| fine::neighbour_normals(p, o.weights, 60)).enumerate().filter(|(_, f)| f.0 < 0.0).collect();
            let reported: std::collections::HashSet<usize> =
                c.mesh.patch_folds.iter().enumerate().filter(|(_, f)| f.samples > 0).map(|(p, _)| p).collect();
            let missed: Vec<usize> = flips.iter().map(|(p, _)| *p).filter(|p| !reported.contains(p)).collect();
            let flipped: std::collections::HashSet<usize> = flips.iter().map(|(p, _)| *p).collect();
            let mut extra: Vec<usize> = reported.iter().copied().filter(|p| !flipped.contains(p)).collect();
            extra.sort_unstable();
            let dense = c.mesh.patch_folds.iter().filter(|f| f.dense).count();
            println!(
                "{name} {}: report {} rule@4,8,16,40 {:?} flips {} missed {} {missed:?} not flipped {extra:?} dense {dense}/{} flipped triangles {}",
                method.name(),
                c.report.folds,
                levels,
                flips.len(),
                missed.len(),
                s.patches.len(),
                c.mesh.flipped_triangles.len()
            );
            for (p, (d, at, ratio)) in flips.iter().take(4) {
                println!("    patch {p} ({:?}, {} sides): dot {d:.3} at {at:?}, min/max |Su x Sv| {ratio:.1e}", s.sources[*p], s.patches[*p].sides());
            }
        }
    }
}
