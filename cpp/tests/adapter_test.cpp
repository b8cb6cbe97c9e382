// The C++ wrapper and the OpenMesh adapter: bad models give the right gbsurf::error code, good
// models give TriMeshes with normals and properties; exceptions from callbacks are rethrown.
//   adapter_test MODELS_DIR
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <gbsurf/openmesh.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>
#include <string>

#include "check.hpp"

// The code of a thrown gbsurf::error, GBSURF_OK when nothing was thrown.
template <class F>
uint32_t code_of(F f, std::string* message = nullptr) {
    try {
        f();
    } catch (const gbsurf::error& e) {
        if (message) *message = e.what();
        return e.code();
    }
    return GBSURF_OK;
}

static void bad_models(const std::string& dir) {
    // The library's strict readers: the exact code for every bad model.
    const std::map<std::string, uint32_t> expected = {
        {"bowtie_vertex.obj", GBSURF_ERR_INVALID_MESH},   {"duplicate_face.obj", GBSURF_ERR_INVALID_MESH},
        {"empty.obj", GBSURF_ERR_INVALID_MESH},           {"flipped_face.obj", GBSURF_ERR_INVALID_MESH},
        {"garbage.obj", GBSURF_ERR_IO},                   {"huge_coordinates.obj", GBSURF_ERR_INVALID_MESH},
        {"index_out_of_range.obj", GBSURF_ERR_INDEX},     {"inf.obj", GBSURF_ERR_NAN},
        {"isolated_vertex.obj", GBSURF_OK},               {"nan.obj", GBSURF_ERR_NAN},
        {"nonmanifold_edge.obj", GBSURF_ERR_INVALID_MESH}, {"repeated_index.obj", GBSURF_ERR_INVALID_MESH},
        {"zero_area.obj", GBSURF_ERR_INVALID_MESH},
    };
    for (const auto& [name, code] : expected) {
        const std::string path = dir + "/bad/" + name;
        std::string msg;
        uint32_t got = code_of([&] {
            auto r = gbsurf::convert_file(path, gbsurf::options().resolution(3));
            if (name == "isolated_vertex.obj") CHECK(!r.warnings().empty());
        }, &msg);
        if (got != code) {
            std::cerr << name << ": got " << gbsurf_status_name(got) << " (" << msg << "), expected "
                      << gbsurf_status_name(code) << "\n";
            ++failures;
        }
        if (got != GBSURF_OK) CHECK(msg.find(name) != std::string::npos);  // names the file

        // OpenMesh's reader repairs some defects (it splits non-manifold vertices, skips faces
        // it cannot add, ...). Whatever reaches the adapter must give a result or an input
        // error, never an internal one.
        OpenMesh::PolyMesh_ArrayKernelT<> in;
        if (!OpenMesh::IO::read_mesh(in, path)) continue;
        got = code_of([&] { gbsurf::openmesh::convert(in, gbsurf::options().resolution(3)); }, &msg);
        const std::set<uint32_t> input_errors = {GBSURF_OK, GBSURF_ERR_NAN, GBSURF_ERR_INDEX,
                                                 GBSURF_ERR_INVALID_MESH, GBSURF_ERR_COUNT};
        if (!input_errors.count(got)) {
            std::cerr << name << " via OpenMesh: " << gbsurf_status_name(got) << " " << msg << "\n";
            ++failures;
        }
        if (in.n_faces() == 0) CHECK(got == GBSURF_ERR_INVALID_MESH);
    }
}

static void wrapper_errors() {
    const std::vector<double> p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    const std::vector<uint32_t> s = {4, 4, 4, 4, 4, 4};
    const std::vector<uint32_t> f = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    CHECK(code_of([&] { gbsurf::options().resolution(0).validate(); }) == GBSURF_ERR_INVALID_OPTION);
    CHECK(code_of([&] { gbsurf::parse_method("loop"); }) == GBSURF_ERR_INVALID_OPTION);
    CHECK(code_of([&] { gbsurf::convert(p, s, std::vector<uint32_t>(f.begin(), f.end() - 1)); }) == GBSURF_ERR_COUNT);
    auto f2 = f;
    f2[5] = 8;
    std::string msg;
    CHECK(code_of([&] { gbsurf::convert(p, s, f2); }, &msg) == GBSURF_ERR_INDEX);
    CHECK(msg.find("face 1 corner 1") != std::string::npos);
    // A progress callback that returns false cancels; one that throws cancels and rethrows.
    CHECK(code_of([&] { gbsurf::convert(p, s, f, gbsurf::options(), [](float) { return false; }); }) ==
          GBSURF_ERR_CANCELLED);
    bool rethrown = false;
    try {
        gbsurf::convert(p, s, f, gbsurf::options(), [](float) -> bool { throw std::runtime_error("stop"); });
    } catch (const std::runtime_error& e) {
        rethrown = std::string(e.what()) == "stop";
    }
    CHECK(rethrown);
}

