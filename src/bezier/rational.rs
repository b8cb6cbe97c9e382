//! Rational (weighted) Bézier curves and exact circles (seed 001 §2.4 eq. 2.15 for the curve
//! analogue, §3 for circle weights).
//!
//! Note on seed 001 §3: it lists the circle weights as alternating 0.25 and √2/2. A quadratic
//! arc is circular only when w_1/w_0 = cos(θ/2) with equal end weights, so for quarter arcs the
//! weights alternate 1 and √2/2 (any common multiple gives the same curve); the ratio
//! (√2/2)/0.25 does not give a circle. The constructors here use 1 and cos(θ/2).

use super::bernstein::binomial;
use super::curve::BezierCurve;
use super::{BezierError, Point};
use glam::DVec3;

/// R(t) = Σ w_i p_i B^n_i(t) / Σ w_i B^n_i(t): the central projection of the homogeneous
/// Bézier curve (w_i p_i, w_i). Weights are finite and positive, so the denominator is positive
/// on [0, 1]; scaling all weights by one factor leaves the curve unchanged.
#[derive(Debug, Clone, PartialEq)]
pub struct RationalCurve<P> {
    points: Vec<P>,
    weights: Vec<f64>,
}

impl<P: Point> RationalCurve<P> {
    /// Rational curve from control points and their weights.
    pub fn new(points: Vec<P>, weights: Vec<f64>) -> Result<Self, BezierError> {
        // Validates the points (non-empty, finite).
        BezierCurve::new(points.clone())?;
        if weights.len() != points.len() {
            return Err(BezierError::WeightCount {
                got: weights.len(),
                expected: points.len(),
            });
        }
        if let Some(index) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(BezierError::BadWeight {
                index,
                value: weights[index],
            });
        }
        Ok(Self { points, weights })
    }

    /// Internal constructor without validation (weights from positive combinations).
    pub(crate) fn from_parts(points: Vec<P>, weights: Vec<f64>) -> Self {
        Self { points, weights }
    }

    /// A polynomial curve as a rational one with unit weights.
    pub fn from_polynomial(c: &BezierCurve<P>) -> Self {
        Self {
            points: c.points().to_vec(),
            weights: vec![1.0; c.points().len()],
        }
    }

    /// Degree n.
    pub fn degree(&self) -> usize {
        self.points.len() - 1
    }

    /// Control points p_i.
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// Weights w_i.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The numerator curve N(t) = Σ (w_i p_i) B^n_i(t) (homogeneous coordinates).
    pub fn numerator(&self) -> BezierCurve<P> {
        BezierCurve::from_vec(
            self.points
                .iter()
                .zip(&self.weights)
                .map(|(&p, &w)| p * w)
                .collect(),
        )
    }

    /// The denominator W(t) = Σ w_i B^n_i(t).
    pub fn denominator(&self) -> BezierCurve<f64> {
        BezierCurve::from_vec(self.weights.clone())
    }

    fn from_homogeneous(num: BezierCurve<P>, den: BezierCurve<f64>) -> Self {
        let weights = den.into_points();
        let points = num
            .into_points()
            .into_iter()
            .zip(&weights)
            .map(|(p, &w)| p * (1.0 / w))
            .collect();
        Self { points, weights }
    }

    /// R(t) by de Casteljau on the homogeneous points (w_i p_i, w_i) (seed 001 §3:
    /// w^n_i = (1 − t) w^{n−1}_i + t w^{n−1}_{i+1}).
    pub fn eval(&self, t: f64) -> P {
        self.numerator().eval(t) * (1.0 / self.denominator().eval(t))
    }

    /// R(t), R′(t), …, R^{(r)}(t) from the Leibniz rule applied to N = W·R:
    /// R^{(k)} = (N^{(k)} − Σ_{i=1}^{k} C(k, i) W^{(i)} R^{(k−i)}) / W.
    /// For k = 1: R′ = (N′ − W′R)/W; k = 2: R″ = (N″ − 2W′R′ − W″R)/W.
    pub fn derivatives(&self, t: f64, r: usize) -> Vec<P> {
        let n = self.numerator().derivatives(t, r);
        let w = self.denominator().derivatives(t, r);
        let mut out: Vec<P> = Vec::with_capacity(r + 1);
        for k in 0..=r {
            let s = (1..=k).fold(n[k], |acc, i| acc - out[k - i] * (binomial(k, i) * w[i]));
            out.push(s * (1.0 / w[0]));
        }
        out
    }

    /// The r-th derivative at t.
    pub fn derivative(&self, t: f64, r: usize) -> P {
        self.derivatives(t, r)[r]
    }

    /// Degree elevation by k: elevate the homogeneous curve (w_i p_i, w_i) (seed 001 eq. 1.22).
    pub fn elevate_by(&self, k: usize) -> Self {
        Self::from_homogeneous(
            self.numerator().elevate_by(k),
            self.denominator().elevate_by(k),
        )
    }

    /// Degree elevation by one.
    pub fn elevate(&self) -> Self {
        self.elevate_by(1)
    }

    /// Subdivision at t of the homogeneous curve.
    pub fn subdivide(&self, t: f64) -> (Self, Self) {
        let (nl, nr) = self.numerator().subdivide(t);
        let (wl, wr) = self.denominator().subdivide(t);
        (
            Self::from_homogeneous(nl, wl),
            Self::from_homogeneous(nr, wr),
        )
    }

    /// The same curve traversed backwards.
    pub fn reversed(&self) -> Self {
        Self {
            points: self.points.iter().rev().copied().collect(),
            weights: self.weights.iter().rev().copied().collect(),
        }
    }

    /// Map the control points, keeping the weights: maps the curve for affine maps.
    pub fn map<Q: Point>(&self, f: impl FnMut(P) -> Q) -> RationalCurve<Q> {
        RationalCurve {
            points: self.points.iter().copied().map(f).collect(),
            weights: self.weights.clone(),
        }
    }
}

