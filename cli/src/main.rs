//! The `gbsurf` command line.
//!
//! `gbsurf convert IN -o OUT [options]`: control mesh (OBJ/OFF/PLY/STL; with the cargo feature
//! `openmesh` also OpenMesh's OM) → welded triangle mesh of the smooth surface (OBJ/PLY/STL, or OM
//! through OpenMesh, by the extension of OUT; PLY carries per-vertex `patch`,
//! `mean_curvature`, `gaussian_curvature`, `g1_deviation`). Optional outputs: `--curves` (the
//! curve network as OBJ polylines of the Bézier control polygons), `--nets` (the control nets as
//! OBJ), `--patches FILE.json` (exact description; `.gbp` files beside it for GB patches that have
//! one), `--report FILE.json`. Before any work every output path is checked: none may be the input
//! or another output (compared after resolving `.`, `..` and links, and by device and inode), and
//! each must go into an existing directory and not be a directory (`gbsurf::export::check_output_paths`).
//! Every output is written completely to a temporary file beside its
//! target before any target is replaced, so a failed conversion or a failed write leaves all
//! targets untouched; only a failing rename at the very end (see `gbsurf::export::AtomicFiles`)
//! can leave the earlier targets replaced and the later ones not.
//!
//! The conversion flags are those of `gbsurf::ConvertOptions`: their values are parsed by the
//! core's `FromStr` impls, and an absent flag keeps the value of `ConvertOptions::default()`
//! (shown in `--help`).
//!
//! `gbsurf eval-gbp FILE.gbp [--weights squared|linear]`: reads `u v` lines on stdin (domain
//! coordinates inside the domain polygon of `gbsurf::gb::Domain`; blank lines are skipped) and
//! prints `x y z` per line with 17 significant digits.
//!
//! `gbsurf tessellate-gbp FILE.gbp -o OUT.obj [--resolution N] [--weights …]`: one patch as a
//! triangle mesh with normals (Wavefront OBJ); written to a temporary file and renamed, so
//! nothing is written on failure.
//!
//! `gbsurf ph5`, `gbsurf ph-spline`, `gbsurf pn-grid`: exact offsets of PH curves and PN surfaces
//! (module `offsets`).
//!
//! Errors print one line and exit with status 1 (2 for usage errors).

// The C ABI is the workspace's only unsafe code; the CLI has none.
#![forbid(unsafe_code)]
use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use gbsurf::api::{self, ConvertError};
use gbsurf::export::{self, AtomicFiles, FlagPath, MeshFormat, WriteMesh};
use gbsurf::gb::gbp::load_gbp;
use gbsurf::gb::GbPatch;
use gbsurf::options::{check_resolution, check_slice_count, check_stripes, ConvertOptions, Layout, Method, Middle, OptionValue, Twist, WeightForm};
use gbsurf::tessellate::patch::tessellate_gb;
use gbsurf::DVec2;
use std::io::{BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod offsets;

#[derive(Parser)]
#[command(name = "gbsurf", version, about = "Smooth G1 surfaces of n-sided Generalized Bézier patches from polygon control meshes")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Convert a polygon control mesh into a smooth surface, tessellated into one watertight mesh.
    Convert(ConvertArgs),
    /// Evaluate a .gbp patch at domain points `u v` read from stdin, one per line.
    EvalGbp {
        /// The patch (.gbp, format of the `transfinite` library).
        file: PathBuf,
        /// Correction-weight form.
        #[arg(long, value_parser = choice::<WeightForm>())]
        weights: Option<WeightForm>,
    },
    /// Tessellate a .gbp patch into a triangle mesh (OBJ with normals).
    TessellateGbp {
        /// The patch (.gbp).
        file: PathBuf,
        /// Output OBJ file.
        #[arg(short, long)]
        output: PathBuf,
        /// Samples per side (the mesh has n·r² triangles).
        #[arg(short, long, default_value_t = 16)]
        resolution: usize,
        /// Correction-weight form.
        #[arg(long, value_parser = choice::<WeightForm>())]
        weights: Option<WeightForm>,
    },
    /// Elevate a .gbp patch to degree D (boundary curves and cross-derivatives kept exactly).
    GbpElevate {
        /// The patch (.gbp).
        file: PathBuf,
        /// The target degree D (at least the patch's degree).
        #[arg(long)]
        to: usize,
        /// Output .gbp file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Planar PH quintic Hermite interpolants of two points and derivatives, as JSON on stdout
    /// (the chosen one at the top level, all four under `solutions`), with `--offset` their exact
    /// rational offsets and cusps.
    Ph5(offsets::Ph5Args),
    /// A planar PH quintic spline through the points of a text file, written as JSON (per segment
    /// control points and arc length; with `--offset` the exact offsets).
    #[command(after_help = offsets::POINTS_FORMAT)]
    PhSpline(offsets::PhSplineArgs),
    /// A PN surface interpolating a grid of points with normals (JSON in), written as the exact
    /// rational form of every patch (JSON out).
    PnGrid(offsets::PnGridArgs),
    /// The exact offset of the GB surface of a control mesh, through PN patches: a triangle mesh
    /// of the offset (or with --shell a closed solid), a report and the rational patches.
    Offset(offsets::OffsetArgs),
}

/// The values of an option enum of the core as possible values, parsed by its `FromStr`.
fn choice<T: OptionValue + Send + Sync>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::ALL.iter().map(|v| v.name())).try_map(|s| s.parse::<T>())
}

