// gbsurf.hpp: header-only C++17 RAII wrapper of the gbsurf C API (gbsurf.h).
//
//   gbsurf::options opt;                       // defaults
//   opt.method(gbsurf::method::topology).resolution(12);
//   gbsurf::result r = gbsurf::convert_file("cube.obj", opt);
//   auto pos = r.positions();                  // gbsurf::span<const double>, 3 per vertex
//
// Handles are freed automatically; every failing call throws gbsurf::error, which carries the
// status code (GBSURF_ERR_*) and the library's message. Views (gbsurf::span) point into the
// result they came from and are valid while it lives; calling a view accessor on a temporary
// result does not compile. Constructing options and every conversion check that the library
// linked implements this header's ABI (GBSURF_ERR_VERSION otherwise).
#ifndef GBSURF_HPP
#define GBSURF_HPP

#include "gbsurf.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace gbsurf {

/// A failed call: the status code (GBSURF_ERR_*) and the message naming the problem.
class error : public std::runtime_error {
public:
    error(uint32_t code, const std::string& message)
        : std::runtime_error(std::string(gbsurf_status_name(code)) + ": " + message), code_(code) {}
    /// The status code, one of the GBSURF_ERR_* values.
    uint32_t code() const noexcept { return code_; }

private:
    uint32_t code_;
};

/// Throws gbsurf::error for a non-OK status, with the thread's last error message.
inline void check(uint32_t status) {
    if (status != GBSURF_OK) {
        throw error(status, std::string(gbsurf_last_error_message(), gbsurf_last_error_length()));
    }
}

/// The library version string, e.g. "0.1.0".
inline std::string version() { return gbsurf_version(); }

/// Throws gbsurf::error(GBSURF_ERR_VERSION) unless `library` (the ABI version of the library
/// linked, gbsurf_abi_version()) equals `header` (GBSURF_ABI_VERSION of the gbsurf.h compiled in).
inline void check_abi(uint32_t library = gbsurf_abi_version(), uint32_t header = GBSURF_ABI_VERSION) {
    if (library != header) {
        throw error(GBSURF_ERR_VERSION, "the gbsurf library implements ABI version " + std::to_string(library) +
                                            " but gbsurf.h declares version " + std::to_string(header) +
                                            " (headers and library from different releases)");
    }
}

/// A read-only view of a contiguous array owned by a result.
template <class T>
class span {
public:
    span() = default;
    span(const T* data, std::size_t size) : data_(data), size_(size) {}
    const T* data() const noexcept { return data_; }
    std::size_t size() const noexcept { return size_; }
    bool empty() const noexcept { return size_ == 0; }
    const T* begin() const noexcept { return data_; }
    const T* end() const noexcept { return data_ + size_; }
    const T& operator[](std::size_t i) const noexcept { return data_[i]; }
    std::vector<T> to_vector() const { return std::vector<T>(begin(), end()); }

private:
    const T* data_ = nullptr;
    std::size_t size_ = 0;
};

/// Construction methods.
enum class method : uint32_t {
    dual = GBSURF_METHOD_DUAL,
    topology = GBSURF_METHOD_TOPOLOGY,
    doo_sabin = GBSURF_METHOD_DOO_SABIN,
    catmull_clark = GBSURF_METHOD_CATMULL_CLARK,
};

/// Twist constructions.
enum class twist : uint32_t {
    none = GBSURF_TWIST_NONE,
    approx = GBSURF_TWIST_APPROX,
    interp = GBSURF_TWIST_INTERP,
};

/// Middle constraint of the direction blends: the seed's rule or the fair one.
enum class middle : uint32_t {
    seed = GBSURF_MIDDLE_SEED,
    fair = GBSURF_MIDDLE_FAIR,
};

/// Correction weight forms.
enum class weights : uint32_t {
    squared = GBSURF_WEIGHTS_SQUARED,
    linear = GBSURF_WEIGHTS_LINEAR,
};

/// Patch kinds.
enum class patch_kind : uint32_t { gb = GBSURF_PATCH_GB, cgb = GBSURF_PATCH_CGB };

