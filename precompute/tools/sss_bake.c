/* sss-bake: bakes a mesh and a translucent material into a .sss file
 * (Hao–Varshney 2004 §3). See `sss-bake --help` and README.md ("Baking").
 *
 * main: parse() reads the command line into bake_args and checks its
 * combinations, options() turns it into the bake's options, compression
 * and material, run() imports, bakes, writes and reports. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <stdint.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/clock.h"
#include "sss/nearterms.h"
#include "bake_mpi.h"
#include "sss/cli.h"
#include "sss/bake.h"
#include "sss/compress.h"
#include "sss/fileio.h"
#include "sss/jsontext.h"
#include "sss/import.h"
#include "scene_cli.h"

static const char *TOOL = "sss-bake";

/* The most --point-light one command line takes, as sss-view's: the
 * shells serve every point light at once (§3.3: the light's distance and
 * direction are the shells' coordinates, not baked per light), so more
 * bake nothing more; a scene file takes more. */
#define BAKE_POINTS_MAX 16

static void usage(FILE *f)
{
    fprintf(f,
        "usage: sss-bake MESH -o OUT.sss [options]\n"
        "       sss-bake --scene SCENE.json (--plan [--json] | -o DIR)   (docs/scenes.md)\n"
        "Bakes per-vertex subsurface-scattering integrals q(x, w_j) for a set of light\n"
        "directions (Hao & Varshney 2004) into OUT.sss.\n\n"
        "  MESH                 .ply (ascii/binary), .obj, .off, .stl, .gltf or .glb\n"
        "  -o, --out FILE       output .sss file (written atomically)\n"
        "  --material NAME      Jensen 2001 preset: apple chicken1 chicken2 cream ketchup\n"
        "                       marble potato skimmilk skin1 skin2 wholemilk (default marble)\n"
        "  --sigma-a R,G,B      custom absorption, 1/mm (with --sigma-s, --eta)\n"
        "  --sigma-s R,G,B      custom *reduced* scattering sigma'_s = sigma_s (1-g), 1/mm;\n"
        "                       with --g, the scattering sigma_s itself\n"
        "  --g G                Henyey-Greenstein mean cosine in [-0.99, 0.99] (default 0;\n"
        "                       single scattering: docs/layers.md)\n"
        "  --eta E              relative index of refraction (default 1.3)\n"
        "  --mm-per-unit S      millimetres per mesh unit (default 1)\n"
        "  --dirs N             number of light directions (default 200)\n"
        "  --preset paper       Hao & Varshney 2004 exactly: 200 directions, point weights, every\n"
        "                       term baked, --compress paper (refuses options that would change it)\n"
        "  --preset paper-sh    the same with the paper's SH-only storage (sec. 4.1), --compress paper-sh\n"
        "  --eps E              neighbourhood energy cutoff: radius holds 1-E of R_d total (default 1e-3)\n"
        "  --quant float|lloyd8 store the integrals uncompressed, as floats or 8-bit codes\n"
        "                       (default: compressed, --compress compact)\n"
        "  --weights hat|point  R_d integrated over the vertices' hat functions, whatever the\n"
        "                       tessellation (default; docs/physics.md 9), or sampled at the\n"
        "                       vertices (the paper)\n"
        "  --own-term M         runtime (default): the near terms are split off and readers add\n"
        "                       them back with a shadow test per vertex (docs/accuracy.md): every\n"
        "                       vertex within the radius that holds --near-fraction of the\n"
        "                       material's R_d total; baked: they stay in q (the paper)\n"
        "  --near-fraction F    with --own-term runtime: that fraction, in [0.5, 0.999] (default 0.95;\n"
        "                       0.97 for a one-channel material)\n"
        "  --near-radius MM     with --own-term runtime: the near terms within MM millimetres instead\n"
        "  --rings K            with --own-term runtime: K mesh rings instead, 0..8 (expert: a fine\n"
        "                       mesh's rings cover less of the scattering than a coarse one's)\n"
        "  --vector             also the vector integrals Q (Hao & Varshney 2004 sec. 3.1; section QVEC):\n"
        "                       readers interpolate Q and dot it with the light (needs --quant)\n"
        "Compression (Hao & Varshney 2004 sec. 4; docs/compression.md), the default storage:\n"
        "  --compress P         preset: compact (default: 1 %% references for RGB, 3 %% grey, SH\n"
        "                       order 3 in 4-bit codes, 8-bit least-squares weights; docs/compression.md)\n"
        "                       or paper (3 %% references, SH order 3, linear 8-bit codes, 16-bit\n"
        "                       barycentric weights) or paper-sh (sec. 4.1: SH order 7 in linear\n"
        "                       16-bit codes, no references, 98 code bytes per vertex and channel);\n"
        "                       the options below override it\n"
        "  --sh-order N         SH order 0..8 (N^2 coefficients per vertex and channel)\n"
        "  --refs FRACTION      reference vertices as a fraction of all (0: SH only)\n"
        "  --sh-quant K         SH codes: linear8 (paper) | lloyd8 | lloyd4 | linear16 (paper sec. 4.1)\n"
        "  --weight-bits B      8 or 16 bits per stored weight\n"
        "  --ls-weights         least-squares weights instead of barycentrics\n"
        "  --illum-refs W       illumination-aware references, feature weight W > 0\n"
        "  --gather direct|tree how the integrals are summed: every neighbour, or far sources\n"
        "                       through an octree of flux moments and the near ones as dense\n"
        "                       matrix-product blocks (default tree; docs/benchmarks.md)\n"
        "  --theta T            tree opening threshold in (0, 1): smaller is more accurate (default 0.4)\n"
        "  --scene S.json       bake the effects a scene calls for: one DIR/NAME.sss per object, at\n"
        "                       these defaults (hat weights in every pass; the direction set's near\n"
        "                       terms at run time and its rows compact, unless static occluders\n"
        "                       shadow the object); the scene's \"bake\" object sets weights,\n"
        "                       compress and near_terms (docs/scenes.md)\n"
        "  --plan               with --scene: print the effect set and the reason for each decision\n"
        "                       (weights, compression and near terms included)\n"
        "  --point-light X,Y,Z[,I]   also bake distance shells (Hao & Varshney 2004 sec. 3.3) for point\n"
        "                       lights near the object, e.g. at X,Y,Z (mesh units), up to 16: the file\n"
        "                       serves sss-view --point-light anywhere as well as --light; baked and\n"
        "                       stored as a scene's object (docs/scenes.md), so not with --quant,\n"
        "                       --compress, --weights and the like\n"
        "  --threads T          worker threads (default: all cores); output does not depend on it\n"
        "  --json               print one JSON object with statistics on stdout\n"
        "  -q, --quiet          no progress bar or summary on stderr\n"
        "  -h, --help           this text\n");
}

