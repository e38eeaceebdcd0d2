/* Offscreen renderer on OSMesa (OpenGL 4.5 core, llvmpipe): the GPU/CPU parity test of
 * the GLSL ports, the reference image of the GLFW test, and a frame-time benchmark.
 *
 *   render_osmesa test OUTDIR MAP.png...        parity of every method, images in OUTDIR
 *   render_osmesa bench W H FRAMES MAP.png...   frame time per method and map (software)
 *   render_osmesa shaders OUTDIR                the composed shaders, for glslangValidator
 *   render_osmesa generated MAP.png...          generated (hf_shader_generate) vs general
 *                                               shaders: identical frames, CPU parity
 *   render_osmesa bench-generated W H FRAMES MAP.png...
 *                                               median frame time, generated vs general
 *   render_osmesa gpu-bake MAP.png...           GPU bakes (GLSL compute: maximum mipmap,
 *                                               N-buffers, safety distances, cc with
 *                                               N-buffer slopes) against the CPU's,
 *                                               byte for byte, and times
 *   render_osmesa dynamic FRAMES MAP.png...     dynamic terrain: a mound moves every
 *                                               frame, the pyramid refreshed on the GPU
 *                                               for the edit only; CPU parity per frame
 *   render_osmesa table1 W H MAP.png SIDE...    frame times of Table 1's safety-shape
 *                                               settings on centre crops (Markdown)
 *   render_osmesa impostor MESH.obj...          six-field impostors (impostor.h): CPU
 *                                               parity, clipped vs unclipped proxies,
 *                                               depth output, frusta vs the mesh
 *   render_osmesa impostor-report W H MESH.obj...
 *                                               docs/report/impostors.md's tables
 */
#define _POSIX_C_SOURCE 200112L
#include "render_common.h"
#include "gpu_bake.h"
#include "roll.h"
#include "hybrid.h"
#include "impostor.h"

#include <GL/osmesa.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TEST_W 256
#define TEST_H 192

static OSMesaContext ctx;
static unsigned char *osmesa_buffer;

static int gl_start(int w, int h) {
    setenv("MESA_SHADER_CACHE_DISABLE", "true", 0);
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           4,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           5,
                           0};
    ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!ctx) {
        fprintf(stderr, "OSMesaCreateContextAttribs (4.5 core) failed\n");
        return -1;
    }
    osmesa_buffer = (unsigned char *)malloc((size_t)w * h * 4);
    if (!OSMesaMakeCurrent(ctx, osmesa_buffer, GL_UNSIGNED_BYTE, w, h)) {
        fprintf(stderr, "OSMesaMakeCurrent failed\n");
        return -1;
    }
    return 0;
}

static void gl_stop(void) {
    OSMesaDestroyContext(ctx);
    free(osmesa_buffer);
}

/* ---- shared by the runs ------------------------------------------------------------ */

/* The configuration of `method` on `surface` the tests and benchmarks use: 64 search
 * steps and 8 bisections (linear + binary), 64 steps (secant), an iteration budget of
 * 512 (cones, QDM), 64 cone steps and 8 bisections (relaxed), a one-texel distance
 * of 64 grid units (multires: coarse levels beyond 128); directional safety map; zero
 * radii walked. */
static method_cfg cfg_of(uint32_t method, uint32_t surface) {
    static const uint32_t steps[NUM_METHODS][2] = {{0, 0},   {64, 8}, {64, 0},  {0, 0},
                                                   {0, 0},   {512, 0}, {64, 8}, {512, 0},
                                                   {0, 0},   {0, 0},  {64, 0}};
    method_cfg c = {method, surface, steps[method][0], steps[method][1],
                    HF_SAFETY_DIRECTIONAL, HF_RADIUS_WALK};
    return c;
}

/* Most configurations search_to_cc_cfgs adds: 13, and 2 variants. */
enum { SEARCH_TO_CC_CFGS = 15 };

/* Appends to `out[n..]` the parity configurations that follow exact traversal and
 * maximum mipmaps: linear + binary search on triangles and bilinear, linear + secant,
 * multires on triangles and bilinear,
 * safety (then its isotropic layout when `variants`), cones, QDM, cylinder-cones and
 * safety radii (then zero radii clamped when `variants`) on triangles, then safety,
 * cylinder-cones and radii on the view-linear surface. Returns the new count. */
static int search_to_cc_cfgs(method_cfg *out, int n, int variants) {
    static const uint32_t list[][2] = {
        {HF_METHOD_LINEAR_BINARY, HF_SURFACE_TRIANGLES},
        {HF_METHOD_LINEAR_BINARY, HF_SURFACE_BILINEAR},
        {HF_METHOD_LINEAR_SECANT, HF_SURFACE_TRIANGLES},
        {HF_METHOD_MULTIRES, HF_SURFACE_TRIANGLES},
        {HF_METHOD_MULTIRES, HF_SURFACE_BILINEAR},
        {HF_METHOD_SAFETY, HF_SURFACE_TRIANGLES},
        {HF_METHOD_CONE, HF_SURFACE_TRIANGLES},
        {HF_METHOD_QDM, HF_SURFACE_TRIANGLES},
        {HF_METHOD_CC, HF_SURFACE_TRIANGLES},
        {HF_METHOD_RADIUS, HF_SURFACE_TRIANGLES},
        /* The same maps finishing on the view-linear surface (Baboud et al. §7). */
        {HF_METHOD_SAFETY, HF_SURFACE_VIEW_LINEAR},
        {HF_METHOD_CC, HF_SURFACE_VIEW_LINEAR},
        {HF_METHOD_RADIUS, HF_SURFACE_VIEW_LINEAR},
    };
    _Static_assert(sizeof list / sizeof list[0] + 2 <= SEARCH_TO_CC_CFGS, "callers' arrays");
    for (size_t k = 0; k < sizeof list / sizeof list[0]; k++) {
        out[n++] = cfg_of(list[k][0], list[k][1]);
        int tri = list[k][1] == HF_SURFACE_TRIANGLES;
        if (variants && tri && list[k][0] == HF_METHOD_SAFETY) {
            out[n] = out[n - 1];
            out[n++].variant = HF_SAFETY_ISOTROPIC;
        }
        if (variants && tri && list[k][0] == HF_METHOD_RADIUS) {
            out[n] = out[n - 1];
            out[n++].zero = HF_RADIUS_CLAMP;
        }
    }
    return n;
}

/* Whether `method` answers exactly (the searches and relaxed cones have step budgets). */
/* "METHOD/SURFACE". */
static void cfg_name(char *buf, size_t len, method_cfg c) {
    snprintf(buf, len, "%s/%s", method_name(c.method), surface_name(c.surface));
}

/* The class subsets of the compact-map cases (HF_RAYS_* bits). The default camera looks
 * along -x and -y (azimuth 0.6 rad): its primary rays are of the classes x- and y-, so
 * either subset holds the class of some pixels' rays and not of the others' (those
 * read zero jumps without a fetch); the shadow rays (LIGHT_DIR) are of class x+, held
 * by the first subset only. */
static const uint32_t SUBSETS[] = {HF_RAYS_X_POS | HF_RAYS_Y_NEG, HF_RAYS_X_NEG};
#define NUM_SUBSETS (sizeof SUBSETS / sizeof SUBSETS[0])

/* The maps of one compact-map or ray-set case: the classes they hold and the ray set
 * they are baked for (hf_bake_options' exterior and max_view_angle_deg). */
typedef struct map_set {
    uint32_t classes, exterior;
    float angle;
    int walls; /* baked over walls around the field (scene_use_walls) */
} map_set;

/* Each class subset for every ray, then every class for exterior rays within 60
 * degrees of the downward vertical (shadertest's RAY_SET), then for exterior rays. The
 * default camera is outside the box and looks 14 to 54 degrees below the horizon: its
 * steeper rays are within 60 degrees, the flatter ones not. Over exterior maps the
 * shadow rays are traced from the light's side (query_walked_back, hf_ray_walked_back):
 * exterior, 61 degrees from the vertical (outside the first set, in the second). Last,
 * the first set over walls around the field (scene_use_walls): rays whose line dips
 * under a wall are outside it. A ray outside the set walks cell by cell. */
static const map_set MAP_SETS[] = {
    {HF_RAYS_X_POS | HF_RAYS_Y_NEG, 0, 0.0f, 0},
    {HF_RAYS_X_NEG, 0, 0.0f, 0},
    {HF_RAYS_ALL, 1, 60.0f, 0},
    {HF_RAYS_ALL, 1, 0.0f, 0},
    {HF_RAYS_ALL, 1, 60.0f, 1},
};
#define NUM_MAP_SETS (sizeof MAP_SETS / sizeof MAP_SETS[0])

/* Whether `r` is a ray of the set of s's maps (`Rays::holds`, in float, its walls
 * aside: for the counts printed only). */
static int ray_in_set(const scene *s, const hf_ray *r) {
    if (s->exterior) {
        float p[3];
        for (int k = 0; k < 3; k++) p[k] = r->origin[k] + r->t_min * r->dir[k];
        int outside = p[0] < 0.0f || p[0] > (float)(s->w - 1) || p[1] < 0.0f ||
                      p[1] > (float)(s->h - 1) || p[2] < s->info.min_height ||
                      p[2] > s->info.max_height;
        if (!outside) return 0;
    }
    if (s->max_view_angle_deg > 0.0f && s->max_view_angle_deg < 180.0f) {
        float a = s->max_view_angle_deg * 0.017453292519943295f;
        float run = sqrtf(r->dir[0] * r->dir[0] + r->dir[1] * r->dir[1]);
        if (r->dir[2] > -cosf(a) / sinf(a) * run) return 0;
    }
    return 1;
}

/* The HF_RAYS_* bit of a ray direction's class (as the library classifies). */
static uint32_t ray_class_bit(const float *d) {
    float dx = d[0], dy = d[1];
    int zero = dx == 0.0f && dy == 0.0f;
    if (dx >= fabsf(dy) && !zero) return HF_RAYS_X_POS;
    if (-dx >= fabsf(dy) && !zero) return HF_RAYS_X_NEG;
    return dy > fabsf(dx) ? HF_RAYS_Y_POS : HF_RAYS_Y_NEG;
}

/* " holding x+,y-" for maps of the classes `classes`; "" for the whole maps. */
static void classes_suffix(char *buf, size_t len, const scene *s) {
    static const char *names[4] = {"x+", "x-", "y+", "y-"};
    const char *sep = " holding ";
    buf[0] = 0;
    for (int k = 0; k < 4 && s->classes != HF_RAYS_ALL; k++) {
        if (!(s->classes & (1u << k))) continue;
        size_t at = strlen(buf);
        snprintf(buf + at, len - at, "%s%s", sep, names[k]);
        sep = ",";
    }
    size_t at = strlen(buf);
    if (s->exterior && s->max_view_angle_deg > 0.0f)
        snprintf(buf + at, len - at, " for exterior,angle:%g", s->max_view_angle_deg);
    else if (s->exterior)
        snprintf(buf + at, len - at, " for exterior");
    else if (s->max_view_angle_deg > 0.0f)
        snprintf(buf + at, len - at, " for angle:%g", s->max_view_angle_deg);
    at = strlen(buf);
    if (s->occluder_count) snprintf(buf + at, len - at, " over walls");
}

/* A map set up for rendering: its scene, GPU state and the default camera's rays. */
typedef struct map_job {
    scene s;
    gpu g;
    float depth_far;
    hf_ray *rays; /* w x h, uploaded */
    int relaxed;  /* the scene has its relaxed cone map (test runs) */
} map_job;

