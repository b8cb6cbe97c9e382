#![no_main]
//! The .gbp patch reader on arbitrary bytes (invariants: gbsurf_fuzz::check_gbp_reader).
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| gbsurf_fuzz::check_gbp_reader(data));
