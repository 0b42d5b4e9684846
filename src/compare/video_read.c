/* springpend: video frames back to RGBA8 (video_read.h). The decode loop
 * is FFmpeg's doc/examples/demux_decode.c: read a packet, send it, drain
 * receive_frame until EAGAIN; at the end send NULL and drain to EOF. */
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/avstring.h>
#include <libavutil/display.h>
#include <libavutil/imgutils.h>
#include <libavutil/pixdesc.h>
#include <libswscale/swscale.h>

#include <sys/stat.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/infile.h"
#include "springpend/provenance.h"
#include "springpend/video_read.h"
#include "video_names.h"

struct sp_video_reader {
    char *path;              /* owned copy, for messages */
    AVFormatContext *fmt;    /* owned */
    AVCodecContext *dec;     /* owned */
    AVPacket *pkt;           /* owned, reused */
    AVFrame *frame;          /* owned, reused: the decoded frame */
    AVCodecContext *alpha;   /* owned: a VP9 stream's alpha (open_alpha), or NULL */
    AVPacket *apkt;          /* owned, reused: a packet's alpha data, for alpha */
    AVFrame *aframe;         /* owned, reused: frame's alpha, when it has any */
    struct SwsContext *sws;  /* owned, made for the first frame's format */
    struct sp_image rgba;    /* owned, the converted frame */
    int stream;              /* index of the video stream in fmt */
    int flushing;            /* the demuxer is done; NULL was sent */
    volatile int no_buffer;  /* 1: the decoder said "get_buffer() failed" (av_line) */
    volatile unsigned big_w, big_h; /* a frame FFmpeg refused by max_pixels (av_line): its size */
    int head_w, head_h;      /* the stream's size as its header says */
};

/* This thread's held errors (sp_video_hold_errors): NULL, or a buffer of
 * held_size bytes that messages are appended to, under held_lock (a
 * compare decodes its two videos on two threads into one buffer). */
static _Thread_local char *held;
static _Thread_local size_t held_size;
static pthread_mutex_t held_lock = PTHREAD_MUTEX_INITIALIZER;

void sp_video_hold_errors(char *buf, size_t size)
{
    held = size ? buf : NULL;
    held_size = size;
}

/* Appends text to this thread's held buffer, cut to fit. */
static void hold_text(const char *text)
{
    pthread_mutex_lock(&held_lock);
    size_t used = strlen(held);
    snprintf(held + used, held_size - used, "%s", text);
    pthread_mutex_unlock(&held_lock);
}

/* Logs libav's error averr (or holds it: sp_video_hold_errors), but for
 * out of memory: SP_E_NOMEM, unsaid (video_read.h); a frame that FFmpeg
 * refused as larger than SP_VIDEO_MAX_PIXELS: SP_E_INPUT, said. */
static int av_fail(const struct sp_video_reader *r, const char *what, int averr)
{
    /* FFmpeg's decoders report some failed allocations as damaged data
     * (h264's INVALIDDATA after "get_buffer() failed"): out of memory too,
     * not the file's fault (attack9 #13) */
    char line[PATH_MAX + 256];
    if (r->big_w && (int64_t)r->big_w * r->big_h <= SP_VIDEO_MAX_PIXELS)
        snprintf(line, sizeof(line), "%s: its stream grows to %ux%u, larger than its header's "
                 "%dx%d; not decoded (a video's frames keep one size)", r->path, r->big_w,
                 r->big_h, r->head_w, r->head_h);
    else if (r->big_w) /* refused by max_pixels, which FFmpeg then also calls
                   * "get_buffer() failed": the file's, not memory (attack10 #16) */
        snprintf(line, sizeof(line), "%s: its stream grows to %ux%u, %llu pixels a frame; "
                 "compare reads videos of at most %ld pixels a frame (8192x4352, the largest "
                 "level of H.264, HEVC, VP9 and AV1)", r->path, r->big_w, r->big_h,
                 (unsigned long long)r->big_w * r->big_h, SP_VIDEO_MAX_PIXELS);
    else if (averr == AVERROR(ENOMEM) || r->no_buffer)
        return SP_E_NOMEM;
    else
        snprintf(line, sizeof(line), "%s: %s: %s", r->path, what, av_err2str(averr));
    if (held) {
        char whole[sizeof(line) + 16];
        snprintf(whole, sizeof(whole), "springpend: %s\n", line);
        hold_text(whole);
    } else {
        sp_log_error("%s", line);
    }
    return r->big_w ? SP_E_INPUT : SP_E_CODEC;
}

/* The most bytes a box that FFmpeg's mov demuxer reads into memory as
 * metadata (udta, meta) may hold: what springpend writes there (every
 * scene of a side-by-side render, SP_PROVENANCE_SCENE_MAX each, and its
 * other text) with room to spare. */
#define SP_VIDEO_META_MAX ((off_t)(2 * (SP_PROVENANCE_MAX_SCENES + 1)) * SP_PROVENANCE_SCENE_MAX)

static uint64_t be(const unsigned char *b, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v = v << 8 | b[i];
    return v;
}

/* Refuses (SP_E_INPUT, logged) an MP4/MOV at fd whose metadata FFmpeg would
 * read into memory before springpend can look at its size: avformat_open_-
 * input allocates every tag of moov/udta/meta whole (twice its size for a
 * QuickTime string) and inflates a compressed moov (cmov) to the size the
 * file claims, so a forged 1 GB tag costs gigabytes before the
 * SP_PROVENANCE_SCENE_MAX check. FFmpeg has no option that bounds this, so
 * the box sizes are walked first, as the demuxer does (a size clamped to
 * its parent's end): only box headers are read. The box containers that
 * hold udta or meta are followed; a file that is not ISO BMFF has no such
 * boxes and passes (Matroska, GIF: their readers are FFmpeg's). 0 to go
 * on. path NULL: nothing is logged. */
