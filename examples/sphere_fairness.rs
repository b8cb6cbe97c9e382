//! Where the mean curvature of the GB surfaces of the sphere cages of `scripts/bench_fairness`
//! departs from a sphere's, and what moving the dual patches' central points does to it:
//! `cargo run --release --example sphere_fairness [-- TOP]`.
//!
//! For the UV sphere (32 × 16), the ico sphere (2 splits) and the quad sphere (4 × 4) and both
//! structures (default options), every patch is sampled on its domain (the centre and, per fan
//! triangle (0, v_{i−1}, v_i) of the regular n-gon, a barycentric grid of step 1/12, boundary
//! excluded) and the analytic mean curvature H is compared with the sphere's −1/R (R the mean
//! distance of the samples from the origin; docs/math.md §1.9). Printed per cage and structure:
//! - max |r/R − 1| and the p99 / max of |H·R + 1| over the samples;
//! - per patch kind (n sides, GB or CGB, what the patch stands for: the valence of its vertex or
//!   the sides of its face): the count, the largest |H·R + 1| with its sign (`flat`: H·R + 1 > 0,
//!   less curved than the sphere; `curved`: more curved) and where in the domain it is (`centre`:
//!   under ⅓ of the way to the boundary; `corner`: within ¼ of a side length of a domain vertex;
//!   `side`: beyond ⅔ of the way; `middle` otherwise), and where each patch's worst sample is;
//! - the TOP (default 5) worst patches with their source element and its height z.
//!
//! Experiments (environment variables), each printed as an extra table:
//! - `FAIR=G` (dual): the central point C of every GB patch with n ≥ `MIN_N` (default 3) moved to
//!   C = V + T·(C* − V) (`T` default 1), C* the minimiser of the thin-plate energy
//!   Σ_s |S_uu|² + 2|S_uv|² + |S_vv|² over the samples of [`energy_samples`] with grid G and
//!   `REACH` (default G). S = A + B0·C is affine in C, so C* = −Σ_s (B0_uu A_uu + 2 B0_uv A_uv +
//!   B0_vv A_vv) / Σ_s (B0_uu² + 2 B0_uv² + B0_vv²), a fixed mask on the ribbon points
//!   ([`fair_center_mask`]); the ribbons, hence G1, are unchanged. `ENERGY=lapvar`: C* minimises
//!   the variance over the samples of the Laplacian S_uu + S_vv instead (same closed-form shape).
//! - `FAIR_MID=G` (both structures): every shared curve's middle constraint D_{0.5} (seed 000
//!   §4.4.5) chosen to minimise an energy summed over the patches (samples as above with grid G).
//!   The twists are affine in D_{0.5} with one scalar factor γ per twist (the blend's cross
//!   derivative is αT + βD; measured: the response to D = x̂ has no y, z part), so this is a
//!   least-squares problem with one unknown per curve, the same for x, y and z. `ENERGY=lapvar`:
//!   the variance over each patch's samples of the Laplacian S_uu + S_vv (else thin-plate);
//!   `PATCH_MEAN=1`: each patch's variance divided by its sample count; `LOCAL=1`: each curve's
//!   D alone with every other at the seed's (one Jacobi step from the seed: a per-curve rule),
//!   else the joint solve; `MAX_N=K`: curves on a patch of more than K sides keep the seed's D;
//!   `FAIR_C=1` (joint solve): the GB central points are unknowns too.
//! - `CAGES=1 … sphere_fairness 0 CAGE.obj…` with the `FAIR_MID` variables: instead of the spheres,
//!   per cage and structure the patches with folds at level 8 with the seed's and the fair D_{0.5}
//!   (`cage_folds`).
//! - `KAPPA`, `DEPTH`, `MID`, `TWIST`, `MIDDLE`: fullness, tile depth, mid scale (D_{0.5} factor),
//!   twist mode, middle rule (`seed`, `fair`) instead of the defaults, for every table. With
//!   `CAGES=1` a last column gives the folds of the construction's own `Middle::Fair` (guarded).
//! - `SPLIT=K` (dual): the network's patches of more than K sides split into fans
//!   (`construct::network::split_large_patches`, the rule used above 64 sides).

