#version 330 core
// Coverage of a capsule from the pixel's distance to its segment:
// clamp(radius - d + 0.5, 0, 1), one pixel of analytic antialiasing.
// kind 1 shades the disc as a lit ball (light from the upper left) with a
// darker rim. kind 2 is a box: the segment's rectangle without round caps
// (panel backgrounds, axes, ticks). kind 3 is a soft ellipse: radii v_half_len
// along and v_radius across, alpha falling as (1 - d^2)^2 with d the distance
// in radii (shadows). Output is premultiplied by alpha * coverage.
in vec2 v_local;
flat in float v_half_len;
flat in float v_radius;
flat in float v_kind;
flat in vec4 v_color;

out vec4 o_color;

void main()
{
    if (v_kind > 2.5) {
        vec2 q = v_local / vec2(max(v_half_len, 1e-3), max(v_radius, 1e-3));
        float f = max(1.0 - dot(q, q), 0.0);
        float sa = v_color.a * f * f;
        if (sa <= 0.0)
            discard;
        o_color = vec4(v_color.rgb * sa, sa);
        return;
    }
    float d = length(vec2(max(abs(v_local.x) - v_half_len, 0.0), v_local.y));
    float cover = clamp(v_radius - d + 0.5, 0.0, 1.0);
    if (v_kind > 1.5)
        cover = clamp(min(v_half_len - abs(v_local.x), v_radius - abs(v_local.y)) + 0.5, 0.0, 1.0);
    if (cover <= 0.0)
        discard;
    vec3 rgb = v_color.rgb;
    if (v_kind > 0.5 && v_kind < 1.5) {
        // v_local is (x right, y down) from the centre for a disc.
        vec2 q = v_local / v_radius;
        vec3 nrm = vec3(q, sqrt(max(1.0 - dot(q, q), 0.0)));
        const vec3 light = normalize(vec3(-0.55, -0.65, 0.75));
        float diffuse = max(dot(nrm, light), 0.0);
        float spec = pow(max(dot(nrm, normalize(light + vec3(0.0, 0.0, 1.0))), 0.0), 28.0);
        rgb = rgb * (0.32 + 0.78 * diffuse) + vec3(0.55 * spec);
        float rim = smoothstep(v_radius - 2.2, v_radius - 0.7, d);
        rgb = mix(rgb, v_color.rgb * 0.35, rim);
    }
    float a = v_color.a * cover;
    o_color = vec4(rgb * a, a);
}
