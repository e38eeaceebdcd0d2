/* Issue 26, item 1: maps that know what they belong to. Every bake writes a descriptor
 * (HF_MAP_DESC_BYTES after the texels: the map, the field's size, cap, ray classes,
 * ray set and the fingerprint of the heights) and every trace checks it:
 *  - a map of another field of the same size: HF_ERR_MAP_MISMATCH (before: HF_OK and
 *    wrong answers, e.g. 140 of 2,000 rays for the pyramid);
 *  - a map of the heights before an update: HF_ERR_STALE_MAP (before: stale answers);
 *  - a wrong class set or layout, another method's map, a damaged descriptor:
 *    HF_ERR_MAP_MISMATCH;
 *  - hf_maxmip_update_rect refreshes only over a rectangle covering every update
 *    since the bake, and then equals a fresh bake byte for byte;
 *  - KTX2 files keep the fingerprint, so a map read back traces again.
 * Every refused call writes nothing. Prints `c-maps: N passed, M failed`. */
#include "hfcast.h"
#include "check_api.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { W = 37, H = 29, N = 500, CAP = 32 };

static uint32_t seed = 12345u;
static float frand(void) {
    seed = seed * 1664525u + 1013904223u;
    return (float)(seed >> 8) / 16777216.0f;
}

static char detail[256];

/* Checks that the detail of the last failing call contains `part`. */
#define CHECK_DETAIL(part)                                                         \
    do {                                                                           \
        size_t w_ = 0;                                                             \
        checks++;                                                                  \
        if (hf_last_error_detail(detail, sizeof detail, &w_) != HF_OK ||           \
            !strstr(detail, (part))) {                                             \
            failures++;                                                            \
            fprintf(stderr, "%s:%d: detail \"%s\" lacks \"%s\"\n", __FILE__,       \
                    __LINE__, detail, (part));                                     \
        }                                                                          \
    } while (0)

/* Every baked map of one field. */
typedef struct {
    float *pyr, *cone, *qdm, *relaxed;
    size_t pyr_len, cone_len, qdm_len, relaxed_len;
    uint8_t *sd, *si, *cc, *rad;
    size_t sd_len, si_len, cc_len, rad_len;
} maps;

static const uint32_t CLASSES = HF_RAYS_X_POS | HF_RAYS_Y_NEG;

/* `method`'s map of `f` baked with `o`, in a new buffer of hf_map_len elements (*len;
 * floats, or bytes for the safety-distance, cylinder-cone and radius maps). */
static void *bake_map(const hf_field *f, uint32_t method, const hf_bake_options *o, size_t *len) {
    int bytes = method == HF_METHOD_SAFETY || method == HF_METHOD_CC || method == HF_METHOD_RADIUS;
    CHECK_OK(hf_map_len(method, W, H, o, len));
    void *map = malloc(*len * (bytes ? 1 : sizeof(float)));
    CHECK_OK(hf_bake(method, f, o, map, *len));
    return map;
}

/* Every map on 2 threads: safety distances (both layouts) and radii (tolerance 0) of
 * cap 64, the cylinder-cone shapes of the N-buffer slope, cap CAP and CLASSES. */
static void bake_all(const hf_field *f, maps *m) {
    hf_bake_options o;
    CHECK_OK(hf_bake_options_default(HF_METHOD_SAFETY, &o));
    o.cap = 64;
    o.ray_classes = HF_RAYS_ALL;
    o.threads = 2;
    m->pyr = bake_map(f, HF_METHOD_MAXMIP, &o, &m->pyr_len);
    m->sd = bake_map(f, HF_METHOD_SAFETY, &o, &m->sd_len);
    m->rad = bake_map(f, HF_METHOD_RADIUS, &o, &m->rad_len);
    m->cone = bake_map(f, HF_METHOD_CONE, &o, &m->cone_len);
    m->qdm = bake_map(f, HF_METHOD_QDM, &o, &m->qdm_len);
    m->relaxed = bake_map(f, HF_METHOD_RELAXED, &o, &m->relaxed_len);
    o.variant = HF_SAFETY_ISOTROPIC;
    m->si = bake_map(f, HF_METHOD_SAFETY, &o, &m->si_len);
    o.slope = HF_CC_SLOPE_NBUFFER;
    o.cap = CAP;
    o.ray_classes = CLASSES;
    m->cc = bake_map(f, HF_METHOD_CC, &o, &m->cc_len);
}

