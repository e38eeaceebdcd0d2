/* libFuzzer target: every trace of libhfcast with arbitrary rays.
 * Input: a field (fz_field), the options of its maps (caps, cc slope, ray classes), a
 * surface, then up to FZ_MAX_RAYS rays (fz_ray: valid ones near the field, lattice
 * and axis-parallel ones, and now and then raw bits). Every method traces the batch
 * (hf_trace_batch); each answer is checked against the exact method's on the same
 * rays: maximum mipmaps bit for bit, safety distances (both layouts, and a map of some
 * classes only), cylinder–cone, radius with the walk, cone and QDM within their budget
 * up to rounding on grazing rays (fz_compare); the search and relaxed methods only for
 * their codes; a surface a method does not trace is refused. A batch that fails writes
 * nothing; a single call (hf_trace) answers as the batch.
 * Then the maps' descriptors (check_descriptors): a flipped descriptor byte is
 * HF_ERR_MAP_MISMATCH, an updated sample makes every map HF_ERR_STALE_MAP, and a
 * pyramid refreshed over the update answers as the exact DDA again. */
#include "common.h"

typedef struct maps {
    float *pyr;
    size_t pyr_len;
    uint8_t *sd, *si, *sc, *cc, *rad;
    size_t sd_len, si_len, sc_len, cc_len, rad_len;
    uint32_t classes;
    float *cone, *qdm, *relaxed;
    size_t cone_len, qdm_len, relaxed_len;
} maps;

static void must(hf_result r, const char *what) {
    if (fz_code(r, what) != HF_OK) FZ_FAIL("%s failed with %u", what, (unsigned)r);
}

static void bake_all(hf_field *f, uint32_t w, uint32_t h, fz_in *in, maps *m) {
    hf_safety_options so = {HF_SAFETY_DIRECTIONAL, 0, fz_u8(in), HF_RAYS_ALL};
    hf_cc_options co = {fz_u8(in) & 1, fz_u8(in), HF_RAYS_ALL};
    hf_radius_options ro = {0.0f, fz_u8(in)};
    m->classes = 1 + fz_u8(in) % 15;
    co.ray_classes = m->classes;
    must(hf_maxmip_len(w, h, &m->pyr_len), "hf_maxmip_len");
    m->pyr = (float *)fz_buf(m->pyr_len * sizeof(float));
    must(hf_maxmip_bake(f, m->pyr, m->pyr_len), "hf_maxmip_bake");
    must(hf_safety_map_len(w, h, so.variant, so.ray_classes, &m->sd_len), "hf_safety_map_len");
    m->sd = (uint8_t *)fz_buf(m->sd_len);
    must(hf_safety_bake(f, &so, 1, m->sd, m->sd_len), "hf_safety_bake");
    so.variant = HF_SAFETY_ISOTROPIC;
    must(hf_safety_map_len(w, h, so.variant, so.ray_classes, &m->si_len), "hf_safety_map_len");
    m->si = (uint8_t *)fz_buf(m->si_len);
    must(hf_safety_bake(f, &so, 1, m->si, m->si_len), "hf_safety_bake");
    so.variant = HF_SAFETY_DIRECTIONAL;
    so.ray_classes = m->classes;
    must(hf_safety_map_len(w, h, so.variant, so.ray_classes, &m->sc_len), "hf_safety_map_len");
    m->sc = (uint8_t *)fz_buf(m->sc_len);
    must(hf_safety_bake(f, &so, 1, m->sc, m->sc_len), "hf_safety_bake");
    must(hf_cc_map_len(w, h, co.ray_classes, &m->cc_len), "hf_cc_map_len");
    m->cc = (uint8_t *)fz_buf(m->cc_len);
    must(hf_cc_bake(f, &co, 1, m->cc, m->cc_len), "hf_cc_bake");
    must(hf_radius_map_len(w, h, &m->rad_len), "hf_radius_map_len");
    m->rad = (uint8_t *)fz_buf(m->rad_len);
    must(hf_radius_bake(f, &ro, 1, m->rad, m->rad_len), "hf_radius_bake");
    must(hf_cone_map_len(w, h, &m->cone_len), "hf_cone_map_len");
    m->cone = (float *)fz_buf(m->cone_len * sizeof(float));
    must(hf_cone_bake(f, 1, m->cone, m->cone_len), "hf_cone_bake");
    must(hf_qdm_map_len(w, h, &m->qdm_len), "hf_qdm_map_len");
    m->qdm = (float *)fz_buf(m->qdm_len * sizeof(float));
    must(hf_qdm_bake(f, 1, m->qdm, m->qdm_len), "hf_qdm_bake");
    must(hf_relaxed_map_len(w, h, &m->relaxed_len), "hf_relaxed_map_len");
    m->relaxed = (float *)fz_buf(m->relaxed_len * sizeof(float));
    must(hf_relaxed_bake(f, 1, m->relaxed, m->relaxed_len), "hf_relaxed_bake");
}

