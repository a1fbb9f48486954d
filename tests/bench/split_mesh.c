/* split_mesh: every triangle split into four at its edge midpoints, K
 * times, the surface itself unchanged (docs/accuracy.md, "Model error":
 * how much of the dipole's measured error is its per-vertex sum's, which
 * shrinks with the spacing, and how much is the model's, which does not).
 *
 *   split_mesh IN.ply OUT.ply [K]       (K = 1: 4× the triangles)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/import.h"

/* One 1-to-4 split of m into out; midpoints shared by an edge's two
 * triangles through a hash of the edge. */
static int split(const sss_mesh *m, sss_mesh *out, sss_error *err)
{
    const size_t ne = 3 * (size_t)m->nf, cap = 4 * ne + 7;
    uint64_t *key = malloc(cap * sizeof(uint64_t));
    uint32_t *val = malloc(cap * sizeof(uint32_t));
    if (!key || !val) return 0;
    memset(key, 0xff, cap * sizeof(uint64_t));
    /* at most nv + ne vertices */
    if (sss_mesh_alloc(out, m->nv + (uint32_t)ne, 4 * m->nf, err) != SSS_OK) return 0;
    memcpy(out->pos, m->pos, 3 * sizeof(float) * m->nv);
    uint32_t nv = m->nv;
    for (uint32_t f = 0; f < m->nf; f++) {
        const uint32_t *t = &m->tri[3 * (size_t)f];
        uint32_t mid[3];
        for (int e = 0; e < 3; e++) {
            uint32_t a = t[e], b = t[(e + 1) % 3];
            if (a > b) { uint32_t x = a; a = b; b = x; }
            const uint64_t k = (uint64_t)a << 32 | b;
            size_t h = (size_t)((k * 0x9E3779B97F4A7C15ull) % cap);
            while (key[h] != UINT64_MAX && key[h] != k) h = (h + 1) % cap;
            if (key[h] != k) {
                key[h] = k;
                val[h] = nv;
                for (int q = 0; q < 3; q++)
                    out->pos[3 * (size_t)nv + q] = 0.5f * (m->pos[3 * (size_t)a + q] + m->pos[3 * (size_t)b + q]);
                nv++;
            }
            mid[e] = val[h];
        }
        const uint32_t nt[4][3] = {{t[0], mid[0], mid[2]}, {mid[0], t[1], mid[1]}, {mid[2], mid[1], t[2]}, {mid[0], mid[1], mid[2]}};
        memcpy(&out->tri[12 * (size_t)f], nt, sizeof nt);
    }
    out->nv = nv;
    free(key);
    free(val);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: split_mesh IN.ply OUT.ply [K]\n");
        return 2;
    }
    const int K = argc > 3 ? atoi(argv[3]) : 1;
    sss_mesh m;
    sss_error err = {{0}};
    if (sss_import_mesh(argv[1], &m, NULL, &err) != SSS_OK) {
        fprintf(stderr, "split_mesh: %s\n", err.msg);
        return 1;
    }
    for (int k = 0; k < K; k++) {
        sss_mesh s;
        memset(&s, 0, sizeof s);
        if (!split(&m, &s, &err)) {
            fprintf(stderr, "split_mesh: out of memory %s\n", err.msg);
            return 1;
        }
        sss_mesh_free(&m);
        m = s;
    }
    if (sss_export_ply(argv[2], &m, &err) != SSS_OK) {
        fprintf(stderr, "split_mesh: %s\n", err.msg);
        return 1;
    }
    printf("split_mesh: %s: %u vertices, %u triangles\n", argv[2], m.nv, m.nf);
    sss_mesh_free(&m);
    return 0;
}
