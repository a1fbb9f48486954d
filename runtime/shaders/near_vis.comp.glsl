layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Pos { float pos[]; };
layout(std430, binding = 1) readonly buffer Nrm { float nrm[]; };
layout(std430, binding = 2) writeonly buffer Gv { float gv[]; };  // g V per vertex
layout(std430, binding = 4) writeonly buffer Lit { uint lit[]; };
uniform vec3 u_light;       // unit, towards the light
uniform float u_delta;      // the rays' offset, sss_mesh_ray_offset: the rule is applied here, not derived
uniform float u_eta;
uniform uint u_count;       // vertices
// g = F_t(eta, c) max(0, c), c = n.w: sss_near_g, term for term
float near_g(float eta, vec3 n, vec3 d) {
    precise float c = n.x * d.x + n.y * d.y + n.z * d.z;
    if (!(c > 0.0)) return 0.0;
    if (c > 1.0) c = 1.0;
    precise float g2 = eta * eta - 1.0 + c * c;
    if (g2 < 0.0) return 0.0;
    precise float g = sqrt(g2);
    precise float a = (g - c) / (g + c);
    precise float b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    precise float fr = min(0.5 * a * a * (1.0 + b * b), 1.0);
    precise float t = (1.0 - fr) * c;
    return t;
}
vec3 vtx(uint i) { return vec3(pos[3u * i], pos[3u * i + 1u], pos[3u * i + 2u]); }
#ifdef RAYS
// The BVH (bvh.h): inner node children a, a + 1, split axis b & 3; leaf:
// triangles a .. a + (b >> 2) - 1, 12 floats each (v0, e1, e2, Ng as Embree's
// TriangleM forms them)
struct Node { vec3 lo; uint a; vec3 hi; uint b; };
layout(std430, binding = 5) readonly buffer Nodes { Node node[]; };
layout(std430, binding = 6) readonly buffer Tris { float tri[]; };
uniform dvec3 u_light_d;    // u_light before rounding: the bake's facing test is in double
uniform uint u_ntri;        // triangles in the BVH (0: nothing can block)
// Embree's cross and dot, with the fused multiply-adds of its AVX2/AVX-512
// kernels (msub(a, b, c) = a b - c, madd(a, b, c) = a b + c); `precise`
// makes fma() one rounding and forbids fusing anything else
vec3 cross_e(vec3 a, vec3 b) {
    precise vec3 c = vec3(fma(a.y, b.z, -(a.z * b.y)), fma(a.z, b.x, -(a.x * b.z)), fma(a.x, b.y, -(a.y * b.x)));
    return c;
}
float dot_e(vec3 a, vec3 b) {
    precise float d = fma(a.x, b.x, fma(a.y, b.y, a.z * b.z));
    return d;
}
vec3 tri3(uint i) { return vec3(tri[i], tri[i + 1u], tri[i + 2u]); }
// Embree's Moller-Trumbore test (triangle_intersector_moeller.h): a hit with
// tnear < t, edges inclusive, no culling
bool tri_hit(uint t, vec3 o, vec3 d, float tnear) {
    uint i = 12u * t;
    vec3 v0 = tri3(i), e1 = tri3(i + 3u), e2 = tri3(i + 6u), ng = tri3(i + 9u);
    precise vec3 C = v0 - o;
    vec3 R = cross_e(C, d);
    float den = dot_e(ng, d);
    float ad = abs(den), sg = den < 0.0 ? -1.0 : 1.0; // Embree flips the sign bit: exact
    float U = sg * dot_e(R, e2), V = sg * dot_e(R, e1);
    precise float uv = U + V;
    if (!(den != 0.0 && U >= 0.0 && V >= 0.0 && uv <= ad)) return false;
    float T = sg * dot_e(ng, C);
    precise float near = ad * tnear;
    return near < T;
}
// Does the ray enter node i's box at t >= 0? Its entry t in t_in. The boxes
// are padded (bvh.h), so the slab test is conservative and needs no care
// beyond avoiding 0 * inf (inv holds 1e30 for a zero component).
bool box_hit(uint i, vec3 o, vec3 inv, out float t_in) {
    vec3 t0 = (node[i].lo - o) * inv, t1 = (node[i].hi - o) * inv;
    vec3 tn = min(t0, t1), tf = max(t0, t1);
    t_in = max(max(tn.x, tn.y), max(tn.z, 0.0));
    return t_in <= min(min(tf.x, tf.y), tf.z);
}
// Any hit along o + t d, t > tnear: stack traversal that tests both children's
// boxes at their parent and enters the nearer first (a shadow ray from the
// surface is most often blocked close to its origin)
bool occluded(vec3 o, vec3 d, float tnear) {
    vec3 inv = vec3(abs(d.x) > 1e-30 ? 1.0 / d.x : 1e30, abs(d.y) > 1e-30 ? 1.0 / d.y : 1e30,
                    abs(d.z) > 1e-30 ? 1.0 / d.z : 1e30);
    uint stack[SSS_BVH_STACK];
    uint sp = 0u, ni = 0u;
    float t0, t1;
    if (!box_hit(0u, o, inv, t0)) return false;
    for (;;) {
        uint a = node[ni].a, cnt = node[ni].b >> 2u;
        if (cnt == 0u) {
            bool h0 = box_hit(a, o, inv, t0), h1 = box_hit(a + 1u, o, inv, t1);
            if (h0 && h1) {
                uint first = t1 < t0 ? 1u : 0u;
                stack[sp++] = a + 1u - first;
                ni = a + first;
                continue;
            }
            if (h0 || h1) {
                ni = h0 ? a : a + 1u;
                continue;
            }
        } else {
            for (uint k = 0u; k < cnt; k++)
                if (tri_hit(a + k, o, d, tnear)) return true;
        }
        if (sp == 0u) return false;
        ni = stack[--sp];
    }
}
void main() {
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_count) return;
    vec3 n = vec3(nrm[3u * v], nrm[3u * v + 1u], nrm[3u * v + 2u]);
    // the bake traces where n.w > 0 in double (float n, double w), left to right
    precise double c = double(n.x) * u_light_d.x + double(n.y) * u_light_d.y + double(n.z) * u_light_d.z;
    uint vis = 0u;
    if (c > 0.0lf) {
        // the bake's origin x + delta n in float, product and sum rounded apart
        precise vec3 o = vtx(v) + u_delta * n;
        vis = u_ntri == 0u || !occluded(o, u_light, u_delta) ? 1u : 0u;
    }
    lit[v] = vis;
    gv[v] = vis != 0u ? near_g(u_eta, n, u_light) : 0.0;
}
#else
layout(std430, binding = 5) readonly buffer Tri { uint tri[]; };
// incident triangles of vertex v: fan[fan[v]] .. fan[fan[v + 1] - 1]
layout(std430, binding = 6) readonly buffer Fan { uint fan[]; };
// sin of the largest angle between n_v and its triangles' normals: above it no hit
layout(std430, binding = 3) readonly buffer FanSin { float fan_sin[]; };
// Does the bake's ray (from x + delta n towards d, beyond t = delta) hit one of
// the triangles around x? (Moller-Trumbore.) They lie within a fraction of a
// texel of the vertex, where the map cannot tell them from its own surface.
bool fan_blocks(uint v, vec3 x, vec3 n, vec3 d) {
    vec3 o = x + u_delta * n;
    for (uint k = fan[v]; k < fan[v + 1u]; k++) {
        uint t = 3u * fan[k];
        vec3 a = vtx(tri[t]), e1 = vtx(tri[t + 1u]) - a, e2 = vtx(tri[t + 2u]) - a;
        vec3 h = cross(d, e2);
        float det = dot(e1, h);
        if (det == 0.0) continue;
        vec3 s = o - a;
        float u = dot(s, h) / det;
        if (u < 0.0 || u > 1.0) continue;
        vec3 qv = cross(s, e1);
        float w = dot(d, qv) / det;
        if (w < 0.0 || u + w > 1.0) continue;
        if (dot(e2, qv) / det > u_delta) return true;
    }
    return false;
}
void main() {
    uint v = gl_GlobalInvocationID.x;
    if (v >= u_count) return;
    vec3 n = vec3(nrm[3u * v], nrm[3u * v + 1u], nrm[3u * v + 2u]);
    precise float c = n.x * u_light.x + n.y * u_light.y + n.z * u_light.z;
    uint vis = 0u;
    if (c > 0.0 && (c > fan_sin[v] || !fan_blocks(v, vtx(v), n, u_light))) {
        // Hao-Varshney 2004 3.1: transform the vertex into light space and
        // compare its depth with the depth image (shadow_map.glsl)
        vis = shadow_map_lit(vtx(v), n, c) ? 1u : 0u;
    }
    lit[v] = vis;
    gv[v] = vis != 0u ? near_g(u_eta, n, u_light) : 0.0;
}
#endif
