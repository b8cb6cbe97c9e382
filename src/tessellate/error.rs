//! Why a patch or a surface cannot be tessellated; every variant names the element.

use crate::gb::{GbError, LayoutError};
use crate::limits::MAX_RESOLUTION;

/// Why a patch or a surface cannot be tessellated. A single patch ([`super::patch`]) is named
/// patch 0.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TessellateError {
    /// The sampling layout of a patch could not be built.
    #[error("patch {patch}: {source}")]
    Layout { patch: usize, source: LayoutError },
    /// `neighbors` has no entry for a patch, or one of the wrong length.
    #[error("patch {patch} has {sides} sides but {entries} neighbour entries")]
    NeighborCount { patch: usize, sides: usize, entries: usize },
    /// A neighbour reference points outside the surface or is not reciprocated.
    #[error("side {side} of patch {patch} names neighbour (patch {other_patch}, side {other_side}), which does not name it back")]
    Adjacency { patch: usize, side: usize, other_patch: usize, other_side: usize },
    /// An evaluator returned a wrong number of samples or a non-finite position.
    #[error("patch {patch}: evaluation failed at sample {sample} (non-finite or missing)")]
    Evaluation { patch: usize, sample: usize },
    /// The output needs more than 2^32 − 1 vertices.
    #[error("the output mesh would need {count} vertices, more than u32 indices allow")]
    TooLarge { count: usize },
    /// A patch is malformed (row lengths, degrees, non-finite control points).
    #[error("patch {patch}: {source}")]
    InvalidPatch { patch: usize, source: GbError },
    /// Resolution above [`MAX_RESOLUTION`].
    #[error("resolution {r} is above the supported maximum {MAX_RESOLUTION}")]
    ResolutionTooHigh { r: usize },
    /// The progress callback asked to stop.
    #[error("cancelled")]
    Cancelled,
    /// An output array could not be allocated (`what` names it).
    #[error("out of memory: could not allocate {bytes} bytes for {what}")]
    OutOfMemory { what: &'static str, bytes: u64 },
    /// A single patch's tessellation would need more memory than the limit (estimated from its
    /// sample count before anything is allocated).
    #[error("{sides} sides at resolution {r} make {samples} samples, about {mib} MiB, above the limit of {limit_mib} MiB: lower the resolution")]
    OverMemoryLimit { sides: usize, r: usize, samples: u64, mib: u64, limit_mib: u64 },
}
