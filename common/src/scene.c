/* scene.c: scene files (docs/scenes.md) parsed with cJSON into sss_scene.
 * Every check reports the JSON path of the element at fault (RFC 6901
 * pointer syntax), so a user can find it in a long file: README.md, "Errors"
 * "Effects" makes the scene the input that decides what gets baked, so a
 * misread scene would silently bake the wrong effects.
 *
 * Unknown keys are refused, not ignored: a misspelt "moving" would
 * otherwise turn a moving light into a static one and bake a single exact
 * direction where the scene needs the direction set.
 */
#define _POSIX_C_SOURCE 200809L
#include "sss/scene.h"
#include "sss/fileio.h"
#include "sss/vec3.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A JSON path under construction plus where to report. */
typedef struct ctx {
    const char *file;
    char dir[SSS_SCENE_PATH_MAX]; /* directory of the file, with trailing '/', or "" */
    sss_error *err;
} ctx;

static sss_result fail_at(const ctx *c, const char *jpath, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static sss_result fail_at(const ctx *c, const char *jpath, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    sss_result r = sss_fail(c->err, SSS_ERR_ARG, "%s: %s: %s", c->file, jpath[0] ? jpath : "/", msg);
    /* Keys and strings from the file are echoed in the message: a control
     * character there (a newline, found by fuzz_scene) would break the
     * one-line contract of README.md, "Errors", so it is shown as '?'. */
    if (c->err)
        for (char *q = c->err->msg; *q; q++)
            if ((unsigned char)*q < 0x20 || *q == 0x7f) *q = '?';
    return r;
}

/* child path "parent/key" (RFC 6901 escapes ~ and /). */
static void join(char *out, size_t n, const char *parent, const char *key)
{
    size_t k = (size_t)snprintf(out, n, "%s/", parent);
    for (const char *p = key; *p && k + 3 < n; p++) {
        if (*p == '~') { out[k++] = '~'; out[k++] = '0'; }
        else if (*p == '/') { out[k++] = '~'; out[k++] = '1'; }
        else out[k++] = *p;
    }
    out[k < n ? k : n - 1] = 0;
}

/* A JSON path for messages: one too long for out is cut (snprintf ends it
 * with 0 either way; the check is what tells GCC the cut is meant). */
static void join_index(char *out, size_t n, const char *parent, int i)
{
    if (snprintf(out, n, "%s/%d", parent, i) < 0) out[0] = 0;
}

/* Refuses keys of obj not in `allowed` (NULL-terminated, at most 16), and a
 * key given twice: cJSON keeps both and a lookup finds the first, so the
 * second would be silently ignored. */
static sss_result only_keys(const ctx *c, const cJSON *obj, const char *jpath, const char *const *allowed)
{
    unsigned seen = 0;
    for (const cJSON *it = obj->child; it; it = it->next) {
        int ok = 0, idx = 0;
        for (const char *const *a = allowed; *a && !ok; a++, idx++) ok = !strcmp(*a, it->string);
        if (ok && (seen >> (idx - 1) & 1u)) {
            char p[512];
            join(p, sizeof p, jpath, it->string);
            return fail_at(c, p, "given twice (a key may appear once in an object)");
        }
        if (ok) seen |= 1u << (idx - 1);
        if (!ok) {
            char p[512];
            join(p, sizeof p, jpath, it->string);
            char list[300] = "";
            size_t k = 0;
            for (const char *const *a = allowed; *a; a++)
                k += (size_t)snprintf(list + k, k < sizeof list ? sizeof list - k : 0, "%s%s", a == allowed ? "" : ", ", *a);
            return fail_at(c, p, "unknown key (expected one of: %s)", list);
        }
    }
    return SSS_OK;
}

static sss_result get_number(const ctx *c, const cJSON *obj, const char *jpath, const char *key, int required,
                             double lo, double hi, double *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    char p[512];
    join(p, sizeof p, jpath, key);
    if (!v) return required ? fail_at(c, p, "missing (expected a number)") : SSS_OK;
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) return fail_at(c, p, "expected a number");
    if (!(v->valuedouble >= lo && v->valuedouble <= hi))
        return fail_at(c, p, "%g is out of range [%g, %g]", v->valuedouble, lo, hi);
    *out = v->valuedouble;
    return SSS_OK;
}

static sss_result get_u32(const ctx *c, const cJSON *obj, const char *jpath, const char *key, uint32_t lo, uint32_t hi,
                          uint32_t *out)
{
    double d = 0;
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return SSS_OK;
    sss_result r = get_number(c, obj, jpath, key, 1, lo, hi, &d);
    if (r != SSS_OK) return r;
    if (d != floor(d)) {
        char p[512];
        join(p, sizeof p, jpath, key);
        return fail_at(c, p, "expected an integer");
    }
    *out = (uint32_t)d;
    return SSS_OK;
}

static sss_result get_bool(const ctx *c, const cJSON *obj, const char *jpath, const char *key, int *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return SSS_OK;
    if (!cJSON_IsBool(v)) {
        char p[512];
        join(p, sizeof p, jpath, key);
        return fail_at(c, p, "expected true or false");
    }
    *out = cJSON_IsTrue(v);
    return SSS_OK;
}

/* Array of exactly 3 finite numbers, each in [lo, hi]. */
static sss_result get_vec3(const ctx *c, const cJSON *obj, const char *jpath, const char *key, int required,
                           double lo, double hi, double out[3])
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    char p[512];
    join(p, sizeof p, jpath, key);
    if (!v) return required ? fail_at(c, p, "missing (expected 3 numbers)") : SSS_OK;
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3) return fail_at(c, p, "expected 3 numbers");
    double t[3];
    for (int i = 0; i < 3; i++) {
        const cJSON *e = cJSON_GetArrayItem(v, i);
        char pi[520];
        join_index(pi, sizeof pi, p, i);
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble)) return fail_at(c, p, "expected 3 numbers");
        if (!(e->valuedouble >= lo && e->valuedouble <= hi))
            return fail_at(c, pi, "%g is out of range [%g, %g]", e->valuedouble, lo, hi);
        t[i] = e->valuedouble;
    }
    memcpy(out, t, sizeof t);
    return SSS_OK;
}

/* One of the strings of `names` (NULL-terminated): *out = its index + 1
 * (0 stays: the key is absent). */
static sss_result get_choice(const ctx *c, const cJSON *obj, const char *jpath, const char *key,
                             const char *const *names, uint32_t *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return SSS_OK;
    char p[512], list[200] = "";
    join(p, sizeof p, jpath, key);
    size_t k = 0;
    for (const char *const *n = names; *n; n++)
        k += (size_t)snprintf(list + k, k < sizeof list ? sizeof list - k : 0, "%s\"%s\"", n == names ? "" : " or ", *n);
    if (!cJSON_IsString(v)) return fail_at(c, p, "expected %s", list);
    for (uint32_t i = 0; names[i]; i++)
        if (!strcmp(v->valuestring, names[i])) {
            *out = i + 1;
            return SSS_OK;
        }
    return fail_at(c, p, "'%s' is not %s", v->valuestring, list);
}

