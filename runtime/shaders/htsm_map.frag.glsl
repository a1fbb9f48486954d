// Per texel, the surface nearest the light (Shopf 2007 Fig. 4.2): its
// position and unit normal with coverage 1 in w (empty texels stay 0, so
// the mip levels' means are coverage-weighted sums), and the flux it lets in
// per unit area across the light, E_t = E0 F_t(eta, n.l): the projected area
// already carries the cosine. fresnel_r: fresnel.glsl, put before this part.
in vec3 v_pos;
in vec3 v_nrm;
uniform vec3 u_l;         // unit direction towards the light
uniform vec3 u_light_rgb; // E0 per channel
uniform float u_eta;
layout(location = 0) out vec4 o_pos;
layout(location = 1) out vec4 o_nrm;
layout(location = 2) out vec4 o_irr;
void main() {
    vec3 n = normalize(v_nrm);
    float c = dot(n, u_l);
    o_pos = vec4(v_pos, 1.0);
    o_nrm = vec4(n, 1.0);
    o_irr = vec4(c > 0.0 ? u_light_rgb * (1.0 - fresnel_r(u_eta, c)) : vec3(0.0), 1.0);
}
