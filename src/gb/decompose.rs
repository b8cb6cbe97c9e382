//! Editing tools for GB patches (seed 002, last slides):
//! - the decomposition S = S_B + Σ_i S_Di + S_I of a degree-d patch into a base patch (end
//!   positions and tangents of every side, from a cubic patch), one displacement per side and an
//!   interior part ([`decompose`]);
//! - elevation of several patches to one common degree ("közös fokszám 6←5←4←3",
//!   [`common_degree`]).
//!
//! The rule, with the reasons why each term acts where it is said to, is in
//! `docs/math/editing.md` ("Patches: base, displacements, interior"). In short, for d ≥ 3:
//! 1. Base, cubic: side i gets the cubic ribbon with row 0 = H(P_{·,0}) and
//!    row 1 = H(P_{·,0}) + (d/3)·H(P_{·,1} − P_{·,0}), H the cubic Hermite form of a curve
//!    ([`crate::bezier::reduce::hermite_cubic`]); so its boundary and its cross-derivative
//!    3(row1 − row0) have the patch's end positions and end first derivatives. Its central point
//!    is the patch's.
//! 2. S_B: that cubic patch elevated to degree d ([`GbPatch::elevate_to`]). Its rows 0 and 1 are
//!    H(row 0) and H(row 1) elevated to degree d, whose columns 0, 1, d−1, d equal the patch's, so
//!    the corner blocks (rows 0–1, columns 0, 1, d−1, d) agree; they are copied from the patch to
//!    remove round-off.
//! 3. Δ = S − S_B control point by control point. S_Di holds Δ on side i, rows 0 and 1,
//!    columns 2..=d−2 (the ribbon points of seed 002 that belong to side i only) and zero
//!    elsewhere. S_I holds Δ on rows k ≥ 2 of every side and the central point.
//!
//! Terms are stored as [`GbPatch`]es of degree d whose "points" are vectors; the GB patch is
//! linear in its control points (fixed weights), so `term.eval(uv, form)` is that term's value
//! Σ weight·vector and the four parts add up to `S.eval(uv, form)` exactly (to round-off).
//! S_Di changes only the boundary and cross-derivative of side i; S_I changes none.

use super::error::GbError;
use super::patch::{GbPatch, Ribbon};
use crate::limits::MAX_DEGREE;
use crate::bezier::reduce::hermite_cubic;
use crate::bezier::BezierCurve;
use glam::DVec3;
use thiserror::Error;

/// Errors of [`decompose`] and [`base_patch`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DecomposeError {
    /// The patch itself is malformed.
    #[error(transparent)]
    Invalid(#[from] GbError),
    /// The base patch is cubic and needs the cross-derivative row, so d ≥ 3.
    #[error("patch degree {degree} is below 3 (the base patch is cubic)")]
    BelowCubic { degree: usize },
}

/// Errors of [`common_degree`]; each names the offending patch by its index in the input.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CommonDegreeError {
    /// Patch `patch` is malformed.
    #[error("patch {patch}: {source}")]
    Patch {
        patch: usize,
        #[source]
        source: GbError,
    },
    /// Patch `patch` already has a degree above the requested common degree (degree reduction of
    /// patches is not exact on the boundaries, so it is not done here).
    #[error("patch {patch} has degree {degree}, above the common degree {target}")]
    AboveTarget {
        patch: usize,
        degree: usize,
        target: usize,
    },
    /// Patch `patch` is a ribbon-only (CGB) patch: its ribbons are normalised by the sum of their
    /// weights, so elevating them does not reproduce the patch; only GB patches have a common degree.
    #[error("patch {patch} is a ribbon-only (CGB) patch; a common degree exists only for GB patches (the dual structure)")]
    NotGb { patch: usize },
    /// The requested common degree exceeds [`MAX_DEGREE`].
    #[error("common degree {target} is above the supported maximum {max}")]
    TargetTooHigh { target: usize, max: usize },
}

/// Cubic ribbon of a degree-d ribbon with d ≥ 3 (two rows or more): row 0 = H(P_{·,0}),
/// row 1 = H(P_{·,0}) + (d/3)·H(P_{·,1} − P_{·,0}), H = [`hermite_cubic`]. The boundary and the
/// cross-derivative d(P_{·,1} − P_{·,0}) keep their end values and end first derivatives.
/// Rows k ≥ 2 are ignored. Only for validated ribbons of degree ≥ 3 (see [`base_patch`]).
fn hermite_ribbon(ribbon: &Ribbon) -> Ribbon {
    let d = ribbon.degree;
    let r0 = BezierCurve::from_vec(ribbon.row(0).to_vec());
    let diff = BezierCurve::from_vec(
        ribbon
            .row(1)
            .iter()
            .zip(ribbon.row(0))
            .map(|(a, b)| *a - *b)
            .collect(),
    );
    let h0 = hermite_cubic(&r0).into_points();
    let f = d as f64 / 3.0;
    let h1: Vec<DVec3> = hermite_cubic(&diff)
        .into_points()
        .into_iter()
        .zip(&h0)
        .map(|(v, p)| *p + v * f)
        .collect();
    Ribbon::from_fn(3, 2, h0.len(), |k, j| if k == 0 { h0[j] } else { h1[j] })
}

/// The cubic base patch of a degree-d patch (d ≥ 3): side i gets row 0 = H(P_{·,0}),
/// row 1 = H(P_{·,0}) + (d/3)·H(P_{·,1} − P_{·,0}) with H = [`hermite_cubic`], and the central
/// point is the patch's (rule 1 of the module documentation).
pub fn base_patch(patch: &GbPatch) -> Result<GbPatch, DecomposeError> {
    patch.validate()?;
    let d = patch.degree();
    if d < 3 {
        return Err(DecomposeError::BelowCubic { degree: d });
    }
    Ok(GbPatch {
        ribbons: patch.ribbons.iter().map(hermite_ribbon).collect(),
        center: patch.center,
    })
}

