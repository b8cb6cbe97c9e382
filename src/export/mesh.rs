//! The mesh writers of [`PolyMesh`], [`TriMesh`] and [`SurfaceMesh`], and the by-extension
//! dispatch ([`WriteMesh`], [`encode_mesh`]).

use super::ply::{write_ply_faces, Faces, PlyFormat, VertexScalar};
use super::{obj, stl, write_atomic, ExportError, MeshFormat};
use crate::mesh::{PolyMesh, TriMesh};
use crate::tessellate::SurfaceMesh;
use std::io::{self, Write};
use std::path::Path;

/// A mesh that can be written in every [`MeshFormat`].
pub trait WriteMesh {
    /// Writes the mesh in `format`.
    fn write_format(&self, format: MeshFormat, w: &mut dyn Write) -> io::Result<()>;
}

impl WriteMesh for PolyMesh {
    fn write_format(&self, format: MeshFormat, w: &mut dyn Write) -> io::Result<()> {
        match format {
            MeshFormat::Obj => self.write_obj(w),
            MeshFormat::Ply => self.write_ply(w, PlyFormat::BinaryLittleEndian, &[]),
            MeshFormat::Stl => self.write_stl(w),
        }
    }
}

impl WriteMesh for TriMesh {
    fn write_format(&self, format: MeshFormat, w: &mut dyn Write) -> io::Result<()> {
        match format {
            MeshFormat::Obj => self.write_obj(w),
            MeshFormat::Ply => self.write_ply(w, PlyFormat::BinaryLittleEndian, &[]),
            MeshFormat::Stl => self.write_stl(w),
        }
    }
}

impl WriteMesh for SurfaceMesh {
    fn write_format(&self, format: MeshFormat, w: &mut dyn Write) -> io::Result<()> {
        match format {
            MeshFormat::Obj => self.write_obj(w),
            MeshFormat::Ply => self.write_ply(w),
            MeshFormat::Stl => self.write_stl(w),
        }
    }
}

/// `mesh` in the format named by the extension of `path` ([`MeshFormat::of`]), in memory.
pub fn encode_mesh(mesh: &impl WriteMesh, path: &Path) -> Result<Vec<u8>, ExportError> {
    let format = MeshFormat::of(path)?;
    let mut buf = Vec::new();
    mesh.write_format(format, &mut buf).map_err(|e| ExportError::io(path, e))?;
    Ok(buf)
}

/// `mesh` written atomically to `path` in the format named by its extension.
pub(super) fn write_mesh_file(mesh: &impl WriteMesh, path: &Path) -> Result<(), ExportError> {
    let format = MeshFormat::of(path)?;
    write_atomic(path, |w| mesh.write_format(format, w))
}

