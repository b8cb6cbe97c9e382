//! Domain, Wachspress coordinates and local parameters (seed 000 §2.5–2.6).

use gbsurf::assert_near;
use gbsurf::gb::{Domain, Jet2};
use gbsurf::DVec2;
use proptest::prelude::*;

/// A point inside the closed domain from barycentric-like numbers (convex combination of the
/// centre and two adjacent vertices).
fn domain_point(dom: &Domain, i: usize, a: f64, b: f64) -> DVec2 {
    let (a, b) = if a + b > 1.0 {
        (1.0 - a, 1.0 - b)
    } else {
        (a, b)
    };
    dom.vertex(i) * a + dom.vertex(i + 1) * b
}

fn fd_check(f: impl Fn(DVec2) -> Jet2, x: DVec2, tol1: f64, tol2: f64) {
    let e = 1e-5;
    let j = f(x);
    let fu = |dx: f64, dy: f64| f(x + DVec2::new(dx, dy)).val;
    assert_near!(j.du, (fu(e, 0.0) - fu(-e, 0.0)) / (2.0 * e), tol1);
    assert_near!(j.dv, (fu(0.0, e) - fu(0.0, -e)) / (2.0 * e), tol1);
    assert_near!(
        j.duu,
        (fu(e, 0.0) - 2.0 * j.val + fu(-e, 0.0)) / (e * e),
        tol2
    );
    assert_near!(
        j.dvv,
        (fu(0.0, e) - 2.0 * j.val + fu(0.0, -e)) / (e * e),
        tol2
    );
    assert_near!(
        j.duv,
        (fu(e, e) - fu(e, -e) - fu(-e, e) + fu(-e, -e)) / (4.0 * e * e),
        tol2
    );
}

#[test]
fn vertices_follow_the_conventions() {
    let sq = Domain::regular(4).unwrap();
    let expect = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)];
    for (v, e) in sq.vertices().iter().zip(expect) {
        assert_eq!(*v, DVec2::new(e.0, e.1));
    }
    for n in [3, 5, 6, 7, 8] {
        let d = Domain::regular(n).unwrap();
        for i in 0..n {
            let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            assert_near!(d.vertex(i), DVec2::new(a.cos(), a.sin()));
        }
        // side i runs from vertex i−1 to vertex i
        assert_near!(d.side_point(2, 0.0), d.vertex(1));
        assert_near!(d.side_point(2, 1.0), d.vertex(2));
    }
    assert!(Domain::regular(2).is_err());
    assert!(Domain::regular(0).is_err());
}

#[test]
fn wachspress_partition_reproduction_lagrange() {
    for n in 3..=9 {
        let dom = Domain::regular(n).unwrap();
        for i in 0..n {
            for &(a, b) in &[
                (0.2, 0.3),
                (0.5, 0.5),
                (1.0, 0.0),
                (0.0, 0.0),
                (0.7, 0.1),
                (0.0, 0.6),
            ] {
                let x = domain_point(&dom, i, a, b);
                let l = dom.wachspress(x);
                let sum: f64 = l.iter().map(|j| j.val).sum();
                assert_near!(sum, 1.0);
                let (su, sv): (f64, f64) =
                    (l.iter().map(|j| j.du).sum(), l.iter().map(|j| j.dv).sum());
                assert_near!(su, 0.0, 1e-11);
                assert_near!(sv, 0.0, 1e-11);
                let rep: DVec2 = l.iter().zip(dom.vertices()).map(|(j, v)| *v * j.val).sum();
                assert_near!(rep, x);
                assert!(l.iter().all(|j| j.val >= -1e-15 && j.is_finite()));
            }
            // Lagrange property
            let l = dom.wachspress(dom.vertex(i));
            for (m, j) in l.iter().enumerate() {
                assert_eq!(j.val, if m == i { 1.0 } else { 0.0 }, "n={n} i={i} m={m}");
            }
        }
    }
}

#[test]
fn local_parameters_on_sides() {
    for n in 3..=9 {
        let dom = Domain::regular(n).unwrap();
        for i in 0..n {
            for m in 0..=16 {
                let t = m as f64 / 16.0;
                let x = dom.side_point(i, t);
                let p = dom.local_params(x);
                // s_i is linear along side i, h_i = 0 there
                assert_near!(p[i].s.val, t);
                assert_near!(p[i].h.val, 0.0, 1e-15);
                // neighbours: s_{i+1} = 0 and h_{i+1} = 1−t; s_{i−1} = 1, h_{i−1} = t
                if t > 0.0 && t < 1.0 {
                    assert_near!(p[(i + 1) % n].s.val, 0.0);
                    assert_near!(p[(i + n - 1) % n].s.val, 1.0);
                }
                assert_near!(p[(i + 1) % n].h.val, 1.0 - t);
                assert_near!(p[(i + n - 1) % n].h.val, t);
                for (q, lp) in p.iter().enumerate() {
                    assert!(
                        lp.s.is_finite() && lp.h.is_finite(),
                        "n={n} i={i} t={t} q={q}"
                    );
                    assert!(lp.s.val >= -1e-12 && lp.s.val <= 1.0 + 1e-12);
                    let far = q != i && q != (i + 1) % n && q != (i + n - 1) % n;
                    if far {
                        assert_near!(lp.h.val, 1.0);
                    }
                }
            }
        }
    }
}

