//! `gbsurf offset`: the exact offset of a GB surface through PN patches (docs/math/pn.md §11).
//!
//! Steps: the GB surface of the control mesh ([`super::build_surface`], the construction step of
//! [`super::convert`]); every n-sided patch split at its domain centre into n quad pieces
//! ([`piece_point`]); on every piece an N × N grid of points, normals and normal derivatives
//! taken from the exact GB derivatives (chain rule through the piece map); the grid data of
//! points shared by several pieces made ONE value, keyed by topology ([`Slots`]); one
//! [`PnSurface::from_derivatives`] per piece; dense samples of the PN surface and its offset
//! x + d·n, welded by topology; the report ([`OffsetReport`]).
//!
//! Where a piece's PN fit is singular (zero Gaussian curvature: flat or cylindrical regions,
//! or a curvature sign change inside the piece) the exact offset of the GB surface itself,
//! x + d·n of the GB patch, is sampled instead, and the piece is counted in
//! `singular_pieces`.

use super::{build_surface, ConvertError, ConvertOptions};
use crate::construct::{Patch, Surface};
use crate::gb::{Domain, Evaluate, SurfaceDerivs};
use crate::mesh::PolyMesh;
use crate::offset::pn::{IsotropicFrame, PnError, PnGrid, PnRational, PnSurface};
use glam::{DMat3, DVec2, DVec3};
use rayon::prelude::*;
use std::collections::HashMap;

/// A PN piece whose surface is farther than this times the size of its grid from the GB surface
/// at a grid point, a cell's edge midpoint or centre is refused and offset as a singular piece (x + d·n of the GB surface).
/// Good fits are about 1e-3 of the piece's size.
pub const FIT_REJECT: f64 = 0.1;

/// Options of [`offset`] besides the convert options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OffsetOptions {
    /// Signed offset distance along the outward surface normal (non-zero, finite).
    pub distance: f64,
    /// PN grid size N per quad piece (2..=[`crate::limits::MAX_OFFSET_GRID`]).
    pub grid: usize,
    /// Output a closed solid: offset, reversed surface and side walls along open boundaries.
    pub shell: bool,
}

impl Default for OffsetOptions {
    fn default() -> Self {
        Self { distance: 0.1, grid: crate::limits::DEFAULT_OFFSET_GRID, shell: false }
    }
}

/// Why an offset failed.
#[derive(Debug, thiserror::Error)]
pub enum OffsetError {
    /// Reading, validating or constructing the surface failed.
    #[error("{0}")]
    Convert(#[from] ConvertError),
    /// `--distance` is NaN or infinite.
    #[error("invalid --distance {d}: must be finite")]
    BadDistance { d: f64 },
    /// `--distance 0` asks for the surface itself.
    #[error("invalid --distance 0: the offset at distance 0 is the surface itself; use `gbsurf convert`")]
    ZeroDistance,
    /// `--grid` outside 2..=MAX_OFFSET_GRID.
    #[error("invalid --grid {grid}: must be in 2..={max}")]
    BadGrid { grid: usize, max: usize },
    /// The rational export of a PN piece failed (names the patch, piece and Coons patch).
    #[error("rational export of patch {patch} piece {piece}: {source}")]
    Export { patch: usize, piece: usize, source: PnError },
}

/// A sample where |D| reaches the local radius of curvature on the concave side (the offset
/// has a cusp or self-overlap there).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CuspSite {
    pub patch: usize,
    pub piece: usize,
    /// Piece parameters (s, t) ∈ [0, 1]².
    pub s: f64,
    pub t: f64,
    pub point: [f64; 3],
    /// The smallest radius of curvature on the side of the offset, 1/max(d·κ/|d|).
    pub radius: f64,
}

