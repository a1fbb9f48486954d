/* deform.c: the procedural deformers of sss/deform.h (docs/deformable.md
 * §2). Each maps a rest position to its pose in the frame (a, u, v) of the
 * rest mesh; the formulas and their meaning are in the header. The pose is
 * computed in double from the float rest positions and rounded once per
 * coordinate, vertex by vertex, so it does not depend on the thread count.
 */
#include "sss/deform.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/vec3.h"

double sss_deform_theta(double angle_deg, double period_s, double t)
{
    if (!(period_s > 0)) return 0.0;
    return angle_deg * (SSS_PI / 180.0) * sin(2.0 * SSS_PI * t / period_s);
}

double sss_deform_angle(const sss_deform *d, double t)
{
    if (!d || d->kind == SSS_DEFORM_NONE) return 0.0;
    if (d->kind == SSS_DEFORM_SKIN) {
        const sss_skin *s = &d->skin;
        int m = 0;
        for (int b = 1; b < s->nbones && b < SSS_SKIN_MAX_BONES; b++)
            if (fabs(s->bone[b].angle_deg) > fabs(s->bone[m].angle_deg)) m = b;
        return s->nbones > 0 ? sss_deform_theta(s->bone[m].angle_deg, s->bone[m].period_s, t) : 0.0;
    }
    return sss_deform_theta(d->angle_deg, d->period_s, t);
}

const char *sss_deform_kind_name(sss_deform_kind k)
{
    switch (k) {
    case SSS_DEFORM_NONE: return "none";
    case SSS_DEFORM_BEND: return "bend";
    case SSS_DEFORM_TWIST: return "twist";
    case SSS_DEFORM_WAVE: return "wave";
    case SSS_DEFORM_SKIN: return "skin";
    }
    return "?";
}

static double max_deg(sss_deform_kind k)
{
    return k == SSS_DEFORM_BEND ? SSS_DEFORM_BEND_MAX_DEG
           : k == SSS_DEFORM_TWIST ? SSS_DEFORM_TWIST_MAX_DEG
                                  : SSS_DEFORM_WAVE_MAX_DEG;
}

/* The frame of sss/deform.h: u is the world axis least aligned with a,
 * made perpendicular to it; v = a × u. */
static void frame(const double a[3], double u[3], double v[3])
{
    int k = 0;
    for (int j = 1; j < 3; j++)
        if (fabs(a[j]) < fabs(a[k])) k = j;
    double e[3] = {0, 0, 0};
    e[k] = 1.0;
    const double ea = sss_dot3(e, a);
    for (int j = 0; j < 3; j++) u[j] = e[j] - ea * a[j];
    sss_normalize3(u);
    sss_cross3(a, u, v);
}

/* sin(x)/x and (1 − cos x)/x, with their limits at 0 (1 and 0). */
static double sinc(double x) { return x == 0.0 ? 1.0 : sin(x) / x; }
static double cosc(double x)
{
    const double h = sin(0.5 * x);
    return x == 0.0 ? 0.0 : 2.0 * h * h / x;
}

/* The skin's pose (sss/skin.h) into out->pos, a copy of the rest
 * positions: weights from the rest mesh, the bones' matrices at t, linear
 * blend skinning; left as the copy where every θ_b(t) is 0. */
static sss_result pose_skin(const sss_skin *s, double t, const sss_mesh *rest, const char *name, sss_mesh *out,
                            sss_error *err)
{
    double theta[SSS_SKIN_MAX_BONES], M[16 * SSS_SKIN_MAX_BONES];
    int moves = 0;
    for (int b = 0; b < s->nbones; b++) {
        theta[b] = sss_deform_theta(s->bone[b].angle_deg, s->bone[b].period_s, t);
        moves |= theta[b] != 0.0;
    }
    if (!moves || rest->nv == 0) return SSS_OK;
    const size_t nb = (size_t)s->nbones;
    double *w = malloc((size_t)rest->nv * nb * sizeof *w);
    if (!w) return sss_fail(err, SSS_ERR_NOMEM, "%s: deform: out of memory for %u vertices' weights", name, rest->nv);
    sss_skin_weights(s, rest, w);
    sss_skin_matrices(s, theta, M);
    uint32_t joint[SSS_SKIN_MAX_BONES];
    for (int b = 0; b < s->nbones; b++) joint[b] = (uint32_t)b;
    for (uint32_t v = 0; v < rest->nv; v++) {
        const float *pf = &rest->pos[3 * (size_t)v];
        const double p[3] = {pf[0], pf[1], pf[2]};
        double q[3];
        sss_skin_blend(M, joint, &w[(size_t)v * nb], s->nbones, p, q);
        for (int k = 0; k < 3; k++) out->pos[3 * (size_t)v + k] = (float)q[k];
    }
    free(w);
    return SSS_OK;
}

