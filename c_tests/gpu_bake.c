/* GPU bakes in OpenGL compute shaders and the dynamic-terrain scene (gpu_bake.h). */
#include "gpu_bake.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The GLSL source of a GPU bake from the C API (`len_fn`, `src_fn`), in a new buffer. */
static char *bake_source(hf_result (*len_fn)(uint32_t, size_t *),
                         hf_result (*src_fn)(uint32_t, char *, size_t, size_t *)) {
    size_t len = 0, written = 0;
    if (len_fn(HF_SHADER_GLSL, &len) != HF_OK) return NULL;
    char *src = (char *)malloc(len);
    if (src_fn(HF_SHADER_GLSL, src, len, &written) != HF_OK) {
        free(src);
        return NULL;
    }
    return src;
}

/* A buffer object of `bytes` bytes (`data` or unset) for `target`. */
static GLuint make_buffer(GLenum target, size_t bytes, const void *data) {
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    glBufferData(target, (GLsizeiptr)bytes, data, GL_DYNAMIC_COPY);
    return b;
}

int gpu_bakes_init(gpu_bakes *b, uint32_t w, uint32_t h) {
    memset(b, 0, sizeof *b);
    char *maxmip = bake_source(hf_maxmip_bake_shader_len, hf_maxmip_bake_shader);
    char *nbuffer = bake_source(hf_nbuffer_bake_shader_len, hf_nbuffer_bake_shader);
    char *safety = bake_source(hf_safety_bake_shader_len, hf_safety_bake_shader);
    char *cc = bake_source(hf_cc_bake_shader_len, hf_cc_bake_shader);
    if (!maxmip || !nbuffer || !safety || !cc) {
        fprintf(stderr, "the library has no GLSL GPU bakes\n");
        free(maxmip);
        free(nbuffer);
        free(safety);
        free(cc);
        return -1;
    }
    b->maxmip = link_compute(maxmip);
    b->nbuffer = link_compute(nbuffer);
    b->safety = link_compute(safety);
    b->cc = link_compute(cc);
    free(maxmip);
    free(nbuffer);
    free(safety);
    free(cc);
    hf_bake_options o;
    if (hf_bake_options_default(HF_METHOD_MAXMIP, &o) != HF_OK) return -1;
    if (hf_map_len(HF_METHOD_MAXMIP, w, h, &o, &b->pyramid_len) != HF_OK) return -1;
    /* hf_map_len counts the descriptor after the texels: the shader writes texels only. */
    hf_level levels[HF_MAX_LEVELS];
    uint32_t n = 0;
    if (hf_maxmip_levels(w, h, levels, HF_MAX_LEVELS, &n) != HF_OK) return -1;
    b->pyramid_len = levels[n - 1].offset + (size_t)levels[n - 1].width * levels[n - 1].height;
    b->pyramid = make_buffer(GL_SHADER_STORAGE_BUFFER, sizeof(float) * b->pyramid_len, NULL);
    b->pass = make_buffer(GL_UNIFORM_BUFFER, 64, NULL);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

void gpu_bakes_free(gpu_bakes *b) {
    glDeleteProgram(b->maxmip);
    glDeleteProgram(b->nbuffer);
    glDeleteProgram(b->safety);
    glDeleteProgram(b->cc);
    glDeleteBuffers(1, &b->pyramid);
    glDeleteBuffers(1, &b->pass);
}

/* One dispatch of `program` with the pass uniform `uniform` (`bytes`) at binding
 * `pass_binding`, then a barrier before the next pass reads what it wrote. */
static void dispatch(gpu_bakes *b, GLuint program, GLuint pass_binding, const void *uniform,
                     size_t bytes, const uint32_t workgroups[2]) {
    glUseProgram(program);
    glBindBuffer(GL_UNIFORM_BUFFER, b->pass);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, (GLsizeiptr)bytes, uniform);
    glBindBufferBase(GL_UNIFORM_BUFFER, pass_binding, b->pass);
    glDispatchCompute(workgroups[0], workgroups[1], 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
}

/* Copies pyramid texels [first, first + count) from the storage buffer (bound as the
 * pixel unpack buffer) into the pyramid texture, row span by row span. */
static void copy_span(size_t first, size_t count) {
    while (count > 0) {
        size_t x = first % HF_PYRAMID_TEX_WIDTH, y = first / HF_PYRAMID_TEX_WIDTH;
        size_t n = HF_PYRAMID_TEX_WIDTH - x < count ? HF_PYRAMID_TEX_WIDTH - x : count;
        glTexSubImage2D(GL_TEXTURE_2D, 0, (GLint)x, (GLint)y, (GLsizei)n, 1, GL_RED, GL_FLOAT,
                        (const void *)(first * sizeof(float)));
        first += n;
        count -= n;
    }
}

long gpu_pyramid_bake(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights,
                      const uint32_t *rect, GLuint tex_pyramid) {
    hf_maxmip_pass passes[HF_MAX_LEVELS];
    uint32_t n = 0;
    if (hf_maxmip_bake_passes(w, h, rect, passes, HF_MAX_LEVELS, &n) != HF_OK) return -1;
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex_heights);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 13, b->pyramid);
    long texels = 0;
    for (uint32_t p = 0; p < n; p++) {
        dispatch(b, b->maxmip, 14, passes[p].uniform, sizeof passes[p].uniform,
                 passes[p].workgroups);
        const uint32_t *u = passes[p].uniform; /* level, offset, width, .., lo, hi */
        texels += (long)(u[8] - u[6]) * (long)(u[9] - u[7]);
    }
    if (tex_pyramid) {
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, b->pyramid);
        glBindTexture(GL_TEXTURE_2D, tex_pyramid);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        if (!rect) copy_span(0, b->pyramid_len);
        for (uint32_t p = 0; rect && p < n; p++) {
            const uint32_t *u = passes[p].uniform;
            for (uint32_t j = u[7]; j < u[9]; j++)
                copy_span(u[1] + (size_t)j * u[2] + u[6], u[8] - u[6]);
        }
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    }
    return glGetError() == GL_NO_ERROR ? texels : -1;
}

