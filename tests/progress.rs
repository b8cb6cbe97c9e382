//! Progress and cancellation of every method (gbsurf::progress, threaded through the pipeline):
//! the fractions start at 0, never decrease, end at 1 and advance in small steps (a structural
//! bound on the interval between reports: no stage runs long without a report); a cancel at 50 %
//! returns Cancelled and the callback is never called after it returned false. No timed asserts:
//! examples/progress_timing.rs measures the intervals and cancel latencies in seconds.

use gbsurf::api::{convert, ConvertError, ConvertOptions, Method};
use gbsurf::mesh::generate::{torus, uv_sphere};
use gbsurf::mesh::PolyMesh;
use gbsurf::progress::{chunk_size, Cancelled, Ticker, STEP};
use proptest::prelude::*;

const METHODS: [Method; 4] = [Method::Dual, Method::Topology, Method::DooSabin, Method::CatmullClark];

/// Largest allowed step of the fraction between two consecutive reports.
const MAX_GAP: f32 = 0.05;

fn options(method: Method) -> ConvertOptions {
    ConvertOptions { method, resolution: 4, levels: 2, ..Default::default() }
}

/// The fractions reported by a full conversion.
fn fractions(mesh: &PolyMesh, method: Method) -> Vec<f32> {
    let mut seen = Vec::new();
    let mut cb = |f: f32| {
        seen.push(f);
        true
    };
    convert(mesh, &options(method), Some(&mut cb)).expect("conversion");
    seen
}

fn largest_gap(seen: &[f32]) -> f32 {
    seen.windows(2).map(|w| w[1] - w[0]).fold(0.0, f32::max)
}

fn inputs() -> Vec<(&'static str, PolyMesh)> {
    vec![("torus 24x24", torus(24, 24, 10.0, 3.0).unwrap()), ("sphere 24x12", uv_sphere(24, 12).unwrap())]
}

#[test]
fn every_method_reports_from_0_to_1_in_small_steps() {
    for (name, mesh) in inputs() {
        for method in METHODS {
            let seen = fractions(&mesh, method);
            assert_eq!(seen.first(), Some(&0.0), "{name} {method}");
            assert_eq!(seen.last(), Some(&1.0), "{name} {method}");
            assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{name} {method}: not monotone: {seen:?}");
            assert!(seen.iter().all(|f| (0.0..=1.0).contains(f)), "{name} {method}: {seen:?}");
            let gap = largest_gap(&seen);
            assert!(gap <= MAX_GAP, "{name} {method}: largest step {gap} > {MAX_GAP} in {} reports: {seen:?}", seen.len());
            // At least one report per STEP on average over the run, at most a few per STEP.
            assert!(seen.len() >= 20, "{name} {method}: only {} reports", seen.len());
        }
    }
}

#[test]
fn a_cancel_at_half_stops_every_method_at_once() {
    for (name, mesh) in inputs() {
        for method in METHODS {
            let (mut calls, mut after) = (0usize, 0usize);
            let mut stopped = false;
            let mut cb = |f: f32| {
                calls += 1;
                if stopped {
                    after += 1;
                }
                if f >= 0.5 {
                    stopped = true;
                    return false;
                }
                true
            };
            let r = convert(&mesh, &options(method), Some(&mut cb));
            assert!(matches!(r, Err(ConvertError::Cancelled)), "{name} {method}: {r:?}");
            assert!(stopped, "{name} {method}: never reached 0.5");
            assert_eq!(after, 0, "{name} {method}: {after} calls after the cancel");
            assert!(calls >= 10, "{name} {method}: {calls} calls");
        }
    }
}

