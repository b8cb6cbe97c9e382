//! Degree reduction of Bézier curves and the base + displacement form of a curve
//! (seed 002 "Fokszám emelés és csökkentés" and "alap + eltolás" slides).
//! The formulas are written out in `docs/math/editing.md`.
//!
//! - [`reduce_degree`]: constrained least-squares (L2) reduction from degree d to m < d that keeps
//!   the end derivatives of order 0..=r at both ends, with a rigorous bound of the error.
//! - [`hermite_cubic`]: the cubic with the same end points and end first derivatives (seed 002's
//!   quartic example: C1 = Q0 + (4/3)(Q1 − Q0)).
//! - [`BaseDisplacement`]: r(u) = r_B(u) + r_D(u), a cubic base curve carrying the end positions
//!   and tangents plus displacement vectors that move only the inside of the curve.

use super::bernstein::{bernstein_all, binomial};
use super::curve::gauss_legendre;
use super::{BezierCurve, Point};
use thiserror::Error;

/// Errors of degree reduction and of the base + displacement form; each names the offending
/// argument (degree, derivative order or displacement index).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ReduceError {
    /// Reduction needs a target degree m below the curve's degree d.
    #[error("target degree {target} is not below the curve degree {degree}")]
    TargetNotLower { target: usize, degree: usize },
    /// Keeping the end derivatives of order 0..=order at both ends needs m ≥ 2·order + 1.
    #[error(
        "target degree {target} cannot keep end derivatives up to order {order} at both ends \
         (needs degree >= {min})"
    )]
    TargetTooLow {
        target: usize,
        order: usize,
        min: usize,
    },
    /// The least-squares system is numerically rank-deficient at column `pivot` of the QR
    /// solve, or the solution has a non-finite control point `pivot` (Bernstein bases are badly
    /// conditioned for high degrees).
    #[error(
        "the least-squares system of the reduction to degree {target} is singular (column or control point {pivot})"
    )]
    Singular { target: usize, pivot: usize },
    /// The base + displacement form needs a curve of degree at least 3 (the base is cubic).
    #[error("curve degree {degree} is below 3; the base curve is cubic")]
    BelowCubic { degree: usize },
    /// A base curve must be cubic.
    #[error("base curve has degree {degree}, expected 3")]
    BaseNotCubic { degree: usize },
    /// Displacement vectors 0, 1, d−1 and d are zero by definition (they would move the end
    /// positions or tangents); `index` is one of them or past d.
    #[error("displacement vector {index} of a degree-{degree} curve is not editable (editable: 2..={last})", last = .degree.saturating_sub(2))]
    FixedDisplacement { index: usize, degree: usize },
    /// A displacement vector with a NaN or infinite coordinate.
    #[error("displacement vector {index} is not finite")]
    NonFiniteDisplacement { index: usize },
}

/// A reduced curve with a bound of its distance to the original curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Reduction<P> {
    /// The curve of the target degree.
    pub curve: BezierCurve<P>,
    /// Upper bound of max_t |r(t) − r_reduced(t)| (see [`error_bound`]).
    pub error_bound: f64,
}

