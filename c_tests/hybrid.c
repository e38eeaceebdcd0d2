/* Qu et al.'s hybrid rasterization renderer (hybrid.h). */
#include "hybrid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Pass 1's vertices: a corner of a boundary rectangle (x, y, z) and its axis (0: the
 * plane x = line, 1: y = line), projected with the camera of make_rays: clip (x, y) =
 * the view-plane coordinates over the window's half extents, w = the distance along
 * the view axis (z = 0: the fragment writes its depth). */
static const char *PASS1_VERTEX =
    "#version 430 core\n"
    "layout(location = 0) in vec4 corner;\n"
    "uniform vec3 eye, cam_right, cam_up, cam_fwd;\n"
    "flat out int v_axis;\n"
    "flat out float v_line;\n"
    "void main() {\n"
    "    vec3 v = corner.xyz - eye;\n"
    "    gl_Position = vec4(dot(v, cam_right), dot(v, cam_up), 0.0, dot(v, cam_fwd));\n"
    "    v_axis = int(corner.w);\n"
    "    v_line = corner.w == 0.0 ? corner.x : corner.y;\n"
    "}\n";

/* The pixel's query and the boundary height where the ray crosses line `line` of axis
 * `a` at point p (the line's two samples around p, as the exact walk's crossings). */
static const char *COMMON =
    "uniform sampler2D hf_ray_origin, hf_ray_dir;\n"
    "uniform float depth_far;\n"
    "Query hy_query() {\n"
    "    ivec2 px = ivec2(gl_FragCoord.xy);\n"
    "    vec4 o = texelFetch(hf_ray_origin, px, 0);\n"
    "    vec4 d = texelFetch(hf_ray_dir, px, 0);\n"
    "    return Query(o.xyz, d.xyz, o.w, d.w);\n"
    "}\n"
    "float hy_lim(int b) { return float(b == 0 ? field_width() - 1u : field_height() - 1u); }\n"
    "float hy_boundary_height(int a, float line, vec3 p) {\n"
    "    int b = 1 - a;\n"
    "    uint j = min(uint(max(p[b], 0.0)), uint(hy_lim(b)) - 1u);\n"
    "    float f = clamp(p[b] - float(j), 0.0, 1.0);\n"
    "    uint l = uint(line);\n"
    "    float h0 = a == 0 ? field_at(l, j) : field_at(j, l);\n"
    "    float h1 = a == 0 ? field_at(l, j + 1u) : field_at(j + 1u, l);\n"
    "    return real_lerp(h0, h1, f);\n"
    "}\n";

/* Pass 1: the crossing of this pixel's ray with this fragment's plane, kept when on or
 * under the surface; the depth test keeps the nearest. Counts its fragments. */
static const char *PASS1_MAIN =
    "layout(binding = 0, offset = 0) uniform atomic_uint hy_fragments;\n"
    "layout(binding = 0, offset = 4) uniform atomic_uint hy_kept;\n"
    "flat in int v_axis;\n"
    "flat in float v_line;\n"
    "layout(location = 0) out vec4 out_p2;\n"
    "void main() {\n"
    "    atomicCounterIncrement(hy_fragments);\n"
    "    Query q = hy_query();\n"
    "    int a = v_axis, b = 1 - v_axis;\n"
    "    if (q.dir[a] == 0.0) discard;\n"
    "    float t = (v_line - q.origin[a]) / q.dir[a];\n"
    "    if (!(t >= q.t_min && t <= q.t_max)) discard;\n"
    "    vec3 p = query_at(q, t);\n"
    "    if (!(p[b] >= 0.0 && p[b] <= hy_lim(b))) discard;\n"
    "    if (p[2] - hy_boundary_height(a, v_line, p) > 0.0) discard;\n"
    "    atomicCounterIncrement(hy_kept);\n"
    "    gl_FragDepth = clamp(t / depth_far, 0.0, 1.0);\n"
    "    out_p2 = vec4(t, float(a + 1), v_line, 0.0);\n"
    "}\n";

/* Pass 2, every pixel: core/src/hybrid.rs's `trace` after pass 1. A ray under the
 * surface where its span begins hits there; P2 is pass 1's crossing, else the span's
 * end when under the surface; P1 the last crossing before P2 on either axis, or the
 * span's start; then the interpolation of the clearances. Writes the frame as the
 * ray-cast shader does. */