typedef void (*map_fn)(map_job *j, int w, int h, void *ctx);

/* "MAP METHOD[-isotropic|-clamp]/SURFACE`extra`[ holding CLASSES]": a case's label. */
static void case_label(char *buf, size_t len, const map_job *j, method_cfg c,
                       const char *extra) {
    char holding[64];
    classes_suffix(holding, sizeof holding, &j->s);
    snprintf(buf, len, "%s %s%s/%s%s%s", j->s.name, method_name(c.method),
             c.method == HF_METHOD_SAFETY && c.variant == HF_SAFETY_ISOTROPIC ? "-isotropic"
             : c.method == HF_METHOD_RADIUS && c.zero == HF_RADIUS_CLAMP   ? "-clamp"
                                                                           : "",
             surface_name(c.surface), extra, holding);
}

/* Runs `fn` on every map of `maps` set up for a w x h image (with the relaxed cone map
 * when `with_relaxed`), a map it cannot read skipped with a line "skip MAP" and
 * `skip_note`. Returns the number of maps loaded, -1 when the GPU setup failed. */
static int for_each_map(int w, int h, int nmaps, char **maps, int with_relaxed,
                        const char *skip_note, map_fn fn, void *ctx) {
    int loaded = 0;
    for (int m = 0; m < nmaps; m++) {
        map_job j;
        j.relaxed = with_relaxed;
        const char *path = maps[m];
        if (scene_load_ex(&j.s, path, with_relaxed) != 0) {
            printf("skip %s%s\n", path, skip_note);
            continue;
        }
        loaded++;
        if (gpu_init(&j.g, &j.s, w, h) != 0) {
            fprintf(stderr, "gpu_init failed\n");
            return -1;
        }
        camera cam = default_camera();
        j.depth_far = scene_depth_far(&j.s, &cam);
        j.rays = (hf_ray *)malloc(sizeof(hf_ray) * (size_t)w * h);
        make_rays(&j.s, &cam, w, h, j.rays);
        gpu_upload_rays(&j.g, j.rays);
        fn(&j, w, h, ctx);
        free(j.rays);
        gpu_free(&j.g);
        scene_free(&j.s);
    }
    return loaded;
}

/* Renders a frame of `c` with program `prog` (0: the general shader of the method;
 * `u16` as gpu_render_program) and waits for it; returns its time in ms. */
static double render_ms(map_job *j, method_cfg c, GLuint prog, int u16) {
    double t0 = now_seconds();
    if (prog)
        gpu_render_program(&j->g, prog, &j->s, c, j->depth_far, u16);
    else
        gpu_render(&j->g, &j->s, c, j->depth_far);
    glFinish();
    return 1e3 * (now_seconds() - t0);
}

/* The count of a test run. */
typedef struct tally {
    int passed, failed;
    int identical;      /* generated shaders: frames bit-identical to the general one's */
    const char *outdir; /* parity: where the images go */
} tally;

/* Starts the renderer of the tests (TEST_W x TEST_H) and names it. */
static int tests_start(void) {
    if (gl_start(TEST_W, TEST_H) != 0) return -1;
    printf("renderer: %s / %s\n", (const char *)glGetString(GL_RENDERER),
           (const char *)glGetString(GL_VERSION));
    return 0;
}

/* Stops the renderer after a test run over `loaded` maps (for_each_map's count): 0, or
 * 2 when the GPU setup failed or no map could be loaded. */
static int tests_stop(int loaded) {
    gl_stop();
    if (loaded < 0) return 2;
    if (loaded == 0) {
        fprintf(stderr, "no map could be loaded\n");
        return 2;
    }
    return 0;
}

/* Counts one check in `t`. */
static void tally_add(tally *t, int ok) {
    if (ok)
        t->passed++;
    else
        t->failed++;
}

/* The last line of a test run, "NAME: N passed, M failed", and its exit status. */
static int tests_result(const char *name, const tally *t) {
    printf("%s: %d passed, %d failed\n", name, t->passed, t->failed);
    return t->failed == 0 ? 0 : 1;
}

/* ---- parity test ------------------------------------------------------------------- */

/* Renders `c` with program `prog` (0: the general shader) on the job's maps, compares the
 * frame `f` with the CPU's answers for `rays` (the uploaded ones) and prints the line of
 * the case, labelled with `extra`. Returns whether it passed (`strict`: no pixel, shadow
 * or depth may differ, beyond parity_ok). */
static int parity_case_with(map_job *j, int w, int h, method_cfg c, frame *f, int strict,
                            GLuint prog, const hf_ray *rays, const char *extra) {
    double ms = render_ms(j, c, prog, 0);
    gpu_read(&j->g, f);
    char label[256];
    case_label(label, sizeof label, j, c, extra);
    parity p = compare(&j->s, c, rays, f, j->depth_far, w, h, 0, label);
    int ok = parity_ok(&p, c.method) &&
             (!strict || p.differ + p.shadow_differ + p.depth_differ == 0);
    printf("parity %-40s %d pixels, %d cpu hits, %d differ (%d hit/miss, %d > 1e-3), max "
           "err %.2e; shadows %d/%d differ; depth %d differ; gpu %.0f ms  %s\n",
           label, p.pixels, p.hits, p.differ, p.differ_hit, p.differ_pos, p.max_err,
           p.shadow_differ, p.shadow_checked, p.depth_differ, ms, ok ? "ok" : "FAILED");
    if (!ok || p.differ > 0) compare(&j->s, c, rays, f, j->depth_far, w, h, 1, label);
    return ok;
}

/* parity_case_with the general shader on the job's rays. */
static int parity_case(map_job *j, int w, int h, method_cfg c, frame *f, int strict) {
    return parity_case_with(j, w, h, c, f, strict, 0, j->rays, "");
}

/* The configurations run on the compact maps of each of MAP_SETS: safety (directional
 * and isotropic) and cylinder-cones on triangles. */
enum { SUBSET_CFGS = 3 };
static void subset_cfgs(method_cfg out[SUBSET_CFGS]) {
    out[0] = cfg_of(HF_METHOD_SAFETY, HF_SURFACE_TRIANGLES);
    out[1] = out[0];
    out[1].variant = HF_SAFETY_ISOTROPIC;
    out[2] = cfg_of(HF_METHOD_CC, HF_SURFACE_TRIANGLES);
}

/* Rebakes the job's safety and cylinder-cone maps for the map set `m` (its ray classes
 * only, for its ray set), uploads them (W x nH) and prints how many primary rays are of
 * classes held and in the set. */
static void use_maps(map_job *j, int w, int h, map_set m) {
    scene_use_walls(&j->s, m.walls);
    scene_set_maps(&j->s, m.classes, m.exterior, m.angle);
    gpu_upload_class_maps(&j->g, &j->s);
    size_t held = 0, in_set = 0, n = (size_t)w * h;
    for (size_t k = 0; k < n; k++) {
        held += (ray_class_bit(j->rays[k].dir) & m.classes) != 0;
        in_set += ray_in_set(&j->s, &j->rays[k]);
    }
    char holding[64];
    classes_suffix(holding, sizeof holding, &j->s);
    const float from_light[3] = {-LIGHT_DIR[0], -LIGHT_DIR[1], -LIGHT_DIR[2]};
    const float *shadow_dir = m.exterior ? from_light : LIGHT_DIR;
    printf("maps of %s%s: %zu primary rays of classes held, %zu of classes not held, %zu in "
           "the ray set (walls aside); shadow rays (%s, from the %s) of a class %s\n",
           j->s.name, holding, held, n - held, in_set, m.exterior ? "x-" : "x+",
           m.exterior ? "light" : "surface",
           ray_class_bit(shadow_dir) & m.classes ? "held" : "not held");
}

/* The rays of `a` and `b` that differ: hit or miss, or hit points more than 1e-3 apart. */
static int hits_differ(const hf_hit *a, const hf_hit *b, size_t n) {
    int differ = 0;
    for (size_t k = 0; k < n; k++)
        differ += a[k].hit != b[k].hit || (a[k].hit && !(dist3(a[k].point, b[k].point) <= 1e-3f));
    return differ;
}

/* The compact-map and ray-set cases on one map (after the whole-map ones), each of
 * MAP_SETS: the GPU on those maps (the uniform masks and ray set set) against the CPU
 * with the same mask (the ray set read from the maps' descriptors), no pixel
 * differing, and the CPU answers on those maps against those on the whole maps (exact
 * marches: the same hits). */
static void parity_subsets(map_job *j, int w, int h, frame *f, tally *t) {
    size_t n = (size_t)w * h;
    method_cfg cfgs[SUBSET_CFGS];
    subset_cfgs(cfgs);
    hf_hit *whole = (hf_hit *)malloc(sizeof(hf_hit) * n * SUBSET_CFGS);
    hf_hit *part = (hf_hit *)malloc(sizeof(hf_hit) * n);
    for (int k = 0; k < SUBSET_CFGS; k++)
        if (cpu_trace(&j->s, cfgs[k], j->rays, n, whole + k * n) != HF_OK) t->failed++;
    for (size_t m = 0; m < NUM_MAP_SETS; m++) {
        use_maps(j, w, h, MAP_SETS[m]);
        for (int k = 0; k < SUBSET_CFGS; k++) {
            int ok = parity_case(j, w, h, cfgs[k], f, 1);
            int differ = cpu_trace(&j->s, cfgs[k], j->rays, n, part) == HF_OK
                             ? hits_differ(whole + k * n, part, n)
                             : (int)n;
            printf("  cpu on these maps vs the whole maps: %d of %zu rays differ  %s\n",
                   differ, n, differ == 0 ? "ok" : "FAILED");
            if (ok && differ == 0) t->passed++; else t->failed++;
        }
    }
    free(whole);
    free(part);
}

/* ---- world units (world.glsl) ------------------------------------------------------ */

/* The transform of the world-unit cases: unequal spacings, y flipped, heights scaled
 * and offset (as shadertest/tests/wgsl_world.rs). */
static const hf_transform WORLD = {{-310.5, 1250.25}, {3.0, -2.5}, 1.75, -42.0};

/* The program of `method` whose main traces with hf_trace_world instead of hf_trace. */
static GLuint link_world_program(uint32_t method) {
    char *src = fragment_source(method);
    const char *call = "Trace tr = hf_trace(q);", *world = "Trace tr = hf_trace_world(q);";
    char *at = strstr(src, call);
    if (!at) {
        fprintf(stderr, "no \"%s\" in the renderer's main\n", call);
        exit(2);
    }
    char *out = (char *)malloc(strlen(src) + strlen(world) - strlen(call) + 1);
    size_t head = (size_t)(at - src);
    memcpy(out, src, head);
    strcpy(out + head, world);
    strcat(out, at + strlen(call));
    free(src);
    GLuint p = link_fragment(out);
    free(out);
    return p;
}

/* The world rays of the grid rays `rays` under `t`: the same lines, the directions
 * scaled (not renormalised) so that t and the ranges are unchanged. */
static void world_rays(const hf_transform *t, const hf_ray *rays, size_t n, hf_ray *out) {
    const double off[3] = {t->origin[0], t->origin[1], t->height_offset};
    const double sc[3] = {t->spacing[0], t->spacing[1], t->height_scale};
    for (size_t k = 0; k < n; k++) {
        out[k] = rays[k];
        for (int a = 0; a < 3; a++) {
            out[k].origin[a] = (float)(off[a] + sc[a] * rays[k].origin[a]);
            out[k].dir[a] = (float)(sc[a] * rays[k].dir[a]);
        }
    }
}

