//! Composite (piecewise) Bézier curves and the smoothness of their joints (seed 001 §1.6).

use super::curve::BezierCurve;
use super::{angle_between, BezierError, Point};

/// A composite Bézier curve S on [u_0, u_N] (seed 001 def. 1.11): segment i is the Bézier curve
/// S_i over [u_i, u_{i+1}], S(u) = S_i((u − u_i)/Δ_i) with Δ_i = u_{i+1} − u_i.
/// Segments may have different degrees. Joint j is the break value u_{j+1} between segments j
/// and j + 1.
#[derive(Debug, Clone, PartialEq)]
pub struct CompositeCurve<P> {
    segments: Vec<BezierCurve<P>>,
    breaks: Vec<f64>,
}

impl<P: Point> CompositeCurve<P> {
    /// Composite curve from segments and break values u_0 < u_1 < … < u_N (N = segments).
    pub fn new(segments: Vec<BezierCurve<P>>, breaks: Vec<f64>) -> Result<Self, BezierError> {
        if segments.is_empty() {
            return Err(BezierError::Empty);
        }
        if breaks.len() != segments.len() + 1 {
            return Err(BezierError::BreakCount {
                breaks: breaks.len(),
                segments: segments.len(),
            });
        }
        if let Some(index) = (0..breaks.len())
            .find(|&i| !breaks[i].is_finite() || (i > 0 && breaks[i] <= breaks[i - 1]))
        {
            return Err(BezierError::BadBreak { index });
        }
        Ok(Self { segments, breaks })
    }

    /// Composite curve with the uniform break values 0, 1, …, N.
    pub fn uniform(segments: Vec<BezierCurve<P>>) -> Result<Self, BezierError> {
        let breaks = (0..=segments.len()).map(|i| i as f64).collect();
        Self::new(segments, breaks)
    }

    /// The segments S_0 … S_{N−1}.
    pub fn segments(&self) -> &[BezierCurve<P>] {
        &self.segments
    }

    /// The break values u_0 … u_N.
    pub fn breaks(&self) -> &[f64] {
        &self.breaks
    }

    /// Number of joints (N − 1).
    pub fn joint_count(&self) -> usize {
        self.segments.len() - 1
    }

    /// Index of the segment containing u (the first one at a break; u outside the range uses
    /// the first or last segment, extrapolating).
    pub fn segment_index(&self, u: f64) -> usize {
        let k = self.breaks[1..self.breaks.len() - 1].partition_point(|&b| b < u);
        k.min(self.segments.len() - 1)
    }

    /// S(u).
    pub fn eval(&self, u: f64) -> P {
        self.derivative(u, 0)
    }

    /// d^r S/du^r = Δ_i^{−r} S_i^{(r)}(t) with t = (u − u_i)/Δ_i (chain rule, seed 001 eq. 1.6).
    pub fn derivative(&self, u: f64, r: usize) -> P {
        let i = self.segment_index(u);
        let d = self.breaks[i + 1] - self.breaks[i];
        self.segments[i].derivative((u - self.breaks[i]) / d, r) * d.powi(-(r as i32))
    }

    /// For k = 0..=r, |S_j^{(k)}(1)/Δ_j^k − S_{j+1}^{(k)}(0)/Δ_{j+1}^k| at joint j: the gaps of
    /// the one-sided derivatives with respect to the global parameter (seed 001 eq. 1.18).
    pub fn joint_gaps(&self, joint: usize, r: usize) -> Result<Vec<f64>, BezierError> {
        Ok(self
            .joint_derivatives(joint, r)?
            .into_iter()
            .map(|(l, rr)| (l - rr).norm())
            .collect())
    }

    fn joint_derivatives(&self, joint: usize, r: usize) -> Result<Vec<(P, P)>, BezierError> {
        if joint >= self.joint_count() {
            return Err(BezierError::NoSuchJoint {
                joint,
                joints: self.joint_count(),
            });
        }
        let (a, b) = (&self.segments[joint], &self.segments[joint + 1]);
        let da = self.breaks[joint + 1] - self.breaks[joint];
        let db = self.breaks[joint + 2] - self.breaks[joint + 1];
        let left = a.derivatives(1.0, r);
        let right = b.derivatives(0.0, r);
        Ok((0..=r)
            .map(|k| {
                (
                    left[k] * da.powi(-(k as i32)),
                    right[k] * db.powi(-(k as i32)),
                )
            })
            .collect())
    }

    /// The continuity order achieved at joint j, checked up to `max_order`: the largest r such
    /// that the k-th derivatives agree for all k ≤ r, each to `tol` relative to
    /// max(1, |left|, |right|). `None` when the segments do not even meet (not C^0).
    pub fn continuity_order(
        &self,
        joint: usize,
        max_order: usize,
        tol: f64,
    ) -> Result<Option<usize>, BezierError> {
        let derivs = self.joint_derivatives(joint, max_order)?;
        let ok = |(l, r): &(P, P)| (*l - *r).norm() <= tol * 1f64.max(l.norm()).max(r.norm());
        Ok(derivs.iter().take_while(|lr| ok(lr)).count().checked_sub(1))
    }

    /// The angle in [0, π] between the end tangent of segment j and the start tangent of
    /// segment j + 1 at joint j: 0 means G1 (tangents parallel with the same orientation,
    /// seed 001 §1.6). Tangent directions come from the first control point different from the
    /// end point, so a vanishing first derivative still gives the geometric tangent.
    pub fn g1_angle(&self, joint: usize) -> Result<f64, BezierError> {
        if joint >= self.joint_count() {
            return Err(BezierError::NoSuchJoint {
                joint,
                joints: self.joint_count(),
            });
        }
        let left = end_tangent(&self.segments[joint].reversed())
            .ok_or(BezierError::DegenerateTangent { segment: joint })?;
        let right = end_tangent(&self.segments[joint + 1])
            .ok_or(BezierError::DegenerateTangent { segment: joint + 1 })?;
        Ok(angle_between(-left, right))
    }
}

/// Direction p_k − p_0 for the first control point p_k ≠ p_0: the tangent direction at t = 0.
fn end_tangent<P: Point>(c: &BezierCurve<P>) -> Option<P> {
    let p = c.points();
    p[1..].iter().map(|&q| q - p[0]).find(|d| d.norm() > 0.0)
}
