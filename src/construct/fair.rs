//! The fair middle constraint ([`crate::options::Middle::Fair`], docs/math.md#fair-middle): each
//! shared curve's D_{0.5} moved from the seed's value D⁰ (seed 000 §4.4.5) to the minimiser of
//! the thin-plate energy of its two patches, the other curves' D_{0.5} kept at the seed's.
//!
//! A twist of a blended side is affine in its curve's D_{0.5} with one scalar factor γ
//! ([`SharedCurve::gamma`]), so each patch control point P_q moves by g_q·(D − D⁰) (g_q = γ on
//! the side's two twists and on the twists an open neighbour side adopts from it). With
//! E_p = Σ_s |S_uu|² + 2|S_uv|² + |S_vv|² over a fixed sample set of the domain and the Gram
//! table G_{qr} = Σ_s (w_q,uu w_r,uu + 2 w_q,uv w_r,uv + w_q,vv w_r,vv) of the weights w:
//!
//! ```text
//!   D = D⁰ − Σ_{p∈{A,B}} Σ_{q,r} g_q G_{qr} P_r / Σ_{p∈{A,B}} Σ_{q,q'} g_q G_{qq'} g_{q'}
//! ```
//!
//! One D per curve, used by both patches' blends: G1 holds exactly as with the seed's rule.
//! The fold guard keeps D⁰ on every curve of a patch that folds with the fair values
//! ([`guard_folds`]) but not with the seed's, until no such patch remains.

use super::surface::{Patch, Surface};
use crate::gb::{CgbBasisEvaluator, Domain, GbBasisEvaluator, Jet2, WeightForm};
use crate::options::ConvertOptions;
use crate::progress::{chunk_size, par_map, Cancelled, Ticker};
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// Curves on a patch of more sides keep the seed's D_{0.5} (measured: on the UV sphere's poles
/// the fair value does not help; docs/math.md#fair-middle).
pub const MAX_FAIR_SIDES: usize = 8;

/// Steps per side of the energy's sample grid (docs/math.md#fair-middle).
pub const ENERGY_GRID: usize = 8;

/// Steps per side of the fold guard's first layout (the tessellation's at the defaults): a patch
/// its samples clear ([`crate::tessellate::fold::ClearTest`]) has no fold; the others are
/// sampled at [`crate::tessellate::fold::DENSE_STEPS`], as the report does.
pub const GUARD_STEPS: usize = 4;

/// A curve shared by two blended patches: patch A traverses it forward, B backwards.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SharedCurve {
    /// [A, B].
    pub patches: [usize; 2],
    /// The side of each patch on the curve.
    pub sides: [usize; 2],
    /// Twist per unit D_{0.5}: [A column 1, A column 2, B column 1, B column 2] of row 1.
    pub gamma: [f64; 4],
}

/// The domain samples of the energy of an n-sided patch: the centre and, per fan triangle
/// (0, v_{i−1}, v_i) of the regular domain, (a·v_{i−1} + b·v_i)/`grid` with a ≥ 1, b ≥ 0,
/// a + b < `grid` (the boundary excluded).
pub fn energy_samples(dom: &Domain, grid: usize) -> Vec<DVec2> {
    let n = dom.n();
    let mut out = vec![DVec2::ZERO];
    for i in 0..n {
        let (p, q) = (dom.vertex(i + n - 1), dom.vertex(i));
        for a in 1..grid {
            for b in 0..grid - a {
                out.push((a as f64 * p + b as f64 * q) / grid as f64);
            }
        }
    }
    out
}

/// The rows of the Gram table G of a cubic n-sided patch for its twists: row 2i + j − 1 is
/// twist (side i, row 1, column j ∈ {1, 2}); column i·8 + k·4 + j is ribbon point (i, k, j) and
/// column 8n the central point (GB; its weight is zero for CGB). CGB weights are normalised by
/// their sum (eq. 3.8).
#[derive(Clone, Debug)]
pub struct Gram {
    n: usize,
    rows: Vec<f64>,
}

impl Gram {
    /// The table for n sides, a GB (`gb`) or CGB patch and weight form `form`.
    pub fn new(n: usize, gb: bool, form: WeightForm) -> Option<Gram> {
        let dom = Domain::regular(n).ok()?;
        let len = 8 * n + 1;
        let mut w = vec![Jet2::ZERO; len];
        let mut rows = vec![0.0; 2 * n * len];
        let (mut gbe, mut cgbe) = if gb {
            (Some(GbBasisEvaluator::new(n, 3).ok()?), None)
        } else {
            (None, Some(CgbBasisEvaluator::new(&vec![3; n], &vec![2; n]).ok()?))
        };
        for uv in energy_samples(&dom, ENERGY_GRID) {
            if let Some(e) = gbe.as_mut() {
                w[8 * n] = e.for_each_ribbon_weight(uv, form, |idx, j| w[idx - 1] = j);
            } else if let Some(e) = cgbe.as_mut() {
                e.eval_into(uv, form, &mut w[..8 * n]).ok()?;
            }
            for i in 0..n {
                for j in 0..2 {
                    let a = w[i * 8 + 5 + j];
                    let row = &mut rows[(2 * i + j) * len..(2 * i + j + 1) * len];
                    for (g, b) in row.iter_mut().zip(&w) {
                        *g += a.duu * b.duu + 2.0 * a.duv * b.duv + a.dvv * b.dvv;
                    }
                }
            }
        }
        Some(Gram { n, rows })
    }

