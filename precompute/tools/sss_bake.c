/* sss-bake: bakes a mesh and a translucent material into a .sss file
 * (Hao–Varshney 2004 §3). See `sss-bake --help` and docs/usage.md. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime under -std=c11 */
#include <cjson/cJSON.h>
#include <stdint.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bake_mpi.h"
#include "sss/cli.h"
#include "sss/bake.h"
#include "sss/compress.h"
#include "sss/import.h"
#include "scene_cli.h"

static const char *TOOL = "sss-bake";

static void usage(FILE *f)
{
    fprintf(f,
        "usage: sss-bake MESH -o OUT.sss [options]\n"
        "       sss-bake --scene SCENE.json (--plan [--json] | -o DIR)   (docs/scenes.md)\n"
        "Bakes per-vertex subsurface-scattering integrals q(x, w_j) for a set of light\n"
        "directions (Hao & Varshney 2004) into OUT.sss.\n\n"
        "  MESH                 .ply (ascii/binary), .obj, .off or .stl\n"
        "  -o, --out FILE       output .sss file (written atomically)\n"
        "  --material NAME      Jensen 2001 preset: apple chicken1 chicken2 cream ketchup\n"
        "                       marble potato skimmilk skin1 skin2 wholemilk (default marble)\n"
        "  --sigma-a R,G,B      custom absorption, 1/mm (with --sigma-s, --eta)\n"
        "  --sigma-s R,G,B      custom *reduced* scattering sigma'_s = sigma_s (1-g), 1/mm\n"
        "  --eta E              relative index of refraction (default 1.3)\n"
        "  --mm-per-unit S      millimetres per mesh unit (default 1)\n"
        "  --dirs N             number of light directions (default 200)\n"
        "  --eps E              neighbourhood energy cutoff: radius holds 1-E of R_d total (default 1e-3)\n"
        "  --quant float|lloyd8 storage of the integrals (default float)\n"
        "  --own-term M         baked: the vertex's own term stays in q (the paper); runtime:\n"
        "                       it and its --rings are split off and readers add them back\n"
        "                       with a shadow test per vertex (format 1.3; docs/accuracy.md)\n"
        "  --rings K            with --own-term runtime: mesh rings split off too, 0..8 (default 1)\n"
        "Compression (Hao & Varshney 2004 sec. 4; docs/compression.md); any of these\n"
        "stores the compressed form instead of --quant:\n"
        "  --compress P         preset: paper (3%% references, SH order 3, linear 8-bit codes,\n"
        "                       16-bit barycentric weights) or compact (<= 16 / 30 bytes per\n"
        "                       vertex grey / RGB at lower error: docs/compression.md);\n"
        "                       the options below override it\n"
        "  --sh-order N         SH order 0..8 (N^2 coefficients per vertex and channel)\n"
        "  --refs FRACTION      reference vertices as a fraction of all (0: SH only;\n"
        "                       default 0.03 with --sh-order)\n"
        "  --sh-quant K         SH codes: linear8 (paper) | lloyd8 | lloyd4 (default linear8)\n"
        "  --weight-bits B      8 or 16 bits per stored weight (default 16)\n"
        "  --ls-weights         least-squares weights instead of barycentrics\n"
        "  --illum-refs W       illumination-aware references, feature weight W > 0\n"
        "  --gather direct|tree how the integrals are summed: every neighbour, or far sources\n"
        "                       through an octree of flux moments and the near ones as dense\n"
        "                       matrix-product blocks (default tree; docs/benchmarks.md)\n"
        "  --theta T            tree opening threshold in (0, 1): smaller is more accurate (default 0.4)\n"
        "  --scene S.json       bake the effects a scene calls for: one DIR/NAME.sss per object\n"
        "  --plan               with --scene: print the effect set and the reason for each decision\n"
        "  --threads T          worker threads (default: all cores); output does not depend on it\n"
        "  --json               print one JSON object with statistics on stdout\n"
        "  -q, --quiet          no progress bar or summary on stderr\n"
        "  -h, --help           this text\n");
}

/* Set by SIGINT / SIGTERM; the bake polls it (sss_bake_options.cancel). */
static volatile sig_atomic_t interrupted;

