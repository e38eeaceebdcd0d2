/* API tests of libhfcast: every bad input returns its error code and writes nothing;
 * good queries match known values; the methods agree with each other.
 * Built by the Makefile with -Wall -Wextra -Werror -std=c99, run plain, under
 * -fsanitize=address,undefined, and under valgrind. */
#define _POSIX_C_SOURCE 200112L
#include "hfcast.h"

#include "check_api.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* An output that is not there: nothing to compare. */
static unsigned char nothing[1];

static int near(float a, float b, float tol) { return fabsf(a - b) <= tol; }

static hf_ray ray(float ox, float oy, float oz, float dx, float dy, float dz) {
    hf_ray r;
    r.origin[0] = ox;
    r.origin[1] = oy;
    r.origin[2] = oz;
    r.dir[0] = dx;
    r.dir[1] = dy;
    r.dir[2] = dz;
    r.t_min = 0.0f;
    r.t_max = INFINITY;
    return r;
}

/* Rays of `got` that agree with `want`: same hit or miss, points within 1e-3. */
static int agreeing(const hf_hit *want, const hf_hit *got, int n) {
    int same = 0;
    for (int k = 0; k < n; k++)
        same += want[k].hit == got[k].hit &&
                (!want[k].hit || (near(want[k].point[0], got[k].point[0], 1e-3f) &&
                                  near(want[k].point[1], got[k].point[1], 1e-3f) &&
                                  near(want[k].point[2], got[k].point[2], 1e-3f)));
    return same;
}

/* The default trace options with surface `surface`. */
static hf_trace_options on(uint32_t surface) {
    hf_trace_options o;
    hf_trace_options_default(&o);
    o.surface = surface;
    return o;
}

/* The default trace options with surface `surface` and the step budgets `steps`
 * (linear steps, cone iterations) and `binary` (bisections). */
static hf_trace_options budget(uint32_t surface, uint32_t steps, uint32_t binary) {
    hf_trace_options o = on(surface);
    o.steps = steps;
    o.binary_steps = binary;
    return o;
}

/* A map and its field (the method, the ray classes the trace names: 0 for the
 * descriptor's), for trace_on below. */
struct safety_ctx {
    hf_field *f;
    uint32_t method;
    const unsigned char *map;
    size_t len;
    uint32_t classes;
};

/* The `n` rays traced with the map of `c` on `surface`. */
static hf_result trace_on(const struct safety_ctx *c, uint32_t surface, const hf_ray *rays, int n,
                          hf_hit *out) {
    hf_trace_options o = on(surface);
    o.ray_classes = c->classes;
    return hf_trace_batch(c->f, c->method, c->map, c->len, &o, rays, (size_t)n, out, (size_t)n);
}

/* The view-linear surface (Baboud et al. §7) from maps baked for triangles: the map of
 * `ctx` fills `out` for all `n` rays on that surface; it must give the exact method's
 * hits there, which differ from the triangle surface's. */
static int view_linear_agrees(hf_field *f, const hf_ray *rays, int n, hf_hit *out,
                              const struct safety_ctx *ctx) {
    hf_hit *tri = (hf_hit *)malloc(sizeof(hf_hit) * n);
    hf_hit *vl = (hf_hit *)malloc(sizeof(hf_hit) * n);
    hf_trace_options o = on(HF_SURFACE_VIEW_LINEAR);
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, n, tri, n));
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &o, rays, n, vl, n));
    CHECK_OK(trace_on(ctx, HF_SURFACE_VIEW_LINEAR, rays, n, out));
    int same = agreeing(vl, out, n);
    CHECK(same == n);
    CHECK(agreeing(tri, vl, n) < n);
    /* Surfaces the maps do not bound are refused; unknown ones are bad enums. */
    CHECK(trace_on(ctx, HF_SURFACE_BILINEAR, rays, n, out) == HF_ERR_INVALID_ARGUMENT);
    CHECK(trace_on(ctx, 99, rays, n, out) == HF_ERR_INVALID_ENUM);
    free(tri);
    free(vl);
    return same;
}

/* ---- version and messages ---------------------------------------------------- */

static void test_version_and_messages(void) {
    uint32_t ma = 99, mi = 99, pa = 99;
    CHECK_OK(hf_version(&ma, &mi, &pa));
    CHECK(ma == HFCAST_VERSION_MAJOR && mi == HFCAST_VERSION_MINOR &&
          pa == HFCAST_VERSION_PATCH);
    char s[32];
    snprintf(s, sizeof s, "%u.%u.%u", (unsigned)ma, (unsigned)mi, (unsigned)pa);
    CHECK(strcmp(s, HFCAST_VERSION_STRING) == 0);
    CHECK_BAD(hf_version(NULL, &mi, &pa), HF_ERR_NULL_POINTER, &mi, sizeof mi);
    CHECK_BAD(hf_version(&ma, NULL, &pa), HF_ERR_NULL_POINTER, &ma, sizeof ma);
    CHECK_BAD(hf_version(&ma, &mi, NULL), HF_ERR_NULL_POINTER, &ma, sizeof ma);

    char buf[128];
    size_t written = 777;
    for (uint32_t code = 0; code <= HF_ERR_STALE_MAP; code++) {
        memset(buf, 'x', sizeof buf);
        CHECK_OK(hf_error_message(code, buf, sizeof buf, &written));
        CHECK(written > 0 && written < sizeof buf && buf[written] == 0 &&
              strlen(buf) == written);
    }
    CHECK_OK(hf_error_message(HF_OK, buf, sizeof buf, &written));
    CHECK(strcmp(buf, "success") == 0);
    memset(buf, 'x', sizeof buf);
    written = 777;
    CHECK_BAD(hf_error_message(HF_ERR_STALE_MAP + 1, buf, sizeof buf, &written),
              HF_ERR_INVALID_ENUM, buf, sizeof buf);
    CHECK_BAD(hf_error_message(0xFFFFFFFFu, buf, sizeof buf, &written),
              HF_ERR_INVALID_ENUM, &written, sizeof written);
    CHECK_BAD(hf_error_message(HF_OK, NULL, sizeof buf, &written), HF_ERR_NULL_POINTER,
              &written, sizeof written);
    CHECK_BAD(hf_error_message(HF_OK, buf, sizeof buf, NULL), HF_ERR_NULL_POINTER, buf,
              sizeof buf);
    /* "success" needs 8 bytes with its NUL. */
    CHECK_BAD(hf_error_message(HF_OK, buf, 7, &written), HF_ERR_BUFFER_TOO_SMALL, buf,
              sizeof buf);
    CHECK_BAD(hf_error_message(HF_OK, buf, 0, &written), HF_ERR_BUFFER_TOO_SMALL,
              &written, sizeof written);
    CHECK_OK(hf_error_message(HF_OK, buf, 8, &written));
    CHECK(written == 7);
}

/* ---- fields ------------------------------------------------------------------ */

static void test_field_constructors(void) {
    const float h4[4] = {0.0f, 1.0f, 1.0f, 2.0f};
    hf_field *f = NULL;
    hf_field *sentinel = (hf_field *)(uintptr_t)0x1234;
    hf_field *out = sentinel;

    /* NULL pointers, sizes, buffer lengths, non-finite values. */
    CHECK_BAD(hf_field_create_f32(NULL, 4, 2, 2, 2, &out), HF_ERR_NULL_POINTER, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 2, 2, 2, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_field_create_f32(h4, 4, 0, 2, 2, &out), HF_ERR_INVALID_SIZE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 1, 2, 2, &out), HF_ERR_INVALID_SIZE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 2, 1, 2, &out), HF_ERR_INVALID_SIZE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 2, 0, 2, &out), HF_ERR_INVALID_SIZE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, HF_MAX_SIDE + 1u, 2, HF_MAX_SIDE + 1u, &out),
              HF_ERR_INVALID_SIZE, &out, sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 2, 0xFFFFFFFFu, 2, &out), HF_ERR_INVALID_SIZE,
              &out, sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 2, 2, 1, &out), HF_ERR_INVALID_SIZE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 2, 3, SIZE_MAX / 2, &out), HF_ERR_INVALID_SIZE,
              &out, sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, SIZE_MAX, 2, 2, 2, &out), HF_ERR_INVALID_SIZE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 3, 2, 2, 2, &out), HF_ERR_BUFFER_TOO_SMALL, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 0, 2, 2, 2, &out), HF_ERR_BUFFER_TOO_SMALL, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 2, 2, 3, &out), HF_ERR_BUFFER_TOO_SMALL, &out,
              sizeof out);
    const float hnan[4] = {0.0f, NAN, 1.0f, 2.0f};
    const float hinf[4] = {0.0f, 1.0f, -INFINITY, 2.0f};
    CHECK_BAD(hf_field_create_f32(hnan, 4, 2, 2, 2, &out), HF_ERR_NOT_FINITE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_f32(hinf, 4, 2, 2, 2, &out), HF_ERR_NOT_FINITE, &out,
              sizeof out);
    /* A misaligned float pointer. */
    float storage[8] = {0};
    const float *misaligned = (const float *)((const char *)storage + 1);
    CHECK_BAD(hf_field_create_f32(misaligned, 4, 2, 2, 2, &out),
              HF_ERR_MISALIGNED_POINTER, &out, sizeof out);

    const uint8_t s8[6] = {0, 255, 51, 0, 0, 0};
    CHECK_BAD(hf_field_create_u8(NULL, 6, 3, 2, 3, 10.0f, &out), HF_ERR_NULL_POINTER, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_u8(s8, 6, 3, 2, 3, NAN, &out), HF_ERR_NOT_FINITE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_u8(s8, 6, 3, 2, 3, INFINITY, &out), HF_ERR_NOT_FINITE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_u8(s8, 5, 3, 2, 3, 10.0f, &out), HF_ERR_BUFFER_TOO_SMALL,
              &out, sizeof out);
    CHECK_BAD(hf_field_create_u8(s8, 6, 3, 2, 2, 10.0f, &out), HF_ERR_INVALID_SIZE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_u8(s8, 6, 3, 2, 3, 10.0f, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    const uint16_t s16[4] = {0, 65535, 13107, 0};
    CHECK_BAD(hf_field_create_u16(NULL, 4, 2, 2, 2, 10.0f, &out), HF_ERR_NULL_POINTER,
              &out, sizeof out);
    CHECK_BAD(hf_field_create_u16(s16, 4, 2, 2, 2, NAN, &out), HF_ERR_NOT_FINITE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_u16(s16, 3, 2, 2, 2, 10.0f, &out), HF_ERR_BUFFER_TOO_SMALL,
              &out, sizeof out);
    CHECK_BAD(hf_field_create_u16(s16, 4, 2, 1, 2, 10.0f, &out), HF_ERR_INVALID_SIZE, &out,
              sizeof out);
    CHECK_BAD(hf_field_create_u16((const uint16_t *)((const char *)storage + 1), 4, 2, 2,
                                  2, 10.0f, &out),
              HF_ERR_MISALIGNED_POINTER, &out, sizeof out);
    CHECK(out == sentinel);

    /* Good constructors. */
    hf_field_info info;
    CHECK_OK(hf_field_create_f32(h4, 4, 2, 2, 2, &f));
    CHECK_OK(hf_field_get_info(f, &info));
    CHECK(info.width == 2 && info.height == 2 && info.min_height == 0.0f &&
          info.max_height == 2.0f);
    memset(&info, 0xAB, sizeof info);
    CHECK_BAD(hf_field_get_info(NULL, &info), HF_ERR_NULL_POINTER, &info, sizeof info);
    CHECK_BAD(hf_field_get_info(f, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    float copy[4] = {-1, -1, -1, -1};
    CHECK_BAD(hf_field_copy_heights(f, copy, 3), HF_ERR_BUFFER_TOO_SMALL, copy, sizeof copy);
    CHECK_BAD(hf_field_copy_heights(NULL, copy, 4), HF_ERR_NULL_POINTER, copy, sizeof copy);
    CHECK_BAD(hf_field_copy_heights(f, NULL, 4), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_OK(hf_field_copy_heights(f, copy, 4));
    CHECK(memcmp(copy, h4, sizeof h4) == 0);
    hf_field_destroy(f);
    hf_field_destroy(NULL);

    /* Strided f32: a 2 x 2 field inside rows of 3. */
    const float strided[5] = {0.0f, 1.0f, 99.0f, 1.0f, 2.0f};
    CHECK_OK(hf_field_create_f32(strided, 5, 2, 2, 3, &f));
    CHECK_OK(hf_field_copy_heights(f, copy, 4));
    CHECK(memcmp(copy, h4, sizeof h4) == 0);
    hf_field_destroy(f);

    /* 8-bit: 255 -> depth, 51 -> depth / 5. */
    CHECK_OK(hf_field_create_u8(s8, 6, 3, 2, 3, 10.0f, &f));
    float c6[6];
    CHECK_OK(hf_field_copy_heights(f, c6, 6));
    CHECK(c6[0] == 0.0f && near(c6[1], 10.0f, 1e-5f) && near(c6[2], 2.0f, 1e-5f));
    hf_field_destroy(f);
    /* 16-bit: 65535 -> depth, 13107 -> depth / 5. */
    CHECK_OK(hf_field_create_u16(s16, 4, 2, 2, 2, 10.0f, &f));
    CHECK_OK(hf_field_copy_heights(f, copy, 4));
    CHECK(copy[0] == 0.0f && near(copy[1], 10.0f, 1e-5f) && near(copy[2], 2.0f, 1e-5f));
    hf_field_destroy(f);
}

/* ---- single-ray queries with known answers ----------------------------------------- */

/* Floats of a 2 x 2 field's pyramid: one texel and the descriptor. */
#define P1 (1 + HF_MAP_DESC_BYTES / 4)

/* A method and its map (NULL and 0 for none). */
typedef struct method_map {
    uint32_t method;
    const void *map;
    size_t len;
} method_map;

/* The methods a 2 x 2 field traces with its pyramid `pyr` (P1 floats): exact, the two
 * searches and the maximum mipmap. */
static void four_methods(const float *pyr, method_map four[4]) {
    const method_map m[4] = {{HF_METHOD_EXACT, NULL, 0},
                             {HF_METHOD_LINEAR_BINARY, NULL, 0},
                             {HF_METHOD_LINEAR_SECANT, NULL, 0},
                             {HF_METHOD_MAXMIP, pyr, P1}};
    memcpy(four, m, sizeof m);
}

static void test_known_hits(void) {
    const float h4[4] = {0.0f, 1.0f, 1.0f, 2.0f};
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(h4, 4, 2, 2, 2, &f));
    size_t plen = 0;
    CHECK_OK(hf_maxmip_len(2, 2, &plen));
    CHECK(plen == P1);
    float pyr[P1];
    CHECK_OK(hf_maxmip_bake(f, pyr, P1));
    CHECK(pyr[0] == 2.0f);

    /* A vertical ray onto the plane z = x + y at (0.5, 0.5): z = 1, t = 4. */
    hf_ray r = ray(0.5f, 0.5f, 5.0f, 0.0f, 0.0f, -1.0f);
    hf_hit h;
    /* Exact, the searches (64 steps, 24 bisections) and the pyramid. */
    method_map four[4];
    four_methods(pyr, four);
    hf_trace_options o = budget(HF_SURFACE_TRIANGLES, 64, 24);
    for (uint32_t m = 0; m < 4; m++) {
        memset(&h, 0, sizeof h);
        hf_result res = hf_trace(f, four[m].method, four[m].map, four[m].len, &o, &r, &h);
        CHECK(res == HF_OK);
        CHECK(h.hit == 1 && h.flags == 0 && h.cell[0] == 0 && h.cell[1] == 0);
        CHECK(near(h.t, 4.0f, 1e-4f) && near(h.point[2], 1.0f, 1e-4f));
        CHECK(near(h.point[0], 0.5f, 1e-6f) && near(h.point[1], 0.5f, 1e-6f));
        float n = 1.0f / sqrtf(3.0f);
        CHECK(near(h.normal[0], -n, 1e-5f) && near(h.normal[1], -n, 1e-5f) &&
              near(h.normal[2], n, 1e-5f));
        CHECK(h.fetches >= 4);
    }
    CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, NULL, &r, &h));
    CHECK(h.fetches == 4 && h.t == 4.0f && h.point[2] == 1.0f);

    /* Every surface of this field is the plane z = x + y except height planes. */
    for (uint32_t s = HF_SURFACE_TRIANGLES; s <= HF_SURFACE_VIEW_LINEAR; s++) {
        o = on(s);
        CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, &o, &r, &h));
        CHECK(h.hit == 1);
        if (s == HF_SURFACE_HEIGHT_PLANES) {
            CHECK(near(h.point[2], 2.0f, 1e-6f)); /* (0.5, 0.5) ties to sample (1, 1) */
        } else {
            CHECK(near(h.point[2], 1.0f, 1e-5f));
        }
    }

    /* Under the surface: hit at t_min, flagged. */
    r = ray(0.5f, 0.5f, 0.25f, 1.0f, 0.0f, 0.0f);
    r.t_min = 0.0f;
    CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, NULL, &r, &h));
    CHECK(h.hit == 1 && h.t == 0.0f && (h.flags & HF_FLAG_ORIGIN_INSIDE));
    CHECK_OK(hf_trace(f, HF_METHOD_MAXMIP, pyr, P1, NULL, &r, &h));
    CHECK(h.hit == 1 && h.t == 0.0f && (h.flags & HF_FLAG_ORIGIN_INSIDE));

    /* A horizontal ray entering the side x = 0 below the edge: a side hit at x = 0. */
    r = ray(-3.0f, 0.75f, 0.5f, 1.0f, 0.0f, 0.0f);
    CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, NULL, &r, &h));
    CHECK(h.hit == 1 && (h.flags & HF_FLAG_SIDE) && near(h.t, 3.0f, 1e-6f) &&
          h.normal[0] == -1.0f);

    /* Upwards from above: a miss that reads nothing or little. */
    r = ray(0.5f, 0.5f, 3.0f, 0.1f, 0.2f, 1.0f);
    CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, NULL, &r, &h));
    CHECK(h.hit == 0 && h.t == 0.0f);
    /* Outside the footprint. */
    r = ray(10.0f, 10.0f, 0.0f, 0.0f, 0.0f, -1.0f);
    CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, NULL, &r, &h));
    CHECK(h.hit == 0 && h.fetches == 0);
    /* t_max before the surface. */
    r = ray(0.5f, 0.5f, 5.0f, 0.0f, 0.0f, -1.0f);
    r.t_max = 3.5f;
    CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, NULL, &r, &h));
    CHECK(h.hit == 0);
    hf_field_destroy(f);
}

