//! Evaluation of GB patches and ribbons: points, first and second derivatives, normals and
//! curvature (seed 000 eq. 2.24; seed 002 "A felület egyenlete").

use super::derivs::{Curvature, SurfaceDerivs};
use super::error::GbError;
use super::patch::{GbPatch, Ribbon, WeightForm};
use super::weights::{layers_for_degree, GbBasis, GbBasisEvaluator};
use crate::bezier::bernstein::bernstein_all_into;
use glam::{DVec2, DVec3};

impl Ribbon {
    /// Row k as a Bézier curve of degree `degree` at s (zero vector for a missing row).
    pub fn row_point(&self, k: usize, s: f64) -> DVec3 {
        let Some(row) = self.get_row(k) else {
            return DVec3::ZERO;
        };
        let mut b = vec![0.0; row.len().max(1)];
        bernstein_all_into(row.len().saturating_sub(1), s, &mut b);
        row.iter().zip(&b).map(|(p, w)| *p * *w).sum()
    }

    /// The boundary curve (row 0) at s.
    pub fn boundary_point(&self, s: f64) -> DVec3 {
        self.row_point(0, s)
    }

    /// d/ds of the boundary curve: d Σ_j (P_{j+1,0} − P_{j,0}) B^{d−1}_j(s).
    pub fn boundary_tangent(&self, s: f64) -> DVec3 {
        let Some(row) = self.get_row(0) else {
            return DVec3::ZERO;
        };
        if row.len() < 2 {
            return DVec3::ZERO;
        }
        let d = row.len() - 1;
        let mut b = vec![0.0; d];
        bernstein_all_into(d - 1, s, &mut b);
        (0..d)
            .map(|j| (row[j + 1] - row[j]) * (d as f64 * b[j]))
            .sum()
    }

    /// The ribbon's cross-boundary derivative d Σ_j (P_{j,1} − P_{j,0}) B^d_j(s) (derivative
    /// with respect to h of the ribbon surface Σ P_{j,k} B^d_j(s) B^d_k(h) at h = 0).
    pub fn cross_derivative(&self, s: f64) -> DVec3 {
        if self.layers() < 2 {
            return DVec3::ZERO;
        }
        let d = self.degree as f64;
        (self.row_point(1, s) - self.row_point(0, s)) * d
    }

    /// Unit normal of the ribbon along the boundary: tangent × cross-derivative, normalized
    /// (None where they are parallel). For a GB patch this is the patch normal on side i
    /// (squared weights; the domain's side direction and inward normal keep orientation).
    pub fn boundary_normal(&self, s: f64) -> Option<DVec3> {
        let c = self.boundary_tangent(s).cross(self.cross_derivative(s));
        let l = c.length();
        (l > 1e-300 && l.is_finite()).then(|| c / l)
    }
}

impl GbPatch {
    /// Number of sides n.
    pub fn n(&self) -> usize {
        self.ribbons.len()
    }

    /// Degree d (of side 0; [`Self::validate`] checks all sides agree).
    pub fn degree(&self) -> usize {
        self.ribbons.first().map_or(0, |r| r.degree)
    }

    /// Layers l = ⌈d/2⌉.
    pub fn layers(&self) -> usize {
        layers_for_degree(self.degree())
    }

    /// Checks n ≥ 3, one degree 2 ≤ d ≤ [`crate::limits::MAX_DEGREE`] on every side, l = ⌈d/2⌉
    /// rows of d+1 points per side and finite coordinates everywhere: what evaluation needs.
    pub fn validate(&self) -> Result<(), GbError> {
        self.check(true).map(|_| ())
    }

    /// The shape part of [`Self::validate`] alone: n ≥ 3 ribbons of one degree d ≥ 1, each with
    /// l = ⌈d/2⌉ rows of d + 1 points. Returns d. Enough to list or copy the points of a
    /// connected net ([`crate::gb::connected`]), which is also defined for d = 1.
    pub fn check_shape(&self) -> Result<usize, GbError> {
        self.check(false)
    }

    /// The one GB patch validator: the shape, and with `evaluable` also the degree range and
    /// finiteness. Returns d.
    fn check(&self, evaluable: bool) -> Result<usize, GbError> {
        let n = self.n();
        if n < 3 {
            return Err(GbError::TooFewSides(n));
        }
        let d = self.degree();
        if !evaluable && d < 1 {
            return Err(GbError::DegreeTooLow { side: 0, degree: d });
        }
        validate_ribbons(&self.ribbons, evaluable, |i, r| {
            if r.degree != d {
                return Err(GbError::DegreeMismatch {
                    side: i,
                    expected: d,
                    found: r.degree,
                });
            }
            if r.layers() != layers_for_degree(d) {
                return Err(GbError::LayerCount {
                    side: i,
                    expected: layers_for_degree(d),
                    found: r.layers(),
                });
            }
            Ok(())
        })?;
        if evaluable && !self.center.is_finite() {
            return Err(GbError::NonFinite {
                side: None,
                row: 0,
                col: 0,
            });
        }
        Ok(d)
    }

