//! The options of a conversion: [`ConvertOptions`] with its enums [`Method`], [`Twist`],
//! [`Middle`], [`WeightForm`] and [`Layout`]. This is their one definition: the construction reads them directly, the
//! command line derives its flags from them (names from [`OptionValue::ALL`], parsing with the
//! `FromStr` impls here, defaults from [`ConvertOptions::default`]) and the C ABI fills its struct
//! from [`ConvertOptions::default`].

use std::fmt;
use std::str::FromStr;

pub use crate::gb::{Layout, WeightForm};

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

/// How the twist control points (row 1, columns 1 and 2 of each ribbon) are set (seed 000 §4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Twist {
    /// First approximation: convex combination of seed 000 eq. 2.11 (dual) or the tile vertex
    /// (§3.4.1). G1 only where four-sided faces meet four-sided patches; reported, not guaranteed.
    None,
    /// Approximating direction blend (eq. 4.16): G1 along every shared side.
    Approx,
    /// Interpolating direction blend (eq. 4.24): G1 along every shared side.
    #[default]
    Interp,
}

impl Twist {
    /// `none`, `approx`, `interp`.
    pub fn name(self) -> &'static str {
        match self {
            Twist::None => "none",
            Twist::Approx => "approx",
            Twist::Interp => "interp",
        }
    }
}

/// How each shared curve's middle constraint D_{0.5} of the direction blend is set
/// (docs/math.md#fair-middle).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Middle {
    /// The seed's rule: `mid_scale` times the curve's D_{0.5} (seed 000 §4.4.5).
    #[default]
    Seed,
    /// The seed's D_{0.5} moved to the minimiser of the thin-plate energy of the curve's two
    /// patches (one closed form per curve), kept where that makes a patch fold.
    Fair,
}

impl Middle {
    /// `seed`, `fair`.
    pub fn name(self) -> &'static str {
        match self {
            Middle::Seed => "seed",
            Middle::Fair => "fair",
        }
    }
}

impl OptionValue for Middle {
    const OPTION: &'static str = "middle";
    const ALL: &'static [Self] = &[Middle::Seed, Middle::Fair];
    fn name(self) -> &'static str {
        Middle::name(self)
    }
}

impl FromStr for Middle {
    type Err = OptionError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_value(s)
    }
}

impl fmt::Display for Middle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An option enum: every value and its command-line name.
pub trait OptionValue: Copy + PartialEq + FromStr<Err = OptionError> + 'static {
    /// The option's name (`method`, `twist`, `weights`), for messages.
    const OPTION: &'static str;
    /// Every value, in the order the C ABI numbers them.
    const ALL: &'static [Self];
    /// The command-line name of the value.
    fn name(self) -> &'static str;
}

impl OptionValue for Method {
    const OPTION: &'static str = "method";
    const ALL: &'static [Self] = &[Method::Dual, Method::Topology, Method::DooSabin, Method::CatmullClark];
    fn name(self) -> &'static str {
        Method::name(self)
    }
}

impl OptionValue for Twist {
    const OPTION: &'static str = "twist";
    const ALL: &'static [Self] = &[Twist::None, Twist::Approx, Twist::Interp];
    fn name(self) -> &'static str {
        Twist::name(self)
    }
}

impl OptionValue for WeightForm {
    const OPTION: &'static str = "weights";
    const ALL: &'static [Self] = &[WeightForm::Squared, WeightForm::Linear];
    fn name(self) -> &'static str {
        match self {
            WeightForm::Squared => "squared",
            WeightForm::Linear => "linear",
        }
    }
}

impl OptionValue for Layout {
    const OPTION: &'static str = "layout";
    const ALL: &'static [Self] = &[Layout::Triangles, Layout::Quads];
    fn name(self) -> &'static str {
        match self {
            Layout::Triangles => "triangles",
            Layout::Quads => "quads",
        }
    }
}

impl FromStr for Layout {
    type Err = OptionError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_value(s)
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(OptionValue::name(*self))
    }
}

