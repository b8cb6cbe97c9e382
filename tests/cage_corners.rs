//! Cage corners of the output faces (SurfaceMesh::cage_corner, cage_coords; docs/math.md#cage-corners):
//! every output face names a valid (face, corner) of the control mesh, the faces of one corner
//! are contiguous and number r² (so n·r² per n-gon), the cage coordinates of the loops give one
//! cage point per (output vertex, cage face) (the interpolated UV map is continuous within every
//! cage face), the (0,0) loops of a cage vertex meet in one output vertex and the (1,1) loops of
//! a face in another; the triangle layout and subdivision give what their doc says. The
//! triangle layout's per-loop coordinates are the quad layout's at the samples both layouts
//! share (tests/cage_triangles.rs).

use gbsurf::api::{convert, ConvertOptions, Method};
use gbsurf::gb::Layout;
use gbsurf::mesh::PolyMesh;
use glam::DVec3;
use proptest::prelude::*;
use std::collections::HashMap;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn model(name: &str) -> PolyMesh {
    gbsurf::api::read_mesh(format!("{MODELS}/{name}")).unwrap()
}

fn opts(method: Method, layout: Layout, r: usize) -> ConvertOptions {
    ConvertOptions { method, layout, resolution: r, ..Default::default() }
}

/// The cage point of coordinates (σ, τ) in corner k of face f: bilinear between the vertex,
/// the midpoint of the edge to the next vertex, the face centre and the midpoint of the edge
/// from the previous vertex.
fn cage_point(cage: &PolyMesh, f: usize, k: usize, [s, t]: [f64; 2]) -> DVec3 {
    let face = &cage.faces[f];
    let n = face.len();
    let p = |i: usize| cage.positions[face[i % n] as usize];
    let centre = (0..n).map(p).sum::<DVec3>() / n as f64;
    let (v, next, prev) = (p(k), 0.5 * (p(k) + p(k + 1)), 0.5 * (p(k) + p(k + n - 1)));
    v * ((1.0 - s) * (1.0 - t)) + next * (s * (1.0 - t)) + centre * (s * t) + prev * ((1.0 - s) * t)
}

/// All the checks of the module doc on one conversion; `closed`: the (0,0) loops of a vertex
/// meet in one output vertex (on an open cage's dual, the open sectors flatten a spoke onto it).
fn check(name: &str, cage: &PolyMesh, method: Method, r: usize, closed: bool) {
    let out = convert(cage, &opts(method, Layout::Quads, r), None).unwrap_or_else(|e| panic!("{name} {method}: {e}"));
    let m = &out.mesh;
    let nq = m.quads.len();
    assert_eq!(m.cage_corner.len(), nq, "{name} {method}");
    assert_eq!(m.cage_coords.len(), 4 * nq, "{name} {method}");
    // Valid, contiguous, r² per corner.
    let mut runs: HashMap<[u32; 2], usize> = HashMap::new();
    let mut count: HashMap<[u32; 2], usize> = HashMap::new();
    for (k, c) in m.cage_corner.iter().enumerate() {
        let (f, i) = (c[0] as usize, c[1] as usize);
        assert!(f < cage.faces.len() && i < cage.faces[f].len(), "{name} {method}: face {k} → {c:?}");
        if k == 0 || m.cage_corner[k - 1] != *c {
            *runs.entry(*c).or_default() += 1;
        }
        *count.entry(*c).or_default() += 1;
    }
    let per_face = |f: usize| count.iter().filter(|(c, _)| c[0] as usize == f).map(|(_, n)| n).sum::<usize>();
    if closed {
        assert!(runs.values().all(|&n| n == 1), "{name} {method}: a corner's faces are not contiguous");
        assert!(count.values().all(|&n| n == r * r), "{name} {method}: {count:?}");
        for (f, face) in cage.faces.iter().enumerate() {
            assert_eq!(per_face(f), r * r * face.len(), "{name} {method} face {f}");
        }
    } else {
        // Open dual: the open sectors add r² faces to the corners at the boundary.
        assert!(count.values().all(|&n| n % (r * r) == 0 && n >= r * r), "{name} {method}: {count:?}");
    }
    // One cage point per (output vertex, cage face); corner and centre loops meet.
    let mut point: HashMap<(u32, u32), DVec3> = HashMap::new();
    let mut at_vertex: HashMap<u32, u32> = HashMap::new();
    let mut at_centre: HashMap<u32, u32> = HashMap::new();
    let scale = cage.positions.iter().map(|p| p.length()).fold(1.0, f64::max);
    for (k, q) in m.quads.iter().enumerate() {
        let [f, i] = m.cage_corner[k];
        for (j, &x) in q.iter().enumerate() {
            let st = m.cage_coords[4 * k + j];
            assert!(st.iter().all(|c| (0.0..=1.0).contains(c)), "{name} {method}: {st:?}");
            let p = cage_point(cage, f as usize, i as usize, st);
            let prev = *point.entry((x, f)).or_insert(p);
            assert!(prev.distance(p) <= 1e-12 * scale, "{name} {method}: vertex {x} in face {f}: {prev} vs {p}");
            if st == [0.0, 0.0] && closed {
                let v = cage.faces[f as usize][i as usize];
                assert_eq!(*at_vertex.entry(v).or_insert(x), x, "{name} {method}: corner loops of vertex {v}");
            }
            if st == [1.0, 1.0] {
                assert_eq!(*at_centre.entry(f).or_insert(x), x, "{name} {method}: centre loops of face {f}");
            }
        }
    }
    if closed {
        assert_eq!(at_vertex.len(), cage.positions.len(), "{name} {method}");
        let distinct: std::collections::HashSet<u32> = at_vertex.values().copied().collect();
        assert_eq!(distinct.len(), at_vertex.len(), "{name} {method}: two cage vertices share an output vertex");
    }
    assert_eq!(at_centre.len(), cage.faces.len(), "{name} {method}");
}

