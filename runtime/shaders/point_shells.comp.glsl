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
void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e >= u_count) return;
    uint c = e % C;
    precise double acc = 0.0lf;
    acc = acc + u_pw[0] * double(r0[e]);
    acc = acc + u_pw[1] * double(r1[e]);
    acc = acc + u_pw[2] * double(r2[e]);
    acc = acc + u_pw[3] * double(r3[e]);
    acc = acc + u_pw[4] * double(r4[e]);
    acc = acc + u_pw[5] * double(r5[e]);
    precise double sd = acc / u_r2;
    float s = float(sd);
    light_add(e, c, s);
}
