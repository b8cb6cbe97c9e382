//! Where the mean curvature of the GB surfaces of the sphere cages of `scripts/bench_fairness`
//! departs from a sphere's: `cargo run --release --example sphere_fairness [-- TOP]`.
//!
//! For the UV sphere (32 × 16), the ico sphere (2 splits) and the quad sphere (4 × 4) and both
//! structures, every patch is sampled densely on its domain (per fan triangle (centre, v_{i−1},
//! v_i) of the regular n-gon a barycentric grid, boundary excluded) and the analytic mean
//! curvature H is compared with the sphere's −1/R (R the mean distance of the samples from the
//! origin; docs/math.md §1.9). Printed per cage and structure:
//! - max |r/R − 1| and the p99 / max of |H·R + 1| over the samples;
//! - per patch kind (n sides, what the patch stands for: the valence of its vertex or the sides of
//!   its face): the count, the largest |H·R + 1| with its sign (`flat`: H·R + 1 > 0, less curved
//!   than the sphere; `curved`: more curved) and where in the domain it is (`centre`: |x| < ⅓ of
//!   the way to the boundary; `corner`: within ¼ of a side length of a domain vertex; `side`:
//!   beyond ⅔ of the way; `middle` otherwise);
//! - the TOP (default 5) worst patches with their source element and its position.

use gbsurf::construct::{Patch, PatchSource, Surface};
use gbsurf::gb::{Domain, Evaluate, WeightForm};
use gbsurf::mesh::generate::{ico_sphere, quad_sphere, uv_sphere};
use gbsurf::mesh::PolyMesh;
use gbsurf::{ConvertOptions, DVec3, Method};
use glam::DVec2;
use std::collections::BTreeMap;

/// Interior domain points of an n-sided patch: per fan triangle (0, v_{i−1}, v_i) the points
/// (a·v_{i−1} + b·v_i)/m with a, b ≥ 0, a + b < m, excluding the boundary (a + b = m).
fn domain_samples(dom: &Domain, m: usize) -> Vec<DVec2> {
    let n = dom.n();
    let mut out = vec![DVec2::ZERO];
    for i in 0..n {
        let (p, q) = (dom.vertex(i + n - 1), dom.vertex(i));
        for a in 1..m {
            for b in 0..m - a {
                out.push((a as f64 * p + b as f64 * q) / m as f64);
            }
        }
    }
    out
}

/// Where `uv` lies in the domain (see the module doc).
fn place(dom: &Domain, uv: DVec2) -> &'static str {
    let n = dom.n();
    let side = dom.vertex(0).distance(dom.vertex(1));
    if (0..n).any(|i| dom.vertex(i).distance(uv) < 0.25 * side) {
        return "corner";
    }
    // Fraction of the way to the boundary along the ray from the centre.
    let inradius = 0.5 * (dom.vertex(0) + dom.vertex(1)).length();
    let circum = dom.vertex(0).length();
    let angle = uv.y.atan2(uv.x);
    let rho = (0..n)
        .map(|i| {
            let (p, q) = (dom.vertex(i + n - 1), dom.vertex(i));
            let dir = DVec2::new(angle.cos(), angle.sin());
            // Ray t·dir meets the side line: t = (p × q)/(dir × (q − p)).
            let den = dir.perp_dot(q - p);
            if den.abs() < 1e-14 {
                f64::INFINITY
            } else {
                let t = p.perp_dot(q) / den;
                if t > 0.0 {
                    t
                } else {
                    f64::INFINITY
                }
            }
        })
        .fold(f64::INFINITY, f64::min);
    let _ = (inradius, circum);
    let f = uv.length() / rho;
    if f < 1.0 / 3.0 {
        "centre"
    } else if f > 2.0 / 3.0 {
        "side"
    } else {
        "middle"
    }
}

struct Sample {
    patch: usize,
    uv: DVec2,
    p: DVec3,
    h: f64,
}

fn sample(s: &Surface, form: WeightForm, m: usize) -> Vec<Sample> {
    let mut out = Vec::new();
    for (k, patch) in s.patches.iter().enumerate() {
        let dom = Domain::regular(patch.sides()).expect("domain");
        for uv in domain_samples(&dom, m) {
            let d = patch.eval_derivs(uv, form);
            if let Some(c) = d.curvature() {
                out.push(Sample { patch: k, uv, p: d.p, h: c.mean });
            }
        }
    }
    out
}

fn p99_max(mut v: Vec<f64>) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    (v[((v.len() - 1) as f64 * 0.99).round() as usize], v[v.len() - 1])
}

