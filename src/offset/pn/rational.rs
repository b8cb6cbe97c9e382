//! Exact rational Bézier form of a PN patch and of its offsets (seed 004 §4.2–4.6).
//!
//! Write the isotropic patch as y = (a, b, c) (bicubic polynomials). The surface point x is the
//! envelope of the planes q·(x·n − h) = 2a x_1 + 2b x_2 + (a² + b² − 1) x_3 − 2c = 0 and their
//! u- and v-derivatives. Solving these three linear equations (the same x as the general formula
//! x = h n + N (NᵀN)⁻¹ ∇h of seed 004 §4.2) gives, with
//! J = a_u b_v − a_v b_u, A = b_v c_u − b_u c_v, B = a_u c_v − a_v c_u,
//! S = a A + b B − c J, q = 1 + a² + b²:
//! x = (q A − 2a S, q B − 2b S, 2S) / (q J).
//! The 3 × 3 system has determinant −q·J; one factor q cancels against the Cramer numerators,
//! leaving the denominator W = q J. Degrees per parameter: a, b, c 3; J, A, B 5; S 8; q 6;
//! W and the numerators 11. So every patch is a rational Bézier patch of degree (11, 11).
//! The offset x + d·n = (X + d·J·(2a, 2b, a² + b² − 1)) / W has the same degree and weights.
//! The unit normal n = (2a, 2b, a² + b² − 1)/q is rational of degree (6, 6).
//! All products are computed exactly (up to round-off) in the Bernstein basis:
//! a product of degrees (m1, n1) and (m2, n2) has coefficients
//! c_ij = Σ C(m1,i1) C(m2,i2) / C(m1+m2,i) · C(n1,j1) C(n2,j2) / C(n1+n2,j) · a_{i1 j1} b_{i2 j2}.

use crate::bezier::bernstein::binomial;
use crate::bezier::{BezierError, BezierSurface, RationalSurface};
use glam::{DVec3, DVec4};

/// A scalar tensor-product polynomial in Bernstein form, degree (m, n), coefficients row-major
/// `c[i·(n+1) + j]`, i along u.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Bern2 {
    m: usize,
    n: usize,
    c: Vec<f64>,
}

impl Bern2 {
    fn get(&self, i: usize, j: usize) -> f64 {
        self.c[i * (self.n + 1) + j]
    }

    /// One coordinate of a Bézier surface.
    pub(crate) fn coordinate(s: &BezierSurface<DVec3>, k: usize) -> Self {
        let (m, n) = (s.degree_u(), s.degree_v());
        let c = s
            .points()
            .iter()
            .flat_map(|r| r.iter().map(move |p| p[k]))
            .collect();
        Self { m, n, c }
    }

    fn constant(v: f64) -> Self {
        Self {
            m: 0,
            n: 0,
            c: vec![v],
        }
    }

    /// ∂/∂u: degree (m − 1, n), coefficients m (c_{i+1,j} − c_ij).
    fn d_u(&self) -> Self {
        let (m, n) = (self.m, self.n);
        let mut c = Vec::with_capacity(m * (n + 1));
        for i in 0..m {
            for j in 0..=n {
                c.push(m as f64 * (self.get(i + 1, j) - self.get(i, j)));
            }
        }
        Self { m: m - 1, n, c }
    }

    /// ∂/∂v: degree (m, n − 1).
    fn d_v(&self) -> Self {
        let (m, n) = (self.m, self.n);
        let mut c = Vec::with_capacity((m + 1) * n);
        for i in 0..=m {
            for j in 0..n {
                c.push(n as f64 * (self.get(i, j + 1) - self.get(i, j)));
            }
        }
        Self { m, n: n - 1, c }
    }

    /// Bernstein product (formula in the module doc).
    fn mul(&self, o: &Self) -> Self {
        let (m, n) = (self.m + o.m, self.n + o.n);
        let mut c = vec![0.0; (m + 1) * (n + 1)];
        for i1 in 0..=self.m {
            for j1 in 0..=self.n {
                let x = self.get(i1, j1) * binomial(self.m, i1) * binomial(self.n, j1);
                for i2 in 0..=o.m {
                    for j2 in 0..=o.n {
                        let y = o.get(i2, j2) * binomial(o.m, i2) * binomial(o.n, j2);
                        c[(i1 + i2) * (n + 1) + j1 + j2] += x * y;
                    }
                }
            }
        }
        for i in 0..=m {
            for j in 0..=n {
                c[i * (n + 1) + j] /= binomial(m, i) * binomial(n, j);
            }
        }
        Self { m, n, c }
    }

    fn scale(&self, k: f64) -> Self {
        Self {
            m: self.m,
            n: self.n,
            c: self.c.iter().map(|x| x * k).collect(),
        }
    }

