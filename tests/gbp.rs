//! The connected GB net (gb::connected) and the `.gbp` format (gb::gbp).

use gbsurf::gb::connected::{listed_point_count, listed_positions};
use gbsurf::gb::gbp::{load_gbp, parse_gbp, read_gbp, to_gbp_string, write_gbp, GbpError};
use gbsurf::gb::{layers_for_degree as layers, GbError, GbPatch};
use gbsurf::DVec3;
use proptest::prelude::*;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data");

fn sample_patch(n: usize, d: usize) -> GbPatch {
    GbPatch::from_connected(n, d, DVec3::new(0.5, -0.25, 2.0), |i, j, k| {
        DVec3::new(
            i as f64 + 0.1 * j as f64,
            (j * j) as f64 / 7.0,
            k as f64 * 1.5 + 0.01 * i as f64,
        )
    })
    .unwrap()
}

/// The sharing rule exactly as docs/math.md#sharing states it.
fn assert_sharing_rule(p: &GbPatch) {
    let n = p.ribbons.len();
    let d = p.ribbons[0].degree;
    let l = layers(d);
    for i in 0..n {
        for k in 0..l {
            for j in 0..=d {
                let here = p.ribbons[i].row(k)[j];
                if j < l {
                    assert_eq!(
                        here,
                        p.ribbons[(i + n - 1) % n].row(j)[d - k],
                        "({i},{j},{k})"
                    );
                }
                if d - j < l {
                    assert_eq!(here, p.ribbons[(i + 1) % n].row(d - j)[k], "({i},{j},{k})");
                }
            }
        }
    }
}

#[test]
fn from_connected_obeys_sharing_rule_and_listing_order() {
    for n in 3..=8 {
        for d in 1..=8 {
            let p = sample_patch(n, d);
            assert_eq!(p.check_shape(), Ok(d));
            assert_sharing_rule(&p);
            assert!(p.is_connected(0.0));
            let listing = p.connected_listing().unwrap();
            assert_eq!(listing.len(), 1 + listed_point_count(n, d));
            assert_eq!(GbPatch::from_connected_listing(n, d, &listing).unwrap(), p);
        }
    }
}

#[test]
fn listing_order_is_row_side_column() {
    let order: Vec<_> = listed_positions(3, 3).collect();
    assert_eq!(
        order,
        vec![
            (0, 0, 0),
            (0, 1, 0),
            (0, 2, 0),
            (1, 0, 0),
            (1, 1, 0),
            (1, 2, 0),
            (2, 0, 0),
            (2, 1, 0),
            (2, 2, 0),
            (0, 1, 1),
            (1, 1, 1),
            (2, 1, 1),
        ]
    );
}

#[test]
fn shape_errors_are_reported() {
    assert_eq!(
        GbPatch::from_connected(2, 3, DVec3::ZERO, |_, _, _| DVec3::ZERO),
        Err(GbError::TooFewSides(2))
    );
    assert_eq!(
        GbPatch::from_connected(4, 0, DVec3::ZERO, |_, _, _| DVec3::ZERO),
        Err(GbError::DegreeTooLow { side: 0, degree: 0 })
    );
    assert_eq!(
        GbPatch::from_connected_listing(5, 3, &[DVec3::ZERO; 20]),
        Err(GbError::ListingLength {
            expected: 21,
            found: 20
        })
    );
    let mut p = sample_patch(4, 3);
    // Rows one point short (a ribbon's rows all have one length).
    p.ribbons[2] = gbsurf::gb::Ribbon::from_fn(3, 2, 3, |k, j| p.ribbons[2].row(k)[j]);
    assert_eq!(
        p.check_shape(),
        Err(GbError::RowLength {
            side: 2,
            row: 0,
            expected: 4,
            found: 3
        })
    );
    assert!(!p.is_connected(1.0));
    let mut p = sample_patch(4, 3);
    p.ribbons[3].degree = 4;
    assert!(matches!(
        p.check_shape(),
        Err(GbError::DegreeMismatch { side: 3, .. })
    ));
}

#[test]
fn perturbed_shared_point_breaks_connection() {
    let mut p = sample_patch(5, 3);
    // (1, 0, 1) is the copy of (0, 2, 0) (j < l rule); move only the copy.
    p.ribbons[1].row_mut(1)[0] += DVec3::new(0.0, 1e-6, 0.0);
    assert!(!p.is_connected(1e-9));
    assert!(p.is_connected(1e-5));
    let (defect, at) = p.connection_defect().unwrap();
    gbsurf::assert_near!(defect, 1e-6, 1e-15);
    assert_eq!(at, Some((1, 0, 1)));
    match write_gbp(&p, Vec::new()) {
        Err(GbpError::NotConnected {
            side: 1,
            column: 0,
            row: 1,
            ..
        }) => {}
        other => panic!("expected NotConnected, got {other:?}"),
    }
}

