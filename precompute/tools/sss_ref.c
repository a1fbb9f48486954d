/* sss-ref: the path-traced reference (sss/reference.h, docs/reference.md):
 * the radiance leaving a mesh of a translucent material through its surface,
 * at one vertex towards one view direction or through every pixel of the
 * viewer's camera, each with its standard error, for the inputs sss-bake
 * takes. See `sss-ref --help`.
 *
 * main: parse() reads the command line into ref_args and checks its
 * combinations, setup() turns it into the medium, the light and the
 * options, run() imports, traces and reports; under mpirun the ranks split
 * every round's blocks and rank 0 alone speaks and writes (bake_mpi.c). */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake_mpi.h"
#include "sss/cli.h"
#include "sss/fileio.h"
#include "sss/import.h"
#include "sss/probe.h"
#include "sss/reference.h"

static const char *TOOL = "sss-ref";

static void usage(FILE *f)
{
    fprintf(f,
        "usage: sss-ref MESH [--material NAME | --sigma-a R,G,B --sigma-s R,G,B [--g G]] [--eta E]\n"
        "               [--mm-per-unit S] (--light X,Y,Z | --point-light X,Y,Z[,I] | --env FILE.exr|uniform)\n"
        "               (--query V --view X,Y,Z | --out IMG.exr\n"
        "               [--size WxH --view X,Y,Z]) [--paths N | --seconds T] [--seed K] [--json]\n"
        "A volumetric path-traced reference (docs/reference.md): the radiance leaving the mesh\n"
        "through its surface, by Monte Carlo random walks inside it (free flights, Henyey-\n"
        "Greenstein scattering, Fresnel reflection and refraction at the smooth boundary with\n"
        "the mesh's interpolated normals, next-event estimation through the boundary), with\n"
        "its standard error: the physics the dipole of sss-bake approximates.\n\n"
        "  MESH                 .ply (ascii/binary), .obj, .off, .stl, .gltf or .glb: a closed surface\n"
        "  --material NAME      Jensen 2001 preset (default marble); its sigma'_s is taken with\n"
        "                       g = 0 unless --g is given\n"
        "  --sigma-a R,G,B      custom absorption, 1/mm (with --sigma-s)\n"
        "  --sigma-s R,G,B      custom *reduced* scattering sigma'_s, 1/mm, as sss-bake's;\n"
        "                       with --g it is sigma_s itself and sigma'_s = sigma_s (1-g)\n"
        "  --g G                Henyey-Greenstein asymmetry in (-1, 1) (default 0)\n"
        "  --eta E              relative index of refraction (default 1.3)\n"
        "  --mm-per-unit S      millimetres per mesh unit (default 1)\n"
        "  --light X,Y,Z        directional light from (towards the light), irradiance 1 on a\n"
        "                       surface facing it (sss-view's E = 1)\n"
        "  --point-light X,Y,Z[,I]  instead: an isotropic point light at X,Y,Z (mesh units,\n"
        "                       outside the mesh) of intensity I per sr (default 1): irradiance\n"
        "                       I cos / r^2, r in mesh units, as sss-bake's scene point lights\n"
        "  --env FILE.exr|uniform  instead of --light: environment light, a lat-long probe\n"
        "                       (z up, docs/scenes.md) or radiance 1 from every direction\n"
        "  --query V            vertex index (as sss-bake and sss-stat number them)\n"
        "  --view X,Y,Z         towards the eye: the query's view, or the camera's direction\n"
        "                       from the object's centre as sss-view's --view (default 0,0,1)\n"
        "  --out IMG.exr        image with sss-view's camera (linear radiance, E = 1, the\n"
        "                       subsurface term only: compare with sss-view --no-specular);\n"
        "                       its standard error goes to IMG.stderr.exr\n"
        "  --size WxH           image size (default 800x600, as sss-view)\n"
        "  --paths N            paths per query or pixel (default 1024)\n"
        "  --seconds T          time budget instead: whole rounds until T seconds have passed\n"
        "                       (the path count reached is reported; --paths N repeats it)\n"
        "  --seed K             random seed (default 1): the result depends on it and on the path\n"
        "                       count only, not on --threads or the number of MPI ranks\n"
        "  --max-order K        scattering orders 1..K only (default: all)\n"
        "  --no-nee-roulette    make every next-event estimate, also at collisions too deep to\n"
        "                       matter (the same mean, more rays: docs/reference.md section 3)\n"
        "  --threads T          worker threads (default: all cores)\n"
        "  --json               print one JSON object on stdout\n"
        "  -q, --quiet          no progress bar or summary on stderr\n"
        "  -h, --help           this text\n"
        "Under mpirun the ranks share every round's paths and rank 0 reports the same result.\n"
        "Exit status: 0 success, 1 unreadable mesh or failed run, 2 bad arguments, 130 interrupted.\n");
}

