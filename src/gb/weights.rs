//! Blending functions of the GB patch: correction weights μ (seed 000 eq. 2.23, generalized to
//! any degree as in docs/math.md#correction-weights), ribbon weights μ·B^d_j(s_i)·B^d_k(h_i) (eq. 2.22) and the
//! central weight B0 = 1 − Σ μ B B (eq. 2.25), each with first and second derivatives in (u, v).
//!
//! Flat control-point order (used by [`GbBasis`] and `GbPatch::control_points_flat`):
//! index 0 is the central point; then side i = 0..n−1, row k = 0..l−1, column j = 0..=d at
//! index `1 + (i·l + k)·(d+1) + j`, with l = ⌈d/2⌉.

use super::derivs::Jet2;
use super::domain::{Domain, DomainScratch, LocalParam};
use super::error::GbError;
use super::patch::WeightForm;
use crate::bezier::bernstein::bernstein_all_into;
use glam::DVec2;

use crate::limits::MAX_DEGREE;

/// Err unless 2 ≤ d ≤ [`MAX_DEGREE`] (`side` names the ribbon in the error).
pub(crate) fn check_degree(side: usize, d: usize) -> Result<(), GbError> {
    if d < 2 {
        return Err(GbError::DegreeTooLow { side, degree: d });
    }
    if d > MAX_DEGREE {
        return Err(GbError::DegreeTooHigh {
            side,
            degree: d,
            max: MAX_DEGREE,
        });
    }
    Ok(())
}

/// Layers of a degree-d GB ribbon: l = ⌈d/2⌉.
pub fn layers_for_degree(d: usize) -> usize {
    d.div_ceil(2)
}

/// The five cases of the correction weight μ^i_{j,k} (docs/math.md#correction-weights, any degree d):
/// k < 2 and j < 2 → α_i; k < 2 and j > d−2 → β_i; otherwise j = k or j = d−k → ½;
/// otherwise j < k or j > d−k → 0; otherwise 1.
/// One exception: for d = 2 the middle boundary point (k = 0, j = 1) belongs to side i alone
/// (it is not in a corner block), so μ = 1 there; the literal rule would give α_i, which breaks the
/// n = 4 tensor-product reproduction (the `transfinite` evaluator applies the literal rule).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MuKind {
    Alpha,
    Beta,
    Half,
    Zero,
    One,
}

/// μ case of the control point in row k, column j of a degree-d ribbon.
pub fn mu_kind(d: usize, k: usize, j: usize) -> MuKind {
    if d == 2 && k == 0 && j == 1 {
        MuKind::One
    } else if k < 2 && j < 2 {
        MuKind::Alpha
    } else if k < 2 && j + 2 > d {
        MuKind::Beta
    } else if j == k || j + k == d {
        MuKind::Half
    } else if j < k || j + k > d {
        MuKind::Zero
    } else {
        MuKind::One
    }
}

/// Round-off control at the corners, where α_i (β_i) is 0/0 and its derivatives grow like
/// 1/r and 1/r² with the distance r to the corner. The value is always the exact quotient
/// (½ exactly at the corner). Its derivatives only multiply the difference of two corner blocks,
/// which vanishes at the corner, but in a per-control-point basis they are summed with
/// cancellation (round-off ε/r and ε/r²). So the second derivatives of α are dropped for
/// r < `CORNER_R2` and the first ones for r < `CORNER_R1`: for shared corner blocks this is
/// exact (α_i + β_{i−1} = 1), for independent blocks the surface's own second derivatives have no
/// limit at the corner and the first ones change by O(r).
const CORNER_R0: f64 = 1e-12;
const CORNER_R1: f64 = 1e-8;
const CORNER_R2: f64 = 1e-5;

/// α = a²/(a²+b²) (squared) or a/(a+b) (linear) with derivatives; ½ at the 0/0 corner.
/// α_i uses (a, b) = (h_{i−1}, h_i); β_i uses (h_{i+1}, h_i).
#[inline]
pub fn corner_weight(a: Jet2, b: Jet2, form: WeightForm) -> Jet2 {
    let (num, den, r) = match form {
        WeightForm::Squared => {
            let a2 = a * a;
            let den = a2 + b * b;
            (a2, den, den.val.max(0.0).sqrt())
        }
        WeightForm::Linear => {
            let den = a + b;
            (a, den, den.val.abs())
        }
    };
    // Within 1e-12 of the corner the quotient of two round-off-sized numbers is meaningless
    // (the linear form may even divide by a cancelled sum); ½ changes the point by O(r).
    if !(r > CORNER_R0) {
        return Jet2::constant(0.5);
    }
    let mut w = num / den;
    if r < CORNER_R2 {
        w.duu = 0.0;
        w.duv = 0.0;
        w.dvv = 0.0;
        if r < CORNER_R1 {
            w.du = 0.0;
            w.dv = 0.0;
        }
    }
    if !w.is_finite() {
        return Jet2::constant(w.val.clamp(0.0, 1.0));
    }
    w
}

