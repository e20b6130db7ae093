/* Little-endian field readers for the peer parsers (VN200, SBP): byte assembly plus
 * memcpy, so they are alignment- and host-endianness-safe and free of UB. */
#ifndef AW_LE_BYTES_H
#define AW_LE_BYTES_H

#include <stdint.h>
#include <string.h>

static inline uint16_t le_u16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

static inline uint32_t le_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static inline uint64_t le_u64(const uint8_t *p)
{
    return (uint64_t)le_u32(p) | ((uint64_t)le_u32(p + 4) << 32);
}

static inline int16_t le_i16(const uint8_t *p)
{
    const uint16_t u = le_u16(p);
    int16_t v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static inline int32_t le_i32(const uint8_t *p)
{
    const uint32_t u = le_u32(p);
    int32_t v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static inline float le_f32(const uint8_t *p)
{
    const uint32_t u = le_u32(p);
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static inline double le_f64(const uint8_t *p)
{
    const uint64_t u = le_u64(p);
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
}

#endif
