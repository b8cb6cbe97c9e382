//! Grid input, derivative estimates (seed 004 §4.4), the grid of Coons patches (§4.5) and the
//! pull-back to space (§4.2, §4.6): evaluation, offsets and exact rational export.
//!
//! Indexing: grid point [i][j], i = 0..rows along u, j = 0..cols along v (rows ≠ cols allowed).
//! Patch [i][j] (i < rows − 1, j < cols − 1) spans grid points [i..=i+1][j..=j+1]; its local
//! parameters are u, v ∈ [0, 1] with grid spacing 1, so derivative vectors are per grid step.

use super::coons::CoonsPatch;
use super::error::{Argument, PnError};
use super::isotropic::{
    admissible_normal, db_dy, from_isotropic, point_from_dual, IsotropicFrame, SINGULAR_SIN,
};
use super::rational::{PatchPolys, PnRational};
use glam::DVec3;

/// Largest relative residual |v·t|/(|v||t|) accepted for a caller-supplied isotropic derivative
/// vector t at a grid point with admissible-plane normal v; it is then projected exactly.
pub const ADMISSIBLE_TOL: f64 = 1e-9;

/// Validated input: an m × n grid of points with unit normals (both in world coordinates).
#[derive(Debug, Clone, PartialEq)]
pub struct PnGrid {
    rows: usize,
    cols: usize,
    points: Vec<DVec3>,
    normals: Vec<DVec3>,
}

/// Check that `grid` is rows × cols and finite; returns the row-major values.
fn check_shape(
    argument: Argument,
    grid: &[Vec<DVec3>],
    rows: usize,
    cols: usize,
) -> Result<Vec<DVec3>, PnError> {
    if grid.len() != rows {
        return Err(PnError::RowCount {
            argument,
            expected: rows,
            found: grid.len(),
        });
    }
    for (row, r) in grid.iter().enumerate() {
        if r.len() != cols {
            return Err(PnError::RaggedGrid {
                argument,
                row,
                expected: cols,
                found: r.len(),
            });
        }
    }
    for (i, r) in grid.iter().enumerate() {
        if let Some(j) = r.iter().position(|p| !p.is_finite()) {
            return Err(PnError::NotFinite { argument, i, j });
        }
    }
    Ok(grid.iter().flatten().copied().collect())
}

impl PnGrid {
    /// Validate `points[i][j]` and `normals[i][j]` (seed 004 §4.1): at least 2 × 2, rectangular,
    /// finite, normals non-zero. Normals are normalized.
    pub fn new(points: &[Vec<DVec3>], normals: &[Vec<DVec3>]) -> Result<Self, PnError> {
        let rows = points.len();
        let cols = points.first().map_or(0, Vec::len);
        let pts = check_shape("points", points, rows, cols)?;
        if rows < 2 || cols < 2 {
            return Err(PnError::GridTooSmall { rows, cols });
        }
        let nrm = check_shape("normals", normals, rows, cols)?;
        let normals = nrm
            .iter()
            .enumerate()
            .map(|(k, n)| {
                n.try_normalize().ok_or(PnError::ZeroNormal {
                    i: k / cols,
                    j: k % cols,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            rows,
            cols,
            points: pts,
            normals,
        })
    }

    /// Number of grid rows m (along u).
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of grid columns n (along v).
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Point [i][j] (panics when out of range, like slice indexing).
    pub fn point(&self, i: usize, j: usize) -> DVec3 {
        self.points[i * self.cols + j]
    }

    /// Unit normal [i][j] (panics when out of range, like slice indexing).
    pub fn normal(&self, i: usize, j: usize) -> DVec3 {
        self.normals[i * self.cols + j]
    }

    /// The normals as rows, e.g. for [`IsotropicFrame::auto`].
    pub fn normal_rows(&self) -> Vec<Vec<DVec3>> {
        self.normals
            .chunks(self.cols)
            .map(<[DVec3]>::to_vec)
            .collect()
    }

    /// Isotropic images y[i][j] in `frame` (seed 004 §4.3), row-major.
    fn isotropic(&self, frame: &IsotropicFrame) -> Result<Vec<DVec3>, PnError> {
        (0..self.points.len())
            .map(|k| {
                frame
                    .isotropic(self.points[k], self.normals[k])
                    .ok_or(PnError::NormalAtPole {
                        i: k / self.cols,
                        j: k % self.cols,
                    })
            })
            .collect()
    }
}

/// How [`PnOptions`] picks the isotropic frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum FrameChoice {
    /// [`IsotropicFrame::auto`] on the grid's normals.
    #[default]
    Auto,
    /// This frame (e.g. [`IsotropicFrame::IDENTITY`], the seed's map as printed).
    Fixed(IsotropicFrame),
}

/// Raw tangent estimate in the isotropic model, per grid direction, grid spacing 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TangentEstimate {
    /// Seed 004 §4.4: central differences (y_{i+1} − y_{i−1})/2 inside, one-sided differences
    /// y_1 − y_0 and y_m − y_{m−1} at the ends.
    SeedDifferences,
    /// Bessel tangents (the derivative of the parabola through three consecutive points):
    /// central differences inside, (−3y_0 + 4y_1 − y_2)/2 and (3y_m − 4y_{m−1} + y_{m−2})/2 at the
    /// ends; the plain difference when a direction has only 2 points. Exact for quadratics.
    #[default]
    Bessel,
}

