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
//! all objects and groups into one [`PolyMesh`] in file order, strips `#` comments, joins lines
//! ending in `\`, ignores `vn vt vp g o s usemtl mtllib l p` statements, reads OpenSubdiv's
//! `t crease` and `t corner` tags into [`super::Creases`] (see [`obj_sharpness`]), skips free-form
//! geometry, render attributes and the other `t` tags with a [`MeshWarning::SkippedStatement`]
//! (carried in [`SourceMap::warnings`] to the mesh's warnings), and rejects anything else with
//! [`MeshError::Parse`] naming the line, so a garbage file is an error, never a partial mesh.
//!
//! Faces with holes ([`super::Hole`]) follow the convention of the public polyhedral GB modeller
//! molihua (github.com/salvipeter/molihua: `read-obj` in `molihua.scm`, models such as
//! `models/elretolt-otszog-lyukkal.obj`): a comment line `#h N` after a face line announces that
//! the next N `f` lines are inner loops of that face (listed in the opposite orientation to the
//! outer loop), not faces of their own; other statements may come in between. `#h` must be
//! followed by exactly one count ([`MeshError::Parse`] otherwise, or when it comes before any
//! face); fewer than N `f` lines before the next `#h` or the end of the file give
//! [`MeshError::MissingHoleLoops`] naming the `#h` line; errors about an inner loop name its own
//! `f` line ([`SourceMap::hole_lines`]). Any other `#` line stays a comment.
//!
//! Hostile input. Every reader takes bytes: a UTF-8 byte-order mark is skipped, and UTF-8 is
//! required only where numbers are parsed (names and comments may hold any bytes). A declared
//! count (OFF/PLY element counts, OFF face sizes, PLY list lengths, the binary STL triangle
//! count) never allocates more than the remaining input can hold, and must match the data: a
//! record missing or left over is an error naming the line (or the element, for binary
//! files). [`read_polymesh`] checks the extension and that the path is a regular file before
//! reading, and reads at most [`MAX_INPUT_BYTES`].
//!
//! The writers are in [`crate::export`].

use super::error::{MeshError, MeshWarning, SourceMap};
use super::halfedge::HalfEdgeMesh;
use super::PolyMesh;
#[cfg(doc)]
use crate::limits::MAX_INPUT_BYTES;
use glam::DVec3;
use std::collections::HashMap;

use std::io;
use std::path::Path;

fn parse_err(line: Option<usize>, message: impl Into<String>) -> MeshError {
    MeshError::Parse { line, message: message.into() }
}

fn io_err(path: &Path, e: io::Error) -> MeshError {
    MeshError::Io { path: path.display().to_string(), message: e.to_string() }
}

/// The UTF-8 byte-order mark, skipped at the start of every text format.
const BOM: &[u8] = b"\xEF\xBB\xBF";

fn strip_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(BOM).unwrap_or(bytes)
}

/// The lines of `bytes` (split at `\n`, a trailing `\r` removed) numbered from `first`.
fn lines_from(bytes: &[u8], first: usize) -> impl Iterator<Item = (usize, &[u8])> {
    bytes
        .split(|&b| b == b'\n')
        .enumerate()
        .map(move |(i, l)| (first + i, l.strip_suffix(b"\r").unwrap_or(l)))
}

/// `l` up to its `#` comment.
fn strip_comment(l: &[u8]) -> &[u8] {
    l.iter().position(|&b| b == b'#').map_or(l, |e| &l[..e])
}

/// The part of line `ln` where numbers are parsed, as text: only there UTF-8 is required.
fn text_at(l: &[u8], ln: usize) -> Result<&str, MeshError> {
    std::str::from_utf8(l).map_err(|_| parse_err(Some(ln), "line is not UTF-8 text"))
}

/// Room to reserve for `count` declared items of at least `min_bytes` bytes each when
/// `remaining` bytes of input are left: a declared count never allocates more than the input
/// can hold.
fn reserve(count: usize, remaining: usize, min_bytes: usize) -> usize {
    count.min(remaining / min_bytes.max(1))
}

/// OBJ statements that are skipped with a [`MeshWarning::SkippedStatement`]: free-form geometry
/// and the display/render attributes. (`vn vt vp g o s usemtl mtllib l p` are ignored silently.)
const OBJ_SKIPPED: &[&str] = &[
    "cstype", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp", "end", "deg", "bmat", "step",
    "usemap", "lod", "bevel", "c_interp", "d_interp", "shadow_obj", "trace_obj", "mg", "maplib",
];

/// Counts skipped statements per kind: one warning per kind (first line and count), so a
/// file with millions of them gives a handful of warnings.
#[derive(Default)]
struct Skipped(Vec<(String, usize, usize)>);

