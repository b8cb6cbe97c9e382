//! Per-(n, d, r, weight form) weight tables: for every sample of a [`SampleLayout`] the GB basis
//! weight of every control point and its u and v derivatives, as dense matrices.
//! A patch is then evaluated at all samples by matrix × control-vector products:
//! S = Σ_c w_c P_c, S_u = Σ_c ∂_u w_c P_c, S_v = Σ_c ∂_v w_c P_c, normal = S_u × S_v / |S_u × S_v|.
//!
//! Control points are in the flat order of the GB basis: the central point first, then side i,
//! row k, column j (index 1 + (i·l + k)(d+1) + j); coordinates as SoA (x, y, z arrays).
//!
//! Layout, chosen for speed without fast-math: samples are grouped in tiles of [`TILE`]; within a
//! tile, for each control point c in order, the weights w, ∂_u w, ∂_v w of the tile's samples
//! (`data[((tile·N + c)·3 + q)·TILE + lane]`). The kernel walks the control points once per
//! tile (inner loop over control points, contiguous memory), broadcasting each control
//! coordinate and updating 9 accumulators that each hold the TILE samples as SIMD lanes: no
//! horizontal sums, no shuffles, no allocation. The kernel runs on the code path the CPU offers,
//! chosen at run time in safe code ([`SimdPath`]; the one place is `Rows::run`): 4-lane fused
//! multiply-adds with AVX2 + FMA, else the portable 2-lane kernel (multiply, then add: the
//! results of builds without dispatch). Normals are computed 4 at a time in the same pass.
//! A table is a pure kernel, like a stencil table: weights × control points → samples. It knows
//! the domain points it was built for ([`SampleLayout`]) but nothing of meshes; emitting samples
//! as triangles and keeping tables between patches or conversions belong to
//! [`crate::tessellate`].
//!
//! A large [`GbTable`] (rows for every sample above [`SECTOR_ROWS_ABOVE`] bytes) holds rows for
//! the centre and one sector only and serves all n sectors of the regular domain from them, by
//! turning the control vector's side blocks and the resulting derivatives ([`Sectors`],
//! docs/math.md#sector-tables): 1/n of the memory, and each tile of rows is read once for the n
//! sectors. Results are reported per layout sample ([`WeightTable::for_each_sample_derivs`]).
//!
//! Optionally a table also holds the second derivatives ∂_uu w, ∂_uv w, ∂_vv w (same layout, a
//! second array), for curvature: [`GbTable::with_second_derivatives`]. [`CgbTable`] is the same
//! for ribbon-only (CGB) patches: for a fixed domain point and a fixed list of per-side (d_i,
//! l_i), the normalized CGB weights w / B_sum (seed 000 eq. 3.8) are constants, so a CGB patch
//! is linear in its control points exactly like a GB patch.

use super::cgb::CgbBasisEvaluator;
use super::derivs::SurfaceDerivs;
use super::error::GbError;
use super::layout::{LayoutError, SampleLayout, Sampling};
use super::patch::{CgbPatch, GbPatch, WeightForm};
use super::weights::{GbBasis, GbBasisEvaluator};
use super::Jet2;
use crate::limits::MAX_TABLE_BYTES;
use glam::{DVec2, DVec3};
use pulp::{Simd, WithSimd};
use std::ops::Deref;

/// Samples per tile: the lanes of the kernel. 4 × f64 fills an AVX register (the dispatched
/// path); the portable path takes a tile in two halves of 2 × f64 (an SSE2 register), so the
/// table layout is the same whatever the CPU.
pub const TILE: usize = 4;

/// Lanes of the portable kernel: half a tile (safe SIMD from the `wide` crate; SSE2 on x86-64,
/// NEON on aarch64).
type Half = wide::f64x2;

/// Which code evaluates the tiles of a weight table (see [`WeightTable::eval_all_with`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SimdPath {
    /// The best the CPU offers, detected at run time (`pulp::x86::V3::try_new()`): on x86-64 with AVX2
    /// and FMA, 4-lane fused multiply-adds (results within a few ulp of the portable path's:
    /// the sums round once per term instead of twice); otherwise the portable path.
    #[default]
    Detected,
    /// The portable kernel: 2-lane multiply, then add (the results of builds without runtime
    /// dispatch, the same on every CPU).
    Portable,
}

/// Errors building a table or evaluating a patch with it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TableError {
    /// The sampling layout cannot be built.
    #[error(transparent)]
    Layout(#[from] LayoutError),
    /// The patch or the (n, d) request is invalid.
    #[error(transparent)]
    Patch(#[from] GbError),
    /// The patch does not match the table's n or d.
    #[error("patch has n = {n}, d = {d}; the table is for n = {table_n}, d = {table_d}")]
    Mismatch {
        n: usize,
        d: usize,
        table_n: usize,
        table_d: usize,
    },
    /// The CGB patch's per-side (degree, layers) differ from the table's.
    #[error("patch has sides (degree, layers) {found:?}; the table is for {table:?}")]
    CgbMismatch {
        found: Vec<(usize, usize)>,
        table: Vec<(usize, usize)>,
    },
    /// The table would need more than [`MAX_TABLE_BYTES`] of memory.
    #[error("a weight table for n = {n}, d = {d}, r = {r} would need {bytes} bytes")]
    TooLarge {
        n: usize,
        d: usize,
        r: usize,
        bytes: u128,
    },
    /// A weight of the basis came out non-finite.
    #[error("basis weight of control point {control} at sample {sample} is not finite")]
    NonFiniteWeight { sample: usize, control: usize },
}

/// The control points of one patch as padded SoA coordinate arrays, in flat basis order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ControlSoa {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
}

impl ControlSoa {
    /// Replaces the contents with flat-ordered points (no allocation once the capacity suffices).
    pub fn fill(&mut self, points: impl IntoIterator<Item = DVec3>) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
        for p in points {
            self.x.push(p.x);
            self.y.push(p.y);
            self.z.push(p.z);
        }
    }

    /// The flat-ordered control points of a GB patch: centre, then side i, row k, column j.
    pub fn fill_gb(&mut self, patch: &GbPatch) {
        let ribbons = patch.ribbons.iter().flat_map(|r| r.points().iter().copied());
        self.fill(std::iter::once(patch.center).chain(ribbons));
    }

    /// The flat-ordered control points of a CGB patch: side i, row k, column j.
    pub fn fill_cgb(&mut self, patch: &CgbPatch) {
        self.fill(patch.ribbons.iter().flat_map(|r| r.points().iter().copied()));
    }

    /// Number of control points.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True without control points.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// From flat-ordered points.
    pub fn from_points(points: &[DVec3]) -> Self {
        ControlSoa {
            x: points.iter().map(|p| p.x).collect(),
            y: points.iter().map(|p| p.y).collect(),
            z: points.iter().map(|p| p.z).collect(),
        }
    }
}

/// Position and first derivatives at one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleFrame {
    pub position: DVec3,
    pub du: DVec3,
    pub dv: DVec3,
}

impl SampleFrame {
    /// Unit normal S_u × S_v / |S_u × S_v|, `None` where the parameterization degenerates (same
    /// criterion as [`SurfaceDerivs::normal`]).
    #[inline]
    pub fn normal(&self) -> Option<DVec3> {
        SurfaceDerivs {
            p: self.position,
            su: self.du,
            sv: self.dv,
            ..Default::default()
        }
        .normal()
    }
}

