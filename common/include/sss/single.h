/* sss/single.h: single scattering (the first-order term of the radiative
 * transfer) for homogeneous and flat layered media, per colour channel.
 *
 * Models (formulas, units and every choice: docs/layers.md):
 *   - phase functions: Henyey–Greenstein and Schlick's rational form, the
 *     one seed 002 (François et al. 2006, §3) uses;
 *   - Jensen et al. 2001's S⁽¹⁾ for a half-space (docs/layers.md §1):
 *     refracted light and view directions, Fresnel at both crossings;
 *   - the layered model of seed 002 (Eqs. 1–6, 11, 12): layers bounded below
 *     at given depths, the light attenuated through the layers above on its
 *     way in (the reduced intensity) and the scattered light on its way out;
 *     per-layer closed forms on a flat surface, the paper's ray march
 *     (Algorithms 1 and 2) and a per-segment closed-form march.
 *
 * Units: lengths in mm, coefficients in 1/mm. Radiances are per unit
 * incident radiance L_i of a collimated light (equivalently per unit
 * irradiance E normal to the beam). Directions are unit vectors; a phase
 * function takes the cosine between the propagation directions before and
 * after scattering, so g > 0 means forward scattering.
 */
#ifndef SSS_SINGLE_H
#define SSS_SINGLE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Henyey–Greenstein: p(cos θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}),
 * 1/sr; normalised over the sphere, mean cosine g; |g| < 1. */
double sss_phase_hg(double g, double cos_theta);

/* Schlick's form p(cos θ) = (1 − k²) / (4π (1 − k cos θ)²), 1/sr, with θ
 * between the propagation directions: normalised, forward for k > 0, but
 * its mean cosine is not k. Seed 002 (§3) writes (1 + g cos θ') with θ'
 * between ω_in (towards the light) and ω_out (towards the viewer); since
 * cos θ' = −cos θ the two are the same function with k = g. */
double sss_phase_schlick(double k, double cos_theta);

typedef enum sss_phase_kind {
    SSS_PHASE_HG = 0,      /* the default: the path tracer's phase (docs/reference.md) */
    SSS_PHASE_SCHLICK = 1  /* seed 002's, with k = g */
} sss_phase_kind;

/* The phase of `kind` with parameter g at cos θ (propagation directions). */
double sss_phase_eval(sss_phase_kind kind, double g, double cos_theta);

/* The geometry of one single-scattering evaluation on a locally flat
 * surface, inside the medium. */
typedef struct sss_ss_geom {
    double mu_i;      /* cosine of the (refracted) light direction with the normal, (0, 1] */
    double mu_o;      /* cosine of the (refracted) view direction with the normal, (0, 1] */
    double cos_phase; /* cosine between the light's and the scattered light's propagation directions */
    double boundary;  /* what the two crossings pass: F_t(η, ω_i) F_t(η, ω_o) cos θ_i / (η² μ_i), 1 without them */
    double dir_i[3];  /* the light's propagation direction inside (unit, into the medium) */
    double dir_o[3];  /* the view ray's direction inside (unit, into the medium; the scattered light runs against it) */
} sss_ss_geom;

/* Snell's law: the direction t (unit) a ray arriving from outside along −w
 * (w unit, n·w > 0, n the unit outward normal) continues in inside a medium
 * of relative index eta; returns μ = −n·t, the cosine of t with the inward
 * normal. */
double sss_ss_refract(const double n[3], const double w[3], double eta, double t[3]);

/* The geometry of a light from direction wi (unit, towards the light) seen
 * from direction wo (unit, towards the viewer) at a surface of outward unit
 * normal n. With refract = 1 both directions are refracted by Snell's law
 * into a medium of relative index η = n_inside / n_outside, and the
 * boundary factor is what the crossings let through: F_t(η, cos θ_i)
 * (sss_ft) of the irradiance, spread over the refracted beam's wider
 * cross-section (cos θ_i / μ_i), and on the way out F_t(η, cos θ_o) of the
 * radiance, divided by η² as it leaves the denser medium (radiance over n²
 * is conserved). Jensen 2001's eq. 4 keeps the two F_t only; the factor
 * cos θ_i / (η² μ_i) is what the path-traced reference measures
 * (docs/reference.md §5.4; docs/layers.md §1). With refract = 0 the
 * directions go straight on and the factor is 1 (seed 002's model).
 * Returns 0 and leaves g zeroed when the light or the viewer is below the
 * surface. */
int sss_ss_geometry(const double n[3], const double wi[3], const double wo[3], double eta, int refract,
                    sss_ss_geom *g);

/* The single scattering of a homogeneous half-space (Jensen 2001's S⁽¹⁾,
 * docs/layers.md §1, with the boundary factor above), closed form of its
 * integral along the refracted view ray:
 *   L / L_i = B · σs · p · μ_i / (σt (μ_i + μ_o)),
 * B = g->boundary, p the HG phase of hg_g at g->cos_phase; with
 * refraction B μ_i = F_t F_t cos θ_i / η², the reference's closed form.
 * 0 when σt = 0. */
double sss_ss_halfspace(double sigma_s, double sigma_t, double hg_g, const sss_ss_geom *g);

/* The half-space's single-scattering albedo at normal incidence: the
 * radiant exitance of sss_ss_halfspace (refracted, both crossings, index
 * η) over the incident irradiance,
 *   R_ss = ∫ L⁽¹⁾(ω_o) cos θ_o dω_o / E,
 * by the midpoint rule on 1024 cells in cos θ_o (at normal incidence the
 * phase angle depends on θ_o alone). Dimensionless, in [0, 1). The planner
 * sets it against R_d,total (docs/layers.md, "When it is on"). */
