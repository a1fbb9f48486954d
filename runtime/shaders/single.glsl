// Single scattering per pixel (docs/layers.md §8): Jensen et al. 2001's
// S(1) marched along the refracted view ray as seed 002 (Algorithm 1) does,
// or with the per-segment closed form (docs/layers.md §3), the light's entry
// point K from a light-space map of the surface nearest the light (its
// position and triangle per texel, effects/single.c) and the march's end
// where the view ray leaves the object from a camera-space map of the
// nearest back faces (the same per pixel). The formulas are those of
// common/src/single.c and common/src/single_mesh.c, which are the CPU
// oracle of this pass (sss_ss_mesh_point): the same geometry
// (sss_ss_geometry), the same layer rule (seed 002 Eq. 12,
// sss_layers_tau_path), the same entry weight at K and the same focusing
// of the refracted beam by a curved surface.
// Included in the shading fragment shader before shade.frag.glsl; only the
// program draw.c compiles with SSS_SINGLE holds it.
#ifdef SSS_SINGLE
#define SS_CAST_STEPS 4          // triangle planes a cast steps through before it bisects
#define SS_MAXL 9                // 8 layers of a file + the material beneath
uniform int u_ss_n;              // N: segments (or Algorithm 1's samples)
uniform int u_ss_seed;           // 1: seed 002's Algorithm 1; 0: the per-segment closed form
uniform int u_ss_schlick;        // the stack's phase: 1 Schlick (k = g), 0 Henyey-Greenstein
uniform int u_ss_nl;             // layers in the stack, the material included (1 ... SS_MAXL)
uniform vec3 u_ss_sigma_s[SS_MAXL], u_ss_sigma_t[SS_MAXL]; // 1/mm, per channel
uniform float u_ss_g[SS_MAXL];
uniform float u_ss_mm;           // mm per mesh unit
uniform float u_ss_smax_cap;     // 16 / (smallest sigma_t): where the view ray's light is gone, mm
uniform sampler2D u_ss_kpos;     // light space: the nearest surface's position, w = its triangle + 1 (0: none)
uniform mat4 u_ss_light;         // world -> (s, t, z) of the light map
uniform int u_ss_size;           // the light map's texels per side
uniform sampler2D u_ss_bpos;     // camera: the nearest back face's position, w = its triangle + 1 (0: none)
uniform mat4 u_ss_mvp;           // the camera's matrix (as the vertex shader's u_mvp)
in float v_ld[8];                // the layers' lower boundaries at this point, mm (the entry point P's)
// the mesh itself (the renderer's vertex and index buffers): a map texel
// names its triangle, whose plane and interpolated normal are exact
layout(std430, binding = 0) readonly buffer SSP { float ss_pos[]; };
layout(std430, binding = 1) readonly buffer SSN { float ss_nrm[]; };
layout(std430, binding = 2) readonly buffer SST { uint ss_tri[]; };
// fresnel_r(η, cos θ): fresnel.glsl, which the shading program puts before this part
uniform float u_ss_eta;              // the material's relative index (as shade.frag.glsl's u_eta)
const float PI_SS = 3.14159265358979;

