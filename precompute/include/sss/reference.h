/* sss/reference.h: a volumetric path-traced reference (libsss_bake, stage
 * reference/): a Monte Carlo solution of the radiative transfer equation
 * inside a closed triangle mesh with a smooth refractive boundary, for the
 * inputs the bake takes, so that the dipole model itself (Hao–Varshney 2004
 * §2.2, §3.1; docs/physics.md §4) can be measured against the light
 * transport it approximates. docs/reference.md states the model, the
 * estimators and their verification.
 *
 * The model: a homogeneous medium with absorption σa, scattering σs (not
 * reduced) per colour channel and a Henyey–Greenstein phase function of
 * asymmetry g; a smooth dielectric boundary of relative index η (inside /
 * outside) with Fresnel reflection and refraction about the mesh's
 * interpolated vertex normals; light from outside. Lengths in mm (the mesh
 * is scaled by mm_per_unit), coefficients in 1/mm.
 *
 * The radiance estimator follows a path backwards from the surface point:
 * the view ray refracts in, the path takes free flights and
 * Henyey–Greenstein scatterings, reflects or refracts at the boundary
 * (leaving, crossing air and entering again where the mesh says so), and at
 * every scattering event a next-event estimate finds the point where the
 * light's own refracted ray reaches the event (docs/reference.md §3). One
 * walk serves every colour channel (the distance sampled from a channel
 * chosen per flight, each channel weighted by the balance heuristic).
 *
 * Determinism: path k of task t (a query or a pixel) draws its numbers from
 * its own stream, a hash of (seed, t, k); paths are summed in fixed blocks
 * in a fixed order, so the result for a given path count does not depend on
 * the thread count or the process count (sss_ref_comm).
 */
#ifndef SSS_REFERENCE_H
#define SSS_REFERENCE_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/mesh.h"
#include "sss/probe.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the medium ---------------------------------------------------------- */

/* Per channel σa and σs (1/mm, σs the full scattering coefficient, not σ′s),
 * one Henyey–Greenstein g in (−1, 1) and one η for all channels.
 * hetero (not owned; NULL or a field of kind SSS_FIELD_NONE: homogeneous)
 * makes the medium a material field (docs/heterogeneous.md §3): at x, σa
 * and σs are (1 − f) times the ones above plus f times hetero->inside's
 * (its σ′s over 1 − g), f the field at x's rest-frame point. Walks then
 * track it with a majorant (docs/reference.md §3.1); particles refuse it. */
typedef struct sss_ref_medium {
    double sigma_a[SSS_MAX_CHANNELS];
    double sigma_s[SSS_MAX_CHANNELS];
    double g;
    double eta;
    const struct sss_hetero *hetero;
} sss_ref_medium;

/* From a material whose σ′s is reduced (Jensen's table, sss-bake's
 * --sigma-s): σs = σ′s / (1 − g). SSS_ERR_ARG when g is not in (−1, 1) or
 * the material fails sss_material_validate. */
sss_result sss_ref_medium_from_material(const sss_material *m, double g, sss_ref_medium *out, sss_error *err);

/* Checks finite, σa ≥ 0, σs ≥ 0, σa + σs > 0 per channel, |g| < 1,
 * SSS_ETA_MIN ≤ η ≤ SSS_ETA_MAX. */
sss_result sss_ref_medium_validate(const sss_ref_medium *m, sss_error *err);

/* ---- the light ----------------------------------------------------------- */

typedef enum sss_ref_light_kind {
    /* parallel light from dir (towards the light), irradiance 1 on a surface
     * facing it (the toolkit's E = 1, docs/physics.md §4) */
    SSS_REF_DIRECTIONAL = 0,
    /* radiance from every direction: probe (sss/probe.h's lat-long
     * convention, z up) or, probe NULL, radiance 1 everywhere */
    SSS_REF_ENVIRONMENT = 1,
    /* an isotropic point light at pos (mesh units) of intensity I per sr:
     * irradiance I cos θ / r² with r in mesh units, as the toolkit's point
     * lights (docs/scenes.md, the point-shells effect) */
    SSS_REF_POINT = 2
} sss_ref_light_kind;

typedef struct sss_ref_light {
    sss_ref_light_kind kind;
    double dir[3];            /* SSS_REF_DIRECTIONAL: towards the light, any non-zero length */
    const sss_probe *probe;   /* SSS_REF_ENVIRONMENT: NULL for a uniform sky of radiance 1 */
    double pos[3];            /* SSS_REF_POINT: position, mesh units, outside the mesh */
    double intensity;         /* SSS_REF_POINT: per sr, finite and > 0 */
} sss_ref_light;