/* Whether two frames are the same bit for bit. */
static int frames_identical(const frame *a, const frame *b, size_t n) {
    return memcmp(a->point, b->point, sizeof(float) * 4 * n) == 0 &&
           memcmp(a->normal, b->normal, sizeof(float) * 4 * n) == 0 &&
           memcmp(a->color, b->color, 4 * n) == 0 &&
           memcmp(a->depth, b->depth, sizeof(float) * n) == 0;
}

/* World units on one map, for exact traversal, maximum mipmaps and cylinder-cones on
 * triangles, with the renderer's main calling hf_trace_world: with its default
 * (identity) uniforms on the grid rays, the frame of hf_trace bit for bit; with
 * hf_world_offset / hf_world_scale set to WORLD, on the world rays, the C API's answers
 * on the field placed by hf_field_set_transform(WORLD) (parity_ok). The field's
 * transform and the uploaded rays are restored after. */
static void parity_world(map_job *j, int w, int h, frame *f, tally *t) {
    static const hf_transform identity = {{0.0, 0.0}, {1.0, 1.0}, 1.0, 0.0};
    static const uint32_t methods[] = {HF_METHOD_EXACT, HF_METHOD_MAXMIP, HF_METHOD_CC};
    size_t n = (size_t)w * h;
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * n);
    world_rays(&WORLD, j->rays, n, rays);
    frame plain;
    frame_alloc(&plain, w, h);
    for (size_t k = 0; k < sizeof methods / sizeof methods[0]; k++) {
        method_cfg c = cfg_of(methods[k], HF_SURFACE_TRIANGLES);
        GLuint prog = link_world_program(c.method);
        render_ms(j, c, 0, 0);
        gpu_read(&j->g, &plain);
        render_ms(j, c, prog, 0);
        gpu_read(&j->g, f);
        int same = frames_identical(&plain, f, n);
        char label[256];
        case_label(label, sizeof label, j, c, "");
        printf("world %-41s identity: frame of hf_trace_world %s that of hf_trace  %s\n",
               label, same ? "bit-identical to" : "DIFFERS from", same ? "ok" : "FAILED");
        glUseProgram(prog);
        glUniform3f(glGetUniformLocation(prog, "hf_world_offset"), (float)WORLD.origin[0],
                    (float)WORLD.origin[1], (float)WORLD.height_offset);
        glUniform3f(glGetUniformLocation(prog, "hf_world_scale"), (float)WORLD.spacing[0],
                    (float)WORLD.spacing[1], (float)WORLD.height_scale);
        hf_result r = hf_field_set_transform(j->s.field, &WORLD);
        gpu_upload_rays(&j->g, rays);
        int ok = r == HF_OK && parity_case_with(j, w, h, c, f, 0, prog, rays, " world");
        if (hf_field_set_transform(j->s.field, &identity) != HF_OK) ok = 0;
        gpu_upload_rays(&j->g, j->rays);
        glDeleteProgram(prog);
        if (ok && same) t->passed++; else t->failed++;
    }
    frame_free(&plain);
    free(rays);
}

/* ---- projective fields (projective.glsl) -------------------------------------------- */

/* `a · b`, 4 x 4 row-major. */
static void mat4_mul(const double *a, const double *b, double *out) {
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            double v = 0.0;
            for (int k = 0; k < 4; k++) v += a[4 * r + k] * b[4 * k + c];
            out[4 * r + c] = v;
        }
}

/* `m · [v, 1]` divided by its w. */
static void mat4_point(const double *m, const double *v, double *out) {
    double h[4];
    for (int r = 0; r < 4; r++)
        h[r] = m[4 * r] * v[0] + m[4 * r + 1] * v[1] + m[4 * r + 2] * v[2] + m[4 * r + 3];
    for (int k = 0; k < 3; k++) out[k] = h[k] / h[3];
}

/* The reverse-perspective frustum of core/tests/projective.rs for a w x h field, world
 * to homogeneous grid, and its inverse (both row-major): P · A with P the perspective
 * (centre f under (cx, cy)) and A a shear and scale, inverted in closed form. */
static void projective_frustum(uint32_t w, uint32_t h, double m[16], double inv[16]) {
    const double xm = (double)w - 1.0, ym = (double)h - 1.0, f = 3.0 * (xm + ym);
    const double a = 0.5 * xm / f, b = 0.4 * ym / f;
    const double p[16] = {1, 0, a, 0, 0, 1, b, 0, 0, 0, 1, 0, 0, 0, 1 / f, 1};
    const double p_inv[16] = {1, 0, -a, 0, 0, 1, -b, 0, 0, 0, 1, 0, 0, 0, -1 / f, 1};
    const double s[16] = {1.5, 0.2, 0, 0, 0, 0.8, 0, 0, 0, 0, 1.2, 0, 0, 0, 0, 1};
    const double s_inv[16] = {1 / 1.5, -0.2 / (1.5 * 0.8), 0, 0, 0, 1 / 0.8, 0, 0,
                              0,       0,                  1 / 1.2, 0, 0, 0, 0, 1};
    mat4_mul(p, s, m);
    mat4_mul(s_inv, p_inv, inv);
}

/* The program of `method` whose main traces with hf_trace_projective, the map and its
 * inverse by rows from the uniforms proj_m0..3 and proj_i0..3. */
static GLuint link_projective_program(uint32_t method) {
    char *src = fragment_source(method);
    const char *call = "Trace tr = hf_trace(q);";
    const char *proj = "Trace tr = hf_trace_projective(Mat4Rows(proj_m0, proj_m1, proj_m2, "
                       "proj_m3), Mat4Rows(proj_i0, proj_i1, proj_i2, proj_i3), q);";
    const char *decl = "uniform vec4 proj_m0, proj_m1, proj_m2, proj_m3;\n"
                       "uniform vec4 proj_i0, proj_i1, proj_i2, proj_i3;\n";
    char *at = strstr(src, call), *main_at = strstr(src, "void main() {");
    if (!at || !main_at || main_at > at) {
        fprintf(stderr, "no \"%s\" in the renderer's main\n", call);
        exit(2);
    }
    size_t cap = strlen(src) + strlen(proj) + strlen(decl) + 1;
    char *out = (char *)malloc(cap);
    size_t head = (size_t)(main_at - src);
    memcpy(out, src, head);
    out[head] = 0;
    strcat(out, decl);
    strncat(out, main_at, (size_t)(at - main_at));
    strcat(out, proj);
    strcat(out, at + strlen(call));
    free(src);
    GLuint p = link_fragment(out);
    free(out);
    return p;
}

/* Projective fields on one map, for exact traversal, maximum mipmaps and cylinder-cones
 * on triangles: the renderer's main calling hf_trace_projective through the
 * reverse-perspective frustum (projective_frustum), primary rays only, on world rays
 * whose grid lines are the camera's rays, against hf_projective_trace_batch: hit or
 * miss the same and hit points within 1e-4 of the ray's magnitude (the shader maps in
 * float, the library in double) on at least 99.99 % of the pixels. */
static void parity_projective(map_job *j, int w, int h, frame *f, tally *t) {
    static const uint32_t methods[] = {HF_METHOD_EXACT, HF_METHOD_MAXMIP, HF_METHOD_CC};
    size_t n = (size_t)w * h;
    double m[16], inv[16];
    projective_frustum(j->s.w, j->s.h, m, inv);
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * n);
    for (size_t k = 0; k < n; k++) {
        const hf_ray *g = &j->rays[k];
        double o[3] = {g->origin[0], g->origin[1], g->origin[2]}, p[3], ow[3], pw[3];
        for (int c = 0; c < 3; c++) p[c] = o[c] + g->dir[c];
        mat4_point(inv, o, ow);
        mat4_point(inv, p, pw);
        double len = 0.0;
        for (int c = 0; c < 3; c++) len += (pw[c] - ow[c]) * (pw[c] - ow[c]);
        len = sqrt(len);
        rays[k] = *g;
        for (int c = 0; c < 3; c++) {
            rays[k].origin[c] = (float)ow[c];
            rays[k].dir[c] = (float)((pw[c] - ow[c]) / len);
        }
        rays[k].t_min = 0.0f;
        rays[k].t_max = INFINITY;
    }
    hf_hit *hits = (hf_hit *)malloc(sizeof(hf_hit) * n);
    gpu_upload_rays(&j->g, rays);
    j->g.primary_only = 1;
    for (size_t k = 0; k < sizeof methods / sizeof methods[0]; k++) {
        method_cfg c = cfg_of(methods[k], HF_SURFACE_TRIANGLES);
        GLuint prog = link_projective_program(c.method);
        glUseProgram(prog);
        const char *names[2] = {"proj_m", "proj_i"};
        const double *mats[2] = {m, inv};
        for (int q = 0; q < 2; q++)
            for (int r = 0; r < 4; r++) {
                char name[16];
                snprintf(name, sizeof name, "%s%d", names[q], r);
                const double *row = mats[q] + 4 * r;
                glUniform4f(glGetUniformLocation(prog, name), (float)row[0], (float)row[1],
                            (float)row[2], (float)row[3]);
            }
        render_ms(j, c, prog, 0); /* the first frame: its time is the shader's compile */
        gpu_read(&j->g, f);
        int differ = 0, gpu_hits = 0;
        double max_rel = 0.0;
        hf_result r = cpu_trace_projective(&j->s, c, m, rays, n, hits);
        for (size_t q = 0; q < n && r == HF_OK; q++) {
            const float *gp = f->point + 4 * q;
            int ghit = gp[3] >= 0.0f, chit = hits[q].hit != 0;
            gpu_hits += ghit;
            if (ghit != chit) {
                differ++;
                continue;
            }
            if (!chit) continue;
            double mag = 1.0;
            for (int a = 0; a < 3; a++) {
                double v = fabs((double)rays[q].origin[a]);
                if (v > mag) mag = v;
            }
            double rel = dist3(gp, hits[q].point) / mag;
            if (rel > max_rel) max_rel = rel;
            if (!(rel <= 1e-4)) differ++;
        }
        char label[256];
        case_label(label, sizeof label, j, c, "");
        int ok = r == HF_OK && gpu_hits > (int)(n / 10) && (double)differ <= 1e-4 * (double)n;
        printf("projective %-36s %zu pixels, %d gpu hits, %d differ, max rel err %.1e  %s\n",
               label, n, gpu_hits, differ, max_rel, ok ? "ok" : "FAILED");
        glDeleteProgram(prog);
        if (ok) t->passed++; else t->failed++;
    }
    j->g.primary_only = 0;
    gpu_upload_rays(&j->g, j->rays);
    free(hits);
    free(rays);
}

/* Every configuration on one map (relaxed cones too when the job has their map)
 * against the CPU, then the world-unit, projective and class-subset cases; the images
 * of the exact methods on triangles (safety: directional) go to the outdir. */
