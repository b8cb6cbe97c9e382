//! The sampling layout of the n-sided domain at resolution r and its triangulation: the domain
//! points at which patches are evaluated (directly, through weight tables or CGB) and how the
//! samples form triangles. It lives below the evaluators and knows nothing of meshes.
//!
//! Layout: ring m = 0..r is the domain polygon scaled by m/r about the centre (ring 0 is the
//! centre point). Ring m ≥ 1 has m samples per side, n·m in all, uniform along each side; on the
//! boundary ring (m = r) sample t of side i lies at parameter s_i = t/r (side i runs from domain
//! vertex i−1 to vertex i, so Wachspress s_i is linear along it). Sector i (centre, v_{i−1},
//! v_i) is thus the regular r-subdivision of a triangle: r² triangles per side, n·r² in all,
//! 1 + n·r(r+1)/2 samples. All triangles are counter-clockwise in the domain.
//!
//! Quad layout ([`Layout::Quads`], docs/math.md#quad-layout): the domain is split at its centre c
//! into n sectors, sector i being the quad (c, m_i, v_i, m_{i+1}) with m_i the midpoint of side i;
//! each sector is sampled bilinearly on an r × r grid: n·r² quads, r samples per half side, 2r
//! steps per side, 1 + n·r(r+1) samples. Sample order: the centre, the spokes c → m_i (steps
//! 1..r−1 each), the sector interiors, then the boundary loop (side 0 steps 0..2r−1, side 1, …)
//! as in the triangle layout, so the welding code ([`SampleLayout::boundary_index`] with
//! [`SampleLayout::per_side`] steps) serves both. Every quad is counter-clockwise; `triangles`
//! holds each quad split along its diagonal (a, c) into two triangles (quad k → triangles 2k,
//! 2k+1), for the validity checks and measures that work on triangles.

use super::Domain;
use glam::DVec2;

/// Errors building a sampling layout.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LayoutError {
    /// Fewer than 3 domain vertices.
    #[error("a domain polygon needs at least 3 vertices, got {n}")]
    TooFewSides { n: usize },
    /// Resolution 0.
    #[error("tessellation resolution must be at least 1, got {r}")]
    ZeroResolution { r: usize },
    /// So many samples or triangles that u32 indices would overflow.
    #[error("resolution {r} with {n} sides needs more than 2^32 samples or triangles")]
    TooLarge { n: usize, r: usize },
    /// A domain vertex that is not finite.
    #[error("domain vertex {index} is not finite")]
    NonFiniteVertex { index: usize },
    /// A domain polygon that is not strictly convex and counter-clockwise around its centroid.
    #[error("domain polygon is not strictly convex and counter-clockwise at vertex {index}")]
    NotConvex { index: usize },
}

/// How an n-sided domain is sampled and cut into faces: the triangle layout (concentric rings)
/// or the quad layout (n bilinear sectors), see the module doc.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Layout {
    /// Concentric rings, n·r² triangles per patch, r steps per side.
    Triangles,
    /// n sectors of r × r quads per patch (like Catmull–Clark level L at r = 2^(L−1)), 2r steps
    /// per side.
    #[default]
    Quads,
}

/// A layout and its resolution r. A bare `usize` converts to the triangle layout at that
/// resolution (the layout every older call site means).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Sampling {
    /// The layout.
    pub layout: Layout,
    /// Resolution r: samples per side (triangles) or per half side (quads).
    pub resolution: usize,
}

impl From<usize> for Sampling {
    fn from(resolution: usize) -> Self {
        Sampling { layout: Layout::Triangles, resolution }
    }
}

impl Sampling {
    /// The sampling of `layout` at resolution `resolution`.
    pub fn new(layout: Layout, resolution: usize) -> Self {
        Sampling { layout, resolution }
    }

    /// Boundary steps per side: r (triangles) or 2r (quads).
    pub fn per_side(self) -> usize {
        match self.layout {
            Layout::Triangles => self.resolution,
            Layout::Quads => 2 * self.resolution,
        }
    }