/* A path relative to the scene file's directory (absolute ones as given). */
static sss_result get_path(const ctx *c, const cJSON *obj, const char *jpath, const char *key, char *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    char p[512];
    join(p, sizeof p, jpath, key);
    if (!v) return fail_at(c, p, "missing (expected a file name)");
    if (!cJSON_IsString(v) || !v->valuestring[0]) return fail_at(c, p, "expected a non-empty file name");
    const char *s = v->valuestring;
    int n = s[0] == '/' ? snprintf(out, SSS_SCENE_PATH_MAX, "%s", s)
                        : snprintf(out, SSS_SCENE_PATH_MAX, "%s%s", c->dir, s);
    if (n < 0 || n >= SSS_SCENE_PATH_MAX) return fail_at(c, p, "file name too long");
    return SSS_OK;
}

/* The scattering of a material object: "sigmap_s" (σ′s, as before), or
 * "sigma_s" with an optional "g" (σ′s = σs (1 − g), docs/physics.md §1);
 * "g" alone keeps σ′s (a preset's, or "sigmap_s") and only sets the phase.
 * `required`: one of the two coefficients must be given (no preset). */
static sss_result parse_scattering(const ctx *c, const cJSON *m, const char *jpath, int required, sss_material *out)
{
    const int has_s = cJSON_GetObjectItemCaseSensitive(m, "sigma_s") != NULL;
    char p[512];
    join(p, sizeof p, jpath, "sigma_s");
    if (has_s && cJSON_GetObjectItemCaseSensitive(m, "sigmap_s"))
        return fail_at(c, p, "give either sigma_s (with g) or sigmap_s, not both");
    sss_result r = get_number(c, m, jpath, "g", 0, -SSS_G_MAX, SSS_G_MAX, &out->g);
    if (r != SSS_OK) return r;
    if (!has_s) return get_vec3(c, m, jpath, "sigmap_s", required, 0.0, SSS_SIGMA_MAX, out->sigmap_s);
    double s[3];
    if ((r = get_vec3(c, m, jpath, "sigma_s", 1, 0.0, SSS_SIGMA_MAX, s)) != SSS_OK) return r;
    for (int k = 0; k < 3; k++) out->sigmap_s[k] = s[k] * (1.0 - out->g);
    return SSS_OK;
}

/* A layer's "depth_mm" given as an object (docs/layers.md §3): {"map":
 * FILE, "scale_mm": s} or {"procedural": "veins" | "blobs" | "bumps",
 * "seed": N, "scale_mm": S, "depth_mm": [min, max]}. *lo, *hi: the least
 * and the largest depth it can give (mm). The map is read by the bake. */
static sss_result parse_depth_spec(const ctx *c, const cJSON *d, const char *jpath, sss_depth_spec *s, double *lo,
                                   double *hi)
{
    sss_result r;
    memset(s, 0, sizeof *s);
    char p[600];
    if (cJSON_GetObjectItemCaseSensitive(d, "map")) {
        static const char *const keys[] = {"map", "scale_mm", NULL};
        if ((r = only_keys(c, d, jpath, keys)) != SSS_OK) return r;
        s->kind = SSS_DEPTH_MAP;
        if ((r = get_path(c, d, jpath, "map", s->map)) != SSS_OK) return r;
        if ((r = get_number(c, d, jpath, "scale_mm", 1, 1e-9, SSS_DEPTH_MAX_MM, &s->scale_mm)) != SSS_OK) return r;
        *lo = 0.0;
        *hi = s->scale_mm;
        return SSS_OK;
    }
    if (!cJSON_GetObjectItemCaseSensitive(d, "procedural"))
        return fail_at(c, jpath, "expected a number, {\"map\": FILE, \"scale_mm\": s} or {\"procedural\": ...}");
    static const char *const keys[] = {"procedural", "seed", "scale_mm", "depth_mm", NULL};
    if ((r = only_keys(c, d, jpath, keys)) != SSS_OK) return r;
    static const char *const kinds[] = {"veins", "blobs", "bumps", NULL};
    s->kind = SSS_DEPTH_PROCEDURAL;
    if ((r = get_choice(c, d, jpath, "procedural", kinds, &s->pattern)) != SSS_OK) return r;
    if ((r = get_u32(c, d, jpath, "seed", 0, UINT32_MAX, &s->seed)) != SSS_OK) return r;
    if ((r = get_number(c, d, jpath, "scale_mm", 1, 1e-6, 1e9, &s->scale_mm)) != SSS_OK) return r;
    const cJSON *rg = cJSON_GetObjectItemCaseSensitive(d, "depth_mm");
    join(p, sizeof p, jpath, "depth_mm");
    if (!cJSON_IsArray(rg) || cJSON_GetArraySize(rg) != 2) return fail_at(c, p, "expected [min, max] in mm");
    for (int k = 0; k < 2; k++) {
        const cJSON *e = cJSON_GetArrayItem(rg, k);
        char pk[620];
        join_index(pk, sizeof pk, p, k);
        if (!cJSON_IsNumber(e) || !(e->valuedouble >= 0.0 && e->valuedouble <= SSS_DEPTH_MAX_MM))
            return fail_at(c, pk, "expected a depth in [0, %g] mm", SSS_DEPTH_MAX_MM);
        s->range_mm[k] = e->valuedouble;
    }
    if (s->range_mm[1] < s->range_mm[0]) return fail_at(c, p, "max %g is below min %g", s->range_mm[1], s->range_mm[0]);
    *lo = s->range_mm[0];
    *hi = s->range_mm[1];
    return SSS_OK;
}

/* A material's "layers" (docs/layers.md §3): each {"name", "sigma_s",
 * "sigma_a", "g", "depth_mm"}; a numeric depth not above the least depth
 * of the layer before it (equal: a layer of no thickness). A depth map or
 * a procedural depth (parse_depth_spec) goes to depth[k] and the stack
 * holds the largest depth it can give; the bake evaluates the depths per
 * vertex and replaces these by each layer's deepest (sss/depthmap.h). */
