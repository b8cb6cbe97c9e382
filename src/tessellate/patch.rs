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

/// Peak bytes per sample of [`tessellate_gb`] and writing its OBJ (layout, evaluated points, the
/// triangle mesh; measured 180–193 on a 1024-sided patch at r = 32 and 64, peak RSS of
/// `gbsurf tessellate-gbp`).
pub const SINGLE_PATCH_BYTES_PER_SAMPLE: u64 = 256;

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
    // The memory bound before anything is allocated: 1 + n·r(r+1)/2 samples of at most
    // SINGLE_PATCH_BYTES_PER_SAMPLE each, against the default memory limit.
    let n = patch.ribbons.len() as u64;
    let r = resolution as u64;
    let samples = n.saturating_mul(r).saturating_mul(r + 1) / 2 + 1;
    let bytes = samples.saturating_mul(SINGLE_PATCH_BYTES_PER_SAMPLE);
    let limit = crate::limits::DEFAULT_MAX_MEMORY_MB << 20;
    if bytes > limit {
        return Err(TessellateError::OverMemoryLimit { sides: n as usize, r: resolution, samples, mib: bytes >> 20, limit_mib: limit >> 20 });
    }
    let ev = patch.evaluator().map_err(invalid)?;
    let layout = SampleLayout::for_domain(ev.domain(), resolution)
        .map_err(|source| TessellateError::Layout { patch: 0, source })?;
    // One evaluation per sample (the normal from the same derivatives; the nearby fallback only
    // where they degenerate), samples in parallel: a patch of n sides costs O(n) per sample
    // (docs/math.md#cost-per-point), so a 1024-sided patch is worth both cores.
    use rayon::prelude::*;
    if patch.ribbons.len() > crate::limits::MAX_UNSPLIT_SIDES && layout.sampling().layout == crate::gb::Layout::Triangles {
        let points = symmetric_points(patch, &ev, &layout, form);
        if let Some(sample) = points.iter().position(|(p, _)| !p.is_finite()) {
            return Err(TessellateError::Evaluation { patch: 0, sample });
        }
        return Ok(tessellate_with(&layout, |s, _| points[s]));
    }
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

/// Positions and unit normals of a GB patch of many sides at every sample of the triangle
/// layout on its regular domain, by rotational symmetry (docs/math.md#cost-per-point).
///
/// The regular n-gon domain and the layout are invariant under the rotation R taking domain
/// vertex i−1 to vertex i: sample t of side i on ring m is R^i applied to sample t of side 0
/// (layout order: index 1 + n·m(m−1)/2 + i·m + t). Wachspress coordinates rotate with it,
/// λ_k(R x) = λ_{k−1}(x), and with them every ribbon's local parameters and weights: ribbon j's
/// weights at R^i x are ribbon (j − i)'s at x. So the basis is evaluated once per sample of side 0
/// (r(r+1)/2 of them, the costly part: Bernstein jets, corner weights) and applied to all n
/// rotations (a dot product with the control points). Derivatives taken in the frame of side 0
/// are those at the rotated point turned by R^i, which leaves S_u × S_v, hence the normal,
/// unchanged. The centre sample and any sample whose normal degenerates are evaluated directly.
fn symmetric_points(patch: &GbPatch, ev: &crate::gb::GbBasisEvaluator, layout: &SampleLayout, form: WeightForm) -> Vec<(DVec3, DVec3)> {
    use rayon::prelude::*;
    let n = patch.ribbons.len();
    let (l, d1) = (ev.layers(), ev.degree() + 1);
    let per = l * d1;
    let r = layout.sampling().resolution;
    let mut points = vec![(DVec3::ZERO, DVec3::ZERO); layout.uv.len()];
    // Control points in the weights' flat order (ribbon j, row k, column c).
    let ctrl: Vec<DVec3> = patch
        .ribbons
        .iter()
        .flat_map(|rb| (0..l).flat_map(move |k| (0..d1).map(move |c| rb.get_row(k).and_then(|row| row.get(c)).copied().unwrap_or(DVec3::ZERO))))
        .collect();
    let reps: Vec<(usize, usize)> = (1..=r).flat_map(|m| (0..m).map(move |t| (m, t))).collect();
    let done: Vec<Vec<(usize, DVec3, DVec3, DVec3)>> = reps
        .par_iter()
        .map_init(
            || (ev.clone(), Vec::with_capacity(n * per)),
            |(ev, w), &(m, t)| {
                let first = 1 + n * m * (m - 1) / 2 + t;
                w.clear();
                let b0 = ev.for_each_ribbon_weight(layout.uv[first], form, |_, x| w.push([x.val, x.du, x.dv]));
                (0..n)
                    .map(|i| {
                        let (mut p, mut su, mut sv) = (b0.val * patch.center, b0.du * patch.center, b0.dv * patch.center);
                        // Ribbon j at this sample uses the weights of ribbon j − i at side 0:
                        // control points from ribbon i on meet weights from ribbon 0 on, and
                        // the first i ribbons' meet the last i ribbons' weights.
                        let mut add = |ws: &[[f64; 3]], cs: &[DVec3]| {
                            for (x, &c) in ws.iter().zip(cs) {
                                p += x[0] * c;
                                su += x[1] * c;
                                sv += x[2] * c;
                            }
                        };
                        add(&w[..(n - i) * per], &ctrl[i * per..]);
                        add(&w[(n - i) * per..], &ctrl[..i * per]);
                        (first + i * m, p, su, sv)
                    })
                    .collect()
            },
        )
        .collect();
    let mut ev = ev.clone();
    for (s, p, su, sv) in done.into_iter().flatten() {
        let d = crate::gb::SurfaceDerivs { p, su, sv, ..Default::default() };
        let nrm = d.normal().unwrap_or_else(|| normal_or_nearby(patch, &mut ev, layout.uv[s], form));
        points[s] = (p, nrm);
    }
    let centre = patch.eval_derivs_with_form(&mut ev, layout.uv[0], form);
    points[0] = (centre.p, centre.normal().unwrap_or_else(|| normal_or_nearby(patch, &mut ev, layout.uv[0], form)));
    points
}
