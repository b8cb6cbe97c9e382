//! The `gbsurf` command line.
//!
//! `gbsurf convert IN -o OUT [options]`: control mesh (OBJ/OFF/PLY/STL; with the cargo feature
//! `openmesh` also OpenMesh's OM) → welded triangle mesh of the smooth surface (OBJ/PLY/STL, or OM
//! through OpenMesh, by the extension of OUT; PLY carries per-vertex `patch`,
//! `mean_curvature`, `gaussian_curvature`, `g1_deviation`). Optional outputs: `--curves` (the
//! curve network as OBJ polylines of the Bézier control polygons), `--nets` (the control nets as
//! OBJ), `--patches FILE.json` (exact description; `.gbp` files beside it for GB patches that have
//! one), `--report FILE.json`. All outputs are written together or not at all.
//!
//! `gbsurf eval-gbp FILE.gbp [--weights squared|linear]`: reads `u v` lines on stdin (domain
//! coordinates inside the domain polygon of `gbsurf::gb::Domain`; blank lines are skipped) and
//! prints `x y z` per line with 17 significant digits.
//!
//! `gbsurf tessellate-gbp FILE.gbp -o OUT.obj [--resolution N] [--weights …]`: one patch as a
//! triangle mesh with normals (Wavefront OBJ); written to a temporary file and renamed, so
//! nothing is written on failure.
//!
//! Errors print one line and exit with status 1 (2 for usage errors).

use clap::{Parser, Subcommand, ValueEnum};
use gbsurf::api::{self, ConvertOptions, Method, Twist};
use gbsurf::gb::gbp::load_gbp;
use gbsurf::gb::{GbPatch, WeightForm};
use gbsurf::limits::MAX_RESOLUTION;
use gbsurf::tessellate::patch::tessellate_gb;
use gbsurf::DVec2;
use std::io::{BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

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
        #[arg(long, value_enum, default_value = "squared")]
        weights: WeightsArg,
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
        #[arg(long, value_enum, default_value = "squared")]
        weights: WeightsArg,
    },
}