static sss_result parse_layers(const ctx *c, const cJSON *a, const char *jpath, sss_layer_stack *out,
                               sss_depth_spec *depth)
{
    memset(out, 0, sizeof *out);
    memset(depth, 0, SSS_MAX_LAYERS * sizeof *depth);
    if (!a) return SSS_OK;
    char p[512];
    join(p, sizeof p, jpath, "layers");
    const int n = cJSON_IsArray(a) ? cJSON_GetArraySize(a) : -1;
    if (n < 1 || n > SSS_MAX_LAYERS)
        return fail_at(c, p, "expected an array of 1 to %d layers", SSS_MAX_LAYERS);
    static const char *const keys[] = {"name", "sigma_s", "sigma_a", "g", "depth_mm", NULL};
    double top = 0.0;
    for (int i = 0; i < n; i++) {
        const cJSON *l = cJSON_GetArrayItem(a, i);
        char pi[520], pd[540];
        join_index(pi, sizeof pi, p, i);
        if (!cJSON_IsObject(l)) return fail_at(c, pi, "expected an object {name, sigma_s, sigma_a, g, depth_mm}");
        sss_result r = only_keys(c, l, pi, keys);
        if (r != SSS_OK) return r;
        sss_layer *ly = &out->layer[i];
        double sa[3];
        if ((r = get_vec3(c, l, pi, "sigma_s", 1, 0.0, SSS_SIGMA_MAX, ly->sigma_s)) != SSS_OK) return r;
        if ((r = get_vec3(c, l, pi, "sigma_a", 1, 0.0, SSS_SIGMA_MAX, sa)) != SSS_OK) return r;
        if ((r = get_number(c, l, pi, "g", 0, -SSS_G_MAX, SSS_G_MAX, &ly->g)) != SSS_OK) return r;
        for (int k = 0; k < 3; k++) ly->sigma_t[k] = sa[k] + ly->sigma_s[k];
        const cJSON *d = cJSON_GetObjectItemCaseSensitive(l, "depth_mm");
        join(pd, sizeof pd, pi, "depth_mm");
        if (cJSON_IsObject(d)) {
            double lo = 0.0, hi = 0.0;
            if ((r = parse_depth_spec(c, d, pd, &depth[i], &lo, &hi)) != SSS_OK) return r;
            top = lo > top ? lo : top;
            ly->depth = hi;
        } else {
            if ((r = get_number(c, l, pi, "depth_mm", 1, 0.0, SSS_DEPTH_MAX_MM, &ly->depth)) != SSS_OK) return r;
            if (ly->depth < top) return fail_at(c, pd, "%g is above the layer before it (%g mm)", ly->depth, top);
            top = ly->depth;
        }
        const cJSON *nm = cJSON_GetObjectItemCaseSensitive(l, "name");
        if (nm && !cJSON_IsString(nm)) {
            join(pd, sizeof pd, pi, "name");
            return fail_at(c, pd, "expected a string");
        }
    }
    out->n = (uint32_t)n;
    out->phase = SSS_PHASE_HG;
    return SSS_OK;
}

static sss_result parse_field(const ctx *c, const cJSON *fj, const char *jpath, sss_scene_object *obj);

/* obj: the object whose material this is, which may then carry a field and
 * an inside material (docs/heterogeneous.md §1); NULL for the inside
 * material itself. */
static sss_result parse_material(const ctx *c, const cJSON *m, const char *jpath, sss_material *out,
                                 sss_scene_object *obj)
{
    sss_error e2 = {{0}};
    if (!m) return fail_at(c, jpath, "missing (expected a preset name or {sigma_a, sigmap_s, eta})");
    if (cJSON_IsString(m)) {
        if (sss_material_preset(m->valuestring, out, &e2) != SSS_OK)
            return fail_at(c, jpath, "unknown material preset '%s'", m->valuestring);
        return SSS_OK;
    }
    if (!cJSON_IsObject(m)) return fail_at(c, jpath, "expected a preset name or an object");
    static const char *const keys[] = {"preset", "sigma_a", "sigmap_s", "eta", "sigma_s", "g", "layers",
                                       "transport", "field", "inside", NULL};
    static const char *const inside_keys[] = {"preset", "sigma_a", "sigmap_s", "transport", NULL};
    sss_result r = only_keys(c, m, jpath, obj ? keys : inside_keys);
    if (r != SSS_OK) return r;
    memset(out, 0, sizeof *out);
    const cJSON *pr = cJSON_GetObjectItemCaseSensitive(m, "preset");
    if (pr) {
        char p[512];
        join(p, sizeof p, jpath, "preset");
        if (!cJSON_IsString(pr) || sss_material_preset(pr->valuestring, out, &e2) != SSS_OK)
            return fail_at(c, p, "unknown material preset");
    } else {
        snprintf(out->name, sizeof out->name, "custom");
        out->eta = 1.3;
    }
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(m, "transport");
    if (tr && cJSON_GetObjectItemCaseSensitive(m, "sigma_a")) {
        char p[512];
        join(p, sizeof p, jpath, "transport");
        return fail_at(c, p, "give sigma_a or transport, not both (the transport colour sets sigma_a)");
    }
    if ((r = get_vec3(c, m, jpath, "sigma_a", !pr && !tr, 0.0, SSS_SIGMA_MAX, out->sigma_a)) != SSS_OK) return r;
    if ((r = parse_scattering(c, m, jpath, !pr, out)) != SSS_OK) return r;
    if ((r = get_number(c, m, jpath, "eta", 0, SSS_ETA_MIN, SSS_ETA_MAX, &out->eta)) != SSS_OK) return r;
    if (tr) { /* Shopf 2007 §4.3.3: σa from the transport colour and distance, with this σ′s */
        char p[512];
        join(p, sizeof p, jpath, "transport");
        if (!cJSON_IsObject(tr)) return fail_at(c, p, "expected an object {colour, distance_mm}");
        static const char *const tk[] = {"colour", "distance_mm", NULL};
        if ((r = only_keys(c, tr, p, tk)) != SSS_OK) return r;
        double col[3], dist = 0.0;
        if ((r = get_vec3(c, tr, p, "colour", 1, 0.0, 1.0, col)) != SSS_OK) return r;
        if ((r = get_number(c, tr, p, "distance_mm", 1, 0.0, 1e9, &dist)) != SSS_OK) return r;
        if (sss_transport_sigma_a(col, dist, out->sigmap_s, out->sigma_a, &e2) != SSS_OK)
            return fail_at(c, p, "%s", e2.msg);
    }
    if (pr && (cJSON_GetObjectItemCaseSensitive(m, "sigma_a") || cJSON_GetObjectItemCaseSensitive(m, "sigmap_s") ||
               cJSON_GetObjectItemCaseSensitive(m, "sigma_s") || tr))
        snprintf(out->name, sizeof out->name, "custom");
    if (sss_material_validate(out, &e2) != SSS_OK) return fail_at(c, jpath, "%s", e2.msg);
    const cJSON *fj = obj ? cJSON_GetObjectItemCaseSensitive(m, "field") : NULL;
    const cJSON *in = obj ? cJSON_GetObjectItemCaseSensitive(m, "inside") : NULL;
    char p[512];
    if (!fj != !in) {
        join(p, sizeof p, jpath, fj ? "inside" : "field");
        return fail_at(c, p, "missing (a field blends the material with an inside material: give both)");
    }
    if (fj) {
        join(p, sizeof p, jpath, "inside");
        if ((r = parse_material(c, in, p, &obj->hetero.inside, NULL)) != SSS_OK) return r;
        obj->hetero.inside.eta = out->eta; /* one surface, one η */
        join(p, sizeof p, jpath, "field");
        if ((r = parse_field(c, fj, p, obj)) != SSS_OK) return r;
    }
    return SSS_OK;
}

