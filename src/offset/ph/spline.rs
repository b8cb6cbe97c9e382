//! PH quintic splines (Farouki, "Pythagorean-Hodograph Curves", ch. 18–19; Albrecht & Farouki
//! 1996; Farouki, Kuspa, Manni & Sestini 2001; Algorithm 952 `open_PHquintic_spline`,
//! `closed_PHquintic_spline`):
//! - segment-wise Hermite PH quintics through points with tangents (C¹), planar and spatial;
//! - C² planar PH quintic splines through points, open and closed, by Newton–Raphson on the
//!   complex quadratic system in the unknowns z_1..z_n.
//!
//! C² construction. Segment i (1..n) runs from q_{i−1} to q_i with preimage coefficients
//! w0 = (z_{i−1} + z_i)/2, w1 = z_i, w2 = (z_i + z_{i+1})/2. Then w and w′ agree at every
//! joint, so r′ = w² and r″ = 2ww′ do: the spline is C² by construction, and the remaining
//! condition ∫ w_i² = q_i − q_{i−1} reads (×60)
//!   f_i = 3z_{i−1}² + 27z_i² + 3z_{i+1}² + z_{i−1}z_{i+1} + 13z_{i−1}z_i + 13z_i z_{i+1}
//!         − 60(q_i − q_{i−1}) = 0,
//! with ∂f_i/∂z_{i−1} = 6z_{i−1} + 13z_i + z_{i+1}, ∂f_i/∂z_i = 13z_{i−1} + 54z_i + 13z_{i+1},
//! ∂f_i/∂z_{i+1} = z_{i−1} + 13z_i + 6z_{i+1}: a tridiagonal (open) or cyclic tridiagonal
//! (closed) Jacobian. End conditions:
//! - open, [`OpenEnds::CubicEndSpans`] (Algorithm 952): z_0 = 2z_1 − z_2, z_{n+1} = 2z_n − z_{n−1},
//!   so w is linear on the end spans (they are cubics);
//! - open, [`OpenEnds::Derivatives`]: w_1(0)² = r′(0) = d_start and w_n(1)² = d_end, i.e.
//!   z_0 = 2s_0 − z_1, z_{n+1} = 2s_1 − z_n with s_0 = ±√d_start, s_1 = ±√d_end (sign: the one
//!   closer to the starting guess of the end span's mid-point preimage);
//! - closed: z_0 = η z_n, z_{n+1} = η z_1 with η = ±1 fixed from the starting guess.
//!
//! Starting guess (Algorithm 952): the C² cubic spline through the points gives nodal
//! derivatives d_i; the PH mid-point preimage of segment i should satisfy
//! w_i(½)² = r′(½) = (6Δq_i − d_{i−1} − d_i)/4, and w_i(½) = (z_{i−1} + 6z_i + z_{i+1})/8, so
//! z solves the linear system z_{i−1} + 6z_i + z_{i+1} = 8√((6Δq_i − d_{i−1} − d_i)/4) with
//! the square roots' signs chosen continuously from segment to segment.
//!
//! Each segment is a [`PlanarPhQuintic`] holding its own w, so its speed, arc length and offset
//! use that segment's data only (the published C code writes segment 1's σ_1 for every
//! segment; that slip cannot occur here).

use super::complex::Complex;
use super::error::{check_finite2, check_finite3, PhError};
use super::planar::PlanarPhQuintic;
use super::spatial::SpatialPhQuintic;
use glam::{DVec2, DVec3};

/// End conditions of an open C² PH quintic spline.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum OpenEnds {
    /// The first and last spans are cubics (w linear there), as in Algorithm 952. Needs at
    /// least 3 points.
    #[default]
    CubicEndSpans,
    /// Given end derivatives r′(0) of the first segment and r′(1) of the last one.
    Derivatives { start: DVec2, end: DVec2 },
}

/// A planar PH quintic spline: segment i runs from point i to point i + 1 (for a closed spline
/// the last segment returns to point 0).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarPhSpline {
    pub segments: Vec<PlanarPhQuintic>,
    pub closed: bool,
    /// Newton iterations used (0 for Hermite splines).
    pub iterations: usize,
}

