/* test_format.c: the .sss file format v1 (docs/format.md): exact round trips,
 * atomic writes, rejection of every truncation and every flipped byte,
 * version and section rules, hostile headers, the CPU decoder, and a
 * committed golden file that pins the v1 byte layout.
 *
 * Files are edited here with the test's own little-endian helpers and CRC
 * (independent of the library), so the checks behind the checksums are
 * reachable: an edit followed by fix-up of the CRCs must still be rejected.
 *
 * SSS_WRITE_GOLDEN=1 ./test_format regenerates tests/data/golden_v1.sss
 * (only do that for a new major version: old files must keep reading).
 */
#define _POSIX_C_SOURCE 200809L

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sss/decode.h"
#include "sss/dirset.h"
#include "sss/format.h"
#include "test_util.h"

#define GOLDEN_PATH SSS_TEST_DATA "/golden_v1.sss"
#define HDR 24u
#define ENT 40u

/* ---- test-side little-endian helpers and a bitwise CRC ----------------- */

static void wr16(uint8_t *p, uint16_t v) { p[0] = (uint8_t)v; p[1] = (uint8_t)(v >> 8); }
static void wr32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static void wr64(uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static void wrf32(uint8_t *p, float x) { uint32_t u; memcpy(&u, &x, 4); wr32(p, u); }
static void wrf64(uint8_t *p, double x) { uint64_t u; memcpy(&u, &x, 8); wr64(p, u); }

static uint32_t ref_crc32(const uint8_t *p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

/* Recomputes the header CRC after an edit of bytes 0 .. end of table. */
static void fix_header_crc(uint8_t *b)
{
    uint32_t n = test_rd32(b + 12);
    wr32(b + HDR + ENT * n, ref_crc32(b, HDR + ENT * (size_t)n));
}

/* A file taken apart into sections and put back together with fresh
 * offsets, sizes, CRCs and file size. */
typedef struct tsec {
    char tag[5];
    uint32_t flags;
    uint64_t count;
    uint8_t *data;
    size_t size;
} tsec;

typedef struct tfile {
    uint16_t major, minor;
    uint32_t n;
    tsec s[40];
} tfile;

static void t_split(const uint8_t *b, size_t len, tfile *t)
{
    (void)len;
    memset(t, 0, sizeof *t);
    t->major = (uint16_t)(b[8] | b[9] << 8);
    t->minor = (uint16_t)(b[10] | b[11] << 8);
    t->n = test_rd32(b + 12);
    assert_true(t->n <= 32);
    for (uint32_t i = 0; i < t->n; i++) {
        const uint8_t *e = b + HDR + ENT * i;
        tsec *s = &t->s[i];
        memcpy(s->tag, e, 4);
        s->flags = test_rd32(e + 4);
        s->count = test_rd64(e + 24);
        s->size = (size_t)test_rd64(e + 16);
        s->data = malloc(s->size + 1);
        assert_non_null(s->data);
        memcpy(s->data, b + test_rd64(e + 8), s->size);
    }
}

static uint8_t *t_join(const tfile *t, size_t *len)
{
    size_t h = HDR + ENT * (size_t)t->n + 4, total = h;
    for (uint32_t i = 0; i < t->n; i++) total += t->s[i].size;
    uint8_t *b = calloc(total, 1);
    assert_non_null(b);
    static const uint8_t magic[8] = {0x89, 'S', 'S', 'S', '\r', '\n', 0x1A, '\n'};
    memcpy(b, magic, 8);
    wr16(b + 8, t->major);
    wr16(b + 10, t->minor);
    wr32(b + 12, t->n);
    wr64(b + 16, total);
    size_t off = h;
    for (uint32_t i = 0; i < t->n; i++) {
        const tsec *s = &t->s[i];
        uint8_t *e = b + HDR + ENT * i;
        memcpy(e, s->tag, 4);
        wr32(e + 4, s->flags);
        wr64(e + 8, off);
        wr64(e + 16, s->size);
        wr64(e + 24, s->count);
        wr32(e + 32, ref_crc32(s->data, s->size));
        wr32(e + 36, 0);
        memcpy(b + off, s->data, s->size);
        off += s->size;
    }
    fix_header_crc(b);
    *len = total;
    return b;
}

static void t_free(tfile *t)
{
    for (uint32_t i = 0; i < t->n; i++) free(t->s[i].data);
    memset(t, 0, sizeof *t);
}

static tsec *t_find(tfile *t, const char *tag)
{
    for (uint32_t i = 0; i < t->n; i++)
        if (memcmp(t->s[i].tag, tag, 4) == 0) return &t->s[i];
    fail_msg("no section %s", tag);
    return NULL;
}

static int t_has(const tfile *t, const char *tag)
{
    for (uint32_t i = 0; i < t->n; i++)
        if (memcmp(t->s[i].tag, tag, 4) == 0) return 1;
    return 0;
}

static void t_remove(tfile *t, const char *tag)
{
    tsec *s = t_find(t, tag);
    free(s->data);
    size_t i = (size_t)(s - t->s);
    memmove(&t->s[i], &t->s[i + 1], (t->n - i - 1) * sizeof *s);
    t->n--;
}

static void t_append(tfile *t, const char *tag, uint32_t flags, const void *data, size_t size)
{
    tsec *s = &t->s[t->n++];
    memset(s, 0, sizeof *s);
    memcpy(s->tag, tag, 4);
    s->flags = flags;
    s->count = size;
    s->size = size;
    s->data = malloc(size + 1);
    assert_non_null(s->data);
    memcpy(s->data, data, size);
}

/* ---- deterministic content --------------------------------------------- */

static const double PI = 3.14159265358979323846;

/* Regular octahedron, unit radius: 6 vertices, 8 counter-clockwise faces,
 * normals = positions. */
static void make_octahedron(sss_mesh *m)
{
    static const float P[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const uint32_t T[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                     {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    assert_int_equal(sss_mesh_alloc(m, 6, 8, NULL), SSS_OK);
    m->nrm = malloc(sizeof P);
    assert_non_null(m->nrm);
    memcpy(m->pos, P, sizeof P);
    memcpy(m->nrm, P, sizeof P);
    memcpy(m->tri, T, sizeof T);
}

/* A bake-like file: q = albedo_c (0.05 + 0.95 max(0, n_v · ω_j)) / π, a
 * Lloyd table of evenly spaced levels and indices from a fixed pattern. */
static void make_file(sss_bake_file *f, uint32_t ndirs, uint32_t channels, sss_quant quant)
{
    memset(f, 0, sizeof *f);
    make_octahedron(&f->mesh);
    strcpy(f->material.name, "skin1");
    const double sa[3] = {0.032, 0.17, 0.48}, ss[3] = {0.74, 0.88, 1.01};
    for (int c = 0; c < 3; c++) { f->material.sigma_a[c] = sa[c]; f->material.sigmap_s[c] = ss[c]; }
    f->material.eta = 1.3;
    f->mm_per_unit = 12.5;
    f->channels = channels;
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_fibonacci(&f->dirs, ndirs, &err), SSS_OK);
    f->quant = quant;
    size_t nv = f->mesh.nv, nq = (size_t)ndirs * nv * channels;
    if (quant == SSS_QUANT_FLOAT) {
        f->q = malloc(nq * sizeof(float));
        assert_non_null(f->q);
        for (uint32_t j = 0; j < ndirs; j++)
            for (size_t v = 0; v < nv; v++) {
                const double *w = &f->dirs.dir[3 * (size_t)j];
                const float *n = &f->mesh.nrm[3 * v];
                double cosv = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
                for (uint32_t c = 0; c < channels; c++) {
                    double albedo = 0.2 + 0.3 * c;
                    f->q[(j * nv + v) * channels + c] = (float)(albedo * (0.05 + 0.95 * fmax(0.0, cosv)) / PI);
                }
            }
    } else {
        f->levels = malloc((size_t)channels * 256 * sizeof(float));
        f->qidx = malloc(nq + 1);
        assert_non_null(f->levels);
        assert_non_null(f->qidx);
        for (uint32_t c = 0; c < channels; c++)
            for (int k = 0; k < 256; k++) f->levels[c * 256 + k] = (float)k * 0.001f * (float)(c + 1);
        for (size_t i = 0; i < nq; i++) f->qidx[i] = (uint8_t)((i * 37u + 11u) & 255u);
    }
    const char *json = "{\"mesh\":\"octahedron\",\"material\":\"skin1\",\"ndirs\":12,\"eps\":0.01}";
    f->params_json = malloc(strlen(json) + 1);
    assert_non_null(f->params_json);
    strcpy(f->params_json, json);
}

static uint8_t *encode(const sss_bake_file *f, size_t *len)
{
    uint8_t *buf = NULL;
    sss_error err = {{0}};
    sss_result r = sss_file_encode(f, &buf, len, &err);
    if (r != SSS_OK) fail_msg("encode: %s", err.msg);
    return buf;
}

static uint8_t *encode_new(uint32_t ndirs, uint32_t channels, sss_quant quant, size_t *len)
{
    sss_bake_file f;
    make_file(&f, ndirs, channels, quant);
    uint8_t *b = encode(&f, len);
    sss_file_free(&f);
    return b;
}

static void assert_same_file(const sss_bake_file *a, const sss_bake_file *b)
{
    assert_int_equal(a->mesh.nv, b->mesh.nv);
    assert_int_equal(a->mesh.nf, b->mesh.nf);
    assert_memory_equal(a->mesh.pos, b->mesh.pos, 3 * a->mesh.nv * sizeof(float));
    assert_memory_equal(a->mesh.nrm, b->mesh.nrm, 3 * a->mesh.nv * sizeof(float));
    assert_memory_equal(a->mesh.tri, b->mesh.tri, 3 * a->mesh.nf * sizeof(uint32_t));
    assert_memory_equal(&a->material, &b->material, sizeof a->material);
    assert_memory_equal(&a->mm_per_unit, &b->mm_per_unit, sizeof(double));
    assert_int_equal(a->channels, b->channels);
    assert_int_equal(a->dirs.n, b->dirs.n);
    assert_int_equal(a->dirs.ntri, b->dirs.ntri);
    assert_memory_equal(a->dirs.dir, b->dirs.dir, 3 * a->dirs.n * sizeof(double));
    if (a->dirs.ntri) assert_memory_equal(a->dirs.tri, b->dirs.tri, 3 * a->dirs.ntri * sizeof(uint32_t));
    assert_int_equal(a->quant, b->quant);
    size_t nq = (size_t)a->dirs.n * a->mesh.nv * a->channels;
    if (a->quant == SSS_QUANT_FLOAT) {
        assert_memory_equal(a->q, b->q, nq * sizeof(float));
        assert_null(b->levels);
        assert_null(b->qidx);
    } else {
        assert_memory_equal(a->levels, b->levels, a->channels * 256 * sizeof(float));
        assert_memory_equal(a->qidx, b->qidx, nq);
        assert_null(b->q);
    }
    assert_string_equal(a->params_json, b->params_json);
}

static int is_zero(const void *p, size_t n)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < n; i++)
        if (c[i]) return 0;
    return 1;
}

/* Decodes and requires a rejection: non-OK (and `code` unless -1), a
 * non-empty message containing `needle` (unless NULL), *f left zeroed. */
static void expect_reject(const uint8_t *b, size_t len, int code, const char *needle)
{
    sss_bake_file f;
    sss_error err = {{0}};
    sss_result r = sss_file_decode(b, len, "t.sss", &f, &err);
    if (r == SSS_OK) fail_msg("accepted a bad file (len %zu)", len);
    if (code >= 0 && (int)r != code) fail_msg("result %d, expected %d: %s", (int)r, code, err.msg);
    assert_true(err.msg[0] != 0);
    assert_null(strchr(err.msg, '\n'));
    assert_true(strncmp(err.msg, "t.sss: ", 7) == 0);
    if (needle && !strstr(err.msg, needle)) fail_msg("message \"%s\" lacks \"%s\"", err.msg, needle);
    assert_true(is_zero(&f, sizeof f));
}

/* Rebuilds t into a file and requires its rejection. */
static void expect_reject_t(const tfile *t, int code, const char *needle)
{
    size_t len;
    uint8_t *b = t_join(t, &len);
    expect_reject(b, len, code, needle);
    free(b);
}

static void expect_accept(const uint8_t *b, size_t len, sss_bake_file *f)
{
    sss_error err = {{0}};
    sss_result r = sss_file_decode(b, len, "t.sss", f, &err);
    if (r != SSS_OK) fail_msg("rejected: %s", err.msg);
}

/* ---- CRC --------------------------------------------------------------- */

static void crc32MatchesCheckValueAndBitwiseReference(void **state)
{
    (void)state;
    assert_int_equal(sss_crc32(0, "123456789", 9), 0xCBF43926u);
    assert_int_equal(sss_crc32(sss_crc32(0, "1234", 4), "56789", 5), 0xCBF43926u);
    assert_int_equal(sss_crc32(0, "", 0), 0);
    assert_int_equal(sss_crc32(0, NULL, 0), 0);
    enum { N = 4099 };
    uint8_t *b = malloc(N);
    assert_non_null(b);
    uint32_t x = 12345;
    for (int i = 0; i < N; i++) { x = x * 1103515245u + 12345u; b[i] = (uint8_t)(x >> 24); }
    /* every start alignment and a spread of lengths, incl. the 8-byte path */
    for (size_t off = 0; off < 9; off++)
        for (size_t n = 0; n + off <= N; n += (n < 40 ? 1 : 397))
            assert_int_equal(sss_crc32(0, b + off, n), ref_crc32(b + off, n));
    /* chaining over an odd split equals one call */
    assert_int_equal(sss_crc32(sss_crc32(0, b, 1001), b + 1001, N - 1001), ref_crc32(b, N));
    free(b);
}

/* ---- round trips ------------------------------------------------------- */

static void round_trip(uint32_t ndirs, uint32_t channels, sss_quant quant)
{
    sss_bake_file a, b;
    make_file(&a, ndirs, channels, quant);
    size_t len;
    uint8_t *buf = encode(&a, &len);
    expect_accept(buf, len, &b);
    assert_same_file(&a, &b);
    assert_null(b.mesh.area);
    assert_int_equal(b.version_major, SSS_FORMAT_MAJOR);
    assert_int_equal(b.version_minor, 0); /* 1.0 sections only: written as 1.0 for 1.0 readers */
    assert_int_equal(b.file_size, len);
    assert_int_equal(b.nsections, 5);
    /* encoding is deterministic and decode∘encode is the identity on bytes */
    size_t len2;
    uint8_t *buf2 = encode(&b, &len2);
    assert_int_equal(len, len2);
    assert_memory_equal(buf, buf2, len);
    free(buf);
    free(buf2);
    sss_file_free(&a);
    sss_file_free(&b);
}

static void encodeDecodeRoundTripIsExactFloat(void **state) { (void)state; round_trip(12, 3, SSS_QUANT_FLOAT); }
static void encodeDecodeRoundTripIsExactLloyd8(void **state) { (void)state; round_trip(12, 3, SSS_QUANT_LLOYD8); }

static void encodeDecodeRoundTripIsExactGreyAndUntriangulated(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= 4; n++) {
        round_trip(n, 1, SSS_QUANT_FLOAT);
        round_trip(n, 1, SSS_QUANT_LLOYD8);
    }
}

static void encodeWritesDocumentedLayout(void **state)
{
    (void)state;
    sss_bake_file f;
    make_file(&f, 12, 3, SSS_QUANT_FLOAT);
    size_t len;
    uint8_t *b = encode(&f, &len);
    static const uint8_t magic[8] = {0x89, 'S', 'S', 'S', '\r', '\n', 0x1A, '\n'};
    assert_memory_equal(b, magic, 8);
    assert_int_equal(b[8] | b[9] << 8, SSS_FORMAT_MAJOR);
    assert_int_equal(b[10] | b[11] << 8, 0);
    assert_int_equal(test_rd32(b + 12), 5);
    assert_int_equal(test_rd64(b + 16), len);
    assert_int_equal(test_rd32(b + HDR + 5 * ENT), ref_crc32(b, HDR + 5 * ENT));
    static const char *tags[5] = {"GEOM", "MATL", "DIRS", "QFLT", "PARM"};
    static const uint32_t flags[5] = {1, 1, 1, 1, 0};
    const uint64_t counts[5] = {6, 3, 12, 12 * 6 * 3, strlen(f.params_json)};
    const uint64_t sizes[5] = {8 + 24 * 6 + 12 * 8, 100, 8 + 24 * 12 + 12 * 20, 4 * 12 * 6 * 3, strlen(f.params_json)};
    uint64_t off = HDR + 5 * ENT + 4;
    for (int i = 0; i < 5; i++) {
        const uint8_t *e = b + HDR + ENT * i;
        assert_memory_equal(e, tags[i], 4);
        assert_int_equal(test_rd32(e + 4), flags[i]);
        assert_int_equal(test_rd64(e + 8), off);
        assert_int_equal(test_rd64(e + 16), sizes[i]);
        assert_int_equal(test_rd64(e + 24), counts[i]);
        assert_int_equal(test_rd32(e + 32), ref_crc32(b + off, sizes[i]));
        assert_int_equal(test_rd32(e + 36), 0);
        if (i < 4) assert_int_equal(off % 4, 0); /* float arrays 4-byte aligned */
        off += sizes[i];
    }
    assert_int_equal(off, len);
    /* GEOM payload: counts, then x of vertex 0 as little-endian float32 1.0 */
    const uint8_t *g = b + test_rd64(b + HDR + 8);
    assert_int_equal(test_rd32(g), 6);
    assert_int_equal(test_rd32(g + 4), 8);
    assert_int_equal(test_rd32(g + 8), 0x3F800000u);
    /* MATL payload: name, then sigma_a[0] as little-endian float64 */
    const uint8_t *m = b + test_rd64(b + HDR + ENT + 8);
    assert_string_equal((const char *)m, "skin1");
    double sa0;
    uint64_t u = test_rd64(m + 32);
    memcpy(&sa0, &u, 8);
    assert_true(sa0 == 0.032);
    assert_int_equal(test_rd32(m + 96), 3);
    free(b);
    sss_file_free(&f);
}

/* ---- files ------------------------------------------------------------- */

static char tmpdir[256];

static int setup_tmpdir(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/sss_test_format.XXXXXX");
    return mkdtemp(tmpdir) ? 0 : -1;
}

static int teardown_tmpdir(void **state)
{
    (void)state;
    DIR *d = opendir(tmpdir);
    if (d) {
        struct dirent *e;
        char p[512];
        while ((e = readdir(d)) != NULL) {
            if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
            snprintf(p, sizeof p, "%s/%s", tmpdir, e->d_name);
            if (remove(p) != 0) rmdir(p);
        }
        closedir(d);
    }
    rmdir(tmpdir);
    return 0;
}

/* Number of entries in dir whose name contains ".tmp". */
static int count_temps(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strstr(e->d_name, ".tmp")) n++;
    closedir(d);
    return n;
}