    /// Samples of an n-sided patch: 1 + n·r(r+1)/2 (triangles) or 1 + n·r(r+1) (quads);
    /// saturating.
    pub fn sample_count(self, n: usize) -> usize {
        let r = self.resolution;
        let x = n.saturating_mul(r).saturating_mul(r.saturating_add(1));
        match self.layout {
            Layout::Triangles => 1 + x / 2,
            Layout::Quads => x.saturating_add(1),
        }
    }

    /// Output faces of an n-sided patch: n·r² triangles or n·r² quads; saturating.
    pub fn face_count(self, n: usize) -> usize {
        n.saturating_mul(self.resolution).saturating_mul(self.resolution)
    }

    /// Triangles of an n-sided patch (a quad counts as two); saturating.
    pub fn triangle_count(self, n: usize) -> usize {
        match self.layout {
            Layout::Triangles => self.face_count(n),
            Layout::Quads => self.face_count(n).saturating_mul(2),
        }
    }
}

/// The bilinear map of the quad `q` = (c, m, v, m') at (s, t): (1−s)(1−t)·c + s(1−t)·m + st·v +
/// (1−s)t·m' ((0,0) ↦ c, (1,0) ↦ m, (1,1) ↦ v, (0,1) ↦ m'); the quad layout's sector map.
pub fn bilinear(q: [DVec2; 4], s: f64, t: f64) -> DVec2 {
    let [c, m0, v, m1] = q;
    c * ((1.0 - s) * (1.0 - t)) + m0 * (s * (1.0 - t)) + v * (s * t) + m1 * ((1.0 - s) * t)
}

/// The inverse of [`bilinear`] on a convex quad: the (s, t) ∈ [0,1]² with `bilinear(q, s, t)` =
/// `p` for a point p of the quad (clamped to [0,1]² for one outside it, by rounding or not;
/// docs/math.md#cage-corners). With e = m − c, f = m' − c, g = c − m + v − m', x = p − c and
/// a × b = a.x·b.y − a.y·b.x, x = s·e + t·f + st·g gives (x − s·e) × (f + s·g) = 0, i.e.
/// (e × g)·s² + (e × f − x × g)·s + f × x = 0 (linear for a parallelogram, e × g = 0); of its
/// roots the one nearest to [0,1], then t = (x − s·e)·(f + s·g) / |f + s·g|².
pub fn bilinear_inverse(q: [DVec2; 4], p: DVec2) -> DVec2 {
    let [c, m0, v, m1] = q;
    let (e, f, g, x) = (m0 - c, m1 - c, c - m0 + v - m1, p - c);
    let (a, b, k) = (e.perp_dot(g), e.perp_dot(f) - x.perp_dot(g), f.perp_dot(x));
    // Roots by the cancellation-free pair w / a and k / w, w = −(b + sign(b)·√disc)/2.
    let disc = (b * b - 4.0 * a * k).max(0.0);
    let w = -0.5 * (b + disc.sqrt().copysign(b));
    let roots = [if a != 0.0 { w / a } else { f64::NAN }, if w != 0.0 { k / w } else { f64::NAN }];
    let off = |s: f64| if s.is_finite() { (s.clamp(0.0, 1.0) - s).abs() } else { f64::INFINITY };
    let s = if off(roots[1]) <= off(roots[0]) { roots[1] } else { roots[0] };
    let s = if s.is_finite() { s.clamp(0.0, 1.0) } else { 0.0 };
    let d = f + g * s;
    let len2 = d.length_squared();
    let t = if len2 > 0.0 { (x - e * s).dot(d) / len2 } else { 0.0 };
    DVec2::new(s, if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 })
}

/// Where a sample of the triangle layout lies in the quad layout's sectors (sector i the quad
/// (c, m_i, v_i, m_{i+1}), [`SampleLayout::quad_sector`]): in the closed sectors `first`,
/// `first + 1`, …, `first + count − 1` (mod n), at bilinear coordinates `st[j]` in sector
/// `first + j` ([`bilinear_inverse`]). One sector inside one; two on a spoke c → m_i (sectors
/// i − 1 and i); all n, at (0, 0), for the centre (then `st` holds two copies).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectorPoint {
    pub first: u32,
    pub count: u32,
    pub st: [DVec2; 2],
}

