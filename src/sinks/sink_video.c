/* springpend: video through libavformat: MP4 with H.264 (libx264) in
 * yuv420p, and WebM with VP9 (libvpx) in yuv420p or, with desc.alpha,
 * yuva420p. Follows FFmpeg's doc/examples/mux.c: send each frame, drain
 * receive_packet until EAGAIN, rescale timestamps, write interleaved; at
 * the end flush with NULL and write the trailer. The muxer writes a unique
 * .part (outfile.h; format named explicitly, since ".part" says nothing)
 * and +faststart moves the index (moov) before the data at the trailer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>

#include "springpend/common.h"
#include "springpend/scene.h"
#include "sink_impl.h"

/* On springpend's content (flat background, thin lines) superfast looks as
 * clean as veryfast (SSIM 0.9917 vs 0.9915 at CRF 23, 1080p) for 18% less
 * encoder CPU; the files are larger (about 0.7 Mbit/s at 1080p60), still
 * small. */
#define VIDEO_PRESET_DEFAULT SP_SINK_PRESET_DEFAULT

/* The scene's presets (scene.h) and x264's slowest, fastest first. */
#define X264_PRESET(name) name,
static const char *const x264_presets[] = {SP_VIDEO_PRESETS(X264_PRESET) "placebo", NULL};

/* What differs between the containers. */
struct video_codec {
    const char *encoder;  /* libavcodec encoder name */
    const char *muxer;    /* libavformat muxer name */
    const char *what;     /* for messages: "H.264", "VP9" */
    int crf_default, crf_max;
    int has_alpha;        /* yuva420p possible */
};

static const struct video_codec codec_h264 = {
    "libx264", "mp4", "H.264", SP_SINK_CRF_H264, 51, 0,
};
static const struct video_codec codec_vp9 = {
    "libvpx-vp9", "webm", "VP9", SP_SINK_CRF_VP9, 63, 1,
};

struct video {
    const struct video_codec *codec; /* set by the backend's open */
    AVFormatContext *oc;    /* owned; oc->pb opened by us, closed by release */
    AVStream *st;           /* owned by oc */
    AVCodecContext *enc;    /* owned */
    AVFrame *frame;         /* owned: the one YUV(A)420P picture RGBA images
                               are converted into, reused; allocated at the
                               first RGBA image */
    AVFrame *planes;        /* owned: wraps a YUV420 image's planes, which the
                               renderer converted (no copy, no conversion) */
    int released;           /* the encoder let go of the planes' buffer */
    AVPacket *pkt;          /* owned: reused for every packet */
    struct SwsContext *sws; /* owned: RGBA -> YUV(A)420P, BT.709 limited;
                               made at the first RGBA image */
    struct sp_outfile file; /* the .part libav writes by name (file.url) */
    const struct sp_png_text *text; /* the caller's provenance (sp_sink_desc):
                                       its texts may grow until the close */
    int n_text;
};

