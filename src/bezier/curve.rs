//! Polynomial Bézier curves of any degree (seed 001 §1.2–1.7; seed 000 eq. 2.3, 2.10).

use super::bernstein::{bernstein_all, binomial};
use super::{BezierError, Point};

/// A Bézier curve B(t) = Σ_{i=0}^{n} p_i B^n_i(t), t ∈ [0, 1] (seed 001 eq. 1.13).
/// The degree n is the number of control points minus one; there is always at least one point.
#[derive(Debug, Clone, PartialEq)]
pub struct BezierCurve<P> {
    points: Vec<P>,
}

impl<P: Point> BezierCurve<P> {
    /// Curve from its control polygon p_0 … p_n; errors on an empty or non-finite polygon.
    pub fn new(points: Vec<P>) -> Result<Self, BezierError> {
        if points.is_empty() {
            return Err(BezierError::Empty);
        }
        if let Some(index) = points.iter().position(|p| !p.is_finite()) {
            return Err(BezierError::NonFinitePoint { index });
        }
        Ok(Self { points })
    }

    /// Internal constructor for polygons known to be non-empty.
    pub(crate) fn from_vec(points: Vec<P>) -> Self {
        debug_assert!(!points.is_empty());
        Self { points }
    }

    /// Degree n.
    pub fn degree(&self) -> usize {
        self.points.len() - 1
    }

    /// Control points p_0 … p_n.
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// The control polygon, consuming the curve.
    pub fn into_points(self) -> Vec<P> {
        self.points
    }

    /// Point at t by the de Casteljau algorithm (seed 001 eq. 1.5):
    /// p^j_i = (1 − t) p^{j−1}_i + t p^{j−1}_{i+1}, B(t) = p^n_0. Works for t outside [0, 1] too.
    pub fn eval(&self, t: f64) -> P {
        let mut b = self.points.clone();
        for j in 1..b.len() {
            for i in 0..b.len() - j {
                b[i] = b[i].lerp_to(b[i + 1], t);
            }
        }
        b[0]
    }

    /// Point at t from the Bernstein form Σ p_i B^n_i(t) (seed 001 eq. 1.13, seed 000 eq. 2.3).
    pub fn eval_bernstein(&self, t: f64) -> P {
        let b = bernstein_all(self.degree(), t);
        self.points
            .iter()
            .zip(&b)
            .fold(P::ZERO, |acc, (&p, &w)| acc + p * w)
    }

    /// The full de Casteljau triangle at t: level j holds p^j_0 … p^j_{n−j} (seed 001 eq. 1.5).
    pub fn de_casteljau(&self, t: f64) -> Vec<Vec<P>> {
        let mut levels = vec![self.points.clone()];
        for j in 1..self.points.len() {
            let prev = &levels[j - 1];
            let next = prev.windows(2).map(|w| w[0].lerp_to(w[1], t)).collect();
            levels.push(next);
        }
        levels
    }

    /// Forward differences Δ^r p_i, i = 0..n−r (seed 001 eq. 1.14–1.15); empty when r > n.
    pub fn forward_differences(&self, r: usize) -> Vec<P> {
        let mut d = self.points.clone();
        for _ in 0..r {
            if d.len() <= 1 {
                return Vec::new();
            }
            d = d.windows(2).map(|w| w[1] - w[0]).collect();
        }
        d
    }

    /// The hodograph B′(t) = n Σ_{i<n} Δp_i B^{n−1}_i(t) (seed 001 eq. 1.16 with r = 1).
    /// The derivative of a degree-0 curve is the zero curve of degree 0.
    pub fn hodograph(&self) -> Self {
        self.derivative_curve(1)
    }

    /// The r-th derivative curve B^{(r)}(t) = n!/(n−r)! Σ Δ^r p_i B^{n−r}_i(t) (seed 001 eq. 1.16);
    /// the zero curve of degree 0 when r > n.
    pub fn derivative_curve(&self, r: usize) -> Self {
        let n = self.degree();
        if r > n {
            return Self::from_vec(vec![P::ZERO]);
        }
        let factor: f64 = ((n - r + 1)..=n).map(|k| k as f64).product();
        Self::from_vec(
            self.forward_differences(r)
                .into_iter()
                .map(|d| d * factor)
                .collect(),
        )
    }

    /// The r-th derivative at t (r = 0 is the point).
    pub fn derivative(&self, t: f64, r: usize) -> P {
        self.derivative_curve(r).eval(t)
    }

    /// B(t), B′(t), …, B^{(r)}(t).
    pub fn derivatives(&self, t: f64, r: usize) -> Vec<P> {
        let mut out = Vec::with_capacity(r + 1);
        let mut c = self.clone();
        for _ in 0..=r {
            out.push(c.eval(t));
            c = c.hodograph();
        }
        out
    }

    /// Degree elevation by one (seed 001 eq. 1.22):
    /// p̄_i = i/(n+1) p_{i−1} + (1 − i/(n+1)) p_i, i = 0..n+1. The curve is unchanged.
    pub fn elevate(&self) -> Self {
        self.elevate_by(1)
    }

