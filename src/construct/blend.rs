//! Direction blends for G1 twists (seed 000 §4.3–4.4, corrected: see docs/math.md#direction-blends).
//!
//! Along a boundary curve C(s) (cubic, tangent T(s) = C'(s), quadratic with Bernstein
//! coefficients t_j = 3(C_{j+1} − C_j)) shared by patches A and B, both ribbons' cross-derivatives
//! are written in A's parameter s as (seed 000 eq. 4.5)
//!
//! ```text
//!   X_A(s) = α_A(s) D(s) + β_A(s) T(s),     X_B(s) = α_B(s) D(s) + β_B(s) T(s)
//! ```
//!
//! with ONE direction blend D (quadratic) and linear scalars α, β (eq. 4.11–4.12). Then
//! det(T, X_A, X_B) = α_A α_B det(T, D, D) = 0 for every s: the tangent planes agree along the
//! whole curve (eq. 4.8). X = α D + β T is cubic; its Bernstein coefficients Q_j give the ribbon's
//! second row by P_{j,1} = P_{j,0} + Q_j / 3 (eq. 4.23).
//!
//! End values (eq. 4.7): D(0) = (X_A(0) − X_B(0)) / 2, D(1) = (X_A(1) − X_B(1)) / 2, where the
//! X(0), X(1) are fixed by the curve network (corner blocks). The scalars at the ends are the
//! unique solution of X = α D + β T in the node's tangent plane (eq. 4.13–4.15 is Cramer's rule for
//! the same 2×2 system; here it is solved by the normal equations, which are exact when X lies in
//! span(D, T) and a least-squares fit otherwise).
//!
//! The middle constraint D_{0.5} is a VECTOR (eq. 4.29 prints a position; docs/math.md#mid-constraint):
//! - [`BlendKind::Approx`] (eq. 4.16): D(u) = (1−u)² D0 + 2u(1−u) D_{0.5} + u² D1, i.e. D_{0.5} is
//!   the middle Bernstein coefficient (approximated, D(½) = (D0 + 2D_{0.5} + D1)/4).
//! - [`BlendKind::Interp`] (eq. 4.24): D(u) = (2u²−3u+1) D0 + 4u(1−u) D_{0.5} + (2u²−u) D1, i.e.
//!   D(½) = D_{0.5}; its middle Bernstein coefficient is 2 D_{0.5} − (D0 + D1)/2.
//!
//! (The printed eq. 4.19–4.22 and 4.25–4.28 mix up indices; the products below are the plain
//! Bernstein products of a linear and a quadratic polynomial.)

use glam::DVec3;

/// How the middle constraint D_{0.5} enters the quadratic direction blend.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum BlendKind {
    /// D_{0.5} is the middle Bernstein coefficient (seed 000 eq. 4.16).
    Approx,
    /// D(½) = D_{0.5} (seed 000 eq. 4.24).
    Interp,
}

/// k of the side rule (docs/math.md#blend-side): the middle Bernstein coefficient's component
/// across T(½) is raised to −k√(ab), which keeps D(u)·e ≥ ab(1 − k²)/(a + b + 2k√(ab)). k = 0
/// (raised to 0, D·e ≥ ab/(a + b)): k = ¼ and ½ were measured to raise max |H|·diag on the rook's
/// and car's topology structure (rook 1043 → 1475, 1993) and k = ¾ folds the rook's.
pub const SIDE_MARGIN: f64 = 0.0;

/// τ of the side rule's ramps (docs/math.md#blend-side): the full lift where
/// min(a, b)/(a + b) ≥ τ and |mean⊥| ≥ τ (|d_0| + |d_2|)/2, none as either tends to 0.
pub const SIDE_RAMP: f64 = 0.01;

/// A quadratic direction blend D(u) = Σ_j B²_j(u) d_j (Bernstein coefficients `d`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionBlend {
    pub d: [DVec3; 3],
}

impl DirectionBlend {
    /// The blend through D(0) = `d0`, D(1) = `d1` with middle constraint `mid` of the given kind.
    pub fn new(kind: BlendKind, d0: DVec3, mid: DVec3, d1: DVec3) -> Self {
        let m = match kind {
            BlendKind::Approx => mid,
            BlendKind::Interp => 2.0 * mid - 0.5 * (d0 + d1),
        };
        Self { d: [d0, m, d1] }
    }