/// What [`offset`] measured. Lengths are in the input's units.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct OffsetReport {
    pub distance: f64,
    pub grid: usize,
    /// Quad pieces (Σ n over the patches).
    pub pieces: usize,
    /// Pieces whose PN fit was singular; their offset is the GB surface's x + d·n.
    pub singular_pieces: usize,
    /// The first few reasons of singular pieces (`patch p piece k: …`).
    pub singular_sites: Vec<String>,
    /// Largest |x_PN(s, t) − x_GB(P(s, t))| over the dense samples of the PN pieces (same
    /// parameters; an upper bound of the distance between the surfaces).
    pub max_fit_error: f64,
    /// Largest |n·x_u|/|x_u|, |n·x_v|/|x_v| over dense samples of the PN pieces, and the same
    /// for the offset o (|n·o_u|/|o_u|, |n·o_v|/|o_v|, away from cusps): central differences of
    /// fourth order, step 1e-4 of a Coons cell, at parameters moved 2e-4 inside the cell. Their
    /// rounding error, about ε·|x|/(h·|x_u|), is the floor of this figure (≈ 2e-10 on the shared
    /// torus).
    pub max_normal_residual: f64,
    /// Largest | |o − x| − |d| | over the dense samples of the PN pieces away from cusps (o the
    /// offset point). That n is the surface normal is `max_normal_residual`: a normal off by an
    /// angle θ moves the offset's distance from the surface only by |d|(1 − cos θ) ≈ |d|θ²/2.
    pub max_offset_error: f64,
    /// Largest distance between two pieces' own evaluations of one shared dense sample, on the
    /// offset surface (before welding; the output uses one value per shared sample).
    pub max_gap: f64,
    /// As `max_gap`, only between two PN pieces in one isotropic frame (the case the construction
    /// makes watertight). Where a grid edge ends at an unmatched point (`unmatched_points`) the
    /// two sides' cross derivatives differ along that edge, and so does this figure (≈ 4e-3 on the
    /// shared cube).
    pub max_gap_pn: f64,
    /// Largest angle (radians) between the two pieces' unit normals at a shared dense sample,
    /// over the same pairs as `max_gap_pn` (G1 across the pieces; atan2(|a × b|, a·b)).
    pub max_normal_angle_pn: f64,
    /// Shared piece edges whose two sides are in different isotropic frames.
    pub frame_seams: usize,
    /// Shared grid points where the derivative rays could not be matched (valence ≠ 4: patch
    /// centres of n ≠ 4 sides, cage vertices of valence ≠ 4); the pieces use their own
    /// derivatives there and the join is not exactly G1.
    pub unmatched_points: usize,
    /// Samples where |d| ≥ the local radius of curvature on the offset's concave side.
    pub cusps: usize,
    pub cusp_sites: Vec<CuspSite>,
    pub vertices: usize,
    pub triangles: usize,
    pub closed: bool,
    pub two_manifold: bool,
    pub shell: bool,
    pub seconds: f64,
}

/// One quad piece's fit.
#[derive(Clone, Debug)]
pub struct OffsetPiece {
    pub patch: usize,
    pub piece: usize,
    /// The PN surface; `None` where the fit was singular (the GB surface is offset directly).
    pub pn: Option<PnSurface>,
    /// Why the fit was refused, where `pn` is `None` (the text of `singular_sites`, which keeps
    /// only the first ten).
    pub singular: Option<String>,
}

/// The result of [`offset`].
#[derive(Clone, Debug)]
pub struct Offset {
    /// Output vertices and counter-clockwise triangles (outward for a closed input and d > 0
    /// with `shell`).
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    pub pieces: Vec<OffsetPiece>,
    pub report: OffsetReport,
}

impl Offset {
    /// The exact rational patches of the offset, degree (11, 11): for every PN piece its
    /// (N − 1)² Coons patches `(patch, piece, i, j, form)`. Singular pieces have none (the offset
    /// there is the GB surface's x + d·n, which is not rational): the export is then incomplete,
    /// with holes at [`Offset::singular_pieces`].
    pub fn rational_patches(&self) -> Result<Vec<(usize, usize, usize, usize, PnRational)>, OffsetError> {
        let mut out = Vec::new();
        for p in &self.pieces {
            if let Some(pn) = &p.pn {
                let (a, b) = pn.patch_count();
                for i in 0..a {
                    for j in 0..b {
                        let r = pn.rational_offset(i, j, self.report.distance).map_err(|source| OffsetError::Export {
                            patch: p.patch,
                            piece: p.piece,
                            source,
                        })?;
                        out.push((p.patch, p.piece, i, j, r));
                    }
                }
            }
        }
        Ok(out)
    }

    /// The pieces without a rational form (singular fits): `(patch, piece, reason)`, in piece
    /// order. Empty exactly when [`Offset::rational_patches`] covers the whole offset.
    pub fn singular_pieces(&self) -> Vec<(usize, usize, &str)> {
        self.pieces
            .iter()
            .filter(|p| p.pn.is_none())
            .map(|p| (p.patch, p.piece, p.singular.as_deref().unwrap_or("no PN fit")))
            .collect()
    }
}

