//! Wavefront OBJ: meshes, the curve network, the control nets and planar slices. Every point
//! line is `tag x y z` with each coordinate as the shortest decimal text that parses back to the
//! same `f64` ([`push_point`], [`ObjPoint`]: round-trip exact).

use super::encode::{push_f64, push_int, write_chunks};
use crate::construct::Surface;
use glam::DVec3;
use std::fmt::{self, Write as _};
use std::io::{self, Write};

/// Appends the OBJ point line `tag x y z\n` (`v` or `vn`), coordinates as the shortest
/// round-trip decimal text ([`push_f64`]).
pub(crate) fn push_point(buf: &mut Vec<u8>, tag: &str, p: DVec3) {
    buf.extend_from_slice(tag.as_bytes());
    for c in p.to_array() {
        buf.push(b' ');
        push_f64(buf, c);
    }
    buf.push(b'\n');
}

/// One OBJ point line `tag x y z` (`v` or `vn`), without the newline, as [`push_point`] writes it.
pub(crate) struct ObjPoint(pub &'static str, pub DVec3);

impl fmt::Display for ObjPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ObjPoint(tag, p) = self;
        let mut buf = Vec::with_capacity(80);
        push_point(&mut buf, tag, *p);
        buf.pop();
        f.write_str(std::str::from_utf8(&buf).map_err(|_| fmt::Error)?)
    }
}

/// Point lines `tag x y z` for every point, encoded in parallel chunks.
fn write_points<W: Write + ?Sized>(w: &mut W, tag: &str, points: &[DVec3]) -> io::Result<()> {
    write_chunks(w, points.len(), |r, buf| {
        buf.reserve(r.len() * 64);
        for &p in &points[r] {
            push_point(buf, tag, p);
        }
        Ok(())
    })
}

/// Polygon faces: `v` lines, then `f` lines with 1-based vertex loops.
pub(crate) fn write_polygons<W: Write>(mut w: W, positions: &[DVec3], faces: &[Vec<u32>]) -> io::Result<()> {
    write_points(&mut w, "v", positions)?;
    write_chunks(&mut w, faces.len(), |r, buf| {
        for f in &faces[r] {
            buf.push(b'f');
            for &i in f {
                buf.push(b' ');
                push_int(buf, u64::from(i) + 1);
            }
            buf.push(b'\n');
        }
        Ok(())
    })?;
    w.flush()
}

/// Triangles (or quads, N = 4) with normals: optional comment line, `v`, `vn`, then
/// `f a//a b//b c//c` (or `f a b c` when there is not one normal per vertex).
pub(crate) fn write_triangles<W: Write, const N: usize>(
    mut w: W,
    comment: Option<&str>,
    positions: &[DVec3],
    normals: &[DVec3],
    triangles: &[[u32; N]],
) -> io::Result<()> {
    if let Some(c) = comment {
        writeln!(w, "# {c}")?;
    }
    write_points(&mut w, "v", positions)?;
    write_points(&mut w, "vn", normals)?;
    let with_normals = normals.len() == positions.len();
    write_chunks(&mut w, triangles.len(), |r, buf| {
        buf.reserve(r.len() * N * if with_normals { 16 } else { 8 });
        for t in &triangles[r] {
            buf.push(b'f');
            for i in t {
                let i = u64::from(*i) + 1;
                buf.push(b' ');
                push_int(buf, i);
                if with_normals {
                    buf.extend_from_slice(b"//");
                    push_int(buf, i);
                }
            }
            buf.push(b'\n');
        }
        Ok(())
    })?;
    w.flush()
}

/// The curve network as Wavefront OBJ: every boundary curve once, as the polyline of its Bézier
/// control points (`v` lines, then one `l` line per curve, in [`Surface::curves`] order; object
/// `curve_<k>`). The curves are exact: the control polygon, not a sampling.
pub fn curves_obj(surface: &Surface) -> String {
    let mut out = String::from("# gbsurf curve network: Bézier control polygons, one l line per curve\n");
    let mut base = 1usize;
    for (k, c) in surface.curves.iter().enumerate() {
        let _ = writeln!(out, "o curve_{k}");
        for &p in c {
            let _ = writeln!(out, "{}", ObjPoint("v", p));
        }
        let idx: Vec<String> = (base..base + c.len()).map(|x| x.to_string()).collect();
        if idx.len() >= 2 {
            let _ = writeln!(out, "l {}", idx.join(" "));
        }
        base += c.len();
    }
    out
}

/// The control nets of every patch as Wavefront OBJ, from [`Surface::control_net`] (the one
/// builder of the net, which the C ABI and the adapters show too): all control points as `v`
/// lines, then per patch an object `patch_<p>` with the quads between consecutive ribbon rows as
/// `f` lines and the lines that bound no face (one-row ribbons, the spokes to a GB patch's
/// central point) as `l` lines.
pub fn nets_obj(surface: &Surface) -> String {
    let net = surface.control_net();
    let mut out = String::from("# gbsurf control nets: quads between ribbon rows, lines for one-row ribbons and centre spokes\n");
    for &p in &net.positions {
        let _ = writeln!(out, "{}", ObjPoint("v", p));
    }
    let mut per_patch: Vec<Vec<String>> = vec![Vec::new(); surface.patches.len()];
    let mut corners = net.face_indices.iter();
    for &size in &net.face_sizes {
        let face: Vec<u32> = corners.by_ref().take(size as usize).copied().collect();
        if let Some(&first) = face.first() {
            let idx: Vec<String> = face.iter().map(|v| (v + 1).to_string()).collect();
            per_patch[net.patch[first as usize] as usize].push(format!("f {}", idx.join(" ")));
        }
    }
    for &[a, b] in &net.edges {
        per_patch[net.patch[a as usize] as usize].push(format!("l {} {}", a + 1, b + 1));
    }
    for (p, elements) in per_patch.iter().enumerate() {
        let _ = writeln!(out, "o patch_{p}");
        for e in elements {
            let _ = writeln!(out, "{e}");
        }
    }
    out
}

/// Planar slices ([`crate::quality::slices`]) as OBJ: a `g slice_K` group per plane with its
/// offset `d` along the normal as a comment, each polyline as one `l` line.
pub fn slices_obj(cuts: &[(f64, Vec<crate::quality::Polyline>)]) -> String {
    let mut out = String::from("# gbsurf planar slices: one group per plane (offset d along the normal)\n");
    let mut next = 1usize;
    for (k, (d, lines)) in cuts.iter().enumerate() {
        let _ = writeln!(out, "g slice_{k}\n# d = {d:.17e}");
        for line in lines {
            for &p in &line.points {
                let _ = writeln!(out, "{}", ObjPoint("v", p));
            }
            let ids: Vec<String> = (next..next + line.points.len()).map(|i| i.to_string()).collect();
            let _ = writeln!(out, "l {}", ids.join(" "));
            next += line.points.len();
        }
    }
    out
}
