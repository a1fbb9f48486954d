/* sss-view: interactive and offscreen viewer of baked translucent meshes.
 * See `sss-view --help`. */
#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "edit.h"
#include "pose.h"
#include "sss/cli.h"
#include "sss/clock.h"
#include "sss/decode.h"
#include "sss/fileio.h"
#include "sss/format.h"
#include "sss/render.h"
#include "sss/scene_edit.h"
#include "sss/vec3.h"

static const char *TOOL = "sss-view";

/* The most --light and the most --point-light one command line takes: each
 * light is one more evaluation of q per frame (a direction-set decode or a
 * §3.3 shell interpolation over every vertex), and 16 of either already
 * make a frame 16 times the one-light frame; a scene file takes more
 * (docs/viewer.md, "Several lights and point lights"). */
#define VIEW_LIGHTS_MAX 16

static void usage(FILE *f)
{
    fprintf(f,
        "usage: sss-view FILE.sss [options]\n"
        "       sss-view FILE.sss --offscreen --out IMG.png|IMG.exr [--size WxH] [--light X,Y,Z] [--view X,Y,Z] [--exposure E]\n"
        "       sss-view --scene S.json [--time T] [--offscreen --out IMG.png|IMG.exr]   (a deforming or editable object, no file)\n"
        "Shows a baked translucent mesh: every frame reconstructs each vertex's scattering q for the\n"
        "light direction (GPU compute shader by default, or the CPU decoder) and shades\n"
        "L = E q F_t(eta, n.w_o) + the surface terms, shadowed. Any storage form: float, lloyd8, and the\n"
        "compressed sh and refs (SH codes; reference rows + SH-coded deltas), decoded per frame.\n\n"
        "options:\n"
        "  --offscreen          render one image without a window (EGL surfaceless) and exit\n"
        "  --out FILE           image to write: .png (8-bit sRGB, tone-mapped) or .exr (linear float)\n"
        "  --size WxH           image or window size (default 800x600)\n"
        "  --light X,Y,Z        direction towards the light (default 0,0,1); up to 16 --light, summed\n"
        "  --point-light X,Y,Z[,I]   a point light at X,Y,Z (mesh units) of intensity I per steradian\n"
        "                       (default: irradiance 1 at the object's centre, times --intensity); up\n"
        "                       to 16, summed with the --light ones; needs a file baked with\n"
        "                       sss-bake --point-light (distance shells, Hao & Varshney 2004 sec. 3.3)\n"
        "  --view X,Y,Z         direction from the object towards the camera (default 0,0,1)\n"
        "  --exposure E         radiance multiplier before tone mapping (default: 1 / (I q_slab), q_slab\n"
        "                       the q of a flat surface of the file's material lit head-on: the\n"
        "                       brightest lit parts reach about 1, neither black nor clipped)\n"
        "  --intensity I        light irradiance E (default 1)\n"
        "  --tonemap clamp|reinhard   (default clamp: values in [0,1], the measurement convention)\n"
        "  --exit jensen|normalised  the subsurface exit term: Jensen's F_t (default, as the paper), or\n"
        "                       F_t / c(eta) so that the radiance integrates to the dipole's exitance\n"
        "                       (docs/physics.md section 4; closer to the path-traced reference in marble)\n"
        "  --cpu                evaluate on the CPU (C decoder; with --scene, the CPU sum of the lights)\n"
        "  --no-vector          files baked with --vector: draw q's rows, not the vector integrals Q\n"
        "                       interpolated and dotted with the light (for comparison)\n"
        "  --no-scatter, --no-specular   drop one of the two terms\n"
        "  --diffuse RHO        share in [0, 1] of the Fresnel-reflected light the surface reflects\n"
        "                       diffusely (Lambert) instead of in the specular lobe (default 0)\n"
        "  --no-surface-shadow  do not shadow the surface terms (by default the shadow map of\n"
        "                       --shadow-size zeroes them where the light is blocked: docs/viewer.md)\n"
        "  --interp triangle|nearest4  q between the direction samples: inside their triangle\n"
        "                       (default), or the paper's 4 nearest samples (both paths)\n"
        "  --sh-tables uniform|storage   GPU path, SH codes: the frame's tables as a uniform block or a\n"
        "                       storage buffer; default: uniform on a software GL, storage on a GPU.\n"
        "                       Same q to the bit, only the time differs (docs/viewer.md)\n"
        "  --no-own-term        files baked with --own-term runtime: draw the stored rows alone, without\n"
        "                       the near terms the viewer adds back (for comparison)\n"
        "  --near-visibility rays|map   where those near terms' visibility comes from: the bake's own ray,\n"
        "                       traced on the GPU (default), or a shadow map (cheaper on a software GL,\n"
        "                       wrong near shadow outlines: docs/viewer.md)\n"
        "  --shadow-size N      the shadow map's texels per side (near terms, surface terms), 256 ... 8192\n"
        "                       (default 2048; finer agrees\n"
        "                       with the bake's rays at more vertices)\n"
        "  --single on|off      single scattering per pixel (docs/layers.md section 8); default: on when\n"
        "                       the file's effect set has single-scattering\n"
        "  --single-samples N   its segments along the refracted view ray, 1 ... 1024 (default 32)\n"
        "  --single-march segments|seed   the per-segment closed form (default) or seed 002's Algorithm 1\n"
        "  --wireframe          draw edges over the surface\n"
        "  --screenshot FILE    where the P key saves a PNG (window mode)\n"
        "  --bench N            offscreen: time N frames and print JSON timings on stdout\n"
        "  --scene S.json       the scene's lights (summed, each from the effect the file records)\n"
        "                       and camera instead of --light/--view (docs/scenes.md)\n"
        "  --time T             without FILE.sss: the pose of the scene's deforming object at T seconds\n"
        "                       (the window starts there and plays), q evaluated on the CPU (docs/deformable.md)\n"
        "  --splat              with --time --offscreen: q by the GPU's multiresolution splatting (Chen et al.\n"
        "                       2012) instead of the object-space path (docs/deformable.md §9)\n"
        "  --splat-levels N     the splatting's levels, 1 ... 3 (default 3)\n"
        "  --splat-uniform      the splatting without the adaptive selection: every light texel a sample\n"
        "  --save-scene PATH    an editable object: where E (or the panel's button) writes the scene with the\n"
        "                       edited material (default NAME.edited.json next to S.json; never S.json itself);\n"
        "                       with --offscreen, written after the image (docs/heterogeneous.md §9.6)\n"
        "  -h, --help           this text\n\n"
        "window controls:\n%s",
        sss_app_controls_help);
}

