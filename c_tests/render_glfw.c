/* The scene of render_osmesa in a GLFW window (OpenGL 4.5 core).
 *
 * By hand:   render_glfw MAP.png
 *   arrows orbit, +/- zoom, M next method, S next surface, Esc quits; the title shows
 *   the method and the frame time.
 * In tests:  render_glfw --frames N --screenshot OUT.png --compare REF.png MAP.png
 *   draws N frames of the fixed view (exact method, triangles, 256 x 192), reads the
 *   window back and compares it with the OSMesa image of the same view.
 * Impostor:  render_glfw --impostor MESH.obj [--frames N]
 *   the mesh's six-field impostor (impostor.h) while the camera orbits; with --frames,
 *   every frame against the CPU (99.99 % of pixels must agree).
 * Dynamic terrain: render_glfw --dynamic [--frames N] MAP.png
 *   every frame raises a mound that moves along a circle (gpu_bake.h), refreshes the
 *   pyramid on the GPU for the edited rectangle only and draws the maximum-mipmap
 *   march; with --frames, each frame's hits are compared with the CPU's on the CPU's
 *   own refreshed pyramid (99.99 % of pixels must agree).
 */
#define _POSIX_C_SOURCE 200112L
#include "render_common.h"
#include "gpu_bake.h"
#include "roll.h"
#include "hybrid.h"
#include "impostor.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static camera cam;
/* `linear`: search steps, or the cone/QDM iteration budget. */
static method_cfg cfg = {HF_METHOD_EXACT, HF_SURFACE_TRIANGLES, 64, 8, HF_SAFETY_DIRECTIONAL, HF_RADIUS_WALK};
static int dirty = 1;

/* The dynamic scene's frame `k`: edits the heights and refreshes the GPU pyramid. With
 * `check`, compares the frame's hits with the CPU's (`rays` are the uploaded ones) and
 * prints its line; returns whether it passed. */
static int dynamic_frame(scene *s, gpu *g, gpu_bakes *b, int k, const hf_ray *rays, int w,
                         int h, int check, frame *f) {
    uint32_t rect[4];
    double cpu_ms = 0;
    if (dynamic_edit(s, g->tex_heights, k, rect, &cpu_ms) != 0) return 0;
    double t0 = now_seconds();
    long texels = gpu_pyramid_bake(b, s->w, s->h, g->tex_heights, rect, g->tex_pyramid);
    if (texels < 0) return 0;
    if (!check) return 1;
    glFinish();
    double gpu_ms = 1e3 * (now_seconds() - t0);
    gpu_render(g, s, cfg, scene_depth_far(s, &cam));
    gpu_read(g, f);
    parity p = compare(s, cfg, rays, f, scene_depth_far(s, &cam), w, h, 0, "glfw-dynamic");
    int ok = parity_ok(&p, cfg.method);
    printf("glfw-dynamic frame %d: edit %ux%u, cpu update %.2f ms, gpu update %.2f ms (%ld "
           "texels); %d pixels, %d differ; shadows %d/%d differ  %s\n",
           k, rect[2] - rect[0], rect[3] - rect[1], cpu_ms, gpu_ms, texels, p.pixels, p.differ,
           p.shadow_differ, p.shadow_checked, ok ? "ok" : "FAILED");
    return ok;
}

static void on_key(GLFWwindow *win, int key, int scancode, int action, int mods) {
    (void)scancode;
    (void)mods;
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    switch (key) {
    case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(win, 1); break;
    case GLFW_KEY_LEFT: cam.azimuth -= 0.05f; break;
    case GLFW_KEY_RIGHT: cam.azimuth += 0.05f; break;
    case GLFW_KEY_UP: cam.elevation = cam.elevation < 1.5f ? cam.elevation + 0.05f : 1.5f; break;
    case GLFW_KEY_DOWN: cam.elevation = cam.elevation > -0.3f ? cam.elevation - 0.05f : -0.3f; break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: cam.distance *= 0.9f; break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: cam.distance *= 1.1f; break;
    case GLFW_KEY_M:
        /* Relaxed cones are skipped: their bake takes minutes on a full map. */
        do cfg.method = (cfg.method + 1) % NUM_METHODS;
        while (cfg.method == HF_METHOD_RELAXED);
        break;
    case GLFW_KEY_S: cfg.surface = (cfg.surface + 1) % HF_SURFACE_COUNT; break;
    case GLFW_KEY_R: cam.roll += 0.0872665f; break; /* 5 degrees */
    default: return;
    }
    dirty = 1;
}

