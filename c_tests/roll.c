/* Camera roll the way of Qu et al. (roll.h). */
#include "roll.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The texture-mapping pass: every pixel of the rolled image takes the unrolled render's
 * pixel (nearest) under its own view-plane point turned into the unrolled frame; all
 * three outputs, so hits and shading can be compared. */
static const char *ROLL_FRAGMENT =
    "#version 330 core\n"
    "uniform sampler2D src_point, src_normal, src_color;\n"
    "uniform vec2 dst_size, dst_half, src_half, roll_cs;\n"
    "uniform ivec2 src_size;\n"
    "layout(location = 0) out vec4 out_point;\n"
    "layout(location = 1) out vec4 out_normal;\n"
    "layout(location = 2) out vec4 out_color;\n"
    "void main() {\n"
    "    vec2 s = (gl_FragCoord.xy / dst_size * 2.0 - 1.0) * dst_half;\n"
    "    vec2 u = vec2(roll_cs.x * s.x - roll_cs.y * s.y, roll_cs.y * s.x + roll_cs.x * s.y);\n"
    "    ivec2 p = ivec2(floor((u / src_half * 0.5 + 0.5) * vec2(src_size)));\n"
    "    p = clamp(p, ivec2(0), src_size - 1);\n"
    "    out_point = texelFetch(src_point, p, 0);\n"
    "    out_normal = texelFetch(src_normal, p, 0);\n"
    "    out_color = texelFetch(src_color, p, 0);\n"
    "}\n";

int roll_init(roll_view *r, const scene *s, const gpu *g) {
    memset(r, 0, sizeof *r);
    r->side = (int)ceil(sqrt((double)g->w * g->w + (double)g->h * g->h)) + 2;
    if (gpu_init(&r->unrolled, s, r->side, r->side) != 0) return -1;
    r->prog = link_fragment(ROLL_FRAGMENT);
    return r->prog != 0 && glGetError() == GL_NO_ERROR ? 0 : -1;
}

void roll_free(roll_view *r) {
    glDeleteProgram(r->prog);
    gpu_free(&r->unrolled);
}

void roll_window(const camera *c, int w, int h, float half[2], int size[2]) {
    float win[2];
    camera_window(c, w, h, win);
    if (c->roll == 0.0f) {
        memcpy(half, win, sizeof win);
        size[0] = w;
        size[1] = h;
        return;
    }
    float cr = fabsf(cosf(c->roll)), sr = fabsf(sinf(c->roll));
    float pitch = 2.0f * win[1] / (float)h;
    float box[2] = {cr * win[0] + sr * win[1], sr * win[0] + cr * win[1]};
    for (int k = 0; k < 2; k++) {
        size[k] = (int)ceilf(2.0f * box[k] / pitch - 1e-3f);
        half[k] = 0.5f * pitch * (float)size[k];
    }
}

void roll_render_mapped(roll_view *r, gpu *g, const scene *s, method_cfg cfg, const camera *c,
                        hf_ray *rays) {
    float half[2], dst_half[2];
    int size[2];
    roll_window(c, g->w, g->h, half, size);
    camera_window(c, g->w, g->h, dst_half);
    camera flat = *c;
    flat.roll = 0.0f;
    gpu *u = &r->unrolled;
    u->w = size[0];
    u->h = size[1];
    make_rays_window(s, &flat, size[0], size[1], half, rays);
    gpu_upload_rays(u, rays);
    gpu_render(u, s, cfg, scene_depth_far(s, c));
    glUseProgram(r->prog);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glViewport(0, 0, g->w, g->h);
    glDisable(GL_DEPTH_TEST);
    GLuint src[3] = {u->tex_point, u->tex_normal, u->tex_color};
    const char *names[3] = {"src_point", "src_normal", "src_color"};
    for (int k = 0; k < 3; k++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)k);
        glBindTexture(GL_TEXTURE_2D, src[k]);
        glUniform1i(glGetUniformLocation(r->prog, names[k]), k);
    }
    glUniform2f(glGetUniformLocation(r->prog, "dst_size"), (float)g->w, (float)g->h);
    glUniform2f(glGetUniformLocation(r->prog, "dst_half"), dst_half[0], dst_half[1]);
    glUniform2f(glGetUniformLocation(r->prog, "src_half"), half[0], half[1]);
    glUniform2f(glGetUniformLocation(r->prog, "roll_cs"), cosf(c->roll), sinf(c->roll));
    glUniform2i(glGetUniformLocation(r->prog, "src_size"), size[0], size[1]);
    glBindVertexArray(g->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEnable(GL_DEPTH_TEST);
}

