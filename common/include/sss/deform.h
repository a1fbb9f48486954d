/* sss/deform.h: procedural deformers of a scene object (docs/deformable.md
 * §2): bend, twist and wave map the rest pose, the mesh as imported, to its
 * pose at time t. They stand in for a rig on meshes that have none, so that
 * the per-frame path (docs/deformable.md §3) has deforming geometry to work
 * on. No GL: part of libsss.
 *
 * Frame. The deformer acts in the mesh's own units, before the object's
 * transform (x_world = scale · R · D_t(x) + translate). With a the unit
 * axis, every rest position x is written
 *     x = c⊥ + (s_min + σ) a + y u + z v,
 * where s_min is the smallest x·a over the rest vertices (so σ ∈ [0, L],
 * L the rest extent along a), c⊥ the rest bounding box's centre with its
 * a-component removed, u the unit vector of the world axis least aligned
 * with a (x, then y, then z on a tie) made perpendicular to a, and v = a×u.
 * The end σ = 0 stays fixed.
 *
 * Time. The angle at time t is θ(t) = angle_deg · sin(2π t / period_s), so
 * t = 0 (and every whole half period) is the rest pose and the motion is
 * periodic.
 *
 * Maps (θ in radians, κ = θ / L):
 *   bend   the axis line bends into a circular arc of curvature κ in the
 *          (a, u) plane, its length kept (the bend of Barr 1984, "Global
 *          and local deformations of solid primitives"):
 *              σ' = (1/κ − y) sin(κσ),  y' = 1/κ − (1/κ − y) cos(κσ),  z' = z
 *          evaluated as σ' = σ·sinc − y·sin, y' = σ·(1 − cos)/(κσ) + y·cos so
 *          that small κ loses nothing to cancellation.
 *   twist  each cross-section turns about the axis line by φ = θ σ / L:
 *              y' = y cos φ − z sin φ,  z' = y sin φ + z cos φ,  σ' = σ
 *   wave   a standing wave along u, one wavelength over L, whose steepest
 *          slope is tan θ (the axis line tilts by at most θ):
 *              y' = y + (L tan θ / 2π) sin(2π σ / L),  σ' = σ,  z' = z
 * Where θ(t) is 0 the rest positions are copied bit for bit.
 *
 * Skin. A chain of bones given in the scene (sss/skin.h): each bone b turns
 * about its head by θ_b(t) = angle_deg_b · sin(2π t / period_s_b), the same
 * time law, composed down the chain, and the vertices follow by linear
 * blend skinning with weights from their rest distances to the bones (the
 * formula is in sss/skin.h). The axis, angle_deg and period_s above are
 * unused. Where every θ_b(t) is 0 the rest positions are copied bit for
 * bit.
 */
#ifndef SSS_DEFORM_H
#define SSS_DEFORM_H

#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/skin.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sss_deform_kind {
    SSS_DEFORM_NONE = 0, /* a rigid object */
    SSS_DEFORM_BEND = 1,
    SSS_DEFORM_TWIST = 2,
    SSS_DEFORM_WAVE = 3,
    SSS_DEFORM_SKIN = 4 /* a bone chain of the scene (sss/skin.h) */
} sss_deform_kind;

/* The largest |angle_deg| each kind accepts: a bend of two full turns and a
 * twist of ten already fold any mesh onto itself; a wave's slope tan θ must
 * stay finite. */
#define SSS_DEFORM_BEND_MAX_DEG 720.0
#define SSS_DEFORM_TWIST_MAX_DEG 3600.0
#define SSS_DEFORM_WAVE_MAX_DEG 80.0
/* period_s when the scene gives none (docs/scenes.md). */
#define SSS_DEFORM_PERIOD_DEFAULT 4.0

typedef struct sss_deform {
    sss_deform_kind kind;
    double axis[3];   /* unit, mesh units' frame (default +z) */
    double angle_deg; /* the amplitude of θ(t), degrees */
    double period_s;  /* > 0, seconds */
    sss_skin skin;    /* SSS_DEFORM_SKIN: the bones (the fields above unused) */
} sss_deform;

/* θ(t) = angle_deg · sin(2π t / period_s) in radians: the time law of every
 * deformer and of each bone of a skin. */
double sss_deform_theta(double angle_deg, double period_s, double t);

/* θ(t) in radians (0 for SSS_DEFORM_NONE); for a skin, θ_b(t) of the bone
 * of the largest |angle_deg| (the first on a tie), for messages. */
double sss_deform_angle(const sss_deform *d, double t);

/* "bend", "twist", "wave", "skin" or "none". */
const char *sss_deform_kind_name(sss_deform_kind k);

/* The pose at time t of rest (positions and triangles read; its normals and
 * areas are not needed) into *out: positions mapped as above, then normals
 * and areas recomputed with sss_mesh_compute_normals_areas, so a posed mesh
 * is what an imported one is to every later stage. A NONE deformer copies
 * the rest positions. Errors (name prefixes them): SSS_ERR_ARG for a
 * non-finite t, a non-unit axis, a period ≤ 0 or an angle out of range, a
 * skin that sss_skin_check refuses ("name: deform: bones/1/parent: …");
 * SSS_ERR_NOMEM; the mesh's own errors. On failure *out is zeroed. */
sss_result sss_deform_pose(const sss_deform *d, double t, const sss_mesh *rest, const char *name, sss_mesh *out,
                           sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
