#version 330 core
// Glyph coverage from the R8 atlas (nearest: quads sit on whole pixels),
// output premultiplied.
in vec2 v_uv;
flat in vec4 v_color;
uniform sampler2D u_atlas_tex;
out vec4 o_color;

void main()
{
    float a = texture(u_atlas_tex, v_uv).r * v_color.a;
    if (a <= 0.0)
        discard;
    o_color = vec4(v_color.rgb * a, a);
}
