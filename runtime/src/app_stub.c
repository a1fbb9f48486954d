/* Temporary: replaced by app.c (GLFW window). */
#include <stdio.h>
#include "app.h"
const char *sss_app_controls_help = "  (window mode not built yet)\n";
int sss_app_run(const sss_bake_file *f, const sss_view_params *initial, const sss_app_options *opt)
{
    (void)f; (void)initial; (void)opt;
    fprintf(stderr, "sss-view: window mode not available yet\n");
    return 1;
}
