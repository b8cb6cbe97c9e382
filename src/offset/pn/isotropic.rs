//! The dual (n, h) representation of a surface, the isotropic model and the pull-back to space
//! (seed 004 §4.2–4.3, with the corrected derivative matrix).
//!
//! Map (seed 004 §4.3): projection of the Blaschke cylinder {(n, h) : |n| = 1} from the point
//! w = (0, 0, 1, 0) into the hyperplane n_z = 0:
//! y = (n_x, n_y, h) / (1 − n_z). Inverse, with q = 1 + y_x² + y_y²:
//! n = (2y_x, 2y_y, y_x² + y_y² − 1) / q, h = 2y_z / q.
//! The normal part is the inverse stereographic projection of (y_x, y_y); the map is undefined
//! at the pole n = (0, 0, 1), which [`IsotropicFrame`] keeps away from the data by a rotation.

use super::error::PnError;
use glam::{DMat3, DQuat, DVec3};

/// Smallest 1 − n_z (in the frame) accepted by the isotropic map: closer normals are reported
/// as [`PnError::NormalAtPole`].
pub const POLE_GAP: f64 = 1e-9;

/// [`IsotropicFrame::auto`] keeps the identity frame while every normal has n_z ≤ this value
/// (every normal at least 60° from the pole, so |(y_x, y_y)| ≤ √3).
pub const AUTO_MAX_NZ: f64 = 0.5;

/// Relative tolerance on sin∠(n_u, n_v) below which NᵀN counts as singular (the shared
/// round-off tolerance [`crate::tol::EPS`]).
pub const SINGULAR_SIN: f64 = crate::tol::EPS;

/// A tangent plane in dual coordinates: unit normal n and support value h = n·x
/// (seed 004 §4.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual {
    /// Unit normal.
    pub n: DVec3,
    /// Support function value h = n·x: signed distance of the tangent plane from the origin.
    pub h: f64,
}

impl Dual {
    /// The tangent plane at point x with unit normal n: (n, h = n·x) (seed 004 §4.2).
    pub fn of(x: DVec3, n: DVec3) -> Self {
        Self { n, h: n.dot(x) }
    }
}

/// y = (n_x, n_y, h)/(1 − n_z) (seed 004 §4.3); `None` when 1 − n_z ≤ [`POLE_GAP`] (at the pole).
/// `n` must be a unit vector.
pub fn to_isotropic(d: Dual) -> Option<DVec3> {
    let s = 1.0 - d.n.z;
    (s > POLE_GAP).then(|| DVec3::new(d.n.x, d.n.y, d.h) / s)
}

/// The inverse map (seed 004 §4.3): n = (2y_x, 2y_y, y_x² + y_y² − 1)/q, h = 2y_z/q,
/// q = 1 + y_x² + y_y². Defined for every y; n is a unit vector.
pub fn from_isotropic(y: DVec3) -> Dual {
    let r2 = y.x * y.x + y.y * y.y;
    let q = 1.0 + r2;
    Dual {
        n: DVec3::new(2.0 * y.x, 2.0 * y.y, r2 - 1.0) / q,
        h: 2.0 * y.z / q,
    }
}

/// The Jacobian db/dy of b = (n_x, n_y, n_z, h) with respect to y = (y_x, y_y, y_z), rows
/// n_x, n_y, n_z, h (seed 004 §4.3, corrected):
/// db/dy = 2/q² · [[1 − y_x² + y_y², −2y_x y_y, 0], [−2y_x y_y, 1 + y_x² − y_y², 0],
/// [2y_x, 2y_y, 0], [−2y_x y_z, −2y_y y_z, q]].
/// The seed prints 1 as the bottom-right entry; it must be q because h = 2y_z/q.
pub fn db_dy(y: DVec3) -> [[f64; 3]; 4] {
    let (a, b, c) = (y.x, y.y, y.z);
    let q = 1.0 + a * a + b * b;
    let k = 2.0 / (q * q);
    [
        [k * (1.0 - a * a + b * b), k * (-2.0 * a * b), 0.0],
        [k * (-2.0 * a * b), k * (1.0 + a * a - b * b), 0.0],
        [k * 2.0 * a, k * 2.0 * b, 0.0],
        [k * (-2.0 * a * c), k * (-2.0 * b * c), k * q],
    ]
}