#[test]
fn far_side_s_is_the_continuous_limit() {
    // on far sides s_i is finite and equals the limit from the inside
    for n in 4..=8 {
        let dom = Domain::regular(n).unwrap();
        for i in 0..n {
            for q in 0..n {
                if q == i || q == (i + 1) % n || q == (i + n - 1) % n {
                    continue;
                }
                for &t in &[0.1, 0.5, 0.9] {
                    let x = dom.side_point(q, t);
                    let inside = x * (1.0 - 1e-9);
                    let a = dom.local_params(x)[i];
                    let b = dom.local_params(inside)[i];
                    assert_near!(a.s.val, b.s.val, 1e-7);
                    assert!(a.s.is_finite());
                }
            }
        }
    }
}

#[test]
fn square_parameters_are_bilinear() {
    let dom = Domain::regular(4).unwrap();
    let x = DVec2::new(0.3, -0.55);
    let p = dom.local_params(x);
    let (u, v) = ((1.0 + x.x) / 2.0, (1.0 + x.y) / 2.0);
    assert_near!(p[0].s.val, v);
    assert_near!(p[0].h.val, 1.0 - u);
    assert_near!(p[1].s.val, 1.0 - u);
    assert_near!(p[1].h.val, 1.0 - v);
    assert_near!(p[2].s.val, 1.0 - v);
    assert_near!(p[2].h.val, u);
    assert_near!(p[3].s.val, u);
    assert_near!(p[3].h.val, v);
}