    /// The blend kept on its side of the curve (docs/math.md#blend-side; not in the seeds, which
    /// take D0.5 as given, seed 000 eq. 4.16, 4.24). With T̂ the unit of `t` (the tangent T(½)), e
    /// the unit part of (d_0 + d_2)/2 orthogonal to T̂ and a = d_0·e, c = d_1·e, b = d_2·e: where
    /// a > 0, b > 0 and c < −k√(ab) ([`SIDE_MARGIN`] k = 0), d_1 is moved along e by
    /// w·(−k√(ab) − c), with the ramp w = r(min(a, b)/(a + b))·r(|mean⊥|/((|d_0| + |d_2|)/2)),
    /// r(x) = clamp(x/τ, 0, 1), τ = [`SIDE_RAMP`]. At w = 1, d_1·e becomes −k√(ab), so
    /// D(u)·e ≥ ab(1 − k²)/(a + b + 2k√(ab)) > 0: D does not swing across T(½) and turn the
    /// cross-derivatives X = αD + βT of both patches over. The move is continuous in d_0, d_1, d_2
    /// (w → 0 as a, b or |mean⊥| → 0); d_1's components along T̂ and T̂ × e stay. Elsewhere the
    /// blend is unchanged. One blend serves both patches, so G1 holds for any d_1.
    pub fn kept_on_side(mut self, t: DVec3) -> Self {
        let Some(t) = t.try_normalize() else { return self };
        let mean = 0.5 * (self.d[0] + self.d[2]);
        let across = mean - mean.dot(t) * t;
        let Some(e) = across.try_normalize() else { return self };
        let (a, c, b) = (self.d[0].dot(e), self.d[1].dot(e), self.d[2].dot(e));
        if !(a > 0.0 && b > 0.0) {
            return self;
        }
        let lift = -SIDE_MARGIN * (a * b).sqrt() - c;
        if lift > 0.0 {
            let ramp = |x: f64| (x / SIDE_RAMP).clamp(0.0, 1.0);
            let size = 0.5 * (self.d[0].length() + self.d[2].length());
            let w = ramp(a.min(b) / (a + b)) * ramp(across.length() / size);
            self.d[1] += w * lift * e;
        }
        self
    }

    /// D(u).
    pub fn eval(&self, u: f64) -> DVec3 {
        let v = 1.0 - u;
        v * v * self.d[0] + 2.0 * u * v * self.d[1] + u * u * self.d[2]
    }
}

/// Bernstein coefficients of the cubic (linear a) · (quadratic q):
/// c0 = a0 q0, c1 = (a1 q0 + 2 a0 q1)/3, c2 = (2 a1 q1 + a0 q2)/3, c3 = a1 q2.
pub fn linear_times_quadratic(a: [f64; 2], q: [DVec3; 3]) -> [DVec3; 4] {
    [
        a[0] * q[0],
        (a[1] * q[0] + 2.0 * a[0] * q[1]) / 3.0,
        (2.0 * a[1] * q[1] + a[0] * q[2]) / 3.0,
        a[1] * q[2],
    ]
}

/// Bernstein coefficients 3(C_{j+1} − C_j) of the (quadratic) derivative of a cubic.
pub fn hodograph(c: &[DVec3; 4]) -> [DVec3; 3] {
    [3.0 * (c[1] - c[0]), 3.0 * (c[2] - c[1]), 3.0 * (c[3] - c[2])]
}

/// Solves x ≈ α d + β t by the normal equations (exact when x ∈ span(d, t)).
/// Returns `None` when d and t are (nearly) parallel: |d × t| ≤ 1e-10 |d||t|.
pub fn decompose(x: DVec3, d: DVec3, t: DVec3) -> Option<(f64, f64)> {
    let dd = d.dot(d);
    let tt = t.dot(t);
    let dt = d.dot(t);
    let cross = d.cross(t).length_squared();
    if !(cross > 1e-20 * dd * tt) || dd == 0.0 || tt == 0.0 {
        return None;
    }
    let det = dd * tt - dt * dt;
    let xd = x.dot(d);
    let xt = x.dot(t);
    let alpha = (xd * tt - xt * dt) / det;
    let beta = (dd * xt - dt * xd) / det;
    Some((alpha, beta))
}

/// The Bernstein coefficients Q_0..Q_3 of X(s) = α(s) D(s) + β(s) T(s) for linear α, β (values
/// at s = 0 and 1), the blend `d` and the curve `c` (T = C'). The end coefficients are replaced by
/// the exact network values `x0`, `x1` (equal to α D + β T up to round-off when x lies in the
/// tangent plane), so the corner blocks are reproduced bit-exactly.
pub fn cross_derivative_coeffs(
    alpha: [f64; 2],
    beta: [f64; 2],
    blend: &DirectionBlend,
    c: &[DVec3; 4],
    x0: DVec3,
    x1: DVec3,
) -> [DVec3; 4] {
    let qa = linear_times_quadratic(alpha, blend.d);
    let qb = linear_times_quadratic(beta, hodograph(c));
    [x0, qa[1] + qb[1], qa[2] + qb[2], x1]
}