impl Skipped {
    fn add(&mut self, statement: String, line: usize) {
        match self.0.iter_mut().find(|(s, _, _)| *s == statement) {
            Some(e) => e.2 += 1,
            None => self.0.push((statement, line, 1)),
        }
    }
    fn into_warnings(self) -> Vec<MeshWarning> {
        self.0
            .into_iter()
            .map(|(statement, line, count)| MeshWarning::SkippedStatement { statement, line, count })
            .collect()
    }
}

/// Parses OBJ (see the module doc). The input is bytes: a UTF-8 byte-order mark is skipped,
/// names and comments may hold any bytes (only `v` and `f` lines must be UTF-8), a line ending in
/// `\` continues on the next one. Indices are checked against the vertex count
/// ([`MeshError::ObjIndexOutOfRange`], naming the index as written, with the line); other checks
/// are left to validation. Skipped statements are listed in [`SourceMap::warnings`].
pub fn parse_obj(input: impl AsRef<[u8]>) -> Result<(PolyMesh, SourceMap), MeshError> {
    let bytes = strip_bom(input.as_ref());
    let mut positions = Vec::new();
    // Per face: the indices as written, the line and the number of vertices above it.
    let mut raw_faces: Vec<(Vec<i64>, usize, usize)> = Vec::new();
    let mut map = SourceMap { vertex_base: 1, ..SourceMap::default() };
    let mut skipped = Skipped::default();
    let mut tags: Vec<ObjTag> = Vec::new();
    let mut lines = lines_from(bytes, 1);
    let mut joined: Vec<u8> = Vec::new();
    // Holes (molihua's convention, see the module doc): per inner loop the indices as written,
    // the line, the vertices above it and the face it belongs to; the open `#h` announcement.
    let mut raw_holes: Vec<(Vec<i64>, usize, usize, usize)> = Vec::new();
    let mut pending_holes: Option<PendingHoles> = None;
    while let Some((ln, physical)) = lines.next() {
        if let Some(rest) = physical.trim_ascii_start().strip_prefix(b"#h") {
            if rest.first().is_none_or(|b| b.is_ascii_whitespace()) {
                if let Some(p) = pending_holes.take().filter(|p| p.remaining > 0) {
                    return Err(p.missing());
                }
                let toks: Vec<&str> = text_at(rest, ln)?.split_whitespace().collect();
                let [count] = toks.as_slice() else {
                    return Err(parse_err(Some(ln), "`#h` needs exactly one count (the number of hole loops that follow)"));
                };
                let declared: usize = count
                    .parse()
                    .map_err(|_| parse_err(Some(ln), format!("bad hole count {count:?} after `#h`")))?;
                if declared > 0 && raw_faces.is_empty() {
                    return Err(parse_err(Some(ln), "`#h` before any face (the holes belong to the face above)"));
                }
                pending_holes = Some(PendingHoles { face: raw_faces.len().saturating_sub(1), declared, remaining: declared, line: ln });
                continue;
            }
        }
        let mut content = strip_comment(physical);
        if content.trim_ascii_end().ends_with(b"\\") {
            // Backslash continuation: join the physical lines (each without its comment).
            joined.clear();
            let mut cur = content;
            loop {
                let t = cur.trim_ascii_end();
                match t.strip_suffix(b"\\") {
                    Some(head) => {
                        joined.extend_from_slice(head);
                        joined.push(b' ');
                        match lines.next() {
                            Some((_, next)) => cur = strip_comment(next),
                            None => break,
                        }
                    }
                    None => {
                        joined.extend_from_slice(cur);
                        break;
                    }
                }
            }
            content = &joined;
        }
        let mut toks = content.split(|b| b.is_ascii_whitespace()).filter(|t| !t.is_empty());
        let Some(kw) = toks.next() else { continue };
        match kw {
            b"v" => {
                let vals: Vec<&str> = text_at(content, ln)?.split_whitespace().skip(1).collect();
                if vals.len() < 3 {
                    return Err(parse_err(Some(ln), format!("vertex needs 3 coordinates, found {}", vals.len())));
                }
                let mut xyz = [0.0; 3];
                for (i, t) in vals.iter().enumerate() {
                    let x: f64 = t.parse().map_err(|_| parse_err(Some(ln), format!("bad number {t:?} in vertex")))?;
                    if i < 3 {
                        xyz[i] = x;
                    }
                }
                positions.push(DVec3::from_array(xyz));
                map.vertex_lines.push(ln);
            }
            b"f" => {
                let mut idx = Vec::new();
                for t in text_at(content, ln)?.split_whitespace().skip(1) {
                    let first = t.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| parse_err(Some(ln), format!("bad vertex index {t:?} in face")))?;
                    if i == 0 {
                        return Err(parse_err(Some(ln), "vertex index 0 in face (OBJ is 1-based)"));
                    }
                    idx.push(i);
                }
                match pending_holes.as_mut() {
                    Some(p) if p.remaining > 0 => {
                        p.remaining -= 1;
                        raw_holes.push((idx, ln, positions.len(), p.face));
                        map.hole_lines.push(ln);
                    }
                    _ => {
                        raw_faces.push((idx, ln, positions.len()));
                        map.face_lines.push(ln);
                    }
                }
            }
            b"vn" | b"vt" | b"vp" | b"g" | b"o" | b"s" | b"usemtl" | b"mtllib" | b"l" | b"p" => {}
            b"t" => {
                let tag = toks.next().unwrap_or(b"");
                match tag {
                    b"crease" | b"corner" => {
                        parse_obj_tag(tag == b"crease", text_at(content, ln)?, ln, &mut tags)?;
                    }
                    _ => skipped.add(format!("t {}", String::from_utf8_lossy(tag)), ln),
                }
            }
            kw => {
                let kw = String::from_utf8_lossy(kw);
                if OBJ_SKIPPED.contains(&kw.as_ref()) {
                    skipped.add(kw.into_owned(), ln);
                } else {
                    return Err(parse_err(Some(ln), format!("unknown statement {kw:?}")));
                }
            }
        }
    }
    let nv = positions.len();
    let mut faces = Vec::with_capacity(raw_faces.len());
    for (f, (idx, ln, above)) in raw_faces.into_iter().enumerate() {
        let mut face = Vec::with_capacity(idx.len());
        for (c, &i) in idx.iter().enumerate() {
            // 1-based from the start, or negative relative to the `above` vertices read so far.
            let (i0, available) = if i > 0 { (i - 1, nv) } else { (above as i64 + i, above) };
            if i0 < 0 || i0 as usize >= available || i0 >= u32::MAX as i64 {
                return Err(MeshError::ObjIndexOutOfRange { face: f, corner: c, index: i, available, line: Some(ln) });
            }
            face.push(i0 as u32);
        }
        faces.push(face);
    }
    if let Some(p) = pending_holes.filter(|p| p.remaining > 0) {
        return Err(p.missing());
    }
    let mut holes = Vec::with_capacity(raw_holes.len());
    for (idx, ln, above, face) in raw_holes {
        let mut lp = Vec::with_capacity(idx.len());
        for (c, &i) in idx.iter().enumerate() {
            let (i0, available) = if i > 0 { (i - 1, nv) } else { (above as i64 + i, above) };
            if i0 < 0 || i0 as usize >= available || i0 >= u32::MAX as i64 {
                return Err(MeshError::ObjIndexOutOfRange { face, corner: c, index: i, available, line: Some(ln) });
            }
            lp.push(i0 as u32);
        }
        holes.push(super::Hole { face: face as u32, vertices: lp });
    }
    map.warnings = skipped.into_warnings();
    let mut mesh = PolyMesh::new(positions, faces);
    mesh.holes = holes;
    for tag in tags {
        if let Some(&v) = tag.vertices.iter().find(|&&v| v >= nv as u64) {
            return Err(parse_err(Some(tag.line), format!("vertex index {v} out of range (0..{nv}; tags are 0-based)")));
        }
        let c = tag.sharpness;
        if tag.edge {
            mesh.creases.edges.push(([tag.vertices[0] as u32, tag.vertices[1] as u32], c));
            map.edge_crease_lines.push(tag.line);
        } else {
            mesh.creases.vertices.push((tag.vertices[0] as u32, c));
            map.vertex_crease_lines.push(tag.line);
        }
    }
    Ok((mesh, map))
}

