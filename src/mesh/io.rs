//! Mesh file input and output.
//!
//! Reading: [`read_mesh`] (validated [`HalfEdgeMesh`]) and [`read_polymesh`] (syntax only, with
//! a [`SourceMap`] of line numbers) dispatch on the extension: `.obj`, `.off`, `.ply` (ASCII and
//! binary little-endian), `.stl` (binary and ASCII; identical corner positions are welded).
//!
//! OBJ is read by a strict line parser of our own ([`parse_obj`]), not by `tobj`. Checked
//! against `tobj` 4.0.5 with `use_f64` and `LoadOptions { triangulate: false, single_index:
//! false, ignore_points: true, ignore_lines: true, .. }`: its geometry cannot be mapped back to
//! the file's `v` numbering, which our errors, warnings and [`SourceMap`] are keyed on. Each
//! model (`o`/`g`/`usemtl` section) gets its own copy of only the positions its faces use,
//! renumbered in first-use order, with no local → file index map; vertices used by no face are
//! dropped (so no isolated-vertex warning is possible); matching copies back by value would weld
//! coincident vertices (seams). Recovering the numbering would need the face indices and all
//! coordinates parsed by a pre-scan, i.e. this parser again. `tobj` also drops 1- and 2-corner
//! `f` statements silently under `ignore_points`/`ignore_lines` (treating `l` like `f`
//! otherwise), ignores unknown statements (a garbage line would give a partial mesh), reports
//! index errors as a bare `FaceVertexOutOfBounds` (no face, corner or line; index 0 wraps to
//! `usize::MAX`) and rejects `v 0 0 0 # comment`.
//!
//! Ours keeps n-gons, reads `f64` (`nan`/`inf` parse and are rejected by validation with the
//! vertex and line), uses only position indices (`v/vt/vn` → `v`, negative = relative), merges
//! all objects and groups into one [`PolyMesh`] in file order, strips `#` comments, ignores
//! `vn vt vp g o s usemtl mtllib l p` statements, and rejects anything else with
//! [`MeshError::Parse`] naming the line, so a garbage file is an error, never a partial mesh.
//!
//! The writers are in [`crate::export`].

use super::error::{MeshError, SourceMap};
use super::halfedge::HalfEdgeMesh;
use super::PolyMesh;
use glam::DVec3;
use std::collections::HashMap;
use std::fs;
use std::io;
use std::path::Path;

fn parse_err(line: Option<usize>, message: impl Into<String>) -> MeshError {
    MeshError::Parse { line, message: message.into() }
}

fn io_err(path: &Path, e: io::Error) -> MeshError {
    MeshError::Io { path: path.display().to_string(), message: e.to_string() }
}

/// Parses OBJ text: positions and polygon faces (see the module doc). Indices are checked
/// against the vertex count ([`MeshError::IndexOutOfRange`] with the line); other checks are left
/// to validation.
pub fn parse_obj(text: &str) -> Result<(PolyMesh, SourceMap), MeshError> {
    let mut positions = Vec::new();
    let mut raw_faces: Vec<(Vec<i64>, usize)> = Vec::new();
    let mut map = SourceMap::default();
    for (ln0, raw) in text.lines().enumerate() {
        let ln = ln0 + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut toks = content.split_whitespace();
        let Some(kw) = toks.next() else { continue };
        match kw {
            "v" => {
                let vals: Vec<&str> = toks.collect();
                if vals.len() < 3 {
                    return Err(parse_err(
                        Some(ln),
                        format!("vertex needs 3 coordinates, found {}", vals.len()),
                    ));
                }
                let mut xyz = [0.0; 3];
                for (i, t) in vals.iter().enumerate() {
                    let x: f64 = t
                        .parse()
                        .map_err(|_| parse_err(Some(ln), format!("bad number {t:?} in vertex")))?;
                    if i < 3 {
                        xyz[i] = x;
                    }
                }
                positions.push(DVec3::from_array(xyz));
                map.vertex_lines.push(ln);
            }
            "f" => {
                let mut idx = Vec::new();
                for t in toks {
                    let first = t.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| parse_err(Some(ln), format!("bad vertex index {t:?} in face")))?;
                    let i0 = match i {
                        0 => return Err(parse_err(Some(ln), "vertex index 0 in face (OBJ is 1-based)")),
                        i if i > 0 => i - 1,
                        i => positions.len() as i64 + i,
                    };
                    idx.push(i0);
                }
                raw_faces.push((idx, ln));
                map.face_lines.push(ln);
            }
            "vn" | "vt" | "vp" | "g" | "o" | "s" | "usemtl" | "mtllib" | "l" | "p" => {}
            other => {
                return Err(parse_err(Some(ln), format!("unknown statement {other:?}")));
            }
        }
    }
    let nv = positions.len();
    let mut faces = Vec::with_capacity(raw_faces.len());
    for (f, (idx, ln)) in raw_faces.into_iter().enumerate() {
        for (c, &i) in idx.iter().enumerate() {
            if i < 0 || i as usize >= nv || i > u32::MAX as i64 - 1 {
                return Err(MeshError::IndexOutOfRange {
                    face: f,
                    corner: c,
                    index: i,
                    n_vertices: nv,
                    line: Some(ln),
                });
            }
        }
        faces.push(idx.into_iter().map(|i| i as u32).collect());
    }
    Ok((PolyMesh { positions, faces }, map))
}

