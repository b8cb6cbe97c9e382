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
//! Tables are shared between patches through [`GbTable::cached`].

use super::connected::layers;
use super::derivs::SurfaceDerivs;
use super::error::GbError;
use super::patch::{GbPatch, WeightForm};
use super::weights::GbBasisEvaluator;
use super::Jet2;
use crate::mesh::{MeshSink, TriMesh};
use crate::tessellate::patch::{emit_patch, LayoutError, SampleLayout};
use glam::{DVec2, DVec3};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

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

/// Largest weight table built (bytes): 1 GiB.
pub const MAX_TABLE_BYTES: u128 = 1 << 30;

/// Number of flat control points of an n-sided degree-d GB patch: 1 + n·l·(d+1).
pub fn flat_control_count(n: usize, degree: usize) -> usize {
    1 + n * layers(degree) * (degree + 1)
}

/// Key of the table cache.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TableKey {
    pub sides: usize,
    pub degree: usize,
    pub resolution: usize,
    pub form: WeightForm,
}

/// The control points of one patch as padded SoA coordinate arrays, in flat basis order.
#[derive(Clone, Debug, PartialEq)]
pub struct ControlSoa {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
}

impl ControlSoa {
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

/// Dense weight table of one (n, d, r, weight form); see the module doc.
#[derive(Clone, Debug)]
pub struct GbTable {
    /// Number of sides n.
    pub sides: usize,
    /// Degree d.
    pub degree: usize,
    /// Weight form of the correction weights μ.
    pub form: WeightForm,
    /// Samples and triangles.
    pub layout: SampleLayout,
    /// Number of flat control points N.
    controls: usize,
    /// Tiles of [`TILE`] samples (the last one padded with zero weights).
    tiles: usize,
    /// `data[((tile·N + c)·3 + q)·TILE + lane]`, q = 0, 1, 2 for w, ∂_u w, ∂_v w.
    data: Vec<f64>,
}

impl GbTable {
    /// The table of the GB basis ([`GbBasisEvaluator`]) of n sides, degree d and weight form
    /// `form` at the samples of [`SampleLayout::for_domain`] at resolution r.
    pub fn new(
        sides: usize,
        degree: usize,
        resolution: usize,
        form: WeightForm,
    ) -> Result<Self, TableError> {
        let mut ev = GbBasisEvaluator::new(sides, degree)?;
        let controls = flat_control_count(sides, degree) as u128;
        let samples = 1 + (sides as u128) * (resolution as u128) * (resolution as u128 + 1) / 2;
        let bytes = samples.div_ceil(TILE as u128) * TILE as u128 * 3 * controls * 8;
        if bytes > MAX_TABLE_BYTES {
            return Err(TableError::TooLarge {
                n: sides,
                d: degree,
                r: resolution,
                bytes,
            });
        }
        let layout = SampleLayout::for_domain(ev.domain(), resolution)?;
        let mut jets = vec![Jet2::ZERO; ev.len()];
        Self::from_basis(sides, degree, form, layout, |uv, w, wu, wv| {
            // `jets` has the evaluator's length, so this cannot fail.
            if ev.eval_into(uv, form, &mut jets).is_ok() {
                for (m, j) in jets.iter().enumerate() {
                    (w[m], wu[m], wv[m]) = (j.val, j.du, j.dv);
                }
            }
        })
    }

    /// The shared table of (n, d, r, form) from the process-wide cache (built on first use).
    pub fn cached(
        sides: usize,
        degree: usize,
        resolution: usize,
        form: WeightForm,
    ) -> Result<Arc<GbTable>, TableError> {
        let key = TableKey {
            sides,
            degree,
            resolution,
            form,
        };
        Self::cached_with(key, || GbTable::new(sides, degree, resolution, form))
    }

