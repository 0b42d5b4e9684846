/* springpend: sink and PNG tests, TAP. Synthetic frames (a coloured square
 * moving over a gradient), no GL. Usage: test_sink SRC_DIR BUILD_DIR;
 * outputs go under BUILD_DIR/sink-out. */
#ifdef NDEBUG
#error "tests need assert()"
#endif
#include <assert.h>
#include <ftw.h>
#include <glob.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>

#include "springpend/common.h"
#include "springpend/png_io.h"
#include "springpend/sink.h"

static char out_dir[4096];

static const char *out_path(const char *name)
{
    static char buf[8][4200];
    static int next;
    char *p = buf[next++ % 8];
    snprintf(p, sizeof(buf[0]), "%s/%s", out_dir, name);
    return p;
}

static bool exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Any PATH.XXXXXX.part (outfile.h's unique .part names). */
static bool exists_part(const char *path)
{
    char pattern[4300];
    glob_t g;
    snprintf(pattern, sizeof(pattern), "%s.??????.part", path);
    bool found = glob(pattern, 0, NULL, &g) == 0 && g.gl_pathc > 0;
    globfree(&g);
    return found;
}

/* ---- synthetic frames ---- */

enum { SQ = 48 };
static const uint8_t sq_rgb[3] = { 230, 40, 40 };

static int sq_x(int k) { return 20 + 8 * k; }
static int sq_y(int k) { return 60 + 4 * k; }

/* Gradient background plus the square for frame k. alpha: vary alpha over
 * the image (for PNG round trips) or keep it opaque. */
static void draw(struct sp_image *img, int k, bool alpha)
{
    for (int y = 0; y < img->height; y++) {
        uint8_t *row = img->pixels + (size_t)y * img->stride;
        for (int x = 0; x < img->width; x++) {
            uint8_t *p = row + 4 * x;
            bool in = x >= sq_x(k) && x < sq_x(k) + SQ && y >= sq_y(k) &&
                      y < sq_y(k) + SQ;
            p[0] = in ? sq_rgb[0] : (uint8_t)(255 * x / img->width);
            p[1] = in ? sq_rgb[1] : (uint8_t)(255 * y / img->height);
            p[2] = in ? sq_rgb[2] : 96;
            p[3] = alpha ? (uint8_t)(x * 7 + y * 3) : 255;
        }
    }
}

/* ---- checks ---- */

static bool images_equal(const struct sp_image *a, const struct sp_image *b)
{
    if (a->width != b->width || a->height != b->height)
        return false;
    for (int y = 0; y < a->height; y++)
        if (memcmp(a->pixels + (size_t)y * a->stride,
                   b->pixels + (size_t)y * b->stride, 4 * (size_t)a->width))
            return false;
    return true;
}

static bool file_contains(const char *path, const void *needle, size_t n)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return false;
    static char buf[1 << 20];
    size_t len = fread(buf, 1, sizeof(buf), fp);
    fclose(fp);
    return memmem(buf, len, needle, n) != NULL;
}

static bool test_png_round_trip(void)
{
    struct sp_image a, b = { 0 };
    const char *path = out_path("roundtrip.png");
    bool pass = sp_image_alloc(&a, 97, 61) == 0; /* odd sizes on purpose */
    draw(&a, 2, true);
    const struct sp_png_text text[] = {
        { .key = "Software", .text = "springpend " SP_VERSION },
        { .key = "Comment", .text = "round trip" },
    };
    pass = pass && sp_png_write_opts(path, &a, &(struct sp_png_write_opts){
        .level = SP_PNG_LEVEL_DEFAULT, .text = text, .n_text = 2 }) == 0;
    pass = pass && sp_png_read(path, &b) == 0 && images_equal(&a, &b);
    static const char chunk[] = "tEXtSoftware\0springpend " SP_VERSION;
    pass = pass && file_contains(path, chunk, sizeof(chunk) - 1);
    sp_image_free(&a);
    sp_image_free(&b);
    return pass;
}

static bool test_png_errors(void)
{
    struct sp_image img;
    /* png_io.h: what is not a regular file (a missing one too) is refused */
    bool pass = sp_png_read(out_path("missing.png"), &img) == SP_E_INPUT &&
                img.pixels == NULL;
    struct sp_image tiny;
    assert(sp_image_alloc(&tiny, 2, 2) == 0);
    pass = pass && sp_png_write(out_path("bad-level.png"), &tiny, 10) ==
                       SP_E_INPUT;
    pass = pass && sp_png_write_opts(out_path("bad-key.png"), &tiny,
                       &(struct sp_png_write_opts){
                           .level = 1, .n_text = 1,
                           .text = &(struct sp_png_text){ .key = "", .text = "x" } }) ==
                       SP_E_INPUT;
    pass = pass && !exists(out_path("bad-level.png")) &&
           !exists(out_path("bad-key.png"));
    sp_image_free(&tiny);
    return pass;
}