/* The command line, as parse() fills it. The view parameters the options set
 * go straight into p; --tonemap and --cpu are read as ints (a table row
 * stores an int) and moved into p's enumerations by parse(). The run
 * functions below take p as their working copy (scene cameras, --bench's
 * moving light, the window's background). */
typedef struct view_args {
    const char *path;  /* FILE.sss */
    const char *out;   /* --out IMG.png|IMG.exr, or NULL */
    const char *shot;  /* --screenshot, or NULL */
    const char *scene; /* --scene S.json, or NULL */
    const char *save_scene; /* --save-scene PATH, or NULL */
    double time;       /* --time T: the pose of a deforming object (docs/deformable.md) */
    int time_given;
    int splat, splat_levels, splat_uniform; /* --splat, --splat-levels, --splat-uniform */
    int offscreen;     /* --offscreen */
    int size[2];       /* --size W H */
    int nbench;        /* --bench N (0: none) */
    double intensity;  /* --intensity: every channel of p.light_rgb */
    int exposure_given; /* --exposure given; else 1 / the file material's flat-slab q */
    int tonemap, cpu;  /* --tonemap, --cpu */
    int no_vector;     /* --no-vector: q's rows of a file with Q */
    sss_view_params p;
    /* --light (each given one) and --point-light X,Y,Z[,I] (I 0: the
     * default); several --light or any --point-light are summed as a
     * scene's lights are (lights_scene) */
    double lights[VIEW_LIGHTS_MAX][3], points[VIEW_LIGHTS_MAX][4];
    int nlights, npoints;
    const char *input[2]; /* the files read (FILE.sss, --scene): no output may be one of them */
    sss_inputs inputs;
} view_args;

/* Reads argv into *a: the option table, then the one combination it cannot
 * say. Returns SSS_CLI_RUN, or the exit status (0 after --help, 2 after a
 * message on stderr). */
