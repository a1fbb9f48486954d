#define _POSIX_C_SOURCE 200809L
/* The run-time near terms (format 1.3, section OWNT; sss/nearterms.h) in the
 * renderer (runtime/src/render/: renderer.c, effects/near.c, shadow.c; common/src/bvh.c), offscreen on EGL.
 * Files baked with the own term split off (sss_bake with near_terms =
 * SSS_NEAR_TERMS_RUNTIME: what `sss-bake --own-term runtime [--rings K]`
 * writes) store q − Σ_{i in o's rings} w̃(o, i) g_i(ω_j) V(x_i, ω_j); the
 * renderer adds the sum back for the actual light with every vertex's own
 * visibility, by default from the bake's ray traced on the GPU through a
 * BVH, on request (near_visibility = SSS_NEAR_MAP) from a shadow map.
 *
 *  (a) the GPU rays' V(x_o, ω) equals the bake's rule (an Embree ray from
 *      x_o, sss_vis_occluded) on >= 99.95 % of the vertices facing the
 *      light, and the shadow map's on >= 99 %, at each of several light
 *      directions, on meshes that shadow themselves (the generated blob and
 *      torus, and the 23K Stanford dragon, visibility only); on the dragon
 *      the BVH's CPU traversal (sss_bvh_occluded, the shader's arithmetic)
 *      too;
 *  (b) at a direction sample ω_j the renderer's full q (read back, GPU and
 *      CPU paths, rays) is the plain float bake's row j to 1e-5 of the
 *      row's maximum, except at the vertices whose near row holds a vertex
 *      where (a) disagrees; between samples, and for lloyd8 storage, the
 *      passes add exactly what the C reference (sss_near_transfer +
 *      sss_near_add with the renderer's visibility, rays or map) adds;
 *      rings 0, 1 and 2;
 *  (c) with p.near_terms = 0 an uploaded q is drawn as given, nothing added;
 *      with p.near_terms = 1 the next draw adds the near terms once;
 *  (d) a file without OWNT builds no shadow map and renders bit-identically
 *      whatever p.near_terms says.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <epoxy/gl.h>

#include "genmesh.h"
#include "sss/bake.h"
#include "sss/visibility.h"
#include "sss/decode.h"
#include "sss/import.h"
#include "sss/nearterms.h"
#include "sss/render.h"

#include "gl_fixture.h"
#include "sss/vec3.h"
#include "test_util.h"

/* Ray visibility of every vertex from d, as the bake decides it (the ray is
 * traced only where n·d > 0, sss_transfer_one); front[] marks those. */
static void ray_visibility(const sss_mesh *m, const sss_vis *vis, const double d[3], uint8_t *lit, uint8_t *front)
{
    for (uint32_t v = 0; v < m->nv; v++) {
        const float *n = &m->nrm[3 * (size_t)v];
        const double c = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        front[v] = c > 0.0;
        lit[v] = front[v] && !sss_vis_occluded(vis, v, d);
    }
}

static uint64_t rng = 0x6f776e7465726d31ull; /* "ownterm1" */


static void unit3(const double l[3], double d[3])
{
    const double n = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    for (int k = 0; k < 3; k++) d[k] = l[k] / n;
}

/* The C reference of what the renderer holds after its own-term passes
 * for light l over `base` (the rows as evaluated or uploaded): base +
 * sss_near_add(sss_near_transfer(lit)). Worst difference of got from it,
 * relative to its largest value. */
static double near_reference_diff(const sss_weights *nr, const sss_bake_file *f, const double l[3], const float *base,
                                  const uint8_t *lit, const float *got)
{
    const size_t n = (size_t)f->mesh.nv * f->channels;
    float *ref = malloc(n * sizeof *ref), *gv = malloc((size_t)f->mesh.nv * sizeof *gv);
    assert_non_null(ref);
    assert_non_null(gv);
    memcpy(ref, base, n * sizeof *ref);
    double d[3];
    unit3(l, d);
    sss_near_transfer(f->mesh.nrm, f->mesh.nv, (float)f->material.eta, d, lit, gv);
    sss_near_add(nr, gv, ref);
    double worst = 0, mx = 0;
    for (size_t i = 0; i < n; i++) mx = fmax(mx, fabs((double)ref[i]));
    for (size_t i = 0; i < n; i++) worst = fmax(worst, fabs((double)got[i] - ref[i]));
    free(ref);
    free(gv);
    return mx > 0 ? worst / mx : worst;
}

