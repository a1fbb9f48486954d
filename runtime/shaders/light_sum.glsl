layout(local_size_x = 256) in;
const uint C = uint(CHANNELS);
layout(std430, binding = 6) buffer Q { float q[]; };  // the frame's sum, nv x C
uniform uint u_count;    // invocations: nv x C values (rows, shells) or nv vertices (environment)
uniform int u_first;     // 1: the first light of the frame, the sum starts at 0
uniform double u_w[3];   // colour x intensity per channel (a grey file: the mean)
// q[e] += float(w_c * s): the light's term rounded to float, then added in float,
// as the CPU sum does it
void light_add(uint e, uint c, float s) {
    precise double t = u_w[c] * double(s);
    float tf = float(t);
    if (u_first == 0) {
        precise float x = q[e] + tf;
        tf = x;
    } else {
        precise float x = 0.0 + tf; // as the CPU's 0 + term (-0 becomes +0)
        tf = x;
    }
    q[e] = tf;
}
