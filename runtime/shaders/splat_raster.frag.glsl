// The two geometry buffers of the splatting (splat_gpu.c). LIGHT: the
// irradiance buffer, each texel a surface sample x_i seen from the light
// (the depth test keeps the nearest, so visibility is implicit) with its
// flux per unit irradiance F_t(eta, n.w) E(x_i) dA(x_i) = F_t(eta, n.w) a_t
// (a_t the texel's area across the beam, mm^2: the surface it covers is
// a_t / n.w, lit by n.w; Chen et al. 2012 Eqs. 5-6). Otherwise the
// splatting buffer: position, view depth and normal of the visible surface.
// Both write the material's f there (o_c; 0 for a homogeneous object),
// interpolated across the triangle as sigma_a and sigma'_s are linear in it.
in vec3 v_pos;
in vec3 v_nrm;
in float v_f;
layout(location = 0) out vec4 o_a;
layout(location = 1) out vec4 o_b;
layout(location = 2) out vec4 o_c;
#if LIGHT
uniform vec3 u_light;      // unit, towards the light
uniform vec3 u_centre;     // the light frame's origin
uniform float u_eta;
uniform float u_texel_mm2; // a_t
void main() {
    float nl = dot(normalize(v_nrm), u_light);
    float flux = nl > 0.0 ? (1.0 - fresnel_r(u_eta, nl)) * u_texel_mm2 : 0.0;
    o_a = vec4(v_pos, flux);
    o_b = vec4(dot(v_pos - u_centre, u_light), nl, 1.0, 0.0);
    o_c = vec4(v_f, 0.0, 0.0, 0.0);
}
#else
uniform vec3 u_eye;
uniform vec3 u_fwd;
void main() {
    o_a = vec4(v_pos, dot(v_pos - u_eye, u_fwd));
    o_b = vec4(normalize(v_nrm), 1.0);
    o_c = vec4(v_f, 0.0, 0.0, 0.0);
}
#endif