/// An OBJ `#h N` announcement whose `f` lines are still being read.
struct PendingHoles {
    face: usize,
    declared: usize,
    remaining: usize,
    line: usize,
}

impl PendingHoles {
    fn missing(&self) -> MeshError {
        MeshError::MissingHoleLoops { face: self.face, declared: self.declared, found: self.declared - self.remaining, line: self.line }
    }
}

/// One edge (`t crease`) or vertex (`t corner`) sharpness read from an OBJ tag line.
struct ObjTag {
    edge: bool,
    vertices: Vec<u64>,
    /// Sharpness mapped to [0, 1] by [`obj_sharpness`].
    sharpness: f64,
    line: usize,
}

/// OpenSubdiv sharpness s ≥ 0 (≥ 10 infinitely sharp) as the crease c ∈ [0, 1] of
/// [`super::Creases`]: c = sqrt(min(s, 10)/10), the inverse of Blender's s = 10·c².
pub fn obj_sharpness(s: f64) -> f64 {
    (s.min(10.0) / 10.0).sqrt()
}

/// Parses the arguments of `t crease N/F/0 v0 v1 … s…` (N even ≥ 2: vertex pairs, one edge each)
/// or `t corner N/F/0 v… s…` (N ≥ 1: one vertex each) in OpenSubdiv's tag syntax (0-based vertex
/// indices): F = 1 gives every element the same sharpness, F = N/2 (crease) or N (corner) one
/// each. Sharpness must be a finite number ≥ 0 and is mapped by [`obj_sharpness`]. Index range is
/// checked once all vertices are read.
fn parse_obj_tag(edge: bool, text: &str, ln: usize, out: &mut Vec<ObjTag>) -> Result<(), MeshError> {
    let name = if edge { "t crease" } else { "t corner" };
    let err = |m: String| parse_err(Some(ln), format!("{name}: {m}"));
    let args: Vec<&str> = text.split_whitespace().skip(2).collect();
    let counts = args.first().ok_or_else(|| err("missing the argument counts (e.g. 2/1/0)".into()))?;
    let n: Vec<usize> = counts
        .split('/')
        .map(|t| t.parse::<usize>())
        .collect::<Result<_, _>>()
        .map_err(|_| err(format!("bad argument counts {counts:?} (expected ints/floats/strings, e.g. 2/1/0)")))?;
    let [ni, nf, ns] = n[..] else {
        return Err(err(format!("bad argument counts {counts:?} (expected ints/floats/strings, e.g. 2/1/0)")));
    };
    let per = if edge { 2 } else { 1 };
    let elems = ni / per;
    if ni == 0 || ni % per != 0 || ns != 0 || !(nf == 1 || nf == elems) {
        return Err(err(format!(
            "unsupported argument counts {counts:?} ({} vertex indices, then 1 or one sharpness per {})",
            if edge { "pairs of" } else { "one or more" },
            if edge { "edge" } else { "vertex" }
        )));
    }
    if args.len() != 1 + ni + nf {
        return Err(err(format!("expected {} arguments after {counts}, found {}", ni + nf, args.len() - 1)));
    }
    let idx: Vec<u64> = args[1..=ni]
        .iter()
        .map(|t| t.parse::<u64>().map_err(|_| err(format!("bad vertex index {t:?}"))))
        .collect::<Result<_, _>>()?;
    let sharp: Vec<f64> = args[1 + ni..]
        .iter()
        .map(|t| match t.parse::<f64>() {
            Ok(s) if s.is_finite() && s >= 0.0 => Ok(s),
            _ => Err(err(format!("sharpness {t:?} is not a finite number >= 0"))),
        })
        .collect::<Result<_, _>>()?;
    for k in 0..elems {
        let s = if nf == 1 { sharp[0] } else { sharp[k] };
        out.push(ObjTag { edge, vertices: idx[k * per..(k + 1) * per].to_vec(), sharpness: obj_sharpness(s), line: ln });
    }
    Ok(())
}