/* ---- bad query inputs ----------------------------------------------------------- */

static void test_bad_queries(void) {
    const float h4[4] = {0.0f, 1.0f, 1.0f, 2.0f};
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(h4, 4, 2, 2, 2, &f));
    float pyr[P1];
    CHECK_OK(hf_maxmip_bake(f, pyr, P1));
    hf_ray good = ray(0.5f, 0.5f, 5.0f, 0.0f, 0.0f, -1.0f);
    hf_hit h;
    memset(&h, 0x5A, sizeof h);
    method_map four[4];
    four_methods(pyr, four);
    hf_trace_options o = budget(HF_SURFACE_TRIANGLES, 8, 8);

    hf_ray bad[9];
    hf_result bad_code = HF_ERR_INVALID_RAY;
    for (int k = 0; k < 9; k++) bad[k] = good;
    bad[0].origin[0] = NAN;
    bad[1].origin[2] = INFINITY;
    bad[2].dir[1] = NAN;
    bad[3].dir[2] = -INFINITY;
    bad[4].dir[2] = 0.0f; /* zero direction */
    bad[5].t_min = NAN;
    bad[6].t_min = -INFINITY;
    bad[7].t_max = NAN;
    bad[8].t_min = 2.0f;
    bad[8].t_max = 1.0f; /* empty range */

    for (int k = 0; k < 9; k++)
        for (int m = 0; m < 4; m++)
            CHECK_BAD(hf_trace(f, four[m].method, four[m].map, four[m].len, &o, &bad[k], &h),
                      bad_code, &h, sizeof h);
    /* NULL pointers, unknown enums, zero steps of every method. */
    const uint32_t bad_surfaces[3] = {5, 6, 0xFFFFFFFFu};
    for (int m = 0; m < 4; m++) {
        uint32_t me = four[m].method;
        const void *map = four[m].map;
        size_t len = four[m].len;
        CHECK_BAD(hf_trace(NULL, me, map, len, &o, &good, &h), HF_ERR_NULL_POINTER, &h, sizeof h);
        CHECK_BAD(hf_trace(f, me, map, len, &o, NULL, &h), HF_ERR_NULL_POINTER, &h, sizeof h);
        CHECK_BAD(hf_trace(f, me, map, len, &o, &good, NULL), HF_ERR_NULL_POINTER, nothing, 0);
        for (int k = 0; k < 3; k++) {
            hf_trace_options bs = budget(bad_surfaces[k], 8, 8);
            CHECK_BAD(hf_trace(f, me, map, len, &bs, &good, &h), HF_ERR_INVALID_ENUM, &h, sizeof h);
        }
    }
    CHECK_BAD(hf_trace(f, HF_METHOD_MAXMIP, NULL, 1, &o, &good, &h), HF_ERR_NULL_POINTER, &h,
              sizeof h);
    hf_trace_options zero = budget(HF_SURFACE_TRIANGLES, 0, 8);
    CHECK_BAD(hf_trace(f, HF_METHOD_LINEAR_BINARY, NULL, 0, &zero, &good, &h),
              HF_ERR_INVALID_ARGUMENT, &h, sizeof h);
    CHECK_BAD(hf_trace(f, HF_METHOD_LINEAR_SECANT, NULL, 0, &zero, &good, &h),
              HF_ERR_INVALID_ARGUMENT, &h, sizeof h);
    CHECK_BAD(hf_trace(f, HF_METHOD_MAXMIP, pyr, 0, &o, &good, &h), HF_ERR_BUFFER_TOO_SMALL, &h,
              sizeof h);

    /* Batches: empty, short output, NULLs, one bad ray among good ones. */
    hf_ray rays[3] = {good, good, good};
    hf_hit hits[3];
    memset(hits, 0x5A, sizeof hits);
    const uint32_t ex = HF_METHOD_EXACT;
    /* Empty: HF_OK (test_errors.c). */
    CHECK_OK(hf_trace_batch(f, ex, NULL, 0, NULL, rays, 0, hits, 3));
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, rays, 3, hits, 2), HF_ERR_BUFFER_TOO_SMALL,
              hits, sizeof hits);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, NULL, 3, hits, 3), HF_ERR_NULL_POINTER, hits,
              sizeof hits);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, rays, 3, NULL, 3), HF_ERR_NULL_POINTER,
              nothing, 0);
    CHECK_BAD(hf_trace_batch(NULL, ex, NULL, 0, NULL, rays, 3, hits, 3), HF_ERR_NULL_POINTER, hits,
              sizeof hits);
    hf_trace_options nine = on(9);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, &nine, rays, 3, hits, 3), HF_ERR_INVALID_ENUM, hits,
              sizeof hits);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, rays, SIZE_MAX, hits, SIZE_MAX),
              HF_ERR_INVALID_SIZE, hits, sizeof hits);
    rays[2] = bad[2];
    for (int m = 0; m < 4; m++)
        CHECK_BAD(hf_trace_batch(f, four[m].method, four[m].map, four[m].len, &o, rays, 3, hits, 3),
                  HF_ERR_INVALID_RAY, hits, sizeof hits);
    rays[2] = good;
    CHECK_BAD(hf_trace_batch(f, HF_METHOD_LINEAR_BINARY, NULL, 0, &zero, rays, 3, hits, 3),
              HF_ERR_INVALID_ARGUMENT, hits, sizeof hits);
    CHECK_OK(hf_trace_batch(f, HF_METHOD_LINEAR_SECANT, NULL, 0, &o, rays, 0, hits, 3));
    hf_trace_options seven = budget(7, 8, 8);
    CHECK_BAD(hf_trace_batch(f, HF_METHOD_LINEAR_BINARY, NULL, 0, &seven, rays, 3, hits, 3),
              HF_ERR_INVALID_ENUM, hits, sizeof hits);
    CHECK_BAD(hf_trace_batch(NULL, HF_METHOD_LINEAR_SECANT, NULL, 0, &o, rays, 3, hits, 3),
              HF_ERR_NULL_POINTER, hits, sizeof hits);
    const uint32_t mm = HF_METHOD_MAXMIP;
    CHECK_BAD(hf_trace_batch(f, mm, NULL, 1, NULL, rays, 3, hits, 3), HF_ERR_NULL_POINTER, hits,
              sizeof hits);
    CHECK_BAD(hf_trace_batch(f, mm, pyr, 0, NULL, rays, 3, hits, 3), HF_ERR_BUFFER_TOO_SMALL, hits,
              sizeof hits);
    CHECK_BAD(hf_trace_batch(f, mm, pyr, P1, NULL, rays, 3, hits, 1), HF_ERR_BUFFER_TOO_SMALL,
              hits, sizeof hits);
    CHECK_OK(hf_trace_batch(f, mm, pyr, P1, NULL, rays, 3, hits, 3));
    CHECK(hits[2].hit == 1 && hits[2].t == 4.0f);
    hf_field_destroy(f);
}

/* ---- a random field: every method on many rays ------------------------------------ */

static uint32_t rng_state = 12345u;
static float frand(void) {
    rng_state = rng_state * 1664525u + 1013904223u;
    return (float)(rng_state >> 8) / 16777216.0f;
}

static void test_methods_agree(void) {
    enum { W = 37, H = 23, N = 2000 };
    float *heights = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) heights[k] = 8.0f * frand();
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    size_t plen = 0;
    CHECK_OK(hf_maxmip_len(W, H, &plen));
    float *pyr = (float *)malloc(sizeof(float) * plen);
    CHECK_OK(hf_maxmip_bake(f, pyr, plen));

    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        rays[k] = ray(-5.0f + (W + 10) * frand(), -5.0f + (H + 10) * frand(), 12.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, -frand());
        if (k % 10 == 0) rays[k].dir[0] = 0.0f; /* axis-parallel */
        if (k % 17 == 0) rays[k].dir[0] = rays[k].dir[1] = 0.0f; /* vertical */
    }
    hf_hit *exact = (hf_hit *)malloc(sizeof(hf_hit) * N);
    hf_hit *other = (hf_hit *)malloc(sizeof(hf_hit) * N);
    int hits = 0, lb_close = 0, lb_hits = 0, sec_hits = 0;
    for (uint32_t s = HF_SURFACE_TRIANGLES; s <= HF_SURFACE_VIEW_LINEAR; s++) {
        hf_trace_options o = on(s);
        CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &o, rays, N, exact, N));
        /* The batch answers as the single-ray call. */
        for (int k = 0; k < N; k += 97) {
            hf_hit one;
            CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, &o, &rays[k], &one));
            CHECK(memcmp(&one, &exact[k], sizeof one) == 0);
        }
        /* Maxmip is exact: the same hit as the exact method, bit for bit. */
        CHECK_OK(hf_trace_batch(f, HF_METHOD_MAXMIP, pyr, plen, &o, rays, N, other, N));
        int same = 0;
        for (int k = 0; k < N; k++) {
            hits += exact[k].hit;
            same += exact[k].hit == other[k].hit && exact[k].t == other[k].t &&
                    memcmp(exact[k].point, other[k].point, sizeof exact[k].point) == 0 &&
                    exact[k].flags == other[k].flags;
        }
        CHECK(same == N);
        /* The search baselines: approximate; with many steps, mostly right. */
        hf_trace_options search = budget(s, 256, 20);
        CHECK_OK(hf_trace_batch(f, HF_METHOD_LINEAR_BINARY, NULL, 0, &search, rays, N, other, N));
        for (int k = 0; k < N; k++) {
            lb_hits += other[k].hit;
            if (exact[k].hit && other[k].hit) {
                float dx = exact[k].point[0] - other[k].point[0];
                float dy = exact[k].point[1] - other[k].point[1];
                float dz = exact[k].point[2] - other[k].point[2];
                lb_close += sqrtf(dx * dx + dy * dy + dz * dz) < 1e-2f;
            }
        }
        CHECK_OK(hf_trace_batch(f, HF_METHOD_LINEAR_SECANT, NULL, 0, &search, rays, N, other, N));
        for (int k = 0; k < N; k++) sec_hits += other[k].hit;
    }
    CHECK(hits > N); /* most rays hit */
    CHECK(lb_close > hits * 9 / 10);
    CHECK(lb_hits > hits * 9 / 10 && sec_hits > hits * 9 / 10);
    printf("methods: %d rays x 5 surfaces, %d exact hits, maxmip identical, linear-binary "
           "within 1e-2 on %d\n",
           N, hits, lb_close);
    free(exact);
    free(other);
    free(rays);
    free(pyr);
    free(heights);
    hf_field_destroy(f);
}

/* ---- world units and shadow rays ---------------------------------------------------- */

/* A world ray of the grid ray `g` under `t` (in double, then rounded to float). */
static hf_ray world_ray(const hf_transform *t, hf_ray g) {
    double off[3] = {t->origin[0], t->origin[1], t->height_offset};
    double sc[3] = {t->spacing[0], t->spacing[1], t->height_scale};
    hf_ray w = g;
    for (int k = 0; k < 3; k++) {
        w.origin[k] = (float)(off[k] + sc[k] * (double)g.origin[k]);
        w.dir[k] = (float)(sc[k] * (double)g.dir[k]);
    }
    return w;
}

