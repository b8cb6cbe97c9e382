//! Geometry derived from a [`Surface`] for display: the control nets of all patches as one
//! polygon mesh, and the curve network as chains of cubic Bézier segments. The adapters (C ABI,
//! C++/OpenMesh, Blender) copy these; none of them builds its own.

use super::surface::{Patch, Surface};
use crate::bezier::reduce::{error_bound, hermite_cubic};
use crate::bezier::BezierCurve;
use glam::DVec3;

/// The control nets of all patches as one mesh.
///
/// Vertices, patch by patch: for each ribbon (side order) its control points row by row
/// (`rows[k][j]`, row 0 on the boundary), then, for a GB patch, its central control point.
/// Faces: the quads between consecutive rows of a ribbon, (k, j), (k, j+1), (k+1, j+1), (k+1, j).
/// Edges (lines that bound no face): the control polygon of a one-row ribbon, and for a GB patch
/// the spokes from the middle point (j = d/2) of each ribbon's innermost row to the centre.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ControlNet {
    /// Control point positions.
    pub positions: Vec<DVec3>,
    /// Corner count of each face (the faces are quads: all 4).
    pub face_sizes: Vec<u32>,
    /// The faces' corners, one face after another.
    pub face_indices: Vec<u32>,
    /// Lines that bound no face, as vertex index pairs.
    pub edges: Vec<[u32; 2]>,
    /// Per vertex: the patch it belongs to.
    pub patch: Vec<u32>,
}

pub use crate::limits::MAX_CUBIC_SPLIT_DEPTH;

/// The tolerance of [`Surface::default_cubic_curves`], relative to the diagonal of the bounding
/// box of the curve network's control points.
pub const CUBIC_CURVE_RELATIVE_TOLERANCE: f64 = 1e-9;

impl Surface {
    /// The control nets of all patches as one mesh (see [`ControlNet`]).
    pub fn control_net(&self) -> ControlNet {
        let mut net = ControlNet::default();
        for (p, patch) in self.patches.iter().enumerate() {
            let mut inner_middles = Vec::new();
            for rb in patch.ribbons() {
                let mut row_start = Vec::with_capacity(rb.layers());
                for row in rb.rows() {
                    row_start.push(net.positions.len() as u32);
                    net.positions.extend_from_slice(row);
                }
                for k in 0..rb.layers().saturating_sub(1) {
                    let (a, b) = (row_start[k], row_start[k + 1]);
                    let width = rb.width() as u32;
                    for j in 0..width.saturating_sub(1) {
                        net.face_sizes.push(4);
                        net.face_indices.extend_from_slice(&[a + j, a + j + 1, b + j + 1, b + j]);
                    }
                }
                if rb.layers() == 1 {
                    let row = rb.row(0);
                    let a = row_start[0];
                    net.edges.extend((0..row.len().saturating_sub(1) as u32).map(|j| [a + j, a + j + 1]));
                }
                if let (Some(last), Some(&start)) = (rb.rows().last(), row_start.last()) {
                    if !last.is_empty() {
                        inner_middles.push(start + (rb.degree / 2).min(last.len() - 1) as u32);
                    }
                }
            }
            if let Patch::Gb(g) = patch {
                let c = net.positions.len() as u32;
                net.positions.push(g.center);
                net.edges.extend(inner_middles.iter().map(|&m| [m, c]));
            }
            net.patch.resize(net.positions.len(), p as u32);
        }
        net
    }

    /// The curve network as cubic Bézier chains: per curve 3k + 1 control points (k segments,
    /// segment i = points 3i..=3i+3, consecutive segments sharing an end point).
    ///
    /// Degree ≤ 3: one segment, exactly (degree elevation). Degree d > 3: the curve's cubic
    /// Hermite form ([`hermite_cubic`], the same as `reduce_degree` to degree 3 keeping end points
    /// and end tangents) when its [`error_bound`] to the curve is ≤ `tolerance`; otherwise the
    /// curve is halved at t = ½ and each half treated the same way, at most
    /// [`MAX_CUBIC_SPLIT_DEPTH`] times (then the Hermite form is taken whatever its bound). Each
    /// segment keeps the end points and end tangents of its piece, so the chain is C1 in the
    /// curve's parameter. A curve without points gives an empty chain.
    pub fn cubic_curves(&self, tolerance: f64) -> Vec<Vec<DVec3>> {
        self.curves.iter().map(|c| cubic_chain(c, tolerance)).collect()
    }