/* Reads the first `floats` floats of storage buffer `buffer` into `out`. */
static void read_buffer(GLuint buffer, float *out, size_t floats) {
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(sizeof(float) * floats), out);
}

void gpu_pyramid_read(const gpu_bakes *b, float *out) { read_buffer(b->pyramid, out, b->pyramid_len); }

/* A new storage buffer of the N-buffers (`len` = hf_nbuffer_len floats) of the heights
 * in `tex_heights` for the cone reach `cap`, filled on the GPU; 0 on an error. */
static GLuint fill_nbuffers(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights,
                            uint32_t cap, size_t len) {
    hf_bake_pass passes[HF_NBUFFER_MAX_PASSES];
    uint32_t n = 0;
    size_t need = 0;
    if (hf_nbuffer_len(w, h, cap, &need) != HF_OK || need != len) return 0;
    if (hf_nbuffer_bake_passes(w, h, cap, passes, HF_NBUFFER_MAX_PASSES, &n) != HF_OK) return 0;
    GLuint nb = make_buffer(GL_SHADER_STORAGE_BUFFER, sizeof(float) * len, NULL);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex_heights);
    for (uint32_t p = 0; p < n; p++) {
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 15, nb, (GLintptr)passes[p].bind_offset,
                          (GLsizeiptr)passes[p].bind_size);
        dispatch(b, b->nbuffer, 16, passes[p].uniform, sizeof passes[p].uniform,
                 passes[p].workgroups);
    }
    return nb;
}

int gpu_nbuffer_bake(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights, uint32_t cap,
                     float *out, size_t len) {
    GLuint nb = fill_nbuffers(b, w, h, tex_heights, cap, len);
    if (!nb) return -1;
    read_buffer(nb, out, len);
    glDeleteBuffers(1, &nb);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

/* Runs the two passes of the safety shader `program` (strip bounds, then the map)
 * and reads `len` bytes of the map back into `out`. */
static int run_safety_passes(gpu_bakes *b, GLuint program, const hf_bake_pass passes[2],
                             GLuint tex_heights, unsigned char *out, size_t len) {
    size_t out_bytes = (size_t)passes[1].bind_size;
    if (len > out_bytes) return -1;
    GLuint scratch = make_buffer(GL_SHADER_STORAGE_BUFFER, (size_t)passes[0].bind_size, NULL);
    GLuint map = make_buffer(GL_SHADER_STORAGE_BUFFER, out_bytes, NULL);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex_heights);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 17, scratch);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 18, map);
    for (int p = 0; p < 2; p++)
        dispatch(b, program, 19, passes[p].uniform, sizeof passes[p].uniform, passes[p].workgroups);
    /* The words' bytes are the map's in order on a little-endian machine. */
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, map);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)len, out);
    glDeleteBuffers(1, &scratch);
    glDeleteBuffers(1, &map);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

