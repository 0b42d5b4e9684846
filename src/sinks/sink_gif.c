/* springpend: animated GIF through libavfilter and libavformat, with
 * FFmpeg's own two-step palette recipe in two passes, so that memory stays
 * flat however long the clip:
 *   pass 1 (each write): the kept frame goes to palettegen, which only
 *     counts colours, and, zlib-compressed, to a spool (an unlinked
 *     temporary file: nothing is left behind, whatever happens);
 *   pass 2 (close): the palette and the spooled frames go through
 *     paletteuse into the GIF encoder.
 * The 256 colours are chosen for this content, from every frame. GIF delays
 * are in 1/100 s and players slow down delays under 2/100 s, so above
 * 50 fps every second (third, ...) frame is kept. Written as a unique .part
 * (outfile.h), renamed on close. */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libavcodec/avcodec.h>
#include <libavfilter/avfilter.h>
#include <libavfilter/buffersink.h>
#include <libavfilter/buffersrc.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <zlib.h>

#include "springpend/common.h"
#include "sink_impl.h"

#define GIF_MAX_FPS 50.0

struct gif {
    AVFilterGraph *stats;       /* owned, pass 1: in -> palettegen -> out */
    AVFilterContext *stats_src, *stats_sink;
    AVFilterGraph *map;         /* owned, pass 2: [in][pal] paletteuse -> out */
    AVFilterContext *map_src, *pal_src, *map_sink;
    FILE *spool;                /* owned: the kept frames, each a uint32 length
                                   and its zlib data; unlinked temp file */
    uint8_t *raw, *z;           /* owned: one frame, packed, and compressed */
    uLongf z_cap;               /* bytes of z */
    z_stream zs;                /* deflate (pass 1), then inflate (pass 2),
                                   reset per frame: no allocation per frame */
    int zs_mode;                /* 0 none, 1 deflate, 2 inflate */
    long kept;                  /* frames in the spool */
    int step;                   /* every step-th frame is kept */
    AVRational tb;              /* s per kept frame: step / fps */
    AVFormatContext *oc;        /* owned; oc->pb opened by us */
    AVStream *st;               /* owned by oc */
    AVCodecContext *enc;        /* owned: the "gif" encoder, PAL8 */
    AVFrame *in, *out;          /* owned: reused */
    AVBufferPool *pool;         /* owned: in's pixel buffers, recycled (a
                                   fresh buffer per frame fragmented the heap:
                                   memory grew with length) */
    AVPacket *pkt;              /* owned: reused */
    struct sp_outfile file;     /* the .part libav writes by name (file.url) */
};

static int gif_failed(const struct sp_sink *s, const char *doing, int ret,
                      int code)
{
    sp_log_error("%s: %s: %s", s->path, doing, av_err2str(ret));
    return code;
}

static int gif_check(const struct sp_sink_desc *d)
{
    if (!(d->fps > 0 && d->fps <= 1000)) {
        sp_log_error("%s: frame rate %g is not in (0, 1000] fps", d->path,
                     d->fps);
        return SP_E_INPUT;
    }
    if (d->alpha) {
        sp_log_error("%s: springpend's GIFs have no transparency; use .webm, "
                     ".png or raw for a transparent background", d->path);
        return SP_E_INPUT;
    }
    if (d->width > 65535 || d->height > 65535) {
        sp_log_error("%s: GIF sides are at most 65535 px", d->path);
        return SP_E_INPUT;
    }
    if (!avcodec_find_encoder(AV_CODEC_ID_GIF) ||
        !avfilter_get_by_name("palettegen")) {
        sp_log_error("%s: this FFmpeg (%s) lacks the GIF encoder or the "
                     "palettegen filter", d->path, av_version_info());
        return SP_E_CODEC;
    }
    return 0;
}