    /// Builds a table from a basis function: `basis(uv, w, w_u, w_v)` fills the weights and
    /// their u, v derivatives of the `controls` flat control points (slices of that length).
    pub fn from_basis(
        sides: usize,
        degree: usize,
        form: WeightForm,
        layout: SampleLayout,
        mut basis: impl FnMut(DVec2, &mut [f64], &mut [f64], &mut [f64]),
    ) -> Result<Self, TableError> {
        let controls = flat_control_count(sides, degree);
        let samples = layout.uv.len();
        let tiles = samples.div_ceil(TILE);
        let mut data = vec![0.0; tiles * TILE * 3 * controls];
        let (mut w, mut wu, mut wv) = (
            vec![0.0; controls],
            vec![0.0; controls],
            vec![0.0; controls],
        );
        for (s, &uv) in layout.uv.iter().enumerate() {
            basis(uv, &mut w, &mut wu, &mut wv);
            let (t, lane) = (s / TILE, s % TILE);
            for c in 0..controls {
                let at = (t * controls + c) * 3 * TILE + lane;
                for (q, v) in [w[c], wu[c], wv[c]].into_iter().enumerate() {
                    if !v.is_finite() {
                        return Err(TableError::NonFiniteWeight {
                            sample: s,
                            control: c,
                        });
                    }
                    data[at + q * TILE] = v;
                }
            }
        }
        Ok(GbTable {
            sides,
            degree,
            form,
            layout,
            controls,
            tiles,
            data,
        })
    }

    /// Number of flat control points N.
    pub fn control_count(&self) -> usize {
        self.controls
    }

    /// Memory held by the weights, in bytes.
    pub fn memory_bytes(&self) -> usize {
        self.data.len() * std::mem::size_of::<f64>()
    }

    /// Number of samples.
    pub fn sample_count(&self) -> usize {
        self.layout.uv.len()
    }

