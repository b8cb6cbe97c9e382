//! The one way the mesh writers produce their bodies: items (vertices, faces, triangles) are
//! encoded into byte buffers in parallel chunks (rayon), a bounded window of chunks at a time,
//! and written in order. Memory stays bounded (a window is a few MB, whatever the mesh size) and
//! the output is identical to a sequential encoding. Also the number formatting shared by the
//! text writers: shortest round-trip decimal floats (`zmij`) and integers (`itoa`).

use rayon::prelude::*;
use std::io::{self, Write};
use std::ops::Range;

/// Items per chunk: large enough that a chunk's work dwarfs the scheduling, small enough that a
/// window of chunks stays a few MB.
const CHUNK_ITEMS: usize = 1 << 14;

/// Writes the encoding of items `0..n` to `w`: `encode(range, buf)` appends the bytes of the items
/// in `range` to `buf`. Chunks run in parallel; at most a window of
/// `4 × rayon::current_num_threads()` chunks is held in memory at once. The first error of
/// `encode` (in item order) stops the writing and is returned.
pub(crate) fn write_chunks<W, F>(w: &mut W, n: usize, encode: F) -> io::Result<()>
where
    W: Write + ?Sized,
    F: Fn(Range<usize>, &mut Vec<u8>) -> io::Result<()> + Sync,
{
    let window = CHUNK_ITEMS * 4 * rayon::current_num_threads().max(1);
    let mut start = 0;
    while start < n {
        let end = n.min(start + window);
        let chunks: Vec<io::Result<Vec<u8>>> = (start..end)
            .step_by(CHUNK_ITEMS)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|a| {
                let mut buf = Vec::new();
                encode(a..end.min(a + CHUNK_ITEMS), &mut buf).map(|()| buf)
            })
            .collect();
        for chunk in chunks {
            w.write_all(&chunk?)?;
        }
        start = end;
    }
    Ok(())
}

/// Appends `x` as the shortest decimal text that parses back to the same `f64` bits (`zmij`,
/// Schubfach: e.g. `1.0`, `0.1`, `1e-20`, `-2.5e300`); NaN and infinities as `NaN`, `inf`,
/// `-inf` (as `std::fmt`).
#[inline]
pub(crate) fn push_f64(buf: &mut Vec<u8>, x: f64) {
    buf.extend_from_slice(zmij::Buffer::new().format(x).as_bytes());
}

/// Appends `x` in decimal.
#[inline]
pub(crate) fn push_int(buf: &mut Vec<u8>, x: impl itoa::Integer) {
    buf.extend_from_slice(itoa::Buffer::new().format(x).as_bytes());
}

/// `x` as `f32` for the float32 fields of a format (PLY `float` properties), never infinite: values
/// beyond the `f32` range are clamped to ±`f32::MAX`; every other value is the nearest `f32`
/// (so an `f64` that is an `f32` is kept exactly); NaN stays NaN.
#[inline]
pub(crate) fn f32_clamped(x: f64) -> f32 {
    x.clamp(-f32::MAX as f64, f32::MAX as f64) as f32
}
