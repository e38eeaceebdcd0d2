/* libFuzzer target: the generic bake functions of libhfcast (hf_map_len,
 * hf_bake_scratch_len, hf_bake_row_count, hf_bake_prepare, hf_bake_rows, hf_bake) with
 * arbitrary methods and options.
 * Input: a field (fz_field), a method number (now and then any u32), every
 * hf_bake_options field (variant, positive, cap, slope, ray classes, tolerance,
 * threads 0..4, the ray set, occluders, a reserved word; each now and then out of range), whether to pass
 * NULL options (the defaults), an output length off the needed one by a fuzzed
 * amount, a row split, then a few rays. Checks: a valid code; the size queries
 * accept exactly the known methods with valid options, and the bakes refuse the
 * others with the same code; a failing bake writes nothing, a succeeding one nothing
 * past its length, and it succeeds exactly when the buffer is long enough (a method
 * without a map: exactly when the length is 0); the whole bake equals the same bake
 * in two row ranges on one thread (NULL options: with hf_bake_options_default's), and
 * a maximum mipmap also level by level (hf_maxmip_bake_rows); the map then traces the
 * rays as the exact method does (bit for bit for maxmip; on stable rays for the exact
 * options of the others, fz_compare); its descriptor (hf_map_read_desc) names the
 * field's fingerprint and size. */
#include "common.h"

/* An option value: mostly a small valid one, now and then any u32. */
static uint32_t opt(fz_in *in, uint32_t valid_below) {
    uint8_t k = fz_u8(in);
    if (k >= 248) return fz_u32(in);
    return k % valid_below;
}

static void same_bytes(const void *a, const void *b, size_t len, const char *what) {
    if (memcmp(a, b, len) != 0) FZ_FAIL("%s: the maps differ", what);
}

/* Occluders for the ray set: two wall tops west of the field (GOOD_WALLS) and one
 * whose footprint is a segment (BAD_WALL, refused). */
static const hf_occluder GOOD_WALLS[2] = {
    {{{-3.0f, -3.0f, 5.0f}, {-1.0f, -3.0f, 5.0f}, {-1.0f, 9.0f, 6.0f}}},
    {{{-3.0f, -3.0f, 5.0f}, {-1.0f, 9.0f, 6.0f}, {-3.0f, 9.0f, 6.0f}}},
};
static const hf_occluder BAD_WALL[1] = {{{{0.0f, 0.0f, 1.0f}, {1.0f, 1.0f, 2.0f}, {2.0f, 2.0f, 3.0f}}}};

/* Every field of `o` from the input, each now and then out of range. */
static void read_options(fz_in *in, hf_bake_options *o) {
    memset(o, 0, sizeof *o);
    o->variant = opt(in, 2);
    o->positive = opt(in, 2);
    o->cap = opt(in, 256);
    o->slope = opt(in, 2);
    o->ray_classes = opt(in, 16); /* 0: all four; > 15 is an error */
    o->tolerance = (fz_u8(in) < 200) ? 0.0f : fz_range(in, -1.0f, 4.0f);
    if (fz_u8(in) == 255) o->tolerance = fz_raw_float(in);
    o->threads = opt(in, 5);
    o->exterior = opt(in, 2);
    uint8_t a = fz_u8(in);
    o->max_view_angle_deg = a < 128 ? 0.0f : a < 250 ? fz_range(in, 1.0f, 180.0f) : fz_raw_float(in);
    uint8_t oc = fz_u8(in);
    if (oc >= 232) {
        /* 1 or 2 good walls, one bad, NULL with a count, or too many. */
        static const hf_occluder *const lists[4] = {GOOD_WALLS, GOOD_WALLS, BAD_WALL, NULL};
        static const uint32_t counts[4] = {1, 2, 1, 2};
        o->occluders = lists[oc % 4];
        o->occluder_count = oc >= 254 ? HF_MAX_OCCLUDERS + 1 : counts[oc % 4];
    }
    uint8_t rb = fz_u8(in);
    if (rb >= 248) o->reserved[rb % 4] = fz_u32(in);
}

