/* sss-genmesh: writes a procedural test mesh as binary PLY, or as glTF 2.0
 * when OUT ends in .gltf or .glb (gltf_write.h).
 * Usage: sss-genmesh KIND RES OUT.ply|OUT.gltf|OUT.glb [SIZE [SCENE]]
 *        sss-genmesh subdivide N IN OUT.ply (sss_gen_subdivide)
 *        sss-genmesh field KIND RES OUT.vdb [SIZE [SEED]] (a procedural material field as .vdb)
 *        sss-genmesh depthmap KIND RES OUT.png [BITS] (a layer's depth map, docs/layers.md §3) */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include "genmesh.h"
#include "gltf_write.h"
#include "sss/cli.h"
#include "sss/depthmap.h"
#include "sss/field.h"
#include "sss/fieldio.h"
#include "sss/fileio.h"
#include "sss/import.h"

static const char *TOOL = "sss-genmesh";

static void usage(FILE *f)
{
    fprintf(f, "usage: sss-genmesh sphere|blob|plane|cube|slab|torus|tube|pair RES OUT.ply|OUT.gltf|OUT.glb [SIZE [SCENE]]\n"
               "  RES: subdivisions (sphere, blob, pair) or segments per side (others); SIZE: radius or edge,\n"
               "  default 1 (pair: a sphere of radius SIZE and one of 250 SIZE, far apart; tube: radius SIZE/2,\n"
               "  length 4 SIZE along z, 2 RES vertices around and 4 RES segments along)\n"
               "  SCENE (glTF only): one (default), two (two instances under transformed nodes),\n"
               "  one+attributes or two+attributes (with TEXCOORD_0 and COLOR_0), or skin (a two-bone rig along z\n"
               "  with JOINTS_0, WEIGHTS_0 and a clip 'bend': sss-genmesh tube 8 tube.gltf 0.25 skin)\n"
               "       sss-genmesh subdivide N IN OUT.ply|OUT.gltf|OUT.glb\n"
               "  every triangle of the mesh IN (any format sss-bake reads) cut into N x N, each edge into N\n"
               "  equal segments: the midpoint subdivision for N = 2, the shape unchanged\n"
               "       sss-genmesh field veins|inclusions|sphere|box|layers RES OUT.vdb [SIZE [SEED]]\n"
               "  a procedural material field (docs/heterogeneous.md sec. 2) sampled on RES nodes per side over\n"
               "  the cube [-SIZE/2, SIZE/2]^3 mm (SIZE default 20), written as the float grid 'density'\n"
               "       sss-genmesh depthmap constant|ramp|veins RES OUT.png [BITS]\n"
               "  a layer's depth map (docs/layers.md sec. 3), RES x RES samples of BITS (8 or 16, default 16) as a\n"
               "  grey PNG: constant 1, ramp u (0 at the left edge, 1 at the right), or veins (the procedural veins\n"
               "  of scale 1/4 over the unit square of (u, v), seed 1)\n");
}

/* The command line, as the positional rows fill it. */
typedef struct genmesh_args {
    const char *kind, *out;
    int res;
    double size;
    int scene; /* SSS_GLTF_* flags */
} genmesh_args;

/* SSS_CLI_RUN, or 2 after the usage or a message. */
static int parse_args(int argc, char **argv, genmesh_args *a)
{
    a->kind = a->out = NULL;
    a->res = 0;
    a->size = 1.0;
    a->scene = 0;
    static const char *const scenes[] = {"one", "two", "one+attributes", "two+attributes", "skin", NULL};
    static const int scene_flags[] = {0, SSS_GLTF_TWO_NODES, SSS_GLTF_ATTRIBUTES, SSS_GLTF_TWO_NODES | SSS_GLTF_ATTRIBUTES,
                                      SSS_GLTF_SKIN};
    int npos = 0;
    /* Only positionals, read as strtol and strtod read them (SSS_CLI_LAX):
     * an empty RES is 0 and a SIZE may be infinite, as they always were. */
    const sss_cli_opt pos[] = {
        {.name = "KIND", .kind = SSS_CLI_STRING, .dest = &a->kind},
        {.name = "RES", .kind = SSS_CLI_INT, .dest = &a->res, .lo = 0, .hi = 100000, .flags = SSS_CLI_LAX,
         .msg = "%s: %s '%s' must be an integer in [%d, %d]\n"},
        {.name = "OUT.ply", .kind = SSS_CLI_STRING, .dest = &a->out},
        {.name = "SIZE", .kind = SSS_CLI_DOUBLE, .dest = &a->size, .lo = 0, .hi = INFINITY,
         .flags = SSS_CLI_ABOVE_LO | SSS_CLI_LAX, .msg = "%s: %s '%s' must be a number > 0\n"},
        {.name = "SCENE", .kind = SSS_CLI_CHOICE, .dest = &a->scene, .choices = scenes, .values = scene_flags},
    };
    /* no options: "-h" is a KIND and a wrong count prints the usage on stderr */
    const sss_cli cli = {.tool = TOOL, .pos = pos, .npos = SSS_CLI_COUNT(pos), .min_pos = 3, .usage = usage,
                         .flags = SSS_CLI_NO_OPTIONS, .npos_given = &npos};
    int rc = sss_cli_parse(&cli, argc, argv);
    if (rc == SSS_CLI_RUN && npos == 5 && !sss_gltf_path(a->out)) {
        sss_cli_printf(stderr, "%s: SCENE is for glTF output only (OUT ending in .gltf or .glb)\n", TOOL);
        return 2;
    }
    return rc;
}