/// Tiled weight rows of a basis that is linear in its control points (see the module doc), at
/// the table's row samples ([`Sectors`]).
#[derive(Clone, Debug)]
struct Rows {
    /// Number of control points N.
    controls: usize,
    /// Tiles of [`TILE`] row samples (the last one padded with zero weights).
    tiles: usize,
    /// `first[((tile·N + c)·3 + q)·TILE + lane]`, q = 0, 1, 2 for w, ∂_u w, ∂_v w.
    first: Vec<f64>,
    /// Same layout, q = 0, 1, 2 for ∂_uu w, ∂_uv w, ∂_vv w (when built).
    second: Option<Vec<f64>>,
}

/// Bytes of the rows of `samples` samples and `controls` control points.
fn rows_bytes(samples: u128, controls: u128, second: bool) -> u128 {
    samples.div_ceil(TILE as u128) * TILE as u128 * 3 * controls * 8 * if second { 2 } else { 1 }
}

impl Rows {
    /// Rows at the domain points `uv` (row sample j at `uv[j]`, layout sample `ids[j]` for
    /// errors) from `basis(uv, w, w_u, w_v, w_uu, w_uv, w_vv)` filling the weights of every
    /// control point (the last three kept when `want_second`).
    fn build(
        uv: &[DVec2],
        ids: &[u32],
        controls: usize,
        want_second: bool,
        mut basis: impl FnMut(DVec2, [&mut [f64]; 6]),
    ) -> Result<Self, TableError> {
        let samples = uv.len();
        let tiles = samples.div_ceil(TILE);
        let len = tiles * TILE * 3 * controls;
        let mut first = vec![0.0; len];
        let mut second = if want_second { vec![0.0; len] } else { Vec::new() };
        let mut buf = vec![0.0; 6 * controls];
        for (s, &uv) in uv.iter().enumerate() {
            buf.fill(0.0);
            {
                let (a, rest) = buf.split_at_mut(controls);
                let (b, rest) = rest.split_at_mut(controls);
                let (c, rest) = rest.split_at_mut(controls);
                let (d, rest) = rest.split_at_mut(controls);
                let (e, f) = rest.split_at_mut(controls);
                basis(uv, [a, b, c, d, e, f]);
            }
            let (t, lane) = (s / TILE, s % TILE);
            for c in 0..controls {
                let at = (t * controls + c) * 3 * TILE + lane;
                for q in 0..6 {
                    let v = buf[q * controls + c];
                    if !v.is_finite() {
                        let sample = ids.get(s).map_or(s, |&g| g as usize);
                        return Err(TableError::NonFiniteWeight { sample, control: c });
                    }
                    if q < 3 {
                        first[at + q * TILE] = v;
                    } else if want_second {
                        second[at + (q - 3) * TILE] = v;
                    }
                }
            }
        }
        Ok(Rows {
            controls,
            tiles,
            first,
            second: want_second.then_some(second),
        })
    }

    /// Rows of a basis given as jets (value, first and second derivatives), at the row samples
    /// of `sectors` in `layout`.
    fn from_jets(
        layout: &SampleLayout,
        sectors: &Sectors,
        controls: usize,
        want_second: bool,
        mut jets: impl FnMut(DVec2, &mut [Jet2]),
    ) -> Result<Self, TableError> {
        let ids = &sectors.global[..sectors.local];
        let uv: Vec<DVec2> = ids.iter().map(|&g| layout.uv[g as usize]).collect();
        let mut buf = vec![Jet2::ZERO; controls];
        Self::build(&uv, ids, controls, want_second, |uv, [w, wu, wv, wuu, wuv, wvv]| {
            buf.fill(Jet2::ZERO);
            jets(uv, &mut buf);
            for (m, j) in buf.iter().enumerate() {
                (w[m], wu[m], wv[m]) = (j.val, j.du, j.dv);
                (wuu[m], wuv[m], wvv[m]) = (j.duu, j.duv, j.dvv);
            }
        })
    }

    fn memory_bytes(&self) -> usize {
        (self.first.len() + self.second.as_ref().map_or(0, |s| s.len())) * std::mem::size_of::<f64>()
    }

    #[cfg(test)]
    fn weight(&self, s: usize, c: usize) -> [f64; 3] {
        let at = ((s / TILE) * self.controls + c) * 3 * TILE + s % TILE;
        [self.first[at], self.first[at + TILE], self.first[at + 2 * TILE]]
    }

    #[inline]
    fn block<'a>(&self, rows: &'a [f64], t: usize) -> &'a [f64] {
        let len = self.controls * 3 * TILE;
        rows.get(t * len..(t + 1) * len).unwrap_or(&[])
    }

    /// Runs `job` on the code path `path`: the one place of runtime CPU dispatch in the crate.
    /// With pulp (`pulp::x86::V3::try_new()`, then `vectorize`) the job, and everything it
    /// inlines (the kernel and the caller's per-sample work, e.g. normals and curvature), is
    /// compiled a second time with AVX2 and FMA enabled, and that copy runs when the CPU has
    /// them; all in safe code (the `multiversion` crate expands to `unsafe`, which this crate
    /// forbids). The job's `with_simd` must be `#[inline(always)]` for the features to reach the
    /// loop. V3 is asked for by name rather than through `pulp::Arch::new()`: should another
    /// crate of a build enable pulp's `x86-v4` feature, `Arch` would pick AVX-512, whose 8 lanes
    /// the 4-lane tiles do not use (measured here: AVX-512 with 8-lane tiles was within the
    /// noise of AVX2, 43 against 47 ns per point for n = 8). Elsewhere (aarch64's NEON has 2
    /// lanes, as `wide` already uses) the portable kernel runs.
    #[inline]
    fn run<J: WithSimd>(path: SimdPath, job: J) -> J::Output {
        #[cfg(target_arch = "x86_64")]
        if let (SimdPath::Detected, Some(v3)) = (path, pulp::x86::V3::try_new()) {
            return Simd::vectorize(v3, job);
        }
        job.with_simd(pulp::Scalar)
    }
}

/// The 9 sums of one tile: x, y, z of rows q = 0, 1, 2, each over the tile's lanes.
pub(crate) type TileSums = [[f64; TILE]; 9];

/// Σ_c row_q(c) · P_c for q = 0, 1, 2 over the lanes of one tile (`block`: the tile's weights,
/// [`Rows::block`]): with `S`'s vectors and fused multiply-adds where `S` has 4 or more f64
/// lanes dividing [`TILE`] (AVX2 + FMA, AVX-512), else the portable kernel.
#[inline(always)]
fn tile_sums<S: Simd>(simd: S, block: &[f64], ctrl: &ControlSoa) -> TileSums {
    let mut out = [[0.0; TILE]; 9];
    if S::F64_LANES >= 4 && TILE % S::F64_LANES == 0 {
        for lane in (0..TILE).step_by(S::F64_LANES) {
            vector_sums(simd, block, ctrl, lane, &mut out);
        }
    } else {
        for lane in (0..TILE).step_by(2) {
            let h = half_sums(block, ctrl, lane);
            for (o, h) in out.iter_mut().zip(h) {
                o[lane..lane + 2].copy_from_slice(&h);
            }
        }
    }
    out
}

