/* ref_internal.h: what the reference stage's files share (sss/reference.h
 * is the public side): the scene's rays and surface frames (ref_scene.c),
 * the medium and one path (ref_walk.c), used by the drivers
 * (reference.c). Lengths in mm. */
#ifndef SSS_REF_INTERNAL_H
#define SSS_REF_INTERNAL_H

#include <stdint.h>
#include "sss/reference.h"

/* ---- scene (ref_scene.c) ---- */

struct sss_ref_scene {
    void *device, *scene;   /* RTCDevice, RTCScene */
    uint32_t nv, nf;
    double *pos;            /* 3·nv, mm */
    double *nrm;            /* 3·nv, unit vertex normals (the mesh's) */
    uint32_t *tri;          /* 3·nf */
    double *ng;             /* 3·nf, unit geometric normals, outward (counter-clockwise from outside) */
    double mm_per_unit;
    double eps;             /* tnear of rays leaving a surface, mm: 1e-7 of the diagonal, at least a few
                               float ulps of the coordinates */
    double centre[3], radius; /* bounding sphere about the box centre, mm (particle beams) */
};

/* A surface point: position (mm), shading normal ns (interpolated vertex
 * normals, unit), geometric normal ng (unit, outward), the triangle
 * (UINT32_MAX at a vertex, where ng is ns) and the ray distance. */
typedef struct ref_hit {
    double t;
    double p[3], ns[3], ng[3];
    uint32_t tri;
} ref_hit;

/* Closest hit of the ray o + t·d, t in (tnear, ∞) (d unit); 0 on a miss. */
int ref_intersect(const sss_ref_scene *s, const double o[3], const double d[3], double tnear, ref_hit *h);
/* 1 when anything blocks o + t·d, t in (tnear, ∞). */
int ref_occluded(const sss_ref_scene *s, const double o[3], const double d[3], double tnear);
/* 1 when anything blocks o + t·d, t in (tnear, tfar). */
int ref_occluded_upto(const sss_ref_scene *s, const double o[3], const double d[3], double tnear, double tfar);
/* The shading normal at point p (mm) of the plane of triangle f, from its
 * barycentrics (extrapolated outside the triangle): unit, or 0 on a
 * degenerate triangle. */
int ref_shading_normal_at(const sss_ref_scene *s, uint32_t f, const double p[3], double n[3]);
/* Where the ray o + t·d meets the plane of triangle f: t, or −1. */
double ref_plane_t(const sss_ref_scene *s, uint32_t f, const double o[3], const double d[3]);

/* ---- medium and paths (ref_walk.c) ---- */

typedef struct ref_medium {
    uint32_t C;                       /* channels: 1 when σa, σs agree in R, G, B */
    double sigma_a[3], sigma_s[3], sigma_t[3];
    double g, eta;
    /* a material field (sss_ref_medium's hetero): the inside material's σa,
     * σs at f = 1, the majorant σ̄ ≥ σt(x) everywhere (the largest σt of
     * both materials over the channels: the blend is linear in f ∈ [0, 1])
     * and the scene's mm per unit, for the field's rest frame */
    const struct sss_hetero *het;
    double sigma_a1[3], sigma_s1[3], sigma_bar, mm_per_unit;
} ref_medium;

void ref_medium_init(const sss_ref_medium *m, double mm_per_unit, ref_medium *out);

/* Everything one path needs. */
typedef struct ref_ctx {
    const sss_ref_scene *s;
    ref_medium m;
    sss_ref_light_kind light;
    double wl[3];             /* directional: unit, towards the light */
    double P[3];              /* point: the light's position, mm */
    double I;                 /* point: intensity per sr for distances in mm (the given one × mm_per_unit²) */
    const sss_probe *probe;   /* environment */
    uint32_t max_order;       /* 0: all */
    int no_nee;
    int no_nee_roulette;
} ref_ctx;

/* Per-thread counters (summed into sss_ref_stats). */
typedef struct ref_counters {
    uint64_t walks, rays, scatterings, nee, nee_hits, nee_unsolved, nee_skipped, leaks, truncated, crossed;
} ref_counters;

/* The first hit of o + t·d (t > tnear) seen from inside (want_out 1) or
 * from outside (0), passing through surfaces that face the other way
 * (counted in k->crossed unless within a few eps); 0 when none. */
int ref_hit_facing(const sss_ref_scene *s, const double o[3], const double d[3], double tnear, int want_out,
                   ref_hit *h, ref_counters *k);

/* One path of the radiance leaving surface point h towards wo (unit,
 * outside) through the surface, per channel into L[3] (channel 0 copied to
 * 1 and 2 for a grey medium). */
void ref_radiance_path(const ref_ctx *c, const ref_hit *h, const double wo[3], uint64_t *rng, double L[3],
                       ref_counters *k);

/* One particle of a beam along −c->wl through the disk of radius
 * bradius_mm about bcentre_mm: its outcome into t (incident 0 or 1, the
 * rest its weights). */
void ref_particle_path(const ref_ctx *c, const double bcentre_mm[3], double bradius_mm, uint64_t *rng,
                       sss_ref_tally *t, ref_counters *k);

/* The path's random stream: a hash of (seed, task, path). */
uint64_t ref_stream(uint64_t seed, uint64_t task, uint64_t path);

#endif
