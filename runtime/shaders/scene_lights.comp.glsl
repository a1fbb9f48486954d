layout(local_size_x = 256) in;
const uint C = uint(CHANNELS);
layout(std430, binding = 6) buffer Q { float q[]; };  // the frame's sum, nv x C
uniform uint u_count;    // invocations: nv x C values (rows, shells) or nv vertices (environment)
uniform int u_first;     // 1: the first light of the frame, the sum starts at 0
uniform double u_w[3];   // colour x intensity per channel (a grey file: the mean)
#if defined(FX_ROWS)
// one stored row: QDIR's values for this light (directional-exact, format §5.11),
// or the direction-set interpolation of the renderer's pass (Hao-Varshney 2004 §3.2)
layout(std430, binding = 0) readonly buffer Src { float src[]; };
#elif defined(FX_SHELL)
// §3.3: the six rows around the light, shells s and s+1 x the spherical triangle
// of directions around P - centre (format §5.13: r_s^2 q_pt)
layout(std430, binding = 0) readonly buffer R0 { float r0[]; };
layout(std430, binding = 1) readonly buffer R1 { float r1[]; };
layout(std430, binding = 2) readonly buffer R2 { float r2[]; };
layout(std430, binding = 3) readonly buffer R3 { float r3[]; };
layout(std430, binding = 4) readonly buffer R4 { float r4[]; };
layout(std430, binding = 5) readonly buffer R5 { float r5[]; };
uniform double u_pw[6];  // (1 - t, t) x barycentric, as sss_fx_point_weights forms them
uniform double u_r2;     // |P - centre|^2: the falloff put back
#elif defined(FX_ENV)
// format §5.12's T_i(x_v), each (vertex, channel)'s K = NCOEF coefficients padded
// with zeros to NQ vec4s: one 16-byte load per four coefficients
const uint NQ = (uint(NCOEF) + 3u) / 4u;
layout(std430, binding = 0) readonly buffer T { vec4 tr[]; };
uniform vec4 u_L[3u * NQ]; // the probe's SH this frame (rotated about +z on the CPU), padded alike
#endif
void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e >= u_count) return;
#if defined(FX_ROWS) || defined(FX_SHELL)
    uint c = e % C;
#if defined(FX_ROWS)
    float s = src[e];
#else
    precise double acc = 0.0lf;
    acc = acc + u_pw[0] * double(r0[e]);
    acc = acc + u_pw[1] * double(r1[e]);
    acc = acc + u_pw[2] * double(r2[e]);
    acc = acc + u_pw[3] * double(r3[e]);
    acc = acc + u_pw[4] * double(r4[e]);
    acc = acc + u_pw[5] * double(r5[e]);
    precise double sd = acc / u_r2;
    float s = float(sd);
#endif
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
#elif defined(FX_ENV)
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
#endif
}