/// Upper bound of max over t ∈ [0, 1] of |a(t) − b(t)|: elevate the lower-degree curve to the
/// degree of the other and take the largest distance of corresponding control points. It is a bound
/// because a − b = Σ (a_i − b_i) B_i(t) with B_i ≥ 0, Σ B_i = 1 (convex hull property).
pub fn error_bound<P: Point>(a: &BezierCurve<P>, b: &BezierCurve<P>) -> f64 {
    let (lo, hi) = if a.degree() <= b.degree() {
        (a, b)
    } else {
        (b, a)
    };
    let e = lo.elevate_by(hi.degree() - lo.degree());
    e.points()
        .iter()
        .zip(hi.points())
        .map(|(&p, &q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// The cubic Hermite form of a degree-d curve (seed 002, quartic example with d = 4):
/// C0 = Q0, C1 = Q0 + (d/3)(Q1 − Q0), C2 = Qd + (d/3)(Q_{d−1} − Qd), C3 = Qd.
/// It has the curve's end points and end first derivatives; for d ≤ 3 it is the curve itself
/// (elevated to degree 3). For d > 3 it equals [`reduce_degree`] to m = 3 with order 1.
pub fn hermite_cubic<P: Point>(curve: &BezierCurve<P>) -> BezierCurve<P> {
    let q = curve.points();
    let d = curve.degree();
    if d == 0 {
        return BezierCurve::from_vec(vec![q[0]; 4]);
    }
    let f = d as f64 / 3.0;
    BezierCurve::from_vec(vec![
        q[0],
        q[0] + (q[1] - q[0]) * f,
        q[d] + (q[d - 1] - q[d]) * f,
        q[d],
    ])
}

/// The first `order + 1` control points of a degree-m curve whose derivatives of order 0..=order
/// at t = 0 are those of the degree-d polygon `p`:
/// Δ^k q_0 = [d!/(d−k)!] / [m!/(m−k)!] · Δ^k p_0 and q_k = Σ_{i≤k} C(k, i) Δ^i q_0.
fn end_points<P: Point>(p: &[P], m: usize, order: usize) -> Vec<P> {
    let d = p.len() - 1;
    let mut diffs = Vec::with_capacity(order + 1);
    let mut row = p.to_vec();
    let mut ratio = 1.0;
    for k in 0..=order {
        if k > 0 {
            row = row.windows(2).map(|w| w[1] - w[0]).collect();
            ratio *= (d - (k - 1)) as f64 / (m - (k - 1)) as f64;
        }
        diffs.push(row[0] * ratio);
    }
    (0..=order)
        .map(|k| (0..=k).fold(P::ZERO, |acc, i| acc + diffs[i] * binomial(k, i)))
        .collect()
}

/// Constrained least-squares degree reduction (seed 002 "fokszám csökkentés"; formulas in
/// `docs/math/editing.md`): the degree-m curve q that minimizes ∫_0^1 |r(t) − q(t)|² dt among the
/// curves with r^{(k)}(0) = q^{(k)}(0) and r^{(k)}(1) = q^{(k)}(1) for k = 0..=order.
/// `order = 1` keeps end positions and first derivatives (Hermite constraints), `order = 0` only
/// the end points. The constraints fix q_0..q_order and q_{m−order}..q_m; the others solve the
/// normal equations Σ_j G_ij q_j = Σ_k H_ik p_k (i, j free), G and H Bernstein Gram matrices,
/// here by QR on d + 1 Gauss–Legendre samples (the same objective, exactly).
/// Errors: m ≥ d, or m < 2·order + 1.
pub fn reduce_degree<P: Point>(
    curve: &BezierCurve<P>,
    target: usize,
    order: usize,
) -> Result<Reduction<P>, ReduceError> {
    let d = curve.degree();
    if target >= d {
        return Err(ReduceError::TargetNotLower { target, degree: d });
    }
    // 2·order + 1, saturating: an absurd `order` is "target too low", never an overflow.
    let min = order.saturating_mul(2).saturating_add(1);
    if target < min {
        return Err(ReduceError::TargetTooLow { target, order, min });
    }
    let m = target;
    let p = curve.points();
    let mut q = vec![P::ZERO; m + 1];
    let head = end_points(p, m, order);
    let rev: Vec<P> = p.iter().rev().copied().collect();
    let tail = end_points(&rev, m, order);
    for k in 0..=order {
        q[k] = head[k];
        q[m - k] = tail[k];
    }
    let free: Vec<usize> = (order + 1..m - order).collect();
    if !free.is_empty() {
        // The objective is a polynomial of degree 2d in t, so N = d + 1 Gauss–Legendre nodes
        // integrate it exactly: minimize Σ_k w_k |r(t_k) − q(t_k)|² over the free points, by QR
        // (condition number √cond(G), unlike the normal equations G x = H p).
        let (x, w) = gauss_legendre(d + 1);
        let rows = x.len();
        let nf = free.len();
        let mut a = vec![0.0; rows * nf];
        let mut b = vec![P::ZERO; rows];
        for (k, (&xk, &wk)) in x.iter().zip(&w).enumerate() {
            let t = 0.5 * (xk + 1.0);
            let sk = (0.5 * wk).sqrt();
            let bm = bernstein_all(m, t);
            for (c, &i) in free.iter().enumerate() {
                a[k * nf + c] = sk * bm[i];
            }
            let fixed = (0..=order)
                .chain(m - order..=m)
                .fold(P::ZERO, |acc, j| acc + q[j] * bm[j]);
            b[k] = (curve.eval(t) - fixed) * sk;
        }
        let sol = householder_solve(&mut a, rows, nf, b)
            .map_err(|pivot| ReduceError::Singular { target: m, pivot })?;
        for (c, &i) in free.iter().enumerate() {
            q[i] = sol[c];
        }
    }
    if let Some(pivot) = q.iter().position(|v| !v.is_finite()) {
        return Err(ReduceError::Singular { target: m, pivot });
    }
    let reduced = BezierCurve::from_vec(q);
    let bound = error_bound(curve, &reduced);
    Ok(Reduction {
        curve: reduced,
        error_bound: bound,
    })
}

/// Least-squares solution of A x ≈ b (A: `rows` × `cols`, row-major, rows ≥ cols, overwritten)
/// with vector-valued b, by Householder QR; Err(column) when a diagonal entry of R is below
/// 1e-13 times the largest (numerically rank-deficient).
fn householder_solve<P: Point>(
    a: &mut [f64],
    rows: usize,
    cols: usize,
    mut b: Vec<P>,
) -> Result<Vec<P>, usize> {
    let mut diag = vec![0.0; cols];
    for c in 0..cols {
        let norm = (c..rows)
            .map(|r| a[r * cols + c].powi(2))
            .sum::<f64>()
            .sqrt();
        let alpha = if a[c * cols + c] > 0.0 { -norm } else { norm };
        diag[c] = alpha;
        // v = x − alpha e_1 stored in column c (rows c..), H = I − 2 v vᵀ / vᵀv
        a[c * cols + c] -= alpha;
        let vtv: f64 = (c..rows).map(|r| a[r * cols + c].powi(2)).sum();
        if vtv == 0.0 {
            continue;
        }
        for c2 in c + 1..cols {
            let dot: f64 = (c..rows).map(|r| a[r * cols + c] * a[r * cols + c2]).sum();
            let f = 2.0 * dot / vtv;
            for r in c..rows {
                a[r * cols + c2] -= f * a[r * cols + c];
            }
        }
        let dot = (c..rows).fold(P::ZERO, |acc, r| acc + b[r] * a[r * cols + c]);
        let f = 2.0 / vtv;
        for r in c..rows {
            b[r] = b[r] - dot * (f * a[r * cols + c]);
        }
    }
    let scale = diag.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    if let Some(c) = diag
        .iter()
        .position(|d| d.is_nan() || d.abs() <= 1e-13 * scale)
    {
        return Err(c);
    }
    let mut x = vec![P::ZERO; cols];
    for c in (0..cols).rev() {
        let mut t = b[c];
        for c2 in c + 1..cols {
            t = t - x[c2] * a[c * cols + c2];
        }
        x[c] = t * (1.0 / diag[c]);
    }
    Ok(x)
}

/// A curve of degree d ≥ 3 written as r(u) = r_B(u) + r_D(u) (seed 002, "alap + eltolás"):
/// the base r_B is the cubic [`hermite_cubic`] (end positions and end tangents), the displacement
/// r_D(u) = Σ D_i B^d_i(u) with D_i = Q_i − C*_i, where C*_i are the control points of the base
/// elevated to degree d. D_0 = D_1 = D_{d−1} = D_d = 0 exactly, so any change of the other
/// displacement vectors keeps the end positions and tangents; a new base moves only those.
#[derive(Debug, Clone, PartialEq)]
pub struct BaseDisplacement<P> {
    base: BezierCurve<P>,
    displacement: Vec<P>,
}

impl<P: Point> BaseDisplacement<P> {
    /// Splits a curve of degree d ≥ 3 into base and displacement.
    pub fn new(curve: &BezierCurve<P>) -> Result<Self, ReduceError> {
        let d = curve.degree();
        if d < 3 {
            return Err(ReduceError::BelowCubic { degree: d });
        }
        let base = hermite_cubic(curve);
        let elevated = base.elevate_by(d - 3);
        let mut displacement = vec![P::ZERO; d + 1];
        for (i, (q, c)) in curve.points().iter().zip(elevated.points()).enumerate() {
            if (2..=d - 2).contains(&i) {
                displacement[i] = *q - *c;
            }
        }
        Ok(Self { base, displacement })
    }

    /// Degree d of the curve (and of the displacement).
    pub fn degree(&self) -> usize {
        self.displacement.len() - 1
    }

    /// The cubic base curve r_B (control points C_0..C_3).
    pub fn base(&self) -> &BezierCurve<P> {
        &self.base
    }

    /// The base elevated to degree d (control points C*_0..C*_d).
    pub fn base_elevated(&self) -> BezierCurve<P> {
        self.base.elevate_by(self.degree() - 3)
    }

    /// Displacement vectors D_0..D_d (the first two and last two are zero).
    pub fn displacement(&self) -> &[P] {
        &self.displacement
    }

    /// The displacement curve r_D(u) = Σ D_i B^d_i(u) (a curve of vectors).
    pub fn displacement_curve(&self) -> BezierCurve<P> {
        BezierCurve::from_vec(self.displacement.clone())
    }

    /// The curve r = r_B + r_D of degree d: control points C*_i + D_i.
    pub fn curve(&self) -> BezierCurve<P> {
        let e = self.base_elevated();
        BezierCurve::from_vec(
            e.points()
                .iter()
                .zip(&self.displacement)
                .map(|(&c, &v)| c + v)
                .collect(),
        )
    }

    /// r(u) = r_B(u) + r_D(u).
    pub fn eval(&self, u: f64) -> P {
        self.base.eval(u) + self.displacement_curve().eval(u)
    }

    /// Sets displacement vector `index` (2 ≤ index ≤ d−2): changes the inside of the curve only.
    pub fn set_displacement(&mut self, index: usize, vector: P) -> Result<(), ReduceError> {
        let d = self.degree();
        if index < 2 || index > d - 2 {
            return Err(ReduceError::FixedDisplacement { index, degree: d });
        }
        if !vector.is_finite() {
            return Err(ReduceError::NonFiniteDisplacement { index });
        }
        self.displacement[index] = vector;
        Ok(())
    }

    /// Replaces the cubic base (new end positions and tangents), keeping the displacement.
    pub fn set_base(&mut self, base: BezierCurve<P>) -> Result<(), ReduceError> {
        if base.degree() != 3 {
            return Err(ReduceError::BaseNotCubic {
                degree: base.degree(),
            });
        }
        self.base = base;
        Ok(())
    }
}