/// The value of `T` named `s`; the error lists the names.
fn parse_value<T: OptionValue>(s: &str) -> Result<T, OptionError> {
    T::ALL.iter().copied().find(|v| v.name() == s).ok_or_else(|| {
        let names: Vec<&str> = T::ALL.iter().map(|v| v.name()).collect();
        let list = match names.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
            _ => names.join(""),
        };
        OptionError::new(T::OPTION, s, format!("expected {list}"))
    })
}

impl FromStr for Method {
    type Err = OptionError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_value(s)
    }
}

impl FromStr for Twist {
    type Err = OptionError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_value(s)
    }
}

impl FromStr for WeightForm {
    type Err = OptionError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_value(s)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for Twist {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl fmt::Display for WeightForm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(OptionValue::name(*self))
    }
}

pub use crate::limits::{DEFAULT_MAX_MEMORY_MB, MAX_LEVELS, MAX_MEMORY_MB, MAX_RESOLUTION, MAX_SLICES, MAX_STRIPES};

/// `value` of option `name` if it is in `1..=max`.
fn count_in_range<T: PartialOrd + From<u8> + fmt::Display + Copy>(name: &'static str, value: T, max: T) -> Result<T, OptionError> {
    if value >= T::from(1) && value <= max {
        Ok(value)
    } else {
        Err(OptionError::new(name, value, format!("must be in 1..={max}")))
    }
}

/// Checks a tessellation resolution (`--resolution`, samples per patch side): 1..=[`MAX_RESOLUTION`].
pub fn check_resolution(resolution: usize) -> Result<usize, OptionError> {
    count_in_range("resolution", resolution, MAX_RESOLUTION)
}

/// Checks a number of isophote stripes (`--stripes`): 1..=[`MAX_STRIPES`].
pub fn check_stripes(stripes: u32) -> Result<u32, OptionError> {
    count_in_range("stripes", stripes, MAX_STRIPES)
}

/// Checks a number of slicing planes (`--slice-count`): 1..=[`MAX_SLICES`].
pub fn check_slice_count(count: usize) -> Result<usize, OptionError> {
    count_in_range("slice-count", count, MAX_SLICES)
}

/// An option value out of range or unknown; `name` is the command-line name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("invalid --{name} {value}: {reason}")]
pub struct OptionError {
    /// The command-line name of the option (`resolution`, `tile-depth`, …).
    pub name: &'static str,
    /// The rejected value as text.
    pub value: String,
    /// What the value must be.
    pub reason: String,
}

impl OptionError {
    /// The error for option `name` with `value`.
    pub fn new(name: &'static str, value: impl ToString, reason: impl Into<String>) -> Self {
        OptionError { name, value: value.to_string(), reason: reason.into() }
    }
}

