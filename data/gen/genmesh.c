/* genmesh.c: procedural test meshes (see genmesh.h). */
#include "genmesh.h"
#include "sss/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Growable mesh builder with a vertex-weld table keyed by exact position. */
typedef struct builder {
    float *pos; uint32_t nv, cap_v;
    float *uv;  /* 2 * cap_v texture coordinates, or NULL (the mesh has none) */
    uint32_t *tri; uint32_t nf, cap_f;
    int failed;
} builder;

static uint32_t b_vertex(builder *b, double x, double y, double z)
{
    if (b->nv == b->cap_v) {
        uint32_t cap = b->cap_v ? 2 * b->cap_v : 1024;
        float *p = realloc(b->pos, (size_t)cap * 3 * sizeof(float));
        if (!p) { b->failed = 1; return 0; }
        b->pos = p;
        if (b->uv) {
            float *t = realloc(b->uv, (size_t)cap * 2 * sizeof(float));
            if (!t) { b->failed = 1; return 0; }
            b->uv = t;
        }
        b->cap_v = cap;
    }
    b->pos[3 * (size_t)b->nv + 0] = (float)x;
    b->pos[3 * (size_t)b->nv + 1] = (float)y;
    b->pos[3 * (size_t)b->nv + 2] = (float)z;
    return b->nv++;
}

/* Texture coordinates (u, v) of vertex i (docs/layers.md §3: what a depth
 * map is read at); the first call gives the mesh texture coordinates. */
static void b_uv(builder *b, uint32_t i, double u, double v)
{
    if (b->failed) return;
    if (!b->uv && !(b->uv = calloc((size_t)b->cap_v * 2 + 2, sizeof(float)))) { b->failed = 1; return; }
    b->uv[2 * (size_t)i] = (float)u;
    b->uv[2 * (size_t)i + 1] = (float)v;
}

static void b_tri(builder *b, uint32_t i, uint32_t j, uint32_t k)
{
    if (b->nf == b->cap_f) {
        uint32_t cap = b->cap_f ? 2 * b->cap_f : 2048;
        uint32_t *t = realloc(b->tri, (size_t)cap * 3 * sizeof(uint32_t));
        if (!t) { b->failed = 1; return; }
        b->tri = t; b->cap_f = cap;
    }
    b->tri[3 * (size_t)b->nf + 0] = i;
    b->tri[3 * (size_t)b->nf + 1] = j;
    b->tri[3 * (size_t)b->nf + 2] = k;
    b->nf++;
}

static sss_result b_finish(builder *b, sss_mesh *m, const char *name, sss_error *err)
{
    memset(m, 0, sizeof *m);
    if (b->failed) {
        free(b->pos); free(b->tri); free(b->uv);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", name);
    }
    m->pos = b->pos; m->nv = b->nv;
    m->uv = b->uv;
    m->tri = b->tri; m->nf = b->nf;
    sss_result r = sss_mesh_compute_normals_areas(m, name, err);
    if (r != SSS_OK) sss_mesh_free(m);
    return r;
}

/* Edge-midpoint cache for icosphere subdivision: key (min, max) → vertex. */
typedef struct { uint64_t *key; uint32_t *val; size_t cap; } edge_map;

/* The slot of edge (i, j), either way round: where its key is, or the
 * empty slot (key UINT64_MAX) where it goes. */
static size_t em_slot(const edge_map *em, uint32_t i, uint32_t j)
{
    const uint64_t a = i < j ? i : j, c = i < j ? j : i, key = (a << 32) | c;
    size_t h = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & (em->cap - 1);
    while (em->key[h] != UINT64_MAX && em->key[h] != key) h = (h + 1) & (em->cap - 1);
    return h;
}

static uint32_t midpoint(builder *b, edge_map *em, uint32_t i, uint32_t j, double radius)
{
    const uint64_t key = ((uint64_t)(i < j ? i : j) << 32) | (i < j ? j : i);
    const size_t h = em_slot(em, i, j);
    if (em->key[h] == key) return em->val[h];
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = 0.5 * ((double)b->pos[3 * (size_t)i + k] + b->pos[3 * (size_t)j + k]);
    double len = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    uint32_t v = b_vertex(b, p[0] / len * radius, p[1] / len * radius, p[2] / len * radius);
    em->key[h] = key;
    em->val[h] = v;
    return v;
}

