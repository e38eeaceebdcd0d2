#define _POSIX_C_SOURCE 199309L
#include "render_common.h"
#include "png16.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Towards the light (unit): a low sun, for long shadows. */
const float LIGHT_DIR[3] = {0.75f, -0.45f, 0.48541f};

/* hf_method_name's name of `method` ("?" for none), in a static buffer. */
const char *method_name(uint32_t method) {
    static char name[32];
    size_t n = 0;
    return hf_method_name(method, name, sizeof name, &n) == HF_OK ? name : "?";
}

/* hf_surface_name's name of `surface` ("?" for none), in a static buffer. */
const char *surface_name(uint32_t surface) {
    static char name[32];
    size_t n = 0;
    return hf_surface_name(surface, name, sizeof name, &n) == HF_OK ? name : "?";
}

double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void die_hf(const char *what, hf_result r) {
    char msg[128];
    size_t n = 0;
    if (hf_error_message(r, msg, sizeof msg, &n) != HF_OK) strcpy(msg, "?");
    fprintf(stderr, "%s failed: %s (%u)\n", what, msg, (unsigned)r);
    exit(2);
}

/* ---- PNG ------------------------------------------------------------------------- */

int write_png_rgba(const char *path, const unsigned char *rgba, int w, int h) {
    FILE *fp = fopen(path, "wb");
    if (!fp) return -1;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(fp);
        return -1;
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_bytep row = (png_bytep)malloc((size_t)w * 3);
    /* GL row 0 is the bottom row: write top first. */
    for (int y = h - 1; y >= 0; y--) {
        for (int x = 0; x < w; x++) memcpy(row + 3 * x, rgba + 4 * ((size_t)y * w + x), 3);
        png_write_row(png, row);
    }
    free(row);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
    return 0;
}

/* Reads an 8-bit RGB PNG written by write_png_rgba, rows back in GL order (bottom first). */
int read_png_rgb(const char *path, unsigned char **rgb, int *w, int *h) {
    FILE *fp = fopen(path, "rb");
    if (!fp) return -1;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    *rgb = NULL;
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        free(*rgb);
        *rgb = NULL;
        return -1;
    }
    png_init_io(png, fp);
    png_read_info(png, info);
    *w = (int)png_get_image_width(png, info);
    *h = (int)png_get_image_height(png, info);
    if (png_get_color_type(png, info) != PNG_COLOR_TYPE_RGB || png_get_bit_depth(png, info) != 8) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        return -1;
    }
    *rgb = (unsigned char *)malloc((size_t)*w * *h * 3);
    for (int y = *h - 1; y >= 0; y--) png_read_row(png, *rgb + (size_t)y * *w * 3, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return 0;
}

/* ---- scene ------------------------------------------------------------------------ */

int scene_load(scene *s, const char *png_path) { return scene_load_ex(s, png_path, 0); }

/* Bytes of one element of `method`'s map: floats for the maximum mipmap and the cone
 * family, bytes for the safety-distance, cylinder-cone and radius maps. */
static size_t map_elem_bytes(uint32_t method) {
    int bytes = method == HF_METHOD_SAFETY || method == HF_METHOD_CC || method == HF_METHOD_RADIUS;
    return bytes ? 1 : sizeof(float);
}

/* Exits with the message of `r` unless it is HF_OK; `what` names the call of `method`. */
static void check_method(hf_result r, const char *what, uint32_t method) {
    char buf[64];
    if (r == HF_OK) return;
    snprintf(buf, sizeof buf, "%s (%s)", what, method_name(method));
    die_hf(buf, r);
}

/* The default bake options of `method`. */
static hf_bake_options bake_defaults(uint32_t method) {
    hf_bake_options o;
    check_method(hf_bake_options_default(method, &o), "hf_bake_options_default", method);
    return o;
}

/* `method`'s map of s->field with options `o` (NULL: the method's defaults) on every
 * core, in a new zeroed buffer of hf_map_len elements (*len); baked when `bake` (the
 * time in *ms unless NULL), else left zero (*ms -1). */
static void *bake_map(const scene *s, uint32_t method, const hf_bake_options *o, int bake,
                      size_t *len, double *ms) {
    hf_bake_options all = o ? *o : bake_defaults(method);
    all.threads = 0;
    check_method(hf_map_len(method, s->w, s->h, &all, len), "hf_map_len", method);
    void *map = calloc(*len, map_elem_bytes(method));
    double t0 = now_seconds();
    if (bake) check_method(hf_bake(method, s->field, &all, map, *len), "hf_bake", method);
    if (ms) *ms = bake ? 1e3 * (now_seconds() - t0) : -1.0;
    return map;
}

/* Bakes the maps of the ray classes s->classes for the ray set s->exterior,
 * s->max_view_angle_deg (all cores): the directional and isotropic safety maps when
 * `safety` (W x nH texels for n classes, isotropic W x H), the cylinder-cone map when
 * `cc`; a map not baked is zeros of its size. */
