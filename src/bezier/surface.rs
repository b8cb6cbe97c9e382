//! Tensor-product Bézier surfaces, polynomial and rational (seed 001 §2.2–2.4).
//!
//! The control grid is `points[i][j]`, i = 0..=m along u (degree_u = m), j = 0..=n along v
//! (degree_v = n): x(u, v) = Σ_i Σ_j p_ij B^m_i(u) B^n_j(v) (seed 001 eq. 2.4).

use super::bernstein::{bernstein_all, bernstein_all_d2};
use super::curve::BezierCurve;
use super::rational::RationalCurve;
use super::{BezierError, Point};
use glam::DVec3;

/// Position and first and second partial derivatives at one (u, v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePartials<P> {
    pub p: P,
    pub u: P,
    pub v: P,
    pub uu: P,
    pub uv: P,
    pub vv: P,
}

impl SurfacePartials<DVec3> {
    /// Unit normal x_u × x_v / |x_u × x_v|; `None` where the cross product vanishes (e.g. a
    /// degenerate pole edge) relative to |x_u||x_v|.
    pub fn normal(&self) -> Option<DVec3> {
        let c = self.u.cross(self.v);
        let scale = self.u.length() * self.v.length();
        (c.length() > 1e-14 * scale && scale > 0.0).then(|| c / c.length())
    }

    /// (mean H, Gaussian K) curvature from the fundamental forms:
    /// E = x_u·x_u, F = x_u·x_v, G = x_v·x_v, L = x_uu·n, M = x_uv·n, N = x_vv·n,
    /// K = (LN − M²)/(EG − F²), H = (EN − 2FM + GL)/(2(EG − F²)).
    /// Sign convention: n = x_u × x_v, and curvature is positive when the surface bends towards n
    /// (a sphere with outward normal has H = −1/R, K = 1/R²). `None` where the normal is undefined.
    pub fn curvature(&self) -> Option<(f64, f64)> {
        let n = self.normal()?;
        let (e, f, g) = (self.u.dot(self.u), self.u.dot(self.v), self.v.dot(self.v));
        let (l, m, nn) = (self.uu.dot(n), self.uv.dot(n), self.vv.dot(n));
        let det = e * g - f * f;
        Some((
            (e * nn - 2.0 * f * m + g * l) / (2.0 * det),
            (l * nn - m * m) / det,
        ))
    }
}

/// Validate a rectangular, non-empty, finite grid; returns (m, n).
fn check_grid<P: Point>(grid: &[Vec<P>]) -> Result<(usize, usize), BezierError> {
    let cols = grid.first().map_or(0, Vec::len);
    if cols == 0 {
        return Err(BezierError::Empty);
    }
    for (row, r) in grid.iter().enumerate() {
        if r.len() != cols {
            return Err(BezierError::RaggedRow {
                row,
                len: r.len(),
                expected: cols,
            });
        }
        if let Some(j) = r.iter().position(|p| !p.is_finite()) {
            return Err(BezierError::NonFinitePoint {
                index: row * cols + j,
            });
        }
    }
    Ok((grid.len() - 1, cols - 1))
}

/// Apply a curve operation to every column (fixed j: the u-direction curves).
fn map_columns<P: Point>(
    grid: &[Vec<P>],
    f: impl Fn(BezierCurve<P>) -> BezierCurve<P>,
) -> Vec<Vec<P>> {
    let cols: Vec<Vec<P>> = (0..grid[0].len())
        .map(|j| f(BezierCurve::from_vec(grid.iter().map(|r| r[j]).collect())).into_points())
        .collect();
    transpose(&cols)
}

fn transpose<P: Copy>(grid: &[Vec<P>]) -> Vec<Vec<P>> {
    (0..grid[0].len())
        .map(|j| grid.iter().map(|r| r[j]).collect())
        .collect()
}

/// A polynomial tensor-product Bézier surface of degree (m, n) (seed 001 eq. 2.4).
#[derive(Debug, Clone, PartialEq)]
pub struct BezierSurface<P> {
    degree_u: usize,
    degree_v: usize,
    points: Vec<Vec<P>>,
}

