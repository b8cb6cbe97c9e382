//! The options struct of the C ABI and the report figures.

use super::*;
use gbsurf::api::ConvertError;
use gbsurf::options::{ConvertOptions, Layout, Method, Middle, OptionValue, Twist, WeightForm};

/// Method: dual structure, one GB patch per mesh vertex (seed 000 §2). The default.
pub const GBSURF_METHOD_DUAL: u32 = 0;
/// Method: topology-preserving structure, one ribbon-only patch per mesh face (seed 000 §3).
pub const GBSURF_METHOD_TOPOLOGY: u32 = 1;
/// Method: Doo–Sabin subdivision, for comparison (no patches).
pub const GBSURF_METHOD_DOO_SABIN: u32 = 2;
/// Method: Catmull–Clark subdivision, for comparison (no patches).
pub const GBSURF_METHOD_CATMULL_CLARK: u32 = 3;

/// Twist: first approximation (G1 only where four-sided patches meet).
pub const GBSURF_TWIST_NONE: u32 = 0;
/// Twist: approximating direction blend (seed 000 eq. 4.16).
pub const GBSURF_TWIST_APPROX: u32 = 1;
/// Twist: interpolating direction blend (seed 000 eq. 4.24). The default.
pub const GBSURF_TWIST_INTERP: u32 = 2;

/// Middle constraint of the direction blends: the seed's rule, mid_scale · D_{0.5}. The default.
pub const GBSURF_MIDDLE_SEED: u32 = 0;
/// Middle constraint of the direction blends: the fair rule (docs/math.md#fair-middle).
pub const GBSURF_MIDDLE_FAIR: u32 = 1;

/// Correction weights: squared α (default, keeps G1).
pub const GBSURF_WEIGHTS_SQUARED: u32 = 0;
/// Correction weights: linear α (comparison only).
pub const GBSURF_WEIGHTS_LINEAR: u32 = 1;

/// Layout: n·r² triangles per n-sided patch (r samples per side).
pub const GBSURF_LAYOUT_TRIANGLES: u32 = 0;
/// Layout: n·r² quads per n-sided patch (r samples per half side; Catmull–Clark level L counts
/// at r = 2^(L−1)). The default.
pub const GBSURF_LAYOUT_QUADS: u32 = 1;

/// Conversion options. Always initialize with `gbsurf_options_init`, which sets `struct_size`
/// and the defaults, then change fields. Unknown `struct_size` values are rejected
/// (`GBSURF_ERR_INVALID_OPTION`), so the struct can grow at its end in later versions.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GbsurfOptions {
    /// `sizeof(GbsurfOptions)`, set by `gbsurf_options_init`.
    pub struct_size: u32,
    /// `GBSURF_METHOD_*`. Default `GBSURF_METHOD_DUAL`.
    pub method: u32,
    /// Samples per patch side (triangles) or per half side (quads), 1..=1024. Default 2.
    pub resolution: u32,
    /// `GBSURF_TWIST_*`. Default `GBSURF_TWIST_INTERP`.
    pub twist: u32,
    /// `GBSURF_WEIGHTS_*`. Default `GBSURF_WEIGHTS_SQUARED`.
    pub weights: u32,
    /// Subdivision levels of the comparison methods, 0..=8. Default 3.
    pub levels: u32,
    /// 1: project onto best-fit planes (seed 000 §3.3.2), 0: do not. Default 1.
    pub best_plane: u32,
    /// `GBSURF_LAYOUT_*`: output faces. Default `GBSURF_LAYOUT_QUADS`.
    pub layout: u32,
    /// Fullness κ of the dual curves, 0 ≤ κ < 1 (seed 000 eq. 2.2). Default 1/3.
    pub fullness: f64,
    /// Tile split ratio w > 2 of the topology-preserving structure. Default 3.
    pub tile_depth: f64,
    /// Factor on the middle constraint of the direction blends, finite. Default 1.
    pub mid_scale: f64,
    /// Memory bound of the conversion in MiB, 1..=1048576: a conversion estimated to need more is
    /// refused before any work (`GBSURF_ERR_TOO_LARGE`). Default 1024.
    pub max_memory_mb: u64,
    /// `GBSURF_MIDDLE_*`. Default `GBSURF_MIDDLE_SEED`.
    pub middle: u32,
}

const OPTIONS_SIZE: u32 = std::mem::size_of::<GbsurfOptions>() as u32;

/// The one mapping between the core's option enums and the `GBSURF_*` codes: the code of every
/// value (an exhaustive match); the value of a code is found through [`OptionValue::ALL`].
trait Code: OptionValue {
    fn code(self) -> u32;
    /// The value with code `c`, if any.
    fn from_code(c: u32) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.code() == c)
    }
}

