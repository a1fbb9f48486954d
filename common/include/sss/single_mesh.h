/* sss/single_mesh.h: single scattering at a vertex of a closed mesh, on the
 * CPU: the oracle a per-pixel pass is checked against, and what
 * `sss-stat --query V --light --view` reports (docs/layers.md §5).
 *
 * The view ray refracts at the vertex (its normal, η of the material) and
 * is marched inside until it leaves the mesh or its light is negligible;
 * the light reaching each sample comes from the point K where the reversed
 * refracted light direction leaves the mesh, found by an exact ray cast
 * through the mesh's BVH (sss/bvh.h), not by seed 002's fitted planes; K
 * itself is lit only when nothing outside the object shades it. By default
 * the light is refracted at K's own interpolated normal (two fixed-point
 * steps), and the entry's Fresnel, beam spread and phase angle are K's;
 * the exit's are the vertex's (sss_ss_geometry). On a flat surface every K
 * shares the vertex's normal and the result is the half-space's or the
 * slab's closed form.
 * The material is a half-space of σs = σ′s / (1 − g) with HG phase of g.
 */
#ifndef SSS_SINGLE_MESH_H
#define SSS_SINGLE_MESH_H

#include <stdint.h>

#include "sss/bvh.h"
#include "sss/dipole.h"
#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/single.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Options; zero means default. */
typedef struct sss_ss_mesh_opts {
    uint32_t samples;  /* N, segments along the view ray (default 64) */
    double tau_max;    /* the march ends where the view ray's optical depth σt s reaches this (default 16: e^{−16} ≈ 10⁻⁷) */
    int seed_march;    /* 1: seed 002's Algorithm 1 (left Riemann sum); 0: the per-segment closed form */
    int vertex_refraction; /* 1: the light refracted at the vertex for every sample (Jensen's local plane);
                              0: refracted at its own entry point K (two fixed-point steps) */
    int fitted_planes; /* 1: seed 002's entry estimate instead of the ray cast: the distance to a plane
                          blended between the vertex's tangent plane and the least-squares plane of
                          the vertices within −ln(0.01)/σt (Eqs. 7–10), light refracted at the vertex */
    int no_focusing;   /* 1: without the focusing of the refracted beam by a curved surface (the GPU pass has none) */
    int shared_end;    /* 1: one march end for every channel, where the least extinguishing channel's light
                          has gone (the GPU pass marches the three channels together) */
} sss_ss_mesh_opts;

/* Single-scattered radiance leaving vertex v of mesh (built into bvh, which
 * must be the mesh's own) towards the unit direction view, for a
 * directional light of unit irradiance across its beam from the unit
 * direction light, per channel c < channels into out[c] (1/sr). mm_per_unit
 * converts mesh units to mm. 0 where the light or the viewer is below the
 * vertex's tangent plane. layers (NULL or n = 0: none) lie over the
 * material, at depths below the vertex's tangent plane (seed 002's flat
 * layers; Eq. 12 with the cast's |KM| for the light's share of each).
 * SSS_ERR_ARG for an invalid material or vertex. */
sss_result sss_ss_mesh_vertex(const sss_mesh *mesh, const sss_bvh *bvh, double mm_per_unit, const sss_material *m,
                              const sss_layer_stack *layers, uint32_t channels, uint32_t v, const double light[3],
                              const double view[3], const sss_ss_mesh_opts *opts, double *out, sss_error *err);

/* The same at any surface point x (mesh units) of the mesh, with unit
 * outward normal nrm (a pixel's interpolated normal): the vertex function
 * is this at the vertex's position and normal. Seed 002's fitted plane
 * (opts->fitted_planes) is then the one of the vertices around x.
 * SSS_ERR_ARG for an invalid material or a mesh without normals. */
sss_result sss_ss_mesh_point(const sss_mesh *mesh, const sss_bvh *bvh, double mm_per_unit, const sss_material *m,
                             const sss_layer_stack *layers, uint32_t channels, const double x[3], const double nrm[3],
                             const double light[3], const double view[3], const sss_ss_mesh_opts *opts,
                             double *out, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
