/* A costing probe for issue 21, not a method: what Embree's own design costs on a height
 * field. The 16 rays of a 4 x 4 pixel tile descend a quadtree of cell tops (a maximum
 * mipmap, built here) together, front to back: every node is tested against every live
 * ray (its slabs and its top, in AVX-512), a node's four children at once; a leaf cell
 * gets a plain f32 test against its two triangles. Nothing is exact here (no margins,
 * no rounding argument, lanes whose direction's signs differ from the tile's first ray
 * are visited in its order): its hits are only compared with hfcast's exact ones
 * (`agree`: the same hit or miss and t within 10⁻³ relative), and its cost with
 * Embree's 8-ray packets over the same triangles, in the same run.
 *
 * Two runs per ray set:
 * - from the root, as a BVH traversal starts;
 * - with oracle starts: each ray starts `back` cells (horizontally) before hfcast's
 *   exact hit, and the tile enters the quadtree at the nodes of level `level` (2^level
 *   cells a side) its rays cross from there, listed before the timing. A bound on what
 *   a start as tight as the horizon's could give this traversal.
 * Each prints ns per ray and, per ray, the tile-wide node tests, leaves and lane tests
 * at leaves.
 *
 * Usage: packet_cost [MAP [sets [back [level]]]]  (MAP as embree_bench; sets: digits of
 * the ray sets, default 0123, the four cameras; back 10 cells, level 2). Built by
 * `make -C c_tests packet-cost` (after scripts/embree_bench.sh installed Embree).
 * It reuses embree_bench.c's fields, cameras and Embree scene: that file is included
 * with its main renamed. */
#define main embree_bench_main
#include "embree_bench.c"
#undef main
#include <immintrin.h>

/* The rays of a tile: 4 x 4 pixels. */
#define TILE_W 4
#define TILE_H 4
#define LANES (TILE_W * TILE_H)

/* The most entry nodes a tile may list (its rays' segments may cross the field). */
#define ENTRY_CAP 4096

/* The quadtree: level 0 is the cells' tops (the highest of their four corners), padded
 * with -inf to a power of two; level k + 1 the largest of four of level k. */
typedef struct pyramid {
    int levels;
    uint32_t side[32];
    float *top[32];
} pyramid;

/* The quadtree of `fd`'s cells. */
static pyramid build_pyramid(const field_data *fd) {
    pyramid p;
    uint32_t n = 1;
    while (n < fd->w - 1 || n < fd->h - 1) n *= 2;
    p.side[0] = n;
    p.top[0] = (float *)malloc(sizeof(float) * n * n);
    for (uint32_t y = 0; y < n; y++) {
        for (uint32_t x = 0; x < n; x++) {
            float m = -INFINITY;
            if (x + 1 < fd->w && y + 1 < fd->h) {
                const float *r0 = fd->heights + (size_t)y * fd->w + x, *r1 = r0 + fd->w;
                m = fmaxf(fmaxf(r0[0], r0[1]), fmaxf(r1[0], r1[1]));
            }
            p.top[0][(size_t)y * n + x] = m;
        }
    }
    p.levels = 1;
    while (p.side[p.levels - 1] > 1) {
        int k = p.levels++;
        uint32_t s = p.side[k - 1] / 2;
        const float *below = p.top[k - 1];
        p.side[k] = s;
        p.top[k] = (float *)malloc(sizeof(float) * s * s);
        for (uint32_t y = 0; y < s; y++) {
            for (uint32_t x = 0; x < s; x++) {
                size_t a = (size_t)(2 * y) * (2 * s) + 2 * x;
                p.top[k][(size_t)y * s + x] = fmaxf(fmaxf(below[a], below[a + 1]),
                                                    fmaxf(below[a + 2 * s], below[a + 2 * s + 1]));
            }
        }
    }
    return p;
}

/* A node: its level and position at that level. */
typedef struct node {
    int level, x, y;
} node;

/* A node whose test passed: its live lanes and their entry and exit t. */
typedef struct passed {
    node n;
    __mmask16 live;
    __m512 t_in, t_out;
} passed;

/* A tile's rays, lane by lane. */
typedef struct tile {
    float o[3][LANES], d[3][LANES], inv[2][LANES], t0[LANES], hit[LANES];
    size_t index[LANES];
} tile;

/* A tile's rays as vectors, for the node tests. */
typedef struct vectors {
    __m512 inv_x, inv_y, ox_inv, oy_inv, oz, dz, t0;
    __mmask16 rising;
} vectors;