/// [`tile_sums`] on lanes `lane..lane + S::F64_LANES`, one vector of `S` per weight row: 9
/// accumulators, 3 broadcast coordinates and one row fit the 16 AVX registers; a fused
/// multiply-add per term.
#[inline(always)]
fn vector_sums<S: Simd>(simd: S, block: &[f64], ctrl: &ControlSoa, lane: usize, out: &mut TileSums) {
    let lanes = S::F64_LANES;
    let mut acc = [simd.splat_f64s(0.0); 9];
    let coords = ctrl.x.iter().zip(ctrl.y.iter()).zip(ctrl.z.iter());
    for (wq, ((&x, &y), &z)) in block.chunks_exact(3 * TILE).zip(coords) {
        let (x, y, z) = (simd.splat_f64s(x), simd.splat_f64s(y), simd.splat_f64s(z));
        for q in 0..3 {
            let at = q * TILE + lane;
            let Some(&w) = S::as_simd_f64s(&wq[at..at + lanes]).0.first() else { continue };
            acc[3 * q] = simd.mul_add_e_f64s(w, x, acc[3 * q]);
            acc[3 * q + 1] = simd.mul_add_e_f64s(w, y, acc[3 * q + 1]);
            acc[3 * q + 2] = simd.mul_add_e_f64s(w, z, acc[3 * q + 2]);
        }
    }
    for (o, a) in out.iter_mut().zip(acc) {
        if let Some(v) = S::as_mut_simd_f64s(&mut o[lane..lane + lanes]).0.first_mut() {
            *v = a;
        }
    }
}

/// The portable kernel on lanes `lane..lane + 2` of a tile: 9 accumulators of 2 lanes (with 3
/// coordinates, one row and one product they fit the 16 SSE registers without spilling);
/// multiply, then add (`wide`'s `mul_add` without the `fma` target feature).
#[inline(always)]
fn half_sums(block: &[f64], ctrl: &ControlSoa, lane: usize) -> [[f64; 2]; 9] {
    let mut acc = [Half::ZERO; 9];
    let coords = ctrl.x.iter().zip(ctrl.y.iter()).zip(ctrl.z.iter());
    for (wq, ((&x, &y), &z)) in block.chunks_exact(3 * TILE).zip(coords) {
        let (x, y, z) = (Half::splat(x), Half::splat(y), Half::splat(z));
        for q in 0..3 {
            let at = q * TILE + lane;
            let w = Half::new([wq[at], wq[at + 1]]);
            acc[3 * q] = w * x + acc[3 * q];
            acc[3 * q + 1] = w * y + acc[3 * q + 1];
            acc[3 * q + 2] = w * z + acc[3 * q + 2];
        }
    }
    acc.map(|v| v.to_array())
}

/// A dispatched pass over the tiles of a table's rows, for each tile over the control vectors
/// `ctrls` (tile-major: each tile's weights are read from memory once for all of them, and stay
/// in the L1 cache while they serve every vector): the first-derivative sums, turned to the
/// frame of sector `q mod turns.len()` for vector q ([`turn_first`]), the unit normals
/// ([`SurfaceDerivs::normal_lanes`] of the turned derivatives: zero where undefined) and, with
/// `second`, the turned sums of the second-derivative rows, handed to
/// `emit(patch, samples, first, normals, second)` with the layout sample of each lane
/// ([`Sectors::NONE`] for none; vector q is sector q mod k of patch q / k, k sectors;
/// [`Sectors::global`]).
struct TilePass<'a, F> {
    rows: &'a Rows,
    sectors: &'a Sectors,
    ctrls: &'a [ControlSoa],
    second: bool,
    emit: F,
}

/// Unit normals of a tile's samples: `[axis][lane]`.
type TileNormals = [[f64; TILE]; 3];

impl<F: FnMut(usize, &[u32], &TileSums, &TileNormals, Option<&TileSums>)> WithSimd for TilePass<'_, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        let TilePass { rows, sectors, ctrls, second, mut emit } = self;
        let second = if second { rows.second.as_deref() } else { None };
        let (k, local) = (sectors.count.max(1), sectors.local);
        for t in 0..rows.tiles {
            let lanes = TILE.min(local.saturating_sub(t * TILE));
            for (q, ctrl) in ctrls.iter().enumerate() {
                let (p, m) = (q / k, q % k);
                let turn = sectors.turns.get(m).copied().unwrap_or(NO_TURN);
                let mut a = tile_sums(simd, rows.block(&rows.first, t), ctrl);
                if turn != NO_TURN {
                    turn_first(&mut a, turn);
                }
                // The normals before the second sums: with those sums taken first, the first
                // ones are spilled while the 16 AVX registers serve the second kernel, and the
                // conversion's path (`+curvature` in benches/gb_eval.rs) took 75–105 instead of
                // 60–65 ns per point.
                let n = SurfaceDerivs::normal_lanes([&a[3], &a[4], &a[5]], [&a[6], &a[7], &a[8]]);
                let b = second.map(|s| {
                    let mut b = tile_sums(simd, rows.block(s, t), ctrl);
                    if turn != NO_TURN {
                        turn_second(&mut b, turn);
                    }
                    b
                });
                let at = m * local + t * TILE;
                emit(p, sectors.global.get(at..at + lanes).unwrap_or(&[]), &a, &n, b.as_ref());
            }
        }
    }
}

/// Above this many bytes of rows for every sample, a [`GbTable`] holds sector rows instead
/// ([`Sectors`]): 1/n of the memory. Measured (min of 5 alternating runs, one thread, cubic,
/// position and normal): sector rows are faster once whole rows stream from memory (n = 8,
/// r = 64, 25 MiB of whole rows: 31 against 56 ns per point; in the conversion, the 26 MiB table
/// of n = 4 at r = 64 with second derivatives: 6 % less CPU in the evaluation stage), the same
/// at r = 16 (n = 3: 16.2 against 15.7 ns, n = 8: 30.4 both), and slower for tables that stay
/// in the cache, where the padding of each sector's last tile, the turns and the per-patch
/// turned control vectors weigh (n = 5, r = 4: 27.5 against 20.9 ns; with curvature, n = 4,
/// r = 2: 79 against 66 ns; the conversion's evaluation stage with 1.7 and 6.7 MiB tables: 3–5 %
/// more).
pub const SECTOR_ROWS_ABOVE: u128 = 16 << 20;

/// (cos, sin) of the zero turn.
const NO_TURN: [f64; 2] = [1.0, 0.0];

/// The first-derivative sums of a tile (rows q = 1, 2: S_u, S_v per coordinate) turned from
/// sector 0's parameter frame to that of a sector turned by the angle φ with (c, s) = (cos φ,
/// sin φ): S_u ← c·S_u − s·S_v, S_v ← s·S_u + c·S_v (docs/math.md#sector-tables).
#[inline(always)]
fn turn_first(a: &mut TileSums, [c, s]: [f64; 2]) {
    for k in 0..3 {
        for l in 0..TILE {
            let (u, v) = (a[3 + k][l], a[6 + k][l]);
            a[3 + k][l] = c * u - s * v;
            a[6 + k][l] = s * u + c * v;
        }
    }
}

/// The second-derivative sums of a tile (S_uu, S_uv, S_vv per coordinate) turned like
/// [`turn_first`]: the Hessian H ← R H Rᵀ, i.e. S_uu ← c²·S_uu − 2cs·S_uv + s²·S_vv,
/// S_uv ← cs·(S_uu − S_vv) + (c² − s²)·S_uv, S_vv ← s²·S_uu + 2cs·S_uv + c²·S_vv.
#[inline(always)]
fn turn_second(b: &mut TileSums, [c, s]: [f64; 2]) {
    let (cc, ss, cs) = (c * c, s * s, c * s);
    for k in 0..3 {
        for l in 0..TILE {
            let (uu, uv, vv) = (b[k][l], b[3 + k][l], b[6 + k][l]);
            b[k][l] = cc * uu - 2.0 * cs * uv + ss * vv;
            b[3 + k][l] = cs * (uu - vv) + (cc - ss) * uv;
            b[6 + k][l] = ss * uu + 2.0 * cs * uv + cc * vv;
        }
    }
}