static int metadata_bounded(int fd, const char *path, off_t from, off_t to, int depth)
{
    static const char *const containers[] = {"moov", "trak", "mdia", "minf", "moof", "traf",
                                             "edts"};
    while (to - from >= 8) {
        unsigned char h[16];
        if (pread(fd, h, sizeof(h), from) < 8)
            return 0; /* short: FFmpeg says what is wrong */
        off_t size = (off_t)be(h, 4), head = 8;
        if (size == 1 && to - from >= 16)
            size = (off_t)(be(h + 8, 8) & INT64_MAX), head = 16;
        else if (size == 0)
            size = to - from; /* to the end */
        if (size < head)
            return 0; /* damaged: FFmpeg's to refuse */
        if (size > to - from)
            size = to - from;
        if (!memcmp(h + 4, "cmov", 4)) {
            if (path)
                sp_log_error("%s: holds a compressed movie header (cmov), which FFmpeg "
                             "would inflate to any size it claims; springpend writes none",
                             path);
            return SP_E_INPUT;
        }
        if ((!memcmp(h + 4, "udta", 4) || !memcmp(h + 4, "meta", 4)) &&
            size - head > SP_VIDEO_META_MAX) {
            if (path)
                sp_log_error("%s: its metadata box %.4s holds %lld bytes, which FFmpeg would "
                             "read into memory whole; springpend writes at most %lld there",
                             path, (const char *)h + 4, (long long)(size - head),
                             (long long)SP_VIDEO_META_MAX);
            return SP_E_INPUT;
        }
        for (size_t i = 0; depth < 8 && i < sizeof(containers) / sizeof(containers[0]); i++) {
            int err;
            if (!memcmp(h + 4, containers[i], 4) &&
                (err = metadata_bounded(fd, path, from + head, from + size, depth + 1)) != 0)
                return err;
        }
        from += size;
    }
    return 0;
}

/* The containers springpend writes and compares (FFmpeg's demuxer names:
 * "mov,mp4,m4a,3gp,3g2,mj2" and "matroska,webm" match by any of theirs),
 * and raw H.264/HEVC streams (an encoder's output with no container). None
 * of them names another file or URL to open. */
#define SP_VIDEO_FORMATS "mov,mp4,matroska,webm,gif,h264,hevc"
#define SP_VIDEO_FORMATS_SAID                                                                \
    "compare reads the MP4/MOV, WebM/Matroska and GIF files springpend writes (and raw "    \
    "H.264/HEVC streams)"

/* The video codecs springpend writes (H.264 in MP4, VP9 in WebM, GIF) and
 * HEVC (raw streams are read: SP_VIDEO_FORMATS): only their decoders are
 * opened, whatever codec a file names (FFmpeg has some 290 video decoders,
 * a few rarely audited: attack9 #4). FFmpeg's decoder names. */
#define SP_VIDEO_CODECS "h264,hevc,vp9,gif"
#define SP_VIDEO_CODECS_SAID "H.264, VP9 and GIF, the codecs springpend writes, and HEVC"

/* What a video's name promises: video_names.h, one table with the
 * folder walk's. */

/* The entry of video_names that path's ending names, or NULL. */
static const struct sp_video_name *video_name_of(const char *path)
{
    const size_t n = strlen(path);
    for (int i = 0; i < SP_VIDEO_NAMES_COUNT; i++) {
        const size_t k = strlen(sp_video_names[i].ending);
        if (n > k && path[n - k - 1] != '/' && !strcasecmp(path + n - k, sp_video_names[i].ending))
            return &sp_video_names[i];
    }
    return NULL;
}

/* 0 when the format FFmpeg found in the file at path (its demuxer name and
 * long name) is what the file's name says (video_names); else SP_E_INPUT,
 * logged when say. */
static int format_named(const char *path, const AVInputFormat *found, int say)
{
    const struct sp_video_name *v = video_name_of(path);
    if (v && av_match_list(found->name, v->formats, ',') > 0)
        return 0;
    if (say && v)
        sp_log_error("%s: a file of format '%s' (%s), not %s as its name says; "
                     SP_VIDEO_NAMES_SAID, path, found->name,
                     found->long_name ? found->long_name : "?", v->said);
    else if (say)
        sp_log_error("%s: a file of format '%s' (%s), under a name compare does not read as "
                     "a video; " SP_VIDEO_NAMES_SAID, path, found->name,
                     found->long_name ? found->long_name : "?");
    return SP_E_INPUT;
}

/* 0 unless path is named .webm and fmt (a Matroska file, format_named has
 * seen) holds a video stream of a codec WebM does not (WebM: VP8, VP9 or
 * AV1): then SP_E_INPUT, logged when say. WebM and Matroska share FFmpeg's
 * demuxer, so the format alone takes an H.264 Matroska file for WebM,
 * which browsers do not play as one (attack12 #8). The streams and their
 * codecs are the Matroska header's: nothing is decoded. */
static int webm_codecs(const char *path, const AVFormatContext *fmt, int say)
{
    const struct sp_video_name *v = video_name_of(path);
    if (!v || strcmp(v->ending, ".webm"))
        return 0;
    for (unsigned i = 0; i < fmt->nb_streams; i++) {
        const AVCodecParameters *par = fmt->streams[i]->codecpar;
        const AVCodecDescriptor *d = avcodec_descriptor_get(par->codec_id);
        /* a codec compare does not decode is refused by name later (attack9) */
        if (par->codec_type != AVMEDIA_TYPE_VIDEO || par->codec_id == AV_CODEC_ID_VP8 ||
            par->codec_id == AV_CODEC_ID_VP9 || par->codec_id == AV_CODEC_ID_AV1 || !d ||
            av_match_list(d->name, SP_VIDEO_CODECS, ',') <= 0)
            continue;
        if (say) {
            sp_log_error("%s: a Matroska file with %s video (%s), not WebM as its name says "
                         "(WebM holds VP8, VP9 or AV1; springpend writes VP9): name it .mkv to "
                         "compare it as Matroska", path,
                         d->long_name ? d->long_name : d->name, d->name);
        }
        return SP_E_INPUT;
    }
    return 0;
}

/* Opens the file at name (open at fd; path: its name, for its ending and
 * in messages when say) in *fmt as one of SP_VIDEO_FORMATS, through the
 * file protocol only: a playlist (HLS, concat, ...) naming other files, or
 * any other format FFmpeg would detect from the content, is refused, naming
 * the format found, before FFmpeg reads anything it names; so is a format
 * other than the one path's ending names (format_named), once FFmpeg has
 * found it. 0, SP_E_INPUT (logged when say) or SP_E_NOMEM. */
