//! Every file the crate writes, in one place: meshes as OBJ, PLY and STL ([`MeshFormat`], chosen
//! by extension in [`MeshFormat::of`], the one dispatcher), the exact surface as JSON and `.gbp`
//! ([`patches_json`], [`gbp_texts`], [`patch_files`]), the curve network and control nets as OBJ
//! ([`curves_obj`], [`nets_obj`]), isophotes and slices ([`write_isophotes_ply`], [`slices_obj`]), and
//! the one atomic writer ([`AtomicFiles`], [`write_atomic`]) and the check of a set of output
//! paths before anything is written ([`check_output_paths`]).
//!
//! The writers of [`PolyMesh`], [`TriMesh`] and [`SurfaceMesh`] are methods of those types
//! (`write_obj`, `write_ply`, `write_stl`, `write_file`), defined here.

mod atomic;
mod encode;
mod mesh;
mod obj;
mod paths;
mod ply;
mod stl;
mod surface;

pub use atomic::{write_atomic, AtomicFiles};
pub use mesh::{encode_mesh, WriteMesh};
pub use obj::{curves_obj, nets_obj, slices_obj};
pub use paths::{check_output_paths, FlagPath, OutputPathError, OutputPathProblem};
pub use ply::{write_isophotes_ply, write_ply, PlyFormat, ScalarType, VertexScalar};
pub use stl::{write_stl_triangles, Float32RangeError};
pub use surface::{gbp_texts, patch_files, patches_json};

use crate::mesh::{PolyMesh, TriMesh};
use crate::tessellate::SurfaceMesh;
use std::path::{Path, PathBuf};

/// Why writing failed; names the file.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The extension of `path` names no mesh format this module writes.
    #[error("{}: the output extension must be {}", path.display(), MeshFormat::EXTENSIONS_TEXT)]
    UnknownFormat { path: PathBuf },
    /// An output path is refused before anything is written (the same file as an input or
    /// another output, or not writable as a new regular file).
    #[error("{0}")]
    OutputPath(#[from] OutputPathError),
    /// Creating, writing or renaming the file failed.
    #[error("i/o error on {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl ExportError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        ExportError::Io { path: path.to_path_buf(), source }
    }
}

/// The mesh file formats, by extension (case-insensitive).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront OBJ (`.obj`), coordinates as the shortest text that parses back to the same `f64`.
    Obj,
    /// Binary little-endian PLY (`.ply`) with the mesh's per-vertex data.
    Ply,
    /// Binary STL (`.stl`).
    Stl,
}

impl MeshFormat {
    /// The accepted extensions, for messages.
    pub const EXTENSIONS_TEXT: &'static str = ".obj, .ply or .stl";

    /// The format named by the extension of `path`.
    pub fn of(path: &Path) -> Result<Self, ExportError> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Ok(MeshFormat::Obj),
            "ply" => Ok(MeshFormat::Ply),
            "stl" => Ok(MeshFormat::Stl),
            _ => Err(ExportError::UnknownFormat { path: path.to_path_buf() }),
        }
    }
}

impl PolyMesh {
    /// Writes the file named by `path` atomically ([`write_atomic`]), format by extension
    /// ([`MeshFormat::of`]): `obj`, `ply` (binary), `stl` (binary).
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), ExportError> {
        mesh::write_mesh_file(self, path.as_ref())
    }
}

impl TriMesh {
    /// Writes the file named by `path` atomically ([`write_atomic`]), format by extension
    /// ([`MeshFormat::of`]): `obj`, `ply` (binary), `stl` (binary).
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), ExportError> {
        mesh::write_mesh_file(self, path.as_ref())
    }
}

impl SurfaceMesh {
    /// Writes the file named by `path` atomically ([`write_atomic`]), format by extension
    /// ([`MeshFormat::of`]): `obj`, `ply` (binary, with the per-vertex quality data), `stl`.
    pub fn write_file(&self, path: impl AsRef<Path>) -> Result<(), ExportError> {
        mesh::write_mesh_file(self, path.as_ref())
    }
}
