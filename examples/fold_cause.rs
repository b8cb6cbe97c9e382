//! Why a patch turns over: `cargo run --release --example fold_cause -- CAGE.obj...`. For every
//! patch whose parameterisation really flips (the test of `fold_truth`: neighbouring unit normals
//! with a negative dot on 60 steps per radius) it prints, per structure (default options; METHOD=
//! dual|topology for one; FULLNESS, DEPTH override them; LIMIT = patches printed per cage, 6):
//! - where the flip is: the domain point, the nearest side i, its side parameter s and distance
//!   h (both in [0, 1]), the neighbour across side i and whether that side is sharp;
//! - side i's ribbon along s: the curve's tangent T(s), the ribbon's cross-derivative
//!   X(s) = d·(row 1 − row 0)(s), the signed angle of X from T about the side's mid normal, |X|/|T|
//!   and the direction blend's share: X = αD + βT gives α (across) and β (along);
//! - the two corner blocks at side i's ends: side lengths |P01 − P00|, |P10 − P00|, the angle
//!   between them, and the twist's offset from the parallelogram point in that basis.
//!
//! - for a dual side between two GB patches, the direction blend's components across the curve
//!   (D(0), D0.5, D(1) and the middle Bernstein coefficient; docs/math.md#blend-side).
//!
//! A sign change of (T × X)·n along s is a ribbon that turns over on the boundary itself: the
//! patch must fold there whatever its interior does. The rook dual's base ring turned over that
//! way until the blends were kept on their side of the curve (docs/math.md#blend-side).

#[path = "common/fine.rs"]
mod fine;

use gbsurf::gb::{Evaluate, Ribbon};
use gbsurf::{ConvertOptions, DVec2, DVec3, Method};
use rayon::prelude::*;

fn env(name: &str) -> Option<f64> {
    std::env::var(name).ok().and_then(|s| s.parse().ok())
}

/// Value of the Bézier row `p` at s (de Casteljau).
fn bez(p: &[DVec3], s: f64) -> DVec3 {
    let mut q = p.to_vec();
    for k in 1..q.len() {
        for j in 0..q.len() - k {
            q[j] = q[j] * (1.0 - s) + q[j + 1] * s;
        }
    }
    q[0]
}

/// Derivative of the Bézier row `p` at s.
fn bez_d(p: &[DVec3], s: f64) -> DVec3 {
    let d = (p.len() - 1) as f64;
    let h: Vec<DVec3> = p.windows(2).map(|w| d * (w[1] - w[0])).collect();
    bez(&h, s)
}

/// (T, X) of a ribbon at s: boundary tangent and cross-derivative (first chord times degree).
fn tx(r: &Ribbon, s: f64) -> (DVec3, DVec3) {
    let (r0, r1) = (r.row(0), r.row(1));
    (bez_d(r0, s), r.degree as f64 * (bez(r1, s) - bez(r0, s)))
}

/// Signed angle (degrees) from a to b about n.
fn signed_angle(a: DVec3, b: DVec3, n: DVec3) -> f64 {
    let c = a.cross(b).dot(n);
    c.atan2(a.dot(b)).to_degrees()
}

fn corner(label: &str, p00: DVec3, p10: DVec3, p01: DVec3, twist: DVec3) {
    let (a, b) = (p10 - p00, p01 - p00);
    let off = twist - (p10 + p01 - p00);
    // off = x a + y b (+ normal part): least squares in span(a, b).
    let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
    let det = aa * bb - ab * ab;
    let (ra, rb) = (off.dot(a), off.dot(b));
    let (x, y) = ((ra * bb - rb * ab) / det, (rb * aa - ra * ab) / det);
    let nrm = a.cross(b).normalize_or_zero();
    println!(
        "      {label}: |along| {:.4} |across| {:.4} ratio {:.2} angle {:6.1}°, \
         twist − parallelogram = {:+.3}·along {:+.3}·across {:+.4} normal",
        a.length(),
        b.length(),
        b.length() / a.length(),
        a.angle_between(b).to_degrees(),
        x,
        y,
        off.dot(nrm)
    );
}

