/* Issue 26, items 2 and 3: thread counts are capped (a bake asked for 100000 threads
 * answers HF_OK, byte for byte the 1-thread bake, and never runs more threads than
 * cores); errors are worth reading (overlap of a batch's rays and hits is found
 * before anything is written, empty batches and rectangles are HF_OK and change
 * nothing, hf_last_error_detail / hf_last_error_index name the argument and the ray).
 * Prints `c-errors: N passed, M failed`. */
#define _POSIX_C_SOURCE 200809L
#include "hfcast.h"
#include "check_api.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define N 512
#define MANY 100000u

static char detail[256];

/* The detail of the last failing call, as hf_last_error_detail gives it. */
static const char *last_detail(void) {
    size_t written = 0;
    if (hf_last_error_detail(detail, sizeof detail, &written) != HF_OK)
        return "(hf_last_error_detail failed)";
    return detail;
}

/* Checks that the detail of the last failing call contains `part`. */
#define CHECK_DETAIL(part)                                                         \
    do {                                                                           \
        const char *d_ = last_detail();                                            \
        checks++;                                                                  \
        if (!strstr(d_, (part))) {                                                 \
            failures++;                                                            \
            fprintf(stderr, "%s:%d: detail \"%s\" lacks \"%s\"\n", __FILE__,       \
                    __LINE__, d_, (part));                                         \
        }                                                                          \
    } while (0)

/* ---- threads: a sampler of this process's thread count while a bake runs ---- */

static volatile int sampling = 0;
static int peak_threads = 0;

static int thread_count_now(void) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    int n = 0;
    if (!f) return 0;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "Threads: %d", &n) == 1) break;
    fclose(f);
    return n;
}

static void *sample(void *arg) {
    (void)arg;
    while (__atomic_load_n(&sampling, __ATOMIC_ACQUIRE)) {
        int n = thread_count_now();
        if (n > peak_threads) peak_threads = n;
        struct timespec pause = {0, 200000};
        nanosleep(&pause, NULL);
    }
    return NULL;
}

/* Runs `call` while sampling the thread count; the peak is in peak_threads. */
#define SAMPLED(result, call)                                                      \
    do {                                                                           \
        pthread_t t_;                                                              \
        peak_threads = 0;                                                          \
        __atomic_store_n(&sampling, 1, __ATOMIC_RELEASE);                          \
        pthread_create(&t_, NULL, sample, NULL);                                   \
        (result) = (call);                                                         \
        __atomic_store_n(&sampling, 0, __ATOMIC_RELEASE);                          \
        pthread_join(t_, NULL);                                                    \
    } while (0)

/* Bakes `method`'s map of `f` (all four ray classes, elements of `elem` bytes) on one
 * thread and on MANY while sampling the thread count: HF_OK, the same bytes, at most
 * `limit` threads. */
static void check_bake_threads(const hf_field *f, uint32_t method, const char *name,
                               size_t elem, int limit) {
    hf_bake_options o;
    CHECK_OK(hf_bake_options_default(method, &o));
    o.ray_classes = HF_RAYS_ALL;
    size_t len = 0;
    CHECK_OK(hf_map_len(method, N, N, &o, &len));
    void *one = malloc(len * elem), *many = malloc(len * elem);
    o.threads = 1;
    CHECK_OK(hf_bake(method, f, &o, one, len));
    o.threads = MANY;
    hf_result r;
    SAMPLED(r, hf_bake(method, f, &o, many, len));
    CHECK(r == HF_OK);
    CHECK(memcmp(one, many, len * elem) == 0);
    CHECK(peak_threads <= limit);
    printf("threads: %s with %u threads: result %u, peak %d threads (limit %d)\n", name, MANY,
           (unsigned)r, peak_threads, limit);
    free(one);
    free(many);
}

static void check_threads(const hf_field *f) {
    /* This process has the main thread and the sampler; the bake may add one per core
     * at most (the calling thread is one of them). */
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    int limit = 2 + (int)(cores > 0 ? cores : 1);
    /* The maximum mipmap, the safety distances (directional, cap 255) and the exact
     * cylinder-cone shapes (cap 64): their defaults. */
    check_bake_threads(f, HF_METHOD_MAXMIP, "maxmip", sizeof(float), limit);
    check_bake_threads(f, HF_METHOD_SAFETY, "safety", 1, limit);
    check_bake_threads(f, HF_METHOD_CC, "cc", 1, limit);
}

/* ---- errors ---- */

static const hf_hit nothing_hit;

