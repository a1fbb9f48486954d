/* skin.c: linear blend skinning and the scene's bone chain (sss/skin.h,
 * docs/deformable.md §2 and §5). Everything in double, vertex by vertex in
 * a fixed order: the result does not depend on the thread count. */
#include "sss/skin.h"

#include <math.h>
#include <string.h>

#include "sss/vec3.h"

void sss_mat4_mul(const double *a, const double *b, double *c)
{
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += a[4 * k + row] * b[4 * col + k];
            c[4 * col + row] = s;
        }
}

void sss_skin_blend(const double *J, const uint32_t *joint, const double *w, int n, const double p[3], double q[3])
{
    q[0] = q[1] = q[2] = 0;
    for (int i = 0; i < n; i++) {
        if (w[i] == 0) continue;
        const double *M = &J[16 * (size_t)joint[i]];
        for (int a = 0; a < 3; a++) q[a] += w[i] * (M[a] * p[0] + M[4 + a] * p[1] + M[8 + a] * p[2] + M[12 + a]);
    }
}

static int finite3(const double v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

static double bone_length(const sss_skin_bone *b)
{
    double d[3];
    sss_sub3(d, b->tail, b->head);
    return sqrt(sss_dot3(d, d));
}

sss_result sss_skin_check(const sss_skin *s, int *bone, const char **key, sss_error *err)
{
    *bone = -1;
    *key = "bones";
    if (s->nbones < 1 || s->nbones > SSS_SKIN_MAX_BONES)
        return sss_fail(err, SSS_ERR_ARG, "%d bones, expected 1 to %d", s->nbones, SSS_SKIN_MAX_BONES);
    for (int b = 0; b < s->nbones; b++) {
        const sss_skin_bone *o = &s->bone[b];
        *bone = b;
        if (!finite3(o->head) || !(fabs(o->head[0]) <= SSS_COORD_MAX && fabs(o->head[1]) <= SSS_COORD_MAX &&
                                    fabs(o->head[2]) <= SSS_COORD_MAX))
            return *key = "head", sss_fail(err, SSS_ERR_ARG, "not a point of finite coordinates");
        if (!finite3(o->tail) || !(fabs(o->tail[0]) <= SSS_COORD_MAX && fabs(o->tail[1]) <= SSS_COORD_MAX &&
                                    fabs(o->tail[2]) <= SSS_COORD_MAX))
            return *key = "tail", sss_fail(err, SSS_ERR_ARG, "not a point of finite coordinates");
        /* a segment of length 0 has no direction: its distances would make
         * a ball, not a bone */
        if (!(bone_length(o) > 0))
            return *key = "tail", sss_fail(err, SSS_ERR_ARG, "equals the head (a bone needs a length)");
        const double n = sqrt(sss_dot3(o->axis, o->axis));
        if (!(fabs(n - 1.0) <= 1e-9))
            return *key = "axis", sss_fail(err, SSS_ERR_ARG, "(%g, %g, %g) is not a unit vector", o->axis[0], o->axis[1],
                                           o->axis[2]);
        if (!(fabs(o->angle_deg) <= SSS_SKIN_MAX_DEG))
            return *key = "angle_deg", sss_fail(err, SSS_ERR_ARG, "%g is beyond +-%g", o->angle_deg, SSS_SKIN_MAX_DEG);
        if (!(o->period_s > 0) || !isfinite(o->period_s))
            return *key = "period_s", sss_fail(err, SSS_ERR_ARG, "%g must be > 0", o->period_s);
        if (o->parent < -1 || o->parent >= s->nbones)
            return *key = "parent", sss_fail(err, SSS_ERR_ARG, "%d is not a bone index in [0, %d)", o->parent,
                                             s->nbones);
    }
    /* the parents form trees: from every bone, at most nbones steps reach a
     * root (more would revisit a bone, i.e. a cycle) */
    for (int b = 0; b < s->nbones; b++) {
        int k = b, steps = 0;
        while (k >= 0 && steps <= s->nbones) k = s->bone[k].parent, steps++;
        if (k >= 0) {
            *bone = b;
            *key = "parent";
            return sss_fail(err, SSS_ERR_ARG, "%d: the parents of bone %d never reach a root (a cycle)",
                            s->bone[b].parent, b);
        }
    }
    *bone = -1;
    *key = "blend_radius";
    if (!(s->blend_radius >= 0) || !isfinite(s->blend_radius))
        return sss_fail(err, SSS_ERR_ARG, "%g must be > 0 (0 in the struct: the default)", s->blend_radius);
    return SSS_OK;
}

double sss_skin_radius(const sss_skin *s)
{
    if (s->blend_radius > 0) return s->blend_radius;
    double lmin = INFINITY;
    for (int b = 0; b < s->nbones; b++) lmin = fmin(lmin, bone_length(&s->bone[b]));
    return SSS_SKIN_BLEND_DEFAULT * lmin;
}

/* |x − segment [h, t]|: the distance to the nearest point h + u (t − h),
 * u clamped to [0, 1]. */
static double segment_distance(const double x[3], const double h[3], const double t[3])
{
    double d[3], e[3];
    sss_sub3(d, t, h);
    sss_sub3(e, x, h);
    double u = sss_dot3(e, d) / sss_dot3(d, d);
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    for (int k = 0; k < 3; k++) e[k] -= u * d[k];
    return sqrt(sss_dot3(e, e));
}

static double smoothstep01(double s) { return s <= 0 ? 0.0 : s >= 1 ? 1.0 : s * s * (3.0 - 2.0 * s); }

void sss_skin_weights(const sss_skin *s, const sss_mesh *rest, double *w)
{
    const int nb = s->nbones;
    const double r = sss_skin_radius(s);
    for (uint32_t v = 0; v < rest->nv; v++) {
        const float *pf = &rest->pos[3 * (size_t)v];
        const double x[3] = {pf[0], pf[1], pf[2]};
        double d[SSS_SKIN_MAX_BONES], dmin = INFINITY, sum = 0;
        for (int b = 0; b < nb; b++) {
            d[b] = segment_distance(x, s->bone[b].head, s->bone[b].tail);
            dmin = fmin(dmin, d[b]);
        }
        double *wv = &w[(size_t)v * (size_t)nb];
        for (int b = 0; b < nb; b++) sum += wv[b] = smoothstep01(1.0 - (d[b] - dmin) / r);
        for (int b = 0; b < nb; b++) wv[b] /= sum; /* sum ≥ 1: the nearest bone's ŵ is 1 */
    }
}

/* T(h) · R(a, θ) · T(−h): Rodrigues' rotation about the line through h. At
 * θ = 0, R = I and the translation h − I h = 0, both exactly. */
static void turn_about(const double h[3], const double a[3], double theta, double m[16])
{
    const double c = cos(theta), s = sin(theta), k = 1.0 - c;
    const double R[9] = {c + k * a[0] * a[0],        k * a[0] * a[1] + s * a[2], k * a[0] * a[2] - s * a[1], /* col 0 */
                         k * a[0] * a[1] - s * a[2], c + k * a[1] * a[1],        k * a[1] * a[2] + s * a[0], /* col 1 */
                         k * a[0] * a[2] + s * a[1], k * a[1] * a[2] - s * a[0], c + k * a[2] * a[2]};       /* col 2 */
    for (int col = 0; col < 3; col++) {
        for (int row = 0; row < 3; row++) m[4 * col + row] = R[3 * col + row];
        m[4 * col + 3] = 0;
    }
    for (int row = 0; row < 3; row++)
        m[12 + row] = h[row] - (R[row] * h[0] + R[3 + row] * h[1] + R[6 + row] * h[2]);
    m[15] = 1;
}

void sss_skin_matrices(const sss_skin *s, const double *theta, double *M)
{
    int done[SSS_SKIN_MAX_BONES] = {0};
    for (int b = 0; b < s->nbones; b++) {
        /* the chain from b up to the first bone done (or a root), then
         * down again, each from its parent (sss_skin_check: no cycles) */
        int chain[SSS_SKIN_MAX_BONES], len = 0;
        for (int k = b; k >= 0 && !done[k]; k = s->bone[k].parent) chain[len++] = k;
        for (int i = len - 1; i >= 0; i--) {
            const int k = chain[i], p = s->bone[k].parent;
            double local[16];
            turn_about(s->bone[k].head, s->bone[k].axis, theta[k], local);
            if (p < 0) memcpy(&M[16 * (size_t)k], local, sizeof local);
            else sss_mat4_mul(&M[16 * (size_t)p], local, &M[16 * (size_t)k]);
            done[k] = 1;
        }
    }
}