impl SectorPoint {
    /// The sample's coordinates in sector `i` (0..n of an `n`-sided domain), `None` when the
    /// sample does not lie in it.
    pub fn in_sector(&self, i: u32, n: u32) -> Option<DVec2> {
        let j = (i + n - self.first % n) % n;
        (j < self.count).then(|| self.st[(j as usize).min(1)])
    }
}

/// The samples of an n-sided domain at resolution r and their CCW triangulation (see the
/// module doc). Sample 0 is the centre; ring m ≥ 1 starts at index 1 + n·m(m−1)/2 and lists
/// side 0 (t = 0..m−1), side 1, …; step t = m of side i is step 0 of side i+1.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleLayout {
    /// Number of sides n.
    pub sides: usize,
    /// Resolution r: samples per side on the boundary (per half side in the quad layout).
    pub resolution: usize,
    /// The layout.
    pub layout: Layout,
    /// Domain position of every sample.
    pub uv: Vec<DVec2>,
    /// Counter-clockwise triangles of sample indices (in the quad layout: quad k split into
    /// triangles 2k and 2k+1).
    pub triangles: Vec<[u32; 3]>,
    /// Counter-clockwise quads of sample indices (quad layout only; empty for triangles), sector
    /// by sector: the quads of sector i (around domain vertex i) are `i·r²..(i+1)·r²`.
    pub quads: Vec<[u32; 4]>,
}

impl SampleLayout {
    /// Number of samples 1 + n·r(r+1)/2.
    pub fn sample_count(n: usize, r: usize) -> usize {
        1 + n * r * (r + 1) / 2
    }

    /// Number of triangles n·r².
    pub fn triangle_count(n: usize, r: usize) -> usize {
        n * r * r
    }

    /// The vertices of the GB domain polygon ([`Domain::regular`]: vertex i at
    /// (cos 2πi/n, sin 2πi/n), for n = 4 the square (1,1), (−1,1), (−1,−1), (1,−1)); empty for
    /// n < 3.
    pub fn regular_polygon(n: usize) -> Vec<DVec2> {
        Domain::regular(n)
            .map(|d| d.vertices().to_vec())
            .unwrap_or_default()
    }

    /// The layout on the GB domain of n sides ([`SampleLayout::regular_polygon`]); its centre
    /// sample is exactly the domain centre, the origin.
    pub fn regular(n: usize, resolution: usize) -> Result<Self, LayoutError> {
        match Domain::regular(n) {
            Ok(d) => Self::for_domain(&d, resolution),
            Err(_) => Err(LayoutError::TooFewSides { n }),
        }
    }

    /// The layout on a GB domain, centred at its centre.
    pub fn for_domain(domain: &Domain, sampling: impl Into<Sampling>) -> Result<Self, LayoutError> {
        Self::build(domain.vertices(), Some(domain.center()), sampling.into())
    }

    /// The layout on a strictly convex CCW domain polygon (vertex i ends side i), scaled about
    /// its vertex centroid.
    pub fn new(vertices: &[DVec2], sampling: impl Into<Sampling>) -> Result<Self, LayoutError> {
        Self::build(vertices, None, sampling.into())
    }

    /// Boundary steps per side: r (triangles) or 2r (quads).
    pub fn per_side(&self) -> usize {
        self.sampling().per_side()
    }

    /// The layout and resolution.
    pub fn sampling(&self) -> Sampling {
        Sampling { layout: self.layout, resolution: self.resolution }
    }

    /// Index of the first boundary sample (side 0, step 0); the samples before it are interior.
    pub fn first_boundary(&self) -> usize {
        self.uv.len() - self.sides * self.per_side()
    }

    /// The domain corner (0..n; corner i is domain vertex i, the end of side i) of every output
    /// face: the sector of each quad; in the triangle layout, the quad sector (c, m_i, v_i,
    /// m_{i+1}) holding the triangle's centroid: of the 2m − 1 triangles of ring m in the side
    /// sector (centre, v_{i−1}, v_i), the first m − 1 lie on v_{i−1}'s side of the spoke c → m_i
    /// (corner i − 1) and the last m − 1 on v_i's (corner i); the middle one, symmetric about the
    /// spoke, takes corner i (by the integers: no rounding decides it).
    pub fn face_corners(&self) -> Vec<u32> {
        let r2 = self.resolution * self.resolution;
        let n = self.sides;
        match self.layout {
            Layout::Quads => (0..self.quads.len()).map(|k| (k / r2.max(1)) as u32).collect(),
            Layout::Triangles => {
                let mut out = Vec::with_capacity(self.triangles.len());
                for m in 1..=self.resolution {
                    for i in 0..n {
                        let before = ((i + n - 1) % n) as u32;
                        out.extend((0..2 * m - 1).map(|j| if j + 1 < m { before } else { i as u32 }));
                    }
                }
                out
            }
        }
    }