/* Whether the library must accept `o` (whatever the method): the checks that
 * hf_bake_options documents. */
static int options_valid(const hf_bake_options *o) {
    for (int k = 0; k < 4; k++)
        if (o->reserved[k] != 0) return 0;
    if (o->occluder_count != 0 &&
        (o->occluders != GOOD_WALLS || o->occluder_count > HF_MAX_OCCLUDERS))
        return 0;
    float a = o->max_view_angle_deg;
    return o->variant <= 1 && o->positive <= 1 && o->cap <= 255 && o->slope <= 1 &&
           o->ray_classes <= HF_RAYS_ALL && isfinite(o->tolerance) && o->tolerance >= 0.0f &&
           o->exterior <= 1 && (a == 0.0f || (a > 0.0f && a <= 180.0f));
}

/* Whether `method`'s map is floats (else bytes; methods without a map: bytes). */
static int float_map(uint32_t method) {
    return method == HF_METHOD_MAXMIP || method == HF_METHOD_CONE ||
           method == HF_METHOD_RELAXED || method == HF_METHOD_QDM;
}

/* The rows hf_bake_row_count documents for `method`'s map of `h` rows. */
static uint32_t documented_rows(uint32_t method, uint32_t h, size_t need) {
    if (need == 0) return 0;
    if (method == HF_METHOD_MAXMIP) return 1;
    return method == HF_METHOD_CONE || method == HF_METHOD_QDM ? h - 1 : h;
}

/* Bakes `method`'s map of `f` again into `again` (`len` elements of `elem` bytes) by
 * rows on one thread: prepare, then rows [mid, rows) and [0, mid); checks each call
 * and that the result equals the whole bake `map`. */
static void bake_by_rows(uint32_t method, const hf_field *f, const hf_bake_options *o,
                         uint32_t w, uint32_t h, size_t need, uint32_t split, void *map,
                         void *again, size_t len, size_t elem, const char *what) {
    size_t slen = 0;
    uint32_t rows = 0;
    if (fz_code(hf_bake_scratch_len(method, w, h, o, &slen), "hf_bake_scratch_len") ||
        fz_code(hf_bake_row_count(method, w, h, o, &rows), "hf_bake_row_count"))
        FZ_FAIL("%s: a size query failed after hf_map_len succeeded", what);
    if (rows != documented_rows(method, h, need))
        FZ_FAIL("%s: %u rows, not %u", what, rows, documented_rows(method, h, need));
    float *scratch = (float *)fz_buf(slen * sizeof(float));
    hf_result r = hf_bake_prepare(method, f, o, scratch, slen);
    fz_after(r, scratch, slen * sizeof(float), "hf_bake_prepare");
    if (r != HF_OK) FZ_FAIL("%s: hf_bake_prepare failed with %u", what, (unsigned)r);
    uint32_t mid = split % (rows + 1);
    for (int part = 0; part < 2 && r == HF_OK; part++) {
        uint32_t b = part ? 0 : mid, e = part ? mid : rows;
        r = hf_bake_rows(method, f, o, scratch, slen, b, e, again, len);
        fz_after(r, again, len * elem, "hf_bake_rows");
    }
    if (r != HF_OK)
        FZ_FAIL("%s: the row bake failed with %u after the whole bake succeeded", what,
                (unsigned)r);
    same_bytes(map, again, len * elem, what);
    free(scratch);
}

/* A maximum mipmap level by level (hf_maxmip_bake_rows), each level split in two,
 * finest first, into `again` (poisoned again first); it must equal `map`. */
static void bake_by_levels(const hf_field *f, uint32_t w, uint32_t h, uint32_t split,
                           const void *map, float *again, size_t len) {
    hf_level levels[HF_MAX_LEVELS];
    uint32_t count = 0;
    if (fz_code(hf_maxmip_levels(w, h, levels, HF_MAX_LEVELS, &count), "hf_maxmip_levels"))
        FZ_FAIL("hf_maxmip_levels failed");
    memset(again, FZ_POISON, len * sizeof(float));
    hf_result r = HF_OK;
    for (uint32_t l = 0; l < count && r == HF_OK; l++) {
        uint32_t mid = split % (levels[l].height + 1);
        r = hf_maxmip_bake_rows(f, l, mid, levels[l].height, again, len);
        if (r == HF_OK) r = hf_maxmip_bake_rows(f, l, 0, mid, again, len);
    }
    if (fz_code(r, "hf_maxmip_bake_rows") != HF_OK)
        FZ_FAIL("maxmip: the level bake failed with %u", (unsigned)r);
    same_bytes(map, again, len * sizeof(float), "maxmip by levels");
}

