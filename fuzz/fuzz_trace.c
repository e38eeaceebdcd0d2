/* libFuzzer target: every trace of libhfcast with arbitrary rays.
 * Input: a field (fz_field), the options of its maps (caps, cc slope, ray classes), a
 * surface, then up to FZ_MAX_RAYS rays (fz_ray: valid ones near the field, lattice
 * and axis-parallel ones, and now and then raw bits). Every method traces the batch
 * (hf_trace_batch); each answer is checked against the exact method's on the same
 * rays: maximum mipmaps bit for bit, safety distances (both layouts, and a map of some
 * classes only), cylinder–cone, radius with the walk, cone and QDM within their budget
 * up to rounding on grazing rays (fz_compare); the search, relaxed and multires methods only for
 * their codes; a surface a method does not trace is refused. A batch that fails writes
 * nothing; a single call (hf_trace) answers as the batch.
 * Then the maps' descriptors (check_descriptors): a flipped descriptor byte is
 * HF_ERR_MAP_MISMATCH, an updated sample makes every map HF_ERR_STALE_MAP, and a
 * pyramid refreshed over the update answers as the exact DDA again. */
#include "common.h"

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
    M_LINEAR_BINARY, /* the first method without a map */
    M_LINEAR_SECANT,
    M_MULTIRES,
    M_COUNT
};
static const char *const names[M_COUNT] = {
    "maxmip", "safety directional", "safety isotropic", "safety classes", "cc",
    "radius", "cone", "qdm", "relaxed", "linear-binary", "linear-secant", "multires"};
static const uint32_t api[M_COUNT] = {
    HF_METHOD_MAXMIP, HF_METHOD_SAFETY, HF_METHOD_SAFETY,  HF_METHOD_SAFETY,
    HF_METHOD_CC,     HF_METHOD_RADIUS, HF_METHOD_CONE,    HF_METHOD_QDM,
    HF_METHOD_RELAXED, HF_METHOD_LINEAR_BINARY, HF_METHOD_LINEAR_SECANT, HF_METHOD_MULTIRES};

/* One baked map: `len` elements of `elem` bytes (floats or bytes), descriptor included. */
typedef struct baked {
    void *p;
    size_t len, elem;
} baked;

/* The maps of the methods before M_LINEAR_BINARY, and the classes of M_SAFETY_CLASSES
 * and M_CC. */
typedef struct maps {
    baked m[M_LINEAR_BINARY];
    uint32_t classes;
} maps;

static void must(hf_result r, const char *what) {
    if (fz_code(r, what) != HF_OK) FZ_FAIL("%s failed with %u", what, (unsigned)r);
}

/* Bakes map `k` of `f` with options `o` (on one thread) into `b`. */
static void bake_one(const hf_field *f, uint32_t w, uint32_t h, int k, const hf_bake_options *o,
                     baked *b) {
    must(hf_map_len(api[k], w, h, o, &b->len), names[k]);
    b->elem = k == M_MAXMIP || k >= M_CONE ? sizeof(float) : 1;
    b->p = fz_buf(b->len * b->elem);
    must(hf_bake(api[k], f, o, b->p, b->len), names[k]);
}

/* Every map, from the defaults with caps, the cc slope and the classes from the input. */
static void bake_all(hf_field *f, uint32_t w, uint32_t h, fz_in *in, maps *m) {
    hf_bake_options o[M_LINEAR_BINARY];
    for (int k = 0; k < M_LINEAR_BINARY; k++)
        must(hf_bake_options_default(api[k], &o[k]), "hf_bake_options_default");
    uint32_t safety_cap = fz_u8(in);
    for (int k = M_SAFETY_DIR; k <= M_SAFETY_CLASSES; k++) {
        o[k].cap = safety_cap;
        o[k].ray_classes = HF_RAYS_ALL;
    }
    o[M_SAFETY_ISO].variant = HF_SAFETY_ISOTROPIC;
    o[M_CC].slope = fz_u8(in) & 1;
    o[M_CC].cap = fz_u8(in);
    o[M_RADIUS].cap = fz_u8(in);
    m->classes = 1 + fz_u8(in) % 15;
    o[M_SAFETY_CLASSES].ray_classes = o[M_CC].ray_classes = m->classes;
    for (int k = 0; k < M_LINEAR_BINARY; k++) bake_one(f, w, h, k, &o[k], &m->m[k]);
}

