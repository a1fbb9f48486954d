/* cli_stat_parse.c: sss-stat's own command-line reading (parse_args and its
 * checks), with its main renamed, for fuzz_cli.c. */
#define main sss_stat_tool_main
#include "../../precompute/tools/sss_stat.c"
#undef main

int fuzz_cli_stat(int argc, char **argv);
int fuzz_cli_stat(int argc, char **argv)
{
    stat_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc != SSS_CLI_RUN) return rc;
    if (!a.path == !a.scene) abort(); /* a file, or a deforming scene without one */
    if (a.views < 1 || a.views > 100000) abort();
    if (a.ea.exposure != 0 && !(a.ea.exposure > 0 && a.ea.exposure <= SSS_VIEW_GAIN_MAX)) abort();
    if (a.ea.image_size != 0 && (a.ea.image_size < 16 || a.ea.image_size > 4096)) abort();
    if (a.qlight) { /* what query() reads after the file: refused or a direction */
        double l[3];
        if (parse_light("fuzz.sss", a.qlight, l)) {
            const double l2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
            if (!(l2 >= DBL_MIN && l2 <= DBL_MAX)) abort();
        }
    }
    if (a.qvertex) {
        uint32_t v;
        if (parse_vertex("fuzz.sss", a.qvertex, 1000, &v) && v >= 1000) abort();
    }
    return combinations_ok(&a) ? SSS_CLI_RUN : 2;
}
