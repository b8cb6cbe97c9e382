//! Creases and corners (docs/math.md#creases): infinitely sharp edges are G0 exactly there and
//! leave the rest G1, semi-sharp creases move the surface continuously, sharpness 0 is
//! bit-identical to no crease data, and the OBJ `t crease` / `t corner` tags.

use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::construct::{build_topology, Surface};
use gbsurf::gb::{angle_deg, Domain, Evaluate, WeightForm};
use gbsurf::mesh::io::{obj_sharpness, parse_obj};
use gbsurf::mesh::{HalfEdgeMesh, MeshError, MeshWarning, PolyMesh};

use proptest::prelude::*;

mod common_cage;
use common_cage::{cage_faces, loop_jump, per_corner};

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn cube() -> PolyMesh {
    gbsurf::mesh::read_polymesh(format!("{MODELS}/cube.obj")).unwrap().0
}

/// The 12 edges of a mesh as vertex pairs.
fn edges(m: &PolyMesh) -> Vec<[u32; 2]> {
    let mut e: Vec<[u32; 2]> = m
        .faces
        .iter()
        .flat_map(|f| (0..f.len()).map(move |i| [f[i].min(f[(i + 1) % f.len()]), f[i].max(f[(i + 1) % f.len()])]))
        .collect();
    e.sort();
    e.dedup();
    e
}

fn with_creases(mut m: PolyMesh, pick: impl Fn([u32; 2]) -> bool, c: f64) -> PolyMesh {
    m.creases.edges = edges(&m).into_iter().filter(|&e| pick(e)).map(|e| (e, c)).collect();
    m
}

/// The four edges of the top face (z = 1) of the cube.
fn top_loop(m: &PolyMesh) -> impl Fn([u32; 2]) -> bool + '_ {
    move |[a, b]| m.positions[a as usize].z > 0.0 && m.positions[b as usize].z > 0.0
}

fn topology() -> ConvertOptions {
    ConvertOptions { method: Method::Topology, ..ConvertOptions::triangles_r8() }
}

fn topo(m: &PolyMesh) -> Surface {
    build_topology(&HalfEdgeMesh::from_polymesh(m).unwrap(), &ConvertOptions::triangles_r8()).unwrap()
}

/// Max normal angle and max gap along the shared sides, separately for smooth and creased sides:
/// ([smooth angle, smooth gap], [creased min-of-max angle, creased gap]).
struct Joins {
    smooth_angle: f64,
    smooth_gap: f64,
    sharp_min_angle: f64,
    sharp_gap: f64,
    sharp_sides: usize,
}

fn joins(s: &Surface) -> Joins {
    let mut j = Joins { smooth_angle: 0.0, smooth_gap: 0.0, sharp_min_angle: f64::INFINITY, sharp_gap: 0.0, sharp_sides: 0 };
    let ts: Vec<f64> = (1..16).map(|k| k as f64 / 16.0).collect();
    for (p, i, n) in s.shared_sides() {
        let da = Domain::regular(s.patches[p].sides()).unwrap();
        let db = Domain::regular(s.patches[n.patch].sides()).unwrap();
        let sharp = s.side_crease(p, i) > 0.0;
        let mut side_min = f64::INFINITY;
        for &t in &ts {
            let a = s.patches[p].eval_derivs(da.side_point(i, t), WeightForm::Squared);
            let b = s.patches[n.patch].eval_derivs(db.side_point(n.side, 1.0 - t), WeightForm::Squared);
            let ang = angle_deg(a.normal().unwrap(), b.normal().unwrap());
            let gap = a.p.distance(b.p);
            if sharp {
                j.sharp_gap = j.sharp_gap.max(gap);
                side_min = side_min.min(ang);
            } else {
                j.smooth_gap = j.smooth_gap.max(gap);
                j.smooth_angle = j.smooth_angle.max(ang);
            }
        }
        if sharp {
            j.sharp_sides += 1;
            j.sharp_min_angle = j.sharp_min_angle.min(side_min);
        }
    }
    j
}