/// `on` / `off` as a bool.
fn on_off() -> impl TypedValueParser<Value = bool> {
    PossibleValuesParser::new(["on", "off"]).map(|s| s == "on")
}

fn on_off_name(b: bool) -> &'static str {
    if b {
        "on"
    } else {
        "off"
    }
}

/// The flags of [`ConvertOptions`]: a flag that is not given keeps the value of
/// `ConvertOptions::default()`.
#[derive(clap::Args)]
struct OptionFlags {
    /// Surface structure: dual (patch per vertex), topology (patch per face), or a subdivision
    /// scheme for comparison.
    #[arg(long, value_parser = choice::<Method>())]
    method: Option<Method>,
    /// Output faces: quads (n·N² per n-sided patch, like Subdivision Surface level L at
    /// N = 2^(L−1)) or triangles. STL output is always triangles.
    #[arg(long, value_parser = choice::<Layout>())]
    layout: Option<Layout>,
    /// Samples per patch side (triangles: n·N² per n-sided patch) or per half side (quads).
    #[arg(long)]
    resolution: Option<usize>,
    /// Fullness κ ∈ [0, 1) of the dual curves.
    #[arg(long)]
    fullness: Option<f64>,
    /// Tile split ratio w > 2 (topology structure).
    #[arg(long)]
    tile_depth: Option<f64>,
    /// Twist construction.
    #[arg(long, value_parser = choice::<Twist>())]
    twist: Option<Twist>,
    /// Factor on the middle constraint of the direction blends.
    #[arg(long)]
    mid_scale: Option<f64>,
    /// Middle constraint of the direction blends: the seed's rule or the fair one.
    #[arg(long, value_parser = choice::<Middle>())]
    middle: Option<Middle>,
    /// Project onto best-fit planes.
    #[arg(long, value_parser = on_off())]
    best_plane: Option<bool>,
    /// Correction weights of the GB patches.
    #[arg(long, value_parser = choice::<WeightForm>())]
    weights: Option<WeightForm>,
    /// Subdivision levels (doo-sabin, catmull-clark).
    #[arg(long)]
    levels: Option<u32>,
    /// Memory bound in MiB: a conversion estimated to need more is refused before any work.
    #[arg(long)]
    max_memory_mb: Option<u64>,
}

impl OptionFlags {
    /// `options` with every given flag applied.
    fn apply(&self, mut options: ConvertOptions) -> ConvertOptions {
        fn set<T: Copy>(slot: &mut T, flag: Option<T>) {
            if let Some(v) = flag {
                *slot = v;
            }
        }
        // No `..`: a new option is a compile error here until it has a flag (or, as `cage_maps`,
        // `keep_surface` and `quality_arrays`, is set from the outputs in `convert_input`).
        let ConvertOptions { method, layout, resolution, fullness, tile_depth, twist, mid_scale, middle, best_plane, weights, levels, max_memory_mb, cage_maps: _, keep_surface: _, quality_arrays: _ } =
            &mut options;
        set(method, self.method);
        set(layout, self.layout);
        set(resolution, self.resolution);
        set(fullness, self.fullness);
        set(tile_depth, self.tile_depth);
        set(twist, self.twist);
        set(mid_scale, self.mid_scale);
        set(middle, self.middle);
        set(best_plane, self.best_plane);
        set(weights, self.weights);
        set(levels, self.levels);
        set(max_memory_mb, self.max_memory_mb);
        options
    }

