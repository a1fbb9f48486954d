/* test_robustness.c: the hard inputs of docs/robustness.md baked end to end
 * (docs/robustness.md): each either gives finite, bounded q with the
 * documented warning count, or the same q as its well-formed counterpart. */
#define _POSIX_C_SOURCE 200809L

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

#include "genmesh.h"
#include "sss/bake.h"
#include "sss/visibility.h"
#include "sss/lloyd.h"
#include "sss/compress.h"
#include "sss/decode.h"
#include "sss/import.h"
#include "sss/vec3.h"

static sss_material material(const char *preset)
{
    sss_material m;
    sss_error err = {{0}};
    assert_int_equal(sss_material_preset(preset, &m, &err), SSS_OK);
    return m;
}

static sss_bake_options options(double mm_per_unit, uint32_t dirs)
{
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.mm_per_unit = mm_per_unit;
    o.n_dirs = dirs;
    o.quant = SSS_QUANT_FLOAT;
    o.threads = 2;
    return o;
}

/* Every stored q finite and >= 0; returns the largest. */
static double assert_q_finite(const sss_bake_file *f)
{
    double mx = 0;
    size_t n = (size_t)f->dirs.n * f->mesh.nv * f->channels;
    for (size_t i = 0; i < n; i++) {
        if (!(isfinite(f->q[i]) && f->q[i] >= 0.0f)) fail_msg("q[%zu] = %g is not finite and >= 0", i, f->q[i]);
        if (f->q[i] > mx) mx = f->q[i];
    }
    return mx;
}

/* The flat-slab value F_t(η, 1) R_d,total / π of channel c: the most a
 * vertex lit head-on can receive on a well-resolved surface. */
static double slab_q(const sss_material *m, int c)
{
    sss_dipole d;
    sss_dipole_init(&d, m->sigma_a[c], m->sigmap_s[c], m->eta);
    return sss_ft(m->eta, 1.0) * sss_rd_total(&d) / SSS_PI;
}

static void bake(const sss_mesh *mesh, const sss_material *m, const sss_bake_options *o, sss_bake_file *f, sss_bake_stats *st)
{
    sss_error err = {{0}};
    sss_result r = sss_bake(mesh, "mesh", m, o, f, st, &err);
    if (r != SSS_OK) fail_msg("bake: %s", err.msg);
}

static char g_dir[64];

static const char *tmp_path(const char *name)
{
    static char buf[4][192];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, name);
    return buf[k];
}

static int setup(void **state)
{
    (void)state;
    strcpy(g_dir, "/tmp/sss_test_robustness_XXXXXX");
    return mkdtemp(g_dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    const char *names[] = {"origin.off", "far.off"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) unlink(tmp_path(names[i]));
    rmdir(g_dir);
    return 0;
}

static void write_off(const char *path, const sss_mesh *m, double offset)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "OFF\n%u %u 0\n", m->nv, m->nf);
    for (uint32_t v = 0; v < m->nv; v++)
        fprintf(f, "%.17g %.17g %.17g\n", offset + m->pos[3 * v], offset + m->pos[3 * v + 1], offset + m->pos[3 * v + 2]);
    for (uint32_t t = 0; t < m->nf; t++) fprintf(f, "3 %u %u %u\n", m->tri[3 * t], m->tri[3 * t + 1], m->tri[3 * t + 2]);
    assert_int_equal(fclose(f), 0);
}

/* B6: a unit sphere 10^6 from the origin bakes the q it bakes at the origin
 * (float precision), with no triangle dropped and no ray blocked. */
static void farSphereBakesTheSameAsAtTheOrigin(void **state)
{
    (void)state;
    sss_mesh s, a, b;
    sss_import_report ra, rb;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&s, 1.0, 3, &err), SSS_OK);
    write_off(tmp_path("origin.off"), &s, 0.0);
    write_off(tmp_path("far.off"), &s, 1e6);
    assert_int_equal(sss_import_mesh(tmp_path("origin.off"), &a, &ra, &err), SSS_OK);
    assert_int_equal(sss_import_mesh(tmp_path("far.off"), &b, &rb, &err), SSS_OK);
    assert_int_equal(rb.recentred, 1);
    assert_int_equal(rb.faces_zero_area, 0);
    assert_int_equal(b.nf, a.nf);
    sss_material m = material("skin1");
    sss_bake_options o = options(20.0, 20);
    sss_bake_file fa, fb;
    sss_bake_stats sa, sb;
    bake(&a, &m, &o, &fa, &sa);
    bake(&b, &m, &o, &fb, &sb);
    assert_true(sb.occluded_fraction == 0.0); /* convex: nothing shadows */
    size_t n = (size_t)fa.dirs.n * fa.mesh.nv * fa.channels;
    double worst = 0;
    for (size_t i = 0; i < n; i++) {
        double d = fabs((double)fb.q[i] - fa.q[i]) / (fabs(fa.q[i]) + 1e-6);
        if (d > worst) worst = d;
    }
    print_message("far sphere: largest relative q difference %.3g\n", worst);
    assert_true(worst < 1e-4);
    sss_file_free(&fa);
    sss_file_free(&fb);
    sss_mesh_free(&a);
    sss_mesh_free(&b);
    sss_mesh_free(&s);
}

