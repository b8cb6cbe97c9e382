//! The welding map of a surface: which output vertex every sample of every patch becomes (see
//! the [`super::surface`] module doc), from the adjacency alone (no position comparison).

use super::TessellateError;
use crate::construct::Surface;
use crate::gb::SampleLayout;
use std::collections::HashMap;

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[x as usize];
        parent[x as usize] = parent[p as usize];
        x = p;
    }
    x
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        // Keep the smaller root so the node's representative is its first (patch, corner).
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent[hi as usize] = lo;
    }
}

/// Checks that `neighbors` matches the patches and is reciprocal.
pub fn check_adjacency(surface: &Surface) -> Result<(), TessellateError> {
    for (p, patch) in surface.patches.iter().enumerate() {
        let sides = patch.sides();
        let entries = surface.neighbors.get(p).map_or(0, |v| v.len());
        if entries != sides {
            return Err(TessellateError::NeighborCount { patch: p, sides, entries });
        }
    }
    for (p, sides) in surface.neighbors.iter().enumerate().take(surface.patches.len()) {
        for (i, nb) in sides.iter().enumerate() {
            if let Some(nb) = nb {
                let back = surface.neighbors.get(nb.patch).and_then(|s| s.get(nb.side)).copied().flatten();
                let ok = back.is_some_and(|b| b.patch == p && b.side == i) && (nb.patch, nb.side) != (p, i);
                if !ok {
                    return Err(TessellateError::Adjacency { patch: p, side: i, other_patch: nb.patch, other_side: nb.side });
                }
            }
        }
    }
    Ok(())
}

/// Global vertex ids of every sample of every patch (the welding map), see the module doc.
/// `ids[offsets[p] + s]` is the output vertex of sample s of patch p; `owner` tells whether
/// each id was created by this sample.
pub(crate) struct WeldMap {
    pub offsets: Vec<usize>,
    pub ids: Vec<u32>,
    pub owner: Vec<bool>,
    /// The vertices created by patch p are `vstart[p]..vstart[p + 1]`, in sample order.
    pub vstart: Vec<usize>,
    pub vertex_count: usize,
}

impl WeldMap {
    /// The map of `surface` sampled with `layouts` (one per side count n), `r` boundary steps
    /// per side ([`SampleLayout::per_side`], the same for every layout).
    pub fn new(surface: &Surface, layouts: &HashMap<usize, SampleLayout>, r: usize) -> Result<WeldMap, TessellateError> {
        let np = surface.patches.len();
        let sides: Vec<usize> = surface.patches.iter().map(|p| p.sides()).collect();
        // Corner numbering: corner c of patch p is corner_base[p] + c.
        let mut corner_base = Vec::with_capacity(np + 1);
        let mut total = 0usize;
        for &n in &sides {
            corner_base.push(total);
            total += n;
        }
        corner_base.push(total);
        let mut parent: Vec<u32> = (0..total as u32).collect();
        for p in 0..np {
            let n = sides[p];
            for i in 0..n {
                if let Some(nb) = surface.neighbors[p][i] {
                    let m = sides[nb.patch];
                    // Side i of p runs from corner i−1 to corner i; side j of q from corner j−1 to
                    // j, in the opposite direction along the shared curve.
                    let p_start = corner_base[p] + (i + n - 1) % n;
                    let p_end = corner_base[p] + i;
                    let q_start = corner_base[nb.patch] + (nb.side + m - 1) % m;
                    let q_end = corner_base[nb.patch] + nb.side;
                    union(&mut parent, p_start as u32, q_end as u32);
                    union(&mut parent, p_end as u32, q_start as u32);
                }
            }
        }
        let mut offsets = Vec::with_capacity(np + 1);
        let mut len = 0usize;
        for &n in &sides {
            offsets.push(len);
            len += layouts[&n].uv.len();
        }
        offsets.push(len);
        let mut ids = vec![u32::MAX; len];
        let mut owner = vec![false; len];
        let mut node_id = vec![u32::MAX; total];
        let mut next: usize = 0;
        let mut vstart = Vec::with_capacity(np + 1);
        for p in 0..np {
            vstart.push(next);
            let n = sides[p];
            let layout = &layouts[&n];
            let base = offsets[p];
            let first_boundary = layout.first_boundary();
            for s in 0..first_boundary {
                ids[base + s] = next as u32;
                owner[base + s] = true;
                next += 1;
            }
            for i in 0..n {
                for t in 0..r {
                    let s = layout.boundary_index(i, t);
                    let id = if t == 0 {
                        let root = find(&mut parent, (corner_base[p] + (i + n - 1) % n) as u32) as usize;
                        if node_id[root] == u32::MAX {
                            node_id[root] = next as u32;
                            owner[base + s] = true;
                            next += 1;
                        }
                        node_id[root]
                    } else {
                        match surface.neighbors[p][i] {
                            Some(nb) if (nb.patch, nb.side) < (p, i) => {
                                let q_layout = &layouts[&sides[nb.patch]];
                                ids[offsets[nb.patch] + q_layout.boundary_index(nb.side, r - t)]
                            }
                            _ => {
                                owner[base + s] = true;
                                next += 1;
                                (next - 1) as u32
                            }
                        }
                    };
                    ids[base + s] = id;
                }
            }
            if next > u32::MAX as usize - 1 {
                return Err(TessellateError::TooLarge { count: next });
            }
        }
        vstart.push(next);
        debug_assert!(ids.iter().all(|&x| x != u32::MAX));
        Ok(WeldMap { offsets, ids, owner, vstart, vertex_count: next })
    }
}
