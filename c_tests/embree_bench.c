/* hfcast against Embree over the same triangles, on the same rays, in one process.
 *
 * Benchmark (default): hfcast's exact cylinder-cone, maximum-mipmap and
 * safety-distance marches and its DDA against Embree's single rays and 8-ray packets,
 * on one thread each by default, or on as many threads each as its third argument says
 * (wall time per ray; Embree's threads take bands of 8 image rows in turn): the CPU
 * comparison issue 3 asks for ("exact CC hits faster than
 * Embree over the same triangles ... with a few percent of its memory"), with the
 * memory and preprocessing of both. Each run is timed cold (passes running every
 * method in turn: the figures quoted) and warm (its own passes back to back).
 * Check (--check): Embree's watertight mode as an independent oracle of hfcast's exact
 * marches; a C suite of scripts/test.sh.
 *
 * The field: a 16-bit PNG, heights v / 65535 x 0.1 x side, as the Rust benchmarks load
 * it, or a synthetic one of the same relief, synthetic:NAME[:SIDE] (SIDE x SIDE, default
 * 1024; seeded, the same on every run): `fractal`, fBm of value noise over the whole
 * depth (fractal_heights), or `needles`, a low base under one-texel-wide walls and
 * one-texel needles (needles_heights). Both go through hf_field_create_f32 as the
 * PNGs do. Embree gets the field's triangle surface (each cell cut along the diagonal
 * whose midpoint is lower, as hfcast's triangle surface) and the four side walls from
 * the surface's edges far down: for hfcast everything under the surface is solid, so a
 * ray entering the field's footprint through a side under the surface (even under the
 * lowest sample) hits there, and with the walls it does in Embree too.
 *
 * The rays (ray_set; 640 x 512 cameras in the benchmark), all at azimuth 30, each a
 * set with its tag in the speedup lines:
 * - 45deg, 5deg: cameras at 45 and 5 degrees elevation framing the whole box, 40
 *   degrees of vertical field of view, as core/examples/common (camera_rays) computes
 *   them; more than half of their rays leave the box early (issue 21).
 * - filled45deg, filled5deg: the terrain filling the frame: the 40 degree lens from 45
 *   degrees, and a 2 degree telephoto from 5 degrees, its eye outside the box, its
 *   rays grazing across the field. Each is as far back as keeps its corner rays'
 *   meetings with the plane z = zmin inside the footprint, so that every ray meets the
 *   field (camera_rays); the telephoto, whose lower rays would then enter the near side
 *   under the surface, is lifted as far as every ray still hits (ray_set). The set's
 *   name gives the lift and the misses and side hits in hfcast's exact answers.
 * - random: random rays inside the box, any direction (a quarter as many), as
 *   safety_bench (random_rays) computes them. Those that start under the surface are a
 *   hit at t = 0 for hfcast (the solid is solid) but not for a triangle mesh, so only
 *   those that start above it are kept.
 * hfcast traces through its C API (hf_trace_batch with HF_METHOD_CC: the exact CC map,
 * cap 64; HF_METHOD_MAXMIP, by default (a camera's rays share a horizon that starts each
 * ray's march near its hit), and without the horizon in SIMD lanes (AVX-512 or AVX2)
 * where the CPU has them and with HF_SIMD_OFF one ray after another; HF_METHOD_SAFETY:
 * the exact directional safety distances; HF_METHOD_EXACT: the exact DDA, no bake, by default:
 * with the horizon); Embree traces single rays (rtcIntersect1) and, for the cameras,
 * packets of 8 rays from 4 x 2 pixel tiles (rtcIntersect8).
 *
 * The benchmark ends with two lines per set, `speedup over embree-packets <set>: <x>`
 * and `speedup over embree-single <set>: <x>`: x = the best Embree variant's ns per ray
 * (plain or robust) over hfcast's fastest exact method's in the same run.
 *
 * Usage: embree_bench [MAP [reps [threads]]]   (MAP: a PNG or synthetic:NAME[:SIDE];
 *                                     default the Himalaya DEM of ../shared/data at
 *                                     1024², 5 repetitions (medians), 1 thread)
 *        embree_bench --check MAP...
 * Built by `make -C c_tests embree-bench` / `embree-check`; scripts/embree_bench.sh
 * installs libembree-dev, builds the library in release and runs the benchmark (--all:
 * on the Himalaya DEM, synthetic:fractal and synthetic:needles). */
#define _POSIX_C_SOURCE 200112L
#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <time.h>

#include "hfcast.h"
#include "png16.h"

#define CC_CAP 64
#define PI 3.14159265358979323846 /* Rust's f64 PI */
/* How far under the lowest sample the side walls of the Embree mesh reach: the camera
 * rays that enter a side under the surface do so within a few hundred units of it. */
#define WALL_DEPTH 1e5f

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static void check_hf(const char *what, hf_result r) {
    if (r == HF_OK) return;
    fprintf(stderr, "%s failed (%u)\n", what, (unsigned)r);
    exit(2);
}

/* ---- the rays ------------------------------------------------------------------ */

static void direction(double az_deg, double el_deg, double out[3]) {
    double a = az_deg * (PI / 180.0), e = el_deg * (PI / 180.0);
    out[0] = cos(e) * sin(a);
    out[1] = -cos(e) * cos(a);
    out[2] = sin(e);
}

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* A camera of the ray sets: its view from `elevation` degrees above the horizon and
 * `azimuth` degrees, `half_fov` degrees of half its vertical field of view, and its
 * framing. */
typedef struct camera {
    const char *tag; /* the set's name in the speedup lines */
    double elevation, azimuth, half_fov;
    int filled; /* 0: the whole box in view; 1: the terrain fills the frame */
} camera;

/* The rays of `cam`, a `cam_w x cam_h` image. Whole-box framing, the camera of
 * core/examples/common/mod.rs (camera_rays): looking at the box's centre, far enough that
 * the whole box is in view (`zref` unused). Filled framing: looking at the footprint's
 * centre on the plane z = zref, as far back as keeps the four corner rays' meetings with
 * that plane inside the footprint (shrunk by 1%). With zref = zmin every ray meets the
 * field: it descends (half_fov < elevation), and over the footprint the surface is never
 * under zmin, so by the time the ray is down to zmin it is at or under the surface (the
 * rays between the corners meet the plane inside the corners' quadrilateral, convex). */
