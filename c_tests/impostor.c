/* Six-field impostors of a triangle mesh in OpenGL (impostor.h). */
#include "impostor.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* pi (M_PI is POSIX, not C99). */
static const double PI = 3.14159265358979323846;

/* Prints `what` failed with the C API's message for `r`; returns -1. */
static int fail_hf(const char *what, hf_result r) {
    char msg[256];
    size_t n = 0;
    if (hf_error_message(r, msg, sizeof msg, &n) != HF_OK) strcpy(msg, "?");
    fprintf(stderr, "%s: %s\n", what, msg);
    return -1;
}

/* ---- the mesh ------------------------------------------------------------------- */

/* Appends to a growing array of `size`-byte items. */
static void *grow(void *p, size_t *cap, size_t need, size_t size) {
    if (need <= *cap) return p;
    *cap = need * 2 + 64;
    void *q = realloc(p, *cap * size);
    if (!q) {
        fprintf(stderr, "out of memory\n");
        exit(2);
    }
    return q;
}

int imp_mesh_load_obj(imp_mesh *m, const char *path) {
    memset(m, 0, sizeof *m);
    FILE *fp = fopen(path, "r");
    if (!fp) {
        fprintf(stderr, "cannot open %s\n", path);
        return -1;
    }
    size_t cap_v = 0, cap_t = 0;
    char line[4096];
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == 'v' && line[1] == ' ') {
            float p[3];
            if (sscanf(line + 2, "%f %f %f", &p[0], &p[1], &p[2]) != 3) continue;
            m->pos = grow(m->pos, &cap_v, 3 * (m->nv + 1), sizeof(float));
            memcpy(m->pos + 3 * m->nv++, p, sizeof p);
        } else if (line[0] == 'f' && line[1] == ' ') {
            /* Each token's first number: 1-based, negative from the end. */
            long idx[64];
            int n = 0;
            char *s = line + 2;
            while (*s && n < 64) {
                while (*s && isspace((unsigned char)*s)) s++;
                if (!*s) break;
                char *end;
                long v = strtol(s, &end, 10);
                if (end == s) break;
                idx[n++] = v < 0 ? (long)m->nv + v : v - 1;
                while (*end && !isspace((unsigned char)*end)) end++;
                s = end;
            }
            for (int k = 2; k < n; k++) {
                m->tri = grow(m->tri, &cap_t, 3 * (m->nt + 1), sizeof(uint32_t));
                uint32_t *t = m->tri + 3 * m->nt++;
                t[0] = (uint32_t)idx[0];
                t[1] = (uint32_t)idx[k - 1];
                t[2] = (uint32_t)idx[k];
            }
        }
    }
    fclose(fp);
    if (m->nt == 0) {
        fprintf(stderr, "%s: no triangles\n", path);
        imp_mesh_free(m);
        return -1;
    }
    return 0;
}

void imp_mesh_free(imp_mesh *m) {
    free(m->pos);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

/* ---- the capture ---------------------------------------------------------------- */

/* The inverse of the row-major 4 x 4 `m` (Gauss-Jordan, partial pivoting). */
static void invert4(const double *m, double *inv) {
    double a[4][8];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 8; c++) a[r][c] = c < 4 ? m[4 * r + c] : (c - 4 == r);
    for (int c = 0; c < 4; c++) {
        int p = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(a[r][c]) > fabs(a[p][c])) p = r;
        for (int k = 0; k < 8; k++) {
            double t = a[c][k];
            a[c][k] = a[p][k];
            a[p][k] = t;
        }
        double f = a[c][c];
        for (int k = 0; k < 8; k++) a[c][k] /= f;
        for (int r = 0; r < 4; r++) {
            if (r == c) continue;
            double g = a[r][c];
            for (int k = 0; k < 8; k++) a[r][k] -= g * a[c][k];
        }
    }
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) inv[4 * r + c] = a[r][4 + c];
}

