/* decode_bench: CPU scatter-evaluation throughput of sss_decode_all against
 * the memory-bandwidth bound, for one .sss file.
 *   decode_bench FILE.sss [FRAMES]
 *   decode_bench --decode-only FRAMES [--evict MIB] FILE.sss...
 *     one line per file: "FILE quant ms_1t", the one-thread median alone
 *     (no bandwidth runs: the files' forms compared side by side);
 *     --evict: before each frame, write MIB MiB of other memory, as the
 *     viewer's draw does between two decodes, so that the decode reads
 *     its data from memory, not from the caches (docs/benchmarks.md)
 * Prints one JSON object: the measured read and copy bandwidth (one thread
 * and all threads), the decode time per frame (median over FRAMES light
 * directions, one thread and all threads), the bytes each frame must move
 * (3 direction rows read + the q output written) and the resulting bound.
 */
#include <math.h>
#include <stdint.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/clock.h"
#include "sss/decode.h"
#include "sss/format.h"

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmpd);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Bandwidth with the decode's own access pattern: three read streams and
 * one write stream, out[i] = a[i] + b[i] + c[i] over float arrays far larger
 * than the caches (STREAM-style "sum3"); bytes/s counting 16 bytes per
 * element, median of 9 runs. Also a plain copy for reference. */
static void bandwidth(int threads, double *sum3_bps, double *copy_bps)
{
    const size_t n = (size_t)32 << 20; /* 128 MiB per array */
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c), *o = malloc(n * sizeof *o);
#pragma omp parallel for num_threads(threads)
    for (size_t i = 0; i < n; i++) { a[i] = (float)(i & 1023); b[i] = 1; c[i] = 2; o[i] = 0; }
    double ts[9], tc[9];
    for (int r = 0; r < 9; r++) {
        double t = sss_now();
#pragma omp parallel for num_threads(threads)
        for (size_t i = 0; i < n; i++) o[i] = a[i] + b[i] + c[i];
        ts[r] = sss_now() - t;
        t = sss_now();
#pragma omp parallel for num_threads(threads)
        for (size_t i = 0; i < n; i++) o[i] = a[i];
        tc[r] = sss_now() - t;
    }
    *sum3_bps = 16.0 * n / median(ts, 9);
    *copy_bps = 8.0 * n / median(tc, 9);
    free(a); free(b); free(c); free(o);
}

/* Memory written between frames (--evict): n bytes, each frame other
 * values, so no cache keeps the decode's data. */
static unsigned char *g_evict;
static size_t g_evict_n;

static double decode_ms(const sss_bake_file *f, float *out, int threads, int frames)
{
    omp_set_num_threads(threads);
    double *t = malloc(sizeof(double) * (size_t)frames);
    for (int i = -2; i < frames; i++) {
        double a = 0.37 * i, light[3] = {sin(a), 0.3, cos(a)};
        /* read and written through the caches (a large memset may bypass them) */
        for (size_t k = 0; k < g_evict_n; k += 64) g_evict[k] = (unsigned char)(g_evict[k] + 1);
        double t0 = sss_now();
        sss_decode_all(f, light, out);
        if (i >= 0) t[i] = 1e3 * (sss_now() - t0);
    }
    double m = median(t, frames);
    free(t);
    return m;
}

int main(int argc, char **argv)
{
    if (argc < 2) { fprintf(stderr, "usage: decode_bench FILE.sss [FRAMES] | --decode-only FRAMES [--evict MIB] FILE...\n"); return 2; }
    if (!strcmp(argv[1], "--decode-only") && argc > 3) {
        const int n = atoi(argv[2]) > 0 ? atoi(argv[2]) : 1;
        int a = 3;
        if (!strcmp(argv[3], "--evict") && argc > 5) {
            g_evict_n = (size_t)atoi(argv[4]) << 20;
            if (!(g_evict = calloc(g_evict_n ? g_evict_n : 1, 1))) return 1;
            a = 5;
        }
        for (; a < argc; a++) {
            sss_bake_file g;
            sss_error e = {{0}};
            if (sss_file_read(argv[a], &g, &e) != SSS_OK) { fprintf(stderr, "decode_bench: %s\n", e.msg); return 1; }
            float *o = malloc((size_t)g.mesh.nv * g.channels * sizeof(float));
            if (!o) return 1;
            printf("%s %s %.4f\n", argv[a], sss_quant_name(g.quant), decode_ms(&g, o, 1, n));
            fflush(stdout);
            free(o);
            sss_file_free(&g);
        }
        free(g_evict);
        return 0;
    }
    int frames = argc > 2 ? atoi(argv[2]) : 50;
    if (frames < 1) frames = 1;
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_read(argv[1], &f, &err) != SSS_OK) { fprintf(stderr, "decode_bench: %s\n", err.msg); return 1; }
    int maxt = omp_get_max_threads();
    double r1, c1, rN, cN;
    bandwidth(1, &r1, &c1);
    bandwidth(maxt, &rN, &cN);
    size_t nv = f.mesh.nv, C = f.channels;
    float *out = malloc(nv * C * sizeof(float));
    double ms1 = decode_ms(&f, out, 1, frames), msN = decode_ms(&f, out, maxt, frames);
    /* per vertex: three rows of C values read, C floats written */
    /* bytes a frame must read per vertex: three direction rows (float,
     * lloyd8); for the compressed forms, every stored byte that a vertex's
     * evaluation touches is about its share of the scattering data (the
     * reference rows are read for three directions only: 3/n of them) */
    double bytes_read = 3.0 * C * (f.quant == SSS_QUANT_LLOYD8 ? 1 : 4), bytes_written = 4.0 * C;
    if (f.quant == SSS_QUANT_SH || f.quant == SSS_QUANT_REFS) {
        sss_storage st;
        sss_file_storage(&f, &st);
        bytes_read = (double)(st.scattering - st.ref_values) / nv + 3.0 * (double)st.ref_values / f.dirs.n / nv;
    }
    double moved = (bytes_read + bytes_written) * nv;
    /* the bound uses the sum3 bandwidth: the same three-reads-one-write pattern as the decode */
    double bound1 = 1e3 * moved / r1, boundN = 1e3 * moved / rN;
    printf("{\"file\":\"%s\",\"vertices\":%zu,\"channels\":%zu,\"quant\":\"%s\",\"frames\":%d,\"threads_max\":%d,"
           "\"sum3_GBps_1t\":%.2f,\"copy_GBps_1t\":%.2f,\"sum3_GBps_all\":%.2f,\"copy_GBps_all\":%.2f,"
           "\"bytes_read_per_vertex\":%.0f,\"bytes_written_per_vertex\":%.0f,"
           "\"decode_ms_1t\":%.4f,\"decode_ms_all\":%.4f,\"bound_ms_1t\":%.4f,\"bound_ms_all\":%.4f,"
           "\"ratio_to_bound_1t\":%.3f,\"ratio_to_bound_all\":%.3f,\"vertices_per_s_1t\":%.4g,\"vertices_per_s_all\":%.4g}\n",
           argv[1], nv, C, sss_quant_name(f.quant), frames, maxt, r1 / 1e9, c1 / 1e9,
           rN / 1e9, cN / 1e9, bytes_read, bytes_written, ms1, msN, bound1, boundN, ms1 / bound1, msN / boundN,
           nv / (1e-3 * ms1), nv / (1e-3 * msN));
    free(out);
    sss_file_free(&f);
    return 0;
}