static int parse(int argc, char **argv, view_args *a)
{
    *a = (view_args){.size = {800, 600}, .intensity = 1.0};
    sss_view_params_default(&a->p);
    a->p.background[0] = a->p.background[1] = a->p.background[2] = 0.0f;
    a->tonemap = (int)a->p.tonemap;
    static const char *const tonemaps[] = {"clamp", "reinhard", NULL};
    static const int tonemap_values[] = {SSS_TONEMAP_CLAMP, SSS_TONEMAP_REINHARD};
    static const char *const visibilities[] = {"rays", "map", NULL};
    static const int visibility_values[] = {SSS_NEAR_RAYS, SSS_NEAR_MAP};
    static const char *const interps[] = {"triangle", "nearest4", NULL};
    static const int interp_values[] = {SSS_INTERP_TRIANGLE, SSS_INTERP_NEAREST4};
    static const char *const exits[] = {"jensen", "normalised", NULL};
    static const int off[] = {0};
    static const char *const onoff[] = {"on", "off", NULL};
    static const int onoff_values[] = {1, -1};
    static const char *const tables[] = {"uniform", "storage", NULL};
    static const int table_values[] = {SSS_SH_TABLES_UNIFORM, SSS_SH_TABLES_STORAGE};
    static const char *const marches[] = {"segments", "seed", NULL};
    static const int march_values[] = {SSS_SINGLE_MARCH_SEGMENTS, SSS_SINGLE_MARCH_SEED};
    /* sss-view's own wordings where they differ from the library's defaults */
    static const char *const positive = "%s: %s: '%s' must be a number > %g and <= %g\n";
    const sss_cli_opt opts[] = {
        {.name = "--offscreen", .kind = SSS_CLI_FLAG, .dest = &a->offscreen},
        {.name = "--out", .kind = SSS_CLI_STRING, .dest = &a->out},
        /* 16384: the renderer's largest image side (sss/render.h) */
        {.name = "--size", .kind = SSS_CLI_SIZE, .dest = a->size, .lo = 1, .hi = 16384},
        {.name = "--light", .kind = SSS_CLI_TRIPLE, .dest = a->lights, .flags = SSS_CLI_NONZERO | SSS_CLI_REPEAT,
         .count = &a->nlights, .max = VIEW_LIGHTS_MAX},
        {.name = "--point-light", .kind = SSS_CLI_POINT, .dest = a->points, .flags = SSS_CLI_REPEAT,
         .count = &a->npoints, .max = VIEW_LIGHTS_MAX},
        {.name = "--view", .kind = SSS_CLI_TRIPLE, .dest = a->p.view, .flags = SSS_CLI_NONZERO},
        /* at most 1e12 each: with the stored values' bound (SSS_VALUE_MAX)
         * q · E · exposure stays far inside float (docs/robustness.md) */
        {.name = "--exposure", .kind = SSS_CLI_DOUBLE, .dest = &a->p.exposure, .lo = 0, .hi = SSS_VIEW_GAIN_MAX,
         .flags = SSS_CLI_ABOVE_LO, .msg = positive, .given = &a->exposure_given},
        {.name = "--intensity", .kind = SSS_CLI_DOUBLE, .dest = &a->intensity, .lo = 0, .hi = SSS_VIEW_GAIN_MAX,
         .flags = SSS_CLI_ABOVE_LO, .msg = positive},
        {.name = "--tonemap", .kind = SSS_CLI_CHOICE, .dest = &a->tonemap, .choices = tonemaps,
         .values = tonemap_values},
        {.name = "--exit", .kind = SSS_CLI_CHOICE, .dest = &a->p.exit_normalised, .choices = exits},
        {.name = "--cpu", .kind = SSS_CLI_FLAG, .dest = &a->cpu},
        {.name = "--no-vector", .kind = SSS_CLI_FLAG, .dest = &a->no_vector},
        {.name = "--no-scatter", .kind = SSS_CLI_FLAG, .dest = &a->p.scatter, .values = off},
        {.name = "--no-specular", .kind = SSS_CLI_FLAG, .dest = &a->p.specular, .values = off},
        {.name = "--diffuse", .kind = SSS_CLI_DOUBLE, .dest = &a->p.diffuse, .lo = 0, .hi = 1},
        {.name = "--no-surface-shadow", .kind = SSS_CLI_FLAG, .dest = &a->p.surface_shadow, .values = off},
        {.name = "--interp", .kind = SSS_CLI_CHOICE, .dest = &a->p.interp, .choices = interps,
         .values = interp_values},
        {.name = "--sh-tables", .kind = SSS_CLI_CHOICE, .dest = &a->p.sh_tables, .choices = tables,
         .values = table_values},
        {.name = "--no-own-term", .kind = SSS_CLI_FLAG, .dest = &a->p.near_terms, .values = off},
        {.name = "--near-visibility", .kind = SSS_CLI_CHOICE, .dest = &a->p.near_visibility,
         .choices = visibilities, .values = visibility_values},
        {.name = "--shadow-size", .kind = SSS_CLI_INT, .dest = &a->p.shadow_size, .lo = 256, .hi = 8192,
         .msg = "%s: %s: '%s' must be an integer %d ... %d\n"},
        {.name = "--single", .kind = SSS_CLI_CHOICE, .dest = &a->p.single, .choices = onoff, .values = onoff_values},
        {.name = "--single-samples", .kind = SSS_CLI_INT, .dest = &a->p.single_samples, .lo = 1, .hi = 1024,
         .msg = "%s: %s: '%s' must be an integer %d ... %d\n"},
        {.name = "--single-march", .kind = SSS_CLI_CHOICE, .dest = &a->p.single_march, .choices = marches,
         .values = march_values},
        {.name = "--wireframe", .kind = SSS_CLI_FLAG, .dest = &a->p.wireframe},
        {.name = "--screenshot", .kind = SSS_CLI_STRING, .dest = &a->shot},
        {.name = "--bench", .kind = SSS_CLI_INT, .dest = &a->nbench, .lo = 1, .hi = 100000},
        {.name = "--scene", .kind = SSS_CLI_STRING, .dest = &a->scene},
        {.name = "--save-scene", .kind = SSS_CLI_STRING, .dest = &a->save_scene},
        {.name = "--time", .kind = SSS_CLI_DOUBLE, .dest = &a->time, .lo = -1e9, .hi = 1e9, .given = &a->time_given},
        {.name = "--splat", .kind = SSS_CLI_FLAG, .dest = &a->splat},
        {.name = "--splat-levels", .kind = SSS_CLI_INT, .dest = &a->splat_levels, .lo = 1, .hi = 3},
        {.name = "--splat-uniform", .kind = SSS_CLI_FLAG, .dest = &a->splat_uniform},
    };
    const sss_cli_opt pos[] = {{.name = "FILE.sss", .kind = SSS_CLI_STRING, .dest = &a->path}};
    const sss_cli cli = {.tool = TOOL, .opts = opts, .nopts = SSS_CLI_COUNT(opts), .pos = pos, .npos = 1,
                         .min_pos = 0, .usage = usage, .extra_msg = "%s: unexpected argument '%s'\n",
                         .missing_msg = "%s: missing FILE.sss (see --help)\n"};
    int rc = sss_cli_parse(&cli, argc, argv);
    if (rc != SSS_CLI_RUN) return rc;
    /* without FILE.sss: a scene of one deforming object, one pose offscreen
     * (pose.c, docs/deformable.md §4) */
    if (!a->path && !a->scene) {
        sss_cli_printf(stderr, "%s: missing FILE.sss (see --help)\n", TOOL);
        return 2;
    }
    if (!a->path && a->offscreen && (a->nbench || !a->out)) {
        sss_cli_printf(stderr, "%s: --scene without FILE.sss draws one pose offscreen with --out IMG.png (not "
                       "--bench)\n", TOOL);
        return 2;
    }
    if ((a->splat_levels || a->splat_uniform) && !a->splat) {
        sss_cli_printf(stderr, "%s: --splat-levels and --splat-uniform set up --splat\n", TOOL);
        return 2;
    }
    if (a->splat && (a->path || !a->offscreen)) {
        sss_cli_printf(stderr, "%s: --splat draws a deforming object of --scene offscreen, without FILE.sss\n", TOOL);
        return 2;
    }
    if (a->path && a->time_given) {
        sss_cli_printf(stderr, "%s: --time poses a deforming object of --scene without FILE.sss (a file holds one "
                       "fixed mesh)\n", TOOL);
        return 2;
    }
    if (a->nlights) memcpy(a->p.light, a->lights[0], sizeof a->p.light); /* one --light: the plain path, as ever */
    if (a->scene && (a->npoints || a->nlights > 1)) {
        sss_cli_printf(stderr, "%s: --scene names its own lights: not with %s\n", TOOL,
                       a->npoints ? "--point-light" : "several --light");
        return 2;
    }
    if (a->offscreen && !a->out && !a->nbench) {
        sss_cli_printf(stderr, "%s: --offscreen needs --out IMG.png|IMG.exr or --bench N\n", TOOL);
        return 2;
    }
    if (a->out && !sss_image_type_known(a->out)) {
        sss_cli_printf(stderr, "%s: --out %s: unknown image type (use .png or .exr)\n", TOOL, a->out);
        return 2;
    }
    for (int k = 0; k < 3; k++) a->p.light_rgb[k] = a->intensity;
    a->p.tonemap = (sss_tonemap)a->tonemap;
    if (a->cpu) a->p.path = SSS_EVAL_CPU;
    return SSS_CLI_RUN;
}

