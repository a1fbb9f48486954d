/* fuzz_sss.c: libFuzzer harness for the .sss reader (docs/robustness.md). The input is
 * a whole file image. sss_file_decode must refuse it with a message or
 * accept it; an accepted file must then decode to finite, non-negative q at
 * a few light directions through sss_decode_all and sss_decode_vertex (and
 * sss_decode_vector_range for a file with Q), and
 * re-encode; the runtime API (sss/api.h) must open the same bytes and
 * decode a range of vertices as the slice of sss_decode_all. Files with
 * run-time near terms are left out of that step: opening builds their
 * weight rows (sss_near_build_file), which on a mutated scale can take
 * seconds for a few dozen vertices, past the per-input time limit; the
 * reader's checks they share are fuzzed above, and test_api covers the
 * rest. Any crash, sanitizer report or non-finite value is a bug.
 *
 * Every input is tried twice: as given, and with its checksums repaired
 * (each section's CRC and the header CRC recomputed where the table's
 * offsets and sizes lie inside the input). Without the second pass almost
 * every mutation dies at the CRC check and the section parsers behind it
 * are never reached. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sss/api.h"
#include "sss/decode.h"
#include "sss/format.h"
#include "test_util.h"
#include "fuzz_sss_crc.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int check_one(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    check_one(data, size);
    uint8_t *copy = malloc(size + 1);
    if (!copy) return 0;
    if (size) memcpy(copy, data, size);
    fuzz_repair_crcs(copy, size);
    check_one(copy, size);
    free(copy);
    return 0;
}

static int check_one(const uint8_t *data, size_t size)
{
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_decode(data, size, "fuzz.sss", &f, &err) != SSS_OK) {
        if (!err.msg[0]) abort(); /* a refusal always says why */
        return 0;
    }
    /* bounded work per input: the decoder never exceeds the file size, but
     * a 1 MB file can declare 2.6e5 vertices; evaluate at most 3 lights */
    const size_t n = (size_t)f.mesh.nv * f.channels;
    float *out = malloc(n * sizeof *out + 1);
    if (out) {
        static const double lights[3][3] = {{0, 0, 1}, {0.3, -0.4, 0.866}, {-1, 0, 0}};
        for (int t = 0; t < 3; t++) {
            sss_decode_all(&f, lights[t], out);
            for (size_t i = 0; i < n; i++)
                if (!isfinite(out[i]) || out[i] < 0.0f) abort();
            float one[3];
            uint32_t v = f.mesh.nv / 2;
            sss_decode_vertex(&f, v, lights[t], one);
            for (uint32_t c = 0; c < f.channels; c++)
                if (one[c] != out[(size_t)v * f.channels + c]) abort();
            if (f.qvec) { /* section QVEC: Q dotted with the light, finite and >= 0 too */
                sss_decode_vector_range(&f, lights[t], SSS_INTERP_TRIANGLE, 0, f.mesh.nv, out);
                for (size_t i = 0; i < n; i++)
                    if (!isfinite(out[i]) || out[i] < 0.0f) abort();
            }
        }
        /* the API over the same bytes: a range of the last light's decode */
        sss_asset *a;
        const int dir_set = f.fx.mask == 0 || (f.fx.mask & SSS_FX_DIR_SET);
        const uint32_t first = f.mesh.nv / 3, count = f.mesh.nv - first;
        if (!f.near_terms) { /* (files with near terms: the header comment says why not) */
            if (sss_asset_open_memory(data, size, "fuzz.sss", &a, &err) != SSS_OK) abort(); /* the reader took these bytes */
            if (dir_set && count > 0) {
                if (sss_asset_decode(a, lights[2], first, count, NULL, out, &err) != SSS_OK) abort();
                float *whole = malloc(n * sizeof *whole + 1);
                if (whole) {
                    sss_decode_all(&f, lights[2], whole);
                    if (memcmp(out, whole + (size_t)first * f.channels, (size_t)count * f.channels * sizeof *out))
                        abort();
                    free(whole);
                }
            }
            sss_asset_close(a);
        }
        free(out);
    }
    uint8_t *buf;
    size_t len;
    if (sss_file_encode(&f, &buf, &len, &err) == SSS_OK) free(buf);
    sss_file_free(&f);
    return 0;
}