#[test]
fn a_cancel_in_every_stage_returns_cancelled() {
    // Cancelling at each reported fraction in turn: every stage's cancel path is taken.
    let mesh = torus(12, 12, 10.0, 3.0).unwrap();
    for method in METHODS {
        let seen = fractions(&mesh, method);
        for (k, &stop) in seen.iter().enumerate().step_by(3) {
            let mut n = 0;
            let mut cb = |_f: f32| {
                n += 1;
                n <= k
            };
            let r = convert(&mesh, &options(method), Some(&mut cb));
            assert!(matches!(r, Err(ConvertError::Cancelled)), "{method} at report {k} ({stop}): {r:?}");
            assert_eq!(n, k + 1, "{method} at report {k}: called after the cancel");
        }
    }
}

#[test]
fn progress_does_not_change_the_output() {
    let mesh = uv_sphere(16, 8).unwrap();
    for method in METHODS {
        let quiet = convert(&mesh, &options(method), None).unwrap();
        let mut cb = |_f: f32| true;
        let ticked = convert(&mesh, &options(method), Some(&mut cb)).unwrap();
        assert_eq!(quiet.mesh, ticked.mesh, "{method}");
        assert_eq!(quiet.surface, ticked.surface, "{method}");
    }
}

#[test]
fn uv_sphere_is_a_closed_oriented_sphere() {
    let m = uv_sphere(8, 5).unwrap();
    assert_eq!(m.faces.len(), 40);
    assert_eq!(m.positions.len(), 2 + 8 * 4);
    let he = gbsurf::mesh::HalfEdgeMesh::from_polymesh(&m).unwrap();
    assert!(he.is_closed());
    // Outward: positive signed volume (Σ over fan triangles of det / 6).
    let vol: f64 = m
        .faces
        .iter()
        .flat_map(|f| (1..f.len() - 1).map(move |i| [f[0], f[i], f[i + 1]]))
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    assert!(vol > 0.0 && vol < 4.0 / 3.0 * std::f64::consts::PI, "{vol}");
    assert!(uv_sphere(2, 5).is_err() && uv_sphere(8, 1).is_err());
}

#[test]
fn ticker_maps_ranges_and_stops_after_false() {
    let mut seen = Vec::new();
    let mut cb = |f: f32| {
        seen.push(f);
        f < 0.7
    };
    let mut t = Ticker::new(Some(&mut cb));
    t.stage(0.2, 0.6).unwrap();
    t.within(0.5, 1.0, |t| {
        for i in 0..=100 {
            t.at(i, 100)?;
        }
        Ok::<_, Cancelled>(())
    })
    .unwrap();
    // Nested range [0.4, 0.6]: reports 0.4 .. 0.6 in steps of at least STEP.
    t.stage(0.6, 1.0).unwrap();
    assert_eq!(t.at(50, 100), Err(Cancelled)); // 0.8 ≥ 0.7: the callback says stop
    assert_eq!(t.report(0.9), Err(Cancelled));
    assert_eq!(t.at(100, 100), Err(Cancelled));
    drop(t);
    let near = |a: f32, b: f32| (a - b).abs() < 1e-6;
    assert!(near(seen[0], 0.2) && near(seen[1], 0.4), "{seen:?}");
    assert!(near(seen[seen.len() - 2], 0.6), "{seen:?}");
    assert!(near(seen[seen.len() - 1], 0.8), "{seen:?}");
    assert!(seen.windows(2).all(|w| w[0] <= w[1]));
    assert!(seen[1..seen.len() - 2].windows(2).all(|w| w[1] - w[0] >= STEP - 1e-6), "{seen:?}");
    let mut none = Ticker::none();
    assert_eq!(none.at(5, 10), Ok(()));
}

proptest! {
    #[test]
    fn chunks_cover_the_loop_in_enough_ticks(n in 0usize..100_000, max in 1usize..10_000) {
        let c = chunk_size(n, max);
        prop_assert!(c >= 1 && c <= max);
        prop_assert!(n.div_ceil(c) >= n.min(gbsurf::progress::TICKS_PER_LOOP).min(n.div_ceil(max)));
    }

    #[test]
    fn reports_never_decrease(steps in proptest::collection::vec((0usize..5, 0usize..=20), 1..60)) {
        let mut seen = Vec::new();
        let mut cb = |f: f32| { seen.push(f); true };
        let mut t = Ticker::new(Some(&mut cb));
        for (stage, done) in steps {
            let lo = stage as f32 / 5.0;
            if done == 0 { t.stage(lo, lo + 0.2).unwrap(); }
            t.at(done, 20).unwrap();
        }
        drop(t);
        prop_assert!(seen.windows(2).all(|w| w[0] <= w[1]));
        prop_assert!(seen.iter().all(|f| (0.0..=1.0).contains(f)));
    }
}

