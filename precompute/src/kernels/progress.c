/* progress.c: progress bar with ETA on stderr, and the same figures as
 * lines in a log file (see progress.h). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime under -std=c11 */
#include "kernels/progress.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

static int bar;     /* draw the bar on stderr (a terminal) */
static FILE *logf_; /* the log file, if one was given */
static char label_[48];
static uint64_t total_;
static _Atomic uint64_t done_;
static _Atomic int64_t next_draw_ms;
static atomic_flag drawing = ATOMIC_FLAG_INIT;
static double t0;

void sss_progress_enable(int on, const char *log_path)
{
    bar = on && isatty(STDERR_FILENO);
    const char *path = on ? log_path : NULL;
    if (logf_ && !(path && *path)) {
        fclose(logf_);
        logf_ = NULL;
    }
    if (!logf_ && path && *path) logf_ = fopen(path, "a"); /* unwritable: no log, the bake goes on */
}

int sss_progress_active(void) { return bar || logf_; }

/* Redraw interval: the bar twice a second; the log ten times, so that a
 * phase of a few seconds leaves enough lines to check the ETA against. */
static int64_t interval_ms(void) { return logf_ ? 100 : 500; }

/* One reading of the counter, drawn and logged. Callers hold `drawing`,
 * so readings are printed in the order they were taken: since the counter
 * only grows, the fractions printed never go back. */
static void draw(double now, int last)
{
    uint64_t d = atomic_load(&done_);
    double f = total_ ? (double)d / (double)total_ : 1.0;
    double el = now - t0, eta = f > 0 ? el * (1.0 - f) / f : 0.0;
    if (eta < 0) eta = 0;
    if (logf_) {
        /* the fraction unclamped: a phase whose ticks overshoot their
         * total shows it here (tests/integration/cli_progress.sh) */
        fprintf(logf_, "%s\t%.6f\t%.3f\t%.3f%s\n", label_, f, el, eta, last ? "\tend" : "");
        fflush(logf_);
    }
    if (!bar) return;
    if (f > 1.0) f = 1.0;
    int w = 30, k = (int)(f * w);
    char b[32];
    for (int i = 0; i < w; i++) b[i] = i < k ? '#' : '.';
    b[w] = 0;
    fprintf(stderr, "\r%-16s [%s] %5.1f%%  %6.1fs elapsed  ETA %6.1fs ", label_, b, 100.0 * f, el, eta);
    fflush(stderr);
}

void sss_progress_begin(const char *label, uint64_t total)
{
    snprintf(label_, sizeof label_, "%s", label);
    total_ = total;
    atomic_store(&done_, 0);
    t0 = sss_now();
    atomic_store(&next_draw_ms, (int64_t)(t0 * 1000.0) + interval_ms());
    if (sss_progress_active()) draw(t0, 0);
}

void sss_progress_tick(uint64_t n)
{
    atomic_fetch_add(&done_, n);
    if (!sss_progress_active()) return;
    double now = sss_now();
    int64_t ms = (int64_t)(now * 1000.0), next = atomic_load(&next_draw_ms);
    if (ms >= next && atomic_compare_exchange_strong(&next_draw_ms, &next, ms + interval_ms()) &&
        !atomic_flag_test_and_set(&drawing)) {
        draw(now, 0);
        atomic_flag_clear(&drawing);
    }
}

void sss_progress_end(void)
{
    if (!sss_progress_active()) return;
    /* the counter as it stands (all work ticked: 100 %; an interrupted
     * phase stops short), not forced to the total */
    while (atomic_flag_test_and_set(&drawing)) {
    }
    draw(sss_now(), 1);
    atomic_flag_clear(&drawing);
    if (bar) fputc('\n', stderr);
}
