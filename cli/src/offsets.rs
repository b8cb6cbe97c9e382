//! The exact-offset commands (`gbsurf::offset`, docs/math/ph.md and docs/math/pn.md):
//!
//! - `gbsurf ph5 --p0 X,Y --d0 X,Y --p1 X,Y --d1 X,Y [--offset D]`: the planar PH quintic
//!   Hermite interpolants, printed as JSON on stdout;
//! - `gbsurf ph-spline IN -o OUT.json [--closed | --tangents] [--offset D]`: a planar PH quintic
//!   spline through the points of a text file (format in [`POINTS_FORMAT`]);
//! - `gbsurf pn-grid IN.json -o OUT.json [--offset D]`: a PN surface interpolating a grid of points
//!   with normals, written as the exact rational form of each patch.
//!
//! Output files are checked against the input (`gbsurf::export::check_output_paths`) before any
//! work and written through the atomic writer (`gbsurf::export::write_atomic`). JSON has no
//! infinity: an infinite number (the curvature radius of a straight segment) is written as `null`.

use gbsurf::export::{self, ExportError, FlagPath, OutputPathError};
use gbsurf::mesh::MeshError;
use gbsurf::offset::ph::{HermiteSolution, OpenEnds, PhError, PlanarPhQuintic, PlanarPhSpline, RationalOffset};
use gbsurf::offset::pn::{PnError, PnGrid, PnOptions, PnRational, PnSurface};
use gbsurf::{DVec2, DVec3};
use serde_json::{json, Value};
use std::io::Write;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The input format of `ph-spline`, shown in its help.
pub const POINTS_FORMAT: &str = "IN is a text file with one point per line: `x y`, or `x y tx ty` \
with --tangents (the tangent, i.e. the derivative r'(t) of the segments at that point). Numbers \
are separated by spaces or tabs; `#` starts a comment; blank lines are skipped.";

