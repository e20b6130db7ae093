/*
 * Little-endian wire byte order for the protocol's field types, and the error codes the
 * protocol functions return. Explicit byte packing: never rely on struct layout. Float
 * and signed values are reinterpreted through unions of exact-width types (defined in
 * C99/C11; exact-width signed types are two's complement), so NaN payloads and -0.0
 * travel bit-exact.
 */
#ifndef AW_WIRE_H
#define AW_WIRE_H

#include <stdint.h>

enum {
    AW_ERR_NO_SPACE = -1,   /* output buffer smaller than the worst case */
    AW_ERR_UNKNOWN_ID = -2, /* message id not in this schema */
    AW_ERR_SIZE = -3,       /* payload length does not match the message */
};

static inline void aw_put_u8(uint8_t *p, uint8_t v) { p[0] = v; }

static inline void aw_put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static inline void aw_put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static inline void aw_put_u64(uint8_t *p, uint64_t v)
{
    aw_put_u32(p, (uint32_t)v);
    aw_put_u32(p + 4, (uint32_t)(v >> 32));
}

static inline void aw_get_u8(uint8_t *v, const uint8_t *p) { *v = p[0]; }

static inline void aw_get_u16(uint16_t *v, const uint8_t *p)
{
    *v = (uint16_t)((unsigned)p[0] | ((unsigned)p[1] << 8));
}

static inline void aw_get_u32(uint32_t *v, const uint8_t *p)
{
    *v = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static inline void aw_get_u64(uint64_t *v, const uint8_t *p)
{
    uint32_t lo, hi;
    aw_get_u32(&lo, p);
    aw_get_u32(&hi, p + 4);
    *v = (uint64_t)lo | ((uint64_t)hi << 32);
}

#define AW_WIRE_PUN(NAME, T, U, BITS)                                                   \
    static inline void aw_put_##NAME(uint8_t *p, T v)                                    \
    {                                                                                    \
        const union { T t; U u; } x = {.t = v};                                          \
        aw_put_u##BITS(p, x.u);                                                          \
    }                                                                                    \
    static inline void aw_get_##NAME(T *v, const uint8_t *p)                             \
    {                                                                                    \
        union { T t; U u; } x;                                                           \
        aw_get_u##BITS(&x.u, p);                                                         \
        *v = x.t;                                                                        \
    }

AW_WIRE_PUN(i8, int8_t, uint8_t, 8)
AW_WIRE_PUN(i16, int16_t, uint16_t, 16)
AW_WIRE_PUN(i32, int32_t, uint32_t, 32)
AW_WIRE_PUN(i64, int64_t, uint64_t, 64)
AW_WIRE_PUN(f32, float, uint32_t, 32)
AW_WIRE_PUN(f64, double, uint64_t, 64)

#undef AW_WIRE_PUN

#endif /* AW_WIRE_H */
