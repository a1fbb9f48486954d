/* sss/bake_scene.h: the bake of one object of a planned scene
 * (docs/scenes.md). It runs the passes the plan chose for the object —
 * directional-exact, direction-set, point-shells, environment-sh — over
 * one set of neighbourhoods N(x_o) (Hao–Varshney 2004 §3.1) and one
 * visibility structure (against the object itself and/or the occluders the
 * plan lists, or none), and records the effect set in the file (format 1.2).
 */
#ifndef SSS_BAKE_SCENE_H
#define SSS_BAKE_SCENE_H

#include "sss/bake.h"
#include "sss/planner.h"
#include "sss/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bakes object `obj`. world[k] is object k's world-space mesh (normals and
 * areas computed). opt: eps and threads are used; n_dirs is overridden by
 * the scene's "bake"/"dirs" when given. Environment probes are read here.
 * stats->rays counts the visibility rays actually traced (0 when the plan
 * turns visibility off). */
sss_result sss_bake_object(const sss_scene *scene, const sss_plan *plan, const sss_mesh *world, uint32_t obj,
                           const sss_bake_options *opt, sss_bake_file *out, sss_bake_stats *stats, sss_error *err);

/* Exact q for a point light of unit intensity at P (world units) on the
 * object of file f, with self-shadowing (the reference of the point-shell
 * test): Σ_i w(o,i) F_t(η, n_i·l_i) max(0, n_i·l_i) V(x_i, P) / |P − x_i|²
 * with l_i = (P − x_i)/|P − x_i| (§3.1 with the per-vertex light direction
 * and falloff of §3.3). out[v * channels + c]. */
sss_result sss_point_exact(const sss_bake_file *f, int self_shadow, const double P[3], float *out, sss_error *err);

/* M, the number of spherical-Fibonacci directions over which the
 * environment-sh pass projects G onto SH of this order (docs/scenes.md):
 * max(2048, 128 · order²). sss-stat --error takes its reference from a set
 * denser than this (sss/env_error.h). */
uint32_t sss_env_sh_dirs(uint32_t order);

#ifdef __cplusplus
}
#endif
#endif
