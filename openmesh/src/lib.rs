//! Bridge to OpenMesh (needs Debian's `libopenmesh-dev` and a C++17
//! compiler): mesh file I/O in every format OpenMesh knows (OBJ, OFF, PLY, STL, OM) with double
//! positions, and OpenMesh's own uniform Catmull–Clark subdivider as a reference for
//! [`gbsurf::subdiv::catmull_clark`].
//!
//! The C++ side is `openmesh/cpp/openmesh_bridge.cpp` (a `PolyMesh_ArrayKernelT` with `Vec3d`
//! points). Meshes cross the bridge as flat arrays; every C++ failure is a thrown
//! `std::runtime_error` that cxx turns into an `Err`, never an abort.
//!
//! Precision: OpenMesh 9.0 (Debian bookworm) passes OBJ, OFF, PLY and STL coordinates through
//! `f32` even for a `Vec3d` mesh (text written with 17 digits included), so a round trip through
//! those formats rounds every coordinate to single precision; only OM keeps the doubles exactly.
//! Use the crate's own readers when full precision matters.
//!
//! OpenMesh's Catmull–Clark (`Tools/Subdivider/Uniform/CatmullClarkT_impl.hh`, OpenMesh 9.0)
//! equals the textbook rule on closed meshes: face points = centroids, interior edge points
//! `(a + b + F₀ + F₁)/4`, interior vertices `Σ neighbours/n² + Σ F/n² + (n−2)/n·V`
//! (= `(Q + 2R + (n−3)V)/n`). On boundaries it differs from [`gbsurf::subdiv::catmull_clark`]:
//! boundary edge points are midpoints in both, but every boundary vertex, corners included, gets
//! `(V + m₁ + m₂)/3` with `m₁, m₂` the midpoints of its two boundary edges, i.e. the mask
//! `(1, 4, 1)/6` (the cubic B-spline *limit* mask) instead of the subdivision mask `(1, 6, 1)/8`,
//! and corners are not kept fixed. (An isolated vertex counts as a boundary vertex there and
//! moves to V/3.)

use gbsurf::mesh::{HalfEdgeMesh, MeshError, PolyMesh, TriMesh};
use glam::DVec3;
use std::path::{Path, PathBuf};

#[cxx::bridge(namespace = "gbsurf_om")]
mod bridge {
    /// A mesh as flat arrays: xyz triples, optional per-vertex normals (same length as
    /// `positions` or empty), face sizes and the concatenated face index loops.
    struct MeshData {
        positions: Vec<f64>,
        normals: Vec<f64>,
        face_sizes: Vec<u32>,
        face_indices: Vec<u32>,
    }

    unsafe extern "C++" {
        include!("gbsurf-openmesh/cpp/openmesh_bridge.h");
        fn read_mesh(path: &str) -> Result<MeshData>;
        fn write_mesh(mesh: &MeshData, path: &str, binary: bool, precision: u32) -> Result<()>;
        fn catmull_clark(mesh: &MeshData, levels: u32) -> Result<MeshData>;
    }
}

/// Why an OpenMesh call failed.
#[derive(Debug, thiserror::Error)]
pub enum OpenMeshError {
    #[error("path {0:?} is not valid UTF-8")]
    NonUtf8Path(PathBuf),
    #[error("STL holds triangles only, but face {face} has {len} vertices")]
    NotTriangles { face: usize, len: usize },
    #[error("invalid mesh: {0}")]
    InvalidMesh(#[from] MeshError),
    #[error("the result would have {count} vertices, more than OpenMesh's int handles allow")]
    TooLarge { count: u64 },
    #[error("OpenMesh returned malformed data: {0}")]
    Malformed(String),
    #[error("OpenMesh: {0}")]
    OpenMesh(String),
}

impl From<cxx::Exception> for OpenMeshError {
    fn from(e: cxx::Exception) -> Self {
        OpenMeshError::OpenMesh(e.what().to_string())
    }
}

fn path_str(path: &Path) -> Result<&str, OpenMeshError> {
    path.to_str()
        .ok_or_else(|| OpenMeshError::NonUtf8Path(path.to_path_buf()))
}

fn to_data(mesh: &PolyMesh, normals: &[DVec3]) -> MeshData {
    MeshData {
        positions: mesh.positions.iter().flat_map(|p| p.to_array()).collect(),
        normals: normals.iter().flat_map(|n| n.to_array()).collect(),
        face_sizes: mesh.faces.iter().map(|f| f.len() as u32).collect(),
        face_indices: mesh.faces.iter().flatten().copied().collect(),
    }
}

use bridge::MeshData;

fn from_data(data: MeshData) -> Result<PolyMesh, OpenMeshError> {
    if data.positions.len() % 3 != 0 {
        return Err(OpenMeshError::Malformed("positions not in triples".into()));
    }
    let positions = data
        .positions
        .chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect();
    let mut faces = Vec::with_capacity(data.face_sizes.len());
    let mut offset = 0usize;
    for &k in &data.face_sizes {
        let end = offset + k as usize;
        let Some(face) = data.face_indices.get(offset..end) else {
            return Err(OpenMeshError::Malformed("face indices too short".into()));
        };
        faces.push(face.to_vec());
        offset = end;
    }
    Ok(PolyMesh::new(positions, faces))
}

fn is_stl(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("stl"))
}

