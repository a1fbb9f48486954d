// Seed 000's run-time estimator per pixel (Shopf 2007 §4.3;
// docs/heterogeneous.md §9): the sum of common/src/htsm.c (sss_htsm_q, its
// CPU oracle) over the hierarchical pattern's samples of the light-space map
// (htsm_map.*.glsl), each weighted by the geometric mean of the endpoints'
// dipoles and the transmittance marched through the field's mipmapped 3D
// texture with a fixed number of steps. Writes q and the exit point x_o,
// and the light's surface terms at x_o (surface.glsl), shadowed by the same
// map. fresnel_r and surface_light_add: fresnel.glsl and surface.glsl, put
// before this part.
#define HT_MAX 13
uniform mat4 u_ht_lookup;        // world -> (s, t) of the map, after the division by w
uniform vec4 u_ht_light;         // the map's light: (unit direction towards it, 0) or (its position, 1)
uniform float u_ht_wref;         // w where the pattern's mm hold (1: orthographic)
uniform float u_ht_span;         // mm across the map at w = u_ht_wref
uniform float u_ht_mm;           // mm per mesh unit
uniform int u_ht_size;           // the map's level-0 texels per side
uniform int u_ht_n;              // samples: 1, 5, 9, 13
uniform int u_ht_steps;          // march steps per sample
uniform vec2 u_ht_off[HT_MAX];   // sample offsets along s, t, mm
uniform float u_ht_rho[HT_MAX];  // the radius of the disk a sample stands for, sqrt(area / pi), mm
uniform int u_ht_mlev[HT_MAX];   // the map's mip level of each sample
uniform int u_ht_vlev[HT_MAX];   // the field's mip level of each sample
uniform vec3 u_ht_base_sa, u_ht_base_ss, u_ht_in_sa, u_ht_in_ss; // 1/mm
uniform float u_ht_A;            // the dipole's boundary term (1 + F_dr)/(1 - F_dr) of the base's eta
uniform float u_ht_strength;     // f scaled, clamped to 1
uniform int u_ht_vol_on;         // 0: no field (f = 0)
uniform int u_ht_vol_n;          // voxels per side at level 0
uniform int u_ht_vol_levels;
uniform vec3 u_ht_vol_lo, u_ht_vol_h; // mesh units: the box's corner, a level-0 voxel
uniform sampler2D u_ht_pos;      // position x coverage, coverage (mips)
uniform sampler2D u_ht_irr;      // E_t, coverage (mips)
uniform sampler3D u_ht_vol;      // f (mips)
// the surface terms (docs/heterogeneous.md sec. 9.1)
uniform vec3 u_ht_rgb;           // E0 (directional) or I (point, per steradian) per channel
uniform vec3 u_ht_eye;           // the camera, world
uniform float u_ht_eta;
uniform int u_ht_specular;       // the specular lobe on
uniform float u_ht_diffuse;      // rho_d (0: no diffuse surface reflection)
uniform int u_ht_shadow;         // 1: tested against the map (ht_lit)
uniform float u_ht_texel;        // a level-0 texel's width at w = u_ht_wref, world units
uniform float u_ht_k_n, u_ht_k_c, u_ht_k_s, u_ht_tan_max; // shadow.h's lookup constants, texels
in vec3 v_pos;
in vec3 v_nrm;
layout(location = 0) out vec4 o_q;
layout(location = 1) out vec4 o_x;
layout(location = 2) out vec4 o_s;
const float PI_HT = 3.14159265358979;

