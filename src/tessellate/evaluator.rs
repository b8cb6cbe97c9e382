//! Patch evaluators for whole-surface tessellation, and the weight tables they own.
//!
//! [`GbSurfaceEvaluator`] evaluates the GB and CGB patches of one surface through the weight
//! tables of [`crate::gb::table`], one per distinct (kind, n, degrees, r, weight form). The
//! tables belong to the evaluator and are dropped with it (with the conversion). A caller that
//! converts repeatedly (a live preview) may keep a [`TableCache`] of its own: a bounded,
//! least-recently-used store of tables shared between conversions.

use crate::construct::{Patch, Surface};
use crate::gb::table::{CgbTable, ControlSoa, GbTable, TableError};
use crate::gb::{Domain, SampleLayout, Sampling, SurfaceDerivs, WeightForm};
use super::TessellateError;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// One evaluated sample: position, unit normal (zero when undefined, e.g. at a degenerate corner;
/// the welded mesh then falls back to the average of the other patches' normals or, failing that,
/// the area-weighted triangle normal), mean and Gaussian curvature (0 where undefined), and the
/// Jacobian |S_u × S_v| (0 where the normal is undefined; the fold pass's clear test reads it,
/// [`super::fold::ClearTest`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfacePoint {
    pub position: DVec3,
    pub normal: DVec3,
    pub mean_curvature: f64,
    pub gaussian_curvature: f64,
    pub jacobian: f64,
}

/// Evaluates all samples of one patch. Implementations must be pure (they run in parallel over
/// patches) and must fill `out` with one point per `layout.uv` entry.
pub trait PatchEvaluator: Sync {
    /// The domain polygon (counter-clockwise, vertex i ends side i) in which this evaluator reads
    /// the parameters of an n-sided patch.
    fn domain(&self, n: usize) -> Vec<DVec2> {
        SampleLayout::regular_polygon(n)
    }
    /// The weight form the patches are evaluated with (the fold pass's dense grids use it too).
    fn weight_form(&self) -> WeightForm;
    /// Evaluates patch `index` of `surface` at every sample of `layout` into `out`, replacing its
    /// contents (empty when the patch cannot be evaluated).
    fn evaluate(&self, surface: &Surface, index: usize, layout: &SampleLayout, out: &mut Vec<SurfacePoint>);
}

/// Which table a patch uses: GB (n, d) or CGB (per-side degree and layer count).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum Kind {
    Gb(usize, usize),
    Cgb(Vec<(usize, usize)>),
}

fn kind_of(p: &Patch) -> Kind {
    match p {
        Patch::Gb(g) => Kind::Gb(g.ribbons.len(), g.ribbons.first().map_or(0, |r| r.degree)),
        Patch::Cgb(c) => Kind::Cgb(c.ribbons.iter().map(|r| (r.degree, r.layers())).collect()),
    }
}

use crate::limits::MAX_TESSELLATION_TABLE_BYTES as TABLE_BYTES;

/// Key of a [`TableCache`]: the patch kind, the resolution and the weight form (the tables
/// always hold second derivatives).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct TableKey {
    kind: Kind,
    resolution: Sampling,
    form: WeightForm,
}

/// A built table of either kind.
#[derive(Clone, Debug)]
enum Table {
    Gb(Arc<GbTable>),
    Cgb(Arc<CgbTable>),
}

impl Table {
    fn memory_bytes(&self) -> usize {
        match self {
            Table::Gb(t) => t.memory_bytes(),
            Table::Cgb(t) => t.memory_bytes(),
        }
    }
}

struct CacheEntry {
    key: TableKey,
    table: Table,
    bytes: u128,
    last_used: u64,
}

#[derive(Default)]
struct CacheState {
    entries: Vec<CacheEntry>,
    bytes: u128,
    clock: u64,
}

/// Weight tables kept between conversions, owned by the caller: at most `max_bytes` of tables,
/// the least recently used dropped first; a table larger than the bound is built for its
/// conversion only. Tables still in use by an evaluator stay alive through their `Arc`s.
pub struct TableCache {
    max_bytes: u128,
    state: Mutex<CacheState>,
}

impl Default for TableCache {
    /// A cache of [`TableCache::DEFAULT_BYTES`].
    fn default() -> Self {
        TableCache::new(Self::DEFAULT_BYTES)
    }
}

