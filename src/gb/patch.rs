//! GB and CGB patches: data layout (seed 000 §2.7 eq. 2.24–2.26, §3.6 eq. 3.7–3.8).

use super::error::GbError;
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

/// The control rows of one side: row k, column j is P^i_{j,k}, row k = 0..l−1 (k = 0 is the
/// boundary curve), column j = 0..=d. Each side owns its rows, so adjacent sides may hold
/// different corner blocks and twists.
///
/// Stored as one buffer of `layers × width` points, row after row (row k is
/// `points[k·width .. (k+1)·width]`): one allocation per ribbon, and rows cannot be ragged. The
/// width is that of the rows as given; validation checks it against `degree + 1`. Serialized as
/// before, `{"degree": d, "rows": [[p, …], …]}`; a ragged `rows` is refused
/// ([`GbError::RaggedRows`]).
#[derive(Clone, Debug, PartialEq, serde::Deserialize)]
#[serde(try_from = "RibbonRows")]
pub struct Ribbon {
    /// Degree d of the ribbon along the side.
    pub degree: usize,
    layers: usize,
    width: usize,
    points: Vec<DVec3>,
}

/// The serialized form of a [`Ribbon`]: one Vec per row.
#[derive(serde::Deserialize)]
struct RibbonRows {
    degree: usize,
    rows: Vec<Vec<DVec3>>,
}

impl TryFrom<RibbonRows> for Ribbon {
    type Error = GbError;
    fn try_from(r: RibbonRows) -> Result<Self, GbError> {
        Ribbon::from_rows(r.degree, r.rows)
    }
}

impl serde::Serialize for Ribbon {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        /// The rows as a sequence of sequences, as `Vec<Vec<DVec3>>` serializes.
        struct Rows<'a>(&'a Ribbon);
        impl serde::Serialize for Rows<'_> {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.collect_seq(self.0.rows())
            }
        }
        let mut st = s.serialize_struct("Ribbon", 2)?;
        st.serialize_field("degree", &self.degree)?;
        st.serialize_field("rows", &Rows(self))?;
        st.end()
    }
}

impl Ribbon {
    /// `layers` rows of `width` points, point (k, j) = `f(k, j)` (no rows: width 0, as a ribbon
    /// read back from its rows).
    pub fn from_fn(degree: usize, layers: usize, width: usize, mut f: impl FnMut(usize, usize) -> DVec3) -> Self {
        let width = if layers == 0 { 0 } else { width };
        let mut points = Vec::with_capacity(layers * width);
        for k in 0..layers {
            points.extend((0..width).map(|j| f(k, j)));
        }
        Ribbon { degree, layers, width, points }
    }

    /// The ribbon of the given rows; [`GbError::RaggedRows`] when they differ in length.
    pub fn from_rows(degree: usize, rows: Vec<Vec<DVec3>>) -> Result<Self, GbError> {
        let width = rows.first().map_or(0, Vec::len);
        if let Some(row) = rows.iter().position(|r| r.len() != width) {
            return Err(GbError::RaggedRows { row, expected: width, found: rows[row].len() });
        }
        Ok(Ribbon { degree, layers: rows.len(), width, points: rows.concat() })
    }

    /// Number of rows (layers).
    pub fn layers(&self) -> usize {
        self.layers
    }

    /// Points per row.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Row k (panics when k ≥ layers).
    pub fn row(&self, k: usize) -> &[DVec3] {
        assert!(k < self.layers, "row {k} of a ribbon of {} rows", self.layers);
        &self.points[k * self.width..(k + 1) * self.width]
    }

    /// Row k, mutable (panics when k ≥ layers).
    pub fn row_mut(&mut self, k: usize) -> &mut [DVec3] {
        assert!(k < self.layers, "row {k} of a ribbon of {} rows", self.layers);
        &mut self.points[k * self.width..(k + 1) * self.width]
    }

    /// Row k, or `None` when k ≥ layers.
    pub fn get_row(&self, k: usize) -> Option<&[DVec3]> {
        (k < self.layers).then(|| &self.points[k * self.width..(k + 1) * self.width])
    }

    /// The rows in order.
    pub fn rows(&self) -> impl ExactSizeIterator<Item = &[DVec3]> + DoubleEndedIterator + '_ {
        (0..self.layers).map(move |k| &self.points[k * self.width..(k + 1) * self.width])
    }

    /// All points, row after row.
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// All points, row after row, mutable.
    pub fn points_mut(&mut self) -> &mut [DVec3] {
        &mut self.points
    }

    /// The rows as one Vec each.
    pub fn to_rows(&self) -> Vec<Vec<DVec3>> {
        self.rows().map(<[DVec3]>::to_vec).collect()
    }
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
