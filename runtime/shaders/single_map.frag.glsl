// Per texel, the surface nearest (the light, or the camera for the back
// faces): its position (w = 1: covered), interpolated normal and triangle
// (w = index + 1), where single.glsl finds the entry point K and the exit.
in vec3 v_pos;
in vec3 v_nrm;
layout(location = 0) out vec4 o_pos;
layout(location = 1) out vec4 o_nrm;
void main() {
    o_pos = vec4(v_pos, 1.0);
    o_nrm = vec4(normalize(v_nrm), float(gl_PrimitiveID + 1));
}
