/* compress_bench: size and error of the Hao–Varshney 2004 §4 compression
 * (reference points + barycentric weights + SH-coded deltas, or SH alone)
 * of one float .sss bake.
 *   compress_bench FILE.sss ORDER FRACTION [DIRECTIONS=1000]
 * FRACTION 0 is SH-only mode. Prints one JSON object: counts, bytes of every
 * part, bytes per vertex, area-weighted relative RMS error against the
 * uncompressed interpolation (per channel and overall) over DIRECTIONS
 * random light directions (fixed seed), the largest absolute error, and the
 * compression and per-call evaluation times.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "sss/compress.h"
#include "sss/format.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 4 || argc > 5) {
        fprintf(stderr, "usage: compress_bench FILE.sss ORDER FRACTION [DIRECTIONS=1000]\n");
        return 2;
    }
    char *end;
    unsigned long order = strtoul(argv[2], &end, 10);
    if (*end || order > 100) {
        fprintf(stderr, "compress_bench: bad ORDER '%s'\n", argv[2]);
        return 2;
    }
    double fraction = strtod(argv[3], &end);
    if (*end) {
        fprintf(stderr, "compress_bench: bad FRACTION '%s'\n", argv[3]);
        return 2;
    }
    unsigned long ndt = 1000;
    if (argc == 5) {
        ndt = strtoul(argv[4], &end, 10);
        if (*end || ndt == 0 || ndt > 1000000) {
            fprintf(stderr, "compress_bench: bad DIRECTIONS '%s'\n", argv[4]);
            return 2;
        }
    }
    sss_error err = {{0}};
    sss_bake_file f;
    if (sss_file_read(argv[1], &f, &err) != SSS_OK) {
        fprintf(stderr, "compress_bench: %s\n", err.msg);
        return 1;
    }
    sss_compressed cq;
    double t0 = now();
    if (sss_compress(&f, (uint32_t)order, fraction, &cq, &err) != SSS_OK) {
        fprintf(stderr, "compress_bench: %s\n", err.msg);
        sss_file_free(&f);
        return 1;
    }
    double t_compress = now() - t0;
    sss_compressed_bytes b;
    sss_compressed_bytes_of(&cq, &b);

    double rel[SSS_MAX_CHANNELS + 1], max_abs = 0, max_rel = 0;
    t0 = now();
    if (sss_compressed_error(&cq, &f, (uint32_t)ndt, 12345, rel, &max_abs, &max_rel, &err) != SSS_OK) {
        fprintf(stderr, "compress_bench: %s\n", err.msg);
        sss_compressed_free(&cq);
        sss_file_free(&f);
        return 1;
    }
    double t_error = now() - t0;
    /* per-call evaluation time: mean over 50 directions */
    float *out = malloc((size_t)cq.nv * cq.channels * sizeof *out);
    double t_eval = 0.0;
    if (out) {
        t0 = now();
        for (int i = 0; i < 50; i++) {
            double a = 0.37 * i, light[3] = {sin(a), 0.3, cos(a)};
            sss_compressed_eval(&cq, light, out);
        }
        t_eval = (now() - t0) / 50.0;
        free(out);
    }
    const double raw_float = (double)f.dirs.n * f.channels * 4.0, raw_lloyd8 = (double)f.dirs.n * f.channels;
    printf("{\"file\": \"%s\", \"vertices\": %u, \"channels\": %u, \"directions\": %u, \"order\": %lu, "
           "\"fraction\": %g, \"refs\": %u, \"ref_triangles\": %u, \"coded_vertices\": %u,\n",
           argv[1], cq.nv, cq.channels, cq.dirs.n, order, fraction, cq.nref, cq.nrt, cq.ncoded);
    printf(" \"bytes\": {\"header\": %llu, \"directions\": %llu, \"ref_integrals\": %llu, \"lloyd_tables\": %llu, "
           "\"ref_vertex_list\": %llu, \"vertex_tri\": %llu, \"ref_tri_table\": %llu, \"weights\": %llu, "
           "\"sh_codes\": %llu, \"sh_scales\": %llu, \"total\": %llu},\n",
           (unsigned long long)b.header, (unsigned long long)b.directions, (unsigned long long)b.ref_integrals,
           (unsigned long long)b.lloyd_tables, (unsigned long long)b.ref_vertex_list,
           (unsigned long long)b.vertex_tri, (unsigned long long)b.ref_tri_table, (unsigned long long)b.weights,
           (unsigned long long)b.sh_codes, (unsigned long long)b.sh_scales, (unsigned long long)b.total);
    printf(" \"bytes_per_vertex\": %.3f, \"uncompressed_float_bytes_per_vertex\": %.0f, "
           "\"uncompressed_lloyd8_bytes_per_vertex\": %.0f,\n",
           b.per_vertex, raw_float, raw_lloyd8);
    printf(" \"test_directions\": %lu, \"rel_rms\": %.6g, \"rel_rms_channel\": [", ndt, rel[cq.channels]);
    for (uint32_t c = 0; c < cq.channels; c++) printf("%s%.6g", c ? ", " : "", rel[c]);
    printf("], \"max_abs_error\": %.6g, \"max_error_over_rms\": %.6g,\n", max_abs, max_rel);
    printf(" \"seconds\": {\"compress\": %.3f, \"eval_per_call\": %.6f, \"error_measurement\": %.3f}}\n", t_compress,
           t_eval, t_error);
    sss_compressed_free(&cq);
    sss_file_free(&f);
    return 0;
}