/// Non-allocating Bernstein values with derivatives of one degree, reusable across calls.
#[derive(Clone, Debug, Default)]
pub struct BernsteinBuf {
    b: Vec<f64>,
    b1: Vec<f64>,
    b2: Vec<f64>,
}

impl BernsteinBuf {
    /// B^d_j(t(u,v)) for j = 0..=d as jets, written to `out[0..=d]`.
    pub fn jets_into(&mut self, d: usize, t: Jet2, out: &mut [Jet2]) {
        self.b.resize(d + 1, 0.0);
        self.b1.resize(d + 1, 0.0);
        self.b2.resize(d + 1, 0.0);
        bernstein_all_into(d, t.val, &mut self.b);
        if d >= 1 {
            bernstein_all_into(d - 1, t.val, &mut self.b1);
        }
        if d >= 2 {
            bernstein_all_into(d - 2, t.val, &mut self.b2);
        }
        let df = d as f64;
        let dd = (d * d.saturating_sub(1)) as f64;
        let lower1 = |j: usize| -> f64 {
            // B^{d−1}_{j−1} − B^{d−1}_j
            if d == 0 {
                return 0.0;
            }
            let a = if j >= 1 { self.b1[j - 1] } else { 0.0 };
            let c = if j < d { self.b1[j] } else { 0.0 };
            a - c
        };
        let lower2 = |j: usize| -> f64 {
            if d < 2 {
                return 0.0;
            }
            let g = |m: isize| {
                if m >= 0 && (m as usize) <= d - 2 {
                    self.b2[m as usize]
                } else {
                    0.0
                }
            };
            let j = j as isize;
            g(j - 2) - 2.0 * g(j - 1) + g(j)
        };
        for j in 0..=d {
            out[j] = t.compose(self.b[j], df * lower1(j), dd * lower2(j));
        }
    }
}

/// Per-control-point weights of a GB patch at one domain point, with derivatives, in the flat
/// order of the module docs (central point first).
#[derive(Clone, Debug, PartialEq)]
pub struct GbBasis {
    pub n: usize,
    pub degree: usize,
    pub layers: usize,
    /// `weights[0]` = B0 (central point), `weights[GbBasis::index(..)]` = μ B^d_j(s_i) B^d_k(h_i).
    pub weights: Vec<Jet2>,
}

impl GbBasis {
    /// Number of control points 1 + n·l·(d+1).
    pub fn len_for(n: usize, d: usize) -> usize {
        1 + n * layers_for_degree(d) * (d + 1)
    }

    /// Flat index of control point (side i, row k, column j).
    pub fn index_for(d: usize, i: usize, k: usize, j: usize) -> usize {
        1 + (i * layers_for_degree(d) + k) * (d + 1) + j
    }

    /// Flat index of (side i, row k, column j) in this basis.
    pub fn index(&self, i: usize, k: usize, j: usize) -> usize {
        1 + (i * self.layers + k) * (self.degree + 1) + j
    }

    /// Weight of the central point.
    pub fn center(&self) -> Jet2 {
        self.weights[0]
    }

    /// Number of weights.
    pub fn len(&self) -> usize {
        self.weights.len()
    }

    /// Always false (a basis has at least the central weight).
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }
}

/// Reusable evaluator of GB basis functions for one (n, d): holds the domain and scratch, so
/// repeated evaluations do not allocate.
#[derive(Clone, Debug)]
pub struct GbBasisEvaluator {
    domain: Domain,
    degree: usize,
    layers: usize,
    mu: Vec<MuKind>,
    scratch: DomainScratch,
    params: Vec<LocalParam>,
    bs: Vec<Jet2>,
    bh: Vec<Jet2>,
    bern: BernsteinBuf,
}