static void free_all(maps *m) {
    void *all[] = {m->pyr, m->cone, m->qdm, m->relaxed, m->sd, m->si, m->cc, m->rad};
    for (size_t k = 0; k < sizeof all / sizeof all[0]; k++) free(all[k]);
}

enum { MAXMIP, SAFETY_DIR, SAFETY_ISO, CC, RADIUS, CONE, QDM, RELAXED, METHODS };
static const char *const names[METHODS] = {"maxmip", "safety", "safety-iso", "cc",
                                           "radius", "cone",   "qdm",        "relaxed"};

/* The default trace options naming the ray classes `classes` (0: the map's). */
static hf_trace_options with_classes(uint32_t classes) {
    hf_trace_options o;
    hf_trace_options_default(&o);
    o.ray_classes = classes;
    return o;
}

/* Traces the batch with method m's map of `m` on field f (cone, QDM: 1000 iterations;
 * relaxed: the default 64 cone steps, 8 bisections; cc: the map's classes named). */
static hf_result trace(int method, const hf_field *f, const maps *m, const hf_ray *rays,
                       hf_hit *out) {
    static const uint32_t api[METHODS] = {HF_METHOD_MAXMIP, HF_METHOD_SAFETY, HF_METHOD_SAFETY,
                                          HF_METHOD_CC,     HF_METHOD_RADIUS, HF_METHOD_CONE,
                                          HF_METHOD_QDM,    HF_METHOD_RELAXED};
    const void *map[METHODS] = {m->pyr, m->sd, m->si, m->cc, m->rad, m->cone, m->qdm, m->relaxed};
    const size_t len[METHODS] = {m->pyr_len, m->sd_len,   m->si_len,  m->cc_len,
                                 m->rad_len, m->cone_len, m->qdm_len, m->relaxed_len};
    hf_trace_options o = with_classes(method == CC ? CLASSES : 0);
    if (method == CONE || method == QDM) o.steps = 1000;
    return hf_trace_batch(f, api[method], map[method], len[method], &o, rays, N, out, N);
}

/* Every method answers the batch as the exact DDA on f (hits equal up to 1e-3 in t;
 * relaxed cone stepping is approximate and only has to answer). */
static void check_exact(const hf_field *f, const maps *m, const hf_ray *rays, const char *when) {
    static hf_hit exact[N], got[N];
    CHECK_OK(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, N, exact, N));
    for (int method = 0; method < METHODS; method++) {
        hf_result r = trace(method, f, m, rays, got);
        CHECK(r == HF_OK);
        if (r != HF_OK || method == RELAXED) continue;
        int wrong = 0;
        for (int k = 0; k < N; k++)
            wrong += got[k].hit != exact[k].hit ||
                     (exact[k].hit && (got[k].t - exact[k].t > 1e-3f || exact[k].t - got[k].t > 1e-3f));
        if (wrong) fprintf(stderr, "%s %s: %d of %d rays wrong\n", names[method], when, wrong, N);
        CHECK(wrong == 0);
    }
}

/* Every method refuses its map on f with `code`, writing nothing. */
static void check_refused(const hf_field *f, const maps *m, const hf_ray *rays,
                          hf_result code, const char *part) {
    static hf_hit got[N];
    for (int method = 0; method < METHODS; method++) {
        memset(got, 0x5A, sizeof got);
        CHECK_BAD(trace(method, f, m, rays, got), code, got, sizeof got);
        CHECK_DETAIL(part);
    }
}

/* A field of W x H heights: smooth hills plus noise, and a needle. */
static hf_field *field(float scale, float phase) {
    static float h[W * H];
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++)
            h[j * W + i] = scale * (1.5f + sinf(0.3f * (float)i + phase) * cosf(0.2f * (float)j)) +
                           2.0f * frand();
    h[(H / 2) * W + W / 3] = 14.0f;
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(h, W * H, W, H, W, &f));
    return f;
}

