/* Misuse of the C API: every call must return its status code without aborting the process.
 * C11, -pedantic, the header alone. Exit status 0 when every check passes. */
#include <gbsurf.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

static int failures = 0;

#define EXPECT(call, code)                                                                        \
    do {                                                                                          \
        uint32_t got_ = (call);                                                                   \
        if (got_ != (code)) {                                                                     \
            fprintf(stderr, "%s:%d: %s returned %s, expected %s (%s)\n", __FILE__, __LINE__, #call, \
                    gbsurf_status_name(got_), gbsurf_status_name(code), gbsurf_last_error_message()); \
            ++failures;                                                                           \
        }                                                                                         \
    } while (0)

#define EXPECT_MSG(word)                                                                          \
    do {                                                                                          \
        if (strstr(gbsurf_last_error_message(), (word)) == NULL) {                                \
            fprintf(stderr, "%s:%d: message '%s' lacks '%s'\n", __FILE__, __LINE__,              \
                    gbsurf_last_error_message(), (word));                                         \
            ++failures;                                                                           \
        }                                                                                         \
    } while (0)

#define CHECK(cond)                                                                               \
    do {                                                                                          \
        if (!(cond)) {                                                                            \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);              \
            ++failures;                                                                           \
        }                                                                                         \
    } while (0)

