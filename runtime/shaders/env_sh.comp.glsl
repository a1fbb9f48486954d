// format §5.12's T_i(x_v), each (vertex, channel)'s K = NCOEF coefficients padded
// with zeros to NQ vec4s: one 16-byte load per four coefficients
const uint NQ = (uint(NCOEF) + 3u) / 4u;
layout(std430, binding = 0) readonly buffer T { vec4 tr[]; };
uniform vec4 u_L[3u * NQ]; // the probe's SH this frame (rotated about +z on the CPU), padded alike
void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e >= u_count) return;
    uint v = e;
    float ek[3];
    for (uint k = 0u; k < 3u; k++) {
        uint base = (v * C + (C == 3u ? k : 0u)) * NQ;
        // Σ_i T_i L_i in i order, as sss_fx_env (a padded term adds 0)
        precise double acc = 0.0lf;
        for (uint j = 0u; j < NQ; j++) {
            vec4 t = tr[base + j], l = u_L[k * NQ + j];
            acc = acc + double(t.x) * double(l.x);
            acc = acc + double(t.y) * double(l.y);
            acc = acc + double(t.z) * double(l.z);
            acc = acc + double(t.w) * double(l.w);
        }
        // the SH truncation can ring below zero; radiance cannot
        ek[k] = acc > 0.0lf ? float(acc) : 0.0;
    }
    if (C == 3u) {
        for (uint k = 0u; k < 3u; k++) {
            precise float x = (u_first != 0 ? 0.0 : q[3u * v + k]) + ek[k];
            q[3u * v + k] = x;
        }
    } else {
        // a grey file: the mean of R, G, B, as the CPU path (division in double,
        // rounded once: the float quotient, since 53 >= 2 x 24 + 2)
        precise float m = (ek[0] + ek[1]) + ek[2];
        precise double md = double(m) / 3.0lf;
        precise float x = (u_first != 0 ? 0.0 : q[v]) + float(md);
        q[v] = x;
    }
}