/// The domain point of quad piece `k` of an n-sided patch at (s, t) ∈ [0, 1]²: bilinear in
/// (centre c, midpoint M_k of side k, vertex V_k, midpoint M_{k+1} of side k + 1):
/// P(s, t) = (1−s)(1−t) c + s(1−t) M_k + s t V_k + (1−s) t M_{k+1}, with its partials P_s, P_t.
/// Piece k's edges: t = 0 is c → M_k (shared with piece k − 1's s = 0), s = 1 is the second half
/// of side k, t = 1 is the first half of side k + 1 (reversed), s = 0 is c → M_{k+1}.
/// Counter-clockwise, so P_s × P_t > 0 and the piece keeps the patch's orientation.
pub fn piece_point(domain: &Domain, k: usize, s: f64, t: f64) -> (DVec2, DVec2, DVec2) {
    let c = domain.center();
    let mk = domain.side_point(k, 0.5);
    let vk = domain.vertex(k);
    let mk1 = domain.side_point(k + 1, 0.5);
    let p = c * ((1.0 - s) * (1.0 - t)) + mk * (s * (1.0 - t)) + vk * (s * t) + mk1 * ((1.0 - s) * t);
    let ps = (mk - c) * (1.0 - t) + (vk - mk1) * t;
    let pt = (mk1 - c) * (1.0 - s) + (vk - mk) * s;
    (p, ps, pt)
}

/// Point, unit normal and the normal's derivatives along domain directions `a`, `b` (Weingarten:
/// n_w = (m_w − n (n·m_w))/|m| with m = S_u × S_v). `None` where m vanishes.
fn normal_jet(d: &SurfaceDerivs, a: DVec2, b: DVec2) -> Option<(DVec3, DVec3, DVec3, DVec3)> {
    let m = d.su.cross(d.sv);
    let len = m.length();
    if !(len > 0.0) || !len.is_finite() {
        return None;
    }
    let n = m / len;
    let dm = |w: DVec2| {
        let su_w = d.suu * w.x + d.suv * w.y;
        let sv_w = d.suv * w.x + d.svv * w.y;
        let mw = su_w.cross(d.sv) + d.su.cross(sv_w);
        (mw - n * n.dot(mw)) / len
    };
    Some((d.p, n, dm(a), dm(b)))
}

/// Slots of every patch's pieces on an M × M grid each, identified by topology with a
/// union-find whose root is the smallest slot: the centre and the inner edges c → M_k of a
/// patch, and the patch sides with their neighbours' (side i at σ is the neighbour's side at
/// 1 − σ).
struct Slots {
    m: usize,
    offsets: Vec<usize>,
    parent: Vec<usize>,
}

impl Slots {
    fn new(surface: &Surface, m: usize) -> Self {
        let mut offsets = Vec::with_capacity(surface.patches.len() + 1);
        let mut total = 0;
        for p in &surface.patches {
            offsets.push(total);
            total += p.sides() * m * m;
        }
        offsets.push(total);
        let mut s = Slots { m, offsets, parent: (0..total).collect() };
        let l = m - 1;
        for (p, patch) in surface.patches.iter().enumerate() {
            let n = patch.sides();
            for k in 0..n {
                let prev = (k + n - 1) % n;
                for i in 0..m {
                    s.union(s.id(p, k, i, 0), s.id(p, prev, 0, i));
                }
                // Side k and side k + 1 meet at V_k: side k's last index is side k + 1's first.
            }
            for (side, nb) in surface.neighbors[p].iter().enumerate() {
                if let Some(nb) = nb {
                    for idx in 0..=2 * l {
                        let a = s.side_slot(surface, p, side, idx);
                        let b = s.side_slot(surface, nb.patch, nb.side, 2 * l - idx);
                        s.union(a, b);
                    }
                }
            }
        }
        for x in 0..s.parent.len() {
            s.find(x);
        }
        s
    }

    fn id(&self, p: usize, k: usize, i: usize, j: usize) -> usize {
        self.offsets[p] + (k * self.m + i) * self.m + j
    }

    /// Slot of side `side` of patch `p` at index `idx` ∈ 0..=2(M−1) (σ = idx / (2(M−1))): the
    /// first half is piece side−1's t = 1 edge (reversed), the second half piece side's s = 1 edge.
    fn side_slot(&self, surface: &Surface, p: usize, side: usize, idx: usize) -> usize {
        let n = surface.patches[p].sides();
        let l = self.m - 1;
        if idx <= l {
            self.id(p, (side + n - 1) % n, l - idx, l)
        } else {
            self.id(p, side, l, idx - l)
        }
    }

    fn find(&mut self, mut x: usize) -> usize {
        let mut r = x;
        while self.parent[r] != r {
            r = self.parent[r];
        }
        while self.parent[x] != r {
            let next = self.parent[x];
            self.parent[x] = r;
            x = next;
        }
        r
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi] = lo;
        }
    }

    /// The root of slot x (after construction every parent is a root).
    fn root(&self, x: usize) -> usize {
        self.parent[x]
    }
}

/// The four derivative rays of a slot: u+, u−, v+, v−, each as the canonical id of the grid
/// neighbour it points to, or of the neighbour it points away from (`Away`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ray {
    To(usize),
    Away(usize),
}

