//! G1 of the constructed surfaces measured with the patch evaluators (GB for the dual structure,
//! CGB for the topology-preserving one): normals of the two patches along every shared side, and
//! the gap between their evaluations of the shared curve. Run with `--nocapture` for the table.

use gbsurf::construct::check::{corner_plane_angle, join_report};
use gbsurf::construct::{
    build_dual, build_topology, convex_mesh, dual_network, topology_network, Surface, TwistMode,
};
use gbsurf::ConvertOptions;
use gbsurf::gb::WeightForm;
use gbsurf::mesh::{read_mesh, HalfEdgeMesh};

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models");
const GOOD: &[&str] = &[
    "cube", "cube_corner_pulled", "cube_extruded", "cube_nonplanar", "dodecahedron", "grid_open", "house", "l_prism", "octahedron",
    "prism3", "pyramid", "star_prism", "torus",
];
const SAMPLES: usize = 17;

fn load(name: &str) -> HalfEdgeMesh {
    read_mesh(format!("{MODELS}/{name}.obj")).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn opts(t: TwistMode) -> ConvertOptions {
    ConvertOptions { twist: t, ..ConvertOptions::triangles_r8() }
}

fn build(structure: &str, m: &HalfEdgeMesh, mode: TwistMode) -> Surface {
    match structure {
        "dual" => build_dual(m, &opts(mode)).unwrap(),
        _ => build_topology(m, &opts(mode)).unwrap(),
    }
}

#[test]
fn blend_twists_are_g1_with_the_evaluator() {
    let mut failures = Vec::new();
    for name in GOOD {
        let m = load(name);
        for structure in ["dual", "topology"] {
            for mode in [TwistMode::Approx, TwistMode::Interp] {
                let s = build(structure, &m, mode);
                let r = join_report(&s, SAMPLES, WeightForm::Squared);
                println!(
                    "{name:14} {structure:8} {mode:?}: sides {:3}  max angle {:.3e}°  max gap {:.3e}  degenerate {}",
                    r.sides, r.angle_deg.value, r.gap.value, r.degenerate
                );
                if !(r.angle_deg.value <= 1e-4 && r.gap.value <= 1e-12 && r.degenerate == 0) {
                    failures.push(format!("{name} {structure} {mode:?}: {r:?}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn first_approximation_twists_report_g1_error() {
    let mut worst = Vec::new();
    for name in GOOD {
        let m = load(name);
        for structure in ["dual", "topology"] {
            let s = build(structure, &m, TwistMode::None);
            let r = join_report(&s, SAMPLES, WeightForm::Squared);
            println!("{name:14} {structure:8} None: max angle {:.3e}°  max gap {:.3e}", r.angle_deg.value, r.gap.value);
            assert!(r.gap.value <= 1e-12, "{name} {structure}: {r:?}");
            worst.push(((*name, structure), r.angle_deg.value));
        }
    }
    let get = |n: &str, s: &str| worst.iter().find(|((a, b), _)| *a == n && *b == s).unwrap().1;
    // Non-quadrilateral junctions: clearly not G1.
    for name in ["octahedron", "dodecahedron", "prism3"] {
        assert!(get(name, "dual") > 0.01, "{name}");
    }
    for name in ["dodecahedron", "cube"] {
        assert!(get(name, "topology") > 0.01, "{name}");
    }
    // Planar quads of valence 4 (torus): the first approximation is already G1 in both structures.
    assert!(get("torus", "dual") <= 1e-4);
    assert!(get("torus", "topology") <= 1e-4);
}

#[test]
fn corner_tangent_planes_are_the_node_planes() {
    // Dual nodes are face centroids; on planar faces the node plane is the face plane
    // (seed 000 §4.4.4), otherwise its best-fit plane. Topology nodes: the tile planes.
    for name in GOOD {
        let m = load(name);
        let (cm, _) = convex_mesh(&m).unwrap();
        for structure in ["dual", "topology"] {
            let o = opts(TwistMode::Interp);
            let net = if structure == "dual" { dual_network(&cm, &o) } else { topology_network(&cm, &o) }.unwrap();
            let s = build(structure, &m, TwistMode::Interp);
            let node = |p: usize, i: usize| {
                let side = net.patches[p].sides[i];
                Some(net.curve_nodes[side.curve][if side.reversed { 0 } else { 1 }])
            };
            let w = corner_plane_angle(&s, &net.node_normals, node, WeightForm::Squared);
            assert!(w.value < 1e-4, "{name} {structure}: {w:?}");
        }
    }
}
