//! A small private adjacency structure for subdivision: corners (face, vertex slot), undirected
//! edges with their one or two faces, and per-vertex fans ordered counter-clockwise. Built in
//! linear time from a [`PolyMesh`] with a `HashMap` of directed edges; validates the input.

use super::SubdivError;
use crate::mesh::PolyMesh;
use std::collections::HashMap;

/// Marker for "no face" on a boundary edge.
pub(crate) const NONE: u32 = u32::MAX;

/// An undirected edge. `v[0] → v[1]` is its direction in `faces[0]`; `faces[1]` is [`NONE`] on a
/// boundary edge. `corners[k]` is the corner in `faces[k]` where the edge starts (the corner of
/// `v[0]` in `faces[0]`, of `v[1]` in `faces[1]`; [`NONE`] when absent).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Edge {
    pub v: [u32; 2],
    pub faces: [u32; 2],
    pub corners: [u32; 2],
}

impl Edge {
    pub fn is_boundary(&self) -> bool {
        self.faces[1] == NONE
    }
}

/// The corners around one vertex, in counter-clockwise order seen from outside.
/// For a boundary vertex the first corner's outgoing edge and the last corner's incoming edge
/// are the two boundary edges at the vertex.
#[derive(Clone, Debug, Default)]
pub(crate) struct Fan {
    pub corners: Vec<u32>,
    pub boundary: bool,
}

/// Corners are numbered face by face: corner `face_start[f] + i` is slot `i` of face `f`.
pub(crate) struct Topology {
    pub face_start: Vec<usize>,
    /// Vertex of each corner.
    pub corner_vertex: Vec<u32>,
    /// Face of each corner.
    pub corner_face: Vec<u32>,
    /// Edge from each corner to the next corner of its face.
    pub corner_edge: Vec<u32>,
    pub edges: Vec<Edge>,
    /// One fan per vertex (empty for unused vertices).
    pub fans: Vec<Fan>,
}

impl Topology {
    /// Validates `mesh` and builds its adjacency.
    ///
    /// Errors: a face with fewer than 3 vertices, an index out of range, a vertex repeated inside
    /// a face, a non-finite position, a directed edge used twice (an edge with more than two
    /// faces or inconsistently oriented neighbours), a vertex whose faces do not form one fan.
    pub fn new(mesh: &PolyMesh) -> Result<Self, SubdivError> {
        let nv = mesh.positions.len();
        if let Some(v) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(SubdivError::NonFinitePosition { vertex: v });
        }
        let mut face_start = Vec::with_capacity(mesh.faces.len() + 1);
        let mut corner_vertex = Vec::new();
        let mut corner_face = Vec::new();
        face_start.push(0);
        for (f, face) in mesh.faces.iter().enumerate() {
            if face.len() < 3 {
                return Err(SubdivError::FaceTooSmall {
                    face: f,
                    len: face.len(),
                });
            }
            for (i, &v) in face.iter().enumerate() {
                if v as usize >= nv {
                    return Err(SubdivError::IndexOutOfRange {
                        face: f,
                        vertex: v,
                        count: nv,
                    });
                }
                if face[..i].contains(&v) {
                    return Err(SubdivError::RepeatedVertex { face: f, vertex: v });
                }
                corner_vertex.push(v);
                corner_face.push(f as u32);
            }
            face_start.push(corner_vertex.len());
        }
        let nc = corner_vertex.len();
        if nc >= NONE as usize || mesh.faces.len() >= NONE as usize {
            return Err(SubdivError::TooLarge { count: nc as u64 });
        }

        let mut topo = Topology {
            face_start,
            corner_vertex,
            corner_face,
            corner_edge: vec![NONE; nc],
            edges: Vec::new(),
            fans: vec![Fan::default(); nv],
        };

        // Directed edge (a, b) → the corner of `a` in the face that runs a → b.
        let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(nc);
        for c in 0..nc as u32 {
            let key = (
                topo.corner_vertex[c as usize],
                topo.corner_vertex[topo.next(c) as usize],
            );
            if let Some(&other) = directed.get(&key) {
                return Err(SubdivError::DuplicateDirectedEdge {
                    a: key.0,
                    b: key.1,
                    first: topo.corner_face[other as usize] as usize,
                    second: topo.corner_face[c as usize] as usize,
                });
            }
            directed.insert(key, c);
        }

        // Undirected edges, numbered by first appearance.
        for c in 0..nc as u32 {
            let (a, b) = (
                topo.corner_vertex[c as usize],
                topo.corner_vertex[topo.next(c) as usize],
            );
            match directed.get(&(b, a)) {
                Some(&twin) if twin < c => {
                    let e = topo.corner_edge[twin as usize];
                    topo.corner_edge[c as usize] = e;
                    topo.edges[e as usize].faces[1] = topo.corner_face[c as usize];
                    topo.edges[e as usize].corners[1] = c;
                }
                _ => {
                    topo.corner_edge[c as usize] = topo.edges.len() as u32;
                    topo.edges.push(Edge {
                        v: [a, b],
                        faces: [topo.corner_face[c as usize], NONE],
                        corners: [c, NONE],
                    });
                }
            }
        }

        // Fans: walk counter-clockwise from the corner at v in face f to the face that runs
        // v → prev(v in f), starting (for a boundary vertex) at the corner whose outgoing edge
        // has no twin.
        let mut incident: Vec<Vec<u32>> = vec![Vec::new(); nv];
        for c in 0..nc as u32 {
            incident[topo.corner_vertex[c as usize] as usize].push(c);
        }
        for (v, corners) in incident.iter().enumerate() {
            if corners.is_empty() {
                continue;
            }
            let v32 = v as u32;
            let mut start = None;
            for &c in corners {
                let n = topo.corner_vertex[topo.next(c) as usize];
                if !directed.contains_key(&(n, v32)) {
                    if start.is_some() {
                        return Err(SubdivError::NonManifoldVertex { vertex: v });
                    }
                    start = Some(c);
                }
            }
            let boundary = start.is_some();
            let first = start.unwrap_or(corners[0]);
            let mut fan = Vec::with_capacity(corners.len());
            let mut c = first;
            loop {
                fan.push(c);
                if fan.len() > corners.len() {
                    return Err(SubdivError::NonManifoldVertex { vertex: v });
                }
                let p = topo.corner_vertex[topo.prev(c) as usize];
                match directed.get(&(v32, p)) {
                    Some(&nc) if nc == first => break,
                    Some(&nc) => c = nc,
                    None => break,
                }
            }
            if fan.len() != corners.len() {
                return Err(SubdivError::NonManifoldVertex { vertex: v });
            }
            topo.fans[v] = Fan {
                corners: fan,
                boundary,
            };
        }
        Ok(topo)
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.face_start.len() - 1
    }

    /// Corner indices of face `f`.
    pub fn face_corners(&self, f: usize) -> std::ops::Range<usize> {
        self.face_start[f]..self.face_start[f + 1]
    }

    /// The next corner of the same face.
    pub fn next(&self, c: u32) -> u32 {
        let f = self.corner_face[c as usize] as usize;
        if c as usize + 1 == self.face_start[f + 1] {
            self.face_start[f] as u32
        } else {
            c + 1
        }
    }

    /// The previous corner of the same face.
    pub fn prev(&self, c: u32) -> u32 {
        let f = self.corner_face[c as usize] as usize;
        if c as usize == self.face_start[f] {
            self.face_start[f + 1] as u32 - 1
        } else {
            c - 1
        }
    }
}
