//! Topology and sanity checks of a triangle mesh (positions + CCW triangles), linear time.

use glam::DVec3;
use rayon::prelude::*;

/// Result of [`check_mesh`].
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MeshCheck {
    /// Vertices and triangles counted.
    pub vertices: usize,
    pub triangles: usize,
    /// Edges used by exactly one triangle.
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Vertices whose triangles do not form a single fan (a disk or a half-disk), or that are
    /// used by no triangle.
    pub non_manifold_vertices: usize,
    /// Directed edges used twice (two neighbouring triangles with opposite orientation).
    pub inconsistent_edges: usize,
    /// Pairs of vertices at exactly the same position (each extra copy counted once).
    pub duplicate_vertices: usize,
    /// Triangles with a repeated index or with area ≤ 1e-14·(longest edge)² (relative test).
    pub zero_area_triangles: usize,
    /// Triangles naming a vertex that does not exist.
    pub bad_indices: usize,
    /// Euler characteristic V − E + F (over used vertices).
    pub euler_characteristic: i64,
}

impl MeshCheck {
    /// Two-manifold (with or without boundary) and consistently oriented, no bad indices.
    pub fn is_two_manifold(&self) -> bool {
        self.non_manifold_edges == 0 && self.non_manifold_vertices == 0 && self.inconsistent_edges == 0 && self.bad_indices == 0
    }
    /// A closed, consistently oriented two-manifold.
    pub fn is_closed_manifold(&self) -> bool {
        self.is_two_manifold() && self.boundary_edges == 0
    }
    /// Closed two-manifold with no duplicate vertices and no zero-area triangles.
    pub fn is_clean_closed(&self) -> bool {
        self.is_closed_manifold() && self.duplicate_vertices == 0 && self.zero_area_triangles == 0
    }
}

/// Relative area threshold of [`MeshCheck::zero_area_triangles`].
pub const ZERO_AREA_REL: f64 = 1e-14;

/// Checks a triangle mesh; see [`MeshCheck`]. Linear time without hashing: the triangles'
/// corners are bucketed per vertex (compressed rows), edges and vertex fans are checked on those
/// short lists; duplicate positions by a parallel sort.
pub fn check_mesh(positions: &[DVec3], triangles: &[[u32; 3]]) -> MeshCheck {
    let nv = positions.len();
    let mut c = MeshCheck { vertices: nv, triangles: triangles.len(), ..Default::default() };
    let good: Vec<bool> = triangles.iter().map(|t| t.iter().all(|&i| (i as usize) < nv)).collect();
    c.bad_indices = good.iter().filter(|&&g| !g).count();
    c.zero_area_triangles = triangles
        .par_iter()
        .zip(&good)
        .filter(|(t, &g)| {
            if !g {
                return false;
            }
            let [a, b, cc] = t.map(|i| positions[i as usize]);
            let longest = (b - a).length_squared().max((cc - b).length_squared()).max((a - cc).length_squared());
            let area2 = (b - a).cross(cc - a).length();
            t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(area2 > 2.0 * ZERO_AREA_REL * longest)
        })
        .count();
    // Corners per vertex: corner (v; a, b) for triangle (v, a, b) in CCW order. Its outgoing
    // directed edge is v → a and its link edge a → b.
    let mut start = vec![0u32; nv + 1];
    for (t, &g) in triangles.iter().zip(&good) {
        if g {
            for &v in t {
                start[v as usize + 1] += 1;
            }
        }
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut links = vec![(0u32, 0u32); start[nv] as usize];
    for (t, &g) in triangles.iter().zip(&good) {
        if g {
            for k in 0..3 {
                let v = t[k] as usize;
                links[fill[v] as usize] = (t[(k + 1) % 3], t[(k + 2) % 3]);
                fill[v] += 1;
            }
        }
    }
    let corners = |v: usize| &links[start[v] as usize..start[v + 1] as usize];
    // Directed edge u → w exists (count) iff some corner of u has first link vertex w.
    let count_out = |u: usize, w: u32| corners(u).iter().filter(|&&(a, _)| a == w).count();
    // Per vertex (in parallel): its outgoing edges and its fan.
    // Tally: [inconsistent, undirected, boundary, non-manifold edges, non-manifold vertices, used].
    let tally = (0..nv)
        .into_par_iter()
        .map(|u| {
            let mut t = [0usize; 6];
            let list = corners(u);
            for (idx, &(w, _)) in list.iter().enumerate() {
                if list[..idx].iter().any(|&(a, _)| a == w) {
                    continue; // counted at its first occurrence
                }
                let forward = count_out(u, w);
                let backward = count_out(w as usize, u as u32);
                if forward > 1 {
                    t[0] += 1;
                }
                // Each undirected edge once: from its smaller end, or from the only direction used.
                if (u as u32) < w || backward == 0 {
                    t[1] += 1;
                    match forward + backward {
                        1 => t[2] += 1,
                        2 => {}
                        _ => t[3] += 1,
                    }
                }
            }
            // The link edges a → b around u must form one path or one cycle.
            if list.is_empty() {
                t[4] += 1; // unused vertex
                return t;
            }
            t[5] += 1;
            let m = list.len();
            let unique_from = (0..m).all(|i| !list[..i].iter().any(|x| x.0 == list[i].0));
            let unique_to = (0..m).all(|i| !list[..i].iter().any(|x| x.1 == list[i].1));
            if !(unique_from && unique_to) {
                t[4] += 1;
                return t;
            }
            // Start where no link edge leads in (boundary fan), else anywhere (closed fan).
            let first = (0..m).find(|&i| !list.iter().any(|x| x.1 == list[i].0)).unwrap_or(0);
            let mut cur = first;
            let mut steps = 1;
            while let Some(next) = (0..m).find(|&j| list[j].0 == list[cur].1) {
                if next == first || steps > m {
                    break;
                }
                cur = next;
                steps += 1;
            }
            if steps != m {
                t[4] += 1;
            }
            t
        })
        .reduce(|| [0usize; 6], |a, b| std::array::from_fn(|i| a[i] + b[i]));
    let [inconsistent, undirected, boundary, nm_edges, nm_vertices, used] = tally;
    c.inconsistent_edges = inconsistent;
    c.boundary_edges = boundary;
    c.non_manifold_edges = nm_edges;
    c.non_manifold_vertices = nm_vertices;
    // Duplicate positions (bitwise equal coordinates, −0 = +0).
    let mut keys: Vec<[u64; 3]> = positions.par_iter().map(|p| [p.x, p.y, p.z].map(|x| (x + 0.0).to_bits())).collect();
    keys.par_sort_unstable();
    c.duplicate_vertices = keys.windows(2).filter(|w| w[0] == w[1]).count();
    c.euler_characteristic = used as i64 - undirected as i64 + (triangles.len() - c.bad_indices) as i64;
    c
}

/// Area-weighted vertex normals of a triangle mesh (unit, zero for unused vertices).
pub fn vertex_normals(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<DVec3> {
    let mut n = vec![DVec3::ZERO; positions.len()];
    for t in triangles {
        if t.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let f = (b - a).cross(c - a);
        for &i in t {
            n[i as usize] += f;
        }
    }
    n.iter().map(|v| v.normalize_or_zero()).collect()
}
