/* sss/nearterms.h: the vertex's own term of q, evaluated at run time.
 *
 * Hao–Varshney 2004 §3.1 sums over the whole neighbourhood, the vertex
 * itself included:
 *
 *   q(x_o, ω) = Σ_{x_i ∈ N(x_o)} w(o, i) F_t(η, n_i·ω) max(0, n_i·ω) V(x_i, ω).
 *
 * R_d peaks at r = 0, so the own entry i = o carries a large share of the
 * sum, and it is the entry that changes most abruptly with ω: it switches
 * off where x_o itself falls into a cast shadow and has a kink where x_o
 * turns away from the light. Interpolating between direction samples
 * (§3.2) smears both over the sample spacing (~14° at 200 directions), and
 * on the dragon 97 % of the squared per-vertex error sits at those steps
 * (docs/accuracy_4000.md, "Where the error comes from").
 *
 * A file baked with `--own-term runtime` (section OWNT, docs/format.md
 * §5.14) therefore stores the rest, q − w̃_o g_o(ω_j) V(x_o, ω_j), and the
 * reader adds w̃_o g_o(ω) V(x_o, ω) back for the actual light, with the
 * vertex's own visibility from a shadow test of its own (rays in the tools,
 * a shadow map in the viewer: the paper's local-illumination pass already
 * shadows the surface, §3.2). w̃_o is not stored: both sides compute it
 * with sss_near_build from the file's geometry and material, so it costs
 * no bytes.
 */
#ifndef SSS_NEARTERMS_H
#define SSS_NEARTERMS_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/format.h"
#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/weights.h"