impl<P: Point> BezierSurface<P> {
    /// Surface from the control grid `points[i][j]`; errors on an empty, ragged or non-finite
    /// grid (the index of a non-finite point is i·(n+1) + j).
    pub fn new(points: Vec<Vec<P>>) -> Result<Self, BezierError> {
        let (degree_u, degree_v) = check_grid(&points)?;
        Ok(Self {
            degree_u,
            degree_v,
            points,
        })
    }

    fn from_grid(points: Vec<Vec<P>>) -> Self {
        Self {
            degree_u: points.len() - 1,
            degree_v: points[0].len() - 1,
            points,
        }
    }

    /// Degree m in u.
    pub fn degree_u(&self) -> usize {
        self.degree_u
    }

    /// Degree n in v.
    pub fn degree_v(&self) -> usize {
        self.degree_v
    }

    /// The control grid, rows i (along u) of points j (along v).
    pub fn points(&self) -> &[Vec<P>] {
        &self.points
    }

    /// Control point p_ij.
    pub fn point(&self, i: usize, j: usize) -> P {
        self.points[i][j]
    }

    /// x(u, v) = Σ_i Σ_j p_ij B^m_i(u) B^n_j(v) (seed 001 eq. 2.4).
    pub fn eval(&self, u: f64, v: f64) -> P {
        let (bu, bv) = (
            bernstein_all(self.degree_u, u),
            bernstein_all(self.degree_v, v),
        );
        self.points.iter().zip(&bu).fold(P::ZERO, |acc, (row, &a)| {
            acc + row.iter().zip(&bv).fold(P::ZERO, |s, (&p, &b)| s + p * b) * a
        })
    }

    /// Position and analytic first and second partials: the Bernstein derivatives of
    /// `bernstein_all_d2` in both directions (equivalent to seed 001 eq. 2.6–2.9).
    pub fn partials(&self, u: f64, v: f64) -> SurfacePartials<P> {
        let (b, db, ddb) = bernstein_all_d2(self.degree_u, u);
        let (c, dc, ddc) = bernstein_all_d2(self.degree_v, v);
        let z = P::ZERO;
        let mut s = SurfacePartials {
            p: z,
            u: z,
            v: z,
            uu: z,
            uv: z,
            vv: z,
        };
        for (i, row) in self.points.iter().enumerate() {
            let (mut r, mut rv, mut rvv) = (z, z, z);
            for (j, &p) in row.iter().enumerate() {
                r = r + p * c[j];
                rv = rv + p * dc[j];
                rvv = rvv + p * ddc[j];
            }
            s.p = s.p + r * b[i];
            s.u = s.u + r * db[i];
            s.uu = s.uu + r * ddb[i];
            s.v = s.v + rv * b[i];
            s.uv = s.uv + rv * db[i];
            s.vv = s.vv + rvv * b[i];
        }
        s
    }

    /// The derivative surface ∂x/∂u of degree (m−1, n): control points m Δ^{1,0} p_ij
    /// (seed 001 eq. 2.6); the zero surface of degree (0, n) when m = 0.
    pub fn derivative_u(&self) -> Self {
        Self::from_grid(map_columns(&self.points, |c| c.hodograph()))
    }

    /// The derivative surface ∂x/∂v of degree (m, n−1).
    pub fn derivative_v(&self) -> Self {
        Self::from_grid(
            self.points
                .iter()
                .map(|r| BezierCurve::from_vec(r.clone()).hodograph().into_points())
                .collect(),
        )
    }

    /// The iso-parametric curve u = u0, a degree-n curve in v with control points
    /// Σ_i B^m_i(u0) p_ij (seed 001 §2.2).
    pub fn iso_u(&self, u0: f64) -> BezierCurve<P> {
        let b = bernstein_all(self.degree_u, u0);
        BezierCurve::from_vec(
            (0..=self.degree_v)
                .map(|j| {
                    self.points
                        .iter()
                        .zip(&b)
                        .fold(P::ZERO, |acc, (r, &w)| acc + r[j] * w)
                })
                .collect(),
        )
    }

