//! The curve network and its assembly into patches: boundary rows, corner blocks and twists
//! (seed 000 §2.4, §3.4, §4). Structure-agnostic: the dual (§2) and the topology-preserving (§3)
//! builders both produce a [`CurveNetwork`], and [`assemble`] turns it into a [`Surface`].

use super::blend::{cross_derivative_coeffs, decompose, hodograph, BlendKind, DirectionBlend};
use super::surface::{Patch, PatchSource, SideRef, Surface};
use super::centre;
use super::fair::{self, SharedCurve};
use super::{check_options, ConstructError, TwistMode};
use crate::options::{ConvertOptions, Middle};
use crate::progress::{par_map, Ticker};
use crate::gb::{CgbPatch, GbPatch, Ribbon};
use glam::DVec3;
use rayon::prelude::*;

/// How a patch side runs along a network curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SideUse {
    /// Index into [`CurveNetwork::curves`].
    pub curve: usize,
    /// The side runs from the curve's last control point to its first.
    pub reversed: bool,
}

/// One patch of the network before twists are set.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchLayout {
    /// Sides counter-clockwise seen from outside; side i runs from corner i−1 to corner i.
    pub sides: Vec<SideUse>,
    /// The first-approximation twist at corner i (the end of side i), used by
    /// [`TwistMode::None`] and on open sides: seed 000 eq. 2.11 (dual) or the tile vertex (§3.4.1).
    pub corner_twists: Vec<DVec3>,
    /// Central control point of a GB patch (the mesh vertex, §2.4.1; fitted to the boundary when the
    /// patch is built, for every side count but 4, docs/math.md#centre-fit); `None` for a CGB patch.
    pub center: Option<DVec3>,
    /// What the patch stands for.
    pub source: PatchSource,
}

/// A cubic curve network with node tangent planes and per-curve middle constraints: the
/// "DualNetwork" of seed 000 §2.3 or the tile network of §3.3.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveNetwork {
    /// Network nodes (face centroids / tile centres / boundary edge midpoints).
    pub nodes: Vec<DVec3>,
    /// Unit normal of the tangent plane prescribed at each node (all curve tangents there lie in it).
    pub node_normals: Vec<DVec3>,
    /// Cubic curves, control points C0..C3.
    pub curves: Vec<[DVec3; 4]>,
    /// `curve_nodes[c] = [start, end]` node indices of curve c.
    pub curve_nodes: Vec<[usize; 2]>,
    /// D_{0.5} of each curve before `mid_scale`, pointing to the left of the curve as stored, i.e.
    /// into the patch that traverses it forward (seed 000 §4.4.4 / §4.4.5; unused on open curves).
    pub mid: Vec<DVec3>,
    /// The patches.
    pub patches: Vec<PatchLayout>,
    /// Sharpness of each curve in [0, 1] (docs/math.md#creases); empty when every curve is
    /// smooth. A shared curve of sharpness 1 gets no direction blend: each side keeps the twists
    /// of an open side (G0 across it); in between the blended twists move towards those.
    pub crease: Vec<f64>,
    /// `end_scale[c][k]`: the factor by which the end vector X = 3(P − C) that curve c gives a
    /// blend at its end k (as the side next to the blended one at that corner) enters
    /// D = (λ_A X_A − λ_B X_B)/2 as λ ([`end_d`], docs/math.md#direction-blends): 2 at the
    /// face-centroid ends of the halves of a cut dual curve, whose parameter runs twice as fast
    /// as the curve's (docs/math.md#dual-creases). Empty or shorter than `curves`: 1.
    pub end_scale: Vec<[f64; 2]>,
}

/// Which patch sides use a curve: (patch, side, reversed).
type Use = (usize, usize, bool);

/// Control points of the side as the patch traverses it.
pub(super) fn side_points(net: &CurveNetwork, u: SideUse) -> [DVec3; 4] {
    let c = net.curves[u.curve];
    if u.reversed {
        [c[3], c[2], c[1], c[0]]
    } else {
        c
    }
}

/// Builds the patches of a network.
///
/// Ribbon i of a patch: row 0 = the side's curve points; row 1 = [boundary point of side i−1 at
/// column 2, twist, twist, boundary point of side i+1 at column 1] (the corner blocks interpolate
/// the adjacent boundaries). Twists:
/// - [`TwistMode::None`]: the layout's `corner_twists` (shared by both sides at a corner);
/// - [`TwistMode::Approx`] / [`TwistMode::Interp`]: on every curve shared by two patches, one
///   direction blend for both (see [`super::blend`]), with D_{0.5} = `mid_scale` · `mid[c]`
///   (kept on its side of the curve, docs/math.md#blend-side; with [`Middle::Fair`] the fair
///   value, docs/math.md#fair-middle);
/// - on open sides (curve used once): the twist of the adjacent side at that corner when that side
///   is shared, otherwise the corner twist, so the corner block stays consistent.
pub fn assemble(net: &CurveNetwork, opts: &ConvertOptions) -> Result<Surface, ConstructError> {
    assemble_ticked(net, opts, &mut Ticker::none())
}