static void bake_class_maps(scene *s, int safety, int cc) {
    hf_bake_options o = bake_defaults(HF_METHOD_SAFETY); /* exact, cap 255 */
    o.ray_classes = s->classes;
    o.exterior = s->exterior;
    o.max_view_angle_deg = s->max_view_angle_deg;
    o.occluders = s->occluder_count ? s->occluders : NULL;
    o.occluder_count = s->occluder_count;
    s->safety = bake_map(s, HF_METHOD_SAFETY, &o, safety, &s->safety_len, &s->safety_bake_ms);
    o.variant = HF_SAFETY_ISOTROPIC;
    s->safety_iso = bake_map(s, HF_METHOD_SAFETY, &o, safety, &s->safety_iso_len, NULL);
    hf_bake_options c = bake_defaults(HF_METHOD_CC); /* exact slope */
    c.cap = CC_CAP;
    c.ray_classes = s->classes;
    c.exterior = s->exterior;
    c.max_view_angle_deg = s->max_view_angle_deg;
    c.occluders = o.occluders;
    c.occluder_count = o.occluder_count;
    s->cc = bake_map(s, HF_METHOD_CC, &c, cc, &s->cc_len, &s->cc_bake_ms);
}

void scene_set_maps(scene *s, uint32_t classes, uint32_t exterior, float max_view_angle_deg) {
    scene_set_maps_of(s, classes, exterior, max_view_angle_deg, 1, 1);
}

void scene_set_maps_of(scene *s, uint32_t classes, uint32_t exterior, float max_view_angle_deg,
                       int safety, int cc) {
    free(s->safety);
    free(s->safety_iso);
    free(s->cc);
    s->classes = classes;
    s->exterior = exterior;
    s->max_view_angle_deg = max_view_angle_deg;
    bake_class_maps(s, safety, cc);
}

void scene_use_walls(scene *s, int on) {
    s->occluder_count = 0;
    if (!on) return;
    const float xm = (float)(s->w - 1), ym = (float)(s->h - 1);
    const float zlo = s->info.min_height;
    const float zr = s->info.max_height > zlo ? s->info.max_height - zlo : 1e-3f;
    const float rects[4][4] = {{-3.0f, -1.0f, -3.0f, ym + 3.0f},
                               {xm + 1.0f, xm + 3.0f, -3.0f, ym + 3.0f},
                               {-3.0f, xm + 3.0f, -3.0f, -1.0f},
                               {-3.0f, xm + 3.0f, ym + 1.0f, ym + 3.0f}};
    const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int r = 0; r < 4; r++) {
        const float *q = rects[r];
        const float xy[4][2] = {{q[0], q[2]}, {q[1], q[2]}, {q[1], q[3]}, {q[0], q[3]}};
        for (int t = 0; t < 2; t++)
            for (int v = 0; v < 3; v++) {
                float *c = s->occluders[2 * r + t].corners[v];
                c[0] = xy[tri[t][v]][0];
                c[1] = xy[tri[t][v]][1];
                c[2] = (float)((double)zlo + 0.5 * zr + 0.35 * zr * (c[0] / xm + c[1] / ym));
            }
    }
    s->occluder_count = 8;
}

int scene_load_heights(scene *s, const char *png_path) { return scene_load_crop(s, png_path, 0); }

int scene_load_crop(scene *s, const char *png_path, uint32_t side) {
    memset(s, 0, sizeof *s);
    uint32_t fw, fh;
    uint16_t *samples = read_png_gray16(png_path, &fw, &fh);
    if (!samples) return -1;
    uint32_t stride = fw;
    s->w = side && side < fw ? side : fw;
    s->h = side && side < fh ? side : fh;
    const uint16_t *first = samples + (size_t)((fh - s->h) / 2) * stride + (fw - s->w) / 2;
    const char *base = strrchr(png_path, '/');
    base = base ? base + 1 : png_path;
    snprintf(s->name, sizeof s->name, "%s", base);
    char *dot = strrchr(s->name, '.');
    if (dot) *dot = 0;
    /* The tools' default relief depth: 0.1 x max(W, H) grid units, of the whole map. */
    s->depth = 0.1f * (float)(fw > fh ? fw : fh);
    size_t n = (size_t)s->w * s->h;
    size_t avail = (size_t)stride * (s->h - 1) + s->w;
    hf_result r = hf_field_create_u16(first, avail, s->w, s->h, stride, s->depth, &s->field);
    if (r != HF_OK) die_hf("hf_field_create_u16", r);
    s->samples16 = (uint16_t *)malloc(sizeof(uint16_t) * n);
    for (uint32_t j = 0; j < s->h; j++)
        memcpy(s->samples16 + (size_t)j * s->w, first + (size_t)j * stride,
               sizeof(uint16_t) * s->w);
    free(samples);
    if ((r = hf_field_get_info(s->field, &s->info)) != HF_OK) die_hf("hf_field_get_info", r);
    s->heights = (float *)malloc(sizeof(float) * n);
    if ((r = hf_field_copy_heights(s->field, s->heights, n)) != HF_OK) die_hf("copy_heights", r);
    s->pyramid = bake_map(s, HF_METHOD_MAXMIP, NULL, 1, &s->pyramid_len, NULL);
    if ((r = hf_maxmip_levels(s->w, s->h, s->levels, HF_MAX_LEVELS, &s->nlevels)) != HF_OK)
        die_hf("hf_maxmip_levels", r);
    return 0;
}

int scene_load_ex(scene *s, const char *png_path, int relaxed) {
    if (scene_load_heights(s, png_path) != 0) return -1;
    s->classes = HF_RAYS_ALL;
    bake_class_maps(s, 1, 1);
    /* The defaults: radii of tolerance 0 and cap 255. */
    s->radius = bake_map(s, HF_METHOD_RADIUS, NULL, 1, &s->radius_len, &s->radius_bake_ms);
    s->cone = bake_map(s, HF_METHOD_CONE, NULL, 1, &s->cone_len, &s->cone_bake_ms);
    s->relaxed = bake_map(s, HF_METHOD_RELAXED, NULL, relaxed, &s->relaxed_len, &s->relaxed_bake_ms);
    s->qdm = bake_map(s, HF_METHOD_QDM, NULL, 1, &s->qdm_len, &s->qdm_bake_ms);
    return 0;
}