static void parity_map(map_job *j, int w, int h, void *ctx) {
    tally *t = (tally *)ctx;
    frame f;
    frame_alloc(&f, w, h);
    method_cfg cfgs[2 * HF_SURFACE_COUNT + 1 + SEARCH_TO_CC_CFGS];
    int ncfg = 0;
    for (uint32_t sf = 0; sf < HF_SURFACE_COUNT; sf++)
        cfgs[ncfg++] = cfg_of(HF_METHOD_EXACT, sf);
    for (uint32_t sf = 0; sf < HF_SURFACE_COUNT; sf++)
        cfgs[ncfg++] = cfg_of(HF_METHOD_MAXMIP, sf);
    ncfg = search_to_cc_cfgs(cfgs, ncfg, 1);
    if (j->relaxed) cfgs[ncfg++] = cfg_of(HF_METHOD_RELAXED, HF_SURFACE_TRIANGLES);
    for (int k = 0; k < ncfg; k++) {
        method_cfg c = cfgs[k];
        if (parity_case(j, w, h, c, &f, 0)) t->passed++; else t->failed++;
        if (c.surface == HF_SURFACE_TRIANGLES && method_exact(c.method) &&
            c.variant == HF_SAFETY_DIRECTIONAL && c.zero == HF_RADIUS_WALK) {
            char path[512];
            snprintf(path, sizeof path, "%s/%s_%s_triangles.png", t->outdir, j->s.name,
                     method_name(c.method));
            if (write_png_rgba(path, f.color, w, h) != 0) {
                fprintf(stderr, "cannot write %s\n", path);
                t->failed++;
            }
        }
    }
    parity_world(j, w, h, &f, t);
    parity_projective(j, w, h, &f, t);
    parity_subsets(j, w, h, &f, t);
    frame_free(&f);
}

static int run_tests(const char *outdir, int nmaps, char **maps) {
    if (tests_start() != 0) return 2;
    tally t = {0, 0, 0, outdir};
    int loaded = for_each_map(TEST_W, TEST_H, nmaps, maps, 1, ": cannot read it", parity_map, &t);
    if (tests_stop(loaded) != 0) return 2;
    return tests_result("osmesa-parity", &t);
}

/* ---- benchmark --------------------------------------------------------------------- */

/* The frame time of every method but relaxed cones (its bake takes minutes) on one
 * map, and the time and texel fetches of its primary rays on the CPU. */
static void bench_map(map_job *j, int w, int h, void *ctx) {
    int frames = *(const int *)ctx;
    size_t n = (size_t)w * h;
    hf_hit *hits = (hf_hit *)malloc(sizeof(hf_hit) * n);
    printf("%-36s bakes (all cores): safety %.0f ms, cone %.0f ms, qdm %.0f ms, cc %.0f ms, "
           "radius %.0f ms\n",
           j->s.name, j->s.safety_bake_ms, j->s.cone_bake_ms, j->s.qdm_bake_ms, j->s.cc_bake_ms,
           j->s.radius_bake_ms);
    for (uint32_t m = 0; m < NUM_METHODS; m++) {
        if (m == HF_METHOD_RELAXED) continue;
        method_cfg c = cfg_of(m, HF_SURFACE_TRIANGLES);
        render_ms(j, c, 0, 0); /* warm-up: shader compile */
        double gpu_ms = 0;
        for (int i = 0; i < frames; i++) gpu_ms += render_ms(j, c, 0, 0);
        gpu_ms /= frames;
        double t0 = now_seconds();
        cpu_trace(&j->s, c, j->rays, n, hits);
        double cpu_ms = 1e3 * (now_seconds() - t0);
        double fetches = 0;
        for (size_t i = 0; i < n; i++) fetches += hits[i].fetches;
        char mname[64];
        cfg_name(mname, sizeof mname, c);
        printf("%-36s %-24s %10.1f %10.1f %12.1f\n", j->s.name, mname, gpu_ms, cpu_ms,
               fetches / (double)n);
    }
    free(hits);
}

static int run_bench(int w, int h, int frames, int nmaps, char **maps) {
    if (gl_start(w, h) != 0) return 2;
    printf("frame time, %d x %d, primary + shadow ray per pixel, %s (software)\n", w, h,
           (const char *)glGetString(GL_RENDERER));
    printf("%-36s %-24s %10s %10s %12s\n", "map", "method", "gpu ms", "cpu ms", "fetches/ray");
    if (for_each_map(w, h, nmaps, maps, 0, "", bench_map, &frames) < 0) return 2;
    printf("(gpu ms: llvmpipe, whole frame with shadow rays; cpu ms: primary rays only, one "
           "thread, C API batch)\n");
    gl_stop();
    return 0;
}

/* ---- generated shaders --------------------------------------------------------------- */

/* The scene description of a renderer configuration: the general scene of its method
 * and surface (any view angle, so upward rays stay; shadows from the light), with 16-bit
 * heights when `u16`, its ray classes those the maps hold (`classes`: the generated
 * shader's hf_safety_classes / hf_cc_classes constants). */
static hf_scene scene_of_cfg(method_cfg c, int u16, uint32_t classes) {
    hf_scene sc;
    hf_result r = hf_scene_general(c.method, c.surface, &sc);
    if (r != HF_OK) {
        fprintf(stderr, "hf_scene_general failed (%u)\n", (unsigned)r);
        exit(2);
    }
    sc.depth_output = 1;
    /* Shadow rays from the light's side keep query_walked_back (the renderer calls it
     * over maps of exterior rays); nothing else changes (the view angle stays 180). */
    sc.shadows = HF_SHADOWS_FROM_LIGHT;
    sc.height_format = u16 ? HF_HEIGHTS_U16 : HF_HEIGHTS_F32;
    sc.ray_classes = classes;
    return sc;
}

static size_t count_lines(const char *src) {
    size_t n = 0;
    for (; *src; src++) n += *src == '\n';
    return n;
}

/* The program of the shader generated for `c` (`u16`: 16-bit heights) on maps of the
 * ray classes `classes`, and the line counts of its fragment shader and of the general
 * one of the method. */
static GLuint generated_program(method_cfg c, int u16, uint32_t classes, size_t *lines_min,
                                size_t *lines_gen) {
    hf_scene sc = scene_of_cfg(c, u16, classes);
    char *src = generated_fragment_source(&sc);
    char *gen_src = fragment_source(c.method);
    *lines_min = count_lines(src);
    *lines_gen = count_lines(gen_src);
    free(gen_src);
    GLuint prog = link_fragment(src);
    free(src);
    return prog;
}

/* How two frames of the same rays compare: 2 when every hit, normal, shadow, depth and
 * colour is the same bit for bit; 1 when they hold the same hits (hit or miss, shadow,
 * hit points within 1e-3 texel: the shader compiler may fuse a multiply-add differently
 * in different code); 0 otherwise, listing up to 5 such pixels. `*rounded`: pixels
 * not bit-identical. */
static int frames_compare(const frame *a, const frame *b, int w, int h, int *rounded) {
    size_t n = (size_t)w * h;
    int listed = 0;
    *rounded = 0;
    for (size_t k = 0; k < n; k++) {
        const float *pa = a->point + 4 * k, *pb = b->point + 4 * k;
        if (memcmp(pa, pb, sizeof(float) * 4) == 0 &&
            memcmp(a->normal + 4 * k, b->normal + 4 * k, sizeof(float) * 4) == 0 &&
            memcmp(a->depth + k, b->depth + k, sizeof(float)) == 0 &&
            memcmp(a->color + 4 * k, b->color + 4 * k, 4) == 0)
            continue;
        (*rounded)++;
        int ha = pa[3] >= 0.0f, hb = pb[3] >= 0.0f;
        int sa = a->normal[4 * k + 3] > 0.5f, sb = b->normal[4 * k + 3] > 0.5f;
        if (ha == hb && sa == sb && (!ha || dist3(pa, pb) <= 1e-3f)) continue;
        if (listed++ < 5)
            fprintf(stderr,
                    "  pixel (%d, %d): general (%.9g, %.9g, %.9g) t=%.9g shadow %d, generated "
                    "(%.9g, %.9g, %.9g) t=%.9g shadow %d\n",
                    (int)(k % w), (int)(k / w), pa[0], pa[1], pa[2], pa[3], sa, pb[0], pb[1],
                    pb[2], pb[3], sb);
    }
    return listed > 0 ? 0 : *rounded > 0 ? 1 : 2;
}

/* The configurations the generated-shader test uses. */
typedef struct gen_case {
    method_cfg cfg;
    int u16;
} gen_case;

static int generated_cases(gen_case *out) {
    method_cfg cfgs[2 * HF_SURFACE_COUNT + SEARCH_TO_CC_CFGS];
    int n = 0;
    for (uint32_t sf = 0; sf < HF_SURFACE_COUNT; sf++) {
        cfgs[n++] = cfg_of(HF_METHOD_EXACT, sf);
        cfgs[n++] = cfg_of(HF_METHOD_MAXMIP, sf);
    }
    n = search_to_cc_cfgs(cfgs, n, 0);
    for (int k = 0; k < n; k++) {
        out[k].cfg = cfgs[k];
        out[k].u16 = 0;
    }
    /* 16-bit heights: an R16UI texture of the samples, the generated field_at. */
    static const uint32_t u16[][2] = {{HF_METHOD_EXACT, HF_SURFACE_TRIANGLES},
                                      {HF_METHOD_MAXMIP, HF_SURFACE_BILINEAR},
                                      {HF_METHOD_CC, HF_SURFACE_TRIANGLES}};
    for (size_t k = 0; k < sizeof u16 / sizeof u16[0]; k++) {
        out[n].cfg = cfg_of(u16[k][0], u16[k][1]);
        out[n++].u16 = 1;
    }
    return n;
}

/* One case with the general and the generated shader (for the job's maps' classes):
 * the frames must be identical (16-bit heights: the general shader reads the same
 * heights as floats), and the generated one must agree with the CPU as the parity
 * test demands. `fg`, `fm`: room for the two frames. */
static void generated_case(map_job *j, int w, int h, gen_case gc, frame *fg, frame *fm,
                           tally *t) {
    method_cfg c = gc.cfg;
    size_t lines_min, lines_gen;
    GLuint prog = generated_program(c, gc.u16, j->s.classes, &lines_min, &lines_gen);
    render_ms(j, c, 0, 0);
    gpu_read(&j->g, fg);
    render_ms(j, c, prog, gc.u16);
    gpu_read(&j->g, fm);
    glDeleteProgram(prog);
    int rounded = 0;
    int same = frames_compare(fg, fm, w, h, &rounded);
    t->identical += same == 2;
    char label[256];
    case_label(label, sizeof label, j, c, gc.u16 ? " u16" : "");
    parity p = compare(&j->s, c, j->rays, fm, j->depth_far, w, h, 0, label);
    int ok = same && parity_ok(&p, c.method);
    char how[64];
    if (same == 2) snprintf(how, sizeof how, "bit-identical");
    else if (same == 1) snprintf(how, sizeof how, "same hits (%d px rounded)", rounded);
    else snprintf(how, sizeof how, "DIFFER");
    printf("generated %-44s %4zu lines (general %4zu): frames %s; vs cpu %d differ, "
           "shadows %d/%d differ  %s\n",
           label, lines_min, lines_gen, how, p.differ, p.shadow_differ, p.shadow_checked,
           ok ? "ok" : "FAILED");
    if (ok) t->passed++; else t->failed++;
}

/* Every case on one map (relaxed cones too when the job has their map), then the
 * safety and cylinder-cone cases on the compact maps of each of SUBSETS (scenes of
 * those ray classes; safety in the layout their bake plan picks: isotropic for one
 * class), with the general and the generated shader (generated_case). */
