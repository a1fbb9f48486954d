// The light-space map of single scattering's entry points (effects/single.c):
// the mesh seen along the light, orthographic (shadow.h's projection).
layout(location = 0) in vec3 a_pos;
uniform mat4 u_mat; // world -> the light's clip space
out vec3 v_pos;
void main() {
    v_pos = a_pos;
    gl_Position = u_mat * vec4(a_pos, 1.0);
}