static void test_world_units(void) {
    enum { W = 41, H = 29, N = 3000 };
    float *heights = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) heights[k] = 8.0f * frand();
    hf_field *grid = NULL, *world = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &grid));
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &world));

    /* The default is the identity. */
    hf_transform t;
    memset(&t, 0xff, sizeof t);
    CHECK_OK(hf_field_get_transform(world, &t));
    CHECK(t.origin[0] == 0 && t.origin[1] == 0 && t.spacing[0] == 1 && t.spacing[1] == 1 &&
          t.height_scale == 1 && t.height_offset == 0);

    /* Bad transforms are refused and leave the field's transform as it was. */
    hf_transform bad = {{0, 0}, {1, 1}, 1, 0};
    CHECK_BAD(hf_field_set_transform(NULL, &bad), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_field_set_transform(world, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_field_get_transform(world, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_field_get_transform(NULL, &t), HF_ERR_NULL_POINTER, &t, sizeof t);
    bad.origin[1] = NAN;
    CHECK_BAD(hf_field_set_transform(world, &bad), HF_ERR_NOT_FINITE, nothing, 0);
    bad.origin[1] = 0;
    bad.height_offset = INFINITY;
    CHECK_BAD(hf_field_set_transform(world, &bad), HF_ERR_NOT_FINITE, nothing, 0);
    bad.height_offset = 0;
    bad.spacing[0] = 0;
    CHECK_BAD(hf_field_set_transform(world, &bad), HF_ERR_INVALID_ARGUMENT, nothing, 0);
    bad.spacing[0] = 1;
    bad.height_scale = 0;
    CHECK_BAD(hf_field_set_transform(world, &bad), HF_ERR_INVALID_ARGUMENT, nothing, 0);
    bad.height_scale = -3;
    CHECK_BAD(hf_field_set_transform(world, &bad), HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_OK(hf_field_get_transform(world, &t));
    CHECK(t.spacing[0] == 1 && t.height_scale == 1);

    /* A DEM-like transform: unequal spacings, y flipped, a height scale and offsets. */
    hf_transform dem = {{1000.0, 2000.0}, {30.0, -25.0}, 2.5, 236.0};
    CHECK_OK(hf_field_set_transform(world, &dem));
    CHECK_OK(hf_field_get_transform(world, &t));
    CHECK(memcmp(&t, &dem, sizeof t) == 0);

    hf_ray *g = (hf_ray *)malloc(sizeof(hf_ray) * N);
    hf_ray *w = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        g[k] = ray(-5.0f + (W + 10) * frand(), -5.0f + (H + 10) * frand(), 10.0f + 4.0f * frand(),
                   frand() - 0.5f, frand() - 0.5f, -frand());
        w[k] = world_ray(&dem, g[k]);
    }
    hf_hit *gh = (hf_hit *)malloc(sizeof(hf_hit) * N);
    hf_hit *wh = (hf_hit *)malloc(sizeof(hf_hit) * N);
    hf_hit *mh = (hf_hit *)malloc(sizeof(hf_hit) * N);
    CHECK_OK(hf_trace_batch(grid, HF_METHOD_EXACT, NULL, 0, NULL, g, N, gh, N));
    CHECK_OK(hf_trace_batch(world, HF_METHOD_EXACT, NULL, 0, NULL, w, N, wh, N));
    int hits = 0, same = 0;
    for (int k = 0; k < N; k++) {
        hits += gh[k].hit;
        if (gh[k].hit != wh[k].hit) continue;
        if (!gh[k].hit) {
            same++;
            continue;
        }
        /* The world hit is the grid hit mapped: point, normal by the inverse transpose. */
        double off[3] = {dem.origin[0], dem.origin[1], dem.height_offset};
        double sc[3] = {dem.spacing[0], dem.spacing[1], dem.height_scale};
        double n[3], len = 0;
        int ok = near(gh[k].t, wh[k].t, 1e-4f * (1.0f + gh[k].t)) &&
                 gh[k].cell[0] == wh[k].cell[0] && gh[k].cell[1] == wh[k].cell[1];
        for (int c = 0; c < 3; c++) {
            double p = off[c] + sc[c] * (double)gh[k].point[c];
            ok &= fabs(p - (double)wh[k].point[c]) <= 1e-3 * fabs(sc[c]) + 1e-4 * fabs(p);
            n[c] = (double)gh[k].normal[c] / sc[c];
            len += n[c] * n[c];
        }
        for (int c = 0; c < 3; c++) ok &= fabs(n[c] / sqrt(len) - (double)wh[k].normal[c]) < 1e-4;
        same += ok;
    }
    CHECK(hits > N / 2);
    /* The float world ray is not exactly the grid ray: a near-graze may flip. */
    CHECK(same >= N - N / 500);
    printf("world units: %d rays, %d grid hits, %d agree mapped\n", N, hits, same);

    /* Every method converts alike: the maximum mipmap answers the exact method's
     * world hits bit for bit (their costs differ), single and batch. */
    size_t plen = 0;
    CHECK_OK(hf_maxmip_len(W, H, &plen));
    float *pyr = (float *)malloc(sizeof(float) * plen);
    CHECK_OK(hf_maxmip_bake(world, pyr, plen));
    CHECK_OK(hf_trace_batch(world, HF_METHOD_MAXMIP, pyr, plen, NULL, w, N, mh, N));
    int ident = 0;
    for (int k = 0; k < N; k++)
        ident += wh[k].hit == mh[k].hit && wh[k].t == mh[k].t && wh[k].flags == mh[k].flags &&
                 memcmp(wh[k].point, mh[k].point, sizeof wh[k].point) == 0 &&
                 memcmp(wh[k].normal, mh[k].normal, sizeof wh[k].normal) == 0;
    CHECK(ident == N);
    hf_hit one;
    CHECK_OK(hf_trace(world, HF_METHOD_EXACT, NULL, 0, NULL, &w[7], &one));
    CHECK(memcmp(&one, &wh[7], sizeof one) == 0);

    /* A world ray whose grid image overflows is an invalid ray, not a miss. */
    hf_transform tiny = {{0, 0}, {1e-30, 1e-30}, 1, 0};
    hf_field *tf = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &tf));
    CHECK_OK(hf_field_set_transform(tf, &tiny));
    hf_ray far = ray(1e10f, 0, 1, 1, 0, -1);
    CHECK_BAD(hf_trace(tf, HF_METHOD_EXACT, NULL, 0, NULL, &far, &one), HF_ERR_INVALID_RAY, &one,
              sizeof one);
    hf_field_destroy(tf);

    /* Shadow rays: from the hit point itself many start inside the solid; from
     * hf_shadow_ray none does, with and without a transform. */
    const float light[3] = {0.3f, -0.4f, 0.6f};
    hf_field *fields[2] = {grid, world};
    hf_hit *answers[2] = {gh, wh};
    hf_ray *primaries[2] = {g, w};
    for (int f = 0; f < 2; f++) {
        int lit = 0, naive_inside = 0, lifted_inside = 0;
        for (int k = 0; k < N; k++) {
            const hf_hit *h = &answers[f][k];
            if (!h->hit || (h->flags & HF_FLAG_ORIGIN_INSIDE)) continue;
            lit++;
            hf_ray at = ray(h->point[0], h->point[1], h->point[2], light[0], light[1], light[2]);
            hf_hit s;
            CHECK_OK(hf_trace(fields[f], HF_METHOD_EXACT, NULL, 0, NULL, &at, &s));
            naive_inside += s.hit && (s.flags & HF_FLAG_ORIGIN_INSIDE);
            hf_ray sr;
            CHECK_OK(hf_shadow_ray(fields[f], HF_SURFACE_TRIANGLES, &primaries[f][k], h, &light,
                                   &sr));
            CHECK_OK(hf_trace(fields[f], HF_METHOD_EXACT, NULL, 0, NULL, &sr, &s));
            lifted_inside += s.hit && (s.flags & HF_FLAG_ORIGIN_INSIDE);
        }
        CHECK(lit > N / 2 && naive_inside > lit / 20);
        CHECK(lifted_inside == 0);
        printf("shadow rays (%s): %d hits, %d start inside from the hit point, %d from "
               "hf_shadow_ray\n",
               f ? "world" : "grid", lit, naive_inside, lifted_inside);
    }
    hf_ray sr;
    memset(&sr, 0x5a, sizeof sr);
    hf_hit miss = gh[0];
    miss.hit = 0;
    CHECK_BAD(hf_shadow_ray(grid, HF_SURFACE_TRIANGLES, &g[0], &miss, &light, &sr),
              HF_ERR_INVALID_ARGUMENT, &sr, sizeof sr);
    CHECK_BAD(hf_shadow_ray(grid, 99, &g[0], &gh[0], &light, &sr), HF_ERR_INVALID_ENUM, &sr,
              sizeof sr);
    CHECK_BAD(hf_shadow_ray(grid, HF_SURFACE_TRIANGLES, NULL, &gh[0], &light, &sr),
              HF_ERR_NULL_POINTER, &sr, sizeof sr);
    CHECK_BAD(hf_shadow_ray(grid, HF_SURFACE_TRIANGLES, &g[0], &gh[0], &light, NULL),
              HF_ERR_NULL_POINTER, nothing, 0);
    free(pyr);
    free(g);
    free(w);
    free(gh);
    free(wh);
    free(mh);
    free(heights);
    hf_field_destroy(grid);
    hf_field_destroy(world);
}

/* ---- bakes and updates ------------------------------------------------------------ */

/* Floats of the 3 x 3 field's pyramid: 5 texels and the descriptor. */
#define PL (5 + HF_MAP_DESC_BYTES / 4)

static void test_bake_and_update(void) {
    /* A 3 x 3 field 0..8: level 0 is 2 x 2 (each cell's highest corner), level 1 1 x 1. */
    const float h9[9] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(h9, 9, 3, 3, 3, &f));
    size_t len = 0;
    CHECK_OK(hf_maxmip_len(3, 3, &len));
    CHECK(len == PL); /* 5 texels, then the descriptor */
    float p[PL];
    for (size_t k = 0; k < PL; k++) p[k] = -1.0f;
    CHECK_OK(hf_maxmip_bake(f, p, PL));
    CHECK(p[0] == 4 && p[1] == 5 && p[2] == 7 && p[3] == 8 && p[4] == 8);
    hf_level levels[HF_MAX_LEVELS];
    uint32_t count = 0;
    CHECK_OK(hf_maxmip_levels(3, 3, levels, HF_MAX_LEVELS, &count));
    CHECK(count == 2 && levels[0].width == 2 && levels[0].height == 2 && levels[0].offset == 0);
    CHECK(levels[1].width == 1 && levels[1].height == 1 && levels[1].offset == 4);

    size_t big = 0;
    CHECK_OK(hf_maxmip_len(4096, 2048, &big));
    CHECK(big > 4095u * 2047u && big < 4095u * 2047u / 2u * 3u);
    CHECK_OK(hf_maxmip_levels(HF_MAX_SIDE, 2, levels, HF_MAX_LEVELS, &count));
    CHECK(count == 25);

    /* Bad bake inputs. */
    float q[PL];
    for (size_t k = 0; k < PL; k++) q[k] = -1.0f;
    size_t zlen = 99;
    CHECK_BAD(hf_maxmip_len(1, 3, &zlen), HF_ERR_INVALID_SIZE, &zlen, sizeof zlen);
    CHECK_BAD(hf_maxmip_len(3, 0, &zlen), HF_ERR_INVALID_SIZE, &zlen, sizeof zlen);
    CHECK_BAD(hf_maxmip_len(HF_MAX_SIDE + 1u, 3, &zlen), HF_ERR_INVALID_SIZE, &zlen,
              sizeof zlen);
    CHECK_BAD(hf_maxmip_len(3, 3, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_maxmip_levels(3, 3, levels, 1, &count), HF_ERR_BUFFER_TOO_SMALL, levels,
              sizeof levels);
    CHECK_BAD(hf_maxmip_levels(3, 3, NULL, 2, &count), HF_ERR_NULL_POINTER, &count,
              sizeof count);
    CHECK_BAD(hf_maxmip_levels(3, 3, levels, 2, NULL), HF_ERR_NULL_POINTER, levels,
              sizeof levels);
    CHECK_BAD(hf_maxmip_levels(0, 3, levels, 2, &count), HF_ERR_INVALID_SIZE, levels,
              sizeof levels);
    CHECK_BAD(hf_maxmip_bake(f, q, PL - 1), HF_ERR_BUFFER_TOO_SMALL, q, sizeof q);
    CHECK_BAD(hf_maxmip_bake(f, NULL, 5), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_maxmip_bake(NULL, q, PL), HF_ERR_NULL_POINTER, q, sizeof q);
    CHECK_BAD(hf_maxmip_bake_threaded(f, 2, q, PL - 1), HF_ERR_BUFFER_TOO_SMALL, q, sizeof q);
    CHECK_BAD(hf_maxmip_bake_threaded(NULL, 2, q, PL), HF_ERR_NULL_POINTER, q, sizeof q);
    CHECK_BAD(hf_maxmip_bake_threaded(f, 2, NULL, 5), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_maxmip_bake_rows(f, 2, 0, 1, q, PL), HF_ERR_INVALID_ARGUMENT, q, sizeof q);
    CHECK_BAD(hf_maxmip_bake_rows(f, 0, 1, 3, q, PL), HF_ERR_INVALID_ARGUMENT, q, sizeof q);
    CHECK_BAD(hf_maxmip_bake_rows(f, 0, 2, 1, q, PL), HF_ERR_INVALID_ARGUMENT, q, sizeof q);
    CHECK_BAD(hf_maxmip_bake_rows(f, 0xFFFFFFFFu, 0, 1, q, PL), HF_ERR_INVALID_ARGUMENT, q,
              sizeof q);
    CHECK_BAD(hf_maxmip_bake_rows(f, 0, 0, 1, q, PL - 1), HF_ERR_BUFFER_TOO_SMALL, q, sizeof q);
    CHECK_BAD(hf_maxmip_bake_rows(f, 0, 0, 1, NULL, 5), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_maxmip_bake_rows(NULL, 0, 0, 1, q, PL), HF_ERR_NULL_POINTER, q, sizeof q);
    CHECK_BAD(hf_maxmip_update_rect(f, 0, 0, 4, 1, p, PL), HF_ERR_INVALID_RECT, p, sizeof p);
    CHECK_BAD(hf_maxmip_update_rect(f, 2, 0, 1, 1, p, PL), HF_ERR_INVALID_RECT, p, sizeof p);
    CHECK_BAD(hf_maxmip_update_rect(f, 0, 0, 1, 1, p, PL - 1), HF_ERR_BUFFER_TOO_SMALL, p, sizeof p);
    CHECK_BAD(hf_maxmip_update_rect(f, 0, 0, 1, 1, NULL, 5), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_maxmip_update_rect(NULL, 0, 0, 1, 1, p, PL), HF_ERR_NULL_POINTER, p, sizeof p);

    /* Row-range bake, level by level, rows split: equals the whole bake. */
    CHECK_OK(hf_maxmip_bake_rows(f, 0, 1, 2, q, PL));
    CHECK_OK(hf_maxmip_bake_rows(f, 0, 0, 1, q, PL));
    CHECK_OK(hf_maxmip_bake_rows(f, 0, 2, 2, q, PL)); /* empty range: nothing */
    CHECK_OK(hf_maxmip_bake_rows(f, 1, 0, 1, q, PL));
    CHECK(memcmp(p, q, sizeof p) == 0);

    /* Field update: bad inputs leave the field as it was. */
    const float v[4] = {20.0f, 21.0f, 22.0f, 23.0f};
    const float vnan[4] = {20.0f, NAN, 22.0f, 23.0f};
    float heights[9], before[9];
    CHECK_OK(hf_field_copy_heights(f, before, 9));
    CHECK_BAD(hf_field_update_rect(NULL, 0, 0, 2, 2, v, 4, 2), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_field_update_rect(f, 0, 0, 2, 2, NULL, 4, 2), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_field_update_rect(f, 0, 0, 2, 2, vnan, 4, 2), HF_ERR_NOT_FINITE, nothing, 0);
    CHECK_BAD(hf_field_update_rect(f, 0, 0, 2, 2, v, 3, 2), HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_field_update_rect(f, 0, 0, 2, 2, v, 4, 1), HF_ERR_INVALID_SIZE, nothing, 0);
    CHECK_BAD(hf_field_update_rect(f, 0, 0, 2, 2, v, 4, SIZE_MAX), HF_ERR_INVALID_SIZE, nothing, 0);
    CHECK_OK(hf_field_update_rect(f, 0, 0, 0, 2, v, 4, 2)); /* empty: HF_OK, no change */
    CHECK_BAD(hf_field_update_rect(f, 2, 0, 1, 2, v, 4, 2), HF_ERR_INVALID_RECT, nothing, 0);
    CHECK_BAD(hf_field_update_rect(f, 2, 2, 4, 3, v, 4, 2), HF_ERR_INVALID_RECT, nothing, 0);
    CHECK_OK(hf_field_copy_heights(f, heights, 9));
    CHECK(memcmp(heights, before, sizeof before) == 0);

    /* A 2 x 2 update at (1, 1), then the pyramid update: equals a fresh bake. */
    CHECK_OK(hf_field_update_rect(f, 1, 1, 3, 3, v, 4, 2));
    hf_field_info info;
    CHECK_OK(hf_field_get_info(f, &info));
    CHECK(info.max_height == 23.0f && info.min_height == 0.0f);
    CHECK_OK(hf_maxmip_update_rect(f, 1, 1, 3, 3, p, PL));
    CHECK_OK(hf_field_copy_heights(f, heights, 9));
    hf_field *g = NULL;
    CHECK_OK(hf_field_create_f32(heights, 9, 3, 3, 3, &g));
    CHECK(heights[4] == 20.0f && heights[8] == 23.0f && heights[0] == 0.0f);
    CHECK_OK(hf_maxmip_bake(g, q, PL));
    CHECK(memcmp(p, q, sizeof p) == 0 && p[4] == 23.0f);
    hf_ray r = ray(1.5f, 1.5f, 50.0f, 0.0f, 0.0f, -1.0f);
    hf_hit a, b;
    hf_trace_options bilinear = on(HF_SURFACE_BILINEAR);
    CHECK_OK(hf_trace(f, HF_METHOD_MAXMIP, p, PL, &bilinear, &r, &a));
    CHECK_OK(hf_trace(g, HF_METHOD_EXACT, NULL, 0, &bilinear, &r, &b));
    CHECK(a.hit && b.hit && a.t == b.t && near(a.point[2], 21.5f, 1e-5f));
    hf_field_destroy(g);
    hf_field_destroy(f);

    /* A larger odd-sized field: threaded and single-threaded bakes agree. */
    enum { W = 301, H = 157 };
    float *hs = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) hs[k] = 100.0f * frand();
    CHECK_OK(hf_field_create_f32(hs, W * H, W, H, W, &f));
    CHECK_OK(hf_maxmip_len(W, H, &len));
    float *p1 = (float *)malloc(sizeof(float) * len);
    float *p2 = (float *)malloc(sizeof(float) * len);
    CHECK_OK(hf_maxmip_bake(f, p1, len));
    for (uint32_t t = 0; t <= 5; t++) {
        memset(p2, 0, sizeof(float) * len);
        CHECK_OK(hf_maxmip_bake_threaded(f, t, p2, len));
        CHECK(memcmp(p1, p2, sizeof(float) * len) == 0);
    }
    free(p1);
    free(p2);
    free(hs);
    hf_field_destroy(f);
}

