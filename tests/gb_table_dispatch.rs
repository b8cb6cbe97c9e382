//! The runtime-dispatched evaluation of weight tables (AVX2 + FMA where the CPU has them)
//! against the portable path: same samples and normals up to the rounding of fused
//! multiply-adds; the lane-wise normals bit for bit those of `SurfaceDerivs::normal`.

use gbsurf::gb::table::{GbTable, SimdPath};
use gbsurf::gb::{GbPatch, Ribbon, SurfaceDerivs, WeightForm};
use gbsurf::DVec3;
use proptest::prelude::*;

fn patch(n: usize, d: usize, coords: &[f64]) -> GbPatch {
    let mut k = 0;
    let mut next = || {
        k += 1;
        coords[k % coords.len()] + (k as f64 * 0.37).sin()
    };
    let ribbons = (0..n)
        .map(|_| Ribbon::from_fn(d, d.div_ceil(2), d + 1, |_, _| DVec3::new(next(), next(), next())))
        .collect();
    GbPatch { ribbons, center: DVec3::new(next(), next(), next()) }
}

/// `SurfaceDerivs::normal` of each lane.
fn normals_one_by_one(su: &[DVec3; 4], sv: &[DVec3; 4]) -> [DVec3; 4] {
    std::array::from_fn(|l| SurfaceDerivs { su: su[l], sv: sv[l], ..Default::default() }.normal().unwrap_or(DVec3::ZERO))
}

fn lanes(v: &[DVec3; 4]) -> [[f64; 4]; 3] {
    [v.map(|p| p.x), v.map(|p| p.y), v.map(|p| p.z)]
}

#[test]
fn normal_lanes_match_normal_on_special_vectors() {
    let su = [DVec3::X, DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0), DVec3::new(f64::INFINITY, 0.0, 1.0)];
    let sv = [DVec3::Y, DVec3::Y, DVec3::new(2.0, 4.0, 6.0), DVec3::Z];
    let (a, b) = (lanes(&su), lanes(&sv));
    let got = SurfaceDerivs::normal_lanes([&a[0], &a[1], &a[2]], [&b[0], &b[1], &b[2]]);
    let want = normals_one_by_one(&su, &sv);
    assert_eq!(got, lanes(&want));
    assert_eq!(want[0], DVec3::Z);
    assert_eq!(&want[1..], &[DVec3::ZERO; 3]);
}

fn vec3() -> impl Strategy<Value = DVec3> {
    let c = prop_oneof![3 => -1e3..1e3f64, 1 => Just(0.0), 1 => -1e-150..1e-150f64];
    (c.clone(), c.clone(), c).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

proptest! {
    #[test]
    fn normal_lanes_match_normal_bit_for_bit(su in prop::array::uniform4(vec3()), sv in prop::array::uniform4(vec3()), parallel in any::<bool>()) {
        // Some lanes parallel (degenerate) on request.
        let sv = if parallel { std::array::from_fn(|l| if l % 2 == 0 { su[l] * 3.0 } else { sv[l] }) } else { sv };
        let (a, b) = (lanes(&su), lanes(&sv));
        let got = SurfaceDerivs::normal_lanes([&a[0], &a[1], &a[2]], [&b[0], &b[1], &b[2]]);
        let want = lanes(&normals_one_by_one(&su, &sv));
        prop_assert_eq!(got.map(|r| r.map(f64::to_bits)), want.map(|r| r.map(f64::to_bits)));
    }

    #[test]
    fn dispatched_and_portable_eval_all_agree(n in 3usize..=8, d in 3usize..=5, coords in prop::collection::vec(-10.0..10.0f64, 8..40)) {
        let table = GbTable::new(n, d, 6, WeightForm::Squared).unwrap();
        let ctrl = table.controls_of(&patch(n, d, &coords)).unwrap();
        let size = ctrl.x.iter().chain(&ctrl.y).chain(&ctrl.z).fold(0.0f64, |m, v| m.max(v.abs()));
        let (mut p0, mut n0, mut p1, mut n1) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        table.eval_all_with(SimdPath::Detected, &ctrl, &mut p0, &mut n0);
        table.eval_all_with(SimdPath::Portable, &ctrl, &mut p1, &mut n1);
        prop_assert_eq!((p0.len(), p1.len()), (table.sample_count(), table.sample_count()));
        let mut derivs = vec![SurfaceDerivs::default(); p0.len()];
        table.for_each_sample_derivs_with(SimdPath::Portable, &ctrl, |s, d, _| derivs[s] = *d);
        for s in 0..p0.len() {
            // Positions: within 1e-14 of (largest coordinate) × (control points).
            prop_assert!((p0[s] - p1[s]).abs().max_element() <= 1e-14 * size * ctrl.len() as f64, "sample {}: {} vs {}", s, p0[s], p1[s]);
            // Normals: both unit (or both undefined) and close where S_u × S_v is not tiny.
            let f = derivs[s];
            // The derivatives differ by rounding (≈ 1e-14 relative); the normal's error grows as
            // 1/sin of the angle between S_u and S_v, so the bound does too.
            let sin = f.su.cross(f.sv).length() / (f.su.length() * f.sv.length());
            if sin > 1e-6 {
                prop_assert!((n0[s] - n1[s]).length() <= 1e-12 / sin, "sample {}: {} vs {} (sin {})", s, n0[s], n1[s], sin);
            }
        }
    }
}