static void camera_rays(uint32_t fw, uint32_t fh, double zmin, double zmax, const camera *cam,
                        double zref, uint32_t cam_w, uint32_t cam_h, hf_ray *rays) {
    double size[3] = {(double)(fw - 1), (double)(fh - 1), zmax - zmin};
    double tan_y = tan(cam->half_fov * (PI / 180.0));
    double tan_x = tan_y * cam_w / cam_h;
    double to_eye[3], fwd[3], right[3], up[3];
    direction(cam->azimuth, cam->elevation, to_eye);
    for (int k = 0; k < 3; k++) fwd[k] = -to_eye[k];
    direction(cam->azimuth + 270.0, 0.0, right);
    up[0] = fwd[1] * right[2] - fwd[2] * right[1];
    up[1] = fwd[2] * right[0] - fwd[0] * right[2];
    up[2] = fwd[0] * right[1] - fwd[1] * right[0];
    double target[3] = {size[0] / 2.0, size[1] / 2.0, zmin + size[2] / 2.0};
    double dist = 1e-3;
    if (!cam->filled) {
        for (int corner = 0; corner < 8; corner++) {
            double c[3];
            for (int k = 0; k < 3; k++) c[k] = size[k] * ((double)((corner >> k) & 1) - 0.5);
            double need_x = fabs(dot3(c, right)) / tan_x - dot3(c, fwd);
            double need_y = fabs(dot3(c, up)) / tan_y - dot3(c, fwd);
            dist = fmax(dist, fmax(need_x, need_y));
        }
        dist *= 1.05;
    } else {
        /* The eye at target + dist x to_eye; corner ray c meets the plane after
         * s = dist x to_eye_z / -c_z, at target + dist x (to_eye + to_eye_z / -c_z x c):
         * horizontally linear in dist, so each bound gives dist directly. */
        target[2] = zref;
        dist = INFINITY;
        for (int corner = 0; corner < 4; corner++) {
            double c[3];
            for (int k = 0; k < 3; k++) {
                c[k] = fwd[k] + (corner & 1 ? tan_x : -tan_x) * right[k] +
                       (corner & 2 ? tan_y : -tan_y) * up[k];
            }
            for (int k = 0; k < 2; k++) {
                double v = to_eye[k] + to_eye[2] / -c[2] * c[k];
                if (v != 0.0) dist = fmin(dist, 0.99 * (size[k] / 2.0) / fabs(v));
            }
        }
    }
    float eye[3];
    for (int k = 0; k < 3; k++) eye[k] = (float)(target[k] + dist * to_eye[k]);
    for (uint32_t py = 0; py < cam_h; py++) {
        for (uint32_t px = 0; px < cam_w; px++) {
            double sx = 2.0 * (px + 0.5) / cam_w - 1.0;
            double sy = 1.0 - 2.0 * (py + 0.5) / cam_h;
            hf_ray *r = &rays[(size_t)py * cam_w + px];
            for (int k = 0; k < 3; k++) {
                r->origin[k] = eye[k];
                r->dir[k] = (float)(fwd[k] + sx * tan_x * right[k] + sy * tan_y * up[k]);
            }
            r->t_min = 0.0f;
            r->t_max = INFINITY;
        }
    }
}

/* The random rays of core/examples/safety_bench.rs (random_rays): origins uniform in
 * the box, directions uniform on the sphere, from a xorshift generator. */
static void random_rays(uint32_t fw, uint32_t fh, double zmin, double zmax, size_t n,
                        uint64_t seed, hf_ray *rays) {
    uint64_t x = (seed * 0x9e3779b97f4a7c15ull) | 1;
#define NEXT() (x ^= x << 13, x ^= x >> 7, x ^= x << 17, (double)(x >> 11) / 9007199254740992.0)
    for (size_t i = 0; i < n; i++) {
        double o[3], d[3];
        o[0] = NEXT() * (fw - 1);
        o[1] = NEXT() * (fh - 1);
        o[2] = zmin + NEXT() * (zmax - zmin);
        double z = 2.0 * NEXT() - 1.0;
        double a = NEXT() * 2.0 * PI;
        double s = sqrt(1.0 - z * z);
        d[0] = s * cos(a);
        d[1] = s * sin(a);
        d[2] = z;
        for (int k = 0; k < 3; k++) {
            rays[i].origin[k] = (float)o[k];
            rays[i].dir[k] = (float)d[k];
        }
        rays[i].t_min = 0.0f;
        rays[i].t_max = INFINITY;
    }
#undef NEXT
}

/* ---- Embree ---------------------------------------------------------------------- */

/* Bytes Embree holds (its memory monitor). */
static ssize_t embree_bytes;

static bool monitor(void *user, ssize_t bytes, bool post) {
    (void)user;
    (void)post;
    embree_bytes += bytes;
    return true;
}

/* The triangle surface of the W x H heights `h` and its four side walls down to
 * `bottom`, committed in a new scene of `dev` with `flags` (RTC_SCENE_FLAG_ROBUST:
 * watertight, no ray slips between two triangles). */
static RTCScene embree_scene(RTCDevice dev, const float *h, uint32_t w, uint32_t hh, float bottom,
                             enum RTCSceneFlags flags) {
    size_t grid = (size_t)w * hh;
    /* The boundary samples in order around the field, and a copy of each at `bottom`. */
    size_t ring = 2 * (size_t)(w - 1) + 2 * (size_t)(hh - 1);
    size_t cells = (size_t)(w - 1) * (hh - 1);
    RTCScene scene = rtcNewScene(dev);
    rtcSetSceneFlags(scene, flags);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                3 * sizeof(float), grid + ring);
    unsigned *tri = (unsigned *)rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 2 * cells + 2 * ring);
    for (uint32_t j = 0; j < hh; j++) {
        for (uint32_t i = 0; i < w; i++) {
            float *p = &v[3 * ((size_t)j * w + i)];
            p[0] = (float)i;
            p[1] = (float)j;
            p[2] = h[(size_t)j * w + i];
        }
    }
    size_t t = 0;
#define TRI(a, b, c) (tri[3 * t] = (unsigned)(a), tri[3 * t + 1] = (unsigned)(b), tri[3 * t + 2] = (unsigned)(c), t++)
    for (uint32_t j = 0; j + 1 < hh; j++) {
        for (uint32_t i = 0; i + 1 < w; i++) {
            size_t s00 = (size_t)j * w + i, s10 = s00 + 1, s01 = s00 + w, s11 = s01 + 1;
            if (h[s00] + h[s11] <= h[s10] + h[s01]) {
                TRI(s00, s10, s11);
                TRI(s00, s11, s01);
            } else {
                TRI(s00, s10, s01);
                TRI(s10, s11, s01);
            }
        }
    }
    /* Walk the boundary: along j = 0, i = W-1, j = H-1 (backwards), i = 0 (backwards). */
    size_t k = 0;
    size_t *around = (size_t *)malloc(sizeof(size_t) * ring);
    for (uint32_t i = 0; i + 1 < w; i++) around[k++] = i;
    for (uint32_t j = 0; j + 1 < hh; j++) around[k++] = (size_t)j * w + (w - 1);
    for (uint32_t i = w - 1; i > 0; i--) around[k++] = (size_t)(hh - 1) * w + i;
    for (uint32_t j = hh - 1; j > 0; j--) around[k++] = (size_t)j * w;
    for (size_t r = 0; r < ring; r++) {
        float *p = &v[3 * (grid + r)];
        p[0] = v[3 * around[r]];
        p[1] = v[3 * around[r] + 1];
        p[2] = bottom;
    }
    for (size_t r = 0; r < ring; r++) {
        size_t a = around[r], b = around[(r + 1) % ring];
        size_t a0 = grid + r, b0 = grid + (r + 1) % ring;
        TRI(a, b, b0);
        TRI(a, b0, a0);
    }
