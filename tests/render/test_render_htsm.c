/* Seed 000's run-time path on the GPU (sss/htsm_gpu.h, runtime/shaders/
 * htsm.frag.glsl, docs/heterogeneous.md §9) against its CPU oracle
 * (sss_htsm_q): a back-lit block (20 × 20 × 10 mm) with an embedded box
 * field; every pixel the camera sees is estimated again on the CPU at the
 * GPU's own exit point from the GPU's own light-space map (read back, its
 * mips rebuilt), and must agree within a bound; an edit of the inside
 * material shows in the next frame, darkens the picture and undoes
 * exactly; strength 0 is the homogeneous pass; two lights give the sum of
 * each alone. A point light (a perspective map, §9.2) agrees with the
 * oracle as well, joins the sum, and far away along a direction converges
 * to that directional light's frame. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "gl_fixture.h"
#include "sss/htsm_gpu.h"

#define W 64
#define H 48
#define MAP 128

typedef struct block {
    sss_mesh m;
    sss_bake_file f;
    sss_renderer *r;
    sss_hetero h;
} block;

/* 2 × 2 × 1 units at 10 mm per unit, marble, with a ketchup box of half
 * extents 4 × 4 × 2 mm in the middle (its edge 1 mm wide). */
static void block_make(block *b)
{
    sss_error err = {{0}};
    memset(b, 0, sizeof *b);
    assert_int_equal(sss_gen_box(&b->m, 2.0, 2.0, 1.0, 6, 0, &err), SSS_OK);
    if (!b->m.nrm) assert_int_equal(sss_mesh_compute_normals_areas(&b->m, "mesh", &err), SSS_OK);
    bake_preset(&b->m, "marble", 0, 10.0, 6, SSS_QUANT_FLOAT, -1, &b->f);
    if (sss_renderer_create(&b->f, &b->r, &err) != SSS_OK) fail_msg("renderer: %s", err.msg);
    b->h.field.kind = SSS_FIELD_BOX;
    b->h.field.half_mm[0] = b->h.field.half_mm[1] = 4.0;
    b->h.field.half_mm[2] = 2.0;
    b->h.field.edge_mm = 1.0;
    assert_int_equal(sss_material_preset("ketchup", &b->h.inside, NULL), SSS_OK);
    b->h.xf[0] = b->h.xf[5] = b->h.xf[10] = 10.0; /* units → rest-frame mm */
}

static void block_free(block *b)
{
    sss_renderer_destroy(b->r);
    sss_file_free(&b->f);
    sss_mesh_free(&b->m);
}

/* The pass on b's renderer, MAP² map, 32³ field h (NULL: none). */
static sss_htsm_gpu *gpu_of(const block *b, const sss_hetero *h)
{
    sss_htsm_gpu *g = NULL;
    sss_error err = {{0}};
    if (sss_htsm_gpu_create(b->r, h, MAP, 5, &g, &err) != SSS_OK) fail_msg("htsm: %s", err.msg);
    return g;
}

/* Lit from behind (−z), seen from the front (+z), q alone. */
static void params(sss_view_params *p)
{
    sss_view_params_default(p);
    p->specular = 0;
    p->surface_shadow = 0;
    p->tonemap = SSS_TONEMAP_CLAMP;
    p->light[0] = 0.2, p->light[1] = 0.1, p->light[2] = -1.0;
    p->view[0] = 0.15, p->view[1] = 0.1, p->view[2] = 1.0;
    p->distance = 2.4;
}

static void view(const block *b, uint32_t n, uint32_t steps, sss_htsm_view *v)
{
    sss_htsm_view_default(v, &b->f, &b->h);
    v->n = n;
    v->steps = steps;
    v->r0_mm = 2.0;
}

/* The largest difference of the GPU's q from the oracle's over the drawn
 * pixels, relative to the largest q of the image; and the drawn pixels. */
