/* error_sources: where the direction-interpolation error of a float bake
 * comes from (docs/accuracy_4000.md "Where the error comes from").
 *
 *   error_sources FILE.sss [NDIRS [SEED]]
 *
 * q(x_o, ω) = Σ_i w(o, i) F_t(n_i·ω) max(0, n_i·ω) V(x_i, ω) (Hao–Varshney
 * 2004 §3.1) has three kinds of feature in ω that linear interpolation
 * between direction samples (§3.2) cannot follow: the smooth curvature of
 * the lit lobe, the kink where a source turns away (n_i·ω = 0, the
 * terminator), and the steps where a source's visibility V flips (cast
 * shadows). This tool separates them, at NDIRS random light directions
 * (default 100) that miss every sample, with the per-vertex, area-weighted
 * relative RMS of sss/vertex_error.h:
 *
 *  - rows "shadows": the file's own rows against the exact evaluator;
 *  - rows "no shadows": the same physics with V ≡ 1 (sss_exact_set_shadows),
 *    its sample rows recomputed at the file's directions: only the lobe and
 *    the terminator are left;
 *
 * each reconstructed three ways from the same three samples of the
 * spherical Delaunay triangle (sss_dirset_lookup):
 *
 *  - "triangle": the shipped weights, λ_k = det(ω, ω_{k+1}, ω_{k+2}) /
 *    det(ω_a, ω_b, ω_c) normalised to Σλ = 1 (constants exact);
 *  - "linear": the same λ not normalised, so that Σ λ_k ω_k = ω and every
 *    function linear in ω is reproduced exactly. Without kinks and with F_t
 *    constant q is such a function (Σ_i w F_t V n_i is a fixed vector), so
 *    this is the natural weight for the lit lobe;
 *  - "terminator": linear weights applied to q / s with
 *    s(ω) = max(0, n_o·ω) + δ (δ = 0.05, n_o the vertex normal), the result
 *    multiplied by s(ω): the vertex's own kink is divided out before
 *    interpolating and put back after.
 *
 * For the shadowed rows it also splits the squared error of "triangle" by
 * the vertex's own state over the four directions {ω, ω_a, ω_b, ω_c}:
 * steady (same facing and visibility at all four), terminator (n_o·ω
 * changes sign) or shadow edge (facing throughout, own V changes). The
 * neighbours' shadows land in "steady" too, so this split is a lower
 * bound on the share of cast shadows.
 *
 * Prints one JSON object. Float files only (no quantisation error mixed in).
 */
#define _DEFAULT_SOURCE /* M_PI */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/vertex_error.h"
#include "sss/nearterms.h"
#include "sss/visibility.h"
#include "sss/exact.h"
#include "sss/format.h"

enum { SCHEMES = 6, CLASSES = 3, NEAR = 3 };
static const char *scheme_name[SCHEMES] = {"triangle", "linear", "terminator", "own", "own_ring1", "own_ring2"};
static const char *class_name[CLASSES] = {"steady", "terminator", "shadow_edge"};
#define DELTA 0.05

