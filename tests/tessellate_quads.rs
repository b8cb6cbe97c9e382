//! The quad layout (gb::layout, Layout::Quads): the domain split at its centre into n bilinear
//! sectors of r × r quads. Exact layout counts and orientation; on the shared models, the vertex
//! and face counts of Catmull–Clark level L at r = 2^(L−1) (topology structure on every quad
//! cage, dual structure on the torus); watertight, G1 and gap as in the triangle layout; the
//! triangle layout unchanged; the writers' face counts.

use gbsurf::api::{convert, convert_file, ConvertOptions, Method};
use gbsurf::gb::{Layout, SampleLayout, Sampling};
use gbsurf::mesh::PolyMesh;
use gbsurf::quality::check_mesh;
use proptest::prelude::*;
use std::collections::HashMap;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");

fn quads(method: Method, r: usize) -> ConvertOptions {
    ConvertOptions { method, layout: Layout::Quads, resolution: r, ..Default::default() }
}

fn model(name: &str) -> PolyMesh {
    gbsurf::api::read_mesh(format!("{MODELS}/{name}")).unwrap()
}

/// Directed edge counts of a face list: every undirected edge of a closed two-manifold appears
/// once in each direction.
fn edge_uses(faces: &[&[u32]]) -> HashMap<(u32, u32), usize> {
    let mut m = HashMap::new();
    for f in faces {
        for k in 0..f.len() {
            *m.entry((f[k], f[(k + 1) % f.len()])).or_insert(0) += 1;
        }
    }
    m
}

#[test]
fn layout_counts_orientation_and_boundary() {
    for n in 3..=8 {
        for r in 1..=5 {
            let l = SampleLayout::new(&SampleLayout::regular_polygon(n), Sampling::new(Layout::Quads, r)).unwrap_or_else(|e| panic!("{n} {r}: {e}"));
            let s = Sampling::new(Layout::Quads, r);
            assert_eq!(l.uv.len(), 1 + n * r * (r + 1));
            assert_eq!(l.uv.len(), s.sample_count(n));
            assert_eq!(l.quads.len(), n * r * r);
            assert_eq!(l.triangles.len(), 2 * n * r * r);
            assert_eq!(l.per_side(), 2 * r);
            assert_eq!(l.boundary_loop().len(), 2 * n * r);
            // Every quad counter-clockwise and convex in the domain.
            for q in &l.quads {
                for k in 0..4 {
                    let (a, b, c) = (l.uv[q[k] as usize], l.uv[q[(k + 1) % 4] as usize], l.uv[q[(k + 2) % 4] as usize]);
                    assert!((b - a).perp_dot(c - b) > 0.0, "n {n} r {r}: {q:?}");
                }
            }
            // Every sample used, interior edges twice (once each way), boundary edges once, in the
            // loop's direction.
            let faces: Vec<&[u32]> = l.quads.iter().map(|q| &q[..]).collect();
            let uses = edge_uses(&faces);
            let lp = l.boundary_loop();
            for (&(a, b), &c) in &uses {
                assert_eq!(c, 1, "n {n} r {r}");
                let boundary = uses.get(&(b, a)).is_none();
                assert_eq!(boundary, l.is_boundary(a as usize) && l.is_boundary(b as usize) && {
                    let i = lp.iter().position(|&x| x == a).unwrap();
                    lp[(i + 1) % lp.len()] == b
                });
            }
            assert_eq!(uses.len(), 4 * n * r * r);
            // Boundary samples at s = t/(2r) of each side, exactly the domain vertex at t = 0.
            let poly = SampleLayout::regular_polygon(n);
            for i in 0..n {
                let (a, b) = (poly[(i + n - 1) % n], poly[i]);
                assert_eq!(l.uv[l.boundary_index(i, 0)], a);
                for t in 1..2 * r {
                    let p = l.uv[l.boundary_index(i, t)];
                    assert!((p - (a + (b - a) * (t as f64 / (2 * r) as f64))).length() <= 1e-15);
                }
            }
            // Sector i's quads are i·r²..(i+1)·r², around domain vertex i.
            let corners = l.face_corners();
            for (k, &c) in corners.iter().enumerate() {
                assert_eq!(c as usize, k / (r * r));
                let q = l.quads[k];
                let centroid = q.iter().map(|&x| l.uv[x as usize]).sum::<gbsurf::DVec2>() / 4.0;
                let nearest = (0..n).min_by(|&x, &y| centroid.distance(poly[x]).total_cmp(&centroid.distance(poly[y]))).unwrap();
                assert_eq!(nearest, c as usize, "n {n} r {r} quad {k}");
            }
        }
    }
}

