/* sh.c: real spherical harmonics (Cartesian evaluation, no Condon–Shortley
 * phase), spherical Voronoi areas of a direction set, and the two
 * projections of baked samples onto the first n² harmonics
 * (Hao–Varshney 2004 §4.1; conventions in docs/physics.md §7 and sss/sh.h).
 */
#include "sss/sh.h"
#include "sss/vec3.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SH_PI 3.14159265358979323846

/* Condition limit for least squares: κ_F = ‖Y‖_F ‖P‖_F satisfies
 * cond₂(Y) ≤ κ_F ≤ n² cond₂(Y). Beyond the limit the coefficients of
 * measured data are dominated by amplified rounding/noise. Fibonacci sets
 * give κ_F ≈ n² (its minimum, orthonormal-like columns) for N ≥ 100 and
 * κ_F < 90 even at N = n² = 64. */
#define SH_LS_COND_LIMIT 1e10
/* Relative size of a QR pivot below which the columns count as dependent. */
#define SH_LS_RANK_TOL 1e-12

/* ------------------------------------------------------------------------ */
/* Evaluation                                                               */
/* ------------------------------------------------------------------------ */

/* K_l^|m| = sqrt((2l+1)/(4π) · (l−|m|)!/(l+|m|)!) (Hao–Varshney 2004 §4.1),
 * times √2 for m ≠ 0, for l < 8, row l starting at l(l+1)/2. Computed to 40
 * digits and rounded; test_sh checks every entry against the factorial
 * formula. */
static const double sh_norm[36] = {
    /* l = 0 */ 0.28209479177387814,
    /* l = 1 */ 0.48860251190291992, 0.48860251190291992,
    /* l = 2 */ 0.63078313050503998, 0.36418281019735971, 0.18209140509867985,
    /* l = 3 */ 0.7463526651802308, 0.30469719964297715, 0.096353714754685141, 0.0393362393284429,
    /* l = 4 */ 0.84628437532163447, 0.26761861742291565, 0.063078313050504001, 0.016858388283618388,
    0.0059603403376112009,
    /* l = 5 */ 0.9356025796273888, 0.24157154730437169, 0.045652731285460227, 0.0093188247511476266,
    0.0021964680580751758, 0.00069458418713245508,
    /* l = 6 */ 1.0171072362820548, 0.22195099524523101, 0.03509353369580661, 0.0058489222826344353,
    0.0010678622237644956, 0.00022766899107568562, 6.5722376641838803e-05,
    /* l = 7 */ 1.0925484305920792, 0.20647224590289673, 0.028097313806030644, 0.0039735602250741339,
    0.00059903674311141165, 9.9839457185235271e-05, 1.9580128477462541e-05, 5.2330094536914652e-06,
};

uint32_t sss_sh_count(uint32_t order)
{
    return order <= SSS_SH_MAX_ORDER ? order * order : 0;
}

/* Normalises d into u; 0 when d is zero or not finite. Scales by the largest
 * component first so that neither huge nor subnormal input over/underflows. */
static int sh_unit(const double d[3], double u[3])
{
    double a = fmax(fabs(d[0]), fmax(fabs(d[1]), fabs(d[2])));
    /* fmax ignores a NaN argument, so test the components themselves. */
    if (!isfinite(d[0]) || !isfinite(d[1]) || !isfinite(d[2]) || !(a > 0.0)) return 0;
    double x = d[0] / a, y = d[1] / a, z = d[2] / a;
    double r = sqrt(x * x + y * y + z * z);
    u[0] = x / r;
    u[1] = y / r;
    u[2] = z / r;
    return 1;
}

/* y_i(u) for a unit u, i < order², order in [1, 8].
 *
 * With P_l^m(z) = (1 − z²)^{m/2} Q_l^m(z) (no Condon–Shortley phase) and
 * sin^m θ (cos mφ, sin mφ) = (C_m, S_m), where C_m + i S_m = (x + iy)^m:
 *   y_l^{±m} = √2 K_l^m Q_l^m(z) (C_m, S_m),  y_l^0 = K_l^0 Q_l^0(z),
 * with the polynomial recurrence
 *   Q_m^m = (2m−1)!!,  Q_{m+1}^m = (2m+1) z Q_m^m,
 *   Q_l^m = ((2l−1) z Q_{l−1}^m − (l+m−1) Q_{l−2}^m) / (l−m).
 * Everything is a polynomial in (x, y, z): no angle, no division by sin θ
 * (docs/physics.md §7). */