void scene_free(scene *s) {
    hf_field_destroy(s->field);
    free(s->heights);
    free(s->samples16);
    free(s->pyramid);
    free(s->safety);
    free(s->safety_iso);
    free(s->radius);
    free(s->cone);
    free(s->relaxed);
    free(s->qdm);
    free(s->cc);
    memset(s, 0, sizeof *s);
}

camera default_camera(void) {
    camera c = {0.6f, 0.6f, 1.25f, 0.7f, 0.0f};
    return c;
}

static float scene_size(const scene *s) { return (float)(s->w > s->h ? s->w : s->h); }

float scene_depth_far(const scene *s, const camera *c) {
    return 4.0f * c->distance * scene_size(s);
}

static void normalize3(float v[3]) {
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
}

void camera_window(const camera *c, int w, int h, float half[2]) {
    float th = tanf(0.5f * c->fov);
    half[0] = th * (float)w / (float)h;
    half[1] = th;
}

void make_rays(const scene *s, const camera *c, int w, int h, hf_ray *rays) {
    float half[2];
    camera_window(c, w, h, half);
    make_rays_window(s, c, w, h, half, rays);
}

void camera_frame(const scene *s, const camera *c, float eye[3], float fwd[3], float right[3],
                  float up[3]) {
    float size = scene_size(s);
    float target[3] = {0.5f * (float)(s->w - 1), 0.5f * (float)(s->h - 1),
                       0.5f * (s->info.min_height + s->info.max_height)};
    float dist = c->distance * size;
    float ce = cosf(c->elevation);
    eye[0] = target[0] + dist * ce * cosf(c->azimuth);
    eye[1] = target[1] + dist * ce * sinf(c->azimuth);
    eye[2] = target[2] + dist * sinf(c->elevation);
    for (int k = 0; k < 3; k++) fwd[k] = target[k] - eye[k];
    normalize3(fwd);
    /* Grid space is x east, y south, z up (left-handed): right = up x fwd keeps the
     * image unmirrored. */
    right[0] = -fwd[1];
    right[1] = fwd[0];
    right[2] = 0.0f;
    normalize3(right);
    up[0] = right[1] * fwd[2] - right[2] * fwd[1];
    up[1] = right[2] * fwd[0] - right[0] * fwd[2];
    up[2] = right[0] * fwd[1] - right[1] * fwd[0];
    if (up[2] < 0) {
        up[0] = -up[0];
        up[1] = -up[1];
        up[2] = -up[2];
    }
    /* Roll turns the view plane's axes (an exact identity at roll 0). */
    float cr = cosf(c->roll), sr = sinf(c->roll);
    for (int k = 0; k < 3 && c->roll != 0.0f; k++) {
        float rk = right[k], uk = up[k];
        right[k] = cr * rk + sr * uk;
        up[k] = cr * uk - sr * rk;
    }
}

void make_rays_window(const scene *s, const camera *c, int w, int h, const float half[2],
                      hf_ray *rays) {
    float eye[3], fwd[3], right[3], up[3];
    camera_frame(s, c, eye, fwd, right, up);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            float sx = ((2.0f * ((float)x + 0.5f) / (float)w) - 1.0f) * half[0];
            float sy = ((2.0f * ((float)y + 0.5f) / (float)h) - 1.0f) * half[1];
            hf_ray *r = &rays[(size_t)y * w + x];
            for (int k = 0; k < 3; k++) {
                r->origin[k] = eye[k];
                r->dir[k] = fwd[k] + sx * right[k] + sy * up[k];
            }
            normalize3(r->dir);
            r->t_min = 0.0f;
            r->t_max = INFINITY;
        }
    }
}

/* The map cpu_trace traces cfg's method over (the safety map of cfg's layout; none for
 * exact and the searches) and its options; HF_ERR_INVALID_ENUM for an unknown method. */
static hf_result trace_setup(const scene *s, method_cfg cfg, const void **map, size_t *len,
                             hf_trace_options *o) {
    const int iso = cfg.variant == HF_SAFETY_ISOTROPIC;
    const void *maps[NUM_METHODS] = {NULL, NULL, NULL, s->pyramid,
                                     iso ? s->safety_iso : s->safety,
                                     s->cone, s->relaxed, s->qdm, s->cc, s->radius, NULL};
    const size_t lens[NUM_METHODS] = {0, 0, 0, s->pyramid_len,
                                      iso ? s->safety_iso_len : s->safety_len,
                                      s->cone_len, s->relaxed_len, s->qdm_len, s->cc_len,
                                      s->radius_len, 0};
    if (cfg.method >= NUM_METHODS) return HF_ERR_INVALID_ENUM;
    hf_result r = hf_trace_options_default(o);
    if (r != HF_OK) return r;
    o->surface = cfg.surface;
    o->steps = cfg.linear;
    o->binary_steps = cfg.binary;
    o->radius_zero = cfg.zero;
    /* The maps' ray classes, as the shaders' hf_safety_classes and hf_cc_classes. */
    if (cfg.method == HF_METHOD_SAFETY || cfg.method == HF_METHOD_CC) {
        o->ray_classes = s->classes;
        /* And the occluders they are baked over. */
        o->occluders = s->occluder_count ? s->occluders : NULL;
        o->occluder_count = s->occluder_count;
    }
    *map = maps[cfg.method];
    *len = lens[cfg.method];
    return HF_OK;
}