/* ---- the scene ----------------------------------------------------------- */

/* The mesh in mm for Embree (closest-hit rays), with its vertex normals. */
typedef struct sss_ref_scene sss_ref_scene;

/* m needs normals (sss_mesh_compute_normals_areas; the importer computes
 * them) and at least one triangle; m may be freed afterwards. mm_per_unit
 * 0 means 1. SSS_ERR_UNSUPPORTED when Embree fails. */
sss_result sss_ref_scene_create(const sss_mesh *m, double mm_per_unit, sss_ref_scene **out, sss_error *err);
void sss_ref_scene_destroy(sss_ref_scene *s);

/* ---- options and results ------------------------------------------------- */

/* The collectives a multi-process run needs (the tool's MPI, bake_mpi.c's
 * pattern: the library links no MPI). NULL or nranks ≤ 1: one process. */
typedef struct sss_ref_comm {
    /* every rank passes buf (n doubles) holding its own items' values and
     * zeros elsewhere; afterwards every rank holds their element-wise sum
     * (an MPI_Allreduce with MPI_SUM: each item is non-zero on one rank
     * only, so the sum is exact and its order does not matter). 0 on
     * success. */
    int (*allsum)(double *buf, uint64_t n, void *ctx);
    /* *flag from rank 0 to every rank (the time budget's decision). */
    int (*bcast)(int *flag, void *ctx);
    void *ctx;
} sss_ref_comm;

/* Zero means the default for every field. */
typedef struct sss_ref_options {
    uint64_t seed;
    uint64_t paths;       /* paths per query or pixel; 0: 1024 without a time budget, else no cap */
    double seconds;       /* time budget (wall clock, whole rounds): 0 none */
    int threads;          /* 0: every core (OpenMP's default) */
    uint32_t max_order;   /* scattering orders estimated: 0 all; 1 single scattering only */
    int no_nee;           /* 1: no next-event estimate (a directional light then gives nothing;
                             environment light only through paths that leave: a check) */
    int no_nee_roulette;  /* 1: every next-event estimate is made, also at collisions so deep that
                             it adds nothing (docs/reference.md §3: the same mean, more rays) */
    int progress;         /* a progress bar with ETA on stderr when it is a terminal */
    const char *progress_log; /* progress lines for scripts (kernels/progress.h), or NULL */
    const sss_cancel_flag *cancel;
    int rank, nranks;     /* this process and the process count (with comm) */
    const sss_ref_comm *comm;
} sss_ref_options;

/* What the walks did, summed over every path of a call (this process's
 * paths; under MPI each rank counts its own). */
typedef struct sss_ref_stats {
    uint64_t paths;       /* paths per task actually traced (all tasks the same) */
    uint64_t walks;       /* paths traced by this process, over every task */
    uint64_t rays;        /* closest-hit and occlusion rays */
    uint64_t scatterings; /* scattering events */
    uint64_t nee;         /* next-event estimates tried */
    uint64_t nee_hits;    /* ... that found the light's refracted ray and added light */
    uint64_t nee_unsolved; /* ... whose boundary point did not converge (docs/reference.md §3) */
    uint64_t nee_skipped; /* ... left out by their roulette (deep collisions, weighted) */
    uint64_t leaks;       /* paths stopped because a ray from inside left the scene without
                             meeting a wall seen from inside (a hole in an open mesh) */
    uint64_t truncated;   /* paths stopped at the event limit (SSS_REF_MAX_EVENTS) */
    uint64_t crossed;     /* surfaces rays passed through because they faced the wrong way (overlapping
                             parts, sheets inside the body, flipped triangles: the medium is taken to be
                             continuous across them) */
    double seconds;       /* wall clock of the call */
    uint32_t rounds;      /* rounds of blocks run */
} sss_ref_stats;

/* A path stops after this many events (scatterings and boundary events);
 * Russian roulette ends any path long before, so this only guards against a
 * mesh that traps a ray. */
#define SSS_REF_MAX_EVENTS 1000000

/* An estimate per channel: the mean over paths and its standard error
 * √(s² / n), s² the unbiased sample variance of the per-path values. */
typedef struct sss_ref_estimate {
    double mean[SSS_MAX_CHANNELS];
    double se[SSS_MAX_CHANNELS];
} sss_ref_estimate;

