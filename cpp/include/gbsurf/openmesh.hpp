// gbsurf/openmesh.hpp: OpenMesh adapter of the gbsurf C++ wrapper (header-only; link OpenMeshCore).
//
//   OpenMesh::PolyMesh_ArrayKernelT<> in;  OpenMesh::IO::read_mesh(in, "model.off");
//   gbsurf::openmesh::TriMesh out = gbsurf::openmesh::convert(in, gbsurf::options());
//   double h = out.property(gbsurf::openmesh::mean_curvature(out), vh);
//
// The output TriMesh has double-precision points and vertex normals, and the named vertex
// properties "gbsurf:patch" (int), "gbsurf:mean_curvature", "gbsurf:gaussian_curvature",
// "gbsurf:g1_deviation" (double, degrees). curve_network() and control_nets() give the exact
// description as OpenMesh meshes (vertices = control points, edges = control polygon lines).
//
// Creases: if the input mesh has an edge property "crease" (float or double: sharpness c in
// [0, 1], Blender's crease meaning: 0 smooth, 1 infinitely sharp) and/or a vertex property
// "crease" (corner sharpness, same meaning), found by name with get_property_handle, the
// conversion passes every non-zero value to the creased convert (gbsurf_convert_creased; both
// structures build creases, the subdivision methods ignore them). A value outside [0, 1], NaN or infinite is refused by
// the library's validator (GBSURF_ERR_INVALID_MESH or GBSURF_ERR_NAN) with a message that ends
// with the OpenMesh element, e.g. "(OpenMesh edge 7)". Properties of other types are ignored.
#ifndef GBSURF_OPENMESH_HPP
#define GBSURF_OPENMESH_HPP

