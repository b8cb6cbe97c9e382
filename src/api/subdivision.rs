//! Face ancestry of the subdivision methods (Doo–Sabin, Catmull–Clark) for the pipeline.

use super::{ConvertError, ConvertOptions, Method};
use crate::mesh::PolyMesh;
use crate::tessellate::SurfaceMesh;

/// Subdivision methods: `levels` steps of the scheme, tracking for every face the input face it
/// descends from (Catmull–Clark: the children of a face are consecutive, one per corner;
/// Doo–Sabin: every new point belongs to one corner of an old face, and a new face descends from
/// the face of its first such point — see [`crate::subdiv::doo_sabin`]'s output order). The result
/// is split into convex pieces ([`crate::mesh::geometry::convexify`]) and fan-triangulated.
/// Normals: area-weighted; curvatures: [`crate::quality::discrete_curvature`]; G1 deviation 0;
/// patch index (per vertex: the smallest over its triangles) = input face.
pub(super) fn subdivision_mesh(mesh: &PolyMesh, options: &ConvertOptions) -> Result<(SurfaceMesh, Vec<Vec<u32>>), ConvertError> {
    let sub_err = |e: crate::subdiv::SubdivError| ConvertError::Subdiv(e.to_string());
    let mut current = mesh.clone();
    let mut ancestor: Vec<u32> = (0..mesh.faces.len() as u32).collect();
    if options.levels == 0 {
        crate::subdiv::catmull_clark(&current, 0).map_err(sub_err)?;
    }
    for _ in 0..options.levels {
        let next = match options.method {
            Method::CatmullClark => {
                let next = crate::subdiv::catmull_clark(&current, 1).map_err(sub_err)?;
                let mut anc = Vec::with_capacity(next.faces.len());
                for (f, face) in current.faces.iter().enumerate() {
                    anc.extend(std::iter::repeat(ancestor[f]).take(face.len()));
                }
                ancestor = anc;
                next
            }
            _ => {
                let next = crate::subdiv::doo_sabin(&current, 1).map_err(sub_err)?;
                // Corner c of old face f is new vertex c (faces in order, corners in order).
                let mut corner_face = Vec::new();
                for (f, face) in current.faces.iter().enumerate() {
                    corner_face.extend(std::iter::repeat(f as u32).take(face.len()));
                }
                ancestor = next
                    .faces
                    .iter()
                    .map(|face| {
                        let c = face.iter().find(|&&v| (v as usize) < corner_face.len()).copied().unwrap_or(0);
                        ancestor[corner_face.get(c as usize).copied().unwrap_or(0) as usize]
                    })
                    .collect();
                next
            }
        };
        if ancestor.len() != next.faces.len() {
            return Err(ConvertError::Subdiv(format!(
                "face ancestry mismatch after subdivision: {} faces, {} ancestors",
                next.faces.len(),
                ancestor.len()
            )));
        }
        current = next;
    }
    let (convex, piece_face) = crate::mesh::geometry::convexify(&current);
    let nv = current.positions.len();
    let mut out = SurfaceMesh { positions: current.positions.clone(), ..Default::default() };
    out.patch = vec![u32::MAX; nv];
    for (k, f) in convex.faces.iter().enumerate() {
        let anc = piece_face.get(k).and_then(|&f| ancestor.get(f as usize)).copied().unwrap_or(0);
        for i in 1..f.len().saturating_sub(1) {
            out.triangles.push([f[0], f[i], f[i + 1]]);
            out.triangle_patch.push(anc);
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
    out.normals = crate::quality::vertex_normals(&out.positions, &out.triangles);
    let (h, k) = crate::quality::discrete_curvature(&out.positions, &out.triangles, &out.normals);
    out.mean_curvature = h;
    out.gaussian_curvature = k;
    out.g1_deviation_deg = vec![0.0; nv];
    Ok((out, current.faces))
}
