//! The `gbsurf` command line tool.
//!
//! - `gbsurf eval-gbp FILE.gbp [--weights squared|linear]`: reads `u v` lines on stdin (domain
//!   coordinates inside the domain polygon of `gbsurf::gb::Domain`; blank lines are skipped)
//!   and prints `x y z` per line with 17 significant
//!   digits.
//! - `gbsurf tessellate-gbp FILE.gbp -o OUT.obj [--resolution N] [--weights …]`: one patch as a
//!   triangle mesh with normals (Wavefront OBJ); written to a temporary file and renamed, so
//!   nothing is written on failure.
//!
//! Errors: one line on stderr, exit status 1 (2 for command-line usage errors).

use clap::{Parser, Subcommand, ValueEnum};
use gbsurf::gb::gbp::load_gbp;
use gbsurf::gb::{GbPatch, WeightForm};
use gbsurf::tessellate::patch::{tessellate_gb, MAX_RESOLUTION};
use gbsurf::DVec2;
use std::io::{BufRead, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Points this far outside the domain polygon (in area units) still count as inside.
const DOMAIN_TOL: f64 = 1e-12;

#[derive(Parser)]
#[command(name = "gbsurf", version, about = "Generalized Bézier patch surfaces")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// Correction-weight form of the GB patch.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum Weights {
    /// α_i = h_{i−1}² / (h_{i−1}² + h_i²) (default; keeps G1 with independent corner blocks).
    Squared,
    /// α_i = h_{i−1} / (h_{i−1} + h_i) (for comparison).
    Linear,
}

impl From<Weights> for WeightForm {
    fn from(w: Weights) -> Self {
        match w {
            Weights::Squared => WeightForm::Squared,
            Weights::Linear => WeightForm::Linear,
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Evaluate a .gbp patch at domain points `u v` read from stdin, one per line.
    EvalGbp {
        /// The patch (.gbp, format of the `transfinite` library).
        file: PathBuf,
        /// Correction-weight form.
        #[arg(long, value_enum, default_value = "squared")]
        weights: Weights,
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
        weights: Weights,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::EvalGbp { file, weights } => eval_gbp(&file, weights.into()),
        Command::TessellateGbp {
            file,
            output,
            resolution,
            weights,
        } => tessellate_gbp(&file, &output, resolution, weights.into()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("gbsurf: error: {msg}");
            ExitCode::FAILURE
        }
    }
}

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
