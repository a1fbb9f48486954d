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
               "Prints vertex count, channels, directions, storage, material, and the bytes of every\n"
               "section in total and per vertex. --json prints one JSON object on stdout.\n");
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
    const char *quant = f.quant == SSS_QUANT_LLOYD8 ? "lloyd8" : "float";
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
    }
    sss_file_free(&f);
    return 0;
}