/// Projection of a raw tangent t* onto the admissible plane v·t = 0 of its grid point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Projection {
    /// Seed 004 §4.4: orthogonal projection t = t* − (v·t*)/(v·v) v.
    Orthogonal,
    /// Along the isotropic (y_z) direction: keep t_x, t_y and set
    /// t_z = (x_1 + y_x x_3) t_x + (x_2 + y_y x_3) t_y. Keeps the Gauss-map part (t_x, t_y)
    /// unchanged; with Bessel tangents it reproduces spheres sampled on a grid uniform in
    /// (y_x, y_y) exactly.
    #[default]
    Isotropic,
}

/// Options of [`PnSurface::interpolate`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PnOptions {
    /// Frame of the isotropic map.
    pub frame: FrameChoice,
    /// Raw tangent estimate.
    pub tangents: TangentEstimate,
    /// Projection onto the admissible plane.
    pub projection: Projection,
}

/// Raw tangent of the sequence `ys` at index k (see [`TangentEstimate`]).
fn raw_tangent(ys: &[DVec3], k: usize, est: TangentEstimate) -> DVec3 {
    let l = ys.len() - 1;
    let bessel = est == TangentEstimate::Bessel && l >= 2;
    if k == 0 {
        if bessel {
            (ys[1] * 4.0 - ys[0] * 3.0 - ys[2]) * 0.5
        } else {
            ys[1] - ys[0]
        }
    } else if k == l {
        if bessel {
            (ys[l] * 3.0 - ys[l - 1] * 4.0 + ys[l - 2]) * 0.5
        } else {
            ys[l] - ys[l - 1]
        }
    } else {
        (ys[k + 1] - ys[k - 1]) * 0.5
    }
}

/// Project t onto the plane with normal v (v.z = −1, see [`admissible_normal`]).
fn project(t: DVec3, v: DVec3, p: Projection) -> DVec3 {
    match p {
        Projection::Orthogonal => t - v * (v.dot(t) / v.dot(v)),
        Projection::Isotropic => DVec3::new(t.x, t.y, v.x * t.x + v.y * t.y),
    }
}

/// Isotropic derivative vectors (du, dv) as grids `[i][j]`.
pub type DerivativeGrids = (Vec<Vec<DVec3>>, Vec<Vec<DVec3>>);

