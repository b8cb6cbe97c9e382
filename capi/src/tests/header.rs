//! The committed C header `cpp/include/gbsurf.h` must equal what cbindgen generates from
//! `capi/src/` now. To update it after changing the C ABI:
//!
//! ```text
//! GBSURF_BLESS=1 cargo test -p gbsurf-capi header
//! ```

use std::path::Path;

fn generate() -> String {
    let dir = env!("CARGO_MANIFEST_DIR");
    let config = cbindgen::Config::from_file(Path::new(dir).join("cbindgen.toml"))
        .expect("cbindgen.toml is readable and valid");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(Path::new(dir).join("src/lib.rs"))
        .generate()
        .expect("cbindgen can parse capi/src");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("header is UTF-8")
}

#[test]
fn header_is_up_to_date() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cpp/include/gbsurf.h");
    let fresh = generate();
    if std::env::var_os("GBSURF_BLESS").is_some() {
        std::fs::write(&path, &fresh).expect("write cpp/include/gbsurf.h");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    if committed != fresh {
        let first = committed
            .lines()
            .zip(fresh.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(committed.lines().count().min(fresh.lines().count()));
        panic!(
            "cpp/include/gbsurf.h is stale (first difference at line {}).\n\
             Regenerate it with:\n    GBSURF_BLESS=1 cargo test -p gbsurf-capi header\n\
             and commit the result.",
            first + 1
        );
    }
}

#[test]
fn header_declares_every_status_code_and_entry_point() {
    let h = generate();
    for name in [
        "GBSURF_OK",
        "GBSURF_ERR_NULL",
        "GBSURF_ERR_COUNT",
        "GBSURF_ERR_INDEX",
        "GBSURF_ERR_NAN",
        "GBSURF_ERR_INVALID_MESH",
        "GBSURF_ERR_INVALID_OPTION",
        "GBSURF_ERR_CANCELLED",
        "GBSURF_ERR_PANIC",
        "GBSURF_ERR_IO",
        "GBSURF_ERR_CAPACITY",
        "GBSURF_ERR_KIND",
        "gbsurf_convert(",
        "gbsurf_convert_file(",
        "gbsurf_result_free(",
        "gbsurf_options_init(",
        "gbsurf_last_error_message(",
        "gbsurf_mesh_positions(",
        "gbsurf_patch_ribbon_points(",
        "gbsurf_curve_points(",
        "gbsurf_result_report(",
        "typedef struct GbsurfResult GbsurfResult",
        "GBSURF_ERR_DEGENERATE",
        "gbsurf_ph5_hermite(",
        "gbsurf_cage_loop_values_holed(",
        "gbsurf_ph5_offset(",
        "gbsurf_ph_spline_hermite(",
        "gbsurf_ph_spline_offset(",
        "gbsurf_pn_interpolate(",
        "gbsurf_pn_rational(",
        "typedef struct GbsurfPh5 GbsurfPh5",
        "typedef struct GbsurfPn GbsurfPn",
    ] {
        assert!(h.contains(name), "generated header lacks {name}");
    }
    // No C enum types in the interface (inputs are uint32_t).
    assert!(!h.contains("enum "), "the C API must not use C enums");
}
