/* compress_bench: size and error of the Hao–Varshney 2004 §4 compression
 * (reference points + weights + SH-coded deltas, or SH alone) of one float
 * .sss bake, for the table in docs/compression.md.
 *   compress_bench FILE.sss ORDER FRACTION [options]
 *     --dirs N          random test light directions (default 1000)
 *     --kind K          SH codes: linear8 (paper) | lloyd8 | lloyd4 | linear16
 *     --wbits B         8 or 16 bits per weight (default 16)
 *     --ls              least-squares weights (beyond the paper)
 *     --illum W         illumination-aware references with weight W
 *     --mono C          compress channel C only, as a one-channel bake
 *     --out FILE        also write the compressed .sss
 *     --configs FILE    run every line of FILE ("ORDER FRACTION [options]") after
 *                       reading the bake once; references are chosen once per
 *                       (fraction, --illum) and reused across SH settings
 *     --row             print one markdown table row instead of JSON:
 *                       | channels | refs (%) | order | codes | weights | B/vertex (all scattering bytes, directions included) | rel. RMS | RMS | max |
 * FRACTION 0 is SH-only mode. Prints one JSON object: counts, bytes of every
 * part (sss_file_storage: all bytes of the scattering data), bytes per vertex,
 * area-weighted relative RMS against the uncompressed interpolation (per
 * channel and overall) over the test directions (fixed seed), and times.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/clock.h"
#include "sss/compress.h"
#include "sss/decode.h"
#include "sss/format.h"
#include "sss/refs.h"

static int usage(void)
{
    fprintf(stderr, "usage: compress_bench FILE.sss ORDER FRACTION [--dirs N] [--kind linear8|lloyd8|lloyd4|linear16] "
                    "[--wbits 8|16] [--ls] [--illum W] [--mono C] [--out FILE] [--row]\n"
                    "       compress_bench FILE.sss --configs LIST [--dirs N] [--mono C] [--row]\n");
    return 2;
}

typedef struct globals {
    unsigned long ndt;
    long mono;
    int row;
    const char *outpath;
    const char *configs;
} globals;

/* Parses options (and, when positional is set, ORDER FRACTION first) into
 * o and g. Returns 0 on a bad argument. */
static int parse_args(int n, char **a, int positional, sss_compress_opts *o, globals *g)
{
    int i = 0;
    char *end;
    if (positional) {
        if (n < 2) return 0;
        unsigned long order = strtoul(a[0], &end, 10);
        if (*end || order > 100) return 0;
        o->order = (uint32_t)order;
        o->fraction = strtod(a[1], &end);
        if (*end) return 0;
        i = 2;
    }
    for (; i < n; i++) {
        const char *x = a[i], *v = i + 1 < n ? a[i + 1] : NULL;
        if (!strcmp(x, "--ls")) o->ls_weights = 1;
        else if (!strcmp(x, "--row")) g->row = 1;
        else if (!v) return 0;
        else if (!strcmp(x, "--dirs")) g->ndt = strtoul(v, NULL, 10), i++;
        else if (!strcmp(x, "--wbits")) o->wbits = (uint32_t)strtoul(v, NULL, 10), i++;
        else if (!strcmp(x, "--illum")) o->illum_weight = strtod(v, NULL), i++;
        else if (!strcmp(x, "--mono")) g->mono = strtol(v, NULL, 10), i++;
        else if (!strcmp(x, "--out")) g->outpath = v, i++;
        else if (!strcmp(x, "--configs")) g->configs = v, i++;
        else if (!strcmp(x, "--kind")) {
            if (!strcmp(v, "linear8")) o->sh_kind = SSS_SHQ_LINEAR8;
            else if (!strcmp(v, "lloyd8")) o->sh_kind = SSS_SHQ_LLOYD8;
            else if (!strcmp(v, "lloyd4")) o->sh_kind = SSS_SHQ_LLOYD4;
            else if (!strcmp(v, "linear16")) o->sh_kind = SSS_SHQ_LINEAR16;
            else return 0;
            i++;
        } else return 0;
    }
    return 1;
}

/* References reused across configurations with the same (fraction, illum). */
typedef struct refs_cache {
    int valid;
    double fraction, illum;
    sss_refs refs;
} refs_cache;

