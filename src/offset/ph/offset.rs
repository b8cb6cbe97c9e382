//! The exact rational offset of a planar PH quintic (seed 004 §1.5; Farouki ch. 17.3;
//! Algorithm 952 `PHquintic_offset`).
//!
//! With the right-hand unit normal n = −i w²/σ (σ = |w|²) the offset at signed distance d is
//! r_d = r + d n = (σ r − i d w²)/σ: a rational curve of degree 9 with the quartic σ as
//! denominator. In Bernstein form, with the product rule
//! B^4_j B^5_l = C(4,j) C(5,l)/C(9,j+l) B^9_{j+l} and r′ = w² = 5 Σ Δp_j B^4_j
//! (degree-elevated to 9 by multiplying with Σ_l B^5_l = 1):
//!   W_k = Σ_j c_{kj} σ_j,   Q_k = Σ_j c_{kj} (σ_j p_{k−j} − 5 i d Δp_j),
//!   c_{kj} = C(4,j) C(5,k−j) / C(9,k),  max(0,k−5) ≤ j ≤ min(4,k),
//! and the control points are P_k = Q_k / W_k with weights W_k. Cusps: r_d′ = σ T (1 + dκ), so
//! the offset is regular where 1 + dκ ≠ 0 and cusps at the roots of 1 + dκ(t) = 0, i.e. of the
//! degree-8 polynomial σ² + 2dN (κ = 2N/σ²). With d > 0 to the right and κ > 0 for left turns,
//! cusps occur where the curve turns right (κ < 0) with radius 1/|κ| ≤ d, and for d < 0 where
//! it turns left with 1/κ ≤ |d|: always on the concave side.

use super::complex::Complex;
use super::error::PhError;
use super::planar::PlanarPhQuintic;
use super::poly;
use crate::bezier::bernstein::binomial;
use crate::bezier::RationalCurve;
use glam::{DVec2, DVec3};

/// The offset of a planar PH quintic at distance d as a degree-9 rational Bézier curve.
#[derive(Debug, Clone, PartialEq)]
pub struct RationalOffset {
    /// Signed offset distance (positive to the right of the direction of travel).
    pub distance: f64,
    /// Control points P_0..P_9 (affine, P_k = Q_k / W_k).
    pub points: Vec<DVec2>,
    /// Weights W_0..W_9: the Bernstein coefficients of σ(t) raised to degree 9. σ > 0 on [0, 1]
    /// but single weights may be negative for very uneven preimages.
    pub weights: Vec<f64>,
    /// Parameters in [0, 1] where the offset has a cusp (roots of 1 + dκ(t) = 0), ascending.
    pub cusps: Vec<f64>,
}

impl RationalOffset {
    /// Homogeneous control points (W_k P_k, W_k).
    pub fn homogeneous(&self) -> Vec<DVec3> {
        self.points
            .iter()
            .zip(&self.weights)
            .map(|(p, &w)| (*p * w).extend(w))
            .collect()
    }

    /// The offset point at t: de Casteljau on the homogeneous points, then division by the
    /// weight σ(t) > 0.
    pub fn eval(&self, t: f64) -> DVec2 {
        let mut h = [DVec3::ZERO; 10];
        for (k, (p, &w)) in self.points.iter().zip(&self.weights).take(10).enumerate() {
            h[k] = (*p * w).extend(w);
        }
        let q = poly::de_casteljau(h, t);
        q.truncate() / q.z
    }

    /// True when the offset has no cusp on [0, 1].
    pub fn is_regular(&self) -> bool {
        self.cusps.is_empty()
    }

    /// The offset as a [`RationalCurve`] of the `bezier` layer; errors when a weight is not
    /// positive (that layer requires positive weights).
    pub fn to_rational_curve(&self) -> Result<RationalCurve<DVec2>, PhError> {
        Ok(RationalCurve::new(
            self.points.clone(),
            self.weights.clone(),
        )?)
    }
}

impl PlanarPhQuintic {
    /// The exact offset at signed distance `d` (positive to the right), with its cusp
    /// parameters. Errors when d is zero or not finite, when w vanishes on [0, 1], or when a
    /// weight is exactly zero.
    pub fn offset(&self, d: f64) -> Result<RationalOffset, PhError> {
        if !d.is_finite() {
            return Err(PhError::NonFinite {
                arg: "d",
                index: None,
            });
        }
        if d == 0.0 {
            return Err(PhError::ZeroOffsetDistance);
        }
        self.check_regular()?;
        let p = self.control_points();
        let sigma = self.speed_coeffs();
        let c9 = |k: usize| binomial(9, k);
        let mut weights = Vec::with_capacity(10);
        let mut points = Vec::with_capacity(10);
        for k in 0..=9usize {
            let (lo, hi) = (k.saturating_sub(5), k.min(4));
            let mut wk = 0.0;
            let mut qk = Complex::ZERO;
            for j in lo..=hi {
                let c = binomial(4, j) * binomial(5, k - j) / c9(k);
                let dpj = Complex::from_vec(p[j + 1] - p[j]);
                wk += c * sigma[j];
                qk += (Complex::from_vec(p[k - j]) * sigma[j] - Complex::I * dpj * (5.0 * d)) * c;
            }
            if wk == 0.0 {
                return Err(PhError::ZeroOffsetWeight { index: k });
            }
            weights.push(wk);
            points.push(qk.to_vec() / wk);
        }
        Ok(RationalOffset {
            distance: d,
            points,
            weights,
            cusps: self.offset_cusps(d),
        })
    }

    /// Parameters in [0, 1] where the offset at distance d cusps: roots of 1 + dκ(t) = 0,
    /// computed as the roots of the polynomial σ² + 2dN (κ = 2N/σ², N = Im(conj(w) w′)).
    pub fn offset_cusps(&self, d: f64) -> Vec<f64> {
        let (sigma, n) = self.speed_and_turning_power();
        let f = poly::lin(1.0, &poly::mul(&sigma, &sigma), 2.0 * d, &n);
        poly::roots_in(&f, 0.0, 1.0)
    }
}
