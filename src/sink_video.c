/* springpend: MP4 video, H.264 (libx264) in yuv420p, through libavformat.
 * Follows FFmpeg's doc/examples/mux.c: send each frame, drain
 * receive_packet until EAGAIN, rescale timestamps, write interleaved; at
 * the end flush with NULL and write the trailer. The muxer writes
 * NAME.part (format named explicitly, since ".part" says nothing) and
 * +faststart moves the index (moov) before the data at the trailer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>

#include "springpend/common.h"
#include "sink_impl.h"

#define VIDEO_ENCODER "libx264"
#define VIDEO_CRF_DEFAULT 23
#define VIDEO_PRESET_DEFAULT "veryfast"

static const char *const x264_presets[] = {
    "ultrafast", "superfast", "veryfast", "faster", "fast",
    "medium", "slow", "slower", "veryslow", "placebo", NULL,
};

struct video {
    AVFormatContext *oc;    /* owned; oc->pb opened by us, closed by release */
    AVStream *st;           /* owned by oc */
    AVCodecContext *enc;    /* owned */
    AVFrame *frame;         /* owned: the one YUV420P picture, reused */
    AVPacket *pkt;          /* owned: reused for every packet */
    struct SwsContext *sws; /* owned: RGBA -> YUV420P, BT.709 limited */
    char *url;              /* owned: "file:PATH.part"; NULL once renamed */
};

static int video_check(const struct sp_sink_desc *d)
{
    if (d->width % 2 || d->height % 2) {
        sp_log_error("%s: H.264 video in yuv420p needs an even width and "
                     "height, got %dx%d (try %dx%d)", d->path, d->width,
                     d->height, d->width & ~1, d->height & ~1);
        return SP_E_INPUT;
    }
    if (!(d->fps > 0 && d->fps <= 1000)) {
        sp_log_error("%s: frame rate %g is not in (0, 1000] fps", d->path,
                     d->fps);
        return SP_E_INPUT;
    }
    if (d->crf < 0 || d->crf > 51) {
        sp_log_error("%s: CRF %d is not in 1..51 (0 = default %d)", d->path,
                     d->crf, VIDEO_CRF_DEFAULT);
        return SP_E_INPUT;
    }
    if (d->preset) {
        const char *const *p = x264_presets;
        while (*p && strcmp(*p, d->preset))
            p++;
        if (!*p) {
            sp_log_error("%s: unknown x264 preset \"%s\"; use ultrafast, "
                         "superfast, veryfast, faster, fast, medium, slow, "
                         "slower, veryslow or placebo", d->path, d->preset);
            return SP_E_INPUT;
        }
    }
    if (!avcodec_find_encoder_by_name(VIDEO_ENCODER)) {
        sp_log_error("%s: this FFmpeg (%s) has no %s encoder; install one "
                     "built with --enable-libx264, or write PNG frames "
                     "instead", d->path, av_version_info(), VIDEO_ENCODER);
        return SP_E_CODEC;
    }
    return 0;
}

/* Logs "PATH: DOING: libav's words" and returns code. */
static int av_failed(const struct sp_sink *s, const char *doing, int ret,
                     int code)
{
    sp_log_error("%s: %s: %s", s->path, doing, av_err2str(ret));
    return code;
}

/* Frees everything in v and removes the .part unless it was renamed. */
static void video_release(struct sp_sink *s)
{
    struct video *v = s->priv;
    if (v->oc)
        avio_closep(&v->oc->pb);
    avformat_free_context(v->oc);
    v->oc = NULL;
    v->st = NULL;
    avcodec_free_context(&v->enc);
    av_frame_free(&v->frame);
    av_packet_free(&v->pkt);
    sws_freeContext(v->sws);
    v->sws = NULL;
    if (v->url)
        sp_sink_discard(v->url + strlen("file:"));
    free(v->url);
    v->url = NULL;
}

/* Sends frame (NULL = flush) and writes every packet the encoder returns. */
static int video_encode(struct sp_sink *s, const AVFrame *frame)
{
    struct video *v = s->priv;
    int ret = avcodec_send_frame(v->enc, frame);
    if (ret < 0)
        return av_failed(s, "H.264 encoder refused a frame", ret, SP_E_CODEC);
    for (;;) {
        ret = avcodec_receive_packet(v->enc, v->pkt);
        if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF)
            return 0;
        if (ret < 0)
            return av_failed(s, "H.264 encoding failed", ret, SP_E_CODEC);
        av_packet_rescale_ts(v->pkt, v->enc->time_base, v->st->time_base);
        v->pkt->stream_index = v->st->index;
        /* Takes the packet's reference and leaves pkt blank for reuse. */
        ret = av_interleaved_write_frame(v->oc, v->pkt);
        if (ret < 0)
            return av_failed(s, "cannot write video", ret, SP_E_IO);
    }
}

