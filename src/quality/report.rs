//! The conversion report: written as JSON by `gbsurf convert --report`.

use crate::quality::validity::FoldSite;
use std::collections::BTreeMap;

/// What a conversion produced and how good it is.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Report {
    /// `dual`, `topology`, `doo-sabin` or `catmull-clark`.
    pub method: String,
    /// Number of patches (GB methods) or of faces of the subdivided mesh (subdivision methods).
    pub patches: usize,
    /// Number of patches (faces) per side count, keyed by the count as a string: {"4": 120}.
    pub sides_histogram: BTreeMap<String, usize>,
    /// Output vertices and triangles (in the quad layout: two per quad).
    pub vertices: usize,
    pub triangles: usize,
    /// Output face layout: `triangles` or `quads` ([`crate::options::Layout`]).
    #[serde(default)]
    pub layout: String,
    /// Output quads (0 in the triangle layout).
    #[serde(default)]
    pub quads: usize,
    /// The output is a closed, consistently oriented two-manifold.
    pub closed: bool,
    /// The output is a consistently oriented two-manifold (possibly with boundary).
    pub two_manifold: bool,
    /// Edges of the output used by one triangle only.
    pub boundary_edges: usize,
    /// Output vertices at identical positions (extra copies).
    pub duplicate_vertices: usize,
    /// Output triangles of (relatively) zero area.
    pub zero_area_triangles: usize,
    /// Largest angle (degrees) between the normals of two patches on their shared boundary.
    pub max_g1_deg: f64,
    /// Mean of that angle over the output vertices on shared boundaries.
    pub mean_g1_deg: f64,
    /// Shared patch sides with a crease (sharpness above 0, see [`crate::mesh::Creases`]): welded
    /// but deliberately not G1, so left out of `max_g1_deg` and `mean_g1_deg`.
    #[serde(default)]
    pub sharp_edges: usize,
    /// Largest distance between the two patches' samples of a shared boundary before welding.
    pub max_boundary_gap: f64,
    /// Wall-clock seconds of the conversion (construction + tessellation + checks).
    pub seconds: f64,
    /// Tessellation resolution (samples per patch side) or subdivision levels.
    pub resolution: usize,
    /// Input mesh: vertices and faces.
    pub input_vertices: usize,
    pub input_faces: usize,
    /// Warnings collected on the way (dropped vertices, split faces, …).
    pub warnings: Vec<String>,
    /// Patches that fold: the parameterisation turns over (a sample's normal opposes its
    /// reference and a neighbouring sample's normal is reversed, docs/math.md#folds), or a flipped
    /// output triangle ([`crate::quality::validity::Folds::of_tessellation`]; 0 for subdivision
    /// methods).
    #[serde(default)]
    pub folds: usize,
    /// The first few folded patches (at most [`crate::quality::validity::MAX_FOLD_SITES`]) with
    /// the domain point of their worst sample.
    #[serde(default)]
    pub fold_sites: Vec<FoldSite>,
    /// Output triangles whose geometric normal opposes all three vertex normals.
    #[serde(default)]
    pub flipped_triangles: usize,
    /// Pairs of output triangles of one connected shell, sharing no vertex, that meet.
    #[serde(default)]
    pub self_intersections: usize,
    /// Pairs of input faces of one connected shell, sharing no vertex, that meet (fan triangles
    /// of the convex pieces); `None` (JSON `null`): not counted. The cage is checked only when
    /// the output self-intersects (`self_intersections` > 0), the only case in which
    /// [`Report::valid`] depends on it.
    #[serde(default)]
    pub input_self_intersections: Option<usize>,
    /// Largest |mean curvature| of the output times its bounding-box diagonal.
    #[serde(default)]
    pub max_abs_mean_curvature_times_diagonal: f64,
    /// The input mesh is closed (no boundary edges).
    #[serde(default)]
    pub input_closed: bool,
    /// Closed two-manifold (two-manifold for an open input), no folds, and no self-intersections
    /// unless the input itself has some (see [`Report::validity_problems`]).
    #[serde(default)]
    pub valid: bool,
}

impl Report {
    /// Adds patches (faces) to the histogram, one per side count `sides` yields.
    pub fn count_sides(&mut self, sides: impl IntoIterator<Item = usize>) {
        // Counted by number first (one key string per distinct count, not one per patch).
        let mut counts: BTreeMap<usize, usize> = BTreeMap::new();
        for n in sides {
            *counts.entry(n).or_insert(0) += 1;
        }
        for (n, c) in counts {
            *self.sides_histogram.entry(n.to_string()).or_insert(0) += c;
        }
    }

    /// What makes the output invalid, one phrase each (empty when valid): not a closed
    /// two-manifold (for a closed input) or not a two-manifold, folds, self-intersections beyond
    /// the input's (any, when the input has none or was not checked).
    pub fn validity_problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        if !self.two_manifold {
            out.push("not a consistently oriented two-manifold".to_string());
        } else if self.input_closed && !self.closed {
            out.push(format!("open: {} boundary edges on a closed input", self.boundary_edges));
        }
        if self.folds > 0 {
            let first = self.fold_sites.first().map(|s| format!(" (first: patch {} at ({:.4}, {:.4}))", s.patch, s.u, s.v)).unwrap_or_default();
            let flipped = if self.flipped_triangles > 0 { format!(", {} flipped triangles", self.flipped_triangles) } else { String::new() };
            out.push(format!("{} folded patches{first}{flipped}", self.folds));
        }
        if self.self_intersections > 0 && self.input_self_intersections.unwrap_or(0) == 0 {
            out.push(format!("{} self-intersecting triangle pairs", self.self_intersections));
        }
        out
    }

    /// Sets [`Report::valid`] from [`Report::validity_problems`].
    pub fn set_valid(&mut self) {
        self.valid = self.validity_problems().is_empty();
    }

    /// Pretty JSON text.
    pub fn to_json(&self) -> String {
        // A plain struct of numbers, strings and maps: serialization cannot fail; non-finite
        // floats are written as null by serde_json.
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}
