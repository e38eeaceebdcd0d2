/* Offscreen renderer on OSMesa (OpenGL 4.5 core, llvmpipe): the GPU/CPU parity test of
 * the GLSL ports, the reference image of the GLFW test, and a frame-time benchmark.
 *
 *   render_osmesa test OUTDIR MAP.png...        parity of every method, images in OUTDIR
 *   render_osmesa bench W H FRAMES MAP.png...   frame time per method and map (software)
 *   render_osmesa shaders OUTDIR                the composed shaders, for glslangValidator
 */
#define _POSIX_C_SOURCE 200112L
#include "render_common.h"

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

/* ---- parity ----------------------------------------------------------------------- */

typedef struct parity {
    int pixels, hits, differ, differ_hit, differ_pos;
    int shadow_checked, shadow_differ, depth_differ;
    double max_err;
} parity;

static float dist3(const float *a, const float *b) {
    float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrtf(dx * dx + dy * dy + dz * dz);
}

/* Compares the GPU frame with the CPU answers for the same rays; lists every differing
 * pixel when `list` is set. */
static parity compare(const scene *s, method_cfg cfg, const hf_ray *rays, const frame *f,
                      float depth_far, int w, int h, int list, const char *label) {
    size_t n = (size_t)w * h;
    hf_hit *hits = (hf_hit *)malloc(sizeof(hf_hit) * n);
    hf_result r = cpu_trace(s, cfg, rays, n, hits);
    if (r != HF_OK) {
        fprintf(stderr, "cpu_trace failed (%u)\n", (unsigned)r);
        exit(2);
    }
    /* Shadow rays from the CPU's own hits, with the shader's formula. */
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

static int run_tests(const char *outdir, int nmaps, char **maps) {
    if (gl_start(TEST_W, TEST_H) != 0) return 2;
    printf("renderer: %s / %s\n", (const char *)glGetString(GL_RENDERER),
           (const char *)glGetString(GL_VERSION));
    int failed = 0, passed = 0, loaded = 0;
    /* Every map with every method but relaxed cones, whose bake (the book's, Θ(N⁴) pruned)
     * takes minutes on a full map; then relaxed cones on a 64 x 64 crop of the first. */
    for (int m = 0; m <= nmaps; m++) {
        int crop_job = m == nmaps;
        scene s;
        if (scene_load_ex(&s, maps[crop_job ? 0 : m], crop_job ? 64 : 0, crop_job) != 0) {
            printf("skip %s: cannot read it\n", maps[crop_job ? 0 : m]);
            continue;
        }
        loaded++;
        gpu g;
        if (gpu_init(&g, &s, TEST_W, TEST_H) != 0) {
            fprintf(stderr, "gpu_init failed\n");
            return 2;
        }
        camera cam = default_camera();
        float depth_far = scene_depth_far(&s, &cam);
        size_t n = (size_t)TEST_W * TEST_H;
        hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * n);
        make_rays(&s, &cam, TEST_W, TEST_H, rays);
        gpu_upload_rays(&g, rays);
        frame f;
        frame_alloc(&f, TEST_W, TEST_H);
        method_cfg cfgs[24];
        int ncfg = 0;
        for (uint32_t sf = 0; sf <= HF_SURFACE_VIEW_LINEAR; sf++) {
            method_cfg c = {HF_METHOD_EXACT, sf, 0, 0, HF_SAFETY_DIRECTIONAL};
            cfgs[ncfg++] = c;
        }
        for (uint32_t sf = 0; sf <= HF_SURFACE_VIEW_LINEAR; sf++) {
            method_cfg c = {HF_METHOD_MAXMIP, sf, 0, 0, HF_SAFETY_DIRECTIONAL};
            cfgs[ncfg++] = c;
        }
        method_cfg lb = {HF_METHOD_LINEAR_BINARY, HF_SURFACE_TRIANGLES, 64, 8, HF_SAFETY_DIRECTIONAL};
        method_cfg lbb = {HF_METHOD_LINEAR_BINARY, HF_SURFACE_BILINEAR, 64, 8, HF_SAFETY_DIRECTIONAL};
        method_cfg ls = {HF_METHOD_LINEAR_SECANT, HF_SURFACE_TRIANGLES, 64, 0, HF_SAFETY_DIRECTIONAL};
        method_cfg sd = {HF_METHOD_SAFETY, HF_SURFACE_TRIANGLES, 0, 0, HF_SAFETY_DIRECTIONAL};
        cfgs[ncfg++] = lb;
        cfgs[ncfg++] = lbb;
        cfgs[ncfg++] = ls;
        cfgs[ncfg++] = sd;
        sd.variant = HF_SAFETY_ISOTROPIC;
        cfgs[ncfg++] = sd;
        method_cfg cone = {HF_METHOD_CONE, HF_SURFACE_TRIANGLES, 512, 0, HF_SAFETY_DIRECTIONAL};
        method_cfg relaxed = {HF_METHOD_RELAXED, HF_SURFACE_TRIANGLES, 64, 8, HF_SAFETY_DIRECTIONAL};
        method_cfg qdm = {HF_METHOD_QDM, HF_SURFACE_TRIANGLES, 512, 0, HF_SAFETY_DIRECTIONAL};
        method_cfg ccc = {HF_METHOD_CC, HF_SURFACE_TRIANGLES, 0, 0, HF_SAFETY_DIRECTIONAL};
        cfgs[ncfg++] = cone;
        cfgs[ncfg++] = qdm;
        cfgs[ncfg++] = ccc;
        if (crop_job) {
            ncfg = 1; /* exact/triangles (cfgs[0]) for reference, then relaxed */
            cfgs[ncfg++] = relaxed;
        }
        for (int k = 0; k < ncfg; k++) {
            method_cfg c = cfgs[k];
            int exact = c.method == HF_METHOD_EXACT || c.method == HF_METHOD_MAXMIP ||
                        c.method == HF_METHOD_SAFETY || c.method == HF_METHOD_CONE ||
                        c.method == HF_METHOD_QDM || c.method == HF_METHOD_CC;
            double t0 = now_seconds();
            gpu_render(&g, &s, c, depth_far);
            glFinish();
            double t1 = now_seconds();
            gpu_read(&g, &f);
            char label[160];
            snprintf(label, sizeof label, "%s %s%s/%s", s.name, method_name(c.method),
                     c.method == HF_METHOD_SAFETY && c.variant == HF_SAFETY_ISOTROPIC
                         ? "-isotropic"
                         : "",
                     surface_name(c.surface));
            parity p = compare(&s, c, rays, &f, depth_far, TEST_W, TEST_H, 0, label);
            /* Exact methods: at least 99.99 % of pixels within 1e-3 texel; approximate
             * ones run the same algorithm, so they must agree nearly as well (99.9 %). */
            int allowed = exact ? p.pixels / 10000 : p.pixels / 1000;
            int shadow_allowed = p.shadow_checked / 1000;
            int depth_allowed = p.pixels / 10000;
            int ok = p.differ <= allowed && p.shadow_differ <= shadow_allowed &&
                     p.depth_differ <= depth_allowed;
            printf("parity %-40s %d pixels, %d cpu hits, %d differ (%d hit/miss, %d > 1e-3), max "
                   "err %.2e; shadows %d/%d differ; depth %d differ; gpu %.0f ms  %s\n",
                   label, p.pixels, p.hits, p.differ, p.differ_hit, p.differ_pos, p.max_err,
                   p.shadow_differ, p.shadow_checked, p.depth_differ, 1e3 * (t1 - t0),
                   ok ? "ok" : "FAILED");
            if (!ok || p.differ > 0) compare(&s, c, rays, &f, depth_far, TEST_W, TEST_H, 1, label);
            if (ok) passed++; else failed++;
            if (c.surface == HF_SURFACE_TRIANGLES && exact && c.variant == HF_SAFETY_DIRECTIONAL &&
                !crop_job) {
                char path[512];
                snprintf(path, sizeof path, "%s/%s_%s_triangles.png", outdir, s.name,
                         method_name(c.method));
                if (write_png_rgba(path, f.color, TEST_W, TEST_H) != 0) {
                    fprintf(stderr, "cannot write %s\n", path);
                    failed++;
                }
            }
        }
        frame_free(&f);
        free(rays);
        gpu_free(&g);
        scene_free(&s);
    }
    gl_stop();
    if (loaded == 0) {
        fprintf(stderr, "no map could be loaded\n");
        return 2;
    }
    printf("osmesa-parity: %d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}

/* ---- benchmark --------------------------------------------------------------------- */

static int run_bench(int w, int h, int frames, int nmaps, char **maps) {
    if (gl_start(w, h) != 0) return 2;
    printf("frame time, %d x %d, primary + shadow ray per pixel, %s (software)\n", w, h,
           (const char *)glGetString(GL_RENDERER));
    printf("%-36s %-24s %10s %10s %12s\n", "map", "method", "gpu ms", "cpu ms", "fetches/ray");
    for (int m = 0; m < nmaps; m++) {
        scene s;
        if (scene_load(&s, maps[m]) != 0) {
            printf("skip %s\n", maps[m]);
            continue;
        }
        gpu g;
        if (gpu_init(&g, &s, w, h) != 0) return 2;
        camera cam = default_camera();
        float depth_far = scene_depth_far(&s, &cam);
        size_t n = (size_t)w * h;
        hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * n);
        hf_hit *hits = (hf_hit *)malloc(sizeof(hf_hit) * n);
        make_rays(&s, &cam, w, h, rays);
        gpu_upload_rays(&g, rays);
        method_cfg cfgs[NUM_METHODS] = {{HF_METHOD_EXACT, HF_SURFACE_TRIANGLES, 0, 0, HF_SAFETY_DIRECTIONAL},
                                        {HF_METHOD_LINEAR_BINARY, HF_SURFACE_TRIANGLES, 64, 8, HF_SAFETY_DIRECTIONAL},
                                        {HF_METHOD_LINEAR_SECANT, HF_SURFACE_TRIANGLES, 64, 0, HF_SAFETY_DIRECTIONAL},
                                        {HF_METHOD_MAXMIP, HF_SURFACE_TRIANGLES, 0, 0, HF_SAFETY_DIRECTIONAL},
                                        {HF_METHOD_SAFETY, HF_SURFACE_TRIANGLES, 0, 0, HF_SAFETY_DIRECTIONAL},
                                        {HF_METHOD_CONE, HF_SURFACE_TRIANGLES, 512, 0, HF_SAFETY_DIRECTIONAL},
                                        {HF_METHOD_RELAXED, HF_SURFACE_TRIANGLES, 64, 8, HF_SAFETY_DIRECTIONAL},
                                        {HF_METHOD_QDM, HF_SURFACE_TRIANGLES, 512, 0, HF_SAFETY_DIRECTIONAL},
                                        {HF_METHOD_CC, HF_SURFACE_TRIANGLES, 0, 0, HF_SAFETY_DIRECTIONAL}};
        printf("%-36s bakes (all cores): safety %.0f ms, cone %.0f ms, qdm %.0f ms, cc %.0f ms\n",
               s.name, s.safety_bake_ms, s.cone_bake_ms, s.qdm_bake_ms, s.cc_bake_ms);
        for (int k = 0; k < NUM_METHODS; k++) {
            if (cfgs[k].method == HF_METHOD_RELAXED) continue; /* its bake takes minutes */
            gpu_render(&g, &s, cfgs[k], depth_far); /* warm-up: shader compile */
            glFinish();
            double t0 = now_seconds();
            for (int i = 0; i < frames; i++) {
                gpu_render(&g, &s, cfgs[k], depth_far);
                glFinish();
            }
            double gpu_ms = 1e3 * (now_seconds() - t0) / frames;
            t0 = now_seconds();
            cpu_trace(&s, cfgs[k], rays, n, hits);
            double cpu_ms = 1e3 * (now_seconds() - t0);
            double fetches = 0;
            for (size_t i = 0; i < n; i++) fetches += hits[i].fetches;
            char mname[64];
            snprintf(mname, sizeof mname, "%s/%s", method_name(cfgs[k].method),
                     surface_name(cfgs[k].surface));
            printf("%-36s %-24s %10.1f %10.1f %12.1f\n", s.name, mname, gpu_ms, cpu_ms,
                   fetches / (double)n);
        }
        free(rays);
        free(hits);
        gpu_free(&g);
        scene_free(&s);
    }
    printf("(gpu ms: llvmpipe, whole frame with shadow rays; cpu ms: primary rays only, one "
           "thread, C API batch)\n");
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

int main(int argc, char **argv) {
    if (argc >= 4 && strcmp(argv[1], "test") == 0) return run_tests(argv[2], argc - 3, argv + 3);
    if (argc >= 6 && strcmp(argv[1], "bench") == 0)
        return run_bench(atoi(argv[2]), atoi(argv[3]), atoi(argv[4]), argc - 5, argv + 5);
    if (argc == 3 && strcmp(argv[1], "shaders") == 0) return dump_shaders(argv[2]);
    fprintf(stderr,
            "usage: %s test OUTDIR MAP.png...\n"
            "       %s bench W H FRAMES MAP.png...\n"
            "       %s shaders OUTDIR\n",
            argv[0], argv[0], argv[0]);
    return 2;
}