/// The table's row samples and the layout's (docs/math.md#sector-tables). On the regular
/// n-gon the GB basis is n-fold symmetric: the weight of control point (side i, row k, column
/// j) at the domain point R·x, R the turn by 2π/n, is that of (side i − 1, row k, column j) at
/// x. A large [`GbTable`] therefore holds rows only for the centre and the samples of sector 0
/// ([`SampleLayout::sector_samples`]); sector m is evaluated with those rows and the control
/// vector whose side blocks are turned back by m (side i reads side i + m), its derivatives
/// then turned by 2πm/n. The n sectors of a patch share each tile of rows while it is in the
/// L1 cache, and the table takes 1/n of the memory. "Large" means above [`SECTOR_ROWS_ABOVE`]
/// bytes of rows for every sample; a smaller GbTable, and a table without this symmetry (a CGB
/// table), has one sector, the whole layout.
#[derive(Clone, Debug)]
struct Sectors {
    /// Number of sectors (n for a symmetric table, 1 otherwise).
    count: usize,
    /// Control points before the side blocks (the GB centre).
    head: usize,
    /// Control points per side block.
    per_side: usize,
    /// Row samples: the centre and sector 0's samples (symmetric), or every layout sample.
    local: usize,
    /// `global[m·local + j]`: the layout sample of row sample j in sector m; [`Sectors::NONE`]
    /// for the centre in sectors m ≥ 1 (it is sector 0's).
    global: Vec<u32>,
    /// Per layout sample: (sector, row sample).
    local_of: Vec<(u32, u32)>,
    /// Per sector m: (cos, sin) of its turn 2πm/n, exact at multiples of a quarter turn.
    turns: Vec<[f64; 2]>,
}

impl Sectors {
    const NONE: u32 = u32::MAX;

    /// One sector, every sample a row sample.
    fn whole(samples: usize) -> Self {
        Sectors {
            count: 1,
            head: 0,
            per_side: 0,
            local: samples,
            global: (0..samples as u32).collect(),
            local_of: (0..samples as u32).map(|s| (0, s)).collect(),
            turns: vec![NO_TURN],
        }
    }

    /// The n sectors of a layout of the regular n-gon, for a basis whose control vector is
    /// `head` points followed by n side blocks of `per_side` points.
    fn symmetric(layout: &SampleLayout, head: usize, per_side: usize) -> Self {
        let n = layout.sides;
        let lists: Vec<Vec<u32>> = (0..n).map(|m| layout.sector_samples(m)).collect();
        let local = 1 + lists.first().map_or(0, Vec::len);
        let mut global = Vec::with_capacity(n * local);
        let mut local_of = vec![(0, 0); layout.uv.len()];
        for (m, list) in lists.iter().enumerate() {
            global.push(if m == 0 { 0 } else { Self::NONE });
            global.extend_from_slice(list);
            for (j, &g) in list.iter().enumerate() {
                local_of[g as usize] = (m as u32, j as u32 + 1);
            }
        }
        let turns = (0..n).map(|m| Self::turn(m, n)).collect();
        Sectors { count: n, head, per_side, local, global, local_of, turns }
    }

    /// (cos, sin) of 2πm/n; exact when 4m/n is an integer.
    fn turn(m: usize, n: usize) -> [f64; 2] {
        if (4 * m) % n == 0 {
            [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]][(4 * m / n) % 4]
        } else {
            let (s, c) = (std::f64::consts::TAU * m as f64 / n as f64).sin_cos();
            [c, s]
        }
    }

    /// Bytes of the maps: 4 per entry of `global`, 8 per layout sample (`local_of`).
    fn memory_bytes(&self) -> usize {
        4 * self.global.len() + 8 * self.local_of.len()
    }

    /// [`Sectors::memory_bytes`] of a table of `samples` layout samples of an n-gon, with or
    /// without sector rows.
    fn bytes_for(samples: u128, n: u128, symmetric: bool) -> u128 {
        let sectors = if symmetric { n } else { 1 };
        4 * sectors * Self::local_count(samples, n, symmetric) + 8 * samples
    }

    /// Row samples needed for `samples` layout samples of an n-gon: 1 + (samples − 1)/n when
    /// `symmetric`.
    fn local_count(samples: u128, n: u128, symmetric: bool) -> u128 {
        if symmetric && n > 0 {
            1 + samples.saturating_sub(1) / n
        } else {
            samples
        }
    }

    /// Sector m's control vector into `out`: the head, then the side blocks turned back by m
    /// (block i of `out` is block i + m mod n of `ctrl`); `ctrl` as it is for sector 0 or a
    /// vector of another length (which the table's checks refuse elsewhere).
    fn turn_controls(&self, ctrl: &ControlSoa, m: usize, out: &mut ControlSoa) {
        let whole = self.head + self.count * self.per_side;
        let split = self.head + (m % self.count.max(1)) * self.per_side;
        for (o, c) in [(&mut out.x, &ctrl.x), (&mut out.y, &ctrl.y), (&mut out.z, &ctrl.z)] {
            o.clear();
            if c.len() != whole || split == self.head {
                o.extend_from_slice(c);
            } else {
                o.extend_from_slice(&c[..self.head]);
                o.extend_from_slice(&c[split..]);
                o.extend_from_slice(&c[self.head..split]);
            }
        }
    }
}

/// Patches per pass of a table with sector rows (see [`WeightTable::eval_batch`]).
const SECTOR_CHUNK: usize = 16;