static void free_all(maps *m) {
    free(m->pyr);
    free(m->sd);
    free(m->si);
    free(m->sc);
    free(m->cc);
    free(m->rad);
    free(m->cone);
    free(m->qdm);
    free(m->relaxed);
}

enum {
    M_MAXMIP,
    M_SAFETY_DIR,
    M_SAFETY_ISO,
    M_SAFETY_CLASSES,
    M_CC,
    M_RADIUS,
    M_CONE,
    M_QDM,
    M_RELAXED,
    M_LINEAR_BINARY,
    M_LINEAR_SECANT,
    M_COUNT
};
static const char *const names[M_COUNT] = {
    "maxmip", "safety directional", "safety isotropic", "safety classes", "cc",
    "radius", "cone", "qdm", "relaxed", "linear-binary", "linear-secant"};

/* Method m on the batch (`single`: the single-ray call on rays[0]) on surface `s`, with
 * `iter` steps (cone, QDM iterations; relaxed cone steps; linear steps) and 8
 * bisections; the safety and cc traces name the classes their maps hold. */
static hf_result trace(int m, const hf_field *f, const maps *mp, uint32_t s, uint32_t iter,
                       const hf_ray *rays, size_t n, hf_hit *out, size_t out_len, int single) {
    static const uint32_t api[M_COUNT] = {
        HF_METHOD_MAXMIP, HF_METHOD_SAFETY, HF_METHOD_SAFETY,  HF_METHOD_SAFETY,
        HF_METHOD_CC,     HF_METHOD_RADIUS, HF_METHOD_CONE,    HF_METHOD_QDM,
        HF_METHOD_RELAXED, HF_METHOD_LINEAR_BINARY, HF_METHOD_LINEAR_SECANT};
    const void *map[M_COUNT] = {mp->pyr, mp->sd,  mp->si,      mp->sc, mp->cc, mp->rad,
                                mp->cone, mp->qdm, mp->relaxed, NULL,   NULL};
    const size_t len[M_COUNT] = {mp->pyr_len,  mp->sd_len,  mp->si_len,      mp->sc_len,
                                 mp->cc_len,   mp->rad_len, mp->cone_len,    mp->qdm_len,
                                 mp->relaxed_len, 0,        0};
    const uint32_t classes[M_COUNT] = {0, HF_RAYS_ALL, HF_RAYS_ALL, mp->classes, mp->classes};
    hf_trace_options o;
    hf_trace_options_default(&o);
    o.surface = s;
    o.ray_classes = classes[m];
    o.steps = iter;
    o.binary_steps = 8;
    if (single) return hf_trace(f, api[m], map[m], len[m], &o, rays, out);
    return hf_trace_batch(f, api[m], map[m], len[m], &o, rays, n, out, out_len);
}

/* Which surfaces a method traces (others: an error, never a wrong answer). */
static int takes_surface(int m, uint32_t s) {
    if (s > HF_SURFACE_VIEW_LINEAR) return 0;
    switch (m) {
    case M_MAXMIP:
    case M_LINEAR_BINARY:
    case M_LINEAR_SECANT: return 1;
    case M_CONE:
    case M_QDM:
    case M_RELAXED: return s == HF_SURFACE_TRIANGLES;
    default: return s == HF_SURFACE_TRIANGLES || s == HF_SURFACE_VIEW_LINEAR;
    }
}