/// The output of the cube `m` is the cube: largest coordinate 1, every corner hit, every point
/// on a face (one coordinate at ±1).
fn assert_is_the_cube(m: &PolyMesh, c: &gbsurf::api::Conversion) {
    let lim = c.mesh.positions.iter().flat_map(|p| p.to_array()).fold(0.0f64, |a, x| a.max(x.abs()));
    assert!((lim - 1.0).abs() <= 1e-12, "largest coordinate {lim}");
    for corner in &m.positions {
        let d = c.mesh.positions.iter().map(|p| p.distance(*corner)).fold(f64::INFINITY, f64::min);
        assert!(d <= 1e-12, "corner {corner} missed by {d}");
    }
    for p in &c.mesh.positions {
        let on = p.to_array().iter().any(|x| (x.abs() - 1.0).abs() <= 1e-9);
        assert!(on, "{p} is off the cube");
    }
}

#[test]
fn cube_with_every_edge_sharp_keeps_its_corners() {
    let m = with_creases(cube(), |_| true, 1.0);
    let c = convert(&m, &topology(), None).unwrap();
    assert_is_the_cube(&m, &c);
    assert_eq!(c.report.sharp_edges, 12);
    assert_eq!(c.report.folds, 0);
    // the subdivision methods ignore creases, with a warning
    let d = convert(&m, &ConvertOptions { method: Method::CatmullClark, ..ConvertOptions::triangles_r8() }, None).unwrap();
    assert!(d.warnings.iter().any(|w| w.contains("creases are ignored by the catmull-clark")), "{:?}", d.warnings);
}

#[test]
fn one_sharp_loop_is_g0_there_and_g1_elsewhere() {
    let base = cube();
    let m = with_creases(base.clone(), top_loop(&base), 1.0);
    let s = topo(&m);
    let j = joins(&s);
    assert_eq!(j.sharp_sides, 4);
    assert!(j.sharp_gap <= 1e-12, "gap on the crease {}", j.sharp_gap);
    assert!(j.smooth_gap <= 1e-12, "gap {}", j.smooth_gap);
    assert!(j.smooth_angle <= 1e-4, "G1 off the crease: {}°", j.smooth_angle);
    println!("sharp loop: crease angle >= {:.2}°, smooth G1 {:.2e}°, gaps {:.1e} / {:.1e}", j.sharp_min_angle, j.smooth_angle, j.sharp_gap, j.smooth_gap);
    assert!(j.sharp_min_angle >= 5.0, "the crease is not sharp: {}°", j.sharp_min_angle);
    let c = convert(&m, &topology(), None).unwrap();
    assert_eq!(c.report.sharp_edges, 4);
    assert!(c.report.max_g1_deg <= 1e-4, "report G1 {}", c.report.max_g1_deg);
    assert_eq!(c.report.folds, 0, "{:?} flipped {}", c.report.fold_sites, c.report.flipped_triangles);
    assert!(c.report.closed);
}

#[test]
fn crease_zero_is_bit_identical_to_no_creases() {
    let base = cube();
    let plain = convert(&base, &topology(), None).unwrap();
    let zero = with_creases(base.clone(), |_| true, 0.0);
    let mut zero = zero;
    zero.creases.vertices = vec![(0, 0.0)];
    let z = convert(&zero, &topology(), None).unwrap();
    assert_eq!(plain.mesh.positions, z.mesh.positions);
    assert_eq!(plain.mesh.normals, z.mesh.normals);
    assert_eq!(plain.mesh.triangles, z.mesh.triangles);
    assert_eq!(topo(&base).patches, topo(&zero).patches);
}

fn max_move(a: &Surface, b: &Surface) -> f64 {
    let mut d = 0.0f64;
    for (pa, pb) in a.patches.iter().zip(&b.patches) {
        let dom = Domain::regular(pa.sides()).unwrap();
        for k in 0..pa.sides() {
            for t in [0.1, 0.3, 0.5, 0.7, 0.9] {
                for depth in [0.0, 0.25, 0.5] {
                    let q = dom.side_point(k, t);
                    let uv = q + depth * (dom.center() - q);
                    d = d.max(pa.eval_derivs(uv, WeightForm::Squared).p.distance(pb.eval_derivs(uv, WeightForm::Squared).p));
                }
            }
        }
    }
    d
}

#[test]
fn crease_sweep_is_continuous() {
    let base = cube();
    let mut prev = topo(&base);
    let mut worst = 0.0f64;
    for k in 1..=20 {
        let c = k as f64 * 0.05;
        let s = topo(&with_creases(base.clone(), top_loop(&base), c));
        let d = max_move(&prev, &s);
        worst = worst.max(d);
        assert!(d <= 0.05, "step to c = {c}: the surface moved {d}");
        prev = s;
    }
    println!("crease sweep: largest move per step of 0.05 = {worst:.4}");
    // a tiny sharpness moves the surface only a little
    let tiny = topo(&with_creases(base.clone(), top_loop(&base), 1e-9));
    assert!(max_move(&topo(&base), &tiny) <= 1e-8);
}