impl TableCache {
    /// The default bound: [`crate::limits::DEFAULT_TABLE_CACHE_BYTES`].
    pub const DEFAULT_BYTES: u128 = crate::limits::DEFAULT_TABLE_CACHE_BYTES;

    /// An empty cache holding at most `max_bytes` of tables.
    pub fn new(max_bytes: u128) -> Self {
        TableCache { max_bytes, state: Mutex::new(CacheState::default()) }
    }

    /// Memory held by the cached tables, in bytes.
    pub fn memory_bytes(&self) -> u128 {
        self.state.lock().map_or(0, |s| s.bytes)
    }

    /// Number of cached tables.
    pub fn len(&self) -> usize {
        self.state.lock().map_or(0, |s| s.entries.len())
    }

    /// True without cached tables.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Drops all cached tables.
    pub fn clear(&self) {
        if let Ok(mut s) = self.state.lock() {
            s.entries.clear();
            s.bytes = 0;
        }
    }

    /// The table for `key`, from the cache or built with `build` (built outside the lock: two
    /// threads may build the same table once each).
    fn get_or_build(&self, key: TableKey, build: impl FnOnce() -> Result<Table, TableError>) -> Result<Table, TableError> {
        if let Ok(mut s) = self.state.lock() {
            s.clock += 1;
            let now = s.clock;
            if let Some(e) = s.entries.iter_mut().find(|e| e.key == key) {
                e.last_used = now;
                return Ok(e.table.clone());
            }
        }
        let table = build()?;
        let bytes = table.memory_bytes() as u128;
        if bytes > self.max_bytes {
            return Ok(table);
        }
        if let Ok(mut s) = self.state.lock() {
            if let Some(e) = s.entries.iter().find(|e| e.key == key) {
                return Ok(e.table.clone());
            }
            while s.bytes + bytes > self.max_bytes {
                let Some(oldest) = s.entries.iter().enumerate().min_by_key(|(_, e)| e.last_used).map(|(i, _)| i) else { break };
                let e = s.entries.swap_remove(oldest);
                s.bytes -= e.bytes;
            }
            s.clock += 1;
            let last_used = s.clock;
            s.bytes += bytes;
            s.entries.push(CacheEntry { key, table: table.clone(), bytes, last_used });
        }
        Ok(table)
    }
}

/// How the patches of one kind are evaluated.
enum Evaluation {
    /// A weight table ([`GbTable`] with second derivatives, or [`CgbTable`]).
    Table(Table),
    /// No table (it would be too large): the basis is evaluated at every sample.
    Direct,
}

/// The evaluator of GB and CGB patches used by the conversion: the weight tables of
/// [`crate::gb::table`] ([`GbTable`] with second derivatives for GB patches, [`CgbTable`] for
/// CGB patches), one per (kind, n, degrees, r, weight form), owned by the evaluator; every
/// patch is then a tile-wise SIMD weighted sum over its control points (seed 000 eq. 2.24 for
/// GB, eq. 3.8 for CGB, with the weight form of [`crate::gb::WeightForm`]). The domain is
/// [`crate::gb::Domain::regular`] (for n = 4 the square of docs/math.md#domain).
pub struct GbSurfaceEvaluator {
    evaluations: Vec<Evaluation>,
    /// Per patch: its entry of `evaluations`.
    which: Vec<u32>,
    form: WeightForm,
}

fn gb_domain(n: usize) -> Vec<DVec2> {
    match Domain::regular(n) {
        Ok(d) => d.vertices().to_vec(),
        Err(_) => SampleLayout::regular_polygon(n),
    }
}

fn table_error(patch: usize, e: TableError) -> TessellateError {
    match e {
        TableError::Layout(source) => TessellateError::Layout { patch, source },
        TableError::Patch(source) => TessellateError::InvalidPatch { patch, source },
        _ => TessellateError::Evaluation { patch, sample: 0 },
    }
}

/// The sample record of the surface derivatives: unit normal (zero where undefined) and mean
/// and Gaussian curvature ([`SurfaceDerivs::mean_and_gaussian`]; 0 where undefined), the
/// normal computed once.
#[inline]
fn surface_point(d: &SurfaceDerivs) -> SurfacePoint {
    surface_point_with(d, d.normal())
}