hf_result cpu_trace(const scene *s, method_cfg cfg, const hf_ray *rays, size_t n, hf_hit *hits) {
    return cpu_trace_projective(s, cfg, NULL, rays, n, hits);
}

hf_result cpu_trace_projective(const scene *s, method_cfg cfg, const double *matrix,
                               const hf_ray *rays, size_t n, hf_hit *hits) {
    const void *map = NULL;
    size_t len = 0;
    hf_trace_options o;
    hf_result r = trace_setup(s, cfg, &map, &len, &o);
    if (r != HF_OK) return r;
    if (matrix)
        return hf_projective_trace_batch(s->field, matrix, cfg.method, map, len, &o, rays, n,
                                         hits, n);
    return hf_trace_batch(s->field, cfg.method, map, len, &o, rays, n, hits, n);
}

/* ---- shaders ---------------------------------------------------------------------- */

const char *VERTEX_SOURCE =
    "#version 330 core\n"
    "// A full-screen triangle; the fragment shader reads its ray by pixel.\n"
    "void main() {\n"
    "    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n"
    "    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n"
    "}\n";

/* The renderer's main: one primary ray per pixel (read from the ray textures), then a
 * shadow ray towards the light from just above the hit (walked back from the light's
 * side, query_walked_back, when shadow_from_light: an exterior ray), both with the
 * method's hf_trace; writes the hit, the normal and shadow, a shaded colour, and the
 * depth. */
static const char *FRAGMENT_MAIN =
    "// ---- renderer main (c_tests/render_common.c)\n"
    "uniform sampler2D hf_ray_origin; // RGBA32F: origin.xyz, t_min\n"
    "uniform sampler2D hf_ray_dir;    // RGBA32F: dir.xyz, t_max\n"
    "uniform vec3 light_dir;          // unit, towards the light\n"
    "uniform float depth_far;         // gl_FragDepth = t / depth_far\n"
    "uniform float shadow_offset;     // shadow rays start at point + normal * offset\n"
    "uniform uint shadow_from_light;  // 1: traced from the light's side, to that start\n"
    "uniform uint primary_only;       // 1: no shadow rays (frame times of primary rays)\n"
    "layout(location = 0) out vec4 out_point;  // hit point, t (-1 on a miss)\n"
    "layout(location = 1) out vec4 out_normal; // normal, 1 when shadowed\n"
    "layout(location = 2) out vec4 out_color;  // shaded\n"
    "void main() {\n"
    "    ivec2 px = ivec2(gl_FragCoord.xy);\n"
    "    vec4 o = texelFetch(hf_ray_origin, px, 0);\n"
    "    vec4 d = texelFetch(hf_ray_dir, px, 0);\n"
    "    Query q = Query(o.xyz, d.xyz, o.w, d.w);\n"
    "    Trace first = trace_miss(0u, real_infinity());\n"
    "    bool shadowed = false;\n"
    "    // One call site of hf_trace in a loop: the march is compiled once.\n"
    "    for (int pass = 0; pass < 2; pass++) {\n"
    "        Trace tr = hf_trace(q);\n"
    "        if (pass == 1) { shadowed = tr.has_hit; break; }\n"
    "        first = tr;\n"
    "        if (!tr.has_hit || primary_only != 0u) break;\n"
    "        vec3 p = tr.hit.point, n = tr.hit.normal;\n"
    "        vec3 so = vec3(p.x + n.x * shadow_offset, p.y + n.y * shadow_offset,\n"
    "                       p.z + n.z * shadow_offset);\n"
    "        q = Query(so, light_dir, 0.0, real_infinity());\n"
    "        if (shadow_from_light != 0u) q = query_walked_back(q);\n"
    "    }\n"
    "    if (!first.has_hit) {\n"
    "        out_point = vec4(0.0, 0.0, 0.0, -1.0);\n"
    "        out_normal = vec4(0.0);\n"
    "        out_color = vec4(0.55, 0.70, 0.90, 1.0);\n"
    "        gl_FragDepth = 1.0;\n"
    "        return;\n"
    "    }\n"
    "    Hit h = first.hit;\n"
    "    out_point = vec4(h.point, h.t);\n"
    "    out_normal = vec4(h.normal, shadowed ? 1.0 : 0.0);\n"
    "    float range = max(field_max_height() - field_min_height(), 1e-6);\n"
    "    float k = clamp((h.point.z - field_min_height()) / range, 0.0, 1.0);\n"
    "    vec3 albedo = mix(vec3(0.30, 0.50, 0.22), vec3(0.92, 0.90, 0.85), k);\n"
    "    float lit = max(dot(h.normal, light_dir), 0.0) * (shadowed ? 0.2 : 1.0);\n"
    "    out_color = vec4(albedo * (0.18 + 0.82 * lit), 1.0);\n"
    "    gl_FragDepth = clamp(h.t / depth_far, 0.0, 1.0);\n"
    "}\n";

char *fragment_source(uint32_t method) {
    size_t len = 0, written = 0;
    hf_result r = hf_shader_source_len(method, &len);
    if (r != HF_OK) die_hf("hf_shader_source_len", r);
    const char *head = "#version 330 core\n";
    size_t total = strlen(head) + len + strlen(FRAGMENT_MAIN) + 1;
    char *src = (char *)malloc(total);
    strcpy(src, head);
    r = hf_shader_source(method, src + strlen(head), len, &written);
    if (r != HF_OK) die_hf("hf_shader_source", r);
    strcat(src, FRAGMENT_MAIN);
    return src;
}

