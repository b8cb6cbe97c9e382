//! The `gbsurf` command line.
//!
//! `gbsurf convert IN -o OUT [options]`: control mesh (OBJ/OFF/PLY/STL) → welded triangle mesh of
//! the smooth surface (OBJ/PLY/STL by the extension of OUT; PLY carries per-vertex `patch`,
//! `mean_curvature`, `gaussian_curvature`, `g1_deviation`). Optional outputs: `--curves` (the
//! curve network as OBJ polylines of the Bézier control polygons), `--nets` (the control nets as
//! OBJ), `--patches FILE.json` (exact description; `.gbp` files beside it for GB patches that have
//! one), `--report FILE.json`. All outputs are written together or not at all; errors print one
//! line and exit with status 1 (2 for usage errors).

use clap::{Parser, Subcommand, ValueEnum};
use gbsurf::api::{self, ConvertOptions, Method, Twist};
use gbsurf::gb::WeightForm;
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
    api::encode_mesh(&Default::default(), &args.output)?;
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
    let result = api::convert_file(&args.input, &options, Some(&mut cb));
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let conv = result?;

    let mut files: Vec<(PathBuf, Vec<u8>)> = vec![(args.output.clone(), api::encode_mesh(&conv.mesh, &args.output)?)];
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Convert(args) => run_convert(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gbsurf: error: {e}");
            ExitCode::FAILURE
        }
    }
}