/* "deform": {"type": "skin", "bones": [...], "blend_radius": r}
 * (docs/deformable.md §2, sss/skin.h). The chain's own rules (lengths,
 * parents, cycles) are sss_skin_check's, reported here at their path. */
static sss_result parse_skin(const ctx *c, const cJSON *d, const char *jpath, sss_skin *out)
{
    static const char *const keys[] = {"type", "bones", "blend_radius", NULL};
    static const char *const bkeys[] = {"head", "tail", "parent", "axis", "angle_deg", "period_s", NULL};
    sss_result r = only_keys(c, d, jpath, keys);
    if (r != SSS_OK) return r;
    char p[512];
    join(p, sizeof p, jpath, "bones");
    const cJSON *bs = cJSON_GetObjectItemCaseSensitive(d, "bones");
    if (!bs) return fail_at(c, p, "missing (expected an array of 1 to %d bones)", SSS_SKIN_MAX_BONES);
    const int nb = cJSON_IsArray(bs) ? cJSON_GetArraySize(bs) : 0;
    if (nb < 1 || nb > SSS_SKIN_MAX_BONES)
        return fail_at(c, p, "expected an array of 1 to %d bones {head, tail, parent, axis, angle_deg, period_s}",
                       SSS_SKIN_MAX_BONES);
    memset(out, 0, sizeof *out);
    out->nbones = nb;
    for (int i = 0; i < nb; i++) {
        const cJSON *b = cJSON_GetArrayItem(bs, i);
        sss_skin_bone *o = &out->bone[i];
        char pb[520], pk[600];
        join_index(pb, sizeof pb, p, i);
        if (!cJSON_IsObject(b))
            return fail_at(c, pb, "expected an object {head, tail, parent, axis, angle_deg, period_s}");
        if ((r = only_keys(c, b, pb, bkeys)) != SSS_OK) return r;
        if ((r = get_vec3(c, b, pb, "head", 1, -SSS_COORD_MAX, SSS_COORD_MAX, o->head)) != SSS_OK) return r;
        if ((r = get_vec3(c, b, pb, "tail", 1, -SSS_COORD_MAX, SSS_COORD_MAX, o->tail)) != SSS_OK) return r;
        if ((r = get_vec3(c, b, pb, "axis", 1, -1e12, 1e12, o->axis)) != SSS_OK) return r;
        join(pk, sizeof pk, pb, "axis");
        if (!(sss_normalize3(o->axis) > 1e-12)) return fail_at(c, pk, "must be a non-zero vector");
        if ((r = get_number(c, b, pb, "angle_deg", 1, -SSS_SKIN_MAX_DEG, SSS_SKIN_MAX_DEG, &o->angle_deg)) != SSS_OK)
            return r;
        o->period_s = SSS_DEFORM_PERIOD_DEFAULT;
        if ((r = get_number(c, b, pb, "period_s", 0, 1e-6, 1e9, &o->period_s)) != SSS_OK) return r;
        double parent = -1;
        if ((r = get_number(c, b, pb, "parent", 0, -1e6, 1e6, &parent)) != SSS_OK) return r;
        join(pk, sizeof pk, pb, "parent");
        if (parent != floor(parent)) return fail_at(c, pk, "expected an integer (a bone index, -1 for none)");
        o->parent = (int)parent;
    }
    join(p, sizeof p, jpath, "blend_radius");
    if ((r = get_number(c, d, jpath, "blend_radius", 0, 0, SSS_COORD_MAX, &out->blend_radius)) != SSS_OK) return r;
    if (cJSON_GetObjectItemCaseSensitive(d, "blend_radius") && !(out->blend_radius > 0))
        return fail_at(c, p, "must be > 0 (mesh units)");
    int bone;
    const char *key;
    sss_error why = {{0}};
    if (sss_skin_check(out, &bone, &key, &why) != SSS_OK) {
        if (bone < 0) join(p, sizeof p, jpath, key);
        else {
            char pbs[520], pb[540];
            join(pbs, sizeof pbs, jpath, "bones");
            join_index(pb, sizeof pb, pbs, bone);
            join(p, sizeof p, pb, key);
        }
        return fail_at(c, p, "%s", why.msg);
    }
    return SSS_OK;
}

/* "deform" of an object (docs/scenes.md, sss/deform.h). */
static sss_result parse_deform(const ctx *c, const cJSON *d, const char *jpath, sss_deform *out)
{
    if (!cJSON_IsObject(d)) return fail_at(c, jpath, "expected an object {type, axis, angle_deg, period_s}");
    static const char *const keys[] = {"type", "axis", "angle_deg", "period_s", NULL};
    static const char *const types[] = {"bend", "twist", "wave", "skin", NULL};
    uint32_t type = 0;
    sss_result r = get_choice(c, d, jpath, "type", types, &type);
    if (r != SSS_OK) return r;
    char p[512];
    join(p, sizeof p, jpath, "type");
    if (!type) return fail_at(c, p, "missing (expected \"bend\", \"twist\", \"wave\" or \"skin\")");
    memset(out, 0, sizeof *out);
    if (type == SSS_DEFORM_SKIN) { /* a bone chain: its own keys */
        out->kind = SSS_DEFORM_SKIN;
        return parse_skin(c, d, jpath, &out->skin);
    }
    if ((r = only_keys(c, d, jpath, keys)) != SSS_OK) return r;
    out->kind = (sss_deform_kind)type; /* SSS_DEFORM_* in the order of `types` */
    out->axis[2] = 1.0;
    out->period_s = SSS_DEFORM_PERIOD_DEFAULT;
    if ((r = get_vec3(c, d, jpath, "axis", 0, -1e12, 1e12, out->axis)) != SSS_OK) return r;
    join(p, sizeof p, jpath, "axis");
    if (!(sss_normalize3(out->axis) > 1e-12)) return fail_at(c, p, "must be a non-zero vector");
    const double lim = out->kind == SSS_DEFORM_BEND    ? SSS_DEFORM_BEND_MAX_DEG
                       : out->kind == SSS_DEFORM_TWIST ? SSS_DEFORM_TWIST_MAX_DEG
                                                       : SSS_DEFORM_WAVE_MAX_DEG;
    if ((r = get_number(c, d, jpath, "angle_deg", 1, -lim, lim, &out->angle_deg)) != SSS_OK) return r;
    if ((r = get_number(c, d, jpath, "period_s", 0, 1e-6, 1e9, &out->period_s)) != SSS_OK) return r;
    return SSS_OK;
}

/* "field" (docs/heterogeneous.md §1): {"constant": c}, {"procedural":
 * KIND, ...} or {"vdb": FILE, "grid": NAME}, each with an optional
 * "surface": true (a surface texture, §4.4). */