#[test]
fn triangle_opposite_vertex_is_finite() {
    let dom = Domain::regular(3).unwrap();
    for v in 0..3 {
        let p = dom.local_params(dom.vertex(v));
        for lp in &p {
            assert!(lp.s.is_finite() && lp.h.is_finite());
        }
        // side v+2 is opposite to vertex v: h = 1 there
        assert_near!(p[(v + 2) % 3].h.val, 1.0);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn derivatives_match_finite_differences(n in 3usize..9, i in 0usize..9, a in 0.02f64..0.9, b in 0.02f64..0.9) {
        let dom = Domain::regular(n).unwrap();
        let x = domain_point(&dom, i % n, a * 0.95, b * 0.95);
        for q in 0..n {
            fd_check(|y| dom.wachspress(y)[q], x, 1e-7, 1e-4);
            fd_check(|y| dom.local_params(y)[q].h, x, 1e-7, 1e-4);
            // s is only well conditioned away from the triangle's opposite vertex
            if n > 3 || (x - dom.vertex(q + 1)).length() > 0.05 {
                fd_check(|y| dom.local_params(y)[q].s, x, 1e-6, 2e-3);
            }
        }
    }
}

/// Many-sided domains (a `.gbp` file may have up to 1024 sides): the (n−2)-fold Wachspress
/// products must neither underflow (they did, to 0/0 = NaN everywhere, for n ≳ 180 with
/// unscaled triangle areas) nor lose the corner values s_i(v_{i−1}) = 0, s_i(v_i) = 1.
#[test]
fn many_sided_domains_stay_finite_and_exact() {
    for n in [150usize, 200, 300, 1024] {
        let dom = Domain::regular(n).unwrap();
        let mut pts = vec![DVec2::ZERO];
        for i in (0..n).step_by(n / 7) {
            for (a, b) in [(0.3, 0.3), (0.9, 0.05), (0.5, 0.5), (0.0, 1.0), (0.999, 0.0)] {
                pts.push(domain_point(&dom, i, a, b));
            }
        }
        for x in &pts {
            let lam = dom.wachspress(*x);
            assert!(lam.iter().all(|l| l.is_finite()), "n={n} at {x}");
            assert_near!(lam.iter().map(|l| l.val).sum::<f64>(), 1.0, 1e-12);
            let lp = dom.local_params(*x);
            assert!(lp.iter().all(|p| p.s.is_finite() && p.h.is_finite()), "n={n} at {x}");
        }
        for i in (0..n).step_by(n / 5) {
            let lp0 = dom.local_params(dom.vertex(i + n - 1));
            let lp1 = dom.local_params(dom.vertex(i));
            assert_near!(lp0[i].s.val, 0.0, 1e-12);
            assert_near!(lp1[i].s.val, 1.0, 1e-12);
            let mid = dom.local_params(dom.side_point(i, 0.25));
            assert_near!(mid[i].s.val, 0.25, 1e-9);
            assert_near!(mid[i].h.val, 0.0, 1e-12);
        }
    }
}

/// The product form of seed 000 eq. 2.12 term by term, O(n²) per point: the reference of the
/// O(n) prefix/suffix evaluation.
fn wachspress_product_form(dom: &Domain, x: DVec2) -> Vec<Jet2> {
    let n = dom.n();
    let v = |i: usize| dom.vertex(i % n);
    let area = |a: DVec2, b: DVec2, c: DVec2| 0.5 * (b - a).perp_dot(c - a);
    // D_j(x) = A(x, v_{j−1}, v_j), affine in x
    let d: Vec<Jet2> = (0..n)
        .map(|j| {
            let (a, b) = (v(j + n - 1), v(j));
            let e = b - a;
            Jet2::affine(area(x, a, b), -0.5 * e.y, 0.5 * e.x)
        })
        .collect();
    let w: Vec<Jet2> = (0..n)
        .map(|i| {
            let mut w = Jet2::constant(area(v(i + n - 1), v(i), v(i + 1)));
            for m in 2..n {
                w = w * d[(i + m) % n];
            }
            w
        })
        .collect();
    let sum = w.iter().fold(Jet2::ZERO, |a, &b| a + b);
    w.into_iter().map(|wi| wi / sum).collect()
}

fn assert_jets_near(a: &Jet2, b: &Jet2, tol: f64, what: &str) {
    for (p, q) in [(a.val, b.val), (a.du, b.du), (a.dv, b.dv), (a.duu, b.duu), (a.duv, b.duv), (a.dvv, b.dvv)] {
        assert!((p - q).abs() <= tol * (1.0 + q.abs()), "{what}: {a:?} vs {b:?}");
    }
}

proptest! {
    /// The O(n) prefix/suffix Wachspress coordinates equal the product form to rounding, with
    /// derivatives, inside and on the boundary (n = 3..12), and they keep its exact zeros.
    #[test]
    fn wachspress_prefix_suffix_matches_product_form(
        n in 3usize..=12,
        side in 0usize..12,
        a in 0.0f64..=1.0,
        b in 0.0f64..=1.0,
        on_boundary in proptest::bool::ANY,
    ) {
        let dom = Domain::regular(n).unwrap();
        let i = side % n;
        let x = if on_boundary { dom.side_point(i, a) } else { domain_point(&dom, i, a, b) };
        let fast = dom.wachspress(x);
        let slow = wachspress_product_form(&dom, x);
        for (j, (f, s)) in fast.iter().zip(&slow).enumerate() {
            assert_jets_near(f, s, 1e-12, &format!("n={n} λ_{j} at {x:?}"));
            if s.val == 0.0 {
                prop_assert_eq!(f.val, 0.0, "n={} λ_{} at {:?}", n, j, x);
            }
        }
        // h_i = Σ_{j∉{i−1,i}} λ_j from prefix and suffix sums: the same sum to rounding, and
        // exactly 0 on side i.
        let lp = dom.local_params(x);
        for q in 0..n {
            let h = (1..n - 1).fold(Jet2::ZERO, |acc, m| acc + slow[(q + m) % n]);
            assert_jets_near(&lp[q].h, &h, 1e-12, &format!("n={n} h_{q} at {x:?}"));
        }
        // Exactly on side i (D_i = 0 in floating point: the rounded side point need not be),
        // h_i is exactly 0.
        if (0..n).all(|j| j == i || (j + 1) % n == i || slow[j].val == 0.0) {
            prop_assert_eq!(lp[i].h.val, 0.0);
        }
    }
}

/// Many sides: the partial products of n/2 side areas reach e^{±0.24 n}, beyond the range of
/// f64 for n ≳ 3000, and near the boundary the numerators themselves underflow (Π_j D_j ≈ 2^−n,
/// 0/0 in the plain product form for n = 5000); the exponent-carrying prefix and suffix products
/// and the common exponent keep every coordinate finite, a partition of unity and Lagrange at
/// the vertices. (The rounded side points may lie outside by rounding, where λ is slightly
/// negative with large derivatives: hence −1e-9.)
#[test]
fn wachspress_many_sides_stays_finite() {
    for n in [1024usize, 5000] {
        let dom = Domain::regular(n).unwrap();
        for x in [
            DVec2::ZERO,
            dom.side_point(7, 0.3),
            dom.side_point(n / 2, 0.5) * 0.999,
            dom.vertex(3) * 0.9999,
            dom.vertex(11),
        ] {
            let l = dom.wachspress(x);
            assert!(l.iter().all(|j| j.is_finite() && j.val >= -1e-9), "n={n} at {x:?}");
            let sum: f64 = l.iter().map(|j| j.val).sum();
            assert_near!(sum, 1.0, 1e-12);
            let p = dom.local_params(x);
            assert!(p.iter().all(|q| q.h.is_finite() && q.s.is_finite()), "n={n} at {x:?}");
        }
        // At vertex 11 (where D_11 and D_12 are exactly 0) λ is exactly δ_{11,j} and
        // h_11 = h_12 = 0 exactly.
        let at = dom.wachspress(dom.vertex(11));
        for (j, l) in at.iter().enumerate() {
            assert_eq!(l.val, if j == 11 { 1.0 } else { 0.0 }, "n={n} λ_{j} at vertex 11");
        }
        let p = dom.local_params(dom.vertex(11));
        assert_eq!((p[11].h.val, p[12].h.val), (0.0, 0.0));
    }
}