    /// Control points in the flat basis order: central point, then side i, row k, column j
    /// (see [`crate::gb::weights`]). Meaningful for a valid patch.
    pub fn control_points_flat(&self) -> Vec<DVec3> {
        let mut out = Vec::with_capacity(GbBasis::len_for(self.n(), self.degree()));
        out.push(self.center);
        for r in &self.ribbons {
            out.extend_from_slice(r.points());
        }
        out
    }

    /// A basis evaluator matching this patch's n and d (reuse it for many evaluations).
    pub fn evaluator(&self) -> Result<GbBasisEvaluator, GbError> {
        GbBasisEvaluator::new(self.n(), self.degree())
    }

    /// S(u, v) and its first and second derivatives with a prepared evaluator (no allocation).
    /// The evaluator must match n and d; control points missing from a malformed patch are
    /// skipped (call [`Self::validate`] first).
    pub fn eval_derivs_with(&self, ev: &mut GbBasisEvaluator, uv: DVec2) -> SurfaceDerivs {
        self.eval_derivs_with_form(ev, uv, WeightForm::Squared)
    }

    /// As [`Self::eval_derivs_with`] with an explicit weight form.
    pub fn eval_derivs_with_form(
        &self,
        ev: &mut GbBasisEvaluator,
        uv: DVec2,
        form: WeightForm,
    ) -> SurfaceDerivs {
        let l = ev.layers();
        let d1 = ev.degree() + 1;
        let mut out = SurfaceDerivs::default();
        // The weights come in flat order (side i, row k, column j): count along instead of
        // dividing the flat index.
        let (mut i, mut k, mut j) = (0usize, 0usize, 0usize);
        let b0 = ev.for_each_ribbon_weight(uv, form, |_, w| {
            if let Some(p) = self.ribbons.get(i).and_then(|r| r.get_row(k)).and_then(|row| row.get(j)) {
                out.add_weighted(&w, *p);
            }
            j += 1;
            if j == d1 {
                j = 0;
                k += 1;
                if k == l {
                    k = 0;
                    i += 1;
                }
            }
        });
        out.add_weighted(&b0, self.center);
        out
    }

}

/// Point evaluation shared by the patch types (GB, CGB, and any patch of a constructed
/// surface): each gives S(u, v) with its derivatives, the rest follows from
/// [`SurfaceDerivs`]. Each call allocates an evaluator; for many points use the patch's
/// `evaluator()` and `eval_derivs_with…`, or a weight table.
pub trait Evaluate {
    /// S(u, v) with its first and second derivatives.
    fn eval_derivs(&self, uv: DVec2, form: WeightForm) -> SurfaceDerivs;

    /// S(u, v) (seed 000 eq. 2.24 for GB, eq. 3.8 for CGB).
    fn eval(&self, uv: DVec2, form: WeightForm) -> DVec3 {
        self.eval_derivs(uv, form).p
    }

    /// Unit normal at (u, v), None where S_u × S_v vanishes.
    fn normal(&self, uv: DVec2, form: WeightForm) -> Option<DVec3> {
        self.eval_derivs(uv, form).normal()
    }

    /// Mean / Gaussian / principal curvatures at (u, v) (see [`Curvature`] for signs).
    fn curvature(&self, uv: DVec2, form: WeightForm) -> Option<Curvature> {
        self.eval_derivs(uv, form).curvature()
    }
}

impl Evaluate for GbPatch {
    /// For a patch with n < 3 or d < 2: the central point with zero derivatives.
    fn eval_derivs(&self, uv: DVec2, form: WeightForm) -> SurfaceDerivs {
        match self.evaluator() {
            Ok(mut ev) => self.eval_derivs_with_form(&mut ev, uv, form),
            Err(_) => SurfaceDerivs {
                p: self.center,
                ..Default::default()
            },
        }
    }
}

/// Shared row-shape checks, with `evaluable` also the degree range and finiteness;
/// `extra(i, ribbon)` adds per-patch rules (checked after the degree range, before the rows).
pub(crate) fn validate_ribbons(
    ribbons: &[super::patch::Ribbon],
    evaluable: bool,
    mut extra: impl FnMut(usize, &super::patch::Ribbon) -> Result<(), GbError>,
) -> Result<(), GbError> {
    for (i, r) in ribbons.iter().enumerate() {
        if evaluable {
            super::weights::check_degree(i, r.degree)?;
        }
        extra(i, r)?;
        for (k, row) in r.rows().enumerate() {
            if row.len() != r.degree + 1 {
                return Err(GbError::RowLength {
                    side: i,
                    row: k,
                    expected: r.degree + 1,
                    found: row.len(),
                });
            }
            if !evaluable {
                continue;
            }
            if let Some(j) = row.iter().position(|p| !p.is_finite()) {
                return Err(GbError::NonFinite {
                    side: Some(i),
                    row: k,
                    col: j,
                });
            }
        }
    }
    Ok(())
}