#[test]
fn triangle_layout_is_unchanged_by_a_bare_resolution() {
    for n in 3..=6 {
        for r in [1, 3, 8] {
            let a = SampleLayout::regular(n, r).unwrap();
            let b = SampleLayout::new(&SampleLayout::regular_polygon(n), Sampling::new(Layout::Triangles, r)).unwrap();
            assert_eq!(a.uv.len(), SampleLayout::sample_count(n, r));
            assert_eq!(a.triangles.len(), SampleLayout::triangle_count(n, r));
            assert!(a.quads.is_empty());
            assert_eq!(a.layout, Layout::Triangles);
            assert_eq!(b.uv.len(), a.uv.len());
            assert_eq!(a.first_boundary(), a.ring_index(r, 0, 0));
            assert_eq!(a.face_corners().len(), a.triangles.len());
        }
    }
}

/// Catmull–Clark level L of the cage: (vertices, faces).
fn cc_counts(mesh: &PolyMesh, levels: u32) -> (usize, usize) {
    let m = gbsurf::subdiv::catmull_clark(mesh, levels).unwrap();
    assert!(m.faces.iter().all(|f| f.len() == 4));
    (m.positions.len(), m.faces.len())
}

/// Both structures at r = 2^(L−1) have the vertex and face counts of Catmull–Clark level L on
/// every closed cage, not only on quad cages: the topology structure has one patch per face with
/// |f| sectors, the dual one patch per vertex with valence(v) sectors, and Σ|f| = Σ valence = 2E;
/// both have one mesh vertex per cage vertex, edge and face at r = 1 (patch centres and corners
/// are the cage's vertices and faces in one structure and its faces and vertices in the other),
/// and every sector quad is a face corner (f, v), as every quad of Catmull–Clark level 1. On an
/// open cage the dual structure differs: a boundary vertex's patch gets one more side (and
/// sector) than it has faces, so its counts exceed Catmull–Clark's.
#[test]
fn quad_layout_has_catmull_clark_counts() {
    let torus = gbsurf::mesh::generate::torus(8, 6, 2.0, 0.6).unwrap();
    let mut cages: Vec<(String, PolyMesh)> = std::fs::read_dir(MODELS)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), gbsurf::api::read_mesh(&p).unwrap()))
        .collect();
    cages.sort_by(|a, b| a.0.cmp(&b.0));
    cages.push(("generated torus 8×6".into(), torus));
    let quad_cages = ["cube.obj", "cube_corner_pulled.obj", "cube_extruded.obj", "cube_nonplanar.obj", "grid_open.obj", "torus.obj", "generated torus 8×6"];
    let mut checked = (0, 0);
    for (name, cage) in &cages {
        let closed = gbsurf::mesh::HalfEdgeMesh::from_polymesh(cage).unwrap().is_closed();
        for level in 1..=4u32 {
            let r = 1usize << (level - 1);
            let want = cc_counts(cage, level);
            let t = convert(cage, &quads(Method::Topology, r), None).unwrap();
            let d = convert(cage, &quads(Method::Dual, r), None).unwrap();
            let (tc, dc) = ((t.mesh.positions.len(), t.mesh.quads.len()), (d.mesh.positions.len(), d.mesh.quads.len()));
            assert_eq!(t.mesh.triangles.len(), 2 * t.mesh.quads.len());
            assert_eq!(t.mesh.face_corner.len(), t.mesh.quads.len());
            // The topology structure keeps one patch per face unless it splits a concave face.
            if t.report.patches == cage.faces.len() {
                assert_eq!(tc, want, "{name} topology L {level}");
                checked.0 += 1;
            }
            // The dual structure keeps one patch per vertex with one side per edge unless it
            // splits a concave face (l_prism, star_prism).
            let corners: usize = cage.faces.iter().map(|f| f.len()).sum();
            let sides: usize = d.report.sides_histogram.iter().map(|(n, c)| n.parse::<usize>().unwrap() * c).sum();
            if closed && d.report.patches == cage.positions.len() && sides == corners {
                assert_eq!(dc, want, "{name} dual L {level}");
                checked.1 += 1;
            } else if !closed {
                assert!(dc.0 > want.0 && dc.1 > want.1, "{name} dual L {level}: {dc:?} {want:?}");
            }
            if quad_cages.contains(&name.as_str()) {
                assert_eq!(t.report.patches, cage.faces.len(), "{name}");
                assert_eq!(tc, want, "{name} topology L {level}");
            }
        }
    }
    assert!(checked.0 >= 4 * 12 && checked.1 >= 4 * 9, "{checked:?}");
}

