/* memory.c: the memory a plan may count on (sss/memory.h). */
#define _POSIX_C_SOURCE 200809L
#include "sss/memory.h"

#include <stdio.h>
#include <unistd.h>

static uint64_t memory_available_system(void)
{
    FILE *f = fopen("/proc/meminfo", "r");
    if (f) {
        char line[256];
        unsigned long long kb;
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "MemAvailable: %llu kB", &kb) == 1) {
                fclose(f);
                return (uint64_t)kb * 1024u;
            }
        fclose(f);
    }
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    return pages > 0 && size > 0 ? (uint64_t)pages * (uint64_t)size : 0;
}

uint64_t sss_memory_available(uint64_t limit)
{
    uint64_t sys = memory_available_system();
    if (limit && (!sys || limit < sys)) sys = limit;
    return sys;
}
