// The exact-offset classes of the C++ wrapper (gbsurf::ph5, gbsurf::pn_surface) and the C entries
// under them: results, error codes with messages, move-only ownership.
#include <gbsurf.hpp>

#include <cmath>
#include <iostream>
#include <string>
#include <type_traits>

#include "check.hpp"

static_assert(!std::is_copy_constructible<gbsurf::ph5>::value, "ph5 must not be copyable");
static_assert(std::is_nothrow_move_constructible<gbsurf::ph5>::value, "noexcept move");
static_assert(!std::is_copy_constructible<gbsurf::pn_surface>::value, "pn_surface must not be copyable");
static_assert(std::is_nothrow_move_constructible<gbsurf::pn_surface>::value, "noexcept move");

template <class Fn>
static std::pair<uint32_t, std::string> error_of(Fn f) {
    try {
        f();
    } catch (const gbsurf::error& e) {
        return {e.code(), e.what()};
    }
    return {GBSURF_OK, ""};
}

static bool contains(const std::string& s, const char* needle) { return s.find(needle) != std::string::npos; }

int main() {
    // A PH quintic from (0,0) to (2,0) with r'(0) = (1,2), r'(1) = (1,-2): a symmetric arch.
    gbsurf::ph5 c({0, 0}, {1, 2}, {2, 0}, {1, -2});
    CHECK(c.solution_count() == 4);
    std::size_t k = c.chosen();
    CHECK(k < 4);
    auto p = c.control_points(k);
    // Hermite data: the first leg is d0 / 5, the last d1 / 5, the ends are p0 and p1.
    CHECK(std::abs(p[0][0]) < 1e-14 && std::abs(p[0][1]) < 1e-14);
    CHECK(std::abs(p[1][0] - 0.2) < 1e-14 && std::abs(p[1][1] - 0.4) < 1e-14);
    CHECK(std::abs(p[5][0] - 2.0) < 1e-14 && std::abs(p[5][1]) < 1e-14);
    CHECK(std::abs(p[5][0] - p[4][0] - 0.2) < 1e-14 && std::abs(p[5][1] - p[4][1] + 0.4) < 1e-14);
    GbsurfPh5Measures m = c.measures(k);
    CHECK(m.arc_length > 2.0 && m.arc_length < 4.0);
    CHECK(m.abs_rotation_index > 0.0 && m.bending_energy > 0.0 && m.min_curvature_radius > 0.0);
    for (std::size_t s = 0; s < 4; ++s) {
        CHECK(c.measures(s).abs_rotation_index >= m.abs_rotation_index - 1e-9);
    }
    // The offset at distance d: its end points are p0 and p1 moved by d along the right normals.
    gbsurf::ph5_offset o = c.offset(k, 0.1);
    double n0 = std::sqrt(5.0);
    CHECK(std::abs(o.points[0][0] - 0.1 * 2 / n0) < 1e-14 && std::abs(o.points[0][1] + 0.1 * 1 / n0) < 1e-14);
    CHECK(std::abs(o.weights[0] - o.weights[9]) < 1e-12 && o.weights[0] > 0);
    CHECK(o.cusps.empty());
    // Beyond the smallest curvature radius on the concave side, the offset has cusps.
    gbsurf::ph5_offset far = c.offset(k, 1.2 * m.min_curvature_radius);
    CHECK(!far.cusps.empty() && far.cusps.size() <= GBSURF_PH5_MAX_CUSPS);
    for (double t : far.cusps) CHECK(t >= 0.0 && t <= 1.0);

    auto e = error_of([] { gbsurf::ph5({0, 0}, {0, 0}, {2, 0}, {1, 0}); });
    CHECK(e.first == GBSURF_ERR_DEGENERATE && contains(e.second, "derivative `d0` is zero"));
    e = error_of([] { gbsurf::ph5({0, 0}, {1, 0}, {0, 0}, {1, 0}); });
    CHECK(e.first == GBSURF_ERR_DEGENERATE && contains(e.second, "coincide"));
    e = error_of([] { gbsurf::ph5({NAN, 0}, {1, 0}, {2, 0}, {1, 0}); });
    CHECK(e.first == GBSURF_ERR_NAN && contains(e.second, "`p0` is not finite"));
    e = error_of([&] { c.offset(k, 0.0); });
    CHECK(e.first == GBSURF_ERR_DEGENERATE && contains(e.second, "offset distance `d` is zero"));
    e = error_of([&] { c.measures(4); });
    CHECK(e.first == GBSURF_ERR_INDEX);
    gbsurf::ph5 moved = std::move(c);
    CHECK(moved.chosen() == k);
    e = error_of([&] { (void)c.chosen(); });  // NOLINT(bugprone-use-after-move): the moved-from state is defined
    CHECK(e.first == GBSURF_ERR_NULL);

    // A PN surface through a 4 x 3 cap of the unit sphere (normals = points).
    std::vector<double> g;
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 3; ++j) {
            double x = 0.3 * i - 0.45, y = 0.25 * j - 0.25, z = -1.0, l = std::sqrt(x * x + y * y + z * z);
            g.insert(g.end(), {x / l, y / l, z / l});
        }
    }
    gbsurf::pn_surface s(4, 3, g, g);
    CHECK(s.patch_count() == std::make_pair(std::size_t(3), std::size_t(2)));
    // Corners interpolate the grid: patch [1][1] at (0, 0) is grid point [1][1].
    auto x = s.point(1, 1, 0.0, 0.0);
    for (int c3 = 0; c3 < 3; ++c3) CHECK(std::abs(x[c3] - g[3 * (1 * 3 + 1) + c3]) < 1e-12);
    auto nrm = s.normal(1, 1, 0.5, 0.5);
    CHECK(std::abs(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2] - 1.0) < 1e-12);
    auto q = s.point(1, 1, 0.5, 0.5);
    auto off = s.offset_point(1, 1, 0.5, 0.5, 0.5);
    double dist = std::sqrt((off[0] - q[0]) * (off[0] - q[0]) + (off[1] - q[1]) * (off[1] - q[1]) + (off[2] - q[2]) * (off[2] - q[2]));
    CHECK(std::abs(dist - 0.5) < 1e-12);
    gbsurf::pn_rational r = s.rational(1, 1);
    CHECK(r.degree_u == 11 && r.degree_v == 11 && r.homogeneous.size() == 4 * 12 * 12);
    // The rational form's corner control point is the surface's corner.
    CHECK(std::abs(r.homogeneous[0] / r.homogeneous[3] - x[0]) < 1e-9);
    gbsurf::pn_rational ro = s.rational(1, 1, 0.5);
    CHECK(ro.homogeneous.size() == r.homogeneous.size());

    e = error_of([&] { gbsurf::pn_surface(1, 12, g, g); });
    CHECK(e.first == GBSURF_ERR_COUNT && contains(e.second, "the grid is 1"));
    std::vector<double> zero = g;
    zero[3 * 5] = zero[3 * 5 + 1] = zero[3 * 5 + 2] = 0.0;
    e = error_of([&] { gbsurf::pn_surface(4, 3, g, zero); });
    CHECK(e.first == GBSURF_ERR_DEGENERATE && contains(e.second, "normal [1][2] has length zero"));
    e = error_of([&] { s.point(3, 0, 0.5, 0.5); });
    CHECK(e.first == GBSURF_ERR_INDEX && contains(e.second, "patch [3][0] does not exist"));

    // gbsurf::offset: a closed shell of a torus-like ring of 4 x 4 quads (every patch 4-sided,
    // every vertex of valence 4): PN pieces sharing data meet without gaps.
    {
        std::vector<double> pos;
        std::vector<uint32_t> sizes, idx;
        const int nu = 8, nv = 6;
        for (int i = 0; i < nu; ++i) {
            for (int j = 0; j < nv; ++j) {
                double a = 2 * M_PI * i / nu, b = 2 * M_PI * j / nv, r = 2.0 + 0.7 * std::cos(b);
                pos.insert(pos.end(), {r * std::cos(a), r * std::sin(a), 0.7 * std::sin(b)});
            }
        }
        for (int i = 0; i < nu; ++i) {
            for (int j = 0; j < nv; ++j) {
                auto at = [&](int a, int b) { return uint32_t(((a % nu) * nv) + (b % nv)); };
                sizes.push_back(4);
                idx.insert(idx.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
            }
        }
        GbsurfOffsetReport rep{};
        gbsurf::result o = gbsurf::offset(pos, sizes, idx, 0.1, gbsurf::options().resolution(4), 0, true, &rep);
        CHECK(o.vertex_count() > 0 && o.triangle_count() > 0);
        CHECK(rep.closed == 1 && rep.two_manifold == 1);
        CHECK(rep.pieces == uint64_t(nu * nv * 4));
        CHECK(rep.max_gap_pn <= 1e-12);
        // The torus's normals cover the sphere: both isotropic frames are used (seams), and the
        // PN pieces sharing data in one frame are G1.
        CHECK(rep.frame_seams > 0);
        CHECK(rep.max_normal_angle_pn <= 1e-9);
        e = error_of([&] { gbsurf::offset(pos, sizes, idx, 0.0); });
        CHECK(e.first == GBSURF_ERR_INVALID_OPTION && contains(e.second, "--distance 0"));
        e = error_of([&] { gbsurf::offset(pos, sizes, idx, 0.1, gbsurf::options(), 1); });
        CHECK(e.first == GBSURF_ERR_INVALID_OPTION && contains(e.second, "--grid 1"));
    }

    if (failures) {
        std::cerr << failures << " check(s) failed\n";
        return 1;
    }
    std::cout << "offsets_test: ok\n";
    return 0;
}