    /// G between twist `t` (2i + j − 1) and column `q`.
    fn at(&self, t: usize, q: usize) -> f64 {
        self.rows[t * (8 * self.n + 1) + q]
    }
}

/// The Gram tables for n = 3..=[`MAX_FAIR_SIDES`], GB and CGB, one weight form.
pub struct GramTables {
    gb: Vec<Option<Gram>>,
    cgb: Vec<Option<Gram>>,
}

impl GramTables {
    /// The tables of form `form`.
    pub fn new(form: WeightForm) -> GramTables {
        // Serial (a few milliseconds): they are built inside a `OnceLock`'s initialiser, and a
        // rayon worker waiting there for its own parallel loop could pick up another conversion
        // that enters the same initialiser (a deadlock).
        let make = |gb: bool| (0..=MAX_FAIR_SIDES).map(|n| if n >= 3 { Gram::new(n, gb, form) } else { None }).collect();
        GramTables { gb: make(true), cgb: make(false) }
    }

    fn get(&self, n: usize, gb: bool) -> Option<&Gram> {
        (if gb { &self.gb } else { &self.cgb }).get(n)?.as_ref()
    }
}

/// The tables of a weight form, made once per process.
pub fn gram_tables(form: WeightForm) -> &'static GramTables {
    use std::sync::OnceLock;
    static SQUARED: OnceLock<GramTables> = OnceLock::new();
    static LINEAR: OnceLock<GramTables> = OnceLock::new();
    match form {
        WeightForm::Squared => SQUARED.get_or_init(|| GramTables::new(form)),
        WeightForm::Linear => LINEAR.get_or_init(|| GramTables::new(form)),
    }
}

/// The rows of a patch: `rows[i] = [row 0, row 1]` of side i.
pub type SideRows = [[DVec3; 4]; 2];

/// What the fair rule needs of the assembly (network.rs): patch sides, rows and how to build a
/// patch from its rows.
pub struct Assembly<'a> {
    /// Sides of patch p: `start[p]..start[p + 1]` in the flat side arrays.
    pub start: &'a [usize],
    /// Whether each side is on a curve shared by two patches.
    pub shared: &'a [bool],
    /// The curves each patch's sides run along.
    pub side_curves: &'a [usize],
    /// The central point of patch p (GB), `None` for CGB.
    pub center: &'a (dyn Fn(usize) -> Option<DVec3> + Sync),
    /// Patch p from its rows (`None` when a point is not finite).
    pub patch: &'a (dyn Fn(usize, &[SideRows]) -> Option<Patch> + Sync),
}

/// The control points of patch p moved per unit D_{0.5} of a curve on side `side` whose twists
/// move by `g = [column 1, column 2]`: (flat index i·8 + 4 + j, factor), the open neighbour
/// sides' adopted twists included.
fn entries(shared: &[bool], side: usize, g: [f64; 2]) -> [(usize, f64); 4] {
    let n = shared.len();
    let (prev, next) = ((side + n - 1) % n, (side + 1) % n);
    // An open side adopts the shared neighbour's twist at their corner (network.rs).
    let adopt = |j: usize, q: usize, f: f64| if shared[j] { (usize::MAX, 0.0) } else { (j * 8 + q, f) };
    [(side * 8 + 5, g[0]), (side * 8 + 6, g[1]), adopt(prev, 6, g[0]), adopt(next, 5, g[1])]
}

/// (Σ g_q G_{qr} P_r, Σ g_q G_{qq'} g_{q'}) of one patch for one curve (see the module doc).
fn patch_terms(gram: &Gram, rows: &[SideRows], centre: DVec3, e: &[(usize, f64); 4]) -> (DVec3, f64) {
    let n = rows.len();
    let twist = |q: usize| 2 * (q / 8) + (q % 8) - 5;
    let (mut num, mut den) = (DVec3::ZERO, 0.0);
    for &(q, g) in e.iter().filter(|x| x.0 != usize::MAX) {
        let t = twist(q);
        let mut s = gram.at(t, 8 * n) * centre;
        for (i, r) in rows.iter().enumerate() {
            for k in 0..2 {
                for j in 0..4 {
                    s += gram.at(t, i * 8 + k * 4 + j) * r[k][j];
                }
            }
        }
        num += g * s;
        for &(q2, g2) in e.iter().filter(|x| x.0 != usize::MAX) {
            den += g * g2 * gram.at(t, q2);
        }
    }
    (num, den)
}

