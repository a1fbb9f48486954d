/* decode_print.c: the runtime API (sss/api.h) in one small program. Opens a
 * .sss file, prints what it holds, decodes q for a directional light given
 * on the command line and prints a few vertices and the minimum, mean and
 * maximum of each channel.
 *
 *   decode_print FILE X,Y,Z [VERTEX]
 *
 * X,Y,Z points towards the light in the mesh's coordinates (any length);
 * VERTEX adds that vertex's values. Values print with 9 significant digits,
 * which give a float back exactly. Exit status 0, or 1 with a one-line
 * message on stderr. */
#include <stdio.h>
#include <stdlib.h>

#include <sss/api.h>

static int fail(const char *what, const sss_error *err)
{
    fprintf(stderr, "decode_print: %s%s\n", what, err ? err->msg : "");
    return 1;
}

static void print_vertex(const float *q, uint32_t v, uint32_t channels)
{
    printf("q[%u] =", v);
    for (uint32_t c = 0; c < channels; c++) printf(" %.9g", q[(size_t)v * channels + c]);
    printf("\n");
}

int main(int argc, char **argv)
{
    if (argc != 3 && argc != 4) return fail("usage: decode_print FILE X,Y,Z [VERTEX]", NULL);
    double light[3];
    char end;
    if (sscanf(argv[2], "%lf,%lf,%lf%c", &light[0], &light[1], &light[2], &end) != 3)
        return fail("the light must be three numbers X,Y,Z", NULL);
    sss_error err = {{0}};
    sss_asset *a;
    if (sss_asset_open(argv[1], &a, &err) != SSS_OK) return fail("", &err);
    sss_asset_desc d;
    if (sss_asset_info(a, &d, &err) != SSS_OK) {
        sss_asset_close(a);
        return fail("", &err);
    }
    long vq = -1;
    if (argc == 4) {
        char *e;
        vq = strtol(argv[3], &e, 10);
        if (*e || vq < 0 || vq >= (long)d.nv) {
            sss_asset_close(a);
            return fail("VERTEX must be a vertex index of the file", NULL);
        }
    }

    printf("file %s: format %u.%u, %llu bytes\n", sss_asset_name(a), d.version_major, d.version_minor,
           (unsigned long long)d.file_bytes);
    printf("mesh: %u vertices, %u triangles, %g mm per unit\n", d.nv, d.nf, d.mm_per_unit);
    printf("material %s: eta %g; sigma_a", d.material_name, d.eta);
    for (uint32_t c = 0; c < d.channels; c++) printf(" %g", d.sigma_a[c]);
    printf(", sigma'_s");
    for (uint32_t c = 0; c < d.channels; c++) printf(" %g", d.sigmap_s[c]);
    printf(" (1/mm)\n");
    printf("storage: %s", d.quant_name);
    if (d.sh_order) printf(" (SH order %u, %s codes)", d.sh_order, d.sh_kind_name);
    printf(", %u directions, %u channels, %.1f bytes per vertex\n", d.ndirs, d.channels,
           d.integral_bytes_per_vertex);
    if (d.near_terms) {
        if (d.near_radius_mm > 0) printf("near terms: at run time, every vertex within %g mm\n", d.near_radius_mm);
        else printf("near terms: at run time, %u ring(s)\n", d.near_rings);
    }
    if (d.effects) printf("scene effects: mask 0x%x (%u static lights, %u shells, environment order %u)\n",
                          d.effects, d.nexact, d.nshells, d.env_order);
    if (!d.has_dir_set) {
        printf("no direction set: nothing to decode for a moving light\n");
        sss_asset_close(a);
        return 0;
    }

    /* the whole mesh in one call; an engine may split it into ranges, on
     * as many threads as it likes (sss/api.h: "Threads") */
    float *q = malloc((size_t)d.nv * d.channels * sizeof *q);
    if (!q) {
        sss_asset_close(a);
        return fail("out of memory", NULL);
    }
    if (sss_asset_decode(a, light, 0, d.nv, NULL, q, &err) != SSS_OK) {
        free(q);
        sss_asset_close(a);
        return fail("", &err);
    }
    printf("light (%g, %g, %g):\n", light[0], light[1], light[2]);
    for (uint32_t v = 0; v < d.nv && v < 3; v++) print_vertex(q, v, d.channels);
    if (vq >= 0) print_vertex(q, (uint32_t)vq, d.channels);
    for (uint32_t c = 0; c < d.channels; c++) {
        double lo = q[c], hi = q[c], sum = 0;
        for (uint32_t v = 0; v < d.nv; v++) {
            const double x = q[(size_t)v * d.channels + c];
            lo = x < lo ? x : lo;
            hi = x > hi ? x : hi;
            sum += x;
        }
        printf("channel %u: min %.9g mean %.9g max %.9g\n", c, lo, sum / d.nv, hi);
    }
    free(q);
    sss_asset_close(a);
    return 0;
}
