//! Spatial PH quintics in quaternion form (seed 004 §2.2; Farouki, "Pythagorean-Hodograph
//! Curves", ch. 22 and 25; Farouki, al-Kandari & Sakkalis 2002; Farouki, Giannelli, Manni &
//! Sestini 2008): r′(t) = A(t) i A*(t) with a quadratic quaternion preimage A(t), so
//! |r′| = |A|² is a polynomial and the Euler–Rodrigues frame is rational.

use super::error::{check_finite3, PhError};
use super::poly;
use super::quaternion::Quaternion;
use crate::bezier::BezierCurve;
use glam::DVec3;
use std::f64::consts::FRAC_PI_2;

/// A spatial PH quintic r(t) = p0 + ∫_0^t A i A* du with
/// A(t) = A0 (1−t)² + 2 A1 (1−t)t + A2 t² (Bernstein coefficients `a`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialPhQuintic {
    /// Start point r(0).
    pub p0: DVec3,
    /// Bernstein coefficients A0, A1, A2 of the quaternion preimage.
    pub a: [Quaternion; 3],
}

/// The angle φ1 of the middle quaternion root, fixed: right-multiplying A(t) by exp(iθ) leaves
/// r′ = A i A* unchanged and shifts φ0, φ1, φ2 together, so only φ0 − φ1 and φ2 − φ1 matter.
pub const PHI1: f64 = -FRAC_PI_2;

/// The quaternions A with A i A* = v, a circle parameterized by φ (Farouki et al. 2002):
/// with v = |v|(λ, μ, ν),
/// A(φ) = √(|v|(1+λ)/2) (−sin φ + cos φ i) + √(|v|/(2(1+λ))) ((μ cos φ + ν sin φ) j + (ν cos φ − μ sin φ) k).
/// For λ < 0 the factor 1 + λ is computed as (μ² + ν²)/(1 − λ) (no cancellation); for
/// v = −|v| i (1 + λ = 0) the limit along μ > 0, √|v| (cos φ j − sin φ k), is used.
/// Returns 0 for v = 0.
pub fn i_sandwich_root(v: DVec3, phi: f64) -> Quaternion {
    let n = v.length();
    if n == 0.0 {
        return Quaternion::ZERO;
    }
    let (l, m, nu) = (v.x / n, v.y / n, v.z / n);
    let s = if l >= 0.0 {
        1.0 + l
    } else {
        (m * m + nu * nu) / (1.0 - l)
    };
    let (sp, cp) = phi.sin_cos();
    if s > 0.0 {
        let c = (n * s / 2.0).sqrt();
        let k = (n / (2.0 * s)).sqrt();
        Quaternion::new(
            -c * sp,
            c * cp,
            k * (m * cp + nu * sp),
            k * (nu * cp - m * sp),
        )
    } else {
        let r = n.sqrt();
        Quaternion::new(0.0, 0.0, r * cp, -r * sp)
    }
}

impl SpatialPhQuintic {
    /// Curve from its start point and preimage coefficients; errors on non-finite input.
    pub fn new(p0: DVec3, a: [Quaternion; 3]) -> Result<Self, PhError> {
        check_finite3("p0", None, p0)?;
        if let Some(i) = a.iter().position(|q| !q.is_finite()) {
            return Err(PhError::NonFinite {
                arg: "a",
                index: Some(i),
            });
        }
        Ok(Self { p0, a })
    }

    /// Bézier control points: p_{k+1} = p_k + leg_k with legs A0 i A0*/5, vec(A0 i A1*)/5,
    /// (2 A1 i A1* + vec(A0 i A2*))/15, vec(A1 i A2*)/5, A2 i A2*/5, where
    /// A_j i A_k* + A_k i A_j* = 2 vec(A_j i A_k*) (Farouki eq. 22.11).
    pub fn control_points(&self) -> [DVec3; 6] {
        let [a0, a1, a2] = self.a;
        let legs = [
            a0.i_sandwich() / 5.0,
            a0.i_product_vec(a1) / 5.0,
            (a1.i_sandwich() * 2.0 + a0.i_product_vec(a2)) / 15.0,
            a1.i_product_vec(a2) / 5.0,
            a2.i_sandwich() / 5.0,
        ];
        let mut p = [self.p0; 6];
        for k in 0..5 {
            p[k + 1] = p[k] + legs[k];
        }
        p
    }

