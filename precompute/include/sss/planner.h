/* sss/planner.h: scene → effect set (docs/scenes.md). For every
 * object the planner decides, with a reason per decision, how many colour
 * channels to bake, whether visibility rays are traced against the object
 * itself and against the other objects, and which light parameterisation
 * each light gets; the bake then runs one pass per parameterisation and the
 * file records the set (sss_effects, docs/format.md §5.10).
 *
 * The planner is a table of rules (planner.c) run in order over each object;
 * a rule reads the scene and the geometry facts and appends decisions and
 * passes. A later effect (seed 002's single scattering, heterogeneous
 * density, deformation) is one more rule and one more pass kind.
 */
#ifndef SSS_PLANNER_H
#define SSS_PLANNER_H

#include <stdint.h>
#include <stdio.h>
#include "sss/format.h"
#include "sss/mesh.h"
#include "sss/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sss_pass_kind {
    SSS_PASS_DIR_EXACT = 0,  /* static directional light: q for its one direction (§3.1, no §3.2 interpolation) */
    SSS_PASS_DIR_SET = 1,    /* moving directional light: the direction set of §3.2 */
    SSS_PASS_POINT_SHELLS = 2, /* near point light: directions × distance shells (§3.3) */
    SSS_PASS_ENV_SH = 3,     /* environment probe: SH transfer of q */
    SSS_PASS_KINDS = 4
} sss_pass_kind;

#define SSS_PLAN_MAX_DECISIONS 64

typedef struct sss_decision {
    char effect[32];    /* "channels", "self-shadow", "scene-shadow", "light 2", … */
    char choice[48];    /* "1 channel", "off", "directional-exact", … */
    char reason[320];
} sss_decision;

typedef struct sss_object_plan {
    uint32_t object;              /* index into the scene */
    uint32_t effects;             /* SSS_FX_* bits the file will carry */
    uint32_t channels;            /* 1 or 3 */
    int self_shadow;              /* trace rays against the object itself */
    int scene_shadow;             /* trace rays against the occluders below */
    uint32_t noccluders;
    uint32_t *occluders;          /* object indices whose geometry occludes this one; owned */
    int convex;                   /* geometry fact used by the self-shadow rule */
    double size;                  /* bounding-box diagonal, world units */
    double centre[3];             /* bounding-box centre, world units */
    uint32_t pass_lights[SSS_PASS_KINDS]; /* per pass kind: how many lights use it (0: pass not run) */
    uint32_t exact_rows;          /* directional-exact: distinct directions among its lights (QDIR rows) */
    uint32_t *light_pass;         /* per scene light: its sss_pass_kind, or UINT32_MAX if it adds nothing; owned */
    /* How the rows are computed and stored (the storage rule, planner.c):
     * the weight rule of every pass (SSS_WEIGHTS_HAT or _POINT), the
     * direction set's rows compressed (compact) or float, and its near
     * terms at run time (sections OWNT, NRAD) or baked. */
    uint32_t weights;
    int compress;
    int near_runtime;
    /* How every pass sums the rows (rule_gather): SSS_GATHER_DIRECT (every
     * neighbour's row) or SSS_GATHER_TREE (the hierarchical gather,
     * sss/gather.h; with a field docs/heterogeneous.md §4.5). */
    int gather;
    /* 1: the object deforms ("deform", sss/deform.h): nothing is baked for
     * it, q is evaluated per frame on its pose (sss/perframe.h,
     * docs/deformable.md §4); effects and passes are then 0 and light_pass
     * is UINT32_MAX for every light */
    int per_frame;
    /* A material field (rule_field, docs/heterogeneous.md §5): none, folded
     * into the homogeneous blend of a constant, or baked with the spatially
     * varying kernel, or read per frame at the rest pose (a deforming
     * object, docs/deformable.md §10). material is what the bake takes as the object's
     * (base) material: the scene's, or the constant's blend. */
    int field;
    sss_material material;
    uint32_t ndecisions;
    sss_decision decisions[SSS_PLAN_MAX_DECISIONS];
} sss_object_plan;

/* SSS_PLAN_FIELD_PER_FRAME: a deforming object with a field, the
 * endpoints' product per pair every frame (docs/deformable.md §10).
 * SSS_PLAN_FIELD_RUNTIME: "editable": true, the material is edited live;
 * nothing is baked (per_frame is 1) and the viewer runs seed 000's
 * run-time path (sss/htsm_gpu.h, docs/heterogeneous.md §9). */