/* ---- safety distances -------------------------------------------------------------- */

/* HF_RAYS_* bit of a ray's class: x+ if dx >= |dy|, x- if -dx >= |dy|, y+ if dy > |dx|,
 * else y-. */
static uint32_t class_bit(const hf_ray *r) {
    float dx = r->dir[0], dy = r->dir[1];
    if (dx >= fabsf(dy)) return HF_RAYS_X_POS;
    if (-dx >= fabsf(dy)) return HF_RAYS_X_NEG;
    return dy > fabsf(dx) ? HF_RAYS_Y_POS : HF_RAYS_Y_NEG;
}

/* The options of a map of the ray classes `classes` (`len` elements at `map`, of
 * `method`): one element short is too small; `ray_classes` 0 takes the descriptor's
 * classes (the same hit as naming them); 16 is no class set. */
static void check_class_options(const hf_field *f, uint32_t method, const void *map, size_t len,
                                uint32_t classes, const hf_ray *ray) {
    hf_hit bad_hit, named, any;
    memset(&bad_hit, 0x5A, sizeof bad_hit);
    hf_trace_options o = on(HF_SURFACE_TRIANGLES);
    o.ray_classes = classes;
    CHECK_BAD(hf_trace(f, method, map, len - 1, &o, ray, &bad_hit), HF_ERR_BUFFER_TOO_SMALL,
              &bad_hit, sizeof bad_hit);
    CHECK_OK(hf_trace(f, method, map, len, &o, ray, &named));
    o.ray_classes = 0;
    CHECK_OK(hf_trace(f, method, map, len, &o, ray, &any));
    CHECK(memcmp(&named, &any, sizeof any) == 0);
    o.ray_classes = 16;
    CHECK_BAD(hf_trace(f, method, map, len, &o, ray, &bad_hit), HF_ERR_INVALID_ARGUMENT, &bad_hit,
              sizeof bad_hit);
}

/* A map of the ray classes `ctx->classes` only, traced on the triangle surface: every
 * ray finds its exact hit (`exact`; rays of the other classes read zero jumps and
 * walk), and the rays of its classes trace bit for bit as on the whole map (`full`). */
static void check_class_map(const char *what, const hf_ray *rays, int n, const hf_hit *exact,
                            const hf_hit *full, const struct safety_ctx *ctx) {
    hf_hit *got = (hf_hit *)malloc(sizeof(hf_hit) * n);
    CHECK_OK(trace_on(ctx, HF_SURFACE_TRIANGLES, rays, n, got));
    int held = 0, same = 0;
    for (int k = 0; k < n; k++) {
        if (!(class_bit(&rays[k]) & ctx->classes)) continue;
        held++;
        same += memcmp(&got[k], &full[k], sizeof(hf_hit)) == 0;
    }
    int ok = agreeing(exact, got, n);
    CHECK(ok == n && held > 0 && held < n && same == held);
    printf("%s: %zu bytes; exact on %d of %d rays, as the whole map on %d of its %d\n", what,
           ctx->len, ok, n, same, held);
    free(got);
}