/// Patches per progress tick of the parallel loops of [`assemble_ticked`].
const CHUNK: usize = 4096;

/// The end of the twists' share of [`assemble_ticked`]'s progress range; the fair middle
/// constraint (when chosen) takes the rest up to ½, the patches the second half.
const TWISTS_END: f32 = 0.4;

/// [`assemble`] reporting progress to `ticker` (its current part: the twists and the patches, in
/// chunks of [`CHUNK`] curves or patches; see [`crate::progress`]).
pub fn assemble_ticked(net: &CurveNetwork, opts: &ConvertOptions, ticker: &mut Ticker<'_>) -> Result<Surface, ConstructError> {
    assemble_middles(net, opts, ticker).map(|(s, _)| s)
}

/// [`assemble`] and the middle constraint D_{0.5} each curve's blend uses: `mid_scale` · `mid[c]`
/// ([`crate::options::Middle::Seed`], and every curve the fair rule leaves) or the fair value
/// (docs/math.md#fair-middle).
pub fn middles(net: &CurveNetwork, opts: &ConvertOptions) -> Result<(Surface, Vec<DVec3>), ConstructError> {
    assemble_middles(net, opts, &mut Ticker::none())
}

/// [`assemble_ticked`] and the D_{0.5} of each curve ([`middles`]).
fn assemble_middles(
    net: &CurveNetwork,
    opts: &ConvertOptions,
    ticker: &mut Ticker<'_>,
) -> Result<(Surface, Vec<DVec3>), ConstructError> {
    check_options(opts)?;
    let np = net.patches.len();
    // Curve uses and consistency: the first two uses of each curve and the count (a third use
    // is an error), in flat arrays rather than a Vec per curve.
    let nc = net.curves.len();
    let mut use_count = vec![0usize; nc];
    let mut uses: Vec<[Use; 2]> = vec![[(0, 0, false); 2]; nc];
    // Sides of patch p: flat index start[p] + i (one buffer per quantity for all sides).
    let mut start = Vec::with_capacity(np + 1);
    start.push(0usize);
    // The patch of every side, by flat side index (a table rather than a search of `start` per
    // side, for the parallel rows below; patch counts stay far below u32::MAX under the memory
    // limits).
    let mut side_patch: Vec<u32> = Vec::with_capacity(np.saturating_mul(4));
    for (p, lay) in net.patches.iter().enumerate() {
        let n = lay.sides.len();
        if n < 3 {
            return Err(ConstructError::TooFewSides { patch: p, sides: n });
        }
        if lay.corner_twists.len() != n {
            return Err(ConstructError::Internal(format!(
                "patch {p}: {} corner twists for {n} sides",
                lay.corner_twists.len()
            )));
        }
        for (i, s) in lay.sides.iter().enumerate() {
            if s.curve >= nc {
                return Err(ConstructError::Internal(format!("patch {p} side {i}: no curve {}", s.curve)));
            }
            let k = use_count[s.curve];
            if k < 2 {
                uses[s.curve][k] = (p, i, s.reversed);
            }
            use_count[s.curve] = k + 1;
        }
        // Consecutive sides must meet.
        for i in 0..n {
            let a = side_points(net, lay.sides[i]);
            let b = side_points(net, lay.sides[(i + 1) % n]);
            if a[3].distance(b[0]) > 1e-9 * (1.0 + a[3].length()) {
                return Err(ConstructError::Internal(format!(
                    "patch {p}: side {i} ends at {} but side {} starts at {}",
                    a[3],
                    (i + 1) % n,
                    b[0]
                )));
            }
        }
        start.push(start[p] + n);
        side_patch.extend(std::iter::repeat_n(p as u32, n));
    }
    for (c, (u, &count)) in uses.iter().zip(&use_count).enumerate() {
        match count {
            0 | 1 => {}
            2 if u[0].2 != u[1].2 => {}
            2 => return Err(ConstructError::InconsistentOrientation { curve: c, patches: [u[0].0, u[1].0] }),
            _ => return Err(ConstructError::NonManifoldCurve { curve: c, uses: count }),
        }
    }
    // The curve's two uses, A (forward) first, when it has two.
    let pair = |c: usize| -> Option<(Use, Use)> {
        let u = &uses[c];
        (use_count[c] == 2).then(|| if !u[0].2 { (u[0], u[1]) } else { (u[1], u[0]) })
    };

    // Rows: rows[start[p] + i] = [row0, row1] of side i of patch p, per side in parallel: an
    // indexed collect writes straight into the result (a flat_map over patches went through
    // per-thread pieces and copies: 24 ms at 160k sides).
    let mut rows: Vec<[[DVec3; 4]; 2]> = (0..start[np])
        .into_par_iter()
        .with_min_len(1 << 10)
        .map(|k| {
            let p = side_patch[k] as usize;
            let (lay, i) = (&net.patches[p], k - start[p]);
            let n = lay.sides.len();
            let prev = side_points(net, lay.sides[(i + n - 1) % n]);
            let next = side_points(net, lay.sides[(i + 1) % n]);
            let t0 = lay.corner_twists[(i + n - 1) % n];
            let t1 = lay.corner_twists[i];
            [side_points(net, lay.sides[i]), [prev[2], t0, t1, next[1]]]
        })
        .collect();

    let kind = match opts.twist {
        TwistMode::None => None,
        TwistMode::Approx => Some(BlendKind::Approx),
        TwistMode::Interp => Some(BlendKind::Interp),
    };
    let mut shared = vec![false; start[np]];
    for c in 0..nc {
        if let Some(((pa, sa, _), (pb, sb, _))) = pair(c) {
            shared[start[pa] + sa] = true;
            shared[start[pb] + sb] = true;
        }
    }
    // Sharpness per curve; a creased curve whose blend cannot be built (its node folds, or a
    // corner degenerates) is made sharp instead of refused: G0 is what a crease tends to anyway.
    let mut crease: Vec<f64> = net.crease.clone();
    let mut made_sharp = 0usize;
    let crease_of = |crease: &[f64], c: usize| crease.get(c).copied().unwrap_or(0.0);
    // The curves with a direction blend and their twists' factors per unit D_{0.5}.
    let mut blends: Vec<Option<SharedCurve>> = vec![None; nc];
    if let Some(kind) = kind {
        // Per shared curve in parallel: the blends read only rows 0 (never written here) and each
        // write only the two inner twists of its own two sides, so the order does not matter; the
        // first error in curve order is returned, as in a serial loop.
        let twists: Vec<Result<Option<([DVec3; 4], [f64; 4])>, ConstructError>> = ticker.within(0.0, TWISTS_END, |t| par_map(t, nc, CHUNK, |c| {
            let Some((a, b)) = pair(c).filter(|_| crease_of(&crease, c) < 1.0) else {
                return Ok(None);
            };
            let side_rows = |p: usize| &rows[start[p]..start[p + 1]];
            shared_twists(net, opts, kind, c, [side_rows(a.0), side_rows(b.0)], [a.1, b.1], [a.0, b.0]).map(Some)
        }))?;
        for (c, t) in twists.into_iter().enumerate() {
            let t = match t {
                Err(ConstructError::FoldedCorner { .. } | ConstructError::DegenerateCorner { .. }) if crease_of(&crease, c) > 0.0 => {
                    crease[c] = 1.0;
                    made_sharp += 1;
                    continue;
                }
                t => t,
            };
            let Some((t, gamma)) = t? else { continue };
            let Some(((pa, sa, _), (pb, sb, _))) = pair(c) else { continue };
            blends[c] = Some(SharedCurve { patches: [pa, pb], sides: [sa, sb], gamma });
            let (a, b) = (start[pa] + sa, start[pb] + sb);
            rows[a][1][1] = t[0];
            rows[a][1][2] = t[1];
            rows[b][1][1] = t[2];
            rows[b][1][2] = t[3];
        }
    }
    // Creased sides (docs/math.md#creases): at each corner the twist an open side would take (the
    // adjacent side's when that side is shared and smooth, else the corner twist), reached at
    // sharpness 1; in between the blended twist moves towards it linearly in the sharpness.
    if !net.crease.is_empty() {
        let blended = rows.clone();
        for (p, lay) in net.patches.iter().enumerate() {
            let n = lay.sides.len();
            let (shared, blended) = (&shared[start[p]..start[p + 1]], &blended[start[p]..start[p + 1]]);
            for i in 0..n {
                let c = crease_of(&crease, lay.sides[i].curve);
                if !shared[i] || c == 0.0 {
                    continue;
                }
                let (prev, next) = ((i + n - 1) % n, (i + 1) % n);
                // The adjacent side j's twist at the corner, itself moved towards the corner twist
                // by its own sharpness (so the target is continuous in every sharpness).
                let adj = |j: usize, col: usize, corner: DVec3| {
                    if kind.is_some() && shared[j] {
                        let b = blended[j][1][col];
                        b + crease_of(&crease, lay.sides[j].curve) * (corner - b)
                    } else {
                        corner
                    }
                };
                let t0 = adj(prev, 2, lay.corner_twists[prev]);
                let t1 = adj(next, 1, lay.corner_twists[i]);
                let r = &mut rows[start[p] + i][1];
                r[1] += c * (t0 - r[1]);
                r[2] += c * (t1 - r[2]);
            }
        }
    }
    // Open sides: adopt the adjacent shared side's twist at each corner.
    if kind.is_some() {
        for p in 0..np {
            let (shared, rows) = (&shared[start[p]..start[p + 1]], &mut rows[start[p]..start[p + 1]]);
            let n = rows.len();
            for i in 0..n {
                if shared[i] {
                    continue;
                }
                let prev = (i + n - 1) % n;
                let next = (i + 1) % n;
                if shared[prev] {
                    rows[i][1][1] = rows[prev][1][2];
                }
                if shared[next] {
                    rows[i][1][2] = rows[next][1][1];
                }
            }
        }
    }

    // Patch p from its rows, its central point fitted to its boundary where every side is shared
    // (docs/math.md#centre-fit): the one rule for the patches built below and for those the fair
    // middle's fold guard checks, so that the guard sees the patches the surface will have.
    let fitted = |p: usize, rows_p: &[fair::SideRows]| {
        let mut patch = patch_from_rows(&net.patches[p], rows_p)?;
        if let Patch::Gb(g) = &mut patch {
            if centre::fits(g.ribbons.len()) && shared[start[p]..start[p + 1]].iter().all(|&s| s) {
                centre::fit_centre(g, opts.weights);
            }
        }
        Some(patch)
    };
    let mut mids: Vec<DVec3> = net.mid.iter().map(|m| opts.mid_scale * *m).collect();
    // The fair middle constraints (docs/math.md#fair-middle): blended curves between two distinct
    // patches with no creased side and at most MAX_FAIR_SIDES sides (a curve used twice by one
    // patch keeps the seed's: the closed form treats its two uses as independent patches).
    if opts.middle == Middle::Fair && kind.is_some() {
        let side_curves: Vec<usize> = net.patches.iter().flat_map(|l| l.sides.iter().map(|s| s.curve)).collect();
        let plain = |p: usize| {
            let l = &net.patches[p];
            l.sides.len() <= fair::MAX_FAIR_SIDES && l.sides.iter().all(|s| crease_of(&crease, s.curve) == 0.0)
        };
        let movable: Vec<Option<SharedCurve>> =
            blends.iter().map(|b| b.filter(|b| b.patches[0] != b.patches[1] && plain(b.patches[0]) && plain(b.patches[1]))).collect();
        let center = |p: usize| net.patches[p].center;
        let asm =
            fair::Assembly { start: &start, shared: &shared, side_curves: &side_curves, center: &center, patch: &fitted };
        let delta = ticker.within(TWISTS_END, 0.5, |t| fair::fair_middles(&asm, opts, &movable, &mut rows, t))?;
        for (m, d) in mids.iter_mut().zip(delta) {
            *m += d;
        }
    }

    // Per patch in parallel, collected in patch order; the first error in patch order wins.
    let built: Vec<Result<Patch, ConstructError>> = ticker.within(0.5, 1.0, |t| {
        par_map(t, np, CHUNK, |p| {
            let rows_p = &rows[start[p]..start[p + 1]];
            if let Some(i) = rows_p.iter().position(|r| r.iter().flatten().any(|q| !q.is_finite())) {
                return Err(ConstructError::NonFinite { patch: p, side: i });
            }
            fitted(p, rows_p).ok_or_else(|| ConstructError::Internal(format!("patch {p}")))
        })
    })?;
    let patches = built.into_iter().collect::<Result<Vec<Patch>, ConstructError>>()?;
    let mut neighbors: Vec<Vec<Option<SideRef>>> = net.patches.iter().map(|l| vec![None; l.sides.len()]).collect();
    for c in 0..nc {
        if let Some(((pa, sa, _), (pb, sb, _))) = pair(c) {
            neighbors[pa][sa] = Some(SideRef { patch: pb, side: sb });
            neighbors[pb][sb] = Some(SideRef { patch: pa, side: sa });
        }
    }
    let sources: Vec<PatchSource> = net.patches.iter().map(|l| l.source).collect();
    let creases: Vec<Vec<f64>> = if net.crease.is_empty() {
        Vec::new()
    } else {
        net.patches
            .iter()
            .enumerate()
            .map(|(p, l)| {
                let shared = &shared[start[p]..start[p + 1]];
                l.sides.iter().zip(shared).map(|(s, &sh)| if sh { crease_of(&crease, s.curve) } else { 0.0 }).collect()
            })
            .collect()
    };
    let surface = Surface {
        creases,
        patches,
        neighbors,
        sources,
        curves: net.curves.iter().map(|c| c.to_vec()).collect(),
        warnings: if made_sharp > 0 {
            vec![format!(
                "{made_sharp} semi-sharp crease curve(s) were built sharp: the network folds at their node, so no G1 blend exists there (docs/math.md#creases)"
            )]
        } else {
            Vec::new()
        },
        cage: Vec::new(),
    };
    Ok((surface, mids))
}

