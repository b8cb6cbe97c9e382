//! Single-patch tessellation: the samples of a [`SampleLayout`] evaluated by any evaluator
//! (direct GB evaluation, weight tables, CGB) and emitted as triangles through a mesh sink.

use super::TessellateError;
use crate::gb::table::{GbTable, TableError};
use crate::gb::{GbPatch, SampleLayout, WeightForm};
use crate::limits::MAX_RESOLUTION;
use crate::mesh::{MeshSink, TriMesh};
use glam::{DVec2, DVec3};

/// Emits a patch through `sink`: every sample's position and normal come from
/// `eval(sample_index, uv)`, except where `existing(sample_index)` already names a sink vertex
/// (boundary vertices shared with a neighbouring patch). Returns the sink index of every sample.
pub fn emit_patch<S: MeshSink + ?Sized>(
    layout: &SampleLayout,
    mut eval: impl FnMut(usize, DVec2) -> (DVec3, DVec3),
    mut existing: impl FnMut(usize) -> Option<u32>,
    sink: &mut S,
) -> Vec<u32> {
    let ids: Vec<u32> = layout
        .uv
        .iter()
        .enumerate()
        .map(|(s, &uv)| {
            existing(s).unwrap_or_else(|| {
                let (p, nrm) = eval(s, uv);
                sink.add_vertex(p, nrm)
            })
        })
        .collect();
    for t in &layout.triangles {
        sink.add_triangle(t.map(|x| ids[x as usize]));
    }
    ids
}

/// One patch as a stand-alone triangle mesh (sample i is vertex i).
pub fn tessellate_with(
    layout: &SampleLayout,
    eval: impl FnMut(usize, DVec2) -> (DVec3, DVec3),
) -> TriMesh {
    let mut mesh = TriMesh::default();
    mesh.positions.reserve(layout.uv.len());
    mesh.normals.reserve(layout.uv.len());
    mesh.triangles.reserve(layout.triangles.len());
    emit_patch(layout, eval, |_| None, &mut mesh);
    mesh
}

/// One patch as a triangle mesh through a weight table (sample i is vertex i): the table gives
/// positions and normals ([`crate::gb::table::WeightTable::eval_all`]), the layout the triangles.
pub fn tessellate_table(table: &GbTable, patch: &GbPatch) -> Result<TriMesh, TableError> {
    let ctrl = table.controls_of(patch)?;
    let mut mesh = TriMesh::default();
    table.eval_all(&ctrl, &mut mesh.positions, &mut mesh.normals);
    mesh.triangles = table.layout.triangles.clone();
    Ok(mesh)
}

/// The unit normal at `uv`; where S_u × S_v degenerates (e.g. a corner with parallel tangents),
/// the normal a short step towards the domain centre, else zero.
pub fn normal_or_nearby(
    patch: &GbPatch,
    ev: &mut crate::gb::GbBasisEvaluator,
    uv: DVec2,
    form: WeightForm,
) -> DVec3 {
    let centre = ev.domain().center();
    for step in [0.0, 1e-9, 1e-6, 1e-3] {
        let q = uv + (centre - uv) * step;
        if let Some(nrm) = patch.eval_derivs_with_form(ev, q, form).normal() {
            return nrm;
        }
    }
    DVec3::ZERO
}

/// One GB patch as a triangle mesh at resolution r by direct evaluation (no weight table; for
/// many patches of one (n, d) use [`tessellate_table`]). Sample i is vertex i. Errors name the
/// patch as patch 0.
pub fn tessellate_gb(
    patch: &GbPatch,
    resolution: usize,
    form: WeightForm,
) -> Result<TriMesh, TessellateError> {
    if resolution > MAX_RESOLUTION {
        return Err(TessellateError::ResolutionTooHigh { r: resolution });
    }
    let invalid = |source| TessellateError::InvalidPatch { patch: 0, source };
    patch.validate().map_err(invalid)?;
    let ev = patch.evaluator().map_err(invalid)?;
    let layout = SampleLayout::for_domain(ev.domain(), resolution)
        .map_err(|source| TessellateError::Layout { patch: 0, source })?;
    // One evaluation per sample (the normal from the same derivatives; the nearby fallback only
    // where they degenerate), samples in parallel: a patch of n sides costs O(n) per sample
    // (docs/math.md#cost-per-point), so a 1024-sided patch is worth both cores.
    use rayon::prelude::*;
    let points: Vec<(DVec3, DVec3)> = layout
        .uv
        .par_iter()
        .with_min_len(64)
        .map_init(
            || ev.clone(),
            |ev, &uv| {
                let d = patch.eval_derivs_with_form(ev, uv, form);
                let n = d.normal().unwrap_or_else(|| normal_or_nearby(patch, ev, uv, form));
                (d.p, n)
            },
        )
        .collect();
    if let Some(sample) = points.iter().position(|(p, _)| !p.is_finite()) {
        return Err(TessellateError::Evaluation { patch: 0, sample });
    }
    Ok(tessellate_with(&layout, |s, _| points[s]))
}
