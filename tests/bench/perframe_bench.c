/* perframe_bench.c: the object-space per-frame path (sss/perframe.h,
 * docs/deformable.md §3 and §5) on a real mesh posed by a bend: per-stage
 * wall times of each mode per frame (t_pose: the deformer with normals and
 * areas), and the tree mode's error against
 * the exact mode on the same pose. One JSON line per mode and frame.
 *
 * usage: perframe_bench MESH MATERIAL MM_PER_UNIT FRAMES [grey] [point|hat] [tree]
 * (tree: the tree mode alone, without the exact mode and the error)
 * The bend is 40° about the mesh's longest bounding-box axis with a 4 s
 * period; frame k is taken at t = k · 0.25 s; the light is (0.3, 0.2, 0.93).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/clock.h"
#include "sss/deform.h"
#include "sss/format.h"
#include "sss/import.h"
#include "sss/perframe.h"

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: perframe_bench MESH MATERIAL MM_PER_UNIT FRAMES [grey] [point|hat] [tree]\n");
        return 2;
    }
    sss_error err = {{0}};
    sss_material mat;
    if (sss_material_preset(argv[2], &mat, &err) != SSS_OK) { fprintf(stderr, "%s\n", err.msg); return 1; }
    const double mm = atof(argv[3]);
    const int frames = atoi(argv[4]);
    uint32_t C = 3, weights = SSS_WEIGHTS_POINT;
    int tree_only = 0;
    for (int a = 5; a < argc; a++) {
        if (!strcmp(argv[a], "tree")) tree_only = 1;
        if (!strcmp(argv[a], "grey")) C = 1;
        if (!strcmp(argv[a], "hat")) weights = SSS_WEIGHTS_HAT;
    }
    sss_mesh rest;
    if (sss_import_mesh(argv[1], &rest, NULL, &err) != SSS_OK) { fprintf(stderr, "%s\n", err.msg); return 1; }
    double lo[3], hi[3];
    sss_mesh_bounds(&rest, lo, hi);
    int ax = 0;
    for (int k = 1; k < 3; k++)
        if (hi[k] - lo[k] > hi[ax] - lo[ax]) ax = k;
    sss_deform d = {.kind = SSS_DEFORM_BEND, .axis = {0, 0, 0}, .angle_deg = 40.0, .period_s = 4.0};
    d.axis[ax] = 1.0;
    const double light[3] = {0.3, 0.2, 0.93};
    float *qe = malloc((size_t)rest.nv * C * sizeof *qe), *qt = malloc((size_t)rest.nv * C * sizeof *qt);
    if (!qe || !qt) return 1;
    for (int f = 0; f < frames; f++) {
        const double t = 0.25 * f;
        sss_mesh pose;
        const double tp0 = sss_now();
        if (sss_deform_pose(&d, t, &rest, argv[1], &pose, &err) != SSS_OK) { fprintf(stderr, "%s\n", err.msg); return 1; }
        const double t_pose = sss_now() - tp0;
        for (int mode = tree_only; mode < 2; mode++) {
            sss_perframe_options o = {.mode = mode, .weights = weights};
            sss_perframe_stats st;
            if (sss_perframe_q(&pose, &mat, C, mm, light, &o, mode ? qt : qe, &st, &err) != SSS_OK) {
                fprintf(stderr, "%s\n", err.msg);
                return 1;
            }
            double emax = 0, e2 = 0, qmax = 0, q2 = 0;
            if (mode == SSS_PERFRAME_TREE && !tree_only)
                for (size_t i = 0; i < (size_t)rest.nv * C; i++) {
                    const double dd = (double)qt[i] - qe[i];
                    emax = fmax(emax, fabs(dd));
                    e2 += dd * dd;
                    qmax = fmax(qmax, fabs((double)qe[i]));
                    q2 += (double)qe[i] * qe[i];
                }
            printf("{\"mesh\":\"%s\",\"vertices\":%u,\"channels\":%u,\"weights\":\"%s\",\"mode\":\"%s\",\"t\":%.2f,"
                   "\"radius_mm\":%.4g,\"pairs\":%llu,\"rays\":%llu,\"t_neighbourhoods\":%.4f,\"t_visibility\":%.4f,"
                   "\"t_gather\":%.4f,\"t_total\":%.4f,\"t_pose\":%.4f",
                   argv[1], rest.nv, C, weights ? "hat" : "point", mode ? "tree" : "exact", t, st.radius_mm,
                   (unsigned long long)st.pairs, (unsigned long long)st.rays, st.t_neighbourhoods, st.t_visibility,
                   st.t_gather, st.t_total, t_pose);
            if (mode == SSS_PERFRAME_TREE && !tree_only)
                printf(",\"tree_max_err\":%.3g,\"tree_rms_rel\":%.3g", qmax > 0 ? emax / qmax : 0,
                       q2 > 0 ? sqrt(e2 / q2) : 0);
            printf("}\n");
            fflush(stdout);
        }
        sss_mesh_free(&pose);
    }
    free(qe);
    free(qt);
    sss_mesh_free(&rest);
    return 0;
}
