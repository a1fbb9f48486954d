/* jsontext.c: valid UTF-8 in the tools' JSON (sss/jsontext.h). */
#include "sss/jsontext.h"

#include <cjson/cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Length of the valid UTF-8 sequence at s[0 .. n), or 0 (RFC 3629 §4). */
static size_t seq_len(const unsigned char *s, size_t n)
{
    const unsigned char c = s[0];
    if (c < 0x80) return 1;
    size_t len;
    uint32_t cp, min;
    if ((c & 0xE0) == 0xC0) len = 2, cp = c & 0x1F, min = 0x80;
    else if ((c & 0xF0) == 0xE0) len = 3, cp = c & 0x0F, min = 0x800;
    else if ((c & 0xF8) == 0xF0) len = 4, cp = c & 0x07, min = 0x10000;
    else return 0;
    if (len > n) return 0;
    for (size_t i = 1; i < len; i++) {
        if ((s[i] & 0xC0) != 0x80) return 0;
        cp = cp << 6 | (s[i] & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    return len;
}

int sss_utf8_valid(const char *s, size_t n)
{
    const unsigned char *u = (const unsigned char *)s;
    for (size_t i = 0; i < n;) {
        const size_t k = seq_len(u + i, n - i);
        if (!k) return 0;
        i += k;
    }
    return 1;
}

/* s with every invalid byte as \xNN, malloc'ed; NULL when out of memory. */
static char *escaped(const char *s)
{
    const size_t n = strlen(s);
    char *o = malloc(4 * n + 1);
    if (!o) return NULL;
    const unsigned char *u = (const unsigned char *)s;
    size_t k = 0;
    for (size_t i = 0; i < n;) {
        const size_t l = seq_len(u + i, n - i);
        if (l) {
            memcpy(o + k, s + i, l);
            k += l;
            i += l;
        } else {
            k += (size_t)snprintf(o + k, 5, "\\x%02X", u[i]);
            i++;
        }
    }
    o[k] = 0;
    return o;
}

/* *p replaced by its escaped form when not valid UTF-8 (cJSON's strings
 * are malloc'ed by its default hooks, which the tools keep). */
static int fix(char **p)
{
    if (!*p || sss_utf8_valid(*p, strlen(*p))) return 0;
    char *e = escaped(*p);
    if (!e) return -1;
    free(*p);
    *p = e;
    return 0;
}

static int fix_node(cJSON *n)
{
    int rc = 0;
    if (n->string && !(n->type & cJSON_StringIsConst) && fix(&n->string) != 0) rc = -1;
    if ((n->type & 0xFF) == cJSON_String && !(n->type & cJSON_IsReference) && fix(&n->valuestring) != 0) rc = -1;
    for (cJSON *c = n->child; c; c = c->next)
        if (fix_node(c) != 0) rc = -1;
    return rc;
}

int sss_json_utf8(cJSON *item) { return item ? fix_node(item) : 0; }
