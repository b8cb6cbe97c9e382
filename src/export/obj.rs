//! Wavefront OBJ: meshes, the curve network, the control nets and planar slices. Every point
//! line is written by [`ObjPoint`] (17 significant digits).

use crate::construct::Surface;
use glam::DVec3;
use std::fmt::{self, Write as _};
use std::io::{self, Write};

/// One OBJ point line `tag x y z` (`v` or `vn`), coordinates as `{:.17e}` (round-trip exact).
pub(crate) struct ObjPoint(pub &'static str, pub DVec3);

impl fmt::Display for ObjPoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ObjPoint(tag, p) = self;
        write!(f, "{tag} {:.17e} {:.17e} {:.17e}", p.x, p.y, p.z)
    }
}

/// Polygon faces: `v` lines, then `f` lines with 1-based vertex loops.
pub(crate) fn write_polygons<W: Write>(mut w: W, positions: &[DVec3], faces: &[Vec<u32>]) -> io::Result<()> {
    for &p in positions {
        writeln!(w, "{}", ObjPoint("v", p))?;
    }
    for f in faces {
        write!(w, "f")?;
        for i in f {
            write!(w, " {}", i + 1)?;
        }
        writeln!(w)?;
    }
    w.flush()
}

/// Triangles with normals: optional comment line, `v`, `vn`, then `f a//a b//b c//c` (or
/// `f a b c` when there is not one normal per vertex).
pub(crate) fn write_triangles<W: Write>(
    mut w: W,
    comment: Option<&str>,
    positions: &[DVec3],
    normals: &[DVec3],
    triangles: &[[u32; 3]],
) -> io::Result<()> {
    if let Some(c) = comment {
        writeln!(w, "# {c}")?;
    }
    for &p in positions {
        writeln!(w, "{}", ObjPoint("v", p))?;
    }
    for &n in normals {
        writeln!(w, "{}", ObjPoint("vn", n))?;
    }
    let with_normals = normals.len() == positions.len();
    for t in triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if with_normals {
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
        } else {
            writeln!(w, "f {a} {b} {c}")?;
        }
    }
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
