/* test_near_terms.c: the own term split off at bake time and added back by the
 * reader (sss/nearterms.h, format 1.3 section OWNT; docs/accuracy_4000.md "Where
 * the error comes from"). On a torus, whose inner side is shadowed by the
 * opposite side (cast shadows, not only the terminator):
 *  - at every direction sample the reader's rows + near terms (the own
 *    term, and with --rings 1 the 1-ring too) give back the q of the same
 *    bake without the split (1e-5 of the largest q), whole-mesh and
 *    vertex-by-vertex reconstructions agreeing;
 *  - the stored rest is never negative and never above q;
 *  - at random directions the per-vertex error against the exact
 *    evaluator is well below the unsplit file's (measured 0.055 vs 0.103:
 *    the torus is coarse, so its neighbours' shadows keep a large share),
 *    and lower again with the 1-ring split off;
 *  - the bytes do not depend on the thread count;
 *  - the reader refuses an OWNT section it does not understand, the writer
 *    an OWNT in a scene bake; compression keeps the mark. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/vertex_error.h"
#include "sss/bake.h"
#include "sss/compress.h"
#include "sss/dipole.h"
#include "sss/exact.h"
#include "sss/hatweights.h"
#include "sss/nearterms.h"
#include "sss/reconstruct.h"
#include "test_util.h"

static sss_mesh g_mesh;
static sss_bake_file g_plain, g_own, g_ring; /* the same bake: all baked, own term split, own + 1-ring split
                                                * (through encode/decode) */
static sss_bake_file g_hat, g_hatr; /* with the hat-function weights: all baked, the near terms within 5 mm split */

