//! PLY: `double` positions, optional `float` normals, per-vertex scalars (`float` or `double`),
//! polygon faces.
//!
//! No written value is ever infinite unless the `f64` was: `float` fields (normals, scalars
//! declared [`ScalarType::Float`]) go through [`f32_clamped`] (values beyond the `f32` range
//! become ±`f32::MAX`; every value in range is the nearest `f32`), and data whose range is not
//! bounded (curvatures) are declared [`ScalarType::Double`] and written exactly.

use super::encode::{f32_clamped, push_f64, push_int, write_chunks};
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

/// The PLY type a per-vertex scalar is written as.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ScalarType {
    /// `property float`: for bounded display values (isophotes, stripes, quality); values beyond
    /// the `f32` range are written as ±`f32::MAX` (never `inf`).
    #[default]
    Float,
    /// `property double`: exact, for unbounded data (curvatures) and integers above 2^24.
    Double,
}

/// A named per-vertex scalar written as `property float <name>` or `property double <name>`
/// (e.g. `quality`, curvature).
#[derive(Clone, Copy, Debug)]
pub struct VertexScalar<'a> {
    pub name: &'a str,
    pub values: &'a [f64],
    pub ty: ScalarType,
}

impl<'a> VertexScalar<'a> {
    /// A scalar written as `float` (see [`ScalarType::Float`]).
    pub fn float(name: &'a str, values: &'a [f64]) -> Self {
        VertexScalar { name, values, ty: ScalarType::Float }
    }
    /// A scalar written as `double` (exact).
    pub fn double(name: &'a str, values: &'a [f64]) -> Self {
        VertexScalar { name, values, ty: ScalarType::Double }
    }
}

/// Writes PLY: `double x y z`, optional `float nx ny nz` (when `normals` has one per vertex),
/// the given per-vertex scalars as their [`ScalarType`], and faces as
/// `list uchar int vertex_indices` (faces with more than 255 corners use `list int int`).
/// `float` values are clamped to the `f32` range (see the module doc); ASCII numbers are the
/// shortest text that parses back to the written `f64`/`f32`. The body is encoded in parallel
/// chunks (bounded memory).
pub fn write_ply<W: Write>(
    w: W,
    positions: &[DVec3],
    normals: Option<&[DVec3]>,
    faces: &[&[u32]],
    scalars: &[VertexScalar<'_>],
    format: PlyFormat,
) -> io::Result<()> {
    write_ply_faces(w, positions, normals, Faces::Slices(faces), scalars, format)
}

/// The faces [`write_ply_faces`] writes, borrowed as the caller holds them (no copy).
#[derive(Clone, Copy)]
pub(crate) enum Faces<'a> {
    Slices(&'a [&'a [u32]]),
    Polygons(&'a [Vec<u32>]),
    Triangles(&'a [[u32; 3]]),
    Quads(&'a [[u32; 4]]),
}

impl<'a> Faces<'a> {
    /// The output faces of a surface mesh: its quads when it has any, else its triangles.
    pub(crate) fn of(mesh: &'a SurfaceMesh) -> Self {
        if mesh.quads.is_empty() {
            Faces::Triangles(&mesh.triangles)
        } else {
            Faces::Quads(&mesh.quads)
        }
    }
}

impl<'a> Faces<'a> {
    fn len(self) -> usize {
        match self {
            Faces::Slices(f) => f.len(),
            Faces::Polygons(f) => f.len(),
            Faces::Triangles(f) => f.len(),
            Faces::Quads(f) => f.len(),
        }
    }
    fn get(self, i: usize) -> &'a [u32] {
        match self {
            Faces::Slices(f) => f[i],
            Faces::Polygons(f) => &f[i],
            Faces::Triangles(f) => &f[i],
            Faces::Quads(f) => &f[i],
        }
    }
}

/// [`write_ply`] for faces in any of the layouts of [`Faces`].
pub(crate) fn write_ply_faces<W: Write>(
    mut w: W,
    positions: &[DVec3],
    normals: Option<&[DVec3]>,
    faces: Faces<'_>,
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
    let wide = match faces {
        Faces::Triangles(_) => false,
        _ => (0..faces.len()).any(|i| faces.get(i).len() > 255),
    };
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
        let ty = match s.ty {
            ScalarType::Float => "float",
            ScalarType::Double => "double",
        };
        writeln!(w, "property {ty} {}", s.name)?;
    }
    writeln!(w, "element face {}", faces.len())?;
    writeln!(w, "property list {} int vertex_indices", if wide { "int" } else { "uchar" })?;
    writeln!(w, "end_header")?;
    match format {
        PlyFormat::Ascii => {
            write_chunks(&mut w, nv, |r, buf| {
                let mut f32_text = zmij::Buffer::new();
                for i in r {
                    let p = positions[i];
                    push_f64(buf, p.x);
                    for c in [p.y, p.z] {
                        buf.push(b' ');
                        push_f64(buf, c);
                    }
                    let mut push_f32 = |buf: &mut Vec<u8>, x: f64| {
                        buf.push(b' ');
                        buf.extend_from_slice(f32_text.format(f32_clamped(x)).as_bytes());
                    };
                    if let Some(n) = normals {
                        for c in n[i].to_array() {
                            push_f32(buf, c);
                        }
                    }
                    for s in scalars {
                        match s.ty {
                            ScalarType::Float => push_f32(buf, s.values[i]),
                            ScalarType::Double => {
                                buf.push(b' ');
                                push_f64(buf, s.values[i]);
                            }
                        }
                    }
                    buf.push(b'\n');
                }
                Ok(())
            })?;
            write_chunks(&mut w, faces.len(), |r, buf| {
                for f in r.map(|i| faces.get(i)) {
                    push_int(buf, f.len());
                    for &i in f.iter() {
                        buf.push(b' ');
                        push_int(buf, i);
                    }
                    buf.push(b'\n');
                }
                Ok(())
            })?;
        }
        PlyFormat::BinaryLittleEndian => {
            let record = 24
                + if normals.is_some() { 12 } else { 0 }
                + scalars.iter().map(|s| if s.ty == ScalarType::Double { 8 } else { 4 }).sum::<usize>();
            write_chunks(&mut w, nv, |r, buf| {
                buf.reserve(r.len() * record);
                for i in r {
                    for c in positions[i].to_array() {
                        buf.extend_from_slice(&c.to_le_bytes());
                    }
                    if let Some(n) = normals {
                        for c in n[i].to_array() {
                            buf.extend_from_slice(&f32_clamped(c).to_le_bytes());
                        }
                    }
                    for s in scalars {
                        match s.ty {
                            ScalarType::Float => buf.extend_from_slice(&f32_clamped(s.values[i]).to_le_bytes()),
                            ScalarType::Double => buf.extend_from_slice(&s.values[i].to_le_bytes()),
                        }
                    }
                }
                Ok(())
            })?;
            write_chunks(&mut w, faces.len(), |r, buf| {
                for f in r.map(|i| faces.get(i)) {
                    if wide {
                        buf.extend_from_slice(&(f.len() as i32).to_le_bytes());
                    } else {
                        buf.push(f.len() as u8);
                    }
                    for &i in f.iter() {
                        buf.extend_from_slice(&(i as i32).to_le_bytes());
                    }
                }
                Ok(())
            })?;
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
    let scalars = [VertexScalar::float("isophote", &iso), VertexScalar::float("stripe", &band)];
    write_ply_faces(w, &mesh.positions, Some(&mesh.normals), Faces::of(mesh), &scalars, PlyFormat::BinaryLittleEndian)
}