double sss_ss_albedo(double sigma_s, double sigma_t, double hg_g, double eta);

/* One layer of seed 002's material, all three channels: σs and σt in 1/mm,
 * one phase parameter g, and the depth of its lower boundary below the
 * surface (mm, measured along the normal; INFINITY for the last layer of a
 * half-space). A layer spans from the previous layer's depth (0 for the
 * first) to its own: a depth equal to the previous one is a layer of zero
 * thickness, which no point lies in and no path crosses. */
typedef struct sss_layer {
    double sigma_s[3];
    double sigma_t[3];
    double g;
    double depth;
} sss_layer;

#define SSS_MAX_LAYERS 8

/* A stack of layers, top first, depths non-decreasing. Below the last layer
 * nothing scatters or attenuates (the march ends there). */
typedef struct sss_layer_stack {
    uint32_t n;
    sss_layer layer[SSS_MAX_LAYERS + 1]; /* + 1: room for the material beneath a file's layers */
    sss_phase_kind phase;
} sss_layer_stack;

/* The layer holding depth z ≥ 0 (mm): the first k with z < depth_k, so a
 * zero-thickness layer never holds a point; n when z lies below them all
 * (seed 002 §2.1, FindLayer). */
uint32_t sss_layers_find(const sss_layer_stack *st, double z);

/* Optical depth of channel c along a straight path from the surface down
 * to depth z at cosine mu with the normal: Σ_j σt_j d_j with seed 002's
 * Eq. 12, d_j = clamp(|KM| − Σ_{k<j} D_k/μ, 0, D_j/μ), |KM| = z/μ and D_j
 * the thickness of layer j (flat layers: the same at M and at K, so the
 * paper's average of the two is the thickness itself). The clamp at 0 is
 * the one Eq. 12 lacks (docs/layers.md). Exact for flat layers. */
double sss_layers_tau(const sss_layer_stack *st, uint32_t c, double z, double mu);

/* The same for a path of known length km (mm) at cosine mu with the
 * normal, |KM| = km in Eq. 12: where a ray cast, not the plane, gives the
 * distance to the entry point (sss/single_mesh.h). sss_layers_tau is this
 * with km = z/μ. */
double sss_layers_tau_path(const sss_layer_stack *st, uint32_t c, double km, double mu);

/* The stack's single scattering on a flat surface, closed form: the sum
 * over layers k of
 *   B · σs_k p_k μ_i / (σt_k (μ_i + μ_o)) · e^{−τ_k m} (1 − e^{−σt_k h_k m}),
 * B = g->boundary, m = 1/μ_i + 1/μ_o, τ_k the optical depth of the layers
 * above k along the normal, h_k the thickness of layer k. One homogeneous layer of depth D
 * gives seed 002's closed form
 *   L = (σs/σt)·p·L_i·μ_i/(μ_i+μ_o)·[1 − e^{−σt D (1/μ_i + 1/μ_o)}].
 * Result per unit L_i, channel c. */
double sss_layers_closed(const sss_layer_stack *st, uint32_t c, const sss_ss_geom *g);

/* What a march needs to know at distance s (mm) along the view ray inside
 * the medium: the layer holding the point (n: below every layer) and the
 * optical depth of channel c along the light's path from its entry point K
 * to the point (seed 002 Eqs. 6, 11). A flat surface answers with
 * sss_layers_find and sss_layers_tau; a mesh answers with its own entry
 * points. */
typedef struct sss_ss_point {
    uint32_t layer;
    double tau_light;
} sss_ss_point;
typedef void (*sss_ss_locate_fn)(void *user, uint32_t c, double s, sss_ss_point *out);

/* Seed 002's march (Algorithm 1, Eqs. 4, 5 and 13): N samples at s_j = j Δ,
 * j = 0 … N−1, Δ = s_max / N; each adds σs p L_ri T Δ with the layer and the
 * reduced intensity of its own point and the view attenuation T of the
 * points before it, then T *= e^{−σt Δ} with its own layer's σt (the
 * incremental attenuation of Eq. 13). A left Riemann sum: first order in Δ.
 * The boundary factor and the phase's cosine from g. Channel c; n = 0
 * gives 0. */
double sss_ss_march(const sss_layer_stack *st, uint32_t c, const sss_ss_geom *g, double s_max, uint32_t n,
                    sss_ss_locate_fn locate, void *user);

/* The per-segment closed-form march: the same N segments, but on each the
 * integrand σs p e^{−τ_light(s) − τ_view(s)} is integrated exactly with
 * both optical depths linear between the segment's ends; a segment whose
 * ends lie in different layers is split at the crossing, found by bisection
 * to 2⁻⁴⁰ s_max. Exact for flat layers at any N; second order in Δ where
 * τ_light curves. */
double sss_ss_march_segments(const sss_layer_stack *st, uint32_t c, const sss_ss_geom *g, double s_max,
                             uint32_t n, sss_ss_locate_fn locate, void *user);

/* The locate function of a flat surface: user points to an sss_ss_flat;
 * the point at s lies at depth z = s μ_o, its layer is sss_layers_find(z)
 * and the light reaches it along z/μ_i (sss_layers_tau). */
typedef struct sss_ss_flat {
    const sss_layer_stack *stack;
    double mu_i, mu_o;
} sss_ss_flat;
void sss_ss_locate_flat(void *user, uint32_t c, double s, sss_ss_point *out);

#ifdef __cplusplus
}
#endif
#endif