static void writeThenReadRoundTrips(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/a.sss", tmpdir);
    for (int q = 0; q < 2; q++) {
        sss_bake_file a, b;
        make_file(&a, 10, 3, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT);
        sss_error err = {{0}};
        assert_int_equal(sss_file_write(path, &a, &err), SSS_OK);
        sss_result r = sss_file_read(path, &b, &err);
        if (r != SSS_OK) fail_msg("%s", err.msg);
        assert_same_file(&a, &b);
        struct stat st;
        assert_int_equal(stat(path, &st), 0);
        assert_int_equal((uint64_t)st.st_size, b.file_size);
        sss_file_free(&a);
        sss_file_free(&b);
    }
    assert_int_equal(count_temps(tmpdir), 0);
}

static void writeReplacesExistingFile(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/replace.sss", tmpdir);
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    fputs("an old file that is not a .sss file at all, and longer than it needs to be", fp);
    fclose(fp);
    sss_bake_file a, b;
    make_file(&a, 6, 1, SSS_QUANT_LLOYD8);
    sss_error err = {{0}};
    assert_int_equal(sss_file_write(path, &a, &err), SSS_OK);
    assert_int_equal(sss_file_read(path, &b, &err), SSS_OK);
    assert_same_file(&a, &b);
    sss_file_free(&b);
    sss_file_free(&a);
    /* and again over a valid .sss of another kind */
    make_file(&a, 9, 3, SSS_QUANT_FLOAT);
    assert_int_equal(sss_file_write(path, &a, &err), SSS_OK);
    assert_int_equal(sss_file_read(path, &b, &err), SSS_OK);
    assert_same_file(&a, &b);
    sss_file_free(&b);
    sss_file_free(&a);
    assert_int_equal(count_temps(tmpdir), 0);
}

static void writeToMissingDirectoryFailsWithoutTemp(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/no/such/dir/x.sss", tmpdir);
    sss_bake_file a;
    make_file(&a, 6, 3, SSS_QUANT_FLOAT);
    sss_error err = {{0}};
    assert_int_equal(sss_file_write(path, &a, &err), SSS_ERR_IO);
    assert_non_null(strstr(err.msg, path));
    assert_int_equal(count_temps(tmpdir), 0);
    sss_file_free(&a);
}