static const char *PASS2_MAIN =
    "uniform sampler2D hy_p2;\n"
    "uniform vec3 light_dir;\n"
    "layout(location = 0) out vec4 out_point;\n"
    "layout(location = 1) out vec4 out_normal;\n"
    "layout(location = 2) out vec4 out_color;\n"
    "// `line_before`: the last line `m` of axis b crossed before t2 (d[b] != 0), its t.\n"
    "float hy_before(Query q, int b, float t2, out float m) {\n"
    "    float o = q.origin[b], d = q.dir[b];\n"
    "    float x = o + t2 * d;\n"
    "    float s = d > 0.0 ? 1.0 : -1.0;\n"
    "    m = d > 0.0 ? -floor(-x) - 1.0 : floor(x) + 1.0;\n"
    "    for (int k = 0; k < 2; k++) if ((m + s - o) / d < t2) m += s;\n"
    "    for (int k = 0; k < 2; k++) if ((m - o) / d >= t2) m -= s;\n"
    "    return (m - o) / d;\n"
    "}\n"
    "// The clearance at t: on line `line` of axis `on`, or bilinear (on < 0).\n"
    "float hy_clearance(Query q, float t, int on, float line) {\n"
    "    vec3 p = query_at(q, t);\n"
    "    float h = on < 0 ? surface_height_at(HF_SURFACE_BILINEAR, p[0], p[1])\n"
    "                     : hy_boundary_height(on, line, p);\n"
    "    return p[2] - h;\n"
    "}\n"
    "void hy_miss() {\n"
    "    out_point = vec4(0.0, 0.0, 0.0, -1.0);\n"
    "    out_normal = vec4(0.0);\n"
    "    out_color = vec4(0.55, 0.70, 0.90, 1.0);\n"
    "    gl_FragDepth = 1.0;\n"
    "}\n"
    "void main() {\n"
    "    Query q = hy_query();\n"
    "    Span span;\n"
    "    if (!dda_clip_surface(HF_SURFACE_VIEW_LINEAR, q, span)) { hy_miss(); return; }\n"
    "    int start_on = -1;\n"
    "    float start_line = 0.0;\n"
    "    if (span.entry == HF_ENTRY_SIDE) {\n"
    "        start_on = span.entry_normal[0] == 0.0 ? 1 : 0;\n"
    "        start_line = span.entry_normal[start_on] > 0.0 ? hy_lim(start_on) : 0.0;\n"
    "    }\n"
    "    float t;\n"
    "    if (hy_clearance(q, span.t0, start_on, start_line) <= 0.0) {\n"
    "        t = span.t0;\n"
    "    } else {\n"
    "        vec4 p2 = texelFetch(hy_p2, ivec2(gl_FragCoord.xy), 0);\n"
    "        float t2 = p2.x, line2 = p2.z;\n"
    "        int on2 = int(p2.y) - 1;\n"
    "        if (on2 < 0) {\n"
    "            if (hy_clearance(q, span.t1, -1, 0.0) > 0.0) { hy_miss(); return; }\n"
    "            t2 = span.t1;\n"
    "        }\n"
    "        float t1 = span.t0, line1 = start_line;\n"
    "        int on1 = start_on;\n"
    "        for (int b = 0; b < 2; b++) {\n"
    "            if (q.dir[b] == 0.0) continue;\n"
    "            float m;\n"
    "            float tb = hy_before(q, b, t2, m);\n"
    "            if (tb >= t1 && m >= 0.0 && m <= hy_lim(b)) { t1 = tb; on1 = b; line1 = m; }\n"
    "        }\n"
    "        float d1 = hy_clearance(q, t1, on1, line1), d2 = hy_clearance(q, t2, on2, line2);\n"
    "        t = t1 + (t2 - t1) * (d1 / (d1 - d2));\n"
    "    }\n"
    "    vec3 p = query_at(q, t);\n"
    "    vec3 n = surface_normal_at(HF_SURFACE_VIEW_LINEAR, p[0], p[1]);\n"
    "    out_point = vec4(p, t);\n"
    "    out_normal = vec4(n, 0.0);\n"
    "    float lit = max(dot(n, light_dir), 0.0);\n"
    "    out_color = vec4(vec3(0.62, 0.56, 0.45) * (0.18 + 0.82 * lit), 1.0);\n"
    "    gl_FragDepth = clamp(t / depth_far, 0.0, 1.0);\n"
    "}\n";

/* "#version 430 core", the exact method's GLSL (the field, surfaces, clip), COMMON and
 * `main_src`. */
