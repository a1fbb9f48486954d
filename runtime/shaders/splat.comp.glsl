// The compute passes of the multiresolution splatting (splat_gpu.c; Chen
// et al. 2012 §4), one per PASS value:
//   1 LIGHT0   the irradiance buffer's level 0 from the light raster
//   2 LIGHTMIP level j+1 from j: flux summed, position flux-weighted, the
//              min/max depth mip (Nichols et al., as §4 "Buffer generation")
//   3 SELECT   the adaptive selection (Eq. 10, with M of Eq. 11): bit c of
//              a texel: used for channel c at its level; bit 3: the cut of
//              some channel lies below it
//   4 CAM0     the splatting buffer's level 0 from the camera raster
//   5 CAMMIP   its level k+1 from k: the child of median depth (§4)
//   6 GATHER   B^k at camera level k (Eq. 12), as a gather: each pixel
//              walks the selected samples of the light-space quadtree within
//              its reach (docs/deformable.md §9)
//   7 UP       bilateral upsampling and accumulation (Eq. 17), the frame's
//              q image at level 0
// A spatially varying material (u_field = 1; docs/deformable.md sec. 10)
// carries f per texel and pixel in MF: the light levels from 0, the camera
// levels from u_cfo. The material at f is the blend of u_sa0/u_ss0 (f = 0)
// and u_sa1/u_ss1 (f = 1), sigma_a and sigma'_s linear in f; a pair's
// profile is sqrt(R_d(r; m_o) R_d(r; m_i)) (seed 003 Eq. 8), the dipole
// evaluated here; its level range takes the larger of the two endpoints'
// R_P; the upsampling's material weight is Eq. 17's w_m.
layout(local_size_x = 8, local_size_y = 8) in;
// The gather walks its reach in shares of CHUNK x CHUNK coarse texels, one
// dispatch each, at most CHUNK^2 (1 + 4 + 16) loop iterations: llvmpipe's
// loop limiter cut a whole reach short, and shares of 32^2 too
// (docs/deformable.md §9).
#define CHUNK 16
layout(std430, binding = 0) buffer LA { vec4 la[]; };   // light: position, flux
layout(std430, binding = 1) buffer LB { vec4 lb[]; };   // light: z_min, z_max, n.L, covered share
layout(std430, binding = 2) buffer SEL { uint sel[]; };
layout(std430, binding = 3) buffer CA { vec4 ca[]; };   // camera: position, view depth
layout(std430, binding = 4) buffer CB { vec4 cb[]; };   // camera: normal, covered
layout(std430, binding = 5) buffer BK { vec4 bk[]; };   // B^k per camera level
layout(std430, binding = 6) readonly buffer TAB { float tab[]; }; // R-bar(log2 T), then R_d per channel, then R_P(f) per channel
layout(std430, binding = 7) buffer MF { float mf[]; };  // f: light levels, then camera levels from u_cfo
uniform uvec2 u_size;   // this pass's grid (texels or pixels)
uniform uint u_off;     // its offset in the level arrays
uniform uint u_off2;    // the other level's offset (the source of a mip, the coarse level of UP)
uniform uvec2 u_size2;  // the other level's size
const float PI = 3.14159265358979;
uniform int u_field;    // 1: a spatially varying material (MF holds f)
uniform uint u_cfo;     // the camera levels' offset in MF

#if PASS == 1 || PASS == 4
layout(binding = 0) uniform sampler2D u_ta;
layout(binding = 1) uniform sampler2D u_tb;
layout(binding = 2) uniform sampler2D u_tc;  // f
#endif
#if PASS == 6 || PASS == 7
uniform uint u_rpo;         // R_P(f) in TAB: channel c's u_nrp samples, f = 0 ... 1, from u_rpo + c u_nrp
uniform int u_nrp;
// R_P of the material at f, channel c (mm)
float rp(uint c, float f) {
    float x = clamp(f, 0.0, 1.0) * float(u_nrp - 1);
    int i = min(int(x), u_nrp - 2);
    uint o = u_rpo + c * uint(u_nrp);
    return mix(tab[o + uint(i)], tab[o + uint(i) + 1u], x - float(i));
}
#endif

