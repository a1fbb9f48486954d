layout(local_size_x = 256) in;
#ifdef LLOYD8
layout(std430, binding = 0) readonly buffer RowA { uint row_a[]; };
layout(std430, binding = 1) readonly buffer RowB { uint row_b[]; };
layout(std430, binding = 2) readonly buffer RowC { uint row_c[]; };
#ifdef NEAREST4
layout(std430, binding = 7) readonly buffer RowD { uint row_d[]; };
#endif
// three (NEAREST4: four) folded tables, rewritten per frame: levels[(r * channels + c) * 256 + x] = w_r * level_c[x]
layout(std430, binding = 4) readonly buffer Levels { float levels[]; };
uint byte_at(uint word, uint i) { return (word >> ((i & 3u) * 8u)) & 255u; }
#else
layout(std430, binding = 0) readonly buffer RowA { float row_a[]; };
layout(std430, binding = 1) readonly buffer RowB { float row_b[]; };
layout(std430, binding = 2) readonly buffer RowC { float row_c[]; };
#ifdef NEAREST4
layout(std430, binding = 7) readonly buffer RowD { float row_d[]; };
#endif
#endif
layout(std430, binding = 3) writeonly buffer Q { float q[]; };
#ifdef REFS
// reference values for pass 2, four floats a reference (the coded pass loads
// a reference's channels as one vec4), and which vertex each reference is
layout(std430, binding = 5) writeonly buffer Refs { float refq[]; };
layout(std430, binding = 6) readonly buffer RefVertex { uint ref_vertex[]; };
#endif
#ifdef NEAREST4
// Hao-Varshney 2004 3.2, Fig. 3: the four nearest direction samples, inverse-angle
// weights (sss_dirset_nearest4); the fourth row is bound at 7, since 3 is q
uniform vec4 u_w;
#else
uniform vec3 u_w;       // barycentric weights of the three direction samples (float rows)
#endif
#ifdef VECTOR
// the vector integral Q (section QVEC): rows of three components per value,
// interpolated and dotted with the light (Hao-Varshney 2004 sec. 3.2)
uniform vec3 u_light;   // the unit light direction, as float
#endif
uniform uint u_count;   // row entries: (vertices or references) x channels
uniform uint u_channels;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
#ifdef LLOYD8
    // three loads and two adds in this order: the C decoder's sum, to the bit
    uint ch = i % u_channels, k = i >> 2u, t = 256u * u_channels, base = 256u * ch;
    precise float x = levels[base + byte_at(row_a[k], i)] + levels[t + base + byte_at(row_b[k], i)]
                    + levels[2u * t + base + byte_at(row_c[k], i)];
#ifdef NEAREST4
    x = x + levels[3u * t + base + byte_at(row_d[k], i)];
#endif
#elif defined(VECTOR)
    // the C decoder's order (sss_decode_vector_range): each component as q's
    // float rows (NEAREST4: with the fourth sample), then the dot product,
    // clamped at 0
    uint b = 3u * i;
#ifdef NEAREST4
    precise float qx = u_w.x * row_a[b] + u_w.y * row_b[b] + u_w.z * row_c[b] + u_w.w * row_d[b];
    precise float qy = u_w.x * row_a[b + 1u] + u_w.y * row_b[b + 1u] + u_w.z * row_c[b + 1u] + u_w.w * row_d[b + 1u];
    precise float qz = u_w.x * row_a[b + 2u] + u_w.y * row_b[b + 2u] + u_w.z * row_c[b + 2u] + u_w.w * row_d[b + 2u];
#else
    precise float qx = u_w.x * row_a[b] + u_w.y * row_b[b] + u_w.z * row_c[b];
    precise float qy = u_w.x * row_a[b + 1u] + u_w.y * row_b[b + 1u] + u_w.z * row_c[b + 1u];
    precise float qz = u_w.x * row_a[b + 2u] + u_w.y * row_b[b + 2u] + u_w.z * row_c[b + 2u];
#endif
    precise float x = max(qx * u_light.x + qy * u_light.y + qz * u_light.z, 0.0);
#elif defined(NEAREST4)
    precise float x = u_w.x * row_a[i] + u_w.y * row_b[i] + u_w.z * row_c[i] + u_w.w * row_d[i];
#else
    // precise: no fused multiply-adds (NVIDIA's compiler fuses where it
    // may), so the products and sums round as the C decoder's do
    precise float x = u_w.x * row_a[i] + u_w.y * row_b[i] + u_w.z * row_c[i];
#endif
#ifdef REFS
    uint r = i / u_channels;
    refq[4u * r + ch] = x;
    q[ref_vertex[r] * u_channels + ch] = x;
#else
    q[i] = x;
#endif
}