#[test]
fn corner_vertex_is_pulled_to_its_position() {
    let mut m = cube();
    m.creases.vertices = vec![(7, 1.0)];
    let s = topo(&m);
    let target = m.positions[7];
    let hit = s.curves.iter().flat_map(|c| [c[0], *c.last().unwrap()]).any(|p| p.distance(target) <= 1e-12);
    assert!(hit, "no node at the corner vertex");
}

// ------------------------------------------------------------ validation

#[test]
fn crease_values_and_edges_are_validated() {
    let mut m = cube();
    m.creases.edges = vec![([0, 1], 0.5), ([0, 3], 0.5)];
    let e = HalfEdgeMesh::from_polymesh(&m).unwrap_err();
    assert_eq!(e, MeshError::CreaseEdgeMissing { entry: 1, edge: (0, 3), line: None });
    m.creases.edges = vec![([0, 1], f64::NAN)];
    assert!(matches!(HalfEdgeMesh::from_polymesh(&m), Err(MeshError::EdgeCreaseValue { entry: 0, edge: (0, 1), .. })));
    m.creases.edges = vec![([0, 1], 1.5)];
    assert!(matches!(HalfEdgeMesh::from_polymesh(&m), Err(MeshError::EdgeCreaseValue { .. })));
    m.creases.edges.clear();
    m.creases.vertices = vec![(9, 1.0)];
    assert_eq!(
        HalfEdgeMesh::from_polymesh(&m).unwrap_err(),
        MeshError::CreaseVertexOutOfRange { entry: 0, vertex: 9, n_vertices: 8, line: None }
    );
    m.creases.vertices = vec![(2, -0.1)];
    assert!(matches!(HalfEdgeMesh::from_polymesh(&m), Err(MeshError::VertexCreaseValue { entry: 0, vertex: 2, .. })));
    // repeated entries keep the larger value, in either vertex order
    m.creases.vertices.clear();
    m.creases.edges = vec![([1, 0], 0.25), ([0, 1], 0.75)];
    let he = HalfEdgeMesh::from_polymesh(&m).unwrap();
    let e = he.edges().find(|&e| he.edge_crease(e) > 0.0).unwrap();
    assert_eq!(he.edge_crease(e), 0.75);
    assert_eq!(he.edges().filter(|&e| he.edge_crease(e) > 0.0).count(), 1);
}

// ------------------------------------------------------------ OBJ tags

const CUBE_OBJ: &str = "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n\
f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

fn obj(tags: &str) -> Result<(PolyMesh, gbsurf::mesh::SourceMap), MeshError> {
    parse_obj(format!("{CUBE_OBJ}{tags}"))
}

fn line_of(e: &MeshError) -> Option<usize> {
    match e {
        MeshError::Parse { line, .. } => *line,
        _ => None,
    }
}

#[test]
fn obj_crease_and_corner_tags_are_read() {
    let (m, map) = obj("t crease 2/1/0 0 1 10\nt crease 4/1/0 1 3 3 2 2.5\nt crease 4/2/0 4 5 5 7 0 40\nt corner 2/1/0 6 7 5\n").unwrap();
    assert_eq!(
        m.creases.edges,
        vec![([0, 1], 1.0), ([1, 3], 0.5), ([3, 2], 0.5), ([4, 5], 0.0), ([5, 7], 1.0)]
    );
    assert_eq!(m.creases.vertices, vec![(6, obj_sharpness(5.0)), (7, obj_sharpness(5.0))]);
    assert_eq!(map.edge_crease_lines, vec![15, 16, 16, 17, 17]);
    assert_eq!(map.vertex_crease_lines, vec![18, 18]);
    assert_eq!(obj_sharpness(2.5), 0.5);
    assert_eq!(obj_sharpness(1e9), 1.0);
    assert!(HalfEdgeMesh::from_polymesh(&m).is_ok());
}