    /// The iso-parametric curve v = v0, a degree-m curve in u.
    pub fn iso_v(&self, v0: f64) -> BezierCurve<P> {
        BezierCurve::from_vec(
            self.points
                .iter()
                .map(|r| BezierCurve::from_vec(r.clone()).eval(v0))
                .collect(),
        )
    }

    /// Degree elevation in u by k: every column is elevated as a curve (seed 001 eq. 2.5).
    pub fn elevate_u(&self, k: usize) -> Self {
        Self::from_grid(map_columns(&self.points, |c| c.elevate_by(k)))
    }

    /// Degree elevation in v by k: every row is elevated as a curve.
    pub fn elevate_v(&self, k: usize) -> Self {
        Self::from_grid(
            self.points
                .iter()
                .map(|r| BezierCurve::from_vec(r.clone()).elevate_by(k).into_points())
                .collect(),
        )
    }

    /// Subdivision at u = t into the patches over [0, t] and [t, 1] in u.
    pub fn subdivide_u(&self, t: f64) -> (Self, Self) {
        let left = map_columns(&self.points, |c| c.subdivide(t).0);
        let right = map_columns(&self.points, |c| c.subdivide(t).1);
        (Self::from_grid(left), Self::from_grid(right))
    }

    /// Subdivision at v = t.
    pub fn subdivide_v(&self, t: f64) -> (Self, Self) {
        let (a, b) = self.transposed().subdivide_u(t);
        (a.transposed(), b.transposed())
    }

    /// The same surface with u and v swapped: x̃(u, v) = x(v, u) (its normal is flipped).
    pub fn transposed(&self) -> Self {
        Self::from_grid(transpose(&self.points))
    }

    /// x̃(u, v) = x(1 − u, v).
    pub fn reversed_u(&self) -> Self {
        Self::from_grid(self.points.iter().rev().cloned().collect())
    }

    /// x̃(u, v) = x(u, 1 − v).
    pub fn reversed_v(&self) -> Self {
        Self::from_grid(
            self.points
                .iter()
                .map(|r| r.iter().rev().copied().collect())
                .collect(),
        )
    }

    /// Apply a map to every control point (maps the surface for affine maps).
    pub fn map<Q: Point>(&self, mut f: impl FnMut(P) -> Q) -> BezierSurface<Q> {
        BezierSurface::from_grid(
            self.points
                .iter()
                .map(|r| r.iter().map(|&p| f(p)).collect())
                .collect(),
        )
    }
}

impl BezierSurface<DVec3> {
    /// Unit normal (x_u × x_v normalized), `None` where it is undefined.
    pub fn normal(&self, u: f64, v: f64) -> Option<DVec3> {
        self.partials(u, v).normal()
    }

    /// (mean, Gaussian) curvature, see [`SurfacePartials::curvature`].
    pub fn curvature(&self, u: f64, v: f64) -> Option<(f64, f64)> {
        self.partials(u, v).curvature()
    }
}

/// A rational tensor-product Bézier surface (seed 001 eq. 2.15):
/// x(u, v) = Σ Σ w_ij p_ij B^m_i(u) B^n_j(v) / Σ Σ w_ij B^m_i(u) B^n_j(v), weights positive.
#[derive(Debug, Clone, PartialEq)]
pub struct RationalSurface<P> {
    points: BezierSurface<P>,
    weights: Vec<Vec<f64>>,
}