static void test_safety(void) {
    enum { W = 41, H = 29, N = 3000 };
    float *heights = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) heights[k] = 10.0f * frand() * frand();
    heights[15 * W + 20] = 40.0f; /* a needle */
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));

    size_t dlen = 0, ilen = 0, slen = 0, junk = 77;
    CHECK_OK(hf_safety_map_len(W, H, HF_SAFETY_DIRECTIONAL, 0, &dlen));
    CHECK_OK(hf_safety_map_len(W, H, HF_SAFETY_ISOTROPIC, 0, &ilen));
    CHECK(dlen == (size_t)W * H * 4 + HF_MAP_DESC_BYTES && ilen == (size_t)W * H + HF_MAP_DESC_BYTES);
    CHECK_OK(hf_safety_scratch_len(W, H, &slen));
    CHECK(slen > 0);
    CHECK_BAD(hf_safety_map_len(W, H, 2, 0, &junk), HF_ERR_INVALID_ENUM, &junk, sizeof junk);
    CHECK_BAD(hf_safety_map_len(1, H, 0, 0, &junk), HF_ERR_INVALID_SIZE, &junk, sizeof junk);
    CHECK_BAD(hf_safety_map_len(W, H, 0, 0, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_safety_scratch_len(W, 0, &junk), HF_ERR_INVALID_SIZE, &junk, sizeof junk);
    CHECK_BAD(hf_safety_scratch_len(W, H, NULL), HF_ERR_NULL_POINTER, nothing, 0);

    unsigned char *dmap = (unsigned char *)malloc(dlen);
    unsigned char *imap = (unsigned char *)malloc(ilen);
    unsigned char *rows = (unsigned char *)malloc(dlen);
    float *scratch = (float *)malloc(sizeof(float) * slen);
    memset(dmap, 0xEE, dlen);
    hf_safety_options good = {HF_SAFETY_DIRECTIONAL, 0, 255, HF_RAYS_ALL};
    hf_safety_options bad_variant = {5, 0, 255, 0}, bad_positive = {0, 2, 255, 0};
    hf_safety_options bad_cap = {0, 0, 256, 0}, bad_classes = {0, 0, 255, 16};
    CHECK_BAD(hf_safety_bake(NULL, &good, 1, dmap, dlen), HF_ERR_NULL_POINTER, dmap, 64);
    CHECK_BAD(hf_safety_bake(f, NULL, 1, dmap, dlen), HF_ERR_NULL_POINTER, dmap, 64);
    CHECK_BAD(hf_safety_bake(f, &good, 1, NULL, dlen), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_safety_bake(f, &good, 1, dmap, dlen - 1), HF_ERR_BUFFER_TOO_SMALL, dmap, 64);
    CHECK_BAD(hf_safety_bake(f, &bad_variant, 1, dmap, dlen), HF_ERR_INVALID_ENUM, dmap, 64);
    CHECK_BAD(hf_safety_bake(f, &bad_positive, 1, dmap, dlen), HF_ERR_INVALID_ARGUMENT, dmap, 64);
    CHECK_BAD(hf_safety_bake(f, &bad_cap, 1, dmap, dlen), HF_ERR_INVALID_ARGUMENT, dmap, 64);
    CHECK_BAD(hf_safety_bake(f, &bad_classes, 1, dmap, dlen), HF_ERR_INVALID_ARGUMENT, dmap, 64);
    CHECK_BAD(hf_safety_prepare(f, scratch, slen - 1), HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_safety_prepare(f, NULL, slen), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_safety_prepare(NULL, scratch, slen), HF_ERR_NULL_POINTER, nothing, 0);

    /* The whole bake on 1, 3 and all threads equals prepare + row bakes in pieces. */
    CHECK_OK(hf_safety_bake(f, &good, 1, dmap, dlen));
    CHECK_OK(hf_safety_prepare(f, scratch, slen));
    CHECK_BAD(hf_safety_bake_rows(f, scratch, slen, &good, 5, 4, rows, dlen),
              HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_BAD(hf_safety_bake_rows(f, scratch, slen, &good, 0, H + 1, rows, dlen),
              HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_BAD(hf_safety_bake_rows(f, scratch, slen - 1, &good, 0, 1, rows, dlen),
              HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_safety_bake_rows(f, scratch, slen, &good, 0, 1, rows, dlen - 1),
              HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_safety_bake_rows(f, NULL, slen, &good, 0, 1, rows, dlen), HF_ERR_NULL_POINTER,
              nothing, 0);
    CHECK_BAD(hf_safety_bake_rows(f, scratch, slen, NULL, 0, 1, rows, dlen), HF_ERR_NULL_POINTER,
              nothing, 0);
    CHECK_BAD(hf_safety_bake_rows(f, scratch, slen, &good, 0, 1, NULL, dlen),
              HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_safety_bake_rows(f, scratch, slen, &bad_variant, 0, 1, rows, dlen),
              HF_ERR_INVALID_ENUM, nothing, 0);
    CHECK_BAD(hf_safety_bake_rows(f, scratch, slen, &bad_classes, 0, 1, rows, dlen),
              HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_OK(hf_safety_bake_rows(f, scratch, slen, &good, 10, H, rows, dlen));
    CHECK_OK(hf_safety_bake_rows(f, scratch, slen, &good, 0, 10, rows, dlen));
    CHECK(memcmp(rows, dmap, dlen) == 0);
    for (uint32_t t = 0; t <= 3; t += 3) {
        memset(rows, 0, dlen);
        CHECK_OK(hf_safety_bake(f, &good, t, rows, dlen));
        CHECK(memcmp(rows, dmap, dlen) == 0);
    }
    hf_safety_options iso = {HF_SAFETY_ISOTROPIC, 0, 255, HF_RAYS_ALL};
    CHECK_OK(hf_safety_bake(f, &iso, 2, imap, ilen));
    /* Isotropic = the minimum over the four classes; directional: class c of texel
     * (i, j) at byte (j * 4 + c) * W + i. */
    int iso_ok = 1;
    for (int k = 0; k < W * H; k++) {
        const unsigned char *d = dmap + (k / W) * 4 * W + k % W;
        unsigned char m = d[0];
        for (int c = 1; c < 4; c++) m = d[c * W] < m ? d[c * W] : m;
        iso_ok &= imap[k] == m;
    }
    CHECK(iso_ok);

    /* Two ray classes (x+, y-): a map of their rows only, two per texel row in class
     * order (byte k: texel row k / 2W, slot k / W % 2), equal to the full bake's rows;
     * the row bake with the same classes agrees. */
    uint32_t two = HF_RAYS_X_POS | HF_RAYS_Y_NEG;
    size_t tlen = 0, ilen_two = 0, alen = 0;
    CHECK_OK(hf_safety_map_len(W, H, HF_SAFETY_DIRECTIONAL, two, &tlen));
    CHECK_OK(hf_safety_map_len(W, H, HF_SAFETY_ISOTROPIC, two, &ilen_two));
    CHECK(tlen == (size_t)W * H * 2 + HF_MAP_DESC_BYTES && ilen_two == (size_t)W * H + HF_MAP_DESC_BYTES);
    /* ray_classes 0 means all four (the full map's size and bytes); above 15 is an error. */
    CHECK_BAD(hf_safety_map_len(W, H, HF_SAFETY_DIRECTIONAL, 16, &tlen), HF_ERR_INVALID_ARGUMENT,
              nothing, 0);
    CHECK_OK(hf_safety_map_len(W, H, HF_SAFETY_DIRECTIONAL, HF_RAYS_ALL, &alen));
    CHECK(alen == dlen);
    CHECK_BAD(hf_safety_map_len(W, H, 7, two, &tlen), HF_ERR_INVALID_ENUM, nothing, 0);
    hf_safety_options so = good;
    so.ray_classes = 0;
    CHECK_OK(hf_safety_bake(f, &so, 1, rows, dlen));
    CHECK(memcmp(rows, dmap, dlen) == 0);
    so.ray_classes = two;
    CHECK_BAD(hf_safety_bake(f, &so, 1, rows, tlen - 1), HF_ERR_BUFFER_TOO_SMALL, rows, 64);
    CHECK_OK(hf_safety_bake(f, &so, 2, rows, tlen));
    static const size_t two_classes[2] = {0, 3};
    int mask_ok = 1;
    for (size_t k = 0; k < tlen - HF_MAP_DESC_BYTES; k++)
        mask_ok &= rows[k] == dmap[(k / (2 * W) * 4 + two_classes[k / W % 2]) * W + k % W];
    CHECK(mask_ok);
    /* In two row ranges (each call writes its rows of the whole map). */
    unsigned char *rows2 = (unsigned char *)malloc(tlen);
    CHECK_OK(hf_safety_bake_rows(f, scratch, slen, &so, 7, H, rows2, tlen));
    CHECK_OK(hf_safety_bake_rows(f, scratch, slen, &so, 0, 7, rows2, tlen));
    CHECK(memcmp(rows, rows2, tlen) == 0);
    free(rows2);

    /* Exact: the safety march finds the exact method's hits on the triangle surface. */
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        rays[k] = ray(-5.0f + (W + 10) * frand(), -5.0f + (H + 10) * frand(), 30.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, -0.05f - 0.5f * frand());
        if (k % 13 == 0) rays[k].dir[1] = 0.0f;
        if (k % 31 == 0) rays[k].dir[0] = rays[k].dir[1] = 0.0f;
    }
    hf_hit *exact = (hf_hit *)malloc(sizeof(hf_hit) * N);
    hf_hit *sd = (hf_hit *)malloc(sizeof(hf_hit) * N);
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, exact, N));
    const uint32_t sm = HF_METHOD_SAFETY;
    int same[2] = {0, 0}, hits = 0;
    for (int v = 0; v < 2; v++) {
        /* The trace reads the layout from the map's descriptor. */
        const unsigned char *map = v == 0 ? dmap : imap;
        size_t len = v == 0 ? dlen : ilen;
        CHECK_OK(hf_trace_batch(f, sm, map, len, NULL, rays, N, sd, N));
        for (int k = 0; v == 0 && k < N; k++) hits += exact[k].hit;
        same[v] = agreeing(exact, sd, N);
        hf_hit one;
        CHECK_OK(hf_trace(f, sm, map, len, NULL, &rays[7], &one));
        CHECK(memcmp(&one, &sd[7], sizeof one) == 0);
    }
    CHECK(same[0] == N && same[1] == N);
    printf("safety: %d rays, %d exact hits; directional agrees on %d, isotropic on %d\n", N, hits,
           same[0], same[1]);
    /* The two-class map (still in `rows`). */
    CHECK_OK(hf_trace_batch(f, sm, dmap, dlen, NULL, rays, N, sd, N));
    struct safety_ctx two_ctx = {f, sm, rows, tlen, two};
    check_class_map("safety, two classes", rays, N, exact, sd, &two_ctx);
    check_class_options(f, sm, rows, tlen, two, &rays[0]);
    hf_trace_options o = on(HF_SURFACE_TRIANGLES);
    struct safety_ctx sctx = {f, sm, dmap, dlen, HF_RAYS_ALL};
    int vl = view_linear_agrees(f, rays, N, sd, &sctx);
    hf_hit one_vl;
    o = on(HF_SURFACE_VIEW_LINEAR);
    o.ray_classes = HF_RAYS_ALL;
    CHECK_OK(hf_trace(f, sm, dmap, dlen, &o, &rays[7], &one_vl));
    CHECK(memcmp(&one_vl, &sd[7], sizeof one_vl) == 0);
    printf("safety on the view-linear surface: agrees on %d of %d\n", vl, N);

    /* Bad trace inputs. */
    hf_hit h;
    memset(&h, 0x5A, sizeof h);
    hf_ray nan_ray = rays[0];
    nan_ray.dir[2] = NAN;
    CHECK_BAD(hf_trace(NULL, sm, dmap, dlen, NULL, &rays[0], &h), HF_ERR_NULL_POINTER, &h,
              sizeof h);
    CHECK_BAD(hf_trace(f, sm, NULL, dlen, NULL, &rays[0], &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, sm, dmap, dlen, NULL, NULL, &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, sm, dmap, dlen, NULL, &rays[0], NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_trace(f, sm, dmap, dlen - 1, NULL, &rays[0], &h), HF_ERR_BUFFER_TOO_SMALL, &h,
              sizeof h);
    /* The layout is no longer passed: the isotropic map traces as itself (it was refused
     * when named directional). */
    CHECK_OK(hf_trace(f, sm, imap, ilen, NULL, &rays[7], &h));
    CHECK(agreeing(&exact[7], &h, 1) == 1);
    memset(&h, 0x5A, sizeof h);
    /* Nor a bad layout: an unknown enum of the options is the bad enum now. */
    hf_trace_options five = on(5);
    CHECK_BAD(hf_trace(f, sm, dmap, dlen, &five, &rays[0], &h), HF_ERR_INVALID_ENUM, &h, sizeof h);
    CHECK_BAD(hf_trace(f, sm, dmap, dlen, NULL, &nan_ray, &h), HF_ERR_INVALID_RAY, &h, sizeof h);
    memset(sd, 0x5A, sizeof(hf_hit) * N);
    rays[N - 1] = nan_ray;
    CHECK_BAD(hf_trace_batch(f, sm, dmap, dlen, NULL, rays, N, sd, N), HF_ERR_INVALID_RAY, sd,
              512);
    CHECK_OK(hf_trace_batch(f, sm, dmap, dlen, NULL, rays, 0, sd, N));
    CHECK_BAD(hf_trace_batch(f, sm, dmap, dlen, NULL, rays, 2, sd, 1), HF_ERR_BUFFER_TOO_SMALL, sd,
              512);
    hf_trace_options nine = on(9);
    CHECK_BAD(hf_trace_batch(f, sm, dmap, dlen, &nine, rays, 2, sd, 2), HF_ERR_INVALID_ENUM, sd,
              512);
    CHECK_BAD(hf_trace_batch(f, sm, dmap, dlen, NULL, NULL, 2, sd, 2), HF_ERR_NULL_POINTER, sd,
              512);
    CHECK_BAD(hf_trace_batch(f, sm, dmap, dlen, NULL, rays, 2, NULL, 2), HF_ERR_NULL_POINTER,
              nothing, 0);
    free(rays);
    free(exact);
    free(sd);
    free(dmap);
    free(imap);
    free(rows);
    free(scratch);
    free(heights);
    hf_field_destroy(f);
}

/* ---- safety radius ------------------------------------------------------------------ */

static void test_radius(void) {
    enum { W = 37, H = 23, N = 2000 };
    float *heights = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) heights[k] = 8.0f * frand() * frand();
    heights[11 * W + 17] = 30.0f; /* a needle */
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));

    size_t len = 0, slen = 0, junk = 77;
    CHECK_OK(hf_radius_map_len(W, H, &len));
    CHECK(len == (size_t)W * H + HF_MAP_DESC_BYTES);
    CHECK_OK(hf_radius_scratch_len(W, H, &slen));
    CHECK_BAD(hf_radius_map_len(1, H, &junk), HF_ERR_INVALID_SIZE, &junk, sizeof junk);
    CHECK_BAD(hf_radius_map_len(W, H, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_radius_scratch_len(W, 0, &junk), HF_ERR_INVALID_SIZE, &junk, sizeof junk);
    CHECK_BAD(hf_radius_scratch_len(W, H, NULL), HF_ERR_NULL_POINTER, nothing, 0);

    unsigned char *map = (unsigned char *)malloc(len);
    unsigned char *rows = (unsigned char *)malloc(len);
    float *scratch = (float *)malloc(sizeof(float) * slen);
    memset(map, 0xEE, len); /* defined bytes: the bad-input checks compare them */
    memset(rows, 0xEE, len);
    hf_radius_options good = {0.0f, 255};
    hf_radius_options bad_tol = {-1.0f, 255}, nan_tol = {NAN, 255}, bad_cap = {0.0f, 256};
    CHECK_BAD(hf_radius_bake(NULL, &good, 1, map, len), HF_ERR_NULL_POINTER, map, 64);
    CHECK_BAD(hf_radius_bake(f, NULL, 1, map, len), HF_ERR_NULL_POINTER, map, 64);
    CHECK_BAD(hf_radius_bake(f, &good, 1, NULL, len), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_radius_bake(f, &good, 1, map, len - 1), HF_ERR_BUFFER_TOO_SMALL, map, 64);
    CHECK_BAD(hf_radius_bake(f, &bad_tol, 1, map, len), HF_ERR_INVALID_ARGUMENT, map, 64);
    CHECK_BAD(hf_radius_bake(f, &nan_tol, 1, map, len), HF_ERR_INVALID_ARGUMENT, map, 64);
    CHECK_BAD(hf_radius_bake(f, &bad_cap, 1, map, len), HF_ERR_INVALID_ARGUMENT, map, 64);
    CHECK_BAD(hf_radius_prepare(f, scratch, slen - 1), HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_radius_prepare(f, NULL, slen), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_radius_prepare(NULL, scratch, slen), HF_ERR_NULL_POINTER, nothing, 0);

    /* Whole, by rows and threaded bakes agree. */
    CHECK_OK(hf_radius_bake(f, &good, 1, map, len));
    CHECK_OK(hf_radius_prepare(f, scratch, slen));
    CHECK_BAD(hf_radius_bake_rows(f, scratch, slen, &good, 5, 4, rows, len),
              HF_ERR_INVALID_ARGUMENT, rows, 64);
    CHECK_BAD(hf_radius_bake_rows(f, scratch, slen, &good, 0, H + 1, rows, len),
              HF_ERR_INVALID_ARGUMENT, rows, 64);
    CHECK_BAD(hf_radius_bake_rows(f, scratch, slen - 1, &good, 0, 1, rows, len),
              HF_ERR_BUFFER_TOO_SMALL, rows, 64);
    CHECK_BAD(hf_radius_bake_rows(f, scratch, slen, &good, 0, 1, rows, len - 1),
              HF_ERR_BUFFER_TOO_SMALL, rows, 64);
    CHECK_BAD(hf_radius_bake_rows(f, NULL, slen, &good, 0, 1, rows, len), HF_ERR_NULL_POINTER,
              rows, 64);
    CHECK_BAD(hf_radius_bake_rows(f, scratch, slen, NULL, 0, 1, rows, len), HF_ERR_NULL_POINTER,
              rows, 64);
    CHECK_BAD(hf_radius_bake_rows(f, scratch, slen, &bad_cap, 0, 1, rows, len),
              HF_ERR_INVALID_ARGUMENT, rows, 64);
    CHECK_OK(hf_radius_bake_rows(f, scratch, slen, &good, 9, H, rows, len));
    CHECK_OK(hf_radius_bake_rows(f, scratch, slen, &good, 0, 9, rows, len));
    CHECK(memcmp(map, rows, len) == 0);
    for (uint32_t t = 0; t <= 3; t++) {
        memset(rows, 0xAA, len);
        CHECK_OK(hf_radius_bake(f, &good, t, rows, len));
        CHECK(memcmp(map, rows, len) == 0);
    }

    /* Exact with zero radii walked: the exact method's hits on the triangle surface;
       clamped: the batch equals one-by-one traces. */
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        rays[k] = ray(-5.0f + (W + 10) * frand(), -5.0f + (H + 10) * frand(), 25.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, -0.05f - 0.5f * frand());
        if (k % 13 == 0) rays[k].dir[1] = 0.0f;
        if (k % 31 == 0) rays[k].dir[0] = rays[k].dir[1] = 0.0f;
    }
    hf_hit *exact = (hf_hit *)malloc(sizeof(hf_hit) * N);
    hf_hit *rd = (hf_hit *)malloc(sizeof(hf_hit) * N);
    const uint32_t rm = HF_METHOD_RADIUS;
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, exact, N));
    CHECK_OK(hf_trace_batch(f, rm, map, len, NULL, rays, N, rd, N)); /* HF_RADIUS_WALK */
    int same = agreeing(exact, rd, N), hits = 0;
    for (int k = 0; k < N; k++) hits += exact[k].hit;
    CHECK(same == N);
    hf_trace_options o = on(HF_SURFACE_TRIANGLES);
    for (uint32_t z = HF_RADIUS_WALK; z <= HF_RADIUS_CLAMP; z++) {
        hf_hit one;
        o.radius_zero = z;
        CHECK_OK(hf_trace_batch(f, rm, map, len, &o, rays, N, rd, N));
        CHECK_OK(hf_trace(f, rm, map, len, &o, &rays[7], &one));
        CHECK(memcmp(&one, &rd[7], sizeof one) == 0);
    }
    printf("radius: %d rays, %d exact hits; walk agrees on %d\n", N, hits, same);
    struct safety_ctx rctx = {f, rm, map, len, 0};
    int vl = view_linear_agrees(f, rays, N, rd, &rctx);
    hf_hit one_vl;
    o = on(HF_SURFACE_VIEW_LINEAR);
    CHECK_OK(hf_trace(f, rm, map, len, &o, &rays[7], &one_vl));
    CHECK(memcmp(&one_vl, &rd[7], sizeof one_vl) == 0);
    printf("radius on the view-linear surface: agrees on %d of %d\n", vl, N);

    /* Bad trace inputs. */
    hf_hit h;
    memset(&h, 0x5A, sizeof h);
    hf_ray nan_ray = rays[0];
    nan_ray.dir[2] = NAN;
    CHECK_BAD(hf_trace(NULL, rm, map, len, NULL, &rays[0], &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, rm, NULL, len, NULL, &rays[0], &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, rm, map, len, NULL, NULL, &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, rm, map, len, NULL, &rays[0], NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_trace(f, rm, map, len - 1, NULL, &rays[0], &h), HF_ERR_BUFFER_TOO_SMALL, &h,
              sizeof h);
    hf_trace_options bad_zero = on(HF_SURFACE_TRIANGLES);
    bad_zero.radius_zero = 2;
    CHECK_BAD(hf_trace(f, rm, map, len, &bad_zero, &rays[0], &h), HF_ERR_INVALID_ENUM, &h,
              sizeof h);
    CHECK_BAD(hf_trace(f, rm, map, len, NULL, &nan_ray, &h), HF_ERR_INVALID_RAY, &h, sizeof h);
    memset(rd, 0x5A, sizeof(hf_hit) * N);
    rays[N - 1] = nan_ray;
    CHECK_BAD(hf_trace_batch(f, rm, map, len, NULL, rays, N, rd, N), HF_ERR_INVALID_RAY, rd, 512);
    CHECK_OK(hf_trace_batch(f, rm, map, len, NULL, rays, 0, rd, N));
    CHECK_BAD(hf_trace_batch(f, rm, map, len, NULL, rays, 2, rd, 1), HF_ERR_BUFFER_TOO_SMALL, rd,
              512);
    bad_zero.radius_zero = 9;
    CHECK_BAD(hf_trace_batch(f, rm, map, len, &bad_zero, rays, 2, rd, 2), HF_ERR_INVALID_ENUM, rd,
              512);
    CHECK_BAD(hf_trace_batch(f, rm, map, len, NULL, NULL, 2, rd, 2), HF_ERR_NULL_POINTER, rd, 512);
    CHECK_BAD(hf_trace_batch(f, rm, map, len, NULL, rays, 2, NULL, 2), HF_ERR_NULL_POINTER,
              nothing, 0);
    free(rays);
    free(exact);
    free(rd);
    free(map);
    free(rows);
    free(scratch);
    free(heights);
    hf_field_destroy(f);
}

/* ---- the cone family: cone step mapping, relaxed cones, QDM ----------------------------- */

