// Per texel, the surface nearest the light (Shopf 2007 Fig. 4.2): its
// position and unit normal with coverage 1 in w (empty texels stay 0, so
// the mip levels' means are coverage-weighted sums), and the flux it lets in
// per unit area across the light's ray, E_t = E0 F_t(eta, n.l) from a
// directional light, I F_t(eta, n.l) / r^2 from a point light at distance r
// (docs/heterogeneous.md sec. 9.1): the projected area already carries the
// cosine. fresnel_r: fresnel.glsl, put before this part.
in vec3 v_pos;
in vec3 v_nrm;
uniform vec4 u_light;     // (unit direction towards the light, 0), or (a point light's position, 1)
uniform vec3 u_light_rgb; // E0 (directional) or I (point, per steradian) per channel
uniform float u_eta;
layout(location = 0) out vec4 o_pos;
layout(location = 1) out vec4 o_nrm;
layout(location = 2) out vec4 o_irr;
void main() {
    vec3 n = normalize(v_nrm), l = u_light.xyz, E0 = u_light_rgb;
    if (u_light.w != 0.0) {
        vec3 d = u_light.xyz - v_pos;
        float r2 = dot(d, d);
        l = d * inversesqrt(r2);
        E0 /= r2;
    }
    float c = dot(n, l);
    o_pos = vec4(v_pos, 1.0);
    o_nrm = vec4(n, 1.0);
    o_irr = vec4(c > 0.0 ? E0 * (1.0 - fresnel_r(u_eta, c)) : vec3(0.0), 1.0);
}
