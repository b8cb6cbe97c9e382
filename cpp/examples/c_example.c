/* A C11 program that uses gbsurf.h alone: convert a cube, print the figures, show an error.
 * Build: cc -std=c11 -pedantic c_example.c $(pkg-config --cflags --libs gbsurf) */
#include <gbsurf.h>

#include <stdio.h>
#include <stdlib.h>

static bool print_progress(float fraction, void *user_data) {
    int *calls = (int *)user_data;
    ++*calls;
    (void)fraction;
    return true;
}

int main(void) {
    static const double positions[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                       0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    static const uint32_t face_sizes[] = {4, 4, 4, 4, 4, 4};
    static const uint32_t faces[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                     1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    GbsurfOptions options;
    GbsurfResult *result = NULL;
    GbsurfReport report;
    size_t vertices = 0, triangles = 0, patches = 0, curves = 0;
    int calls = 0;
    uint32_t status;

    printf("gbsurf %s (ABI %u)\n", gbsurf_version(), (unsigned)gbsurf_abi_version());
    gbsurf_options_init(&options);
    options.method = GBSURF_METHOD_DUAL;
    options.resolution = 6;
    status = gbsurf_convert(positions, sizeof positions / sizeof *positions, face_sizes, 6, faces,
                            sizeof faces / sizeof *faces, &options, print_progress, &calls, &result);
    if (status != GBSURF_OK) {
        fprintf(stderr, "convert failed: %s: %s\n", gbsurf_status_name(status), gbsurf_last_error_message());
        return 1;
    }
    gbsurf_mesh_vertex_count(result, &vertices);
    gbsurf_mesh_triangle_count(result, &triangles);
    gbsurf_patch_count(result, &patches);
    gbsurf_curve_count(result, &curves);
    report.struct_size = sizeof report;
    gbsurf_result_report(result, &report);
    printf("%zu vertices, %zu triangles, %zu patches, %zu curves, closed %u, max G1 %g deg, %d progress calls\n",
           vertices, triangles, patches, curves, (unsigned)report.closed, report.max_g1_deg, calls);
    gbsurf_result_free(result);

    /* An error: vertex index 8 does not exist. */
    {
        static const uint32_t bad_faces[] = {0, 1, 8};
        static const uint32_t bad_sizes[] = {3};
        status = gbsurf_convert(positions, 24, bad_sizes, 1, bad_faces, 3, NULL, NULL, NULL, &result);
        printf("expected error: %s: %s\n", gbsurf_status_name(status), gbsurf_last_error_message());
        if (status != GBSURF_ERR_INDEX || result != NULL) return 1;
    }
    return 0;
}
