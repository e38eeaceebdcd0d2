/* The check macro and counters the C test programs share (test_api.c, one_method.c):
 * CHECK(cond) counts a check and reports a failed one with its file and line; the
 * program prints `checks - failures` passed and `failures` failed at the end. */
#ifndef HFCAST_C_TESTS_CHECK_H
#define HFCAST_C_TESTS_CHECK_H

#include <stdio.h>

static int failures = 0;
static int checks = 0;

#define CHECK(cond)                                                                \
    do {                                                                           \
        checks++;                                                                  \
        if (!(cond)) {                                                             \
            failures++;                                                            \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
        }                                                                          \
    } while (0)

#endif
