/* clock.c: sss/clock.h. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime under -std=c11 */
#include "sss/clock.h"

#include <time.h>

double sss_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double sss_thread_cpu(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return sss_now();
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