#undef TRI
    free(around);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    return scene;
}

/* Threads the benchmark traces on (its third argument; default 1): hfcast through
 * hf_trace_options.threads, Embree on as many POSIX threads, thread k taking every
 * bench_threads-th band of BAND_ROWS image rows (rays, for single rays) from band k. */
static int bench_threads = 1;
#define BAND_ROWS 8

/* The first hit's t (INFINITY: none) of the rays of every `parts`-th band of `band`
 * rays from band `part`, single rays. */
static void embree_trace1_part(RTCScene scene, const hf_ray *rays, size_t n, float *t_out,
                               size_t band, int part, int parts) {
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t first = (size_t)part * band; first < n; first += (size_t)parts * band) {
        size_t end = first + band < n ? first + band : n;
        for (size_t i = first; i < end; i++) {
            struct RTCRayHit rh;
            memset(&rh, 0, sizeof rh);
            rh.ray.org_x = rays[i].origin[0];
            rh.ray.org_y = rays[i].origin[1];
            rh.ray.org_z = rays[i].origin[2];
            rh.ray.dir_x = rays[i].dir[0];
            rh.ray.dir_y = rays[i].dir[1];
            rh.ray.dir_z = rays[i].dir[2];
            rh.ray.tnear = rays[i].t_min;
            rh.ray.tfar = rays[i].t_max;
            rh.ray.mask = 0xffffffffu;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            t_out[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? INFINITY : rh.ray.tfar;
        }
    }
}

/* Every ray's first hit t (INFINITY: none), single rays on the calling thread. */
static void embree_trace1(RTCScene scene, const hf_ray *rays, size_t n, float *t_out) {
    embree_trace1_part(scene, rays, n, t_out, n, 0, 1);
}

/* [embree_trace1_part] for a `cam_w x cam_h` camera image (both even, cam_w a multiple
 * of 4), in packets of 8 rays from 4 x 2 pixel tiles, bands of BAND_ROWS rows. */
static void embree_trace8_part(RTCScene scene, const hf_ray *rays, uint32_t cam_w, uint32_t cam_h,
                               float *t_out, int part, int parts) {
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    static const int valid[8] __attribute__((aligned(32))) = {-1, -1, -1, -1, -1, -1, -1, -1};
    struct RTCRayHit8 rh __attribute__((aligned(32)));
    size_t idx[8];
    for (uint32_t first = (uint32_t)part * BAND_ROWS; first < cam_h;
         first += (uint32_t)parts * BAND_ROWS) {
        for (uint32_t py = first; py < first + BAND_ROWS && py < cam_h; py += 2) {
            for (uint32_t px = 0; px < cam_w; px += 4) {
                memset(&rh, 0, sizeof rh);
                for (int l = 0; l < 8; l++) {
                    size_t i = (size_t)(py + l / 4) * cam_w + px + l % 4;
                    idx[l] = i;
                    rh.ray.org_x[l] = rays[i].origin[0];
                    rh.ray.org_y[l] = rays[i].origin[1];
                    rh.ray.org_z[l] = rays[i].origin[2];
                    rh.ray.dir_x[l] = rays[i].dir[0];
                    rh.ray.dir_y[l] = rays[i].dir[1];
                    rh.ray.dir_z[l] = rays[i].dir[2];
                    rh.ray.tnear[l] = rays[i].t_min;
                    rh.ray.tfar[l] = rays[i].t_max;
                    rh.ray.mask[l] = 0xffffffffu;
                    rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
                }
                rtcIntersect8(valid, scene, &ctx, &rh);
                for (int l = 0; l < 8; l++) {
                    t_out[idx[l]] =
                        rh.hit.geomID[l] == RTC_INVALID_GEOMETRY_ID ? INFINITY : rh.ray.tfar[l];
                }
            }
        }
    }
}

/* One thread's share of an Embree run. */
typedef struct embree_job {
    RTCScene scene;
    const hf_ray *rays;
    size_t n;
    float *t_out;
    uint32_t cam_w, cam_h; /* the camera image, for packets */
    int packets, part;
} embree_job;

static void *embree_job_run(void *arg) {
    const embree_job *j = (const embree_job *)arg;
    if (j->packets) {
        embree_trace8_part(j->scene, j->rays, j->cam_w, j->cam_h, j->t_out, j->part, bench_threads);
    } else {
        embree_trace1_part(j->scene, j->rays, j->n, j->t_out, (size_t)BAND_ROWS * j->cam_w,
                           j->part, bench_threads);
    }
    return NULL;
}

#define MAX_THREADS 64

/* An Embree run of `n` rays (single rays, or packets of a `cam_w x cam_h` camera's
 * tiles) on bench_threads threads, the calling one included. */
static void embree_trace(RTCScene scene, const hf_ray *rays, size_t n, uint32_t cam_w,
                         uint32_t cam_h, int packets, float *t_out) {
    embree_job jobs[MAX_THREADS];
    pthread_t threads[MAX_THREADS];
    for (int k = 0; k < bench_threads; k++) {
        embree_job j = {scene, rays, n, t_out, cam_w, cam_h, packets, k};
        jobs[k] = j;
        if (k > 0 && pthread_create(&threads[k], NULL, embree_job_run, &jobs[k]) != 0) {
            fprintf(stderr, "pthread_create failed\n");
            exit(2);
        }
    }
    embree_job_run(&jobs[0]);
    for (int k = 1; k < bench_threads; k++) pthread_join(threads[k], NULL);
}

/* ---- the field and the ray sets ------------------------------------------------- */

