/* progress.c: progress bar with ETA on stderr (see progress.h). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime under -std=c11 */
#include "progress.h"

#include <stdatomic.h>
#include <stdio.h>
#include <time.h>
#include <unistd.h>

static int enabled;
static const char *label_;
static uint64_t total_;
static _Atomic uint64_t done_;
static _Atomic int64_t next_draw_ms;
static double t0;

double sss_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void sss_progress_enable(int on) { enabled = on && isatty(STDERR_FILENO); }

static void draw(double now)
{
    uint64_t d = atomic_load(&done_);
    double f = total_ ? (double)d / (double)total_ : 1.0;
    if (f > 1.0) f = 1.0;
    double el = now - t0, eta = f > 0 ? el * (1.0 - f) / f : 0.0;
    int w = 30, k = (int)(f * w);
    char bar[32];
    for (int i = 0; i < w; i++) bar[i] = i < k ? '#' : '.';
    bar[w] = 0;
    fprintf(stderr, "\r%-14s [%s] %5.1f%%  %6.1fs elapsed  ETA %6.1fs ", label_, bar, 100.0 * f, el, eta);
    fflush(stderr);
}

void sss_progress_begin(const char *label, uint64_t total)
{
    label_ = label;
    total_ = total;
    atomic_store(&done_, 0);
    t0 = sss_now();
    atomic_store(&next_draw_ms, (int64_t)(t0 * 1000.0) + 500);
    if (enabled) draw(t0);
}

void sss_progress_tick(uint64_t n)
{
    atomic_fetch_add(&done_, n);
    if (!enabled) return;
    double now = sss_now();
    int64_t ms = (int64_t)(now * 1000.0), next = atomic_load(&next_draw_ms);
    if (ms >= next && atomic_compare_exchange_strong(&next_draw_ms, &next, ms + 500)) draw(now);
}

void sss_progress_end(void)
{
    if (!enabled) return;
    atomic_store(&done_, total_);
    draw(sss_now());
    fputc('\n', stderr);
}