/* An entry node of a tile's traversal, and the lanes it enters for. */
typedef struct entry {
    node n;
    __mmask16 lanes;
} entry;

/* The counts of a run. */
typedef struct counts {
    size_t node_tests, leaves, lane_tests;
} counts;

/* The test of node `n` against the tile's rays (`t_hit` their hits so far): the lanes
 * whose segment over the node's footprint reaches down to its top. */
__attribute__((target("avx512f,fma"))) static inline __mmask16 node_test(
    const pyramid *p, const field_data *fd, const vectors *v, node n, __m512 t_hit,
    __m512 *t_in, __m512 *t_out) {
    float x0 = (float)((uint32_t)n.x << n.level), y0 = (float)((uint32_t)n.y << n.level);
    /* (Plain comparisons: fminf is a library call where NaN rules apply.) */
    float x1 = (float)((uint32_t)(n.x + 1) << n.level), y1 = (float)((uint32_t)(n.y + 1) << n.level);
    x1 = x1 < (float)(fd->w - 1) ? x1 : (float)(fd->w - 1);
    y1 = y1 < (float)(fd->h - 1) ? y1 : (float)(fd->h - 1);
    if (x0 >= x1 || y0 >= y1) return 0;
    float top = p->top[n.level][(size_t)n.y * p->side[n.level] + n.x];
    __m512 a = _mm512_fmsub_ps(_mm512_set1_ps(x0), v->inv_x, v->ox_inv);
    __m512 b = _mm512_fmsub_ps(_mm512_set1_ps(x1), v->inv_x, v->ox_inv);
    __m512 c = _mm512_fmsub_ps(_mm512_set1_ps(y0), v->inv_y, v->oy_inv);
    __m512 d = _mm512_fmsub_ps(_mm512_set1_ps(y1), v->inv_y, v->oy_inv);
    __m512 in = _mm512_max_ps(_mm512_max_ps(_mm512_min_ps(a, b), _mm512_min_ps(c, d)), v->t0);
    __m512 out = _mm512_min_ps(_mm512_min_ps(_mm512_max_ps(a, b), _mm512_max_ps(c, d)), t_hit);
    __m512 low = _mm512_fmadd_ps(v->dz, _mm512_mask_blend_ps(v->rising, out, in), v->oz);
    *t_in = in;
    *t_out = out;
    return _mm512_cmp_ps_mask(in, out, _CMP_LE_OQ) &
           _mm512_cmp_ps_mask(low, _mm512_set1_ps(top), _CMP_LE_OQ);
}

/* The live lanes' f32 test of leaf cell (cx, cy) over [t_in, t_out]: entering under the
 * surface (a side wall) or crossing one of its two triangles, cut along the diagonal
 * whose midpoint is lower. */
static void leaf_test(const field_data *fd, tile *t, uint32_t cx, uint32_t cy, __mmask16 live,
                      const float *t_in, const float *t_out, counts *c) {
    const float *r0 = fd->heights + (size_t)cy * fd->w + cx, *r1 = r0 + fd->w;
    float c0 = r0[0], c1 = r0[1], c2 = r1[0], c3 = r1[1];
    int main_diagonal = c0 + c3 <= c1 + c2;
    /* Planes h0 + gu u + gv v of the triangle under (u >= v, or u + v <= 1) and the other. */
    float pa[3] = {c0, c1 - c0, main_diagonal ? c3 - c1 : c2 - c0};
    float pb[3] = {main_diagonal ? c0 : c1 + c2 - c3, c3 - c2, main_diagonal ? c2 - c0 : c3 - c1};
    for (int l = 0; l < LANES; l++) {
        if (!(live >> l & 1)) continue;
        c->lane_tests++;
        float u0 = t->o[0][l] - (float)cx, v0 = t->o[1][l] - (float)cy;
        float ue = u0 + t_in[l] * t->d[0][l], ve = v0 + t_in[l] * t->d[1][l];
        int first = main_diagonal ? ue >= ve : ue + ve <= 1.0f;
        const float *pe = first ? pa : pb;
        if (t->o[2][l] + t_in[l] * t->d[2][l] <= pe[0] + pe[1] * ue + pe[2] * ve) {
            if (t_in[l] < t->hit[l]) t->hit[l] = t_in[l];
            continue;
        }
        for (int k = 0; k < 2; k++) {
            const float *q = k ? pb : pa;
            float den = t->d[2][l] - q[1] * t->d[0][l] - q[2] * t->d[1][l];
            float s = (q[0] + q[1] * u0 + q[2] * v0 - t->o[2][l]) / den;
            if (!(s >= t_in[l] && s <= t_out[l])) continue;
            float u = u0 + s * t->d[0][l], v = v0 + s * t->d[1][l];
            int inside = main_diagonal ? (k == 0 ? u >= v : v >= u)
                                       : (k == 0 ? u + v <= 1.0f : u + v >= 1.0f);
            if (inside && s < t->hit[l]) t->hit[l] = s;
        }
    }
}

