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
#if NCOEF > 0
// each coded vertex's C * N codes in file order (channel-major), packed from the
// low bits up, starting on a word of its own; word-major, so that neighbouring
// invocations read neighbouring words: code b of vertex k is in codes[(b / PER) * u_count + k]
layout(std430, binding = 0) readonly buffer Codes { uint codes[]; };
// dequantisation tables times y_i(light), rewritten per frame: sh_t[(c * N + i) * L + code];
// SH_NIBBLE: two codes a table (common/src/decode.c, sss_decode_fold_sh), pair m of channel c
// at sh_t[(c * P + m) * 256 + (x0 | x1 << 4)], an odd last code at sh_t[C * P * 256 + c * 16 + x];
// linear kinds (L = 1): sh_t[c * N + i] = scale * y_i / M (M = 127 or 32767), the coefficient is code * sh_t
layout(std430, binding = 4) readonly buffer ShTable { float sh_t[]; };
#endif
#ifdef REFS
// per coded vertex: vertex index, reference triangle, weight codes (low 16 bits w0, high w1)
layout(std430, binding = 1) readonly buffer Coded { uint rec[]; };
layout(std430, binding = 2) readonly buffer RefTri { uint ref_tri[]; };
layout(std430, binding = 5) readonly buffer Refs { float refq[]; };
// weight of each code, w_lo + (w_hi - w_lo) * code / (2^bits - 1) rounded to float, computed by the CPU
// as the C decoder does (sss_decode_ref_weight)
layout(std430, binding = 6) readonly buffer Weights { float wtab[]; };
#endif
uniform uint u_count;   // coded vertices
void main() {
    uint k = gl_GlobalInvocationID.x, v = k;
    if (k >= u_count) return;
#ifdef REFS
    // the channels share the triangle and the weights (§4.2)
    v = rec[3u * k];
    uint t = 3u * rec[3u * k + 1u], wc = rec[3u * k + 2u];
    uint r0 = ref_tri[t] * C, r1 = ref_tri[t + 1u] * C, r2 = ref_tri[t + 2u] * C;
    float w0 = wtab[wc & 65535u], w1 = wtab[wc >> 16u];
    precise float w2 = 1.0 - w0 - w1;
#endif
#if NCOEF > 0
    // the word holding the current code, loaded when the walk reaches it:
    // no per-invocation array, which a software rasteriser keeps in memory
    // when the loops are too long to unroll (order 7 in 16 bits: 74 words)
    uint word = 0u;
#endif
    for (uint ch = 0u; ch < C; ch++) {
        precise float x = 0.0;
#ifdef REFS
        // the C decoder's float blend (coded_blend): products and sums in this order, none fused
        precise float b = w0 * refq[r0 + ch] + w1 * refq[r1 + ch] + w2 * refq[r2 + ch];
        x = b;
#endif
#if NCOEF > 0
        precise float acc = 0.0;
#ifdef SH_NIBBLE
        const uint P = N / 2u;
        for (uint m = 0u; m < P; m++) {
            uint e = ch * N + 2u * m;
            if (e % PER == 0u) word = codes[(e / PER) * u_count + k]; // e walks 0 … C·N − 1 in order
            uint x0 = (word >> ((e % PER) * BITS)) & 15u;
            e++;
            if (e % PER == 0u) word = codes[(e / PER) * u_count + k];
            uint x1 = (word >> ((e % PER) * BITS)) & 15u;
            acc += sh_t[(ch * P + m) * 256u + (x0 | (x1 << 4u))];
        }
        if (N % 2u == 1u) {
            uint e = ch * N + N - 1u;
            if (e % PER == 0u) word = codes[(e / PER) * u_count + k];
            acc += sh_t[C * P * 256u + ch * 16u + ((word >> ((e % PER) * BITS)) & 15u)];
        }
#else
        for (uint j = 0u; j < N; j++) {
            uint e = ch * N + j;
            if (e % PER == 0u) word = codes[(e / PER) * u_count + k]; // e walks 0 … C·N − 1 in order
#ifdef SH_LINEAR
            // the BITS bits, sign-extended: the C decoder's (int8_t) or (int16_t) code
            int code = int(word << (32u - BITS - (e % PER) * BITS)) >> (32u - BITS);
            precise float p = float(code) * sh_t[ch * N + j];
            acc += p;
#else
            uint code = (word >> ((e % PER) * BITS)) & ((1u << BITS) - 1u);
            acc += sh_t[(ch * N + j) * L + code];
#endif
        }
#endif
        x += acc;
#endif
        q[v * C + ch] = x > 0.0 ? x : 0.0; // q >= 0 physically; the C decoder clamps the same way
    }
}