#[test]
fn obj_bad_tags_name_their_line() {
    for (tag, msg) in [
        ("t crease 2/1/0 0 8 1", "vertex index 8 out of range"),
        ("t crease 2/1/0 0 1 nan", "not a finite number"),
        ("t crease 2/1/0 0 1 -1", "not a finite number"),
        ("t crease 2/1/0 0 1", "expected 3 arguments"),
        ("t crease 2/1/0 0 x 1", "bad vertex index"),
        ("t crease", "missing the argument counts"),
        ("t crease 3/1/0 0 1 2 1", "unsupported argument counts"),
        ("t crease 2/1 0 1 1", "bad argument counts"),
        ("t corner 1/1/0 12 1", "vertex index 12 out of range"),
        ("t corner 1/0/0 1", "unsupported argument counts"),
    ] {
        let e = obj(&format!("{tag}\n")).unwrap_err();
        assert_eq!(line_of(&e), Some(15), "{tag}: {e}");
        assert!(e.to_string().contains(msg), "{tag}: {e}");
    }
    // an edge that no face has: named with its line by the reader
    let path = std::env::temp_dir().join(format!("gbsurf_crease_{}.obj", std::process::id()));
    std::fs::write(&path, format!("{CUBE_OBJ}t crease 2/1/0 0 1 1\nt crease 2/1/0 0 3 1\n")).unwrap();
    let e = gbsurf::mesh::read_mesh(&path).unwrap_err();
    std::fs::remove_file(&path).ok();
    assert_eq!(e, MeshError::CreaseEdgeMissing { entry: 1, edge: (0, 3), line: Some(16) });
    assert!(e.to_string().contains("line 16"), "{e}");
}

#[test]
fn obj_unsupported_tags_are_warned_and_skipped() {
    let (m, map) = obj("t interpolateboundary 1/0/0 1\nt hole 1/0/0 3\nt hole 1/0/0 4\nt facevaryingpropagatecorners 1/0/0 1\n").unwrap();
    assert!(m.creases.is_smooth());
    let sk = |s: &str, line: usize, count: usize| MeshWarning::SkippedStatement { statement: s.into(), line, count };
    assert_eq!(
        map.warnings,
        vec![sk("t interpolateboundary", 15, 1), sk("t hole", 16, 2), sk("t facevaryingpropagatecorners", 18, 1)]
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, .. ProptestConfig::default() })]
    /// The OBJ mapping is monotone, in [0, 1], and 1 from sharpness 10 on.
    #[test]
    fn obj_sharpness_is_monotone(a in 0.0f64..20.0, b in 0.0f64..20.0) {
        let (ca, cb) = (obj_sharpness(a), obj_sharpness(b));
        prop_assert!((0.0..=1.0).contains(&ca));
        if a <= b { prop_assert!(ca <= cb); }
        if a >= 10.0 { prop_assert_eq!(ca, 1.0); }
        prop_assert!((10.0 * ca * ca - a.min(10.0)).abs() <= 1e-12);
    }

    /// Any sharpness on the top loop gives a closed, gap-free surface whose smooth joins stay G1.
    #[test]
    fn any_sharpness_keeps_the_smooth_joins_g1(c in 0.0f64..=1.0) {
        let base = cube();
        let s = topo(&with_creases(base.clone(), top_loop(&base), c));
        let j = joins(&s);
        prop_assert!(j.smooth_gap <= 1e-12 && j.sharp_gap <= 1e-12);
        prop_assert!(j.smooth_angle <= 1e-4, "c = {}: {}°", c, j.smooth_angle);
    }
}

// ------------------------------------------------------------ dual structure (docs/math.md#dual-creases)

fn dual() -> ConvertOptions {
    ConvertOptions { method: Method::Dual, ..ConvertOptions::triangles_r8() }
}