/* The renderer's V (rays or map) against Embree's on front-facing vertices:
 * "lit / shadowed" count the renderer lit where Embree's ray is blocked,
 * and the other way round. */
typedef struct agreement {
    uint64_t front, agree, sm_lit_ray_shadow, sm_shadow_ray_lit;
} agreement;

static double agree_pct(const agreement *a) { return a->front ? 100.0 * (double)a->agree / (double)a->front : 100.0; }

static void agreement_count(agreement *a, uint32_t nv, const uint8_t *front, const uint8_t *lit_map,
                            const uint8_t *lit_ray)
{
    memset(a, 0, sizeof *a);
    for (uint32_t v = 0; v < nv; v++) {
        if (!front[v]) continue;
        a->front++;
        a->agree += lit_map[v] == lit_ray[v];
        a->sm_lit_ray_shadow += lit_map[v] && !lit_ray[v];
        a->sm_shadow_ray_lit += !lit_map[v] && lit_ray[v];
    }
}

static void agreement_sum(agreement *all, const agreement *a)
{
    all->front += a->front, all->agree += a->agree;
    all->sm_lit_ray_shadow += a->sm_lit_ray_shadow, all->sm_shadow_ray_lit += a->sm_shadow_ray_lit;
}

/* (a) and (b) for a mesh: a plain float bake (the truth at the samples),
 * and its OWNT bakes with `rings` rings, float and (with_lloyd8) lloyd8. */
