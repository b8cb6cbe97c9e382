//! Planar PH quintics in complex form (seed 004 §1.5 and §2.1; Farouki, "Pythagorean-Hodograph
//! Curves", ch. 11 and 17; Farouki & Neff 1995): the hodograph is the square of a complex
//! quadratic preimage, r′(t) = w(t)², so the parametric speed |r′| = |w|² is a polynomial.

use super::complex::Complex;
use super::error::{check_finite2, PhError};
use super::poly;
use crate::bezier::BezierCurve;
use glam::DVec2;

/// A planar PH quintic r(t) = p0 + ∫_0^t w(u)² du, t ∈ [0, 1], with the quadratic preimage
/// w(t) = w0 (1−t)² + 2 w1 (1−t)t + w2 t² (Bernstein coefficients `w`, seed 004 §2.1.2).
///
/// Sign conventions used throughout: the unit tangent is T = w²/|w|²; the unit normal is the
/// *right-hand* normal n = −i w²/|w|² (as in Algorithm 952); the signed curvature
/// κ = 2 Im(conj(w) w′)/|w|⁴ is positive where the curve turns left (counter-clockwise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanarPhQuintic {
    /// Start point r(0).
    pub p0: DVec2,
    /// Bernstein coefficients of the preimage w(t).
    pub w: [Complex; 3],
}

/// One of the four PH quintic Hermite interpolants with its shape measures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HermiteSolution {
    pub curve: PlanarPhQuintic,
    /// Sign η0 of the start root: w0 = η0 √(d0/Δp) √Δp (Algorithm 952's labelling).
    pub eta0: i8,
    /// Sign η2 of the end root: w2 = η2 √(d1/Δp) √Δp.
    pub eta2: i8,
    /// Absolute rotation index R = (1/2π) ∫ |κ| ds.
    pub rotation_index: f64,
    /// Elastic bending energy E = ∫ κ² ds.
    pub bending_energy: f64,
    /// Arc length L = ∫ |r′| dt.
    pub arc_length: f64,
}

/// All four Hermite interpolants and the index of the chosen one.
#[derive(Debug, Clone, PartialEq)]
pub struct HermiteSolutions {
    /// Solutions in the order (η0, η2) = (−1,−1), (−1,1), (1,−1), (1,1).
    pub solutions: [HermiteSolution; 4],
    /// Index of the solution with the smallest absolute rotation index (Farouki–Neff), ties
    /// (within 1e-9) broken by the smaller bending energy.
    pub best: usize,
}

impl HermiteSolutions {
    /// The chosen solution.
    pub fn best(&self) -> &HermiteSolution {
        &self.solutions[self.best]
    }
}

/// The extreme curvature of a curve: where |κ| is largest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvatureExtreme {
    /// Parameter of the maximum of |κ| on [0, 1].
    pub t: f64,
    /// Signed curvature there.
    pub curvature: f64,
    /// 1/|κ| (infinite for a straight line).
    pub radius: f64,
}

/// w0², w0w1, (2w1² + w0w2)/3, w1w2, w2² divided by 5: the control-polygon legs of a PH
/// quintic (Farouki eq. 17.6).
pub(crate) fn legs(w: &[Complex; 3]) -> [Complex; 5] {
    let [w0, w1, w2] = *w;
    [
        w0 * w0 * 0.2,
        w0 * w1 * 0.2,
        (w1 * w1 * 2.0 + w0 * w2) * (0.2 / 3.0),
        w1 * w2 * 0.2,
        w2 * w2 * 0.2,
    ]
}

impl PlanarPhQuintic {
    /// Curve from its start point and preimage coefficients; errors on non-finite input.
    pub fn new(p0: DVec2, w: [Complex; 3]) -> Result<Self, PhError> {
        check_finite2("p0", None, p0)?;
        if let Some(i) = w.iter().position(|z| !z.is_finite()) {
            return Err(PhError::NonFinite {
                arg: "w",
                index: Some(i),
            });
        }
        Ok(Self { p0, w })
    }