/* The traversal of one tile from `entries` (nodes listed far first, each for some of
 * the lanes): each passed node popped, its lanes checked against their hits so far, a
 * leaf tested, else its four children tested, the nearer pushed last. */
__attribute__((target("avx512f,fma"))) static void traverse(const pyramid *p,
                                                            const field_data *fd, tile *t,
                                                            const entry *entries, int n,
                                                            counts *c) {
    /* (Static: 800 KiB; one tile at a time.) */
    static passed stack[4 * 32 + ENTRY_CAP];
    int sp = 0;
    vectors v;
    v.inv_x = _mm512_loadu_ps(t->inv[0]);
    v.inv_y = _mm512_loadu_ps(t->inv[1]);
    v.ox_inv = _mm512_mul_ps(_mm512_loadu_ps(t->o[0]), v.inv_x);
    v.oy_inv = _mm512_mul_ps(_mm512_loadu_ps(t->o[1]), v.inv_y);
    v.oz = _mm512_loadu_ps(t->o[2]);
    v.dz = _mm512_loadu_ps(t->d[2]);
    v.t0 = _mm512_loadu_ps(t->t0);
    v.rising = _mm512_cmp_ps_mask(v.dz, _mm512_setzero_ps(), _CMP_GT_OQ);
    __m512 t_hit = _mm512_loadu_ps(t->hit);
    for (int k = 0; k < n; k++) {
        passed e = {entries[k].n, 0, _mm512_setzero_ps(), _mm512_setzero_ps()};
        e.live = entries[k].lanes & node_test(p, fd, &v, e.n, t_hit, &e.t_in, &e.t_out);
        c->node_tests++;
        if (e.live) stack[sp++] = e;
    }
    int near_x = t->d[0][0] > 0 ? 0 : 1, near_y = t->d[1][0] > 0 ? 0 : 1;
    while (sp > 0) {
        passed e = stack[--sp];
        __mmask16 live = e.live & _mm512_cmp_ps_mask(e.t_in, t_hit, _CMP_LE_OQ);
        if (!live) continue;
        if (e.n.level == 0) {
            float t_in[LANES], t_out[LANES];
            _mm512_storeu_ps(t_in, e.t_in);
            _mm512_storeu_ps(t_out, _mm512_min_ps(e.t_out, t_hit));
            c->leaves++;
            leaf_test(fd, t, (uint32_t)e.n.x, (uint32_t)e.n.y, live, t_in, t_out, c);
            t_hit = _mm512_loadu_ps(t->hit);
            continue;
        }
        int level = e.n.level - 1, x = 2 * e.n.x, y = 2 * e.n.y;
        node children[4] = {{level, x + 1 - near_x, y + 1 - near_y},
                            {level, x + 1 - near_x, y + near_y},
                            {level, x + near_x, y + 1 - near_y},
                            {level, x + near_x, y + near_y}};
        for (int k = 0; k < 4; k++) {
            passed ch = {children[k], 0, _mm512_setzero_ps(), _mm512_setzero_ps()};
            ch.live = live & node_test(p, fd, &v, ch.n, t_hit, &ch.t_in, &ch.t_out);
            if (ch.live) stack[sp++] = ch;
        }
        c->node_tests += 4;
    }
}

/* The tile of pixels (px, py).. of `rays` (a BENCH_W-wide image), each ray starting
 * `back` cells before its exact hit in `exact` (0 for none: from t = 0). */
