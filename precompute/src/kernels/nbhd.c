/* nbhd.c: scattering neighbourhoods N(x_o) (Hao–Varshney 2004 §3.1): every
 * vertex within the radius that captures 1−ε of the total diffuse
 * reflectance, found with a FLANN kd-tree radius search, with the dipole
 * weights precomputed per channel.
 */
#include "sss/nbhd.h"

#include <flann/flann.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "kernels/progress.h"
#include "sss/hatweights.h"
#include "sss/vec3.h"

/* A neighbour closer than its own area-disk radius ρ = sqrt(ΔA/π) (its area
 * covers the receiving point: duplicate or nearly coincident vertices) is
 * integrated over that disk (sss_rd_disk_offset) instead of point-sampled:
 * R_d(r) ΔA would weight the whole area with the profile's peak, up to
 * R_d(0) ΔA, far more than the area can hold (docs/physics.md §6). Farther
 * neighbours keep the paper's point sample (§3.1), which on a regular
 * tessellation is the second-order midpoint rule: integrating every
 * neighbour over a disk instead was measured worse on the planar-slab check
 * (tests/unit/test_bake.c), since disks of equal area neither tile the plane
 * nor match the cells. */
#define NEAR_DISKS 1.0

/* Vertices i and o at bit-identical positions. */
static int same_position(const sss_mesh *m, uint32_t i, uint32_t o)
{
    const float *a = m->pos + 3 * (size_t)i, *b = m->pos + 3 * (size_t)o;
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}


static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

