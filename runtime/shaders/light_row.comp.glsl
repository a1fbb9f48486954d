// one stored row: QDIR's values for this light (directional-exact, format §5.11),
// or the direction-set interpolation of the renderer's pass (Hao-Varshney 2004 §3.2)
layout(std430, binding = 0) readonly buffer Src { float src[]; };
void main() {
    uint e = gl_GlobalInvocationID.x;
    if (e >= u_count) return;
    uint c = e % C;
    float s = src[e];
    light_add(e, c, s);
}