/// Parses ASCII OFF (`OFF`, counts, vertices, faces `n i0 … i(n−1)`; `#` comments; colours after
/// the indices ignored). The counts must match the data: a missing or an extra face (or vertex)
/// is an error naming the line.
pub fn parse_off(input: impl AsRef<[u8]>) -> Result<(PolyMesh, SourceMap), MeshError> {
    let bytes = strip_bom(input.as_ref());
    let mut lines = lines_from(bytes, 1)
        .map(|(ln, l)| (ln, strip_comment(l).trim_ascii()))
        .filter(|(_, l)| !l.is_empty());
    // The next line, or an error on line `blame` (the line whose count promised more).
    let mut next = |blame: usize, what: &dyn Fn() -> String| -> Result<(usize, &str), MeshError> {
        let (ln, l) = lines.next().ok_or_else(|| parse_err(Some(blame), what()))?;
        Ok((ln, text_at(l, ln)?))
    };
    let (ln, head) = next(1, &|| "empty OFF file (no header)".into())?;
    let mut head_toks: Vec<&str> = head.split_whitespace().collect();
    if head_toks.first().map(|t| t.ends_with("OFF")) != Some(true) {
        return Err(parse_err(Some(ln), "missing OFF header"));
    }
    head_toks.remove(0);
    let (counts_ln, counts_toks): (usize, Vec<&str>) = if head_toks.is_empty() {
        let (ln, l) = next(ln, &|| "missing OFF counts after the header".into())?;
        (ln, l.split_whitespace().collect())
    } else {
        (ln, head_toks)
    };
    if counts_toks.len() < 2 {
        return Err(parse_err(Some(counts_ln), "OFF counts need vertex and face numbers"));
    }
    let cnt = |k: usize| -> Result<usize, MeshError> {
        counts_toks[k]
            .parse()
            .map_err(|_| parse_err(Some(counts_ln), format!("bad OFF count {:?}", counts_toks[k])))
    };
    let (nv, nf) = (cnt(0)?, cnt(1)?);
    let mut map = SourceMap::default();
    // A vertex line has at least 6 bytes ("0 0 0\n"), a face line at least 2.
    let mut positions = Vec::with_capacity(reserve(nv, bytes.len(), 6));
    for v in 0..nv {
        let (ln, l) = next(counts_ln, &|| format!("OFF file ends after {v} of the {nv} vertices declared here"))?;
        let vals: Result<Vec<f64>, _> = l.split_whitespace().take(3).map(str::parse::<f64>).collect();
        let vals = vals.map_err(|_| parse_err(Some(ln), "bad number in OFF vertex"))?;
        if vals.len() < 3 {
            return Err(parse_err(Some(ln), "OFF vertex needs 3 coordinates"));
        }
        positions.push(DVec3::new(vals[0], vals[1], vals[2]));
        map.vertex_lines.push(ln);
    }
    let mut faces = Vec::with_capacity(reserve(nf, bytes.len(), 2));
    for f in 0..nf {
        let (ln, l) = next(counts_ln, &|| format!("OFF file ends after {f} of the {nf} faces declared here"))?;
        let toks: Vec<&str> = l.split_whitespace().collect();
        let t0 = toks.first().copied().unwrap_or("");
        let n: usize = t0.parse().map_err(|_| parse_err(Some(ln), format!("bad OFF face size {t0:?}")))?;
        if toks.len() - 1 < n {
            return Err(parse_err(
                Some(ln),
                format!("OFF face announces {n} indices but has {}", toks.len() - 1),
            ));
        }
        let mut face = Vec::with_capacity(n);
        for (c, t) in toks[1..=n].iter().enumerate() {
            let i: i64 = t.parse().map_err(|_| parse_err(Some(ln), format!("bad OFF vertex index {t:?}")))?;
            if i < 0 || i as usize >= nv || i >= u32::MAX as i64 {
                return Err(MeshError::IndexOutOfRange { face: f, corner: c, index: i, n_vertices: nv, line: Some(ln) });
            }
            face.push(i as u32);
        }
        faces.push(face);
        map.face_lines.push(ln);
    }
    if let Some((ln, _)) = lines.next() {
        return Err(parse_err(
            Some(ln),
            format!("data after the {nf} faces declared on line {counts_ln} (the face count is too low)"),
        ));
    }
    Ok((PolyMesh::new(positions, faces), map))
}

