//! Binary STL.

use super::encode::write_chunks;
use glam::DVec3;
use std::io::{self, Write};

/// A coordinate that a float32 format cannot hold: `|value|` is beyond `f32::MAX`, so it would be
/// written as `inf`. Names the vertex (0-based, in the mesh being written) and the format.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("vertex {vertex}: coordinate {value:e} is beyond the float32 range of {format} (|x| <= {max:e})", max = f32::MAX)]
pub struct Float32RangeError {
    pub vertex: usize,
    pub value: f64,
    pub format: &'static str,
}

/// The first vertex with a finite coordinate beyond the `f32` range, as an `InvalidInput` error
/// carrying a [`Float32RangeError`] (retrieve it with `io::Error::get_ref` and `downcast_ref`).
pub(crate) fn check_f32_range(positions: &[DVec3], format: &'static str) -> io::Result<()> {
    let bad = positions.iter().enumerate().find_map(|(vertex, p)| {
        p.to_array().into_iter().find(|c| c.abs() > f32::MAX as f64).map(|value| Float32RangeError { vertex, value, format })
    });
    match bad {
        Some(e) => Err(io::Error::new(io::ErrorKind::InvalidInput, e)),
        None => Ok(()),
    }
}

/// Writes binary STL triangles (80-byte header, count, per triangle unit normal + 3 corners as
/// `f32`, zero attribute). The facet normal is that of the triangle (zero if degenerate).
/// A position beyond the `f32` range is refused ([`Float32RangeError`], naming the vertex) rather
/// than written as `inf`. The body is encoded in parallel chunks (bounded memory).
pub fn write_stl_triangles<W: Write>(mut w: W, positions: &[DVec3], tris: &[[u32; 3]]) -> io::Result<()> {
    let n = u32::try_from(tris.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "too many triangles for STL"))?;
    if let Some(t) = tris.iter().find(|t| t.iter().any(|&i| i as usize >= positions.len())) {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("triangle {t:?} names a missing vertex")));
    }
    check_f32_range(positions, "STL")?;
    let mut header = [0u8; 80];
    let tag = b"binary STL written by gbsurf";
    header[..tag.len()].copy_from_slice(tag);
    w.write_all(&header)?;
    w.write_all(&n.to_le_bytes())?;
    write_chunks(&mut w, tris.len(), |r, buf| {
        buf.reserve(r.len() * 50);
        for t in &tris[r] {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let nrm = (b - a).cross(c - a).normalize_or_zero();
            for v in [nrm, a, b, c] {
                for x in v.to_array() {
                    buf.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
            buf.extend_from_slice(&[0, 0]);
        }
        Ok(())
    })?;
    w.flush()
}