    /// `(argument id, value)` of every flag for `options`, for the defaults shown in `--help`.
    fn shown(options: &ConvertOptions) -> [(&'static str, String); 12] {
        let ConvertOptions { method, layout, resolution, fullness, tile_depth, twist, mid_scale, middle, best_plane, weights, levels, max_memory_mb, cage_maps: _, keep_surface: _, quality_arrays: _ } =
            *options;
        [
            ("method", method.to_string()),
            ("layout", layout.to_string()),
            ("resolution", resolution.to_string()),
            ("fullness", fullness.to_string()),
            ("tile_depth", tile_depth.to_string()),
            ("twist", twist.to_string()),
            ("mid_scale", mid_scale.to_string()),
            ("middle", middle.to_string()),
            ("best_plane", on_off_name(best_plane).to_string()),
            ("weights", weights.to_string()),
            ("levels", levels.to_string()),
            ("max_memory_mb", max_memory_mb.to_string()),
        ]
    }
}

/// Appends `[default: value]` to the help of argument `id` (the value is not set: the flag stays
/// absent and the core's default applies).
fn show_default(cmd: clap::Command, id: &str, value: &str) -> clap::Command {
    cmd.mut_arg(id, |a| {
        let help = a.get_help().map(|h| h.to_string()).unwrap_or_default();
        a.help(format!("{help} [default: {value}]"))
    })
}

/// The command line with the defaults of the core shown in the help.
fn command() -> clap::Command {
    let weights = WeightForm::default().to_string();
    Cli::command()
        .mut_subcommand("convert", |mut c| {
            for (id, value) in OptionFlags::shown(&ConvertOptions::default()) {
                c = show_default(c, id, &value);
            }
            c
        })
        .mut_subcommand("eval-gbp", |c| show_default(c, "weights", &weights))
        .mut_subcommand("tessellate-gbp", |c| show_default(c, "weights", &weights))
}

#[derive(clap::Args)]
struct ConvertArgs {
    /// Input control mesh (.obj, .off, .ply, .stl).
    input: PathBuf,
    /// Output mesh (.obj, .ply: quads or triangles per --layout; .stl: triangles).
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    options: OptionFlags,
    /// Write the curve network (OBJ polylines of the Bézier control polygons).
    #[arg(long)]
    curves: Option<PathBuf>,
    /// Write the control nets of all patches (OBJ).
    #[arg(long)]
    nets: Option<PathBuf>,
    /// Write the exact surface as JSON, with .gbp files beside it for GB patches.
    #[arg(long)]
    patches: Option<PathBuf>,
    /// Elevate every patch of the exact description (--patches) to this common degree: boundaries
    /// and cross-derivatives stay exact, so G1 is kept, while the interiors change slightly (GB
    /// patches only, i.e. the dual method). The tessellated output (-o) is of the surface as
    /// constructed, not of the elevated patches. `.gbp` files are written up to degree 40.
    #[arg(long, requires = "patches")]
    degree: Option<usize>,
    /// Write the report (JSON).
    #[arg(long)]
    report: Option<PathBuf>,
    /// Write the isophote display (seed 000 §5.2): the surface as PLY with per-vertex `isophote`
    /// (n·L) and `stripe` (zebra band coordinate; its integer part's parity is the stripe colour).
    #[arg(long)]
    isophotes: Option<PathBuf>,
    /// Light direction L of the isophotes, `x,y,z`.
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,1")]
    light: gbsurf::DVec3,
    /// Number of isophote stripes over the angle range 0..180°.
    #[arg(long, default_value_t = 16)]
    stripes: u32,
    /// Write planar slices of the surface (seed 000 §5.2) as OBJ polylines (`l` lines).
    #[arg(long)]
    slices: Option<PathBuf>,
    /// Normal of the slicing planes, `x,y,z`.
    #[arg(long, value_parser = parse_vec3, default_value = "0,0,1")]
    slice_normal: gbsurf::DVec3,
    /// Number of evenly spaced slicing planes across the surface.
    #[arg(long, default_value_t = 10)]
    slice_count: usize,
    /// No progress bar, no summary (the line saying the output is not valid is still printed).
    #[arg(long)]
    quiet: bool,
    /// Fail (exit status 1, no output written) when the report says the output is not valid
    /// (folds, self-intersections beyond the input's, open or non-manifold output).
    #[arg(long)]
    strict: bool,
}

impl ConvertArgs {
    /// Every output path given, with its flag (`-o` first).
    fn outputs(&self) -> Vec<FlagPath<'_>> {
        let optional = [
            ("--curves", &self.curves),
            ("--nets", &self.nets),
            ("--patches", &self.patches),
            ("--report", &self.report),
            ("--isophotes", &self.isophotes),
            ("--slices", &self.slices),
        ];
        let given = optional.into_iter().filter_map(|(flag, p)| p.as_deref().map(|p| FlagPath::new(flag, p)));
        std::iter::once(FlagPath::new("-o", &self.output)).chain(given).collect()
    }
}

