//! Topology and sanity checks of a triangle mesh (positions + CCW triangles), linear time.

use crate::progress::{chunk_size, Cancelled, Ticker};
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

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

/// Most vertices per chunk of the per-vertex pass of [`check_mesh_ticked`] (a few tens of
/// milliseconds on two cores), so progress ticks and a cancel take effect between chunks.
const VERTEX_CHUNK: usize = 1 << 15;

/// Most parts of the triangle list bucketed in parallel by [`check_mesh_ticked`]: each part holds
/// a u32 counter per vertex from its count pass to the end of its fill pass (up to 16 bytes per
/// vertex, where the atomic counters before took 8). On more than 4 threads these two passes
/// use 4 of them, deliberately: more parts would cost more counters than the passes save.
const MAX_PARTS: usize = 4;

/// Checks a triangle mesh; see [`MeshCheck`]. Linear time, no hash maps: the triangles'
/// corners are bucketed per vertex (compressed rows), edges and vertex fans are checked on those
/// short lists; duplicate positions by a counting sort into hash buckets ([`duplicate_positions`]).
pub fn check_mesh(positions: &[DVec3], triangles: &[[u32; 3]]) -> MeshCheck {
    check_mesh_ticked(positions, triangles, &mut Ticker::none()).unwrap_or_default()
}