    /// Bézier control points p0..p5: p_{k+1} = p_k + leg_k with the legs
    /// w0²/5, w0w1/5, (2w1² + w0w2)/15, w1w2/5, w2²/5 (seed 004 §2.1.2, Farouki eq. 17.6).
    pub fn control_points(&self) -> [DVec2; 6] {
        let l = legs(&self.w);
        let mut p = [self.p0; 6];
        for k in 0..5 {
            p[k + 1] = p[k] + l[k].to_vec();
        }
        p
    }

    /// The curve as a Bézier curve of degree 5 (for the `bezier` layer's tools).
    pub fn bezier(&self) -> BezierCurve<DVec2> {
        BezierCurve::from_vec(self.control_points().to_vec())
    }

    /// End point r(1).
    pub fn end_point(&self) -> DVec2 {
        self.control_points()[5]
    }

    /// r(t) by de Casteljau on the control points.
    pub fn eval(&self, t: f64) -> DVec2 {
        poly::de_casteljau(self.control_points(), t)
    }

    /// w(t) = w0 (1−t)² + 2 w1 (1−t)t + w2 t².
    pub fn preimage(&self, t: f64) -> Complex {
        let s = 1.0 - t;
        let [w0, w1, w2] = self.w;
        w0 * (s * s) + w1 * (2.0 * s * t) + w2 * (t * t)
    }

    /// w′(t) = 2[(w1 − w0)(1−t) + (w2 − w1)t].
    pub fn preimage_derivative(&self, t: f64) -> Complex {
        let [w0, w1, w2] = self.w;
        ((w1 - w0) * (1.0 - t) + (w2 - w1) * t) * 2.0
    }

    /// Hodograph r′(t) = w(t)² (seed 004 §2.1.2).
    pub fn derivative(&self, t: f64) -> DVec2 {
        let w = self.preimage(t);
        (w * w).to_vec()
    }

    /// Second derivative r″(t) = 2 w w′.
    pub fn second_derivative(&self, t: f64) -> DVec2 {
        (self.preimage(t) * self.preimage_derivative(t) * 2.0).to_vec()
    }

    /// Parametric speed σ(t) = |r′(t)| = |w(t)|² (seed 004 §1.5: here a polynomial).
    pub fn speed(&self, t: f64) -> f64 {
        self.preimage(t).norm_sqr()
    }

    /// Bernstein coefficients of the quartic σ(t): |w0|², Re(w0 w̄1), (2|w1|² + Re(w0 w̄2))/3,
    /// Re(w1 w̄2), |w2|² (Farouki eq. 17.9).
    pub fn speed_coeffs(&self) -> [f64; 5] {
        let [w0, w1, w2] = self.w;
        [
            w0.norm_sqr(),
            (w0 * w1.conj()).re,
            (2.0 * w1.norm_sqr() + (w0 * w2.conj()).re) / 3.0,
            (w1 * w2.conj()).re,
            w2.norm_sqr(),
        ]
    }

    /// Bernstein coefficients of the quintic arc length s(t) = ∫_0^t σ: s_0 = 0,
    /// s_k = s_{k−1} + σ_{k−1}/5.
    pub fn arc_length_coeffs(&self) -> [f64; 6] {
        poly::arc_length_coeffs(&self.speed_coeffs())
    }

    /// Total arc length L = s(1) = (σ0 + … + σ4)/5 (exact).
    pub fn arc_length(&self) -> f64 {
        self.arc_length_coeffs()[5]
    }

    /// Arc length s(t) from 0 to t (exact polynomial).
    pub fn arc_length_at(&self, t: f64) -> f64 {
        poly::de_casteljau(self.arc_length_coeffs(), t)
    }

    /// The parameter t with s(t) = `s`, by Newton's method with a bisection safeguard; errors
    /// when s ∉ [0, L] or s is not finite.
    pub fn param_at_arc_length(&self, s: f64) -> Result<f64, PhError> {
        poly::invert_arc_length(&self.arc_length_coeffs(), &self.speed_coeffs(), s)
    }

