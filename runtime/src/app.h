/* app.h: the interactive GLFW window of sss-view. */
#ifndef SSS_APP_H
#define SSS_APP_H

#include "renderer.h"

typedef struct sss_app_options {
    const char *file_path;       /* for the title and overlay */
    int width, height;           /* initial window size */
    const char *screenshot_path; /* where 'P' saves a PNG (NULL: sss-view-NNN.png in the cwd) */
} sss_app_options;

/* Opens a window, runs the event loop until closed (Esc / Q / window close),
 * returns the process exit code (0 ok, 1 when no window or GL context could
 * be created, with a one-line message on stderr). f must stay alive. */
int sss_app_run(const sss_bake_file *f, const sss_view_params *initial, const sss_app_options *opt);

/* The controls, one per line, for --help. */
extern const char *sss_app_controls_help;

#endif