static void test_cones(void) {
    enum { W = 33, H = 25, N = 2000, D = HF_MAP_DESC_BYTES / 4 };
    float *heights = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) heights[k] = 6.0f * frand() * frand();
    heights[12 * W + 9] = 20.0f; /* a needle */
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    size_t slen = 0, mlen = 0, clen = 0, rlen = 0, qlen = 0, junk = 5;
    CHECK_OK(hf_cone_scratch_len(W, H, &slen));
    CHECK_OK(hf_maxmip_len(W, H, &mlen));
    CHECK(slen + HF_MAP_DESC_BYTES / 4 == mlen); /* the scratch is the pyramid's texels */
    CHECK_OK(hf_cone_map_len(W, H, &clen));
    CHECK_OK(hf_relaxed_map_len(W, H, &rlen));
    CHECK_OK(hf_qdm_map_len(W, H, &qlen));
    CHECK(clen == 2u * (W - 1) * (H - 1) + D && rlen == (size_t)W * H + D &&
          qlen == 4u * (W - 1) * (H - 1) + D);
    CHECK_BAD(hf_cone_scratch_len(0, H, &junk), HF_ERR_INVALID_SIZE, &junk, sizeof junk);
    CHECK_BAD(hf_cone_map_len(W, 1, &junk), HF_ERR_INVALID_SIZE, &junk, sizeof junk);
    CHECK_BAD(hf_relaxed_map_len(HF_MAX_SIDE + 1u, H, &junk), HF_ERR_INVALID_SIZE, &junk,
              sizeof junk);
    CHECK_BAD(hf_qdm_map_len(W, H, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_cone_scratch_len(W, H, NULL), HF_ERR_NULL_POINTER, nothing, 0);

    float *scratch = (float *)malloc(sizeof(float) * slen);
    float *cmap = (float *)malloc(sizeof(float) * clen), *crows = (float *)malloc(sizeof(float) * clen);
    float *rmap = (float *)malloc(sizeof(float) * rlen), *rrows = (float *)malloc(sizeof(float) * rlen);
    float *qmap = (float *)malloc(sizeof(float) * qlen), *qrows = (float *)malloc(sizeof(float) * qlen);
    memset(cmap, 0, sizeof(float) * clen);
    CHECK_BAD(hf_cone_bake(NULL, 1, cmap, clen), HF_ERR_NULL_POINTER, cmap, 64);
    CHECK_BAD(hf_cone_bake(f, 1, NULL, clen), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_cone_bake(f, 1, cmap, clen - 1), HF_ERR_BUFFER_TOO_SMALL, cmap, 64);
    CHECK_BAD(hf_relaxed_bake(f, 1, rmap, rlen - 1), HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_qdm_bake(f, 1, qmap, qlen - 1), HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_cone_prepare(f, scratch, slen - 1), HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_cone_prepare(NULL, scratch, slen), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_cone_prepare(f, NULL, slen), HF_ERR_NULL_POINTER, nothing, 0);

    /* Whole bakes (1 and 3 threads) against prepare + row bakes in two pieces. */
    CHECK_OK(hf_cone_bake(f, 1, cmap, clen));
    CHECK_OK(hf_relaxed_bake(f, 3, rmap, rlen));
    CHECK_OK(hf_qdm_bake(f, 3, qmap, qlen));
    CHECK_OK(hf_cone_prepare(f, scratch, slen));
    CHECK_BAD(hf_cone_bake_rows(f, scratch, slen, 0, H, crows, clen), HF_ERR_INVALID_ARGUMENT,
              nothing, 0); /* cone rows are cell rows: H - 1 */
    CHECK_BAD(hf_cone_bake_rows(f, scratch, slen, 3, 2, crows, clen), HF_ERR_INVALID_ARGUMENT,
              nothing, 0);
    CHECK_BAD(hf_relaxed_bake_rows(f, scratch, slen, 0, H + 1, rrows, rlen),
              HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_BAD(hf_qdm_bake_rows(f, scratch, slen - 1, 0, 1, qrows, qlen), HF_ERR_BUFFER_TOO_SMALL,
              nothing, 0);
    CHECK_BAD(hf_qdm_bake_rows(f, scratch, slen, 0, 1, qrows, qlen - 1), HF_ERR_BUFFER_TOO_SMALL,
              nothing, 0);
    CHECK_BAD(hf_cone_bake_rows(f, NULL, slen, 0, 1, crows, clen), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_cone_bake_rows(f, scratch, slen, 0, 1, NULL, clen), HF_ERR_NULL_POINTER, nothing,
              0);
    CHECK_BAD(hf_relaxed_bake_rows(NULL, scratch, slen, 0, 1, rrows, rlen), HF_ERR_NULL_POINTER,
              nothing, 0);
    CHECK_OK(hf_cone_bake_rows(f, scratch, slen, 7, H - 1, crows, clen));
    CHECK_OK(hf_cone_bake_rows(f, scratch, slen, 0, 7, crows, clen));
    CHECK(memcmp(crows, cmap, sizeof(float) * clen) == 0);
    CHECK_OK(hf_relaxed_bake_rows(f, scratch, slen, 5, H, rrows, rlen));
    CHECK_OK(hf_relaxed_bake_rows(f, scratch, slen, 0, 5, rrows, rlen));
    CHECK(memcmp(rrows, rmap, sizeof(float) * rlen) == 0);
    CHECK_OK(hf_qdm_bake_rows(f, scratch, slen, 0, H - 1, qrows, qlen));
    CHECK(memcmp(qrows, qmap, sizeof(float) * qlen) == 0);

    /* Cone and QDM are exact within their budget; relaxed cones are approximate. */
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        rays[k] = ray(-5.0f + (W + 10) * frand(), -5.0f + (H + 10) * frand(), 25.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, -0.05f - 0.5f * frand());
        if (k % 11 == 0) rays[k].dir[0] = 0.0f;
        if (k % 29 == 0) rays[k].dir[0] = rays[k].dir[1] = 0.0f;
    }
    hf_hit *exact = (hf_hit *)malloc(sizeof(hf_hit) * N);
    hf_hit *other = (hf_hit *)malloc(sizeof(hf_hit) * N);
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, exact, N));
    /* Each method, its map, its budget (iterations; relaxed: cone steps, bisections). */
    const struct {
        method_map m;
        uint32_t steps, binary;
    } cones[3] = {{{HF_METHOD_CONE, cmap, clen}, 1000, 8},
                  {{HF_METHOD_QDM, qmap, qlen}, 1000, 8},
                  {{HF_METHOD_RELAXED, rmap, rlen}, 64, 16}};
    int same[3] = {0, 0, 0}, hits = 0;
    hf_hit one, h;
    for (int m = 0; m < 3; m++) {
        hf_trace_options o = budget(HF_SURFACE_TRIANGLES, cones[m].steps, cones[m].binary);
        const method_map *c = &cones[m].m;
        CHECK_OK(hf_trace_batch(f, c->method, c->map, c->len, &o, rays, N, other, N));
        for (int k = 0; m == 0 && k < N; k++) hits += exact[k].hit;
        same[m] = agreeing(exact, other, N);
        /* The single call answers as the batch. */
        CHECK_OK(hf_trace(f, c->method, c->map, c->len, &o, &rays[3], &one));
        CHECK_OK(hf_trace_batch(f, c->method, c->map, c->len, &o, &rays[3], 1, &h, 1));
        CHECK(memcmp(&one, &h, sizeof h) == 0);
    }
    CHECK(same[0] == N && same[1] == N && same[2] > N * 9 / 10);
    printf("cones: %d rays, %d exact hits; agree with the exact method: cone %d, qdm %d, relaxed "
           "%d (approximate)\n",
           N, hits, same[0], same[1], same[2]);
    /* A budget of one iteration: the current point, flagged. */
    hf_ray down = ray(16.0f, 12.0f, 100.0f, 0.0f, 0.0f, -1.0f);
    hf_trace_options o = budget(HF_SURFACE_TRIANGLES, 1, 8);
    CHECK_OK(hf_trace(f, HF_METHOD_CONE, cmap, clen, &o, &down, &one));
    CHECK((one.flags & HF_FLAG_BUDGET_EXHAUSTED) || one.hit);

    /* Bad inputs, each of the three methods. */
    memset(&h, 0x5A, sizeof h);
    memset(other, 0x5A, sizeof(hf_hit) * N);
    hf_ray nan_ray = rays[0];
    nan_ray.origin[1] = NAN;
    hf_ray *bad_rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    memcpy(bad_rays, rays, sizeof(hf_ray) * N);
    bad_rays[N / 2] = nan_ray;
    hf_trace_options zero = budget(HF_SURFACE_TRIANGLES, 0, 8);
    o = budget(HF_SURFACE_TRIANGLES, 10, 8);
    for (int m = 0; m < 3; m++) {
        uint32_t me = cones[m].m.method;
        const void *map = cones[m].m.map;
        size_t len = cones[m].m.len;
        CHECK_BAD(hf_trace(f, me, map, len, &zero, &rays[0], &h), HF_ERR_INVALID_ARGUMENT, &h,
                  sizeof h);
        CHECK_BAD(hf_trace(f, me, map, len - 1, &o, &rays[0], &h), HF_ERR_BUFFER_TOO_SMALL, &h,
                  sizeof h);
        CHECK_BAD(hf_trace(f, me, NULL, len, &o, &rays[0], &h), HF_ERR_NULL_POINTER, &h, sizeof h);
        CHECK_BAD(hf_trace(NULL, me, map, len, &o, &rays[0], &h), HF_ERR_NULL_POINTER, &h,
                  sizeof h);
        CHECK_BAD(hf_trace(f, me, map, len, &o, NULL, &h), HF_ERR_NULL_POINTER, &h, sizeof h);
        CHECK_BAD(hf_trace(f, me, map, len, &o, &rays[0], NULL), HF_ERR_NULL_POINTER, nothing, 0);
        CHECK_BAD(hf_trace(f, me, map, len, &o, &nan_ray, &h), HF_ERR_INVALID_RAY, &h, sizeof h);
        CHECK_BAD(hf_trace_batch(f, me, map, len, &o, bad_rays, N, other, N), HF_ERR_INVALID_RAY,
                  other, 512);
        CHECK_OK(hf_trace_batch(f, me, map, len, &o, rays, 0, other, N));
        CHECK_BAD(hf_trace_batch(f, me, map, len, &o, rays, 3, other, 2), HF_ERR_BUFFER_TOO_SMALL,
                  other, 512);
        CHECK_BAD(hf_trace_batch(f, me, map, len, &zero, rays, 3, other, 3),
                  HF_ERR_INVALID_ARGUMENT, other, 512);
        CHECK_BAD(hf_trace_batch(f, me, map, len, &o, NULL, 3, other, 3), HF_ERR_NULL_POINTER,
                  other, 512);
        CHECK_BAD(hf_trace_batch(f, me, NULL, len, &o, rays, 3, other, 3), HF_ERR_NULL_POINTER,
                  other, 512);
        CHECK_BAD(hf_trace_batch(f, me, map, len, &o, rays, 3, NULL, 3), HF_ERR_NULL_POINTER,
                  nothing, 0);
    }
    free(bad_rays);
    free(rays);
    free(exact);
    free(other);
    free(scratch);
    free(cmap);
    free(crows);
    free(rmap);
    free(rrows);
    free(qmap);
    free(qrows);
    free(heights);
    hf_field_destroy(f);
}

/* ---- cylinder-cone safety shapes ------------------------------------------------------ */

