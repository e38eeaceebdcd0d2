/* Six-field impostors of a triangle mesh in OpenGL (Baboud & Décoret §4; issue 22),
 * shared by both renderers.
 *
 * The mesh (an OBJ file) is captured through the C API (hf_impostor_layout_around,
 * hf_impostor_capture: six padded fields of one side), the fields stacked in one R32F
 * texture, and drawn by rasterizing a proxy whose fragments call the generated GLSL's
 * hf_trace_impostor (hf_shader_generate_impostor) on their pixel's ray. Each pixel's
 * ray is computed once in C and uploaded as two RGBA32F textures (as render_common
 * does), so the CPU (hf_impostor_trace_batch) traces bit-identical rays. The proxy is
 * either the clipped frustum, the layout's cube (every face's frustum clipped by the
 * bounding box, §4.1; the trace clips each ray to it), or the unclipped frusta, the
 * six truncated pyramids of the faces' regions (footprint times heights from
 * HF_IMPOSTOR_FLOOR up). An atomic counter counts the fragments the impostor's shader runs.
 *
 * The ground truth is the mesh itself rasterized from the same camera; its fragments
 * write the same outputs (the forward distance of the point), so that silhouettes and
 * depths compare pixel by pixel. */
#ifndef HFCAST_IMPOSTOR_H
#define HFCAST_IMPOSTOR_H

#include "render_common.h"

typedef struct imp_mesh {
    float *pos;    /* 3 per vertex */
    size_t nv;
    uint32_t *tri; /* 3 per triangle */
    size_t nt;
} imp_mesh;

/* Reads the `v` and `f` lines of an OBJ file (polygons fanned, `i/j/k` and negative
 * indices as OBJ defines them). 0, or -1 with a message. */
int imp_mesh_load_obj(imp_mesh *m, const char *path);
void imp_mesh_free(imp_mesh *m);

/* A capture: the layout, six side x side fields (face after face, padded), and what
 * the shader takes: each face's grid map and its inverse (row-major, rounded to
 * float), and each field's height range. */
typedef struct imp_fields {
    hf_impostor_layout layout;
    uint32_t side;
    float *heights;
    float maps[6][16], inverses[6][16];
    float ranges[6][2];
    double capture_ms; /* the six captures through the C API */
} imp_fields;

/* Captures `m` with `frustum` (an hf_impostor_frustum) at `side`. 0, or -1. */
int imp_fields_capture(imp_fields *f, const imp_mesh *m, uint32_t frustum, uint32_t side);
void imp_fields_free(imp_fields *f);

/* A pinhole camera: eye, unit axes, the window's half extents at unit distance and
 * the depth range of its projection. */
typedef struct imp_view {
    double eye[3], fwd[3], right[3], up[3];
    double half[2];
    double near_, far_;
} imp_view;

/* A camera `dist` half sides from the layout's centre, at compass azimuth and
 * elevation (degrees, +z up), looking at the centre, vertical field of view `fov`
 * degrees, for a w x h image. */
imp_view imp_orbit(const hf_impostor_layout *l, double azimuth, double elevation, double dist,
                   double fov, int w, int h);
/* The rays of the pixels' centres, rays[y * w + x] with y = 0 the bottom row (t from
 * 0 to infinity, directions fwd + sx right + sy up). */
void imp_rays(const imp_view *v, int w, int h, hf_ray *rays);

/* The GL side: programs, proxies, textures, the frame buffer. */
typedef struct imp_gl {
    int w, h;
    GLuint prog[2][2]; /* [combine][depth output] */
    GLuint prog_mesh;
    GLuint vao_box, vbo_box, vao_frusta, vbo_frusta;
    GLuint vao_mesh, vbo_mesh, ibo_mesh;
    GLsizei mesh_indices;
    GLuint tex_fields, tex_origin, tex_dir;
    GLuint fbo, tex_point, tex_info, rb_depth;
    GLuint counter;
} imp_gl;

/* Compiles the programs (the generated impostor shader of the exact method on
 * triangles, with and without depth output, for each combination) and makes a w x h
 * frame buffer. 0, or -1. */
int imp_gl_init(imp_gl *g, int w, int h);
void imp_gl_free(imp_gl *g);
/* Uploads the mesh (for the ground truth). */
void imp_gl_set_mesh(imp_gl *g, const imp_mesh *m);
/* Uploads the fields and the proxies of a capture: the cube (clipped) and the six
 * frusta (unclipped). */
void imp_gl_set_fields(imp_gl *g, const imp_fields *f);
/* Uploads the rays of the pixels (imp_rays of the view the draws use). */
void imp_gl_set_rays(imp_gl *g, const hf_ray *rays);

/* What one draw cost: to glFinish, and the fragments the impostor's shader ran. */
typedef struct imp_stats {
    double ms;
    unsigned fragments;
} imp_stats;

/* Draws the impostor of `f` from `v`: `combine` an hf_impostor_combine; `depth` 1 to
 * write the hit's depth (else the proxy's); `clipped` 1 for the box, 0 for the six
 * frusta. When `clear` is 0 the frame is drawn over (a scene with other geometry). */
imp_stats imp_gl_draw(imp_gl *g, const imp_fields *f, const imp_view *v, uint32_t combine,
                      int depth, int clipped, int clear);
/* Rasterizes the mesh from `v` (the ground truth), over the frame unless `clear`. */
imp_stats imp_gl_draw_mesh(imp_gl *g, const imp_view *v, int clear);
/* Rasterizes the plane z = `z` across the box (in the frame, depth tested): the other
 * geometry of the depth-output test. */
void imp_gl_draw_plane(imp_gl *g, const imp_view *v, const imp_mesh *m, double z);

/* The frame read back (row 0 = bottom): per pixel the hit point and t (point: w*h*4,
 * t = -1 on a miss) and (forward distance, face or -1 for the mesh, fetches, 1 = hit
 * or 2 = plane) (info: w*h*4). */
void imp_gl_read(imp_gl *g, float *point, float *info);

/* A frame against the CPU (hf_impostor_trace_batch on the same rays). */
typedef struct imp_check {
    int pixels, hits;  /* pixels, and the CPU's hits */
    int differ;        /* hit against miss, or the points over 1e-3 half sides apart */
    int hit_differ;    /* of those, hit against miss */
    int face_differ;   /* hits on another face (where two fields cross: allowed) */
    double max_err;    /* largest point distance of the hits both have (half sides) */
    double cpu_ms;
} imp_check;

imp_check imp_check_cpu(const imp_fields *f, uint32_t combine, const hf_ray *rays, size_t n,
                        const float *point, const float *info);
/* Whether at least 99.99 % of the pixels agree and some hit. */
int imp_check_ok(const imp_check *c);

/* A frame of the impostor against the mesh's frame from the same view: the mesh's
 * pixels, the pixels covered by one and not the other, and the mean and largest
 * forward-distance error (in half sides) of the pixels both cover. */
typedef struct imp_error {
    int mesh_pixels, differ;
    double depth_mean, depth_max;
} imp_error;

imp_error imp_against_mesh(const float *info, const float *mesh_info, size_t n, double half);

#endif