/* A field loaded from a PNG, with what both sides trace on. */
typedef struct field_data {
    uint32_t w, h;
    float depth, zmin, zmax;
    float *heights; /* W x H, row by row */
    hf_field *field;
    uint8_t *cc; /* the exact cylinder-cone map, all four ray classes, cap CC_CAP */
    size_t cc_len;
    double cc_bake_s; /* its bake, on every core */
    float *pyramid;   /* the maximum mipmap */
    size_t pyramid_len;
    double pyramid_bake_s;
    uint8_t *sd; /* the exact directional safety distances (cap 255) */
    size_t sd_len;
} field_data;

/* `method`'s map of fd->field baked with `o` on every core, in a new buffer of
 * hf_map_len elements (*len) of `elem` bytes; the bake's seconds in *secs unless NULL. */
static void *bake_map(const field_data *fd, uint32_t method, hf_bake_options o, size_t elem,
                      size_t *len, double *secs) {
    o.threads = 0;
    check_hf("hf_map_len", hf_map_len(method, fd->w, fd->h, &o, len));
    void *map = malloc(*len * elem);
    double t0 = now();
    check_hf("hf_bake", hf_bake(method, fd->field, &o, map, *len));
    if (secs) *secs = now() - t0;
    return map;
}

/* ---- synthetic fields ----------------------------------------------------------- */

/* A hash of (seed, i, j) to [0, 1) (splitmix64's finaliser over the packed inputs). */
static double lattice(uint64_t seed, int64_t i, int64_t j) {
    uint64_t x = seed * 0x9e3779b97f4a7c15ull ^ (uint64_t)i * 0xbf58476d1ce4e5b9ull ^
                 (uint64_t)j * 0x94d049bb133111ebull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    x ^= x >> 31;
    return (double)(x >> 11) / 9007199254740992.0;
}

/* Value noise: the lattice's values at the integer points around (x, y), blended with
 * smoothstep weights; in [0, 1]. */
static double value_noise(uint64_t seed, double x, double y) {
    double fx = floor(x), fy = floor(y);
    int64_t i = (int64_t)fx, j = (int64_t)fy;
    double u = x - fx, v = y - fy;
    u = u * u * (3.0 - 2.0 * u);
    v = v * v * (3.0 - 2.0 * v);
    double a = lattice(seed, i, j) + (lattice(seed, i + 1, j) - lattice(seed, i, j)) * u;
    double b = lattice(seed, i, j + 1) + (lattice(seed, i + 1, j + 1) - lattice(seed, i, j + 1)) * u;
    return a + (b - a) * v;
}

/* fBm over an n x n grid into h: octaves of value noise from period `period` texels
 * down to 2, each half the period and half the amplitude of the one before (seeded by
 * `seed` and the octave), scaled to [0, relief]. */
static void fbm(uint32_t n, double period, uint64_t seed, double relief, float *h) {
    double lo = INFINITY, hi = -INFINITY;
    double *acc = (double *)calloc((size_t)n * n, sizeof *acc);
    for (uint32_t j = 0; j < n; j++) {
        for (uint32_t i = 0; i < n; i++) {
            double sum = 0.0, amp = 1.0, p = period;
            for (uint64_t octave = 0; p >= 2.0; octave++, p /= 2.0, amp /= 2.0) {
                sum += amp * value_noise(seed * 64 + octave, i / p, j / p);
            }
            acc[(size_t)j * n + i] = sum;
            lo = fmin(lo, sum);
            hi = fmax(hi, sum);
        }
    }
    for (size_t k = 0; k < (size_t)n * n; k++) h[k] = (float)((acc[k] - lo) / (hi - lo) * relief);
    free(acc);
}

/* synthetic:fractal: fBm from a quarter of the side down to 2 texels, over the whole
 * depth (0.1 x side, as a PNG that uses its whole range): mountains whose slopes stay
 * rough down to the texel. */
static void fractal_heights(uint32_t n, double depth, float *h) {
    fbm(n, n / 4.0, 1, depth, h);
}

/* synthetic:needles: a low base (fBm over a tenth of the depth) under thin walls, each
 * a 4-connected line of samples one texel wide (a ridge of the triangle surface with no
 * gap), side / 32 of them, side / 8 to side / 2 long, in any direction, 0.1 to 0.3 x the
 * depth high (low enough that grazing rays pass over some), and one-texel needles (a
 * single tall sample: a spike of four triangles over 2 x 2 cells), side^2 / 1024 of
 * them, 0.3 to 1 x the depth high. A cone or a maximum-mipmap level sees their tops
 * over cells they barely cover: the marches must step slowly near every one while the
 * rays pass between them. */
static void needles_heights(uint32_t n, double depth, float *h) {
    fbm(n, n / 8.0, 2, 0.1 * depth, h);
    uint64_t x = 0x2545f4914f6cdd1dull;
#define NEXT() (x ^= x << 13, x ^= x >> 7, x ^= x << 17, (double)(x >> 11) / 9007199254740992.0)
#define RAISE(i, j, z) (h[(size_t)(j) * n + (i)] = fmaxf(h[(size_t)(j) * n + (i)], (float)(z)))
    for (uint32_t w = 0; w < n / 32; w++) {
        int x0 = (int)(NEXT() * n), y0 = (int)(NEXT() * n);
        double len = n * (0.125 + 0.375 * NEXT()), a = 2.0 * PI * NEXT();
        double z = depth * (0.1 + 0.2 * NEXT());
        int x1 = (int)fmin(fmax(x0 + len * cos(a), 0.0), n - 1.0);
        int y1 = (int)fmin(fmax(y0 + len * sin(a), 0.0), n - 1.0);
        /* The grid walk: one step in x or in y at a time, whichever lags the line. */
        int dx = abs(x1 - x0), dy = abs(y1 - y0), sx = x1 > x0 ? 1 : -1, sy = y1 > y0 ? 1 : -1;
        RAISE(x0, y0, z);
        for (int ix = 0, iy = 0; ix < dx || iy < dy;) {
            if ((2 * ix + 1) * dy < (2 * iy + 1) * dx) {
                x0 += sx;
                ix++;
            } else {
                y0 += sy;
                iy++;
            }
            RAISE(x0, y0, z);
        }
    }
    for (size_t k = 0; k < (size_t)n * n / 1024; k++) {
        uint32_t i = (uint32_t)(NEXT() * n), j = (uint32_t)(NEXT() * n);
        RAISE(i, j, depth * (0.3 + 0.7 * NEXT()));
    }
#undef RAISE
#undef NEXT
}

/* The heights of `path` into fd->heights, fd->w x fd->h, and fd->depth (0.1 x side): a
 * 16-bit PNG (heights v / 65535 x depth, as the Rust benchmarks load it) or
 * synthetic:NAME[:SIDE] (fractal or needles, SIDE x SIDE, default 1024). 0 when the file
 * cannot be read or the name is unknown. */
