/* cli_genmesh_parse.c: sss-genmesh's own command-line reading, with its
 * main renamed, for fuzz_cli.c. */
#define main sss_genmesh_tool_main
#include "../../data/gen/genmesh_main.c"
#undef main

int fuzz_cli_genmesh(int argc, char **argv);
int fuzz_cli_genmesh(int argc, char **argv)
{
    genmesh_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc != SSS_CLI_RUN) return rc;
    if (!a.kind || !a.out || a.res < 0 || a.res > 100000 || !(a.size > 0)) abort();
    return rc;
}