/// Parses "dual", "topology", "doo-sabin", "catmull-clark".
inline method parse_method(const std::string& s) {
    if (s == "dual") return method::dual;
    if (s == "topology") return method::topology;
    if (s == "doo-sabin") return method::doo_sabin;
    if (s == "catmull-clark") return method::catmull_clark;
    throw error(GBSURF_ERR_INVALID_OPTION,
                "unknown method '" + s + "' (expected dual, topology, doo-sabin or catmull-clark)");
}

/// Conversion options (defaults from gbsurf_options_init); fluent setters.
class options {
public:
    options() {
        check_abi();
        check(gbsurf_options_init(&raw_));
    }
    options& method(gbsurf::method m) { raw_.method = static_cast<uint32_t>(m); return *this; }
    options& resolution(uint32_t r) { raw_.resolution = r; return *this; }
    /// GBSURF_LAYOUT_QUADS (default) or GBSURF_LAYOUT_TRIANGLES.
    options& layout(uint32_t l) { raw_.layout = l; return *this; }
    options& twist(gbsurf::twist t) { raw_.twist = static_cast<uint32_t>(t); return *this; }
    options& weights(gbsurf::weights w) { raw_.weights = static_cast<uint32_t>(w); return *this; }
    options& levels(uint32_t l) { raw_.levels = l; return *this; }
    options& best_plane(bool b) { raw_.best_plane = b ? 1u : 0u; return *this; }
    options& fullness(double f) { raw_.fullness = f; return *this; }
    options& tile_depth(double w) { raw_.tile_depth = w; return *this; }
    options& mid_scale(double s) { raw_.mid_scale = s; return *this; }
    options& middle(gbsurf::middle m) { raw_.middle = static_cast<uint32_t>(m); return *this; }
    /// Memory bound in MiB: a conversion estimated to need more throws GBSURF_ERR_TOO_LARGE.
    options& max_memory_mb(uint64_t mb) { raw_.max_memory_mb = mb; return *this; }
    /// Throws gbsurf::error if a value is out of range.
    void validate() const { check(gbsurf_options_validate(&raw_)); }
    const GbsurfOptions& raw() const noexcept { return raw_; }
    GbsurfOptions& raw() noexcept { return raw_; }

private:
    GbsurfOptions raw_{};
};

/// Progress callback: fraction done in [0, 1]; return false to cancel (gbsurf::error with
/// GBSURF_ERR_CANCELLED). An exception thrown by it cancels the run and is rethrown (it never
/// crosses the C boundary). It is called only on the thread that called convert, never
/// concurrently, so it needs no locking of its own.
using progress_fn = std::function<bool(float)>;

/// Degree and layer count of one ribbon.
struct ribbon_shape {
    std::size_t degree;
    std::size_t layers;
};

struct holes;

/// The result of a conversion (owns a GbsurfResult handle; move-only, noexcept moves; a
/// moved-from result throws GBSURF_ERR_NULL from every accessor). The spans returned point into
/// the handle: valid while this result lives (view accessors are deleted on temporaries).
class result {
public:
    explicit result(GbsurfResult* h) : h_(h) {}
    const GbsurfResult* get() const noexcept { return h_.get(); }