static void generated_map(map_job *j, int w, int h, void *ctx) {
    tally *t = (tally *)ctx;
    frame fg, fm;
    frame_alloc(&fg, w, h);
    frame_alloc(&fm, w, h);
    gen_case cases[32];
    int ncases = generated_cases(cases);
    if (j->relaxed) {
        cases[ncases].cfg = cfg_of(HF_METHOD_RELAXED, HF_SURFACE_TRIANGLES);
        cases[ncases++].u16 = 0;
    }
    for (int k = 0; k < ncases; k++) generated_case(j, w, h, cases[k], &fg, &fm, t);
    for (size_t m = 0; m < NUM_SUBSETS; m++) {
        map_set ms = {SUBSETS[m], 0, 0.0f, 0};
        use_maps(j, w, h, ms);
        gen_case gc = {cfg_of(HF_METHOD_SAFETY, HF_SURFACE_TRIANGLES), 0};
        hf_scene sc = scene_of_cfg(gc.cfg, 0, SUBSETS[m]);
        hf_bake_plan plan;
        if (hf_scene_bake_plan(&sc, &plan) != HF_OK) {
            fprintf(stderr, "hf_scene_bake_plan failed\n");
            exit(2);
        }
        gc.cfg.variant = plan.safety_variant;
        generated_case(j, w, h, gc, &fg, &fm, t);
        gc.cfg = cfg_of(HF_METHOD_CC, HF_SURFACE_TRIANGLES);
        generated_case(j, w, h, gc, &fg, &fm, t);
    }
    frame_free(&fg);
    frame_free(&fm);
}

static int run_generated(int nmaps, char **maps) {
    if (tests_start() != 0) return 2;
    tally t = {0, 0, 0, NULL};
    int loaded =
        for_each_map(TEST_W, TEST_H, nmaps, maps, 1, ": cannot read it", generated_map, &t);
    if (tests_stop(loaded) != 0) return 2;
    printf("generated shaders bit-identical to the general shader: %d of %d\n", t.identical,
           t.passed + t.failed);
    return tests_result("osmesa-generated", &t);
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* What the generated-shader benchmark times: frames per case, and room for their
 * times with the general (`tg`) and the generated (`tm`) shader. */
typedef struct gen_bench {
    int frames;
    double *tg, *tm;
} gen_bench;

/* The median frame times of the general and the generated shader of a few
 * configurations on one map, frames alternating between the two so that both see the
 * same machine load. */
static void bench_generated_map(map_job *j, int w, int h, void *ctx) {
    (void)w;
    (void)h;
    gen_bench *b = (gen_bench *)ctx;
    static const uint32_t cases[][2] = {
        {HF_METHOD_EXACT, HF_SURFACE_TRIANGLES},         {HF_METHOD_EXACT, HF_SURFACE_BILINEAR},
        {HF_METHOD_LINEAR_BINARY, HF_SURFACE_TRIANGLES}, {HF_METHOD_MAXMIP, HF_SURFACE_TRIANGLES},
        {HF_METHOD_SAFETY, HF_SURFACE_TRIANGLES},        {HF_METHOD_CONE, HF_SURFACE_TRIANGLES},
        {HF_METHOD_CC, HF_SURFACE_TRIANGLES},           {HF_METHOD_RADIUS, HF_SURFACE_TRIANGLES},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        method_cfg c = cfg_of(cases[k][0], cases[k][1]);
        size_t lines_min, lines_gen;
        GLuint prog = generated_program(c, 0, j->s.classes, &lines_min, &lines_gen);
        /* Warm-up: llvmpipe compiles on first use. */
        render_ms(j, c, 0, 0);
        render_ms(j, c, prog, 0);
        for (int i = 0; i < b->frames; i++) {
            b->tg[i] = render_ms(j, c, 0, 0);
            b->tm[i] = render_ms(j, c, prog, 0);
        }
        glDeleteProgram(prog);
        double mg = median(b->tg, b->frames), mm = median(b->tm, b->frames);
        char mname[64];
        cfg_name(mname, sizeof mname, c);
        printf("%-30s %-22s %7zu %7zu %10.1f %10.1f %7.3f\n", j->s.name, mname, lines_min,
               lines_gen, mg, mm, mm / mg);
    }
}

static int run_bench_generated(int w, int h, int frames, int nmaps, char **maps) {
    if (gl_start(w, h) != 0) return 2;
    if (frames < 1) frames = 1;
    printf("median frame time of %d, %d x %d, primary + shadow ray per pixel, %s (software)\n",
           frames, w, h, (const char *)glGetString(GL_RENDERER));
    printf("%-30s %-22s %7s %7s %10s %10s %7s\n", "map", "method", "lines", "(gen.)",
           "general ms", "minimal ms", "ratio");
    gen_bench b = {frames, (double *)malloc(sizeof(double) * (size_t)frames),
                   (double *)malloc(sizeof(double) * (size_t)frames)};
    int loaded = for_each_map(w, h, nmaps, maps, 0, "", bench_generated_map, &b);
    free(b.tg);
    free(b.tm);
    if (loaded < 0) return 2;
    printf("(lines: generated minimal shader, then the general one, renderer main included; "
           "ratio = minimal / general)\n");
    gl_stop();
    return 0;
}

/* ---- shader dump --------------------------------------------------------------------- */

static int dump_shaders(const char *outdir) {
    char path[512];
    snprintf(path, sizeof path, "%s/fullscreen.vert", outdir);
    FILE *fp = fopen(path, "w");
    if (!fp) return 2;
    fputs(VERTEX_SOURCE, fp);
    fclose(fp);
    for (uint32_t m = 0; m < NUM_METHODS; m++) {
        char *src = fragment_source(m);
        snprintf(path, sizeof path, "%s/%s.frag", outdir, method_name(m));
        fp = fopen(path, "w");
        if (!fp) return 2;
        fputs(src, fp);
        fclose(fp);
        free(src);
        printf("wrote %s\n", path);
    }
    return 0;
}

/* ---- GPU bakes ---------------------------------------------------------------------- */

/* The first float where `got` and `want` differ (their bits), or -1. */
static long first_difference(const float *got, const float *want, size_t n) {
    for (size_t k = 0; k < n; k++)
        if (memcmp(&got[k], &want[k], sizeof(float)) != 0) return (long)k;
    return -1;
}

/* Prints a bake's line and counts it: `at` is first_difference's answer. */
static void bake_result(tally *t, const char *name, const char *what, size_t n, double cpu_ms,
                        double gpu_ms, long at, const float *got, const float *want) {
    printf("gpu-bake %-36s %-30s %10zu floats: cpu %8.2f ms, gpu (software) %8.2f ms  ", name,
           what, n, cpu_ms, gpu_ms);
    if (at < 0) {
        printf("identical\n");
        t->passed++;
    } else {
        printf("FAILED at float %ld: gpu %.9g, cpu %.9g\n", at, got[at], want[at]);
        t->failed++;
    }
}

/* The N-buffers of `s` for `cap` on the CPU: the last hf_nbuffer_len floats of
 * hf_bake_prepare's scratch for HF_METHOD_CC, into `out`; its time in *ms. */
static int cpu_nbuffers(const scene *s, uint32_t cap, float *out, size_t len, double *ms) {
    hf_bake_options o;
    size_t scratch_len = 0;
    if (hf_bake_options_default(HF_METHOD_CC, &o) != HF_OK) return -1;
    o.cap = cap;
    if (hf_bake_scratch_len(HF_METHOD_CC, s->w, s->h, &o, &scratch_len) != HF_OK) return -1;
    float *scratch = (float *)malloc(sizeof(float) * scratch_len);
    double t0 = now_seconds();
    hf_result r = hf_bake_prepare(HF_METHOD_CC, s->field, &o, scratch, scratch_len);
    *ms = 1e3 * (now_seconds() - t0);
    if (r == HF_OK) memcpy(out, scratch + scratch_len - len, sizeof(float) * len);
    free(scratch);
    return r == HF_OK ? 0 : -1;
}

/* Edits the samples `rect` of `s` (a bumpy change of every sample: a quarter of 0 to
 * 4 grid units up) on the CPU side (heights, field, pyramid refreshed by
 * hf_maxmip_update_rect, timed in *ms) and in the texture `tex`. */
static hf_result edit_rect(scene *s, GLuint tex, const uint32_t rect[4], double *ms) {
    uint32_t rw = rect[2] - rect[0], rh = rect[3] - rect[1];
    float *v = (float *)malloc(sizeof(float) * rw * rh);
    for (uint32_t j = 0; j < rh; j++)
        for (uint32_t i = 0; i < rw; i++) {
            float *h = &s->heights[(size_t)(rect[1] + j) * s->w + rect[0] + i];
            *h += 0.25f * (float)((i * 7 + j * 3) % 5);
            v[j * rw + i] = *h;
        }
    double t0 = now_seconds();
    hf_result rc = hf_field_update_rect(s->field, rect[0], rect[1], rect[2], rect[3], v,
                                        (size_t)rw * rh, rw);
    if (rc == HF_OK)
        rc = hf_maxmip_update_rect(s->field, rect[0], rect[1], rect[2], rect[3], s->pyramid,
                                   s->pyramid_len);
    *ms = 1e3 * (now_seconds() - t0);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, (GLint)rect[0], (GLint)rect[1], (GLsizei)rw, (GLsizei)rh,
                    GL_RED, GL_FLOAT, v);
    free(v);
    return rc;
}

/* The GPU bakes of one map against the CPU's: the pyramid whole, then refreshed after
 * edits of about 1 %, 10 % and 100 % of the samples; the N-buffers for the cone
 * reaches 6 and 255; the safety distances, directional and isotropic; the
 * cylinder-cones with N-buffer slopes. */