static void bake_or_fail_w(uint32_t own, uint32_t rings, double radius, uint32_t weights, int threads,
                           sss_bake_file *out, uint8_t **bytes, size_t *nbytes)
{
    sss_material mat;
    sss_error err = {{0}};
    if (sss_material_preset("skin1", &mat, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 20.0;
    opt.n_dirs = 100;
    opt.threads = threads;
    opt.near_terms = own;
    opt.near_rings = rings;
    opt.near_radius_mm = radius;
    opt.weights = weights;
    sss_bake_file baked;
    if (sss_bake(&g_mesh, "torus", &mat, &opt, &baked, NULL, &err) != SSS_OK) fail_msg("bake: %s", err.msg);
    uint8_t *buf;
    size_t len;
    if (sss_file_encode(&baked, &buf, &len, &err) != SSS_OK) fail_msg("encode: %s", err.msg);
    sss_file_free(&baked);
    if (out && sss_file_decode(buf, len, "torus.sss", out, &err) != SSS_OK) fail_msg("decode: %s", err.msg);
    if (bytes) {
        *bytes = buf;
        *nbytes = len;
    } else {
        free(buf);
    }
}

static void bake_or_fail(uint32_t own, uint32_t rings, int threads, sss_bake_file *out, uint8_t **bytes,
                         size_t *nbytes)
{
    bake_or_fail_w(own, rings, 0.0, SSS_WEIGHTS_POINT, threads, out, bytes, nbytes);
}

static int setup(void **state)
{
    (void)state;
    sss_error err = {{0}};
    /* R = 1, r = 0.45: the hole is narrow enough for the inner side to
     * shadow itself over a wide range of light directions */
    if (sss_gen_torus(&g_mesh, 1.0, 0.45, 48, 24, &err) != SSS_OK) return -1;
    bake_or_fail(0, 0, 2, &g_plain, NULL, NULL);
    bake_or_fail(SSS_NEAR_TERMS_RUNTIME, 0, 2, &g_own, NULL, NULL);
    bake_or_fail(SSS_NEAR_TERMS_RUNTIME, 1, 2, &g_ring, NULL, NULL);
    bake_or_fail_w(0, 0, 0.0, SSS_WEIGHTS_HAT, 2, &g_hat, NULL, NULL);
    bake_or_fail_w(SSS_NEAR_TERMS_RUNTIME, 0, 5.0, SSS_WEIGHTS_HAT, 2, &g_hatr, NULL, NULL);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    sss_file_free(&g_plain);
    sss_file_free(&g_own);
    sss_file_free(&g_ring);
    sss_file_free(&g_hat);
    sss_file_free(&g_hatr);
    sss_mesh_free(&g_mesh);
    return 0;
}

static void fileIsMarked(void **state)
{
    (void)state;
    assert_int_equal(g_plain.near_terms, 0);
    assert_int_equal(g_own.near_terms, SSS_NEAR_TERMS_RUNTIME);
    /* both record ε (section NBHD), which makes them 1.4 files; without it
     * the own term alone makes a file 1.3 (docs/format.md §5.9) */
    assert_int_equal(g_plain.version_minor, 4);
    assert_int_equal(g_own.version_minor, 4);
    assert_true(g_own.eps == 1e-3);
    sss_bake_file h = g_own;
    h.eps = 0.0;
    uint8_t *buf;
    size_t len;
    sss_error err = {{0}};
    assert_int_equal(sss_file_encode(&h, &buf, &len, &err), SSS_OK);
    assert_int_equal(buf[10], 3);
    free(buf);
    assert_non_null(strstr(g_own.params_json, "\"own_term\":\"runtime"));
}

/* Rows + own term at ω_j = the unsplit q_j; 0 ≤ rest ≤ q; and the split
 * takes something off (the own term is not empty). */
static void samples_restore_q_of(const sss_bake_file *plain, const sss_bake_file *own, double min_share)
{
    const uint32_t nv = own->mesh.nv, C = own->channels, nd = own->dirs.n;
    const size_t row = (size_t)nv * C;
    sss_error err = {{0}};
    sss_reconstruct *rc;
    assert_int_equal(sss_reconstruct_create(own, &rc, &err), SSS_OK);
    assert_true(sss_reconstruct_has_near_terms(rc));
    float *r = malloc(row * sizeof *r);
    assert_non_null(r);
    double qmax = 0.0, worst = 0.0, taken = 0.0, total = 0.0;
    for (size_t k = 0; k < (size_t)nd * row; k++) {
        qmax = fmax(qmax, plain->q[k]);
        assert_true(own->q[k] >= 0.0f);
        assert_true(own->q[k] <= plain->q[k] * (1.0f + 1e-6f) + 1e-30f);
        taken += plain->q[k] - own->q[k];
        total += plain->q[k];
    }
    for (uint32_t j = 0; j < nd; j++) {
        sss_reconstruct_eval(rc, own->dirs.dir + 3 * (size_t)j, SSS_INTERP_TRIANGLE, r);
        for (size_t k = 0; k < row; k++) worst = fmax(worst, fabs((double)r[k] - plain->q[(size_t)j * row + k]));
    }
    print_message("%u rings, radius %g mm: near terms %.1f %% of all q; rows + near terms vs unsplit q at the samples: "
                  "max |diff| %.3g of max q\n", own->near_rings, own->near_radius_mm, 100.0 * taken / total, worst / qmax);
    assert_true(taken > min_share * total);
    assert_true(worst <= 1e-5 * qmax);
    /* one vertex at a time (sss-stat --query) gives the same floats */
    float one[SSS_MAX_CHANNELS];
    const double *d = own->dirs.dir + 3 * (size_t)(nd / 3);
    sss_reconstruct_eval(rc, d, SSS_INTERP_TRIANGLE, r);
    for (uint32_t v = 0; v < nv; v += 37) {
        sss_reconstruct_eval_vertex(rc, v, d, one);
        for (uint32_t c = 0; c < C; c++) assert_float_equal(one[c], r[(size_t)v * C + c], 1e-6 * qmax);
    }
    free(r);
    sss_reconstruct_destroy(rc);
}

static void samples_restore_q(const sss_bake_file *own, double min_share)
{
    samples_restore_q_of(&g_plain, own, min_share);
}

static void samplesRestoreQ(void **state)
{
    (void)state;
    samples_restore_q(&g_own, 0.1);
    samples_restore_q(&g_ring, 0.3);
    /* the near terms by radius, with the hat-function weights (format 1.5):
     * the reader's weights, built from the file's entries alone, are the
     * bake's */
    assert_int_equal(g_hatr.weights, SSS_WEIGHTS_HAT);
    assert_true(g_hatr.near_radius_mm == 5.0);
    assert_int_equal(g_hatr.version_minor, 5);
    samples_restore_q_of(&g_hat, &g_hatr, 0.3);
}

/* Between the samples the split file is much closer to the exact q. */
static void errorShrinksBetweenSamples(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_exact *e;
    assert_int_equal(sss_exact_create(&g_plain, &e, &err), SSS_OK);
    sss_vertex_error a, b;
    assert_int_equal(sss_vertex_error_vs_exact(&g_plain, e, 40, 7, &a, &err), SSS_OK);
    sss_exact_destroy(e);
    assert_int_equal(sss_exact_create(&g_own, &e, &err), SSS_OK);
    assert_int_equal(sss_vertex_error_vs_exact(&g_own, e, 40, 7, &b, &err), SSS_OK);
    sss_exact_destroy(e);
    const uint32_t C = g_plain.channels;
    print_message("per-vertex rel. RMS at 40 random directions: %.4f without the split, %.4f with it\n", a.rel_rms[C],
                  b.rel_rms[C]);
    assert_true(b.rel_rms[C] > 0.0);
    assert_true(b.rel_rms[C] < 0.6 * a.rel_rms[C]);
    sss_vertex_error c1;
    assert_int_equal(sss_exact_create(&g_ring, &e, &err), SSS_OK);
    assert_int_equal(sss_vertex_error_vs_exact(&g_ring, e, 40, 7, &c1, &err), SSS_OK);
    sss_exact_destroy(e);
    print_message("with the 1-ring split off too: %.4f\n", c1.rel_rms[C]);
    assert_true(c1.rel_rms[C] < 0.6 * b.rel_rms[C]);
}

static void threadsGiveSameBytes(void **state)
{
    (void)state;
    uint8_t *b1, *b2;
    size_t n1, n2;
    bake_or_fail(SSS_NEAR_TERMS_RUNTIME, 1, 1, NULL, &b1, &n1);
    bake_or_fail(SSS_NEAR_TERMS_RUNTIME, 1, 2, NULL, &b2, &n2);
    assert_int_equal(n1, n2);
    assert_memory_equal(b1, b2, n1);
    free(b1);
    free(b2);
}

static void wr32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; k++) p[k] = (uint8_t)(v >> (8 * k));
}