    /// Unit tangent T = w²/|w|² (zero vector where w = 0).
    pub fn tangent(&self, t: f64) -> DVec2 {
        let w = self.preimage(t);
        let s = w.norm_sqr();
        if s == 0.0 {
            return DVec2::ZERO;
        }
        (w * w).to_vec() / s
    }

    /// Unit right-hand normal n = −i w²/|w|² = (T_y, −T_x) (zero vector where w = 0).
    pub fn normal(&self, t: f64) -> DVec2 {
        let tan = self.tangent(t);
        DVec2::new(tan.y, -tan.x)
    }

    /// Offset point r(t) + d n(t) (seed 004 §1.5: r_d = r + d n), d > 0 to the right.
    pub fn offset_point(&self, t: f64, d: f64) -> DVec2 {
        self.eval(t) + self.normal(t) * d
    }

    /// Signed curvature κ(t) = 2 Im(conj(w) w′)/|w|⁴ (from seed 004 §1.5,
    /// κ = (x′y″ − y′x″)/σ³ with r′ = w², r″ = 2ww′). Where w(t) = 0 the curvature is
    /// undefined and `f64::INFINITY` is returned.
    pub fn curvature(&self, t: f64) -> f64 {
        let w = self.preimage(t);
        let s = w.norm_sqr();
        if s == 0.0 {
            return f64::INFINITY;
        }
        2.0 * (w.conj() * self.preimage_derivative(t)).im / (s * s)
    }

    /// Power-basis coefficients of w: w(t) = a0 + a1 t + a2 t² with a0 = w0, a1 = 2(w1 − w0),
    /// a2 = w0 − 2w1 + w2.
    pub(crate) fn preimage_power(&self) -> [Complex; 3] {
        let [w0, w1, w2] = self.w;
        [w0, (w1 - w0) * 2.0, w0 - w1 * 2.0 + w2]
    }

    /// Power-basis σ(t) = |w|² (degree 4) and N(t) = Im(conj(w) w′) (degree ≤ 2), so that
    /// κ = 2N/σ².
    pub(crate) fn speed_and_turning_power(&self) -> (Vec<f64>, Vec<f64>) {
        let a = self.preimage_power();
        let ac: Vec<Complex> = a.iter().map(|z| z.conj()).collect();
        let da = [a[1], a[2] * 2.0];
        let sigma = poly::cmul(&ac, &a).iter().map(|z| z.re).collect();
        let n = poly::cmul(&ac, &da).iter().map(|z| z.im).collect();
        (sigma, n)
    }

    /// The complex roots of w(t) (0, 1 or 2 of them; none when w is constant). Uses the stable
    /// quadratic formula on w = a2 t² + 2b t + a0 with b = w1 − w0: q = −(b ± √(b² − a2 a0)),
    /// roots q/a2 and a0/q. A leading coefficient below 1e-15·(|w0|+|w1|+|w2|) is treated as 0.
    pub fn preimage_roots(&self) -> Vec<Complex> {
        let [w0, w1, w2] = self.w;
        let scale = w0.abs() + w1.abs() + w2.abs();
        let a2 = w0 - w1 * 2.0 + w2;
        let b = w1 - w0;
        if a2.abs() <= 1e-15 * scale {
            if b.abs() <= 1e-15 * scale {
                return Vec::new();
            }
            return vec![-(w0 / (b * 2.0))];
        }
        let disc = (b * b - a2 * w0).sqrt();
        let q = if (b.conj() * disc).re >= 0.0 {
            -(b + disc)
        } else {
            -(b - disc)
        };
        if q.norm_sqr() == 0.0 {
            // b = 0 and a2 w0 = 0, so w0 = 0: a double root at t = 0.
            return vec![Complex::ZERO, Complex::ZERO];
        }
        vec![q / a2, w0 / q]
    }