/// Raw per-slot grid data from the slot's own patch: point, normal, per-grid-step normal
/// derivatives along the piece's s and t.
#[derive(Clone, Copy, Debug, Default)]
struct Raw {
    x: DVec3,
    n: DVec3,
    nu: DVec3,
    nv: DVec3,
    ok: bool,
}

fn patch_domain(p: &Patch) -> Option<Domain> {
    Domain::regular(p.sides()).ok()
}

/// Builds the surface with [`build_surface`], then [`offset_surface`].
pub fn offset(mesh: &PolyMesh, options: &ConvertOptions, off: &OffsetOptions) -> Result<Offset, OffsetError> {
    let start = std::time::Instant::now();
    check_offset_options(off)?;
    let surface = build_surface(mesh, options)?;
    let mut out = offset_surface(&surface, options, off)?;
    out.report.seconds = start.elapsed().as_secs_f64();
    Ok(out)
}

fn check_offset_options(off: &OffsetOptions) -> Result<(), OffsetError> {
    if !off.distance.is_finite() {
        return Err(OffsetError::BadDistance { d: off.distance });
    }
    if off.distance == 0.0 {
        return Err(OffsetError::ZeroDistance);
    }
    if !(2..=crate::limits::MAX_OFFSET_GRID).contains(&off.grid) {
        return Err(OffsetError::BadGrid { grid: off.grid, max: crate::limits::MAX_OFFSET_GRID });
    }
    Ok(())
}

/// The two isotropic frames of the pieces: pole at +z (identity) and at −z (a half turn about
/// x). A piece uses the first unless one of its grid normals has n_z > 1/2.
fn frames() -> [IsotropicFrame; 2] {
    let flip = IsotropicFrame::from_rotation(DMat3::from_diagonal(DVec3::new(1.0, -1.0, -1.0)));
    [IsotropicFrame::IDENTITY, flip.unwrap_or(IsotropicFrame::IDENTITY)]
}