/* Bakes a mesh with float storage and with both compressed presets' main
 * forms; every result decodes finite and >= 0. Returns the float file. */
static void bake_all_forms(const sss_mesh *mesh, const sss_material *m, double mm, sss_bake_file *f, sss_bake_stats *st)
{
    sss_bake_options o = options(mm, 64);
    bake(mesh, m, &o, f, st);
    assert_q_finite(f);
    sss_compress_opts co[2];
    sss_compress_opts_default(&co[0]);
    co[0].fraction = 0.03; /* paper: 3 % references, SH order 3 */
    co[0].order = 3;
    sss_compress_opts_default(&co[1]);
    co[1].fraction = 0.0; /* SH only */
    co[1].order = 3;
    const double light[3] = {0.3, 0.4, 0.866};
    float *out = malloc((size_t)f->mesh.nv * f->channels * sizeof(float));
    assert_non_null(out);
    for (int k = 0; k < 2; k++) {
        sss_bake_file c;
        sss_error err = {{0}};
        if (sss_compress(f, &co[k], &c, &err) != SSS_OK) fail_msg("compress: %s", err.msg);
        sss_decode_all(&c, light, out);
        for (size_t i = 0; i < (size_t)f->mesh.nv * f->channels; i++) assert_true(isfinite(out[i]) && out[i] >= 0.0f);
        sss_file_free(&c);
    }
    free(out);
}

/* Non-manifold meshes: a 3-triangle fin on an edge of a sphere, and two
 * spheres sharing one vertex. The bake needs only a triangle soup. */
static void nonManifoldMeshesBakeFinite(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_material m = material("skin1");
    /* fin: two more triangles on the edge of triangle 0 */
    sss_mesh s;
    assert_int_equal(sss_gen_sphere(&s, 1.0, 2, &err), SSS_OK);
    {
        uint32_t a = s.tri[0], b = s.tri[1];
        uint32_t nv = s.nv;
        float *pos = realloc(s.pos, (size_t)(nv + 1) * 3 * sizeof(float));
        uint32_t *tri = realloc(s.tri, (size_t)(s.nf + 2) * 3 * sizeof(uint32_t));
        assert_non_null(pos);
        assert_non_null(tri);
        s.pos = pos;
        s.tri = tri;
        for (int k = 0; k < 3; k++) s.pos[3 * nv + k] = 1.6f * 0.5f * (s.pos[3 * a + k] + s.pos[3 * b + k]);
        uint32_t t0[3] = {a, b, nv}, t1[3] = {b, a, nv};
        memcpy(s.tri + 3 * s.nf, t0, sizeof t0);
        memcpy(s.tri + 3 * (s.nf + 1), t1, sizeof t1);
        s.nv = nv + 1;
        s.nf += 2; /* the edge a-b now has 4 triangles */
        assert_int_equal(sss_mesh_compute_normals_areas(&s, "fin", &err), SSS_OK);
    }
    sss_bake_file f;
    sss_bake_stats st;
    bake_all_forms(&s, &m, 20.0, &f, &st);
    sss_file_free(&f);
    sss_mesh_free(&s);
    /* two spheres touching at one shared vertex */
    sss_mesh a, b;
    assert_int_equal(sss_gen_sphere(&a, 1.0, 2, &err), SSS_OK);
    assert_int_equal(sss_gen_sphere(&b, 1.0, 2, &err), SSS_OK);
    uint32_t top = 0; /* the vertex of a with the largest z */
    for (uint32_t v = 0; v < a.nv; v++)
        if (a.pos[3 * v + 2] > a.pos[3 * top + 2]) top = v;
    uint32_t bottom = 0;
    for (uint32_t v = 0; v < b.nv; v++)
        if (b.pos[3 * v + 2] < b.pos[3 * bottom + 2]) bottom = v;
    for (uint32_t v = 0; v < b.nv; v++)
        for (int k = 0; k < 3; k++) b.pos[3 * v + k] += a.pos[3 * top + k] - b.pos[3 * bottom + k];
    uint32_t nva = a.nv;
    assert_int_equal(sss_mesh_append(&a, &b, &err), SSS_OK);
    for (size_t i = 3 * (size_t)(a.nf - b.nf); i < 3 * (size_t)a.nf; i++)
        if (a.tri[i] == nva + bottom) a.tri[i] = top; /* share the vertex */
    assert_int_equal(sss_mesh_compute_normals_areas(&a, "pair", &err), SSS_OK);
    bake_all_forms(&a, &m, 20.0, &f, &st);
    sss_file_free(&f);
    sss_mesh_free(&a);
    sss_mesh_free(&b);
}