static double oracle_error(sss_htsm_gpu *g, const sss_htsm_view *v, int *drawn)
{
    sss_htsm_map map;
    float *q = NULL, *x = NULL;
    sss_error err = {{0}};
    assert_int_equal(sss_htsm_gpu_read(g, &map, &q, &x, &err), SSS_OK);
    sss_htsm_pattern pat;
    assert_int_equal(
        sss_htsm_pattern_make(v->n, v->r0_mm, sss_htsm_texel_mm(&map, v->mat.mm_per_unit), map.levels, &pat, &err),
        SSS_OK);
    double worst = 0.0, qmax = 0.0;
    double *cpu = malloc((size_t)W * H * 3 * sizeof *cpu);
    assert_non_null(cpu);
    *drawn = 0;
    for (int i = 0; i < W * H; i++) {
        if (x[4 * i + 3] != 1.0f) continue;
        const double xo[3] = {x[4 * i], x[4 * i + 1], x[4 * i + 2]};
        sss_htsm_q(&map, sss_htsm_gpu_volume(g), &v->mat, &pat, v->steps, xo, cpu + 3 * i);
        for (int c = 0; c < 3; c++) qmax = fmax(qmax, cpu[3 * i + c]);
        (*drawn)++;
    }
    for (int i = 0; i < W * H; i++) {
        if (x[4 * i + 3] != 1.0f) continue;
        for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(q[4 * i + c] - cpu[3 * i + c]) / qmax);
    }
    assert_true(qmax > 0.0);
    free(cpu);
    free(q);
    free(x);
    sss_htsm_map_free(&map);
    return worst;
}

static double frame(sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p)
{
    sss_error err = {{0}};
    double ms = 0;
    if (sss_htsm_gpu_frame(g, v, p, W, H, &ms, &err) != SSS_OK) fail_msg("frame: %s", err.msg);
    return ms;
}

static void point_only(const block *b, const sss_view_params *p, double dist, sss_htsm_view *v);
static double radius(const block *b);

/* The GPU frame against the CPU oracle for the smallest and the largest
 * pattern, 8 steps: per pixel within 10⁻⁴ of the image's largest q (float
 * against double, the same texels, levels and steps). point_r > 0: the
 * scene's light replaced by a point light point_r bounding radii behind
 * the block. */
static void check_oracle(double point_r)
{
    block b;
    block_make(&b);
    sss_htsm_gpu *g = gpu_of(&b, &b.h);
    sss_view_params p;
    params(&p);
    const uint32_t ns[2] = {1, 13};
    for (int k = 0; k < 2; k++) {
        sss_htsm_view v;
        view(&b, ns[k], 8, &v);
        if (point_r > 0) point_only(&b, &p, point_r * radius(&b), &v);
        const double ms = frame(g, &v, &p);
        int drawn = 0;
        const double e = oracle_error(g, &v, &drawn);
        printf("%s n = %2u, 8 steps: %d pixels, GPU vs CPU %.2e of the largest q (%.1f ms)\n",
               point_r > 0 ? "point light," : "directional,", ns[k], drawn, e, ms);
        assert_true(drawn > W * H / 4);
        assert_true(e < 1e-4);
    }
    sss_htsm_gpu_destroy(g);
    block_free(&b);
}

static void perPixelAgreesWithTheCpuOracle(void **state)
{
    (void)state;
    check_oracle(0.0);
}

static double mean_q(sss_htsm_gpu *g)
{
    sss_htsm_map map;
    float *q = NULL, *x = NULL;
    sss_error err = {{0}};
    assert_int_equal(sss_htsm_gpu_read(g, &map, &q, &x, &err), SSS_OK);
    double s = 0.0;
    for (int i = 0; i < W * H; i++) s += q[4 * i] + q[4 * i + 1] + q[4 * i + 2];
    free(q);
    free(x);
    sss_htsm_map_free(&map);
    return s / (W * H);
}

/* The inside's absorption ×4 darkens the next frame; ÷4 gives the first
 * frame back bit for bit; strength 0 is the pass with no field at all. */
