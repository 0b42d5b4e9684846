// (yuv_gl.c puts "#version 330 core" and the defines W, H, SS before this.)
// The last pass of a video frame: the frame's RGBA8 texture (opaque, so
// premultiplied equals straight) to BT.709 limited-range Y'CbCr 4:2:0.
// A fragment (x, j) takes the 8 x 2 block of pixels at columns 8x .. 8x+7,
// rows 2j, 2j+1 (rows counted from the top), and the column to its left,
// each texel fetched once, and writes 8 + 8 Y bytes and 4 Cb and 4 Cr
// bytes to four integer targets (yuv_gl.c reads them back into image.h's
// SP_IMAGE_YUV420 layout; little-endian: byte k in bits 8k..8k+7).
//   Y  = 16 + 219 (0.2126 R + 0.7152 G + 0.0722 B)
//   Cb = 128 + 224 (B - Y') / 1.8556,  Cr = 128 + 224 (R - Y') / 1.5748
// with R, G, B in 0..1 and Y' the bracket above; rounded to the nearest
// level. Chroma sited left, as H.264 assumes unless told: sample (i, j)
// takes luma columns 2i-1, 2i, 2i+1 weighted 1/4, 1/2, 1/4 (column 0
// repeated at the left edge) and rows 2j, 2j+1 averaged. Supersampled
// (SS > 1): each output pixel is the mean of its SS x SS block.
uniform sampler2D u_frame; // SS*W x SS*H; texture row 0 is the image's bottom row

layout(location = 0) out uvec2 o_y0; // Y of row 2j, bytes 8x .. 8x+7
layout(location = 1) out uvec2 o_y1; // Y of row 2j+1
layout(location = 2) out uint o_cb;  // Cb of chroma row j, bytes 4x .. 4x+3
layout(location = 3) out uint o_cr;  // Cr

const vec3 K = vec3(0.2126, 0.7152, 0.0722);

// Output pixel (x, y) of the image, y from the top; x clamped to the image
// (beyond the right edge: padding bytes).
vec3 rgb(int x, int y)
{
    x = clamp(x, 0, W - 1);
#if SS == 1
    return texelFetch(u_frame, ivec2(x, H - 1 - y), 0).rgb;
#else
    ivec2 base = ivec2(x * SS, (H - 1 - y) * SS);
    vec3 s = vec3(0.0);
    for (int j = 0; j < SS; j++)
        for (int i = 0; i < SS; i++)
            s += texelFetch(u_frame, base + ivec2(i, j), 0).rgb;
    return s * (1.0 / float(SS * SS));
#endif
}

uint pack4(vec4 v)
{
    uvec4 b = uvec4(clamp(floor(v + 0.5), 0.0, 255.0));
    return b.x | (b.y << 8) | (b.z << 16) | (b.w << 24);
}

vec4 luma(vec3 p0, vec3 p1, vec3 p2, vec3 p3)
{
    return 16.0 + 219.0 * vec4(dot(K, p0), dot(K, p1), dot(K, p2), dot(K, p3));
}

void main()
{
    ivec2 f = ivec2(gl_FragCoord.xy);
    int x0 = 8 * f.x, y0 = 2 * f.y;
    vec3 a[9], b[9]; // rows 2j, 2j+1; columns x0-1 .. x0+7
    for (int k = 0; k < 9; k++) {
        a[k] = rgb(x0 - 1 + k, y0);
        b[k] = rgb(x0 - 1 + k, y0 + 1);
    }
    o_y0 = uvec2(pack4(luma(a[1], a[2], a[3], a[4])), pack4(luma(a[5], a[6], a[7], a[8])));
    o_y1 = uvec2(pack4(luma(b[1], b[2], b[3], b[4])), pack4(luma(b[5], b[6], b[7], b[8])));
    vec4 cb, cr;
    for (int m = 0; m < 4; m++) { // sample 4x+m: columns x0+2m-1 .. x0+2m+1
        vec3 c = 0.125 * (a[2 * m] + 2.0 * a[2 * m + 1] + a[2 * m + 2]
                          + b[2 * m] + 2.0 * b[2 * m + 1] + b[2 * m + 2]);
        float y = dot(K, c);
        cb[m] = 128.0 + 224.0 / 1.8556 * (c.b - y);
        cr[m] = 128.0 + 224.0 / 1.5748 * (c.r - y);
    }
    o_cb = pack4(cb);
    o_cr = pack4(cr);
}
