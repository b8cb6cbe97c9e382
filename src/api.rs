//! The public API of the main job: polygon control mesh → watertight triangle mesh of a
//! G1 surface of GB patches (or, for comparison, of a subdivision surface), with per-vertex
//! quality data and a report.
//!
//! Everything here is plain data (vectors of f64/u32, enums without payload in the options) so the
//! C ABI (`ffi`) can wrap it one to one.
//!
//! ```no_run
//! use gbsurf::api::{convert_file, ConvertOptions, Method};
//! let opts = ConvertOptions { method: Method::Topology, resolution: 6, ..Default::default() };
//! let conv = convert_file("cube.obj", &opts, None).unwrap();
//! println!("{} vertices, max G1 {}°", conv.mesh.vertex_count(), conv.report.max_g1_deg);
//! ```

use crate::construct::Surface;
use crate::gb::WeightForm;
use crate::mesh::{MeshError, PolyMesh};
use crate::quality::Report;
use crate::tessellate::{SurfaceMesh, TessellateError};
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// How the control mesh becomes a surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Dual structure: one GB patch per mesh vertex (seed 000 §2).
    #[default]
    Dual,
    /// Topology-preserving structure: one ribbon-only patch per mesh face (seed 000 §3).
    Topology,
    /// Doo–Sabin subdivision, for comparison (seed 000 §6.4).
    DooSabin,
    /// Catmull–Clark subdivision, for comparison (seed 000 §6.4).
    CatmullClark,
}

impl Method {
    /// The command-line / report name: `dual`, `topology`, `doo-sabin`, `catmull-clark`.
    pub fn name(self) -> &'static str {
        match self {
            Method::Dual => "dual",
            Method::Topology => "topology",
            Method::DooSabin => "doo-sabin",
            Method::CatmullClark => "catmull-clark",
        }
    }
    /// True for the GB-patch methods (dual, topology).
    pub fn is_patch_method(self) -> bool {
        matches!(self, Method::Dual | Method::Topology)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = ConvertError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "dual" => Ok(Method::Dual),
            "topology" => Ok(Method::Topology),
            "doo-sabin" => Ok(Method::DooSabin),
            "catmull-clark" => Ok(Method::CatmullClark),
            _ => Err(invalid("method", s, "expected dual, topology, doo-sabin or catmull-clark")),
        }
    }
}

/// How the twist control points are set (seed 000 §4): the construction's own
/// [`crate::construct::TwistMode`], under the name the API and the CLI use.
pub use crate::construct::TwistMode as Twist;

impl FromStr for Twist {
    type Err = ConvertError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "none" => Ok(Twist::None),
            "approx" => Ok(Twist::Approx),
            "interp" => Ok(Twist::Interp),
            _ => Err(invalid("twist", s, "expected none, approx or interp")),
        }
    }
}

use crate::limits::{MAX_LEVELS, MAX_RESOLUTION};

/// Options of [`convert`]. Every field has a default ([`ConvertOptions::default`]); values are
/// checked by [`ConvertOptions::validate`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ConvertOptions {
    /// Construction method. Default: dual.
    pub method: Method,
    /// Samples per patch side (an n-sided patch gets n·r² triangles). 1..=1024, default 8.
    pub resolution: usize,
    /// Fullness κ of the dual curves, 0 ≤ κ < 1 (seed 000 eq. 2.2). Default 1/3.
    pub fullness: f64,
    /// Tile split ratio w > 2 of the topology-preserving structure (seed 000 §3.3.1). Default 3.
    pub tile_depth: f64,
    /// Twist construction. Default: interp.
    pub twist: Twist,
    /// Factor on the middle constraint D_{0.5} of the direction blends, finite. Default 1.
    pub mid_scale: f64,
    /// Project onto best-fit planes (seed 000 §3.3.2). Default on.
    pub best_plane: bool,
    /// Correction weights of the GB patches. Default squared.
    pub weights: WeightForm,
    /// Subdivision levels of the comparison methods, 0..=8. Default 3.
    pub levels: u32,
}

impl Default for ConvertOptions {
    fn default() -> Self {
        Self {
            method: Method::Dual,
            resolution: 8,
            fullness: 1.0 / 3.0,
            tile_depth: 3.0,
            twist: Twist::Interp,
            mid_scale: 1.0,
            best_plane: true,
            weights: WeightForm::Squared,
            levels: 3,
        }
    }
}

