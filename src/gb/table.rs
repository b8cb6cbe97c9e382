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
//! horizontal sums, no shuffles, no allocation.
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
use std::ops::Deref;

/// Samples per tile: the SIMD lanes of the kernel (`wide::f64x2` / `f64x4`). 2 × f64 fills an
/// SSE2 register (the 9 accumulators then fit the 16 registers of x86-64); when the build
/// enables AVX (`-C target-cpu=…`), 4 × f64 fills a YMM register.
pub const TILE: usize = if cfg!(target_feature = "avx") { 4 } else { 2 };

/// One f64 per sample of a tile (safe SIMD from the `wide` crate).
#[cfg(target_feature = "avx")]
type Lanes = wide::f64x4;
#[cfg(not(target_feature = "avx"))]
type Lanes = wide::f64x2;

/// The first [`TILE`] values of `s` as lanes.
#[inline(always)]
fn load(s: &[f64]) -> Lanes {
    #[cfg(target_feature = "avx")]
    return Lanes::new([s[0], s[1], s[2], s[3]]);
    #[cfg(not(target_feature = "avx"))]
    return Lanes::new([s[0], s[1]]);
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
        let ribbons = patch.ribbons.iter().flat_map(|r| r.rows.iter().flatten().copied());
        self.fill(std::iter::once(patch.center).chain(ribbons));
    }

    /// The flat-ordered control points of a CGB patch: side i, row k, column j.
    pub fn fill_cgb(&mut self, patch: &CgbPatch) {
        self.fill(patch.ribbons.iter().flat_map(|r| r.rows.iter().flatten().copied()));
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

    /// [`Rows::kernel`] as a call of its own, so that its 9 accumulators get the register file
    /// to themselves (inlined twice into [`Rows::tile_derivs`] the compiler kept one
    /// accumulator on the stack: about 20 % slower).
    #[inline(never)]
    fn kernel_call(block: &[f64], ctrl: &ControlSoa) -> [[f64; TILE]; 9] {
        Self::kernel(block, ctrl)
    }

    /// Σ_c row_q(c) · P_c for q = 0, 1, 2 over the tile's lanes: the 9 sums (x, y, z of each q).
    #[inline(always)]
    fn kernel(block: &[f64], ctrl: &ControlSoa) -> [[f64; TILE]; 9] {
        // 9 accumulators (x, y, z of the three rows), each with the tile's samples as lanes.
        let mut acc = [Lanes::ZERO; 9];
        let coords = ctrl.x.iter().zip(ctrl.y.iter()).zip(ctrl.z.iter());
        for (wq, ((&x, &y), &z)) in block.chunks_exact(3 * TILE).zip(coords) {
            // One weight row live at a time (9 accumulators + 3 coordinates + 1 row + 1
            // product fit the 16 SSE registers without spilling).
            let (x, y, z) = (Lanes::splat(x), Lanes::splat(y), Lanes::splat(z));
            for q in 0..3 {
                let w = load(&wq[q * TILE..]);
                acc[3 * q] = w.mul_add(x, acc[3 * q]);
                acc[3 * q + 1] = w.mul_add(y, acc[3 * q + 1]);
                acc[3 * q + 2] = w.mul_add(z, acc[3 * q + 2]);
            }
        }
        acc.map(|v| v.to_array())
    }

    #[inline]
    fn block<'a>(&self, rows: &'a [f64], t: usize) -> &'a [f64] {
        let len = self.controls * 3 * TILE;
        &rows[t * len..(t + 1) * len]
    }

    #[inline]
    fn tile(&self, t: usize, ctrl: &ControlSoa) -> [SampleFrame; TILE] {
        let a = Self::kernel(self.block(&self.first, t), ctrl);
        std::array::from_fn(|l| SampleFrame {
            position: DVec3::new(a[0][l], a[1][l], a[2][l]),
            du: DVec3::new(a[3][l], a[4][l], a[5][l]),
            dv: DVec3::new(a[6][l], a[7][l], a[8][l]),
        })
    }

    #[inline]
    fn tile_derivs(&self, t: usize, ctrl: &ControlSoa) -> [SurfaceDerivs; TILE] {
        let a = Self::kernel_call(self.block(&self.first, t), ctrl);
        let b = match &self.second {
            Some(second) => Self::kernel_call(self.block(second, t), ctrl),
            None => [[0.0; TILE]; 9],
        };
        std::array::from_fn(|l| SurfaceDerivs {
            p: DVec3::new(a[0][l], a[1][l], a[2][l]),
            su: DVec3::new(a[3][l], a[4][l], a[5][l]),
            sv: DVec3::new(a[6][l], a[7][l], a[8][l]),
            suu: DVec3::new(b[0][l], b[1][l], b[2][l]),
            suv: DVec3::new(b[3][l], b[4][l], b[5][l]),
            svv: DVec3::new(b[6][l], b[7][l], b[8][l]),
        })
    }

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
    /// past the last sample are zero). `ctrl` must come from the table's `controls_of`.
    #[inline]
    pub fn eval_tile(&self, t: usize, ctrl: &ControlSoa) -> [SampleFrame; TILE] {
        self.rows.tile(t, ctrl)
    }

    /// Position with first and second derivatives at the samples of tile `t` (second
    /// derivatives zero unless the table has them).
    #[inline]
    pub fn eval_tile_derivs(&self, t: usize, ctrl: &ControlSoa) -> [SurfaceDerivs; TILE] {
        self.rows.tile_derivs(t, ctrl)
    }

    /// Position and derivatives at sample `s` alone. For all samples use
    /// [`WeightTable::eval_all`] (tile-wise, faster).
    pub fn eval_sample(&self, s: usize, ctrl: &ControlSoa) -> SampleFrame {
        self.rows.sample(s, ctrl)
    }

    /// Positions and unit normals at all samples, into `positions` and `normals` (cleared
    /// first; no allocation once they have the capacity).
    pub fn eval_all(
        &self,
        ctrl: &ControlSoa,
        positions: &mut Vec<DVec3>,
        normals: &mut Vec<DVec3>,
    ) {
        positions.clear();
        normals.clear();
        positions.reserve(self.sample_count());
        normals.reserve(self.sample_count());
        let samples = self.sample_count();
        for t in 0..self.rows.tiles {
            let frames = self.eval_tile(t, ctrl);
            for f in frames.iter().take(samples - t * TILE) {
                positions.push(f.position);
                normals.push(f.normal().unwrap_or(DVec3::ZERO));
            }
        }
    }

    /// Several patches at once, sample-major: each weight row is read once from memory and
    /// applied to every patch (the way to go when the table is larger than the cache).
    /// `positions[p]`, `normals[p]` receive patch p's samples.
    pub fn eval_batch(
        &self,
        ctrls: &[ControlSoa],
        positions: &mut [Vec<DVec3>],
        normals: &mut [Vec<DVec3>],
    ) {
        for (p, n) in positions.iter_mut().zip(normals.iter_mut()) {
            p.clear();
            n.clear();
            p.reserve(self.sample_count());
            n.reserve(self.sample_count());
        }
        let samples = self.sample_count();
        for t in 0..self.rows.tiles {
            for ((c, p), n) in ctrls
                .iter()
                .zip(positions.iter_mut())
                .zip(normals.iter_mut())
            {
                let frames = self.eval_tile(t, c);
                for f in frames.iter().take(samples - t * TILE) {
                    p.push(f.position);
                    n.push(f.normal().unwrap_or(DVec3::ZERO));
                }
            }
        }
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
        let found: Vec<(usize, usize)> = patch.ribbons.iter().map(|r| (r.degree, r.rows.len())).collect();
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
            .map(|(i, (&d, &l))| crate::gb::Ribbon {
                degree: d,
                rows: (0..l)
                    .map(|k| (0..=d).map(|j| DVec3::new(i as f64 + next(), j as f64 + next(), k as f64 + next())).collect())
                    .collect(),
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