static void gif_release(struct sp_sink *s)
{
    struct gif *g = s->priv;
    avfilter_graph_free(&g->stats);
    avfilter_graph_free(&g->map);
    if (g->zs_mode == 1)
        deflateEnd(&g->zs);
    else if (g->zs_mode == 2)
        inflateEnd(&g->zs);
    g->zs_mode = 0;
    if (g->spool)
        fclose(g->spool);
    g->spool = NULL;
    free(g->raw);
    free(g->z);
    g->raw = g->z = NULL;
    if (g->oc)
        avio_closep(&g->oc->pb);
    avformat_free_context(g->oc);
    g->oc = NULL;
    avcodec_free_context(&g->enc);
    av_frame_free(&g->in);
    av_frame_free(&g->out);
    av_buffer_pool_uninit(&g->pool);
    av_packet_free(&g->pkt);
    sp_outfile_discard(&g->file);
}

/* The kept frame rate: fps divided by the smallest whole step that brings
 * it to at most GIF_MAX_FPS. */
static int gif_step(double fps)
{
    int step = 1;
    while (fps / step > GIF_MAX_FPS)
        step++;
    return step;
}

/* A buffer source named name in graph for w x h frames of pix. */
static int make_src(AVFilterGraph *graph, AVFilterContext **src, const char *name,
                    int w, int h, enum AVPixelFormat pix, AVRational tb)
{
    char args[256];
    snprintf(args, sizeof(args),
             "video_size=%dx%d:pix_fmt=%d:time_base=%d/%d:pixel_aspect=1/1", w, h,
             pix, tb.num, tb.den);
    return avfilter_graph_create_filter(src, avfilter_get_by_name("buffer"), name, args,
                                        NULL, graph);
}

/* Links the sources srcs (named like themselves in chain) and the sink
 * "out" through chain, and configures the graph. */
static int link_graph(AVFilterGraph *graph, const char *chain, AVFilterContext **srcs,
                      int n_srcs, AVFilterContext **sink)
{
    AVFilterInOut *outputs = NULL, *inputs = avfilter_inout_alloc();
    int ret = avfilter_graph_create_filter(sink, avfilter_get_by_name("buffersink"), "out",
                                           NULL, NULL, graph);
    for (int i = n_srcs - 1; i >= 0 && ret >= 0; i--) {
        AVFilterInOut *o = avfilter_inout_alloc();
        if (!o) {
            ret = AVERROR(ENOMEM);
            break;
        }
        o->name = av_strdup(srcs[i]->name);
        o->filter_ctx = srcs[i];
        o->next = outputs;
        outputs = o;
    }
    if (ret >= 0 && !inputs)
        ret = AVERROR(ENOMEM);
    if (ret >= 0) {
        inputs->name = av_strdup("out");
        inputs->filter_ctx = *sink;
        ret = avfilter_graph_parse_ptr(graph, chain, &inputs, &outputs, NULL);
    }
    if (ret >= 0)
        ret = avfilter_graph_config(graph, NULL);
    avfilter_inout_free(&inputs);
    avfilter_inout_free(&outputs);
    return ret;
}

/* Builds both passes' graphs. palettegen's palette is 16x16 RGB32. */
static int gif_make_graphs(struct sp_sink *s)
{
    struct gif *g = s->priv;
    const struct sp_sink_desc *d = &s->desc;
    g->stats = avfilter_graph_alloc();
    g->map = avfilter_graph_alloc();
    if (!g->stats || !g->map)
        return AVERROR(ENOMEM);
    int ret = make_src(g->stats, &g->stats_src, "in", d->width, d->height,
                       AV_PIX_FMT_RGBA, g->tb);
    if (ret >= 0)
        ret = link_graph(g->stats, "[in]palettegen=stats_mode=full[out]", &g->stats_src, 1,
                         &g->stats_sink);
    if (ret >= 0)
        ret = make_src(g->map, &g->map_src, "in", d->width, d->height, AV_PIX_FMT_RGBA, g->tb);
    if (ret >= 0)
        ret = make_src(g->map, &g->pal_src, "pal", 16, 16, AV_PIX_FMT_RGB32, g->tb);
    if (ret >= 0)
        ret = link_graph(g->map, "[in][pal]paletteuse=dither=sierra2_4a[out]",
                         (AVFilterContext *[]){g->map_src, g->pal_src}, 2, &g->map_sink);
    return ret;
}