static sss_result parse_field(const ctx *c, const cJSON *fj, const char *jpath, sss_scene_object *obj)
{
    sss_field *f = &obj->hetero.field;
    if (!cJSON_IsObject(fj)) return fail_at(c, jpath, "expected an object {constant}, {procedural, ...} or {vdb, grid}");
    /* "surface" is a key of every kind: read once (unknown keys are still
     * refused per kind below) */
    sss_result r = get_bool(c, fj, jpath, "surface", &obj->hetero.surface);
    if (r != SSS_OK) return r;
    /* "strength" too: the run-time path's scale of f (docs/heterogeneous.md §9.6) */
    if ((r = get_number(c, fj, jpath, "strength", 0, 1.0 / 64, 64.0, &obj->field_strength)) != SSS_OK) return r;
    char p[512];
    if (cJSON_GetObjectItemCaseSensitive(fj, "constant")) {
        static const char *const k[] = {"constant", "surface", "strength", NULL};
        if ((r = only_keys(c, fj, jpath, k)) != SSS_OK) return r;
        f->kind = SSS_FIELD_CONSTANT;
        return get_number(c, fj, jpath, "constant", 1, 0.0, 1.0, &f->value);
    }
    if (cJSON_GetObjectItemCaseSensitive(fj, "vdb")) {
        static const char *const k[] = {"vdb", "grid", "surface", "strength", NULL};
        if ((r = only_keys(c, fj, jpath, k)) != SSS_OK) return r;
        if ((r = get_path(c, fj, jpath, "vdb", obj->field_path)) != SSS_OK) return r;
        const cJSON *g = cJSON_GetObjectItemCaseSensitive(fj, "grid");
        join(p, sizeof p, jpath, "grid");
        if (!g) return fail_at(c, p, "missing (expected the name of a float grid)");
        if (!cJSON_IsString(g) || !g->valuestring[0] || strlen(g->valuestring) >= SSS_SCENE_NAME_MAX)
            return fail_at(c, p, "expected a grid name of 1 to %d characters", SSS_SCENE_NAME_MAX - 1);
        snprintf(obj->field_grid, sizeof obj->field_grid, "%s", g->valuestring);
        f->kind = SSS_FIELD_GRID; /* the samples are read by the bake (precompute/src/input/vdb_read.cpp) */
        return SSS_OK;
    }
    static const char *const kinds[] = {"veins", "inclusions", "box", "sphere", "layers", NULL};
    uint32_t kind = 0;
    join(p, sizeof p, jpath, "procedural");
    if (!cJSON_GetObjectItemCaseSensitive(fj, "procedural"))
        return fail_at(c, jpath, "expected one of the keys constant, procedural or vdb");
    if ((r = get_choice(c, fj, jpath, "procedural", kinds, &kind)) != SSS_OK) return r;
    static const uint32_t kind_of[] = {0, SSS_FIELD_VEINS, SSS_FIELD_INCLUSIONS, SSS_FIELD_BOX, SSS_FIELD_SPHERE,
                                       SSS_FIELD_LAYERS};
    f->kind = kind_of[kind];
    static const char *const kv[] = {"procedural", "seed", "scale_mm", "surface", "strength", NULL};
    static const char *const ki[] = {"procedural", "seed", "scale_mm", "radius_mm", "edge_mm", "surface", "strength",
                                     NULL};
    static const char *const kb[] = {"procedural", "centre_mm", "half_mm", "edge_mm", "surface", "strength", NULL};
    static const char *const ks[] = {"procedural", "centre_mm", "radius_mm", "edge_mm", "surface", "strength", NULL};
    static const char *const kl[] = {"procedural", "normal", "thickness_mm", "period_mm", "offset_mm", "edge_mm",
                                     "surface", "strength", NULL};
    static const char *const *const keys[] = {NULL, kv, ki, kb, ks, kl};
    if ((r = only_keys(c, fj, jpath, keys[kind])) != SSS_OK) return r;
    uint32_t seed = 0;
    if ((r = get_u32(c, fj, jpath, "seed", 0, UINT32_MAX, &seed)) != SSS_OK) return r;
    f->seed = seed;
    if ((r = get_number(c, fj, jpath, "edge_mm", 0, 0.0, 1e9, &f->edge_mm)) != SSS_OK) return r;
    switch (f->kind) {
    case SSS_FIELD_VEINS:
    case SSS_FIELD_INCLUSIONS:
        if ((r = get_number(c, fj, jpath, "scale_mm", 1, 1e-9, 1e9, &f->scale_mm)) != SSS_OK) return r;
        f->thickness_mm = 0.3 * f->scale_mm;
        if ((r = get_number(c, fj, jpath, "radius_mm", 0, 1e-9, 1e9, &f->thickness_mm)) != SSS_OK) return r;
        break;
    case SSS_FIELD_BOX:
        if ((r = get_vec3(c, fj, jpath, "centre_mm", 1, -1e9, 1e9, f->centre_mm)) != SSS_OK) return r;
        if ((r = get_vec3(c, fj, jpath, "half_mm", 1, 1e-9, 1e9, f->half_mm)) != SSS_OK) return r;
        break;
    case SSS_FIELD_SPHERE:
        if ((r = get_vec3(c, fj, jpath, "centre_mm", 1, -1e9, 1e9, f->centre_mm)) != SSS_OK) return r;
        if ((r = get_number(c, fj, jpath, "radius_mm", 1, 1e-9, 1e9, &f->half_mm[0])) != SSS_OK) return r;
        break;
    case SSS_FIELD_LAYERS: {
        if ((r = get_vec3(c, fj, jpath, "normal", 1, -1e9, 1e9, f->normal)) != SSS_OK) return r;
        const double n = sqrt(f->normal[0] * f->normal[0] + f->normal[1] * f->normal[1] + f->normal[2] * f->normal[2]);
        join(p, sizeof p, jpath, "normal");
        if (!(n > 1e-12)) return fail_at(c, p, "must be a non-zero vector");
        for (int a = 0; a < 3; a++) f->normal[a] /= n;
        if ((r = get_number(c, fj, jpath, "thickness_mm", 1, 1e-9, 1e9, &f->thickness_mm)) != SSS_OK) return r;
        if ((r = get_number(c, fj, jpath, "period_mm", 0, 0.0, 1e9, &f->scale_mm)) != SSS_OK) return r;
        if ((r = get_number(c, fj, jpath, "offset_mm", 0, -1e9, 1e9, &f->offset_mm)) != SSS_OK) return r;
        break;
    }
    default: break;
    }
    sss_error e2 = {{0}};
    if (sss_field_check(f, &e2) != SSS_OK) return fail_at(c, jpath, "%s", e2.msg);
    return SSS_OK;
}

