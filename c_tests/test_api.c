/* API tests of libhfcast: every bad input returns its error code and writes nothing;
 * good queries match known values; the methods agree with each other.
 * Built by the Makefile with -Wall -Wextra -Werror -std=c99, run plain, under
 * -fsanitize=address,undefined, and under valgrind. */
#define _POSIX_C_SOURCE 200112L
#include "hfcast.h"

#include "check_api.h"

#include <math.h>
#include <pthread.h>
#include <stddef.h>
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

/* Bad trace inputs of `method` over its `map` (`len` elements) with options `o` (NULL:
 * the defaults), on `rays[0..n)` (n >= 4) and `hits` (n hits): NULL pointers, a short
 * map or hit buffer, NaN rays (alone and inside a batch) and unknown surfaces are
 * refused and write nothing; an empty batch is HF_OK. */
static void check_bad_traces(const hf_field *f, uint32_t method, const void *map, size_t len,
                             const hf_trace_options *o, const hf_ray *rays, int n,
                             hf_hit *hits) {
    hf_hit h;
    memset(&h, 0x5A, sizeof h);
    memset(hits, 0x5A, sizeof(hf_hit) * n);
    const size_t some = 3;
    CHECK_BAD(hf_trace(NULL, method, map, len, o, &rays[0], &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, method, NULL, len, o, &rays[0], &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, method, map, len, o, NULL, &h), HF_ERR_NULL_POINTER, &h, sizeof h);
    CHECK_BAD(hf_trace(f, method, map, len, o, &rays[0], NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_trace(f, method, map, len - 1, o, &rays[0], &h), HF_ERR_BUFFER_TOO_SMALL, &h,
              sizeof h);
    CHECK_OK(hf_trace_batch(f, method, map, len, o, rays, 0, hits, n));
    CHECK_BAD(hf_trace_batch(f, method, map, len, o, rays, some, hits, some - 1),
              HF_ERR_BUFFER_TOO_SMALL, hits, 512);
    CHECK_BAD(hf_trace_batch(f, method, map, len - 1, o, rays, some, hits, some),
              HF_ERR_BUFFER_TOO_SMALL, hits, 512);
    CHECK_BAD(hf_trace_batch(NULL, method, map, len, o, rays, some, hits, some),
              HF_ERR_NULL_POINTER, hits, 512);
    CHECK_BAD(hf_trace_batch(f, method, NULL, len, o, rays, some, hits, some),
              HF_ERR_NULL_POINTER, hits, 512);
    CHECK_BAD(hf_trace_batch(f, method, map, len, o, NULL, some, hits, some),
              HF_ERR_NULL_POINTER, hits, 512);
    CHECK_BAD(hf_trace_batch(f, method, map, len, o, rays, some, NULL, some),
              HF_ERR_NULL_POINTER, nothing, 0);
    /* Unknown surfaces (HF_SURFACE_COUNT and 4 past it) are bad enums. */
    hf_trace_options s;
    if (o)
        s = *o;
    else
        CHECK_OK(hf_trace_options_default(&s));
    for (s.surface = HF_SURFACE_COUNT; s.surface <= HF_SURFACE_COUNT + 4; s.surface += 4) {
        CHECK_BAD(hf_trace(f, method, map, len, &s, &rays[0], &h), HF_ERR_INVALID_ENUM, &h,
                  sizeof h);
        CHECK_BAD(hf_trace_batch(f, method, map, len, &s, rays, some, hits, some),
                  HF_ERR_INVALID_ENUM, hits, 512);
    }
    /* A NaN origin, direction or t_max: alone, and far into a batch of good rays. */
    hf_ray *bad = (hf_ray *)malloc(sizeof(hf_ray) * n);
    for (int k = 0; k < 3; k++) {
        memcpy(bad, rays, sizeof(hf_ray) * n);
        hf_ray *r = &bad[n - 1 - k];
        *(k == 0 ? &r->origin[1] : k == 1 ? &r->dir[2] : &r->t_max) = NAN;
        CHECK_BAD(hf_trace(f, method, map, len, o, r, &h), HF_ERR_INVALID_RAY, &h, sizeof h);
        CHECK_BAD(hf_trace_batch(f, method, map, len, o, bad, n, hits, n), HF_ERR_INVALID_RAY,
                  hits, 512);
    }
    free(bad);
}

/* ---- the bake functions (hf_bake*) ------------------------------------------------- */

/* Bytes of an element of `method`'s map: floats for the maximum mipmap and the cone
 * family, bytes for the safety-shape maps (and the methods without a map). */
static size_t elem_bytes(uint32_t method) {
    switch (method) {
    case HF_METHOD_MAXMIP:
    case HF_METHOD_CONE:
    case HF_METHOD_RELAXED:
    case HF_METHOD_QDM: return sizeof(float);
    default: return 1;
    }
}

/* The default bake options of `method`. */
/* 1 for the methods that read no map: exact, the searches, multires. */
static int without_map(uint32_t method) {
    return method <= HF_METHOD_LINEAR_SECANT || method == HF_METHOD_MULTIRES;
}

static hf_bake_options bake_defaults(uint32_t method) {
    hf_bake_options o;
    memset(&o, 0xAB, sizeof o);
    CHECK_OK(hf_bake_options_default(method, &o));
    return o;
}

/* A size query of the bakes: hf_map_len (elements) or hf_bake_scratch_len (floats). */
typedef hf_result (*size_query)(uint32_t, uint32_t, uint32_t, const hf_bake_options *, size_t *);

/* The answer of `query` for `method`, a `w` x `h` field and options `o` (NULL: the
 * defaults). */
static size_t ask(size_query query, uint32_t method, uint32_t w, uint32_t h,
                  const hf_bake_options *o) {
    size_t n = 0;
    CHECK_OK(query(method, w, h, o, &n));
    return n;
}

/* The width and height of `f`. */
static void field_size(const hf_field *f, uint32_t *w, uint32_t *h) {
    hf_field_info info;
    CHECK_OK(hf_field_get_info(f, &info));
    *w = info.width;
    *h = info.height;
}

/* `method`'s map of `f` baked with `o` (NULL: the defaults) into a new zeroed buffer of
 * `*len` elements and one spare, to free; NULL and 0 for a method without a map (its
 * bake of nothing is HF_OK). */
static void *bake_map(uint32_t method, const hf_field *f, const hf_bake_options *o, size_t *len) {
    uint32_t w, h;
    field_size(f, &w, &h);
    *len = ask(hf_map_len, method, w, h, o);
    void *map = *len ? calloc(*len + 1, elem_bytes(method)) : NULL;
    CHECK_OK(hf_bake(method, f, o, map, *len));
    return map;
}

/* The size queries of `method` with options `o` refuse bad sizes (`w` or `h` 1 or 0,
 * beyond HF_MAX_SIDE) and NULL outputs. */
static void check_size_queries(uint32_t method, uint32_t w, uint32_t h, const hf_bake_options *o) {
    const uint32_t sizes[3][2] = {{1, h}, {w, 0}, {HF_MAX_SIDE + 1u, h}};
    const size_query queries[2] = {hf_map_len, hf_bake_scratch_len};
    size_t junk = 77;
    uint32_t rows = 77;
    for (int k = 0; k < 3; k++) {
        for (int q = 0; q < 2; q++)
            CHECK_BAD(queries[q](method, sizes[k][0], sizes[k][1], o, &junk), HF_ERR_INVALID_SIZE,
                      &junk, sizeof junk);
        CHECK_BAD(hf_bake_row_count(method, sizes[k][0], sizes[k][1], o, &rows),
                  HF_ERR_INVALID_SIZE, &rows, sizeof rows);
    }
    for (int q = 0; q < 2; q++)
        CHECK_BAD(queries[q](method, w, h, o, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_bake_row_count(method, w, h, o, NULL), HF_ERR_NULL_POINTER, nothing, 0);
}

/* An option set to a bad value (`value`: a float for the tolerance and the view angle,
 * else a uint32_t) and
 * the code every bake function answers it with. */
typedef struct bad_option {
    size_t offset;
    double value;
    hf_result code;
} bad_option;

#define BAD_OPTION(field, value, code) {offsetof(hf_bake_options, field), (value), (code)}

/* Options every method's bake refuses, whichever fields it reads: the bake functions
 * check them all. */
static const bad_option bad_options[] = {
    BAD_OPTION(variant, 2, HF_ERR_INVALID_ENUM),
    BAD_OPTION(variant, 5, HF_ERR_INVALID_ENUM),
    BAD_OPTION(positive, 2, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(cap, 256, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(cap, 999, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(slope, 2, HF_ERR_INVALID_ENUM),
    BAD_OPTION(ray_classes, 16, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(tolerance, -1.0, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(tolerance, NAN, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(tolerance, INFINITY, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(exterior, 2, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(max_view_angle_deg, -1.0, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(max_view_angle_deg, 180.5, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(max_view_angle_deg, NAN, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(max_view_angle_deg, INFINITY, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(occluder_count, HF_MAX_OCCLUDERS + 1, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(occluder_count, 1, HF_ERR_NULL_POINTER), /* occluders NULL */
    BAD_OPTION(reserved[0], 1, HF_ERR_INVALID_ARGUMENT),
    BAD_OPTION(reserved[3], 1, HF_ERR_INVALID_ARGUMENT),
};

/* `o` with the bad option `b`. */
static hf_bake_options with_bad(const hf_bake_options *o, const bad_option *b) {
    hf_bake_options x = *o;
    if (b->offset == offsetof(hf_bake_options, tolerance)) {
        x.tolerance = (float)b->value;
    } else if (b->offset == offsetof(hf_bake_options, max_view_angle_deg)) {
        x.max_view_angle_deg = (float)b->value;
    } else {
        uint32_t v = (uint32_t)b->value;
        memcpy((char *)&x + b->offset, &v, sizeof v);
    }
    return x;
}

/* Each bake function refuses `method`'s options `o` made bad by `b` and writes nothing:
 * the size queries, the whole bake into `map` (`len` elements), the prepare of
 * `scratch` (`slen` floats, non-NULL) and a row bake. */
static void check_bad_option(uint32_t method, const hf_field *f, const hf_bake_options *o,
                             const bad_option *b, void *map, size_t len, float *scratch,
                             size_t slen) {
    hf_bake_options x = with_bad(o, b);
    uint32_t w, h, rows = 77;
    size_t junk = 77, bytes = len * elem_bytes(method);
    field_size(f, &w, &h);
    CHECK_BAD(hf_map_len(method, w, h, &x, &junk), b->code, &junk, sizeof junk);
    CHECK_BAD(hf_bake_scratch_len(method, w, h, &x, &junk), b->code, &junk, sizeof junk);
    CHECK_BAD(hf_bake_row_count(method, w, h, &x, &rows), b->code, &rows, sizeof rows);
    CHECK_BAD(hf_bake(method, f, &x, map, len), b->code, map, bytes);
    CHECK_BAD(hf_bake_prepare(method, f, &x, scratch, slen), b->code, scratch,
              (slen + 1) * sizeof(float));
    CHECK_BAD(hf_bake_rows(method, f, &x, scratch, slen, 0, 1, map, len), b->code, map, bytes);
}

/* The whole bake of `method`'s map of `f` with `o`, which is `want` (`len` elements):
 * on 1 and 2 threads a NULL field or map, a short or misaligned map are refused and
 * write nothing; on 0 (one per core) to 5 threads it bakes `want`. */
static void check_whole_bakes(uint32_t method, const hf_field *f, const hf_bake_options *o,
                              const void *want, size_t len) {
    size_t e = elem_bytes(method), bytes = len * e;
    unsigned char *map = (unsigned char *)malloc(bytes + e);
    hf_bake_options t = *o;
    for (t.threads = 0; t.threads <= 5; t.threads++) {
        memset(map, 0x5A, bytes + e);
        if (t.threads == 1 || t.threads == 2) {
            CHECK_BAD(hf_bake(method, NULL, &t, map, len), HF_ERR_NULL_POINTER, map, bytes);
            CHECK_BAD(hf_bake(method, f, &t, NULL, len), HF_ERR_NULL_POINTER, nothing, 0);
            CHECK_BAD(hf_bake(method, f, &t, map, len - 1), HF_ERR_BUFFER_TOO_SMALL, map, bytes);
            if (e > 1)
                CHECK_BAD(hf_bake(method, f, &t, map + 1, len), HF_ERR_MISALIGNED_POINTER, map,
                          bytes);
        }
        CHECK_OK(hf_bake(method, f, &t, map, len));
        CHECK(memcmp(map, want, bytes) == 0);
    }
    free(map);
}

/* The prepare and row bakes of `method`'s map of `f` with `o`, which is `want` (`len`
 * elements): a NULL field, scratch or map, short or misaligned buffers and bad row
 * ranges are refused and write nothing; three row ranges baked out of order, and an
 * empty one, give `want`. Only the maximum mipmap needs no scratch. */
static void check_row_bakes(uint32_t method, const hf_field *f, const hf_bake_options *o,
                            const void *want, size_t len) {
    uint32_t w, h, rows = 0;
    field_size(f, &w, &h);
    CHECK_OK(hf_bake_row_count(method, w, h, o, &rows));
    size_t slen = ask(hf_bake_scratch_len, method, w, h, o);
    size_t e = elem_bytes(method), bytes = len * e, sbytes = (slen + 1) * sizeof(float);
    CHECK(rows > 0 && (slen == 0) == (method == HF_METHOD_MAXMIP));
    float *scratch = (float *)calloc(slen + 1, sizeof(float));
    unsigned char *map = (unsigned char *)malloc(bytes + e);
    memset(map, 0xEE, bytes + e);
    float *odd_scratch = (float *)(void *)((char *)scratch + 1);
    CHECK_BAD(hf_bake_prepare(method, NULL, o, scratch, slen), HF_ERR_NULL_POINTER, scratch,
              sbytes);
    if (slen > 0) {
        CHECK_BAD(hf_bake_prepare(method, f, o, scratch, slen - 1), HF_ERR_BUFFER_TOO_SMALL,
                  scratch, sbytes);
        CHECK_BAD(hf_bake_prepare(method, f, o, NULL, slen), HF_ERR_NULL_POINTER, nothing, 0);
        CHECK_BAD(hf_bake_prepare(method, f, o, odd_scratch, slen), HF_ERR_MISALIGNED_POINTER,
                  scratch, sbytes);
    }
    CHECK_OK(hf_bake_prepare(method, f, o, scratch, slen));

    const uint32_t bad_rows[2][2] = {{rows, rows - 1}, {0, rows + 1}};
    for (int k = 0; k < 2; k++)
        CHECK_BAD(hf_bake_rows(method, f, o, scratch, slen, bad_rows[k][0], bad_rows[k][1], map,
                               len),
                  HF_ERR_INVALID_ARGUMENT, map, bytes);
    CHECK_BAD(hf_bake_rows(method, f, o, scratch, slen, 0, 1, map, len - 1),
              HF_ERR_BUFFER_TOO_SMALL, map, bytes);
    CHECK_BAD(hf_bake_rows(method, NULL, o, scratch, slen, 0, 1, map, len), HF_ERR_NULL_POINTER,
              map, bytes);
    CHECK_BAD(hf_bake_rows(method, f, o, scratch, slen, 0, 1, NULL, len), HF_ERR_NULL_POINTER,
              nothing, 0);
    if (e > 1)
        CHECK_BAD(hf_bake_rows(method, f, o, scratch, slen, 0, 1, map + 1, len),
                  HF_ERR_MISALIGNED_POINTER, map, bytes);
    if (slen > 0) {
        CHECK_BAD(hf_bake_rows(method, f, o, scratch, slen - 1, 0, 1, map, len),
                  HF_ERR_BUFFER_TOO_SMALL, map, bytes);
        CHECK_BAD(hf_bake_rows(method, f, o, NULL, slen, 0, 1, map, len), HF_ERR_NULL_POINTER,
                  map, bytes);
        CHECK_BAD(hf_bake_rows(method, f, o, odd_scratch, slen, 0, 1, map, len),
                  HF_ERR_MISALIGNED_POINTER, map, bytes);
    }

    /* Three ranges out of order, then an empty one, which bakes nothing (also for the
     * pyramid's one row). */
    const uint32_t cut[4] = {0, rows / 3, 2 * rows / 3, rows};
    const int order[4] = {2, 0, 1, -1}; /* -1: the empty range [cut[2], cut[2]) */
    for (int k = 0; k < 4; k++) {
        uint32_t r0 = cut[order[k] < 0 ? 2 : order[k]], r1 = order[k] < 0 ? r0 : cut[order[k] + 1];
        CHECK_OK(hf_bake_rows(method, f, o, scratch, slen, r0, r1, map, len));
    }
    CHECK(memcmp(map, want, bytes) == 0);
    free(map);
    free(scratch);
}

/* `method`'s map of `f` with options `o`, baked and checked through every bake function
 * (check_size_queries, check_bad_option with each of bad_options, check_whole_bakes,
 * check_row_bakes); returns it (`*len` elements) to free. */
static void *check_bakes(uint32_t method, const hf_field *f, const hf_bake_options *o,
                         size_t *len) {
    uint32_t w, h;
    field_size(f, &w, &h);
    check_size_queries(method, w, h, o);
    void *map = bake_map(method, f, o, len);
    size_t slen = ask(hf_bake_scratch_len, method, w, h, o);
    float *scratch = (float *)calloc(slen + 1, sizeof(float));
    void *out = calloc(*len + 1, elem_bytes(method));
    for (size_t k = 0; k < sizeof bad_options / sizeof bad_options[0]; k++)
        check_bad_option(method, f, o, &bad_options[k], out, *len, scratch, slen);
    check_whole_bakes(method, f, o, map, *len);
    check_row_bakes(method, f, o, map, *len);
    free(scratch);
    free(out);
    return map;
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

    /* NULL pointers, sizes, buffer lengths, non-finite values, a misaligned pointer. */
    const float hnan[4] = {0.0f, NAN, 1.0f, 2.0f};
    const float hinf[4] = {0.0f, 1.0f, -INFINITY, 2.0f};
    float storage[8] = {0};
    const float *misaligned = (const float *)(const void *)((const char *)storage + 1);
    const struct {
        const float *heights;
        size_t len;
        uint32_t width, height;
        size_t stride;
        hf_result code;
    } bad_f32[16] = {
        {NULL, 4, 2, 2, 2, HF_ERR_NULL_POINTER},
        {h4, 4, 0, 2, 2, HF_ERR_INVALID_SIZE},
        {h4, 4, 1, 2, 2, HF_ERR_INVALID_SIZE},
        {h4, 4, 2, 1, 2, HF_ERR_INVALID_SIZE},
        {h4, 4, 2, 0, 2, HF_ERR_INVALID_SIZE},
        {h4, 4, HF_MAX_SIDE + 1u, 2, HF_MAX_SIDE + 1u, HF_ERR_INVALID_SIZE},
        {h4, 4, 2, 0xFFFFFFFFu, 2, HF_ERR_INVALID_SIZE},
        {h4, 4, 2, 2, 1, HF_ERR_INVALID_SIZE},
        {h4, 4, 2, 3, SIZE_MAX / 2, HF_ERR_INVALID_SIZE},
        {h4, SIZE_MAX, 2, 2, 2, HF_ERR_INVALID_SIZE},
        {h4, 3, 2, 2, 2, HF_ERR_BUFFER_TOO_SMALL},
        {h4, 0, 2, 2, 2, HF_ERR_BUFFER_TOO_SMALL},
        {h4, 4, 2, 2, 3, HF_ERR_BUFFER_TOO_SMALL},
        {hnan, 4, 2, 2, 2, HF_ERR_NOT_FINITE},
        {hinf, 4, 2, 2, 2, HF_ERR_NOT_FINITE},
        {misaligned, 4, 2, 2, 2, HF_ERR_MISALIGNED_POINTER},
    };
    for (int k = 0; k < 16; k++)
        CHECK_BAD(hf_field_create_f32(bad_f32[k].heights, bad_f32[k].len, bad_f32[k].width,
                                      bad_f32[k].height, bad_f32[k].stride, &out),
                  bad_f32[k].code, &out, sizeof out);
    CHECK_BAD(hf_field_create_f32(h4, 4, 2, 2, 2, NULL), HF_ERR_NULL_POINTER, nothing, 0);

    const uint8_t s8[6] = {0, 255, 51, 0, 0, 0};
    const uint16_t s16[4] = {0, 65535, 13107, 0};
    const void *odd16 = (const char *)storage + 1;
    /* The 8-bit (`bits` 8) and 16-bit constructors' bad inputs. */
    const struct {
        int bits;
        const void *samples;
        size_t len;
        uint32_t width, height;
        size_t stride;
        float depth;
        hf_result code;
    } bad_int[10] = {
        {8, NULL, 6, 3, 2, 3, 10.0f, HF_ERR_NULL_POINTER},
        {8, s8, 6, 3, 2, 3, NAN, HF_ERR_NOT_FINITE},
        {8, s8, 6, 3, 2, 3, INFINITY, HF_ERR_NOT_FINITE},
        {8, s8, 5, 3, 2, 3, 10.0f, HF_ERR_BUFFER_TOO_SMALL},
        {8, s8, 6, 3, 2, 2, 10.0f, HF_ERR_INVALID_SIZE},
        {16, NULL, 4, 2, 2, 2, 10.0f, HF_ERR_NULL_POINTER},
        {16, s16, 4, 2, 2, 2, NAN, HF_ERR_NOT_FINITE},
        {16, s16, 3, 2, 2, 2, 10.0f, HF_ERR_BUFFER_TOO_SMALL},
        {16, s16, 4, 2, 1, 2, 10.0f, HF_ERR_INVALID_SIZE},
        {16, odd16, 4, 2, 2, 2, 10.0f, HF_ERR_MISALIGNED_POINTER},
    };
    for (int k = 0; k < 10; k++) {
        if (bad_int[k].bits == 8)
            CHECK_BAD(hf_field_create_u8((const uint8_t *)bad_int[k].samples, bad_int[k].len,
                                         bad_int[k].width, bad_int[k].height, bad_int[k].stride,
                                         bad_int[k].depth, &out),
                      bad_int[k].code, &out, sizeof out);
        else
            CHECK_BAD(hf_field_create_u16((const uint16_t *)bad_int[k].samples, bad_int[k].len,
                                          bad_int[k].width, bad_int[k].height, bad_int[k].stride,
                                          bad_int[k].depth, &out),
                      bad_int[k].code, &out, sizeof out);
    }
    CHECK_BAD(hf_field_create_u8(s8, 6, 3, 2, 3, 10.0f, NULL), HF_ERR_NULL_POINTER, nothing, 0);
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
    CHECK(ask(hf_map_len, HF_METHOD_MAXMIP, 2, 2, NULL) == P1);
    float pyr[P1];
    CHECK_OK(hf_bake(HF_METHOD_MAXMIP, f, NULL, pyr, P1));
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
    for (uint32_t s = HF_SURFACE_TRIANGLES; s < HF_SURFACE_COUNT; s++) {
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
    CHECK_OK(hf_bake(HF_METHOD_MAXMIP, f, NULL, pyr, P1));
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
    const uint32_t bad_surfaces[3] = {HF_SURFACE_COUNT, HF_SURFACE_COUNT + 1, 0xFFFFFFFFu};
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
    float *pyr = (float *)bake_map(HF_METHOD_MAXMIP, f, NULL, &plen);

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
    for (uint32_t s = HF_SURFACE_TRIANGLES; s < HF_SURFACE_COUNT; s++) {
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
    printf("methods: %d rays x %d surfaces, %d exact hits, maxmip identical, linear-binary "
           "within 1e-2 on %d\n",
           N, HF_SURFACE_COUNT, hits, lb_close);
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

/* hf_projective_trace_batch: with the identity matrix it traces as hf_trace_batch (the
 * normal renormalised in double), for the exact method and the maximum mipmap; through
 * a reverse-perspective frustum (projection centre under the field, as
 * core/tests/projective.rs) both methods agree, and every top hit's world point maps
 * onto the surface; a NULL, NaN or singular matrix and a bad ray are refused, nothing
 * written. */
static void test_projective(void) {
    enum { W = 41, H = 29, N = 1500 };
    float *heights = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) heights[k] = 8.0f * frand();
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    size_t plen = 0;
    float *pyr = (float *)bake_map(HF_METHOD_MAXMIP, f, NULL, &plen);
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        float dz = -0.2f - frand();
        float ox = -10.0f + (W + 20) * frand(), oy = -10.0f + (H + 20) * frand();
        rays[k] = ray(ox, oy, 12.0f + 20 * frand(), frand() - 0.5f, frand() - 0.5f, dz);
    }
    hf_hit *a = (hf_hit *)malloc(sizeof(hf_hit) * N), *b = (hf_hit *)malloc(sizeof(hf_hit) * N);
    const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const double fc = 3.0 * (W + H), cx = 0.5 * W, cy = 0.4 * H;
    const double persp[16] = {1, 0, cx / fc, 0, 0, 1, cy / fc, 0, 0, 0, 1, 0, 0, 0, 1 / fc, 1};
    const uint32_t methods[2] = {HF_METHOD_EXACT, HF_METHOD_MAXMIP};
    const void *maps[2] = {NULL, pyr};
    size_t lens[2] = {0, plen};
    int same = 1, hits = 0, on_surface = 0, agree = 1;
    for (int m = 0; m < 2; m++) {
        CHECK_OK(hf_trace_batch(f, methods[m], maps[m], lens[m], NULL, rays, N, a, N));
        CHECK_OK(hf_projective_trace_batch(f, identity, methods[m], maps[m], lens[m], NULL, rays,
                                           N, b, N));
        for (int k = 0; k < N; k++) {
            same &= a[k].hit == b[k].hit;
            if (!a[k].hit || !b[k].hit) continue;
            same &= a[k].t == b[k].t && a[k].flags == b[k].flags &&
                    memcmp(a[k].point, b[k].point, sizeof a[k].point) == 0 &&
                    memcmp(a[k].cell, b[k].cell, sizeof a[k].cell) == 0;
            for (int c = 0; c < 3; c++) same &= fabsf(a[k].normal[c] - b[k].normal[c]) < 1e-6f;
        }
    }
    CHECK(same);
    for (int m = 0; m < 2; m++) {
        CHECK_OK(hf_projective_trace_batch(f, persp, methods[m], maps[m], lens[m], NULL, rays, N,
                                           m ? b : a, N));
    }
    for (int k = 0; k < N; k++) {
        agree &= a[k].hit == b[k].hit && (!a[k].hit || fabsf(a[k].t - b[k].t) <= 1e-4f);
        if (!a[k].hit || (a[k].flags & (HF_FLAG_ORIGIN_INSIDE | HF_FLAG_SIDE))) continue;
        hits++;
        /* The world point's grid image, and the surface height there. */
        double p[4] = {a[k].point[0], a[k].point[1], a[k].point[2], 1.0}, g[4];
        for (int r = 0; r < 4; r++)
            g[r] = persp[4 * r] * p[0] + persp[4 * r + 1] * p[1] + persp[4 * r + 2] * p[2] +
                   persp[4 * r + 3] * p[3];
        hf_ray down = ray((float)(g[0] / g[3]), (float)(g[1] / g[3]), 100.0f, 0, 0, -1);
        hf_hit s;
        CHECK_OK(hf_trace(f, HF_METHOD_EXACT, NULL, 0, NULL, &down, &s));
        on_surface += s.hit && fabs(s.point[2] - g[2] / g[3]) <= 1e-3;
    }
    CHECK(agree && hits > N / 4 && on_surface == hits);
    printf("projective: identity as hf_trace_batch %s; perspective: %d hits, %d on the surface, "
           "exact and maxmip %s\n",
           same ? "yes" : "NO", hits, on_surface, agree ? "agree" : "DIFFER");
    /* Bad matrices and rays: refused, nothing written. */
    double nan_m[16], flat[16];
    memcpy(nan_m, persp, sizeof nan_m);
    nan_m[6] = NAN;
    memcpy(flat, persp, sizeof flat);
    for (int c = 0; c < 4; c++) flat[8 + c] = 0.0;
    memset(b, 0x5a, sizeof(hf_hit) * N);
    CHECK_BAD(hf_projective_trace_batch(f, NULL, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, b, N),
              HF_ERR_NULL_POINTER, b, sizeof(hf_hit) * 8);
    CHECK_BAD(hf_projective_trace_batch(f, nan_m, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, b, N),
              HF_ERR_INVALID_ARGUMENT, b, sizeof(hf_hit) * 8);
    CHECK_BAD(hf_projective_trace_batch(f, flat, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, b, N),
              HF_ERR_INVALID_ARGUMENT, b, sizeof(hf_hit) * 8);
    rays[N - 1].origin[1] = NAN;
    CHECK_BAD(hf_projective_trace_batch(f, persp, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, b, N),
              HF_ERR_INVALID_RAY, b, sizeof(hf_hit) * 8);
    CHECK_BAD(
        hf_projective_trace_batch(f, persp, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, b, N - 1),
        HF_ERR_BUFFER_TOO_SMALL, b, sizeof(hf_hit) * 8);
    free(rays);
    free(a);
    free(b);
    free(pyr);
    free(heights);
    hf_field_destroy(f);
}

/* ---- six-field impostors ----------------------------------------------------------- */

/* An axis-aligned box [lo, hi] as a mesh: each of its faces (in the impostor's face
 * order +x, -x, +y, -y, +z, -z) a 3 x 3 grid of vertices, 8 triangles. */
enum { BOX_VERTS = 54, BOX_TRIS = 48 };
static void box_mesh(const double lo[3], const double hi[3], float *pos, uint32_t *tri) {
    for (int k = 0; k < 6; k++) {
        int a = k / 2, u = (a + 1) % 3, v = (a + 2) % 3;
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 3; i++) {
                float *p = pos + 3 * (9 * k + 3 * j + i);
                p[a] = (float)(k % 2 == 0 ? hi[a] : lo[a]);
                p[u] = (float)(lo[u] + 0.5 * i * (hi[u] - lo[u]));
                p[v] = (float)(lo[v] + 0.5 * j * (hi[v] - lo[v]));
            }
        for (int j = 0; j < 2; j++)
            for (int i = 0; i < 2; i++) {
                uint32_t c = (uint32_t)(9 * k + 3 * j + i), *t = tri + 3 * (8 * k + 4 * j + 2 * i);
                t[0] = c, t[1] = c + 1, t[2] = c + 4;
                t[3] = c, t[4] = c + 4, t[5] = c + 3;
            }
    }
}

/* The ray o + t d (t >= 0) against the box [lo, hi] by slabs, in double: 1 and the
 * entry t and axis when it meets the box, else 0. */
static int box_hit(const double lo[3], const double hi[3], const hf_ray *r, double *t_in,
                   int *axis) {
    double t0 = 0.0, t1 = INFINITY;
    *axis = -1;
    for (int a = 0; a < 3; a++) {
        double o = r->origin[a], d = r->dir[a];
        if (d == 0.0) {
            if (o < lo[a] || o > hi[a]) return 0;
            continue;
        }
        double ta = (lo[a] - o) / d, tb = (hi[a] - o) / d;
        if (ta > tb) {
            double s = ta;
            ta = tb;
            tb = s;
        }
        if (ta > t0) t0 = ta, *axis = a;
        if (tb < t1) t1 = tb;
    }
    *t_in = t0;
    return t0 <= t1;
}

/* The face hf_impostor_trace_batch's facing field traces for `d`: the first axis of
 * largest |d|, 2 * axis + (d positive). */
static uint32_t facing_face(const float d[3]) {
    int a = 0;
    for (int k = 1; k < 3; k++)
        if (fabsf(d[k]) > fabsf(d[a])) a = k;
    return (uint32_t)(2 * a + (d[a] > 0.0f));
}

/* The six fields of the box mesh on `l` at `side`, padded, face after face. */
static int capture_box(const float *pos, const uint32_t *tri, const hf_impostor_layout *l,
                       uint32_t side, float *heights, uint32_t *ids) {
    size_t n = (size_t)side * side;
    int ok = 1;
    for (uint32_t k = 0; k < 6; k++)
        ok &= hf_impostor_capture(pos, BOX_VERTS, tri, BOX_TRIS, l, k, side, 1, heights + k * n,
                                  n, ids ? ids + k * n : NULL, n) == HF_OK;
    return ok;
}

/* Six-field impostors of an axis-aligned box (48 triangles) at side 64, against the
 * analytic ray-box intersection in double: with orthographic faces the box's fields are
 * flat at the top (every sample 63, its triangle on that face), and every ray whose
 * entry point is not within two texels of an edge (nor passes within two texels of the
 * box) hits where the box does (within 1e-4), for the intersection and, on the rays
 * that meet the box, the facing field (which traces one face per ray, the one the ray
 * faces); with reverse perspective, whose fields cut the box's edges, within a quarter
 * texel away from them. Bad meshes, layouts, faces, sides, buffers and rays are
 * refused, nothing written. */
static void test_impostor(void) {
    enum { SIDE = 64, N = 400 };
    const size_t n = (size_t)SIDE * SIDE;
    const double lo[3] = {-1.0, -0.5, 0.2}, hi[3] = {1.5, 0.8, 1.4};
    float pos[3 * BOX_VERTS];
    uint32_t tri[3 * BOX_TRIS];
    box_mesh(lo, hi, pos, tri);
    size_t len = 0;
    CHECK_OK(hf_impostor_field_len(SIDE, &len));
    CHECK(len == n);
    hf_impostor_layout ortho, rev;
    CHECK_OK(hf_impostor_layout_around(pos, BOX_VERTS, tri, BOX_TRIS, HF_IMPOSTOR_ORTHOGRAPHIC,
                                       NAN, &ortho));
    CHECK_OK(hf_impostor_layout_around(pos, BOX_VERTS, tri, BOX_TRIS,
                                       HF_IMPOSTOR_REVERSE_PERSPECTIVE, 0.0, &rev));
    CHECK(ortho.frustum == HF_IMPOSTOR_ORTHOGRAPHIC &&
          rev.frustum == HF_IMPOSTOR_REVERSE_PERSPECTIVE && rev.apex == 2.0);
    CHECK(fabs(ortho.half - 0.505 * 2.5) < 1e-6 && fabs(ortho.center[2] - 0.8) < 1e-6);
    /* The +z face's grid map: the top's centre at the grid's centre, height 63. */
    double m[16], top[4] = {0.25, 0.15, 1.4, 1.0}, g[4];
    CHECK_OK(hf_impostor_face_map(&ortho, 4, SIDE, m));
    for (int r = 0; r < 4; r++)
        g[r] = m[4 * r] * top[0] + m[4 * r + 1] * top[1] + m[4 * r + 2] * top[2] + m[4 * r + 3];
    CHECK(fabs(g[0] / g[3] - 31.5) < 1e-4 && fabs(g[1] / g[3] - 31.5) < 1e-4 &&
          fabs(g[2] / g[3] - 63.0) < 1e-4);

    float *heights = (float *)malloc(sizeof(float) * 6 * n);
    uint32_t *ids = (uint32_t *)malloc(sizeof(uint32_t) * 6 * n);
    CHECK(capture_box(pos, tri, &ortho, SIDE, heights, ids));
    /* Samples on the footprint's rim may round outside the face (then padded, with no
     * triangle). */
    int flat = 1;
    for (size_t s = 0; s < 6 * n; s++) {
        size_t i = s % SIDE, j = s / SIDE % SIDE;
        int on_rim = i == 0 || j == 0 || i == SIDE - 1 || j == SIDE - 1;
        flat &= fabsf(heights[s] - 63.0f) < 1e-3f &&
                (ids[s] == HF_IMPOSTOR_NONE ? on_rim : ids[s] / 8 == s / n);
    }
    CHECK(flat);

    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        double u[3], l2 = 0.0;
        do {
            l2 = 0.0;
            for (int a = 0; a < 3; a++) u[a] = 2.0 * frand() - 1.0, l2 += u[a] * u[a];
        } while (l2 < 0.01 || l2 > 1.0);
        float o[3], d[3];
        for (int a = 0; a < 3; a++) {
            double c = 0.5 * (lo[a] + hi[a]), h = 0.5 * (hi[a] - lo[a]);
            o[a] = (float)(c + 4.0 * u[a] / sqrt(l2));
            d[a] = (float)(c + 1.3 * h * (2.0 * frand() - 1.0)) - o[a];
        }
        rays[k] = ray(o[0], o[1], o[2], d[0], d[1], d[2]);
    }
    hf_hit *hits = (hf_hit *)malloc(sizeof(hf_hit) * N);
    uint32_t faces[N];
    const char *names[3] = {"orthographic intersection", "orthographic facing-field",
                            "reverse-perspective intersection"};
    for (int run = 0; run < 3; run++) {
        const hf_impostor_layout *l = run < 2 ? &ortho : &rev;
        uint32_t combine = run == 1 ? HF_IMPOSTOR_FACING_FIELD : HF_IMPOSTOR_INTERSECTION;
        if (run == 2) CHECK(capture_box(pos, tri, &rev, SIDE, heights, NULL));
        CHECK_OK(hf_impostor_trace_batch(l, heights, 6 * n, SIDE, HF_SURFACE_TRIANGLES, combine,
                                         rays, N, hits, N, faces, N));
        /* Rays compared, skipped, as the box, hitting it; every hit on one face (the facing
         * one for the facing field). */
        int compared = 0, skipped = 0, agree = 0, n_hits = 0, one_face = 1;
        /* Within two texels, in the orthographic fields' texels; a reverse perspective with apex 2
         * draws each face on a third of its field's side (its texels three times as wide),
         * and its fields cut the corners of the box's edges (the cells across the crease
         * where a face meets a side), so its points are held to a quarter texel and its
         * normals to 0.99. */
        const double margin = run == 2 ? 6.0 : 2.0, tol = run == 2 ? 1e-2 : 1e-4;
        const float cosine = run == 2 ? 0.99f : 0.999f;
        double worst = 0.0;
        for (int k = 0; k < N; k++) {
            const hf_ray *r = &rays[k];
            one_face &= hits[k].hit ? faces[k] < 6 : faces[k] == HF_IMPOSTOR_NONE;
            if (combine == HF_IMPOSTOR_FACING_FIELD && hits[k].hit)
                one_face &= faces[k] == facing_face(r->dir);
            double t = 0.0, band[3], wlo[3], whi[3];
            int axis = -1, near_edge = 0;
            for (int a = 0; a < 3; a++) {
                band[a] = margin * (hi[a] - lo[a]) / (SIDE - 1);
                wlo[a] = lo[a] - band[a], whi[a] = hi[a] + band[a];
            }
            int want = box_hit(lo, hi, r, &t, &axis);
            if (want) {
                for (int a = 0; a < 3; a++) {
                    double p = r->origin[a] + t * r->dir[a];
                    near_edge |= a != axis && (p - lo[a] < band[a] || hi[a] - p < band[a]);
                }
            } else {
                double tw;
                int aw;
                near_edge = box_hit(wlo, whi, r, &tw, &aw);
            }
            /* The facing field's solid runs on under the box (a field's solid is all
             * under its surface): a ray that misses the box may meet it there. */
            if (near_edge || (combine == HF_IMPOSTOR_FACING_FIELD && !want)) {
                skipped++;
                continue;
            }
            compared++;
            n_hits += want;
            if ((uint32_t)want != hits[k].hit) continue;
            /* The point's error, and the point at the hit's t (world units). */
            double err = 0.0, err_t = 0.0;
            for (int a = 0; want && a < 3; a++) {
                double p = r->origin[a] + t * r->dir[a];
                double e = fabs(hits[k].point[a] - p), et = fabs((hits[k].t - t) * r->dir[a]);
                err = e > err ? e : err;
                err_t = et > err_t ? et : err_t;
            }
            /* The normal of the face entered: against the ray along its axis. */
            int normal_ok = !want || hits[k].normal[axis] * (r->dir[axis] < 0 ? 1 : -1) > cosine;
            worst = err > worst ? err : worst;
            agree += err < tol && err_t < tol && normal_ok;
        }
        printf("impostor: box of %d triangles, six %dx%d fields, %s: %d of %d rays as the "
               "analytic box (%d hits; %d near an edge or, facing field, under the box "
               "skipped), max point error %.2e\n",
               BOX_TRIS, SIDE, SIDE, names[run], agree, compared, n_hits, skipped, worst);
        CHECK(one_face && n_hits > compared / 4 && compared > N / 2);
        CHECK(agree == compared);
    }

    /* Bad meshes and layouts: refused, nothing written. */
    hf_impostor_layout out;
    memset(&out, 0x5a, sizeof out);
    float bad_pos[3 * BOX_VERTS];
    uint32_t bad_tri[3 * BOX_TRIS];
    memcpy(bad_pos, pos, sizeof pos);
    memcpy(bad_tri, tri, sizeof tri);
    bad_pos[40] = NAN;
    CHECK_BAD(hf_impostor_layout_around(bad_pos, BOX_VERTS, tri, BOX_TRIS, 0, 0.0, &out),
              HF_ERR_NOT_FINITE, &out, sizeof out);
    CHECK_BAD(hf_impostor_layout_around(pos, BOX_VERTS, tri, 0, 0, 0.0, &out),
              HF_ERR_INVALID_SIZE, &out, sizeof out);
    bad_tri[100] = BOX_VERTS;
    CHECK_BAD(hf_impostor_layout_around(pos, BOX_VERTS, bad_tri, BOX_TRIS, 0, 0.0, &out),
              HF_ERR_INVALID_ARGUMENT, &out, sizeof out);
    const double apexes[4] = {0.5, 1.0, NAN, -INFINITY};
    for (int k = 0; k < 4; k++)
        CHECK_BAD(hf_impostor_layout_around(pos, BOX_VERTS, tri, BOX_TRIS, 1, apexes[k], &out),
                  HF_ERR_INVALID_ARGUMENT, &out, sizeof out);
    const float point[9] = {1, 2, 3, 1, 2, 3, 1, 2, 3};
    const uint32_t one[3] = {0, 1, 2};
    CHECK_BAD(hf_impostor_layout_around(point, 3, one, 1, 0, 0.0, &out),
              HF_ERR_INVALID_ARGUMENT, &out, sizeof out);
    CHECK_BAD(hf_impostor_layout_around(pos, BOX_VERTS, tri, BOX_TRIS, 2, 0.0, &out),
              HF_ERR_INVALID_ENUM, &out, sizeof out);
    CHECK_BAD(hf_impostor_layout_around(NULL, BOX_VERTS, tri, BOX_TRIS, 0, 0.0, &out),
              HF_ERR_NULL_POINTER, &out, sizeof out);
    CHECK_BAD(hf_impostor_layout_around(pos, BOX_VERTS, NULL, BOX_TRIS, 0, 0.0, &out),
              HF_ERR_NULL_POINTER, &out, sizeof out);
    CHECK_BAD(hf_impostor_layout_around(pos, BOX_VERTS, tri, BOX_TRIS, 0, 0.0, NULL),
              HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_impostor_layout_around(pos, SIZE_MAX, tri, BOX_TRIS, 0, 0.0, &out),
              HF_ERR_INVALID_SIZE, &out, sizeof out);
    hf_impostor_layout nan_l = ortho, singular = ortho, enum_l = ortho;
    nan_l.center[1] = NAN;
    for (int c = 0; c < 4; c++) singular.units[3][8 + c] = 0.0;
    enum_l.frustum = 7;
    CHECK_BAD(hf_impostor_face_map(&nan_l, 0, SIDE, m), HF_ERR_NOT_FINITE, m, sizeof m);
    CHECK_BAD(hf_impostor_face_map(&singular, 0, SIDE, m), HF_ERR_INVALID_ARGUMENT, m, sizeof m);
    CHECK_BAD(hf_impostor_face_map(&enum_l, 0, SIDE, m), HF_ERR_INVALID_ENUM, m, sizeof m);
    CHECK_BAD(hf_impostor_face_map(&ortho, 6, SIDE, m), HF_ERR_INVALID_ARGUMENT, m, sizeof m);
    CHECK_BAD(hf_impostor_face_map(&ortho, 0, 1, m), HF_ERR_INVALID_SIZE, m, sizeof m);
    CHECK_BAD(hf_impostor_face_map(NULL, 0, SIDE, m), HF_ERR_NULL_POINTER, m, sizeof m);
    CHECK_BAD(hf_impostor_face_map(&ortho, 0, SIDE, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_impostor_field_len(1, &len), HF_ERR_INVALID_SIZE, &len, sizeof len);
    CHECK_BAD(hf_impostor_field_len(HF_MAX_SIDE + 1, &len), HF_ERR_INVALID_SIZE, &len, sizeof len);
    CHECK_BAD(hf_impostor_field_len(SIDE, NULL), HF_ERR_NULL_POINTER, nothing, 0);

    /* Bad captures: faces, sides, buffers, flags; nothing written. */
#define CAPTURE(l, face, side, pad, h, hl, t, tl) \
    hf_impostor_capture(pos, BOX_VERTS, tri, BOX_TRIS, l, face, side, pad, h, hl, t, tl)
    CHECK_BAD(CAPTURE(&ortho, 6, SIDE, 1, heights, n, ids, n), HF_ERR_INVALID_ARGUMENT, heights,
              256);
    CHECK_BAD(CAPTURE(&ortho, 0, 1, 1, heights, n, ids, n), HF_ERR_INVALID_SIZE, heights, 256);
    CHECK_BAD(CAPTURE(&ortho, 0, 0, 1, heights, n, ids, n), HF_ERR_INVALID_SIZE, heights, 256);
    CHECK_BAD(CAPTURE(&ortho, 0, HF_MAX_SIDE + 1, 1, heights, n, ids, n), HF_ERR_INVALID_SIZE,
              heights, 256);
    CHECK_BAD(CAPTURE(&ortho, 0, HF_MAX_SIDE, 1, heights, n, ids, n), HF_ERR_BUFFER_TOO_SMALL,
              heights, 256);
    CHECK_BAD(CAPTURE(&ortho, 0, SIDE, 1, heights, n - 1, ids, n), HF_ERR_BUFFER_TOO_SMALL,
              heights, 256);
    CHECK_BAD(CAPTURE(&ortho, 0, SIDE, 1, heights, n, ids, n - 1), HF_ERR_BUFFER_TOO_SMALL,
              heights, 256);
    CHECK_BAD(CAPTURE(&ortho, 0, SIDE, 2, heights, n, ids, n), HF_ERR_INVALID_ARGUMENT, heights,
              256);
    CHECK_BAD(CAPTURE(&ortho, 0, SIDE, 1, NULL, n, ids, n), HF_ERR_NULL_POINTER, ids, 256);
    CHECK_BAD(CAPTURE(NULL, 0, SIDE, 1, heights, n, ids, n), HF_ERR_NULL_POINTER, heights, 256);
    CHECK_BAD(CAPTURE(&nan_l, 0, SIDE, 1, heights, n, ids, n), HF_ERR_NOT_FINITE, heights, 256);
    CHECK_BAD(CAPTURE(&ortho, 0, SIDE, 1, heights, n, (uint32_t *)(void *)(heights + 8), n),
              HF_ERR_INVALID_ARGUMENT, heights, 256);
    CHECK_BAD(hf_impostor_capture(pos, BOX_VERTS, tri, BOX_TRIS, &ortho, 0, 4, 1, (float *)pos, 16,
                                  NULL, 0),
              HF_ERR_INVALID_ARGUMENT, pos, sizeof pos);
#undef CAPTURE

    /* Bad traces: nothing written. */
    CHECK(capture_box(pos, tri, &ortho, SIDE, heights, NULL));
    memset(hits, 0x5a, sizeof(hf_hit) * N);
#define TRACE(l, h, hl, side, surface, combine, r, rl, out, ol, f, fl) \
    hf_impostor_trace_batch(l, h, hl, side, surface, combine, r, rl, out, ol, f, fl)
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, SIDE, 0, 2, rays, N, hits, N, faces, N),
              HF_ERR_INVALID_ENUM, hits, 256);
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, SIDE, 99, 0, rays, N, hits, N, faces, N),
              HF_ERR_INVALID_ENUM, hits, 256);
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, 1, 0, 0, rays, N, hits, N, faces, N),
              HF_ERR_INVALID_SIZE, hits, 256);
    CHECK_BAD(TRACE(&ortho, heights, 6 * n - 1, SIDE, 0, 0, rays, N, hits, N, faces, N),
              HF_ERR_BUFFER_TOO_SMALL, hits, 256);
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, SIDE, 0, 0, rays, N, hits, N - 1, faces, N),
              HF_ERR_BUFFER_TOO_SMALL, hits, 256);
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, SIDE, 0, 0, rays, N, hits, N, faces, N - 1),
              HF_ERR_BUFFER_TOO_SMALL, hits, 256);
    CHECK_BAD(TRACE(&singular, heights, 6 * n, SIDE, 0, 0, rays, N, hits, N, faces, N),
              HF_ERR_INVALID_ARGUMENT, hits, 256);
    CHECK_BAD(TRACE(NULL, heights, 6 * n, SIDE, 0, 0, rays, N, hits, N, faces, N),
              HF_ERR_NULL_POINTER, hits, 256);
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, SIDE, 0, 0, rays, N, (hf_hit *)(void *)rays, N,
                    faces, N),
              HF_ERR_INVALID_ARGUMENT, rays, 256);
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, SIDE, 0, 0, rays, N, hits, N,
                    (uint32_t *)(void *)(hits + 3), N),
              HF_ERR_INVALID_ARGUMENT, hits, 256);
    heights[3 * n + 17] = NAN;
    size_t at = 0;
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, SIDE, 0, 0, rays, N, hits, N, faces, N),
              HF_ERR_NOT_FINITE, hits, 256);
    CHECK(hf_last_error_index(&at) == HF_OK && at == 3 * n + 17);
    heights[3 * n + 17] = 63.0f;
    rays[N - 1].dir[0] = NAN;
    CHECK_BAD(TRACE(&ortho, heights, 6 * n, SIDE, 0, 0, rays, N, hits, N, faces, N),
              HF_ERR_INVALID_RAY, hits, 256);
    CHECK(hf_last_error_index(&at) == HF_OK && at == N - 1);
    /* An empty batch and a batch without faces. */
    CHECK_OK(TRACE(&ortho, heights, 6 * n, SIDE, 0, 0, rays, 0, hits, 0, NULL, 0));
    CHECK_OK(TRACE(&ortho, heights, 6 * n, SIDE, 0, 0, rays, N - 1, hits, N, NULL, 0));
