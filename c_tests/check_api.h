/* The C API checks test_api.c and test_ktx2.c share (on top of check.h): CHECK_OK(call)
 * expects HF_OK; CHECK_BAD(call, code, out, len) expects `code` and the `len` bytes at
 * `out` unchanged (outputs are written only on success), counting the bad inputs tried. */
#ifndef HFCAST_C_TESTS_CHECK_API_H
#define HFCAST_C_TESTS_CHECK_API_H

#include "check.h"

#include <string.h>

static int bad_inputs = 0;

#define CHECK_OK(call)                                                             \
    do {                                                                           \
        hf_result r_ = (call);                                                     \
        checks++;                                                                  \
        if (r_ != HF_OK) {                                                         \
            failures++;                                                            \
            fprintf(stderr, "%s:%d: %s returned %u\n", __FILE__, __LINE__, #call,  \
                    (unsigned)r_);                                                 \
        }                                                                          \
    } while (0)

/* A bad call: must return `code` and leave the `len` bytes at `out` as they were. */
#define CHECK_BAD(call, code, out, len)                                            \
    do {                                                                           \
        unsigned char before_[512];                                                \
        size_t n_ = (len) < sizeof before_ ? (size_t)(len) : sizeof before_;       \
        memcpy(before_, (out), n_);                                               \
        hf_result r_ = (call);                                                     \
        checks++;                                                                  \
        bad_inputs++;                                                              \
        if (r_ != (code)) {                                                        \
            failures++;                                                            \
            fprintf(stderr, "%s:%d: %s returned %u, expected %s (%u)\n", __FILE__, \
                    __LINE__, #call, (unsigned)r_, #code, (unsigned)(code));       \
        } else if (memcmp(before_, (out), n_) != 0) {                              \
            failures++;                                                            \
            fprintf(stderr, "%s:%d: %s wrote its output on error\n", __FILE__,     \
                    __LINE__, #call);                                              \
        }                                                                          \
    } while (0)

#endif