/* R = Rz · Ry · Rx (x first) of the transform's angles in degrees. */
static void rotation(const double deg[3], double R[9])
{
    double a[3];
    for (int k = 0; k < 3; k++) a[k] = deg[k] * (SSS_PI / 180.0);
    const double cx = cos(a[0]), sx = sin(a[0]), cy = cos(a[1]), sy = sin(a[1]), cz = cos(a[2]), sz = sin(a[2]);
    const double m[9] = {cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx,
                         sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx,
                         -sy,     cy * sx,                cy * cx};
    memcpy(R, m, sizeof m);
}

static sss_result parse_object(const ctx *c, const cJSON *o, const char *jpath, int index, sss_scene_object *out)
{
    if (!cJSON_IsObject(o)) return fail_at(c, jpath, "expected an object");
    static const char *const keys[] = {"name", "mesh", "material", "mm_per_unit", "transform", "moving", "deform",
                                       "single_scattering", "editable", NULL};
    sss_result r = only_keys(c, o, jpath, keys);
    if (r != SSS_OK) return r;
    memset(out, 0, sizeof *out);
    out->scale = 1.0;
    out->mm_per_unit = 1.0;
    out->field_strength = 1.0;
    snprintf(out->name, sizeof out->name, "object%d", index);
    const cJSON *nm = cJSON_GetObjectItemCaseSensitive(o, "name");
    if (nm) {
        char p[512];
        join(p, sizeof p, jpath, "name");
        if (!cJSON_IsString(nm) || !nm->valuestring[0] || strlen(nm->valuestring) >= SSS_SCENE_NAME_MAX)
            return fail_at(c, p, "expected a non-empty string of at most %d characters", SSS_SCENE_NAME_MAX - 1);
        /* the name becomes part of an output file name (docs/scenes.md) */
        for (const char *s = nm->valuestring; *s; s++)
            if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') || *s == '-' ||
                  *s == '_' || *s == '.'))
                return fail_at(c, p, "'%s': only letters, digits, '-', '_' and '.' are allowed", nm->valuestring);
        /* a leading '.' makes a hidden file ("." gives DIR/..sss) */
        if (nm->valuestring[0] == '.')
            return fail_at(c, p, "'%s': a name may not start with '.' (it names the object's file)", nm->valuestring);
        snprintf(out->name, sizeof out->name, "%s", nm->valuestring);
    }
    if ((r = get_path(c, o, jpath, "mesh", out->mesh)) != SSS_OK) return r;
    char p[512];
    join(p, sizeof p, jpath, "material");
    if ((r = parse_material(c, cJSON_GetObjectItemCaseSensitive(o, "material"), p, &out->material, out)) != SSS_OK)
        return r;
    const cJSON *mo = cJSON_GetObjectItemCaseSensitive(o, "material");
    if (cJSON_IsObject(mo) &&
        (r = parse_layers(c, cJSON_GetObjectItemCaseSensitive(mo, "layers"), p, &out->layers, out->layer_depth)) != SSS_OK)
        return r;
    if ((r = get_number(c, o, jpath, "mm_per_unit", 0, 1e-12, 1e12, &out->mm_per_unit)) != SSS_OK) return r;
    if (!(out->mm_per_unit > 0)) {
        join(p, sizeof p, jpath, "mm_per_unit");
        return fail_at(c, p, "must be > 0");
    }
    if ((r = get_bool(c, o, jpath, "moving", &out->moving)) != SSS_OK) return r;
    /* the material is edited live: seed 000's run-time path (docs/heterogeneous.md §9) */
    if ((r = get_bool(c, o, jpath, "editable", &out->editable)) != SSS_OK) return r;
    const cJSON *df = cJSON_GetObjectItemCaseSensitive(o, "deform");
    if (df) {
        join(p, sizeof p, jpath, "deform");
        if ((r = parse_deform(c, df, p, &out->deform)) != SSS_OK) return r;
    }
    if (cJSON_GetObjectItemCaseSensitive(o, "single_scattering")) { /* forces the planner's rule (docs/layers.md §4) */
        int on = 0;
        if ((r = get_bool(c, o, jpath, "single_scattering", &on)) != SSS_OK) return r;
        out->single_scattering = on ? 1 : -1;
    }
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(o, "transform");
    if (t) {
        join(p, sizeof p, jpath, "transform");
        if (!cJSON_IsObject(t)) return fail_at(c, p, "expected an object {translate, rotate_deg, scale}");
        static const char *const tk[] = {"translate", "rotate_deg", "scale", NULL};
        if ((r = only_keys(c, t, p, tk)) != SSS_OK) return r;
        if ((r = get_vec3(c, t, p, "translate", 0, -1e12, 1e12, out->translate)) != SSS_OK) return r;
        if ((r = get_vec3(c, t, p, "rotate_deg", 0, -1e6, 1e6, out->rotate_deg)) != SSS_OK) return r;
        if ((r = get_number(c, t, p, "scale", 0, 1e-12, 1e12, &out->scale)) != SSS_OK) return r;
        /* the object is baked at mm_per_unit / scale mm per world unit: the
         * bake's own range (sss/mesh.h) */
        const double mpw = out->mm_per_unit / out->scale;
        if (!(mpw >= SSS_MM_PER_UNIT_MIN && mpw <= SSS_MM_PER_UNIT_MAX)) {
            char ps[540];
            join(ps, sizeof ps, p, "scale");
            return fail_at(c, ps, "mm_per_unit / scale = %g mm per world unit is outside [%g, %g]", mpw,
                           SSS_MM_PER_UNIT_MIN, SSS_MM_PER_UNIT_MAX);
        }
    }
    /* The field lives in the rest frame (docs/heterogeneous.md §3): world
     * x_w = s R x + t, so rest-frame mm = mm_per_unit · x = (mm_per_unit /
     * s) Rᵀ (x_w − t). */
    /* (procedural layer depths live there too, docs/layers.md §3) */
    if (out->hetero.field.kind != SSS_FIELD_NONE || out->layers.n) {
        double R[9];
        rotation(out->rotate_deg, R);
        const double k = out->mm_per_unit / out->scale;
        for (int a = 0; a < 3; a++) {
            double t = 0.0;
            for (int b = 0; b < 3; b++) {
                out->hetero.xf[4 * a + b] = k * R[3 * b + a];
                t -= R[3 * b + a] * out->translate[b];
            }
            out->hetero.xf[4 * a + 3] = k * t;
        }
    }
    return SSS_OK;
}

