/* hatweights.c: the weights of Hao–Varshney 2004 §3.1 integrated over the
 * hat functions of the vertices (sss/hatweights.h, docs/physics.md §9). */
#include "sss/hatweights.h"
#include "sss/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

double sss_hat_zmin(const sss_dipole *dip, uint32_t C)
{
    double z = INFINITY;
    for (uint32_t c = 0; c < C; c++) z = fmin(z, dip[c].z_r);
    return z;
}

/* The profile's two length scales for the quadrature: the peak's width
 * (the smallest z_r) and the exponential's decay length (1 / the largest
 * σtr; infinite for σa = 0). */
typedef struct hat_scales {
    uint32_t C;
    double zmin;                        /* the smallest z_r: the close test */
    double z[SSS_MAX_CHANNELS];         /* per channel: the peak's width z_r, */
    double lexp[SSS_MAX_CHANNELS];      /* the exponential's decay length 1/σtr (∞ for σa = 0) */
    double inv_total[SSS_MAX_CHANNELS]; /* and π / R_d,total: a flat slab's q = 1 */
} hat_scales;

static hat_scales scales_of(const sss_dipole *dip, uint32_t C)
{
    hat_scales sc;
    memset(&sc, 0, sizeof sc);
    sc.C = C;
    sc.zmin = sss_hat_zmin(dip, C);
    for (uint32_t c = 0; c < C; c++) {
        sc.z[c] = dip[c].z_r;
        sc.lexp[c] = dip[c].sigma_tr > 0.0 ? 1.0 / dip[c].sigma_tr : INFINITY;
        const double tot = sss_rd_total(&dip[c]);
        sc.inv_total[c] = tot > 0.0 ? SSS_PI / tot : 0.0;
    }
    return sc;
}

/* A piece is split while, for some channel, it is larger than
 * SSS_HAT_KAPPA_LEAF times the profile's scale there — its distance dlb
 * from x_o, but at least that channel's z_r and at most HAT_DECAY_LENGTHS
 * decay lengths 1/σtr — unless, beyond that, the piece holds less than
 * HAT_PIECE_SHARE of a flat slab's q in that channel: even a wrong rule
 * there moves q by less, and far pieces would otherwise be cut down to
 * 1/σtr where the profile has all but vanished. Measured on the 23K dragon
 * at 1000 mm per unit in skin1 (the shortest decay, 0.68 mm in blue),
 * against leaves 2.5× smaller, no cap and a share of 1e-10: rows within
 * 3.6e-5 of a slab's q either way (1e-7 and one decay length: 3.4e-5), at
 * a sixth of the time. */
#define HAT_DECAY_LENGTHS 4.0
#define HAT_PIECE_SHARE 1e-6

double sss_cutoff_radius_mm(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t C, double eps,
                            double *radius_mm)
{
    double lo[3], hi[3], search = 0.0;
    const double diag_mm = sss_mesh_bounds(mesh, lo, hi) * mm_per_unit;
    for (uint32_t c = 0; c < C; c++) {
        const double rc = sss_rd_radius(&dip[c], eps, diag_mm);
        if (radius_mm) radius_mm[c] = rc;
        if (rc > search) search = rc;
    }
    return search;
}

double sss_point_weight(const sss_dipole *d, double r, double dA)
{
    const double rho = sqrt(dA / SSS_PI);
    return r < rho ? sss_rd_disk_offset(d, r, rho) / SSS_PI : sss_rd(d, r) * dA / SSS_PI;
}

/* ---- the profile as polynomials in r² ------------------------------------ */

/* (1/π) R_d as piecewise polynomials of x = r², one per octave [2^e, 2^(e+1))
 * of x, Chebyshev-interpolated at RDP_DEG + 1 nodes (the method of the
 * gather's float tables, precompute/src/gather/gather_rdtab.c, in double):
 * the quadrature evaluates R_d a few thousand times per receiver, and the
 * polynomial costs a tenth of the two exponentials, square roots and
 * divisions. On an octave [a, 2a] the profile's nearest singularity is at
 * x = −z² ≤ 0, at least 3 half-widths from the centre, so degree 12
 * converges fast; the exponential e^{−σtr √x} varies by e^{0.41 σtr √a}
 * over an octave, a few e-folds up to the cutoff radius. Measured against
 * sss_rd for every preset: 3e-8 relative inside the cutoff radius, 4e-6
 * out to twice it (tests/unit/test_hatweights.c). Below the first
 * octave the value at its start is used (R_d is flat there to 1e-11);
 * above the last, sss_rd itself. */
#define RDP_N 44
#define RDP_DEG 12

typedef struct rdpoly {
    const sss_dipole *d;
    int e0;      /* first octave */
    double xtop; /* 2^(e0 + RDP_N) */
    double c[RDP_N][RDP_DEG + 1];
} rdpoly;

