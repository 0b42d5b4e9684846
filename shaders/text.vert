#version 330 core
// One instance = one glyph quad: a screen rectangle (px, y down from the
// top-left corner) textured with an atlas rectangle (texels).
layout(location = 0) in vec4 a_rect;  // x0, y0, x1, y1
layout(location = 1) in vec4 a_uv;    // u0, v0, u1, v1 (texels)
layout(location = 2) in vec4 a_color; // straight RGBA

uniform vec2 u_size;  // viewport, px
uniform vec2 u_atlas; // atlas size, texels

out vec2 v_uv;
flat out vec4 v_color;

void main()
{
    vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));
    vec2 pos = mix(a_rect.xy, a_rect.zw, corner);
    gl_Position = vec4(2.0 * pos.x / u_size.x - 1.0, 1.0 - 2.0 * pos.y / u_size.y, 0.0, 1.0);
    v_uv = mix(a_uv.xy, a_uv.zw, corner) / u_atlas;
    v_color = a_color;
}
