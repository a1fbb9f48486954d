/* cli_bake_parse.c: sss-bake's own command-line reading (parse, options),
 * with its main renamed, for fuzz_cli.c: the tool's table as it ships. */
#define main sss_bake_tool_main
#include "../../precompute/tools/sss_bake.c"
#undef main

int fuzz_cli_bake(int argc, char **argv);
int fuzz_cli_bake(int argc, char **argv)
{
    bake_args a;
    bake_setup s;
    int rc = parse(argc, argv, &a);
    if (rc == SSS_CLI_RUN) rc = options(&a, &s);
    if (rc != SSS_CLI_RUN) return rc;
    /* what the bake is handed: inside the ranges the options promise */
    const sss_bake_options *o = &s.opt;
    if (o->n_dirs > 100000 || (o->mm_per_unit != 0 && !(o->mm_per_unit >= 1e-12 && o->mm_per_unit <= 1e12))) abort();
    if (o->eps != 0 && !(o->eps >= 1e-12 && o->eps <= 0.5)) abort();
    if (o->theta != 0 && !(o->theta >= 1e-3 && o->theta <= 0.95)) abort();
    if (o->near_rings > SSS_NEAR_RINGS_MAX) abort();
    /* a radius from the material: a fraction in range, only for run-time
     * near terms without a radius or rings of their own */
    if (o->near_fraction != 0 && !(o->near_fraction >= 0.5 && o->near_fraction <= 0.999 &&
                                   o->near_terms == SSS_NEAR_TERMS_RUNTIME && o->near_radius_mm == 0 &&
                                   o->near_rings == 0))
        abort();
    if (!a.scene) {
        sss_error err = {{0}};
        if (sss_material_validate(&s.mat, &err) != SSS_OK) abort();
    }
    return rc;
}