static void writeOverDirectoryFailsAndRemovesTemp(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/isdir.sss", tmpdir);
    assert_int_equal(mkdir(path, 0755), 0);
    sss_bake_file a;
    make_file(&a, 6, 3, SSS_QUANT_FLOAT);
    sss_error err = {{0}};
    /* the temporary is written and synced, then rename onto a directory fails */
    assert_int_equal(sss_file_write(path, &a, &err), SSS_ERR_IO);
    assert_non_null(strstr(err.msg, path));
    assert_int_equal(count_temps(tmpdir), 0);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true(S_ISDIR(st.st_mode));
    rmdir(path);
    sss_file_free(&a);
}

static void writeOfInvalidContentKeepsExistingFile(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/keep.sss", tmpdir);
    sss_bake_file a, b;
    make_file(&a, 6, 3, SSS_QUANT_FLOAT);
    sss_error err = {{0}};
    assert_int_equal(sss_file_write(path, &a, &err), SSS_OK);
    float saved = a.q[5];
    a.q[5] = NAN;
    err.msg[0] = 0;
    assert_int_equal(sss_file_write(path, &a, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, path));
    a.q[5] = saved;
    assert_int_equal(sss_file_read(path, &b, &err), SSS_OK);
    assert_same_file(&a, &b);
    assert_int_equal(count_temps(tmpdir), 0);
    sss_file_free(&a);
    sss_file_free(&b);
}

static void readMissingOrNonRegularFileFailsNamingPath(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/absent.sss", tmpdir);
    sss_bake_file f;
    sss_error err = {{0}};
    assert_int_equal(sss_file_read(path, &f, &err), SSS_ERR_IO);
    assert_non_null(strstr(err.msg, path));
    assert_true(is_zero(&f, sizeof f));
    err.msg[0] = 0;
    assert_int_equal(sss_file_read(tmpdir, &f, &err), SSS_ERR_IO);
    assert_non_null(strstr(err.msg, tmpdir));
}

static void readOfCorruptFileNamesPathAndSection(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/corrupt.sss", tmpdir);
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    b[len - 1] ^= 0x20; /* inside PARM */
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(b, 1, len, fp), len);
    fclose(fp);
    sss_bake_file f;
    sss_error err = {{0}};
    assert_int_equal(sss_file_read(path, &f, &err), SSS_ERR_CORRUPT);
    char want[600];
    snprintf(want, sizeof want, "%s: section PARM: checksum mismatch", path);
    assert_non_null(strstr(err.msg, want));
    free(b);
}

/* ---- corruption -------------------------------------------------------- */

static void decodeRejectsEveryTruncatedPrefix(void **state)
{
    (void)state;
    for (int q = 0; q < 2; q++) {
        size_t len;
        uint8_t *b = encode_new(8, 3, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT, &len);
        for (size_t n = 0; n < len; n++) {
            /* a fresh exact-size copy, so ASan sees any read past n */
            uint8_t *c = malloc(n ? n : 1);
            assert_non_null(c);
            memcpy(c, b, n);
            expect_reject(c, n, -1, NULL);
            free(c);
        }
        free(b);
    }
}

static void decodeRejectsEveryFlippedByte(void **state)
{
    (void)state;
    static const uint8_t masks[2] = {0xFF, 0x01};
    for (int q = 0; q < 2; q++) {
        size_t len;
        uint8_t *b = encode_new(8, 3, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT, &len);
        for (int m = 0; m < 2; m++)
            for (size_t i = 0; i < len; i++) {
                b[i] ^= masks[m];
                expect_reject(b, len, -1, NULL);
                b[i] ^= masks[m];
            }
        free(b);
    }
}

static void decodeRejectsAppendedBytes(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    uint8_t *c = calloc(len + 8, 1);
    assert_non_null(c);
    memcpy(c, b, len);
    expect_reject(c, len + 8, SSS_ERR_CORRUPT, "trailing");
    /* even when the header's size field agrees, the bytes are covered by no section */
    wr64(c + 16, len + 8);
    fix_header_crc(c);
    expect_reject(c, len + 8, SSS_ERR_CORRUPT, "not covered");
    free(b);
    free(c);
}

static void decodeRejectsBadMagicAndTextModeMangling(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    uint8_t *c = malloc(len);
    assert_non_null(c);
    /* CRLF -> LF, as a text-mode transfer would do */
    size_t n = 0;
    for (size_t i = 0; i < len; i++)
        if (!(b[i] == '\r' && i + 1 < len && b[i + 1] == '\n')) c[n++] = b[i];
    expect_reject(c, n, SSS_ERR_FORMAT, "magic");
    memcpy(c, "SSSBAKE\0", 8);
    expect_reject(c, 8, SSS_ERR_FORMAT, "magic");
    expect_reject((const uint8_t *)"{}", 2, SSS_ERR_FORMAT, "magic");
    expect_reject(NULL, 0, -1, NULL);
    free(b);
    free(c);
}

/* ---- versions and sections -------------------------------------------- */

static void decodeRejectsNewerMajorVersion(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    wr16(b + 8, 2);
    wr16(b + 10, 0);
    fix_header_crc(b);
    expect_reject(b, len, SSS_ERR_VERSION, "t.sss: format version 2.0 is newer than this reader (1.x)");
    /* judged before anything after byte 12, which a new major may redefine */
    memset(b + 12, 0xEE, len - 12);
    expect_reject(b, len, SSS_ERR_VERSION, "2.0 is newer");
    wr16(b + 8, 0);
    expect_reject(b, len, SSS_ERR_VERSION, "0.0");
    free(b);
}

static void decodeAcceptsNewerMinorVersion(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    wr16(b + 10, 7);
    fix_header_crc(b);
    sss_bake_file f;
    expect_accept(b, len, &f);
    assert_int_equal(f.version_major, 1);
    assert_int_equal(f.version_minor, 7);
    sss_file_free(&f);
    free(b);
}

static void decodeSkipsUnknownOptionalSection(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_LLOYD8, &len);
    tfile t;
    t_split(b, len, &t);
    free(b);
    t_append(&t, "XTRA", 0, "future data", 11);
    /* also in the middle, before the sections it might depend on */
    t_append(&t, "ZERO", 0, "", 0);
    tsec zero = t.s[t.n - 1];
    memmove(&t.s[1], &t.s[0], (t.n - 1) * sizeof zero);
    t.s[0] = zero;
    b = t_join(&t, &len);
    sss_bake_file f, ref;
    expect_accept(b, len, &f);
    assert_int_equal(f.nsections, 7);
    assert_string_equal(f.sections[0].tag, "ZERO");
    assert_string_equal(f.sections[6].tag, "XTRA");
    assert_int_equal(f.sections[6].size, 11);
    make_file(&ref, 6, 3, SSS_QUANT_LLOYD8);
    assert_same_file(&ref, &f);
    sss_file_free(&ref);
    sss_file_free(&f);
    free(b);
    t_free(&t);
}

static void decodeRejectsUnknownRequiredSection(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    tfile t;
    t_split(b, len, &t);
    free(b);
    t_append(&t, "XREQ", 1 | 0x100, "must understand", 15);
    expect_reject_t(&t, SSS_ERR_UNSUPPORTED, "section XREQ");
    t_free(&t);
}

static void decodeRejectsMissingRequiredSections(void **state)
{
    (void)state;
    static const char *tags[5] = {"GEOM", "MATL", "DIRS", "QFLT", "PARM"};
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    for (int i = 0; i < 5; i++) {
        tfile t;
        t_split(b, len, &t);
        t_remove(&t, tags[i]);
        char want[64];
        snprintf(want, sizeof want, "missing required section %s", tags[i]);
        expect_reject_t(&t, SSS_ERR_CORRUPT, want);
        t_free(&t);
    }
    tfile t;
    t_split(b, len, &t);
    while (t.n) t_remove(&t, t.s[0].tag);
    expect_reject_t(&t, SSS_ERR_CORRUPT, "missing required section");
    free(b);
}

static void decodeRejectsDuplicateAndConflictingSections(void **state)
{
    (void)state;
    size_t lf, lq;
    uint8_t *bf = encode_new(6, 3, SSS_QUANT_FLOAT, &lf);
    uint8_t *bq = encode_new(6, 3, SSS_QUANT_LLOYD8, &lq);
    tfile t, u;
    t_split(bf, lf, &t);
    t_split(bq, lq, &u);
    tsec *m = t_find(&t, "MATL");
    t_append(&t, "MATL", m->flags, m->data, m->size);
    t.s[t.n - 1].count = m->count;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "MATL appears more than once");
    t_remove(&t, "MATL"); /* removes the first; one is left */
    tsec *l8 = t_find(&u, "QL8 ");
    t_append(&t, "QL8 ", l8->flags, l8->data, l8->size);
    t.s[t.n - 1].count = l8->count;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "more than one");
    t_free(&t);
    t_free(&u);
    free(bf);
    free(bq);
}

static void decodeRejectsNonPrintableTag(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    tfile t;
    t_split(b, len, &t);
    t_append(&t, "X\nY\x01", 0, "x", 1);
    expect_reject_t(&t, SSS_ERR_CORRUPT, "printable");
    t_free(&t);
    free(b);
}

/* ---- hostile headers ---------------------------------------------------- */

static void decodeRejectsHugeSectionCount(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    uint32_t bad[3] = {33, 0x7FFFFFFFu, 0xFFFFFFFFu};
    for (int i = 0; i < 3; i++) {
        wr32(b + 12, bad[i]);
        expect_reject(b, len, SSS_ERR_CORRUPT, "sections");
    }
    free(b);
}