static void good_model(const std::string& dir) {
    OpenMesh::PolyMesh_ArrayKernelT<> in;
    if (!OpenMesh::IO::read_mesh(in, dir + "/cube.obj")) {
        std::cerr << "cannot read cube.obj\n";
        ++failures;
        return;
    }
    for (auto m : {gbsurf::method::dual, gbsurf::method::topology}) {
        std::string msg;
        uint32_t code = code_of([&] {
            gbsurf::result r = gbsurf::openmesh::convert_to_result(in, gbsurf::options().method(m).resolution(4));
            gbsurf::openmesh::TriMesh out = gbsurf::openmesh::to_trimesh(r);
            CHECK(out.n_vertices() == r.vertex_count());
            CHECK(out.n_faces() == r.triangle_count());
            CHECK(out.has_vertex_normals());
            auto ph = gbsurf::openmesh::patch(out);
            auto gh = gbsurf::openmesh::g1_deviation(out);
            auto kh = gbsurf::openmesh::gaussian_curvature(out);
            int max_patch = -1;
            for (auto vh : out.vertices()) {
                max_patch = std::max(max_patch, out.property(ph, vh));
                CHECK(std::isfinite(out.property(gh, vh)) && std::isfinite(out.property(kh, vh)));
                CHECK(std::abs(out.normal(vh).norm() - 1.0) < 1e-9);
            }
            CHECK(static_cast<std::size_t>(max_patch) + 1 == r.patch_count());
            CHECK(r.patch_count() == (m == gbsurf::method::dual ? 8u : 6u));
            CHECK(r.report().closed == 1);
            CHECK(r.patches_with_sides(m == gbsurf::method::dual ? 3 : 4) == r.patch_count());
            // The output faces as a PolyMesh: the quads of the default layout.
            gbsurf::result rq = gbsurf::openmesh::convert_to_result(in, gbsurf::options().method(m));
            gbsurf::openmesh::PolyMesh poly = gbsurf::openmesh::to_polymesh(rq);
            CHECK(rq.quad_count() > 0 && poly.n_faces() == rq.quad_count());
            CHECK(poly.n_vertices() == rq.vertex_count());
            // r = 2 on the cube: 96 quads, the count of Subdivision Surface level 2.
            CHECK(poly.n_faces() == 96);
            OpenMesh::FPropHandleT<int> cf;
            CHECK(poly.get_property_handle(cf, gbsurf::openmesh::cage_face_property_name()));
            std::vector<int> per_cage(6, 0);
            for (auto fh : poly.faces()) {
                CHECK(poly.valence(fh) == 4);
                int c = poly.property(cf, fh);
                CHECK(c >= 0 && c < 6);
                if (c >= 0 && c < 6) ++per_cage[c];
            }
            for (int c : per_cage) CHECK(c == 16);
            bool closed = true;
            for (auto eh : poly.edges()) closed = closed && !poly.is_boundary(eh);
            CHECK(closed);
            auto curves = gbsurf::openmesh::curve_network(r);
            CHECK(r.curve_count() == 12);
            CHECK(curves.n_vertices() > 0 && curves.n_edges() > 0);
            CHECK(curves.n_vertices() == 12 * 4 && curves.n_edges() == 12 * 3);
            auto nets = gbsurf::openmesh::control_nets(r);
            CHECK(nets.n_vertices() > 0);
            CHECK(nets.n_vertices() == r.control_net_positions().size() / 3);
            CHECK(nets.n_faces() == r.control_net_face_sizes().size());
            auto nph = gbsurf::openmesh::patch(nets);
            int max_net_patch = -1;
            for (auto vh : nets.vertices()) max_net_patch = std::max(max_net_patch, nets.property(nph, vh));
            CHECK(static_cast<std::size_t>(max_net_patch) + 1 == r.patch_count());
        }, &msg);
        if (code != GBSURF_OK) {
            std::cerr << "cube " << static_cast<int>(m) << ": " << msg << "\n";
            ++failures;
        }
    }
}

// Any traits with points: double points, a TriMesh input, and deleted elements (status
// attributes, no garbage collection) all give the same result as the flat arrays.
struct DoubleTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
};

