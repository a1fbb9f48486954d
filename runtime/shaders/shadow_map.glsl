// The shadow map's test (shadow.h, shadow.c): Hao-Varshney 2004 3.1's depth
// comparison, shared by the near terms' pass 1 (near_vis.comp.glsl) and the
// surface terms of the shading (shade.frag.glsl, docs/viewer.md "Direct
// surface light"). Uniforms set by sss_shadow_bind.
uniform sampler2D u_depth;  // the shadow map (window depth, nearer the light = smaller)
uniform mat4 u_shadow;      // world -> (s, t, z) in [0, 1]^3
uniform int u_size;         // texels per side
uniform float u_offset;     // normal offset, world units
uniform float u_bias_c, u_bias_s, u_tan_max; // depth bias: (k_c + k_s min(tan, tan_max)) / size
// Is x (unit normal n, c = n.w > 0) lit? x is lifted along n and the depth
// biased so that the answer is the bake's ray's (shadow.c says why); outside
// the map nothing blocks.
bool shadow_map_lit(vec3 x, vec3 n, float c) {
    vec3 p = x + u_offset * n;
    vec3 s = (u_shadow * vec4(p, 1.0)).xyz;
    ivec2 ix = ivec2(floor(s.xy * float(u_size)));
    if (!(all(greaterThanEqual(ix, ivec2(0))) && all(lessThan(ix, ivec2(u_size))))) return true;
    float tn = min(sqrt(max(1.0 - c * c, 0.0)) / c, u_tan_max);
    float bias = (u_bias_c + u_bias_s * tn) / float(u_size);
    return s.z - bias <= texelFetch(u_depth, ix, 0).r;
}