#[test]
fn reads_cubic_sample_file() {
    let p = load_gbp(format!("{DATA}/cubic5.gbp")).unwrap();
    assert_eq!(p.ribbons.len(), 5);
    assert_eq!(p.ribbons[0].degree, 3);
    assert_eq!(p.center, DVec3::new(0.0, 0.0, 0.6));
    // Side 0, row 0 as listed.
    assert_eq!(p.ribbons[0].row(0)[0], DVec3::new(0.309, -0.9511, 0.0));
    assert_eq!(p.ribbons[0].row(0)[2], DVec3::new(0.7697, -0.317, 0.0455));
    // Its column 3 is side 1's column 0 (the corner at domain vertex 0).
    assert_eq!(p.ribbons[0].row(0)[3], DVec3::new(1.0, 0.0, 0.0));
    // Row 1, column 0 of side 0 is side 4's row 0, column 2.
    assert_eq!(p.ribbons[0].row(1)[0], DVec3::new(-0.0637, -0.83, 0.0495));
    // Row 1, column 1 of side 0: the first listed point of row 1.
    assert_eq!(p.ribbons[0].row(1)[1], DVec3::new(0.3775, -0.4438, 0.3921));
    // Row 1, column 2 of side 0 is side 1's row 1, column 1.
    assert_eq!(p.ribbons[0].row(1)[2], DVec3::new(0.5388, 0.2219, 0.3122));
    assert_sharing_rule(&p);

    let q = load_gbp(format!("{DATA}/quintic3.gbp")).unwrap();
    assert_eq!(
        (
            q.ribbons.len(),
            q.ribbons[0].degree,
            q.ribbons[0].layers()
        ),
        (3, 5, 3)
    );
    assert_sharing_rule(&q);
}

#[test]
fn reader_is_whitespace_tolerant_like_operator_extraction() {
    let text = std::fs::read_to_string(format!("{DATA}/cubic5.gbp")).unwrap();
    let p = parse_gbp(&text).unwrap();
    let one_line = text.split_whitespace().collect::<Vec<_>>().join(" ");
    assert_eq!(parse_gbp(&one_line).unwrap(), p);
    let one_per_line = text.split_whitespace().collect::<Vec<_>>().join("\r\n\t ");
    assert_eq!(parse_gbp(&one_per_line).unwrap(), p);
    let padded = format!("\n\n  {}\n\n\n", text.replace(' ', "   \t"));
    assert_eq!(parse_gbp(&padded).unwrap(), p);
}

fn err(text: &str) -> GbpError {
    match parse_gbp(text) {
        Ok(p) => panic!("expected an error for {text:?}, got {p:?}"),
        Err(e) => e,
    }
}

/// A valid 3-sided cubic file (13 points), one point per line; point m is on line m + 2.
fn tri_text() -> String {
    let mut s = String::from("3 3\n");
    for m in 0..13 {
        s += &format!("{m} {} 0.5\n", m as f64 * 0.25);
    }
    s
}