/// Isotropic derivative estimates (γ, δ) at every grid point in `frame`, as rows `[i][j]`
/// (seed 004 §4.4): raw tangents along i (u) and j (v) of the isotropic images, projected onto
/// the admissible plane of each point.
pub fn estimate_derivatives(
    grid: &PnGrid,
    frame: &IsotropicFrame,
    tangents: TangentEstimate,
    projection: Projection,
) -> Result<DerivativeGrids, PnError> {
    let (m, n) = (grid.rows, grid.cols);
    let y = grid.isotropic(frame)?;
    let mut du = vec![vec![DVec3::ZERO; n]; m];
    let mut dv = vec![vec![DVec3::ZERO; n]; m];
    for i in 0..m {
        for j in 0..n {
            let v = admissible_normal(frame.to_frame(grid.point(i, j)), y[i * n + j]);
            let col: Vec<DVec3> = (0..m).map(|k| y[k * n + j]).collect();
            du[i][j] = project(raw_tangent(&col, i, tangents), v, projection);
            dv[i][j] = project(
                raw_tangent(&y[i * n..(i + 1) * n], j, tangents),
                v,
                projection,
            );
        }
    }
    Ok((du, dv))
}

/// A point of a PN surface with its unit normal, in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PnSample {
    /// Surface point x.
    pub point: DVec3,
    /// Unit normal n (the interpolated normal field; x_u·n = x_v·n = 0).
    pub normal: DVec3,
}

impl PnSample {
    /// The offset point x + d·n (exact: n is the rational unit normal).
    pub fn offset(&self, d: f64) -> DVec3 {
        self.point + self.normal * d
    }
}

/// A G¹ PN surface: a grid of Coons patches in the isotropic model (C¹ there), pulled back to
/// space (seed 004 §4).
#[derive(Debug, Clone, PartialEq)]
pub struct PnSurface {
    frame: IsotropicFrame,
    rows: usize,
    cols: usize,
    y: Vec<DVec3>,
    du: Vec<DVec3>,
    dv: Vec<DVec3>,
}

impl PnSurface {
    /// Interpolate the grid with estimated derivatives: frame by `options.frame`, derivatives by
    /// [`estimate_derivatives`], then [`PnSurface::from_derivatives`].
    pub fn interpolate(grid: &PnGrid, options: &PnOptions) -> Result<Self, PnError> {
        let frame = match options.frame {
            FrameChoice::Auto => IsotropicFrame::auto(&grid.normal_rows())?,
            FrameChoice::Fixed(f) => f,
        };
        let (du, dv) = estimate_derivatives(grid, &frame, options.tangents, options.projection)?;
        Self::from_derivatives(grid, frame, &du, &dv)
    }

    /// Interpolate the grid with caller-supplied isotropic derivative vectors `du[i][j]` (along
    /// u, i.e. along i) and `dv[i][j]` (along v, i.e. along j), in `frame`, per grid step (e.g.
    /// from [`IsotropicFrame::isotropic_tangent`] of an exactly sampled surface). Neighbouring
    /// grids that share boundary points, normals and derivative vectors (and the frame) join
    /// with G¹ continuity along the shared boundary.
    ///
    /// Errors: shape or finiteness of `du`/`dv`; a normal at the frame's pole; a derivative off
    /// the admissible plane by more than [`ADMISSIBLE_TOL`] (relative); a singular grid point
    /// (parallel or zero (t_x, t_y) parts of du and dv: zero Gaussian curvature); a patch whose
    /// corners have Gauss-map Jacobians of opposite sign.
    pub fn from_derivatives(
        grid: &PnGrid,
        frame: IsotropicFrame,
        du: &[Vec<DVec3>],
        dv: &[Vec<DVec3>],
    ) -> Result<Self, PnError> {
        let (m, n) = (grid.rows, grid.cols);
        let mut du = check_shape("du", du, m, n)?;
        let mut dv = check_shape("dv", dv, m, n)?;
        let y = grid.isotropic(&frame)?;
        let mut jac = vec![0.0; m * n];
        for k in 0..m * n {
            let (i, j) = (k / n, k % n);
            let v = admissible_normal(frame.to_frame(grid.points[k]), y[k]);
            for (t, direction) in [(&mut du[k], 'u'), (&mut dv[k], 'v')] {
                let scale = v.length() * t.length();
                let residual = if scale > 0.0 {
                    v.dot(*t).abs() / scale
                } else {
                    0.0
                };
                if residual.is_nan() || residual > ADMISSIBLE_TOL {
                    return Err(PnError::InadmissibleDerivative {
                        i,
                        j,
                        direction,
                        residual,
                    });
                }
                *t = project(*t, v, Projection::Orthogonal);
            }
            let (a, b) = (du[k], dv[k]);
            let det = a.x * b.y - a.y * b.x;
            let scale = a.truncate().length() * b.truncate().length();
            if !(scale > 0.0 && det.abs() > SINGULAR_SIN * scale) {
                return Err(PnError::SingularPoint { i, j });
            }
            jac[k] = det;
        }
        for i in 0..m - 1 {
            for j in 0..n - 1 {
                let s = jac[i * n + j].signum();
                let corners = [(i + 1, j), (i, j + 1), (i + 1, j + 1)];
                if corners.iter().any(|&(a, b)| jac[a * n + b].signum() != s) {
                    return Err(PnError::CurvatureSignChange { i, j });
                }
            }
        }
        Ok(Self {
            frame,
            rows: m,
            cols: n,
            y,
            du,
            dv,
        })
    }

