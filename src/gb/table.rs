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

/// Tiled weight rows of a basis that is linear in its control points (see the module doc).
#[derive(Clone, Debug)]
struct Rows {
    /// Number of control points N.
    controls: usize,
    /// Tiles of [`TILE`] samples (the last one padded with zero weights).
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
    /// Rows from `basis(uv, w, w_u, w_v, second)` filling the weights of every control point;
    /// `second` is `Some((w_uu, w_uv, w_vv))` when the second derivatives are wanted.
    fn build(
        layout: &SampleLayout,
        controls: usize,
        want_second: bool,
        mut basis: impl FnMut(DVec2, [&mut [f64]; 6]),
    ) -> Result<Self, TableError> {
        let samples = layout.uv.len();
        let tiles = samples.div_ceil(TILE);
        let len = tiles * TILE * 3 * controls;
        let mut first = vec![0.0; len];
        let mut second = if want_second { vec![0.0; len] } else { Vec::new() };
        let mut buf = vec![0.0; 6 * controls];
        for (s, &uv) in layout.uv.iter().enumerate() {
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
                        return Err(TableError::NonFiniteWeight { sample: s, control: c });
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

    /// Rows of a basis given as jets (value, first and second derivatives).
    fn from_jets(
        layout: &SampleLayout,
        controls: usize,
        want_second: bool,
        mut jets: impl FnMut(DVec2, &mut [Jet2]),
    ) -> Result<Self, TableError> {
        let mut buf = vec![Jet2::ZERO; controls];
        Self::build(layout, controls, want_second, |uv, [w, wu, wv, wuu, wuv, wvv]| {
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

/// A dispatched pass over the tiles `tiles` of a table, for each tile over the control vectors
/// `ctrls` (tile-major: each tile's weights are read from memory once for all of them): the
/// first-derivative sums, the unit normals ([`SurfaceDerivs::normal_lanes`]: zero where
/// undefined) and, with `second`, the sums of the second-derivative rows, handed to
/// `emit(tile, control index, first, normals, second)`.
struct TilePass<'a, F> {
    rows: &'a Rows,
    tiles: std::ops::Range<usize>,
    ctrls: &'a [ControlSoa],
    second: bool,
    emit: F,
}

/// Unit normals of a tile's samples: `[axis][lane]`.
type TileNormals = [[f64; TILE]; 3];

impl<F: FnMut(usize, usize, &TileSums, &TileNormals, Option<&TileSums>)> WithSimd for TilePass<'_, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        let TilePass { rows, tiles, ctrls, second, mut emit } = self;
        let second = if second { rows.second.as_deref() } else { None };
        for t in tiles {
            for (p, ctrl) in ctrls.iter().enumerate() {
                let a = tile_sums(simd, rows.block(&rows.first, t), ctrl);
                let n = SurfaceDerivs::normal_lanes([&a[3], &a[4], &a[5]], [&a[6], &a[7], &a[8]]);
                let b = second.map(|s| tile_sums(simd, rows.block(s, t), ctrl));
                emit(t, p, &a, &n, b.as_ref());
            }
        }
    }
}

/// The frames of a tile's first-derivative sums.
#[inline(always)]
fn frames(a: &TileSums) -> [SampleFrame; TILE] {
    std::array::from_fn(|l| SampleFrame {
        position: DVec3::new(a[0][l], a[1][l], a[2][l]),
        du: DVec3::new(a[3][l], a[4][l], a[5][l]),
        dv: DVec3::new(a[6][l], a[7][l], a[8][l]),
    })
}

/// The derivatives of a tile's sums (second derivatives zero without `b`).
#[inline(always)]
fn derivs(a: &TileSums, b: Option<&TileSums>) -> [SurfaceDerivs; TILE] {
    let b = b.copied().unwrap_or([[0.0; TILE]; 9]);
    std::array::from_fn(|l| SurfaceDerivs {
        p: DVec3::new(a[0][l], a[1][l], a[2][l]),
        su: DVec3::new(a[3][l], a[4][l], a[5][l]),
        sv: DVec3::new(a[6][l], a[7][l], a[8][l]),
        suu: DVec3::new(b[0][l], b[1][l], b[2][l]),
        suv: DVec3::new(b[3][l], b[4][l], b[5][l]),
        svv: DVec3::new(b[6][l], b[7][l], b[8][l]),
    })
}

impl Rows {

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
}

impl WeightTable {
    /// Number of flat control points N.
    pub fn control_count(&self) -> usize {
        self.rows.controls
    }

    /// Memory held by the weights, in bytes.
    pub fn memory_bytes(&self) -> usize {
        self.rows.memory_bytes()
    }

    /// Number of samples.
    pub fn sample_count(&self) -> usize {
        self.layout.uv.len()
    }

    /// Number of tiles of [`TILE`] samples.
    pub fn tile_count(&self) -> usize {
        self.rows.tiles
    }

    /// True when the table holds the second derivatives.
    pub fn has_second_derivatives(&self) -> bool {
        self.rows.second.is_some()
    }

    /// The weight, u- and v-derivative of flat control point `c` at sample `s` (tests only).
    #[cfg(test)]
    fn weight(&self, s: usize, c: usize) -> [f64; 3] {
        self.rows.weight(s, c)
    }

    /// Position and derivatives at the [`TILE`] samples of tile `t` (samples t·TILE..; lanes
    /// past the last sample, and every lane of a tile past the last, are zero). `ctrl` must
    /// come from the table's `controls_of`. For all tiles use [`WeightTable::eval_all`] or
    /// [`WeightTable::for_each_tile`] (one CPU dispatch for the pass instead of one per tile).
    #[inline]
    pub fn eval_tile(&self, t: usize, ctrl: &ControlSoa) -> [SampleFrame; TILE] {
        self.eval_tile_with(SimdPath::Detected, t, ctrl)
    }

    /// [`WeightTable::eval_tile`] on the code path `path`.
    pub fn eval_tile_with(&self, path: SimdPath, t: usize, ctrl: &ControlSoa) -> [SampleFrame; TILE] {
        let mut out = frames(&[[0.0; TILE]; 9]);
        self.pass(path, t..t + 1, std::slice::from_ref(ctrl), false, |_, _, a, _, _| out = frames(a));
        out
    }

    /// Position with first and second derivatives at the samples of tile `t` (second
    /// derivatives zero unless the table has them).
    #[inline]
    pub fn eval_tile_derivs(&self, t: usize, ctrl: &ControlSoa) -> [SurfaceDerivs; TILE] {
        self.eval_tile_derivs_with(SimdPath::Detected, t, ctrl)
    }

    /// [`WeightTable::eval_tile_derivs`] on the code path `path`.
    pub fn eval_tile_derivs_with(&self, path: SimdPath, t: usize, ctrl: &ControlSoa) -> [SurfaceDerivs; TILE] {
        let mut out = derivs(&[[0.0; TILE]; 9], None);
        self.pass(path, t..t + 1, std::slice::from_ref(ctrl), true, |_, _, a, _, b| out = derivs(a, b));
        out
    }

    /// Calls `f(t, derivatives, normals)` for every tile t in order, with what
    /// [`WeightTable::eval_tile_derivs`] gives and the unit normals (bit for bit
    /// [`SurfaceDerivs::normal`] of those derivatives, computed 4 at a time), in one
    /// dispatched pass.
    #[inline]
    pub fn for_each_tile_derivs(&self, ctrl: &ControlSoa, mut f: impl FnMut(usize, &[SurfaceDerivs; TILE], &[Option<DVec3>; TILE])) {
        let tiles = 0..self.rows.tiles;
        self.pass(SimdPath::Detected, tiles, std::slice::from_ref(ctrl), true, |t, _, a, n, b| {
            let normals = std::array::from_fn(|l| {
                let v = DVec3::new(n[0][l], n[1][l], n[2][l]);
                (v != DVec3::ZERO).then_some(v)
            });
            f(t, &derivs(a, b), &normals)
        });
    }

    /// Calls `f(t, frames)` for every tile t in order, with what [`WeightTable::eval_tile`]
    /// gives, in one dispatched pass (as [`WeightTable::for_each_tile_derivs`]).
    #[inline]
    pub fn for_each_tile(&self, ctrl: &ControlSoa, mut f: impl FnMut(usize, &[SampleFrame; TILE])) {
        let tiles = 0..self.rows.tiles;
        self.pass(SimdPath::Detected, tiles, std::slice::from_ref(ctrl), false, |t, _, a, _, _| f(t, &frames(a)));
    }

    #[inline]
    fn pass(
        &self,
        path: SimdPath,
        tiles: std::ops::Range<usize>,
        ctrls: &[ControlSoa],
        second: bool,
        emit: impl FnMut(usize, usize, &TileSums, &TileNormals, Option<&TileSums>),
    ) {
        let tiles = tiles.start.min(self.rows.tiles)..tiles.end.min(self.rows.tiles);
        Rows::run(path, TilePass { rows: &self.rows, tiles, ctrls, second, emit });
    }

    /// Position and derivatives at sample `s` alone. For all samples use
    /// [`WeightTable::eval_all`] (tile-wise, faster).
    pub fn eval_sample(&self, s: usize, ctrl: &ControlSoa) -> SampleFrame {
        self.rows.sample(s, ctrl)
    }

    /// Positions and unit normals at all samples, into `positions` and `normals` (cleared
    /// first; no allocation once they have the capacity).
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

    /// Several patches at once, sample-major: each weight row is read once from memory and
    /// applied to every patch (the way to go when the table is larger than the cache).
    /// `positions[p]`, `normals[p]` receive patch p's samples.
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
        let samples = self.sample_count();
        for (p, n) in positions.iter_mut().zip(normals.iter_mut()) {
            p.clear();
            n.clear();
            p.reserve(samples);
            n.reserve(samples);
        }
        let count = ctrls.len().min(positions.len()).min(normals.len());
        let tiles = 0..self.rows.tiles;
        self.pass(path, tiles, &ctrls[..count], false, |t, p, a, n, _| {
            let (Some(pos), Some(nrm)) = (positions.get_mut(p), normals.get_mut(p)) else { return };
            let lanes = TILE.min(samples - t * TILE);
            pos.extend((0..lanes).map(|l| DVec3::new(a[0][l], a[1][l], a[2][l])));
            nrm.extend((0..lanes).map(|l| DVec3::new(n[0][l], n[1][l], n[2][l])));
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
        Self::build(sides, degree, resolution.into(), form, false)
    }

    /// As [`GbTable::new`], also with the second derivatives of the weights (for
    /// [`WeightTable::eval_tile_derivs`]: curvature). Twice the memory.
    pub fn with_second_derivatives(
        sides: usize,
        degree: usize,
        resolution: impl Into<Sampling>,
        form: WeightForm,
    ) -> Result<Self, TableError> {
        Self::build(sides, degree, resolution.into(), form, true)
    }

    /// The bytes a table of (n, d, r) needs (with or without second derivatives).
    pub fn bytes_needed(sides: usize, degree: usize, resolution: impl Into<Sampling>, second: bool) -> u128 {
        let controls = GbBasis::len_for(sides, degree) as u128;
        rows_bytes(resolution.into().sample_count(sides) as u128, controls, second)
    }

    fn build(
        sides: usize,
        degree: usize,
        sampling: Sampling,
        form: WeightForm,
        second: bool,
    ) -> Result<Self, TableError> {
        let resolution = sampling.resolution;
        let mut ev = GbBasisEvaluator::new(sides, degree)?;
        let bytes = Self::bytes_needed(sides, degree, sampling, second);
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
        let rows = Rows::from_jets(&layout, controls, second, |uv, jets| {
            // `jets` has the evaluator's length, so this cannot fail.
            let _ = ev.eval_into(uv, form, jets);
        })?;
        Ok(GbTable {
            sides,
            degree,
            form,
            table: WeightTable { layout, rows },
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
        rows_bytes(resolution.into().sample_count(sides.len()) as u128, controls, true)
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
        let rows = Rows::from_jets(&layout, ev.len(), true, |uv, jets| {
            // `jets` has the evaluator's length, so this cannot fail.
            let _ = ev.eval_into(uv, form, jets);
        })?;
        Ok(CgbTable {
            sides: sides.to_vec(),
            form,
            table: WeightTable { layout, rows },
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
        assert_eq!(a.memory_bytes(), 41 * 3 * 8 * TILE * tiles);
        let s = GbTable::with_second_derivatives(5, 3, 4, WeightForm::Squared).unwrap();
        assert!(s.has_second_derivatives() && !a.has_second_derivatives());
        assert_eq!(s.memory_bytes(), 2 * a.memory_bytes());
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
        for s in 0..t.sample_count() {
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

    fn assert_derivs(a: &SurfaceDerivs, b: &SurfaceDerivs) {
        for (x, y) in [(a.p, b.p), (a.su, b.su), (a.sv, b.sv), (a.suu, b.suu), (a.suv, b.suv), (a.svv, b.svv)] {
            assert_near!(x, y, 1e-10);
        }
    }

    #[test]
    fn second_derivative_rows_match_direct_gb_evaluation() {
        for form in [WeightForm::Squared, WeightForm::Linear] {
            let t = GbTable::with_second_derivatives(5, 3, 4, form).unwrap();
            let patch = GbPatch { ribbons: ribbons(&[3; 5], &[2; 5]), center: DVec3::new(0.1, 0.2, 1.3) };
            let ctrl = t.controls_of(&patch).unwrap();
            let mut fast = ControlSoa::default();
            fast.fill_gb(&patch);
            assert_eq!(fast, ctrl);
            for s in 0..t.sample_count() {
                let d = t.eval_tile_derivs(s / TILE, &ctrl)[s % TILE];
                assert_derivs(&d, &patch.eval_derivs(t.layout.uv[s], form));
                let f = t.eval_tile(s / TILE, &ctrl)[s % TILE];
                assert_eq!((f.position, f.du, f.dv), (d.p, d.su, d.sv));
            }
        }
        // Without second-derivative rows they read as zero.
        let t = GbTable::new(4, 3, 2, WeightForm::Squared).unwrap();
        let patch = GbPatch { ribbons: ribbons(&[3; 4], &[2; 4]), center: DVec3::Z };
        let d = t.eval_tile_derivs(0, &t.controls_of(&patch).unwrap())[0];
        assert_eq!((d.suu, d.suv, d.svv), (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO));
    }

    /// Both code paths against the plain sum Σ_c w_c·P_c over the table's weights: the portable
    /// path bit for bit (multiply, then add, in control order: the kernel of builds without
    /// runtime dispatch), the detected one (fused multiply-adds on AVX2 + FMA) within 1e-14 of
    /// Σ_c |w_c|·|P_c|, the size of the terms summed.
    #[test]
    fn dispatched_and_portable_paths_agree_with_the_plain_sum() {
        for n in 3..=8 {
            for d in 3..=5 {
                let t = GbTable::with_second_derivatives(n, d, 5, WeightForm::Squared).unwrap();
                let patch = GbPatch { ribbons: ribbons(&vec![d; n], &vec![d.div_ceil(2); n]), center: DVec3::new(0.1, 0.2, 1.3) };
                let ctrl = t.controls_of(&patch).unwrap();
                let pts: Vec<DVec3> = (0..ctrl.len()).map(|c| DVec3::new(ctrl.x[c], ctrl.y[c], ctrl.z[c])).collect();
                let second = t.rows.second.as_deref().unwrap();
                for s in 0..t.sample_count() {
                    let (tile, lane) = (s / TILE, s % TILE);
                    let fast = t.eval_tile_derivs_with(SimdPath::Detected, tile, &ctrl)[lane];
                    let portable = t.eval_tile_derivs_with(SimdPath::Portable, tile, &ctrl)[lane];
                    let got = |d: &SurfaceDerivs| [d.p, d.su, d.sv, d.suu, d.suv, d.svv];
                    for (q, (f, p)) in got(&fast).into_iter().zip(got(&portable)).enumerate() {
                        let rows = if q < 3 { &t.rows.first } else { second };
                        let w = |c: usize| rows[((tile * t.control_count() + c) * 3 + q % 3) * TILE + lane];
                        let (mut sum, mut size) = (DVec3::ZERO, 0.0);
                        for (c, pc) in pts.iter().enumerate() {
                            sum = DVec3::new(w(c) * pc.x + sum.x, w(c) * pc.y + sum.y, w(c) * pc.z + sum.z);
                            size += w(c).abs() * pc.abs().max_element();
                        }
                        assert_eq!(p.to_array().map(f64::to_bits), sum.to_array().map(f64::to_bits), "n {n} d {d} s {s} q {q}");
                        assert!((f - p).abs().max_element() <= 1e-14 * size, "n {n} d {d} s {s} q {q}: {f} vs {p}");
                    }
                    let n_fast = t.eval_tile_with(SimdPath::Detected, tile, &ctrl)[lane];
                    assert_eq!((n_fast.position, n_fast.du, n_fast.dv), (fast.p, fast.su, fast.sv));
                }
                // eval_all: the normals are those of SurfaceDerivs::normal, on either path.
                for path in [SimdPath::Detected, SimdPath::Portable] {
                    let (mut pos, mut nrm) = (Vec::new(), Vec::new());
                    t.eval_all_with(path, &ctrl, &mut pos, &mut nrm);
                    assert_eq!((pos.len(), nrm.len()), (t.sample_count(), t.sample_count()));
                    for s in 0..t.sample_count() {
                        let d = t.eval_tile_derivs_with(path, s / TILE, &ctrl)[s % TILE];
                        assert_eq!((pos[s], nrm[s]), (d.p, d.normal().unwrap_or(DVec3::ZERO)));
                    }
                }
                // Past the last tile: zeros, no panic.
                let past = t.eval_tile_derivs(t.tile_count(), &ctrl);
                assert!(past.iter().all(|d| d.p == DVec3::ZERO && d.svv == DVec3::ZERO));
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
        for s in 0..t.sample_count() {
            let d = t.eval_tile_derivs(s / TILE, &ctrl)[s % TILE];
            assert_derivs(&d, &patch.eval_derivs(t.layout.uv[s], WeightForm::Squared));
        }
        let other = CgbPatch { ribbons: ribbons(&[3; 4], &[2; 4]) };
        assert!(matches!(t.controls_of(&other), Err(TableError::CgbMismatch { .. })));
    }
}