enum { SSS_PLAN_FIELD_NONE = 0, SSS_PLAN_FIELD_FOLDED = 1, SSS_PLAN_FIELD_BAKED = 2, SSS_PLAN_FIELD_RUNTIME = 3,
       SSS_PLAN_FIELD_PER_FRAME = 4 };

typedef struct sss_plan {
    uint32_t nobjects;
    sss_object_plan *obj;         /* owned */
} sss_plan;

/* Plans every object of scene. world[i] is object i's mesh in world units
 * (sss_scene_object_world). Fails (SSS_ERR_ARG, naming the scene file and
 * JSON path) when the scene has no light, and refuses here, before any bake,
 * what a bake would fail on late (docs/robustness.md, "Scenes"): more static
 * directions than section QDIR holds (static directional lights with the
 * same direction share one row), a probe that cannot be read or whose
 * coefficients, times its light's intensity and colour, leave the range a
 * file stores (SSS_PROBE_SH_MAX). Probes are read with the memory limit of
 * sss_plan_scene_limited (this one: what the system has available). */
sss_result sss_plan_scene(const sss_scene *scene, const sss_mesh *world, sss_plan *out, sss_error *err);
sss_result sss_plan_scene_limited(const sss_scene *scene, const sss_mesh *world, uint64_t memory_limit, sss_plan *out,
                                  sss_error *err);

/* The most static light directions one file holds (section QDIR). */
#define SSS_PLAN_MAX_EXACT 1024

/* Whether static light directions a and b (unit) are one QDIR row: the
 * viewer finds a light's row by this test (scene_view.c). */
static inline int sss_plan_same_direction(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 1.0 - 1e-9;
}

/* The unit direction a static light of pass directional-exact is baked
 * for: a directional light's own, or a far point light's from the object's
 * centre. */
void sss_plan_exact_direction(const sss_object_plan *p, const sss_scene_light *L, double d[3]);

/* Single scattering's planner rule (precompute/src/effects/single.c,
 * docs/layers.md §4): not an effect unit, since it claims no light and
 * bakes nothing; its choice is the effect bit SSS_FX_SINGLE. The share is the largest over
 * the first `channels` channels of R_ss / (R_ss + R_ms), both exitances
 * per unit irradiance of the material's half-space lit head-on: R_ss its
 * single-scattering albedo (sss_ss_albedo), R_ms the dipole's
 * F_t(η, 1) R_d,total c(η); *channel (may be NULL) gets the channel. The
 * threshold is the dipole's own error on a flat half-space lit head-on,
 * 6–10 % in marble against the path-traced reference (docs/accuracy.md,
 * "What the truth shows"): a term smaller than that is not worth a
 * per-pixel march. */
#define SSS_SINGLE_SHARE_MIN 0.10
double sss_single_share(const sss_material *m, uint32_t channels, uint32_t *channel);
/* Whether the object gets single scattering: force > 0 on, < 0 off (the
 * scene's "single_scattering"), 0 the share against SSS_SINGLE_SHARE_MIN;
 * the reason, with the share, into reason[0 … n). */
int sss_single_rule(const sss_material *m, uint32_t channels, int force, char *reason, size_t n);

void sss_plan_free(sss_plan *p);

/* Whether a closed mesh is convex: every edge shared by two triangles
 * with a convex (or flat) dihedral, and every vertex on the inner side of
 * every triangle's plane (tolerance 1e-6 of the diagonal; sampled planes for
 * large meshes). An open mesh is reported not convex. */
int sss_mesh_is_convex(const sss_mesh *m);

/* The plan as text (one block per object, one line per decision), or as
 * one JSON object (effects, passes and decisions per object). */
void sss_plan_print(const sss_scene *scene, const sss_plan *p, FILE *out);
char *sss_plan_json(const sss_scene *scene, const sss_plan *p); /* malloc'ed; NULL on no memory */
/* Adds o's decisions to the cJSON object parent as its "decisions" array
 * ({effect, choice, reason} each): the form sss_plan_json and a scene
 * bake's params share. */
struct cJSON;
void sss_plan_add_decisions_json(const sss_object_plan *o, struct cJSON *parent);

const char *sss_pass_name(sss_pass_kind k);

#ifdef __cplusplus
}
#endif
#endif
