//! Times a conversion and its validity checks separately on a quad torus:
//! `cargo run --release --example validity_timing -- [a b] [resolution] [dual|topology] [quads|triangles]`
//! (defaults: 100 × 100 quads, the default options of [`ConvertOptions::default`]: quad layout,
//! resolution 2, dual; `triangles` takes the triangle layout); a first argument ending in `.obj`
//! reads that model instead of the torus. `FOLD_LEVEL=L` overrides the fold sampling level of
//! the dense reference check ([`gbsurf::quality::find_folds`]), timed separately after the
//! conversion with and without its checks. The first line times the conversion with and
//! without its checks after a warm-up conversion, alternating, the best of `RUNS` (default 3).
//! `ONLY=checked|unchecked|none` runs one conversion (or none) and stops, for instruction counts.

use gbsurf::api::{convert, convert_unchecked, ConvertOptions, Method};
use gbsurf::mesh::generate::torus;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let num = |i: usize, d: usize| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (a, b) = (num(1, 100), num(2, 100));
    let mut opts = ConvertOptions::default();
    if args.get(5).map(String::as_str) == Some("triangles") {
        opts.layout = gbsurf::options::Layout::Triangles;
    }
    opts.resolution = num(3, opts.resolution);
    if args.get(4).map(String::as_str) == Some("topology") {
        opts.method = Method::Topology;
    }
    let file = args.get(1).filter(|s| s.ends_with(".obj"));
    let mesh = match file {
        Some(f) => gbsurf::read_mesh(f).expect("model"),
        None => torus(a, b, 10.0, 3.0).expect("torus"),
    };
    // `ONLY=checked|unchecked|none`: one conversion with or without its checks (or none), and
    // nothing else, for instruction counts (`valgrind --tool=callgrind`, all threads): the
    // checks' share is (checked − unchecked) / (unchecked − none).
    match std::env::var("ONLY").as_deref() {
        Ok("checked") => return drop(convert(&mesh, &opts, None).expect("conversion")),
        Ok("unchecked") => return drop(convert_unchecked(&mesh, &opts).expect("conversion")),
        Ok("none") => return,
        _ => {}
    }
    let level = std::env::var("FOLD_LEVEL")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(gbsurf::tessellate::fold::dense_level(opts.sampling()));
    // A warm-up conversion first (the thread pool's start and the first touch of fresh memory
    // otherwise fall on whichever conversion runs first), then `RUNS` (default 3) alternating
    // pairs, the best of each: the machine may be shared.
    // `WARMUP=0 RUNS=1` times as before the warm-up was added.
    if std::env::var("WARMUP").as_deref() != Ok("0") {
        drop(convert_unchecked(&mesh, &opts).expect("conversion"));
    }
    let runs = std::env::var("RUNS").ok().and_then(|s| s.parse().ok()).unwrap_or(3usize).max(1);
    let (mut total, mut t_bare, mut c) = (f64::INFINITY, f64::INFINITY, None);
    for _ in 0..runs {
        let t = Instant::now();
        let checked = convert(&mesh, &opts, None).expect("conversion");
        total = total.min(t.elapsed().as_secs_f64());
        drop(c.replace(checked));
        let t = Instant::now();
        let bare = convert_unchecked(&mesh, &opts).expect("conversion");
        t_bare = t_bare.min(t.elapsed().as_secs_f64());
        drop(bare);
    }
    let c = c.expect("at least one run");
    println!(
        "convert {total:.3} s, without checks {t_bare:.3} s (best of {runs}): checks (in-pass folds, self-intersections, cage) {:.3} s = {:.1} % [folds {}, dense fold passes {}, flipped {}, self-intersections {}]",
        total - t_bare,
        100.0 * (total - t_bare) / t_bare,
        c.report.folds,
        c.mesh.patch_folds.iter().filter(|f| f.dense).count(),
        c.report.flipped_triangles,
        c.report.self_intersections
    );
    let surface = c.surface.as_ref().expect("surface");
    phases(&mesh, &opts, &c);
    let t = Instant::now();
    let folds = gbsurf::quality::find_folds(surface, level, opts.weights);
    let t_folds = t.elapsed().as_secs_f64();
    let cpu = cpu_seconds();
    let t = Instant::now();
    let si_all = gbsurf::quality::self_intersections(&c.mesh.positions, &c.mesh.triangles);
    let t_si_all = t.elapsed().as_secs_f64();
    let cpu_all = cpu_seconds() - cpu;
    let cpu = cpu_seconds();
    let t = Instant::now();
    let cert = gbsurf::quality::Certified::of_mesh(&c.mesh);
    let t_cert = t.elapsed().as_secs_f64();
    let si = gbsurf::quality::self_intersections_certified(&c.mesh.positions, &c.mesh.triangles, &cert);
    let t_si = t.elapsed().as_secs_f64();
    let cpu_si = cpu_seconds() - cpu;
    assert_eq!(si, si_all, "the certificates changed the count");
    println!(
        "self-intersections [{si}]: all pairs {t_si_all:.3} s ({cpu_all:.3} s CPU); with certificates {t_si:.3} s ({cpu_si:.3} s CPU, certificates {t_cert:.3} s, {} of {} patches certified)",
        cert.certified_patches(),
        cert.patches()
    );
    let t = Instant::now();
    let ci = gbsurf::quality::cage_self_intersections(&mesh);
    let t_ci = t.elapsed().as_secs_f64();
    // The cage counts as a check only where `convert` runs it (the output self-intersects).
    let checks = t_folds + t_si + if si > 0 { t_ci } else { 0.0 };
    println!(
        "{a}x{b} r={} {}: {} triangles; convert {total:.3} s (checks {checks:.3} s: folds {t_folds:.3} [{}], self-intersections {t_si:.3} [{si}], cage {t_ci:.3} [{ci}], counted only with self-intersections); checks / (convert − checks) = {:.1} %",
        opts.resolution,
        opts.method.name(),
        c.mesh.triangles.len(),
        folds.patches,
        100.0 * checks / (total - checks)
    );
}

