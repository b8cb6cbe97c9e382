//! Which per-patch measures of the tessellation's own samples separate the patches that really
//! flip from the clean ones? `cargo run --release --example fold_clear_study -- CAGE.obj...`.
//! Per cage and structure, per patch: the smallest dot of a sample's normal with its blended
//! reference ([`gbsurf::tessellate::fold::blended_reference`]), the smallest dot of neighbouring
//! samples' normals (layout triangle edges), min/mean |S_u × S_v| over the samples, and whether
//! the patch flips on the dense sampler (`common/fine.rs`, 60 steps). Prints the flipped patches'
//! measures and, for the clean ones, the worst values.

#[path = "common/fine.rs"]
mod fine;

use gbsurf::gb::{Evaluate, SampleLayout};
use gbsurf::tessellate::evaluator::{GbSurfaceEvaluator, PatchEvaluator};
use gbsurf::tessellate::fold::{blended_reference, centre_reference, ribbon_normal, Binomials, Sectors};
use gbsurf::DVec3;
use rayon::prelude::*;

fn main() {
    fine::for_each_surface(|name, method, o, s| {
        let Ok(eval) = GbSurfaceEvaluator::new(s, o.sampling(), o.weights) else { return };
        let rows: Vec<(usize, bool, f64, f64, f64, f64)> = s
            .patches
            .par_iter()
            .enumerate()
            .map(|(p, patch)| {
                let n = patch.sides();
                let dom = eval.domain(n);
                let layout = SampleLayout::new(&dom, o.sampling()).unwrap();
                let sectors = Sectors::new(&dom, &layout.uv);
                let mut buf = Vec::new();
                eval.evaluate(s, p, &layout, &mut buf);
                let ribbons = patch.ribbons();
                let centre = centre_reference(ribbons, &mut Binomials::default(), || {
                    sectors.centre_sample().map_or(DVec3::ZERO, |k| buf[k].normal)
                });
                let mut min_ref = 1.0f64;
                for (k, sp) in buf.iter().enumerate() {
                    let (i, t) = sectors.at()[k];
                    let r = blended_reference(ribbon_normal(&ribbons[i as usize], t), centre, sectors.centre_weights()[k]);
                    if sp.normal != DVec3::ZERO && r != DVec3::ZERO {
                        min_ref = min_ref.min(sp.normal.dot(r));
                    }
                }
                let mut min_nb = 1.0f64;
                for t in &layout.triangles {
                    for e in 0..3 {
                        let (a, b) = (buf[t[e] as usize].normal, buf[t[(e + 1) % 3] as usize].normal);
                        if a != DVec3::ZERO && b != DVec3::ZERO {
                            min_nb = min_nb.min(a.dot(b));
                        }
                    }
                }
                let j: Vec<f64> = layout.uv.iter().map(|&uv| {
                    let d = patch.eval_derivs(uv, o.weights);
                    d.su.cross(d.sv).length()
                }).collect();
                let mean = j.iter().sum::<f64>() / j.len() as f64;
                let jmin = j.iter().copied().fold(f64::INFINITY, f64::min) / mean;
                // Largest |H| times the patch's boundary-sample extent (scale-free curvature).
                let (lo, hi) = buf.iter().fold((DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)), |(l, h), sp| (l.min(sp.position), h.max(sp.position)));
                let diag = (hi - lo).length();
                let hmax = buf.iter().map(|sp| sp.mean_curvature.abs()).fold(0.0, f64::max) * diag;
                let flip = fine::neighbour_normals(patch, o.weights, 60).0 < 0.0;
                (p, flip, min_ref, min_nb, jmin, hmax)
            })
            .collect();
        let flips = rows.iter().filter(|r| r.1).count();
        println!("{name} {}: {} patches, {} flip", method.name(), rows.len(), flips);
        for r in rows.iter().filter(|r| r.1) {
            println!("   FLIP p{} ref {:.3} nb {:.3} jmin {:.1e} |H|d {:.1}", r.0, r.2, r.3, r.4, r.5);
        }
        let clean: Vec<_> = rows.iter().filter(|r| !r.1).collect();
        let worst = |f: &dyn Fn(&&(usize, bool, f64, f64, f64, f64)) -> f64| clean.iter().map(f).fold(f64::INFINITY, f64::min);
        println!(
            "   clean worst: ref {:.3} nb {:.3} jmin {:.1e} |H|d {:.1}",
            worst(&|r| r.2), worst(&|r| r.3), worst(&|r| r.4), -worst(&|r| -r.5)
        );
        // How many clean patches fall below thresholds.
        for (tr, tn, tj) in [(0.5, 0.5, 1e-2), (0.3, 0.3, 1e-2), (0.5, 0.5, 3e-2), (0.7, 0.7, 5e-2)] {
            let fail = |r: &&(usize, bool, f64, f64, f64, f64)| r.2 < tr || r.3 < tn || r.4 < tj;
            println!(
                "   thresholds ref<{tr} nb<{tn} jmin<{tj}: clean uncleared {}, flips uncleared {}",
                clean.iter().filter(|r| fail(r)).count(),
                rows.iter().filter(|r| r.1).filter(|r| fail(r)).count()
            );
        }
    });
}
