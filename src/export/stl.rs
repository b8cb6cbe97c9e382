//! Binary STL.

use glam::DVec3;
use std::io::{self, Write};

/// Writes binary STL triangles (80-byte header, count, per triangle unit normal + 3 corners as
/// `f32`, zero attribute). The facet normal is that of the triangle (zero if degenerate).
pub fn write_stl_triangles<W: Write>(mut w: W, positions: &[DVec3], tris: &[[u32; 3]]) -> io::Result<()> {
    let mut header = [0u8; 80];
    let tag = b"binary STL written by gbsurf";
    header[..tag.len()].copy_from_slice(tag);
    w.write_all(&header)?;
    let n = u32::try_from(tris.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "too many triangles for STL"))?;
    if let Some(t) = tris.iter().find(|t| t.iter().any(|&i| i as usize >= positions.len())) {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, format!("triangle {t:?} names a missing vertex")));
    }
    w.write_all(&n.to_le_bytes())?;
    for t in tris {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let nrm = (b - a).cross(c - a).normalize_or_zero();
        for v in [nrm, a, b, c] {
            for x in v.to_array() {
                w.write_all(&(x as f32).to_le_bytes())?;
            }
        }
        w.write_all(&[0, 0])?;
    }
    w.flush()
}