/* The window's roll against the rolled rays (roll_measure, roll_ok): prints the result
 * and returns 1 when it fails. */
static int roll_check(roll_view *rv, gpu *g, const scene *s, const camera *c, float degrees) {
    frame direct, mapped;
    frame_alloc(&direct, g->w, g->h);
    frame_alloc(&mapped, g->w, g->h);
    roll_result res = roll_measure(rv, g, s, cfg, c, 3, &direct, &mapped);
    int ok = roll_ok(&res, (int)degrees);
    printf("glfw-roll %g degrees: rolled rays %.1f ms; unrolled %d pixels + mapping %.1f ms; "
           "%d of %d pixels hit/miss differ (unturned: %d), %d colours differ by > 8/255, mean "
           "colour error %.2f/255\n",
           degrees, res.direct_ms, res.unrolled_pixels, res.mapped_ms, res.hit_differ,
           res.pixels, res.unturned, res.color_differ, res.color_mean);
    printf("glfw-roll: %d passed, %d failed\n", ok, !ok);
    frame_free(&direct);
    frame_free(&mapped);
    return !ok;
}

/* The window's hybrid frame (in g) against the CPU (hybrid_compare, hybrid_ok): prints
 * the result and returns 1 when it fails. */
static int hybrid_window_check(gpu *g, const scene *s, const hf_ray *rays) {
    frame f;
    frame_alloc(&f, g->w, g->h);
    gpu_read(g, &f);
    size_t n = (size_t)g->w * g->h;
    hybrid_check c = hybrid_compare(s, rays, &f, n);
    int ok = hybrid_ok(&c, n);
    printf("glfw-hybrid: %zu pixels, %d cpu hits, %d differ from the cpu ray cast of the "
           "view-linear surface (%d hit/miss), max err %.2e; %d differ from the same passes "
           "on the cpu\n",
           n, c.hits, c.differ, c.hit_differ, c.max_err, c.same_differ);
    printf("glfw-hybrid: %d passed, %d failed\n", ok, !ok);
    frame_free(&f);
    return !ok;
}

static int compare_images(const unsigned char *rgba, int w, int h, const char *ref_path) {
    unsigned char *ref = NULL;
    int rw = 0, rh = 0;
    if (read_png_rgb(ref_path, &ref, &rw, &rh) != 0) {
        fprintf(stderr, "cannot read the reference %s\n", ref_path);
        return 1;
    }
    if (rw != w || rh != h) {
        fprintf(stderr, "reference is %d x %d, window %d x %d\n", rw, rh, w, h);
        free(ref);
        return 1;
    }
    int differ = 0, listed = 0;
    for (int k = 0; k < w * h; k++) {
        int bad = 0;
        for (int c = 0; c < 3; c++) {
            int d = (int)rgba[4 * k + c] - (int)ref[3 * k + c];
            if (d > 1 || d < -1) bad = 1;
        }
        if (bad) {
            differ++;
            if (listed++ < 50)
                fprintf(stderr, "  pixel (%d, %d): window (%d, %d, %d), osmesa (%d, %d, %d)\n",
                        k % w, k / w, rgba[4 * k], rgba[4 * k + 1], rgba[4 * k + 2], ref[3 * k],
                        ref[3 * k + 1], ref[3 * k + 2]);
        }
    }
    free(ref);
    printf("glfw: %d pixels compared with %s, %d differ by more than 1/255\n", w * h, ref_path,
           differ);
    printf("glfw: %d passed, %d failed\n", differ == 0 ? 1 : 0, differ == 0 ? 0 : 1);
    return differ == 0 ? 0 : 1;
}

/* The impostor window: the mesh `path` as six reverse-perspective fields of 64²
 * (impostor.h), drawn through the cube proxy with depth output while the camera
 * orbits (3° a frame); the window shows each pixel's forward distance. With `frames`,
 * every frame is checked against hf_impostor_trace_batch on the same rays and the
 * window closes after that many. Returns the exit status. */