static void liveEditsShowAtOnceAndUndo(void **state)
{
    (void)state;
    block b;
    block_make(&b);
    sss_htsm_gpu *g = gpu_of(&b, &b.h), *g0 = gpu_of(&b, NULL);
    sss_view_params p;
    params(&p);
    sss_htsm_view v;
    view(&b, 5, 8, &v);
    frame(g, &v, &p);
    const double q1 = mean_q(g);
    for (int c = 0; c < 3; c++) v.mat.inside.sigma_a[c] *= 4.0;
    frame(g, &v, &p);
    const double q4 = mean_q(g);
    for (int c = 0; c < 3; c++) v.mat.inside.sigma_a[c] /= 4.0;
    frame(g, &v, &p);
    const double qb = mean_q(g);
    printf("mean q: %.5g, inside sigma_a x4: %.5g, back: %.5g\n", q1, q4, qb);
    assert_true(q4 < 0.95 * q1);
    assert_true(qb == q1);
    v.mat.strength = 0.0;
    frame(g, &v, &p);
    const double qs = mean_q(g);
    frame(g0, &v, &p);
    assert_true(qs == mean_q(g0));
    assert_true(qs > q1);
    sss_htsm_gpu_destroy(g0);
    sss_htsm_gpu_destroy(g);
    block_free(&b);
}

/* A frame, then its q and x_o read back (caller frees). */
static void frame_read(sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p, float **q, float **x)
{
    sss_htsm_map map;
    sss_error err = {{0}};
    frame(g, v, p);
    assert_int_equal(sss_htsm_gpu_read(g, &map, q, x, &err), SSS_OK);
    sss_htsm_map_free(&map);
}

/* Two directional lights (p's from behind, one more from the side): q is
 * each light's frame alone added, float for float (the second pass is
 * blended one-to-one onto the first), and x_o is the same. */
static void twoLightsGiveTheSumOfEachAlone(void **state)
{
    (void)state;
    block b;
    block_make(&b);
    sss_htsm_gpu *g = gpu_of(&b, &b.h);
    sss_error err = {{0}};
    sss_view_params p, p2;
    params(&p);
    p2 = p;
    const double side[3] = {0.8, 0.3, 0.5}, rgb[3] = {0.5, 0.7, 0.9};
    memcpy(p2.light, side, sizeof side);
    memcpy(p2.light_rgb, rgb, sizeof rgb);
    sss_htsm_view v;
    view(&b, 5, 8, &v);
    float *q[3], *x[3];
    frame_read(g, &v, &p, &q[0], &x[0]);
    frame_read(g, &v, &p2, &q[1], &x[1]);
    v.nmore = 1;
    memcpy(v.more_light[0], side, sizeof side);
    memcpy(v.more_rgb[0], rgb, sizeof rgb);
    frame_read(g, &v, &p, &q[2], &x[2]);
    int drawn = 0, lit[2] = {0, 0};
    for (int i = 0; i < W * H; i++) {
        for (int c = 0; c < 4; c++) assert_true(x[2][4 * i + c] == x[0][4 * i + c]);
        if (x[0][4 * i + 3] != 1.0f) continue;
        drawn++;
        for (int c = 0; c < 3; c++) {
            assert_true(q[2][4 * i + c] == q[0][4 * i + c] + q[1][4 * i + c]);
            lit[0] += c == 0 && q[0][4 * i] > 0.0f, lit[1] += c == 0 && q[1][4 * i] > 0.0f;
        }
    }
    printf("%d pixels, lit by the back light %d, by the side light %d: the pair is their sum\n", drawn, lit[0], lit[1]);
    assert_true(drawn > W * H / 4 && lit[0] > drawn / 2 && lit[1] > drawn / 2);
    v.nmore = SSS_HTSM_MAX_LIGHTS;
    assert_int_not_equal(sss_htsm_gpu_frame(g, &v, &p, W, H, NULL, &err), SSS_OK);
    for (int k = 0; k < 3; k++) free(q[k]), free(x[k]);
    sss_htsm_gpu_destroy(g);
    block_free(&b);
}

/* b's bounding radius (the light-space map's sphere, less its margin). */
static double radius(const block *b)
{
    double c[3];
    return sss_mesh_bounding_sphere(&b->f.mesh, c);
}

/* A point light at centre + dist · dir (dir as p's back light, unit) of
 * intensity E · dist² per steradian, so that the centre gets p's E: v's
 * only light (p's switched off). */
static void point_only(const block *b, const sss_view_params *p, double dist, sss_htsm_view *v)
{
    double c[3], l[3] = {p->light[0], p->light[1], p->light[2]};
    (void)sss_mesh_bounding_sphere(&b->f.mesh, c);
    sss_normalize3(l);
    v->no_p_light = 1;
    v->nmore = 1;
    v->more_point[0] = 1;
    for (int k = 0; k < 3; k++) v->more_light[0][k] = c[k] + dist * l[k], v->more_rgb[0][k] = p->light_rgb[k] * dist * dist;
}