    std::size_t vertex_count() const { return count(gbsurf_mesh_vertex_count); }
    std::size_t triangle_count() const { return count(gbsurf_mesh_triangle_count); }
    /// x y z per vertex.
    span<double> positions() const& { return view(gbsurf_mesh_positions); }
    span<double> positions() const&& = delete;
    /// Unit normal x y z per vertex.
    span<double> normals() const& { return view(gbsurf_mesh_normals); }
    span<double> normals() const&& = delete;
    /// Three vertex indices per triangle, counter-clockwise.
    span<uint32_t> triangles() const& { return view(gbsurf_mesh_triangles); }
    span<uint32_t> triangles() const&& = delete;
    /// Quad layout (the default): the output faces, four vertex indices per quad,
    /// counter-clockwise; empty in the triangle layout and for the subdivision methods.
    std::size_t quad_count() const { return count(gbsurf_mesh_quad_count); }
    span<uint32_t> quads() const& { return view(gbsurf_mesh_quads); }
    span<uint32_t> quads() const&& = delete;
    /// Per output face (quads when there are any, else triangles): its cage corner, the input
    /// face and the position of the vertex in it (UINT32_MAX when unknown).
    span<uint32_t> cage_corner() const& { return view(gbsurf_mesh_cage_corner); }
    span<uint32_t> cage_corner() const&& = delete;
    /// An attribute of the control mesh given per face corner (`dim` floats per corner, in the
    /// face-corner order of the faces of `face_sizes`, the mesh this result was built from) at
    /// every output face corner, by Subdivision Surface's "keep corners" rule
    /// (docs/math.md#cage-corners): `dim` floats per corner of `quads()` (or of `triangles()` in
    /// the triangle layout). For UV maps: dim = 2. Throws `error` (_COUNT, _INDEX) when the
    /// sizes or lengths do not fit.
    std::vector<float> cage_loop_values(const std::vector<uint32_t>& face_sizes, const std::vector<float>& values,
                                        std::size_t dim) const {
        return cage_values(face_sizes, nullptr, nullptr, 0, values, dim);
    }
    /// cage_loop_values for a control mesh with faces with holes `h` (the holes it was converted
    /// with): `values` has `dim` floats per face corner in the user's numbering, face by face the
    /// corners of its outer loop, then those of each of its holes in order (see
    /// gbsurf_cage_loop_values_holed). Defined after `holes`.
    std::vector<float> cage_loop_values(const std::vector<uint32_t>& face_sizes, const holes& h,
                                        const std::vector<float>& values, std::size_t dim) const;
    /// Patch (or, for subdivision, input face) index per vertex.
    span<uint32_t> patch_index() const& { return view(gbsurf_mesh_patch_index); }
    span<uint32_t> patch_index() const&& = delete;
    span<double> mean_curvature() const& { return view(gbsurf_mesh_mean_curvature); }
    span<double> mean_curvature() const&& = delete;
    span<double> gaussian_curvature() const& { return view(gbsurf_mesh_gaussian_curvature); }
    span<double> gaussian_curvature() const&& = delete;
    /// G1 deviation in degrees per vertex.
    span<double> g1_deviation() const& { return view(gbsurf_mesh_g1_deviation); }
    span<double> g1_deviation() const&& = delete;
    /// Fold flag per vertex: 1 on folded samples and flipped triangles' vertices, else 0.
    span<uint8_t> fold() const& { return view(gbsurf_mesh_fold); }
    span<uint8_t> fold() const&& = delete;

    std::size_t patch_count() const { return count(gbsurf_patch_count); }
    patch_kind kind(std::size_t patch) const {
        uint32_t k = 0;
        check(gbsurf_patch_kind(get(), patch, &k));
        return static_cast<patch_kind>(k);
    }
    std::size_t sides(std::size_t patch) const {
        std::size_t n = 0;
        check(gbsurf_patch_sides(get(), patch, &n));
        return n;
    }
    ribbon_shape shape(std::size_t patch, std::size_t side) const {
        ribbon_shape s{0, 0};
        check(gbsurf_patch_degree(get(), patch, side, &s.degree, &s.layers));
        return s;
    }
    /// Control points of a ribbon: 3 * (k * (degree + 1) + j) + c is coordinate c of P_{j,k}.
    span<double> ribbon_points(std::size_t patch, std::size_t side) const&& = delete;
    span<double> ribbon_points(std::size_t patch, std::size_t side) const& {
        const double* d = nullptr;
        std::size_t n = 0;
        check(gbsurf_patch_ribbon_points(get(), patch, side, &d, &n));
        return {d, n};
    }
    /// Central control point of a GB patch (GBSURF_ERR_KIND for a CGB patch).
    std::array<double, 3> center(std::size_t patch) const {
        std::array<double, 3> c{};
        check(gbsurf_patch_center(get(), patch, c.data()));
        return c;
    }

