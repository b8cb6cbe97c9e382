//! The regular n-gon domain of a GB patch, Wachspress coordinates and the local side/distance
//! parameters (s_i, h_i), all with exact first and second derivatives in (u, v)
//! (seed 000 §2.5–2.6, eq. 2.12–2.21; seed 002 "Domén és paraméterezés").
//!
//! Conventions (docs/math.md#domain): vertex i at (cos 2πi/n, sin 2πi/n); side i runs from vertex i−1 to
//! vertex i; for n = 4 the square (1,1), (−1,1), (−1,−1), (1,−1) in this order.

use super::derivs::Jet2;
use super::error::GbError;
use glam::DVec2;

/// Local parameters of side i at a domain point: side parameter s_i (0 at vertex i−1, 1 at
/// vertex i along side i) and distance parameter h_i (0 on side i, 1 on the far sides),
/// each with derivatives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LocalParam {
    pub s: Jet2,
    pub h: Jet2,
}

/// Below this the denominator of s_i (in the scaled area units of [`Domain`], 1 at the centre)
/// counts as zero: this happens only for n = 3 at the vertex opposite side i, where h_i = 1 and
/// s_i does not matter.
const S_DEN_EPS: f64 = 1e-13;

/// A regular n-sided domain polygon (n ≥ 3).
#[derive(Clone, Debug, PartialEq)]
pub struct Domain {
    n: usize,
    vertices: Vec<DVec2>,
    /// c_i = A(v_{i−1}, v_i, v_{i+1}) / A(v_{n−1}, v_0, v_1), the corner triangle areas relative
    /// to corner 0's (all 1 for a regular polygon).
    corner_area: Vec<f64>,
    /// Gradient of the scaled D_i(x) = A(x, v_{i−1}, v_i) / D_c (constant; D_i is affine in x).
    side_grad: Vec<DVec2>,
    /// 1 / D_c, D_c = A(0, v_{n−1}, v_0) the side areas at the centre. Scaling every D_j by 1/D_c
    /// leaves λ and s unchanged but keeps the (n−2)-fold products of the Wachspress numerators
    /// in range: the scaled D_j average exactly 1 (Σ D_j = area of the polygon), so each product
    /// is at most (n/(n−2))^{n−2} < e², where the unscaled ones underflow to 0/0 for n ≳ 180.
    area_scale: f64,
}

/// Signed area of the triangle (a, b, c), positive when counter-clockwise (seed 000 eq. 2.13).
#[inline]
pub fn signed_area(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    0.5 * (b - a).perp_dot(c - a)
}

impl Domain {
    /// The regular n-gon of the GB patch (see the module conventions).
    pub fn regular(n: usize) -> Result<Domain, GbError> {
        if n < 3 {
            return Err(GbError::TooFewSides(n));
        }
        let vertices: Vec<DVec2> = if n == 4 {
            vec![
                DVec2::new(1.0, 1.0),
                DVec2::new(-1.0, 1.0),
                DVec2::new(-1.0, -1.0),
                DVec2::new(1.0, -1.0),
            ]
        } else {
            (0..n)
                .map(|i| {
                    let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                    DVec2::new(a.cos(), a.sin())
                })
                .collect()
        };
        let prev = |i: usize| (i + n - 1) % n;
        let next = |i: usize| (i + 1) % n;
        let c0 = signed_area(vertices[n - 1], vertices[0], vertices[1]);
        let corner_area = (0..n)
            .map(|i| signed_area(vertices[prev(i)], vertices[i], vertices[next(i)]) / c0)
            .collect();
        let area_scale = 1.0 / signed_area(DVec2::ZERO, vertices[n - 1], vertices[0]);
        // D_i(x) = ½ (v_{i−1} − x) × (v_i − x) = ½ [v_{i−1} × v_i + (v_i − v_{i−1}) × x]
        let side_grad = (0..n)
            .map(|i| {
                let e = vertices[i] - vertices[prev(i)];
                DVec2::new(-0.5 * e.y, 0.5 * e.x) * area_scale
            })
            .collect();
        Ok(Domain {
            n,
            vertices,
            corner_area,
            side_grad,
            area_scale,
        })
    }