/* Open boundaries: a square lit head-on loses the light that would scatter
 * in from beyond its edge. q at the centre is the flat-slab value (2 %), at a
 * corner less, and nowhere more than the slab value. */
static void openSquareLosesLightAtItsBoundaryOnly(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh p;
    assert_int_equal(sss_gen_plane(&p, 40.0, 40.0, 80, 80, &err), SSS_OK); /* 0.5 mm spacing */
    sss_material m = material("skin1");
    sss_bake_options o = options(1.0, 4);
    sss_bake_file f;
    sss_bake_stats st;
    bake(&p, &m, &o, &f, &st);
    assert_q_finite(&f);
    /* the direction closest to +z */
    uint32_t j = 0;
    for (uint32_t k = 0; k < f.dirs.n; k++)
        if (f.dirs.dir[3 * k + 2] > f.dirs.dir[3 * j + 2]) j = k;
    const double cz = f.dirs.dir[3 * j + 2];
    const uint32_t centre = 40 * 81 + 40, corner = 0;
    for (uint32_t c = 0; c < f.channels; c++) {
        const double want = slab_q(&m, (int)c) * cz * sss_ft(m.eta, cz) / sss_ft(m.eta, 1.0);
        const float *q = f.q + (size_t)j * f.mesh.nv * f.channels;
        print_message("open square, channel %u: centre %.4g, corner %.4g, infinite plane %.4g\n", c,
                      q[(size_t)centre * f.channels + c], q[(size_t)corner * f.channels + c], want);
        assert_true(fabs(q[(size_t)centre * f.channels + c] - want) < 0.03 * want);
        assert_true(q[(size_t)corner * f.channels + c] < 0.6 * q[(size_t)centre * f.channels + c]);
        for (uint32_t v = 0; v < f.mesh.nv; v++) assert_true(q[(size_t)v * f.channels + c] <= 1.03 * want);
    }
    assert_int_equal(st.thin_vertices, 0); /* an open sheet has no inside */
    sss_file_free(&f);
    sss_mesh_free(&p);
}

/* Self-intersection: two spheres overlapping by half. Vertices of one inside
 * the other are in shadow from every direction (rays see the whole mesh);
 * q stays finite and below the flat-slab bound. */
static void interpenetratingSpheresShadowTheBuriedPart(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh a, b;
    assert_int_equal(sss_gen_sphere(&a, 1.0, 3, &err), SSS_OK);
    assert_int_equal(sss_gen_sphere(&b, 1.0, 3, &err), SSS_OK);
    for (uint32_t v = 0; v < b.nv; v++) b.pos[3 * v] += 1.0f;
    assert_int_equal(sss_mesh_append(&a, &b, &err), SSS_OK);
    assert_int_equal(sss_mesh_compute_normals_areas(&a, "pair", &err), SSS_OK);
    sss_vis *vis;
    assert_int_equal(sss_vis_create(&a, &vis, &err), SSS_OK);
    sss_dirset ds;
    assert_int_equal(sss_dirset_fibonacci(&ds, 20, &err), SSS_OK);
    uint32_t buried = 0;
    for (uint32_t v = 0; v < a.nv; v++) {
        const float *p = a.pos + 3 * v;
        double cx = v < a.nv / 2 ? 1.0 : 0.0; /* the other sphere's centre */
        double d2 = (p[0] - cx) * (p[0] - cx) + p[1] * p[1] + p[2] * p[2];
        if (d2 > 0.8 * 0.8) continue;
        buried++;
        for (uint32_t j = 0; j < ds.n; j++) assert_true(sss_vis_occluded(vis, v, ds.dir + 3 * j));
    }
    assert_true(buried > 50);
    sss_vis_destroy(vis);
    sss_dirset_free(&ds);
    sss_material m = material("skin1");
    sss_bake_options o = options(20.0, 20);
    sss_bake_file f;
    sss_bake_stats st;
    bake(&a, &m, &o, &f, &st);
    const double mx = assert_q_finite(&f);
    double bound = 0;
    for (int c = 0; c < 3; c++) bound = fmax(bound, slab_q(&m, c));
    assert_true(mx < 1.5 * bound);
    sss_file_free(&f);
    sss_mesh_free(&a);
    sss_mesh_free(&b);
}