static double median3(double *v, int n) {
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && v[j] < v[j - 1]; j--) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    return v[n / 2];
}

roll_result roll_measure(roll_view *r, gpu *g, const scene *s, method_cfg cfg, const camera *c,
                         int reps, frame *direct, frame *mapped) {
    roll_result res;
    memset(&res, 0, sizeof res);
    /* The unrolled render's rays (the larger of the two). */
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * (size_t)r->side * r->side);
    double *direct_ms = (double *)calloc((size_t)reps, sizeof(double));
    double *mapped_ms = (double *)calloc((size_t)reps, sizeof(double));
    for (int k = 0; k < reps; k++) {
        /* Each way from its rays to the finished frame. */
        double t0 = now_seconds();
        make_rays(s, c, g->w, g->h, rays);
        gpu_upload_rays(g, rays);
        gpu_render(g, s, cfg, scene_depth_far(s, c));
        glFinish();
        direct_ms[k] = 1e3 * (now_seconds() - t0);
        if (k == reps - 1) gpu_read(g, direct);
        t0 = now_seconds();
        roll_render_mapped(r, g, s, cfg, c, rays);
        glFinish();
        mapped_ms[k] = 1e3 * (now_seconds() - t0);
        if (k == reps - 1) gpu_read(g, mapped);
    }
    res.direct_ms = median3(direct_ms, reps);
    res.mapped_ms = median3(mapped_ms, reps);
    res.pixels = g->w * g->h;
    res.unrolled_pixels = r->unrolled.w * r->unrolled.h;
    long sum = 0;
    for (int k = 0; k < res.pixels; k++) {
        int hit_d = direct->point[4 * k + 3] >= 0.0f, hit_m = mapped->point[4 * k + 3] >= 0.0f;
        if (hit_d != hit_m) res.hit_differ++;
        int worst = 0;
        for (int ch = 0; ch < 3; ch++) {
            int d = abs((int)direct->color[4 * k + ch] - (int)mapped->color[4 * k + ch]);
            sum += d;
            if (d > worst) worst = d;
        }
        if (worst > 8) res.color_differ++;
    }
    res.color_mean = (double)sum / (3.0 * res.pixels);
    camera unturned = *c;
    unturned.roll = 0.0f;
    frame flat;
    frame_alloc(&flat, g->w, g->h);
    make_rays(s, &unturned, g->w, g->h, rays);
    gpu_upload_rays(g, rays);
    gpu_render(g, s, cfg, scene_depth_far(s, c));
    gpu_read(g, &flat);
    for (int k = 0; k < res.pixels; k++)
        res.unturned += (direct->point[4 * k + 3] >= 0.0f) != (flat.point[4 * k + 3] >= 0.0f);
    frame_free(&flat);
    make_rays(s, c, g->w, g->h, rays);
    gpu_upload_rays(g, rays);
    free(rays);
    free(direct_ms);
    free(mapped_ms);
    return res;
}

int roll_ok(const roll_result *res, int degrees) {
    if (degrees % 90 == 0)
        return res->hit_differ + res->color_differ == 0 && res->color_mean == 0.0;
    return res->hit_differ * 50 <= res->pixels && res->hit_differ * 4 <= res->unturned &&
           res->color_mean < 16.0;
}