fn check_stl(mesh: &PolyMesh, path: &Path) -> Result<(), OpenMeshError> {
    if is_stl(path) {
        if let Some((face, f)) = mesh.faces.iter().enumerate().find(|(_, f)| f.len() != 3) {
            return Err(OpenMeshError::NotTriangles { face, len: f.len() });
        }
    }
    Ok(())
}

/// Reads a mesh with OpenMesh; the format follows the extension (obj, off, ply, stl, om).
/// Vertices keep the file's order (STL: OpenMesh merges equal corners, in order of first use);
/// faces keep the file's vertex loops. Coordinates are single precision except for OM.
pub fn read_mesh(path: impl AsRef<Path>) -> Result<PolyMesh, OpenMeshError> {
    from_data(bridge::read_mesh(path_str(path.as_ref())?)?)
}

/// Writes `mesh` with OpenMesh in the format named by the extension; text formats (OBJ, OFF,
/// PLY, STL) as ASCII with 17 significant digits (of the f32-rounded values, see the module
/// docs), OM in its (only) binary form with doubles.
/// STL needs a triangle mesh ([`OpenMeshError::NotTriangles`] otherwise).
pub fn write_mesh(mesh: &PolyMesh, path: impl AsRef<Path>) -> Result<(), OpenMeshError> {
    write(mesh, &[], path.as_ref(), false)
}

/// Like [`write_mesh`] but binary where the format has a binary form (PLY, STL, OFF, OM).
pub fn write_mesh_binary(mesh: &PolyMesh, path: impl AsRef<Path>) -> Result<(), OpenMeshError> {
    write(mesh, &[], path.as_ref(), true)
}

/// Writes a triangle mesh with its vertex normals (when the format stores them).
pub fn write_tri_mesh(mesh: &TriMesh, path: impl AsRef<Path>) -> Result<(), OpenMeshError> {
    let poly = PolyMesh::new(
        mesh.positions.clone(),
        mesh.triangles.iter().map(|t| t.to_vec()).collect(),
    );
    let normals = if mesh.normals.len() == mesh.positions.len() {
        &mesh.normals[..]
    } else {
        &[]
    };
    write(&poly, normals, path.as_ref(), false)
}

fn write(
    mesh: &PolyMesh,
    normals: &[DVec3],
    path: &Path,
    binary: bool,
) -> Result<(), OpenMeshError> {
    check_stl(mesh, path)?;
    Ok(bridge::write_mesh(
        &to_data(mesh, normals),
        path_str(path)?,
        binary,
        17,
    )?)
}

/// OpenMesh's uniform Catmull–Clark subdivider (`CatmullClarkT`), `levels` times: the reference
/// for [`gbsurf::subdiv::catmull_clark`] (equal on closed meshes; boundary rules differ, see the
/// module docs). The mesh is validated first with the same validator as [`gbsurf::subdiv`]
/// ([`HalfEdgeMesh::from_polymesh`]).
/// Output order: old vertices, then edge points, then face points (OpenMesh's own order).
pub fn openmesh_catmull_clark(mesh: &PolyMesh, levels: u32) -> Result<PolyMesh, OpenMeshError> {
    // Counts per level (S = Σ|f|): V' = V + E + F, E' = 2E + S, F' = S, S' = 4S.
    let mut v = mesh.positions.len() as u64;
    let mut e = HalfEdgeMesh::from_polymesh(mesh)?.n_edges() as u64;
    let mut f = mesh.faces.len() as u64;
    let mut s = mesh.faces.iter().map(|f| f.len() as u64).sum::<u64>();
    for _ in 0..levels {
        (v, e, f, s) = (v + e + f, 2 * e + s, s, 4 * s);
        if v > i32::MAX as u64 || s > i32::MAX as u64 {
            return Err(OpenMeshError::TooLarge { count: v });
        }
    }
    from_data(bridge::catmull_clark(&to_data(mesh, &[]), levels)?)
}
