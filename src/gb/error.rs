//! Errors of the GB patch core (domain, basis, patches, degree elevation).

use thiserror::Error;

/// What is wrong with a domain request or a patch; every variant names the offending element.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GbError {
    /// A domain polygon needs at least three sides.
    #[error("a GB domain needs n >= 3 sides, got n = {0}")]
    TooFewSides(usize),
    /// Degree below 2 (the correction weights μ need d ≥ 2).
    #[error("side {side}: degree {degree} is below the minimum 2")]
    DegreeTooLow { side: usize, degree: usize },
    /// Degree above [`crate::limits::MAX_DEGREE`] (also guards allocations against
    /// absurd degrees coming from files or the C ABI).
    #[error("side {side}: degree {degree} is above the supported maximum {max}")]
    DegreeTooHigh {
        side: usize,
        degree: usize,
        max: usize,
    },
    /// Side `side` has a different degree from side 0.
    #[error("side {side}: degree {found} differs from the patch degree {expected}")]
    DegreeMismatch {
        side: usize,
        expected: usize,
        found: usize,
    },
    /// Wrong number of rows (layers) in a ribbon.
    #[error("side {side}: {found} rows, expected {expected}")]
    LayerCount {
        side: usize,
        expected: usize,
        found: usize,
    },
    /// A row has the wrong number of points.
    #[error("side {side}, row {row}: {found} points, expected {expected}")]
    RowLength {
        side: usize,
        row: usize,
        expected: usize,
        found: usize,
    },
    /// Rows of different lengths given for one ribbon (a ribbon stores `layers × width` points).
    #[error("ribbon row {row} has {found} points where row 0 has {expected}: every row of a ribbon has the same number of points")]
    RaggedRows {
        row: usize,
        expected: usize,
        found: usize,
    },
    /// A control point is NaN or infinite (`side` = None means the central point).
    #[error("control point side {side:?}, row {row}, column {col} is not finite")]
    NonFinite {
        side: Option<usize>,
        row: usize,
        col: usize,
    },
    /// A connected-net listing whose length is not 1 + the listed point count (central point
    /// first, see [`crate::gb::connected`]).
    #[error("connected listing has {found} points, expected {expected}")]
    ListingLength { expected: usize, found: usize },
    /// An output buffer of the wrong length was passed.
    #[error("buffer of length {found}, expected {expected}")]
    BufferLength { expected: usize, found: usize },
}