/// Options of a conversion ([`crate::api::convert`]) and of the constructions
/// ([`crate::construct::build_dual`], [`crate::construct::build_topology`]). Every field has a
/// default ([`ConvertOptions::default`]); values are checked by [`ConvertOptions::validate`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ConvertOptions {
    /// Construction method. Default: dual.
    pub method: Method,
    /// Output faces of the GB methods: `quads` (default; n·r² quads per n-sided patch, like
    /// Blender's Subdivision Surface) or `triangles` (n·r² triangles). STL output is always
    /// triangles (quads split on write).
    #[serde(default)]
    pub layout: Layout,
    /// Resolution r: samples per patch side (triangle layout: an n-sided patch gets n·r²
    /// triangles) or per half side (quad layout: n·r² quads; at r = 2^(L−1) a quad cage gets the
    /// vertex and face counts of Catmull–Clark level L). 1..=1024. Default [`DEFAULT_RESOLUTION`]
    /// = 2 (quads): Subdivision Surface level 2, Blender's render default; level 1 (r = 1, one
    /// quad per patch corner) is too coarse to show a GB surface's shape. The old default, the
    /// triangle layout at r = 8, gave twice the triangles of level 3 (a 50k-face cage became
    /// 12.8 M triangles).
    pub resolution: usize,
    /// Fullness κ ∈ [0, 1) of the dual curves: C1 = κ C0 + (1−κ) F (seed 000 eq. 2.2). Default ⅓,
    /// the value of the seed's figures; it gives uniform curves (linear precision) on regular grids.
    pub fullness: f64,
    /// Tile split ratio w > 2 of the topology-preserving structure: tiles cut at |e|/w from each
    /// vertex (seed 000 §3.3.1). Default 3 (uniform curves on regular grids).
    pub tile_depth: f64,
    /// Twist construction. Default: interp.
    pub twist: Twist,
    /// Factor on the middle constraint D_{0.5} of the direction blends (seed 000 §4.4.5), finite.
    /// Default 1.
    pub mid_scale: f64,
    /// How D_{0.5} is set: the seed's rule (`mid_scale` · D_{0.5}) or the fair rule
    /// (docs/math.md#fair-middle). Default seed.
    #[serde(default)]
    pub middle: Middle,
    /// Project onto best-fit planes (seed 000 §3.3.2): dual – the edge midpoints of each face onto
    /// the face's plane; topology – the tile vertices onto the tile's plane. Default on.
    pub best_plane: bool,
    /// Correction weights of the GB patches. Default squared.
    pub weights: WeightForm,
    /// Subdivision levels of the comparison methods, 0..=8. Default 3.
    pub levels: u32,
    /// Memory bound of one conversion in MiB (1..=[`MAX_MEMORY_MB`]). A conversion whose estimated
    /// peak memory ([`crate::api::estimate_output`], an upper bound of measured peaks) exceeds it
    /// is refused before any work with [`crate::api::ConvertError::OutputTooLarge`]. Default
    /// [`DEFAULT_MAX_MEMORY_MB`] (2048 MiB: about 2 M output vertices, a 10k-face cage in the
    /// triangle layout at r = 8 (about an 80k-face one in the default quad layout, 25 samples per quad patch), safe beside Blender and the OS on a 4 GB machine).
    #[serde(default = "default_max_memory_mb")]
    pub max_memory_mb: u64,
    /// Build the cage maps of the GB methods' output ([`crate::tessellate::SurfaceMesh`]'s
    /// `cage_corner`, `cage_coords`, `cage_loop_corner`: where every output face and loop lies in
    /// the control mesh, for carrying UVs and other cage data over). They are the largest
    /// per-face arrays (72 bytes per output vertex in the quad layout, 148 in the triangle
    /// layout), so a caller that does not read them saves that much peak memory by turning
    /// this off; they are then empty. Default on; the command line turns it off (none of its
    /// outputs reads them). The subdivision methods always fill `cage_corner`.
    #[serde(default = "default_cage_maps")]
    pub cage_maps: bool,
    /// Keep the exact surface of the GB methods in [`crate::api::Conversion::surface`]. Off, it
    /// is freed as soon as the tessellation and the fold report are done with it, before the mesh
    /// checks, and `surface` is `None`: about 1.6 KB per cubic four-sided patch (100 bytes per
    /// output vertex in the default quad layout at r = 2) less peak memory. Default on; the
    /// command line turns it off unless it writes `--curves`, `--nets` or `--patches`.
    #[serde(default = "default_cage_maps")]
    pub keep_surface: bool,
    /// Keep the per-vertex quality arrays of the output ([`crate::tessellate::SurfaceMesh`]'s
    /// `patch`, `mean_curvature`, `gaussian_curvature`, `g1_deviation_deg`) and the per-triangle
    /// patch ids (`triangle_patch`). Off, they are emptied as soon as the report has its figures
    /// from them, before the mesh checks (40 bytes per output vertex less in the quad layout).
    /// Default on; the command line turns it off unless it writes PLY (the only output that
    /// carries them).
    #[serde(default = "default_cage_maps")]
    pub quality_arrays: bool,
}

/// Default of the on/off options of the outputs ([`ConvertOptions::cage_maps`],
/// [`ConvertOptions::keep_surface`], [`ConvertOptions::quality_arrays`]): on.
fn default_cage_maps() -> bool {
    true
}

fn default_max_memory_mb() -> u64 {
    DEFAULT_MAX_MEMORY_MB
}

/// The default resolution (quad layout: Subdivision Surface level 2; see
/// [`ConvertOptions::resolution`]).
pub const DEFAULT_RESOLUTION: usize = 2;