static void custom_traits_and_deleted_elements(const std::string& dir) {
    const std::vector<double> p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    const std::vector<uint32_t> s = {4, 4, 4, 4, 4, 4};
    const std::vector<uint32_t> f = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    const auto opt = gbsurf::options().resolution(3);
    gbsurf::result ref = gbsurf::convert(p, s, f, opt);

    typedef OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits> Mesh;
    Mesh in;
    in.request_vertex_status();
    in.request_edge_status();
    in.request_face_status();
    // A junk triangle first (so the cube's vertices do not start at index 0), deleted below.
    std::vector<Mesh::VertexHandle> junk;
    for (int i = 0; i < 3; ++i) junk.push_back(in.add_vertex(Mesh::Point(10 + i, 20 * i, 5)));
    auto junk_face = in.add_face(junk);
    std::vector<Mesh::VertexHandle> v;
    for (std::size_t i = 0; i < 8; ++i) v.push_back(in.add_vertex(Mesh::Point(p[3 * i], p[3 * i + 1], p[3 * i + 2])));
    for (std::size_t k = 0; k < 6; ++k) {
        CHECK(in.add_face(v[f[4 * k]], v[f[4 * k + 1]], v[f[4 * k + 2]], v[f[4 * k + 3]]).is_valid());
    }
    in.delete_face(junk_face, true);  // also deletes its now isolated vertices
    CHECK(in.n_vertices() == 11 && in.has_vertex_status());
    std::string msg;
    uint32_t code = code_of([&] {
        gbsurf::result got = gbsurf::openmesh::convert_to_result(in, opt);
        CHECK(got.warnings().empty());  // no isolated (deleted) vertex reached the library
        CHECK(got.vertex_count() == ref.vertex_count() && got.triangle_count() == ref.triangle_count());
        auto a = got.positions(), b = ref.positions();
        bool same = a.size() == b.size();
        for (std::size_t i = 0; same && i < a.size(); ++i) same = a[i] == b[i];
        CHECK(same);
        // Garbage collection afterwards changes nothing either.
        in.garbage_collection();
        CHECK(in.n_vertices() == 8);
        gbsurf::result gc = gbsurf::openmesh::convert_to_result(in, opt);
        CHECK(gc.vertex_count() == ref.vertex_count());
    }, &msg);
    if (code != GBSURF_OK) {
        std::cerr << "custom traits: " << msg << "\n";
        ++failures;
    }

    // A triangle mesh input (default float traits) and a double-point TriMesh.
    OpenMesh::TriMesh_ArrayKernelT<> tri;
    OpenMesh::TriMesh_ArrayKernelT<DoubleTraits> trid;
    CHECK(OpenMesh::IO::read_mesh(tri, dir + "/octahedron.obj"));
    CHECK(OpenMesh::IO::read_mesh(trid, dir + "/octahedron.obj"));
    code = code_of([&] {
        auto out = gbsurf::openmesh::convert(tri, opt);
        auto outd = gbsurf::openmesh::convert(trid, opt);
        CHECK(out.n_faces() > 0 && out.n_faces() == outd.n_faces());
    }, &msg);
    if (code != GBSURF_OK) {
        std::cerr << "trimesh input: " << msg << "\n";
        ++failures;
    }
}

