//! The ribbon-only CGB patch (seed 000 §3.6, eq. 3.7–3.8): ribbons of independent degree d_i
//! and layer count l_i, S = Σ_i R_i / B_sum with R_i = Σ_{j,k} μ^i_{j,k} B^{d_i}_j(s_i)
//! B^{d_i}_k(h_i) P^i_{j,k} and B_sum the sum of all these weights; no central point.
//! Derivatives by the quotient rule, exact.

use super::derivs::{Jet2, SurfaceDerivs};
use super::domain::{Domain, DomainScratch, LocalParam};
use super::error::GbError;
use super::eval::{validate_ribbons, Evaluate};
use super::patch::{CgbPatch, WeightForm};
use super::weights::{check_degree, corner_weight, mu_kind, BernsteinBuf, MuKind};
use glam::{DVec2, DVec3};

/// Reusable evaluator of CGB weights for given per-side degrees and layer counts.
#[derive(Clone, Debug)]
pub struct CgbBasisEvaluator {
    domain: Domain,
    degrees: Vec<usize>,
    layers: Vec<usize>,
    scratch: DomainScratch,
    params: Vec<LocalParam>,
    bs: Vec<Jet2>,
    bh: Vec<Jet2>,
    bern: BernsteinBuf,
}

impl CgbBasisEvaluator {
    /// Evaluator for sides with degrees `degrees[i]` (2..=[`crate::limits::MAX_DEGREE`]) and `layers[i]` rows (1..=d_i+1).
    pub fn new(degrees: &[usize], layers: &[usize]) -> Result<Self, GbError> {
        let n = degrees.len();
        let domain = Domain::regular(n)?;
        if layers.len() != n {
            return Err(GbError::BufferLength {
                expected: n,
                found: layers.len(),
            });
        }
        for (i, (&d, &l)) in degrees.iter().zip(layers).enumerate() {
            check_degree(i, d)?;
            if l == 0 || l > d + 1 {
                return Err(GbError::LayerCount {
                    side: i,
                    expected: d.div_ceil(2),
                    found: l,
                });
            }
        }
        let dmax = degrees.iter().copied().max().unwrap_or(0);
        Ok(CgbBasisEvaluator {
            scratch: domain.scratch(),
            params: vec![LocalParam::default(); n],
            bs: vec![Jet2::ZERO; dmax + 1],
            bh: vec![Jet2::ZERO; dmax + 1],
            bern: BernsteinBuf::default(),
            degrees: degrees.to_vec(),
            layers: layers.to_vec(),
            domain,
        })
    }

    /// The domain polygon.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// Number of weights Σ_i l_i (d_i + 1); flat order side i, row k, column j.
    pub fn len(&self) -> usize {
        self.degrees
            .iter()
            .zip(&self.layers)
            .map(|(d, l)| l * (d + 1))
            .sum()
    }

    /// Always false for n ≥ 3.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Calls `f(side, row, column, unnormalized weight)` for every control point and returns
    /// B_sum (eq. 3.7).
    pub fn for_each_weight(
        &mut self,
        uv: DVec2,
        form: WeightForm,
        mut f: impl FnMut(usize, usize, usize, Jet2),
    ) -> Jet2 {
        let n = self.domain.n();
        self.domain
            .local_params_into(uv, &mut self.scratch, &mut self.params);
        let mut sum = Jet2::ZERO;
        for i in 0..n {
            let (d, l) = (self.degrees[i], self.layers[i]);
            let hp = self.params[(i + n - 1) % n].h;
            let LocalParam { s, h } = self.params[i];
            let hn = self.params[(i + 1) % n].h;
            let alpha = corner_weight(hp, h, form);
            let beta = corner_weight(hn, h, form);
            self.bern.jets_into(d, s, &mut self.bs);
            self.bern.jets_into(d, h, &mut self.bh);
            for k in 0..l {
                for j in 0..=d {
                    let bb = self.bs[j] * self.bh[k];
                    let w = match mu_kind(d, k, j) {
                        MuKind::Alpha => alpha * bb,
                        MuKind::Beta => beta * bb,
                        MuKind::Half => bb.scale(0.5),
                        MuKind::One => bb,
                        MuKind::Zero => Jet2::ZERO,
                    };
                    sum = sum + w;
                    f(i, k, j, w);
                }
            }
        }
        sum
    }