/* The descriptor of method m's map: its last HF_MAP_DESC_BYTES bytes. */
static uint8_t *descriptor(int m, const maps *mp) {
    switch (m) {
    case M_MAXMIP: return (uint8_t *)mp->pyr + mp->pyr_len * 4 - HF_MAP_DESC_BYTES;
    case M_SAFETY_DIR: return mp->sd + mp->sd_len - HF_MAP_DESC_BYTES;
    case M_SAFETY_ISO: return mp->si + mp->si_len - HF_MAP_DESC_BYTES;
    case M_SAFETY_CLASSES: return mp->sc + mp->sc_len - HF_MAP_DESC_BYTES;
    case M_CC: return mp->cc + mp->cc_len - HF_MAP_DESC_BYTES;
    case M_RADIUS: return mp->rad + mp->rad_len - HF_MAP_DESC_BYTES;
    case M_CONE: return (uint8_t *)mp->cone + mp->cone_len * 4 - HF_MAP_DESC_BYTES;
    case M_QDM: return (uint8_t *)mp->qdm + mp->qdm_len * 4 - HF_MAP_DESC_BYTES;
    default: return (uint8_t *)mp->relaxed + mp->relaxed_len * 4 - HF_MAP_DESC_BYTES;
    }
}

/* Method m must refuse its map with `want` and write nothing. */
static void expect_refused(int m, const hf_field *f, const maps *mp, uint32_t s, uint32_t iter,
                           const hf_ray *rays, size_t n, hf_hit *got, hf_result want) {
    memset(got, FZ_POISON, sizeof(hf_hit) * FZ_MAX_RAYS + FZ_GUARD);
    hf_result r = trace(m, f, mp, s, iter, rays, n, got, n, 0);
    if (r != want)
        FZ_FAIL("%s: a map %s answered %u, not %u", names[m],
                want == HF_ERR_STALE_MAP ? "of the heights before an update" : "with a damaged descriptor",
                (unsigned)r, (unsigned)want);
    fz_after(r, got, sizeof(hf_hit) * n, names[m]);
}

/* Map descriptors (issue 26): one byte picks a damage. 1: a byte of one map's descriptor
 * flipped, which its traces must refuse (HF_ERR_MAP_MISMATCH); 2: one sample updated,
 * after which every map is stale (HF_ERR_STALE_MAP), a pyramid refresh over a
 * rectangle missing the update is refused, and one over it answers as the exact DDA. */
