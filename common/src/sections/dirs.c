/* dirs.c: section DIRS, the light directions ω_j and their spherical
 * triangulation (docs/format.md §5.3; Hao–Varshney 2004 §3.2). The
 * triangulation is stored, not recomputed, so a reader interpolates
 * exactly as the writer did. */
#include <stdlib.h>

#include "sections.h"

uint64_t sss_sec_dirs_size(const sss_bake_file *f)
{
    return 8u + 24u * (uint64_t)f->dirs.n + 12u * (uint64_t)f->dirs.ntri;
}

uint64_t sss_sec_dirs_count(const sss_bake_file *f) { return f->dirs.n; }

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
static sss_result check_cover(const sss_dirset *s, const char *name, sss_result code, sss_error *err)
{
    if (s->ntri == 0) return SSS_OK;
    double total = 0.0;
    for (uint32_t t = 0; t < s->ntri; t++) {
        const uint32_t *x = &s->tri[3 * (size_t)t];
        const double *a = &s->dir[3 * (size_t)x[0]], *b = &s->dir[3 * (size_t)x[1]], *c = &s->dir[3 * (size_t)x[2]];
        const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                           a[2] * (b[0] * c[1] - b[1] * c[0]);
        if (!(det > 0.0))
            return sss_fail(err, code, "%s: section DIRS: triangle %u (%u %u %u) is not counter-clockwise seen from "
                            "outside (the triangulation is reversed or inconsistent)", name, t, x[0], x[1], x[2]);
        /* its solid angle (Van Oosterom and Strackee) */
        const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2], bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2],
                     ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
        total += 2.0 * atan2(det, 1.0 + ab + bc + ca);
    }
    const double four_pi = 4.0 * 3.14159265358979323846;
    if (!(fabs(total - four_pi) <= 1e-6 * four_pi))
        return sss_fail(err, code, "%s: section DIRS: the triangles cover a solid angle of %.9g, not the sphere's "
                        "4 pi once", name, total);
    const size_t ne = 3 * (size_t)s->ntri;
    uint64_t *e = malloc(ne * sizeof *e);
    if (!e) return sss_fail(err, SSS_ERR_NOMEM, "%s: section DIRS: out of memory for %zu edges", name, ne);
    for (uint32_t t = 0; t < s->ntri; t++)
        for (int k = 0; k < 3; k++)
            e[3 * (size_t)t + k] = (uint64_t)s->tri[3 * (size_t)t + k] << 32 | s->tri[3 * (size_t)t + (k + 1) % 3];
    qsort(e, ne, sizeof *e, cmp_u64);
    sss_result r = SSS_OK;
    for (size_t i = 0; i < ne && r == SSS_OK; i++) {
        const uint64_t rev = e[i] << 32 | e[i] >> 32;
        if ((i + 1 < ne && e[i + 1] == e[i]) || !bsearch(&rev, e, ne, sizeof *e, cmp_u64))
            r = sss_fail(err, code, "%s: section DIRS: edge %u -> %u is not shared by exactly two triangles in "
                         "opposite directions (the triangulation is not a closed surface)", name,
                         (uint32_t)(e[i] >> 32), (uint32_t)e[i]);
    }
    free(e);
    return r;
}

sss_result sss_sec_dirs_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_dirset *s = &f->dirs;
    if (s->n == 0 || !s->dir) return sss_fail(err, code, "%s: section DIRS: no directions", name);
    if (s->ntri != sss_sec_dirs_ntri(s->n))
        return sss_fail(err, code, "%s: section DIRS: %u triangles for %u directions, expected %llu", name, s->ntri,
                        s->n, (unsigned long long)sss_sec_dirs_ntri(s->n));
    if (s->ntri > 0 && !s->tri) return sss_fail(err, code, "%s: section DIRS: triangles missing", name);
    for (uint32_t i = 0; i < s->n; i++) {
        const double *d = &s->dir[3 * (size_t)i];
        if (!isfinite(d[0]) || !isfinite(d[1]) || !isfinite(d[2]))
            return sss_fail(err, code, "%s: section DIRS: direction %u is not finite", name, i);
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(fabs(len - 1.0) <= 1e-6))
            return sss_fail(err, code, "%s: section DIRS: direction %u has length %.9g, not 1 (tolerance 1e-6)",
                            name, i, len);
    }
    for (uint32_t t = 0; t < s->ntri; t++) {
        const uint32_t *x = &s->tri[3 * (size_t)t];
        for (int k = 0; k < 3; k++)
            if (x[k] >= s->n)
                return sss_fail(err, code, "%s: section DIRS: triangle %u: index %u out of range (%u directions)",
                                name, t, x[k], s->n);
        if (x[0] == x[1] || x[1] == x[2] || x[0] == x[2])
            return sss_fail(err, code, "%s: section DIRS: triangle %u repeats a direction (%u %u %u)", name, t,
                            x[0], x[1], x[2]);
    }
    return check_cover(s, name, code, err);
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

sss_result sss_sec_dirs_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size < 8)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section DIRS: size %llu is too small for the direction and "
                        "triangle counts", name, (unsigned long long)size);
    uint32_t n = get_u32(p), ntri = get_u32(p + 4);
    if (n == 0) return sss_fail(err, SSS_ERR_CORRUPT, "%s: section DIRS: no directions", name);
    if (ntri != sss_sec_dirs_ntri(n))
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section DIRS: %u triangles for %u directions, expected %llu", name,
                        ntri, n, (unsigned long long)sss_sec_dirs_ntri(n));
    const uint64_t want = 8u + 24u * (uint64_t)n + 12u * (uint64_t)ntri;
    if (size != want)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section DIRS: size %llu does not match %u directions and %u "
                        "triangles (%llu bytes)", name, (unsigned long long)size, n, ntri, (unsigned long long)want);
    if (count != n) return sss_sec_count_mismatch(err, name, "DIRS", count, n, "directions");
    sss_dirset *s = &f->dirs;
    s->dir = malloc(3 * (size_t)n * sizeof(double));
    s->tri = malloc((3 * (size_t)ntri + 1) * sizeof(uint32_t));
    if (!s->dir || !s->tri) return sss_sec_nomem(err, name, "DIRS", size);
    s->n = n;
    s->ntri = ntri;
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)n; k++, p += 8) s->dir[k] = get_f64(p);
    for (size_t k = 0; k < 3 * (size_t)ntri; k++, p += 4) s->tri[k] = get_u32(p);
    return sss_sec_dirs_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_dirs_free(sss_bake_file *f)
{
    free(f->dirs.dir);
    free(f->dirs.tri);
    f->dirs.dir = NULL;
    f->dirs.tri = NULL;
    f->dirs.n = f->dirs.ntri = 0;
}

int sss_sec_dirs_wants(const sss_bake_file *f) { return sss_sec_fx_uses_dirs(f->fx.mask); }

sss_sec_need sss_sec_dirs_needs(const sss_bake_file *f)
{
    return sss_sec_fx_uses_dirs(f->fx.mask) ? SSS_SEC_PRESENT : SSS_SEC_ABSENT;
}