static int field_heights(const char *path, field_data *fd) {
    if (strncmp(path, "synthetic:", 10) == 0) {
        const char *name = path + 10, *colon = strchr(name, ':');
        size_t name_len = colon ? (size_t)(colon - name) : strlen(name);
        long side = colon ? strtol(colon + 1, NULL, 10) : 1024;
        void (*gen)(uint32_t, double, float *) =
            name_len == 7 && strncmp(name, "fractal", 7) == 0   ? fractal_heights
            : name_len == 7 && strncmp(name, "needles", 7) == 0 ? needles_heights
                                                                : NULL;
        if (!gen || side < 16 || side > 16384) return 0;
        fd->w = fd->h = (uint32_t)side;
        fd->depth = 0.1f * (float)side;
        fd->heights = (float *)malloc(sizeof(float) * (size_t)side * side);
        gen(fd->w, fd->depth, fd->heights);
        return 1;
    }
    uint16_t *raw = read_png_gray16(path, &fd->w, &fd->h);
    if (!raw) return 0;
    size_t n = (size_t)fd->w * fd->h;
    fd->depth = 0.1f * (float)(fd->w > fd->h ? fd->w : fd->h);
    fd->heights = (float *)malloc(sizeof(float) * n);
    for (size_t i = 0; i < n; i++) fd->heights[i] = (float)raw[i] / 65535.0f * fd->depth;
    free(raw);
    return 1;
}

/* Loads `path` ([field_heights]) and bakes its exact CC map, its maximum mipmap and its
 * exact safety distances; 0 when it cannot be read. */
static int field_load(const char *path, field_data *fd) {
    if (!field_heights(path, fd)) return 0;
    size_t n = (size_t)fd->w * fd->h;
    fd->zmin = INFINITY;
    fd->zmax = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        fd->zmin = fminf(fd->zmin, fd->heights[i]);
        fd->zmax = fmaxf(fd->zmax, fd->heights[i]);
    }
    check_hf("hf_field_create_f32",
             hf_field_create_f32(fd->heights, n, fd->w, fd->h, fd->w, &fd->field));
    /* All four ray classes (the defaults): the CC map of the exact slope and cap CC_CAP,
     * the directional safety distances of cap 255. */
    hf_bake_options o;
    check_hf("hf_bake_options_default", hf_bake_options_default(HF_METHOD_CC, &o));
    o.cap = CC_CAP;
    fd->cc = bake_map(fd, HF_METHOD_CC, o, 1, &fd->cc_len, &fd->cc_bake_s);
    fd->pyramid = bake_map(fd, HF_METHOD_MAXMIP, o, sizeof(float), &fd->pyramid_len,
                           &fd->pyramid_bake_s);
    o.cap = 255;
    fd->sd = bake_map(fd, HF_METHOD_SAFETY, o, 1, &fd->sd_len, NULL);
    return 1;
}

static void field_free(field_data *fd) {
    free(fd->sd);
    free(fd->pyramid);
    free(fd->cc);
    hf_field_destroy(fd->field);
    free(fd->heights);
}

/* Rays whose hit differs between `hits` and Embree's `t` (one hits and not the other,
 * or t apart by more than 1e-3 relative); their indices into `out` when not NULL. */
static size_t disagreements(const hf_hit *hits, const float *t, size_t n, size_t *out) {
    size_t bad = 0;
    for (size_t i = 0; i < n; i++) {
        int eh = t[i] != INFINITY;
        if (eh != (int)hits[i].hit ||
            (eh && fabsf(t[i] - hits[i].t) > 1e-3f * fmaxf(1.0f, hits[i].t))) {
            if (out) out[bad] = i;
            bad++;
        }
    }
    return bad;
}

/* hfcast's exact methods compared, through the batch functions of the C API with
 * their default options (a batch from one eye shares a horizon: HF_HORIZON_AUTO); the
 * maximum mipmap also without the horizon, in SIMD lanes (16 rays in AVX-512, 8 in AVX2,
 * where the CPU has them) and one ray after another (HF_SIMD_OFF). */
enum {
    METHOD_CC,
    METHOD_MAXMIP,
    METHOD_MAXMIP_LANES,
    METHOD_MAXMIP_SCALAR,
    METHOD_SD,
    METHOD_DDA,
    METHODS
};
static const char *const METHOD_NAMES[METHODS] = {
    "cc exact",         "maxmip (horizon)", "maxmip (lanes)", "maxmip (scalar)",
    "sd exact",         "dda (horizon)"};

/* Traces `rays` with hfcast's exact `method` (triangle surface) into `hits`. */
static void trace_method(const field_data *fd, int method, const hf_ray *rays, size_t n,
                         hf_hit *hits) {
    static const uint32_t api[METHODS] = {HF_METHOD_CC,     HF_METHOD_MAXMIP, HF_METHOD_MAXMIP,
                                          HF_METHOD_MAXMIP, HF_METHOD_SAFETY, HF_METHOD_EXACT};
    const void *map[METHODS] = {fd->cc, fd->pyramid, fd->pyramid, fd->pyramid, fd->sd, NULL};
    const size_t len[METHODS] = {fd->cc_len,      fd->pyramid_len, fd->pyramid_len,
                                 fd->pyramid_len, fd->sd_len,      0};
    hf_trace_options o;
    check_hf("hf_trace_options_default", hf_trace_options_default(&o));
    if (method == METHOD_MAXMIP_LANES || method == METHOD_MAXMIP_SCALAR)
        o.horizon = HF_HORIZON_OFF;
    if (method == METHOD_MAXMIP_SCALAR) o.simd = HF_SIMD_OFF;
    o.threads = (uint32_t)bench_threads;
    check_hf(METHOD_NAMES[method],
             hf_trace_batch(fd->field, api[method], map[method], len[method], &o, rays, n, hits,
                            n));
}

/* The cameras, then the random rays: the whole box from 45 and 5 degrees (more than
 * half their rays leave the box early), and the terrain filling the frame from 45 and
 * 5 degrees (a 2 degree telephoto, its rays grazing across the field), all at azimuth
 * 30 and 40 degrees of vertical field of view but the telephoto. */
static const camera CAMERAS[] = {{"45deg", 45.0, 30.0, 20.0, 0},
                                 {"5deg", 5.0, 30.0, 20.0, 0},
                                 {"filled45deg", 45.0, 30.0, 20.0, 1},
                                 {"filled5deg", 5.0, 30.0, 1.0, 1}};
#define CAMERA_SETS ((int)(sizeof CAMERAS / sizeof CAMERAS[0]))
#define RAY_SETS (CAMERA_SETS + 1)

