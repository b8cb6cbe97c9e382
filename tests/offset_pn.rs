//! PN surfaces (seed 004 §4): isotropic map, Coons patches, pull-back, offsets, rational export,
//! typed errors. Exact-formula checks plus property tests.

use gbsurf::assert_near;
use gbsurf::bezier::angle_between;
use gbsurf::offset::pn::coons::{hermite, hermite_d};
use gbsurf::offset::pn::isotropic::{
    admissible_normal, db_dy, from_isotropic, point_from_dual, to_isotropic,
};
use gbsurf::offset::pn::{
    estimate_derivatives, CoonsPatch, Dual, FrameChoice, IsotropicFrame, PnError, PnGrid,
    PnOptions, PnSurface, Projection, TangentEstimate,
};
use gbsurf::DVec3;
use glam::DMat3;
use proptest::prelude::*;

type Grid = Vec<Vec<DVec3>>;

fn binom(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64)
}

// ---------------------------------------------------------------- test surfaces

/// A graph z = f(x, y) with f, gradient and Hessian.
#[derive(Clone, Copy)]
struct Graph {
    f: fn(f64, f64) -> f64,
    grad: fn(f64, f64) -> (f64, f64),
    hess: fn(f64, f64) -> (f64, f64, f64),
    /// +1: normal (−f_x, −f_y, 1) (upwards, near the pole); −1: (f_x, f_y, −1) (downwards).
    up: f64,
}

const CONVEX: Graph = Graph {
    f: |x, y| 0.5 * x * x + y * y + 0.1 * x * x * x + 0.05 * x * y,
    grad: |x, y| (x + 0.3 * x * x + 0.05 * y, 2.0 * y + 0.05 * x),
    hess: |x, _| (1.0 + 0.6 * x, 0.05, 2.0),
    up: -1.0,
};

const SADDLE: Graph = Graph {
    f: |x, y| 0.4 * x * x - 0.3 * y * y + 0.1 * x * y * y,
    grad: |x, y| (0.8 * x + 0.1 * y * y, -0.6 * y + 0.2 * x * y),
    hess: |x, y| (0.8, 0.2 * y, -0.6 + 0.2 * x),
    up: -1.0,
};

impl Graph {
    fn upward(self) -> Self {
        Self { up: 1.0, ..self }
    }
    fn point(&self, x: f64, y: f64) -> DVec3 {
        DVec3::new(x, y, (self.f)(x, y))
    }
    fn g(&self, x: f64, y: f64) -> DVec3 {
        let (fx, fy) = (self.grad)(x, y);
        DVec3::new(-fx, -fy, 1.0) * self.up
    }
    fn normal(&self, x: f64, y: f64) -> DVec3 {
        self.g(x, y).normalize()
    }
    /// Exact derivatives of the unit normal along x and y.
    fn normal_derivs(&self, x: f64, y: f64) -> (DVec3, DVec3) {
        let g = self.g(x, y);
        let (l, n) = (g.length(), g.normalize());
        let (fxx, fxy, fyy) = (self.hess)(x, y);
        let gx = DVec3::new(-fxx, -fxy, 0.0) * self.up;
        let gy = DVec3::new(-fxy, -fyy, 0.0) * self.up;
        let d = |gs: DVec3| (gs - n * n.dot(gs)) / l;
        (d(gx), d(gy))
    }
    /// Grid point [i][j] at (x0 + i·hx, y0 + j·hy).
    fn xy(i: usize, j: usize, o: (f64, f64, f64, f64)) -> (f64, f64) {
        (o.0 + i as f64 * o.2, o.1 + j as f64 * o.3)
    }
    fn grid(&self, m: usize, n: usize, o: (f64, f64, f64, f64)) -> (Grid, Grid) {
        let at = |f: &dyn Fn(f64, f64) -> DVec3| -> Grid {
            (0..m)
                .map(|i| {
                    (0..n)
                        .map(|j| {
                            let (x, y) = Self::xy(i, j, o);
                            f(x, y)
                        })
                        .collect()
                })
                .collect()
        };
        (at(&|x, y| self.point(x, y)), at(&|x, y| self.normal(x, y)))
    }
    /// Exact isotropic derivative vectors per grid step in `frame`.
    fn exact_derivs(
        &self,
        m: usize,
        n: usize,
        o: (f64, f64, f64, f64),
        frame: &IsotropicFrame,
    ) -> (Grid, Grid) {
        let mut du = vec![vec![DVec3::ZERO; n]; m];
        let mut dv = du.clone();
        for i in 0..m {
            for j in 0..n {
                let (x, y) = Self::xy(i, j, o);
                let (p, nn) = (self.point(x, y), self.normal(x, y));
                let (nx, ny) = self.normal_derivs(x, y);
                du[i][j] = frame.isotropic_tangent(p, nn, nx * o.2).unwrap();
                dv[i][j] = frame.isotropic_tangent(p, nn, ny * o.3).unwrap();
            }
        }
        (du, dv)
    }
}