#undef TRACE
    free(rays);
    free(hits);
    free(ids);
    free(heights);
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
    float *pyr = (float *)bake_map(HF_METHOD_MAXMIP, world, NULL, &plen);
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
     * hf_shadow_ray none does, with and without a transform. hf_shadow_ray_from_light
     * walks the same points from the light's side: direction -light, t in [t_min, 0]
     * with its start outside the box, in shadow iff hf_shadow_ray's ray is (but for a
     * few touching rays, which f32 may settle either way). */
    const float light[3] = {0.3f, -0.4f, 0.6f};
    hf_field *fields[2] = {grid, world};
    hf_hit *answers[2] = {gh, wh};
    hf_ray *primaries[2] = {g, w};
    for (int f = 0; f < 2; f++) {
        int lit = 0, naive_inside = 0, lifted_inside = 0, shadowed = 0, disagree = 0;
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
            hf_ray lr;
            hf_hit ls;
            CHECK_OK(hf_shadow_ray_from_light(fields[f], HF_SURFACE_TRIANGLES, &primaries[f][k],
                                              h, &light, &lr));
            /* A ray that never meets the box (lifted over it, rising) comes back as
             * it is: it starts outside already. */
            int same = memcmp(&lr, &sr, sizeof lr) == 0;
            CHECK(memcmp(lr.origin, sr.origin, sizeof lr.origin) == 0 &&
                  (same || (lr.t_max == 0.0f && lr.t_min < 0.0f)));
            for (int c = 0; c < 3; c++) CHECK(lr.dir[c] == (same ? light[c] : -light[c]));
            if (f == 0) {
                float o[3];
                for (int c = 0; c < 3; c++) o[c] = lr.origin[c] + lr.t_min * lr.dir[c];
                CHECK(o[0] < 0 || o[0] > W - 1 || o[1] < 0 || o[1] > H - 1 || o[2] > 8.0f);
            }
            CHECK_OK(hf_trace(fields[f], HF_METHOD_EXACT, NULL, 0, NULL, &lr, &ls));
            CHECK(!(ls.flags & HF_FLAG_ORIGIN_INSIDE));
            shadowed += s.hit != 0;
            disagree += (s.hit != 0) != (ls.hit != 0);
        }
        CHECK(lit > N / 2 && naive_inside > lit / 20);
        CHECK(lifted_inside == 0);
        CHECK(shadowed > lit / 50 && disagree * 200 <= lit);
        printf("shadow rays (%s): %d hits, %d start inside from the hit point, %d from "
               "hf_shadow_ray; %d in shadow, %d differ from the light's side\n",
               f ? "world" : "grid", lit, naive_inside, lifted_inside, shadowed, disagree);
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
    CHECK_BAD(hf_shadow_ray_from_light(grid, HF_SURFACE_TRIANGLES, &g[0], &miss, &light, &sr),
              HF_ERR_INVALID_ARGUMENT, &sr, sizeof sr);
    CHECK_BAD(hf_shadow_ray_from_light(grid, 99, &g[0], &gh[0], &light, &sr),
              HF_ERR_INVALID_ENUM, &sr, sizeof sr);
    CHECK_BAD(hf_shadow_ray_from_light(grid, HF_SURFACE_TRIANGLES, &g[0], &gh[0], NULL, &sr),
              HF_ERR_NULL_POINTER, &sr, sizeof sr);
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
    /* Every bake function and its faults (check_bakes: sizes, options, NULL pointers,
     * short buffers, threads, row ranges). */
    const hf_bake_options mo = bake_defaults(HF_METHOD_MAXMIP);
    size_t len = 0;
    float *whole = (float *)check_bakes(HF_METHOD_MAXMIP, f, &mo, &len);
    CHECK(len == PL); /* 5 texels, then the descriptor */
    float p[PL];
    for (size_t k = 0; k < PL; k++) p[k] = -1.0f;
    CHECK_OK(hf_bake(HF_METHOD_MAXMIP, f, NULL, p, PL));
    CHECK(p[0] == 4 && p[1] == 5 && p[2] == 7 && p[3] == 8 && p[4] == 8);
    CHECK(memcmp(p, whole, sizeof p) == 0);
    free(whole);
    hf_level levels[HF_MAX_LEVELS];
    uint32_t count = 0;
    CHECK_OK(hf_maxmip_levels(3, 3, levels, HF_MAX_LEVELS, &count));
    CHECK(count == 2 && levels[0].width == 2 && levels[0].height == 2 && levels[0].offset == 0);
    CHECK(levels[1].width == 1 && levels[1].height == 1 && levels[1].offset == 4);

    size_t big = ask(hf_map_len, HF_METHOD_MAXMIP, 4096, 2048, NULL);
    CHECK(big > 4095u * 2047u && big < 4095u * 2047u / 2u * 3u);
    CHECK_OK(hf_maxmip_levels(HF_MAX_SIDE, 2, levels, HF_MAX_LEVELS, &count));
    CHECK(count == 25);

    /* Bad inputs of the pyramid's own functions (levels, rows of a level, updates). */
    float q[PL];
    for (size_t k = 0; k < PL; k++) q[k] = -1.0f;
    CHECK_BAD(hf_maxmip_levels(3, 3, levels, 1, &count), HF_ERR_BUFFER_TOO_SMALL, levels,
              sizeof levels);
    CHECK_BAD(hf_maxmip_levels(3, 3, NULL, 2, &count), HF_ERR_NULL_POINTER, &count,
              sizeof count);
    CHECK_BAD(hf_maxmip_levels(3, 3, levels, 2, NULL), HF_ERR_NULL_POINTER, levels,
              sizeof levels);
    CHECK_BAD(hf_maxmip_levels(0, 3, levels, 2, &count), HF_ERR_INVALID_SIZE, levels,
              sizeof levels);
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
    CHECK_OK(hf_bake(HF_METHOD_MAXMIP, g, NULL, q, PL));
    CHECK(memcmp(p, q, sizeof p) == 0 && p[4] == 23.0f);
    hf_ray r = ray(1.5f, 1.5f, 50.0f, 0.0f, 0.0f, -1.0f);
    hf_hit a, b;
    hf_trace_options bilinear = on(HF_SURFACE_BILINEAR);
    CHECK_OK(hf_trace(f, HF_METHOD_MAXMIP, p, PL, &bilinear, &r, &a));
    CHECK_OK(hf_trace(g, HF_METHOD_EXACT, NULL, 0, &bilinear, &r, &b));
    CHECK(a.hit && b.hit && a.t == b.t && near(a.point[2], 21.5f, 1e-5f));
    hf_field_destroy(g);
    hf_field_destroy(f);

    /* A larger odd-sized field: threaded and single-threaded bakes agree (check_bakes:
     * 0 to 5 threads). */
    enum { W = 301, H = 157 };
    float *hs = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) hs[k] = 100.0f * frand();
    CHECK_OK(hf_field_create_f32(hs, W * H, W, H, W, &f));
    float *p1 = (float *)check_bakes(HF_METHOD_MAXMIP, f, &mo, &len);
    CHECK(len == ask(hf_map_len, HF_METHOD_MAXMIP, W, H, NULL));
    free(p1);
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