    /// The isotropic frame.
    pub fn frame(&self) -> IsotropicFrame {
        self.frame
    }

    /// Grid size (rows m, cols n).
    pub fn grid_size(&self) -> (usize, usize) {
        (self.rows, self.cols)
    }

    /// Number of patches (m − 1, n − 1).
    pub fn patch_count(&self) -> (usize, usize) {
        (self.rows - 1, self.cols - 1)
    }

    /// Isotropic image y and the (projected) derivative vectors (γ, δ) at grid point [i][j], in
    /// the frame; `None` out of range.
    pub fn grid_data(&self, i: usize, j: usize) -> Option<(DVec3, DVec3, DVec3)> {
        (i < self.rows && j < self.cols).then(|| {
            let k = i * self.cols + j;
            (self.y[k], self.du[k], self.dv[k])
        })
    }

    /// The isotropic Coons patch [i][j] (seed 004 §4.5).
    pub fn patch(&self, i: usize, j: usize) -> Result<CoonsPatch, PnError> {
        let (pr, pc) = self.patch_count();
        if i >= pr || j >= pc {
            return Err(PnError::NoSuchPatch {
                i,
                j,
                rows: pr,
                cols: pc,
            });
        }
        let at = |k: usize, l: usize| (i + k) * self.cols + j + l;
        let pick = |v: &[DVec3]| [[v[at(0, 0)], v[at(0, 1)]], [v[at(1, 0)], v[at(1, 1)]]];
        Ok(CoonsPatch {
            a: pick(&self.y),
            du: pick(&self.du),
            dv: pick(&self.dv),
        })
    }

    /// Point and unit normal of patch [i][j] at (u, v) ∈ [0, 1]², world coordinates:
    /// y, y_u, y_v of the Coons patch; (n, h) by the inverse isotropic map; n_s = (dn/dy)·y_s and
    /// h_s = (dh/dy)·y_s with the corrected db/dy; x = h n + N (NᵀN)⁻¹ ∇h (seed 004 §4.2).
    /// Errors on a bad index or parameter and where NᵀN is singular.
    pub fn eval(&self, i: usize, j: usize, u: f64, v: f64) -> Result<PnSample, PnError> {
        check_param("u", u, 1.0)?;
        check_param("v", v, 1.0)?;
        let p = self.patch(i, j)?.partials(u, v);
        let d = from_isotropic(p.y);
        let m = db_dy(p.y);
        let row = |r: usize, t: DVec3| m[r][0] * t.x + m[r][1] * t.y + m[r][2] * t.z;
        let n_s = |t: DVec3| DVec3::new(row(0, t), row(1, t), row(2, t));
        let x = point_from_dual(d, n_s(p.y_u), n_s(p.y_v), row(3, p.y_u), row(3, p.y_v))
            .ok_or(PnError::SingularPullBack { i, j, u, v })?;
        Ok(PnSample {
            point: self.frame.to_world(x),
            normal: self.frame.to_world(d.n),
        })
    }