/// Sets the fair D_{0.5} of every eligible curve in `rows` (the seed's twists, D⁰ = `seed[c]`),
/// guarded against new folds. `curves[c]`: the blended curves that may move (not creased, no
/// creased side in their patches). Returns D − D⁰ per curve (zero where the seed's is kept).
/// Progress: the closed form takes the first [`CLOSED_FORM_SHARE`] of `ticker`'s range, ticked
/// per chunk of curves; the guard the rest, ticked per chunk of patches checked (chunks of at
/// most [`CHUNK`], [`chunk_size`]), its rounds after the first within what is left (they check
/// few patches). A cancel takes effect after the running chunk.
pub fn fair_middles(
    asm: &Assembly<'_>,
    opts: &ConvertOptions,
    curves: &[Option<SharedCurve>],
    rows: &mut [SideRows],
    ticker: &mut Ticker<'_>,
) -> Result<Vec<DVec3>, Cancelled> {
    let tables = gram_tables(opts.weights);
    let start = asm.start;
    let np = start.len() - 1;
    // The entries of curve c in its patch k (A: 0, B: 1).
    let ent = |sc: &SharedCurve, k: usize| {
        let p = sc.patches[k];
        entries(&asm.shared[start[p]..start[p + 1]], sc.sides[k], [sc.gamma[2 * k], sc.gamma[2 * k + 1]])
    };
    // Δ_c = D − D⁰ per curve (zero: the seed's).
    let seed_rows: &[SideRows] = rows;
    let mut delta: Vec<DVec3> = ticker.within(0.0, CLOSED_FORM_SHARE, |t| {
        par_map(t, curves.len(), CHUNK, |c| {
            let Some(sc) = &curves[c] else { return DVec3::ZERO };
            let (mut num, mut den) = (DVec3::ZERO, 0.0);
            for k in 0..2 {
                let p = sc.patches[k];
                let n = start[p + 1] - start[p];
                let centre = (asm.center)(p);
                let Some(gram) = tables.get(n, centre.is_some()) else { return DVec3::ZERO };
                let rows_p = &seed_rows[start[p]..start[p + 1]];
                let (a, b) = patch_terms(gram, rows_p, centre.unwrap_or_default(), &ent(sc, k));
                num += a;
                den += b;
            }
            let d = -num / den;
            if den > 0.0 && d.is_finite() {
                d
            } else {
                DVec3::ZERO
            }
        })
    })?;
    // Patch p's rows with the current Δ of its curves.
    let moved_rows = |p: usize, delta: &[DVec3]| -> Vec<SideRows> {
        let mut out = seed_rows[start[p]..start[p + 1]].to_vec();
        for i in 0..out.len() {
            let c = asm.side_curves[start[p] + i];
            let Some(sc) = curves[c] else { continue };
            if delta[c] == DVec3::ZERO {
                continue;
            }
            let k = usize::from(sc.patches[1] == p && sc.sides[1] == i);
            for (q, g) in ent(&sc, k) {
                if q != usize::MAX {
                    out[q / 8][1][q % 4] += g * delta[c];
                }
            }
        }
        out
    };
    // The folded samples of each patch of `which`, in chunks of CHUNK patches, ticking the part
    // [a, b] of the guard's range between chunks.
    let folds = |which: &[usize],
                 make: &(dyn Fn(usize) -> Option<Patch> + Sync),
                 t: &mut Ticker<'_>,
                 [a, b]: [f32; 2]|
     -> Result<Vec<usize>, Cancelled> {
        let mut out = Vec::with_capacity(which.len());
        for part in which.chunks(chunk_size(which.len(), CHUNK)) {
            let patches: Vec<Option<Patch>> = part.par_iter().map(|&p| make(p)).collect();
            // A patch that cannot be built (a non-finite point) counts as folded (the caller
            // reverts it); the others are checked.
            let built: Vec<bool> = patches.iter().map(Option::is_some).collect();
            let sub = Surface::of_patches(patches.into_iter().flatten().collect());
            let mut found = guard_folds(&sub, opts.weights).into_iter();
            out.extend(built.iter().map(|&b| if b { found.next().unwrap_or(1) } else { 1 }));
            t.at_part(a, b, out.len(), which.len())?;
        }
        Ok(out)
    };
    // The guard: patches that fold with the fair values but not with the seed's revert all their
    // curves; the patches across those curves are checked again.
    let mut check: Vec<usize> = (0..np)
        .filter(|&p| (start[p]..start[p + 1]).any(|s| delta[asm.side_curves[s]] != DVec3::ZERO))
        .collect();
    // The first round checks nearly every patch: it takes the guard's range up to ¾ (the fair
    // patches to ½, the folded ones' seed patches to ¾); each later round half of what is left.
    let mut part = [0.0f32, 0.75];
    while !check.is_empty() {
        let [a, b] = part;
        let (folded, seed) = ticker.within(CLOSED_FORM_SHARE, 1.0, |t| {
            let mid = a + (b - a) * 2.0 / 3.0;
            let fair = folds(&check, &|p| (asm.patch)(p, &moved_rows(p, &delta)), t, [a, mid])?;
            let folded: Vec<usize> = check.iter().zip(&fair).filter(|x| *x.1 > 0).map(|x| *x.0).collect();
            let seed = folds(&folded, &|p| (asm.patch)(p, &seed_rows[start[p]..start[p + 1]]), t, [mid, b])?;
            Ok::<_, Cancelled>((folded, seed))
        })?;
        part = [b, b + (1.0 - b) / 2.0];
        let mut next = Vec::new();
        for (&p, &s) in folded.iter().zip(&seed) {
            if s > 0 {
                continue;
            }
            for side in start[p]..start[p + 1] {
                let c = asm.side_curves[side];
                if delta[c] != DVec3::ZERO {
                    delta[c] = DVec3::ZERO;
                    if let Some(sc) = curves[c] {
                        next.extend(sc.patches.iter().copied().filter(|&q| q != p));
                    }
                }
            }
        }
        next.sort_unstable();
        next.dedup();
        check = next;
    }
    let moved: Vec<(usize, Vec<SideRows>)> = (0..np)
        .into_par_iter()
        .filter(|&p| (start[p]..start[p + 1]).any(|s| delta[asm.side_curves[s]] != DVec3::ZERO))
        .map(|p| (p, moved_rows(p, &delta)))
        .collect();
    for (p, r) in moved {
        rows[start[p]..start[p + 1]].copy_from_slice(&r);
    }
    Ok(delta)
}