use gbsurf::construct::{CurveNetwork, Patch, PatchSource, Surface};
use gbsurf::gb::{Domain, Evaluate, GbBasisEvaluator, GbError, Ribbon, WeightForm};
use gbsurf::mesh::generate::{ico_sphere, quad_sphere, uv_sphere};
use gbsurf::mesh::PolyMesh;
use gbsurf::{ConvertOptions, DVec3, Method};
use glam::DVec2;
use std::collections::BTreeMap;

// ---------------------------------------------------------------- the fair central point

/// The domain samples of the energy of an n-sided patch: the centre and, per fan triangle
/// (0, v_{i−1}, v_i) of the regular domain, the points (a·v_{i−1} + b·v_i)/`grid` with a ≥ 1, b ≥ 0,
/// a + b < `grid` (the boundary excluded) and a + b ≤ `reach` (`reach` < `grid`: only the inner part).
fn energy_samples(dom: &Domain, grid: usize, reach: usize) -> Vec<DVec2> {
    let n = dom.n();
    let mut out = vec![DVec2::ZERO];
    for i in 0..n {
        let (p, q) = (dom.vertex(i + n - 1), dom.vertex(i));
        for a in 1..grid {
            for b in 0..(grid - a).min(reach + 1 - a.min(reach + 1)) {
                out.push((a as f64 * p + b as f64 * q) / grid as f64);
            }
        }
    }
    out
}

/// The mask of the fair central point of an n-sided degree-d patch with weight form `form`:
/// coefficients in the flat ribbon order (side i, row k, column j at (i·l + k)·(d+1) + j), so
/// that C* = Σ c_q P_q minimises the thin-plate energy on the samples of [`energy_samples`].
fn fair_center_mask(n: usize, d: usize, form: WeightForm, grid: usize, reach: usize) -> Result<Vec<f64>, GbError> {
    let mut ev = GbBasisEvaluator::new(n, d)?;
    let dom = Domain::regular(n)?;
    let len = ev.len() - 1;
    let samples = energy_samples(&dom, grid, reach);
    // Per sample: the central weight's and every ribbon weight's jets.
    let mut b0s = Vec::with_capacity(samples.len());
    let mut ws = Vec::with_capacity(samples.len());
    for &uv in &samples {
        let mut w = vec![gbsurf::gb::Jet2::ZERO; len];
        b0s.push(ev.for_each_ribbon_weight(uv, form, |idx, j| w[idx - 1] = j));
        ws.push(w);
    }
    if env::<String>("ENERGY").as_deref() == Some("lapvar") {
        // Variance of the Laplacian ΔS = S_uu + S_vv over the samples.
        let m = samples.len() as f64;
        let bl: Vec<f64> = b0s.iter().map(|b| b.duu + b.dvv).collect();
        let bbar = bl.iter().sum::<f64>() / m;
        let den: f64 = bl.iter().map(|b| (b - bbar) * (b - bbar)).sum();
        return Ok((0..len)
            .map(|q| {
                let wl: Vec<f64> = ws.iter().map(|w| w[q].duu + w[q].dvv).collect();
                let wbar = wl.iter().sum::<f64>() / m;
                -bl.iter().zip(&wl).map(|(b, w)| (b - bbar) * (w - wbar)).sum::<f64>() / den
            })
            .collect());
    }
    let mut g = vec![0.0; len];
    let mut den = 0.0;
    for (b0, w) in b0s.iter().zip(&ws) {
        den += b0.duu * b0.duu + 2.0 * b0.duv * b0.duv + b0.dvv * b0.dvv;
        for (gq, wq) in g.iter_mut().zip(w) {
            *gq += b0.duu * wq.duu + 2.0 * b0.duv * wq.duv + b0.dvv * wq.dvv;
        }
    }
    Ok(g.into_iter().map(|x| -x / den).collect())
}

/// C* = Σ c_q P_q for `ribbons` (flat order, see [`fair_center_mask`]).
fn fair_center(ribbons: &[Ribbon], mask: &[f64]) -> DVec3 {
    ribbons.iter().flat_map(|r| r.points().iter()).zip(mask).map(|(p, c)| *c * *p).sum()
}

// ---------------------------------------------------------------- sampling