static void decodeRejectsSectionOffsetsAndSizesOutsideFile(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    uint8_t *c = malloc(len);
    assert_non_null(c);
    const size_t e2 = HDR + 2 * ENT; /* DIRS entry */
    const size_t e4 = HDR + 4 * ENT; /* PARM entry, the last */
    struct { size_t field; uint64_t value; const char *needle; } cases[] = {
        {e2 + 8, (uint64_t)1 << 62, "offset"},
        {e2 + 8, UINT64_MAX, "offset"},
        {e2 + 8, len, "offset"},
        {e2 + 8, test_rd64(b + e2 + 8) + 4, "offset"},      /* a gap */
        {e2 + 8, test_rd64(b + e2 + 8) - 4, "offset"},      /* an overlap */
        {e4 + 16, test_rd64(b + e4 + 16) + 1, "past the end"},
        {e4 + 16, UINT64_MAX, "past the end"},
        {e4 + 16, UINT64_MAX - 5, "past the end"},
        {e2 + 16, UINT64_MAX - test_rd64(b + e2 + 8) + 1, "past the end"}, /* offset + size wraps to 0 */
        {e2 + 16, (uint64_t)1 << 63, "past the end"},
        {e4 + 16, test_rd64(b + e4 + 16) - 1, "not covered"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        memcpy(c, b, len);
        wr64(c + cases[i].field, cases[i].value);
        fix_header_crc(c);
        expect_reject(c, len, SSS_ERR_CORRUPT, cases[i].needle);
    }
    /* a huge size on the first section, all later offsets consistent mod 2^64 */
    memcpy(c, b, len);
    wr64(c + HDR + 16, UINT64_MAX);
    fix_header_crc(c);
    expect_reject(c, len, SSS_ERR_CORRUPT, NULL);
    free(c);
    free(b);
}

static void decodeRejectsHugeCountsInTinySections(void **state)
{
    (void)state;
    for (int q = 0; q < 2; q++) {
        size_t len;
        uint8_t *b = encode_new(6, 3, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT, &len);
        struct { const char *tag; size_t at; uint32_t value; const char *needle; } cases[] = {
            {"GEOM", 0, 0x80000000u, "does not match 2147483648 vertices"},
            {"GEOM", 0, 0xFFFFFFFFu, "GEOM: size"},
            {"GEOM", 4, 0xFFFFFFFFu, "GEOM: size"},
            {"GEOM", 0, 0, "no vertices"},
            {"GEOM", 4, 0, "no triangles"},
            {"DIRS", 0, 0x80000000u, "DIRS"},
            {"DIRS", 0, 0xFFFFFFFFu, "DIRS"},
            {"DIRS", 4, 0xFFFFFFFFu, "DIRS"},
            {"DIRS", 0, 0, "no directions"},
            {"QL8 ", 0, 0xFFFFFFFFu, "QL8 "},
        };
        for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
            tfile t;
            t_split(b, len, &t);
            if (!q && !strcmp(cases[i].tag, "QL8 ")) { t_free(&t); continue; }
            wr32(t_find(&t, cases[i].tag)->data + cases[i].at, cases[i].value);
            expect_reject_t(&t, SSS_ERR_CORRUPT, cases[i].needle);
            t_free(&t);
        }
        /* section counts that disagree with the payload */
        const char *tags[] = {"GEOM", "MATL", "DIRS", q ? "QL8 " : "QFLT", "PARM"};
        for (int i = 0; i < 5; i++) {
            tfile t;
            t_split(b, len, &t);
            t_find(&t, tags[i])->count += (uint64_t)1 << 40;
            expect_reject_t(&t, SSS_ERR_CORRUPT, "count");
            t_free(&t);
        }
        /* sections shorter than their fixed fields */
        const char *shorts[] = {"GEOM", "MATL", "DIRS", q ? "QL8 " : "QFLT"};
        for (int i = 0; i < 4; i++)
            for (size_t n = 0; n < 9; n++) {
                tfile t;
                t_split(b, len, &t);
                tsec *s = t_find(&t, shorts[i]);
                s->size = n;
                expect_reject_t(&t, SSS_ERR_CORRUPT, shorts[i]);
                t_free(&t);
            }
        free(b);
    }
}

/* Edits a float32 / uint32 / float64 inside one section and expects a rejection. */
static void reject_edit_f32(const uint8_t *b, size_t len, const char *tag, size_t at, float x, const char *needle)
{
    tfile t;
    t_split(b, len, &t);
    wrf32(t_find(&t, tag)->data + at, x);
    expect_reject_t(&t, SSS_ERR_CORRUPT, needle);
    t_free(&t);
}
static void reject_edit_u32(const uint8_t *b, size_t len, const char *tag, size_t at, uint32_t x, const char *needle)
{
    tfile t;
    t_split(b, len, &t);
    wr32(t_find(&t, tag)->data + at, x);
    expect_reject_t(&t, SSS_ERR_CORRUPT, needle);
    t_free(&t);
}
static void reject_edit_f64(const uint8_t *b, size_t len, const char *tag, size_t at, double x, const char *needle)
{
    tfile t;
    t_split(b, len, &t);
    wrf64(t_find(&t, tag)->data + at, x);
    expect_reject_t(&t, SSS_ERR_CORRUPT, needle);
    t_free(&t);
}

static void decodeRejectsBadGeometry(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    const size_t pos = 8, nrm = 8 + 12 * 6, tri = 8 + 24 * 6;
    reject_edit_f32(b, len, "GEOM", pos, NAN, "vertex 0: position");
    reject_edit_f32(b, len, "GEOM", pos + 4 * 17, INFINITY, "vertex 5: position");
    reject_edit_f32(b, len, "GEOM", nrm + 4, -INFINITY, "vertex 0: normal");
    reject_edit_u32(b, len, "GEOM", tri, 6, "triangle 0: vertex index 6 out of range");
    reject_edit_u32(b, len, "GEOM", tri + 4 * 23, 0xFFFFFFFFu, "triangle 7");
    free(b);
}

static void decodeRejectsBadMaterial(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    tfile t;
    t_split(b, len, &t);
    memset(t_find(&t, "MATL")->data, 'A', 32);
    expect_reject_t(&t, SSS_ERR_CORRUPT, "NUL");
    t_free(&t);
    reject_edit_f64(b, len, "MATL", 32, -0.5, "sigma_a");
    reject_edit_f64(b, len, "MATL", 32 + 16, NAN, "channel 2");
    reject_edit_f64(b, len, "MATL", 56 + 8, -1.0, "sigma'_s");
    reject_edit_f64(b, len, "MATL", 80, 0.0, "eta");
    reject_edit_f64(b, len, "MATL", 80, INFINITY, "eta");
    reject_edit_f64(b, len, "MATL", 88, 0.0, "mm_per_unit");
    reject_edit_f64(b, len, "MATL", 88, NAN, "mm_per_unit");
    reject_edit_u32(b, len, "MATL", 96, 2, "channel count 2");
    reject_edit_u32(b, len, "MATL", 96, 0, "channel count 0");
    /* σa = σ′s = 0 */
    tfile u;
    t_split(b, len, &u);
    wrf64(t_find(&u, "MATL")->data + 32, 0.0);
    wrf64(t_find(&u, "MATL")->data + 56, 0.0);
    expect_reject_t(&u, SSS_ERR_CORRUPT, "sigma'_t = 0");
    t_free(&u);
    free(b);
    /* grey file: MATL says 1 channel, q has 3 per vertex -> size mismatch */
    b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    tfile g;
    t_split(b, len, &g);
    wr32(t_find(&g, "MATL")->data + 96, 1);
    t_find(&g, "MATL")->count = 1;
    expect_reject_t(&g, SSS_ERR_CORRUPT, "QFLT: size");
    t_free(&g);
    free(b);
}

static void decodeRejectsBadDirections(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(8, 3, SSS_QUANT_FLOAT, &len);
    const size_t dir = 8, tri = 8 + 24 * 8;
    reject_edit_f64(b, len, "DIRS", dir, 0.5, "direction 0 has length");
    reject_edit_f64(b, len, "DIRS", dir + 8 * 23, NAN, "direction 7");
    reject_edit_u32(b, len, "DIRS", tri, 8, "triangle 0: index 8 out of range");
    reject_edit_u32(b, len, "DIRS", tri + 4, 1000u, "triangle 0");
    tfile t;
    t_split(b, len, &t);
    uint8_t *d = t_find(&t, "DIRS")->data;
    wr32(d + tri + 4, test_rd32(d + tri)); /* repeated corner */
    expect_reject_t(&t, SSS_ERR_CORRUPT, "repeats");
    t_free(&t);
    reject_edit_u32(b, len, "DIRS", 4, 11, "11 triangles for 8 directions, expected 12");
    free(b);
}

/* §5.17: a set whose every component is a float32 is written as DIRC, in
 * 12 + 6 bytes per direction and triangle pair instead of 24 + 12, and
 * reads back to the same doubles; the file is 1.6. A set that is not stays
 * DIRS. Both sections, or neither, are refused, and a bad DIRC is named. */
static void dircHoldsFloatDirectionsInHalfTheBytes(void **state)
{
    (void)state;
    sss_bake_file a, b;
    make_file(&a, 40, 3, SSS_QUANT_FLOAT);
    size_t l64;
    uint8_t *b64 = encode(&a, &l64);
    tfile t;
    t_split(b64, l64, &t);
    assert_true(t_has(&t, "DIRS") && !t_has(&t, "DIRC"));
    sss_dirset_round_f32(&a.dirs);
    a.dirs_f32 = 1;
    size_t len;
    uint8_t *buf = encode(&a, &len);
    assert_int_equal(buf[10] | buf[11] << 8, 6);
    tfile u;
    t_split(buf, len, &u);
    assert_false(t_has(&u, "DIRS"));
    const tsec *dc = t_find(&u, "DIRC");
    assert_non_null(dc);
    assert_int_equal(dc->size, 8 + 12 * 40 + 6 * 76);
    assert_int_equal(l64 - len, 12 * 40 + 6 * 76);
    expect_accept(buf, len, &b);
    assert_same_file(&a, &b);
    size_t len2;
    uint8_t *buf2 = encode(&b, &len2);
    assert_int_equal(len, len2);
    assert_memory_equal(buf, buf2, len);
    /* both, then neither */
    const tsec *ds = t_find(&t, "DIRS");
    t_append(&u, "DIRS", ds->flags, ds->data, ds->size);
    u.s[u.n - 1].count = ds->count;
    expect_reject_t(&u, SSS_ERR_CORRUPT, "both sections DIRS and DIRC");
    t_remove(&u, "DIRS");
    t_remove(&u, "DIRC");
    expect_reject_t(&u, SSS_ERR_CORRUPT, "missing required section DIRS or DIRC");
    t_free(&u);
    /* a bad DIRC is refused by name: an index, a length, the counts */
    const size_t dir = 8, tri = 8 + 12 * 40;
    t_split(buf, len, &u);
    uint8_t *d = t_find(&u, "DIRC")->data;
    wr16(d + tri, 40);
    expect_reject_t(&u, SSS_ERR_CORRUPT, "section DIRC: triangle 0: index 40 out of range");
    t_free(&u);
    reject_edit_f32(buf, len, "DIRC", dir, 0.5f, "section DIRC: direction 0 has length");
    reject_edit_u32(buf, len, "DIRC", 4, 75, "section DIRC: 75 triangles for 40 directions");
    t_free(&t);
    free(b64);
    free(buf);
    free(buf2);
    sss_file_free(&a);
    sss_file_free(&b);
}

static void decodeRejectsBadQuantisedValues(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    reject_edit_f32(b, len, "QFLT", 0, -1e-3f, "value 0");
    reject_edit_f32(b, len, "QFLT", 4 * 17, NAN, "value 17");
    reject_edit_f32(b, len, "QFLT", 4 * 20, INFINITY, "value 20");
    free(b);
    b = encode_new(6, 3, SSS_QUANT_LLOYD8, &len);
    reject_edit_f32(b, len, "QL8 ", 4 + 4 * 10, 0.0f, "channel 0: level 10");      /* decreasing */
    reject_edit_f32(b, len, "QL8 ", 4 + 4 * 256, -1.0f, "channel 1: level 0");     /* negative */
    reject_edit_f32(b, len, "QL8 ", 4 + 4 * (512 + 255), NAN, "channel 2: level 255");
    reject_edit_u32(b, len, "QL8 ", 0, 1, "QL8 : 1 channels");
    free(b);
}

