//! Patches where the fold rule and the reference sampler disagree: `cargo run --release --example
//! fold_disagree -- CAGE.obj...`. For every patch the dense rule (level 16) flags or the reference
//! sampler (`common/fine.rs`, 60 steps) sees flip: folded samples at levels 16 and 40, the
//! sampler's smallest neighbour dot at 60 and 120 steps, min/max |S_u × S_v|.

#[path = "common/fine.rs"]
mod fine;

use gbsurf::tessellate::fold::dense_folds;

use rayon::prelude::*;

fn main() {
    fine::for_each_surface(|name, method, o, s| {
        let rows: Vec<String> = s
            .patches
            .par_iter()
            .enumerate()
            .filter_map(|(p, patch)| {
                let r16 = dense_folds(patch, 16, o.weights).0;
                let f60 = fine::neighbour_normals(patch, o.weights, 60);
                if r16 == 0 && f60.0 >= 0.0 {
                    return None;
                }
                let r40 = dense_folds(patch, 40, o.weights).0;
                let f120 = fine::neighbour_normals(patch, o.weights, 120);
                let tag = match (r16 > 0, f60.0 < 0.0) {
                    (true, true) => "both",
                    (true, false) => "RULE ONLY",
                    _ => "SAMPLER ONLY",
                };
                Some(format!(
                    "   p{p} ({:?}, {} sides) {tag}: rule@16 {r16} rule@40 {r40} dot@60 {:.3} at {:?} dot@120 {:.3} at {:?} min/max J {:.1e}",
                    s.sources[p], patch.sides(), f60.0, f60.1, f120.0, f120.1, f120.2
                ))
            })
            .collect();
        println!("{name} {}:", method.name());
        for r in rows.iter().filter(|r| !r.contains("both")) {
            println!("{r}");
        }
        println!("   agree on {}", rows.iter().filter(|r| r.contains("both")).count());
    });
}
