//! PLY: `double` positions, optional `float` normals and per-vertex scalars, polygon faces.

use crate::tessellate::SurfaceMesh;
use glam::DVec3;
use std::io::{self, Write};

/// PLY body encoding.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PlyFormat {
    /// Human-readable text.
    #[default]
    Ascii,
    /// `binary_little_endian 1.0`.
    BinaryLittleEndian,
}

/// A named per-vertex scalar written as `property float <name>` (e.g. `quality`, curvature).
#[derive(Clone, Copy, Debug)]
pub struct VertexScalar<'a> {
    pub name: &'a str,
    pub values: &'a [f64],
}

/// Writes PLY: `double x y z`, optional `float nx ny nz` (when `normals` has one per vertex),
/// the given per-vertex scalars as `float`, and faces as `list uchar int vertex_indices`
/// (faces with more than 255 corners use `list int int`).
pub fn write_ply<W: Write>(
    mut w: W,
    positions: &[DVec3],
    normals: Option<&[DVec3]>,
    faces: &[&[u32]],
    scalars: &[VertexScalar<'_>],
    format: PlyFormat,
) -> io::Result<()> {
    let nv = positions.len();
    for s in scalars {
        if s.values.len() != nv || s.name.is_empty() || s.name.contains(char::is_whitespace) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("scalar {:?}: needs one value per vertex and a name without spaces", s.name),
            ));
        }
    }
    let normals = normals.filter(|n| n.len() == nv);
    let wide = faces.iter().any(|f| f.len() > 255);
    writeln!(w, "ply")?;
    match format {
        PlyFormat::Ascii => writeln!(w, "format ascii 1.0")?,
        PlyFormat::BinaryLittleEndian => writeln!(w, "format binary_little_endian 1.0")?,
    }
    writeln!(w, "comment written by gbsurf")?;
    writeln!(w, "element vertex {nv}")?;
    for c in ["x", "y", "z"] {
        writeln!(w, "property double {c}")?;
    }
    if normals.is_some() {
        for c in ["nx", "ny", "nz"] {
            writeln!(w, "property float {c}")?;
        }
    }
    for s in scalars {
        writeln!(w, "property float {}", s.name)?;
    }
    writeln!(w, "element face {}", faces.len())?;
    writeln!(w, "property list {} int vertex_indices", if wide { "int" } else { "uchar" })?;
    writeln!(w, "end_header")?;
    match format {
        PlyFormat::Ascii => {
            for (i, p) in positions.iter().enumerate() {
                write!(w, "{:?} {:?} {:?}", p.x, p.y, p.z)?;
                if let Some(n) = normals {
                    write!(w, " {:?} {:?} {:?}", n[i].x as f32, n[i].y as f32, n[i].z as f32)?;
                }
                for s in scalars {
                    write!(w, " {:?}", s.values[i] as f32)?;
                }
                writeln!(w)?;
            }
            for f in faces {
                write!(w, "{}", f.len())?;
                for i in f.iter() {
                    write!(w, " {i}")?;
                }
                writeln!(w)?;
            }
        }
        PlyFormat::BinaryLittleEndian => {
            for (i, p) in positions.iter().enumerate() {
                for c in p.to_array() {
                    w.write_all(&c.to_le_bytes())?;
                }
                if let Some(n) = normals {
                    for c in n[i].to_array() {
                        w.write_all(&(c as f32).to_le_bytes())?;
                    }
                }
                for s in scalars {
                    w.write_all(&(s.values[i] as f32).to_le_bytes())?;
                }
            }
            for f in faces {
                if wide {
                    w.write_all(&(f.len() as i32).to_le_bytes())?;
                } else {
                    w.write_all(&[f.len() as u8])?;
                }
                for &i in f.iter() {
                    w.write_all(&(i as i32).to_le_bytes())?;
                }
            }
        }
    }
    w.flush()
}

/// Writes the isophote display (seed 000 §5.2) of a surface mesh as binary PLY: per-vertex `isophote`
/// = n·L ([`crate::quality::isophote`]) and `stripe` ([`crate::quality::isophote_stripes`], its
/// integer part's parity is the stripe colour) for the light direction `light`; `stripes` must be
/// in 1..=[`crate::limits::MAX_STRIPES`] (else an `InvalidInput` error carrying the
/// [`crate::options::OptionError`]).
pub fn write_isophotes_ply<W: Write>(w: W, mesh: &SurfaceMesh, light: DVec3, stripes: u32) -> io::Result<()> {
    let stripes = crate::options::check_stripes(stripes).map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e))?;
    let iso = crate::quality::isophote(&mesh.normals, light);
    let band = crate::quality::isophote_stripes(&mesh.normals, light, stripes);
    let faces: Vec<&[u32]> = mesh.triangles.iter().map(|t| t.as_slice()).collect();
    let scalars = [VertexScalar { name: "isophote", values: &iso }, VertexScalar { name: "stripe", values: &band }];
    write_ply(w, &mesh.positions, Some(&mesh.normals), &faces, &scalars, PlyFormat::BinaryLittleEndian)
}