/// Where `uv` lies in the domain (see the module doc).
fn place(dom: &Domain, uv: DVec2) -> &'static str {
    let n = dom.n();
    let side = dom.vertex(0).distance(dom.vertex(1));
    if (0..n).any(|i| dom.vertex(i).distance(uv) < 0.25 * side) {
        return "corner";
    }
    // Fraction of the way to the boundary along the ray from the centre.
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
        for uv in energy_samples(&dom, m, m) {
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
    let opts = options(method);
    let s = gbsurf::api::build_surface(cage, &opts).expect("surface");
    report(name, cage, &s, &opts, top);
    if method == Method::Dual {
        if let Some(grid) = env::<usize>("FAIR") {
            let reach = env("REACH").unwrap_or(grid);
            let t = env("T").unwrap_or(1.0);
            let min_n = env("MIN_N").unwrap_or(3);
            let mut f = s.clone();
            for p in &mut f.patches {
                if let Patch::Gb(g) = p {
                    if g.ribbons.len() >= min_n {
                        let mask = fair_center_mask(g.ribbons.len(), 3, opts.weights, grid, reach).expect("mask");
                        g.center += t * (fair_center(&g.ribbons, &mask) - g.center);
                    }
                }
            }
            let what = format!("{name} [C = V + {t}·(C* − V) for n ≥ {min_n}, grid {grid}, reach {reach}]");
            report(&what, cage, &f, &opts, top);
        }
    }
}

/// The default options with `method`, and `KAPPA` (fullness), `DEPTH` (tile depth), `MID` (mid scale)
/// and `TWIST` from the environment when set.
fn options(method: Method) -> ConvertOptions {
    let d = ConvertOptions::default();
    ConvertOptions {
        method,
        fullness: env("KAPPA").unwrap_or(d.fullness),
        tile_depth: env("DEPTH").unwrap_or(d.tile_depth),
        mid_scale: env("MID").unwrap_or(d.mid_scale),
        twist: env("TWIST").unwrap_or(d.twist),
        middle: env("MIDDLE").unwrap_or(d.middle),
        ..d
    }
}

/// The environment variable `name` parsed, `None` when unset or unparsable.
fn env<T: std::str::FromStr>(name: &str) -> Option<T> {
    std::env::var(name).ok()?.parse().ok()
}

fn split_study(name: &str, cage: &PolyMesh, top: usize) {
    let Some(k) = env::<usize>("SPLIT") else { return };
    let opts = options(Method::Dual);
    let he = gbsurf::mesh::HalfEdgeMesh::from_polymesh(cage).expect("mesh");
    let net = gbsurf::construct::dual_network(&he, &opts).expect("network");
    let Some((split, _)) = gbsurf::construct::network::split_large_patches(&net, k) else { return };
    let s = gbsurf::construct::assemble(&split, &opts).expect("split assembles");
    report(&format!("{name} [split above {k}]"), cage, &s, &opts, top);
}

/// `FAIR_MID=G`: the curves' middle constraints D_{0.5} chosen by an energy (see the module doc).
fn fair_mid_study(name: &str, cage: &PolyMesh, method: Method, top: usize) {
    let Some(grid) = env::<usize>("FAIR_MID") else { return };
    let opts = options(method);
    let he = gbsurf::mesh::HalfEdgeMesh::from_polymesh(cage).expect("mesh");
    let net = network(&he, &opts).expect("network");
    let (s, info) = fair_mid(&net, &opts, grid);
    println!("\n{info}");
    let joint = env::<u8>("FAIR_C") == Some(1);
    report(&format!("{name} [fair D_0.5{}, grid {grid}]", if joint { " and C" } else { "" }), cage, &s, &opts, top);
}

/// The curve network of `opts.method` (no preparation, creases or fan split).
fn network(he: &gbsurf::mesh::HalfEdgeMesh, opts: &ConvertOptions) -> Result<CurveNetwork, String> {
    let net = if opts.method == Method::Dual {
        gbsurf::construct::dual_network(he, opts)
    } else {
        gbsurf::construct::topology_network(he, opts)
    };
    net.map_err(|e| e.to_string())
}

