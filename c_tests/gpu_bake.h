/* GPU bakes in OpenGL 4.3+ compute shaders, as a C program uses them: the shaders of
 * hf_maxmip_bake_shader, hf_nbuffer_bake_shader, hf_safety_bake_shader and
 * hf_cc_bake_shader (GLSL), dispatched pass by pass from their *_bake_passes; and the dynamic-terrain scene
 * that edits the heights every frame and refreshes the pyramid on the GPU for the
 * edited rectangle only. Shared by both OpenGL renderers. */
#ifndef HFCAST_GPU_BAKE_H
#define HFCAST_GPU_BAKE_H

#include "render_common.h"

typedef struct gpu_bakes {
    GLuint maxmip, nbuffer, safety, cc; /* the compute programs */
    GLuint pyramid;         /* storage buffer of the pyramid (hf_pyramid_out) */
    size_t pyramid_len;     /* its floats */
    GLuint pass;            /* uniform buffer of one pass's uniform */
} gpu_bakes;

/* Compiles both bakes and makes the pyramid buffer of a W x H field. 0, or -1. */
int gpu_bakes_init(gpu_bakes *b, uint32_t w, uint32_t h);
void gpu_bakes_free(gpu_bakes *b);

/* Bakes the pyramid of the heights in `tex_heights` (R32F W x H) into b->pyramid
 * (`rect` NULL), or refreshes the texels that depend on the samples rect = {x0, y0,
 * x1, y1}; then, when `tex_pyramid` is not 0, copies the texels written into it (the
 * renderers' pyramid texture, rows of HF_PYRAMID_TEX_WIDTH) on the GPU. Returns the
 * texels written, or -1. */
long gpu_pyramid_bake(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights,
                      const uint32_t *rect, GLuint tex_pyramid);
/* Reads b->pyramid back (pyramid_len floats). */
void gpu_pyramid_read(const gpu_bakes *b, float *out);

/* Fills the N-buffers of the heights in `tex_heights` (W x H) for the cone reach `cap`
 * on the GPU and reads them back into `out` (`len` = hf_nbuffer_len floats). 0, or -1. */
int gpu_nbuffer_bake(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights, uint32_t cap,
                     float *out, size_t len);

/* Bakes the safety distances for every ray of the heights in `tex_heights` (W x H) with
 * `options` (HF_METHOD_SAFETY's, every ray and class) on the GPU, in doubles, and
 * reads the map's bytes back into `out` (`len` = the map's texels: hf_map_len less
 * HF_MAP_DESC_BYTES). 0, or -1. */
int gpu_safety_bake(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights,
                    const hf_bake_options *options, unsigned char *out, size_t len);

/* Bakes the cylinder-cone map with N-buffer slopes (`options`: HF_METHOD_CC's with
 * HF_CC_SLOPE_NBUFFER, every ray and class) of the heights in `tex_heights` on the GPU:
 * its N-buffers, then the map; reads the map's bytes back into `out` (`len` = the
 * map's texels). 1 when the N-buffers exceed what one storage block may hold here
 * (GL_MAX_SHADER_STORAGE_BLOCK_SIZE: nothing baked), 0, or -1. */
int gpu_cc_bake(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights,
                const hf_bake_options *options, unsigned char *out, size_t len);

/* Frame `k` of the dynamic scene: a mound of radius r = max(2, min(W, H) / 16) and
 * height 0.6 r rises at a point that circles the field's centre (raised, not sunk:
 * a pyramid left stale under raised heights is wrong, so the parity sees a missed
 * refresh). Updates the CPU side
 * (s->heights, s->field by hf_field_update_rect, s->pyramid by hf_maxmip_update_rect,
 * their time in *cpu_ms, and s->info, the height range the shaders read) and uploads the edited rectangle into `tex_heights`; writes the
 * rectangle to `rect` (the GPU pyramid is then refreshed with gpu_pyramid_bake). 0,
 * or -1. */
int dynamic_edit(scene *s, GLuint tex_heights, int k, uint32_t rect[4], double *cpu_ms);

#endif