/* An OWNT whose mode this reader does not know is refused by name. A
 * scene bake with the direction-set effect may split its rows (format.md
 * §5.14): written and read back with the mark. */
static void readerAndWriterRefuse(void **state)
{
    (void)state;
    sss_error err = {{0}};
    uint8_t *buf;
    size_t len;
    assert_int_equal(sss_file_encode(&g_own, &buf, &len, &err), SSS_OK);
    const uint32_t nsec = test_rd32(buf + 12);
    int found = 0;
    for (uint32_t i = 0; i < nsec; i++) {
        uint8_t *e = buf + 24 + 40 * (size_t)i;
        if (memcmp(e, "OWNT", 4) != 0) continue;
        found = 1;
        assert_true(test_rd32(e + 4) & 1u); /* required: an older reader must refuse */
        const uint64_t off = test_rd32(e + 8) | (uint64_t)test_rd32(e + 12) << 32;
        wr32(buf + off, 2);
        wr32(e + 32, sss_crc32(0, buf + off, 8));
    }
    assert_true(found);
    wr32(buf + 24 + 40 * (size_t)nsec, sss_crc32(0, buf, 24 + 40 * (size_t)nsec));
    sss_bake_file f;
    sss_result dr = sss_file_decode(buf, len, "bad.sss", &f, &err);
    print_message("refused: %s\n", err.msg);
    assert_int_equal(dr, SSS_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "OWNT"));
    free(buf);

    sss_bake_file s = g_own;
    s.fx.mask = SSS_FX_DIR_SET | (g_own.channels == 3 ? SSS_FX_RGB : 0);
    assert_int_equal(sss_file_encode(&s, &buf, &len, &err), SSS_OK);
    sss_bake_file back;
    assert_int_equal(sss_file_decode(buf, len, "scene.sss", &back, &err), SSS_OK);
    assert_int_equal(back.near_terms, SSS_NEAR_TERMS_RUNTIME);
    assert_int_equal(back.fx.mask, s.fx.mask);
    sss_file_free(&back);
    free(buf);
}