/// Grid on a sphere (centre c, radius r, outward normals), uniform in the isotropic (y_x, y_y)
/// of the identity frame: n = inverse stereographic image of (a0 + i·h, b0 + j·h).
fn sphere_grid(
    c: DVec3,
    r: f64,
    m: usize,
    n: usize,
    a0: f64,
    b0: f64,
    h: f64,
) -> (Grid, Grid, Grid, Grid) {
    let nrm = |a: f64, b: f64| from_isotropic(DVec3::new(a, b, 0.0)).n;
    let (mut pts, mut nrms, mut du, mut dv) = (vec![], vec![], vec![], vec![]);
    for i in 0..m {
        let (mut p, mut nn, mut gu, mut gv) = (vec![], vec![], vec![], vec![]);
        for j in 0..n {
            let (a, b) = (a0 + i as f64 * h, b0 + j as f64 * h);
            let nv = nrm(a, b);
            let x = c + nv * r;
            // Exact dn/da, dn/db from the corrected db/dy (first two columns).
            let d = db_dy(DVec3::new(a, b, 0.0));
            let na = DVec3::new(d[0][0], d[1][0], d[2][0]) * h;
            let nb = DVec3::new(d[0][1], d[1][1], d[2][1]) * h;
            let f = IsotropicFrame::IDENTITY;
            p.push(x);
            nn.push(nv);
            gu.push(f.isotropic_tangent(x, nv, na).unwrap());
            gv.push(f.isotropic_tangent(x, nv, nb).unwrap());
        }
        pts.push(p);
        nrms.push(nn);
        du.push(gu);
        dv.push(gv);
    }
    (pts, nrms, du, dv)
}

fn interp(pts: &Grid, nrms: &Grid, opts: PnOptions) -> PnSurface {
    PnSurface::interpolate(&PnGrid::new(pts, nrms).unwrap(), &opts).unwrap()
}

fn options(frame: FrameChoice, tangents: TangentEstimate, projection: Projection) -> PnOptions {
    PnOptions {
        frame,
        tangents,
        projection,
    }
}

const O1: (f64, f64, f64, f64) = (-0.6, -0.5, 0.3, 0.25);

/// A set of test surfaces: (name, surface).
fn surfaces() -> Vec<(String, PnSurface)> {
    let mut out = vec![];
    let all_opts = [
        options(
            FrameChoice::Auto,
            TangentEstimate::Bessel,
            Projection::Isotropic,
        ),
        options(
            FrameChoice::Auto,
            TangentEstimate::SeedDifferences,
            Projection::Orthogonal,
        ),
    ];
    for (k, opts) in all_opts.iter().enumerate() {
        for (name, g, m, n) in [
            ("convex", CONVEX, 5, 5),
            ("convex-up", CONVEX.upward(), 5, 4),
            ("saddle", SADDLE, 4, 6),
            ("saddle-up", SADDLE.upward(), 3, 5),
        ] {
            let (p, nn) = g.grid(m, n, O1);
            out.push((format!("{name} {m}x{n} opts{k}"), interp(&p, &nn, *opts)));
        }
    }
    out
}

/// Dense interior samples of each patch (including near the edges, not on them).
fn samples(k: usize) -> Vec<(f64, f64)> {
    let mut v = vec![];
    for a in 0..k {
        for b in 0..k {
            v.push(((a as f64 + 0.5) / k as f64, (b as f64 + 0.5) / k as f64));
        }
    }
    v
}

// ---------------------------------------------------------------- isotropic map

#[test]
fn isotropic_map_exact_values() {
    // n = (0, 0, −1) (the "south pole") maps to y_xy = 0; h = 2 maps to y_z = 1.
    let y = to_isotropic(Dual {
        n: DVec3::NEG_Z,
        h: 2.0,
    })
    .unwrap();
    assert_near!(y, DVec3::new(0.0, 0.0, 1.0));
    // The equator: n = (1, 0, 0) ↦ (1, 0, h); q = 2.
    let y = to_isotropic(Dual {
        n: DVec3::X,
        h: 0.5,
    })
    .unwrap();
    assert_near!(y, DVec3::new(1.0, 0.0, 0.5));
    let d = from_isotropic(DVec3::new(1.0, 0.0, 0.5));
    assert_near!(d.n, DVec3::X);
    assert_near!(d.h, 0.5);
    // At the pole the map is undefined.
    assert!(to_isotropic(Dual {
        n: DVec3::Z,
        h: 1.0
    })
    .is_none());
}