impl PolyMesh {
    /// Writes Wavefront OBJ (`v` with shortest round-trip coordinates, `f` with 1-based polygon
    /// loops).
    pub fn write_obj<W: Write>(&self, w: W) -> io::Result<()> {
        obj::write_polygons(w, &self.positions, &self.faces)
    }
    /// Writes PLY with polygon faces and optional per-vertex scalars.
    pub fn write_ply<W: Write>(&self, w: W, format: PlyFormat, scalars: &[VertexScalar<'_>]) -> io::Result<()> {
        write_ply_faces(w, &self.positions, None, Faces::Polygons(&self.faces), scalars, format)
    }
    /// Writes binary STL; faces are first split into convex pieces
    /// ([`crate::mesh::geometry::convexify`]) and then fan-triangulated, so concave faces come
    /// out right.
    pub fn write_stl<W: Write>(&self, w: W) -> io::Result<()> {
        let (convex, _) = crate::mesh::geometry::convexify(self);
        let mut tris = Vec::new();
        for f in &convex.faces {
            for k in 1..f.len().saturating_sub(1) {
                tris.push([f[0], f[k], f[k + 1]]);
            }
        }
        stl::write_stl_triangles(w, &self.positions, &tris)
    }
}

impl TriMesh {
    /// Writes Wavefront OBJ (`v`, `vn`, `f a//a b//b c//c`), shortest round-trip coordinates.
    pub fn write_obj<W: Write>(&self, w: W) -> io::Result<()> {
        obj::write_triangles(w, None, &self.positions, &self.normals, &self.triangles)
    }
    /// Writes PLY with per-vertex normals (when present) and optional per-vertex scalars.
    pub fn write_ply<W: Write>(&self, w: W, format: PlyFormat, scalars: &[VertexScalar<'_>]) -> io::Result<()> {
        write_ply_faces(w, &self.positions, Some(&self.normals), Faces::Triangles(&self.triangles), scalars, format)
    }
    /// Writes binary STL.
    pub fn write_stl<W: Write>(&self, w: W) -> io::Result<()> {
        stl::write_stl_triangles(w, &self.positions, &self.triangles)
    }
}

impl SurfaceMesh {
    /// Wavefront OBJ: a comment with the counts, `v`, `vn`, `f a//a b//b c//c` (quad layout:
    /// `f` with 4 indices), shortest round-trip coordinates.
    pub fn write_obj<W: Write>(&self, w: W) -> io::Result<()> {
        if self.quads.is_empty() {
            let comment = format!("gbsurf: {} vertices, {} triangles", self.positions.len(), self.triangles.len());
            obj::write_triangles(w, Some(&comment), &self.positions, &self.normals, &self.triangles)
        } else {
            let comment = format!("gbsurf: {} vertices, {} quads", self.positions.len(), self.quads.len());
            obj::write_triangles(w, Some(&comment), &self.positions, &self.normals, &self.quads)
        }
    }

    /// Binary little-endian PLY: `double x y z`, `float nx ny nz` (unit normals), per-vertex
    /// `double` scalars `patch`, `mean_curvature`, `gaussian_curvature`, `g1_deviation`
    /// (degrees), a `float` `fold` (1 on vertices of a fold or flipped triangle, else 0),
    /// triangles (or the quads of the quad layout) as `uchar`-counted `int` lists; the first four
    /// scalars only when the mesh has them ([`crate::ConvertOptions::quality_arrays`]). The per-vertex data are `double` so
    /// that every value is written exactly: curvatures are unbounded (a cube scaled by 1e-20 has
    /// Gaussian curvatures near 1e40, beyond `f32`, which would have been written as `inf`), and
    /// patch indices above 2^24 are not all `f32` values.
    pub fn write_ply<W: Write>(&self, w: W) -> io::Result<()> {
        let patch: Vec<f64> = self.patch.iter().map(|&p| p as f64).collect();
        // Meshes built without the fold test (subdivision methods) may have no flags: all 0.
        let fold: Vec<f64> = (0..self.positions.len()).map(|v| self.fold.get(v).map_or(0.0, |&f| f as f64)).collect();
        // A mesh converted without its quality arrays (ConvertOptions::quality_arrays) has none
        // to write: those scalars are left out (of a mesh with vertices; a mesh without vertices
        // writes them all, empty).
        let scalars: Vec<VertexScalar<'_>> = [
            VertexScalar::double("patch", &patch),
            VertexScalar::double("mean_curvature", &self.mean_curvature),
            VertexScalar::double("gaussian_curvature", &self.gaussian_curvature),
            VertexScalar::double("g1_deviation", &self.g1_deviation_deg),
            VertexScalar::float("fold", &fold),
        ]
        .into_iter()
        .filter(|s| !s.values.is_empty() || self.positions.is_empty())
        .collect();
        write_ply_faces(w, &self.positions, Some(&self.normals), Faces::of(self), &scalars, PlyFormat::BinaryLittleEndian)
    }

    /// Binary STL (facet normals from the triangles; the quad layout's quads are written as
    /// their two triangles).
    pub fn write_stl<W: Write>(&self, w: W) -> io::Result<()> {
        stl::write_stl_triangles(w, &self.positions, &self.triangles)
    }
}
