/* effect.h (internal): an effect of a scene bake as one unit
 * (docs/architecture.md §5): its planner rule (which lights it takes, and
 * why), its bake pass, and what it adds to the file's provenance. The
 * planner (bake/planner.c) asks every unit of the table below whether it
 * takes a light; the scene bake (bake/bake_scene.c) runs the pass of every
 * unit some light chose, over one set of neighbourhoods N(x_o)
 * (Hao–Varshney 2004 §3.1) and one visibility structure.
 *
 * Adding an effect: a file here defining its sss_effect_unit, one row in
 * sss_effect_units (effects.c), its pass kind in sss/planner.h, its SSS_FX_
 * bit and section (common/src/sections/), and its run-time pass
 * (runtime/src/render/effects/).
 */
#ifndef SSS_EFFECT_H
#define SSS_EFFECT_H

#include <math.h>
#include <stddef.h>

#include "sss/bake_scene.h"
#include "sss/fieldweights.h"
#include "sss/transfer.h"

struct cJSON;

/* What every pass of a scene bake gets. */
typedef struct sss_pass_ctx {
    const sss_scene *scene;
    const sss_object_plan *plan;
    const sss_mesh *mesh;      /* the object, world units, normals and areas */
    const sss_weights *nb;        /* N(x_o) for every vertex */
    const sss_weights *hat;       /* the hat-function corrections of nb (docs/physics.md §9); NULL: point weights */
    const sss_vis *vis;        /* NULL: no visibility rays */
    double eta;
    uint32_t C;
    uint32_t n_dirs, sh_order, shells;
    double near_factor;
    sss_bake_file *out;
    sss_bake_stats *st;
    uint64_t memory_left;      /* bytes a pass may still take beyond the plan (0: no limit): the probes' */
    /* The hierarchical gather (the plan's gather rule; nb is then NULL):
     * the tree over the object, vertex → its Morton row (for the hat
     * corrections), the channels' dipoles and the cutoff the rows would
     * have had (with a field, the kernel's reference and radius). */
    struct sss_gather_tree *tree;
    const uint32_t *tree_inv;
    const sss_dipole *dip;
    double radius_mm;
} sss_pass_ctx;

typedef struct sss_effect_unit {
    sss_pass_kind kind;  /* its row in sss_effect_units and in sss_object_plan.pass_lights */
    const char *name;    /* the planner's choice for a light, and the pass's name */
    uint32_t fx;         /* the SSS_FX_ bit a file carries when the pass ran */
    /* Planner rule: does this effect take light L of the object planned in
     * p? If so, writes the reason into reason[0 … n) and returns 1. The
     * units' rules exclude each other, so every light with some intensity
     * is taken by exactly one. */
    int (*claim)(const sss_scene *s, const sss_object_plan *p, const sss_scene_light *L, char *reason, size_t n);
    /* Bake pass: the data of the lights p->light_pass gives it, into c->out. */
    sss_result (*bake)(const sss_pass_ctx *c, sss_error *err);
    /* The pass's own parameters in the provenance JSON (may be NULL). */
    void (*provenance)(const sss_pass_ctx *c, struct cJSON *params);
    /* Bytes the pass allocates, planned before the scene bake starts
     * (docs/robustness.md, "Memory"): what it keeps in c->out, and the most
     * it holds besides while it runs. c->nb and c->vis are not built yet. */
    void (*memory)(const sss_pass_ctx *c, uint64_t *kept, uint64_t *transient);
} sss_effect_unit;

/* Every unit, in pass-kind order (effects.c). */
extern const sss_effect_unit *const sss_effect_units[SSS_PASS_KINDS];

/* A point light is near when it is within this many object sizes of the
 * object's centre (scene "bake"/"near_factor", default 5): its direction
 * and 1/r² falloff then vary across the object (Hao–Varshney 2004 §3.3). */
static inline double sss_near_factor(const sss_scene *s)
{
    return s->bake.near_factor > 0 ? s->bake.near_factor : 5.0;
}

/* Distance of point light L from the object's centre in object sizes. */
static inline double sss_point_ratio(const sss_object_plan *p, const sss_scene_light *L)
{
    double d2 = 0;
    for (int c = 0; c < 3; c++) d2 += (L->position[c] - p->centre[c]) * (L->position[c] - p->centre[c]);
    const double dist = sqrt(d2);
    return p->size > 0 ? dist / p->size : INFINITY;
}

/* G(x_i, ω_j) for all vertices and the n directions dirs into G[i * n + j],
 * counting rays only when a visibility structure is present. */
void sss_pass_transfer(const sss_pass_ctx *c, const double *dirs, uint32_t n, float *G, uint64_t *rays);

/* q = the sum of Hao–Varshney 2004 §3.1 over the n columns of G (nv × n,
 * vertex-major), q[(j · nv + v) · C + c]: through c->nb and c->hat (the
 * direct rows), or through c->tree with the hat corrections on top, as the
 * plain bake's tree path sums (bake_tree.c). signed_sources: G takes
 * either sign (SH projections) and q is not clamped at 0. */
sss_result sss_pass_integrate(const sss_pass_ctx *c, const float *G, uint32_t n, int signed_sources, float *q,
                              sss_error *err);

/* The near terms of a plain bake (near_terms.c): q −= the terms of each
 * vertex and its o->near_rings mesh rings (or the vertices within
 * o->near_radius_mm) at every direction sample of ds, with the bake's own
 * visibility rule and weights (hat: the bake's hat-function corrections
 * when o->weights says so), so that a reader adding them back for a
 * sample restores q. In place; polls o->cancel. *entries (when not NULL):
 * the terms' count over all rows, what every reader builds. self_shadow
 * 0: no rays, V = 1 wherever n_i·ω > 0 (a scene's convex object, the
 * planner's self-shadow rule). */
sss_result sss_near_terms_split(const sss_mesh *mesh, const sss_material *mat, const sss_bake_options *o, uint32_t C,
                                const sss_dirset *ds, const sss_weights *hat, int self_shadow, float *q,
                                uint64_t *rays, uint64_t *entries, sss_error *err);
/* The same, splitting them off the vector integrals qvec too (section
 * QVEC, sss/format.h layout; NULL: none), every vertex's own shadow test. */
sss_result sss_near_terms_split_vector(const sss_mesh *mesh, const sss_material *mat, const sss_bake_options *o,
                                       uint32_t C, const sss_dirset *ds, const sss_weights *hat, float *q, float *qvec,
                                       uint64_t *rays, uint64_t *entries, sss_error *err);
/* The same for a heterogeneous object's rows (docs/heterogeneous.md §4):
 * the terms weighed as the rows are, for the kernel's reference material
 * and scaled by κ (sss_near_spec.field), the hat corrections recomputed
 * for the terms' entries (the bake's own are already scaled), so that a
 * reader's sss_near_build_file adds back what this takes off. */
sss_result sss_near_terms_split_field(const sss_mesh *mesh, const sss_field_kernel *field, const sss_bake_options *o,
                                      uint32_t C, const sss_dirset *ds, int self_shadow, float *q, uint64_t *rays,
                                      uint64_t *entries, sss_error *err);

/* The units (one file each). */
extern const sss_effect_unit sss_effect_dir_exact;    /* dir_exact.c */
extern const sss_effect_unit sss_effect_dir_set;      /* dir_set.c */
extern const sss_effect_unit sss_effect_point_shells; /* point_shells.c */
extern const sss_effect_unit sss_effect_env_sh;       /* env_sh.c */

#endif