/* The rays of `cam` framed on zref, traced by the exact CC march into `hits`; the
 * misses, and in *side the hits on the field's sides (rays that enter it under the
 * surface). */
static size_t camera_misses(const field_data *fd, const camera *cam, double zref, uint32_t cam_w,
                            uint32_t cam_h, hf_ray *rays, hf_hit *hits, size_t *side) {
    size_t n = (size_t)cam_w * cam_h, misses = 0;
    camera_rays(fd->w, fd->h, fd->zmin, fd->zmax, cam, zref, cam_w, cam_h, rays);
    trace_method(fd, METHOD_CC, rays, n, hits);
    *side = 0;
    for (size_t i = 0; i < n; i++) {
        misses += !hits[i].hit;
        *side += hits[i].hit && (hits[i].flags & HF_FLAG_SIDE);
    }
    return misses;
}

/* Ray set `k` of a `cam_w x cam_h` camera into `rays` (room for cam_w x cam_h rays):
 * the cameras of CAMERAS, then random rays starting above the surface (from
 * cam_w x cam_h / 4 drawn). Writes its name; returns its ray count. A filled camera
 * framed on zmin meets the field with every ray, but a low one (the telephoto) sees
 * rays enter the near side under the surface: hits on the side wall, not on the
 * terrain. Then it is lifted: zref raised by bisection (8 halvings of the relief) to
 * the highest level at which hfcast's exact answers still have every ray hit. Its name
 * says the lift, the misses and the side hits. */
static size_t ray_set(const field_data *fd, int k, uint32_t cam_w, uint32_t cam_h, hf_ray *rays,
                      char *name, size_t name_len) {
    size_t n = (size_t)cam_w * cam_h;
    if (k < CAMERA_SETS) {
        const camera *cam = &CAMERAS[k];
        if (!cam->filled) {
            camera_rays(fd->w, fd->h, fd->zmin, fd->zmax, cam, fd->zmin, cam_w, cam_h, rays);
            snprintf(name, name_len, "camera %.0f deg", cam->elevation);
            return n;
        }
        hf_hit *hits = (hf_hit *)malloc(sizeof(hf_hit) * n);
        double lo = fd->zmin, hi = fd->zmax;
        size_t side, misses = camera_misses(fd, cam, lo, cam_w, cam_h, rays, hits, &side);
        if (side > 0) {
            for (int step = 0; step < 8; step++) {
                double mid = 0.5 * (lo + hi);
                size_t s;
                *(camera_misses(fd, cam, mid, cam_w, cam_h, rays, hits, &s) == 0 ? &lo : &hi) = mid;
            }
            misses = camera_misses(fd, cam, lo, cam_w, cam_h, rays, hits, &side);
        }
        free(hits);
        snprintf(name, name_len,
                 "filled camera %.0f deg, %.0f deg vertical fov (lift %.1f; %zu misses, %zu side "
                 "hits)",
                 cam->elevation, 2.0 * cam->half_fov, lo - fd->zmin, misses, side);
        return n;
    }
    size_t drawn = n / 4;
    random_rays(fd->w, fd->h, fd->zmin, fd->zmax, drawn, 7, rays);
    hf_hit *probe = (hf_hit *)malloc(sizeof(hf_hit) * drawn);
    check_hf("hf_trace_batch (exact)", hf_trace_batch(fd->field, HF_METHOD_EXACT, NULL, 0, NULL,
                                                      rays, drawn, probe, drawn));
    size_t above = 0;
    for (size_t i = 0; i < drawn; i++) {
        if (!(probe[i].flags & HF_FLAG_ORIGIN_INSIDE)) rays[above++] = rays[i];
    }
    free(probe);
    snprintf(name, name_len, "random, starting above the surface (%zu of %zu)", above, drawn);
    return above;
}

/* ---- benchmark ------------------------------------------------------------------- */

#define BENCH_W 640
#define BENCH_H 512

/* The timed runs of one ray set: hfcast's methods, then Embree's single rays and
 * packets (cameras only) on its default and watertight scenes. */
enum { RUN_E1 = METHODS, RUN_E8, RUN_R1, RUN_R8, RUNS };
static const char *const EMBREE_RUNS[RUNS - METHODS] = {
    "embree single", "embree packets of 8", "embree robust single", "embree robust packets of 8"};

/* Whether `run` traces the ray set: packets trace the cameras' pixel tiles only. */
static int run_applies(int run, int camera) {
    return camera || (run != RUN_E8 && run != RUN_R8);
}

/* One timed run of `rays` (ns per ray): hfcast's method `run`, or an Embree run. */
static double time_run(const field_data *fd, RTCScene scenes[2], int run, const hf_ray *rays,
                       size_t n, hf_hit *hits[METHODS], float *t[RUNS - METHODS]) {
    double t0 = now();
    if (run < METHODS) {
        trace_method(fd, run, rays, n, hits[run]);
    } else {
        int packets = run == RUN_E8 || run == RUN_R8;
        embree_trace(scenes[run >= RUN_R1], rays, n, BENCH_W, BENCH_H, packets, t[run - RUN_E1]);
    }
    return (now() - t0) * 1e9 / n;
}

/* The speedup lines of each ray set benched so far ([0] single rays, [1] packets). */
static char speedups[2][RAY_SETS][96];
static int set_count = 0;

/* The distinct cells that `hits` (of `n` rays over `fd`) land on. Rays over a cell
 * measure a view's magnification: a telephoto's rays hit the same cell by the dozen,
 * where Embree's packets share their traversal and each of hfcast's rays walks alone. */
static size_t hit_cells(const field_data *fd, const hf_hit *hits, size_t n) {
    uint8_t *seen = (uint8_t *)calloc((size_t)fd->w * fd->h, 1);
    size_t cells = 0;
    for (size_t i = 0; i < n; i++) {
        if (!hits[i].hit || hits[i].cell[0] >= fd->w || hits[i].cell[1] >= fd->h) continue;
        uint8_t *s = &seen[(size_t)hits[i].cell[1] * fd->w + hits[i].cell[0]];
        cells += !*s;
        *s = 1;
    }
    free(seen);
    return cells;
}

/* Times every run on `rays` twice over and counts the hits of each hfcast method that
 * differ from each Embree run's. Cold: medians of `reps` passes, each pass running
 * every method once, so that each run finds the caches holding the others' data (the
 * figures quoted). Warm: each run's `reps` passes back to back, after the cold ones, so
 * that it finds what fits of its own data in the caches. */
