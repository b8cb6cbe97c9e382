// The C++ wrapper without OpenMesh: handle ownership (move-only, noexcept moves), spans that
// cannot outlive their result, the ABI check, and the progress callback's thread.
#include <gbsurf.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <thread>
#include <type_traits>
#include <utility>

#include "check.hpp"

// Rule of five of the handle: move-only, moves never throw.
static_assert(!std::is_copy_constructible<gbsurf::result>::value, "result must not be copyable");
static_assert(!std::is_copy_assignable<gbsurf::result>::value, "result must not be copy-assignable");
static_assert(std::is_nothrow_move_constructible<gbsurf::result>::value, "noexcept move");
static_assert(std::is_nothrow_move_assignable<gbsurf::result>::value, "noexcept move assignment");
static_assert(std::is_nothrow_destructible<gbsurf::result>::value, "noexcept destructor");

// Views of a temporary result would dangle at the end of the full expression: they must not
// compile (`gbsurf::convert(...).positions()`), views of a named result must.
template <class R, class = void>
struct has_positions : std::false_type {};
template <class R>
struct has_positions<R, std::void_t<decltype(std::declval<R>().positions())>> : std::true_type {};
template <class R, class = void>
struct has_curve_points : std::false_type {};
template <class R>
struct has_curve_points<R, std::void_t<decltype(std::declval<R>().curve_points(0))>> : std::true_type {};
template <class R, class = void>
struct has_ribbon_points : std::false_type {};
template <class R>
struct has_ribbon_points<R, std::void_t<decltype(std::declval<R>().ribbon_points(0, 0))>> : std::true_type {};
static_assert(has_positions<const gbsurf::result&>::value, "views of a named result");
static_assert(has_positions<gbsurf::result&>::value, "views of a named result");
static_assert(!has_positions<gbsurf::result>::value, "no views of a temporary");
static_assert(!has_positions<const gbsurf::result>::value, "no views of a temporary");
static_assert(has_curve_points<gbsurf::result&>::value && !has_curve_points<gbsurf::result>::value, "curve views");
static_assert(has_ribbon_points<gbsurf::result&>::value && !has_ribbon_points<gbsurf::result>::value, "ribbon views");
template <class R, class = void>
struct has_control_net : std::false_type {};
template <class R>
struct has_control_net<R, std::void_t<decltype(std::declval<R>().control_net_edges()),
                                      decltype(std::declval<R>().curve_cubic_points(0))>> : std::true_type {};
static_assert(has_control_net<gbsurf::result&>::value && !has_control_net<gbsurf::result>::value,
              "control net and cubic curve views");

// A user function with C linkage and a plain name the wrapper might have used for its own
// callback trampoline: must not clash with anything in gbsurf.hpp.
extern "C" bool progress_trampoline(float fraction, void* user) {
    (void)user;
    return fraction >= 0.0f;
}

static const std::vector<double> P = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const std::vector<uint32_t> S = {4, 4, 4, 4, 4, 4};
static const std::vector<uint32_t> F = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};

template <class Fn>
uint32_t code_of(Fn f) {
    try {
        f();
    } catch (const gbsurf::error& e) {
        return e.code();
    }
    return GBSURF_OK;
}

