/* test_cli.c: the tools' option parser (sss/cli.h) on its own: each kind of
 * value, ranges at and beyond their limits, missing values, unknown options,
 * given flags, positionals, and the exact text of every message (the parser
 * writes to the streams it is given, so the tests read them back). */
#define _POSIX_C_SOURCE 200809L /* dup, dup2, fileno: stderr read back */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include <unistd.h>

#include "sss/cli.h"

/* ---- helpers ------------------------------------------------------------ */

static FILE *out_f, *err_f;

static int setup(void **state)
{
    (void)state;
    out_f = tmpfile();
    err_f = tmpfile();
    return out_f && err_f ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    fclose(out_f);
    fclose(err_f);
    return 0;
}

/* Everything written to f so far, then f emptied for the next call. */
static const char *take(FILE *f)
{
    static char buf[2][4096];
    static int which;
    char *b = buf[which ^= 1];
    fflush(f);
    long n = ftell(f);
    rewind(f);
    size_t got = fread(b, 1, n > 0 && (size_t)n < sizeof buf[0] ? (size_t)n : sizeof buf[0] - 1, f);
    b[got] = 0;
    rewind(f);
    /* truncate: reopen the same stream as an empty temporary */
    FILE *fresh = tmpfile();
    assert_non_null(fresh);
    if (f == out_f) { fclose(out_f); out_f = fresh; }
    else { fclose(err_f); err_f = fresh; }
    return b;
}

static sss_cli tool(const sss_cli_opt *opts, size_t n)
{
    sss_cli c = {.tool = "sss-test", .opts = opts, .nopts = n, .out = out_f, .err = err_f};
    return c;
}

/* Runs sss_cli_parse on the NULL-terminated arguments after the tool name. */
static int run(sss_cli *c, ...)
{
    char *argv[32] = {"sss-test"};
    int argc = 1;
    va_list ap;
    va_start(ap, c);
    for (char *a; (a = va_arg(ap, char *)) != NULL && argc < 31;) argv[argc++] = a;
    va_end(ap);
    argv[argc] = NULL;
    c->out = out_f;
    c->err = err_f;
    return sss_cli_parse(c, argc, argv);
}

static void usage(FILE *f) { fputs("usage: sss-test [options]\n", f); }

/* ---- values ------------------------------------------------------------- */