char *generated_fragment_source(const hf_scene *sc) {
    size_t len = 0, written = 0;
    hf_result r = hf_shader_generate_len(sc, HF_SHADER_GLSL, &len);
    if (r != HF_OK) die_hf("hf_shader_generate_len", r);
    const char *head = "#version 330 core\n";
    size_t total = strlen(head) + len + strlen(FRAGMENT_MAIN) + 1;
    char *src = (char *)malloc(total);
    strcpy(src, head);
    r = hf_shader_generate(sc, HF_SHADER_GLSL, src + strlen(head), len, &written);
    if (r != HF_OK) die_hf("hf_shader_generate", r);
    strcat(src, FRAGMENT_MAIN);
    return src;
}

/* ---- GL ------------------------------------------------------------------------- */

/* Exits with the info log of `obj`, a program (`program`: its link) or a shader (its
 * compile), unless that succeeded; `what` names the step. */
static void check_gl(GLuint obj, int program, const char *what) {
    GLint ok = 0;
    char log[4096];
    if (program) glGetProgramiv(obj, GL_LINK_STATUS, &ok);
    else glGetShaderiv(obj, GL_COMPILE_STATUS, &ok);
    if (ok) return;
    if (program) glGetProgramInfoLog(obj, sizeof log, NULL, log);
    else glGetShaderInfoLog(obj, sizeof log, NULL, log);
    fprintf(stderr, "%s failed:\n%s\n", what, log);
    exit(2);
}

static GLuint compile(GLenum type, const char *src) {
    GLuint sh = glCreateShader(type);
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    check_gl(sh, 0, "shader compile");
    return sh;
}

GLuint link_compute(const char *src) {
    GLuint cs = compile(GL_COMPUTE_SHADER, src);
    GLuint p = glCreateProgram();
    glAttachShader(p, cs);
    glLinkProgram(p);
    check_gl(p, 1, "compute program link");
    glDeleteShader(cs);
    return p;
}

static GLuint link_program(uint32_t method) {
    char *fs_src = fragment_source(method);
    GLuint p = link_fragment(fs_src);
    free(fs_src);
    return p;
}

GLuint link_fragment(const char *fs_src) { return link_shaders(VERTEX_SOURCE, fs_src); }

GLuint link_shaders(const char *vs_src, const char *fs_src) {
    GLuint vs = compile(GL_VERTEX_SHADER, vs_src);
    GLuint fs = compile(GL_FRAGMENT_SHADER, fs_src);
    GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    check_gl(p, 1, "program link");
    glDeleteShader(vs);
    glDeleteShader(fs);
    return p;
}

GLuint make_texture(GLenum internal, int w, int h, GLenum format, GLenum type,
                    const void *data) {
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, w, h, 0, format, type, data);
    return t;
}

