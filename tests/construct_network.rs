//! Assembly of a hand-made curve network: corner blocks, and G1 of the direction-blend twists
//! along a shared curve between two triangles with arbitrary node tangent planes.

use gbsurf::construct::check::{corner_block_defect, ribbon_frame, ribbon_g1_angle};
use gbsurf::construct::{
    assemble, ConstructError, CurveNetwork, PatchLayout, PatchSource, SideUse, TwistMode,
};
use gbsurf::ConvertOptions;
use gbsurf::DVec3;
use proptest::prelude::*;

fn rot(v: DVec3, axis: DVec3, ang: f64) -> DVec3 {
    let k = axis.normalize();
    v * ang.cos() + k.cross(v) * ang.sin() + k * k.dot(v) * (1.0 - ang.cos())
}


/// Two triangles A = (C0, C3, P) and B = (C3, C0, Q) sharing curve 0 (C0 → C3).
#[allow(clippy::too_many_arguments)]
fn two_triangles(n0: DVec3, n3: DVec3, q: [f64; 6], th: [f64; 4], mid: DVec3) -> CurveNetwork {
    let c0 = DVec3::ZERO;
    let c3 = DVec3::new(3.0, 0.2, -0.1);
    let p = DVec3::new(1.5, 2.5, 0.3);
    let qq = DVec3::new(1.4, -2.4, -0.2);
    let n0 = n0.normalize();
    let n3 = n3.normalize();
    // In-plane tangent at C0 towards C3 and at C3 towards C0.
    let proj = |v: DVec3, n: DVec3| (v - n * v.dot(n)).normalize();
    let a = proj(c3 - c0, n0) * q[0];
    let b = proj(c0 - c3, n3) * q[1];
    // A lies to the left of C0→C3 (seen from the normal side): rotate +θ at C0, −θ at C3.
    let f = rot(a.normalize(), n0, th[0]) * q[2]; // towards P from C0
    let g = rot(a.normalize(), n0, -th[1]) * q[3]; // towards Q from C0
    let e = rot(b.normalize(), n3, -th[2]) * q[4]; // towards P from C3
    let h = rot(b.normalize(), n3, th[3]) * q[5]; // towards Q from C3
    let curves = vec![
        [c0, c0 + a, c3 + b, c3],
        [c3, c3 + e, p + 0.3 * (c3 - p), p],
        [p, p + 0.3 * (c0 - p), c0 + f, c0],
        [c0, c0 + g, qq + 0.3 * (c0 - qq), qq],
        [qq, qq + 0.3 * (c3 - qq), c3 + h, c3],
    ];
    let s = |c, r| SideUse { curve: c, reversed: r };
    let tw = |v: Vec<DVec3>| v;
    CurveNetwork {
        nodes: vec![c0, c3, p, qq],
        node_normals: vec![n0, n3, DVec3::Z, DVec3::Z],
        curves,
        curve_nodes: vec![[0, 1], [1, 2], [2, 0], [0, 3], [3, 1]],
        mid: vec![mid, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO],
        crease: Vec::new(),
        end_scale: Vec::new(),
        patches: vec![
            PatchLayout {
                sides: vec![s(0, false), s(1, false), s(2, false)],
                corner_twists: tw(vec![c3 + 0.2 * (p - c3), p + 0.2 * (c0 - p), c0 + 0.3 * (p - c0)]),
                center: Some((c0 + c3 + p) / 3.0),
                source: PatchSource::Vertex(0),
            },
            PatchLayout {
                sides: vec![s(0, true), s(3, false), s(4, false)],
                corner_twists: tw(vec![c0 + 0.3 * (qq - c0), qq + 0.2 * (c3 - qq), c3 + 0.3 * (qq - c3)]),
                center: None,
                source: PatchSource::Face(0),
            },
        ],
    }
}

fn opts(t: TwistMode) -> ConvertOptions {
    ConvertOptions { twist: t, ..ConvertOptions::triangles_r8() }
}

proptest! {
    #[test]
    fn blend_twists_are_g1_along_shared_curve(
        n0 in (-0.5f64..0.5, -0.5f64..0.5), n3 in (-0.5f64..0.5, -0.5f64..0.5),
        q in prop::array::uniform6(0.3f64..1.5),
        th in prop::array::uniform4(0.4f64..2.6),
        mid in (-2.0f64..2.0, 0.2f64..3.0, -1.0f64..1.0),
        scale in 0.0f64..3.0,
    ) {
        let net = two_triangles(
            DVec3::new(n0.0, n0.1, 1.0), DVec3::new(n3.0, n3.1, 1.0), q, th,
            DVec3::new(mid.0, mid.1, mid.2),
        );
        for mode in [TwistMode::Approx, TwistMode::Interp] {
            let o = ConvertOptions { mid_scale: scale, ..opts(mode) };
            let s = assemble(&net, &o).unwrap();
            prop_assert_eq!(corner_block_defect(&s).value, 0.0);
            let g = ribbon_g1_angle(&s, 33);
            prop_assert!(g.value < 1e-8, "{:?}: {:?}", mode, g);
            // det(T, X_A, X_B) relative to the sizes, at many s.
            let ra = &s.patches[0].ribbons()[0];
            let rb = &s.patches[1].ribbons()[0];
            for k in 0..=40 {
                let u = k as f64 / 40.0;
                let (pa, ta, xa) = ribbon_frame(ra, u);
                let (pb, _, xb) = ribbon_frame(rb, 1.0 - u);
                prop_assert!(pa.distance(pb) < 1e-14);
                let det = ta.dot(xa.cross(xb));
                prop_assert!(det.abs() <= 1e-12 * ta.length() * xa.length() * xb.length());
            }
        }
    }
}

