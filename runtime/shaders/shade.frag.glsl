in vec3 v_pos;
in vec3 v_nrm;
in vec3 v_q;
uniform vec3 u_eye;
uniform vec3 u_light;     // unit, towards the light
uniform vec3 u_light_rgb; // irradiance E per channel
uniform float u_eta;
uniform float u_exposure;
uniform float u_exit_scale; // 1, or 1/c(η) for the normalised exit (docs/physics.md §4)
uniform int u_scatter;
uniform int u_specular;
uniform float u_diffuse;  // rho_d: the Fresnel-reflected share reflected diffusely (docs/viewer.md)
uniform int u_surface_shadow; // 1: the surface terms are tested against the shadow map (shadow_map.glsl)
uniform int u_tonemap;    // 0 clamp, 1 Reinhard, -1 none (HDR readback)
uniform int u_srgb;       // encode for an 8-bit display framebuffer
uniform int u_flat;       // wireframe: constant colour
uniform int u_qimage;    // 1: q per pixel from u_qtex (the splatting, splat_gpu.c), not per vertex
uniform int u_q_lit;     // 1: that q already holds the lights' irradiance (htsm_gpu.c), not scaled by u_light_rgb
layout(binding = 1) uniform sampler2D u_qtex;
uniform int u_simage;    // 1: the surface terms per pixel from u_stex (every light's, htsm_gpu.c), not u_light's
layout(binding = 4) uniform sampler2D u_stex;
out vec4 o_color;
const float PI = 3.14159265358979;
void main() {
    if (u_flat != 0) { o_color = vec4(0.9, 0.9, 0.9, 1.0); return; }
    vec3 n = normalize(v_nrm);
    vec3 v = normalize(u_eye - v_pos);
    float nv = dot(n, v);
    vec3 L = vec3(0.0);
    // Subsurface term: L = E q F_t(eta, n.w_o) (Hao–Varshney 2004 §3.1),
    // divided by c(η) for the normalised exit
    vec3 q = u_qimage != 0 ? texelFetch(u_qtex, ivec2(gl_FragCoord.xy), 0).rgb : v_q;
    if (u_scatter != 0) L += (u_q_lit != 0 ? vec3(1.0) : u_light_rgb) * q * ((1.0 - fresnel_r(u_eta, nv)) * u_exit_scale);
#ifdef SSS_SINGLE
    // Single scattering per pixel (single.glsl, docs/layers.md §8)
    L += u_light_rgb * single_scattering(v_pos, n, v, u_light);
#endif
    // Direct surface light (surface.glsl), 0 where the shadow map says the
    // light is blocked; or every light's, each tested against its own
    // light-space map, summed per pixel by the run-time path (htsm_gpu.c)
    if (u_simage != 0) {
        L += texelFetch(u_stex, ivec2(gl_FragCoord.xy), 0).rgb;
    } else {
        float nl = max(dot(n, u_light), 0.0);
        if ((u_specular != 0 || u_diffuse > 0.0) && nl > 0.0
            && (u_surface_shadow == 0 || shadow_map_lit(v_pos, n, nl)))
            surface_light_add(L, n, v, u_light, nl, u_light_rgb, u_eta, u_specular, u_diffuse);
    }
    vec3 x = u_exposure * L;
    if (u_tonemap == 0) x = clamp(x, 0.0, 1.0);
    else if (u_tonemap == 1) x = x / (1.0 + x);
    if (u_srgb != 0) {
        x = clamp(x, 0.0, 1.0);
        x = mix(12.92 * x, 1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), x));
    }
    o_color = vec4(x, 1.0);
}