#include "../gbsurf.hpp"

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace gbsurf {
namespace openmesh {

/// Traits of the output meshes: double points and normals, vertex normals.
struct Traits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
    VertexAttributes(OpenMesh::Attributes::Normal);
};

/// The output triangle mesh type.
typedef OpenMesh::TriMesh_ArrayKernelT<Traits> TriMesh;
/// The type of the curve network and control net meshes.
typedef OpenMesh::PolyMesh_ArrayKernelT<Traits> PolyMesh;

/// Names of the vertex properties set on the output meshes.
inline const char* patch_property_name() { return "gbsurf:patch"; }
inline const char* mean_curvature_property_name() { return "gbsurf:mean_curvature"; }
inline const char* gaussian_curvature_property_name() { return "gbsurf:gaussian_curvature"; }
inline const char* g1_deviation_property_name() { return "gbsurf:g1_deviation"; }
/// On curve network meshes: the curve index of each vertex.
inline const char* curve_property_name() { return "gbsurf:curve"; }
/// The edge and vertex properties (float or double) read as sharpness by convert_to_result.
inline const char* crease_property_name() { return "crease"; }

namespace detail {
template <class T, class Mesh>
OpenMesh::VPropHandleT<T> vprop(Mesh& mesh, const char* name) {
    OpenMesh::VPropHandleT<T> h;
    if (!mesh.get_property_handle(h, name)) mesh.add_property(h, name);
    return h;
}
template <class T, class Mesh>
OpenMesh::VPropHandleT<T> existing_vprop(const Mesh& mesh, const char* name) {
    OpenMesh::VPropHandleT<T> h;
    if (!mesh.get_property_handle(h, name)) {
        throw error(GBSURF_ERR_KIND, std::string("the mesh has no vertex property ") + name);
    }
    return h;
}

/// The value of property `name` (float or double) of element `h`, through handle type H<T>.
template <template <class> class H, class Mesh>
struct crease_reader {
    H<float> f;
    H<double> d;
    bool has_f = false, has_d = false;
    crease_reader(const Mesh& m, const char* name) {
        has_f = m.get_property_handle(f, name);
        has_d = !has_f && m.get_property_handle(d, name);
    }
    bool present() const { return has_f || has_d; }
    template <class Handle>
    double operator()(const Mesh& m, Handle h) const {
        return has_f ? static_cast<double>(m.property(f, h)) : m.property(d, h);
    }
};

/// The input mesh's "crease" properties as gbsurf::creases (compact vertex numbers `index`),
/// with the OpenMesh edge / vertex index of every entry; false when the mesh has neither.
template <class InMesh>
bool read_creases(const InMesh& in, const std::vector<uint32_t>& index, creases& cr,
                  std::vector<int>& edge_of, std::vector<int>& vertex_of) {
    crease_reader<OpenMesh::EPropHandleT, InMesh> ec(in, crease_property_name());
    crease_reader<OpenMesh::VPropHandleT, InMesh> vc(in, crease_property_name());
    if (!ec.present() && !vc.present()) return false;
    if (ec.present()) {
        for (auto eh : in.edges()) {
            const double c = ec(in, eh);
            if (c == 0.0) continue;  // smooth (NaN is kept: the library names it)
            auto h = in.halfedge_handle(eh, 0);
            cr.edge(index[in.from_vertex_handle(h).idx()], index[in.to_vertex_handle(h).idx()], c);
            edge_of.push_back(eh.idx());
        }
    }
    if (vc.present()) {
        for (auto vh : in.vertices()) {
            const double c = vc(in, vh);
            if (c == 0.0) continue;
            cr.corner(index[vh.idx()], c);
            vertex_of.push_back(vh.idx());
        }
    }
    return true;
}

/// The crease entry an error message names ("edge crease 3 ..." gives 3 for "edge"), or -1.
inline long crease_entry(const std::string& message, const char* kind) {
    const std::string key = std::string(kind) + " crease ";
    const auto at = message.find(key);
    if (at == std::string::npos) return -1;
    const char* p = message.c_str() + at + key.size();
    char* end = nullptr;
    const long k = std::strtol(p, &end, 10);
    return end == p ? -1 : k;
}

/// Rethrows a library error about crease entry k with the OpenMesh element it came from.
[[noreturn]] inline void rethrow_with_element(const error& e, const std::vector<int>& edge_of,
                                              const std::vector<int>& vertex_of) {
    std::string message = e.what();
    const std::string prefix = std::string(gbsurf_status_name(e.code())) + ": ";
    if (message.compare(0, prefix.size(), prefix) == 0) message.erase(0, prefix.size());
    const long ek = crease_entry(message, "edge");
    const long vk = crease_entry(message, "vertex");
    if (ek >= 0 && static_cast<std::size_t>(ek) < edge_of.size()) {
        message += " (OpenMesh edge " + std::to_string(edge_of[ek]) + ")";
    } else if (vk >= 0 && static_cast<std::size_t>(vk) < vertex_of.size()) {
        message += " (OpenMesh vertex " + std::to_string(vertex_of[vk]) + ")";
    } else {
        throw e;
    }
    throw error(e.code(), message);
}
}  // namespace detail

/// Handles of the named properties of a converted mesh (throws GBSURF_ERR_KIND if missing).
template <class Mesh> OpenMesh::VPropHandleT<int> patch(const Mesh& m) {
    return detail::existing_vprop<int>(m, patch_property_name());
}
template <class Mesh> OpenMesh::VPropHandleT<double> mean_curvature(const Mesh& m) {
    return detail::existing_vprop<double>(m, mean_curvature_property_name());
}
template <class Mesh> OpenMesh::VPropHandleT<double> gaussian_curvature(const Mesh& m) {
    return detail::existing_vprop<double>(m, gaussian_curvature_property_name());
}
template <class Mesh> OpenMesh::VPropHandleT<double> g1_deviation(const Mesh& m) {
    return detail::existing_vprop<double>(m, g1_deviation_property_name());
}

/// Converts any OpenMesh polygon mesh (any traits with points; deleted elements skipped) with the
/// library. Face corners are taken in halfedge order (counter-clockwise). The "crease" edge and
/// vertex properties, if present, are passed as sharpness (see the top of this header).
template <class InMesh>
result convert_to_result(const InMesh& in, const options& opt = options(), const progress_fn& progress = {}) {
    std::vector<uint32_t> index(in.n_vertices(), 0);
    std::vector<double> positions;
    positions.reserve(3 * in.n_vertices());
    uint32_t next = 0;
    for (auto vh : in.vertices()) {
        const auto& p = in.point(vh);
        positions.push_back(static_cast<double>(p[0]));
        positions.push_back(static_cast<double>(p[1]));
        positions.push_back(static_cast<double>(p[2]));
        index[vh.idx()] = next++;
    }
    std::vector<uint32_t> sizes, corners;
    sizes.reserve(in.n_faces());
    for (auto fh : in.faces()) {
        uint32_t n = 0;
        auto h0 = in.halfedge_handle(fh);
        auto h = h0;
        do {
            corners.push_back(index[in.to_vertex_handle(h).idx()]);
            ++n;
            h = in.next_halfedge_handle(h);
        } while (h != h0 && n <= in.n_halfedges());
        sizes.push_back(n);
    }
    creases cr;
    std::vector<int> edge_of, vertex_of;
    if (!detail::read_creases(in, index, cr, edge_of, vertex_of)) {
        return gbsurf::convert(positions, sizes, corners, opt, progress);
    }
    try {
        return gbsurf::convert(positions, sizes, corners, cr, opt, progress);
    } catch (const error& e) {
        if (e.code() != GBSURF_ERR_NAN && e.code() != GBSURF_ERR_INVALID_MESH && e.code() != GBSURF_ERR_INDEX) throw;
        detail::rethrow_with_element(e, edge_of, vertex_of);
    }
}

namespace detail {
/// The output vertices of `r` added to `out` with their normals and the gbsurf vertex
/// properties (shared by to_trimesh and to_polymesh).
template <class Mesh>
std::vector<typename Mesh::VertexHandle> add_output_vertices(Mesh& out, const result& r) {
    auto pos = r.positions();
    auto nrm = r.normals();
    auto pat = r.patch_index();
    auto h = r.mean_curvature();
    auto k = r.gaussian_curvature();
    auto g = r.g1_deviation();
    const std::size_t nv = pos.size() / 3;
    out.request_vertex_normals();
    auto ph = vprop<int>(out, patch_property_name());
    auto hh = vprop<double>(out, mean_curvature_property_name());
    auto kh = vprop<double>(out, gaussian_curvature_property_name());
    auto gh = vprop<double>(out, g1_deviation_property_name());
    std::vector<typename Mesh::VertexHandle> vhs;
    vhs.reserve(nv);
    for (std::size_t i = 0; i < nv; ++i) {
        auto vh = out.add_vertex(typename Mesh::Point(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
        if (nrm.size() == pos.size()) out.set_normal(vh, typename Mesh::Normal(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]));
        out.property(ph, vh) = i < pat.size() ? static_cast<int>(pat[i]) : -1;
        out.property(hh, vh) = i < h.size() ? h[i] : 0.0;
        out.property(kh, vh) = i < k.size() ? k[i] : 0.0;
        out.property(gh, vh) = i < g.size() ? g[i] : 0.0;
        vhs.push_back(vh);
    }
    return vhs;
}
}  // namespace detail

/// The output mesh of a result as an OpenMesh TriMesh with normals and the gbsurf properties.
inline TriMesh to_trimesh(const result& r) {
    TriMesh out;
    auto tri = r.triangles();
    auto vhs = detail::add_output_vertices(out, r);
    for (std::size_t t = 0; 3 * t + 2 < tri.size(); ++t) {
        auto fh = out.add_face(vhs[tri[3 * t]], vhs[tri[3 * t + 1]], vhs[tri[3 * t + 2]]);
        if (!fh.is_valid()) {
            throw error(GBSURF_ERR_INVALID_MESH,
                        "OpenMesh rejected output triangle " + std::to_string(t) + " (non-manifold)");
        }
    }
    return out;
}

/// On to_polymesh's output: per face, the input face it lies in (-1 when unknown).
inline const char* cage_face_property_name() { return "gbsurf:cage_face"; }

/// The output faces of a result as an OpenMesh PolyMesh: the quads of the quad layout (the
/// default; n·r² per n-sided patch, like Subdivision Surface level L at r = 2^(L−1)), else the
/// triangles, with normals, the vertex properties of to_trimesh and the face property
/// "gbsurf:cage_face" (materials and per-face data of the input follow it).
inline PolyMesh to_polymesh(const result& r) {
    PolyMesh out;
    auto quads = r.quads();
    auto tris = r.triangles();
    auto cage = r.cage_corner();
    const bool q = !quads.empty();
    const std::size_t m = q ? 4 : 3;
    auto corners = q ? quads : tris;
    OpenMesh::FPropHandleT<int> fh_cage;
    out.add_property(fh_cage, cage_face_property_name());
    auto vhs = detail::add_output_vertices(out, r);
    std::vector<PolyMesh::VertexHandle> face(m);
    for (std::size_t f = 0; m * f + m - 1 < corners.size(); ++f) {
        for (std::size_t c = 0; c < m; ++c) face[c] = vhs[corners[m * f + c]];
        auto fh = out.add_face(face);
        if (!fh.is_valid()) {
            throw error(GBSURF_ERR_INVALID_MESH, std::string("OpenMesh rejected output ") + (q ? "quad " : "triangle ") +
                                                     std::to_string(f) + " (non-manifold)");
        }
        const bool known = 2 * f + 1 < cage.size() && cage[2 * f] != UINT32_MAX;
        out.property(fh_cage, fh) = known ? static_cast<int>(cage[2 * f]) : -1;
    }
    return out;
}

/// Converts an OpenMesh polygon mesh into a PolyMesh of its output faces (see convert_to_result
/// and to_polymesh).
template <class InMesh>
PolyMesh convert_poly(const InMesh& in, const options& opt = options(), const progress_fn& progress = {}) {
    return to_polymesh(convert_to_result(in, opt, progress));
}

/// Converts an OpenMesh polygon mesh into a TriMesh (see convert_to_result and to_trimesh).
template <class InMesh>
TriMesh convert(const InMesh& in, const options& opt = options(), const progress_fn& progress = {}) {
    return to_trimesh(convert_to_result(in, opt, progress));
}

/// The curve network: per curve the control points of its cubic Bézier chain
/// (result::curve_cubic_points) as vertices (property "gbsurf:curve") joined by edges along the
/// control polygon. The mesh has no faces (OpenMesh file writers store only its vertices); use it
/// in memory or walk its edges.
inline PolyMesh curve_network(const result& r) {
    PolyMesh out;
    auto ch = detail::vprop<int>(out, curve_property_name());
    for (std::size_t c = 0; c < r.curve_count(); ++c) {
        auto pts = r.curve_cubic_points(c);
        PolyMesh::VertexHandle prev;
        for (std::size_t i = 0; i + 2 < pts.size(); i += 3) {
            auto vh = out.add_vertex(PolyMesh::Point(pts[i], pts[i + 1], pts[i + 2]));
            out.property(ch, vh) = static_cast<int>(c);
            if (prev.is_valid()) out.new_edge(prev, vh);
            prev = vh;
        }
    }
    return out;
}

/// The control nets of all patches (the library's control net, see result::control_net_*):
/// control points as vertices (property "gbsurf:patch"), the quads between ribbon rows as faces,
/// and as bare edges the control polygons of one-row ribbons and the spokes from a GB patch's
/// centre to the middle of each innermost row.
inline PolyMesh control_nets(const result& r) {
    PolyMesh out;
    auto ph = detail::vprop<int>(out, patch_property_name());
    auto pos = r.control_net_positions();
    auto pat = r.control_net_patch_index();
    auto sizes = r.control_net_face_sizes();
    auto corners = r.control_net_face_indices();
    auto edges = r.control_net_edges();
    std::vector<PolyMesh::VertexHandle> vhs;
    vhs.reserve(pos.size() / 3);
    for (std::size_t i = 0; 3 * i + 2 < pos.size(); ++i) {
        auto vh = out.add_vertex(PolyMesh::Point(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]));
        out.property(ph, vh) = i < pat.size() ? static_cast<int>(pat[i]) : -1;
        vhs.push_back(vh);
    }
    std::vector<PolyMesh::VertexHandle> face;
    std::size_t at = 0;
    for (uint32_t n : sizes) {
        face.clear();
        for (uint32_t k = 0; k < n && at < corners.size(); ++k) face.push_back(vhs[corners[at++]]);
        out.add_face(face);
    }
    for (std::size_t e = 0; 2 * e + 1 < edges.size(); ++e) out.new_edge(vhs[edges[2 * e]], vhs[edges[2 * e + 1]]);
    return out;
}

}  // namespace openmesh
}  // namespace gbsurf

#endif  // GBSURF_OPENMESH_HPP
