/* KTX 2 files of baked maps through the C API: every map kind baked through the C
 * API on a synthetic field, written with hf_ktx2_write, read back with
 * hf_ktx2_read_info / hf_ktx2_read_map / hf_ktx2_read_level and compared byte for byte
 * and field by field; bad input (NULL, short buffers, a truncated file, another
 * identifier, a bad description) returns its error and writes nothing.
 * Built by the Makefile with -Wall -Wextra -Werror -std=c99, run plain and under
 * -fsanitize=address,undefined. */
#include "hfcast.h"

#include "check_api.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 19u
#define H 12u

/* A baked map: its bytes and its description. */
typedef struct {
    const char *name;
    hf_ktx2_desc desc;
    void *data;
    size_t len; /* bytes */
    uint32_t vk_format;
} baked;

/* Each baked map kind: its name, Vulkan format, the method that bakes it and the bytes
 * of one element of its map (floats or bytes). */
static const struct {
    uint32_t map;
    const char *name;
    uint32_t vk_format, method;
    size_t elem;
} KINDS[] = {
    {HF_KTX2_MAXMIP, "maxmip", 100, HF_METHOD_MAXMIP, 4},
    {HF_KTX2_SAFETY, "safety", 13, HF_METHOD_SAFETY, 1},
    {HF_KTX2_SAFETY_ISOTROPIC, "safety-isotropic", 13, HF_METHOD_SAFETY, 1},
    {HF_KTX2_CC, "cc", 20, HF_METHOD_CC, 1},
    {HF_KTX2_CONE, "cone", 103, HF_METHOD_CONE, 4},
    {HF_KTX2_RELAXED, "relaxed", 100, HF_METHOD_RELAXED, 4},
    {HF_KTX2_QDM, "qdm", 109, HF_METHOD_QDM, 4},
    {HF_KTX2_RADIUS, "radius", 13, HF_METHOD_RADIUS, 1},
};

/* Bakes map `map` of `field` with `classes` (class-row maps only) through the C API:
 * safety distances of cap 40, exact cylinder-cone shapes of cap 64 (on 2 threads),
 * radii of tolerance 0.5 and cap 200. */
static baked bake(const hf_field *field, uint32_t map, uint32_t classes) {
    baked b;
    memset(&b, 0, sizeof b);
    CHECK(hf_ktx2_desc_default(map, W, H, &b.desc) == HF_OK);
    b.desc.ray_classes = classes;
    size_t n = 0;
    CHECK(hf_ktx2_map_len(&b.desc, &n) == HF_OK);
    b.len = n;
    b.data = malloc(n);
    if (map == HF_KTX2_HEIGHTS) {
        b.name = "heights", b.vk_format = 100;
        CHECK(hf_field_copy_heights(field, (float *)b.data, n / 4) == HF_OK);
        CHECK(n == W * H * 4);
        return b;
    }
    size_t k = 0;
    while (k + 1 < sizeof KINDS / sizeof KINDS[0] && KINDS[k].map != map) k++;
    CHECK(KINDS[k].map == map);
    b.name = KINDS[k].name, b.vk_format = KINDS[k].vk_format;
    uint32_t method = KINDS[k].method;
    hf_bake_options o;
    CHECK(hf_bake_options_default(method, &o) == HF_OK);
    o.ray_classes = classes;
    o.variant = map == HF_KTX2_SAFETY_ISOTROPIC ? HF_SAFETY_ISOTROPIC : HF_SAFETY_DIRECTIONAL;
    o.threads = map == HF_KTX2_CC ? 2 : 1;
    if (method == HF_METHOD_SAFETY) o.cap = b.desc.cap = 40;
    if (method == HF_METHOD_RADIUS) {
        o.cap = b.desc.cap = 200;
        o.tolerance = b.desc.tolerance = 0.5f;
    }
    size_t want = 0;
    CHECK(hf_map_len(method, W, H, &o, &want) == HF_OK);
    CHECK(want * KINDS[k].elem == n); /* the container's size of the map is the bake's */
    CHECK(hf_bake(method, field, &o, b.data, n / KINDS[k].elem) == HF_OK);
    return b;
}