/// The offset of an already constructed surface (see the module doc).
pub fn offset_surface(surface: &Surface, options: &ConvertOptions, off: &OffsetOptions) -> Result<Offset, OffsetError> {
    let start = std::time::Instant::now();
    check_offset_options(off)?;
    let d = off.distance;
    let form = options.weights;
    let g = off.grid;
    let gl = (g - 1) as f64;
    let domains: Vec<Option<Domain>> = surface.patches.iter().map(patch_domain).collect();
    let grid_slots = Slots::new(surface, g);
    let total = *grid_slots.offsets.last().unwrap_or(&0);
    let mut report = OffsetReport { distance: d, grid: g, shell: off.shell, ..Default::default() };

    // 1. Raw grid data per slot, from the slot's own patch (patches in parallel, written in
    // patch order: the same result as a serial loop).
    let mut raw = vec![Raw::default(); total];
    let per_patch = per_grid_point(surface, &domains, g, |p, patch, dom, k, i, j| {
        let (uv, ps, pt) = piece_point(dom, k, i as f64 / gl, j as f64 / gl);
        let sd = patch.eval_derivs(uv, form);
        normal_jet(&sd, ps / gl, pt / gl).map(|(x, n, nu, nv)| (grid_slots.id(p, k, i, j), Raw { x, n, nu, nv, ok: true }))
    });
    for (id, r) in per_patch {
        raw[id] = r;
    }

    // 2. Rays of every incidence, grouped by root.
    let mut rays: Vec<[Ray; 4]> = vec![[Ray::To(0); 4]; total];
    let mut incid: HashMap<usize, Vec<usize>> = HashMap::new();
    for (p, patch) in surface.patches.iter().enumerate() {
        for k in 0..patch.sides() {
            for i in 0..g {
                for j in 0..g {
                    let id = grid_slots.id(p, k, i, j);
                    let nb = |a: usize, b: usize| grid_slots.root(grid_slots.id(p, k, a, b));
                    let up = if i + 1 < g { Ray::To(nb(i + 1, j)) } else { Ray::Away(nb(i - 1, j)) };
                    let um = if i > 0 { Ray::To(nb(i - 1, j)) } else { Ray::Away(nb(i + 1, j)) };
                    let vp = if j + 1 < g { Ray::To(nb(i, j + 1)) } else { Ray::Away(nb(i, j - 1)) };
                    let vm = if j > 0 { Ray::To(nb(i, j - 1)) } else { Ray::Away(nb(i, j + 1)) };
                    rays[id] = [up, um, vp, vm];
                    incid.entry(grid_slots.root(id)).or_default().push(id);
                }
            }
        }
    }

    // 3. Shared derivative data: the root's own (n_u, n_v) defines the vector of each
    // neighbour direction; every incidence reads its (n_u, n_v) from there (negated where its
    // ray points away from the neighbour). Opposite neighbours at a point are known from a piece
    // that has both, or (valence 4) as the one neighbour not adjacent to it in any piece.
    let mut shared_nu = vec![DVec3::ZERO; total];
    let mut shared_nv = vec![DVec3::ZERO; total];
    let mut matched = vec![true; total];
    for (&root, list) in &incid {
        let mut opposite: HashMap<usize, usize> = HashMap::new();
        let mut adjacent: HashMap<usize, Vec<usize>> = HashMap::new();
        for &id in list {
            let r = rays[id];
            for (a, b) in [(r[0], r[1]), (r[2], r[3])] {
                if let (Ray::To(x), Ray::To(y)) = (a, b) {
                    opposite.insert(x, y);
                    opposite.insert(y, x);
                }
            }
            let to = |r: Ray| if let Ray::To(x) = r { Some(x) } else { None };
            for a in [r[0], r[1]].into_iter().filter_map(to) {
                for b in [r[2], r[3]].into_iter().filter_map(to) {
                    adjacent.entry(a).or_default().push(b);
                    adjacent.entry(b).or_default().push(a);
                }
            }
        }
        let all: Vec<usize> = adjacent.keys().copied().collect();
        if all.len() == 4 {
            for &x in &all {
                let adj = &adjacent[&x];
                let rest: Vec<usize> = all.iter().copied().filter(|y| *y != x && !adj.contains(y)).collect();
                if rest.len() == 1 {
                    opposite.entry(x).or_insert(rest[0]);
                }
            }
        }
        let resolve = |r: Ray| -> Option<(usize, f64)> {
            match r {
                Ray::To(x) => Some((x, 1.0)),
                Ray::Away(x) => opposite.get(&x).map(|&y| (y, 1.0)),
            }
        };
        let owner = root;
        let ro = raw[owner];
        let mut vec_of: HashMap<usize, DVec3> = HashMap::new();
        let ro_rays = rays[owner];
        for (ray, v) in [(ro_rays[0], ro.nu), (ro_rays[1], -ro.nu), (ro_rays[2], ro.nv), (ro_rays[3], -ro.nv)] {
            if let Some((x, _)) = resolve(ray) {
                vec_of.insert(x, v);
            }
        }
        for &id in list {
            let r = rays[id];
            let pick = |plus: Ray, minus: Ray| -> Option<DVec3> {
                if let Some(v) = resolve(plus).and_then(|(x, _)| vec_of.get(&x)) {
                    return Some(*v);
                }
                resolve(minus).and_then(|(x, _)| vec_of.get(&x)).map(|v| -*v)
            };
            match (pick(r[0], r[1]), pick(r[2], r[3])) {
                (Some(a), Some(b)) if list.len() > 1 || id == owner => {
                    shared_nu[id] = a;
                    shared_nv[id] = b;
                }
                _ => {
                    shared_nu[id] = raw[id].nu;
                    shared_nv[id] = raw[id].nv;
                    matched[id] = false;
                }
            }
        }
        if list.iter().any(|&id| !matched[id]) && list.len() > 1 {
            report.unmatched_points += 1;
        }
    }

    // 4. One PN surface per piece: the fits of each patch in parallel, then merged into the
    // report in patch order (the same report as a serial loop).
    let fr = frames();
    let fits: Vec<Vec<Result<(PnSurface, usize), String>>> = surface
        .patches
        .par_iter()
        .enumerate()
        .map(|(p, patch)| (0..patch.sides()).map(|k| fit_piece(surface, &domains, &grid_slots, &raw, &shared_nu, &shared_nv, &fr, form, g, p, k)).collect())
        .collect();
    let mut pieces = Vec::new();
    let mut piece_frame: Vec<Vec<Option<usize>>> = Vec::new();
    for (p, fits_p) in fits.into_iter().enumerate() {
        let mut frames_p = Vec::new();
        for (k, fit) in fits_p.into_iter().enumerate() {
            report.pieces += 1;
            match fit {
                Ok((s, which)) => {
                    frames_p.push(Some(which));
                    pieces.push(OffsetPiece { patch: p, piece: k, pn: Some(s), singular: None });
                }
                Err(e) => {
                    report.singular_pieces += 1;
                    if report.singular_sites.len() < 10 {
                        report.singular_sites.push(format!("patch {p} piece {k}: {e}"));
                    }
                    frames_p.push(None);
                    pieces.push(OffsetPiece { patch: p, piece: k, pn: None, singular: Some(e) });
                }
            }
        }
        piece_frame.push(frames_p);
    }

    // 5. Dense samples: own evaluation of every slot, then one value per shared sample (the
    // root's).
    let r = options.resolution.max(1) + 1;
    let rl = (r - 1) as f64;
    let sample_slots = Slots::new(surface, r);
    let stotal = *sample_slots.offsets.last().unwrap_or(&0);
    let mut surf = vec![DVec3::ZERO; stotal];
    let mut offs = vec![DVec3::ZERO; stotal];
    let mut nrm = vec![DVec3::ZERO; stotal];
    let mut pn_ok = vec![false; stotal];
    let mut frame_of = vec![usize::MAX; stotal];
    let h = 1e-4;
    // Per piece in parallel (each patch's pieces in one task), merged in piece order below: the
    // same arrays and report as a serial loop.
    let first_piece: Vec<usize> = surface
        .patches
        .iter()
        .scan(0usize, |acc, pt| {
            let at = *acc;
            *acc += pt.sides();
            Some(at)
        })
        .collect();
    let per_patch = per_grid_point(surface, &domains, r, |p, patch, dom, k, i, j| {
        let piece = &pieces[first_piece[p] + k];
        let (s, t) = (i as f64 / rl, j as f64 / rl);
        let mut o = DenseSample { id: sample_slots.id(p, k, i, j), patch: p, piece: k, s, t, frame: usize::MAX, ..Default::default() };
        let (uv, _, _) = piece_point(dom, k, s, t);
        let sd = patch.eval_derivs(uv, form);
        let gb_n = sd.su.cross(sd.sv).normalize_or_zero();
        let mut done = false;
        if let Some(pn) = &piece.pn {
            if let Ok(e) = pn.eval_global(s * gl, t * gl) {
                o.surf = e.point;
                o.offs = e.offset(d);
                o.normal = e.normal;
                o.pn_ok = true;
                o.frame = piece_frame[p][k].unwrap_or(usize::MAX);
                done = true;
                o.fit_error = (e.point - sd.p).length();
                // Residuals by fourth-order central differences inside one Coons
                // cell (x is only G1 across cells, so a stencil must not straddle
                // a cell boundary).
                let (ci, cj) = (((s * gl).floor() as usize).min(g - 2), ((t * gl).floor() as usize).min(g - 2));
                let (uc, vc) = ((s * gl - ci as f64).clamp(2.0 * h, 1.0 - 2.0 * h), (t * gl - cj as f64).clamp(2.0 * h, 1.0 - 2.0 * h));
                let at = |u: f64, v: f64| pn.eval(ci, cj, u, v);
                let diff = |dir: (f64, f64)| -> Option<(DVec3, DVec3)> {
                    let e = |k: f64| at(uc + k * h * dir.0, vc + k * h * dir.1).ok();
                    let (m2, m1, p1, p2) = (e(-2.0)?, e(-1.0)?, e(1.0)?, e(2.0)?);
                    let f = |g: &dyn Fn(&crate::offset::pn::PnSample) -> DVec3| g(&m2) - g(&p2) + (g(&p1) - g(&m1)) * 8.0;
                    Some((f(&|x| x.point), f(&|x| x.offset(d))))
                };
                if let (Ok(c), Some(du_), Some(dv_)) = (at(uc, vc), diff((1.0, 0.0)), diff((0.0, 1.0))) {
                    for (xu, ou) in [du_, dv_] {
                        if xu.length() > 0.0 {
                            o.normal_residual = o.normal_residual.max(c.normal.dot(xu).abs() / xu.length());
                        }
                        if ou.length() > 0.0 && !is_cusp(&sd, d) {
                            o.normal_residual = o.normal_residual.max(c.normal.dot(ou).abs() / ou.length());
                        }
                    }
                    if !is_cusp(&sd, d) {
                        o.offset_error = o.offset_error.max(((c.offset(d) - c.point).length() - d.abs()).abs());
                    }
                }
            }
        }
        if !done {
            o.surf = sd.p;
            o.offs = sd.p + gb_n * d;
            o.normal = gb_n;
        }
        o.cusp = cusp_radius(&sd, d);
        Some(o)
    });
    for o in per_patch {
        surf[o.id] = o.surf;
        offs[o.id] = o.offs;
        nrm[o.id] = o.normal;
        pn_ok[o.id] = o.pn_ok;
        frame_of[o.id] = o.frame;
        report.max_fit_error = report.max_fit_error.max(o.fit_error);
        report.max_normal_residual = report.max_normal_residual.max(o.normal_residual);
        report.max_offset_error = report.max_offset_error.max(o.offset_error);
        if let Some(radius) = o.cusp {
            report.cusps += 1;
            if report.cusp_sites.len() < 10 {
                report.cusp_sites.push(CuspSite { patch: o.patch, piece: o.piece, s: o.s, t: o.t, point: o.offs.to_array(), radius });
            }
        }
    }
    // Gaps and frame seams.
    let mut seam_pairs = std::collections::HashSet::new();
    for id in 0..stotal {
        let root = sample_slots.root(id);
        if root == id {
            continue;
        }
        let gap = (offs[id] - offs[root]).length();
        report.max_gap = report.max_gap.max(gap);
        if pn_ok[id] && pn_ok[root] && frame_of[id] == frame_of[root] {
            report.max_gap_pn = report.max_gap_pn.max(gap);
            let angle = nrm[id].cross(nrm[root]).length().atan2(nrm[id].dot(nrm[root]));
            report.max_normal_angle_pn = report.max_normal_angle_pn.max(angle);
        } else if pn_ok[id] && pn_ok[root] {
            seam_pairs.insert((piece_of(&sample_slots, id), piece_of(&sample_slots, root)));
        }
    }
    report.frame_seams = seam_pairs.len();

    // 6. Welded mesh: one vertex per root.
    let mut index = vec![u32::MAX; stotal];
    let mut base = Vec::new();
    let mut top = Vec::new();
    for id in 0..stotal {
        let root = sample_slots.root(id);
        if index[root] == u32::MAX {
            index[root] = base.len() as u32;
            base.push(surf[root]);
            top.push(offs[root]);
        }
        index[id] = index[root];
    }
    let mut tris = Vec::new();
    for (p, patch) in surface.patches.iter().enumerate() {
        for k in 0..patch.sides() {
            let v = |i: usize, j: usize| index[sample_slots.id(p, k, i, j)];
            for i in 0..r - 1 {
                for j in 0..r - 1 {
                    let (a, b, c, e) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
                    for t in [[a, b, c], [a, c, e]] {
                        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                            tris.push(t);
                        }
                    }
                }
            }
        }
    }
    let (positions, triangles) = if off.shell { shell(&base, &top, &tris, d) } else { (top, tris) };
    let check = crate::quality::check_mesh(&positions, &triangles);
    report.vertices = positions.len();
    report.triangles = triangles.len();
    report.closed = check.is_closed_manifold();
    report.two_manifold = check.is_two_manifold();
    report.seconds = start.elapsed().as_secs_f64();
    Ok(Offset { positions, triangles, pieces, report })
}