static char *fragment(const char *main_src) {
    size_t len = 0, written = 0;
    if (hf_shader_source_len(HF_METHOD_EXACT, &len) != HF_OK) return NULL;
    const char *head = "#version 430 core\n";
    char *src = (char *)malloc(strlen(head) + len + strlen(COMMON) + strlen(main_src) + 1);
    strcpy(src, head);
    if (hf_shader_source(HF_METHOD_EXACT, src + strlen(head), len, &written) != HF_OK) {
        free(src);
        return NULL;
    }
    strcat(src, COMMON);
    strcat(src, main_src);
    return src;
}

/* Appends the rectangle of line `line` of axis `a` (its other coordinate over [-1,
 * lim + 1], z over [zlo, zhi]) as two triangles. */
static void rectangle(float *v, GLsizei *n, int a, float line, float lim, float zlo, float zhi) {
    const float other[6] = {-1.0f, lim + 1.0f, lim + 1.0f, -1.0f, lim + 1.0f, -1.0f};
    const float z[6] = {zlo, zlo, zhi, zlo, zhi, zhi};
    for (int k = 0; k < 6; k++) {
        float *c = v + 4 * (*n)++;
        c[a] = line;
        c[1 - a] = other[k];
        c[2] = z[k];
        c[3] = (float)a;
    }
}

int hybrid_init(hybrid *hy, const scene *s, const gpu *g) {
    memset(hy, 0, sizeof *hy);
    hy->w = g->w;
    hy->h = g->h;
    char *fs1 = fragment(PASS1_MAIN), *fs2 = fragment(PASS2_MAIN);
    if (!fs1 || !fs2) return -1;
    hy->pass1 = link_shaders(PASS1_VERTEX, fs1);
    hy->pass2 = link_fragment(fs2);
    free(fs1);
    free(fs2);
    /* Every boundary from the lowest sample less twice the span's margin (the exact walk
     * stops 1 + the relief under it; a ray that drops further between two crossings is
     * left out) to the highest; the footprint's sides, which rays may enter anywhere
     * below the surface (a hit where they enter), down to the far depth. */
    float lo = s->info.min_height, hi = s->info.max_height;
    float zlo = lo - 2.0f * (1.0f + (hi - lo)), zhi = hi + 1.0f;
    float zfar = lo - 4.0f * (float)(s->w > s->h ? s->w : s->h) - 4.0f * (hi - lo);
    size_t quads = (size_t)s->w + s->h;
    float *v = (float *)malloc(sizeof(float) * 4 * 6 * quads);
    for (uint32_t i = 0; i < s->w; i++)
        rectangle(v, &hy->vertices, 0, (float)i, (float)(s->h - 1),
                  i == 0 || i + 1 == s->w ? zfar : zlo, zhi);
    for (uint32_t j = 0; j < s->h; j++)
        rectangle(v, &hy->vertices, 1, (float)j, (float)(s->w - 1),
                  j == 0 || j + 1 == s->h ? zfar : zlo, zhi);
    glGenVertexArrays(1, &hy->vao);
    glBindVertexArray(hy->vao);
    glGenBuffers(1, &hy->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, hy->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * 4 * hy->vertices), v,
                 GL_STATIC_DRAW);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
    free(v);
    hy->tex_p2 = make_texture(GL_RGBA32F, g->w, g->h, GL_RGBA, GL_FLOAT, NULL);
    glGenRenderbuffers(1, &hy->rb_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, hy->rb_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, g->w, g->h);
    glGenFramebuffers(1, &hy->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, hy->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, hy->tex_p2, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, hy->rb_depth);
    glGenBuffers(1, &hy->counters);
    glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, hy->counters);
    glBufferData(GL_ATOMIC_COUNTER_BUFFER, 8, NULL, GL_DYNAMIC_COPY);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return -1;
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

void hybrid_free(hybrid *hy) {
    glDeleteProgram(hy->pass1);
    glDeleteProgram(hy->pass2);
    glDeleteBuffers(1, &hy->vbo);
    glDeleteBuffers(1, &hy->counters);
    glDeleteVertexArrays(1, &hy->vao);
    glDeleteTextures(1, &hy->tex_p2);
    glDeleteRenderbuffers(1, &hy->rb_depth);
    glDeleteFramebuffers(1, &hy->fbo);
}

/* The uniforms both passes read: the field (as gpu_render_program sets them), the rays
 * and the depth scale; texture units 0 and 2, 3 as gpu_render_program binds them. */