static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* What the environment says about this run: a memory limit (a share of a
 * machine used by others; the tests use it to exercise the refusal), a
 * progress log for scripts and tests, the gather's own figures. */
static void options_from_env(sss_bake_options *opt)
{
    const char *lim = getenv("SSS_MEMORY_LIMIT_MB");
    if (lim && *lim) {
        char *end;
        unsigned long long mb = strtoull(lim, &end, 10);
        if (*end == 0 && mb > 0 && mb <= (UINT64_MAX >> 20)) opt->memory_limit = (uint64_t)mb << 20;
    }
    const char *log = getenv("SSS_PROGRESS_LOG");
    if (log && *log) opt->progress_log = log;
    opt->verbose = getenv("SSS_GATHER_VERBOSE") != NULL;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    const char *in = NULL, *outp = NULL, *preset = NULL;
    double sa[3], ss[3], eta = 1.3;
    int have_sa = 0, have_ss = 0, have_eta = 0, json = 0, quiet = 0, plan_only = 0;
    const char *scene = NULL;
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    sss_compress_opts co;
    sss_compress_opts_default(&co);
    int compress = 0, have_quant = 0, have_refs = 0, compact = 0, own_set = 0, rings_set = 0;
    /* which compression options were given, so a preset only fills the rest */
    int set_order = 0, set_kind = 0, set_wbits = 0, set_ls = 0, set_illum = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
#define NEED() do { if (!v) { fprintf(stderr, "%s: %s needs a value\n", TOOL, a); return 2; } i++; } while (0)
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) { usage(stdout); return 0; }
        else if (!strcmp(a, "-o") || !strcmp(a, "--out")) { NEED(); outp = v; }
        else if (!strcmp(a, "--material")) { NEED(); preset = v; }
        else if (!strcmp(a, "--sigma-a")) { NEED(); if (!sss_cli_parse_triple(TOOL, a, v, sa)) return 2; have_sa = 1; }
        else if (!strcmp(a, "--sigma-s")) { NEED(); if (!sss_cli_parse_triple(TOOL, a, v, ss)) return 2; have_ss = 1; }
        else if (!strcmp(a, "--eta")) { NEED(); if (!sss_cli_parse_double(TOOL, a, v, 1e-3, 1e3, &eta)) return 2; have_eta = 1; }
        else if (!strcmp(a, "--mm-per-unit")) { NEED(); if (!sss_cli_parse_double(TOOL, a, v, 1e-12, 1e12, &opt.mm_per_unit)) return 2; if (!(opt.mm_per_unit > 0)) { fprintf(stderr, "%s: --mm-per-unit must be > 0\n", TOOL); return 2; } }
        else if (!strcmp(a, "--dirs")) { NEED(); if (!sss_cli_parse_u32(TOOL, a, v, 1, 100000, &opt.n_dirs)) return 2; }
        else if (!strcmp(a, "--eps")) { NEED(); if (!sss_cli_parse_double(TOOL, a, v, 1e-12, 0.5, &opt.eps)) return 2; }
        else if (!strcmp(a, "--quant")) {
            NEED();
            if (!strcmp(v, "float")) opt.quant = SSS_QUANT_FLOAT;
            else if (!strcmp(v, "lloyd8")) opt.quant = SSS_QUANT_LLOYD8;
            else { fprintf(stderr, "%s: --quant: '%s' must be float or lloyd8\n", TOOL, v); return 2; }
            have_quant = 1;
        }
        else if (!strcmp(a, "--compress")) {
            NEED();
            if (!strcmp(v, "paper")) compact = 0;
            else if (!strcmp(v, "compact")) compact = 1;
            else { fprintf(stderr, "%s: --compress: '%s' must be paper or compact\n", TOOL, v); return 2; }
            compress = 1;
        }
        else if (!strcmp(a, "--sh-order")) { NEED(); if (!sss_cli_parse_u32(TOOL, a, v, 0, 8, &co.order)) return 2; compress = 1; set_order = 1; }
        else if (!strcmp(a, "--refs")) { NEED(); if (!sss_cli_parse_double(TOOL, a, v, 0.0, 1.0, &co.fraction)) return 2; compress = 1; have_refs = 1; }
        else if (!strcmp(a, "--sh-quant")) {
            NEED();
            if (!strcmp(v, "linear8")) co.sh_kind = SSS_SHQ_LINEAR8;
            else if (!strcmp(v, "lloyd8")) co.sh_kind = SSS_SHQ_LLOYD8;
            else if (!strcmp(v, "lloyd4")) co.sh_kind = SSS_SHQ_LLOYD4;
            else { fprintf(stderr, "%s: --sh-quant: '%s' must be linear8, lloyd8 or lloyd4\n", TOOL, v); return 2; }
            compress = 1;
            set_kind = 1;
        }
        else if (!strcmp(a, "--weight-bits")) {
            NEED();
            if (!sss_cli_parse_u32(TOOL, a, v, 8, 16, &co.wbits)) return 2;
            if (co.wbits != 8 && co.wbits != 16) { fprintf(stderr, "%s: --weight-bits: '%s' must be 8 or 16\n", TOOL, v); return 2; }
            compress = 1;
            set_wbits = 1;
        }
        else if (!strcmp(a, "--ls-weights")) { co.ls_weights = 1; compress = 1; set_ls = 1; }
        else if (!strcmp(a, "--illum-refs")) { NEED(); if (!sss_cli_parse_double(TOOL, a, v, 1e-9, 1e9, &co.illum_weight)) return 2; compress = 1; set_illum = 1; }
        else if (!strcmp(a, "--gather")) {
            NEED();
            if (!strcmp(v, "direct")) opt.gather = SSS_GATHER_DIRECT;
            else if (!strcmp(v, "tree")) opt.gather = SSS_GATHER_TREE;
            else { fprintf(stderr, "%s: --gather: '%s' must be direct or tree\n", TOOL, v); return 2; }
        }
        else if (!strcmp(a, "--own-term")) {
            NEED();
            if (!strcmp(v, "runtime")) opt.own_term = SSS_OWN_TERM_RUNTIME, opt.own_rings = rings_set ? opt.own_rings : 1;
            else if (!strcmp(v, "baked")) opt.own_term = 0;
            else { fprintf(stderr, "%s: --own-term: '%s' must be runtime or baked\n", TOOL, v); return 2; }
            own_set = 1;
        }
        else if (!strcmp(a, "--rings")) {
            NEED();
            double k;
            if (!sss_cli_parse_double(TOOL, a, v, 0, SSS_OWN_RINGS_MAX, &k) || k != floor(k)) {
                fprintf(stderr, "%s: --rings: '%s' must be an integer 0 ... %u\n", TOOL, v, SSS_OWN_RINGS_MAX);
                return 2;
            }
            opt.own_rings = (uint32_t)k;
            rings_set = 1;
        }
        else if (!strcmp(a, "--theta")) { NEED(); if (!sss_cli_parse_double(TOOL, a, v, 1e-3, 0.95, &opt.theta)) return 2; }
        else if (!strcmp(a, "--threads")) { uint32_t t; NEED(); if (!sss_cli_parse_u32(TOOL, a, v, 1, 1024, &t)) return 2; opt.threads = (int)t; }
        else if (!strcmp(a, "--scene")) { NEED(); scene = v; }
        else if (!strcmp(a, "--plan")) plan_only = 1;
        else if (!strcmp(a, "--json")) json = 1;
        else if (!strcmp(a, "-q") || !strcmp(a, "--quiet")) quiet = 1;
        else if (a[0] == '-' && a[1]) { fprintf(stderr, "%s: unknown option '%s' (see --help)\n", TOOL, a); return 2; }
        else if (!in) in = a;
        else { fprintf(stderr, "%s: unexpected argument '%s' (one MESH only)\n", TOOL, a); return 2; }