int gpu_safety_bake(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights,
                    const hf_bake_options *options, unsigned char *out, size_t len) {
    hf_bake_pass passes[2];
    uint32_t n = 0;
    if (hf_safety_bake_passes(w, h, options, passes, 2, &n) != HF_OK || n != 2) return -1;
    return run_safety_passes(b, b->safety, passes, tex_heights, out, len);
}

int gpu_cc_bake(gpu_bakes *b, uint32_t w, uint32_t h, GLuint tex_heights,
                const hf_bake_options *options, unsigned char *out, size_t len) {
    hf_bake_pass passes[2];
    uint32_t n = 0;
    size_t nb_len = 0;
    GLint block = 0;
    if (hf_cc_bake_passes(w, h, options, passes, 2, &n) != HF_OK || n != 2) return -1;
    if (hf_nbuffer_len(w, h, options->cap, &nb_len) != HF_OK) return -1;
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    if (sizeof(float) * nb_len > (size_t)(GLuint)block) return 1;
    GLuint nb = fill_nbuffers(b, w, h, tex_heights, options->cap, nb_len);
    if (!nb) return -1;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 15, nb);
    int rc = run_safety_passes(b, b->cc, passes, tex_heights, out, len);
    glDeleteBuffers(1, &nb);
    return rc;
}

int dynamic_edit(scene *s, GLuint tex_heights, int k, uint32_t rect[4], double *cpu_ms) {
    uint32_t side = s->w < s->h ? s->w : s->h;
    uint32_t r = side / 16 > 2 ? side / 16 : 2;
    double a = 0.7 * k;
    double cx = 0.5 * s->w + 0.3 * s->w * cos(a), cy = 0.5 * s->h + 0.3 * s->h * sin(a);
    uint32_t x0 = cx > r ? (uint32_t)(cx - r) : 0, y0 = cy > r ? (uint32_t)(cy - r) : 0;
    uint32_t x1 = (uint32_t)(cx + r) + 1, y1 = (uint32_t)(cy + r) + 1;
    if (x1 > s->w) x1 = s->w;
    if (y1 > s->h) y1 = s->h;
    uint32_t rw = x1 - x0, rh = y1 - y0;
    float *v = (float *)malloc(sizeof(float) * rw * rh);
    for (uint32_t j = 0; j < rh; j++)
        for (uint32_t i = 0; i < rw; i++) {
            double d = hypot(x0 + i - cx, y0 + j - cy);
            float *h = &s->heights[(size_t)(y0 + j) * s->w + x0 + i];
            if (d < r) *h += (float)(0.6 * (r - d));
            v[j * rw + i] = *h;
        }
    double t0 = now_seconds();
    hf_result e = hf_field_update_rect(s->field, x0, y0, x1, y1, v, (size_t)rw * rh, rw);
    if (e == HF_OK) e = hf_maxmip_update_rect(s->field, x0, y0, x1, y1, s->pyramid, s->pyramid_len);
    /* The field's height range widened: the shaders' field uniforms read it. */
    if (e == HF_OK) e = hf_field_get_info(s->field, &s->info);
    *cpu_ms = 1e3 * (now_seconds() - t0);
    if (e != HF_OK) {
        fprintf(stderr, "dynamic edit: hf_result %u\n", (unsigned)e);
        free(v);
        return -1;
    }
    glBindTexture(GL_TEXTURE_2D, tex_heights);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, (GLint)x0, (GLint)y0, (GLsizei)rw, (GLsizei)rh, GL_RED,
                    GL_FLOAT, v);
    free(v);
    rect[0] = x0;
    rect[1] = y0;
    rect[2] = x1;
    rect[3] = y1;
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}
