//! The `.gbp` text format of the public `transfinite` library (its `loadBezier`/`saveBezier`):
//!
//! ```text
//! n d
//! cx cy cz                      central control point
//! x y z                         row k = 0..l−1; within a row sides i = 0..n−1;
//! …                             within a side columns j = k..d−k−1
//! ```
//!
//! l = ⌈d/2⌉; the file holds 1 + n·l·(⌊d/2⌋+1) points (4n + 1 for cubic patches); the other
//! ribbon points follow from the connected-net sharing rule ([`super::connected`]).
//! Like that reader (C++ `operator>>`), numbers are separated by any whitespace, so a point may
//! be split over lines; the writer puts one point per line, with 17 significant digits.

use super::connected::listed_point_count;
use super::error::GbError;
use super::weights::layers_for_degree as layers;
use super::patch::GbPatch;
use glam::DVec3;
use std::io::{Read, Write};
use std::path::Path;

use crate::limits::{MAX_GBP_DEGREE, MAX_GBP_SIDES};

/// Errors reading or writing `.gbp`. Lines are 1-based.
#[derive(Debug, thiserror::Error)]
pub enum GbpError {
    /// The underlying reader or writer failed.
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
    /// The input file is not a regular file, too large or unreadable.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// The file is not UTF-8 text.
    #[error("line {line}: not valid UTF-8 text")]
    NotText { line: usize },
    /// The file ended before all expected numbers were read.
    #[error("line {line}: unexpected end of file, expected {expected}")]
    UnexpectedEof { line: usize, expected: String },
    /// A header entry that is not a non-negative integer.
    #[error("line {line}: expected {what} as a non-negative integer, found `{token}`")]
    BadInteger {
        line: usize,
        what: &'static str,
        token: String,
    },
    /// Fewer than 3 sides.
    #[error("line {line}: a GB patch needs at least 3 sides, got n = {n}")]
    TooFewSides { line: usize, n: usize },
    /// More than [`MAX_GBP_SIDES`] sides.
    #[error("line {line}: n = {n} sides is more than the supported {MAX_GBP_SIDES}")]
    TooManySides { line: usize, n: usize },
    /// Degree below 2 or above [`MAX_GBP_DEGREE`]. (`transfinite` reads d = 1 files, but a GB patch
    /// needs d ≥ 2 for its correction weights μ; gbsurf does not evaluate such a patch, so it
    /// rejects the file instead of returning a patch that cannot be evaluated.)
    #[error("line {line}: degree d = {d} is outside the supported range 2..={MAX_GBP_DEGREE}")]
    BadDegree { line: usize, d: usize },
    /// A coordinate that is not a number.
    #[error("line {line}: coordinate {coord} of control point {point}: `{token}` is not a number")]
    BadNumber {
        line: usize,
        point: usize,
        coord: char,
        token: String,
    },
    /// A coordinate that is NaN or infinite.
    #[error("line {line}: coordinate {coord} of control point {point} is not finite (`{token}`)")]
    NonFinite {
        line: usize,
        point: usize,
        coord: char,
        token: String,
    },
    /// Data after the last control point.
    #[error("line {line}: unexpected data `{token}` after the last of {points} control points")]
    TrailingData {
        line: usize,
        token: String,
        points: usize,
    },
    /// The patch to write has a malformed shape.
    #[error("cannot write .gbp: {0}")]
    Shape(#[from] GbError),
    /// The patch to write is not a connected net, so `.gbp` cannot represent it.
    #[error(
        "cannot write .gbp: the patch is not a connected net (side {side}, column {column}, \
         row {row} is {distance:e} away from the point it must share)"
    )]
    NotConnected {
        side: usize,
        column: usize,
        row: usize,
        distance: f64,
    },
    /// The patch to write has a degree outside 2..=[`MAX_GBP_DEGREE`], which the reader rejects.
    #[error("cannot write .gbp: degree d = {d} is outside the supported range 2..={MAX_GBP_DEGREE}")]
    DegreeOutput { d: usize },
    /// A coordinate to write is NaN or infinite.
    #[error("cannot write .gbp: control point {point} has a non-finite coordinate")]
    NonFiniteOutput { point: usize },
}

/// Whitespace-separated tokens with their 1-based line numbers.
struct Tokens<'a> {
    rest: &'a str,
    line: usize,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str) -> Self {
        Tokens {
            rest: text,
            line: 1,
        }
    }

    /// The next token and its line, or None at the end (then `self.line` is the line of the
    /// last token).
    fn next_token(&mut self) -> Option<(&'a str, usize)> {
        let trimmed = self.rest.trim_start();
        if trimmed.is_empty() {
            // Keep `line` at the last token's line: that is where the data stops.
            self.rest = trimmed;
            return None;
        }
        let skipped = &self.rest[..self.rest.len() - trimmed.len()];
        self.line += skipped.bytes().filter(|&b| b == b'\n').count();
        let end = trimmed.find(char::is_whitespace).unwrap_or(trimmed.len());
        let (tok, rest) = trimmed.split_at(end);
        self.rest = rest;
        Some((tok, self.line))
    }
}

