/* api.c: the runtime API an engine embeds (sss/api.h). A thin layer: the
 * file is read by format.c, the rows decoded by decode.c, the near terms
 * summed by nearterms.c, the visibility rays traced by bvh.c and the scene
 * effects decoded by effects.c; this file checks arguments and ties them
 * together for a range of vertices. After open nothing here writes to the
 * asset, which is what makes concurrent decodes safe. */
#include "sss/api.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/bvh.h"
#include "sss/decode.h"
#include "sss/effects.h"
#include "sss/nearterms.h"

struct sss_asset {
    sss_bake_file f;
    char *name;
    /* a file with run-time near terms (OWNT): their rows, the hierarchy of
     * the bake's visibility rays and their origin offset δ */
    int near_on;
    sss_weights near;
    sss_bvh bvh;
    float delta;
};

static const char *label(const sss_asset *a) { return a && a->name ? a->name : "sss_asset"; }

/* Finishes an asset whose file is decoded: the near terms' rows and rays. */
static sss_result finish(sss_asset *a, sss_error *err)
{
    const sss_bake_file *f = &a->f;
    if (!f->near_terms) return SSS_OK;
    sss_result r = sss_near_build_file(f, &a->near, err);
    if (r == SSS_OK) r = sss_bvh_build(f->mesh.pos, f->mesh.nv, f->mesh.tri, f->mesh.nf, &a->bvh, err);
    if (r != SSS_OK) return r;
    a->delta = sss_mesh_ray_offset(&f->mesh);
    a->near_on = 1;
    return SSS_OK;
}

/* The common tail of both opens: *a holds a decoded file (or the reader's
 * error r). */
static sss_result open_tail(sss_asset *a, const char *name, sss_result r, sss_asset **out, sss_error *err)
{
    if (r == SSS_OK && !(a->name = malloc(strlen(name) + 1))) r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", name);
    if (r == SSS_OK) {
        memcpy(a->name, name, strlen(name) + 1);
        r = finish(a, err);
    }
    if (r != SSS_OK) {
        sss_asset_close(a);
        return r;
    }
    *out = a;
    return SSS_OK;
}

sss_result sss_asset_open(const char *path, sss_asset **out, sss_error *err)
{
    if (!out) return sss_fail(err, SSS_ERR_ARG, "sss_asset_open: out is NULL");
    *out = NULL;
    if (!path) return sss_fail(err, SSS_ERR_ARG, "sss_asset_open: path is NULL");
    if (!*path) return sss_fail(err, SSS_ERR_ARG, "sss_asset_open: path is empty");
    sss_asset *a = calloc(1, sizeof *a);
    if (!a) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    return open_tail(a, path, sss_file_read(path, &a->f, err), out, err);
}

sss_result sss_asset_open_memory(const void *buf, size_t len, const char *name, sss_asset **out, sss_error *err)
{
    if (!name) name = "<memory>";
    if (!out) return sss_fail(err, SSS_ERR_ARG, "%s: sss_asset_open_memory: out is NULL", name);
    *out = NULL;
    if (!buf) return sss_fail(err, SSS_ERR_ARG, "%s: sss_asset_open_memory: buf is NULL", name);
    if (len == 0) return sss_fail(err, SSS_ERR_ARG, "%s: sss_asset_open_memory: len is 0", name);
    sss_asset *a = calloc(1, sizeof *a);
    if (!a) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", name);
    return open_tail(a, name, sss_file_decode(buf, len, name, &a->f, err), out, err);
}

void sss_asset_close(sss_asset *a)
{
    if (!a) return;
    sss_file_free(&a->f);
    sss_weights_free(&a->near);
    sss_bvh_free(&a->bvh);
    free(a->name);
    free(a);
}

static void copy_name(char *dst, const char *src)
{
    snprintf(dst, SSS_ASSET_NAME_MAX, "%s", src);
}

static int has_dir_set(const sss_bake_file *f) { return f->fx.mask == 0 || (f->fx.mask & SSS_FX_DIR_SET); }

