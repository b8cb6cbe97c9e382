//! Agreement with the public `transfinite` library (P. Salvi), the reference GB evaluator whose
//! `.gbp` format and domain convention gbsurf follows (docs/math.md#transfinite).
//!
//! `Tf` below re-implements, literally and slowly, what that library does for a GB patch, read from
//! its sources (salvipeter/transfinite, `src/transfinite/`):
//! - `domain-regular.cc`: vertices (cos 2πi/m, sin 2πi/m), for m = 4 the square
//!   (1,1), (−1,1), (−1,−1), (1,−1); centre (0,0).
//! - `domain.cc`: du_i = v_i − v_{i−1}, dv_i = du_i rotated, turned towards the centre;
//!   toLocal(i, v) = (v·du_i, v·dv_i)/|du_i|²; edgeLength, angle.
//! - `parameterization-barycentric.cc` (the GB patch's `ParamType`, Wachspress by default):
//!   l_i ∝ A_{i−1}·Π + A_i·Π − B_i·Π (its three products), s_i = l_i/(l_{i−1}+l_i) with the
//!   sine/distance fallback when that denominator is below ε = 1e-8, d_i = 1 − l_i − l_{i−1}.
//! - `surface-generalized-bezier.cc` `eval`: corner return (d_i + d_{i+1} < ε → the corner
//!   control point), linear α = d_{i−1}/(d_{i−1}+d_i) by default, squared with
//!   `useSquaredRationalWeights(true)`; the μ rule; central weight 1 − Σ.
//! - `test/io.cc` `loadBezier` with `setControlPoint`'s sharing copies.
//!
//! Differences by design (checked below, not hidden):
//! - Default weight form: transfinite's default is LINEAR (`squared_weights_ = false`), gbsurf's
//!   is `WeightForm::Squared`. Points agree when the same form is chosen on both sides; with
//!   different forms they differ (even on connected nets).
//! - Within ε = 1e-8 (in h) of a corner transfinite returns the corner control point; gbsurf keeps
//!   evaluating the formula, so there the two differ by O(1e-8) (exactly at the corner both give
//!   the corner point).
//! - d = 2: transfinite applies the μ rule literally (α to the middle boundary point), gbsurf
//!   gives that point μ = 1 (see `gbsurf::gb::weights::mu_kind`), so degree-2 patches differ.
//! - d = 1: not a GB patch for gbsurf (μ needs d ≥ 2); see `tests/gbp.rs` for how `.gbp` treats it.

// The reference is a line-by-line transcription of C++ loops (index loops, `(d + 1) / 2`).
#![allow(clippy::needless_range_loop, clippy::manual_div_ceil)]

use gbsurf::gb::Evaluate;
use gbsurf::gb::gbp::{parse_gbp, to_gbp_string};
use gbsurf::gb::{layers_for_degree, GbPatch, Ribbon, WeightForm};
use gbsurf::{DVec2, DVec3};

const EPSILON: f64 = 1.0e-8; // libgeom's Geometry::epsilon
const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");

/// transfinite's SurfaceGeneralizedBezier with its DomainRegular and ParameterizationBarycentric.
struct Tf {
    n: usize,
    degree: usize,
    layers: usize,
    /// nets[i][j][k], as in the C++ (`ControlNet` = column j, row k).
    nets: Vec<Vec<Vec<DVec3>>>,
    central: DVec3,
    squared: bool,
    vertices: Vec<DVec2>,
    du: Vec<DVec2>,
    dv: Vec<DVec2>,
}

impl Tf {
    fn prev(&self, i: usize) -> usize {
        (i + self.n - 1) % self.n
    }
    fn next(&self, i: usize) -> usize {
        (i + 1) % self.n
    }

    /// initNetwork + DomainRegular::update + Domain::update.
    fn new(n: usize, degree: usize) -> Tf {
        let layers = (degree + 1) / 2;
        let nets = vec![vec![vec![DVec3::ZERO; layers]; degree + 1]; n];
        let vertices: Vec<DVec2> = if n == 4 {
            vec![
                DVec2::new(1.0, 1.0),
                DVec2::new(-1.0, 1.0),
                DVec2::new(-1.0, -1.0),
                DVec2::new(1.0, -1.0),
            ]
        } else {
            let alpha = 2.0 * std::f64::consts::PI / n as f64;
            (0..n)
                .map(|i| DVec2::new((alpha * i as f64).cos(), (alpha * i as f64).sin()))
                .collect()
        };
        let center = DVec2::ZERO;
        let mut du = vec![DVec2::ZERO; n];
        let mut dv = vec![DVec2::ZERO; n];
        for i in 0..n {
            du[i] = vertices[i] - vertices[(i + n - 1) % n];
            dv[i] = DVec2::new(du[i].y, -du[i].x);
            if (center - vertices[i]).dot(dv[i]) < 0.0 {
                dv[i] = -dv[i];
            }
        }
        Tf {
            n,
            degree,
            layers,
            nets,
            central: DVec3::ZERO,
            squared: false,
            vertices,
            du,
            dv,
        }
    }