proptest! {
    #[test]
    fn isotropic_inverse_roundtrip(a in -3.0..3.0f64, b in -3.0..3.0f64, c in -5.0..5.0f64) {
        let y = DVec3::new(a, b, c);
        let d = from_isotropic(y);
        prop_assert!((d.n.length() - 1.0).abs() < 1e-14);
        let back = to_isotropic(d).unwrap();
        prop_assert!((back - y).length() < 1e-12 * (1.0 + y.length_squared()));
    }

    #[test]
    fn isotropic_forward_roundtrip(th in 0.05..3.1f64, ph in 0.0..std::f64::consts::TAU, h in -4.0..4.0f64) {
        let n = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), -th.cos());
        let y = to_isotropic(Dual { n, h }).unwrap();
        let d = from_isotropic(y);
        prop_assert!((d.n - n).length() < 1e-12);
        prop_assert!((d.h - h).abs() < 1e-12 * (1.0 + h.abs()));
    }

    /// db/dy against central differences of the inverse map; in particular ∂h/∂y_z = 2/q
    /// (the seed prints an entry that gives 2/q²).
    #[test]
    fn db_dy_matches_finite_differences(a in -2.0..2.0f64, b in -2.0..2.0f64, c in -2.0..2.0f64) {
        let y = DVec3::new(a, b, c);
        let m = db_dy(y);
        let e = 1e-6;
        for col in 0..3 {
            let mut dy = DVec3::ZERO;
            dy[col] = e;
            let (p, q) = (from_isotropic(y + dy), from_isotropic(y - dy));
            let fd = [(p.n.x - q.n.x), (p.n.y - q.n.y), (p.n.z - q.n.z), (p.h - q.h)];
            for row in 0..4 {
                prop_assert!((fd[row] / (2.0 * e) - m[row][col]).abs() < 1e-7, "row {} col {}", row, col);
            }
        }
        let q = 1.0 + a * a + b * b;
        prop_assert!((m[3][2] - 2.0 / q).abs() < 1e-15);
    }

    /// The admissible-plane normal (x_1 + y_x x_3, x_2 + y_y x_3, −1) is parallel to the seed's
    /// v = xᵀ dn/dy − dh/dy at a data point (x·n = h).
    #[test]
    fn admissible_normal_is_seed_v(a in -2.0..2.0f64, b in -2.0..2.0f64,
                                   t1 in -3.0..3.0f64, t2 in -3.0..3.0f64, h in -3.0..3.0f64) {
        let d = from_isotropic(DVec3::new(a, b, 0.0));
        let n = d.n;
        // A point on the plane n·x = h.
        let e1 = n.any_orthonormal_vector();
        let e2 = n.cross(e1);
        let x = n * h + e1 * t1 + e2 * t2;
        let y = to_isotropic(Dual { n, h }).unwrap();
        let m = db_dy(y);
        let seed_v = DVec3::new(
            (0..3).map(|r| x[r] * m[r][0]).sum::<f64>() - m[3][0],
            (0..3).map(|r| x[r] * m[r][1]).sum::<f64>() - m[3][1],
            (0..3).map(|r| x[r] * m[r][2]).sum::<f64>() - m[3][2],
        );
        let v = admissible_normal(x, y);
        let q = 1.0 + y.x * y.x + y.y * y.y;
        prop_assert!((seed_v - v * (2.0 / q)).length() < 1e-10 * (1.0 + v.length()));
    }
}

#[test]
fn pull_back_without_orthogonality() {
    // A plane family with n_u not ⟂ n_v: the general formula recovers the point exactly; the
    // shortcut that assumes n_u ⟂ n_v does not.
    let x = DVec3::new(0.3, -0.2, 0.7);
    let n = DVec3::new(0.2, 0.1, -1.0).normalize();
    let n_u = n.any_orthonormal_vector() * 0.8;
    let n_v = (n.cross(n_u).normalize() + n_u * 0.9) * 0.6;
    let d = Dual::of(x, n);
    let got = point_from_dual(d, n_u, n_v, x.dot(n_u), x.dot(n_v)).unwrap();
    assert_near!(got, x);
    let shortcut = n * d.h
        + n_u * (x.dot(n_u) / n_u.length_squared())
        + n_v * (x.dot(n_v) / n_v.length_squared());
    assert!((shortcut - x).length() > 0.05);
    // Parallel derivatives: singular, reported as None, never NaN.
    assert!(point_from_dual(d, n_u, n_u * 2.0, 0.1, 0.2).is_none());
    assert!(point_from_dual(d, DVec3::ZERO, n_v, 0.1, 0.2).is_none());
}

// ---------------------------------------------------------------- Hermite / Coons