static int video_check(const struct sp_sink_desc *d,
                       const struct video_codec *c)
{
    if (d->width % 2 || d->height % 2) {
        sp_log_error("%s: %s video in yuv420p needs an even width and "
                     "height, got %dx%d (try %dx%d)", d->path, c->what, d->width,
                     d->height, d->width & ~1, d->height & ~1);
        return SP_E_INPUT;
    }
    if (!(d->fps > 0 && d->fps <= 1000)) {
        sp_log_error("%s: frame rate %g is not in (0, 1000] fps", d->path,
                     d->fps);
        return SP_E_INPUT;
    }
    if (d->crf < 0 || d->crf > c->crf_max) {
        sp_log_error("%s: CRF %d is not in 1..%d for %s (0 = default %d)",
                     d->path, d->crf, c->crf_max, c->what, c->crf_default);
        return SP_E_INPUT;
    }
    if (d->alpha && !c->has_alpha) {
        sp_log_error("%s: %s video has no alpha; use .webm (VP9) for a "
                     "transparent background", d->path, c->what);
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
    if (!avcodec_find_encoder_by_name(c->encoder)) {
        sp_log_error("%s: this FFmpeg (%s) has no %s encoder; install one "
                     "built with it, or write PNG frames instead", d->path,
                     av_version_info(), c->encoder);
        return SP_E_CODEC;
    }
    return 0;
}

static int mp4_check(const struct sp_sink_desc *d)
{
    return video_check(d, &codec_h264);
}

static int webm_check(const struct sp_sink_desc *d)
{
    return video_check(d, &codec_vp9);
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
    av_frame_free(&v->planes);
    av_packet_free(&v->pkt);
    sws_freeContext(v->sws);
    v->sws = NULL;
    sp_outfile_discard(&v->file);
}

/* A WebM's packet times (pkt in frame numbers, enc) in the muxer's time
 * base (mux: Matroska's 1 ms), for a video whose first frame is number
 * first of the whole (--frames, --shard): frame first + j at
 * T(first + j) - T(first), T(k) = k / fps rounded once to the time base, and
 * lasting T(first + j + 1) - T(first + j). A piece then lasts
 * T(last + 1) - T(first), and ffmpeg's concat demuxer, which starts each
 * piece where the ones before it end, puts every frame at T(k), as the
 * one-piece render does (rounding each piece's times on its own put frames
 * 1 ms off: attack17 #7). MP4 holds frame times exactly (mp4_options). */
static void piece_times(AVPacket *pkt, AVRational enc, AVRational mux, long first)
{
    const int64_t start = av_rescale_q(first, enc, mux);
    const int64_t k = pkt->pts;
    if (pkt->pts != AV_NOPTS_VALUE)
        pkt->pts = av_rescale_q(first + pkt->pts, enc, mux) - start;
    if (pkt->dts != AV_NOPTS_VALUE)
        pkt->dts = av_rescale_q(first + pkt->dts, enc, mux) - start;
    if (k != AV_NOPTS_VALUE)
        pkt->duration = av_rescale_q(first + k + 1, enc, mux) - av_rescale_q(first + k, enc, mux);
    else
        pkt->duration = av_rescale_q(pkt->duration, enc, mux);
}

/* Sends frame (NULL = flush) and writes every packet the encoder returns. */
static int video_encode(struct sp_sink *s, const AVFrame *frame)
{
    struct video *v = s->priv;
    int ret = avcodec_send_frame(v->enc, frame);
    if (ret < 0)
        return av_failed(s, "the encoder refused a frame", ret, SP_E_CODEC);
    for (;;) {
        ret = avcodec_receive_packet(v->enc, v->pkt);
        if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF)
            return 0;
        if (ret < 0)
            return av_failed(s, "encoding failed", ret, SP_E_CODEC);
        if (strcmp(v->codec->muxer, "mp4"))
            piece_times(v->pkt, v->enc->time_base, v->st->time_base, s->desc.first_frame);
        else
            av_packet_rescale_ts(v->pkt, v->enc->time_base, v->st->time_base);
        v->pkt->stream_index = v->st->index;
        /* Takes the packet's reference and leaves pkt blank for reuse. */
        ret = av_interleaved_write_frame(v->oc, v->pkt);
        if (ret < 0)
            return av_failed(s, "cannot write video", ret, SP_E_IO);
    }
}

/* Encoder threads, whatever the core count (see video_open). x264 takes
 * X264_THREADS and X264_SLICED: 1 cuts each frame into that many slices
 * encoded at once (no frames in flight), 0 encodes that many frames at
 * once. Four slices, measured against 1, 2, 3, 4 and 8 frame threads and
 * 2 and 3 slices (doc/performance.md): the least CPU and wall time of
 * those settings, all of which give the same bytes on any machine, and
 * 275 MiB at 1080p where 8 frame threads (each holding frames) took 450;
 * the file is about 5% larger at the same CRF. VP9 (libvpx, row-mt) keeps
 * VIDEO_THREADS. (Overridable when building, for measuring.) */
#define VIDEO_THREADS 8
#ifndef X264_THREADS
#define X264_THREADS 4
#endif
#ifndef X264_SLICED
#define X264_SLICED 1
#endif

/* The encoder's speed from an x264 preset name. VP9 (libvpx) has no
 * presets: "good" quality with cpu-used from 8 (ultrafast) down to 0, and
 * row-based threading so both cores work. */
static int set_speed(AVCodecContext *enc, const struct video_codec *vc,
                     const char *preset)
{
    if (!strcmp(vc->encoder, "libx264"))
        return av_opt_set(enc->priv_data, "preset", preset, 0);
    int i = 0;
    while (x264_presets[i] && strcmp(x264_presets[i], preset))
        i++;
    int cpu_used = i >= 8 ? 0 : 8 - i; /* superfast -> 7 */
    enc->bit_rate = 0;                 /* constant quality: crf alone */
    int ret = av_opt_set(enc->priv_data, "deadline", "good", 0);
    if (ret >= 0)
        ret = av_opt_set_int(enc->priv_data, "cpu-used", cpu_used, 0);
    if (ret >= 0)
        ret = av_opt_set_int(enc->priv_data, "row-mt", 1, 0);
    return ret;
}