static void check_batches(const hf_field *f) {
    hf_ray good = {{1.5f, 1.5f, 100.0f}, {0.1f, 0.2f, -1.0f}, 0.0f, INFINITY};
    enum { R = 8 };
    hf_ray rays[R];
    hf_hit hits[R];
    for (int k = 0; k < R; k++) rays[k] = good;
    memset(hits, 0x5A, sizeof hits);

    /* The first bad ray of a batch: its index, as a number and in the detail. */
    const uint32_t ex = HF_METHOD_EXACT;
    rays[5].dir[0] = rays[5].dir[1] = rays[5].dir[2] = 0.0f;
    rays[6].origin[0] = NAN;
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, rays, R, hits, R), HF_ERR_INVALID_RAY, hits,
              sizeof hits);
    CHECK_DETAIL("rays[5]: ray direction is zero");
    size_t index = 0;
    CHECK_OK(hf_last_error_index(&index));
    CHECK(index == 5);
    /* The queries change nothing, even when they fail. */
    size_t written = 7;
    CHECK_BAD(hf_last_error_detail(detail, 4, &written), HF_ERR_BUFFER_TOO_SMALL, &written,
              sizeof written);
    CHECK_BAD(hf_last_error_index(NULL), HF_ERR_NULL_POINTER, &index, 0);
    CHECK_DETAIL("rays[5]: ray direction is zero");
    CHECK_OK(hf_last_error_index(&index));
    CHECK(index == 5);
    rays[5] = rays[6] = good;

    /* A single ray: named `ray`, no index. */
    hf_ray bad = good;
    bad.t_min = 2.0f;
    bad.t_max = 1.0f;
    hf_hit h = nothing_hit;
    CHECK_BAD(hf_trace(f, ex, NULL, 0, NULL, &bad, &h), HF_ERR_INVALID_RAY, &h, sizeof h);
    CHECK_DETAIL("ray: t_min is greater than t_max");
    CHECK_OK(hf_last_error_index(&index));
    CHECK(index == SIZE_MAX);

    /* Which pointer is NULL, which enum or option is bad. */
    CHECK_BAD(hf_trace_batch(NULL, ex, NULL, 0, NULL, rays, R, hits, R), HF_ERR_NULL_POINTER, hits,
              sizeof hits);
    CHECK_DETAIL("field: pointer is NULL");
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, NULL, R, hits, R), HF_ERR_NULL_POINTER, hits,
              sizeof hits);
    CHECK_DETAIL("rays: pointer is NULL");
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, rays, R, NULL, R), HF_ERR_NULL_POINTER, rays, 0);
    CHECK_DETAIL("out_hits: pointer is NULL");
    CHECK_BAD(hf_trace(f, ex, NULL, 0, NULL, &good, NULL), HF_ERR_NULL_POINTER, rays, 0);
    CHECK_DETAIL("out_hit: pointer is NULL");
    hf_trace_options o;
    CHECK_OK(hf_trace_options_default(&o));
    o.surface = 9;
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, &o, rays, R, hits, R), HF_ERR_INVALID_ENUM, hits,
              sizeof hits);
    CHECK_DETAIL("surface: 9");
    CHECK_BAD(hf_trace_batch(f, 99, NULL, 0, NULL, rays, R, hits, R), HF_ERR_INVALID_ENUM, hits,
              sizeof hits);
    CHECK_DETAIL("method: 99");
    o.surface = HF_SURFACE_TRIANGLES;
    o.reserved[3] = 1;
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, &o, rays, R, hits, R), HF_ERR_INVALID_ARGUMENT, hits,
              sizeof hits);
    CHECK_DETAIL("options.reserved[3]");
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 1, NULL, rays, R, hits, R), HF_ERR_INVALID_ARGUMENT,
              hits, sizeof hits);
    CHECK_DETAIL("map_len");
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, rays, R, hits, R - 1), HF_ERR_BUFFER_TOO_SMALL,
              hits, sizeof hits);
    CHECK_DETAIL("out_hits: 7 hits for 8 rays");
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, (const hf_ray *)((char *)rays + 1), 1, hits, R),
              HF_ERR_MISALIGNED_POINTER, hits, sizeof hits);
    CHECK_DETAIL("rays: pointer is not aligned to 4 bytes");
    /* A success leaves the index meaningless, but a new failure replaces it. */
    CHECK_OK(hf_trace_batch(f, ex, NULL, 0, NULL, rays, R, hits, R));

    /* Outputs overlapping the rays: found before anything is written. */
    union {
        hf_ray rays[R];
        hf_hit hits[R];
        unsigned char bytes[R * sizeof(hf_hit)];
    } both;
    for (int k = 0; k < R; k++) both.rays[k] = good;
    unsigned char saved[sizeof both];
    memcpy(saved, &both, sizeof both);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, both.rays, R, both.hits, R),
              HF_ERR_INVALID_ARGUMENT, &both, sizeof both);
    CHECK_DETAIL("out_hits overlaps rays");
    /* Overlap by one element's tail: hits start inside the last ray. */
    hf_hit *late = (hf_hit *)(void *)((char *)both.bytes + (R - 1) * sizeof(hf_ray) + 4);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, both.rays, R, late, 1), HF_ERR_INVALID_ARGUMENT,
              &both, sizeof both);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, both.rays, 4, both.hits + 4, 1),
              HF_ERR_BUFFER_TOO_SMALL, &both, sizeof both);
    CHECK(memcmp(saved, &both, sizeof both) == 0);
    /* Adjacent, not overlapping: fine. */
    hf_hit *after = (hf_hit *)(void *)((char *)both.bytes + 2 * sizeof(hf_ray));
    CHECK_OK(hf_trace_batch(f, ex, NULL, 0, NULL, both.rays, 2, after, 2));
    CHECK(after[0].hit == 1);

    /* Empty batches: HF_OK, nothing written; the pointers must still be valid. */
    memset(hits, 0x5A, sizeof hits);
    unsigned char before[sizeof hits];
    memcpy(before, hits, sizeof hits);
    CHECK_OK(hf_trace_batch(f, ex, NULL, 0, NULL, rays, 0, hits, 0));
    CHECK_OK(hf_trace_batch(f, ex, NULL, 0, NULL, rays, 0, hits, R));
    CHECK_OK(hf_trace_batch(f, HF_METHOD_LINEAR_SECANT, NULL, 0, NULL, rays, 0, hits, R));
    CHECK(memcmp(before, hits, sizeof hits) == 0);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, NULL, 0, hits, R), HF_ERR_NULL_POINTER, hits,
              sizeof hits);
    CHECK_BAD(hf_trace_batch(f, ex, NULL, 0, NULL, rays, 0, NULL, 0), HF_ERR_NULL_POINTER, hits, 0);
}