static void rdpoly_init(rdpoly *t, const sss_dipole *d, double xmax)
{
    int E = 0;
    (void)frexp(xmax > 0.0 && isfinite(xmax) ? xmax : 1.0, &E); /* xmax < 2^E */
    t->d = d;
    t->e0 = E - RDP_N;
    t->xtop = ldexp(1.0, E);
    enum { NP = RDP_DEG + 1 };
    for (int i = 0; i < RDP_N; i++) {
        const double a = ldexp(1.0, t->e0 + i);
        double fu[NP], ch[NP];
        for (int m = 0; m < NP; m++) {
            const double u = cos(SSS_PI * (m + 0.5) / NP);
            fu[m] = sss_rd(d, sqrt(a * (1.0 + (u + 1.0) / 2.0))) / SSS_PI;
        }
        for (int k = 0; k < NP; k++) {
            double sum = 0.0;
            for (int m = 0; m < NP; m++) sum += fu[m] * cos(SSS_PI * k * (m + 0.5) / NP);
            ch[k] = 2.0 * sum / NP;
        }
        ch[0] *= 0.5;
        /* Σ c_k T_k(u) as powers of u (T_{k+1} = 2u T_k − T_{k−1}) */
        double mono[NP] = {0}, Tkm1[NP] = {0}, Tk[NP] = {0}, Tn[NP];
        Tkm1[0] = 1.0;
        Tk[1] = 1.0;
        mono[0] += ch[0];
        for (int j = 0; j < NP; j++) mono[j] += ch[1] * Tk[j];
        for (int k = 2; k < NP; k++) {
            for (int j = 0; j < NP; j++) Tn[j] = (j > 0 ? 2.0 * Tk[j - 1] : 0.0) - Tkm1[j];
            for (int j = 0; j < NP; j++) mono[j] += ch[k] * Tn[j];
            memcpy(Tkm1, Tk, sizeof Tk);
            memcpy(Tk, Tn, sizeof Tn);
        }
        memcpy(t->c[i], mono, sizeof mono);
    }
}

/* (1/π) R_d(√x) */
static inline double rdpoly_eval(const rdpoly *t, double x)
{
    if (!(x < t->xtop)) return sss_rd(t->d, sqrt(x)) / SSS_PI;
    int e;
    const double m = frexp(x, &e); /* x = m 2^e, m in [0.5, 1): octave e − 1, t = 2m − 1 */
    int i = e - 1 - t->e0;
    double u;
    if (i < 0) i = 0, u = -1.0;
    else u = 4.0 * m - 3.0; /* 2t − 1 */
    const double *c = t->c[i];
    double p = c[RDP_DEG];
    for (int j = RDP_DEG - 1; j >= 0; j--) p = p * u + c[j];
    return p;
}

/* The tables need reach no farther than twice the profile's 1e-3 cutoff
 * radius, where they still hold to 4e-6 and beyond which rdpoly_eval takes
 * sss_rd itself: a mesh with a triangle kilometres long (a stray vertex)
 * would otherwise stretch the 44 octaves so far up that the first one
 * began metres from x_o and every near value read as the profile there.
 * Meshes whose candidate triangles lie inside that radius keep the tables
 * they had. */
static double rdpoly_reach2(const sss_dipole *d, double x)
{
    const double R = sss_rd_radius(d, 1e-3, 1e6);
    return R > 0.0 ? fmin(x, 4.0 * R * R) : x;
}

double sss_hat_rdpoly_check(const sss_dipole *d, double xmax, double x)
{
    rdpoly t;
    rdpoly_init(&t, d, xmax);
    return rdpoly_eval(&t, x);
}

/* ---- one triangle ---------------------------------------------------------- */

/* The 7-point degree-5 rule on a triangle (Radon 1948; Stroud T2:5-1):
 * barycentric points and weights summing to 1. */
#define R15 3.872983346207417 /* √15 */
static const double RULE_A1 = (6.0 - R15) / 21.0, RULE_B1 = (9.0 + 2.0 * R15) / 21.0;
static const double RULE_A2 = (6.0 + R15) / 21.0, RULE_B2 = (9.0 - 2.0 * R15) / 21.0;
static const double RULE_W0 = 9.0 / 40.0, RULE_W1 = (155.0 - R15) / 1200.0, RULE_W2 = (155.0 + R15) / 1200.0;

/* A piece is split into four similar ones (edge midpoints), which keeps its
 * shape; a sliver — area below HAT_SLIVER times its diameter squared — is
 * instead cut in two across its longest edge, so that the cuts go across
 * its length and not also across its width: four-way splits of a needle
 * 10^9 times longer than wide would need ~2^d pieces across the width at
 * depth d near x_o, bisection a few per level (docs/robustness.md,
 * "Degenerate triangles"). Depth counts area halvings (two per four-way
 * split); HAT_MAX_HALVINGS is 2^-30 of the triangle's diameter for similar
 * pieces. Triangles no thinner than HAT_SLIVER get exactly the four-way
 * pieces, areas and diameters they always had (both are halved and
 * quartered exactly in binary). */
#define HAT_MAX_HALVINGS 60
#define HAT_SLIVER 0.05

typedef struct piece {
    double b[3][3]; /* barycentric coordinates (of the whole triangle) of the piece's corners */
    double h, a;    /* the piece's diameter (longest edge) and area */
    int depth;      /* area halvings from the whole triangle */
} piece;

