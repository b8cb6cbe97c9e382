//! Errors of the PH curve layer; each names the offending argument and, for sequences, the index.

use crate::bezier::BezierError;
use thiserror::Error;

fn at(index: &Option<usize>) -> String {
    match index {
        Some(i) => format!(" (index {i})"),
        None => String::new(),
    }
}

/// Errors of PH curve construction and analysis.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PhError {
    /// An input value has a NaN or infinite coordinate.
    #[error("argument `{arg}`{} is not finite", at(.index))]
    NonFinite {
        arg: &'static str,
        index: Option<usize>,
    },
    /// An end derivative is the zero vector: a PH preimage w (or A) with w(t)² = 0 has no
    /// direction, so the Hermite problem has no regular solution.
    #[error("derivative `{arg}`{} is zero", at(.index))]
    ZeroDerivative {
        arg: &'static str,
        index: Option<usize>,
    },
    /// Two consecutive points coincide (`index` and `index + 1`; for a closed spline the last
    /// index wraps to 0).
    #[error("points `{arg}` {index} and the next one coincide")]
    CoincidentPoints { arg: &'static str, index: usize },
    /// An offset at distance 0 is the curve itself; it is rejected so that callers notice.
    #[error("offset distance `d` is zero")]
    ZeroOffsetDistance,
    /// Too few points for the requested construction.
    #[error("`{arg}` has {got} points; at least {need} are needed")]
    TooFewPoints {
        arg: &'static str,
        got: usize,
        need: usize,
    },
    /// Two input sequences that must have equal length do not.
    #[error("`{arg}` has {got} entries, expected {expected}")]
    LengthMismatch {
        arg: &'static str,
        got: usize,
        expected: usize,
    },
    /// A Newton iteration did not reach its tolerance.
    #[error("Newton iteration for {what} did not converge after {iterations} steps (residual {residual:e})")]
    NewtonNoConvergence {
        what: &'static str,
        iterations: usize,
        residual: f64,
    },
    /// The preimage w(t) (or A(t)) vanishes at parameter `t` in [0, 1]: the curve stops there,
    /// its normal and curvature are undefined and the offset has a pole.
    #[error("the hodograph vanishes at t = {t}")]
    SingularHodograph { t: f64 },
    /// A weight of the rational offset is exactly zero, so its control point `index` is at
    /// infinity (use the homogeneous points).
    #[error("offset weight {index} is zero")]
    ZeroOffsetWeight { index: usize },
    /// An arc length outside [0, L].
    #[error("arc length {s} is outside [0, {length}]")]
    ArcLengthOutOfRange { s: f64, length: f64 },
    /// An error of the Bézier layer (e.g. a rational curve with a non-positive weight).
    #[error(transparent)]
    Bezier(#[from] BezierError),
}

pub(crate) fn check_finite2(
    arg: &'static str,
    index: Option<usize>,
    v: glam::DVec2,
) -> Result<(), PhError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(PhError::NonFinite { arg, index })
    }
}

pub(crate) fn check_finite3(
    arg: &'static str,
    index: Option<usize>,
    v: glam::DVec3,
) -> Result<(), PhError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(PhError::NonFinite { arg, index })
    }
}