#[test]
fn malformed_files_give_typed_errors_with_lines() {
    assert!(parse_gbp(&tri_text()).is_ok());
    assert!(matches!(err(""), GbpError::UnexpectedEof { line: 1, .. }));
    assert!(matches!(err("3"), GbpError::UnexpectedEof { line: 1, .. }));
    assert!(matches!(
        err("2 3\n"),
        GbpError::TooFewSides { line: 1, n: 2 }
    ));
    assert!(matches!(
        err("\n5 0\n"),
        GbpError::BadDegree { line: 2, d: 0 }
    ));
    // d = 1 has no GB correction weights: rejected on read and on write.
    assert!(matches!(
        err("3 1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"),
        GbpError::BadDegree { line: 1, d: 1 }
    ));
    let linear = GbPatch::from_connected_listing(3, 1, &[DVec3::ZERO; 4]).unwrap();
    assert!(matches!(
        to_gbp_string(&linear),
        Err(GbpError::DegreeOutput { d: 1 })
    ));
    assert!(matches!(
        err("5 1\n0 0 0\n"),
        GbpError::BadDegree { line: 1, d: 1 }
    ));
    assert!(matches!(
        err("3 3\n\n\n"),
        GbpError::UnexpectedEof { line: 1, .. }
    ));
    assert!(matches!(
        err("5\n\n1000000\n"),
        GbpError::BadDegree {
            line: 3,
            d: 1000000
        }
    ));
    assert!(matches!(
        err("99999999999 3\n"),
        GbpError::TooManySides { line: 1, .. }
    ));
    assert!(matches!(
        err("-3 3\n"),
        GbpError::BadInteger { line: 1, .. }
    ));
    assert!(matches!(
        err("5 3.0\n"),
        GbpError::BadInteger { line: 1, .. }
    ));
    assert!(matches!(
        err("5 three\n"),
        GbpError::BadInteger { line: 1, .. }
    ));

    let good = tri_text();
    let lines: Vec<&str> = good.lines().collect();
    // Truncated: drop the last line and half of the one before.
    let truncated = format!("{}\n{}\n", lines[..13].join("\n"), "12 3");
    match err(&truncated) {
        GbpError::UnexpectedEof { line, expected } => {
            assert_eq!(line, 14);
            assert!(expected.contains("control point 12 of 13"), "{expected}");
        }
        e => panic!("{e:?}"),
    }
    // A bad number on line 6 (point 4, y).
    let bad = good.replacen("4 1 0.5", "4 1,0 0.5", 1);
    assert!(matches!(
        err(&bad),
        GbpError::BadNumber { line: 6, point: 4, coord: 'y', ref token } if token == "1,0"
    ));
    for nonfinite in ["NaN", "inf", "-infinity", "1e400"] {
        let bad = good.replacen("7 1.75 0.5", &format!("7 1.75 {nonfinite}"), 1);
        assert!(matches!(
            err(&bad),
            GbpError::NonFinite {
                line: 9,
                point: 7,
                coord: 'z',
                ..
            }
        ));
    }
    let trailing = format!("{good}\n\n0.0\n");
    assert!(matches!(
        err(&trailing),
        GbpError::TrailingData { line: 17, points: 13, ref token } if token == "0.0"
    ));
    // Messages name the line.
    assert!(err(&trailing).to_string().starts_with("line 17:"));
    // Non-UTF-8 bytes on line 2.
    let mut bytes = b"3 3\n0 \xff 0\n".to_vec();
    bytes.extend_from_slice(good.as_bytes());
    assert!(matches!(
        read_gbp(&bytes[..]),
        Err(GbpError::NotText { line: 2 })
    ));
    // A directory (like a device or FIFO) is refused, never read without end.
    assert!(matches!(load_gbp(std::env::temp_dir()), Err(GbpError::Input(gbsurf::input::InputError::NotAFile { .. }))));
    assert!(matches!(
        load_gbp("/nonexistent/x.gbp"),
        Err(GbpError::Input(gbsurf::input::InputError::Io { .. }))
    ));
}

#[test]
fn writer_layout_matches_transfinite() {
    let p = load_gbp(format!("{DATA}/cubic5.gbp")).unwrap();
    let s = to_gbp_string(&p).unwrap();
    let lines: Vec<&str> = s.lines().collect();
    assert_eq!(lines[0], "5 3");
    assert_eq!(lines.len(), 2 + 4 * 5);
    assert!(lines[1..].iter().all(|l| l.split(' ').count() == 3));
    // 17 significant digits: 0.6 is written as 5.9999999999999998e-1 (its exact nearest double).
    assert_eq!(
        lines[1],
        "0.0000000000000000e0 0.0000000000000000e0 5.9999999999999998e-1"
    );
    assert_eq!(parse_gbp(&s).unwrap(), p);
}

fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        -10.0..10.0f64,
        (-1e300..1e300f64),
        (-1e-300..1e-300f64),
        Just(0.0),
        Just(-0.0),
        Just(f64::MIN_POSITIVE),
        Just(f64::MAX),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// write → read gives back the same patch, bit for bit.
    #[test]
    fn round_trip_is_exact(n in 3usize..9, d in 2usize..8, seed in proptest::collection::vec(coord(), 3 * 200)) {
        let count = 1 + listed_point_count(n, d);
        prop_assume!(3 * count <= seed.len());
        let pts: Vec<DVec3> = (0..count).map(|m| DVec3::new(seed[3 * m], seed[3 * m + 1], seed[3 * m + 2])).collect();
        let p = GbPatch::from_connected_listing(n, d, &pts).unwrap();
        let s = to_gbp_string(&p).unwrap();
        let q = parse_gbp(&s).unwrap();
        for (a, b) in p.connected_listing().unwrap().iter().zip(q.connected_listing().unwrap()) {
            prop_assert_eq!(a.to_array().map(f64::to_bits), b.to_array().map(f64::to_bits));
        }
        prop_assert_eq!(q, p);
    }

    /// Arbitrary text never panics the reader.
    #[test]
    fn reader_never_panics(text in "[0-9 .eE+\\-\\n\\tnaifNAIF]{0,200}") {
        let _ = parse_gbp(&text);
    }
}