/* A `w` x `h` field of heights `scale` * frand() * frand() with a needle of height
 * `needle` at sample `at`; its heights (to free) in `*heights`. */
static hf_field *needle_field(int w, int h, float scale, int at, float needle, float **heights) {
    float *hs = (float *)malloc(sizeof(float) * w * h);
    for (int k = 0; k < w * h; k++) hs[k] = scale * frand() * frand();
    hs[at] = needle;
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(hs, (size_t)w * h, w, h, w, &f));
    *heights = hs;
    return f;
}

/* `n` random rays (to free) over a `w` x `h` field, from up to 5 beyond its sides and
 * below `top`, going down (dz in (-0.55, -0.05]): every `flat`-th with dir[`axis`] 0,
 * every `vertical`-th vertical. */
static hf_ray *down_rays(int n, int w, int h, float top, int flat, int axis, int vertical) {
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * n);
    for (int k = 0; k < n; k++) {
        rays[k] = ray(-5.0f + (w + 10) * frand(), -5.0f + (h + 10) * frand(), top * frand(),
                      frand() - 0.5f, frand() - 0.5f, -0.05f - 0.5f * frand());
        if (k % flat == 0) rays[k].dir[axis] = 0.0f;
        if (k % vertical == 0) rays[k].dir[0] = rays[k].dir[1] = 0.0f;
    }
    return rays;
}

