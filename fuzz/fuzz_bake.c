/* libFuzzer target: every bake of libhfcast with arbitrary sizes and options.
 * Input: a field (fz_field), a bake (maximum mipmap whole, threaded or by rows;
 * safety distances; cylinder–cone; radius; cone; relaxed cone; QDM), its options
 * (raw enum values now and then), ray classes, a thread count (0..4), an output length
 * off the needed one by a fuzzed amount, a row split, then a few rays. Checks: a valid
 * code; a failing bake writes nothing, a succeeding one nothing past its length;
 * the whole bake equals the same bake in two row ranges and on one thread; the map
 * then traces the rays as the exact method does (bit for bit for maxmip; on stable rays
 * for the exact options of the others, fz_compare); its descriptor (hf_map_read_desc)
 * names the field's fingerprint and size. */
#include "common.h"

enum { B_MAXMIP, B_MAXMIP_THREADED, B_SAFETY, B_CC, B_RADIUS, B_CONE, B_RELAXED, B_QDM, B_COUNT };

/* An option value: mostly a small valid one, now and then any u32. */
static uint32_t opt(fz_in *in, uint32_t valid_below) {
    uint8_t k = fz_u8(in);
    if (k >= 248) return fz_u32(in);
    return k % valid_below;
}

static void same_bytes(const void *a, const void *b, size_t len, const char *what) {
    if (memcmp(a, b, len) != 0) FZ_FAIL("%s: the maps differ", what);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fz_in in = {data, size};
    static float heights[FZ_MAX_SIDE * FZ_MAX_SIDE];
    uint32_t w, h;
    hf_field *f = fz_field(&in, FZ_MAX_SIDE, &w, &h, heights);
    int bake = fz_u8(&in) % B_COUNT;
    uint32_t threads = fz_u8(&in) % 5;
    uint8_t lb = fz_u8(&in);
    long delta = lb < 200 ? 0 : (long)(lb % 16) - 8; /* buffer length off by -8..7 */
    uint32_t split = fz_u16(&in);
    uint32_t classes = opt(&in, 16); /* 0: all four; > 15 is an error */
    hf_safety_options so = {opt(&in, 2), opt(&in, 2), opt(&in, 256), classes};
    hf_cc_options co = {opt(&in, 2), opt(&in, 256), classes};
    hf_radius_options ro = {(fz_u8(&in) < 200) ? 0.0f : fz_range(&in, -1.0f, 4.0f), opt(&in, 256)};
    if (fz_u8(&in) == 255) ro.tolerance = fz_raw_float(&in);

    /* Elements of the map and their size; what the exact comparison traces with. */
    size_t need = 0, elem = 1;
    hf_result lr;
    const char *what = "";
    switch (bake) {
    case B_MAXMIP:
    case B_MAXMIP_THREADED:
        lr = hf_maxmip_len(w, h, &need), elem = sizeof(float), what = "maxmip";
        break;
    case B_SAFETY:
        lr = hf_safety_map_len(w, h, so.variant, classes, &need), what = "safety";
        break;
    case B_CC: lr = hf_cc_map_len(w, h, classes, &need), what = "cc"; break;
    case B_RADIUS: lr = hf_radius_map_len(w, h, &need), what = "radius"; break;
    case B_CONE: lr = hf_cone_map_len(w, h, &need), elem = sizeof(float), what = "cone"; break;
    case B_RELAXED:
        lr = hf_relaxed_map_len(w, h, &need), elem = sizeof(float), what = "relaxed";
        break;
    default: lr = hf_qdm_map_len(w, h, &need), elem = sizeof(float), what = "qdm"; break;
    }
    fz_code(lr, what);
    if (lr != HF_OK) {
        /* Only the options can be wrong here (classes, variant). */
        if (classes <= 15 && so.variant <= 1)
            FZ_FAIL("%s: the length of a valid map was refused with %u", what, (unsigned)lr);
        hf_field_destroy(f);
        return 0;
    }
    size_t len = (long)need + delta < 0 ? 0 : (size_t)((long)need + delta);
    void *map = fz_buf(len * elem), *again = fz_buf(len * elem);
    hf_result r, r2 = HF_OK;
    uint32_t rows = h, rows_end = h;
    switch (bake) {
    case B_MAXMIP:
    case B_MAXMIP_THREADED: {
        r = bake == B_MAXMIP ? hf_maxmip_bake(f, (float *)map, len)
                             : hf_maxmip_bake_threaded(f, threads, (float *)map, len);
        if (r != HF_OK) break;
        /* By rows, each level split in two, finest first. */
        hf_level levels[HF_MAX_LEVELS];
        uint32_t count = 0;
        if (fz_code(hf_maxmip_levels(w, h, levels, HF_MAX_LEVELS, &count), "hf_maxmip_levels"))
            FZ_FAIL("hf_maxmip_levels failed");
        for (uint32_t l = 0; l < count && r2 == HF_OK; l++) {
            uint32_t mid = split % (levels[l].height + 1);
            r2 = hf_maxmip_bake_rows(f, l, mid, levels[l].height, (float *)again, len);
            if (r2 == HF_OK) r2 = hf_maxmip_bake_rows(f, l, 0, mid, (float *)again, len);
        }
        if (fz_code(r2, "hf_maxmip_bake_rows") == HF_OK)
            same_bytes(map, again, len * elem, "maxmip by rows");
        break;
    }
    case B_SAFETY:
    case B_CC:
    case B_RADIUS: {
        if (bake == B_SAFETY) r = hf_safety_bake(f, &so, threads, (uint8_t *)map, len);
        else if (bake == B_CC) r = hf_cc_bake(f, &co, threads, (uint8_t *)map, len);
        else r = hf_radius_bake(f, &ro, threads, (uint8_t *)map, len);
        if (r != HF_OK) break;
        size_t slen = 0, nlen = 0;
        if (fz_code(hf_safety_scratch_len(w, h, &slen), "hf_safety_scratch_len"))
            FZ_FAIL("hf_safety_scratch_len failed");
        float *scratch = (float *)fz_buf(slen * sizeof(float));
        fz_after(hf_safety_prepare(f, scratch, slen), scratch, slen * sizeof(float),
                 "hf_safety_prepare");
        float *nb = NULL;
        if (bake == B_CC) {
            if (fz_code(hf_cc_nbuffer_len(w, h, co.cap, &nlen), "hf_cc_nbuffer_len"))
                FZ_FAIL("hf_cc_nbuffer_len failed");
            nb = (float *)fz_buf(nlen * sizeof(float));
            fz_after(hf_cc_prepare_nbuffer(f, co.cap, nb, nlen), nb, nlen * sizeof(float),
                     "hf_cc_prepare_nbuffer");
        }
        uint32_t mid = split % (h + 1);
        for (int part = 0; part < 2 && r2 == HF_OK; part++) {
            uint32_t b = part ? 0 : mid, e = part ? mid : h;
            if (bake == B_SAFETY)
                r2 = hf_safety_bake_rows(f, scratch, slen, &so, b, e, (uint8_t *)again, len);
            else if (bake == B_CC)
                r2 = hf_cc_bake_rows(f, scratch, slen, nb, nlen, &co, b, e, (uint8_t *)again,
                                     len);
            else
                r2 = hf_radius_bake_rows(f, scratch, slen, &ro, b, e, (uint8_t *)again, len);
        }
        if (fz_code(r2, "row bake") != HF_OK)
            FZ_FAIL("%s: the row bake failed with %u after the whole bake succeeded", what,
                    (unsigned)r2);
        same_bytes(map, again, len, what);
        free(scratch);
        free(nb);
        break;
    }
    default: {
        if (bake == B_CONE) r = hf_cone_bake(f, threads, (float *)map, len);
        else if (bake == B_RELAXED) r = hf_relaxed_bake(f, threads, (float *)map, len);
        else r = hf_qdm_bake(f, threads, (float *)map, len);
        if (r != HF_OK) break;
        size_t slen = 0;
        if (fz_code(hf_cone_scratch_len(w, h, &slen), "hf_cone_scratch_len"))
            FZ_FAIL("hf_cone_scratch_len failed");
        float *scratch = (float *)fz_buf(slen * sizeof(float));
        fz_after(hf_cone_prepare(f, scratch, slen), scratch, slen * sizeof(float),
                 "hf_cone_prepare");
        rows = bake == B_RELAXED ? h : h - 1;
        rows_end = rows;
        uint32_t mid = split % (rows + 1);
        for (int part = 0; part < 2 && r2 == HF_OK; part++) {
            uint32_t b = part ? 0 : mid, e = part ? mid : rows_end;
            if (bake == B_CONE) r2 = hf_cone_bake_rows(f, scratch, slen, b, e, (float *)again, len);
            else if (bake == B_RELAXED)
                r2 = hf_relaxed_bake_rows(f, scratch, slen, b, e, (float *)again, len);
            else r2 = hf_qdm_bake_rows(f, scratch, slen, b, e, (float *)again, len);
        }
        if (fz_code(r2, "row bake") != HF_OK)
            FZ_FAIL("%s: the row bake failed with %u", what, (unsigned)r2);
        same_bytes(map, again, len * elem, what);
        free(scratch);
        break;
    }
    }
    fz_after(r, map, len * elem, what);
    if (r == HF_OK && len < need) FZ_FAIL("%s accepted %zu < %zu elements", what, len, need);
    if (r != HF_OK && len >= need && bake != B_SAFETY && bake != B_CC && bake != B_RADIUS)
        FZ_FAIL("%s refused a good buffer with %u", what, (unsigned)r);

    if (r == HF_OK) {
        /* The descriptor after the texels names this field's heights and size. */
        hf_map_desc d;
        uint64_t fp = 0, generation = 0;
        if (fz_code(hf_field_get_fingerprint(f, &fp, &generation), "hf_field_get_fingerprint") ||
            fz_code(hf_map_read_desc(map, need * elem, &d), "hf_map_read_desc") != HF_OK ||
            d.fingerprint != fp || d.flags != HF_MAP_FINGERPRINT_KNOWN || d.map.width != w ||
            d.map.height != h || d.texel_bytes != need * elem - HF_MAP_DESC_BYTES)
            FZ_FAIL("%s: the descriptor does not describe the bake", what);
        /* The map traces as the exact method (for the options that make it exact). */
        int exact_opts = (bake != B_SAFETY || so.positive == 0) &&
                         (bake != B_RADIUS || ro.tolerance == 0.0f);
        size_t n = fz_u8(&in) % 17;
        hf_ray rays[16];
        hf_hit exact[16], got[16];
        int raw = 0, any_raw = 0;
        for (size_t k = 0; k < n; k++) {
            rays[k] = fz_ray(&in, w, h, &raw);
            any_raw |= raw;
        }
        hf_result re = n ? hf_trace_batch(f, HF_METHOD_EXACT, NULL, 0, NULL, rays, n, exact, n)
                         : HF_ERR_INVALID_ARGUMENT;
        fz_code(re, "exact batch");
        if (re != HF_OK && n && !any_raw) FZ_FAIL("exact refused valid rays");
        if (re == HF_OK && bake != B_RELAXED) {
            /* The bake's method; the safety and cc traces name the bake's classes, the
             * cap and the safety layout are the descriptor's. */
            static const uint32_t api[B_COUNT] = {HF_METHOD_MAXMIP, HF_METHOD_MAXMIP,
                                                  HF_METHOD_SAFETY, HF_METHOD_CC,
                                                  HF_METHOD_RADIUS, HF_METHOD_CONE,
                                                  HF_METHOD_RELAXED, HF_METHOD_QDM};
            hf_trace_options o;
            hf_trace_options_default(&o);
            o.ray_classes = bake == B_SAFETY || bake == B_CC ? classes : 0;
            o.steps = 1000; /* cone, QDM iterations */
            hf_result rt = hf_trace_batch(f, api[bake], map, len, &o, rays, n, got, n);
            if (fz_code(rt, what) != HF_OK)
                FZ_FAIL("%s: tracing its own map failed with %u", what, (unsigned)rt);
            if (exact_opts)
                fz_compare(f, HF_SURFACE_TRIANGLES, rays, (int)n, exact, got,
                           bake == B_MAXMIP || bake == B_MAXMIP_THREADED, what);
        }
    }
    free(map);
    free(again);
    hf_field_destroy(f);
    return 0;
}