    /// Domain vertex i (mod n, the end of side i) of the layout's polygon.
    pub fn vertex(&self, i: usize) -> DVec2 {
        self.uv[self.boundary_index(i + 1, 0)]
    }

    /// Sector i (mod n) of the quad layout on this layout's domain, in either layout: the quad
    /// (c, m_i, v_i, m_{i+1}) of the centre (sample 0), the midpoint of side i, domain vertex i
    /// and the midpoint of side i+1, for [`bilinear`].
    pub fn quad_sector(&self, i: usize) -> [DVec2; 4] {
        let n = self.sides;
        let mid = |j: usize| (self.vertex(j + n - 1) + self.vertex(j)) * 0.5;
        [self.uv[0], mid(i), self.vertex(i), mid(i + 1)]
    }

    /// Triangle layout (empty for the quad layout, whose samples are its sectors' grid points):
    /// per sample, the quad sectors it lies in and its coordinates there
    /// (docs/math.md#cage-corners). Sample t of side i on ring m (0 ≤ t < m, between the scaled
    /// v_{i−1} and v_i) lies in sector i − 1 for 2t < m, in sector i for 2t > m and on the spoke
    /// c → m_i for 2t = m, at (0, m/r) in sector i − 1 and (m/r, 0) in sector i. On the boundary
    /// ring (m = r) the coordinates are exact too: (1 − 2t/r, 1) in sector i − 1 and
    /// (1, 2t/r − 1) in sector i; elsewhere [`bilinear_inverse`].
    pub fn sector_points(&self) -> Vec<SectorPoint> {
        if self.layout != Layout::Triangles {
            return Vec::new();
        }
        let (n, r) = (self.sides, self.resolution);
        let mut out = Vec::with_capacity(self.uv.len());
        out.push(SectorPoint { first: 0, count: n as u32, st: [DVec2::ZERO; 2] });
        let sectors: Vec<[DVec2; 4]> = (0..n).map(|i| self.quad_sector(i)).collect();
        for m in 1..=r {
            for i in 0..n {
                let before = (i + n - 1) % n;
                for t in 0..m {
                    let p = self.uv[self.ring_index(m, i, t)];
                    let (mf, rf) = (m as f64, r as f64);
                    let point = if 2 * t == m {
                        let l = mf / rf;
                        SectorPoint { first: before as u32, count: 2, st: [DVec2::new(0.0, l), DVec2::new(l, 0.0)] }
                    } else {
                        let sector = if 2 * t < m { before } else { i };
                        let st = if m < r {
                            bilinear_inverse(sectors[sector], p)
                        } else if 2 * t < m {
                            DVec2::new((rf - 2.0 * t as f64) / rf, 1.0)
                        } else {
                            DVec2::new(1.0, (2.0 * t as f64 - rf) / rf)
                        };
                        SectorPoint { first: sector as u32, count: 1, st: [st; 2] }
                    };
                    out.push(point);
                }
            }
        }
        out
    }