/* A point light behind the block at 3 bounding radii from its centre (a
 * perspective map whose texels' areas differ by their depth, §9.2): per
 * pixel within 10⁻⁴ of the image's largest q, as the directional light. */
static void pointLightPerPixelAgreesWithTheCpuOracle(void **state)
{
    (void)state;
    check_oracle(3.0);
}

/* The largest difference between two frames' q over the drawn pixels,
 * relative to the largest q of the second; *mean the mean difference
 * relative to the mean q of the second. */
static double frame_difference(const float *a, const float *b, const float *x, double *mean)
{
    double worst = 0.0, qmax = 0.0, d = 0.0, s = 0.0;
    for (int i = 0; i < W * H; i++)
        if (x[4 * i + 3] == 1.0f)
            for (int c = 0; c < 3; c++) qmax = fmax(qmax, b[4 * i + c]), s += b[4 * i + c];
    for (int i = 0; i < W * H; i++)
        if (x[4 * i + 3] == 1.0f)
            for (int c = 0; c < 3; c++) {
                worst = fmax(worst, fabs(a[4 * i + c] - b[4 * i + c]) / qmax);
                d += fabs(a[4 * i + c] - b[4 * i + c]);
            }
    assert_true(qmax > 0.0);
    *mean = d / s;
    return worst;
}

static void frame_read(sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p, float **q, float **x);

/* A point light far along the directional light's direction, of intensity
 * E · dist², converges to that light's frame: the largest per-pixel
 * difference falls about as R / dist (at least 4× per decade of dist),
 * below 10⁻³ of the largest q at 10⁴ bounding radii. */
static void farPointLightConvergesToTheDirectionalFrame(void **state)
{
    (void)state;
    block b;
    block_make(&b);
    sss_htsm_gpu *g = gpu_of(&b, &b.h);
    sss_view_params p;
    params(&p);
    sss_htsm_view v;
    view(&b, 13, 8, &v);
    float *q0, *x0;
    frame_read(g, &v, &p, &q0, &x0);
    double e[4], mean;
    const double dist[4] = {10.0, 100.0, 1000.0, 10000.0};
    for (int k = 0; k < 4; k++) {
        sss_htsm_view vp = v;
        point_only(&b, &p, dist[k] * radius(&b), &vp);
        float *q, *x;
        frame_read(g, &vp, &p, &q, &x);
        e[k] = frame_difference(q, q0, x0, &mean);
        printf("point light at %5.0f R: difference from the directional frame %.2e of its largest q at most, "
               "%.2e of its mean q on average\n", dist[k], e[k], mean);
        free(q);
        free(x);
    }
    assert_true(e[0] > 1e-2);
    for (int k = 1; k < 4; k++) assert_true(e[k] < 0.25 * e[k - 1]);
    assert_true(e[3] < 1e-3);
    free(q0);
    free(x0);
    sss_htsm_gpu_destroy(g);
    block_free(&b);
}

/* A point light among the lights: the back light and a point light at the
 * side give the sum of each alone, float for float; a point light within
 * the bounding sphere is refused, naming it. */