static int gif_open(struct sp_sink *s)
{
    struct gif *g = s->priv;
    const struct sp_sink_desc *d = &s->desc;
    int err = SP_E_CODEC, ret;

    if (av_log_get_level() == AV_LOG_INFO)
        av_log_set_level(AV_LOG_ERROR);
    if ((err = sp_outfile_open(&g->file, s->path, 0)) != 0)
        return err;
    err = SP_E_CODEC; /* what a failure below is, unless it says */
    g->step = gif_step(d->fps);
    g->tb = av_mul_q(av_inv_q(av_d2q(d->fps, 1001000)), (AVRational){g->step, 1});
    ret = gif_make_graphs(s);
    if (ret < 0) {
        err = gif_failed(s, "cannot set up the palette filters", ret, SP_E_CODEC);
        goto fail;
    }
    g->z_cap = compressBound(4 * (uLong)d->width * (uLong)d->height);
    g->raw = malloc(4 * (size_t)d->width * (size_t)d->height);
    g->z = malloc(g->z_cap);
    if (!g->raw || !g->z) {
        sp_log_error("%s: out of memory for the GIF's frames", s->path);
        err = SP_E_NOMEM;
        goto fail;
    }
    if (deflateInit(&g->zs, 1) != Z_OK) {
        sp_log_error("%s: out of memory for the GIF's frames", s->path);
        err = SP_E_NOMEM;
        goto fail;
    }
    g->zs_mode = 1;
    if (!(g->spool = tmpfile())) {
        sp_log_error("%s: cannot create a temporary file for the GIF's frames: %s",
                     s->path, strerror(errno));
        err = SP_E_IO;
        goto fail;
    }
    ret = avformat_alloc_output_context2(&g->oc, NULL, "gif", g->file.url);
    if (ret < 0) {
        err = gif_failed(s, "cannot set up the GIF muxer", ret, SP_E_CODEC);
        goto fail;
    }
    g->oc->flags |= AVFMT_FLAG_BITEXACT;
    const AVCodec *codec = avcodec_find_encoder(AV_CODEC_ID_GIF);
    g->st = avformat_new_stream(g->oc, NULL);
    g->enc = avcodec_alloc_context3(codec);
    g->in = av_frame_alloc();
    g->out = av_frame_alloc();
    g->pkt = av_packet_alloc();
    g->pool = av_buffer_pool_init(4 * (size_t)d->width * (size_t)d->height, NULL);
    if (!g->st || !g->enc || !g->in || !g->out || !g->pkt || !g->pool) {
        sp_log_error("%s: out of memory for the GIF encoder", s->path);
        err = SP_E_NOMEM;
        goto fail;
    }
    g->enc->width = d->width;
    g->enc->height = d->height;
    g->enc->pix_fmt = AV_PIX_FMT_PAL8;
    g->enc->time_base = av_buffersink_get_time_base(g->map_sink);
    ret = avcodec_open2(g->enc, codec, NULL);
    if (ret >= 0)
        ret = avcodec_parameters_from_context(g->st->codecpar, g->enc);
    if (ret < 0) {
        err = gif_failed(s, "cannot open the GIF encoder", ret, SP_E_CODEC);
        goto fail;
    }
    g->st->time_base = g->enc->time_base;
    ret = avio_open(&g->oc->pb, g->file.url, AVIO_FLAG_WRITE);
    if (ret < 0) {
        err = gif_failed(s, "cannot open its .part file", ret, SP_E_IO);
        goto fail;
    }
    ret = avformat_write_header(g->oc, NULL);
    if (ret < 0) {
        err = gif_failed(s, "cannot write the GIF header", ret, SP_E_IO);
        goto fail;
    }
    return 0;
fail:
    gif_release(s);
    return err;
}

