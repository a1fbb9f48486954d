layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(std430, binding = 3) readonly buffer Q { float q[]; };
uniform mat4 u_mvp;
uniform uint u_channels;
out vec3 v_pos;
out vec3 v_nrm;
out vec3 v_q;
// the layers' lower boundaries per vertex, mm (single.glsl): nv x u_ss_nd
layout(std430, binding = 6) readonly buffer LD { float ld[]; };
uniform int u_ss_nd; // layers per vertex (0: none)
out float v_ld[8];
void main() {
    uint v = uint(gl_VertexID);
    v_q = u_channels == 3u ? vec3(q[3u * v], q[3u * v + 1u], q[3u * v + 2u]) : vec3(q[v]);
    for (int k = 0; k < 8; k++) v_ld[k] = k < u_ss_nd ? ld[uint(u_ss_nd) * v + uint(k)] : 0.0;
    v_pos = a_pos;
    v_nrm = a_nrm;
    gl_Position = u_mvp * vec4(a_pos, 1.0);
}
