/* sss/layer_depth.h: layers of variable depth (seed 002 §2.1, "layers of
 * variable thickness"; docs/layers.md §3): how a layer's lower boundary
 * is given in a scene file (a number, a depth map over the texture
 * coordinates, or a procedural pattern over rest-pose positions), the
 * evaluation of the map's samples and of the patterns, and the per-vertex
 * stack a file's depths (section LDEP) make.
 *
 * Units: mm, positions in the object's rest frame (as sss/field.h's), so
 * a depth moves rigidly with its object. Reading a map's PNG is the
 * bake's (precompute/src/input/depthmap.c): libsss has no image library.
 */
#ifndef SSS_LAYER_DEPTH_H
#define SSS_LAYER_DEPTH_H

#include <stdint.h>
#include "sss/result.h"
#include "sss/single.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sss_depth_kind {
    SSS_DEPTH_CONSTANT = 0,   /* "depth_mm": D, the layer's own depth */
    SSS_DEPTH_MAP = 1,        /* {"map": FILE, "scale_mm": s}: depth = value / max · s at the vertex's (u, v) */
    SSS_DEPTH_PROCEDURAL = 2  /* {"procedural": ..., "seed", "scale_mm", "depth_mm": [min, max]} */
} sss_depth_kind;

typedef enum sss_depth_pattern {
    SSS_DEPTH_VEINS = 1,  /* f = sss/field.h's marble veins (1 on a vein) */
    SSS_DEPTH_BLOBS = 2,  /* f = Worley inclusions, balls of radius 0.3 scale_mm with an edge 0.1 scale_mm (1 inside) */
    SSS_DEPTH_BUMPS = 3   /* f = one octave of smooth value noise (sss_field_noise) */
} sss_depth_pattern;

#define SSS_DEPTH_PATH_MAX 1024
#define SSS_DEPTH_MAX_MM 1e6 /* the largest depth a scene or a file gives (mm) */

/* How one layer's lower boundary is given. */
typedef struct sss_depth_spec {
    uint32_t kind;            /* sss_depth_kind */
    uint32_t pattern;         /* procedural: sss_depth_pattern */
    uint32_t seed;            /* procedural: the noise's seed */
    double scale_mm;          /* map: the depth at the map's largest value; procedural: the feature size */
    double range_mm[2];       /* procedural: depth = min + (max − min) f, 0 ≤ min ≤ max */
    char map[SSS_DEPTH_PATH_MAX]; /* map: the resolved path of the PNG */
} sss_depth_spec;

/* A grey depth map: w × h samples in [0, 1] (the PNG's value over its
 * largest, 255 or 65535), row 0 the image's top row. */
typedef struct sss_depth_image {
    uint32_t w, h;
    float *value;             /* w · h, row-major, owned */
} sss_depth_image;

/* The map at texture coordinates (u, v), v upward (sss_mesh.uv; the
 * image's top row is v = 1): bilinear between sample centres, u and v
 * wrapped into [0, 1) (a texture repeats, as the generated meshes' seams
 * at u = 1 ≡ 0 need). In [0, 1]. */
double sss_depth_image_sample(const sss_depth_image *im, double u, double v);

void sss_depth_image_free(sss_depth_image *im);

/* A procedural depth at rest-frame x (mm): min + (max − min) f(x) with
 * f ∈ [0, 1] of the pattern (veins and blobs through sss/field.h's kinds,
 * bumps its noise; no noise of its own). */
double sss_depth_procedural(const sss_depth_spec *s, const double x_mm[3]);

/* Makes the n depths of one vertex non-decreasing, top first: a layer's
 * depth above the one before it is raised to it (the layer has no
 * thickness there; docs/layers.md §3). */
void sss_layer_depths_monotone(float *d, uint32_t n);

/* The stack at vertex v: st with layer k's depth layer_depth[v · st->n + k]
 * (section LDEP's layout); layer_depth NULL gives st itself. The
 * material's half-space below a file's layers, if st has it at index n,
 * is copied unchanged. */
void sss_layer_stack_at(const sss_layer_stack *st, const float *layer_depth, uint32_t v, sss_layer_stack *out);

#ifdef __cplusplus
}
#endif
#endif
