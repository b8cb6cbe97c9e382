//! Discrete curvature of triangle meshes, for the subdivision methods (whose limit surfaces have
//! no evaluator here).
//!
//! Gaussian curvature: angle defect over the barycentric area, K_v = (2π − Σθ)/A_v (π − Σθ at
//! boundary vertices), A_v = ⅓ of the areas of the triangles at v. Mean curvature: the cotangent
//! Laplace–Beltrami operator Δx_v = 1/(2A_v) Σ_u (cot α_vu + cot β_vu)(x_u − x_v) = 2H n, so
//! H = ½ Δx·n with the sign convention of the analytic evaluator (H = (eG − 2fF + gE)/(2(EG − F²))
//! with the outward normal: a sphere of radius R gives H = −1/R, K = 1/R²).

use crate::progress::{Cancelled, Ticker};
use glam::DVec3;

/// (mean, Gaussian) curvature per vertex; `normals` orient H. Unused vertices and vertices with
/// zero area get 0.
pub fn discrete_curvature(positions: &[DVec3], triangles: &[[u32; 3]], normals: &[DVec3]) -> (Vec<f64>, Vec<f64>) {
    discrete_curvature_ticked(positions, triangles, normals, &mut Ticker::none()).unwrap_or_default()
}

/// [`discrete_curvature`] reporting progress to `ticker` (per triangle, then per vertex; see
/// [`crate::progress`]).
pub fn discrete_curvature_ticked(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    normals: &[DVec3],
    ticker: &mut Ticker<'_>,
) -> Result<(Vec<f64>, Vec<f64>), Cancelled> {
    let total = triangles.len() + positions.len();
    let nv = positions.len();
    let mut area = vec![0.0; nv];
    let mut angle = vec![0.0; nv];
    let mut lap = vec![DVec3::ZERO; nv];
    // Boundary detection: an undirected edge used once.
    let mut edge_count: std::collections::HashMap<(u32, u32), u32> = std::collections::HashMap::with_capacity(triangles.len() * 2);
    for (i, t) in triangles.iter().enumerate() {
        ticker.at(i, total)?;
        if t.iter().any(|&i| i as usize >= nv) {
            continue;
        }
        let p = t.map(|i| positions[i as usize]);
        let a = (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0;
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let (u, v) = (p[j] - p[i], p[k] - p[i]);
            let cross = u.cross(v).length();
            let dot = u.dot(v);
            angle[t[i] as usize] += cross.atan2(dot);
            area[t[i] as usize] += a / 3.0;
            if cross > 0.0 {
                let cot = dot / cross;
                let (xj, xk) = (t[j] as usize, t[k] as usize);
                lap[xj] += cot * (p[k] - p[j]);
                lap[xk] += cot * (p[j] - p[k]);
            }
            let (x, y) = (t[i].min(t[j]), t[i].max(t[j]));
            *edge_count.entry((x, y)).or_insert(0) += 1;
        }
    }
    let mut boundary = vec![false; nv];
    for (&(x, y), &c) in &edge_count {
        if c == 1 {
            boundary[x as usize] = true;
            boundary[y as usize] = true;
        }
    }
    let mut h = vec![0.0; nv];
    let mut k = vec![0.0; nv];
    for v in 0..nv {
        ticker.at(triangles.len() + v, total)?;
        if area[v] > 0.0 {
            let full = if boundary[v] { std::f64::consts::PI } else { std::f64::consts::TAU };
            k[v] = (full - angle[v]) / area[v];
            let n = normals.get(v).copied().unwrap_or(DVec3::ZERO);
            h[v] = 0.5 * (lap[v] / (2.0 * area[v])).dot(n);
        }
    }
    Ok((h, k))
}