/* B8: the bake counts vertices on parts thinner than the range (the tool
 * warns with the count; tests/integration/cli_hard_meshes.sh). */
static void thinSlabIsCountedThickSphereIsNot(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh slab, s;
    assert_int_equal(sss_gen_box(&slab, 1.0, 1.0, 0.02, 10, 0, &err), SSS_OK); /* 200 x 200 x 4 mm */
    sss_material w;
    memset(&w, 0, sizeof w);
    snprintf(w.name, sizeof w.name, "white");
    for (int c = 0; c < 3; c++) { w.sigma_a[c] = 0.0; w.sigmap_s[c] = 1.0; }
    w.eta = 1.3;
    sss_bake_options o = options(200.0, 12);
    sss_bake_file f;
    sss_bake_stats st;
    bake(&slab, &w, &o, &f, &st);
    assert_q_finite(&f);
    print_message("thin slab: %u of %u vertices thin (thinnest %.3g mm, limit %.3g mm)\n", st.thin_vertices, f.mesh.nv,
                  st.thinnest_mm, st.thin_limit_mm);
    assert_true(st.thin_vertices > f.mesh.nv / 2);
    assert_true(fabs(st.thinnest_mm - 4.0) < 0.01);
    sss_file_free(&f);
    assert_int_equal(sss_gen_sphere(&s, 1.0, 3, &err), SSS_OK);
    sss_material skin = material("skin1");
    o = options(20.0, 12);
    bake(&s, &skin, &o, &f, &st);
    assert_int_equal(st.thin_vertices, 0);
    assert_true(st.thinnest_mm > 39.0 && st.thinnest_mm < 40.01); /* the diameter */
    sss_file_free(&f);
    sss_mesh_free(&s);
    sss_mesh_free(&slab);
}

/* 10^-4 and 10^4 mm per unit: finite. Scaling the coordinates by k and the
 * scale by 1/k bakes the same q (float precision). At 10^4 mm per unit the
 * vertices are far beyond the range and q is the self term alone, at most
 * the flat-slab value. */
static void extremeScalesBakeFiniteAndScaleInvariant(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh s, big;
    assert_int_equal(sss_gen_sphere(&s, 1.0, 2, &err), SSS_OK);
    assert_int_equal(sss_mesh_copy(&s, &big, &err), SSS_OK);
    for (size_t i = 0; i < 3 * (size_t)big.nv; i++) big.pos[i] *= 1024.0f; /* exact */
    assert_int_equal(sss_mesh_compute_normals_areas(&big, "big", &err), SSS_OK);
    sss_material m = material("skin1");
    const double scales[2] = {1e4, 1e-4};
    for (int i = 0; i < 2; i++) {
        sss_bake_options o = options(scales[i], 12), ob = options(scales[i] / 1024.0, 12);
        sss_bake_file f, fb;
        sss_bake_stats st;
        bake(&s, &m, &o, &f, &st);
        bake(&big, &m, &ob, &fb, &st);
        const double mx = assert_q_finite(&f);
        assert_q_finite(&fb);
        if (i == 0) {
            double bound = 0;
            for (int c = 0; c < 3; c++) bound = fmax(bound, slab_q(&m, c));
            assert_true(mx > 0 && mx <= bound * (1 + 1e-6));
        } else {
            assert_true(mx > 0 && mx < 1e-6);
        }
        size_t n = (size_t)f.dirs.n * f.mesh.nv * f.channels;
        for (size_t k = 0; k < n; k++) assert_true(fabs((double)fb.q[k] - f.q[k]) <= 1e-5 * fabs(f.q[k]) + 1e-30);
        sss_file_free(&f);
        sss_file_free(&fb);
    }
    sss_mesh_free(&big);
    sss_mesh_free(&s);
}