static struct sp_sink *open_sink(const char *path, int w, int h, int *err)
{
    struct sp_sink *s = NULL;
    *err = sp_sink_open(&s, &(struct sp_sink_desc){
        .path = path, .width = w, .height = h, .fps = 30 });
    return s;
}

static bool test_png_sequence(void)
{
    const char *pattern = out_path("seq/a/%05d.png"); /* folders are new */
    struct sp_image img, back = { 0 };
    int err;
    assert(sp_image_alloc(&img, 64, 48) == 0);
    struct sp_sink *s = NULL;
    err = sp_sink_open(&s, &(struct sp_sink_desc){
        .path = pattern, .width = 64, .height = 48, .fps = 30, .alpha = 1 });
    bool pass = err == 0;
    for (int k = 0; pass && k < 5; k++) {
        draw(&img, k, true);
        pass = sp_sink_write(s, &img) == 0;
    }
    pass = pass && sp_sink_close(&s) == 0 && s == NULL;
    for (int k = 0; pass && k < 5; k++) {
        char name[64];
        snprintf(name, sizeof(name), "seq/a/%05d.png", k);
        pass = exists(out_path(name)) && !exists_part(out_path(name));
    }
    pass = pass && !exists(out_path("seq/a/00005.png"));
    /* the last frame holds what was drawn last */
    pass = pass && sp_png_read(out_path("seq/a/00004.png"), &back) == 0 &&
           images_equal(&img, &back);
    /* "%%" is a literal '%' */
    s = open_sink(out_path("seq/b/%%_%d.png"), 64, 48, &err);
    pass = pass && err == 0 && sp_sink_write(s, &img) == 0 &&
           sp_sink_close(&s) == 0 && exists(out_path("seq/b/%_0.png"));
    sp_image_free(&img);
    sp_image_free(&back);
    return pass;
}

/* Numbering from first_frame; an aborted sequence removes what it wrote
 * (sink.h: nothing is left at the target path). */
static bool test_png_sequence_abort(void)
{
    struct sp_image img;
    struct sp_sink *s = NULL;
    assert(sp_image_alloc(&img, 32, 24) == 0);
    int err = sp_sink_open(&s, &(struct sp_sink_desc){
        .path = out_path("seqab/%03d.png"), .width = 32, .height = 24,
        .fps = 30, .first_frame = 7 });
    bool pass = err == 0;
    for (int k = 0; pass && k < 4; k++) {
        draw(&img, k, false);
        pass = sp_sink_write(s, &img) == 0;
    }
    sp_sink_abort(&s);
    pass = pass && !s;
    for (int k = 0; k < 12; k++) {
        char name[64];
        snprintf(name, sizeof(name), "seqab/%03d.png", k);
        pass = pass && !exists(out_path(name)) && !exists_part(out_path(name));
    }
    /* and a closed one keeps frames 007..010 */
    err = sp_sink_open(&s, &(struct sp_sink_desc){
        .path = out_path("seqab/%03d.png"), .width = 32, .height = 24,
        .fps = 30, .first_frame = 7 });
    for (int k = 0; pass && k < 4; k++)
        pass = sp_sink_write(s, &img) == 0;
    pass = pass && sp_sink_close(&s) == 0 && !exists(out_path("seqab/006.png")) &&
           exists(out_path("seqab/007.png")) && exists(out_path("seqab/010.png")) &&
           !exists(out_path("seqab/011.png"));
    sp_image_free(&img);
    return pass;
}

static bool test_png_single(void)
{
    const char *path = out_path("single.png");
    struct sp_image img;
    int err;
    assert(sp_image_alloc(&img, 32, 32) == 0);
    draw(&img, 0, false);
    struct sp_sink *s = open_sink(path, 32, 32, &err);
    bool pass = err == 0 && sp_sink_write(s, &img) == 0 &&
                !exists(path) && /* not before close */
                sp_sink_write(s, &img) == SP_E_INPUT &&
                sp_sink_close(&s) == 0 && exists(path) && !exists_part(path);
    sp_image_free(&img);
    return pass;
}

/* Top-level MP4 boxes: true when moov comes before mdat. */
static bool moov_before_mdat(const char *path)
{
    FILE *fp = fopen(path, "rb");
    long moov = -1, mdat = -1, pos = 0;
    uint8_t h[16];
    while (fp && fseek(fp, pos, SEEK_SET) == 0 && fread(h, 1, 8, fp) == 8) {
        uint64_t size = (uint64_t)h[0] << 24 | h[1] << 16 | h[2] << 8 | h[3];
        if (size == 1 && fread(h + 8, 1, 8, fp) == 8) {
            size = 0;
            for (int i = 8; i < 16; i++)
                size = size << 8 | h[i];
        }
        if (!memcmp(h + 4, "moov", 4))
            moov = pos;
        if (!memcmp(h + 4, "mdat", 4))
            mdat = pos;
        if (size < 8)
            break;
        pos += (long)size;
    }
    if (fp)
        fclose(fp);
    return moov >= 0 && mdat >= 0 && moov < mdat;
}

