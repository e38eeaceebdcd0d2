/* Concurrency stress test of libhfcast (issue 26, item 4): READERS threads trace
 * batches on one field, with the exact method and with the maximum mipmap on one
 * shared pyramid, while a writer thread changes the field (hf_field_update_rect) and
 * refreshes the pyramid (hf_maxmip_update_rect). The documented protocol
 * (include/hfcast.h, "Thread safety"): readers hold a pthread rwlock in read mode
 * around their traces, the writer in write mode around the update and the refresh.
 * Each reader checks that the maxmip answers equal the exact ones, bit for bit, on
 * the field state both saw.
 *
 *   test_concurrency [ROUNDS]            the protocol: must be clean under helgrind
 *   test_concurrency --no-lock [ROUNDS]  the protocol broken (no lock taken):
 *       helgrind must report the race (the Makefile's `concurrency` target expects
 *       its report); answers may then disagree.
 * ROUNDS (default 1) multiplies the batches and the updates: the plain run takes
 * many, helgrind (about 50 times slower) one.
 *
 * Counters of check.h are touched by the main thread only; each thread counts in its
 * own job and the main thread checks the totals after joining. */
#define _POSIX_C_SOURCE 200112L
#include "hfcast.h"

#include "check.h"

#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 48, H = 40, READERS = 3, RAYS = 48, BATCHES = 40, UPDATES = 60, SIDE = 6 };

/* What every thread shares: the field, its pyramid, the lock, and the update count
 * (written by the writer, read by readers, both under the lock). */
typedef struct {
    hf_field *field;
    float *pyramid;
    size_t pyramid_len;
    pthread_rwlock_t lock;
    int use_lock;
    int rounds;
    unsigned generation;
} shared_state;

/* One reader's work and what it saw. */
typedef struct {
    shared_state *s;
    uint32_t seed;
    int batches, errors, mismatches;
    unsigned first_generation, last_generation;
} reader_job;

/* One writer's work. */
typedef struct {
    shared_state *s;
    uint32_t seed;
    int updates, errors;
} writer_job;

/* A per-thread pseudo-random number in [0, 1). */
static float frand(uint32_t *state) {
    *state = *state * 1664525u + 1013904223u;
    return (float)(*state >> 8) / 16777216.0f;
}

static void lock(shared_state *s, int write) {
    if (!s->use_lock) return;
    if (write) pthread_rwlock_wrlock(&s->lock);
    else pthread_rwlock_rdlock(&s->lock);
}

static void unlock(shared_state *s) {
    if (s->use_lock) pthread_rwlock_unlock(&s->lock);
}

/* The same answer as test_api.c's test_methods_agree compares: hit, t, point, flags. */
static int same_hit(const hf_hit *a, const hf_hit *b) {
    return a->hit == b->hit && a->t == b->t &&
           memcmp(a->point, b->point, sizeof a->point) == 0 && a->flags == b->flags;
}

static void *reader(void *arg) {
    reader_job *j = (reader_job *)arg;
    shared_state *s = j->s;
    hf_ray rays[RAYS];
    hf_hit exact[RAYS], maxmip[RAYS];
    for (int k = 0; k < RAYS; k++) {
        hf_ray *r = &rays[k];
        r->origin[0] = -4.0f + (W + 8) * frand(&j->seed);
        r->origin[1] = -4.0f + (H + 8) * frand(&j->seed);
        r->origin[2] = 10.0f * frand(&j->seed);
        r->dir[0] = k % 7 == 0 ? 0.0f : frand(&j->seed) - 0.5f; /* some axis-parallel */
        r->dir[1] = frand(&j->seed) - 0.5f;
        r->dir[2] = -frand(&j->seed);
        r->t_min = 0.0f;
        r->t_max = INFINITY;
    }
    for (int b = 0; b < BATCHES * s->rounds; b++) {
        hf_trace_options o;
        hf_trace_options_default(&o);
        o.surface = HF_SURFACE_TRIANGLES + (uint32_t)b % 5; /* the five surfaces */
        lock(s, 0);
        /* Without the lock the count is not read: the only races left are the
         * library's reads of what the writer changes. */
        unsigned g = s->use_lock ? s->generation : 0;
        hf_result r1 = hf_trace_batch(s->field, HF_METHOD_EXACT, NULL, 0, &o, rays, RAYS, exact,
                                      RAYS);
        hf_result r2 = hf_trace_batch(s->field, HF_METHOD_MAXMIP, s->pyramid, s->pyramid_len, &o,
                                      rays, RAYS, maxmip, RAYS);
        unlock(s);
        if (b == 0) j->first_generation = g;
        j->last_generation = g;
        j->batches++;
        j->errors += (r1 != HF_OK) + (r2 != HF_OK);
        for (int k = 0; k < RAYS; k++) j->mismatches += !same_hit(&exact[k], &maxmip[k]);
        sched_yield();
    }
    return NULL;
}