static void bary_pos(const double p[3][3], const double b[3], double x[3])
{
    for (int k = 0; k < 3; k++) x[k] = b[0] * p[0][k] + b[1] * p[1][k] + b[2] * p[2][k];
}

static double dist3(const double a[3], const double b[3])
{
    double d[3];
    sss_sub3(d, a, b);
    return sqrt(sss_dot3(d, d));
}

static void hat_triangle(const rdpoly *tab, uint32_t C, hat_scales sc, const double p[3][3], const double xo[3],
                         double *out);

void sss_hat_triangle(const sss_dipole *dip, uint32_t C, const double p[3][3], const double xo[3], double *out)
{
    /* tables reaching past the triangle's farthest point from x_o */
    double far2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double d[3];
        sss_sub3(d, p[k], xo);
        far2 = fmax(far2, sss_dot3(d, d));
    }
    rdpoly tab[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < C; c++) rdpoly_init(&tab[c], &dip[c], rdpoly_reach2(&dip[c], 2.0 * far2) + 1e-300);
    hat_triangle(tab, C, scales_of(dip, C), p, xo, out);
}

static void hat_triangle(const rdpoly *tab, uint32_t C, hat_scales sc, const double p[3][3], const double xo[3],
                         double *out)
{
    for (uint32_t k = 0; k < 3 * C; k++) out[k] = 0.0;
    double e[3][3], cr[3];
    for (int k = 0; k < 3; k++) sss_sub3(e[k], p[(k + 1) % 3], p[k]);
    sss_cross3(e[0], e[2], cr);
    const double area = 0.5 * sqrt(sss_dot3(cr, cr));
    if (!(area > 0.0)) return;
    double h = 0.0;
    for (int k = 0; k < 3; k++) h = fmax(h, sqrt(sss_dot3(e[k], e[k])));
    /* Depth-first over the pieces, children in a fixed order: the sum is
     * taken in the same order on every run. The stack holds at most three
     * siblings per four-way level (two halvings) and one per bisection,
     * plus the piece being split. */
    piece stack[3 * HAT_MAX_HALVINGS / 2 + 4];
    int top = 0;
    memset(&stack[0], 0, sizeof stack[0]);
    for (int k = 0; k < 3; k++) stack[0].b[k][k] = 1.0;
    stack[0].h = h;
    stack[0].a = area;
    top = 1;
    while (top > 0) {
        const piece pc = stack[--top];
        double x[3][3], cen[3] = {0, 0, 0};
        for (int m = 0; m < 3; m++) {
            bary_pos(p, pc.b[m], x[m]);
            for (int k = 0; k < 3; k++) cen[k] += x[m][k] / 3.0;
        }
        double rad = 0.0;
        for (int m = 0; m < 3; m++) rad = fmax(rad, dist3(x[m], cen));
        const double dlb = fmax(0.0, dist3(cen, xo) - rad);
        const int sliver = pc.a < HAT_SLIVER * pc.h * pc.h;
        int split = 0;
        for (uint32_t c = 0; c < C && !split && pc.depth + 2 - sliver <= HAT_MAX_HALVINGS; c++) {
            const double ldec = HAT_DECAY_LENGTHS * sc.lexp[c];
            if (!(pc.h > SSS_HAT_KAPPA_LEAF * fmax(sc.z[c], fmin(dlb, ldec)))) continue;
            split = dlb <= ldec || rdpoly_eval(&tab[c], dlb * dlb) * pc.a * sc.inv_total[c] >= HAT_PIECE_SHARE;
        }
        if (split && sliver) {
            int m = 0; /* the corner opposite the longest edge */
            double best = -1.0;
            for (int k = 0; k < 3; k++) {
                const double l = dist3(x[(k + 1) % 3], x[(k + 2) % 3]);
                if (l > best) best = l, m = k;
            }
            const int i = (m + 1) % 3, j = (m + 2) % 3;
            double mid[3];
            for (int k = 0; k < 3; k++) mid[k] = 0.5 * (pc.b[i][k] + pc.b[j][k]);
            piece ch[2];
            for (int n = 0; n < 2; n++) {
                memcpy(ch[n].b[0], pc.b[m], sizeof ch[n].b[0]);
                memcpy(ch[n].b[1], n ? mid : pc.b[i], sizeof ch[n].b[1]);
                memcpy(ch[n].b[2], n ? pc.b[j] : mid, sizeof ch[n].b[2]);
                double y[3][3];
                for (int k = 0; k < 3; k++) bary_pos(p, ch[n].b[k], y[k]);
                ch[n].h = fmax(dist3(y[0], y[1]), fmax(dist3(y[1], y[2]), dist3(y[2], y[0])));
                ch[n].a = 0.5 * pc.a;
                ch[n].depth = pc.depth + 1;
            }
            stack[top++] = ch[1];
            stack[top++] = ch[0];
            continue;
        }
        if (split) {
            double mid[3][3]; /* mid[m]: the midpoint of the edge opposite corner m */
            for (int m = 0; m < 3; m++)
                for (int k = 0; k < 3; k++) mid[m][k] = 0.5 * (pc.b[(m + 1) % 3][k] + pc.b[(m + 2) % 3][k]);
            piece ch[4];
            for (int m = 0; m < 3; m++) { /* corner pieces */
                memcpy(ch[m].b[0], pc.b[m], sizeof ch[m].b[0]);
                memcpy(ch[m].b[1], mid[(m + 2) % 3], sizeof ch[m].b[1]);
                memcpy(ch[m].b[2], mid[(m + 1) % 3], sizeof ch[m].b[2]);
            }
            memcpy(ch[3].b, mid, sizeof mid); /* the middle piece */
            for (int m = 3; m >= 0; m--) {
                ch[m].h = 0.5 * pc.h;
                ch[m].a = 0.25 * pc.a;
                ch[m].depth = pc.depth + 2;
                stack[top++] = ch[m];
            }
            continue;
        }
        const double ap = pc.a; /* the piece's area (the tables hold R_d / π) */
        static const int NPT = 7;
        for (int q = 0; q < NPT; q++) {
            double beta[3], w;
            if (q == 0) beta[0] = beta[1] = beta[2] = 1.0 / 3.0, w = RULE_W0;
            else if (q <= 3) {
                const int m = q - 1;
                beta[0] = beta[1] = beta[2] = RULE_A1;
                beta[m] = RULE_B1;
                w = RULE_W1;
            } else {
                const int m = q - 4;
                beta[0] = beta[1] = beta[2] = RULE_A2;
                beta[m] = RULE_B2;
                w = RULE_W2;
            }
            double lam[3], xq[3];
            for (int k = 0; k < 3; k++) lam[k] = beta[0] * pc.b[0][k] + beta[1] * pc.b[1][k] + beta[2] * pc.b[2][k];
            bary_pos(p, lam, xq);
            double dq[3];
            sss_sub3(dq, xq, xo);
            const double r2 = sss_dot3(dq, dq);
            for (uint32_t c = 0; c < C; c++) {
                const double f = w * ap * rdpoly_eval(&tab[c], r2);
                for (int k = 0; k < 3; k++) out[k * C + c] += lam[k] * f;
            }
        }
    }
}