static double now_ms(void) { return 1e3 * sss_now(); }

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* --bench: N frames of evaluate + draw, each timed on the wall clock after
 * glFinish (so it measures completed work), plus GPU timer queries. */
static void bench(sss_renderer *r, const sss_bake_file *f, sss_view_params *p, int w, int h, int n)
{
    double *scatter = malloc(sizeof(double) * (size_t)n), *draw = malloc(sizeof(double) * (size_t)n),
           *frame = malloc(sizeof(double) * (size_t)n), *submit = malloc(sizeof(double) * (size_t)n),
           *timer = malloc(sizeof(double) * (size_t)n);
    float *rgb = NULL, *hdr = NULL;
    sss_error err;
    sss_renderer_render_image(r, p, w, h, &rgb, &hdr, &err); /* warms caches */
    free(rgb);
    free(hdr);
    sss_renderer_bind_offscreen(r, w, h, &err); /* draw into a real framebuffer: a surfaceless context has none */
    for (int i = 0; i < n; i++) {
        /* move the light a little each frame so every frame really works */
        double a = 0.05 * i;
        p->light[0] = sin(a);
        p->light[1] = 0.3;
        p->light[2] = cos(a);
        glFinish();
        double t0 = now_ms();
        sss_renderer_evaluate(r, p);
        submit[i] = now_ms() - t0;
        glFinish();
        double t1 = now_ms();
        sss_renderer_draw(r, p, w, h);
        glFinish();
        double t2 = now_ms();
        scatter[i] = t1 - t0;
        draw[i] = t2 - t1;
        frame[i] = t2 - t0;
        timer[i] = sss_renderer_times(r).scatter_ms; /* complete after glFinish */
    }
    sss_frame_times gt = sss_renderer_times(r);
    char storage[128], own[96];
    sss_storage_describe(f, storage, sizeof storage);
    /* the near terms (OWNT) run inside the evaluation, so scatter_ms holds
     * them; near_terms says whether they ran */
    if (!f->near_terms) snprintf(own, sizeof own, "none");
    else if (!p->near_terms) snprintf(own, sizeof own, "off (--no-own-term)");
    else {
        char set[40];
        if (f->near_radius_mm > 0.0) snprintf(set, sizeof set, "within %.3g mm", f->near_radius_mm);
        else snprintf(set, sizeof set, "%u ring(s)", f->near_rings);
        if (p->near_visibility == SSS_NEAR_MAP)
            snprintf(own, sizeof own, "%s, shadow map %d", set, p->shadow_size ? p->shadow_size : SSS_SHADOW_SIZE);
        else snprintf(own, sizeof own, "%s, rays", set);
    }
    printf("{\"vertices\":%u,\"channels\":%u,\"quant\":\"%s\",\"storage\":\"%s\",\"path\":\"%s\",\"renderer\":\"%s\",\"frames\":%d,"
           "\"width\":%d,\"height\":%d,\"own_term\":\"%s\",\"scatter_ms_median\":%.4f,\"draw_ms_median\":%.4f,"
           "\"frame_ms_median\":%.4f,\"scatter_vertices_per_s\":%.6g,\"fps\":%.3f,\"gpu_timer_scatter_ms_last\":%.4f,"
           "\"gpu_timer_draw_ms_last\":%.4f,\"gpu_timer_own_ms_last\":%.4f,\"bytes_per_vertex\":%.3f,"
           "\"interp\":\"%s\",\"surface_shadow\":%s,\"diffuse\":%.4g,\"scatter_submit_ms_median\":%.4f,"
           "\"scheme\":\"%s\",\"gpu_timer_scatter_ms_median\":%.4f}\n",
           f->mesh.nv, f->channels, sss_quant_name(f->quant), storage,
           p->path == SSS_EVAL_CPU ? "cpu" : "gpu", sss_gl_renderer_name(), n, w, h, own, median(scatter, n),
           median(draw, n), median(frame, n), f->mesh.nv / (1e-3 * median(scatter, n)), 1e3 / median(frame, n),
           gt.scatter_ms, gt.draw_ms, gt.near_ms, sss_renderer_bytes_per_vertex(r),
           p->interp == SSS_INTERP_NEAREST4 ? "nearest4" : "triangle",
           p->surface_shadow && (p->specular || p->diffuse > 0) ? "true" : "false", p->diffuse,
           median(submit, n), sss_renderer_scheme(r, p), median(timer, n));
    free(submit);
    free(timer);
    free(scatter);
    free(draw);
    free(frame);
}