    std::size_t curve_count() const { return count(gbsurf_curve_count); }
    /// Bézier control points of a curve of the network, x y z each.
    span<double> curve_points(std::size_t curve) const&& = delete;
    span<double> curve_points(std::size_t curve) const& {
        const double* d = nullptr;
        std::size_t n = 0;
        check(gbsurf_curve_points(get(), curve, &d, &n));
        return {d, n};
    }
    /// A curve of the network as a chain of cubic Bézier segments: 3k + 1 points, x y z each
    /// (segment i = points 3i..3i+3; exact for curves of degree <= 3).
    span<double> curve_cubic_points(std::size_t curve) const&& = delete;
    span<double> curve_cubic_points(std::size_t curve) const& {
        const double* d = nullptr;
        std::size_t n = 0;
        check(gbsurf_curve_cubic_points(get(), curve, &d, &n));
        return {d, n};
    }

    /// The control nets of all patches as one mesh (empty for subdivision methods): vertex
    /// positions x y z; quads between ribbon rows (face sizes, corners); edges bounding no face
    /// (2 indices each: one-row ribbons, GB centre spokes); the patch of each vertex.
    span<double> control_net_positions() const& { return view(gbsurf_control_net_positions); }
    span<double> control_net_positions() const&& = delete;
    span<uint32_t> control_net_face_sizes() const& { return view(gbsurf_control_net_face_sizes); }
    span<uint32_t> control_net_face_sizes() const&& = delete;
    span<uint32_t> control_net_face_indices() const& { return view(gbsurf_control_net_face_indices); }
    span<uint32_t> control_net_face_indices() const&& = delete;
    span<uint32_t> control_net_edges() const& { return view(gbsurf_control_net_edges); }
    span<uint32_t> control_net_edges() const&& = delete;
    span<uint32_t> control_net_patch_index() const& { return view(gbsurf_control_net_patch_index); }
    span<uint32_t> control_net_patch_index() const&& = delete;

    GbsurfReport report() const {
        GbsurfReport r{};
        r.struct_size = sizeof(GbsurfReport);
        check(gbsurf_result_report(get(), &r));
        return r;
    }
    /// Where the surface folds: the first few folded patches (report().fold_sites of them) and the
    /// domain point of each (regular n-gon domain).
    struct FoldSite {
        std::size_t patch;
        double u, v;
    };
    std::vector<FoldSite> fold_sites() const {
        std::vector<FoldSite> sites(static_cast<std::size_t>(report().fold_sites));
        for (std::size_t i = 0; i < sites.size(); ++i) {
            check(gbsurf_report_fold_site(get(), i, &sites[i].patch, &sites[i].u, &sites[i].v));
        }
        return sites;
    }
    std::size_t patches_with_sides(std::size_t sides) const {
        std::size_t n = 0;
        check(gbsurf_report_patches_with_sides(get(), sides, &n));
        return n;
    }
    std::vector<std::string> warnings() const {
        std::vector<std::string> w(count(gbsurf_warning_count));
        for (std::size_t i = 0; i < w.size(); ++i) {
            const char* m = nullptr;
            check(gbsurf_warning_message(get(), i, &m));
            w[i] = m;
        }
        return w;
    }

private:
    struct deleter {
        void operator()(GbsurfResult* h) const noexcept { gbsurf_result_free(h); }
    };
    std::unique_ptr<GbsurfResult, deleter> h_;

