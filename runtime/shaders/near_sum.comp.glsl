layout(local_size_x = 256) in;
const uint C = uint(CHANNELS);
// one chunk of receivers u_first ... u_first + u_count - 1 (near.c): row o
// of the chunk is the count row[o].z entries of its own Idx and W from
// row[o].x on, row[o].y apart: the rows of a slice of receivers interleaved,
// so that neighbouring invocations read neighbouring entries
layout(std430, binding = 0) readonly buffer Row { uvec4 row[]; };    // row o: first entry, stride, count
layout(std430, binding = 1) readonly buffer Idx { uint idx[]; };     // the row's vertices, o first
layout(std430, binding = 2) readonly buffer Gv { float gv[]; };
layout(std430, binding = 3) buffer Q { float q[]; };
layout(std430, binding = 4) readonly buffer W { float w[]; };        // w~(o, i) per channel
uniform uint u_first;
uniform uint u_count;
void main() {
    uint o = gl_GlobalInvocationID.x;
    if (o >= u_count) return;
    precise float s[3] = float[3](0.0, 0.0, 0.0);
    uvec4 r = row[o];
    for (uint k = 0u, a = r.x; k < r.z; k++, a += r.y) {
        float g = gv[idx[a]];
        for (uint ch = 0u; ch < C; ch++) s[ch] += w[a * C + ch] * g;
    }
    for (uint ch = 0u; ch < C; ch++) {
        precise float x = q[(u_first + o) * C + ch] + s[ch];
        q[(u_first + o) * C + ch] = x;
    }
}
