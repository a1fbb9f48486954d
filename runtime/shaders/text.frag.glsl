uniform sampler2D u_atlas;
in vec2 v_uv;
in vec4 v_rgba;
out vec4 o_color;
void main() {
    float cover = texture(u_atlas, v_uv).r;
    if (cover <= 0.0) discard;
    o_color = vec4(v_rgba.rgb, v_rgba.a * cover);
}
