/* Reading 16-bit grayscale height maps (the PNGs of ../shared/data and data/). */
#ifndef HFCAST_PNG16_H
#define HFCAST_PNG16_H

#include <stdint.h>

/* Reads a grayscale PNG (8 or 16 bits) as 16-bit samples (8-bit values widened
 * v * 257), row by row, into a malloc'ed array the caller frees; NULL when the file
 * cannot be read or is not such a PNG. */
uint16_t *read_png_gray16(const char *path, uint32_t *w, uint32_t *h);

#endif