impl Code for Method {
    fn code(self) -> u32 {
        match self {
            Method::Dual => GBSURF_METHOD_DUAL,
            Method::Topology => GBSURF_METHOD_TOPOLOGY,
            Method::DooSabin => GBSURF_METHOD_DOO_SABIN,
            Method::CatmullClark => GBSURF_METHOD_CATMULL_CLARK,
        }
    }
}

impl Code for Twist {
    fn code(self) -> u32 {
        match self {
            Twist::None => GBSURF_TWIST_NONE,
            Twist::Approx => GBSURF_TWIST_APPROX,
            Twist::Interp => GBSURF_TWIST_INTERP,
        }
    }
}

impl Code for Middle {
    fn code(self) -> u32 {
        match self {
            Middle::Seed => GBSURF_MIDDLE_SEED,
            Middle::Fair => GBSURF_MIDDLE_FAIR,
        }
    }
}

impl Code for WeightForm {
    fn code(self) -> u32 {
        match self {
            WeightForm::Squared => GBSURF_WEIGHTS_SQUARED,
            WeightForm::Linear => GBSURF_WEIGHTS_LINEAR,
        }
    }
}

impl Code for Layout {
    fn code(self) -> u32 {
        match self {
            Layout::Triangles => GBSURF_LAYOUT_TRIANGLES,
            Layout::Quads => GBSURF_LAYOUT_QUADS,
        }
    }
}

impl From<&ConvertOptions> for GbsurfOptions {
    /// The C struct of `o` (`gbsurf_options_init` passes `ConvertOptions::default()`).
    fn from(o: &ConvertOptions) -> Self {
        // No `..`: a new option is a compile error here until the struct has it.
        // `cage_maps`, `keep_surface` and `quality_arrays` have no field: the C ABI always builds
        // the cage maps (the Blender add-on and the adapters read them through
        // gbsurf_mesh_cage_*), the surface and the quality arrays (gbsurf_result_*).
        let ConvertOptions {
            method,
            layout,
            resolution,
            fullness,
            tile_depth,
            twist,
            mid_scale,
            middle,
            best_plane,
            weights,
            levels,
            max_memory_mb,
            cage_maps: _,
            keep_surface: _,
            quality_arrays: _,
        } = *o;
        GbsurfOptions {
            struct_size: OPTIONS_SIZE,
            method: method.code(),
            resolution: u32::try_from(resolution).unwrap_or(u32::MAX),
            twist: twist.code(),
            weights: weights.code(),
            levels,
            best_plane: best_plane as u32,
            layout: layout.code(),
            fullness,
            tile_depth,
            mid_scale,
            max_memory_mb,
            middle: middle.code(),
        }
    }
}

fn bad_option(name: &str, value: impl std::fmt::Display, expected: &str) -> FfiError {
    FfiError::new(
        GBSURF_ERR_INVALID_OPTION,
        format!("option {name} = {value}: {expected}"),
    )
}

impl GbsurfOptions {
    /// The Rust options, every value checked (unknown enum values, `struct_size`, ranges).
    pub(crate) fn to_convert_options(self) -> FfiResult<ConvertOptions> {
        if self.struct_size != OPTIONS_SIZE {
            return Err(bad_option(
                "struct_size",
                self.struct_size,
                &format!(
                    "unknown size (this library expects {OPTIONS_SIZE}); call gbsurf_options_init"
                ),
            ));
        }
        let method = Method::from_code(self.method)
            .ok_or_else(|| bad_option("method", self.method, "expected GBSURF_METHOD_* (0..=3)"))?;
        let twist = Twist::from_code(self.twist)
            .ok_or_else(|| bad_option("twist", self.twist, "expected GBSURF_TWIST_* (0..=2)"))?;
        let middle = Middle::from_code(self.middle)
            .ok_or_else(|| bad_option("middle", self.middle, "expected GBSURF_MIDDLE_* (0..=1)"))?;
        let weights = WeightForm::from_code(self.weights)
            .ok_or_else(|| bad_option("weights", self.weights, "expected GBSURF_WEIGHTS_* (0..=1)"))?;
        let best_plane = match self.best_plane {
            0 => false,
            1 => true,
            b => return Err(bad_option("best_plane", b, "expected 0 or 1")),
        };
        let layout = Layout::from_code(self.layout)
            .ok_or_else(|| bad_option("layout", self.layout, "expected GBSURF_LAYOUT_* (0..=1)"))?;
        for (name, v) in [
            ("fullness", self.fullness),
            ("tile_depth", self.tile_depth),
            ("mid_scale", self.mid_scale),
        ] {
            if !v.is_finite() {
                return Err(FfiError::new(
                    GBSURF_ERR_NAN,
                    format!("option {name} = {v} is not finite"),
                ));
            }
        }
        let o = ConvertOptions {
            method,
            layout,
            resolution: self.resolution as usize,
            fullness: self.fullness,
            tile_depth: self.tile_depth,
            twist,
            mid_scale: self.mid_scale,
            middle,
            best_plane,
            weights,
            levels: self.levels,
            max_memory_mb: self.max_memory_mb,
            cage_maps: true,
            keep_surface: true,
            quality_arrays: true,
        };
        o.validate()
            .map_err(|e| FfiError::new(GBSURF_ERR_INVALID_OPTION, e.to_string()))?;
        Ok(o)
    }
}