/* One channel with σ'_s = 0 bakes q = 0 in that channel exactly; one with
 * σa = 0 (α' = 1, the range clamped to the object) bakes finite q. */
static void singleChannelLimitsBake(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh s;
    assert_int_equal(sss_gen_sphere(&s, 1.0, 2, &err), SSS_OK);
    sss_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "custom");
    const double sa[3] = {0.0, 0.05, 0.1}, ss[3] = {1.0, 1.0, 0.0};
    for (int c = 0; c < 3; c++) { m.sigma_a[c] = sa[c]; m.sigmap_s[c] = ss[c]; }
    m.eta = 1.3;
    sss_bake_options o = options(20.0, 12);
    sss_bake_file f;
    sss_bake_stats st;
    bake(&s, &m, &o, &f, &st);
    assert_int_equal(f.channels, 3);
    assert_q_finite(&f);
    double sum[3] = {0, 0, 0};
    for (size_t i = 0; i < (size_t)f.dirs.n * f.mesh.nv; i++)
        for (int c = 0; c < 3; c++) sum[c] += f.q[3 * i + (size_t)c];
    assert_true(sum[0] > 0 && sum[1] > 0);
    assert_true(sum[2] == 0.0); /* no scattering: nothing comes back out */
    sss_file_free(&f);
    sss_mesh_free(&s);
}

/* The Lloyd quantiser on constant data: exact (all levels the constant) at
 * 2, 3, 16 and 256 levels, pinned and unpinned; on two values, exact with 2
 * or more levels. */
static void lloydIsExactOnConstantAndTwoValuedDataAtAnyLevelCount(void **state)
{
    (void)state;
    enum { N = 1000 };
    float *x = malloc(N * sizeof(float)), levels[256];
    uint8_t *idx = malloc(N);
    assert_non_null(x);
    assert_non_null(idx);
    const uint32_t nl[4] = {2, 3, 16, 256};
    for (int data = 0; data < 2; data++) {
        for (int i = 0; i < N; i++) x[i] = data == 0 ? 0.3125f : (i % 3 ? 1.5f : -0.25f);
        for (int k = 0; k < 4; k++)
            for (int pin = 0; pin < 2; pin++) {
                if (data == 1 && pin) continue; /* pinned: level 0 is the minimum, fine too, but tested unpinned */
                double sig, noise;
                sss_error err = {{0}};
                assert_int_equal(sss_lloyd(x, N, 1, nl[k], pin, levels, idx, &sig, &noise, &err), SSS_OK);
                for (int i = 0; i < N; i++) assert_true(levels[idx[i]] == x[i]);
                assert_true(noise == 0.0);
                for (uint32_t l = 0; l < nl[k]; l++) assert_true(isfinite(levels[l]));
            }
    }
    free(x);
    free(idx);
}


/* Largest |decoded - stored| over vertices, channels and the direction
 * samples, with `offset` taken off the decoded value. */
static double max_decode_error(const sss_bake_file *c, const sss_bake_file *ref, double offset)
{
    const uint32_t nv = ref->mesh.nv, C = ref->channels;
    float *out = malloc((size_t)nv * C * sizeof(float));
    assert_non_null(out);
    double worst = 0;
    for (uint32_t j = 0; j < ref->dirs.n; j++) {
        sss_decode_all(c, ref->dirs.dir + 3 * (size_t)j, out);
        for (size_t i = 0; i < (size_t)nv * C; i++) {
            assert_true(isfinite(out[i]));
            worst = fmax(worst, fabs(((double)out[i] - offset) - ref->q[(size_t)j * nv * C + i]));
        }
    }
    free(out);
    return worst;
}

/* Cancellation in reference deltas: the same integrals plus a common offset
 * 100 times their largest value (every coded vertex then differs from its
 * references by a tiny fraction of what they hold) reconstruct with the same
 * absolute error, up to float rounding of the offset. The delta is formed in
 * double from the quantised rows and weights (compress.c), so nothing of the
 * small difference is lost to cancellation before it is coded. */