/// S = S_B + Σ_i S_Di + S_I of a degree-d GB patch (seed 002; rule in the module documentation
/// and `docs/math/editing.md`). All terms except `base_cubic` have the patch's degree and shape.
#[derive(Clone, Debug, PartialEq)]
pub struct GbDecomposition {
    /// The cubic base patch (rule 1).
    pub base_cubic: GbPatch,
    /// S_B: the cubic base elevated to degree d, corner blocks equal to the patch's (rule 2).
    pub base: GbPatch,
    /// S_Di for side i: vectors, non-zero only on side i, rows 0–1, columns 2..=d−2 (rule 3).
    pub displacements: Vec<GbPatch>,
    /// S_I: vectors, non-zero only on rows k ≥ 2 and the central point (rule 3).
    pub interior: GbPatch,
}

/// Whether (row k, column j) of a degree-d ribbon is in a corner block: k < 2 and
/// j ∈ {0, 1, d−1, d}.
fn in_corner_block(d: usize, k: usize, j: usize) -> bool {
    k < 2 && (j < 2 || j + 2 > d)
}

/// A patch of the same shape with every control point replaced by `f(side, row, col, point)`
/// (side = None for the central point).
fn map_points(
    p: &GbPatch,
    mut f: impl FnMut(Option<usize>, usize, usize, DVec3) -> DVec3,
) -> GbPatch {
    GbPatch {
        ribbons: p
            .ribbons
            .iter()
            .enumerate()
            .map(|(i, r)| Ribbon::from_fn(r.degree, r.layers(), r.width(), |k, j| f(Some(i), k, j, r.row(k)[j])))
            .collect(),
        center: f(None, 0, 0, p.center),
    }
}

/// Decomposes a GB patch of degree d ≥ 3 into base, per-side displacements and interior part
/// (seed 002, S = S_B + Σ S_Di + S_I).
pub fn decompose(patch: &GbPatch) -> Result<GbDecomposition, DecomposeError> {
    let base_cubic = base_patch(patch)?;
    let d = patch.degree();
    let elevated = base_cubic.elevate_to(d)?;
    let own = |i: Option<usize>, k: usize, j: usize| -> DVec3 {
        match i {
            Some(i) => patch.ribbons[i].row(k)[j],
            None => patch.center,
        }
    };
    let base = map_points(&elevated, |i, k, j, q| match i {
        Some(_) if in_corner_block(d, k, j) => own(i, k, j),
        _ => q,
    });
    let delta = map_points(&base, |i, k, j, q| own(i, k, j) - q);
    let displacements = (0..patch.n())
        .map(|side| {
            map_points(&delta, |i, k, j, v| {
                if i == Some(side) && k < 2 && !in_corner_block(d, k, j) {
                    v
                } else {
                    DVec3::ZERO
                }
            })
        })
        .collect();
    let interior = map_points(&delta, |i, k, _, v| {
        if i.is_none() || k >= 2 {
            v
        } else {
            DVec3::ZERO
        }
    });
    Ok(GbDecomposition {
        base_cubic,
        base,
        displacements,
        interior,
    })
}

impl GbDecomposition {
    /// Degree d of the decomposed patch.
    pub fn degree(&self) -> usize {
        self.base.degree()
    }

    /// The patch S_B + Σ S_Di + S_I, control point by control point (the decomposed patch, to
    /// round-off; after editing a term, the edited patch).
    pub fn recompose(&self) -> GbPatch {
        let mut out = self.base.clone();
        for term in self
            .displacements
            .iter()
            .chain(std::iter::once(&self.interior))
        {
            for (r, t) in out.ribbons.iter_mut().zip(&term.ribbons) {
                for k in 0..r.layers().min(t.layers()) {
                    for (p, v) in r.row_mut(k).iter_mut().zip(t.row(k)) {
                        *p += *v;
                    }
                }
            }
            out.center += term.center;
        }
        out
    }
}

/// Highest degree among `patches` (0 for none).
pub fn max_degree(patches: &[GbPatch]) -> usize {
    patches.iter().map(GbPatch::degree).max().unwrap_or(0)
}

/// Elevates every patch to the common degree `degree` (seed 002, "közös fokszám 6←5←4←3") with
/// [`GbPatch::elevate_to`]: boundary curves are kept exactly, cross-derivatives too for patches of
/// degree ≥ 3, so G1 joins between neighbours stay G1; the interiors change slightly (seed 002).
/// Pass [`max_degree`] to elevate to the highest degree present. Errors name the patch.
pub fn common_degree(
    patches: &[GbPatch],
    degree: usize,
) -> Result<Vec<GbPatch>, CommonDegreeError> {
    if degree > MAX_DEGREE {
        return Err(CommonDegreeError::TargetTooHigh {
            target: degree,
            max: MAX_DEGREE,
        });
    }
    patches
        .iter()
        .enumerate()
        .map(|(index, p)| {
            p.validate().map_err(|source| CommonDegreeError::Patch {
                patch: index,
                source,
            })?;
            if p.degree() > degree {
                return Err(CommonDegreeError::AboveTarget {
                    patch: index,
                    degree: p.degree(),
                    target: degree,
                });
            }
            p.elevate_to(degree)
                .map_err(|source| CommonDegreeError::Patch {
                    patch: index,
                    source,
                })
        })
        .collect()
}
