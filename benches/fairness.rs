//! Fairness benchmark (`scripts/bench_fairness`, or `cargo bench --bench fairness`): how round,
//! fair and valid the GB surfaces are next to Catmull–Clark on the same cages. Prints markdown
//! tables; the goals are printed next to the numbers, never asserted.
//!
//! 1. Sphere cages: Blender's UV sphere (32 segments × 16 rings, [`uv_sphere`]), an ico sphere
//!    (icosahedron, each triangle split into 4 twice, projected to the unit sphere) and a quad
//!    sphere (a cube of 4 × 4 faces per side projected to the unit sphere). Per structure
//!    (dual, topology; quads at r = 8) and for Catmull–Clark level 4 (the same quad count on a
//!    closed cage: r = 2^(L−1)): the largest radial deviation |r/R − 1| over the output vertices,
//!    the sphere being centred at the origin (the cages are symmetric about it) with R the mean
//!    distance of the output vertices from it; and the largest |H·R + 1| (H the per-vertex mean
//!    curvature of the report: analytic for GB, discrete for Catmull–Clark; a sphere has
//!    H = −1/R, docs/math.md §1.9). Goals: GB radial deviation ≤ CC's, |H·R + 1| ≤ 0.25.
//! 2. Every good model of `../shared/models` and every public cage of `tests/data/opensubdiv`:
//!    per structure at the default (quads, r = 2): folds, output and input self-intersections,
//!    valid, max |H|·diagonal, and the p99 and largest dihedral angle (degrees) between the
//!    normals of two output triangles sharing an edge (quads count as their two triangles), next
//!    to Catmull–Clark level 2 (the same quad count on closed cages). Goals: zero folds and no
//!    self-intersections beyond the input's. Cages the reader or validator refuses get a row
//!    with the error.
//!
//! `-- --quick` skips the spheres' r = 8 and CC level 4 (uses r = 4, level 3). `-- --middle fair`
//! builds the GB rows with the fair middle constraint ([`Middle::Fair`], docs/math.md#fair-middle).

use gbsurf::api::{convert, read_mesh, Conversion, ConvertOptions, Method};
use gbsurf::Middle;
use gbsurf::mesh::generate::{ico_sphere, quad_sphere, uv_sphere};
use gbsurf::mesh::PolyMesh;
use glam::DVec3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

fn main() {
    let start = Instant::now();
    let quick = std::env::args().any(|a| a == "--quick");
    let (r, level) = if quick { (4, 3) } else { (8, 4) };
    let args: Vec<String> = std::env::args().collect();
    let middle =
        args.iter().position(|a| a == "--middle").and_then(|i| args.get(i + 1)?.parse().ok()).unwrap_or_default();
    println!("GB middle constraint: {middle}\n");
    spheres(r, level, middle);
    cages(middle);
    println!("\ntotal {:.1} s", start.elapsed().as_secs_f64());
}

// ---------------------------------------------------------------- spheres

fn spheres(r: usize, level: u32, middle: Middle) {
    println!("## Sphere cages (GB quads r = {r}, Catmull–Clark level {level})\n");
    println!("Sphere: centre at the origin, R = mean distance of the output vertices from it.");
    println!("Goals: GB radial deviation ≤ CC's; max |H·R + 1| ≤ 0.25 (H analytic for GB, discrete for CC).\n");
    println!("| cage | faces | structure | vertices | max \\|r/R − 1\\| | median H·R | \\|H·R + 1\\| p99 / max | CC vertices | CC max \\|r/R − 1\\| | CC median H·R | CC \\|H·R + 1\\| p99 / max | dev ≤ CC | max \\|HR+1\\| ≤ 0.25 |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let cages: Vec<(&str, PolyMesh)> = vec![
        ("uv sphere 32×16", uv_sphere(32, 16).expect("uv sphere")),
        ("ico sphere (2 splits)", ico_sphere(2)),
        ("quad sphere 4×4", quad_sphere(4)),
    ];
    for (name, cage) in &cages {
        let cc = convert(cage, &ConvertOptions { method: Method::CatmullClark, levels: level, ..Default::default() }, None);
        let cc_fit = cc.as_ref().ok().map(|c| sphere_fit(&c.mesh.positions, &c.mesh.mean_curvature));
        for method in [Method::Dual, Method::Topology] {
            let opts = ConvertOptions { method, resolution: r, middle, ..Default::default() };
            match convert(cage, &opts, None) {
                Ok(c) => {
                    let (dev, med, h) = sphere_fit(&c.mesh.positions, &c.mesh.mean_curvature);
                    let (cc_n, cc_dev, cc_med, cc_h) = match (&cc, cc_fit) {
                        (Ok(cc), Some((d, m, h))) => (cc.mesh.positions.len().to_string(), d, m, h),
                        _ => ("error".into(), f64::NAN, f64::NAN, (f64::NAN, f64::NAN)),
                    };
                    println!(
                        "| {name} | {} | {} | {} | {dev:.2e} | {med:.3} | {:.3} / {:.3} | {cc_n} | {cc_dev:.2e} | {cc_med:.3} | {:.3} / {:.3} | {} | {} |",
                        cage.faces.len(),
                        method.name(),
                        c.mesh.positions.len(),
                        h.0,
                        h.1,
                        cc_h.0,
                        cc_h.1,
                        yes(dev <= cc_dev),
                        yes(h.1 <= 0.25)
                    );
                }
                Err(e) => println!("| {name} | {} | {} | error: {e} | | | | | | | | | |", cage.faces.len(), method.name()),
            }
        }
    }
}