static void referenceDeltasKeepPrecisionUnderCancellation(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh s;
    assert_int_equal(sss_gen_blob(&s, 1.0, 3, &err), SSS_OK);
    sss_material m = material("skin1");
    sss_bake_options o = options(20.0, 50);
    sss_bake_file f, g;
    sss_bake_stats st;
    bake(&s, &m, &o, &f, &st);
    const double qmax = assert_q_finite(&f);
    assert_int_equal(sss_mesh_copy(&f.mesh, &g.mesh, &err), SSS_OK); /* g: f with the offset */
    sss_bake_file tmp = f;
    tmp.mesh = g.mesh;
    g = tmp;
    g.q = malloc((size_t)f.dirs.n * f.mesh.nv * f.channels * sizeof(float));
    assert_non_null(g.q);
    const double A = 100.0 * qmax;
    for (size_t i = 0; i < (size_t)f.dirs.n * f.mesh.nv * f.channels; i++) g.q[i] = (float)(f.q[i] + A);
    sss_compress_opts co;
    sss_compress_opts_default(&co);
    co.fraction = 0.05;
    co.order = 3;
    sss_bake_file cf, cg;
    if (sss_compress(&f, &co, &cf, &err) != SSS_OK) fail_msg("compress: %s", err.msg);
    if (sss_compress(&g, &co, &cg, &err) != SSS_OK) fail_msg("compress: %s", err.msg);
    /* g's stored values are f's plus A, rounded to float */
    sss_bake_file gref = g;
    const double ef = max_decode_error(&cf, &f, 0.0), eg = max_decode_error(&cg, &gref, 0.0);
    print_message("cancellation: max error %.3g without offset, %.3g with an offset of %.3g (q max %.3g)\n", ef, eg, A, qmax);
    assert_true(eg <= 1.5 * ef + 1e-5 * A);
    sss_file_free(&cf);
    sss_file_free(&cg);
    free(g.q);
    sss_mesh_free(&g.mesh);
    sss_file_free(&f);
    sss_mesh_free(&s);
}

/* A mesh spanning more than SSS_EXTENT_MM_MAX (1e15 mm): the tree
 * gather's float squares of distances overflowed beyond about 1.8e19 mm
 * and it wrote q = 0 everywhere with success, while the direct sum was
 * right. Both gathers now refuse the mesh before anything is computed,
 * naming its extent; 1e14 mm still bakes with both, to the same values
 * (docs/robustness.md item 4). */
static void meshBeyondTheFloatRangeIsRefusedByBothGathers(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1e7, 1, &err), SSS_OK); /* 2e7 units across */
    const sss_material mat = material("marble");
    for (int g = SSS_GATHER_DIRECT; g <= SSS_GATHER_TREE; g++) {
        sss_bake_options o = options(1e12, 12); /* 2e19 mm */
        o.gather = g;
        sss_bake_file f;
        sss_bake_stats st;
        assert_int_equal(sss_bake(&m, "big", &mat, &o, &f, &st, &err), SSS_ERR_MESH);
        assert_non_null(strstr(err.msg, "the mesh spans"));
        assert_non_null(strstr(err.msg, "beyond 1e+15 mm"));
    }
    double q[2] = {0, 0};
    for (int g = SSS_GATHER_DIRECT; g <= SSS_GATHER_TREE; g++) {
        sss_bake_options o = options(5e6, 12); /* 1e14 mm: inside */
        o.gather = g;
        sss_bake_file f;
        sss_bake_stats st;
        if (sss_bake(&m, "big", &mat, &o, &f, &st, &err) != SSS_OK) fail_msg("%s", err.msg);
        q[g - SSS_GATHER_DIRECT] = assert_q_finite(&f);
        sss_file_free(&f);
    }
    assert_true(q[0] > 0 && fabs(q[1] - q[0]) <= 1e-3 * q[0]);
    sss_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(farSphereBakesTheSameAsAtTheOrigin),
        cmocka_unit_test(meshBeyondTheFloatRangeIsRefusedByBothGathers),
        cmocka_unit_test(nonManifoldMeshesBakeFinite),
        cmocka_unit_test(openSquareLosesLightAtItsBoundaryOnly),
        cmocka_unit_test(interpenetratingSpheresShadowTheBuriedPart),
        cmocka_unit_test(thinSlabIsCountedThickSphereIsNot),
        cmocka_unit_test(extremeScalesBakeFiniteAndScaleInvariant),
        cmocka_unit_test(singleChannelLimitsBake),
        cmocka_unit_test(lloydIsExactOnConstantAndTwoValuedDataAtAnyLevelCount),
        cmocka_unit_test(referenceDeltasKeepPrecisionUnderCancellation),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