/// Curves or patches per parallel chunk between two progress ticks of [`fair_middles`].
const CHUNK: usize = 4096;

/// The closed form's share of [`fair_middles`]' progress range (one pass over the curves; the
/// guard, which builds and samples the patches, takes the rest).
const CLOSED_FORM_SHARE: f32 = 0.15;

/// The folded samples of each patch of `sub` as the report finds them at the defaults
/// (docs/math.md#fold-clearing): the fold rule and [`ClearTest`] on the triangle layout of
/// [`GUARD_STEPS`] steps per side; a patch cleared without a folded sample has none, the others
/// get [`dense_folds_of`] at [`DENSE_STEPS`].
///
/// [`ClearTest`]: crate::tessellate::fold::ClearTest
/// [`dense_folds_of`]: crate::tessellate::fold::dense_folds_of
/// [`DENSE_STEPS`]: crate::tessellate::fold::DENSE_STEPS
pub fn guard_folds(sub: &Surface, form: WeightForm) -> Vec<usize> {
    use crate::gb::SampleLayout;
    use crate::tessellate::fold::{dense_folds_of, patch_folds, Sectors, DENSE_STEPS};
    use crate::tessellate::{GbSurfaceEvaluator, PatchEvaluator};
    use std::collections::HashMap;
    let np = sub.patches.len();
    let mut counts = vec![usize::MAX; np];
    if let Ok(eval) = GbSurfaceEvaluator::new(sub, GUARD_STEPS, form) {
        let mut layouts: HashMap<usize, Option<(Sectors, SampleLayout)>> = HashMap::new();
        for p in &sub.patches {
            layouts.entry(p.sides()).or_insert_with(|| {
                let domain = eval.domain(p.sides());
                let layout = SampleLayout::new(&domain, GUARD_STEPS).ok()?;
                Some((Sectors::new(&domain, &layout.uv), layout))
            });
        }
        counts = (0..np)
            .into_par_iter()
            .map_init(Vec::new, |buf, i| {
                let p = &sub.patches[i];
                let Some((sectors, layout)) = &layouts[&p.sides()] else { return usize::MAX };
                eval.evaluate(sub, i, layout, buf);
                let f = patch_folds(p, sectors, layout, buf);
                if buf.len() == layout.uv.len() && f.cleared && f.samples.is_empty() {
                    0
                } else {
                    usize::MAX
                }
            })
            .collect();
    }
    let rest: Vec<usize> = (0..np).filter(|&p| counts[p] == usize::MAX).collect();
    for (&p, (n, _)) in rest.iter().zip(dense_folds_of(sub, &rest, DENSE_STEPS, form)) {
        counts[p] = n;
    }
    counts
}