#if PASS == 3 || PASS == 6
uniform int u_J;            // light levels in use
uniform uint u_loff[3];     // their offsets
uniform uint u_N0;          // level 0's texels per side
#endif
#if PASS == 3
uniform float u_z0;         // Eq. 10's depth threshold, world units
uniform float u_alpha_Rw;   // Eq. 11's alpha R_w, world units
uniform vec3 u_RPw;         // R_P per channel, world units
uniform uint u_C;
uniform int u_j;            // this pass's level
// Eq. 10 at level j for channel c: no depth discontinuity (nor background)
// under the texel, and its resolution T^j above M (Eq. 11)
bool valid(int j, uvec2 t, uint c) {
    uint N = u_N0 >> uint(j);
    vec4 b = lb[u_loff[j] + t.y * N + t.x];
    if (b.w < 1.0 || !(b.y - b.x < u_z0)) return false;
    float nl = abs(b.z);
    if (!(nl > 0.0)) return false;
    return float(N) > u_alpha_Rw / (u_RPw[c] * nl);
}
#endif

#if PASS == 6 || PASS == 7
uniform int u_k;            // camera level
uniform int u_K;            // camera levels
#endif
#if PASS == 6
uniform vec3 u_c, u_u, u_v; // the light frame: origin and plane axes
uniform float u_Rl;         // its half extent, world units
uniform float u_window;     // reach of level k, world units
uniform vec3 u_eye, u_fwd;
uniform float u_tk0, u_tk1; // T^k / (2 tan(fov/2)) at levels k and k+1: T(x_i) = u_tk R_P / z(x_i)
uniform vec3 u_RPw, u_RPmm, u_Rcut;
uniform float u_mpu;
uniform uint u_C;
uniform int u_nrbar;        // R-bar samples, log2 T from u_rb0 by u_rbs
uniform float u_rb0, u_rbs;
uniform int u_nrd;          // R_d samples per channel, at sqrt(r / R_cut) uniform
uniform ivec2 u_chunk;      // this dispatch's share of the reach: CHUNK² coarse texels from its corner
uniform int u_accum;        // 0: the first share writes B^k, the others add to it
float rbar(float T) {
    float x = clamp((log2(max(T, 1e-30)) - u_rb0) / u_rbs, 0.0, float(u_nrbar - 1));
    int i = min(int(x), u_nrbar - 2);
    return mix(tab[i], tab[i + 1], x - float(i));
}
float rd(uint c, float d) {
    float x = clamp(sqrt(d / u_Rcut[c]), 0.0, 1.0) * float(u_nrd - 1);
    int i = min(int(x), u_nrd - 2);
    int o = u_nrbar + int(c) * u_nrd;
    return mix(tab[o + i], tab[o + i + 1], x - float(i));
}
uniform vec3 u_sa0, u_ss0, u_sa1, u_ss1; // sigma_a, sigma'_s at f = 0 and f = 1 (1/mm)
uniform float u_A;          // the dipole's A = (1 + F_dr) / (1 - F_dr), from the base's eta
// The dipole of the blend at f, channel c, as sss_dipole_init makes it:
// sigma_tr, z_r, z_v, alpha' / (4 pi)
vec4 dipole(uint c, float f) {
    float sa = mix(u_sa0[c], u_sa1[c], f), ss = mix(u_ss0[c], u_ss1[c], f), st = sa + ss;
    float zr = 1.0 / st;
    return vec4(sqrt(3.0 * sa * st), zr, zr + 4.0 * u_A / (3.0 * st), ss / st / (4.0 * PI));
}
// R_d(r) of that dipole (sss_rd, Jensen et al. 2001)
float rd_term(float tr, float z, float r) {
    float d = sqrt(r * r + z * z);
    return z * (1.0 + tr * d) * exp(-tr * d) / (d * d * d);
}
float rd_dip(vec4 p, float r) { return p.w * (rd_term(p.x, p.y, r) + rd_term(p.x, p.z, r)); }
#endif
#if PASS == 7
uniform float u_lambda_Rw;  // lambda_z / R_w
uniform float u_mpu;        // mm per world unit
layout(rgba32f, binding = 0) uniform image2D u_out;
uniform vec3 u_w;           // the light's weight (intensity x colour)
uniform int u_first;        // 1: the first light overwrites
uniform uint u_C;
#endif