sss_result sss_asset_info(const sss_asset *a, sss_asset_desc *info, sss_error *err)
{
    if (!a) return sss_fail(err, SSS_ERR_ARG, "sss_asset_info: asset is NULL");
    if (!info) return sss_fail(err, SSS_ERR_ARG, "%s: sss_asset_info: info is NULL", label(a));
    const sss_bake_file *f = &a->f;
    memset(info, 0, sizeof *info);
    info->nv = f->mesh.nv;
    info->nf = f->mesh.nf;
    info->channels = f->channels;
    info->quant = (uint32_t)f->quant;
    copy_name(info->quant_name, sss_quant_name(f->quant));
    const int coded = f->quant == SSS_QUANT_SH || f->quant == SSS_QUANT_REFS;
    info->sh_order = coded ? f->sh.order : 0;
    copy_name(info->sh_kind_name, coded && f->sh.order ? sss_shq_name(f->sh.kind) : "");
    info->ndirs = f->dirs.n;
    info->effects = f->fx.mask;
    info->has_dir_set = (uint32_t)has_dir_set(f);
    info->near_terms = f->near_terms ? 1u : 0u;
    info->near_rings = f->near_terms ? f->near_rings : 0;
    info->near_radius_mm = f->near_terms ? f->near_radius_mm : 0.0;
    info->nexact = (f->fx.mask & SSS_FX_DIR_EXACT) ? f->fx.nexact : 0;
    info->nshells = (f->fx.mask & SSS_FX_POINT_SHELLS) ? f->fx.nshells : 0;
    info->env_order = (f->fx.mask & SSS_FX_ENV_SH) ? f->fx.env_order : 0;
    info->version_major = f->version_major;
    info->version_minor = f->version_minor;
    info->file_bytes = f->file_size;
    info->integral_bytes_per_vertex = sss_file_integral_bytes_per_vertex(f);
    info->mm_per_unit = f->mm_per_unit;
    snprintf(info->material_name, sizeof info->material_name, "%s", f->material.name);
    for (uint32_t c = 0; c < 3 && c < SSS_MAX_CHANNELS; c++) {
        info->sigma_a[c] = f->material.sigma_a[c];
        info->sigmap_s[c] = f->material.sigmap_s[c];
    }
    info->eta = f->material.eta;
    info->g = f->material.g;
    info->nlayers = f->layers.n;
    info->layer_depths = f->layer_depth != NULL;
    return SSS_OK;
}

const char *sss_asset_name(const sss_asset *a) { return a ? a->name : NULL; }
const float *sss_asset_positions(const sss_asset *a) { return a ? a->f.mesh.pos : NULL; }
const float *sss_asset_normals(const sss_asset *a) { return a ? a->f.mesh.nrm : NULL; }
const uint32_t *sss_asset_triangles(const sss_asset *a) { return a ? a->f.mesh.tri : NULL; }
const sss_bake_file *sss_asset_file(const sss_asset *a) { return a ? &a->f : NULL; }

const char *sss_asset_params_json(const sss_asset *a)
{
    if (!a) return NULL;
    return a->f.params_json ? a->f.params_json : "";
}

/* The checks every decode shares: the asset, the output, the range. */
static sss_result check_range(const sss_asset *a, const char *fn, uint32_t first, uint32_t count, const void *out,
                              sss_error *err)
{
    if (!a) return sss_fail(err, SSS_ERR_ARG, "%s: asset is NULL", fn);
    if (!out) return sss_fail(err, SSS_ERR_ARG, "%s: %s: out is NULL", label(a), fn);
    if (count == 0) return sss_fail(err, SSS_ERR_ARG, "%s: %s: count is 0", label(a), fn);
    const uint32_t nv = a->f.mesh.nv;
    if (first >= nv || count > nv - first)
        return sss_fail(err, SSS_ERR_ARG, "%s: %s: vertices [%u, %llu) beyond the mesh's %u", label(a), fn, first,
                        (unsigned long long)first + count, nv);
    return SSS_OK;
}

