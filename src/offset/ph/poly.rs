//! Small numerical helpers shared by the PH code: power-basis polynomials, their real roots on
//! an interval, Bernstein evaluation of fixed-size coefficient arrays, the exact arc-length
//! polynomial and its inverse.

use super::complex::Complex;
use super::error::PhError;
use crate::bezier::Point;

/// p(t) = Σ c_k t^k by Horner's rule.
pub(crate) fn eval(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &a| acc * t + a)
}

/// Coefficients of p′.
pub(crate) fn derivative(c: &[f64]) -> Vec<f64> {
    c.iter()
        .enumerate()
        .skip(1)
        .map(|(k, &a)| a * k as f64)
        .collect()
}

/// Product of two real power-basis polynomials.
pub(crate) fn mul(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; a.len() + b.len() - 1];
    for (i, &x) in a.iter().enumerate() {
        for (j, &y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

/// a·x + b·y for polynomials (the shorter one padded with zeros).
pub(crate) fn lin(a: f64, x: &[f64], b: f64, y: &[f64]) -> Vec<f64> {
    let n = x.len().max(y.len());
    (0..n)
        .map(|k| a * x.get(k).copied().unwrap_or(0.0) + b * y.get(k).copied().unwrap_or(0.0))
        .collect()
}

/// Product of two complex power-basis polynomials.
pub(crate) fn cmul(a: &[Complex], b: &[Complex]) -> Vec<Complex> {
    let mut out = vec![Complex::ZERO; a.len() + b.len() - 1];
    for (i, &x) in a.iter().enumerate() {
        for (j, &y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

/// All real roots of p in [a, b], ascending. Roots are isolated between consecutive roots of
/// p′ (found recursively), where p is monotone, and refined by bisection to full precision.
/// A critical point where |p| ≤ 1e-14·Σ|c_k|·max(1,|a|,|b|)^k counts as a (touching, double)
/// root. An identically zero polynomial has no isolated roots and returns none.
pub(crate) fn roots_in(c: &[f64], a: f64, b: f64) -> Vec<f64> {
    let mut c = c.to_vec();
    while c.last() == Some(&0.0) {
        c.pop();
    }
    if c.len() <= 1 {
        return Vec::new();
    }
    if c.len() == 2 {
        let r = -c[0] / c[1];
        return if r >= a && r <= b {
            vec![r]
        } else {
            Vec::new()
        };
    }
    let m = a.abs().max(b.abs()).max(1.0);
    let scale: f64 = c
        .iter()
        .enumerate()
        .map(|(k, x)| x.abs() * m.powi(k as i32))
        .sum();
    let touch = 1e-14 * scale;
    let crit: Vec<f64> = roots_in(&derivative(&c), a, b)
        .into_iter()
        .filter(|&x| x > a && x < b)
        .collect();
    let mut knots = Vec::with_capacity(crit.len() + 2);
    knots.push(a);
    knots.extend_from_slice(&crit);
    knots.push(b);
    let mut roots = Vec::new();
    for (idx, &x) in knots.iter().enumerate() {
        let f = eval(&c, x);
        let interior = idx > 0 && idx + 1 < knots.len();
        if f == 0.0 || (interior && f.abs() <= touch) {
            roots.push(x);
        }
    }
    for w in knots.windows(2) {
        let (mut lo, mut hi) = (w[0], w[1]);
        let (mut flo, fhi) = (eval(&c, lo), eval(&c, hi));
        if flo == 0.0 || fhi == 0.0 || (flo < 0.0) == (fhi < 0.0) {
            continue;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            let fm = eval(&c, mid);
            if fm == 0.0 {
                lo = mid;
                hi = mid;
                break;
            }
            if (fm < 0.0) == (flo < 0.0) {
                lo = mid;
                flo = fm;
            } else {
                hi = mid;
            }
        }
        roots.push(0.5 * (lo + hi));
    }
    roots.sort_by(f64::total_cmp);
    roots.dedup_by(|x, y| (*x - *y).abs() <= 1e-12);
    roots
}

/// De Casteljau evaluation of a fixed-size Bézier control array (seed 001 eq. 1.5), on the
/// stack: p^j_i = (1 − t) p^{j−1}_i + t p^{j−1}_{i+1}.
#[inline]
pub(crate) fn de_casteljau<P: Point, const N: usize>(mut b: [P; N], t: f64) -> P {
    let s = 1.0 - t;
    for j in 1..N {
        for i in 0..N - j {
            b[i] = b[i] * s + b[i + 1] * t;
        }
    }
    b[0]
}

/// Bernstein coefficients of the arc-length polynomial s(t) = ∫_0^t σ(u) du for a quartic
/// speed with Bernstein coefficients σ_0..σ_4: s_0 = 0, s_k = s_{k−1} + σ_{k−1}/5 (the
/// integral of a degree-n Bernstein form, seed 001 §1.5 read backwards).
pub(crate) fn arc_length_coeffs(sigma: &[f64; 5]) -> [f64; 6] {
    let mut s = [0.0; 6];
    for k in 1..6 {
        s[k] = s[k - 1] + sigma[k - 1] / 5.0;
    }
    s
}

/// The parameter t with s(t) = target for the increasing quintic s (Bernstein coefficients
/// `s`) with derivative σ (`sigma`): Newton steps t ← t − (s(t) − target)/σ(t), kept inside a
/// bracket [lo, hi] that always contains the root; a step that leaves the bracket, or a zero
/// speed, is replaced by bisection.
pub(crate) fn invert_arc_length(
    s: &[f64; 6],
    sigma: &[f64; 5],
    target: f64,
) -> Result<f64, PhError> {
    let length = s[5];
    if !target.is_finite() {
        return Err(PhError::NonFinite {
            arg: "s",
            index: None,
        });
    }
    if target < 0.0 || target > length {
        return Err(PhError::ArcLengthOutOfRange { s: target, length });
    }
    if target == 0.0 {
        return Ok(0.0);
    }
    if target == length {
        return Ok(1.0);
    }
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let mut t = target / length;
    let tol = 4.0 * f64::EPSILON * length;
    let mut f = 0.0;
    for _ in 0..200 {
        f = de_casteljau(*s, t) - target;
        if f.abs() <= tol {
            return Ok(t);
        }
        if f < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        if hi - lo <= f64::EPSILON * hi.max(1e-300) {
            return Ok(t);
        }
        let d = de_casteljau(*sigma, t);
        let newton = if d > 0.0 { t - f / d } else { f64::NAN };
        t = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
    }
    Err(PhError::NewtonNoConvergence {
        what: "arc-length parameter t(s)",
        iterations: 200,
        residual: f.abs(),
    })
}

/// ∫_0^1 f by [`crate::bezier::curve::integrate`] from 4 pieces to 1e-13 relative.
pub(crate) fn integrate(f: impl Fn(f64) -> f64) -> f64 {
    crate::bezier::curve::integrate(f, 4, 1e-13)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_of_a_product_are_found() {
        // (t − 0.2)(t − 0.5)(t − 0.9) = t³ − 1.6t² + 0.73t − 0.09
        let r = roots_in(&[-0.09, 0.73, -1.6, 1.0], 0.0, 1.0);
        assert_eq!(r.len(), 3);
        for (a, b) in r.iter().zip([0.2, 0.5, 0.9]) {
            assert!((a - b).abs() < 1e-14, "{a} vs {b}");
        }
        // (t − 0.3)² touches zero.
        let r = roots_in(&[0.09, -0.6, 1.0], 0.0, 1.0);
        assert_eq!(r.len(), 1);
        assert!((r[0] - 0.3).abs() < 1e-12);
        assert!(roots_in(&[1.0, 0.0, 1.0], 0.0, 1.0).is_empty());
    }
}
