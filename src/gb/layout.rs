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

/// The samples of an n-sided domain at resolution r and their CCW triangulation (see the
/// module doc). Sample 0 is the centre; ring m ≥ 1 starts at index 1 + n·m(m−1)/2 and lists
/// side 0 (t = 0..m−1), side 1, …; step t = m of side i is step 0 of side i+1.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleLayout {
    /// Number of sides n.
    pub sides: usize,
    /// Resolution r: samples per side on the boundary.
    pub resolution: usize,
    /// Domain position of every sample.
    pub uv: Vec<DVec2>,
    /// Counter-clockwise triangles of sample indices.
    pub triangles: Vec<[u32; 3]>,
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
    pub fn for_domain(domain: &Domain, resolution: usize) -> Result<Self, LayoutError> {
        Self::build(domain.vertices(), Some(domain.center()), resolution)
    }

    /// The layout on a strictly convex CCW domain polygon (vertex i ends side i), scaled about
    /// its vertex centroid.
    pub fn new(vertices: &[DVec2], resolution: usize) -> Result<Self, LayoutError> {
        Self::build(vertices, None, resolution)
    }

    fn build(
        vertices: &[DVec2],
        centre: Option<DVec2>,
        resolution: usize,
    ) -> Result<Self, LayoutError> {
        let n = vertices.len();
        let r = resolution;
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
            .ok_or_else(too_large)?;
        let samples = n
            .checked_mul(r)
            .and_then(|x| x.checked_mul(r + 1))
            .map(|x| 1 + x / 2)
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
            uv,
            triangles: Vec::new(),
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

    /// Index of sample (ring m, side i, step t), 0 ≤ t ≤ m, sides taken mod n; step m of side
    /// i is step 0 of side i+1. Ring 0 is the centre (index 0) whatever i and t.
    pub fn ring_index(&self, m: usize, side: usize, t: usize) -> usize {
        if m == 0 {
            return 0;
        }
        let n = self.sides;
        1 + n * m * (m - 1) / 2 + ((side % n) * m + t) % (n * m)
    }

    /// Index of boundary sample (side i, step t), t = 0..=r: at parameter s_i = t/r of side i.
    /// Step r of side i is step 0 of side i+1. A neighbour across side i traverses it in the
    /// opposite direction: its step r − t is this patch's step t.
    pub fn boundary_index(&self, side: usize, t: usize) -> usize {
        self.ring_index(self.resolution, side, t)
    }

    /// The boundary loop, counter-clockwise: side 0 steps 0..r−1, side 1, …; n·r samples.
    pub fn boundary_loop(&self) -> Vec<u32> {
        let first = self.ring_index(self.resolution, 0, 0);
        (first..self.uv.len()).map(|x| x as u32).collect()
    }

    /// True for samples on the boundary ring.
    pub fn is_boundary(&self, sample: usize) -> bool {
        sample >= self.ring_index(self.resolution, 0, 0) && sample < self.uv.len()
    }
}