static int open_video(AVFormatContext **fmt, const char *name, int fd, const char *path, int say)
{
    uint8_t head[4096 + AVPROBE_PADDING_SIZE] = {0};
    ssize_t got = pread(fd, head, sizeof(head) - AVPROBE_PADDING_SIZE, 0);
    AVProbeData pd = {.filename = name, .buf = head, .buf_size = got > 0 ? (int)got : 0};
    const AVInputFormat *found = av_probe_input_format(&pd, 1);
    AVDictionary *opts = NULL;
    int ret;
    if (found && av_match_list(found->name, SP_VIDEO_FORMATS, ',') <= 0) {
        if (say)
            sp_log_error("%s: a file of format '%s' (%s), not a video springpend reads; "
                         SP_VIDEO_FORMATS_SAID,
                         path, found->name, found->long_name ? found->long_name : "?");
        return SP_E_INPUT;
    }
    if (av_dict_set(&opts, "protocol_whitelist", "file", 0) < 0 ||
        av_dict_set(&opts, "format_whitelist", SP_VIDEO_FORMATS, 0) < 0 ||
        av_dict_set(&opts, "codec_whitelist", SP_VIDEO_CODECS, 0) < 0) {
        av_dict_free(&opts);
        return SP_E_NOMEM;
    }
    ret = avformat_open_input(fmt, name, NULL, &opts);
    av_dict_free(&opts);
    if (ret == AVERROR(ENOMEM))
        return SP_E_NOMEM;
    if (ret < 0) {
        if (say)
            sp_log_error("%s: cannot read a video from it: %s (" SP_VIDEO_FORMATS_SAID ")",
                         path, av_err2str(ret));
        return SP_E_INPUT;
    }
    if ((ret = format_named(path, (*fmt)->iformat, say)) != 0 ||
        (ret = webm_codecs(path, *fmt, say)) != 0)
        avformat_close_input(fmt);
    return ret;
}

/* Matroska's element IDs (marker bits kept) that lead to a video track's
 * AlphaMode: Segment, Tracks, TrackEntry, TrackType, Video, AlphaMode. */
#define MKV_SEGMENT 0x18538067u
#define MKV_TRACKS 0x1654AE6Bu
#define MKV_TRACK_ENTRY 0xAEu
#define MKV_TRACK_TYPE 0x83u
#define MKV_VIDEO 0xE0u
#define MKV_ALPHA_MODE 0x53C0u

/* An EBML variable-length integer at b (n bytes there): its length in
 * bytes, 0 when malformed; its value in *v, the marker bit kept for an ID
 * (id 1, at most 4 bytes), dropped for a size, whose all ones (unknown)
 * is UINT64_MAX. */
static int ebml_vint(const unsigned char *b, int n, int id, uint64_t *v)
{
    int len = 1;
    if (n < 1 || !b[0])
        return 0;
    while (!(b[0] & (0x80 >> (len - 1))))
        len++;
    if (len > n || (id && len > 4))
        return 0;
    uint64_t x = id ? b[0] : b[0] & (0xFFu >> len);
    int ones = x == (0xFFu >> len);
    for (int i = 1; i < len; i++)
        x = x << 8 | b[i], ones &= b[i] == 0xFF;
    *v = !id && ones ? UINT64_MAX : x;
    return len;
}

/* Walks the EBML elements of fd in [from, to), children of the element
 * parent (0: the file), for the first video TrackEntry (TrackType 1): its
 * Video's AlphaMode, which browsers honour to composite the BlockAdditional
 * alpha, into *alpha (*alpha < 0 until such a track is found). FFmpeg has
 * it only as the stream tag alpha_mode, which a Matroska Tag of that name
 * overwrites (ffmpeg's copies write one): the file says, not the tags. A
 * Cluster of unknown size, or 4096 elements at one level, end the walk. */
static void mkv_alpha_mode(int fd, off_t from, off_t to, uint32_t parent, int depth,
                           int *alpha)
{
    int video = 0, mode = 0;
    for (int count = 0; to - from >= 2 && count < 4096 && *alpha < 0; count++) {
        unsigned char h[12];
        uint64_t id, size;
        ssize_t got = pread(fd, h, sizeof(h), from);
        int a = got > 0 ? ebml_vint(h, (int)got, 1, &id) : 0;
        int b = a ? ebml_vint(h + a, (int)got - a, 0, &size) : 0;
        if (!b)
            return;
        const off_t data = from + a + b;
        if (size == UINT64_MAX && id != MKV_SEGMENT)
            return; /* a live Cluster: the tracks came before, if at all */
        const off_t end = size == UINT64_MAX || size > (uint64_t)(to - data) ? to
                          : data + (off_t)size;
        if (size <= 8 && (id == MKV_TRACK_TYPE || id == MKV_ALPHA_MODE) &&
            pread(fd, h, (size_t)size, data) == (ssize_t)size) {
            if (id == MKV_TRACK_TYPE && parent == MKV_TRACK_ENTRY)
                video = be(h, (int)size) == 1;
            else if (id == MKV_ALPHA_MODE && parent == MKV_VIDEO)
                *alpha = be(h, (int)size) == 1; /* the Video's parent sees it */
        }
        if (depth < 4 && ((id == MKV_SEGMENT && !parent) || (id == MKV_TRACKS &&
            parent == MKV_SEGMENT) || (id == MKV_TRACK_ENTRY && parent == MKV_TRACKS) ||
            (id == MKV_VIDEO && parent == MKV_TRACK_ENTRY))) {
            mkv_alpha_mode(fd, data, end, (uint32_t)id, depth + 1, alpha);
            if (parent == MKV_TRACK_ENTRY)
                mode = *alpha > 0, *alpha = -1; /* the entry's, once its type is known */
        }
        from = end;
    }
    if (parent == MKV_TRACK_ENTRY && video)
        *alpha = mode;
}

/* Opens the video at path in *fmt through a descriptor checked by infile.h
 * (a regular file: FFmpeg would wait on a FIFO for ever) and by
 * metadata_bounded; FFmpeg opens that descriptor, not the name again.
 * SP_E_INPUT (logged) when it cannot. alpha, unless NULL: 1 when the file
 * is Matroska and its video track has AlphaMode 1 (mkv_alpha_mode), else 0. */
