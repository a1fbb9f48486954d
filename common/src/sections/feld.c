/* feld.c: section FELD (format 1.8), a heterogeneous object's material
 * field (docs/format.md §5.22, docs/heterogeneous.md): the field f(x) in
 * the object's rest frame, the material at f = 1 and the map from the
 * file's mesh units to the rest frame, so that the exact evaluator
 * recomputes the spatially varying kernel from the file alone. Layout:
 *
 *   u32 kind (1 … 7, sss_field_kind), u32 seed,
 *   f64 value, scale_mm, centre_mm[3], half_mm[3], normal[3],
 *       thickness_mm, offset_mm, edge_mm,
 *   f64 xf[12] (mesh units → rest-frame mm, row-major 3 × 4),
 *   f64 inside sigma_a[3], sigmap_s[3],
 *   u32 n[3], u32 flags (bit 0: a surface texture), f64 origin_mm[3], voxel_mm,
 *   f32 values[n0 · n1 · n2] (kind grid only; n = 0 otherwise).
 *
 * Required-flagged: a reader that ignored it would take the object for
 * the homogeneous base material of section MATL.
 */
#include <stdlib.h>
#include <string.h>

#include "sections.h"

#define FELD_FIXED 312u
/* flag bit 0: a surface texture (Hao–Varshney 2004 §5), the kernel
 * without τ (docs/heterogeneous.md §4.4); the only bit 1.9 knows */
#define FELD_SURFACE 1u

static uint64_t nodes(const sss_field *fl)
{
    return fl->kind == SSS_FIELD_GRID ? (uint64_t)fl->n[0] * fl->n[1] * fl->n[2] : 0;
}

uint64_t sss_sec_feld_size(const sss_bake_file *f) { return FELD_FIXED + 4u * nodes(&f->hetero.field); }

uint64_t sss_sec_feld_count(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_result sss_sec_feld_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_hetero *h = &f->hetero;
    sss_error e2 = {{0}};
    if (h->field.kind == SSS_FIELD_NONE || h->field.kind >= SSS_FIELD_KINDS)
        return sss_fail(err, code, "%s: section FELD: field kind %u (1 to %u)", name, h->field.kind,
                        SSS_FIELD_KINDS - 1);
    if (sss_field_check(&h->field, &e2) != SSS_OK) return sss_fail(err, code, "%s: section FELD: %s", name, e2.msg);
    for (int k = 0; k < 12; k++)
        if (!isfinite(h->xf[k]) || fabs(h->xf[k]) > 1e15)
            return sss_fail(err, code, "%s: section FELD: rest-frame map entry %d is %g", name, k, h->xf[k]);
    sss_material m = f->material; /* the inside material shares the object's η */
    memcpy(m.sigma_a, h->inside.sigma_a, sizeof m.sigma_a);
    memcpy(m.sigmap_s, h->inside.sigmap_s, sizeof m.sigmap_s);
    if (sss_material_check(&m, f->channels, code, &e2) != SSS_OK)
        return sss_fail(err, code, "%s: section FELD: inside material: %s", name, e2.msg);
    return SSS_OK;
}

void sss_sec_feld_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_hetero *h = &f->hetero;
    const sss_field *fl = &h->field;
    put_u32(p, fl->kind);
    put_u32(p + 4, fl->seed);
    double v[14 + 12 + 6];
    int k = 0;
    v[k++] = fl->value;
    v[k++] = fl->scale_mm;
    for (int a = 0; a < 3; a++) v[k++] = fl->centre_mm[a];
    for (int a = 0; a < 3; a++) v[k++] = fl->half_mm[a];
    for (int a = 0; a < 3; a++) v[k++] = fl->normal[a];
    v[k++] = fl->thickness_mm;
    v[k++] = fl->offset_mm;
    v[k++] = fl->edge_mm;
    for (int a = 0; a < 12; a++) v[k++] = h->xf[a];
    for (int a = 0; a < 3; a++) v[k++] = h->inside.sigma_a[a];
    for (int a = 0; a < 3; a++) v[k++] = h->inside.sigmap_s[a];
    uint8_t *q = p + 8;
    for (int a = 0; a < k; a++, q += 8) put_f64(q, v[a]);
    const int grid = fl->kind == SSS_FIELD_GRID;
    for (int a = 0; a < 3; a++, q += 4) put_u32(q, grid ? fl->n[a] : 0);
    put_u32(q, h->surface ? FELD_SURFACE : 0u); /* 0 for a volume field: its bytes as before the flag */
    q += 4;
    for (int a = 0; a < 3; a++, q += 8) put_f64(q, grid ? fl->origin_mm[a] : 0.0);
    put_f64(q, grid ? fl->voxel_mm : 0.0);
    q += 8;
    for (uint64_t i = 0; i < nodes(fl); i++, q += 4) put_f32(q, fl->data[i]);
}

