// Per texel, the surface nearest the light: its position (w = 1: covered)
// and interpolated normal, where single.glsl finds the entry point K.
in vec3 v_pos;
in vec3 v_nrm;
layout(location = 0) out vec4 o_pos;
layout(location = 1) out vec4 o_nrm;
void main() {
    o_pos = vec4(v_pos, 1.0);
    o_nrm = vec4(normalize(v_nrm), 0.0);
}