static int open_checked(AVFormatContext **fmt, const char *path, int *alpha)
{
    char name[32];
    int fd = sp_infile_open(path, "a video must be a file"), ret, mode = -1;
    struct stat st;
    if (fd < 0)
        return fd; /* as a file FFmpeg cannot read, or out of descriptors */
    const int sized = fstat(fd, &st) == 0;
    ret = sized ? metadata_bounded(fd, path, 0, st.st_size, 0) : 0;
    if (ret) {
        close(fd);
        return ret;
    }
    snprintf(name, sizeof(name), "/proc/self/fd/%d", fd);
    ret = open_video(fmt, access(name, R_OK) ? path : name, fd, path, 1);
    if (alpha && !ret && sized && !strcmp((*fmt)->iformat->name, "matroska,webm"))
        mkv_alpha_mode(fd, 0, st.st_size, 0, 0, &mode);
    if (alpha)
        *alpha = mode > 0;
    close(fd);
    return ret;
}

static int codec_read(enum AVCodecID id)
{
    return id == AV_CODEC_ID_H264 || id == AV_CODEC_ID_HEVC || id == AV_CODEC_ID_VP9 ||
           id == AV_CODEC_ID_GIF;
}

/* What fmt's first video stream's header says, before anything is
 * decoded: its frame size in *w, *h (0 when none says one) and codec in
 * *id (AV_CODEC_ID_NONE without a video stream). 1 when the reader refuses
 * it unread: a size beyond SP_VIDEO_MAX_PIXELS or one FFmpeg refuses, or a
 * codec springpend does not read (codec_read); else 0. */
static int header_check(const AVFormatContext *fmt, int *w, int *h, enum AVCodecID *id)
{
    *w = *h = 0;
    *id = AV_CODEC_ID_NONE;
    for (unsigned i = 0; i < fmt->nb_streams; i++) {
        const AVCodecParameters *p = fmt->streams[i]->codecpar;
        if (p->codec_type != AVMEDIA_TYPE_VIDEO)
            continue;
        *id = p->codec_id;
        if (p->width > 0 && p->height > 0)
            *w = p->width, *h = p->height;
        return !codec_read(p->codec_id) || (int64_t)*w * *h > SP_VIDEO_MAX_PIXELS ||
               (*w && av_image_check_size(*w, *h, 0, NULL) != 0);
    }
    return 0;
}

/* The index of fmt's first video stream, the one header_check reads and
 * the reader decodes, when it is its only one (attached pictures count);
 * SP_E_INPUT (logged) when there are more: players show the first video
 * track, FFmpeg's av_find_best_stream picks the largest bit rate, so a
 * file holding another scene first and a copy of the baseline second
 * passed while browsers showed the other (attack15 #5); springpend writes
 * one. AVERROR_STREAM_NOT_FOUND when there is none. */
static int one_video(const AVFormatContext *fmt, const char *path)
{
    int first = AVERROR_STREAM_NOT_FOUND, n = 0;
    for (unsigned i = 0; i < fmt->nb_streams; i++)
        if (fmt->streams[i]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO && !n++)
            first = (int)i;
    if (n <= 1)
        return first;
    sp_log_error("%s: holds %d video streams; springpend writes one, and players show the "
                 "first while others would judge another: keep the one to compare (ffmpeg -i "
                 "FILE -map 0:v:0 -c copy OUT)", path, n);
    return SP_E_INPUT;
}

/* Refuses (SP_E_INPUT, logged) a frame size beyond SP_VIDEO_MAX_PIXELS:
 * what says where it was read. */
static int too_large(const char *path, const char *what, int w, int h)
{
    sp_log_error("%s: %s %dx%d, %lld pixels a frame; compare reads videos of at most %ld "
                 "pixels a frame (8192x4352, the largest level of H.264, HEVC, VP9 and AV1)",
                 path, what, w, h, (long long)w * h, SP_VIDEO_MAX_PIXELS);
    return SP_E_INPUT;
}

/* FFmpeg's own log lines (av_log), each written whole under stderr's stdio
 * lock as springpend's are (log.c), and shown as sp_fputs_printable shows
 * text: FFmpeg's default writes its "[mov @ 0x...] " prefix and its text
 * apart, so that compare --jobs interleaved them with springpend's lines
 * from other threads (attack8 #8). Its level still filters. */
static _Thread_local int av_quiet; /* 1: FFmpeg's lines are dropped */

static void av_line(void *avcl, int level, const char *fmt, va_list vl)
{
    static _Thread_local int prefix = 1;
    char line[1024];
    /* a frame buffer that could not be had: said by ff_get_buffer and
     * h264, with the decoder's context, whose opaque is its reader */
    if (avcl && *(const AVClass *const *)avcl == avcodec_get_class() &&
        !strcmp(fmt, "get_buffer() failed\n") && ((AVCodecContext *)avcl)->opaque)
        ((struct sp_video_reader *)((AVCodecContext *)avcl)->opaque)->no_buffer = 1;
    /* a frame over max_pixels: said by av_image_check_size2 with its own
     * context, whose parent is the decoder's */
    const AVClass *cls = avcl ? *(const AVClass *const *)avcl : NULL;
    if (cls && cls->parent_log_context_offset &&
        !strncmp(fmt, "Picture size %ux%u exceeds specified max pixel count", 52)) {
        void *parent = *(void **)((char *)avcl + cls->parent_log_context_offset);
        if (parent && *(const AVClass *const *)parent == avcodec_get_class() &&
            ((AVCodecContext *)parent)->opaque) {
            struct sp_video_reader *r = ((AVCodecContext *)parent)->opaque;
            va_list size;
            va_copy(size, vl);
            const unsigned w = va_arg(size, unsigned), h = va_arg(size, unsigned);
            va_end(size);
            r->big_h = h, r->big_w = w;
        }
    }
    if (level > av_log_get_level() || av_quiet)
        return;
    av_log_format_line2(avcl, level, fmt, vl, line, sizeof(line), &prefix);
    if (held) {
        hold_text(line);
        return;
    }
    flockfile(stderr);
    sp_fputs_printable(line, stderr);
    funlockfile(stderr);
}

static void log_through_lines(void)
{
    av_log_set_callback(av_line);
}

static pthread_once_t log_once = PTHREAD_ONCE_INIT;

/* avformat_find_stream_info, whose probing decoders refuse a frame beyond
 * SP_VIDEO_MAX_PIXELS as the reader's own does (the codec option
 * max_pixels, a stream each). Its return value. */