/// `CAGES=1 sphere_fairness 0 CAGE.obj…` with `FAIR_MID=G`: per cage and structure, the patches
/// with folds ([`gbsurf::quality::find_folds`] at level 8) of the network assembled with the seed's
/// D_{0.5} and with the fair ones (the cage prepared as in a conversion; no creases, no fan split,
/// no scale normalisation: both columns are built the same way).
fn cage_folds(files: &[String]) {
    let grid = env::<usize>("FAIR_MID").unwrap_or(8);
    println!("| cage | structure | patches | folded (seed D) | folded (fair D) | folded (Middle::Fair) |");
    println!("|---|---|---|---|---|---|");
    for file in files {
        let name = file.rsplit('/').next().unwrap_or(file);
        let Ok(poly) = gbsurf::read_mesh(file) else { continue };
        let Ok(he) = gbsurf::mesh::HalfEdgeMesh::from_polymesh(&poly) else { continue };
        let Ok(prep) = gbsurf::construct::prepare(&he) else { continue };
        for method in [Method::Dual, Method::Topology] {
            let opts = options(method);
            let row = network(&prep.mesh, &opts).and_then(|net| {
                let seed = gbsurf::construct::assemble(&net, &opts).map_err(|e| e.to_string())?;
                let (fair, _) = fair_mid(&net, &opts, grid);
                let guarded = ConvertOptions { middle: gbsurf::Middle::Fair, ..opts };
                let built = gbsurf::construct::assemble(&net, &guarded).map_err(|e| e.to_string())?;
                let f = |s: &Surface| gbsurf::quality::find_folds(s, 8, opts.weights).patches;
                Ok(format!("{} | {} | {} | {}", seed.patches.len(), f(&seed), f(&fair), f(&built)))
            });
            println!("| {name} | {} | {} |", method.name(), row.unwrap_or_else(|e| format!("error: {e} | |")));
        }
    }
}

