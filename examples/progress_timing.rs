//! Times the progress reports and the cancel latency of [`gbsurf::api::convert`] for every
//! method on a 50k-face UV sphere (250 segments × 200 rings) and a 40k-face quad torus (200 × 200):
//! `cargo run --release --example progress_timing -- [sphere|torus|all] [dual|topology|doo-sabin|catmull-clark|all]`.
//! `MIDDLE=fair` runs the patch methods with the fair middle constraint.
//!
//! Per case it prints the wall time, the number of progress calls, the largest interval between
//! two consecutive reports (counting the start of `convert` and its return as reports) with the
//! fractions around it, and the cancel latency: the time from the callback returning false (the
//! first time the fraction reaches 0.5) to `convert` returning. Goals: interval ≤ 0.25 s,
//! latency ≤ 0.5 s. The default layout (quads) at resolution 2 (its default; 4 steps per patch
//! side, like the triangle layout at r = 4 that this measured before the quad layout, which at
//! quads r = 4 exceeds the default memory limit) and 2 subdivision levels (the default, 3,
//! exceeds the default memory limit on these inputs).

use gbsurf::api::{convert, ConvertError, ConvertOptions, Method};
use gbsurf::mesh::generate::{torus, uv_sphere};
use gbsurf::mesh::PolyMesh;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let which = args.get(1).map_or("all", String::as_str);
    let only = args.get(2).map_or("all", String::as_str);
    let mut inputs: Vec<(&str, PolyMesh)> = Vec::new();
    if which == "all" || which == "sphere" {
        inputs.push(("sphere 50k", uv_sphere(250, 200).expect("sphere")));
    }
    if which == "all" || which == "torus" {
        inputs.push(("torus 40k", torus(200, 200, 10.0, 3.0).expect("torus")));
    }
    let methods = [Method::Dual, Method::Topology, Method::DooSabin, Method::CatmullClark];
    let (mut worst_gap, mut worst_latency) = (0.0f64, 0.0f64);
    for (name, mesh) in &inputs {
        for &method in methods.iter().filter(|m| only == "all" || m.name() == only) {
            let middle: gbsurf::Middle = std::env::var("MIDDLE").ok().and_then(|s| s.parse().ok()).unwrap_or_default();
            let opts = ConvertOptions { method, resolution: 2, levels: 2, middle, ..Default::default() };
            let mut calls: Vec<(f64, f32)> = Vec::new();
            let t0 = Instant::now();
            let mut cb = |f: f32| {
                calls.push((t0.elapsed().as_secs_f64(), f));
                true
            };
            convert(mesh, &opts, Some(&mut cb)).expect("conversion");
            let total = t0.elapsed().as_secs_f64();
            let (mut gap, mut at) = (0.0f64, (0.0f32, 0.0f32));
            let (mut prev_t, mut prev_f) = (0.0f64, 0.0f32);
            for &(t, f) in calls.iter().chain(std::iter::once(&(total, 1.0))) {
                if t - prev_t > gap {
                    gap = t - prev_t;
                    at = (prev_f, f);
                }
                (prev_t, prev_f) = (t, f);
            }
            let mut cancelled_at: Option<Instant> = None;
            let mut cancel = |f: f32| {
                if f >= 0.5 {
                    cancelled_at.get_or_insert_with(Instant::now);
                    return false;
                }
                true
            };
            let r = convert(mesh, &opts, Some(&mut cancel));
            let end = Instant::now();
            let latency = cancelled_at.map_or(f64::NAN, |c| (end - c).as_secs_f64());
            assert!(matches!(r, Err(ConvertError::Cancelled)), "{name} {method}: not cancelled");
            if std::env::var_os("PROGRESS_TRACE").is_some() {
                for (t, f) in &calls {
                    eprintln!("{name} {} {t:.4} {f:.4}", method.name());
                }
            }
            println!(
                "{name:10} {:13} {total:7.3} s, {:5} calls, largest interval {gap:6.3} s (between {:.3} and {:.3}), cancel latency {latency:6.3} s",
                method.name(),
                calls.len(),
                at.0,
                at.1
            );
            worst_gap = worst_gap.max(gap);
            worst_latency = worst_latency.max(latency);
        }
    }
    println!("worst interval {worst_gap:.3} s (goal 0.25), worst cancel latency {worst_latency:.3} s (goal 0.5)");
}