static int impostor_window(GLFWwindow *win, int w, int h, const char *path, int frames) {
    imp_mesh m;
    imp_fields f;
    imp_gl g;
    if (imp_mesh_load_obj(&m, path) != 0) return 2;
    if (imp_fields_capture(&f, &m, HF_IMPOSTOR_REVERSE_PERSPECTIVE, 64) != 0) return 2;
    if (imp_gl_init(&g, w, h) != 0) return 2;
    imp_gl_set_fields(&g, &f);
    size_t n = (size_t)w * h;
    hf_ray *rays = (hf_ray *)malloc(n * sizeof *rays);
    float *pt = (float *)malloc(n * 16), *info = (float *)malloc(n * 16);
    int passed = 0, failed = 0;
    for (int frame = 0; !glfwWindowShouldClose(win); frame++) {
        imp_view v = imp_orbit(&f.layout, 30.0 + 3.0 * frame, 25.0, 3.2, 40.0, w, h);
        imp_rays(&v, w, h, rays);
        imp_gl_set_rays(&g, rays);
        imp_stats st = imp_gl_draw(&g, &f, &v, HF_IMPOSTOR_INTERSECTION, 1, 1, 1);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, g.fbo);
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        glDrawBuffer(GL_BACK);
        glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        if (frames > 0) {
            imp_gl_read(&g, pt, info);
            imp_check c = imp_check_cpu(&f, HF_IMPOSTOR_INTERSECTION, rays, n, pt, info);
            int ok = imp_check_ok(&c);
            ok ? passed++ : failed++;
            printf("glfw-impostor frame %d: %d pixels, %d cpu hits, %d differ (%d hit/miss), "
                   "max err %.1e half sides; %u fragments, %.1f ms  %s\n",
                   frame, c.pixels, c.hits, c.differ, c.hit_differ, c.max_err, st.fragments,
                   st.ms, ok ? "ok" : "FAILED");
            if (frame == frames - 1) glfwSetWindowShouldClose(win, 1);
        }
        glfwSwapBuffers(win);
        glfwPollEvents();
    }
    if (frames > 0) printf("glfw-impostor: %d passed, %d failed\n", passed, failed);
    free(rays);
    free(pt);
    free(info);
    imp_gl_free(&g);
    imp_fields_free(&f);
    imp_mesh_free(&m);
    return failed == 0 && (frames == 0 || passed > 0) ? 0 : 1;
}