    /// The curve as a degree-5 Bézier curve.
    pub fn bezier(&self) -> BezierCurve<DVec3> {
        BezierCurve::from_vec(self.control_points().to_vec())
    }

    /// End point r(1).
    pub fn end_point(&self) -> DVec3 {
        self.control_points()[5]
    }

    /// r(t) by de Casteljau.
    pub fn eval(&self, t: f64) -> DVec3 {
        poly::de_casteljau(self.control_points(), t)
    }

    /// A(t) = A0 (1−t)² + 2 A1 (1−t)t + A2 t².
    pub fn preimage(&self, t: f64) -> Quaternion {
        let s = 1.0 - t;
        let [a0, a1, a2] = self.a;
        a0 * (s * s) + a1 * (2.0 * s * t) + a2 * (t * t)
    }

    /// A′(t) = 2[(A1 − A0)(1−t) + (A2 − A1)t].
    pub fn preimage_derivative(&self, t: f64) -> Quaternion {
        let [a0, a1, a2] = self.a;
        ((a1 - a0) * (1.0 - t) + (a2 - a1) * t) * 2.0
    }

    /// Hodograph r′(t) = A(t) i A*(t) (seed 004 §2.2.2).
    pub fn derivative(&self, t: f64) -> DVec3 {
        self.preimage(t).i_sandwich()
    }

    /// r″(t) = A′ i A* + A i A′* = 2 vec(A′ i A*).
    pub fn second_derivative(&self, t: f64) -> DVec3 {
        self.preimage_derivative(t).i_product_vec(self.preimage(t)) * 2.0
    }

    /// Parametric speed σ(t) = |r′(t)| = |A(t)|².
    pub fn speed(&self, t: f64) -> f64 {
        self.preimage(t).norm_sqr()
    }

    /// Bernstein coefficients of σ: |A0|², A0·A1, (2|A1|² + A0·A2)/3, A1·A2, |A2|² (4D dot
    /// products).
    pub fn speed_coeffs(&self) -> [f64; 5] {
        let [a0, a1, a2] = self.a;
        [
            a0.norm_sqr(),
            a0.dot(a1),
            (2.0 * a1.norm_sqr() + a0.dot(a2)) / 3.0,
            a1.dot(a2),
            a2.norm_sqr(),
        ]
    }

    /// Bernstein coefficients of the arc length s(t): s_0 = 0, s_k = s_{k−1} + σ_{k−1}/5.
    pub fn arc_length_coeffs(&self) -> [f64; 6] {
        poly::arc_length_coeffs(&self.speed_coeffs())
    }

    /// Total arc length (exact).
    pub fn arc_length(&self) -> f64 {
        self.arc_length_coeffs()[5]
    }

    /// Arc length s(t) from 0 to t.
    pub fn arc_length_at(&self, t: f64) -> f64 {
        poly::de_casteljau(self.arc_length_coeffs(), t)
    }

    /// The parameter t with s(t) = `s` (Newton with bisection safeguard).
    pub fn param_at_arc_length(&self, s: f64) -> Result<f64, PhError> {
        poly::invert_arc_length(&self.arc_length_coeffs(), &self.speed_coeffs(), s)
    }

    /// The Euler–Rodrigues frame (e1, e2, e3) = (A i A*, A j A*, A k A*)/|A|²: orthonormal,
    /// rational, with e1 the unit tangent. `None` where A(t) = 0.
    pub fn frame(&self, t: f64) -> Option<[DVec3; 3]> {
        let a = self.preimage(t);
        let s = a.norm_sqr();
        if s == 0.0 {
            return None;
        }
        Some([
            a.sandwich(DVec3::X) / s,
            a.sandwich(DVec3::Y) / s,
            a.sandwich(DVec3::Z) / s,
        ])
    }

    /// Curvature κ = |r′ × r″|/|r′|³ (zero-free speed assumed; infinite where A = 0).
    pub fn curvature(&self, t: f64) -> f64 {
        let s = self.speed(t);
        if s == 0.0 {
            return f64::INFINITY;
        }
        self.derivative(t).cross(self.second_derivative(t)).length() / (s * s * s)
    }