float ss_ft(float eta, float c) { return c > 0.0 ? 1.0 - fresnel_r(eta, c) : 0.0; } // sss_ft
float ss_phase(float g, float c) {   // sss_phase_eval
    if (u_ss_schlick != 0) { float d = 1.0 - g * c; return (1.0 - g * g) / (4.0 * PI_SS * d * d); }
    float d = 1.0 + g * g - 2.0 * g * c;
    return (1.0 - g * g) / (4.0 * PI_SS * d * sqrt(d));
}
// Snell's law (sss_ss_refract): the inside direction t of a ray arriving
// along -w at normal n; returns mu = -n.t
float ss_refract(vec3 n, vec3 w, float eta, out vec3 t) {
    float c = dot(n, w);
    float ct = sqrt(max(0.0, 1.0 - (1.0 - c * c) / (eta * eta)));
    t = -w / eta + (c / eta - ct) * n;
    return ct;
}
float ss_depth(int k) { return k < u_ss_nl - 1 ? v_ld[k] : 1e30; }
int ss_find(float z) { // sss_layers_find
    int k = 0;
    while (k < u_ss_nl && !(z < ss_depth(k))) k++;
    return k;
}
vec3 ss_tau_path(float km, float mu) { // sss_layers_tau_path (seed 002 Eq. 12, clamped)
    float left = km, top = 0.0;
    vec3 tau = vec3(0.0);
    for (int j = 0; j < u_ss_nl && left > 0.0; j++) {
        float Dj = (ss_depth(j) - top) / mu;
        tau += u_ss_sigma_t[j] * clamp(left, 0.0, Dj);
        left -= Dj;
        top = ss_depth(j);
    }
    return tau;
}
vec3 ss_vec(uint i, bool nrm) {
    return nrm ? vec3(ss_nrm[3u * i], ss_nrm[3u * i + 1u], ss_nrm[3u * i + 2u])
               : vec3(ss_pos[3u * i], ss_pos[3u * i + 1u], ss_pos[3u * i + 2u]);
}
// The interpolated unit normal of triangle t at p (barycentrics of its
// projection, extrapolated off the triangle): single_mesh.c's normal_at.
vec3 ss_normal_at(int t, vec3 p) {
    uint i0 = ss_tri[3 * t], i1 = ss_tri[3 * t + 1], i2 = ss_tri[3 * t + 2];
    vec3 a = ss_vec(i0, false), e1 = ss_vec(i1, false) - a, e2 = ss_vec(i2, false) - a, q = p - a;
    float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2), q1 = dot(q, e1), q2 = dot(q, e2);
    float den = d11 * d22 - d12 * d12;
    float w1 = den != 0.0 ? (d22 * q1 - d12 * q2) / den : 1.0 / 3.0;
    float w2 = den != 0.0 ? (d11 * q2 - d12 * q1) / den : 1.0 / 3.0;
    return normalize((1.0 - w1 - w2) * ss_vec(i0, true) + w1 * ss_vec(i1, true) + w2 * ss_vec(i2, true));
}
// The (unnormalised) normal of triangle t's plane, and a vertex of it.
vec3 ss_face_normal(int t) {
    vec3 a = ss_vec(ss_tri[3 * t], false);
    return cross(ss_vec(ss_tri[3 * t + 1], false) - a, ss_vec(ss_tri[3 * t + 2], false) - a);
}
// The surface nearest the light in the texel holding x: a point of it and
// its triangle; false outside the map or where no surface was drawn.
bool ss_map(vec3 x, out vec3 K, out int prim) {
    vec2 st = (u_ss_light * vec4(x, 1.0)).xy;
    ivec2 ix = ivec2(floor(st * float(u_ss_size)));
    prim = -1;
    if (any(lessThan(ix, ivec2(0))) || any(greaterThanEqual(ix, ivec2(u_ss_size)))) return false;
    vec4 p = texelFetch(u_ss_kpos, ix, 0);
    K = p.xyz;
    prim = int(p.w + 0.5) - 1;
    return prim >= 0;
}
// Whether x lies inside the object as the light sees it: behind the
// surface nearest the light on its line.
bool ss_inside(vec3 x, vec3 L) {
    vec3 K;
    int t;
    return ss_map(x, K, t) && dot(K - x, L) >= 0.0;
}
// Where the ray from M back along -d leaves the surface (the CPU's cast,
// sss_bvh_nearest): the plane of the triangle the map holds on M's line
// along the light, then of the triangle at each new estimate's texel (the
// map is drawn along the light; d is refracted) until the triangle repeats.
// A step that lands outside the object (beyond the silhouette the light
// sees) is undone by bisection between M and it. Distance in mesh units
// and K's triangle; < 0 when nothing is found.
float ss_cast(vec3 M, vec3 d, vec3 L, out int prim) {
    vec3 K;
    int p2;
    if (!ss_map(M, K, prim)) return -1.0;
    float t = -1.0;
    for (int it = 0; it < SS_CAST_STEPS; it++) {
        vec3 a = ss_vec(ss_tri[3 * prim], false), fn = ss_face_normal(prim);
        float den = dot(-d, fn);
        if (den == 0.0) return -1.0;
        float tn = dot(a - M, fn) / den;
        if (!(tn > 0.0)) return -1.0;
        t = tn;
        if (!ss_map(M - t * d, K, p2)) break; /* outside: bisect below */
        if (p2 == prim) return t;
        prim = p2;
    }
    if (ss_inside(M - t * d, L)) return t; /* the steps ran out inside: keep the last */
    float lo = 0.0, hi = t;
    for (int b = 0; b < 20; b++) {
        float mid = 0.5 * (lo + hi);
        if (ss_inside(M - mid * d, L)) lo = mid; else hi = mid;
    }
    if (!ss_map(M - lo * d, K, p2)) return -1.0;
    prim = p2; /* the triangle on the inside end's line */
    return 0.5 * (lo + hi);
}
// How much a curved surface concentrates the refracted beam from K to M
// (single_mesh.c's focusing): the cross-section of a small bundle entering
// at K and two points 1e-3 |KM| away on K's tangent plane, each refracted at
// its own interpolated normal of triangle prim, at K over at M; clamped to
// [0.01, 100]. Offsets from K, so that float keeps the small differences.
float ss_focusing(int prim, vec3 M, float t, vec3 tK, vec3 L) {
    vec3 K0 = M - t * tK, nK = ss_normal_at(prim, K0);
    vec3 h = abs(nK.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 u = normalize(cross(nK, h)), v = cross(nK, u);
    float delta = 1e-3 * t;
    vec3 off[3] = vec3[3](vec3(0.0), delta * u, delta * v), P[3];
    for (int j = 0; j < 3; j++) {
        vec3 nj = ss_normal_at(prim, K0 + off[j]), tj;
        if (!(dot(nj, L) > 0.0)) return 1.0;
        ss_refract(nj, L, u_ss_eta, tj);
        vec3 mk = t * tK - off[j]; // M - K_j
        P[j] = off[j] + dot(mk, tK) / dot(tj, tK) * tj;
    }
    float at_M = length(cross(P[1] - P[0], P[2] - P[0])), at_K = abs(dot(cross(off[1], off[2]), tK));
    if (!(at_M > 0.0) || !(at_K > 0.0)) return 1.0;
    return clamp(at_K / at_M, 0.01, 100.0);
}
struct ss_pt { int layer; vec3 tau; };
// What the march needs at s mm along the view ray (single_mesh.c's
// locate_mesh): the layer by depth below P's tangent plane, and the light's
// optical depth from K with the entry weight of K against P's.
ss_pt ss_locate(float s, vec3 P, vec3 n, vec3 L, vec3 di, vec3 dop, float mu_i, float mu_o, float entry_v,
                float cphase_v) {
    ss_pt o;
    o.layer = ss_find(s * mu_o);
    float su = s / u_ss_mm;
    vec3 M = P + su * dop;
    float t = -1.0, weight = 1.0, mu_path = mu_i;
    int prim;
    if (su > 0.0) t = ss_cast(M, di, L, prim);
    if (!(t > 0.0)) {
        t = su * mu_o / mu_i; // no surface found: P's tangent plane
    } else {
        // the light refracts at K's own normal: two fixed-point steps
        vec3 tK;
        bool refracted = false;
        for (int it = 0; it < 2; it++) {
            vec3 nK = ss_normal_at(prim, M - t * (it == 0 ? di : tK));
            float cK = dot(nK, L);
            if (!(cK > 0.0)) break;
            vec3 tn;
            float ct = ss_refract(nK, L, u_ss_eta, tn);
            int p2;
            float t2 = ss_cast(M, tn, L, p2);
            if (!(t2 > 0.0)) break;
            t = t2;
            prim = p2;
            tK = tn;
            float gl = u_ss_g[o.layer < u_ss_nl ? o.layer : 0];
            float ph = ss_phase(gl, -dot(tK, dop)), phv = ss_phase(gl, cphase_v);
            weight = ss_ft(u_ss_eta, cK) * cK / ct / entry_v * (phv > 0.0 ? ph / phv : 1.0);
            mu_path = max(1e-6, -dot(tK, n));
            refracted = true;
        }
        if (refracted) weight *= ss_focusing(prim, M, t, tK, L);
    }
    o.tau = weight > 0.0 ? ss_tau_path(t * u_ss_mm, mu_path) - log(weight) : vec3(1e30);
    return o;
}
// Whether the point x (world) is outside the object as the camera sees it:
// beyond the plane of the nearest back face's triangle in its pixel
// (outward: as its interpolated normal), or in a pixel with none.
bool ss_outside(vec3 x) {
    vec4 c = u_ss_mvp * vec4(x, 1.0);
    vec2 ndc = c.xy / c.w;
    ivec2 size = textureSize(u_ss_bpos, 0);
    ivec2 px = ivec2(floor((ndc * 0.5 + 0.5) * vec2(size)));
    if (any(lessThan(px, ivec2(0))) || any(greaterThanEqual(px, size))) return true;
    vec4 b = texelFetch(u_ss_bpos, px, 0);
    int t = int(b.w + 0.5) - 1;
    if (t < 0) return true;
    vec3 fn = ss_face_normal(t);
    return dot(x - b.xyz, dot(fn, ss_normal_at(t, b.xyz)) < 0.0 ? -fn : fn) > 0.0;
}
vec3 ss_mean_exp(vec3 x) { // (1 - e^-x)/x, 1 at 0 (single.c's mean_exp); a series where float cancels
    vec3 series = 1.0 - x * (0.5 - x * (1.0 / 6.0 - x / 24.0));
    return mix((1.0 - exp(-x)) / max(x, vec3(1e-30)), series, lessThan(abs(x), vec3(1e-2)));
}
// One piece of the per-segment closed form (docs/layers.md §3) in one
// layer, of length len from a point with light optical depth tau_a to one
// with tau_b, both optical depths linear along it; tauv, the view ray's
// optical depth at its start, moves to its end.
vec3 ss_segment(int layer, vec3 tau_a, vec3 tau_b, float len, float cphase, inout vec3 tauv) {
    vec3 dv = u_ss_sigma_t[layer] * len;
    vec3 Ea = tau_a + tauv, Eb = tau_b + tauv + dv;
    tauv += dv;
    return u_ss_sigma_s[layer] * ss_phase(u_ss_g[layer], cphase) * len * exp(-min(Ea, Eb)) * ss_mean_exp(abs(Eb - Ea));
}
// The single-scattered radiance leaving P (unit normal n) towards v for a
// light of unit irradiance from L, per channel, 1/sr.
vec3 single_scattering(vec3 P, vec3 n, vec3 v, vec3 L) {
    float ci = dot(n, L), co = dot(n, v);
    if (!(ci > 0.0) || !(co > 0.0)) return vec3(0.0);
    vec3 di, dop;
    float mu_i = ss_refract(n, L, u_ss_eta, di), mu_o = ss_refract(n, v, u_ss_eta, dop);
    float B = ss_ft(u_ss_eta, ci) * ci / mu_i * ss_ft(u_ss_eta, co) / (u_ss_eta * u_ss_eta); // sss_ss_geometry
    float cphase = -dot(di, dop);
    float entry_v = ss_ft(u_ss_eta, ci) * ci / mu_i;
    int N = max(u_ss_n, 1);
    // the march's end: where the view ray leaves the object (the first of
    // N steps outside, then bisection), or where its light is gone
    float smax = u_ss_smax_cap;
    float step0 = smax / float(N);
    for (int j = 1; j <= N; j++) {
        if (ss_outside(P + (float(j) * step0 / u_ss_mm) * dop)) {
            float lo = float(j - 1) * step0, hi = float(j) * step0;
            for (int b = 0; b < 20; b++) {
                float mid = 0.5 * (lo + hi);
                if (ss_outside(P + (mid / u_ss_mm) * dop)) hi = mid; else lo = mid;
            }
            smax = hi;
            break;
        }
    }
    float delta = smax / float(N);
    vec3 Lss = vec3(0.0);
    if (u_ss_seed != 0) { // Algorithm 1: a left Riemann sum
        vec3 T = vec3(1.0);
        for (int j = 0; j < N; j++) {
            ss_pt p = ss_locate(float(j) * delta, P, n, L, di, dop, mu_i, mu_o, entry_v, cphase);
            if (p.layer >= u_ss_nl) continue;
            Lss += u_ss_sigma_s[p.layer] * ss_phase(u_ss_g[p.layer], cphase) * exp(-p.tau) * T * delta;
            T *= exp(-u_ss_sigma_t[p.layer] * delta); // Eq. 13
        }
        return B * Lss;
    }
    // the per-segment closed form: both optical depths linear on each
    // stretch; a stretch that crosses a layer boundary (flat layers below
    // P's tangent plane: at s = depth / mu_o) is split there
    vec3 tauv = vec3(0.0);
    float a = 0.0;
    ss_pt pa = ss_locate(0.0, P, n, L, di, dop, mu_i, mu_o, entry_v, cphase);
    for (int j = 0; j < N; j++) {
        float b = j + 1 == N ? smax : float(j + 1) * delta;
        ss_pt pb = ss_locate(b, P, n, L, di, dop, mu_i, mu_o, entry_v, cphase);
        for (int guard = 0; guard < SS_MAXL && pa.layer != pb.layer && pa.layer < u_ss_nl; guard++) {
            float x = clamp(ss_depth(pa.layer) / mu_o, a, b);
            ss_pt px = ss_locate(x, P, n, L, di, dop, mu_i, mu_o, entry_v, cphase);
            px.layer = ss_find(ss_depth(pa.layer)); // the next layer with a thickness (z < depth_k)
            Lss += ss_segment(pa.layer, pa.tau, px.tau, x - a, cphase, tauv);
            a = x;
            pa = px;
        }
        if (pa.layer < u_ss_nl) {
            Lss += ss_segment(pa.layer, pa.tau, pb.tau, b - a, cphase, tauv);
        }
        a = b;
        pa = pb;
    }
    return B * Lss;
}
#endif