    /// [`Surface::cubic_curves`] with the tolerance [`CUBIC_CURVE_RELATIVE_TOLERANCE`] times the
    /// bounding-box diagonal of the curve network's control points.
    pub fn default_cubic_curves(&self) -> Vec<Vec<DVec3>> {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for &p in self.curves.iter().flatten() {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        let diagonal = if lo.x <= hi.x { (hi - lo).length() } else { 0.0 };
        self.cubic_curves(CUBIC_CURVE_RELATIVE_TOLERANCE * diagonal)
    }
}

/// The cubic chain of one Bézier curve (see [`Surface::cubic_curves`]).
fn cubic_chain(points: &[DVec3], tolerance: f64) -> Vec<DVec3> {
    let Some(&first) = points.first() else {
        return Vec::new();
    };
    let curve = BezierCurve::from_vec(points.to_vec());
    let mut chain = vec![first];
    if curve.degree() <= 3 {
        chain.extend_from_slice(&curve.elevate_by(3 - curve.degree()).points()[1..]);
    } else {
        push_cubics(&curve, tolerance, 0, &mut chain);
    }
    chain
}

/// Appends the cubic segments of `curve` (degree > 3) without their first point.
fn push_cubics(curve: &BezierCurve<DVec3>, tolerance: f64, depth: usize, chain: &mut Vec<DVec3>) {
    let cubic = hermite_cubic(curve);
    if depth >= MAX_CUBIC_SPLIT_DEPTH || error_bound(curve, &cubic) <= tolerance {
        chain.extend_from_slice(&cubic.points()[1..]);
        return;
    }
    let (left, right) = curve.subdivide(0.5);
    push_cubics(&left, tolerance, depth + 1, chain);
    push_cubics(&right, tolerance, depth + 1, chain);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::construct::PatchSource;
    use crate::gb::{CgbPatch, GbPatch, Ribbon};

    fn ribbon(degree: usize, layers: usize, z: f64) -> Ribbon {
        Ribbon::from_fn(degree, layers, degree + 1, |k, j| DVec3::new(j as f64, k as f64, z))
    }

    fn surface(patches: Vec<Patch>, curves: Vec<Vec<DVec3>>) -> Surface {
        let n = patches.len();
        Surface {
            neighbors: patches.iter().map(|p| vec![None; p.sides()]).collect(),
            patches,
            sources: (0..n).map(PatchSource::Face).collect(),
            curves,
            warnings: Vec::new(),
            creases: Vec::new(),
            cage: Vec::new(),
        }
    }

    #[test]
    fn gb_net_has_quads_between_rows_and_spokes_to_the_centre() {
        // Three sides, degree 3, 2 rows: 3 × 8 ribbon points + 1 centre.
        let g = GbPatch { ribbons: (0..3).map(|i| ribbon(3, 2, i as f64)).collect(), center: DVec3::new(9.0, 9.0, 9.0) };
        let net = surface(vec![Patch::Gb(g)], vec![]).control_net();
        assert_eq!(net.positions.len(), 25);
        assert_eq!(net.patch, vec![0; 25]);
        assert_eq!(net.face_sizes, vec![4; 9]);
        assert_eq!(net.face_indices.len(), 36);
        // First quad of ribbon 1: rows start at 8 and 12.
        assert_eq!(&net.face_indices[12..16], &[8, 9, 13, 12]);
        // Spokes: innermost row middle j = 1 of each ribbon to the centre 24.
        assert_eq!(net.edges, vec![[5, 24], [13, 24], [21, 24]]);
        assert_eq!(net.positions[24], DVec3::splat(9.0));
        assert_eq!(net.positions[13], DVec3::new(1.0, 1.0, 1.0));
    }

    #[test]
    fn one_row_ribbons_give_edges_and_patches_are_numbered() {
        let a = CgbPatch { ribbons: vec![ribbon(2, 1, 0.0), ribbon(3, 2, 0.0)] };
        let b = CgbPatch { ribbons: vec![ribbon(1, 1, 1.0)] };
        let net = surface(vec![Patch::Cgb(a), Patch::Cgb(b)], vec![]).control_net();
        assert_eq!(net.positions.len(), 3 + 8 + 2);
        assert_eq!(net.edges, vec![[0, 1], [1, 2], [11, 12]]);
        assert_eq!(net.face_indices, vec![3, 4, 8, 7, 4, 5, 9, 8, 5, 6, 10, 9]);
        assert_eq!(net.patch, [vec![0; 11], vec![1; 2]].concat());
        // Every index is in range.
        let nv = net.positions.len() as u32;
        assert!(net.face_indices.iter().chain(net.edges.iter().flatten()).all(|&i| i < nv));
    }

    #[test]
    fn low_degrees_are_elevated_exactly() {
        let line = vec![DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0)];
        let quad = vec![DVec3::ZERO, DVec3::new(1.5, 3.0, 0.0), DVec3::new(3.0, 0.0, 0.0)];
        let cubic = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let s = surface(vec![], vec![line, quad.clone(), cubic.clone(), vec![]]);
        let c = s.cubic_curves(0.0);
        assert_eq!(c[0], vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0), DVec3::new(3.0, 0.0, 0.0)]);
        assert_eq!(c[1], vec![DVec3::ZERO, DVec3::new(1.0, 2.0, 0.0), DVec3::new(2.0, 2.0, 0.0), DVec3::new(3.0, 0.0, 0.0)]);
        assert_eq!(c[2], cubic);
        assert!(c[3].is_empty());
        let q = BezierCurve::from_vec(quad);
        let e = BezierCurve::from_vec(c[1].clone());
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            assert!((q.eval(t) - e.eval(t)).length() < 1e-15);
        }
    }

    #[test]
    fn higher_degrees_are_split_until_the_bound_meets_the_tolerance() {
        let pts: Vec<DVec3> = (0..=6).map(|i| DVec3::new(i as f64, ((i * i) % 5) as f64, (i % 2) as f64)).collect();
        let curve = BezierCurve::from_vec(pts.clone());
        let s = surface(vec![], vec![pts]);
        for tol in [1.0, 1e-2, 1e-4, 1e-6] {
            let chain = &s.cubic_curves(tol)[0];
            assert_eq!(chain.len() % 3, 1);
            // Walk the segments: each ends at a dyadic parameter t + 2^-j of the curve, and is
            // within the tolerance of the curve's piece over [t, t + 2^-j].
            let mut t = 0.0;
            for seg in chain.windows(4).step_by(3) {
                let j = (0..=MAX_CUBIC_SPLIT_DEPTH)
                    .find(|&j| (curve.eval(t + 0.5f64.powi(j as i32)) - seg[3]).length() < 1e-12)
                    .expect("segment ends on the curve at a dyadic parameter");
                let h = 0.5f64.powi(j as i32);
                let piece = curve.segment(t, t + h);
                assert!(error_bound(&piece, &BezierCurve::from_vec(seg.to_vec())) <= tol * (1.0 + 1e-9) + 1e-14, "tol {tol} at t = {t}");
                t += h;
            }
            assert_eq!(t, 1.0);
            assert_eq!(chain[0], curve.points()[0]);
            assert_eq!(*chain.last().unwrap(), curve.points()[6]);
        }
        assert_eq!(s.cubic_curves(10.0)[0].len(), 4);
        // Tolerance 0 (or NaN) stops at the depth limit.
        assert_eq!(s.cubic_curves(0.0)[0].len(), 3 * (1 << MAX_CUBIC_SPLIT_DEPTH) + 1);
        assert_eq!(s.cubic_curves(f64::NAN)[0].len(), 3 * (1 << MAX_CUBIC_SPLIT_DEPTH) + 1);
    }

    #[test]
    fn default_tolerance_keeps_cubic_networks_unchanged() {
        let c = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let s = surface(vec![], vec![c.clone()]);
        assert_eq!(s.default_cubic_curves(), vec![c]);
        assert!(surface(vec![], vec![]).default_cubic_curves().is_empty());
    }

    #[test]
    fn nets_of_constructed_surfaces_cover_every_control_point() {
        use crate::api::{convert, ConvertOptions, Method};
        use crate::mesh::PolyMesh;
        let corner = |i: usize| DVec3::new((i & 1) as f64 * 2.0 - 1.0, (i >> 1 & 1) as f64 * 2.0 - 1.0, (i >> 2 & 1) as f64 * 2.0 - 1.0);
        let faces = vec![vec![0, 2, 3, 1], vec![4, 5, 7, 6], vec![0, 1, 5, 4], vec![2, 6, 7, 3], vec![0, 4, 6, 2], vec![1, 3, 7, 5]];
        let cube = PolyMesh::new((0..8).map(corner).collect(), faces);
        for method in [Method::Dual, Method::Topology] {
            let options = ConvertOptions { method, resolution: 2, ..Default::default() };
            let s = convert(&cube, &options, None).unwrap().surface.unwrap();
            let net = s.control_net();
            let mut expected = Vec::new();
            for (p, patch) in s.patches.iter().enumerate() {
                let mut n = patch.ribbons().iter().map(|r| r.points().len()).sum::<usize>();
                if let Patch::Gb(g) = patch {
                    n += 1;
                    assert_eq!(net.edges.iter().filter(|e| net.positions[e[1] as usize] == g.center).count(), patch.sides());
                }
                expected.extend(std::iter::repeat(p as u32).take(n));
            }
            assert_eq!(net.patch, expected);
            let nv = net.positions.len() as u32;
            assert!(net.face_indices.iter().chain(net.edges.iter().flatten()).all(|&i| i < nv));
            assert_eq!(net.face_indices.len(), 4 * net.face_sizes.len());
            assert_eq!(s.default_cubic_curves(), s.curves, "the networks are cubic");
        }
    }
}