impl RationalCurve<DVec3> {
    /// Exact circular arc in the plane z = center.z: a quadratic rational curve with control
    /// points c + r(cos θ0, sin θ0), c + r/cos(φ/2)·(cos(θ0+φ/2), sin(θ0+φ/2)), c + r(cos(θ0+φ),
    /// sin(θ0+φ)) and weights 1, cos(φ/2), 1, for a sweep φ ∈ (0, π).
    pub fn circular_arc(
        center: DVec3,
        radius: f64,
        theta0: f64,
        sweep: f64,
    ) -> Result<Self, BezierError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(BezierError::BadRadius { radius });
        }
        if !(sweep > 0.0 && sweep < std::f64::consts::PI) {
            return Err(BezierError::BadSweep { sweep });
        }
        let half = 0.5 * sweep;
        let dir = |a: f64| DVec3::new(a.cos(), a.sin(), 0.0);
        let points = vec![
            center + dir(theta0) * radius,
            center + dir(theta0 + half) * (radius / half.cos()),
            center + dir(theta0 + sweep) * radius,
        ];
        Self::new(points, vec![1.0, half.cos(), 1.0])
    }

    /// Exact full circle in the plane z = center.z as four quadratic quarter arcs starting at
    /// angle 0: the control polygon is the circumscribed square, corner weights √2/2, edge
    /// midpoints 1 (seed 001 fig. 3.3).
    pub fn full_circle(center: DVec3, radius: f64) -> Result<[Self; 4], BezierError> {
        let q = std::f64::consts::FRAC_PI_2;
        Ok([
            Self::circular_arc(center, radius, 0.0, q)?,
            Self::circular_arc(center, radius, q, q)?,
            Self::circular_arc(center, radius, 2.0 * q, q)?,
            Self::circular_arc(center, radius, 3.0 * q, q)?,
        ])
    }
}