/* Encodes every frame pass 2 has ready (all of them once flushed). */
static int gif_drain(struct sp_sink *s)
{
    struct gif *g = s->priv;
    for (;;) {
        int ret = av_buffersink_get_frame(g->map_sink, g->out);
        if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF)
            break;
        if (ret < 0)
            return gif_failed(s, "palette filters failed", ret, SP_E_CODEC);
        ret = avcodec_send_frame(g->enc, g->out);
        av_frame_unref(g->out);
        if (ret < 0)
            return gif_failed(s, "the GIF encoder refused a frame", ret, SP_E_CODEC);
        while ((ret = avcodec_receive_packet(g->enc, g->pkt)) >= 0) {
            av_packet_rescale_ts(g->pkt, g->enc->time_base, g->st->time_base);
            g->pkt->stream_index = g->st->index;
            ret = av_interleaved_write_frame(g->oc, g->pkt);
            if (ret < 0)
                return gif_failed(s, "cannot write the GIF", ret, SP_E_IO);
        }
        if (ret != AVERROR(EAGAIN))
            return gif_failed(s, "GIF encoding failed", ret, SP_E_CODEC);
    }
    return 0;
}

/* Hands g->raw (packed RGBA) to src as frame number pts. */
static int send_raw(struct sp_sink *s, AVFilterContext *src, long pts)
{
    struct gif *g = s->priv;
    const int w = s->desc.width, h = s->desc.height;
    /* A buffer from the pool: paletteuse keeps the last frame, so the one
     * before comes back to the pool instead of being freed. */
    g->in->buf[0] = av_buffer_pool_get(g->pool);
    if (!g->in->buf[0])
        return gif_failed(s, "cannot allocate a frame", AVERROR(ENOMEM), SP_E_NOMEM);
    g->in->data[0] = g->in->buf[0]->data;
    g->in->linesize[0] = 4 * w;
    g->in->format = AV_PIX_FMT_RGBA;
    g->in->width = w;
    g->in->height = h;
    memcpy(g->in->data[0], g->raw, 4 * (size_t)w * (size_t)h);
    g->in->pts = pts;
    /* The graph takes the frame's reference and leaves g->in blank; PUSH
     * runs the filters now, so frames do not queue at the source. */
    int ret = av_buffersrc_add_frame_flags(src, g->in, AV_BUFFERSRC_FLAG_PUSH);
    return ret < 0 ? gif_failed(s, "palette filters refused a frame", ret, SP_E_CODEC) : 0;
}

static int spool_failed(struct sp_sink *s, const char *doing)
{
    sp_log_error("%s: cannot %s the GIF's temporary frames: %s", s->path, doing,
                 errno ? strerror(errno) : "short file");
    return SP_E_IO;
}

/* Pass 1: counts the kept frame's colours and spools it. */
static int gif_write(struct sp_sink *s, const struct sp_image *img)
{
    struct gif *g = s->priv;
    if (s->frames % g->step)
        return 0;
    const size_t row = 4 * (size_t)img->width;
    for (int y = 0; y < img->height; y++)
        memcpy(g->raw + y * row, img->pixels + (size_t)y * img->stride, row);
    g->zs.next_in = g->raw;
    g->zs.avail_in = (uInt)(row * img->height);
    g->zs.next_out = g->z;
    g->zs.avail_out = (uInt)g->z_cap;
    if (deflate(&g->zs, Z_FINISH) != Z_STREAM_END || deflateReset(&g->zs) != Z_OK) {
        sp_log_error("%s: cannot compress a frame", s->path);
        return SP_E_NOMEM;
    }
    uLongf n = g->z_cap - g->zs.avail_out;
    uint32_t len = (uint32_t)n;
    errno = 0;
    if (fwrite(&len, sizeof(len), 1, g->spool) != 1 || fwrite(g->z, 1, n, g->spool) != n)
        return spool_failed(s, "write");
    return send_raw(s, g->stats_src, g->kept++);
}

