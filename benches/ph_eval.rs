//! ns per point of planar PH quintics: position plus offset point r(t) + d n(t) evaluated
//! directly from the preimage w (n = −i w²/|w|²), versus evaluating the exact degree-9 rational
//! offset (de Casteljau on homogeneous points) plus the position. Also the spatial position
//! plus Euler–Rodrigues frame. 1024 points per iteration; a per-point summary is printed.

use criterion::{black_box, Criterion, Throughput};
use gbsurf::offset::ph::{PlanarPhQuintic, SpatialPhQuintic};
use gbsurf::{DVec2, DVec3};
use std::time::{Duration, Instant};

const N: usize = 1024;

fn main() {
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_millis(100))
        .measurement_time(Duration::from_millis(400))
        .sample_size(10)
        .configure_from_args();
    let curve = PlanarPhQuintic::hermite(
        DVec2::new(0.8, 1.4),
        DVec2::new(8.0, -3.0),
        DVec2::new(4.2, 3.6),
        DVec2::new(8.0, -3.0),
    )
    .expect("sample data")
    .best()
    .curve;
    let d = 0.25;
    let off = curve.offset(d).expect("offset");
    let space = SpatialPhQuintic::hermite_default(
        DVec3::ZERO,
        DVec3::new(1.0, 1.5, -0.5),
        DVec3::new(2.0, 1.0, 1.5),
        DVec3::new(1.5, -1.0, 1.0),
    )
    .expect("spatial data");
    let ts: Vec<f64> = (0..N).map(|k| k as f64 / (N - 1) as f64).collect();

    let direct = |ts: &[f64]| -> DVec2 {
        ts.iter().fold(DVec2::ZERO, |acc, &t| {
            acc + curve.eval(t) + curve.offset_point(t, d)
        })
    };
    let rational = |ts: &[f64]| -> DVec2 {
        ts.iter()
            .fold(DVec2::ZERO, |acc, &t| acc + curve.eval(t) + off.eval(t))
    };
    let spatial = |ts: &[f64]| -> DVec3 {
        ts.iter().fold(DVec3::ZERO, |acc, &t| {
            let f = space.frame(t).expect("regular");
            acc + space.eval(t) + f[1] + f[2]
        })
    };

    let mut g = c.benchmark_group("ph_eval");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("planar_position_plus_offset_direct", |b| {
        b.iter(|| direct(black_box(&ts)))
    });
    g.bench_function("planar_position_plus_offset_rational", |b| {
        b.iter(|| rational(black_box(&ts)))
    });
    g.bench_function("spatial_position_plus_frame", |b| {
        b.iter(|| spatial(black_box(&ts)))
    });
    g.finish();

    let per_point = |f: &dyn Fn() -> f64| {
        let reps = 200;
        let start = Instant::now();
        let mut sink = 0.0;
        for _ in 0..reps {
            sink += f();
        }
        black_box(sink);
        start.elapsed().as_nanos() as f64 / (reps * N) as f64
    };
    println!("\nns per point (position + offset point / frame), {N} points:");
    println!(
        "  planar direct   : {:7.1}",
        per_point(&|| direct(black_box(&ts)).x)
    );
    println!(
        "  planar rational : {:7.1}",
        per_point(&|| rational(black_box(&ts)).x)
    );
    println!(
        "  spatial + frame : {:7.1}",
        per_point(&|| spatial(black_box(&ts)).x)
    );
}