/// Errors of the offset commands, each naming the argument or the input line.
#[derive(Debug, Error)]
pub enum OffsetCmdError {
    /// A PH construction failed; `context` names the command line arguments or the input lines.
    #[error("{context}: {source}")]
    Ph { context: String, source: PhError },
    /// A PN construction failed.
    #[error("{context}: {source}")]
    Pn { context: String, source: PnError },
    /// A line of a point file that is not `x y` (or `x y tx ty`).
    #[error("{path} line {line}: {message}")]
    Line { path: String, line: usize, message: String },
    /// A file that is not valid (not JSON of the expected shape, too few points, …).
    #[error("{path}: {message}")]
    File { path: String, message: String },
    #[error(transparent)]
    Read(#[from] MeshError),
    #[error(transparent)]
    Paths(#[from] OutputPathError),
    #[error(transparent)]
    Export(#[from] ExportError),
    #[error("writing stdout: {0}")]
    Stdout(std::io::Error),
}

type Result<T> = std::result::Result<T, OffsetCmdError>;

/// `x,y` as a vector; NaN and infinities are accepted here and refused by the core with the
/// argument's name (exit status 1, like every other bad value).
pub fn parse_vec2(text: &str) -> std::result::Result<DVec2, String> {
    let parts: Vec<f64> = text
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|e| format!("'{t}': {e}")))
        .collect::<std::result::Result<_, _>>()?;
    match parts[..] {
        [x, y] => Ok(DVec2::new(x, y)),
        _ => Err(format!("expected two numbers x,y, got '{text}'")),
    }
}

#[derive(clap::Args)]
pub struct Ph5Args {
    /// Start point `x,y`.
    #[arg(long, value_parser = parse_vec2, allow_hyphen_values = true)]
    p0: DVec2,
    /// Start derivative r'(0), `x,y` (non-zero).
    #[arg(long, value_parser = parse_vec2, allow_hyphen_values = true)]
    d0: DVec2,
    /// End point `x,y`.
    #[arg(long, value_parser = parse_vec2, allow_hyphen_values = true)]
    p1: DVec2,
    /// End derivative r'(1), `x,y` (non-zero).
    #[arg(long, value_parser = parse_vec2, allow_hyphen_values = true)]
    d1: DVec2,
    /// Also give the exact offset (rational, degree 9) at this signed distance (positive to the
    /// right of the direction of travel), with its cusp parameters.
    #[arg(long, allow_hyphen_values = true)]
    offset: Option<f64>,
}

#[derive(clap::Args)]
pub struct PhSplineArgs {
    /// Input points (see the format above).
    input: PathBuf,
    /// Output JSON file.
    #[arg(short, long)]
    output: PathBuf,
    /// A closed C² spline (the last point joins the first; do not repeat the first point).
    #[arg(long, conflicts_with = "tangents")]
    closed: bool,
    /// Lines carry tangents `x y tx ty`: a C¹ Hermite PH spline (otherwise an open C² spline
    /// with cubic end spans, at least 3 points).
    #[arg(long)]
    tangents: bool,
    /// Also give each segment's exact offset at this signed distance.
    #[arg(long, allow_hyphen_values = true)]
    offset: Option<f64>,
}

#[derive(clap::Args)]
pub struct PnGridArgs {
    /// Input JSON: {"points": [[[x,y,z], …], …], "normals": [[[x,y,z], …], …]}, m × n each
    /// (m, n ≥ 2), row i along u, column j along v.
    input: PathBuf,
    /// Output JSON file.
    #[arg(short, long)]
    output: PathBuf,
    /// Also give each patch's exact offset surface at this signed distance (along the normals).
    #[arg(long, allow_hyphen_values = true)]
    offset: Option<f64>,
}

fn xy(p: DVec2) -> Value {
    json!([p.x, p.y])
}

/// The shape measures of one PH quintic (shared by `ph5` and the segments of `ph-spline`).
fn quintic_json(c: &PlanarPhQuintic) -> Value {
    json!({
        "control_points": c.control_points().iter().map(|p| xy(*p)).collect::<Vec<_>>(),
        "arc_length": c.arc_length(),
        "bending_energy": c.bending_energy(),
        "abs_rotation_index": c.rotation_index(),
        // Unbounded curvature (w vanishes on [0, 1]) gives radius 0.
        "min_curvature_radius": c.min_radius_of_curvature().unwrap_or(0.0),
        "singular_parameters": c.singular_params(),
    })
}

fn offset_json(o: &RationalOffset) -> Value {
    json!({
        "distance": o.distance,
        "degree": o.points.len().saturating_sub(1),
        "control_points": o.points.iter().map(|p| xy(*p)).collect::<Vec<_>>(),
        "weights": o.weights,
        "cusps": o.cusps,
    })
}

fn with(mut v: Value, key: &str, x: Value) -> Value {
    if let Value::Object(m) = &mut v {
        m.insert(key.to_string(), x);
    }
    v
}

/// `--offset D` of a curve, the error naming the flag (and `which` curve when the error is the
/// curve's, not the distance's).
fn curve_offset(c: &PlanarPhQuintic, d: f64, which: impl FnOnce() -> String) -> Result<Value> {
    c.offset(d).map(|o| offset_json(&o)).map_err(|source| {
        let context = match source {
            PhError::ZeroOffsetDistance | PhError::NonFinite { .. } => format!("--offset {d}"),
            _ => format!("--offset {d} ({})", which()),
        };
        OffsetCmdError::Ph { context, source }
    })
}

fn solution_json(s: &HermiteSolution, d: Option<f64>, index: usize) -> Result<Value> {
    let mut v = quintic_json(&s.curve);
    v = with(v, "eta0", json!(s.eta0));
    v = with(v, "eta2", json!(s.eta2));
    if let Some(d) = d {
        let o = curve_offset(&s.curve, d, || format!("solution {index}"))?;
        v = with(v, "offset", o);
    }
    Ok(v)
}

/// `ph5`: the chosen Hermite interpolant's fields at the top level, all four under `solutions`
/// (`chosen` is the index of the top-level one).
pub fn ph5(args: &Ph5Args) -> Result<()> {
    let sols = PlanarPhQuintic::hermite(args.p0, args.d0, args.p1, args.d1)
        .map_err(|source| OffsetCmdError::Ph { context: "ph5".into(), source })?;
    let all = sols
        .solutions
        .iter()
        .enumerate()
        .map(|(i, s)| solution_json(s, args.offset, i))
        .collect::<Result<Vec<_>>>()?;
    let mut v = all[sols.best].clone();
    v = with(v, "chosen", json!(sols.best));
    v = with(v, "solutions", Value::Array(all));
    let text = serde_json::to_string_pretty(&v).unwrap_or_default();
    let mut out = std::io::stdout().lock();
    writeln!(out, "{text}").and_then(|()| out.flush()).map_err(OffsetCmdError::Stdout)
}

/// The lines of a point file: `(line number, numbers)` of every non-blank line (comments cut).
fn point_lines(path: &Path, bytes: &[u8], width: usize) -> Result<Vec<(usize, Vec<f64>)>> {
    let shown = path.display().to_string();
    let text = std::str::from_utf8(bytes).map_err(|e| OffsetCmdError::File { path: shown.clone(), message: format!("not UTF-8 text: {e}") })?;
    let mut rows = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let err = |message: String| OffsetCmdError::Line { path: shown.clone(), line, message };
        let body = raw.split('#').next().unwrap_or("");
        let tokens: Vec<&str> = body.split_whitespace().collect();
        if tokens.is_empty() {
            continue;
        }
        let form = if width == 4 { "`x y tx ty` (--tangents)" } else { "`x y`" };
        if tokens.len() != width {
            return Err(err(format!("expected {width} numbers {form}, found {}", tokens.len())));
        }
        let nums = tokens
            .iter()
            .map(|t| match t.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                Ok(_) => Err(err(format!("`{t}` is not finite"))),
                Err(_) => Err(err(format!("`{t}` is not a number"))),
            })
            .collect::<Result<Vec<f64>>>()?;
        rows.push((line, nums));
    }
    Ok(rows)
}

