//! The result of surface construction: patches plus how their sides meet. This is the contract
//! between construction (networks, ribbons, twists) and tessellation/quality.

use crate::bezier::BezierCurve;
use crate::gb::decompose::{common_degree, CommonDegreeError};
use crate::gb::{CgbPatch, GbPatch, Ribbon};
use glam::DVec3;

/// One patch of a constructed surface.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum Patch {
    /// A Generalized Bézier patch (dual structure: one per mesh vertex).
    Gb(GbPatch),
    /// A ribbon-only patch (topology-preserving structure: one per mesh face).
    Cgb(CgbPatch),
}

impl Patch {
    /// The ribbons of the patch, one per side (side i runs from domain vertex i−1 to vertex i).
    pub fn ribbons(&self) -> &[Ribbon] {
        match self {
            Patch::Gb(g) => &g.ribbons,
            Patch::Cgb(c) => &c.ribbons,
        }
    }

    /// The number of sides n.
    pub fn sides(&self) -> usize {
        self.ribbons().len()
    }
}

/// Where a patch side continues: the neighbouring patch and its side. Both sides share one
/// boundary curve, traversed in opposite directions: side `i` of patch A at parameter s is side
/// `side` of patch `patch` at 1 − s.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct SideRef {
    pub patch: usize,
    pub side: usize,
}

/// What element of the control mesh a patch stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", content = "index", rename_all = "lowercase")]
pub enum PatchSource {
    /// A mesh vertex (dual structure).
    Vertex(usize),
    /// A mesh face (topology-preserving structure).
    Face(usize),
}

/// How the bilinear coordinates (s, t) of a quad-layout sector (`SampleLayout::sector_index`:
/// (0,0) the patch centre, (1,0) the midpoint of side i, (1,1) corner i, (0,1) the midpoint of
/// side i+1) map to the coordinates (σ, τ) of its cage corner: (0,0) the cage vertex, (1,0) the
/// midpoint of the edge to the face's next vertex, (0,1) the midpoint of the edge from its
/// previous vertex, (1,1) the face centre (docs/math.md#cage-corners).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SectorMap {
    /// Topology structure: patch = face, corner i = vertex i: (σ, τ) = (1 − s, 1 − t).
    Face,
    /// Dual structure: patch = vertex, corner i = a face around it: (σ, τ) = (s, t).
    Vertex,
    /// Dual boundary patch, the sector between the open side and the first boundary edge: it
    /// is flattened onto that edge's half at the vertex: (σ, τ) = (t, 0).
    OpenStart,
    /// Dual boundary patch, the sector between the last boundary edge and the open side:
    /// (σ, τ) = (0, s).
    OpenEnd,
    /// Dual crease sector (docs/math.md#dual-creases): the cage coordinates of the sector's four
    /// points (centre, midpoint of side i, corner i, midpoint of side i+1) in units of 1/65535,
    /// bilinear in between.
    Corners([[u16; 2]; 4]),
}

impl SectorMap {
    /// The cage-corner coordinates (σ, τ) of sector point (s, t).
    pub fn cage_coords(self, s: f64, t: f64) -> [f64; 2] {
        match self {
            SectorMap::Face => [1.0 - s, 1.0 - t],
            SectorMap::Vertex => [s, t],
            SectorMap::OpenStart => [t, 0.0],
            SectorMap::OpenEnd => [0.0, s],
            SectorMap::Corners(q) => {
                let v = |k: usize, i: usize| q[k][i] as f64 / CORNERS_UNIT;
                let at = |i: usize| (1.0 - s) * (1.0 - t) * v(0, i) + s * (1.0 - t) * v(1, i) + s * t * v(2, i) + (1.0 - s) * t * v(3, i);
                [at(0), at(1)]
            }
        }
    }

