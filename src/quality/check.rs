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
    // Per vertex (in parallel): its edges and its fan, from its own corner list only. A corner
    // (u; a, b) of triangle (u, a, b) carries the directed edges u → a and b → u, and every
    // directed edge x → y of a triangle appears exactly once as an outgoing edge (at x's corner)
    // and once as an incoming edge (at y's corner), so the counts of u → w and w → u are both
    // read from u's list.
    // Tally: [inconsistent, undirected, boundary, non-manifold edges, non-manifold vertices, used].
    let tally = (0..nv)
        .into_par_iter()
        .with_min_len(1024)
        .map(|u| {
            let mut t = [0usize; 6];
            let list = corners(u);
            let m = list.len();
            let uu = u as u32;
            for (idx, &(a, b)) in list.iter().enumerate() {
                // Neighbour a (first seen here unless an earlier corner named it).
                if !list[..idx].iter().any(|&(x, y)| x == a || y == a) {
                    let forward = list.iter().filter(|&&(x, _)| x == a).count();
                    let backward = list.iter().filter(|&&(_, y)| y == a).count();
                    if forward > 1 {
                        t[0] += 1;
                    }
                    if uu < a {
                        t[1] += 1;
                        match forward + backward {
                            1 => t[2] += 1,
                            2 => {}
                            _ => t[3] += 1,
                        }
                    }
                }
                // Neighbour b.
                if b != a && !list[..idx].iter().any(|&(x, y)| x == b || y == b) {
                    let forward = list.iter().filter(|&&(x, _)| x == b).count();
                    let backward = list.iter().filter(|&&(_, y)| y == b).count();
                    if forward > 1 {
                        t[0] += 1;
                    }
                    if uu < b {
                        t[1] += 1;
                        match forward + backward {
                            1 => t[2] += 1,
                            2 => {}
                            _ => t[3] += 1,
                        }
                    }
                }
            }
            // The link edges a → b around u must form one path or one cycle.
            if m == 0 {
                t[4] += 1; // unused vertex
                return t;
            }
            t[5] += 1;
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
            while let Some(next) = list.iter().position(|x| x.0 == list[cur].1) {
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
    // First a sort of 64-bit hashes of the keys: without two equal hashes there is no duplicate;
    // otherwise the exact count by sorting the full keys.
    let key = |p: &DVec3| [p.x, p.y, p.z].map(|x| (x + 0.0).to_bits());
    let mut hashes: Vec<u64> = positions.par_iter().map(|p| hash_key(key(p))).collect();
    hashes.par_sort_unstable();
    if hashes.windows(2).any(|w| w[0] == w[1]) {
        let mut keys: Vec<[u64; 3]> = positions.par_iter().map(key).collect();
        keys.par_sort_unstable();
        c.duplicate_vertices = keys.windows(2).filter(|w| w[0] == w[1]).count();
    }
    c.euler_characteristic = used as i64 - undirected as i64 + (triangles.len() - c.bad_indices) as i64;
    c
}

/// A 64-bit mix of three words (multiply–xorshift rounds, as in splitmix64).
fn hash_key(k: [u64; 3]) -> u64 {
    let mix = |mut z: u64| {
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    mix(mix(mix(k[0]).wrapping_add(k[1])).wrapping_add(k[2]))
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::collections::{HashMap, HashSet};

    /// Edge counts by hashing directed edges (independent of the corner lists).
    fn reference_edges(nv: usize, triangles: &[[u32; 3]]) -> (usize, usize, usize, usize) {
        let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
        for t in triangles.iter().filter(|t| t.iter().all(|&i| (i as usize) < nv)) {
            for k in 0..3 {
                *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        let inconsistent = directed.values().filter(|&&c| c > 1).count();
        let undirected: HashSet<(u32, u32)> = directed.keys().filter(|(a, b)| a != b).map(|&(a, b)| (a.min(b), a.max(b))).collect();
        let (mut boundary, mut nm) = (0, 0);
        for &(a, b) in &undirected {
            let n = directed.get(&(a, b)).copied().unwrap_or(0) + directed.get(&(b, a)).copied().unwrap_or(0);
            match n {
                1 => boundary += 1,
                2 => {}
                _ => nm += 1,
            }
        }
        (inconsistent, undirected.len(), boundary, nm)
    }

    #[test]
    fn closed_tetrahedron_and_open_fan() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let tet = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        let c = check_mesh(&p, &tet);
        assert!(c.is_clean_closed(), "{c:?}");
        assert_eq!(c.euler_characteristic, 2);
        let c = check_mesh(&p, &tet[..3]);
        assert_eq!(c.boundary_edges, 3);
        assert!(c.is_two_manifold() && !c.is_closed_manifold());
        // Flipping one face makes three edges inconsistent.
        let c = check_mesh(&p, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 2, 3]]);
        assert_eq!(c.inconsistent_edges, 3);
        // A duplicated position.
        let c = check_mesh(&[DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::X], &[[0, 1, 2]]);
        assert_eq!(c.duplicate_vertices, 1);
    }

    proptest! {
        #[test]
        fn edge_counts_match_a_hash_reference(
            tris in proptest::collection::vec(proptest::array::uniform3(0u32..9), 0..24),
            pts in proptest::collection::vec(0u8..4, 8),
        ) {
            let nv = 8;
            let positions: Vec<DVec3> = pts.iter().enumerate().map(|(i, &k)| DVec3::new(k as f64, (i % 2) as f64, 0.0)).collect();
            let c = check_mesh(&positions, &tris);
            let (inconsistent, undirected, boundary, nm) = reference_edges(nv, &tris);
            prop_assert_eq!(c.inconsistent_edges, inconsistent);
            prop_assert_eq!(c.boundary_edges, boundary);
            prop_assert_eq!(c.non_manifold_edges, nm);
            let good: Vec<&[u32; 3]> = tris.iter().filter(|t| t.iter().all(|&i| (i as usize) < nv)).collect();
            let used: HashSet<u32> = good.iter().flat_map(|t| t.iter().copied()).collect();
            prop_assert_eq!(c.bad_indices, tris.len() - good.len());
            prop_assert_eq!(c.euler_characteristic, used.len() as i64 - undirected as i64 + good.len() as i64);
            let distinct: HashSet<[u64; 3]> = positions.iter().map(|p| p.to_array().map(f64::to_bits)).collect();
            prop_assert_eq!(c.duplicate_vertices, nv - distinct.len());
        }
    }
}