#[test]
fn interp_blend_reproduces_mid_direction() {
    // With Interp, X_A(½) = α_A(½) D_{0.5} + β_A(½) T(½): the normal at the middle is T(½) × D_{0.5}.
    let mid = DVec3::new(0.3, 1.7, 0.4);
    let net = two_triangles(DVec3::new(0.1, 0.2, 1.0), DVec3::new(-0.2, 0.1, 1.0), [1.0; 6], [1.2; 4], mid);
    let s = assemble(&net, &opts(TwistMode::Interp)).unwrap();
    let (_, t, x) = ribbon_frame(&s.patches[0].ribbons()[0], 0.5);
    let n = t.cross(x).normalize();
    assert!(n.dot(mid).abs() < 1e-12, "{}", n.dot(mid));
}

#[test]
fn none_mode_uses_corner_twists_and_is_not_g1_here() {
    let net = two_triangles(DVec3::new(0.1, 0.2, 1.0), DVec3::new(-0.2, 0.1, 1.0), [1.0; 6], [1.2; 4], DVec3::Y);
    let s = assemble(&net, &opts(TwistMode::None)).unwrap();
    let r = &s.patches[0].ribbons()[0];
    assert_eq!(r.row(1)[1], net.patches[0].corner_twists[2]);
    assert_eq!(r.row(1)[2], net.patches[0].corner_twists[0]);
    assert!(ribbon_g1_angle(&s, 17).value > 0.01);
    assert_eq!(s.neighbors[0][0], Some(gbsurf::construct::SideRef { patch: 1, side: 0 }));
    assert_eq!(s.neighbors[0][1], None);
}

#[test]
fn open_sides_adopt_shared_twists() {
    let net = two_triangles(DVec3::new(0.1, 0.2, 1.0), DVec3::new(-0.2, 0.1, 1.0), [1.0; 6], [1.2; 4], DVec3::Y);
    let s = assemble(&net, &opts(TwistMode::Interp)).unwrap();
    let r = s.patches[0].ribbons();
    // Side 1 starts at corner 0 (end of shared side 0).
    assert_eq!(r[1].row(1)[1], r[0].row(1)[2]);
    assert_eq!(r[2].row(1)[2], r[0].row(1)[1]);
}

#[test]
fn orientation_and_option_errors() {
    let mut net = two_triangles(DVec3::Z, DVec3::Z, [1.0; 6], [1.2; 4], DVec3::Y);
    let bad = ConvertOptions { fullness: 1.0, ..ConvertOptions::triangles_r8() };
    assert!(matches!(assemble(&net, &bad), Err(ConstructError::InvalidOption(_))));
    let bad = ConvertOptions { tile_depth: 2.0, ..ConvertOptions::triangles_r8() };
    assert!(matches!(assemble(&net, &bad), Err(ConstructError::InvalidOption(_))));
    net.patches[1].sides[0].reversed = false;
    assert!(assemble(&net, &opts(TwistMode::Interp)).is_err());
    let mut net = two_triangles(DVec3::Z, DVec3::Z, [1.0; 6], [1.2; 4], DVec3::Y);
    net.patches[1].sides.truncate(2);
    net.patches[1].corner_twists.truncate(2);
    assert!(matches!(assemble(&net, &opts(TwistMode::Interp)), Err(ConstructError::TooFewSides { patch: 1, sides: 2 })));
}