/* Compressing a split file keeps the mark (the rows compressed are the
 * rest, and the reader must still add the own term). */
static void compressionKeepsTheMark(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_compress_opts co;
    sss_compress_opts_default(&co);
    sss_bake_file c;
    assert_int_equal(sss_compress(&g_own, &co, &c, &err), SSS_OK);
    uint8_t *buf;
    size_t len;
    assert_int_equal(sss_file_encode(&c, &buf, &len, &err), SSS_OK);
    sss_file_free(&c);
    assert_int_equal(sss_file_decode(buf, len, "c.sss", &c, &err), SSS_OK);
    assert_int_equal(c.near_terms, SSS_NEAR_TERMS_RUNTIME);
    assert_int_equal(c.version_minor, c.eps > 0 ? 4 : 3); /* OWNT is 1.3; NBHD (the bake's ε) 1.4 */
    sss_file_free(&c);
    free(buf);
    /* ... and which terms and weights (NRAD, QUAD): a compressed file
     * without them had its readers add the own term alone with point
     * weights back to rows that lack every term within the radius (the
     * 23K dragon at 20 cm: image RMS 0.16 instead of 1e-3) */
    assert_int_equal(sss_compress(&g_hatr, &co, &c, &err), SSS_OK);
    assert_int_equal(sss_file_encode(&c, &buf, &len, &err), SSS_OK);
    sss_file_free(&c);
    assert_int_equal(sss_file_decode(buf, len, "c.sss", &c, &err), SSS_OK);
    assert_int_equal(c.version_minor, 5);
    assert_true(c.near_radius_mm == g_hatr.near_radius_mm && c.near_rings == 0);
    assert_int_equal(c.weights, SSS_WEIGHTS_HAT);
    sss_weights a, b;
    assert_int_equal(sss_near_build_file(&g_hatr, &a, &err), SSS_OK);
    assert_int_equal(sss_near_build_file(&c, &b, &err), SSS_OK);
    assert_int_equal(a.start[c.mesh.nv], b.start[c.mesh.nv]);
    assert_memory_equal(a.w, b.w, a.start[c.mesh.nv] * 3 * sizeof *a.w);
    sss_weights_free(&a);
    sss_weights_free(&b);
    sss_file_free(&c);
    free(buf);
}

/* The near rows: entry 0 is the vertex, then its rings ascending; the 1-ring
 * of a grid vertex is its edge neighbours; coincident copies (a seam with
 * duplicated vertices) join ring 0 and share one disk by area, as nbhd.c's
 * self term does. */