/* --offscreen without --scene: --bench's timings (which leave the light
 * where their last frame put it), then --out's image. */
static int offscreen_render(const sss_bake_file *f, view_args *a)
{
    const int w = a->size[0], h = a->size[1];
    sss_error err = {{0}};
    sss_offscreen *ctx;
    sss_renderer *r;
    if (sss_offscreen_create(&ctx, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    if (sss_renderer_create(f, &r, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, a->path, err.msg);
        sss_offscreen_destroy(ctx);
        return 1;
    }
    int rc = 0;
    if (a->nbench) bench(r, f, &a->p, w, h, a->nbench);
    if (a->out) {
        float *rgb = NULL, *hdr = NULL;
        if (sss_renderer_render_image(r, &a->p, w, h, &rgb, &hdr, &err) != SSS_OK ||
            sss_write_image_with(a->out, rgb, hdr, w, h, &a->inputs, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
            rc = 1;
        } else {
            sss_cli_printf(stderr, "%s: %s: %dx%d, %s, %s path\n", TOOL, a->out, w, h, sss_gl_renderer_name(),
                    a->p.path == SSS_EVAL_CPU ? "CPU" : "GPU");
        }
        free(rgb);
        free(hdr);
    }
    sss_renderer_destroy(r);
    sss_offscreen_destroy(ctx);
    return rc;
}

/* The command that bakes the distance shells file f lacks, as far as its
 * provenance (PARM's "mesh", the material) tells: for the one-line message
 * of a --point-light on a file without them. */
static void shells_command(const sss_bake_file *f, const view_args *a, char *buf, size_t n)
{
    char mesh[256] = "MESH", mat[256];
    const char *k = f->params_json ? strstr(f->params_json, "\"mesh\":\"") : NULL;
    const char *e = k ? strchr(k + 8, '"') : NULL;
    if (e && e > k + 8 && !memchr(k + 8, '\\', (size_t)(e - k - 8))) {
        const char *b = k + 8;
        for (const char *q = b; q < e; q++)
            if (*q == '/') b = q + 1;
        if (e > b) snprintf(mesh, sizeof mesh, "%.*s", (int)(e - b), b);
    }
    const sss_material *m = &f->material;
    if (strcmp(m->name, "custom"))
        snprintf(mat, sizeof mat, "--material %s", m->name);
    else
        snprintf(mat, sizeof mat, "--sigma-a %.6g,%.6g,%.6g --sigma-s %.6g,%.6g,%.6g --eta %.6g", m->sigma_a[0],
                 m->sigma_a[1], m->sigma_a[2], m->sigmap_s[0], m->sigmap_s[1], m->sigmap_s[2], m->eta);
    char mm[64] = "";
    if (f->mm_per_unit != 1.0) snprintf(mm, sizeof mm, " --mm-per-unit %.9g", f->mm_per_unit);
    snprintf(buf, n, "sss-bake %s %s%s --point-light %.9g,%.9g,%.9g -o %s", mesh, mat, mm, a->points[0][0],
             a->points[0][1], a->points[0][2], a->path);
}

/* --point-light and several --light: each light needs its effect in the
 * file (the point-shells of sss-bake --point-light, the direction set of a
 * plain bake). Non-zero (one line printed) when one is missing. */
static int lights_check(const sss_bake_file *f, const view_args *a)
{
    if (a->npoints && !(f->fx.mask & SSS_FX_POINT_SHELLS)) {
        char cmd[1024];
        shells_command(f, a, cmd, sizeof cmd);
        sss_cli_printf(stderr, "%s: %s: not baked for near point lights (no distance shells, section PSHL): bake it "
                       "with '%s'\n", TOOL, a->path, cmd);
        return 2;
    }
    if (a->nlights && f->fx.mask && !(f->fx.mask & SSS_FX_DIR_SET)) {
        sss_cli_printf(stderr, "%s: %s: no direction set for --light (the file holds a scene's static lights "
                       "only): bake it without --scene, or with a moving directional light\n", TOOL, a->path);
        return 2;
    }
    return 0;
}

/* --light and --point-light as the lights of a scene with no file, so that
 * they are summed by the scene's own evaluators (scene_view.c, fx_gpu.c):
 * each --light a static directional light of irradiance --intensity; each
 * --point-light a point light of its intensity, or by default of
 * --intensity × d² with d its distance from the shells' centre, the
 * irradiance of a --light at the object's centre (I / d², §3.3). A point
 * light is marked moving so that the sum takes the file's shells for it,
 * never a far light's one direction; the window holds it still. */
static sss_result lights_scene(const sss_bake_file *f, const view_args *a, sss_scene *sc, sss_error *err)
{
    memset(sc, 0, sizeof *sc);
    snprintf(sc->path, sizeof sc->path, "%s", a->path);
    const uint32_t n = (uint32_t)(a->nlights + a->npoints);
    sc->lights = calloc(n, sizeof *sc->lights);
    if (!sc->lights) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    sc->nlights = n;
    for (int i = 0; i < a->nlights; i++) {
        sss_scene_light *L = &sc->lights[i];
        L->kind = SSS_LIGHT_DIRECTIONAL;
        memcpy(L->direction, a->lights[i], sizeof L->direction);
        sss_normalize3(L->direction);
        L->intensity = a->intensity;
        L->colour[0] = L->colour[1] = L->colour[2] = 1.0;
    }
    for (int i = 0; i < a->npoints; i++) {
        sss_scene_light *L = &sc->lights[a->nlights + i];
        L->kind = SSS_LIGHT_POINT;
        L->moving = 1;
        memcpy(L->position, a->points[i], sizeof L->position);
        double d2 = 0;
        for (int k = 0; k < 3; k++) d2 += (L->position[k] - f->fx.shell_centre[k]) * (L->position[k] - f->fx.shell_centre[k]);
        L->intensity = a->points[i][3] > 0 ? a->points[i][3] : a->intensity * d2;
        L->colour[0] = L->colour[1] = L->colour[2] = 1.0;
    }
    return SSS_OK;
}

/* Loads the scene (--scene, or the lights of the command line), prepares
 * its light sum for file f and takes its camera; the lights' colours are
 * folded into q. Non-zero (message printed) on failure. */
static int scene_open(const sss_bake_file *f, const view_args *a, sss_view_params *p, sss_scene *sc,
                      sss_scene_eval **ev)
{
    sss_error err = {{0}};
    if ((a->scene ? sss_scene_load(a->scene, sc, &err) : lights_scene(f, a, sc, &err)) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    if (sss_scene_eval_create(f, sc, ev, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        sss_scene_free(sc);
        return 1;
    }
    sss_scene_camera_params(sc, f, p);
    for (int k = 0; k < 3; k++) p->light_rgb[k] = 1.0;
    return 0;
}

/* --scene --bench: N frames of the light sum (on the GPU with g, else on
 * the CPU and uploaded) and the draw, timed as bench() times them. q is
 * scratch of the file's nv x channels floats. */
static void scene_bench(const sss_bake_file *f, sss_scene_eval *ev, sss_fx_gpu *g, sss_renderer *r,
                        const sss_view_params *p, float *q, int w, int h, int n)
{
    double *ev_ms = malloc(sizeof(double) * (size_t)n), *draw = malloc(sizeof(double) * (size_t)n),
           *frame = malloc(sizeof(double) * (size_t)n);
    float *rgb = NULL, *hdr = NULL;
    sss_error err = {{0}};
    sss_scene_eval_set_view(ev, p);
    /* the sums hold the near terms: the draw adds none */
    sss_view_params dp = *p;
    dp.near_terms = 0;
    dp.single = -1; /* as sss_scene_render_image: a sum of lights draws no single scattering */
    p = &dp;
    sss_scene_eval_frame(ev, 0.0, q);
    if (sss_renderer_render_q_image(r, p, q, w, h, &rgb, &hdr, &err) == SSS_OK) { free(rgb); free(hdr); }
    sss_renderer_bind_offscreen(r, w, h, &err);
    for (int i = 0; ev_ms && draw && frame && i < n; i++) {
        glFinish();
        double t0 = now_ms();
        if (g) {
            sss_fx_gpu_frame(g, 0.05 * i);
        } else {
            sss_scene_eval_frame(ev, 0.05 * i, q);
            sss_renderer_upload_q(r, q);
        }
        glFinish();
        double t1 = now_ms();
        sss_renderer_draw(r, p, w, h);
        glFinish();
        double t2 = now_ms();
        ev_ms[i] = t1 - t0;
        draw[i] = t2 - t1;
        frame[i] = t2 - t0;
    }
    if (ev_ms && draw && frame)
        printf("{\"vertices\":%u,\"channels\":%u,\"paths\":\"%s\",\"eval\":\"%s\",\"gpu_programs\":\"%s\","
               "\"renderer\":\"%s\",\"frames\":%d,\"width\":%d,"
               "\"height\":%d,\"scatter_ms_median\":%.4f,\"draw_ms_median\":%.4f,\"frame_ms_median\":%.4f,"
               "\"bytes_per_vertex\":%.3f}\n", f->mesh.nv, f->channels, sss_scene_eval_paths(ev),
               g ? "gpu" : "cpu", g ? sss_fx_gpu_describe(g) : "none", sss_gl_renderer_name(), n, w, h,
               median(ev_ms, n), median(draw, n), median(frame, n), sss_file_integral_bytes_per_vertex(f));
    free(ev_ms);
    free(draw);
    free(frame);
}

/* --scene --offscreen: the scene's lights summed from the file's effects, on
 * the GPU (fx_gpu.c: only the programs the file's sections need) or, with
 * --cpu or when the GPU path cannot be built, on the CPU (scene_view.c), then
 * drawn with the shading program: --bench's timings, then --out's image. */
static int scene_offscreen(const sss_bake_file *f, view_args *a)
{
    const int w = a->size[0], h = a->size[1];
    sss_error err = {{0}};
    sss_scene sc;
    sss_scene_eval *ev = NULL;
    if (scene_open(f, a, &a->p, &sc, &ev) != 0) return 2;
    sss_offscreen *ctx = NULL;
    sss_renderer *r = NULL;
    float *q = malloc((size_t)f->mesh.nv * f->channels * sizeof(float));
    int rc = 1;
    if (!q) { sss_cli_printf(stderr, "%s: out of memory\n", TOOL); goto done; }
    if (sss_offscreen_create(&ctx, &err) != SSS_OK || sss_renderer_create(f, &r, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, a->path, err.msg);
        goto done;
    }
    rc = 0;
    sss_fx_gpu *g = NULL;
    if (a->p.path != SSS_EVAL_CPU && sss_fx_gpu_create(f, ev, r, &g, &err) != SSS_OK)
        sss_cli_printf(stderr, "%s: %s: the scene's lights are summed on the CPU (%s)\n", TOOL, a->path, err.msg);
    char evals[96];
    snprintf(evals, sizeof evals, g ? "gpu (programs: %s)" : "cpu%s", g ? sss_fx_gpu_describe(g) : "");
    if (a->nbench) scene_bench(f, ev, g, r, &a->p, q, w, h, a->nbench);
    if (a->out) {
        float *rgb = NULL, *hdr = NULL;
        /* the sum (GPU or CPU) holds each light's near terms; drawn without
         * adding them again (sss_scene_render_image) */
        if (sss_scene_render_image(r, ev, g, &a->p, 0.0, w, h, &rgb, &hdr, &err) != SSS_OK ||
            sss_write_image_with(a->out, rgb, hdr, w, h, &a->inputs, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
            rc = 1;
        } else {
            sss_cli_printf(stderr, "%s: %s: %dx%d, %s, lights summed on the %s, %s %s: %s\n", TOOL, a->out, w, h,
                    sss_gl_renderer_name(), evals, a->scene ? "scene" : "lights of", a->scene ? a->scene : "the command line",
                    sss_scene_eval_paths(ev));
        }
        free(rgb);
        free(hdr);
    }
    sss_fx_gpu_destroy(g);
done:
    free(q);
    sss_renderer_destroy(r);
    sss_offscreen_destroy(ctx);
    sss_scene_eval_destroy(ev);
    sss_scene_free(&sc);
    return rc;
}

/* --scene in the window: the scene's lights every frame (moving ones turn
 * about +z at 0.3 rad/s), the scene's camera as the start view; summed on
 * the GPU (built on the first frame, in the window's context) unless --cpu
 * or the GPU path cannot be built. */
typedef struct scene_win {
    const sss_bake_file *f;
    sss_scene_eval *ev;
    sss_fx_gpu *g;
    int cpu;
    char desc[192];
    int still; /* the command line's lights: they stay where they were given */
} scene_win;

static void scene_frame(void *user, const sss_view_params *p, double t, float *q)
{
    sss_scene_eval_set_view(((scene_win *)user)->ev, p); /* the near terms as the O key leaves them */
    const scene_win *s = user;
    sss_scene_eval_frame(s->ev, s->still ? 0.0 : 0.3 * t, q);
}

static const char *scene_frame_gpu(void *user, const sss_view_params *p, sss_renderer *r, double t)
{
    scene_win *s = user;
    if (p) sss_scene_eval_set_view(s->ev, p);
    if (!r) {
        sss_fx_gpu_destroy(s->g);
        s->g = NULL;
        return NULL;
    }
    if (s->cpu) return NULL;
    if (!s->g) {
        sss_error err = {{0}};
        if (sss_fx_gpu_create(s->f, s->ev, r, &s->g, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: the scene's lights are summed on the CPU (%s)\n", TOOL, err.msg);
            s->cpu = 1;
            return NULL;
        }
        snprintf(s->desc, sizeof s->desc, "%s on the GPU (programs: %s)", sss_scene_eval_paths(s->ev),
                 sss_fx_gpu_describe(s->g));
        sss_cli_printf(stderr, "%s: scene lights: %s\n", TOOL, s->desc);
    }
    sss_fx_gpu_frame(s->g, s->still ? 0.0 : 0.3 * t);
    return s->desc;
}

static int scene_window(const sss_bake_file *f, view_args *a)
{
    sss_scene sc;
    sss_scene_eval *ev = NULL;
    if (scene_open(f, a, &a->p, &sc, &ev) != 0) return 2;
    a->p.background[0] = a->p.background[1] = a->p.background[2] = 0.02f;
    scene_win sw = {f, ev, NULL, a->p.path == SSS_EVAL_CPU, "", !a->scene};
    sss_app_options ao = {.file_path = a->path, .width = a->size[0], .height = a->size[1], .screenshot_path = a->shot,
                          .frame_q = scene_frame, .user = &sw, .frame_gpu = scene_frame_gpu, .scene_eval = ev};
    int rc = sss_app_run(f, &a->p, &ao);
    sss_scene_eval_destroy(ev);
    sss_scene_free(&sc);
    return rc;
}

/* The window without --scene: the renderer's own evaluation for the light
 * the mouse moves (app.c). */
static int window(const sss_bake_file *f, view_args *a)
{
    sss_app_options ao = {.file_path = a->path, .width = a->size[0], .height = a->size[1], .screenshot_path = a->shot};
    a->p.background[0] = a->p.background[1] = a->p.background[2] = 0.02f;
    return sss_app_run(f, &a->p, &ao);
}

int main(int argc, char **argv)
{
    view_args a;
    int rc = parse(argc, argv, &a);
    if (rc != SSS_CLI_RUN) return rc;
    sss_error err = {{0}};
    if (a.save_scene && (!a.scene || a.path)) {
        sss_cli_printf(stderr, "%s: --save-scene: only with --scene on an editable object, without FILE.sss\n", TOOL);
        return 2;
    }
    if (!a.path) {
        a.input[0] = a.scene;
        a.inputs = (sss_inputs){a.input, 1};
        if (a.out && sss_output_check(a.out, &a.inputs, NULL, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
            return 1;
        }
        sss_pose_view pv = {TOOL, a.scene, a.time, a.out, a.shot, a.size[0], a.size[1], a.exposure_given, &a.inputs,
                            a.splat, a.splat_levels, !a.splat_uniform, a.save_scene};
        if (!a.offscreen) a.p.background[0] = a.p.background[1] = a.p.background[2] = 0.02f; /* as window() */
        const int editable = sss_edit_wanted(a.scene);
        /* the edited scene replaces no input (sss/fileio.h) and its folder
         * exists, checked before anything is drawn (docs/heterogeneous.md §9.6) */
        if (a.save_scene && (!editable || sss_scene_edited_check(a.scene, a.save_scene, &err) != SSS_OK)) {
            if (!editable) snprintf(err.msg, sizeof err.msg, "--save-scene: only for a scene whose object is editable");
            sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
            return 2;
        }
        /* an editable object: seed 000's run-time path (edit.c, docs/heterogeneous.md §9) */
        if (editable) return a.offscreen ? sss_edit_offscreen(&pv, &a.p) : sss_edit_window(&pv, &a.p);
        return a.offscreen ? sss_pose_offscreen(&pv, &a.p) : sss_pose_window(&pv, &a.p);
    }
    a.input[0] = a.path;
    a.input[1] = a.scene;
    a.inputs = (sss_inputs){a.input, a.scene ? 2 : 1};
    /* the output before anything is read or drawn (sss/fileio.h); the
     * writer checks it again */
    if (a.out && sss_output_check(a.out, &a.inputs, NULL, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    sss_bake_file f;
    if (sss_file_read(a.path, &f, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    if (a.no_vector) { /* the renderer draws Q whenever the file holds it (sss/render.h) */
        free(f.qvec);
        f.qvec = NULL;
    }
    /* a first render neither black nor clipped: the radiance of a flat
     * surface of the material lit head-on, E q F_t(η, n_o·ω_o) with q its
     * slab value (docs/physics.md §4), maps to F_t(η, 1) ≈ 1; --scene's
     * lights carry their own irradiance, so there E = 1; --exit normalised
     * divides the exit term by c(η), so the exposure multiplies by it */
    if (!a.exposure_given) {
        const double c = a.p.exit_normalised ? sss_exit_norm(f.material.eta) : 1.0;
        const double qs = sss_material_slab_q(&f.material, f.channels) * (a.scene ? 1.0 : a.intensity) / c;
        a.p.exposure = qs > 0.0 && isfinite(1.0 / qs) ? 1.0 / qs : 1.0;
    }
    /* several lights, or point lights: summed as a scene's (lights_scene) */
    const int summed = a.scene || a.npoints || a.nlights > 1;
    if (!a.scene && summed && (rc = lights_check(&f, &a)) != 0) {
        sss_file_free(&f);
        return rc;
    }
    if (a.offscreen) rc = summed ? scene_offscreen(&f, &a) : offscreen_render(&f, &a);
    else rc = summed ? scene_window(&f, &a) : window(&f, &a);
    sss_file_free(&f);
    return rc;
}