/// `f(p, patch, domain, k, i, j)` at every point (i, j) of the m × m grid of every piece k of
/// every patch p with a domain: patches in parallel, the results in patch, piece and grid order
/// (the order of a serial loop), `None`s left out.
fn per_grid_point<T: Send>(
    surface: &Surface,
    domains: &[Option<Domain>],
    m: usize,
    f: impl Fn(usize, &Patch, &Domain, usize, usize, usize) -> Option<T> + Sync,
) -> Vec<T> {
    let per_patch: Vec<Vec<T>> = surface
        .patches
        .par_iter()
        .enumerate()
        .map(|(p, patch)| {
            let Some(dom) = &domains[p] else { return Vec::new() };
            (0..patch.sides())
                .flat_map(|k| (0..m).flat_map(move |i| (0..m).map(move |j| (k, i, j))))
                .filter_map(|(k, i, j)| f(p, patch, dom, k, i, j))
                .collect()
        })
        .collect();
    per_patch.into_iter().flatten().collect()
}

/// One dense sample of step 5 of [`offset_surface`], before it is merged into the arrays and
/// the report.
#[derive(Clone, Copy, Default)]
struct DenseSample {
    id: usize,
    patch: usize,
    piece: usize,
    s: f64,
    t: f64,
    surf: DVec3,
    offs: DVec3,
    /// Unit normal of the evaluation (the PN piece's, or the GB surface's for a singular piece).
    normal: DVec3,
    pn_ok: bool,
    frame: usize,
    fit_error: f64,
    normal_residual: f64,
    offset_error: f64,
    cusp: Option<f64>,
}