int imp_fields_capture(imp_fields *f, const imp_mesh *m, uint32_t frustum, uint32_t side) {
    memset(f, 0, sizeof *f);
    f->side = side;
    hf_result r = hf_impostor_layout_around(m->pos, m->nv, m->tri, m->nt, frustum, 0.0, &f->layout);
    if (r != HF_OK) return fail_hf("hf_impostor_layout_around", r);
    size_t n = (size_t)side * side;
    f->heights = (float *)malloc(6 * n * sizeof(float));
    double t0 = now_seconds();
    for (uint32_t k = 0; k < 6; k++) {
        r = hf_impostor_capture(m->pos, m->nv, m->tri, m->nt, &f->layout, k, side, 1,
                                f->heights + k * n, n, NULL, 0);
        if (r != HF_OK) {
            imp_fields_free(f);
            return fail_hf("hf_impostor_capture", r);
        }
    }
    f->capture_ms = 1e3 * (now_seconds() - t0);
    for (uint32_t k = 0; k < 6; k++) {
        double map[16], inv[16];
        hf_impostor_face_map(&f->layout, k, side, map);
        invert4(map, inv);
        for (int e = 0; e < 16; e++) {
            f->maps[k][e] = (float)map[e];
            f->inverses[k][e] = (float)inv[e];
        }
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < n; i++) {
            float v = f->heights[k * n + i];
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        f->ranges[k][0] = lo;
        f->ranges[k][1] = hi;
    }
    return 0;
}

void imp_fields_free(imp_fields *f) {
    free(f->heights);
    memset(f, 0, sizeof *f);
}

/* ---- the camera ----------------------------------------------------------------- */

static void normalize3(double *v) {
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) v[k] /= l;
}

static void cross3(const double *a, const double *b, double *out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

imp_view imp_orbit(const hf_impostor_layout *l, double azimuth, double elevation, double dist,
                   double fov, int w, int h) {
    imp_view v;
    double az = azimuth * PI / 180.0, el = elevation * PI / 180.0;
    double back[3] = {cos(el) * sin(az), cos(el) * cos(az), sin(el)};
    for (int k = 0; k < 3; k++) {
        v.eye[k] = l->center[k] + dist * l->half * back[k];
        v.fwd[k] = -back[k];
    }
    double zup[3] = {0, 0, 1};
    cross3(v.fwd, zup, v.right);
    normalize3(v.right);
    cross3(v.right, v.fwd, v.up);
    v.half[1] = tan(0.5 * fov * PI / 180.0);
    v.half[0] = v.half[1] * (double)w / (double)h;
    v.near_ = 0.05 * l->half;
    v.far_ = (dist + 2.0) * l->half;
    return v;
}

void imp_rays(const imp_view *v, int w, int h, hf_ray *rays) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double sx = (2.0 * (x + 0.5) / w - 1.0) * v->half[0];
            double sy = (2.0 * (y + 0.5) / h - 1.0) * v->half[1];
            hf_ray *r = &rays[(size_t)y * w + x];
            for (int k = 0; k < 3; k++) {
                r->origin[k] = (float)v->eye[k];
                r->dir[k] = (float)(v->fwd[k] + sx * v->right[k] + sy * v->up[k]);
            }
            r->t_min = 0.0f;
            r->t_max = INFINITY;
        }
}

/* The world-to-clip matrix of `v` (row-major): clip x, y the view-plane coordinates
 * over the window's half extents, w the forward distance, z mapping [near, far] to
 * [-1, 1]. */
static void view_proj(const imp_view *v, float *m) {
    double a = (v->far_ + v->near_) / (v->far_ - v->near_);
    double b = -2.0 * v->far_ * v->near_ / (v->far_ - v->near_);
    const double *rows[4] = {v->right, v->up, v->fwd, v->fwd};
    double scale[4] = {1.0 / v->half[0], 1.0 / v->half[1], a, 1.0};
    double add[4] = {0, 0, b, 0};
    for (int r = 0; r < 4; r++) {
        double dot = 0;
        for (int k = 0; k < 3; k++) {
            m[4 * r + k] = (float)(scale[r] * rows[r][k]);
            dot += rows[r][k] * v->eye[k];
        }
        m[4 * r + 3] = (float)(add[r] - scale[r] * dot);
    }
}