thread_local! {
    /// Per thread: the sector control vectors of the patches being evaluated (reused, so a
    /// pass allocates nothing once warm).
    static SECTOR_CONTROLS: std::cell::RefCell<Vec<ControlSoa>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Lane `l` of the sums rows `q..q + 3` (x, y, z) as a point.
#[inline(always)]
fn lane3(a: &TileSums, q: usize, l: usize) -> DVec3 {
    DVec3::new(a[q][l], a[q + 1][l], a[q + 2][l])
}

/// The derivatives at every lane of a tile's sums (second derivatives zero without `b`).
#[inline(always)]
fn derivs(a: &TileSums, b: Option<&TileSums>) -> [SurfaceDerivs; TILE] {
    let b = b.copied().unwrap_or([[0.0; TILE]; 9]);
    std::array::from_fn(|l| SurfaceDerivs {
        p: lane3(a, 0, l),
        su: lane3(a, 3, l),
        sv: lane3(a, 6, l),
        suu: lane3(&b, 0, l),
        suv: lane3(&b, 3, l),
        svv: lane3(&b, 6, l),
    })
}

impl Rows {
    /// Position and derivatives at row sample `s` (scalar; sector 0's frame).
    fn sample(&self, s: usize, ctrl: &ControlSoa) -> SampleFrame {
        let (t, lane) = (s / TILE, s % TILE);
        let block = self.block(&self.first, t);
        let mut acc = [DVec3::ZERO; 3];
        let coords = ctrl.x.iter().zip(ctrl.y.iter()).zip(ctrl.z.iter());
        for (wq, ((&x, &y), &z)) in block.chunks_exact(3 * TILE).zip(coords) {
            let p = DVec3::new(x, y, z);
            for (q, a) in acc.iter_mut().enumerate() {
                *a += wq[q * TILE + lane] * p;
            }
        }
        SampleFrame { position: acc[0], du: acc[1], dv: acc[2] }
    }
}

/// The part every weight table shares: the samples it was built for and the tiled weight rows
/// of its control points. [`GbTable`] and [`CgbTable`] add what the rows are the basis of and
/// dereference to this.
#[derive(Clone, Debug)]
pub struct WeightTable {
    /// Samples and triangles.
    pub layout: SampleLayout,
    rows: Rows,
    sectors: Sectors,
}

impl WeightTable {
    /// Number of flat control points N.
    pub fn control_count(&self) -> usize {
        self.rows.controls
    }

    /// Memory held by the weights and the sample maps ([`Sectors`]), in bytes (the layout's
    /// own arrays not counted).
    pub fn memory_bytes(&self) -> usize {
        self.rows.memory_bytes() + self.sectors.memory_bytes()
    }

    /// Number of samples (of the layout).
    pub fn sample_count(&self) -> usize {
        self.layout.uv.len()
    }

    /// Number of tiles of [`TILE`] row samples (of sector 0 and the centre with sector rows; of
    /// the whole layout otherwise).
    pub fn tile_count(&self) -> usize {
        self.rows.tiles
    }

    /// Number of sectors the rows serve: n for a [`GbTable`] with sector rows (above
    /// [`SECTOR_ROWS_ABOVE`]), else 1.
    pub fn sector_count(&self) -> usize {
        self.sectors.count
    }

    /// True when the table holds the second derivatives.
    pub fn has_second_derivatives(&self) -> bool {
        self.rows.second.is_some()
    }

    /// The weight, u- and v-derivative of flat control point `c` at row sample `s` (tests only).
    #[cfg(test)]
    fn weight(&self, s: usize, c: usize) -> [f64; 3] {
        self.rows.weight(s, c)
    }

    /// Calls `f(s, derivatives, normal)` for every sample s of the layout (in the order of
    /// the row tiles and sectors, each sample once), with the position, first and second
    /// derivatives (second ones zero unless the table has them) and the unit normal (bit for
    /// bit [`SurfaceDerivs::normal`] of those derivatives, computed 4 at a time), in one
    /// dispatched pass. `ctrl` must come from the table's `controls_of` (another vector gives
    /// unspecified values, without a panic).
    #[inline]
    pub fn for_each_sample_derivs(&self, ctrl: &ControlSoa, f: impl FnMut(usize, &SurfaceDerivs, Option<DVec3>)) {
        self.for_each_sample_derivs_with(SimdPath::Detected, ctrl, f);
    }

    /// [`WeightTable::for_each_sample_derivs`] on the code path `path`.
    #[inline]
    pub fn for_each_sample_derivs_with(
        &self,
        path: SimdPath,
        ctrl: &ControlSoa,
        mut f: impl FnMut(usize, &SurfaceDerivs, Option<DVec3>),
    ) {
        self.pass(path, std::slice::from_ref(ctrl), true, |_, ids, a, n, b| {
            let normals: [Option<DVec3>; TILE] = std::array::from_fn(|l| {
                let v = DVec3::new(n[0][l], n[1][l], n[2][l]);
                (v != DVec3::ZERO).then_some(v)
            });
            for ((&g, d), &n) in ids.iter().zip(&derivs(a, b)).zip(&normals) {
                if g != Sectors::NONE {
                    f(g as usize, d, n);
                }
            }
        });
    }

    /// One dispatched pass over the rows for the control vectors `ctrls` (of patches), each
    /// expanded into its sectors' vectors ([`Sectors::turn_controls`]): calls
    /// `emit(patch, samples, first, normals, second)` once per tile and sector of each patch,
    /// `samples` the layout sample of each lane ([`Sectors::NONE`] for none).
    #[inline]
    fn pass(
        &self,
        path: SimdPath,
        ctrls: &[ControlSoa],
        second: bool,
        emit: impl FnMut(usize, &[u32], &TileSums, &TileNormals, Option<&TileSums>),
    ) {
        let sec = &self.sectors;
        let k = sec.count.max(1);
        if k == 1 {
            return Rows::run(path, TilePass { rows: &self.rows, sectors: sec, ctrls, second, emit });
        }
        // Taken out of the thread's cell for the pass (a nested pass finds it empty, not
        // borrowed; a thread being torn down uses a fresh Vec), put back afterwards. Patches
        // go in chunks of SECTOR_CHUNK, so the scratch stays small and each tile's sweep over
        // the chunk's sector vectors stays in the cache.
        let mut all = SECTOR_CONTROLS.try_with(|c| c.take()).unwrap_or_default();
        let mut emit = emit;
        for (c, chunk) in ctrls.chunks(SECTOR_CHUNK).enumerate() {
            all.resize_with(chunk.len() * k, ControlSoa::default);
            for (p, ctrl) in chunk.iter().enumerate() {
                for m in 0..k {
                    sec.turn_controls(ctrl, m, &mut all[p * k + m]);
                }
            }
            let emit = |p: usize, ids: &[u32], a: &TileSums, n: &TileNormals, b: Option<&TileSums>| emit(c * SECTOR_CHUNK + p, ids, a, n, b);
            Rows::run(path, TilePass { rows: &self.rows, sectors: sec, ctrls: &all[..chunk.len() * k], second, emit });
        }
        let _ = SECTOR_CONTROLS.try_with(|c| c.replace(all));
    }

    /// Position and derivatives at sample `s` alone (scalar). For all samples use
    /// [`WeightTable::eval_all`] or [`WeightTable::for_each_sample_derivs`] (tile-wise, faster).
    pub fn eval_sample(&self, s: usize, ctrl: &ControlSoa) -> SampleFrame {
        let sec = &self.sectors;
        let Some(&(m, j)) = sec.local_of.get(s) else {
            return SampleFrame { position: DVec3::ZERO, du: DVec3::ZERO, dv: DVec3::ZERO };
        };
        if m == 0 {
            return self.rows.sample(j as usize, ctrl);
        }
        let mut turned = ControlSoa::default();
        sec.turn_controls(ctrl, m as usize, &mut turned);
        let f = self.rows.sample(j as usize, &turned);
        // The same turn as the tiles' (turn_first), on lane 0.
        let mut a = [[0.0; TILE]; 9];
        for (k, (u, v)) in f.du.to_array().into_iter().zip(f.dv.to_array()).enumerate() {
            (a[3 + k][0], a[6 + k][0]) = (u, v);
        }
        turn_first(&mut a, sec.turns.get(m as usize).copied().unwrap_or(NO_TURN));
        SampleFrame { position: f.position, du: lane3(&a, 3, 0), dv: lane3(&a, 6, 0) }
    }

    /// Positions and unit normals at all samples, into `positions` and `normals` (resized to
    /// the sample count and overwritten; no allocation once they have the capacity). `ctrl`
    /// must come from the table's `controls_of`.
    pub fn eval_all(&self, ctrl: &ControlSoa, positions: &mut Vec<DVec3>, normals: &mut Vec<DVec3>) {
        self.eval_all_with(SimdPath::Detected, ctrl, positions, normals);
    }

    /// [`WeightTable::eval_all`] on the code path `path`.
    pub fn eval_all_with(
        &self,
        path: SimdPath,
        ctrl: &ControlSoa,
        positions: &mut Vec<DVec3>,
        normals: &mut Vec<DVec3>,
    ) {
        self.eval_batch_with(path, std::slice::from_ref(ctrl), std::slice::from_mut(positions), std::slice::from_mut(normals));
    }

    /// Several patches at once, tile-major: each tile of weight rows is read once from memory
    /// and applied to every patch (and sector). `positions[p]`, `normals[p]` receive patch p's
    /// samples (zero normals where undefined).
    pub fn eval_batch(&self, ctrls: &[ControlSoa], positions: &mut [Vec<DVec3>], normals: &mut [Vec<DVec3>]) {
        self.eval_batch_with(SimdPath::Detected, ctrls, positions, normals);
    }

    /// [`WeightTable::eval_batch`] on the code path `path`.
    pub fn eval_batch_with(
        &self,
        path: SimdPath,
        ctrls: &[ControlSoa],
        positions: &mut [Vec<DVec3>],
        normals: &mut [Vec<DVec3>],
    ) {
        // The pass writes every sample once, so vectors of the right length are only
        // overwritten (no clearing pass over memory the evaluation fills anyway).
        let samples = self.sample_count();
        let count = ctrls.len().min(positions.len()).min(normals.len());
        for (k, v) in positions.iter_mut().enumerate().chain(normals.iter_mut().enumerate()) {
            if k < count {
                v.resize(samples, DVec3::ZERO);
            } else {
                v.clear();
            }
        }
        self.pass(path, &ctrls[..count], false, |p, ids, a, n, _| {
            for (l, &g) in ids.iter().enumerate() {
                if let (Some(pos), Some(nrm)) = (positions[p].get_mut(g as usize), normals[p].get_mut(g as usize)) {
                    *pos = lane3(a, 0, l);
                    *nrm = DVec3::new(n[0][l], n[1][l], n[2][l]);
                }
            }
        });
    }
}

/// Dense weight table of one (n, d, r, weight form); see the module doc.
#[derive(Clone, Debug)]
pub struct GbTable {
    /// Number of sides n.
    pub sides: usize,
    /// Degree d.
    pub degree: usize,
    /// Weight form of the correction weights μ.
    pub form: WeightForm,
    table: WeightTable,
}

impl Deref for GbTable {
    type Target = WeightTable;
    fn deref(&self) -> &WeightTable {
        &self.table
    }
}

impl GbTable {
    /// The table of the GB basis ([`GbBasisEvaluator`]) of n sides, degree d and weight form
    /// `form` at the samples of [`SampleLayout::for_domain`] at resolution r.
    pub fn new(
        sides: usize,
        degree: usize,
        resolution: impl Into<Sampling>,
        form: WeightForm,
    ) -> Result<Self, TableError> {
        Self::build(sides, degree, resolution.into(), form, false, None)
    }

    /// As [`GbTable::new`], also with the second derivatives of the weights (for
    /// [`WeightTable::for_each_sample_derivs`]: curvature). Twice the memory.
    pub fn with_second_derivatives(
        sides: usize,
        degree: usize,
        resolution: impl Into<Sampling>,
        form: WeightForm,
    ) -> Result<Self, TableError> {
        Self::build(sides, degree, resolution.into(), form, true, None)
    }

    /// Whether a table of (n, d, r) holds sector rows ([`Sectors`]; `force` decides when
    /// given, else: when rows for every sample would take more than [`SECTOR_ROWS_ABOVE`]
    /// bytes), and the bytes it needs (rows and sample maps). `GbTable::new` and
    /// `with_second_derivatives` may thus choose differently for one (n, d, r); their results
    /// then differ by rounding.
    fn plan(sides: usize, degree: usize, sampling: Sampling, second: bool, force: Option<bool>) -> (bool, u128) {
        let controls = GbBasis::len_for(sides, degree) as u128;
        let samples = sampling.sample_count(sides) as u128;
        let sectors = force.unwrap_or_else(|| rows_bytes(samples, controls, second) > SECTOR_ROWS_ABOVE);
        let n = sides as u128;
        let rows = rows_bytes(Sectors::local_count(samples, n, sectors), controls, second);
        (sectors, rows + Sectors::bytes_for(samples, n, sectors))
    }

    /// The bytes a table of (n, d, r) needs (with or without second derivatives): rows for
    /// every sample, or for the centre and one sector's samples above [`SECTOR_ROWS_ABOVE`],
    /// and the sample maps ([`WeightTable::memory_bytes`]).
    pub fn bytes_needed(sides: usize, degree: usize, resolution: impl Into<Sampling>, second: bool) -> u128 {
        Self::plan(sides, degree, resolution.into(), second, None).1
    }

    /// The table; with sector rows when `sectors` says so, else as [`GbTable::plan`] decides.
    fn build(
        sides: usize,
        degree: usize,
        sampling: Sampling,
        form: WeightForm,
        second: bool,
        sectors: Option<bool>,
    ) -> Result<Self, TableError> {
        let resolution = sampling.resolution;
        let mut ev = GbBasisEvaluator::new(sides, degree)?;
        let (use_sectors, bytes) = Self::plan(sides, degree, sampling, second, sectors);
        if bytes > MAX_TABLE_BYTES {
            return Err(TableError::TooLarge {
                n: sides,
                d: degree,
                r: resolution,
                bytes,
            });
        }
        let layout = SampleLayout::for_domain(ev.domain(), sampling)?;
        let controls = ev.len();
        let sectors = if use_sectors {
            // Control vector: the centre, then n side blocks of l·(d+1) points.
            Sectors::symmetric(&layout, 1, (controls - 1) / sides)
        } else {
            Sectors::whole(layout.uv.len())
        };
        let rows = Rows::from_jets(&layout, &sectors, controls, second, |uv, jets| {
            // `jets` has the evaluator's length, so this cannot fail.
            let _ = ev.eval_into(uv, form, jets);
        })?;
        Ok(GbTable {
            sides,
            degree,
            form,
            table: WeightTable { layout, rows, sectors },
        })
    }

    /// The SoA control vector of a patch of this table's n and d.
    pub fn controls_of(&self, patch: &GbPatch) -> Result<ControlSoa, TableError> {
        patch.validate()?;
        let pts = patch.control_points_flat();
        let (n, d) = (patch.n(), patch.degree());
        if n != self.sides || d != self.degree {
            return Err(TableError::Mismatch {
                n,
                d,
                table_n: self.sides,
                table_d: self.degree,
            });
        }
        Ok(ControlSoa::from_points(&pts))
    }
}

/// Weight table of ribbon-only (CGB) patches with per-side (degree, layers) `sides`, at the
/// samples of [`SampleLayout::for_domain`] at one resolution: the normalized weights
/// w / B_sum (seed 000 eq. 3.8) with first and second derivatives (quotient rule, exact), in
/// the flat order side i, row k, column j ([`CgbPatch::control_points_flat`]).
#[derive(Clone, Debug)]
pub struct CgbTable {
    /// Per side: (degree d_i, layer count l_i).
    pub sides: Vec<(usize, usize)>,
    /// Weight form of the correction weights μ.
    pub form: WeightForm,
    table: WeightTable,
}

impl Deref for CgbTable {
    type Target = WeightTable;
    fn deref(&self) -> &WeightTable {
        &self.table
    }
}

impl CgbTable {
    /// The bytes a CGB table of `sides` at resolution r needs.
    pub fn bytes_needed(sides: &[(usize, usize)], resolution: impl Into<Sampling>) -> u128 {
        let controls: u128 = sides.iter().map(|&(d, l)| (l * (d + 1)) as u128).sum();
        let samples = resolution.into().sample_count(sides.len()) as u128;
        rows_bytes(samples, controls, true) + Sectors::bytes_for(samples, sides.len() as u128, false)
    }

    /// Builds the table (with second derivatives).
    pub fn new(sides: &[(usize, usize)], resolution: impl Into<Sampling>, form: WeightForm) -> Result<Self, TableError> {
        let sampling: Sampling = resolution.into();
        let resolution = sampling.resolution;
        let degrees: Vec<usize> = sides.iter().map(|s| s.0).collect();
        let layers: Vec<usize> = sides.iter().map(|s| s.1).collect();
        let mut ev = CgbBasisEvaluator::new(&degrees, &layers)?;
        let bytes = Self::bytes_needed(sides, sampling);
        if bytes > MAX_TABLE_BYTES {
            return Err(TableError::TooLarge {
                n: sides.len(),
                d: degrees.iter().copied().max().unwrap_or(0),
                r: resolution,
                bytes,
            });
        }
        let layout = SampleLayout::for_domain(ev.domain(), sampling)?;
        let sectors = Sectors::whole(layout.uv.len());
        let rows = Rows::from_jets(&layout, &sectors, ev.len(), true, |uv, jets| {
            // `jets` has the evaluator's length, so this cannot fail.
            let _ = ev.eval_into(uv, form, jets);
        })?;
        Ok(CgbTable {
            sides: sides.to_vec(),
            form,
            table: WeightTable { layout, rows, sectors },
        })
    }

    /// The SoA control vector of a patch with this table's sides.
    pub fn controls_of(&self, patch: &CgbPatch) -> Result<ControlSoa, TableError> {
        patch.validate()?;
        let found: Vec<(usize, usize)> = patch.ribbons.iter().map(|r| (r.degree, r.layers())).collect();
        if found != self.sides {
            return Err(TableError::CgbMismatch {
                found,
                table: self.sides.clone(),
            });
        }
        let mut c = ControlSoa::default();
        c.fill_cgb(patch);
        Ok(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gb::Evaluate;

    #[test]
    fn table_sizes_and_errors() {
        let a = GbTable::new(5, 3, 4, WeightForm::Squared).unwrap();
        assert_eq!(a.control_count(), 1 + 5 * 2 * 4);
        let tiles = SampleLayout::sample_count(5, 4).div_ceil(TILE);
        assert_eq!((a.sector_count(), a.tile_count()), (1, tiles));
        let samples = SampleLayout::sample_count(5, 4);
        assert_eq!(a.memory_bytes(), 41 * 3 * 8 * TILE * tiles + 12 * samples);
        assert_eq!(GbTable::bytes_needed(5, 3, 4, false), a.memory_bytes() as u128);
        // Sector rows: the centre and one sector, 1 + 4·5/2 = 11 samples, 3 tiles.
        let b = GbTable::build(5, 3, 4.into(), WeightForm::Squared, false, Some(true)).unwrap();
        assert_eq!((b.sector_count(), b.tile_count()), (5, 3));
        assert_eq!(b.memory_bytes(), 41 * 3 * 8 * TILE * 3 + 4 * 5 * 11 + 8 * samples);
        // Large tables take sector rows by themselves, and say so in bytes_needed.
        let sampling = Sampling::new(super::super::layout::Layout::Quads, 40);
        let big = GbTable::new(8, 3, sampling, WeightForm::Squared).unwrap();
        assert_eq!(big.sector_count(), 8);
        assert_eq!(GbTable::bytes_needed(8, 3, sampling, false), big.memory_bytes() as u128);
        assert!(rows_bytes(sampling.sample_count(8) as u128, 65, false) > SECTOR_ROWS_ABOVE);
        let s = GbTable::with_second_derivatives(5, 3, 4, WeightForm::Squared).unwrap();
        assert!(s.has_second_derivatives() && !a.has_second_derivatives());
        assert_eq!(s.memory_bytes() - 12 * 51, 2 * (a.memory_bytes() - 12 * 51));
        // Exact turns at quarter and half turns.
        assert_eq!((Sectors::turn(1, 4), Sectors::turn(3, 6), Sectors::turn(6, 8)), ([0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]));
        assert!(matches!(
            GbTable::new(2, 3, 4, WeightForm::Squared),
            Err(TableError::Patch(_))
        ));
        assert!(matches!(
            GbTable::new(8, 10, 100_000, WeightForm::Squared),
            Err(TableError::TooLarge { .. })
        ));
    }

    #[test]
    fn weights_sum_to_one_and_derivatives_to_zero() {
        let t = GbTable::new(6, 4, 5, WeightForm::Squared).unwrap();
        for s in 0..t.sectors.local {
            let sum = (0..t.control_count()).fold([0.0; 3], |a, c| {
                let w = t.weight(s, c);
                [a[0] + w[0], a[1] + w[1], a[2] + w[2]]
            });
            assert_near!(sum[0], 1.0);
            assert_near!(sum[1], 0.0, 1e-11);
            assert_near!(sum[2], 0.0, 1e-11);
        }
    }

    /// Deterministic scattered control rows: side i of degree `degrees[i]` with `layers[i]` rows.
    fn ribbons(degrees: &[usize], layers: &[usize]) -> Vec<crate::gb::Ribbon> {
        let mut seed = 0.37_f64;
        let mut next = || {
            seed = (seed * 97.13 + 0.311).fract();
            seed - 0.5
        };
        degrees
            .iter()
            .zip(layers)
            .enumerate()
            .map(|(i, (&d, &l))| {
                crate::gb::Ribbon::from_fn(d, l, d + 1, |k, j| {
                    DVec3::new(i as f64 + next(), j as f64 + next(), k as f64 + next())
                })
            })
            .collect()
    }

    /// Every sample's derivatives and normal through [`WeightTable::for_each_sample_derivs_with`].
    fn all_derivs(t: &WeightTable, path: SimdPath, ctrl: &ControlSoa) -> Vec<(SurfaceDerivs, Option<DVec3>)> {
        let mut out = vec![None; t.sample_count()];
        t.for_each_sample_derivs_with(path, ctrl, |s, d, n| {
            assert!(out[s].is_none(), "sample {s} twice");
            out[s] = Some((*d, n));
        });
        out.into_iter().enumerate().map(|(s, d)| d.unwrap_or_else(|| panic!("sample {s} missing"))).collect()
    }

    fn assert_derivs(a: &SurfaceDerivs, b: &SurfaceDerivs) {
        for (x, y) in [(a.p, b.p), (a.su, b.su), (a.sv, b.sv), (a.suu, b.suu), (a.suv, b.suv), (a.svv, b.svv)] {
            assert_near!(x, y, 1e-10);
        }
    }

    #[test]
    fn second_derivative_rows_match_direct_gb_evaluation() {
        for (form, sectors) in [(WeightForm::Squared, false), (WeightForm::Linear, false), (WeightForm::Squared, true)] {
            let t = GbTable::build(5, 3, 4.into(), form, true, Some(sectors)).unwrap();
            let patch = GbPatch { ribbons: ribbons(&[3; 5], &[2; 5]), center: DVec3::new(0.1, 0.2, 1.3) };
            let ctrl = t.controls_of(&patch).unwrap();
            let mut fast = ControlSoa::default();
            fast.fill_gb(&patch);
            assert_eq!(fast, ctrl);
            for (s, (d, n)) in all_derivs(&t, SimdPath::Detected, &ctrl).iter().enumerate() {
                assert_derivs(d, &patch.eval_derivs(t.layout.uv[s], form));
                assert_eq!(*n, d.normal());
                let f = t.eval_sample(s, &ctrl);
                for (x, y) in [(f.position, d.p), (f.du, d.su), (f.dv, d.sv)] {
                    assert_near!(x, y, 1e-12);
                }
            }
        }
        // Without second-derivative rows they read as zero.
        let t = GbTable::new(4, 3, 2, WeightForm::Squared).unwrap();
        let patch = GbPatch { ribbons: ribbons(&[3; 4], &[2; 4]), center: DVec3::Z };
        for (d, _) in all_derivs(&t, SimdPath::Detected, &t.controls_of(&patch).unwrap()) {
            assert_eq!((d.suu, d.suv, d.svv), (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO));
        }
    }

    /// The sector rows ([`Sectors`]) against direct evaluation at every sample of both layouts,
    /// every n, several resolutions: the turned control vectors and the turned first and second
    /// derivatives are those of the patch at the sample's own domain point.
    #[test]
    fn sector_rows_serve_every_sector_of_both_layouts() {
        use super::super::layout::Layout;
        for layout in [Layout::Triangles, Layout::Quads] {
            for n in 3..=8 {
                for r in [1, 2, 3, 5] {
                    let (d, form) = [(3, WeightForm::Squared), (2, WeightForm::Squared), (4, WeightForm::Linear), (5, WeightForm::Squared)][(n + r) % 4];
                    let t = GbTable::build(n, d, Sampling::new(layout, r), form, true, Some(true)).unwrap();
                    assert_eq!(t.sector_count(), n);
                    let l = d.div_ceil(2);
                    let patch = GbPatch { ribbons: ribbons(&vec![d; n], &vec![l; n]), center: DVec3::new(0.1, -0.2, 1.1) };
                    let ctrl = t.controls_of(&patch).unwrap();
                    for path in [SimdPath::Detected, SimdPath::Portable] {
                        for (s, (dv, nv)) in all_derivs(&t, path, &ctrl).iter().enumerate() {
                            assert_derivs(dv, &patch.eval_derivs(t.layout.uv[s], form));
                            assert_eq!(*nv, dv.normal(), "{layout:?} r {r} s {s}");
                            let f = t.eval_sample(s, &ctrl);
                            assert_near!(f.du, dv.su, 1e-12);
                        }
                    }
                    // Several patches at once (more than one chunk of SECTOR_CHUNK): each its own.
                    let patches: Vec<GbPatch> = (0..SECTOR_CHUNK + 3)
                        .map(|k| GbPatch { center: DVec3::new(0.1 * k as f64, -0.2, 1.1), ..patch.clone() })
                        .collect();
                    let ctrls: Vec<ControlSoa> = patches.iter().map(|p| t.controls_of(p).unwrap()).collect();
                    let (mut pos, mut nrm) = (vec![Vec::new(); ctrls.len() + 1], vec![Vec::new(); ctrls.len()]);
                    t.eval_batch(&ctrls, &mut pos, &mut nrm);
                    assert!(pos[ctrls.len()].is_empty());
                    for (k, p) in patches.iter().enumerate() {
                        for (s, &uv) in t.layout.uv.iter().enumerate() {
                            assert_near!(pos[k][s], p.eval(uv, form), 1e-10);
                        }
                    }
                }
            }
        }
    }

    /// Both code paths against the plain sum Σ_c w_c·P_c over the table's weights (at the
    /// sample's row sample, with its sector's control vector, then turned by the same
    /// [`turn_first`] / [`turn_second`]): the portable path bit for bit (multiply, then add, in
    /// control order: the kernel of builds without runtime dispatch), the detected one (fused
    /// multiply-adds on AVX2 + FMA) within 1e-14 of Σ_c |w_c|·|P_c|, the size of the terms
    /// summed.
    #[test]
    fn dispatched_and_portable_paths_agree_with_the_plain_sum() {
        for n in 3..=8 {
            for d in 3..=5 {
                let t = GbTable::build(n, d, 5.into(), WeightForm::Squared, true, Some(n % 2 == 0)).unwrap();
                let patch = GbPatch { ribbons: ribbons(&vec![d; n], &vec![d.div_ceil(2); n]), center: DVec3::new(0.1, 0.2, 1.3) };
                let ctrl = t.controls_of(&patch).unwrap();
                let second = t.rows.second.as_deref().unwrap();
                let fast = all_derivs(&t, SimdPath::Detected, &ctrl);
                let portable = all_derivs(&t, SimdPath::Portable, &ctrl);
                let mut turned = ControlSoa::default();
                for s in 0..t.sample_count() {
                    let (m, j) = t.sectors.local_of[s];
                    let (tile, lane) = (j as usize / TILE, j as usize % TILE);
                    t.sectors.turn_controls(&ctrl, m as usize, &mut turned);
                    let pts: Vec<DVec3> = (0..turned.len()).map(|c| DVec3::new(turned.x[c], turned.y[c], turned.z[c])).collect();
                    // Lane 0 of two tiles of sums: the plain sums, turned like the kernel's.
                    let (mut a, mut b) = ([[0.0; TILE]; 9], [[0.0; TILE]; 9]);
                    let mut size = [0.0; 6];
                    for q in 0..6 {
                        let rows = if q < 3 { &t.rows.first } else { second };
                        let w = |c: usize| rows[((tile * t.control_count() + c) * 3 + q % 3) * TILE + lane];
                        let mut sum = DVec3::ZERO;
                        for (c, pc) in pts.iter().enumerate() {
                            sum = DVec3::new(w(c) * pc.x + sum.x, w(c) * pc.y + sum.y, w(c) * pc.z + sum.z);
                            size[q] += w(c).abs() * pc.abs().max_element();
                        }
                        let out = if q < 3 { &mut a } else { &mut b };
                        for (k, v) in sum.to_array().into_iter().enumerate() {
                            out[3 * (q % 3) + k][0] = v;
                        }
                    }
                    let turn = t.sectors.turns[m as usize];
                    if turn != NO_TURN {
                        turn_first(&mut a, turn);
                        turn_second(&mut b, turn);
                    }
                    let plain = derivs(&a, Some(&b))[0];
                    let got = |d: &SurfaceDerivs| [d.p, d.su, d.sv, d.suu, d.suv, d.svv];
                    let (f, p) = (&fast[s].0, &portable[s].0);
                    for (q, ((f, p), want)) in got(f).into_iter().zip(got(p)).zip(got(&plain)).enumerate() {
                        assert_eq!(p.to_array().map(f64::to_bits), want.to_array().map(f64::to_bits), "n {n} d {d} s {s} q {q}");
                        // The turn mixes S_u with S_v (S_uu, S_uv, S_vv): the bound takes the sizes of both.
                        let size = if q == 0 || q == 3 && turn == NO_TURN { size[q] } else if q < 3 { size[1] + size[2] } else { 4.0 * (size[3] + size[4] + size[5]) };
                        assert!((f - p).abs().max_element() <= 1e-14 * size, "n {n} d {d} s {s} q {q}: {f} vs {p}");
                    }
                    // The normals are those of SurfaceDerivs::normal, on either path.
                    assert_eq!((fast[s].1, portable[s].1), (f.normal(), p.normal()));
                }
                // eval_all: the same positions and normals, on either path.
                for (path, all) in [(SimdPath::Detected, &fast), (SimdPath::Portable, &portable)] {
                    let (mut pos, mut nrm) = (Vec::new(), Vec::new());
                    t.eval_all_with(path, &ctrl, &mut pos, &mut nrm);
                    assert_eq!((pos.len(), nrm.len()), (t.sample_count(), t.sample_count()));
                    for s in 0..t.sample_count() {
                        assert_eq!((pos[s], nrm[s]), (all[s].0.p, all[s].1.unwrap_or(DVec3::ZERO)));
                    }
                }
            }
        }
    }

    #[test]
    fn cgb_table_matches_direct_cgb_evaluation() {
        let (degrees, layers) = ([3, 4, 3, 5], [2, 2, 1, 3]);
        let sides: Vec<(usize, usize)> = degrees.iter().copied().zip(layers).collect();
        let t = CgbTable::new(&sides, 5, WeightForm::Squared).unwrap();
        assert_eq!(t.control_count(), 8 + 10 + 4 + 18);
        let patch = CgbPatch { ribbons: ribbons(&degrees, &layers) };
        let ctrl = t.controls_of(&patch).unwrap();
        assert_eq!(t.sector_count(), 1);
        for (s, (d, _)) in all_derivs(&t, SimdPath::Detected, &ctrl).iter().enumerate() {
            assert_derivs(d, &patch.eval_derivs(t.layout.uv[s], WeightForm::Squared));
        }
        let other = CgbPatch { ribbons: ribbons(&[3; 4], &[2; 4]) };
        assert!(matches!(t.controls_of(&other), Err(TableError::CgbMismatch { .. })));
    }
}
