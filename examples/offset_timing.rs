//! Wall time of `api::offset` beside `api::convert` on generated tori (release build):
//!   cargo run --release --example offset_timing [-- quads...]
//! Prints per size the conversion time, the offset time and their ratio, and the offset report's
//! max gap and fit error (so a faster offset can be checked to give the same surface).
use gbsurf::api::{convert, offset, ConvertOptions, OffsetOptions};
use std::time::Instant;

fn main() {
    let sizes: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let sizes = if sizes.is_empty() { vec![1000, 4000] } else { sizes };
    let threads = rayon::current_num_threads();
    println!("offset d = 0.05, grid 4, default options; {threads} threads");
    for n in sizes {
        let major = ((n as f64 * 1.6).sqrt().round() as usize).max(3);
        let minor = (n / major).max(3);
        let mesh = gbsurf::mesh::generate::torus(major, minor, 3.0, 1.0).expect("torus");
        let opts = ConvertOptions::default();
        let t = Instant::now();
        convert(&mesh, &opts, None).expect("convert");
        let tc = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let o = offset(&mesh, &opts, &OffsetOptions { distance: 0.05, grid: 4, shell: false }).expect("offset");
        let to = t.elapsed().as_secs_f64();
        println!(
            "torus {major}x{minor} ({} quads): convert {tc:.3} s, offset {to:.3} s, ratio {:.1}; max gap {:.3e}, max fit error {:.3e}",
            major * minor,
            to / tc,
            o.report.max_gap,
            o.report.max_fit_error
        );
    }
}
