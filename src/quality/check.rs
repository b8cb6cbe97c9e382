//! Topology and sanity checks of a triangle mesh (positions + CCW triangles), linear time.

use glam::DVec3;
use std::collections::HashMap;

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

/// Checks a triangle mesh; see [`MeshCheck`].
pub fn check_mesh(positions: &[DVec3], triangles: &[[u32; 3]]) -> MeshCheck {
    let nv = positions.len();
    let mut c = MeshCheck { vertices: nv, triangles: triangles.len(), ..Default::default() };
    // Directed edge → count; undirected edge → count.
    let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(triangles.len() * 3);
    let mut undirected: HashMap<(u32, u32), u32> = HashMap::with_capacity(triangles.len() * 2);
    let mut used = vec![false; nv];
    for t in triangles {
        if t.iter().any(|&i| i as usize >= nv) {
            c.bad_indices += 1;
            continue;
        }
        let [a, b, cc] = t.map(|i| positions[i as usize]);
        let longest = (b - a).length_squared().max((cc - b).length_squared()).max((a - cc).length_squared());
        let area2 = (b - a).cross(cc - a).length();
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(area2 > 2.0 * ZERO_AREA_REL * longest) {
            c.zero_area_triangles += 1;
        }
        for k in 0..3 {
            let (u, v) = (t[k], t[(k + 1) % 3]);
            used[u as usize] = true;
            *directed.entry((u, v)).or_insert(0) += 1;
            *undirected.entry((u.min(v), u.max(v))).or_insert(0) += 1;
        }
    }
    c.inconsistent_edges = directed.values().filter(|&&k| k > 1).count();
    for &k in undirected.values() {
        match k {
            1 => c.boundary_edges += 1,
            2 => {}
            _ => c.non_manifold_edges += 1,
        }
    }
    // Vertex fans: around vertex v, each triangle (v, a, b) links a → b. A manifold vertex's links
    // form one path (boundary) or one cycle (interior). Count components by union–find on the
    // link vertices.
    let mut links: Vec<Vec<(u32, u32)>> = vec![Vec::new(); nv];
    for t in triangles {
        if t.iter().any(|&i| i as usize >= nv) {
            continue;
        }
        for k in 0..3 {
            links[t[k] as usize].push((t[(k + 1) % 3], t[(k + 2) % 3]));
        }
    }
    for (v, l) in links.iter().enumerate() {
        if l.is_empty() {
            if nv > 0 && !used[v] {
                c.non_manifold_vertices += 1;
            }
            continue;
        }
        let mut nodes: Vec<u32> = l.iter().flat_map(|&(a, b)| [a, b]).collect();
        nodes.sort_unstable();
        nodes.dedup();
        let idx = |x: u32| nodes.binary_search(&x).unwrap();
        let mut parent: Vec<usize> = (0..nodes.len()).collect();
        fn root(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        let mut comps = nodes.len();
        for &(a, b) in l {
            let (ra, rb) = (root(&mut parent, idx(a)), root(&mut parent, idx(b)));
            if ra != rb {
                parent[ra] = rb;
                comps -= 1;
            }
        }
        if comps != 1 {
            c.non_manifold_vertices += 1;
        }
    }
    // Duplicate positions (bitwise equal coordinates, −0 = +0).
    let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(nv);
    for p in positions {
        let key = [p.x, p.y, p.z].map(|x| (x + 0.0).to_bits());
        *seen.entry(key).or_insert(0) += 1;
    }
    c.duplicate_vertices = seen.values().map(|&k| k as usize - 1).sum();
    let used_count = used.iter().filter(|&&u| u).count() as i64;
    c.euler_characteristic = used_count - undirected.len() as i64 + triangles.len() as i64 - c.bad_indices as i64;
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
