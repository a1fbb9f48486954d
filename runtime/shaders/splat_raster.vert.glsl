// The geometry buffers of the splatting (splat_gpu.c; Chen et al. 2012 §4,
// "Buffer generation"): the posed mesh seen from the light (orthographic)
// or from the camera (the draw's matrix), world position and normal passed on.
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
uniform mat4 u_mvp;
out vec3 v_pos;
out vec3 v_nrm;
void main() {
    v_pos = a_pos;
    v_nrm = a_nrm;
    gl_Position = u_mvp * vec4(a_pos, 1.0);
}