/* The exact method's hits (to free) of `rays[0..n)` over `f`. */
static hf_hit *exact_hits(const hf_field *f, const hf_ray *rays, int n) {
    hf_hit *exact = (hf_hit *)malloc(sizeof(hf_hit) * n);
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, n, exact, n));
    return exact;
}

/* `method`'s options `o` with ray_classes 0 (all four) bake `want` (`len` bytes), the
 * map of all four classes: its size and bytes. */
static void check_all_classes(uint32_t method, const hf_field *f, hf_bake_options o,
                              const void *want, size_t len) {
    size_t n = 0;
    o.ray_classes = 0;
    void *all = bake_map(method, f, &o, &n);
    CHECK(n == len && memcmp(all, want, len) == 0);
    free(all);
}

/* A safety-shape method's maps over `rays[0..n)` (`exact`: the exact method's hits):
 * `part`, of fewer ray classes, against the whole map `whole` (check_class_map,
 * check_class_options), then `whole` on the view-linear surface; returns
 * view_linear_agrees's count, its hits left in `hits`. */
static int check_class_maps(const char *what, const hf_ray *rays, int n, const hf_hit *exact,
                            hf_hit *hits, const struct safety_ctx *whole,
                            const struct safety_ctx *part) {
    CHECK_OK(hf_trace_batch(whole->f, whole->method, whole->map, whole->len, NULL, rays,
                            (size_t)n, hits, (size_t)n));
    check_class_map(what, rays, n, exact, hits, part);
    check_class_options(part->f, part->method, part->map, part->len, part->classes, &rays[0]);
    return view_linear_agrees(whole->f, rays, n, hits, whole);
}

static void test_safety(void) {
    enum { W = 41, H = 29, N = 3000 };
    float *heights = NULL;
    hf_field *f = needle_field(W, H, 10.0f, 15 * W + 20, 40.0f, &heights);

    /* Every bake function and its faults (check_bakes), directional and isotropic. */
    const uint32_t sm = HF_METHOD_SAFETY;
    hf_bake_options good = bake_defaults(sm), iso;
    CHECK(good.cap == 255 && good.variant == HF_SAFETY_DIRECTIONAL && good.positive == 0);
    good.ray_classes = HF_RAYS_ALL;
    iso = good;
    iso.variant = HF_SAFETY_ISOTROPIC;
    size_t dlen = 0, ilen = 0;
    unsigned char *dmap = (unsigned char *)check_bakes(sm, f, &good, &dlen);
    unsigned char *imap = (unsigned char *)check_bakes(sm, f, &iso, &ilen);
    CHECK(dlen == (size_t)W * H * 4 + HF_MAP_DESC_BYTES && ilen == (size_t)W * H + HF_MAP_DESC_BYTES);
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
     * the row bakes with the same classes agree (check_bakes). */
    uint32_t two = HF_RAYS_X_POS | HF_RAYS_Y_NEG;
    hf_bake_options so = good;
    so.ray_classes = two;
    size_t tlen = 0;
    unsigned char *rows = (unsigned char *)check_bakes(sm, f, &so, &tlen);
    iso.ray_classes = two;
    CHECK(tlen == (size_t)W * H * 2 + HF_MAP_DESC_BYTES &&
          ask(hf_map_len, sm, W, H, &iso) == (size_t)W * H + HF_MAP_DESC_BYTES);
    static const size_t two_classes[2] = {0, 3};
    int mask_ok = 1;
    for (size_t k = 0; k < tlen - HF_MAP_DESC_BYTES; k++)
        mask_ok &= rows[k] == dmap[(k / (2 * W) * 4 + two_classes[k / W % 2]) * W + k % W];
    CHECK(mask_ok);
    /* ray_classes 0 means all four (the full map's size and bytes); above 15 is an error
     * (bad_options). */
    check_all_classes(sm, f, so, dmap, dlen);

    /* Exact: the safety march finds the exact method's hits on the triangle surface. */
    hf_ray *rays = down_rays(N, W, H, 30.0f, 13, 1, 31);
    hf_hit *exact = exact_hits(f, rays, N);
    hf_hit *sd = (hf_hit *)malloc(sizeof(hf_hit) * N);
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
    /* The two-class map (in `rows`); the whole map on the view-linear surface. */
    struct safety_ctx two_ctx = {f, sm, rows, tlen, two}, sctx = {f, sm, dmap, dlen, HF_RAYS_ALL};
    int vl = check_class_maps("safety, two classes", rays, N, exact, sd, &sctx, &two_ctx);
    hf_hit one_vl;
    hf_trace_options o = on(HF_SURFACE_VIEW_LINEAR);
    o.ray_classes = HF_RAYS_ALL;
    CHECK_OK(hf_trace(f, sm, dmap, dlen, &o, &rays[7], &one_vl));
    CHECK(memcmp(&one_vl, &sd[7], sizeof one_vl) == 0);
    printf("safety on the view-linear surface: agrees on %d of %d\n", vl, N);

    /* Ray sets: maps baked for exterior rays, for rays within 45 degrees of the
     * vertical, and both, are never shorter than the every-ray map and longer somewhere;
     * their traces (the descriptor records the set, and rays outside it walk cell by
     * cell) find the exact hits of every ray, inside the box or not. */
    for (int set = 0; set < 3; set++) {
        hf_bake_options ro = good;
        ro.exterior = set != 1;
        ro.max_view_angle_deg = set == 0 ? 0.0f : 45.0f;
        size_t rlen = 0;
        unsigned char *rmap = (unsigned char *)bake_map(sm, f, &ro, &rlen);
        int shorter = 0, longer = 0;
        for (size_t k = 0; k + HF_MAP_DESC_BYTES < rlen; k++) {
            shorter += rmap[k] < dmap[k];
            longer += rmap[k] > dmap[k];
        }
        CHECK(rlen == dlen && shorter == 0 && longer > 0);
        CHECK_OK(hf_trace_batch(f, sm, rmap, rlen, NULL, rays, N, sd, N));
        int agree = agreeing(exact, sd, N);
        CHECK(agree == N);
        printf("safety, ray set %d: %d texel distances longer, %d of %d rays agree\n", set,
               longer, agree, N);
        free(rmap);
    }

    /* Bad trace inputs (unknown surfaces too: the layout is no longer passed, nor a bad
     * one). The isotropic map traces as itself (it was refused when named directional). */
    check_bad_traces(f, sm, dmap, dlen, NULL, rays, N, sd);
    hf_hit h;
    CHECK_OK(hf_trace(f, sm, imap, ilen, NULL, &rays[7], &h));
    CHECK(agreeing(&exact[7], &h, 1) == 1);
    free(rays);
    free(exact);
    free(sd);
    free(dmap);
    free(imap);
    free(rows);
    free(heights);
    hf_field_destroy(f);
}

/* ---- safety radius ------------------------------------------------------------------ */

