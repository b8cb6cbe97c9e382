#![no_main]
//! The OFF reader on arbitrary bytes (invariants: gbsurf_fuzz::check_mesh_reader).
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| gbsurf_fuzz::check_mesh_reader(data, "off"));