/// A spatial PH quintic spline (segment-wise Hermite).
#[derive(Debug, Clone, PartialEq)]
pub struct SpatialPhSpline {
    pub segments: Vec<SpatialPhQuintic>,
}

fn check_points2(
    arg: &'static str,
    pts: &[DVec2],
    need: usize,
    closed: bool,
) -> Result<(), PhError> {
    if pts.len() < need {
        return Err(PhError::TooFewPoints {
            arg,
            got: pts.len(),
            need,
        });
    }
    for (i, p) in pts.iter().enumerate() {
        check_finite2(arg, Some(i), *p)?;
    }
    let m = if closed { pts.len() } else { pts.len() - 1 };
    for i in 0..m {
        let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
        let size = a.abs().max(b.abs()).max_element();
        if a == b || (b - a).length() <= f64::EPSILON * size {
            return Err(PhError::CoincidentPoints { arg, index: i });
        }
    }
    Ok(())
}

impl PlanarPhSpline {
    /// Segment-wise Hermite interpolation: segment i is the chosen (least absolute rotation
    /// index) PH quintic with r(0) = points[i], r′(0) = tangents[i], r(1) = points[i+1],
    /// r′(1) = tangents[i+1]. C¹ at the joints.
    pub fn hermite(points: &[DVec2], tangents: &[DVec2]) -> Result<Self, PhError> {
        check_points2("points", points, 2, false)?;
        if tangents.len() != points.len() {
            return Err(PhError::LengthMismatch {
                arg: "tangents",
                got: tangents.len(),
                expected: points.len(),
            });
        }
        for (i, d) in tangents.iter().enumerate() {
            check_finite2("tangents", Some(i), *d)?;
            if *d == DVec2::ZERO {
                return Err(PhError::ZeroDerivative {
                    arg: "tangents",
                    index: Some(i),
                });
            }
        }
        let segments = (0..points.len() - 1)
            .map(|i| {
                PlanarPhQuintic::hermite(points[i], tangents[i], points[i + 1], tangents[i + 1])
                    .map(|s| s.best().curve)
            })
            .collect::<Result<_, _>>()?;
        Ok(Self {
            segments,
            closed: false,
            iterations: 0,
        })
    }

    /// Open C² PH quintic spline through `points` (at least 3 for cubic end spans, 2 for given
    /// end derivatives).
    pub fn c2_open(points: &[DVec2], ends: OpenEnds) -> Result<Self, PhError> {
        let need = match ends {
            OpenEnds::CubicEndSpans => 3,
            OpenEnds::Derivatives { start, end } => {
                check_finite2("ends.start", None, start)?;
                check_finite2("ends.end", None, end)?;
                if start == DVec2::ZERO {
                    return Err(PhError::ZeroDerivative {
                        arg: "ends.start",
                        index: None,
                    });
                }
                if end == DVec2::ZERO {
                    return Err(PhError::ZeroDerivative {
                        arg: "ends.end",
                        index: None,
                    });
                }
                2
            }
        };
        check_points2("points", points, need, false)?;
        let q: Vec<Complex> = points.iter().map(|p| Complex::from_vec(*p)).collect();
        let n = q.len() - 1;
        // Nodal derivatives of the C² cubic spline (starting guess).
        let mut sys = Cyclic::new(n + 1);
        let mut rhs = vec![Complex::ZERO; n + 1];
        match ends {
            OpenEnds::CubicEndSpans => {
                sys.add(0, 0, 1.0.into());
                sys.add(0, 1, 1.0.into());
                rhs[0] = (q[1] - q[0]) * 2.0;
                sys.add(n, n - 1, 1.0.into());
                sys.add(n, n, 1.0.into());
                rhs[n] = (q[n] - q[n - 1]) * 2.0;
            }
            OpenEnds::Derivatives { start, end } => {
                sys.add(0, 0, 1.0.into());
                rhs[0] = Complex::from_vec(start);
                sys.add(n, n, 1.0.into());
                rhs[n] = Complex::from_vec(end);
            }
        }
        for i in 1..n {
            sys.add(i, i - 1, 1.0.into());
            sys.add(i, i, 4.0.into());
            sys.add(i, i + 1, 1.0.into());
            rhs[i] = (q[i + 1] - q[i - 1]) * 3.0;
        }
        let dq = sys.solve(&rhs);
        let mid = mid_guesses(&q, &dq, n, false);
        let (start, end) = match ends {
            OpenEnds::CubicEndSpans => (
                Boundary::Affine {
                    alpha: Complex::ZERO,
                    beta: 2.0,
                    gamma: -1.0,
                },
                Boundary::Affine {
                    alpha: Complex::ZERO,
                    beta: 2.0,
                    gamma: -1.0,
                },
            ),
            OpenEnds::Derivatives { start, end } => {
                let s0 = aligned_root(Complex::from_vec(start), mid[0]);
                let s1 = aligned_root(Complex::from_vec(end), mid[n - 1]);
                (
                    Boundary::Affine {
                        alpha: s0 * 2.0,
                        beta: -1.0,
                        gamma: 0.0,
                    },
                    Boundary::Affine {
                        alpha: s1 * 2.0,
                        beta: -1.0,
                        gamma: 0.0,
                    },
                )
            }
        };
        solve_c2(&q, n, start, end, &mid, false)
    }

