/* sss-stat: what a .sss file holds and where its bytes go. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_util.h"
#include "sss/format.h"

static const char *TOOL = "sss-stat";

static void usage(FILE *f)
{
    fprintf(f, "usage: sss-stat FILE.sss [--json]\n"
               "Prints vertex count, channels, directions, storage, material, the bytes of every\n"
               "section, and every part of the scattering data (directions, reference indices,\n"
               "triangles, weights, tables, codes) in total and per vertex, with the compression\n"
               "ratio against 8-bit and float storage. --json prints one JSON object on stdout.\n");
}

int main(int argc, char **argv)
{
    const char *path = NULL;
    int json = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--json")) json = 1;
        else if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) { usage(stdout); return 0; }
        else if (argv[i][0] == '-' && argv[i][1]) { fprintf(stderr, "%s: unknown option '%s' (see --help)\n", TOOL, argv[i]); return 2; }
        else if (!path) path = argv[i];
        else { fprintf(stderr, "%s: unexpected argument '%s'\n", TOOL, argv[i]); return 2; }
    }
    if (!path) { fprintf(stderr, "%s: missing FILE.sss (see --help)\n", TOOL); return 2; }
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_read(path, &f, &err) != SSS_OK) {
        fprintf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    const double nv = f.mesh.nv;
    const char *quant = sss_quant_name(f.quant);
    /* every byte of the scattering data, by part (docs/format.md §5) */
    sss_storage st;
    sss_file_storage(&f, &st);
    const struct { const char *name; uint64_t bytes; } part[] = {
        {"directions", st.dirs},           {"values", st.values},         {"lloyd_tables", st.lloyd_tables},
        {"section_headers", st.section_headers}, {"ref_vertex_indices", st.ref_vertex},
        {"ref_triangles", st.ref_tri},     {"vertex_triangle_indices", st.vertex_tri},
        {"weights", st.weights},           {"ref_values", st.ref_values}, {"sh_tables", st.sh_tables},
        {"sh_codes", st.sh_codes},
    };
    const size_t nparts = sizeof part / sizeof part[0];
    const double raw8 = (double)f.dirs.n * f.channels, rawf = 4.0 * raw8; /* bytes/vertex, uncompressed */
    const double sbpv = (double)st.total / nv; /* scattering data incl. directions, per vertex */
    if (json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "file", path);
        char ver[32];
        snprintf(ver, sizeof ver, "%u.%u", f.version_major, f.version_minor);
        cJSON_AddStringToObject(o, "format_version", ver);
        cJSON_AddNumberToObject(o, "vertices", f.mesh.nv);
        cJSON_AddNumberToObject(o, "triangles", f.mesh.nf);
        cJSON_AddNumberToObject(o, "channels", f.channels);
        cJSON_AddNumberToObject(o, "directions", f.dirs.n);
        cJSON_AddStringToObject(o, "quant", quant);
        cJSON_AddStringToObject(o, "material", f.material.name);
        cJSON_AddNumberToObject(o, "mm_per_unit", f.mm_per_unit);
        cJSON_AddNumberToObject(o, "file_bytes", (double)f.file_size);
        cJSON_AddNumberToObject(o, "bytes_per_vertex", (double)f.file_size / nv);
        cJSON *secs = cJSON_AddArrayToObject(o, "sections");
        for (uint32_t s = 0; s < f.nsections; s++) {
            cJSON *e = cJSON_CreateObject();
            cJSON_AddStringToObject(e, "tag", f.sections[s].tag);
            cJSON_AddNumberToObject(e, "bytes", (double)f.sections[s].size);
            cJSON_AddNumberToObject(e, "bytes_per_vertex", (double)f.sections[s].size / nv);
            cJSON_AddNumberToObject(e, "count", (double)f.sections[s].count);
            cJSON_AddItemToArray(secs, e);
        }
        cJSON *sto = cJSON_AddObjectToObject(o, "storage");
        for (size_t k = 0; k < nparts; k++) {
            if (!part[k].bytes) continue;
            cJSON *e = cJSON_AddObjectToObject(sto, part[k].name);
            cJSON_AddNumberToObject(e, "bytes", (double)part[k].bytes);
            cJSON_AddNumberToObject(e, "bytes_per_vertex", (double)part[k].bytes / nv);
        }
        cJSON_AddNumberToObject(o, "scattering_bytes", (double)st.total);
        cJSON_AddNumberToObject(o, "scattering_bytes_per_vertex", sbpv);
        cJSON_AddNumberToObject(o, "ratio_vs_8bit", raw8 / sbpv);
        cJSON_AddNumberToObject(o, "ratio_vs_float", rawf / sbpv);
        if (f.quant == SSS_QUANT_SH || f.quant == SSS_QUANT_REFS) {
            cJSON *c = cJSON_AddObjectToObject(o, "compression");
            cJSON_AddNumberToObject(c, "sh_order", f.sh.order);
            cJSON_AddNumberToObject(c, "sh_coefficients", f.sh.ncoef);
            cJSON_AddStringToObject(c, "sh_quant", sss_shq_name(f.sh.kind));
            cJSON_AddNumberToObject(c, "coded_vertices", f.sh.ncoded);
            if (f.quant == SSS_QUANT_REFS) {
                cJSON_AddNumberToObject(c, "refs", f.ref.nref);
                cJSON_AddNumberToObject(c, "refs_fraction", f.ref.nref / nv);
                cJSON_AddNumberToObject(c, "ref_triangles", f.ref.nrt);
                cJSON_AddNumberToObject(c, "weight_bits", f.ref.wbits);
                cJSON_AddItemToObject(c, "weight_range", cJSON_CreateDoubleArray((double[]){f.ref.w_lo, f.ref.w_hi}, 2));
            }
        }
        cJSON *p = f.params_json ? cJSON_Parse(f.params_json) : NULL;
        if (p) cJSON_AddItemToObject(o, "params", p);
        char *s = cJSON_PrintUnformatted(o);
        puts(s);
        free(s);
        cJSON_Delete(o);
    } else {
        printf("%s: format %u.%u, %llu bytes\n", path, f.version_major, f.version_minor, (unsigned long long)f.file_size);
        printf("  vertices %u, triangles %u, channels %u, directions %u, storage %s\n", f.mesh.nv, f.mesh.nf,
               f.channels, f.dirs.n, quant);
        printf("  material %s (eta %g), %g mm per unit\n", f.material.name, f.material.eta, f.mm_per_unit);
        printf("  %-6s %14s %12s %14s\n", "section", "bytes", "bytes/vertex", "count");
        for (uint32_t s = 0; s < f.nsections; s++)
            printf("  %-6s %14llu %12.2f %14llu\n", f.sections[s].tag, (unsigned long long)f.sections[s].size,
                   (double)f.sections[s].size / nv, (unsigned long long)f.sections[s].count);
        printf("  total  %14llu %12.2f\n", (unsigned long long)f.file_size, (double)f.file_size / nv);
        if (f.quant == SSS_QUANT_REFS)
            printf("  compression: %u references (%.2f%%), %u triangles, %u-bit weights in [%g, %g], SH order %u (%s)\n",
                   f.ref.nref, 100.0 * f.ref.nref / nv, f.ref.nrt, f.ref.wbits, (double)f.ref.w_lo,
                   (double)f.ref.w_hi, f.sh.order, sss_shq_name(f.sh.kind));
        if (f.quant == SSS_QUANT_SH)
            printf("  compression: SH order %u (%s) at every vertex\n", f.sh.order, sss_shq_name(f.sh.kind));
        printf("  scattering data by part:\n  %-24s %14s %12s\n", "part", "bytes", "bytes/vertex");
        for (size_t k = 0; k < nparts; k++)
            if (part[k].bytes)
                printf("  %-24s %14llu %12.3f\n", part[k].name, (unsigned long long)part[k].bytes,
                       (double)part[k].bytes / nv);
        printf("  %-24s %14llu %12.3f  (%.1fx smaller than 8-bit, %.1fx than float)\n", "all", (unsigned long long)st.total,
               sbpv, raw8 / sbpv, rawf / sbpv);
    }
    sss_file_free(&f);
    return 0;
}