    /// Normalized weights w / B_sum with derivatives (quotient rule) into `out` (length
    /// [`Self::len`], flat order).
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
        let mut idx = 0;
        let sum = self.for_each_weight(uv, form, |_, _, _, w| {
            out[idx] = w;
            idx += 1;
        });
        for w in out.iter_mut() {
            *w = *w / sum;
        }
        Ok(())
    }
}

/// S = N / W for a vector numerator N (given as derivatives) and scalar jet W: the quotient rule
/// up to second order.
fn vector_quotient(nm: &SurfaceDerivs, w: &Jet2) -> SurfaceDerivs {
    let inv = 1.0 / w.val;
    let p = nm.p * inv;
    let su = (nm.su - p * w.du) * inv;
    let sv = (nm.sv - p * w.dv) * inv;
    SurfaceDerivs {
        p,
        su,
        sv,
        suu: (nm.suu - su * (2.0 * w.du) - p * w.duu) * inv,
        suv: (nm.suv - su * w.dv - sv * w.du - p * w.duv) * inv,
        svv: (nm.svv - sv * (2.0 * w.dv) - p * w.dvv) * inv,
    }
}

impl CgbPatch {
    /// Number of sides n.
    pub fn n(&self) -> usize {
        self.ribbons.len()
    }

    /// Degree of each side.
    pub fn degrees(&self) -> Vec<usize> {
        self.ribbons.iter().map(|r| r.degree).collect()
    }

    /// Layer count (rows) of each side.
    pub fn layer_counts(&self) -> Vec<usize> {
        self.ribbons.iter().map(|r| r.layers()).collect()
    }

    /// Checks n ≥ 3, d_i ≥ 2, 1 ≤ l_i ≤ d_i + 1 rows of d_i + 1 finite points.
    pub fn validate(&self) -> Result<(), GbError> {
        if self.n() < 3 {
            return Err(GbError::TooFewSides(self.n()));
        }
        validate_ribbons(&self.ribbons, true, |i, r| {
            let l = r.layers();
            if l == 0 || l > r.degree + 1 {
                return Err(GbError::LayerCount {
                    side: i,
                    expected: r.degree.div_ceil(2),
                    found: l,
                });
            }
            Ok(())
        })
    }

    /// Control points in flat order (side i, row k, column j).
    pub fn control_points_flat(&self) -> Vec<DVec3> {
        self.ribbons
            .iter()
            .flat_map(|r| r.points().iter().copied())
            .collect()
    }

    /// A weight evaluator matching this patch's degrees and layers.
    pub fn evaluator(&self) -> Result<CgbBasisEvaluator, GbError> {
        CgbBasisEvaluator::new(&self.degrees(), &self.layer_counts())
    }

    /// S(u, v) = Σ R_i / B_sum and its derivatives with a prepared evaluator (eq. 3.8).
    pub fn eval_derivs_with(
        &self,
        ev: &mut CgbBasisEvaluator,
        uv: DVec2,
        form: WeightForm,
    ) -> SurfaceDerivs {
        let mut num = SurfaceDerivs::default();
        let sum = ev.for_each_weight(uv, form, |i, k, j, w| {
            if let Some(p) = self
                .ribbons
                .get(i)
                .and_then(|r| r.get_row(k))
                .and_then(|row| row.get(j))
            {
                num.add_weighted(&w, *p);
            }
        });
        if !(sum.val.abs() > 1e-300) {
            return SurfaceDerivs {
                p: num.p,
                ..Default::default()
            };
        }
        vector_quotient(&num, &sum)
    }

}

impl Evaluate for CgbPatch {
    /// For an invalid patch: zeros.
    fn eval_derivs(&self, uv: DVec2, form: WeightForm) -> SurfaceDerivs {
        match self.evaluator() {
            Ok(mut ev) => self.eval_derivs_with(&mut ev, uv, form),
            Err(_) => SurfaceDerivs::default(),
        }
    }
}