static void check_descriptor_reads(const hf_field *f, const maps *m) {
    hf_map_desc d;
    memset(&d, 0, sizeof d);
    uint64_t fp = 0, generation = 9;
    CHECK_OK(hf_field_get_fingerprint(f, &fp, &generation));
    CHECK(generation == 0);
    CHECK_OK(hf_map_read_desc(m->cc, m->cc_len, &d));
    CHECK(d.map.map == HF_KTX2_CC && d.map.width == W && d.map.height == H);
    CHECK(d.map.cap == CAP && d.map.ray_classes == CLASSES);
    CHECK(d.flags == HF_MAP_FINGERPRINT_KNOWN && d.fingerprint == fp);
    CHECK(d.texel_bytes == m->cc_len - HF_MAP_DESC_BYTES);
    CHECK_OK(hf_map_read_desc(m->pyr, m->pyr_len * 4, &d));
    CHECK(d.map.map == HF_KTX2_MAXMIP && d.fingerprint == fp);
    CHECK_OK(hf_map_read_desc(m->si, m->si_len, &d));
    CHECK(d.map.map == HF_KTX2_SAFETY_ISOTROPIC);
    hf_map_desc keep = d;
    CHECK_BAD(hf_map_read_desc(m->si, m->si_len - 1, &d), HF_ERR_MAP_MISMATCH, &d, sizeof d);
    CHECK_BAD(hf_map_read_desc(m->si, 10, &d), HF_ERR_BUFFER_TOO_SMALL, &d, sizeof d);
    CHECK_BAD(hf_map_read_desc(NULL, 64, &d), HF_ERR_NULL_POINTER, &d, sizeof d);
    CHECK(memcmp(&keep, &d, sizeof d) == 0);
}

/* Wrong arguments for a right map, and maps of the wrong kind. */
static void check_wrong_arguments(const hf_field *f, const maps *m, const hf_ray *rays) {
    static hf_hit got[N];
    const uint32_t cc = HF_METHOD_CC, sm = HF_METHOD_SAFETY, rm = HF_METHOD_RADIUS;
    memset(got, 0x5A, sizeof got);
    /* The cap is no longer passed (a wrong one was HF_ERR_MAP_MISMATCH): the descriptor
     * names it. Another method's map is refused instead: the cc map (as long as a
     * directional safety map) traced as a safety map. */
    CHECK_BAD(hf_trace_batch(f, sm, m->cc, m->cc_len, NULL, rays, N, got, N), HF_ERR_MAP_MISMATCH,
              got, sizeof got);
    CHECK_DETAIL("a cc map, a directional safety map expected");
    /* Another class set: the descriptor is not where that set's texels end. */
    hf_trace_options x_pos = with_classes(HF_RAYS_X_POS);
    CHECK_BAD(hf_trace_batch(f, cc, m->cc, m->cc_len, &x_pos, rays, N, got, N),
              HF_ERR_MAP_MISMATCH, got, sizeof got);
    /* The layout is no longer passed (a directional map named isotropic was refused): the
     * descriptor names it. Either layout of the four classes named as holding two is
     * refused instead; and an isotropic map (W x H bytes) as a radius map (W x H). */
    hf_trace_options two = with_classes(CLASSES);
    CHECK_BAD(hf_trace_batch(f, sm, m->sd, m->sd_len, &two, rays, N, got, N),
              HF_ERR_MAP_MISMATCH, got, sizeof got);
    CHECK_BAD(hf_trace_batch(f, sm, m->si, m->si_len, &two, rays, N, got, N),
              HF_ERR_MAP_MISMATCH, got, sizeof got);
    CHECK_BAD(hf_trace_batch(f, rm, m->si, m->si_len, NULL, rays, N, got, N),
              HF_ERR_MAP_MISMATCH, got, sizeof got);
    CHECK_DETAIL("isotropic safety map, a radius map expected");
    /* A cone map traced as a relaxed map (long enough: the relaxed texels end inside
     * the cone texels, where no descriptor is). */
    CHECK_BAD(hf_trace_batch(f, HF_METHOD_RELAXED, m->cone, m->cone_len, NULL, rays, N, got, N),
              HF_ERR_MAP_MISMATCH, got, sizeof got);
    CHECK_DETAIL("descriptor after its");
    /* A damaged descriptor, then repaired. */
    m->rad[m->rad_len - 30] ^= 4;
    CHECK_BAD(hf_trace_batch(f, rm, m->rad, m->rad_len, NULL, rays, N, got, N),
              HF_ERR_MAP_MISMATCH, got, sizeof got);
    CHECK_DETAIL("damaged");
    m->rad[m->rad_len - 30] ^= 4;
    CHECK_OK(hf_trace_batch(f, rm, m->rad, m->rad_len, NULL, rays, N, got, N));
    /* A map without room for its descriptor. */
    CHECK_BAD(hf_trace_batch(f, HF_METHOD_MAXMIP, m->pyr, m->pyr_len - 1, NULL, rays, N, got, N),
              HF_ERR_BUFFER_TOO_SMALL, got, sizeof got);
}