static int find_stream_info(AVFormatContext *fmt)
{
    const unsigned n = fmt->nb_streams;
    AVDictionary **opts = n ? av_calloc(n, sizeof(*opts)) : NULL;
    int ret = n && !opts ? AVERROR(ENOMEM) : 0;
    for (unsigned i = 0; i < n && ret >= 0; i++)
        ret = av_dict_set_int(&opts[i], "max_pixels", SP_VIDEO_MAX_PIXELS, 0);
    if (ret >= 0)
        ret = avformat_find_stream_info(fmt, opts);
    for (unsigned i = 0; opts && i < n; i++)
        av_dict_free(&opts[i]);
    av_freep(&opts);
    return ret;
}

/* Refuses (SP_E_INPUT, logged) a video stream whose colour tags make
 * players convert its colours otherwise than springpend's videos: other
 * primaries, transfer or matrix than BT.709 (or none), or full range
 * (springpend writes BT.709, limited range). compare judges the decoded
 * pixels alike whatever the tags, so a file retagged BT.2020/PQ without
 * re-encoding passed as identical while players tone-map it (attack14 #4),
 * as a PNG's cICP or iCCP would (png_io.c). 0 when as springpend writes. */
static int colour_as_coded(const AVStream *st, const char *path)
{
    const AVCodecParameters *p = st->codecpar;
    const int pri = p->color_primaries, trc = p->color_trc, spc = p->color_space;
    const int bad_pri = pri != AVCOL_PRI_UNSPECIFIED && pri != AVCOL_PRI_BT709,
              bad_trc = trc != AVCOL_TRC_UNSPECIFIED && trc != AVCOL_TRC_BT709,
              bad_spc = spc != AVCOL_SPC_UNSPECIFIED && spc != AVCOL_SPC_BT709,
              full = p->color_range == AVCOL_RANGE_JPEG;
    if (!bad_pri && !bad_trc && !bad_spc && !full)
        return 0;
    const char *name = bad_pri ? av_color_primaries_name(p->color_primaries)
                       : bad_trc ? av_color_transfer_name(p->color_trc)
                       : bad_spc ? av_color_space_name(p->color_space) : "full range";
    sp_log_error("%s: its video is tagged %s %s, by which players convert its colours; "
                 "springpend writes BT.709 (limited range) and compares the pixels as coded: "
                 "re-encode it with BT.709 tags (ffmpeg -colorspace bt709 -color_primaries bt709 "
                 "-color_trc bt709 -color_range tv), or remove the tags", path,
                 bad_pri ? "with colour primaries" : bad_trc ? "with the transfer"
                 : bad_spc ? "with the matrix" : "as", name ? name : "unknown");
    return SP_E_INPUT;
}

/* Refuses (SP_E_INPUT, logged) a video stream st of fmt that players show
 * otherwise than its pixels are coded: by a display matrix other than the
 * identity (turned, mirrored: attack12 #12, scaled), or stretched by a
 * sample aspect ratio other than 1:1 (unset counts as square). springpend
 * writes neither, and compare judges the coded pixels, so such a file
 * would pass for its baseline while players show it turned, mirrored or
 * stretched (attack11 #8). 0 when shown as coded. */
static int shown_as_coded(AVFormatContext *fmt, AVStream *st, const char *path)
{
    size_t size = 0;
    const uint8_t *side = av_stream_get_side_data(st, AV_PKT_DATA_DISPLAYMATRIX, &size);
    const AVRational sar = av_guess_sample_aspect_ratio(fmt, st, NULL);
    int32_t m[9] = {1 << 16, 0, 0, 0, 1 << 16, 0, 0, 0, 1 << 30}; /* none: the identity */
    if (side && size >= sizeof(m))
        memcpy(m, side, sizeof(m));
    /* the matrix's 2x2 part (16.16) and its projective column (2.30); a
     * translation alone (m[6], m[7]) moves no pixel of the picture */
    const double a = m[0] / 65536.0, b = m[1] / 65536.0, c = m[3] / 65536.0,
                 d = m[4] / 65536.0, det = a * d - b * c;
    const int identity = m[0] == 1 << 16 && m[1] == 0 && m[3] == 0 && m[4] == 1 << 16 &&
                         m[2] == 0 && m[5] == 0 && m[8] == 1 << 30;
    if (identity && (sar.num == 0 || sar.num == sar.den))
        return 0;
    const char *how = "springpend writes none, and compare judges the pixels as coded, "
                      "which no player shows";
    if (!identity && det < 0) {
        /* a mirror: undo the left-right one, and the rest is a turn */
        int32_t unmirrored[9];
        memcpy(unmirrored, m, sizeof(m));
        av_display_matrix_flip(unmirrored, 1, 0);
        const double turn = av_display_rotation_get(unmirrored);
        if (isnan(turn) || fabs(turn) < 0.5)
            sp_log_error("%s: its video is shown mirrored left to right (a display matrix); %s",
                         path, how);
        else if (fabs(fabs(turn) - 180) < 0.5)
            sp_log_error("%s: its video is shown mirrored top to bottom, upside down (a display "
                         "matrix); %s", path, how);
        else
            sp_log_error("%s: its video is shown mirrored left to right and turned by %.0f "
                         "degrees %sclockwise (a display matrix); %s", path, fabs(turn),
                         turn < 0 ? "" : "counter", how);
    } else if (!identity) {
        const double turn = av_display_rotation_get(m);
        const int rotation = m[2] == 0 && m[5] == 0 && m[8] == 1 << 30 && !isnan(turn) &&
                             fabs(a - d) < 1e-3 && fabs(b + c) < 1e-3 && fabs(det - 1) < 1e-3;
        if (rotation)
            sp_log_error("%s: its video is shown turned by %.0f degrees %sclockwise (a display "
                         "matrix); %s", path, fabs(turn), turn < 0 ? "" : "counter", how);
        else
            sp_log_error("%s: its video is shown scaled, sheared or in perspective by a display "
                         "matrix (%g %g / %g %g); %s", path, a, b, c, d, how);
    } else
        sp_log_error("%s: its video's pixels are shown %d:%d (a sample aspect ratio), not "
                     "square; springpend writes square pixels, and compare judges them as "
                     "coded, which no player shows", path, sar.num, sar.den);
    return SP_E_INPUT;
}