    fn set_control_point(&mut self, i: usize, j: usize, k: usize, p: DVec3) {
        let (d, l) = (self.degree, self.layers);
        self.nets[i][j][k] = p;
        if j < l {
            let pi = self.prev(i);
            self.nets[pi][d - k][j] = p;
        } else if d - j < l {
            let ni = self.next(i);
            self.nets[ni][k][d - j] = p;
        }
    }

    /// io.cc loadBezier (from text, numbers split on whitespace like `operator>>`).
    fn load(text: &str) -> Tf {
        let mut it = text.split_whitespace();
        let n: usize = it.next().unwrap().parse().unwrap();
        let d: usize = it.next().unwrap().parse().unwrap();
        let mut pt = || {
            let mut c = [0.0; 3];
            for x in &mut c {
                *x = it.next().unwrap().parse().unwrap();
            }
            DVec3::from_array(c)
        };
        let l = (d + 1) / 2;
        let cp = n * (1 + d / 2) * l + 1;
        let mut surf = Tf::new(n, d);
        surf.central = pt();
        let (mut side, mut col, mut row) = (0usize, 0usize, 0usize);
        let mut i = 1;
        while i < cp {
            if col >= d - row {
                side += 1;
                if side >= n {
                    side = 0;
                    row += 1;
                }
                col = row;
            }
            let p = pt();
            surf.set_control_point(side, col, row, p);
            i += 1;
            col += 1;
        }
        surf
    }

    /// setIndividualControlPoint for every point of our ribbons (independent corner blocks).
    fn from_ribbons(p: &GbPatch) -> Tf {
        let n = p.ribbons.len();
        let d = p.ribbons[0].degree;
        let mut surf = Tf::new(n, d);
        surf.central = p.center;
        for i in 0..n {
            for k in 0..surf.layers {
                for j in 0..=d {
                    surf.nets[i][j][k] = p.ribbons[i].row(k)[j];
                }
            }
        }
        surf
    }

    fn to_local(&self, i: usize, v: DVec2) -> DVec2 {
        DVec2::new(v.dot(self.du[i]), v.dot(self.dv[i])) / self.du[i].length_squared()
    }
    fn edge_length(&self, i: usize) -> f64 {
        (self.vertices[i] - self.vertices[self.prev(i)]).length()
    }
    fn angle(&self, i: usize) -> f64 {
        let v1 = self.vertices[self.prev(i)] - self.vertices[i];
        let v2 = self.vertices[self.next(i)] - self.vertices[i];
        v1.normalize().dot(v2.normalize()).clamp(-1.0, 1.0).acos()
    }

    /// ParameterizationBarycentric::barycentric, type WACHSPRESS (all r = 1).
    fn barycentric(&self, uv: DVec2) -> Vec<f64> {
        let n = self.n;
        let vectors: Vec<DVec2> = self.vertices.iter().map(|p| uv - *p).collect();
        let areas: Vec<f64> = (0..n)
            .map(|i| {
                let si = vectors[i];
                let si1 = vectors[self.next(i)];
                (si.x * si1.y - si.y * si1.x) / 2.0
            })
            .collect();
        let mut l = Vec::with_capacity(n);
        for i in 0..n {
            let (i_1, i1) = (self.prev(i), self.next(i));
            let (mut ai, mut ai_1, mut ai_1i) = (1.0, 1.0, 1.0);
            for (j, &a) in areas.iter().enumerate() {
                if j == i {
                    ai_1 *= a;
                } else if j == i_1 {
                    ai *= a;
                } else {
                    ai_1 *= a;
                    ai *= a;
                    ai_1i *= a;
                }
            }
            let si_1 = vectors[i_1];
            let si1 = vectors[i1];
            let bi = (si_1.x * si1.y - si_1.y * si1.x) / 2.0;
            l.push(ai_1 + ai - bi * ai_1i);
        }
        let sum: f64 = l.iter().sum();
        l.iter().map(|x| x / sum).collect()
    }

