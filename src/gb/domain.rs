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

    /// Length of scratch buffers needed by [`Self::local_params_into`]: 2n.
    pub fn scratch_len(&self) -> usize {
        2 * self.n
    }

    /// Wachspress coordinates λ_0 … λ_{n−1} with derivatives, in the product form
    /// λ_i ∝ A(v_{i−1}, v_i, v_{i+1}) · Π_{j∉{i,i+1}} D_j(x), normalized (seed 000 eq. 2.12;
    /// the product form has no division and is exact on the boundary).
    /// `areas` (length n) receives the jets of D_j / D_c (see the field `area_scale`); `out` has
    /// length n.
    pub fn wachspress_into(&self, uv: DVec2, areas: &mut [Jet2], out: &mut [Jet2]) {
        let n = self.n;
        for (j, a) in areas.iter_mut().enumerate().take(n) {
            *a = self.side_jet(j, uv);
        }
        let mut sum = Jet2::ZERO;
        for i in 0..n {
            let mut w = Jet2::constant(self.corner_area[i]);
            // sides i+2, …, i+n−1 (mod n): all but sides i and i+1, the two at vertex i
            for m in 2..n {
                w = w * areas[(i + m) % n];
            }
            out[i] = w;
            sum = sum + w;
        }
        for l in out.iter_mut().take(n) {
            *l = *l / sum;
        }
    }

    /// Wachspress coordinates with derivatives (allocating convenience form).
    pub fn wachspress(&self, uv: DVec2) -> Vec<Jet2> {
        let mut areas = vec![Jet2::ZERO; self.n];
        let mut out = vec![Jet2::ZERO; self.n];
        self.wachspress_into(uv, &mut areas, &mut out);
        out
    }

    /// Local parameters of every side (seed 000 eq. 2.19–2.21):
    /// h_i = 1 − λ_{i−1} − λ_i, computed as Σ_{j∉{i−1,i}} λ_j (exactly 0 on side i);
    /// s_i = λ_i/(λ_{i−1}+λ_i), computed in the cancelled form
    /// s_i = c_i D_{i−1} / (c_{i−1} D_{i+1} + c_i D_{i−1}) (c = corner areas), which is the same
    /// function and is also the limit form of eq. 2.21 on the far sides, finite on the whole closed
    /// domain. Only for n = 3 at the vertex opposite side i (where h_i = 1) is it 0/0: there s_i = ½
    /// with zero derivatives. `scratch` must have length ≥ 2n, `out` length n.
    pub fn local_params_into(&self, uv: DVec2, scratch: &mut [Jet2], out: &mut [LocalParam]) {
        let n = self.n;
        let (areas, lambda) = scratch.split_at_mut(n);
        self.wachspress_into(uv, areas, lambda);
        for i in 0..n {
            let im = (i + n - 1) % n;
            let ip = (i + 1) % n;
            let mut h = Jet2::ZERO;
            for m in 1..n - 1 {
                h = h + lambda[(i + m) % n];
            }
            let num = areas[im].scale(self.corner_area[i]);
            let den = num + areas[ip].scale(self.corner_area[im]);
            let s = if den.val.abs() < S_DEN_EPS {
                Jet2::constant(0.5)
            } else {
                num / den
            };
            out[i] = LocalParam { s, h };
        }
    }

    /// Local parameters of every side (allocating convenience form).
    pub fn local_params(&self, uv: DVec2) -> Vec<LocalParam> {
        let mut scratch = vec![Jet2::ZERO; 2 * self.n];
        let mut out = vec![LocalParam::default(); self.n];
        self.local_params_into(uv, &mut scratch, &mut out);
        out
    }
}