    /// Number of sides.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The vertices v_0 … v_{n−1}.
    pub fn vertices(&self) -> &[DVec2] {
        &self.vertices
    }

    /// Vertex i (index taken modulo n).
    pub fn vertex(&self, i: usize) -> DVec2 {
        self.vertices[i % self.n]
    }

    /// The domain centre (the origin).
    pub fn center(&self) -> DVec2 {
        DVec2::ZERO
    }

    /// The point (1−t) v_{i−1} + t v_i of side i.
    pub fn side_point(&self, i: usize, t: f64) -> DVec2 {
        let i = i % self.n;
        let a = self.vertices[(i + self.n - 1) % self.n];
        let b = self.vertices[i];
        a + (b - a) * t
    }

    /// True when `uv` is inside the closed polygon up to `tol` (in area units of D_i).
    pub fn contains(&self, uv: DVec2, tol: f64) -> bool {
        (0..self.n).all(|i| self.side_area(i, uv) >= -tol)
    }

    /// D_i(x) = A(x, v_{i−1}, v_i): vanishes on side i, positive inside.
    #[inline]
    fn side_area(&self, i: usize, uv: DVec2) -> f64 {
        let a = self.vertices[(i + self.n - 1) % self.n];
        let b = self.vertices[i];
        0.5 * (a - uv).perp_dot(b - uv)
    }

    #[inline]
    fn side_jet(&self, i: usize, uv: DVec2) -> Jet2 {
        let g = self.side_grad[i];
        Jet2::affine(self.side_area(i, uv) * self.area_scale, g.x, g.y)
    }

    /// Scratch buffers for [`Self::wachspress_into`] and [`Self::local_params_into`] (3n jets
    /// and n exponents; allocate once per evaluator).
    pub fn scratch(&self) -> DomainScratch {
        DomainScratch {
            areas: vec![Jet2::ZERO; self.n],
            lambda: vec![Jet2::ZERO; self.n],
            suffix: vec![Jet2::ZERO; self.n + 1],
            suffix_exp: vec![0; self.n + 1],
        }
    }