static void check_mesh(const sss_mesh *m, const char *material, double mm, uint32_t dirs, uint32_t rings,
                       int with_lloyd8, const char *label)
{
    sss_error err = {{0}};
    sss_bake_file src, f;
    bake_preset(m, material, 0, mm, dirs, SSS_QUANT_FLOAT, -1, &src);
    bake_preset(m, material, 0, mm, dirs, SSS_QUANT_FLOAT, (int)rings, &f);
    const uint32_t nv = f.mesh.nv, C = f.channels;
    const size_t n = (size_t)nv * C;
    sss_vis *vis;
    if (sss_vis_create(&f.mesh, &vis, &err) != SSS_OK) fail_msg("vis: %s", err.msg);
    sss_weights nr;
    assert_int_equal(sss_near_build(&f.mesh, &f.material, f.mm_per_unit, C, rings, &nr, &err), SSS_OK);
    sss_renderer *r;
    if (sss_renderer_create(&f, &r, &err) != SSS_OK) fail_msg("renderer: %s", err.msg);
    assert_true(sss_renderer_has_near_terms(r));
    float *q = malloc(n * sizeof *q), *rows = malloc(n * sizeof *rows), *gv = malloc(nv * sizeof *gv);
    uint8_t *lit_map = malloc(nv), *lit_gpu = malloc(nv), *lit_ray = malloc(nv), *front = malloc(nv);
    assert_true(q && rows && gv && lit_map && lit_gpu && lit_ray && front);
    sss_view_params p;
    sss_view_params_default(&p);
    assert_int_equal(p.near_terms, 1);

    /* direction samples (where the plain bake's row is the truth) and
     * random directions (where the C reference is) */
    agreement all = {0, 0, 0, 0}, all_map = {0, 0, 0, 0};
    double worst_sample = 0, worst_ref = 0, worst_ref_map = 0, near_share = 0, worst_ray = 100.0, worst_map = 100.0;
    uint64_t excepted = 0, clamped = 0, nsample_vals = 0;
    for (int t = 0; t < 16; t++) {
        const int on_sample = t < 8;
        const uint32_t j = on_sample ? (uint32_t)((t * 37 + 5) % (int)f.dirs.n) : 0;
        if (on_sample) memcpy(p.light, &f.dirs.dir[3 * (size_t)j], sizeof p.light);
        else test_random_dir(&rng, p.light);
        double d[3];
        unit3(p.light, d);
        ray_visibility(&f.mesh, vis, d, lit_ray, front);
        sss_decode_all(&f, d, rows);
        /* the shadow map first, so that the rays after it, at the same
         * light, show that pass 1 reruns when the visibility asked for
         * changes */
        p.near_visibility = SSS_NEAR_MAP;
        p.path = SSS_EVAL_GPU;
        sss_renderer_evaluate(r, &p);
        sss_renderer_read_q(r, q);
        sss_renderer_read_near_visibility(r, lit_map);
        agreement am;
        agreement_count(&am, nv, front, lit_map, lit_ray);
        assert_true(agree_pct(&am) >= 99.0); /* (a), map */
        agreement_sum(&all_map, &am);
        worst_map = fmin(worst_map, agree_pct(&am));
        worst_ref_map = fmax(worst_ref_map, near_reference_diff(&nr, &f, d, rows, lit_map, q));
        p.near_visibility = SSS_NEAR_RAYS;
        for (int path = 0; path < 2; path++) {
            p.path = path ? SSS_EVAL_CPU : SSS_EVAL_GPU;
            sss_renderer_evaluate(r, &p);
            sss_renderer_read_q(r, q);
            sss_renderer_read_near_visibility(r, lit_gpu);
            agreement a;
            agreement_count(&a, nv, front, lit_gpu, lit_ray);
            if (path == 0) {
                print_message("%s: light (%+.3f, %+.3f, %+.3f)%s: %llu front-facing vertices; GPU rays = Embree on "
                              "%.3f%% (lit / shadowed %llu, shadowed / lit %llu), shadow map on %.2f%% (%llu, %llu)\n",
                              label, d[0], d[1], d[2], on_sample ? " (sample)" : "", (unsigned long long)a.front,
                              agree_pct(&a), (unsigned long long)a.sm_lit_ray_shadow,
                              (unsigned long long)a.sm_shadow_ray_lit, agree_pct(&am),
                              (unsigned long long)am.sm_lit_ray_shadow, (unsigned long long)am.sm_shadow_ray_lit);
                agreement_sum(&all, &a);
                worst_ray = fmin(worst_ray, agree_pct(&a));
            }
            assert_true(agree_pct(&a) >= 99.95); /* (a), rays, both paths (the CPU path reuses pass 1) */
            worst_ref = fmax(worst_ref, near_reference_diff(&nr, &f, d, rows, lit_gpu, q));
            if (!on_sample) continue;
            /* (b): the plain bake's row j, except where a vertex of o's near
             * row has the renderer's V and the ray's disagree, and where the
             * bake clamped the rest at 0 (rounding, or weights that are not
             * the bake's) */
            const float *row = &src.q[(size_t)j * n];
            sss_near_transfer(f.mesh.nrm, nv, (float)f.material.eta, d, lit_ray, gv);
            double mx = 0, worst = 0, near = 0, tot = 0;
            for (size_t i = 0; i < n; i++) mx = fmax(mx, fabs((double)row[i]));
            for (uint32_t o = 0; o < nv; o++) {
                int skip = 0;
                for (uint32_t a2 = nr.start[o]; a2 < nr.start[o + 1]; a2++) {
                    const uint32_t i = nr.idx[a2];
                    skip |= front[i] && lit_gpu[i] != lit_ray[i];
                }
                float s[3];
                sss_near_sum(&nr, o, gv, s);
                for (uint32_t c = 0; c < C; c++) {
                    const size_t i = (size_t)o * C + c;
                    near += s[c];
                    tot += row[i];
                    const int clamp = row[i] - s[c] < 0.0f;
                    clamped += clamp && path == 0;
                    if (skip || clamp) continue;
                    worst = fmax(worst, fabs((double)q[i] - row[i]));
                    nsample_vals++;
                }
                excepted += skip && path == 0;
            }
            assert_true(mx > 0);
            worst_sample = fmax(worst_sample, worst / mx);
            if (tot > 0) near_share = fmax(near_share, near / tot);
        }
    }
    print_message("%s, %u ring(s): %u vertices x %u channels, %llu front-facing vertex-lights: GPU rays = Embree on "
                  "%.3f%% (worst light %.3f%%; lit / shadowed %llu, shadowed / lit %llu), shadow map on %.3f%% "
                  "(worst light %.2f%%; %llu, %llu); at direction samples the full q (rays, GPU and CPU paths) vs "
                  "the plain bake: worst %.3g of the row's max over %llu values (%llu vertex-lights excepted for "
                  "visibility, %llu values clamped by the bake); vs rows + sss_near_add: worst %.3g (rays), %.3g "
                  "(map); near terms up to %.1f%% of the row's sum\n",
                  label, rings, nv, C, (unsigned long long)all.front, agree_pct(&all), worst_ray,
                  (unsigned long long)all.sm_lit_ray_shadow, (unsigned long long)all.sm_shadow_ray_lit,
                  agree_pct(&all_map), worst_map, (unsigned long long)all_map.sm_lit_ray_shadow,
                  (unsigned long long)all_map.sm_shadow_ray_lit, worst_sample, (unsigned long long)nsample_vals,
                  (unsigned long long)excepted, (unsigned long long)clamped, worst_ref, worst_ref_map,
                  100.0 * near_share);
    assert_true(worst_sample <= 1e-5); /* (b) */
    assert_true(worst_ref <= 1e-6);    /* the GLSL passes are sss_near_transfer + sss_near_add */
    assert_true(worst_ref_map <= 1e-6);
    assert_true(near_share > 0.01);    /* the near terms are not negligible: the test sees them */
    assert_true(nsample_vals > 16 * n / 2); /* few exceptions */

    if (with_lloyd8) {
        /* any storage form: the passes run after the lloyd8 compute pass too */
        sss_bake_file l8;
        bake_preset(m, material, 0, mm, dirs, SSS_QUANT_LLOYD8, (int)rings, &l8);
        sss_renderer *r8;
        if (sss_renderer_create(&l8, &r8, &err) != SSS_OK) fail_msg("renderer: %s", err.msg);
        double worst8 = 0;
        for (int t = 0; t < 6; t++) {
            test_random_dir(&rng, p.light);
            p.path = t % 2 ? SSS_EVAL_CPU : SSS_EVAL_GPU;
            sss_renderer_evaluate(r8, &p);
            sss_renderer_read_q(r8, q);
            sss_renderer_read_near_visibility(r8, lit_map);
            sss_decode_all(&l8, p.light, rows);
            worst8 = fmax(worst8, near_reference_diff(&nr, &l8, p.light, rows, lit_map, q));
        }
        print_message("%s, %u ring(s), lloyd8: full q vs rows + sss_near_add: worst %.3g\n", label, rings, worst8);
        assert_true(worst8 <= 1e-6);
        sss_renderer_destroy(r8);
        sss_file_free(&l8);
    }

    sss_renderer_destroy(r);
    sss_weights_free(&nr);
    sss_vis_destroy(vis);
    sss_file_free(&f);
    sss_file_free(&src);
    free(q);
    free(rows);
    free(gv);
    free(lit_map);
    free(lit_gpu);
    free(lit_ray);
    free(front);
}

