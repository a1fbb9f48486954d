/* cli_ref_parse.c: sss-ref's own command-line reading (parse, and setup
 * when it reads no file), with its main renamed, for fuzz_cli.c. */
#include <float.h>
#include <math.h>

#define main sss_ref_tool_main
#include "../../precompute/tools/sss_ref.c"
#undef main

int fuzz_cli_ref(int argc, char **argv);
int fuzz_cli_ref(int argc, char **argv)
{
    ref_args a;
    int rc = parse(argc, argv, &a);
    if (rc != SSS_CLI_RUN) return rc;
    if (!a.mesh || (!a.have_query && !a.out)) abort();
    if (a.size[0] < 1 || a.size[0] > 16384 || a.size[1] < 1 || a.size[1] > 16384) abort();
    if (a.have_seconds && !(a.seconds > 0 && a.seconds <= 1e9)) abort();
    if (a.have_light) {
        const double l2 = a.light[0] * a.light[0] + a.light[1] * a.light[1] + a.light[2] * a.light[2];
        if (!(l2 >= DBL_MIN && l2 <= DBL_MAX)) abort();
    }
    if (a.env && strcmp(a.env, "uniform") != 0) return SSS_CLI_RUN; /* setup would read the probe */
    ref_setup s;
    rc = setup(&a, &s);
    if (rc == SSS_CLI_RUN) { /* a medium the walks can use */
        for (int c = 0; c < 3; c++)
            if (!(isfinite(s.medium.sigma_a[c]) && s.medium.sigma_a[c] >= 0 && isfinite(s.medium.sigma_s[c]) &&
                  s.medium.sigma_s[c] >= 0))
                abort();
        if (!(s.medium.g > -1 && s.medium.g < 1) || !(s.medium.eta > 0 && isfinite(s.medium.eta))) abort();
    }
    sss_probe_free(&s.probe);
    return rc;
}
