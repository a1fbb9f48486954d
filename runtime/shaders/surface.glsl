// One light's direct surface light (Hao-Varshney 2004 3.2, "direct
// on-surface reflected light (including shadow)"), shared by the shading
// (shade.frag.glsl) and the run-time path's per-light pass (htsm.frag.glsl,
// docs/heterogeneous.md sec. 9.1): of the irradiance E n.l the boundary
// reflects F_r; the rest entered and is q's. A share rho_d of the reflected
// light leaves in a Lambert lobe, the rest in a Fresnel-weighted normalised
// Blinn-Phong lobe, so nothing is counted twice (docs/viewer.md, "Direct
// surface light"). Added to L for a lit point (nl = n.l > 0; the caller
// tests the shadow). fresnel_r: fresnel.glsl, put before this part.
void surface_light_add(inout vec3 L, vec3 n, vec3 v, vec3 l, float nl, vec3 E, float eta, int specular,
                       float rho_d) {
    if (specular != 0) {
        vec3 h = normalize(l + v);
        const float s = 80.0;
        float d = (s + 8.0) / (8.0 * 3.14159265358979) * pow(max(dot(n, h), 0.0), s);
        L += E * ((1.0 - rho_d) * fresnel_r(eta, dot(v, h)) * d * nl);
    }
    if (rho_d > 0.0) L += E * (rho_d * fresnel_r(eta, nl) * nl / 3.14159265358979);
}