/* Sets up v->enc (size, threads, frame rate, BT.709 limited range, speed
 * and quality) and opens it. 0, or SP_E_CODEC (said). */
static int encoder_open(struct sp_sink *s, const AVCodec *codec, AVRational rate)
{
    struct video *v = s->priv;
    const struct sp_sink_desc *d = &s->desc;
    const struct video_codec *vc = v->codec;
    char crf[16];
    int ret;
    v->enc->width = d->width;
    v->enc->height = d->height;
    v->enc->pix_fmt = d->alpha ? AV_PIX_FMT_YUVA420P : AV_PIX_FMT_YUV420P;
    /* A fixed thread count, not one per core: x264's output depends on its
     * threads, so the same scene gives the same bytes on any machine. */
    v->enc->thread_count = VIDEO_THREADS;
    if (!strcmp(vc->encoder, "libx264")) {
        v->enc->thread_count = X264_THREADS;
        v->enc->thread_type = X264_SLICED ? FF_THREAD_SLICE : FF_THREAD_FRAME;
    }
    v->enc->framerate = rate;
    v->enc->time_base = av_inv_q(rate); /* pts = frame index */
    /* sRGB pixels go through the BT.709 matrix into limited range. */
    v->enc->color_range = AVCOL_RANGE_MPEG;
    v->enc->colorspace = AVCOL_SPC_BT709;
    v->enc->color_primaries = AVCOL_PRI_BT709;
    v->enc->color_trc = AVCOL_TRC_BT709;
    /* As swscale's output and the renderer's YUV pass site it (yuv.frag). */
    v->enc->chroma_sample_location = AVCHROMA_LOC_LEFT;
    if (v->oc->oformat->flags & AVFMT_GLOBALHEADER)
        v->enc->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    snprintf(crf, sizeof(crf), "%d", d->crf ? d->crf : vc->crf_default);
    ret = set_speed(v->enc, vc, d->preset ? d->preset : VIDEO_PRESET_DEFAULT);
    if (ret >= 0)
        ret = av_opt_set(v->enc->priv_data, "crf", crf, 0);
    if (ret >= 0)
        ret = avcodec_open2(v->enc, codec, NULL);
    if (ret < 0) {
        sp_log_error("%s: cannot open the %s encoder: %s", s->path,
                     vc->encoder, av_err2str(ret));
        return SP_E_CODEC;
    }
    return 0;
}

/* The MP4 muxer's options into *opts: faststart, the scene's tags when
 * there are (tags), and a movie timescale that holds frame times at rate
 * exactly. */
static void mp4_options(AVDictionary **opts, AVRational rate, int tags)
{
    /* The movie header keeps the file's duration in movie_timescale
     * units, 1000 by default: 20 frames at 60 fps became 0.334 s, and
     * ffmpeg's concat demuxer starts the next shard's frames there, off
     * k / fps. The track's own timescale (the mov muxer doubles the
     * time base's denominator up to 10000 at least) holds it exactly. */
    char timescale[16];
    int ts = rate.num;
    while (ts < 10000)
        ts *= 2;
    snprintf(timescale, sizeof(timescale), "%d", ts);
    av_dict_set(opts, "movflags", tags ? "+faststart+use_metadata_tags" : "+faststart", 0);
    av_dict_set(opts, "movie_timescale", timescale, 0);
}