/* The descriptor after the texels of `map` (`bytes` long) names `f`'s heights and size. */
static void check_desc(const hf_field *f, uint32_t w, uint32_t h, const void *map,
                       size_t bytes, const char *what) {
    hf_map_desc d;
    uint64_t fp = 0, generation = 0;
    if (fz_code(hf_field_get_fingerprint(f, &fp, &generation), "hf_field_get_fingerprint") ||
        fz_code(hf_map_read_desc(map, bytes, &d), "hf_map_read_desc") != HF_OK ||
        d.fingerprint != fp || d.flags != HF_MAP_FINGERPRINT_KNOWN || d.map.width != w ||
        d.map.height != h || d.texel_bytes != bytes - HF_MAP_DESC_BYTES)
        FZ_FAIL("%s: the descriptor does not describe the bake", what);
}

/* A few rays from the input traced with `method` over its `map` as the exact method
 * traces them (for the options `o` that make the map exact). */
static void trace_map(fz_in *in, const hf_field *f, uint32_t w, uint32_t h, uint32_t method,
                      const hf_bake_options *o, const void *map, size_t len,
                      const char *what) {
    int exact_opts = (method != HF_METHOD_SAFETY || o->positive == 0) &&
                     (method != HF_METHOD_RADIUS || o->tolerance == 0.0f);
    size_t n = fz_u8(in) % 17;
    hf_ray rays[16];
    hf_hit exact[16], got[16];
    int raw = 0, any_raw = 0;
    for (size_t k = 0; k < n; k++) {
        rays[k] = fz_ray(in, w, h, &raw);
        any_raw |= raw;
    }
    hf_result re = n ? hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, n, exact, n)
                     : HF_ERR_INVALID_ARGUMENT;
    fz_code(re, "exact batch");
    if (re != HF_OK && n && !any_raw) FZ_FAIL("exact refused valid rays");
    if (re != HF_OK || method == HF_METHOD_RELAXED) return;
    /* The safety and cc traces name the bake's classes; the cap and the safety layout
     * are the descriptor's. */
    hf_trace_options to;
    hf_trace_options_default(&to);
    int set = method == HF_METHOD_SAFETY || method == HF_METHOD_CC;
    to.ray_classes = set ? o->ray_classes : 0;
    /* And the occluders the map was baked over. */
    to.occluders = set ? o->occluders : NULL;
    to.occluder_count = set ? o->occluder_count : 0;
    to.steps = 1000; /* cone, QDM iterations */
    hf_result rt = hf_trace_batch(f, method, map, len, &to, rays, n, got, n);
    if (fz_code(rt, what) != HF_OK)
        FZ_FAIL("%s: tracing its own map failed with %u", what, (unsigned)rt);
    if (exact_opts)
        fz_compare(f, HF_SURFACE_TRIANGLES, rays, (int)n, exact, got,
                   method == HF_METHOD_MAXMIP, what);
}

/* Ray-set bakes (exterior rays, a view angle) scan the surface behind each segment
 * for every candidate triangle ahead: tens of microseconds a texel in a release build,
 * and this instrumented build (ASan, UBSan, comparison tracing, debug assertions) runs
 * them ~30 times slower (a 32 x 39 field: 0.13 s release, 3.7 s here). They bake the
 * field's top-left crop of at most FZ_RAYSET_SIDE samples a side (a strided view of the
 * same heights), so that an input stays under the 1 s hang limit. */
#define FZ_RAYSET_SIDE 12

/* Over occluders the same bakes cut every candidate by every wall: a smaller crop. */
#define FZ_OCCLUDER_SIDE 6