int gpu_init(gpu *g, const scene *s, int w, int h) {
    memset(g, 0, sizeof *g);
    g->w = w;
    g->h = h;
    for (uint32_t m = 0; m < NUM_METHODS; m++) g->prog[m] = link_program(m);
    glGenVertexArrays(1, &g->vao);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    g->tex_heights = make_texture(GL_R32F, (int)s->w, (int)s->h, GL_RED, GL_FLOAT, s->heights);
    /* The 16-bit samples as an integer texture (rows of 2W bytes: alignment 2). */
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    g->tex_heights16 = make_texture(GL_R16UI, (int)s->w, (int)s->h, GL_RED_INTEGER,
                                    GL_UNSIGNED_SHORT, s->samples16);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    /* The pyramid buffer as rows of HF_PYRAMID_TEX_WIDTH texels (last row padded). */
    size_t rows = (s->pyramid_len + HF_PYRAMID_TEX_WIDTH - 1) / HF_PYRAMID_TEX_WIDTH;
    float *padded = (float *)calloc(rows * HF_PYRAMID_TEX_WIDTH, sizeof(float));
    memcpy(padded, s->pyramid, sizeof(float) * s->pyramid_len);
    g->tex_pyramid =
        make_texture(GL_R32F, HF_PYRAMID_TEX_WIDTH, (int)rows, GL_RED, GL_FLOAT, padded);
    free(padded);
    gpu_upload_class_maps(g, s);
    /* Safety radii: one byte per texel, an R8UI texture (rows of W bytes: alignment 1). */
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    g->tex_radius = make_texture(GL_R8UI, (int)s->w, (int)s->h, GL_RED_INTEGER,
                                 GL_UNSIGNED_BYTE, s->radius);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    /* The cone family: per cell [top, ratio] (RG32F), per cell [a, b, c, h] (RGBA32F),
     * per sample the relaxed ratio (R32F). */
    g->tex_cone = make_texture(GL_RG32F, (int)s->w - 1, (int)s->h - 1, GL_RG, GL_FLOAT, s->cone);
    g->tex_qdm = make_texture(GL_RGBA32F, (int)s->w - 1, (int)s->h - 1, GL_RGBA, GL_FLOAT, s->qdm);
    g->tex_relaxed = make_texture(GL_R32F, (int)s->w, (int)s->h, GL_RED, GL_FLOAT, s->relaxed);
    g->tex_origin = make_texture(GL_RGBA32F, w, h, GL_RGBA, GL_FLOAT, NULL);
    g->tex_dir = make_texture(GL_RGBA32F, w, h, GL_RGBA, GL_FLOAT, NULL);
    g->tex_point = make_texture(GL_RGBA32F, w, h, GL_RGBA, GL_FLOAT, NULL);
    g->tex_normal = make_texture(GL_RGBA32F, w, h, GL_RGBA, GL_FLOAT, NULL);
    g->tex_color = make_texture(GL_RGBA8, w, h, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glGenRenderbuffers(1, &g->rb_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, g->rb_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    glGenFramebuffers(1, &g->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->tex_point, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, g->tex_normal, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT2, GL_TEXTURE_2D, g->tex_color, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g->rb_depth);
    GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, bufs);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        fprintf(stderr, "framebuffer incomplete\n");
        return -1;
    }
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

void gpu_upload_class_maps(gpu *g, const scene *s) {
    int n = 0;
    for (uint32_t c = s->classes; c != 0; c &= c - 1) n++;
    GLuint old[4] = {g->tex_safety, g->tex_safety_iso, g->tex_cc, g->tex_occluders};
    glDeleteTextures(4, old); /* names 0 (gpu_init) are ignored */
    /* The occluders: corner v of occluder k at texel 3k + v (x, y, z), RGBA32F; one
     * unused occluder's texels when there are none. */
    float corners[8 * 3 * 4] = {0};
    for (uint32_t k = 0; k < s->occluder_count; k++)
        for (int v = 0; v < 3; v++)
            memcpy(&corners[(3 * k + v) * 4], s->occluders[k].corners[v], 3 * sizeof(float));
    int texels = 3 * (s->occluder_count ? (int)s->occluder_count : 1);
    g->tex_occluders = make_texture(GL_RGBA32F, texels, 1, GL_RGBA, GL_FLOAT, corners);
    /* R8UI rows are W bytes: alignment 1. Directional safety distances: one byte per ray
     * class, each texel row as n rows (one per class held, in class order), an R8UI
     * texture of W x nH, texel (i, n j + slot); the shaders' hf_safety_classes says
     * which classes. Isotropic: one byte per texel, W x H. */
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    g->tex_safety = make_texture(GL_R8UI, (int)s->w, n * (int)s->h, GL_RED_INTEGER,
                                 GL_UNSIGNED_BYTE, s->safety);
    g->tex_safety_iso = make_texture(GL_R8UI, (int)s->w, (int)s->h, GL_RED_INTEGER,
                                     GL_UNSIGNED_BYTE, s->safety_iso);
    /* Cylinder-cone shapes [r, s]: n RG8UI texels (one per class held) per map texel,
     * W x nH (hf_cc_classes); rows are 2W bytes: alignment 2. */
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    g->tex_cc = make_texture(GL_RG8UI, (int)s->w, n * (int)s->h, GL_RG_INTEGER,
                             GL_UNSIGNED_BYTE, s->cc);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

void gpu_upload_rays(gpu *g, const hf_ray *rays) {
    size_t n = (size_t)g->w * g->h;
    float *o = (float *)malloc(sizeof(float) * 4 * n);
    float *d = (float *)malloc(sizeof(float) * 4 * n);
    for (size_t k = 0; k < n; k++) {
        memcpy(o + 4 * k, rays[k].origin, sizeof(float) * 3);
        o[4 * k + 3] = rays[k].t_min;
        memcpy(d + 4 * k, rays[k].dir, sizeof(float) * 3);
        d[4 * k + 3] = rays[k].t_max;
    }
    glBindTexture(GL_TEXTURE_2D, g->tex_origin);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, g->w, g->h, GL_RGBA, GL_FLOAT, o);
    glBindTexture(GL_TEXTURE_2D, g->tex_dir);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, g->w, g->h, GL_RGBA, GL_FLOAT, d);
    free(o);
    free(d);
}

void gpu_render(gpu *g, const scene *s, method_cfg cfg, float depth_far) {
    gpu_render_program(g, g->prog[cfg.method], s, cfg, depth_far, 0);
}