static void sh_eval_unit(uint32_t order, double x, double y, double z, double *out)
{
    double cm = 1.0, sm = 0.0;  /* C_m, S_m */
    double qmm = 1.0;           /* Q_m^m = (2m−1)!! */
    for (uint32_t m = 0; m < order; m++) {
        if (m > 0) {
            double c = x * cm - y * sm, s = x * sm + y * cm;
            cm = c;
            sm = s;
            qmm *= (double)(2 * m - 1);
        }
        double q2 = 0.0, q1 = qmm; /* Q_{l−2}^m, Q_{l−1}^m; start at l = m */
        for (uint32_t l = m; l < order; l++) {
            double q;
            if (l == m) {
                q = qmm;
            } else if (l == m + 1) {
                q = (double)(2 * m + 1) * z * qmm;
            } else {
                q = ((double)(2 * l - 1) * z * q1 - (double)(l + m - 1) * q2) / (double)(l - m);
            }
            if (l > m) {
                q2 = q1;
                q1 = q;
            }
            const double k = sh_norm[l * (l + 1) / 2 + m] * q;
            const uint32_t c0 = l * (l + 1);
            if (m == 0) {
                out[c0] = k;
            } else {
                out[c0 + m] = k * cm;
                out[c0 - m] = k * sm;
            }
        }
    }
}

void sss_sh_eval(uint32_t order, const double d[3], double *y)
{
    if (order > SSS_SH_MAX_ORDER || order == 0) return;
    double u[3];
    if (!sh_unit(d, u)) {
        memset(y, 0, (size_t)order * order * sizeof *y);
        return;
    }
    sh_eval_unit(order, u[0], u[1], u[2], y);
}

void sss_sh_evalf(uint32_t order, const float d[3], float *y)
{
    if (order > SSS_SH_MAX_ORDER || order == 0) return;
    double dd[3] = {d[0], d[1], d[2]}, yd[SSS_SH_MAX_COUNT];
    sss_sh_eval(order, dd, yd);
    for (uint32_t i = 0; i < order * order; i++) y[i] = (float)yd[i];
}

double sss_sh_reconstruct(uint32_t order, const double *coeffs, const double d[3])
{
    if (order > SSS_SH_MAX_ORDER || order == 0) return 0.0;
    double y[SSS_SH_MAX_COUNT], u[3];
    if (!sh_unit(d, u)) return 0.0;
    sh_eval_unit(order, u[0], u[1], u[2], y);
    double s = 0.0;
    for (uint32_t i = 0; i < order * order; i++) s += coeffs[i] * y[i];
    return s;
}

/* ------------------------------------------------------------------------ */
/* Spherical Voronoi areas                                                  */
/* ------------------------------------------------------------------------ */


/* Signed solid angle of the spherical triangle (a, b, c) of unit vectors:
 * tan(E/2) = a·(b×c) / (1 + a·b + b·c + c·a) (Van Oosterom–Strackee);
 * atan2 keeps it exact for E near π and signs it by orientation. */
static double sph_tri_area(const double *a, const double *b, const double *c)
{
    double bc[3];
    sss_cross3(b, c, bc);
    double num = sss_dot3(a, bc), den = 1.0 + sss_dot3(a, b) + sss_dot3(b, c) + sss_dot3(c, a);
    return 2.0 * atan2(num, den);
}

/* Incident-triangle record: triangle t seen from one of its corners j, with
 * the next two corners (counter-clockwise) a and b. */
typedef struct sh_corner {
    uint32_t t, a, b;
} sh_corner;

/* Fills area (n values). Returns SSS_OK, SSS_ERR_NOMEM, or SSS_ERR_ARG with
 * *bad = the first direction whose incident triangles do not form one
 * closed fan (UINT32_MAX when the set has no triangles or a bad index). */