/// The end scales λ enter D = (λ_A X_A − λ_B X_B)/2 only (docs/math.md#direction-blends): with
/// λ = 2 at every end next to the shared curve and D_{0.5} doubled (`mid_scale` 2), D doubles,
/// α halves and the twists are those of λ = 1 (up to rounding), while D_{0.5} doubled alone
/// moves them. A single λ_A ≠ λ_B still gives G1 twists, other than λ = 1's.
#[test]
fn end_scales_scale_the_blends_direction() {
    let net = two_triangles(DVec3::new(0.1, 0.2, 1.0), DVec3::new(-0.2, 0.1, 1.0), [1.0; 6], [1.2; 4], DVec3::Y);
    let twists = |net: &CurveNetwork, o: &ConvertOptions| {
        let s = assemble(net, o).unwrap();
        let r = |p: usize| s.patches[p].ribbons()[0].row(1).to_vec();
        (r(0), r(1), ribbon_g1_angle(&s, 33).value)
    };
    let dist = |a: &[DVec3], b: &[DVec3]| a.iter().zip(b).map(|(x, y)| x.distance(*y)).fold(0.0f64, f64::max);
    for mode in [TwistMode::Approx, TwistMode::Interp] {
        let one = twists(&net, &opts(mode));
        let mut doubled = net.clone();
        doubled.end_scale = vec![[1.0, 1.0], [2.0, 2.0], [2.0, 2.0], [2.0, 2.0], [2.0, 2.0]];
        let o2 = ConvertOptions { mid_scale: 2.0, ..opts(mode) };
        let two = twists(&doubled, &o2);
        let mid_only = twists(&net, &o2);
        let d = dist(&one.0, &two.0).max(dist(&one.1, &two.1));
        let m = dist(&one.0, &mid_only.0).max(dist(&one.1, &mid_only.1));
        assert!(d <= 1e-12, "{mode:?}: λ = 2 with D_0.5 doubled moved the twists by {d}");
        assert!(m >= 1e-3, "{mode:?}: D_0.5 doubled alone moved the twists by {m} only");
        // λ_A = 2 at C0 only (curve 2 is A's side before the shared curve, ending at C0).
        let mut one_end = net.clone();
        one_end.end_scale = vec![[1.0, 1.0], [1.0, 1.0], [1.0, 2.0]];
        let skew = twists(&one_end, &opts(mode));
        assert!(skew.2 < 1e-8, "{mode:?}: G1 {}° with λ_A = 2", skew.2);
        assert!(dist(&one.0, &skew.0) >= 1e-3, "{mode:?}: λ_A = 2 at C0 left the twists");
    }
}

/// The fan split of a patch of more than 64 sides gives spoke i the D_{0.5} (D(0) + D(1))/2 with
/// D(1) the blend's own end direction at N_i, end scales included (docs/math.md#high-valence-split):
/// sides whose inner control points are halved towards their ends, with end scale 2 at both
/// ends, give every spoke the D_{0.5} of the unhalved sides with scale 1 (their λX agree).
#[test]
fn fan_split_spokes_use_the_end_scales() {
    use gbsurf::construct::network::split_large_patches;
    let n = 70;
    let node = |i: usize| {
        let t = std::f64::consts::TAU * (i % n) as f64 / n as f64;
        DVec3::new(t.cos(), t.sin(), 0.1 * (3.0 * t).sin())
    };
    // Side i runs from N_{i−1} to N_i, bulging upwards; `half` moves its inner points halfway
    // towards its ends.
    let network = |half: bool, scale: f64| {
        let f = if half { 0.5 } else { 1.0 };
        let curves: Vec<[DVec3; 4]> = (0..n)
            .map(|i| {
                let (a, b) = (node(i + n - 1), node(i));
                let (c1, c2) = (a + (b - a) / 3.0 + 0.05 * DVec3::Z, b + (a - b) / 3.0 + 0.05 * DVec3::Z);
                [a, a + f * (c1 - a), b + f * (c2 - b), b]
            })
            .collect();
        CurveNetwork {
            nodes: (0..n).map(node).collect(),
            node_normals: vec![DVec3::Z; n],
            curves,
            curve_nodes: (0..n).map(|i| [(i + n - 1) % n, i]).collect(),
            mid: vec![DVec3::ZERO; n],
            crease: Vec::new(),
            end_scale: vec![[scale, scale]; n],
            patches: vec![PatchLayout {
                sides: (0..n).map(|i| SideUse { curve: i, reversed: false }).collect(),
                corner_twists: vec![DVec3::ZERO; n],
                center: Some(DVec3::new(0.0, 0.0, 0.3)),
                source: PatchSource::Vertex(0),
            }],
        }
    };
    let spoke_mids = |net: &CurveNetwork| {
        let (split, parts) = split_large_patches(net, 64).expect("the patch is split");
        assert_eq!(parts[0].parts.len(), n);
        split.mid[n..].to_vec()
    };
    let plain = spoke_mids(&network(false, 1.0));
    let dist = |a: &[DVec3], b: &[DVec3]| a.iter().zip(b).map(|(x, y)| x.distance(*y)).fold(0.0f64, f64::max);
    let scaled = dist(&plain, &spoke_mids(&network(true, 2.0)));
    let unscaled = dist(&plain, &spoke_mids(&network(true, 1.0)));
    assert!(scaled <= 1e-12, "halved sides with end scale 2 moved the spokes' D_0.5 by {scaled}");
    assert!(unscaled >= 1e-3, "halved sides with end scale 1 moved the spokes' D_0.5 by {unscaled} only");
}