/* BT.709 limited-range Y, Cb, Cr of an sRGB colour. */
static void rgb_to_yuv709(const uint8_t rgb[3], double yuv[3])
{
    double r = rgb[0] / 255.0, g = rgb[1] / 255.0, b = rgb[2] / 255.0;
    double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    yuv[0] = 16 + 219 * y;
    yuv[1] = 128 + 224 * (b - y) / 1.8556;
    yuv[2] = 128 + 224 * (r - y) / 1.5748;
}

static bool near_yuv(const AVFrame *f, int x, int y, const uint8_t rgb[3])
{
    double want[3];
    rgb_to_yuv709(rgb, want);
    int got[3] = {
        f->data[0][y * f->linesize[0] + x],
        f->data[1][y / 2 * f->linesize[1] + x / 2],
        f->data[2][y / 2 * f->linesize[2] + x / 2],
    };
    bool pass = true;
    for (int i = 0; i < 3; i++)
        pass = pass && got[i] > want[i] - 6 && got[i] < want[i] + 6;
    if (!pass)
        printf("# at (%d,%d) got YUV %d %d %d, want %.1f %.1f %.1f\n", x, y,
               got[0], got[1], got[2], want[0], want[1], want[2]);
    return pass;
}

/* Reopens the MP4 and checks stream, packets, duration and frame 15. */
static bool check_mp4(const char *path, int w, int h, int n, double fps)
{
    AVFormatContext *ic = NULL;
    AVCodecContext *dec = NULL;
    AVPacket *pkt = av_packet_alloc();
    AVFrame *frame = av_frame_alloc();
    int packets = 0, frames = 0;
    bool pass = false, colour = false;

    if (avformat_open_input(&ic, path, NULL, NULL) < 0 ||
        avformat_find_stream_info(ic, NULL) < 0 || ic->nb_streams != 1)
        goto done;
    AVStream *st = ic->streams[0];
    AVCodecParameters *par = st->codecpar;
    double duration = ic->duration / (double)AV_TIME_BASE;
    printf("# %s: %s %s %dx%d, %.4f s, %s\n", path,
           avcodec_get_name(par->codec_id),
           av_get_pix_fmt_name(par->format), par->width, par->height,
           duration, av_color_space_name(par->color_space));
    if (par->codec_id != AV_CODEC_ID_H264 ||
        par->format != AV_PIX_FMT_YUV420P || par->width != w ||
        par->height != h || par->color_space != AVCOL_SPC_BT709 ||
        duration < n / fps - 1 / fps || duration > n / fps + 1 / fps)
        goto done;

    const AVCodec *codec = avcodec_find_decoder(par->codec_id);
    dec = avcodec_alloc_context3(codec);
    if (!dec || avcodec_parameters_to_context(dec, par) < 0 ||
        avcodec_open2(dec, codec, NULL) < 0)
        goto done;
    for (bool eof = false; !eof;) {
        eof = av_read_frame(ic, pkt) < 0;
        if (!eof)
            packets++;
        if (avcodec_send_packet(dec, eof ? NULL : pkt) < 0)
            goto done;
        av_packet_unref(pkt);
        while (avcodec_receive_frame(dec, frame) == 0) {
            if (frames == 15) {
                int cx = sq_x(15) + SQ / 2, cy = sq_y(15) + SQ / 2;
                /* the square now, and the gradient where it began */
                uint8_t bg[3] = { 255 * (sq_x(0) + 8) / w,
                                  255 * (sq_y(0) + 8) / h, 96 };
                colour = near_yuv(frame, cx, cy, sq_rgb) &&
                         near_yuv(frame, sq_x(0) + 8, sq_y(0) + 8, bg);
            }
            frames++;
        }
    }
    printf("# %d packets, %d frames\n", packets, frames);
    pass = packets == n && frames == n && colour && moov_before_mdat(path);
done:
    avcodec_free_context(&dec);
    avformat_close_input(&ic);
    av_packet_free(&pkt);
    av_frame_free(&frame);
    return pass;
}

static bool test_mp4(void)
{
    const char *path = out_path("video/clip.mp4");
    struct sp_image img;
    int err;
    assert(sp_image_alloc(&img, 320, 240) == 0);
    struct sp_sink *s = open_sink(path, 320, 240, &err);
    bool pass = err == 0;
    for (int k = 0; pass && k < 30; k++) {
        draw(&img, k, false);
        pass = sp_sink_write(s, &img) == 0;
    }
    pass = pass && exists_part(path) && !exists(path);
    pass = pass && sp_sink_close(&s) == 0 && s == NULL;
    pass = pass && exists(path) && !exists_part(path) &&
           check_mp4(path, 320, 240, 30, 30);
    sp_image_free(&img);
    return pass;
}