/// Context of a spline error: the input line of the point (or tangent) it names.
fn spline_context(path: &Path, lines: &[usize], e: &PhError) -> String {
    let at = |i: usize| lines.get(i).copied();
    let line = match e {
        PhError::CoincidentPoints { index, .. } => at(*index).map(|l| {
            let next = at(index + 1).or_else(|| lines.first().copied()).unwrap_or(l);
            format!(" lines {l} and {next}")
        }),
        PhError::ZeroDerivative { index: Some(i), .. } | PhError::NonFinite { index: Some(i), .. } => {
            at(*i).map(|l| format!(" line {l}"))
        }
        _ => None,
    };
    format!("{}{}", path.display(), line.unwrap_or_default())
}

pub fn ph_spline(args: &PhSplineArgs) -> Result<()> {
    export::check_output_paths(&[FlagPath::new("input", &args.input)], &[FlagPath::new("-o", &args.output)])?;
    let bytes = gbsurf::mesh::io::read_input_bytes(&args.input)?;
    let rows = point_lines(&args.input, &bytes, if args.tangents { 4 } else { 2 })?;
    let lines: Vec<usize> = rows.iter().map(|(l, _)| *l).collect();
    let points: Vec<DVec2> = rows.iter().map(|(_, v)| DVec2::new(v[0], v[1])).collect();
    let (kind, built) = if args.tangents {
        let tangents: Vec<DVec2> = rows.iter().map(|(_, v)| DVec2::new(v[2], v[3])).collect();
        ("hermite", PlanarPhSpline::hermite(&points, &tangents))
    } else if args.closed {
        ("c2_closed", PlanarPhSpline::c2_closed(&points))
    } else {
        ("c2_open", PlanarPhSpline::c2_open(&points, OpenEnds::CubicEndSpans))
    };
    let spline = built.map_err(|e| OffsetCmdError::Ph { context: spline_context(&args.input, &lines, &e), source: e })?;
    let segments = spline
        .segments
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let v = quintic_json(s);
            match args.offset {
                Some(d) => Ok(with(v, "offset", curve_offset(s, d, || format!("segment {i}"))?)),
                None => Ok(v),
            }
        })
        .collect::<Result<Vec<_>>>()?;
    let v = json!({
        "kind": kind,
        "closed": spline.closed,
        "newton_iterations": spline.iterations,
        "arc_length": spline.arc_length(),
        "segments": segments,
    });
    write_json(&args.output, &v)
}

