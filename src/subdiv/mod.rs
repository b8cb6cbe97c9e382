//! Doo–Sabin and Catmull–Clark subdivision, the comparison methods of seed 000 §6.4
//! (described in seed 000 §1.2.1.1–1.2.1.2).
//!
//! Both schemes take any face sizes (triangles, quads, n-gons, mixed) and open meshes; the
//! boundary rules are documented on [`catmull_clark`] and [`doo_sabin`]. Input is validated
//! (see [`SubdivError`]); nothing panics on bad input.
//!
//! Note on seed 000 eq. 1.1 (`v' = 1/n² Σf + 2/n² Σe + (n−3)/n v`): it is the textbook
//! Catmull–Clark vertex rule only when `e` are the edge *midpoints*. With the new edge points
//! (which the seed's text suggests) the cube corner would move to ±4/9 instead of ±5/9; we use
//! midpoints, as Catmull and Clark (1978) and OpenMesh do.

mod catmull_clark;
mod doo_sabin;
mod topology;

pub use catmull_clark::catmull_clark;
pub use doo_sabin::{doo_sabin, doo_sabin_weights};

use crate::mesh::PolyMesh;

/// The subdivision schemes available for comparison with GB surfaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SubdivisionScheme {
    /// Catmull–Clark (primal, quads after one level; seed 000 §1.2.1.2).
    CatmullClark,
    /// Doo–Sabin (dual, corner cutting; seed 000 §1.2.1.1).
    DooSabin,
}

/// Why a mesh cannot be subdivided. Every variant names the offending element.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SubdivError {
    #[error("face {face} has {len} vertices; at least 3 are needed")]
    FaceTooSmall { face: usize, len: usize },
    #[error("face {face} refers to vertex {vertex}, but the mesh has only {count} vertices")]
    IndexOutOfRange {
        face: usize,
        vertex: u32,
        count: usize,
    },
    #[error("face {face} lists vertex {vertex} more than once")]
    RepeatedVertex { face: usize, vertex: u32 },
    #[error("vertex {vertex} has a non-finite position")]
    NonFinitePosition { vertex: usize },
    #[error(
        "edge {a}->{b} runs the same way in faces {first} and {second} \
         (edge with more than two faces, or inconsistent orientation)"
    )]
    DuplicateDirectedEdge {
        a: u32,
        b: u32,
        first: usize,
        second: usize,
    },
    #[error("vertex {vertex} is non-manifold: its faces do not form a single fan")]
    NonManifoldVertex { vertex: usize },
    #[error(
        "vertex {vertex} is an interior vertex of valence 2; Doo–Sabin would make a two-sided face"
    )]
    InteriorValenceTwo { vertex: usize },
    #[error("the subdivided mesh would need {count} indices, more than u32 can address")]
    TooLarge { count: u64 },
}

/// Subdivides `mesh` `levels` times with `scheme`. `levels == 0` validates and returns a copy.
pub fn subdivide(
    mesh: &PolyMesh,
    scheme: SubdivisionScheme,
    levels: u32,
) -> Result<PolyMesh, SubdivError> {
    match scheme {
        SubdivisionScheme::CatmullClark => catmull_clark(mesh, levels),
        SubdivisionScheme::DooSabin => doo_sabin(mesh, levels),
    }
}

/// Checks that `mesh` can be subdivided (the rules listed on [`SubdivError`]).
pub fn validate(mesh: &PolyMesh) -> Result<(), SubdivError> {
    topology::Topology::new(mesh).map(|_| ())
}

/// Number of undirected edges, after the checks of [`validate`].
pub fn edge_count(mesh: &PolyMesh) -> Result<usize, SubdivError> {
    topology::Topology::new(mesh).map(|t| t.edges.len())
}

/// Errors with [`SubdivError::TooLarge`] when `count` does not fit a u32 index.
fn check_size(count: u64) -> Result<(), SubdivError> {
    if count >= u32::MAX as u64 {
        Err(SubdivError::TooLarge { count })
    } else {
        Ok(())
    }
}
