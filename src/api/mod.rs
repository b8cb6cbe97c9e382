//! The pipeline of the main job: polygon control mesh → watertight triangle mesh of a G1
//! surface of GB patches (or, for comparison, of a subdivision surface), with per-vertex quality
//! data and a report. The options are defined in [`crate::options`] (re-exported here), the
//! writers in [`crate::export`].
//!
//! Progress and cancel: the callback ([`Progress`]) is wrapped in one
//! [`crate::progress::Ticker`] that goes down every layer (construction, subdivision levels,
//! tessellation, mesh check, certificates, self-intersection searches, curvatures). Each stage
//! owns a range of [0, 1] (`GB_STAGES`, `SUBDIV_STAGES`, from the time shares measured by
//! `examples/progress_timing.rs` on a 50k-face UV sphere and a 40k-face torus); loops tick per
//! item or per chunk of a parallel loop on the calling thread (never from rayon workers), and the
//! callback is called when the fraction advanced by 1 % or 0.1 s passed. Fractions never
//! decrease, start at 0 and end at 1; after the callback returns false it is never called again
//! and `convert` returns [`ConvertError::Cancelled`] after the running chunk. Measured (release,
//! shared 2-core machine): largest interval between reports ≤ 1.5 s (the setup of the
//! tessellation and the mesh validation are not split yet), cancel latency ≤ 0.35 s.
//!
//! Everything here is plain data (vectors of f64/u32, enums without payload in the options) so the
//! C ABI crate can wrap it one to one.
//!
//! ```no_run
//! use gbsurf::api::{convert_file, ConvertOptions, Method};
//! let opts = ConvertOptions { method: Method::Topology, resolution: 6, ..Default::default() };
//! let conv = convert_file("cube.obj", &opts, None).unwrap();
//! println!("{} vertices, max G1 {}°", conv.mesh.vertex_count(), conv.report.max_g1_deg);
//! ```

mod budget;
mod offset;
mod scale;
mod subdivision;

pub use offset::{offset, offset_surface, piece_point as offset_piece_point, CuspSite, Offset, OffsetError, OffsetOptions, OffsetPiece, OffsetReport};
pub use budget::{estimate_output, OutputEstimate, BASE_BYTES, GB_BYTES_PER_SAMPLE, GB_TRIANGLE_BYTES_PER_SAMPLE, SUBDIV_BYTES_PER_VERTEX};

pub use crate::options::{ConvertOptions, Method, OptionError, OptionValue, Twist, MAX_LEVELS, MAX_RESOLUTION};

use crate::construct::{ConstructError, Surface};
use crate::mesh::{HalfEdgeMesh, MeshError, PolyMesh};
use crate::quality::Report;
use crate::tessellate::{SurfaceMesh, TessellateError};
use crate::progress::{Cancelled, Ticker};
use std::path::Path;
use subdivision::subdivision_mesh;

/// Ends of the stages of the GB methods in the overall progress range: construction,
/// tessellation (with welding and the fold test), mesh check, self-intersection search, input
/// cage search (the rest: report). Measured time shares on a 50k-face UV sphere and a 40k-face
/// quad torus at resolution 4 (see the module doc).
const GB_STAGES: [f32; 5] = [0.08, 0.45, 0.48, 0.95, 0.99];
/// The same for the subdivision methods: subdivision (with triangulation, normals and
/// curvatures), mesh check, self-intersection search, cage search.
const SUBDIV_STAGES: [f32; 5] = [0.3, 0.3, 0.33, 0.95, 0.99];

impl From<Cancelled> for ConvertError {
    fn from(_: Cancelled) -> Self {
        ConvertError::Cancelled
    }
}