    /// Parameters in [0, 1] where w(t) = 0 (real roots of w): the curve stops there.
    pub fn singular_params(&self) -> Vec<f64> {
        let scale = self.w.iter().map(|z| z.abs()).sum::<f64>();
        self.preimage_roots()
            .into_iter()
            .filter(|r| r.im.abs() <= 1e-14 * (1.0 + r.re.abs()) && (0.0..=1.0).contains(&r.re))
            .filter(|r| self.preimage(r.re).abs() <= 1e-12 * scale)
            .map(|r| r.re)
            .collect()
    }

    /// Error when w vanishes somewhere on [0, 1].
    pub fn check_regular(&self) -> Result<(), PhError> {
        match self.singular_params().first() {
            Some(&t) => Err(PhError::SingularHodograph { t }),
            None => Ok(()),
        }
    }

    /// Absolute rotation index R = (1/2π) ∫_0^1 |κ| ds = (1/2π) ∫ |θ′| dt, θ = arg r′ = 2 arg w
    /// (Farouki & Neff 1995), computed exactly: [0, 1] is split at the roots of
    /// N = Im(conj(w) w′) (where θ′ changes sign); on each piece arg w is monotone and its change
    /// is Σ_roots a of w arg((t1 − a)/(t0 − a)), each term below π in magnitude. Then
    /// R = (1/π) Σ_pieces |Δ arg w|.
    pub fn rotation_index(&self) -> f64 {
        let (_, n) = self.speed_and_turning_power();
        let mut knots = vec![0.0];
        knots.extend(
            poly::roots_in(&n, 0.0, 1.0)
                .into_iter()
                .filter(|&t| t > 0.0 && t < 1.0),
        );
        knots.push(1.0);
        let roots = self.preimage_roots();
        let mut total = 0.0;
        for k in knots.windows(2) {
            let (t0, t1) = (Complex::new(k[0], 0.0), Complex::new(k[1], 0.0));
            let delta: f64 = roots
                .iter()
                .map(|&a| {
                    let (u, v) = (t1 - a, t0 - a);
                    if u.norm_sqr() == 0.0 || v.norm_sqr() == 0.0 {
                        0.0
                    } else {
                        (u / v).arg()
                    }
                })
                .sum();
            total += delta.abs();
        }
        total / std::f64::consts::PI
    }

    /// Elastic bending energy E = ∫ κ² ds = ∫_0^1 4 N(t)²/σ(t)³ dt (N = Im(conj(w) w′),
    /// σ = |w|², both exact polynomials), integrated by composite 16-point Gauss–Legendre
    /// quadrature, doubling the pieces until two passes agree to 1e-13 relative.
    /// Infinite when w vanishes on [0, 1].
    pub fn bending_energy(&self) -> f64 {
        if !self.singular_params().is_empty() {
            return f64::INFINITY;
        }
        let (sigma, n) = self.speed_and_turning_power();
        poly::integrate(|t| {
            let nn = poly::eval(&n, t);
            let s = poly::eval(&sigma, t);
            4.0 * nn * nn / (s * s * s)
        })
    }

    /// The maximum of |κ| on [0, 1] and the minimum radius of curvature 1/max|κ|. Candidates
    /// are t = 0, 1 and the roots in [0, 1] of N′σ − 2Nσ′ (the numerator of κ′ after dividing
    /// by σ, since κ = 2N/σ²). Errors when w vanishes on [0, 1] (κ unbounded).
    pub fn max_curvature(&self) -> Result<CurvatureExtreme, PhError> {
        self.check_regular()?;
        let (sigma, n) = self.speed_and_turning_power();
        let g = poly::lin(
            1.0,
            &poly::mul(&poly::derivative(&n), &sigma),
            -2.0,
            &poly::mul(&n, &poly::derivative(&sigma)),
        );
        let mut best = CurvatureExtreme {
            t: 0.0,
            curvature: 0.0,
            radius: f64::INFINITY,
        };
        let mut cands = vec![0.0, 1.0];
        cands.extend(poly::roots_in(&g, 0.0, 1.0));
        for t in cands {
            let k = self.curvature(t);
            if k.abs() > best.curvature.abs() || (best.curvature == 0.0 && t == 0.0) {
                best = CurvatureExtreme {
                    t,
                    curvature: k,
                    radius: if k == 0.0 {
                        f64::INFINITY
                    } else {
                        1.0 / k.abs()
                    },
                };
            }
        }
        Ok(best)
    }