sss_result sss_gen_sphere(sss_mesh *m, double radius, unsigned subdiv, sss_error *err)
{
    if (subdiv > 10 || !(radius > 0)) return sss_fail(err, SSS_ERR_ARG, "sphere: subdivisions %u (max 10), radius %g", subdiv, radius);
    builder b = {0};
    const double t = (1.0 + sqrt(5.0)) / 2.0, s = radius / sqrt(1.0 + t * t);
    const double iv[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    static const uint32_t it[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                       {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int i = 0; i < 12; i++) b_vertex(&b, iv[i][0] * s, iv[i][1] * s, iv[i][2] * s);
    for (int i = 0; i < 20; i++) b_tri(&b, it[i][0], it[i][1], it[i][2]);
    for (unsigned l = 0; l < subdiv && !b.failed; l++) {
        edge_map em;
        em.cap = 1;
        while (em.cap < (size_t)b.nf * 4) em.cap <<= 1;
        em.key = malloc(em.cap * sizeof *em.key);
        em.val = malloc(em.cap * sizeof *em.val);
        uint32_t *old = b.tri, nf = b.nf;
        b.tri = NULL; b.nf = b.cap_f = 0;
        if (!em.key || !em.val) { b.failed = 1; free(em.key); free(em.val); free(old); break; }
        memset(em.key, 0xff, em.cap * sizeof *em.key);
        for (uint32_t f = 0; f < nf; f++) {
            uint32_t a = old[3 * f], c = old[3 * f + 1], d = old[3 * f + 2];
            uint32_t ab = midpoint(&b, &em, a, c, radius), bc = midpoint(&b, &em, c, d, radius),
                     ca = midpoint(&b, &em, d, a, radius);
            b_tri(&b, a, ab, ca); b_tri(&b, c, bc, ab); b_tri(&b, d, ca, bc); b_tri(&b, ab, bc, ca);
        }
        free(old); free(em.key); free(em.val);
    }
    /* spherical coordinates about z: u the longitude over 2π from −x, v the
     * latitude from the south pole (vertices are welded, so the triangles
     * across u = 0 ≡ 1 span the seam) */
    for (uint32_t i = 0; i < b.nv && !b.failed; i++) {
        const double x = b.pos[3 * (size_t)i], y = b.pos[3 * (size_t)i + 1], z = b.pos[3 * (size_t)i + 2];
        const double zr = fmax(-1.0, fmin(1.0, z / sqrt(x * x + y * y + z * z)));
        b_uv(&b, i, 0.5 + atan2(y, x) / (2 * SSS_PI), 0.5 + asin(zr) / SSS_PI);
    }
    return b_finish(&b, m, "sphere", err);
}

sss_result sss_gen_plane(sss_mesh *m, double sx, double sy, unsigned nx, unsigned ny, sss_error *err)
{
    if (nx < 1 || ny < 1 || (uint64_t)(nx + 1) * (ny + 1) > 50000000u)
        return sss_fail(err, SSS_ERR_ARG, "plane: %u x %u segments out of range", nx, ny);
    builder b = {0};
    for (unsigned j = 0; j <= ny; j++)
        for (unsigned i = 0; i <= nx; i++)
            b_uv(&b, b_vertex(&b, sx * ((double)i / nx - 0.5), sy * ((double)j / ny - 0.5), 0.0), (double)i / nx,
                 (double)j / ny);
    for (unsigned j = 0; j < ny; j++)
        for (unsigned i = 0; i < nx; i++) {
            uint32_t v00 = j * (nx + 1) + i, v10 = v00 + 1, v01 = v00 + nx + 1, v11 = v01 + 1;
            b_tri(&b, v00, v10, v11);
            b_tri(&b, v00, v11, v01);
        }
    return b_finish(&b, m, "plane", err);
}

sss_result sss_gen_box(sss_mesh *m, double sx, double sy, double sz, unsigned n, int inward, sss_error *err)
{
    if (n < 1 || n > 1024) return sss_fail(err, SSS_ERR_ARG, "box: %u segments out of range [1, 1024]", n);
    builder b = {0};
    size_t side = (size_t)n + 1;
    uint32_t *lat = malloc(side * side * side * sizeof(uint32_t)); /* lattice (i,j,k) → vertex, welds edges */
    if (!lat) return sss_fail(err, SSS_ERR_NOMEM, "box: out of memory");
    memset(lat, 0xff, side * side * side * sizeof(uint32_t));
    const double h[3] = {sx, sy, sz};
    /* Each face: fixed axis a at side s (0 or n); u, v span the other axes so
     * that (u × v) points outward. */
    for (int a = 0; a < 3; a++)
        for (int sgn = 0; sgn < 2; sgn++) {
            int u = (a + 1) % 3, v = (a + 2) % 3;
            if (!sgn) { int t = u; u = v; v = t; }
            for (unsigned j = 0; j < n; j++)
                for (unsigned i = 0; i < n; i++) {
                    uint32_t q[4];
                    const unsigned du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
                    for (int c = 0; c < 4; c++) {
                        unsigned L[3];
                        L[a] = sgn ? n : 0; L[u] = i + du[c]; L[v] = j + dv[c];
                        size_t key = ((size_t)L[0] * side + L[1]) * side + L[2];
                        if (lat[key] == UINT32_MAX) {
                            double p[3];
                            for (int k = 0; k < 3; k++) p[k] = h[k] * ((double)L[k] / n - 0.5);
                            lat[key] = b_vertex(&b, p[0], p[1], p[2]);
                        }
                        q[c] = lat[key];
                    }
                    if (inward) { b_tri(&b, q[0], q[2], q[1]); b_tri(&b, q[0], q[3], q[2]); }
                    else { b_tri(&b, q[0], q[1], q[2]); b_tri(&b, q[0], q[2], q[3]); }
                }
        }
    free(lat);
    return b_finish(&b, m, "box", err);
}

sss_result sss_gen_torus(sss_mesh *m, double R, double r, unsigned nu, unsigned nv, sss_error *err)
{
    if (nu < 3 || nv < 3 || (uint64_t)nu * nv > 50000000u || !(R > r) || !(r > 0))
        return sss_fail(err, SSS_ERR_ARG, "torus: bad parameters (R %g, r %g, %u x %u)", R, r, nu, nv);
    builder b = {0};
    for (unsigned i = 0; i < nu; i++)
        for (unsigned j = 0; j < nv; j++) {
            double u = 2 * SSS_PI * i / nu, v = 2 * SSS_PI * j / nv;
            b_uv(&b, b_vertex(&b, (R + r * cos(v)) * cos(u), (R + r * cos(v)) * sin(u), r * sin(v)), (double)i / nu,
                 (double)j / nv);
        }
    for (unsigned i = 0; i < nu; i++)
        for (unsigned j = 0; j < nv; j++) {
            uint32_t a = i * nv + j, c = ((i + 1) % nu) * nv + j, d = ((i + 1) % nu) * nv + (j + 1) % nv,
                     e = i * nv + (j + 1) % nv;
            b_tri(&b, a, c, d);
            b_tri(&b, a, d, e);
        }
    return b_finish(&b, m, "torus", err);
}

sss_result sss_gen_tube(sss_mesh *m, double radius, double length, unsigned nring, unsigned nseg, sss_error *err)
{
    if (nring < 3 || nseg < 1 || (uint64_t)nring * (nseg + 1) > 50000000u || !(radius > 0) || !(length > 0))
        return sss_fail(err, SSS_ERR_ARG, "tube: bad parameters (radius %g, length %g, %u x %u)", radius, length,
                        nring, nseg);
    builder b = {0};
    for (unsigned i = 0; i <= nseg; i++)
        for (unsigned j = 0; j < nring; j++) {
            const double u = 2 * SSS_PI * j / nring;
            b_uv(&b, b_vertex(&b, radius * cos(u), radius * sin(u), length * ((double)i / nseg - 0.5)), (double)j / nring,
                 (double)i / nseg);
        }
    const uint32_t bottom = (nseg + 1) * nring, top = bottom + 1;
    b_uv(&b, b_vertex(&b, 0.0, 0.0, -0.5 * length), 0.5, 0.0); /* the caps' centres: v at their ring's */
    b_uv(&b, b_vertex(&b, 0.0, 0.0, 0.5 * length), 0.5, 1.0);
    for (unsigned i = 0; i < nseg; i++)
        for (unsigned j = 0; j < nring; j++) { /* side quads, outward: (around) × (along z) is radial */
            const uint32_t a = i * nring + j, c = i * nring + (j + 1) % nring, d = (i + 1) * nring + (j + 1) % nring,
                           e = (i + 1) * nring + j;
            b_tri(&b, a, c, d);
            b_tri(&b, a, d, e);
        }
    for (unsigned j = 0; j < nring; j++) { /* caps: fans about their centres, facing −z and +z */
        b_tri(&b, bottom, (j + 1) % nring, j);
        b_tri(&b, top, nseg * nring + j, nseg * nring + (j + 1) % nring);
    }
    return b_finish(&b, m, "tube", err);
}

sss_result sss_gen_blob(sss_mesh *m, double radius, unsigned subdiv, sss_error *err)
{
    sss_result r = sss_gen_sphere(m, 1.0, subdiv, err);
    if (r != SSS_OK) return r;
    for (uint32_t v = 0; v < m->nv; v++) {
        float *p = &m->pos[3 * (size_t)v];
        double x = p[0], y = p[1], z = p[2];
        /* Low-frequency lobes deep enough to make concavities that shadow. */
        double k = 1.0 + 0.22 * sin(3.0 * x + 1.0) * cos(2.0 * y) + 0.18 * cos(4.0 * z + 0.5 * x) + 0.08 * sin(5.0 * y + z);
        for (int c = 0; c < 3; c++) p[c] = (float)(p[c] * k * radius);
    }
    r = sss_mesh_compute_normals_areas(m, "blob", err);
    if (r != SSS_OK) sss_mesh_free(m);
    return r;
}

sss_result sss_mesh_append(sss_mesh *a, const sss_mesh *b, sss_error *err)
{
    sss_mesh c;
    sss_result r = sss_mesh_alloc(&c, a->nv + b->nv, a->nf + b->nf, err);
    if (r != SSS_OK) return r;
    memcpy(c.pos, a->pos, (size_t)a->nv * 3 * sizeof(float));
    memcpy(c.pos + (size_t)a->nv * 3, b->pos, (size_t)b->nv * 3 * sizeof(float));
    memcpy(c.tri, a->tri, (size_t)a->nf * 3 * sizeof(uint32_t));
    for (size_t i = 0; i < (size_t)b->nf * 3; i++) c.tri[(size_t)a->nf * 3 + i] = b->tri[i] + a->nv;
    r = sss_mesh_compute_normals_areas(&c, "merged mesh", err);
    if (r != SSS_OK) { sss_mesh_free(&c); return r; }
    sss_mesh_free(a);
    *a = c;
    return SSS_OK;
}

/* Two spheres of `subdiv` subdivisions, far apart: one of radius 250·r at
 * the origin, one of radius r beyond it (larger coordinates, so later in
 * Morton order). With r = 12 mm and a 32 mm scattering cutoff, every
 * vertex of the small sphere sees all the others and one of the large
 * sphere sees only itself: half the receivers hold almost all the work of
 * the gather (tests/integration/cli_progress.sh). */
static sss_result gen_pair(sss_mesh *m, double r, unsigned subdiv, sss_error *err)
{
    sss_mesh small;
    sss_result res = sss_gen_sphere(m, 250.0 * r, subdiv, err);
    if (res != SSS_OK) return res;
    res = sss_gen_sphere(&small, r, subdiv, err);
    if (res != SSS_OK) {
        sss_mesh_free(m);
        return res;
    }
    for (size_t i = 0; i < (size_t)small.nv * 3; i++) small.pos[i] += (float)(350.0 * r);
    res = sss_mesh_append(m, &small, err);
    sss_mesh_free(&small);
    if (res != SSS_OK) sss_mesh_free(m);
    return res;
}

/* Vertex k of n − 1 on edge (i, j), counted from i (k in 1 .. n − 1): the
 * edge's points are made once, from its lower index to its higher, when
 * the edge is first met, so both triangles on it share them. */
static uint32_t edge_point(builder *b, edge_map *em, uint32_t i, uint32_t j, unsigned k, unsigned n)
{
    const uint64_t key = ((uint64_t)(i < j ? i : j) << 32) | (i < j ? j : i);
    const size_t h = em_slot(em, i, j);
    if (em->key[h] != key) {
        const uint32_t lo = i < j ? i : j, hi = i < j ? j : i;
        em->key[h] = key;
        em->val[h] = b->nv;
        for (unsigned s = 1; s < n; s++) {
            double p[3];
            for (int c = 0; c < 3; c++) {
                const double x0 = b->pos[3 * (size_t)lo + c], x1 = b->pos[3 * (size_t)hi + c];
                p[c] = x0 + (x1 - x0) * s / n;
            }
            b_vertex(b, p[0], p[1], p[2]);
        }
    }
    return em->val[h] + (i < j ? k - 1 : n - k - 1);
}

sss_result sss_gen_subdivide(const sss_mesh *in, unsigned n, sss_mesh *m, sss_error *err)
{
    memset(m, 0, sizeof *m);
    const uint64_t nf = (uint64_t)in->nf * n * n, nv_max = in->nv + 3ull * in->nf * n * n;
    if (n < 1 || n > 1000 || nf > 200000000u || nv_max > UINT32_MAX)
        return sss_fail(err, SSS_ERR_ARG, "subdivide: %u segments per edge of %u triangles out of range", n, in->nf);
    builder b = {0};
    for (uint32_t v = 0; v < in->nv; v++)
        b_vertex(&b, in->pos[3 * (size_t)v], in->pos[3 * (size_t)v + 1], in->pos[3 * (size_t)v + 2]);
    edge_map em;
    em.cap = 1;
    while (em.cap < (size_t)in->nf * 4) em.cap <<= 1;
    em.key = malloc(em.cap * sizeof *em.key);
    em.val = malloc(em.cap * sizeof *em.val);
    uint32_t *grid = malloc((size_t)(n + 1) * (n + 1) * sizeof *grid);
    if (!em.key || !em.val || !grid) b.failed = 1;
    else memset(em.key, 0xff, em.cap * sizeof *em.key);
    for (uint32_t f = 0; f < in->nf && !b.failed; f++) {
        const uint32_t A = in->tri[3 * (size_t)f], B = in->tri[3 * (size_t)f + 1], C = in->tri[3 * (size_t)f + 2];
        /* grid point (i, j) = A + (B − A) i/n + (C − A) j/n, i + j <= n */
#define G(i, j) grid[(size_t)(i) * (n + 1) + (j)]
        for (unsigned i = 0; i <= n; i++)
            for (unsigned j = 0; i + j <= n; j++) {
                uint32_t v;
                if (i == 0 && j == 0) v = A;
                else if (i == n) v = B;
                else if (j == n) v = C;
                else if (j == 0) v = edge_point(&b, &em, A, B, i, n);
                else if (i == 0) v = edge_point(&b, &em, A, C, j, n);
                else if (i + j == n) v = edge_point(&b, &em, B, C, j, n);
                else {
                    double p[3];
                    for (int c = 0; c < 3; c++) {
                        const double a = in->pos[3 * (size_t)A + c], bb = in->pos[3 * (size_t)B + c],
                                     cc = in->pos[3 * (size_t)C + c];
                        p[c] = a + (bb - a) * i / n + (cc - a) * j / n;
                    }
                    v = b_vertex(&b, p[0], p[1], p[2]);
                }
                G(i, j) = v;
            }
        /* the winding of (A, B, C) in every small triangle */
        for (unsigned i = 0; i < n; i++)
            for (unsigned j = 0; i + j < n; j++) {
                b_tri(&b, G(i, j), G(i + 1, j), G(i, j + 1));
                if (i + j + 1 < n) b_tri(&b, G(i + 1, j), G(i + 1, j + 1), G(i, j + 1));
            }
#undef G
    }
    free(grid);
    free(em.key);
    free(em.val);
    return b_finish(&b, m, "subdivide", err);
}

sss_result sss_gen_by_name(const char *kind, unsigned res, double size, sss_mesh *m, sss_error *err)
{
    if (!(size > 0)) size = 1.0;
    if (!strcmp(kind, "pair")) return gen_pair(m, size, res, err);
    if (!strcmp(kind, "sphere")) return sss_gen_sphere(m, size, res, err);
    if (!strcmp(kind, "blob")) return sss_gen_blob(m, size, res, err);
    if (!strcmp(kind, "plane")) return sss_gen_plane(m, size, size, res, res, err);
    if (!strcmp(kind, "cube") || !strcmp(kind, "box")) return sss_gen_box(m, size, size, size, res, 0, err);
    if (!strcmp(kind, "slab")) return sss_gen_box(m, size, size, size / 50.0, res, 0, err);
    if (!strcmp(kind, "torus")) return sss_gen_torus(m, size, size / 3.0, 2 * res, res, err);
    if (!strcmp(kind, "tube")) return sss_gen_tube(m, 0.5 * size, 4.0 * size, 2 * res, 4 * res, err);
    return sss_fail(err, SSS_ERR_ARG, "unknown mesh kind '%s' (sphere, blob, plane, cube, slab, torus, tube, pair)",
                    kind);
}