/// The options behind a C pointer: NULL means the defaults.
pub(crate) fn read_options(options: *const GbsurfOptions) -> FfiResult<ConvertOptions> {
    if options.is_null() {
        return Ok(ConvertOptions::default());
    }
    // Aligned for the whole struct (f64 fields): reading a misaligned struct is UB.
    non_null(options, "options")?;
    // Read the size first: an older/newer caller's struct may be smaller than ours.
    // SAFETY: a non-null options pointer points to at least its `struct_size` field (contract).
    let size = unsafe { std::ptr::read_unaligned(options as *const u32) };
    if size != OPTIONS_SIZE {
        return Err(bad_option(
            "struct_size",
            size,
            &format!(
                "unknown size (this library expects {OPTIONS_SIZE}); call gbsurf_options_init"
            ),
        ));
    }
    // SAFETY: the caller's struct has our full size (checked above).
    unsafe { *options }.to_convert_options()
}

/// The status code of a conversion error.
pub(crate) fn convert_error(e: ConvertError) -> FfiError {
    let code = match &e {
        ConvertError::InvalidOption { .. } => GBSURF_ERR_INVALID_OPTION,
        ConvertError::Mesh(m) => result::mesh_error_code(m),
        ConvertError::Io { .. } | ConvertError::OutputPath(_) => GBSURF_ERR_IO,
        ConvertError::Cancelled => GBSURF_ERR_CANCELLED,
        ConvertError::Construct(_) | ConvertError::Subdiv(_) | ConvertError::Tessellate(_) => {
            GBSURF_ERR_CONSTRUCTION
        }
        ConvertError::OutputTooLarge { .. } | ConvertError::OutOfMemory { .. } => GBSURF_ERR_TOO_LARGE,
        ConvertError::ScaleOutOfRange { .. } => GBSURF_ERR_INVALID_MESH,
    };
    FfiError::new(code, e.to_string())
}

/// Sets `*options` to the defaults (including `struct_size`).
///
/// # Safety
/// `options` must be NULL or point to a writable `GbsurfOptions`.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_options_init(options: *mut GbsurfOptions) -> u32 {
    boundary("gbsurf_options_init", || {
        let p = non_null_mut(options, "options")?;
        // SAFETY: non-null and writable (contract).
        unsafe { p.write(GbsurfOptions::from(&ConvertOptions::default())) };
        Ok(())
    })
}

/// Checks options without converting anything: `GBSURF_OK` or the code and message
/// `gbsurf_convert` would give for them.
///
/// # Safety
/// `options` must be NULL or point to an initialized `GbsurfOptions`.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_options_validate(options: *const GbsurfOptions) -> u32 {
    boundary("gbsurf_options_validate", || {
        non_null(options, "options")?;
        read_options(options).map(|_| ())
    })
}

/// A count of `GbsurfReport` that was not computed (`UINT64_MAX`): see
/// `GbsurfReport::input_self_intersections`.
pub const GBSURF_NOT_CHECKED: u64 = 0xFFFF_FFFF_FFFF_FFFF;