sss_result sss_nbhd_build(const sss_mesh *mesh, double s, const sss_dipole *dip, uint32_t channels,
                          double radius_mm, const uint32_t *targets, uint32_t ntargets, uint64_t max_bytes,
                          const sss_cancel_flag *cancel, sss_weights *out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    if (!mesh->area || mesh->nv == 0 || channels < 1 || channels > SSS_MAX_CHANNELS || !(s > 0) ||
        !(radius_mm >= 0) || mesh->nv > (uint32_t)INT32_MAX)
        return sss_fail(err, SSS_ERR_ARG, "neighbourhoods: invalid arguments");
    uint32_t nt = targets ? ntargets : mesh->nv;
    for (uint32_t t = 0; targets && t < nt; t++)
        if (targets[t] >= mesh->nv) return sss_fail(err, SSS_ERR_ARG, "neighbourhoods: target vertex %u out of range", targets[t]);

    /* FLANN works in float; positions in mm. */
    float *pts = malloc((size_t)mesh->nv * 3 * sizeof(float));
    uint32_t *cnt = calloc((size_t)nt + 1, sizeof *cnt);
    out->start = calloc((size_t)nt + 1, sizeof(uint64_t));
    if (!pts || !cnt || !out->start) {
        free(pts); free(cnt); sss_weights_free(out);
        return sss_fail(err, SSS_ERR_NOMEM, "neighbourhoods: out of memory for %u vertices", mesh->nv);
    }
    for (size_t k = 0; k < (size_t)mesh->nv * 3; k++) pts[k] = (float)(mesh->pos[k] * s);

    struct FLANNParameters p = DEFAULT_FLANN_PARAMETERS;
    p.algorithm = FLANN_INDEX_KDTREE_SINGLE; /* exact search, deterministic build */
    p.leaf_max_size = 16;
    p.checks = FLANN_CHECKS_UNLIMITED;
    p.sorted = 0;
    p.cores = 1;
    p.log_level = FLANN_LOG_NONE;
    float speedup = 0;
    flann_index_t index = flann_build_index_float(pts, (int)mesh->nv, 3, &speedup, &p);
    if (!index) {
        free(pts); free(cnt); sss_weights_free(out);
        return sss_fail(err, SSS_ERR_NOMEM, "neighbourhoods: FLANN index build failed");
    }

    /* Search a hair wider in float, then decide membership exactly in double
     * so the set does not depend on FLANN's rounding. Two passes: the first
     * only counts, so the memory is known (and refused if too much) before
     * anything large is allocated; the second fills the rows in place. */
    const double r2 = radius_mm * radius_mm;
    const float search_r2 = (float)(r2 * (1.0 + 1e-5)) + 1e-30f;
    int failed = 0;
    /* The cancel flag (a tool's SIGINT/SIGTERM) is polled per vertex: this phase
     * took 355 s for 10^6 vertices, and a stop must not wait for it
     * (docs/robustness.md, "Interrupted bakes"). */
    for (int pass = 0; pass < 2 && !failed && !sss_cancelled(cancel); pass++) {
        if (pass == 1) {
            uint64_t total = 0;
            for (uint32_t t = 0; t < nt; t++) { out->start[t] = total; total += cnt[t]; }
            out->start[nt] = total;
            uint64_t bytes = total * (sizeof(uint32_t) + channels * sizeof(float));
            if (max_bytes && bytes > max_bytes) {
                flann_free_index_float(index, &p);
                free(pts); free(cnt); sss_weights_free(out);
                return sss_fail(err, SSS_ERR_NOMEM,
                                "neighbourhoods need %.2f GiB (%.1f neighbours per vertex within %.3g mm) but only %.2f GiB "
                                "may be used: raise --mm-per-unit or --eps",
                                bytes / 1073741824.0, (double)total / nt, radius_mm, max_bytes / 1073741824.0);
            }
            out->idx = malloc((size_t)total * sizeof(uint32_t) + 1);
            out->w = malloc((size_t)total * channels * sizeof(float) + 1);
            if (!out->idx || !out->w) { failed = 1; break; }
        }
#pragma omp parallel
        {
            int cap = 256;
            int *ind = malloc((size_t)cap * sizeof(int));
            float *dst = malloc((size_t)cap * sizeof(float));
            struct FLANNParameters pq = p;
#pragma omp for schedule(dynamic, 64)
            for (int64_t t = 0; t < (int64_t)nt; t++) {
                if (sss_cancelled(cancel)) continue; /* the rest of the loop is skipped quickly */
                if (failed || !ind || !dst) {
#pragma omp atomic write
                    failed = 1;
                    continue;
                }
                uint32_t o = targets ? targets[t] : (uint32_t)t;
                float q[3] = {pts[3 * (size_t)o], pts[3 * (size_t)o + 1], pts[3 * (size_t)o + 2]};
                int k;
                for (;;) {
                    pq.max_neighbors = cap;
                    k = flann_radius_search_float(index, q, ind, dst, cap, search_r2, &pq);
                    if (k < cap || cap >= (int)mesh->nv) break;
                    int ncap = cap > (int)mesh->nv / 2 ? (int)mesh->nv : cap * 2;
                    int *i2 = realloc(ind, (size_t)ncap * sizeof(int));
                    if (i2) ind = i2;
                    float *d2 = realloc(dst, (size_t)ncap * sizeof(float));
                    if (d2) dst = d2;
                    if (!i2 || !d2) { k = -1; break; }
                    cap = ncap;
                }
                if (k < 0) {
#pragma omp atomic write
                    failed = 1;
                    continue;
                }
                /* Keep the vertices inside the radius (always x_o itself),
                 * in increasing index order; ind is reused as scratch. */
                uint32_t m = 0;
                int self = 0;
                for (int a = 0; a < k; a++) {
                    uint32_t i = (uint32_t)ind[a];
                    if (i >= mesh->nv) continue;
                    double d2 = 0;
                    for (int c = 0; c < 3; c++) {
                        double dx = ((double)mesh->pos[3 * (size_t)i + c] - mesh->pos[3 * (size_t)o + c]) * s;
                        d2 += dx * dx;
                    }
                    if (i == o) self = 1;
                    if (d2 <= r2 || i == o) ind[m++] = (int)i;
                }
                if (!self) ind[m++] = (int)o; /* k < cap here (else all vertices, self included, were found) */
                sss_progress_tick(1);
                if (pass == 0) { cnt[t] = m; continue; }
                if (m != cnt[t]) { /* cannot happen: the search is deterministic */
#pragma omp atomic write
                    failed = 1;
                    continue;
                }
                qsort(ind, m, sizeof *ind, cmp_int);
                uint64_t base = out->start[t];
                /* Vertices at exactly x_o's position (unwelded meshes: STL
                 * soups, seams) are one patch of the surface cut into
                 * pieces: their areas form one disk around x_o, shared in
                 * proportion to area. Separate small disks, each centred on
                 * the profile's peak, would add up to several times what
                 * the combined area holds (docs/robustness.md B4). */
                double group_area = 0.0;
                for (uint32_t a = 0; a < m; a++) {
                    uint32_t i = (uint32_t)ind[a];
                    if (i == o || same_position(mesh, i, o)) group_area += mesh->area[i];
                }
                double group_disk[SSS_MAX_CHANNELS];
                for (uint32_t c = 0; c < channels; c++)
                    group_disk[c] = group_area > 0.0 ? sss_rd_disk(&dip[c], sqrt(group_area * s * s / SSS_PI)) / SSS_PI : 0.0;
                for (uint32_t a = 0; a < m; a++) {
                    uint32_t i = (uint32_t)ind[a];
                    out->idx[base + a] = i;
                    float *w = &out->w[(base + a) * channels];
                    if (i == o || same_position(mesh, i, o)) {
                        /* Self term: R_d integrated over a disk of x_o's own
                         * area (docs/physics.md §2 (a)); a point sample at
                         * r = 0 is wrong. With coincident copies, this
                         * vertex's share of their common disk. */
                        const double share = group_area > 0.0 ? mesh->area[i] / group_area : 0.0;
                        for (uint32_t c = 0; c < channels; c++) w[c] = (float)(group_disk[c] * share);
                    } else {
                        double d2 = 0;
                        for (int c = 0; c < 3; c++) {
                            double dx = ((double)mesh->pos[3 * (size_t)i + c] - mesh->pos[3 * (size_t)o + c]) * s;
                            d2 += dx * dx;
                        }
                        double r = sqrt(d2), dA = mesh->area[i] * s * s; /* mm, mm² */
                        const double rho = sqrt(dA / SSS_PI); /* radius of x_i's area as a disk */
                        if (r < NEAR_DISKS * rho) {
                            /* x_i's area covers x_o: integrate over it as a disk */
                            for (uint32_t c = 0; c < channels; c++)
                                w[c] = (float)(sss_rd_disk_offset(&dip[c], r, rho) / SSS_PI);
                        } else {
                            /* (1/π) R_d(r) ΔA(x_i): Hao–Varshney 2004 §3.1 */
                            for (uint32_t c = 0; c < channels; c++) w[c] = (float)(sss_rd(&dip[c], r) * dA / SSS_PI);
                        }
                    }
                }
            }
            free(ind);
            free(dst);
        }
    }
    flann_free_index_float(index, &p);
    free(pts);
    free(cnt);
    if (sss_cancelled(cancel)) {
        sss_weights_free(out);
        return sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted during neighbourhoods");
    }
    if (failed) {
        uint64_t total = out->start[nt];
        sss_weights_free(out);
        return sss_fail(err, SSS_ERR_NOMEM, "neighbourhoods: out of memory (%llu neighbour entries)",
                        (unsigned long long)total);
    }
    out->nrows = nt;
    out->channels = channels;
    return SSS_OK;
}

double sss_nbhd_radii(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t channels, double eps,
                      double *radius_mm)
{
    return sss_cutoff_radius_mm(mesh, mm_per_unit, dip, channels, eps, radius_mm);
}