    /// The rule across split diagonals (docs/math.md#cage-corners): when the face's edge to its
    /// next vertex or from its previous vertex is a diagonal of a split face (concave or with
    /// holes; not an edge of the input face), the diagonal's midpoint maps to the face centre
    /// (1,1) instead of (1,0) or (0,1), so both sides of the diagonal map it to the same cage
    /// points (σ = τ in the same cage corner): the map is composed with [`Diagonals::phi`]. For
    /// [`SectorMap::Face`] and [`SectorMap::Vertex`] (affine) the result is bilinear, a
    /// [`SectorMap::Corners`] with exact 0/1 entries. The open maps lie on a boundary edge (never
    /// a diagonal); dual crease sectors apply φ to their points where they are built
    /// (`dual_crease::sector_cage`), so they are returned unchanged.
    pub fn across_diagonals(self, diagonals: Diagonals) -> SectorMap {
        if !diagonals.any() || !matches!(self, SectorMap::Face | SectorMap::Vertex) {
            return self;
        }
        let at = |s: f64, t: f64| diagonals.phi(self.cage_coords(s, t));
        SectorMap::corners(at(0.0, 0.0), at(1.0, 0.0), at(1.0, 1.0), at(0.0, 1.0))
    }

    /// [`SectorMap::Corners`] from the cage coordinates of the sector's centre, its two side
    /// midpoints and its corner (each clamped to [0, 1]).
    pub fn corners(centre: [f64; 2], mid_i: [f64; 2], corner: [f64; 2], mid_next: [f64; 2]) -> SectorMap {
        let q = |p: [f64; 2]| p.map(|x| (x.clamp(0.0, 1.0) * CORNERS_UNIT).round() as u16);
        SectorMap::Corners([q(centre), q(mid_i), q(corner), q(mid_next)])
    }
}

/// Which edges of a cage corner (a corner of a face of the prepared mesh) are diagonals of a split
/// face (concave or with holes, docs/math.md#cage-corners): `next` the edge to the face's next
/// vertex ((σ, τ) = (1,0) is its midpoint), `prev` the edge from its previous vertex ((0,1)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Diagonals {
    pub next: bool,
    pub prev: bool,
}

impl Diagonals {
    /// Some edge is a diagonal (φ is not the identity).
    pub fn any(self) -> bool {
        self.next || self.prev
    }

    /// The rule across split diagonals (docs/math.md#cage-corners): the bilinear φ of the cage
    /// square fixing (0,0) and (1,1), with φ(1,0) = a = (1,1) when `next` (else (1,0)) and
    /// φ(0,1) = b = (1,1) when `prev` (else (0,1)): φ(σ, τ) = σ(1−τ)·a + (1−σ)τ·b + στ·(1,1). The
    /// identity when neither edge is a diagonal; maps the unit square into itself.
    pub fn phi(self, [x, y]: [f64; 2]) -> [f64; 2] {
        let (a, b) = ([1.0, if self.next { 1.0 } else { 0.0 }], [if self.prev { 1.0 } else { 0.0 }, 1.0]);
        [0, 1].map(|i| x * (1.0 - y) * a[i] + (1.0 - x) * y * b[i] + x * y)
    }
}

/// The unit of [`SectorMap::Corners`]: coordinates are stored as multiples of 1/65535.
const CORNERS_UNIT: f64 = u16::MAX as f64;

/// The cage corner (face, corner) a patch corner's sector lies in, in the numbering of the mesh
/// the surface was built from, as the user wrote it: `corner` is the position of the vertex in
/// the face's vertex list, for a face with holes in "outer loop, then the holes' loops in order"
/// ([`crate::mesh::HalfEdgeMesh::input_corner`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct CageSector {
    pub face: u32,
    pub corner: u32,
    pub map: SectorMap,
}