/* ---- which triangles are close -------------------------------------------- */

/* Distance from x to the triangle a b c (closest point on the triangle:
 * Ericson, Real-Time Collision Detection §5.1.5). */
static double point_triangle_distance(const double x[3], const double a[3], const double b[3], const double c[3])
{
    double ab[3], ac[3], ap[3], q[3];
    sss_sub3(ab, b, a);
    sss_sub3(ac, c, a);
    sss_sub3(ap, x, a);
    const double d1 = sss_dot3(ab, ap), d2 = sss_dot3(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return dist3(x, a);
    double bp[3];
    sss_sub3(bp, x, b);
    const double d3 = sss_dot3(ab, bp), d4 = sss_dot3(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return dist3(x, b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++) q[k] = a[k] + v * ab[k];
        return dist3(x, q);
    }
    double cp[3];
    sss_sub3(cp, x, c);
    const double d5 = sss_dot3(ab, cp), d6 = sss_dot3(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return dist3(x, c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++) q[k] = a[k] + w * ac[k];
        return dist3(x, q);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++) q[k] = b[k] + w * (c[k] - b[k]);
        return dist3(x, q);
    }
    const double den = 1.0 / (va + vb + vc), v = vb * den, w = vc * den;
    for (int k = 0; k < 3; k++) q[k] = a[k] + ab[k] * v + ac[k] * w;
    return dist3(x, q);
}

/* Triangles binned by diameter class (powers of two) and, per class, by a
 * grid cell as wide as the class's search radius, sorted by (class, cell)
 * key: a receiver reads the 27 cells around it in each class. */
#define GRID_BITS 19
#define CLASS_MAX 63

typedef struct tkey {
    uint64_t key;
    uint32_t t;
} tkey;

typedef struct trigrid {
    tkey *keys;
    uint32_t n;
    int nclass;
    double cell[CLASS_MAX + 1], lo[3];
    double *h, *area, *cen; /* per triangle, mm; h = 0 for a degenerate one */
} trigrid;

static int cmp_tkey(const void *x, const void *y)
{
    const tkey *a = x, *b = y;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->t > b->t) - (a->t < b->t);
}

static uint64_t make_key(int cls, int64_t ix, int64_t iy, int64_t iz)
{
    return ((uint64_t)cls << (3 * GRID_BITS)) | ((uint64_t)ix << (2 * GRID_BITS)) | ((uint64_t)iy << GRID_BITS) |
           (uint64_t)iz;
}

static int64_t cell_of(double x, double lo, double cell)
{
    double f = floor((x - lo) / cell);
    const double top = (double)((1 << GRID_BITS) - 1);
    return (int64_t)(f < 0.0 ? 0.0 : f > top ? top : f);
}

static void tri_mm(const sss_mesh *m, double s, uint32_t t, double p[3][3])
{
    for (int k = 0; k < 3; k++) {
        const uint32_t v = m->tri[3 * (size_t)t + k];
        for (int x = 0; x < 3; x++) p[k][x] = (double)m->pos[3 * (size_t)v + x] * s;
    }
}