static int video_open(struct sp_sink *s)
{
    struct video *v = s->priv;
    const struct sp_sink_desc *d = &s->desc;
    const struct video_codec *vc = v->codec;
    const AVCodec *codec = avcodec_find_encoder_by_name(vc->encoder);
    AVDictionary *mux_opts = NULL; /* owned, freed at fail/return */
    AVRational rate = av_d2q(d->fps, 1001000);
    int err = SP_E_CODEC, ret;

    /* x264 and the muxer chat at INFO; keep errors unless the caller chose. */
    if (av_log_get_level() == AV_LOG_INFO)
        av_log_set_level(AV_LOG_ERROR);

    if ((err = sp_outfile_open(&v->file, s->path, 0)) != 0)
        return err;
    err = SP_E_CODEC; /* what a failure below is, unless it says */
    ret = avformat_alloc_output_context2(&v->oc, NULL, vc->muxer, v->file.url);
    if (ret < 0) {
        err = av_failed(s, "cannot set up the muxer", ret, SP_E_CODEC);
        goto fail;
    }
    /* No random Matroska UIDs, no version strings: the same bytes each run. */
    v->oc->flags |= AVFMT_FLAG_BITEXACT;
    v->st = avformat_new_stream(v->oc, NULL);
    v->enc = avcodec_alloc_context3(codec);
    v->frame = av_frame_alloc();
    v->planes = av_frame_alloc();
    v->pkt = av_packet_alloc();
    if (!v->st || !v->enc || !v->frame || !v->planes || !v->pkt) {
        sp_log_error("%s: out of memory for the video encoder", s->path);
        err = SP_E_NOMEM;
        goto fail;
    }
    if ((err = encoder_open(s, codec, rate)) != 0)
        goto fail;
    ret = avcodec_parameters_from_context(v->st->codecpar, v->enc);
    if (ret < 0) {
        err = av_failed(s, "cannot copy the encoder's parameters", ret,
                        SP_E_CODEC);
        goto fail;
    }
    v->st->time_base = v->enc->time_base; /* a hint; the muxer may change it */
    v->st->avg_frame_rate = rate;

    /* A refused setup removes the .part (video_release). */
    ret = avio_open(&v->oc->pb, v->file.url, AVIO_FLAG_WRITE);
    if (ret < 0) {
        err = av_failed(s, "cannot open its .part file", ret, SP_E_IO);
        goto fail;
    }
    /* The provenance chunks a PNG carries, as container tags (MP4 keeps
     * keys of its own only with use_metadata_tags): compare names the scene
     * keys that changed between two videos. */
    for (int i = 0; i < d->n_text; i++)
        if (strcmp(d->text[i].key, "springpend.time")) /* a frame's, not the video's */
            av_dict_set(&v->oc->metadata, d->text[i].key, d->text[i].text, 0);
    v->text = d->text;
    v->n_text = d->n_text;
    if (!strcmp(vc->muxer, "mp4"))
        mp4_options(&mux_opts, rate, d->n_text != 0);
    ret = avformat_write_header(v->oc, &mux_opts);
    if (ret < 0) {
        err = av_failed(s, "cannot write the header", ret, SP_E_IO);
        goto fail;
    }
    av_dict_free(&mux_opts);
    return 0;
fail:
    av_dict_free(&mux_opts);
    video_release(s);
    return err;
}

/* The RGBA path's frame and converter, at the first RGBA image. */
static int rgba_setup(struct sp_sink *s)
{
    struct video *v = s->priv;
    const struct sp_sink_desc *d = &s->desc;
    enum AVPixelFormat pix = v->enc->pix_fmt;
    v->frame->format = pix;
    v->frame->width = d->width;
    v->frame->height = d->height;
    int ret = av_frame_get_buffer(v->frame, 0);
    if (ret < 0)
        return av_failed(s, "cannot allocate a video frame", ret, SP_E_NOMEM);
    v->sws = sws_getContext(d->width, d->height, AV_PIX_FMT_RGBA, d->width,
                            d->height, pix, SWS_BICUBIC, NULL,
                            NULL, NULL);
    if (!v->sws) {
        sp_log_error("%s: cannot set up RGBA to YUV conversion", s->path);
        return SP_E_CODEC;
    }
    const int *bt709 = sws_getCoefficients(SWS_CS_ITU709);
    sws_setColorspaceDetails(v->sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16);
    return 0;
}

/* The planes' buffer is the caller's image: nothing to free. */
static void planes_released(void *opaque, uint8_t *data)
{
    (void)data;
    *(int *)opaque = 1;
}

/* A YUV420 image (already BT.709 limited range, chroma sited left) handed
 * to the encoder as it is. libavcodec's encoders that take one frame at a
 * time (libx264, libvpx) copy it into their own pictures before
 * avcodec_send_frame returns (the packets were drained after the last
 * frame, so the frame is encoded at once), and let go of it: the image
 * is the caller's again. A reference kept beyond that would read an image
 * the caller reuses, so it is an error. */
