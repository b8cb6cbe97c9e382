//! Bernstein polynomials B^n_i(t) = C(n,i) t^i (1−t)^(n−i) (seed 001 §1.2).

/// Binomial coefficient C(n, k) as f64 (exact for the degrees used here, n ≤ 60).
pub fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    let mut c = 1.0;
    for i in 0..k {
        c = c * (n - i) as f64 / (i + 1) as f64;
    }
    c.round()
}

/// B^n_i(t); zero outside 0 ≤ i ≤ n.
pub fn bernstein(n: usize, i: usize, t: f64) -> f64 {
    if i > n {
        return 0.0;
    }
    binomial(n, i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

/// All B^n_0(t) … B^n_n(t) into `out` (length n + 1), by the triangular recurrence
/// B^n_i = (1−t) B^{n−1}_i + t B^{n−1}_{i−1}: stable, no powers, sums to 1 to round-off.
pub fn bernstein_all_into(n: usize, t: f64, out: &mut [f64]) {
    assert!(
        out.len() > n,
        "bernstein_all_into: output shorter than n + 1"
    );
    let s = 1.0 - t;
    out[0] = 1.0;
    for k in 1..=n {
        let mut saved = 0.0;
        for i in 0..k {
            let tmp = out[i];
            out[i] = saved + s * tmp;
            saved = t * tmp;
        }
        out[k] = saved;
    }
}

/// All B^n_i(t), i = 0..=n.
pub fn bernstein_all(n: usize, t: f64) -> Vec<f64> {
    let mut out = vec![0.0; n + 1];
    bernstein_all_into(n, t, &mut out);
    out
}

/// Values and first and second derivatives of all B^n_i at t:
/// d/dt B^n_i = n (B^{n−1}_{i−1} − B^{n−1}_i), d²/dt² B^n_i = n(n−1)(B^{n−2}_{i−2} − 2B^{n−2}_{i−1} + B^{n−2}_i).
/// Returns (values, first derivatives, second derivatives), each of length n + 1.
pub fn bernstein_all_d2(n: usize, t: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let b = bernstein_all(n, t);
    let mut d1 = vec![0.0; n + 1];
    let mut d2 = vec![0.0; n + 1];
    if n >= 1 {
        let b1 = bernstein_all(n - 1, t);
        let nf = n as f64;
        for i in 0..=n {
            let a = if i >= 1 { b1[i - 1] } else { 0.0 };
            let c = if i < n { b1[i] } else { 0.0 };
            d1[i] = nf * (a - c);
        }
    }
    if n >= 2 {
        let b2 = bernstein_all(n - 2, t);
        let f = (n * (n - 1)) as f64;
        let get = |j: isize| -> f64 {
            if j >= 0 && (j as usize) <= n - 2 {
                b2[j as usize]
            } else {
                0.0
            }
        };
        for i in 0..=n {
            let i = i as isize;
            d2[i as usize] = f * (get(i - 2) - 2.0 * get(i - 1) + get(i));
        }
    }
    (b, d1, d2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_of_unity_and_closed_form() {
        for n in 0..12 {
            for &t in &[0.0, 0.1, 0.5, 0.77, 1.0] {
                let all = bernstein_all(n, t);
                assert_near!(all.iter().sum::<f64>(), 1.0);
                for i in 0..=n {
                    assert_near!(all[i], bernstein(n, i, t));
                }
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-5;
        for n in 0..9 {
            let t = 0.37;
            let (_, d1, d2) = bernstein_all_d2(n, t);
            let p = bernstein_all(n, t + h);
            let m = bernstein_all(n, t - h);
            let c = bernstein_all(n, t);
            for i in 0..=n {
                assert_near!(d1[i], (p[i] - m[i]) / (2.0 * h), 1e-8);
                assert_near!(d2[i], (p[i] - 2.0 * c[i] + m[i]) / (h * h), 1e-4);
            }
        }
    }

    #[test]
    fn binomials() {
        assert_eq!(binomial(5, 2), 10.0);
        assert_eq!(binomial(10, 0), 1.0);
        assert_eq!(binomial(3, 4), 0.0);
    }
}