    /// Wachspress coordinates λ_0 … λ_{n−1} with derivatives, in the product form
    /// λ_i ∝ w_i = A(v_{i−1}, v_i, v_{i+1}) · Π_{j∉{i,i+1}} D_j(x), normalized (seed 000 eq. 2.12;
    /// the product form has no division and is exact on the boundary), in O(n) per point
    /// (docs/math.md#wachspress-linear): with the prefix products P_k = Π_{j<k} D_j
    /// and the suffix products S_k = Π_{j≥k} D_j, the product over all sides but the two
    /// consecutive ones i, i+1 is P_i · S_{i+2} for i ≤ n−2, and Π_{j=1}^{n−2} D_j (one direct
    /// product) for i = n−1. No division, so a zero D_j at the boundary stays an exact zero; the
    /// values differ from the sequential product only by rounding (≤ a few n ulps, tested against
    /// it). Partial products of n/2 factors reach e^{±0.24 n} (they overflow for n ≳ 3000), so
    /// P and S carry a binary exponent and are rescaled by exact powers of two; the w_i (which
    /// underflow near the boundary of a large polygon) are scaled by their common largest
    /// exponent before normalizing.
    /// `areas` receives the jets of D_j / D_c (see the field `area_scale`), `out` (length n) the λ_i.
    pub fn wachspress_into(&self, uv: DVec2, scratch: &mut DomainScratch, out: &mut [Jet2]) {
        let n = self.n;
        let DomainScratch { areas, suffix, suffix_exp, .. } = scratch;
        for (j, a) in areas.iter_mut().enumerate().take(n) {
            *a = self.side_jet(j, uv);
        }
        // suffix[k] · 2^suffix_exp[k] = S_k = Π_{j≥k} D_j, k = 0..=n.
        suffix[n] = Jet2::constant(1.0);
        suffix_exp[n] = 0;
        for k in (0..n).rev() {
            let (j, e) = renormalize(areas[k] * suffix[k + 1]);
            suffix[k] = j;
            suffix_exp[k] = suffix_exp[k + 1] + e;
        }
        // w_i = out[i] · 2^suffix_exp[i] (step i reads suffix_exp[i+2] only, so the exponent
        // of w_i can take slot i). The w_i themselves may underflow (at a boundary point of a
        // large polygon Π_j D_j ≈ 2^−n), so they are normalized by their common largest
        // exponent before summing: λ is unchanged, and never 0/0.
        // prefix · 2^prefix_exp = P_i = Π_{j<i} D_j
        let (mut prefix, mut prefix_exp) = (Jet2::constant(1.0), 0i32);
        for i in 0..n - 1 {
            let (w, e) = normalize(Jet2::constant(self.corner_area[i]) * prefix * suffix[i + 2]);
            out[i] = w;
            suffix_exp[i] = e.saturating_add(prefix_exp + suffix_exp[i + 2]);
            let (j, e) = renormalize(prefix * areas[i]);
            prefix = j;
            prefix_exp += e;
        }
        // i = n−1: all sides but n−1 and 0.
        let (mut w, mut e) = (Jet2::constant(self.corner_area[n - 1]), 0i32);
        for a in &areas[1..n - 1] {
            let (j, de) = renormalize(w * *a);
            w = j;
            e += de;
        }
        let (w, de) = normalize(w);
        out[n - 1] = w;
        suffix_exp[n - 1] = de.saturating_add(e);
        let top = suffix_exp[..n].iter().copied().max().unwrap_or(0);
        let mut sum = Jet2::ZERO;
        for (l, &e) in out.iter_mut().zip(suffix_exp.iter()).take(n) {
            *l = scale_pow2(*l, e.saturating_sub(top).max(-2100));
            sum = sum + *l;
        }
        for l in out.iter_mut().take(n) {
            *l = *l / sum;
        }
    }

    /// Wachspress coordinates with derivatives (allocating convenience form).
    pub fn wachspress(&self, uv: DVec2) -> Vec<Jet2> {
        let mut scratch = self.scratch();
        let mut out = vec![Jet2::ZERO; self.n];
        self.wachspress_into(uv, &mut scratch, &mut out);
        out
    }

    /// Local parameters of every side (seed 000 eq. 2.19–2.21):
    /// h_i = 1 − λ_{i−1} − λ_i, computed as Σ_{j∉{i−1,i}} λ_j (exactly 0 on side i), in O(1) per
    /// side from prefix and suffix sums (Σ_{j<i−1} λ_j + Σ_{j>i} λ_j; for i = 0 one direct sum
    /// of λ_1 … λ_{n−2}): every term is ≥ 0 and on side i every term is exactly 0, so the sum is
    /// exactly 0 there in any order;
    /// s_i = λ_i/(λ_{i−1}+λ_i), computed in the cancelled form
    /// s_i = c_i D_{i−1} / (c_{i−1} D_{i+1} + c_i D_{i−1}) (c = corner areas), which is the same
    /// function and is also the limit form of eq. 2.21 on the far sides, finite on the whole closed
    /// domain. Only for n = 3 at the vertex opposite side i (where h_i = 1) is it 0/0: there s_i = ½
    /// with zero derivatives. `scratch` from [`Self::scratch`], `out` of length n.
    pub fn local_params_into(&self, uv: DVec2, scratch: &mut DomainScratch, out: &mut [LocalParam]) {
        let n = self.n;
        let mut lambda = std::mem::take(&mut scratch.lambda);
        self.wachspress_into(uv, scratch, &mut lambda);
        let DomainScratch { areas, suffix, .. } = scratch;
        // suffix[k] = Σ_{j≥k} λ_j, k = 0..=n
        suffix[n] = Jet2::ZERO;
        for k in (0..n).rev() {
            suffix[k] = lambda[k] + suffix[k + 1];
        }
        // prefix = Σ_{j<i−1} λ_j
        let mut prefix = Jet2::ZERO;
        for i in 0..n {
            let im = (i + n - 1) % n;
            let ip = (i + 1) % n;
            let h = if i == 0 {
                lambda[1..n - 1].iter().fold(Jet2::ZERO, |a, &l| a + l)
            } else {
                if i >= 2 {
                    prefix = prefix + lambda[i - 2];
                }
                prefix + suffix[i + 1]
            };
            let num = areas[im].scale(self.corner_area[i]);
            let den = num + areas[ip].scale(self.corner_area[im]);
            let s = if den.val.abs() < S_DEN_EPS {
                Jet2::constant(0.5)
            } else {
                num / den
            };
            out[i] = LocalParam { s, h };
        }
        scratch.lambda = lambda;
    }