    std::size_t count(uint32_t (*f)(const GbsurfResult*, std::size_t*)) const {
        std::size_t n = 0;
        check(f(get(), &n));
        return n;
    }
    template <class T>
    span<T> view(uint32_t (*f)(const GbsurfResult*, const T**, std::size_t*)) const {
        const T* d = nullptr;
        std::size_t n = 0;
        check(f(get(), &d, &n));
        return {d, n};
    }
    /// Both cage_loop_values overloads: gbsurf_cage_loop_values_holed at this result's face
    /// corners (no holes: nullptr, nullptr, 0, which is gbsurf_cage_loop_values).
    std::vector<float> cage_values(const std::vector<uint32_t>& face_sizes, const uint32_t* hole_faces,
                                   const uint32_t* hole_sizes, std::size_t n_holes, const std::vector<float>& values,
                                   std::size_t dim) const {
        span<uint32_t> fc = view(gbsurf_mesh_cage_corner);
        span<uint32_t> lc = view(gbsurf_mesh_cage_loop_corner);
        span<double> st = view(gbsurf_mesh_cage_coords);
        std::vector<float> out(st.size() / 2 * dim);
        check(gbsurf_cage_loop_values_holed(face_sizes.data(), face_sizes.size(), hole_faces, hole_sizes, n_holes,
                                            values.data(), values.size(), dim, fc.data(), fc.size(), lc.data(),
                                            lc.size(), st.data(), st.size(), out.data(), out.size()));
        return out;
    }
};

namespace detail {
struct progress_state {
    const progress_fn* fn;
    std::exception_ptr thrown;
};
// Never lets an exception unwind into the library: stores it and cancels. C language linkage
// (the library calls it through a C function pointer) puts the name in the global C namespace,
// hence the gbsurf_ prefix: a user's own `progress_trampoline` must not collide with it.
extern "C" inline bool gbsurf_hpp_progress_trampoline(float fraction, void* user) {
    auto* st = static_cast<progress_state*>(user);
    try {
        return (*st->fn)(fraction);
    } catch (...) {
        st->thrown = std::current_exception();
        return false;
    }
}
template <class Call>
result run(const progress_fn& progress, Call call) {
    check_abi();
    progress_state st{&progress, nullptr};
    GbsurfResult* out = nullptr;
    uint32_t status = progress ? call(&gbsurf_hpp_progress_trampoline, &st, &out) : call(nullptr, nullptr, &out);
    if (st.thrown) {
        gbsurf_result_free(out);
        std::rethrow_exception(st.thrown);
    }
    check(status);
    return result(out);
}
}  // namespace detail

/// Converts a polygon mesh given as flat arrays (see gbsurf_convert).
inline result convert(const double* positions, std::size_t positions_len, const uint32_t* face_sizes,
                      std::size_t face_count, const uint32_t* face_indices, std::size_t face_indices_len,
                      const options& opt = options(), const progress_fn& progress = {}) {
    return detail::run(progress, [&](GbsurfProgressFn cb, void* user, GbsurfResult** out) {
        return gbsurf_convert(positions, positions_len, face_sizes, face_count, face_indices,
                              face_indices_len, &opt.raw(), cb, user, out);
    });
}

/// Converts a polygon mesh given as vectors: x y z per vertex, corner count per face, corners.
inline result convert(const std::vector<double>& positions, const std::vector<uint32_t>& face_sizes,
                      const std::vector<uint32_t>& face_indices, const options& opt = options(),
                      const progress_fn& progress = {}) {
    return convert(positions.data(), positions.size(), face_sizes.data(), face_sizes.size(),
                   face_indices.data(), face_indices.size(), opt, progress);
}

/// The offset at signed distance `distance` of the GB surface of a polygon mesh, through PN
/// pieces of `grid` x `grid` points (0: the default 4); `shell` makes a closed solid (see
/// gbsurf_offset). The figures go to `*report` when given.
inline result offset(const std::vector<double>& positions, const std::vector<uint32_t>& face_sizes,
                     const std::vector<uint32_t>& face_indices, double distance, const options& opt = options(),
                     std::size_t grid = 0, bool shell = false, GbsurfOffsetReport* report = nullptr) {
    return detail::run({}, [&](GbsurfProgressFn, void*, GbsurfResult** out) {
        return gbsurf_offset(positions.data(), positions.size(), face_sizes.data(), face_sizes.size(),
                             face_indices.data(), face_indices.size(), &opt.raw(), distance, grid,
                             shell ? 1u : 0u, report, out);
    });
}

