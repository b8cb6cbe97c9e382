//! Faces with holes from OBJ (`#h N`, molihua's convention) through the command line: a holed slab
//! converts to a closed G1 surface, a bad inner loop is a one-line error naming its OBJ line.

mod common;
use common::{fails_in, run_in};

/// A slab over [-2, 2]² with the square hole [-1, 1]² through it: top and bottom faces carry
/// one inner loop each (`#h 1` and the loop in the opposite orientation).
const RING: &str = "\
v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\nv -2 -2 1\nv 2 -2 1\nv 2 2 1\nv -2 2 1
v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1
f 5 6 7 8
#h 1
f 16 15 14 13
f 4 3 2 1
#h 1
f 9 10 11 12
f 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8
f 10 9 13 14\nf 11 10 14 15\nf 12 11 15 16\nf 9 12 16 13
";

fn tmpdir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("gbsurf-cli-holes-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn holed_obj_converts_to_a_closed_g1_surface() {
    let dir = tmpdir("ok");
    std::fs::write(dir.join("ring.obj"), RING).unwrap();
    for method in ["dual", "topology"] {
        let out = run_in(&dir, &["convert", "ring.obj", "-o", "out.ply", "--report", "r.json", "--method", method, "--quiet"]);
        assert!(out.status.success(), "{method}: {}", String::from_utf8_lossy(&out.stderr));
        let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("r.json")).unwrap()).unwrap();
        assert_eq!(r["closed"], true, "{method}: {r}");
        assert_eq!(r["valid"], true, "{method}: {r}");
        assert!(r["max_g1_deg"].as_f64().unwrap() <= 1e-4, "{method}: {r}");
        // 10 input faces; the two ring faces become four trapezoids each
        assert_eq!(r["input_faces"], 10, "{method}: {r}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_inner_loop_names_its_obj_line() {
    let dir = tmpdir("bad");
    // the top face's inner loop in the outer loop's orientation (line 19)
    std::fs::write(dir.join("same.obj"), RING.replace("f 16 15 14 13", "f 13 14 15 16")).unwrap();
    fails_in(&dir, &["convert", "same.obj", "-o", "out.ply", "--quiet"], &["hole 0 of face 0", "line 19", "orientation"]);
    // `#h 2` with one loop following
    std::fs::write(dir.join("short.obj"), RING.replacen("#h 1", "#h 2", 1).replacen("f 4 3 2 1\n", "", 1)).unwrap();
    fails_in(&dir, &["convert", "short.obj", "-o", "out.ply", "--quiet"], &["line 18", "#h 2"]);
    assert!(!dir.join("out.ply").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
