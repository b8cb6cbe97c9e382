//! Mesh generators for tests and benchmarks: quad tori, UV, ico and quad spheres, convex polyhedra
//! (convex hulls) and the large-n cases (a planar n-gon, a cone over an n-gon, a prism with n-gon caps).

use super::error::MeshError;
use super::geometry::newell_normal;
use super::PolyMesh;
use glam::DVec3;
use std::collections::HashMap;
use std::f64::consts::TAU;

/// Torus of `n_major × n_minor` quads around the z axis: vertex `i·n_minor + j` is at
/// `((R + r cos v) cos u, (R + r cos v) sin u, r sin v)` with `u = 2πi/n_major`,
/// `v = 2πj/n_minor`; face `(i, j)` is `[(i,j), (i+1,j), (i+1,j+1), (i,j+1)]` (outward,
/// counter-clockwise), faces ordered by `i` then `j` (the layout of `models/torus.obj`).
/// Needs `n_major, n_minor ≥ 3` and `0 < r < R`.
pub fn torus(n_major: usize, n_minor: usize, major_radius: f64, minor_radius: f64) -> Result<PolyMesh, MeshError> {
    if n_major < 3 || n_minor < 3 || !(minor_radius > 0.0 && minor_radius < major_radius) || !major_radius.is_finite() {
        return Err(MeshError::Degenerate(format!(
            "torus needs n_major, n_minor >= 3 and 0 < r < R (got {n_major}, {n_minor}, R = {major_radius}, r = {minor_radius})"
        )));
    }
    let (nu, nv) = (n_major, n_minor);
    let mut positions = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let u = TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let v = TAU * j as f64 / nv as f64;
            let rho = major_radius + minor_radius * v.cos();
            positions.push(DVec3::new(rho * u.cos(), rho * u.sin(), minor_radius * v.sin()));
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    let mut faces = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            faces.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Ok(PolyMesh::new(positions, faces))
}

/// Unit UV sphere like Blender's: `segments` meridians and `rings` bands of faces
/// (`segments · rings` faces: a triangle fan at each pole and quads between). Vertex 0 is the
/// south pole (0, 0, −1), then the `rings − 1` parallels from south to north, `segments` vertices
/// each (vertex `1 + k·segments + i` at polar angle `π(k+1)/rings`, azimuth `2πi/segments`), then
/// the north pole. Faces outward, counter-clockwise. Needs `segments ≥ 3`, `rings ≥ 2`.
pub fn uv_sphere(segments: usize, rings: usize) -> Result<PolyMesh, MeshError> {
    if segments < 3 || rings < 2 {
        return Err(MeshError::Degenerate(format!("UV sphere needs segments >= 3 and rings >= 2 (got {segments}, {rings})")));
    }
    let (s, r) = (segments, rings);
    let mut positions = Vec::with_capacity(2 + s * (r - 1));
    positions.push(-DVec3::Z);
    for k in 1..r {
        let theta = std::f64::consts::PI * k as f64 / r as f64;
        for i in 0..s {
            let phi = TAU * i as f64 / s as f64;
            positions.push(DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), -theta.cos()));
        }
    }
    positions.push(DVec3::Z);
    let north = (positions.len() - 1) as u32;
    let id = |k: usize, i: usize| (1 + k * s + i % s) as u32;
    let mut faces = Vec::with_capacity(s * r);
    for i in 0..s {
        faces.push(vec![0, id(0, i + 1), id(0, i)]);
    }
    for k in 0..r - 2 {
        for i in 0..s {
            faces.push(vec![id(k, i), id(k, i + 1), id(k + 1, i + 1), id(k + 1, i)]);
        }
    }
    for i in 0..s {
        faces.push(vec![id(r - 2, i), id(r - 2, i + 1), north]);
    }
    Ok(PolyMesh::new(positions, faces))
}

