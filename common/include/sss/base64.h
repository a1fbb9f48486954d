/* sss/base64.h: the base64 alphabet of RFC 4648 §4 (with '=' padding), as
 * glTF 2.0 embeds buffers in "data:" URIs: sss-genmesh writes them and the
 * glTF importer reads them (docs/robustness.md, "glTF"). */
#ifndef SSS_BASE64_H
#define SSS_BASE64_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Characters sss_base64_encode writes for n bytes (without the NUL). */
size_t sss_base64_encoded_len(size_t n);

/* Writes the encoding of in[0..n) and a terminating NUL to out, which holds
 * sss_base64_encoded_len(n) + 1 characters. */
void sss_base64_encode(const uint8_t *in, size_t n, char *out);

/* Decodes text[0..len) into out (room for len / 4 * 3 bytes). Strict: the
 * length is a multiple of 4, only the alphabet, '=' only as the last one or
 * two characters. Returns the byte count, or -1 with *bad set to the
 * position of the first character that breaks the rules. */
long long sss_base64_decode(const char *text, size_t len, uint8_t *out, size_t *bad);

#ifdef __cplusplus
}
#endif
#endif