static void test_cc(void) {
    enum { W = 37, H = 27, N = 2000, CAP = 32 };
    float *heights = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) heights[k] = 8.0f * frand() * frand();
    heights[10 * W + 20] = 30.0f;
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    size_t mlen = 0, nlen = 0, slen = 0, junk = 3;
    CHECK_OK(hf_cc_map_len(W, H, 0, &mlen));
    CHECK(mlen == (size_t)W * H * 8 + HF_MAP_DESC_BYTES); /* [r, s] per texel and class */
    CHECK_OK(hf_cc_nbuffer_len(W, H, CAP, &nlen));
    CHECK_OK(hf_safety_scratch_len(W, H, &slen));
    CHECK_BAD(hf_cc_map_len(1, H, 0, &junk), HF_ERR_INVALID_SIZE, &junk, sizeof junk);
    CHECK_BAD(hf_cc_nbuffer_len(W, H, 256, &junk), HF_ERR_INVALID_ARGUMENT, &junk, sizeof junk);
    CHECK_BAD(hf_cc_nbuffer_len(W, H, CAP, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    unsigned char *map = (unsigned char *)malloc(mlen), *rows = (unsigned char *)malloc(mlen);
    float *scratch = (float *)malloc(sizeof(float) * slen), *nb = (float *)malloc(sizeof(float) * nlen);
    hf_cc_options good = {HF_CC_SLOPE_EXACT, CAP, HF_RAYS_ALL};
    hf_cc_options nbo = {HF_CC_SLOPE_NBUFFER, CAP, HF_RAYS_ALL}, bad_slope = {2, CAP, 0};
    hf_cc_options bad_cap = {HF_CC_SLOPE_EXACT, 300, 0}, bad_classes = {HF_CC_SLOPE_EXACT, CAP, 16};
    memset(map, 0, mlen);
    CHECK_BAD(hf_cc_bake(f, &bad_slope, 1, map, mlen), HF_ERR_INVALID_ENUM, map, 64);
    CHECK_BAD(hf_cc_bake(f, &bad_cap, 1, map, mlen), HF_ERR_INVALID_ARGUMENT, map, 64);
    CHECK_BAD(hf_cc_bake(f, &bad_classes, 1, map, mlen), HF_ERR_INVALID_ARGUMENT, map, 64);
    CHECK_BAD(hf_cc_bake(f, &good, 1, map, mlen - 1), HF_ERR_BUFFER_TOO_SMALL, map, 64);
    CHECK_BAD(hf_cc_bake(f, NULL, 1, map, mlen), HF_ERR_NULL_POINTER, map, 64);
    CHECK_BAD(hf_cc_bake(NULL, &good, 1, map, mlen), HF_ERR_NULL_POINTER, map, 64);
    CHECK_BAD(hf_cc_bake(f, &good, 1, NULL, mlen), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_cc_prepare_nbuffer(f, CAP, nb, nlen - 1), HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_cc_prepare_nbuffer(f, 999, nb, nlen), HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_BAD(hf_cc_prepare_nbuffer(NULL, CAP, nb, nlen), HF_ERR_NULL_POINTER, nothing, 0);

    /* Whole bakes (1 and 3 threads) against prepare + row bakes in two pieces. */
    CHECK_OK(hf_cc_bake(f, &good, 1, map, mlen));
    CHECK_OK(hf_cc_bake(f, &good, 3, rows, mlen));
    CHECK(memcmp(rows, map, mlen) == 0);
    CHECK_OK(hf_safety_prepare(f, scratch, slen));
    CHECK_OK(hf_cc_prepare_nbuffer(f, CAP, nb, nlen));
    CHECK_BAD(hf_cc_bake_rows(f, scratch, slen, nb, nlen, &good, 0, H + 1, rows, mlen),
              HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_BAD(hf_cc_bake_rows(f, scratch, slen, nb, nlen - 1, &good, 0, 1, rows, mlen),
              HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_cc_bake_rows(f, scratch, slen - 1, nb, nlen, &good, 0, 1, rows, mlen),
              HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_cc_bake_rows(f, scratch, slen, nb, nlen, &good, 0, 1, rows, mlen - 1),
              HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_cc_bake_rows(f, scratch, slen, NULL, nlen, &good, 0, 1, rows, mlen),
              HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_cc_bake_rows(f, scratch, slen, nb, nlen, &bad_slope, 0, 1, rows, mlen),
              HF_ERR_INVALID_ENUM, nothing, 0);
    CHECK_BAD(hf_cc_bake_rows(f, scratch, slen, nb, nlen, &bad_classes, 0, 1, rows, mlen),
              HF_ERR_INVALID_ARGUMENT, nothing, 0);
    memset(rows, 0, mlen);
    CHECK_OK(hf_cc_bake_rows(f, scratch, slen, nb, nlen, &good, 9, H, rows, mlen));
    CHECK_OK(hf_cc_bake_rows(f, scratch, slen, nb, nlen, &good, 0, 9, rows, mlen));
    CHECK(memcmp(rows, map, mlen) == 0);
    unsigned char *nbmap = (unsigned char *)malloc(mlen);
    CHECK_OK(hf_cc_bake(f, &nbo, 0, nbmap, mlen));
    /* The bytes are [r, s] per texel and class: a radius at the cap stores no cone (slope
     * code 255, HF_CC_NO_CONE of the shaders), and some texels have one. */
    int capped_ok = 1, cones = 0;
    for (size_t k = 0; k < mlen - HF_MAP_DESC_BYTES; k += 2) {
        capped_ok &= map[k] < CAP || map[k + 1] == 255;
        cones += map[k + 1] != 255;
    }
    CHECK(capped_ok && cones > 0);

    /* One ray class (y+): a map of its rows only (a quarter of the bytes), equal to the
     * full bake's rows of that class (texel row j of class 2 holds bytes from ((j * 4 + 2)
     * * W) * 2); the row bake agrees. */
    size_t ylen = 0, alen = 0;
    CHECK_OK(hf_cc_map_len(W, H, HF_RAYS_Y_POS, &ylen));
    CHECK((ylen - HF_MAP_DESC_BYTES) * 4 == mlen - HF_MAP_DESC_BYTES);
    /* ray_classes 0 means all four (the full map's size and bytes); above 15 is an error. */
    CHECK_BAD(hf_cc_map_len(W, H, 16, &ylen), HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_OK(hf_cc_map_len(W, H, HF_RAYS_ALL, &alen));
    CHECK(alen == mlen);
    CHECK_BAD(hf_cc_map_len(W, H, HF_RAYS_Y_POS, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    hf_cc_options co = good;
    co.ray_classes = 0;
    CHECK_OK(hf_cc_bake(f, &co, 1, rows, mlen));
    CHECK(memcmp(rows, map, mlen) == 0);
    co.ray_classes = HF_RAYS_Y_POS;
    CHECK_BAD(hf_cc_bake(f, &co, 1, rows, ylen - 1), HF_ERR_BUFFER_TOO_SMALL, rows, 64);
    CHECK_OK(hf_cc_bake(f, &co, 2, rows, ylen));
    int cc_mask_ok = 1;
    for (size_t j = 0; j < (size_t)H; j++)
        cc_mask_ok &= memcmp(rows + j * W * 2, map + (j * 4 + 2) * W * 2, (size_t)W * 2) == 0;
    CHECK(cc_mask_ok);
    /* In two row ranges (each call writes its rows of the whole map). */
    unsigned char *rows2 = (unsigned char *)malloc(ylen);
    CHECK_OK(hf_cc_bake_rows(f, scratch, slen, nb, nlen, &co, 5, H, rows2, ylen));
    CHECK_OK(hf_cc_bake_rows(f, scratch, slen, nb, nlen, &co, 0, 5, rows2, ylen));
    CHECK(memcmp(rows, rows2, ylen) == 0);
    free(rows2);

    /* Exact: both slope variants find the exact method's hits (shadow rays too). */
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        rays[k] = ray(-5.0f + (W + 10) * frand(), -5.0f + (H + 10) * frand(), 35.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, (k % 4 == 0 ? 0.3f : -0.5f) * frand());
        if (k % 13 == 0) rays[k].dir[1] = 0.0f;
    }
    hf_hit *exact = (hf_hit *)malloc(sizeof(hf_hit) * N), *cc = (hf_hit *)malloc(sizeof(hf_hit) * N);
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, exact, N));
    const uint32_t cm = HF_METHOD_CC; /* the cap is the map's (its descriptor names it) */
    int same[2] = {0, 0}, hits = 0;
    for (int v = 0; v < 2; v++) {
        CHECK_OK(hf_trace_batch(f, cm, v == 0 ? map : nbmap, mlen, NULL, rays, N, cc, N));
        for (int k = 0; v == 0 && k < N; k++) hits += exact[k].hit;
        same[v] = agreeing(exact, cc, N);
    }
    CHECK(same[0] == N && same[1] == N);
    printf("cc: %d rays, %d exact hits; exact slopes agree on %d, n-buffer slopes on %d\n", N, hits,
           same[0], same[1]);
    /* The one-class map (still in `rows`); `cc` holds the whole exact-slope map's hits. */
    CHECK_OK(hf_trace_batch(f, cm, map, mlen, NULL, rays, N, cc, N));
    struct safety_ctx y_ctx = {f, cm, rows, ylen, HF_RAYS_Y_POS};
    check_class_map("cc, one class", rays, N, exact, cc, &y_ctx);
    check_class_options(f, cm, rows, ylen, HF_RAYS_Y_POS, &rays[0]);
    hf_trace_options o = on(HF_SURFACE_TRIANGLES);
    struct safety_ctx cctx = {f, cm, map, mlen, HF_RAYS_ALL};
    int vl = view_linear_agrees(f, rays, N, cc, &cctx);
    printf("cc on the view-linear surface: agrees on %d of %d\n", vl, N);
    hf_hit one, h;
    CHECK_OK(hf_trace(f, cm, map, mlen, NULL, &rays[5], &one));
    CHECK_OK(hf_trace_batch(f, cm, map, mlen, NULL, &rays[5], 1, &h, 1));
    CHECK(memcmp(&one, &h, sizeof h) == 0);
    memset(&h, 0x5A, sizeof h);
    hf_ray nan_ray = rays[0];
    nan_ray.t_max = NAN;
    /* The cap is no longer passed (a bad one was HF_ERR_INVALID_ARGUMENT): a class set
     * other than the map's is refused instead. */
    o.ray_classes = HF_RAYS_Y_POS;
    CHECK_BAD(hf_trace(f, cm, map, mlen, &o, &rays[0], &h), HF_ERR_MAP_MISMATCH, &h, sizeof h);
    CHECK_BAD(hf_trace(f, cm, map, mlen - 1, NULL, &rays[0], &h), HF_ERR_BUFFER_TOO_SMALL, &h,
              sizeof h);
    CHECK_BAD(hf_trace(f, cm, NULL, mlen, NULL, &rays[0], &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, cm, map, mlen, NULL, NULL, &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, cm, map, mlen, NULL, &rays[0], NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_trace(f, cm, map, mlen, NULL, &nan_ray, &h), HF_ERR_INVALID_RAY, &h, sizeof h);
    memset(cc, 0x5A, sizeof(hf_hit) * N);
    rays[1] = nan_ray;
    CHECK_BAD(hf_trace_batch(f, cm, map, mlen, NULL, rays, N, cc, N), HF_ERR_INVALID_RAY, cc, 512);
    CHECK_OK(hf_trace_batch(f, cm, map, mlen, NULL, rays, 0, cc, N));
    CHECK_BAD(hf_trace_batch(f, cm, map, mlen, NULL, rays, 4, cc, 3), HF_ERR_BUFFER_TOO_SMALL, cc,
              512);
    CHECK_BAD(hf_trace_batch(NULL, cm, map, mlen, NULL, rays, 4, cc, 4), HF_ERR_NULL_POINTER, cc,
              512);
    free(rays);
    free(exact);
    free(cc);
    free(map);
    free(nbmap);
    free(rows);
    free(scratch);
    free(nb);
    free(heights);
    hf_field_destroy(f);
}

/* ---- the trace options, method and surface numbers and names --------------------- */

/* 1 when `method` traces `surface` (hf_trace_options::surface): the safety-shape
 * methods the triangle and view-linear surfaces, the cone family triangles only. */
static int traces_surface(uint32_t method, uint32_t surface) {
    switch (method) {
    case HF_METHOD_SAFETY:
    case HF_METHOD_CC:
    case HF_METHOD_RADIUS:
        return surface == HF_SURFACE_TRIANGLES || surface == HF_SURFACE_VIEW_LINEAR;
    case HF_METHOD_CONE:
    case HF_METHOD_RELAXED:
    case HF_METHOD_QDM: return surface == HF_SURFACE_TRIANGLES;
    default: return 1;
    }
}

/* hf_trace_camera: its hits are hf_trace_batch's on hf_camera_ray's rays, bit for bit,
 * for each of `n` methods `all` of field `f` (W x H), at 1 and 2 threads; its shadow
 * pass is hf_shadow_ray then hf_trace per pixel; bad cameras and buffers are refused. */
static void check_camera(const hf_field *f, const method_map *all, int n, uint32_t w,
                         uint32_t h) {
    enum { CW = 19, CH = 13, NP = CW * CH };
    hf_camera cam = {{-3.0f, -4.0f, 12.0f}, {0.5f * w + 3.0f, 0.5f * h + 4.0f, -10.0f},
                     {0.0f, 0.0f, 1.0f}, 50.0f, CW, CH, INFINITY};
    static hf_ray rays[NP];
    static hf_hit batch[NP], cam_hits[NP], shadows[NP];
    for (uint32_t y = 0; y < CH; y++)
        for (uint32_t x = 0; x < CW; x++) CHECK_OK(hf_camera_ray(&cam, x, y, &rays[y * CW + x]));
    const float light[3] = {0.5f, -0.3f, 0.8f};
    size_t hits = 0;
    for (int m = 0; m < n; m++) {
        CHECK_OK(hf_trace_batch(f, all[m].method, all[m].map, all[m].len, NULL, rays, NP, batch,
                                NP));
        for (uint32_t t = 1; t <= 2; t++) {
            hf_trace_options o;
            CHECK_OK(hf_trace_options_default(&o));
            o.threads = t;
            memset(cam_hits, 0x5A, sizeof cam_hits);
            CHECK_OK(hf_trace_camera(f, all[m].method, all[m].map, all[m].len, &o, &cam,
                                     cam_hits, NP));
            CHECK(memcmp(cam_hits, batch, sizeof batch) == 0);
        }
        CHECK_OK(hf_trace_camera_shadows(f, all[m].method, all[m].map, all[m].len, NULL, &cam,
                                         cam_hits, NP, &light, shadows, NP));
        int same = 1;
        for (int k = 0; k < NP; k++) {
            if (!cam_hits[k].hit) {
                same &= shadows[k].hit == 0;
                continue;
            }
            hits += m == 0;
            hf_ray sr;
            hf_hit one;
            CHECK_OK(hf_shadow_ray(f, HF_SURFACE_TRIANGLES, &rays[k], &cam_hits[k], &light, &sr));
            CHECK_OK(hf_trace(f, all[m].method, all[m].map, all[m].len, NULL, &sr, &one));
            same &= memcmp(&one, &shadows[k], sizeof one) == 0;
        }
        CHECK(same);
    }
    CHECK(hits > NP / 4 && hits < NP);
    /* Bad cameras, pixels and buffers: refused, nothing written. */
    const hf_camera good = cam;
    hf_camera bad[7];
    for (int k = 0; k < 7; k++) bad[k] = good;
    bad[0].width = 0;
    bad[1].fov_y_deg = 0.0f;
    bad[2].fov_y_deg = 180.0f;
    bad[3].forward[0] = bad[3].forward[1] = bad[3].forward[2] = 0.0f;
    bad[4].up[0] = good.forward[0], bad[4].up[1] = good.forward[1], bad[4].up[2] = good.forward[2];
    bad[5].eye[1] = NAN;
    bad[6].t_max = 0.0f;
    hf_ray r;
    memset(&r, 0x5A, sizeof r);
    memset(cam_hits, 0x5A, sizeof cam_hits);
    for (int k = 0; k < 7; k++) {
        CHECK_BAD(hf_camera_ray(&bad[k], 0, 0, &r), HF_ERR_INVALID_ARGUMENT, &r, sizeof r);
        CHECK_BAD(hf_trace_camera(f, HF_METHOD_EXACT, NULL, 0, NULL, &bad[k], cam_hits, NP),
                  HF_ERR_INVALID_ARGUMENT, cam_hits, sizeof cam_hits);
    }
    CHECK_BAD(hf_camera_ray(&good, CW, 0, &r), HF_ERR_INVALID_ARGUMENT, &r, sizeof r);
    CHECK_BAD(hf_camera_ray(NULL, 0, 0, &r), HF_ERR_NULL_POINTER, &r, sizeof r);
    CHECK_BAD(hf_trace_camera(f, HF_METHOD_EXACT, NULL, 0, NULL, &good, cam_hits, NP - 1),
              HF_ERR_BUFFER_TOO_SMALL, cam_hits, sizeof cam_hits);
    CHECK_BAD(hf_trace_camera(f, HF_METHOD_EXACT, NULL, 0, NULL, NULL, cam_hits, NP),
              HF_ERR_NULL_POINTER, cam_hits, sizeof cam_hits);
    CHECK_BAD(hf_trace_camera(f, 99, NULL, 0, NULL, &good, cam_hits, NP), HF_ERR_INVALID_ENUM,
              cam_hits, sizeof cam_hits);
    CHECK_OK(hf_trace_camera(f, HF_METHOD_EXACT, NULL, 0, NULL, &good, batch, NP));
    CHECK_BAD(hf_trace_camera_shadows(f, HF_METHOD_EXACT, NULL, 0, NULL, &good, batch, NP - 1,
                                      &light, shadows, NP),
              HF_ERR_BUFFER_TOO_SMALL, nothing, 0);
    CHECK_BAD(hf_trace_camera_shadows(f, HF_METHOD_EXACT, NULL, 0, NULL, &good, batch, NP,
                                      &light, batch, NP),
              HF_ERR_INVALID_ARGUMENT, nothing, 0);
    CHECK_BAD(hf_trace_camera_shadows(f, HF_METHOD_EXACT, NULL, 0, NULL, &good, batch, NP, NULL,
                                      shadows, NP),
              HF_ERR_NULL_POINTER, nothing, 0);
    printf("camera: %zu of %d pixels hit; hf_trace_camera and its shadow pass as the batch\n",
           hits, NP);
}

static void test_trace_options(void) {
    enum { W = 9, H = 7, R = 16 };
    float heights[W * H];
    for (int k = 0; k < W * H; k++) heights[k] = 5.0f * frand();
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));

    /* The defaults; NULL is an error. */
    hf_trace_options d;
    memset(&d, 0xAB, sizeof d);
    CHECK_OK(hf_trace_options_default(&d));
    int reserved_zero = 1;
    for (int k = 0; k < 10; k++) reserved_zero &= d.reserved[k] == 0;
    CHECK(d.surface == HF_SURFACE_TRIANGLES && d.ray_classes == 0 && d.steps == 64 &&
          d.binary_steps == 8 && d.radius_zero == HF_RADIUS_WALK && d.threads == 1 &&
          reserved_zero);
    CHECK_BAD(hf_trace_options_default(NULL), HF_ERR_NULL_POINTER, nothing, 0);

    /* Every method's map of this field (NULL and 0 for the three without one). */
    size_t plen, slen, clen, rlen, qlen, cclen, radlen;
    CHECK_OK(hf_maxmip_len(W, H, &plen));
    CHECK_OK(hf_safety_map_len(W, H, HF_SAFETY_DIRECTIONAL, 0, &slen));
    CHECK_OK(hf_cone_map_len(W, H, &clen));
    CHECK_OK(hf_relaxed_map_len(W, H, &rlen));
    CHECK_OK(hf_qdm_map_len(W, H, &qlen));
    CHECK_OK(hf_cc_map_len(W, H, 0, &cclen));
    CHECK_OK(hf_radius_map_len(W, H, &radlen));
    float *pyr = (float *)malloc(sizeof(float) * plen);
    float *cone = (float *)malloc(sizeof(float) * clen);
    float *relaxed = (float *)malloc(sizeof(float) * rlen);
    float *qdm = (float *)malloc(sizeof(float) * qlen);
    unsigned char *safety = (unsigned char *)malloc(slen), *cc = (unsigned char *)malloc(cclen);
    unsigned char *radius = (unsigned char *)malloc(radlen);
    hf_safety_options so = {HF_SAFETY_DIRECTIONAL, 0, 255, HF_RAYS_ALL};
    hf_cc_options co = {HF_CC_SLOPE_EXACT, 32, HF_RAYS_ALL};
    hf_radius_options ro = {0.0f, 255};
    CHECK_OK(hf_maxmip_bake(f, pyr, plen));
    CHECK_OK(hf_safety_bake(f, &so, 1, safety, slen));
    CHECK_OK(hf_cone_bake(f, 1, cone, clen));
    CHECK_OK(hf_relaxed_bake(f, 1, relaxed, rlen));
    CHECK_OK(hf_qdm_bake(f, 1, qdm, qlen));
    CHECK_OK(hf_cc_bake(f, &co, 1, cc, cclen));
    CHECK_OK(hf_radius_bake(f, &ro, 1, radius, radlen));
    const method_map all[10] = {
        {HF_METHOD_EXACT, NULL, 0},      {HF_METHOD_LINEAR_BINARY, NULL, 0},
        {HF_METHOD_LINEAR_SECANT, NULL, 0}, {HF_METHOD_MAXMIP, pyr, plen},
        {HF_METHOD_SAFETY, safety, slen}, {HF_METHOD_CONE, cone, clen},
        {HF_METHOD_RELAXED, relaxed, rlen}, {HF_METHOD_QDM, qdm, qlen},
        {HF_METHOD_CC, cc, cclen},       {HF_METHOD_RADIUS, radius, radlen}};

    hf_ray rays[R];
    for (int k = 0; k < R; k++)
        rays[k] = ray(-2.0f + (W + 4) * frand(), -2.0f + (H + 4) * frand(), 6.0f + 4.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, -0.1f - frand());
    hf_hit a[R], b[R], h;
    for (int m = 0; m < 10; m++) {
        uint32_t me = all[m].method;
        const void *map = all[m].map;
        size_t len = all[m].len;
        /* NULL options are the defaults: the same hits, single and batch. */
        CHECK(all[m].method == (uint32_t)m);
        CHECK_OK(hf_trace_batch(f, me, map, len, NULL, rays, R, a, R));
        CHECK_OK(hf_trace_batch(f, me, map, len, &d, rays, R, b, R));
        CHECK(memcmp(a, b, sizeof a) == 0);
        CHECK_OK(hf_trace(f, me, map, len, NULL, &rays[3], &h));
        CHECK(memcmp(&h, &a[3], sizeof h) == 0);
        /* A nonzero reserved word, whichever, is refused. */
        memset(b, 0x5A, sizeof b);
        for (int k = 0; k < 10; k++) {
            hf_trace_options o = d;
            o.reserved[k] = 1;
            CHECK_BAD(hf_trace(f, me, map, len, &o, &rays[0], &h), HF_ERR_INVALID_ARGUMENT, &h,
                      sizeof h);
            CHECK_BAD(hf_trace_batch(f, me, map, len, &o, rays, R, b, R), HF_ERR_INVALID_ARGUMENT,
                      b, sizeof b);
        }
        /* The surfaces it does not trace are refused, unknown ones are bad enums. */
        for (uint32_t s = HF_SURFACE_TRIANGLES; s <= HF_SURFACE_VIEW_LINEAR + 1; s++) {
            hf_trace_options o = on(s);
            if (s <= HF_SURFACE_VIEW_LINEAR && traces_surface(me, s)) {
                CHECK_OK(hf_trace_batch(f, me, map, len, &o, rays, R, a, R));
                continue;
            }
            hf_result want =
                s > HF_SURFACE_VIEW_LINEAR ? HF_ERR_INVALID_ENUM : HF_ERR_INVALID_ARGUMENT;
            CHECK_BAD(hf_trace(f, me, map, len, &o, &rays[0], &h), want, &h, sizeof h);
            CHECK_BAD(hf_trace_batch(f, me, map, len, &o, rays, R, b, R), want, b, sizeof b);
        }
    }
    /* A batch on several threads (bands of 256 rays) answers as on one, every method:
     * threads 2, 3 and 0 (one per core) against the default 1. */
    enum { BIG = 2000 };
    hf_ray *many = (hf_ray *)malloc(sizeof(hf_ray) * BIG);
    hf_hit *one_thread = (hf_hit *)malloc(sizeof(hf_hit) * BIG);
    hf_hit *threaded = (hf_hit *)malloc(sizeof(hf_hit) * BIG);
    for (int k = 0; k < BIG; k++) many[k] = rays[k % R];
    for (int k = 0; k < BIG; k++) many[k].origin[0] += 0.001f * (float)(k / R);
    for (int m = 0; m < 10; m++) {
        CHECK_OK(hf_trace_batch(f, all[m].method, all[m].map, all[m].len, NULL, many, BIG,
                                one_thread, BIG));
        for (uint32_t t = 0; t < 4; t = t == 0 ? 2 : t + 1) {
            hf_trace_options o = d;
            o.threads = t;
            memset(threaded, 0x5A, sizeof(hf_hit) * BIG);
            CHECK_OK(hf_trace_batch(f, all[m].method, all[m].map, all[m].len, &o, many, BIG,
                                    threaded, BIG));
            CHECK(memcmp(one_thread, threaded, sizeof(hf_hit) * BIG) == 0);
            if (t == 0) break;
        }
    }
    /* A bad ray far into a threaded batch still fails it first and writes nothing. */
    many[1500].dir[0] = many[1500].dir[1] = many[1500].dir[2] = 0.0f;
    hf_trace_options o3 = d;
    o3.threads = 3;
    memset(threaded, 0x5A, sizeof(hf_hit) * BIG);
    CHECK_BAD(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &o3, many, BIG, threaded, BIG),
              HF_ERR_INVALID_RAY, threaded, sizeof(hf_hit) * BIG);
    free(threaded);
    free(one_thread);
    free(many);
    /* A method without a map takes NULL and 0: a length is refused, with or without a
     * pointer. */
    for (uint32_t me = HF_METHOD_EXACT; me <= HF_METHOD_LINEAR_SECANT; me++) {
        CHECK_BAD(hf_trace(f, me, NULL, 1, NULL, &rays[0], &h), HF_ERR_INVALID_ARGUMENT, &h,
                  sizeof h);
        CHECK_BAD(hf_trace(f, me, pyr, plen, NULL, &rays[0], &h), HF_ERR_INVALID_ARGUMENT, &h,
                  sizeof h);
        CHECK_BAD(hf_trace_batch(f, me, NULL, 1, NULL, rays, R, b, R), HF_ERR_INVALID_ARGUMENT, b,
                  sizeof b);
    }
    /* Unknown methods. */
    const uint32_t bad_methods[3] = {HF_METHOD_RADIUS + 1, 99, 0xFFFFFFFFu};
    for (int k = 0; k < 3; k++) {
        CHECK_BAD(hf_trace(f, bad_methods[k], NULL, 0, NULL, &rays[0], &h), HF_ERR_INVALID_ENUM,
                  &h, sizeof h);
        CHECK_BAD(hf_trace_batch(f, bad_methods[k], pyr, plen, NULL, rays, R, b, R),
                  HF_ERR_INVALID_ENUM, b, sizeof b);
    }

    /* Names of every method and surface; short buffers, unknown values, NULLs. */
    static const char *const methods[10] = {"exact", "linear-binary", "linear-secant", "maxmip",
                                            "safety", "cone", "relaxed", "qdm", "cc", "radius"};
    static const char *const surfaces[5] = {"triangles", "bilinear", "height-planes",
                                            "linear-planes", "view-linear"};
    hf_result (*const name_of[2])(uint32_t, char *, size_t, size_t *) = {hf_method_name,
                                                                        hf_surface_name};
    const char *const *names[2] = {methods, surfaces};
    const uint32_t counts[2] = {10, 5};
    for (int t = 0; t < 2; t++) {
        char buf[32];
        size_t written = 777;
        for (uint32_t v = 0; v < counts[t]; v++) {
            size_t n = strlen(names[t][v]);
            memset(buf, 'x', sizeof buf);
            CHECK_OK(name_of[t](v, buf, sizeof buf, &written));
            CHECK(written == n && strcmp(buf, names[t][v]) == 0);
            CHECK_OK(name_of[t](v, buf, n + 1, &written));
            CHECK(written == n && strcmp(buf, names[t][v]) == 0);
            memset(buf, 'x', sizeof buf);
            CHECK_BAD(name_of[t](v, buf, n, &written), HF_ERR_BUFFER_TOO_SMALL, buf, sizeof buf);
            CHECK_BAD(name_of[t](v, buf, 0, &written), HF_ERR_BUFFER_TOO_SMALL, &written,
                      sizeof written);
        }
        CHECK_BAD(name_of[t](counts[t], buf, sizeof buf, &written), HF_ERR_INVALID_ENUM, buf,
                  sizeof buf);
        CHECK_BAD(name_of[t](0xFFFFFFFFu, buf, sizeof buf, &written), HF_ERR_INVALID_ENUM,
                  &written, sizeof written);
        CHECK_BAD(name_of[t](0, NULL, sizeof buf, &written), HF_ERR_NULL_POINTER, &written,
                  sizeof written);
        CHECK_BAD(name_of[t](0, buf, sizeof buf, NULL), HF_ERR_NULL_POINTER, buf, sizeof buf);
    }
    check_camera(f, all, 10, W, H);
    free(pyr);
    free(cone);
    free(relaxed);
    free(qdm);
    free(safety);
    free(cc);
    free(radius);
    hf_field_destroy(f);
}

/* ---- row bakes from several threads at once ------------------------------------------- */

typedef struct rows_job {
    const hf_field *field;
    uint32_t level, r0, r1;
    float *pyramid;
    size_t len;
    const float *scratch;
    size_t scratch_len;
    unsigned char *map;
    size_t map_len;
    hf_result result;
} rows_job;

static void *bake_rows_thread(void *arg) {
    rows_job *j = (rows_job *)arg;
    if (j->pyramid) {
        j->result = hf_maxmip_bake_rows(j->field, j->level, j->r0, j->r1, j->pyramid, j->len);
    } else {
        hf_safety_options o = {HF_SAFETY_DIRECTIONAL, 0, 255, HF_RAYS_ALL};
        j->result = hf_safety_bake_rows(j->field, j->scratch, j->scratch_len, &o, j->r0, j->r1,
                                        j->map, j->map_len);
    }
    return NULL;
}

/* Disjoint row ranges of one level (or of the safety map) baked by four threads at once
 * into one buffer: what a job system does. Equals the single-threaded bake. */
static void test_concurrent_rows(void) {
    enum { W = 203, H = 117, T = 4 };
    float *hs = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) hs[k] = 50.0f * frand();
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(hs, W * H, W, H, W, &f));
    size_t len = 0;
    CHECK_OK(hf_maxmip_len(W, H, &len));
    float *p1 = (float *)malloc(sizeof(float) * len), *p2 = (float *)calloc(len, sizeof(float));
    CHECK_OK(hf_maxmip_bake(f, p1, len));
    hf_level levels[HF_MAX_LEVELS];
    uint32_t count = 0;
    CHECK_OK(hf_maxmip_levels(W, H, levels, HF_MAX_LEVELS, &count));
    pthread_t th[T];
    rows_job jobs[T];
    for (uint32_t l = 0; l < count; l++) {
        uint32_t h = levels[l].height, per = (h + T - 1) / T;
        for (int t = 0; t < T; t++) {
            uint32_t r0 = per * (uint32_t)t < h ? per * (uint32_t)t : h;
            uint32_t r1 = r0 + per < h ? r0 + per : h;
            rows_job j = {f, l, r0, r1, p2, len, NULL, 0, NULL, 0, HF_ERR_PANIC};
            jobs[t] = j;
            CHECK(pthread_create(&th[t], NULL, bake_rows_thread, &jobs[t]) == 0);
        }
        for (int t = 0; t < T; t++) {
            pthread_join(th[t], NULL);
            CHECK(jobs[t].result == HF_OK);
        }
    }
    CHECK(memcmp(p1, p2, sizeof(float) * len) == 0);

    size_t slen = 0, mlen = 0;
    CHECK_OK(hf_safety_scratch_len(W, H, &slen));
    CHECK_OK(hf_safety_map_len(W, H, HF_SAFETY_DIRECTIONAL, 0, &mlen));
    float *scratch = (float *)malloc(sizeof(float) * slen);
    unsigned char *m1 = (unsigned char *)malloc(mlen), *m2 = (unsigned char *)calloc(mlen, 1);
    hf_safety_options o = {HF_SAFETY_DIRECTIONAL, 0, 255, HF_RAYS_ALL};
    CHECK_OK(hf_safety_bake(f, &o, 1, m1, mlen));
    CHECK_OK(hf_safety_prepare(f, scratch, slen));
    uint32_t per = (H + T - 1) / T;
    for (int t = 0; t < T; t++) {
        uint32_t r0 = per * (uint32_t)t, r1 = r0 + per < H ? r0 + per : H;
        rows_job j = {f, 0, r0, r1, NULL, 0, scratch, slen, m2, mlen, HF_ERR_PANIC};
        jobs[t] = j;
        CHECK(pthread_create(&th[t], NULL, bake_rows_thread, &jobs[t]) == 0);
    }
    for (int t = 0; t < T; t++) {
        pthread_join(th[t], NULL);
        CHECK(jobs[t].result == HF_OK);
    }
    CHECK(memcmp(m1, m2, mlen) == 0);
    free(scratch);
    free(m1);
    free(m2);
    free(p1);
    free(p2);
    free(hs);
    hf_field_destroy(f);
}