/* ---- shaders -------------------------------------------------------------------- */

/* The proxies' and the mesh's vertex shader: world positions through `imp_view_proj`. */
static const char *VERTEX =
    "#version 430 core\n"
    "layout(location = 0) in vec3 position;\n"
    "uniform mat4 imp_view_proj;\n"
    "out vec3 v_world;\n"
    "void main() {\n"
    "    v_world = position;\n"
    "    gl_Position = imp_view_proj * vec4(position, 1.0);\n"
    "}\n";

/* The impostor's main: the pixel's ray, hf_trace_impostor, a discard on a miss; then
 * the depth line when the shader has depth output, and the closing brace. */
static const char *IMPOSTOR_MAIN =
    "uniform sampler2D hf_ray_origin, hf_ray_dir;\n"
    "uniform vec3 imp_eye, imp_fwd;\n"
    "uniform uint imp_combine;\n"
    "layout(binding = 0, offset = 0) uniform atomic_uint imp_fragments;\n"
    "in vec3 v_world;\n"
    "layout(location = 0) out vec4 out_point;\n"
    "layout(location = 1) out vec4 out_info;\n"
    "void main() {\n"
    "    atomicCounterIncrement(imp_fragments);\n"
    "    ivec2 px = ivec2(gl_FragCoord.xy);\n"
    "    vec4 o = texelFetch(hf_ray_origin, px, 0);\n"
    "    vec4 d = texelFetch(hf_ray_dir, px, 0);\n"
    "    ImpostorTrace r = hf_trace_impostor(Query(o.xyz, d.xyz, o.w, d.w), imp_combine);\n"
    "    if (!r.trace.has_hit) discard;\n"
    "    vec3 p = r.trace.hit.point;\n"
    "    out_point = vec4(p, r.trace.hit.t);\n"
    "    out_info = vec4(dot(p - imp_eye, imp_fwd), float(r.face), float(r.trace.fetches), 1.0);\n";

/* The mesh's and the plane's: the point and its forward distance (`imp_kind` 1 for the
 * mesh, 2 for the plane). */
static const char *MESH_FRAGMENT =
    "#version 430 core\n"
    "uniform vec3 imp_eye, imp_fwd;\n"
    "uniform float imp_kind;\n"
    "in vec3 v_world;\n"
    "layout(location = 0) out vec4 out_point;\n"
    "layout(location = 1) out vec4 out_info;\n"
    "void main() {\n"
    "    out_point = vec4(v_world, 0.0);\n"
    "    out_info = vec4(dot(v_world - imp_eye, imp_fwd), -1.0, 0.0, imp_kind);\n"
    "}\n";

/* The impostor's fragment shader: the generated library (exact method, triangles,
 * with or without depth output) and the main. */
static char *impostor_source(int depth) {
    hf_scene sc;
    hf_result r = hf_scene_general(HF_METHOD_EXACT, HF_SURFACE_TRIANGLES, &sc);
    if (r != HF_OK) return NULL;
    sc.depth_output = (uint32_t)depth;
    size_t len = 0, written = 0;
    r = hf_shader_generate_impostor_len(&sc, HF_SHADER_GLSL, &len);
    if (r != HF_OK) {
        fail_hf("hf_shader_generate_impostor_len", r);
        return NULL;
    }
    const char *head = "#version 430 core\n";
    const char *depth_line = depth ? "    gl_FragDepth = hf_impostor_depth(p);\n" : "";
    size_t total = strlen(head) + len + strlen(IMPOSTOR_MAIN) + strlen(depth_line) + 3;
    char *src = (char *)malloc(total);
    strcpy(src, head);
    r = hf_shader_generate_impostor(&sc, HF_SHADER_GLSL, src + strlen(head), len, &written);
    if (r != HF_OK) {
        fail_hf("hf_shader_generate_impostor", r);
        free(src);
        return NULL;
    }
    strcat(src, IMPOSTOR_MAIN);
    strcat(src, depth_line);
    strcat(src, "}\n");
    return src;
}

