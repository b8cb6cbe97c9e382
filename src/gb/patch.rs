//! GB and CGB patches: data layout (seed 000 §2.7 eq. 2.24–2.26, §3.6 eq. 3.7–3.8).

use glam::DVec3;

/// Form of the correction weights μ (docs/math.md#correction-weights): squared α_i = h_{i−1}²/(h_{i−1}²+h_i²)
/// (default, keeps G1 with independent corner blocks) or linear α_i = h_{i−1}/(h_{i−1}+h_i)
/// (kept for comparison only).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum WeightForm {
    #[default]
    Squared,
    Linear,
}

/// The control rows of one side: `rows[k][j]` is P^i_{j,k}, row k = 0..l−1 (k = 0 is the
/// boundary curve), column j = 0..=d. Each side owns its rows, so adjacent sides may hold
/// different corner blocks and twists.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ribbon {
    /// Degree d of the ribbon along the side.
    pub degree: usize,
    /// `rows[k][j]`, k < layers, j ≤ degree.
    pub rows: Vec<Vec<DVec3>>,
}

/// An n-sided GB patch: n ribbons of one degree d with l = ⌈d/2⌉ rows each, plus the central
/// control point (seed 000 eq. 2.26).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GbPatch {
    /// Ribbon of side i (side i runs from domain vertex i−1 to domain vertex i).
    pub ribbons: Vec<Ribbon>,
    /// Central control point, weight B0.
    pub center: DVec3,
}

/// A ribbon-only patch (CGB, seed 000 §3.6): independent ribbons, each of its own degree and
/// layer count, normalized by the sum of their weights (eq. 3.7–3.8); no central point.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CgbPatch {
    /// Ribbon of side i.
    pub ribbons: Vec<Ribbon>,
}