/// The largest distance between an output quad corner and the keep-corners point of its cage
/// coordinates (docs/math.md#cage-corners); panics on a quad whose (σ, τ) span no area.
fn cage_point_error(m: &PolyMesh, c: &gbsurf::api::Conversion) -> f64 {
    let mut worst = 0.0f64;
    for (k, (q, cc)) in c.mesh.quads.iter().zip(&c.mesh.cage_corner).enumerate() {
        let face = &m.faces[cc[0] as usize];
        let (len, i) = (face.len(), cc[1] as usize);
        let p = |j: usize| m.positions[face[j % len] as usize];
        let (v, next, prev) = (p(i), p(i + 1), p(i + len - 1));
        let centre = face.iter().map(|&x| m.positions[x as usize]).sum::<glam::DVec3>() / len as f64;
        let st = &c.mesh.cage_coords[4 * k..4 * k + 4];
        let area = (0..4).map(|a| st[a][0] * st[(a + 1) % 4][1] - st[(a + 1) % 4][0] * st[a][1]).sum::<f64>().abs() / 2.0;
        assert!(area > 1e-6, "quad {k} is flat in (σ, τ): {st:?}");
        for (corner, &[sg, ta]) in q.iter().zip(st) {
            let at = (1.0 - sg) * (1.0 - ta) * v + sg * (1.0 - ta) * (v + next) / 2.0 + sg * ta * centre + (1.0 - sg) * ta * (v + prev) / 2.0;
            worst = worst.max(at.distance(c.mesh.positions[*corner as usize]));
        }
    }
    worst
}

/// The dual conversion in the default quad layout (cage corners and coordinates).
fn dual_quads(m: &PolyMesh) -> gbsurf::api::Conversion {
    convert(m, &ConvertOptions { method: Method::Dual, ..Default::default() }, None).unwrap()
}

fn dual_surface(m: &PolyMesh) -> Surface {
    gbsurf::construct::build_dual(&HalfEdgeMesh::from_polymesh(m).unwrap(), &ConvertOptions::triangles_r8()).unwrap()
}

/// Largest distance from an output vertex of one conversion to the other's triangles, both
/// ways (a Hausdorff distance of the two tessellations, through parry's point queries).
fn surface_distance(a: &gbsurf::api::Conversion, b: &gbsurf::api::Conversion) -> f64 {
    use parry3d_f64::math::Vector;
    use parry3d_f64::query::PointQuery;
    let one = |x: &gbsurf::api::Conversion, y: &gbsurf::api::Conversion| {
        let v = |p: &glam::DVec3| Vector::new(p.x, p.y, p.z);
        let mesh = parry3d_f64::shape::TriMesh::new(y.mesh.positions.iter().map(v).collect(), y.mesh.triangles.clone()).unwrap();
        x.mesh.positions.iter().map(|p| mesh.distance_to_local_point(v(p), false)).fold(0.0f64, f64::max)
    };
    one(a, b).max(one(b, a))
}

#[test]
fn dual_cube_with_every_edge_sharp_is_the_cube() {
    let m = with_creases(cube(), |_| true, 1.0);
    let c = convert(&m, &dual(), None).unwrap();
    assert_is_the_cube(&m, &c);
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
    assert_eq!(c.report.folds, 0);
    assert!(c.report.closed && c.report.self_intersections == 0);
    // Every output face keeps its cage face (UVs and materials follow it): each sector of a
    // corner lies on one face of the cube, the one its cage corner names.
    // Its cage coordinates say where it is: the output is the cube, so the keep-corners point
    // of each quad corner, (1−σ)(1−τ)·V + σ(1−τ)·M_next + στ·c_f + (1−σ)τ·M_prev of its cage
    // corner, lies near the output vertex, and no quad is flat in (σ, τ) (a checker texture
    // would smear).
    let quads = dual_quads(&m);
    let worst = cage_point_error(&m, &quads);
    println!("dual cube, every edge sharp: cage coordinates within {worst:.3} of the vertices");
    assert!(worst <= 0.2, "a quad corner lies {worst} from its cage point");
    for (q, cc) in quads.mesh.quads.iter().zip(&quads.mesh.cage_corner) {
        let face = &m.faces[cc[0] as usize];
        let normal = (m.positions[face[1] as usize] - m.positions[face[0] as usize]).cross(m.positions[face[2] as usize] - m.positions[face[0] as usize]).normalize();
        let centre = q.iter().map(|&i| quads.mesh.positions[i as usize]).sum::<glam::DVec3>() / 4.0;
        assert!((centre.dot(normal) - 1.0).abs() <= 1e-9, "quad at {centre} is not on its cage face {face:?}");
    }
    println!("dual cube, every edge sharp: {} patches, {} sharp sides", c.report.patches, c.report.sharp_edges);
}