/* ---- GL ------------------------------------------------------------------------- */

int imp_gl_init(imp_gl *g, int w, int h) {
    memset(g, 0, sizeof *g);
    g->w = w;
    g->h = h;
    for (int depth = 0; depth < 2; depth++) {
        char *fs = impostor_source(depth);
        if (!fs) return -1;
        for (int c = 0; c < 2; c++) g->prog[c][depth] = link_shaders(VERTEX, fs);
        free(fs);
    }
    g->prog_mesh = link_shaders(VERTEX, MESH_FRAGMENT);
    glGenVertexArrays(1, &g->vao_box);
    glGenBuffers(1, &g->vbo_box);
    glGenVertexArrays(1, &g->vao_frusta);
    glGenBuffers(1, &g->vbo_frusta);
    glGenVertexArrays(1, &g->vao_mesh);
    glGenBuffers(1, &g->vbo_mesh);
    glGenBuffers(1, &g->ibo_mesh);
    g->tex_point = make_texture(GL_RGBA32F, w, h, GL_RGBA, GL_FLOAT, NULL);
    g->tex_info = make_texture(GL_RGBA32F, w, h, GL_RGBA, GL_FLOAT, NULL);
    glGenRenderbuffers(1, &g->rb_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, g->rb_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    glGenFramebuffers(1, &g->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->tex_point, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, g->tex_info, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g->rb_depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        fprintf(stderr, "impostor frame buffer incomplete\n");
        return -1;
    }
    glGenBuffers(1, &g->counter);
    glBindBuffer(GL_ATOMIC_COUNTER_BUFFER, g->counter);
    glBufferData(GL_ATOMIC_COUNTER_BUFFER, sizeof(GLuint), NULL, GL_DYNAMIC_COPY);
    return 0;
}

void imp_gl_free(imp_gl *g) {
    for (int c = 0; c < 2; c++)
        for (int d = 0; d < 2; d++) glDeleteProgram(g->prog[c][d]);
    glDeleteProgram(g->prog_mesh);
    GLuint vaos[3] = {g->vao_box, g->vao_frusta, g->vao_mesh};
    GLuint bufs[5] = {g->vbo_box, g->vbo_frusta, g->vbo_mesh, g->ibo_mesh, g->counter};
    glDeleteVertexArrays(3, vaos);
    glDeleteBuffers(5, bufs);
    GLuint tex[5] = {g->tex_fields, g->tex_origin, g->tex_dir, g->tex_point, g->tex_info};
    glDeleteTextures(5, tex);
    glDeleteRenderbuffers(1, &g->rb_depth);
    glDeleteFramebuffers(1, &g->fbo);
}

/* The 36 vertices (12 outward-wound triangles) of the hexahedron of `corners`
 * (corner k at bit 0: x, bit 1: y, bit 2: z of its unit cube) into `out`. */
static void hexahedron(const double corners[8][3], float *out) {
    /* Each face: four corners counter-clockwise seen from outside. */
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    static const int split[6] = {0, 1, 2, 0, 2, 3};
    int n = 0;
    for (int f = 0; f < 6; f++)
        for (int k = 0; k < 6; k++) {
            const double *c = corners[faces[f][split[k]]];
            for (int a = 0; a < 3; a++) out[n++] = (float)c[a];
        }
}

/* Uploads `count` vertices of 3 floats to vao/vbo (attribute 0). */
static void upload_positions(GLuint vao, GLuint vbo, const float *v, size_t count) {
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(count * 3 * sizeof(float)), v, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
}

void imp_gl_set_mesh(imp_gl *g, const imp_mesh *m) {
    glBindVertexArray(g->vao_mesh);
    upload_positions(g->vao_mesh, g->vbo_mesh, m->pos, m->nv);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ibo_mesh);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(m->nt * 3 * sizeof(uint32_t)), m->tri,
                 GL_STATIC_DRAW);
    g->mesh_indices = (GLsizei)(3 * m->nt);
    glBindVertexArray(0);
}

