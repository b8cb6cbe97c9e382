//! The exact description of a surface: JSON with every patch's control points, and `.gbp` files
//! for the GB patches that have one.

use crate::construct::{Patch, Surface};
use std::path::{Path, PathBuf};

/// The exact description of a surface as JSON: for every patch its index, `type` (`gb`/`cgb`),
/// `n`, `degree` (per ribbon), the control-mesh element it stands for, its neighbours (per
/// side: `{patch, side}` or null) and its control points (`ribbons[i].rows[k][j]` as [x, y, z];
/// `center` for GB patches), plus the curve network. `gbp_files[p]` (if given) names the `.gbp`
/// file written for patch p.
pub fn patches_json(surface: &Surface, gbp_files: &[Option<String>]) -> serde_json::Value {
    use serde_json::json;
    let pt = |p: &glam::DVec3| json!([p.x, p.y, p.z]);
    let patches: Vec<serde_json::Value> = surface
        .patches
        .iter()
        .enumerate()
        .map(|(i, patch)| {
            let rbs = patch.ribbons();
            let ribbons_json: Vec<serde_json::Value> = rbs
                .iter()
                .map(|r| json!({"degree": r.degree, "rows": r.rows().map(|row| row.iter().map(pt).collect::<Vec<_>>()).collect::<Vec<_>>()}))
                .collect();
            let (kind, center) = match patch {
                Patch::Gb(g) => ("gb", Some(pt(&g.center))),
                Patch::Cgb(_) => ("cgb", None),
            };
            let degree: Vec<usize> = rbs.iter().map(|r| r.degree).collect();
            let mut v = json!({
                "index": i,
                "type": kind,
                "n": rbs.len(),
                "degree": degree,
                "source": surface.sources.get(i),
                "neighbors": surface.neighbors.get(i),
                "ribbons": ribbons_json,
            });
            if let Some(c) = center {
                v["center"] = c;
            }
            if let Some(Some(f)) = gbp_files.get(i) {
                v["gbp"] = json!(f);
            }
            v
        })
        .collect();
    let curves: Vec<serde_json::Value> = surface.curves.iter().map(|c| json!(c.iter().map(pt).collect::<Vec<_>>())).collect();
    json!({"format": "gbsurf-surface", "version": 1, "patches": patches, "curves": curves})
}

/// The `.gbp` text of every GB patch that has one (a connected net, see [`crate::gb::gbp`]);
/// `None` for CGB patches and for GB patches whose corner blocks are independent (direction-blend
/// twists), which only the JSON describes exactly.
///
/// A patch above [`crate::limits::MAX_GBP_DEGREE`] has no `.gbp` text either (the format's bound).
pub fn gbp_texts(surface: &Surface) -> Vec<Option<String>> {
    surface
        .patches
        .iter()
        .map(|p| match p {
            Patch::Gb(g) => crate::gb::gbp::to_gbp_string(g).ok(),
            Patch::Cgb(_) => None,
        })
        .collect()
}

/// The files of the exact description for the JSON file `json_path`: the `.gbp` files
/// ([`gbp_texts`]) beside it, named `<stem>_<patch:05>.gbp`, then the JSON ([`patches_json`],
/// pretty-printed) naming them.
pub fn patch_files(surface: &Surface, json_path: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let stem = json_path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "patches".into());
    let dir = json_path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut files = Vec::new();
    let names: Vec<Option<String>> = gbp_texts(surface)
        .into_iter()
        .enumerate()
        .map(|(i, t)| {
            t.map(|text| {
                let name = format!("{stem}_{i:05}.gbp");
                files.push((dir.join(&name), text.into_bytes()));
                name
            })
        })
        .collect();
    let json = patches_json(surface, &names);
    files.push((json_path.to_path_buf(), format!("{json:#}").into_bytes()));
    files
}