static void decodeRejectsNulInParams(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    tfile t;
    t_split(b, len, &t);
    t_find(&t, "PARM")->data[3] = 0;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "PARM: NUL byte at offset 3");
    t_free(&t);
    /* an empty PARM is valid */
    t_split(b, len, &t);
    t_find(&t, "PARM")->size = 0;
    t_find(&t, "PARM")->count = 0;
    size_t n;
    uint8_t *c = t_join(&t, &n);
    sss_bake_file f;
    expect_accept(c, n, &f);
    assert_string_equal(f.params_json, "");
    sss_file_free(&f);
    free(c);
    t_free(&t);
    free(b);
}

/* ---- NBHD: the neighbourhood cutoff (1.4) ------------------------------ */

/* make_file's content with ε as a bake records it (0.01, as its PARM says). */
static uint8_t *encode_with_eps(uint32_t ndirs, sss_quant quant, size_t *len)
{
    sss_bake_file f;
    make_file(&f, ndirs, 3, quant);
    f.eps = 0.01;
    uint8_t *b = encode(&f, len);
    sss_file_free(&f);
    return b;
}

static void nbhdRoundTripsAndMakesTheFile1_4(void **state)
{
    (void)state;
    for (int q = 0; q < 2; q++) {
        sss_bake_file a, b;
        make_file(&a, 12, 3, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT);
        a.eps = 0.01;
        size_t len;
        uint8_t *buf = encode(&a, &len);
        /* NBHD is required-flagged and makes the file 1.4, so a 1.0–1.3
         * reader refuses it by name (§4) instead of ignoring ε */
        assert_int_equal(buf[10] | buf[11] << 8, 4);
        assert_int_equal(test_rd32(buf + 12), 6);
        const uint8_t *e = buf + HDR + 4 * ENT; /* before PARM, the last */
        assert_memory_equal(e, "NBHD", 4);
        assert_int_equal(test_rd32(e + 4), 1);
        assert_int_equal(test_rd64(e + 16), 8);
        assert_int_equal(test_rd64(e + 24), 1);
        uint64_t bits;
        memcpy(&bits, &a.eps, 8);
        assert_int_equal(test_rd64(buf + test_rd64(e + 8)), bits);
        assert_memory_equal(buf + HDR + 5 * ENT, "PARM", 4);
        expect_accept(buf, len, &b);
        assert_same_file(&a, &b);
        assert_true(b.eps == 0.01);
        assert_int_equal(b.version_minor, 4);
        size_t len2;
        uint8_t *buf2 = encode(&b, &len2);
        assert_int_equal(len, len2);
        assert_memory_equal(buf, buf2, len);
        free(buf);
        free(buf2);
        sss_file_free(&a);
        sss_file_free(&b);
    }
}

static void decodeRejectsNbhdOfWrongSizeOrCount(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_with_eps(8, SSS_QUANT_FLOAT, &len);
    for (size_t n = 0; n < 12; n += (n == 7 ? 2 : 1)) {
        tfile t;
        t_split(b, len, &t);
        tsec *s = t_find(&t, "NBHD");
        uint8_t *d = realloc(s->data, 16);
        assert_non_null(d);
        memset(d + 8, 0, 8);
        s->data = d;
        s->size = n;
        char want[64];
        snprintf(want, sizeof want, "section NBHD: %zu bytes, count 1 (expected 8 and 1)", n);
        expect_reject_t(&t, SSS_ERR_CORRUPT, want);
        t_free(&t);
    }
    tfile t;
    t_split(b, len, &t);
    t_find(&t, "NBHD")->count = 2;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section NBHD: 8 bytes, count 2");
    t_free(&t);
    free(b);
}

static void decodeRejectsNbhdEpsOutsideZeroOne(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_with_eps(8, SSS_QUANT_LLOYD8, &len);
    const double bad[] = {0.0, -0.01, 1.0, 7.5, NAN, INFINITY, -INFINITY};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        reject_edit_f64(b, len, "NBHD", 0, bad[i], "section NBHD: eps");
    free(b);
    /* the writer refuses what the reader would */
    sss_bake_file f;
    make_file(&f, 8, 3, SSS_QUANT_FLOAT);
    uint8_t *buf = NULL;
    sss_error err = {{0}};
    for (size_t i = 1; i < sizeof bad / sizeof bad[0]; i++) {
        f.eps = bad[i];
        err.msg[0] = 0;
        assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_ERR_ARG);
        assert_null(buf);
        assert_non_null(strstr(err.msg, "section NBHD: eps"));
    }
    sss_file_free(&f);
}

static void decodeRejects1_4FileWithoutNbhd(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_with_eps(8, SSS_QUANT_FLOAT, &len);
    tfile t;
    t_split(b, len, &t);
    assert_int_equal(t.minor, 4);
    t_remove(&t, "NBHD");
    expect_reject_t(&t, SSS_ERR_CORRUPT, "t.sss: missing required section NBHD");
    /* the same sections under minor 3, as a 1.3 writer wrote them, read */
    t.minor = 3;
    size_t n;
    uint8_t *c = t_join(&t, &n);
    sss_bake_file f;
    expect_accept(c, n, &f);
    assert_true(f.eps == 0.0);
    sss_file_free(&f);
    free(c);
    t_free(&t);
    free(b);
}

static void filesWithoutNbhdStillReadAndKeepTheirVersion(void **state)
{
    (void)state;
    /* ε not given (another writer, or a file read from before 1.4): no NBHD,
     * the old minor version, the old bytes; ε is then only in PARM */
    for (int q = 0; q < 2; q++) {
        sss_bake_file a, b;
        make_file(&a, 12, 3, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT);
        size_t len;
        uint8_t *buf = encode(&a, &len);
        assert_int_equal(buf[10], 0);
        expect_accept(buf, len, &b);
        assert_true(b.eps == 0.0);
        assert_int_equal(b.nsections, 5);
        assert_non_null(strstr(b.params_json, "\"eps\":0.01"));
        free(buf);
        sss_file_free(&a);
        sss_file_free(&b);
    }
    /* a newer minor version without NBHD still reads (§4) */
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    wr16(b + 10, SSS_FORMAT_MINOR + 1);
    fix_header_crc(b);
    sss_bake_file f;
    expect_accept(b, len, &f);
    assert_true(f.eps == 0.0);
    sss_file_free(&f);
    free(b);
}

/* ---- PHAS: the material's phase function (1.8) ---- */

static void phasRoundTripsGAndMakesTheFile1_8(void **state)
{
    (void)state;
    sss_bake_file a, b;
    make_file(&a, 12, 3, SSS_QUANT_FLOAT);
    a.material.g = 0.4;
    size_t len;
    uint8_t *buf = encode(&a, &len);
    assert_int_equal(buf[10] | buf[11] << 8, 8);
    tfile t;
    t_split(buf, len, &t);
    const tsec *ph = t_find(&t, "PHAS");
    assert_non_null(ph);
    /* optional: a reader without it shows the dipole of MATL's σ′s as before */
    assert_int_equal(ph->flags, 0);
    assert_int_equal(ph->size, 8);
    assert_int_equal(ph->count, 1);
    t_free(&t);
    expect_accept(buf, len, &b);
    assert_same_file(&a, &b);
    assert_true(b.material.g == 0.4);
    assert_int_equal(b.version_minor, 8);
    size_t len2;
    uint8_t *buf2 = encode(&b, &len2);
    assert_int_equal(len, len2);
    assert_memory_equal(buf, buf2, len);
    free(buf);
    free(buf2);
    sss_file_free(&a);
    sss_file_free(&b);
}

static void isotropicFilesHaveNoPhasAndReadGZero(void **state)
{
    (void)state;
    sss_bake_file a, b;
    make_file(&a, 12, 3, SSS_QUANT_FLOAT);
    size_t len;
    uint8_t *buf = encode(&a, &len);
    assert_int_equal(buf[10], 0); /* the minor of its other sections */
    tfile t;
    t_split(buf, len, &t);
    for (uint32_t i = 0; i < t.n; i++) assert_memory_not_equal(t.s[i].tag, "PHAS", 4);
    t_free(&t);
    expect_accept(buf, len, &b);
    assert_true(b.material.g == 0.0);
    free(buf);
    sss_file_free(&a);
    sss_file_free(&b);
    /* the golden file, written before 1.8, reads with g = 0 */
    sss_bake_file gf;
    sss_error err = {{0}};
    assert_int_equal(sss_file_read(GOLDEN_PATH, &gf, &err), SSS_OK);
    assert_true(gf.material.g == 0.0);
    sss_file_free(&gf);
}

static void decodeRejectsPhasOutOfRangeOrWrongSize(void **state)
{
    (void)state;
    sss_bake_file a;
    make_file(&a, 12, 3, SSS_QUANT_FLOAT);
    a.material.g = -0.3;
    size_t len;
    uint8_t *buf = encode(&a, &len);
    reject_edit_f64(buf, len, "PHAS", 0, 0.995, "section PHAS: g 0.995 is outside");
    reject_edit_f64(buf, len, "PHAS", 0, NAN, "section PHAS: g nan is outside");
    tfile t;
    t_split(buf, len, &t);
    t_find(&t, "PHAS")->size = 4;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section PHAS: 4 bytes");
    t_free(&t);
    /* the writer refuses what the reader would */
    a.material.g = 1.0;
    uint8_t *bad = NULL;
    sss_error err = {{0}};
    assert_int_not_equal(sss_file_encode(&a, &bad, &len, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "g 1 is outside"));
    free(buf);
    sss_file_free(&a);
}

/* ---- LAYR: seed 002's layers (1.8) ---- */

static void make_layers(sss_bake_file *f)
{
    const sss_layer t1[2] = {{{2.0, 1.0, 1.0}, {2.6, 1.6, 1.6}, 0.25, 0.3}, {{6.0, 3.0, 2.0}, {6.6, 3.6, 2.6}, 0.4, 0.8}};
    f->layers.n = 2;
    f->layers.phase = SSS_PHASE_SCHLICK;
    memcpy(f->layers.layer, t1, sizeof t1);
}