/// `n` separate planar L-shaped hexagons (one reflex corner each), every face its own vertices.
fn l_shapes(n: usize) -> PolyMesh {
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for i in 0..n {
        let o = glam::DVec3::new((i % 100) as f64 * 3.0, (i / 100) as f64 * 3.0, 0.0);
        let base = positions.len() as u32;
        for (x, y) in [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)] {
            positions.push(o + glam::DVec3::new(x, y, 0.0));
        }
        faces.push((base..base + 6).collect());
    }
    PolyMesh::new(positions, faces)
}

#[test]
fn convexify_ticks_cancels_and_keeps_the_per_face_order() {
    use gbsurf::mesh::geometry::{convex_split, convexify, convexify_ticked};
    let mesh = l_shapes(5000);
    let mut seen = Vec::new();
    let mut cb = |f: f32| {
        seen.push(f);
        true
    };
    let (split, origin) = convexify_ticked(&mesh, &mut Ticker::new(Some(&mut cb))).unwrap();
    assert!(seen.len() >= 20 && seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
    assert!(seen[seen.len() - 1] > 1.0 - 2.0 * gbsurf::progress::STEP, "{seen:?}");
    // The reference: each face's pieces in face order.
    let (mut faces, mut from) = (Vec::new(), Vec::new());
    for (f, face) in mesh.faces.iter().enumerate() {
        let pts: Vec<glam::DVec3> = face.iter().map(|&i| mesh.positions[i as usize]).collect();
        for piece in convex_split(&pts, face) {
            faces.push(piece.iter().map(|&k| face[k]).collect::<Vec<u32>>());
            from.push(f as u32);
        }
    }
    assert_eq!(split.faces.len(), 2 * mesh.faces.len());
    assert_eq!((&split.faces, &origin), (&faces, &from));
    assert_eq!(convexify(&mesh), (split, origin));
    let mut calls = 0;
    let mut stop = |_: f32| {
        calls += 1;
        calls < 3
    };
    assert_eq!(convexify_ticked(&mesh, &mut Ticker::new(Some(&mut stop))), Err(Cancelled));
    assert_eq!(calls, 3, "called again after it returned false");
}

#[test]
fn check_mesh_ticks_through_the_per_vertex_pass_and_cancels() {
    use gbsurf::quality::{check_mesh, check_mesh_ticked};
    let quads = torus(200, 100, 10.0, 3.0).unwrap();
    let tris: Vec<[u32; 3]> = quads.faces.iter().flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]]).collect();
    let mut seen = Vec::new();
    let mut cb = |f: f32| {
        seen.push(f);
        true
    };
    let c = check_mesh_ticked(&quads.positions, &tris, &mut Ticker::new(Some(&mut cb))).unwrap();
    assert_eq!(c, check_mesh(&quads.positions, &tris));
    assert!(c.is_clean_closed() && c.euler_characteristic == 0, "{c:?}");
    // The per-vertex pass is [3/6, 5/6] of the range: many reports inside it.
    let inside = seen.iter().filter(|&&f| f > 0.5 + 1e-6 && f < 5.0 / 6.0 - 1e-6).count();
    assert!(inside >= 10, "{seen:?}");
    let mut stop = |f: f32| f < 0.6;
    assert_eq!(check_mesh_ticked(&quads.positions, &tris, &mut Ticker::new(Some(&mut stop))), Err(Cancelled));
}