#[test]
fn cube_corners_both_structures() {
    let cube = model("cube.obj");
    for r in 1..=3 {
        check("cube", &cube, Method::Topology, r, true);
        check("cube", &cube, Method::Dual, r, true);
    }
}

#[test]
fn closed_and_open_cages() {
    for r in [1, 2] {
        check("torus", &model("torus.obj"), Method::Topology, r, true);
        check("torus", &model("torus.obj"), Method::Dual, r, true);
        check("grid_open", &model("grid_open.obj"), Method::Topology, r, true);
        check("grid_open", &model("grid_open.obj"), Method::Dual, r, false);
    }
}

/// Without `cage_maps` the three cage arrays stay empty and everything else is bit-identical
/// (both layouts, both structures, a closed and an open cage); carrying cage values over is then
/// a typed error, not an empty result.
#[test]
fn without_cage_maps_only_the_cage_arrays_are_empty() {
    for name in ["torus.obj", "grid_open.obj"] {
        let cage = model(name);
        for method in [Method::Dual, Method::Topology] {
            for layout in [Layout::Quads, Layout::Triangles] {
                let with = opts(method, layout, 2);
                let a = convert(&cage, &with, None).unwrap().mesh;
                let mut b = convert(&cage, &ConvertOptions { cage_maps: false, ..with }, None).unwrap().mesh;
                assert!(!a.cage_corner.is_empty() && !a.cage_coords.is_empty(), "{name} {method} {layout}");
                assert!(b.cage_corner.is_empty() && b.cage_coords.is_empty() && b.cage_loop_corner.is_empty(), "{name} {method} {layout}");
                let sizes: Vec<u32> = cage.faces.iter().map(|f| f.len() as u32).collect();
                let uv = vec![0.5f32; 2 * sizes.iter().sum::<u32>() as usize];
                assert!(a.cage_loop_values(&sizes, &uv, 2).is_ok(), "{name} {method} {layout}");
                assert_eq!(b.cage_loop_values(&sizes, &uv, 2), Err(gbsurf::tessellate::CageValuesError::NoCageMaps), "{name} {method} {layout}");
                b.cage_corner = a.cage_corner.clone();
                b.cage_coords = a.cage_coords.clone();
                b.cage_loop_corner = a.cage_loop_corner.clone();
                assert!(a == b, "{name} {method} {layout}: the mesh changed without the cage maps");
            }
        }
    }
}

/// Without `keep_surface` and/or `quality_arrays` (as the command line converts for OBJ and STL:
/// both off; `--curves`: the surface kept; PLY: the quality arrays kept) the surface is `None`
/// or the per-vertex patch ids, curvatures and G1 deviation and the per-triangle patch ids are
/// empty, and everything else (the rest of the mesh, the report but its time) is bit-identical:
/// both layouts, both structures, a subdivision method, a closed and an open cage.
#[test]
fn without_the_surface_and_quality_arrays_only_they_are_empty() {
    for name in ["torus.obj", "grid_open.obj"] {
        let cage = model(name);
        for method in [Method::Dual, Method::Topology, Method::CatmullClark] {
            for layout in [Layout::Quads, Layout::Triangles] {
                let with = opts(method, layout, 2);
                let a = convert(&cage, &with, None).unwrap();
                assert_eq!(a.surface.is_some(), method.is_patch_method(), "{name} {method} {layout}");
                let kept = [a.mesh.patch.len(), a.mesh.triangle_patch.len(), a.mesh.mean_curvature.len()];
                assert!(kept.iter().all(|&n| n > 0), "{name} {method} {layout}");
                for (keep_surface, quality_arrays) in [(false, false), (true, false), (false, true)] {
                    let without = ConvertOptions { keep_surface, quality_arrays, ..with.clone() };
                    let mut b = convert(&cage, &without, None).unwrap();
                    let what = format!("{name} {method} {layout} surface {keep_surface} quality {quality_arrays}");
                    assert_eq!(b.surface.is_some(), keep_surface && method.is_patch_method(), "{what}");
                    assert!(b.surface == a.surface || !keep_surface, "{what}: the surface changed");
                    let m = &mut b.mesh;
                    for v in [&m.mean_curvature, &m.gaussian_curvature, &m.g1_deviation_deg] {
                        assert_eq!(v.is_empty(), !quality_arrays, "{what}");
                    }
                    assert_eq!(m.patch.is_empty() && m.triangle_patch.is_empty(), !quality_arrays, "{what}");
                    m.patch = a.mesh.patch.clone();
                    m.triangle_patch = a.mesh.triangle_patch.clone();
                    m.mean_curvature = a.mesh.mean_curvature.clone();
                    m.gaussian_curvature = a.mesh.gaussian_curvature.clone();
                    m.g1_deviation_deg = a.mesh.g1_deviation_deg.clone();
                    assert!(a.mesh == b.mesh, "{what}: the mesh changed");
                    b.report.seconds = a.report.seconds;
                    assert_eq!(a.report, b.report, "{what}");
                    assert_eq!(a.warnings, b.warnings, "{what}");
                }
            }
        }
    }
}