int main(int argc, char **argv) {
    int frames = 0, w = 800, h = 600, dynamic = 0, rolled = 0, hybrid_mode = 0;
    float roll_deg = 0.0f;
    const char *shot = NULL, *ref = NULL, *map = NULL, *mesh = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--frames") == 0 && i + 1 < argc) frames = atoi(argv[++i]);
        else if (strcmp(argv[i], "--impostor") == 0 && i + 1 < argc) mesh = argv[++i];
        else if (strcmp(argv[i], "--dynamic") == 0) dynamic = 1;
        else if (strcmp(argv[i], "--hybrid") == 0) hybrid_mode = 1;
        else if (strcmp(argv[i], "--roll") == 0 && i + 1 < argc) {
            rolled = 1;
            roll_deg = (float)atof(argv[++i]);
        }
        else if (strcmp(argv[i], "--screenshot") == 0 && i + 1 < argc) shot = argv[++i];
        else if (strcmp(argv[i], "--compare") == 0 && i + 1 < argc) ref = argv[++i];
        else map = argv[i];
    }
    if (!map && !mesh) {
        fprintf(stderr,
                "usage: %s [--frames N --screenshot OUT.png --compare REF.png] MAP.png\n"
                "       %s --dynamic [--frames N] MAP.png\n"
                "       %s --roll DEGREES [--frames N] MAP.png (Qu et al.'s roll: the\n"
                "         unrolled view texture-mapped; R rolls by 5 degrees)\n"
                "       %s --hybrid [--frames N] MAP.png (Qu et al.'s hybrid rasterization\n"
                "         of the view-linear surface)\n"
                "       %s --impostor MESH.obj [--frames N] (six-field impostor, orbiting)\n",
                argv[0], argv[0], argv[0], argv[0], argv[0]);
        return 2;
    }
    if (frames > 0) {
        w = 256; /* the size of the OSMesa test image */
        h = 192;
    }
    setenv("MESA_SHADER_CACHE_DISABLE", "true", 0);
    if (!glfwInit()) {
        fprintf(stderr, "glfwInit failed (no display?)\n");
        return 2;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    GLFWwindow *win = glfwCreateWindow(w, h, "hfcast", NULL, NULL);
    if (!win) {
        fprintf(stderr, "glfwCreateWindow (4.5 core) failed\n");
        glfwTerminate();
        return 2;
    }
    glfwMakeContextCurrent(win);
    glfwSwapInterval(0);
    glfwSetKeyCallback(win, on_key);
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(win, &fw, &fh);
    if (mesh) {
        int rc = impostor_window(win, fw, fh, mesh, frames);
        glfwDestroyWindow(win);
        glfwTerminate();
        return rc;
    }
    scene s;
    if (scene_load(&s, map) != 0) {
        fprintf(stderr, "cannot read %s\n", map);
        return 2;
    }
    gpu g;
    if (gpu_init(&g, &s, fw, fh) != 0) return 2;
    cam = default_camera();
    cam.roll = roll_deg * 3.14159265f / 180.0f;
    roll_view rv;
    if (rolled && roll_init(&rv, &s, &g) != 0) return 2;
    hf_ray *unrolled_rays = rolled ? (hf_ray *)malloc(sizeof(hf_ray) * (size_t)rv.side * rv.side)
                                   : NULL;
    int roll_failed = 0, hybrid_failed = 0;
    hybrid hy;
    if (hybrid_mode && hybrid_init(&hy, &s, &g) != 0) return 2;
    gpu_bakes bakes;
    frame checked;
    int dyn_passed = 0, dyn_failed = 0;
    if (dynamic) {
        cfg.method = HF_METHOD_MAXMIP;
        if (gpu_bakes_init(&bakes, s.w, s.h) != 0 ||
            gpu_pyramid_bake(&bakes, s.w, s.h, g.tex_heights, NULL, g.tex_pyramid) < 0)
            return 2;
        frame_alloc(&checked, fw, fh);
    }
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * (size_t)fw * fh);
    unsigned char *pixels = (unsigned char *)malloc((size_t)fw * fh * 4);
    int rc = 0;
    double last = now_seconds(), shown = 0;
    for (int frame = 0; !glfwWindowShouldClose(win); frame++) {
        if (dirty) {
            make_rays(&s, &cam, fw, fh, rays);
            gpu_upload_rays(&g, rays);
            dirty = 0;
        }
        if (dynamic) {
            int ok = dynamic_frame(&s, &g, &bakes, frame, rays, fw, fh, frames > 0, &checked);
            ok ? dyn_passed++ : dyn_failed++;
        }
        if (rolled)
            roll_render_mapped(&rv, &g, &s, cfg, &cam, unrolled_rays);
        else if (hybrid_mode)
            hybrid_render(&hy, &g, &s, &cam);
        else
            gpu_render(&g, &s, cfg, scene_depth_far(&s, &cam));
        glBindFramebuffer(GL_READ_FRAMEBUFFER, g.fbo);
        glReadBuffer(GL_COLOR_ATTACHMENT2);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        glDrawBuffer(GL_BACK);
        glBlitFramebuffer(0, 0, fw, fh, 0, 0, fw, fh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        if (frames > 0 && frame == frames - 1) {
            glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
            glReadBuffer(GL_BACK);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
            if (shot && write_png_rgba(shot, pixels, fw, fh) != 0) rc = 1;
            if (ref) rc |= compare_images(pixels, fw, fh, ref);
            if (rolled) roll_failed = roll_check(&rv, &g, &s, &cam, roll_deg);
            if (hybrid_mode) hybrid_failed = hybrid_window_check(&g, &s, rays);
            glfwSetWindowShouldClose(win, 1);
        }
        glfwSwapBuffers(win);
        glfwPollEvents();
        double t = now_seconds();
        if (t - shown > 0.25) {
            char title[256];
            snprintf(title, sizeof title, "hfcast - %s/%s - %.1f ms/frame (M: method, S: surface)",
                     method_name(cfg.method), surface_name(cfg.surface), 1e3 * (t - last));
            glfwSetWindowTitle(win, title);
            shown = t;
        }
        last = t;
    }
    if (glGetError() != GL_NO_ERROR) {
        fprintf(stderr, "GL error\n");
        rc = 1;
    }
    if (hybrid_mode) {
        rc |= hybrid_failed;
        hybrid_free(&hy);
    }
    if (rolled) {
        rc |= roll_failed;
        free(unrolled_rays);
        roll_free(&rv);
    }
    if (dynamic) {
        if (frames > 0) {
            printf("glfw-dynamic: %d passed, %d failed\n", dyn_passed, dyn_failed);
            rc |= dyn_failed != 0 || dyn_passed == 0;
        }
        frame_free(&checked);
        gpu_bakes_free(&bakes);
    }
    free(rays);
    free(pixels);
    gpu_free(&g);
    scene_free(&s);
    glfwDestroyWindow(win);
    glfwTerminate();
    return rc;
}
