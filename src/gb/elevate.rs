//! Degree elevation of a GB patch d → d+1 (seed 002, "Fokszám emelés"): exact on the boundary
//! curves and on the cross-boundary derivatives, approximate inside.
//!
//! Each ribbon is elevated as the tensor-product Bézier net it is a part of:
//! P'_{j,k} = Σ_{a,b∈{0,1}} c_a(j) c_b(k) G(j−a, k−b) with c_1(m) = m/(d+1), c_0(m) = 1 − m/(d+1),
//! where G(j, k) is the side's own point for k < l; for k = l (only when d is even, l' = l+1)
//! the point is taken by the connected-structure sharing rules (docs/math.md#sharing):
//! j < l → side i−1, row j, column d−k; d−j < l → side i+1, row d−j, column k; else the centre.
//! Rows 0 and 1 of the result depend only on rows 0 and 1, so the boundary (row 0 elevated) and
//! the cross-derivative d(row1 − row0) are reproduced exactly. The new central point keeps the
//! surface point at the domain centre (when its weight there is not ~0, else it is kept).
//! For n = 4 with shared corner blocks this is the exact tensor-product elevation.

use super::error::GbError;
use super::eval::Evaluate;
use super::patch::{GbPatch, Ribbon, WeightForm};
use super::weights::{layers_for_degree, GbBasisEvaluator};
use glam::{DVec2, DVec3};

impl GbPatch {
    /// The degree-(d+1) patch with the same boundary curves and cross-derivatives.
    pub fn elevate(&self) -> Result<GbPatch, GbError> {
        self.validate()?;
        let n = self.n();
        let d = self.degree();
        let l = self.layers();
        let d1 = d + 1;
        let l1 = layers_for_degree(d1);
        let grid = |i: usize, j: usize, k: usize| -> DVec3 {
            if k < l {
                self.ribbons[i].row(k)[j]
            } else if j < l {
                self.ribbons[(i + n - 1) % n].row(j)[d - k]
            } else if d - j < l {
                self.ribbons[(i + 1) % n].row(d - j)[k]
            } else {
                self.center
            }
        };
        let c = |m: usize, a: usize| -> f64 {
            let t = m as f64 / d1 as f64;
            if a == 1 {
                t
            } else {
                1.0 - t
            }
        };
        let ribbons = (0..n)
            .map(|i| {
                Ribbon::from_fn(d1, l1, d1 + 1, |k, j| {
                    let mut p = DVec3::ZERO;
                    for a in 0..2 {
                        for b in 0..2 {
                            let w = c(j, a) * c(k, b);
                            if w != 0.0 && j >= a && k >= b && j - a <= d {
                                p += grid(i, j - a, k - b) * w;
                            }
                        }
                    }
                    p
                })
            })
            .collect();
        let mut out = GbPatch {
            ribbons,
            center: self.center,
        };
        // keep S(0) (α = β = ½ at the centre for both weight forms)
        let target = self.eval(DVec2::ZERO, WeightForm::Squared);
        let mut ev = GbBasisEvaluator::new(n, d1)?;
        let pts = out.control_points_flat();
        let mut rest = DVec3::ZERO;
        let b0 = ev.for_each_ribbon_weight(DVec2::ZERO, WeightForm::Squared, |idx, w| {
            rest += pts[idx] * w.val
        });
        if b0.val.abs() > 1e-6 {
            out.center = (target - rest) / b0.val;
        }
        Ok(out)
    }

    /// Elevates until the degree is at least `degree` (a no-op when it already is).
    pub fn elevate_to(&self, degree: usize) -> Result<GbPatch, GbError> {
        let mut p = self.clone();
        p.validate()?;
        while p.degree() < degree {
            p = p.elevate()?;
        }
        Ok(p)
    }
}