/// [`check_mesh`] reporting progress to `ticker` between its passes (see [`crate::progress`]).
pub fn check_mesh_ticked(positions: &[DVec3], triangles: &[[u32; 3]], ticker: &mut Ticker<'_>) -> Result<MeshCheck, Cancelled> {
    let nv = positions.len();
    let mut c = MeshCheck { vertices: nv, triangles: triangles.len(), ..Default::default() };
    let good = |t: &[u32; 3]| t.iter().all(|&i| (i as usize) < nv);
    // One pass: [bad indices, zero-area triangles].
    [c.bad_indices, c.zero_area_triangles] = triangles
        .par_iter()
        .with_min_len(1 << 12)
        .map(|t| {
            if !good(t) {
                return [1, 0];
            }
            let [a, b, cc] = t.map(|i| positions[i as usize]);
            let longest = (b - a).length_squared().max((cc - b).length_squared()).max((a - cc).length_squared());
            let area2 = (b - a).cross(cc - a).length();
            [0, usize::from(t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(area2 > 2.0 * ZERO_AREA_REL * longest))]
        })
        .reduce(|| [0, 0], |x, y| [x[0] + y[0], x[1] + y[1]]);
    ticker.at(1, 6)?;
    // Corners per vertex: corner (v; a, b) for triangle (v, a, b) in CCW order. Its outgoing
    // directed edge is v → a and its link edge a → b. Bucketed in parallel by a counting sort
    // over a few contiguous parts of the triangles: each part counts its corners per vertex in
    // its own plain array, the prefix sums make those counts each part's next slot per vertex,
    // and each part then writes its corners to its own slots (relaxed atomic stores into the
    // shared array, plain stores on x86; no atomic read-modify-write, which cost half the
    // check). The sort is stable: every bucket lists its corners in triangle order whatever the
    // thread count (the order within a bucket does not matter below anyway).
    let parts = rayon::current_num_threads().clamp(1, MAX_PARTS);
    let per_part = triangles.len().div_ceil(parts).max(1);
    let mut next: Vec<Vec<u32>> = triangles
        .par_chunks(per_part)
        .map(|ts| {
            let mut count = vec![0u32; nv];
            for t in ts.iter().filter(|t| good(t)) {
                for &v in t {
                    count[v as usize] += 1;
                }
            }
            count
        })
        .collect();
    ticker.at(2, 6)?;
    let mut start = vec![0u32; nv + 1];
    for v in 0..nv {
        let mut at = start[v];
        for count in next.iter_mut() {
            (count[v], at) = (at, at + count[v]);
        }
        start[v + 1] = at;
    }
    let links: Vec<AtomicU64> = (0..start[nv]).into_par_iter().map(|_| AtomicU64::new(0)).collect();
    triangles.par_chunks(per_part).zip(next.par_iter_mut()).for_each(|(ts, next)| {
        for t in ts.iter().filter(|t| good(t)) {
            for k in 0..3 {
                let at = &mut next[t[k] as usize];
                links[*at as usize].store((t[(k + 1) % 3] as u64) << 32 | t[(k + 2) % 3] as u64, Ordering::Relaxed);
                *at += 1;
            }
        }
    });
    drop(next);
    ticker.at(3, 6)?;
    let unpack = |x: &AtomicU64| {
        let x = x.load(Ordering::Relaxed);
        ((x >> 32) as u32, x as u32)
    };
    // Per vertex (in parallel): its edges and its fan, from its own corner list only. A corner
    // (u; a, b) of triangle (u, a, b) carries the directed edges u → a and b → u, and every
    // directed edge x → y of a triangle appears exactly once as an outgoing edge (at x's corner)
    // and once as an incoming edge (at y's corner), so the counts of u → w and w → u are both
    // read from u's list.
    // Tally: [inconsistent, undirected, boundary, non-manifold edges, non-manifold vertices, used].
    // In chunks of vertices, ticking between them (integer sums: the chunking changes nothing).
    let per_vertex = |u: usize| {
            let mut t = [0usize; 6];
            let packed = &links[start[u] as usize..start[u + 1] as usize];
            let (mut stack, heap): ([(u32, u32); 16], Vec<(u32, u32)>);
            let list: &[(u32, u32)] = if packed.len() <= 16 {
                stack = [(0, 0); 16];
                for (x, p) in stack.iter_mut().zip(packed) {
                    *x = unpack(p);
                }
                &stack[..packed.len()]
            } else {
                heap = packed.iter().map(unpack).collect();
                &heap
            };
            let m = list.len();
            let uu = u as u32;
            if m == 0 {
                t[4] += 1; // unused vertex
                return t;
            }
            t[5] += 1;
            // The common case first, a closed fan: from corner 0, follow each link edge's end to
            // the first corner whose link edge starts there. If that returns to corner 0 after
            // visiting all m corners once, the successor map is one m-cycle, so every a is the
            // first of its value (all distinct), every b is the a of another corner (the b's are
            // the a's: every edge u → w is used once in each direction). The rest (open fans,
            // repeated edges, more than one fan) takes the general test below.
            if m <= 16 {
                let (mut cur, mut seen, mut steps) = (0usize, 1u32, 1usize);
                while let Some(next) = list.iter().position(|y| y.0 == list[cur].1) {
                    if next == 0 || seen & (1 << next) != 0 {
                        break;
                    }
                    seen |= 1 << next;
                    cur = next;
                    steps += 1;
                }
                if steps == m && list[0].0 == list[cur].1 {
                    t[1] += list.iter().filter(|&&(a, _)| uu < a).count();
                    return t;
                }
            }
            // The link edges a → b around u must form one path or one cycle. Lookups by an
            // edge's start or end: linear in small fans, binary searches in sorted copies in
            // large ones (a node of valence 16000 would cost m² = 2.6·10⁸ steps otherwise).
            let large = m > 16;
            let (mut by_from, mut by_to): (Vec<(u32, u32)>, Vec<u32>) = (Vec::new(), Vec::new());
            if large {
                by_from = list.iter().enumerate().map(|(i, x)| (x.0, i as u32)).collect();
                by_from.sort_unstable();
                by_to = list.iter().map(|x| x.1).collect();
                by_to.sort_unstable();
            }
            let (unique_from, unique_to) = if large {
                (by_from.windows(2).all(|w| w[0].0 != w[1].0), by_to.windows(2).all(|w| w[0] != w[1]))
            } else {
                (
                    (0..m).all(|i| !list[..i].iter().any(|x| x.0 == list[i].0)),
                    (0..m).all(|i| !list[..i].iter().any(|x| x.1 == list[i].1)),
                )
            };
            let leads_in = |x: u32| if large { by_to.binary_search(&x).is_ok() } else { list.iter().any(|y| y.1 == x) };
            let starting = |x: u32| {
                if large {
                    by_from.binary_search_by_key(&x, |e| e.0).ok().map(|k| by_from[k].1 as usize)
                } else {
                    list.iter().position(|y| y.0 == x)
                }
            };
            if unique_from && unique_to {
                // Start where no link edge leads in (boundary fan), else anywhere (closed fan).
                let open = (0..m).find(|&i| !leads_in(list[i].0));
                let first = open.unwrap_or(0);
                let mut cur = first;
                let mut steps = 1;
                while let Some(next) = starting(list[cur].1) {
                    if next == first || steps > m {
                        break;
                    }
                    cur = next;
                    steps += 1;
                }
                if steps == m {
                    // One fan through all corners. The a's are distinct (every edge u → w at
                    // most once), as are the b's (w → u at most once). A closed fan has the
                    // same a's and b's: every edge is used in both directions. An open fan
                    // a_first, …, b_last adds the boundary edges u–a_first (out only) and
                    // u–b_last (in only). Each undirected edge is counted at its smaller end.
                    t[1] += list.iter().filter(|&&(a, _)| uu < a).count();
                    if let Some(f) = open {
                        let (a_first, b_last) = (list[f].0, list[cur].1);
                        if uu < a_first {
                            t[2] += 1;
                        }
                        if uu < b_last {
                            t[1] += 1;
                            t[2] += 1;
                        }
                    }
                    return t;
                }
            }
            t[4] += 1;
            // A non-manifold vertex: count its edges one neighbour at a time.
            for (idx, &(a, b)) in list.iter().enumerate() {
                for (w, seen) in [(a, list[..idx].iter().any(|&(x, y)| x == a || y == a)), (b, b == a || list[..idx].iter().any(|&(x, y)| x == b || y == b))] {
                    if seen {
                        continue;
                    }
                    let forward = list.iter().filter(|&&(x, _)| x == w).count();
                    let backward = list.iter().filter(|&&(_, y)| y == w).count();
                    if forward > 1 {
                        t[0] += 1;
                    }
                    if uu < w {
                        t[1] += 1;
                        match forward + backward {
                            1 => t[2] += 1,
                            2 => {}
                            _ => t[3] += 1,
                        }
                    }
                }
            }
            t
        };
    let add = |a: [usize; 6], b: [usize; 6]| -> [usize; 6] { std::array::from_fn(|i| a[i] + b[i]) };
    let chunk = chunk_size(nv, VERTEX_CHUNK);
    let mut tally = [0usize; 6];
    let mut done = 0;
    while done < nv {
        let end = (done + chunk).min(nv);
        tally = add(tally, (done..end).into_par_iter().with_min_len(1024).map(per_vertex).reduce(|| [0usize; 6], add));
        done = end;
        ticker.at_part(3.0 / 6.0, 5.0 / 6.0, done, nv)?;
    }
    ticker.at(5, 6)?;
    let [inconsistent, undirected, boundary, nm_edges, nm_vertices, used] = tally;
    c.inconsistent_edges = inconsistent;
    c.boundary_edges = boundary;
    c.non_manifold_edges = nm_edges;
    c.non_manifold_vertices = nm_vertices;
    c.duplicate_vertices = duplicate_positions(positions);
    c.euler_characteristic = used as i64 - undirected as i64 + (triangles.len() - c.bad_indices) as i64;
    Ok(c)
}

