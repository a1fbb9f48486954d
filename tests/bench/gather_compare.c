/* gather_compare: the hierarchical gather (sss/gather.h) against the direct
 * sum (nbhd.c + sss_integrate) on one mesh, for several θ (docs/benchmarks.md, "Bake at scale").
 *
 *   gather_compare MESH MATERIAL MM_PER_UNIT DIRS "THETAS" [STRIDE [grey]]
 *
 * The direct sum runs on every STRIDE-th vertex only (default 1: all), so
 * that meshes whose full direct bake would take hours can still be checked
 * and their direct time estimated: t_direct_est = t(subset) × nv / subset
 * (neighbourhood search + weights + integrals scale with the receivers).
 * `grey` bakes one channel with the preset's green coefficients.
 * Prints one JSON line per θ: per-vertex relative RMS error
 * ‖q_tree − q_direct‖ / ‖q_direct‖ over directions and channels, its RMS
 * and maximum over the subset, and the timings.
 */
#define _POSIX_C_SOURCE 200809L /* strdup */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/nbhd.h"
#include "sss/visibility.h"
#include "sss/transfer.h"
#include "sss/dirset.h"
#include "sss/gather.h"
#include "sss/import.h"

double sss_now(void);

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: gather_compare MESH MATERIAL MM_PER_UNIT DIRS \"THETAS\" [STRIDE [grey]]\n");
        return 2;
    }
    const char *path = argv[1];
    const double s = atof(argv[3]);
    const uint32_t D = (uint32_t)atoi(argv[4]);
    const uint32_t stride = argc > 6 ? (uint32_t)atoi(argv[6]) : 1;
    const int grey = argc > 7 && !strcmp(argv[7], "grey");
    sss_error err = {{0}};
    sss_material mat;
    if (sss_material_preset(argv[2], &mat, &err) != SSS_OK) { fprintf(stderr, "%s\n", err.msg); return 1; }
    if (grey)
        for (int c = 0; c < 3; c++) { mat.sigma_a[c] = mat.sigma_a[1]; mat.sigmap_s[c] = mat.sigmap_s[1]; }
    const uint32_t C = grey ? 1 : 3;
    sss_mesh mesh;
    if (sss_import_mesh(path, &mesh, NULL, &err) != SSS_OK ||
        sss_mesh_compute_normals_areas(&mesh, path, &err) != SSS_OK) {
        fprintf(stderr, "gather_compare: %s\n", err.msg);
        return 1;
    }
    const uint32_t nv = mesh.nv;
    sss_dipole dip[3];
    double lo[3], hi[3], R = 0;
    const double diag = sss_mesh_bounds(&mesh, lo, hi) * s;
    for (uint32_t c = 0; c < C; c++) {
        sss_dipole_init(&dip[c], mat.sigma_a[c], mat.sigmap_s[c], mat.eta);
        R = fmax(R, sss_rd_radius(&dip[c], 1e-3, diag));
    }
    sss_dirset ds;
    if (sss_dirset_fibonacci(&ds, D, &err) != SSS_OK) return 1;
    float *G = malloc((size_t)nv * D * sizeof(float));
    sss_vis *vis;
    double t = sss_now();
    if (!G || sss_vis_create(&mesh, &vis, &err) != SSS_OK ||
        sss_transfer_compute(&mesh, vis, ds.dir, D, mat.eta, NULL, G, NULL, NULL, &err) != SSS_OK) {
        fprintf(stderr, "gather_compare: %s\n", err.msg);
        return 1;
    }
    sss_vis_destroy(vis);
    const double t_vis = sss_now() - t;

    /* direct sum on the subset */
    uint32_t ns = (nv + stride - 1) / stride;
    uint32_t *sub = malloc((size_t)ns * sizeof *sub);
    for (uint32_t k = 0; k < ns; k++) sub[k] = k * stride;
    sss_weights nb;
    t = sss_now();
    if (sss_nbhd_build(&mesh, s, dip, C, R, sub, ns, 0, NULL, &nb, &err) != SSS_OK) {
        fprintf(stderr, "gather_compare: %s\n", err.msg);
        return 1;
    }
    const double t_nb = sss_now() - t;
    float *qd = malloc((size_t)ns * D * C * sizeof(float));
    t = sss_now();
    sss_integrate(&nb, G, D, qd);
    const double t_int = sss_now() - t;
    const double mean_nb = (double)nb.start[ns] / ns;
    sss_weights_free(&nb);

    float *qt = malloc((size_t)nv * D * C * sizeof(float));
    char *th = strdup(argv[5]);
    for (char *tok = strtok(th, " ,"); tok; tok = strtok(NULL, " ,")) {
        /* tuning knobs of the bench only: leaf and block sizes */
        sss_gather_params p = {.theta = atof(tok),
                               .leaf_size = getenv("SSS_GATHER_LEAF") ? (uint32_t)atoi(getenv("SSS_GATHER_LEAF")) : 0,
                               .block_size = getenv("SSS_GATHER_BLOCK") ? (uint32_t)atoi(getenv("SSS_GATHER_BLOCK")) : 0};
        sss_gather_tree *tree;
        t = sss_now();
        if (sss_gather_tree_build(&mesh, s, G, D, &p, &tree, &err) != SSS_OK) { fprintf(stderr, "%s\n", err.msg); return 1; }
        const double t_tree = sss_now() - t;
        sss_gather_stats gs;
        t = sss_now();
        if (sss_gather_run(tree, &mesh, dip, C, R, 0, sss_gather_tree_blocks(tree), qt, 1, &gs, &err) != SSS_OK) {
            fprintf(stderr, "%s\n", err.msg);
            return 1;
        }
        const double t_gather = sss_now() - t;
        double e2sum = 0, emax = 0, num = 0, den = 0;
        uint32_t vmax = 0;
        for (uint32_t k = 0; k < ns; k++) {
            double a = 0, b = 0;
            for (uint32_t j = 0; j < D; j++)
                for (uint32_t c = 0; c < C; c++) {
                    const double x = qd[((size_t)j * ns + k) * C + c], y = qt[((size_t)j * nv + sub[k]) * C + c];
                    a += (y - x) * (y - x);
                    b += x * x;
                }
            const double e = b > 0 ? sqrt(a / b) : 0;
            e2sum += e * e;
            if (e > emax) { emax = e; vmax = sub[k]; }
            num += a;
            den += b;
        }
        printf("{\"mesh\":\"%s\",\"vertices\":%u,\"channels\":%u,\"dirs\":%u,\"mm_per_unit\":%g,\"radius_mm\":%.3f,"
               "\"theta\":%g,\"subset\":%u,\"neighbours_mean\":%.1f,\"rel_rms_per_vertex\":%.3e,\"rel_max\":%.3e,"
               "\"rel_max_vertex\":%u,\"rel_global\":%.3e,\"t_visibility\":%.3f,\"t_direct_subset\":%.3f,"
               "\"t_direct_est\":%.3f,\"t_tree\":%.3f,\"t_gather\":%.3f,\"rows_per_block\":%.0f,\"near_per_recv\":%.1f,"
               "\"far_per_recv\":%.1f,\"sgemm_gflops\":%.1f,\"thread_s\":{\"lists\":%.2f,\"weights\":%.2f,\"sgemm\":%.2f,"
               "\"scatter\":%.2f},\"nodes\":%u,\"blocks\":%u}\n",
               path, nv, C, D, s, R, p.theta, ns, mean_nb, sqrt(e2sum / ns), emax, vmax, sqrt(num / den), t_vis,
               t_nb + t_int, (t_nb + t_int) * nv / ns, t_tree, t_gather, gs.rows_mean, (double)gs.near_pairs / nv,
               (double)gs.far_pairs / nv, gs.t_sgemm > 0 ? gs.flops / gs.t_sgemm * 1e-9 : 0, gs.t_lists, gs.t_weights,
               gs.t_sgemm, gs.t_scatter, gs.nodes, gs.blocks);
        fflush(stdout);
        sss_gather_tree_destroy(tree);
    }
    free(th);
    free(qt);
    free(qd);
    free(sub);
    free(G);
    sss_dirset_free(&ds);
    sss_mesh_free(&mesh);
    return 0;
}
