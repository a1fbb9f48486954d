/* sss/skin.h: linear blend skinning, shared by the scene's "skin" deformer
 * (docs/deformable.md §2, a bone chain given in the scene file) and the
 * glTF importer's skinned meshes (docs/deformable.md §5). No GL: part of
 * libsss.
 *
 * Matrices are 4 × 4, column-major (element (row r, column c) at 4c + r), as
 * glTF stores them. Linear blend skinning of a point p with joints j_i and
 * weights w_i (Σ w_i = 1) is p' = Σ_i w_i J_{j_i} p (glTF 2.0 §3.7.3).
 *
 * The scene's bone chain. Each bone b has a head h_b and a tail t_b in the
 * rest frame (mesh units), an optional parent, and turns about its head by
 * θ_b(t) about its unit axis a_b (given in the rest frame). Its matrix
 *     M_b = M_parent(b) · T(h_b) · R(a_b, θ_b) · T(−h_b)
 * (M_parent = I for a root), so a child rides on its parent's motion and
 * adds its own. The weights come from the rest pose: with d_b the distance
 * from x to the segment [h_b, t_b], d_min the smallest, r the blend radius
 * and S(s) = s²(3 − 2s) clamped to [0, 1] (smoothstep),
 *     ŵ_b = S(1 − (d_b − d_min) / r),   w_b = ŵ_b / Σ_c ŵ_c.
 * The nearest bone has ŵ = 1, so Σ ŵ ≥ 1; a bone more than r farther than
 * the nearest has weight exactly 0, so a vertex that far from every other
 * bone follows its own bone exactly. The weights are continuous, and C¹
 * where the nearest bone changes (S'(1) = 0): no crease at a joint.
 */
#ifndef SSS_SKIN_H
#define SSS_SKIN_H

#include <stddef.h>
#include <stdint.h>

#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The most bones of a scene's chain: a limb or a tail, not a character
 * (every vertex weighs every bone). */
#define SSS_SKIN_MAX_BONES 16
/* The largest |angle_deg| of a bone: one full turn. */
#define SSS_SKIN_MAX_DEG 360.0
/* The blend radius when the scene gives none: this fraction of the
 * shortest bone's length. */
#define SSS_SKIN_BLEND_DEFAULT 0.25

typedef struct sss_skin_bone {
    double head[3], tail[3]; /* rest frame, mesh units; |tail − head| > 0 */
    int parent;              /* index of the parent bone, -1 for a root */
    double axis[3];          /* unit rotation axis, rest frame */
    double angle_deg;        /* amplitude of θ_b(t) (sss/deform.h's time law) */
    double period_s;         /* > 0 */
} sss_skin_bone;

typedef struct sss_skin {
    int nbones;          /* 1 … SSS_SKIN_MAX_BONES */
    double blend_radius; /* r > 0, mesh units */
    sss_skin_bone bone[SSS_SKIN_MAX_BONES];
} sss_skin;

/* c = a · b */
void sss_mat4_mul(const double *a, const double *b, double *c);

/* q = Σ_i w_i J[j_i] p over n influences (J: 16 doubles a joint); zero
 * weights are skipped. */
void sss_skin_blend(const double *J, const uint32_t *joint, const double *w, int n, const double p[3], double q[3]);

/* Checks a chain. On a fault returns SSS_ERR_ARG with err->msg the reason
 * alone ("is 3, beyond the 2 bones"), *bone the bone at fault (-1: the
 * chain itself) and *key its member ("parent", "tail", …, or "bones",
 * "blend_radius"), for the caller to say where. */
sss_result sss_skin_check(const sss_skin *s, int *bone, const char **key, sss_error *err);

/* The blend radius r of a checked chain: its blend_radius, or
 * SSS_SKIN_BLEND_DEFAULT times the shortest bone when that is 0. */
double sss_skin_radius(const sss_skin *s);

/* The weights of the rest vertices (above), w[v · nbones + b]. */
void sss_skin_weights(const sss_skin *s, const sss_mesh *rest, double *w);

/* M_b for the angles theta[b] (radians) of a checked chain, 16 doubles a
 * bone. Where every θ_b is 0 every M_b is exactly I. */
void sss_skin_matrices(const sss_skin *s, const double *theta, double *M);

#ifdef __cplusplus
}
#endif
#endif