static void layrRoundTripsAndRejectsDisorder(void **state)
{
    (void)state;
    sss_bake_file a, b;
    make_file(&a, 12, 3, SSS_QUANT_FLOAT);
    make_layers(&a);
    size_t len;
    uint8_t *buf = encode(&a, &len);
    assert_int_equal(buf[10] | buf[11] << 8, 8);
    expect_accept(buf, len, &b);
    assert_same_file(&a, &b);
    assert_memory_equal(&a.layers, &b.layers, sizeof a.layers);
    tfile t;
    t_split(buf, len, &t);
    const tsec *ly = t_find(&t, "LAYR");
    assert_int_equal(ly->flags, 0);
    assert_int_equal(ly->size, 8 + 64 * 2);
    assert_int_equal(ly->count, 2);
    t_free(&t);
    /* the second layer's depth (offset 8 + 64 + 56) above the first's */
    reject_edit_f64(buf, len, "LAYR", 8 + 64 + 56, 0.1, "section LAYR: layer 1: depth 0.1 mm is above the layer before it");
    /* sigma_s above sigma_t */
    reject_edit_f64(buf, len, "LAYR", 8, 3.0, "section LAYR: layer 0 channel 0: sigma_s 3, sigma_t 2.6");
    reject_edit_f64(buf, len, "LAYR", 8 + 48, 1.5, "section LAYR: layer 0: g 1.5 is outside");
    t_split(buf, len, &t);
    t_find(&t, "LAYR")->size = 8 + 64;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section LAYR: 72 bytes, count 2 for 2 layers");
    t_free(&t);
    free(buf);
    sss_file_free(&a);
    sss_file_free(&b);
    /* without layers: no LAYR, and n = 0 read back */
    make_file(&a, 12, 3, SSS_QUANT_FLOAT);
    buf = encode(&a, &len);
    expect_accept(buf, len, &b);
    assert_int_equal(b.layers.n, 0);
    assert_int_equal(buf[10], 0);
    free(buf);
    sss_file_free(&a);
    sss_file_free(&b);
}

/* ---- LDEP: per-vertex layer depths (1.9) ---- */

static void ldepRoundTripsAndRejectsBadDepths(void **state)
{
    (void)state;
    sss_bake_file a, b;
    make_file(&a, 12, 3, SSS_QUANT_FLOAT);
    make_layers(&a);
    /* the octahedron's 6 vertices, 2 layers each, non-decreasing */
    a.layer_depth = malloc(6 * 2 * sizeof(float));
    assert_non_null(a.layer_depth);
    for (int v = 0; v < 6; v++) {
        a.layer_depth[2 * v] = 0.05f * (float)v;
        a.layer_depth[2 * v + 1] = 0.3f + 0.1f * (float)v;
    }
    size_t len;
    uint8_t *buf = encode(&a, &len);
    assert_int_equal(buf[10] | buf[11] << 8, 9);
    expect_accept(buf, len, &b);
    assert_same_file(&a, &b);
    assert_non_null(b.layer_depth);
    assert_memory_equal(a.layer_depth, b.layer_depth, 6 * 2 * sizeof(float));
    tfile t;
    t_split(buf, len, &t);
    const tsec *ld = t_find(&t, "LDEP");
    assert_int_equal(ld->flags, 0); /* optional: LAYR's depths stand in for it */
    assert_int_equal(ld->size, 6 * 2 * 4);
    assert_int_equal(ld->count, 6);
    t_free(&t);
    reject_edit_f32(buf, len, "LDEP", 4 * 3, NAN, "section LDEP: vertex 1 layer 1: depth nan mm is not in [0,");
    reject_edit_f32(buf, len, "LDEP", 4 * 4, -0.5f, "section LDEP: vertex 2 layer 0: depth -0.5 mm is not in [0,");
    reject_edit_f32(buf, len, "LDEP", 4 * 5, 0.01f, "section LDEP: vertex 2 layer 1: depth 0.01 mm is above the layer before it");
    /* a count or size that does not match GEOM's vertices and LAYR's layers */
    t_split(buf, len, &t);
    t_find(&t, "LDEP")->count = 5;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section LDEP: 48 bytes, count 5 (expected 48 bytes and the 6 vertices");
    t_find(&t, "LDEP")->count = 6;
    t_find(&t, "LDEP")->size = 40;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section LDEP: 40 bytes, count 6");
    t_free(&t);
    /* depths without layers */
    t_split(buf, len, &t);
    t_remove(&t, "LAYR");
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section LDEP: per-vertex layer depths without section LAYR");
    t_free(&t);
    /* the writer refuses what the reader would */
    a.layer_depth[3] = NAN;
    uint8_t *bad = NULL;
    size_t blen = 0;
    sss_error err = {{0}};
    assert_int_equal(sss_file_encode(&a, &bad, &blen, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "section LDEP: vertex 1 layer 1"));
    free(buf);
    sss_file_free(&a);
    sss_file_free(&b);
    /* flat layers: no LDEP, the minor stays 8 */
    make_file(&a, 12, 3, SSS_QUANT_FLOAT);
    make_layers(&a);
    buf = encode(&a, &len);
    assert_int_equal(buf[10] | buf[11] << 8, 8);
    expect_accept(buf, len, &b);
    assert_null(b.layer_depth);
    free(buf);
    sss_file_free(&a);
    sss_file_free(&b);
}

/* ---- QUAD and NRAD: the weight rule and the near terms' radius (1.5) ---- */

/* make_file's content with ε, the hat-function weights and, when radius > 0,
 * the near terms within that radius at run time. */
static void make_file_1_5(sss_bake_file *f, sss_quant quant, double radius)
{
    make_file(f, 12, 3, quant);
    f->eps = 0.01;
    f->weights = SSS_WEIGHTS_HAT;
    if (radius > 0.0) {
        f->near_terms = SSS_NEAR_TERMS_RUNTIME;
        f->near_radius_mm = radius;
    }
}

static void quadAndNradRoundTripAndMakeTheFile1_5(void **state)
{
    (void)state;
    for (int q = 0; q < 2; q++)
        for (int withr = 0; withr < 2; withr++) {
            sss_bake_file a, b;
            make_file_1_5(&a, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT, withr ? 2.5 : 0.0);
            size_t len;
            uint8_t *buf = encode(&a, &len);
            /* required-flagged, and the file is 1.5: a 1.0–1.4 reader
             * refuses it by naming the section instead of summing other
             * weights (§4) */
            assert_int_equal(buf[10] | buf[11] << 8, 5);
            tfile t;
            t_split(buf, len, &t);
            const tsec *qs = t_find(&t, "QUAD");
            assert_non_null(qs);
            assert_int_equal(qs->size, 4);
            assert_int_equal(test_rd32(qs->data), SSS_WEIGHTS_HAT);
            if (withr) {
                const tsec *ns = t_find(&t, "NRAD");
                assert_non_null(ns);
                assert_int_equal(ns->size, 8);
                assert_non_null(t_find(&t, "OWNT"));
            }
            t_free(&t);
            expect_accept(buf, len, &b);
            assert_same_file(&a, &b);
            assert_int_equal(b.weights, SSS_WEIGHTS_HAT);
            assert_true(b.near_radius_mm == (withr ? 2.5 : 0.0));
            assert_int_equal(b.version_minor, 5);
            size_t len2;
            uint8_t *buf2 = encode(&b, &len2);
            assert_int_equal(len, len2);
            assert_memory_equal(buf, buf2, len);
            free(buf);
            free(buf2);
            sss_file_free(&a);
            sss_file_free(&b);
        }
}

static void decodeRejectsBadQuadAndNrad(void **state)
{
    (void)state;
    sss_bake_file f;
    make_file_1_5(&f, SSS_QUANT_FLOAT, 2.5);
    size_t len;
    uint8_t *b = encode(&f, &len);
    sss_file_free(&f);
    /* an unknown rule is this reader's limit, not damage */
    tfile t;
    t_split(b, len, &t);
    wr32(t_find(&t, "QUAD")->data, 7);
    expect_reject_t(&t, SSS_ERR_UNSUPPORTED, "section QUAD: weight rule 7 is unknown to this reader");
    t_free(&t);
    t_split(b, len, &t);
    t_find(&t, "QUAD")->size = 3;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section QUAD: 3 bytes, count 1 (expected 4 and 1)");
    t_free(&t);
    t_split(b, len, &t);
    t_find(&t, "NRAD")->count = 2;
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section NRAD: 8 bytes, count 2 (expected 8 and 1)");
    t_free(&t);
    const double bad[] = {0.0, -1.0, NAN, INFINITY};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        reject_edit_f64(b, len, "NRAD", 0, bad[i], "section NRAD: radius");
    /* the radius without the split it sizes */
    t_split(b, len, &t);
    t_remove(&t, "OWNT");
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section NRAD without section OWNT");
    t_free(&t);
    free(b);
    /* the writer refuses what the reader would */
    make_file_1_5(&f, SSS_QUANT_FLOAT, 2.5);
    f.near_terms = 0;
    uint8_t *buf = NULL;
    sss_error err = {{0}};
    assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_ERR_ARG);
    assert_null(buf);
    assert_non_null(strstr(err.msg, "section NRAD without section OWNT"));
    f.near_terms = SSS_NEAR_TERMS_RUNTIME;
    f.weights = 3;
    assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "section QUAD: weight rule 3"));
    sss_file_free(&f);
}

/* ---- encoder input checks ---------------------------------------------- */

static void encodeRejectsInvalidInput(void **state)
{
    (void)state;
    sss_bake_file f;
    make_file(&f, 8, 3, SSS_QUANT_FLOAT);
    uint8_t *buf = (uint8_t *)&f; /* must come back NULL */
    size_t len = 99;
    sss_error err = {{0}};
#define EXPECT_ENC_FAIL(edit, undo, needle)                                        \
    do {                                                                           \
        edit;                                                                      \
        err.msg[0] = 0;                                                            \
        assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_ERR_ARG);      \
        assert_null(buf);                                                          \
        if (!strstr(err.msg, needle)) fail_msg("\"%s\" lacks \"%s\"", err.msg, needle); \
        undo;                                                                      \
    } while (0)
    float *nrm = f.mesh.nrm;
    EXPECT_ENC_FAIL(f.mesh.nrm = NULL, f.mesh.nrm = nrm, "GEOM");
    EXPECT_ENC_FAIL(f.mesh.pos[4] = NAN, f.mesh.pos[4] = 0, "vertex 1: position");
    EXPECT_ENC_FAIL(f.mesh.tri[2] = 6, f.mesh.tri[2] = 4, "out of range");
    EXPECT_ENC_FAIL(f.channels = 2, f.channels = 3, "channel count 2");
    EXPECT_ENC_FAIL(f.material.eta = 0, f.material.eta = 1.3, "eta");
    EXPECT_ENC_FAIL(f.dirs.ntri = 3, f.dirs.ntri = 12, "DIRS");
    EXPECT_ENC_FAIL(f.dirs.dir[0] *= 2, f.dirs.dir[0] /= 2, "direction 0");
    EXPECT_ENC_FAIL(f.q[7] = -1, f.q[7] = 0, "value 7");
    EXPECT_ENC_FAIL(f.quant = SSS_QUANT_LLOYD8, f.quant = SSS_QUANT_FLOAT, "QL8");
    EXPECT_ENC_FAIL(f.quant = (sss_quant)7, f.quant = SSS_QUANT_FLOAT, "quantisation");