/* The command line, as the option table fills it. */
typedef struct ref_args {
    const char *mesh, *material, *out, *env;
    double sigma_a[3], sigma_s[3], g, eta, mm_per_unit, seconds;
    double light[3], view[3], point[4];
    const char *point_text;
    int have_sigma_a, have_sigma_s, have_g, have_eta, have_light, have_view, have_size, have_paths, have_seconds;
    uint32_t query, max_order;
    int have_query;
    uint32_t paths, seed;
    int size[2];
    int threads, json, quiet, no_nee_roulette;
} ref_args;

static int refuse(const char *msg)
{
    sss_cli_printf(stderr, "%s: %s\n", TOOL, msg);
    return 2;
}

/* the bound every tool puts on gains and intensities (docs/robustness.md,
 * item 5) */
#define REF_INTENSITY_MAX 1e12

/* --point-light X,Y,Z[,I]: a position within the toolkit's coordinate
 * range (sss/mesh.h) and an intensity in (0, 1e12] (default 1). */
static int parse_point(const char *text, double out[4])
{
    double v[4] = {0, 0, 0, 1};
    int n = 0;
    const char *p = text;
    for (; n < 4; n++) {
        char *end;
        errno = 0;
        v[n] = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(v[n])) break;
        p = end;
        if (*p != ',') {
            n++;
            break;
        }
        p++;
    }
    if (*p || n < 3) {
        sss_cli_printf(stderr, "%s: --point-light: '%s' must be X,Y,Z or X,Y,Z,I (finite numbers)\n", TOOL, text);
        return 0;
    }
    for (int k = 0; k < 3; k++)
        if (fabs(v[k]) > SSS_COORD_MAX) {
            sss_cli_printf(stderr, "%s: --point-light: '%s': coordinates must lie within +-%g\n", TOOL, text, SSS_COORD_MAX);
            return 0;
        }
    if (!(v[3] > 0.0 && v[3] <= REF_INTENSITY_MAX)) {
        sss_cli_printf(stderr, "%s: --point-light: '%s': the intensity must lie in (0, %g]\n", TOOL, text, REF_INTENSITY_MAX);
        return 0;
    }
    memcpy(out, v, sizeof v);
    return 1;
}

/* Reads the command line into *a and checks its combinations. Returns
 * SSS_CLI_RUN, or the exit status after --help (0) or a message (2). */