    /// Closed C² PH quintic spline through `points` (at least 3 distinct points, the first one
    /// not repeated at the end); segment n−1 runs from the last point back to the first.
    pub fn c2_closed(points: &[DVec2]) -> Result<Self, PhError> {
        check_points2("points", points, 3, true)?;
        let mut q: Vec<Complex> = points.iter().map(|p| Complex::from_vec(*p)).collect();
        let n = q.len();
        q.push(q[0]);
        let mut sys = Cyclic::new(n);
        let mut rhs = vec![Complex::ZERO; n];
        for i in 0..n {
            sys.add(i, (i + n - 1) % n, 1.0.into());
            sys.add(i, i, 4.0.into());
            sys.add(i, (i + 1) % n, 1.0.into());
            rhs[i] = (q[i + 1] - q[(i + n - 1) % n]) * 3.0;
        }
        let mut dq = sys.solve(&rhs);
        dq.push(dq[0]);
        let mid = mid_guesses(&q, &dq, n, true);
        let eta = if (mid[n - 1] * mid[0].conj()).re < 0.0 {
            -1.0
        } else {
            1.0
        };
        solve_c2(
            &q,
            n,
            Boundary::Periodic { eta },
            Boundary::Periodic { eta },
            &mid,
            true,
        )
    }

    /// Total arc length (sum of the exact segment lengths).
    pub fn arc_length(&self) -> f64 {
        self.segments.iter().map(|s| s.arc_length()).sum()
    }

    /// Point at global parameter u ∈ [0, n]: segment ⌊u⌋ (clamped) at u − ⌊u⌋.
    pub fn eval(&self, u: f64) -> DVec2 {
        let (i, t) = split(u, self.segments.len());
        self.segments[i].eval(t)
    }
}