#undef NEED
    }
    options_from_env(&opt);
    opt.cancel = &interrupted;
    if (plan_only && !scene) {
        fprintf(stderr, "%s: --plan needs --scene S.json\n", TOOL);
        return 2;
    }
    if (rings_set && opt.own_term != SSS_OWN_TERM_RUNTIME) {
        fprintf(stderr, "%s: --rings needs --own-term runtime\n", TOOL);
        return 2;
    }
    if (scene && own_set) {
        fprintf(stderr, "%s: --own-term applies to plain bakes, not to --scene (scene bakes keep the own term)\n",
                TOOL);
        return 2;
    }
    if (scene) {
        if (in) {
            fprintf(stderr, "%s: --scene and a MESH argument exclude each other (the scene names the meshes)\n", TOOL);
            return 2;
        }
        opt.progress = 0;
        return scene_main(TOOL, scene, outp, plan_only, json, quiet, &opt);
    }
    if (compress && have_quant) {
        fprintf(stderr, "%s: --quant and the compression options (--sh-order, --refs, ...) exclude each other\n",
                TOOL);
        return 2;
    }
    if (compress && !have_refs && set_order && co.order == 0) {
        fprintf(stderr, "%s: --sh-order 0 needs --refs FRACTION > 0 (nothing would be stored)\n", TOOL);
        return 2;
    }
    if (compress && co.fraction == 0.0 && co.order == 0) {
        fprintf(stderr, "%s: --refs 0 (SH only) needs --sh-order >= 1\n", TOOL);
        return 2;
    }
    if (compress) opt.quant = SSS_QUANT_FLOAT;
    if (!in || !outp) {
        fprintf(stderr, "%s: %s (see --help)\n", TOOL, !in ? "missing MESH" : "missing -o OUT.sss");
        return 2;
    }
    sss_error err = {{0}};
    sss_material mat;
    if (have_sa || have_ss) {
        if (preset || !have_sa || !have_ss) {
            fprintf(stderr, "%s: give either --material NAME or both --sigma-a and --sigma-s\n", TOOL);
            return 2;
        }
        memset(&mat, 0, sizeof mat);
        snprintf(mat.name, sizeof mat.name, "custom");
        for (int c = 0; c < 3; c++) { mat.sigma_a[c] = sa[c]; mat.sigmap_s[c] = ss[c]; }
        mat.eta = eta;
    } else if (sss_material_preset(preset ? preset : "marble", &mat, &err) != SSS_OK) {
        fprintf(stderr, "%s: %s\n", TOOL, err.msg);
        return 2;
    } else if (have_eta) {
        mat.eta = eta;
    }
    if (sss_material_validate(&mat, &err) != SSS_OK) {
        fprintf(stderr, "%s: %s\n", TOOL, err.msg);
        return 2;
    }
    if (compress) {
        /* a preset fills what the user did not set (docs/compression.md) */
        const uint32_t given = (set_order ? SSS_CO_ORDER : 0) | (have_refs ? SSS_CO_FRACTION : 0) |
                               (set_kind ? SSS_CO_SH_KIND : 0) | (set_wbits ? SSS_CO_WBITS : 0) |
                               (set_ls ? SSS_CO_LS_WEIGHTS : 0) | (set_illum ? SSS_CO_ILLUM : 0);
        sss_compress_preset_apply(&co, compact ? SSS_COMPRESS_COMPACT : SSS_COMPRESS_PAPER,
                                  sss_material_channels(&mat), given);
        opt.compress = &co;
    }
    opt.progress = !quiet;
    /* under mpirun: split the receivers, rank 0 alone speaks and writes */
    int mpi_rank = 0, mpi_n = 1;
    sss_mpi_start(&argc, &argv, &mpi_rank, &mpi_n);
    if (mpi_n > 1) {
        opt.rank = mpi_rank;
        opt.nranks = mpi_n;
        opt.comm = sss_mpi_comm();
        if (mpi_rank != 0) { opt.progress = 0; quiet = 1; json = 0; }
    }
    signal(SIGINT, on_sigint);
    signal(SIGTERM, on_sigint);

    double t0 = now_s();
    sss_mesh mesh;
    sss_import_report rep;
    if (sss_import_mesh(in, &mesh, &rep, &err) != SSS_OK) {
        fprintf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    double t_import = now_s() - t0;
    {
        char prefix[600];
        snprintf(prefix, sizeof prefix, "%s: %s", TOOL, in);
        if (!quiet) sss_import_print_repairs(&rep, prefix, stderr);
        sss_import_print_warnings(&rep, prefix, stderr); /* also with -q, like the bake's warnings */
    }
    if (rep.recentred) opt.import_offset = rep.offset; /* provenance (docs/robustness.md B6) */

    sss_bake_file f;
    sss_bake_stats st;
    if (sss_bake(&mesh, sss_cli_basename(in), &mat, &opt, &f, &st, &err) != SSS_OK) {
        fprintf(stderr, "%s: %s: %s\n", TOOL, in, err.msg);
        sss_mesh_free(&mesh);
        sss_mpi_abort(interrupted ? 130 : 1); /* the other ranks wait in a collective */
        return interrupted ? 130 : 1;
    }
    if (mpi_n > 1 && mpi_rank != 0) { /* its part went to rank 0 */
        sss_file_free(&f);
        sss_mesh_free(&mesh);
        sss_mpi_stop();
        return 0;
    }
    const double t_compress = st.t_compress;
    t0 = now_s();
    /* a signal after the bake's last poll: still nothing is written */
    sss_result r = interrupted ? sss_fail(&err, SSS_ERR_INTERRUPTED, "%s: interrupted, nothing written", outp)
                                        : sss_file_write(outp, &f, &err);
    double t_write = now_s() - t0;
    if (r != SSS_OK) {
        fprintf(stderr, "%s: %s\n", TOOL, err.msg);
        sss_file_free(&f);
        sss_mesh_free(&mesh);
        return r == SSS_ERR_INTERRUPTED ? 130 : 1;
    }
    FILE *fp = fopen(outp, "rb");
    long long fsize = -1;
    if (fp) { fseek(fp, 0, SEEK_END); fsize = ftell(fp); fclose(fp); }
    const uint32_t nv = f.mesh.nv, C = f.channels, N = f.dirs.n;
    double q_bytes = sss_file_integral_bytes_per_vertex(&f);
    double total = t_import + st.t_neighbourhoods + st.t_tree + st.t_visibility + st.t_integrals + st.t_quantise + t_compress +
                   t_write;
    if (!quiet)
        fprintf(stderr,
                "%s: %s: %u vertices, %u triangles, %u directions, %u channels, %s\n"
                "  neighbourhood radius %.3g/%.3g/%.3g mm, mean %.1f neighbours (max %u)\n"
                "  rays %llu (%.1f%% occluded)%s\n"
                "  time: import %.3fs, neighbourhoods %.3fs, visibility %.3fs, integrals %.3fs, quantise %.3fs, compress %.3fs, write %.3fs\n"
                "  %s: %lld bytes, %.1f bytes/vertex (integrals %.1f)\n",
                TOOL, in, nv, f.mesh.nf, N, C, sss_quant_name(f.quant), st.radius_mm[0],
                st.radius_mm[1], st.radius_mm[2], st.neighbours_mean, st.neighbours_max, (unsigned long long)st.rays,
                100.0 * st.occluded_fraction, "", t_import, st.t_neighbourhoods, st.t_visibility, st.t_integrals,
                st.t_quantise, t_compress, t_write, outp, fsize, (double)fsize / nv, q_bytes);
    if (st.thin_vertices)
        fprintf(stderr, "%s: %s: warning: %u vertices lie on parts thinner than the scattering length 1/sigma_tr = %.3g mm "
                "(thinnest %.3g mm): the semi-infinite dipole counts light gathered through them twice, so q there comes "
                "out too large (docs/robustness.md B8)\n", TOOL, in, st.thin_vertices, st.thin_limit_mm, st.thinnest_mm);
    if (!quiet)
        fprintf(stderr, "  gather %s%s: tree %.3fs, %.1f GFLOP/s%s; memory predicted %.0f MiB, peak RSS %.0f MiB%s\n",
                st.gather == SSS_GATHER_TREE ? "tree" : "direct",
                st.gather == SSS_GATHER_TREE ? "" : " (every neighbour)", st.t_tree, st.gather_gflops,
                st.gather == SSS_GATHER_TREE ? " in the block products" : " multiply-adds x 2", st.predicted_peak_bytes / 1048576.0,
                sss_cli_peak_rss_mib(), mpi_n > 1 ? " (rank 0)" : "");
    if (!quiet && st.direction_chunks > 1) /* issue 8: the memory plan of bake_gather.c */
        fprintf(stderr, "  light directions in %u chunks of at most %u: the memory available would not hold the "
                "transfer rows and tree moments of all %u at once (same output)\n",
                st.direction_chunks, st.direction_chunk_width, N);
    if (st.coarse_vertices)
        fprintf(stderr, "%s: %s: warning: %u vertices have an edge longer than %.3g mm, twice the scattering length "
                "1/sigma_tr = %.3g mm (longest edge %.3g mm): the per-vertex sum does not resolve the profile there "
                "and q comes out too large; resample the mesh finer\n", TOOL, in, st.coarse_vertices,
                2.0 * st.range_mm, st.range_mm, st.longest_edge_mm);
    if (!quiet && f.quant == SSS_QUANT_REFS)
        fprintf(stderr, "  %u references (%.2f%%), %u reference triangles, SH order %u (%s), %u-bit %s weights\n",
                f.ref.nref, 100.0 * f.ref.nref / nv, f.ref.nrt, f.sh.order, sss_shq_name(f.sh.kind), f.ref.wbits,
                co.ls_weights ? "least-squares" : "barycentric");
    if (!quiet && f.quant == SSS_QUANT_SH)
        fprintf(stderr, "  SH order %u (%s) at every vertex\n", f.sh.order, sss_shq_name(f.sh.kind));
    if (!quiet && f.quant == SSS_QUANT_LLOYD8)
        fprintf(stderr, "  lloyd8 SNR %.2f dB (R %.2f, G %.2f, B %.2f)\n", st.lloyd_snr_db_all, st.lloyd_snr_db[0],
                st.lloyd_snr_db[1], st.lloyd_snr_db[2]);
    if (json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "mesh", in);
        cJSON_AddStringToObject(o, "output", outp);
        cJSON_AddNumberToObject(o, "vertices", nv);
        cJSON_AddNumberToObject(o, "triangles", f.mesh.nf);
        cJSON_AddNumberToObject(o, "directions", N);
        cJSON_AddNumberToObject(o, "channels", C);
        cJSON_AddStringToObject(o, "quant", sss_quant_name(f.quant));
        if (compress) {
            cJSON_AddNumberToObject(o, "sh_order", f.sh.order);
            cJSON_AddStringToObject(o, "sh_quant", sss_shq_name(f.sh.kind));
            cJSON_AddNumberToObject(o, "refs", f.quant == SSS_QUANT_REFS ? f.ref.nref : 0);
        }
        cJSON_AddStringToObject(o, "material", mat.name);
        cJSON_AddNumberToObject(o, "mm_per_unit", f.mm_per_unit);
        cJSON *rp = cJSON_AddObjectToObject(o, "repairs");
        cJSON_AddNumberToObject(rp, "polygons_triangulated", (double)rep.polygons_triangulated);
        cJSON_AddNumberToObject(rp, "faces_too_small", (double)rep.faces_too_small);
        cJSON_AddNumberToObject(rp, "faces_repeated_index", (double)rep.faces_repeated_index);
        cJSON_AddNumberToObject(rp, "faces_zero_area", (double)rep.faces_zero_area);
        cJSON_AddNumberToObject(rp, "vertices_unreferenced", (double)rep.vertices_unreferenced);
        cJSON_AddNumberToObject(rp, "polygons_ear_clipped", (double)rep.polygons_ear_clipped);
        cJSON_AddNumberToObject(rp, "polygons_unclipped", (double)rep.polygons_unclipped);
        cJSON_AddNumberToObject(rp, "faces_duplicate", (double)rep.faces_duplicate);
        cJSON_AddNumberToObject(rp, "faces_flipped", (double)rep.faces_flipped);
        cJSON_AddNumberToObject(rp, "surfaces_inside_out", (double)rep.surfaces_inside_out);
        cJSON_AddNumberToObject(rp, "open_faces_flipped", (double)rep.open_faces_flipped);
        cJSON_AddNumberToObject(rp, "orientation_conflicts", (double)rep.orientation_conflicts);
        cJSON_AddNumberToObject(rp, "recentred", (double)rep.recentred);
        if (rep.recentred) cJSON_AddItemToObject(rp, "offset", cJSON_CreateDoubleArray(rep.offset, 3));
        cJSON_AddItemToObject(o, "radius_mm", cJSON_CreateDoubleArray(st.radius_mm, 3));
        cJSON_AddNumberToObject(o, "coarse_vertices", st.coarse_vertices);
        cJSON_AddNumberToObject(o, "thin_vertices", st.thin_vertices);
        if (isfinite(st.thinnest_mm)) cJSON_AddNumberToObject(o, "thinnest_mm", st.thinnest_mm);
        cJSON_AddNumberToObject(o, "longest_edge_mm", st.longest_edge_mm);
        cJSON_AddNumberToObject(o, "scattering_length_mm", st.range_mm);
        cJSON_AddNumberToObject(o, "neighbours_mean", st.neighbours_mean);
        cJSON_AddNumberToObject(o, "neighbours_max", st.neighbours_max);
        cJSON_AddNumberToObject(o, "rays", (double)st.rays);
        cJSON_AddNumberToObject(o, "occluded_fraction", st.occluded_fraction);
        cJSON *tm = cJSON_AddObjectToObject(o, "seconds");
        cJSON_AddNumberToObject(tm, "import", t_import);
        cJSON_AddNumberToObject(tm, "neighbourhoods", st.t_neighbourhoods);
        cJSON_AddNumberToObject(tm, "visibility", st.t_visibility);
        cJSON_AddNumberToObject(tm, "integrals", st.t_integrals);
        cJSON_AddNumberToObject(tm, "quantise", st.t_quantise);
        cJSON_AddNumberToObject(tm, "compress", t_compress);
        cJSON_AddNumberToObject(tm, "write", t_write);
        cJSON_AddNumberToObject(tm, "total", total);
        cJSON_AddNumberToObject(o, "peak_rss_mib", sss_cli_peak_rss_mib());
        /* issue 8: the gather, its sgemm rate and the memory predicted before starting */
        cJSON_AddStringToObject(o, "gather", st.gather == SSS_GATHER_TREE ? "tree" : "direct");
        if (st.gather == SSS_GATHER_TREE) {
            cJSON_AddNumberToObject(o, "theta", st.theta);
            cJSON_AddNumberToObject(o, "tree_nodes", st.tree_nodes);
            cJSON_AddNumberToObject(o, "tree_blocks", st.tree_blocks);
            cJSON_AddNumberToObject(o, "rows_per_block", st.rows_mean);
            cJSON_AddNumberToObject(o, "far_nodes_per_vertex", st.far_pairs / (double)nv);
            cJSON_AddNumberToObject(o, "sgemm_fraction", st.sgemm_fraction);
            cJSON_AddNumberToObject(o, "direction_chunks", st.direction_chunks);
            cJSON_AddNumberToObject(o, "direction_chunk_width", st.direction_chunk_width);
            cJSON_AddNumberToObject(tm, "tree", st.t_tree);
        }
        cJSON_AddNumberToObject(o, "gather_gflops", st.gather_gflops);
        if (st.gather == SSS_GATHER_TREE) cJSON_AddNumberToObject(o, "near_gflops", st.near_gflops);
        cJSON_AddNumberToObject(o, "predicted_peak_mib", st.predicted_peak_bytes / 1048576.0);
        cJSON_AddNumberToObject(o, "mpi_ranks", mpi_n);
        cJSON_AddNumberToObject(o, "file_bytes", (double)fsize);
        cJSON_AddNumberToObject(o, "bytes_per_vertex", (double)fsize / nv);
        cJSON_AddNumberToObject(o, "integral_bytes_per_vertex", q_bytes);
        if (f.quant == SSS_QUANT_LLOYD8) {
            cJSON_AddNumberToObject(o, "lloyd_snr_db", st.lloyd_snr_db_all);
            cJSON_AddItemToObject(o, "lloyd_snr_db_per_channel", cJSON_CreateDoubleArray(st.lloyd_snr_db, 3));
        }
        char *s = cJSON_PrintUnformatted(o);
        puts(s);
        free(s);
        cJSON_Delete(o);
    }
    sss_file_free(&f);
    sss_mesh_free(&mesh);
    sss_mpi_stop();
    return 0;
}
