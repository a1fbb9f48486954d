/* sss/memory.h: how much memory a step may still take, for the plans made
 * before anything large is allocated (docs/robustness.md, "Memory"): the
 * bake, the scene bake, the exact evaluator of sss-stat and the probe
 * reader all refuse with one line, before allocating, when their estimate
 * exceeds it. The limit a caller passes comes from its options (the tools
 * fill it from SSS_MEMORY_LIMIT_MB; the libraries read no environment). */
#ifndef SSS_MEMORY_H
#define SSS_MEMORY_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bytes this process may still use: MemAvailable from /proc/meminfo
 * (Linux), else all physical memory, lowered to limit when limit is not 0;
 * 0 when nothing is known and no limit is given (no limit). */
uint64_t sss_memory_available(uint64_t limit);

#ifdef __cplusplus
}
#endif
#endif