static int trigrid_build(const sss_mesh *m, double s, trigrid *g)
{
    memset(g, 0, sizeof *g);
    const uint32_t nf = m->nf;
    g->h = malloc((size_t)nf * sizeof *g->h + 1);
    g->area = malloc((size_t)nf * sizeof *g->area + 1);
    g->cen = malloc((size_t)nf * 3 * sizeof *g->cen + 1);
    g->keys = malloc((size_t)nf * sizeof *g->keys + 1);
    if (!g->h || !g->area || !g->cen || !g->keys) return 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int emax = INT32_MIN;
    for (uint32_t t = 0; t < nf; t++) {
        double p[3][3], e[3][3], cr[3];
        tri_mm(m, s, t, p);
        double h = 0.0;
        for (int k = 0; k < 3; k++) {
            sss_sub3(e[k], p[(k + 1) % 3], p[k]);
            h = fmax(h, sqrt(sss_dot3(e[k], e[k])));
        }
        sss_cross3(e[0], e[2], cr);
        g->area[t] = 0.5 * sqrt(sss_dot3(cr, cr));
        g->h[t] = g->area[t] > 0.0 && isfinite(h) ? h : 0.0;
        for (int x = 0; x < 3; x++) {
            g->cen[3 * (size_t)t + x] = (p[0][x] + p[1][x] + p[2][x]) / 3.0;
            lo[x] = fmin(lo[x], g->cen[3 * (size_t)t + x]);
            hi[x] = fmax(hi[x], g->cen[3 * (size_t)t + x]);
        }
        if (g->h[t] > 0.0) emax = ilogb(g->h[t]) > emax ? ilogb(g->h[t]) : emax;
    }
    memcpy(g->lo, lo, sizeof lo);
    double ext = 0.0;
    for (int x = 0; x < 3; x++) ext = fmax(ext, hi[x] - lo[x]);
    g->nclass = 0;
    if (emax == INT32_MIN) return 1; /* every triangle degenerate: nothing to integrate */
    /* class c holds diameters below 2^(emax + 1 − c); the smallest class
     * takes every smaller triangle too (a wider search than they need) */
    for (int c = 0; c <= CLASS_MAX; c++) {
        const double H = ldexp(1.0, emax + 1 - c);
        g->cell[c] = fmax(H * (1.0 / SSS_HAT_KAPPA + 1.0), ext / (double)(1 << (GRID_BITS - 1)));
    }
    uint32_t n = 0;
    for (uint32_t t = 0; t < nf; t++) {
        if (!(g->h[t] > 0.0)) continue;
        int c = emax - ilogb(g->h[t]);
        c = c > CLASS_MAX ? CLASS_MAX : c;
        if (c + 1 > g->nclass) g->nclass = c + 1;
        const double *x = g->cen + 3 * (size_t)t;
        g->keys[n].key = make_key(c, cell_of(x[0], lo[0], g->cell[c]), cell_of(x[1], lo[1], g->cell[c]),
                                  cell_of(x[2], lo[2], g->cell[c]));
        g->keys[n].t = t;
        n++;
    }
    g->n = n;
    qsort(g->keys, n, sizeof *g->keys, cmp_tkey);
    return 1;
}

static void trigrid_free(trigrid *g)
{
    free(g->keys);
    free(g->h);
    free(g->area);
    free(g->cen);
    memset(g, 0, sizeof *g);
}

/* first key index ≥ key */
static uint32_t lower_bound(const tkey *k, uint32_t n, uint64_t key)
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (k[mid].key < key) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* ---- the corrections ----------------------------------------------------- */

static int cmp_u32(const void *x, const void *y)
{
    const uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
    return (a > b) - (a < b);
}

typedef struct tbuf { /* one thread's scratch and output */
    uint32_t *cand;
    size_t capc;
    /* per vertex, for the receiver at hand (stamp[v] = receiver + 1 when
     * set): the close triangles' integrals and their areas / 3, summed in
     * triangle order */
    uint32_t *stamp;
    double *acc; /* nv × (C + 1) */
    uint32_t *touched;
    size_t capt;
    uint32_t *idx;
    float *w;
    size_t n, cap, capw;
    int failed;
} tbuf;

static int grow(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return 1;
    size_t c = need + need / 2 + 64;
    void *q = realloc(*p, c * elem);
    if (!q) return 0;
    *p = q;
    *cap = c;
    return 1;
}

/* The receiver's candidate triangles into b->cand, ascending: every
 * triangle within diam / κ of x_o found through the grid, or (want) only
 * those incident to the wanted vertices. Returns the count, −1 when out of
 * memory. */