static sss_result voronoi_areas(const sss_dirset *s, double *area, uint32_t *bad)
{
    const uint32_t n = s->n, nt = s->ntri;
    *bad = UINT32_MAX;
    if (nt == 0 || !s->tri || !s->dir) return SSS_ERR_ARG;
    for (size_t k = 0; k < 3 * (size_t)nt; k++)
        if (s->tri[k] >= n) return SSS_ERR_ARG;

    double *cc = malloc(3 * (size_t)nt * sizeof *cc);
    uint32_t *start = calloc((size_t)n + 1, sizeof *start);
    sh_corner *cor = malloc(3 * (size_t)nt * sizeof *cor);
    if (!cc || !start || !cor) {
        free(cc);
        free(start);
        free(cor);
        return SSS_ERR_NOMEM;
    }

    /* Circumcentre of a counter-clockwise triangle on the unit sphere: the
     * outward normal of its plane, (b−a)×(c−a) normalised. */
    for (uint32_t t = 0; t < nt; t++) {
        const double *a = s->dir + 3 * (size_t)s->tri[3 * t], *b = s->dir + 3 * (size_t)s->tri[3 * t + 1],
                     *c = s->dir + 3 * (size_t)s->tri[3 * t + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double *w = cc + 3 * (size_t)t;
        sss_cross3(u, v, w);
        double len = sqrt(sss_dot3(w, w));
        if (!(len > 0.0)) len = 1.0; /* degenerate triangle: caught by the fan sum below */
        w[0] /= len;
        w[1] /= len;
        w[2] /= len;
    }

    /* Corners grouped by vertex (counting sort). */
    for (size_t k = 0; k < 3 * (size_t)nt; k++) start[s->tri[k] + 1]++;
    for (uint32_t j = 0; j < n; j++) start[j + 1] += start[j];
    {
        uint32_t *fill = malloc((size_t)n * sizeof *fill);
        if (!fill) {
            free(cc);
            free(start);
            free(cor);
            return SSS_ERR_NOMEM;
        }
        memcpy(fill, start, (size_t)n * sizeof *fill);
        for (uint32_t t = 0; t < nt; t++)
            for (int k = 0; k < 3; k++) {
                uint32_t j = s->tri[3 * t + k];
                cor[fill[j]++] = (sh_corner){t, s->tri[3 * t + (k + 1) % 3], s->tri[3 * t + (k + 2) % 3]};
            }
        free(fill);
    }

    /* Around ω_j, triangle (j, a, b) is followed counter-clockwise by the
     * triangle (j, b, c): its circumcentre is the next Voronoi vertex. Each
     * incident triangle t contributes the fan piece (ω_j, cc_t, cc_next(t)).
     * Every corner must have exactly one successor, and following successors
     * must visit all corners of j once (one closed fan, not several). */
    sss_result r = SSS_OK;
    for (uint32_t j = 0; j < n && r == SSS_OK; j++) {
        const uint32_t b0 = start[j], e0 = start[j + 1], val = e0 - b0;
        const double *w = s->dir + 3 * (size_t)j;
        if (val < 3) {
            r = SSS_ERR_ARG;
            *bad = j;
            break;
        }
        double sum = 0.0;
        uint32_t cur = b0, steps = 0;
        do {
            uint32_t nxt = UINT32_MAX;
            for (uint32_t k = b0; k < e0; k++)
                if (cor[k].a == cor[cur].b) {
                    if (nxt != UINT32_MAX) nxt = UINT32_MAX - 1; /* two successors: non-manifold */
                    else nxt = k;
                }
            if (nxt >= UINT32_MAX - 1) break;
            sum += sph_tri_area(w, cc + 3 * (size_t)cor[cur].t, cc + 3 * (size_t)cor[nxt].t);
            cur = nxt;
            steps++;
        } while (cur != b0 && steps < val);
        if (cur != b0 || steps != val || !(sum > 0.0)) {
            r = SSS_ERR_ARG;
            *bad = j;
            break;
        }
        area[j] = sum;
    }
    free(cc);
    free(start);
    free(cor);
    return r;
}

void sss_sh_voronoi_areas(const sss_dirset *s, double *area)
{
    uint32_t bad;
    if (voronoi_areas(s, area, &bad) != SSS_OK)
        for (uint32_t j = 0; j < s->n; j++) area[j] = NAN;
}

/* ------------------------------------------------------------------------ */
/* Projectors                                                               */
/* ------------------------------------------------------------------------ */

struct sss_sh_projector {
    uint32_t order, nc, n;
    sss_sh_method method;
    double *P; /* nc × n, row-major */
};

/* Least squares, P = R⁻¹ Qᵀ from the Householder QR of Y (n × nc). A is Y
 * column-major (column i = y_i at every direction), overwritten. Returns
 * SSS_OK, SSS_ERR_NOMEM, or SSS_ERR_ARG with *cond set (inf when a pivot
 * vanished). */
static sss_result ls_matrix(double *A, uint32_t n, uint32_t nc, double *P, double *cond)
{
    double *Q = calloc((size_t)n * nc, sizeof *Q);
    double *R = calloc((size_t)nc * nc, sizeof *R); /* row-major upper triangle */
    double *vtv = malloc((size_t)nc * sizeof *vtv);
    if (!Q || !R || !vtv) {
        free(Q);
        free(R);
        free(vtv);
        return SSS_ERR_NOMEM;
    }
    double yf2 = 0.0;
    for (size_t k = 0; k < (size_t)n * nc; k++) yf2 += A[k] * A[k];

    sss_result r = SSS_OK;
    double rmax = 0.0;
    *cond = INFINITY;
    for (uint32_t k = 0; k < nc; k++) {
        double *col = A + (size_t)k * n;
        double nrm2 = 0.0;
        for (uint32_t j = k; j < n; j++) nrm2 += col[j] * col[j];
        double nrm = sqrt(nrm2);
        double alpha = col[k] >= 0.0 ? -nrm : nrm;
        rmax = fmax(rmax, nrm);
        if (!(nrm > SH_LS_RANK_TOL * rmax)) {
            r = SSS_ERR_ARG;
            goto done;
        }
        /* v = x − α e_k stored in place of x; H = I − 2 v vᵀ / (vᵀv). */
        col[k] -= alpha;
        vtv[k] = 2.0 * nrm2 - 2.0 * alpha * (col[k] + alpha); /* = ‖x − α e_k‖² */
        R[(size_t)k * nc + k] = alpha;
        for (uint32_t c = k + 1; c < nc; c++) {
            double *x = A + (size_t)c * n, dp = 0.0;
            for (uint32_t j = k; j < n; j++) dp += col[j] * x[j];
            double f = 2.0 * dp / vtv[k];
            for (uint32_t j = k; j < n; j++) x[j] -= f * col[j];
            R[(size_t)k * nc + c] = x[k];
        }
    }
    /* Thin Q = H_0 H_1 … H_{nc−1} [I; 0]. */
    for (uint32_t i = 0; i < nc; i++) Q[(size_t)i * n + i] = 1.0;
    for (uint32_t kk = nc; kk-- > 0;) {
        const double *v = A + (size_t)kk * n;
        for (uint32_t c = 0; c < nc; c++) {
            double *x = Q + (size_t)c * n, dp = 0.0;
            for (uint32_t j = kk; j < n; j++) dp += v[j] * x[j];
            double f = 2.0 * dp / vtv[kk];
            for (uint32_t j = kk; j < n; j++) x[j] -= f * v[j];
        }
    }
    /* Column j of P solves R p = (row j of Q)ᵀ. */
    double pf2 = 0.0;
    for (uint32_t j = 0; j < n; j++) {
        for (uint32_t ii = nc; ii-- > 0;) {
            double s = Q[(size_t)ii * n + j];
            for (uint32_t c = ii + 1; c < nc; c++) s -= R[(size_t)ii * nc + c] * P[(size_t)c * n + j];
            double p = s / R[(size_t)ii * nc + ii];
            P[(size_t)ii * n + j] = p;
            pf2 += p * p;
        }
    }
    *cond = sqrt(yf2 * pf2);
    if (!(*cond <= SH_LS_COND_LIMIT)) r = SSS_ERR_ARG;
done:
    free(Q);
    free(R);
    free(vtv);
    return r;
}

sss_result sss_sh_projector_create(const sss_dirset *s, uint32_t order, sss_sh_method method,
                                   sss_sh_projector **out, sss_error *err)
{
    if (out) *out = NULL;
    if (!s || !out) return sss_fail(err, SSS_ERR_ARG, "sh projector: NULL direction set or output");
    if (method != SSS_SH_LEAST_SQUARES && method != SSS_SH_QUADRATURE)
        return sss_fail(err, SSS_ERR_ARG, "sh projector: unknown method %d", (int)method);
    const char *mname = method == SSS_SH_LEAST_SQUARES ? "least squares" : "quadrature";
    if (order > SSS_SH_MAX_ORDER)
        return sss_fail(err, SSS_ERR_ARG, "sh projector: order %u out of range [0, %u] (%u directions)", order,
                        SSS_SH_MAX_ORDER, s->n);
    if (s->n == 0 || !s->dir) return sss_fail(err, SSS_ERR_ARG, "sh projector: order %u: direction set is empty", order);
    const uint32_t n = s->n, nc = order * order;
    if (nc > n)
        return sss_fail(err, SSS_ERR_ARG,
                        "sh projector: order %u needs %u coefficients but there are only %u directions "
                        "(need order² ≤ directions)",
                        order, nc, n);
    for (uint32_t j = 0; j < n; j++) {
        const double *d = s->dir + 3 * (size_t)j;
        if (!isfinite(d[0]) || !isfinite(d[1]) || !isfinite(d[2]) || (d[0] == 0 && d[1] == 0 && d[2] == 0))
            return sss_fail(err, SSS_ERR_ARG, "sh projector: order %u, %u directions: direction %u is zero or not finite",
                            order, n, j);
    }

    sss_sh_projector *p = calloc(1, sizeof *p);
    if (!p) return sss_fail(err, SSS_ERR_NOMEM, "sh projector: out of memory (order %u, %u directions)", order, n);
    p->order = order;
    p->nc = nc;
    p->n = n;
    p->method = method;

    double *area = NULL, *Y = NULL;
    sss_result r = SSS_OK;
    if (method == SSS_SH_QUADRATURE) {
        area = malloc((size_t)n * sizeof *area);
        if (!area) {
            r = sss_fail(err, SSS_ERR_NOMEM, "sh projector: out of memory (order %u, %u directions)", order, n);
            goto fail;
        }
        uint32_t bad;
        r = voronoi_areas(s, area, &bad);
        if (r == SSS_ERR_NOMEM) {
            sss_fail(err, r, "sh projector: out of memory (order %u, %u directions)", order, n);
            goto fail;
        }
        if (r != SSS_OK) {
            if (bad == UINT32_MAX)
                sss_fail(err, r,
                         "sh projector: quadrature at order %u needs a triangulated direction set "
                         "(%u directions, %u triangles)",
                         order, n, s->ntri);
            else
                sss_fail(err, r,
                         "sh projector: quadrature at order %u on %u directions: triangles around direction %u "
                         "do not form one closed counter-clockwise fan",
                         order, n, bad);
            goto fail;
        }
    }
    if (nc == 0) goto ok;

    p->P = malloc((size_t)nc * n * sizeof *p->P);
    Y = malloc((size_t)nc * n * sizeof *Y); /* column-major: Y[i*n + j] = y_i(ω_j) */
    if (!p->P || !Y) {
        r = sss_fail(err, SSS_ERR_NOMEM, "sh projector: out of memory (order %u, %u directions)", order, n);
        goto fail;
    }
    for (uint32_t j = 0; j < n; j++) {
        double y[SSS_SH_MAX_COUNT];
        sss_sh_eval(order, s->dir + 3 * (size_t)j, y);
        for (uint32_t i = 0; i < nc; i++) Y[(size_t)i * n + j] = y[i];
    }
    if (method == SSS_SH_QUADRATURE) {
        /* c_i = Σ_j A_j y_i(ω_j) f_j: the paper's projection integral
         * (Hao–Varshney 2004 §4.1) with the Voronoi cells as quadrature. */
        for (uint32_t i = 0; i < nc; i++)
            for (uint32_t j = 0; j < n; j++) p->P[(size_t)i * n + j] = area[j] * Y[(size_t)i * n + j];
    } else {
        double cond;
        r = ls_matrix(Y, n, nc, p->P, &cond);
        if (r == SSS_ERR_NOMEM) {
            sss_fail(err, r, "sh projector: out of memory (order %u, %u directions)", order, n);
            goto fail;
        }
        if (r != SSS_OK) {
            if (isinf(cond))
                sss_fail(err, r,
                         "sh projector: %s at order %u is rank deficient on these %u directions "
                         "(the %u harmonics are linearly dependent at the samples)",
                         mname, order, n, nc);
            else
                sss_fail(err, r,
                         "sh projector: %s at order %u is ill-conditioned on these %u directions "
                         "(condition estimate %.3g > %.0e)",
                         mname, order, n, cond, SH_LS_COND_LIMIT);
            goto fail;
        }
    }
ok:
    free(area);
    free(Y);
    *out = p;
    return SSS_OK;
fail:
    free(area);
    free(Y);
    sss_sh_projector_destroy(p);
    return r;
}

void sss_sh_project_strided(const sss_sh_projector *p, const double *f, size_t stride, double *coeffs)
{
    const uint32_t n = p->n;
    for (uint32_t i = 0; i < p->nc; i++) {
        const double *row = p->P + (size_t)i * n;
        double s = 0.0;
        for (uint32_t j = 0; j < n; j++) s += row[j] * f[(size_t)j * stride];
        coeffs[i] = s;
    }
}

void sss_sh_project(const sss_sh_projector *p, const double *f, double *coeffs)
{
    sss_sh_project_strided(p, f, 1, coeffs);
}

const double *sss_sh_projector_matrix(const sss_sh_projector *p) { return p->P; }

uint32_t sss_sh_projector_order(const sss_sh_projector *p) { return p->order; }

uint32_t sss_sh_projector_ndirs(const sss_sh_projector *p) { return p->n; }

void sss_sh_projector_destroy(sss_sh_projector *p)
{
    if (!p) return;
    free(p->P);
    free(p);
}
