/* sss/jsontext.h: text that goes into the tools' JSON (README.md: --json is
 * one JSON object). JSON strings are Unicode: a file name is any bytes on
 * POSIX, so a name that is not valid UTF-8 would make the output invalid
 * JSON. Every string and key of a cJSON tree is made valid UTF-8 before it
 * is printed: each byte that is not part of a valid UTF-8 sequence is
 * written as the four characters \xNN (its hex value), which JSON shows as
 * "\\xNN" — visible, reversible and valid (docs/robustness.md, item 9). */
#ifndef SSS_JSONTEXT_H
#define SSS_JSONTEXT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

struct cJSON;

/* Rewrites, in place, every string value and key under item that is not
 * valid UTF-8 (NULL-safe). Returns 0, or -1 when out of memory (the strings
 * concerned are then left as they were). */
int sss_json_utf8(struct cJSON *item);

/* Whether the n bytes at s are valid UTF-8 (no overlong forms, no
 * surrogates, nothing above U+10FFFF). */
int sss_utf8_valid(const char *s, size_t n);

#ifdef __cplusplus
}
#endif
#endif