static void load_tile(tile *t, const hf_ray *rays, const hf_hit *exact, uint32_t px,
                      uint32_t py, float back) {
    for (int l = 0; l < LANES; l++) {
        size_t i = (size_t)(py + l / TILE_W) * BENCH_W + px + l % TILE_W;
        t->index[l] = i;
        for (int k = 0; k < 3; k++) {
            t->o[k][l] = rays[i].origin[k];
            t->d[k][l] = rays[i].dir[k];
        }
        t->inv[0][l] = 1.0f / t->d[0][l];
        t->inv[1][l] = 1.0f / t->d[1][l];
        t->hit[l] = INFINITY;
        float along = sqrtf(t->d[0][l] * t->d[0][l] + t->d[1][l] * t->d[1][l]);
        t->t0[l] = back > 0 && exact[i].hit ? fmaxf(0.0f, exact[i].t - back / along) : 0.0f;
    }
}

/* The entries of a tile with oracle starts: the nodes of `level` that its hitting rays
 * cross from their starts to their exact hits, far first along the first ray, for
 * those rays; then the root for the others (at most `cap` in all). */
static int entry_nodes(const pyramid *p, const field_data *fd, const tile *t,
                       const hf_hit *exact, int level, entry *out, int cap) {
    int n = 0;
    double side = (double)(1u << level);
    __mmask16 hitting = 0;
    for (int l = 0; l < LANES; l++) {
        const hf_hit *h = &exact[t->index[l]];
        if (!h->hit) continue;
        hitting |= (__mmask16)(1u << l);
        double t_end = h->t;
        /* Points every quarter node along the segment: enough for a costing. */
        double along = sqrt((double)t->d[0][l] * t->d[0][l] + (double)t->d[1][l] * t->d[1][l]);
        double dt = side / 4.0 / along;
        for (double s = t->t0[l]; s <= t_end + dt; s += dt) {
            double u = fmin(s, t_end);
            double x = t->o[0][l] + u * t->d[0][l], y = t->o[1][l] + u * t->d[1][l];
            /* Clamped into the field: a hit on a side wall lies on its edge. */
            x = fmin(fmax(x, 0.0), fd->w - 1.5);
            y = fmin(fmax(y, 0.0), fd->h - 1.5);
            node e = {level, (int)(x / side), (int)(y / side)};
            int seen = 0;
            for (int k = 0; k < n && !seen; k++) seen = out[k].n.x == e.x && out[k].n.y == e.y;
            if (!seen && n < cap - 1) out[n++] = (entry){e, 0};
        }
    }
    /* Far first: by the centre's distance along the first ray. */
#define ALONG(e) (((e).n.x + 0.5) * side - t->o[0][0]) * t->d[0][0] + \
                     (((e).n.y + 0.5) * side - t->o[1][0]) * t->d[1][0]
    for (int a = 1; a < n; a++) {
        entry e = out[a];
        int b = a;
        while (b > 0 && ALONG(out[b - 1]) < ALONG(e)) {
            out[b] = out[b - 1];
            b--;
        }
        out[b] = e;
    }
#undef ALONG
    for (int k = 0; k < n; k++) out[k].lanes = hitting;
    if (hitting != 0xffff) out[n++] = (entry){{p->levels - 1, 0, 0}, (__mmask16)~hitting};
    return n;
}

/* One run over the image: the best of `reps` timings (ns per ray), its counts, and the
 * share of rays agreeing with `exact`. With `back` > 0, the oracle starts and entries at
 * `level`, listed before the timing. */