void main() {
    uvec2 t = gl_GlobalInvocationID.xy;
    if (t.x >= u_size.x || t.y >= u_size.y) return;
    uint i = u_off + t.y * u_size.x + t.x;
#if PASS == 1
    vec4 a = texelFetch(u_ta, ivec2(t), 0), b = texelFetch(u_tb, ivec2(t), 0);
    la[i] = b.z > 0.0 ? a : vec4(0.0);
    lb[i] = vec4(b.x, b.x, b.y, b.z);
    if (u_field != 0) mf[i] = b.z > 0.0 ? texelFetch(u_tc, ivec2(t), 0).x : 0.0;
#elif PASS == 2
    vec3 pf = vec3(0.0), pc = vec3(0.0);
    float F = 0.0, n = 0.0, cov = 0.0, zmin = 3.4e38, zmax = -3.4e38, nl = 0.0, ff = 0.0, fc = 0.0;
    for (uint k = 0u; k < 4u; k++) {
        uint s = u_off2 + (2u * t.y + (k >> 1)) * u_size2.x + 2u * t.x + (k & 1u);
        vec4 a = la[s], b = lb[s];
        cov += 0.25 * b.w;
        if (b.w > 0.0) {
            F += a.w;
            pf += a.w * a.xyz;
            pc += a.xyz;
            n += 1.0;
            zmin = min(zmin, b.x);
            zmax = max(zmax, b.y);
            nl += b.z;
            if (u_field != 0) ff += a.w * mf[s], fc += mf[s];
        }
    }
    // the coarse sample's material: its children's, flux-weighted as its position
    if (u_field != 0) mf[i] = n > 0.0 ? (F > 0.0 ? ff / F : fc / n) : 0.0;
    la[i] = n > 0.0 ? vec4(F > 0.0 ? pf / F : pc / n, F) : vec4(0.0);
    lb[i] = n > 0.0 ? vec4(zmin, zmax, nl / n, cov) : vec4(0.0);
#elif PASS == 3
    uint s = 0u;
    if (la[i].w > 0.0 || lb[i].w > 0.0) {
        bool desc = false;
        for (uint c = 0u; c < u_C; c++) {
            bool anc = false; // an ancestor stands for this texel (Nichols et al.'s cut, checked on every level above)
            for (int j = u_j + 1; j < u_J; j++) anc = anc || valid(j, t >> uint(j - u_j), c);
            if (anc) continue;
            bool v = valid(u_j, t, c);
            if ((v || u_j == 0) && la[i].w > 0.0) s |= 1u << c;
            if (!v && u_j > 0) desc = true;
        }
        if (desc) s |= 8u;
    }
    sel[i] = s;
#elif PASS == 4
    vec4 a = texelFetch(u_ta, ivec2(t), 0), b = texelFetch(u_tb, ivec2(t), 0);
    ca[i] = a;
    cb[i] = b.w > 0.0 ? b : vec4(0.0);
    if (u_field != 0) mf[u_cfo + i] = b.w > 0.0 ? texelFetch(u_tc, ivec2(t), 0).x : 0.0;
#elif PASS == 5
    // the child of median depth among the covered ones (the lower median of an even count)
    uint idx[4];
    float z[4];
    int n = 0;
    for (uint k = 0u; k < 4u; k++) {
        uvec2 ct = min(2u * t + uvec2(k & 1u, k >> 1), u_size2 - 1u);
        uint s = u_off2 + ct.y * u_size2.x + ct.x;
        if (cb[s].w > 0.0) {
            float zs = ca[s].w;
            int m = n++;
            while (m > 0 && z[m - 1] > zs) { z[m] = z[m - 1]; idx[m] = idx[m - 1]; m--; }
            z[m] = zs;
            idx[m] = s;
        }
    }
    if (n > 0) {
        uint s = idx[(n - 1) / 2];
        ca[i] = ca[s];
        cb[i] = cb[s];
        if (u_field != 0) mf[u_cfo + i] = mf[u_cfo + s];
    } else {
        ca[i] = vec4(0.0);
        cb[i] = vec4(0.0);
        if (u_field != 0) mf[u_cfo + i] = 0.0;
    }
#elif PASS == 6
    vec3 acc = vec3(0.0);
    if (cb[i].w > 0.0) {
        vec3 xo = ca[i].xyz;
        // x_o's material (a field): its dipole and R_P per channel, once per pixel
        float fo = u_field != 0 ? mf[u_cfo + i] : 0.0;
        vec4 dipo[3];
        vec3 rpo = vec3(0.0);
        if (u_field != 0)
            for (uint c = 0u; c < u_C; c++) dipo[c] = dipole(c, fo), rpo[c] = rp(c, fo);
        vec2 lp = vec2(dot(xo - u_c, u_u), dot(xo - u_c, u_v)) + u_Rl; // [0, 2 R_l]
        int jt = u_J - 1;
        uint Nt = u_N0 >> uint(jt);
        float tex = 2.0 * u_Rl / float(Nt);
        ivec2 lo = clamp(ivec2(floor((lp - u_window) / tex)), ivec2(0), ivec2(Nt - 1u));
        ivec2 hi = clamp(ivec2(floor((lp + u_window) / tex)), ivec2(0), ivec2(Nt - 1u));
        lo += u_chunk * CHUNK;
        hi = min(hi, lo + (CHUNK - 1));
        uint stack[16];
        for (int y = lo.y; y <= hi.y; y++)
            for (int x = lo.x; x <= hi.x; x++) {
                int sp = 0;
                stack[sp++] = (uint(jt) << 28) | (uint(y) << 14) | uint(x);
                while (sp > 0) {
                    uint e = stack[--sp];
                    int j = int(e >> 28);
                    uvec2 tt = uvec2(e & 16383u, (e >> 14) & 16383u);
                    uint N = u_N0 >> uint(j);
                    uint li = u_loff[j] + tt.y * N + tt.x;
                    uint s = sel[li];
                    if ((s & 7u) != 0u) {
                        vec4 a = la[li];
                        float d = length(xo - a.xyz) * u_mpu;
                        float z = dot(a.xyz - u_eye, u_fwd);
                        if (u_field != 0) {
                            float fi = mf[li];
                            for (uint c = 0u; c < u_C; c++) {
                                if ((s & (1u << c)) == 0u) continue;
                                // Eq. 13's range for the larger of the two endpoints' R_P (the finer
                                // level reaches farther: conservative), R-bar at its T(x_i) (Eq. 14)
                                float RP = max(rpo[c], rp(c, fi)), RPw = RP / u_mpu;
                                float rlo = u_k == 0 ? 0.0 : RP * rbar(u_tk0 * RPw / z);
                                float rhi = u_k == u_K - 1 ? u_Rcut[c] : RP * rbar(u_tk1 * RPw / z);
                                if (d >= rlo && d < rhi) {
                                    float po = rd_dip(dipo[c], d);
                                    float pi = fi == fo ? po : rd_dip(dipole(c, fi), d);
                                    acc[c] += sqrt(po * pi) * a.w; // seed 003 Eq. 8
                                }
                            }
                        } else
                        for (uint c = 0u; c < u_C; c++) {
                            if ((s & (1u << c)) == 0u) continue;
                            // level k's range for x_i (Eq. 13), R-bar at T(x_i) (Eq. 14)
                            float rlo = u_k == 0 ? 0.0 : u_RPmm[c] * rbar(u_tk0 * u_RPw[c] / z);
                            float rhi = u_k == u_K - 1 ? u_Rcut[c] : u_RPmm[c] * rbar(u_tk1 * u_RPw[c] / z);
                            if (d >= rlo && d < rhi) acc[c] += rd(c, d) * a.w;
                        }
                    }
                    if ((s & 8u) != 0u && j > 0) {
                        float ct = 2.0 * u_Rl / float(N << 1);
                        for (uint k = 0u; k < 4u; k++) {
                            uvec2 ch = 2u * tt + uvec2(k & 1u, k >> 1);
                            // the child's square against the reach (the light plane's distance bounds the 3D one)
                            vec2 q = clamp(lp, vec2(ch) * ct, vec2(ch + 1u) * ct);
                            if (length(q - lp) > u_window) continue;
                            stack[sp++] = (uint(j - 1) << 28) | (ch.y << 14) | ch.x;
                        }
                    }
                }
            }
    }
    bk[i] = (u_accum != 0 ? bk[i] : vec4(0.0)) + vec4(acc / PI, 0.0);
#elif PASS == 7
    vec3 B = vec3(0.0);
    if (cb[i].w > 0.0) {
        B = bk[i].xyz;
        if (u_k < u_K - 1) {
            // Eq. 17: the four nearest coarse pixels, bilinear x exp(-lambda_z |dz| / R_w), and with a
            // field the material weight w_m = exp(-lambda_m |R_P(x_o) - R_P(x_j)| / R_w) per channel,
            // lambda_m = lambda_z = 8 and R_P over R_w as |dz| is (w_m = 1: one material)
            vec2 f = (vec2(t) + 0.5) * 0.5 - 0.5;
            ivec2 b0 = ivec2(floor(f));
            vec2 w = f - vec2(b0);
            float zo = ca[i].w, fo = u_field != 0 ? mf[u_cfo + i] : 0.0;
            vec3 sum = vec3(0.0), ws = vec3(0.0);
            for (int k = 0; k < 4; k++) {
                ivec2 o = ivec2(k & 1, k >> 1);
                ivec2 c = clamp(b0 + o, ivec2(0), ivec2(u_size2) - 1);
                uint s = u_off2 + uint(c.y) * u_size2.x + uint(c.x);
                if (cb[s].w <= 0.0) continue;
                float wp = (o.x == 1 ? w.x : 1.0 - w.x) * (o.y == 1 ? w.y : 1.0 - w.y);
                float wk = wp * exp(-u_lambda_Rw * abs(zo - ca[s].w));
                float fj = u_field != 0 ? mf[u_cfo + s] : 0.0;
                for (uint ch = 0u; ch < u_C; ch++) {
                    float wm = u_field != 0 ? wk * exp(-u_lambda_Rw * abs(rp(ch, fo) - rp(ch, fj)) / u_mpu) : wk;
                    sum[ch] += wm * bk[s][ch];
                    ws[ch] += wm;
                }
            }
            for (uint ch = 0u; ch < u_C; ch++)
                if (ws[ch] > 0.0) B[ch] += sum[ch] / ws[ch];
        }
    }
    bk[i] = vec4(B, 0.0);
    if (u_k == 0) {
        vec3 q = u_C == 3u ? B : vec3(B.x);
        vec3 prev = u_first != 0 ? vec3(0.0) : imageLoad(u_out, ivec2(t)).xyz;
        imageStore(u_out, ivec2(t), vec4(prev + u_w * q, 1.0));
    }
#endif
}