fn invalid(name: &'static str, value: impl ToString, reason: &str) -> ConvertError {
    ConvertError::InvalidOption { name, value: value.to_string(), reason: reason.to_string() }
}

impl ConvertOptions {
    /// Checks every value; the error names the option.
    pub fn validate(&self) -> Result<(), ConvertError> {
        if self.resolution == 0 || self.resolution > MAX_RESOLUTION {
            return Err(invalid("resolution", self.resolution, "must be in 1..=1024"));
        }
        if !(self.fullness >= 0.0 && self.fullness < 1.0) {
            return Err(invalid("fullness", self.fullness, "must be in [0, 1)"));
        }
        if !(self.tile_depth > 2.0 && self.tile_depth.is_finite()) {
            return Err(invalid("tile-depth", self.tile_depth, "must be finite and > 2"));
        }
        if !self.mid_scale.is_finite() {
            return Err(invalid("mid-scale", self.mid_scale, "must be finite"));
        }
        if self.levels > MAX_LEVELS {
            return Err(invalid("levels", self.levels, "must be in 0..=8"));
        }
        Ok(())
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
    /// Reading or writing a file failed.
    #[error("i/o error on {path}: {message}")]
    Io { path: String, message: String },
    /// The progress callback returned false.
    #[error("cancelled")]
    Cancelled,
}

impl From<TessellateError> for ConvertError {
    fn from(e: TessellateError) -> Self {
        match e {
            TessellateError::Cancelled => ConvertError::Cancelled,
            e => ConvertError::Tessellate(e),
        }
    }
}

/// The result of [`convert`].
#[derive(Clone, Debug, PartialEq)]
pub struct Conversion {
    /// The welded output triangle mesh with per-vertex normals, patch indices, curvatures and G1
    /// deviation.
    pub mesh: SurfaceMesh,
    /// The exact surface (patches, adjacency, curve network); `None` for subdivision methods.
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
    let he = crate::mesh::HalfEdgeMesh::from_polymesh(mesh)?;
    convert_valid(&he, mesh, options, progress, start)
}

fn convert_valid(
    he: &crate::mesh::HalfEdgeMesh,
    mesh: &PolyMesh,
    options: &ConvertOptions,
    mut progress: Progress<'_>,
    start: std::time::Instant,
) -> Result<Conversion, ConvertError> {
    let mut warnings: Vec<String> = he.warnings().iter().map(|w| w.to_string()).collect();
    let mut report = Report {
        method: options.method.name().to_string(),
        input_vertices: mesh.positions.len(),
        input_faces: mesh.faces.len(),
        ..Default::default()
    };
    let mut tick = |f: f32| -> Result<(), ConvertError> {
        if let Some(cb) = progress.as_mut() {
            if !cb(f.clamp(0.0, 1.0)) {
                return Err(ConvertError::Cancelled);
            }
        }
        Ok(())
    };
    tick(0.0)?;
    let (out, surface) = if options.method.is_patch_method() {
        let surface = build_surface(he, options)?;
        warnings.extend(surface.warnings.iter().cloned());
        tick(0.2)?;
        let mut sub = |f: f32| tick(0.2 + 0.7 * f).is_ok();
        let (m, stats) = crate::tessellate::tessellate_surface(&surface, options.resolution, options.weights, Some(&mut sub))?;
        for p in &surface.patches {
            report.count_sides(p.sides());
        }
        report.patches = surface.patches.len();
        report.resolution = options.resolution;
        report.max_boundary_gap = stats.max_boundary_gap;
        report.max_g1_deg = stats.max_g1_deg;
        report.mean_g1_deg = stats.mean_g1_deg;
        (m, Some(surface))
    } else {
        let (m, faces) = subdivision_mesh(&he.to_polymesh(), options)?;
        for f in &faces {
            report.count_sides(f.len());
        }
        report.patches = faces.len();
        report.resolution = options.levels as usize;
        (m, None)
    };
    tick(0.95)?;
    let check = crate::quality::check_mesh(&out.positions, &out.triangles);
    report.vertices = out.positions.len();
    report.triangles = out.triangles.len();
    report.closed = check.is_closed_manifold();
    report.two_manifold = check.is_two_manifold();
    report.boundary_edges = check.boundary_edges;
    report.duplicate_vertices = check.duplicate_vertices;
    report.zero_area_triangles = check.zero_area_triangles;
    if !check.is_two_manifold() {
        warnings.push(format!(
            "output is not a consistently oriented two-manifold: {} non-manifold edges, {} non-manifold vertices, {} inconsistent edges",
            check.non_manifold_edges, check.non_manifold_vertices, check.inconsistent_edges
        ));
    }
    report.warnings = warnings.clone();
    report.seconds = start.elapsed().as_secs_f64();
    tick(1.0)?;
    Ok(Conversion { mesh: out, surface, report, warnings })
}

/// The construction options of [`crate::construct`] for `options`.
pub fn construct_options(options: &ConvertOptions) -> crate::construct::ConstructOptions {
    crate::construct::ConstructOptions {
        fullness: options.fullness,
        twist: options.twist,
        mid_scale: options.mid_scale,
        best_plane: options.best_plane,
        tile_depth: options.tile_depth,
    }
}

/// The GB surface of a validated mesh for the patch methods (dual: [`crate::construct::build_dual`],
/// topology: [`crate::construct::build_topology`]).
fn build_surface(he: &crate::mesh::HalfEdgeMesh, options: &ConvertOptions) -> Result<Surface, ConvertError> {
    let co = construct_options(options);
    match options.method {
        Method::Topology => crate::construct::build_topology(he, &co),
        _ => crate::construct::build_dual(he, &co),
    }
    .map_err(ConvertError::Construct)
}

/// Subdivision methods: `levels` steps of the scheme, tracking for every face the input face it
/// descends from (Catmull–Clark: the children of a face are consecutive, one per corner;
/// Doo–Sabin: every new point belongs to one corner of an old face, and a new face descends from
/// the face of its first such point — see [`crate::subdiv::doo_sabin`]'s output order). The result
/// is split into convex pieces ([`crate::mesh::geometry::convexify`]) and fan-triangulated.
/// Normals: area-weighted; curvatures: [`crate::quality::discrete_curvature`]; G1 deviation 0;
/// patch index (per vertex: the smallest over its triangles) = input face.
fn subdivision_mesh(mesh: &PolyMesh, options: &ConvertOptions) -> Result<(SurfaceMesh, Vec<Vec<u32>>), ConvertError> {
    use crate::subdiv::{subdivide, Subdivided, SubdivisionScheme};
    let scheme = match options.method {
        Method::CatmullClark => SubdivisionScheme::CatmullClark,
        Method::DooSabin => SubdivisionScheme::DooSabin,
        m @ (Method::Dual | Method::Topology) => {
            return Err(ConvertError::Subdiv(format!("{m} is not a subdivision method")));
        }
    };
    let Subdivided { mesh: current, face_ancestor: ancestor } =
        subdivide(mesh, scheme, options.levels).map_err(|e| ConvertError::Subdiv(e.to_string()))?;
    let (convex, piece_face) = crate::mesh::geometry::convexify(&current);
    let nv = current.positions.len();
    let mut out = SurfaceMesh { positions: current.positions.clone(), ..Default::default() };
    out.patch = vec![u32::MAX; nv];
    for (k, f) in convex.faces.iter().enumerate() {
        let anc = piece_face.get(k).and_then(|&f| ancestor.get(f as usize)).copied().unwrap_or(0);
        for i in 1..f.len().saturating_sub(1) {
            out.triangles.push([f[0], f[i], f[i + 1]]);
            out.triangle_patch.push(anc);
        }
        for &v in f {
            let slot = &mut out.patch[v as usize];
            *slot = (*slot).min(anc);
        }
    }
    for p in &mut out.patch {
        if *p == u32::MAX {
            *p = 0;
        }
    }
    out.normals = crate::quality::vertex_normals(&out.positions, &out.triangles);
    let (h, k) = crate::quality::discrete_curvature(&out.positions, &out.triangles, &out.normals);
    out.mean_curvature = h;
    out.gaussian_curvature = k;
    out.g1_deviation_deg = vec![0.0; nv];
    Ok((out, current.faces))
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
    let (mesh, map) = crate::mesh::read_polymesh(path)?;
    let mut he = crate::mesh::HalfEdgeMesh::from_polymesh(&mesh).map_err(|e| e.with_source(&map))?;
    he.annotate_warnings(&map);
    convert_valid(&he, &mesh, options, progress, start)
}

// ------------------------------------------------------------------ exact descriptions

/// The ribbons of a patch.
fn ribbons(p: &crate::construct::Patch) -> &[crate::gb::Ribbon] {
    match p {
        crate::construct::Patch::Gb(g) => &g.ribbons,
        crate::construct::Patch::Cgb(c) => &c.ribbons,
    }
}

fn obj_v(out: &mut String, p: glam::DVec3) {
    use std::fmt::Write as _;
    let _ = writeln!(out, "v {:.17e} {:.17e} {:.17e}", p.x, p.y, p.z);
}

/// The curve network as Wavefront OBJ: every boundary curve once, as the polyline of its Bézier
/// control points (`v` lines, then one `l` line per curve, in [`Surface::curves`] order; object
/// `curve_<k>`). The curves are exact: the control polygon, not a sampling.
pub fn curves_obj(surface: &Surface) -> String {
    use std::fmt::Write as _;
    let mut out = String::from("# gbsurf curve network: Bézier control polygons, one l line per curve\n");
    let mut base = 1usize;
    for (k, c) in surface.curves.iter().enumerate() {
        let _ = writeln!(out, "o curve_{k}");
        for &p in c {
            obj_v(&mut out, p);
        }
        let idx: Vec<String> = (base..base + c.len()).map(|x| x.to_string()).collect();
        if idx.len() >= 2 {
            let _ = writeln!(out, "l {}", idx.join(" "));
        }
        base += c.len();
    }
    out
}

/// The control nets of every patch as Wavefront OBJ (object `patch_<p>`): for each ribbon the
/// polylines of its rows (k fixed) and of its columns (j fixed); for GB patches the central
/// control point as a `p` element, joined by `l` lines to the innermost row's middle points.
pub fn nets_obj(surface: &Surface) -> String {
    use std::fmt::Write as _;
    let mut out = String::from("# gbsurf control nets: ribbon rows and columns per patch\n");
    let mut base = 1usize;
    for (pi, patch) in surface.patches.iter().enumerate() {
        let _ = writeln!(out, "o patch_{pi}");
        let mut lines: Vec<Vec<usize>> = Vec::new();
        let mut ribbon_first = Vec::new();
        for rb in ribbons(patch) {
            let first = base;
            ribbon_first.push(first);
            for row in &rb.rows {
                for &p in row {
                    obj_v(&mut out, p);
                }
                base += row.len();
            }
            let width = rb.degree + 1;
            for k in 0..rb.rows.len() {
                lines.push((0..rb.rows[k].len()).map(|j| first + k * width + j).collect());
            }
            if rb.rows.len() >= 2 {
                for j in 0..width {
                    lines.push((0..rb.rows.len()).filter(|&k| j < rb.rows[k].len()).map(|k| first + k * width + j).collect());
                }
            }
        }
        if let crate::construct::Patch::Gb(g) = patch {
            obj_v(&mut out, g.center);
            let c = base;
            base += 1;
            let _ = writeln!(out, "p {c}");
            for (rb, first) in g.ribbons.iter().zip(&ribbon_first) {
                if let Some(k) = rb.rows.len().checked_sub(1) {
                    lines.push(vec![first + k * (rb.degree + 1) + rb.degree / 2, c]);
                }
            }
        }
        for l in lines {
            if l.len() >= 2 {
                let idx: Vec<String> = l.iter().map(|x| x.to_string()).collect();
                let _ = writeln!(out, "l {}", idx.join(" "));
            }
        }
    }
    out
}

/// The exact description of a surface as JSON: for every patch its index, `type` (`gb`/`cgb`),
/// `n`, `degree` (per ribbon), the control-mesh element it stands for, its neighbours (per
/// side: `{patch, side}` or null) and its control points (`ribbons[i].rows[k][j]` as [x, y, z];
/// `center` for GB patches), plus the curve network. `gbp_files[p]` (if given) names the `.gbp`
/// file written for patch p.
pub fn patches_json(surface: &Surface, gbp_files: &[Option<String>]) -> serde_json::Value {
    use serde_json::json;
    let pt = |p: &glam::DVec3| json!([p.x, p.y, p.z]);
    let patches: Vec<serde_json::Value> = surface
        .patches
        .iter()
        .enumerate()
        .map(|(i, patch)| {
            let rbs = ribbons(patch);
            let ribbons_json: Vec<serde_json::Value> = rbs
                .iter()
                .map(|r| json!({"degree": r.degree, "rows": r.rows.iter().map(|row| row.iter().map(pt).collect::<Vec<_>>()).collect::<Vec<_>>()}))
                .collect();
            let (kind, center) = match patch {
                crate::construct::Patch::Gb(g) => ("gb", Some(pt(&g.center))),
                crate::construct::Patch::Cgb(_) => ("cgb", None),
            };
            let degree: Vec<usize> = rbs.iter().map(|r| r.degree).collect();
            let mut v = json!({
                "index": i,
                "type": kind,
                "n": rbs.len(),
                "degree": degree,
                "source": surface.sources.get(i),
                "neighbors": surface.neighbors.get(i),
                "ribbons": ribbons_json,
            });
            if let Some(c) = center {
                v["center"] = c;
            }
            if let Some(Some(f)) = gbp_files.get(i) {
                v["gbp"] = json!(f);
            }
            v
        })
        .collect();
    let curves: Vec<serde_json::Value> = surface.curves.iter().map(|c| json!(c.iter().map(pt).collect::<Vec<_>>())).collect();
    json!({"format": "gbsurf-surface", "version": 1, "patches": patches, "curves": curves})
}

/// The `.gbp` text of every GB patch that has one (a connected net, see [`crate::gb::gbp`]);
/// `None` for CGB patches and for GB patches whose corner blocks are independent (direction-blend
/// twists), which only the JSON describes exactly.
pub fn gbp_texts(surface: &Surface) -> Vec<Option<String>> {
    surface
        .patches
        .iter()
        .map(|p| match p {
            crate::construct::Patch::Gb(g) => crate::gb::gbp::to_gbp_string(g).ok(),
            crate::construct::Patch::Cgb(_) => None,
        })
        .collect()
}

/// Writes a [`SurfaceMesh`] by the extension of `path` (`obj`, `ply`, `stl`) into memory.
pub fn encode_mesh(mesh: &SurfaceMesh, path: &Path) -> Result<Vec<u8>, ConvertError> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let mut buf = Vec::new();
    let r = match ext.as_str() {
        "obj" => mesh.write_obj(&mut buf),
        "ply" => mesh.write_ply(&mut buf),
        "stl" => mesh.write_stl(&mut buf),
        _ => return Err(invalid("output", path.display(), "the output extension must be .obj, .ply or .stl")),
    };
    r.map_err(|e| ConvertError::Io { path: path.display().to_string(), message: e.to_string() })?;
    Ok(buf)
}