/// Icosahedron (the convex hull of the 12 points (0, ±1, ±φ) and their cyclic permutations),
/// each triangle split into 4 at its edge midpoints `splits` times, every vertex projected to the
/// unit sphere (the ico sphere of `scripts/bench_fairness`). Outward, counter-clockwise (the hull's
/// orientation, kept by the split).
pub fn ico_sphere(splits: usize) -> PolyMesh {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pts = Vec::new();
    for a in [-1.0, 1.0] {
        for b in [-phi, phi] {
            pts.extend([DVec3::new(0.0, a, b), DVec3::new(a, b, 0.0), DVec3::new(b, 0.0, a)]);
        }
    }
    let hull = convex_hull(&pts).expect("icosahedron");
    let mut positions: Vec<DVec3> = hull.positions.iter().map(|p| p.normalize()).collect();
    let mut faces: Vec<[u32; 3]> = hull.faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
    assert_eq!(faces.len(), 20);
    for _ in 0..splits {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<DVec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        faces = next;
    }
    PolyMesh::new(positions, faces.into_iter().map(|f| f.to_vec()).collect())
}

/// The cube [−1, 1]³ with `n × n` quads per side (vertices shared along the cube's edges),
/// every vertex projected to the unit sphere; quads outward, counter-clockwise.
pub fn quad_sphere(n: i32) -> PolyMesh {
    let mut index: HashMap<[i32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let mut vertex = |g: [i32; 3], positions: &mut Vec<DVec3>| {
        *index.entry(g).or_insert_with(|| {
            positions.push(DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64).normalize());
            (positions.len() - 1) as u32
        })
    };
    // Grid coordinates in −n..=n step 2 (so the cube is [−n, n]³).
    for axis in 0..3 {
        for sign in [-1, 1] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: i32, dj: i32| {
                        let mut g = [0; 3];
                        g[axis] = sign * n;
                        g[u] = -n + 2 * (i + di);
                        g[v] = -n + 2 * (j + dj);
                        g
                    };
                    let mut quad = vec![corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                    // (u, v, axis) is right-handed: counter-clockwise seen from +axis.
                    if sign < 0 {
                        quad.reverse();
                    }
                    faces.push(quad.into_iter().map(|g| vertex(g, &mut positions)).collect::<Vec<u32>>());
                }
            }
        }
    }
    PolyMesh::new(positions, faces)
}

/// The regular n-gon of unit radius in the plane z = 0, vertex i at angle 2πi/n.
fn ngon_ring(n: usize, z: f64) -> Vec<DVec3> {
    (0..n).map(|i| {
        let a = TAU * i as f64 / n as f64;
        DVec3::new(a.cos(), a.sin(), z)
    }).collect()
}

fn check_sides(what: &str, n: usize) -> Result<(), MeshError> {
    if n < 3 {
        return Err(MeshError::Degenerate(format!("{what} needs n >= 3 sides (got {n})")));
    }
    Ok(())
}

/// One planar regular n-gon (an open mesh of one face, counter-clockwise seen from +z):
/// a face of n sides. Needs n ≥ 3.
pub fn polygon(n: usize) -> Result<PolyMesh, MeshError> {
    check_sides("polygon", n)?;
    Ok(PolyMesh::new(ngon_ring(n, 0.0), vec![(0..n as u32).collect()]))
}

/// A closed cone over the regular n-gon: apex (0, 0, 1) (vertex n, valence n) over the base
/// ring at z = 0; n triangles and the base n-gon, outward. Needs n ≥ 3.
pub fn cone(n: usize) -> Result<PolyMesh, MeshError> {
    check_sides("cone", n)?;
    let mut positions = ngon_ring(n, 0.0);
    positions.push(DVec3::Z);
    let m = n as u32;
    let mut faces: Vec<Vec<u32>> = (0..m).map(|i| vec![i, (i + 1) % m, m]).collect();
    faces.push((0..m).rev().collect());
    Ok(PolyMesh::new(positions, faces))
}

/// A closed prism with regular n-gon caps at z = 0 and z = 1: n quads and two n-gons, outward
/// (vertex i of the bottom ring, n + i above it). Needs n ≥ 3.
pub fn prism(n: usize) -> Result<PolyMesh, MeshError> {
    check_sides("prism", n)?;
    let mut positions = ngon_ring(n, 0.0);
    positions.extend(ngon_ring(n, 1.0));
    let m = n as u32;
    let mut faces: Vec<Vec<u32>> = (0..m).map(|i| vec![i, (i + 1) % m, m + (i + 1) % m, m + i]).collect();
    faces.push((0..m).rev().collect());
    faces.push((m..2 * m).collect());
    Ok(PolyMesh::new(positions, faces))
}