/* The command line, as the option table fills it. A value left 0 (dirs,
 * eps, mm_per_unit, theta, threads, gather) is the bake's own default. */
typedef struct bake_args {
    const char *mesh, *out, *scene;
    const char *material; /* --material; NULL: marble unless --sigma-a/-s */
    double sigma_a[3], sigma_s[3], eta, g;
    int have_sigma_a, have_sigma_s, have_eta, have_g;
    double mm_per_unit, eps, theta;
    uint32_t dirs;
    int dirs_given;
    /* --preset paper | paper-sh: Hao–Varshney 2004's configuration (its
     * §4.2–4.3 references, or its §4.1 SH alone), every other option that
     * would change it refused (docs/accuracy.md, "The defaults";
     * docs/compression.md, "The paper's SH-only storage") */
    int bake_preset, bake_preset_given;
    int threads;
    int quant, have_quant; /* sss_quant */
    int gather;
    /* --own-term, --rings: runtime brings one ring unless --rings is given,
     * before or after it; baked leaves the rings as they were */
    uint32_t near_terms, near_rings;
    int near_terms_given, rings_given;
    double near_radius; /* --near-radius MM (> 0) */
    int near_radius_given;
    double near_fraction; /* --near-fraction F; without --rings and --near-radius the radius is the material's */
    int near_fraction_given;
    int weights, weights_given; /* --weights: SSS_WEIGHTS_HAT or SSS_WEIGHTS_POINT */
    /* compression: the sss_compress_opts fields, each with its given flag so
     * that the preset fills only the rest (docs/compression.md) */
    int preset, preset_given; /* sss_compress_preset */
    uint32_t sh_order, weight_bits;
    double refs, illum_weight;
    int sh_quant, ls_weights; /* sss_shq */
    int order_given, refs_given, sh_quant_given, wbits_given, ls_given, illum_given;
    int compress; /* any compression option: the compressed form, not --quant */
    int plan, json, quiet;
    int vector; /* --vector: section QVEC */
    double points[BAKE_POINTS_MAX][4]; /* --point-light X,Y,Z[,I] */
    int npoints;
} bake_args;

/* --weight-bits: an integer in [8, 16] (that message first), then 8 or 16
 * (the row's message), as the tool has always read it. */
static int read_weight_bits(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    uint32_t b;
    const sss_cli_opt num = {.kind = SSS_CLI_U32, .dest = &b, .lo = o->lo, .hi = o->hi};
    if (!sss_cli_value(cli, &num, opt, text)) return SSS_CLI_PRINTED;
    if (b != 8 && b != 16) return 0;
    *(uint32_t *)o->dest = b;
    return 1;
}

/* --rings K: an integer in [lo, hi]; anything else gets the row's one
 * line, "must be an integer lo ... hi" (a number out of range printed the
 * number's message before it: two lines). */
static int read_rings(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    (void)cli;
    (void)opt;
    char *end;
    errno = 0;
    const double k = strtod(text, &end);
    if (end == text || *end || errno || !(k >= o->lo && k <= o->hi) || k != floor(k)) return 0;
    *(uint32_t *)o->dest = (uint32_t)k;
    return 1;
}

/* --own-term runtime|baked into bake_args (the row's dest): runtime sets one
 * ring unless --rings came first; baked keeps whatever rings were set, so
 * `--own-term runtime --own-term baked` bakes with near_rings 1, as ever. */
static int read_near_terms(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    static const char *const modes[] = {"runtime", "baked", NULL};
    static const int mode_values[] = {SSS_NEAR_TERMS_RUNTIME, 0};
    bake_args *a = o->dest;
    int mode;
    const sss_cli_opt choice = {.kind = SSS_CLI_CHOICE, .dest = &mode, .choices = modes, .values = mode_values};
    if (!sss_cli_value(cli, &choice, opt, text)) return SSS_CLI_PRINTED;
    a->near_terms = (uint32_t)mode;
    if (mode == SSS_NEAR_TERMS_RUNTIME && !a->rings_given) a->near_rings = 1;
    return 1;
}

/* Prints the one-line message of a combination of options that does not go
 * together; returns the exit status 2. */
static int refuse(const char *msg)
{
    sss_cli_printf(stderr, "%s: %s\n", TOOL, msg);
    return 2;
}

/* Reads the command line into *a and checks its combinations. Returns
 * SSS_CLI_RUN, or the exit status after --help (0) or a message (2). */