/// Why `convert` failed: the conversion itself, or `--strict` with an invalid output.
#[derive(Debug)]
enum RunError {
    Convert(ConvertError),
    Invalid(String),
}

impl From<ConvertError> for RunError {
    fn from(e: ConvertError) -> Self {
        RunError::Convert(e)
    }
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Convert(e) => e.fmt(f),
            RunError::Invalid(problems) => write!(f, "output is not valid (--strict): {problems}"),
        }
    }
}

fn run_convert(args: &ConvertArgs) -> Result<(), RunError> {
    let (mut conv, options, format) = convert_input(args)?;
    let problems = conv.report.validity_problems();
    if !problems.is_empty() {
        if args.strict {
            return Err(RunError::Invalid(problems.join("; ")));
        }
        if args.quiet {
            eprintln!("warning: output is not valid: {}", problems.join("; "));
        }
    }
    write_outputs(args, &mut conv, &options, format)?;
    // Everything is written and renamed: the process ends right after this, and the operating
    // system takes back the output arrays at once, where dropping them would walk and free them
    // first (about 10 ms at 640k output vertices).
    std::mem::forget(conv);
    Ok(())
}

/// Reads and converts the input (with a progress bar unless `--quiet`); also returns the options
/// and the output format (`None`: through OpenMesh), checked before any work.
fn convert_input(args: &ConvertArgs) -> Result<(api::Conversion, ConvertOptions, Option<MeshFormat>), ConvertError> {
    // The output format (its error is reported after the options', as before).
    let format = if openmesh_io::handles(&args.output) { Ok(None) } else { MeshFormat::of(&args.output).map(Some) };
    // No output of the command line reads the cage maps: not building them saves 72 bytes per
    // output vertex of peak memory (quad layout). The exact surface is kept only for the outputs
    // written from it, the quality arrays only for PLY (see `drop_unneeded`).
    let options = ConvertOptions {
        cage_maps: false,
        keep_surface: args.curves.is_some() || args.nets.is_some() || args.patches.is_some(),
        quality_arrays: matches!(format, Ok(Some(MeshFormat::Ply))),
        ..args.options.apply(ConvertOptions::default())
    };
    options.validate()?;
    check_stripes(args.stripes)?;
    check_slice_count(args.slice_count)?;
    // Check the output extension and every output path before doing any work.
    let format = format?;
    let inputs = [FlagPath::new("input", &args.input)];
    export::check_output_paths(&inputs, &args.outputs())?;
    let bar = (!args.quiet).then(|| {
        let bar = indicatif::ProgressBar::new(1000);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{spinner} converting [{bar:40}] {percent:>3}% {elapsed}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        bar
    });
    let mut cb = |f: f32| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
        true
    };
    let result = if openmesh_io::handles(&args.input) {
        openmesh_io::read(&args.input).and_then(|mesh| api::convert(&mesh, &options, Some(&mut cb)))
    } else {
        api::convert_file(&args.input, &options, Some(&mut cb))
    };
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    Ok((result?, options, format))
}

