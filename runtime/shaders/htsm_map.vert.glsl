// The light-space map of a heterogeneous object (effects/htsm.c; Shopf 2007
// Fig. 4.2): the mesh seen from the light, orthographic along a directional
// light, perspective from a point light (shadow.h's projections), position
// and normal passed on.
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
uniform mat4 u_mat; // world -> the light's clip space
out vec3 v_pos;
out vec3 v_nrm;
void main() {
    v_pos = a_pos;
    v_nrm = a_nrm;
    gl_Position = u_mat * vec4(a_pos, 1.0);
}