static double run(const pyramid *p, const field_data *fd, const hf_ray *rays,
                  const hf_hit *exact, float back, int level, int reps, counts *c,
                  double *agree) {
    uint32_t tiles_x = BENCH_W / TILE_W, tiles = tiles_x * (BENCH_H / TILE_H);
    size_t *first = (size_t *)malloc(sizeof(size_t) * (tiles + 1));
    size_t cap = (size_t)tiles * 4, len = 0;
    entry *entries = (entry *)malloc(sizeof(entry) * cap);
    entry *listed = (entry *)malloc(sizeof(entry) * ENTRY_CAP);
    tile *loaded = (tile *)malloc(sizeof(tile) * tiles);
    for (uint32_t k = 0; k < tiles; k++) {
        tile *t = &loaded[k];
        load_tile(t, rays, exact, k % tiles_x * TILE_W, k / tiles_x * TILE_H, back);
        int m = 1;
        if (back > 0) {
            m = entry_nodes(p, fd, t, exact, level, listed, ENTRY_CAP);
        } else {
            listed[0] = (entry){{p->levels - 1, 0, 0}, 0xffff};
        }
        if (len + (size_t)m > cap) {
            cap = 2 * (len + (size_t)m);
            entries = (entry *)realloc(entries, sizeof(entry) * cap);
        }
        first[k] = len;
        memcpy(&entries[len], listed, sizeof(entry) * (size_t)m);
        len += (size_t)m;
    }
    first[tiles] = len;
    float *t_hit = (float *)malloc(sizeof(float) * BENCH_W * BENCH_H);
    double best = INFINITY;
    for (int rep = 0; rep < reps; rep++) {
        counts now_counts = {0, 0, 0};
        double t0 = now();
        for (uint32_t k = 0; k < tiles; k++) {
            tile t = loaded[k];
            traverse(p, fd, &t, &entries[first[k]], (int)(first[k + 1] - first[k]), &now_counts);
            for (int l = 0; l < LANES; l++) t_hit[t.index[l]] = t.hit[l];
        }
        double ns = (now() - t0) * 1e9 / ((double)BENCH_W * BENCH_H);
        if (ns < best) best = ns;
        *c = now_counts;
    }
    size_t same = 0;
    for (size_t i = 0; i < (size_t)BENCH_W * BENCH_H; i++) {
        int a = exact[i].hit, b = isfinite(t_hit[i]);
        same += a == b && (!a || fabsf(exact[i].t - t_hit[i]) <= 1e-3f * exact[i].t + 1e-3f);
    }
    *agree = (double)same / ((double)BENCH_W * BENCH_H);
    free(t_hit);
    free(loaded);
    free(listed);
    free(first);
    free(entries);
    return best;
}

int main(int argc, char **argv) {
    const char *map = argc > 1 ? argv[1] : "../../shared/data/dem_etopo5_himalaya_1024.png";
    const char *sets = argc > 2 ? argv[2] : "0123";
    float back = argc > 3 ? (float)atof(argv[3]) : 10.0f;
    int level = argc > 4 ? atoi(argv[4]) : 2;
    if (!__builtin_cpu_supports("avx512f")) {
        printf("packet_cost: needs AVX-512\n");
        return 0;
    }
    field_data fd;
    if (!field_load(map, &fd)) {
        fprintf(stderr, "cannot read %s\n", map);
        return 2;
    }
    RTCDevice dev = rtcNewDevice(NULL);
    RTCScene scene = embree_scene(dev, fd.heights, fd.w, fd.h, fd.zmin - WALL_DEPTH,
                                  RTC_SCENE_FLAG_NONE);
    pyramid p = build_pyramid(&fd);
    size_t n = (size_t)BENCH_W * BENCH_H;
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * n);
    hf_hit *exact = (hf_hit *)malloc(sizeof(hf_hit) * n);
    float *embree_t = (float *)malloc(sizeof(float) * n);
    printf("%s: 4 x 4 tiles; oracle starts %.0f cells before the hit, entering at nodes of "
           "%u cells a side\n", map, back, 1u << level);
    for (const char *s = sets; *s; s++) {
        int k = *s - '0';
        if (k < 0 || k >= CAMERA_SETS) continue;
        char name[200];
        ray_set(&fd, k, BENCH_W, BENCH_H, rays, name, sizeof name);
        check_hf("hf_trace_batch", hf_trace_batch(fd.field, HF_METHOD_EXACT, NULL, 0, NULL,
                                                  rays, n, exact, n));
        double e_best = INFINITY;
        for (int rep = 0; rep < 5; rep++) {
            double t0 = now();
            embree_trace(scene, rays, n, BENCH_W, BENCH_H, 1, embree_t);
            e_best = fmin(e_best, (now() - t0) * 1e9 / n);
        }
        counts c;
        double agree;
        double root = run(&p, &fd, rays, exact, 0.0f, 0, 5, &c, &agree);
        printf("%s (%s): embree packets of 8 %.1f ns/ray\n", CAMERAS[k].tag, name, e_best);
        printf("  from the root: %.1f ns/ray (%.2fx embree's); per ray %.2f node tests, "
               "%.2f leaves, %.2f lane tests at leaves; agree %.4f\n",
               root, e_best / root, (double)c.node_tests / n, (double)c.leaves / n,
               (double)c.lane_tests / n, agree);
        double started = run(&p, &fd, rays, exact, back, level, 5, &c, &agree);
        printf("  oracle starts: %.1f ns/ray (%.2fx); per ray %.2f node tests, %.2f leaves, "
               "%.2f lane tests at leaves; agree %.4f\n",
               started, e_best / started, (double)c.node_tests / n, (double)c.leaves / n,
               (double)c.lane_tests / n, agree);
        fflush(stdout);
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    return 0;
}
