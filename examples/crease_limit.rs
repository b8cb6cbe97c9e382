//! Where the dual crease split leaves the smooth surface as the sharpness tends to 0
//! (docs/math.md#dual-creases): `[ALL=1] cargo run --release --example crease_limit -- [MODEL.obj] [C]`.
//!
//! Builds the dual surface of MODEL (default: the shared cube) with sharp edges at sharpness C
//! (default 1e-9): a model's own crease tags, else the edges with both ends at z > 0 (the cube's
//! top loop), or with `ALL=1` every edge (vertices of three cut edges, spokes); and without crease
//! data (S₀), samples every patch of the creased surface on a grid of its domain and prints, per
//! patch that moved, the largest distance to S₀'s fine tessellation and where it is (side,
//! parameter along it, depth towards the centre). The largest of them is the step at c → 0.

use gbsurf::construct::{build_dual, PatchSource};
use gbsurf::gb::{Domain, Evaluate, WeightForm};
use gbsurf::mesh::{read_polymesh, HalfEdgeMesh, PolyMesh};
use gbsurf::{convert, ConvertOptions};
use parry3d_f64::math::Vector;
use parry3d_f64::query::PointQuery;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().cloned().unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/models/cube.obj").into());
    let c: f64 = args.get(1).map(|s| s.parse().expect("sharpness")).unwrap_or(1e-9);
    let (mut m, _): (PolyMesh, _) = read_polymesh(&path).expect("model");
    if m.creases.edges.is_empty() {
        // ALL=1: every edge (three cut edges at each cube vertex: spokes), else the top loop.
        let all = std::env::var("ALL").is_ok();
        let top = |a: u32| all || m.positions[a as usize].z > 0.0;
        let mut edges: Vec<[u32; 2]> = m
            .faces
            .iter()
            .flat_map(|f| (0..f.len()).map(move |i| [f[i].min(f[(i + 1) % f.len()]), f[i].max(f[(i + 1) % f.len()])]))
            .filter(|&[a, b]| top(a) && top(b))
            .collect();
        edges.sort();
        edges.dedup();
        m.creases.edges = edges.into_iter().map(|e| (e, 0.0)).collect();
    }
    m.creases.vertices.clear();
    let mut smooth = m.clone();
    smooth.creases = Default::default();
    for e in &mut m.creases.edges {
        e.1 = c;
    }
    let opts = ConvertOptions { resolution: 48, ..ConvertOptions::triangles_r8() };
    let fine = convert(&smooth, &opts, None).expect("smooth conversion");
    let v = |p: gbsurf::DVec3| Vector::new(p.x, p.y, p.z);
    let tri = parry3d_f64::shape::TriMesh::new(fine.mesh.positions.iter().map(|&p| v(p)).collect(), fine.mesh.triangles.clone()).unwrap();
    let s = build_dual(&HalfEdgeMesh::from_polymesh(&m).expect("mesh"), &ConvertOptions::triangles_r8()).expect("dual");
    let s0 = build_dual(&HalfEdgeMesh::from_polymesh(&smooth).expect("mesh"), &ConvertOptions::triangles_r8()).expect("dual");
    println!("{} patches creased, {} smooth; sharpness {c:e}", s.patches.len(), s0.patches.len());
    let mut rows = Vec::new();
    for (p, patch) in s.patches.iter().enumerate() {
        let n = patch.sides();
        let dom = Domain::regular(n).unwrap();
        let mut worst = (0.0f64, 0usize, 0.0f64, 0.0f64);
        for k in 0..n {
            for ti in 0..=16 {
                let t = ti as f64 / 16.0;
                for di in 0..=8 {
                    let depth = di as f64 / 8.0;
                    let q = dom.side_point(k, t);
                    let uv = q + depth * (dom.center() - q);
                    let x = patch.eval_derivs(uv, WeightForm::Squared).p;
                    let d = tri.distance_to_local_point(v(x), true);
                    if d > worst.0 {
                        worst = (d, k, t, depth);
                    }
                }
            }
        }
        let src = match s.sources[p] {
            PatchSource::Vertex(i) => format!("V{i}"),
            PatchSource::Face(i) => format!("F{i}"),
        };
        rows.push((worst.0, p, src, n, worst));
    }
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (d, p, src, n, w) in rows.iter().take(12) {
        println!("patch {p:3} ({src}, {n} sides): {d:.4} at side {} t = {:.3} depth {:.3}", w.1, w.2, w.3);
    }
    println!("step at c -> 0: {:.4}", rows.first().map_or(0.0, |r| r.0));
}
