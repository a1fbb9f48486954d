/* single_entry: where single scattering's light enters, three ways, against
 * the path tracer's single scattering (sss-ref's max_order 1) at vertices of
 * generated meshes (docs/layers.md §6): seed 002's fitted planes (Eqs. 7–10),
 * the exact ray cast with the light refracted at the vertex, and the default
 * (refracted at K, with the curved entry's focusing). Seed 002's dermis
 * (σs 2, 1, 1; σa 0.6; g 0.25; η 1.3); light (0.4, 0.1, 0.9), view
 * (−0.3, 0.2, 0.93); per mesh its topmost vertex and the 4 vertices nearest
 * to 45° around it. Prints, per mesh, mesh/reference ratios averaged over
 * vertices and channels, and the largest |ratio − 1|.
 * Usage: single_entry [PATHS] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/reference.h"
#include "sss/single_mesh.h"

static void unit(double v[3])
{
    const double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++) v[k] /= l;
}

int main(int argc, char **argv)
{
    const uint64_t paths = argc > 1 ? strtoull(argv[1], NULL, 10) : 40000;
    const sss_material mat = {"dermis", {0.6, 0.6, 0.6}, {1.5, 0.75, 0.75}, 1.3, 0.25};
    double light[3] = {0.4, 0.1, 0.9}, view[3] = {-0.3, 0.2, 0.93};
    unit(light);
    unit(view);
    const struct { const char *kind; double size; unsigned res; } meshes[] = {
        {"sphere", 20.0, 4}, {"sphere", 5.0, 4}, {"sphere", 2.0, 4}, {"blob", 5.0, 4}, {"torus", 10.0, 48}};
    printf("| mesh | fitted planes: mean ratio | max dev | cast at the vertex: mean | max dev | cast at K + focusing: mean | max dev | reference se (rel.) |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < sizeof meshes / sizeof meshes[0]; i++) {
        sss_mesh m;
        sss_error err = {{0}};
        if (sss_gen_by_name(meshes[i].kind, meshes[i].res, meshes[i].size, &m, &err) != SSS_OK ||
            (!m.nrm && sss_mesh_compute_normals_areas(&m, "mesh", &err) != SSS_OK)) {
            fprintf(stderr, "single_entry: %s: %s\n", meshes[i].kind, err.msg);
            return 1;
        }
        /* the topmost vertex and the 4 nearest to 45° from +z at azimuths 0, 90, 180, 270 */
        uint32_t vs[5] = {0, 0, 0, 0, 0};
        double best[5] = {-2, -2, -2, -2, -2};
        for (uint32_t v = 0; v < m.nv; v++) {
            const float *n = &m.nrm[3 * (size_t)v];
            if (n[2] > best[0]) best[0] = n[2], vs[0] = v;
            for (int a = 0; a < 4; a++) {
                const double t[3] = {0.7071 * cos(a * 1.5708), 0.7071 * sin(a * 1.5708), 0.7071};
                const double c = n[0] * t[0] + n[1] * t[1] + n[2] * t[2];
                if (c > best[1 + a]) best[1 + a] = c, vs[1 + a] = v;
            }
        }
        sss_bvh bvh;
        sss_ref_scene *rs;
        sss_ref_medium med;
        sss_material iso = mat;
        iso.g = 0.0;
        if (sss_bvh_build(m.pos, m.nv, m.tri, m.nf, &bvh, &err) != SSS_OK ||
            sss_ref_scene_create(&m, 1.0, &rs, &err) != SSS_OK ||
            sss_ref_medium_from_material(&iso, mat.g, &med, &err) != SSS_OK) {
            fprintf(stderr, "single_entry: %s\n", err.msg);
            return 1;
        }
        double sum[3] = {0, 0, 0}, dev[3] = {0, 0, 0}, se_rel = 0;
        int cnt = 0;
        for (int j = 0; j < 5; j++) {
            const sss_ref_light l = {.kind = SSS_REF_DIRECTIONAL, .dir = {light[0], light[1], light[2]}};
            const sss_ref_query q = {vs[j], {view[0], view[1], view[2]}};
            sss_ref_options o = {0};
            o.seed = 11 + (uint64_t)j;
            o.paths = paths;
            o.max_order = 1;
            sss_ref_estimate e;
            sss_ref_stats st;
            if (sss_ref_queries(rs, &med, &l, &q, 1, &o, &e, &st, &err) != SSS_OK) {
                fprintf(stderr, "single_entry: %s\n", err.msg);
                return 1;
            }
            const sss_ss_mesh_opts opt[3] = {{.fitted_planes = 1}, {.vertex_refraction = 1}, {0}};
            for (int w = 0; w < 3; w++) {
                double out[3];
                if (sss_ss_mesh_vertex(&m, &bvh, 1.0, &mat, NULL, 3, vs[j], light, view, &opt[w], out, &err) != SSS_OK) {
                    fprintf(stderr, "single_entry: %s\n", err.msg);
                    return 1;
                }
                for (int c = 0; c < 3; c++) {
                    if (!(e.mean[c] > 0.0)) continue;
                    const double r = out[c] / e.mean[c];
                    sum[w] += r;
                    dev[w] = fmax(dev[w], fabs(r - 1.0));
                    if (w == 0) cnt++, se_rel = fmax(se_rel, e.se[c] / e.mean[c]);
                }
            }
        }
        printf("| %s %g (%u v) | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | ≤ %.4f |\n", meshes[i].kind, meshes[i].size,
               m.nv, sum[0] / cnt, dev[0], sum[1] / cnt, dev[1], sum[2] / cnt, dev[2], se_rel);
        sss_ref_scene_destroy(rs);
        sss_bvh_free(&bvh);
        sss_mesh_free(&m);
    }
    return 0;
}