fn piece_of(s: &Slots, id: usize) -> (usize, usize) {
    let p = s.offsets.partition_point(|&o| o <= id) - 1;
    (p, (id - s.offsets[p]) / (s.m * s.m))
}

/// The smallest radius of curvature on the side the offset moves to, where it is ≤ |d|
/// (a cusp): with this crate's convention (an outward sphere has κ = −1/R), the offset
/// x + d·n degenerates where 1 − d·κ_i = 0, i.e. d·κ_i ≥ 1 marks a cusp.
fn cusp_radius(sd: &SurfaceDerivs, d: f64) -> Option<f64> {
    let c = sd.curvature()?;
    let worst = (d * c.k1).max(d * c.k2);
    (worst >= 1.0).then(|| d.abs() / worst)
}

fn is_cusp(sd: &SurfaceDerivs, d: f64) -> bool {
    cusp_radius(sd, d).is_some()
}

/// A closed solid from the surface (`base`) and the offset (`top`) sampled on one welded
/// triangulation: the outer sheet as is, the inner one reversed, and side walls along the
/// boundary edges (edges used by one triangle).
fn shell(base: &[DVec3], top: &[DVec3], tris: &[[u32; 3]], d: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let (outer, inner) = if d > 0.0 { (top, base) } else { (base, top) };
    let nv = outer.len() as u32;
    let mut positions = outer.to_vec();
    positions.extend_from_slice(inner);
    let mut out: Vec<[u32; 3]> = tris.to_vec();
    out.extend(tris.iter().map(|t| [t[0] + nv, t[2] + nv, t[1] + nv]));
    let mut count: HashMap<(u32, u32), usize> = HashMap::new();
    for t in tris {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    for t in tris {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            if count[&(a.min(b), a.max(b))] == 1 {
                out.push([b, a, a + nv]);
                out.push([b, a + nv, b + nv]);
            }
        }
    }
    (positions, out)
}