    /// [`PnSurface::eval`] at global parameters s ∈ [0, m − 1] (along i), t ∈ [0, n − 1]
    /// (along j): patch [⌊s⌋][⌊t⌋] (the last patch at the far ends), local u = s − i, v = t − j.
    pub fn eval_global(&self, s: f64, t: f64) -> Result<PnSample, PnError> {
        check_param("s", s, (self.rows - 1) as f64)?;
        check_param("t", t, (self.cols - 1) as f64)?;
        let i = (s.floor() as usize).min(self.rows - 2);
        let j = (t.floor() as usize).min(self.cols - 2);
        self.eval(i, j, s - i as f64, t - j as f64)
    }

    /// Offset point x + d·n of patch [i][j] at (u, v); d = 0 gives the surface point.
    pub fn offset(&self, i: usize, j: usize, u: f64, v: f64, d: f64) -> Result<DVec3, PnError> {
        if !d.is_finite() {
            return Err(PnError::BadOffset { d });
        }
        Ok(self.eval(i, j, u, v)?.offset(d))
    }

    fn polys(&self, i: usize, j: usize) -> Result<PatchPolys, PnError> {
        let b = self
            .patch(i, j)?
            .to_bezier()
            .map_err(|_| PnError::NonFiniteExport { i, j })?;
        Ok(PatchPolys::new(&b))
    }

    /// Exact rational form of patch [i][j]: degree (11, 11), homogeneous control points in world
    /// coordinates (see [`PnRational`] and the rational module for the formula).
    pub fn rational(&self, i: usize, j: usize) -> Result<PnRational, PnError> {
        self.polys(i, j)?
            .offset_form(0.0, |p| self.frame.to_world(p))
            .map_err(|_| PnError::NonFiniteExport { i, j })
    }

    /// Exact rational form of the offset x + d·n of patch [i][j]: degree (11, 11), same weights
    /// as the patch. Errors on d = 0 ([`PnError::ZeroOffset`]) or a non-finite d.
    pub fn rational_offset(&self, i: usize, j: usize, d: f64) -> Result<PnRational, PnError> {
        if !d.is_finite() {
            return Err(PnError::BadOffset { d });
        }
        if d == 0.0 {
            return Err(PnError::ZeroOffset);
        }
        self.polys(i, j)?
            .offset_form(d, |p| self.frame.to_world(p))
            .map_err(|_| PnError::NonFiniteExport { i, j })
    }

    /// Exact rational form of the unit normal of patch [i][j]: degree (6, 6).
    pub fn rational_normal(&self, i: usize, j: usize) -> Result<PnRational, PnError> {
        self.polys(i, j)?
            .normal_form(|p| self.frame.to_world(p))
            .map_err(|_| PnError::NonFiniteExport { i, j })
    }

    /// Certify that no patch has a singular point: the Bézier coefficients of each patch's
    /// Gauss-map Jacobian J = a_u b_v − a_v b_u (degree (5, 5)) are all of one sign. A sufficient
    /// test; [`PnError::MaybeSingular`] names the first patch that fails it.
    pub fn certify_regular(&self) -> Result<(), PnError> {
        let (pr, pc) = self.patch_count();
        for i in 0..pr {
            for j in 0..pc {
                if !self.polys(i, j)?.j.one_signed() {
                    return Err(PnError::MaybeSingular { i, j });
                }
            }
        }
        Ok(())
    }
}

fn check_param(name: &'static str, value: f64, max: f64) -> Result<(), PnError> {
    if (0.0..=max).contains(&value) {
        Ok(())
    } else {
        Err(PnError::BadParameter { name, value, max })
    }
}