/* sss-genmesh subdivide N IN OUT: IN imported and repaired as sss-bake
 * imports it, then subdivided. */
static int subdivide_main(int argc, char **argv)
{
    int n = 0;
    const char *in = NULL, *out = NULL, *kind = NULL;
    const sss_cli_opt pos[] = {
        {.name = "KIND", .kind = SSS_CLI_STRING, .dest = &kind},
        {.name = "N", .kind = SSS_CLI_INT, .dest = &n, .lo = 1, .hi = 1000},
        {.name = "IN", .kind = SSS_CLI_STRING, .dest = &in},
        {.name = "OUT.ply", .kind = SSS_CLI_STRING, .dest = &out},
    };
    const sss_cli cli = {.tool = TOOL, .pos = pos, .npos = SSS_CLI_COUNT(pos), .min_pos = 4, .usage = usage,
                         .flags = SSS_CLI_NO_OPTIONS};
    int rc = sss_cli_parse(&cli, argc, argv);
    if (rc != SSS_CLI_RUN) return rc;
    sss_error err = {{0}};
    const char *inputs[1] = {in};
    const sss_inputs ins = {inputs, 1};
    sss_mesh src, m;
    sss_import_report rep;
    memset(&m, 0, sizeof m);
    if (sss_output_check(out, &ins, NULL, &err) != SSS_OK || sss_import_mesh(in, &src, &rep, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    sss_result r = sss_gen_subdivide(&src, (unsigned)n, &m, &err);
    sss_mesh_free(&src);
    if (r == SSS_OK) r = sss_mesh_check_range(&m, 0.0, out, &err);
    if (r == SSS_OK) r = sss_gltf_path(out) ? sss_gltf_write(out, &m, 0, &err) : sss_export_ply(out, &m, &err);
    if (r != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        sss_mesh_free(&m);
        return 1;
    }
    sss_cli_printf(stderr, "%s: %s: %u vertices, %u triangles (%s cut %d x %d)\n", TOOL, out, m.nv, m.nf, in, n, n);
    sss_mesh_free(&m);
    return 0;
}

/* sss-genmesh field KIND RES OUT.vdb [SIZE [SEED]]: test fields for
 * scenes, without downloads; the parameters scale with SIZE
 * (docs/heterogeneous.md §6). */
static int field_main(int argc, char **argv)
{
    int res = 0, seed = 0;
    double size = 20.0;
    const char *out = NULL, *tool = NULL, *kind = NULL;
    const sss_cli_opt pos[] = {
        {.name = "field", .kind = SSS_CLI_STRING, .dest = &tool},
        {.name = "KIND", .kind = SSS_CLI_STRING, .dest = &kind},
        {.name = "RES", .kind = SSS_CLI_INT, .dest = &res, .lo = 2, .hi = 512},
        {.name = "OUT.vdb", .kind = SSS_CLI_STRING, .dest = &out},
        {.name = "SIZE", .kind = SSS_CLI_DOUBLE, .dest = &size, .lo = 1e-6, .hi = 1e9},
        {.name = "SEED", .kind = SSS_CLI_INT, .dest = &seed, .lo = 0, .hi = 2147483647},
    };
    const sss_cli cli = {.tool = TOOL, .pos = pos, .npos = SSS_CLI_COUNT(pos), .min_pos = 4, .usage = usage,
                         .flags = SSS_CLI_NO_OPTIONS};
    int rc = sss_cli_parse(&cli, argc, argv);
    if (rc != SSS_CLI_RUN) return rc;
    sss_field f = {.seed = (uint32_t)seed};
    if (!strcmp(kind, "veins")) f.kind = SSS_FIELD_VEINS, f.scale_mm = size / 3;
    else if (!strcmp(kind, "inclusions")) f.kind = SSS_FIELD_INCLUSIONS, f.scale_mm = size / 4, f.thickness_mm = size / 16;
    else if (!strcmp(kind, "sphere")) f.kind = SSS_FIELD_SPHERE, f.half_mm[0] = size / 4, f.edge_mm = size / 40;
    else if (!strcmp(kind, "box"))
        f.kind = SSS_FIELD_BOX, f.half_mm[0] = f.half_mm[1] = f.half_mm[2] = size / 5, f.edge_mm = size / 40;
    else if (!strcmp(kind, "layers"))
        f.kind = SSS_FIELD_LAYERS, f.normal[2] = 1.0, f.thickness_mm = size / 10, f.scale_mm = size / 4,
        f.edge_mm = size / 40;
    else {
        sss_cli_printf(stderr, "%s: field kind '%s' is not veins, inclusions, sphere, box or layers\n", TOOL, kind);
        return 2;
    }
    const double lo[3] = {-size / 2, -size / 2, -size / 2}, hi[3] = {size / 2, size / 2, size / 2};
    sss_field g;
    sss_error err = {{0}};
    if (sss_field_sample(&f, lo, hi, (uint32_t)res, &g, &err) != SSS_OK ||
        sss_field_write_vdb(out, "density", &g, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        sss_field_free(&g);
        return 1;
    }
    sss_cli_printf(stderr, "%s: %s: grid 'density', %u x %u x %u nodes, voxel %g mm (%s)\n", TOOL, out, g.n[0], g.n[1],
                   g.n[2], g.voxel_mm, kind);
    sss_field_free(&g);
    return 0;
}

/* sss-genmesh depthmap KIND RES OUT.png [BITS]: the tests' and the
 * examples' depth maps, made here rather than downloaded. */
static int depthmap_main(int argc, char **argv)
{
    int res = 0, bits = 16;
    const char *out = NULL, *tool = NULL, *kind = NULL;
    const sss_cli_opt pos[] = {
        {.name = "depthmap", .kind = SSS_CLI_STRING, .dest = &tool},
        {.name = "KIND", .kind = SSS_CLI_STRING, .dest = &kind},
        {.name = "RES", .kind = SSS_CLI_INT, .dest = &res, .lo = 1, .hi = 8192},
        {.name = "OUT.png", .kind = SSS_CLI_STRING, .dest = &out},
        {.name = "BITS", .kind = SSS_CLI_INT, .dest = &bits, .lo = 8, .hi = 16},
    };
    const sss_cli cli = {.tool = TOOL, .pos = pos, .npos = SSS_CLI_COUNT(pos), .min_pos = 4, .usage = usage,
                         .flags = SSS_CLI_NO_OPTIONS};
    int rc = sss_cli_parse(&cli, argc, argv);
    if (rc != SSS_CLI_RUN) return rc;
    if (bits != 8 && bits != 16) {
        sss_cli_printf(stderr, "%s: BITS %d is not 8 or 16\n", TOOL, bits);
        return 2;
    }
    int k = !strcmp(kind, "constant") ? 0 : !strcmp(kind, "ramp") ? 1 : !strcmp(kind, "veins") ? 2 : -1;
    if (k < 0) {
        sss_cli_printf(stderr, "%s: depth map kind '%s' is not constant, ramp or veins\n", TOOL, kind);
        return 2;
    }
    sss_depth_image im = {(uint32_t)res, (uint32_t)res, malloc((size_t)res * (size_t)res * sizeof(float))};
    if (!im.value) {
        sss_cli_printf(stderr, "%s: out of memory\n", TOOL);
        return 1;
    }
    const sss_depth_spec veins = {.kind = SSS_DEPTH_PROCEDURAL, .pattern = SSS_DEPTH_VEINS, .seed = 1, .scale_mm = 0.25,
                                  .range_mm = {0.0, 1.0}};
    for (int j = 0; j < res; j++)
        for (int i = 0; i < res; i++) {
            /* the texel's centre in (u, v), v upward from the bottom row */
            const double x[3] = {(i + 0.5) / res, 1.0 - (j + 0.5) / res, 0.0};
            im.value[(size_t)j * res + i] = (float)(k == 0 ? 1.0 : k == 1 ? x[0] : sss_depth_procedural(&veins, x));
        }
    sss_error err = {{0}};
    const sss_result r = sss_depth_map_write(out, &im, bits, &err);
    free(im.value);
    if (r != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    sss_cli_printf(stderr, "%s: %s: %d x %d %d-bit grey depth map (%s)\n", TOOL, out, res, res, bits, kind);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "depthmap")) return depthmap_main(argc, argv);
    if (argc > 1 && !strcmp(argv[1], "subdivide")) return subdivide_main(argc, argv);
    if (argc > 1 && !strcmp(argv[1], "field")) return field_main(argc, argv);
    genmesh_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc != SSS_CLI_RUN) return rc;
    sss_mesh m;
    memset(&m, 0, sizeof m); /* freed on every path, also when no mesh was made */
    sss_error err = {{0}};
    /* a SIZE read as infinite (or so large its coordinates overflow float)
     * makes no mesh the bake can take: refused by the range every stage
     * computes in (sss/mesh.h), not written */
    if (sss_gen_by_name(a.kind, (unsigned)a.res, a.size, &m, &err) != SSS_OK ||
        sss_mesh_check_range(&m, 0.0, a.out, &err) != SSS_OK ||
        (sss_gltf_path(a.out) ? sss_gltf_write(a.out, &m, (unsigned)a.scene, &err) : sss_export_ply(a.out, &m, &err)) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        sss_mesh_free(&m);
        return 1;
    }
    sss_cli_printf(stderr, "%s: %s: %u vertices, %u triangles\n", TOOL, a.out, m.nv, m.nf);
    sss_mesh_free(&m);
    return 0;
}