/// The surface of `net` with every shared curve's D_{0.5} chosen by the energy of the module doc
/// (`FAIR_MID`), and a line on the solve.
fn fair_mid(net: &CurveNetwork, opts: &ConvertOptions, grid: usize) -> (Surface, String) {
    let opts = *opts;
    let nc = net.curves.len();
    // With `FAIR_C` the central points are unknowns too (after the curves: unknown nc + p).
    let joint = env::<u8>("FAIR_C") == Some(1);
    let nu = if joint { nc + net.patches.len() } else { nc };
    let lapvar = env::<String>("ENERGY").as_deref() == Some("lapvar");
    let with_mid = |d: DVec3| {
        let mut n = net.clone();
        n.mid = vec![d; nc];
        gbsurf::construct::assemble(&n, &ConvertOptions { mid_scale: 1.0, ..opts }).expect("assembles")
    };
    let (s0, sx) = (with_mid(DVec3::ZERO), with_mid(DVec3::X));
    // γ[p][i][j−1]: the twist (row 1, column j) of side i of patch p per unit D_{0.5} of its curve.
    let mut gamma = Vec::new();
    let mut off_axis: f64 = 0.0;
    for (a, b) in s0.patches.iter().zip(&sx.patches) {
        let g: Vec<[f64; 2]> = a
            .ribbons()
            .iter()
            .zip(b.ribbons())
            .map(|(ra, rb)| {
                let d = [rb.row(1)[1] - ra.row(1)[1], rb.row(1)[2] - ra.row(1)[2]];
                off_axis = off_axis.max(d[0].y.abs().max(d[0].z.abs()).max(d[1].y.abs()).max(d[1].z.abs()));
                [d[0].x, d[1].x]
            })
            .collect();
        gamma.push(g);
    }
    // Normal equations N D = r (r: one column per coordinate).
    let mut nmat = vec![0.0; nu * nu];
    let mut rhs = vec![DVec3::ZERO; nu];
    for (p, patch) in s0.patches.iter().enumerate() {
        let (ribbons, center) = match patch {
            Patch::Gb(g) => (&g.ribbons, Some(g.center)),
            Patch::Cgb(c) => (&c.ribbons, None),
        };
        let n = ribbons.len();
        let mut curves: Vec<usize> = net.patches[p].sides.iter().map(|s| s.curve).collect();
        if joint && center.is_some() {
            curves.push(nc + p);
        }
        let nl = curves.len();
        let dom = Domain::regular(n).expect("domain");
        let mut rows: Vec<(Vec<[f64; 3]>, [DVec3; 3])> = Vec::new();
        for uv in energy_samples(&dom, grid, grid) {
            // Ribbon weights (normalised for CGB) and the central weight (zero for CGB).
            let (w, b0) = weights_at(n, center.is_some(), uv, opts.weights);
            let c = if joint { DVec3::ZERO } else { center.unwrap_or_default() };
            let mut a = [b0.duu * c, b0.duv * c, b0.dvv * c];
            for (q, p) in ribbons.iter().flat_map(|r| r.points()).enumerate() {
                a[0] += w[q].duu * *p;
                a[1] += w[q].duv * *p;
                a[2] += w[q].dvv * *p;
            }
            // Coefficient of each side's D in S_uu, S_uv, S_vv (row 1 is flat index i·8 + 4 + j).
            let mut m: Vec<[f64; 3]> = (0..n)
                .map(|i| {
                    let (w1, w2) = (w[i * 8 + 5], w[i * 8 + 6]);
                    let (g1, g2) = (gamma[p][i][0], gamma[p][i][1]);
                    [w1.duu * g1 + w2.duu * g2, w1.duv * g1 + w2.duv * g2, w1.dvv * g1 + w2.dvv * g2]
                })
                .collect();
            if joint && center.is_some() {
                m.push([b0.duu, b0.duv, b0.dvv]);
            }
            rows.push((m, a));
        }
        if lapvar {
            // Laplacian L = S_uu + S_vv minus its mean over the patch's samples.
            let k = rows.len() as f64;
            let lap = |m: &[[f64; 3]], i: usize| m[i][0] + m[i][2];
            let mbar: Vec<f64> = (0..nl).map(|i| rows.iter().map(|(m, _)| lap(m, i)).sum::<f64>() / k).collect();
            let abar = rows.iter().map(|(_, a)| a[0] + a[2]).sum::<DVec3>() / k;
            // `PATCH_MEAN`: each patch's energy divided by its sample count.
            let pw = if env::<u8>("PATCH_MEAN") == Some(1) { 1.0 / k } else { 1.0 };
            for (m, a) in &rows {
                let al = a[0] + a[2] - abar;
                for i in 0..nl {
                    let mi = m[i][0] + m[i][2] - mbar[i];
                    rhs[curves[i]] -= pw * mi * al;
                    for j in 0..nl {
                        nmat[curves[i] * nu + curves[j]] += pw * mi * (m[j][0] + m[j][2] - mbar[j]);
                    }
                }
            }
        } else {
            for (m, a) in &rows {
                for (k, om) in [(0, 1.0), (1, 2.0), (2, 1.0)] {
                    for i in 0..nl {
                        rhs[curves[i]] -= om * m[i][k] * a[k];
                        for j in 0..nl {
                            nmat[curves[i] * nu + curves[j]] += om * m[i][k] * m[j][k];
                        }
                    }
                }
            }
        }
    }
    // Curves without a blend (none on a closed cage) keep D = 0 rows: regularise the diagonal.
    let trace = (0..nu).map(|c| nmat[c * nu + c]).sum::<f64>() / nu as f64;
    for c in 0..nu {
        nmat[c * nu + c] += 1e-9 * trace;
    }
    // `LOCAL`: each curve's D alone, the others at the seed's (one Jacobi step from the seed).
    // `MAX_N`: curves on a patch of more sides keep the seed's D.
    let max_n = env::<usize>("MAX_N").unwrap_or(usize::MAX);
    let mut big = vec![false; nu];
    for lay in &net.patches {
        if lay.sides.len() > max_n {
            for s in &lay.sides {
                big[s.curve] = true;
            }
        }
    }
    let mut d = if env::<u8>("LOCAL") == Some(1) {
        let seed: Vec<DVec3> =
            (0..nu).map(|u| if u < nc { net.mid[u] } else { net.patches[u - nc].center.unwrap_or_default() }).collect();
        (0..nu)
            .map(|c| {
                if big[c] {
                    return seed[c];
                }
                let off: DVec3 = (0..nu).filter(|&j| j != c).map(|j| nmat[c * nu + j] * seed[j]).sum();
                (rhs[c] - off) / nmat[c * nu + c]
            })
            .collect()
    } else {
        solve(nmat, rhs, nu)
    };
    let centres = d.split_off(nc);
    let seed_ratio = net.mid.iter().zip(&d).map(|(a, b)| b.length() / a.length()).collect::<Vec<f64>>();
    let (lo, hi) = seed_ratio.iter().fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
    let info = format!("fair D_0.5: twist response off-axis {off_axis:.1e}; |D|/|D_seed| in [{lo:.3}, {hi:.3}]");
    let mut fair = net.clone();
    fair.mid = d;
    for (lay, c) in fair.patches.iter_mut().zip(&centres) {
        if lay.center.is_some() {
            lay.center = Some(*c);
        }
    }
    (gbsurf::construct::assemble(&fair, &ConvertOptions { mid_scale: 1.0, ..opts }).expect("assembles"), info)
}

