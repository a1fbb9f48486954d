/* dirs.c: sections DIRS and DIRC, the light directions ω_j and their
 * spherical triangulation (docs/format.md §5.3, §5.18; Hao–Varshney 2004
 * §3.2), in double precision with 32-bit indices (DIRS) or, when every
 * component is a float and the indices fit 16 bits, in float32 with 16-bit
 * indices (DIRC: half the bytes, the same directions). The triangulation is
 * stored, not recomputed, so a reader interpolates exactly as the writer
 * did. */
#include <stdlib.h>

#include "sections.h"

/* DIRC holds a set exactly: every component a float32, every index below
 * 2^16. */
static int dirs_compact(const sss_dirset *s)
{
    if (s->n > 65536u) return 0;
    for (size_t k = 0; k < 3 * (size_t)s->n; k++)
        if ((double)(float)s->dir[k] != s->dir[k]) return 0;
    return 1;
}

uint64_t sss_sec_dirs_size(const sss_bake_file *f)
{
    return 8u + 24u * (uint64_t)f->dirs.n + 12u * (uint64_t)f->dirs.ntri;
}

uint64_t sss_sec_dirc_size(const sss_bake_file *f)
{
    return 8u + 12u * (uint64_t)f->dirs.n + 6u * (uint64_t)f->dirs.ntri;
}

uint64_t sss_sec_dirs_count(const sss_bake_file *f) { return f->dirs.n; }
uint64_t sss_sec_dirc_count(const sss_bake_file *f) { return f->dirs.n; }

uint64_t sss_sec_directions_size(const sss_bake_file *f)
{
    if (!f->dirs.n) return 0;
    return f->dirs_f32 ? sss_sec_dirc_size(f) : sss_sec_dirs_size(f);
}

static int cmp_u64(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* The triangulation a reader interpolates over (Hao–Varshney 2004 §3.2;
 * docs/format.md §5.3) must cover the sphere once: every triangle
 * counter-clockwise seen from outside, det(a, b, c) > 0, as the hull makes
 * them; every edge shared by exactly two triangles, once in each direction
 * (a closed surface); and the solid angles summing to 4π. A reversed or
 * inconsistent triangulation would make the lookup take triangles that do
 * not hold the light, with weights of either sign: the errors it gave were
 * 8 to 17 times the file's own. */
static sss_result check_cover(const sss_dirset *s, const char *tag, const char *name, sss_result code,
                               sss_error *err)
{
    if (s->ntri == 0) return SSS_OK;
    double total = 0.0;
    for (uint32_t t = 0; t < s->ntri; t++) {
        const uint32_t *x = &s->tri[3 * (size_t)t];
        const double *a = &s->dir[3 * (size_t)x[0]], *b = &s->dir[3 * (size_t)x[1]], *c = &s->dir[3 * (size_t)x[2]];
        const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                           a[2] * (b[0] * c[1] - b[1] * c[0]);
        if (!(det > 0.0))
            return sss_fail(err, code, "%s: section %s: triangle %u (%u %u %u) is not counter-clockwise seen from "
                            "outside (the triangulation is reversed or inconsistent)", name, tag, t, x[0], x[1], x[2]);
        /* its solid angle (Van Oosterom and Strackee) */
        const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2], bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2],
                     ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
        total += 2.0 * atan2(det, 1.0 + ab + bc + ca);
    }
    const double four_pi = 4.0 * 3.14159265358979323846;
    if (!(fabs(total - four_pi) <= 1e-6 * four_pi))
        return sss_fail(err, code, "%s: section %s: the triangles cover a solid angle of %.9g, not the sphere's "
                        "4 pi once", name, tag, total);
    const size_t ne = 3 * (size_t)s->ntri;
    uint64_t *e = malloc(ne * sizeof *e);
    if (!e) return sss_fail(err, SSS_ERR_NOMEM, "%s: section %s: out of memory for %zu edges", name, tag, ne);
    for (uint32_t t = 0; t < s->ntri; t++)
        for (int k = 0; k < 3; k++)
            e[3 * (size_t)t + k] = (uint64_t)s->tri[3 * (size_t)t + k] << 32 | s->tri[3 * (size_t)t + (k + 1) % 3];
    qsort(e, ne, sizeof *e, cmp_u64);
    sss_result r = SSS_OK;
    for (size_t i = 0; i < ne && r == SSS_OK; i++) {
        const uint64_t rev = e[i] << 32 | e[i] >> 32;
        if ((i + 1 < ne && e[i + 1] == e[i]) || !bsearch(&rev, e, ne, sizeof *e, cmp_u64))
            r = sss_fail(err, code, "%s: section %s: edge %u -> %u is not shared by exactly two triangles in "
                         "opposite directions (the triangulation is not a closed surface)", name, tag,
                         (uint32_t)(e[i] >> 32), (uint32_t)e[i]);
    }
    free(e);
    return r;
}

