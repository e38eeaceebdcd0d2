/* The scene both OpenGL renderers draw (OSMesa offscreen, GLFW window): a height map
 * loaded from a 16-bit PNG, baked through the C API, and ray cast by the GLSL port of
 * a method in a full-screen pass, one ray per pixel.
 *
 * Parity: the C code computes every pixel's ray once (origin, direction, t range as
 * floats) and uploads the very same floats as two RGBA32F textures; the fragment
 * shader reads its ray with texelFetch at its pixel, and the CPU check traces the same
 * array through the C API. Both sides therefore trace bit-identical rays, and any
 * difference comes from the marches themselves. */
#ifndef HFCAST_RENDER_COMMON_H
#define HFCAST_RENDER_COMMON_H

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include "hfcast.h"

#define NUM_METHODS HF_METHOD_COUNT
#define CC_CAP 64     /* the cylinder-cone bake's (and march's) cap */

/* One method configuration: an hf_method, an hf_surface, the step counts (`linear`:
 * search steps, or the cone/QDM iteration budget, or relaxed cone steps; `binary`:
 * bisections), the safety map layout and what the radius march does at a zero radius. */
typedef struct method_cfg {
    uint32_t method;
    uint32_t surface;
    uint32_t linear;
    uint32_t binary;
    uint32_t variant; /* safety: an hf_safety_variant */
    uint32_t zero;    /* radius: an hf_radius_zero */
} method_cfg;

typedef struct scene {
    char name[128];
    uint32_t w, h;
    float depth;       /* relief depth: a PNG value of 65535 is this many grid units */
    hf_field *field;
    hf_field_info info;
    float *heights;    /* W x H, for the texture */
    uint16_t *samples16; /* W x H, the PNG's 16-bit samples (generated u16-height shaders) */
    float *pyramid;
    size_t pyramid_len;
    hf_level levels[HF_MAX_LEVELS];
    uint32_t nlevels;
    /* HF_RAYS_* bits of the ray classes the safety and cylinder-cone maps hold:
     * HF_RAYS_ALL (whole maps) after scene_load, else scene_set_maps's. */
    uint32_t classes;
    /* The ray set those maps are baked for, as hf_bake_options.exterior and
     * .max_view_angle_deg (0 and 0, every ray, after scene_load): the shaders'
     * hf_rays_exterior and hf_rays_max_view_angle. */
    uint32_t exterior;
    float max_view_angle_deg;
    /* The occluders those maps are baked over (hf_bake_options.occluders; none after
     * scene_load): the shaders' hf_occluders and hf_occluder_count. scene_use_walls. */
    hf_occluder occluders[8];
    uint32_t occluder_count;
    unsigned char *safety; /* directional safety distances, W x H x n for n classes */
    size_t safety_len;
    unsigned char *safety_iso; /* isotropic safety distances, W x H (of those classes) */
    size_t safety_iso_len;
    float *cone, *relaxed, *qdm; /* the cone family's maps */
    size_t cone_len, relaxed_len, qdm_len;
    double cone_bake_ms, relaxed_bake_ms, qdm_bake_ms;
    unsigned char *cc; /* cylinder-cone shapes [r, s], W x H x 2n bytes for n classes */
    size_t cc_len;
    double cc_bake_ms;
    double safety_bake_ms;
    unsigned char *radius; /* safety radii (tolerance 0), W x H */
    size_t radius_len;
    double radius_bake_ms;
} scene;

typedef struct camera {
    float azimuth, elevation; /* radians */
    float distance;           /* in units of max(W, H) */
    float fov;                /* vertical, radians */
    float roll;               /* about the view axis, radians, counter-clockwise on screen */
} camera;

typedef struct gpu {
    int w, h;
    GLuint prog[NUM_METHODS]; /* one program per hf_method */
    GLuint vao;
    GLuint tex_heights, tex_pyramid, tex_safety, tex_safety_iso, tex_origin, tex_dir;
    GLuint tex_cone, tex_relaxed, tex_qdm, tex_cc, tex_radius;
    GLuint tex_heights16; /* R16UI samples, for generated shaders of HF_HEIGHTS_U16 scenes */
    GLuint tex_occluders; /* RGBA32F, 3 texels per occluder (gpu_upload_class_maps) */
    GLuint fbo, tex_point, tex_normal, tex_color, rb_depth;
    int primary_only; /* 1: frames trace no shadow rays (0 after gpu_init) */
} gpu;

/* Output of one pass, read back (row 0 = bottom row, as GL). */
typedef struct frame {
    float *point;         /* w*h*4: hit point, t (-1 on a miss) */
    float *normal;        /* w*h*4: normal, shadow (1 = shadowed) */
    unsigned char *color; /* w*h*4: shaded RGBA8 */
    float *depth;         /* w*h: the depth buffer (t / depth_far, 1 on a miss) */
} frame;

#define SHADOW_OFFSET 0.01f

extern const float LIGHT_DIR[3];

const char *method_name(uint32_t method);
const char *surface_name(uint32_t surface);

int scene_load(scene *s, const char *png_path);
/* The field, heights and maximum mipmap of the map only (no other map baked). */
int scene_load_heights(scene *s, const char *png_path);
/* scene_load_heights of the centre side x side samples (the whole map when side is 0 or
 * larger), the relief depth that of the whole map. */