/* Keeps channel c of a float bake as a one-channel bake (in place). */
static int to_mono(sss_bake_file *f, uint32_t c)
{
    if (c >= f->channels || f->quant != SSS_QUANT_FLOAT) return 0;
    const size_t n = (size_t)f->dirs.n * f->mesh.nv, C = f->channels;
    for (size_t i = 0; i < n; i++) f->q[i] = f->q[i * C + c];
    f->material.sigma_a[0] = f->material.sigma_a[c];
    f->material.sigmap_s[0] = f->material.sigmap_s[c];
    f->channels = 1;
    return 1;
}


static int run_one(const char *path, sss_bake_file *f, sss_compress_opts o, const globals *g, refs_cache *cache)
{
    sss_error err = {{0}};
    sss_bake_file cf;
    double t0 = sss_now(), t_refs = 0.0;
    if (o.fraction > 0.0) {
        if (!cache->valid || cache->fraction != o.fraction || cache->illum != o.illum_weight) {
            sss_refs_free(&cache->refs);
            cache->valid = 0;
            if (sss_compress_choose_refs(f, o.fraction, o.illum_weight, &cache->refs, &err) != SSS_OK) {
                fprintf(stderr, "compress_bench: %s\n", err.msg);
                return 1;
            }
            cache->valid = 1;
            cache->fraction = o.fraction;
            cache->illum = o.illum_weight;
        }
        o.refs = &cache->refs;
        t_refs = sss_now() - t0;
    }
    if (sss_compress(f, &o, &cf, &err) != SSS_OK) {
        fprintf(stderr, "compress_bench: %s\n", err.msg);
        return 1;
    }
    double t_compress = sss_now() - t0;
    if (g->outpath && sss_file_write(g->outpath, &cf, &err) != SSS_OK) {
        fprintf(stderr, "compress_bench: %s\n", err.msg);
        return 1;
    }
    sss_storage b;
    sss_file_storage(&cf, &b);
    double rel[SSS_MAX_CHANNELS + 1], rms[SSS_MAX_CHANNELS + 1], max_abs = 0;
    t0 = sss_now();
    if (sss_decode_error(&cf, f, (uint32_t)g->ndt, 12345, rel, rms, &max_abs, &err) != SSS_OK) {
        fprintf(stderr, "compress_bench: %s\n", err.msg);
        return 1;
    }
    double t_error = sss_now() - t0;
    /* per-call evaluation time: median-free mean over 20 directions */
    float *out = malloc((size_t)cf.mesh.nv * cf.channels * sizeof *out);
    double t_eval = 0.0;
    if (out) {
        t0 = sss_now();
        for (int i = 0; i < 20; i++) {
            double a = 0.37 * i, light[3] = {sin(a), 0.3, cos(a)};
            sss_decode_all(&cf, light, out);
        }
        t_eval = (sss_now() - t0) / 20.0;
        free(out);
    }
    const uint32_t nv = cf.mesh.nv, C = cf.channels;
    static const char *kinds[] = {"linear8", "lloyd8", "lloyd4", "linear16"};
    if (g->row) {
        char refs[64] = "—", w[64] = "—";
        if (cf.quant == SSS_QUANT_REFS) {
            snprintf(refs, sizeof refs, "%u (%.2f %%)%s", cf.ref.nref, 100.0 * cf.ref.nref / nv,
                     o.illum_weight > 0 ? " illum" : "");
            snprintf(w, sizeof w, "%u-bit %s", o.wbits, o.ls_weights ? "LS" : "bary");
        }
        printf("| %s | %s | %u | %s | %s | %.2f | %.4f | %.3g | %.3g |\n", C == 1 ? "mono" : "RGB", refs, o.order,
               o.order ? kinds[o.sh_kind] : "—", w, (double)b.total / nv, rel[C], rms[C], max_abs);
        fflush(stdout);
        sss_file_free(&cf);
        return 0;
    }
    printf("{\"file\": \"%s\", \"vertices\": %u, \"channels\": %u, \"directions\": %u, \"order\": %u, "
           "\"sh_kind\": \"%s\", \"fraction\": %g, \"wbits\": %u, \"ls_weights\": %d, \"illum_weight\": %g, "
           "\"refs\": %u, \"ref_triangles\": %u, \"coded_vertices\": %u,\n",
           path, nv, C, cf.dirs.n, o.order, kinds[o.sh_kind], o.fraction, o.wbits, o.ls_weights, o.illum_weight,
           cf.ref.nref, cf.ref.nrt, cf.sh.ncoded);
    printf(" \"bytes\": {\"dirs\": %llu, \"section_headers\": %llu, \"lloyd_tables\": %llu, \"ref_vertex\": %llu, "
           "\"ref_tri\": %llu, \"vertex_tri\": %llu, \"weights\": %llu, \"ref_values\": %llu, \"sh_tables\": %llu, "
           "\"sh_codes\": %llu, \"scattering\": %llu, \"total\": %llu},\n",
           (unsigned long long)b.dirs, (unsigned long long)b.section_headers, (unsigned long long)b.lloyd_tables,
           (unsigned long long)b.ref_vertex, (unsigned long long)b.ref_tri, (unsigned long long)b.vertex_tri,
           (unsigned long long)b.weights, (unsigned long long)b.ref_values, (unsigned long long)b.sh_tables,
           (unsigned long long)b.sh_codes, (unsigned long long)b.scattering, (unsigned long long)b.total);
    printf(" \"bytes_per_vertex\": %.3f, \"bytes_per_vertex_with_dirs\": %.3f, "
           "\"uncompressed_float_bytes_per_vertex\": %u, \"uncompressed_lloyd8_bytes_per_vertex\": %u,\n",
           (double)b.scattering / nv, (double)b.total / nv, cf.dirs.n * C * 4, cf.dirs.n * C);
    printf(" \"test_directions\": %lu, \"rel_rms\": %.6g, \"rms\": %.6g, \"rel_rms_channel\": [", g->ndt, rel[C], rms[C]);
    for (uint32_t c = 0; c < C; c++) printf("%s%.6g", c ? ", " : "", rel[c]);
    printf("], \"max_abs_error\": %.6g,\n", max_abs);
    printf(" \"seconds\": {\"compress\": %.3f, \"references\": %.3f, \"eval_per_call\": %.6f, "
           "\"error_measurement\": %.3f}}\n", t_compress, t_refs, t_eval, t_error);
    fflush(stdout);
    sss_file_free(&cf);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 3) return usage();
    sss_compress_opts base;
    sss_compress_opts_default(&base);
    globals g = {1000, -1, 0, NULL, NULL};
    int has_configs = 0;
    for (int i = 2; i < argc; i++)
        if (!strcmp(argv[i], "--configs")) has_configs = 1;
    if (!parse_args(argc - 2, argv + 2, !has_configs, &base, &g)) return usage();
    if (g.ndt == 0 || g.ndt > 1000000) return usage();
    sss_error err = {{0}};
    sss_bake_file f;
    if (sss_file_read(argv[1], &f, &err) != SSS_OK) {
        fprintf(stderr, "compress_bench: %s\n", err.msg);
        return 1;
    }
    if (g.mono >= 0 && !to_mono(&f, (uint32_t)g.mono)) {
        fprintf(stderr, "compress_bench: --mono %ld: no such channel in a float bake\n", g.mono);
        sss_file_free(&f);
        return 1;
    }
    refs_cache cache;
    memset(&cache, 0, sizeof cache);
    int rc = 0;
    if (!has_configs) {
        rc = run_one(argv[1], &f, base, &g, &cache);
    } else {
        FILE *lf = fopen(g.configs, "r");
        if (!lf) {
            fprintf(stderr, "compress_bench: cannot open %s\n", g.configs);
            rc = 1;
        }
        char line[512];
        while (lf && !rc && fgets(line, sizeof line, lf)) {
            char *tok[32];
            int n = 0;
            for (char *t = strtok(line, " \t\r\n"); t && n < 32; t = strtok(NULL, " \t\r\n")) tok[n++] = t;
            if (n == 0 || tok[0][0] == '#') continue;
            sss_compress_opts o = base;
            globals gl = g;
            if (!parse_args(n, tok, 1, &o, &gl)) {
                fprintf(stderr, "compress_bench: %s: bad configuration line\n", g.configs);
                rc = 2;
                break;
            }
            rc = run_one(argv[1], &f, o, &gl, &cache);
        }
        if (lf) fclose(lf);
    }
    sss_refs_free(&cache.refs);
    sss_file_free(&f);
    return rc;
}