/// Writes the output mesh and every optional output (all or none, see `AtomicFiles`), then the
/// summary and the warnings unless `--quiet`.
fn write_outputs(args: &ConvertArgs, conv: &mut api::Conversion, options: &ConvertOptions, format: Option<MeshFormat>) -> Result<(), ConvertError> {
    // The .gbp files beside --patches are known only now: check the whole set again.
    let inputs = [FlagPath::new("input", &args.input)];
    let patch_files = match &args.patches {
        Some(path) => {
            let surface = need_surface(&conv.surface, options, "patches")?;
            let elevated = match args.degree {
                Some(degree) => Some(surface.with_common_degree(degree).map_err(|e| ConvertError::InvalidOption {
                    name: "degree",
                    value: degree.to_string(),
                    reason: e.to_string(),
                })?),
                None => None,
            };
            export::patch_files(elevated.as_ref().unwrap_or(surface), path)
        }
        None => Vec::new(),
    };
    let mut outputs = args.outputs();
    let beside = patch_files.iter().filter(|(file, _)| Some(file) != args.patches.as_ref());
    outputs.extend(beside.map(|(file, _)| FlagPath::new("--patches", file)));
    export::check_output_paths(&inputs, &outputs)?;
    drop_unneeded(args, conv, format);
    let conv = &*conv;
    // All outputs go to temporaries first; dropping `files` on an error removes them.
    let mut files = AtomicFiles::new();
    match format {
        Some(format) => files.add_with(&args.output, |w| conv.mesh.write_format(format, w))?,
        None => openmesh_io::add(&mut files, &conv.mesh, &args.output)?,
    }
    if let Some(path) = &args.curves {
        files.add(path, export::curves_obj(need_surface(&conv.surface, options, "curves")?).as_bytes())?;
    }
    if let Some(path) = &args.nets {
        files.add(path, export::nets_obj(need_surface(&conv.surface, options, "nets")?).as_bytes())?;
    }
    for (file, bytes) in &patch_files {
        files.add(file, bytes)?;
    }
    if let Some(path) = &args.report {
        files.add(path, conv.report.to_json().as_bytes())?;
    }
    if let Some(path) = &args.isophotes {
        files.add_with(path, |w| export::write_isophotes_ply(w, &conv.mesh, args.light, args.stripes))?;
    }
    if let Some(path) = &args.slices {
        let cuts = gbsurf::quality::slices(&conv.mesh.positions, &conv.mesh.triangles, args.slice_normal, args.slice_count)?;
        files.add(path, export::slices_obj(&cuts).as_bytes())?;
    }
    files.commit()?;
    if !args.quiet {
        let r = &conv.report;
        let faces = if r.quads > 0 { format!("{} quads", r.quads) } else { format!("{} triangles", r.triangles) };
        eprintln!(
            "{}: {} patches, {} vertices, {faces}, closed {}, max G1 {:.3e}°, max gap {:.3e}, {:.3} s",
            r.method, r.patches, r.vertices, r.closed, r.max_g1_deg, r.max_boundary_gap, r.seconds
        );
        for w in &conv.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(())
}

/// The exact surface, which `--what` needs (an error for the subdivision methods).
fn need_surface<'a>(surface: &'a Option<gbsurf::construct::Surface>, options: &ConvertOptions, what: &str) -> Result<&'a gbsurf::construct::Surface, ConvertError> {
    surface.as_ref().ok_or_else(|| ConvertError::InvalidOption {
        name: "method",
        value: options.method.to_string(),
        reason: format!("--{what} needs a patch method (dual or topology)"),
    })
}

/// Frees what none of the chosen outputs reads, so that only the data being written stay
/// resident while writing: the exact surface (kept for `--curves` and `--nets`; `--patches` is
/// encoded before this), the per-triangle patch ids (no output writes them), the per-vertex patch
/// ids, curvatures and G1 deviation (only the PLY output writes them) and the normals (unused by
/// STL and `--slices`; kept for `--isophotes`).
fn drop_unneeded(args: &ConvertArgs, conv: &mut api::Conversion, format: Option<MeshFormat>) {
    if args.curves.is_none() && args.nets.is_none() {
        conv.surface = None;
    }
    let mesh = &mut conv.mesh;
    mesh.triangle_patch = Vec::new();
    if format != Some(MeshFormat::Ply) {
        mesh.patch = Vec::new();
        mesh.mean_curvature = Vec::new();
        mesh.gaussian_curvature = Vec::new();
        mesh.g1_deviation_deg = Vec::new();
    }
    if format == Some(MeshFormat::Stl) && args.isophotes.is_none() {
        mesh.normals = Vec::new();
    }
}