/// The patch of layout `lay` with side rows `rows` (row 0: the curve, row 1: corner blocks and
/// twists); `None` when a point is not finite.
fn patch_from_rows(lay: &PatchLayout, rows: &[[[DVec3; 4]; 2]]) -> Option<Patch> {
    if rows.iter().flatten().flatten().any(|q| !q.is_finite()) {
        return None;
    }
    let ribbons: Vec<Ribbon> = rows.iter().map(|r| Ribbon::from_fn(3, 2, 4, |k, j| r[k][j])).collect();
    Some(match lay.center {
        Some(center) => Patch::Gb(GbPatch { ribbons, center }),
        None => Patch::Cgb(CgbPatch { ribbons }),
    })
}

/// The inner twists of the two sides on shared curve `c` (A traverses it forward, B backwards):
/// `[A col 1, A col 2, B col 1, B col 2]` of row 1, from one direction blend (seed 000 §4.4).
/// `[ra, rb]`: the rows of A's and B's sides; `[sa, sb]`: the sides on curve `c`; `[pa, pb]`:
/// the two patches. D at each end is (λ_A X_A − λ_B X_B)/2 with the end scales λ of the sides
/// next to the corner ([`CurveNetwork::end_scale`]); X_A, X_B themselves are kept. Also returns
/// each twist's factor per unit D_{0.5} (the twists are affine in it: 2kα/9 with k = 1 (approx)
/// or 2 (interp) and α that side's scalar at the twist's end; docs/math.md#fair-middle).
fn shared_twists(
    net: &CurveNetwork,
    opts: &ConvertOptions,
    kind: BlendKind,
    c: usize,
    [ra, rb]: [&[[[DVec3; 4]; 2]]; 2],
    [sa, sb]: [usize; 2],
    [pa, pb]: [usize; 2],
) -> Result<([DVec3; 4], [f64; 4]), ConstructError> {
    let cc = net.curves[c];
    let (na, nb) = (ra.len(), rb.len());
    // The end scale of the side next to the corner: side i of patch p, at its end or its start.
    let scale = |p: usize, i: usize, at_end: bool| side_end_scale(net, net.patches[p].sides[i], at_end);
    let (la0, la1) = (scale(pa, (sa + na - 1) % na, true), scale(pa, (sa + 1) % na, false));
    let (lb0, lb1) = (scale(pb, (sb + 1) % nb, false), scale(pb, (sb + nb - 1) % nb, true));
    // Cross-derivatives fixed by the network, all in A's parameter s.
    let xa0 = 3.0 * (ra[(sa + na - 1) % na][0][2] - cc[0]);
    let xa1 = 3.0 * (ra[(sa + 1) % na][0][1] - cc[3]);
    let xb0 = 3.0 * (rb[(sb + 1) % nb][0][1] - cc[0]);
    let xb1 = 3.0 * (rb[(sb + nb - 1) % nb][0][2] - cc[3]);
    let t0 = 3.0 * (cc[1] - cc[0]);
    let t1 = 3.0 * (cc[3] - cc[2]);
    let d0 = end_direction([la0, lb0], xa0, xb0, t0).ok_or_else(|| corner_error(net, c, 0, xa0, xb0, t0))?;
    let d1 = end_direction([la1, lb1], xa1, xb1, t1).ok_or_else(|| corner_error(net, c, 1, xa1, xb1, t1))?;
    // Kept on its side of the curve at T(½) = (t_0 + 2 t_1 + t_2)/4 (docs/math.md#blend-side).
    let h = hodograph(&cc);
    let blend =
        DirectionBlend::new(kind, d0, opts.mid_scale * net.mid[c], d1).kept_on_side(0.25 * (h[0] + 2.0 * h[1] + h[2]));
    let dec = |x: DVec3, d: DVec3, t: DVec3, end: usize| {
        decompose(x, d, t).ok_or(ConstructError::DegenerateCorner { curve: c, end })
    };
    let (aa0, ba0) = dec(xa0, d0, t0, 0)?;
    let (aa1, ba1) = dec(xa1, d1, t1, 1)?;
    let (ab0, bb0) = dec(xb0, d0, t0, 0)?;
    let (ab1, bb1) = dec(xb1, d1, t1, 1)?;
    // With D = (λ_A X_A − λ_B X_B)/2, λ > 0, α_A > 0 > α_B iff X_A and X_B lie on opposite sides of T. Equal
    // signs mean the network folds at that node: the blend would still make the tangent planes
    // agree, but with opposite normals (a 180° flip), so report it instead.
    for (end, aa, ab) in [(0, aa0, ab0), (1, aa1, ab1)] {
        if !(aa > 0.0 && ab < 0.0) {
            return Err(ConstructError::FoldedCorner { curve: c, end, node: net.curve_nodes[c][end] });
        }
    }
    let qa = cross_derivative_coeffs([aa0, aa1], [ba0, ba1], &blend, &cc, xa0, xa1);
    let qb = cross_derivative_coeffs([ab0, ab1], [bb0, bb1], &blend, &cc, xb0, xb1);
    // P_{j,1} = P_{j,0} + Q_j / 3 (eq. 4.23); B runs the curve backwards: its column j is A's 3−j.
    // D_{0.5} enters the blend's middle coefficient with factor k, which enters Q_1 (Q_2) with
    // 2α(0)/3 (2α(1)/3), and the twist is P + Q/3.
    let k = match kind {
        BlendKind::Approx => 1.0,
        BlendKind::Interp => 2.0,
    };
    let g = |alpha: f64| 2.0 * k * alpha / 9.0;
    Ok((
        [cc[1] + qa[1] / 3.0, cc[2] + qa[2] / 3.0, cc[2] + qb[2] / 3.0, cc[1] + qb[1] / 3.0],
        [g(aa0), g(aa1), g(ab1), g(ab0)],
    ))
}