/// Parses ASCII OFF (`OFF`, counts, vertices, faces `n i0 … i(n−1)`; `#` comments; colours after
/// the indices ignored).
pub fn parse_off(text: &str) -> Result<(PolyMesh, SourceMap), MeshError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| !l.is_empty());
    let (ln, head) = lines.next().ok_or_else(|| parse_err(None, "empty OFF file"))?;
    let mut head_toks: Vec<&str> = head.split_whitespace().collect();
    if head_toks.first().map(|t| t.ends_with("OFF")) != Some(true) {
        return Err(parse_err(Some(ln), "missing OFF header"));
    }
    head_toks.remove(0);
    let counts_toks: Vec<(usize, String)> = if head_toks.is_empty() {
        let (ln, l) = lines.next().ok_or_else(|| parse_err(None, "missing OFF counts"))?;
        l.split_whitespace().map(|t| (ln, t.to_string())).collect()
    } else {
        head_toks.iter().map(|t| (ln, t.to_string())).collect()
    };
    if counts_toks.len() < 2 {
        return Err(parse_err(Some(ln), "OFF counts need vertex and face numbers"));
    }
    let cnt = |k: usize| -> Result<usize, MeshError> {
        counts_toks[k].1.parse().map_err(|_| parse_err(Some(counts_toks[k].0), "bad OFF count"))
    };
    let (nv, nf) = (cnt(0)?, cnt(1)?);
    let mut map = SourceMap::default();
    let mut positions = Vec::with_capacity(nv.min(1 << 24));
    for _ in 0..nv {
        let (ln, l) = lines.next().ok_or_else(|| parse_err(None, "OFF file ends in the vertices"))?;
        let v: Result<Vec<f64>, _> = l.split_whitespace().take(3).map(str::parse::<f64>).collect();
        let v = v.map_err(|_| parse_err(Some(ln), "bad number in OFF vertex"))?;
        if v.len() < 3 {
            return Err(parse_err(Some(ln), "OFF vertex needs 3 coordinates"));
        }
        positions.push(DVec3::new(v[0], v[1], v[2]));
        map.vertex_lines.push(ln);
    }
    let mut faces = Vec::with_capacity(nf.min(1 << 24));
    for f in 0..nf {
        let (ln, l) = lines.next().ok_or_else(|| parse_err(None, "OFF file ends in the faces"))?;
        let toks: Vec<&str> = l.split_whitespace().collect();
        let n: usize = toks
            .first()
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| parse_err(Some(ln), "bad OFF face size"))?;
        if toks.len() < n + 1 {
            return Err(parse_err(Some(ln), "OFF face has fewer indices than announced"));
        }
        let mut face = Vec::with_capacity(n);
        for (c, t) in toks[1..=n].iter().enumerate() {
            let i: i64 = t.parse().map_err(|_| parse_err(Some(ln), "bad OFF vertex index"))?;
            if i < 0 || i as usize >= nv {
                return Err(MeshError::IndexOutOfRange {
                    face: f,
                    corner: c,
                    index: i,
                    n_vertices: nv,
                    line: Some(ln),
                });
            }
            face.push(i as u32);
        }
        faces.push(face);
        map.face_lines.push(ln);
    }
    Ok((PolyMesh { positions, faces }, map))
}