    /// The weight, u- and v-derivative of flat control point `c` at sample `s`.
    pub fn weight(&self, s: usize, c: usize) -> [f64; 3] {
        let at = ((s / TILE) * self.controls + c) * 3 * TILE + s % TILE;
        [
            self.data[at],
            self.data[at + TILE],
            self.data[at + 2 * TILE],
        ]
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

    /// Position and derivatives at the [`TILE`] samples of tile `t` (samples t·TILE..; lanes
    /// past the last sample are zero). `ctrl` must come from [`GbTable::controls_of`].
    #[inline]
    pub fn eval_tile(&self, t: usize, ctrl: &ControlSoa) -> [SampleFrame; TILE] {
        let len = self.controls * 3 * TILE;
        let block = &self.data[t * len..(t + 1) * len];
        // 9 accumulators (x, y, z of S, S_u, S_v), each with the tile's samples as lanes.
        let mut acc = [Lanes::ZERO; 9];
        let coords = ctrl.x.iter().zip(ctrl.y.iter()).zip(ctrl.z.iter());
        for (wq, ((&x, &y), &z)) in block.chunks_exact(3 * TILE).zip(coords) {
            let (w, wu, wv) = (load(wq), load(&wq[TILE..]), load(&wq[2 * TILE..]));
            let (x, y, z) = (Lanes::splat(x), Lanes::splat(y), Lanes::splat(z));
            acc[0] = w.mul_add(x, acc[0]);
            acc[1] = w.mul_add(y, acc[1]);
            acc[2] = w.mul_add(z, acc[2]);
            acc[3] = wu.mul_add(x, acc[3]);
            acc[4] = wu.mul_add(y, acc[4]);
            acc[5] = wu.mul_add(z, acc[5]);
            acc[6] = wv.mul_add(x, acc[6]);
            acc[7] = wv.mul_add(y, acc[7]);
            acc[8] = wv.mul_add(z, acc[8]);
        }
        let a = acc.map(|v| v.to_array());
        std::array::from_fn(|l| SampleFrame {
            position: DVec3::new(a[0][l], a[1][l], a[2][l]),
            du: DVec3::new(a[3][l], a[4][l], a[5][l]),
            dv: DVec3::new(a[6][l], a[7][l], a[8][l]),
        })
    }

    /// Position and derivatives at sample `s` alone. `ctrl` must come from
    /// [`GbTable::controls_of`]. For all samples use [`GbTable::eval_all`] (tile-wise, faster).
    pub fn eval_sample(&self, s: usize, ctrl: &ControlSoa) -> SampleFrame {
        let len = self.controls * 3 * TILE;
        let (t, lane) = (s / TILE, s % TILE);
        let block = &self.data[t * len..(t + 1) * len];
        let mut acc = [DVec3::ZERO; 3];
        let coords = ctrl.x.iter().zip(ctrl.y.iter()).zip(ctrl.z.iter());
        for (wq, ((&x, &y), &z)) in block.chunks_exact(3 * TILE).zip(coords) {
            let p = DVec3::new(x, y, z);
            for (q, a) in acc.iter_mut().enumerate() {
                *a += wq[q * TILE + lane] * p;
            }
        }
        SampleFrame {
            position: acc[0],
            du: acc[1],
            dv: acc[2],
        }
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
        for t in 0..self.tiles {
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
        for t in 0..self.tiles {
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

    /// Emits a patch through `sink` (see [`emit_patch`]); `existing` names sink vertices to
    /// reuse (shared boundary samples). Returns the sink index of every sample.
    pub fn emit<S: MeshSink + ?Sized>(
        &self,
        patch: &GbPatch,
        existing: impl FnMut(usize) -> Option<u32>,
        sink: &mut S,
    ) -> Result<Vec<u32>, TableError> {
        let ctrl = self.controls_of(patch)?;
        Ok(emit_patch(
            &self.layout,
            |s, _| {
                let f = self.eval_sample(s, &ctrl);
                (f.position, f.normal().unwrap_or(DVec3::ZERO))
            },
            existing,
            sink,
        ))
    }

    /// One patch as a triangle mesh with normals (sample i is vertex i).
    pub fn tessellate(&self, patch: &GbPatch) -> Result<TriMesh, TableError> {
        let ctrl = self.controls_of(patch)?;
        let mut mesh = TriMesh::default();
        self.eval_all(&ctrl, &mut mesh.positions, &mut mesh.normals);
        mesh.triangles = self.layout.triangles.clone();
        Ok(mesh)
    }
}

type Cache = Mutex<HashMap<TableKey, Arc<GbTable>>>;

fn cache() -> &'static Cache {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Drops all cached tables (tables still in use stay alive through their `Arc`s).
pub fn clear_table_cache() {
    if let Ok(mut c) = cache().lock() {
        c.clear();
    }
}

impl GbTable {
    /// The shared table for `key`, built on first use with `build` (held in a process-wide
    /// cache until [`clear_table_cache`]).
    pub fn cached_with(
        key: TableKey,
        build: impl FnOnce() -> Result<GbTable, TableError>,
    ) -> Result<Arc<GbTable>, TableError> {
        if let Ok(c) = cache().lock() {
            if let Some(t) = c.get(&key) {
                return Ok(Arc::clone(t));
            }
        }
        // Built outside the lock: two threads may build the same table once each.
        let table = Arc::new(build()?);
        if let Ok(mut c) = cache().lock() {
            return Ok(Arc::clone(c.entry(key).or_insert(table)));
        }
        Ok(table)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cache_shares_tables_per_key() {
        let a = GbTable::cached(5, 3, 4, WeightForm::Squared).unwrap();
        let b = GbTable::cached(5, 3, 4, WeightForm::Squared).unwrap();
        let c = GbTable::cached(5, 3, 4, WeightForm::Linear).unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        assert!(!Arc::ptr_eq(&a, &c));
        assert_eq!(a.control_count(), 1 + 5 * 2 * 4);
        let tiles = SampleLayout::sample_count(5, 4).div_ceil(TILE);
        assert_eq!(a.memory_bytes(), 41 * 3 * 8 * TILE * tiles);
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
}
