//! Errors of the PN layer; each names the offending input element (grid index (i, j), patch
//! index, or argument).

use thiserror::Error;

/// Which input grid an error refers to.
pub type Argument = &'static str;

/// Errors of PN interpolation, evaluation and export (seed 004 §4).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PnError {
    /// A PN surface needs at least 2 × 2 grid points (one Coons patch).
    #[error("the grid is {rows} × {cols}; PN interpolation needs at least 2 × 2 points")]
    GridTooSmall { rows: usize, cols: usize },
    /// A row of an input grid has the wrong length (ragged grid), or the grids differ in shape.
    #[error("{argument}: row {row} has {found} entries, expected {expected}")]
    RaggedGrid {
        argument: Argument,
        row: usize,
        expected: usize,
        found: usize,
    },
    /// An input grid has a different number of rows than the points grid.
    #[error("{argument} has {found} rows, expected {expected} (as many as the points)")]
    RowCount {
        argument: Argument,
        expected: usize,
        found: usize,
    },
    /// A NaN or infinite coordinate in an input grid.
    #[error("{argument}[{i}][{j}] is not finite")]
    NotFinite {
        argument: Argument,
        i: usize,
        j: usize,
    },
    /// A normal of length zero (or too short to normalize).
    #[error("normal [{i}][{j}] has length zero")]
    ZeroNormal { i: usize, j: usize },
    /// A normal at (or within round-off of) the pole (0, 0, 1) of the isotropic map in the
    /// chosen frame, where the map is undefined (seed 004 §4.3). Use an automatic frame.
    #[error("normal [{i}][{j}] is at the pole (0, 0, 1) of the isotropic map in the chosen frame")]
    NormalAtPole { i: usize, j: usize },
    /// The normals cover the whole sphere so densely that no rotation keeps them off the pole.
    #[error("no frame rotation keeps all normals off the pole; normal [{i}][{j}] is closest")]
    NoFrame { i: usize, j: usize },
    /// A frame rotation that is not a proper rotation matrix.
    #[error("the frame matrix is not a rotation (orthonormal with determinant 1)")]
    BadRotation,
    /// A supplied isotropic derivative vector is not on the admissible plane of its grid point
    /// (seed 004 §4.3), so the patch would miss the data point.
    #[error("isotropic {direction}-derivative at [{i}][{j}] is off the admissible plane (relative residual {residual:e})")]
    InadmissibleDerivative {
        i: usize,
        j: usize,
        direction: char,
        residual: f64,
    },
    /// NᵀN is singular at a grid point: the derivative vectors of the normal are parallel or zero
    /// (zero Gaussian curvature; seed 004 §4.2), so the point cannot be pulled back.
    #[error("singular point at grid [{i}][{j}]: the normal field has a degenerate derivative (zero Gaussian curvature)")]
    SingularPoint { i: usize, j: usize },
    /// The Jacobian of the Gauss map changes sign between two corners of a patch (the data mixes
    /// positive and negative Gaussian curvature), so the pull-back is singular inside the patch.
    #[error(
        "patch [{i}][{j}] is singular: the Gaussian curvature changes sign between its corners"
    )]
    CurvatureSignChange { i: usize, j: usize },
    /// NᵀN is singular at an evaluated point of a patch (seed 004 §4.2).
    #[error("patch [{i}][{j}] is singular at (u, v) = ({u}, {v}) (zero Gaussian curvature)")]
    SingularPullBack { i: usize, j: usize, u: f64, v: f64 },
    /// A patch index outside the grid of patches.
    #[error("patch [{i}][{j}] does not exist; there are {rows} × {cols} patches")]
    NoSuchPatch {
        i: usize,
        j: usize,
        rows: usize,
        cols: usize,
    },
    /// A parameter that is not finite or outside its range.
    #[error("parameter {name} = {value} is not finite or outside [0, {max}]")]
    BadParameter {
        name: &'static str,
        value: f64,
        max: f64,
    },
    /// The Bézier coefficients of the Gauss-map Jacobian J on a patch are not all of one sign,
    /// so the patch cannot be certified free of singular points (it may still be regular).
    #[error("patch [{i}][{j}] may be singular: its Gauss-map Jacobian has Bézier coefficients of both signs")]
    MaybeSingular { i: usize, j: usize },
    /// The exact rational form of a patch overflowed (a non-finite coefficient).
    #[error("the rational form of patch [{i}][{j}] has a non-finite coefficient")]
    NonFiniteExport { i: usize, j: usize },
    /// An offset distance that is not finite.
    #[error("offset distance {d} is not finite")]
    BadOffset { d: f64 },
    /// An offset surface of distance zero was requested (it is the surface itself).
    #[error("offset distance 0 asks for the surface itself; use the surface's own rational form")]
    ZeroOffset,
}