/// [`surface_point`] with the normal `d.normal()` already computed.
#[inline]
fn surface_point_with(d: &SurfaceDerivs, normal: Option<DVec3>) -> SurfacePoint {
    let Some(n) = normal else {
        return SurfacePoint { position: d.p, ..Default::default() };
    };
    let (h, k) = d.mean_and_gaussian(n).unwrap_or((0.0, 0.0));
    let jacobian = d.su.cross(d.sv).length();
    SurfacePoint { position: d.p, normal: n, mean_curvature: h, gaussian_curvature: k, jacobian }
}

thread_local! {
    /// Per worker thread: the control vector of the patch being evaluated.
    static CONTROLS: RefCell<ControlSoa> = RefCell::new(ControlSoa::default());
}

impl GbSurfaceEvaluator {
    /// Validates every patch and builds the weight tables for resolution `r`; they are dropped
    /// with the evaluator.
    pub fn new(surface: &Surface, r: impl Into<Sampling>, form: WeightForm) -> Result<Self, TessellateError> {
        Self::build(surface, r.into(), form, None)
    }

    /// As [`GbSurfaceEvaluator::new`], taking the tables from `cache` (and adding the ones it
    /// builds).
    pub fn with_cache(surface: &Surface, r: impl Into<Sampling>, form: WeightForm, cache: &TableCache) -> Result<Self, TessellateError> {
        Self::build(surface, r.into(), form, Some(cache))
    }

    fn build(surface: &Surface, r: Sampling, form: WeightForm, cache: Option<&TableCache>) -> Result<Self, TessellateError> {
        let mut which = Vec::with_capacity(surface.patches.len());
        let mut distinct: HashMap<Kind, u32> = HashMap::new();
        let mut firsts: Vec<(Kind, usize)> = Vec::new();
        // Validation in parallel; the first invalid patch (smallest index) is reported.
        let validate = |p: &Patch| match p {
            Patch::Gb(g) => g.validate(),
            Patch::Cgb(c) => c.validate(),
        };
        if let Some((i, p)) = surface.patches.par_iter().enumerate().find_first(|(_, p)| validate(p).is_err()) {
            validate(p).map_err(|source| TessellateError::InvalidPatch { patch: i, source })?;
        }
        let kinds: Vec<Kind> = surface.patches.par_iter().map(kind_of).collect();
        for (i, k) in kinds.into_iter().enumerate() {
            let id = match distinct.get(&k) {
                Some(&id) => id,
                None => {
                    let id = firsts.len() as u32;
                    distinct.insert(k.clone(), id);
                    firsts.push((k, i));
                    id
                }
            };
            which.push(id);
        }
        let evaluations: Result<Vec<Evaluation>, TessellateError> = firsts
            .into_par_iter()
            .map(|(kind, first)| {
                SampleLayout::new(&gb_domain(surface.patches[first].sides()), r)
                    .map_err(|source| TessellateError::Layout { patch: first, source })?;
                let bytes = match &kind {
                    Kind::Gb(n, d) => GbTable::bytes_needed(*n, *d, r, true),
                    Kind::Cgb(sides) => CgbTable::bytes_needed(sides, r),
                };
                if bytes > TABLE_BYTES {
                    return Ok(Evaluation::Direct);
                }
                let build = || -> Result<Table, TableError> {
                    Ok(match &kind {
                        Kind::Gb(n, d) => Table::Gb(Arc::new(GbTable::with_second_derivatives(*n, *d, r, form)?)),
                        Kind::Cgb(sides) => Table::Cgb(Arc::new(CgbTable::new(sides, r, form)?)),
                    })
                };
                let table = match cache {
                    Some(c) => c.get_or_build(TableKey { kind: kind.clone(), resolution: r, form }, build),
                    None => build(),
                };
                Ok(Evaluation::Table(table.map_err(|e| table_error(first, e))?))
            })
            .collect();
        Ok(GbSurfaceEvaluator { evaluations: evaluations?, which, form })
    }
}

impl PatchEvaluator for GbSurfaceEvaluator {
    fn domain(&self, n: usize) -> Vec<DVec2> {
        gb_domain(n)
    }

    fn weight_form(&self) -> WeightForm {
        self.form
    }