sss_result sss_deform_pose(const sss_deform *d, double t, const sss_mesh *rest, const char *name, sss_mesh *out,
                           sss_error *err)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "mesh";
    if (d->kind == SSS_DEFORM_SKIN) {
        if (!isfinite(t)) return sss_fail(err, SSS_ERR_ARG, "%s: deform: time %g is not a finite number", name, t);
        int bone;
        const char *key;
        sss_error why = {{0}};
        if (sss_skin_check(&d->skin, &bone, &key, &why) != SSS_OK) {
            if (bone < 0) return sss_fail(err, SSS_ERR_ARG, "%s: deform: %s: %s", name, key, why.msg);
            return sss_fail(err, SSS_ERR_ARG, "%s: deform: bones/%d/%s: %s", name, bone, key, why.msg);
        }
    } else if (d->kind != SSS_DEFORM_NONE) {
        if (!isfinite(t)) return sss_fail(err, SSS_ERR_ARG, "%s: deform: time %g is not a finite number", name, t);
        const double n = sqrt(sss_dot3(d->axis, d->axis));
        if (!(fabs(n - 1.0) <= 1e-9))
            return sss_fail(err, SSS_ERR_ARG, "%s: deform: axis (%g, %g, %g) is not a unit vector", name, d->axis[0],
                            d->axis[1], d->axis[2]);
        if (!(d->period_s > 0) || !isfinite(d->period_s))
            return sss_fail(err, SSS_ERR_ARG, "%s: deform: period %g s must be > 0", name, d->period_s);
        if (!(fabs(d->angle_deg) <= max_deg(d->kind)))
            return sss_fail(err, SSS_ERR_ARG, "%s: deform: %s angle %g degrees is beyond +-%g", name,
                            sss_deform_kind_name(d->kind), d->angle_deg, max_deg(d->kind));
    }
    const sss_mesh geom = {.nv = rest->nv, .nf = rest->nf, .pos = rest->pos, .tri = rest->tri};
    sss_result r = sss_mesh_copy(&geom, out, err);
    if (r != SSS_OK) return r;
    if (d->kind == SSS_DEFORM_SKIN) r = pose_skin(&d->skin, t, rest, name, out, err);
    if (r != SSS_OK) {
        sss_mesh_free(out);
        return r;
    }
    const double theta = d->kind == SSS_DEFORM_SKIN ? 0.0 : sss_deform_angle(d, t);
    if (theta != 0.0 && rest->nv > 0) {
        double a[3] = {d->axis[0], d->axis[1], d->axis[2]}, u[3], v[3], lo[3], hi[3], c[3];
        frame(a, u, v);
        sss_mesh_bounds(rest, lo, hi);
        for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]);
        double smin = INFINITY, smax = -INFINITY;
        for (uint32_t i = 0; i < rest->nv; i++) {
            const float *p = &rest->pos[3 * (size_t)i];
            const double s = a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
            smin = s < smin ? s : smin;
            smax = s > smax ? s : smax;
        }
        const double L = smax - smin, ca = sss_dot3(c, a);
        double cp[3]; /* c⊥ + s_min a: the fixed end of the axis line */
        for (int k = 0; k < 3; k++) cp[k] = c[k] - ca * a[k] + smin * a[k];
        const double kappa = L > 0 ? theta / L : 0.0, amp = L * tan(theta) / (2.0 * SSS_PI);
        for (uint32_t i = 0; i < rest->nv; i++) {
            const float *pf = &rest->pos[3 * (size_t)i];
            const double p[3] = {pf[0], pf[1], pf[2]};
            double q[3];
            sss_sub3(q, p, cp);
            double s = sss_dot3(q, a), y = sss_dot3(q, u), z = sss_dot3(q, v);
            if (d->kind == SSS_DEFORM_BEND) {
                const double x = kappa * s, cs = cos(x), sn = sin(x);
                const double s2 = s * sinc(x) - y * sn, y2 = s * cosc(x) + y * cs;
                s = s2, y = y2;
            } else if (d->kind == SSS_DEFORM_TWIST) {
                const double phi = L > 0 ? theta * s / L : 0.0, cs = cos(phi), sn = sin(phi);
                const double y2 = y * cs - z * sn, z2 = y * sn + z * cs;
                y = y2, z = z2;
            } else if (d->kind == SSS_DEFORM_WAVE && L > 0) {
                y += amp * sin(2.0 * SSS_PI * s / L);
            }
            for (int k = 0; k < 3; k++) out->pos[3 * (size_t)i + k] = (float)(cp[k] + s * a[k] + y * u[k] + z * v[k]);
        }
    }
    r = sss_mesh_compute_normals_areas(out, name, err);
    if (r != SSS_OK) sss_mesh_free(out);
    return r;
}
