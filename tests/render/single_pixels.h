/* single_pixels.h: what a pixel of sss-view's image shows, on the CPU, for
 * checking single scattering per pixel (docs/layers.md §8) against
 * sss_ss_mesh_point: test_render_single and the single_gpu_error bench
 * include it once. */
#ifndef SSS_TEST_SINGLE_PIXELS_H
#define SSS_TEST_SINGLE_PIXELS_H

#include <math.h>
#include <stdint.h>

#include "sss/bvh.h"
#include "sss/render.h"
#include "sss/vec3.h"

/* Pixel (x, y) of the image (row 0 at the bottom, as glReadPixels) seen by
 * the camera of p: the surface point, its interpolated normal and the
 * direction towards the eye; 0 where the ray misses the mesh. */
static int pixel_point(const sss_renderer *r, const sss_mesh *m, const sss_bvh *bvh, const sss_view_params *p,
                       int W, int H, int x, int y, double P[3], double n[3], double v[3])
{
    double eye[3], right[3], up[3], fwd[3];
    sss_renderer_camera(r, p, eye, right, up, fwd);
    const double fy = 1.0 / tan(0.5 * p->fov_deg * SSS_PI / 180.0), aspect = (double)W / H;
    const double nx = 2.0 * (x + 0.5) / W - 1.0, ny = 2.0 * (y + 0.5) / H - 1.0;
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = fwd[k] + nx * aspect / fy * right[k] + ny / fy * up[k];
    sss_normalize3(d);
    const float o[3] = {(float)eye[0], (float)eye[1], (float)eye[2]}, df[3] = {(float)d[0], (float)d[1], (float)d[2]};
    uint32_t prim = UINT32_MAX;
    const float t = sss_bvh_nearest(bvh, o, df, 0.0f, &prim);
    if (!isfinite(t) || prim == UINT32_MAX) return 0;
    for (int k = 0; k < 3; k++) P[k] = eye[k] + t * d[k], v[k] = -d[k];
    sss_mesh_normal_at(m, prim, P, n); /* the rasteriser's interpolation */
    return 1;
}

#endif