#[test]
fn a_cancel_in_the_dense_fold_pass_returns_cancelled() {
    // The rook's dual leaves 153 of its 1088 patches uncleared (docs/math.md#fold-clearing), so
    // the dense pass runs in many chunks and ticks between them: in the tessellation stage
    // (0.08..0.45 of the whole, `GB_STAGES` of the api) it owns 0.8..0.9, so 0.376..0.413 overall.
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/opensubdiv/catmark_rook.obj");
    let mesh = gbsurf::mesh::read_polymesh(path).unwrap().0;
    let opts = ConvertOptions { method: Method::Dual, ..Default::default() };
    let (lo, hi) = (0.08 + 0.37 * 0.8, 0.08 + 0.37 * 0.9);
    let inside = |f: f32| f > lo + 1e-4 && f < hi - 1e-4;
    let mut seen = Vec::new();
    let mut cb = |f: f32| {
        seen.push(f);
        true
    };
    convert(&mesh, &opts, Some(&mut cb)).unwrap();
    assert!(seen.iter().any(|&f| inside(f)), "no report inside the dense pass: {seen:?}");
    let (mut stopped, mut after) = (false, 0);
    let mut cb = |f: f32| {
        if stopped {
            after += 1;
        }
        if inside(f) {
            stopped = true;
            return false;
        }
        true
    };
    let r = convert(&mesh, &opts, Some(&mut cb));
    assert!(matches!(r, Err(ConvertError::Cancelled)), "{r:?}");
    assert!(stopped && after == 0, "stopped {stopped}, {after} calls after the cancel");
}

/// The fair middle constraint's step (docs/math.md#fair-middle) ticks inside its share of the
/// assembly, [0.4, 0.5] (its closed form and its fold guard each in chunks), and a cancel there
/// returns Cancelled without a further call. Before it ticked, the 50k-face UV sphere (topology)
/// went 0.44 s without a report there (examples/progress_timing with MIDDLE=fair).
#[test]
fn the_fair_middle_step_ticks_and_cancels() {
    use gbsurf::construct::{dual_network, network::assemble_ticked, prepare, ConstructError};
    use gbsurf::Middle;
    let mesh = torus(24, 24, 10.0, 3.0).unwrap();
    let he = gbsurf::mesh::HalfEdgeMesh::from_polymesh(&mesh).unwrap();
    let prep = prepare(&he).unwrap();
    let opts = ConvertOptions { middle: Middle::Fair, ..Default::default() };
    let net = dual_network(&prep.mesh, &opts).unwrap();
    let mut seen = Vec::new();
    let mut cb = |f: f32| {
        seen.push(f);
        true
    };
    assemble_ticked(&net, &opts, &mut Ticker::new(Some(&mut cb))).unwrap();
    let inside = seen.iter().filter(|&&f| f > 0.4 && f < 0.5).count();
    assert!(inside >= 5, "{inside} reports inside the fair step: {seen:?}");
    // With the seed's rule nothing runs there: the reports inside come from the fair step.
    let mut seed_seen = Vec::new();
    let mut cb = |f: f32| {
        seed_seen.push(f);
        true
    };
    let seed_opts = ConvertOptions { middle: Middle::Seed, ..opts.clone() };
    assemble_ticked(&net, &seed_opts, &mut Ticker::new(Some(&mut cb))).unwrap();
    assert!(!seed_seen.iter().any(|&f| f > 0.4 && f < 0.5), "{seed_seen:?}");
    let stop = *seen.iter().find(|&&f| f > 0.42).unwrap();
    assert!(stop < 0.5, "{seen:?}");
    let (mut after, mut stopped) = (0, false);
    let mut cb = |f: f32| {
        after += usize::from(stopped);
        stopped |= f >= stop;
        !stopped
    };
    let r = assemble_ticked(&net, &opts, &mut Ticker::new(Some(&mut cb)));
    assert!(matches!(r, Err(ConstructError::Cancelled)), "{r:?}");
    assert_eq!(after, 0);
}