    /// Degree elevation by k in one step:
    /// p̄_i = Σ_j C(n, j) C(k, i−j) / C(n+k, i) · p_j, i = 0..n+k (seed 001 §1.7 iterated).
    pub fn elevate_by(&self, k: usize) -> Self {
        let n = self.degree();
        let pts = (0..=n + k)
            .map(|i| {
                let lo = i.saturating_sub(k);
                let hi = i.min(n);
                let c = binomial(n + k, i);
                (lo..=hi).fold(P::ZERO, |acc, j| {
                    acc + self.points[j] * (binomial(n, j) * binomial(k, i - j) / c)
                })
            })
            .collect();
        Self::from_vec(pts)
    }

    /// Subdivision at t: the two curves over [0, t] and [t, 1], from the outer edges of the
    /// de Casteljau triangle (p^0_0, p^1_0, …, p^n_0) and (p^n_0, p^{n−1}_1, …, p^0_n).
    pub fn subdivide(&self, t: f64) -> (Self, Self) {
        let tri = self.de_casteljau(t);
        let left = tri.iter().map(|l| l[0]).collect();
        let right = tri
            .iter()
            .rev()
            .map(|l| *l.last().expect("levels are non-empty"))
            .collect();
        (Self::from_vec(left), Self::from_vec(right))
    }

    /// The piece of the curve over [a, b] reparameterized to [0, 1] (a > b reverses it).
    pub fn segment(&self, a: f64, b: f64) -> Self {
        // Blossom-free version: control points q_i = blossom(a^{n−i}, b^i) by de Casteljau.
        let n = self.degree();
        let pts = (0..=n)
            .map(|i| {
                let mut c = self.points.clone();
                for level in 1..=n {
                    let t = if level <= n - i { a } else { b };
                    for m in 0..=n - level {
                        c[m] = c[m].lerp_to(c[m + 1], t);
                    }
                }
                c[0]
            })
            .collect();
        Self::from_vec(pts)
    }

    /// The same curve traversed backwards: B̃(t) = B(1 − t).
    pub fn reversed(&self) -> Self {
        Self::from_vec(self.points.iter().rev().copied().collect())
    }

    /// Apply a map to every control point; for an affine map this maps the curve (affine
    /// invariance, seed 001 §1.3).
    pub fn map<Q: Point>(&self, f: impl FnMut(P) -> Q) -> BezierCurve<Q> {
        BezierCurve::from_vec(self.points.iter().copied().map(f).collect())
    }

    /// Power-basis coefficients a_k with B(t) = Σ a_k t^k: a_k = C(n, k) Δ^k p_0
    /// (Taylor expansion at 0 with seed 001 eq. 1.17).
    pub fn to_power_basis(&self) -> Vec<P> {
        let n = self.degree();
        (0..=n)
            .map(|k| self.forward_differences(k)[0] * binomial(n, k))
            .collect()
    }

    /// Curve from power-basis coefficients a_0 … a_n: p_i = Σ_{k≤i} C(i, k)/C(n, k) a_k.
    pub fn from_power_basis(coeffs: Vec<P>) -> Result<Self, BezierError> {
        if coeffs.is_empty() {
            return Err(BezierError::Empty);
        }
        let n = coeffs.len() - 1;
        let pts = (0..=n)
            .map(|i| {
                (0..=i).fold(P::ZERO, |acc, k| {
                    acc + coeffs[k] * (binomial(i, k) / binomial(n, k))
                })
            })
            .collect();
        Self::new(pts)
    }

    /// Length of the control polygon Σ |p_{i+1} − p_i| (an upper bound of the arc length).
    pub fn control_polygon_length(&self) -> f64 {
        self.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    }

    /// Arc length ∫_0^1 |B′(t)| dt by [`integrate`] (from one piece, to 1e-14 relative).
    pub fn arc_length(&self) -> f64 {
        let d = self.hodograph();
        integrate(|t| d.eval(t).norm(), 1, 1e-14)
    }
}

/// ∫_0^1 f(t) dt by composite 16-point Gauss–Legendre quadrature on `pieces` equal pieces,
/// doubling them until two passes agree to `rel_tol` relative (at most 2^12 pieces; the last pass
/// is returned then). The one adaptive quadrature of the crate (arc lengths, PH bending energy).
pub fn integrate(f: impl Fn(f64) -> f64, pieces: usize, rel_tol: f64) -> f64 {
    let (x, w) = gauss_legendre(16);
    let pass = |pieces: usize| -> f64 {
        let h = 1.0 / pieces as f64;
        (0..pieces)
            .map(|k| {
                let a = k as f64 * h;
                x.iter().zip(&w).map(|(&xi, &wi)| wi * f(a + 0.5 * h * (xi + 1.0))).sum::<f64>() * 0.5 * h
            })
            .sum()
    };
    let mut pieces = pieces.max(1);
    let mut prev = pass(pieces);
    while pieces < 1 << 12 {
        pieces *= 2;
        let next = pass(pieces);
        if (next - prev).abs() <= rel_tol * next.abs().max(f64::MIN_POSITIVE) {
            return next;
        }
        prev = next;
    }
    prev
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton iteration on P_n from the Chebyshev
/// guesses); exact for polynomials of degree ≤ 2n − 1.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(z) and P_n'(z) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pn = if n == 0 { 1.0 } else { p1 };
            let pn1 = if n == 0 { 0.0 } else { p0 };
            dp = n as f64 * (z * pn - pn1) / (z * z - 1.0);
            let dz = pn / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        x[i] = -z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}