/* light as a unit vector in d; SSS_ERR_ARG for NULL, zero or non-finite. */
static sss_result unit_light(const sss_asset *a, const char *fn, const char *what, const double light[3], double d[3],
                             sss_error *err)
{
    if (!light) return sss_fail(err, SSS_ERR_ARG, "%s: %s: %s is NULL", label(a), fn, what);
    const double n = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    if (!(n > 0.0) || !isfinite(n))
        return sss_fail(err, SSS_ERR_ARG, "%s: %s: %s (%g, %g, %g) is zero or not finite", label(a), fn, what,
                        light[0], light[1], light[2]);
    for (int k = 0; k < 3; k++) d[k] = light[k] / n;
    return SSS_OK;
}

/* The near terms of rows [first, first + count) added to out: every vertex
 * the rows hold gets its visibility (the caller's lit, else the bake's ray
 * through the BVH), then each row sss_near_sum's float sum, as sss_near_add
 * forms it for the whole mesh. */
static sss_result add_near(const sss_asset *a, const double d[3], uint32_t first, uint32_t count, const uint8_t *lit,
                           float *out, sss_error *err)
{
    const sss_bake_file *f = &a->f;
    const uint32_t nv = f->mesh.nv, C = f->channels;
    const sss_weights *nr = &a->near;
    float *gv = malloc((size_t)nv * sizeof *gv + 1);
    uint8_t *own = lit ? NULL : calloc((size_t)nv + 1, 1);
    if (!gv || (!lit && !own)) {
        free(gv);
        free(own);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: sss_asset_decode: out of memory for the near terms of %u vertices",
                        label(a), nv);
    }
    if (!lit) {
        /* mark the vertices the range's rows hold (2), then trace those */
        for (uint32_t o = first; o < first + count; o++)
            for (uint64_t e = nr->start[o]; e < nr->start[o + 1]; e++) own[nr->idx[e]] = 2;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1024) if (nv >= 4096)
#endif
        for (int64_t v = 0; v < (int64_t)nv; v++)
            if (own[v] == 2) own[v] = sss_bvh_lit(&a->bvh, &f->mesh, a->delta, (uint32_t)v, d);
        lit = own;
    }
    sss_near_transfer(f->mesh.nrm, nv, (float)f->material.eta, d, lit, gv);
    for (uint32_t o = first; o < first + count; o++) {
        float s[SSS_MAX_CHANNELS];
        sss_near_sum(nr, o, gv, s);
        for (uint32_t c = 0; c < C; c++) out[(size_t)(o - first) * C + c] += s[c];
    }
    free(gv);
    free(own);
    return SSS_OK;
}

sss_result sss_asset_decode(const sss_asset *a, const double light[3], uint32_t first, uint32_t count,
                            const uint8_t *lit, float *out, sss_error *err)
{
    static const char fn[] = "sss_asset_decode";
    sss_result r = check_range(a, fn, first, count, out, err);
    double d[3];
    if (r == SSS_OK) r = unit_light(a, fn, "light", light, d, err);
    if (r != SSS_OK) return r;
    if (!has_dir_set(&a->f))
        return sss_fail(err, SSS_ERR_ARG, "%s: %s: the file holds no direction set (a scene bake without DIRS rows)",
                        label(a), fn);
    /* the rows decoded from the caller's light, not from d: sss_decode_all
     * normalises it itself, and so gives these very bits; a file with the
     * vector integrals Q is read as the viewer reads it, Q interpolated and
     * dotted with the light (Hao–Varshney 2004 §3.2, docs/format.md §5.19) */
    if (sss_decode_has_vector(&a->f)) sss_decode_vector_range(&a->f, light, SSS_INTERP_TRIANGLE, first, count, out);
    else sss_decode_range(&a->f, light, first, count, out);
    return a->near_on ? add_near(a, d, first, count, lit, out, err) : SSS_OK;
}

sss_result sss_asset_visibility(const sss_asset *a, const double light[3], uint8_t *lit, sss_error *err)
{
    static const char fn[] = "sss_asset_visibility";
    if (!a) return sss_fail(err, SSS_ERR_ARG, "%s: asset is NULL", fn);
    if (!lit) return sss_fail(err, SSS_ERR_ARG, "%s: %s: lit is NULL", label(a), fn);
    double d[3];
    sss_result r = unit_light(a, fn, "light", light, d, err);
    if (r != SSS_OK) return r;
    if (!a->near_on)
        return sss_fail(err, SSS_ERR_ARG,
                        "%s: %s: the file has no run-time near terms (no section OWNT), so no visibility to trace",
                        label(a), fn);
    const int64_t nv = a->f.mesh.nv;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1024) if (nv >= 4096)
