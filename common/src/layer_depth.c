/* layer_depth.c: depth maps' samples, procedural depths and per-vertex
 * stacks (sss/layer_depth.h; docs/layers.md §3). */
#include "sss/layer_depth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/field.h"

/* t wrapped into [0, 1) */
static double wrap01(double t)
{
    t -= floor(t);
    return t >= 1.0 ? 0.0 : t;
}

double sss_depth_image_sample(const sss_depth_image *im, double u, double v)
{
    if (!im || !im->value || !im->w || !im->h || !isfinite(u) || !isfinite(v)) return 0.0;
    /* sample centres at (i + 1/2)/w; the image's top row at v = 1 */
    const double x = wrap01(u) * im->w - 0.5, y = (1.0 - wrap01(v)) * im->h - 0.5;
    const double fx = floor(x), fy = floor(y), a = x - fx, b = y - fy;
    const long long i0 = (long long)fx, j0 = (long long)fy;
    const long long W = im->w, H = im->h;
    /* the neighbours across the edge wrap too */
    const long long i[2] = {(i0 % W + W) % W, ((i0 + 1) % W + W) % W}, j[2] = {(j0 % H + H) % H, ((j0 + 1) % H + H) % H};
    const double s00 = im->value[j[0] * W + i[0]], s10 = im->value[j[0] * W + i[1]];
    const double s01 = im->value[j[1] * W + i[0]], s11 = im->value[j[1] * W + i[1]];
    return (1 - b) * ((1 - a) * s00 + a * s10) + b * ((1 - a) * s01 + a * s11);
}

void sss_depth_image_free(sss_depth_image *im)
{
    if (!im) return;
    free(im->value);
    memset(im, 0, sizeof *im);
}

double sss_depth_procedural(const sss_depth_spec *s, const double x[3])
{
    double f = 0.0;
    sss_field fd;
    memset(&fd, 0, sizeof fd);
    fd.seed = s->seed;
    fd.scale_mm = s->scale_mm;
    switch (s->pattern) {
    case SSS_DEPTH_VEINS:
        fd.kind = SSS_FIELD_VEINS;
        f = sss_field_eval(&fd, x);
        break;
    case SSS_DEPTH_BLOBS:
        fd.kind = SSS_FIELD_INCLUSIONS;
        fd.thickness_mm = 0.3 * s->scale_mm; /* the scene's inclusions' default radius (docs/heterogeneous.md §2) */
        fd.edge_mm = 0.1 * s->scale_mm;
        f = sss_field_eval(&fd, x);
        break;
    case SSS_DEPTH_BUMPS: f = sss_field_noise(x, s->scale_mm, s->seed); break;
    default: break;
    }
    return s->range_mm[0] + (s->range_mm[1] - s->range_mm[0]) * f;
}

void sss_layer_depths_monotone(float *d, uint32_t n)
{
    for (uint32_t k = 1; k < n; k++)
        if (d[k] < d[k - 1]) d[k] = d[k - 1];
}

void sss_layer_stack_at(const sss_layer_stack *st, const float *layer_depth, uint32_t v, sss_layer_stack *out)
{
    *out = *st;
    if (!layer_depth) return;
    for (uint32_t k = 0; k < st->n && k < SSS_MAX_LAYERS; k++)
        out->layer[k].depth = layer_depth[(size_t)v * st->n + k];
}