#[test]
fn hermite_basis_end_conditions() {
    // (F0, G0, F1, G1): values (1,0,0,0) at 0, (0,0,1,0) at 1; derivatives (0,1,0,0), (0,0,0,1).
    assert_eq!(hermite(0.0), [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(hermite(1.0), [0.0, 0.0, 1.0, 0.0]);
    assert_eq!(hermite_d(0.0), [0.0, 1.0, 0.0, 0.0]);
    assert_eq!(hermite_d(1.0), [0.0, 0.0, 0.0, 1.0]);
    // Exact values at t = 1/2: F0 = F1 = 1/2, G0 = 1/8, G1 = −1/8.
    assert_eq!(hermite(0.5), [0.5, 0.125, 0.5, -0.125]);
}

fn v3() -> impl Strategy<Value = DVec3> {
    (-2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64).prop_map(|(a, b, c)| DVec3::new(a, b, c))
}

proptest! {
    /// The Hermite form equals its bicubic Bézier form, interpolates the corner data, and has
    /// zero twist at the corners.
    #[test]
    fn coons_patch_forms_agree(v in proptest::collection::vec(v3(), 12), u in 0.0..1.0f64, w in 0.0..1.0f64) {
        let g = |k: usize| [[v[k], v[k + 1]], [v[k + 2], v[k + 3]]];
        let p = CoonsPatch { a: g(0), du: g(4), dv: g(8) };
        let b = p.to_bezier().unwrap();
        prop_assert!((b.eval(u, w) - p.eval(u, w)).length() < 1e-13);
        let s = b.partials(u, w);
        let q = p.partials(u, w);
        prop_assert!((s.u - q.y_u).length() < 1e-12 && (s.v - q.y_v).length() < 1e-12);
        for k in 0..2 {
            for l in 0..2 {
                let c = p.partials(k as f64, l as f64);
                prop_assert!((c.y - p.a[k][l]).length() < 1e-14);
                prop_assert!((c.y_u - p.du[k][l]).length() < 1e-14);
                prop_assert!((c.y_v - p.dv[k][l]).length() < 1e-14);
                prop_assert!(b.partials(k as f64, l as f64).uv.length() < 1e-12);
            }
        }
    }
}

// ---------------------------------------------------------------- interpolation

#[test]
fn data_points_and_normals_are_interpolated() {
    for (g, m, n) in [
        (CONVEX, 5, 5),
        (CONVEX.upward(), 4, 6),
        (SADDLE, 6, 3),
        (SADDLE.upward(), 3, 3),
    ] {
        let (p, nn) = g.grid(m, n, O1);
        for opts in [
            options(
                FrameChoice::Auto,
                TangentEstimate::Bessel,
                Projection::Isotropic,
            ),
            options(
                FrameChoice::Auto,
                TangentEstimate::SeedDifferences,
                Projection::Orthogonal,
            ),
            options(
                FrameChoice::Auto,
                TangentEstimate::Bessel,
                Projection::Orthogonal,
            ),
        ] {
            let s = interp(&p, &nn, opts);
            for i in 0..m {
                for j in 0..n {
                    // Every patch that has this grid point as a corner.
                    for (pi, u) in [(i.wrapping_sub(1), 1.0), (i, 0.0)] {
                        for (pj, v) in [(j.wrapping_sub(1), 1.0), (j, 0.0)] {
                            if pi < m - 1 && pj < n - 1 {
                                let e = s.eval(pi, pj, u, v).unwrap();
                                assert_near!(
                                    e.point,
                                    p[i][j],
                                    1e-12,
                                    "point [{i}][{j}] patch [{pi}][{pj}]"
                                );
                                assert_near!(e.normal, nn[i][j], 1e-12, "normal [{i}][{j}]");
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The test that catches the seed's derivative matrix: n·x_u = n·x_v = 0 inside every patch,
/// with x_u, x_v from the exact rational form (quotient rule), relative to |x_u|, |x_v|.
#[test]
fn normal_is_perpendicular_to_the_surface_inside_every_patch() {
    for (name, s) in surfaces() {
        let (pr, pc) = s.patch_count();
        let mut worst: f64 = 0.0;
        for i in 0..pr {
            for j in 0..pc {
                let r = s.rational(i, j).unwrap();
                for (u, v) in samples(9) {
                    let e = s.eval(i, j, u, v).unwrap();
                    let (x, xu, xv) = r.partials(u, v).unwrap();
                    // The rational form agrees with the pull-back formula.
                    assert_near!(
                        x,
                        e.point,
                        1e-10 * (1.0 + x.length()),
                        "{name} [{i}][{j}] ({u},{v})"
                    );
                    worst = worst.max(e.normal.dot(xu).abs() / xu.length());
                    worst = worst.max(e.normal.dot(xv).abs() / xv.length());
                }
            }
        }
        assert!(worst < 1e-9, "{name}: max |n·x_s|/|x_s| = {worst:e}");
    }
}

/// What the seed's printed matrix (bottom-right entry 1 instead of q) and the orthogonal-shortcut
/// pull-back do on the same patches: still exact at the corners, but n is not the surface normal
/// inside. Shows the test above can fail.
#[test]
fn seed_printed_matrix_and_shortcut_fail_inside() {
    let (p, nn) = CONVEX.grid(4, 4, O1);
    let s = interp(&p, &nn, PnOptions::default());
    let frame = s.frame();
    // x(u, v) by one of the wrong variants, in world coordinates.
    let wrong = |patch: &CoonsPatch, u: f64, v: f64, variant: u8| -> (DVec3, DVec3) {
        let q = patch.partials(u, v);
        let d = from_isotropic(q.y);
        let mut m = db_dy(q.y);
        if variant == 0 {
            let qq = 1.0 + q.y.x * q.y.x + q.y.y * q.y.y;
            m[3][2] /= qq; // the printed entry 1 in place of q
        }
        let row = |r: usize, t: DVec3| m[r][0] * t.x + m[r][1] * t.y + m[r][2] * t.z;
        let ns = |t: DVec3| DVec3::new(row(0, t), row(1, t), row(2, t));
        let (nu, nv, hu, hv) = (ns(q.y_u), ns(q.y_v), row(3, q.y_u), row(3, q.y_v));
        let x = if variant == 0 {
            point_from_dual(d, nu, nv, hu, hv).unwrap()
        } else {
            d.n * d.h + nu * (hu / nu.length_squared()) + nv * (hv / nv.length_squared())
        };
        (frame.to_world(x), frame.to_world(d.n))
    };
    for variant in [0u8, 1] {
        let mut worst: f64 = 0.0;
        let patch = s.patch(1, 1).unwrap();
        for (u, v) in samples(5) {
            let e = 1e-6;
            let (_, n) = wrong(&patch, u, v, variant);
            let xu = (wrong(&patch, u + e, v, variant).0 - wrong(&patch, u - e, v, variant).0)
                / (2.0 * e);
            worst = worst.max(n.dot(xu).abs() / xu.length());
        }
        assert!(worst > 1e-3, "variant {variant}: worst {worst:e}");
    }
}

#[test]
fn sphere_with_exact_derivatives_is_reproduced() {
    let (c, r) = (DVec3::new(0.2, -0.1, 0.4), 1.7);
    for (m, n) in [(4, 4), (5, 3), (3, 6)] {
        let (p, nn, du, dv) = sphere_grid(c, r, m, n, -0.5, -0.4, 0.3);
        let g = PnGrid::new(&p, &nn).unwrap();
        let s = PnSurface::from_derivatives(&g, IsotropicFrame::IDENTITY, &du, &dv).unwrap();
        let mut worst: f64 = 0.0;
        for i in 0..m - 1 {
            for j in 0..n - 1 {
                for (u, v) in samples(7) {
                    let e = s.eval(i, j, u, v).unwrap();
                    worst = worst.max(((e.point - c).length() - r).abs());
                    assert_near!(e.point, c + e.normal * r, 1e-12);
                    let x = s.rational(i, j).unwrap().eval(u, v).unwrap();
                    worst = worst.max(((x - c).length() - r).abs());
                }
            }
        }
        assert!(worst < 1e-12, "{m}x{n}: distance to the sphere {worst:e}");
    }
}

#[test]
fn sphere_with_estimated_derivatives() {
    let (c, r) = (DVec3::new(-0.3, 0.5, 0.1), 0.8);
    let (p, nn, du, dv) = sphere_grid(c, r, 5, 4, -0.6, -0.3, 0.25);
    let g = PnGrid::new(&p, &nn).unwrap();
    let dist = |s: &PnSurface| {
        let mut w: f64 = 0.0;
        for i in 0..4 {
            for j in 0..3 {
                for (u, v) in samples(6) {
                    w = w.max(((s.eval(i, j, u, v).unwrap().point - c).length() - r).abs());
                }
            }
        }
        w
    };
    // Bessel tangents + isotropic projection: exact derivatives, exact sphere.
    let id = FrameChoice::Fixed(IsotropicFrame::IDENTITY);
    let opts = options(id, TangentEstimate::Bessel, Projection::Isotropic);
    let (eu, ev) = estimate_derivatives(
        &g,
        &IsotropicFrame::IDENTITY,
        opts.tangents,
        opts.projection,
    )
    .unwrap();
    for i in 0..5 {
        for j in 0..4 {
            assert_near!(eu[i][j], du[i][j], 1e-12);
            assert_near!(ev[i][j], dv[i][j], 1e-12);
        }
    }
    let s = PnSurface::interpolate(&g, &opts).unwrap();
    assert!(dist(&s) < 1e-12);
    // The seed's estimate (one-sided differences, orthogonal projection) is close but not exact.
    let seed = PnSurface::interpolate(
        &g,
        &options(id, TangentEstimate::SeedDifferences, Projection::Orthogonal),
    )
    .unwrap();
    let d = dist(&seed);
    assert!(d > 1e-8 && d < 0.05, "seed estimate distance {d:e}");
}

#[test]
fn offsets_are_at_distance_d() {
    for (name, s) in surfaces() {
        let (pr, pc) = s.patch_count();
        for d in [0.3, -0.2, 1.5] {
            for i in 0..pr {
                for j in 0..pc {
                    let ro = s.rational_offset(i, j, d).unwrap();
                    assert_eq!(ro.degree(), (11, 11));
                    for (u, v) in samples(4) {
                        let e = s.eval(i, j, u, v).unwrap();
                        let o = s.offset(i, j, u, v, d).unwrap();
                        assert_near!((o - e.point).length(), d.abs(), 1e-10, "{name}");
                        let (xo, xou, xov) = ro.partials(u, v).unwrap();
                        assert_near!(xo, o, 1e-10 * (1.0 + o.length()), "{name} rational offset");
                        assert_near!((xo - e.point).length(), d.abs(), 1e-10, "{name}");
                        // A true offset: its tangents are perpendicular to n as well.
                        assert!(e.normal.dot(xou).abs() < 1e-9 * xou.length(), "{name}");
                        assert!(e.normal.dot(xov).abs() < 1e-9 * xov.length(), "{name}");
                    }
                }
            }
        }
    }
}

#[test]
fn rational_forms_have_the_stated_degrees() {
    let (p, nn) = CONVEX.grid(5, 4, O1);
    let s = interp(&p, &nn, PnOptions::default());
    let r = s.rational(1, 1).unwrap();
    assert_eq!(r.degree(), (11, 11));
    assert_eq!(r.homogeneous.points().len(), 12);
    // (A direction with only 3 grid points would give a quadratic y and a lower degree.)
    // The weight W = qJ has full degree 11 in u and in v: the 11th forward difference of its
    // Bernstein coefficients (proportional to the leading power coefficient) is not zero.
    let w = r.weights();
    let diff11 = |c: Vec<f64>| -> f64 {
        (0..=11)
            .map(|k| if k % 2 == 0 { 1.0 } else { -1.0 } * binom(11, k) * c[11 - k])
            .sum()
    };
    let wmax = w.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let du11 = diff11(w.iter().map(|r| r[5]).collect()).abs();
    let dv11 = diff11(w[5].clone()).abs();
    // Round-off in an 11th difference is about 2^11 · 1e-16 relative; measured here: 6e-8 (u),
    // 8e-6 (v) relative (small: the cubic terms of y are small on a fine grid, but not zero).
    assert!(
        du11 > 1e-10 * wmax && dv11 > 1e-10 * wmax,
        "{du11:e} {dv11:e} {wmax:e}"
    );
    let rn = s.rational_normal(1, 1).unwrap();
    assert_eq!(rn.degree(), (6, 6));
    for (u, v) in samples(5) {
        let e = s.eval(1, 1, u, v).unwrap();
        assert_near!(rn.eval(u, v).unwrap(), e.normal, 1e-12);
    }
    // For this convex patch all weights are positive: it converts to a RationalSurface.
    let rs = r.to_rational_surface().unwrap();
    assert_near!(
        rs.eval(0.3, 0.6),
        s.eval(1, 1, 0.3, 0.6).unwrap().point,
        1e-10
    );
    s.certify_regular().unwrap();
}

#[test]
fn non_square_grids() {
    for (m, n) in [(2, 2), (2, 5), (5, 2), (3, 7), (7, 3)] {
        let o = (-0.6, -0.5, 1.2 / (m - 1) as f64, 1.0 / (n - 1) as f64);
        let (p, nn) = CONVEX.grid(m, n, o);
        let s = interp(&p, &nn, PnOptions::default());
        assert_eq!(s.grid_size(), (m, n));
        assert_eq!(s.patch_count(), (m - 1, n - 1));
        // Global parameters reach every corner.
        assert_near!(
            s.eval_global((m - 1) as f64, 0.0).unwrap().point,
            p[m - 1][0],
            1e-12
        );
        assert_near!(
            s.eval_global(0.0, (n - 1) as f64).unwrap().point,
            p[0][n - 1],
            1e-12
        );
        assert_near!(
            s.eval_global((m - 1) as f64, (n - 1) as f64).unwrap().point,
            p[m - 1][n - 1],
            1e-12
        );
        for i in 0..m - 1 {
            for j in 0..n - 1 {
                let e = s.eval(i, j, 0.5, 0.5).unwrap();
                assert!(e.point.is_finite());
                // Close to the sampled surface (a loose sanity bound).
                let dev = (e.point.z - (CONVEX.f)(e.point.x, e.point.y)).abs();
                // Loose sanity bound: the interpolation error shrinks with the grid step.
                let bound = 0.1 * (o.2 * o.2 + o.3 * o.3) + 0.01;
                assert!(dev < bound, "{m}x{n} [{i}][{j}] deviation {dev} > {bound}");
            }
        }
        assert!(
            matches!(s.eval(m - 1, 0, 0.0, 0.0), Err(PnError::NoSuchPatch { i, .. }) if i == m - 1)
        );
    }
}

fn edge_continuity(s: &PnSurface, name: &str) {
    let (pr, pc) = s.patch_count();
    let ts: Vec<f64> = (0..=16).map(|k| k as f64 / 16.0).collect();
    for i in 0..pr {
        for j in 0..pc {
            for &t in &ts {
                if i + 1 < pr {
                    let (a, b) = (
                        s.eval(i, j, 1.0, t).unwrap(),
                        s.eval(i + 1, j, 0.0, t).unwrap(),
                    );
                    assert_near!(a.point, b.point, 1e-12, "{name}: u-edge [{i}][{j}] t={t}");
                    let ang = angle_between(a.normal, b.normal);
                    assert!(ang < 1e-9, "{name}: normal angle {ang:e}");
                }
                if j + 1 < pc {
                    let (a, b) = (
                        s.eval(i, j, t, 1.0).unwrap(),
                        s.eval(i, j + 1, t, 0.0).unwrap(),
                    );
                    assert_near!(a.point, b.point, 1e-12, "{name}: v-edge [{i}][{j}] t={t}");
                    let ang = angle_between(a.normal, b.normal);
                    assert!(ang < 1e-9, "{name}: normal angle {ang:e}");
                }
            }
        }
    }
}

#[test]
fn g1_and_c0_across_patch_edges() {
    for (name, s) in surfaces() {
        edge_continuity(&s, &name);
    }
}

/// Two grids sharing a boundary row, with exact derivatives from one surface: their boundary
/// curves and normals coincide (the watertight G¹ join the caller-supplied entry is for).
#[test]
fn grids_sharing_exact_derivatives_join() {
    for g in [CONVEX, SADDLE.upward()] {
        let frame = IsotropicFrame::auto(&g.grid(7, 4, O1).1).unwrap();
        let build = |i0: usize| {
            let o = (O1.0 + i0 as f64 * O1.2, O1.1, O1.2, O1.3);
            let (p, nn) = g.grid(4, 4, o);
            let (du, dv) = g.exact_derivs(4, 4, o, &frame);
            PnSurface::from_derivatives(&PnGrid::new(&p, &nn).unwrap(), frame, &du, &dv).unwrap()
        };
        let (a, b) = (build(0), build(3));
        for j in 0..3 {
            for k in 0..=10 {
                let t = k as f64 / 10.0;
                let (ea, eb) = (a.eval(2, j, 1.0, t).unwrap(), b.eval(0, j, 0.0, t).unwrap());
                assert_near!(ea.point, eb.point, 1e-12);
                assert!(angle_between(ea.normal, eb.normal) < 1e-9);
            }
        }
        edge_continuity(&a, "shared a");
    }
}

#[test]
fn auto_frame_handles_normals_at_the_pole() {
    // The upward convex graph has n = (0, 0, 1) exactly at the grid point (x, y) = (0, 0).
    let o = (-0.6, -0.6, 0.3, 0.3);
    let (p, nn) = CONVEX.upward().grid(5, 5, o);
    assert_eq!(nn[2][2], DVec3::Z);
    let g = PnGrid::new(&p, &nn).unwrap();
    let id = options(
        FrameChoice::Fixed(IsotropicFrame::IDENTITY),
        TangentEstimate::Bessel,
        Projection::Isotropic,
    );
    assert_eq!(
        PnSurface::interpolate(&g, &id),
        Err(PnError::NormalAtPole { i: 2, j: 2 })
    );
    let s = PnSurface::interpolate(&g, &PnOptions::default()).unwrap();
    let r = s.frame().rotation();
    assert!(r
        .transpose()
        .mul_mat3(&r)
        .abs_diff_eq(DMat3::IDENTITY, 1e-12));
    // In the frame, every normal is far from the pole.
    for row in &nn {
        for n in row {
            assert!(s.frame().to_frame(*n).z < 0.5);
        }
    }
    assert_near!(s.eval(1, 1, 1.0, 1.0).unwrap().point, p[2][2], 1e-12);
}

#[test]
fn caller_derivatives_match_estimates_in_shape_and_are_admissible() {
    let (p, nn) = SADDLE.grid(4, 3, O1);
    let g = PnGrid::new(&p, &nn).unwrap();
    let f = IsotropicFrame::IDENTITY;
    let (du, dv) = SADDLE.exact_derivs(4, 3, O1, &f);
    for i in 0..4 {
        for j in 0..3 {
            let y = f.isotropic(p[i][j], nn[i][j]).unwrap();
            let v = admissible_normal(p[i][j], y);
            assert!(v.dot(du[i][j]).abs() < 1e-14 * v.length() * du[i][j].length());
            assert!(v.dot(dv[i][j]).abs() < 1e-14 * v.length() * dv[i][j].length());
        }
    }
    let s = PnSurface::from_derivatives(&g, f, &du, &dv).unwrap();
    for i in 0..4 {
        for j in 0..3 {
            let (y, a, b) = s.grid_data(i, j).unwrap();
            assert_near!(y, f.isotropic(p[i][j], nn[i][j]).unwrap(), 1e-15);
            assert_near!(a, du[i][j], 1e-14);
            assert_near!(b, dv[i][j], 1e-14);
        }
    }
}

// ---------------------------------------------------------------- errors

#[test]
fn bad_inputs_give_typed_errors() {
    let (p, nn) = CONVEX.grid(3, 4, O1);
    let grid = |p: &Grid, n: &Grid| PnGrid::new(p, n);
    // 1 × n and n × 1 grids.
    assert_eq!(
        grid(&p[..1].to_vec(), &nn[..1].to_vec()),
        Err(PnError::GridTooSmall { rows: 1, cols: 4 })
    );
    let col: Grid = p.iter().map(|r| r[..1].to_vec()).collect();
    assert_eq!(
        grid(&col, &col),
        Err(PnError::GridTooSmall { rows: 3, cols: 1 })
    );
    assert_eq!(
        grid(&vec![], &vec![]),
        Err(PnError::GridTooSmall { rows: 0, cols: 0 })
    );
    // Ragged grids.
    let mut rp = p.clone();
    rp[2].pop();
    assert_eq!(
        grid(&rp, &nn),
        Err(PnError::RaggedGrid {
            argument: "points",
            row: 2,
            expected: 4,
            found: 3
        })
    );
    let mut rn = nn.clone();
    rn[1].push(DVec3::Z);
    assert_eq!(
        grid(&p, &rn),
        Err(PnError::RaggedGrid {
            argument: "normals",
            row: 1,
            expected: 4,
            found: 5
        })
    );
    assert_eq!(
        grid(&p, &nn[..2].to_vec()),
        Err(PnError::RowCount {
            argument: "normals",
            expected: 3,
            found: 2
        })
    );
    // Zero normal, NaN point, NaN normal.
    let mut zn = nn.clone();
    zn[1][2] = DVec3::ZERO;
    assert_eq!(grid(&p, &zn), Err(PnError::ZeroNormal { i: 1, j: 2 }));
    let mut np = p.clone();
    np[2][3].y = f64::NAN;
    assert_eq!(
        grid(&np, &nn),
        Err(PnError::NotFinite {
            argument: "points",
            i: 2,
            j: 3
        })
    );
    let mut nnan = nn.clone();
    nnan[0][1].x = f64::INFINITY;
    assert_eq!(
        grid(&p, &nnan),
        Err(PnError::NotFinite {
            argument: "normals",
            i: 0,
            j: 1
        })
    );

    let g = grid(&p, &nn).unwrap();
    let s = PnSurface::interpolate(&g, &PnOptions::default()).unwrap();
    // Offsets: d = 0 is meaningless for an offset surface; NaN is rejected.
    assert_eq!(s.rational_offset(0, 0, 0.0), Err(PnError::ZeroOffset));
    assert!(matches!(
        s.rational_offset(0, 0, f64::NAN),
        Err(PnError::BadOffset { .. })
    ));
    assert!(matches!(
        s.offset(0, 0, 0.5, 0.5, f64::INFINITY),
        Err(PnError::BadOffset { .. })
    ));
    assert_eq!(
        s.offset(0, 0, 0.5, 0.5, 0.0).unwrap(),
        s.eval(0, 0, 0.5, 0.5).unwrap().point
    );
    // Parameters and indices.
    assert!(matches!(
        s.eval(0, 0, f64::NAN, 0.5),
        Err(PnError::BadParameter { name: "u", .. })
    ));
    assert!(matches!(
        s.eval(0, 0, 0.5, 1.5),
        Err(PnError::BadParameter { name: "v", .. })
    ));
    assert!(matches!(
        s.eval_global(2.5, 0.0),
        Err(PnError::BadParameter { name: "s", .. })
    ));
    assert_eq!(
        s.eval(0, 3, 0.5, 0.5),
        Err(PnError::NoSuchPatch {
            i: 0,
            j: 3,
            rows: 2,
            cols: 3
        })
    );
    // Derivative grids of the wrong shape, NaN, off the admissible plane.
    let f = IsotropicFrame::IDENTITY;
    let (du, dv) = CONVEX.exact_derivs(3, 4, O1, &f);
    let mut bad = du.clone();
    bad[1].pop();
    assert_eq!(
        PnSurface::from_derivatives(&g, f, &bad, &dv),
        Err(PnError::RaggedGrid {
            argument: "du",
            row: 1,
            expected: 4,
            found: 3
        })
    );
    let mut bad = dv.clone();
    bad[2][0].z = f64::NAN;
    assert_eq!(
        PnSurface::from_derivatives(&g, f, &du, &bad),
        Err(PnError::NotFinite {
            argument: "dv",
            i: 2,
            j: 0
        })
    );
    let mut bad = dv.clone();
    bad[1][3].z += 0.1;
    assert!(matches!(
        PnSurface::from_derivatives(&g, f, &du, &bad),
        Err(PnError::InadmissibleDerivative {
            i: 1,
            j: 3,
            direction: 'v',
            ..
        })
    ));
    assert_eq!(
        IsotropicFrame::from_rotation(DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0))),
        Err(PnError::BadRotation)
    );
}

#[test]
fn singular_data_is_reported_with_its_index() {
    // A plane: all normals equal, the Gauss map is constant (zero Gaussian curvature).
    let p: Grid = (0..3)
        .map(|i| {
            (0..3)
                .map(|j| DVec3::new(i as f64, j as f64, 0.0))
                .collect()
        })
        .collect();
    let n: Grid = vec![vec![DVec3::NEG_Z; 3]; 3];
    let g = PnGrid::new(&p, &n).unwrap();
    assert_eq!(
        PnSurface::interpolate(&g, &PnOptions::default()),
        Err(PnError::SingularPoint { i: 0, j: 0 })
    );
    // A cylinder (normals on a great circle): singular too.
    let p: Grid = (0..3)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let a = 0.3 * j as f64;
                    DVec3::new(a.sin(), i as f64, -a.cos())
                })
                .collect()
        })
        .collect();
    let n: Grid = p
        .iter()
        .map(|r| r.iter().map(|x| DVec3::new(x.x, 0.0, x.z)).collect())
        .collect();
    let g = PnGrid::new(&p, &n).unwrap();
    assert_eq!(
        PnSurface::interpolate(&g, &PnOptions::default()),
        Err(PnError::SingularPoint { i: 0, j: 0 })
    );
    // A surface whose Gaussian curvature changes sign (z = x³/3 + y²: K ∝ 2x): the patch that
    // straddles x = 0 is named.
    let mixed = Graph {
        f: |x, y| x * x * x / 3.0 + y * y,
        grad: |x, y| (x * x, 2.0 * y),
        hess: |x, _| (2.0 * x, 0.0, 2.0),
        up: -1.0,
    };
    let (p, nn) = mixed.grid(4, 3, (-0.75, -0.5, 0.5, 0.5));
    let g = PnGrid::new(&p, &nn).unwrap();
    assert_eq!(
        PnSurface::interpolate(&g, &PnOptions::default()),
        Err(PnError::CurvatureSignChange { i: 1, j: 0 })
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Random perturbations of a convex grid: construction and evaluation either succeed with
    /// finite values or return a typed error; never NaN.
    #[test]
    fn never_nan_without_error(noise in proptest::collection::vec(-0.2..0.2f64, 36), u in 0.0..1.0f64, v in 0.0..1.0f64) {
        let (mut p, mut nn) = CONVEX.grid(3, 3, O1);
        for i in 0..3 {
            for j in 0..3 {
                let k = 4 * (3 * i + j);
                p[i][j] += DVec3::new(noise[k], noise[k + 1], noise[k + 2]);
                nn[i][j] += DVec3::new(noise[k + 3], -noise[k + 2], noise[k + 1]) * 2.0;
            }
        }
        let Ok(g) = PnGrid::new(&p, &nn) else { return Ok(()) };
        if let Ok(s) = PnSurface::interpolate(&g, &PnOptions::default()) {
            for i in 0..2 {
                for j in 0..2 {
                    if let Ok(e) = s.eval(i, j, u, v) {
                        prop_assert!(e.point.is_finite() && e.normal.is_finite());
                    }
                    if let Ok(r) = s.rational_offset(i, j, 0.5) {
                        if let Some(x) = r.eval(u, v) {
                            prop_assert!(x.is_finite());
                        }
                    }
                }
            }
        }
    }
}

/// Neighbouring patches' exact rational forms (surface and offset) share their boundary rows of
/// homogeneous control points up to round-off, so an export is watertight.
#[test]
fn rational_boundaries_match() {
    for (name, s) in surfaces() {
        let (pr, pc) = s.patch_count();
        for d in [None, Some(0.4)] {
            let form = |i, j| match d {
                None => s.rational(i, j).unwrap(),
                Some(d) => s.rational_offset(i, j, d).unwrap(),
            };
            for i in 0..pr {
                for j in 0..pc {
                    let a = form(i, j);
                    let ha = a.homogeneous.points();
                    let scale = ha.iter().flatten().map(|p| p.length()).fold(0.0, f64::max);
                    if i + 1 < pr {
                        let b = form(i + 1, j);
                        for (p, q) in ha[11].iter().zip(&b.homogeneous.points()[0]) {
                            assert!(
                                (*p - *q).length() <= 1e-12 * scale,
                                "{name} u-edge [{i}][{j}]"
                            );
                        }
                    }
                    if j + 1 < pc {
                        let b = form(i, j + 1);
                        for (r, rb) in ha.iter().zip(b.homogeneous.points()) {
                            assert!(
                                (r[11] - rb[0]).length() <= 1e-12 * scale,
                                "{name} v-edge [{i}][{j}]"
                            );
                        }
                    }
                }
            }
        }
    }
}