static void free_all(maps *m) {
    for (int k = 0; k < M_LINEAR_BINARY; k++) free(m->m[k].p);
}

/* Method m on the batch (`single`: the single-ray call on rays[0]) on surface `s`, with
 * `iter` steps (cone, QDM iterations; relaxed cone steps; linear steps) and 8
 * bisections; the safety and cc traces name the classes their maps hold. */
static hf_result trace(int m, const hf_field *f, const maps *mp, uint32_t s, uint32_t iter,
                       const hf_ray *rays, size_t n, hf_hit *out, size_t out_len, int single) {
    const void *map = m < M_LINEAR_BINARY ? mp->m[m].p : NULL;
    size_t len = m < M_LINEAR_BINARY ? mp->m[m].len : 0;
    const uint32_t classes[M_COUNT] = {0, HF_RAYS_ALL, HF_RAYS_ALL, mp->classes, mp->classes};
    hf_trace_options o;
    hf_trace_options_default(&o);
    o.surface = s;
    o.ray_classes = classes[m];
    o.steps = iter;
    o.binary_steps = 8;
    if (single) return hf_trace(f, api[m], map, len, &o, rays, out);
    return hf_trace_batch(f, api[m], map, len, &o, rays, n, out, out_len);
}

/* Which surfaces a method traces (others: an error, never a wrong answer). */
static int takes_surface(int m, uint32_t s) {
    if (s >= HF_SURFACE_COUNT) return 0;
    switch (m) {
    case M_MAXMIP:
    case M_LINEAR_BINARY:
    case M_LINEAR_SECANT:
    case M_MULTIRES: return 1;
    case M_CONE:
    case M_QDM:
    case M_RELAXED: return s == HF_SURFACE_TRIANGLES;
    default: return s == HF_SURFACE_TRIANGLES || s == HF_SURFACE_VIEW_LINEAR;
    }
}

/* The descriptor of method m's map: its last HF_MAP_DESC_BYTES bytes. */
static uint8_t *descriptor(int m, const maps *mp) {
    const baked *b = &mp->m[m];
    return (uint8_t *)b->p + b->len * b->elem - HF_MAP_DESC_BYTES;
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
        float *pyr = (float *)mp->m[M_MAXMIP].p;
        size_t pyr_len = mp->m[M_MAXMIP].len;
        if (w > 1 && hf_maxmip_update_rect(f, 1, 0, 2, 1, pyr, pyr_len) != HF_ERR_STALE_MAP)
            FZ_FAIL("hf_maxmip_update_rect accepted a rectangle missing the update");
        must(hf_maxmip_update_rect(f, 0, 0, 1, 1, pyr, pyr_len), "hf_maxmip_update_rect");
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
    uint32_t s = sb < 250 ? sb % HF_SURFACE_COUNT : sb; /* now and then an unknown surface */
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
    if (re == HF_OK && n > 0 && s < HF_SURFACE_COUNT) {
        /* A single exact call answers as the batch; any ray of the batch was valid. */
        for (size_t k = 0; k < n; k++) {
            hf_hit one;
            if (fz_code(hf_trace(f, HF_METHOD_EXACT, NULL, 0, &on, &rays[k], &one), "exact") !=
                    HF_OK ||
                memcmp(&one, &exact[k], sizeof one) != 0)
                FZ_FAIL("the exact single call differs from its batch on ray %zu", k);
            /* Walked back (hf_ray_walked_back): a valid ray, the same one or reversed. */
            hf_ray back;
            if (fz_code(hf_ray_walked_back(f, &rays[k], &back), "walked back") != HF_OK ||
                fz_code(hf_trace(f, HF_METHOD_EXACT, NULL, 0, &on, &back, &one), "back") != HF_OK)
                FZ_FAIL("ray %zu walked back was refused", k);
            int same = memcmp(&back, &rays[k], sizeof back) == 0;
            for (int c = 0; c < 3 && !same; c++)
                if (back.dir[c] != -rays[k].dir[c] || back.origin[c] != rays[k].origin[c])
                    FZ_FAIL("ray %zu walked back is not the same line reversed", k);
        }
    }
    if (re != HF_OK && n > 0 && s < HF_SURFACE_COUNT && !any_raw)
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
