//! Shared test helpers for the GB tests: deterministic random nets.
#![allow(dead_code)]

use gbsurf::gb::{layers_for_degree, GbPatch, Ribbon};
use gbsurf::{DVec2, DVec3};

/// Small deterministic generator (xorshift64*).
pub struct Rng(pub u64);
impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(2654435761).wrapping_add(12345) | 1)
    }
    pub fn f(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn v(&mut self) -> DVec3 {
        DVec3::new(
            self.f() * 2.0 - 1.0,
            self.f() * 2.0 - 1.0,
            self.f() * 2.0 - 1.0,
        )
    }
}

/// Random rows (l rows of d+1 points) whose row-0 end points agree at the corners.
pub fn random_ribbons(degrees: &[usize], layers: &[usize], seed: u64) -> Vec<Ribbon> {
    let mut r = Rng::new(seed);
    let n = degrees.len();
    let mut ribbons: Vec<Ribbon> = (0..n)
        .map(|i| Ribbon::from_fn(degrees[i], layers[i], degrees[i] + 1, |_, _| r.v()))
        .collect();
    for i in 0..n {
        let prev = &ribbons[(i + n - 1) % n];
        let p = prev.row(0)[prev.degree];
        ribbons[i].row_mut(0)[0] = p;
    }
    ribbons
}

/// Random GB patch with consistent corner points.
pub fn random_patch(n: usize, d: usize, seed: u64) -> GbPatch {
    let l = layers_for_degree(d);
    GbPatch {
        ribbons: random_ribbons(&vec![d; n], &vec![l; n], seed),
        center: Rng::new(seed + 1).v(),
    }
}

/// Central finite differences of a map R² → R³: (p, su, sv, suu, suv, svv).
pub fn fd_derivs(f: &dyn Fn(DVec2) -> DVec3, x: DVec2) -> [DVec3; 6] {
    let e = 1e-5;
    let g = |a: f64, b: f64| f(x + DVec2::new(a, b));
    let p = g(0.0, 0.0);
    [
        p,
        (g(e, 0.0) - g(-e, 0.0)) / (2.0 * e),
        (g(0.0, e) - g(0.0, -e)) / (2.0 * e),
        (g(e, 0.0) - 2.0 * p + g(-e, 0.0)) / (e * e),
        (g(e, e) - g(e, -e) - g(-e, e) + g(-e, -e)) / (4.0 * e * e),
        (g(0.0, e) - 2.0 * p + g(0.0, -e)) / (e * e),
    ]
}
