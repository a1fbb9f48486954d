layout(local_size_x = 256) in;
const uint C = uint(CHANNELS), N = uint(NCOEF), L = uint(SH_LEVELS);
#ifdef SH_NIBBLE
const uint BITS = 4u;
#elif defined(SH_LINEAR16)
const uint BITS = 16u; // int16 codes (Hao-Varshney 2004 sec. 4.1), two's complement
#define SH_LINEAR 1
#elif defined(SH_LINEAR8)
const uint BITS = 8u; // int8 codes, the step folded as for int16 (common/src/decode.c, l8_term)
#define SH_LINEAR 1
#else
const uint BITS = 8u;
#endif
const uint PER = 32u / BITS, W = (C * N + PER - 1u) / PER; // codes per word, words per vertex
layout(std430, binding = 3) writeonly buffer Q { float q[]; };
// Every load below is one uvec4, vec4 or vec2 where it can be: a software GPU
// (llvmpipe) runs each storage-buffer load as a loop over the lanes, so the
// count of loads, not their width, sets the pass's time (docs/gpu_layout.md §2,
// docs/benchmarks.md, "One load per table, in vectors").
#if NCOEF > 0
// each coded vertex's C * N codes in file order (channel-major), packed from the
// low bits up, starting on a word of its own, its words in groups of four;
// quad-major, so that neighbouring invocations read neighbouring groups:
// word n of vertex k is codes[(n / 4) * u_count + k][n % 4]
layout(std430, binding = 0) readonly buffer Codes { uvec4 codes[]; };
#ifdef SH_UBO
// dequantisation tables times y_i(light), rewritten per frame, as a uniform
// block when they fit the 16 KiB every GL and Vulkan allows (a constant or
// gathered load, no loop over the lanes); element i at sh_v[i / 4][i % 4]
layout(std140, binding = 4) uniform ShTable { vec4 sh_v[SH_UBO]; };
#define SH_T(i) sh_v[(i) >> 2u][(i) & 3u]
#else
layout(std430, binding = 4) readonly buffer ShTable { float sh_t[]; };
#define SH_T(i) sh_t[i]
#endif
// the table's element i: sh_t[(c * N + i) * L + code];
// SH_NIBBLE: two codes a table (common/src/decode.c, sss_decode_fold_sh), pair m of channel c
// at sh_t[(c * P + m) * 256 + (x0 | x1 << 4)], an odd last code at sh_t[C * P * 256 + c * 16 + x];
// linear kinds (L = 1): sh_t[c * N + i] = scale * y_i / M (M = 127 or 32767), the coefficient is code * sh_t
#endif
#ifdef REFS
// per coded vertex: its vertex and its reference triangle's three references
// (resolved when the layout is made), and its two weights as the floats the C
// decoder blends with (sss_decode_ref_weight)
layout(std430, binding = 1) readonly buffer Coded { uvec4 rec[]; };
layout(std430, binding = 6) readonly buffer Weights { vec2 wts[]; };
// the references' values of the frame, written by the rows pass, four floats a reference
#if CHANNELS == 1
layout(std430, binding = 5) readonly buffer Refs { float refq[]; };
#define REF_AT(r) vec4(refq[4u * (r)])
#else
layout(std430, binding = 5) readonly buffer Refs { vec4 refq[]; };
#define REF_AT(r) refq[r]
#endif
#endif
uniform uint u_count;   // coded vertices
void main() {
    // no early return: an invocation past the end redoes the last vertex and
    // stores nothing, so that the loads run outside any branch
    bool live = gl_GlobalInvocationID.x < u_count;
    uint k = min(gl_GlobalInvocationID.x, u_count - 1u), v = k;
#ifdef REFS
    // the channels share the triangle and the weights (§4.2)
    uvec4 rv = rec[k];
    v = rv.x;
    vec2 w = wts[k];
    float w0 = w.x, w1 = w.y;
    precise float w2 = 1.0 - w0 - w1;
    vec4 R0 = REF_AT(rv.y), R1 = REF_AT(rv.z), R2 = REF_AT(rv.w);
#endif
#if NCOEF > 0
    // the group of words holding the current code, loaded when the walk
    // reaches it: no per-invocation array, which a software rasteriser keeps
    // in memory when the loops are too long to unroll (order 7 in 16 bits: 74 words)
    uvec4 quad = uvec4(0u);
    uint word = 0u;
    // code element e (walking 0 … C·N − 1 in order): at the first code of a
    // word, that word, from a group loaded at the group's first word
#define WORD_AT(e) \
    if ((e) % PER == 0u) { \
        if (((e) / PER) % 4u == 0u) quad = codes[((e) / PER / 4u) * u_count + k]; \
        word = quad[((e) / PER) % 4u]; \
    }
    // each channel's SH sum (§4.1) first, in a loop of its own: with the
    // blend and the store in the same loop body, the reference form's body
    // grew past what the GLSL compiler unrolls (order 3 in linear8), and the
    // loop's every load then ran under a mask (docs/benchmarks.md)
    vec4 S = vec4(0.0);
    for (uint ch = 0u; ch < C; ch++) {
        precise float acc = 0.0;
#ifdef SH_NIBBLE
        const uint P = N / 2u;
        for (uint m = 0u; m < P; m++) {
            uint e = ch * N + 2u * m;
            WORD_AT(e)
            uint x0 = (word >> ((e % PER) * BITS)) & 15u;
            e++;
            WORD_AT(e)
            uint x1 = (word >> ((e % PER) * BITS)) & 15u;
            acc += SH_T((ch * P + m) * 256u + (x0 | (x1 << 4u)));
        }
        if (N % 2u == 1u) {
            uint e = ch * N + N - 1u;
            WORD_AT(e)
            acc += SH_T(C * P * 256u + ch * 16u + ((word >> ((e % PER) * BITS)) & 15u));
        }
#else
        for (uint j = 0u; j < N; j++) {
            uint e = ch * N + j;
            WORD_AT(e)
#ifdef SH_LINEAR
            // the BITS bits, sign-extended: the C decoder's (int8_t) or (int16_t) code
            int code = int(word << (32u - BITS - (e % PER) * BITS)) >> (32u - BITS);
            precise float p = float(code) * SH_T(ch * N + j);
            acc += p;
#else
            uint code = (word >> ((e % PER) * BITS)) & ((1u << BITS) - 1u);
            acc += SH_T((ch * N + j) * L + code);
#endif
        }
#endif
        S[ch] = acc;
    }
#endif
    for (uint ch = 0u; ch < C; ch++) {
        precise float x = 0.0;
#ifdef REFS
        // the C decoder's float blend (coded_blend): products and sums in this order, none fused
        precise float b = w0 * R0[ch] + w1 * R1[ch] + w2 * R2[ch];
        x = b;
#endif
#if NCOEF > 0
        x += S[ch];
#endif
        if (live) q[v * C + ch] = x > 0.0 ? x : 0.0; // q >= 0 physically; the C decoder clamps the same way
    }
}
