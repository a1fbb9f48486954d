/* sss/env_error.h: how far a scene bake's environment transfer (ENVT,
 * docs/format.md §5.12) is from the exact evaluator (sss/exact.h), for
 * sss-stat --error (docs/scenes.md "Accuracy", docs/accuracy.md "How the
 * error is measured").
 *
 * The bake projects T_i(x_o) = ∫ q(x_o, ω) y_i(ω) dω over M = max(2048,
 * 128·K) spherical-Fibonacci directions with weight 4π/M (env_sh.c). The
 * reference takes the exact q itself (no stored data) at a random sample of
 * vertices over a quadrature of 4·M Fibonacci directions under a random
 * rotation (so that it shares no point and no spiral with the bake's set),
 * weight π/M each, projected with the same SH basis (sss_sh_eval). What the
 * measurement reports is then the bake's quadrature error plus the float
 * storage, with the reference's own quadrature error on top: on the
 * self-shadowed blob of tests/integration/cli_scene.sh (order 3) the
 * transfer's relative RMS reads 3.1–3.8e-4 against 4·M directions and
 * 3.2–3.6e-4 against 16·M (seeds 1–3), so 4·M measures the bake, not
 * itself.
 */
#ifndef SSS_ENV_ERROR_H
#define SSS_ENV_ERROR_H
#include <stdint.h>
#include "sss/exact.h"
#include "sss/format.h"
#include "sss/result.h"
#ifdef __cplusplus
extern "C" {
#endif

#define SSS_ENV_ERROR_VERTICES 64       /* receivers drawn (all of a smaller mesh) */
/* at most this many evaluations of G in all: the sources traced per
 * direction are limited to this over the reference's directions (16384 up
 * to order 4, 4096 at order 8), what the bake of a 65536-vertex mesh costs
 * at order 4, whatever the size of the mesh measured */
#define SSS_ENV_ERROR_EVALS (1u << 27)
#define SSS_ENV_ERROR_REF_FACTOR 4u     /* the reference's directions: this times the bake's M */
#define SSS_ENV_ERROR_RANDOM_MAX 8u     /* random environments at most */

/* Every figure compares the file (a) against the reference (r) over the
 * measured vertices, area-weighted (ΔA, as the per-vertex error): rms =
 * sqrt(Σ A (a − r)² / (n Σ A)) with n the values per vertex, rel_rms =
 * sqrt(Σ A (a − r)² / Σ A r²), max_abs = max |a − r|; index `channels`
 * (transfer) or 3 (radiance) is over all channels. */
typedef struct sss_env_error {
    uint32_t order, channels;
    uint32_t bake_dirs, ref_dirs; /* M and the reference's 4·M */
    uint32_t vertices;            /* receivers measured */
    uint64_t sources;             /* distinct vertices whose G the reference traced per direction */
    int shadows;                  /* the reference's visibility: the file's self-shadow bit */
    /* the transfer coefficients T_i, over the K coefficients */
    double t_rms[SSS_MAX_CHANNELS + 1], t_rel_rms[SSS_MAX_CHANNELS + 1], t_max_abs[SSS_MAX_CHANNELS + 1];
    double t_rms_exact[SSS_MAX_CHANNELS + 1];
    /* radiance max(0, Σ_i T_i L_i) per RGB channel (sss_fx_env) under the
     * file's probe (have_probe 0 when the file stores none: every L_i 0) */
    int have_probe;
    double probe_rms[4], probe_rel_rms[4], probe_max_abs[4];
    /* under nrandom random band-limited environments (a constant plus three
     * directional lights of random colour, projected onto the file's order):
     * the relative RMS over RGB of each, worst and mean */
    uint32_t nrandom;
    double random_rel_rms_max, random_rel_rms_mean;
} sss_env_error;

/* Measures f's ENVT (f->fx.mask must hold SSS_FX_ENV_SH) against e, built
 * from f. The receivers are SSS_ENV_ERROR_VERTICES vertices drawn without
 * replacement from `seed` (every vertex of a smaller mesh), as many of them
 * as keep the sources within SSS_ENV_ERROR_EVALS / (4·M) (at least one); the
 * rotation and the random environments come from the same seed. The
 * reference traces visibility when the file's self-shadow bit is set
 * (what the bake did) and restores e's visibility afterwards. Deterministic
 * whatever the thread count. Errors: SSS_ERR_ARG (no ENVT, e not from a
 * file like f), SSS_ERR_NOMEM. */
sss_result sss_env_error_measure(const sss_bake_file *f, sss_exact *e, uint32_t nrandom, uint64_t seed,
                                 sss_env_error *out, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
