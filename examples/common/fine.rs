//! Dense normal sampling shared by the fold studies (`fold_study`, `fold_truth`).

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