/// The ribbon weights of a cubic n-sided patch at `uv` in flat order (GB, or CGB normalised by their
/// sum, eq. 3.8) and the central weight (GB; zero for CGB).
fn weights_at(n: usize, gb: bool, uv: DVec2, form: WeightForm) -> (Vec<gbsurf::gb::Jet2>, gbsurf::gb::Jet2) {
    let zero = gbsurf::gb::Jet2::ZERO;
    if gb {
        let mut ev = GbBasisEvaluator::new(n, 3).expect("evaluator");
        let mut w = vec![zero; ev.len() - 1];
        let b0 = ev.for_each_ribbon_weight(uv, form, |idx, j| w[idx - 1] = j);
        (w, b0)
    } else {
        let mut ev = gbsurf::gb::CgbBasisEvaluator::new(&vec![3; n], &vec![2; n]).expect("evaluator");
        let mut w = vec![zero; ev.len()];
        ev.eval_into(uv, form, &mut w).expect("weights");
        (w, zero)
    }
}

/// Solves the dense symmetric system `a` x = `b` (n × n, row major) by Gaussian elimination with
/// partial pivoting, one right-hand side per coordinate.
fn solve(mut a: Vec<f64>, mut b: Vec<DVec3>, n: usize) -> Vec<DVec3> {
    for k in 0..n {
        let piv = (k..n).max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs())).expect("row");
        if piv != k {
            for j in 0..n {
                a.swap(k * n + j, piv * n + j);
            }
            b.swap(k, piv);
        }
        let d = a[k * n + k];
        for i in k + 1..n {
            let f = a[i * n + k] / d;
            if f == 0.0 {
                continue;
            }
            for j in k..n {
                a[i * n + j] -= f * a[k * n + j];
            }
            let bk = b[k];
            b[i] -= f * bk;
        }
    }
    let mut x = vec![DVec3::ZERO; n];
    for k in (0..n).rev() {
        let s: DVec3 = (k + 1..n).map(|j| a[k * n + j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k * n + k];
    }
    x
}

fn report(name: &str, cage: &PolyMesh, s: &Surface, opts: &ConvertOptions, top: usize) {
    let method = opts.method;
    let samples = sample(s, opts.weights, 12);
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
            PatchSource::Face(f) => {
                let face = &cage.faces[f];
                face.iter().map(|&v| cage.positions[v as usize]).sum::<DVec3>() / face.len() as f64
            }
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
    if env::<u8>("CAGES") == Some(1) {
        return cage_folds(&std::env::args().skip(2).collect::<Vec<String>>());
    }
    let cages: Vec<(&str, PolyMesh)> = vec![
        ("uv sphere 32×16", uv_sphere(32, 16).expect("uv sphere")),
        ("ico sphere (2 splits)", ico_sphere(2)),
        ("quad sphere 4×4", quad_sphere(4)),
    ];
    for (name, cage) in &cages {
        for method in [Method::Dual, Method::Topology] {
            study(name, cage, method, top);
        }
        split_study(name, cage, top);
        fair_mid_study(name, cage, Method::Dual, top);
        fair_mid_study(name, cage, Method::Topology, top);
    }
}