fn main() {
    let limit = env("LIMIT").map_or(6, |l| l as usize);
    let methods: Vec<Method> = match std::env::var("METHOD").as_deref() {
        Ok("dual") => vec![Method::Dual],
        Ok("topology") => vec![Method::Topology],
        _ => vec![Method::Dual, Method::Topology],
    };
    for file in std::env::args().skip(1) {
        let name = file.rsplit('/').next().unwrap_or(&file).to_string();
        let Ok(poly) = gbsurf::read_mesh(&file) else { continue };
        for &method in &methods {
            let mut o = ConvertOptions { method, ..Default::default() };
            if let Some(k) = env("FULLNESS") {
                o.fullness = k;
            }
            if let Some(w) = env("DEPTH") {
                o.tile_depth = w;
            }
            let c = match gbsurf::api::convert(&poly, &o, None) {
                Ok(c) => c,
                Err(e) => {
                    println!("{name} {}: {e}", method.name());
                    continue;
                }
            };
            let Some(surf) = c.surface.as_ref() else { continue };
            let flips: Vec<(usize, (f64, (usize, usize, usize), f64))> = surf
                .patches
                .par_iter()
                .map(|p| fine::neighbour_normals(p, o.weights, 60))
                .enumerate()
                .filter(|(_, f)| f.0 < 0.0)
                .collect();
            println!("{name} {}: {} patches flip", method.name(), flips.len());
            for (p, (dot, (sec, r, t), ratio)) in flips.iter().take(limit) {
                let patch = &surf.patches[*p];
                let n = patch.sides();
                let dom = gbsurf::gb::Domain::regular(n).unwrap();
                let vs = dom.vertices().to_vec();
                let (a, b) = (vs[(sec + n - 1) % n], vs[*sec]);
                let (rr, tt) = (*r as f64 / 60.0, if *r == 0 { 0.0 } else { *t as f64 / *r as f64 });
                let x: DVec2 = rr * ((1.0 - tt) * a + tt * b) * 0.999;
                // Nearest side: side i runs from vertex i−1 to vertex i.
                let (mut best, mut bs, mut bh) = (0, 0.0, f64::MAX);
                let apothem = (std::f64::consts::PI / n as f64).cos() * vs[0].length();
                for i in 0..n {
                    let (p0, p1) = (vs[(i + n - 1) % n], vs[i]);
                    let e = p1 - p0;
                    let s = ((x - p0).dot(e) / e.length_squared()).clamp(0.0, 1.0);
                    let h = (x - (p0 + s * e)).length() / (2.0 * apothem);
                    if h < bh {
                        (best, bs, bh) = (i, s, h);
                    }
                }
                let nb = surf.neighbors[*p][best];
                println!(
                    "  patch {p} ({:?}, {n} sides) dot {dot:.3} ratio {ratio:.1e} at domain ({:.3},{:.3}): \
                     side {best} s {bs:.3} h {bh:.3}; neighbour {:?} sharpness {}",
                    surf.sources[*p],
                    x.x,
                    x.y,
                    nb.map(|s| (s.patch, s.side)),
                    surf.side_crease(*p, best)
                );
                let d = patch.eval_derivs(x, o.weights);
                let rib = &patch.ribbons()[best];
                let nmid = {
                    let (t, x) = tx(rib, 0.5);
                    t.cross(x).normalize_or_zero()
                };
                println!(
                    "    surface at flip: |Su x Sv| {:.2e}, normal·n_mid {:+.3}",
                    d.su.cross(d.sv).length(),
                    d.su.cross(d.sv).normalize_or_zero().dot(nmid)
                );
                print!("    side {best} along s: ");
                for k in 0..=10 {
                    let s = k as f64 / 10.0;
                    let (t, xv) = tx(rib, s);
                    print!("[{s:.1} {:+.0}° {:.2}] ", signed_angle(t, xv, nmid), xv.length() / t.length());
                }
                println!();
                // The direction blend's across components (dual, default options: D at the ends is
                // (X_A − X_B)/2, D_{0.5} = (3/2)(1 − κ)(V_A − V_B), V the patches' centres).
                if let (Some(nb), gbsurf::construct::Patch::Gb(ga)) = (nb, patch) {
                    if let gbsurf::construct::Patch::Gb(gb_) = &surf.patches[nb.patch] {
                        let rb = &surf.patches[nb.patch].ribbons()[nb.side];
                        let (a0, a1) = (rib.row(0), rib.row(1));
                        let (b0, b1) = (rb.row(0), rb.row(1));
                        let xa = [3.0 * (a1[0] - a0[0]), 3.0 * (a1[3] - a0[3])];
                        let xb = [3.0 * (b1[3] - b0[3]), 3.0 * (b1[0] - b0[0])];
                        let d0 = 0.5 * (xa[0] - xb[0]);
                        let d1 = 0.5 * (xa[1] - xb[1]);
                        // V_A, V_B: the cage vertices of the two patches (their central points are
                        // fitted to the boundary for valences other than 4, docs/math.md#centre-fit).
                        let cage_vertex = |q: usize, fallback: DVec3| match surf.sources[q] {
                            gbsurf::construct::PatchSource::Vertex(v) => poly.positions.get(v).copied().unwrap_or(fallback),
                            _ => fallback,
                        };
                        let mid = 1.5 * (1.0 - o.fullness) * (cage_vertex(*p, ga.center) - cage_vertex(nb.patch, gb_.center));
                        let tm = bez_d(a0, 0.5).normalize();
                        let db = 0.5 * (d0 + d1);
                        let e = (db - db.dot(tm) * tm).normalize_or_zero();
                        let (a, m, b) = (d0.dot(e), mid.dot(e), d1.dot(e));
                        let c = 2.0 * m - 0.5 * (a + b);
                        println!(
                            "    blend across (e ⟂ T(½)): D(0) {a:.5} D0.5 {m:.5} D(1) {b:.5}; \
                             middle Bernstein coefficient {c:+.5}; \
                             D·e < 0 somewhere iff D0.5 < (√D(0) − √D(1))²/4 = {:.5}; \
                             |D0.5| {:.5} along T {:+.5}",
                            (a.max(0.0).sqrt() - b.max(0.0).sqrt()).powi(2) / 4.0,
                            mid.length(),
                            mid.dot(tm)
                        );
                    }
                }
                // Corner blocks of side `best`: start (column 0) and end (column d).
                let (r0, r1) = (rib.row(0), rib.row(1));
                let dg = rib.degree;
                let (t0, t1) = (bez_d(r0, 0.0).length(), bez_d(r0, 1.0).length());
                println!("    side {best}: |T(0)| {t0:.4} |T(1)| {t1:.4} chord {:.4}", (r0[dg] - r0[0]).length());
                corner("start", r0[0], r0[1], r1[0], r1[1]);
                corner("end  ", r0[dg], r0[dg - 1], r1[dg], r1[dg - 1]);
                // The adjacent sides' corner blocks at the same corners (their twists may differ).
                let prev = &patch.ribbons()[(best + n - 1) % n];
                let next = &patch.ribbons()[(best + 1) % n];
                let (q0, q1) = (prev.row(0), prev.row(1));
                let pd = prev.degree;
                corner("prev side end", q0[pd], q0[pd - 1], q1[pd], q1[pd - 1]);
                let (q0, q1) = (next.row(0), next.row(1));
                corner("next side start", q0[0], q0[1], q1[0], q1[1]);
                for (i, rb) in patch.ribbons().iter().enumerate() {
                    let r0 = rb.row(0);
                    println!(
                        "      side {i}: chord {:.4} |P1−P0| {:.4} |P2−P3| {:.4}",
                        (r0[rb.degree] - r0[0]).length(),
                        (r0[1] - r0[0]).length(),
                        (r0[rb.degree - 1] - r0[rb.degree]).length()
                    );
                }
            }
        }
    }
}