#[test]
fn dual_sharp_loop_is_g0_there_and_g1_elsewhere() {
    let base = cube();
    let m = with_creases(base.clone(), top_loop(&base), 1.0);
    let s = dual_surface(&m);
    let j = joins(&s);
    println!("dual sharp loop: {} sharp sides, crease angle >= {:.2}°, smooth G1 {:.2e}°, gaps {:.1e} / {:.1e}", j.sharp_sides, j.sharp_min_angle, j.smooth_angle, j.sharp_gap, j.smooth_gap);
    assert_eq!(j.sharp_sides, 4);
    assert!(j.sharp_gap <= 1e-12 && j.smooth_gap <= 1e-12, "gaps {} {}", j.sharp_gap, j.smooth_gap);
    assert!(j.smooth_angle <= 1e-4, "G1 off the crease: {}°", j.smooth_angle);
    assert!(j.sharp_min_angle >= 5.0, "the crease is not sharp: {}°", j.sharp_min_angle);
    let c = convert(&m, &dual(), None).unwrap();
    assert_eq!(c.report.sharp_edges, 4);
    let quads = dual_quads(&m);
    let worst = cage_point_error(&m, &quads);
    let plain = cage_point_error(&base, &dual_quads(&base));
    println!("dual sharp loop: cage coordinates within {worst:.3} of the vertices (no crease: {plain:.3})");
    assert!(worst <= plain + 0.1, "{worst} against {plain} without the crease");
    // A per-vertex attribute (the cage positions over the extent 2) is continuous at every output
    // vertex, across the cut curves between two wall faces too (docs/math.md#cage-corners: a cut
    // curve's midpoint maps to V). Bound: f32 values ≤ 1 after a mean and three lerps; 1e-5.
    let (sizes, hole_faces, hole_sizes) = cage_faces(&m);
    let faces = gbsurf::tessellate::CageFaces { sizes: &sizes, hole_faces: &hole_faces, hole_sizes: &hole_sizes };
    let values = per_corner(&m, |_, v| (m.positions[v as usize] / 2.0).to_array().map(|x| x as f32));
    let jump = loop_jump(&quads.mesh, &quads.mesh.cage_loop_values(faces, &values, 3).unwrap(), 3, false);
    println!("dual sharp loop: cage positions / extent jump by {jump:.2e} at an output vertex");
    assert!(jump <= 1e-5, "the cage positions jump by {jump} of the extent");
    assert!(c.report.max_g1_deg <= 1e-4, "report G1 {}", c.report.max_g1_deg);
    assert_eq!(c.report.folds, 0, "{:?} flipped {}", c.report.fold_sites, c.report.flipped_triangles);
    assert!(c.report.closed && c.report.self_intersections == 0);
}

#[test]
fn dual_crease_sweep_is_continuous() {
    let base = cube();
    let at = |c: f64| dual_surface(&with_creases(base.clone(), top_loop(&base), c));
    let mut prev = at(0.05);
    let mut worst = 0.0f64;
    for k in 2..=20 {
        let c = k as f64 * 0.05;
        let s = at(c);
        let d = max_move(&prev, &s);
        worst = worst.max(d);
        assert!(d <= 0.05, "step to c = {c}: the surface moved {d}");
        prev = s;
    }
    // The first step changes the patch layout: measured on the output samples.
    let conv = |c: f64| convert(&with_creases(base.clone(), top_loop(&base), c), &dual(), None).unwrap();
    let jump = surface_distance(&conv(0.0), &conv(1e-9));
    let full = surface_distance(&conv(0.0), &conv(1.0));
    println!("dual crease sweep: largest move per step of 0.05 = {worst:.4}; sharpness 0 -> 1e-9: {jump:.4} (0 -> 1: {full:.4})");
    // The split's own step (docs/math.md#dual-creases): measured 0.021 with the cut curves
    // following S₀ at sharpness 0 (0.062 before), below one step of 0.05 (0.029).
    assert!(jump <= 0.03 && jump < full / 10.0, "sharpness 0 -> 1e-9 moved the surface {jump}");
    // G1 off the crease curves at every sharpness below 1, also while the cut curves turn from
    // S₀'s directions to the edge's (c < 0.25).
    // Also where a turning edge has a spoke at its other end (the top and bottom loops and one
    // vertical edge sharp: the vertical edge's ends have three cut edges).
    let mixed = |[a, b]: [u32; 2]| {
        let (pa, pb) = (base.positions[a as usize], base.positions[b as usize]);
        pa.z * pb.z > 0.0 || (pa.x == pb.x && pa.y == pb.y && pa.x > 0.0 && pa.y > 0.0)
    };
    for c in [1e-9, 0.1, 0.2, 0.5, 0.9] {
        let g1 = conv(c).report.max_g1_deg;
        assert!(g1 <= 1e-4, "sharpness {c}: G1 {g1}°");
        let g1 = convert(&with_creases(base.clone(), mixed, c), &dual(), None).unwrap().report.max_g1_deg;
        assert!(g1 <= 1e-4, "sharpness {c}, loops and a vertical edge: G1 {g1}°");
    }
}