/// Edge and vertex sharpness in [0, 1] (see GbsurfCreases): 0 smooth, 1 infinitely sharp.
/// Only the topology method builds creases.
struct creases {
    /// Pairs of 0-based vertex indices, one pair per creased edge (either order).
    std::vector<uint32_t> edge_vertices;
    /// One sharpness per edge pair.
    std::vector<double> edge_sharpness;
    /// 0-based corner vertices.
    std::vector<uint32_t> vertices;
    /// One corner sharpness per vertex.
    std::vector<double> vertex_sharpness;

    /// Adds edge (a, b) with sharpness c.
    creases& edge(uint32_t a, uint32_t b, double c) {
        edge_vertices.push_back(a);
        edge_vertices.push_back(b);
        edge_sharpness.push_back(c);
        return *this;
    }
    /// Adds corner vertex v with sharpness c.
    creases& corner(uint32_t v, double c) {
        vertices.push_back(v);
        vertex_sharpness.push_back(c);
        return *this;
    }
};

/// Converts a polygon mesh given as vectors with creases (see gbsurf_convert_creased). The
/// arrays must pair up (two edge vertices and one sharpness per edge, one sharpness per corner):
/// otherwise GBSURF_ERR_COUNT.
inline result convert(const std::vector<double>& positions, const std::vector<uint32_t>& face_sizes,
                      const std::vector<uint32_t>& face_indices, const creases& cr,
                      const options& opt = options(), const progress_fn& progress = {}) {
    if (cr.edge_vertices.size() != 2 * cr.edge_sharpness.size() || cr.vertices.size() != cr.vertex_sharpness.size()) {
        throw error(GBSURF_ERR_COUNT, "creases: need two edge vertices per edge sharpness and one sharpness per corner");
    }
    GbsurfCreases raw{cr.edge_vertices.data(), cr.edge_sharpness.data(), cr.edge_sharpness.size(),
                      cr.vertices.data(),      cr.vertex_sharpness.data(), cr.vertex_sharpness.size()};
    return detail::run(progress, [&](GbsurfProgressFn cb, void* user, GbsurfResult** out) {
        return gbsurf_convert_creased(positions.data(), positions.size(), face_sizes.data(), face_sizes.size(),
                                      face_indices.data(), face_indices.size(), &raw, &opt.raw(), cb, user, out);
    });
}

/// Inner loops (holes) of faces (see GbsurfHoles): the face's own loop is its outer loop, each hole
/// runs the opposite way strictly inside it. Faces with holes are split into convex simple faces.
struct holes {
    std::vector<uint32_t> faces;
    std::vector<uint32_t> sizes;
    std::vector<uint32_t> indices;
    /// Adds the inner loop `loop` to face `face`.
    holes& add(uint32_t face, const std::vector<uint32_t>& loop) {
        faces.push_back(face);
        sizes.push_back(static_cast<uint32_t>(loop.size()));
        indices.insert(indices.end(), loop.begin(), loop.end());
        return *this;
    }
};

inline std::vector<float> result::cage_loop_values(const std::vector<uint32_t>& face_sizes, const holes& h,
                                                  const std::vector<float>& values, std::size_t dim) const {
    if (h.faces.size() != h.sizes.size()) {
        throw error(GBSURF_ERR_COUNT, "holes: need one size per hole face");
    }
    return cage_values(face_sizes, h.faces.data(), h.sizes.data(), h.faces.size(), values, dim);
}

/// Converts a polygon mesh with creases and faces with holes (see gbsurf_convert_holed). The
/// arrays must pair up (as for the creases overload; one face and one size per hole, the sizes
/// summing to the index count): otherwise GBSURF_ERR_COUNT.
inline result convert(const std::vector<double>& positions, const std::vector<uint32_t>& face_sizes,
                      const std::vector<uint32_t>& face_indices, const creases& cr, const holes& h,
                      const options& opt = options(), const progress_fn& progress = {}) {
    if (cr.edge_vertices.size() != 2 * cr.edge_sharpness.size() || cr.vertices.size() != cr.vertex_sharpness.size()) {
        throw error(GBSURF_ERR_COUNT, "creases: need two edge vertices per edge sharpness and one sharpness per corner");
    }
    if (h.faces.size() != h.sizes.size()) {
        throw error(GBSURF_ERR_COUNT, "holes: need one size per hole face");
    }
    GbsurfCreases raw{cr.edge_vertices.data(), cr.edge_sharpness.data(), cr.edge_sharpness.size(),
                      cr.vertices.data(),      cr.vertex_sharpness.data(), cr.vertex_sharpness.size()};
    GbsurfHoles raw_h{h.faces.data(), h.sizes.data(), h.faces.size(), h.indices.data(), h.indices.size()};
    return detail::run(progress, [&](GbsurfProgressFn cb, void* user, GbsurfResult** out) {
        return gbsurf_convert_holed(positions.data(), positions.size(), face_sizes.data(), face_sizes.size(),
                                    face_indices.data(), face_indices.size(), &raw, &raw_h, &opt.raw(), cb, user,
                                    out);
    });
}