static void test_radius(void) {
    enum { W = 37, H = 23, N = 2000 };
    float *heights = NULL;
    hf_field *f = needle_field(W, H, 8.0f, 11 * W + 17, 30.0f, &heights);

    /* Every bake function and its faults (check_bakes; a negative, NaN or infinite
     * tolerance, a cap above 255 among the bad options). */
    const uint32_t rm = HF_METHOD_RADIUS;
    const hf_bake_options good = bake_defaults(rm);
    CHECK(good.tolerance == 0.0f && good.cap == 255);
    size_t len = 0;
    unsigned char *map = (unsigned char *)check_bakes(rm, f, &good, &len);
    CHECK(len == (size_t)W * H + HF_MAP_DESC_BYTES);

    /* Exact with zero radii walked: the exact method's hits on the triangle surface;
       clamped: the batch equals one-by-one traces. */
    hf_ray *rays = down_rays(N, W, H, 25.0f, 13, 1, 31);
    hf_hit *exact = exact_hits(f, rays, N);
    hf_hit *rd = (hf_hit *)malloc(sizeof(hf_hit) * N);
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

    /* Bad trace inputs; unknown radius_zero values are bad enums. */
    check_bad_traces(f, rm, map, len, NULL, rays, N, rd);
    hf_hit h;
    memset(&h, 0x5A, sizeof h);
    hf_trace_options bad_zero = on(HF_SURFACE_TRIANGLES);
    for (bad_zero.radius_zero = 2; bad_zero.radius_zero <= 9; bad_zero.radius_zero += 7) {
        CHECK_BAD(hf_trace(f, rm, map, len, &bad_zero, &rays[0], &h), HF_ERR_INVALID_ENUM, &h,
                  sizeof h);
        CHECK_BAD(hf_trace_batch(f, rm, map, len, &bad_zero, rays, 2, rd, 2), HF_ERR_INVALID_ENUM,
                  rd, 512);
    }
    free(rays);
    free(exact);
    free(rd);
    free(map);
    free(heights);
    hf_field_destroy(f);
}

/* ---- the cone family: cone step mapping, relaxed cones, QDM ----------------------------- */

static void test_cones(void) {
    enum { W = 33, H = 25, N = 2000, D = HF_MAP_DESC_BYTES / 4 };
    float *heights = NULL;
    hf_field *f = needle_field(W, H, 6.0f, 12 * W + 9, 20.0f, &heights);
    /* Every bake function and its faults (check_bakes), each of the three methods (in
     * the order of the budgets below): cone, QDM, relaxed. */
    const uint32_t family[3] = {HF_METHOD_CONE, HF_METHOD_QDM, HF_METHOD_RELAXED};
    float *maps[3];
    size_t lens[3];
    for (int m = 0; m < 3; m++) {
        const hf_bake_options d = bake_defaults(family[m]);
        maps[m] = (float *)check_bakes(family[m], f, &d, &lens[m]);
    }
    CHECK(lens[0] == 2u * (W - 1) * (H - 1) + D && lens[1] == 4u * (W - 1) * (H - 1) + D &&
          lens[2] == (size_t)W * H + D);
    /* One scratch, the pyramid's texels, prepared once serves the three row bakes. */
    size_t slen = ask(hf_bake_scratch_len, HF_METHOD_CONE, W, H, NULL);
    CHECK(slen + D == ask(hf_map_len, HF_METHOD_MAXMIP, W, H, NULL));
    float *scratch = (float *)malloc(sizeof(float) * slen);
    CHECK_OK(hf_bake_prepare(HF_METHOD_CONE, f, NULL, scratch, slen));
    for (int m = 0; m < 3; m++) {
        uint32_t rows = 0;
        CHECK(ask(hf_bake_scratch_len, family[m], W, H, NULL) == slen);
        CHECK_OK(hf_bake_row_count(family[m], W, H, NULL, &rows));
        float *shared = (float *)calloc(lens[m], sizeof(float));
        CHECK_OK(hf_bake_rows(family[m], f, NULL, scratch, slen, 0, rows, shared, lens[m]));
        CHECK(memcmp(shared, maps[m], sizeof(float) * lens[m]) == 0);
        free(shared);
    }
    free(scratch);

    /* Cone and QDM are exact within their budget; relaxed cones are approximate. */
    hf_ray *rays = down_rays(N, W, H, 25.0f, 11, 0, 29);
    hf_hit *exact = exact_hits(f, rays, N);
    hf_hit *other = (hf_hit *)malloc(sizeof(hf_hit) * N);
    /* Each method, its map, its budget (iterations; relaxed: cone steps, bisections). */
    const struct {
        method_map m;
        uint32_t steps, binary;
    } cones[3] = {{{HF_METHOD_CONE, maps[0], lens[0]}, 1000, 8},
                  {{HF_METHOD_QDM, maps[1], lens[1]}, 1000, 8},
                  {{HF_METHOD_RELAXED, maps[2], lens[2]}, 64, 16}};
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
    CHECK_OK(hf_trace(f, HF_METHOD_CONE, maps[0], lens[0], &o, &down, &one));
    CHECK((one.flags & HF_FLAG_BUDGET_EXHAUSTED) || one.hit);

    /* Bad inputs, each of the three methods; zero iterations are refused. */
    hf_trace_options zero = budget(HF_SURFACE_TRIANGLES, 0, 8);
    o = budget(HF_SURFACE_TRIANGLES, 10, 8);
    memset(&h, 0x5A, sizeof h);
    for (int m = 0; m < 3; m++) {
        const method_map *c = &cones[m].m;
        check_bad_traces(f, c->method, c->map, c->len, &o, rays, N, other);
        CHECK_BAD(hf_trace(f, c->method, c->map, c->len, &zero, &rays[0], &h),
                  HF_ERR_INVALID_ARGUMENT, &h, sizeof h);
        CHECK_BAD(hf_trace_batch(f, c->method, c->map, c->len, &zero, rays, 3, other, 3),
                  HF_ERR_INVALID_ARGUMENT, other, 512);
        free(maps[m]);
    }
    free(rays);
    free(exact);
    free(other);
    free(heights);
    hf_field_destroy(f);
}

/* ---- cylinder-cone safety shapes ------------------------------------------------------ */

static void test_cc(void) {
    enum { W = 37, H = 27, N = 2000, CAP = 32 };
    float *heights = NULL;
    hf_field *f = needle_field(W, H, 8.0f, 10 * W + 20, 30.0f, &heights);
    /* Every bake function and its faults (check_bakes), exact and N-buffer slopes. */
    const uint32_t cm = HF_METHOD_CC; /* the cap is the map's (its descriptor names it) */
    hf_bake_options good = bake_defaults(cm), nbo;
    CHECK(good.cap == 64 && good.slope == HF_CC_SLOPE_EXACT);
    good.cap = CAP;
    good.ray_classes = HF_RAYS_ALL;
    nbo = good;
    nbo.slope = HF_CC_SLOPE_NBUFFER;
    size_t mlen = 0, nlen = 0, ylen = 0;
    unsigned char *map = (unsigned char *)check_bakes(cm, f, &good, &mlen);
    unsigned char *nbmap = (unsigned char *)check_bakes(cm, f, &nbo, &nlen);
    /* [r, s] per texel and class, whichever slope. */
    CHECK(mlen == (size_t)W * H * 8 + HF_MAP_DESC_BYTES && nlen == mlen);
    /* The scratch: the safety bakes' strip bounds, then the N-buffers, more of them for a
     * larger cap (the default 64). */
    size_t slen = ask(hf_bake_scratch_len, cm, W, H, &good);
    CHECK(slen > ask(hf_bake_scratch_len, HF_METHOD_SAFETY, W, H, NULL) &&
          ask(hf_bake_scratch_len, cm, W, H, NULL) > slen);
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
     * * W) * 2); the row bakes agree (check_bakes). */
    hf_bake_options co = good;
    co.ray_classes = HF_RAYS_Y_POS;
    unsigned char *rows = (unsigned char *)check_bakes(cm, f, &co, &ylen);
    CHECK((ylen - HF_MAP_DESC_BYTES) * 4 == mlen - HF_MAP_DESC_BYTES);
    int cc_mask_ok = 1;
    for (size_t j = 0; j < (size_t)H; j++)
        cc_mask_ok &= memcmp(rows + j * W * 2, map + (j * 4 + 2) * W * 2, (size_t)W * 2) == 0;
    CHECK(cc_mask_ok);
    /* ray_classes 0 means all four (the full map's size and bytes); above 15 is an error
     * (bad_options). */
    check_all_classes(cm, f, co, map, mlen);

    /* Exact: both slope variants find the exact method's hits (shadow rays too). */
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        rays[k] = ray(-5.0f + (W + 10) * frand(), -5.0f + (H + 10) * frand(), 35.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, (k % 4 == 0 ? 0.3f : -0.5f) * frand());
        if (k % 13 == 0) rays[k].dir[1] = 0.0f;
    }
    hf_hit *exact = exact_hits(f, rays, N), *cc = (hf_hit *)malloc(sizeof(hf_hit) * N);
    int same[2] = {0, 0}, hits = 0;
    for (int v = 0; v < 2; v++) {
        CHECK_OK(hf_trace_batch(f, cm, v == 0 ? map : nbmap, mlen, NULL, rays, N, cc, N));
        for (int k = 0; v == 0 && k < N; k++) hits += exact[k].hit;
        same[v] = agreeing(exact, cc, N);
    }
    CHECK(same[0] == N && same[1] == N);
    printf("cc: %d rays, %d exact hits; exact slopes agree on %d, n-buffer slopes on %d\n", N, hits,
           same[0], same[1]);
    /* The one-class map (in `rows`); the whole exact-slope map on the view-linear
     * surface. */
    struct safety_ctx y_ctx = {f, cm, rows, ylen, HF_RAYS_Y_POS}, cctx = {f, cm, map, mlen, HF_RAYS_ALL};
    int vl = check_class_maps("cc, one class", rays, N, exact, cc, &cctx, &y_ctx);
    hf_trace_options o = on(HF_SURFACE_TRIANGLES);
    printf("cc on the view-linear surface: agrees on %d of %d\n", vl, N);
    hf_hit one, h;
    CHECK_OK(hf_trace(f, cm, map, mlen, NULL, &rays[5], &one));
    CHECK_OK(hf_trace_batch(f, cm, map, mlen, NULL, &rays[5], 1, &h, 1));
    CHECK(memcmp(&one, &h, sizeof h) == 0);
    memset(&h, 0x5A, sizeof h);
    /* The cap is no longer passed (a bad one was HF_ERR_INVALID_ARGUMENT): a class set
     * other than the map's is refused instead. */
    o.ray_classes = HF_RAYS_Y_POS;
    CHECK_BAD(hf_trace(f, cm, map, mlen, &o, &rays[0], &h), HF_ERR_MAP_MISMATCH, &h, sizeof h);
    check_bad_traces(f, cm, map, mlen, NULL, rays, N, cc);
    free(rays);
    free(exact);
    free(cc);
    free(map);
    free(nbmap);
    free(rows);
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

/* 1 when two answers hit the same point the same way, bit for bit: `fetches` and
 * `clearance` may differ between a shared horizon and none. */
static int same_hit(const hf_hit *a, const hf_hit *b) {
    return a->hit == b->hit && a->flags == b->flags && a->cell[0] == b->cell[0] &&
           a->cell[1] == b->cell[1] && memcmp(&a->t, &b->t, sizeof a->t) == 0 &&
           memcmp(a->point, b->point, sizeof a->point) == 0 &&
           memcmp(a->normal, b->normal, sizeof a->normal) == 0;
}

/* Rays from one eye share a horizon (hf_trace_options::horizon): a camera of 64 x 48
 * pixels over a rough 120 x 100 field, from outside it at a low elevation and from over
 * it looking down, traced by hf_trace_camera and by hf_trace_batch on its rays, each
 * with the default HF_HORIZON_AUTO and with HF_HORIZON_OFF, by the exact DDA and the
 * maximum mipmap, on 1 and 2 threads: the same hits bit for bit, and the horizon reads
 * fewer texels. */
static void check_horizon(void) {
    enum { W = 120, H = 100, CW = 64, CH = 48, NP = CW * CH };
    static float heights[W * H];
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++)
            heights[j * W + i] = 6.0f * sinf(0.21f * (float)i) * cosf(0.17f * (float)j) +
                                 2.0f * sinf(0.9f * (float)(i + 2 * j)) + (float)((i * 7 + j * 13) % 5);
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    size_t plen = 0;
    float *pyr = (float *)bake_map(HF_METHOD_MAXMIP, f, NULL, &plen);
    /* From outside, from over the field looking down, and from far away (a telephoto
     * whose rays the batches condition: their local form, not the plain queries). */
    const hf_camera cams[3] = {
        {{-30.0f, -20.0f, 16.0f}, {150.0f, 120.0f, -12.0f}, {0.0f, 0.0f, 1.0f}, 35.0f, CW, CH,
         INFINITY},
        {{55.0f, 45.0f, 60.0f}, {0.1f, 0.2f, -1.0f}, {0.0f, 1.0f, 0.0f}, 100.0f, CW, CH,
         INFINITY},
        {{-2000.0f, -1700.0f, 300.0f}, {2060.0f, 1750.0f, -300.0f}, {0.0f, 0.0f, 1.0f}, 4.0f, CW,
         CH, INFINITY}};
    static hf_ray rays[NP];
    static hf_hit off[NP], on[NP];
    const uint32_t methods[2] = {HF_METHOD_EXACT, HF_METHOD_MAXMIP};
    const void *maps[2] = {NULL, pyr};
    const size_t lens[2] = {0, plen};
    unsigned long long fetched[2] = {0, 0};
    int far_hits = 0;
    for (int c = 0; c < 3; c++) {
        for (uint32_t y = 0; y < CH; y++)
            for (uint32_t x = 0; x < CW; x++)
                CHECK_OK(hf_camera_ray(&cams[c], x, y, &rays[y * CW + x]));
        for (int m = 0; m < 2; m++) {
            hf_trace_options o;
            CHECK_OK(hf_trace_options_default(&o));
            o.horizon = HF_HORIZON_OFF;
            CHECK_OK(hf_trace_batch(f, methods[m], maps[m], lens[m], &o, rays, NP, off, NP));
            for (int k = 0; c == 2 && k < NP; k++) far_hits += (int)off[k].hit;
            for (uint32_t t = 1; t <= 2; t++) {
                o.horizon = HF_HORIZON_AUTO;
                o.threads = t;
                for (int camera = 0; camera < 2; camera++) {
                    memset(on, 0x5A, sizeof on);
                    if (camera)
                        CHECK_OK(hf_trace_camera(f, methods[m], maps[m], lens[m], &o, &cams[c],
                                                 on, NP));
                    else
                        CHECK_OK(hf_trace_batch(f, methods[m], maps[m], lens[m], &o, rays, NP,
                                                on, NP));
                    int same = 1;
                    for (int k = 0; k < NP; k++) {
                        same &= same_hit(&on[k], &off[k]);
                        if (m == 0 && t == 1 && !camera) {
                            fetched[0] += off[k].fetches;
                            fetched[1] += on[k].fetches;
                        }
                    }
                    CHECK(same);
                }
            }
        }
    }
    CHECK(fetched[1] < fetched[0]);
    CHECK(far_hits > NP / 2); /* the far camera sees the field */
    printf("horizon: %llu texels read one ray at a time, %llu sharing a horizon\n",
           fetched[0], fetched[1]);
    free(pyr);
    hf_field_destroy(f);
}

/* A camera batch large enough that hf_trace_batch checks and sights its rays in parts on
 * its threads (the first bad ray reported wherever it lies, nothing written; the horizon
 * of the parts giving the hits of rays traced without one). */
static void check_batch_in_parts(void) {
    enum { W = 120, H = 100, CW = 256, CH = 160, NP = CW * CH };
    static float heights[W * H];
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++)
            heights[j * W + i] = 5.0f * sinf(0.23f * (float)i) * cosf(0.19f * (float)j) +
                                 (float)((i * 5 + j * 11) % 4);
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    const hf_camera cam = {{-25.0f, -15.0f, 30.0f}, {140.0f, 110.0f, -90.0f},
                           {0.0f, 0.0f, 1.0f}, 40.0f, CW, CH, INFINITY};
    static hf_ray rays[NP];
    static hf_hit off[NP], on[NP], before[NP];
    for (uint32_t y = 0; y < CH; y++)
        for (uint32_t x = 0; x < CW; x++) CHECK_OK(hf_camera_ray(&cam, x, y, &rays[y * CW + x]));
    hf_trace_options o;
    CHECK_OK(hf_trace_options_default(&o));
    o.horizon = HF_HORIZON_OFF;
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &o, rays, NP, off, NP));
    o.horizon = HF_HORIZON_AUTO;
    int hits = 0;
    for (uint32_t t = 1; t <= 2; t++) {
        o.threads = t;
        CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &o, rays, NP, on, NP));
        int same = 1;
        unsigned long long fetched[2] = {0, 0};
        for (int k = 0; k < NP; k++) {
            same &= same_hit(&on[k], &off[k]);
            fetched[0] += off[k].fetches;
            fetched[1] += on[k].fetches;
        }
        CHECK(same);
        CHECK(fetched[1] < fetched[0]); /* the horizon was built and used */
        for (int k = 0; t == 1 && k < NP; k++) hits += (int)on[k].hit;
    }
    CHECK(hits > NP / 2);
    /* Bad rays in the second thread's part, then in both: the first is reported. */
    const size_t bad[2] = {NP - 5000, NP / 4};
    const hf_ray keep[2] = {rays[bad[0]], rays[bad[1]]};
    char detail[128], want[32];
    size_t written = 0, at = 0;
    memset(on, 0x5A, sizeof on);
    memcpy(before, on, sizeof on);
    for (int b = 0; b < 2; b++) {
        rays[bad[b]].dir[0] = rays[bad[b]].dir[1] = rays[bad[b]].dir[2] = 0.0f;
        for (uint32_t t = 1; t <= 2; t++) {
            o.threads = t;
            CHECK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &o, rays, NP, on, NP) ==
                  HF_ERR_INVALID_RAY);
            CHECK(memcmp(on, before, sizeof on) == 0);
            CHECK(hf_last_error_index(&at) == HF_OK && at == bad[b]);
            snprintf(want, sizeof want, "rays[%zu]", bad[b]);
            CHECK(hf_last_error_detail(detail, sizeof detail, &written) == HF_OK &&
                  strstr(detail, want) != NULL);
        }
    }
    rays[bad[0]] = keep[0];
    rays[bad[1]] = keep[1];
    hf_field_destroy(f);
}

