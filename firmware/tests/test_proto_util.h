/* Helpers shared by the protocol C tests: checks, a seeded PRNG, message filling. */
#ifndef TEST_PROTO_UTIL_H
#define TEST_PROTO_UTIL_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aw_frame.h"

static int tp_failures;
static int tp_checks;

#define CHECK(cond)                                                                      \
    do {                                                                                 \
        ++tp_checks;                                                                     \
        if (!(cond)) {                                                                   \
            ++tp_failures;                                                               \
            fprintf(stderr, "%s:%d: %s: check failed: %s\n", __FILE__, __LINE__, __func__, \
                    #cond);                                                              \
        }                                                                                \
    } while (0)

#define CHECK_EQ_U(a, b)                                                                 \
    do {                                                                                 \
        ++tp_checks;                                                                     \
        const unsigned long long a_ = (unsigned long long)(a), b_ = (unsigned long long)(b); \
        if (a_ != b_) {                                                                  \
            ++tp_failures;                                                               \
            fprintf(stderr, "%s:%d: %s: %s == %llu, expected %s == %llu\n", __FILE__,    \
                    __LINE__, __func__, #a, a_, #b, b_);                                 \
        }                                                                                \
    } while (0)

#define RUN(test)                                                                        \
    do {                                                                                 \
        const int before_ = tp_failures;                                                 \
        test();                                                                          \
        printf("%s %s\n", tp_failures == before_ ? "ok  " : "FAIL", #test);              \
    } while (0)

static inline int tp_finish(void)
{
    printf("%d checks, %d failed\n", tp_checks, tp_failures);
    return tp_failures == 0 ? 0 : 1;
}

/* xorshift64*: deterministic test randomness */
typedef struct {
    uint64_t s;
} tp_rng_t;

static inline uint64_t tp_next(tp_rng_t *r)
{
    r->s ^= r->s >> 12;
    r->s ^= r->s << 25;
    r->s ^= r->s >> 27;
    return r->s * UINT64_C(2685821657736338717);
}

static inline uint32_t tp_below(tp_rng_t *r, uint32_t n)
{
    return (uint32_t)(tp_next(r) % n);
}

/* Random payload bytes; zero_permille of them zero (COBS paths depend on zeros). */
static inline void tp_fill(tp_rng_t *r, uint8_t *p, size_t n, uint32_t zero_permille)
{
    for (size_t i = 0; i < n; ++i) {
        p[i] = tp_below(r, 1000) < zero_permille ? 0 : (uint8_t)(1 + tp_below(r, 255));
    }
}

#endif /* TEST_PROTO_UTIL_H */
