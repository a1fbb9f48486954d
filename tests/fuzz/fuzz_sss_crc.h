/* fuzz_sss_crc.h: the CRC repair the .sss harnesses share (fuzz_sss.c,
 * fuzz_view.c): every input is tried as given and with the checksums of its
 * sections and header recomputed where the table's offsets and sizes lie
 * inside it (docs/format.md §2–3), so that mutations reach the section
 * checks behind the checksums. Header-only (each harness is one program). */
#ifndef SSS_FUZZ_SSS_CRC_H
#define SSS_FUZZ_SSS_CRC_H

#include <stddef.h>
#include <stdint.h>

#include "sss/format.h"
#include "test_util.h"

static inline void fuzz_wr32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}

/* Recomputes the CRCs of a file image in place. */
static inline void fuzz_repair_crcs(uint8_t *b, size_t len)
{
    if (len < 28) return;
    uint32_t n = test_rd32(b + 12);
    if (n > 32 || 28 + 40 * (size_t)n > len) return;
    for (uint32_t i = 0; i < n; i++) {
        uint8_t *e = b + 24 + 40 * (size_t)i;
        uint64_t off = test_rd64(e + 8), sz = test_rd64(e + 16);
        if (off <= len && sz <= len - off) fuzz_wr32(e + 32, sss_crc32(0, b + off, (size_t)sz));
    }
    fuzz_wr32(b + 24 + 40 * (size_t)n, sss_crc32(0, b, 24 + 40 * (size_t)n));
}

#endif