    /// Minimum radius of curvature 1/max|κ| on [0, 1] (infinite for a straight segment).
    pub fn min_radius_of_curvature(&self) -> Result<f64, PhError> {
        Ok(self.max_curvature()?.radius)
    }

    /// The four first-order Hermite interpolants r(0) = p0, r′(0) = d0, r(1) = p1, r′(1) = d1
    /// (Farouki & Neff 1995; Algorithm 952 `construct_PHquintic`, which takes the control points
    /// p0, p0 + d0/5, p1 − d1/5, p1). In the canonical frame (Δp = p1 − p0 mapped to 1):
    /// w0 = η0 √(d0/Δp), w2 = η2 √(d1/Δp),
    /// w1 = −¾(w0 + w2) + ¼ √(120 − 15(w0² + w2²) + 10 w0 w2),
    /// then every w_k is multiplied by √Δp. The middle equation is ∫_0^1 w² = Δp written out
    /// with the legs of [`control_points`](Self::control_points). The chosen solution
    /// minimizes the absolute rotation index, ties broken by bending energy.
    pub fn hermite(
        p0: DVec2,
        d0: DVec2,
        p1: DVec2,
        d1: DVec2,
    ) -> Result<HermiteSolutions, PhError> {
        check_finite2("p0", None, p0)?;
        check_finite2("d0", None, d0)?;
        check_finite2("p1", None, p1)?;
        check_finite2("d1", None, d1)?;
        if d0 == DVec2::ZERO {
            return Err(PhError::ZeroDerivative {
                arg: "d0",
                index: None,
            });
        }
        if d1 == DVec2::ZERO {
            return Err(PhError::ZeroDerivative {
                arg: "d1",
                index: None,
            });
        }
        let dp = p1 - p0;
        let size = p0.abs().max(p1.abs()).max_element();
        if dp.length() <= f64::EPSILON * size || dp == DVec2::ZERO {
            return Err(PhError::CoincidentPoints {
                arg: "p0, p1",
                index: 0,
            });
        }
        let scale = Complex::from_vec(dp);
        let root_scale = scale.sqrt();
        let c0 = (Complex::from_vec(d0) / scale).sqrt();
        let c2 = (Complex::from_vec(d1) / scale).sqrt();
        let mut out = Vec::with_capacity(4);
        for eta0 in [-1i8, 1] {
            for eta2 in [-1i8, 1] {
                let w0 = c0 * f64::from(eta0);
                let w2 = c2 * f64::from(eta2);
                let rad = Complex::new(120.0, 0.0) - (w0 * w0 + w2 * w2) * 15.0 + w0 * w2 * 10.0;
                let w1 = (w0 + w2) * -0.75 + rad.sqrt() * 0.25;
                let curve = PlanarPhQuintic {
                    p0,
                    w: [w0 * root_scale, w1 * root_scale, w2 * root_scale],
                };
                out.push(HermiteSolution {
                    curve,
                    eta0,
                    eta2,
                    rotation_index: curve.rotation_index(),
                    bending_energy: curve.bending_energy(),
                    arc_length: curve.arc_length(),
                });
            }
        }
        let solutions: [HermiteSolution; 4] = [out[0], out[1], out[2], out[3]];
        let mut best = 0;
        for (i, s) in solutions.iter().enumerate().skip(1) {
            let b = &solutions[best];
            let better = if (s.rotation_index - b.rotation_index).abs() <= 1e-9 {
                s.bending_energy < b.bending_energy
            } else {
                s.rotation_index < b.rotation_index
            };
            if better {
                best = i;
            }
        }
        Ok(HermiteSolutions { solutions, best })
    }
}