impl From<WeightsArg> for WeightForm {
    fn from(w: WeightsArg) -> Self {
        match w {
            WeightsArg::Squared => WeightForm::Squared,
            WeightsArg::Linear => WeightForm::Linear,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum MethodArg {
    Dual,
    Topology,
    DooSabin,
    CatmullClark,
}

#[derive(Clone, Copy, ValueEnum)]
enum TwistArg {
    None,
    Approx,
    Interp,
}

#[derive(Clone, Copy, ValueEnum)]
enum OnOff {
    On,
    Off,
}

#[derive(Clone, Copy, ValueEnum)]
enum WeightsArg {
    Squared,
    Linear,
}

#[derive(clap::Args)]
struct ConvertArgs {
    /// Input control mesh (.obj, .off, .ply, .stl).
    input: PathBuf,
    /// Output triangle mesh (.obj, .ply, .stl).
    #[arg(short, long)]
    output: PathBuf,
    /// Surface structure: dual (patch per vertex), topology (patch per face), or a subdivision
    /// scheme for comparison.
    #[arg(long, value_enum, default_value = "dual")]
    method: MethodArg,
    /// Samples per patch side (an n-sided patch gets n·N² triangles).
    #[arg(long, default_value_t = 8)]
    resolution: usize,
    /// Fullness κ ∈ [0, 1) of the dual curves.
    #[arg(long, default_value_t = 1.0 / 3.0)]
    fullness: f64,
    /// Tile split ratio w > 2 (topology structure).
    #[arg(long, default_value_t = 3.0)]
    tile_depth: f64,
    /// Twist construction.
    #[arg(long, value_enum, default_value = "interp")]
    twist: TwistArg,
    /// Factor on the middle constraint of the direction blends.
    #[arg(long, default_value_t = 1.0)]
    mid_scale: f64,
    /// Project onto best-fit planes.
    #[arg(long, value_enum, default_value = "on")]
    best_plane: OnOff,
    /// Correction weights of the GB patches.
    #[arg(long, value_enum, default_value = "squared")]
    weights: WeightsArg,
    /// Subdivision levels (doo-sabin, catmull-clark).
    #[arg(long, default_value_t = 3)]
    levels: u32,
    /// Write the curve network (OBJ polylines of the Bézier control polygons).
    #[arg(long)]
    curves: Option<PathBuf>,
    /// Write the control nets of all patches (OBJ).
    #[arg(long)]
    nets: Option<PathBuf>,
    /// Write the exact surface as JSON, with .gbp files beside it for GB patches.
    #[arg(long)]
    patches: Option<PathBuf>,
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
    /// No progress bar, no summary.
    #[arg(long)]
    quiet: bool,
}

impl ConvertArgs {
    fn options(&self) -> ConvertOptions {
        ConvertOptions {
            method: match self.method {
                MethodArg::Dual => Method::Dual,
                MethodArg::Topology => Method::Topology,
                MethodArg::DooSabin => Method::DooSabin,
                MethodArg::CatmullClark => Method::CatmullClark,
            },
            resolution: self.resolution,
            fullness: self.fullness,
            tile_depth: self.tile_depth,
            twist: match self.twist {
                TwistArg::None => Twist::None,
                TwistArg::Approx => Twist::Approx,
                TwistArg::Interp => Twist::Interp,
            },
            mid_scale: self.mid_scale,
            best_plane: matches!(self.best_plane, OnOff::On),
            weights: match self.weights {
                WeightsArg::Squared => WeightForm::Squared,
                WeightsArg::Linear => WeightForm::Linear,
            },
            levels: self.levels,
        }
    }
}

fn run_convert(args: &ConvertArgs) -> Result<(), api::ConvertError> {
    let options = args.options();
    options.validate()?;
    // Check the output extension before doing any work.
    if !openmesh_io::handles(&args.output) {
        api::encode_mesh(&Default::default(), &args.output)?;
    }
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
    let conv = result?;

    let surface_bytes = if openmesh_io::handles(&args.output) {
        openmesh_io::encode(&conv.mesh, &args.output)?
    } else {
        api::encode_mesh(&conv.mesh, &args.output)?
    };
    let mut files: Vec<(PathBuf, Vec<u8>)> = vec![(args.output.clone(), surface_bytes)];
    let need_surface = |what: &str| -> Result<&gbsurf::construct::Surface, api::ConvertError> {
        conv.surface.as_ref().ok_or_else(|| api::ConvertError::InvalidOption {
            name: "method",
            value: options.method.to_string(),
            reason: format!("--{what} needs a patch method (dual or topology)"),
        })
    };
    if let Some(path) = &args.curves {
        files.push((path.clone(), api::curves_obj(need_surface("curves")?).into_bytes()));
    }
    if let Some(path) = &args.nets {
        files.push((path.clone(), api::nets_obj(need_surface("nets")?).into_bytes()));
    }
    if let Some(path) = &args.patches {
        let surface = need_surface("patches")?;
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "patches".into());
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let texts = api::gbp_texts(surface);
        let mut names = Vec::with_capacity(texts.len());
        for (i, t) in texts.into_iter().enumerate() {
            match t {
                Some(text) => {
                    let name = format!("{stem}_{i:05}.gbp");
                    files.push((dir.join(&name), text.into_bytes()));
                    names.push(Some(name));
                }
                None => names.push(None),
            }
        }
        let json = api::patches_json(surface, &names);
        let text = serde_json::to_string_pretty(&json).map_err(|e| api::ConvertError::Io { path: path.display().to_string(), message: e.to_string() })?;
        files.push((path.clone(), text.into_bytes()));
    }
    if let Some(path) = &args.report {
        files.push((path.clone(), conv.report.to_json().into_bytes()));
    }
    if let Some(path) = &args.isophotes {
        files.push((path.clone(), isophote_ply(&conv.mesh, args.light, args.stripes, path)?));
    }
    if let Some(path) = &args.slices {
        let cuts = gbsurf::quality::slices(&conv.mesh.positions, &conv.mesh.triangles, args.slice_normal, args.slice_count);
        files.push((path.clone(), slices_obj(&cuts).into_bytes()));
    }
    api::write_files_atomic(&files)?;
    if !args.quiet {
        let r = &conv.report;
        eprintln!(
            "{}: {} patches, {} vertices, {} triangles, closed {}, max G1 {:.3e}°, max gap {:.3e}, {:.3} s",
            r.method, r.patches, r.vertices, r.triangles, r.closed, r.max_g1_deg, r.max_boundary_gap, r.seconds
        );
        for w in &conv.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(())
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

/// The surface as binary PLY with per-vertex `isophote` = n·L and `stripe` band coordinates.
fn isophote_ply(mesh: &gbsurf::tessellate::SurfaceMesh, light: gbsurf::DVec3, stripes: u32, path: &Path) -> Result<Vec<u8>, api::ConvertError> {
    use gbsurf::mesh::io::{write_ply, PlyFormat, VertexScalar};
    let iso = gbsurf::quality::isophote(&mesh.normals, light);
    let band = gbsurf::quality::isophote_stripes(&mesh.normals, light, stripes);
    let faces: Vec<&[u32]> = mesh.triangles.iter().map(|t| t.as_slice()).collect();
    let scalars = [VertexScalar { name: "isophote", values: &iso }, VertexScalar { name: "stripe", values: &band }];
    let mut buf = Vec::new();
    write_ply(&mut buf, &mesh.positions, Some(&mesh.normals), &faces, &scalars, PlyFormat::BinaryLittleEndian)
        .map_err(|e| api::ConvertError::Io { path: path.display().to_string(), message: e.to_string() })?;
    Ok(buf)
}

/// Slices as OBJ: a `g slice_K` group per plane, each polyline as one `l` line.
fn slices_obj(cuts: &[(f64, Vec<gbsurf::quality::Polyline>)]) -> String {
    use std::fmt::Write as _;
    let mut out = String::from("# gbsurf planar slices: one group per plane (offset d along the normal)\n");
    let mut next = 1usize;
    for (k, (d, lines)) in cuts.iter().enumerate() {
        let _ = writeln!(out, "g slice_{k}\n# d = {d:.17e}");
        for line in lines {
            for p in &line.points {
                let _ = writeln!(out, "v {:.17e} {:.17e} {:.17e}", p.x, p.y, p.z);
            }
            let ids: Vec<String> = (next..next + line.points.len()).map(|i| i.to_string()).collect();
            let _ = writeln!(out, "l {}", ids.join(" "));
            next += line.points.len();
        }
    }
    out
}

/// Files in formats the crate's own readers and writers do not handle (OpenMesh's `.om`) go
/// through OpenMesh when the cargo feature `openmesh` is on. OBJ, OFF, PLY and STL always use the
/// crate's own strict readers: they keep full double precision (OpenMesh reads text formats in
/// single precision) and name the offending line, where OpenMesh silently repairs bad input.
#[cfg(feature = "openmesh")]
mod openmesh_io {
    use gbsurf::api::ConvertError;
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

    /// The file OpenMesh writes for `mesh` (positions, triangles, vertex normals), as bytes, so it
    /// joins the all-or-nothing write of the other outputs.
    pub fn encode(mesh: &SurfaceMesh, path: &Path) -> Result<Vec<u8>, ConvertError> {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let tmp = std::env::temp_dir().join(format!("gbsurf-{}-{name}", std::process::id()));
        let tri = TriMesh { positions: mesh.positions.clone(), normals: mesh.normals.clone(), triangles: mesh.triangles.clone() };
        let written = gbsurf_openmesh::write_tri_mesh(&tri, &tmp).map_err(|e| om_error(path, e));
        let bytes = written.and_then(|()| std::fs::read(&tmp).map_err(|e| om_error(path, e)));
        let _ = std::fs::remove_file(&tmp);
        bytes
    }
}

/// Without the `openmesh` feature only the crate's own formats exist.
#[cfg(not(feature = "openmesh"))]
mod openmesh_io {
    use gbsurf::api::ConvertError;
    use gbsurf::tessellate::SurfaceMesh;
    use gbsurf::mesh::PolyMesh;
    use std::path::Path;

    pub fn handles(_: &Path) -> bool {
        false
    }
    pub fn read(path: &Path) -> Result<PolyMesh, ConvertError> {
        Err(ConvertError::Io { path: path.display().to_string(), message: "unreachable: no OpenMesh".into() })
    }
    pub fn encode(_: &SurfaceMesh, path: &Path) -> Result<Vec<u8>, ConvertError> {
        Err(ConvertError::Io { path: path.display().to_string(), message: "unreachable: no OpenMesh".into() })
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Convert(args) => run_convert(args).map_err(|e| e.to_string()),
        Command::EvalGbp { file, weights } => eval_gbp(file, (*weights).into()),
        Command::TessellateGbp { file, output, resolution, weights } => {
            tessellate_gbp(file, output, *resolution, (*weights).into())
        }
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
    if resolution == 0 || resolution > MAX_RESOLUTION {
        return Err(format!(
            "--resolution {resolution} is outside 1..={MAX_RESOLUTION}"
        ));
    }
    let patch = load_patch(file)?;
    let mesh =
        tessellate_gb(&patch, resolution, form).map_err(|e| format!("{}: {e}", file.display()))?;
    write_atomically(output, |w| mesh.write_obj(w))
}

/// Writes through a temporary file next to `path`, renamed over it only on success.
fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<(), String> {
    let name = path
        .file_name()
        .ok_or_else(|| format!("{}: not a file name", path.display()))?
        .to_string_lossy();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut w = BufWriter::new(std::fs::File::create(&tmp)?);
        write(&mut w)?;
        w.flush()?;
        w.get_ref().sync_all()?;
        drop(w);
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("{}: {e}", path.display())
    })
}
