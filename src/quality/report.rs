//! The conversion report: written as JSON by `gbsurf convert --report`.

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
    /// Output vertices and triangles.
    pub vertices: usize,
    pub triangles: usize,
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
}

impl Report {
    /// Adds one patch (face) with `n` sides to the histogram.
    pub fn count_sides(&mut self, n: usize) {
        *self.sides_histogram.entry(n.to_string()).or_insert(0) += 1;
    }

    /// Pretty JSON text.
    pub fn to_json(&self) -> String {
        // A plain struct of numbers, strings and maps: serialization cannot fail; non-finite
        // floats are written as null by serde_json.
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}