sss_result sss_sec_feld_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size < FELD_FIXED || count != 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section FELD: %llu bytes, count %llu (expected at least %u and 1)",
                        name, (unsigned long long)size, (unsigned long long)count, FELD_FIXED);
    sss_hetero *h = &f->hetero;
    sss_field *fl = &h->field;
    memset(h, 0, sizeof *h);
    fl->kind = get_u32(p);
    fl->seed = get_u32(p + 4);
    const uint8_t *q = p + 8;
    double v[14 + 12 + 6];
    for (int a = 0; a < 32; a++, q += 8) v[a] = get_f64(q);
    int k = 0;
    fl->value = v[k++];
    fl->scale_mm = v[k++];
    for (int a = 0; a < 3; a++) fl->centre_mm[a] = v[k++];
    for (int a = 0; a < 3; a++) fl->half_mm[a] = v[k++];
    for (int a = 0; a < 3; a++) fl->normal[a] = v[k++];
    fl->thickness_mm = v[k++];
    fl->offset_mm = v[k++];
    fl->edge_mm = v[k++];
    for (int a = 0; a < 12; a++) h->xf[a] = v[k++];
    h->inside = f->material;
    for (int a = 0; a < 3; a++) h->inside.sigma_a[a] = v[k++];
    for (int a = 0; a < 3; a++) h->inside.sigmap_s[a] = v[k++];
    uint32_t n[3];
    for (int a = 0; a < 3; a++, q += 4) n[a] = get_u32(q);
    const uint32_t flags = get_u32(q);
    q += 4;
    if (flags & ~FELD_SURFACE) {
        /* a later model of the field's kernel: recomputing it as this one
         * would give another q (docs/format.md §5.22) */
        uint32_t b = 0;
        while (!((flags & ~FELD_SURFACE) >> b & 1u)) b++;
        memset(h, 0, sizeof *h);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: section FELD: flag bit %u is unknown to this reader (format %d.%d)",
                        name, b, SSS_FORMAT_MAJOR, SSS_FORMAT_MINOR);
    }
    h->surface = (flags & FELD_SURFACE) != 0;
    double origin[3], voxel;
    for (int a = 0; a < 3; a++, q += 8) origin[a] = get_f64(q);
    voxel = get_f64(q);
    q += 8;
    const uint64_t nn = (uint64_t)n[0] * n[1] * n[2];
    if (fl->kind == SSS_FIELD_GRID) {
        /* the node count checked against the limit and the section's size
         * before anything is allocated */
        if (!n[0] || !n[1] || !n[2] || nn > SSS_FIELD_GRID_MAX_NODES || size != FELD_FIXED + 4u * nn) {
            memset(h, 0, sizeof *h);
            return sss_fail(err, SSS_ERR_CORRUPT, "%s: section FELD: a grid of %u x %u x %u nodes in %llu bytes", name,
                            n[0], n[1], n[2], (unsigned long long)size);
        }
        memcpy(fl->n, n, sizeof n);
        memcpy(fl->origin_mm, origin, sizeof origin);
        fl->voxel_mm = voxel;
        if (!(fl->data = malloc((size_t)nn * sizeof *fl->data))) {
            memset(h, 0, sizeof *h);
            return sss_fail(err, SSS_ERR_NOMEM, "%s: section FELD: out of memory for %llu nodes", name,
                            (unsigned long long)nn);
        }
        for (uint64_t i = 0; i < nn; i++, q += 4) fl->data[i] = get_f32(q);
    } else if (size != FELD_FIXED || nn != 0) {
        memset(h, 0, sizeof *h);
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section FELD: %llu bytes for a %s field (expected %u, no grid)",
                        name, (unsigned long long)size, sss_field_kind_name(fl->kind), FELD_FIXED);
    }
    return sss_sec_feld_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_feld_free(sss_bake_file *f)
{
    sss_field_free(&f->hetero.field);
    memset(&f->hetero, 0, sizeof f->hetero);
}

int sss_sec_feld_wants(const sss_bake_file *f) { return f->hetero.field.kind != SSS_FIELD_NONE; }

sss_sec_need sss_sec_feld_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
