/* sss/cli.h: the command-line tools' option parser (sss-bake, sss-stat,
 * sss-view, sss-genmesh), in the spirit of pbrt's ParseArg: a tool describes
 * each option by one row of a table (name, kind, where the value goes, its
 * range or choices, the message it prints), one call walks argv and fills
 * the tool's own options struct, and the tool then checks the combinations
 * and runs. Pure C11 and libc; not part of libsss, which engines link: only
 * the tools link this library (CMake target sss_cli).
 *
 * The messages are the tools' own, byte for byte: every row may carry the
 * printf format the tool prints, and the defaults below are the formats
 * sss-bake and sss-stat have always printed. A format receives its arguments
 * in a fixed order and may stop early (printf ignores arguments it does not
 * use), never skip one:
 *
 *   missing value (need_msg) ......... tool, option
 *   unknown option (unknown_msg) ..... tool, argument
 *   extra positional (extra_msg) ..... tool, argument
 *   too few positionals (missing_msg)  tool
 *   bad value (msg, msg2) ............ tool, option, value text, lo, hi
 *
 * "option" is the text as typed ("-o" or "--out"); for a positional it is the
 * row's name ("RES"). lo and hi are passed as the kind reads them: unsigned
 * for SSS_CLI_U32, int for SSS_CLI_INT and SSS_CLI_SIZE, double for every
 * other kind, so "%u", "%d" and "%g" respectively.
 *
 * Nothing here allocates or keeps state: a string value is a pointer into
 * argv, which outlives main's use of it. */
#ifndef SSS_CLI_H
#define SSS_CLI_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What an option's value is and where it goes (the row's dest). */
typedef enum sss_cli_kind {
    /* No value. Stores 1 in *(int *)dest, or values[0] when values is set
     * (sss-view's --no-scatter stores 0); dest may be NULL when the given
     * flag is all the tool needs. */
    SSS_CLI_FLAG,
    /* *(const char **)dest = the text (a pointer into argv). With
     * SSS_CLI_NONEMPTY an empty text counts as no value (need message). */
    SSS_CLI_STRING,
    /* *(double *)dest: strtod's reading of the whole text, errno clear,
     * finite, in [lo, hi] ((lo, hi] with SSS_CLI_ABOVE_LO).
     * Default message: "%s: %s: '%s' must be a number in [%g, %g]\n". */
    SSS_CLI_DOUBLE,
    /* *(uint32_t *)dest: a decimal integer in [lo, hi], 0 <= lo <= hi <=
     * UINT32_MAX, read by strtoull: leading blanks and '+' allowed, a
     * leading '-' refused, errno clear, nothing after the digits.
     * Default message: "%s: %s: '%s' must be an integer in [%u, %u]\n". */
    SSS_CLI_U32,
    /* *(int *)dest: read as SSS_CLI_U32, 0 <= lo <= hi <= INT_MAX (with
     * SSS_CLI_LAX lo may be negative).
     * Default message: "%s: %s: '%s' must be an integer in [%d, %d]\n". */
    SSS_CLI_INT,
    /* ((double *)dest)[0..2]: "X,Y,Z", three numbers read as SSS_CLI_DOUBLE
     * (no range) with exactly one comma between them; with SSS_CLI_NONZERO
     * a direction: its squared length a positive normal double (not all
     * zero, not so small or large that normalising it fails).
     * Default messages: "%s: %s: '%s' must be three numbers X,Y,Z\n";
     * all zero (msg2): "%s: %s: '%s' is not a direction\n". */
    SSS_CLI_TRIPLE,
    /* ((double *)dest)[0..3]: "X,Y,Z" or "X,Y,Z,I", a position and an
     * optional intensity (sss-view's and sss-bake's --point-light): the
     * numbers read as SSS_CLI_TRIPLE's, I a finite number > 0 when given,
     * 0 when not (the tool's default then).
     * Default message: "%s: %s: '%s' must be X,Y,Z or X,Y,Z,I with I > 0\n". */
    SSS_CLI_POINT,
    /* ((int *)dest)[0..1] = W, H: "WxH" as sscanf's "%dx%d" reads it (blanks
     * before W and H), each in [lo, hi] without wrapping, nothing after H.
     * Default message: "%s: %s: '%s' must be WxH with each in [%d, %d]\n". */
    SSS_CLI_SIZE,
    /* *(int *)dest = values[k] (or k when values is NULL) for the text equal
     * to choices[k]; choices is NULL-terminated.
     * Default message: "%s: %s: '%s' must be A, B or C\n" with the choices
     * listed in order (sss-bake's and sss-view's wording). */
    SSS_CLI_CHOICE,
    /* Anything else (sss-stat's "map:N", sss-bake's --weight-bits 8|16):
     * the row's parse callback reads the text into dest (sss_cli_parse_fn).
     * Default message: "%s: %s: '%s' is not a valid value\n". */
    SSS_CLI_CUSTOM
} sss_cli_kind;