impl Default for ConvertOptions {
    fn default() -> Self {
        Self {
            method: Method::Dual,
            layout: Layout::Quads,
            resolution: DEFAULT_RESOLUTION,
            fullness: 1.0 / 3.0,
            tile_depth: 3.0,
            twist: Twist::Interp,
            mid_scale: 1.0,
            middle: Middle::Seed,
            best_plane: true,
            weights: WeightForm::Squared,
            levels: 3,
            max_memory_mb: DEFAULT_MAX_MEMORY_MB,
            cage_maps: true,
            keep_surface: true,
            quality_arrays: true,
        }
    }
}

impl ConvertOptions {
    /// The layout and resolution of the tessellation.
    pub fn sampling(&self) -> crate::gb::Sampling {
        crate::gb::Sampling::new(self.layout, self.resolution)
    }

    /// The defaults before the quad layout: triangles at r = 8 (bit-identical output), for
    /// callers and tests that compare with it.
    pub fn triangles_r8() -> Self {
        ConvertOptions { layout: Layout::Triangles, resolution: 8, ..Default::default() }
    }

    /// Checks every value; the error names the option.
    pub fn validate(&self) -> Result<(), OptionError> {
        check_resolution(self.resolution)?;
        if !(self.fullness >= 0.0 && self.fullness < 1.0) {
            return Err(OptionError::new("fullness", self.fullness, "must be in [0, 1)"));
        }
        if !(self.tile_depth > 2.0 && self.tile_depth.is_finite()) {
            return Err(OptionError::new("tile-depth", self.tile_depth, "must be finite and > 2"));
        }
        if !self.mid_scale.is_finite() {
            return Err(OptionError::new("mid-scale", self.mid_scale, "must be finite"));
        }
        if self.levels > MAX_LEVELS {
            return Err(OptionError::new("levels", self.levels, format!("must be in 0..={MAX_LEVELS}")));
        }
        count_in_range("max-memory-mb", self.max_memory_mb, MAX_MEMORY_MB)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip<T: OptionValue + fmt::Debug>() {
        for &v in T::ALL {
            assert_eq!(v.name().parse::<T>(), Ok(v));
        }
        let e = "nonsense".parse::<T>().unwrap_err();
        assert_eq!(e.name, T::OPTION);
        assert!(T::ALL.iter().all(|v| e.reason.contains(v.name())), "{e}");
    }

    #[test]
    fn names_parse_back() {
        round_trip::<Method>();
        round_trip::<Twist>();
        round_trip::<Middle>();
        round_trip::<WeightForm>();
        round_trip::<Layout>();
        assert_eq!(
            "x".parse::<Method>().unwrap_err().to_string(),
            "invalid --method x: expected dual, topology, doo-sabin or catmull-clark"
        );
    }

    #[test]
    fn counts_are_bounded() {
        assert_eq!(check_resolution(MAX_RESOLUTION), Ok(MAX_RESOLUTION));
        assert_eq!(check_stripes(1), Ok(1));
        assert_eq!(check_slice_count(MAX_SLICES), Ok(MAX_SLICES));
        assert_eq!(check_slice_count(usize::MAX).unwrap_err().to_string(), format!("invalid --slice-count {}: must be in 1..={MAX_SLICES}", usize::MAX));
        assert_eq!(check_slice_count(0).unwrap_err().name, "slice-count");
        assert_eq!(check_stripes(u32::MAX).unwrap_err().name, "stripes");
        assert_eq!(check_stripes(0).unwrap_err().name, "stripes");
        assert_eq!(check_resolution(MAX_RESOLUTION + 1).unwrap_err().to_string(), "invalid --resolution 1025: must be in 1..=1024");
    }

    #[test]
    fn defaults_are_valid_and_the_enums_defaults() {
        let d = ConvertOptions::default();
        assert_eq!(d.validate(), Ok(()));
        assert_eq!((d.method, d.twist, d.weights, d.layout), Default::default());
        assert_eq!((d.layout, d.resolution), (Layout::Quads, 2));
    }
}