impl SpatialPhSpline {
    /// Segment-wise spatial Hermite interpolation with the default angles of
    /// [`SpatialPhQuintic::hermite_default`] (`angles = None`) or given (φ0, φ2) for every
    /// segment.
    pub fn hermite(
        points: &[DVec3],
        tangents: &[DVec3],
        angles: Option<(f64, f64)>,
    ) -> Result<Self, PhError> {
        if points.len() < 2 {
            return Err(PhError::TooFewPoints {
                arg: "points",
                got: points.len(),
                need: 2,
            });
        }
        if tangents.len() != points.len() {
            return Err(PhError::LengthMismatch {
                arg: "tangents",
                got: tangents.len(),
                expected: points.len(),
            });
        }
        for (i, p) in points.iter().enumerate() {
            check_finite3("points", Some(i), *p)?;
        }
        for (i, d) in tangents.iter().enumerate() {
            check_finite3("tangents", Some(i), *d)?;
            if *d == DVec3::ZERO {
                return Err(PhError::ZeroDerivative {
                    arg: "tangents",
                    index: Some(i),
                });
            }
        }
        for i in 0..points.len() - 1 {
            let (a, b) = (points[i], points[i + 1]);
            let size = a.abs().max(b.abs()).max_element();
            if a == b || (b - a).length() <= f64::EPSILON * size {
                return Err(PhError::CoincidentPoints {
                    arg: "points",
                    index: i,
                });
            }
        }
        let segments = (0..points.len() - 1)
            .map(|i| {
                let (p0, d0, p1, d1) = (points[i], tangents[i], points[i + 1], tangents[i + 1]);
                match angles {
                    None => SpatialPhQuintic::hermite_default(p0, d0, p1, d1),
                    Some((a, b)) => SpatialPhQuintic::hermite(p0, d0, p1, d1, a, b),
                }
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { segments })
    }

    /// Total arc length.
    pub fn arc_length(&self) -> f64 {
        self.segments.iter().map(|s| s.arc_length()).sum()
    }

    /// Point at global parameter u ∈ [0, n].
    pub fn eval(&self, u: f64) -> DVec3 {
        let (i, t) = split(u, self.segments.len());
        self.segments[i].eval(t)
    }
}

fn split(u: f64, n: usize) -> (usize, f64) {
    let i = (u.floor().max(0.0) as usize).min(n - 1);
    (i, u - i as f64)
}

/// The square root of `d` with the sign closer to `guess` (Re(conj(root)·guess) ≥ 0).
fn aligned_root(d: Complex, guess: Complex) -> Complex {
    let r = d.sqrt();
    if (r.conj() * guess).re < 0.0 {
        -r
    } else {
        r
    }
}

/// Mid-point preimages w_i(½) = √((6Δq_i − d_{i−1} − d_i)/4), i = 1..n (stored at i − 1), with
/// signs continuous along the spline.
fn mid_guesses(q: &[Complex], dq: &[Complex], n: usize, _closed: bool) -> Vec<Complex> {
    let mut mid: Vec<Complex> = Vec::with_capacity(n);
    for i in 1..=n {
        let m = ((q[i] - q[i - 1]) * 6.0 - dq[i - 1] - dq[i]) * 0.25;
        let r = m.sqrt();
        let r = match mid.last() {
            Some(prev) if (prev.conj() * r).re < 0.0 => -r,
            _ => r,
        };
        mid.push(r);
    }
    mid
}

/// How the ghost unknowns z_0 and z_{n+1} depend on z_1..z_n.
#[derive(Debug, Clone, Copy)]
enum Boundary {
    /// z_0 = α + β z_1 + γ z_2 (start) or z_{n+1} = α + β z_n + γ z_{n−1} (end).
    Affine {
        alpha: Complex,
        beta: f64,
        gamma: f64,
    },
    /// z_0 = η z_n (start) or z_{n+1} = η z_1 (end).
    Periodic { eta: f64 },
}

/// z_0..z_{n+1} from the unknowns z_1..z_n (stored at 0..n−1).
fn full(z: &[Complex], start: Boundary, end: Boundary) -> Vec<Complex> {
    let n = z.len();
    let get = |k: usize| if k < n { z[k] } else { Complex::ZERO };
    let z0 = match start {
        Boundary::Affine { alpha, beta, gamma } => alpha + z[0] * beta + get(1) * gamma,
        Boundary::Periodic { eta } => z[n - 1] * eta,
    };
    let zn1 = match end {
        Boundary::Affine { alpha, beta, gamma } => {
            alpha
                + z[n - 1] * beta
                + if n >= 2 {
                    z[n - 2] * gamma
                } else {
                    Complex::ZERO
                }
        }
        Boundary::Periodic { eta } => z[0] * eta,
    };
    let mut out = Vec::with_capacity(n + 2);
    out.push(z0);
    out.extend_from_slice(z);
    out.push(zn1);
    out
}

/// Assemble Σ_rows (ca z_{i−1} + cb z_i + cc z_{i+1}) with the ghost unknowns substituted:
/// returns the matrix and the constant parts (α terms) per row.
fn assemble(coef: &[[Complex; 3]], start: Boundary, end: Boundary) -> (Cyclic, Vec<Complex>) {
    let n = coef.len();
    let mut m = Cyclic::new(n);
    let mut konst = vec![Complex::ZERO; n];
    for (i, &[ca, cb, cc]) in coef.iter().enumerate() {
        m.add(i, i, cb);
        if i > 0 {
            m.add(i, i - 1, ca);
        } else {
            match start {
                Boundary::Affine { alpha, beta, gamma } => {
                    m.add(0, 0, ca * beta);
                    if gamma != 0.0 {
                        m.add(0, 1, ca * gamma);
                    }
                    konst[0] += ca * alpha;
                }
                Boundary::Periodic { eta } => m.add(0, n - 1, ca * eta),
            }
        }
        if i + 1 < n {
            m.add(i, i + 1, cc);
        } else {
            match end {
                Boundary::Affine { alpha, beta, gamma } => {
                    m.add(n - 1, n - 1, cc * beta);
                    if gamma != 0.0 {
                        m.add(n - 1, n - 2, cc * gamma);
                    }
                    konst[n - 1] += cc * alpha;
                }
                Boundary::Periodic { eta } => m.add(n - 1, 0, cc * eta),
            }
        }
    }
    (m, konst)
}

fn solve_c2(
    q: &[Complex],
    n: usize,
    start: Boundary,
    end: Boundary,
    mid: &[Complex],
    closed: bool,
) -> Result<PlanarPhSpline, PhError> {
    // Starting guess: z_{i−1} + 6 z_i + z_{i+1} = 8 w_i(½).
    let one = Complex::ONE;
    let (m, konst) = assemble(&vec![[one, one * 6.0, one]; n], start, end);
    let rhs: Vec<Complex> = (0..n).map(|i| mid[i] * 8.0 - konst[i]).collect();
    let mut z = m.solve(&rhs);
    let dq: Vec<Complex> = (1..=n).map(|i| q[i] - q[i - 1]).collect();
    let qscale = dq.iter().map(|d| d.abs()).fold(0.0, f64::max);
    let residual = |z: &[Complex]| -> (Vec<Complex>, f64) {
        let zf = full(z, start, end);
        let f: Vec<Complex> = (1..=n)
            .map(|i| {
                let (a, b, c) = (zf[i - 1], zf[i], zf[i + 1]);
                a * a * 3.0 + b * b * 27.0 + c * c * 3.0 + a * c + a * b * 13.0 + b * c * 13.0
                    - dq[i - 1] * 60.0
            })
            .collect();
        let r = f.iter().map(|x| x.abs()).fold(0.0, f64::max) / 60.0;
        (f, r)
    };
    const MAX_ITER: usize = 50;
    let mut iterations = 0;
    let (mut f, mut res) = residual(&z);
    while iterations < MAX_ITER {
        if !res.is_finite() {
            break;
        }
        iterations += 1;
        let zf = full(&z, start, end);
        let coef: Vec<[Complex; 3]> = (1..=n)
            .map(|i| {
                let (a, b, c) = (zf[i - 1], zf[i], zf[i + 1]);
                [
                    a * 6.0 + b * 13.0 + c,
                    a * 13.0 + b * 54.0 + c * 13.0,
                    a + b * 13.0 + c * 6.0,
                ]
            })
            .collect();
        // The Jacobian of the α terms is zero: only the matrix is used.
        let (jac, _) = assemble(&coef, start, end);
        let rhs: Vec<Complex> = f.iter().map(|x| -*x).collect();
        let dz = jac.solve(&rhs);
        let zn: f64 = z.iter().map(|x| x.norm_sqr()).sum();
        let dzn: f64 = dz.iter().map(|x| x.norm_sqr()).sum();
        for (zi, di) in z.iter_mut().zip(&dz) {
            *zi += *di;
        }
        (f, res) = residual(&z);
        if !(dzn.is_finite() && zn.is_finite()) {
            break;
        }
        if dzn <= 1e-28 * zn || res <= 1e-15 * qscale {
            break;
        }
    }
    if res.is_nan() || res > 1e-11 * qscale || z.iter().any(|x| !x.is_finite()) {
        return Err(PhError::NewtonNoConvergence {
            what: "C2 PH quintic spline",
            iterations,
            residual: res,
        });
    }
    let zf = full(&z, start, end);
    let segments = (1..=n)
        .map(|i| PlanarPhQuintic {
            p0: q[i - 1].to_vec(),
            w: [(zf[i - 1] + zf[i]) * 0.5, zf[i], (zf[i] + zf[i + 1]) * 0.5],
        })
        .collect();
    Ok(PlanarPhSpline {
        segments,
        closed,
        iterations,
    })
}

/// A complex (cyclic) tridiagonal matrix: sub-, main and super-diagonal plus the two corner
/// entries M[0][n−1] and M[n−1][0] of a periodic system.
struct Cyclic {
    sub: Vec<Complex>,
    diag: Vec<Complex>,
    sup: Vec<Complex>,
    top_right: Complex,
    bottom_left: Complex,
}

impl Cyclic {
    fn new(n: usize) -> Self {
        Self {
            sub: vec![Complex::ZERO; n],
            diag: vec![Complex::ZERO; n],
            sup: vec![Complex::ZERO; n],
            top_right: Complex::ZERO,
            bottom_left: Complex::ZERO,
        }
    }