static bool test_abort(void)
{
    const char *mp4 = out_path("abort.mp4"), *png = out_path("abort.png");
    struct sp_image img;
    int err1, err2;
    assert(sp_image_alloc(&img, 64, 64) == 0);
    draw(&img, 0, false);
    struct sp_sink *v = open_sink(mp4, 64, 64, &err1);
    struct sp_sink *p = open_sink(png, 64, 64, &err2);
    bool pass = err1 == 0 && err2 == 0;
    for (int k = 0; pass && k < 3; k++)
        pass = sp_sink_write(v, &img) == 0;
    pass = pass && sp_sink_write(p, &img) == 0;
    pass = pass && exists_part(mp4) && exists_part(png);
    sp_sink_abort(&v);
    sp_sink_abort(&p);
    sp_sink_abort(&p); /* safe on NULL */
    pass = pass && !v && !p && !exists(mp4) && !exists_part(mp4) &&
           !exists(png) && !exists_part(png);
    sp_image_free(&img);
    return pass;
}

static bool test_refusals(void)
{
    int err;
    struct sp_sink *s;
    bool pass = true;
    const char *bad[] = { "clip.avi", "noext", "frames/%s.png",
                          "frames/%d_%d.png", "f%d/x.png", "f%%/%d.png",
                          "frames/%123d.png", "frames/%-5d.png" };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        s = open_sink(out_path(bad[i]), 64, 64, &err);
        pass = pass && err == SP_E_INPUT && !s;
    }
    /* odd size: refused before any folder or file exists */
    s = open_sink(out_path("odd/clip.mp4"), 321, 240, &err);
    pass = pass && err == SP_E_INPUT && !s && !exists(out_path("odd"));
    return pass;
}

static bool test_misuse(void)
{
    const char *path = out_path("misuse.mp4");
    struct sp_image small;
    int err;
    assert(sp_image_alloc(&small, 32, 32) == 0);
    struct sp_sink *s = open_sink(path, 64, 64, &err);
    bool pass = err == 0 && sp_sink_write(s, &small) == SP_E_INPUT;
    /* nothing written: close fails and leaves nothing */
    pass = pass && sp_sink_close(&s) == SP_E_INPUT && !s && !exists(path) &&
           !exists_part(path);
    sp_image_free(&small);
    return pass;
}

static int rm_entry(const char *path, const struct stat *st, int flag,
                    struct FTW *ftw)
{
    (void)st, (void)flag, (void)ftw;
    return remove(path);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s SRC_DIR BUILD_DIR\n", argv[0]);
        return 2;
    }
    snprintf(out_dir, sizeof(out_dir), "%s/sink-out", argv[2]);
    nftw(out_dir, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
    if (mkdir(out_dir, 0777) != 0) {
        perror(out_dir);
        return 1;
    }
    bool x264 = avcodec_find_encoder_by_name("libx264") != NULL;

    static const struct {
        const char *name;
        bool (*fn)(void);
        bool needs_x264;
    } tests[] = {
        { "PNG write/read round trip keeps RGBA and text", test_png_round_trip, false },
        { "PNG I/O refuses a missing file, level 10, empty key", test_png_errors, false },
        { "PNG sequence of 5 frames with alpha, folders created, no .part, %% literal", test_png_sequence, false },
        { "single PNG: one write, second refused, renamed on close", test_png_single, false },
        { "PNG sequence numbered from first_frame; abort removes every frame", test_png_sequence_abort, false },
        { "MP4 30 frames 320x240 at 30 fps: h264 yuv420p, 1 s, faststart, colours", test_mp4, true },
        { "abort leaves neither target nor .part", test_abort, true },
        { "unknown kinds, bad patterns, odd MP4 size: SP_E_INPUT, no files", test_refusals, true },
        { "wrong image size refused; close with no frames leaves nothing", test_misuse, true },
    };
    int n = sizeof(tests) / sizeof(tests[0]), failed = 0;
    printf("1..%d\n", n);
    for (int i = 0; i < n; i++) {
        if (tests[i].needs_x264 && !x264) {
            printf("ok %d - %s # SKIP no libx264\n", i + 1, tests[i].name);
            continue;
        }
        fflush(stdout);
        bool pass = tests[i].fn();
        failed += !pass;
        printf("%sok %d - %s\n", pass ? "" : "not ", i + 1, tests[i].name);
        fflush(stdout);
    }
    return failed ? 1 : 0;
}