/* ---- shader sources -------------------------------------------------------------- */

/* The full build has every method; bake plans follow the scene. */
static void test_build_and_plan(void) {
    for (uint32_t m = 0; m <= HF_METHOD_RADIUS; m++) {
        uint32_t has = 7;
        CHECK_OK(hf_build_has_method(m, &has));
        CHECK(has == 1);
    }
    uint32_t has = 7;
    CHECK_BAD(hf_build_has_method(HF_METHOD_RADIUS + 1, &has), HF_ERR_INVALID_ENUM, &has,
              sizeof has);
    CHECK_BAD(hf_build_has_method(0, NULL), HF_ERR_NULL_POINTER, nothing, 0);

    hf_scene scene;
    hf_bake_plan plan;
    char text[1024];
    size_t n = 0;
    CHECK_OK(hf_scene_general(HF_METHOD_EXACT, HF_SURFACE_TRIANGLES, &scene));
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.pyramid == HF_NEED_SKIP && plan.safety_map == HF_NEED_SKIP &&
          plan.cone_map == HF_NEED_SKIP && plan.ray_classes == 0);
    CHECK_OK(hf_scene_bake_plan_skipped(&scene, text, sizeof text, &n));
    CHECK(n == strlen(text) && strstr(text, "pyramid: ") != NULL);

    CHECK_OK(hf_scene_general(HF_METHOD_SAFETY, HF_SURFACE_TRIANGLES, &scene));
    scene.ray_classes = HF_RAYS_X_POS | HF_RAYS_Y_NEG;
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.safety_scratch == HF_NEED_SCRATCH && plan.safety_map == HF_NEED_KEEP);
    CHECK(plan.cc_map == HF_NEED_SKIP && plan.pyramid == HF_NEED_SKIP);
    CHECK(plan.ray_classes == scene.ray_classes && plan.safety_variant == HF_SAFETY_DIRECTIONAL);
    CHECK_OK(hf_scene_bake_plan_skipped(&scene, text, sizeof text, &n));
    CHECK(strstr(text, "x- channel: ") != NULL && strstr(text, "x+ channel") == NULL);
    scene.ray_classes = HF_RAYS_Y_POS;
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.safety_variant == HF_SAFETY_ISOTROPIC);

    CHECK_OK(hf_scene_general(HF_METHOD_CC, HF_SURFACE_TRIANGLES, &scene));
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.cc_map == HF_NEED_KEEP && plan.nbuffer == HF_NEED_SCRATCH &&
          plan.safety_map == HF_NEED_SKIP && plan.ray_classes == HF_RAYS_ALL);
    CHECK_OK(hf_scene_general(HF_METHOD_RADIUS, HF_SURFACE_TRIANGLES, &scene));
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.radius_map == HF_NEED_KEEP && plan.safety_scratch == HF_NEED_SCRATCH &&
          plan.safety_map == HF_NEED_SKIP && plan.ray_classes == 0);
    CHECK_OK(hf_scene_general(HF_METHOD_QDM, HF_SURFACE_TRIANGLES, &scene));
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.qdm_map == HF_NEED_KEEP && plan.pyramid == HF_NEED_SCRATCH &&
          plan.cone_map == HF_NEED_SKIP);

    hf_bake_plan before = plan;
    scene.ray_classes = 0;
    CHECK_BAD(hf_scene_bake_plan(&scene, &plan), HF_ERR_INVALID_ARGUMENT, &plan, sizeof plan);
    CHECK(memcmp(&before, &plan, sizeof plan) == 0);
    CHECK_BAD(hf_scene_bake_plan(NULL, &plan), HF_ERR_NULL_POINTER, &plan, sizeof plan);
    scene.ray_classes = HF_RAYS_ALL;
    CHECK_BAD(hf_scene_bake_plan(&scene, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_scene_bake_plan_skipped(&scene, text, 3, &n), HF_ERR_BUFFER_TOO_SMALL, text, 3);
}

static void test_shader_source(void) {
    for (uint32_t m = HF_METHOD_EXACT; m <= HF_METHOD_RADIUS; m++) {
        size_t len = 0, written = 0;
        CHECK_OK(hf_shader_source_len(m, &len));
        CHECK(len > 100);
        char *buf = (char *)malloc(len);
        CHECK_BAD(hf_shader_source(m, buf, len - 1, &written), HF_ERR_BUFFER_TOO_SMALL, &written,
                  sizeof written);
        CHECK_OK(hf_shader_source(m, buf, len, &written));
        CHECK(written == len - 1 && buf[written] == 0 && strlen(buf) == written);
        CHECK(strstr(buf, "Trace hf_trace(Query q)") != NULL);
        CHECK(strstr(buf, "#version") == NULL);
        free(buf);
    }
    size_t len = 5, written = 5;
    char buf[8];
    memset(buf, 'x', sizeof buf);
    CHECK_BAD(hf_shader_source_len(HF_METHOD_RADIUS + 1, &len), HF_ERR_INVALID_ENUM, &len,
              sizeof len);
    CHECK_BAD(hf_shader_source_len(0, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_shader_source(77, buf, sizeof buf, &written), HF_ERR_INVALID_ENUM, &written,
              sizeof written);
    CHECK_BAD(hf_shader_source(0, NULL, 100, &written), HF_ERR_NULL_POINTER, &written,
              sizeof written);
    CHECK_BAD(hf_shader_source(0, buf, sizeof buf, NULL), HF_ERR_NULL_POINTER, buf, sizeof buf);
}

int main(void) {
    test_version_and_messages();
    test_field_constructors();
    test_known_hits();
    test_bad_queries();
    test_methods_agree();
    test_world_units();
    test_bake_and_update();
    test_safety();
    test_radius();
    test_cones();
    test_cc();
    test_trace_options();
    test_concurrent_rows();
    test_build_and_plan();
    test_shader_source();
    printf("c api: %d checks, %d bad inputs tried\n", checks, bad_inputs);
    printf("c-api: %d passed, %d failed\n", checks - failures, failures);
    return failures == 0 ? 0 : 1;
}
