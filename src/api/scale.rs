//! Scale normalisation of the pipeline: the construction, tessellation and checks run on the cage
//! scaled to about a unit box, and the results are mapped back, so that every extent in
//! [`EXTENT_RANGE`] converts the same way (every tolerance of the construction is then relative).
//!
//! The scale is a power of two, so scaling is exact (no rounding) and a cage whose extent is
//! already in [1/16, 16] is not scaled at all (its conversion is bit-identical to the unscaled
//! one). The cage is translated to its bounding-box centre only when that centre is more than 16
//! extents from the origin (the translation rounds; far translations beyond
//! [`crate::limits::MIN_RELATIVE_EXTENT`] are refused earlier by the mesh validation).
//!
//! Mapped back, with p = c + s·q: positions (output mesh, patch control points, curves); mean
//! curvature H/s; Gaussian curvature K/s²; lengths (`max_boundary_gap`) ·s. Unchanged: normals,
//! angles (G1), counts, fold sites (domain parameters), |H|·diagonal, validity.

use crate::construct::{Patch, Surface};
use crate::limits::EXTENT_RANGE;
use crate::mesh::{HalfEdgeMesh, PolyMesh};
use crate::tessellate::SurfaceMesh;
use glam::DVec3;

/// Extents in this range of powers of two are left unscaled.
const KEEP_EXPONENT: i32 = 4;

/// The map q = (p − centre)/scale into the normalised frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Normalisation {
    pub centre: DVec3,
    /// A power of two.
    pub scale: f64,
}

/// Why a cage cannot be normalised: its extent is outside [`EXTENT_RANGE`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct OutOfRange {
    pub extent: f64,
}

impl Normalisation {
    /// The normalisation of a cage with these positions (none needed: identity).
    pub fn of(positions: &[DVec3]) -> Result<Self, OutOfRange> {
        let (lo, hi) = positions
            .iter()
            .fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        if positions.is_empty() {
            return Ok(Normalisation { centre: DVec3::ZERO, scale: 1.0 });
        }
        // Half-differences first: hi − lo may overflow for coordinates near f64::MAX.
        let half = hi * 0.5 - lo * 0.5;
        let extent = 2.0 * half.max_element();
        if !(extent >= EXTENT_RANGE.0 && extent <= EXTENT_RANGE.1) {
            return Err(OutOfRange { extent });
        }
        let exponent = extent.log2().round() as i32;
        let scale = if exponent.abs() <= KEEP_EXPONENT { 1.0 } else { 2f64.powi(exponent) };
        let centre = lo * 0.5 + hi * 0.5;
        let centre = if centre.abs().max_element() > 16.0 * extent { centre } else { DVec3::ZERO };
        Ok(Normalisation { centre, scale })
    }

    /// True if the map is the identity.
    pub fn is_identity(&self) -> bool {
        self.scale == 1.0 && self.centre == DVec3::ZERO
    }

    fn to_unit(&self, p: DVec3) -> DVec3 {
        (p - self.centre) / self.scale
    }

    fn back(&self, q: DVec3) -> DVec3 {
        q * self.scale + self.centre
    }

    /// The half-edge mesh and the polygon mesh in the normalised frame.
    pub fn apply(&self, he: &HalfEdgeMesh, mesh: &PolyMesh) -> (HalfEdgeMesh, PolyMesh) {
        let mut he = he.clone();
        for v in 0..he.n_vertices() {
            let v = crate::mesh::halfedge::VertexId::from(v);
            he.set_position(v, self.to_unit(he.position(v)));
        }
        let mesh = PolyMesh { positions: mesh.positions.iter().map(|&p| self.to_unit(p)).collect(), faces: mesh.faces.clone(), creases: mesh.creases.clone(), holes: mesh.holes.clone() };
        (he, mesh)
    }

    /// Maps an output mesh back (positions, curvatures; normals and angles are unchanged).
    pub fn restore_mesh(&self, m: &mut SurfaceMesh) {
        for p in &mut m.positions {
            *p = self.back(*p);
        }
        let s = self.scale;
        for h in &mut m.mean_curvature {
            *h /= s;
        }
        for k in &mut m.gaussian_curvature {
            *k /= s * s;
        }
    }

    /// Maps a surface back: every control point and curve point.
    pub fn restore_surface(&self, surface: &mut Surface) {
        for p in &mut surface.patches {
            let ribbons = match p {
                Patch::Gb(g) => {
                    g.center = self.back(g.center);
                    &mut g.ribbons
                }
                Patch::Cgb(c) => &mut c.ribbons,
            };
            for q in ribbons.iter_mut().flat_map(|r| r.points_mut()) {
                *q = self.back(*q);
            }
        }
        for q in surface.curves.iter_mut().flatten() {
            *q = self.back(*q);
        }
    }

    /// Maps a length back.
    pub fn restore_length(&self, l: f64) -> f64 {
        l * self.scale
    }
}