static void *writer(void *arg) {
    writer_job *j = (writer_job *)arg;
    shared_state *s = j->s;
    float values[SIDE * SIDE];
    for (int u = 0; u < UPDATES * s->rounds; u++) {
        uint32_t w = 1 + (uint32_t)(SIDE * frand(&j->seed)) % SIDE;
        uint32_t h = 1 + (uint32_t)(SIDE * frand(&j->seed)) % SIDE;
        uint32_t x0 = (uint32_t)((W - w) * frand(&j->seed));
        uint32_t y0 = (uint32_t)((H - h) * frand(&j->seed));
        for (int k = 0; k < SIDE * SIDE; k++) values[k] = 8.0f * frand(&j->seed);
        lock(s, 1);
        hf_result r1 = hf_field_update_rect(s->field, x0, y0, x0 + w, y0 + h, values,
                                            SIDE * SIDE, SIDE);
        hf_result r2 = hf_maxmip_update_rect(s->field, x0, y0, x0 + w, y0 + h, s->pyramid,
                                             s->pyramid_len);
        if (s->use_lock) s->generation++;
        unlock(s);
        j->updates++;
        j->errors += (r1 != HF_OK) + (r2 != HF_OK);
        sched_yield();
    }
    return NULL;
}

int main(int argc, char **argv) {
    shared_state s;
    memset(&s, 0, sizeof s);
    s.use_lock = 1;
    s.rounds = 1;
    for (int a = 1; a < argc; a++) {
        if (strcmp(argv[a], "--no-lock") == 0) s.use_lock = 0;
        else s.rounds = atoi(argv[a]) > 0 ? atoi(argv[a]) : 1;
    }
    uint32_t seed = 2026u;
    float heights[W * H];
    for (int k = 0; k < W * H; k++) heights[k] = 8.0f * frand(&seed);
    CHECK(hf_field_create_f32(heights, W * H, W, H, W, &s.field) == HF_OK);
    CHECK(hf_map_len(HF_METHOD_MAXMIP, W, H, NULL, &s.pyramid_len) == HF_OK);
    s.pyramid = (float *)malloc(sizeof(float) * s.pyramid_len);
    CHECK(s.pyramid != NULL);
    CHECK(hf_bake(HF_METHOD_MAXMIP, s.field, NULL, s.pyramid, s.pyramid_len) == HF_OK);
    CHECK(pthread_rwlock_init(&s.lock, NULL) == 0);

    pthread_t th[READERS + 1];
    reader_job readers[READERS];
    writer_job wj = {&s, 7u, 0, 0};
    CHECK(pthread_create(&th[READERS], NULL, writer, &wj) == 0);
    for (int t = 0; t < READERS; t++) {
        reader_job r = {&s, 100u + (uint32_t)t, 0, 0, 0, 0, 0};
        readers[t] = r;
        CHECK(pthread_create(&th[t], NULL, reader, &readers[t]) == 0);
    }
    for (int t = 0; t <= READERS; t++) CHECK(pthread_join(th[t], NULL) == 0);

    int batches = 0, mismatches = 0, overlapped = 0;
    for (int t = 0; t < READERS; t++) {
        CHECK(readers[t].errors == 0);
        batches += readers[t].batches;
        mismatches += readers[t].mismatches;
        /* A reader that saw the field change between its batches ran beside the writer. */
        overlapped += readers[t].first_generation != readers[t].last_generation;
    }
    CHECK(wj.errors == 0 && wj.updates == UPDATES * s.rounds);
    CHECK(batches == READERS * BATCHES * s.rounds);
    if (s.use_lock) {
        CHECK(mismatches == 0);
        CHECK(s.generation == (unsigned)(UPDATES * s.rounds));
        /* Informative: helgrind serialises threads, so a reader may run alone. */
        printf("concurrency: %d readers x %d batches of %d rays (exact and maxmip, 5 "
               "surfaces), %d updates; %d readers traced across updates; maxmip "
               "identical\n",
               READERS, BATCHES * s.rounds, RAYS, UPDATES * s.rounds, overlapped);
    } else {
        /* The protocol is broken on purpose: no check on the answers, only a count. */
        printf("concurrency --no-lock: %d of %d maxmip answers differed from the exact "
               "ones (no lock: a race, for the tool to report)\n",
               mismatches, batches * RAYS);
    }

    pthread_rwlock_destroy(&s.lock);
    free(s.pyramid);
    hf_field_destroy(s.field);
    /* The summary line scripts/test.sh counts, for the run that keeps the protocol. */
    if (s.use_lock) printf("c-concurrency: %d passed, %d failed\n", checks - failures, failures);
    return failures == 0 ? 0 : 1;
}