/// Normal of the admissible plane of isotropic derivative vectors at a data point x whose
/// isotropic image is y (seed 004 §4.3): the seed's v = xᵀ dn/dy − dh/dy equals
/// (2/q)·(x_1 + y_x x_3, x_2 + y_y x_3, −1) wherever x·n = h; this returns the vector without the
/// positive factor 2/q. A derivative t is admissible iff v·t = 0, i.e.
/// t_z = (x_1 + y_x x_3) t_x + (x_2 + y_y x_3) t_y.
pub fn admissible_normal(x: DVec3, y: DVec3) -> DVec3 {
    DVec3::new(x.x + y.x * x.z, x.y + y.y * x.z, -1.0)
}

/// Pull-back to space, general form of seed 004 §4.2: x = h·n + N (NᵀN)⁻¹ ∇h, with
/// N = [n_u n_v] (3 × 2) and ∇h = (h_u, h_v). `None` where NᵀN is singular: when
/// sin∠(n_u, n_v) ≤ [`SINGULAR_SIN`] or a derivative vanishes (zero Gaussian curvature).
/// No assumption n_u ⟂ n_v is made.
pub fn point_from_dual(d: Dual, n_u: DVec3, n_v: DVec3, h_u: f64, h_v: f64) -> Option<DVec3> {
    let (g11, g12, g22) = (n_u.dot(n_u), n_u.dot(n_v), n_v.dot(n_v));
    let det = g11 * g22 - g12 * g12;
    let scale = g11 * g22;
    if scale.is_nan() || scale <= 0.0 || det.is_nan() || det <= SINGULAR_SIN * SINGULAR_SIN * scale
    {
        return None;
    }
    let r1 = (g22 * h_u - g12 * h_v) / det;
    let r2 = (g11 * h_v - g12 * h_u) / det;
    let x = d.n * d.h + n_u * r1 + n_v * r2;
    x.is_finite().then_some(x)
}

/// A global rotation of space applied before the isotropic map so that no normal is at (or near)
/// its pole (0, 0, 1). Points, normals and isotropic derivative vectors given to or returned by
/// the PN layer are in world coordinates except isotropic vectors, which are in this frame.
/// Grids that must join (share boundary data) must use the same frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsotropicFrame {
    /// World → frame rotation.
    rotation: DMat3,
}

impl Default for IsotropicFrame {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl IsotropicFrame {
    /// No rotation: the isotropic map of seed 004 §4.3 as printed.
    pub const IDENTITY: Self = Self {
        rotation: DMat3::IDENTITY,
    };

    /// A frame with the given world → frame rotation; errors unless it is a proper rotation
    /// (RᵀR = I and det R = 1 to 1e-9).
    pub fn from_rotation(rotation: DMat3) -> Result<Self, PnError> {
        let e = rotation.transpose() * rotation - DMat3::IDENTITY;
        let off = e.x_axis.length() + e.y_axis.length() + e.z_axis.length();
        if !rotation.is_finite() || off > 1e-9 || (rotation.determinant() - 1.0).abs() > 1e-9 {
            return Err(PnError::BadRotation);
        }
        Ok(Self { rotation })
    }

