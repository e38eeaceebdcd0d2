/* The library built with one method (cargo build -p hfcast-capi --no-default-features
 * --features cone) and the header of that build (the `header` example of hfcast-capi):
 * the header declares the exact traversal and cone step mapping only, the library bakes
 * and traces with them, and it answers HF_ERR_NOT_BUILT for the methods it lacks.
 * Built by `make one-method` with -Wall -Wextra -Werror -std=c99 -pedantic. */
#include "hfcast.h"

#include "check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#if !defined(HF_HAVE_CONE) || defined(HF_HAVE_MAXMIP) || defined(HF_HAVE_SAFETY) || \
    defined(HF_HAVE_SEARCH) || defined(HF_HAVE_QDM) || defined(HF_HAVE_RELAXED)
#error "not the header of the cone-only build"
#endif

/* These names are functions of one method in the full header (the bakes of the other
 * methods go through hf_bake, which answers HF_ERR_NOT_BUILT): declaring them as objects
 * here only compiles when the header of this build does not declare them. */
static int hf_maxmip_levels = 1, hf_maxmip_bake_rows = 2, hf_maxmip_update_rect = 3;

enum { W = 33, H = 25 };

int main(void) {
    CHECK(hf_maxmip_levels + hf_maxmip_bake_rows + hf_maxmip_update_rect == 6);

    /* What the build has. */
    static const struct {
        uint32_t method, has;
    } build[] = {
        {HF_METHOD_EXACT, 1},  {HF_METHOD_LINEAR_BINARY, 0}, {HF_METHOD_LINEAR_SECANT, 0},
        {HF_METHOD_MAXMIP, 0}, {HF_METHOD_SAFETY, 0},        {HF_METHOD_CONE, 1},
        {HF_METHOD_RELAXED, 0}, {HF_METHOD_QDM, 0},          {HF_METHOD_CC, 0},
        {HF_METHOD_RADIUS, 0}, {HF_METHOD_MULTIRES, 1},
    };
    for (size_t k = 0; k < sizeof build / sizeof build[0]; k++) {
        uint32_t has = 7;
        CHECK(hf_build_has_method(build[k].method, &has) == HF_OK);
        CHECK(has == build[k].has);
        /* Functions taking a method number refuse the ones left out. */
        size_t len = 0;
        hf_result r = hf_shader_source_len(build[k].method, &len);
        CHECK(r == (build[k].has ? HF_OK : HF_ERR_NOT_BUILT));
        r = hf_map_len(build[k].method, W, H, NULL, &len);
        CHECK(r == (build[k].has ? HF_OK : HF_ERR_NOT_BUILT));
    }
    uint32_t has = 0;
    CHECK(hf_build_has_method(HF_METHOD_COUNT, &has) == HF_ERR_INVALID_ENUM);

    /* A field of bumps. */
    float heights[W * H];
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++)
            heights[j * W + i] = 3.0f + 2.0f * sinf(0.7f * (float)i) * cosf(0.5f * (float)j) +
                                 (float)((i * 7 + j * 13) % 5) * 0.3f;
    hf_field *field = NULL;
    CHECK(hf_field_create_f32(heights, W * H, W, H, W, &field) == HF_OK);
    if (!field) return 1;

    /* The one trace function refuses the methods left out, before it looks at a map. */
    hf_ray down = {{5.5f, 5.5f, 20.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, INFINITY};
    for (size_t k = 0; k < sizeof build / sizeof build[0]; k++) {
        hf_hit hit;
        hf_result r = hf_trace(field, build[k].method, NULL, 0, NULL, &down, &hit);
        if (!build[k].has) CHECK(r == HF_ERR_NOT_BUILT);
        else if (build[k].method == HF_METHOD_EXACT) CHECK(r == HF_OK && hit.hit == 1);
    }

    /* The bake plan of a cone scene: the pyramid as scratch, the cone map kept. */
    hf_scene scene;
    CHECK(hf_scene_general(HF_METHOD_CONE, HF_SURFACE_TRIANGLES, &scene) == HF_OK);
    hf_bake_plan plan;
    CHECK(hf_scene_bake_plan(&scene, &plan) == HF_OK);
    CHECK(plan.pyramid == HF_NEED_SCRATCH && plan.cone_map == HF_NEED_KEEP);
    CHECK(plan.safety_map == HF_NEED_SKIP && plan.qdm_map == HF_NEED_SKIP);

    /* Bake and trace with the one method; every hit is the exact one. */
    size_t map_len = 0;
    CHECK(hf_map_len(HF_METHOD_CONE, W, H, NULL, &map_len) == HF_OK);
    float *map = malloc(map_len * sizeof *map);
    if (!map) return 1;
    hf_bake_options bo;
    CHECK(hf_bake_options_default(HF_METHOD_CONE, &bo) == HF_OK);
    bo.threads = 2;
    CHECK(hf_bake(HF_METHOD_CONE, field, &bo, map, map_len) == HF_OK);
    /* A method left out bakes nothing. */
    CHECK(hf_bake(HF_METHOD_QDM, field, NULL, map, map_len) == HF_ERR_NOT_BUILT);
    hf_trace_options o;
    CHECK(hf_trace_options_default(&o) == HF_OK);
    o.steps = 1000;
    int hits = 0;
    for (int k = 0; k < 400; k++) {
        float a = 0.37f * (float)k, e = 0.2f + 0.6f * (float)(k % 17) / 17.0f;
        hf_ray ray = {{(float)(k % W), (float)((k * 7) % H), 12.0f},
                      {cosf(a) * cosf(e), sinf(a) * cosf(e), -sinf(e)},
                      0.0f,
                      INFINITY};
        hf_hit exact, cone;
        CHECK(hf_trace(field, HF_METHOD_EXACT, NULL, 0, NULL, &ray, &exact) == HF_OK);
        CHECK(hf_trace(field, HF_METHOD_CONE, map, map_len, &o, &ray, &cone) == HF_OK);
        CHECK(exact.hit == cone.hit);
        if (exact.hit && cone.hit) {
            hits++;
            CHECK(fabsf(exact.t - cone.t) < 1e-3f * (1.0f + exact.t));
        }
    }
    CHECK(hits > 100);
    free(map);
    hf_field_destroy(field);
    printf("one-method: %d passed, %d failed\n", checks - failures, failures);
    return failures != 0;
}