/// Why a conversion failed. Every variant names the offending element or option.
#[derive(Debug, thiserror::Error)]
pub enum ConvertError {
    /// An option value out of range (`name` is the command-line name).
    #[error("invalid --{name} {value}: {reason}")]
    InvalidOption { name: &'static str, value: String, reason: String },
    /// The input mesh was rejected (names the vertex/face/edge and source line).
    #[error("{0}")]
    Mesh(#[from] MeshError),
    /// The surface construction failed (names the patch, face, vertex or curve).
    #[error("construction: {0}")]
    Construct(crate::construct::ConstructError),
    /// The subdivision failed (names the face or vertex).
    #[error("subdivision: {0}")]
    Subdiv(String),
    /// The tessellation failed (names the patch).
    #[error("tessellation: {0}")]
    Tessellate(TessellateError),
    /// An output path was refused before anything was written (names both flags).
    #[error("{0}")]
    OutputPath(crate::export::OutputPathError),
    /// Reading or writing a file failed.
    #[error("i/o error on {path}: {message}")]
    Io { path: String, message: String },
    /// The progress callback returned false.
    #[error("cancelled")]
    Cancelled,
    /// The estimated peak memory ([`estimate_output`]) exceeds `--max-memory-mb`; nothing was
    /// computed.
    #[error(
        "output too large: {method} would make about {vertices} output vertices and need about {} MiB, above the limit of {limit_mb} MiB; lower --resolution or --levels, or raise --max-memory-mb (C ABI: GbsurfOptions.max_memory_mb; Blender: Memory Limit)",
        bytes.div_ceil(1 << 20)
    )]
    OutputTooLarge { method: &'static str, vertices: u64, bytes: u64, limit_mb: u64 },
    /// An output buffer could not be allocated (`what` names it).
    #[error("out of memory: could not allocate {bytes} bytes for {what}; lower --resolution or --levels")]
    OutOfMemory { what: &'static str, bytes: u64 },
    /// The control mesh's bounding-box extent is outside [`crate::limits::EXTENT_RANGE`]: the
    /// curvatures of the output would overflow or vanish in f64.
    #[error("control mesh extent {extent:e} is outside the supported range {min:e}..{max:e} (curvature would overflow f64); rescale the mesh")]
    ScaleOutOfRange { extent: f64, min: f64, max: f64 },
}

impl From<OptionError> for ConvertError {
    fn from(e: OptionError) -> Self {
        ConvertError::InvalidOption { name: e.name, value: e.value, reason: e.reason }
    }
}

impl From<crate::export::ExportError> for ConvertError {
    fn from(e: crate::export::ExportError) -> Self {
        use crate::export::{ExportError, MeshFormat};
        match e {
            ExportError::UnknownFormat { path } => ConvertError::InvalidOption {
                name: "output",
                value: path.display().to_string(),
                reason: format!("the output extension must be {}", MeshFormat::EXTENSIONS_TEXT),
            },
            ExportError::OutputPath(e) => ConvertError::OutputPath(e),
            ExportError::Io { path, source } => ConvertError::Io { path: path.display().to_string(), message: source.to_string() },
        }
    }
}

impl From<crate::export::OutputPathError> for ConvertError {
    fn from(e: crate::export::OutputPathError) -> Self {
        ConvertError::OutputPath(e)
    }
}

impl From<TessellateError> for ConvertError {
    fn from(e: TessellateError) -> Self {
        match e {
            TessellateError::Cancelled => ConvertError::Cancelled,
            TessellateError::OutOfMemory { what, bytes } => ConvertError::OutOfMemory { what, bytes },
            e => ConvertError::Tessellate(e),
        }
    }
}

/// The result of [`convert`].
#[derive(Clone, Debug, PartialEq)]
pub struct Conversion {
    /// The welded output triangle mesh with per-vertex normals, patch indices, curvatures and G1
    /// deviation (the last four empty without [`ConvertOptions::quality_arrays`]).
    pub mesh: SurfaceMesh,
    /// The exact surface (patches, adjacency, curve network); `None` for subdivision methods and
    /// without [`ConvertOptions::keep_surface`].
    pub surface: Option<Surface>,
    /// The report (see [`crate::quality::Report`]).
    pub report: Report,
    /// Human-readable warnings (also in `report.warnings`).
    pub warnings: Vec<String>,
}

/// Progress callback: receives the fraction done in [0, 1]; returning false cancels.
pub type Progress<'a> = Option<&'a mut dyn FnMut(f32) -> bool>;

/// Converts a polygon control mesh into a welded triangle mesh (see the module doc).
///
/// Steps: option check, mesh validation (isolated vertices dropped with a warning), then
/// - dual/topology: construction of the GB surface, tessellation at `resolution` (parallel over
///   patches), welding, boundary gap and G1 measurement;
/// - doo-sabin/catmull-clark: `levels` subdivision steps, fan triangulation of every face,
///   area-weighted normals, discrete curvatures ([`crate::quality::discrete_curvature`]), G1 = 0,
///   patch index = the input face each output face descends from;
///
/// and finally the mesh checks of [`crate::quality::check_mesh`] for the report.
/// `progress` receives the fraction done; returning false stops with [`ConvertError::Cancelled`].
pub fn convert(mesh: &PolyMesh, options: &ConvertOptions, progress: Progress<'_>) -> Result<Conversion, ConvertError> {
    let start = std::time::Instant::now();
    options.validate()?;
    let mut ticker = Ticker::new(progress);
    ticker.report(0.0)?;
    let he = crate::mesh::HalfEdgeMesh::from_polymesh(mesh)?;
    convert_valid(&he, mesh, options, &mut ticker, start, true)
}

/// [`convert`] without the validity checks (no fold test, no self-intersection counts: the
/// report's `folds`, `flipped_triangles` and `self_intersections` stay 0,
/// `input_self_intersections` `None` and `valid` false). Only for measuring what the checks cost (benches/convert.rs).
#[doc(hidden)]
pub fn convert_unchecked(mesh: &PolyMesh, options: &ConvertOptions) -> Result<Conversion, ConvertError> {
    let start = std::time::Instant::now();
    options.validate()?;
    let he = crate::mesh::HalfEdgeMesh::from_polymesh(mesh)?;
    convert_valid(&he, mesh, options, &mut Ticker::none(), start, false)
}

fn convert_valid(
    he: &HalfEdgeMesh,
    mesh: &PolyMesh,
    options: &ConvertOptions,
    ticker: &mut Ticker<'_>,
    start: std::time::Instant,
    checks: bool,
) -> Result<Conversion, ConvertError> {
    let mut warnings: Vec<String> = he.warnings().iter().map(|w| w.to_string()).collect();
    let mut report = Report {
        method: options.method.name().to_string(),
        input_vertices: mesh.positions.len(),
        input_faces: mesh.faces.len(),
        ..Default::default()
    };
    let estimate = estimate_output(he, options);
    if estimate.bytes > options.max_memory_mb.saturating_mul(1 << 20) {
        return Err(ConvertError::OutputTooLarge {
            method: options.method.name(),
            vertices: estimate.vertices,
            bytes: estimate.bytes,
            limit_mb: options.max_memory_mb,
        });
    }
    let norm = scale::Normalisation::of(he.positions()).map_err(|e| ConvertError::ScaleOutOfRange {
        extent: e.extent,
        min: crate::limits::EXTENT_RANGE.0,
        max: crate::limits::EXTENT_RANGE.1,
    })?;
    let normalised;
    let (he, mesh) = if norm.is_identity() {
        (he, mesh)
    } else {
        normalised = norm.apply(he, mesh);
        (&normalised.0, &normalised.1)
    };
    let build = builder(options.method);
    if he.has_creases() && !options.method.is_patch_method() {
        warnings.push(format!(
            "creases are ignored by the {} method (the dual and topology structures build them)",
            options.method.name()
        ));
    }
    let (out, surface) = if let Some(build) = build {
        let [construct, tessellate] = [GB_STAGES[0], GB_STAGES[1]];
        ticker.stage(0.0, construct)?;
        let surface = build(he, options, ticker).map_err(|e| match e {
            ConstructError::Cancelled => ConvertError::Cancelled,
            e => ConvertError::Construct(e),
        })?;
        warnings.extend(surface.warnings.iter().cloned());
        ticker.stage(construct, tessellate)?;
        let mut sub = |f: f32| ticker.report(construct + (tessellate - construct) * f).is_ok();
        let (m, stats) = crate::tessellate::surface::tessellate_surface_checked(
            &surface,
            options.sampling(),
            options.weights,
            checks,
            options.cage_maps,
            options.quality_arrays,
            Some(&mut sub),
        )?;
        report.count_sides(surface.patches.iter().map(|p| p.sides()));
        report.patches = surface.patches.len();
        report.resolution = options.resolution;
        report.max_boundary_gap = stats.max_boundary_gap;
        report.max_g1_deg = stats.max_g1_deg;
        report.mean_g1_deg = stats.mean_g1_deg;
        report.sharp_edges = stats.crease_sides;
        // Checked in the tessellation pass, on its own samples (crate::tessellate::fold).
        let folds = crate::quality::Folds::of_tessellation(&m);
        report.folds = folds.patches;
        report.fold_sites = folds.sites;
        report.flipped_triangles = folds.flipped_triangles;
        let (at_cage, first) = crate::quality::validity::folds_at_cage_folds(&m, &surface.sources, he);
        if let Some(v) = first {
            warnings.push(format!(
                "{at_cage} of the {} folded patches lie where the cage itself turns back (an incident face more than 90° from the vertex normal; the first at vertex {}): smoothing the cage there is the likely fix",
                report.folds,
                v
            ));
        }
        // Freed here unless the caller keeps it (the checks below read only the mesh).
        (m, options.keep_surface.then_some(surface))
    } else {
        ticker.stage(0.0, SUBDIV_STAGES[0])?;
        let input_face = |f: u32| he.input_face(crate::mesh::FaceId(f)) as u32;
        let (m, faces) = subdivision_mesh(&he.to_polymesh(), &input_face, options, ticker)?;
        report.count_sides(faces.iter().map(Vec::len));
        report.patches = faces.len();
        report.resolution = options.levels as usize;
        (m, None)
    };
    let (mut out, mut surface) = (out, surface);
    report.max_abs_mean_curvature_times_diagonal =
        crate::quality::validity::max_abs_mean_curvature_times_diagonal(&out.positions, &out.mean_curvature);
    if !options.quality_arrays {
        // Their figures are in the report: freed before the checks take their memory.
        for v in [&mut out.mean_curvature, &mut out.gaussian_curvature, &mut out.g1_deviation_deg] {
            *v = Vec::new();
        }
        (out.patch, out.triangle_patch) = (Vec::new(), Vec::new());
    }
    let [_, check_start, self_start, cage_start, cage_end] = if build.is_some() { GB_STAGES } else { SUBDIV_STAGES };
    ticker.stage(check_start, self_start)?;
    let check = crate::quality::check_mesh_ticked(&out.positions, &out.triangles, ticker)?;
    report.vertices = out.positions.len();
    report.triangles = out.triangles.len();
    report.quads = out.quads.len();
    report.layout = out.layout().to_string();
    report.closed = check.is_closed_manifold();
    report.two_manifold = check.is_two_manifold();
    report.boundary_edges = check.boundary_edges;
    report.duplicate_vertices = check.duplicate_vertices;
    report.zero_area_triangles = check.zero_area_triangles;
    report.input_closed = he.is_closed();
    if checks {
        ticker.stage(self_start, cage_start)?;
        report.self_intersections = crate::quality::validity::mesh_self_intersections_checked(&out, &check, ticker)?;
        ticker.stage(cage_start, cage_end)?;
        // The cage's own intersections matter only to excuse the output's (Report::validity_problems):
        // counted only when there are some. A face with holes is checked as its split pieces (the
        // outer loop alone covers the holes).
        if report.self_intersections > 0 {
            let split;
            let cage = if mesh.holes.is_empty() {
                mesh
            } else {
                split = he.to_polymesh();
                &split
            };
            report.input_self_intersections = Some(crate::quality::cage_self_intersections_ticked(cage, ticker)?);
        }
    }
    ticker.stage(cage_end, 1.0)?;
    if checks {
        report.set_valid();
    }
    if !check.is_two_manifold() {
        warnings.push(format!(
            "output is not a consistently oriented two-manifold: {} non-manifold edges, {} non-manifold vertices, {} inconsistent edges",
            check.non_manifold_edges, check.non_manifold_vertices, check.inconsistent_edges
        ));
    }
    let problems = report.validity_problems();
    if !problems.is_empty() {
        warnings.push(format!("output is not valid: {}", problems.join("; ")));
    }
    if !norm.is_identity() {
        norm.restore_mesh(&mut out);
        if let Some(s) = surface.as_mut() {
            norm.restore_surface(s);
        }
        report.max_boundary_gap = norm.restore_length(report.max_boundary_gap);
    }
    report.warnings = warnings.clone();
    report.seconds = start.elapsed().as_secs_f64();
    ticker.report(1.0)?;
    Ok(Conversion { mesh: out, surface, report, warnings })
}

type Build = fn(&HalfEdgeMesh, &ConvertOptions, &mut Ticker<'_>) -> Result<Surface, ConstructError>;

/// The construction step of a GB method (`None` for the subdivision methods).
fn builder(method: Method) -> Option<Build> {
    match method {
        Method::Dual => Some(crate::construct::build_dual_ticked),
        Method::Topology => Some(crate::construct::build_topology_ticked),
        Method::DooSabin | Method::CatmullClark => None,
    }
}

/// The construction step of [`convert`] alone: option check, mesh validation, scale
/// normalisation, [`crate::construct::build_dual`] or [`crate::construct::build_topology`] by
/// `options.method`, and the surface restored to the input's coordinates. For consumers of the
/// exact surface (e.g. [`offset`]). A subdivision method is an [`ConvertError::InvalidOption`].
pub fn build_surface(mesh: &PolyMesh, options: &ConvertOptions) -> Result<Surface, ConvertError> {
    options.validate()?;
    let Some(build) = builder(options.method) else {
        return Err(ConvertError::InvalidOption {
            name: "method",
            value: options.method.name().to_string(),
            reason: "an exact surface needs a GB method (dual or topology)".to_string(),
        });
    };
    let he = crate::mesh::HalfEdgeMesh::from_polymesh(mesh)?;
    let norm = scale::Normalisation::of(he.positions()).map_err(|e| ConvertError::ScaleOutOfRange {
        extent: e.extent,
        min: crate::limits::EXTENT_RANGE.0,
        max: crate::limits::EXTENT_RANGE.1,
    })?;
    let mut surface = if norm.is_identity() {
        build(&he, options, &mut Ticker::none()).map_err(ConvertError::Construct)?
    } else {
        let (nhe, _) = norm.apply(&he, mesh);
        build(&nhe, options, &mut Ticker::none()).map_err(ConvertError::Construct)?
    };
    if !norm.is_identity() {
        norm.restore_surface(&mut surface);
    }
    Ok(surface)
}

/// Reads a mesh file (OBJ, OFF, PLY, STL by extension) and validates it; errors name the element
/// and its source line. Returns the mesh as read (validation happens again in [`convert`], which
/// then drops isolated vertices with a warning).
pub fn read_mesh(path: impl AsRef<Path>) -> Result<PolyMesh, ConvertError> {
    let (mesh, map) = crate::mesh::read_polymesh(path)?;
    crate::mesh::HalfEdgeMesh::from_polymesh(&mesh).map_err(|e| e.with_source(&map))?;
    Ok(mesh)
}

/// [`read_mesh`] then [`convert`].
/// Errors and warnings name the source line of the element.
pub fn convert_file(path: impl AsRef<Path>, options: &ConvertOptions, progress: Progress<'_>) -> Result<Conversion, ConvertError> {
    let start = std::time::Instant::now();
    options.validate()?;
    let mut ticker = Ticker::new(progress);
    ticker.report(0.0)?;
    let (mesh, map) = crate::mesh::read_polymesh(path)?;
    let mut he = crate::mesh::HalfEdgeMesh::from_polymesh(&mesh).map_err(|e| e.with_source(&map))?;
    he.annotate_warnings(&map);
    convert_valid(&he, &mesh, options, &mut ticker, start, true)
}

#[allow(unused)]
fn _assert_send_sync() {
    fn f<T: Send + Sync>() {}
    f::<ConvertOptions>();
    f::<Conversion>();
    f::<ConvertError>();
}
