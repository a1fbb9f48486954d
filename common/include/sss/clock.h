/* sss/clock.h: the clocks the tools and benchmarks time phases with. */
#ifndef SSS_CLOCK_H
#define SSS_CLOCK_H

#ifdef __cplusplus
extern "C" {
#endif

/* Monotonic wall-clock seconds (an arbitrary origin). */
double sss_now(void);

/* CPU seconds of the calling thread: what the gather's phase timings
 * count, so that a machine shared with other jobs (time slices taken away)
 * does not inflate them (monotonic seconds where unavailable). */
double sss_thread_cpu(void);

#ifdef __cplusplus
}
#endif
#endif
