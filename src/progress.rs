//! Progress reports and cancellation for every layer below the api: one [`Ticker`] wraps the
//! caller's callback (`FnMut(f32) -> bool`: the overall fraction done in [0, 1]; returning false
//! cancels) and is passed as `&mut Ticker` down the pipeline.
//!
//! - The api splits [0, 1] into stages ([`Ticker::stage`], weights measured, see the api module
//!   doc); a function with several internal phases narrows its range further with
//!   [`Ticker::within`] (nestable).
//! - Loops call [`Ticker::at`]`(done, total)` per item or per chunk of items. It is cheap (a
//!   multiply and a compare; the clock is read only every [`CLOCK_EVERY`] calls) and calls the
//!   callback when the overall fraction advanced by [`STEP`] since the last report or
//!   [`INTERVAL`] passed, so a fast loop does not flood the host (Blender redraws on each call).
//! - Parallel (rayon) loops never call the callback from a worker: they run in chunks of items
//!   and tick between chunks on the calling thread, so the callback stays a plain `&mut FnMut`
//!   and a cancel takes effect after the running chunk.
//! - Once the callback returned false every further call returns [`Cancelled`] at once without
//!   calling it again; each layer's error type has a `Cancelled` case that the api maps to
//!   `ConvertError::Cancelled`.
//!
//! Reported fractions never decrease.

use std::time::{Duration, Instant};

/// The smallest advance of the overall fraction that is reported without waiting for
/// [`INTERVAL`].
pub const STEP: f32 = 0.01;
/// The longest time between two reports while [`Ticker::at`] is being called.
pub const INTERVAL: Duration = Duration::from_millis(100);
/// [`Ticker::at`] reads the clock once per this many calls.
pub const CLOCK_EVERY: u32 = 16;

/// Least number of ticks of a chunked loop ([`chunk_size`]), so small inputs tick finely too.
pub const TICKS_PER_LOOP: usize = 64;

/// The chunk size of a chunked parallel loop over `n` items: at most `max` (the size that
/// keeps a chunk short on large inputs) and small enough for [`TICKS_PER_LOOP`] chunks.
pub fn chunk_size(n: usize, max: usize) -> usize {
    max.min(n.div_ceil(TICKS_PER_LOOP)).max(1)
}

/// The progress callback asked to stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

/// The progress state of one conversion (see the module doc).
pub struct Ticker<'a> {
    callback: Option<&'a mut dyn FnMut(f32) -> bool>,
    /// The current range (stage or part of one), in overall fractions.
    range: (f32, f32),
    /// The last fraction reported.
    last: f32,
    last_time: Instant,
    calls: u32,
    cancelled: bool,
}

impl std::fmt::Debug for Ticker<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ticker").field("range", &self.range).field("last", &self.last).field("cancelled", &self.cancelled).finish()
    }
}

impl<'a> Ticker<'a> {
    /// A ticker over the whole range [0, 1] calling `callback` (none: nothing is reported and
    /// nothing cancels).
    pub fn new(callback: Option<&'a mut dyn FnMut(f32) -> bool>) -> Self {
        Ticker { callback, range: (0.0, 1.0), last: 0.0, last_time: Instant::now(), calls: 0, cancelled: false }
    }

    /// A ticker without callback.
    pub fn none() -> Ticker<'static> {
        Ticker::new(None)
    }

    /// True when a callback is attached.
    pub fn is_active(&self) -> bool {
        self.callback.is_some()
    }

    /// Sets the current range to [`lo`, `hi`] of the overall range (a stage of the api) and
    /// reports `lo`.
    pub fn stage(&mut self, lo: f32, hi: f32) -> Result<(), Cancelled> {
        self.range = (lo, hi.max(lo));
        self.report(lo)
    }

    /// Runs `f` with the current range narrowed to its part [`a`, `b`] (fractions of the
    /// range), reporting the part's start first; the range is restored afterwards.
    pub fn within<R, E: From<Cancelled>>(&mut self, a: f32, b: f32, f: impl FnOnce(&mut Self) -> Result<R, E>) -> Result<R, E> {
        let outer = self.range;
        let at = |t: f32| outer.0 + (outer.1 - outer.0) * t.clamp(0.0, 1.0);
        self.range = (at(a), at(b.max(a)));
        self.report(self.range.0)?;
        let r = f(self);
        self.range = outer;
        r
    }

    /// `done` of `total` items of the current range are finished: reports when due (see the
    /// module doc).
    #[inline]
    pub fn at(&mut self, done: usize, total: usize) -> Result<(), Cancelled> {
        self.at_part(0.0, 1.0, done, total)
    }

    /// `done` of `total` items of the part [`a`, `b`] (fractions) of the current range are
    /// finished: [`Ticker::at`] for a loop that is one phase of a range.
    #[inline]
    pub fn at_part(&mut self, a: f32, b: f32, done: usize, total: usize) -> Result<(), Cancelled> {
        if self.cancelled {
            return Err(Cancelled);
        }
        if self.callback.is_none() {
            return Ok(());
        }
        let t = if total == 0 { 1.0 } else { (done as f64 / total as f64).min(1.0) as f32 };
        let f = self.range.0 + (self.range.1 - self.range.0) * (a + (b - a) * t);
        if f >= self.last + STEP {
            return self.report(f);
        }
        self.calls = self.calls.wrapping_add(1);
        if self.calls % CLOCK_EVERY == 0 && self.last_time.elapsed() >= INTERVAL {
            return self.report(f);
        }
        Ok(())
    }

    /// Reports the overall fraction `f` now (clamped to [0, 1], never below the last report).
    pub fn report(&mut self, f: f32) -> Result<(), Cancelled> {
        if self.cancelled {
            return Err(Cancelled);
        }
        let Some(cb) = self.callback.as_mut() else { return Ok(()) };
        let f = f.clamp(0.0, 1.0).max(self.last);
        self.last = f;
        self.last_time = Instant::now();
        if cb(f) {
            Ok(())
        } else {
            self.cancelled = true;
            Err(Cancelled)
        }
    }
}

/// Maps `f` over `0..n` in parallel (rayon), in chunks of at most `chunk` indices ([`chunk_size`]), ticking `ticker`
/// between chunks on the calling thread; the results in index order.
pub fn par_map<R: Send>(ticker: &mut Ticker<'_>, n: usize, chunk: usize, f: impl Fn(usize) -> R + Sync) -> Result<Vec<R>, Cancelled> {
    use rayon::prelude::*;
    let chunk = chunk_size(n, chunk);
    let mut out = Vec::with_capacity(n);
    let mut start = 0;
    while start < n {
        let end = (start + chunk).min(n);
        out.par_extend((start..end).into_par_iter().map(&f));
        start = end;
        ticker.at(end, n)?;
    }
    Ok(out)
}
