/* sss/depthmap.h: a layer's depth map on disk (docs/layers.md §3): grey
 * PNG files read into and written from sss_depth_image. Part of
 * libsss_bake's input stage (input/depthmap.c, over libpng); the bake
 * evaluates the maps per vertex (sss/layer_depths.h). */
#ifndef SSS_DEPTHMAP_H
#define SSS_DEPTHMAP_H

#include "sss/layer_depth.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The largest depth map read: 2²⁶ samples (a 8192 × 8192 map). */
#define SSS_DEPTH_MAP_MAX_SAMPLES ((uint64_t)1 << 26)

/* Reads an 8- or 16-bit grey PNG (colour type 0, any interlace) into *im,
 * each sample over its largest value (255 or 65535). One line naming the
 * file otherwise: missing or unreadable, not a PNG, another colour type
 * or bit depth (named), more than SSS_DEPTH_MAP_MAX_SAMPLES samples, or
 * libpng's own complaint about damaged data. */
sss_result sss_depth_map_read(const char *path, sss_depth_image *im, sss_error *err);

/* Writes im as a grey PNG of 8 or 16 bits per sample, each value in
 * [0, 1] (clamped) times 255 or 65535, rounded; atomically, to a path the
 * output policy allows (sss/fileio.h). The tests' and sss-genmesh's maps. */
sss_result sss_depth_map_write(const char *path, const sss_depth_image *im, int bits, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