/* ---- radiance at vertices ------------------------------------------------ */

/* Radiance leaving vertex `vertex` towards `view` (from the surface towards
 * the eye, any non-zero length) through the surface: the light that entered
 * the medium and came out at the vertex (the toolkit's subsurface term, L =
 * E · q · F_t(η, n·ω_o) of docs/physics.md §4), not the light reflected at
 * the surface. 0 where n·view ≤ 0 at the vertex (the surface faces away). */
typedef struct sss_ref_query {
    uint32_t vertex;
    double view[3];
} sss_ref_query;

/* Estimates every query (out[nq]). SSS_ERR_ARG for a vertex out of range or
 * a zero direction, SSS_ERR_INTERRUPTED when cancelled. */
sss_result sss_ref_queries(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_light *l,
                           const sss_ref_query *q, uint32_t nq, const sss_ref_options *o, sss_ref_estimate *out,
                           sss_ref_stats *st, sss_error *err);

/* ---- images -------------------------------------------------------------- */

/* The viewer's camera (sss-view, sss_renderer_camera in sss/render.h):
 * about the centre of the mesh's bounding box and its bounding radius (the
 * largest distance of a vertex from that centre), the eye at 3.6 radii
 * along view, vertical field of view 35°, up +y unless looking along it
 * (then +z). Mesh units. */
typedef struct sss_ref_camera {
    double eye[3], right[3], up[3], fwd[3];
    double tan_half_fov; /* tan(fov/2), vertical */
    int width, height;
} sss_ref_camera;

/* The camera above for mesh m (mesh units), view from the centre towards
 * the eye (any non-zero length), width × height pixels. */
void sss_ref_camera_view(const sss_mesh *m, const double view[3], int width, int height, sss_ref_camera *cam);

/* Renders the subsurface radiance seen through each pixel centre (rows
 * from the top, 3 floats per pixel) into rgb and its standard error into se
 * (either may be NULL); pixels that see no surface are 0. */
sss_result sss_ref_image(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_light *l,
                         const sss_ref_camera *cam, const sss_ref_options *o, float *rgb, float *se,
                         sss_ref_stats *st, sss_error *err);

/* ---- single paths and particles (tests, studies) ------------------------- */

/* One path's estimate of the radiance leaving the surface point hit by the
 * ray (org, dir) (mesh units; the first surface hit, which must face the
 * ray) towards −dir, per channel into L; stream is the path's own random
 * state. Returns 0 when the ray misses or hits a back face (L zero). */
int sss_ref_sample_ray(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_light *l,
                       const double org[3], const double dir[3], const sss_ref_options *o, uint64_t *stream,
                       double L[SSS_MAX_CHANNELS], sss_ref_stats *st);

/* A collimated beam for particle tracing: light arriving along −dir (dir
 * towards the light) through the disk of radius `radius` (mesh units; 0: a
 * pencil beam) about `centre`, perpendicular to dir. */
typedef struct sss_ref_beam {
    double centre[3];
    double radius;
    double dir[3];
} sss_ref_beam;

/* Where a beam's power went, per channel, as fractions of the particles
 * launched. `incident` counts particles that reached the mesh; the others
 * split it: reflected at the first surface (`specular`), absorbed inside
 * (estimated along every flight by its expected absorption,
 * (σa/σt)(1 − e^{−σt ℓ}), independently of where the walk goes next), left
 * through a face lit by the beam (n_g · dir > 0: `front`) or through the
 * others (`back`), or lost to a leak or the event limit (`lost`).
 * `balance` is specular + absorbed + front + back per particle, so that its
 * standard error (the parts are correlated) is at hand: energy is
 * conserved when its mean is `incident`. */
typedef struct sss_ref_tally {
    double incident;
    double specular[SSS_MAX_CHANNELS];
    double absorbed[SSS_MAX_CHANNELS];
    double front[SSS_MAX_CHANNELS];
    double back[SSS_MAX_CHANNELS];
    double lost[SSS_MAX_CHANNELS];
    double balance[SSS_MAX_CHANNELS];
} sss_ref_tally;

/* Traces o->paths particles (0: 1024) from the beam; mean and standard
 * error of every tally (se may be NULL). Deterministic for o->seed whatever
 * the thread count. */
sss_result sss_ref_particles(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_beam *b,
                             const sss_ref_options *o, sss_ref_tally *mean, sss_ref_tally *se, sss_ref_stats *st,
                             sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