/// (max |r/R − 1|, median H·R, (p99, max) of |H·R + 1|) with the centre at the origin and R the
/// mean radius.
fn sphere_fit(positions: &[DVec3], mean_curvature: &[f64]) -> (f64, f64, (f64, f64)) {
    let radius = positions.iter().map(|p| p.length()).sum::<f64>() / positions.len() as f64;
    let dev = positions.iter().map(|p| (p.length() / radius - 1.0).abs()).fold(0.0, f64::max);
    let h = p99_max(mean_curvature.iter().map(|h| (h * radius + 1.0).abs()).collect());
    let mut hr: Vec<f64> = mean_curvature.iter().map(|h| h * radius).collect();
    hr.sort_by(f64::total_cmp);
    (dev, hr[hr.len() / 2], h)
}

/// (p99, max) of `values` (NaN, NaN when empty).
fn p99_max(mut values: Vec<f64>) -> (f64, f64) {
    if values.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    values.sort_by(f64::total_cmp);
    (values[((values.len() - 1) as f64 * 0.99).round() as usize], values[values.len() - 1])
}

// ---------------------------------------------------------------- cages

fn cages(middle: Middle) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    for (label, dir) in [("shared", root.join("../shared/models")), ("opensubdiv", root.join("tests/data/opensubdiv"))] {
        let mut list: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.extension().is_some_and(|x| x == "obj")).collect())
            .unwrap_or_default();
        list.sort();
        for p in list {
            let stem = p.file_stem().unwrap_or_default().to_string_lossy().into_owned();
            files.push((format!("{label}/{stem}"), p));
        }
    }
    println!("\n## Cages (GB quads r = 2 next to Catmull–Clark level 2)\n");
    println!("Dihedral: angle (°) between the normals of two output triangles sharing an edge (quads as two triangles).");
    println!("Self-int: pairs of output / input triangles that meet. Goals: 0 folds, no self-intersections beyond the input's.\n");
    println!("| cage | faces | structure | quads | folds | self-int out/in | valid | max \\|H\\|·diag | dihedral p99 / max | CC quads | CC max \\|H\\|·diag | CC dihedral p99 / max | goals |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (name, path) in files {
        let t = Instant::now();
        let mesh = match read_mesh(&path) {
            Ok(m) => m,
            Err(e) => {
                println!("| {name} | | refused | {} | | | | | | | | | |", one_line(&e.to_string()));
                continue;
            }
        };
        let cc = convert(&mesh, &ConvertOptions { method: Method::CatmullClark, levels: 2, ..Default::default() }, None);
        let (cc_quads, cc_h, cc_dih) = match &cc {
            Ok(c) => {
                let (p99, max) = dihedral(c);
                (c.mesh.triangles.len().div_ceil(2).to_string(), format!("{:.2}", c.report.max_abs_mean_curvature_times_diagonal), format!("{p99:.1} / {max:.1}"))
            }
            Err(e) => (format!("error: {}", one_line(&e.to_string())), String::new(), String::new()),
        };
        for method in [Method::Dual, Method::Topology] {
            match convert(&mesh, &ConvertOptions { method, middle, ..Default::default() }, None) {
                Ok(c) => {
                    let rep = &c.report;
                    let (p99, max) = dihedral(&c);
                    let goals = rep.folds == 0 && rep.self_intersections <= rep.input_self_intersections.unwrap_or(0);
                    println!(
                        "| {name} | {} | {} | {} | {} | {} / {} | {} | {:.2} | {p99:.1} / {max:.1} | {cc_quads} | {cc_h} | {cc_dih} | {} |",
                        mesh.faces.len(),
                        method.name(),
                        rep.quads,
                        rep.folds,
                        rep.self_intersections,
                        rep.input_self_intersections.map_or("not checked".to_string(), |n| n.to_string()),
                        yes(rep.valid),
                        rep.max_abs_mean_curvature_times_diagonal,
                        yes(goals)
                    );
                }
                Err(e) => println!("| {name} | {} | {} | error: {} | | | | | | {cc_quads} | {cc_h} | {cc_dih} | |", mesh.faces.len(), method.name(), one_line(&e.to_string())),
            }
        }
        if t.elapsed().as_secs_f64() > 20.0 {
            eprintln!("{name}: {:.1} s", t.elapsed().as_secs_f64());
        }
    }
}

/// (p99, max) of the dihedral angles (degrees) between the normals of two output triangles that
/// share an edge (edges of exactly two triangles; degenerate triangles skipped).
fn dihedral(c: &Conversion) -> (f64, f64) {
    let (pos, tris) = (&c.mesh.positions, &c.mesh.triangles);
    let normal = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|i| pos[i as usize]);
        (b - a).cross(c - a).try_normalize()
    };
    let normals: Vec<Option<DVec3>> = tris.iter().map(normal).collect();
    let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::with_capacity(tris.len() * 2);
    for (k, t) in tris.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(k);
        }
    }
    p99_max(
        edges
            .values()
            .filter(|f| f.len() == 2)
            .filter_map(|f| Some(normals[f[0]]?.dot(normals[f[1]]?).clamp(-1.0, 1.0).acos().to_degrees()))
            .collect(),
    )
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "**no**"
    }
}

fn one_line(s: &str) -> String {
    let s = s.replace('\n', " ").replace('|', "/");
    if s.chars().count() > 110 {
        format!("{}…", s.chars().take(110).collect::<String>())
    } else {
        s
    }
}
