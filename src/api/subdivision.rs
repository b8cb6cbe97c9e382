//! Face ancestry of the subdivision methods (Doo–Sabin, Catmull–Clark) for the pipeline.

use super::{ConvertError, ConvertOptions, Method};
use crate::mesh::PolyMesh;
use crate::progress::Ticker;
use crate::subdiv::SubdivError;
use crate::tessellate::SurfaceMesh;

/// Ends of the shares of [`subdivision_mesh`]'s range: subdivision, convex split, triangulation,
/// normals (then the curvatures), measured on a 50k-face UV sphere at 2 levels.
const SHARES: [f32; 4] = [0.6, 0.7, 0.8, 0.85];

/// Subdivision methods: `levels` steps of the scheme, tracking for every face the input face it
/// descends from (Catmull–Clark: the children of a face are consecutive, one per corner;
/// Doo–Sabin: every new point belongs to one corner of an old face, and a new face descends from
/// the face of its first such point — see [`crate::subdiv::doo_sabin`]'s output order). The result
/// is split into convex pieces ([`crate::mesh::geometry::convexify`]) and fan-triangulated.
/// Normals: area-weighted; curvatures: [`crate::quality::discrete_curvature`]; G1 deviation 0;
/// patch index (per vertex: the smallest over its triangles) = input face, as the user wrote it:
/// `input_face` maps a face of `mesh` to it (the pieces of a face with holes to that face,
/// [`crate::mesh::HalfEdgeMesh::input_face`]).
/// Progress goes to `ticker` (its current range; shares in [`SHARES`]).
pub(super) fn subdivision_mesh(
    mesh: &PolyMesh,
    input_face: &dyn Fn(u32) -> u32,
    options: &ConvertOptions,
    ticker: &mut Ticker<'_>,
) -> Result<(SurfaceMesh, Vec<Vec<u32>>), ConvertError> {
    let [s_subdivided, s_convex, s_triangulated, s_normals] = SHARES;
    use crate::subdiv::{subdivide_ticked, Subdivided, SubdivisionScheme};
    let scheme = match options.method {
        Method::CatmullClark => SubdivisionScheme::CatmullClark,
        Method::DooSabin => SubdivisionScheme::DooSabin,
        m @ (Method::Dual | Method::Topology) => {
            return Err(ConvertError::Subdiv(format!("{m} is not a subdivision method")));
        }
    };
    let Subdivided { mesh: current, face_ancestor: ancestor } =
        ticker.within(0.0, s_subdivided, |t| subdivide_ticked(mesh, scheme, options.levels, t)).map_err(|e| match e {
            SubdivError::Cancelled => ConvertError::Cancelled,
            e => ConvertError::Subdiv(e.to_string()),
        })?;
    let (convex, piece_face) = ticker.within(s_subdivided, s_convex, |t| crate::mesh::geometry::convexify_ticked(&current, t))?;
    let nv = current.positions.len();
    let oom = |what: &'static str, bytes: usize| ConvertError::OutOfMemory { what, bytes: bytes as u64 };
    let nt: usize = convex.faces.iter().map(|f| f.len().saturating_sub(2)).sum();
    let mut out = SurfaceMesh::default();
    out.positions.try_reserve_exact(nv).map_err(|_| oom("output positions", nv * 24))?;
    out.positions.extend_from_slice(&current.positions);
    out.triangles.try_reserve_exact(nt).map_err(|_| oom("output triangles", nt * 12))?;
    out.triangle_patch.try_reserve_exact(nt).map_err(|_| oom("output triangle patches", nt * 4))?;
    out.cage_corner.try_reserve_exact(nt).map_err(|_| oom("output cage corners", nt * 8))?;
    out.patch.try_reserve_exact(nv).map_err(|_| oom("output patch indices", nv * 4))?;
    out.patch.resize(nv, u32::MAX);
    out.fold.try_reserve_exact(nv).map_err(|_| oom("output fold flags", nv))?;
    out.fold.resize(nv, 0);
    let nf = convex.faces.len();
    for (k, f) in convex.faces.iter().enumerate() {
        ticker.at_part(s_convex, s_triangulated, k, nf)?;
        let anc = input_face(piece_face.get(k).and_then(|&f| ancestor.get(f as usize)).copied().unwrap_or(0));
        for i in 1..f.len().saturating_sub(1) {
            out.triangles.push([f[0], f[i], f[i + 1]]);
            out.triangle_patch.push(anc);
            out.cage_corner.push([anc, u32::MAX]);
        }
        for &v in f {
            let slot = &mut out.patch[v as usize];
            *slot = (*slot).min(anc);
        }
    }
    for p in &mut out.patch {
        if *p == u32::MAX {
            *p = 0;
        }
    }
    ticker.at_part(0.0, s_triangulated, 1, 1)?;
    out.normals = crate::mesh::geometry::vertex_normals(&out.positions, &out.triangles);
    let (h, k) = ticker.within(s_normals, 1.0, |t| crate::quality::discrete_curvature_ticked(&out.positions, &out.triangles, &out.normals, t))?;
    out.mean_curvature = h;
    out.gaussian_curvature = k;
    out.g1_deviation_deg = vec![0.0; nv];
    Ok((out, current.faces))
}