static sss_result check_set(const sss_bake_file *f, const char *tag, const char *name, sss_result code,
                            sss_error *err)
{
    const sss_dirset *s = &f->dirs;
    if (s->n == 0 || !s->dir) return sss_fail(err, code, "%s: section %s: no directions", name, tag);
    if (s->ntri != sss_sec_dirs_ntri(s->n))
        return sss_fail(err, code, "%s: section %s: %u triangles for %u directions, expected %llu", name, tag, s->ntri,
                        s->n, (unsigned long long)sss_sec_dirs_ntri(s->n));
    if (s->ntri > 0 && !s->tri) return sss_fail(err, code, "%s: section %s: triangles missing", name, tag);
    for (uint32_t i = 0; i < s->n; i++) {
        const double *d = &s->dir[3 * (size_t)i];
        if (!isfinite(d[0]) || !isfinite(d[1]) || !isfinite(d[2]))
            return sss_fail(err, code, "%s: section %s: direction %u is not finite", name, tag, i);
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(fabs(len - 1.0) <= 1e-6))
            return sss_fail(err, code, "%s: section %s: direction %u has length %.9g, not 1 (tolerance 1e-6)",
                            name, tag, i, len);
    }
    for (uint32_t t = 0; t < s->ntri; t++) {
        const uint32_t *x = &s->tri[3 * (size_t)t];
        for (int k = 0; k < 3; k++)
            if (x[k] >= s->n)
                return sss_fail(err, code, "%s: section %s: triangle %u: index %u out of range (%u directions)",
                                name, tag, t, x[k], s->n);
        if (x[0] == x[1] || x[1] == x[2] || x[0] == x[2])
            return sss_fail(err, code, "%s: section %s: triangle %u repeats a direction (%u %u %u)", name, tag, t,
                            x[0], x[1], x[2]);
    }
    return check_cover(s, tag, name, code, err);
}

sss_result sss_sec_dirs_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    return check_set(f, "DIRS", name, code, err);
}

sss_result sss_sec_dirc_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    if (!dirs_compact(&f->dirs))
        return sss_fail(err, code, "%s: section DIRC: the %u directions are not all float32 with 16-bit indices",
                        name, f->dirs.n);
    return check_set(f, "DIRC", name, code, err);
}

void sss_sec_dirs_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_dirset *ds = &f->dirs;
    put_u32(p, ds->n);
    put_u32(p + 4, ds->ntri);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)ds->n; k++, p += 8) put_f64(p, ds->dir[k]);
    for (size_t k = 0; k < 3 * (size_t)ds->ntri; k++, p += 4) put_u32(p, ds->tri[k]);
}

void sss_sec_dirc_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_dirset *ds = &f->dirs;
    put_u32(p, ds->n);
    put_u32(p + 4, ds->ntri);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)ds->n; k++, p += 4) put_f32(p, (float)ds->dir[k]);
    for (size_t k = 0; k < 3 * (size_t)ds->ntri; k++, p += 2) put_u16(p, (uint16_t)ds->tri[k]);
}