/// The checks of one conversion, phase by phase, as `convert` runs them on its output `c`:
/// the in-pass fold test (tessellation with it minus without it), the mesh check, the
/// self-intersection search (with its certificates), the cage search (timed always, counted in
/// the checks only when the output self-intersects, as `convert` runs it) and the curvature
/// maximum.
fn phases(mesh: &gbsurf::mesh::PolyMesh, opts: &ConvertOptions, c: &gbsurf::api::Conversion) {
    use gbsurf::tessellate::surface::tessellate_surface_checked;
    let surface = c.surface.as_ref().expect("surface");
    let time = |f: &mut dyn FnMut()| {
        let t = Instant::now();
        f();
        t.elapsed().as_secs_f64()
    };
    let tess = |folds: bool| {
        // Best of 2: the tessellation dominates and the machine is shared.
        (0..2)
            .map(|_| time(&mut || drop(tessellate_surface_checked(surface, opts.sampling(), opts.weights, folds, opts.cage_maps, true, None).expect("tessellation"))))
            .fold(f64::INFINITY, f64::min)
    };
    let (t_with, t_without) = (tess(true), tess(false));
    let m = &c.mesh;
    let mut check = gbsurf::quality::MeshCheck::default();
    let t_check = time(&mut || check = gbsurf::quality::check_mesh(&m.positions, &m.triangles));
    let closed = check.is_closed_manifold();
    let mut si = 0;
    let t_si = time(&mut || {
        let mut ticker = gbsurf::progress::Ticker::none();
        si = gbsurf::quality::validity::mesh_self_intersections_checked(m, &check, &mut ticker).expect("not cancelled")
    });
    let mut ci = 0;
    let t_cage = time(&mut || ci = gbsurf::quality::cage_self_intersections(mesh));
    let t_h = time(&mut || {
        std::hint::black_box(gbsurf::quality::validity::max_abs_mean_curvature_times_diagonal(&m.positions, &m.mean_curvature));
    });
    sub_phases(mesh, m, closed);
    let folds = t_with - t_without;
    // `convert` counts the cage only when the output self-intersects.
    let cage_run = if si > 0 { "" } else { ", not run by convert" };
    let checks = folds + t_si + if si > 0 { t_cage } else { 0.0 } + t_h;
    println!(
        "phases: tessellation {t_without:.3} s + in-pass folds {folds:.3} s; mesh check {t_check:.3} s; self-intersections {t_si:.3} s [{si}]; cage {t_cage:.3} s [{ci}{cage_run}]; |H| max {t_h:.4} s; checks {checks:.3} s = {:.1} % of convert {:.3} s, {:.1} % of the rest (mesh check counted as conversion)",
        100.0 * checks / c.report.seconds,
        c.report.seconds,
        100.0 * checks / (c.report.seconds - checks)
    );
}

/// The self-intersection checks' parts, each timed alone (best of 3): the star-shaped gate,
/// the certificates of the nodes, the certified search, the cage's convex split and its search.
fn sub_phases(cage: &gbsurf::mesh::PolyMesh, m: &gbsurf::tessellate::SurfaceMesh, closed: bool) {
    use gbsurf::quality::{certify, validity, Certified};
    let best = |f: &mut dyn FnMut()| {
        (0..3)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let t_gate = best(&mut || { std::hint::black_box(closed && certify::star_shaped_about_centroid(&m.positions, &m.triangles)); });
    let mut cert = Certified::none();
    let t_cert = best(&mut || cert = Certified::of_mesh(m));
    let free = validity::free_shells(&m.positions, &m.triangles);
    let t_free = best(&mut || drop(std::hint::black_box(validity::free_shells(&m.positions, &m.triangles))));
    drop(free);
    let t_search = best(&mut || { std::hint::black_box(validity::self_intersections_certified(&m.positions, &m.triangles, &cert)); });
    let mut convex = None;
    let t_split = best(&mut || convex = Some(gbsurf::mesh::geometry::convexify(cage)));
    let (convex, _) = convex.expect("split");
    let tris: Vec<[u32; 3]> = convex.faces.iter().flat_map(|f| (1..f.len().saturating_sub(1)).map(move |i| [f[0], f[i], f[i + 1]])).collect();
    let t_cage_search = best(&mut || { std::hint::black_box(validity::self_intersections(&convex.positions, &tris)); });
    println!(
        "self-intersection parts (best of 3): gate {t_gate:.4} s; certificates {t_cert:.4} s; free shells {t_free:.4} s; certified search {t_search:.4} s (with free shells); cage: convex split {t_split:.4} s, search {t_cage_search:.4} s"
    );
}

/// CPU seconds of this process (user + system, all threads) from /proc/self/stat; 0 elsewhere.
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else { return 0.0 };
    let Some(rest) = stat.rsplit(')').next() else { return 0.0 };
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| f.get(i).and_then(|s| s.parse::<f64>().ok()).unwrap_or(0.0);
    // Fields 14 and 15 (utime, stime) are at 11 and 12 after the command name; 100 ticks/s.
    (ticks(11) + ticks(12)) / 100.0
}