/* Pass 2: the palette, then every spooled frame through paletteuse. */
static int gif_map(struct sp_sink *s)
{
    struct gif *g = s->priv;
    int ret = av_buffersrc_add_frame(g->stats_src, NULL);
    if (ret >= 0)
        ret = av_buffersink_get_frame(g->stats_sink, g->out);
    if (ret >= 0) {
        g->out->pts = 0;
        ret = av_buffersrc_add_frame(g->pal_src, g->out);
    }
    if (ret >= 0)
        ret = av_buffersrc_add_frame(g->pal_src, NULL);
    if (ret < 0)
        return gif_failed(s, "cannot make the palette", ret, SP_E_CODEC);
    errno = 0;
    if (fflush(g->spool) != 0 || fseek(g->spool, 0, SEEK_SET) != 0)
        return spool_failed(s, "read");
    const uLongf size = 4 * (uLongf)s->desc.width * (uLongf)s->desc.height;
    deflateEnd(&g->zs);
    g->zs = (z_stream){0};
    g->zs_mode = 0;
    if (inflateInit(&g->zs) != Z_OK) {
        sp_log_error("%s: out of memory for the GIF's frames", s->path);
        return SP_E_NOMEM;
    }
    g->zs_mode = 2;
    for (long k = 0; k < g->kept; k++) {
        uint32_t len;
        errno = 0;
        if (fread(&len, sizeof(len), 1, g->spool) != 1 || len > g->z_cap ||
            fread(g->z, 1, len, g->spool) != len)
            return spool_failed(s, "read");
        g->zs.next_in = g->z;
        g->zs.avail_in = len;
        g->zs.next_out = g->raw;
        g->zs.avail_out = (uInt)size;
        if (inflate(&g->zs, Z_FINISH) != Z_STREAM_END || g->zs.avail_out != 0 ||
            inflateReset(&g->zs) != Z_OK) {
            sp_log_error("%s: the GIF's temporary frames are damaged", s->path);
            return SP_E_IO;
        }
        int err = send_raw(s, g->map_src, k);
        if (!err)
            err = gif_drain(s);
        if (err)
            return err;
    }
    ret = av_buffersrc_add_frame(g->map_src, NULL);
    if (ret < 0)
        return gif_failed(s, "cannot flush the palette filters", ret, SP_E_CODEC);
    return gif_drain(s);
}

static int gif_close(struct sp_sink *s)
{
    struct gif *g = s->priv;
    int err = gif_map(s);
    if (err)
        return err;
    int ret = avcodec_send_frame(g->enc, NULL);
    while (ret >= 0 && (ret = avcodec_receive_packet(g->enc, g->pkt)) >= 0) {
        av_packet_rescale_ts(g->pkt, g->enc->time_base, g->st->time_base);
        g->pkt->stream_index = g->st->index;
        ret = av_interleaved_write_frame(g->oc, g->pkt);
    }
    if (ret != AVERROR_EOF)
        return gif_failed(s, "cannot finish the GIF", ret, SP_E_IO);
    ret = av_write_trailer(g->oc);
    if (ret >= 0)
        ret = avio_closep(&g->oc->pb);
    if (ret < 0)
        return gif_failed(s, "cannot finish the GIF", ret, SP_E_IO);
    err = sp_outfile_commit(&g->file); /* then nothing to remove */
    if (err)
        return err;
    gif_release(s);
    return 0;
}

const struct sp_sink_backend sp_sink_backend_gif = {
    .priv_size = sizeof(struct gif),
    .check = gif_check,
    .open = gif_open,
    .write = gif_write,
    .close = gif_close,
    .abort = gif_release,
};