/// Parses `x,y,z` into a non-zero vector.
fn parse_vec3(text: &str) -> Result<gbsurf::DVec3, String> {
    let parts: Vec<f64> = text
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|e| format!("'{t}': {e}")))
        .collect::<Result<_, _>>()?;
    match parts[..] {
        [x, y, z] if [x, y, z].iter().all(|c| c.is_finite()) && (x, y, z) != (0.0, 0.0, 0.0) => Ok(gbsurf::DVec3::new(x, y, z)),
        _ => Err(format!("expected a finite non-zero vector x,y,z, got '{text}'")),
    }
}

/// Files in formats the crate's own readers and writers do not handle (OpenMesh's `.om`) go
/// through OpenMesh when the cargo feature `openmesh` is on. OBJ, OFF, PLY and STL always use the
/// crate's own strict readers: they keep full double precision (OpenMesh reads text formats in
/// single precision) and name the offending line, where OpenMesh silently repairs bad input.
#[cfg(feature = "openmesh")]
mod openmesh_io {
    use gbsurf::api::ConvertError;
    use gbsurf::export::AtomicFiles;
    use gbsurf::tessellate::SurfaceMesh;
    use gbsurf::mesh::{PolyMesh, TriMesh};
    use std::path::Path;

    /// Formats OpenMesh reads and writes that the crate's own I/O does not.
    const OPENMESH_ONLY: [&str; 1] = ["om"];

    fn om_error(path: &Path, e: impl std::fmt::Display) -> ConvertError {
        ConvertError::Io { path: path.display().to_string(), message: e.to_string() }
    }

    pub fn handles(path: &Path) -> bool {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        OPENMESH_ONLY.contains(&ext.as_str())
    }

    pub fn read(path: &Path) -> Result<PolyMesh, ConvertError> {
        gbsurf_openmesh::read_mesh(path).map_err(|e| om_error(path, e))
    }

    /// Adds the file OpenMesh writes for `mesh` (positions, triangles, vertex normals) to the
    /// outputs, so it joins the atomic write of the others.
    pub fn add(files: &mut AtomicFiles, mesh: &SurfaceMesh, path: &Path) -> Result<(), ConvertError> {
        let tri = TriMesh { positions: mesh.positions.clone(), normals: mesh.normals.clone(), triangles: mesh.triangles.clone() };
        Ok(files.add_by_path(path, |tmp| gbsurf_openmesh::write_tri_mesh(&tri, tmp))?)
    }
}

/// Without the `openmesh` feature only the crate's own formats exist.
#[cfg(not(feature = "openmesh"))]
mod openmesh_io {
    use gbsurf::api::ConvertError;
    use gbsurf::export::AtomicFiles;
    use gbsurf::tessellate::SurfaceMesh;
    use gbsurf::mesh::PolyMesh;
    use std::path::Path;

    pub fn handles(_: &Path) -> bool {
        false
    }
    pub fn read(path: &Path) -> Result<PolyMesh, ConvertError> {
        Err(ConvertError::Io { path: path.display().to_string(), message: "unreachable: no OpenMesh".into() })
    }
    pub fn add(_: &mut AtomicFiles, _: &SurfaceMesh, path: &Path) -> Result<(), ConvertError> {
        Err(ConvertError::Io { path: path.display().to_string(), message: "unreachable: no OpenMesh".into() })
    }
}