/// The halves' face-centroid ends count twice in the blends' D (`CurveNetwork::end_scale`,
/// docs/math.md#direction-blends), so as the sharpness tends to 0 the patches next to a sector
/// without a cut edge of their own keep S₀'s ribbons: on the cube with its top loop sharp at
/// 1e-9 the bottom vertices' patches equal those without crease data up to rounding (measured
/// 0 with them; without, the largest control point moved 0.296, the surface 0.037).
#[test]
fn dual_crease_leaves_the_unsplit_patches_alone_as_sharpness_tends_to_0() {
    use gbsurf::construct::PatchSource;
    let base = cube();
    let plain = dual_surface(&base);
    let split = dual_surface(&with_creases(base.clone(), top_loop(&base), 1e-9));
    fn patch(s: &Surface, v: usize) -> &gbsurf::construct::Patch {
        let mut of = s.sources.iter().enumerate().filter(|(_, &x)| x == PatchSource::Vertex(v)).map(|(p, _)| p);
        let p = of.next().expect("every vertex has a patch");
        assert!(of.next().is_none(), "vertex {v} is split");
        &s.patches[p]
    }
    let mut worst = 0.0f64;
    for v in (0..base.positions.len()).filter(|&v| base.positions[v].z < 0.0) {
        let (a, b) = (patch(&plain, v), patch(&split, v));
        assert_eq!(a.sides(), b.sides());
        for (ra, rb) in a.ribbons().iter().zip(b.ribbons()) {
            for k in 0..ra.layers() {
                for (pa, pb) in ra.row(k).iter().zip(rb.row(k)) {
                    worst = worst.max(pa.distance(*pb));
                }
            }
        }
    }
    println!("dual crease at 1e-9: the bottom vertices' ribbons move by {worst:.2e}");
    assert!(worst <= 1e-12, "the unsplit patches' ribbons moved by {worst}");
}

/// A vertex of valence 4 with three sharp edges (a T-junction: a torus with two longitude
/// loops sharp and the meridian segment joining them) has a sector spanning two faces; the
/// spoke into it has no point in the frame of the sector's V corner, so its midpoint maps to V
/// in both sectors at that spoke (docs/math.md#cage-corners). A per-vertex attribute (the cage
/// positions over the extent) is then continuous at every output vertex; bound as above, 1e-5.
#[test]
fn dual_t_junction_keeps_per_vertex_attributes_continuous() {
    let (nu, nv) = (8usize, 6usize);
    let mut m = gbsurf::mesh::generate::torus(nu, nv, 2.0, 0.7).unwrap();
    let id = |i: usize, j: usize| ((i % nu) * nv + j % nv) as u32;
    let mut sharp: Vec<[u32; 2]> = Vec::new();
    for i in 0..nu {
        sharp.push([id(i, 0), id(i + 1, 0)]);
        sharp.push([id(i, 3), id(i + 1, 3)]);
    }
    sharp.extend((0..3).map(|j| [id(0, j), id(0, j + 1)]));
    let extent = 2.0 * (2.0 + 0.7);
    let (sizes, hole_faces, hole_sizes) = cage_faces(&m);
    let faces = gbsurf::tessellate::CageFaces { sizes: &sizes, hole_faces: &hole_faces, hole_sizes: &hole_sizes };
    let values = per_corner(&m, |_, v| (m.positions[v as usize] / extent).to_array().map(|x| x as f32));
    for c in [1.0, 0.5] {
        m.creases.edges = sharp.iter().map(|&[a, b]| ([a.min(b), a.max(b)], c)).collect();
        let opts = ConvertOptions { method: Method::Dual, resolution: 4, ..Default::default() };
        let conv = convert(&m, &opts, None).unwrap();
        assert!(conv.report.sharp_edges >= sharp.len(), "sharpness {c}: {:?}", conv.warnings);
        let jump = loop_jump(&conv.mesh, &conv.mesh.cage_loop_values(faces, &values, 3).unwrap(), 3, false);
        println!("dual T-junction at {c}: cage positions / extent jump by {jump:.2e} at an output vertex");
        assert!(jump <= 1e-5, "sharpness {c}: the cage positions jump by {jump} of the extent");
    }
}