    /// Bending energy ∫ κ² ds = ∫_0^1 |r′ × r″|²/σ⁵ dt by the adaptive Gauss–Legendre rule of
    /// the planar case.
    pub fn bending_energy(&self) -> f64 {
        poly::integrate(|t| {
            let c = self
                .derivative(t)
                .cross(self.second_derivative(t))
                .length_squared();
            let s = self.speed(t);
            c / (s * s * s * s * s)
        })
    }

    /// First-order Hermite interpolant r(0) = p0, r′(0) = d0, r(1) = p1, r′(1) = d1 with free
    /// angles φ0, φ2 (Farouki et al. 2002, 2008): A0 = [`i_sandwich_root`](d0, φ0),
    /// A2 = i_sandwich_root(d1, φ2), Z = i_sandwich_root(V, φ1 = −π/2) with
    /// V = 120Δp − 15(d0 + d1) + 5(A0 i A2* + A2 i A0*), and A1 = (Z − 3(A0 + A2))/4, the
    /// quaternion form of the planar w1 formula (∫ r′ = Δp).
    pub fn hermite(
        p0: DVec3,
        d0: DVec3,
        p1: DVec3,
        d1: DVec3,
        phi0: f64,
        phi2: f64,
    ) -> Result<Self, PhError> {
        check_hermite(p0, d0, p1, d1)?;
        if !phi0.is_finite() {
            return Err(PhError::NonFinite {
                arg: "phi0",
                index: None,
            });
        }
        if !phi2.is_finite() {
            return Err(PhError::NonFinite {
                arg: "phi2",
                index: None,
            });
        }
        Ok(Self::hermite_unchecked(p0, d0, p1, d1, phi0, phi2))
    }

    fn hermite_unchecked(p0: DVec3, d0: DVec3, p1: DVec3, d1: DVec3, phi0: f64, phi2: f64) -> Self {
        let a0 = i_sandwich_root(d0, phi0);
        let a2 = i_sandwich_root(d1, phi2);
        let v = (p1 - p0) * 120.0 - (d0 + d1) * 15.0 + a0.i_product_vec(a2) * 10.0;
        let z = i_sandwich_root(v, PHI1);
        let a1 = (z - (a0 + a2) * 3.0) * 0.25;
        Self {
            p0,
            a: [a0, a1, a2],
        }
    }

    /// The default Hermite interpolant: among (φ0, φ2) ∈ {−π/2, π/2}² the one of least bending
    /// energy (ties: the first in that order). With φ1 = −π/2 these four choices give, for data
    /// in the xy plane, exactly the four planar PH quintic interpolants (A then lies in the
    /// subalgebra span{1, k} ≅ ℂ), so planar data reproduce the planar interpolant of least
    /// bending energy. This is not the shape-optimal choice of Farouki et al. 2008 for general
    /// spatial data.
    pub fn hermite_default(p0: DVec3, d0: DVec3, p1: DVec3, d1: DVec3) -> Result<Self, PhError> {
        check_hermite(p0, d0, p1, d1)?;
        let mut best: Option<(f64, Self)> = None;
        for phi0 in [-FRAC_PI_2, FRAC_PI_2] {
            for phi2 in [-FRAC_PI_2, FRAC_PI_2] {
                let c = Self::hermite_unchecked(p0, d0, p1, d1, phi0, phi2);
                let e = c.bending_energy();
                if best.as_ref().map_or(true, |(b, _)| e < *b) {
                    best = Some((e, c));
                }
            }
        }
        Ok(best.expect("four candidates").1)
    }
}

fn check_hermite(p0: DVec3, d0: DVec3, p1: DVec3, d1: DVec3) -> Result<(), PhError> {
    check_finite3("p0", None, p0)?;
    check_finite3("d0", None, d0)?;
    check_finite3("p1", None, p1)?;
    check_finite3("d1", None, d1)?;
    if d0 == DVec3::ZERO {
        return Err(PhError::ZeroDerivative {
            arg: "d0",
            index: None,
        });
    }
    if d1 == DVec3::ZERO {
        return Err(PhError::ZeroDerivative {
            arg: "d1",
            index: None,
        });
    }
    let size = p0.abs().max(p1.abs()).max_element();
    if (p1 - p0).length() <= f64::EPSILON * size || p1 == p0 {
        return Err(PhError::CoincidentPoints {
            arg: "p0, p1",
            index: 0,
        });
    }
    Ok(())
}