    fn add(&mut self, i: usize, j: usize, v: Complex) {
        let n = self.diag.len();
        if i == j {
            self.diag[i] += v;
        } else if j + 1 == i {
            self.sub[i] += v;
        } else if j == i + 1 {
            self.sup[i] += v;
        } else if i == 0 && j == n - 1 {
            self.top_right += v;
        } else if i == n - 1 && j == 0 {
            self.bottom_left += v;
        } else {
            unreachable!("entry ({i}, {j}) outside the cyclic tridiagonal pattern");
        }
    }

    /// Thomas algorithm on (sub, diag, sup) without the corners.
    fn thomas(sub: &[Complex], diag: &[Complex], sup: &[Complex], r: &[Complex]) -> Vec<Complex> {
        let n = diag.len();
        let mut c = vec![Complex::ZERO; n];
        let mut d = vec![Complex::ZERO; n];
        c[0] = sup[0] / diag[0];
        d[0] = r[0] / diag[0];
        for i in 1..n {
            let m = diag[i] - sub[i] * c[i - 1];
            c[i] = sup[i] / m;
            d[i] = (r[i] - sub[i] * d[i - 1]) / m;
        }
        let mut x = vec![Complex::ZERO; n];
        x[n - 1] = d[n - 1];
        for i in (0..n - 1).rev() {
            x[i] = d[i] - c[i] * x[i + 1];
        }
        x
    }

    /// Solve M x = r: Thomas when there are no corner entries, otherwise Sherman–Morrison:
    /// M = T + u vᵀ with u = (γ, 0, …, 0, bottom_left), v = (1, 0, …, 0, top_right/γ), γ = −diag_0.
    fn solve(&self, r: &[Complex]) -> Vec<Complex> {
        let n = self.diag.len();
        if self.top_right == Complex::ZERO && self.bottom_left == Complex::ZERO {
            return Self::thomas(&self.sub, &self.diag, &self.sup, r);
        }
        let gamma = -self.diag[0];
        let mut diag = self.diag.clone();
        diag[0] -= gamma;
        diag[n - 1] -= self.bottom_left * self.top_right / gamma;
        let x = Self::thomas(&self.sub, &diag, &self.sup, r);
        let mut u = vec![Complex::ZERO; n];
        u[0] = gamma;
        u[n - 1] = self.bottom_left;
        let zz = Self::thomas(&self.sub, &diag, &self.sup, &u);
        let fact = (x[0] + self.top_right * x[n - 1] / gamma)
            / (Complex::ONE + zz[0] + self.top_right * zz[n - 1] / gamma);
        x.iter().zip(&zz).map(|(a, b)| *a - fact * *b).collect()
    }
}
