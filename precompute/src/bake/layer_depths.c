/* layer_depths.c: every layer's depth at every vertex of a scene object
 * (sss/layer_depths.h; docs/layers.md §3), what section LDEP stores. */
#include "sss/layer_depths.h"

#include <stdlib.h>
#include <string.h>

#include "sss/depthmap.h"
#include "sss/field.h"

sss_result sss_layer_depths_eval(const sss_scene *scene, uint32_t obj, const sss_mesh *world, float **layer_depth,
                                 sss_layer_stack *stack, sss_error *err)
{
    *layer_depth = NULL;
    const sss_scene_object *ob = &scene->objects[obj];
    const uint32_t n = ob->layers.n;
    int varies = 0;
    for (uint32_t k = 0; k < n; k++) varies |= ob->layer_depth[k].kind != SSS_DEPTH_CONSTANT;
    if (!varies) return SSS_OK;
    const uint32_t nv = world->nv;
    float *d = malloc((size_t)nv * n * sizeof(float) + 1);
    if (!d) return sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u x %u layer depths", nv, n);
    sss_result r = SSS_OK;
    for (uint32_t k = 0; k < n && r == SSS_OK; k++) {
        const sss_depth_spec *s = &ob->layer_depth[k];
        if (s->kind == SSS_DEPTH_CONSTANT) {
            for (uint32_t v = 0; v < nv; v++) d[(size_t)v * n + k] = (float)ob->layers.layer[k].depth;
        } else if (s->kind == SSS_DEPTH_MAP) {
            if (!world->uv) {
                r = sss_fail(err, SSS_ERR_MESH, "material/layers/%u/depth_mm: the depth map %s needs texture "
                             "coordinates, and the mesh %s has none", k, s->map, ob->mesh);
                break;
            }
            sss_depth_image im;
            sss_error e2 = {{0}};
            const sss_result rr = sss_depth_map_read(s->map, &im, &e2);
            if (rr != SSS_OK) {
                r = sss_fail(err, rr, "material/layers/%u/depth_mm/map: %s", k, e2.msg);
                break;
            }
            /* depth = value / max · scale_mm (the map's value at (u, v)) */
            for (uint32_t v = 0; v < nv; v++)
                d[(size_t)v * n + k] = (float)(sss_depth_image_sample(&im, world->uv[2 * (size_t)v],
                                                                      world->uv[2 * (size_t)v + 1]) * s->scale_mm);
            sss_depth_image_free(&im);
        } else {
            /* at rest-frame positions (mm): a rigid transform of the object
             * moves its depths with it (sss/field.h's frame) */
            for (uint32_t v = 0; v < nv; v++) {
                const float *p = &world->pos[3 * (size_t)v];
                const double pw[3] = {p[0], p[1], p[2]};
                double x[3];
                sss_hetero_to_rest(&ob->hetero, pw, x);
                d[(size_t)v * n + k] = (float)sss_depth_procedural(s, x);
            }
        }
    }
    if (r != SSS_OK) {
        free(d);
        return r;
    }
    for (uint32_t k = 0; k < n; k++) stack->layer[k].depth = 0.0;
    for (uint32_t v = 0; v < nv; v++) {
        float *dv = &d[(size_t)v * n];
        sss_layer_depths_monotone(dv, n);
        for (uint32_t k = 0; k < n; k++)
            if (dv[k] > stack->layer[k].depth) stack->layer[k].depth = dv[k];
    }
    *layer_depth = d;
    return SSS_OK;
}
