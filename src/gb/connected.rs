//! The classic connected GB control net (seed 000 §2.7, seed 002 "control structure"), where the
//! corner blocks of adjacent ribbons are shared points.
//!
//! Sharing rule (docs/math.md#sharing, and the `transfinite` library's `setControlPoint`): with
//! l = ⌈d/2⌉ layers, point (i, j, k) with j < l is the same point as (i−1, d−k, j); a point with
//! d−j < l is the same as (i+1, k, d−j). The *listed* points — row k, columns j = k..d−k−1 of
//! every side — are independent; every other point of a ribbon equals exactly one listed point.
//! The listing order (row k, then side i, then column j) is the `.gbp` order.

use super::error::GbError;
use super::patch::{GbPatch, Ribbon};
use super::weights::layers_for_degree as layers;
use glam::DVec3;

/// Number of independent (listed) ribbon points of a connected net, without the central point:
/// n · Σ_{k<l} (d − 2k) = n · l · (⌊d/2⌋ + 1).
pub fn listed_point_count(n: usize, degree: usize) -> usize {
    n * layers(degree) * (degree / 2 + 1)
}

/// The listed positions (side i, column j, row k) in `.gbp` order: rows k = 0..l−1, within a row
/// sides i = 0..n−1, within a side columns j = k..d−k−1.
pub fn listed_positions(n: usize, degree: usize) -> impl Iterator<Item = (usize, usize, usize)> {
    let l = layers(degree);
    (0..l).flat_map(move |k| (0..n).flat_map(move |i| (k..degree - k).map(move |j| (i, j, k))))
}

/// The listed representative (side, column, row) of control point (i, j, k) of a connected net
/// (k < l, j ≤ d, i < n): itself when k ≤ j ≤ d−k−1, else (i−1, d−k, j) when j < k, else
/// (i+1, k, d−j). One step always reaches a listed point.
pub fn listed_representative(
    n: usize,
    degree: usize,
    i: usize,
    j: usize,
    k: usize,
) -> (usize, usize, usize) {
    if j < k {
        ((i + n - 1) % n, degree - k, j)
    } else if j + k >= degree {
        ((i + 1) % n, k, degree - j)
    } else {
        (i, j, k)
    }
}

/// A control-point position (side i, column j, row k).
pub type Position = (usize, usize, usize);

/// Checks n ≥ 3 and d ≥ 1 (the errors of [`GbPatch::check_shape`]).
fn check_nd(n: usize, degree: usize) -> Result<(), GbError> {
    if n < 3 {
        return Err(GbError::TooFewSides(n));
    }
    if degree < 1 {
        return Err(GbError::DegreeTooLow { side: 0, degree });
    }
    Ok(())
}

impl GbPatch {
    /// The classic connected GB net (seed 000 §2.7): `unique(i, j, k)` is called once for every
    /// listed position (row k, columns j = k..d−k−1 of side i, in `.gbp` order); all other
    /// ribbon points are copies of their listed representative ([`listed_representative`]).
    pub fn from_connected(
        n: usize,
        degree: usize,
        center: DVec3,
        mut unique: impl FnMut(usize, usize, usize) -> DVec3,
    ) -> Result<Self, GbError> {
        check_nd(n, degree)?;
        let l = layers(degree);
        let mut ribbons: Vec<Ribbon> = (0..n)
            .map(|_| Ribbon::from_fn(degree, l, degree + 1, |_, _| DVec3::ZERO))
            .collect();
        for (i, j, k) in listed_positions(n, degree) {
            ribbons[i].row_mut(k)[j] = unique(i, j, k);
        }
        for i in 0..n {
            for k in 0..l {
                for j in 0..=degree {
                    let (ri, rj, rk) = listed_representative(n, degree, i, j, k);
                    if (ri, rj, rk) != (i, j, k) {
                        ribbons[i].row_mut(k)[j] = ribbons[ri].row(rk)[rj];
                    }
                }
            }
        }
        Ok(GbPatch { ribbons, center })
    }

    /// The connected net from a listing in `.gbp` order: the central point first, then the
    /// listed points (see [`listed_positions`]); 1 + [`listed_point_count`] points.
    pub fn from_connected_listing(
        n: usize,
        degree: usize,
        points: &[DVec3],
    ) -> Result<Self, GbError> {
        check_nd(n, degree)?;
        let expected = 1 + listed_point_count(n, degree);
        if points.len() != expected {
            return Err(GbError::ListingLength {
                expected,
                found: points.len(),
            });
        }
        let mut it = points[1..].iter();
        // `it` has exactly as many points as listed positions, so `next()` never runs out.
        GbPatch::from_connected(n, degree, points[0], |_, _, _| {
            it.next().copied().unwrap_or(DVec3::ZERO)
        })
    }

    /// The listing in `.gbp` order (central point, then the listed points). For a patch that is
    /// not connected this reads the listed positions only; check [`GbPatch::is_connected`].
    pub fn connected_listing(&self) -> Result<Vec<DVec3>, GbError> {
        let degree = self.check_shape()?;
        let n = self.n();
        let mut out = Vec::with_capacity(1 + listed_point_count(n, degree));
        out.push(self.center);
        out.extend(listed_positions(n, degree).map(|(i, j, k)| self.ribbons[i].row(k)[j]));
        Ok(out)
    }

    /// The largest distance between a ribbon point and its listed representative, with the
    /// position (side, column, row) where it occurs; (0, None) for a connected net.
    pub fn connection_defect(&self) -> Result<(f64, Option<Position>), GbError> {
        let degree = self.check_shape()?;
        let n = self.n();
        let mut worst = (0.0, None);
        for i in 0..n {
            for k in 0..layers(degree) {
                for j in 0..=degree {
                    let (ri, rj, rk) = listed_representative(n, degree, i, j, k);
                    let dist = self.ribbons[i].row(k)[j].distance(self.ribbons[ri].row(rk)[rj]);
                    // NaN coordinates count as infinitely far.
                    let dist = if dist.is_nan() { f64::INFINITY } else { dist };
                    if dist > worst.0 {
                        worst = (dist, Some((i, j, k)));
                    }
                }
            }
        }
        Ok(worst)
    }

    /// True when the patch has a valid shape and every shared point coincides with its listed
    /// representative within `tol` (a classic connected GB net).
    pub fn is_connected(&self, tol: f64) -> bool {
        matches!(self.connection_defect(), Ok((d, _)) if d <= tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_match_transfinite_formula() {
        // transfinite's io.cc: n · (1 + d/2) · ⌈d/2⌉ + 1 points in a .gbp file.
        for n in 3..9 {
            for d in 1..9 {
                let c = listed_positions(n, d).count();
                assert_eq!(c, listed_point_count(n, d));
                assert_eq!(c, n * (1 + d / 2) * d.div_ceil(2));
            }
        }
        assert_eq!(listed_point_count(5, 3), 20);
    }

    #[test]
    fn representatives_are_listed_and_idempotent() {
        for n in 3..8 {
            for d in 1..9 {
                let listed: std::collections::HashSet<_> = listed_positions(n, d).collect();
                for i in 0..n {
                    for k in 0..layers(d) {
                        for j in 0..=d {
                            let r = listed_representative(n, d, i, j, k);
                            assert!(listed.contains(&r), "n={n} d={d} ({i},{j},{k}) -> {r:?}");
                        }
                    }
                }
            }
        }
    }
}
