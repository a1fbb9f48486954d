// Per texel, the surface nearest the light (or the camera, for the back
// faces): its position and its triangle + 1 (0: no surface), where
// single.glsl finds the entry point K and the view ray's exit.
out vec4 o_pos;
in vec3 v_pos;
void main() { o_pos = vec4(v_pos, float(gl_PrimitiveID + 1)); }