static sss_result parse_light(const ctx *c, const cJSON *l, const char *jpath, sss_scene_light *out)
{
    if (!cJSON_IsObject(l)) return fail_at(c, jpath, "expected an object");
    memset(out, 0, sizeof *out);
    out->intensity = 1.0;
    out->colour[0] = out->colour[1] = out->colour[2] = 1.0;
    const cJSON *ty = cJSON_GetObjectItemCaseSensitive(l, "type");
    char p[512];
    join(p, sizeof p, jpath, "type");
    if (!ty) return fail_at(c, p, "missing (expected \"directional\", \"point\" or \"environment\")");
    if (!cJSON_IsString(ty)) return fail_at(c, p, "expected \"directional\", \"point\" or \"environment\"");
    sss_result r;
    if (!strcmp(ty->valuestring, "directional")) {
        static const char *const k[] = {"type", "direction", "intensity", "colour", "moving", NULL};
        if ((r = only_keys(c, l, jpath, k)) != SSS_OK) return r;
        out->kind = SSS_LIGHT_DIRECTIONAL;
        if ((r = get_vec3(c, l, jpath, "direction", 1, -1e12, 1e12, out->direction)) != SSS_OK) return r;
        double n = sqrt(out->direction[0] * out->direction[0] + out->direction[1] * out->direction[1] +
                        out->direction[2] * out->direction[2]);
        join(p, sizeof p, jpath, "direction");
        if (!(n > 1e-12) || !isfinite(n)) return fail_at(c, p, "must be a non-zero vector");
        for (int k2 = 0; k2 < 3; k2++) out->direction[k2] /= n;
    } else if (!strcmp(ty->valuestring, "point")) {
        static const char *const k[] = {"type", "position", "intensity", "colour", "moving", NULL};
        if ((r = only_keys(c, l, jpath, k)) != SSS_OK) return r;
        out->kind = SSS_LIGHT_POINT;
        if ((r = get_vec3(c, l, jpath, "position", 1, -1e12, 1e12, out->position)) != SSS_OK) return r;
    } else if (!strcmp(ty->valuestring, "environment")) {
        static const char *const k[] = {"type", "probe", "intensity", "colour", "moving", "rotation_deg", NULL};
        if ((r = only_keys(c, l, jpath, k)) != SSS_OK) return r;
        out->kind = SSS_LIGHT_ENVIRONMENT;
        if ((r = get_path(c, l, jpath, "probe", out->probe)) != SSS_OK) return r;
        if ((r = get_number(c, l, jpath, "rotation_deg", 0, -1e6, 1e6, &out->rotation_deg)) != SSS_OK) return r;
    } else {
        return fail_at(c, p, "'%s' is not \"directional\", \"point\" or \"environment\"", ty->valuestring);
    }
    if ((r = get_number(c, l, jpath, "intensity", 0, 0.0, 1e12, &out->intensity)) != SSS_OK) return r;
    if ((r = get_vec3(c, l, jpath, "colour", 0, 0.0, 1e12, out->colour)) != SSS_OK) return r;
    if ((r = get_bool(c, l, jpath, "moving", &out->moving)) != SSS_OK) return r;
    return SSS_OK;
}

static sss_result parse_camera(const ctx *c, const cJSON *o, sss_scene_camera *out)
{
    const char *jp = "/camera";
    if (!cJSON_IsObject(o)) return fail_at(c, jp, "expected an object");
    static const char *const k[] = {"position", "target", "up", "fov_deg", NULL};
    sss_result r = only_keys(c, o, jp, k);
    if (r != SSS_OK) return r;
    out->present = 1;
    out->up[1] = 1.0;
    out->fov_deg = 40.0;
    if ((r = get_vec3(c, o, jp, "position", 1, -1e12, 1e12, out->position)) != SSS_OK) return r;
    if ((r = get_vec3(c, o, jp, "target", 0, -1e12, 1e12, out->target)) != SSS_OK) return r;
    if ((r = get_vec3(c, o, jp, "up", 0, -1e12, 1e12, out->up)) != SSS_OK) return r;
    if ((r = get_number(c, o, jp, "fov_deg", 0, 1.0, 179.0, &out->fov_deg)) != SSS_OK) return r;
    double d[3] = {out->target[0] - out->position[0], out->target[1] - out->position[1], out->target[2] - out->position[2]};
    if (!(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 0)) return fail_at(c, "/camera/target", "equals the position");
    return SSS_OK;
}

static sss_result parse_bake(const ctx *c, const cJSON *o, sss_scene_bake *out)
{
    const char *jp = "/bake";
    if (!cJSON_IsObject(o)) return fail_at(c, jp, "expected an object");
    static const char *const k[] = {"dirs", "eps", "sh_order", "shells", "near_factor", "weights", "compress",
                                    "near_terms", "gather", NULL};
    sss_result r = only_keys(c, o, jp, k);
    if (r != SSS_OK) return r;
    if ((r = get_u32(c, o, jp, "dirs", 4, 100000, &out->dirs)) != SSS_OK) return r;
    if ((r = get_number(c, o, jp, "eps", 0, 1e-12, 0.5, &out->eps)) != SSS_OK) return r;
    if ((r = get_u32(c, o, jp, "sh_order", 1, 8, &out->sh_order)) != SSS_OK) return r;
    if ((r = get_u32(c, o, jp, "shells", 2, 64, &out->shells)) != SSS_OK) return r;
    if ((r = get_number(c, o, jp, "near_factor", 0, 0.0, 1e6, &out->near_factor)) != SSS_OK) return r;
    /* in the order of the SSS_SCENE_* values (sss/scene.h) */
    static const char *const weights[] = {"hat", "point", NULL}, *const compress[] = {"compact", "none", NULL},
                             *const near[] = {"runtime", "baked", NULL}, *const gather[] = {"direct", "tree", NULL};
    if ((r = get_choice(c, o, jp, "weights", weights, &out->weights)) != SSS_OK) return r;
    if ((r = get_choice(c, o, jp, "compress", compress, &out->compress)) != SSS_OK) return r;
    if ((r = get_choice(c, o, jp, "near_terms", near, &out->near_terms)) != SSS_OK) return r;
    if ((r = get_choice(c, o, jp, "gather", gather, &out->gather)) != SSS_OK) return r;
    return SSS_OK;
}

