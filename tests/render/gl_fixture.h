/* gl_fixture.h: what the renderer tests share — the cmocka group setup,
 * one EGL offscreen context for the whole group (Mesa llvmpipe in CI), and
 * a bake of a test mesh with a preset material. Setup fails the group,
 * rather than skipping it, when no GL 4.3 context exists: these tests are
 * the viewer's, and CI has GL. Include once per test program, after
 * cmocka.h. */
#ifndef SSS_TEST_GL_FIXTURE_H
#define SSS_TEST_GL_FIXTURE_H

#include <stdio.h>
#include <string.h>
#include "sss/bake.h"
#include "sss/render.h"

static sss_offscreen *gl_ctx;

static int gl_setup(void **state)
{
    (void)state;
    sss_error err = {{0}};
    if (sss_offscreen_create(&gl_ctx, &err) != SSS_OK) {
        fprintf(stderr, "no offscreen GL context: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int gl_teardown(void **state)
{
    (void)state;
    sss_offscreen_destroy(gl_ctx);
    return 0;
}

/* Bakes m with preset `material` (grey: channel R's coefficients in all
 * three), mm per unit, dirs directions and storage q; own < 0: a plain
 * bake, else near terms at run time with `own` rings. */
static void bake_preset(const sss_mesh *m, const char *material, int grey, double mm, uint32_t dirs, sss_quant q,
                        int own, sss_bake_file *f)
{
    sss_material mat;
    assert_int_equal(sss_material_preset(material, &mat, NULL), SSS_OK);
    if (grey)
        for (int c = 1; c < 3; c++) mat.sigma_a[c] = mat.sigma_a[0], mat.sigmap_s[c] = mat.sigmap_s[0];
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.mm_per_unit = mm;
    o.n_dirs = dirs;
    o.quant = q;
    o.threads = 2;
    if (own >= 0) o.near_terms = SSS_NEAR_TERMS_RUNTIME, o.near_rings = (uint32_t)own;
    sss_error err = {{0}};
    if (sss_bake(m, "test", &mat, &o, f, NULL, &err) != SSS_OK) fail_msg("bake: %s", err.msg);
    assert_int_equal(f->near_terms, own >= 0 ? SSS_NEAR_TERMS_RUNTIME : 0u);
    if (own >= 0) assert_int_equal(f->near_rings, (uint32_t)own);
}

#endif