#endif
    for (int64_t v = 0; v < nv; v++) lit[v] = sss_bvh_lit(&a->bvh, &a->f.mesh, a->delta, (uint32_t)v, d);
    return SSS_OK;
}

/* SSS_ERR_ARG unless the file holds effect `bit`. */
static sss_result need_effect(const sss_asset *a, const char *fn, uint32_t bit, const char *section, sss_error *err)
{
    if (a->f.fx.mask & bit) return SSS_OK;
    return sss_fail(err, SSS_ERR_ARG, "%s: %s: the file holds no %s (section %s)", label(a), fn,
                    bit == SSS_FX_DIR_EXACT    ? "static directional lights"
                    : bit == SSS_FX_POINT_SHELLS ? "point-light shells"
                                                 : "environment transfer",
                    section);
}

static sss_result check_exact(const sss_asset *a, const char *fn, uint32_t index, sss_error *err)
{
    sss_result r = need_effect(a, fn, SSS_FX_DIR_EXACT, "QDIR", err);
    if (r == SSS_OK && index >= a->f.fx.nexact)
        r = sss_fail(err, SSS_ERR_ARG, "%s: %s: index %u beyond the file's %u static directional lights", label(a),
                     fn, index, a->f.fx.nexact);
    return r;
}

sss_result sss_asset_exact_direction(const sss_asset *a, uint32_t index, double dir[3], sss_error *err)
{
    static const char fn[] = "sss_asset_exact_direction";
    if (!a) return sss_fail(err, SSS_ERR_ARG, "%s: asset is NULL", fn);
    if (!dir) return sss_fail(err, SSS_ERR_ARG, "%s: %s: dir is NULL", label(a), fn);
    sss_result r = check_exact(a, fn, index, err);
    if (r != SSS_OK) return r;
    for (int k = 0; k < 3; k++) dir[k] = a->f.fx.exact_dir[3 * (size_t)index + k];
    return SSS_OK;
}

sss_result sss_asset_decode_exact(const sss_asset *a, uint32_t index, uint32_t first, uint32_t count, float *out,
                                  sss_error *err)
{
    static const char fn[] = "sss_asset_decode_exact";
    sss_result r = check_range(a, fn, first, count, out, err);
    if (r == SSS_OK) r = check_exact(a, fn, index, err);
    if (r != SSS_OK) return r;
    const size_t C = a->f.channels;
    memcpy(out, sss_fx_exact(&a->f, index) + (size_t)first * C, (size_t)count * C * sizeof *out);
    return SSS_OK;
}

sss_result sss_asset_decode_point(const sss_asset *a, const double position[3], uint32_t first, uint32_t count,
                                  float *out, sss_error *err)
{
    static const char fn[] = "sss_asset_decode_point";
    sss_result r = check_range(a, fn, first, count, out, err);
    if (r == SSS_OK) r = need_effect(a, fn, SSS_FX_POINT_SHELLS, "PSHL", err);
    if (r != SSS_OK) return r;
    if (!position) return sss_fail(err, SSS_ERR_ARG, "%s: %s: position is NULL", label(a), fn);
    if (!isfinite(position[0]) || !isfinite(position[1]) || !isfinite(position[2]))
        return sss_fail(err, SSS_ERR_ARG, "%s: %s: position (%g, %g, %g) is not finite", label(a), fn, position[0],
                        position[1], position[2]);
    sss_fx_point_range(&a->f, position, first, count, out);
    return SSS_OK;
}

sss_result sss_asset_decode_env(const sss_asset *a, const float *probe, uint32_t first, uint32_t count, float *out,
                                sss_error *err)
{
    static const char fn[] = "sss_asset_decode_env";
    sss_result r = check_range(a, fn, first, count, out, err);
    if (r == SSS_OK) r = need_effect(a, fn, SSS_FX_ENV_SH, "ENVT", err);
    if (r != SSS_OK) return r;
    sss_fx_env_range(&a->f, probe, first, count, out);
    return SSS_OK;
}