#undef EXPECT_ENC_FAIL
    /* the undo edits left a valid file */
    buf = NULL;
    assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_OK);
    free(buf);
    /* NULL params are written as an empty PARM */
    free(f.params_json);
    f.params_json = NULL;
    buf = encode(&f, &len);
    sss_bake_file g;
    expect_accept(buf, len, &g);
    assert_string_equal(g.params_json, "");
    sss_file_free(&g);
    free(buf);
    sss_file_free(&f);
}

/* ---- decoder ----------------------------------------------------------- */

static void decodeSampleReturnsStoredValues(void **state)
{
    (void)state;
    sss_bake_file f;
    make_file(&f, 8, 3, SSS_QUANT_FLOAT);
    for (uint32_t j = 0; j < 8; j++)
        for (uint32_t v = 0; v < 6; v++)
            for (uint32_t c = 0; c < 3; c++)
                assert_true(sss_decode_sample(&f, j, v, c) == f.q[(j * 6 + v) * 3 + c]);
    sss_file_free(&f);
    make_file(&f, 8, 3, SSS_QUANT_LLOYD8);
    for (uint32_t j = 0; j < 8; j++)
        for (uint32_t v = 0; v < 6; v++)
            for (uint32_t c = 0; c < 3; c++)
                assert_true(sss_decode_sample(&f, j, v, c) == f.levels[c * 256 + f.qidx[(j * 6 + v) * 3 + c]]);
    sss_file_free(&f);
}

static void decodeAllIsExactAtEveryDirectionSample(void **state)
{
    (void)state;
    static const uint32_t ns[] = {1, 3, 4, 12};
    for (size_t k = 0; k < sizeof ns / sizeof ns[0]; k++)
        for (uint32_t channels = 1; channels <= 3; channels += 2)
            for (int q = 0; q < 2; q++) {
                sss_bake_file f;
                make_file(&f, ns[k], channels, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT);
                float out[6 * 3];
                for (uint32_t j = 0; j < f.dirs.n; j++) {
                    double light[3];
                    for (int i = 0; i < 3; i++) light[i] = 3.0 * f.dirs.dir[3 * j + i]; /* not unit */
                    sss_decode_all(&f, light, out);
                    for (uint32_t v = 0; v < 6; v++)
                        for (uint32_t c = 0; c < channels; c++)
                            if (out[v * channels + c] != sss_decode_sample(&f, j, v, c))
                                fail_msg("n %u ch %u quant %d dir %u v %u c %u: %.9g != %.9g", ns[k], channels, q,
                                         j, v, c, (double)out[v * channels + c],
                                         (double)sss_decode_sample(&f, j, v, c));
                }
                sss_file_free(&f);
            }
}

static void decodeAllInterpolatesWithLookupWeights(void **state)
{
    (void)state;
    for (int q = 0; q < 2; q++) {
        sss_bake_file f;
        make_file(&f, 12, 3, q ? SSS_QUANT_LLOYD8 : SSS_QUANT_FLOAT);
        float out[18];
        for (int s = 0; s < 50; s++) {
            double light[3] = {sin(0.7 * s + 0.1), cos(1.3 * s), 0.3 * sin(2.1 * s) - 0.1};
            double len = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
            double unit[3] = {light[0] / len, light[1] / len, light[2] / len};
            uint32_t idx[3];
            double w[3];
            sss_dirset_lookup(&f.dirs, unit, idx, w);
            sss_decode_all(&f, light, out);
            for (uint32_t v = 0; v < 6; v++)
                for (uint32_t c = 0; c < 3; c++) {
                    double want = 0.0, lo = INFINITY, hi = -INFINITY;
                    for (int k = 0; k < 3; k++) {
                        double x = sss_decode_sample(&f, idx[k], v, c);
                        want += w[k] * x;
                        if (w[k] > 0) { lo = fmin(lo, x); hi = fmax(hi, x); }
                    }
                    if (fabs(out[v * 3 + c] - want) > 1e-6 * (1.0 + fabs(want)))
                        fail_msg("dir %d v %u c %u: %.9g, expected %.9g", s, v, c, (double)out[v * 3 + c], want);
                    /* a convex combination stays within its samples, up to the
                     * rounding of float weights (a few ulps) */
                    assert_true(out[v * 3 + c] >= (float)lo * (1 - 4e-7f) && out[v * 3 + c] <= (float)hi * (1 + 4e-7f));
                }
        }
        /* a zero direction yields zeros rather than garbage */
        const double zero[3] = {0, 0, 0};
        memset(out, 0xFF, sizeof out);
        sss_decode_all(&f, zero, out);
        for (int i = 0; i < 18; i++) assert_true(out[i] == 0.0f);
        sss_file_free(&f);
    }
}

/* ---- golden file ------------------------------------------------------- */

/* Known content of tests/data/golden_v1.sss: make_file(12 directions, RGB,
 * float) as generated when the file was committed. */
#define GOLDEN_NDIRS 12
#define GOLDEN_SIZE 2038
#define GOLDEN_DIR1_X (-0x1.f36dd55efdabap-2)
#define GOLDEN_DIR1_Y (-0x1.c98495ad8a53fp-2)
#define GOLDEN_DIR1_Z 0x1.8p-1
#define GOLDEN_Q_5_2_1 0x1.6bd62p-4f
#define GOLDEN_Q_11_4_2 0x1.a13714p-7f

static void writeGoldenFileWhenRequested(void **state)
{
    (void)state;
    const char *w = getenv("SSS_WRITE_GOLDEN");
    if (!w || strcmp(w, "1") != 0) {
        skip();
        return;
    }
    sss_bake_file f;
    make_file(&f, GOLDEN_NDIRS, 3, SSS_QUANT_FLOAT);
    sss_error err = {{0}};
    if (sss_file_write(GOLDEN_PATH, &f, &err) != SSS_OK) fail_msg("%s", err.msg);
    printf("wrote %s\n", GOLDEN_PATH);
    printf("dir[1] = {%a, %a, %a}\n", f.dirs.dir[3], f.dirs.dir[4], f.dirs.dir[5]);
    printf("q(j=5, v=2, c=1) = %a\n", (double)f.q[(5 * 6 + 2) * 3 + 1]);
    printf("q(j=11, v=4, c=2) = %a\n", (double)f.q[(11 * 6 + 4) * 3 + 2]);
    printf("dirs.tri[0..2] = %u %u %u\n", f.dirs.tri[0], f.dirs.tri[1], f.dirs.tri[2]);
    sss_file_free(&f);
}

static uint8_t *slurp(const char *path, size_t *len)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) fail_msg("cannot open %s", path);
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    uint8_t *b = malloc((size_t)n + 1);
    assert_non_null(b);
    assert_int_equal(fread(b, 1, (size_t)n, fp), (size_t)n);
    fclose(fp);
    *len = (size_t)n;
    return b;
}

static void goldenFileDecodesWithKnownValues(void **state)
{
    (void)state;
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_read(GOLDEN_PATH, &f, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(f.version_major, 1);
    assert_int_equal(f.version_minor, 0);
    assert_int_equal(f.file_size, GOLDEN_SIZE);
    assert_int_equal(f.nsections, 5);
    assert_string_equal(f.sections[3].tag, "QFLT");
    assert_int_equal(f.mesh.nv, 6);
    assert_int_equal(f.mesh.nf, 8);
    assert_int_equal(f.channels, 3);
    assert_int_equal(f.dirs.n, GOLDEN_NDIRS);
    assert_int_equal(f.dirs.ntri, 2 * GOLDEN_NDIRS - 4);
    assert_int_equal(f.quant, SSS_QUANT_FLOAT);
    assert_null(f.levels);
    assert_string_equal(f.material.name, "skin1");
    assert_true(f.material.sigma_a[0] == 0.032 && f.material.sigma_a[1] == 0.17 && f.material.sigma_a[2] == 0.48);
    assert_true(f.material.sigmap_s[0] == 0.74 && f.material.sigmap_s[1] == 0.88 && f.material.sigmap_s[2] == 1.01);
    assert_true(f.material.eta == 1.3);
    assert_true(f.mm_per_unit == 12.5);
    assert_true(f.mesh.pos[3 * 3 + 1] == -1.0f); /* vertex 3 = (0, -1, 0) */
    assert_int_equal(f.mesh.tri[3 * 7 + 2], 5);
    assert_true(f.dirs.dir[3] == GOLDEN_DIR1_X && f.dirs.dir[4] == GOLDEN_DIR1_Y && f.dirs.dir[5] == GOLDEN_DIR1_Z);
    assert_true(f.q[(5 * 6 + 2) * 3 + 1] == GOLDEN_Q_5_2_1);
    assert_true(f.q[(11 * 6 + 4) * 3 + 2] == GOLDEN_Q_11_4_2);
    assert_string_equal(f.params_json, "{\"mesh\":\"octahedron\",\"material\":\"skin1\",\"ndirs\":12,\"eps\":0.01}");
    /* the runtime path reproduces a stored sample */
    float out[18];
    sss_decode_all(&f, &f.dirs.dir[3 * 5], out);
    assert_true(out[2 * 3 + 1] == GOLDEN_Q_5_2_1);
    sss_file_free(&f);
}

static void goldenFileReencodesToSameBytes(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = slurp(GOLDEN_PATH, &len);
    sss_bake_file f;
    expect_accept(b, len, &f);
    { /* a float file is still written as 1.0, byte for byte */
        size_t len2;
        uint8_t *c = encode(&f, &len2);
        assert_int_equal(len, len2);
        assert_memory_equal(b, c, len);
        free(c);
    }
    sss_file_free(&f);
    free(b);
}

/* ---- bounds a decode survives (docs/robustness.md items 3, 5, 6, 9) ----- */

/* Decodes and requires acceptance. */
static void expect_accept_t(const tfile *t)
{
    size_t len;
    uint8_t *b = t_join(t, &len);
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_decode(b, len, "t.sss", &f, &err) != SSS_OK) fail_msg("refused: %s", err.msg);
    sss_file_free(&f);
    free(b);
}

/* Coordinates beyond 1e15 (Embree asserted on the rays of a vertex at
 * 2e18), normals that are not unit (3e38 long: the ray origins leave any
 * range), a mesh spanning more than 1e15 mm, and mm per unit outside the
 * bake's [1e-12, 1e12]: refused. A zero normal (the bake's, where incident
 * normals cancel) is kept. */