/// The end scale λ ([`CurveNetwork::end_scale`]) of side `u` at its end (`at_end`) or its start,
/// as the patch traverses it: 1 unless the network sets it.
pub(super) fn side_end_scale(net: &CurveNetwork, u: SideUse, at_end: bool) -> f64 {
    net.end_scale.get(u.curve).map_or(1.0, |s| s[usize::from(at_end != u.reversed)])
}

/// D at a curve end (seed 000 eq. 4.7 with the end scales, docs/math.md#direction-blends):
/// (λ_A X_A − λ_B X_B)/2, X_A, X_B the end vectors 3(P − C) of the sides next to the corner in
/// the two patches and λ_A, λ_B those sides' end scales there ([`side_end_scale`]). The one
/// place D is written: the blends, the fan split's and the dual creases' D_{0.5} use it.
pub(super) fn end_d([la, lb]: [f64; 2], xa: DVec3, xb: DVec3) -> DVec3 {
    0.5 * (la * xa - lb * xb)
}

/// [`end_d`], `None` when D is parallel to the tangent (both cross-derivatives on the same side
/// of the curve by the same amount: a folded or degenerate corner).
fn end_direction(scales: [f64; 2], xa: DVec3, xb: DVec3, t: DVec3) -> Option<DVec3> {
    let d = end_d(scales, xa, xb);
    decompose(xa, d, t).map(|_| d)
}