static void bench_set(const field_data *fd, RTCScene scenes[2], int reps, const char *name,
                      const char *tag, const hf_ray *rays, size_t n, int camera) {
    hf_hit *hits[METHODS];
    float *t[RUNS - METHODS];
    for (int m = 0; m < METHODS; m++) hits[m] = (hf_hit *)malloc(sizeof(hf_hit) * n);
    for (int k = 0; k < RUNS - METHODS; k++) t[k] = (float *)malloc(sizeof(float) * n);
    double *ns = (double *)malloc(sizeof(double) * reps * RUNS);
    double *warm = (double *)malloc(sizeof(double) * reps * RUNS);
    for (int r = 0; r < reps; r++) {
        for (int run = 0; run < RUNS; run++) {
            if (!run_applies(run, camera)) continue;
            ns[run * reps + r] = time_run(fd, scenes, run, rays, n, hits, t);
        }
    }
    for (int run = 0; run < RUNS; run++) {
        for (int r = 0; r < reps && run_applies(run, camera); r++) {
            warm[run * reps + r] = time_run(fd, scenes, run, rays, n, hits, t);
        }
    }
    size_t hit_count = 0;
    double fetches[METHODS] = {0.0};
    for (size_t i = 0; i < n; i++) {
        hit_count += hits[METHOD_CC][i].hit;
        for (int m = 0; m < METHODS; m++) fetches[m] += hits[m][i].fetches;
    }
    size_t cells = hit_cells(fd, hits[METHOD_CC], n);
    printf("%s: %zu rays, %zu hits on %zu cells (%.1f a cell)\n", name, n, hit_count, cells,
           (double)hit_count / (double)(cells ? cells : 1));
    double cc = median(ns + METHOD_CC * reps, reps);
    double cc_warm = median(warm + METHOD_CC * reps, reps);
    for (int run = 0; run < RUNS; run++) {
        if (!run_applies(run, camera)) continue;
        double m = median(ns + run * reps, reps), w = median(warm + run * reps, reps);
        if (run < METHODS) {
            printf("  hfcast %-22s %6.0f ns/ray %6.2f M rays/s  (warm %4.0f)  %.1f fetches/ray\n",
                   METHOD_NAMES[run], m, 1e3 / m, w, fetches[run] / n);
        } else {
            printf("  %-27s %6.0f ns/ray %6.2f M rays/s  (warm %4.0f)  cc / this %.2f (warm %.2f); "
                   "hits differing:",
                   EMBREE_RUNS[run - RUN_E1], m, 1e3 / m, w, cc / m, cc_warm / w);
            for (int k = 0; k < METHODS; k++) {
                printf(" %s %zu", METHOD_NAMES[k], disagreements(hits[k], t[run - RUN_E1], n, NULL));
            }
            printf("\n");
        }
    }
    /* hfcast's fastest exact method against Embree's best single-ray and packet runs
     * (> 1: hfcast is faster), the lines scripts/embree_bench.sh ends with. */
    double best = INFINITY;
    for (int m = 0; m < METHODS; m++) best = fmin(best, median(ns + m * reps, reps));
    double single = fmin(median(ns + RUN_E1 * reps, reps), median(ns + RUN_R1 * reps, reps));
    snprintf(speedups[0][set_count], sizeof speedups[0][0], "speedup over embree-single %s: %.2f",
             tag, single / best);
    if (camera) {
        double packets =
            fmin(median(ns + RUN_E8 * reps, reps), median(ns + RUN_R8 * reps, reps));
        snprintf(speedups[1][set_count], sizeof speedups[1][0],
                 "speedup over embree-packets %s: %.2f", tag, packets / best);
    } else {
        snprintf(speedups[1][set_count], sizeof speedups[1][0],
                 "speedup over embree-packets %s: n/a (Embree's packets trace camera tiles)", tag);
    }
    set_count++;
    free(warm);
    free(ns);
    for (int k = 0; k < RUNS - METHODS; k++) free(t[k]);
    for (int m = 0; m < METHODS; m++) free(hits[m]);
}

static int bench(const char *path, int reps) {
    field_data fd;
    if (!field_load(path, &fd)) {
        fprintf(stderr, "cannot read %s\n", path);
        return 2;
    }
    RTCDevice dev = rtcNewDevice(NULL);
    if (!dev) {
        fprintf(stderr, "rtcNewDevice failed\n");
        return 2;
    }
    rtcSetDeviceMemoryMonitorFunction(dev, monitor, NULL);
    const enum RTCSceneFlags flags[2] = {RTC_SCENE_FLAG_NONE, RTC_SCENE_FLAG_ROBUST};
    RTCScene scenes[2];
    double build[2];
    ssize_t bytes[2];
    for (int k = 0; k < 2; k++) {
        ssize_t before = embree_bytes;
        double t0 = now();
        scenes[k] = embree_scene(dev, fd.heights, fd.w, fd.h, fd.zmin - WALL_DEPTH, flags[k]);
        build[k] = now() - t0;
        bytes[k] = embree_bytes - before;
    }
    if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) {
        fprintf(stderr, "embree scene build failed\n");
        return 2;
    }
    size_t n = (size_t)fd.w * fd.h;
    printf("%s: %u x %u, depth %.1f, %d thread%s; embree %s (8-wide packets native: %s)\n",
           path, fd.w, fd.h, fd.depth, bench_threads, bench_threads > 1 ? "s" : "",
           RTC_VERSION_STRING,
           rtcGetDeviceProperty(dev, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) ? "yes" : "no");
    printf("memory: hfcast f32 heights %.1f MiB + exact cc map %.1f (all four ray classes), "
           "maximum mipmap %.1f or safety distances %.1f; embree %.1f MiB (robust %.1f; BVH "
           "and buffers, its memory monitor)\n",
           n * 4.0 / 1048576.0, fd.cc_len / 1048576.0, fd.pyramid_len * 4.0 / 1048576.0,
           fd.sd_len / 1048576.0, bytes[0] / 1048576.0, bytes[1] / 1048576.0);
    printf("preprocessing (all cores): hfcast exact cc bake %.2f s, maximum mipmap %.3f s; "
           "embree bvh build %.2f s (robust %.2f s)\n",
           fd.cc_bake_s, fd.pyramid_bake_s, build[0], build[1]);
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * BENCH_W * BENCH_H);
    for (int k = 0; k < RAY_SETS; k++) {
        char name[160];
        size_t m = ray_set(&fd, k, BENCH_W, BENCH_H, rays, name, sizeof name);
        int camera = k < CAMERA_SETS;
        bench_set(&fd, scenes, reps, name, camera ? CAMERAS[k].tag : "random", rays, m, camera);
    }
    for (int k = 0; k < set_count; k++) printf("%s\n%s\n", speedups[1][k], speedups[0][k]);
    free(rays);
    rtcReleaseScene(scenes[0]);
    rtcReleaseScene(scenes[1]);
    rtcReleaseDevice(dev);
    field_free(&fd);
    return 0;
}

