/* gbsurf.h alone must compile as C99 with -pedantic-errors (built as an object, never run). */
#include <gbsurf.h>

uint32_t gbsurf_header_c99_probe(void);
uint32_t gbsurf_header_c99_probe(void) {
    GbsurfOptions o;
    GbsurfProgressFn cb = 0;
    (void)cb;
    return gbsurf_options_init(&o) + GBSURF_ABI_VERSION + GBSURF_ERR_VERSION;
}
