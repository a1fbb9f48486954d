/* base64.c: RFC 4648 §4 base64 (sss/base64.h). */
#include "sss/base64.h"

static const char ALPHABET[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

size_t sss_base64_encoded_len(size_t n) { return (n + 2) / 3 * 4; }

void sss_base64_encode(const uint8_t *in, size_t n, char *out)
{
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t w = (uint32_t)in[i] << 16;
        if (i + 1 < n) w |= (uint32_t)in[i + 1] << 8;
        if (i + 2 < n) w |= in[i + 2];
        out[o++] = ALPHABET[(w >> 18) & 63];
        out[o++] = ALPHABET[(w >> 12) & 63];
        out[o++] = i + 1 < n ? ALPHABET[(w >> 6) & 63] : '=';
        out[o++] = i + 2 < n ? ALPHABET[w & 63] : '=';
    }
    out[o] = '\0';
}

/* The 6-bit value of c, or -1. */
static int sextet(char c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

long long sss_base64_decode(const char *text, size_t len, uint8_t *out, size_t *bad)
{
    if (len % 4 != 0) {
        *bad = len;
        return -1;
    }
    size_t o = 0;
    for (size_t i = 0; i < len; i += 4) {
        int pad = 0;
        uint32_t w = 0;
        for (int k = 0; k < 4; k++) {
            char c = text[i + (size_t)k];
            int v = sextet(c);
            /* '=' only in the last group, at its last one or two places */
            if (v < 0 && c == '=' && i + 4 == len && k >= 2 && (k == 3 || text[i + 3] == '=')) {
                pad++;
                v = 0;
            } else if (v < 0 || pad) {
                *bad = i + (size_t)k;
                return -1;
            }
            w = w << 6 | (uint32_t)v;
        }
        out[o++] = (uint8_t)(w >> 16);
        if (pad < 2) out[o++] = (uint8_t)(w >> 8);
        if (pad < 1) out[o++] = (uint8_t)w;
    }
    return (long long)o;
}