/// Converts a polygon mesh with faces with holes and no creases (see gbsurf_convert_holed).
inline result convert(const std::vector<double>& positions, const std::vector<uint32_t>& face_sizes,
                      const std::vector<uint32_t>& face_indices, const holes& h, const options& opt = options(),
                      const progress_fn& progress = {}) {
    return convert(positions, face_sizes, face_indices, creases(), h, opt, progress);
}

/// Reads a mesh file (OBJ, OFF, PLY, STL) with the library's strict readers and converts it.
inline result convert_file(const std::string& path, const options& opt = options(),
                           const progress_fn& progress = {}) {
    return detail::run(progress, [&](GbsurfProgressFn cb, void* user, GbsurfResult** out) {
        return gbsurf_convert_file(path.c_str(), &opt.raw(), cb, user, out);
    });
}

// ---------------------------------------------------------------------------------------------
// Exact offsets: PH quintics and PN surfaces (docs/math/ph.md, docs/math/pn.md)
// ---------------------------------------------------------------------------------------------

/// A 2D point or vector.
using vec2 = std::array<double, 2>;
/// A 3D point or vector.
using vec3 = std::array<double, 3>;

/// The exact rational offset of a PH quintic: degree 9, 10 control points with weights, and the
/// parameters in [0, 1] where the offset has a cusp (ascending, possibly none).
struct ph5_offset {
    std::array<vec2, GBSURF_PH5_OFFSET_POINTS> points;
    std::array<double, GBSURF_PH5_OFFSET_POINTS> weights;
    std::vector<double> cusps;
};

/// The four planar PH quintic Hermite interpolants of r(0) = p0, r'(0) = d0, r(1) = p1,
/// r'(1) = d1 (owns a GbsurfPh5 handle; move-only; a moved-from object throws GBSURF_ERR_NULL).
class ph5 {
public:
    ph5(const vec2& p0, const vec2& d0, const vec2& p1, const vec2& d1) {
        check_abi();
        GbsurfPh5* h = nullptr;
        check(gbsurf_ph5_hermite(p0.data(), d0.data(), p1.data(), d1.data(), &h));
        h_.reset(h);
    }
    const GbsurfPh5* get() const noexcept { return h_.get(); }

    /// Always 4.
    std::size_t solution_count() const {
        std::size_t n = 0;
        check(gbsurf_ph5_solutions(get(), &n, nullptr));
        return n;
    }
    /// The solution with the least absolute rotation index (ties: least bending energy).
    std::size_t chosen() const {
        std::size_t k = 0;
        check(gbsurf_ph5_solutions(get(), nullptr, &k));
        return k;
    }
    /// The 6 Bezier control points of solution `index`.
    std::array<vec2, 6> control_points(std::size_t index) const {
        double flat[12];
        check(gbsurf_ph5_control_points(get(), index, flat));
        std::array<vec2, 6> p{};
        for (std::size_t k = 0; k < 6; ++k) {
            p[k] = {flat[2 * k], flat[2 * k + 1]};
        }
        return p;
    }
    /// Arc length, bending energy, absolute rotation index, minimum curvature radius, root signs.
    GbsurfPh5Measures measures(std::size_t index) const {
        GbsurfPh5Measures m{};
        check(gbsurf_ph5_measures(get(), index, &m));
        return m;
    }
    /// The exact offset of solution `index` at signed distance d (positive to the right).
    ph5_offset offset(std::size_t index, double d) const {
        ph5_offset o{};
        double flat[2 * GBSURF_PH5_OFFSET_POINTS];
        double cusps[GBSURF_PH5_MAX_CUSPS];
        std::size_t n = 0;
        check(gbsurf_ph5_offset(get(), index, d, flat, o.weights.data(), cusps, GBSURF_PH5_MAX_CUSPS, &n));
        for (std::size_t k = 0; k < GBSURF_PH5_OFFSET_POINTS; ++k) {
            o.points[k] = {flat[2 * k], flat[2 * k + 1]};
        }
        o.cusps.assign(cusps, cusps + n);
        return o;
    }

private:
    struct deleter {
        void operator()(GbsurfPh5* h) const noexcept { gbsurf_ph5_free(h); }
    };
    std::unique_ptr<GbsurfPh5, deleter> h_;
};