/* Opens r->alpha, a second decoder of codec (FFmpeg's own VP9), for the
 * alpha of a WebM whose VP9 track says it has one (alpha: Matroska's
 * AlphaMode 1, mkv_alpha_mode), as springpend's transparent WebM does: each
 * frame's alpha is a VP9 picture of its own in the block's BlockAdditional
 * (id 1), whose luma plane is the alpha, and which browsers composite.
 * FFmpeg's VP9 decoder drops it, so a WebM made transparent, or opaque,
 * passed for its baseline (attack15 #4); decoded here by the same decoder
 * under the same limits (max_pixels, strict) as the picture, one thread
 * each: one frame out for each packet in, so the two stay paired. 0 when
 * there is no alpha to decode, or av_fail's code. */
static int open_alpha(struct sp_video_reader *r, const AVCodec *codec, int alpha)
{
    const AVStream *st = r->fmt->streams[r->stream];
    if (codec->id != AV_CODEC_ID_VP9 || !alpha)
        return 0;
    if (!(r->alpha = avcodec_alloc_context3(codec)) || !(r->apkt = av_packet_alloc()) ||
        !(r->aframe = av_frame_alloc()))
        return av_fail(r, "cannot make the alpha's decoder", AVERROR(ENOMEM));
    int ret = avcodec_parameters_to_context(r->alpha, st->codecpar);
    r->alpha->max_pixels = r->dec->max_pixels;
    r->alpha->thread_count = 1;
    r->alpha->opaque = r;
    r->alpha->err_recognition = r->dec->err_recognition;
    if (ret >= 0)
        ret = avcodec_open2(r->alpha, codec, NULL);
    return ret < 0 ? av_fail(r, "cannot open the alpha's decoder", ret) : 0;
}

/* sp_video_reader_open; strict: the decoder stops at the first damage it
 * finds (AV_EF_EXPLODE) rather than hiding it, as it may a cut frame. */
static int reader_open(struct sp_video_reader **out, const char *path, int strict)
{
    pthread_once(&log_once, log_through_lines);
    struct sp_video_reader *r = calloc(1, sizeof(*r));
    const AVCodec *codec = NULL;
    int ret;
    *out = NULL;
    if (!r || !(r->path = strdup(path)) || !(r->pkt = av_packet_alloc()) ||
        !(r->frame = av_frame_alloc())) {
        ret = SP_E_NOMEM;
        goto fail;
    }
    int w, h, first, alpha;
    if ((ret = open_checked(&r->fmt, path, &alpha)) != 0 ||
        (ret = first = one_video(r->fmt, path)) == SP_E_INPUT)
        goto fail;
    enum AVCodecID id;
    if (header_check(r->fmt, &w, &h, &id)) { /* before anything is decoded */
        const AVCodecDescriptor *d = avcodec_descriptor_get(id);
        if (codec_read(id)) {
            ret = too_large(path, "its header says", w, h);
        } else {
            sp_log_error("%s: its video is %s (%s); compare reads " SP_VIDEO_CODECS_SAID, path,
                         d && d->long_name ? d->long_name : "of an unknown codec",
                         d ? d->name : "?");
            ret = SP_E_INPUT;
        }
        goto fail;
    }
    ret = find_stream_info(r->fmt);
    if (ret >= 0) /* the first video stream, header_check's, and no other */
        ret = r->stream = av_find_best_stream(r->fmt, AVMEDIA_TYPE_VIDEO, first < 0 ? -1 : first, -1,
                                            &codec, 0);
    if (ret == AVERROR(ENOMEM)) {
        ret = SP_E_NOMEM;
        goto fail;
    }
    if (ret < 0) {
        sp_log_error("%s: cannot read a video from it: %s", path, av_err2str(ret));
        ret = SP_E_INPUT;
        goto fail;
    }
    if (!codec_read(codec->id)) { /* the best stream, which may not be the first */
        sp_log_error("%s: its video is %s (%s); compare reads " SP_VIDEO_CODECS_SAID, path,
                     codec->long_name ? codec->long_name : codec->name, codec->name);
        ret = SP_E_INPUT;
        goto fail;
    }
    if ((ret = shown_as_coded(r->fmt, r->fmt->streams[r->stream], path)) != 0 ||
        (ret = colour_as_coded(r->fmt->streams[r->stream], path)) != 0)
        goto fail;
    if (!(r->dec = avcodec_alloc_context3(codec))) {
        ret = av_fail(r, "cannot make a decoder", AVERROR(ENOMEM));
        goto fail;
    }
    ret = avcodec_parameters_to_context(r->dec, r->fmt->streams[r->stream]->codecpar);
    if (ret >= 0 && (int64_t)r->dec->width * r->dec->height > SP_VIDEO_MAX_PIXELS) {
        ret = too_large(path, "its stream says", r->dec->width, r->dec->height);
        goto fail;
    }
    /* a larger frame is an error, unallocated: larger than the limit, or
     * than the header's size, by which compare counted the memory (a stream
     * that grows mid-way: attack10 #12); every frame must have that size
     * anyway. The margin: ff_get_buffer checks the width aligned up (to 64) */
    const int64_t head = r->dec->width > 0 && r->dec->height > 0
                             ? ((int64_t)r->dec->width + 128) * (r->dec->height + 64)
                             : SP_VIDEO_MAX_PIXELS;
    r->dec->max_pixels = head < SP_VIDEO_MAX_PIXELS ? head : SP_VIDEO_MAX_PIXELS;
    r->head_w = r->dec->width, r->head_h = r->dec->height;
    r->dec->opaque = r;                       /* for av_line's get_buffer() failures */
    r->dec->thread_count = 1;                 /* a frame out for each packet in: open_alpha */
    if (strict)
        r->dec->err_recognition |= AV_EF_EXPLODE;
    if (ret >= 0)
        ret = avcodec_open2(r->dec, codec, NULL);
    if (ret < 0) {
        ret = av_fail(r, "cannot open the decoder", ret);
        goto fail;
    }
    if ((ret = open_alpha(r, codec, alpha)) != 0)
        goto fail;
    *out = r;
    return 0;
fail:
    sp_video_reader_destroy(&r);
    return ret;
}

int sp_video_reader_open(struct sp_video_reader **out, const char *path)
{
    return reader_open(out, path, 0);
}