/// Why [`end_direction`] failed at end `end` of curve `c`: a cross-derivative parallel to the
/// tangent (degenerate corner) or both on the same side (fold).
fn corner_error(net: &CurveNetwork, c: usize, end: usize, xa: DVec3, xb: DVec3, t: DVec3) -> ConstructError {
    let parallel = |x: DVec3| !(x.cross(t).length_squared() > 1e-20 * x.length_squared() * t.length_squared());
    if parallel(xa) || parallel(xb) {
        ConstructError::DegenerateCorner { curve: c, end }
    } else {
        ConstructError::FoldedCorner { curve: c, end, node: net.curve_nodes[c][end] }
    }
}

/// A patch split by [`split_large_patches`]: its index in the network before the split and the
/// indices of its parts in the split network (part j stands on side j; part 0 keeps the index).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitPatch {
    pub patch: usize,
    pub parts: Vec<usize>,
}

/// Splits every patch of more than `max_sides` sides ([`crate::limits::MAX_UNSPLIT_SIDES`]) into
/// a fan of three-sided patches around a new node (docs/math.md#high-valence-split): one point
/// of an n-sided patch costs O(n) (docs/math.md#cost-per-point), three-sided parts O(1), so
/// large faces and high valences convert in time linear in the output.
///
/// For a patch with corners N_0..N_{n−1} (corner i ends side i):
/// - centre node c: the central control point when the patch has one (the dual structure's mesh
///   vertex; at the centre of an n-gon the GB patch's central weight is (n−2)(n−4)/n² → 1, so the
///   seed's unsplit surface passes near it), else the mean of the first-approximation corner twists;
///   normal: the Newell normal of N_0..N_{n−1};
/// - spoke i from c to N_i: C0 = c, C1 = c + π_c(N_i − c)/3, C2 = N_i + (|N_i − c|/3)·w_i,
///   C3 = N_i, π_c the projection onto the tangent plane at c and w_i = unit(n_i × (â + b̂)) the
///   inward bisector of corner i in its tangent plane (â, b̂ the unit end tangent of side i and
///   start tangent of side i+1; for a corner of interior angle below 180° it lies strictly inside
///   the corner, so the parts do not fold there), so every spoke lies in both tangent planes at
///   its ends;
/// - part j: sides (side j, spoke j reversed, spoke j−1), CGB (no central point), corner twists
///   the parallelogram points C_a[2] + C_b[1] − C_a[3] of the two sides meeting there;
/// - D_{0.5} of spoke i: (D(0) + D(1))/2, D(0), D(1) the blend's end directions from the two
///   parts' neighbouring sides ([`end_d`], with their end scales), so the direction blend is
///   linear along the spoke in both blend kinds at `mid_scale` = 1, where the side rule
///   ([`DirectionBlend::kept_on_side`]) is a no-op.
///
/// A patch whose spokes would leave a tangent plane degenerate (a corner straight above or below
/// c, or no Newell normal) is left unsplit. `None` when nothing is split.
pub fn split_large_patches(net: &CurveNetwork, max_sides: usize) -> Option<(CurveNetwork, Vec<SplitPatch>)> {
    if net.patches.iter().all(|p| p.sides.len() <= max_sides) {
        return None;
    }
    let mut out = net.clone();
    let mut splits = Vec::new();
    for (p, lay) in net.patches.iter().enumerate() {
        let n = lay.sides.len();
        if n <= max_sides {
            continue;
        }
        let pts: Vec<[DVec3; 4]> = lay.sides.iter().map(|&s| side_points(net, s)).collect();
        let corner_node = |i: usize| {
            let s = lay.sides[i];
            net.curve_nodes[s.curve][if s.reversed { 0 } else { 1 }]
        };
        let corners: Vec<DVec3> = pts.iter().map(|c| c[3]).collect();
        let c = lay.center.unwrap_or_else(|| lay.corner_twists.iter().sum::<DVec3>() / n as f64);
        let nc = crate::mesh::geometry::newell_normal(&corners).normalize_or_zero();
        let plane = |x: DVec3, normal: DVec3| x - normal * normal.dot(x);
        let spokes: Vec<[DVec3; 4]> = (0..n)
            .map(|i| {
                // Into the corner, halfway between its two sides: n_i × (â + b̂), â the arriving
                // side's end tangent and b̂ the leaving side's start tangent (unit).
                let ni = net.node_normals[corner_node(i)];
                let (a, b) = (pts[i][3] - pts[i][2], pts[(i + 1) % n][1] - pts[(i + 1) % n][0]);
                let inward = ni.cross(a.normalize_or_zero() + b.normalize_or_zero()).normalize_or_zero();
                let len = corners[i].distance(c) / 3.0;
                [c, c + plane(corners[i] - c, nc) / 3.0, corners[i] + len * inward, corners[i]]
            })
            .collect();
        let ok = nc != DVec3::ZERO
            && c.is_finite()
            && spokes.iter().all(|s| {
                let len = s[3].distance(s[0]);
                s[1].distance(s[0]) > 1e-6 * len && s[2].distance(s[3]) > 1e-6 * len && s.iter().all(|q| q.is_finite())
            });
        if !ok {
            continue;
        }
        let centre_node = out.nodes.len();
        out.nodes.push(c);
        out.node_normals.push(nc);
        let first_spoke = out.curves.len();
        for (i, s) in spokes.iter().enumerate() {
            // Parts i+1 (forward, A) and i (reversed, B): D(0) from the neighbouring spokes,
            // D(1) from the sides i+1 and i at N_i (docs/math.md#high-valence-split).
            // The spokes are new curves (end scale 1); sides i+1 and i keep theirs.
            let (next, prev) = (&spokes[(i + 1) % n], &spokes[(i + n - 1) % n]);
            let d0 = end_d([1.0, 1.0], 3.0 * (next[1] - c), 3.0 * (prev[1] - c));
            let scales = [side_end_scale(net, lay.sides[(i + 1) % n], false), side_end_scale(net, lay.sides[i], true)];
            let d1 = end_d(scales, 3.0 * (pts[(i + 1) % n][1] - corners[i]), 3.0 * (pts[i][2] - corners[i]));
            out.curves.push(*s);
            out.curve_nodes.push([centre_node, corner_node(i)]);
            out.mid.push(0.5 * (d0 + d1));
            if !out.crease.is_empty() {
                out.crease.push(0.0);
            }
        }
        let spoke = |i: usize, reversed: bool| SideUse { curve: first_spoke + i, reversed };
        let mut parts = Vec::with_capacity(n);
        for j in 0..n {
            let sides = vec![lay.sides[j], spoke(j, true), spoke((j + n - 1) % n, false)];
            let sp: Vec<[DVec3; 4]> = sides.iter().map(|&s| side_points(&out, s)).collect();
            let corner_twists = (0..3).map(|k| sp[k][2] + sp[(k + 1) % 3][1] - sp[k][3]).collect();
            let part = PatchLayout { sides, corner_twists, center: None, source: lay.source };
            if j == 0 {
                out.patches[p] = part;
                parts.push(p);
            } else {
                parts.push(out.patches.len());
                out.patches.push(part);
            }
        }
        splits.push(SplitPatch { patch: p, parts });
    }
    (!splits.is_empty()).then_some((out, splits))
}

