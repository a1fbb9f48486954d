/* ldep.c: section LDEP (format 1.9), the per-vertex depths of the layers
 * of LAYR (docs/format.md §5.22, docs/layers.md §3): nv × n float32 mm,
 * vertex-major (layer k of vertex v at v · n + k), each vertex's depths
 * non-decreasing, finite, in [0, SSS_DEPTH_MAX_MM]. Written only when a
 * scene gives some layer a depth map or a procedural depth, so files with
 * flat layers keep their bytes and their minor; optional, as LAYR is (a
 * reader without it uses LAYR's depths, each layer's largest). Read after
 * GEOM (nv) and LAYR (n). */
#include "sections.h"

#include <stdlib.h>

#include "sss/layer_depth.h"

uint64_t sss_sec_ldep_size(const sss_bake_file *f)
{
    uint64_t n;
    return mul_u64((uint64_t)f->mesh.nv * 4u, f->layers.n, &n) ? n : 0;
}

uint64_t sss_sec_ldep_count(const sss_bake_file *f) { return f->mesh.nv; }

sss_result sss_sec_ldep_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const uint32_t n = f->layers.n;
    if (!f->layer_depth || n < 1 || n > SSS_MAX_LAYERS)
        return sss_fail(err, code, "%s: section LDEP: per-vertex depths without the layers of LAYR", name);
    for (uint32_t v = 0; v < f->mesh.nv; v++) {
        const float *d = &f->layer_depth[(size_t)v * n];
        for (uint32_t k = 0; k < n; k++) {
            if (!(d[k] >= 0.0f && d[k] <= SSS_DEPTH_MAX_MM))
                return sss_fail(err, code, "%s: section LDEP: vertex %u layer %u: depth %g mm is not in [0, %g]", name,
                                v, k, (double)d[k], SSS_DEPTH_MAX_MM);
            if (k && d[k] < d[k - 1])
                return sss_fail(err, code, "%s: section LDEP: vertex %u layer %u: depth %g mm is above the layer "
                                "before it (%g mm)", name, v, k, (double)d[k], (double)d[k - 1]);
        }
    }
    return SSS_OK;
}

void sss_sec_ldep_pack(const sss_bake_file *f, uint8_t *p)
{
    const size_t m = (size_t)f->mesh.nv * f->layers.n;
    for (size_t i = 0; i < m; i++, p += 4) put_f32(p, f->layer_depth[i]);
}

sss_result sss_sec_ldep_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    const uint32_t n = f->layers.n;
    if (n == 0) return sss_fail(err, SSS_ERR_CORRUPT, "%s: section LDEP: per-vertex layer depths without section LAYR", name);
    if (count != f->mesh.nv || size != (uint64_t)f->mesh.nv * 4u * n)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section LDEP: %llu bytes, count %llu (expected %llu bytes and the "
                        "%u vertices of GEOM for %u layers)", name, (unsigned long long)size, (unsigned long long)count,
                        (unsigned long long)f->mesh.nv * 4u * n, f->mesh.nv, n);
    f->layer_depth = malloc((size_t)size + 1);
    if (!f->layer_depth) return sss_fail(err, SSS_ERR_NOMEM, "%s: section LDEP: out of memory", name);
    for (size_t i = 0; i < (size_t)f->mesh.nv * n; i++, p += 4) f->layer_depth[i] = get_f32(p);
    return sss_sec_ldep_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_ldep_free(sss_bake_file *f)
{
    free(f->layer_depth);
    f->layer_depth = NULL;
}

int sss_sec_ldep_wants(const sss_bake_file *f) { return f->layer_depth != NULL; }

sss_sec_need sss_sec_ldep_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