/// The PN surface of piece `k` of patch `p` (step 4 of [`offset_surface`]) and the index of its
/// isotropic frame, or why the piece is offset as a singular piece.
#[allow(clippy::too_many_arguments)]
fn fit_piece(
    surface: &Surface,
    domains: &[Option<Domain>],
    grid_slots: &Slots,
    raw: &[Raw],
    shared_nu: &[DVec3],
    shared_nv: &[DVec3],
    fr: &[IsotropicFrame; 2],
    form: crate::gb::WeightForm,
    g: usize,
    p: usize,
    k: usize,
) -> Result<(PnSurface, usize), String> {
    let patch = &surface.patches[p];
    let gl = (g - 1) as f64;
    let at = |i: usize, j: usize| grid_slots.id(p, k, i, j);
    let mut pts = vec![vec![DVec3::ZERO; g]; g];
    let mut nrm = vec![vec![DVec3::ZERO; g]; g];
    for i in 0..g {
        for j in 0..g {
            let r = raw[grid_slots.root(at(i, j))];
            if !r.ok {
                return Err(format!("degenerate normal at grid [{i}][{j}]"));
            }
            pts[i][j] = r.x;
            nrm[i][j] = r.n;
        }
    }
    let which = usize::from(nrm.iter().flatten().any(|n| n.z > 0.5));
    let frame = fr[which];
    let grid = PnGrid::new(&pts, &nrm).map_err(|e| e.to_string())?;
    let mut du = vec![vec![DVec3::ZERO; g]; g];
    let mut dv = vec![vec![DVec3::ZERO; g]; g];
    for i in 0..g {
        for j in 0..g {
            let id = at(i, j);
            let (x, n) = (grid.point(i, j), grid.normal(i, j));
            du[i][j] = frame.isotropic_tangent(x, n, shared_nu[id]).ok_or("normal at the pole")?;
            dv[i][j] = frame.isotropic_tangent(x, n, shared_nv[id]).ok_or("normal at the pole")?;
        }
    }
    let s = PnSurface::from_derivatives(&grid, frame, &du, &dv).map_err(|e| e.to_string())?;
    // Corners of one sign do not exclude J = 0 inside: only certified pieces are used.
    s.certify_regular().map_err(|e| e.to_string())?;
    // A certified fit can still stray from the GB surface (a 25 × 16 torus, topology,
    // resolution 2 gave a fit error of 4.34 against a tube radius of 3): compare with
    // the GB surface at the grid points, the cells' edge midpoints and centres and
    // refuse the fit beyond
    // FIT_REJECT times the size of the piece's grid.
    if let Some(dom) = &domains[p] {
        let (lo, hi) = pts.iter().flatten().fold((pts[0][0], pts[0][0]), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        let size = lo.distance(hi);
        for ci in 0..2 * g - 1 {
            for cj in 0..2 * g - 1 {
                let (a, b) = (ci as f64 / 2.0, cj as f64 / 2.0);
                let pn = s.eval_global(a, b).map_err(|e| e.to_string())?.point;
                let (uv, _, _) = piece_point(dom, k, a / gl, b / gl);
                let dist = pn.distance(patch.eval_derivs(uv, form).p);
                if !(dist <= FIT_REJECT * size) {
                    return Err(format!(
                        "the fit strays {dist:.3e} from the GB surface at grid parameter ({a}, {b}) (piece size {size:.3e})"
                    ));
                }
            }
        }
    }
    Ok((s, which))
}
