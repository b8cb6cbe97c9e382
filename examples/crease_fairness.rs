//! Fairness of the crease curves of a converted cage:
//! `cargo run --release --example crease_fairness -- MODEL.obj [dual|topology]`.
//!
//! For every shared patch side with sharpness above 0 (a crease curve, each once) it samples the
//! curve's curvature κ = |c′ × c″| / |c′|³ and the crease angle θ (the angle between the two
//! patches' unit normals at the same curve point). Where two crease curves meet end to end it
//! compares their values at the join. Printed:
//! - `kappa jump`: the largest and the median of |κ_a − κ_b| / ((κ_a + κ_b)/2) over the joins;
//! - `theta range`: per crease curve the spread max θ − min θ over its samples and its two
//!   joins, largest and median, in degrees (a ring of equal cage edges should have an even θ);
//! - `theta jump`: the largest |θ_a − θ_b| at a join (0 for a continuous crease angle).
//!
//! `PROFILE=1` also prints θ along the curve with the largest spread and along a typical one;
//! `ALL=1` every curve whose spread exceeds 20°.

use gbsurf::construct::{Patch, Surface};
use gbsurf::gb::{Domain, Evaluate};
use gbsurf::{ConvertOptions, DVec3, Method};

fn curvature(c: &[DVec3], t: f64) -> f64 {
    let curve = gbsurf::bezier::BezierCurve::new(c.to_vec()).expect("curve");
    let d = curve.derivatives(t, 2);
    d[1].cross(d[2]).length() / d[1].length().powi(3)
}

/// Unit normal of patch `p` at parameter `t` of its side `i`.
fn side_normal(s: &Surface, p: usize, i: usize, t: f64, form: gbsurf::gb::WeightForm) -> DVec3 {
    let patch: &Patch = &s.patches[p];
    let dom = Domain::regular(patch.sides()).expect("domain");
    let uv = dom.side_point(i, t.clamp(1e-6, 1.0 - 1e-6));
    patch.normal(uv * (1.0 - 1e-9), form).unwrap_or(DVec3::ZERO)
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let file = args.get(1).expect("usage: crease_fairness MODEL.obj [dual|topology]");
    let mut opts = ConvertOptions::default();
    if args.get(2).map(String::as_str) == Some("topology") {
        opts.method = Method::Topology;
    }
    let mesh = gbsurf::read_mesh(file).expect("model");
    let c = gbsurf::convert(&mesh, &opts, None).expect("conversion");
    let s = c.surface.as_ref().expect("a GB surface");
    let form = opts.weights;
    struct Crease {
        pts: Vec<DVec3>,
        theta: Vec<f64>,
    }
    let samples = 16;
    let mut creases: Vec<Crease> = Vec::new();
    for (p, i, nb) in s.shared_sides() {
        if s.side_crease(p, i) <= 0.0 {
            continue;
        }
        let pts = s.patches[p].ribbons()[i].row(0).to_vec();
        let theta = (0..=samples)
            .map(|k| {
                let t = k as f64 / samples as f64;
                let a = side_normal(s, p, i, t, form);
                let b = side_normal(s, nb.patch, nb.side, 1.0 - t, form);
                a.dot(b).clamp(-1.0, 1.0).acos().to_degrees()
            })
            .collect();
        creases.push(Crease { pts, theta });
    }
    let key = |x: DVec3| [(x.x * 1e7).round() as i64, (x.y * 1e7).round() as i64, (x.z * 1e7).round() as i64];
    let mut ends: std::collections::HashMap<[i64; 3], Vec<(usize, bool)>> = Default::default();
    for (k, c) in creases.iter().enumerate() {
        ends.entry(key(c.pts[0])).or_default().push((k, false));
        ends.entry(key(*c.pts.last().unwrap())).or_default().push((k, true));
    }
    let end_kappa = |k: usize, last: bool| curvature(&creases[k].pts, if last { 1.0 } else { 0.0 });
    let end_theta = |k: usize, last: bool| if last { *creases[k].theta.last().unwrap() } else { creases[k].theta[0] };
    let (mut kj, mut tj) = (Vec::new(), Vec::new());
    for v in ends.values().filter(|v| v.len() == 2) {
        let (a, b) = (v[0], v[1]);
        let (ka, kb) = (end_kappa(a.0, a.1), end_kappa(b.0, b.1));
        kj.push((ka - kb).abs() / (0.5 * (ka + kb)).max(1e-300));
        tj.push((end_theta(a.0, a.1) - end_theta(b.0, b.1)).abs());
    }
    let ranges: Vec<f64> = creases
        .iter()
        .map(|c| {
            let (lo, hi) = c.theta.iter().fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
            hi - lo
        })
        .collect();
    let mean_theta = creases.iter().flat_map(|c| c.theta.iter()).sum::<f64>() / (creases.len() * (samples + 1)).max(1) as f64;
    println!(
        "{} crease curves, {} joins; kappa jump max {:.3} median {:.3}; theta range max {:.2}° median {:.2}° (mean theta {:.2}°); theta jump max {:.3}°; report: valid {}, folds {}, self-intersections {}",
        creases.len(),
        kj.len(),
        kj.iter().cloned().fold(0.0, f64::max),
        median(kj.clone()),
        ranges.iter().cloned().fold(0.0, f64::max),
        median(ranges.clone()),
        mean_theta,
        tj.iter().cloned().fold(0.0, f64::max),
        c.report.valid,
        c.report.folds,
        c.report.self_intersections
    );
    if std::env::var("PROFILE").is_ok() {
        let worst = (0..creases.len()).max_by(|&a, &b| ranges[a].total_cmp(&ranges[b])).unwrap_or(0);
        let med = median(ranges.clone());
        let typical = (0..creases.len()).min_by(|&a, &b| (ranges[a] - med).abs().total_cmp(&(ranges[b] - med).abs())).unwrap_or(0);
        for k in [worst, typical] {
            let t: Vec<String> = creases[k].theta.iter().map(|x| format!("{x:.1}")).collect();
            println!("theta along curve {k}: {}", t.join(" "));
        }
    }
    if std::env::var("ALL").is_ok() {
        for (k, c) in creases.iter().enumerate().filter(|(k, _)| ranges[*k] > 20.0) {
            let t: Vec<String> = c.theta.iter().map(|x| format!("{x:.0}")).collect();
            println!("curve {k} from {:.3} to {:.3}: {}", c.pts[0], c.pts[c.pts.len() - 1], t.join(" "));
        }
    }
    for w in &c.warnings {
        println!("warning: {w}");
    }
}
