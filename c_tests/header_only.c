/* Includes nothing but hfcast.h: proves the header stands alone. Compiled as C99 and
 * as C++ (g++), and linked, which also proves the C++ declarations are extern "C". */
#include "hfcast.h"

/* Layout the header promises (checked at compile time in both languages). */
typedef char check_ray_size[sizeof(hf_ray) == 8 * sizeof(float) ? 1 : -1];
typedef char check_ok_zero[HF_OK == 0 ? 1 : -1];
typedef char check_levels[HF_MAX_LEVELS == 25 ? 1 : -1];

int main(void) {
    check_ray_size a;
    check_ok_zero b;
    check_levels c;
    uint32_t major = 0, minor = 0, patch = 0;
    hf_result r = hf_version(&major, &minor, &patch);
    hf_surface s = HF_SURFACE_TRIANGLES;
    hf_method m = HF_METHOD_MAXMIP;
    hf_field *f = NULL;
    hf_field_destroy(f);
    (void)a;
    (void)b;
    (void)c;
    (void)s;
    (void)m;
    return (r == HF_OK && major == HFCAST_VERSION_MAJOR && minor == HFCAST_VERSION_MINOR &&
            patch == HFCAST_VERSION_PATCH)
               ? 0
               : 1;
}
