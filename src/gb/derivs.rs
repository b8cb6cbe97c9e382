//! Second-order jets of scalar functions on the (u, v) domain, surface derivatives, and the
//! normal / fundamental forms / curvatures computed from them (seed 001 differential geometry;
//! used by the GB and CGB evaluators and by quality analysis).

use glam::DVec3;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Value and first and second partial derivatives of a scalar f(u, v):
/// (f, f_u, f_v, f_uu, f_uv, f_vv). Arithmetic follows the product and quotient rules exactly.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Jet2 {
    pub val: f64,
    pub du: f64,
    pub dv: f64,
    pub duu: f64,
    pub duv: f64,
    pub dvv: f64,
}

impl Jet2 {
    /// The zero function.
    pub const ZERO: Jet2 = Jet2 {
        val: 0.0,
        du: 0.0,
        dv: 0.0,
        duu: 0.0,
        duv: 0.0,
        dvv: 0.0,
    };

    /// A constant function.
    pub const fn constant(c: f64) -> Self {
        Jet2 {
            val: c,
            du: 0.0,
            dv: 0.0,
            duu: 0.0,
            duv: 0.0,
            dvv: 0.0,
        }
    }

    /// An affine function c + g·(u, v).
    pub const fn affine(c: f64, gu: f64, gv: f64) -> Self {
        Jet2 {
            val: c,
            du: gu,
            dv: gv,
            duu: 0.0,
            duv: 0.0,
            dvv: 0.0,
        }
    }

    /// Multiplies every component by `c`.
    #[inline]
    pub fn scale(self, c: f64) -> Self {
        Jet2 {
            val: self.val * c,
            du: self.du * c,
            dv: self.dv * c,
            duu: self.duu * c,
            duv: self.duv * c,
            dvv: self.dvv * c,
        }
    }

    /// f(t(u, v)) for a univariate f given by its value, first and second derivative at t.
    #[inline]
    pub fn compose(self, f: f64, f1: f64, f2: f64) -> Jet2 {
        Jet2 {
            val: f,
            du: f1 * self.du,
            dv: f1 * self.dv,
            duu: f2 * self.du * self.du + f1 * self.duu,
            duv: f2 * self.du * self.dv + f1 * self.duv,
            dvv: f2 * self.dv * self.dv + f1 * self.dvv,
        }
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.val.is_finite()
            && self.du.is_finite()
            && self.dv.is_finite()
            && self.duu.is_finite()
            && self.duv.is_finite()
            && self.dvv.is_finite()
    }
}

impl Div for Jet2 {
    type Output = Jet2;
    /// Quotient a / b by the quotient rule (caller guarantees b ≠ 0).
    #[inline]
    fn div(self, b: Jet2) -> Jet2 {
        let q = self.val / b.val;
        let qu = (self.du - q * b.du) / b.val;
        let qv = (self.dv - q * b.dv) / b.val;
        Jet2 {
            val: q,
            du: qu,
            dv: qv,
            duu: (self.duu - 2.0 * qu * b.du - q * b.duu) / b.val,
            duv: (self.duv - qu * b.dv - qv * b.du - q * b.duv) / b.val,
            dvv: (self.dvv - 2.0 * qv * b.dv - q * b.dvv) / b.val,
        }
    }

}

impl Add for Jet2 {
    type Output = Jet2;
    #[inline]
    fn add(self, b: Jet2) -> Jet2 {
        Jet2 {
            val: self.val + b.val,
            du: self.du + b.du,
            dv: self.dv + b.dv,
            duu: self.duu + b.duu,
            duv: self.duv + b.duv,
            dvv: self.dvv + b.dvv,
        }
    }
}

impl Sub for Jet2 {
    type Output = Jet2;
    #[inline]
    fn sub(self, b: Jet2) -> Jet2 {
        self + (-b)
    }
}

impl Neg for Jet2 {
    type Output = Jet2;
    #[inline]
    fn neg(self) -> Jet2 {
        self.scale(-1.0)
    }
}

impl Mul for Jet2 {
    type Output = Jet2;
    /// Product rule up to second order.
    #[inline]
    fn mul(self, b: Jet2) -> Jet2 {
        let a = self;
        Jet2 {
            val: a.val * b.val,
            du: a.du * b.val + a.val * b.du,
            dv: a.dv * b.val + a.val * b.dv,
            duu: a.duu * b.val + 2.0 * a.du * b.du + a.val * b.duu,
            duv: a.duv * b.val + a.du * b.dv + a.dv * b.du + a.val * b.duv,
            dvv: a.dvv * b.val + 2.0 * a.dv * b.dv + a.val * b.dvv,
        }
    }
}

/// A surface point S(u, v) with its first and second partial derivatives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceDerivs {
    pub p: DVec3,
    pub su: DVec3,
    pub sv: DVec3,
    pub suu: DVec3,
    pub suv: DVec3,
    pub svv: DVec3,
}

/// Mean and Gaussian curvature with the principal curvatures k1 ≥ k2.
/// Sign convention: with the normal n = S_u × S_v / |S_u × S_v| and L = S_uu·n (etc.),
/// H = (L G − 2 M F + N E) / (2 (E G − F²)), K = (L N − M²) / (E G − F²);
/// a sphere of radius R whose S_u × S_v points outward has H = −1/R and K = 1/R².
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Curvature {
    pub mean: f64,
    pub gaussian: f64,
    pub k1: f64,
    pub k2: f64,
}

