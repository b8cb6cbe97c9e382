//! Where and why converted cages fold: `cargo run --release --example fold_study -- CAGE.obj... `.
//! Per cage and structure (dual, topology) prints folded patches and self-intersecting pairs;
//! with `DUMP=1` one line per folded patch: its cage element, valence / face sizes, whether the
//! cage itself folds there, the largest cage dihedral angle around it and the worst domain point.
//! `CENTRE=1` adds, per folded patch, the angles between the normal at its worst point and each
//! side's reference normal (the fold rule's T × X at the side's middle); `FINE=1` samples each
//! folded patch densely (80 steps per radius) and prints the smallest dot of neighbouring unit
//! normals and min/max |S_u × S_v|: a Jacobian sign change shows as a dot near −1 and a ratio
//! near 0, a patch that only bends more than 90° from a side's reference keeps both away from it.
//! Options from the environment: FULLNESS, DEPTH, TWIST (none|approx|interp), MID, RES (resolution),
//! METHOD.

#[path = "common/fine.rs"]
mod fine;

use gbsurf::construct::PatchSource;
use gbsurf::mesh::geometry::newell_normal;
use gbsurf::mesh::{FaceId, HalfEdgeMesh, VertexId};
use gbsurf::gb::Evaluate;
use gbsurf::{ConvertOptions, DVec3, Method, Twist};

fn env(name: &str) -> Option<f64> {
    std::env::var(name).ok().and_then(|s| s.parse().ok())
}

