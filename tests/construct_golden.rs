//! Bit-identity guard for performance work: FNV-1a hashes of the half-edge numbering and of the
//! dual / topology-preserving surfaces (serialized with serde_json, which prints every f64 with
//! round-trip precision) of a 20×20 torus, recorded before the parallel assembly and the faster
//! validation hash maps. Any change of patch order, half-edge numbering or a single bit of a
//! control point changes a hash.

use gbsurf::construct::{build_dual, build_topology};
use gbsurf::ConvertOptions;
use gbsurf::mesh::generate::torus;
use gbsurf::mesh::halfedge::HalfEdgeMesh;

fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3))
}

fn mesh() -> HalfEdgeMesh {
    HalfEdgeMesh::from_polymesh(&torus(20, 20, 3.0, 1.0).unwrap()).unwrap()
}

#[test]
fn halfedge_numbering_golden() {
    let m = mesh();
    let mut s = String::new();
    for h in m.halfedges() {
        s.push_str(&format!("{} {} {} {:?};", m.origin(h).0, m.next(h).0, m.prev(h).0, m.face(h).map(|f| f.0)));
    }
    for v in m.vertices() {
        s.push_str(&format!("{};", m.vertex_halfedge(v).0));
    }
    for f in m.faces() {
        s.push_str(&format!("{};", m.face_halfedge(f).0));
    }
    assert_eq!(fnv(s.as_bytes()), GOLDEN_HE, "hash {:#x}", fnv(s.as_bytes()));
}

#[test]
fn dual_surface_golden() {
    let s = build_dual(&mesh(), &ConvertOptions::triangles_r8()).unwrap();
    let h = fnv(serde_json::to_string(&s).unwrap().as_bytes());
    assert_eq!(h, GOLDEN_DUAL, "hash {h:#x}");
}

#[test]
fn topology_surface_golden() {
    let s = build_topology(&mesh(), &ConvertOptions::triangles_r8()).unwrap();
    let h = fnv(serde_json::to_string(&s).unwrap().as_bytes());
    assert_eq!(h, GOLDEN_TOPO, "hash {h:#x}");
}

const GOLDEN_HE: u64 = 0x88e0cdc0c0a2a56c;
const GOLDEN_DUAL: u64 = 0x130d41cafe24d52;
const GOLDEN_TOPO: u64 = 0x2f656f4290b5d152;
