/* format_bytes.h (internal): little-endian packing and overflow-checked
 * 64-bit size arithmetic shared by the .sss encoder and decoder (format.c
 * and the section codecs in sections/). Field by field, never struct
 * dumps, so host byte order and padding never reach a file
 * (docs/format.md §1). */
#ifndef SSS_FORMAT_BYTES_H
#define SSS_FORMAT_BYTES_H
#include <stdint.h>
#include <string.h>

/* ---- byte packing ---------------------------------------------------- */

static inline void put_u16(uint8_t *p, uint16_t v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); }
static inline void put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static inline void put_u64(uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static inline void put_f32(uint8_t *p, float x) { uint32_t u; memcpy(&u, &x, 4); put_u32(p, u); }
static inline void put_f64(uint8_t *p, double x) { uint64_t u; memcpy(&u, &x, 8); put_u64(p, u); }

static inline uint16_t get_u16(const uint8_t *p) { return (uint16_t)(p[0] | (unsigned)p[1] << 8); }
static inline uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static inline uint64_t get_u64(const uint8_t *p) { return (uint64_t)get_u32(p) | (uint64_t)get_u32(p + 4) << 32; }
static inline float get_f32(const uint8_t *p) { uint32_t u = get_u32(p); float x; memcpy(&x, &u, 4); return x; }
static inline double get_f64(const uint8_t *p) { uint64_t u = get_u64(p); double x; memcpy(&x, &u, 8); return x; }

/* ---- overflow-checked 64-bit arithmetic ------------------------------ */

static inline int mul_u64(uint64_t a, uint64_t b, uint64_t *r)
{
    if (a != 0 && b > UINT64_MAX / a) return 0;
    *r = a * b;
    return 1;
}
static inline int add_u64(uint64_t a, uint64_t b, uint64_t *r)
{
    if (b > UINT64_MAX - a) return 0;
    *r = a + b;
    return 1;
}
/* a*b + c*d + e, 0 on overflow. */
static inline int lin_u64(uint64_t a, uint64_t b, uint64_t c, uint64_t d, uint64_t e, uint64_t *r)
{
    uint64_t x, y;
    return mul_u64(a, b, &x) && mul_u64(c, d, &y) && add_u64(x, y, &x) && add_u64(x, e, r);
}

#endif