static void pointLightJoinsTheSumOfTheLights(void **state)
{
    (void)state;
    block b;
    block_make(&b);
    sss_htsm_gpu *g = gpu_of(&b, &b.h);
    sss_view_params p;
    params(&p);
    sss_htsm_view v, vp;
    view(&b, 5, 8, &v);
    double c[3];
    sss_mesh_bounding_sphere(&b.f.mesh, c);
    const double at[3] = {c[0] + 2.5, c[1] + 1.0, c[2] + 1.5}, I[3] = {4.0, 3.0, 2.0};
    vp = v;
    vp.no_p_light = 1;
    vp.nmore = 1;
    vp.more_point[0] = 1;
    memcpy(vp.more_light[0], at, sizeof at);
    memcpy(vp.more_rgb[0], I, sizeof I);
    float *q[3], *x[3];
    frame_read(g, &v, &p, &q[0], &x[0]);
    frame_read(g, &vp, &p, &q[1], &x[1]);
    vp.no_p_light = 0;
    frame_read(g, &vp, &p, &q[2], &x[2]);
    int drawn = 0, lit = 0;
    for (int i = 0; i < W * H; i++) {
        for (int c4 = 0; c4 < 4; c4++) assert_true(x[2][4 * i + c4] == x[0][4 * i + c4] && x[1][4 * i + c4] == x[0][4 * i + c4]);
        if (x[0][4 * i + 3] != 1.0f) continue;
        drawn++;
        lit += q[1][4 * i] > 0.0f;
        for (int ch = 0; ch < 3; ch++) assert_true(q[2][4 * i + ch] == q[0][4 * i + ch] + q[1][4 * i + ch]);
    }
    printf("%d pixels, %d lit by the point light: the pair is the sum of each alone\n", drawn, lit);
    assert_true(drawn > W * H / 4 && lit > drawn / 2);
    sss_error err = {{0}};
    memcpy(vp.more_light[0], c, sizeof c);
    assert_int_equal(sss_htsm_gpu_frame(g, &vp, &p, W, H, NULL, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "lies within the object's bounding sphere"));
    vp.nmore = 0;
    vp.no_p_light = 1;
    assert_int_equal(sss_htsm_gpu_frame(g, &vp, &p, W, H, NULL, &err), SSS_ERR_ARG);
    for (int k = 0; k < 3; k++) free(q[k]), free(x[k]);
    sss_htsm_gpu_destroy(g);
    block_free(&b);
}

/* ---- the surface terms of every light (docs/heterogeneous.md §9.1) ---- */

/* A plate of 0.9 × 0.9 × 0.2 units floating 0.4 units in front of the
 * block's face z = 0.5 (z from PZ0 to PZ1), in the same mesh, so that it
 * shadows part of that face from a light in front. */
#define PH 0.45
#define PZ0 0.9
#define PZ1 1.1

static void shadowed_block_make(block *b)
{
    sss_error err = {{0}};
    sss_mesh box, plate;
    memset(b, 0, sizeof *b);
    assert_int_equal(sss_gen_box(&box, 2.0, 2.0, 1.0, 6, 0, &err), SSS_OK);
    assert_int_equal(sss_gen_box(&plate, 2 * PH, 2 * PH, PZ1 - PZ0, 2, 0, &err), SSS_OK);
    assert_int_equal(sss_mesh_alloc(&b->m, box.nv + plate.nv, box.nf + plate.nf, &err), SSS_OK);
    memcpy(b->m.pos, box.pos, 3 * (size_t)box.nv * sizeof *box.pos);
    memcpy(b->m.tri, box.tri, 3 * (size_t)box.nf * sizeof *box.tri);
    for (uint32_t v = 0; v < plate.nv; v++)
        for (int k = 0; k < 3; k++)
            b->m.pos[3 * (size_t)(box.nv + v) + k] = plate.pos[3 * (size_t)v + k] + (k == 2 ? (float)(0.5 * (PZ0 + PZ1)) : 0.0f);
    for (size_t i = 0; i < 3 * (size_t)plate.nf; i++) b->m.tri[3 * (size_t)box.nf + i] = plate.tri[i] + box.nv;
    sss_mesh_free(&box);
    sss_mesh_free(&plate);
    assert_int_equal(sss_mesh_compute_normals_areas(&b->m, "mesh", &err), SSS_OK);
    bake_preset(&b->m, "marble", 0, 10.0, 6, SSS_QUANT_FLOAT, -1, &b->f);
    if (sss_renderer_create(&b->f, &b->r, &err) != SSS_OK) fail_msg("renderer: %s", err.msg);
}

/* The plate as seen from x along the unit ray u (towards the light, no
 * farther than tmax): −1 when the ray crosses both of the plate's planes
 * z = PZ0, PZ1 within its square shrunk by m (shadowed), +1 when at both it
 * lies beyond the square grown by m on one side (lit), 0 between (the
 * shadow's outline, which the map's texels draw within a few texels). */