static int64_t candidates(const trigrid *g, const double xo[3], const uint32_t *want, uint32_t nwant,
                          const uint32_t *vt_start, const uint32_t *vt_tri, tbuf *b)
{
    const double kap = SSS_HAT_KAPPA;
    size_t nc = 0;
    if (want) {
        for (uint32_t a = 0; a < nwant; a++)
            for (uint32_t e = vt_start[want[a]]; e < vt_start[want[a] + 1]; e++) {
                if (!grow((void **)&b->cand, &b->capc, nc + 1, sizeof *b->cand)) return -1;
                b->cand[nc++] = vt_tri[e];
            }
        qsort(b->cand, nc, sizeof *b->cand, cmp_u32);
        size_t u = 0;
        for (size_t a = 0; a < nc; a++)
            if (u == 0 || b->cand[a] != b->cand[u - 1]) b->cand[u++] = b->cand[a];
        return (int64_t)u;
    }
    for (int c = 0; c < g->nclass; c++) {
        const double cell = g->cell[c];
        const int64_t cx = cell_of(xo[0], g->lo[0], cell), cy = cell_of(xo[1], g->lo[1], cell),
                      cz = cell_of(xo[2], g->lo[2], cell);
        for (int64_t ix = cx - 1; ix <= cx + 1; ix++)
            for (int64_t iy = cy - 1; iy <= cy + 1; iy++)
                for (int64_t iz = cz - 1; iz <= cz + 1; iz++) {
                    if (ix < 0 || iy < 0 || iz < 0 || ix >= (1 << GRID_BITS) || iy >= (1 << GRID_BITS) ||
                        iz >= (1 << GRID_BITS))
                        continue;
                    const uint64_t key = make_key(c, ix, iy, iz);
                    for (uint32_t a = lower_bound(g->keys, g->n, key); a < g->n && g->keys[a].key == key; a++) {
                        const uint32_t t = g->keys[a].t;
                        if (dist3(g->cen + 3 * (size_t)t, xo) > g->h[t] * (1.0 / kap + 1.0)) continue;
                        if (!grow((void **)&b->cand, &b->capc, nc + 1, sizeof *b->cand)) return -1;
                        b->cand[nc++] = t;
                    }
                }
    }
    qsort(b->cand, nc, sizeof *b->cand, cmp_u32);
    return (int64_t)nc;
}

/* Row of receiver o (the t-th, stamp t + 1) into the thread's output:
 * every source with a non-zero correction, or only the wanted ones (want,
 * ascending). Returns its length, or −1 when out of memory. The entries a
 * restricted row holds have the bits of the full row's: each sums the same
 * triangles (all candidates incident to it) in the same order. */
static int64_t receiver_row(const sss_mesh *m, double s, const sss_dipole *dip, const rdpoly *tab, uint32_t C,
                            hat_scales sc, double radius_mm, const trigrid *g, uint32_t o, uint32_t stamp,
                            const uint32_t *want, uint32_t nwant, const uint32_t *vt_start, const uint32_t *vt_tri,
                            tbuf *b)
{
    const double kap = SSS_HAT_KAPPA;
    const size_t W = (size_t)C + 1;
    double xo[3];
    for (int x = 0; x < 3; x++) xo[x] = (double)m->pos[3 * (size_t)o + x] * s;
    const int64_t nc = candidates(g, xo, want, nwant, vt_start, vt_tri, b);
    if (nc < 0) return -1;
    size_t nt = 0;
#define TOUCH(v)                                                                                     \
    do {                                                                                             \
        if (b->stamp[v] != stamp) {                                                                  \
            b->stamp[v] = stamp;                                                                     \
            for (size_t k_ = 0; k_ < W; k_++) b->acc[(size_t)(v) * W + k_] = 0.0;                   \
            if (!grow((void **)&b->touched, &b->capt, nt + 1, sizeof *b->touched)) return -1;       \
            b->touched[nt++] = (v);                                                                  \
        }                                                                                            \
    } while (0)
    TOUCH(o); /* the receiver itself: its point weight is the self-term disk */
    for (int64_t a = 0; a < nc; a++) {
        const uint32_t t = b->cand[a];
        if (!(g->h[t] > 0.0)) continue;
        double p[3][3];
        tri_mm(m, s, t, p);
        const double h = g->h[t], dist = point_triangle_distance(xo, p[0], p[1], p[2]);
        if (!(dist < h / kap)) continue;
        const int close = h > kap * fmax(dist, sc.zmin);
        double Q[3 * SSS_MAX_CHANNELS];
        if (close) hat_triangle(tab, C, sc, (const double(*)[3])p, xo, Q);
        for (int k = 0; k < 3; k++) {
            const uint32_t v = m->tri[3 * (size_t)t + k];
            TOUCH(v);
            if (!close) continue;
            double *ac = &b->acc[(size_t)v * W];
            for (uint32_t c = 0; c < C; c++) ac[c] += Q[k * C + c];
            ac[C] += g->area[t] / 3.0;
        }
    }
#undef TOUCH
    qsort(b->touched, nt, sizeof *b->touched, cmp_u32);

    /* coincident copies of x_o share one self-term disk (nbhd.c): their
     * area, in increasing index order */
    const float *po = m->pos + 3 * (size_t)o;
    double garea = 0.0;
    for (size_t a = 0; a < nt; a++) {
        const float *pi = m->pos + 3 * (size_t)b->touched[a];
        if (pi[0] == po[0] && pi[1] == po[1] && pi[2] == po[2]) garea += m->area[b->touched[a]];
    }
    const double r2max = radius_mm * radius_mm;
    const size_t start = b->n;
    uint32_t wa = 0;
    for (size_t a = 0; a < nt; a++) {
        const uint32_t i = b->touched[a];
        if (want) { /* the wanted entries only */
            while (wa < nwant && want[wa] < i) wa++;
            if (wa == nwant || want[wa] != i) continue;
        }
        const double *ac = &b->acc[(size_t)i * W];
        /* distance and point weight exactly as nbhd.c computes them */
        const float *pi = m->pos + 3 * (size_t)i;
        double d2 = 0.0;
        for (int x = 0; x < 3; x++) {
            const double dx = ((double)pi[x] - po[x]) * s;
            d2 += dx * dx;
        }
        const double r = sqrt(d2), dA = m->area[i] * s * s;
        const int same = i == o || (pi[0] == po[0] && pi[1] == po[1] && pi[2] == po[2]);
        const int inside = d2 <= r2max || i == o;
        double cw[SSS_MAX_CHANNELS];
        int nonzero = 0;
        for (uint32_t c = 0; c < C; c++) {
            double cur; /* nbhd.c's weight */
            if (same) {
                const double share = garea > 0.0 ? m->area[i] / garea : 0.0;
                cur = garea > 0.0 ? sss_rd_disk(&dip[c], sqrt(garea * s * s / SSS_PI)) / SSS_PI * share : 0.0;
            } else {
                cur = inside ? sss_point_weight(&dip[c], r, dA) : 0.0;
            }
            /* W: the close triangles integrated, the rest by the vertex rule
             * (none beyond the cutoff, as the point rule) */
            const double pointw = sss_rd(&dip[c], r) / SSS_PI;
            const double rest = inside ? pointw * dA - cur : -cur;
            cw[c] = (ac[c] - (inside ? pointw * ac[C] : 0.0)) + rest;
            if ((float)cw[c] != 0.0f) nonzero = 1;
        }
        if (!nonzero) continue;
        if (!grow((void **)&b->idx, &b->cap, b->n + 1, sizeof *b->idx) ||
            !grow((void **)&b->w, &b->capw, (b->n + 1) * C, sizeof *b->w))
            return -1;
        b->idx[b->n] = i;
        for (uint32_t c = 0; c < C; c++) b->w[b->n * C + c] = (float)cw[c];
        b->n++;
    }
    return (int64_t)(b->n - start);
}