    /// Degree elevation to (m2, n2) ≥ (m, n): product with the constant 1 of degree
    /// (m2 − m, n2 − n), whose Bernstein coefficients are all 1.
    fn elevate_to(&self, m2: usize, n2: usize) -> Self {
        if (m2, n2) == (self.m, self.n) {
            return self.clone();
        }
        let one = Self {
            m: m2 - self.m,
            n: n2 - self.n,
            c: vec![1.0; (m2 - self.m + 1) * (n2 - self.n + 1)],
        };
        self.mul(&one)
    }

    /// self + k·o, at the larger of the two degrees.
    fn add_scaled(&self, o: &Self, k: f64) -> Self {
        let (m, n) = (self.m.max(o.m), self.n.max(o.n));
        let (a, b) = (self.elevate_to(m, n), o.elevate_to(m, n));
        Self {
            m,
            n,
            c: a.c.iter().zip(&b.c).map(|(x, y)| x + k * y).collect(),
        }
    }

    /// True when all coefficients are > 0 or all are < 0 (then the polynomial has no zero on
    /// the unit square: the convex-hull property).
    pub(crate) fn one_signed(&self) -> bool {
        self.c.iter().all(|&x| x > 0.0) || self.c.iter().all(|&x| x < 0.0)
    }

    fn sum(&self) -> f64 {
        self.c.iter().sum()
    }
}

/// Pack three numerator coordinates and a weight into homogeneous control points (w·p, w) after
/// mapping the numerator by `map` (a linear map: the frame rotation back to world).
fn homogeneous(
    x: [&Bern2; 3],
    w: &Bern2,
    map: impl Fn(DVec3) -> DVec3,
) -> Result<BezierSurface<DVec4>, BezierError> {
    let (m, n) = (w.m, w.n);
    let grid = (0..=m)
        .map(|i| {
            (0..=n)
                .map(|j| {
                    let p = map(DVec3::new(x[0].get(i, j), x[1].get(i, j), x[2].get(i, j)));
                    p.extend(w.get(i, j))
                })
                .collect()
        })
        .collect();
    BezierSurface::new(grid)
}

/// The polynomial pieces of one PN patch in the isotropic frame (module doc for the formulas).
pub(crate) struct PatchPolys {
    a: Bern2,
    b: Bern2,
    /// J = a_u b_v − a_v b_u, degree (5, 5).
    pub(crate) j: Bern2,
    /// q = 1 + a² + b², degree (6, 6).
    q: Bern2,
    /// Numerator X, degree (11, 11), sign-normalized together with `w`.
    x: [Bern2; 3],
    /// W = q J, degree (11, 11), multiplied by −1 when J is mostly negative.
    w: Bern2,
    /// ±1: the sign applied to X and W.
    sign: f64,
}

impl PatchPolys {
    /// From the bicubic Bézier form of the isotropic patch.
    pub(crate) fn new(y: &BezierSurface<DVec3>) -> Self {
        let (a, b, c) = (
            Bern2::coordinate(y, 0),
            Bern2::coordinate(y, 1),
            Bern2::coordinate(y, 2),
        );
        let (a_u, a_v, b_u, b_v, c_u, c_v) = (a.d_u(), a.d_v(), b.d_u(), b.d_v(), c.d_u(), c.d_v());
        let j = a_u.mul(&b_v).add_scaled(&a_v.mul(&b_u), -1.0);
        let big_a = b_v.mul(&c_u).add_scaled(&b_u.mul(&c_v), -1.0);
        let big_b = a_u.mul(&c_v).add_scaled(&a_v.mul(&c_u), -1.0);
        let s = a
            .mul(&big_a)
            .add_scaled(&b.mul(&big_b), 1.0)
            .add_scaled(&c.mul(&j), -1.0);
        let q = Bern2::constant(1.0)
            .add_scaled(&a.mul(&a), 1.0)
            .add_scaled(&b.mul(&b), 1.0);
        let sign = if j.sum() < 0.0 { -1.0 } else { 1.0 };
        let w = q.mul(&j).scale(sign);
        let x1 = q.mul(&big_a).add_scaled(&a.mul(&s), -2.0).scale(sign);
        let x2 = q.mul(&big_b).add_scaled(&b.mul(&s), -2.0).scale(sign);
        let x3 = s.scale(2.0 * sign).elevate_to(w.m, w.n);
        Self {
            a,
            b,
            j,
            q,
            x: [x1, x2, x3],
            w,
            sign,
        }
    }