/* Updates, stale maps and the pyramid refresh. */
static void check_updates(hf_field *f, maps *m, const hf_ray *rays) {
    uint64_t fp0 = 0, fp = 0, generation = 0;
    CHECK_OK(hf_field_get_fingerprint(f, &fp0, &generation));
    const float bump[6] = {12.0f, 13.0f, 11.0f, 12.5f, 13.5f, 10.0f};
    CHECK_OK(hf_field_update_rect(f, 10, 8, 13, 10, bump, 6, 3));
    CHECK_OK(hf_field_get_fingerprint(f, &fp, &generation));
    CHECK(fp != fp0 && generation == 1);
    check_refused(f, m, rays, HF_ERR_STALE_MAP, "update 1");

    /* A refresh over a rectangle that misses part of the update is refused. */
    float *before = (float *)malloc(m->pyr_len * sizeof(float));
    memcpy(before, m->pyr, m->pyr_len * sizeof(float));
    CHECK_BAD(hf_maxmip_update_rect(f, 10, 8, 12, 10, m->pyr, m->pyr_len), HF_ERR_STALE_MAP,
              m->pyr, 512);
    CHECK(memcmp(before, m->pyr, m->pyr_len * sizeof(float)) == 0);
    CHECK_DETAIL("update 1");
    /* A second update elsewhere: a refresh must cover both. */
    const float dip[2] = {0.5f, 0.25f};
    CHECK_OK(hf_field_update_rect(f, 30, 20, 32, 21, dip, 2, 2));
    CHECK_BAD(hf_maxmip_update_rect(f, 10, 8, 13, 10, m->pyr, m->pyr_len), HF_ERR_STALE_MAP,
              m->pyr, 512);
    CHECK_DETAIL("update 2");
    CHECK_OK(hf_maxmip_update_rect(f, 10, 8, 32, 21, m->pyr, m->pyr_len));
    /* The refreshed pyramid equals a fresh bake, descriptor included. */
    float *fresh = (float *)malloc(m->pyr_len * sizeof(float));
    CHECK_OK(hf_bake(HF_METHOD_MAXMIP, f, NULL, fresh, m->pyr_len));
    CHECK(memcmp(fresh, m->pyr, m->pyr_len * sizeof(float)) == 0);
    /* Refreshing a current pyramid again is fine. */
    CHECK_OK(hf_maxmip_update_rect(f, 0, 0, 1, 1, m->pyr, m->pyr_len));
    free(fresh);
    free(before);
    static hf_hit got[N];
    CHECK_OK(trace(MAXMIP, f, m, rays, got));
    CHECK_BAD(trace(CC, f, m, rays, got), HF_ERR_STALE_MAP, got, sizeof got);

    /* Rebaked, every map answers exactly again. */
    free_all(m);
    bake_all(f, m);
    check_exact(f, m, rays, "after the rebake");

    /* More updates than the field remembers: a refresh cannot prove it covers them. */
    for (int k = 0; k < 17; k++) {
        float v = 3.0f + (float)k;
        CHECK_OK(hf_field_update_rect(f, (uint32_t)k, 0, (uint32_t)k + 1, 1, &v, 1, 1));
    }
    CHECK_BAD(hf_maxmip_update_rect(f, 0, 0, W, H, m->pyr, m->pyr_len), HF_ERR_MAP_MISMATCH,
              m->pyr, 512);
    CHECK_DETAIL("last 16 updates");
}

/* A KTX2 file keeps the fingerprint: the map read back traces on the field. */
static void check_ktx2(const hf_field *f, const maps *m, const hf_ray *rays) {
    hf_ktx2_desc d;
    CHECK_OK(hf_ktx2_desc_default(HF_KTX2_CC, W, H, &d));
    d.cap = CAP;
    d.ray_classes = CLASSES;
    size_t n = 0, map_len = 0;
    CHECK_OK(hf_ktx2_len(&d, &n));
    CHECK_OK(hf_ktx2_map_len(&d, &map_len));
    CHECK(map_len == m->cc_len);
    uint8_t *file = (uint8_t *)malloc(n), *back = (uint8_t *)malloc(map_len);
    /* The map's descriptor must describe what desc says. */
    hf_ktx2_desc other = d;
    other.cap = CAP + 1;
    size_t n_other = 0;
    CHECK_OK(hf_ktx2_len(&other, &n_other));
    uint8_t *file_other = (uint8_t *)malloc(n_other);
    CHECK_BAD(hf_ktx2_write(&other, m->cc, m->cc_len, file_other, n_other), HF_ERR_MAP_MISMATCH,
              file_other, n_other);
    free(file_other);
    CHECK_OK(hf_ktx2_write(&d, m->cc, m->cc_len, file, n));
    CHECK_OK(hf_ktx2_read_map(file, n, back, map_len));
    CHECK(memcmp(back, m->cc, map_len) == 0);
    static hf_hit a[N], b[N];
    hf_trace_options o = with_classes(CLASSES);
    CHECK_OK(hf_trace_batch(f, HF_METHOD_CC, m->cc, map_len, &o, rays, N, a, N));
    CHECK_OK(hf_trace_batch(f, HF_METHOD_CC, back, map_len, &o, rays, N, b, N));
    CHECK(memcmp(a, b, sizeof a) == 0);
    free(file);
    free(back);
}