static int parse(int argc, char **argv, ref_args *a)
{
    memset(a, 0, sizeof *a);
    a->eta = 1.3;
    a->seed = 1;
    a->view[2] = 1.0;
    a->size[0] = 800;
    a->size[1] = 600;
    const sss_cli_opt opts[] = {
        {.name = "--material", .kind = SSS_CLI_STRING, .dest = &a->material},
        {.name = "--sigma-a", .kind = SSS_CLI_TRIPLE, .dest = a->sigma_a, .given = &a->have_sigma_a},
        {.name = "--sigma-s", .kind = SSS_CLI_TRIPLE, .dest = a->sigma_s, .given = &a->have_sigma_s},
        {.name = "--g", .kind = SSS_CLI_DOUBLE, .dest = &a->g, .lo = -0.999, .hi = 0.999, .given = &a->have_g},
        {.name = "--eta", .kind = SSS_CLI_DOUBLE, .dest = &a->eta, .lo = SSS_ETA_MIN, .hi = SSS_ETA_MAX, .given = &a->have_eta},
        {.name = "--mm-per-unit", .kind = SSS_CLI_DOUBLE, .dest = &a->mm_per_unit, .lo = 1e-12, .hi = 1e12},
        {.name = "--light", .kind = SSS_CLI_TRIPLE, .dest = a->light, .flags = SSS_CLI_NONZERO, .given = &a->have_light},
        {.name = "--env", .kind = SSS_CLI_STRING, .dest = &a->env, .flags = SSS_CLI_NONEMPTY},
        {.name = "--point-light", .kind = SSS_CLI_STRING, .dest = &a->point_text, .flags = SSS_CLI_NONEMPTY},
        {.name = "--query", .kind = SSS_CLI_U32, .dest = &a->query, .lo = 0, .hi = UINT32_MAX - 2, .given = &a->have_query},
        {.name = "--view", .kind = SSS_CLI_TRIPLE, .dest = a->view, .flags = SSS_CLI_NONZERO, .given = &a->have_view},
        {.name = "--out", .alias = "-o", .kind = SSS_CLI_STRING, .dest = &a->out, .flags = SSS_CLI_NONEMPTY},
        {.name = "--size", .kind = SSS_CLI_SIZE, .dest = a->size, .lo = 1, .hi = 16384, .given = &a->have_size},
        {.name = "--paths", .kind = SSS_CLI_U32, .dest = &a->paths, .lo = 1, .hi = UINT32_MAX, .given = &a->have_paths},
        {.name = "--seconds", .kind = SSS_CLI_DOUBLE, .dest = &a->seconds, .lo = 0, .hi = 1e9, .flags = SSS_CLI_ABOVE_LO,
         .given = &a->have_seconds},
        {.name = "--seed", .kind = SSS_CLI_U32, .dest = &a->seed, .lo = 0, .hi = UINT32_MAX},
        {.name = "--max-order", .kind = SSS_CLI_U32, .dest = &a->max_order, .lo = 1, .hi = 1000000},
        {.name = "--no-nee-roulette", .kind = SSS_CLI_FLAG, .dest = &a->no_nee_roulette},
        {.name = "--threads", .kind = SSS_CLI_INT, .dest = &a->threads, .lo = 1, .hi = 1024},
        {.name = "--json", .kind = SSS_CLI_FLAG, .dest = &a->json},
        {.name = "--quiet", .alias = "-q", .kind = SSS_CLI_FLAG, .dest = &a->quiet},
    };
    const sss_cli_opt pos[] = {{.name = "MESH", .kind = SSS_CLI_STRING, .dest = &a->mesh}};
    const sss_cli cli = {.tool = TOOL, .opts = opts, .nopts = SSS_CLI_COUNT(opts), .pos = pos,
                         .npos = SSS_CLI_COUNT(pos), .usage = usage,
                         .need_msg = "%s: %s needs a value (see --help)\n",
                         .extra_msg = "%s: unexpected argument '%s' (one MESH only)\n"};
    const int rc = sss_cli_parse(&cli, argc, argv);
    if (rc != SSS_CLI_RUN) return rc;
    if (!a->mesh) return refuse("missing MESH (see --help)");
    if ((a->have_sigma_a || a->have_sigma_s) && (a->material || !a->have_sigma_a || !a->have_sigma_s))
        return refuse("give either --material NAME or both --sigma-a and --sigma-s");
    if (!!a->have_light + !!a->env + !!a->point_text > 1)
        return refuse("--light, --point-light and --env exclude each other");
    if (!a->have_light && !a->env && !a->point_text) return refuse("missing --light X,Y,Z (or --point-light, --env)");
    if (a->point_text && !parse_point(a->point_text, a->point)) return 2;
    if (a->have_query && a->out) return refuse("--query and --out exclude each other");
    if (!a->have_query && !a->out) return refuse("give --query V --view X,Y,Z or --out IMG.exr");
    if (a->have_query && !a->have_view) return refuse("--query needs --view X,Y,Z");
    if (a->have_query && a->have_size) return refuse("--size goes with --out");
    if (a->have_paths && a->have_seconds) return refuse("--paths and --seconds exclude each other");
    if (a->out) {
        const size_t n = strlen(a->out);
        if (n < 5 || strcmp(a->out + n - 4, ".exr") != 0) return refuse("--out must name an .exr file");
    }
    return SSS_CLI_RUN;
}

