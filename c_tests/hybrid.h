/* Qu et al. 2003 §4, the hybrid rasterization renderer of the linear approximation
 * (view-linear) surface: every cell boundary, the vertical planes x = i and y = j over
 * the footprint, is one rectangle (W + H of them). Pass 1 rasterizes them; each
 * fragment is the pixel's ray crossing that plane, P2, kept when the ray is on or under
 * the surface there (the boundary's height interpolated from its two samples), and the
 * depth test keeps the nearest. Pass 2, one fragment per pixel, finds P1, the crossing
 * before P2 (or where the ray enters the field's box), and interpolates the clearances
 * d1 > 0 >= d2: I = P1 + d1 / (d1 - d2) (P2 - P1), the first hit on the view-linear
 * surface. Pass 2 also settles what no crossing shows, as core/src/hybrid.rs does: a ray
 * under the surface where its span begins, or one that goes under inside a cell. The
 * CPU implementation of the same passes (hf_hybrid_trace_batch) checks it, and the CPU
 * ray cast of the view-linear surface (hf_trace) is the reference. Shared by both
 * renderers. */
#ifndef HFCAST_HYBRID_H
#define HFCAST_HYBRID_H

#include "render_common.h"

typedef struct hybrid {
    GLuint pass1, pass2;   /* the programs */
    GLuint vao, vbo;       /* the W + H boundary rectangles, two triangles each */
    GLsizei vertices;
    GLuint fbo, tex_p2, rb_depth; /* pass 1's target: (t2, axis + 1, line), depth t2 */
    GLuint counters;       /* atomic counters: pass 1's fragments, those kept */
    int w, h;
} hybrid;

/* What one hybrid frame did. */
typedef struct hybrid_stats {
    double pass1_ms, pass2_ms;          /* each pass to glFinish */
    unsigned fragments, kept;           /* pass 1's fragments, and those under the surface */
} hybrid_stats;

/* The hybrid renderer of scene `s` for g's image size. 0, or -1. */
int hybrid_init(hybrid *hy, const scene *s, const gpu *g);
void hybrid_free(hybrid *hy);

/* Renders camera `c` (whose rays g holds: make_rays, gpu_upload_rays) with both passes
 * into g's frame (point, normal, colour, depth as gpu_render writes them). */
hybrid_stats hybrid_render(hybrid *hy, gpu *g, const scene *s, const camera *c);

/* A hybrid frame against the CPU: the ray cast of the view-linear surface (hf_trace)
 * and the same passes on the CPU (hf_hybrid_trace_batch). */
typedef struct hybrid_check {
    int hits;         /* the ray cast's hits */
    int differ;       /* pixels unlike the ray cast: hit or miss, or the point over 1e-3 */
    int hit_differ;   /* of those, hit against miss */
    double max_err;   /* largest point distance of the hits both have */
    int same_differ;  /* pixels unlike the CPU's passes (hf_hybrid_trace_batch) */
    double cpu_ms;    /* the CPU's two passes */
} hybrid_check;

/* Compares the frame `f` (n pixels) of the rays `rays` with the CPU. */
hybrid_check hybrid_compare(const scene *s, const hf_ray *rays, const frame *f, size_t n);
/* Whether it agrees with the ray cast on at least 99.99 % of the pixels (some hit). */
int hybrid_ok(const hybrid_check *c, size_t n);

#endif