    fn evaluate(&self, surface: &Surface, index: usize, layout: &SampleLayout, out: &mut Vec<SurfacePoint>) {
        let (Some(&id), Some(patch)) = (self.which.get(index), surface.patches.get(index)) else { return out.clear() };
        let Some(evaluation) = self.evaluations.get(id as usize) else { return out.clear() };
        let samples = layout.uv.len();
        let filled = CONTROLS.with(|cell| {
            let mut ctrl = cell.borrow_mut();
            let table = match (evaluation, patch) {
                (Evaluation::Table(Table::Gb(t)), Patch::Gb(g)) => {
                    ctrl.fill_gb(g);
                    &***t
                }
                (Evaluation::Table(Table::Cgb(t)), Patch::Cgb(c)) => {
                    ctrl.fill_cgb(c);
                    &***t
                }
                (Evaluation::Direct, Patch::Gb(g)) => {
                    let Ok(mut ev) = g.evaluator() else { return false };
                    out.clear();
                    out.extend(layout.uv.iter().map(|&uv| surface_point(&g.eval_derivs_with_form(&mut ev, uv, self.form))));
                    return true;
                }
                (Evaluation::Direct, Patch::Cgb(c)) => {
                    let Ok(mut ev) = c.evaluator() else { return false };
                    out.clear();
                    out.extend(layout.uv.iter().map(|&uv| surface_point(&c.eval_derivs_with(&mut ev, uv, self.form))));
                    return true;
                }
                _ => return false,
            };
            if ctrl.len() != table.control_count() || table.sample_count() != samples {
                return false;
            }
            // One dispatched pass (AVX2 + FMA where the CPU has them) for the sums and the
            // per-sample normal and curvature. It writes every sample once, so a buffer of the
            // right length (the caller's, reused from the previous patch) is only overwritten.
            out.resize(samples, SurfacePoint::default());
            table.for_each_sample_derivs(&ctrl, |s, d, n| {
                if let Some(o) = out.get_mut(s) {
                    *o = surface_point_with(d, n);
                }
            });
            true
        });
        if !filled {
            out.clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gb(n: usize, d: usize, r: usize) -> Table {
        Table::Gb(Arc::new(GbTable::with_second_derivatives(n, d, r, WeightForm::Squared).unwrap()))
    }

    fn key(n: usize, d: usize, r: usize) -> TableKey {
        TableKey { kind: Kind::Gb(n, d), resolution: r.into(), form: WeightForm::Squared }
    }

    fn ptr(t: &Table) -> *const () {
        match t {
            Table::Gb(t) => Arc::as_ptr(t) as *const (),
            Table::Cgb(t) => Arc::as_ptr(t) as *const (),
        }
    }

    #[test]
    fn cache_shares_tables_per_key_and_stays_bounded() {
        let one = gb(5, 3, 4).memory_bytes() as u128;
        let cache = TableCache::new(2 * one);
        let a = cache.get_or_build(key(5, 3, 4), || Ok(gb(5, 3, 4))).unwrap();
        let b = cache.get_or_build(key(5, 3, 4), || panic!("cached")).unwrap();
        assert_eq!(ptr(&a), ptr(&b));
        assert_eq!((cache.len(), cache.memory_bytes()), (1, one));
        // Same size, other key: both fit.
        let c = cache.get_or_build(TableKey { form: WeightForm::Linear, ..key(5, 3, 4) }, || Ok(gb(5, 3, 4))).unwrap();
        assert_ne!(ptr(&a), ptr(&c));
        assert_eq!(cache.len(), 2);
        // Touch a, then a third table evicts the least recently used (c).
        cache.get_or_build(key(5, 3, 4), || panic!("cached")).unwrap();
        cache.get_or_build(key(6, 3, 3), || Ok(gb(6, 3, 3))).unwrap();
        assert!(cache.memory_bytes() <= 2 * one);
        let again = cache.get_or_build(key(5, 3, 4), || panic!("a was evicted")).unwrap();
        assert_eq!(ptr(&a), ptr(&again));
        // A table larger than the bound is not kept.
        let small = TableCache::new(one - 1);
        small.get_or_build(key(5, 3, 4), || Ok(gb(5, 3, 4))).unwrap();
        assert!(small.is_empty());
        cache.clear();
        assert_eq!((cache.len(), cache.memory_bytes()), (0, 0));
    }
}
