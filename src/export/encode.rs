//! The one way the mesh writers produce their bodies: items (vertices, faces, triangles) are
//! encoded into byte buffers in parallel chunks (rayon), a bounded window of chunks at a time,
//! and written in order; the next window is encoded while the calling thread writes the current
//! one. Memory stays bounded (two windows of at most 4 × 8 chunks, whatever the mesh size and the
//! number of cores) and the output is identical to a sequential encoding. Also the number
//! formatting shared by the text writers: shortest round-trip decimal floats (`zmij`) and
//! integers (`itoa`).

use rayon::prelude::*;
use std::io::{self, Write};
use std::ops::Range;

/// Items per chunk: large enough that a chunk's work dwarfs the scheduling, small enough that a
/// window of chunks stays a few MB (16Ki items; at most 4 × [`MAX_WINDOW_THREADS`] chunks per
/// window: 38 MB of binary PLY with every quality scalar, 72 bytes per vertex).
const CHUNK_ITEMS: usize = 1 << 14;

/// The most threads a window is sized for: beyond it more cores no longer enlarge the two
/// windows held at once.
const MAX_WINDOW_THREADS: usize = 8;

/// One window of encoded chunks: the bytes of each chunk and its encoding's result. The buffers
/// are kept from window to window (cleared, not freed), so their pages are touched once rather
/// than once per window (fresh pages cost a page fault and zeroing each: at 640k vertices about
/// 10 % of writing an OBJ).
#[derive(Default)]
struct Window {
    chunks: Vec<(Vec<u8>, io::Result<()>)>,
}

impl Window {
    /// Encodes the items `start..end` in parallel chunks of [`CHUNK_ITEMS`].
    fn encode<F>(&mut self, start: usize, end: usize, encode: &F)
    where
        F: Fn(Range<usize>, &mut Vec<u8>) -> io::Result<()> + Sync,
    {
        let count = (end - start).div_ceil(CHUNK_ITEMS);
        self.chunks.truncate(count);
        self.chunks.resize_with(count, || (Vec::new(), Ok(())));
        self.chunks.par_iter_mut().enumerate().for_each(|(k, (buf, result))| {
            let a = start + k * CHUNK_ITEMS;
            buf.clear();
            *result = encode(a..end.min(a + CHUNK_ITEMS), buf);
        });
    }

    /// Writes the chunks in order up to the first failed encoding, whose error it returns.
    fn write<W: Write + ?Sized>(&mut self, w: &mut W) -> io::Result<()> {
        for (buf, result) in &mut self.chunks {
            std::mem::replace(result, Ok(()))?;
            w.write_all(buf)?;
        }
        Ok(())
    }
}

/// Writes the encoding of items `0..n` to `w`: `encode(range, buf)` appends the bytes of the items
/// in `range` to `buf`. Chunks run in parallel, a window of `4 × rayon::current_num_threads()`
/// chunks (at most 4 × [`MAX_WINDOW_THREADS`]) at a time; while the calling thread writes one
/// window, the pool encodes the next (`rayon::in_place_scope`: `w` stays on the calling thread,
/// so it need not be `Send`), so at most two windows are held in memory at once. The first error in item order, of `encode` or of
/// writing, stops the writing and is returned (a later window may have been encoded in vain).
pub(crate) fn write_chunks<W, F>(w: &mut W, n: usize, encode: F) -> io::Result<()>
where
    W: Write + ?Sized,
    F: Fn(Range<usize>, &mut Vec<u8>) -> io::Result<()> + Sync,
{
    let window = CHUNK_ITEMS * 4 * rayon::current_num_threads().clamp(1, MAX_WINDOW_THREADS);
    let (mut ready, mut next) = (Window::default(), Window::default());
    ready.encode(0, n.min(window), &encode);
    let mut start = 0;
    while start < n {
        let following = start + window;
        let written = if following < n {
            let encode = &encode;
            let next = &mut next;
            rayon::in_place_scope(|s| {
                s.spawn(move |_| next.encode(following, n.min(following + window), encode));
                ready.write(w)
            })
        } else {
            ready.write(w)
        };
        written?;
        std::mem::swap(&mut ready, &mut next);
        start = following;
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