fn main() -> ExitCode {
    let cli = match command().try_get_matches().and_then(|m| Cli::from_arg_matches(&m)) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    let result = match &cli.command {
        Command::Convert(args) => run_convert(args).map_err(|e| e.to_string()),
        Command::EvalGbp { file, weights } => eval_gbp(file, weights.unwrap_or_default()),
        Command::TessellateGbp { file, output, resolution, weights } => {
            tessellate_gbp(file, output, *resolution, weights.unwrap_or_default())
        }
        Command::GbpElevate { file, to, output } => gbp_elevate(file, *to, output),
        Command::Ph5(args) => offsets::ph5(args).map_err(|e| e.to_string()),
        Command::PhSpline(args) => offsets::ph_spline(args).map_err(|e| e.to_string()),
        Command::PnGrid(args) => offsets::pn_grid(args).map_err(|e| e.to_string()),
        Command::Offset(args) => offsets::offset(args).map_err(|e| e.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gbsurf: error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Points this far outside the domain polygon (in area units) still count as inside.
const DOMAIN_TOL: f64 = 1e-12;

/// Loads and validates a patch; errors name the file.
fn load_patch(file: &Path) -> Result<GbPatch, String> {
    let patch = load_gbp(file).map_err(|e| format!("{}: {e}", file.display()))?;
    patch
        .validate()
        .map_err(|e| format!("{}: {e}", file.display()))?;
    Ok(patch)
}

fn eval_gbp(file: &Path, form: WeightForm) -> Result<(), String> {
    let patch = load_patch(file)?;
    let mut ev = patch
        .evaluator()
        .map_err(|e| format!("{}: {e}", file.display()))?;
    let stdin = std::io::stdin().lock();
    let stdout = std::io::stdout().lock();
    let mut out = BufWriter::new(stdout);
    let write_err = |e: std::io::Error| format!("writing stdout: {e}");
    for (idx, line) in stdin.split(b'\n').enumerate() {
        let lineno = idx + 1;
        let bytes = line.map_err(|e| format!("reading stdin line {lineno}: {e}"))?;
        let text = std::str::from_utf8(&bytes)
            .map_err(|_| format!("stdin line {lineno}: not valid UTF-8 text"))?;
        let mut tokens = text.split_whitespace();
        let (u, v) = match (tokens.next(), tokens.next(), tokens.next()) {
            (None, _, _) => continue,
            (Some(u), Some(v), None) => (u, v),
            _ => {
                return Err(format!(
                    "stdin line {lineno}: expected two numbers `u v`, found `{}`",
                    text.trim()
                ))
            }
        };
        let parse = |tok: &str, name: &str| -> Result<f64, String> {
            match tok.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                Ok(_) => Err(format!(
                    "stdin line {lineno}: {name} = `{tok}` is not finite"
                )),
                Err(_) => Err(format!(
                    "stdin line {lineno}: {name} = `{tok}` is not a number"
                )),
            }
        };
        let uv = DVec2::new(parse(u, "u")?, parse(v, "v")?);
        if !ev.domain().contains(uv, DOMAIN_TOL) {
            return Err(format!(
                "stdin line {lineno}: ({u}, {v}) is outside the {}-sided domain polygon",
                ev.n()
            ));
        }
        let p = patch.eval_derivs_with_form(&mut ev, uv, form).p;
        if !p.is_finite() {
            return Err(format!(
                "stdin line {lineno}: the patch is not defined at ({u}, {v}) (result not finite)"
            ));
        }
        writeln!(out, "{:.17e} {:.17e} {:.17e}", p.x, p.y, p.z).map_err(write_err)?;
    }
    out.flush().map_err(write_err)
}

fn tessellate_gbp(
    file: &Path,
    output: &Path,
    resolution: usize,
    form: WeightForm,
) -> Result<(), String> {
    check_resolution(resolution).map_err(|e| e.to_string())?;
    export::check_output_paths(&[FlagPath::new("input", file)], &[FlagPath::new("-o", output)]).map_err(|e| e.to_string())?;
    let patch = load_patch(file)?;
    let mesh =
        tessellate_gb(&patch, resolution, form).map_err(|e| format!("{}: {e}", file.display()))?;
    export::write_atomic(output, |w| mesh.write_obj(w)).map_err(|e| e.to_string())
}

/// `gbp-elevate`: the patch elevated to degree `to` (docs/math/editing.md, "common degree"),
/// written as `.gbp` (atomically: nothing is written on failure).
fn gbp_elevate(file: &Path, to: usize, output: &Path) -> Result<(), String> {
    use gbsurf::limits::MAX_GBP_DEGREE;
    if to > MAX_GBP_DEGREE {
        return Err(format!("--to {to} is above {MAX_GBP_DEGREE}, the largest degree a .gbp file holds"));
    }
    let patch = load_patch(file)?;
    if to < patch.degree() {
        return Err(format!("{}: --to {to} is below the patch degree {} (degree reduction is not exact)", file.display(), patch.degree()));
    }
    let elevated = gbsurf::gb::decompose::common_degree(std::slice::from_ref(&patch), to)
        .map_err(|e| format!("{}: --to {to}: {e}", file.display()))?
        .remove(0);
    let text = gbsurf::gb::gbp::to_gbp_string(&elevated).map_err(|e| format!("{}: {e}", output.display()))?;
    export::write_atomic(output, |w| w.write_all(text.as_bytes())).map_err(|e| e.to_string())
}