/* Both sections: counts, then the directions of dbytes (8: f64, 4: f32)
 * and the indices of ibytes (4: u32, 2: u16) each. */
static sss_result parse_set(const uint8_t *p, uint64_t size, uint64_t count, const char *tag, unsigned dbytes,
                            unsigned ibytes, const char *name, sss_bake_file *f, sss_error *err)
{
    if (size < 8)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section %s: size %llu is too small for the direction and "
                        "triangle counts", name, tag, (unsigned long long)size);
    uint32_t n = get_u32(p), ntri = get_u32(p + 4);
    if (n == 0) return sss_fail(err, SSS_ERR_CORRUPT, "%s: section %s: no directions", name, tag);
    if (ntri != sss_sec_dirs_ntri(n))
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section %s: %u triangles for %u directions, expected %llu", name,
                        tag, ntri, n, (unsigned long long)sss_sec_dirs_ntri(n));
    const uint64_t want = 8u + 3u * dbytes * (uint64_t)n + 3u * ibytes * (uint64_t)ntri;
    if (size != want)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section %s: size %llu does not match %u directions and %u "
                        "triangles (%llu bytes)", name, tag, (unsigned long long)size, n, ntri,
                        (unsigned long long)want);
    if (count != n) return sss_sec_count_mismatch(err, name, tag, count, n, "directions");
    sss_dirset *s = &f->dirs;
    s->dir = malloc(3 * (size_t)n * sizeof(double));
    s->tri = malloc((3 * (size_t)ntri + 1) * sizeof(uint32_t));
    if (!s->dir || !s->tri) return sss_sec_nomem(err, name, tag, size);
    s->n = n;
    s->ntri = ntri;
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)n; k++, p += dbytes) s->dir[k] = dbytes == 8 ? get_f64(p) : get_f32(p);
    for (size_t k = 0; k < 3 * (size_t)ntri; k++, p += ibytes) s->tri[k] = ibytes == 4 ? get_u32(p) : get_u16(p);
    return check_set(f, tag, name, SSS_ERR_CORRUPT, err);
}

sss_result sss_sec_dirs_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    return parse_set(p, size, count, "DIRS", 8, 4, name, f, err);
}

sss_result sss_sec_dirc_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    f->dirs_f32 = 1;
    return parse_set(p, size, count, "DIRC", 4, 2, name, f, err);
}

void sss_sec_dirs_free(sss_bake_file *f)
{
    free(f->dirs.dir);
    free(f->dirs.tri);
    f->dirs.dir = NULL;
    f->dirs.tri = NULL;
    f->dirs.n = f->dirs.ntri = 0;
}

/* one set in memory for both sections */
void sss_sec_dirc_free(sss_bake_file *f) { sss_sec_dirs_free(f); }

/* The writer takes DIRC when the file asks for it (a compressed bake
 * rounds its directions to float32 before computing the rows,
 * docs/format.md §5.18), DIRS otherwise, so that a file of the older
 * sections keeps its version whatever its directions are. */
int sss_sec_dirs_wants(const sss_bake_file *f) { return sss_sec_fx_uses_dirs(f->fx.mask) && !f->dirs_f32; }
int sss_sec_dirc_wants(const sss_bake_file *f) { return sss_sec_fx_uses_dirs(f->fx.mask) && f->dirs_f32; }

/* which of the two a file holds is a cross-section rule (format.c, §5.10) */
sss_sec_need sss_sec_dirs_needs(const sss_bake_file *f)
{
    return sss_sec_fx_uses_dirs(f->fx.mask) ? SSS_SEC_EITHER : SSS_SEC_ABSENT;
}

sss_sec_need sss_sec_dirc_needs(const sss_bake_file *f) { return sss_sec_dirs_needs(f); }