static void gpu_bake_map(const char *path, tally *t) {
    scene s;
    if (scene_load_heights(&s, path) != 0) {
        printf("skip %s\n", path);
        return;
    }
    gpu_bakes b;
    if (gpu_bakes_init(&b, s.w, s.h) != 0) {
        t->failed++;
        scene_free(&s);
        return;
    }
    GLuint tex = make_texture(GL_R32F, (int)s.w, (int)s.h, GL_RED, GL_FLOAT, s.heights);
    float *got = (float *)malloc(sizeof(float) * b.pyramid_len);
    /* The CPU's whole bake, timed on one thread (scene_load_heights baked it on all). */
    hf_bake_options o;
    hf_bake_options_default(HF_METHOD_MAXMIP, &o);
    o.threads = 1;
    double t0 = now_seconds();
    hf_result rc = hf_bake(HF_METHOD_MAXMIP, s.field, &o, s.pyramid, s.pyramid_len);
    double cpu_ms = 1e3 * (now_seconds() - t0);
    t0 = now_seconds();
    long texels = rc == HF_OK ? gpu_pyramid_bake(&b, s.w, s.h, tex, NULL, 0) : -1;
    glFinish();
    double gpu_ms = 1e3 * (now_seconds() - t0);
    gpu_pyramid_read(&b, got);
    bake_result(t, s.name, "maximum mipmap", b.pyramid_len, cpu_ms, gpu_ms,
                texels < 0 ? 0 : first_difference(got, s.pyramid, b.pyramid_len), got, s.pyramid);
    uint32_t side = s.w < s.h ? s.w : s.h;
    const uint32_t radii[3] = {side / 20, side / 6, s.w + s.h};
    for (int e = 0; e < 3; e++) {
        uint32_t r = radii[e], cx = (uint32_t)(e + 1) * s.w / 4, cy = s.h / 2;
        uint32_t rect[4] = {cx > r ? cx - r : 0, cy > r ? cy - r : 0, cx + r + 1, cy + r + 1};
        if (rect[2] > s.w) rect[2] = s.w;
        if (rect[3] > s.h) rect[3] = s.h;
        rc = edit_rect(&s, tex, rect, &cpu_ms);
        t0 = now_seconds();
        texels = gpu_pyramid_bake(&b, s.w, s.h, tex, rect, 0);
        glFinish();
        gpu_ms = 1e3 * (now_seconds() - t0);
        gpu_pyramid_read(&b, got);
        char what[64];
        double share = 100.0 * (rect[2] - rect[0]) * (rect[3] - rect[1]) / ((double)s.w * s.h);
        snprintf(what, sizeof what, "update %.1f %% (%ld texels)", share, texels);
        long at = rc != HF_OK || texels < 0 ? 0 : first_difference(got, s.pyramid, b.pyramid_len);
        bake_result(t, s.name, what, b.pyramid_len, cpu_ms, gpu_ms, at, got, s.pyramid);
    }
    free(got);
    for (int c = 0; c < 2; c++) {
        uint32_t cap = c == 0 ? 6 : 255;
        size_t len = 0;
        if (hf_nbuffer_len(s.w, s.h, cap, &len) != HF_OK) {
            t->failed++;
            continue;
        }
        float *want = (float *)malloc(sizeof(float) * len);
        float *gpu_nb = (float *)malloc(sizeof(float) * len);
        int ok = cpu_nbuffers(&s, cap, want, len, &cpu_ms) == 0;
        t0 = now_seconds();
        ok = ok && gpu_nbuffer_bake(&b, s.w, s.h, tex, cap, gpu_nb, len) == 0;
        gpu_ms = 1e3 * (now_seconds() - t0);
        char what[64];
        snprintf(what, sizeof what, "n-buffers, cap %u", cap);
        bake_result(t, s.name, what, len, cpu_ms, gpu_ms,
                    ok ? first_difference(gpu_nb, want, len) : 0, gpu_nb, want);
        free(want);
        free(gpu_nb);
    }
    /* The safety distances for every ray, directional and isotropic (positive), and the
     * cylinder-cones with N-buffer slopes (reaches 6 and 64), in doubles: against
     * hf_bake's texels. */
    for (int v = 0; v < 4; v++) {
        uint32_t method = v < 2 ? HF_METHOD_SAFETY : HF_METHOD_CC;
        hf_bake_options so;
        hf_bake_options_default(method, &so);
        so.threads = 1;
        if (v < 2) {
            so.variant = v == 0 ? HF_SAFETY_DIRECTIONAL : HF_SAFETY_ISOTROPIC;
            so.positive = (uint32_t)v;
        } else {
            so.slope = HF_CC_SLOPE_NBUFFER;
            so.cap = v == 2 ? 6 : 64;
        }
        size_t map_len = 0;
        hf_map_len(method, s.w, s.h, &so, &map_len);
        unsigned char *want = (unsigned char *)malloc(map_len);
        size_t texels = map_len - HF_MAP_DESC_BYTES;
        unsigned char *gpu_map = (unsigned char *)malloc(texels);
        t0 = now_seconds();
        int ok = hf_bake(method, s.field, &so, want, map_len) == HF_OK;
        cpu_ms = 1e3 * (now_seconds() - t0);
        t0 = now_seconds();
        int rc = !ok ? -1
                 : v < 2 ? gpu_safety_bake(&b, s.w, s.h, tex, &so, gpu_map, texels)
                         : gpu_cc_bake(&b, s.w, s.h, tex, &so, gpu_map, texels);
        gpu_ms = 1e3 * (now_seconds() - t0);
        char what[64];
        const char *names[4] = {"safety, directional", "safety, isotropic positive",
                                "cc n-buffer slope", "cc n-buffer slope"};
        snprintf(what, sizeof what, "%s%s", names[v], v == 2 ? ", cap 6" : v == 3 ? ", cap 64" : "");
        if (rc == 1) {
            printf("gpu-bake %-36s %-30s skipped: its N-buffers exceed one storage block here\n",
                   s.name, what);
        } else {
            long at = -1;
            for (size_t k = 0; rc == 0 && at < 0 && k < texels; k++)
                if (gpu_map[k] != want[k]) at = (long)k;
            printf("gpu-bake %-36s %-30s %10zu bytes:  cpu %8.2f ms, gpu (software) %8.2f ms  ",
                   s.name, what, texels, cpu_ms, gpu_ms);
            if (rc == 0 && at < 0) {
                printf("identical\n");
                t->passed++;
            } else {
                if (at >= 0)
                    printf("FAILED at byte %ld: gpu %u, cpu %u\n", at, gpu_map[at], want[at]);
                else
                    printf("FAILED (the bake did not run)\n");
                t->failed++;
            }
        }
        free(want);
        free(gpu_map);
    }
    glDeleteTextures(1, &tex);
    gpu_bakes_free(&b);
    scene_free(&s);
}

static int run_gpu_bake(int nmaps, char **maps) {
    if (tests_start() != 0) return 2;
    tally t = {0, 0, 0, NULL};
    for (int m = 0; m < nmaps; m++) gpu_bake_map(maps[m], &t);
    gl_stop();
    return t.passed == 0 ? 2 : tests_result("gpu-bake", &t);
}

/* ---- dynamic terrain ------------------------------------------------------------------ */

typedef struct dynamic_ctx {
    int frames;
    tally t;
} dynamic_ctx;

/* `frames` frames of the dynamic scene on one map: each edits the heights (a mound
 * moving along a circle), refreshes the GPU pyramid for the edit only, renders the
 * maximum-mipmap march, and compares every pixel with the CPU's answer on the CPU's
 * own refreshed pyramid. */
static void dynamic_map(map_job *j, int w, int h, void *ctx) {
    dynamic_ctx *d = (dynamic_ctx *)ctx;
    gpu_bakes b;
    if (gpu_bakes_init(&b, j->s.w, j->s.h) != 0) {
        d->t.failed++;
        return;
    }
    /* The pyramid the renderer reads comes from the GPU bake from the first frame on. */
    if (gpu_pyramid_bake(&b, j->s.w, j->s.h, j->g.tex_heights, NULL, j->g.tex_pyramid) < 0)
        d->t.failed++;
    method_cfg c = cfg_of(HF_METHOD_MAXMIP, HF_SURFACE_TRIANGLES);
    frame f;
    frame_alloc(&f, w, h);
    double cpu_total = 0, gpu_total = 0;
    int worst = 0;
    for (int k = 0; k < d->frames; k++) {
        uint32_t rect[4];
        double cpu_ms = 0;
        if (dynamic_edit(&j->s, j->g.tex_heights, k, rect, &cpu_ms) != 0) {
            d->t.failed++;
            break;
        }
        double t0 = now_seconds();
        long texels =
            gpu_pyramid_bake(&b, j->s.w, j->s.h, j->g.tex_heights, rect, j->g.tex_pyramid);
        glFinish();
        double gpu_ms = 1e3 * (now_seconds() - t0);
        double ms = render_ms(j, c, 0, 0);
        gpu_read(&j->g, &f);
        char label[160];
        snprintf(label, sizeof label, "%s frame %d", j->s.name, k);
        parity p = compare(&j->s, c, j->rays, &f, j->depth_far, w, h, 0, label);
        int ok = texels >= 0 && parity_ok(&p, c.method);
        printf("dynamic %-40s edit %ux%u: cpu update %.2f ms, gpu update (software) %.2f ms "
               "(%ld texels), render %.0f ms; %d pixels, %d differ; shadows %d/%d differ  %s\n",
               label, rect[2] - rect[0], rect[3] - rect[1], cpu_ms, gpu_ms, texels, ms, p.pixels,
               p.differ, p.shadow_differ, p.shadow_checked, ok ? "ok" : "FAILED");
        if (!ok) compare(&j->s, c, j->rays, &f, j->depth_far, w, h, 1, label);
        if (p.differ > worst) worst = p.differ;
        cpu_total += cpu_ms;
        gpu_total += gpu_ms;
        if (ok)
            d->t.passed++;
        else
            d->t.failed++;
    }
    /* After all frames, the GPU's pyramid is the CPU's, byte for byte. */
    float *got = (float *)malloc(sizeof(float) * b.pyramid_len);
    gpu_pyramid_read(&b, got);
    long at = first_difference(got, j->s.pyramid, b.pyramid_len);
    printf("dynamic %-40s %d frames: pyramid after them %s; mean update cpu %.2f ms, gpu "
           "(software) %.2f ms; most pixels differing in a frame %d\n",
           j->s.name, d->frames, at < 0 ? "identical" : "DIFFERS", cpu_total / d->frames,
           gpu_total / d->frames, worst);
    if (at < 0)
        d->t.passed++;
    else
        d->t.failed++;
    free(got);
    frame_free(&f);
    gpu_bakes_free(&b);
}

static int run_dynamic(int frames, int nmaps, char **maps) {
    if (frames < 1 || tests_start() != 0) return 2;
    dynamic_ctx d = {frames, {0, 0, 0, NULL}};
    int loaded = for_each_map(TEST_W, TEST_H, nmaps, maps, 0, "", dynamic_map, &d);
    int stop = tests_stop(loaded);
    return stop ? stop : tests_result("dynamic", &d.t);
}

/* ---- camera roll (Qu et al.): rolled rays against the unrolled view texture-mapped ---- */

/* The default camera at rolls 0, 10, 30, 45 and 90 degrees on one map (maximum mipmap,
 * triangles): the rolled rays' frame against the CPU, and the mapped frame against it
 * (roll_ok says what must hold). */
static void roll_map(map_job *j, int w, int h, void *ctx) {
    tally *t = (tally *)ctx;
    roll_view r;
    if (roll_init(&r, &j->s, &j->g) != 0) {
        t->failed++;
        return;
    }
    method_cfg c = cfg_of(HF_METHOD_MAXMIP, HF_SURFACE_TRIANGLES);
    frame direct, mapped;
    frame_alloc(&direct, w, h);
    frame_alloc(&mapped, w, h);
    camera cam = default_camera();
    const int degrees[5] = {0, 10, 30, 45, 90};
    for (int k = 0; k < 5; k++) {
        cam.roll = (float)degrees[k] * 3.14159265f / 180.0f;
        roll_result res = roll_measure(&r, &j->g, &j->s, c, &cam, 3, &direct, &mapped);
        make_rays(&j->s, &cam, w, h, j->rays);
        char label[160];
        snprintf(label, sizeof label, "%s roll %d", j->s.name, degrees[k]);
        parity p = compare(&j->s, c, j->rays, &direct, j->depth_far, w, h, 0, label);
        int ok = parity_ok(&p, c.method) && roll_ok(&res, degrees[k]);
        printf("roll %-36s rolled rays: %d pixels, %d differ from the cpu, %.1f ms; unrolled %d "
               "pixels + mapping: %.1f ms, %d hit/miss differ, %d colours differ by > 8/255, "
               "mean colour error %.2f/255 (unturned: %d hit/miss differ)  %s\n",
               label, res.pixels, p.differ, res.direct_ms, res.unrolled_pixels, res.mapped_ms,
               res.hit_differ, res.color_differ, res.color_mean, res.unturned, ok ? "ok" : "FAILED");
        tally_add(t, ok);
    }
    frame_free(&direct);
    frame_free(&mapped);
    roll_free(&r);
}


/* ---- Qu et al.'s hybrid rasterization renderer ------------------------------------ */

/* Median of three. */
static double mid3(double a, double b, double c) {
    return a > b ? (b > c ? b : (a > c ? c : a)) : (a > c ? a : (b > c ? c : b));
}

/* The hybrid renderer on one map (the default camera, the view-linear surface): its
 * frame against the CPU ray cast of the view-linear surface (hf_trace: at least 99.99 %
 * of the pixels agree, hit or miss and the point within 1e-3) and against the same two
 * passes on the CPU; its passes' times and fragments against the ray-cast shaders'
 * frames on the same surface (software GPU). */