    fn build(
        vertices: &[DVec2],
        centre: Option<DVec2>,
        sampling: Sampling,
    ) -> Result<Self, LayoutError> {
        let n = vertices.len();
        let r = sampling.resolution;
        if n < 3 {
            return Err(LayoutError::TooFewSides { n });
        }
        if r == 0 {
            return Err(LayoutError::ZeroResolution { r });
        }
        let too_large = || LayoutError::TooLarge { n, r };
        let tris = n
            .checked_mul(r)
            .and_then(|x| x.checked_mul(r))
            .and_then(|x| x.checked_mul(if sampling.layout == Layout::Quads { 2 } else { 1 }))
            .ok_or_else(too_large)?;
        let samples = n
            .checked_mul(r)
            .and_then(|x| x.checked_mul(r + 1))
            .map(|x| if sampling.layout == Layout::Quads { x + 1 } else { 1 + x / 2 })
            .ok_or_else(too_large)?;
        if tris > u32::MAX as usize || samples > u32::MAX as usize {
            return Err(too_large());
        }
        if let Some(index) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(LayoutError::NonFiniteVertex { index });
        }
        let centre = centre.unwrap_or_else(|| vertices.iter().copied().sum::<DVec2>() / n as f64);
        for i in 0..n {
            let (a, b, c) = (
                vertices[(i + n - 1) % n],
                vertices[i],
                vertices[(i + 1) % n],
            );
            let turn = (b - a).perp_dot(c - b);
            let around = (a - centre).perp_dot(b - centre);
            if !(turn > 0.0 && around > 0.0) {
                return Err(LayoutError::NotConvex { index: i });
            }
        }
        if sampling.layout == Layout::Quads {
            return Ok(Self::quads(vertices, centre, r, samples));
        }