/// Report figures of a conversion. Set `struct_size = sizeof(GbsurfReport)` before calling
/// `gbsurf_result_report` (unknown sizes are rejected so the struct can grow).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GbsurfReport {
    /// `sizeof(GbsurfReport)`, set by the caller.
    pub struct_size: u32,
    /// The `GBSURF_METHOD_*` used.
    pub method: u32,
    /// 1 if the output is a closed, consistently oriented two-manifold.
    pub closed: u32,
    /// 1 if the output is a consistently oriented two-manifold (possibly with boundary).
    pub two_manifold: u32,
    /// Number of patches (patch methods) or faces of the subdivided mesh (subdivision methods).
    pub patches: u64,
    /// Output vertices.
    pub vertices: u64,
    /// Output triangles.
    pub triangles: u64,
    /// Output edges used by one triangle only.
    pub boundary_edges: u64,
    /// Output vertices at identical positions (extra copies).
    pub duplicate_vertices: u64,
    /// Output triangles of (relatively) zero area.
    pub zero_area_triangles: u64,
    /// Tessellation resolution or subdivision levels.
    pub resolution: u64,
    /// Input vertices.
    pub input_vertices: u64,
    /// Input faces.
    pub input_faces: u64,
    /// Number of warnings.
    pub warnings: u64,
    /// Largest angle (degrees) between the normals of two patches on a shared boundary.
    pub max_g1_deg: f64,
    /// Mean of that angle over the output vertices on shared boundaries.
    pub mean_g1_deg: f64,
    /// Largest distance between two patches' samples of a shared boundary before welding.
    pub max_boundary_gap: f64,
    /// Wall-clock seconds of the conversion.
    pub seconds: f64,
    // ---- Second version of this struct (validity, quads). Callers compiled against the first
    // version (ending at `seconds`) pass its size and get the fields above only. ----
    /// 1 if the output is valid: a closed two-manifold for closed input, no folds, no flipped
    /// triangles, no self-intersections beyond the input cage's own.
    pub valid: u32,
    /// 1 if the input cage is closed.
    pub input_closed: u32,
    /// Patches with a fold (the parameterisation turns over: a sample's normal opposes its
    /// reference and a neighbouring sample's normal is reversed) or a flipped output triangle.
    pub folds: u64,
    /// Fold sites listed (at most 10; see `gbsurf_report_fold_site`).
    pub fold_sites: u64,
    /// Output triangles whose geometric normal opposes all three vertex normals.
    pub flipped_triangles: u64,
    /// Pairs of output triangles of one shell, sharing no vertex, that meet.
    pub self_intersections: u64,
    /// Pairs of faces of the input cage, sharing no vertex, that meet; `GBSURF_NOT_CHECKED`
    /// (`UINT64_MAX`) when not counted: the cage is checked only when the output self-intersects
    /// (`self_intersections` > 0), the only case in which `valid` depends on it. Always
    /// `GBSURF_NOT_CHECKED` in the report of an offset result (`gbsurf_offset`), which counts
    /// no self-intersections.
    pub input_self_intersections: u64,
    /// Sharp (crease) patch sides built G0.
    pub sharp_edges: u64,
    /// Output quads (quad layout; 0 in the triangle layout, where `triangles` are the faces).
    pub quads: u64,
    /// Largest |mean curvature| times the output's bounding-box diagonal.
    pub max_abs_mean_curvature_times_diagonal: f64,
}

pub(crate) const REPORT_SIZE: u32 = std::mem::size_of::<GbsurfReport>() as u32;
/// Size of the first version of `GbsurfReport` (up to `seconds`), still accepted.
pub(crate) const REPORT_SIZE_V1: u32 = std::mem::offset_of!(GbsurfReport, valid) as u32;

impl GbsurfReport {
    pub(crate) fn from_report(r: &gbsurf::quality::Report, method: u32) -> Self {
        GbsurfReport {
            struct_size: REPORT_SIZE,
            method,
            closed: r.closed as u32,
            two_manifold: r.two_manifold as u32,
            patches: r.patches as u64,
            vertices: r.vertices as u64,
            triangles: r.triangles as u64,
            boundary_edges: r.boundary_edges as u64,
            duplicate_vertices: r.duplicate_vertices as u64,
            zero_area_triangles: r.zero_area_triangles as u64,
            resolution: r.resolution as u64,
            input_vertices: r.input_vertices as u64,
            input_faces: r.input_faces as u64,
            warnings: r.warnings.len() as u64,
            max_g1_deg: r.max_g1_deg,
            mean_g1_deg: r.mean_g1_deg,
            max_boundary_gap: r.max_boundary_gap,
            seconds: r.seconds,
            valid: r.valid as u32,
            input_closed: r.input_closed as u32,
            folds: r.folds as u64,
            fold_sites: r.fold_sites.len() as u64,
            flipped_triangles: r.flipped_triangles as u64,
            self_intersections: r.self_intersections as u64,
            input_self_intersections: r.input_self_intersections.map_or(GBSURF_NOT_CHECKED, |n| n as u64),
            sharp_edges: r.sharp_edges as u64,
            quads: r.quads as u64,
            max_abs_mean_curvature_times_diagonal: r.max_abs_mean_curvature_times_diagonal,
        }
    }
}