/// Reads a mesh file without validating its topology (dispatch on the extension; see the
/// module doc). Returns the line numbers of elements for text formats (empty for binary ones).
pub fn read_polymesh(path: impl AsRef<Path>) -> Result<(PolyMesh, SourceMap), MeshError> {
    let path = path.as_ref();
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let bytes = fs::read(path).map_err(|e| io_err(path, e))?;
    match ext.as_str() {
        "obj" => parse_obj(&utf8(&bytes)?),
        "off" => parse_off(&utf8(&bytes)?),
        "ply" => parse_ply(&bytes),
        "stl" => parse_stl(&bytes).map(|m| (m, SourceMap::default())),
        _ => Err(parse_err(None, format!("unknown mesh file extension {ext:?} of {}", path.display()))),
    }
}

fn utf8(bytes: &[u8]) -> Result<String, MeshError> {
    String::from_utf8(bytes.to_vec()).map_err(|e| {
        let line = bytes[..e.utf8_error().valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
        parse_err(Some(line), "file is not UTF-8 text")
    })
}

/// Reads and validates a mesh file into a half-edge mesh; errors and warnings carry the source
/// line of the named element for text formats.
pub fn read_mesh(path: impl AsRef<Path>) -> Result<HalfEdgeMesh, MeshError> {
    let (mesh, map) = read_polymesh(path)?;
    let mut he = HalfEdgeMesh::from_polymesh(&mesh).map_err(|e| e.with_source(&map))?;
    he.annotate_warnings(&map);
    Ok(he)
}

// ---------------------------------------------------------------- PLY reading

#[derive(Clone, Copy, Debug, PartialEq)]
enum PlyType {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl PlyType {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
    fn read_le(self, b: &[u8]) -> f64 {
        match self {
            Self::I8 => b[0] as i8 as f64,
            Self::U8 => b[0] as f64,
            Self::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Self::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Self::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Self::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Self::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Self::F64 => f64::from_le_bytes(b[..8].try_into().unwrap_or([0; 8])),
        }
    }
}

#[derive(Debug)]
struct PlyProp {
    name: String,
    /// `Some(count type)` for a list property.
    list: Option<PlyType>,
    ty: PlyType,
}

#[derive(Debug)]
struct PlyElement {
    name: String,
    count: usize,
    props: Vec<PlyProp>,
}

/// Reads PLY (ASCII or binary little-endian): `vertex` x/y/z and `face` `vertex_indices` (or
/// `vertex_index`); other elements and properties are skipped.
pub fn parse_ply(bytes: &[u8]) -> Result<(PolyMesh, SourceMap), MeshError> {
    // Header.
    let mut pos = 0;
    let mut line_no = 0;
    let mut next_line = |pos: &mut usize| -> Option<(usize, String)> {
        if *pos >= bytes.len() {
            return None;
        }
        let end = bytes[*pos..].iter().position(|&b| b == b'\n').map_or(bytes.len(), |e| *pos + e);
        let l = String::from_utf8_lossy(&bytes[*pos..end]).trim_end_matches('\r').to_string();
        *pos = (end + 1).min(bytes.len());
        line_no += 1;
        Some((line_no, l))
    };
    match next_line(&mut pos) {
        Some((_, l)) if l.trim() == "ply" => {}
        _ => return Err(parse_err(Some(1), "missing 'ply' magic")),
    }
    let mut binary = None;
    let mut elements: Vec<PlyElement> = Vec::new();
    loop {
        let (ln, l) = next_line(&mut pos).ok_or_else(|| parse_err(None, "PLY header without end_header"))?;
        let t: Vec<&str> = l.split_whitespace().collect();
        match t.as_slice() {
            ["format", "ascii", _] => binary = Some(false),
            ["format", "binary_little_endian", _] => binary = Some(true),
            ["format", f, ..] => return Err(parse_err(Some(ln), format!("unsupported PLY format {f}"))),
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => elements.push(PlyElement {
                name: name.to_string(),
                count: count.parse().map_err(|_| parse_err(Some(ln), "bad element count"))?,
                props: Vec::new(),
            }),
            ["property", "list", ct, ty, name] => {
                let e = elements.last_mut().ok_or_else(|| parse_err(Some(ln), "property before element"))?;
                let (Some(ct), Some(ty)) = (PlyType::parse(ct), PlyType::parse(ty)) else {
                    return Err(parse_err(Some(ln), "unknown PLY type"));
                };
                e.props.push(PlyProp { name: name.to_string(), list: Some(ct), ty });
            }
            ["property", ty, name] => {
                let e = elements.last_mut().ok_or_else(|| parse_err(Some(ln), "property before element"))?;
                let ty = PlyType::parse(ty).ok_or_else(|| parse_err(Some(ln), "unknown PLY type"))?;
                e.props.push(PlyProp { name: name.to_string(), list: None, ty });
            }
            ["end_header"] => break,
            _ => return Err(parse_err(Some(ln), format!("bad PLY header line {l:?}"))),
        }
    }
    let binary = binary.ok_or_else(|| parse_err(None, "PLY header has no format line"))?;
    let mut positions = Vec::new();
    let mut faces: Vec<Vec<u32>> = Vec::new();
    let mut map = SourceMap::default();
    let mut raw_faces: Vec<(Vec<f64>, Option<usize>)> = Vec::new();
    // Body: one record = Vec of values per property (lists flattened into their own Vec).
    let mut ascii_lines = if binary {
        None
    } else {
        let text = String::from_utf8_lossy(&bytes[pos..]).to_string();
        let start = line_no;
        Some(
            text.lines()
                .enumerate()
                .map(|(i, l)| (start + i + 1, l.to_string()))
                .filter(|(_, l)| !l.trim().is_empty())
                .collect::<Vec<_>>()
                .into_iter(),
        )
    };
    for el in &elements {
        let xyz: Vec<Option<usize>> =
            ["x", "y", "z"].iter().map(|n| el.props.iter().position(|p| p.name == *n)).collect();
        let fidx = el.props.iter().position(|p| {
            p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index")
        });
        for _ in 0..el.count {
            let mut rec: Vec<Vec<f64>> = Vec::with_capacity(el.props.len());
            let mut rec_line = None;
            if let Some(lines) = ascii_lines.as_mut() {
                let (ln, l) = lines.next().ok_or_else(|| parse_err(None, "PLY file ends early"))?;
                rec_line = Some(ln);
                let mut toks = l.split_whitespace();
                let num = |toks: &mut std::str::SplitWhitespace| -> Result<f64, MeshError> {
                    toks.next()
                        .ok_or_else(|| parse_err(Some(ln), "too few values"))?
                        .parse::<f64>()
                        .map_err(|_| parse_err(Some(ln), "bad number"))
                };
                for p in &el.props {
                    if p.list.is_some() {
                        let n = num(&mut toks)?;
                        if !(n >= 0.0 && n < 1e7) {
                            return Err(parse_err(Some(ln), "bad list length"));
                        }
                        let v: Result<Vec<f64>, _> = (0..n as usize).map(|_| num(&mut toks)).collect();
                        rec.push(v?);
                    } else {
                        rec.push(vec![num(&mut toks)?]);
                    }
                }
            } else {
                let mut take = |n: usize| -> Result<&[u8], MeshError> {
                    let s = bytes.get(pos..pos + n).ok_or_else(|| parse_err(None, "PLY file ends early"))?;
                    pos += n;
                    Ok(s)
                };
                for p in &el.props {
                    if let Some(ct) = p.list {
                        let n = ct.read_le(take(ct.size())?);
                        if !(n >= 0.0 && n < 1e7) {
                            return Err(parse_err(None, "bad list length"));
                        }
                        let mut v = Vec::with_capacity(n as usize);
                        for _ in 0..n as usize {
                            v.push(p.ty.read_le(take(p.ty.size())?));
                        }
                        rec.push(v);
                    } else {
                        rec.push(vec![p.ty.read_le(take(p.ty.size())?)]);
                    }
                }
            }
            if el.name == "vertex" {
                let mut c = [0.0; 3];
                for k in 0..3 {
                    let i = xyz[k].ok_or_else(|| parse_err(None, "PLY vertex without x/y/z"))?;
                    c[k] = rec[i].first().copied().ok_or_else(|| parse_err(rec_line, "PLY vertex coordinate is an empty list"))?;
                }
                positions.push(DVec3::from_array(c));
                if let Some(l) = rec_line {
                    map.vertex_lines.push(l);
                }
            } else if el.name == "face" {
                let i = fidx.ok_or_else(|| parse_err(None, "PLY face without vertex_indices"))?;
                raw_faces.push((std::mem::take(&mut rec[i]), rec_line));
                if let Some(l) = rec_line {
                    map.face_lines.push(l);
                }
            }
        }
    }
    let nv = positions.len();
    for (f, (idx, ln)) in raw_faces.into_iter().enumerate() {
        let mut face = Vec::with_capacity(idx.len());
        for (c, &i) in idx.iter().enumerate() {
            if !(i >= 0.0 && (i as usize) < nv) || i.fract() != 0.0 {
                return Err(MeshError::IndexOutOfRange {
                    face: f,
                    corner: c,
                    index: i as i64,
                    n_vertices: nv,
                    line: ln,
                });
            }
            face.push(i as u32);
        }
        faces.push(face);
    }
    Ok((PolyMesh { positions, faces }, map))
}

// ---------------------------------------------------------------- STL reading

/// Reads STL (binary, or ASCII when the file starts with `solid` and its size does not match the
/// binary layout). Corners with bit-identical positions are welded into one vertex.
pub fn parse_stl(bytes: &[u8]) -> Result<PolyMesh, MeshError> {
    let is_binary = bytes.len() >= 84 && {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        84 + 50 * n == bytes.len()
    };
    let mut tris: Vec<[DVec3; 3]> = Vec::new();
    if is_binary {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        for t in 0..n {
            let base = 84 + 50 * t + 12;
            let mut c = [DVec3::ZERO; 3];
            for (k, ck) in c.iter_mut().enumerate() {
                let f = |j: usize| {
                    let o = base + 12 * k + 4 * j;
                    f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]) as f64
                };
                *ck = DVec3::new(f(0), f(1), f(2));
            }
            tris.push(c);
        }
    } else {
        let text = utf8(bytes)?;
        if !text.trim_start().starts_with("solid") {
            return Err(parse_err(Some(1), "neither binary STL nor ASCII STL ('solid')"));
        }
        let mut cur = Vec::new();
        for (i, l) in text.lines().enumerate() {
            let t: Vec<&str> = l.split_whitespace().collect();
            if t.first() == Some(&"vertex") {
                if t.len() != 4 {
                    return Err(parse_err(Some(i + 1), "STL vertex needs 3 coordinates"));
                }
                let v: Result<Vec<f64>, _> = t[1..].iter().map(|s| s.parse::<f64>()).collect();
                let v = v.map_err(|_| parse_err(Some(i + 1), "bad number in STL vertex"))?;
                cur.push(DVec3::new(v[0], v[1], v[2]));
            } else if t.first() == Some(&"endloop") {
                if cur.len() != 3 {
                    return Err(parse_err(Some(i + 1), "STL facet without 3 vertices"));
                }
                tris.push([cur[0], cur[1], cur[2]]);
                cur.clear();
            }
        }
    }
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut faces = Vec::with_capacity(tris.len());
    for t in tris {
        let face = t
            .iter()
            .map(|p| {
                let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
                *index.entry(key).or_insert_with(|| {
                    positions.push(*p);
                    (positions.len() - 1) as u32
                })
            })
            .collect();
        faces.push(face);
    }
    Ok(PolyMesh { positions, faces })
}