/* The blob: concave lobes that shadow each other; the bake's default
 * split (own term + 1 ring), float and lloyd8, and the own term alone. */
static void blobVisibilityMatchesRaysAndFullQMatchesBake(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 5, &err), SSS_OK);
    check_mesh(&m, "skin1", 20.0, 100, 1, 1, "blob");
    check_mesh(&m, "skin1", 20.0, 100, 0, 0, "blob");
    sss_mesh_free(&m);
}

/* A torus: its inner ring shadows itself at grazing and oblique light;
 * two rings. */
static void torusVisibilityMatchesRaysAndFullQMatchesBake(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_torus(&m, 1.0, 0.4, 96, 48, &err), SSS_OK);
    check_mesh(&m, "marble", 10.0, 60, 2, 0, "torus");
    sss_mesh_free(&m);
}

/* (a) on the 23K dragon (data/fetch.sh), the viewer's benchmark mesh, with
 * its fine scales and thin parts: visibility needs geometry only, so the
 * file is a geometry-only view with OWNT set (no rows; q uploaded as 0, the
 * near terms added by the draw). The GPU rays, the shadow map, and the
 * BVH's CPU traversal from the bake's origin, each against Embree. */
static void dragonVisibilityMatchesRays(void **state)
{
    (void)state;
    const char *path = SSS_SOURCE_DIR "/data/stanford/dragon_22998.ply";
    if (access(path, R_OK) != 0) fail_msg("%s is missing: run data/fetch.sh (scripts/test.sh does)", path);
    sss_error err = {{0}};
    sss_bake_file g;
    memset(&g, 0, sizeof g);
    if (sss_import_mesh(path, &g.mesh, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(sss_material_preset("marble", &g.material, NULL), SSS_OK);
    g.mm_per_unit = 1000.0;
    g.channels = 3;
    g.quant = SSS_QUANT_FLOAT;
    g.near_terms = SSS_NEAR_TERMS_RUNTIME;
    const uint32_t nv = g.mesh.nv;
    sss_vis *vis;
    assert_int_equal(sss_vis_create(&g.mesh, &vis, &err), SSS_OK);
    sss_bvh bvh;
    assert_int_equal(sss_bvh_build(g.mesh.pos, nv, g.mesh.tri, g.mesh.nf, &bvh, &err), SSS_OK);
    assert_int_equal(bvh.ntri, g.mesh.nf);
    assert_true(bvh.depth <= SSS_BVH_STACK);
    const float delta = sss_mesh_ray_offset(&g.mesh); /* the bake's rule */
    sss_renderer *r;
    if (sss_renderer_create(&g, &r, &err) != SSS_OK) fail_msg("renderer: %s", err.msg);
    float *zero = calloc((size_t)nv * 3, sizeof *zero);
    uint8_t *lit_map = malloc(nv), *lit_gpu = malloc(nv), *lit_cpu = malloc(nv), *lit_ray = malloc(nv),
            *front = malloc(nv);
    assert_true(zero && lit_map && lit_gpu && lit_cpu && lit_ray && front);
    sss_view_params p;
    sss_view_params_default(&p);
    assert_int_equal(p.near_visibility, SSS_NEAR_RAYS);
    agreement all = {0, 0, 0, 0}, all_map = {0, 0, 0, 0}, all_cpu = {0, 0, 0, 0};
    double worst = 100.0, worst_map = 100.0;
    for (int t = 0; t < 12; t++) {
        test_random_dir(&rng, p.light);
        ray_visibility(&g.mesh, vis, p.light, lit_ray, front);
        for (int m = 0; m < 2; m++) {
            p.near_visibility = m ? SSS_NEAR_MAP : SSS_NEAR_RAYS;
            float *rgb;
            assert_int_equal(sss_renderer_render_q_image(r, &p, zero, 16, 16, &rgb, NULL, &err), SSS_OK);
            free(rgb);
            sss_renderer_read_near_visibility(r, m ? lit_map : lit_gpu);
        }
        /* the shader's traversal on the CPU, from the bake's float origin */
        double d[3];
        unit3(p.light, d);
        const float df[3] = {(float)d[0], (float)d[1], (float)d[2]};
        for (uint32_t v = 0; v < nv; v++) {
            const float *x = &g.mesh.pos[3 * (size_t)v], *nn = &g.mesh.nrm[3 * (size_t)v];
            const float o[3] = {x[0] + delta * nn[0], x[1] + delta * nn[1], x[2] + delta * nn[2]};
            lit_cpu[v] = front[v] && !sss_bvh_occluded(&bvh, o, df, delta);
        }
        agreement a, am, ac;
        agreement_count(&a, nv, front, lit_gpu, lit_ray);
        agreement_count(&am, nv, front, lit_map, lit_ray);
        agreement_count(&ac, nv, front, lit_cpu, lit_ray);
        worst = fmin(worst, agree_pct(&a));
        worst_map = fmin(worst_map, agree_pct(&am));
        agreement_sum(&all, &a);
        agreement_sum(&all_map, &am);
        agreement_sum(&all_cpu, &ac);
        assert_true(agree_pct(&a) >= 99.95);
        assert_true(agree_pct(&ac) >= 99.95);
        assert_true(agree_pct(&am) >= 99.0);
    }
    print_message("dragon: %u vertices, %u triangles (BVH: %u nodes, depth %u), 12 lights, %llu front-facing "
                  "vertex-lights: GPU rays = Embree on %.3f%% (worst light %.3f%%; lit / shadowed %llu, shadowed / "
                  "lit %llu); BVH on the CPU on %.3f%% (%llu, %llu); shadow map on %.3f%% (worst light %.2f%%; "
                  "%llu, %llu)\n",
                  nv, g.mesh.nf, bvh.nnode, bvh.depth, (unsigned long long)all.front, agree_pct(&all), worst,
                  (unsigned long long)all.sm_lit_ray_shadow, (unsigned long long)all.sm_shadow_ray_lit,
                  agree_pct(&all_cpu), (unsigned long long)all_cpu.sm_lit_ray_shadow,
                  (unsigned long long)all_cpu.sm_shadow_ray_lit, agree_pct(&all_map), worst_map,
                  (unsigned long long)all_map.sm_lit_ray_shadow, (unsigned long long)all_map.sm_shadow_ray_lit);
    sss_renderer_destroy(r);
    sss_bvh_free(&bvh);
    sss_vis_destroy(vis);
    sss_mesh_free(&g.mesh);
    free(zero);
    free(lit_map);
    free(lit_gpu);
    free(lit_cpu);
    free(lit_ray);
    free(front);
}

/* (c): an uploaded q with p.near_terms = 0 is drawn (and read back) as
 * given; with p.near_terms = 1 the draw adds the near terms once, for the
 * draw's light. */
static void uploadedQGetsOwnTermOnlyWhenAsked(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 3, &err), SSS_OK);
    sss_bake_file f;
    bake_preset(&m, "marble", 0, 20.0, 40, SSS_QUANT_FLOAT, 1, &f);
    const uint32_t nv = f.mesh.nv, C = f.channels;
    const size_t n = (size_t)nv * C;
    sss_weights nr;
    assert_int_equal(sss_near_build(&f.mesh, &f.material, f.mm_per_unit, C, f.near_rings, &nr, &err), SSS_OK);
    float *up = malloc(n * sizeof *up), *q = malloc(n * sizeof *q), *q2 = malloc(n * sizeof *q2);
    uint8_t *lit = malloc(nv);
    assert_true(up && q && q2 && lit);
    sss_renderer *r;
    assert_int_equal(sss_renderer_create(&f, &r, &err), SSS_OK);
    for (size_t i = 0; i < n; i++) up[i] = (float)(0.01 + 0.1 * test_urand(&rng));
    sss_view_params p;
    sss_view_params_default(&p);
    p.light[0] = 0.3, p.light[1] = -0.5, p.light[2] = 0.8;

    p.near_terms = 0;
    float *rgb0, *rgb1;
    assert_int_equal(sss_renderer_render_q_image(r, &p, up, 64, 48, &rgb0, NULL, &err), SSS_OK);
    sss_renderer_read_q(r, q);
    assert_memory_equal(q, up, n * sizeof *q);
    /* a second draw still adds nothing */
    assert_int_equal(sss_renderer_bind_offscreen(r, 64, 48, &err), SSS_OK);
    sss_renderer_draw(r, &p, 64, 48);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    sss_renderer_read_q(r, q);
    assert_memory_equal(q, up, n * sizeof *q);

    /* upload alone adds nothing yet (no light known) */
    sss_renderer_upload_q(r, up);
    sss_renderer_read_q(r, q);
    assert_memory_equal(q, up, n * sizeof *q);

    p.near_terms = 1;
    assert_int_equal(sss_renderer_render_q_image(r, &p, up, 64, 48, &rgb1, NULL, &err), SSS_OK);
    sss_renderer_read_q(r, q);
    sss_renderer_read_near_visibility(r, lit);
    size_t changed = 0;
    for (size_t i = 0; i < n; i++) changed += q[i] != up[i];
    const double worst = near_reference_diff(&nr, &f, p.light, up, lit, q);
    print_message("uploaded q, own term on: %zu of %zu values changed; vs upload + sss_near_add: worst %.3g\n",
                  changed, n, worst);
    assert_true(changed > n / 10);
    assert_true(worst <= 1e-6);
    /* drawn again: added once only */
    assert_int_equal(sss_renderer_bind_offscreen(r, 64, 48, &err), SSS_OK);
    sss_renderer_draw(r, &p, 64, 48);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    sss_renderer_read_q(r, q2);
    assert_memory_equal(q, q2, n * sizeof *q);
    /* and the image changed with it */
    double diff = 0;
    for (size_t i = 0; i < (size_t)64 * 48 * 3; i++) diff += fabs((double)rgb1[i] - rgb0[i]);
    assert_true(diff > 0);

    free(rgb0);
    free(rgb1);
    sss_renderer_destroy(r);
    sss_weights_free(&nr);
    sss_file_free(&f);
    sss_mesh_free(&m);
    free(up);
    free(q);
    free(q2);
    free(lit);
}