sss_result sss_scene_parse(const char *text, const char *path, sss_scene *out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    ctx c = {path ? path : "scene", "", err};
    snprintf(out->path, sizeof out->path, "%s", c.file);
    const char *slash = strrchr(c.file, '/');
    if (slash) {
        size_t n = (size_t)(slash - c.file) + 1;
        if (n >= sizeof c.dir) return sss_fail(err, SSS_ERR_ARG, "%s: path too long", c.file);
        memcpy(c.dir, c.file, n);
        c.dir[n] = 0;
    }
    /* cJSON decodes the escape \u0000 to a NUL that ends the string there:
     * "a\u0000b" would be read as "a" with no word said. No name, key or
     * path can hold a NUL: refused, with its line. */
    {
        int line = 1, in_str = 0;
        for (const char *q = text; *q; q++) {
            if (*q == '\n') line++;
            if (!in_str) {
                in_str = *q == '"';
                continue;
            }
            if (*q == '"') in_str = 0;
            else if (*q == '\\' && q[1]) {
                if (q[1] == 'u' && q[2] == '0' && q[3] == '0' && q[4] == '0' && q[5] == '0')
                    return sss_fail(err, SSS_ERR_ARG, "%s: line %d: a string holds \\u0000 (no name, key or path may "
                                    "hold a NUL)", c.file, line);
                q++; /* the escaped character, '"' and '\\' included */
            }
        }
    }
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
    if (!root) {
        /* line of the syntax error, counted from the parser's stop point */
        int line = 1;
        const char *stop = end ? end : cJSON_GetErrorPtr();
        for (const char *p = text; stop && p < stop && *p; p++) line += *p == '\n';
        return sss_fail(err, SSS_ERR_ARG, "%s: line %d: not valid JSON", c.file, line);
    }
    sss_result r = SSS_OK;
    if (!cJSON_IsObject(root)) { r = fail_at(&c, "", "expected a JSON object"); goto done; }
    static const char *const keys[] = {"objects", "lights", "camera", "bake", "comment", NULL};
    if ((r = only_keys(&c, root, "", keys)) != SSS_OK) goto done;
    const cJSON *objs = cJSON_GetObjectItemCaseSensitive(root, "objects");
    if (!objs) { r = fail_at(&c, "/objects", "missing (expected an array of objects)"); goto done; }
    if (!cJSON_IsArray(objs) || cJSON_GetArraySize(objs) < 1) {
        r = fail_at(&c, "/objects", "expected a non-empty array");
        goto done;
    }
    int no = cJSON_GetArraySize(objs);
    if (no > SSS_SCENE_MAX_OBJECTS) {
        r = fail_at(&c, "/objects", "%d objects, at most %d", no, SSS_SCENE_MAX_OBJECTS);
        goto done;
    }
    out->objects = calloc((size_t)no, sizeof *out->objects);
    if (!out->objects) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", c.file); goto done; }
    out->nobjects = (uint32_t)no;
    for (int i = 0; i < no; i++) {
        char p[64];
        join_index(p, sizeof p, "/objects", i);
        if ((r = parse_object(&c, cJSON_GetArrayItem(objs, i), p, i, &out->objects[i])) != SSS_OK) goto done;
        for (int j = 0; j < i; j++)
            if (!strcmp(out->objects[j].name, out->objects[i].name)) {
                char pn[80];
                join(pn, sizeof pn, p, "name");
                r = fail_at(&c, pn, "'%s' is also the name of /objects/%d (names must differ: one .sss per object)",
                            out->objects[i].name, j);
                goto done;
            }
    }
    const cJSON *ls = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (ls) {
        if (!cJSON_IsArray(ls)) { r = fail_at(&c, "/lights", "expected an array"); goto done; }
        int nl = cJSON_GetArraySize(ls);
        if (nl > SSS_SCENE_MAX_LIGHTS) {
            r = fail_at(&c, "/lights", "%d lights, at most %d", nl, SSS_SCENE_MAX_LIGHTS);
            goto done;
        }
        out->lights = calloc((size_t)nl + 1, sizeof *out->lights);
        if (!out->lights) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", c.file); goto done; }
        out->nlights = (uint32_t)nl;
        for (int i = 0; i < nl; i++) {
            char p[64];
            join_index(p, sizeof p, "/lights", i);
            if ((r = parse_light(&c, cJSON_GetArrayItem(ls, i), p, &out->lights[i])) != SSS_OK) goto done;
        }
    }
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    if (cam && (r = parse_camera(&c, cam, &out->camera)) != SSS_OK) goto done;
    const cJSON *bk = cJSON_GetObjectItemCaseSensitive(root, "bake");
    if (bk && (r = parse_bake(&c, bk, &out->bake)) != SSS_OK) goto done;
done:
    cJSON_Delete(root);
    if (r != SSS_OK) sss_scene_free(out);
    return r;
}

sss_result sss_scene_load(const char *path, sss_scene *out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    char *buf;
    size_t len;
    /* a regular file only, opened without blocking (sss/fileio.h) */
    sss_result r = sss_input_read_all(path, (uint64_t)64 << 20, &buf, &len, err);
    if (r != SSS_OK) return r;
    if (strlen(buf) != len) { free(buf); return sss_fail(err, SSS_ERR_ARG, "%s: contains a NUL byte (not JSON text)", path); }
    r = sss_scene_parse(buf, path, out, err);
    free(buf);
    return r;
}

void sss_scene_free(sss_scene *s)
{
    if (!s) return;
    for (uint32_t i = 0; s->objects && i < s->nobjects; i++) sss_field_free(&s->objects[i].hetero.field);
    free(s->objects);
    free(s->lights);
    memset(s, 0, sizeof *s);
}

double sss_scene_object_mm_per_world_unit(const sss_scene_object *o) { return o->mm_per_unit / o->scale; }

sss_result sss_scene_object_world(const sss_scene_object *o, const sss_mesh *mesh, sss_mesh *out, sss_error *err)
{
    /* the texture coordinates stay: a layer's depth map is read at them (docs/layers.md §3) */
    const sss_mesh geom = {.nv = mesh->nv, .nf = mesh->nf, .pos = mesh->pos, .tri = mesh->tri, .uv = mesh->uv};
    sss_result r = sss_mesh_copy(&geom, out, err);
    if (r != SSS_OK) return r;
    /* R = Rz · Ry · Rx (x first), in double, rounded once per coordinate */
    double R[9];
    rotation(o->rotate_deg, R);
    const int identity = o->rotate_deg[0] == 0 && o->rotate_deg[1] == 0 && o->rotate_deg[2] == 0 && o->scale == 1.0 &&
                         o->translate[0] == 0 && o->translate[1] == 0 && o->translate[2] == 0;
    if (!identity)
        for (uint32_t v = 0; v < out->nv; v++) {
            const float *p = &mesh->pos[3 * (size_t)v];
            for (int k = 0; k < 3; k++)
                out->pos[3 * (size_t)v + k] =
                    (float)(o->scale * (R[3 * k] * p[0] + R[3 * k + 1] * p[1] + R[3 * k + 2] * p[2]) + o->translate[k]);
        }
    r = sss_mesh_compute_normals_areas(out, o->name, err);
    /* placed, in the range every stage computes in (sss/mesh.h) */
    if (r == SSS_OK) r = sss_mesh_check_range(out, sss_scene_object_mm_per_world_unit(o), o->name, err);
    if (r != SSS_OK) sss_mesh_free(out);
    return r;
}

sss_result sss_scene_object_posed(const sss_scene_object *o, const sss_mesh *rest, double t, sss_mesh *out,
                                  sss_error *err)
{
    sss_mesh posed;
    memset(out, 0, sizeof *out);
    sss_result r = sss_deform_pose(&o->deform, t, rest, o->name, &posed, err);
    if (r != SSS_OK) return r;
    r = sss_scene_object_world(o, &posed, out, err);
    sss_mesh_free(&posed);
    return r;
}

const char *sss_light_kind_name(sss_light_kind k)
{
    switch (k) {
    case SSS_LIGHT_DIRECTIONAL: return "directional";
    case SSS_LIGHT_POINT: return "point";
    case SSS_LIGHT_ENVIRONMENT: return "environment";
    }
    return "?";
}
