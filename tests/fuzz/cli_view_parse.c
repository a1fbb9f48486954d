/* cli_view_parse.c: sss-view's own command-line reading (parse), with its
 * main renamed, for fuzz_cli.c. The window (app.c) is not linked: its two
 * entry points are stubs here. */
#define main sss_view_tool_main
#include "../../runtime/src/view/main.c"
#undef main

#include <float.h>

const char *sss_app_controls_help = "";
int sss_app_run(const sss_bake_file *f, const sss_view_params *initial, const sss_app_options *opt)
{
    (void)f, (void)initial, (void)opt;
    return 0;
}

int fuzz_cli_view(int argc, char **argv);
int fuzz_cli_view(int argc, char **argv)
{
    view_args a;
    int rc = parse(argc, argv, &a);
    if (rc != SSS_CLI_RUN) return rc;
    /* what the renderer is handed: sizes it takes, finite gains within
     * SSS_VIEW_GAIN_MAX, directions that normalise */
    if (a.size[0] < 1 || a.size[0] > 16384 || a.size[1] < 1 || a.size[1] > 16384) abort();
    if (!(a.p.exposure > 0 && a.p.exposure <= SSS_VIEW_GAIN_MAX)) abort();
    if (!(a.intensity > 0 && a.intensity <= SSS_VIEW_GAIN_MAX)) abort();
    for (int k = 0; k < 2; k++) {
        const double *d = k ? a.p.view : a.p.light;
        const double l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (!(l2 >= DBL_MIN && l2 <= DBL_MAX)) abort();
    }
    if (a.p.shadow_size != 0 && (a.p.shadow_size < 256 || a.p.shadow_size > 8192)) abort();
    if (a.out && !sss_image_type_known(a.out)) abort();
    return rc;
}