/// Convex hull of `points` as a closed triangle mesh (outward, counter-clockwise), by the
/// incremental algorithm (O(n²), meant for up to a few hundred points). Only hull vertices are
/// kept (renumbered in input order). Points within `1e-10 · d` (`d` the bounding-box diagonal) of
/// the current hull count as inside, so nearly coplanar corners are dropped rather than producing
/// slivers. Errors: fewer than 4 points, non-finite points, or all points (nearly) coplanar.
pub fn convex_hull(points: &[DVec3]) -> Result<PolyMesh, MeshError> {
    if points.len() < 4 {
        return Err(MeshError::Degenerate(format!("convex hull needs 4 points, got {}", points.len())));
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(MeshError::Degenerate(format!("point {i} is not finite")));
    }
    let (lo, hi) = points.iter().fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(l, h), p| (l.min(*p), h.max(*p)));
    let diag = (hi - lo).length();
    let eps = 1e-10 * diag;
    let degenerate = || MeshError::Degenerate("all points (nearly) coplanar".into());
    if !(diag > 0.0) {
        return Err(degenerate());
    }
    // initial tetrahedron
    let i0 = (0..points.len()).min_by(|&a, &b| points[a].x.total_cmp(&points[b].x)).unwrap_or(0);
    let far = |f: &dyn Fn(DVec3) -> f64| (0..points.len()).max_by(|&a, &b| f(points[a]).total_cmp(&f(points[b]))).unwrap_or(0);
    let p0 = points[i0];
    let i1 = far(&|p| p.distance(p0));
    let p1 = points[i1];
    let dir = (p1 - p0).normalize_or_zero();
    let i2 = far(&|p| (p - p0).reject_from_normalized(dir).length());
    let p2 = points[i2];
    let n = (p1 - p0).cross(p2 - p0);
    if (p2 - p0).reject_from_normalized(dir).length() <= eps || n.length() == 0.0 {
        return Err(degenerate());
    }
    let n = n.normalize();
    let i3 = far(&|p| (p - p0).dot(n).abs());
    if (points[i3] - p0).dot(n).abs() <= eps {
        return Err(degenerate());
    }
    let mut faces: Vec<Option<[usize; 3]>> = Vec::new();
    let mut planes: Vec<(DVec3, f64)> = Vec::new();
    let mut edge_face: HashMap<(usize, usize), usize> = HashMap::new();
    let plane_of = |t: [usize; 3]| {
        let nn = (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]).normalize_or_zero();
        (nn, nn.dot(points[t[0]]))
    };
    let add = |t: [usize; 3], faces: &mut Vec<Option<[usize; 3]>>, planes: &mut Vec<(DVec3, f64)>, ef: &mut HashMap<(usize, usize), usize>| {
        let f = faces.len();
        faces.push(Some(t));
        planes.push(plane_of(t));
        for k in 0..3 {
            ef.insert((t[k], t[(k + 1) % 3]), f);
        }
    };
    let above = (points[i3] - p0).dot(n) > 0.0;
    let tets: [[usize; 3]; 4] = if above {
        [[i0, i2, i1], [i0, i1, i3], [i1, i2, i3], [i2, i0, i3]]
    } else {
        [[i0, i1, i2], [i0, i3, i1], [i1, i3, i2], [i2, i3, i0]]
    };
    for t in tets {
        add(t, &mut faces, &mut planes, &mut edge_face);
    }
    let mut in_hull = vec![false; points.len()];
    for i in [i0, i1, i2, i3] {
        in_hull[i] = true;
    }
    for (pi, &p) in points.iter().enumerate() {
        if in_hull[pi] {
            continue;
        }
        let visible: Vec<usize> = (0..faces.len())
            .filter(|&f| faces[f].is_some() && planes[f].0.dot(p) - planes[f].1 > eps)
            .collect();
        if visible.is_empty() {
            continue;
        }
        let is_vis: HashMap<usize, ()> = visible.iter().map(|&f| (f, ())).collect();
        let mut horizon = Vec::new();
        for &f in &visible {
            let t = faces[f].unwrap_or([0; 3]);
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                match edge_face.get(&(b, a)) {
                    Some(g) if !is_vis.contains_key(g) => horizon.push((a, b)),
                    _ => {}
                }
            }
        }
        for &f in &visible {
            if let Some(t) = faces[f].take() {
                for k in 0..3 {
                    edge_face.remove(&(t[k], t[(k + 1) % 3]));
                }
            }
        }
        for (a, b) in horizon {
            add([a, b, pi], &mut faces, &mut planes, &mut edge_face);
        }
        in_hull[pi] = true;
    }
    // compact: keep vertices of surviving faces, in input order
    let mut used = vec![false; points.len()];
    for t in faces.iter().flatten() {
        for &i in t {
            used[i] = true;
        }
    }
    let mut new_id = vec![u32::MAX; points.len()];
    let mut positions = Vec::new();
    for (i, &u) in used.iter().enumerate() {
        if u {
            new_id[i] = positions.len() as u32;
            positions.push(points[i]);
        }
    }
    let faces = faces.iter().flatten().map(|t| t.iter().map(|&i| new_id[i]).collect()).collect();
    Ok(PolyMesh::new(positions, faces))
}