/* `*f` (`*w` x `*h` of `heights`) as its top-left crop of at most `side` a side. */
static void crop_field(hf_field **f, uint32_t *w, uint32_t *h, uint32_t side,
                       const float *heights) {
    if (*w <= side && *h <= side) return;
    uint32_t cw = *w < side ? *w : side, ch = *h < side ? *h : side;
    hf_field *c = NULL;
    hf_result r = fz_code(hf_field_create_f32(heights, (size_t)*w * *h, cw, ch, *w, &c),
                          "hf_field_create_f32 (crop)");
    if (r != HF_OK) FZ_FAIL("a %ux%u crop of stride %u was refused with %u", cw, ch, *w, (unsigned)r);
    hf_field_destroy(*f);
    *f = c;
    *w = cw;
    *h = ch;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fz_in in = {data, size};
    static float heights[FZ_MAX_SIDE * FZ_MAX_SIDE];
    uint32_t w, h;
    hf_field *f = fz_field(&in, FZ_MAX_SIDE, &w, &h, heights);
    uint32_t method = opt(&in, HF_METHOD_COUNT);
    hf_bake_options given;
    read_options(&in, &given);
    int null_options = fz_u8(&in) >= 224;
    uint8_t lb = fz_u8(&in);
    long delta = lb < 200 ? 0 : (long)(lb % 16) - 8; /* buffer length off by -8..7 */
    uint32_t split = fz_u16(&in);
    if (given.exterior != 0 || given.max_view_angle_deg != 0.0f)
        crop_field(&f, &w, &h, FZ_RAYSET_SIDE, heights);
    if (given.occluder_count != 0) crop_field(&f, &w, &h, FZ_OCCLUDER_SIDE, heights);

    /* NULL options bake as the method's defaults (what the row bakes then pass). */
    const hf_bake_options *op = null_options ? NULL : &given;
    uint32_t built = 0;
    hf_result rb = fz_code(hf_build_has_method(method, &built), "hf_build_has_method");
    hf_bake_options o = given;
    if (null_options && rb == HF_OK && built &&
        fz_code(hf_bake_options_default(method, &o), "hf_bake_options_default") != HF_OK)
        FZ_FAIL("no default options for method %u", (unsigned)method);
    int valid = rb == HF_OK && built && options_valid(&o);
    char what[32] = "unknown method";
    size_t written = 0;
    hf_method_name(method, what, sizeof what, &written);

    size_t need = 0, elem = float_map(method) ? sizeof(float) : 1;
    hf_result lr = fz_code(hf_map_len(method, w, h, op, &need), "hf_map_len");
    if ((lr == HF_OK) != valid)
        FZ_FAIL("%s: hf_map_len answered %u for %s options", what, (unsigned)lr,
                valid ? "valid" : "invalid");
    if (lr != HF_OK) need = 0;
    size_t len = (long)need + delta < 0 ? 0 : (size_t)((long)need + delta);
    void *map = fz_buf(len * elem), *again = fz_buf(len * elem);
    hf_result r = hf_bake(method, f, op, map, len);
    fz_after(r, map, len * elem, what);
    if (lr != HF_OK && r != lr)
        FZ_FAIL("%s: hf_bake answered %u where hf_map_len answered %u", what, (unsigned)r,
                (unsigned)lr);
    int good = need ? len >= need : len == 0;
    if (lr == HF_OK && (r == HF_OK) != good)
        FZ_FAIL("%s: hf_bake answered %u on %zu of %zu elements", what, (unsigned)r, len,
                need);

    if (r == HF_OK) {
        bake_by_rows(method, f, &o, w, h, need, split, map, again, len, elem, what);
        if (method == HF_METHOD_MAXMIP) bake_by_levels(f, w, h, split, map, again, len);
    }
    if (r == HF_OK && need) {
        check_desc(f, w, h, map, need * elem, what);
        trace_map(&in, f, w, h, method, &o, map, len, what);
    }
    free(map);
    free(again);
    hf_field_destroy(f);
    return 0;
}
