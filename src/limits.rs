//! The crate's limits, in one place. Every bound on input sizes (degrees, sides, resolutions,
//! subdivision levels, isophote stripes, slicing planes, table memory) is defined here and used by name everywhere else.
//!
//! Two degree limits exist on purpose and mean different things:
//! - [`MAX_DEGREE`] bounds what the evaluators accept (any patch built in memory, from the C ABI
//!   or by degree elevation). Bernstein weights of higher degree are numerically meaningless for
//!   surfaces; the bound also keeps malformed input from allocating or overflowing.
//! - [`MAX_GBP_DEGREE`] bounds what the `.gbp` reader accepts from a file and what the writer
//!   emits. A file is untrusted text: its header alone decides how many points are read, so it
//!   gets the tighter bound, still far above the degrees the interchange format is used for.
//!   Every patch read from a file is thus also below [`MAX_DEGREE`].

/// Largest ribbon degree the evaluators accept (GB and CGB patches, degree elevation).
pub const MAX_DEGREE: usize = 128;

/// Largest degree the `.gbp` reader accepts and the writer emits (see the module doc).
pub const MAX_GBP_DEGREE: usize = 40;

/// Largest number of sides the `.gbp` reader accepts.
pub const MAX_GBP_SIDES: usize = 1024;

/// Largest number of values per face corner that `tessellate::cage_values` carries (a UV map
/// has 2, an RGBA colour 4; the bound keeps a wrong count from overflowing the buffer sizes).
pub const MAX_CAGE_VALUE_DIM: usize = 256;

/// Largest tessellation resolution (samples per patch side; n·r² triangles per patch).
pub const MAX_RESOLUTION: usize = 1024;

/// Largest number of isophote stripes over 0..180° (a band of 0.18°: finer than any display).
pub const MAX_STRIPES: u32 = 1000;

/// Largest number of slicing planes (each plane is intersected with every triangle; the output
/// grows linearly with the count).
pub const MAX_SLICES: usize = 1000;

/// Largest subdivision level count.
pub const MAX_LEVELS: u32 = 8;

/// Default memory bound of one conversion, in MiB (`ConvertOptions::max_memory_mb`): 2 GiB,
/// about 2 M output vertices by the measured figures of `api::estimate_output` (a 10k-face cage
/// in the triangle layout at r = 8 passes, a 40k-face one is refused with the figures). Chosen so that
/// a conversion inside Blender (itself some 300–500 MB) stays safe on a 4 GB machine.
pub const DEFAULT_MAX_MEMORY_MB: u64 = 2048;

/// Largest accepted memory bound, in MiB (1 TiB): the bound must stay a number of bytes in u64.
pub const MAX_MEMORY_MB: u64 = 1 << 20;

/// Largest weight table built, in bytes (1 GiB).
pub const MAX_TABLE_BYTES: u128 = 1 << 30;

/// Patches of more sides than this (faces of the topology structure, vertex valences of the dual)
/// are split into a fan of three-sided patches around a new node
/// (`construct::network::split_large_patches`, docs/math.md#high-valence-split): one point of an
/// n-sided patch costs O(n), so without the split a 1000-gon costs 1000/4 times a quad per
/// output vertex. 64 keeps every patch of the shared models, Blender's primitives and the
/// valence-64 tests as it was.
pub const MAX_UNSPLIT_SIDES: usize = 64;

/// Corners of a face with holes, its outer loop and inner loops together. Its checks compare
/// every pair of loop edges and its split tests every triangle of its constrained Delaunay
/// triangulation against every loop, O(corners²): 4096 corners stay well under a second.
pub const MAX_HOLED_FACE_CORNERS: usize = 4096;

/// Above this size a tessellation builds no weight table: the weights are evaluated directly at
/// every sample (a table this large would be used for one conversion only).
pub const MAX_TESSELLATION_TABLE_BYTES: u128 = 256 << 20;

/// The default memory bound of a caller-owned `tessellate::TableCache` (the tables of a few
/// (n, d) at the usual resolutions).
pub const DEFAULT_TABLE_CACHE_BYTES: u128 = 64 << 20;

/// Greatest number of halvings of one curve when the curve network is converted into cubic
/// Bézier chains (at most 2^10 cubic segments per curve, reached only for tolerances at round-off
/// level).
pub const MAX_CUBIC_SPLIT_DEPTH: usize = 10;

/// Largest mesh file the readers read, in bytes (2 GiB); larger files (and endless ones such as
/// `/dev/zero`) are refused with [`crate::mesh::MeshError::InputTooLarge`].
pub const MAX_INPUT_BYTES: u64 = 2 << 30;

/// Smallest accepted ratio of a mesh's bounding-box extent to the magnitude of its coordinates.
/// Below it, f64 (about 16 significant digits) cannot resolve the shape well enough for the
/// construction: a unit cube at x = 1e15 gives visibly wrong surfaces. Such meshes are refused
/// with [`crate::mesh::MeshError::UnresolvableExtent`].
pub const MIN_RELATIVE_EXTENT: f64 = 1e-9;

/// Range of a control mesh's bounding-box extent (largest side) that a conversion accepts. The
/// conversion scales the cage to a unit box, so inside this range every extent converts the same
/// way; outside it, the curvatures mapped back (H ~ 1/extent, K ~ 1/extent²) would overflow f64
/// (K at extent 1e-160 is about 1e320) or vanish into subnormals. Refused with
/// `api::ConvertError::ScaleOutOfRange`.
pub const EXTENT_RANGE: (f64, f64) = (1e-140, 1e140);

const _: () = assert!(MAX_GBP_DEGREE <= MAX_DEGREE);

/// Largest PN grid size N of `gbsurf offset` (N × N grid points per quad piece of a patch;
/// (N − 1)² Coons patches per piece, each exported as a rational patch of degree (11, 11)).
pub const MAX_OFFSET_GRID: usize = 64;

/// Default PN grid size N of `gbsurf offset`: 4 × 4 points (9 Coons patches) per quad piece.
pub const DEFAULT_OFFSET_GRID: usize = 4;