static void decodeRejectsGeometryOutsideTheRangeItComputesIn(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    const size_t pos = 8, nrm = 8 + 12 * 6;
    reject_edit_f32(b, len, "GEOM", pos, 2e18f, "vertex 0: position coordinate 0 is 2e+18, beyond 1e+15");
    reject_edit_f32(b, len, "GEOM", pos + 4 * 5, -1.5e15f, "vertex 1: position coordinate 2");
    reject_edit_f32(b, len, "GEOM", nrm, 3e38f, "vertex 0: normal has length");
    reject_edit_f32(b, len, "GEOM", nrm + 12, 2.0f, "vertex 1: normal has length 2");
    tfile t;
    t_split(b, len, &t);
    for (int k = 0; k < 3; k++) wrf32(t_find(&t, "GEOM")->data + nrm + 4 * k, 0.0f);
    expect_accept_t(&t);
    t_free(&t);
    reject_edit_f64(b, len, "MATL", 88, 1e300, "mm_per_unit 1e+300 is outside");
    reject_edit_f64(b, len, "MATL", 88, 1e-300, "mm_per_unit 1e-300 is outside");
    /* coordinates within range, but 1e14 units at 1e12 mm per unit span 2e26 mm */
    t_split(b, len, &t);
    for (int v = 0; v < 6; v++)
        for (int k = 0; k < 3; k++) {
            uint8_t *p = t_find(&t, "GEOM")->data + pos + 12 * v + 4 * k;
            float x;
            uint32_t u = test_rd32(p);
            memcpy(&x, &u, 4);
            wrf32(p, x * 1e14f);
        }
    wrf64(t_find(&t, "MATL")->data + 88, 1e12);
    expect_reject_t(&t, SSS_ERR_CORRUPT, "section MATL: the mesh spans");
    t_free(&t);
    free(b);
}

/* Finite values near FLT_MAX in a valid layout made Inf/NaN in every
 * decoder: every stored value is bounded by SSS_VALUE_MAX (1e6) now, so
 * an accepted file decodes to finite q >= 0 by construction; a material
 * whose σ′t is below 1e-12 (σa = 0, σ′s = 1e-160 gave NaN) or whose η lies
 * where F_dr ≥ 1 is refused like the bake refuses it. */
static void decodeRejectsValuesADecodeCannotSurvive(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    reject_edit_f32(b, len, "QFLT", 4 * 7, 3e38f, "value 7 (3e+38) is beyond 1e+06");
    reject_edit_f32(b, len, "QFLT", 0, 1.0000001e6f, "value 0");
    tfile t;
    t_split(b, len, &t);
    wrf64(t_find(&t, "MATL")->data + 32 + 8, 0.0); /* fine alone: σa_G = 0 keeps σ′t = σ′s */
    expect_accept_t(&t);
    wrf64(t_find(&t, "MATL")->data + 56 + 8, 1e-160);
    expect_reject_t(&t, SSS_ERR_CORRUPT, "channel G has sigma'_t = sigma_a + sigma'_s = 1e-160");
    t_free(&t);
    reject_edit_f64(b, len, "MATL", 80, 4.0, "eta 4 is outside");
    free(b);
    b = encode_new(6, 3, SSS_QUANT_LLOYD8, &len);
    reject_edit_f32(b, len, "QL8 ", 4 + 4 * 255, 3e38f, "level 255 (3e+38) is beyond 1e+06");
    free(b);
}

/* The direction triangulation must cover the sphere once: one triangle
 * reversed, or all of them, made the lookup interpolate over triangles
 * that do not hold the light (errors 8–17 times the file's own). */
static void decodeRejectsReversedOrInconsistentTriangulation(void **state)
{
    (void)state;
    size_t len;
    uint8_t *b = encode_new(6, 3, SSS_QUANT_FLOAT, &len);
    const size_t tri = 8 + 24 * 6;
    tfile t;
    t_split(b, len, &t);
    uint8_t *d = t_find(&t, "DIRS")->data;
    uint32_t a = test_rd32(d + tri + 4), c = test_rd32(d + tri + 8);
    wr32(d + tri + 4, c);
    wr32(d + tri + 8, a);
    expect_reject_t(&t, SSS_ERR_CORRUPT, "triangle 0");
    for (uint32_t k = 1; k < 8; k++) { /* all of them reversed */
        a = test_rd32(d + tri + 12 * k + 4), c = test_rd32(d + tri + 12 * k + 8);
        wr32(d + tri + 12 * k + 4, c);
        wr32(d + tri + 12 * k + 8, a);
    }
    expect_reject_t(&t, SSS_ERR_CORRUPT, "not counter-clockwise");
    t_free(&t);
    /* two triangles made one twice (covering part of the sphere twice) */
    t_split(b, len, &t);
    d = t_find(&t, "DIRS")->data;
    memcpy(d + tri + 12, d + tri, 12);
    expect_reject_t(&t, SSS_ERR_CORRUPT, "DIRS");
    t_free(&t);
    free(b);
}

/* A FIFO given as a .sss file: refused at once (the regular-file check
 * came after a blocking open, which waited for a writer forever). */
static void readRefusesFifoWithoutBlocking(void **state)
{
    (void)state;
    char dir[] = "/tmp/sss_test_fifo_XXXXXX", path[64];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/f.sss", dir);
    assert_int_equal(mkfifo(path, 0600), 0);
    alarm(10); /* the failure of a blocking open */
    sss_bake_file f;
    sss_error err = {{0}};
    assert_int_equal(sss_file_read(path, &f, &err), SSS_ERR_IO);
    alarm(0);
    assert_non_null(strstr(err.msg, "f.sss: not a regular file"));
    unlink(path);
    rmdir(dir);
}

/* Area-weighted RMS on a mesh whose triangles all have zero area: every
 * vertex then weighs 1, so the RMS is not 0 next to a non-zero maximum. */
static void errorOfZeroAreaMeshIsNotZeroRms(void **state)
{
    (void)state;
    sss_bake_file a, r;
    make_file(&a, 6, 1, SSS_QUANT_FLOAT);
    make_file(&r, 6, 1, SSS_QUANT_FLOAT);
    for (uint32_t v = 0; v < a.mesh.nv; v++)
        for (int k = 0; k < 3; k++) a.mesh.pos[3 * v + k] = r.mesh.pos[3 * v + k] = 0.5f; /* one point */
    for (size_t i = 0; i < 6 * (size_t)a.mesh.nv; i++) a.q[i] += 0.2f;
    double rel[2], rms[2], mx = 0;
    sss_error err = {{0}};
    assert_int_equal(sss_decode_error(&a, &r, 8, 1, rel, rms, &mx, &err), SSS_OK);
    assert_true(fabs(mx - 0.2) < 1e-6);
    assert_true(rms[0] > 0.19 && rms[0] < 0.21);
    sss_file_free(&a);
    sss_file_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(crc32MatchesCheckValueAndBitwiseReference),
        cmocka_unit_test(decodeRejectsGeometryOutsideTheRangeItComputesIn),
        cmocka_unit_test(decodeRejectsValuesADecodeCannotSurvive),
        cmocka_unit_test(decodeRejectsReversedOrInconsistentTriangulation),
        cmocka_unit_test(readRefusesFifoWithoutBlocking),
        cmocka_unit_test(errorOfZeroAreaMeshIsNotZeroRms),
        cmocka_unit_test(encodeDecodeRoundTripIsExactFloat),
        cmocka_unit_test(encodeDecodeRoundTripIsExactLloyd8),
        cmocka_unit_test(encodeDecodeRoundTripIsExactGreyAndUntriangulated),
        cmocka_unit_test(encodeWritesDocumentedLayout),
        cmocka_unit_test(encodeRejectsInvalidInput),
        cmocka_unit_test(writeThenReadRoundTrips),
        cmocka_unit_test(writeReplacesExistingFile),
        cmocka_unit_test(writeToMissingDirectoryFailsWithoutTemp),
        cmocka_unit_test(writeOverDirectoryFailsAndRemovesTemp),
        cmocka_unit_test(writeOfInvalidContentKeepsExistingFile),
        cmocka_unit_test(readMissingOrNonRegularFileFailsNamingPath),
        cmocka_unit_test(readOfCorruptFileNamesPathAndSection),
        cmocka_unit_test(decodeRejectsEveryTruncatedPrefix),
        cmocka_unit_test(decodeRejectsEveryFlippedByte),
        cmocka_unit_test(decodeRejectsAppendedBytes),
        cmocka_unit_test(decodeRejectsBadMagicAndTextModeMangling),
        cmocka_unit_test(decodeRejectsNewerMajorVersion),
        cmocka_unit_test(decodeAcceptsNewerMinorVersion),
        cmocka_unit_test(decodeSkipsUnknownOptionalSection),
        cmocka_unit_test(decodeRejectsUnknownRequiredSection),
        cmocka_unit_test(decodeRejectsMissingRequiredSections),
        cmocka_unit_test(decodeRejectsDuplicateAndConflictingSections),
        cmocka_unit_test(decodeRejectsNonPrintableTag),
        cmocka_unit_test(decodeRejectsHugeSectionCount),
        cmocka_unit_test(decodeRejectsSectionOffsetsAndSizesOutsideFile),
        cmocka_unit_test(decodeRejectsHugeCountsInTinySections),
        cmocka_unit_test(decodeRejectsBadGeometry),
        cmocka_unit_test(decodeRejectsBadMaterial),
        cmocka_unit_test(decodeRejectsBadDirections),
        cmocka_unit_test(dircHoldsFloatDirectionsInHalfTheBytes),
        cmocka_unit_test(decodeRejectsBadQuantisedValues),
        cmocka_unit_test(decodeRejectsNulInParams),
        cmocka_unit_test(nbhdRoundTripsAndMakesTheFile1_4),
        cmocka_unit_test(quadAndNradRoundTripAndMakeTheFile1_5),
        cmocka_unit_test(decodeRejectsBadQuadAndNrad),
        cmocka_unit_test(decodeRejectsNbhdOfWrongSizeOrCount),
        cmocka_unit_test(decodeRejectsNbhdEpsOutsideZeroOne),
        cmocka_unit_test(decodeRejects1_4FileWithoutNbhd),
        cmocka_unit_test(filesWithoutNbhdStillReadAndKeepTheirVersion),
        cmocka_unit_test(decodeSampleReturnsStoredValues),
        cmocka_unit_test(decodeAllIsExactAtEveryDirectionSample),
        cmocka_unit_test(decodeAllInterpolatesWithLookupWeights),
        cmocka_unit_test(phasRoundTripsGAndMakesTheFile1_8),
        cmocka_unit_test(isotropicFilesHaveNoPhasAndReadGZero),
        cmocka_unit_test(decodeRejectsPhasOutOfRangeOrWrongSize),
        cmocka_unit_test(layrRoundTripsAndRejectsDisorder),
        cmocka_unit_test(ldepRoundTripsAndRejectsBadDepths),
        cmocka_unit_test(writeGoldenFileWhenRequested),
        cmocka_unit_test(goldenFileDecodesWithKnownValues),
        cmocka_unit_test(goldenFileReencodesToSameBytes),
    };
    return cmocka_run_group_tests(tests, setup_tmpdir, teardown_tmpdir);
}
