//! ns per evaluated point (position + unit normal) of PN surfaces (seed 004 §4): the pull-back
//! x = h n + N (NᵀN)⁻¹ ∇h from the isotropic Coons patch ([`PnSurface::eval`]), versus the exact
//! rational form of degree (11, 11) evaluated by de Casteljau/Bernstein sums
//! ([`PnRational::eval`], point only), plus the one-off cost of building a patch's rational form.
//! A summary in ns per point is printed at the end.

use criterion::{black_box, BenchmarkId, Criterion, Throughput};
use gbsurf::offset::pn::{PnGrid, PnOptions, PnRational, PnSurface};
use gbsurf::DVec3;
use std::time::Duration;

mod common;
use common::ns_per_point;

/// A convex 6 × 5 grid (patches 5 × 4) on the graph z = 0.5x² + y² + 0.1x³, normals downward.
fn surface() -> PnSurface {
    let f = |x: f64, y: f64| DVec3::new(x, y, 0.5 * x * x + y * y + 0.1 * x * x * x);
    let n = |x: f64, y: f64| DVec3::new(x + 0.3 * x * x, 2.0 * y, -1.0).normalize();
    let at = |g: &dyn Fn(f64, f64) -> DVec3| -> Vec<Vec<DVec3>> {
        (0..6)
            .map(|i| {
                (0..5)
                    .map(|j| g(-0.6 + 0.24 * i as f64, -0.5 + 0.25 * j as f64))
                    .collect()
            })
            .collect()
    };
    let grid = PnGrid::new(&at(&f), &at(&n)).expect("valid grid");
    PnSurface::interpolate(&grid, &PnOptions::default()).expect("regular surface")
}

fn eval_all(s: &PnSurface, r: usize, out: &mut Vec<(DVec3, DVec3)>) {
    out.clear();
    let (pr, pc) = s.patch_count();
    let k = 1.0 / (r - 1) as f64;
    for i in 0..pr {
        for j in 0..pc {
            for a in 0..r {
                for b in 0..r {
                    let e = s.eval(i, j, a as f64 * k, b as f64 * k).unwrap();
                    out.push((e.point, e.normal));
                }
            }
        }
    }
}

fn eval_rational(rs: &[PnRational], r: usize, out: &mut Vec<DVec3>) {
    out.clear();
    let k = 1.0 / (r - 1) as f64;
    for p in rs {
        for a in 0..r {
            for b in 0..r {
                out.push(p.eval(a as f64 * k, b as f64 * k).unwrap());
            }
        }
    }
}

fn main() {
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_millis(100))
        .measurement_time(Duration::from_millis(300))
        .sample_size(10)
        .configure_from_args();
    let s = surface();
    let (pr, pc) = s.patch_count();
    let rs: Vec<PnRational> = (0..pr)
        .flat_map(|i| (0..pc).map(move |j| (i, j)))
        .map(|(i, j)| s.rational(i, j).unwrap())
        .collect();
    let mut summary = Vec::new();
    for r in [16, 64] {
        let points = pr * pc * r * r;
        let (mut out, mut rout) = (Vec::new(), Vec::new());
        let mut g = c.benchmark_group(format!("pn_eval/r{r}"));
        g.throughput(Throughput::Elements(points as u64));
        g.bench_function(BenchmarkId::new("pullback", points), |b| {
            b.iter(|| eval_all(black_box(&s), r, &mut out))
        });
        g.bench_function(BenchmarkId::new("rational", points), |b| {
            b.iter(|| eval_rational(black_box(&rs), r, &mut rout))
        });
        g.finish();
        let t = ns_per_point(points, || eval_all(&s, r, &mut out));
        let tr = ns_per_point(points, || eval_rational(&rs, r, &mut rout));
        summary.push((r, points, t, tr));
    }
    let export = ns_per_point(1, || {
        black_box(s.rational(1, 1).unwrap());
    });
    println!("\nPN evaluation, ns per point, 1 thread, median of 5 x 50 ms, cpu/wall");
    println!("(cpu = thread CPU time: the per-core cost on a shared machine)");
    println!("  r  points  pullback (point+normal)  rational (11,11) point");
    for (r, p, t, tr) in summary {
        println!(
            "{r:3} {p:7} {:>12.1}/{:<10.1} {:>12.1}/{:<10.1}",
            t.1, t.0, tr.1, tr.0
        );
    }
    println!(
        "rational form of one patch (degree 11 x 11): {:.1}/{:.1} µs",
        export.1 / 1000.0,
        export.0 / 1000.0
    );
    c.final_summary();
}