    /// ParameterizationBarycentric::mapToRibbon: (s_i, d_i).
    fn map_to_ribbon(&self, i: usize, uv: DVec2) -> (f64, f64) {
        let l = self.barycentric(uv);
        let mut denom = l[self.prev(i)] + l[i];
        let s = if denom < EPSILON {
            let v = &self.vertices;
            let alpha = self.angle(i);
            let beta = self.angle(self.prev(i));
            let dprev = self.to_local(self.prev(i), uv - v[self.prev(i)]).y
                * self.edge_length(self.prev(i));
            let dnext =
                self.to_local(self.next(i), uv - v[i]).y * self.edge_length(self.next(i));
            denom = alpha.sin() * dprev + beta.sin() * dnext;
            if denom < EPSILON {
                0.0
            } else {
                alpha.sin() * dprev / denom
            }
        } else {
            l[i] / denom
        };
        (s, 1.0 - l[i] - l[self.prev(i)])
    }

    /// utilities.cc bernstein(n, u, coeff) (the triangle scheme).
    fn bernstein(n: usize, u: f64) -> Vec<f64> {
        let mut coeff = vec![1.0];
        let u1 = 1.0 - u;
        for j in 1..=n {
            let mut saved = 0.0;
            for c in coeff.iter_mut().take(j) {
                let tmp = *c;
                *c = saved + tmp * u1;
                saved = tmp * u;
            }
            coeff.push(saved);
        }
        coeff
    }

    /// SurfaceGeneralizedBezier::eval; also says whether the corner branch was taken.
    fn eval(&self, uv: DVec2) -> (DVec3, bool) {
        let d = self.degree;
        let sds: Vec<(f64, f64)> = (0..self.n).map(|i| self.map_to_ribbon(i, uv)).collect();
        let mut surface_point = DVec3::ZERO;
        let mut weight_sum = 0.0;
        for i in 0..self.n {
            let si = sds[i].0;
            let di_1 = sds[self.prev(i)].1;
            let di = sds[i].1;
            let di1 = sds[self.next(i)].1;
            if di + di1 < EPSILON || di_1 + di < EPSILON {
                if di + di1 < EPSILON {
                    return (self.nets[i][d][0], true);
                } else {
                    return (self.nets[i][0][0], true);
                }
            }
            let (alpha, beta) = if self.squared {
                let (a, b, c) = (di_1 * di_1, di * di, di1 * di1);
                (a / (a + b), c / (c + b))
            } else {
                (di_1 / (di_1 + di), di1 / (di1 + di))
            };
            let bl_s = Tf::bernstein(d, si);
            let bl_d = Tf::bernstein(d, di);
            for k in 0..self.layers {
                for j in 0..=d {
                    let mut blend = bl_s[j] * bl_d[k];
                    // `degree_ - 2` and `degree_ - k` are size_t in the C++ (d ≥ 2 here).
                    if k < 2 && (j < 2 || j > d - 2) {
                        if j < 2 {
                            blend *= alpha;
                        } else {
                            blend *= beta;
                        }
                    } else if j == k || j == d - k {
                        blend *= 0.5;
                    } else if j < k || j > d - k {
                        blend = 0.0;
                    }
                    surface_point += self.nets[i][j][k] * blend;
                    weight_sum += blend;
                }
            }
        }
        surface_point += self.central * (1.0 - weight_sum);
        (surface_point, false)
    }
}

/// Small deterministic generator (xorshift64*).
struct Rng(u64);
impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E3779B97F4A7C15) | 1)
    }
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn v(&mut self) -> DVec3 {
        DVec3::new(self.f() * 2.0 - 1.0, self.f() * 2.0 - 1.0, self.f() * 2.0 - 1.0)
    }
}