static int video_open(struct sp_sink *s)
{
    struct video *v = s->priv;
    const struct sp_sink_desc *d = &s->desc;
    const AVCodec *codec = avcodec_find_encoder_by_name(VIDEO_ENCODER);
    AVDictionary *mux_opts = NULL; /* owned, freed at fail/return */
    AVRational rate = av_d2q(d->fps, 1001000);
    char crf[16];
    int err = SP_E_CODEC, ret;

    /* x264 and the muxer chat at INFO; keep errors unless the caller chose. */
    if (av_log_get_level() == AV_LOG_INFO)
        av_log_set_level(AV_LOG_ERROR);

    if (asprintf(&v->url, "file:%s.part", s->path) < 0) {
        v->url = NULL;
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    ret = avformat_alloc_output_context2(&v->oc, NULL, "mp4", v->url);
    if (ret < 0) {
        err = av_failed(s, "cannot set up the MP4 muxer", ret, SP_E_CODEC);
        goto fail;
    }
    v->st = avformat_new_stream(v->oc, NULL);
    v->enc = avcodec_alloc_context3(codec);
    v->frame = av_frame_alloc();
    v->pkt = av_packet_alloc();
    if (!v->st || !v->enc || !v->frame || !v->pkt) {
        sp_log_error("%s: out of memory for the video encoder", s->path);
        err = SP_E_NOMEM;
        goto fail;
    }

    v->enc->width = d->width;
    v->enc->height = d->height;
    v->enc->pix_fmt = AV_PIX_FMT_YUV420P;
    v->enc->framerate = rate;
    v->enc->time_base = av_inv_q(rate); /* pts = frame index */
    /* sRGB pixels go through the BT.709 matrix into limited range. */
    v->enc->color_range = AVCOL_RANGE_MPEG;
    v->enc->colorspace = AVCOL_SPC_BT709;
    v->enc->color_primaries = AVCOL_PRI_BT709;
    v->enc->color_trc = AVCOL_TRC_BT709;
    if (v->oc->oformat->flags & AVFMT_GLOBALHEADER)
        v->enc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    snprintf(crf, sizeof(crf), "%d", d->crf ? d->crf : VIDEO_CRF_DEFAULT);
    const char *preset = d->preset ? d->preset : VIDEO_PRESET_DEFAULT;
    if ((ret = av_opt_set(v->enc->priv_data, "preset", preset, 0)) < 0 ||
        (ret = av_opt_set(v->enc->priv_data, "crf", crf, 0)) < 0 ||
        (ret = avcodec_open2(v->enc, codec, NULL)) < 0) {
        err = av_failed(s, "cannot open the " VIDEO_ENCODER " encoder", ret,
                        SP_E_CODEC);
        goto fail;
    }
    ret = avcodec_parameters_from_context(v->st->codecpar, v->enc);
    if (ret < 0) {
        err = av_failed(s, "cannot copy the encoder's parameters", ret,
                        SP_E_CODEC);
        goto fail;
    }
    v->st->time_base = v->enc->time_base; /* a hint; the muxer may change it */
    v->st->avg_frame_rate = rate;

    v->frame->format = AV_PIX_FMT_YUV420P;
    v->frame->width = d->width;
    v->frame->height = d->height;
    ret = av_frame_get_buffer(v->frame, 0);
    if (ret < 0) {
        err = av_failed(s, "cannot allocate a video frame", ret, SP_E_NOMEM);
        goto fail;
    }
    v->sws = sws_getContext(d->width, d->height, AV_PIX_FMT_RGBA, d->width,
                            d->height, AV_PIX_FMT_YUV420P, SWS_BICUBIC, NULL,
                            NULL, NULL);
    if (!v->sws) {
        sp_log_error("%s: cannot set up RGBA to YUV420P conversion", s->path);
        goto fail;
    }
    const int *bt709 = sws_getCoefficients(SWS_CS_ITU709);
    sws_setColorspaceDetails(v->sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);

    /* The file is created last, so a refused setup leaves nothing. */
    ret = avio_open(&v->oc->pb, v->url, AVIO_FLAG_WRITE);
    if (ret < 0) {
        err = av_failed(s, "cannot create its .part file", ret, SP_E_IO);
        goto fail;
    }
    av_dict_set(&mux_opts, "movflags", "+faststart", 0);
    ret = avformat_write_header(v->oc, &mux_opts);
    if (ret < 0) {
        err = av_failed(s, "cannot write the MP4 header", ret, SP_E_IO);
        goto fail;
    }
    av_dict_free(&mux_opts);
    return 0;
fail:
    av_dict_free(&mux_opts);
    video_release(s);
    return err;
}

static int video_write(struct sp_sink *s, const struct sp_image *img)
{
    struct video *v = s->priv;
    const uint8_t *const src[1] = { img->pixels };
    const int src_stride[1] = { img->stride };

    /* The encoder has let go of the last frame, so this does not copy. */
    int ret = av_frame_make_writable(v->frame);
    if (ret < 0)
        return av_failed(s, "cannot reuse the video frame", ret, SP_E_CODEC);
    /* Alpha is dropped: video frames are taken as opaque. */
    ret = sws_scale(v->sws, src, src_stride, 0, img->height, v->frame->data,
                    v->frame->linesize);
    if (ret < 0)
        return av_failed(s, "cannot convert RGBA to YUV420P", ret, SP_E_CODEC);
    v->frame->pts = s->frames;
    return video_encode(s, v->frame);
}

static int video_close(struct sp_sink *s)
{
    struct video *v = s->priv;
    int err = video_encode(s, NULL);
    if (err)
        return err;
    /* With +faststart the trailer reopens the .part to move moov first. */
    int ret = av_write_trailer(v->oc);
    if (ret >= 0)
        ret = avio_closep(&v->oc->pb);
    if (ret < 0)
        return av_failed(s, "cannot finish the MP4 file", ret, SP_E_IO);
    err = sp_sink_commit(v->url + strlen("file:"), s->path);
    if (err)
        return err;
    free(v->url);
    v->url = NULL; /* renamed: nothing left to remove */
    video_release(s);
    return 0;
}

const struct sp_sink_backend sp_sink_backend_video = {
    .priv_size = sizeof(struct video),
    .check = video_check,
    .open = video_open,
    .write = video_write,
    .close = video_close,
    .abort = video_release,
};