#[test]
fn quad_layout_is_watertight_g1_and_valid() {
    for entry in std::fs::read_dir(MODELS).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "obj") {
            continue;
        }
        let cage = gbsurf::mesh::read_mesh(&path).unwrap();
        for method in [Method::Dual, Method::Topology] {
            for r in [1, 2, 3] {
                let what = format!("{} {method} r {r}", path.display());
                let c = convert_file(&path, &quads(method, r), None).unwrap_or_else(|e| panic!("{what}: {e}"));
                let rep = &c.report;
                assert_eq!(rep.layout, "quads");
                assert_eq!(rep.quads, c.mesh.quads.len());
                assert!(rep.max_g1_deg <= 1e-4, "{what}: max G1 {}°", rep.max_g1_deg);
                assert!(rep.max_boundary_gap <= 1e-12, "{what}: gap {}", rep.max_boundary_gap);
                let faces: Vec<&[u32]> = c.mesh.quads.iter().map(|q| &q[..]).collect();
                let uses = edge_uses(&faces);
                assert!(uses.values().all(|&u| u == 1), "{what}");
                let open = uses.keys().filter(|&&(a, b)| !uses.contains_key(&(b, a))).count();
                assert_eq!(open == 0, cage.is_closed(), "{what}: {open} open quad edges");
                let chk = check_mesh(&c.mesh.positions, &c.mesh.triangles);
                assert!(chk.is_two_manifold(), "{what}");
                assert_eq!(chk.boundary_edges, open, "{what}");
                assert_eq!(rep.closed, cage.is_closed(), "{what}");
                assert_eq!(rep.folds, 0, "{what}");
                assert_eq!(rep.self_intersections, 0, "{what}");
                // Every quad's two triangles are in order.
                for (k, q) in c.mesh.quads.iter().enumerate() {
                    assert_eq!(c.mesh.triangles[2 * k], [q[0], q[1], q[2]]);
                    assert_eq!(c.mesh.triangles[2 * k + 1], [q[0], q[2], q[3]]);
                }
            }
        }
    }
}

#[test]
fn quad_and_triangle_layouts_agree_on_shared_samples() {
    // At triangle resolution 2r, the boundary samples are the same domain points: the surface
    // points on the patch boundaries coincide, so the G1 figures are measured on the same points.
    let path = format!("{MODELS}/dodecahedron.obj");
    for r in [1, 2, 4] {
        let q = convert_file(&path, &quads(Method::Dual, r), None).unwrap();
        let t = convert_file(&path, &ConvertOptions { layout: Layout::Triangles, resolution: 2 * r, ..Default::default() }, None).unwrap();
        assert_eq!(q.report.max_g1_deg, t.report.max_g1_deg);
        assert_eq!(q.report.max_boundary_gap, t.report.max_boundary_gap);
        assert_eq!(t.mesh.quads.len(), 0);
        assert_eq!(t.report.layout, "triangles");
    }
}