fn main() {
    let mut opts = ConvertOptions::default();
    if let Some(k) = env("FULLNESS") {
        opts.fullness = k;
    }
    if let Some(w) = env("DEPTH") {
        opts.tile_depth = w;
    }
    if let Some(m) = env("MID") {
        opts.mid_scale = m;
    }
    if let Some(r) = env("RES") {
        opts.resolution = r as usize;
    }
    match std::env::var("TWIST").as_deref() {
        Ok("none") => opts.twist = Twist::None,
        Ok("approx") => opts.twist = Twist::Approx,
        _ => {}
    }
    let dump = std::env::var("DUMP").is_ok();
    let methods: Vec<Method> = match std::env::var("METHOD").as_deref() {
        Ok("dual") => vec![Method::Dual],
        Ok("topology") => vec![Method::Topology],
        _ => vec![Method::Dual, Method::Topology],
    };
    for file in std::env::args().skip(1) {
        let poly = match gbsurf::read_mesh(&file) {
            Ok(m) => m,
            Err(e) => {
                println!("{file}: {e}");
                continue;
            }
        };
        let he = HalfEdgeMesh::from_polymesh(&poly).expect("half-edge mesh");
        let fnorm: Vec<DVec3> = he
            .faces()
            .map(|f| newell_normal(&he.face_vertices(f).map(|v| he.position(v)).collect::<Vec<_>>()).normalize_or_zero())
            .collect();
        let cage_fold = gbsurf::quality::validity::cage_fold_vertices(&he);
        let name = std::path::Path::new(&file).file_stem().unwrap().to_string_lossy().into_owned();
        for &method in &methods {
            let o = ConvertOptions { method, ..opts };
            match gbsurf::convert(&poly, &o, None) {
                Err(e) => println!("{name:24} {:8} error: {e}", method.name()),
                Ok(c) => {
                    let r = &c.report;
                    let g1 = r.max_g1_deg;
                    println!(
                        "{name:24} {:8} folds {:3} selfint {:4} (input {:3}) valid {} |H|diag {:.2} g1 {:.2e}",
                        method.name(),
                        r.folds,
                        r.self_intersections,
                        r.input_self_intersections.map_or("not checked".to_string(), |n| n.to_string()),
                        r.valid,
                        r.max_abs_mean_curvature_times_diagonal,
                        g1
                    );
                    if !dump {
                        continue;
                    }
                    let s = c.surface.as_ref().unwrap();
                    for (p, pf) in c.mesh.patch_folds.iter().enumerate() {
                        let f = pf;
                        if f.samples == 0 {
                            continue;
                        }
                        let w = f.worst.unwrap_or_default();
                        if std::env::var("CENTRE").is_ok() {
                            let patch = &s.patches[p];
                            let cn = patch.normal(w, o.weights).unwrap_or(DVec3::ZERO);
                            let refs: Vec<DVec3> = patch.ribbons().iter().map(|r| gbsurf::tessellate::fold::ribbon_normal(r, 0.5)).collect();
                            let a: Vec<String> = refs.iter().map(|r| format!("{:.0}", cn.dot(*r).clamp(-1.0, 1.0).acos().to_degrees())).collect();
                            let mean = refs.iter().copied().sum::<DVec3>().normalize_or_zero();
                            let spread = refs.iter().map(|r| r.dot(mean).clamp(-1.0, 1.0).acos().to_degrees()).fold(0.0, f64::max);
                            println!("    worst-normal vs side-mid refs {:?}; refs spread {:.0}; vs mean ref {:.0}", a, spread, cn.dot(mean).clamp(-1.0, 1.0).acos().to_degrees());
                        }
                        if std::env::var("FINE").is_ok() {
                            let (min_dot, _, ratio) = fine::neighbour_normals(&s.patches[p], o.weights, 80);
                            println!("    fine: min neighbour normal dot {:.3}, min/max |Su x Sv| {:.2e}", min_dot, ratio);
                        }
                        match s.sources[p] {
                            PatchSource::Vertex(v) => {
                                let v = VertexId(v as u32);
                                let sizes: Vec<usize> = he.vertex_faces(v).map(|f| he.face_size(f)).collect();
                                let dih = he
                                    .vertex_outgoing(v)
                                    .filter_map(|h| Some((he.face(h)?, he.face(he.twin(h))?)))
                                    .map(|(a, b)| fnorm[a.idx()].dot(fnorm[b.idx()]).clamp(-1.0, 1.0).acos().to_degrees())
                                    .fold(0.0, f64::max);
                                println!(
                                    "  patch {p:4} vertex {:4} valence {} faces {:?} cage-fold {} max dihedral {:5.1} samples {:3} worst ({:.2},{:.2}) |uv| {:.2}",
                                    v.idx(),
                                    he.valence(v),
                                    sizes,
                                    cage_fold[v.idx()],
                                    dih,
                                    f.samples,
                                    w.x,
                                    w.y,
                                    w.length()
                                );
                            }
                            PatchSource::Face(fi) => {
                                // `fi` is the face as written; the half-edge mesh holds its
                                // pieces (a face with holes is split there): the line covers them
                                // all, the dihedral only across edges to other input faces.
                                let pieces: Vec<FaceId> = he.faces().filter(|&g| he.input_face(g) == fi).collect();
                                let hs: Vec<_> = pieces.iter().flat_map(|&g| he.face_halfedges(g)).collect();
                                let mut vs: Vec<VertexId> = hs.iter().map(|&h| he.origin(h)).collect();
                                vs.sort_by_key(|v| v.idx());
                                vs.dedup();
                                let val: Vec<usize> = vs.iter().map(|&v| he.valence(v)).collect();
                                let outer = |h: &&_| he.face(he.twin(**h)).is_none_or(|g| he.input_face(g) != fi);
                                let lens: Vec<f64> = hs.iter().filter(outer).map(|&h| (he.position(he.target(h)) - he.position(he.origin(h))).length()).collect();
                                let aspect = lens.iter().cloned().fold(0.0, f64::max) / lens.iter().cloned().fold(f64::MAX, f64::min);
                                let dih = hs
                                    .iter()
                                    .filter(outer)
                                    .filter_map(|&h| Some((he.face(h)?, he.face(he.twin(h))?)))
                                    .map(|(a, b)| fnorm[a.idx()].dot(fnorm[b.idx()]).clamp(-1.0, 1.0).acos().to_degrees())
                                    .fold(0.0, f64::max);
                                let cf: Vec<bool> = vs.iter().map(|v| cage_fold[v.idx()]).collect();
                                println!(
                                    "  patch {p:4} face {fi:4} ({} pieces) sides {} valences {:?} aspect {:.1} cage-fold {:?} max dihedral {:5.1} samples {:3} worst ({:.2},{:.2}) |uv| {:.2}",
                                    pieces.len(),
                                    vs.len(),
                                    val,
                                    aspect,
                                    cf,
                                    dih,
                                    f.samples,
                                    w.x,
                                    w.y,
                                    w.length()
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