// The "crease" properties (edge and vertex, float or double) become the creased convert's
// sharpness: every cube edge at 1 keeps the corners at +-1 (as tests/creases.rs checks); no
// property (or one of another type) leaves the conversion as it was; bad values name the
// OpenMesh element.
static void crease_properties(const std::string& dir) {
    typedef OpenMesh::PolyMesh_ArrayKernelT<> Mesh;
    Mesh in;
    if (!OpenMesh::IO::read_mesh(in, dir + "/cube.obj")) {
        std::cerr << "cannot read cube.obj\n";
        ++failures;
        return;
    }
    const auto opt = gbsurf::options().method(gbsurf::method::topology).resolution(4);
    // The flat arrays the adapter builds (halfedge order), converted without creases.
    std::vector<double> p;
    for (auto vh : in.vertices()) for (int k = 0; k < 3; ++k) p.push_back(in.point(vh)[k]);
    std::vector<uint32_t> s, f;
    for (auto fh : in.faces()) {
        uint32_t n = 0;
        for (auto vh : in.fv_ccw_range(fh)) f.push_back(static_cast<uint32_t>(vh.idx())), ++n;
        s.push_back(n);
    }
    auto max_abs = [](const gbsurf::result& r) {
        double m = 0.0;
        for (double x : r.positions()) m = std::max(m, std::abs(x));
        return m;
    };
    auto same = [](const gbsurf::result& a, const gbsurf::result& b) {
        auto x = a.positions(), y = b.positions();
        if (x.size() != y.size()) return false;
        for (std::size_t i = 0; i < x.size(); ++i) if (x[i] != y[i]) return false;
        return true;
    };
    std::string msg;
    uint32_t code = code_of([&] {
        const gbsurf::result ref = gbsurf::convert(p, s, f, opt);
        // Without the property: the plain conversion, bit for bit, and no sharp edge.
        gbsurf::result plain = gbsurf::openmesh::convert_to_result(in, opt);
        CHECK(same(plain, ref));
        CHECK(plain.report().sharp_edges == 0);
        CHECK(max_abs(plain) < 0.99);  // the smooth cube shrinks inside [-1, 1]^3
        // A property of another type is not a crease property.
        OpenMesh::EPropHandleT<int> ih;
        in.add_property(ih, "crease");
        for (auto eh : in.edges()) in.property(ih, eh) = 1;
        CHECK(same(gbsurf::openmesh::convert_to_result(in, opt), ref));
        in.remove_property(ih);

        // Every edge at 1 (float): the cube itself, corners at +-1.
        OpenMesh::EPropHandleT<float> eh_f;
        in.add_property(eh_f, gbsurf::openmesh::crease_property_name());
        for (auto eh : in.edges()) in.property(eh_f, eh) = 1.0f;
        gbsurf::result sharp = gbsurf::openmesh::convert_to_result(in, opt);
        CHECK(sharp.report().sharp_edges == 12);
        CHECK(std::abs(max_abs(sharp) - 1.0) <= 1e-12);
        auto pos = sharp.positions();
        for (auto vh : in.vertices()) {
            double best = 1e300;
            for (std::size_t i = 0; 3 * i + 2 < pos.size(); ++i) {
                double d = 0.0;
                for (int k = 0; k < 3; ++k) d += std::pow(pos[3 * i + k] - in.point(vh)[k], 2);
                best = std::min(best, std::sqrt(d));
            }
            CHECK(best <= 1e-12);
        }
        // The same as double, and all zeros: unchanged.
        OpenMesh::EPropHandleT<double> eh_d;
        in.remove_property(eh_f);
        in.add_property(eh_d, "crease");
        for (auto eh : in.edges()) in.property(eh_d, eh) = 1.0;
        CHECK(same(gbsurf::openmesh::convert_to_result(in, opt), sharp));
        for (auto eh : in.edges()) in.property(eh_d, eh) = 0.0;
        CHECK(same(gbsurf::openmesh::convert_to_result(in, opt), ref));

        // Out of range on OpenMesh edge 5: the library's error, naming the edge.
        in.property(eh_d, in.edge_handle(5)) = 2.0;
        std::string m;
        CHECK(code_of([&] { gbsurf::openmesh::convert_to_result(in, opt); }, &m) == GBSURF_ERR_INVALID_MESH);
        CHECK(m.find("edge crease 0") != std::string::npos);
        CHECK(m.find("(OpenMesh edge 5)") != std::string::npos);
        in.property(eh_d, in.edge_handle(5)) = 0.0;
        // A vertex property: corner sharpness; NaN on OpenMesh vertex 3 is named.
        OpenMesh::VPropHandleT<double> vh_d;
        in.add_property(vh_d, "crease");
        for (auto vh : in.vertices()) in.property(vh_d, vh) = 1.0;
        gbsurf::result corners = gbsurf::openmesh::convert_to_result(in, opt);
        CHECK(!same(corners, ref));
        in.property(vh_d, in.vertex_handle(3)) = std::nan("");
        CHECK(code_of([&] { gbsurf::openmesh::convert_to_result(in, opt); }, &m) == GBSURF_ERR_NAN);
        CHECK(m.find("vertex crease 3") != std::string::npos);
        CHECK(m.find("(OpenMesh vertex 3)") != std::string::npos);
        in.property(vh_d, in.vertex_handle(3)) = -0.5;
        CHECK(code_of([&] { gbsurf::openmesh::convert_to_result(in, opt); }, &m) == GBSURF_ERR_INVALID_MESH);
        CHECK(m.find("(OpenMesh vertex 3)") != std::string::npos);
        in.remove_property(vh_d);
        in.remove_property(eh_d);
        CHECK(same(gbsurf::openmesh::convert_to_result(in, opt), ref));
    }, &msg);
    if (code != GBSURF_OK) {
        std::cerr << "crease properties: " << msg << "\n";
        ++failures;
    }
}

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: adapter_test MODELS_DIR\n";
        return 2;
    }
    bad_models(argv[1]);
    wrapper_errors();
    good_model(argv[1]);
    custom_traits_and_deleted_elements(argv[1]);
    crease_properties(argv[1]);
    if (failures) {
        std::cerr << failures << " failures\n";
        return 1;
    }
    std::cout << "adapter_test: all checks passed\n";
    return 0;
}