/// Writes several files all or nothing: each goes to a temporary file beside its target, and only
/// when all are written are they renamed into place; on failure the temporaries are removed and
/// no target is touched (a failing rename after the first can still leave earlier ones in place).
pub fn write_files_atomic(files: &[(std::path::PathBuf, Vec<u8>)]) -> Result<(), ConvertError> {
    let mut temps: Vec<std::path::PathBuf> = Vec::new();
    let io = |p: &Path, e: std::io::Error| ConvertError::Io { path: p.display().to_string(), message: e.to_string() };
    let cleanup = |temps: &[std::path::PathBuf]| {
        for t in temps {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, data) in files {
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        if name.is_empty() {
            cleanup(&temps);
            return Err(invalid("output", path.display(), "not a file name"));
        }
        let tmp = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
        if let Err(e) = std::fs::write(&tmp, data) {
            cleanup(&temps);
            return Err(io(path, e));
        }
        temps.push(tmp);
    }
    for ((path, _), tmp) in files.iter().zip(&temps) {
        if let Err(e) = std::fs::rename(tmp, path) {
            cleanup(&temps);
            return Err(io(path, e));
        }
    }
    Ok(())
}

#[allow(unused)]
fn _assert_send_sync() {
    fn f<T: Send + Sync>() {}
    f::<ConvertOptions>();
    f::<Conversion>();
    f::<ConvertError>();
}