impl GbBasisEvaluator {
    /// Evaluator for n sides and degree d (n ≥ 3, 2 ≤ d ≤ [`MAX_DEGREE`]).
    pub fn new(n: usize, d: usize) -> Result<Self, GbError> {
        check_degree(0, d)?;
        let domain = Domain::regular(n)?;
        let layers = layers_for_degree(d);
        let mut mu = Vec::with_capacity(layers * (d + 1));
        for k in 0..layers {
            for j in 0..=d {
                mu.push(mu_kind(d, k, j));
            }
        }
        Ok(GbBasisEvaluator {
            scratch: domain.scratch(),
            params: vec![LocalParam::default(); n],
            bs: vec![Jet2::ZERO; d + 1],
            bh: vec![Jet2::ZERO; d + 1],
            bern: BernsteinBuf::default(),
            domain,
            degree: d,
            layers,
            mu,
        })
    }

    /// The domain polygon.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// Number of sides n.
    pub fn n(&self) -> usize {
        self.domain.n()
    }

    /// Degree d.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Layers l = ⌈d/2⌉.
    pub fn layers(&self) -> usize {
        self.layers
    }

    /// Number of control points / weights 1 + n·l·(d+1).
    pub fn len(&self) -> usize {
        GbBasis::len_for(self.n(), self.degree)
    }

    /// Always false.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Calls `f(flat_index, weight)` for every ribbon control point (flat index ≥ 1, in flat
    /// order) and returns the central weight B0 = 1 − Σ (index 0), which it does not pass to `f`.
    #[inline]
    pub fn for_each_ribbon_weight(
        &mut self,
        uv: DVec2,
        form: WeightForm,
        mut f: impl FnMut(usize, Jet2),
    ) -> Jet2 {
        let n = self.domain.n();
        let d = self.degree;
        let l = self.layers;
        self.domain
            .local_params_into(uv, &mut self.scratch, &mut self.params);
        let mut sum = Jet2::ZERO;
        let mut idx = 1;
        for i in 0..n {
            let hp = self.params[(i + n - 1) % n].h;
            let LocalParam { s, h } = self.params[i];
            let hn = self.params[(i + 1) % n].h;
            let alpha = corner_weight(hp, h, form);
            let beta = corner_weight(hn, h, form);
            self.bern.jets_into(d, s, &mut self.bs);
            self.bern.jets_into(d, h, &mut self.bh);
            for k in 0..l {
                let bk = self.bh[k];
                for j in 0..=d {
                    let w = match self.mu[k * (d + 1) + j] {
                        MuKind::Alpha => alpha * self.bs[j] * bk,
                        MuKind::Beta => beta * self.bs[j] * bk,
                        MuKind::Half => (self.bs[j] * bk).scale(0.5),
                        MuKind::One => self.bs[j] * bk,
                        MuKind::Zero => Jet2::ZERO,
                    };
                    sum = sum + w;
                    f(idx, w);
                    idx += 1;
                }
            }
        }
        Jet2::constant(1.0) - sum
    }

    /// All weights into `out` (length [`Self::len`]), flat order, central weight at index 0.
    pub fn eval_into(
        &mut self,
        uv: DVec2,
        form: WeightForm,
        out: &mut [Jet2],
    ) -> Result<(), GbError> {
        if out.len() != self.len() {
            return Err(GbError::BufferLength {
                expected: self.len(),
                found: out.len(),
            });
        }
        let b0 = self.for_each_ribbon_weight(uv, form, |idx, w| out[idx] = w);
        out[0] = b0;
        Ok(())
    }

    /// All weights as a [`GbBasis`].
    pub fn eval(&mut self, uv: DVec2, form: WeightForm) -> GbBasis {
        let mut weights = vec![Jet2::ZERO; self.len()];
        let b0 = self.for_each_ribbon_weight(uv, form, |idx, w| weights[idx] = w);
        weights[0] = b0;
        GbBasis {
            n: self.n(),
            degree: self.degree,
            layers: self.layers,
            weights,
        }
    }
}

/// The GB basis (every control point's weight with first and second derivatives) of an n-sided
/// degree-d patch at the domain point `uv` (seed 000 eq. 2.22–2.25). For repeated use prefer
/// [`GbBasisEvaluator`].
pub fn gb_basis(n: usize, d: usize, uv: DVec2, form: WeightForm) -> Result<GbBasis, GbError> {
    Ok(GbBasisEvaluator::new(n, d)?.eval(uv, form))
}