void imp_gl_set_fields(imp_gl *g, const imp_fields *f) {
    if (g->tex_fields) glDeleteTextures(1, &g->tex_fields);
    g->tex_fields = make_texture(GL_R32F, (int)f->side, 6 * (int)f->side, GL_RED, GL_FLOAT,
                                 f->heights);
    /* The clipped proxy: the layout's cube, every face's frustum clipped by the box the
     * trace clips the ray to. */
    double corners[8][3];
    for (int k = 0; k < 8; k++)
        for (int a = 0; a < 3; a++)
            corners[k][a] = f->layout.center[a] + ((k >> a & 1) ? 1.0 : -1.0) * f->layout.half;
    float box[36 * 3];
    hexahedron(corners, box);
    upload_positions(g->vao_box, g->vbo_box, box, 36);
    /* The unclipped proxies: each face's frustum, its footprint times the heights of its
     * region (HF_IMPOSTOR_FLOOR to side - 1), mapped back to the world. */
    double floor_z = HF_IMPOSTOR_FLOOR / (double)(f->side - 1);
    float frusta[6 * 36 * 3];
    for (int k = 0; k < 6; k++) {
        double inv[16];
        invert4(f->layout.units[k], inv);
        for (int c = 0; c < 8; c++) {
            double u[4] = {c & 1, c >> 1 & 1, (c >> 2 & 1) ? 1.0 : floor_z, 1.0}, x[4];
            for (int r = 0; r < 4; r++)
                x[r] = inv[4 * r] * u[0] + inv[4 * r + 1] * u[1] + inv[4 * r + 2] * u[2] +
                       inv[4 * r + 3] * u[3];
            for (int a = 0; a < 3; a++) corners[c][a] = x[a] / x[3];
        }
        hexahedron(corners, frusta + k * 36 * 3);
    }
    upload_positions(g->vao_frusta, g->vbo_frusta, frusta, 6 * 36);
    glBindVertexArray(0);
}

void imp_gl_set_rays(imp_gl *g, const hf_ray *rays) {
    size_t n = (size_t)g->w * g->h;
    float *o = (float *)malloc(n * 4 * sizeof(float));
    float *d = (float *)malloc(n * 4 * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        memcpy(o + 4 * i, rays[i].origin, 3 * sizeof(float));
        memcpy(d + 4 * i, rays[i].dir, 3 * sizeof(float));
        o[4 * i + 3] = rays[i].t_min;
        d[4 * i + 3] = rays[i].t_max;
    }
    if (g->tex_origin) glDeleteTextures(1, &g->tex_origin);
    if (g->tex_dir) glDeleteTextures(1, &g->tex_dir);
    g->tex_origin = make_texture(GL_RGBA32F, g->w, g->h, GL_RGBA, GL_FLOAT, o);
    g->tex_dir = make_texture(GL_RGBA32F, g->w, g->h, GL_RGBA, GL_FLOAT, d);
    free(o);
    free(d);
}