static void nearRowsHoldRingsAndCopies(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_material mat;
    assert_int_equal(sss_material_preset("skin1", &mat, &err), SSS_OK);
    sss_mesh plane;
    assert_int_equal(sss_gen_plane(&plane, 1.0, 1.0, 4, 4, &err), SSS_OK); /* 5 x 5 vertices */
    sss_weights n0, n1;
    assert_int_equal(sss_near_build(&plane, &mat, 10.0, 3, 0, &n0, &err), SSS_OK);
    assert_int_equal(sss_near_build(&plane, &mat, 10.0, 3, 1, &n1, &err), SSS_OK);
    for (uint32_t o = 0; o < plane.nv; o++) {
        assert_int_equal(n0.start[o + 1] - n0.start[o], 1);
        assert_int_equal(n0.idx[n0.start[o]], o);
        assert_int_equal(n1.idx[n1.start[o]], o);
        for (uint64_t a = n1.start[o] + 2; a < n1.start[o + 1]; a++) assert_true(n1.idx[a] > n1.idx[a - 1]);
        /* the own weight does not depend on the rings */
        for (uint32_t c = 0; c < 3; c++) assert_float_equal(n0.w[n0.start[o] * 3 + c], n1.w[n1.start[o] * 3 + c], 0.0);
    }
    /* the centre vertex of a 4 x 4 quad grid: 6 edge neighbours (two
     * triangles per quad), so 7 entries */
    assert_int_equal(n1.start[13] - n1.start[12], 7);
    sss_weights_free(&n0);
    sss_weights_free(&n1);
    sss_mesh_free(&plane);

    /* two triangles meeting along an edge whose ends are duplicated (a
     * seam): 0 (0,0), 1 (1,0), 2 (0,1) and 3 (1,0), 4 (0,1), 5 (1,1) */
    sss_mesh seam;
    assert_int_equal(sss_mesh_alloc(&seam, 6, 2, &err), SSS_OK);
    const float P[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    const uint32_t T[6] = {0, 1, 2, 3, 5, 4};
    memcpy(seam.pos, P, sizeof P);
    memcpy(seam.tri, T, sizeof T);
    sss_weights ns;
    assert_int_equal(sss_near_build(&seam, &mat, 10.0, 1, 0, &ns, &err), SSS_OK);
    assert_int_equal(ns.start[2] - ns.start[1], 2); /* vertex 1 and its copy 3 */
    assert_int_equal(ns.idx[ns.start[1]], 1);
    assert_int_equal(ns.idx[ns.start[1] + 1], 3);
    assert_int_equal(ns.start[1] - ns.start[0], 1); /* vertex 0 has no copy */
    /* the copies share the disk of their summed area: each gets its share */
    sss_dipole dip;
    assert_int_equal(sss_dipole_init(&dip, mat.sigma_a[1], mat.sigmap_s[1], mat.eta), SSS_OK);
    sss_weights g1;
    assert_int_equal(sss_near_build(&seam, &mat, 10.0, 3, 0, &g1, &err), SSS_OK);
    const double garea = 2.0 * (0.5 / 3.0) * 100.0; /* mm²: a third of each triangle's 0.5, twice */
    const double whole = sss_rd_disk(&dip, sqrt(garea / 3.14159265358979323846)) / 3.14159265358979323846;
    const double got = (double)g1.w[g1.start[1] * 3 + 1] + g1.w[(g1.start[1] + 1) * 3 + 1];
    assert_float_equal(got, whole, 1e-6 * whole);
    sss_weights_free(&ns);
    sss_weights_free(&g1);
    sss_mesh_free(&seam);
}


/* The rows of a radius (section NRAD): every vertex within it, connected
 * to the receiver or not, whatever the rings; and with the hat-function weights
 * the reader's weights (corrections of the rows' entries alone) have the
 * bits of the bake's (the corrections of whole rows). */
static void nearRowsByRadiusAndHatWeights(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_material mat;
    assert_int_equal(sss_material_preset("skin1", &mat, &err), SSS_OK);
    sss_mesh plane;
    assert_int_equal(sss_gen_plane(&plane, 1.0, 1.0, 8, 8, &err), SSS_OK); /* 9 x 9 vertices, 1.25 mm at 10 mm/unit */
    for (int k = 0; k < 2; k++) {
        const double radius = k ? 2.6 : 1.3;
        const sss_near_spec spec = {.radius_mm = radius};
        sss_weights nr;
        assert_int_equal(sss_near_build_spec(&plane, &mat, 10.0, 3, &spec, NULL, &nr, &err), SSS_OK);
        for (uint32_t o = 0; o < plane.nv; o++) {
            uint32_t want = 0;
            for (uint32_t i = 0; i < plane.nv; i++) {
                double d2 = 0.0;
                for (int x = 0; x < 3; x++) {
                    const double dx = ((double)plane.pos[3 * i + x] - plane.pos[3 * o + x]) * 10.0;
                    d2 += dx * dx;
                }
                want += sqrt(d2) <= radius;
            }
            assert_int_equal(nr.start[o + 1] - nr.start[o], want);
            assert_int_equal(nr.idx[nr.start[o]], o);
        }
        sss_weights_free(&nr);
    }

    /* two parallel sheets 0.5 mm apart, not connected by any edge: a
     * radius takes the other sheet's vertices too (the far side of a thin
     * part scatters through it, docs/format.md §5.17), which a walk along
     * the mesh's edges would miss */
    sss_mesh two;
    assert_int_equal(sss_mesh_alloc(&two, 2 * plane.nv, 2 * plane.nf, &err), SSS_OK);
    for (uint32_t v = 0; v < plane.nv; v++)
        for (int x = 0; x < 3; x++) {
            two.pos[3 * v + x] = plane.pos[3 * v + x];
            two.pos[3 * (plane.nv + v) + x] = plane.pos[3 * v + x] + (x == 2 ? 0.05f : 0.0f);
        }
    for (uint32_t t = 0; t < plane.nf; t++)
        for (int k = 0; k < 3; k++) {
            two.tri[3 * t + k] = plane.tri[3 * t + k];
            two.tri[3 * (plane.nf + t) + k] = plane.tri[3 * t + (2 - k)] + plane.nv; /* facing the other way */
        }
    const sss_near_spec spec2 = {.radius_mm = 1.3};
    sss_weights tw;
    assert_int_equal(sss_near_build_spec(&two, &mat, 10.0, 3, &spec2, NULL, &tw, &err), SSS_OK);
    uint32_t across = 0;
    for (uint32_t o = 0; o < two.nv; o++) {
        uint32_t want = 0;
        for (uint32_t i = 0; i < two.nv; i++) {
            double d2 = 0.0;
            for (int x = 0; x < 3; x++) {
                const double dx = ((double)two.pos[3 * i + x] - two.pos[3 * o + x]) * 10.0;
                d2 += dx * dx;
            }
            want += sqrt(d2) <= 1.3;
        }
        assert_int_equal(tw.start[o + 1] - tw.start[o], want);
        for (uint32_t e = tw.start[o]; e < tw.start[o + 1]; e++) across += (tw.idx[e] < plane.nv) != (o < plane.nv);
    }
    assert_true(across > 0);
    sss_weights_free(&tw);
    sss_mesh_free(&two);
    sss_mesh_free(&plane);

    /* hat weights: reader (restricted corrections) vs bake (whole rows) */
    sss_mesh m;
    assert_int_equal(sss_mesh_copy(&g_hatr.mesh, &m, &err), SSS_OK);
    m.area = malloc((size_t)m.nv * sizeof *m.area);
    assert_non_null(m.area);
    sss_mesh_vertex_areas(&m, m.area);
    sss_dipole d[3];
    for (int c = 0; c < 3; c++)
        assert_int_equal(sss_dipole_init(&d[c], mat.sigma_a[c], mat.sigmap_s[c], mat.eta), SSS_OK);
    const double R = sss_cutoff_radius_mm(&m, g_hatr.mm_per_unit, d, 3, g_hatr.eps, NULL);
    sss_weights full, a, b;
    assert_int_equal(sss_hat_corrections(&m, g_hatr.mm_per_unit, d, 3, R, NULL, 0, NULL, &full, &err), SSS_OK);
    const sss_near_spec spec = {.radius_mm = g_hatr.near_radius_mm, .weights = SSS_WEIGHTS_HAT, .eps = g_hatr.eps};
    assert_int_equal(sss_near_build_spec(&m, &mat, g_hatr.mm_per_unit, 3, &spec, &full, &a, &err), SSS_OK);
    assert_int_equal(sss_near_build_file(&g_hatr, &b, &err), SSS_OK);
    assert_int_equal(a.start[m.nv], b.start[m.nv]);
    assert_memory_equal(a.idx, b.idx, a.start[m.nv] * sizeof *a.idx);
    assert_memory_equal(a.w, b.w, a.start[m.nv] * 3 * sizeof *a.w);
    print_message("near terms within %g mm, hat weights: %.1f entries per row, reader's weights = bake's\n",
                  g_hatr.near_radius_mm, (double)a.start[m.nv] / m.nv);
    sss_weights_free(&full);
    sss_weights_free(&a);
    sss_weights_free(&b);
    sss_mesh_free(&m);
}

/* The radius from the material (sss_near_radius_material): the disk that
 * holds the fraction in every channel, exactly so in the widest one. */
static void materialRadiusHoldsTheFraction(void **state)
{
    (void)state;
    for (int p = 0; p < sss_material_preset_count(); p++) {
        sss_material m;
        assert_int_equal(sss_material_preset(sss_material_preset_name(p), &m, NULL), SSS_OK);
        const double f = SSS_NEAR_FRACTION_DEFAULT, R = sss_near_radius_material(&m, 3, f);
        assert_true(R > 0.0 && R < 1e4);
        double tightest = 0.0;
        for (int c = 0; c < 3; c++) {
            sss_dipole d;
            assert_int_equal(sss_dipole_init(&d, m.sigma_a[c], m.sigmap_s[c], m.eta), SSS_OK);
            const double held = sss_rd_disk(&d, R) / sss_rd_total(&d);
            assert_true(held >= f - 1e-9);
            tightest = c ? fmin(tightest, held) : held;
        }
        assert_true(tightest <= f + 1e-6);
        assert_true(sss_near_radius_material(&m, 3, 0.99) > R);
        assert_true(sss_near_radius_material(&m, 1, f) <= R);
        assert_true(sss_near_radius_material(&m, 3, 0.0) == 0.0 && sss_near_radius_material(&m, 3, 1.0) == 0.0);
    }
}

/* Near terms sized by the material: one sphere (20 mm, skin1) tessellated
 * at 2562 and 10242 vertices (the coarse vertices are vertices of the fine
 * one) gets the same radius, so the same physical neighbourhood: where lit
 * (n.w >= 0.4, docs/physics.md §9) the near terms' part of q and the whole
 * q (rows + near terms) agree within 1 % at every shared vertex and every
 * direction sample. One ring would hold half the distance on the fine
 * mesh and so a different part of q. */
static void materialRadiusSameOnFineAndCoarseSphere(void **state)
{
    (void)state;
    sss_material m;
    sss_error err = {{0}};
    assert_int_equal(sss_material_preset("skin1", &m, NULL), SSS_OK);
    sss_bake_file f[2];
    for (int k = 0; k < 2; k++) {
        sss_mesh mesh;
        assert_int_equal(sss_gen_sphere(&mesh, 1.0, 4 + (unsigned)k, &err), SSS_OK);
        sss_bake_options o;
        memset(&o, 0, sizeof o);
        o.mm_per_unit = 20.0;
        o.n_dirs = 8;
        o.weights = SSS_WEIGHTS_HAT;
        o.near_terms = SSS_NEAR_TERMS_RUNTIME;
        o.near_fraction = SSS_NEAR_FRACTION_DEFAULT;
        o.threads = 2;
        if (sss_bake(&mesh, "sphere", &m, &o, &f[k], NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
        sss_mesh_free(&mesh);
        assert_non_null(strstr(f[k].params_json, "\"near_fraction\":0.95"));
    }
    const double R = sss_near_radius_material(&m, 3, SSS_NEAR_FRACTION_DEFAULT);
    assert_true(f[0].near_radius_mm == R && f[1].near_radius_mm == R && f[0].near_rings == 0);
    const uint32_t n0 = f[0].mesh.nv, n1 = f[1].mesh.nv, C = f[0].channels;
    assert_true(n1 > 3 * n0);
    sss_reconstruct *rc[2];
    float *tot[2];
    for (int k = 0; k < 2; k++) {
        assert_int_equal(sss_reconstruct_create(&f[k], &rc[k], &err), SSS_OK);
        tot[k] = malloc((size_t)f[k].mesh.nv * C * sizeof(float));
        assert_non_null(tot[k]);
    }
    double worst_q = 0.0, worst_near = 0.0, share = 1.0;
    for (uint32_t j = 0; j < f[0].dirs.n; j++) {
        const double *w = f[0].dirs.dir + 3 * (size_t)j;
        for (int k = 0; k < 2; k++) sss_reconstruct_eval(rc[k], w, SSS_INTERP_TRIANGLE, tot[k]);
        for (uint32_t v = 0; v < n0; v++) {
            assert_memory_equal(f[0].mesh.pos + 3 * (size_t)v, f[1].mesh.pos + 3 * (size_t)v, 3 * sizeof(float));
            const float *n = f[0].mesh.nrm + 3 * (size_t)v;
            if (n[0] * w[0] + n[1] * w[1] + n[2] * w[2] < 0.4) continue;
            for (uint32_t c = 0; c < C; c++) {
                const double a = tot[0][(size_t)v * C + c], b = tot[1][(size_t)v * C + c];
                const double na = a - f[0].q[((size_t)j * n0 + v) * C + c], nb = b - f[1].q[((size_t)j * n1 + v) * C + c];
                worst_q = fmax(worst_q, fabs(a / b - 1.0));
                worst_near = fmax(worst_near, fabs(na / nb - 1.0));
                share = fmin(share, na / a);
            }
        }
    }
    print_message("sphere at 2562 / 10242 vertices, near terms within %.3g mm (%.2f of R_d,total): near part differs "
                  "by %.3f %%, q by %.3f %% (near part at least %.1f %% of q)\n", R, SSS_NEAR_FRACTION_DEFAULT,
                  100 * worst_near, 100 * worst_q, 100 * share);
    assert_true(worst_near <= 0.01);
    assert_true(worst_q <= 0.01);
    assert_true(share > 0.5);
    /* what one ring would have split off: the near point weights' sum (the
     * near part under a uniform irradiance) at the shared vertices, coarse
     * over fine, is about 2 (half the distance: R_d is peaked, so less than
     * the 4 of the area) where the radius gives 1 within the point rule's
     * own tessellation error (3 %, docs/physics.md §9) */
    double ratio[2] = {0, 0};
    for (int byring = 0; byring < 2; byring++) {
        const sss_near_spec spec = {.rings = byring ? 1 : 0, .radius_mm = byring ? 0.0 : R};
        sss_weights w[2];
        for (int k = 0; k < 2; k++)
            assert_int_equal(sss_near_build_spec(&f[k].mesh, &m, 20.0, 3, &spec, NULL, &w[k], &err), SSS_OK);
        double sa = 0.0, sb = 0.0;
        for (uint32_t v = 0; v < n0; v++) {
            for (uint32_t e = w[0].start[v]; e < w[0].start[v + 1]; e++) sa += w[0].w[3 * (size_t)e];
            for (uint32_t e = w[1].start[v]; e < w[1].start[v + 1]; e++) sb += w[1].w[3 * (size_t)e];
        }
        ratio[byring] = sa / sb;
        for (int k = 0; k < 2; k++) sss_weights_free(&w[k]);
    }
    print_message("near weights' sum (red), coarse / fine: %.3f within the radius, %.3f with one ring\n", ratio[0],
                  ratio[1]);
    assert_true(fabs(ratio[0] - 1.0) < 0.05);
    assert_true(ratio[1] > 1.6);
    for (int k = 0; k < 2; k++) {
        sss_reconstruct_destroy(rc[k]);
        free(tot[k]);
        sss_file_free(&f[k]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fileIsMarked),
        cmocka_unit_test(samplesRestoreQ),
        cmocka_unit_test(errorShrinksBetweenSamples),
        cmocka_unit_test(threadsGiveSameBytes),
        cmocka_unit_test(readerAndWriterRefuse),
        cmocka_unit_test(compressionKeepsTheMark),
        cmocka_unit_test(nearRowsHoldRingsAndCopies),
        cmocka_unit_test(nearRowsByRadiusAndHatWeights),
        cmocka_unit_test(materialRadiusHoldsTheFraction),
        cmocka_unit_test(materialRadiusSameOnFineAndCoarseSphere),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
