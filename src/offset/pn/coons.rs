//! The bicubically blended Coons patch with cubic Hermite boundary curves, in the isotropic model
//! (seed 004 §4.5).
//!
//! With corners a_kl (k along u, l along v), u-derivatives γ_kl and v-derivatives δ_kl, the
//! seed's combined form is
//! y(u, v) = (F0 G0 F1 G1)(u) · M · (F0 G0 F1 G1)(v)ᵀ,
//! M = [[a00, δ00, a01, δ01], [γ00, 0, γ01, 0], [a10, δ10, a11, δ11], [γ10, 0, γ11, 0]],
//! i.e. the tensor-product bicubic Hermite patch with zero twists. It equals S_c + S_d − B of
//! the seed. The cross-boundary derivative along an edge is the linear blend F0·δ + F1·δ (or γ)
//! of the two end derivatives of that edge, so patches sharing the edge data join C¹.

use crate::bezier::{BezierError, BezierSurface};
use glam::DVec3;

/// Cubic Hermite basis (seed 004 §4.5, corrected): F0 = 2t³ − 3t² + 1, G0 = t³ − 2t² + t,
/// F1 = −2t³ + 3t², G1 = t³ − t², in the order (F0, G0, F1, G1). The seed prints F0 twice and
/// gives G1 = −2t³ + 3t².
pub fn hermite(t: f64) -> [f64; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    [
        2.0 * t3 - 3.0 * t2 + 1.0,
        t3 - 2.0 * t2 + t,
        -2.0 * t3 + 3.0 * t2,
        t3 - t2,
    ]
}

/// Derivatives of [`hermite`]: F0' = 6t² − 6t, G0' = 3t² − 4t + 1, F1' = −6t² + 6t,
/// G1' = 3t² − 2t.
pub fn hermite_d(t: f64) -> [f64; 4] {
    let t2 = t * t;
    [
        6.0 * t2 - 6.0 * t,
        3.0 * t2 - 4.0 * t + 1.0,
        -6.0 * t2 + 6.0 * t,
        3.0 * t2 - 2.0 * t,
    ]
}

/// Value and first partials of an isotropic patch at one (u, v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsoPartials {
    /// y(u, v).
    pub y: DVec3,
    /// ∂y/∂u.
    pub y_u: DVec3,
    /// ∂y/∂v.
    pub y_v: DVec3,
}

/// One Coons patch in the isotropic model: corners `a[k][l]` = y at (u, v) = (k, l), with
/// u-derivatives `du[k][l]` (γ) and v-derivatives `dv[k][l]` (δ) there (seed 004 §4.5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoonsPatch {
    /// Corner values a_kl.
    pub a: [[DVec3; 2]; 2],
    /// Corner u-derivatives γ_kl.
    pub du: [[DVec3; 2]; 2],
    /// Corner v-derivatives δ_kl.
    pub dv: [[DVec3; 2]; 2],
}

impl CoonsPatch {
    /// Sum over the Hermite matrix M of seed 004 §4.5 with basis values `hu` in u and `hv` in v.
    fn contract(&self, hu: &[f64; 4], hv: &[f64; 4]) -> DVec3 {
        let (a, g, d) = (&self.a, &self.du, &self.dv);
        let col = |k: usize| a[k][0] * hv[0] + d[k][0] * hv[1] + a[k][1] * hv[2] + d[k][1] * hv[3];
        let tw = |k: usize| g[k][0] * hv[0] + g[k][1] * hv[2];
        col(0) * hu[0] + tw(0) * hu[1] + col(1) * hu[2] + tw(1) * hu[3]
    }

    /// y(u, v) = (F0 G0 F1 G1)(u) · M · (F0 G0 F1 G1)(v)ᵀ.
    pub fn eval(&self, u: f64, v: f64) -> DVec3 {
        self.contract(&hermite(u), &hermite(v))
    }

    /// y and its first partials (seed 004 §4.5: the basis in one variable is replaced by its
    /// derivative).
    pub fn partials(&self, u: f64, v: f64) -> IsoPartials {
        let (hu, hv) = (hermite(u), hermite(v));
        let (du, dv) = (hermite_d(u), hermite_d(v));
        IsoPartials {
            y: self.contract(&hu, &hv),
            y_u: self.contract(&du, &hv),
            y_v: self.contract(&hu, &dv),
        }
    }

    /// The same patch as a bicubic tensor-product Bézier surface (control grid [i][j], i along u):
    /// Hermite → Bézier per direction (p1 = p0 + t0/3, p2 = p3 − t1/3), zero twist, so the inner
    /// points are p_11 = a00 + γ00/3 + δ00/3 and likewise at the other corners. Errors only
    /// when a field is not finite.
    pub fn to_bezier(&self) -> Result<BezierSurface<DVec3>, BezierError> {
        let (a, g, d) = (&self.a, &self.du, &self.dv);
        // Sign of the 1/3 offset for Bézier index 1 (from corner 0: +) or 2 (from corner 1: −).
        let corner = |i: usize| if i < 2 { 0 } else { 1 };
        let sign = |i: usize| match i {
            1 => 1.0,
            2 => -1.0,
            _ => 0.0,
        };
        let grid = (0..4)
            .map(|i| {
                (0..4)
                    .map(|j| {
                        let (k, l) = (corner(i), corner(j));
                        a[k][l] + g[k][l] * (sign(i) / 3.0) + d[k][l] * (sign(j) / 3.0)
                    })
                    .collect()
            })
            .collect();
        BezierSurface::new(grid)
    }
}