static int plate_shadow(const double x[3], const double u[3], double tmax, double m)
{
    double p[2][2];
    for (int k = 0; k < 2; k++) {
        const double t = ((k ? PZ1 : PZ0) - x[2]) / u[2];
        if (!(t > 0.0 && t < tmax)) return 1;
        p[k][0] = x[0] + t * u[0], p[k][1] = x[1] + t * u[1];
    }
    int in = 1;
    for (int k = 0; k < 2; k++) in = in && fabs(p[k][0]) < PH - m && fabs(p[k][1]) < PH - m;
    if (in) return -1;
    for (int a = 0; a < 2; a++)
        if ((p[0][a] > PH + m && p[1][a] > PH + m) || (p[0][a] < -PH - m && p[1][a] < -PH - m)) return 1;
    return 0;
}

/* surface.glsl's terms in double: E's specular (a share 1 − ρ_d) and
 * diffuse (ρ_d) reflection at a point of normal n seen along v (unit, to
 * the eye) under the unit l (to the light); F_r = 1 − F_t. */
static void surface_oracle(const double n[3], const double v[3], const double l[3], const double E[3], double eta,
                           double rho_d, double out[3])
{
    const double nl = sss_dot3(n, l);
    double h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
    sss_normalize3(h);
    const double d = 88.0 / (8.0 * SSS_PI) * pow(fmax(sss_dot3(n, h), 0.0), 80.0);
    const double sp = (1.0 - rho_d) * (1.0 - sss_ft(eta, sss_dot3(v, h))) * d * nl,
                 di = rho_d * (1.0 - sss_ft(eta, nl)) * nl / SSS_PI;
    for (int c = 0; c < 3; c++) out[c] = nl > 0.0 ? E[c] * (sp + di) : 0.0;
}

/* The face z = 0.5 lit from the front, the plate's shadow on it. */
static void front_params(sss_view_params *p)
{
    params(p);
    p->specular = 1;
    p->diffuse = 0.5;
    p->surface_shadow = 1;
    p->scatter = 0;
    p->tonemap = SSS_TONEMAP_CLAMP;
    p->light[0] = -0.7, p->light[1] = -0.5, p->light[2] = 1.0;
    p->light_rgb[0] = 1.0, p->light_rgb[1] = 0.8, p->light_rgb[2] = 0.6;
    p->view[0] = 0.5, p->view[1] = 0.35, p->view[2] = 1.0; /* the plate hides little of its shadow */
}

/* Per pixel of the face z = 0.5 away from its edges (where every normal is
 * (0, 0, 1)): the surface terms of v's only light against the oracle, lit
 * pixels within 10⁻⁴ of the largest, shadowed ones 0; counts in lit and
 * dark. point: v's light is its first more light, a point light. */
static void check_surface(const block *b, sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p,
                          int point, int *lit, int *dark)
{
    float *q, *x, *s;
    sss_error err = {{0}};
    frame_read(g, v, p, &q, &x);
    assert_int_equal(sss_htsm_gpu_read_surface(g, &s, &err), SSS_OK);
    double eye[3], right[3], up[3], fwd[3], smax = 0.0, worst = 0.0;
    sss_renderer_camera(b->r, p, eye, right, up, fwd);
    const double n[3] = {0.0, 0.0, 1.0};
    *lit = *dark = 0;
    for (int i = 0; i < W * H; i++) {
        const double xo[3] = {x[4 * i], x[4 * i + 1], x[4 * i + 2]};
        if (x[4 * i + 3] != 1.0f || fabs(xo[2] - 0.5) > 1e-5 || fabs(xo[0]) > 2.0 / 3 || fabs(xo[1]) > 2.0 / 3)
            continue;
        double l[3], E[3], tmax = INFINITY, ve[3] = {eye[0] - xo[0], eye[1] - xo[1], eye[2] - xo[2]}, want[3];
        sss_normalize3(ve);
        if (point) {
            for (int k = 0; k < 3; k++) l[k] = v->more_light[0][k] - xo[k];
            tmax = sss_normalize3(l);
            for (int k = 0; k < 3; k++) E[k] = v->more_rgb[0][k] / (tmax * tmax); /* I / r² */
        } else {
            memcpy(l, p->light, sizeof l);
            sss_normalize3(l);
            memcpy(E, p->light_rgb, sizeof E);
        }
        const int sh = plate_shadow(xo, l, tmax, 0.06);
        surface_oracle(n, ve, l, E, b->f.material.eta, p->diffuse, want);
        if (sh < 0) {
            (*dark)++;
            for (int c = 0; c < 3; c++) assert_true(s[4 * i + c] == 0.0f);
        } else if (sh > 0) {
            (*lit)++;
            for (int c = 0; c < 3; c++) {
                smax = fmax(smax, want[c]);
                worst = fmax(worst, fabs(s[4 * i + c] - want[c]));
            }
        }
    }
    printf("%s light: %d pixels lit, %d in the plate's shadow (0); lit against the oracle within %.2e of the "
           "largest surface term %.4g\n", point ? "point" : "directional", *lit, *dark, worst / smax, smax);
    assert_true(smax > 0.0 && worst < 1e-4 * smax);
    free(q);
    free(x);
    free(s);
}