/* Converts r->frame into r->rgba. */
static int convert(struct sp_video_reader *r, struct sp_image *img)
{
    const AVFrame *f = r->frame;
    if (!r->rgba.pixels || r->rgba.width != f->width || r->rgba.height != f->height) {
        sp_image_free(&r->rgba);
        int err = sp_image_alloc_unsaid(&r->rgba, f->width, f->height);
        if (err)
            return err;
    }
    r->sws = sws_getCachedContext(r->sws, f->width, f->height, f->format, f->width,
                                  f->height, AV_PIX_FMT_RGBA,
                                  SWS_BILINEAR | SWS_ACCURATE_RND | SWS_BITEXACT |
                                      SWS_FULL_CHR_H_INT,
                                  NULL, NULL, NULL);
    if (!r->sws) {
        char what[96];
        snprintf(what, sizeof(what), "cannot convert %dx%d %s frames to RGBA", f->width,
                 f->height, av_get_pix_fmt_name(f->format));
        return av_fail(r, what, AVERROR(EINVAL)); /* swscale says no more */
    }
    uint8_t *dst[4] = {r->rgba.pixels};
    int dst_stride[4] = {r->rgba.stride};
    sws_scale(r->sws, (const uint8_t *const *)f->data, f->linesize, 0, f->height, dst,
              dst_stride);
    const AVFrame *a = r->aframe;
    if (a && a->buf[0]) /* its alpha (take_alpha): the alpha picture's luma, as is */
        for (int y = 0; y < f->height; y++)
            for (int x = 0; x < f->width; x++)
                r->rgba.pixels[(size_t)y * r->rgba.stride + 4 * (size_t)x + 3] =
                    a->data[0][(size_t)y * a->linesize[0] + x];
    *img = r->rgba;
    return 1;
}

/* Sends r->alpha (open_alpha; none: nothing) the alpha data of packet pkt
 * (NULL: the end), after dropping an alpha frame that no picture took (a
 * packet whose picture was hidden). A packet without alpha data sends
 * nothing: its frame is opaque, as browsers show it. 0 or av_fail's code. */
static int send_alpha(struct sp_video_reader *r, const AVPacket *pkt)
{
    int ret;
    if (!r->alpha)
        return 0;
    while ((ret = avcodec_receive_frame(r->alpha, r->aframe)) >= 0)
        av_frame_unref(r->aframe);
    if (ret != AVERROR(EAGAIN) && ret != AVERROR_EOF)
        return av_fail(r, "cannot decode its alpha", ret);
    if (!pkt)
        ret = avcodec_send_packet(r->alpha, NULL);
    size_t size = 0;
    const uint8_t *side =
        pkt ? av_packet_get_side_data(pkt, AV_PKT_DATA_MATROSKA_BLOCKADDITIONAL, &size) : NULL;
    if (side && size > 8 && size - 8 <= INT_MAX / 2 && be(side, 8) == 1) { /* id 1: alpha */
        av_packet_unref(r->apkt);
        if (av_new_packet(r->apkt, (int)(size - 8)) < 0)
            return av_fail(r, "cannot read its alpha", AVERROR(ENOMEM));
        memcpy(r->apkt->data, side + 8, size - 8);
        r->apkt->pts = pkt->pts, r->apkt->dts = pkt->dts;
        r->apkt->flags = pkt->flags & AV_PKT_FLAG_KEY;
        ret = avcodec_send_packet(r->alpha, r->apkt);
    }
    return ret < 0 && ret != AVERROR_EOF ? av_fail(r, "cannot decode its alpha", ret) : 0;
}

/* Takes into r->aframe the alpha of the frame just decoded into r->frame,
 * when r->alpha has one (else the frame is opaque, r->aframe empty): an
 * 8-bit picture of the frame's size. 0 or av_fail's code. */
static int take_alpha(struct sp_video_reader *r)
{
    if (!r->alpha)
        return 0;
    const int ret = avcodec_receive_frame(r->alpha, r->aframe);
    if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF)
        return 0;
    if (ret < 0)
        return av_fail(r, "cannot decode its alpha", ret);
    const AVPixFmtDescriptor *d = av_pix_fmt_desc_get(r->aframe->format);
    if (r->aframe->width != r->frame->width || r->aframe->height != r->frame->height || !d ||
        d->comp[0].depth != 8 || (d->flags & AV_PIX_FMT_FLAG_RGB)) {
        av_frame_unref(r->aframe);
        return av_fail(r, "its alpha is not an 8-bit picture of its frame's size",
                       AVERROR_INVALIDDATA);
    }
    return 0;
}

/* Decodes the next frame into r->frame (and its alpha: take_alpha): 1, 0
 * after the last one, or a negative SP_E_* code (av_fail's). */
static int next_frame(struct sp_video_reader *r)
{
    for (;;) {
        int ret = avcodec_receive_frame(r->dec, r->frame);
        if (ret >= 0)
            return (ret = take_alpha(r)) ? ret : 1;
        if (ret == AVERROR_EOF)
            return 0;
        if (ret != AVERROR(EAGAIN))
            return av_fail(r, "cannot decode", ret);
        if (r->flushing)
            return av_fail(r, "the decoder wants input after the end", ret);
        /* Feed the next packet of our stream, or NULL at the end. */
        do {
            av_packet_unref(r->pkt);
            ret = av_read_frame(r->fmt, r->pkt);
        } while (ret >= 0 && r->pkt->stream_index != r->stream);
        if (ret == AVERROR_EOF) {
            r->flushing = 1;
            ret = avcodec_send_packet(r->dec, NULL);
        } else if (ret >= 0) {
            ret = avcodec_send_packet(r->dec, r->pkt);
        }
        if (ret < 0)
            return av_fail(r, "cannot read the next frame", ret);
        if ((ret = send_alpha(r, r->flushing ? NULL : r->pkt)) != 0)
            return ret;
    }
}

int sp_video_reader_read(struct sp_video_reader *r, struct sp_image *img, double *t)
{
    int ret = next_frame(r);
    if (ret != 1)
        return ret;
    if (t) {
        int64_t pts = r->frame->best_effort_timestamp;
        *t = pts == AV_NOPTS_VALUE ? NAN
                                   : pts * av_q2d(r->fmt->streams[r->stream]->time_base);
    }
    ret = convert(r, img);
    av_frame_unref(r->frame);
    if (r->aframe)
        av_frame_unref(r->aframe);
    return ret;
}