static void field_uniforms(GLuint p, const gpu *g, const scene *s, float depth_far) {
    glUseProgram(p);
    const GLuint tex[3] = {g->tex_heights, g->tex_origin, g->tex_dir};
    const char *names[3] = {"hf_heights", "hf_ray_origin", "hf_ray_dir"};
    for (int k = 0; k < 3; k++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)k);
        glBindTexture(GL_TEXTURE_2D, tex[k]);
        glUniform1i(glGetUniformLocation(p, names[k]), k);
    }
    glUniform2i(glGetUniformLocation(p, "hf_size"), (GLint)s->w, (GLint)s->h);
    glUniform2f(glGetUniformLocation(p, "hf_height_range"), s->info.min_height,
                s->info.max_height);
    glUniform1f(glGetUniformLocation(p, "depth_far"), depth_far);
}

hybrid_stats hybrid_render(hybrid *hy, gpu *g, const scene *s, const camera *c) {
    hybrid_stats st;
    memset(&st, 0, sizeof st);
    float depth_far = scene_depth_far(s, c);
    float eye[3], fwd[3], right[3], up[3], half[2];
    camera_frame(s, c, eye, fwd, right, up);
    camera_window(c, g->w, g->h, half);
    for (int k = 0; k < 3; k++) {
        right[k] /= half[0];
        up[k] /= half[1];
    }
    const GLuint zero[2] = {0, 0};
    glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, hy->counters);
    glBufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof zero, zero);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, hy->counters);
    double t0 = now_seconds();
    /* Pass 1: the rectangles, nearest crossing on or under the surface. */
    field_uniforms(hy->pass1, g, s, depth_far);
    glUniform3fv(glGetUniformLocation(hy->pass1, "eye"), 1, eye);
    glUniform3fv(glGetUniformLocation(hy->pass1, "cam_right"), 1, right);
    glUniform3fv(glGetUniformLocation(hy->pass1, "cam_up"), 1, up);
    glUniform3fv(glGetUniformLocation(hy->pass1, "cam_fwd"), 1, fwd);
    glBindFramebuffer(GL_FRAMEBUFFER, hy->fbo);
    glViewport(0, 0, hy->w, hy->h);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(hy->vao);
    glDrawArrays(GL_TRIANGLES, 0, hy->vertices);
    glFinish();
    double t1 = now_seconds();
    /* Pass 2: one fragment per pixel into g's frame. */
    field_uniforms(hy->pass2, g, s, depth_far);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, hy->tex_p2);
    glUniform1i(glGetUniformLocation(hy->pass2, "hy_p2"), 3);
    glUniform3fv(glGetUniformLocation(hy->pass2, "light_dir"), 1, LIGHT_DIR);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glViewport(0, 0, g->w, g->h);
    glDepthFunc(GL_ALWAYS);
    glClear(GL_DEPTH_BUFFER_BIT);
    glBindVertexArray(g->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFinish();
    double t2 = now_seconds();
    GLuint counts[2] = {0, 0};
    glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, hy->counters);
    glGetBufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof counts, counts);
    st.pass1_ms = 1e3 * (t1 - t0);
    st.pass2_ms = 1e3 * (t2 - t1);
    st.fragments = counts[0];
    st.kept = counts[1];
    return st;
}

hybrid_check hybrid_compare(const scene *s, const hf_ray *rays, const frame *f, size_t n) {
    hybrid_check c;
    memset(&c, 0, sizeof c);
    hf_hit *cpu = (hf_hit *)malloc(sizeof(hf_hit) * n);
    hf_hit *same = (hf_hit *)malloc(sizeof(hf_hit) * n);
    method_cfg vl = {HF_METHOD_EXACT, HF_SURFACE_VIEW_LINEAR, 0, 0, HF_SAFETY_DIRECTIONAL,
                     HF_RADIUS_WALK};
    cpu_trace(s, vl, rays, n, cpu);
    double t0 = now_seconds();
    if (hf_hybrid_trace_batch(s->field, rays, n, same, n) != HF_OK) c.same_differ = (int)n;
    c.cpu_ms = 1e3 * (now_seconds() - t0);
    for (size_t k = 0; k < n; k++) {
        const float *p = &f->point[4 * k];
        int hit = p[3] >= 0.0f;
        c.hits += cpu[k].hit != 0;
        if (hit != (same[k].hit != 0) || (hit && dist3(p, same[k].point) > 1e-3))
            c.same_differ++;
        if (hit != (cpu[k].hit != 0)) {
            c.differ++;
            c.hit_differ++;
            continue;
        }
        if (!hit) continue;
        double e = dist3(p, cpu[k].point);
        if (e > c.max_err) c.max_err = e;
        if (e > 1e-3) c.differ++;
    }
    free(cpu);
    free(same);
    return c;
}

int hybrid_ok(const hybrid_check *c, size_t n) {
    return (double)c->differ <= 1e-4 * (double)n && c->hits > 0;
}
