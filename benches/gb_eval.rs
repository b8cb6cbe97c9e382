//! ns per evaluated point (position + unit normal) of GB patches: weight tables
//! ([`GbTable::eval_all`], one patch; [`GbTable::eval_batch`], 16 patches sharing a table) versus
//! direct evaluation ([`GbPatch::eval_derivs_with_form`] with a reused evaluator), for
//! n = 3..8, d = 3 and 5, r = 16 and 64. Criterion measures each case briefly; a summary table
//! with the table/direct ratio is printed at the end. The summary also gives the cost of the
//! conversion's path: a table with second derivatives ([`GbTable::for_each_sample_derivs`]) giving
//! position, normal, mean and Gaussian curvature per point. "table" is the runtime-dispatched
//! path (AVX2 + FMA where the CPU has them, in a portable build), "portable" the fallback
//! ([`SimdPath::Portable`]).

use criterion::{black_box, BenchmarkId, Criterion, Throughput};
use gbsurf::gb::table::{ControlSoa, GbTable, SimdPath};
use gbsurf::gb::{GbPatch, Ribbon, WeightForm};
use gbsurf::DVec3;
use std::time::Duration;

mod common;
use common::ns_per_point;

const FORM: WeightForm = WeightForm::Squared;
const BATCH: usize = 16;

fn patch(n: usize, d: usize, seed: usize) -> GbPatch {
    let l = d.div_ceil(2);
    let ribbons = (0..n)
        .map(|i| {
            Ribbon::from_fn(d, l, d + 1, |k, j| {
                let a =
                    (i as f64 + j as f64 / d as f64) * std::f64::consts::TAU / n as f64;
                let rad = 1.0 - 0.6 * k as f64 / d as f64;
                let wob = 0.05 * ((seed * 7 + i * 3 + j) as f64).sin();
                DVec3::new(
                    rad * a.cos() + wob,
                    rad * a.sin() - wob,
                    0.4 * k as f64 + wob,
                )
            })
        })
        .collect();
    GbPatch {
        ribbons,
        center: DVec3::new(0.0, 0.0, 0.9),
    }
}

fn direct_all(
    p: &GbPatch,
    ev: &mut gbsurf::gb::GbBasisEvaluator,
    table: &GbTable,
    out: &mut Vec<(DVec3, DVec3)>,
) {
    out.clear();
    for &uv in &table.layout.uv {
        let s = p.eval_derivs_with_form(ev, uv, FORM);
        out.push((s.p, s.normal().unwrap_or(DVec3::ZERO)));
    }
}

fn main() {
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_millis(100))
        .measurement_time(Duration::from_millis(300))
        .sample_size(10)
        .configure_from_args();
    let mut summary = Vec::new();
    for d in [3, 5] {
        for n in 3..=8 {
            for r in [16, 64] {
                let table = GbTable::new(n, d, r, FORM).unwrap();
                let patches: Vec<GbPatch> = (0..BATCH).map(|s| patch(n, d, s)).collect();
                let ctrls: Vec<ControlSoa> = patches
                    .iter()
                    .map(|p| table.controls_of(p).unwrap())
                    .collect();
                let samples = table.sample_count();
                let (mut pos, mut nrm) = (Vec::new(), Vec::new());
                let (mut bpos, mut bnrm) = (vec![Vec::new(); BATCH], vec![Vec::new(); BATCH]);
                let mut ev = patches[0].evaluator().unwrap();
                let mut direct_out = Vec::new();

                let mut g = c.benchmark_group(format!("gb_eval/n{n}_d{d}_r{r}"));
                g.throughput(Throughput::Elements(samples as u64));
                g.bench_function(BenchmarkId::new("table", samples), |b| {
                    b.iter(|| table.eval_all(black_box(&ctrls[0]), &mut pos, &mut nrm))
                });
                g.throughput(Throughput::Elements((samples * BATCH) as u64));
                g.bench_function(BenchmarkId::new("table_batch16", samples), |b| {
                    b.iter(|| table.eval_batch(black_box(&ctrls), &mut bpos, &mut bnrm))
                });
                if r == 16 {
                    g.throughput(Throughput::Elements(samples as u64));
                    g.bench_function(BenchmarkId::new("direct", samples), |b| {
                        b.iter(|| {
                            direct_all(black_box(&patches[0]), &mut ev, &table, &mut direct_out)
                        })
                    });
                }
                g.finish();

                let t = ns_per_point(samples, || table.eval_all(&ctrls[0], &mut pos, &mut nrm));
                let tp = ns_per_point(samples, || {
                    table.eval_all_with(SimdPath::Portable, &ctrls[0], &mut pos, &mut nrm)
                });
                let tb = ns_per_point(samples * BATCH, || {
                    table.eval_batch(&ctrls, &mut bpos, &mut bnrm)
                });
                let dt = ns_per_point(samples, || {
                    direct_all(&patches[0], &mut ev, &table, &mut direct_out)
                });
                let mib = table.memory_bytes() as f64 / (1 << 20) as f64;
                let t2 = GbTable::with_second_derivatives(n, d, r, FORM).unwrap();
                // Every sample is written once per pass: sized once, overwritten.
                let mut curv = vec![(DVec3::ZERO, DVec3::ZERO, (0.0, 0.0)); samples];
                let d2 = ns_per_point(samples, || {
                    t2.for_each_sample_derivs(&ctrls[0], |s, f, n| {
                        let c = f.curvature().map_or((0.0, 0.0), |c| (c.mean, c.gaussian));
                        curv[s] = (f.p, n.unwrap_or(DVec3::ZERO), c);
                    });
                    black_box(&curv);
                });
                summary.push((n, d, r, samples, table.sector_count(), mib, t, tp, tb, dt, d2));
            }
        }
    }
    println!(
        "\nGB evaluation, ns per point (position + unit normal), 1 thread, median of 5 x 60 ms;"
    );
    println!("cpu = thread CPU time (per-core cost on a shared machine), wall = elapsed time");
    println!("table = runtime-dispatched path (AVX2 + FMA when the CPU has them), portable = SimdPath::Portable");
    println!("sec = sectors the rows serve (n: sector rows, above gbsurf::gb::table::SECTOR_ROWS_ABOVE bytes; 1: rows for every sample)");
    println!("  n  d   r samples sec  MiB  table cpu/wall  portable cpu/wall  batch16 cpu/wall  direct cpu/wall  direct/table direct/batch (cpu)  +curvature cpu/wall");
    for (n, d, r, s, sec, mib, t, tp, tb, dt, d2) in summary {
        println!(
            "{n:3} {d:2} {r:3} {s:7} {sec:3} {mib:5.1} {:7.1}/{:<7.1} {:8.1}/{:<8.1} {:7.1}/{:<8.1} {:7.1}/{:<8.1} {:8.1} {:12.1}  {:7.1}/{:<7.1}",
            t.1, t.0, tp.1, tp.0, tb.1, tb.0, dt.1, dt.0, dt.1 / t.1, dt.1 / tb.1, d2.1, d2.0
        );
    }
    c.final_summary();
}
