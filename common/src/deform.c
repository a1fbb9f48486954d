/* deform.c: the procedural deformers of sss/deform.h (docs/deformable.md
 * §2). Each maps a rest position to its pose in the frame (a, u, v) of the
 * rest mesh; the formulas and their meaning are in the header. The pose is
 * computed in double from the float rest positions and rounded once per
 * coordinate, vertex by vertex, so it does not depend on the thread count.
 */
#include "sss/deform.h"

#include <math.h>
#include <string.h>

#include "sss/vec3.h"

double sss_deform_angle(const sss_deform *d, double t)
{
    if (!d || d->kind == SSS_DEFORM_NONE || !(d->period_s > 0)) return 0.0;
    return d->angle_deg * (SSS_PI / 180.0) * sin(2.0 * SSS_PI * t / d->period_s);
}

const char *sss_deform_kind_name(sss_deform_kind k)
{
    switch (k) {
    case SSS_DEFORM_NONE: return "none";
    case SSS_DEFORM_BEND: return "bend";
    case SSS_DEFORM_TWIST: return "twist";
    case SSS_DEFORM_WAVE: return "wave";
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

sss_result sss_deform_pose(const sss_deform *d, double t, const sss_mesh *rest, const char *name, sss_mesh *out,
                           sss_error *err)
{
    memset(out, 0, sizeof *out);
    if (!name) name = "mesh";
    if (d->kind != SSS_DEFORM_NONE) {
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
    const double theta = sss_deform_angle(d, t);
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