/* (d): a file without OWNT: no shadow map, no pass; q and images are the
 * same bits whatever p.near_terms says, and q is the C decoder's (within the
 * existing renderer tolerance, counted bit-identical). */
static void fileWithoutOwnTermIsUnchanged(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 3, &err), SSS_OK);
    sss_bake_file f;
    bake_preset(&m, "skin1", 0, 20.0, 40, SSS_QUANT_FLOAT, -1, &f);
    sss_renderer *r;
    assert_int_equal(sss_renderer_create(&f, &r, &err), SSS_OK);
    assert_false(sss_renderer_has_near_terms(r));
    const size_t n = (size_t)f.mesh.nv * f.channels;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
    uint8_t *lit = malloc(f.mesh.nv);
    assert_true(a && b && c && lit);
    sss_view_params p;
    sss_view_params_default(&p);
    size_t same = 0, total = 0;
    double worst = 0;
    for (int t = 0; t < 6; t++) {
        test_random_dir(&rng, p.light);
        p.path = t % 2 ? SSS_EVAL_CPU : SSS_EVAL_GPU;
        p.near_terms = 1;
        sss_renderer_evaluate(r, &p);
        sss_renderer_read_q(r, a);
        p.near_terms = 0;
        sss_renderer_evaluate(r, &p);
        sss_renderer_read_q(r, b);
        assert_memory_equal(a, b, n * sizeof *a);
        sss_decode_all(&f, p.light, c);
        for (size_t i = 0; i < n; i++) {
            same += a[i] == c[i];
            total++;
            const double d = fabs((double)a[i] - c[i]);
            worst = fmax(worst, d < 1e-30 ? 0.0 : d / fmax(fabs((double)c[i]), 1e-30));
        }
        float *img1, *img0;
        p.near_terms = 1;
        assert_int_equal(sss_renderer_render_image(r, &p, 96, 64, &img1, NULL, &err), SSS_OK);
        p.near_terms = 0;
        assert_int_equal(sss_renderer_render_image(r, &p, 96, 64, &img0, NULL, &err), SSS_OK);
        assert_memory_equal(img1, img0, (size_t)96 * 64 * 3 * sizeof(float));
        free(img1);
        free(img0);
    }
    sss_renderer_read_near_visibility(r, lit);
    for (uint32_t v = 0; v < f.mesh.nv; v++) assert_int_equal(lit[v], 1);
    sss_frame_times ft = sss_renderer_times(r);
    assert_true(ft.near_ms == 0.0);
    print_message("no OWNT: q vs C decoder %.2f%% bit-identical, worst relative %.3g; own_term on/off identical\n",
                  100.0 * (double)same / (double)total, worst);
    assert_true(worst <= 1e-4);
    sss_renderer_destroy(r);
    sss_file_free(&f);
    sss_mesh_free(&m);
    free(a);
    free(b);
    free(c);
    free(lit);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(blobVisibilityMatchesRaysAndFullQMatchesBake),
        cmocka_unit_test(torusVisibilityMatchesRaysAndFullQMatchesBake),
        cmocka_unit_test(dragonVisibilityMatchesRays),
        cmocka_unit_test(uploadedQGetsOwnTermOnlyWhenAsked),
        cmocka_unit_test(fileWithoutOwnTermIsUnchanged),
    };
    return cmocka_run_group_tests(tests, gl_setup, gl_teardown);
}
