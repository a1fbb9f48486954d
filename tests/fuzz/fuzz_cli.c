/* fuzz_cli.c: libFuzzer harness for the tools' command lines
 * (common/cli, sss_cli, with each tool's own option table: sss-bake,
 * sss-stat, sss-view, sss-genmesh, sss-ref; docs/robustness.md item 5). The first
 * input byte picks the tool, the rest is its arguments separated by NUL
 * bytes (at most 64). Each tool's reading must return "run" (what it
 * hands on then lies in the ranges its options promise: cli_*_parse.c), 0
 * after --help, or 2 after a message: never anything else, never a crash
 * or undefined behaviour (a --size beyond int wrapped silently). Messages
 * go to stderr: run it with -close_fd_mask=3. Nothing is imported, read or
 * written. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sss/cli.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int fuzz_cli_bake(int argc, char **argv);
int fuzz_cli_stat(int argc, char **argv);
int fuzz_cli_view(int argc, char **argv);
int fuzz_cli_genmesh(int argc, char **argv);
int fuzz_cli_ref(int argc, char **argv);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    static const char *const tools[5] = {"sss-bake", "sss-stat", "sss-view", "sss-genmesh", "sss-ref"};
    const int t = data[0] % 5; /* 0 … 3 as before sss-ref was added */
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data + 1, size - 1);
    text[size - 1] = 0;
    char *argv[66];
    int argc = 0;
    argv[argc++] = (char *)tools[t];
    for (char *p = text; argc < 65 && p <= text + size - 1;) {
        argv[argc++] = p;
        p += strlen(p) + 1;
    }
    if (size == 1) argc = 1;
    argv[argc] = NULL;
    int rc;
    switch (t) {
    case 0: rc = fuzz_cli_bake(argc, argv); break;
    case 1: rc = fuzz_cli_stat(argc, argv); break;
    case 2: rc = fuzz_cli_view(argc, argv); break;
    case 3: rc = fuzz_cli_genmesh(argc, argv); break;
    default: rc = fuzz_cli_ref(argc, argv); break;
    }
    if (rc != SSS_CLI_RUN && rc != 0 && rc != 2) abort();
    free(text);
    return 0;
}