int scene_load_crop(scene *s, const char *png_path, uint32_t side);
/* scene_load, and when `relaxed` the relaxed cone map too (seconds on a test map). */
int scene_load_ex(scene *s, const char *png_path, int relaxed);
void scene_free(scene *s);
/* Rebakes the safety (both layouts) and cylinder-cone maps for the ray classes
 * `classes` only (HF_RAYS_* bits, not 0) and the ray set `exterior`,
 * `max_view_angle_deg` (hf_bake_options' fields): the maps that hf_bake of
 * HF_METHOD_SAFETY and HF_METHOD_CC writes for those options, which cpu_trace and
 * gpu_render then use with that mask and set (after gpu_upload_class_maps). */
void scene_set_maps(scene *s, uint32_t classes, uint32_t exterior, float max_view_angle_deg);
/* scene_set_maps baking the safety maps only when `safety`, the cylinder-cone map only
 * when `cc` (the other maps zeros of their size). */
void scene_set_maps_of(scene *s, uint32_t classes, uint32_t exterior, float max_view_angle_deg,
                       int safety, int cc);
/* When `on`, the next scene_set_maps bakes over four walls one texel around the field
 * (eight occluders: tops rising from the middle of the height range, south-west, to a
 * fifth of it above the highest sample, north-east: hfcast_tools::maps::walls_around);
 * else over none. */
void scene_use_walls(scene *s, int on);
/* The fixed view of the tests: both renderers' images of it are compared. */
camera default_camera(void);
float scene_depth_far(const scene *s, const camera *c);

/* Rays of a w x h image, rays[y * w + x] for pixel (x, y) with y = 0 the bottom row. */
void make_rays(const scene *s, const camera *c, int w, int h, hf_ray *rays);
/* make_rays with the image's window on the view plane (at unit distance) given: it
 * spans [-half[0], half[0]] x [-half[1], half[1]] before the camera's roll turns it. */
void make_rays_window(const scene *s, const camera *c, int w, int h, const float half[2],
                      hf_ray *rays);
/* The camera's eye and unit view axes (forward, right, up; its roll applied), as
 * make_rays aims the rays: pixel (x, y)'s ray is fwd + sx right + sy up. */
void camera_frame(const scene *s, const camera *c, float eye[3], float fwd[3], float right[3],
                  float up[3]);
/* The window make_rays gives a w x h image of `c`: tan(fov / 2) times (aspect, 1). */
void camera_window(const camera *c, int w, int h, float half[2]);

/* Traces `n` rays on the CPU through the C API with `cfg`. */
hf_result cpu_trace(const scene *s, method_cfg cfg, const hf_ray *rays, size_t n, hf_hit *hits);
/* cpu_trace on the projective field of the row-major 4x4 `matrix`
 * (hf_projective_trace_batch); NULL: cpu_trace. */
hf_result cpu_trace_projective(const scene *s, method_cfg cfg, const double *matrix,
                               const hf_ray *rays, size_t n, hf_hit *hits);

/* The fragment shader of `method`: #version, hf_shader_source, the renderer's main. */
char *fragment_source(uint32_t method);
extern const char *VERTEX_SOURCE;

/* The fragment shader hf_shader_generate writes for `sc`: #version, the generated
 * GLSL, the renderer's main. */
char *generated_fragment_source(const hf_scene *sc);
/* A program of the full-screen vertex shader and the fragment shader `fs_src`. */
GLuint link_fragment(const char *fs_src);
/* A program of the vertex shader `vs_src` and the fragment shader `fs_src`. */
GLuint link_shaders(const char *vs_src, const char *fs_src);
/* A compute program of `src` (a whole GLSL compute shader). */
GLuint link_compute(const char *src);
/* A w x h 2D texture, nearest, clamped, of `data` (NULL: unset). */
GLuint make_texture(GLenum internal, int w, int h, GLenum format, GLenum type, const void *data);

int gpu_init(gpu *g, const scene *s, int w, int h);
void gpu_upload_rays(gpu *g, const hf_ray *rays);
/* (Re)creates the textures of the safety and cylinder-cone maps of `s` (W x nH for its
 * n classes; isotropic W x H); gpu_init does it for the maps scene_load baked. */
void gpu_upload_class_maps(gpu *g, const scene *s);
void gpu_render(gpu *g, const scene *s, method_cfg cfg, float depth_far);
/* gpu_render with program `p` (a general or generated shader of cfg.method); `u16`:
 * the heights are the R16UI samples times hf_height_step (a HF_HEIGHTS_U16 scene). */
void gpu_render_program(gpu *g, GLuint p, const scene *s, method_cfg cfg, float depth_far,
                        int u16);
void gpu_read(gpu *g, frame *f);
void gpu_free(gpu *g);

int frame_alloc(frame *f, int w, int h);
void frame_free(frame *f);

int write_png_rgba(const char *path, const unsigned char *rgba, int w, int h);
int read_png_rgb(const char *path, unsigned char **rgb, int *w, int *h);

double now_seconds(void);

/* The distance between two points. */
float dist3(const float *a, const float *b);

/* GPU frame against the CPU's answers for the same rays. */
typedef struct parity {
    int pixels, hits, differ, differ_hit, differ_pos;
    int shadow_checked, shadow_differ, depth_differ;
    double max_err;
} parity;

/* Compares the GPU frame `f` of `cfg` with the CPU answers for `rays` (w x h, and the
 * shadow rays from the CPU's hits); lists every differing pixel when `list` is set. */
parity compare(const scene *s, method_cfg cfg, const hf_ray *rays, const frame *f,
               float depth_far, int w, int h, int list, const char *label);
/* Whether `method` is exact (all but linear + binary, linear + secant, relaxed, multires). */
int method_exact(uint32_t method);
/* Whether a parity count passes (99.99 % of pixels for exact methods, 99.9 % else). */
int parity_ok(const parity *p, uint32_t method);

#endif
