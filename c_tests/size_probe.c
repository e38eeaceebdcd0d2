/* The C program scripts/sizes.sh links against libhfcast builds of different features
 * to measure what an application ships: a field, the exact trace, and where the build
 * has it (HF_HAVE_CONE) a cone bake and trace. Compiled against the header of the
 * build it links. */
#include "hfcast.h"

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv) {
    (void)argv;
    enum { W = 16, H = 16 };
    float heights[W * H];
    for (int k = 0; k < W * H; k++) heights[k] = (float)((k * 37 + argc) % 11);
    hf_field *field = NULL;
    if (hf_field_create_f32(heights, W * H, W, H, W, &field) != HF_OK) return 1;
    hf_ray ray = {{0.5f, 0.5f, 20.0f}, {1.0f, 0.7f, -1.0f}, 0.0f, 1e30f};
    hf_hit hit;
    int ok = hf_trace(field, HF_METHOD_EXACT, NULL, 0, NULL, &ray, &hit) == HF_OK;
#if defined(HF_HAVE_CONE)
    size_t len = 0;
    ok &= hf_map_len(HF_METHOD_CONE, W, H, NULL, &len) == HF_OK;
    float *map = malloc(len * sizeof *map);
    ok &= map && hf_bake(HF_METHOD_CONE, field, NULL, map, len) == HF_OK;
    hf_trace_options o;
    ok &= hf_trace_options_default(&o) == HF_OK;
    o.steps = 256;
    ok &= hf_trace(field, HF_METHOD_CONE, map, len, &o, &ray, &hit) == HF_OK;
    free(map);
#endif
    hf_field_destroy(field);
    printf("%d %u %.3f\n", ok, hit.hit, (double)hit.t);
    return !ok;
}