fn read_header_int(toks: &mut Tokens, what: &'static str) -> Result<(usize, usize), GbpError> {
    let (tok, line) = toks.next_token().ok_or_else(|| GbpError::UnexpectedEof {
        line: toks.line,
        expected: format!("{what} in the header `n d`"),
    })?;
    let v = tok.parse::<usize>().map_err(|_| GbpError::BadInteger {
        line,
        what,
        token: tok.to_string(),
    })?;
    Ok((v, line))
}

/// Parses `.gbp` text into a connected GB patch (see the module doc for the format).
pub fn parse_gbp(text: &str) -> Result<GbPatch, GbpError> {
    let mut toks = Tokens::new(text);
    let (n, n_line) = read_header_int(&mut toks, "the number of sides n")?;
    let (d, d_line) = read_header_int(&mut toks, "the degree d")?;
    if n < 3 {
        return Err(GbpError::TooFewSides { line: n_line, n });
    }
    if n > MAX_GBP_SIDES {
        return Err(GbpError::TooManySides { line: n_line, n });
    }
    if !(2..=MAX_GBP_DEGREE).contains(&d) {
        return Err(GbpError::BadDegree { line: d_line, d });
    }
    let count = 1 + listed_point_count(n, d);
    let mut points = Vec::with_capacity(count);
    for point in 0..count {
        let mut xyz = [0.0; 3];
        for (c, slot) in xyz.iter_mut().enumerate() {
            let coord = ['x', 'y', 'z'][c];
            let (tok, line) = toks.next_token().ok_or_else(|| GbpError::UnexpectedEof {
                line: toks.line,
                expected: format!(
                    "coordinate {coord} of control point {point} of {count} (n = {n}, d = {d}, \
                     l = {})",
                    layers(d)
                ),
            })?;
            let v = tok.parse::<f64>().map_err(|_| GbpError::BadNumber {
                line,
                point,
                coord,
                token: tok.to_string(),
            })?;
            if !v.is_finite() {
                return Err(GbpError::NonFinite {
                    line,
                    point,
                    coord,
                    token: tok.to_string(),
                });
            }
            *slot = v;
        }
        points.push(DVec3::from_array(xyz));
    }
    if let Some((tok, line)) = toks.next_token() {
        return Err(GbpError::TrailingData {
            line,
            token: tok.to_string(),
            points: count,
        });
    }
    Ok(GbPatch::from_connected_listing(n, d, &points)?)
}

/// Reads a `.gbp` patch from a reader (the whole input is read first).
pub fn read_gbp<R: Read>(mut reader: R) -> Result<GbPatch, GbpError> {
    let mut bytes = Vec::new();
    reader.read_to_end(&mut bytes)?;
    let text = match std::str::from_utf8(&bytes) {
        Ok(t) => t,
        Err(e) => {
            let line = 1 + bytes[..e.valid_up_to()]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            return Err(GbpError::NotText { line });
        }
    };
    parse_gbp(text)
}

/// Reads a `.gbp` file: a regular file of at most [`crate::limits::MAX_INPUT_BYTES`]
/// ([`crate::input::read_input`]; a device or FIFO is refused, not read without end).
pub fn load_gbp(path: impl AsRef<Path>) -> Result<GbPatch, GbpError> {
    read_gbp(&crate::input::read_input(path)?[..])
}

/// Writes a connected patch as `.gbp`, one point per line, 17 significant digits (exact
/// round trip). Fails if the patch is malformed, has a degree the reader rejects, has a non-finite coordinate, or is not a
/// connected net within 1e-12 relative to its size (such a patch has no `.gbp` form).
pub fn write_gbp<W: Write>(patch: &GbPatch, mut w: W) -> Result<(), GbpError> {
    let listing = patch.connected_listing()?;
    let degree = patch.ribbons[0].degree;
    if !(2..=MAX_GBP_DEGREE).contains(&degree) {
        return Err(GbpError::DegreeOutput { d: degree });
    }
    if let Some(point) = listing.iter().position(|p| !p.is_finite()) {
        return Err(GbpError::NonFiniteOutput { point });
    }
    let scale = listing
        .iter()
        .fold(1.0f64, |m, p| m.max(p.abs().max_element()));
    let (defect, at) = patch.connection_defect()?;
    if defect > crate::tol::EPS * scale {
        let (side, column, row) = at.unwrap_or((0, 0, 0));
        return Err(GbpError::NotConnected {
            side,
            column,
            row,
            distance: defect,
        });
    }
    writeln!(w, "{} {}", patch.n(), degree)?;
    for p in &listing {
        writeln!(w, "{:.16e} {:.16e} {:.16e}", p.x, p.y, p.z)?;
    }
    w.flush()?;
    Ok(())
}

/// Writes a connected patch to a `.gbp` string (see [`write_gbp`]).
pub fn to_gbp_string(patch: &GbPatch) -> Result<String, GbpError> {
    let mut buf = Vec::new();
    write_gbp(patch, &mut buf)?;
    // The writer emits ASCII only.
    Ok(String::from_utf8_lossy(&buf).into_owned())
}
