/* libFuzzer target: field creation from arbitrary bytes, then updates.
 * Input: a format (f32, u8, u16), sizes (0..FZ_MAX_SIDE + 1, a stride and a length
 * that may be short), the depth (any float bits), the samples (raw bytes: NaN and
 * infinities among the floats), then rectangles with values for hf_field_update_rect.
 * Checks: a valid code; on error no handle written; on success the info, the copied
 * heights (f32: bit for bit) and the height bounds; an update that fails changes no
 * height, one that succeeds changes exactly its rectangle; the pyramid refreshed by
 * hf_maxmip_update_rect equals a full bake; a few rays trace as maxmip answers them. */
#include "common.h"

#define SIDE (FZ_MAX_SIDE + 2)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    fz_in in = {data, size};
    uint8_t fmt = fz_u8(&in) % 3;
    uint32_t w = fz_u8(&in) % SIDE, h = fz_u8(&in) % SIDE;
    size_t stride = w + (fz_u8(&in) % 4 == 0 ? (size_t)(fz_u8(&in) % 8) - 2 : 0);
    size_t need = h ? stride * (h - 1) + w : 0;
    uint8_t lb = fz_u8(&in);
    size_t len = lb < 220 ? need : (need + (lb % 8) >= 4 ? need + (lb % 8) - 4 : 0);
    float depth = fz_u8(&in) < 240 ? fz_range(&in, -50.0f, 50.0f) : fz_raw_float(&in);
    static float fs[SIDE * (SIDE + 8)];
    static uint16_t us[SIDE * (SIDE + 8)];
    static uint8_t bs[SIDE * (SIDE + 8)];
    size_t cap = sizeof fs / sizeof fs[0];
    if (len > cap) len = cap;
    for (size_t k = 0; k < len; k++) {
        if (fmt == 0) fs[k] = fz_u8(&in) < 250 ? fz_range(&in, -100.0f, 100.0f) : fz_raw_float(&in);
        else if (fmt == 1) us[k] = (uint16_t)fz_u16(&in);
        else bs[k] = fz_u8(&in);
    }
    hf_field *f = (hf_field *)(uintptr_t)0x5A5A5A5A;
    hf_result r;
    if (fmt == 0) r = hf_field_create_f32(fs, len, w, h, stride, &f);
    else if (fmt == 1) r = hf_field_create_u16(us, len, w, h, stride, depth, &f);
    else r = hf_field_create_u8(bs, len, w, h, stride, depth, &f);
    fz_code(r, "hf_field_create");
    if (r != HF_OK) {
        if (f != (hf_field *)(uintptr_t)0x5A5A5A5A) FZ_FAIL("a failed create wrote a handle");
        int finite = 1;
        for (size_t j = 0; fmt == 0 && stride >= w && stride <= (size_t)w + 8 && len >= need && j < h; j++)
            for (size_t i = 0; i < w; i++) finite &= isfinite(fs[j * stride + i]) != 0;
        if (w >= 2 && h >= 2 && stride >= w && stride <= (size_t)w + 8 && len >= need && finite && (fmt == 0 || fabsf(depth) <= 1e30f))
            FZ_FAIL("a valid %ux%u field (format %u) was refused with %u", w, h, fmt, (unsigned)r);
        return 0;
    }
    if (w < 2 || h < 2 || stride < w || len < need)
        FZ_FAIL("an invalid field (%ux%u stride %zu len %zu) was accepted", w, h, stride, len);

    hf_field_info info;
    if (fz_code(hf_field_get_info(f, &info), "hf_field_get_info") != HF_OK ||
        info.width != w || info.height != h)
        FZ_FAIL("hf_field_get_info disagrees with the sizes");
    static float got[SIDE * SIDE], before[SIDE * SIDE];
    size_t cells = (size_t)w * h;
    memset(got, FZ_POISON, sizeof got);
    hf_result rs = hf_field_copy_heights(f, got, cells - 1);
    fz_after(rs, got, (cells - 1) * sizeof(float), "hf_field_copy_heights (short)");
    if (rs == HF_OK) FZ_FAIL("hf_field_copy_heights accepted a short buffer");
    if (fz_code(hf_field_copy_heights(f, got, cells), "hf_field_copy_heights") != HF_OK)
        FZ_FAIL("hf_field_copy_heights failed");
    for (size_t j = 0; j < h; j++)
        for (size_t i = 0; i < w; i++) {
            float v = got[j * w + i];
            if (!isfinite(v) || v < info.min_height || v > info.max_height)
                FZ_FAIL("height (%zu, %zu) = %g outside the bounds [%g, %g]", i, j, v,
                        info.min_height, info.max_height);
            if (fmt == 0 && memcmp(&v, &fs[j * stride + i], sizeof v) != 0)
                FZ_FAIL("height (%zu, %zu) is %g, created as %g", i, j, v, fs[j * stride + i]);
        }

    size_t plen = 0;
    if (fz_code(hf_map_len(HF_METHOD_MAXMIP, w, h, NULL, &plen), "hf_map_len"))
        FZ_FAIL("hf_map_len (maxmip) failed");
    float *pyr = (float *)fz_buf(plen * sizeof(float));
    float *full = (float *)fz_buf(plen * sizeof(float));
    if (fz_code(hf_bake(HF_METHOD_MAXMIP, f, NULL, pyr, plen), "hf_bake"))
        FZ_FAIL("hf_bake (maxmip) failed");

    /* Updates: rectangles anywhere (reversed, empty, outside), values with NaN now and then. */
    int updates = fz_u8(&in) % 4;
    for (int u = 0; u < updates; u++) {
        uint32_t x0 = fz_u8(&in) % SIDE, x1 = fz_u8(&in) % SIDE;
        uint32_t y0 = fz_u8(&in) % SIDE, y1 = fz_u8(&in) % SIDE;
        size_t vstride = (x1 > x0 ? x1 - x0 : 0) + fz_u8(&in) % 3;
        size_t vneed = (y1 > y0 && x1 > x0) ? vstride * (y1 - y0 - 1) + (x1 - x0) : 0;
        size_t vlen = fz_u8(&in) < 240 ? vneed : vneed / 2;
        static float vals[SIDE * (SIDE + 2)];
        if (vlen > sizeof vals / sizeof vals[0]) vlen = sizeof vals / sizeof vals[0];
        for (size_t k = 0; k < vlen; k++)
            vals[k] = fz_u8(&in) < 252 ? fz_range(&in, -60.0f, 60.0f) : fz_raw_float(&in);
        memcpy(before, got, cells * sizeof(float));
        hf_result ru = fz_code(hf_field_update_rect(f, x0, y0, x1, y1, vals, vlen, vstride),
                               "hf_field_update_rect");
        if (fz_code(hf_field_copy_heights(f, got, cells), "hf_field_copy_heights") != HF_OK)
            FZ_FAIL("hf_field_copy_heights failed");
        if (ru != HF_OK) {
            if (memcmp(before, got, cells * sizeof(float)) != 0)
                FZ_FAIL("a failed hf_field_update_rect (%u) changed the field", (unsigned)ru);
            continue;
        }
        int empty = x0 == x1 || y0 == y1; /* HF_OK or HF_ERR_INVALID_RECT: both fine */
        if (!empty && (x1 < x0 || y1 < y0 || x1 > w || y1 > h || vlen < vneed))
            FZ_FAIL("hf_field_update_rect accepted [%u,%u)x[%u,%u) len %zu", x0, x1, y0, y1, vlen);
        for (size_t j = 0; j < h; j++)
            for (size_t i = 0; i < w; i++) {
                int in_rect = i >= x0 && i < x1 && j >= y0 && j < y1;
                float want = in_rect ? vals[(j - y0) * vstride + (i - x0)] : before[j * w + i];
                if (memcmp(&want, &got[j * w + i], sizeof want) != 0)
                    FZ_FAIL("after the update height (%zu, %zu) is %g, not %g", i, j,
                            got[j * w + i], want);
            }
        if (fz_code(hf_field_get_info(f, &info), "hf_field_get_info") != HF_OK)
            FZ_FAIL("hf_field_get_info failed");
        for (size_t k = 0; k < cells; k++)
            if (got[k] < info.min_height || got[k] > info.max_height)
                FZ_FAIL("after the update a height is outside the bounds");
        hf_result rp = fz_code(hf_maxmip_update_rect(f, x0, y0, x1, y1, pyr, plen),
                               "hf_maxmip_update_rect");
        if (rp != HF_OK && !empty) FZ_FAIL("hf_maxmip_update_rect failed with %u", (unsigned)rp);
        if (fz_code(hf_bake(HF_METHOD_MAXMIP, f, NULL, full, plen), "hf_bake"))
            FZ_FAIL("hf_bake (maxmip) failed");
        if (memcmp(pyr, full, plen * sizeof(float)) != 0)
            FZ_FAIL("the updated pyramid differs from a full bake");
    }

    /* The (possibly updated) field traces: exact and maxmip, bit for bit. */
    size_t n = fz_u8(&in) % 9;
    for (size_t k = 0; k < n; k++) {
        int raw;
        hf_ray ray = fz_ray(&in, w, h, &raw);
        hf_hit e, m;
        hf_result re =
            fz_code(hf_trace(f, HF_METHOD_EXACT, NULL, 0, NULL, &ray, &e), "hf_trace (exact)");
        hf_result rm = fz_code(hf_trace(f, HF_METHOD_MAXMIP, pyr, plen, NULL, &ray, &m),
                               "hf_trace (maxmip)");
        if ((re == HF_OK) != (rm == HF_OK)) FZ_FAIL("exact %u, maxmip %u", re, rm);
        if (re == HF_OK) fz_compare(f, HF_SURFACE_TRIANGLES, &ray, 1, &e, &m, 1, "maxmip");
    }
    free(pyr);
    free(full);
    hf_field_destroy(f);
    return 0;
}
