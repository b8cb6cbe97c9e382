//! Dense normal sampling shared by the fold studies (`fold_study`, `fold_truth`, `fold_clear_study`,
//! `fold_disagree`) and the fold tests, and the studies' loop over the cages of the command line.

use gbsurf::gb::{Evaluate, WeightForm};
use gbsurf::DVec3;

/// Samples `patch` on `l` steps per radius in every domain sector (points 0.999 of the way to the
/// boundary at most) and returns the smallest dot product of neighbouring samples' unit normals,
/// where it is (sector, radius step, step along it), and min/max |S_u × S_v|. A Jacobian sign
/// change shows as a dot near −1 and a ratio near 0; a patch that only bends keeps both away.
pub fn neighbour_normals(patch: &gbsurf::construct::Patch, form: WeightForm, l: usize) -> (f64, (usize, usize, usize), f64) {
    let n = patch.sides();
    let Ok(dom) = gbsurf::gb::Domain::regular(n) else { return (1.0, (0, 0, 0), 1.0) };
    let vs = dom.vertices().to_vec();
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

/// Every cage named on the command line, converted with default options by both structures:
/// `study(cage file name, method, options, surface)`. Unreadable cages and refused conversions
/// are skipped (the studies look at surfaces; `fold_truth` reports the refusals itself).
#[allow(dead_code)] // not every includer studies cages
pub fn for_each_surface(mut study: impl FnMut(&str, gbsurf::Method, &gbsurf::ConvertOptions, &gbsurf::construct::Surface)) {
    for file in std::env::args().skip(1) {
        let name = file.rsplit('/').next().unwrap_or(&file).to_string();
        let Ok(poly) = gbsurf::read_mesh(&file) else { continue };
        for method in [gbsurf::Method::Dual, gbsurf::Method::Topology] {
            let o = gbsurf::ConvertOptions { method, ..Default::default() };
            let Ok(c) = gbsurf::api::convert(&poly, &o, None) else { continue };
            if let Some(s) = c.surface.as_ref() {
                study(&name, method, &o, s);
            }
        }
    }
}