/* sss_cli_opt.flags */
enum {
    /* SSS_CLI_DOUBLE: the value must be > lo, not >= lo ("a number > 0"). */
    SSS_CLI_ABOVE_LO = 1u << 0,
    /* SSS_CLI_DOUBLE, SSS_CLI_INT, SSS_CLI_U32: the C library's reading is
     * the whole test, as sss-genmesh's RES and SIZE and sss-stat's
     * --exposure have always read numbers: strtod / strtoll (a sign allowed)
     * decide what the text says, errno (ERANGE) is no error, an infinity is a
     * number like any other, an empty text reads as 0; only characters after
     * the number and the range refuse it. */
    SSS_CLI_LAX = 1u << 1,
    /* SSS_CLI_TRIPLE: no direction (all zero, or a length that underflows or
     * overflows when squared) is refused with msg2. */
    SSS_CLI_NONZERO = 1u << 2,
    /* An option whose value is the empty string has no value (need message):
     * sss-stat's --error-images "" is a missing directory. */
    SSS_CLI_NONEMPTY = 1u << 3,
    /* The last positional row only: it takes this and every further
     * positional up to sss_cli.max_pos; dest is then an array with one element
     * per positional it takes (const char * for a string, double for a number,
     * ...). A SSS_CLI_CUSTOM row's dest is not advanced.
     * An option row: the option may be given up to `max` times (a light per
     * --light); dest is an array of max elements, the k-th value given goes
     * into element k, and *count holds how many were given (the parse sets
     * it to 0 first). One more than max is refused with
     * "%s: %s: '%s': at most %d may be given\n" (tool, option, value, max),
     * the value not read. Not with SSS_CLI_CUSTOM. */
    SSS_CLI_REPEAT = 1u << 4
};

/* sss_cli.flags */
enum {
    /* No option syntax at all: every argument is a positional, "-h" and "-1"
     * included (sss-genmesh KIND RES OUT [SIZE]: RES "-1" is a bad RES). */
    SSS_CLI_NO_OPTIONS = 1u << 0
};

/* sss_cli_parse's result when the tool is to run; any other result is the
 * exit status to return at once (0 after -h/--help, 2 after a message). */
#define SSS_CLI_RUN (-1)

/* A custom reader's result when it failed and has printed its message(s)
 * itself (sss_cli_fail, or a sss_cli_value that failed). */
#define SSS_CLI_PRINTED (-1)

/* Number of rows of a table (an array, not a pointer). */
#define SSS_CLI_COUNT(table) (sizeof(table) / sizeof((table)[0]))

typedef struct sss_cli sss_cli;
typedef struct sss_cli_opt sss_cli_opt;

/* A SSS_CLI_CUSTOM row's reader: reads `text`, the value of option `opt`
 * (as typed, or the positional's name), into o->dest. Returns 1 on success;
 * 0 on failure, and the parser prints the row's msg (or the default);
 * SSS_CLI_PRINTED on a failure it has reported itself (two messages, as
 * sss-bake's --weight-bits prints). So no failure goes unreported unless the
 * reader says it printed. */
typedef int (*sss_cli_parse_fn)(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text);

/* One option (or one positional) of a tool. Unused fields stay zero, so
 * rows are written with designated initializers. */
struct sss_cli_opt {
    const char *name;           /* "--views"; a positional's name in messages ("RES") */
    const char *alias;          /* a second spelling ("-o" for "--out"), or NULL */
    sss_cli_kind kind;
    void *dest;                 /* where the value goes: its type is the kind's */
    double lo, hi;              /* the range of SSS_CLI_DOUBLE, _U32, _INT, _SIZE */
    const char *const *choices; /* SSS_CLI_CHOICE: the accepted texts, NULL-terminated */
    const int *values;          /* SSS_CLI_CHOICE: what each stores (NULL: its index);
                                   SSS_CLI_FLAG: values[0] is stored instead of 1 */
    int *given;                 /* set to 1 once the option is read, or NULL. Several rows
                                   may share one (sss-stat's image options; a preset that
                                   fills only what was not given) */
    unsigned flags;             /* SSS_CLI_ABOVE_LO, _LAX, _NONZERO, _NONEMPTY, _REPEAT */
    sss_cli_parse_fn parse;     /* SSS_CLI_CUSTOM */
    const char *msg;            /* bad value; NULL: the kind's default */
    const char *msg2;           /* SSS_CLI_TRIPLE with SSS_CLI_NONZERO: all zero; NULL: default */
    const char *need_msg;       /* missing value; NULL: the tool's (sss_cli.need_msg) */
    int *count;                 /* an option with SSS_CLI_REPEAT: how many values were read */
    int max;                    /* an option with SSS_CLI_REPEAT: the most it takes (dest's length) */
};