/* Occluders: a ring of four walls (eight triangle tops, `top` high) one texel around a
 * W x H field, into `walls`. */
static void walls_around(uint32_t w, uint32_t h, float top, hf_occluder walls[8]) {
    const float X = (float)(w - 1), Y = (float)(h - 1);
    const float rects[4][4] = {{-3.0f, -1.0f, -3.0f, Y + 3.0f},
                               {X + 1.0f, X + 3.0f, -3.0f, Y + 3.0f},
                               {-3.0f, X + 3.0f, -3.0f, -1.0f},
                               {-3.0f, X + 3.0f, Y + 1.0f, Y + 3.0f}};
    for (int r = 0; r < 4; r++) {
        const float *q = rects[r];
        const float c[4][3] = {{q[0], q[2], top}, {q[1], q[2], top}, {q[1], q[3], top},
                               {q[0], q[3], top}};
        const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int t = 0; t < 2; t++)
            for (int v = 0; v < 3; v++)
                memcpy(walls[2 * r + t].corners[v], c[tri[t][v]], sizeof c[0]);
    }
}

/* Safety and cylinder-cone maps baked over occluders (exterior rays that pass over a
 * ring of walls): never shorter than the exterior maps, longer somewhere; traced with
 * the same occluders, every camera ray (over the walls, and low ones through them,
 * which walk cell by cell) gets the exact hit, one by one, in batches and through
 * hf_trace_camera at 1 and 2 threads; other occluders, none, or occluders for a map
 * baked without are HF_ERR_MAP_MISMATCH; bad occluders are refused. */
static void check_occluders(void) {
    enum { W = 48, H = 40, CW = 40, CH = 30, NP = CW * CH };
    static float heights[W * H];
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++)
            heights[j * W + i] = 6.0f * sinf(0.21f * (float)i) * cosf(0.17f * (float)j) +
                                 (float)((i * 7 + j * 13) % 5);
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    hf_occluder walls[8];
    walls_around(W, H, 14.0f, walls);
    const hf_camera cams[2] = {
        {{-2.0f, -2.0f, 20.0f}, {32.0f, 27.0f, -20.0f}, {0.0f, 0.0f, 1.0f}, 50.0f, CW, CH,
         INFINITY},
        {{-12.0f, 20.0f, 12.0f}, {1.0f, 0.0f, -0.15f}, {0.0f, 0.0f, 1.0f}, 60.0f, CW, CH,
         INFINITY}};
    static hf_ray rays[2 * NP];
    for (int c = 0; c < 2; c++)
        for (uint32_t y = 0; y < CH; y++)
            for (uint32_t x = 0; x < CW; x++)
                CHECK_OK(hf_camera_ray(&cams[c], x, y, &rays[c * NP + y * CW + x]));
    hf_hit *exact = exact_hits(f, rays, 2 * NP);
    static hf_hit got[2 * NP];
    const uint32_t methods[2] = {HF_METHOD_SAFETY, HF_METHOD_CC};
    for (int m = 0; m < 2; m++) {
        uint32_t me = methods[m];
        hf_bake_options ext = bake_defaults(me), over = ext;
        ext.exterior = over.exterior = 1;
        over.occluders = walls;
        over.occluder_count = 8;
        size_t elen = 0, olen = 0;
        unsigned char *emap = (unsigned char *)bake_map(me, f, &ext, &elen);
        unsigned char *omap = (unsigned char *)bake_map(me, f, &over, &olen);
        int shorter = 0, longer = 0;
        for (size_t k = 0; m == 0 && k + HF_MAP_DESC_BYTES < olen; k++) {
            shorter += omap[k] < emap[k];
            longer += omap[k] > emap[k];
        }
        CHECK(olen == elen && shorter == 0 && (m == 1 || longer > 0));
        hf_trace_options o;
        CHECK_OK(hf_trace_options_default(&o));
        o.occluders = walls;
        o.occluder_count = 8;
        unsigned long long fetched[2] = {0, 0};
        for (uint32_t t = 1; t <= 2; t++) {
            o.threads = t;
            CHECK_OK(hf_trace_batch(f, me, omap, olen, &o, rays, 2 * NP, got, 2 * NP));
            CHECK(agreeing(exact, got, 2 * NP) == 2 * NP);
            for (int k = 0; t == 1 && k < NP; k++) fetched[1] += got[k].fetches;
            for (int c = 0; c < 2; c++) {
                CHECK_OK(hf_trace_camera(f, me, omap, olen, &o, &cams[c], got, NP));
                CHECK(agreeing(exact + c * NP, got, NP) == NP);
            }
        }
        hf_hit h;
        CHECK_OK(hf_trace(f, me, omap, olen, &o, &rays[5], &h));
        CHECK(agreeing(&exact[5], &h, 1) == 1);
        hf_trace_options eo;
        CHECK_OK(hf_trace_options_default(&eo));
        CHECK_OK(hf_trace_batch(f, me, emap, elen, &eo, rays, 2 * NP, got, 2 * NP));
        for (int k = 0; k < NP; k++) fetched[0] += got[k].fetches;
        printf("occluders, %s: %d texel distances longer than exterior's; %d camera rays "
               "exact; the camera over the walls reads %llu texels over the exterior map, "
               "%llu over the walls'\n",
               m ? "cc" : "safety", longer, 2 * NP, fetched[0], fetched[1]);
        /* Not the map's occluders: none, fewer, or some for a map baked without. */
        hf_trace_options none = o, fewer = o;
        none.occluders = NULL;
        none.occluder_count = 0;
        fewer.occluder_count = 7;
        memset(got, 0x5A, sizeof got);
        CHECK_BAD(hf_trace_batch(f, me, omap, olen, &none, rays, NP, got, NP),
                  HF_ERR_MAP_MISMATCH, got, sizeof(hf_hit) * NP);
        CHECK_BAD(hf_trace(f, me, omap, olen, &fewer, &rays[0], &h), HF_ERR_MAP_MISMATCH, &h,
                  sizeof h);
        CHECK_BAD(hf_trace_camera(f, me, emap, elen, &o, &cams[0], got, NP), HF_ERR_MAP_MISMATCH,
                  got, sizeof(hf_hit) * NP);
        free(emap);
        free(omap);
    }
    /* Bad occluders: a footprint of zero area, a NaN corner, too many, NULL. */
    hf_occluder bad[HF_MAX_OCCLUDERS + 1];
    for (int k = 0; k <= HF_MAX_OCCLUDERS; k++) bad[k] = walls[k % 8];
    hf_bake_options bo = bake_defaults(HF_METHOD_SAFETY);
    bo.exterior = 1;
    bo.occluders = bad;
    size_t len = 0;
    CHECK_OK(hf_map_len(HF_METHOD_SAFETY, W, H, &bo, &len));
    unsigned char *map = (unsigned char *)calloc(len, 1);
    for (int c = 0; c < 4; c++) {
        bad[0] = walls[0];
        bo.occluder_count = 1;
        hf_result want = HF_ERR_INVALID_ARGUMENT;
        if (c == 0) memcpy(bad[0].corners[2], bad[0].corners[0], sizeof bad[0].corners[0]);
        if (c == 1) bad[0].corners[1][2] = NAN;
        if (c == 2) bo.occluder_count = HF_MAX_OCCLUDERS + 1;
        if (c == 3) {
            bo.occluders = NULL;
            want = HF_ERR_NULL_POINTER;
        }
        CHECK_BAD(hf_bake(HF_METHOD_SAFETY, f, &bo, map, len), want, map, len);
        hf_trace_options to;
        CHECK_OK(hf_trace_options_default(&to));
        to.occluders = bo.occluders;
        to.occluder_count = bo.occluder_count;
        hf_hit h;
        CHECK_BAD(hf_trace(f, HF_METHOD_EXACT, NULL, 0, &to, &rays[0], &h), want, &h, sizeof h);
    }
    bo.occluders = bad;
    bo.occluder_count = HF_MAX_OCCLUDERS;
    CHECK_OK(hf_bake(HF_METHOD_SAFETY, f, &bo, map, len));
    free(map);
    free(exact);
    hf_field_destroy(f);
}

/* hf_trace_camera: its hits are hf_trace_batch's on hf_camera_ray's rays, bit for bit,
 * for each of `n` methods `all` of field `f` (W x H), at 1 and 2 threads; its shadow
 * pass is hf_shadow_ray then hf_trace per pixel (hf_shadow_ray_from_light when the maps
 * are baked for `exterior` rays); bad cameras and buffers are refused. */
