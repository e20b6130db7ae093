/* Minimal harness for the board-algorithm tests (test_losa_*, test_marker_*,
 * test_rover_*, test_base_*, test_quat*): checks count failures, RUN prints one line
 * per test, the program exits non-zero when anything failed. */
#ifndef AW_TEST_ALGOS_H
#define AW_TEST_ALGOS_H

#include <math.h>
#include <stdio.h>

static int algo_failures;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
            algo_failures++;                                                         \
        }                                                                            \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                  \
    do {                                                                                       \
        const double a_ = (double)(a), b_ = (double)(b);                                       \
        if (!(fabs(a_ - b_) <= (double)(tol))) {                                               \
            fprintf(stderr, "%s:%d: CHECK_NEAR failed: %s = %.9g, %s = %.9g (tol %g)\n", __FILE__, \
                    __LINE__, #a, a_, #b, b_, (double)(tol));                                  \
            algo_failures++;                                                                   \
        }                                                                                      \
    } while (0)

#define RUN(test)                                                        \
    do {                                                                 \
        const int before_ = algo_failures;                               \
        test();                                                          \
        printf("%s %s\n", before_ == algo_failures ? "ok  " : "FAIL", #test); \
    } while (0)

#define ALGO_TEST_EXIT() (algo_failures ? 1 : 0)

#endif