fn write_json(path: &Path, v: &Value) -> Result<()> {
    let text = serde_json::to_string_pretty(v).unwrap_or_default();
    Ok(export::write_atomic(path, |w| w.write_all(text.as_bytes()))?)
}

/// The input of `pn-grid`.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct GridFile {
    points: Vec<Vec<[f64; 3]>>,
    normals: Vec<Vec<[f64; 3]>>,
}

fn rational_json(r: &PnRational) -> Value {
    let (du, dv) = r.degree();
    let rows: Vec<Vec<[f64; 4]>> = r.homogeneous.points().iter().map(|row| row.iter().map(|h| h.to_array()).collect()).collect();
    json!({ "degree": [du, dv], "homogeneous": rows, "weights": r.weights() })
}

pub fn pn_grid(args: &PnGridArgs) -> Result<()> {
    export::check_output_paths(&[FlagPath::new("input", &args.input)], &[FlagPath::new("-o", &args.output)])?;
    let shown = args.input.display().to_string();
    let bytes = gbsurf::mesh::io::read_input_bytes(&args.input)?;
    let file: GridFile = serde_json::from_slice(&bytes).map_err(|e| OffsetCmdError::File { path: shown.clone(), message: e.to_string() })?;
    let to3 = |g: &[Vec<[f64; 3]>]| -> Vec<Vec<DVec3>> { g.iter().map(|r| r.iter().map(|p| DVec3::from_array(*p)).collect()).collect() };
    let pn = |source: PnError| OffsetCmdError::Pn { context: shown.clone(), source };
    let grid = PnGrid::new(&to3(&file.points), &to3(&file.normals)).map_err(pn)?;
    let surface = PnSurface::interpolate(&grid, &PnOptions::default()).map_err(pn)?;
    let (pm, pn_) = surface.patch_count();
    let mut patches = Vec::with_capacity(pm * pn_);
    for i in 0..pm {
        for j in 0..pn_ {
            let mut v = with(rational_json(&surface.rational(i, j).map_err(pn)?), "patch", json!([i, j]));
            if let Some(d) = args.offset {
                let o = surface
                    .rational_offset(i, j, d)
                    .map_err(|source| OffsetCmdError::Pn { context: format!("--offset {d}"), source })?;
                v = with(v, "offset", rational_json(&o));
            }
            patches.push(v);
        }
    }
    let v = json!({
        "rows": grid.rows(),
        "cols": grid.cols(),
        "patch_rows": pm,
        "patch_cols": pn_,
        "offset_distance": args.offset,
        "patches": patches,
    });
    write_json(&args.output, &v)
}