/// The exact rational form of a PN patch or its offset: homogeneous control points
/// (w x, w y, w z, w), `homogeneous[4 * (a * (degree_v + 1) + b) + c]`.
struct pn_rational {
    std::size_t degree_u = 0;
    std::size_t degree_v = 0;
    std::vector<double> homogeneous;
};

/// A G1 PN surface interpolating a rows x cols grid of points with normals (owns a GbsurfPn
/// handle; move-only; a moved-from object throws GBSURF_ERR_NULL).
class pn_surface {
public:
    /// `points` and `normals`: x y z per grid point, row-major (3 * rows * cols values each).
    pn_surface(std::size_t rows, std::size_t cols, const std::vector<double>& points, const std::vector<double>& normals) {
        check_abi();
        GbsurfPn* h = nullptr;
        check(gbsurf_pn_interpolate(rows, cols, points.data(), points.size(), normals.data(), normals.size(), &h));
        h_.reset(h);
    }
    const GbsurfPn* get() const noexcept { return h_.get(); }

    /// Patches along u (rows - 1) and along v (cols - 1).
    std::pair<std::size_t, std::size_t> patch_count() const {
        std::size_t m = 0, n = 0;
        check(gbsurf_pn_patch_count(get(), &m, &n));
        return {m, n};
    }
    /// Exact point of patch [i][j] at (u, v) in [0, 1]^2.
    vec3 point(std::size_t i, std::size_t j, double u, double v) const {
        vec3 p{};
        check(gbsurf_pn_eval(get(), i, j, u, v, p.data(), nullptr));
        return p;
    }
    /// Exact unit normal of patch [i][j] at (u, v).
    vec3 normal(std::size_t i, std::size_t j, double u, double v) const {
        vec3 p{}, n{};
        check(gbsurf_pn_eval(get(), i, j, u, v, p.data(), n.data()));
        return n;
    }
    /// The offset point x + d n.
    vec3 offset_point(std::size_t i, std::size_t j, double u, double v, double d) const {
        vec3 p{};
        check(gbsurf_pn_offset_point(get(), i, j, u, v, d, p.data()));
        return p;
    }
    /// The rational form of patch [i][j] (d = 0) or of its offset at distance d.
    pn_rational rational(std::size_t i, std::size_t j, double d = 0.0) const {
        pn_rational r;
        std::size_t n = 0;
        uint32_t status = gbsurf_pn_rational(get(), i, j, d, &r.degree_u, &r.degree_v, nullptr, 0, &n);
        if (status != GBSURF_ERR_CAPACITY) {
            check(status);
        }
        r.homogeneous.resize(n);
        check(gbsurf_pn_rational(get(), i, j, d, &r.degree_u, &r.degree_v, r.homogeneous.data(), n, &n));
        return r;
    }

private:
    struct deleter {
        void operator()(GbsurfPn* h) const noexcept { gbsurf_pn_free(h); }
    };
    std::unique_ptr<GbsurfPn, deleter> h_;
};

}  // namespace gbsurf

#endif  // GBSURF_HPP