#[test]
fn writers_write_quads_obj_ply_and_triangles_stl() {
    let c = convert(&model("cube.obj"), &quads(Method::Topology, 2), None).unwrap();
    let m = &c.mesh;
    assert_eq!(m.quads.len(), 96);
    let mut obj = Vec::new();
    m.write_obj(&mut obj).unwrap();
    let obj = String::from_utf8(obj).unwrap();
    let f: Vec<&str> = obj.lines().filter(|l| l.starts_with("f ")).collect();
    assert_eq!(f.len(), 96);
    assert!(f.iter().all(|l| l.split_whitespace().count() == 5), "{}", f[0]);
    assert!(obj.starts_with(&format!("# gbsurf: {} vertices, 96 quads\n", m.positions.len())));
    let mut ply = Vec::new();
    m.write_ply(&mut ply).unwrap();
    let head = String::from_utf8_lossy(&ply[..400.min(ply.len())]).into_owned();
    assert!(head.contains("element face 96\n"), "{head}");
    let mut stl = Vec::new();
    m.write_stl(&mut stl).unwrap();
    assert_eq!(u32::from_le_bytes(stl[80..84].try_into().unwrap()), 192);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// Any strictly convex domain: every sample inside, every quad of positive area, and the
    /// quads' areas sum to the polygon's.
    #[test]
    fn quads_tile_any_convex_domain(n in 3usize..9, r in 1usize..6, wobble in proptest::collection::vec(0.7f64..1.0, 9)) {
        let poly: Vec<gbsurf::DVec2> = (0..n).map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            gbsurf::DVec2::new(a.cos(), a.sin()) * wobble[i]
        }).collect();
        let Ok(l) = SampleLayout::new(&poly, Sampling::new(Layout::Quads, r)) else { return Ok(()) };
        let area = |p: &[gbsurf::DVec2]| 0.5 * (0..p.len()).map(|k| p[k].perp_dot(p[(k + 1) % p.len()])).sum::<f64>();
        let total: f64 = l.quads.iter().map(|q| {
            let pts: Vec<_> = q.iter().map(|&x| l.uv[x as usize]).collect();
            let a = area(&pts);
            assert!(a > 0.0);
            a
        }).sum();
        prop_assert!((total - area(&poly)).abs() <= 1e-12 * area(&poly).max(1.0));
    }
}

/// `SampleLayout::sector_samples`, which the weight tables rely on (one sector's rows serve
/// all n): in both layouts the n sector lists and the centre are a partition of the samples,
/// and sample j of sector m is sample j of sector 0 turned by 2πm/n about the centre.
#[test]
fn sectors_partition_the_samples_and_turn_into_each_other() {
    for layout in [Layout::Triangles, Layout::Quads] {
        for n in 3..=9 {
            for r in 1..=6 {
                let domain = gbsurf::gb::Domain::regular(n).unwrap();
                let l = SampleLayout::for_domain(&domain, Sampling::new(layout, r)).unwrap();
                let mut seen = vec![0u32; l.uv.len()];
                seen[0] += 1;
                let first = l.sector_samples(0);
                let per = if layout == Layout::Quads { r * (r + 1) } else { r * (r + 1) / 2 };
                assert_eq!(first.len(), per);
                for m in 0..n {
                    let list = l.sector_samples(m);
                    assert_eq!(list.len(), per);
                    let (s, c) = (std::f64::consts::TAU * m as f64 / n as f64).sin_cos();
                    for (&g, &g0) in list.iter().zip(&first) {
                        seen[g as usize] += 1;
                        let p = l.uv[g0 as usize];
                        let turned = gbsurf::DVec2::new(c * p.x - s * p.y, s * p.x + c * p.y);
                        assert!((l.uv[g as usize] - turned).length() < 1e-14, "{layout:?} n {n} r {r} m {m}: {} vs {turned}", l.uv[g as usize]);
                    }
                }
                assert!(seen.iter().all(|&k| k == 1), "{layout:?} n {n} r {r}: {seen:?}");
            }
        }
    }
}