static int parse(int argc, char **argv, bake_args *a)
{
    static const char *const quants[] = {"float", "lloyd8", NULL};
    static const int quant_values[] = {SSS_QUANT_FLOAT, SSS_QUANT_LLOYD8};
    static const char *const presets[] = {"paper", "compact", "paper-sh", NULL};
    static const int preset_values[] = {SSS_COMPRESS_PAPER, SSS_COMPRESS_COMPACT, SSS_COMPRESS_PAPER_SH};
    static const char *const shqs[] = {"linear8", "lloyd8", "lloyd4", "linear16", NULL};
    static const int shq_values[] = {SSS_SHQ_LINEAR8, SSS_SHQ_LLOYD8, SSS_SHQ_LLOYD4, SSS_SHQ_LINEAR16};
    static const char *const gathers[] = {"direct", "tree", NULL};
    static const int gather_values[] = {SSS_GATHER_DIRECT, SSS_GATHER_TREE};
    static const char *const weight_rules[] = {"hat", "point", NULL};
    static const char *const bake_presets[] = {"paper", "paper-sh", NULL};
    static const int bake_preset_values[] = {SSS_COMPRESS_PAPER, SSS_COMPRESS_PAPER_SH};
    static const int weight_values[] = {SSS_WEIGHTS_HAT, SSS_WEIGHTS_POINT};
    memset(a, 0, sizeof *a);
    a->eta = 1.3;
    a->quant = SSS_QUANT_FLOAT;
    a->gather = SSS_GATHER_AUTO;
    /* the defaults give the best answer at the fewest bytes (docs/accuracy.md,
     * "The defaults"): hat weights, the near terms at run time within the
     * material's radius, the compact compression; --preset paper is
     * Hao–Varshney's */
    a->near_terms = SSS_NEAR_TERMS_RUNTIME;
    a->weights = SSS_WEIGHTS_HAT;
    a->preset = SSS_COMPRESS_COMPACT;
    sss_compress_opts co; /* what a compression option left unset starts from */
    sss_compress_opts_default(&co);
    a->sh_order = co.order;
    a->refs = co.fraction;
    a->sh_quant = (int)co.sh_kind;
    a->weight_bits = co.wbits;
    a->ls_weights = co.ls_weights;
    a->illum_weight = co.illum_weight;
    const sss_cli_opt opts[] = {
        {.name = "--out", .alias = "-o", .kind = SSS_CLI_STRING, .dest = &a->out},
        {.name = "--material", .kind = SSS_CLI_STRING, .dest = &a->material},
        {.name = "--sigma-a", .kind = SSS_CLI_TRIPLE, .dest = a->sigma_a, .given = &a->have_sigma_a},
        {.name = "--sigma-s", .kind = SSS_CLI_TRIPLE, .dest = a->sigma_s, .given = &a->have_sigma_s},
        {.name = "--eta", .kind = SSS_CLI_DOUBLE, .dest = &a->eta, .lo = 1e-3, .hi = 1e3, .given = &a->have_eta},
        {.name = "--g", .kind = SSS_CLI_DOUBLE, .dest = &a->g, .lo = -SSS_G_MAX, .hi = SSS_G_MAX, .given = &a->have_g},
        {.name = "--mm-per-unit", .kind = SSS_CLI_DOUBLE, .dest = &a->mm_per_unit, .lo = 1e-12, .hi = 1e12},
        {.name = "--dirs", .kind = SSS_CLI_U32, .dest = &a->dirs, .lo = 1, .hi = 100000, .given = &a->dirs_given},
        {.name = "--preset", .kind = SSS_CLI_CHOICE, .dest = &a->bake_preset, .choices = bake_presets,
         .values = bake_preset_values, .given = &a->bake_preset_given},
        {.name = "--eps", .kind = SSS_CLI_DOUBLE, .dest = &a->eps, .lo = 1e-12, .hi = 0.5},
        {.name = "--quant", .kind = SSS_CLI_CHOICE, .dest = &a->quant, .choices = quants, .values = quant_values,
         .given = &a->have_quant},
        {.name = "--compress", .kind = SSS_CLI_CHOICE, .dest = &a->preset, .choices = presets,
         .values = preset_values, .given = &a->preset_given},
        {.name = "--sh-order", .kind = SSS_CLI_U32, .dest = &a->sh_order, .lo = 0, .hi = 8, .given = &a->order_given},
        {.name = "--refs", .kind = SSS_CLI_DOUBLE, .dest = &a->refs, .lo = 0, .hi = 1, .given = &a->refs_given},
        {.name = "--sh-quant", .kind = SSS_CLI_CHOICE, .dest = &a->sh_quant, .choices = shqs, .values = shq_values,
         .given = &a->sh_quant_given},
        {.name = "--weight-bits", .kind = SSS_CLI_CUSTOM, .dest = &a->weight_bits, .lo = 8, .hi = 16,
         .parse = read_weight_bits, .given = &a->wbits_given, .msg = "%s: %s: '%s' must be 8 or 16\n"},
        {.name = "--ls-weights", .kind = SSS_CLI_FLAG, .dest = &a->ls_weights, .given = &a->ls_given},
        {.name = "--illum-refs", .kind = SSS_CLI_DOUBLE, .dest = &a->illum_weight, .lo = 1e-9, .hi = 1e9,
         .given = &a->illum_given},
        {.name = "--gather", .kind = SSS_CLI_CHOICE, .dest = &a->gather, .choices = gathers, .values = gather_values},
        {.name = "--own-term", .kind = SSS_CLI_CUSTOM, .dest = a, .parse = read_near_terms, .given = &a->near_terms_given},
        {.name = "--rings", .kind = SSS_CLI_CUSTOM, .dest = &a->near_rings, .lo = 0, .hi = SSS_NEAR_RINGS_MAX,
         .parse = read_rings, .given = &a->rings_given, .msg = "%s: %s: '%s' must be an integer %g ... %g\n"},
        {.name = "--near-radius", .kind = SSS_CLI_DOUBLE, .dest = &a->near_radius, .lo = 1e-6, .hi = 1e6,
         .given = &a->near_radius_given},
        {.name = "--near-fraction", .kind = SSS_CLI_DOUBLE, .dest = &a->near_fraction, .lo = 0.5, .hi = 0.999,
         .given = &a->near_fraction_given},
        {.name = "--weights", .kind = SSS_CLI_CHOICE, .dest = &a->weights, .choices = weight_rules,
         .values = weight_values, .given = &a->weights_given},
        {.name = "--theta", .kind = SSS_CLI_DOUBLE, .dest = &a->theta, .lo = 1e-3, .hi = 0.95},
        {.name = "--threads", .kind = SSS_CLI_INT, .dest = &a->threads, .lo = 1, .hi = 1024},
        {.name = "--scene", .kind = SSS_CLI_STRING, .dest = &a->scene},
        {.name = "--plan", .kind = SSS_CLI_FLAG, .dest = &a->plan},
        {.name = "--vector", .kind = SSS_CLI_FLAG, .dest = &a->vector},
        {.name = "--point-light", .kind = SSS_CLI_POINT, .dest = a->points, .flags = SSS_CLI_REPEAT,
         .count = &a->npoints, .max = BAKE_POINTS_MAX},
        {.name = "--json", .kind = SSS_CLI_FLAG, .dest = &a->json},
        {.name = "--quiet", .alias = "-q", .kind = SSS_CLI_FLAG, .dest = &a->quiet},
    };
    /* MESH is optional here: "missing MESH" comes after the checks below */
    const sss_cli_opt pos[] = {{.name = "MESH", .kind = SSS_CLI_STRING, .dest = &a->mesh}};
    const sss_cli cli = {.tool = TOOL, .opts = opts, .nopts = SSS_CLI_COUNT(opts), .pos = pos,
                         .npos = SSS_CLI_COUNT(pos), .usage = usage,
                         .extra_msg = "%s: unexpected argument '%s' (one MESH only)\n"};
    const int rc = sss_cli_parse(&cli, argc, argv);
    if (rc != SSS_CLI_RUN) return rc;
    /* --preset paper, Hao–Varshney 2004: 200 light directions (§3.2), the
     * paper's point weights with every term baked (§3.1), its compression
     * (§4: 3 % references, SH order 3, linear 8-bit codes, 16-bit
     * barycentric weights). Exactly that: an option that would change it
     * is refused, not quietly applied. */
    if (a->bake_preset_given) {
        const struct { int given; const char *name; } fixed[] = {
            {a->dirs_given, "--dirs"}, {a->weights_given, "--weights"}, {a->near_terms_given, "--own-term"},
            {a->rings_given, "--rings"}, {a->near_radius_given, "--near-radius"},
            {a->near_fraction_given, "--near-fraction"}, {a->have_quant, "--quant"}, {a->preset_given, "--compress"},
            {a->order_given, "--sh-order"}, {a->refs_given, "--refs"}, {a->sh_quant_given, "--sh-quant"},
            {a->wbits_given, "--weight-bits"}, {a->ls_given, "--ls-weights"}, {a->illum_given, "--illum-refs"}};
        for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; k++)
            if (fixed[k].given) {
                sss_cli_printf(stderr, "%s: --preset %s is the paper's configuration exactly: not with %s\n", TOOL,
                               bake_presets[a->bake_preset == SSS_COMPRESS_PAPER_SH], fixed[k].name);
                return 2;
            }
        if (a->scene) return refuse("--preset applies to plain bakes, not to --scene");
        if (a->npoints) return refuse("--preset paper bakes no point lights: not with --point-light");
        a->dirs = 200;
        a->weights = SSS_WEIGHTS_POINT;
        a->weights_given = 1;
        a->near_terms = 0;
        a->preset = a->bake_preset; /* the paper's compression, §4.2–4.3 or §4.1 */
        a->preset_given = 1;
    }
    const int compress_given = a->preset_given || a->order_given || a->refs_given || a->sh_quant_given ||
                               a->wbits_given || a->ls_given || a->illum_given;
    /* --quant float|lloyd8 asks for the uncompressed rows; without it the
     * rows are compressed (compact unless a preset is named) */
    a->compress = compress_given || !a->have_quant;

    if (a->plan && !a->scene) return refuse("--plan needs --scene S.json");
    if (a->vector && a->scene) return refuse("--vector applies to plain bakes, not to --scene");
    if (a->vector && a->npoints)
        return refuse("--vector applies to plain bakes, not to --point-light (a scene's object has no Q)");
    /* Q is stored as float next to rows per direction sample (docs/format.md §5.19) */
    if (a->vector && a->compress) return refuse("--vector needs --quant float or lloyd8 (Q is not compressed)");
    if (a->rings_given && a->near_terms != SSS_NEAR_TERMS_RUNTIME) return refuse("--rings needs --own-term runtime");
    if (a->near_radius_given && a->near_terms != SSS_NEAR_TERMS_RUNTIME)
        return refuse("--near-radius needs --own-term runtime");
    if (a->near_radius_given && a->rings_given) return refuse("--near-radius and --rings exclude each other");
    if (a->near_fraction_given && a->near_terms != SSS_NEAR_TERMS_RUNTIME)
        return refuse("--near-fraction needs --own-term runtime");
    if (a->near_fraction_given && (a->rings_given || a->near_radius_given))
        return refuse("--near-fraction sizes the near terms by the material: not with --rings or --near-radius");
    if (a->scene && a->near_terms_given)
        return refuse("--own-term applies to plain bakes, not to --scene (a scene's \"bake\" object sets near_terms)");
    if (a->scene && a->npoints) return refuse("--point-light and --scene exclude each other (the scene names its lights)");
    if (a->scene || a->npoints) {
        if (a->scene && a->mesh) return refuse("--scene and a MESH argument exclude each other (the scene names the meshes)");
        /* what the rows hold and how they are stored: the planner's per
         * object (docs/scenes.md, "Rows, weights and near terms"), set in
         * the scene, not quietly dropped here */
        const struct { int given; const char *name; } storage[] = {
            {a->weights_given, "--weights"}, {a->rings_given, "--rings"}, {a->near_radius_given, "--near-radius"},
            {a->near_fraction_given, "--near-fraction"}, {a->have_quant, "--quant"}, {a->preset_given, "--compress"},
            {a->order_given, "--sh-order"}, {a->refs_given, "--refs"}, {a->sh_quant_given, "--sh-quant"},
            {a->wbits_given, "--weight-bits"}, {a->ls_given, "--ls-weights"}, {a->illum_given, "--illum-refs"}};
        for (size_t k = 0; k < sizeof storage / sizeof storage[0]; k++)
            if (storage[k].given && a->scene) {
                sss_cli_printf(stderr, "%s: %s applies to plain bakes, not to --scene (a scene's \"bake\" object sets "
                               "weights, compress and near_terms: docs/scenes.md)\n", TOOL, storage[k].name);
                return 2;
            } else if (storage[k].given) {
                sss_cli_printf(stderr, "%s: %s: not with --point-light (the file is baked and stored as a scene's "
                               "object: docs/scenes.md)\n", TOOL, storage[k].name);
                return 2;
            }
        if (a->near_terms_given) return refuse("--own-term: not with --point-light (the file is baked and stored as "
                                               "a scene's object: docs/scenes.md)");
        if (a->scene) return SSS_CLI_RUN; /* the scene names meshes and materials: the rest is the plain bake's */
    }
    if (compress_given && a->have_quant)
        return refuse("--quant and the compression options (--sh-order, --refs, ...) exclude each other");
    if (a->compress && !a->refs_given && a->order_given && a->sh_order == 0)
        return refuse("--sh-order 0 needs --refs FRACTION > 0 (nothing would be stored)");
    if (a->compress && a->refs == 0.0 && a->sh_order == 0) return refuse("--refs 0 (SH only) needs --sh-order >= 1");
    if (!a->mesh) return refuse("missing MESH (see --help)");
    if (!a->out) return refuse("missing -o OUT.sss (see --help)");
    if ((a->have_sigma_a || a->have_sigma_s) && (a->material || !a->have_sigma_a || !a->have_sigma_s))
        return refuse("give either --material NAME or both --sigma-a and --sigma-s");
    return SSS_CLI_RUN;
}