/* Writes `b` to a file and reads everything back. */
static void round_trip(const baked *b) {
    size_t n = 0;
    CHECK(hf_ktx2_len(&b->desc, &n) == HF_OK);
    uint8_t *file = (uint8_t *)malloc(n);
    CHECK_BAD(hf_ktx2_write(&b->desc, b->data, b->len, file, n - 1), HF_ERR_BUFFER_TOO_SMALL,
              file, n - 1);
    CHECK_BAD(hf_ktx2_write(&b->desc, b->data, b->len - 1, file, n), HF_ERR_BUFFER_TOO_SMALL,
              file, n);
    CHECK(hf_ktx2_write(&b->desc, b->data, b->len, file, n) == HF_OK);
    static const uint8_t ident[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32,
                                      0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
    CHECK(memcmp(file, ident, 12) == 0);

    hf_ktx2_info info;
    memset(&info, 0, sizeof info);
    CHECK(hf_ktx2_read_info(file, n, &info) == HF_OK);
    CHECK(info.desc.map == b->desc.map && info.desc.width == W && info.desc.height == H);
    CHECK(info.vk_format == b->vk_format);
    CHECK(info.map_len == b->len);
    int rays = b->desc.map == HF_KTX2_SAFETY || b->desc.map == HF_KTX2_SAFETY_ISOTROPIC ||
               b->desc.map == HF_KTX2_CC || b->desc.map == HF_KTX2_RADIUS;
    if (rays) {
        CHECK(info.desc.cap == b->desc.cap);
        CHECK(info.desc.ray_classes == b->desc.ray_classes);
        CHECK(info.desc.tolerance == b->desc.tolerance);
    }

    void *back = malloc(b->len);
    memset(back, 0xEE, b->len);
    CHECK_BAD(hf_ktx2_read_map(file, n, back, b->len - 1), HF_ERR_BUFFER_TOO_SMALL, back,
              b->len);
    CHECK(hf_ktx2_read_map(file, n, back, b->len) == HF_OK);
    CHECK(memcmp(back, b->data, b->len) == 0);

    size_t level_len = 0;
    CHECK(hf_ktx2_level_len(file, n, 0, &level_len) == HF_OK);
    CHECK(level_len == (size_t)info.pixel_width * info.pixel_height * info.texel_size);
    uint8_t *level = (uint8_t *)malloc(level_len);
    CHECK(hf_ktx2_read_level(file, n, 0, level, level_len) == HF_OK);
    if (b->desc.map == HF_KTX2_MAXMIP) {
        /* 18 x 11 cells: a 32 x 16 texture, pyramid level 0 row by row, -inf after. */
        hf_level lv[HF_MAX_LEVELS];
        uint32_t count = 0;
        CHECK(hf_maxmip_levels(W, H, lv, HF_MAX_LEVELS, &count) == HF_OK);
        CHECK(info.levels == count && info.pixel_width == 32 && info.pixel_height == 16);
        const float *pyr = (const float *)b->data;
        for (uint32_t j = 0; j < lv[0].height; j++)
            CHECK(memcmp(level + (size_t)j * 32 * 4, pyr + (size_t)j * lv[0].width,
                         lv[0].width * 4) == 0);
        float pad;
        memcpy(&pad, level + 4 * (size_t)lv[0].width, 4);
        CHECK(pad < -1e38f);
        size_t last = 0;
        CHECK(hf_ktx2_level_len(file, n, count - 1, &last) == HF_OK);
        CHECK(last == 4);
        uint8_t top[4];
        CHECK(hf_ktx2_read_level(file, n, count - 1, top, 4) == HF_OK);
        CHECK(memcmp(top, pyr + lv[count - 1].offset, 4) == 0);
        CHECK_BAD(hf_ktx2_level_len(file, n, count, &last), HF_ERR_INVALID_ARGUMENT, &last,
                  sizeof last);
    } else {
        /* The level holds the texels; the map's descriptor (HF_MAP_DESC_BYTES after
         * them, every map but the heights) travels as hfcast.fingerprint. */
        size_t texels = b->len - (b->desc.map == HF_KTX2_HEIGHTS ? 0 : HF_MAP_DESC_BYTES);
        CHECK(info.levels == 1);
        CHECK(level_len == texels && memcmp(level, b->data, texels) == 0);
    }
    CHECK_BAD(hf_ktx2_read_level(file, n, 0, level, level_len - 1), HF_ERR_BUFFER_TOO_SMALL,
              level, level_len - 1);

    /* Bad files: truncated, another identifier, NULL. */
    hf_ktx2_info keep = info;
    CHECK_BAD(hf_ktx2_read_info(file, n - 1, &info), HF_ERR_INVALID_ARGUMENT, &info,
              sizeof info);
    CHECK_BAD(hf_ktx2_read_info(file, 40, &info), HF_ERR_INVALID_ARGUMENT, &info,
              sizeof info);
    file[5] = '1'; /* "KTX 10" */
    CHECK_BAD(hf_ktx2_read_info(file, n, &info), HF_ERR_INVALID_ARGUMENT, &info, sizeof info);
    CHECK_BAD(hf_ktx2_read_map(file, n, back, b->len), HF_ERR_INVALID_ARGUMENT, back,
              b->len);
    file[5] = '2';
    CHECK(hf_ktx2_read_info(file, n, &info) == HF_OK && info.map_len == keep.map_len);
    CHECK_BAD(hf_ktx2_read_info(NULL, n, &info), HF_ERR_NULL_POINTER, &info, sizeof info);
    CHECK_BAD(hf_ktx2_read_info(file, n, NULL), HF_ERR_NULL_POINTER, &info, 0);
    CHECK_BAD(hf_ktx2_read_map(file, n, NULL, b->len), HF_ERR_NULL_POINTER, &info, 0);
    CHECK_BAD(hf_ktx2_write(&b->desc, NULL, b->len, file, n), HF_ERR_NULL_POINTER, file, n);
    free(level);
    free(back);
    free(file);
}

/* Bad descriptions: every size query refuses them and writes nothing. */
static void bad_descs(void) {
    hf_ktx2_desc d;
    size_t len = 7;
    CHECK_BAD(hf_ktx2_desc_default(99, W, H, &d), HF_ERR_INVALID_ENUM, &d, sizeof d);
    CHECK_BAD(hf_ktx2_desc_default(HF_KTX2_CONE, 1, H, &d), HF_ERR_INVALID_SIZE, &d, sizeof d);
    CHECK(hf_ktx2_desc_default(HF_KTX2_CC, W, H, &d) == HF_OK);
    CHECK(d.cap == 64 && d.ray_classes == HF_RAYS_ALL);
    d.ray_classes = 0;
    CHECK_BAD(hf_ktx2_len(&d, &len), HF_ERR_INVALID_ARGUMENT, &len, sizeof len);
    d.ray_classes = HF_RAYS_X_POS;
    d.cap = 256;
    CHECK_BAD(hf_ktx2_map_len(&d, &len), HF_ERR_INVALID_ARGUMENT, &len, sizeof len);
    CHECK_BAD(hf_ktx2_len(NULL, &len), HF_ERR_NULL_POINTER, &len, sizeof len);
    CHECK(hf_ktx2_desc_default(HF_KTX2_RADIUS, W, H, &d) == HF_OK);
    d.tolerance = -1.0f;
    CHECK_BAD(hf_ktx2_len(&d, &len), HF_ERR_INVALID_ARGUMENT, &len, sizeof len);
}

int main(void) {
    float heights[W * H];
    for (uint32_t j = 0; j < H; j++)
        for (uint32_t i = 0; i < W; i++)
            heights[j * W + i] = (float)((i * 7 + j * 13) % 11) * 0.5f + (i == 9 ? 4.0f : 0.0f);
    hf_field *field = NULL;
    CHECK(hf_field_create_f32(heights, W * H, W, H, W, &field) == HF_OK);
    const uint32_t maps[9] = {HF_KTX2_HEIGHTS, HF_KTX2_MAXMIP,  HF_KTX2_SAFETY,
                              HF_KTX2_SAFETY_ISOTROPIC, HF_KTX2_CC,     HF_KTX2_CONE,
                              HF_KTX2_RELAXED, HF_KTX2_QDM,     HF_KTX2_RADIUS};
    for (int m = 0; m < 9; m++) {
        uint32_t classes = maps[m] == HF_KTX2_RADIUS ? HF_RAYS_ALL : HF_RAYS_X_POS | HF_RAYS_Y_NEG;
        baked b = bake(field, maps[m], classes);
        int before = failures;
        round_trip(&b);
        if (failures != before)
            fprintf(stderr, "  (map %s)\n", b.name);
        free(b.data);
    }
    bad_descs();
    hf_field_destroy(field);
    printf("c-ktx: %d passed, %d failed\n", checks - failures, failures);
    return failures == 0 ? 0 : 1;
}