        let mut uv = Vec::with_capacity(samples);
        uv.push(centre);
        for m in 1..=r {
            let scale = m as f64 / r as f64;
            for i in 0..n {
                let a = vertices[(i + n - 1) % n];
                let b = vertices[i];
                for t in 0..m {
                    let s = t as f64 / m as f64;
                    let p = if t == 0 { a } else { a + (b - a) * s };
                    uv.push(if m == r {
                        p
                    } else {
                        centre + (p - centre) * scale
                    });
                }
            }
        }
        let mut layout = SampleLayout {
            sides: n,
            resolution: r,
            layout: Layout::Triangles,
            uv,
            triangles: Vec::new(),
            quads: Vec::new(),
        };
        let mut triangles = Vec::with_capacity(tris);
        for m in 1..=r {
            for i in 0..n {
                for t in 0..m {
                    let outer0 = layout.ring_index(m, i, t) as u32;
                    let outer1 = layout.ring_index(m, i, t + 1) as u32;
                    let inner0 = layout.ring_index(m - 1, i, t) as u32;
                    triangles.push([outer0, outer1, inner0]);
                    if t + 1 < m {
                        let inner1 = layout.ring_index(m - 1, i, t + 1) as u32;
                        triangles.push([inner0, outer1, inner1]);
                    }
                }
            }
        }
        layout.triangles = triangles;
        Ok(layout)
    }

    /// The quad layout (module doc) on a checked polygon.
    fn quads(vertices: &[DVec2], centre: DVec2, r: usize, samples: usize) -> Self {
        let n = vertices.len();
        let vert = |i: usize| vertices[i % n];
        // Side i runs from vertex i−1 to vertex i; m_i is its midpoint.
        let mid = |i: usize| (vert(i + n - 1) + vert(i)) * 0.5;
        let rf = r as f64;
        let mut uv = Vec::with_capacity(samples);
        uv.push(centre);
        for i in 0..n {
            let m = mid(i);
            for k in 1..r {
                uv.push(centre + (m - centre) * (k as f64 / rf));
            }
        }
        for i in 0..n {
            let (m0, v, m1) = (mid(i), vert(i), mid(i + 1));
            for a in 1..r {
                for b in 1..r {
                    uv.push(bilinear([centre, m0, v, m1], a as f64 / rf, b as f64 / rf));
                }
            }
        }
        for i in 0..n {
            let (a, b) = (vert(i + n - 1), vert(i));
            for t in 0..2 * r {
                uv.push(if t == 0 { a } else { a + (b - a) * (t as f64 / (2 * r) as f64) });
            }
        }
        debug_assert_eq!(uv.len(), samples);
        let mut layout = SampleLayout {
            sides: n,
            resolution: r,
            layout: Layout::Quads,
            uv,
            triangles: Vec::new(),
            quads: Vec::with_capacity(n * r * r),
        };
        for i in 0..n {
            for a in 0..r {
                for b in 0..r {
                    let q = [
                        layout.sector_index(i, a, b),
                        layout.sector_index(i, a + 1, b),
                        layout.sector_index(i, a + 1, b + 1),
                        layout.sector_index(i, a, b + 1),
                    ]
                    .map(|x| x as u32);
                    layout.quads.push(q);
                }
            }
        }
        layout.triangles = layout.quads.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
        layout
    }

    /// Quad layout: index of grid point (a, b), 0 ≤ a, b ≤ r, of sector i (bilinear in the quad
    /// (c, m_i, v_i, m_{i+1}): (0,0) the centre, (r,0) the midpoint of side i, (r,r) vertex i,
    /// (0,r) the midpoint of side i+1), sectors taken mod n.
    pub fn sector_index(&self, sector: usize, a: usize, b: usize) -> usize {
        let (n, r) = (self.sides, self.resolution);
        let i = sector % n;
        let spoke = |j: usize, k: usize| 1 + (j % n) * (r - 1) + (k - 1);
        if a == r {
            // Second half of side i: steps r..2r.
            return self.boundary_index(i, r + b);
        }
        if b == r {
            // First half of side i+1, from its step r (a = 0) back to step 0 (a = r).
            return self.boundary_index(i + 1, r - a);
        }
        match (a, b) {
            (0, 0) => 0,
            (a, 0) => spoke(i, a),
            (0, b) => spoke(i + 1, b),
            (a, b) => 1 + n * (r - 1) + i * (r - 1) * (r - 1) + (a - 1) * (r - 1) + (b - 1),
        }
    }

    /// The samples sector `sector` (mod n) owns, in an order that is the same for every sector:
    /// the j-th sample of sector m is the j-th of sector 0 turned by 2πm/n about the centre (on
    /// the regular domain, where the layout is n-fold symmetric). The centre belongs to no
    /// sector; the n lists and the centre are a partition of the samples.
    /// - triangles: sector i = the samples (ring m, side i, step t), m = 1..=r, t = 0..=m−1 (the
    ///   spoke to domain vertex i − 1 included, the one to vertex i not): r(r+1)/2 samples;
    /// - quads: sector i = the grid points (a, b) of [`SampleLayout::sector_index`] with
    ///   a = 1..=r, b = 0..=r (the spoke to m_i included, the one to m_{i+1} not): r(r+1).
    pub fn sector_samples(&self, sector: usize) -> Vec<u32> {
        let r = self.resolution;
        match self.layout {
            Layout::Triangles => (1..=r)
                .flat_map(|m| (0..m).map(move |t| (m, t)))
                .map(|(m, t)| self.ring_index(m, sector, t) as u32)
                .collect(),
            Layout::Quads => (1..=r)
                .flat_map(|a| (0..=r).map(move |b| (a, b)))
                .map(|(a, b)| self.sector_index(sector, a, b) as u32)
                .collect(),
        }
    }

    /// Index of sample (ring m, side i, step t), 0 ≤ t ≤ m, sides taken mod n; step m of side
    /// i is step 0 of side i+1. Ring 0 is the centre (index 0) whatever i and t.
    pub fn ring_index(&self, m: usize, side: usize, t: usize) -> usize {
        if m == 0 {
            return 0;
        }
        let n = self.sides;
        1 + n * m * (m - 1) / 2 + ((side % n) * m + t) % (n * m)
    }

    /// Index of boundary sample (side i, step t), t = 0..=k with k = [`SampleLayout::per_side`]
    /// (r for triangles, 2r for quads): at parameter s_i = t/k of side i. Step k of side i is
    /// step 0 of side i+1. A neighbour across side i traverses it in the opposite direction: its
    /// step k − t is this patch's step t.
    pub fn boundary_index(&self, side: usize, t: usize) -> usize {
        let (n, k) = (self.sides, self.per_side());
        self.first_boundary() + ((side % n) * k + t) % (n * k)
    }

    /// The boundary loop, counter-clockwise: side 0 steps 0..k−1, side 1, …; n·k samples.
    pub fn boundary_loop(&self) -> Vec<u32> {
        (self.first_boundary()..self.uv.len()).map(|x| x as u32).collect()
    }

    /// True for samples on the boundary ring.
    pub fn is_boundary(&self, sample: usize) -> bool {
        sample >= self.first_boundary() && sample < self.uv.len()
    }
}