impl<P: Point> RationalSurface<P> {
    /// Surface from a control grid and a weight grid of the same shape; the weight error index
    /// is i·(n+1) + j.
    pub fn new(points: Vec<Vec<P>>, weights: Vec<Vec<f64>>) -> Result<Self, BezierError> {
        let points = BezierSurface::new(points)?;
        let cols = points.degree_v + 1;
        let count = |g: &[Vec<f64>]| g.iter().map(Vec::len).sum::<usize>();
        if weights.len() != points.degree_u + 1 || weights.iter().any(|r| r.len() != cols) {
            return Err(BezierError::WeightCount {
                got: count(&weights),
                expected: (points.degree_u + 1) * cols,
            });
        }
        for (i, r) in weights.iter().enumerate() {
            if let Some(j) = r.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
                return Err(BezierError::BadWeight {
                    index: i * cols + j,
                    value: r[j],
                });
            }
        }
        Ok(Self { points, weights })
    }

    /// A polynomial surface with unit weights.
    pub fn from_polynomial(s: &BezierSurface<P>) -> Self {
        Self {
            points: s.clone(),
            weights: vec![vec![1.0; s.degree_v + 1]; s.degree_u + 1],
        }
    }

    /// Degree m in u.
    pub fn degree_u(&self) -> usize {
        self.points.degree_u
    }

    /// Degree n in v.
    pub fn degree_v(&self) -> usize {
        self.points.degree_v
    }

    /// The control grid.
    pub fn points(&self) -> &[Vec<P>] {
        &self.points.points
    }

    /// The weight grid.
    pub fn weights(&self) -> &[Vec<f64>] {
        &self.weights
    }

    /// The homogeneous numerator surface with control points w_ij p_ij.
    pub fn numerator(&self) -> BezierSurface<P> {
        BezierSurface::from_grid(
            self.points
                .points
                .iter()
                .zip(&self.weights)
                .map(|(r, w)| r.iter().zip(w).map(|(&p, &w)| p * w).collect())
                .collect(),
        )
    }

    /// The denominator surface with control values w_ij.
    pub fn denominator(&self) -> BezierSurface<f64> {
        BezierSurface::from_grid(self.weights.clone())
    }

    fn from_homogeneous(num: BezierSurface<P>, den: BezierSurface<f64>) -> Self {
        let points = num
            .points
            .iter()
            .zip(&den.points)
            .map(|(r, w)| r.iter().zip(w).map(|(&p, &w)| p * (1.0 / w)).collect())
            .collect();
        Self {
            points: BezierSurface::from_grid(points),
            weights: den.points,
        }
    }

    /// x(u, v) = N(u, v) / W(u, v).
    pub fn eval(&self, u: f64, v: f64) -> P {
        self.numerator().eval(u, v) * (1.0 / self.denominator().eval(u, v))
    }

    /// Position and first and second partials by the quotient rule on x = N/W:
    /// x_u = (N_u − W_u x)/W, x_uu = (N_uu − 2W_u x_u − W_uu x)/W,
    /// x_uv = (N_uv − W_u x_v − W_v x_u − W_uv x)/W (v likewise).
    pub fn partials(&self, u: f64, v: f64) -> SurfacePartials<P> {
        let n = self.numerator().partials(u, v);
        let w = self.denominator().partials(u, v);
        let inv = 1.0 / w.p;
        let p = n.p * inv;
        let xu = (n.u - p * w.u) * inv;
        let xv = (n.v - p * w.v) * inv;
        SurfacePartials {
            p,
            u: xu,
            v: xv,
            uu: (n.uu - xu * (2.0 * w.u) - p * w.uu) * inv,
            uv: (n.uv - xv * w.u - xu * w.v - p * w.uv) * inv,
            vv: (n.vv - xv * (2.0 * w.v) - p * w.vv) * inv,
        }
    }

    /// The iso-parametric curve u = u0 (rational, degree n in v). For u0 ∈ [0, 1] its weights
    /// are positive; outside, they may not be (extrapolation).
    pub fn iso_u(&self, u0: f64) -> RationalCurve<P> {
        let num = self.numerator().iso_u(u0).into_points();
        let den = self.denominator().iso_u(u0).into_points();
        let pts = num
            .into_iter()
            .zip(&den)
            .map(|(p, &w)| p * (1.0 / w))
            .collect();
        RationalCurve::from_parts(pts, den)
    }

    /// The iso-parametric curve v = v0 (rational, degree m in u).
    pub fn iso_v(&self, v0: f64) -> RationalCurve<P> {
        self.transposed().iso_u(v0)
    }

    /// Degree elevation in u by k (on the homogeneous surface).
    pub fn elevate_u(&self, k: usize) -> Self {
        Self::from_homogeneous(
            self.numerator().elevate_u(k),
            self.denominator().elevate_u(k),
        )
    }

    /// Degree elevation in v by k.
    pub fn elevate_v(&self, k: usize) -> Self {
        Self::from_homogeneous(
            self.numerator().elevate_v(k),
            self.denominator().elevate_v(k),
        )
    }

    /// u and v swapped.
    pub fn transposed(&self) -> Self {
        Self {
            points: self.points.transposed(),
            weights: transpose(&self.weights),
        }
    }

    /// x̃(u, v) = x(1 − u, v).
    pub fn reversed_u(&self) -> Self {
        Self {
            points: self.points.reversed_u(),
            weights: self.weights.iter().rev().cloned().collect(),
        }
    }

    /// Map the control points, keeping the weights (maps the surface for affine maps).
    pub fn map<Q: Point>(&self, f: impl FnMut(P) -> Q) -> RationalSurface<Q> {
        RationalSurface {
            points: self.points.map(f),
            weights: self.weights.clone(),
        }
    }
}