/// Parses mesh file contents in the format named by `ext` (`obj`, `off`, `ply`, `stl`, any
/// case), as [`read_polymesh`] does after reading the file.
pub fn parse_mesh_bytes(bytes: &[u8], ext: &str) -> Result<(PolyMesh, SourceMap), MeshError> {
    match ext.to_ascii_lowercase().as_str() {
        "obj" => parse_obj(bytes),
        "off" => parse_off(bytes),
        "ply" => parse_ply(bytes),
        "stl" => parse_stl(bytes).map(|m| (m, SourceMap::default())),
        _ => Err(parse_err(None, format!("unknown mesh file extension {ext:?}"))),
    }
}

/// Reads a mesh file without validating its topology (dispatch on the extension; see the
/// module doc). Returns the line numbers of elements for text formats (empty for binary ones)
/// and the reader's warnings. The extension is checked first, then that the path is a regular
/// file (not a device or FIFO); at most [`MAX_INPUT_BYTES`] are read
/// ([`MeshError::InputTooLarge`] beyond).
pub fn read_polymesh(path: impl AsRef<Path>) -> Result<(PolyMesh, SourceMap), MeshError> {
    let path = path.as_ref();
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    if !matches!(ext.as_str(), "obj" | "off" | "ply" | "stl") {
        return Err(parse_err(None, format!("unknown mesh file extension {ext:?} of {}", path.display())));
    }
    let bytes = read_input_bytes(path)?;
    parse_mesh_bytes(&bytes, &ext)
}

