/* progress.h: one progress bar with ETA on stderr (only when stderr is a
 * terminal and the bar was enabled). Ticks are thread-safe; only the thread
 * that crosses a 0.5 s boundary redraws. */
#ifndef SSS_PROGRESS_H
#define SSS_PROGRESS_H

#include <stdint.h>

void sss_progress_enable(int on);
void sss_progress_begin(const char *label, uint64_t total);
void sss_progress_tick(uint64_t n);
void sss_progress_end(void);
double sss_now(void); /* monotonic seconds */

#endif