int main() {
    // The ABI check: this header and the library linked agree; a mismatch is GBSURF_ERR_VERSION.
    CHECK(gbsurf_abi_version() == GBSURF_ABI_VERSION);
    CHECK(code_of([] { gbsurf::check_abi(); }) == GBSURF_OK);
    CHECK(code_of([] { gbsurf::check_abi(GBSURF_ABI_VERSION + 1); }) == GBSURF_ERR_VERSION);
    CHECK(code_of([] { gbsurf::check_abi(GBSURF_ABI_VERSION, GBSURF_ABI_VERSION + 1); }) == GBSURF_ERR_VERSION);
    CHECK(std::string(gbsurf_status_name(GBSURF_ERR_VERSION)) == "GBSURF_ERR_VERSION");

    // Moves transfer the handle; the moved-from result reports GBSURF_ERR_NULL, never crashes.
    gbsurf::result a = gbsurf::convert(P, S, F, gbsurf::options().resolution(3));
    const std::size_t nv = a.vertex_count();
    CHECK(nv > 0 && a.positions().size() == 3 * nv);
    gbsurf::result b = std::move(a);
    CHECK(b.vertex_count() == nv);
    CHECK(code_of([&] { (void)a.vertex_count(); }) == GBSURF_ERR_NULL);
    a = std::move(b);
    CHECK(a.vertex_count() == nv);

    // The derived geometry comes from the library: the control net (quads, edges, patch per
    // vertex; indices in range) and the curves as cubic chains (3k + 1 points each).
    {
        auto pos = a.control_net_positions();
        auto sizes = a.control_net_face_sizes();
        auto corners = a.control_net_face_indices();
        auto edges = a.control_net_edges();
        const std::size_t n = pos.size() / 3;
        CHECK(n > 0 && a.control_net_patch_index().size() == n);
        CHECK(!sizes.empty() && corners.size() == 4 * sizes.size());
        CHECK(edges.size() % 2 == 0 && edges.size() / 2 == 3 * a.patch_count());  // dual: 8 three-sided GB patches
        bool in_range = true;
        for (uint32_t i : corners) in_range = in_range && i < n;
        for (uint32_t i : edges) in_range = in_range && i < n;
        CHECK(in_range);
        for (std::size_t c = 0; c < a.curve_count(); ++c) {
            const auto cubic = a.curve_cubic_points(c);
            const auto points = a.curve_points(c);
            CHECK(cubic.size() == 12);
            CHECK(std::equal(cubic.begin(), cubic.end(), points.begin(), points.end()));
        }
        CHECK(code_of([&] { (void)a.curve_cubic_points(a.curve_count()); }) == GBSURF_ERR_INDEX);
    }

    // Cage attributes at the output's face corners (keep corners): the cage positions per face
    // corner as the attribute; at a loop in cage corner (f, k) with coordinates (0, 0) the value
    // is that corner's vertex, at (1, 1) the face centre; sizes of another cage are an error.
    {
        std::vector<float> values;
        for (uint32_t v : F)
            for (int c = 0; c < 3; ++c) values.push_back(static_cast<float>(P[3 * v + c]));
        const auto uv = a.cage_loop_values(S, values, 3);
        const auto corner = a.cage_corner();
        std::size_t loops = uv.size() / 3, at_vertex = 0, at_centre = 0;
        CHECK(loops == 4 * a.quad_count());
        std::vector<double> coords;
        {
            const double* d = nullptr;
            std::size_t len = 0;
            CHECK(gbsurf_mesh_cage_coords(a.get(), &d, &len) == GBSURF_OK && len == 2 * loops);
            coords.assign(d, d + len);
        }
        bool exact = true;
        for (std::size_t i = 0; i < loops; ++i) {
            const uint32_t f = corner[2 * (i / 4)], k = corner[2 * (i / 4) + 1];
            const double s = coords[2 * i], t = coords[2 * i + 1];
            for (int c = 0; c < 3; ++c) {
                if (s == 0 && t == 0) exact = exact && uv[3 * i + c] == values[3 * (4 * f + k) + c];
                if (s == 1 && t == 1) {
                    float mean = 0;
                    for (int j = 0; j < 4; ++j) mean += values[3 * (4 * f + j) + c];
                    exact = exact && std::abs(uv[3 * i + c] - mean / 4) < 1e-6f;
                }
            }
            at_vertex += s == 0 && t == 0;
            at_centre += s == 1 && t == 1;
        }
        CHECK(exact && at_vertex > 0 && at_centre > 0);
        CHECK(code_of([&] { (void)a.cage_loop_values({4, 4}, std::vector<float>(24), 3); }) == GBSURF_ERR_INDEX);
        CHECK(code_of([&] { (void)a.cage_loop_values(S, std::vector<float>(5), 3); }) == GBSURF_ERR_COUNT);
    }

    // Validity in the report: the unit cube is valid (no self-intersections, so its cage is not
    // checked: GBSURF_NOT_CHECKED); OpenSubdiv's bishop with its crease tags has dual patches
    // that turn over (docs/math.md#folds), and the fold sites name folded patches. (A cube with a corner pulled inside served
    // here until the fold rule's blended reference: its dual patches only bend.)
    {
        CHECK(a.report().valid == 1 && a.report().folds == 0 && a.fold_sites().empty());
        CHECK(a.report().self_intersections == 0 && a.report().input_self_intersections == GBSURF_NOT_CHECKED);
        gbsurf::result f = gbsurf::convert_file(GBSURF_FOLDED_CAGE, gbsurf::options().method(gbsurf::method::dual).resolution(3));
        const GbsurfReport rep = f.report();
        CHECK(rep.valid == 0 && rep.folds > 0 && rep.input_closed == 0);
        const auto sites = f.fold_sites();
        CHECK(sites.size() == rep.fold_sites && !sites.empty());
        for (const auto& s : sites) CHECK(s.patch < f.patch_count() && std::isfinite(s.u) && std::isfinite(s.v));
    }

    // The progress callback runs on the calling thread only (the library's workers never call
    // it), so a std::function with unsynchronized state is safe.
    const auto caller = std::this_thread::get_id();
    int calls = 0, foreign = 0;
    float last = -1.0f;
    bool monotone = true;
    gbsurf::result r = gbsurf::convert(P, S, F, gbsurf::options().resolution(16), [&](float f) {
        ++calls;
        if (std::this_thread::get_id() != caller) ++foreign;
        if (f < last) monotone = false;
        last = f;
        return true;
    });
    CHECK(calls > 1);
    CHECK(foreign == 0);
    CHECK(monotone && last == 1.0f);
    CHECK(progress_trampoline(0.5f, nullptr));

    // Creases: the cube with every edge infinitely sharp keeps its corners (topology method);
    // bad creases throw with the library's codes.
    {
        gbsurf::creases cr;
        for (std::size_t f = 0; f < 6; ++f)
            for (std::size_t i = 0; i < 4; ++i) {
                const uint32_t u = F[4 * f + i], v = F[4 * f + (i + 1) % 4];
                if (u < v) cr.edge(u, v, 1.0);
            }
        CHECK(cr.edge_sharpness.size() == 12);
        const auto opt = gbsurf::options().method(gbsurf::method::topology).resolution(4);
        gbsurf::result c = gbsurf::convert(P, S, F, cr, opt);
        auto pos = c.positions().to_vector();
        double lo = 1.0, hi = 0.0;
        for (double x : pos) {
            lo = x < lo ? x : lo;
            hi = x > hi ? x : hi;
        }
        CHECK(lo > -1e-12 && lo < 1e-12 && hi > 1.0 - 1e-12 && hi < 1.0 + 1e-12);
        std::size_t corners = 0;
        for (std::size_t k = 0; k < P.size(); k += 3)
            for (std::size_t j = 0; j + 2 < pos.size(); j += 3)
                if (std::fabs(pos[j] - P[k]) + std::fabs(pos[j + 1] - P[k + 1]) + std::fabs(pos[j + 2] - P[k + 2]) <= 1e-12) {
                    ++corners;
                    break;
                }
        CHECK(corners == 8);
        CHECK(code_of([&] { gbsurf::convert(P, S, F, gbsurf::creases().edge(0, 2, 1.0), opt); }) == GBSURF_ERR_INVALID_MESH);
        CHECK(code_of([&] { gbsurf::convert(P, S, F, gbsurf::creases().corner(9, 1.0), opt); }) == GBSURF_ERR_INDEX);
        CHECK(code_of([&] { gbsurf::convert(P, S, F, gbsurf::creases().edge(0, 1, std::nan("")), opt); }) == GBSURF_ERR_NAN);
        gbsurf::creases odd;
        odd.edge_vertices = {0};
        CHECK(code_of([&] { gbsurf::convert(P, S, F, odd, opt); }) == GBSURF_ERR_COUNT);
    }

    // Faces with holes: a slab over [-2, 2]^2 with the hole [-1, 1]^2 through it (top face 0 and
    // bottom face 1 carry one inner loop each) converts to a closed G1 surface; bad holes throw.
    {
        std::vector<double> hp;
        for (double r : {2.0, 1.0})
            for (double z : {0.0, 1.0})
                for (int k = 0; k < 4; ++k) {
                    const double x[4] = {-r, r, r, -r}, y[4] = {-r, -r, r, r};
                    hp.insert(hp.end(), {x[k], y[k], z});
                }
        const std::vector<uint32_t> hs(10, 4);
        const std::vector<uint32_t> hf = {4, 5, 6, 7, 3, 2, 1, 0, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6,
                                          3, 0, 4, 7, 9, 8, 12, 13, 10, 9, 13, 14, 11, 10, 14, 15, 8, 11, 15, 12};
        gbsurf::holes h;
        h.add(0, {15, 14, 13, 12}).add(1, {8, 9, 10, 11});
        const auto opt = gbsurf::options().resolution(4);
        gbsurf::result c = gbsurf::convert(hp, hs, hf, h, opt);
        const GbsurfReport r = c.report();
        CHECK(r.closed && r.two_manifold);
        CHECK(r.max_g1_deg <= 1e-4);
        // Cage values in the user's numbering: face 0's corners are its outer loop (4) then its
        // hole (4); the cage positions as values come back at the loops' cage vertices.
        {
            std::vector<std::vector<uint32_t>> loops;
            for (std::size_t f = 0; f < hs.size(); ++f) loops.emplace_back(hf.begin() + 4 * f, hf.begin() + 4 * f + 4);
            loops[0].insert(loops[0].end(), {15, 14, 13, 12});
            loops[1].insert(loops[1].end(), {8, 9, 10, 11});
            std::vector<float> values;
            for (const auto& l : loops)
                for (uint32_t v : l)
                    for (int k = 0; k < 3; ++k) values.push_back(static_cast<float>(hp[3 * v + k]));
            const auto out = c.cage_loop_values(hs, h, values, 3);
            const auto corner = c.cage_corner();
            const double* d = nullptr;
            std::size_t len = 0;
            CHECK(gbsurf_mesh_cage_coords(c.get(), &d, &len) == GBSURF_OK && out.size() == 3 * (len / 2));
            bool exact = true, past_outer = false;
            for (std::size_t i = 0; i < len / 2; ++i) {
                const uint32_t f = corner[2 * (i / 4)], k = corner[2 * (i / 4) + 1];
                past_outer = past_outer || (f < 2 && k >= 4);
                if (d[2 * i] == 0 && d[2 * i + 1] == 0)
                    for (int c3 = 0; c3 < 3; ++c3)
                        exact = exact && out[3 * i + c3] == static_cast<float>(hp[3 * loops[f][k] + c3]);
            }
            CHECK(exact && past_outer);
            CHECK(code_of([&] { (void)c.cage_loop_values(hs, values, 3); }) == GBSURF_ERR_COUNT);
            CHECK(code_of([&] { (void)c.cage_loop_values(hs, gbsurf::holes().add(99, {8, 9, 10, 11}), values, 3); }) ==
                  GBSURF_ERR_INDEX);
        }
        gbsurf::holes wrong;
        wrong.add(0, {12, 13, 14, 15});
        CHECK(code_of([&] { gbsurf::convert(hp, hs, hf, wrong, opt); }) == GBSURF_ERR_INVALID_MESH);
        CHECK(code_of([&] { gbsurf::convert(hp, hs, hf, gbsurf::holes().add(99, {8, 9, 10}), opt); }) == GBSURF_ERR_INDEX);
        gbsurf::holes odd;
        odd.faces = {0};
        CHECK(code_of([&] { gbsurf::convert(hp, hs, hf, odd, opt); }) == GBSURF_ERR_COUNT);
    }

    if (failures) {
        std::cerr << failures << " failures\n";
        return 1;
    }
    std::cout << "wrapper_test: all checks passed\n";
    return 0;
}
