layout(location = 0) in vec2 a_pos;
layout(location = 1) in vec2 a_uv;
layout(location = 2) in vec4 a_rgba;
uniform vec2 u_size; // framebuffer size in pixels
out vec2 v_uv;
out vec4 v_rgba;
void main() {
    v_uv = a_uv;
    v_rgba = a_rgba;
    // pixels, origin top-left, y down -> clip space
    gl_Position = vec4(2.0 * a_pos.x / u_size.x - 1.0, 1.0 - 2.0 * a_pos.y / u_size.y, 0.0, 1.0);
}