    /// Numerator of the unit normal times q: (2a, 2b, a² + b² − 1), degree (6, 6).
    fn normal_numerator(&self) -> [Bern2; 3] {
        let r2 = self.a.mul(&self.a).add_scaled(&self.b.mul(&self.b), 1.0);
        [
            self.a.scale(2.0).elevate_to(6, 6),
            self.b.scale(2.0).elevate_to(6, 6),
            r2.add_scaled(&Bern2::constant(1.0), -1.0),
        ]
    }

    /// The patch (d = 0) or its offset at distance d: numerator X + d·(±J)·(2a, 2b, a²+b²−1),
    /// weight W; world coordinates through `to_world`.
    pub(crate) fn offset_form(
        &self,
        d: f64,
        to_world: impl Fn(DVec3) -> DVec3,
    ) -> Result<PnRational, BezierError> {
        let x = if d == 0.0 {
            self.x.clone()
        } else {
            let sj = self.j.scale(self.sign * d);
            let nn = self.normal_numerator();
            [0, 1, 2].map(|k| self.x[k].add_scaled(&sj.mul(&nn[k]), 1.0))
        };
        Ok(PnRational {
            homogeneous: homogeneous([&x[0], &x[1], &x[2]], &self.w, to_world)?,
        })
    }

    /// The unit normal n = (2a, 2b, a² + b² − 1)/q as a rational patch of degree (6, 6).
    pub(crate) fn normal_form(
        &self,
        to_world: impl Fn(DVec3) -> DVec3,
    ) -> Result<PnRational, BezierError> {
        let nn = self.normal_numerator();
        Ok(PnRational {
            homogeneous: homogeneous([&nn[0], &nn[1], &nn[2]], &self.q, to_world)?,
        })
    }
}

/// A rational tensor-product Bézier patch in homogeneous form: control points (w·p, w) of
/// degree (11, 11) for a PN patch or its offset, (6, 6) for its unit normal.
/// p(u, v) = X(u, v)/W(u, v) with (X, W) the homogeneous Bézier surface.
/// Weights may be zero or negative at control points (W = q·J is positive or negative on the
/// whole patch, and its sign is normalized to be mostly positive), so the homogeneous form is
/// the primary export; [`PnRational::to_rational_surface`] converts when all weights are > 0.
#[derive(Debug, Clone, PartialEq)]
pub struct PnRational {
    /// Homogeneous control points (w·p, w).
    pub homogeneous: BezierSurface<DVec4>,
}

impl PnRational {
    /// Degree (in u, in v).
    pub fn degree(&self) -> (usize, usize) {
        (self.homogeneous.degree_u(), self.homogeneous.degree_v())
    }

    /// The weights w_ij.
    pub fn weights(&self) -> Vec<Vec<f64>> {
        self.homogeneous
            .points()
            .iter()
            .map(|r| r.iter().map(|p| p.w).collect())
            .collect()
    }

    /// p(u, v) = X/W; `None` where W = 0 or the quotient is not finite.
    pub fn eval(&self, u: f64, v: f64) -> Option<DVec3> {
        let h = self.homogeneous.eval(u, v);
        let p = h.truncate() / h.w;
        (h.w != 0.0 && p.is_finite()).then_some(p)
    }

    /// p, p_u, p_v by the quotient rule p_u = (X_u − p W_u)/W; `None` where W = 0.
    pub fn partials(&self, u: f64, v: f64) -> Option<(DVec3, DVec3, DVec3)> {
        let s = self.homogeneous.partials(u, v);
        if s.p.w == 0.0 {
            return None;
        }
        let p = s.p.truncate() / s.p.w;
        let pu = (s.u.truncate() - p * s.u.w) / s.p.w;
        let pv = (s.v.truncate() - p * s.v.w) / s.p.w;
        (p.is_finite() && pu.is_finite() && pv.is_finite()).then_some((p, pu, pv))
    }

    /// The same patch as a [`RationalSurface`] (control points p_ij = X_ij / w_ij, weights w_ij);
    /// errors with [`BezierError::BadWeight`] when a weight is not positive.
    pub fn to_rational_surface(&self) -> Result<RationalSurface<DVec3>, BezierError> {
        let cols = self.homogeneous.degree_v() + 1;
        let mut points = Vec::new();
        let mut weights = Vec::new();
        for (i, r) in self.homogeneous.points().iter().enumerate() {
            let mut pr = Vec::with_capacity(cols);
            let mut wr = Vec::with_capacity(cols);
            for (j, h) in r.iter().enumerate() {
                if h.w.is_nan() || h.w <= 0.0 {
                    return Err(BezierError::BadWeight {
                        index: i * cols + j,
                        value: h.w,
                    });
                }
                pr.push(h.truncate() / h.w);
                wr.push(h.w);
            }
            points.push(pr);
            weights.push(wr);
        }
        RationalSurface::new(points, weights)
    }
}