/* Binds the frame buffer, clears it when asked, and sets the view's uniforms of `p`. */
static void begin(imp_gl *g, GLuint p, const imp_view *v, int clear) {
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, bufs);
    glViewport(0, 0, g->w, g->h);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    if (clear) {
        const float none[4] = {0, 0, 0, -1}, info[4] = {-1, -1, 0, 0};
        glClearBufferfv(GL_COLOR, 0, none);
        glClearBufferfv(GL_COLOR, 1, info);
        glClear(GL_DEPTH_BUFFER_BIT);
    }
    glUseProgram(p);
    float m[16], eye[3], fwd[3];
    view_proj(v, m);
    for (int k = 0; k < 3; k++) {
        eye[k] = (float)v->eye[k];
        fwd[k] = (float)v->fwd[k];
    }
    glUniformMatrix4fv(glGetUniformLocation(p, "imp_view_proj"), 1, GL_TRUE, m);
    glUniform3fv(glGetUniformLocation(p, "imp_eye"), 1, eye);
    glUniform3fv(glGetUniformLocation(p, "imp_fwd"), 1, fwd);
}

imp_stats imp_gl_draw(imp_gl *g, const imp_fields *f, const imp_view *v, uint32_t combine,
                      int depth, int clipped, int clear) {
    GLuint p = g->prog[combine ? 1 : 0][depth ? 1 : 0];
    begin(g, p, v, clear);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g->tex_fields);
    glUniform1i(glGetUniformLocation(p, "hf_heights"), 0);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, g->tex_origin);
    glUniform1i(glGetUniformLocation(p, "hf_ray_origin"), 1);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, g->tex_dir);
    glUniform1i(glGetUniformLocation(p, "hf_ray_dir"), 2);
    glUniform2i(glGetUniformLocation(p, "hf_size"), (int)f->side, (int)f->side);
    glUniform2fv(glGetUniformLocation(p, "hf_field_ranges"), 6, &f->ranges[0][0]);
    glUniform4fv(glGetUniformLocation(p, "hf_impostor_maps"), 24, &f->maps[0][0]);
    glUniform4fv(glGetUniformLocation(p, "hf_impostor_inverses"), 24, &f->inverses[0][0]);
    float cube[4] = {(float)f->layout.center[0], (float)f->layout.center[1],
                     (float)f->layout.center[2], (float)f->layout.half};
    glUniform4fv(glGetUniformLocation(p, "hf_impostor_cube"), 1, cube);
    glUniform1ui(glGetUniformLocation(p, "imp_combine"), combine);
    if (depth) {
        float m[16];
        view_proj(v, m);
        glUniform4fv(glGetUniformLocation(p, "hf_view_proj"), 4, m);
    }
    GLuint zero = 0;
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, g->counter);
    glBufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof zero, &zero);
    glFinish();
    double t0 = now_seconds();
    glBindVertexArray(clipped ? g->vao_box : g->vao_frusta);
    glDrawArrays(GL_TRIANGLES, 0, clipped ? 36 : 6 * 36);
    glFinish();
    imp_stats s = {1e3 * (now_seconds() - t0), 0};
    glGetBufferSubData(GL_ATOMIC_COUNTER_BUFFER, 0, sizeof s.fragments, &s.fragments);
    glBindVertexArray(0);
    return s;
}

imp_stats imp_gl_draw_mesh(imp_gl *g, const imp_view *v, int clear) {
    begin(g, g->prog_mesh, v, clear);
    glDisable(GL_CULL_FACE); /* the scan's winding is not consistent */
    glUniform1f(glGetUniformLocation(g->prog_mesh, "imp_kind"), 1.0f);
    glFinish();
    double t0 = now_seconds();
    glBindVertexArray(g->vao_mesh);
    glDrawElements(GL_TRIANGLES, g->mesh_indices, GL_UNSIGNED_INT, NULL);
    glFinish();
    imp_stats s = {1e3 * (now_seconds() - t0), 0};
    glBindVertexArray(0);
    return s;
}