static void check_camera(const hf_field *f, const method_map *all, int n, uint32_t w,
                         uint32_t h, int exterior) {
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
            CHECK_OK((exterior ? hf_shadow_ray_from_light : hf_shadow_ray)(
                f, HF_SURFACE_TRIANGLES, &rays[k], &cam_hits[k], &light, &sr));
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
    for (int k = 0; k < 5; k++) reserved_zero &= d.reserved[k] == 0;
    CHECK(d.surface == HF_SURFACE_TRIANGLES && d.ray_classes == 0 && d.steps == 64 &&
          d.binary_steps == 8 && d.radius_zero == HF_RADIUS_WALK && d.threads == 1 &&
          d.simd == HF_SIMD_AUTO && d.horizon == HF_HORIZON_AUTO && d.occluders == NULL &&
          d.occluder_count == 0 && reserved_zero);
    CHECK_BAD(hf_trace_options_default(NULL), HF_ERR_NULL_POINTER, nothing, 0);

    /* Every method's map of this field (NULL and 0 for the three without one): the
     * default options, the cylinder-cones with a cap of 32. */
    method_map all[HF_METHOD_COUNT];
    for (uint32_t m = 0; m < HF_METHOD_COUNT; m++) {
        hf_bake_options bo = bake_defaults(m);
        if (m == HF_METHOD_CC) bo.cap = 32;
        all[m].method = m;
        all[m].map = bake_map(m, f, &bo, &all[m].len);
    }
    const float *pyr = (const float *)all[HF_METHOD_MAXMIP].map;
    const size_t plen = all[HF_METHOD_MAXMIP].len;

    hf_ray rays[R];
    for (int k = 0; k < R; k++)
        rays[k] = ray(-2.0f + (W + 4) * frand(), -2.0f + (H + 4) * frand(), 6.0f + 4.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, -0.1f - frand());
    hf_hit a[R], b[R], h;
    for (int m = 0; m < (int)HF_METHOD_COUNT; m++) {
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
        /* A nonzero reserved word, whichever, is refused; so is an unknown hf_simd or
         * hf_horizon. */
        memset(b, 0x5A, sizeof b);
        for (int k = 0; k < 5; k++) {
            hf_trace_options o = d;
            o.reserved[k] = 1;
            CHECK_BAD(hf_trace(f, me, map, len, &o, &rays[0], &h), HF_ERR_INVALID_ARGUMENT, &h,
                      sizeof h);
            CHECK_BAD(hf_trace_batch(f, me, map, len, &o, rays, R, b, R), HF_ERR_INVALID_ARGUMENT,
                      b, sizeof b);
        }
        hf_trace_options bad_simd = d;
        bad_simd.simd = HF_SIMD_OFF + 1;
        CHECK_BAD(hf_trace(f, me, map, len, &bad_simd, &rays[0], &h), HF_ERR_INVALID_ENUM, &h,
                  sizeof h);
        CHECK_BAD(hf_trace_batch(f, me, map, len, &bad_simd, rays, R, b, R), HF_ERR_INVALID_ENUM,
                  b, sizeof b);
        hf_trace_options bad_horizon = d;
        bad_horizon.horizon = HF_HORIZON_OFF + 1;
        CHECK_BAD(hf_trace(f, me, map, len, &bad_horizon, &rays[0], &h), HF_ERR_INVALID_ENUM, &h,
                  sizeof h);
        CHECK_BAD(hf_trace_batch(f, me, map, len, &bad_horizon, rays, R, b, R),
                  HF_ERR_INVALID_ENUM, b, sizeof b);
        /* The surfaces it does not trace are refused, unknown ones are bad enums. */
        for (uint32_t s = HF_SURFACE_TRIANGLES; s <= HF_SURFACE_COUNT; s++) {
            hf_trace_options o = on(s);
            if (s < HF_SURFACE_COUNT && traces_surface(me, s)) {
                CHECK_OK(hf_trace_batch(f, me, map, len, &o, rays, R, a, R));
                continue;
            }
            hf_result want =
                s >= HF_SURFACE_COUNT ? HF_ERR_INVALID_ENUM : HF_ERR_INVALID_ARGUMENT;
            CHECK_BAD(hf_trace(f, me, map, len, &o, &rays[0], &h), want, &h, sizeof h);
            CHECK_BAD(hf_trace_batch(f, me, map, len, &o, rays, R, b, R), want, b, sizeof b);
        }
    }
    /* A batch on several threads (bands of 256 rays) answers as on one, every method:
     * threads 2, 3 and 0 (one per core) against the default 1; and without SIMD lanes
     * as with them. */
    enum { BIG = 2000 };
    hf_ray *many = (hf_ray *)malloc(sizeof(hf_ray) * BIG);
    hf_hit *one_thread = (hf_hit *)malloc(sizeof(hf_hit) * BIG);
    hf_hit *threaded = (hf_hit *)malloc(sizeof(hf_hit) * BIG);
    for (int k = 0; k < BIG; k++) many[k] = rays[k % R];
    for (int k = 0; k < BIG; k++) many[k].origin[0] += 0.001f * (float)(k / R);
    hf_trace_options variants[4] = {d, d, d, d};
    variants[0].threads = 2;
    variants[1].threads = 3;
    variants[2].threads = 0;
    variants[3].simd = HF_SIMD_OFF;
    for (int m = 0; m < (int)HF_METHOD_COUNT; m++) {
        CHECK_OK(hf_trace_batch(f, all[m].method, all[m].map, all[m].len, NULL, many, BIG,
                                one_thread, BIG));
        for (int v = 0; v < 4; v++) {
            memset(threaded, 0x5A, sizeof(hf_hit) * BIG);
            CHECK_OK(hf_trace_batch(f, all[m].method, all[m].map, all[m].len, &variants[v], many,
                                    BIG, threaded, BIG));
            CHECK(memcmp(one_thread, threaded, sizeof(hf_hit) * BIG) == 0);
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
    for (uint32_t me = HF_METHOD_EXACT; me < HF_METHOD_COUNT; me++) {
        if (!without_map(me)) continue;
        CHECK_BAD(hf_trace(f, me, NULL, 1, NULL, &rays[0], &h), HF_ERR_INVALID_ARGUMENT, &h,
                  sizeof h);
        CHECK_BAD(hf_trace(f, me, pyr, plen, NULL, &rays[0], &h), HF_ERR_INVALID_ARGUMENT, &h,
                  sizeof h);
        CHECK_BAD(hf_trace_batch(f, me, NULL, 1, NULL, rays, R, b, R), HF_ERR_INVALID_ARGUMENT, b,
                  sizeof b);
    }
    /* Unknown methods. */
    const uint32_t bad_methods[3] = {HF_METHOD_COUNT, 99, 0xFFFFFFFFu};
    for (int k = 0; k < 3; k++) {
        CHECK_BAD(hf_trace(f, bad_methods[k], NULL, 0, NULL, &rays[0], &h), HF_ERR_INVALID_ENUM,
                  &h, sizeof h);
        CHECK_BAD(hf_trace_batch(f, bad_methods[k], pyr, plen, NULL, rays, R, b, R),
                  HF_ERR_INVALID_ENUM, b, sizeof b);
    }

    /* Names of every method and surface; short buffers, unknown values, NULLs. */
    static const char *const methods[HF_METHOD_COUNT] = {
        "exact", "linear-binary", "linear-secant", "maxmip", "safety",  "cone",
        "relaxed", "qdm",         "cc",            "radius", "multires"};
    static const char *const surfaces[HF_SURFACE_COUNT] = {
        "triangles", "bilinear", "height-planes", "corner-planes", "view-linear", "qu-triangles"};
    hf_result (*const name_of[2])(uint32_t, char *, size_t, size_t *) = {hf_method_name,
                                                                        hf_surface_name};
    const char *const *names[2] = {methods, surfaces};
    const uint32_t counts[2] = {HF_METHOD_COUNT, HF_SURFACE_COUNT};
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
    check_camera(f, all, HF_METHOD_COUNT, W, H, 0);
    /* Maps of exterior rays: the shadow pass traces from the light's side. */
    method_map exterior[2] = {{HF_METHOD_SAFETY, NULL, 0}, {HF_METHOD_CC, NULL, 0}};
    for (int m = 0; m < 2; m++) {
        hf_bake_options ext;
        CHECK_OK(hf_bake_options_default(exterior[m].method, &ext));
        ext.exterior = 1;
        exterior[m].map = bake_map(exterior[m].method, f, &ext, &exterior[m].len);
    }
    check_camera(f, exterior, 2, W, H, 1);
    for (int m = 0; m < 2; m++) free((void *)exterior[m].map);
    for (int m = 0; m < (int)HF_METHOD_COUNT; m++) free((void *)all[m].map);
    hf_field_destroy(f);
    check_horizon();
    check_batch_in_parts();
    check_occluders();
}

/* ---- bake options, row counts, the methods without a map --------------------------- */

/* Every method's default bake options; NULL options are those defaults in every bake
 * function (sizes, scratch, rows, the map of the whole and of the row bake); the row
 * counts; the methods without a map bake nothing (a map length is refused); unknown
 * methods are bad enums. */
static void test_bake_defaults(void) {
    enum { W = 13, H = 11 };
    float heights[W * H];
    for (int k = 0; k < W * H; k++) heights[k] = 0.5f * (float)(k * 7 % 17);
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    /* Per method: the default cap (255 safety distances and radii, 64 cylinder-cones) and
     * the rows of the row bake (cone and QDM rows are cell rows: H - 1). */
    const uint32_t caps[HF_METHOD_COUNT] = {0, 0, 0, 0, 255, 0, 0, 0, 64, 255, 0};
    const uint32_t rows[HF_METHOD_COUNT] = {0, 0, 0, 1, H, H - 1, H, H - 1, H, H, 0};
    for (uint32_t m = HF_METHOD_EXACT; m < HF_METHOD_COUNT; m++) {
        const hf_bake_options d = bake_defaults(m);
        int zero = 1;
        for (int k = 0; k < 4; k++) zero &= d.reserved[k] == 0;
        CHECK(d.variant == HF_SAFETY_DIRECTIONAL && d.positive == 0 && d.cap == caps[m] &&
              d.slope == HF_CC_SLOPE_EXACT && d.ray_classes == 0 && d.tolerance == 0.0f &&
              d.threads == 1 && d.exterior == 0 && d.max_view_angle_deg == 0.0f &&
              d.occluder_count == 0 && d.occluders == NULL && zero);
        uint32_t r_null = 77, r_def = 77;
        CHECK_OK(hf_bake_row_count(m, W, H, NULL, &r_null));
        CHECK_OK(hf_bake_row_count(m, W, H, &d, &r_def));
        CHECK(r_null == rows[m] && r_def == rows[m]);
        size_t slen = ask(hf_bake_scratch_len, m, W, H, NULL), len = 0, dlen = 0;
        CHECK(slen == ask(hf_bake_scratch_len, m, W, H, &d));
        unsigned char *a = (unsigned char *)bake_map(m, f, NULL, &len);
        unsigned char *b = (unsigned char *)bake_map(m, f, &d, &dlen);
        size_t bytes = len * elem_bytes(m);
        CHECK(len == dlen && (len == 0) == without_map(m));
        CHECK(len == 0 || memcmp(a, b, bytes) == 0);
        /* Prepare and row bake with NULL options: the same map. */
        float *scratch = (float *)calloc(slen + 1, sizeof(float));
        CHECK_OK(hf_bake_prepare(m, f, NULL, scratch, slen));
        if (b) memset(b, 0, bytes);
        CHECK_OK(hf_bake_rows(m, f, NULL, scratch, slen, 0, rows[m], b, len));
        CHECK(len == 0 || memcmp(a, b, bytes) == 0);
        free(scratch);
        free(a);
        free(b);
    }
    /* The methods without a map: no scratch, nothing to prepare; a map is refused. */
    unsigned char byte = 0x5A;
    for (uint32_t m = HF_METHOD_EXACT; m < HF_METHOD_COUNT; m++) {
        if (!without_map(m)) continue;
        CHECK(ask(hf_bake_scratch_len, m, W, H, NULL) == 0);
        CHECK_OK(hf_bake_prepare(m, f, NULL, NULL, 0));
        CHECK_BAD(hf_bake(m, f, NULL, &byte, 1), HF_ERR_INVALID_ARGUMENT, &byte, 1);
        CHECK_BAD(hf_bake(m, f, NULL, NULL, 1), HF_ERR_INVALID_ARGUMENT, nothing, 0);
        CHECK_BAD(hf_bake_rows(m, f, NULL, NULL, 0, 0, 0, &byte, 1), HF_ERR_INVALID_ARGUMENT,
                  &byte, 1);
        CHECK_BAD(hf_bake(m, NULL, NULL, NULL, 0), HF_ERR_NULL_POINTER, nothing, 0);
    }
    /* Unknown methods, a NULL output. */
    const uint32_t bad_methods[3] = {HF_METHOD_COUNT, 99, 0xFFFFFFFFu};
    const size_query queries[2] = {hf_map_len, hf_bake_scratch_len};
    for (int k = 0; k < 3; k++) {
        const uint32_t m = bad_methods[k];
        hf_bake_options o;
        size_t junk = 77;
        uint32_t r = 77;
        memset(&o, 0x5A, sizeof o);
        CHECK_BAD(hf_bake_options_default(m, &o), HF_ERR_INVALID_ENUM, &o, sizeof o);
        for (int q = 0; q < 2; q++)
            CHECK_BAD(queries[q](m, W, H, NULL, &junk), HF_ERR_INVALID_ENUM, &junk, sizeof junk);
        CHECK_BAD(hf_bake_row_count(m, W, H, NULL, &r), HF_ERR_INVALID_ENUM, &r, sizeof r);
        CHECK_BAD(hf_bake_prepare(m, f, NULL, NULL, 0), HF_ERR_INVALID_ENUM, nothing, 0);
        CHECK_BAD(hf_bake_rows(m, f, NULL, NULL, 0, 0, 1, &byte, 1), HF_ERR_INVALID_ENUM, &byte, 1);
        CHECK_BAD(hf_bake(m, f, NULL, &byte, 1), HF_ERR_INVALID_ENUM, &byte, 1);
    }
    CHECK_BAD(hf_bake_options_default(HF_METHOD_SAFETY, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    hf_field_destroy(f);
}

/* ---- row bakes from several threads at once ------------------------------------------- */

/* A row range of a map for one thread: rows [r0, r1) of pyramid level `level`
 * (hf_maxmip_bake_rows) for the maximum mipmap, else of `method`'s map (hf_bake_rows
 * with the default options, reading `scratch`). */
typedef struct rows_job {
    const hf_field *field;
    uint32_t method, level, r0, r1;
    const float *scratch;
    size_t scratch_len;
    void *map;
    size_t map_len;
    hf_result result;
} rows_job;

static void *bake_rows_thread(void *arg) {
    rows_job *j = (rows_job *)arg;
    if (j->method == HF_METHOD_MAXMIP)
        j->result = hf_maxmip_bake_rows(j->field, j->level, j->r0, j->r1, (float *)j->map,
                                        j->map_len);
    else
        j->result = hf_bake_rows(j->method, j->field, NULL, j->scratch, j->scratch_len, j->r0,
                                 j->r1, j->map, j->map_len);
    return NULL;
}

enum { JOBS = 4 };

/* `job` on each of `rows` rows split in JOBS ranges, on JOBS threads at once. */
static void run_jobs(rows_job job, uint32_t rows) {
    pthread_t th[JOBS];
    rows_job jobs[JOBS];
    uint32_t per = (rows + JOBS - 1) / JOBS;
    for (int t = 0; t < JOBS; t++) {
        jobs[t] = job;
        jobs[t].r0 = per * (uint32_t)t < rows ? per * (uint32_t)t : rows;
        jobs[t].r1 = jobs[t].r0 + per < rows ? jobs[t].r0 + per : rows;
        CHECK(pthread_create(&th[t], NULL, bake_rows_thread, &jobs[t]) == 0);
    }
    for (int t = 0; t < JOBS; t++) {
        pthread_join(th[t], NULL);
        CHECK(jobs[t].result == HF_OK);
    }
}

/* Disjoint row ranges of one level (or of every other method's map) baked by four
 * threads at once into one buffer, sharing one scratch: what a job system does. Equals
 * the single-threaded bake. */
static void test_concurrent_rows(void) {
    enum { W = 203, H = 117 };
    float *hs = (float *)malloc(sizeof(float) * W * H);
    for (int k = 0; k < W * H; k++) hs[k] = 50.0f * frand();
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(hs, W * H, W, H, W, &f));
    hf_level levels[HF_MAX_LEVELS];
    uint32_t count = 0;
    CHECK_OK(hf_maxmip_levels(W, H, levels, HF_MAX_LEVELS, &count));
    for (uint32_t m = HF_METHOD_MAXMIP; m <= HF_METHOD_RADIUS; m++) {
        size_t len = 0, slen = ask(hf_bake_scratch_len, m, W, H, NULL);
        uint32_t rows = 0;
        CHECK_OK(hf_bake_row_count(m, W, H, NULL, &rows));
        void *whole = bake_map(m, f, NULL, &len);
        float *scratch = (float *)calloc(slen + 1, sizeof(float));
        void *map = calloc(len, elem_bytes(m));
        CHECK_OK(hf_bake_prepare(m, f, NULL, scratch, slen));
        rows_job job = {f, m, 0, 0, 0, scratch, slen, map, len, HF_ERR_PANIC};
        if (m != HF_METHOD_MAXMIP)
            run_jobs(job, rows);
        for (job.level = 0; m == HF_METHOD_MAXMIP && job.level < count; job.level++)
            run_jobs(job, levels[job.level].height);
        CHECK(memcmp(whole, map, len * elem_bytes(m)) == 0);
        free(map);
        free(scratch);
        free(whole);
    }
    free(hs);
    hf_field_destroy(f);
}

/* ---- shader sources -------------------------------------------------------------- */

/* The full build has every method; bake plans follow the scene. */
static void test_build_and_plan(void) {
    for (uint32_t m = 0; m < HF_METHOD_COUNT; m++) {
        uint32_t has = 7;
        CHECK_OK(hf_build_has_method(m, &has));
        CHECK(has == 1);
    }
    uint32_t has = 7;
    CHECK_BAD(hf_build_has_method(HF_METHOD_COUNT, &has), HF_ERR_INVALID_ENUM, &has,
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
    /* The plan's ray set: every ray for the general scene (it traces shadows from the
     * surface), the scene's set without shadows or with shadows from the light, and
     * the angle only below 180 degrees; an unknown shadow kind is refused. */
    CHECK(scene.shadows == HF_SHADOWS_FROM_SURFACE);
    CHECK(plan.exterior == 0 && plan.max_view_angle_deg == 0.0f);
    scene.outside_only = 1;
    scene.max_view_angle_deg = 60.0f;
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.exterior == 0 && plan.max_view_angle_deg == 0.0f);
    scene.shadows = HF_SHADOWS_FROM_LIGHT;
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.exterior == 1 && plan.max_view_angle_deg == 60.0f);
    scene.shadows = 3;
    CHECK(hf_scene_bake_plan(&scene, &plan) == HF_ERR_INVALID_ARGUMENT);
    scene.shadows = HF_SHADOWS_NONE;
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.exterior == 1 && plan.max_view_angle_deg == 60.0f);
    scene.max_view_angle_deg = 180.0f;
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.exterior == 1 && plan.max_view_angle_deg == 0.0f);
    scene.outside_only = 0;
    scene.max_view_angle_deg = 45.0f;
    CHECK_OK(hf_scene_bake_plan(&scene, &plan));
    CHECK(plan.exterior == 0 && plan.max_view_angle_deg == 45.0f);
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
    for (uint32_t m = HF_METHOD_EXACT; m < HF_METHOD_COUNT; m++) {
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
    CHECK_BAD(hf_shader_source_len(HF_METHOD_COUNT, &len), HF_ERR_INVALID_ENUM, &len,
              sizeof len);
    CHECK_BAD(hf_shader_source_len(0, NULL), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_shader_source(77, buf, sizeof buf, &written), HF_ERR_INVALID_ENUM, &written,
              sizeof written);
    CHECK_BAD(hf_shader_source(0, NULL, 100, &written), HF_ERR_NULL_POINTER, &written,
              sizeof written);
    CHECK_BAD(hf_shader_source(0, buf, sizeof buf, NULL), HF_ERR_NULL_POINTER, buf, sizeof buf);
}

/* The source `fn(lang)` of a GPU bake (`len_fn` its size query), checked for its
 * length, NUL and the strings of `want` (NULL-terminated). */
static void check_bake_source(hf_result (*len_fn)(uint32_t, size_t *),
                              hf_result (*fn)(uint32_t, char *, size_t, size_t *), uint32_t lang,
                              const char *const *want) {
    size_t len = 0, written = 0;
    CHECK_OK(len_fn(lang, &len));
    char *src = (char *)malloc(len);
    CHECK_OK(fn(lang, src, len, &written));
    CHECK(written == len - 1 && strlen(src) == written);
    for (; *want; want++) CHECK(strstr(src, *want) != NULL);
    free(src);
    CHECK_BAD(len_fn(9, &len), HF_ERR_INVALID_ENUM, &len, sizeof len);
    char buf[16] = {0};
    CHECK_BAD(fn(lang, buf, sizeof buf, &written), HF_ERR_BUFFER_TOO_SMALL, buf, sizeof buf);
}

/* The GPU maximum-mipmap bake's shader and passes: a pass per level, in the layout of
 * hf_maxmip_levels; an update's passes cover the texels the edit touches only; the
 * WGSL source and the GLSL compute shader have the entry point and bindings; bad
 * inputs write nothing. */
static void test_gpu_bake(void) {
    const char *wgsl[] = {"fn maxmip_bake_pass(",
                          "@binding(13) var<storage, read_write> hf_pyramid_out",
                          "@binding(14) var<uniform> hf_maxmip_pass", NULL};
    const char *glsl[] = {"#version 430 core", "void main()",
                          "layout(std430, binding = 13) buffer", "layout(std140, binding = 14) uniform",
                          NULL};
    check_bake_source(hf_maxmip_bake_shader_len, hf_maxmip_bake_shader, HF_SHADER_WGSL, wgsl);
    check_bake_source(hf_maxmip_bake_shader_len, hf_maxmip_bake_shader, HF_SHADER_GLSL, glsl);

    hf_level levels[HF_MAX_LEVELS];
    hf_maxmip_pass passes[HF_MAX_LEVELS];
    uint32_t nl = 0, np = 0;
    CHECK_OK(hf_maxmip_levels(13, 6, levels, HF_MAX_LEVELS, &nl));
    CHECK_OK(hf_maxmip_bake_passes(13, 6, NULL, passes, HF_MAX_LEVELS, &np));
    CHECK(np == nl);
    for (uint32_t l = 0; l < np; l++) {
        const uint32_t *u = passes[l].uniform;
        CHECK(passes[l].level == l && u[0] == l && u[1] == levels[l].offset &&
              u[2] == levels[l].width);
        CHECK(u[6] == 0 && u[7] == 0 && u[8] == levels[l].width && u[9] == levels[l].height);
        CHECK(passes[l].workgroups[0] == (levels[l].width + 7) / 8 &&
              passes[l].workgroups[1] == (levels[l].height + 7) / 8);
        CHECK(l == 0 || (u[3] == levels[l - 1].offset && u[4] == levels[l - 1].width &&
                         u[5] == levels[l - 1].height));
    }
    /* Sample (4, 2) is a corner of cells 3..5 x 1..3 of level 0. */
    const uint32_t rect[4] = {4, 2, 5, 3};
    CHECK_OK(hf_maxmip_bake_passes(13, 6, rect, passes, HF_MAX_LEVELS, &np));
    CHECK(np == nl && passes[0].uniform[6] == 3 && passes[0].uniform[7] == 1 &&
          passes[0].uniform[8] == 5 && passes[0].uniform[9] == 3);
    const uint32_t empty[4] = {4, 2, 4, 3};
    CHECK_OK(hf_maxmip_bake_passes(13, 6, empty, passes, HF_MAX_LEVELS, &np));
    CHECK(np == 0);

    hf_maxmip_pass keep[HF_MAX_LEVELS];
    memset(keep, 0xAB, sizeof keep);
    np = 77;
    const uint32_t outside[4] = {4, 2, 14, 3};
    CHECK_BAD(hf_maxmip_bake_passes(13, 6, outside, keep, HF_MAX_LEVELS, &np), HF_ERR_INVALID_RECT,
              keep, sizeof keep);
    CHECK(np == 77);
    CHECK_BAD(hf_maxmip_bake_passes(13, 6, NULL, keep, 2, &np), HF_ERR_BUFFER_TOO_SMALL, keep,
              sizeof keep);
    CHECK_BAD(hf_maxmip_bake_passes(1, 6, NULL, keep, HF_MAX_LEVELS, &np), HF_ERR_INVALID_SIZE,
              keep, sizeof keep);
    /* A valid field, but a pyramid of 2^32 texels or more: the shader's offsets are 32-bit. */
    CHECK_BAD(hf_maxmip_bake_passes(65536, 65536, NULL, keep, HF_MAX_LEVELS, &np),
              HF_ERR_INVALID_SIZE, keep, sizeof keep);
    CHECK_BAD(hf_maxmip_bake_passes(13, 6, NULL, NULL, HF_MAX_LEVELS, &np), HF_ERR_NULL_POINTER,
              &np, sizeof np);
    CHECK_BAD(hf_maxmip_bake_passes(13, 6, NULL, keep, HF_MAX_LEVELS, NULL), HF_ERR_NULL_POINTER,
              keep, sizeof keep);
}

/* The GPU N-buffer bake's shader, passes and size: the passes write every float of
 * hf_nbuffer_len once, each binding an aligned range that holds what it reads and
 * writes; the size is the end of hf_bake_prepare's scratch for HF_METHOD_CC; bad
 * inputs write nothing. */
static void test_gpu_nbuffer_bake(void) {
    const char *wgsl[] = {"fn nbuffer_bake_pass(",
                          "@binding(15) var<storage, read_write> hf_nbuffer",
                          "@binding(16) var<uniform> hf_nbuffer_pass", NULL};
    const char *glsl[] = {"#version 430 core", "void main()",
                          "layout(std430, binding = 15) buffer", "layout(std140, binding = 16) uniform",
                          NULL};
    check_bake_source(hf_nbuffer_bake_shader_len, hf_nbuffer_bake_shader, HF_SHADER_WGSL, wgsl);
    check_bake_source(hf_nbuffer_bake_shader_len, hf_nbuffer_bake_shader, HF_SHADER_GLSL, glsl);

    size_t len = 0, written = 0;
    CHECK_OK(hf_nbuffer_len(37, 19, 64, &len));
    hf_bake_pass passes[HF_NBUFFER_MAX_PASSES];
    uint32_t n = 0;
    CHECK_OK(hf_nbuffer_bake_passes(37, 19, 64, passes, HF_NBUFFER_MAX_PASSES, &n));
    CHECK(n > 4 && n <= HF_NBUFFER_MAX_PASSES);
    for (uint32_t p = 0; p < n; p++) {
        const uint32_t *u = passes[p].uniform; /* kind, axis, rows, row_len, dst, src, .. */
        written += (size_t)u[2] * u[3];
        CHECK(u[0] <= 2 && u[1] <= 1 && passes[p].bind_offset % 256 == 0);
        CHECK(passes[p].bind_offset + passes[p].bind_size <= 4 * (uint64_t)len);
        CHECK(4 * ((uint64_t)u[4] + (uint64_t)u[2] * u[3]) == passes[p].bind_size);
        CHECK(passes[p].workgroups[0] == (u[3] + 7) / 8 && passes[p].workgroups[1] == (u[2] + 7) / 8);
    }
    CHECK(written == len);
    /* The N-buffers are the last floats of the cylinder-cone bake's scratch. */
    hf_bake_options o;
    CHECK_OK(hf_bake_options_default(HF_METHOD_CC, &o));
    o.cap = 64;
    size_t scratch_len = 0;
    CHECK_OK(hf_bake_scratch_len(HF_METHOD_CC, 37, 19, &o, &scratch_len));
    CHECK(scratch_len > len);

    hf_bake_pass keep[HF_NBUFFER_MAX_PASSES];
    memset(keep, 0xAB, sizeof keep);
    n = 77;
    CHECK_BAD(hf_nbuffer_bake_passes(37, 19, 256, keep, HF_NBUFFER_MAX_PASSES, &n),
              HF_ERR_INVALID_ARGUMENT, keep, sizeof keep);
    CHECK(n == 77);
    CHECK_BAD(hf_nbuffer_bake_passes(37, 19, 64, keep, 2, &n), HF_ERR_BUFFER_TOO_SMALL, keep,
              sizeof keep);
    CHECK_BAD(hf_nbuffer_bake_passes(1, 19, 64, keep, HF_NBUFFER_MAX_PASSES, &n),
              HF_ERR_INVALID_SIZE, keep, sizeof keep);
    /* A valid field, but N-buffers of 2^32 floats or more: the shader's offsets are 32-bit. */
    CHECK_BAD(hf_nbuffer_bake_passes(20000, 20000, 255, keep, HF_NBUFFER_MAX_PASSES, &n),
              HF_ERR_INVALID_SIZE, keep, sizeof keep);
    CHECK_BAD(hf_nbuffer_bake_passes(37, 19, 64, NULL, HF_NBUFFER_MAX_PASSES, &n),
              HF_ERR_NULL_POINTER, &n, sizeof n);
    CHECK_BAD(hf_nbuffer_bake_passes(37, 19, 64, keep, HF_NBUFFER_MAX_PASSES, NULL),
              HF_ERR_NULL_POINTER, keep, sizeof keep);
    size_t keep_len = 5;
    CHECK_BAD(hf_nbuffer_len(37, 19, 300, &keep_len), HF_ERR_INVALID_ARGUMENT, &keep_len,
              sizeof keep_len);
    CHECK_BAD(hf_nbuffer_len(37, 1, 64, &keep_len), HF_ERR_INVALID_SIZE, &keep_len,
              sizeof keep_len);
    CHECK_BAD(hf_nbuffer_len(37, 19, 64, NULL), HF_ERR_NULL_POINTER, &written, 0);
}

/* The GPU safety-distance bake's shader and passes: two passes over the strip slots
 * and the map's words; options as hf_bake checks them, every ray and class only; bad
 * inputs write nothing. */
static void test_gpu_safety_bake(void) {
    const char *wgsl[] = {"fn safety_bake_pass(", "f64",
                          "@binding(17) var<storage, read_write> hf_safety_scratch",
                          "@binding(18) var<storage, read_write> hf_safety_out",
                          "@binding(19) var<uniform> hf_safety_pass", NULL};
    const char *glsl[] = {"#version 430 core", "void main()", "double",
                          "layout(std430, binding = 17) buffer", "layout(std430, binding = 18) buffer",
                          "layout(std140, binding = 19) uniform", NULL};
    check_bake_source(hf_safety_bake_shader_len, hf_safety_bake_shader, HF_SHADER_WGSL, wgsl);
    check_bake_source(hf_safety_bake_shader_len, hf_safety_bake_shader, HF_SHADER_GLSL, glsl);

    hf_bake_pass passes[2];
    uint32_t n = 0;
    CHECK_OK(hf_safety_bake_passes(37, 19, NULL, passes, 2, &n));
    CHECK(n == 2 && passes[0].uniform[0] == 0 && passes[1].uniform[0] == 1);
    size_t scratch_len = 0, map_len = 0;
    CHECK_OK(hf_bake_scratch_len(HF_METHOD_SAFETY, 37, 19, NULL, &scratch_len));
    CHECK_OK(hf_map_len(HF_METHOD_SAFETY, 37, 19, NULL, &map_len));
    /* The scratch whole, then the map's texels rounded up to words. */
    CHECK(passes[0].bind_size == 4 * scratch_len);
    CHECK(passes[1].bind_size == (map_len - HF_MAP_DESC_BYTES + 3) / 4 * 4);
    for (int p = 0; p < 2; p++) {
        uint64_t invocations = 64ull * passes[p].workgroups[0] * passes[p].workgroups[1];
        CHECK(invocations >= passes[p].uniform[6]);
    }
    hf_bake_options o;
    CHECK_OK(hf_bake_options_default(HF_METHOD_SAFETY, &o));
    o.variant = HF_SAFETY_ISOTROPIC;
    o.positive = 1;
    o.cap = 9;
    CHECK_OK(hf_safety_bake_passes(37, 19, &o, passes, 2, &n));
    CHECK(passes[1].uniform[3] == 1 && passes[1].uniform[4] == 9 && passes[1].uniform[5] == 1);

    hf_bake_pass keep[2];
    memset(keep, 0xAB, sizeof keep);
    n = 77;
    o.exterior = 1; /* a ray set: bake it with hf_bake */
    CHECK_BAD(hf_safety_bake_passes(37, 19, &o, keep, 2, &n), HF_ERR_INVALID_ARGUMENT, keep,
              sizeof keep);
    o.exterior = 0;
    o.ray_classes = HF_RAYS_X_POS;
    CHECK_BAD(hf_safety_bake_passes(37, 19, &o, keep, 2, &n), HF_ERR_INVALID_ARGUMENT, keep,
              sizeof keep);
    o.ray_classes = 0;
    o.cap = 256;
    CHECK_BAD(hf_safety_bake_passes(37, 19, &o, keep, 2, &n), HF_ERR_INVALID_ARGUMENT, keep,
              sizeof keep);
    o.cap = 9;
    CHECK_BAD(hf_safety_bake_passes(37, 19, &o, keep, 1, &n), HF_ERR_BUFFER_TOO_SMALL, keep,
              sizeof keep);
    CHECK_BAD(hf_safety_bake_passes(1, 19, &o, keep, 2, &n), HF_ERR_INVALID_SIZE, keep,
              sizeof keep);
    CHECK_BAD(hf_safety_bake_passes(37, 19, &o, NULL, 2, &n), HF_ERR_NULL_POINTER, &n, sizeof n);
    CHECK_BAD(hf_safety_bake_passes(37, 19, &o, keep, 2, NULL), HF_ERR_NULL_POINTER, keep,
              sizeof keep);
    CHECK(n == 77);

    /* The cylinder-cone bake: the same shader with the entry cc_bake_pass, N-buffer
     * slopes only. */
    const char *cc_wgsl[] = {"fn cc_bake_pass(", "@binding(15) var<storage, read> hf_nbuffer", NULL};
    const char *cc_glsl[] = {"#version 430 core\n#define HF_CC_BAKE 1\n", "readonly buffer", NULL};
    check_bake_source(hf_cc_bake_shader_len, hf_cc_bake_shader, HF_SHADER_WGSL, cc_wgsl);
    check_bake_source(hf_cc_bake_shader_len, hf_cc_bake_shader, HF_SHADER_GLSL, cc_glsl);
    hf_bake_options cc;
    CHECK_OK(hf_bake_options_default(HF_METHOD_CC, &cc));
    /* The default slope is exact: not this bake's. */
    CHECK_BAD(hf_cc_bake_passes(37, 19, &cc, keep, 2, &n), HF_ERR_INVALID_ARGUMENT, keep,
              sizeof keep);
    CHECK_BAD(hf_cc_bake_passes(37, 19, NULL, keep, 2, &n), HF_ERR_INVALID_ARGUMENT, keep,
              sizeof keep);
    cc.slope = HF_CC_SLOPE_NBUFFER;
    cc.cap = 64;
    CHECK_OK(hf_cc_bake_passes(37, 19, &cc, passes, 2, &n));
    size_t cc_len = 0;
    CHECK_OK(hf_map_len(HF_METHOD_CC, 37, 19, &cc, &cc_len));
    CHECK(n == 2 && passes[1].uniform[0] == 2 && passes[1].uniform[4] == 64);
    CHECK(passes[1].bind_size == cc_len - HF_MAP_DESC_BYTES);
    cc.max_view_angle_deg = 60.0f;
    CHECK_BAD(hf_cc_bake_passes(37, 19, &cc, keep, 2, &n), HF_ERR_INVALID_ARGUMENT, keep,
              sizeof keep);
    cc.max_view_angle_deg = 0.0f;
    CHECK_BAD(hf_cc_bake_passes(37, 19, &cc, keep, 1, &n), HF_ERR_BUFFER_TOO_SMALL, keep,
              sizeof keep);
    CHECK_BAD(hf_cc_bake_shader_len(7, &cc_len), HF_ERR_INVALID_ENUM, &cc_len, sizeof cc_len);
}

/* hf_hybrid_trace_batch: the hybrid renderer's passes on the CPU answer as the exact
 * method on the view-linear surface, on random rays (vertical and axis-parallel ones,
 * origins under the surface included), in grid and world units; bad inputs are refused
 * and write nothing. */
static void test_hybrid(void) {
    enum { W = 29, H = 21, N = 1500 };
    float heights[W * H];
    for (int k = 0; k < W * H; k++) heights[k] = 6.0f * frand();
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, W * H, W, H, W, &f));
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * N);
    for (int k = 0; k < N; k++) {
        rays[k] = ray(-4.0f + (W + 8) * frand(), -4.0f + (H + 8) * frand(), 9.0f * frand(),
                      frand() - 0.5f, frand() - 0.5f, frand() - 0.7f);
        if (k % 10 == 0) rays[k].dir[1] = 0.0f;
        if (k % 13 == 0) rays[k].dir[0] = rays[k].dir[1] = 0.0f;
    }
    hf_hit *exact = (hf_hit *)malloc(sizeof(hf_hit) * N);
    hf_hit *hy = (hf_hit *)malloc(sizeof(hf_hit) * N);
    hf_trace_options o = on(HF_SURFACE_VIEW_LINEAR);
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &o, rays, N, exact, N));
    CHECK_OK(hf_hybrid_trace_batch(f, rays, N, hy, N));
    int same = agreeing(exact, hy, N), hits = 0;
    for (int k = 0; k < N; k++) hits += exact[k].hit;
    CHECK(same >= N - 2 && hits > N / 4);
    /* Bad inputs: NULLs, a short output, a bad ray (first reported), overlap. */
    hf_hit h[4];
    memset(h, 0x5A, sizeof h);
    CHECK_BAD(hf_hybrid_trace_batch(NULL, rays, 4, h, 4), HF_ERR_NULL_POINTER, h, sizeof h);
    CHECK_BAD(hf_hybrid_trace_batch(f, NULL, 4, h, 4), HF_ERR_NULL_POINTER, h, sizeof h);
    CHECK_BAD(hf_hybrid_trace_batch(f, rays, 4, NULL, 4), HF_ERR_NULL_POINTER, nothing, 0);
    CHECK_BAD(hf_hybrid_trace_batch(f, rays, 4, h, 3), HF_ERR_BUFFER_TOO_SMALL, h, sizeof h);
    hf_ray bad[4] = {rays[0], rays[1], rays[2], rays[3]};
    bad[2].dir[0] = NAN;
    CHECK_BAD(hf_hybrid_trace_batch(f, bad, 4, h, 4), HF_ERR_INVALID_RAY, h, sizeof h);
    size_t at = 0;
    CHECK(hf_last_error_index(&at) == HF_OK && at == 2);
    CHECK_BAD(hf_hybrid_trace_batch(f, bad, 4, (hf_hit *)(void *)bad, 4),
              HF_ERR_INVALID_ARGUMENT, bad, sizeof bad);
    printf("hybrid on the cpu: %d of %d rays as the exact method on the view-linear surface, "
           "%d hits\n",
           same, N, hits);
    free(rays);
    free(exact);
    free(hy);
    hf_field_destroy(f);
}

int main(void) {
    test_version_and_messages();
    test_field_constructors();
    test_known_hits();
    test_bad_queries();
    test_methods_agree();
    test_hybrid();
    test_world_units();
    test_projective();
    test_impostor();
    test_bake_and_update();
    test_safety();
    test_radius();
    test_cones();
    test_cc();
    test_trace_options();
    test_concurrent_rows();
    test_bake_defaults();
    test_build_and_plan();
    test_shader_source();
    test_gpu_bake();
    test_gpu_nbuffer_bake();
    test_gpu_safety_bake();
    printf("c api: %d checks, %d bad inputs tried\n", checks, bad_inputs);
    printf("c-api: %d passed, %d failed\n", checks - failures, failures);
    return failures == 0 ? 0 : 1;
}