static void check_rects(void) {
    float h[16] = {0};
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(h, 16, 4, 4, 4, &f));
    size_t plen = 0;
    CHECK_OK(hf_map_len(HF_METHOD_MAXMIP, 4, 4, NULL, &plen));
    float p[64];
    CHECK(plen <= 64);
    CHECK_OK(hf_bake(HF_METHOD_MAXMIP, f, NULL, p, plen));
    float v[4] = {9.0f, 9.0f, 9.0f, 9.0f};
    float samples[16];
    /* Empty rectangles (inside the field): HF_OK in both, nothing changes. */
    CHECK_OK(hf_field_update_rect(f, 1, 1, 1, 3, v, 4, 2));
    CHECK_OK(hf_field_update_rect(f, 0, 4, 4, 4, v, 4, 2));
    CHECK_OK(hf_maxmip_update_rect(f, 1, 1, 1, 3, p, plen));
    CHECK_OK(hf_field_copy_heights(f, samples, 16));
    CHECK(memcmp(samples, h, sizeof h) == 0);
    /* Reversed or outside: HF_ERR_INVALID_RECT in both, with the rectangle said. */
    CHECK_BAD(hf_field_update_rect(f, 2, 0, 1, 2, v, 4, 2), HF_ERR_INVALID_RECT, p, 0);
    CHECK_DETAIL("[2, 1) x [0, 2)");
    CHECK_BAD(hf_field_update_rect(f, 4, 4, 5, 4, v, 4, 2), HF_ERR_INVALID_RECT, p, 0);
    CHECK_BAD(hf_maxmip_update_rect(f, 2, 0, 1, 2, p, plen), HF_ERR_INVALID_RECT, p,
              sizeof p);
    CHECK_BAD(hf_maxmip_update_rect(f, 4, 4, 5, 4, p, plen), HF_ERR_INVALID_RECT, p,
              sizeof p);
    /* An empty rectangle still checks its pointers. */
    CHECK_BAD(hf_field_update_rect(f, 1, 1, 1, 1, NULL, 4, 2), HF_ERR_NULL_POINTER, p, 0);
    CHECK_DETAIL("pointer is NULL");
    hf_field_destroy(f);

    /* A NaN height: its index. */
    float nan_h[16] = {0};
    nan_h[11] = NAN;
    hf_field *g = (hf_field *)&nan_h;
    CHECK_BAD(hf_field_create_f32(nan_h, 16, 4, 4, 4, &g), HF_ERR_NOT_FINITE, &g, sizeof g);
    size_t index = 0;
    CHECK_OK(hf_last_error_index(&index));
    CHECK(index == 11);
    CHECK_DETAIL("11");
}

int main(void) {
    float *heights = malloc((size_t)N * N * sizeof *heights);
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++)
            heights[j * N + i] = 8.0f * sinf(0.05f * (float)i) * cosf(0.07f * (float)j) +
                                 (float)((i * 7 + j * 13) % 5);
    hf_field *f = NULL;
    CHECK_OK(hf_field_create_f32(heights, (size_t)N * N, N, N, N, &f));
    if (f) {
        check_threads(f);
        check_batches(f);
    }
    check_rects();
    hf_field_destroy(f);
    free(heights);
    printf("c errors: %d checks, %d bad inputs tried\n", checks, bad_inputs);
    printf("c-errors: %d passed, %d failed\n", checks - failures, failures);
    return failures != 0;
}