int sp_video_decodes_alone(const char *path, const volatile sig_atomic_t *cancel)
{
    char *const was = held, dropped[512] = "";
    const size_t was_size = held_size;
    struct sp_video_reader *r = NULL;
    sp_video_hold_errors(dropped, sizeof(dropped)); /* what it says is not said */
    av_quiet = 1;
    int ret = reader_open(&r, path, 1);
    while (ret == 0 && !(cancel && *cancel)) { /* 0: on; 1: at the end */
        ret = next_frame(r);
        av_frame_unref(r->frame);
        ret = ret == 1 ? 0 : ret == 0 ? 1 : ret;
    }
    sp_video_reader_destroy(&r);
    av_quiet = 0;
    sp_video_hold_errors(was, was_size);
    return ret == 0 ? SP_E_INTERRUPTED : ret;
}

/* 1 when packets and bytes, read from stream s of fmt, reach the frames
 * and bytes its index lists (where it lists them: MP4's sample tables);
 * else 0, why in why. */
static int index_reached(const AVFormatContext *fmt, int s, int64_t packets, int64_t bytes,
                         char *why, size_t size)
{
    AVStream *st = fmt->streams[s];
    const int n = avformat_index_get_entries_count(st);
    int64_t listed = 0;
    for (int i = 0; i < n; i++)
        listed += avformat_index_get_entry(st, i)->size;
    if (st->nb_frames > 0 && packets < st->nb_frames) {
        snprintf(why, size, "it holds %lld of the %lld frames its index lists", (long long)packets,
                 (long long)st->nb_frames);
        return 0;
    }
    if (n > 0 && n == st->nb_frames && bytes < listed) {
        snprintf(why, size, "its frames hold %lld bytes of the %lld its index lists",
                 (long long)bytes, (long long)listed);
        return 0;
    }
    return 1;
}

int sp_video_demuxes_whole(const char *path, char *why, size_t size)
{
    AVFormatContext *fmt = NULL;
    AVPacket *pkt = av_packet_alloc();
    int64_t packets = 0, bytes = 0;
    int ret = pkt ? 0 : SP_E_NOMEM, s = -1;
    pthread_once(&log_once, log_through_lines);
    av_quiet = 1;
    if (!ret && (ret = open_checked(&fmt, path, NULL)) == 0)
        ret = (s = av_find_best_stream(fmt, AVMEDIA_TYPE_VIDEO, -1, -1, NULL, 0)) < 0
                  ? SP_E_INPUT : 1;
    while (ret == 1) {
        const int got = av_read_frame(fmt, pkt);
        if (got == AVERROR_EOF)
            break;
        if (got == AVERROR(ENOMEM))
            ret = SP_E_NOMEM;
        else if (got < 0)
            snprintf(why, size, "its container is damaged (%s)", av_err2str(got)), ret = 0;
        else if (pkt->stream_index == s && (pkt->flags & AV_PKT_FLAG_CORRUPT))
            snprintf(why, size, "its frame %lld is cut or corrupt", (long long)packets), ret = 0;
        else if (pkt->stream_index == s)
            packets++, bytes += pkt->size;
        av_packet_unref(pkt);
    }
    if (ret == 1)
        ret = index_reached(fmt, s, packets, bytes, why, size);
    av_quiet = 0;
    avformat_close_input(&fmt);
    av_packet_free(&pkt);
    return ret;
}

void sp_video_reader_destroy(struct sp_video_reader **rp)
{
    struct sp_video_reader *r = *rp;
    if (!r)
        return;
    sws_freeContext(r->sws);
    sp_image_free(&r->rgba);
    av_frame_free(&r->frame);
    av_packet_free(&r->pkt);
    av_frame_free(&r->aframe);
    av_packet_free(&r->apkt);
    avcodec_free_context(&r->alpha);
    avcodec_free_context(&r->dec);
    avformat_close_input(&r->fmt);
    free(r->path);
    free(r);
    *rp = NULL;
}

int sp_video_frame_size(const char *path, int *width, int *height, int *alpha)
{
    AVFormatContext *fmt = NULL;
    struct stat st;
    char name[32];
    const char *why;
    int fd = sp_infile_try(path, &why), ret = SP_E_INPUT; /* a regular file only */
    *width = *height = *alpha = 0;
    if (fd < 0)
        return SP_E_INPUT;
    if (fstat(fd, &st) == 0 &&
        metadata_bounded(fd, NULL, 0, st.st_size, 0) == 0) {
        snprintf(name, sizeof(name), "/proc/self/fd/%d", fd);
        pthread_once(&log_once, log_through_lines);
        av_quiet = 1; /* nothing logged: FFmpeg's lines neither */
        if (open_video(&fmt, name, fd, path, 0) == 0) {
            /* the headers only: no frame is decoded; a size the reader
             * refuses unread counts for nothing (attack8 #6) */
            int w, h;
            enum AVCodecID id;
            if (!header_check(fmt, &w, &h, &id) && w > 0)
                *width = w, *height = h, ret = 0;
            int mode = -1;
            if (!ret && id == AV_CODEC_ID_VP9 && !strcmp(fmt->iformat->name, "matroska,webm"))
                mkv_alpha_mode(fd, 0, st.st_size, 0, 0, &mode);
            *alpha = mode > 0;
            avformat_close_input(&fmt);
        }
        av_quiet = 0;
    }
    close(fd);
    return ret;
}

int sp_video_read_text(const char *path, const char *key, char *buf, size_t size)
{
    AVFormatContext *fmt = NULL;
    const AVDictionaryEntry *e;
    int found = 0;
    if (open_checked(&fmt, path, NULL))
        return SP_E_INPUT;
    if ((e = av_dict_get(fmt->metadata, key, NULL, 0)) != NULL) {
        found = 1;
        if (av_dict_get(fmt->metadata, key, e, 0)) {
            sp_log_error("%s: the tag %s is there twice; springpend writes it once", path, key);
            found = SP_E_INPUT;
        } else if (strlen(e->value) >= size) {
            sp_log_error("%s: the tag %s holds %zu bytes; at most %zu are read", path, key,
                         strlen(e->value), size - 1);
            found = SP_E_INPUT;
        } else {
            memcpy(buf, e->value, strlen(e->value) + 1);
        }
    }
    avformat_close_input(&fmt);
    return found;
}