/* Set by SIGINT / SIGTERM; the bake polls it (sss_bake_options.cancel). */
static volatile sig_atomic_t interrupted;

static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
}

/* What the bake is given: its options, the compression they point to, the
 * material. */
typedef struct bake_setup {
    sss_bake_options opt;
    sss_compress_opts co; /* opt.compress points here when compressing */
    sss_material mat;     /* a plain bake's; a scene names its own */
} bake_setup;

/* The options of the bake from the command line and the environment: a
 * memory limit (a share of a machine used by others; the tests use it to
 * exercise the refusal), a progress log for scripts and tests, the
 * gather's own figures. Returns SSS_CLI_RUN, or 2 after a message on the
 * material. */
static int options(const bake_args *a, bake_setup *s)
{
    sss_bake_options *opt = &s->opt;
    memset(opt, 0, sizeof *opt);
    opt->mm_per_unit = a->mm_per_unit;
    opt->n_dirs = a->dirs;
    opt->eps = a->eps;
    opt->quant = (sss_quant)a->quant;
    opt->gather = a->gather;
    opt->theta = a->theta;
    opt->threads = a->threads;
    opt->near_terms = a->near_terms;
    opt->near_rings = a->near_rings;
    opt->near_radius_mm = a->near_radius_given ? a->near_radius : 0.0;
    /* --own-term runtime alone: the radius holding a fraction of R_d,total
     * (sss_near_radius_material), the same physical neighbourhood on a fine
     * and a coarse mesh; --rings and --near-radius are the expert's */
    if (a->near_terms == SSS_NEAR_TERMS_RUNTIME && !a->rings_given && !a->near_radius_given) {
        opt->near_rings = 0;
        opt->near_fraction = a->near_fraction_given ? a->near_fraction : SSS_NEAR_FRACTION_DEFAULT;
    }
    opt->weights = (uint32_t)a->weights;
    opt->vector = a->vector;
    opt->memory_limit = sss_cli_memory_limit();
    const char *log = getenv("SSS_PROGRESS_LOG");
    if (log && *log) opt->progress_log = log;
    opt->verbose = getenv("SSS_GATHER_VERBOSE") != NULL;
    opt->cancel = &interrupted;
    sss_compress_opts_default(&s->co);
    if (a->scene) { /* scene_main bakes every object with the scene's materials */
        opt->progress = 0;
        return SSS_CLI_RUN;
    }

    sss_error err = {{0}};
    sss_material *mat = &s->mat;
    if (a->have_sigma_a || a->have_sigma_s) { /* then both, and no --material: parse() */
        memset(mat, 0, sizeof *mat);
        snprintf(mat->name, sizeof mat->name, "custom");
        for (int c = 0; c < 3; c++) {
            mat->sigma_a[c] = a->sigma_a[c];
            mat->sigmap_s[c] = a->sigma_s[c] * (1.0 - a->g); /* --g makes --sigma-s σs (a->g is 0 without it) */
        }
        mat->eta = a->eta;
    } else if (sss_material_preset(a->material ? a->material : "marble", mat, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 2;
    } else if (a->have_eta) {
        mat->eta = a->eta;
    }
    mat->g = a->g; /* a preset keeps its σ′s and takes the phase */
    if (sss_material_validate(mat, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 2;
    }
    /* a one-channel material holds more by default (sss/nearterms.h) */
    if (opt->near_fraction > 0.0 && !a->near_fraction_given)
        opt->near_fraction = sss_near_fraction_default(sss_material_channels(mat));
    if (a->compress) {
        sss_compress_opts *co = &s->co;
        co->order = a->sh_order;
        co->fraction = a->refs;
        co->sh_kind = (uint32_t)a->sh_quant;
        co->wbits = a->weight_bits;
        co->ls_weights = a->ls_weights;
        co->illum_weight = a->illum_weight;
        /* a preset fills what the user did not set (docs/compression.md) */
        const uint32_t given = (a->order_given ? SSS_CO_ORDER : 0) | (a->refs_given ? SSS_CO_FRACTION : 0) |
                               (a->sh_quant_given ? SSS_CO_SH_KIND : 0) | (a->wbits_given ? SSS_CO_WBITS : 0) |
                               (a->ls_given ? SSS_CO_LS_WEIGHTS : 0) | (a->illum_given ? SSS_CO_ILLUM : 0);
        sss_compress_preset_apply(co, (sss_compress_preset)a->preset, sss_material_channels(mat),
                                  a->dirs ? a->dirs : 200, given);
        opt->quant = SSS_QUANT_FLOAT;
        opt->compress = co;
    }
    opt->progress = !a->quiet;
    return SSS_CLI_RUN;
}

/* What a plain bake produced, for its report. */
typedef struct bake_result {
    sss_import_report rep;
    sss_bake_file f;
    sss_bake_stats st;
    double t_import, t_write;
    double t_total; /* import to written file, every phase and what lies between them */
    long long file_bytes; /* -1: the written file could not be opened */
    int nranks;
} bake_result;

/* The summary and the warnings on stderr (the warnings also with -q). */
static void report_text(const bake_args *a, const bake_setup *s, const bake_result *r, int quiet)
{
    char in_shown[1024], out_shown[1024];
    const char *in = sss_cli_shown(a->mesh, in_shown, sizeof in_shown), *outp = sss_cli_shown(a->out, out_shown,
                                                                                                sizeof out_shown);
    const sss_bake_file *f = &r->f;
    const sss_bake_stats *st = &r->st;
    const uint32_t nv = f->mesh.nv, C = f->channels, N = f->dirs.n;
    const long long fsize = r->file_bytes;
    /* the tree gather sums the near sources in dense blocks and never forms
     * a vertex's row: there is no per-vertex maximum to report (it said
     * "max 0"); its mean is the dense blocks' sources per vertex */
    char maxtext[64];
    if (st->gather == SSS_GATHER_TREE) snprintf(maxtext, sizeof maxtext, " in the dense blocks");
    else snprintf(maxtext, sizeof maxtext, " (max %u)", st->neighbours_max);
    if (!quiet)
        fprintf(stderr, /* several lines: the paths in them shown one-line (sss_cli_shown) */
                "%s: %s: %u vertices, %u triangles, %u directions, %u channels, %s\n"
                "  neighbourhood radius %.3g/%.3g/%.3g mm, mean %.1f neighbours%s\n"
                "  rays %llu (%.1f%% occluded)%s\n"
                "  time: import %.3fs, neighbourhoods %.3fs, visibility %.3fs, integrals %.3fs, quantise %.3fs, compress %.3fs, write %.3fs, total %.3fs\n"
                "  %s: %lld bytes, %.1f bytes/vertex (integrals %.1f)\n",
                TOOL, in, nv, f->mesh.nf, N, C, sss_quant_name(f->quant), st->radius_mm[0],
                st->radius_mm[1], st->radius_mm[2], st->neighbours_mean, maxtext, (unsigned long long)st->rays,
                100.0 * st->occluded_fraction, "", r->t_import, st->t_neighbourhoods, st->t_visibility, st->t_integrals,
                st->t_quantise, st->t_compress, r->t_write, r->t_total, outp, fsize, (double)fsize / nv,
                sss_file_integral_bytes_per_vertex(f));
    if (!quiet && f->near_terms && f->near_radius_mm > 0.0 && nv)
        sss_cli_printf(stderr, "  near terms at run time: every vertex within %.3g mm (%.1f%% of R_d total%s), %.1f per "
                "vertex\n", f->near_radius_mm, 100.0 * st->near_fraction_held,
                st->near_capped ? ", shrunk to hold at most 512 vertices on average: the object is small against "
                "the scattering range" : "", (double)st->near_entries / nv);
    /* the near terms' weights, one float per channel and entry, which every
     * reader builds and sums each frame: beyond OpenGL 4.3's guaranteed
     * storage block of 2^27 bytes the viewer splits them into chunks
     * (runtime/src/render/effects/near.c) and the frame time grows with
     * them (docs/accuracy.md, "Near terms sized by the material") */
    if (f->near_terms && (double)st->near_entries * 4.0 * C > 134217728.0)
        sss_cli_printf(stderr, "%s: %s: warning: the near terms hold %.1f entries per vertex, %.0f MiB of weights that "
                "every reader builds and sums each frame (more than the 128 MiB storage block OpenGL 4.3 guarantees); "
                "a smaller --near-fraction or --near-radius costs less (docs/accuracy.md)\n", TOOL, in,
                (double)st->near_entries / nv, (double)st->near_entries * 4.0 * C / 1048576.0);
    if (st->thin_vertices)
        sss_cli_printf(stderr, "%s: %s: warning: %u vertices lie on parts thinner than the scattering length 1/sigma_tr = %.3g mm "
                "(thinnest %.3g mm): the semi-infinite dipole counts light gathered through them twice, so q there comes "
                "out too large (docs/robustness.md B8)\n", TOOL, in, st->thin_vertices, st->thin_limit_mm, st->thinnest_mm);
    if (!quiet)
        sss_cli_printf(stderr, "  gather %s%s: tree %.3fs, %.1f GFLOP/s%s; memory predicted %.0f MiB, peak RSS %.0f MiB%s\n",
                st->gather == SSS_GATHER_TREE ? "tree" : "direct",
                st->gather == SSS_GATHER_TREE ? "" : " (every neighbour)", st->t_tree, st->gather_gflops,
                st->gather == SSS_GATHER_TREE ? " in the block products" : " multiply-adds x 2", st->predicted_peak_bytes / 1048576.0,
                sss_cli_peak_rss_mib(), r->nranks > 1 ? " (rank 0)" : "");
    /* the memory plan (docs/benchmarks.md, "Memory: light directions in chunks") */
    if (!quiet && st->direction_chunks > 1)
        sss_cli_printf(stderr, "  light directions in %u chunks of at most %u: the memory available would not hold the "
                "transfer rows and tree moments of all %u at once (same output)\n",
                st->direction_chunks, st->direction_chunk_width, N);
    if (st->coarse_vertices && f->weights == SSS_WEIGHTS_HAT)
        sss_cli_printf(stderr, "%s: %s: warning: %u vertices have an edge longer than %.3g mm, twice the scattering length "
                "1/sigma_tr = %.3g mm, whose ends' normals differ by more than 30 degrees (longest edge %.3g mm): "
                "the irradiance, linear along such an edge, cannot follow the bend; resample the mesh finer\n", TOOL, in,
                st->coarse_vertices, 2.0 * st->range_mm, st->range_mm, st->longest_edge_mm);
    else if (st->coarse_vertices)
        sss_cli_printf(stderr, "%s: %s: warning: %u vertices have an edge longer than %.3g mm, twice the scattering length "
                "1/sigma_tr = %.3g mm (longest edge %.3g mm): the per-vertex sum does not resolve the profile there "
                "and q comes out too large; resample the mesh finer\n", TOOL, in, st->coarse_vertices,
                2.0 * st->range_mm, st->range_mm, st->longest_edge_mm);
    if (!quiet && f->quant == SSS_QUANT_REFS)
        sss_cli_printf(stderr, "  %u references (%.2f%%), %u reference triangles, SH order %u (%s), %u-bit %s weights\n",
                f->ref.nref, 100.0 * f->ref.nref / nv, f->ref.nrt, f->sh.order, sss_shq_name(f->sh.kind), f->ref.wbits,
                s->co.ls_weights ? "least-squares" : "barycentric");
    if (!quiet && f->quant == SSS_QUANT_SH)
        sss_cli_printf(stderr, "  SH order %u (%s) at every vertex\n", f->sh.order, sss_shq_name(f->sh.kind));
    if (!quiet && f->quant == SSS_QUANT_LLOYD8)
        sss_cli_printf(stderr, "  lloyd8 SNR %.2f dB (R %.2f, G %.2f, B %.2f)\n", st->lloyd_snr_db_all, st->lloyd_snr_db[0],
                st->lloyd_snr_db[1], st->lloyd_snr_db[2]);
}

/* --json: one object on stdout. */
static void report_json(const bake_args *a, const bake_setup *s, const bake_result *r)
{
    const sss_bake_file *f = &r->f;
    const sss_bake_stats *st = &r->st;
    const sss_import_report *rep = &r->rep;
    const uint32_t nv = f->mesh.nv;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "mesh", a->mesh);
    cJSON_AddStringToObject(o, "output", a->out);
    cJSON_AddNumberToObject(o, "vertices", nv);
    cJSON_AddNumberToObject(o, "triangles", f->mesh.nf);
    cJSON_AddNumberToObject(o, "directions", f->dirs.n);
    cJSON_AddNumberToObject(o, "channels", f->channels);
    cJSON_AddStringToObject(o, "quant", sss_quant_name(f->quant));
    if (a->compress) {
        cJSON_AddNumberToObject(o, "sh_order", f->sh.order);
        cJSON_AddStringToObject(o, "sh_quant", sss_shq_name(f->sh.kind));
        cJSON_AddNumberToObject(o, "refs", f->quant == SSS_QUANT_REFS ? f->ref.nref : 0);
    }
    cJSON_AddStringToObject(o, "material", s->mat.name);
    cJSON_AddNumberToObject(o, "mm_per_unit", f->mm_per_unit);
    /* what the input carries besides its shape (sss/mesh.h): kept in memory
     * for the bake, not stored in the .sss */
    cJSON *in = cJSON_AddObjectToObject(o, "input");
    cJSON_AddBoolToObject(in, "texcoords", rep->texcoords);
    cJSON_AddBoolToObject(in, "colours", rep->colours);
    cJSON_AddNumberToObject(in, "primitives_skipped", (double)rep->primitives_skipped);
    cJSON *rp = cJSON_AddObjectToObject(o, "repairs");
    cJSON_AddNumberToObject(rp, "polygons_triangulated", (double)rep->polygons_triangulated);
    cJSON_AddNumberToObject(rp, "faces_too_small", (double)rep->faces_too_small);
    cJSON_AddNumberToObject(rp, "faces_repeated_index", (double)rep->faces_repeated_index);
    cJSON_AddNumberToObject(rp, "faces_zero_area", (double)rep->faces_zero_area);
    cJSON_AddNumberToObject(rp, "vertices_unreferenced", (double)rep->vertices_unreferenced);
    cJSON_AddNumberToObject(rp, "polygons_ear_clipped", (double)rep->polygons_ear_clipped);
    cJSON_AddNumberToObject(rp, "polygons_unclipped", (double)rep->polygons_unclipped);
    cJSON_AddNumberToObject(rp, "faces_duplicate", (double)rep->faces_duplicate);
    cJSON_AddNumberToObject(rp, "faces_flipped", (double)rep->faces_flipped);
    cJSON_AddNumberToObject(rp, "surfaces_inside_out", (double)rep->surfaces_inside_out);
    cJSON_AddNumberToObject(rp, "open_faces_flipped", (double)rep->open_faces_flipped);
    cJSON_AddNumberToObject(rp, "orientation_conflicts", (double)rep->orientation_conflicts);
    cJSON_AddNumberToObject(rp, "recentred", (double)rep->recentred);
    if (rep->recentred) cJSON_AddItemToObject(rp, "offset", cJSON_CreateDoubleArray(rep->offset, 3));
    cJSON_AddItemToObject(o, "radius_mm", cJSON_CreateDoubleArray(st->radius_mm, 3));
    cJSON_AddNumberToObject(o, "coarse_vertices", st->coarse_vertices);
    cJSON_AddNumberToObject(o, "thin_vertices", st->thin_vertices);
    if (f->near_terms && nv) cJSON_AddNumberToObject(o, "near_entries_per_vertex", (double)st->near_entries / nv);
    if (f->near_terms && f->near_radius_mm > 0.0) {
        cJSON_AddNumberToObject(o, "near_radius_mm", f->near_radius_mm);
        if (st->near_fraction_held > 0.0) cJSON_AddNumberToObject(o, "near_fraction_held", st->near_fraction_held);
        cJSON_AddBoolToObject(o, "near_capped", st->near_capped);
    }
    if (isfinite(st->thinnest_mm)) cJSON_AddNumberToObject(o, "thinnest_mm", st->thinnest_mm);
    cJSON_AddNumberToObject(o, "longest_edge_mm", st->longest_edge_mm);
    cJSON_AddNumberToObject(o, "scattering_length_mm", st->range_mm);
    cJSON_AddNumberToObject(o, "neighbours_mean", st->neighbours_mean);
    if (st->gather == SSS_GATHER_TREE) cJSON_AddNullToObject(o, "neighbours_max"); /* not formed by the tree gather */
    else cJSON_AddNumberToObject(o, "neighbours_max", st->neighbours_max);
    cJSON_AddNumberToObject(o, "rays", (double)st->rays);
    cJSON_AddNumberToObject(o, "occluded_fraction", st->occluded_fraction);
    cJSON *tm = cJSON_AddObjectToObject(o, "seconds");
    cJSON_AddNumberToObject(tm, "import", r->t_import);
    cJSON_AddNumberToObject(tm, "neighbourhoods", st->t_neighbourhoods);
    cJSON_AddNumberToObject(tm, "visibility", st->t_visibility);
    cJSON_AddNumberToObject(tm, "integrals", st->t_integrals);
    cJSON_AddNumberToObject(tm, "quantise", st->t_quantise);
    cJSON_AddNumberToObject(tm, "compress", st->t_compress);
    cJSON_AddNumberToObject(tm, "write", r->t_write);
    if (f->weights == SSS_WEIGHTS_HAT) cJSON_AddNumberToObject(tm, "hat", st->t_hat);
    if (f->qvec) cJSON_AddNumberToObject(tm, "vector", st->t_vector); /* within "integrals" */
    cJSON_AddNumberToObject(tm, "total", r->t_total);
    cJSON_AddNumberToObject(o, "peak_rss_mib", sss_cli_peak_rss_mib());
    /* the gather, its sgemm rate and the memory predicted before starting
     * (docs/benchmarks.md) */
    cJSON_AddStringToObject(o, "gather", st->gather == SSS_GATHER_TREE ? "tree" : "direct");
    if (st->gather == SSS_GATHER_TREE) {
        cJSON_AddNumberToObject(o, "theta", st->theta);
        cJSON_AddNumberToObject(o, "tree_nodes", st->tree_nodes);
        cJSON_AddNumberToObject(o, "tree_blocks", st->tree_blocks);
        cJSON_AddNumberToObject(o, "rows_per_block", st->rows_mean);
        cJSON_AddNumberToObject(o, "far_nodes_per_vertex", st->far_pairs / (double)nv);
        cJSON_AddNumberToObject(o, "sgemm_fraction", st->sgemm_fraction);
        cJSON_AddNumberToObject(o, "direction_chunks", st->direction_chunks);
        cJSON_AddNumberToObject(o, "direction_chunk_width", st->direction_chunk_width);
        cJSON_AddNumberToObject(tm, "tree", st->t_tree);
    }
    cJSON_AddNumberToObject(o, "gather_gflops", st->gather_gflops);
    if (st->gather == SSS_GATHER_TREE) cJSON_AddNumberToObject(o, "near_gflops", st->near_gflops);
    cJSON_AddNumberToObject(o, "predicted_peak_mib", st->predicted_peak_bytes / 1048576.0);
    cJSON_AddNumberToObject(o, "mpi_ranks", r->nranks);
    cJSON_AddNumberToObject(o, "file_bytes", (double)r->file_bytes);
    cJSON_AddNumberToObject(o, "bytes_per_vertex", (double)r->file_bytes / nv);
    cJSON_AddNumberToObject(o, "integral_bytes_per_vertex", sss_file_integral_bytes_per_vertex(f));
    if (f->quant == SSS_QUANT_LLOYD8) {
        cJSON_AddNumberToObject(o, "lloyd_snr_db", st->lloyd_snr_db_all);
        cJSON_AddItemToObject(o, "lloyd_snr_db_per_channel", cJSON_CreateDoubleArray(st->lloyd_snr_db, 3));
    }
    sss_json_utf8(o); /* valid JSON whatever the bytes of a file name (sss/jsontext.h) */
    char *str = cJSON_PrintUnformatted(o);
    puts(str);
    free(str);
    cJSON_Delete(o);
}

/* A plain bake: import, bake, write, report. Under mpirun the ranks split
 * the receivers and rank 0 alone speaks and writes. Returns the exit
 * status: 0, 1 (import, bake or write failed), 130 (interrupted). */
static int run(const bake_args *a, bake_setup *s, int *argc, char ***argv)
{
    const char *in = a->mesh, *outp = a->out;
    sss_bake_options *opt = &s->opt;
    int quiet = a->quiet, json = a->json;
    int mpi_rank = 0;
    bake_result r;
    memset(&r, 0, sizeof r);
    sss_mpi_start(argc, argv, &mpi_rank, &r.nranks);
    if (r.nranks > 1) {
        opt->rank = mpi_rank;
        opt->nranks = r.nranks;
        opt->comm = sss_mpi_comm();
        if (mpi_rank != 0) { opt->progress = 0; quiet = 1; json = 0; }
    }
    signal(SIGINT, on_sigint);
    signal(SIGTERM, on_sigint);

    sss_error err = {{0}};
    /* the output is checked before the bake (sss/fileio.h), so that a path
     * that may not be written is refused at once, not after the bake; the
     * writer checks it again */
    const char *inputs[1] = {in};
    const sss_inputs ins = {inputs, 1};
    if (mpi_rank == 0 && sss_output_check(outp, &ins, NULL, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        sss_mpi_abort(1);
        return 1;
    }
    double t0 = sss_now();
    const double t_start = t0;
    sss_mesh mesh;
    if (sss_import_mesh(in, &mesh, &r.rep, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    r.t_import = sss_now() - t0;
    {
        char prefix[1200], shown[1100];
        snprintf(prefix, sizeof prefix, "%s: %s", TOOL, sss_cli_shown(in, shown, sizeof shown));
        if (!quiet) sss_import_print_repairs(&r.rep, prefix, stderr);
        sss_import_print_warnings(&r.rep, prefix, stderr); /* also with -q, like the bake's warnings */
    }
    if (r.rep.recentred) opt->import_offset = r.rep.offset; /* provenance (docs/robustness.md B6) */

    if (sss_bake(&mesh, sss_cli_basename(in), &s->mat, opt, &r.f, &r.st, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, in, err.msg);
        sss_mesh_free(&mesh);
        sss_mpi_abort(interrupted ? 130 : 1); /* the other ranks wait in a collective */
        return interrupted ? 130 : 1;
    }
    if (r.nranks > 1 && mpi_rank != 0) { /* its part went to rank 0 */
        sss_file_free(&r.f);
        sss_mesh_free(&mesh);
        sss_mpi_stop();
        return 0;
    }
    t0 = sss_now();
    /* a signal after the bake's last poll: still nothing is written */
    sss_result w = interrupted ? sss_fail(&err, SSS_ERR_INTERRUPTED, "%s: interrupted, nothing written", outp)
                               : sss_file_write_with(outp, &r.f, &ins, &err);
    r.t_write = sss_now() - t0;
    r.t_total = sss_now() - t_start;
    if (w != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        sss_file_free(&r.f);
        sss_mesh_free(&mesh);
        return w == SSS_ERR_INTERRUPTED ? 130 : 1;
    }
    FILE *fp = fopen(outp, "rb");
    r.file_bytes = -1;
    if (fp) { fseek(fp, 0, SEEK_END); r.file_bytes = ftell(fp); fclose(fp); }
    report_text(a, s, &r, quiet);
    if (json) report_json(a, s, &r);
    sss_file_free(&r.f);
    sss_mesh_free(&mesh);
    sss_mpi_stop();
    return 0;
}

int main(int argc, char **argv)
{
    bake_args a;
    bake_setup s;
    int rc = parse(argc, argv, &a);
    if (rc == SSS_CLI_RUN) rc = options(&a, &s);
    if (rc != SSS_CLI_RUN) return rc;
    if (a.scene) return scene_main(TOOL, a.scene, a.out, a.plan, a.json, a.quiet, &s.opt);
    if (a.npoints)
        return points_main(TOOL, a.mesh, a.out, &s.mat, a.mm_per_unit, (const double (*)[4])a.points, a.npoints, a.json,
                           a.quiet, &s.opt);
    return run(&a, &s, &argc, &argv);
}