/// The bytes of an input file: it must be a regular file (not a device or FIFO), and at most
/// [`MAX_INPUT_BYTES`] are read ([`MeshError::InputTooLarge`] beyond). Every reader of a user's
/// input file goes through this (meshes here, point lists and grids of the command line).
pub fn read_input_bytes(path: impl AsRef<Path>) -> Result<Vec<u8>, MeshError> {
    let path = path.as_ref();
    crate::input::read_input(path).map_err(|e| match e {
        crate::input::InputError::NotAFile { path } => MeshError::NotAFile { path },
        crate::input::InputError::TooLarge { path, limit } => MeshError::InputTooLarge { path, limit },
        crate::input::InputError::Io { source, .. } => io_err(path, source),
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
    /// Header line declaring the element.
    line: usize,
}

impl PlyElement {
    /// Smallest size of one binary record (a list counts its length field only).
    fn min_bytes(&self) -> usize {
        self.props.iter().map(|p| p.list.unwrap_or(p.ty).size()).sum()
    }
}

/// A PLY list length or vertex index as an integer, or an error naming the value (`what` names
/// it, with the element when there is no line).
fn ply_int(x: f64, line: Option<usize>, what: impl FnOnce() -> String) -> Result<usize, MeshError> {
    if x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= u32::MAX as f64 {
        Ok(x as usize)
    } else {
        Err(parse_err(line, format!("{} {x} is not a non-negative integer", what())))
    }
}

/// Reads PLY (ASCII or binary little-endian): `vertex` x/y/z and `face` `vertex_indices` (or
/// `vertex_index`); other elements and properties are skipped. Element counts must match the
/// data (a record missing or left over is an error naming the element); indices and list
/// lengths must be integers.
pub fn parse_ply(bytes: &[u8]) -> Result<(PolyMesh, SourceMap), MeshError> {
    let bytes = strip_bom(bytes);
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
    let mut last_ln = 1;
    loop {
        let (ln, l) = next_line(&mut pos)
            .ok_or_else(|| parse_err(Some(last_ln), "PLY header ends without end_header"))?;
        last_ln = ln;
        let t: Vec<&str> = l.split_whitespace().collect();
        match t.as_slice() {
            ["format", "ascii", _] => binary = Some(false),
            ["format", "binary_little_endian", _] => binary = Some(true),
            ["format", f, ..] => return Err(parse_err(Some(ln), format!("unsupported PLY format {f}"))),
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => elements.push(PlyElement {
                name: name.to_string(),
                count: count.parse().map_err(|_| parse_err(Some(ln), format!("bad element count {count:?}")))?,
                props: Vec::new(),
                line: ln,
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
    let binary = binary.ok_or_else(|| parse_err(Some(last_ln), "PLY header has no format line"))?;
    let mut map = SourceMap::default();
    // ASCII body: the non-empty lines with their numbers.
    let mut ascii_lines = (!binary).then(|| {
        lines_from(&bytes[pos..], line_no + 1).filter(|(_, l)| !l.trim_ascii().is_empty())
    });
    // Check every declared count against the data before reading (and allocating) anything.
    let mut remaining = bytes.len() - pos;
    for el in &elements {
        let has = |n: &str| el.props.iter().any(|p| p.name == n);
        if el.count > 0 && el.name == "vertex" && !(has("x") && has("y") && has("z")) {
            return Err(parse_err(Some(el.line), "PLY vertex without x/y/z"));
        }
        let is_index = |p: &PlyProp| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index");
        if el.count > 0 && el.name == "face" && !el.props.iter().any(is_index) {
            return Err(parse_err(Some(el.line), "PLY face without vertex_indices"));
        }
        if el.props.is_empty() {
            continue; // empty records: nothing to read
        }
        // An ASCII record takes at least 2 bytes ("0\n").
        let need = if binary { el.min_bytes() as u128 } else { 2 };
        let total = need * el.count as u128;
        if total > remaining as u128 {
            return Err(parse_err(
                Some(el.line),
                format!(
                    "PLY element '{}' declares {} records (at least {total} bytes) but only {remaining} bytes remain",
                    el.name, el.count
                ),
            ));
        }
        remaining -= total as usize;
    }
    let n_vertices = elements.iter().find(|e| e.name == "vertex").map_or(0, |e| e.count);
    let mut positions = Vec::with_capacity(n_vertices);
    let mut raw_faces: Vec<(Vec<f64>, Option<usize>)> = Vec::new();
    for el in &elements {
        let xyz: Vec<Option<usize>> =
            ["x", "y", "z"].iter().map(|n| el.props.iter().position(|p| p.name == *n)).collect();
        let fidx = el.props.iter().position(|p| {
            p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index")
        });
        if el.props.is_empty() {
            continue;
        }
        if el.name == "face" {
            raw_faces.reserve(el.count);
        }
        let ends = |r: usize| {
            parse_err(
                Some(el.line),
                format!("PLY file ends in element '{}' record {r} of the {} declared here", el.name, el.count),
            )
        };
        for r in 0..el.count {
            let mut rec: Vec<Vec<f64>> = Vec::with_capacity(el.props.len());
            let mut rec_line = None;
            if let Some(lines) = ascii_lines.as_mut() {
                let (ln, l) = lines.next().ok_or_else(|| ends(r))?;
                rec_line = Some(ln);
                let l = text_at(l, ln)?;
                let mut toks = l.split_whitespace();
                let num = |toks: &mut std::str::SplitWhitespace| -> Result<f64, MeshError> {
                    let t = toks.next().ok_or_else(|| parse_err(Some(ln), "too few values"))?;
                    t.parse::<f64>().map_err(|_| parse_err(Some(ln), format!("bad number {t:?}")))
                };
                for p in &el.props {
                    if p.list.is_some() {
                        let n = ply_int(num(&mut toks)?, Some(ln), || format!("{} list length", p.name))?;
                        let mut v = Vec::with_capacity(reserve(n, l.len(), 2));
                        for _ in 0..n {
                            v.push(num(&mut toks)?);
                        }
                        rec.push(v);
                    } else {
                        rec.push(vec![num(&mut toks)?]);
                    }
                }
                if toks.next().is_some() {
                    return Err(parse_err(Some(ln), format!("more values than the properties of PLY element '{}'", el.name)));
                }
            } else {
                let mut take = |n: usize| -> Result<&[u8], MeshError> {
                    let s = bytes.get(pos..pos + n).ok_or_else(|| ends(r))?;
                    pos += n;
                    Ok(s)
                };
                for p in &el.props {
                    if let Some(ct) = p.list {
                        let n = ply_int(ct.read_le(take(ct.size())?), None, || {
                            format!("{} record {r}: {} list length", el.name, p.name)
                        })?;
                        let data = take(n.checked_mul(p.ty.size()).ok_or_else(|| ends(r))?)?;
                        rec.push(data.chunks_exact(p.ty.size()).map(|c| p.ty.read_le(c)).collect());
                    } else {
                        rec.push(vec![p.ty.read_le(take(p.ty.size())?)]);
                    }
                }
            }
            if el.name == "vertex" {
                let mut c = [0.0; 3];
                for (k, i) in xyz.iter().enumerate() {
                    let i = i.unwrap_or(0);
                    c[k] = rec[i]
                        .first()
                        .copied()
                        .ok_or_else(|| parse_err(rec_line, format!("PLY vertex {r}: coordinate list is empty")))?;
                }
                positions.push(DVec3::from_array(c));
                if let Some(l) = rec_line {
                    map.vertex_lines.push(l);
                }
            } else if el.name == "face" {
                let i = fidx.unwrap_or(0);
                raw_faces.push((std::mem::take(&mut rec[i]), rec_line));
                if let Some(l) = rec_line {
                    map.face_lines.push(l);
                }
            }
        }
    }
    if let Some((ln, _)) = ascii_lines.as_mut().and_then(|l| l.next()) {
        return Err(parse_err(Some(ln), "data after the last PLY element (an element count is too low)"));
    }
    if binary && pos < bytes.len() {
        return Err(parse_err(
            None,
            format!("{} bytes after the last PLY element (an element count is too low)", bytes.len() - pos),
        ));
    }
    let nv = positions.len();
    let mut faces = Vec::with_capacity(raw_faces.len());
    for (f, (idx, ln)) in raw_faces.into_iter().enumerate() {
        let mut face = Vec::with_capacity(idx.len());
        for (c, &x) in idx.iter().enumerate() {
            let i = ply_int(x, ln, || format!("face {f} corner {c}: vertex index"))?;
            if i >= nv {
                return Err(MeshError::IndexOutOfRange { face: f, corner: c, index: i as i64, n_vertices: nv, line: ln });
            }
            face.push(i as u32);
        }
        faces.push(face);
    }
    Ok((PolyMesh::new(positions, faces), map))
}

// ---------------------------------------------------------------- STL reading

/// Reads STL, binary or ASCII. Binary when the size matches the layout its triangle count
/// announces (84 + 50·count bytes); ASCII when the file (after an optional byte-order mark and
/// blank space) starts with `solid` and is text, read by a strict grammar (`solid`, then
/// `facet … outer loop`, three `vertex x y z`, `endloop`, `endfacet`, then `endsolid`), so a
/// truncated file is an error naming the line. Any other file of at least 84 bytes is a binary
/// STL whose size disagrees with its count: an error naming both.
///
/// Corners with the same position are welded into one vertex (by value: −0.0 equals 0.0).
pub fn parse_stl(bytes: &[u8]) -> Result<PolyMesh, MeshError> {
    let announced = (bytes.len() >= 84).then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64);
    let expected = announced.map(|n| 84 + 50 * n);
    let tris = if expected == Some(bytes.len() as u64) {
        let mut tris = Vec::with_capacity((bytes.len() - 84) / 50);
        for rec in bytes[84..].chunks_exact(50) {
            let f = |o: usize| f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]) as f64;
            let corner = |k: usize| DVec3::new(f(12 + 12 * k), f(16 + 12 * k), f(20 + 12 * k));
            tris.push([corner(0), corner(1), corner(2)]);
        }
        tris
    } else {
        let text = strip_bom(bytes).trim_ascii_start();
        let is_text = !text.contains(&0) && std::str::from_utf8(text).is_ok();
        match (text.starts_with(b"solid") && is_text, announced, expected) {
            (true, _, _) => parse_stl_ascii(bytes)?,
            (false, Some(n), Some(e)) => {
                return Err(parse_err(
                    None,
                    format!("binary STL: expected {e} bytes for {n} triangles, got {}", bytes.len()),
                ))
            }
            _ => {
                return Err(parse_err(
                    Some(1),
                    format!("neither ASCII STL ('solid') nor binary STL (84-byte header; the file has {} bytes)", bytes.len()),
                ))
            }
        }
    };
    let mut index: HashMap<[u64; 3], u32> = HashMap::with_capacity(tris.len() / 2 + 1);
    let mut positions = Vec::new();
    let mut faces = Vec::with_capacity(tris.len());
    for t in tris {
        let face = t
            .iter()
            .map(|p| {
                // `+ 0.0` turns −0.0 into 0.0 (and changes nothing else).
                let key = [(p.x + 0.0).to_bits(), (p.y + 0.0).to_bits(), (p.z + 0.0).to_bits()];
                *index.entry(key).or_insert_with(|| {
                    positions.push(*p + DVec3::ZERO);
                    (positions.len() - 1) as u32
                })
            })
            .collect();
        faces.push(face);
    }
    Ok(PolyMesh::new(positions, faces))
}

/// The triangles of an ASCII STL (see [`parse_stl`]); every error names its line.
fn parse_stl_ascii(bytes: &[u8]) -> Result<Vec<[DVec3; 3]>, MeshError> {
    #[derive(PartialEq)]
    enum State {
        /// Before `solid` or after `endsolid`.
        Outside,
        /// Inside a solid, between facets.
        Solid,
        /// After `facet`.
        Facet,
        /// After `outer loop`, with the vertices read so far.
        Loop,
        /// After `endloop`.
        EndLoop,
    }
    let mut state = State::Outside;
    let mut tris = Vec::new();
    let mut cur: Vec<DVec3> = Vec::with_capacity(3);
    let (mut facet_line, mut solid_line, mut last) = (0, 0, 0);
    for (ln, l) in lines_from(strip_bom(bytes), 1) {
        let l = text_at(l, ln)?;
        let t: Vec<&str> = l.split_whitespace().collect();
        let Some(&kw) = t.first() else { continue };
        last = ln;
        let unexpected = || parse_err(Some(ln), format!("unexpected {kw:?} in ASCII STL"));
        match (kw, &state) {
            ("solid", State::Outside) => {
                state = State::Solid;
                solid_line = ln;
            }
            ("facet", State::Solid) => {
                state = State::Facet;
                facet_line = ln;
            }
            ("outer", State::Facet) => {
                state = State::Loop;
                cur.clear();
            }
            ("vertex", State::Loop) => {
                if t.len() != 4 {
                    return Err(parse_err(Some(ln), "STL vertex needs 3 coordinates"));
                }
                if cur.len() == 3 {
                    return Err(parse_err(Some(ln), "STL facet with more than 3 vertices"));
                }
                let v: Result<Vec<f64>, _> = t[1..].iter().map(|s| s.parse::<f64>()).collect();
                let v = v.map_err(|_| parse_err(Some(ln), "bad number in STL vertex"))?;
                cur.push(DVec3::new(v[0], v[1], v[2]));
            }
            ("endloop", State::Loop) => {
                if cur.len() != 3 {
                    return Err(parse_err(Some(ln), "STL facet without 3 vertices"));
                }
                tris.push([cur[0], cur[1], cur[2]]);
                state = State::EndLoop;
            }
            ("endfacet", State::EndLoop) => state = State::Solid,
            ("endsolid", State::Solid) => state = State::Outside,
            _ => return Err(unexpected()),
        }
    }
    match state {
        State::Outside => Ok(tris),
        State::Solid => Err(parse_err(
            Some(last),
            format!("ASCII STL ends without endsolid (solid opened on line {solid_line})"),
        )),
        _ => Err(parse_err(
            Some(last),
            format!("ASCII STL ends inside the facet of line {facet_line} (truncated file)"),
        )),
    }
}