    /// Local parameters of every side (allocating convenience form).
    pub fn local_params(&self, uv: DVec2) -> Vec<LocalParam> {
        let mut scratch = self.scratch();
        let mut out = vec![LocalParam::default(); self.n];
        self.local_params_into(uv, &mut scratch, &mut out);
        out
    }
}

/// Reusable buffers of [`Domain::wachspress_into`] and [`Domain::local_params_into`].
#[derive(Clone, Debug, Default)]
pub struct DomainScratch {
    /// D_j / D_c with derivatives, j = 0..n (filled by `wachspress_into`).
    pub areas: Vec<Jet2>,
    lambda: Vec<Jet2>,
    suffix: Vec<Jet2>,
    suffix_exp: Vec<i32>,
}

/// Partial products are kept with every component's magnitude below 2^RESCALE_ABOVE and the
/// largest above 2^−RESCALE_ABOVE (or all zero), far from overflow and from subnormals.
const RESCALE_ABOVE: i32 = 256;

/// `j` as (j · 2^−e, e) with the largest component of the first in [2^−256, 2^256] (unchanged,
/// e = 0, when it already is or when j is zero). Exact: only powers of two.
#[inline]
fn renormalize(j: Jet2) -> (Jet2, i32) {
    let m = j.val.abs().max(j.du.abs()).max(j.dv.abs()).max(j.duu.abs()).max(j.duv.abs()).max(j.dvv.abs());
    if m == 0.0 || !m.is_finite() {
        return (j, 0);
    }
    let e = ((m.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    if e.abs() <= RESCALE_ABOVE {
        return (j, 0);
    }
    (scale_pow2(j, -e), e)
}

/// `j` as (j · 2^−e, e) with its largest component in [1, 2) (e = i32::MIN for a zero jet, so
/// that it never sets the common exponent). Exact.
#[inline]
fn normalize(j: Jet2) -> (Jet2, i32) {
    let m = j.val.abs().max(j.du.abs()).max(j.dv.abs()).max(j.duu.abs()).max(j.duv.abs()).max(j.dvv.abs());
    if m == 0.0 || !m.is_finite() {
        return (j, if m == 0.0 { i32::MIN } else { 0 });
    }
    let e = ((m.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    (scale_pow2(j, -e), e)
}

/// j · 2^e, exact (two steps when |e| exceeds one exponent's range).
#[inline]
fn scale_pow2(j: Jet2, e: i32) -> Jet2 {
    if e == 0 {
        return j;
    }
    let pow2 = |e: i32| f64::from_bits(((1023 + e.clamp(-1022, 1023)) as u64) << 52);
    let half = e / 2;
    j.scale(pow2(half)).scale(pow2(e - half))
}