static const double P[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t S[] = {4, 4, 4, 4, 4, 4};
static const uint32_t F[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};

static bool cancel(float fraction, void *user) {
    (void)user;
    (void)fraction;
    return false;
}

static void inputs(void) {
    GbsurfResult *r = NULL;
    double nanp[24];
    uint32_t badf[24];
    memcpy(nanp, P, sizeof P);
    memcpy(badf, F, sizeof F);

    /* NULL pointers */
    EXPECT(gbsurf_convert(P, 24, S, 6, F, 24, NULL, NULL, NULL, NULL), GBSURF_ERR_NULL);
    EXPECT_MSG("out");
    EXPECT(gbsurf_convert(NULL, 24, S, 6, F, 24, NULL, NULL, NULL, &r), GBSURF_ERR_NULL);
    EXPECT_MSG("positions");
    EXPECT(gbsurf_convert(P, 24, NULL, 6, F, 24, NULL, NULL, NULL, &r), GBSURF_ERR_NULL);
    EXPECT_MSG("face_sizes");
    EXPECT(gbsurf_convert(P, 24, S, 6, NULL, 24, NULL, NULL, NULL, &r), GBSURF_ERR_NULL);
    EXPECT_MSG("face_indices");
    EXPECT(gbsurf_convert_file(NULL, NULL, NULL, NULL, &r), GBSURF_ERR_NULL);
    CHECK(r == NULL);
    CHECK(gbsurf_last_error_length() == strlen(gbsurf_last_error_message()));

    /* wrong counts */
    EXPECT(gbsurf_convert(P, 23, S, 6, F, 24, NULL, NULL, NULL, &r), GBSURF_ERR_COUNT);
    EXPECT_MSG("23");
    EXPECT(gbsurf_convert(P, 24, S, 6, F, 20, NULL, NULL, NULL, &r), GBSURF_ERR_COUNT);
    EXPECT(gbsurf_convert(P, 24, S, 5, F, 24, NULL, NULL, NULL, &r), GBSURF_ERR_COUNT);

    /* out-of-range vertex index: face 3 corner 2 */
    badf[14] = 99;
    EXPECT(gbsurf_convert(P, 24, S, 6, badf, 24, NULL, NULL, NULL, &r), GBSURF_ERR_INDEX);
    EXPECT_MSG("face 3 corner 2");

    /* NaN and infinity: vertex 5 */
    nanp[16] = nan("");
    EXPECT(gbsurf_convert(nanp, 24, S, 6, F, 24, NULL, NULL, NULL, &r), GBSURF_ERR_NAN);
    EXPECT_MSG("vertex 5");
    nanp[16] = HUGE_VAL;
    EXPECT(gbsurf_convert(nanp, 24, S, 6, F, 24, NULL, NULL, NULL, &r), GBSURF_ERR_NAN);

    /* invalid mesh: nothing at all */
    EXPECT(gbsurf_convert(NULL, 0, NULL, 0, NULL, 0, NULL, NULL, NULL, &r), GBSURF_ERR_INVALID_MESH);
    CHECK(r == NULL);

    /* progress cancelling */
    EXPECT(gbsurf_convert(P, 24, S, 6, F, 24, NULL, cancel, NULL, &r), GBSURF_ERR_CANCELLED);
    CHECK(r == NULL);

    /* a missing file */
    EXPECT(gbsurf_convert_file("/nonexistent/x.obj", NULL, NULL, NULL, &r), GBSURF_ERR_IO);
    EXPECT_MSG("x.obj");
}

static void options(void) {
    GbsurfOptions o;
    GbsurfResult *r = NULL;
    EXPECT(gbsurf_options_init(NULL), GBSURF_ERR_NULL);
    EXPECT(gbsurf_options_init(&o), GBSURF_OK);
    CHECK(o.struct_size == sizeof o);
    EXPECT(gbsurf_options_validate(&o), GBSURF_OK);
    EXPECT(gbsurf_options_validate(NULL), GBSURF_ERR_NULL);
    o.struct_size = 8;
    EXPECT(gbsurf_options_validate(&o), GBSURF_ERR_INVALID_OPTION);
    EXPECT_MSG("struct_size");
    EXPECT(gbsurf_convert(P, 24, S, 6, F, 24, &o, NULL, NULL, &r), GBSURF_ERR_INVALID_OPTION);
    gbsurf_options_init(&o);
    o.method = 17;
    EXPECT(gbsurf_options_validate(&o), GBSURF_ERR_INVALID_OPTION);
    EXPECT_MSG("method");
    gbsurf_options_init(&o);
    o.twist = 3;
    EXPECT(gbsurf_options_validate(&o), GBSURF_ERR_INVALID_OPTION);
    gbsurf_options_init(&o);
    o.middle = 2;
    EXPECT(gbsurf_options_validate(&o), GBSURF_ERR_INVALID_OPTION);
    EXPECT_MSG("middle");
    gbsurf_options_init(&o);
    o.resolution = 0;
    EXPECT(gbsurf_options_validate(&o), GBSURF_ERR_INVALID_OPTION);
    EXPECT_MSG("resolution");
    gbsurf_options_init(&o);
    o.mid_scale = nan("");
    EXPECT(gbsurf_options_validate(&o), GBSURF_ERR_NAN);
    CHECK(r == NULL);
}

static void accessors(void) {
    GbsurfResult *r = NULL;
    GbsurfOptions o;
    const double *d = NULL;
    const uint32_t *u = NULL;
    size_t n = 0, len = 0, w = 0, deg = 0, lay = 0;
    double buf[4], xyz[3];
    GbsurfReport rep;
    const char *msg = NULL;

    /* NULL handles */
    EXPECT(gbsurf_mesh_vertex_count(NULL, &n), GBSURF_ERR_NULL);
    EXPECT(gbsurf_mesh_positions(NULL, &d, &len), GBSURF_ERR_NULL);
    EXPECT(gbsurf_mesh_copy_normals(NULL, buf, 4, &w), GBSURF_ERR_NULL);
    EXPECT(gbsurf_patch_count(NULL, &n), GBSURF_ERR_NULL);
    EXPECT(gbsurf_curve_points(NULL, 0, &d, &len), GBSURF_ERR_NULL);
    EXPECT(gbsurf_result_report(NULL, &rep), GBSURF_ERR_NULL);
    gbsurf_result_free(NULL); /* a no-op */

    gbsurf_options_init(&o);
    o.resolution = 3;
    EXPECT(gbsurf_convert(P, 24, S, 6, F, 24, &o, NULL, NULL, &r), GBSURF_OK);
    if (r == NULL) return;

    /* NULL outputs */
    EXPECT(gbsurf_mesh_vertex_count(r, NULL), GBSURF_ERR_NULL);
    EXPECT(gbsurf_mesh_positions(r, NULL, &len), GBSURF_ERR_NULL);
    EXPECT(gbsurf_mesh_triangles(r, &u, NULL), GBSURF_ERR_NULL);
    EXPECT(gbsurf_result_report(r, NULL), GBSURF_ERR_NULL);

    /* views and copies agree; too small buffers */
    EXPECT(gbsurf_mesh_vertex_count(r, &n), GBSURF_OK);
    EXPECT(gbsurf_mesh_positions(r, &d, &len), GBSURF_OK);
    CHECK(len == 3 * n && n > 0);
    EXPECT(gbsurf_mesh_copy_positions(r, buf, 4, &w), GBSURF_ERR_CAPACITY);
    CHECK(w == len);
    EXPECT(gbsurf_mesh_copy_positions(r, NULL, 0, &w), GBSURF_ERR_CAPACITY);
    CHECK(w == len);
    EXPECT(gbsurf_mesh_copy_positions(r, NULL, 1000000, &w), GBSURF_ERR_NULL);
    EXPECT(gbsurf_mesh_triangles(r, &u, &len), GBSURF_OK);
    EXPECT(gbsurf_mesh_mean_curvature(r, &d, &len), GBSURF_OK);
    CHECK(len == n);

    /* out-of-range indices */
    EXPECT(gbsurf_patch_count(r, &n), GBSURF_OK);
    CHECK(n == 8); /* dual: one patch per cube vertex */
    EXPECT(gbsurf_patch_sides(r, n, &len), GBSURF_ERR_INDEX);
    EXPECT_MSG("patch index 8");
    EXPECT(gbsurf_patch_degree(r, 0, 3, &deg, &lay), GBSURF_ERR_INDEX);
    EXPECT_MSG("side index 3");
    EXPECT(gbsurf_patch_degree(r, 0, 0, &deg, &lay), GBSURF_OK);
    EXPECT(gbsurf_patch_center(r, 0, xyz), GBSURF_OK);
    EXPECT(gbsurf_patch_ribbon_points(r, 0, 0, &d, &len), GBSURF_OK);
    CHECK(len == 3 * lay * (deg + 1));
    EXPECT(gbsurf_curve_count(r, &n), GBSURF_OK);
    EXPECT(gbsurf_curve_points(r, n, &d, &len), GBSURF_ERR_INDEX);
    EXPECT(gbsurf_warning_message(r, 1000, &msg), GBSURF_ERR_INDEX);

    /* report with a wrong struct_size */
    rep.struct_size = 4;
    EXPECT(gbsurf_result_report(r, &rep), GBSURF_ERR_INVALID_OPTION);
    rep.struct_size = sizeof rep;
    EXPECT(gbsurf_result_report(r, &rep), GBSURF_OK);
    CHECK(rep.patches == 8 && rep.closed == 1);
    gbsurf_result_free(r);

    /* topology method: CGB patches have no center */
    o.method = GBSURF_METHOD_TOPOLOGY;
    EXPECT(gbsurf_convert(P, 24, S, 6, F, 24, &o, NULL, NULL, &r), GBSURF_OK);
    if (r != NULL) {
        uint32_t kind = 99;
        EXPECT(gbsurf_patch_kind(r, 0, &kind), GBSURF_OK);
        CHECK(kind == GBSURF_PATCH_CGB);
        EXPECT(gbsurf_patch_center(r, 0, xyz), GBSURF_ERR_KIND);
        gbsurf_result_free(r);
    }
}

int main(void) {
    CHECK(gbsurf_abi_version() == GBSURF_ABI_VERSION);
    inputs();
    options();
    accessors();
    if (failures) {
        fprintf(stderr, "%d failures\n", failures);
        return 1;
    }
    printf("c_api_misuse: all checks passed\n");
    return 0;
}
