/* What the libFuzzer targets of libhfcast share (fuzz_field.c, fuzz_bake.c,
 * fuzz_trace.c; built and run by scripts/fuzz.sh): a byte reader that turns the
 * fuzzer's input into sizes, heights, options and rays; the checks every call gets
 * (a code `hf_error_message` knows, never `HF_ERR_PANIC`, a failing call leaves its
 * outputs untouched); and the comparison of a method's hits with the exact method's
 * (`hf_trace` with `HF_METHOD_EXACT`).
 * A violation prints what was wrong and calls abort(), which libFuzzer reports as a
 * crash with the input that caused it. */
#ifndef HFCAST_FUZZ_COMMON_H
#define HFCAST_FUZZ_COMMON_H

#include "hfcast.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Sizes kept small so that one input runs in milliseconds. */
#define FZ_MAX_SIDE 48
#define FZ_MAX_RAYS 64
/* The byte every output buffer is filled with before a call, and the guard zone
 * after it: a failing call must leave all of it, a succeeding one the guard. */
#define FZ_POISON 0xA5
#define FZ_GUARD 64

#define FZ_FAIL(...)                                                          \
    do {                                                                      \
        fprintf(stderr, "fuzz violation at %s:%d: ", __FILE__, __LINE__);     \
        fprintf(stderr, __VA_ARGS__);                                         \
        fputc('\n', stderr);                                                  \
        abort();                                                              \
    } while (0)

/* ---- reading the input ---------------------------------------------------- */

typedef struct fz_in {
    const uint8_t *p;
    size_t n;
} fz_in;

/* Past the end every read gives 0: short inputs are still whole cases. */
static inline uint8_t fz_u8(fz_in *in) {
    if (in->n == 0) return 0;
    in->n--;
    return *in->p++;
}

static inline uint32_t fz_u16(fz_in *in) {
    uint32_t v = fz_u8(in);
    return v | (uint32_t)fz_u8(in) << 8;
}

static inline uint32_t fz_u32(fz_in *in) {
    uint32_t v = fz_u16(in);
    return v | fz_u16(in) << 16;
}

