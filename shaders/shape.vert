#version 330 core
// One instance = one capsule: the segment p0-p1 (px, y down from the top-left
// corner) swept by a disc of radius a_style.x (px). A disc has p0 == p1.
// The quad is built from gl_VertexID (triangle strip of 4), one pixel wider
// than the capsule on every side for the antialiased edge.
layout(location = 0) in vec4 a_seg;   // p0.xy, p1.xy, px
layout(location = 1) in vec2 a_style; // half width (px), kind (0 flat, 1 ball, 2 box)
layout(location = 2) in vec4 a_color; // straight RGBA, 0..1

uniform vec2 u_size; // viewport, px

out vec2 v_local;          // px from the segment midpoint: along, across
flat out float v_half_len; // px
flat out float v_radius;   // px
flat out float v_kind;
flat out vec4 v_color;

void main()
{
    vec2 p0 = a_seg.xy, p1 = a_seg.zw;
    vec2 d = p1 - p0;
    float len = length(d);
    vec2 u = len > 1e-4 ? d / len : vec2(1.0, 0.0);
    vec2 n = vec2(-u.y, u.x);
    float ext = a_style.x + 1.0;
    vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0;
    // A box (kind 2) has no round caps: one pixel beyond its ends suffices.
    float ext_along = a_style.y > 1.5 ? 1.0 : ext;
    vec2 local = corner * vec2(0.5 * len + ext_along, ext);
    vec2 pos = 0.5 * (p0 + p1) + u * local.x + n * local.y;

    gl_Position = vec4(2.0 * pos.x / u_size.x - 1.0, 1.0 - 2.0 * pos.y / u_size.y, 0.0, 1.0);
    v_local = local;
    v_half_len = 0.5 * len;
    v_radius = a_style.x;
    v_kind = a_style.y;
    v_color = a_color;
}