#[test]
fn dual_open_chains_and_lone_corners_are_left_smooth_with_a_warning() {
    let base = cube();
    let plain = convert(&base, &dual(), None).unwrap();
    // one sharp edge (an open chain) and a corner on a vertex with no sharp edge
    let mut m = with_creases(base.clone(), |[a, b]| [a, b] == edges(&base)[0], 1.0);
    m.creases.vertices = vec![(3, 1.0)];
    let c = convert(&m, &dual(), None).unwrap();
    assert_eq!(c.mesh.positions, plain.mesh.positions, "the surface changed");
    let [a, b] = edges(&base)[0];
    let edge = format!("the first ({a}, {b})");
    assert!(c.warnings.iter().any(|w| w.contains("closed chains") && w.contains(&edge)), "{:?}", c.warnings);
    assert!(c.warnings.iter().any(|w| w.contains("corner sharpness ignored at 1 vertex(es), the first 3")), "{:?}", c.warnings);
    // three sharp edges of a closed loop around a corner, plus the open one: the loop is built
    let m = with_creases(base.clone(), |e| top_loop(&base)(e) || e == edges(&base)[0], 1.0);
    let c = convert(&m, &dual(), None).unwrap();
    assert!(c.report.sharp_edges >= 4, "{}", c.report.sharp_edges);
}

#[test]
fn dual_semi_sharp_cube_is_valid_and_g1_off_the_creases() {
    for c in [0.1, 0.5, 0.9] {
        let conv = convert(&with_creases(cube(), |_| true, c), &dual(), None).unwrap();
        assert!(conv.report.valid, "c = {c}: {:?}", conv.warnings);
        assert!(conv.report.max_g1_deg <= 1e-4, "c = {c}: G1 {}", conv.report.max_g1_deg);
        assert!(!conv.warnings.iter().any(|w| w.contains("built sharp")), "{:?}", conv.warnings);
    }
}

/// A corner vertex where a smooth edge lies next to a creased one is named in a warning: the
/// creased tangent is pulled off the tangent plane and projected back only by 1 − w3, so the
/// surface is not G1 across the smooth edge near it (docs/math.md#corners-with-smooth-curves);
/// the report's G1 then shows it. A corner tag alone moves no tangent off the plane: G1 and no
/// warning; a cube whose every edge is sharp has no smooth edge and no warning.
#[test]
fn corners_with_smooth_edges_are_warned() {
    let warned = |c: &gbsurf::api::Conversion| -> Vec<String> {
        c.warnings.iter().filter(|w| w.contains("corner vertices")).cloned().collect()
    };
    // Vertex 7 of the cube: a corner tag and one creased edge to a neighbour.
    let m = cube();
    let nb = edges(&m).into_iter().find(|e| e.contains(&7)).unwrap();
    let mut tagged = with_creases(cube(), |e| e == nb, 0.5);
    tagged.creases.vertices = vec![(7, 1.0)];
    let c = convert(&tagged, &topology(), None).unwrap();
    let w = warned(&c);
    assert_eq!(w.len(), 1, "{:?}", c.warnings);
    assert!(w[0].starts_with("1 corner vertices") && w[0].contains("(first: vertex 7)"), "{}", w[0]);
    assert!(c.report.max_g1_deg > 1e-4, "G1 {}", c.report.max_g1_deg);
    // The corner tag alone: G1 holds, nothing is said.
    let mut corner_only = cube();
    corner_only.creases.vertices = vec![(7, 1.0)];
    let c = convert(&corner_only, &topology(), None).unwrap();
    assert!(warned(&c).is_empty(), "{:?}", c.warnings);
    assert!(c.report.max_g1_deg < 1e-4, "G1 {}", c.report.max_g1_deg);
    // Every edge sharp: no smooth edge anywhere.
    let c = convert(&with_creases(cube(), |_| true, 1.0), &topology(), None).unwrap();
    assert!(warned(&c).is_empty(), "{:?}", c.warnings);
    // Without crease data nothing is said.
    assert!(warned(&convert(&cube(), &topology(), None).unwrap()).is_empty());
}