    /// Choose a frame for the given unit normals (rows may have any length; pass the normals of
    /// every grid that must join). Rule: the identity while every n_z ≤ [`AUTO_MAX_NZ`];
    /// otherwise the pole direction e (in world coordinates) is the candidate that minimizes
    /// max_k n_k·e over a fixed candidate set (±x, ±y, ±z and 512 Fibonacci-sphere directions,
    /// first minimum wins), and the frame is the shortest rotation taking e to (0, 0, 1).
    /// Deterministic. Errors with [`PnError::NoFrame`] when even the best e is within
    /// [`POLE_GAP`] of a normal, naming the closest normal.
    pub fn auto(normals: &[Vec<DVec3>]) -> Result<Self, PnError> {
        let all = || normals.iter().flat_map(|r| r.iter().copied());
        if all().all(|n| n.z <= AUTO_MAX_NZ) {
            return Ok(Self::IDENTITY);
        }
        let mut candidates = vec![
            DVec3::NEG_Z,
            DVec3::X,
            DVec3::NEG_X,
            DVec3::Y,
            DVec3::NEG_Y,
            DVec3::Z,
        ];
        let count = 512;
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        for k in 0..count {
            let z = 1.0 - (2.0 * k as f64 + 1.0) / count as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * k as f64;
            candidates.push(DVec3::new(r * phi.cos(), r * phi.sin(), z));
        }
        let worst = |e: DVec3| all().map(|n| n.dot(e)).fold(f64::NEG_INFINITY, f64::max);
        let mut best = (f64::INFINITY, DVec3::NEG_Z);
        for e in candidates {
            let w = worst(e);
            if w < best.0 {
                best = (w, e);
            }
        }
        if 1.0 - best.0 <= POLE_GAP {
            let (mut bi, mut bj, mut bd) = (0, 0, f64::NEG_INFINITY);
            for (i, row) in normals.iter().enumerate() {
                for (j, n) in row.iter().enumerate() {
                    if n.dot(best.1) > bd {
                        (bi, bj, bd) = (i, j, n.dot(best.1));
                    }
                }
            }
            return Err(PnError::NoFrame { i: bi, j: bj });
        }
        let q = DQuat::from_rotation_arc(best.1.normalize(), DVec3::Z);
        Ok(Self {
            rotation: DMat3::from_quat(q),
        })
    }

    /// The world → frame rotation R.
    pub fn rotation(&self) -> DMat3 {
        self.rotation
    }

    /// A world vector or point in frame coordinates: R·v.
    pub fn to_frame(&self, v: DVec3) -> DVec3 {
        self.rotation * v
    }

    /// A frame vector or point in world coordinates: Rᵀ·v.
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        self.rotation.transpose() * v
    }

    /// Isotropic image y of the world point x with world unit normal n (seed 004 §4.2–4.3):
    /// rotate, h = n·x, y = (n_x, n_y, h)/(1 − n_z). `None` at the pole.
    pub fn isotropic(&self, x: DVec3, n: DVec3) -> Option<DVec3> {
        to_isotropic(Dual::of(self.to_frame(x), self.to_frame(n)))
    }

    /// Isotropic derivative vector dy/ds of a surface at world point x with unit normal n, from
    /// the world derivative dn/ds of its unit normal along a parameter s. Uses h_s = x·n_s
    /// (x_s·n = 0, seed 004 §4.2) and, with the rotated n, n_s and s = 1 − n_z:
    /// dy/ds = (n_{x,s}, n_{y,s}, h_s)/s + (n_x, n_y, h)·n_{z,s}/s².
    /// The result is admissible (on the plane of [`admissible_normal`]) whenever x, n, n_s come
    /// from one smooth surface; this is how a caller sampling a surface with exact derivatives
    /// makes the derivative vectors of neighbouring grids agree. `None` at the pole.
    pub fn isotropic_tangent(&self, x: DVec3, n: DVec3, n_s: DVec3) -> Option<DVec3> {
        let (x, n, dn) = (self.to_frame(x), self.to_frame(n), self.to_frame(n_s));
        let s = 1.0 - n.z;
        if s <= POLE_GAP {
            return None;
        }
        let h = n.dot(x);
        let dh = dn.dot(x);
        Some(DVec3::new(dn.x, dn.y, dh) / s + DVec3::new(n.x, n.y, h) * (dn.z / (s * s)))
    }
}