#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interp_blend_hits_mid_value() {
        let d0 = DVec3::new(1.0, 0.0, 0.0);
        let d1 = DVec3::new(0.0, 1.0, 0.0);
        let m = DVec3::new(0.3, 0.2, 0.5);
        let b = DirectionBlend::new(BlendKind::Interp, d0, m, d1);
        assert_near!(b.eval(0.0), d0);
        assert_near!(b.eval(1.0), d1);
        assert_near!(b.eval(0.5), m);
        let a = DirectionBlend::new(BlendKind::Approx, d0, m, d1);
        assert_near!(a.eval(0.5), 0.25 * d0 + 0.5 * m + 0.25 * d1);
    }

    /// min over u of D(u)·e, sampled on 1001 steps.
    fn min_across(b: &DirectionBlend, e: DVec3) -> f64 {
        (0..=1000).map(|k| b.eval(k as f64 / 1000.0).dot(e)).fold(f64::MAX, f64::min)
    }

    /// The side rule's margin ab(1 − k²)/(a + b + 2k√(ab)) for D·e (docs/math.md#blend-side).
    fn margin(a: f64, b: f64) -> f64 {
        let k = SIDE_MARGIN;
        a * b * (1.0 - k * k) / (a + b + 2.0 * k * (a * b).sqrt())
    }

    /// The rook dual's base curves (docs/math.md#blend-side): D(0) and D0.5 across the curve
    /// 0.00131, D(1) 0.0242. The interpolating quadratic through them dips below zero
    /// (D0.5 < (√D(0) − √D(1))²/4), so D swings through the tangent; kept on its side it does not,
    /// and it keeps D(0), D(1) and d_1's components along T̂ and T̂ × e. The move is exactly
    /// (−k√(ab) − c)·e (min(a, b)/(a + b) = 0.051 > τ: the full lift).
    #[test]
    fn a_blend_kept_on_its_side_does_not_swing_across_the_curve() {
        let (t, y, n) = (DVec3::X, DVec3::Y, DVec3::Z);
        let d0 = 0.00131 * y + 0.0004 * t;
        let d1 = 0.02415 * y - 0.003 * t + 0.001 * n;
        let mid = 0.00131 * y;
        let before = DirectionBlend::new(BlendKind::Interp, d0, mid, d1);
        let after = before.kept_on_side(2.0 * t);
        // e: the unit part of (d_0 + d_2)/2 orthogonal to T̂ = X.
        let mean = 0.5 * (d0 + d1);
        let e = (mean - mean.x * t).normalize();
        let (a, c, b) = (d0.dot(e), before.d[1].dot(e), d1.dot(e));
        assert!(min_across(&before, e) < 0.0, "{}", min_across(&before, e));
        assert_near!(after.d[1], before.d[1] + (-SIDE_MARGIN * (a * b).sqrt() - c) * e);
        assert!(min_across(&after, e) >= (1.0 - 1e-9) * margin(a, b), "{} {}", min_across(&after, e), margin(a, b));
        assert!(min_across(&after, e) < 1.01 * margin(a, b), "the margin is attained");
        assert_eq!((after.d[0], after.d[2]), (before.d[0], before.d[2]));
        assert_near!(after.d[1].dot(t), before.d[1].dot(t));
        assert_near!(after.d[1].dot(t.cross(e)), before.d[1].dot(t.cross(e)));
        // A blend already on its side, or one whose ends point to different sides, is unchanged.
        let ok = DirectionBlend::new(BlendKind::Interp, d0, 0.01 * y, d1);
        assert_eq!(ok.kept_on_side(t), ok);
        let twisted = DirectionBlend::new(BlendKind::Interp, d0, mid, -d1 + 0.1 * d0);
        assert_eq!(twisted.kept_on_side(t), twisted);
    }

    /// The approximating blend: d_1 is D0.5 itself, and it is moved the same way.
    #[test]
    fn an_approximating_blend_is_kept_on_its_side() {
        let (t, e) = (DVec3::X, DVec3::Y);
        let (d0, d1) = (0.5 * e + 0.2 * t, 2.0 * e - 0.3 * t);
        let before = DirectionBlend::new(BlendKind::Approx, d0, -1.5 * e + 0.4 * t, d1);
        assert!(min_across(&before, e) < 0.0);
        let after = before.kept_on_side(t);
        assert_near!(after.d[1], -SIDE_MARGIN * (0.5f64 * 2.0).sqrt() * e + 0.4 * t);
        assert!(min_across(&after, e) >= (1.0 - 1e-9) * margin(0.5, 2.0));
    }

    /// The rule acts wherever c < −k√(ab) (k = 0: c < 0), also on curves that do not swing:
    /// with a = b = 1 a curve with D(½)·e = 0.6 (c = 0.2) is left alone, one with D(½)·e = 0.2
    /// (c = −0.6, min D·e = 0.2) is raised to c = −k√(ab), D(½)·e = (2 − 2k)/4.
    #[test]
    fn the_side_rule_acts_below_the_margin_only() {
        let (t, e) = (DVec3::X, DVec3::Y);
        let (d0, d1) = (e + 0.5 * t, e - 0.5 * t);
        let fine = DirectionBlend::new(BlendKind::Interp, d0, 0.6 * e, d1);
        assert_near!(fine.d[1].dot(e), 0.2);
        assert_eq!(fine.kept_on_side(t), fine);
        let near = DirectionBlend::new(BlendKind::Interp, d0, 0.2 * e, d1);
        assert_near!(near.d[1].dot(e), -0.6);
        let lifted = near.kept_on_side(t);
        assert_near!(lifted.d[1].dot(e), -SIDE_MARGIN);
        assert_near!(lifted.eval(0.5).dot(e), (2.0 - 2.0 * SIDE_MARGIN) / 4.0);
    }

    /// The move is continuous where the rule switches on or off: sweeping a = d_0·e across 0 (the
    /// ramp min(a, b)/(a + b)) and (d_0 + d_2)/2 across T̂ (e flips; the ramp |mean⊥|), d_1 moves
    /// by O(step) between neighbouring steps. A rule without ramps jumps by |c| ≈ 1 there.
    #[test]
    fn the_side_rule_is_continuous_at_its_edges() {
        let (t, e) = (DVec3::X, DVec3::Y);
        let max_jump = |blend: &dyn Fn(f64) -> DirectionBlend| {
            let steps = 4000;
            let d1 = |k: usize| blend(-0.02 + 0.04 * k as f64 / steps as f64).kept_on_side(t).d[1];
            (1..=steps).map(|k| (d1(k) - d1(k - 1)).length()).fold(0.0, f64::max)
        };
        // a across 0 (b = 1, D0.5·e = −0.5: c ≈ −1.5 < −k√(ab) wherever a > 0).
        let sweep_a = |a: f64| DirectionBlend::new(BlendKind::Interp, a * e + 0.3 * t, -0.5 * e, e - 0.2 * t);
        assert!(sweep_a(0.02).kept_on_side(t) != sweep_a(0.02), "the rule acts at a = 0.02");
        assert!(max_jump(&sweep_a) < 1e-2, "{}", max_jump(&sweep_a));
        // mean⊥ across 0 (a = b = s; d_1 points the other way along T).
        let sweep_mean = |s: f64| DirectionBlend::new(BlendKind::Approx, s * e + t, -e - t + 0.5 * DVec3::Z, s * e - t);
        assert!(sweep_mean(0.02).kept_on_side(t) != sweep_mean(0.02), "the rule acts at s = 0.02");
        assert!(max_jump(&sweep_mean) < 1e-2, "{}", max_jump(&sweep_mean));
    }

    #[test]
    fn product_matches_pointwise() {
        let a = [0.7, -1.3];
        let q = [DVec3::new(1.0, 2.0, 3.0), DVec3::new(-1.0, 0.5, 2.0), DVec3::new(0.2, 0.1, -4.0)];
        let c = linear_times_quadratic(a, q);
        for k in 0..=10 {
            let s = k as f64 / 10.0;
            let lin = (1.0 - s) * a[0] + s * a[1];
            let quad = DirectionBlend { d: q }.eval(s);
            let b = crate::bezier::bernstein::bernstein_all(3, s);
            let cub: DVec3 = (0..4).map(|j| b[j] * c[j]).sum();
            assert_near!(cub, lin * quad);
        }
    }

    #[test]
    fn decompose_exact_in_plane() {
        let d = DVec3::new(1.0, 0.2, 0.0);
        let t = DVec3::new(0.3, 1.0, 0.0);
        let x = 2.5 * d - 0.75 * t;
        let (a, b) = decompose(x, d, t).unwrap();
        assert_near!(a, 2.5);
        assert_near!(b, -0.75);
        assert!(decompose(x, d, 3.0 * d).is_none());
    }
}
