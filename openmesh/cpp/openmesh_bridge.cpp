// C++ side of the gbsurf <-> OpenMesh cxx bridge; see openmesh_bridge.h.
// MeshIO must be included before the mesh kernel so that all readers/writers are registered.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>

#include <stdexcept>
#include <string>
#include <vector>

#include "gbsurf-openmesh/cpp/openmesh_bridge.h"
#include "gbsurf-openmesh/src/lib.rs.h"

namespace gbsurf_om {

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits> Mesh;

// Builds an OpenMesh mesh; throws naming the first face OpenMesh cannot insert.
void to_openmesh(const MeshData &data, Mesh &mesh) {
  if (data.positions.size() % 3 != 0) {
    throw std::runtime_error("positions length is not a multiple of 3");
  }
  const size_t nv = data.positions.size() / 3;
  const bool with_normals = data.normals.size() == data.positions.size() && nv > 0;
  if (with_normals) mesh.request_vertex_normals();
  std::vector<Mesh::VertexHandle> vh(nv);
  for (size_t i = 0; i < nv; ++i) {
    vh[i] = mesh.add_vertex(Mesh::Point(data.positions[3 * i], data.positions[3 * i + 1],
                                        data.positions[3 * i + 2]));
    if (with_normals) {
      mesh.set_normal(vh[i], Mesh::Normal(data.normals[3 * i], data.normals[3 * i + 1],
                                          data.normals[3 * i + 2]));
    }
  }
  size_t offset = 0;
  std::vector<Mesh::VertexHandle> face;
  for (size_t f = 0; f < data.face_sizes.size(); ++f) {
    const size_t k = data.face_sizes[f];
    if (k < 3) throw std::runtime_error("face " + std::to_string(f) + " has fewer than 3 vertices");
    if (offset + k > data.face_indices.size()) {
      throw std::runtime_error("face " + std::to_string(f) + " runs past the index array");
    }
    face.clear();
    for (size_t j = 0; j < k; ++j) {
      const uint32_t v = data.face_indices[offset + j];
      if (v >= nv) {
        throw std::runtime_error("face " + std::to_string(f) + " refers to vertex " +
                                 std::to_string(v) + " of " + std::to_string(nv));
      }
      face.push_back(vh[v]);
    }
    offset += k;
    if (!mesh.add_face(face).is_valid()) {
      throw std::runtime_error("OpenMesh cannot insert face " + std::to_string(f) +
                               " (non-manifold edge or vertex, or inconsistent orientation)");
    }
  }
}

// Vertices in handle order; each face as the from-vertices of its halfedge loop. add_face stores
// the closing halfedge (v[n-1] -> v[0]) as the face's halfedge, so starting at its successor
// gives back an inserted face's own loop, not a rotation of it.
MeshData from_openmesh(const Mesh &mesh) {
  MeshData out;
  out.positions.reserve(3 * mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const Mesh::Point &p = mesh.point(v);
    out.positions.push_back(p[0]);
    out.positions.push_back(p[1]);
    out.positions.push_back(p[2]);
  }
  for (auto f : mesh.faces()) {
    uint32_t k = 0;
    const auto start = mesh.next_halfedge_handle(mesh.halfedge_handle(f));
    auto h = start;
    do {
      out.face_indices.push_back(static_cast<uint32_t>(mesh.from_vertex_handle(h).idx()));
      ++k;
      h = mesh.next_halfedge_handle(h);
    } while (h != start);
    out.face_sizes.push_back(k);
  }
  return out;
}

}  // namespace

MeshData read_mesh(rust::Str path) {
  const std::string file(path);
  Mesh mesh;
  OpenMesh::IO::Options opt;
  if (!OpenMesh::IO::read_mesh(mesh, file, opt)) {
    throw std::runtime_error("OpenMesh could not read '" + file + "'");
  }
  return from_openmesh(mesh);
}

void write_mesh(const MeshData &data, rust::Str path, bool binary, unsigned int precision) {
  const std::string file(path);
  Mesh mesh;
  to_openmesh(data, mesh);
  OpenMesh::IO::Options opt;
  if (binary) opt += OpenMesh::IO::Options::Binary;
  if (mesh.has_vertex_normals()) opt += OpenMesh::IO::Options::VertexNormal;
  if (!OpenMesh::IO::write_mesh(mesh, file, opt, precision)) {
    throw std::runtime_error("OpenMesh could not write '" + file + "'");
  }
}

MeshData catmull_clark(const MeshData &data, unsigned int levels) {
  Mesh mesh;
  to_openmesh(data, mesh);
  if (levels > 0) {
    OpenMesh::Subdivider::Uniform::CatmullClarkT<Mesh, double> cc;
    cc.attach(mesh);
    const bool ok = cc(levels);
    cc.detach();
    if (!ok) throw std::runtime_error("OpenMesh's Catmull-Clark subdivider failed");
  }
  return from_openmesh(mesh);
}

}  // namespace gbsurf_om