/// |S_u × S_v|² below this (relative to |S_u|²|S_v|²) counts as a degenerate parameterization.
const DEGENERATE_REL: f64 = 1e-24;

impl SurfaceDerivs {
    /// Accumulates `w` times the control point `p` (w with its derivatives).
    #[inline]
    pub fn add_weighted(&mut self, w: &Jet2, p: DVec3) {
        self.p += w.val * p;
        self.su += w.du * p;
        self.sv += w.dv * p;
        self.suu += w.duu * p;
        self.suv += w.duv * p;
        self.svv += w.dvv * p;
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        [self.p, self.su, self.sv, self.suu, self.suv, self.svv]
            .iter()
            .all(|v| v.is_finite())
    }

    /// Unit normal S_u × S_v / |S_u × S_v|, or `None` where the parameterization degenerates.
    pub fn normal(&self) -> Option<DVec3> {
        let c = self.su.cross(self.sv);
        let l2 = c.length_squared();
        let scale = self.su.length_squared() * self.sv.length_squared();
        if !(l2 > DEGENERATE_REL * scale) || !l2.is_finite() || l2 == 0.0 {
            return None;
        }
        Some(c / l2.sqrt())
    }

    /// [`SurfaceDerivs::normal`] of `L` samples at once from their S_u and S_v as lanes
    /// (`su[axis][lane]`): lane by lane the same operations in the same order (so the same
    /// bits), zero where `normal` gives `None`. Branch-free so that it vectorizes: the weight
    /// tables' dispatched pass computes 4 normals with one vector square root and divisions.
    #[inline(always)]
    pub fn normal_lanes<const L: usize>(su: [&[f64; L]; 3], sv: [&[f64; L]; 3]) -> [[f64; L]; 3] {
        let mut out = [[0.0; L]; 3];
        for l in 0..L {
            let (ax, ay, az) = (su[0][l], su[1][l], su[2][l]);
            let (bx, by, bz) = (sv[0][l], sv[1][l], sv[2][l]);
            let c = [ay * bz - by * az, az * bx - bz * ax, ax * by - bx * ay];
            let l2 = (c[0] * c[0]) + (c[1] * c[1]) + (c[2] * c[2]);
            let scale = ((ax * ax) + (ay * ay) + (az * az)) * ((bx * bx) + (by * by) + (bz * bz));
            let ok = l2 > DEGENERATE_REL * scale && l2.is_finite() && l2 != 0.0;
            let s = l2.sqrt();
            for (o, c) in out.iter_mut().zip(c) {
                o[l] = if ok { c / s } else { 0.0 };
            }
        }
        out
    }

    /// First fundamental form (E, F, G).
    pub fn first_fundamental_form(&self) -> (f64, f64, f64) {
        (
            self.su.dot(self.su),
            self.su.dot(self.sv),
            self.sv.dot(self.sv),
        )
    }

    /// Second fundamental form (L, M, N) with respect to [`Self::normal`], or `None` where the
    /// normal is undefined.
    pub fn second_fundamental_form(&self) -> Option<(f64, f64, f64)> {
        let n = self.normal()?;
        Some((self.suu.dot(n), self.suv.dot(n), self.svv.dot(n)))
    }

    /// Mean, Gaussian and principal curvatures from the fundamental forms (see [`Curvature`]),
    /// or `None` where the normal is undefined.
    pub fn curvature(&self) -> Option<Curvature> {
        let (mean, gaussian) = self.mean_and_gaussian(self.normal()?)?;
        let disc = (mean * mean - gaussian).max(0.0).sqrt();
        Some(Curvature {
            mean,
            gaussian,
            k1: mean + disc,
            k2: mean - disc,
        })
    }

    /// Mean and Gaussian curvature H = (L G − 2 M F + N E) / (2 (E G − F²)),
    /// K = (L N − M²) / (E G − F²) with the second fundamental form taken along the unit normal
    /// `n` (normally [`Self::normal`], passed in when the caller has it already); `None` where
    /// E G − F² ≤ 0 or a result is not finite. The one curvature formula of the crate.
    #[inline]
    pub fn mean_and_gaussian(&self, n: DVec3) -> Option<(f64, f64)> {
        let (e, f, g) = self.first_fundamental_form();
        let (l, m, nn) = (self.suu.dot(n), self.suv.dot(n), self.svv.dot(n));
        let det = e * g - f * f;
        if !(det > 0.0) {
            return None;
        }
        let mean = (l * g - 2.0 * m * f + nn * e) / (2.0 * det);
        let gaussian = (l * nn - m * m) / det;
        (mean.is_finite() && gaussian.is_finite()).then_some((mean, gaussian))
    }
}

/// Angle in degrees between two vectors (0 when either vanishes), e.g. between two patches'
/// normals. The atan2 of |a × b| and a · b is accurate also for tiny angles.
pub fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    let la = a.length();
    let lb = b.length();
    if la == 0.0 || lb == 0.0 {
        return 0.0;
    }
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}