/// Domain samples on the closed n-gon: random interior points (fan triangles), a radial grid
/// reaching the boundary (transfinite's own `parametersImpl` layout for n > 4), exact vertices,
/// exact edge points, the centre, and points 1e-9 … 1e-3 from vertices and edges.
fn samples(n: usize, seed: u64) -> Vec<DVec2> {
    let tf = Tf::new(n, 3);
    let v = &tf.vertices;
    let mut out = vec![DVec2::ZERO];
    let mut r = Rng::new(seed);
    for _ in 0..300 {
        let i = (r.f() * n as f64) as usize % n;
        let (mut a, mut b) = (r.f(), r.f());
        if a + b > 1.0 {
            (a, b) = (1.0 - a, 1.0 - b);
        }
        out.push(v[(i + n - 1) % n] * a + v[i] * b);
    }
    let res = 12;
    for j in 1..=res {
        let u = j as f64 / res as f64;
        for k in 0..n {
            for i in 0..j {
                let t = i as f64 / j as f64;
                out.push((v[(k + n - 1) % n] * (1.0 - t) + v[k] * t) * u);
            }
        }
    }
    for i in 0..n {
        let a = v[(i + n - 1) % n];
        let b = v[i];
        out.push(b);
        for t in [0.5, 1.0 / 3.0, 0.1, 0.9, 1e-3, 1.0 - 1e-3] {
            out.push(a + (b - a) * t);
        }
        for e in [1e-9, 1e-7, 1e-5, 1e-3] {
            out.push(b * (1.0 - e)); // towards the centre from a vertex
            out.push((a + b) * 0.5 * (1.0 - e)); // just inside an edge midpoint
            out.push(a + (b - a) * e + (-a - (b - a) * e) * e); // near a vertex along an edge
        }
    }
    out
}

/// Largest |ours − transfinite| over the samples, split into points where transfinite takes its
/// corner shortcut and the others.
fn compare(ours: &GbPatch, tf: &Tf, form: WeightForm, seed: u64) -> (f64, f64, usize) {
    let (mut regular, mut corner, mut count) = (0.0f64, 0.0f64, 0);
    for x in samples(tf.n, seed) {
        let (q, at_corner) = tf.eval(x);
        let p = ours.eval(x, form);
        assert!(p.is_finite(), "n={} d={} at {x}: {p}", tf.n, tf.degree);
        let e = p.distance(q);
        if at_corner {
            corner = corner.max(e);
        } else {
            regular = regular.max(e);
            count += 1;
        }
    }
    (regular, corner, count)
}

/// A connected net as `.gbp` text with random listed points.
fn random_gbp_text(n: usize, d: usize, seed: u64) -> String {
    let mut r = Rng::new(seed);
    let count = 1 + n * (1 + d / 2) * ((d + 1) / 2);
    let mut s = format!("{n} {d}\n");
    for _ in 0..count {
        let p = r.v();
        s += &format!("{:e} {:e} {:e}\n", p.x, p.y, p.z);
    }
    s
}

fn assert_same_nets(ours: &GbPatch, tf: &Tf) {
    assert_eq!(ours.center, tf.central);
    for i in 0..tf.n {
        assert_eq!(ours.ribbons[i].layers(), tf.layers);
        for k in 0..tf.layers {
            for j in 0..=tf.degree {
                assert_eq!(
                    ours.ribbons[i].row(k)[j], tf.nets[i][j][k],
                    "n={} d={} side {i} col {j} row {k}",
                    tf.n, tf.degree
                );
            }
        }
    }
}

#[test]
fn sample_files_load_and_evaluate_like_transfinite() {
    for name in ["cubic5.gbp", "quintic3.gbp"] {
        let text = std::fs::read_to_string(format!("{DATA}/{name}")).unwrap();
        let ours = parse_gbp(&text).unwrap();
        let mut tf = Tf::load(&text);
        assert_same_nets(&ours, &tf);
        for (squared, form) in [(false, WeightForm::Linear), (true, WeightForm::Squared)] {
            tf.squared = squared;
            let (regular, corner, count) = compare(&ours, &tf, form, 7);
            assert!(count > 400, "{name}: {count} points compared");
            assert!(regular <= 1e-12, "{name} {form:?}: max deviation {regular:e}");
            assert!(corner <= 1e-7, "{name} {form:?}: corner shortcut deviation {corner:e}");
        }
    }
}