/* ---- check ----------------------------------------------------------------------- */

#define CHECK_W 256
#define CHECK_H 192

/* The triangle surface's height at (x, y) of the footprint, in f64. */
static double surface_at(const field_data *fd, double x, double y) {
    double u = fmin(fmax(x, 0.0), fd->w - 1.0), v = fmin(fmax(y, 0.0), fd->h - 1.0);
    uint32_t i = (uint32_t)fmin(floor(u), fd->w - 2.0), j = (uint32_t)fmin(floor(v), fd->h - 2.0);
    u -= i;
    v -= j;
    const float *row = fd->heights + (size_t)j * fd->w + i;
    double h00 = row[0], h10 = row[1], h01 = row[fd->w], h11 = row[fd->w + 1];
    if (h00 + h11 <= h10 + h01) {
        return fmax(h00 + (h10 - h00) * u + (h11 - h10) * v, h00 + (h11 - h01) * u + (h01 - h00) * v);
    }
    return fmax(h00 + (h10 - h00) * u + (h01 - h00) * v,
                h10 + h01 - h11 + (h11 - h01) * u + (h11 - h10) * v);
}

/* Whether the ray stays within rounding of the surface (never deeper under it than
 * 2^-13 x max(1, |height|), docs/DESIGN.md's ambiguity bound) for t in [a, b] over the
 * footprint: then a hit anywhere there is a matter of rounding. Exact: between two
 * grid-line crossings the triangle surface is the maximum of planes, so the depth is
 * convex along the ray and largest at a crossing or an end; those are all evaluated. */
static int within_rounding(const field_data *fd, const hf_ray *r, double a, double b) {
    double o[3] = {r->origin[0], r->origin[1], r->origin[2]};
    double d[3] = {r->dir[0], r->dir[1], r->dir[2]};
    double ext[2] = {fd->w - 1.0, fd->h - 1.0};
    for (int k = 0; k < 2; k++) { /* clip [a, b] to the footprint */
        if (d[k] == 0.0) continue;
        double t0 = (0.0 - o[k]) / d[k], t1 = (ext[k] - o[k]) / d[k];
        a = fmax(a, fmin(t0, t1));
        b = fmin(b, fmax(t0, t1));
    }
    for (int k = -1; k < 2; k++) { /* the ends (k = -1), then the crossings of x and y */
        double lo = k < 0 ? 0.0 : ceil(fmin(o[k] + a * d[k], o[k] + b * d[k]));
        double hi = k < 0 ? 1.0 : floor(fmax(o[k] + a * d[k], o[k] + b * d[k]));
        if (k >= 0 && d[k] == 0.0) continue;
        for (double g = lo; g <= hi; g += 1.0) {
            double t = k < 0 ? (g == 0.0 ? a : b) : (g - o[k]) / d[k];
            if (!(t >= a && t <= b)) continue;
            double s = surface_at(fd, o[0] + t * d[0], o[1] + t * d[1]);
            if (s - (o[2] + t * d[2]) > ldexp(fmax(1.0, fabs(s)), -13)) return 0;
        }
    }
    return 1;
}

/* Checks hfcast's exact methods against Embree's watertight scene on the ray sets of
 * `path`: every hit that differs must be within rounding
 * ([within_rounding]). One line per ray set and method; adds to the tallies. */
static void check_map(const char *path, RTCDevice dev, int *passed, int *failed) {
    field_data fd;
    if (!field_load(path, &fd)) {
        fprintf(stderr, "cannot read %s\n", path);
        (*failed)++;
        return;
    }
    RTCScene scene =
        embree_scene(dev, fd.heights, fd.w, fd.h, fd.zmin - WALL_DEPTH, RTC_SCENE_FLAG_ROBUST);
    size_t cap = (size_t)CHECK_W * CHECK_H;
    hf_ray *rays = (hf_ray *)malloc(sizeof(hf_ray) * cap);
    hf_hit *hits = (hf_hit *)malloc(sizeof(hf_hit) * cap);
    float *t = (float *)malloc(sizeof(float) * cap);
    size_t *bad = (size_t *)malloc(sizeof(size_t) * cap);
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    for (int k = 0; k < RAY_SETS; k++) {
        char name[160];
        size_t n = ray_set(&fd, k, CHECK_W, CHECK_H, rays, name, sizeof name);
        embree_trace1(scene, rays, n, t);
        for (int method = 0; method < METHODS; method++) {
            trace_method(&fd, method, rays, n, hits);
            size_t differ = disagreements(hits, t, n, bad), unexplained = 0, hit_count = 0;
            for (size_t i = 0; i < n; i++) hit_count += hits[i].hit;
            for (size_t b = 0; b < differ; b++) {
                size_t i = bad[b];
                double th = hits[i].hit ? hits[i].t : INFINITY;
                double lo = fmin(th, t[bad[b]]), hi = fmax(th, t[bad[b]]);
                if (!within_rounding(&fd, &rays[i], lo, hi)) {
                    if (unexplained++ < 3) {
                        fprintf(stderr, "  ray %zu: hfcast t %g, embree t %g\n", i, th, t[i]);
                    }
                }
            }
            int ok = unexplained == 0 && hit_count > 0;
            printf("%s %s, %s: %zu rays, %zu hits, %zu differ from embree (%zu beyond "
                   "rounding): %s\n",
                   base, name, METHOD_NAMES[method], n, hit_count, differ,
                   unexplained, ok ? "ok" : "FAILED");
            *(ok ? passed : failed) += 1;
        }
    }
    free(bad);
    free(t);
    free(hits);
    free(rays);
    rtcReleaseScene(scene);
    field_free(&fd);
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "--check") == 0) {
        RTCDevice dev = rtcNewDevice(NULL);
        if (!dev) {
            fprintf(stderr, "rtcNewDevice failed\n");
            return 2;
        }
        int passed = 0, failed = 0;
        for (int a = 2; a < argc; a++) check_map(argv[a], dev, &passed, &failed);
        rtcReleaseDevice(dev);
        printf("embree-agreement: %d passed, %d failed\n", passed, failed);
        return failed != 0 || passed == 0;
    }
    const char *path = argc > 1 ? argv[1] : "../../shared/data/dem_etopo5_himalaya_1024.png";
    int reps = argc > 2 ? atoi(argv[2]) : 5;
    bench_threads = argc > 3 ? atoi(argv[3]) : 1;
    if (bench_threads < 1 || bench_threads > MAX_THREADS) {
        fprintf(stderr, "threads: 1 to %d\n", MAX_THREADS);
        return 2;
    }
    return bench(path, reps < 1 ? 1 : reps);
}