/* Set by SIGINT / SIGTERM; the walks poll it (sss_ref_options.cancel). */
static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* What the run is given. */
typedef struct ref_setup {
    sss_material mat;      /* the named or custom material (σ′s reduced), for the report */
    sss_ref_medium medium;
    sss_ref_light light;
    sss_probe probe;       /* --env FILE.exr */
    sss_ref_options opt;
} ref_setup;

/* The medium, the light and the options. Returns SSS_CLI_RUN, 1 (an
 * unreadable probe) or 2 after a message. */
static int setup(const ref_args *a, ref_setup *s)
{
    memset(s, 0, sizeof *s);
    sss_error err = {{0}};
    sss_material *mat = &s->mat;
    double g = a->have_g ? a->g : 0.0;
    if (a->have_sigma_a) { /* and --sigma-s (parse) */
        snprintf(mat->name, sizeof mat->name, "custom");
        for (int c = 0; c < 3; c++) {
            mat->sigma_a[c] = a->sigma_a[c];
            /* --sigma-s is σ′s, unless --g says it is σs (docs/reference.md §6) */
            mat->sigmap_s[c] = a->have_g ? a->sigma_s[c] * (1.0 - g) : a->sigma_s[c];
        }
        mat->eta = a->eta;
    } else if (sss_material_preset(a->material ? a->material : "marble", mat, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 2;
    } else if (a->have_eta) {
        mat->eta = a->eta;
    }
    if (sss_ref_medium_from_material(mat, g, &s->medium, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 2;
    }
    if (a->have_sigma_a && a->have_g) /* σs exactly as given, not through (1 − g) twice */
        for (int c = 0; c < 3; c++) s->medium.sigma_s[c] = a->sigma_s[c];
    if (a->env) {
        s->light.kind = SSS_REF_ENVIRONMENT;
        if (strcmp(a->env, "uniform") != 0) {
            if (sss_probe_read(a->env, &s->probe, &err) != SSS_OK) {
                sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
                return 1;
            }
            s->light.probe = &s->probe;
        }
    } else if (a->point_text) {
        s->light.kind = SSS_REF_POINT;
        memcpy(s->light.pos, a->point, sizeof s->light.pos);
        s->light.intensity = a->point[3];
    } else {
        s->light.kind = SSS_REF_DIRECTIONAL;
        memcpy(s->light.dir, a->light, sizeof a->light);
    }
    sss_ref_options *o = &s->opt;
    o->seed = a->seed;
    o->paths = a->have_seconds ? 0 : a->have_paths ? a->paths : 1024;
    o->seconds = a->have_seconds ? a->seconds : 0.0;
    o->threads = a->threads;
    o->max_order = a->max_order;
    o->no_nee_roulette = a->no_nee_roulette;
    o->progress = !a->quiet;
    const char *log = getenv("SSS_PROGRESS_LOG");
    o->progress_log = log && *log ? log : NULL;
    o->cancel = &interrupted;
    return SSS_CLI_RUN;
}

/* The inputs every report repeats, into o. */
static void json_inputs(cJSON *o, const ref_args *a, const ref_setup *s, const sss_ref_stats *st, int nranks)
{
    cJSON_AddStringToObject(o, "mesh", a->mesh);
    cJSON_AddStringToObject(o, "material", s->mat.name);
    cJSON_AddItemToObject(o, "sigma_a", cJSON_CreateDoubleArray(s->medium.sigma_a, 3));
    cJSON_AddItemToObject(o, "sigma_s", cJSON_CreateDoubleArray(s->medium.sigma_s, 3));
    cJSON_AddItemToObject(o, "sigmap_s", cJSON_CreateDoubleArray(s->mat.sigmap_s, 3));
    cJSON_AddNumberToObject(o, "g", s->medium.g);
    cJSON_AddNumberToObject(o, "eta", s->medium.eta);
    cJSON_AddNumberToObject(o, "mm_per_unit", a->mm_per_unit > 0 ? a->mm_per_unit : 1.0);
    if (s->light.kind == SSS_REF_DIRECTIONAL) cJSON_AddItemToObject(o, "light", cJSON_CreateDoubleArray(a->light, 3));
    else if (s->light.kind == SSS_REF_POINT) cJSON_AddItemToObject(o, "point_light", cJSON_CreateDoubleArray(a->point, 4));
    else cJSON_AddStringToObject(o, "env", a->env);
    cJSON_AddNumberToObject(o, "seed", a->seed);
    cJSON_AddNumberToObject(o, "paths", (double)st->paths);
    if (a->max_order) cJSON_AddNumberToObject(o, "max_order", a->max_order);
    cJSON_AddNumberToObject(o, "seconds", st->seconds);
    cJSON_AddNumberToObject(o, "mpi_ranks", nranks);
    /* this process's walks (rank 0's under MPI) */
    cJSON *w = cJSON_AddObjectToObject(o, "walks");
    cJSON_AddNumberToObject(w, "paths", (double)st->walks);
    cJSON_AddNumberToObject(w, "rays", (double)st->rays);
    cJSON_AddNumberToObject(w, "scatterings", (double)st->scatterings);
    cJSON_AddNumberToObject(w, "nee", (double)st->nee);
    cJSON_AddNumberToObject(w, "nee_hits", (double)st->nee_hits);
    cJSON_AddNumberToObject(w, "nee_unsolved", (double)st->nee_unsolved);
    cJSON_AddNumberToObject(w, "nee_skipped", (double)st->nee_skipped);
    cJSON_AddNumberToObject(w, "leaks", (double)st->leaks);
    cJSON_AddNumberToObject(w, "truncated", (double)st->truncated);
    cJSON_AddNumberToObject(w, "crossed", (double)st->crossed);
    cJSON_AddNumberToObject(w, "paths_per_second", st->seconds > 0 ? st->walks / st->seconds : 0.0);
}

static void print_json(cJSON *o)
{
    char *str = cJSON_PrintUnformatted(o);
    puts(str);
    free(str);
    cJSON_Delete(o);
}

/* A leak means the mesh is not the closed surface the model needs: said
 * on stderr even with -q, like sss-bake's warnings. */
static void warn_leaks(const ref_args *a, const sss_ref_stats *st)
{
    if (st->leaks)
        sss_cli_printf(stderr, "%s: %s: warning: %llu of %llu paths left the mesh through a hole (an open mesh); they end "
                "there and the estimate misses their light\n", TOOL, a->mesh, (unsigned long long)st->leaks,
                (unsigned long long)st->walks);
    if (st->crossed)
        sss_cli_printf(stderr, "%s: %s: warning: rays passed %llu times through surfaces facing the wrong way (overlapping "
                "parts, inner sheets, flipped triangles): the medium is taken to be continuous across them\n", TOOL,
                a->mesh, (unsigned long long)st->crossed);
}

static int run_query(const ref_args *a, const ref_setup *s, const sss_ref_scene *sc, uint32_t nv, int rank, int nranks)
{
    if (a->query >= nv) {
        if (rank == 0)
            sss_cli_printf(stderr, "%s: %s: --query %u: vertex index out of range: the mesh has %u vertices (0 ... %u)\n",
                    TOOL, a->mesh, a->query, nv, nv - 1);
        return 2;
    }
    const sss_ref_query q = {a->query, {a->view[0], a->view[1], a->view[2]}};
    sss_ref_estimate e;
    sss_ref_stats st;
    sss_error err = {{0}};
    const sss_result r = sss_ref_queries(sc, &s->medium, &s->light, &q, 1, &s->opt, &e, &st, &err);
    if (r != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, a->mesh, err.msg);
        return r == SSS_ERR_INTERRUPTED ? 130 : 1;
    }
    if (rank != 0) return 0;
    warn_leaks(a, &st);
    if (a->json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddItemToObject(o, "radiance", cJSON_CreateDoubleArray(e.mean, 3));
        cJSON_AddItemToObject(o, "stderr", cJSON_CreateDoubleArray(e.se, 3));
        cJSON_AddNumberToObject(o, "vertex", a->query);
        cJSON_AddItemToObject(o, "view", cJSON_CreateDoubleArray(a->view, 3));
        json_inputs(o, a, s, &st, nranks);
        print_json(o);
    } else {
        printf("%s: vertex %u, view (%g, %g, %g): radiance leaving through the surface, %llu paths, %.3g s\n",
               a->mesh, a->query, a->view[0], a->view[1], a->view[2], (unsigned long long)st.paths, st.seconds);
        static const char *const rgb[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; c++)
            printf("  %s %.6g +- %.3g (%.2f%%)\n", rgb[c], e.mean[c], e.se[c], e.mean[c] > 0 ? 100.0 * e.se[c] / e.mean[c] : 0.0);
    }
    return 0;
}

/* The files an output must not be (sss/fileio.h): the mesh and the
 * probe, in paths[2]. */
static sss_inputs ref_inputs(const ref_args *a, const char *paths[2])
{
    paths[0] = a->mesh;
    paths[1] = a->env;
    return (sss_inputs){paths, a->env ? 2u : 1u};
}

/* IMG.exr → IMG.stderr.exr */
static void stderr_path(const char *out, char *buf, size_t n)
{
    snprintf(buf, n, "%.*s.stderr.exr", (int)(strlen(out) - 4), out);
}

static int run_image(const ref_args *a, const ref_setup *s, const sss_mesh *mesh, const sss_ref_scene *sc, int rank,
                     int nranks)
{
    sss_ref_camera cam;
    sss_ref_camera_view(mesh, a->view, a->size[0], a->size[1], &cam);
    const size_t np = (size_t)a->size[0] * (size_t)a->size[1];
    float *rgb = malloc(3 * np * sizeof(float)), *se = malloc(3 * np * sizeof(float));
    if (!rgb || !se) {
        free(rgb);
        free(se);
        sss_cli_printf(stderr, "%s: %s: out of memory for a %dx%d image\n", TOOL, a->out, a->size[0], a->size[1]);
        return 1;
    }
    sss_ref_stats st;
    sss_error err = {{0}};
    sss_result r = sss_ref_image(sc, &s->medium, &s->light, &cam, &s->opt, rgb, se, &st, &err);
    if (r != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, a->mesh, err.msg);
        free(rgb);
        free(se);
        return r == SSS_ERR_INTERRUPTED ? 130 : 1;
    }
    int rc = 0;
    if (rank == 0) {
        warn_leaks(a, &st);
        char sepath[4096];
        stderr_path(a->out, sepath, sizeof sepath);
        sss_probe img = {(uint32_t)a->size[0], (uint32_t)a->size[1], rgb}, sei = {img.w, img.h, se};
        /* the probe writer is a plain float RGB EXR writer, rows from the top;
         * both images staged and committed together, never over an input
         * (docs/robustness.md, "Paths") */
        const char *paths[2];
        const sss_inputs in = ref_inputs(a, paths);
        sss_atomic w[2];
        sss_result wr = sss_probe_write_staged(&w[0], a->out, &img, &in, &err);
        if (wr == SSS_OK && (wr = sss_probe_write_staged(&w[1], sepath, &sei, &in, &err)) != SSS_OK)
            sss_atomic_abort(&w[0]);
        if (wr == SSS_OK && (wr = sss_atomic_commit(&w[0], &err)) != SSS_OK) sss_atomic_abort(&w[1]);
        if (wr == SSS_OK) wr = sss_atomic_commit(&w[1], &err);
        if (wr != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
            rc = 1;
        } else {
            /* the covered pixels' mean radiance and relative standard error */
            double sum[3] = {0}, rel = 0.0;
            uint64_t covered = 0;
            for (size_t i = 0; i < np; i++) {
                const float *p = &rgb[3 * i], *e = &se[3 * i];
                if (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f && e[0] == 0.0f) continue;
                covered++;
                for (int c = 0; c < 3; c++) sum[c] += p[c];
                const double l = (p[0] + p[1] + p[2]) / 3.0, le = (e[0] + e[1] + e[2]) / 3.0;
                if (l > 0) rel += le / l;
            }
            double mean[3];
            for (int c = 0; c < 3; c++) mean[c] = covered ? sum[c] / covered : 0.0;
            if (a->json) {
                cJSON *o = cJSON_CreateObject();
                cJSON_AddStringToObject(o, "image", a->out);
                cJSON_AddStringToObject(o, "stderr_image", sepath);
                cJSON_AddNumberToObject(o, "width", a->size[0]);
                cJSON_AddNumberToObject(o, "height", a->size[1]);
                cJSON_AddItemToObject(o, "view", cJSON_CreateDoubleArray(a->view, 3));
                cJSON_AddNumberToObject(o, "covered_pixels", (double)covered);
                cJSON_AddItemToObject(o, "mean_radiance", cJSON_CreateDoubleArray(mean, 3));
                cJSON_AddNumberToObject(o, "mean_relative_stderr", covered ? rel / covered : 0.0);
                json_inputs(o, a, s, &st, nranks);
                print_json(o);
            } else if (!a->quiet) {
                sss_cli_printf(stderr, "%s: %s: %dx%d, %llu paths per pixel, %.3g s; %llu pixels see the mesh, mean "
                        "relative standard error %.3g; %s, %s\n", TOOL, a->mesh, a->size[0], a->size[1],
                        (unsigned long long)st.paths, st.seconds, (unsigned long long)covered,
                        covered ? rel / covered : 0.0, a->out, sepath);
            }
        }
    }
    free(rgb);
    free(se);
    return rc;
}