static double det3(const double *a, const double *b, const double *c)
{
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

static double dotn(const float *n, const double *d) { return n[0] * d[0] + n[1] * d[1] + n[2] * d[2]; }

/* The near terms at rings 0, 1, 2 (sss/nearterms.h) and the vertices' own
 * visibility by rays under the bake's rule. */
static sss_weights g_near[NEAR];

static void transfer_all(const sss_bake_file *f, const sss_vis *vis, const double *d, uint8_t *lit, float *gv)
{
    sss_vis_lit_all(vis, &f->mesh, d, lit);
    sss_near_transfer(f->mesh.nrm, f->mesh.nv, (float)f->material.eta, d, lit, gv);
}

typedef struct {
    double se[SCHEMES], sx; /* Σ A (r − x)² per scheme, Σ A x² */
    double cls_se[CLASSES], cls_area[CLASSES], area;
} tally;

/* One light direction d: reconstruct from rows (D × nv × C) and compare
 * with the exact x; vis, when given, classifies for the split. */
static float *g_gv[4];  /* transfer_all at ω_a, ω_b, ω_c, ω */
static uint8_t *g_lit;

static void measure(const sss_bake_file *f, const float *rows, const float *x, const double *area, const double d[3],
                    const sss_vis *vis, tally *t)
{
    const uint32_t nv = f->mesh.nv, C = f->channels;
    uint32_t idx[3];
    double w[3], lam[3];
    sss_dirset_lookup(&f->dirs, d, idx, w);
    const double *A = f->dirs.dir + 3 * (size_t)idx[0], *B = f->dirs.dir + 3 * (size_t)idx[1],
                 *Cd = f->dirs.dir + 3 * (size_t)idx[2];
    const double det = det3(A, B, Cd);
    lam[0] = det3(d, B, Cd) / det, lam[1] = det3(A, d, Cd) / det, lam[2] = det3(A, B, d) / det;
    for (int k = 0; k < 3; k++)
        if (w[k] == 0.0) lam[k] = 0.0; /* on an edge or at a sample, as the shipped weights */
    const double *smp[3] = {A, B, Cd};
    if (vis) {
        for (int k = 0; k < 3; k++) transfer_all(f, vis, smp[k], g_lit, g_gv[k]);
        transfer_all(f, vis, d, g_lit, g_gv[3]);
    }
    for (uint32_t v = 0; v < nv; v++) {
        const float *n = f->mesh.nrm + 3 * (size_t)v;
        double s[3], sd = fmax(0.0, dotn(n, d)) + DELTA;
        for (int k = 0; k < 3; k++) s[k] = fmax(0.0, dotn(n, smp[k])) + DELTA;
        int cls = 0;
        if (vis) {
            int face = dotn(n, d) > 0.0, occ = face && sss_vis_occluded(vis, v, d);
            for (int k = 0; k < 3 && cls != 1; k++) {
                if (w[k] == 0.0) continue;
                int fk = dotn(n, smp[k]) > 0.0, ok = fk && sss_vis_occluded(vis, v, smp[k]);
                if (fk != face) cls = 1;
                else if (ok != occ) cls = 2;
            }
            t->cls_area[cls] += area[v];
            t->area += area[v];
        }
        for (uint32_t c = 0; c < C; c++) {
            const size_t i = (size_t)v * C + c, row = (size_t)nv * C;
            const double qa = rows[idx[0] * row + i], qb = rows[idx[1] * row + i], qc = rows[idx[2] * row + i];
            /* near terms exact at ω, taken out of the samples before the
             * shipped (normalised) interpolation */
            double nearc[NEAR] = {0, 0, 0};
            if (vis)
                for (int k = 0; k < NEAR; k++) {
                    float sk[4][3];
                    for (int m = 0; m < 4; m++) sss_near_sum(&g_near[k], v, g_gv[m], sk[m]);
                    nearc[k] = sk[3][c] - (w[0] * sk[0][c] + w[1] * sk[1][c] + w[2] * sk[2][c]);
                }
            const double tri = w[0] * qa + w[1] * qb + w[2] * qc;
            const double r[SCHEMES] = {tri, lam[0] * qa + lam[1] * qb + lam[2] * qc,
                                       sd * (lam[0] * qa / s[0] + lam[1] * qb / s[1] + lam[2] * qc / s[2]),
                                       tri + nearc[0], tri + nearc[1], tri + nearc[2]};
            const double xv = x[i];
            for (int m = 0; m < SCHEMES; m++) t->se[m] += area[v] * (r[m] - xv) * (r[m] - xv);
            t->sx += area[v] * xv * xv;
            if (vis) t->cls_se[cls] += area[v] * (r[0] - xv) * (r[0] - xv);
        }
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: error_sources FILE.sss [NDIRS [SEED]]\n");
        return 2;
    }
    const uint32_t ndirs = argc > 2 ? (uint32_t)atoi(argv[2]) : 100;
    const uint64_t seed = argc > 3 ? strtoull(argv[3], NULL, 10) : 1;
    sss_error err = {{0}};
    sss_bake_file f;
    if (sss_file_read(argv[1], &f, &err) != SSS_OK) {
        fprintf(stderr, "error_sources: %s: %s\n", argv[1], err.msg);
        return 1;
    }
    if (f.quant != SSS_QUANT_FLOAT || f.dirs.ntri == 0 || ndirs == 0) {
        fprintf(stderr, "error_sources: %s: needs a float bake with >= 4 directions\n", argv[1]);
        return 1;
    }
    sss_exact *e = NULL;
    sss_vis *vis = NULL;
    if (sss_exact_create(&f, &e, &err) != SSS_OK || sss_vis_create(&f.mesh, &vis, &err) != SSS_OK) {
        fprintf(stderr, "error_sources: %s: %s\n", argv[1], err.msg);
        return 1;
    }
    const uint32_t nv = f.mesh.nv, C = f.channels, D = f.dirs.n;
    const size_t row = (size_t)nv * C;
    double *area = calloc(nv, sizeof *area);
    float *x = malloc(row * sizeof *x), *rows_ns = malloc((size_t)D * row * sizeof *rows_ns);
    if (!area || !x || !rows_ns) {
        fprintf(stderr, "error_sources: out of memory\n");
        return 1;
    }
    sss_mesh_vertex_areas(&f.mesh, area);
    for (int k = 0; k < 4; k++)
        if (!(g_gv[k] = malloc(nv * sizeof(float)))) return 1;
    if (!(g_lit = malloc(nv))) return 1;
    for (int k = 0; k < NEAR; k++)
        if (sss_near_build(&f.mesh, &f.material, f.mm_per_unit, C, (uint32_t)k, &g_near[k], &err) != SSS_OK) {
            fprintf(stderr, "error_sources: %s: %s\n", argv[1], err.msg);
            return 1;
        }
    /* the no-shadow physics at the file's own direction samples */
    sss_exact_set_shadows(e, 0);
    for (uint32_t j = 0; j < D; j++) sss_exact_eval(e, f.dirs.dir + 3 * (size_t)j, rows_ns + j * row);

    tally ts, tn;
    memset(&ts, 0, sizeof ts);
    memset(&tn, 0, sizeof tn);
    uint64_t state = seed;
    for (uint32_t t = 0; t < ndirs; t++) {
        double d[3];
        sss_vertex_error_draw_direction(&f.dirs, &state, d);
        sss_exact_set_shadows(e, 1);
        sss_exact_eval(e, d, x);
        measure(&f, f.q, x, area, d, vis, &ts);
        sss_exact_set_shadows(e, 0);
        sss_exact_eval(e, d, x);
        measure(&f, rows_ns, x, area, d, NULL, &tn);
    }
    printf("{\"file\":\"%s\",\"vertices\":%u,\"directions\":%u,\"random_directions\":%u,\"delta\":%g", argv[1], nv, D,
           ndirs, DELTA);
    const tally *tt[2] = {&ts, &tn};
    const char *tname[2] = {"shadows", "no_shadows"};
    for (int k = 0; k < 2; k++) {
        printf(",\"%s\":{", tname[k]);
        for (int m = 0; m < SCHEMES; m++)
            printf("%s\"%s\":%.6g", m ? "," : "", scheme_name[m], sqrt(tt[k]->se[m] / tt[k]->sx));
        printf("}");
    }
    printf(",\"split\":{");
    for (int c = 0; c < CLASSES; c++)
        printf("%s\"%s\":{\"area_share\":%.4f,\"error_share\":%.4f}", c ? "," : "", class_name[c],
               ts.cls_area[c] / ts.area, ts.cls_se[c] / ts.se[0]);
    printf("}}\n");
    free(area);
    free(x);
    free(rows_ns);
    sss_vis_destroy(vis);
    sss_exact_destroy(e);
    sss_file_free(&f);
    return 0;
}