void gpu_render_program(gpu *g, GLuint p, const scene *s, method_cfg cfg, float depth_far,
                        int u16) {
    glUseProgram(p);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glViewport(0, 0, g->w, g->h);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    GLuint safety = cfg.variant == HF_SAFETY_ISOTROPIC ? g->tex_safety_iso : g->tex_safety;
    GLuint tex[11] = {u16 ? g->tex_heights16 : g->tex_heights, g->tex_pyramid, g->tex_origin,  g->tex_dir, safety,
                      g->tex_cone,    g->tex_qdm,     g->tex_relaxed, g->tex_cc, g->tex_radius,
                      g->tex_occluders};
    const char *names[11] = {"hf_heights",  "hf_pyramid", "hf_ray_origin",  "hf_ray_dir",
                             "hf_safety_map", "hf_cone_map", "hf_qdm_map", "hf_relaxed_map",
                             "hf_cc_map", "hf_radius_map", "hf_occluders"};
    for (int k = 0; k < 11; k++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)k);
        glBindTexture(GL_TEXTURE_2D, tex[k]);
        GLint loc = glGetUniformLocation(p, names[k]);
        if (loc >= 0) glUniform1i(loc, k);
    }
    glUniform2i(glGetUniformLocation(p, "hf_size"), (GLint)s->w, (GLint)s->h);
    /* Generated shaders of 16-bit heights: height = sample x depth / 65535 (in float, as
     * hf_field_create_u16 computes it). */
    GLint hloc = glGetUniformLocation(p, "hf_height_step");
    if (hloc >= 0) glUniform1f(hloc, s->depth / 65535.0f);
    glUniform2f(glGetUniformLocation(p, "hf_height_range"), s->info.min_height,
                s->info.max_height);
    GLint sloc = glGetUniformLocation(p, "hf_surface");
    if (sloc >= 0) glUniform1ui(sloc, cfg.surface);
    sloc = glGetUniformLocation(p, "hf_safety_variant");
    if (sloc >= 0) glUniform1ui(sloc, cfg.variant);
    /* The ray classes the safety-distance and cylinder-cone maps hold (absent from a
     * generated shader, whose scene's ray classes are a constant). */
    sloc = glGetUniformLocation(p, "hf_safety_classes");
    if (sloc >= 0) glUniform1ui(sloc, s->classes);
    sloc = glGetUniformLocation(p, "hf_cc_classes");
    if (sloc >= 0) glUniform1ui(sloc, s->classes);
    /* Their ray set (180 degrees: any direction). */
    sloc = glGetUniformLocation(p, "hf_rays_exterior");
    if (sloc >= 0) glUniform1ui(sloc, s->exterior);
    sloc = glGetUniformLocation(p, "hf_rays_max_view_angle");
    if (sloc >= 0)
        glUniform1f(sloc, s->max_view_angle_deg > 0.0f ? s->max_view_angle_deg : 180.0f);
    sloc = glGetUniformLocation(p, "hf_occluder_count");
    if (sloc >= 0) glUniform1ui(sloc, s->occluder_count);
    GLint loc = glGetUniformLocation(p, "hf_linear_steps");
    if (loc >= 0) glUniform1ui(loc, cfg.linear);
    loc = glGetUniformLocation(p, "hf_binary_steps");
    if (loc >= 0) glUniform1ui(loc, cfg.binary);
    loc = glGetUniformLocation(p, "hf_max_iter");
    if (loc >= 0) glUniform1ui(loc, cfg.linear);
    loc = glGetUniformLocation(p, "hf_cone_steps");
    if (loc >= 0) glUniform1ui(loc, cfg.linear);
    loc = glGetUniformLocation(p, "hf_multires_range");
    if (loc >= 0) glUniform1ui(loc, cfg.linear);
    loc = glGetUniformLocation(p, "hf_radius_clamp");
    if (loc >= 0) glUniform1ui(loc, cfg.zero == HF_RADIUS_CLAMP ? 1u : 0u);
    if (cfg.method == HF_METHOD_CC) {
        glUniform1ui(glGetUniformLocation(p, "hf_cc_cap"), CC_CAP);
    }
    if (cfg.method == HF_METHOD_MAXMIP) {
        GLint dims[2 * HF_MAX_LEVELS] = {0}, offs[HF_MAX_LEVELS] = {0};
        for (uint32_t l = 0; l < s->nlevels; l++) {
            dims[2 * l] = (GLint)s->levels[l].width;
            dims[2 * l + 1] = (GLint)s->levels[l].height;
            offs[l] = (GLint)s->levels[l].offset;
        }
        glUniform1i(glGetUniformLocation(p, "hf_levels"), (GLint)s->nlevels);
        glUniform2iv(glGetUniformLocation(p, "hf_level_dims"), HF_MAX_LEVELS, dims);
        glUniform1iv(glGetUniformLocation(p, "hf_level_offset"), HF_MAX_LEVELS, offs);
    }
    glUniform3fv(glGetUniformLocation(p, "light_dir"), 1, LIGHT_DIR);
    glUniform1f(glGetUniformLocation(p, "depth_far"), depth_far);
    glUniform1f(glGetUniformLocation(p, "shadow_offset"), SHADOW_OFFSET);
    /* Over maps of exterior rays the shadow rays come from the light's side, in the set. */
    glUniform1ui(glGetUniformLocation(p, "shadow_from_light"), s->exterior);
    glUniform1ui(glGetUniformLocation(p, "primary_only"), g->primary_only ? 1u : 0u);
    glBindVertexArray(g->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

int frame_alloc(frame *f, int w, int h) {
    size_t n = (size_t)w * h;
    f->point = (float *)malloc(sizeof(float) * 4 * n);
    f->normal = (float *)malloc(sizeof(float) * 4 * n);
    f->color = (unsigned char *)malloc(4 * n);
    f->depth = (float *)malloc(sizeof(float) * n);
    return f->point && f->normal && f->color && f->depth ? 0 : -1;
}

void frame_free(frame *f) {
    free(f->point);
    free(f->normal);
    free(f->color);
    free(f->depth);
}

void gpu_read(gpu *g, frame *f) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, g->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, g->w, g->h, GL_RGBA, GL_FLOAT, f->point);
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, g->w, g->h, GL_RGBA, GL_FLOAT, f->normal);
    glReadBuffer(GL_COLOR_ATTACHMENT2);
    glReadPixels(0, 0, g->w, g->h, GL_RGBA, GL_UNSIGNED_BYTE, f->color);
    glReadPixels(0, 0, g->w, g->h, GL_DEPTH_COMPONENT, GL_FLOAT, f->depth);
}