static int yuv_write(struct sp_sink *s, const struct sp_image *img)
{
    struct video *v = s->priv;
    AVFrame *f = v->planes;
    f->format = AV_PIX_FMT_YUV420P;
    f->width = img->width;
    f->height = img->height;
    f->color_range = AVCOL_RANGE_MPEG;
    f->colorspace = AVCOL_SPC_BT709;
    f->chroma_location = AVCHROMA_LOC_LEFT;
    sp_image_planes(img, f->data, f->linesize);
    v->released = 0;
    f->buf[0] = av_buffer_create(img->pixels, (size_t)sp_image_size(img->format, img->width,
                                                                    img->height),
                                 planes_released, &v->released, AV_BUFFER_FLAG_READONLY);
    if (!f->buf[0]) {
        sp_log_error("%s: out of memory for a video frame", s->path);
        return SP_E_NOMEM;
    }
    f->pts = s->frames;
    int err = video_encode(s, f);
    av_frame_unref(f);
    if (!err && !v->released) {
        sp_log_error("%s: the %s encoder kept a reference to a frame, which this program "
                     "does not expect of it (FFmpeg %s)", s->path, v->codec->encoder,
                     av_version_info());
        err = SP_E_CODEC;
    }
    return err;
}

static int video_write(struct sp_sink *s, const struct sp_image *img)
{
    struct video *v = s->priv;
    const uint8_t *const src[1] = { img->pixels };
    const int src_stride[1] = { img->stride };

    if (img->format == SP_IMAGE_YUV420)
        return yuv_write(s, img);
    int ret = v->sws ? 0 : rgba_setup(s);
    if (ret)
        return ret;
    /* The encoder has let go of the last frame, so this does not copy. */
    ret = av_frame_make_writable(v->frame);
    if (ret < 0)
        return av_failed(s, "cannot reuse the video frame", ret, SP_E_CODEC);
    /* Alpha is dropped (H.264) or kept in the A plane (VP9 yuva420p). */
    ret = sws_scale(v->sws, src, src_stride, 0, img->height, v->frame->data,
                    v->frame->linesize);
    if (ret < 0)
        return av_failed(s, "cannot convert RGBA to YUV", ret, SP_E_CODEC);
    v->frame->pts = s->frames;
    return video_encode(s, v->frame);
}

static int video_close(struct sp_sink *s)
{
    struct video *v = s->priv;
    int err = video_encode(s, NULL);
    if (err)
        return err;
    /* The font files used (springpend.fonts, and their hashes in
     * springpend.environment) are known only after the first frame: MP4
     * writes its tags with moov, in the trailer, so they are set again
     * here. WebM wrote its tags with the header. */
    for (int i = 0; !strcmp(v->codec->muxer, "mp4") && i < v->n_text; i++)
        if (strcmp(v->text[i].key, "springpend.time"))
            av_dict_set(&v->oc->metadata, v->text[i].key, v->text[i].text, 0);
    /* With +faststart the trailer reopens the .part to move moov first. */
    int ret = av_write_trailer(v->oc);
    if (ret >= 0)
        ret = avio_closep(&v->oc->pb);
    if (ret < 0)
        return av_failed(s, "cannot finish the file", ret, SP_E_IO);
    err = sp_outfile_commit(&v->file); /* then nothing to remove */
    if (err)
        return err;
    video_release(s);
    return 0;
}

static int mp4_open(struct sp_sink *s)
{
    ((struct video *)s->priv)->codec = &codec_h264;
    return video_open(s);
}

static int webm_open(struct sp_sink *s)
{
    ((struct video *)s->priv)->codec = &codec_vp9;
    return video_open(s);
}

const struct sp_sink_backend sp_sink_backend_mp4 = {
    .priv_size = sizeof(struct video),
    .formats = 1u << SP_IMAGE_RGBA | 1u << SP_IMAGE_YUV420,
    .best = SP_IMAGE_YUV420,
    .check = mp4_check,
    .open = mp4_open,
    .write = video_write,
    .close = video_close,
    .abort = video_release,
};

const struct sp_sink_backend sp_sink_backend_webm = {
    .priv_size = sizeof(struct video),
    .formats = 1u << SP_IMAGE_RGBA | 1u << SP_IMAGE_YUV420,
    .best = SP_IMAGE_YUV420,
    .check = webm_check,
    .open = webm_open,
    .write = video_write,
    .close = video_close,
    .abort = video_release,
};