/// `PatchLoops::patch_of` (which names the patch of a flipped triangle once the per-triangle
/// patch ids are gone) agrees with those ids on every triangle, and is `None` past the last: both
/// layouts, both structures, on a closed model and on a public cage with flipped triangles.
#[test]
fn patch_of_agrees_with_the_triangle_patch_ids() {
    let bishop = gbsurf::read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/opensubdiv/catmark_bishop.obj")).unwrap();
    for (name, cage) in [("torus", model("torus.obj")), ("bishop", bishop)] {
        for method in [Method::Dual, Method::Topology] {
            for layout in [Layout::Quads, Layout::Triangles] {
                let Ok(out) = convert(&cage, &opts(method, layout, 2), None) else { continue };
                let m = &out.mesh;
                assert_eq!(m.triangle_patch.len(), m.triangles.len(), "{name} {method} {layout}");
                for (t, &p) in m.triangle_patch.iter().enumerate() {
                    assert_eq!(m.patch_loops.patch_of(t), Some(p as usize), "{name} {method} {layout} triangle {t}");
                }
                assert_eq!(m.patch_loops.patch_of(m.triangles.len()), None, "{name} {method} {layout}");
                if name == "bishop" && method == Method::Dual {
                    assert!(!m.flipped_triangles.is_empty() || out.report.folds > 0, "{name} {method} {layout}: the bishop should fold");
                }
            }
        }
    }
}

/// A cube with one face's vertex list rotated: the corner index follows the list as written.
#[test]
fn corner_index_follows_the_face_list() {
    let mut cube = model("cube.obj");
    cube.faces[2].rotate_left(1);
    check("rotated cube", &cube, Method::Topology, 2, true);
    check("rotated cube", &cube, Method::Dual, 2, true);
}

#[test]
fn triangles_and_subdivision() {
    let cube = model("cube.obj");
    for method in [Method::Topology, Method::Dual] {
        let out = convert(&cube, &opts(method, Layout::Triangles, 3), None).unwrap();
        let m = &out.mesh;
        assert_eq!(m.cage_corner.len(), m.triangles.len());
        assert_eq!(m.cage_coords.len(), 3 * m.triangles.len());
        assert_eq!(m.cage_loop_corner.len(), 3 * m.triangles.len());
        for (c, &fc) in m.cage_corner.iter().zip(&m.face_corner) {
            assert!((c[0] as usize) < 6 && c[1] < 4, "{method}: {c:?} (patch corner {fc})");
        }
        // The quad layout has no per-loop cage corners.
        let quads = convert(&cube, &opts(method, Layout::Quads, 2), None).unwrap();
        assert!(quads.mesh.cage_loop_corner.is_empty());
    }
    for method in [Method::CatmullClark, Method::DooSabin] {
        let out = convert(&cube, &ConvertOptions { method, levels: 2, ..Default::default() }, None).unwrap();
        let m = &out.mesh;
        assert_eq!(m.cage_corner.len(), m.triangles.len());
        assert!(m.cage_coords.is_empty() && m.cage_loop_corner.is_empty());
        for (c, &t) in m.cage_corner.iter().zip(&m.triangle_patch) {
            assert_eq!(*c, [t, u32::MAX], "{method}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    /// Prisms (n-gon caps, quad sides) and tori of any size, both structures: the same checks.
    #[test]
    fn generated_cages(n in 3usize..8, major in 3usize..7, minor in 3usize..6, r in 1usize..4) {
        let prism = gbsurf::mesh::generate::prism(n).unwrap();
        check("prism", &prism, Method::Topology, r, true);
        check("prism", &prism, Method::Dual, r, true);
        let torus = gbsurf::mesh::generate::torus(major, minor, 2.0, 0.6).unwrap();
        check("torus", &torus, Method::Topology, r, true);
        check("torus", &torus, Method::Dual, r, true);
    }
}