/// A patchwork surface: patches, side adjacency and the curve network it interpolates.
///
/// Orientation: each patch's sides run counter-clockwise seen from outside, so the patch normal
/// (∂S/∂u × ∂S/∂v in the domain convention of [`crate::gb`]) points outward for a closed input.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Surface {
    pub patches: Vec<Patch>,
    /// `neighbors[p][i]`: the side across side i of patch p; `None` on an open boundary.
    pub neighbors: Vec<Vec<Option<SideRef>>>,
    /// `sources[p]`: the control-mesh element patch p was built for, in the user's numbering
    /// (filled by [`super::build_topology`] and [`super::build_dual`]): a face as written (the
    /// pieces of a split concave face or face with holes share it), a vertex of the mesh.
    pub sources: Vec<PatchSource>,
    /// The curve network: every boundary curve once, as cubic (or degree-d) Bézier control points.
    pub curves: Vec<Vec<DVec3>>,
    /// What the construction changed in the input (e.g. dissolved interior valence-2 vertices,
    /// see [`super::prepare`]), human-readable.
    #[serde(default)]
    pub warnings: Vec<String>,
    /// `creases[p][i]`: sharpness in [0, 1] of the shared side i of patch p (docs/math.md#creases;
    /// 0 on open sides); empty when the surface has no creases. Sides with sharpness above 0 are
    /// not G1 and are counted apart from the G1 measurement. Not serialized when empty, so a
    /// smooth surface serializes as before creases existed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub creases: Vec<Vec<f64>>,
    /// `cage[p][i]`: the cage corner the sector of corner i of patch p lies in (see
    /// [`CageSector`], filled by [`super::build_topology`] and [`super::build_dual`]); empty for
    /// hand-built surfaces. Not serialized (derived from the control mesh, like `sources`'
    /// numbering; a deserialized surface has none): the serialized surfaces stay as they were.
    #[serde(skip)]
    pub cage: Vec<Vec<CageSector>>,
}

impl Surface {
    /// Patches alone, without adjacency, sources, curves or cage maps: for checks that look at
    /// each patch by itself (the fold tests of a subset of a surface's patches).
    pub fn of_patches(patches: Vec<Patch>) -> Surface {
        Surface {
            patches,
            neighbors: Vec::new(),
            sources: Vec::new(),
            curves: Vec::new(),
            warnings: Vec::new(),
            creases: Vec::new(),
            cage: Vec::new(),
        }
    }

    /// Sharpness of side `side` of patch `p` (0 when the surface has no creases).
    pub fn side_crease(&self, p: usize, side: usize) -> f64 {
        self.creases.get(p).and_then(|c| c.get(side)).copied().unwrap_or(0.0)
    }

    /// Every shared side once: `(patch, side, neighbour)` with `(patch, side) < (neighbour.patch,
    /// neighbour.side)`, in patch order then side order. Open boundary sides are skipped.
    pub fn shared_sides(&self) -> impl Iterator<Item = (usize, usize, SideRef)> + '_ {
        self.neighbors.iter().enumerate().flat_map(|(p, sides)| {
            sides.iter().enumerate().filter_map(move |(i, nb)| match nb {
                Some(nb) if (nb.patch, nb.side) > (p, i) => Some((p, i, *nb)),
                _ => None,
            })
        })
    }

    /// The surface with every patch elevated to the common degree `degree` (docs/math/editing.md,
    /// "common degree"; seed 002): boundary curves and cross-derivatives are kept exactly, so every
    /// G1 join stays G1; the curve network is elevated with them. Only GB patches can be elevated
    /// ([`CommonDegreeError::NotGb`] names the first ribbon-only patch); a patch above `degree`
    /// is an error too (reduction is not exact).
    pub fn with_common_degree(&self, degree: usize) -> Result<Surface, CommonDegreeError> {
        let gb: Vec<GbPatch> = self
            .patches
            .iter()
            .enumerate()
            .map(|(patch, p)| match p {
                Patch::Gb(g) => Ok(g.clone()),
                Patch::Cgb(_) => Err(CommonDegreeError::NotGb { patch }),
            })
            .collect::<Result<_, _>>()?;
        let patches = common_degree(&gb, degree)?.into_iter().map(Patch::Gb).collect();
        let curves = self
            .curves
            .iter()
            .map(|c| match BezierCurve::new(c.clone()) {
                Ok(curve) if curve.degree() < degree => curve.elevate_by(degree - curve.degree()).into_points(),
                _ => c.clone(),
            })
            .collect();
        Ok(Surface { patches, curves, ..self.clone() })
    }

    /// The shared sides across from patch `p`: `(side, neighbour)` for every side of `p` that has
    /// a neighbour with `(p, side) < (neighbour.patch, neighbour.side)` (each shared side is then
    /// visited once when this is called for every patch).
    pub fn shared_sides_of(&self, p: usize) -> impl Iterator<Item = (usize, SideRef)> + '_ {
        self.neighbors.get(p).into_iter().flat_map(move |sides| {
            sides.iter().enumerate().filter_map(move |(i, nb)| match nb {
                Some(nb) if (nb.patch, nb.side) > (p, i) => Some((i, *nb)),
                _ => None,
            })
        })
    }
}