void imp_gl_draw_plane(imp_gl *g, const imp_view *v, const imp_mesh *m, double z) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < m->nv; i++)
        for (int a = 0; a < 2; a++) {
            lo[a] = fmin(lo[a], m->pos[3 * i + a]);
            hi[a] = fmax(hi[a], m->pos[3 * i + a]);
        }
    double wx = 0.3 * (hi[0] - lo[0]), wy = 0.3 * (hi[1] - lo[1]);
    float q[6 * 3] = {
        (float)(lo[0] - wx), (float)(lo[1] - wy), (float)z, (float)(hi[0] + wx), (float)(lo[1] - wy), (float)z,
        (float)(hi[0] + wx), (float)(hi[1] + wy), (float)z, (float)(lo[0] - wx), (float)(lo[1] - wy), (float)z,
        (float)(hi[0] + wx), (float)(hi[1] + wy), (float)z, (float)(lo[0] - wx), (float)(hi[1] + wy), (float)z,
    };
    GLuint vao, vbo;
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &vbo);
    upload_positions(vao, vbo, q, 6);
    begin(g, g->prog_mesh, v, 0);
    glDisable(GL_CULL_FACE);
    glUniform1f(glGetUniformLocation(g->prog_mesh, "imp_kind"), 2.0f);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glFinish();
    glBindVertexArray(0);
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(1, &vbo);
}

void imp_gl_read(imp_gl *g, float *point, float *info) {
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, g->w, g->h, GL_RGBA, GL_FLOAT, point);
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, g->w, g->h, GL_RGBA, GL_FLOAT, info);
}

/* ---- checks --------------------------------------------------------------------- */

imp_check imp_check_cpu(const imp_fields *f, uint32_t combine, const hf_ray *rays, size_t n,
                        const float *point, const float *info) {
    imp_check c;
    memset(&c, 0, sizeof c);
    c.pixels = (int)n;
    hf_hit *hits = (hf_hit *)malloc(n * sizeof *hits);
    uint32_t *faces = (uint32_t *)malloc(n * sizeof *faces);
    size_t len = 6 * (size_t)f->side * f->side;
    double t0 = now_seconds();
    hf_result r = hf_impostor_trace_batch(&f->layout, f->heights, len, f->side,
                                          HF_SURFACE_TRIANGLES, combine, rays, n, hits, n,
                                          faces, n);
    c.cpu_ms = 1e3 * (now_seconds() - t0);
    if (r != HF_OK) {
        fail_hf("hf_impostor_trace_batch", r);
        c.differ = c.pixels;
        free(hits);
        free(faces);
        return c;
    }
    for (size_t i = 0; i < n; i++) {
        int cpu = hits[i].hit != 0, gpu = info[4 * i + 3] == 1.0f;
        c.hits += cpu;
        if (cpu != gpu) {
            c.differ++;
            c.hit_differ++;
            continue;
        }
        if (!cpu) continue;
        double d = 0;
        for (int k = 0; k < 3; k++) {
            double e = (double)hits[i].point[k] - (double)point[4 * i + k];
            d += e * e;
        }
        d = sqrt(d) / f->layout.half;
        c.max_err = d > c.max_err ? d : c.max_err;
        if (d > 1e-3) c.differ++;
        if ((float)faces[i] != info[4 * i + 1]) c.face_differ++;
    }
    free(hits);
    free(faces);
    return c;
}

int imp_check_ok(const imp_check *c) {
    return c->hits > 0 && (double)c->differ <= 1e-4 * (double)c->pixels;
}

imp_error imp_against_mesh(const float *info, const float *mesh_info, size_t n, double half) {
    imp_error e = {0, 0, 0.0, 0.0};
    int both = 0;
    for (size_t i = 0; i < n; i++) {
        int a = info[4 * i + 3] == 1.0f, b = mesh_info[4 * i + 3] == 1.0f;
        e.mesh_pixels += b;
        if (a != b) {
            e.differ++;
            continue;
        }
        if (!a) continue;
        double d = fabs((double)info[4 * i] - (double)mesh_info[4 * i]) / half;
        e.depth_mean += d;
        e.depth_max = d > e.depth_max ? d : e.depth_max;
        both++;
    }
    if (both) e.depth_mean /= both;
    return e;
}