static void check_descriptors(fz_in *in, hf_field *f, uint32_t w, maps *mp, const int *traced,
                              uint32_t s, uint32_t iter, const hf_ray *rays, size_t n,
                              hf_hit *got) {
    uint8_t pick = fz_u8(in), which = fz_u8(in);
    if (pick % 4 == 1) {
        int m = which % M_LINEAR_BINARY;
        if (!traced[m]) return;
        uint8_t *d = descriptor(m, mp);
        d[pick / 4 % HF_MAP_DESC_BYTES] ^= (uint8_t)(1u << which % 8);
        expect_refused(m, f, mp, s, iter, rays, n, got, HF_ERR_MAP_MISMATCH);
        d[pick / 4 % HF_MAP_DESC_BYTES] ^= (uint8_t)(1u << which % 8);
    } else if (pick % 4 == 2) {
        float *hs = (float *)fz_buf(sizeof(float) * FZ_MAX_SIDE * FZ_MAX_SIDE);
        must(hf_field_copy_heights(f, hs, FZ_MAX_SIDE * FZ_MAX_SIDE), "hf_field_copy_heights");
        float h0 = hs[0] == 0.0f ? 1.0f : -hs[0];
        free(hs);
        must(hf_field_update_rect(f, 0, 0, 1, 1, &h0, 1, 1), "hf_field_update_rect");
        for (int m = 0; m < M_LINEAR_BINARY; m++)
            if (traced[m]) expect_refused(m, f, mp, s, iter, rays, n, got, HF_ERR_STALE_MAP);
        if (w > 1 &&
            hf_maxmip_update_rect(f, 1, 0, 2, 1, mp->pyr, mp->pyr_len) != HF_ERR_STALE_MAP)
            FZ_FAIL("hf_maxmip_update_rect accepted a rectangle missing the update");
        must(hf_maxmip_update_rect(f, 0, 0, 1, 1, mp->pyr, mp->pyr_len), "hf_maxmip_update_rect");
        if (!traced[M_MAXMIP] || n == 0) return;
        hf_hit exact[FZ_MAX_RAYS];
        hf_trace_options on = fz_on(s);
        must(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &on, rays, n, exact, n),
             "exact (updated)");
        must(trace(M_MAXMIP, f, mp, s, iter, rays, n, got, n, 0), "maxmip (refreshed)");
        fz_compare(f, s, rays, (int)n, exact, got, 1, "maxmip (refreshed)");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fz_in in = {data, size};
    static float heights[FZ_MAX_SIDE * FZ_MAX_SIDE];
    uint32_t w, h;
    hf_field *f = fz_field(&in, FZ_MAX_SIDE, &w, &h, heights);
    maps mp;
    memset(&mp, 0, sizeof mp);
    bake_all(f, w, h, &in, &mp);
    uint8_t sb = fz_u8(&in);
    uint32_t s = sb < 250 ? sb % 5 : sb; /* now and then an unknown surface */
    uint32_t iter = fz_u8(&in) < 240 ? 1000 : fz_u8(&in); /* cone/QDM budget, steps */
    size_t n = fz_u8(&in) % (FZ_MAX_RAYS + 1);
    hf_ray rays[FZ_MAX_RAYS];
    int any_raw = 0;
    for (size_t k = 0; k < n; k++) {
        int raw;
        rays[k] = fz_ray(&in, w, h, &raw);
        any_raw |= raw;
    }
    hf_hit exact[FZ_MAX_RAYS];
    hf_hit *got = (hf_hit *)fz_buf(sizeof(hf_hit) * FZ_MAX_RAYS);
    size_t bytes = sizeof(hf_hit) * n;

    memset(exact, FZ_POISON, sizeof exact);
    hf_trace_options on = fz_on(s);
    hf_result re = fz_code(hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, &on, rays, n, exact, n),
                           "exact batch");
    if (re != HF_OK && !fz_all_poison(exact, bytes))
        FZ_FAIL("the exact batch failed with %u but wrote hits", (unsigned)re);
    if (re == HF_OK && n > 0 && s <= HF_SURFACE_VIEW_LINEAR) {
        /* A single exact call answers as the batch; any ray of the batch was valid. */
        for (size_t k = 0; k < n; k++) {
            hf_hit one;
            if (fz_code(hf_trace(f, HF_METHOD_EXACT, NULL, 0, &on, &rays[k], &one), "exact") !=
                    HF_OK ||
                memcmp(&one, &exact[k], sizeof one) != 0)
                FZ_FAIL("the exact single call differs from its batch on ray %zu", k);
        }
    }
    if (re != HF_OK && n > 0 && s <= HF_SURFACE_VIEW_LINEAR && !any_raw)
        FZ_FAIL("the exact batch refused %zu valid rays with %u", n, (unsigned)re);

    int traced[M_COUNT] = {0};
    for (int m = 0; m < M_COUNT; m++) {
        memset(got, FZ_POISON, sizeof(hf_hit) * FZ_MAX_RAYS + FZ_GUARD);
        hf_result r = trace(m, f, &mp, s, iter, rays, n, got, n, 0);
        traced[m] = r == HF_OK;
        fz_after(r, got, bytes, names[m]);
        if (n == 0) continue; /* an empty batch: HF_OK or an error, both fine */
        if (re != HF_OK && r == HF_OK)
            FZ_FAIL("%s accepted a batch the exact method refused (%u)", names[m], (unsigned)re);
        if (re != HF_OK) continue;
        int takes = takes_surface(m, s);
        if (takes && r != HF_OK && !(iter == 0 && m >= M_CONE))
            FZ_FAIL("%s refused rays the exact method took, with %u", names[m], (unsigned)r);
        if (!takes && r != HF_ERR_INVALID_ARGUMENT)
            FZ_FAIL("%s answered %u on surface %u, not HF_ERR_INVALID_ARGUMENT", names[m],
                    (unsigned)r, (unsigned)s);
        if (r != HF_OK) continue;
        /* The single-ray call answers as the batch. */
        for (size_t k = 0; k < n; k += 7) {
            hf_hit one;
            fz_code(trace(m, f, &mp, s, iter, &rays[k], 1, &one, 1, 1), names[m]);
            if (memcmp(&one, &got[k], sizeof one) != 0)
                FZ_FAIL("%s: the single call differs from the batch on ray %zu", names[m], k);
        }
        if (m == M_MAXMIP) fz_compare(f, s, rays, (int)n, exact, got, 1, names[m]);
        else if (m <= M_RADIUS) fz_compare(f, s, rays, (int)n, exact, got, 0, names[m]);
        else if (m <= M_QDM) fz_compare(f, s, rays, (int)n, exact, got, 0, names[m]);
    }
    check_descriptors(&in, f, w, &mp, traced, s, iter, rays, n, got);
    free(got);
    free_all(&mp);
    hf_field_destroy(f);
    return 0;
}
