layout(local_size_x = 256) in;
const uint C = uint(CHANNELS);
layout(std430, binding = 0) readonly buffer Start { uint start[]; }; // row o: [start[o], start[o + 1])
layout(std430, binding = 1) readonly buffer Idx { uint idx[]; };     // the row's vertices, o first
layout(std430, binding = 2) readonly buffer Gv { float gv[]; };
layout(std430, binding = 3) buffer Q { float q[]; };
layout(std430, binding = 4) readonly buffer W { float w[]; };        // w~(o, i) per channel
uniform uint u_count;
void main() {
    uint o = gl_GlobalInvocationID.x;
    if (o >= u_count) return;
    precise float s[3] = float[3](0.0, 0.0, 0.0);
    for (uint a = start[o]; a < start[o + 1u]; a++) {
        float g = gv[idx[a]];
        for (uint ch = 0u; ch < C; ch++) s[ch] += w[a * C + ch] * g;
    }
    for (uint ch = 0u; ch < C; ch++) {
        precise float x = q[o * C + ch] + s[ch];
        q[o * C + ch] = x;
    }
}