/// Positions that repeat an earlier one, bit for bit (−0 = +0): each extra copy counted once.
/// Linear time: the positions are bucketed by the top bits of a 64-bit hash of their coordinates
/// (a counting sort, about four per bucket), and only positions in the same bucket are compared.
fn duplicate_positions(positions: &[DVec3]) -> usize {
    let n = positions.len();
    if n < 2 {
        return 0;
    }
    let key = |p: &DVec3| [p.x, p.y, p.z].map(|x| (x + 0.0).to_bits());
    let bits = (usize::BITS - (n / 4).max(1).leading_zeros()).clamp(1, 24);
    let bucket = |h: u64| (h >> (64 - bits)) as usize;
    let hashes: Vec<u64> = positions.par_iter().with_min_len(1 << 14).map(|p| hash_key(key(p))).collect();
    let mut start = vec![0u32; (1 << bits) + 1];
    for &h in &hashes {
        start[bucket(h) + 1] += 1;
    }
    for b in 0..1 << bits {
        start[b + 1] += start[b];
    }
    let mut order = vec![0u32; n];
    let mut fill = start.clone();
    for (i, &h) in hashes.iter().enumerate() {
        let b = bucket(h);
        order[fill[b] as usize] = i as u32;
        fill[b] += 1;
    }
    drop(fill);
    // Per bucket: a member is a repeat when an earlier member has the same hash and key (pairs
    // within a bucket: about four members each; a bucket of many equal positions costs its size
    // squared only in the hashes it shares, so a sort takes buckets of more than 32).
    start
        .par_windows(2)
        .with_min_len(1 << 12)
        .map(|w| {
            let members = &order[w[0] as usize..w[1] as usize];
            if members.len() > 32 {
                let mut keys: Vec<[u64; 3]> = members.iter().map(|&i| key(&positions[i as usize])).collect();
                keys.sort_unstable();
                return keys.windows(2).filter(|k| k[0] == k[1]).count();
            }
            let same = |i: u32, j: u32| hashes[i as usize] == hashes[j as usize] && key(&positions[i as usize]) == key(&positions[j as usize]);
            (1..members.len()).filter(|&k| members[..k].iter().any(|&j| same(j, members[k]))).count()
        })
        .sum()
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
        // −0 and +0 are the same coordinate.
        let c = check_mesh(&[DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(-0.0, 0.0, -0.0)], &[[0, 1, 2]]);
        assert_eq!(c.duplicate_vertices, 1);
    }

    /// The counting sort splits the triangles into one part per thread (at most MAX_PARTS):
    /// the same check with 1, 3 and 4 threads, on a damaged torus (fans spread over several
    /// parts; with 4 threads the parts are of uneven length).
    #[test]
    fn the_check_does_not_depend_on_the_thread_count() {
        let quads = crate::mesh::generate::torus(9, 7, 3.0, 1.0).unwrap();
        let mut tris: Vec<[u32; 3]> = quads.faces.iter().flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]]).collect();
        tris.remove(40);
        tris[7].swap(1, 2);
        tris.push([0, 1, 500]);
        let checks: Vec<MeshCheck> = [1, 3, 4]
            .iter()
            .map(|&k| rayon::ThreadPoolBuilder::new().num_threads(k).build().unwrap().install(|| check_mesh(&quads.positions, &tris)))
            .collect();
        let (inconsistent, _, boundary, nm) = reference_edges(quads.positions.len(), &tris);
        for c in &checks {
            assert_eq!(c, &checks[0]);
            assert_eq!((c.inconsistent_edges, c.boundary_edges, c.non_manifold_edges, c.bad_indices), (inconsistent, boundary, nm, 1));
        }
    }

    /// Many copies of one position fall into one bucket (the sorted path of
    /// `duplicate_positions`), next to distinct positions in small buckets.
    #[test]
    fn duplicates_in_a_large_bucket_are_each_counted_once() {
        let mut p: Vec<DVec3> = (0..1000).map(|i| DVec3::new(i as f64, 0.5 * i as f64, 1.0)).collect();
        p.extend(std::iter::repeat_n(DVec3::new(0.25, 7.0, -3.0), 100));
        p.extend((0..40).map(|i| DVec3::new(i as f64, 0.5 * i as f64, 1.0)));
        assert_eq!(duplicate_positions(&p), 99 + 40);
        assert_eq!(duplicate_positions(&p[..1000]), 0);
        assert_eq!(duplicate_positions(&p[..1]), 0);
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
    
        #[test]
        fn damaged_torus_matches_the_hash_reference(drop in proptest::collection::vec(0usize..96, 0..6), flip in proptest::collection::vec(0usize..96, 0..3)) {
            let quads = crate::mesh::generate::torus(8, 6, 3.0, 1.0).unwrap();
            let mut tris: Vec<[u32; 3]> = quads.faces.iter().flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]]).collect();
            for &k in &flip {
                tris[k].swap(1, 2);
            }
            let kept: Vec<[u32; 3]> = tris.iter().enumerate().filter(|(k, _)| !drop.contains(k)).map(|(_, t)| *t).collect();
            let c = check_mesh(&quads.positions, &kept);
            let (inconsistent, undirected, boundary, nm) = reference_edges(quads.positions.len(), &kept);
            prop_assert_eq!((c.inconsistent_edges, c.boundary_edges, c.non_manifold_edges), (inconsistent, boundary, nm));
            let used: HashSet<u32> = kept.iter().flat_map(|t| t.iter().copied()).collect();
            prop_assert_eq!(c.euler_characteristic, used.len() as i64 - undirected as i64 + kept.len() as i64);
            if drop.is_empty() && flip.is_empty() {
                prop_assert!(c.is_clean_closed());
                prop_assert_eq!(c.euler_characteristic, 0);
            }
        }

        /// Fans of more than 16 corners (the sorted lookups): a double cone over a k-gon, damaged,
        /// with a third apex fan glued to one of the apexes (a non-manifold vertex) when `bowtie`.
        #[test]
        fn large_fans_match_the_hash_reference(k in 17usize..60, drop in proptest::collection::vec(0usize..120, 0..4), flip in proptest::collection::vec(0usize..120, 0..3), bowtie in proptest::bool::ANY) {
            let ku = k as u32;
            let mut positions: Vec<DVec3> = (0..k).map(|i| { let a = std::f64::consts::TAU * i as f64 / k as f64; DVec3::new(a.cos(), a.sin(), 0.0) }).collect();
            positions.push(DVec3::Z);
            positions.push(-DVec3::Z);
            let (top, bottom) = (ku, ku + 1);
            let mut tris: Vec<[u32; 3]> = (0..ku).flat_map(|i| [[i, (i + 1) % ku, top], [(i + 1) % ku, i, bottom]]).collect();
            if bowtie {
                let base = positions.len() as u32;
                positions.extend((0..k).map(|i| { let a = std::f64::consts::TAU * i as f64 / k as f64; DVec3::new(a.cos(), a.sin(), 2.0) }));
                tris.extend((0..ku).map(|i| [base + i, base + (i + 1) % ku, top]));
            }
            for &j in &flip {
                let j = j % tris.len();
                tris[j].swap(1, 2);
            }
            let kept: Vec<[u32; 3]> = tris.iter().enumerate().filter(|(j, _)| !drop.iter().any(|&d| d % tris.len() == *j)).map(|(_, t)| *t).collect();
            let c = check_mesh(&positions, &kept);
            let (inconsistent, undirected, boundary, nm) = reference_edges(positions.len(), &kept);
            prop_assert_eq!((c.inconsistent_edges, c.boundary_edges, c.non_manifold_edges), (inconsistent, boundary, nm));
            let used: HashSet<u32> = kept.iter().flat_map(|t| t.iter().copied()).collect();
            prop_assert_eq!(c.euler_characteristic, used.len() as i64 - undirected as i64 + kept.len() as i64);
            if drop.is_empty() && flip.is_empty() && !bowtie {
                prop_assert!(c.is_clean_closed());
            }
            if bowtie {
                prop_assert!(c.non_manifold_vertices >= 1);
            }
        }
}
}