/// The cage corners of a split surface (see [`split_large_patches`]) from those of the unsplit
/// one: part j of patch p takes the sector of corner j of p at its corner 0 (N_j) and at the
/// centre, and that of corner j−1 at its corner 2 (N_{j−1}). The output faces of a split patch
/// thus keep their cage face and material; their cage coordinates follow the parts' sectors,
/// not the unsplit patch's (an approximation: UVs are continuous only within each sector).
pub fn split_cage(cage: Vec<Vec<super::surface::CageSector>>, splits: &[SplitPatch], patches: usize) -> Vec<Vec<super::surface::CageSector>> {
    if cage.is_empty() || splits.is_empty() {
        return cage;
    }
    let mut out = cage.clone();
    out.resize(patches, Vec::new());
    for s in splits {
        let Some(row) = cage.get(s.patch) else { continue };
        let n = row.len();
        if n != s.parts.len() {
            continue;
        }
        for (j, &q) in s.parts.iter().enumerate() {
            out[q] = vec![row[j], row[j], row[(j + n - 1) % n]];
        }
    }
    out
}

/// One warning per split patch (see [`split_large_patches`]), naming its vertex or face through
/// `sources` (the surface's, in the input numbering).
pub fn split_warnings(sources: &[PatchSource], splits: &[SplitPatch]) -> Vec<String> {
    splits
        .iter()
        .filter_map(|sp| {
            let what = match sources.get(sp.patch)? {
                PatchSource::Vertex(v) => format!("vertex {v} (valence {})", sp.parts.len()),
                PatchSource::Face(f) => format!("face {f} ({} sides)", sp.parts.len()),
            };
            Some(format!(
                "the patch of {what} has more than {} sides: split into {} three-sided patches around a new node (docs/math.md#high-valence-split)",
                crate::limits::MAX_UNSPLIT_SIDES,
                sp.parts.len()
            ))
        })
        .collect()
}

/// [`assemble_ticked`] with the patches of more than [`crate::limits::MAX_UNSPLIT_SIDES`] sides
/// split first ([`split_large_patches`]); when the split network does not assemble (a fan that
/// folds at its new node), the unsplit one is assembled instead. Returns the surface and the
/// splits made (empty when none).
pub fn assemble_split(net: &CurveNetwork, opts: &ConvertOptions, ticker: &mut Ticker<'_>) -> Result<(Surface, Vec<SplitPatch>), ConstructError> {
    let Some((split, splits)) = split_large_patches(net, crate::limits::MAX_UNSPLIT_SIDES) else {
        return assemble_ticked(net, opts, ticker).map(|s| (s, Vec::new()));
    };
    match assemble_ticked(&split, opts, ticker) {
        Ok(s) => Ok((s, splits)),
        Err(ConstructError::Cancelled) => Err(ConstructError::Cancelled),
        Err(_) => assemble_ticked(net, opts, ticker).map(|s| (s, Vec::new())),
    }
}
