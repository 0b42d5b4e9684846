/* springpend: animated GIF through libavfilter and libavformat. The
 * frames go through FFmpeg's own two-step palette recipe,
 *   split [a][b]; [a] palettegen [p]; [b][p] paletteuse
 * so the 256 colours are chosen for this content. palettegen sees every
 * frame before it emits the palette, so the graph holds the frames until
 * close: GIFs are for short, small clips (--quality low). GIF delays are
 * in 1/100 s and players slow down delays under 2/100 s, so above 50 fps
 * every second (third, ...) frame is kept. Written as a unique .part (outfile.h), renamed
 * on close. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libavcodec/avcodec.h>
#include <libavfilter/avfilter.h>
#include <libavfilter/buffersink.h>
#include <libavfilter/buffersrc.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>

#include "springpend/common.h"
#include "sink_impl.h"

#define GIF_MAX_FPS 50.0

struct gif {
    AVFilterGraph *graph;    /* owned; src and sink belong to it */
    AVFilterContext *src, *sink;
    AVFormatContext *oc;     /* owned; oc->pb opened by us */
    AVStream *st;            /* owned by oc */
    AVCodecContext *enc;     /* owned: the "gif" encoder, PAL8 */
    AVFrame *in, *out;       /* owned: reused */
    AVPacket *pkt;           /* owned: reused */
    struct sp_outfile file; /* the .part libav writes by name (file.url) */
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
    avfilter_graph_free(&g->graph);
    if (g->oc)
        avio_closep(&g->oc->pb);
    avformat_free_context(g->oc);
    g->oc = NULL;
    avcodec_free_context(&g->enc);
    av_frame_free(&g->in);
    av_frame_free(&g->out);
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

/* Builds buffer -> [frame thinning] -> palette recipe -> buffersink. */
static int gif_make_graph(struct sp_sink *s)
{
    struct gif *g = s->priv;
    const struct sp_sink_desc *d = &s->desc;
    AVFilterInOut *outputs = avfilter_inout_alloc();
    AVFilterInOut *inputs = avfilter_inout_alloc();
    AVRational rate = av_d2q(d->fps, 1001000);
    char args[256], chain[256];
    int ret;

    g->graph = avfilter_graph_alloc();
    if (!g->graph || !outputs || !inputs) {
        ret = AVERROR(ENOMEM);
        goto done;
    }
    snprintf(args, sizeof(args),
             "video_size=%dx%d:pix_fmt=%d:time_base=%d/%d:pixel_aspect=1/1",
             d->width, d->height, AV_PIX_FMT_RGBA, rate.den, rate.num);
    ret = avfilter_graph_create_filter(&g->src, avfilter_get_by_name("buffer"),
                                       "in", args, NULL, g->graph);
    if (ret < 0)
        goto done;
    ret = avfilter_graph_create_filter(&g->sink,
                                       avfilter_get_by_name("buffersink"),
                                       "out", NULL, NULL, g->graph);
    if (ret < 0)
        goto done;
    snprintf(chain, sizeof(chain),
             "select='not(mod(n\\,%d))',split[a][b];"
             "[a]palettegen=stats_mode=full[p];"
             "[b][p]paletteuse=dither=sierra2_4a", gif_step(d->fps));
    outputs->name = av_strdup("in");
    outputs->filter_ctx = g->src;
    inputs->name = av_strdup("out");
    inputs->filter_ctx = g->sink;
    ret = avfilter_graph_parse_ptr(g->graph, chain, &inputs, &outputs, NULL);
    if (ret >= 0)
        ret = avfilter_graph_config(g->graph, NULL);
done:
    avfilter_inout_free(&inputs);
    avfilter_inout_free(&outputs);
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
    ret = gif_make_graph(s);
    if (ret < 0) {
        err = gif_failed(s, "cannot set up the palette filters", ret, SP_E_CODEC);
        goto fail;
    }
    ret = avformat_alloc_output_context2(&g->oc, NULL, "gif", g->file.url);
    if (ret < 0) {
        err = gif_failed(s, "cannot set up the GIF muxer", ret, SP_E_CODEC);
        goto fail;
    }
    const AVCodec *codec = avcodec_find_encoder(AV_CODEC_ID_GIF);
    g->st = avformat_new_stream(g->oc, NULL);
    g->enc = avcodec_alloc_context3(codec);
    g->in = av_frame_alloc();
    g->out = av_frame_alloc();
    g->pkt = av_packet_alloc();
    if (!g->st || !g->enc || !g->in || !g->out || !g->pkt) {
        sp_log_error("%s: out of memory for the GIF encoder", s->path);
        err = SP_E_NOMEM;
        goto fail;
    }
    g->enc->width = d->width;
    g->enc->height = d->height;
    g->enc->pix_fmt = AV_PIX_FMT_PAL8;
    g->enc->time_base = av_buffersink_get_time_base(g->sink);
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

/* Encodes every frame the graph has ready (all of them once flushed). */
static int gif_drain(struct sp_sink *s)
{
    struct gif *g = s->priv;
    for (;;) {
        int ret = av_buffersink_get_frame(g->sink, g->out);
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

static int gif_write(struct sp_sink *s, const struct sp_image *img)
{
    struct gif *g = s->priv;
    g->in->format = AV_PIX_FMT_RGBA;
    g->in->width = img->width;
    g->in->height = img->height;
    int ret = av_frame_get_buffer(g->in, 0);
    if (ret < 0)
        return gif_failed(s, "cannot allocate a frame", ret, SP_E_NOMEM);
    for (int y = 0; y < img->height; y++)
        memcpy(g->in->data[0] + (size_t)y * g->in->linesize[0],
               img->pixels + (size_t)y * img->stride, 4 * (size_t)img->width);
    g->in->pts = s->frames;
    /* The graph takes the frame's reference and leaves g->in blank. */
    ret = av_buffersrc_add_frame(g->src, g->in);
    if (ret < 0)
        return gif_failed(s, "palette filters refused a frame", ret, SP_E_CODEC);
    return gif_drain(s);
}

static int gif_close(struct sp_sink *s)
{
    struct gif *g = s->priv;
    int ret = av_buffersrc_add_frame(g->src, NULL);
    if (ret < 0)
        return gif_failed(s, "cannot flush the palette filters", ret, SP_E_CODEC);
    int err = gif_drain(s);
    if (err)
        return err;
    ret = avcodec_send_frame(g->enc, NULL);
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
