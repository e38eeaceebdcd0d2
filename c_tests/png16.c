/* Reading 16-bit grayscale height maps: shared by the OpenGL renderers and the Embree
 * benchmark. */
#include "png16.h"

#include <png.h>
#include <stdio.h>
#include <stdlib.h>

/* Reads a grayscale PNG (8 or 16 bits) as 16-bit samples (8-bit values widened v * 257). */
uint16_t *read_png_gray16(const char *path, uint32_t *w, uint32_t *h) {
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    uint16_t *out = NULL;
    png_bytep row = NULL;
    if (setjmp(png_jmpbuf(png))) {
        free(out);
        free(row);
        out = NULL;
        goto done;
    }
    png_init_io(png, fp);
    png_read_info(png, info);
    *w = png_get_image_width(png, info);
    *h = png_get_image_height(png, info);
    int depth = png_get_bit_depth(png, info);
    int type = png_get_color_type(png, info);
    if (type != PNG_COLOR_TYPE_GRAY || (depth != 8 && depth != 16)) {
        fprintf(stderr, "%s: not an 8/16-bit grayscale PNG\n", path);
        goto done;
    }
    out = (uint16_t *)malloc(sizeof(uint16_t) * (size_t)*w * *h);
    row = (png_bytep)malloc(png_get_rowbytes(png, info));
    for (uint32_t j = 0; j < *h; j++) {
        png_read_row(png, row, NULL);
        for (uint32_t i = 0; i < *w; i++) {
            out[(size_t)j * *w + i] = depth == 16 ? (uint16_t)((row[2 * i] << 8) | row[2 * i + 1])
                                                  : (uint16_t)(row[i] * 257);
        }
    }
    free(row);
    row = NULL;
done:
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return out;
}
