// The geometry buffers of the splatting (splat_gpu.c; Chen et al. 2012 §4,
// "Buffer generation"): the posed mesh seen from the light (orthographic)
// or from the camera (the draw's matrix), world position and normal passed on,
// and a spatially varying material's f (docs/deformable.md sec. 10; attribute 2,
// which a homogeneous object leaves disabled: its generic value 0).
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(location = 2) in float a_f;
uniform mat4 u_mvp;
out vec3 v_pos;
out vec3 v_nrm;
out float v_f;
void main() {
    v_pos = a_pos;
    v_nrm = a_nrm;
    v_f = a_f;
    gl_Position = u_mvp * vec4(a_pos, 1.0);
}