static void hybrid_map(map_job *j, int w, int h, void *ctx) {
    tally *t = (tally *)ctx;
    hybrid hy;
    if (hybrid_init(&hy, &j->s, &j->g) != 0) {
        fprintf(stderr, "hybrid_init failed\n");
        t->failed++;
        return;
    }
    camera cam = default_camera();
    hybrid_render(&hy, &j->g, &j->s, &cam); /* warm-up: shader compile */
    hybrid_stats runs[3];
    for (int k = 0; k < 3; k++) runs[k] = hybrid_render(&hy, &j->g, &j->s, &cam);
    frame f;
    frame_alloc(&f, w, h);
    gpu_read(&j->g, &f);
    size_t n = (size_t)w * h;
    hybrid_check c = hybrid_compare(&j->s, j->rays, &f, n);
    method_cfg vl = cfg_of(HF_METHOD_EXACT, HF_SURFACE_VIEW_LINEAR);
    method_cfg mm = cfg_of(HF_METHOD_MAXMIP, HF_SURFACE_VIEW_LINEAR);
    double rc[3], mx[3];
    render_ms(j, vl, 0, 0);
    render_ms(j, mm, 0, 0);
    for (int k = 0; k < 3; k++) {
        rc[k] = render_ms(j, vl, 0, 0);
        mx[k] = render_ms(j, mm, 0, 0);
    }
    double raycast = mid3(rc[0], rc[1], rc[2]), maxmip = mid3(mx[0], mx[1], mx[2]);
    double p1 = mid3(runs[0].pass1_ms, runs[1].pass1_ms, runs[2].pass1_ms);
    double p2 = mid3(runs[0].pass2_ms, runs[1].pass2_ms, runs[2].pass2_ms);
    int ok = hybrid_ok(&c, n);
    printf("hybrid %-36s %zu pixels, %d cpu hits: %d differ from the cpu ray cast of the "
           "view-linear surface (%d hit/miss), max err %.2e; %d differ from the same passes "
           "on the cpu (%.0f ms); pass 1 %u fragments (%.1f per pixel), %u on or under, %.1f "
           "ms; pass 2 %zu fragments, %.1f ms; frame %.1f ms against the ray-cast shader's "
           "%.1f ms (exact) and %.1f ms (maxmip), software  %s\n",
           j->s.name, n, c.hits, c.differ, c.hit_differ, c.max_err, c.same_differ, c.cpu_ms,
           runs[2].fragments, (double)runs[2].fragments / (double)n, runs[2].kept, p1, n, p2,
           p1 + p2, raycast, maxmip, ok ? "ok" : "FAILED");
    tally_add(t, ok);
    frame_free(&f);
    hybrid_free(&hy);
}

/* Runs `fn` (its context a tally) on every map of `maps` with the test renderer; the
 * last line says "`name`: N passed, M failed". */
static int run_tallied(const char *name, map_fn fn, int nmaps, char **maps) {
    if (tests_start() != 0) return 2;
    tally t = {0, 0, 0, NULL};
    int loaded = for_each_map(TEST_W, TEST_H, nmaps, maps, 0, "", fn, &t);
    int stop = tests_stop(loaded);
    return stop ? stop : tests_result(name, &t);
}

/* ---- six-field impostors (impostor.h) ---------------------------------------------- */

/* The views of the impostor runs: compass azimuth and elevation, degrees. */
static const double IMP_VIEWS[3][2] = {{30, 25}, {200, -20}, {110, 65}};
#define IMP_DIST 3.2 /* half sides from the centre */
#define IMP_FOV 40.0

/* The frame of the ground truth, the mesh rasterized from `v`, into `mesh_info`. */
static void imp_mesh_frame(imp_gl *g, const imp_view *v, float *point, float *mesh_info) {
    imp_gl_draw_mesh(g, v, 1);
    imp_gl_read(g, point, mesh_info);
}

/* One capture on the test's views: each combination's frame against the CPU
 * (imp_check_ok), the unclipped frusta's frame identical to the clipped one's with
 * more fragments; adds each view's error against the mesh to err[combine]. */
static void imp_capture_case(imp_gl *g, const imp_mesh *m, const char *name, uint32_t frustum,
                             uint32_t side, tally *t, imp_error err[2]) {
    imp_fields f;
    if (imp_fields_capture(&f, m, frustum, side) != 0) {
        t->failed++;
        return;
    }
    imp_gl_set_fields(g, &f);
    size_t n = (size_t)g->w * g->h;
    hf_ray *rays = (hf_ray *)malloc(n * sizeof *rays);
    float *pt = (float *)malloc(n * 16), *info = (float *)malloc(n * 16);
    float *pt2 = (float *)malloc(n * 16), *info2 = (float *)malloc(n * 16);
    float *mesh = (float *)malloc(n * 16);
    const char *fname = frustum == HF_IMPOSTOR_ORTHOGRAPHIC ? "orthographic" : "reverse";
    for (int v = 0; v < 3; v++) {
        imp_view view = imp_orbit(&f.layout, IMP_VIEWS[v][0], IMP_VIEWS[v][1], IMP_DIST,
                                  IMP_FOV, g->w, g->h);
        imp_rays(&view, g->w, g->h, rays);
        imp_gl_set_rays(g, rays);
        imp_mesh_frame(g, &view, pt2, mesh);
        for (uint32_t c = 0; c < 2; c++) {
            imp_stats clipped = imp_gl_draw(g, &f, &view, c, 0, 1, 1);
            imp_gl_read(g, pt, info);
            imp_check k = imp_check_cpu(&f, c, rays, n, pt, info);
            imp_stats unclipped = imp_gl_draw(g, &f, &view, c, 0, 0, 1);
            imp_gl_read(g, pt2, info2);
            int same = memcmp(pt, pt2, n * 16) == 0;
            imp_error e = imp_against_mesh(info, mesh, n, f.layout.half);
            err[c].mesh_pixels += e.mesh_pixels;
            err[c].differ += e.differ;
            err[c].depth_mean += e.depth_mean / 3.0;
            int ok = imp_check_ok(&k) && same && unclipped.fragments > clipped.fragments;
            printf("impostor %-10s %-12s %ux%u view %d %-12s %d pixels, %d cpu hits, %d differ "
                   "(%d hit/miss, %d on another face), max err %.1e half sides; unclipped "
                   "frame %s, fragments %u clipped vs %u unclipped; %d of %d mesh pixels "
                   "covered differently  %s\n",
                   name, fname, side, side, v, c ? "facing-field" : "intersection", k.pixels,
                   k.hits, k.differ, k.hit_differ, k.face_differ, k.max_err,
                   same ? "identical" : "DIFFERS", clipped.fragments, unclipped.fragments,
                   e.differ, e.mesh_pixels, ok ? "ok" : "FAILED");
            tally_add(t, ok);
        }
    }
    free(rays);
    free(pt);
    free(info);
    free(pt2);
    free(info2);
    free(mesh);
    imp_fields_free(&f);
}

/* The depth output (§4.4): a plane through the object, drawn first, then the
 * impostor; pixels where the plane and the object are in the other order than in the
 * ground truth (plane and mesh rasterized). With exact depth far fewer. */
static void imp_depth_case(imp_gl *g, const imp_mesh *m, const char *name, tally *t) {
    imp_fields f;
    if (imp_fields_capture(&f, m, HF_IMPOSTOR_REVERSE_PERSPECTIVE, 128) != 0) {
        t->failed++;
        return;
    }
    imp_gl_set_fields(g, &f);
    size_t n = (size_t)g->w * g->h;
    hf_ray *rays = (hf_ray *)malloc(n * sizeof *rays);
    float *pt = (float *)malloc(n * 16), *truth = (float *)malloc(n * 16);
    float *info = (float *)malloc(n * 16);
    imp_view view = imp_orbit(&f.layout, IMP_VIEWS[0][0], IMP_VIEWS[0][1], IMP_DIST, IMP_FOV,
                              g->w, g->h);
    imp_rays(&view, g->w, g->h, rays);
    imp_gl_set_rays(g, rays);
    double z = f.layout.center[2];
    imp_gl_draw_mesh(g, &view, 1);
    imp_gl_draw_plane(g, &view, m, z);
    imp_gl_read(g, pt, truth);
    int wrong[2];
    for (int depth = 0; depth < 2; depth++) {
        imp_gl_draw(g, &f, &view, HF_IMPOSTOR_INTERSECTION, depth, 1, 1);
        imp_gl_draw_plane(g, &view, m, z);
        imp_gl_read(g, pt, info);
        wrong[depth] = 0;
        for (size_t i = 0; i < n; i++)
            if (info[4 * i + 3] != truth[4 * i + 3]) wrong[depth]++;
    }
    int ok = wrong[1] * 4 < wrong[0];
    printf("impostor %-10s depth output: a plane through the object, %d pixels in the wrong "
           "order with the proxy's depth, %d with the hit's  %s\n",
           name, wrong[0], wrong[1], ok ? "ok" : "FAILED");
    tally_add(t, ok);
    free(rays);
    free(pt);
    free(truth);
    free(info);
    imp_fields_free(&f);
}

/* `impostor MESH.obj...`: the impostor tests (the cases above) on each mesh at side
 * 64, and, with one field per ray, the reverse perspective covering the mesh's
 * silhouette better than the orthographic fields. */
static int run_impostor_test(int nmeshes, char **meshes) {
    if (tests_start() != 0) return 2;
    imp_gl g;
    if (imp_gl_init(&g, TEST_W, TEST_H) != 0) return 2;
    tally t = {0, 0, 0, NULL};
    for (int k = 0; k < nmeshes; k++) {
        imp_mesh m;
        if (imp_mesh_load_obj(&m, meshes[k]) != 0) {
            t.failed++;
            continue;
        }
        const char *name = strrchr(meshes[k], '/') ? strrchr(meshes[k], '/') + 1 : meshes[k];
        imp_gl_set_mesh(&g, &m);
        imp_error err[2][2];
        memset(err, 0, sizeof err);
        imp_capture_case(&g, &m, name, HF_IMPOSTOR_ORTHOGRAPHIC, 64, &t, err[0]);
        imp_capture_case(&g, &m, name, HF_IMPOSTOR_REVERSE_PERSPECTIVE, 64, &t, err[1]);
        int ok = err[1][1].differ < err[0][1].differ;
        printf("impostor %-10s one field per ray: %d silhouette pixels wrong (reverse "
               "perspective) against %d (orthographic), of %d  %s\n",
               name, err[1][1].differ, err[0][1].differ, err[0][1].mesh_pixels,
               ok ? "ok" : "FAILED");
        tally_add(&t, ok);
        imp_depth_case(&g, &m, name, &t);
        imp_mesh_free(&m);
    }
    imp_gl_free(&g);
    gl_stop();
    return tests_result("impostor", &t);
}

/* `impostor-report W H MESH.obj...`: docs/report/impostors.md's tables (scripts/
 * impostors.sh) as Markdown rows, per mesh, frustum, side (32 to 512) and
 * combination, over the three views: silhouette pixels wrong (of the mesh's),
 * mean forward-distance error (half sides), the median frame time of the clipped
 * proxy and of the unclipped frusta (3 frames each after a warm-up) with their
 * fragments, and the capture time. */
