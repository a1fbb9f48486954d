layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_nrm;
layout(std430, binding = 3) readonly buffer Q { float q[]; };
uniform mat4 u_mvp;
uniform uint u_channels;
out vec3 v_pos;
out vec3 v_nrm;
out vec3 v_q;
void main() {
    uint v = uint(gl_VertexID);
    v_q = u_channels == 3u ? vec3(q[3u * v], q[3u * v + 1u], q[3u * v + 2u]) : vec3(q[v]);
    v_pos = a_pos;
    v_nrm = a_nrm;
    gl_Position = u_mvp * vec4(a_pos, 1.0);
}