impl RationalSurface<DVec3> {
    /// Unit normal, `None` where it is undefined (e.g. at a pole edge).
    pub fn normal(&self, u: f64, v: f64) -> Option<DVec3> {
        self.partials(u, v).normal()
    }

    /// (mean, Gaussian) curvature, see [`SurfacePartials::curvature`].
    pub fn curvature(&self, u: f64, v: f64) -> Option<(f64, f64)> {
        self.partials(u, v).curvature()
    }

    /// Surface of revolution of a profile in the (r, z) half-plane (x = r, z = z) turned by a
    /// circular arc in the xy-plane around the z axis through `center`: the tensor product of
    /// the two rational curves with product weights w_ij = ω_i·w_j, which factorizes as
    /// x(u, v) = center + r(v)·c(u) + z(v)·e_z exactly (seed 001 §2.4, §3).
    pub fn revolution(
        center: DVec3,
        arc: &RationalCurve<DVec3>,
        profile: &RationalCurve<DVec3>,
    ) -> Self {
        let points = arc
            .points()
            .iter()
            .map(|c| {
                profile
                    .points()
                    .iter()
                    .map(|q| center + DVec3::new(q.x * c.x, q.x * c.y, q.z))
                    .collect()
            })
            .collect();
        let weights = arc
            .weights()
            .iter()
            .map(|a| profile.weights().iter().map(|b| a * b).collect())
            .collect();
        Self {
            points: BezierSurface::from_grid(points),
            weights,
        }
    }

    /// One octant of the exact sphere as a biquadratic rational patch: quarter circle in u
    /// (azimuth from `phi0` to `phi0 + π/2`), quarter meridian in v from the equator to the north
    /// pole (`north`) or south pole; the pole edge v = 1 is degenerate. Weights are products of
    /// (1, √2/2, 1) (the seed's weights up to a common factor per row, seed 001 fig. 3.4).
    pub fn sphere_octant(
        center: DVec3,
        radius: f64,
        phi0: f64,
        north: bool,
    ) -> Result<Self, BezierError> {
        let q = std::f64::consts::FRAC_PI_2;
        let arc = RationalCurve::circular_arc(DVec3::ZERO, 1.0, phi0, q)?;
        if !(radius.is_finite() && radius > 0.0) {
            return Err(BezierError::BadRadius { radius });
        }
        // Profile in the (x = r, z) plane: the quarter arc (1, 0), (1, ±1), (0, ±1) times the
        // radius, written out so that the pole row has r = 0 exactly (a degenerate edge).
        let z = if north { radius } else { -radius };
        let meridian = RationalCurve::new(
            vec![
                DVec3::new(radius, 0.0, 0.0),
                DVec3::new(radius, 0.0, z),
                DVec3::new(0.0, 0.0, z),
            ],
            vec![1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0],
        )?;
        Ok(Self::revolution(center, &arc, &meridian))
    }

    /// The exact sphere as eight octant patches (four northern, then four southern). The
    /// southern patches are u-reversed so all normals x_u × x_v point outwards.
    pub fn sphere(center: DVec3, radius: f64) -> Result<Vec<Self>, BezierError> {
        let q = std::f64::consts::FRAC_PI_2;
        let mut out = Vec::with_capacity(8);
        for north in [true, false] {
            for k in 0..4 {
                let s = Self::sphere_octant(center, radius, k as f64 * q, north)?;
                out.push(if north { s } else { s.reversed_u() });
            }
        }
        Ok(out)
    }
}