static int run_impostor_report(int w, int h, int nmeshes, char **meshes) {
    if (gl_start(w, h) != 0) return 2;
    imp_gl g;
    if (imp_gl_init(&g, w, h) != 0) return 2;
    printf("Renderer: %s (software). %d × %d pixels, 3 views, the exact traversal on "
           "every field.\n\n",
           (const char *)glGetString(GL_RENDERER), w, h);
    printf("| mesh | frustum | side | combination | silhouette px wrong | depth error "
           "(half sides) | clipped ms | clipped fragments | unclipped ms | unclipped "
           "fragments | mesh ms | capture ms |\n"
           "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    size_t n = (size_t)w * h;
    hf_ray *rays = (hf_ray *)malloc(n * sizeof *rays);
    float *pt = (float *)malloc(n * 16), *info = (float *)malloc(n * 16);
    float *mesh_info[3];
    for (int v = 0; v < 3; v++) mesh_info[v] = (float *)malloc(n * 16);
    static const uint32_t sides[5] = {32, 64, 128, 256, 512};
    for (int k = 0; k < nmeshes; k++) {
        imp_mesh m;
        if (imp_mesh_load_obj(&m, meshes[k]) != 0) return 2;
        const char *name = strrchr(meshes[k], '/') ? strrchr(meshes[k], '/') + 1 : meshes[k];
        imp_gl_set_mesh(&g, &m);
        for (uint32_t fr = 0; fr < 2; fr++)
            for (int s = 0; s < 5; s++) {
                imp_fields f;
                if (imp_fields_capture(&f, &m, fr, sides[s]) != 0) return 2;
                imp_gl_set_fields(&g, &f);
                imp_view views[3];
                double mesh_ms[3];
                for (int v = 0; v < 3; v++) {
                    views[v] = imp_orbit(&f.layout, IMP_VIEWS[v][0], IMP_VIEWS[v][1],
                                         IMP_DIST, IMP_FOV, w, h);
                    mesh_ms[v] = imp_gl_draw_mesh(&g, &views[v], 1).ms;
                    imp_gl_read(&g, pt, mesh_info[v]);
                }
                for (uint32_t c = 0; c < 2; c++) {
                    imp_error sum = {0, 0, 0.0, 0.0};
                    double ms[2][9];
                    unsigned frags[2] = {0, 0};
                    for (int v = 0; v < 3; v++) {
                        imp_rays(&views[v], w, h, rays);
                        imp_gl_set_rays(&g, rays);
                        imp_gl_draw(&g, &f, &views[v], c, 0, 1, 1); /* warm-up */
                        for (int clip = 0; clip < 2; clip++)
                            for (int r = 0; r < 3; r++) {
                                imp_stats st = imp_gl_draw(&g, &f, &views[v], c, 0, 1 - clip, 1);
                                ms[clip][3 * v + r] = st.ms;
                                if (r == 0) frags[clip] += st.fragments;
                            }
                        imp_gl_draw(&g, &f, &views[v], c, 0, 1, 1);
                        imp_gl_read(&g, pt, info);
                        imp_error e = imp_against_mesh(info, mesh_info[v], n, f.layout.half);
                        sum.mesh_pixels += e.mesh_pixels;
                        sum.differ += e.differ;
                        sum.depth_mean += e.depth_mean / 3.0;
                    }
                    printf("| %s | %s | %u² | %s | %d of %d (%.2f %%) | %.4f | %.1f | %u | %.1f | "
                           "%u | %.1f | %.1f |\n",
                           name, fr ? "reverse perspective" : "orthographic", sides[s],
                           c ? "facing field" : "intersection", sum.differ, sum.mesh_pixels,
                           100.0 * sum.differ / (sum.mesh_pixels ? sum.mesh_pixels : 1),
                           sum.depth_mean, median(ms[0], 9), frags[0], median(ms[1], 9),
                           frags[1], median(mesh_ms, 3), f.capture_ms);
                    fflush(stdout);
                }
                imp_fields_free(&f);
            }
        imp_mesh_free(&m);
    }
    for (int v = 0; v < 3; v++) free(mesh_info[v]);
    free(rays);
    free(pt);
    free(info);
    imp_gl_free(&g);
    gl_stop();
    return 0;
}

/* ---- Table 1 frame times (scripts/table1.sh) ---------------------------------------- */

/* The settings of Table 1 (tools/src/table1.rs): name, method, exterior rays only. */
typedef struct table1_row {
    const char *name;
    uint32_t method, exterior;
} table1_row;

static const table1_row TABLE1_ROWS[5] = {
    {"exact traversal (DDA)", HF_METHOD_EXACT, 0}, {"cyl_all", HF_METHOD_SAFETY, 0},
    {"cyl_ext", HF_METHOD_SAFETY, 1},             {"cyl_all+cone_all", HF_METHOD_CC, 0},
    {"cyl_ext+cone_ext", HF_METHOD_CC, 1},
};

/* One side of run_table1: the centre crop of `map`, each setting without and with
 * phi_max = -45 degrees (rays within 45 degrees of the vertical), on cameras at 45 and
 * 70 degrees of elevation (vertical field of view 40 degrees): primary rays only, the
 * median of 5 frames after a warm-up. */
static int table1_side(int w, int h, const char *map, uint32_t side) {
    map_job j;
    if (scene_load_crop(&j.s, map, side) != 0) return -1;
    if (gpu_init(&j.g, &j.s, w, h) != 0) return -1;
    j.g.primary_only = 1;
    const float elevations[2] = {45.0f, 70.0f};
    hf_ray *rays[2];
    float far[2];
    size_t n = (size_t)w * h;
    for (int e = 0; e < 2; e++) {
        camera cam = default_camera();
        cam.elevation = elevations[e] * 0.017453292f;
        cam.fov = 40.0f * 0.017453292f;
        rays[e] = (hf_ray *)malloc(sizeof(hf_ray) * n);
        make_rays(&j.s, &cam, w, h, rays[e]);
        far[e] = scene_depth_far(&j.s, &cam);
    }
    for (int r = 0; r < 5; r++) {
        table1_row row = TABLE1_ROWS[r];
        for (int phi = 0; phi < (row.method == HF_METHOD_EXACT ? 1 : 2); phi++) {
            double bake_ms = -1.0;
            if (row.method != HF_METHOD_EXACT) {
                int sd = row.method == HF_METHOD_SAFETY;
                scene_set_maps_of(&j.s, HF_RAYS_ALL, row.exterior, phi ? 45.0f : 0.0f, sd, !sd);
                gpu_upload_class_maps(&j.g, &j.s);
                bake_ms = sd ? j.s.safety_bake_ms : j.s.cc_bake_ms;
            }
            method_cfg c = cfg_of(row.method, HF_SURFACE_TRIANGLES);
            for (int e = 0; e < 2; e++) {
                gpu_upload_rays(&j.g, rays[e]);
                j.depth_far = far[e];
                render_ms(&j, c, 0, 0); /* warm-up: compile, caches */
                double ms[5];
                for (int f = 0; f < 5; f++) ms[f] = render_ms(&j, c, 0, 0);
                size_t in_set = 0;
                for (size_t k = 0; k < n; k++) in_set += ray_in_set(&j.s, &rays[e][k]);
                char bake[32] = "–", set[32] = "–";
                if (bake_ms >= 0.0) {
                    snprintf(bake, sizeof bake, "%.2f", bake_ms / 1e3);
                    snprintf(set, sizeof set, "%.0f %%", 100.0 * (double)in_set / (double)n);
                }
                double med = median(ms, 5);
                printf("| %u × %u | %s | %s | %s | %.0f° | %s | %.1f | %.2f |\n", j.s.w, j.s.h,
                       row.name, phi ? "−45°" : "–", bake, elevations[e], set, med,
                       (double)n / (med * 1e3));
                fflush(stdout);
            }
        }
    }
    for (int e = 0; e < 2; e++) free(rays[e]);
    gpu_free(&j.g);
    scene_free(&j.s);
    return 0;
}

/* `table1 W H MAP SIDE...`: the OSMesa frame times of Table 1's settings on centre
 * crops of MAP (scripts/table1.sh puts them under `hfcast table1`'s CPU table), as a
 * Markdown table: bake seconds (the C API, all cores), the camera's rays in the map's
 * set, the median frame time of W x H primary rays (llvmpipe: software) and its rays
 * per second. */
static int run_table1(int w, int h, const char *map, int nsides, char **sides) {
    if (gl_start(w, h) != 0) return 2;
    printf("OSMesa frame times: %d × %d primary rays (no shadow rays), %s (software), "
           "median of 5 frames after a warm-up; bakes through the C API on all cores.\n\n",
           w, h, (const char *)glGetString(GL_RENDERER));
    printf("| side | setting | φmax | bake s | camera | in set | frame ms | Mrays/s |\n"
           "|---:|---|---|---:|---:|---:|---:|---:|\n");
    int rc = 0;
    for (int k = 0; k < nsides && rc == 0; k++)
        if (table1_side(w, h, map, (uint32_t)atoi(sides[k])) != 0) rc = 2;
    gl_stop();
    return rc;
}

int main(int argc, char **argv) {
    if (argc >= 4 && strcmp(argv[1], "test") == 0) return run_tests(argv[2], argc - 3, argv + 3);
    if (argc >= 6 && strcmp(argv[1], "bench") == 0)
        return run_bench(atoi(argv[2]), atoi(argv[3]), atoi(argv[4]), argc - 5, argv + 5);
    if (argc == 3 && strcmp(argv[1], "shaders") == 0) return dump_shaders(argv[2]);
    if (argc >= 3 && strcmp(argv[1], "gpu-bake") == 0) return run_gpu_bake(argc - 2, argv + 2);
    if (argc >= 4 && strcmp(argv[1], "dynamic") == 0)
        return run_dynamic(atoi(argv[2]), argc - 3, argv + 3);
    if (argc >= 3 && strcmp(argv[1], "generated") == 0) return run_generated(argc - 2, argv + 2);
    if (argc >= 3 && strcmp(argv[1], "roll") == 0)
        return run_tallied("roll", roll_map, argc - 2, argv + 2);
    if (argc >= 3 && strcmp(argv[1], "hybrid") == 0)
        return run_tallied("hybrid", hybrid_map, argc - 2, argv + 2);
    if (argc >= 3 && strcmp(argv[1], "impostor") == 0)
        return run_impostor_test(argc - 2, argv + 2);
    if (argc >= 5 && strcmp(argv[1], "impostor-report") == 0)
        return run_impostor_report(atoi(argv[2]), atoi(argv[3]), argc - 4, argv + 4);
    if (argc >= 6 && strcmp(argv[1], "table1") == 0)
        return run_table1(atoi(argv[2]), atoi(argv[3]), argv[4], argc - 5, argv + 5);
    if (argc >= 6 && strcmp(argv[1], "bench-generated") == 0)
        return run_bench_generated(atoi(argv[2]), atoi(argv[3]), atoi(argv[4]), argc - 5,
                                   argv + 5);
    fprintf(stderr,
            "usage: %s test OUTDIR MAP.png...\n"
            "       %s bench W H FRAMES MAP.png...\n"
            "       %s shaders OUTDIR\n"
            "       %s generated MAP.png...\n"
            "       %s bench-generated W H FRAMES MAP.png...\n"
            "       %s gpu-bake MAP.png...\n"
            "       %s dynamic FRAMES MAP.png...\n"
            "       %s roll MAP.png...\n"
            "       %s hybrid MAP.png...\n"
            "       %s table1 W H MAP.png SIDE...\n"
            "       %s impostor MESH.obj...\n"
            "       %s impostor-report W H MESH.obj...\n",
            argv[0], argv[0], argv[0], argv[0], argv[0], argv[0], argv[0], argv[0], argv[0],
            argv[0], argv[0], argv[0]);
    return 2;
}