fn study(name: &str, cage: &PolyMesh, method: Method, top: usize) {
    let opts = ConvertOptions { method, ..Default::default() };
    let s = gbsurf::api::build_surface(cage, &opts).expect("surface");
    let samples = sample(&s, opts.weights, 12);
    let radius = samples.iter().map(|x| x.p.length()).sum::<f64>() / samples.len() as f64;
    let dev = samples.iter().map(|x| (x.p.length() / radius - 1.0).abs()).fold(0.0, f64::max);
    let err = |x: &Sample| x.h * radius + 1.0;
    let (p99, max) = p99_max(samples.iter().map(|x| err(x).abs()).collect());
    println!("\n### {name}, {} ({} patches)", method.name(), s.patches.len());
    println!("max |r/R − 1| {dev:.2e}, |H·R + 1| p99 {p99:.3} max {max:.3}");
    // Valence of each vertex (dual sources) and sides of each face (topology sources).
    let mut valence = vec![0usize; cage.positions.len()];
    for f in &cage.faces {
        for &v in f {
            valence[v as usize] += 1;
        }
    }
    let kind = |p: usize| -> String {
        let n = s.patches[p].sides();
        let gb = matches!(s.patches[p], Patch::Gb(_));
        let src = match s.sources[p] {
            PatchSource::Vertex(v) => format!("vertex of valence {}", valence[v]),
            PatchSource::Face(f) => format!("{}-gon face", cage.faces[f].len()),
        };
        format!("n = {n} {} ({src})", if gb { "GB" } else { "CGB" })
    };
    // Worst sample per patch.
    let mut worst: Vec<Option<&Sample>> = vec![None; s.patches.len()];
    for x in &samples {
        let w = &mut worst[x.patch];
        if w.is_none_or(|w| err(w).abs() < err(x).abs()) {
            *w = Some(x);
        }
    }
    let mut by_kind: BTreeMap<String, (usize, &Sample, BTreeMap<&str, usize>)> = BTreeMap::new();
    for x in worst.iter().flatten() {
        let dom = Domain::regular(s.patches[x.patch].sides()).expect("domain");
        let e = by_kind.entry(kind(x.patch)).or_insert((0, x, BTreeMap::new()));
        e.0 += 1;
        *e.2.entry(place(&dom, x.uv)).or_default() += 1;
        if err(e.1).abs() < err(x).abs() {
            e.1 = x;
        }
    }
    println!("| patch kind | patches | max \\|H·R + 1\\| | sign | where (worst) | where (each patch's worst) |");
    println!("|---|---|---|---|---|---|");
    for (k, (count, x, places)) in &by_kind {
        let dom = Domain::regular(s.patches[x.patch].sides()).expect("domain");
        let sign = if err(x) > 0.0 { "flat" } else { "curved" };
        let places: Vec<String> = places.iter().map(|(p, c)| format!("{p} {c}")).collect();
        println!("| {k} | {count} | {:.3} | {sign} | {} | {} |", err(x).abs(), place(&dom, x.uv), places.join(", "));
    }
    let mut order: Vec<&Sample> = worst.iter().flatten().copied().collect();
    order.sort_by(|a, b| err(b).abs().total_cmp(&err(a).abs()));
    for x in order.iter().take(top) {
        let dom = Domain::regular(s.patches[x.patch].sides()).expect("domain");
        let at = match s.sources[x.patch] {
            PatchSource::Vertex(v) => cage.positions[v],
            PatchSource::Face(f) => cage.faces[f].iter().map(|&v| cage.positions[v as usize]).sum::<DVec3>() / cage.faces[f].len() as f64,
        };
        println!(
            "  patch {} {}: H·R + 1 = {:+.3} at uv ({:.2}, {:.2}) ({}), |uv| {:.2}, element at z = {:.3}",
            x.patch,
            kind(x.patch),
            err(x),
            x.uv.x,
            x.uv.y,
            place(&dom, x.uv),
            x.uv.length(),
            at.z
        );
    }
}

fn main() {
    let top = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(5);
    let cages: Vec<(&str, PolyMesh)> = vec![
        ("uv sphere 32×16", uv_sphere(32, 16).expect("uv sphere")),
        ("ico sphere (2 splits)", ico_sphere(2)),
        ("quad sphere 4×4", quad_sphere(4)),
    ];
    for (name, cage) in &cages {
        for method in [Method::Dual, Method::Topology] {
            study(name, cage, method, top);
        }
    }
}