#ifdef __cplusplus
extern "C" {
#endif

/* g = F_t(η, c) · max(0, c), c = n·ω (n and ω unit; ω towards the light):
 * the transfer factor of the own term without visibility, in float as
 * every reader evaluates it (the GLSL version in runtime/shaders/near_vis.comp.glsl
 * computes the same expression). */
float sss_near_g(float eta, const float n[3], const float d[3]);

/* ---- the near terms: the own term and its mesh rings -----------------
 *
 * The same split taken further: the neighbours within `rings` edges of x_o
 * (its 1-ring, 2-ring, ...) are the next largest entries of the sum and
 * flip with their own shadows as the light moves. Evaluating them at run
 * time too, from every vertex's own visibility (one shadow test per vertex,
 * shared by all the rows that hold it), leaves in the rows only the far
 * part of the neighbourhood, which changes slowly with ω. On the 23K dragon
 * at 200 directions the per-vertex error falls from 15.5 % (all baked) to
 * 2.3 % (own term) and 0.23 % (own + 1-ring): docs/accuracy.md. The weights
 * come from the file's geometry and material alone (no bytes stored). */

/* Builds the weight rows (sss/weights.h; row o: entry 0 is o itself, then
 * its ring neighbours ascending) for rings 0 … 8 (0: the own term alone, w̃(o,o) = (1/π)
 * ∫ R_d over a disk of x_o's own area, shared by area with coincident
 * copies as nbhd.c's self term). Ring neighbours are vertices reachable over at most
 * `rings` triangle edges; their weight follows nbhd.c: (1/π) ∫ R_d over
 * x_i's area as a disk when that disk covers x_o, else (1/π) R_d(r) ΔA_i
 * (Hao–Varshney 2004 §3.1). Deterministic. Errors: SSS_ERR_ARG,
 * SSS_ERR_NOMEM. */
sss_result sss_near_build(const sss_mesh *mesh, const sss_material *mat, double mm_per_unit, uint32_t channels,
                          uint32_t rings, sss_weights *out, sss_error *err);

/* The fraction of R_d,total the run-time near terms hold by default when
 * their radius comes from the material (docs/accuracy.md, "Near terms sized
 * by the material": the baked rest's image error measured about
 * proportional to the fraction left in the rows), in the widest channel of
 * an RGB file. Its other channels then hold more: 0.964–0.983 on average
 * over the three for the Jensen presets (marble 0.971), and the image error
 * averages the channels. A one-channel file has no such margin, so it
 * holds SSS_NEAR_FRACTION_GREY, what the RGB marble holds on average
 * (docs/accuracy.md, "The defaults": grey marble 1.05e-3 worst at 0.95,
 * 5.9e-4 at 0.97). */
#define SSS_NEAR_FRACTION_DEFAULT 0.95
#define SSS_NEAR_FRACTION_GREY 0.97

/* The default fraction for a file of `channels` channels. */
static inline double sss_near_fraction_default(uint32_t channels)
{
    return channels == 1 ? SSS_NEAR_FRACTION_GREY : SSS_NEAR_FRACTION_DEFAULT;
}

/* The most near terms a vertex holds on average when their radius comes
 * from the material: on an object small against its scattering range (a
 * 2 mm blob of marble) the material's radius covers the whole mesh and the
 * terms grow as nv²; the radius then shrinks until the rows hold at most
 * this many entries per vertex on average (docs/accuracy.md, "Near terms
 * sized by the material"). 512 keeps the 100K dragon at 20 cm (445) at the
 * material's radius. */
#define SSS_NEAR_ENTRIES_MAX 512

/* radius_mm, or the largest radius found below it whose rows (every vertex
 * within it, sss_near_spec.radius_mm) hold at most SSS_NEAR_ENTRIES_MAX
 * entries per vertex on average, counted exactly. Deterministic. */
double sss_near_radius_capped(const sss_mesh *mesh, double mm_per_unit, double radius_mm);

/* The fraction of R_d,total (docs/physics.md §2) a disk of radius_mm holds
 * in the channel that holds the least of it (the first `channels`). */
double sss_near_fraction_held(const sss_material *m, uint32_t channels, double radius_mm);

/* The near terms' radius for material m, in mm: the smallest disk that
 * holds `fraction` of R_d,total (docs/physics.md §2) in every one of its
 * first `channels` channels, i.e. the largest channel's sss_rd_radius with
 * ε = 1 − fraction. A property of the material alone, so a fine and a
 * coarse mesh of one object get the same physical neighbourhood. 0 for an
 * invalid material or a fraction outside (0, 1). */
double sss_near_radius_material(const sss_material *m, uint32_t channels, double fraction);

/* The radius a bake's near terms take from the material (docs/accuracy.md,
 * "Near terms sized by the material"): sss_near_radius_material for
 * `fraction`, no wider than the neighbourhood search_mm (beyond it the
 * terms weigh 0), then sss_near_radius_capped. *capped says whether the
 * cap shrank it, *held the fraction it holds (sss_near_fraction_held).
 * Shared by plain and scene bakes. */
double sss_near_radius_bake(const sss_mesh *mesh, double mm_per_unit, const sss_material *m, uint32_t channels,
                            double fraction, double search_mm, int *capped, double *held);

/* Which near terms, and with which weights. */
typedef struct sss_near_spec {
    uint32_t rings;   /* mesh rings 0 … 8 (when radius_mm is 0) */
    /* > 0: instead of rings, every vertex within radius_mm (mm, ‖x_i − x_o‖,
     * whether or not the mesh connects it: the far side of a thin part
     * scatters through it; section NRAD: a physical neighbourhood, the same
     * on a fine and a coarse mesh) */
    double radius_mm;
    /* SSS_WEIGHTS_POINT (0): nbhd.c's point rule, as above; SSS_WEIGHTS_HAT:
     * the bake's hat-function weights (sss/hatweights.h), W = w + C with
     * nbhd.c's w (0 beyond the cutoff radius of eps) */
    uint32_t weights;
    double eps;       /* the bake's ε, for SSS_WEIGHTS_HAT */
    /* NULL: a homogeneous object. Else the object's field kernel
     * (sss/fieldweights.h, built over the same mesh): the weights are then
     * those of the bake's rows, built for the kernel's reference material
     * (the `mat` argument is not read) with its search radius as the hat
     * weights' cutoff, every entry scaled by κ(o, i) (docs/heterogeneous.md
     * §4), so that the terms a reader adds are the terms the rows lost. */
    const struct sss_field_kernel *field;
} sss_near_spec;

/* The same for a spec. hat (may be NULL): the corrections of
 * sss_hat_corrections for every vertex, when the caller already has them
 * (the bake); else they are computed here for SSS_WEIGHTS_HAT. */
sss_result sss_near_build_spec(const sss_mesh *mesh, const sss_material *mat, double mm_per_unit, uint32_t channels,
                               const sss_near_spec *spec, const sss_weights *hat, sss_weights *out, sss_error *err);

/* The near terms a file's reader adds (OWNT with NRAD and QUAD): its rings
 * or radius, its weight rule and ε; with section FELD, the field's kernel
 * as the scene bake built it (sss_field_kernel_create and its far pairs'
 * cache, docs/heterogeneous.md §4.3), so that they equal the terms the
 * bake split off. */
sss_result sss_near_build_file(const sss_bake_file *f, sss_weights *out, sss_error *err);

/* gv[v] = sss_near_g(η, n_v, d) · lit[v] for every vertex (lit NULL:
 * all lit): the transfer of each vertex towards light d, once per frame. */
void sss_near_transfer(const float *nrm, uint32_t nv, float eta, const double d[3], const uint8_t *lit, float *gv);

/* s[c] = Σ_{a in row o} w[a, c] · gv[idx[a]], accumulated in float in row
 * order — the one sum the bake subtracts and every reader adds. */
void sss_near_sum(const sss_weights *n, uint32_t o, const float *gv, float *s);

/* out[o * channels + c] += sss_near_sum for every vertex o. */
void sss_near_add(const sss_weights *n, const float *gv, float *out);

#ifdef __cplusplus
}
#endif
#endif