/* Row bakes: the call whose rows start at 0 writes the descriptor. */
static void check_row_bakes(const hf_field *f, const maps *m) {
    hf_bake_options ro;
    CHECK_OK(hf_bake_options_default(HF_METHOD_RADIUS, &ro));
    ro.cap = 64;
    /* The radii's scratch is the safety distances' (the strip bounds). */
    size_t slen = 0, rlen = 0;
    CHECK_OK(hf_bake_scratch_len(HF_METHOD_SAFETY, W, H, NULL, &slen));
    CHECK_OK(hf_bake_scratch_len(HF_METHOD_RADIUS, W, H, &ro, &rlen));
    CHECK(rlen == slen);
    float *scratch = (float *)malloc(slen * sizeof(float));
    CHECK_OK(hf_bake_prepare(HF_METHOD_SAFETY, f, NULL, scratch, slen));
    uint8_t *rows = (uint8_t *)calloc(m->rad_len, 1);
    CHECK_OK(hf_bake_rows(HF_METHOD_RADIUS, f, &ro, scratch, slen, 9, H, rows, m->rad_len));
    CHECK(memcmp(rows, m->rad, m->rad_len) != 0); /* no descriptor yet */
    CHECK_OK(hf_bake_rows(HF_METHOD_RADIUS, f, &ro, scratch, slen, 0, 9, rows, m->rad_len));
    CHECK(memcmp(rows, m->rad, m->rad_len) == 0);
    free(rows);
    free(scratch);
    /* The pyramid's top level (one texel, baked last) writes it. */
    hf_level lv[HF_MAX_LEVELS];
    uint32_t count = 0;
    CHECK_OK(hf_maxmip_levels(W, H, lv, HF_MAX_LEVELS, &count));
    float *pyr = (float *)calloc(m->pyr_len, sizeof(float));
    for (uint32_t k = 0; k < count; k++)
        CHECK_OK(hf_maxmip_bake_rows(f, k, 0, lv[k].height, pyr, m->pyr_len));
    CHECK(memcmp(pyr, m->pyr, m->pyr_len * sizeof(float)) == 0);
    free(pyr);
}

int main(void) {
    hf_field *a = field(3.0f, 0.0f), *b = field(3.0f, 1.3f);
    if (!a || !b) {
        printf("c-maps: %d passed, %d failed\n", checks - failures, failures + 1);
        return 1;
    }
    static hf_ray rays[N];
    for (int k = 0; k < N; k++) {
        hf_ray r = {{-4.0f + (W + 8) * frand(), -4.0f + (H + 8) * frand(), 4.0f + 16.0f * frand()},
                    {frand() - 0.5f, frand() - 0.5f, -0.6f * frand() - 0.05f},
                    0.0f,
                    INFINITY};
        rays[k] = r;
    }
    maps ma, mb;
    bake_all(a, &ma);
    bake_all(b, &mb);
    check_exact(a, &ma, rays, "on their own field");
    check_exact(b, &mb, rays, "on their own field");
    /* Field a's maps on field b (same size, other heights). */
    check_refused(b, &ma, rays, HF_ERR_MAP_MISMATCH, "other heights");
    check_descriptor_reads(a, &ma);
    check_wrong_arguments(a, &ma, rays);
    check_row_bakes(a, &ma);
    check_ktx2(a, &ma, rays);
    check_updates(a, &ma, rays);
    free_all(&ma);
    free_all(&mb);
    hf_field_destroy(a);
    hf_field_destroy(b);
    printf("c maps: %d checks, %d bad inputs tried\n", checks, bad_inputs);
    printf("c-maps: %d passed, %d failed\n", checks - failures, failures);
    return failures != 0;
}