#[test]
fn random_connected_nets_agree_for_n_3_to_8_and_d_3_to_8() {
    let mut worst = 0.0f64;
    for n in 3..=8 {
        for d in 3..=8 {
            let text = random_gbp_text(n, d, (n * 100 + d) as u64);
            let ours = parse_gbp(&text).unwrap();
            let mut tf = Tf::load(&text);
            assert_same_nets(&ours, &tf);
            // Our writer's output is read back by the reference reader to the same net.
            let back = Tf::load(&to_gbp_string(&ours).unwrap());
            assert_same_nets(&ours, &back);
            for (squared, form) in [(false, WeightForm::Linear), (true, WeightForm::Squared)] {
                tf.squared = squared;
                let (regular, corner, _) = compare(&ours, &tf, form, (n + d) as u64);
                assert!(regular <= 1e-12, "n={n} d={d} {form:?}: {regular:e}");
                assert!(corner <= 1e-7, "n={n} d={d} {form:?}: corner {corner:e}");
                worst = worst.max(regular);
            }
        }
    }
    eprintln!("largest deviation from transfinite on connected nets: {worst:e}");
}

/// Independent corner blocks (transfinite's `setIndividualControlPoint`), row-0 corners shared.
fn independent_patch(n: usize, d: usize, seed: u64) -> GbPatch {
    let mut r = Rng::new(seed);
    let l = layers_for_degree(d);
    let mut ribbons: Vec<Ribbon> = (0..n)
        .map(|_| Ribbon::from_rows(d, (0..l).map(|_| (0..=d).map(|_| r.v()).collect()).collect()).unwrap())
        .collect();
    for i in 0..n {
        let p = ribbons[(i + n - 1) % n].row(0)[d];
        ribbons[i].row_mut(0)[0] = p;
    }
    GbPatch {
        ribbons,
        center: r.v(),
    }
}

#[test]
fn independent_corner_blocks_agree_in_both_weight_forms() {
    for n in 3..=8 {
        for d in 3..=8 {
            let ours = independent_patch(n, d, (n * 31 + d) as u64);
            let mut tf = Tf::from_ribbons(&ours);
            for (squared, form) in [(false, WeightForm::Linear), (true, WeightForm::Squared)] {
                tf.squared = squared;
                let (regular, corner, _) = compare(&ours, &tf, form, d as u64);
                assert!(regular <= 1e-12, "n={n} d={d} {form:?}: {regular:e}");
                assert!(corner <= 1e-7, "n={n} d={d} {form:?}: corner {corner:e}");
            }
        }
    }
}

#[test]
fn exact_corners_and_the_centre_agree_exactly_enough() {
    // At the domain vertices both return the corner control point; at the centre both use the
    // same formula.
    for n in 3..=8 {
        for d in 3..=6 {
            let text = random_gbp_text(n, d, (n * 7 + d) as u64);
            let ours = parse_gbp(&text).unwrap();
            let tf = Tf::load(&text);
            for i in 0..n {
                let (q, at_corner) = tf.eval(tf.vertices[i]);
                assert!(at_corner);
                for form in [WeightForm::Linear, WeightForm::Squared] {
                    let p = ours.eval(tf.vertices[i], form);
                    assert!(p.distance(q) <= 1e-14, "n={n} d={d} vertex {i}: {p} vs {q}");
                }
            }
        }
    }
}

#[test]
fn documented_differences_are_real() {
    // Default forms differ: transfinite linear vs gbsurf squared, on a connected net.
    let text = std::fs::read_to_string(format!("{DATA}/cubic5.gbp")).unwrap();
    let ours = parse_gbp(&text).unwrap();
    let tf = Tf::load(&text);
    assert_eq!(WeightForm::default(), WeightForm::Squared);
    let x = DVec2::new(0.3, -0.4);
    let dev = ours.eval(x, WeightForm::default()).distance(tf.eval(x).0);
    assert!(dev > 1e-4, "default forms should differ, got {dev:e}");

    // The corner shortcut: 1e-9 inside a vertex transfinite returns the corner point exactly.
    let v0 = tf.vertices[0];
    let near = v0 * (1.0 - 1e-9);
    let (q, at_corner) = tf.eval(near);
    assert!(at_corner && q == tf.nets[0][3][0]);
    let p = ours.eval(near, WeightForm::Linear);
    assert!(p.distance(q) > 0.0 && p.distance(q) < 1e-7);

    // d = 2: the middle boundary point gets α in transfinite, 1 in gbsurf.
    for n in [3, 5, 6] {
        let text = random_gbp_text(n, 2, 99 + n as u64);
        let ours = parse_gbp(&text).unwrap();
        let tf = Tf::load(&text);
        let x = DVec2::new(0.2, 0.1);
        let dev = ours.eval(x, WeightForm::Linear).distance(tf.eval(x).0);
        assert!(dev > 1e-3, "n={n}: d = 2 should differ by design, got {dev:e}");
    }
}
