/* progress.h: one progress bar with ETA on stderr (only when stderr is a
 * terminal and the bar was enabled). Ticks are thread-safe; only the thread
 * that crosses a redraw boundary redraws.
 *
 * With a log file (sss_bake_options.progress_log, which sss-bake takes
 * from SSS_PROGRESS_LOG; progress enabled, i.e. not -q, and on MPI rank 0
 * only), every redraw is also appended to it as one line "LABEL<TAB>FRACTION<TAB>ELAPSED_S<TAB>ETA_S", the last
 * line of a phase ending in "<TAB>end": what the bar shows, for scripts and
 * tests (tests/integration/cli_progress.sh). FRACTION is done/total,
 * unclamped; ETA = elapsed × (1 − f)/f, so it is as good as the ticks are
 * proportional to the time the work takes (the gather ticks each block's
 * estimated work, sss_gather_block_work). */
#ifndef SSS_PROGRESS_H
#define SSS_PROGRESS_H

#include <stdint.h>
#include "sss/clock.h" /* sss_now, sss_thread_cpu: the phases' timers */

/* on: draw the bar when stderr is a terminal; log_path (may be NULL): the
 * log above, opened for appending (an unwritable one is no log). */
void sss_progress_enable(int on, const char *log_path);
int sss_progress_active(void); /* a bar or a log is being drawn */
void sss_progress_begin(const char *label, uint64_t total); /* label is copied */
void sss_progress_tick(uint64_t n);
void sss_progress_end(void);

#endif
