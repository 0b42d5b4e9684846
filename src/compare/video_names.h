/* springpend (internal): the names compare reads as videos, by their
 * ending (case aside). One table for both readers of a name: the folder
 * walk (snapshot_list.c), which compares a file under EXPECTED when its
 * name ends so, and the video reader (video_read.c), which checks that the
 * format FFmpeg finds is the one the name says; and for compare.ini's
 * environment keys (compare_config.c), none of which may be an ending.
 * A name read as a video alone is never left out of a folder silently
 * (attack17 #8).
 * Private to src/compare (the executable and springpend-av.so both). */
#ifndef SPRINGPEND_VIDEO_NAMES_H
#define SPRINGPEND_VIDEO_NAMES_H

/* An ending, the formats of SP_VIDEO_FORMATS (video_read.c: FFmpeg's
 * demuxer names) that a file of that name may hold, and what to call them.
 * A raw H.264 stream named .mp4, an MKV named .mp4, an MP4 named .gif are
 * not what their names say: refused (attack10 #7). */
struct sp_video_name {
    const char *ending, *formats, *said;
};

static const struct sp_video_name sp_video_names[] = {
    {".mp4", "mov,mp4", "MP4"},      {".m4v", "mov,mp4", "MP4"},
    {".mov", "mov,mp4", "MOV"},      {".webm", "matroska,webm", "WebM"},
    {".mkv", "matroska,webm", "Matroska"}, {".gif", "gif", "GIF"},
    {".h264", "h264", "a raw H.264 stream"}, {".264", "h264", "a raw H.264 stream"},
    {".hevc", "hevc", "a raw HEVC stream"},  {".h265", "hevc", "a raw HEVC stream"},
    {".265", "hevc", "a raw HEVC stream"},
};
#define SP_VIDEO_NAMES_COUNT ((int)(sizeof(sp_video_names) / sizeof(sp_video_names[0])))

/* The same list in words, for messages (keep it the table's). */
#define SP_VIDEO_NAMES_SAID                                                                  \
    "compare reads .mp4, .m4v and .mov files as MP4/MOV, .webm and .mkv as WebM/Matroska, "  \
    ".gif as GIF, .h264 and .264 as raw H.264, .hevc, .h265 and .265 as raw HEVC"

#endif