/// Merges edge-adjacent faces of a closed convex mesh whose unit normals agree within
/// `1 − cos_tol` into single polygons (e.g. the two triangles of a cube side into a quad). Each
/// merged group must be a disk (true for a convex hull); its boundary loop becomes the face,
/// starting at its smallest vertex index. Groups whose boundary is not a single loop are kept as
/// their original faces.
pub fn merge_coplanar(mesh: &PolyMesh, cos_tol: f64) -> PolyMesh {
    let nf = mesh.faces.len();
    let normals: Vec<DVec3> = mesh
        .faces
        .iter()
        .map(|f| newell_normal(&f.iter().map(|&i| mesh.positions[i as usize]).collect::<Vec<_>>()).normalize_or_zero())
        .collect();
    let mut parent: Vec<usize> = (0..nf).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for (f, face) in mesh.faces.iter().enumerate() {
        for k in 0..face.len() {
            directed.insert((face[k], face[(k + 1) % face.len()]), f);
        }
    }
    for (f, face) in mesh.faces.iter().enumerate() {
        for k in 0..face.len() {
            if let Some(&g) = directed.get(&(face[(k + 1) % face.len()], face[k])) {
                if normals[f].dot(normals[g]) >= 1.0 - cos_tol {
                    let (a, b) = (find(&mut parent, f), find(&mut parent, g));
                    if a != b {
                        parent[a.max(b)] = a.min(b);
                    }
                }
            }
        }
    }
    let root: Vec<usize> = (0..nf).map(|f| find(&mut parent, f)).collect();
    let mut groups: Vec<Vec<usize>> = vec![Vec::new(); nf];
    for f in 0..nf {
        groups[root[f]].push(f);
    }
    let mut faces = Vec::new();
    for g in groups.iter().filter(|g| !g.is_empty()) {
        if g.len() == 1 {
            faces.push(mesh.faces[g[0]].clone());
            continue;
        }
        // boundary edges of the group: directed edges whose twin is not in the group
        let mut next: HashMap<u32, u32> = HashMap::new();
        let mut ok = true;
        for &f in g {
            let face = &mesh.faces[f];
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                let inside = directed.get(&(b, a)).is_some_and(|&h| root[h] == root[f]);
                if !inside && next.insert(a, b).is_some() {
                    ok = false;
                }
            }
        }
        let start = next.keys().copied().min();
        let mut lp = Vec::new();
        if let (true, Some(s)) = (ok, start) {
            let mut v = s;
            loop {
                lp.push(v);
                match next.get(&v) {
                    Some(&w) if w != s && lp.len() <= next.len() => v = w,
                    Some(&w) if w == s => break,
                    _ => {
                        ok = false;
                        break;
                    }
                }
            }
        }
        if ok && lp.len() == next.len() {
            faces.push(lp);
        } else {
            faces.extend(g.iter().map(|&f| mesh.faces[f].clone()));
        }
    }
    PolyMesh::new(mesh.positions.clone(), faces)
}