/* Any bit pattern, NaN and infinities included. */
static inline float fz_raw_float(fz_in *in) {
    uint32_t bits = fz_u32(in);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* In [lo, hi], 65536 steps. */
static inline float fz_range(fz_in *in, float lo, float hi) {
    return lo + (hi - lo) * (float)fz_u16(in) / 65535.0f;
}

/* ---- checks ------------------------------------------------------------------- */

/* Every returned code is one `hf_error_message` knows; a panic is always a bug. */
static inline hf_result fz_code(hf_result r, const char *what) {
    char buf[256];
    size_t written = 0;
    if (hf_error_message((uint32_t)r, buf, sizeof buf, &written) != HF_OK)
        FZ_FAIL("%s returned %u, not a valid hf_result", what, (unsigned)r);
    if (r == HF_ERR_PANIC) FZ_FAIL("%s returned HF_ERR_PANIC", what);
    return r;
}

/* An output buffer of `len` bytes (may be 0) with a guard zone after it. */
static inline void *fz_buf(size_t len) {
    unsigned char *b = (unsigned char *)malloc(len + FZ_GUARD);
    if (!b) FZ_FAIL("out of memory (%zu bytes)", len);
    memset(b, FZ_POISON, len + FZ_GUARD);
    return b;
}

static inline int fz_all_poison(const void *p, size_t len) {
    const unsigned char *b = (const unsigned char *)p;
    for (size_t k = 0; k < len; k++)
        if (b[k] != FZ_POISON) return 0;
    return 1;
}

/* After a call that wrote into `buf` (`len` bytes, from fz_buf): on error nothing
 * touched, on success the guard zone intact. */
static inline void fz_after(hf_result r, const void *buf, size_t len, const char *what) {
    fz_code(r, what);
    if (r != HF_OK && !fz_all_poison(buf, len + FZ_GUARD))
        FZ_FAIL("%s failed with %u but wrote its output", what, (unsigned)r);
    if (r == HF_OK && !fz_all_poison((const unsigned char *)buf + len, FZ_GUARD))
        FZ_FAIL("%s wrote past the end of its %zu-byte output", what, len);
}

/* ---- fields ------------------------------------------------------------------- */

/* Heights of a w × h field (row-major, stride w) from the input: one of a few
 * shapes (noise, terraces with vertical walls, flat, ridges, spikes), quantised to
 * quarter units half of the time so that rays meet vertices and edges exactly. */
static inline void fz_heights(fz_in *in, uint32_t w, uint32_t h, float *out) {
    uint8_t mode = fz_u8(in);
    float scale = (float)(fz_u8(in) % 41);
    int quantise = mode & 8;
    for (uint32_t j = 0; j < h; j++)
        for (uint32_t i = 0; i < w; i++) {
            float v;
            switch (mode % 5) {
            case 0: v = scale * (float)fz_u8(in) / 255.0f; break;
            case 1: v = (float)((fz_u8(in) % 4) * (int)(scale / 4.0f + 1.0f)); break;
            case 2: v = scale * 0.5f; break;
            case 3: v = scale * (0.5f + 0.5f * sinf(0.7f * (float)i + 0.3f * (float)j)); break;
            default: v = (fz_u8(in) > 230) ? scale : 0.0f; break;
            }
            if (quantise) v = floorf(v * 4.0f) / 4.0f;
            out[j * w + i] = v;
        }
}

/* A field of 2..FZ_MAX_SIDE samples a side; NULL when creation fails (it must
 * not: the heights are finite and the sizes valid). */
static inline hf_field *fz_field(fz_in *in, uint32_t max_side, uint32_t *out_w, uint32_t *out_h,
                          float *heights) {
    uint32_t w = 2 + fz_u8(in) % (max_side - 1), h = 2 + fz_u8(in) % (max_side - 1);
    fz_heights(in, w, h, heights);
    hf_field *f = NULL;
    hf_result r = fz_code(hf_field_create_f32(heights, (size_t)w * h, w, h, w, &f),
                          "hf_field_create_f32");
    if (r != HF_OK) FZ_FAIL("a valid %ux%u field was refused with %u", w, h, (unsigned)r);
    *out_w = w;
    *out_h = h;
    return f;
}

/* ---- rays ------------------------------------------------------------------- */

/* One direction or origin component: zero, a lattice value, or any in range. */
static inline float fz_component(fz_in *in, float lo, float hi) {
    uint8_t k = fz_u8(in);
    switch (k % 8) {
    case 0: return 0.0f;
    case 1: return floorf(fz_range(in, lo, hi));
    case 2: return floorf(fz_range(in, lo, hi) * 2.0f) / 2.0f;
    default: return fz_range(in, lo, hi);
    }
}

/* A ray over a w × h field. `*raw` is set when its bits came straight from the
 * input (NaN, infinities, zero directions, reversed ranges: for the error paths),
 * else the ray is valid: finite origin near the field, non-zero finite direction,
 * t range ordered. */
static inline hf_ray fz_ray(fz_in *in, uint32_t w, uint32_t h, int *raw) {
    hf_ray r;
    uint8_t mode = fz_u8(in);
    *raw = (mode % 32) == 31;
    if (*raw) {
        for (int k = 0; k < 3; k++) r.origin[k] = fz_raw_float(in);
        for (int k = 0; k < 3; k++) r.dir[k] = fz_raw_float(in);
        r.t_min = fz_raw_float(in);
        r.t_max = fz_raw_float(in);
        return r;
    }
    r.origin[0] = fz_component(in, -(float)w, 2.0f * (float)w);
    r.origin[1] = fz_component(in, -(float)h, 2.0f * (float)h);
    r.origin[2] = fz_component(in, -5.0f, 60.0f);
    r.dir[0] = fz_component(in, -1.0f, 1.0f);
    r.dir[1] = fz_component(in, -1.0f, 1.0f);
    /* Mostly downwards (primary rays), some upwards (shadow rays), some flat. */
    r.dir[2] = (mode & 3) == 0 ? fz_component(in, -0.2f, 1.0f) : fz_component(in, -1.0f, 0.05f);
    if (r.dir[0] == 0.0f && r.dir[1] == 0.0f && r.dir[2] == 0.0f) r.dir[2] = -1.0f;
    r.t_min = (mode & 4) ? fz_range(in, -5.0f, 20.0f) : 0.0f;
    r.t_max = (mode & 8) ? r.t_min + fz_range(in, 0.0f, 200.0f) : INFINITY;
    return r;
}

/* ---- agreement with the exact method ------------------------------------------ */

static inline int fz_near(float a, float b) { return fabsf(a - b) <= 1e-3f * (1.0f + fabsf(a)); }

/* test_api.c's agreement: same hit or miss, hit points within 1e-3. */
static inline int fz_agree(const hf_hit *want, const hf_hit *got) {
    if (want->hit != got->hit) return 0;
    return !want->hit || (fz_near(want->point[0], got->point[0]) &&
                          fz_near(want->point[1], got->point[1]) &&
                          fz_near(want->point[2], got->point[2]));
}

/* Maximum mipmaps answer as the exact method bit for bit (test_api.c). */
static inline int fz_identical(const hf_hit *want, const hf_hit *got) {
    return want->hit == got->hit && want->flags == got->flags &&
           memcmp(&want->t, &got->t, sizeof want->t) == 0 &&
           memcmp(want->point, got->point, sizeof want->point) == 0;
}

/* The default trace options with surface `surface`. */
static inline hf_trace_options fz_on(uint32_t surface) {
    hf_trace_options o;
    hf_trace_options_default(&o);
    o.surface = surface;
    return o;
}

/* docs/DESIGN.md's ambiguity rule (core/src/judge.rs), on the exact method's answers:
 * a ray is stable when moving its origin by its f32 resolution
 * delta = 2 eps32 (|o|inf + E), E = max(W - 1, H - 1, |min height|, |max height|), along
 * each axis, either way, keeps the answer: the same hit or miss, and a hit within
 * fz_agree's 1e-3 (relative) plus 2 delta (1 + 1/|n . d|), how far a hit slides when
 * the ray moves by delta. Only stable rays must agree; touches, near-touches and
 * clipped ridges are ambiguous. */
static inline int fz_stable(const hf_field *f, uint32_t surface, const hf_ray *ray,
                     const hf_hit *exact) {
    hf_field_info info;
    if (hf_field_get_info(f, &info) != HF_OK) return 0;
    double o = 0.0, extent = (double)(info.width > info.height ? info.width : info.height) - 1.0;
    for (int k = 0; k < 3; k++) o = fmax(o, fabs((double)ray->origin[k]));
    extent = fmax(extent, fmax(fabs((double)info.min_height), fabs((double)info.max_height)));
    double delta = 2.0 * FLT_EPSILON * (o + extent);
    double len = sqrt((double)ray->dir[0] * ray->dir[0] + (double)ray->dir[1] * ray->dir[1] +
                      (double)ray->dir[2] * ray->dir[2]);
    double cosine = exact->hit ? fabs((double)exact->normal[0] * ray->dir[0] +
                                      (double)exact->normal[1] * ray->dir[1] +
                                      (double)exact->normal[2] * ray->dir[2]) / len
                               : 1.0;
    double slide = 2.0 * delta * (1.0 + 1.0 / fmax(cosine, 1e-3));
    hf_trace_options on = fz_on(surface);
    for (int k = 0; k < 6; k++) {
        hf_ray moved = *ray;
        moved.origin[k / 2] = (float)((double)ray->origin[k / 2] + (k % 2 ? -delta : delta));
        hf_hit h;
        if (hf_trace(f, HF_METHOD_EXACT, NULL, 0, &on, &moved, &h) != HF_OK) return 0;
        if (exact->hit != h.hit) return 0;
        for (int a = 0; exact->hit && a < 3; a++) {
            double e = fabs((double)exact->point[a] - h.point[a]);
            if (e > 1e-3 * (1.0 + fabs((double)exact->point[a])) + slide) return 0;
        }
    }
    return 1;
}

static inline void fz_print_ray(const hf_ray *r) {
    fprintf(stderr, "ray origin (%.9g, %.9g, %.9g) dir (%.9g, %.9g, %.9g) t [%.9g, %.9g]\n",
            r->origin[0], r->origin[1], r->origin[2], r->dir[0], r->dir[1], r->dir[2],
            r->t_min, r->t_max);
}

static inline void fz_print_hit(const char *who, const hf_hit *h) {
    fprintf(stderr, "%s: hit %u flags %u t %.9g point (%.9g, %.9g, %.9g)\n", who, h->hit,
            h->flags, h->t, h->point[0], h->point[1], h->point[2]);
}

/* Checks `got[k]` (from method `what`) against the exact answers on the same rays:
 * `identical` demands fz_identical on every ray, else fz_agree on the stable ones;
 * hits flagged HF_FLAG_BUDGET_EXHAUSTED (cone, QDM out of iterations) are skipped. */
/* The field's size and heights, to rebuild a finding outside the fuzzer. */
static inline void fz_print_field(const hf_field *f) {
    hf_field_info info;
    if (hf_field_get_info(f, &info) != HF_OK) return;
    size_t n = (size_t)info.width * info.height;
    float *h = (float *)malloc(n * sizeof *h);
    if (h && hf_field_copy_heights(f, h, n) == HF_OK) {
        fprintf(stderr, "field %u x %u:", (unsigned)info.width, (unsigned)info.height);
        for (size_t k = 0; k < n; k++) fprintf(stderr, " %.9g", (double)h[k]);
        fprintf(stderr, "\n");
    }
    free(h);
}

/* Largest |height| whose fields the answers are compared on by default. Beyond it the
 * triangle surface's plane evaluation cancels catastrophically in float (a cell with a
 * -1.7e38 sample puts a side wall where there is none: fuzz/findings/, the extremes
 * issue); FZ_EXTREME=1 compares every field. Calls on such fields are still fuzzed for
 * their return codes, outputs and sanitizer reports. */
#define FZ_COMPARED_HEIGHT 1e6f

/* 1 when the answers on `f` are compared (see FZ_COMPARED_HEIGHT). */
static inline int fz_compared(const hf_field *f) {
    hf_field_info info;
    if (hf_field_get_info(f, &info) != HF_OK) return 0;
    int moderate = fabsf(info.min_height) <= FZ_COMPARED_HEIGHT &&
                   fabsf(info.max_height) <= FZ_COMPARED_HEIGHT;
    return moderate || getenv("FZ_EXTREME") != NULL;
}

static inline void fz_compare(const hf_field *f, uint32_t surface, const hf_ray *rays, int n,
                       const hf_hit *exact, const hf_hit *got, int identical,
                       const char *what) {
    if (!fz_compared(f)) return;
    for (int k = 0; k < n; k++) {
        if (identical) {
            /* Bit for bit on stable rays; unstable ones (a flat ray exactly at a
             * height level: fuzz/findings/) are reported by FZ_STRICT=1 only. */
            if (fz_identical(&exact[k], &got[k])) continue;
            if (!getenv("FZ_STRICT") && !fz_stable(f, surface, &rays[k], &exact[k])) continue;
        } else {
            if ((got[k].flags & HF_FLAG_BUDGET_EXHAUSTED) || fz_agree(&exact[k], &got[k]))
                continue;
            if (!fz_stable(f, surface, &rays[k], &exact[k])) continue;
        }
        fz_print_ray(&rays[k]);
        fz_print_hit("exact", &exact[k]);
        fz_print_hit(what, &got[k]);
        fz_print_field(f);
        FZ_FAIL("%s disagrees with the exact method on surface %u, ray %d", what,
                (unsigned)surface, k);
    }
}

#endif