/* A tool's command line. */
struct sss_cli {
    const char *tool;           /* "sss-stat": the first argument of every message */
    const sss_cli_opt *opts;    /* the options, in any order */
    size_t nopts;
    const sss_cli_opt *pos;     /* the positionals, in order (see SSS_CLI_REPEAT) */
    size_t npos;
    int min_pos;                /* fewer positionals: missing_msg */
    int max_pos;                /* more positionals: extra_msg; 0: npos (one per row); more
                                   than npos only through a last row with SSS_CLI_REPEAT */
    int *npos_given;            /* out: how many positionals were given, or NULL */
    /* Prints the usage text on f. -h and --help print it on `out` (unless
     * SSS_CLI_NO_OPTIONS); a NULL extra_msg or missing_msg prints it on `err`. */
    void (*usage)(FILE *f);
    const char *need_msg;       /* NULL: "%s: %s needs a value\n" */
    const char *unknown_msg;    /* NULL: "%s: unknown option '%s' (see --help)\n" */
    const char *extra_msg;      /* NULL: the usage text on err (without usage:
                                   "%s: unexpected argument '%s'\n") */
    const char *missing_msg;    /* NULL: the usage text on err (without usage:
                                   "%s: missing argument (see --help)\n") */
    unsigned flags;             /* SSS_CLI_NO_OPTIONS */
    FILE *out, *err;            /* the usage of -h/--help, the messages; NULL: stdout, stderr */
};

/* Walks argv[1 .. argc-1] once, left to right, as the tools always have:
 * -h/--help prints the usage on out and stops (exit status 0); an argument
 * equal to a row's name or alias is that option, and one that takes a value
 * takes the next argument whatever it looks like ("--query -1"); any other
 * argument that starts with '-' and is not "-" itself is an unknown option;
 * the rest are positionals, counted as they come (one too many: extra_msg).
 * The first error prints its one message on err and stops (exit status 2);
 * a value that fails leaves its dest and given flag untouched (a custom
 * reader answers for its own dest). There is no
 * "--opt=value" and no "--": neither was ever accepted.
 * After the walk: fewer than min_pos positionals prints missing_msg; then the
 * positionals are read into their rows in order (so a wrong count is
 * reported before a bad value, as sss-genmesh does).
 * Returns SSS_CLI_RUN when the tool is to run, else the exit status. The
 * combinations of options (one excludes another, one needs another) are the
 * tool's to check afterwards, from its given flags. */
int sss_cli_parse(const sss_cli *cli, int argc, char *const argv[]);

/* Reads one value `text` of option `opt` (as typed) as row o describes,
 * into o->dest, and sets o->given. Returns 1, or 0 after printing the row's
 * message on cli's err. For SSS_CLI_FLAG text is ignored. This is the step
 * sss_cli_parse takes for every value; a SSS_CLI_CUSTOM reader uses it to
 * read a number it then checks further (a temporary row of its own). */
int sss_cli_value(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text);

/* Prints fmt (NULL: the kind's default bad-value message) with the
 * arguments of a bad value (tool, opt, text, lo, hi) on cli's err. Returns
 * SSS_CLI_PRINTED, so a custom reader can `return sss_cli_fail(...)`. */
int sss_cli_fail(const sss_cli *cli, const sss_cli_opt *o, const char *fmt, const char *opt, const char *text);

/* The parsers of a single value outside a table, for tools that read one
 * by hand. Each returns 1 on success, 0 after printing the kind's default
 * message on stderr:
 *   double: "TOOL: OPT: 'S' must be a number in [LO, HI]"   (%g), as SSS_CLI_DOUBLE
 *   u32:    "TOOL: OPT: 'S' must be an integer in [LO, HI]" (%u), as SSS_CLI_U32
 *   triple: "TOOL: OPT: 'S' must be three numbers X,Y,Z",     as SSS_CLI_TRIPLE
 *           (zero allowed).
 * *out is written only on success. */
int sss_cli_parse_double(const char *tool, const char *opt, const char *s, double lo, double hi, double *out);
int sss_cli_parse_u32(const char *tool, const char *opt, const char *s, uint32_t lo, uint32_t hi, uint32_t *out);
int sss_cli_parse_triple(const char *tool, const char *opt, const char *s, double out[3]);

/* Peak resident memory of this process in MiB (getrusage; 0 if that fails). */
/* fprintf for the tools' messages (README.md, "Errors": one line each):
 * every control character of the formatted text, except a last '\n', is
 * written as '?', so that a file name holding a newline or an escape
 * sequence cannot split a message or drive the terminal. Returns
 * fprintf's count. */
int sss_cli_printf(FILE *f, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* s copied into buf (n bytes, truncated) with its control characters shown
 * as '?': a path for a line of text the tool prints itself. Returns buf. */
char *sss_cli_shown(const char *s, char *buf, size_t n);

/* The memory limit a tool passes to the plans of the libraries
 * (sss/memory.h): SSS_MEMORY_LIMIT_MB, in bytes (a share of a machine used
 * by others; the tests use it to exercise the refusals); 0 when unset or not
 * a positive integer. */
uint64_t sss_cli_memory_limit(void);

double sss_cli_peak_rss_mib(void);

/* The part of path after its last '/' (a pointer into path, not a copy). */
const char *sss_cli_basename(const char *path);

#ifdef __cplusplus
}
#endif
#endif