static int run(const ref_args *a, ref_setup *s, int *argc, char ***argv)
{
    int rank = 0, nranks = 1;
    sss_mpi_start(argc, argv, &rank, &nranks);
    if (nranks > 1) {
        s->opt.rank = rank;
        s->opt.nranks = nranks;
        s->opt.comm = sss_mpi_ref_comm();
        if (rank != 0) s->opt.progress = 0;
    }
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    sss_error err = {{0}};
    /* the image and its standard error must be writable, and neither may be
     * an input, before any path is traced (docs/robustness.md, "Paths") */
    if (a->out) { /* every rank, so that all stop together */
        char sepath[4096];
        stderr_path(a->out, sepath, sizeof sepath);
        const char *paths[2];
        const sss_inputs in = ref_inputs(a, paths);
        if (sss_output_check(a->out, &in, NULL, &err) != SSS_OK || sss_output_check(sepath, &in, NULL, &err) != SSS_OK) {
            if (rank == 0) sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
            sss_mpi_stop();
            return 1;
        }
    }
    sss_mesh mesh;
    sss_import_report rep;
    if (sss_import_mesh(a->mesh, &mesh, &rep, &err) != SSS_OK) {
        if (rank == 0) sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        sss_mpi_stop();
        return 1;
    }
    if (rank == 0) {
        char prefix[600];
        snprintf(prefix, sizeof prefix, "%s: %s", TOOL, a->mesh);
        if (!a->quiet) sss_import_print_repairs(&rep, prefix, stderr);
        sss_import_print_warnings(&rep, prefix, stderr);
    }
    sss_ref_scene *sc;
    if (sss_ref_scene_create(&mesh, a->mm_per_unit, &sc, &err) != SSS_OK) {
        if (rank == 0) sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, a->mesh, err.msg);
        sss_mesh_free(&mesh);
        sss_mpi_stop();
        return 1;
    }
    const int rc = a->have_query ? run_query(a, s, sc, mesh.nv, rank, nranks) : run_image(a, s, &mesh, sc, rank, nranks);
    sss_ref_scene_destroy(sc);
    sss_mesh_free(&mesh);
    if (rc == 130 || (rc == 1 && nranks > 1)) sss_mpi_abort(rc);
    sss_mpi_stop();
    return rc;
}

int main(int argc, char **argv)
{
    ref_args a;
    ref_setup s;
    int rc = parse(argc, argv, &a);
    if (rc == SSS_CLI_RUN) rc = setup(&a, &s);
    if (rc != SSS_CLI_RUN) return rc;
    rc = run(&a, &s, &argc, &argv);
    sss_probe_free(&s.probe);
    return rc;
}