// sss_htsm_volume_at, then the strength: trilinear between voxel centres
float ht_f(int l, vec3 x) {
    if (u_ht_vol_on == 0) return 0.0;
    l = min(l, u_ht_vol_levels - 1);
    int n = u_ht_vol_n >> l;
    vec3 u = clamp((x - u_ht_vol_lo) / (u_ht_vol_h * float(1 << l)) - 0.5, vec3(0.0), vec3(float(n - 1)));
    ivec3 i0 = min(ivec3(floor(u)), ivec3(n - 2));
    vec3 fr = u - vec3(i0);
    float s = 0.0;
    for (int c = 0; c < 8; c++) {
        ivec3 o = ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
        vec3 w = mix(1.0 - fr, fr, vec3(o));
        s += w.x * w.y * w.z * texelFetch(u_ht_vol, i0 + o, l).r;
    }
    return min(1.0, u_ht_strength * s);
}
// sss_material_sigma_tr of the blend at f, per channel
vec3 ht_tr(float f) {
    vec3 sa = mix(u_ht_base_sa, u_ht_in_sa, f), ss = mix(u_ht_base_ss, u_ht_in_ss, f);
    return sqrt(3.0 * sa * (sa + ss));
}
// one source over the disk: z (e^{-tr D0}/D0 - e^{-tr D1}/D1), sss_rd_disk_axis's
// closed form (the C side in a form without cancellation)
vec3 ht_term(vec3 tr, vec3 z, float h, float R) {
    vec3 D0 = sqrt(h * h + z * z), D1 = sqrt(R * R + D0 * D0);
    return z * (exp(-tr * D0) / D0 - exp(-tr * D1) / D1);
}
// the blend at f's dipole (docs/physics.md §2): sigma_tr, the two sources'
// depths and the factor alpha'/2, made once per endpoint
struct HtDip { vec3 tr, zr, zv, k; };
HtDip ht_dip(float f) {
    vec3 sa = mix(u_ht_base_sa, u_ht_in_sa, f), ss = mix(u_ht_base_ss, u_ht_in_ss, f), st = sa + ss;
    HtDip p;
    p.tr = sqrt(3.0 * sa * st);
    p.zr = 1.0 / st;
    p.zv = p.zr + 4.0 * u_ht_A / (3.0 * st);
    p.k = 0.5 * ss / st;
    return p;
}
// sss_rd_disk_axis: R_d over a disk of radius R at distance h on its axis
vec3 ht_axis(HtDip p, float h, float R) {
    return p.k * (ht_term(p.tr, p.zr, h, R) + ht_term(p.tr, p.zv, h, R));
}
// htsm.c's disk_at: the sample's disk (radius R across the light), x_o at
// height h above it and l from its centre along it (docs/heterogeneous.md §9.2)
vec3 ht_disk(HtDip p, float h, float l, float R) {
    if (!(l < R)) return ht_axis(p, sqrt(h * h + l * l), R);
    float in_ = (R - l) / R;
    return ht_axis(p, h, R - l) + (1.0 - in_ * in_) * ht_axis(p, sqrt(h * h + R * R), R);
}
// the map's bilinear mean at (s, t) on level l, texels outside empty (map_read)
void ht_map(int l, vec2 st, out vec4 pos, out vec3 irr) {
    int S = u_ht_size >> l;
    vec2 u = st * float(S) - 0.5, f0 = floor(u), w = u - f0;
    pos = vec4(0.0);
    irr = vec3(0.0);
    for (int c = 0; c < 4; c++) {
        ivec2 i = ivec2(f0) + ivec2(c & 1, c >> 1);
        if (any(lessThan(i, ivec2(0))) || any(greaterThanEqual(i, ivec2(S)))) continue;
        float wt = ((c & 1) != 0 ? w.x : 1.0 - w.x) * ((c >> 1) != 0 ? w.y : 1.0 - w.y);
        pos += wt * texelFetch(u_ht_pos, i, l);
        irr += wt * texelFetch(u_ht_irr, i, l).rgb;
    }
}
// htsm.c's ray_at: the unit direction of the light's ray at x_i (away from
// the light) and the factor of the sample's area across it at x_i's depth
float ht_ray(vec3 xi, out vec3 u) {
    if (u_ht_light.w == 0.0) {
        u = -u_ht_light.xyz;
        return 1.0;
    }
    vec3 r = xi - u_ht_light.xyz;
    float n = length(r), w = (u_ht_lookup * vec4(xi, 1.0)).w, k = w / u_ht_wref;
    u = r / n;
    return k * k * w / n;
}
// The light's distance along its ray to x (directional: the depth along
// -l up to a constant; point: the distance from it).
float ht_depth(vec3 x) {
    return u_ht_light.w == 0.0 ? -dot(x, u_ht_light.xyz) : length(x - u_ht_light.xyz);
}
// Is x (unit normal n, c = n.l > 0) lit? shadow_map_lit's test
// (shadow_map.glsl; shadow.h says why, its constants) on the map's own
// level-0 texels: each holds the surface nearest the light there, so x is
// lit unless that surface lies nearer the light than x, lifted k_n texels
// along n, by more than the bias (k_c + k_s min(tan, tan_max)) texels. A
// texel's width grows with depth w in a point light's map. Outside the map,
// or on an empty texel, nothing blocks.
bool ht_lit(vec3 x, vec3 n, float c) {
    float t = u_ht_texel;
    if (u_ht_light.w != 0.0) t *= (u_ht_lookup * vec4(x, 1.0)).w / u_ht_wref;
    vec3 p = x + u_ht_k_n * t * n;
    vec4 hp = u_ht_lookup * vec4(p, 1.0);
    ivec2 ix = ivec2(floor(hp.xy / hp.w * float(u_ht_size)));
    if (!(all(greaterThanEqual(ix, ivec2(0))) && all(lessThan(ix, ivec2(u_ht_size))))) return true;
    vec4 m = texelFetch(u_ht_pos, ix, 0);
    if (!(m.w > 0.0)) return true;
    float tn = min(sqrt(max(1.0 - c * c, 0.0)) / c, u_ht_tan_max);
    return ht_depth(p) - (u_ht_k_c + u_ht_k_s * tn) * t <= ht_depth(m.xyz / m.w);
}
// The light's surface terms at x_o: its irradiance there (E0, or I / r^2
// towards a point light), shadowed by the map.
vec3 ht_surface() {
    vec3 L = vec3(0.0);
    if (u_ht_specular == 0 && !(u_ht_diffuse > 0.0)) return L;
    vec3 n = normalize(v_nrm), v = normalize(u_ht_eye - v_pos), l = u_ht_light.xyz, E = u_ht_rgb;
    if (u_ht_light.w != 0.0) {
        vec3 d = u_ht_light.xyz - v_pos;
        float r2 = dot(d, d);
        l = d * inversesqrt(r2);
        E /= r2;
    }
    float nl = max(dot(n, l), 0.0);
    if (nl > 0.0 && (u_ht_shadow == 0 || ht_lit(v_pos, n, nl)))
        surface_light_add(L, n, v, l, nl, E, u_ht_eta, u_ht_specular, u_ht_diffuse);
    return L;
}
void main() {
    vec4 ho = u_ht_lookup * vec4(v_pos, 1.0);
    vec2 so = ho.xy / ho.w;
    float fo = ht_f(0, v_pos);
    vec3 tro = ht_tr(fo), q = vec3(0.0);
    HtDip dpo = ht_dip(fo); // x_o's profile, the same for every sample
    for (int i = 0; i < u_ht_n; i++) {
        vec4 pos;
        vec3 E;
        ht_map(u_ht_mlev[i], so + u_ht_off[i] / u_ht_span, pos, E);
        if (!(pos.w > 1e-6)) continue; // nothing lit there
        vec3 xi = pos.xyz / pos.w, dx = v_pos - xi;
        float d = length(dx) * u_ht_mm;
        vec3 u;
        float a = ht_ray(xi, u), hu = dot(dx, u);
        float h = abs(hu) * u_ht_mm, l = length(dx - hu * u) * u_ht_mm; // along the ray, across it
        float rho = u_ht_rho[i] * sqrt(a);
        if (!(rho > 0.0)) continue;
        int lv = u_ht_vlev[i];
        float fi = ht_f(lv, xi);
        vec3 sbar = 0.5 * (tro + ht_tr(fi)), ts = vec3(0.0);
        if (u_ht_vol_on != 0)
            for (int j = 0; j < u_ht_steps; j++)
                ts += max(vec3(0.0), ht_tr(ht_f(lv, xi + ((float(j) + 0.5) / float(u_ht_steps)) * dx)) - sbar);
        vec3 tau = exp(-ts * d / float(u_ht_steps));
        q += E * sqrt(ht_disk(dpo, h, l, rho) * ht_disk(ht_dip(fi), h, l, rho)) * tau / PI_HT; // the bake's 1/pi
    }
    o_q = vec4(q, 1.0);
    o_x = vec4(v_pos, 1.0);
    o_s = vec4(ht_surface(), 1.0);
}