/// `gbsurf offset IN -o OUT --distance D [convert options] [--grid N] [--report FILE.json]
/// [--shell] [--export FILE.json]`: the offset of the GB surface of a control mesh through PN
/// pieces (`gbsurf::api::offset`, docs/math/pn.md §11).
#[derive(clap::Args)]
pub struct OffsetArgs {
    /// Input control mesh (.obj, .off, .ply, .stl).
    input: PathBuf,
    /// Output triangle mesh of the offset surface (.obj, .ply, .stl).
    #[arg(short, long)]
    output: PathBuf,
    /// Signed offset distance along the outward normal (non-zero, finite).
    #[arg(long, allow_hyphen_values = true)]
    distance: f64,
    #[command(flatten)]
    options: crate::OptionFlags,
    /// PN grid size N per quad piece (N × N points, 2..=64).
    #[arg(long, default_value_t = gbsurf::limits::DEFAULT_OFFSET_GRID)]
    grid: usize,
    /// Write the report (JSON).
    #[arg(long)]
    report: Option<PathBuf>,
    /// Output a closed solid: offset, reversed surface and side walls along open boundaries.
    #[arg(long)]
    shell: bool,
    /// Write the exact rational patches of the offset (degree (11, 11), homogeneous) as JSON.
    /// Only PN pieces have them: singular pieces (no PN fit; the mesh output covers them with
    /// the GB surface's x + d·n, which is not rational) are holes in the export, listed under
    /// "singular_pieces" by patch and piece with the reason, "complete" is false, and a warning
    /// is printed.
    #[arg(long)]
    export: Option<PathBuf>,
}

/// Why `gbsurf offset` failed.
#[derive(Debug, Error)]
pub enum OffsetRunError {
    #[error(transparent)]
    Offset(#[from] gbsurf::api::OffsetError),
    #[error(transparent)]
    Convert(#[from] gbsurf::api::ConvertError),
    #[error(transparent)]
    Export(#[from] ExportError),
    #[error(transparent)]
    Paths(#[from] OutputPathError),
}

pub fn offset(args: &OffsetArgs) -> std::result::Result<(), OffsetRunError> {
    use gbsurf::api::{self, OffsetOptions};
    let options = args.options.apply(api::ConvertOptions::default());
    options.validate().map_err(api::ConvertError::from)?;
    let format = export::MeshFormat::of(&args.output)?;
    let outputs: Vec<FlagPath<'_>> = std::iter::once(FlagPath::new("-o", &args.output))
        .chain(args.report.as_deref().map(|p| FlagPath::new("--report", p)))
        .chain(args.export.as_deref().map(|p| FlagPath::new("--export", p)))
        .collect();
    export::check_output_paths(&[FlagPath::new("input", &args.input)], &outputs)?;
    let off = OffsetOptions { distance: args.distance, grid: args.grid, shell: args.shell };
    let mesh = api::read_mesh(&args.input)?;
    let result = api::offset(&mesh, &options, &off)?;
    let tri = gbsurf::mesh::TriMesh { positions: result.positions.clone(), normals: Vec::new(), triangles: result.triangles.clone() };
    let mut files = export::AtomicFiles::new();
    files.add_with(&args.output, |w| export::WriteMesh::write_format(&tri, format, w))?;
    if let Some(path) = &args.report {
        files.add(path, serde_json::to_string_pretty(&result.report).unwrap_or_default().as_bytes())?;
    }
    if let Some(path) = &args.export {
        let patches: Vec<Value> = result
            .rational_patches()?
            .iter()
            .map(|(patch, piece, i, j, r)| with(rational_json(r), "piece", json!({ "patch": patch, "piece": piece, "cell": [i, j] })))
            .collect();
        let holes: Vec<Value> = result
            .singular_pieces()
            .iter()
            .map(|(patch, piece, reason)| json!({ "patch": patch, "piece": piece, "reason": reason }))
            .collect();
        if !holes.is_empty() {
            eprintln!(
                "warning: --export {}: {} of {} pieces are singular (no PN fit) and have no rational patches; they are listed under \"singular_pieces\" (the mesh output covers them with the GB surface's own offset)",
                path.display(),
                holes.len(),
                result.report.pieces
            );
        }
        let v = json!({
            "distance": args.distance,
            "grid": args.grid,
            "complete": holes.is_empty(),
            "pieces": result.report.pieces,
            "patches": patches,
            "singular_pieces": holes,
        });
        files.add(path, serde_json::to_string_pretty(&v).unwrap_or_default().as_bytes())?;
    }
    files.commit()?;
    Ok(())
}