static void doubleAtBothLimitsIsAccepted(void **state)
{
    (void)state;
    double v = -1;
    const sss_cli_opt o[] = {{.name = "--eps", .kind = SSS_CLI_DOUBLE, .dest = &v, .lo = 1e-12, .hi = 0.5}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--eps", "1e-12", NULL), SSS_CLI_RUN);
    assert_true(v == 1e-12);
    assert_int_equal(run(&c, "--eps", "0.5", NULL), SSS_CLI_RUN);
    assert_true(v == 0.5);
    assert_string_equal(take(err_f), "");
}

static void doubleBeyondLimitPrintsRangeMessageAndKeepsDest(void **state)
{
    (void)state;
    double v = 7;
    const sss_cli_opt o[] = {{.name = "--eps", .kind = SSS_CLI_DOUBLE, .dest = &v, .lo = 1e-12, .hi = 0.5}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--eps", "0.50001", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --eps: '0.50001' must be a number in [1e-12, 0.5]\n");
    assert_int_equal(run(&c, "--eps", "9e-13", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --eps: '9e-13' must be a number in [1e-12, 0.5]\n");
    assert_true(v == 7);
}

static void doubleRefusesTrailingTextNanInfinityAndUnderflow(void **state)
{
    (void)state;
    double v = 0;
    const sss_cli_opt o[] = {{.name = "--x", .kind = SSS_CLI_DOUBLE, .dest = &v, .lo = 0, .hi = INFINITY}};
    sss_cli c = tool(o, 1);
    const char *bad[] = {"", "1x", "0.5 ", "nan", "inf", "1e400", "1e-400", "abc"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        assert_int_equal(run(&c, "--x", bad[k], NULL), 2);
        char want[128];
        snprintf(want, sizeof want, "sss-test: --x: '%s' must be a number in [0, inf]\n", bad[k]);
        assert_string_equal(take(err_f), want);
    }
}

static void doubleAboveLoRefusesLoAndTakesOwnMessage(void **state)
{
    (void)state;
    double v = 0;
    const sss_cli_opt o[] = {{.name = "--exposure", .kind = SSS_CLI_DOUBLE, .dest = &v, .lo = 0, .hi = 1e308,
                              .flags = SSS_CLI_ABOVE_LO, .msg = "%s: %s: '%s' must be a number > 0\n"}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--exposure", "0", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --exposure: '0' must be a number > 0\n");
    assert_int_equal(run(&c, "--exposure", "4.9e-324", NULL), 2); /* underflow: ERANGE */
    take(err_f);
    assert_int_equal(run(&c, "--exposure", "2.5", NULL), SSS_CLI_RUN);
    assert_true(v == 2.5);
}

static void laxDoubleTakesUnderflowAndInfinityWithinRange(void **state)
{
    (void)state;
    double v = 0;
    const sss_cli_opt o[] = {{.name = "--size", .kind = SSS_CLI_DOUBLE, .dest = &v, .lo = 0, .hi = INFINITY,
                              .flags = SSS_CLI_ABOVE_LO | SSS_CLI_LAX, .msg = "%s: %s '%s' must be a number > 0\n"}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--size", "1e-310", NULL), SSS_CLI_RUN);
    assert_true(v > 0 && v < 1e-300);
    assert_int_equal(run(&c, "--size", "1e400", NULL), SSS_CLI_RUN);
    assert_true(isinf(v));
    assert_int_equal(run(&c, "--size", "nan", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --size 'nan' must be a number > 0\n");
    assert_int_equal(run(&c, "--size", "", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --size '' must be a number > 0\n");
    assert_int_equal(run(&c, "--size", "-inf", NULL), 2);
    take(err_f);
    assert_int_equal(run(&c, "--size", "2 ", NULL), 2);
    take(err_f);
}

static void u32AtLimitsIsAcceptedAndBeyondRefused(void **state)
{
    (void)state;
    uint32_t v = 5;
    const sss_cli_opt o[] = {{.name = "--seed", .kind = SSS_CLI_U32, .dest = &v, .lo = 0, .hi = UINT32_MAX}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--seed", "4294967295", NULL), SSS_CLI_RUN);
    assert_true(v == UINT32_MAX);
    assert_int_equal(run(&c, "--seed", "0", NULL), SSS_CLI_RUN);
    assert_true(v == 0);
    assert_int_equal(run(&c, "--seed", "+7", NULL), SSS_CLI_RUN);
    assert_true(v == 7);
    assert_int_equal(run(&c, "--seed", "4294967296", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --seed: '4294967296' must be an integer in [0, 4294967295]\n");
    assert_int_equal(run(&c, "--seed", "-0", NULL), 2); /* a leading '-' is never an unsigned integer */
    assert_string_equal(take(err_f), "sss-test: --seed: '-0' must be an integer in [0, 4294967295]\n");
    assert_int_equal(run(&c, "--seed", "1.5", NULL), 2);
    take(err_f);
    assert_int_equal(run(&c, "--seed", "", NULL), 2);
    take(err_f);
    assert_int_equal(run(&c, "--seed", "99999999999999999999999", NULL), 2); /* ERANGE */
    take(err_f);
    assert_true(v == 7);
}

static void intStoresIntAndPrintsRangeWithD(void **state)
{
    (void)state;
    int v = 0;
    const sss_cli_opt o[] = {{.name = "--shadow-size", .kind = SSS_CLI_INT, .dest = &v, .lo = 256, .hi = 8192,
                              .msg = "%s: %s: '%s' must be an integer %d ... %d\n"},
                             {.name = "--threads", .kind = SSS_CLI_INT, .dest = &v, .lo = 1, .hi = 1024}};
    sss_cli c = tool(o, 2);
    assert_int_equal(run(&c, "--shadow-size", "8192", NULL), SSS_CLI_RUN);
    assert_int_equal(v, 8192);
    assert_int_equal(run(&c, "--shadow-size", "255", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --shadow-size: '255' must be an integer 256 ... 8192\n");
    assert_int_equal(run(&c, "--threads", "1025", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --threads: '1025' must be an integer in [1, 1024]\n");
}

static void laxIntReadsEmptyAndMinusZeroAsZero(void **state)
{
    (void)state;
    int v = 9;
    const sss_cli_opt o[] = {{.name = "RES", .kind = SSS_CLI_INT, .dest = &v, .lo = 0, .hi = 100000,
                              .flags = SSS_CLI_LAX, .msg = "%s: %s '%s' must be an integer in [%d, %d]\n"}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "RES", "", NULL), SSS_CLI_RUN);
    assert_int_equal(v, 0);
    v = 9;
    assert_int_equal(run(&c, "RES", "-0", NULL), SSS_CLI_RUN);
    assert_int_equal(v, 0);
    assert_int_equal(run(&c, "RES", "100000", NULL), SSS_CLI_RUN);
    assert_int_equal(v, 100000);
    assert_int_equal(run(&c, "RES", "-1", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: RES '-1' must be an integer in [0, 100000]\n");
    assert_int_equal(run(&c, "RES", "100001", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: RES '100001' must be an integer in [0, 100000]\n");
    assert_int_equal(run(&c, "RES", "3x", NULL), 2);
    take(err_f);
}

static void tripleReadsThreeNumbersAndRefusesOtherShapes(void **state)
{
    (void)state;
    double t[3] = {9, 9, 9};
    const sss_cli_opt o[] = {{.name = "--sigma-a", .kind = SSS_CLI_TRIPLE, .dest = t}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--sigma-a", "0.01,2e-1,-3", NULL), SSS_CLI_RUN);
    assert_true(t[0] == 0.01 && t[1] == 0.2 && t[2] == -3);
    assert_int_equal(run(&c, "--sigma-a", "0,0,0", NULL), SSS_CLI_RUN); /* zero allowed without NONZERO */
    const char *bad[] = {"1,2", "1,2,3,", "1,,3", "1;2;3", "1,2,inf", "1,2,3 "};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        assert_int_equal(run(&c, "--sigma-a", bad[k], NULL), 2);
        char want[128];
        snprintf(want, sizeof want, "sss-test: --sigma-a: '%s' must be three numbers X,Y,Z\n", bad[k]);
        assert_string_equal(take(err_f), want);
    }
    assert_true(t[0] == 0 && t[1] == 0 && t[2] == 0);
}

static void nonzeroTripleRefusesZeroVectorWithSecondMessage(void **state)
{
    (void)state;
    double t[3] = {0, 0, 1};
    const sss_cli_opt o[] = {{.name = "--light", .kind = SSS_CLI_TRIPLE, .dest = t, .flags = SSS_CLI_NONZERO}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--light", "0,-0,0", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --light: '0,-0,0' is not a direction\n");
    assert_true(t[2] == 1);
    /* a length that underflows or overflows when squared is no direction
     * either: normalising it gives 0 or NaN (docs/robustness.md, item 5) */
    assert_int_equal(run(&c, "--light", "0,0,-1e-300", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --light: '0,0,-1e-300' is not a direction\n");
    assert_int_equal(run(&c, "--light", "1e200,0,0", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --light: '1e200,0,0' is not a direction\n");
    assert_true(t[2] == 1);
    assert_int_equal(run(&c, "--light", "0,0,-1e-150", NULL), SSS_CLI_RUN);
    assert_true(t[2] == -1e-150);
}

static void sizeReadsWxHWithinRange(void **state)
{
    (void)state;
    int wh[2] = {800, 600};
    const sss_cli_opt o[] = {{.name = "--size", .kind = SSS_CLI_SIZE, .dest = wh, .lo = 1, .hi = 16384}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--size", "16384x1", NULL), SSS_CLI_RUN);
    assert_int_equal(wh[0], 16384);
    assert_int_equal(wh[1], 1);
    /* a side beyond int wrapped to a valid one under sscanf's %d
     * (4294967396 = 2^32 + 100; docs/robustness.md, item 5) */
    const char *bad[] = {"0x10", "10x16385", "10x10x", "10", "10 x10", "axb", "4294967396x100", "100x4294967396",
                         "99999999999999999999x1"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        assert_int_equal(run(&c, "--size", bad[k], NULL), 2);
        char want[128];
        snprintf(want, sizeof want, "sss-test: --size: '%s' must be WxH with each in [1, 16384]\n", bad[k]);
        assert_string_equal(take(err_f), want);
    }
    assert_int_equal(wh[0], 16384);
}

static void choiceStoresValueAndListsChoicesWhenUnknown(void **state)
{
    (void)state;
    int q = -1, g = -1;
    static const char *const kinds[] = {"linear8", "lloyd8", "lloyd4", NULL};
    static const char *const gathers[] = {"direct", "tree", NULL};
    const sss_cli_opt o[] = {
        {.name = "--sh-quant", .kind = SSS_CLI_CHOICE, .dest = &q, .choices = kinds, .values = (const int[]){10, 20, 30}},
        {.name = "--gather", .kind = SSS_CLI_CHOICE, .dest = &g, .choices = gathers},
        {.name = "--interp", .kind = SSS_CLI_CHOICE, .dest = &g, .choices = gathers,
         .msg = "%s: %s '%s' must be direct or tree\n"}};
    sss_cli c = tool(o, 3);
    assert_int_equal(run(&c, "--sh-quant", "lloyd4", "--gather", "tree", NULL), SSS_CLI_RUN);
    assert_int_equal(q, 30);
    assert_int_equal(g, 1);
    assert_int_equal(run(&c, "--sh-quant", "Lloyd8", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --sh-quant: 'Lloyd8' must be linear8, lloyd8 or lloyd4\n");
    assert_int_equal(run(&c, "--gather", "", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --gather: '' must be direct or tree\n");
    assert_int_equal(run(&c, "--interp", "x", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --interp 'x' must be direct or tree\n");
    assert_int_equal(q, 30);
}

static void flagStoresOneOrItsValueAndTakesNoArgument(void **state)
{
    (void)state;
    int json = 0, scatter = 1;
    const char *path = NULL;
    const sss_cli_opt o[] = {{.name = "--json", .kind = SSS_CLI_FLAG, .dest = &json},
                             {.name = "--no-scatter", .kind = SSS_CLI_FLAG, .dest = &scatter, .values = (const int[]){0}}};
    const sss_cli_opt p[] = {{.name = "FILE", .kind = SSS_CLI_STRING, .dest = &path}};
    sss_cli c = tool(o, 2);
    c.pos = p;
    c.npos = 1;
    assert_int_equal(run(&c, "--json", "f.sss", "--no-scatter", NULL), SSS_CLI_RUN);
    assert_int_equal(json, 1);
    assert_int_equal(scatter, 0);
    assert_string_equal(path, "f.sss");
}

/* "map:N" with N in [256, 8192], or one of the names (sss-stat's
 * --image-visibility). */
static int read_map(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    (void)cli;
    (void)opt;
    int *mode = o->dest;
    unsigned n;
    char tail;
    if (!strcmp(text, "rays")) mode[0] = 1;
    else if (sscanf(text, "map:%u%c", &n, &tail) == 1 && n >= 256 && n <= 8192) mode[0] = 2, mode[1] = (int)n;
    else return 0;
    return 1;
}

/* 8 or 16, read first as an integer in [8, 16] (sss-bake's --weight-bits):
 * two messages, the second its own. */
static int read_bits(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    const sss_cli_opt num = {.kind = SSS_CLI_U32, .dest = o->dest, .lo = 8, .hi = 16};
    if (!sss_cli_value(cli, &num, opt, text)) return SSS_CLI_PRINTED;
    uint32_t b = *(uint32_t *)o->dest;
    if (b != 8 && b != 16) return sss_cli_fail(cli, o, "%s: %s: '%s' must be 8 or 16\n", opt, text);
    return 1;
}

static void customReaderFailurePrintsRowMessageUnlessItPrintedItsOwn(void **state)
{
    (void)state;
    int mode[2] = {0, 0}, given = 0;
    uint32_t bits = 0;
    const sss_cli_opt o[] = {
        {.name = "--image-visibility", .kind = SSS_CLI_CUSTOM, .dest = mode, .parse = read_map, .given = &given,
         .msg = "%s: %s '%s' must be rays or map:N (N = 256 ... 8192)\n"},
        {.name = "--weight-bits", .kind = SSS_CLI_CUSTOM, .dest = &bits, .parse = read_bits},
        {.name = "--mode", .kind = SSS_CLI_CUSTOM, .dest = mode, .parse = read_map}};
    sss_cli c = tool(o, 3);
    assert_int_equal(run(&c, "--mode", "x", NULL), 2); /* no msg, nothing printed by the reader */
    assert_string_equal(take(err_f), "sss-test: --mode: 'x' is not a valid value\n");
    assert_int_equal(run(&c, "--image-visibility", "map:512", NULL), SSS_CLI_RUN);
    assert_int_equal(mode[0], 2);
    assert_int_equal(mode[1], 512);
    assert_int_equal(given, 1);
    assert_int_equal(run(&c, "--image-visibility", "map:9000", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --image-visibility 'map:9000' must be rays or map:N (N = 256 ... 8192)\n");
    assert_int_equal(run(&c, "--weight-bits", "12", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --weight-bits: '12' must be 8 or 16\n");
    assert_int_equal(run(&c, "--weight-bits", "17", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --weight-bits: '17' must be an integer in [8, 16]\n");
    assert_int_equal(run(&c, "--weight-bits", "8", NULL), SSS_CLI_RUN);
    assert_int_equal(bits, 8);
}

/* ---- the walk ----------------------------------------------------------- */

static void missingValuePrintsToolRowOrDefaultNeedMessage(void **state)
{
    (void)state;
    const char *s = NULL;
    const sss_cli_opt o[] = {{.name = "--out", .alias = "-o", .kind = SSS_CLI_STRING, .dest = &s},
                             {.name = "--error-images", .kind = SSS_CLI_STRING, .dest = &s, .flags = SSS_CLI_NONEMPTY,
                              .need_msg = "%s: %s needs a directory (see --help)\n"}};
    sss_cli c = tool(o, 2);
    assert_int_equal(run(&c, "-o", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: -o needs a value\n");
    c.need_msg = "%s: %s needs a value (see --help)\n";
    assert_int_equal(run(&c, "--out", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --out needs a value (see --help)\n");
    assert_int_equal(run(&c, "--error-images", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --error-images needs a directory (see --help)\n");
    assert_int_equal(run(&c, "--error-images", "", NULL), 2); /* empty counts as missing */
    assert_string_equal(take(err_f), "sss-test: --error-images needs a directory (see --help)\n");
    assert_null(s);
    assert_int_equal(run(&c, "--out", "", NULL), SSS_CLI_RUN); /* without NONEMPTY "" is a value */
    assert_string_equal(s, "");
}

static void valueStartingWithDashIsTakenAsValue(void **state)
{
    (void)state;
    const char *q = NULL;
    int json = 0;
    const sss_cli_opt o[] = {{.name = "--query", .kind = SSS_CLI_STRING, .dest = &q},
                             {.name = "--json", .kind = SSS_CLI_FLAG, .dest = &json}};
    sss_cli c = tool(o, 2);
    assert_int_equal(run(&c, "--query", "--json", NULL), SSS_CLI_RUN);
    assert_string_equal(q, "--json");
    assert_int_equal(json, 0);
}

static void unknownOptionStopsTheWalkWithItsMessage(void **state)
{
    (void)state;
    int json = 0;
    const sss_cli_opt o[] = {{.name = "--json", .kind = SSS_CLI_FLAG, .dest = &json}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--jsn", "--json", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: unknown option '--jsn' (see --help)\n");
    assert_int_equal(json, 0);
    assert_int_equal(run(&c, "--json=1", NULL), 2); /* no --opt=value */
    assert_string_equal(take(err_f), "sss-test: unknown option '--json=1' (see --help)\n");
    assert_int_equal(run(&c, "--", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: unknown option '--' (see --help)\n");
    c.unknown_msg = "%s: what is %s?\n";
    assert_int_equal(run(&c, "-x", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: what is -x?\n");
}

static void helpPrintsUsageOnOutUnlessAnEarlierArgumentFailed(void **state)
{
    (void)state;
    uint32_t v = 0;
    const sss_cli_opt o[] = {{.name = "--views", .kind = SSS_CLI_U32, .dest = &v, .lo = 1, .hi = 100000}};
    sss_cli c = tool(o, 1);
    c.usage = usage;
    assert_int_equal(run(&c, "--views", "3", "-h", "--views", "0", NULL), 0);
    assert_string_equal(take(out_f), "usage: sss-test [options]\n");
    assert_string_equal(take(err_f), "");
    assert_int_equal(run(&c, "--views", "0", "--help", NULL), 2);
    assert_string_equal(take(out_f), "");
    assert_string_equal(take(err_f), "sss-test: --views: '0' must be an integer in [1, 100000]\n");
    c.usage = NULL; /* no usage: -h is an unknown option */
    assert_int_equal(run(&c, "-h", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: unknown option '-h' (see --help)\n");
}

static void givenFlagIsSetOnlyByItsOptionsAndOnlyOnSuccess(void **state)
{
    (void)state;
    uint32_t order = 3, views = 1;
    int order_given = 0, image_opt = 0, size = 0;
    double exposure = 0;
    const sss_cli_opt o[] = {
        {.name = "--sh-order", .kind = SSS_CLI_U32, .dest = &order, .lo = 0, .hi = 8, .given = &order_given},
        {.name = "--image-size", .kind = SSS_CLI_INT, .dest = &size, .lo = 16, .hi = 4096, .given = &image_opt},
        {.name = "--exposure", .kind = SSS_CLI_DOUBLE, .dest = &exposure, .lo = 0, .hi = 1e308,
         .flags = SSS_CLI_ABOVE_LO, .given = &image_opt},
        {.name = "--views", .kind = SSS_CLI_U32, .dest = &views, .lo = 1, .hi = 100000}};
    sss_cli c = tool(o, 4);
    assert_int_equal(run(&c, "--views", "10", NULL), SSS_CLI_RUN);
    assert_int_equal(order_given, 0);
    assert_int_equal(image_opt, 0);
    assert_int_equal(run(&c, "--image-size", "8", NULL), 2);
    take(err_f);
    assert_int_equal(image_opt, 0);
    assert_int_equal(run(&c, "--exposure", "2", NULL), SSS_CLI_RUN);
    assert_int_equal(image_opt, 1); /* shared by every image option */
    assert_int_equal(run(&c, "--sh-order", "0", NULL), SSS_CLI_RUN);
    assert_int_equal(order_given, 1); /* given even when the value equals the default's */
    assert_int_equal(order, 0);
}

/* ---- positionals -------------------------------------------------------- */

static void positionalsBeyondTheRowsPrintExtraMessageAtOnce(void **state)
{
    (void)state;
    const char *path = NULL;
    uint32_t v = 0;
    const sss_cli_opt o[] = {{.name = "--views", .kind = SSS_CLI_U32, .dest = &v, .lo = 1, .hi = 100000}};
    const sss_cli_opt p[] = {{.name = "FILE.sss", .kind = SSS_CLI_STRING, .dest = &path}};
    sss_cli c = tool(o, 1);
    c.pos = p;
    c.npos = 1;
    c.min_pos = 1;
    c.extra_msg = "%s: unexpected argument '%s'\n";
    c.missing_msg = "%s: missing FILE.sss (see --help)\n";
    assert_int_equal(run(&c, "a.sss", "b.sss", "--views", "0", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: unexpected argument 'b.sss'\n");
    assert_int_equal(run(&c, "--views", "2", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: missing FILE.sss (see --help)\n");
    assert_int_equal(run(&c, "-", NULL), SSS_CLI_RUN); /* "-" alone is a positional */
    assert_string_equal(path, "-");
}

static void countErrorsWithoutMessagePrintUsageOnErr(void **state)
{
    (void)state;
    const char *kind = NULL, *out = NULL;
    int res = -1;
    double size = 1.0;
    int n = 0;
    const sss_cli_opt p[] = {
        {.name = "KIND", .kind = SSS_CLI_STRING, .dest = &kind},
        {.name = "RES", .kind = SSS_CLI_INT, .dest = &res, .lo = 0, .hi = 100000, .flags = SSS_CLI_LAX,
         .msg = "%s: %s '%s' must be an integer in [%d, %d]\n"},
        {.name = "OUT", .kind = SSS_CLI_STRING, .dest = &out},
        {.name = "SIZE", .kind = SSS_CLI_DOUBLE, .dest = &size, .lo = 0, .hi = INFINITY,
         .flags = SSS_CLI_ABOVE_LO | SSS_CLI_LAX, .msg = "%s: %s '%s' must be a number > 0\n"}};
    sss_cli c = tool(NULL, 0);
    c.pos = p;
    c.npos = 4;
    c.min_pos = 3;
    c.npos_given = &n;
    c.usage = usage;
    c.flags = SSS_CLI_NO_OPTIONS;
    assert_int_equal(run(&c, "-h", NULL), 2); /* no options: -h is KIND, and one is too few */
    assert_string_equal(take(err_f), "usage: sss-test [options]\n");
    assert_string_equal(take(out_f), "");
    assert_int_equal(run(&c, "sphere", "bad", "o.ply", "1", "extra", NULL), 2); /* count before value */
    assert_string_equal(take(err_f), "usage: sss-test [options]\n");
    assert_int_equal(run(&c, "sphere", "-1", "o.ply", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: RES '-1' must be an integer in [0, 100000]\n");
    assert_int_equal(run(&c, "sphere", "2", "o.ply", "-0.5", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: SIZE '-0.5' must be a number > 0\n");
    assert_int_equal(run(&c, "-x", "3", "--o.ply", NULL), SSS_CLI_RUN);
    assert_string_equal(kind, "-x");
    assert_int_equal(res, 3);
    assert_string_equal(out, "--o.ply");
    assert_true(size == 1.0);
    assert_int_equal(n, 3);
}

static void repeatedPositionalFillsArrayUpToMax(void **state)
{
    (void)state;
    const char *first = NULL, *rest[3] = {NULL, NULL, NULL};
    int json = 0, n = 0;
    const sss_cli_opt o[] = {{.name = "--json", .kind = SSS_CLI_FLAG, .dest = &json}};
    const sss_cli_opt p[] = {{.name = "OUT", .kind = SSS_CLI_STRING, .dest = &first},
                             {.name = "IN", .kind = SSS_CLI_STRING, .dest = rest, .flags = SSS_CLI_REPEAT}};
    sss_cli c = tool(o, 1);
    c.pos = p;
    c.npos = 2;
    c.max_pos = 4;
    c.npos_given = &n;
    assert_int_equal(run(&c, "o", "a", "--json", "b", "c", NULL), SSS_CLI_RUN);
    assert_int_equal(n, 4);
    assert_string_equal(first, "o");
    assert_string_equal(rest[0], "a");
    assert_string_equal(rest[1], "b");
    assert_string_equal(rest[2], "c");
    assert_int_equal(json, 1);
    assert_int_equal(run(&c, "o", "a", "b", "c", "d", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: unexpected argument 'd'\n"); /* no usage, no extra_msg */
}

static void repeatedOptionFillsArrayAndRefusesOneTooMany(void **state)
{
    (void)state;
    double l[2][3] = {{9, 9, 9}, {9, 9, 9}};
    int n = -1;
    const sss_cli_opt o[] = {{.name = "--light", .kind = SSS_CLI_TRIPLE, .dest = l, .flags = SSS_CLI_REPEAT | SSS_CLI_NONZERO,
                              .count = &n, .max = 2}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, NULL), SSS_CLI_RUN);
    assert_int_equal(n, 0); /* the parse counts from 0 */
    assert_int_equal(run(&c, "--light", "1,0,0", "--light", "0,2,0", NULL), SSS_CLI_RUN);
    assert_int_equal(n, 2);
    assert_true(l[0][0] == 1 && l[0][1] == 0 && l[1][1] == 2 && l[1][2] == 0);
    assert_int_equal(run(&c, "--light", "0,0,3", "--light", "0,0,4", "--light", "0,0,5", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --light: '0,0,5': at most 2 may be given\n");
    assert_true(l[1][2] == 4); /* the one too many is not read */
    /* each value is still checked as its kind says */
    assert_int_equal(run(&c, "--light", "0,0,0", NULL), 2);
    assert_string_equal(take(err_f), "sss-test: --light: '0,0,0' is not a direction\n");
    assert_int_equal(n, 0);
}

static void pointReadsPositionAndOptionalPositiveIntensity(void **state)
{
    (void)state;
    double p[4] = {9, 9, 9, 9};
    const sss_cli_opt o[] = {{.name = "--point-light", .kind = SSS_CLI_POINT, .dest = p}};
    sss_cli c = tool(o, 1);
    assert_int_equal(run(&c, "--point-light", "1,-2,3e1", NULL), SSS_CLI_RUN);
    assert_true(p[0] == 1 && p[1] == -2 && p[2] == 30 && p[3] == 0); /* no intensity: 0, the tool's default */
    assert_int_equal(run(&c, "--point-light", "0,0,0,2.5", NULL), SSS_CLI_RUN);
    assert_true(p[2] == 0 && p[3] == 2.5);
    const char *bad[] = {"1,2", "1,2,3,", "1,2,3,0", "1,2,3,-1", "1,2,3,nan", "nan,0,0", "1,2,3,4,5", "1,2,inf"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        assert_int_equal(run(&c, "--point-light", bad[k], NULL), 2);
        char want[128];
        snprintf(want, sizeof want, "sss-test: --point-light: '%s' must be X,Y,Z or X,Y,Z,I with I > 0\n", bad[k]);
        assert_string_equal(take(err_f), want);
    }
    assert_true(p[3] == 2.5);
}

/* ---- single values and helpers ------------------------------------------ */

/* These print on stderr itself: file descriptor 2 is pointed at err_f
 * for the calls. */
static int saved_fd = -1;
static void stderr_to_err_f(void)
{
    fflush(stderr);
    saved_fd = dup(2);
    assert_true(saved_fd >= 0 && dup2(fileno(err_f), 2) == 2);
}
static void stderr_back(void)
{
    fflush(stderr);
    assert_int_equal(dup2(saved_fd, 2), 2);
    close(saved_fd);
    fseek(err_f, 0, SEEK_END); /* the descriptor moved; the stream reads from its end */
}

static void singleValueParsersPrintOnStderrAndWriteOnlyOnSuccess(void **state)
{
    (void)state;
    double d = 3, t[3] = {1, 2, 3};
    uint32_t u = 4;
    assert_int_equal(sss_cli_parse_double("sss-test", "--eta", "1.4", 1e-3, 1e3, &d), 1);
    assert_true(d == 1.4);
    assert_int_equal(sss_cli_parse_u32("sss-test", "--dirs", "200", 1, 100000, &u), 1);
    assert_true(u == 200);
    assert_int_equal(sss_cli_parse_triple("sss-test", "--sigma-s", "1,1.5,2", t), 1);
    assert_true(t[0] == 1 && t[1] == 1.5 && t[2] == 2);
    stderr_to_err_f();
    int rd = sss_cli_parse_double("sss-test", "--eta", "1e4", 1e-3, 1e3, &d);
    int ru = sss_cli_parse_u32("sss-test", "--dirs", "0", 1, 100000, &u);
    int rt = sss_cli_parse_triple("sss-test", "--sigma-s", "1,2", t);
    stderr_back();
    assert_int_equal(rd, 0);
    assert_int_equal(ru, 0);
    assert_int_equal(rt, 0);
    assert_string_equal(take(err_f), "sss-test: --eta: '1e4' must be a number in [0.001, 1000]\n"
                                     "sss-test: --dirs: '0' must be an integer in [1, 100000]\n"
                                     "sss-test: --sigma-s: '1,2' must be three numbers X,Y,Z\n");
    assert_true(d == 1.4 && u == 200 && t[2] == 2);
}

static void basenameIsTheTailAfterTheLastSlash(void **state)
{
    (void)state;
    const char *p = "/a/b/bunny.ply";
    assert_ptr_equal(sss_cli_basename(p), p + 5);
    assert_string_equal(sss_cli_basename("bunny.ply"), "bunny.ply");
    assert_string_equal(sss_cli_basename("dir/"), "");
    assert_true(sss_cli_peak_rss_mib() > 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(doubleAtBothLimitsIsAccepted, setup, teardown),
        cmocka_unit_test_setup_teardown(doubleBeyondLimitPrintsRangeMessageAndKeepsDest, setup, teardown),
        cmocka_unit_test_setup_teardown(doubleRefusesTrailingTextNanInfinityAndUnderflow, setup, teardown),
        cmocka_unit_test_setup_teardown(doubleAboveLoRefusesLoAndTakesOwnMessage, setup, teardown),
        cmocka_unit_test_setup_teardown(laxDoubleTakesUnderflowAndInfinityWithinRange, setup, teardown),
        cmocka_unit_test_setup_teardown(u32AtLimitsIsAcceptedAndBeyondRefused, setup, teardown),
        cmocka_unit_test_setup_teardown(intStoresIntAndPrintsRangeWithD, setup, teardown),
        cmocka_unit_test_setup_teardown(laxIntReadsEmptyAndMinusZeroAsZero, setup, teardown),
        cmocka_unit_test_setup_teardown(tripleReadsThreeNumbersAndRefusesOtherShapes, setup, teardown),
        cmocka_unit_test_setup_teardown(nonzeroTripleRefusesZeroVectorWithSecondMessage, setup, teardown),
        cmocka_unit_test_setup_teardown(sizeReadsWxHWithinRange, setup, teardown),
        cmocka_unit_test_setup_teardown(choiceStoresValueAndListsChoicesWhenUnknown, setup, teardown),
        cmocka_unit_test_setup_teardown(flagStoresOneOrItsValueAndTakesNoArgument, setup, teardown),
        cmocka_unit_test_setup_teardown(customReaderFailurePrintsRowMessageUnlessItPrintedItsOwn, setup, teardown),
        cmocka_unit_test_setup_teardown(missingValuePrintsToolRowOrDefaultNeedMessage, setup, teardown),
        cmocka_unit_test_setup_teardown(valueStartingWithDashIsTakenAsValue, setup, teardown),
        cmocka_unit_test_setup_teardown(unknownOptionStopsTheWalkWithItsMessage, setup, teardown),
        cmocka_unit_test_setup_teardown(helpPrintsUsageOnOutUnlessAnEarlierArgumentFailed, setup, teardown),
        cmocka_unit_test_setup_teardown(givenFlagIsSetOnlyByItsOptionsAndOnlyOnSuccess, setup, teardown),
        cmocka_unit_test_setup_teardown(positionalsBeyondTheRowsPrintExtraMessageAtOnce, setup, teardown),
        cmocka_unit_test_setup_teardown(countErrorsWithoutMessagePrintUsageOnErr, setup, teardown),
        cmocka_unit_test_setup_teardown(repeatedPositionalFillsArrayUpToMax, setup, teardown),
        cmocka_unit_test_setup_teardown(repeatedOptionFillsArrayAndRefusesOneTooMany, setup, teardown),
        cmocka_unit_test_setup_teardown(pointReadsPositionAndOptionalPositiveIntensity, setup, teardown),
        cmocka_unit_test_setup_teardown(singleValueParsersPrintOnStderrAndWriteOnlyOnSuccess, setup, teardown),
        cmocka_unit_test_setup_teardown(basenameIsTheTailAfterTheLastSlash, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