/* Both forms: every row (sel NULL) or the entries sel names. */
static sss_result corrections(const sss_mesh *mesh, double s, const sss_dipole *dip, uint32_t C, double radius_mm,
                              const uint32_t *targets, uint32_t ntargets, const sss_weights *sel,
                              const sss_cancel_flag *cancel, sss_weights *out, sss_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    if (!mesh || !mesh->area || !dip || !out || C < 1 || C > SSS_MAX_CHANNELS || !(s > 0.0) || !isfinite(s) ||
        !(radius_mm >= 0.0) || (sel && sel->nrows != (targets ? ntargets : mesh->nv)))
        return sss_fail(err, SSS_ERR_ARG, "hat weights: invalid arguments");
    const uint32_t nt = targets ? ntargets : mesh->nv, nv = mesh->nv;
    for (uint32_t t = 0; targets && t < nt; t++)
        if (targets[t] >= nv) return sss_fail(err, SSS_ERR_ARG, "hat weights: target vertex %u out of range", targets[t]);
    trigrid g;
    uint32_t *vt_start = NULL, *vt_tri = NULL, *want = NULL;
    if (!trigrid_build(mesh, s, &g)) {
        trigrid_free(&g);
        return sss_fail(err, SSS_ERR_NOMEM, "hat weights: out of memory for %u triangles", mesh->nf);
    }
    int failed = 0;
    if (sel) { /* each vertex's triangles: the candidates of a restricted row */
        vt_start = calloc((size_t)nv + 1, sizeof *vt_start);
        vt_tri = malloc((size_t)mesh->nf * 3 * sizeof *vt_tri + 1);
        if (!vt_start || !vt_tri) failed = 1;
        else {
            for (size_t k = 0; k < 3 * (size_t)mesh->nf; k++) vt_start[mesh->tri[k] + 1]++;
            for (uint32_t v = 0; v < nv; v++) vt_start[v + 1] += vt_start[v];
            uint32_t *fill = malloc((size_t)nv * sizeof *fill + 1);
            if (!fill) failed = 1;
            else {
                memcpy(fill, vt_start, (size_t)nv * sizeof *fill);
                for (size_t k = 0; k < 3 * (size_t)mesh->nf; k++) vt_tri[fill[mesh->tri[k]]++] = (uint32_t)(k / 3);
                free(fill);
            }
        }
    }
    const hat_scales sc = scales_of(dip, C);
    /* the tables reach the farthest point of a candidate triangle:
     * distance below h / κ, plus h */
    double hmax = 0.0;
    for (uint32_t t = 0; t < mesh->nf; t++) hmax = fmax(hmax, g.h[t]);
    rdpoly tab[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < C; c++) {
        const double reach = hmax * (1.0 / SSS_HAT_KAPPA + 1.0);
        rdpoly_init(&tab[c], &dip[c], rdpoly_reach2(&dip[c], reach * reach) + 1e-300);
    }
#ifdef _OPENMP
    const int nth = omp_get_max_threads();
#else
    const int nth = 1;
#endif
    tbuf *bufs = calloc((size_t)nth, sizeof *bufs);
    uint32_t *owner = malloc((size_t)nt * sizeof *owner + 1);
    uint64_t *at = malloc((size_t)nt * sizeof *at + 1), *len = malloc((size_t)nt * sizeof *len + 1);
    out->start = calloc((size_t)nt + 1, sizeof *out->start);
    failed |= !bufs || !owner || !at || !len || !out->start;
    if (!failed) {
#ifdef _OPENMP
#pragma omp parallel num_threads(nth)
#endif
        {
#ifdef _OPENMP
            const int th = omp_get_thread_num();
#else
            const int th = 0;
#endif
            tbuf *b = &bufs[th];
            b->stamp = calloc((size_t)nv, sizeof *b->stamp);
            b->acc = malloc((size_t)nv * (C + 1) * sizeof *b->acc + 1);
            uint32_t *wl = NULL;
            size_t capwl = 0;
            if (!b->stamp || !b->acc) b->failed = 1;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 64)
#endif
            for (int64_t t = 0; t < (int64_t)nt; t++) {
                if (b->failed || sss_cancelled(cancel)) continue;
                const uint32_t o = targets ? targets[t] : (uint32_t)t;
                const size_t begin = b->n;
                uint32_t nw = 0;
                if (sel) { /* the wanted sources, ascending */
                    nw = (uint32_t)(sel->start[t + 1] - sel->start[t]);
                    if (!grow((void **)&wl, &capwl, (size_t)nw + 1, sizeof *wl)) {
                        b->failed = 1;
                        continue;
                    }
                    memcpy(wl, sel->idx + sel->start[t], (size_t)nw * sizeof *wl);
                    qsort(wl, nw, sizeof *wl, cmp_u32);
                }
                const int64_t n = receiver_row(mesh, s, dip, tab, C, sc, radius_mm, &g, o, (uint32_t)t + 1,
                                               sel ? wl : NULL, nw, vt_start, vt_tri, b);
                if (n < 0) {
                    b->failed = 1;
                    continue;
                }
                owner[t] = (uint32_t)th;
                at[t] = begin;
                len[t] = (uint64_t)n;
            }
            free(wl);
        }
        for (int th = 0; th < nth; th++) failed |= bufs[th].failed;
    }
    if (!failed && !sss_cancelled(cancel)) {
        for (uint32_t t = 0; t < nt; t++) out->start[t + 1] = out->start[t] + len[t];
        const uint64_t total = out->start[nt];
        out->idx = malloc((size_t)total * sizeof *out->idx + 1);
        out->w = malloc((size_t)total * C * sizeof *out->w + 1);
        if (!out->idx || !out->w) failed = 1;
        else
            for (uint32_t t = 0; t < nt; t++) {
                const tbuf *b = &bufs[owner[t]];
                memcpy(out->idx + out->start[t], b->idx + at[t], (size_t)len[t] * sizeof *out->idx);
                memcpy(out->w + out->start[t] * C, b->w + at[t] * C, (size_t)len[t] * C * sizeof *out->w);
            }
    }
    for (int th = 0; bufs && th < nth; th++) {
        free(bufs[th].cand);
        free(bufs[th].stamp);
        free(bufs[th].acc);
        free(bufs[th].touched);
        free(bufs[th].idx);
        free(bufs[th].w);
    }
    free(bufs);
    free(owner);
    free(at);
    free(len);
    free(vt_start);
    free(vt_tri);
    free(want);
    trigrid_free(&g);
    if (sss_cancelled(cancel)) {
        sss_weights_free(out);
        return sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted during the hat weights");
    }
    if (failed) {
        sss_weights_free(out);
        return sss_fail(err, SSS_ERR_NOMEM, "hat weights: out of memory for %u receivers", nt);
    }
    out->nrows = nt;
    out->channels = C;
    return SSS_OK;
}

sss_result sss_hat_corrections(const sss_mesh *mesh, double s, const sss_dipole *dip, uint32_t C, double radius_mm,
                               const uint32_t *targets, uint32_t ntargets, const sss_cancel_flag *cancel,
                               sss_weights *out, sss_error *err)
{
    return corrections(mesh, s, dip, C, radius_mm, targets, ntargets, NULL, cancel, out, err);
}

sss_result sss_hat_corrections_of(const sss_mesh *mesh, double s, const sss_dipole *dip, uint32_t C, double radius_mm,
                                  const sss_weights *sel, const sss_cancel_flag *cancel, sss_weights *out,
                                  sss_error *err)
{
    if (!sel || sel->nrows != (mesh ? mesh->nv : 0))
        return sss_fail(err, SSS_ERR_ARG, "hat weights: the selection must have a row per vertex");
    return corrections(mesh, s, dip, C, radius_mm, NULL, 0, sel, cancel, out, err);
}