/* Each light's surface terms (specular and diffuse reflection) at every
 * pixel: a directional light's and a point light's (E = I / r² at each
 * point) against the oracle on the block's face, none where the plate
 * shadows it from that light (tested against that light's own map); two
 * identical directional lights draw twice one's surface light, and the
 * directional and the point light together the sum of each alone, through
 * the renderer's whole draw. */
static void surfaceTermsOfEveryLight(void **state)
{
    (void)state;
    block b;
    shadowed_block_make(&b);
    sss_htsm_gpu *g = gpu_of(&b, NULL);
    sss_view_params p;
    front_params(&p);
    sss_htsm_view v, vp, v2, vb;
    view(&b, 5, 4, &v);
    int lit, dark;
    check_surface(&b, g, &v, &p, 0, &lit, &dark);
    assert_true(lit > 50 && dark > 100);
    vp = v;
    vp.no_p_light = 1;
    vp.nmore = 1;
    vp.more_point[0] = 1;
    const double P[3] = {-1.4, -1.0, 3.0}, I[3] = {9.0, 12.0, 6.0};
    memcpy(vp.more_light[0], P, sizeof P);
    memcpy(vp.more_rgb[0], I, sizeof I);
    check_surface(&b, g, &vp, &p, 1, &lit, &dark);
    assert_true(lit > 50 && dark > 100);
    /* whole images, exposure · L: one light, the same twice, the point light alone, both */
    v2 = v;
    v2.nmore = 1;
    memcpy(v2.more_light[0], p.light, sizeof p.light);
    memcpy(v2.more_rgb[0], p.light_rgb, sizeof p.light_rgb);
    vb = vp;
    vb.no_p_light = 0;
    const sss_htsm_view *vs[4] = {&v, &v2, &vp, &vb};
    float *rgb[4], *hdr[4];
    sss_error err = {{0}};
    for (int k = 0; k < 4; k++)
        if (sss_htsm_gpu_render_image(g, vs[k], &p, W, H, &rgb[k], &hdr[k], &err) != SSS_OK) fail_msg("%s", err.msg);
    double d2 = 0.0, dsum = 0.0, m1 = 0.0;
    int on = 0;
    for (int i = 0; i < 3 * W * H; i++) {
        m1 = fmax(m1, hdr[0][i]);
        on += hdr[0][i] > 0.0f && hdr[2][i] > 0.0f;
        d2 = fmax(d2, fabs(hdr[1][i] - 2.0 * hdr[0][i]));
        dsum = fmax(dsum, fabs(hdr[3][i] - (hdr[0][i] + hdr[2][i])));
    }
    printf("two identical lights: %.2e from twice one, the pair of kinds %.2e from the sum (largest %.4g, %d "
           "samples lit by both)\n", d2 / m1, dsum / m1, m1, on);
    assert_true(on > W * H / 4 && d2 <= 1e-6 * m1 && dsum <= 1e-6 * m1);
    for (int k = 0; k < 4; k++) free(rgb[k]), free(hdr[k]);
    sss_htsm_gpu_destroy(g);
    block_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(perPixelAgreesWithTheCpuOracle),
        cmocka_unit_test(liveEditsShowAtOnceAndUndo),
        cmocka_unit_test(twoLightsGiveTheSumOfEachAlone),
        cmocka_unit_test(pointLightPerPixelAgreesWithTheCpuOracle),
        cmocka_unit_test(farPointLightConvergesToTheDirectionalFrame),
        cmocka_unit_test(pointLightJoinsTheSumOfTheLights),
        cmocka_unit_test(surfaceTermsOfEveryLight),
    };
    return cmocka_run_group_tests(tests, gl_setup, gl_teardown);
}