void gpu_free(gpu *g) {
    for (int m = 0; m < NUM_METHODS; m++) glDeleteProgram(g->prog[m]);
    GLuint tex[16] = {g->tex_heights, g->tex_pyramid, g->tex_safety, g->tex_safety_iso,
                      g->tex_origin,  g->tex_dir,     g->tex_point,  g->tex_normal,
                      g->tex_color,   g->tex_cone,    g->tex_qdm,    g->tex_relaxed,
                      g->tex_cc,      g->tex_heights16, g->tex_radius, g->tex_occluders};
    glDeleteTextures(16, tex);
    glDeleteRenderbuffers(1, &g->rb_depth);
    glDeleteFramebuffers(1, &g->fbo);
    glDeleteVertexArrays(1, &g->vao);
}

/* ---- parity ------------------------------------------------------------------------ */

float dist3(const float *a, const float *b) {
    float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrtf(dx * dx + dy * dy + dz * dz);
}

/* Compares the GPU frame with the CPU answers for the same rays; lists every differing
 * pixel when `list` is set. */
parity compare(const scene *s, method_cfg cfg, const hf_ray *rays, const frame *f,
                      float depth_far, int w, int h, int list, const char *label) {
    size_t n = (size_t)w * h;
    hf_hit *hits = (hf_hit *)malloc(sizeof(hf_hit) * n);
    hf_result r = cpu_trace(s, cfg, rays, n, hits);
    if (r != HF_OK) {
        fprintf(stderr, "cpu_trace failed (%u)\n", (unsigned)r);
        exit(2);
    }
    /* Shadow rays from the CPU's own hits, with the shader's formula (walked back from
     * the light's side over maps of exterior rays, as the shader does). */
    hf_ray *shadow_rays = (hf_ray *)malloc(sizeof(hf_ray) * n);
    hf_hit *shadow = (hf_hit *)malloc(sizeof(hf_hit) * n);
    size_t ns = 0;
    size_t *shadow_of = (size_t *)malloc(sizeof(size_t) * n);
    for (size_t k = 0; k < n; k++) {
        shadow_of[k] = (size_t)-1;
        if (!hits[k].hit) continue;
        hf_ray *sr = &shadow_rays[ns];
        for (int a = 0; a < 3; a++) {
            sr->origin[a] = hits[k].point[a] + hits[k].normal[a] * SHADOW_OFFSET;
            sr->dir[a] = LIGHT_DIR[a];
        }
        sr->t_min = 0.0f;
        sr->t_max = INFINITY;
        if (s->exterior && (r = hf_ray_walked_back(s->field, sr, sr)) != HF_OK) {
            fprintf(stderr, "hf_ray_walked_back failed (%u)\n", (unsigned)r);
            exit(2);
        }
        shadow_of[k] = ns++;
    }
    if (ns > 0 && (r = cpu_trace(s, cfg, shadow_rays, ns, shadow)) != HF_OK) {
        fprintf(stderr, "cpu_trace (shadows) failed (%u)\n", (unsigned)r);
        exit(2);
    }
    parity p;
    memset(&p, 0, sizeof p);
    p.pixels = (int)n;
    for (size_t k = 0; k < n; k++) {
        const float *gp = f->point + 4 * k;
        int ghit = gp[3] >= 0.0f;
        int chit = hits[k].hit != 0;
        p.hits += chit;
        int bad = 0;
        float err = 0.0f;
        if (ghit != chit) {
            bad = 1;
            p.differ_hit++;
        } else if (chit) {
            err = dist3(gp, hits[k].point);
            if (err > p.max_err) p.max_err = err;
            if (!(err <= 1e-3f)) {
                bad = 1;
                p.differ_pos++;
            }
        }
        if (bad) {
            p.differ++;
            if (list) {
                fprintf(stderr,
                        "  %s pixel (%d, %d): gpu %s (%.6f, %.6f, %.6f) t=%.6f, cpu %s (%.6f, "
                        "%.6f, %.6f) t=%.6f, |d| = %.3g\n",
                        label, (int)(k % w), (int)(k / w), ghit ? "hit" : "miss", gp[0], gp[1],
                        gp[2], gp[3], chit ? "hit" : "miss", hits[k].point[0], hits[k].point[1],
                        hits[k].point[2], hits[k].t, err);
            }
            continue;
        }
        /* Depth: t / depth_far, 1 on a miss. */
        float want = chit ? hits[k].t / depth_far : 1.0f;
        if (want > 1.0f) want = 1.0f;
        if (!(fabsf(f->depth[k] - want) <= 1e-3f / depth_far + 1e-7f)) p.depth_differ++;
        if (chit) {
            p.shadow_checked++;
            int gs = f->normal[4 * k + 3] > 0.5f;
            int cs = shadow[shadow_of[k]].hit != 0;
            if (gs != cs) p.shadow_differ++;
        }
    }
    free(hits);
    free(shadow_rays);
    free(shadow);
    free(shadow_of);
    return p;
}

int method_exact(uint32_t method) {
    return method != HF_METHOD_LINEAR_BINARY && method != HF_METHOD_LINEAR_SECANT &&
           method != HF_METHOD_RELAXED && method != HF_METHOD_MULTIRES;
}

/* Whether a parity count passes. Exact methods: at least 99.99 % of pixels within 1e-3
 * texel; approximate ones run the same algorithm, so they must agree nearly as well
 * (99.9 %). Shadows: 99.9 %; depth: 99.99 %. */
int parity_ok(const parity *p, uint32_t method) {
    int allowed = method_exact(method) ? p->pixels / 10000 : p->pixels / 1000;
    return p->differ <= allowed && p->shadow_differ <= p->shadow_checked / 1000 &&
           p->depth_differ <= p->pixels / 10000;
}
