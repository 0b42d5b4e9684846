/* springpend: PNG files through libpng. Writing uses the full API (so we
 * choose the filter, zlib level and text chunks), and so does reading, which
 * converts any PNG to RGBA8 by value after checking its size. */
#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <png.h>
#include <lcms2.h>
#include <stdlib.h>
#include <stdint.h>
#include <string.h>
#include <pthread.h>
#include <zlib.h>

#include "springpend/common.h"
#include "springpend/outfile.h"
#include "springpend/infile.h"
#include "springpend/png_io.h"

/* Rows are filtered with UP alone: one fixed filter skips libpng's per-row
 * trial of every candidate (2.6x faster than PNG_ALL_FILTERS at 1080p), and
 * on rendered frames (flat background, thin curves) UP gave smaller files
 * than SUB or NONE at the same speed. */

/* libpng's error callback: error_ptr is the destination's name. Logs and
 * jumps back to the setjmp in the writer; never returns. */
static void on_png_error(png_structp png, png_const_charp msg)
{
    if (sp_outfile_write_was_stopped())
        png_longjmp(png, 1); /* a signal: the command names it */
    sp_log_error("%s: libpng: %s", (const char *)png_get_error_ptr(png), msg);
    png_longjmp(png, 1);
}

/* libpng's write callback: stdio, with the OS's reason on failure (e.g.
 * "No space left on device"); jumps back like on_png_error. */
static void on_png_write(png_structp png, png_bytep data, size_t n)
{
    if (fwrite(data, 1, n, (FILE *)png_get_io_ptr(png)) != n) {
        if (sp_outfile_write_was_stopped())
            png_longjmp(png, 1); /* a signal: the command names it */
        sp_log_error("%s: cannot write: %s", (const char *)png_get_error_ptr(png),
                     strerror(errno));
        png_longjmp(png, 1);
    }
}

/* The same for readers, in the words compare's users know. */
/* Text chunks are inflated (zTXt, iTXt) up to this many bytes each, and
 * at most this many ancillary chunks are kept, so that a small file cannot
 * cost gigabytes: text read in total stays under 32 x 256 KiB = 8 MiB.
 * springpend's own largest text, the canonical scene, is a few KiB. */
#define TEXT_CHUNK_MAX (256 * 1024)
#define TEXT_CHUNKS_MAX 32

/* The reader's state, behind a pointer so that what is set after setjmp
 * survives the longjmp; libpng's error pointer. */
struct png_reader {
    const char *path;
    FILE *fp;
    png_structp png;
    png_infop info;
    png_bytep *rows;
    int nomem;        /* an allocation failed: the error that follows is memory's */
    int text_dropped; /* text chunks libpng dropped: damaged or beyond the bounds */
    char text_why[128]; /* libpng's words for the first one dropped */
    char iccp_why[128]; /* libpng's words when it dropped an iCCP (a profile unread) */
    char exif_why[128]; /* libpng's words when it dropped an eXIf (an orientation unread) */
    char lost_why[128]; /* libpng's words when the chunk cache filled: a chunk kept unread */
    png_bytep icc;      /* an iCCP's profile, inflated (iccp_inflate) */
};

/* A damaged PNG is logged; an error after a failed allocation is not: the
 * reader returns SP_E_NOMEM, which its caller says (png_io.h). */
static void on_png_read_error(png_structp png, png_const_charp msg)
{
    const struct png_reader *r = png_get_error_ptr(png);
    if (!r->nomem)
        sp_log_error("%s: cannot read PNG: libpng: %s", r->path, msg);
    png_longjmp(png, 1);
}

/* libpng's allocator for the reader: malloc, noting a failure in the
 * reader, so that the error libpng raises for it is told from a damaged
 * file (libpng's messages are its only other sign). */
static png_voidp reader_malloc(png_structp png, png_alloc_size_t size)
{
    void *p = malloc(size);
    if (!p) {
        struct png_reader *r = png_get_mem_ptr(png);
        r->nomem = 1;
    }
    return p;
}

static void reader_free(png_structp png, png_voidp p)
{
    (void)png;
    free(p);
}

/* Text chunks dropped for their size or number are counted, and said once
 * (reader_close); other warnings are passed on, but those after a failed
 * allocation (out of memory is the caller's to say, once). */
static void on_png_read_warning(png_structp png, png_const_charp msg)
{
    struct png_reader *r = png_get_error_ptr(png);
    if (!strncmp(msg, "tEXt", 4) || !strncmp(msg, "zTXt", 4) || !strncmp(msg, "iTXt", 4)) {
        if (!r->text_dropped++)
            snprintf(r->text_why, sizeof(r->text_why), "%s", msg);
    } else if (strstr(msg, "o space in chunk cache")) {
        /* the chunks kept (reader_setup: iCCP, sRGB, cICP...) and sPLT
         * share a bound; past it libpng drops the rest unsaid, so that
         * shown_as_read would not see what viewers apply */
        if (!r->lost_why[0])
            snprintf(r->lost_why, sizeof(r->lost_why), "%s", msg);
    } else if (!strncmp(msg, "iCCP", 4) && !r->iccp_why[0]) {
        /* a profile libpng did not take (too large, malformed, a second one):
         * viewers may still apply it, so shown_as_read refuses the file */
        snprintf(r->iccp_why, sizeof(r->iccp_why), "%s", msg);
    } else if (!strncmp(msg, "eXIf", 4)) {
        /* one libpng did not take (malformed, a second one): viewers may
         * still turn the image by it, so exif_refused refuses the file */
        if (!r->exif_why[0])
            snprintf(r->exif_why, sizeof(r->exif_why), "%s", msg);
    }
    else if (!r->nomem) /* after a failed allocation: the caller's to say */
        sp_log_error("%s: libpng warning: %s", r->path, msg);
}

static void on_png_flush(png_structp png)
{
    fflush((FILE *)png_get_io_ptr(png));
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    sp_log_error("%s: libpng warning: %s", (const char *)png_get_error_ptr(png),
                 msg);
}

/* 1 when text is ASCII only (Latin-1 and UTF-8 read it alike). */
static int is_ascii(const char *text)
{
    for (const unsigned char *p = (const unsigned char *)text; *p; p++)
        if (*p >= 0x80)
            return 0;
    return 1;
}

static int check_write_args(const struct sp_image *img,
                            const struct sp_png_write_opts *opts,
                            const char *what)
{
    if (!img->pixels || img->width <= 0 || img->height <= 0 ||
        img->stride < 4 * img->width) {
        sp_log_error("%s: cannot write a %dx%d image with stride %d", what,
                     img->width, img->height, img->stride);
        return SP_E_INPUT;
    }
    if (opts->level < 0 || opts->level > 9) {
        sp_log_error("%s: PNG compression level %d is not in 0..9", what,
                     opts->level);
        return SP_E_INPUT;
    }
    if (opts->n_text < 0 || (opts->n_text > 0 && !opts->text)) {
        sp_log_error("%s: %d text chunks but no array", what, opts->n_text);
        return SP_E_INPUT;
    }
    for (int i = 0; i < opts->n_text; i++) {
        size_t len = opts->text[i].key ? strlen(opts->text[i].key) : 0;
        if (len < 1 || len > 79 || !opts->text[i].text) {
            sp_log_error("%s: PNG text key \"%s\" must have 1 to 79 characters "
                         "and a text", what,
                         opts->text[i].key ? opts->text[i].key : "(null)");
            return SP_E_INPUT;
        }
    }
    return 0;
}

int sp_png_write_stream_opts(FILE *fp, const struct sp_image *img,
                             const struct sp_png_write_opts *opts,
                             const char *what)
{
    /* Owned here, released at `done`. Set before setjmp and never changed
     * after, so they survive the longjmp without volatile. */
    png_structp png = NULL;
    png_infop info = NULL;
    int err = check_write_args(img, opts, what);
    if (err)
        return err;

    png = png_create_write_struct(PNG_LIBPNG_VER_STRING, (png_voidp)what,
                                  on_png_error, on_png_warning);
    if (png)
        info = png_create_info_struct(png);
    if (!png || !info) {
        sp_log_error("%s: out of memory for the PNG writer", what);
        err = SP_E_NOMEM;
        goto done;
    }
    if (setjmp(png_jmpbuf(png))) {
        /* on_png_error has logged, or a signal stopped a write */
        err = sp_outfile_write_was_stopped() ? SP_E_INTERRUPTED : SP_E_IO;
        goto done;
    }

    png_set_write_fn(png, fp, on_png_write, on_png_flush);
    png_set_compression_level(png, opts->level);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
    png_set_IHDR(png, info, (png_uint_32)img->width, (png_uint_32)img->height,
                 8, opts->opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA,
                 PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (opts->dpi > 0)
        png_set_pHYs(png, info, (png_uint_32)lround(opts->dpi / 0.0254),
                     (png_uint_32)lround(opts->dpi / 0.0254), PNG_RESOLUTION_METER);
    for (int i = 0; i < opts->n_text; i++) {
        /* libpng copies key and text into info. tEXt and zTXt are Latin-1
         * by the PNG specification: text beyond ASCII (UTF-8: a title's
         * "é") goes into iTXt, the chunk for UTF-8, compressed the same. */
        const int utf8 = !is_ascii(opts->text[i].text), z = opts->text[i].compressed;
        png_text t = {
            .compression = utf8 ? (z ? PNG_ITXT_COMPRESSION_zTXt : PNG_ITXT_COMPRESSION_NONE)
                                : (z ? PNG_TEXT_COMPRESSION_zTXt : PNG_TEXT_COMPRESSION_NONE),
            .key = (png_charp)opts->text[i].key,
            .text = (png_charp)opts->text[i].text,
        };
        png_set_text(png, info, &t, 1);
    }
    png_write_info(png, info);
    if (opts->opaque) /* rows stay RGBA in memory; libpng drops the A */
        png_set_filler(png, 0, PNG_FILLER_AFTER);
    for (int y = 0; y < img->height; y++)
        png_write_row(png, img->pixels + (size_t)y * img->stride);
    png_write_end(png, NULL);

    if (fflush(fp) != 0 || ferror(fp)) {
        if (sp_outfile_write_was_stopped())
            err = SP_E_INTERRUPTED; /* a signal: the command names it */
        else
            sp_log_error("%s: cannot write: %s", what, strerror(errno)), err = SP_E_IO;
    }
done:
    png_destroy_write_struct(&png, &info);
    return err;
}

int sp_png_write_outfile(struct sp_outfile *f, const struct sp_image *img,
                         const struct sp_png_write_opts *opts)
{
    FILE *fp = sp_outfile_fdopen(f); /* f->fd is fp's now */
    if (!fp) {
        sp_log_error("%s: %s", f->target, strerror(errno));
        return SP_E_NOMEM;
    }
    int err = sp_png_write_stream_opts(fp, img, opts, f->target);
    if (fclose(fp) != 0 && !err) {
        if (sp_outfile_write_was_stopped())
            return SP_E_INTERRUPTED; /* a signal: the command names it */
        sp_log_error("%s: cannot write: %s", f->target, strerror(errno));
        err = SP_E_IO;
    }
    return err;
}

int sp_png_write_opts(const char *path, const struct sp_image *img,
                      const struct sp_png_write_opts *opts)
{
    struct sp_outfile f;
    int err = check_write_args(img, opts, path); /* before creating it */
    if (err || (err = sp_outfile_open(&f, path, SP_OUTFILE_STREAM)) != 0)
        return err;
    if ((err = sp_png_write_outfile(&f, img, opts)) != 0) {
        sp_outfile_discard(&f);
        return err;
    }
    return sp_outfile_commit(&f);
}

int sp_png_write_stream(FILE *fp, const struct sp_image *img, int level,
                        const char *what)
{
    return sp_png_write_stream_opts(
        fp, img, &(struct sp_png_write_opts){ .level = level }, what);
}

int sp_png_write(const char *path, const struct sp_image *img, int level)
{
    return sp_png_write_opts(path, img,
                             &(struct sp_png_write_opts){ .level = level });
}

/* Opens path for reading if it is a regular file: a FIFO or a device
 * named *.png must not hang or flood the reader (infile.h). */
static FILE *open_regular(const char *path, int *err)
{
    int fd = sp_infile_open(path, "a PNG must be a file");
    FILE *fp = fd < 0 ? NULL : fdopen(fd, "rb");
    if (fd < 0) {
        *err = fd;
    } else if (!fp) {
        if (errno != ENOMEM) /* out of memory is the caller's to say */
            sp_log_error("%s: cannot open: %s", path, strerror(errno));
        close(fd);
        *err = SP_E_NOMEM;
    }
    return fp;
}

/* 1 the first time in this process that dropped text chunks of the file
 * open as fp are said, 0 after: compare reads a PNG's text once per key
 * (the scene, the environment, the fonts...), and said it once per read,
 * counting one chunk as many ("2 text chunks not read" where `scene` said
 * 1). Files are told apart by device and inode; past TOLD_MAX of them,
 * each read says it again. Thread-safe. */
#define TOLD_MAX 256
static int first_told(FILE *fp)
{
    static struct {
        dev_t dev;
        ino_t ino;
    } told[TOLD_MAX];
    static int n_told;
    static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
    struct stat st;
    int first = 1;
    if (fstat(fileno(fp), &st))
        return 1;
    pthread_mutex_lock(&lock);
    for (int i = 0; i < n_told && first; i++)
        first = !(told[i].dev == st.st_dev && told[i].ino == st.st_ino);
    if (first && n_told < TOLD_MAX)
        told[n_told].dev = st.st_dev, told[n_told++].ino = st.st_ino;
    pthread_mutex_unlock(&lock);
    return first;
}

static void reader_close(struct png_reader *r)
{
    if (r->text_dropped && r->nomem) /* not the file's fault */
        sp_log_error("%s: out of memory to read its text chunks: %d not read", r->path,
                     r->text_dropped);
    else if (r->text_dropped && r->fp && first_told(r->fp))
        sp_log_error("%s: %d text chunk%s not read (libpng: %s); a text chunk is read when "
                     "it is whole (its CRC and zlib stream), at most %d KiB inflated, and "
                     "among the first %d", r->path, r->text_dropped,
                     r->text_dropped == 1 ? "" : "s", r->text_why, TEXT_CHUNK_MAX / 1024,
                     TEXT_CHUNKS_MAX);
    if (r->png && r->icc)
        png_free(r->png, r->icc);
    png_destroy_read_struct(&r->png, &r->info, NULL);
    free(r->rows);
    if (r->fp)
        fclose(r->fp);
}

/* Opens path and makes the libpng reader; calls no libpng function that
 * can fail (they would abort the process with no setjmp armed): the caller
 * arms its setjmp next, then calls reader_setup. SP_E_NOMEM (unsaid) when
 * memory runs out. */
static int reader_open(struct png_reader *r, const char *path)
{
    int err = 0;
    memset(r, 0, sizeof(*r));
    r->path = path;
    if (!(r->fp = open_regular(path, &err)))
        return err;
    r->png = png_create_read_struct_2(PNG_LIBPNG_VER_STRING, r, on_png_read_error,
                                      on_png_read_warning, r, reader_malloc, reader_free);
    if (r->png)
        r->info = png_create_info_struct(r->png);
    if (!r->png || !r->info) {
        reader_close(r);
        return SP_E_NOMEM;
    }
    return 0;
}

/* The reader's settings, under the caller's setjmp (png_set_keep_unknown_-
 * chunks allocates, and libpng raises an error when that fails). with_text
 * = 0 skips the text chunks unread (pixels need none); else they are read
 * within the bounds above (libpng warns of what it drops). */
static void reader_setup(struct png_reader *r, int with_text)
{
    png_init_io(r->png, r->fp);
    if (!with_text) {
        static const png_byte text_chunks[] = "tEXt\0zTXt\0iTXt";
        png_set_keep_unknown_chunks(r->png, PNG_HANDLE_CHUNK_NEVER, text_chunks, 3);
    }
    /* an APNG's animation control chunk and PNG's third edition's colour
     * chunks (cICP: coding-independent code points; mDCv, cLLi: HDR
     * mastering metadata), which libpng 1.6.39 does not know: kept (a few
     * bytes each), so that shown_as_read sees them */
    /* Where the pixels are read (with_text = 0), the iCCP and sRGB chunks
     * too, each as it stands in the file: libpng's own reading takes an
     * sRGB after an iCCP as its verdict on the profile, drops an iCCP
     * after an sRGB, and forgets an iCCP whose neighbours (a second sRGB,
     * a gAMA out of range, a second cHRM) it finds inconsistent, while
     * viewers convert by the profile (attack16 #2): iccp_refused judges
     * every profile itself. gAMA and cHRM too: libpng forgets one written
     * twice or after a palette, and its neighbours, where Chromium draws
     * by the first (attack18 #1): colour_chunks_refused, chrm_refused and
     * gama_refused read them as they stand. */
    static const png_byte kept[] = "acTL\0cICP\0mDCv\0cLLi\0iCCP\0sRGB\0gAMA\0cHRM";
    png_set_keep_unknown_chunks(r->png, PNG_HANDLE_CHUNK_ALWAYS, kept, with_text ? 4 : 8);
    png_set_chunk_malloc_max(r->png, TEXT_CHUNK_MAX);
    png_set_chunk_cache_max(r->png, TEXT_CHUNKS_MAX);
}

/* A colour-managed viewer converts a PNG's pixels by its ICC profile to
 * the screen's colours; on an sRGB screen it shows them as read when that
 * conversion moves no colour by more than this many levels of 255 (the
 * ICC's own sRGB profiles and lcms's, GIMP's built-in one, differ from
 * each other by at most 1). */
#define ICC_SRGB_LEVELS 2

static void lcms_quiet(cmsContext ctx, cmsUInt32Number code, const char *text)
{
    (void)ctx, (void)code, (void)text; /* a profile lcms cannot use is said by the caller */
}

/* The most levels (of 255) by which the ICC profile prof (len bytes), of
 * a gray (gray != 0) or colour PNG, moves a colour when converted to sRGB
 * (lcms2, perceptual and relative colorimetric intents, 8-bit greys and a
 * 18x18x18 grid of colours: every 15th level); 256 when lcms cannot use
 * it (damaged, of another colour space, or memory short). */
static int icc_srgb_distance(const void *prof, png_uint_32 len, int gray)
{
    /* a grid of every 15th level, and every level along each channel and
     * the grey ramp (attack14 #3: a tone curve that is sRGB's on the grid
     * and not between its points was taken) */
    enum { STEP = 15, N = 256 / STEP + 1, RAMPS = 4 * 256 };
    static unsigned char in[(N * N * N + RAMPS) * 3], out[(N * N * N + RAMPS) * 3];
    static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
    int worst = 256;
    cmsContext ctx = cmsCreateContext(NULL, NULL);
    if (!ctx)
        return worst;
    cmsSetLogErrorHandlerTHR(ctx, lcms_quiet);
    cmsHPROFILE from = cmsOpenProfileFromMemTHR(ctx, prof, len);
    cmsHPROFILE srgb = cmsCreate_sRGBProfileTHR(ctx);
    const cmsColorSpaceSignature want = gray ? cmsSigGrayData : cmsSigRgbData;
    pthread_mutex_lock(&lock); /* the buffers are shared: readers run in threads */
    if (from && srgb && cmsGetColorSpace(from) == want) {
        size_t n = 0;
        if (gray)
            for (int v = 0; v < 256; v++)
                in[n++] = (unsigned char)v;
        else
            for (int r = 0; r < N; r++)
                for (int g = 0; g < N; g++)
                    for (int b = 0; b < N; b++, n++) {
                        in[3 * n] = (unsigned char)(r * STEP);
                        in[3 * n + 1] = (unsigned char)(g * STEP);
                        in[3 * n + 2] = (unsigned char)(b * STEP);
                    }
        for (int ramp = 0; !gray && ramp < 4; ramp++) /* red, green, blue, grey */
            for (int v = 0; v < 256; v++, n++)
                for (int c = 0; c < 3; c++)
                    in[3 * n + c] = (unsigned char)(ramp == 3 || ramp == c ? v : 0);
        static const cmsUInt32Number intents[] = {INTENT_PERCEPTUAL,
                                                  INTENT_RELATIVE_COLORIMETRIC};
        worst = 0;
        for (int k = 0; k < 2 && worst < 256; k++) {
            cmsHTRANSFORM t = cmsCreateTransformTHR(ctx, from, gray ? TYPE_GRAY_8 : TYPE_RGB_8,
                                                    srgb, TYPE_RGB_8, intents[k],
                                                    cmsFLAGS_NOOPTIMIZE | cmsFLAGS_NOCACHE);
            if (!t) {
                worst = 256;
                break;
            }
            cmsDoTransform(t, in, out, (cmsUInt32Number)n);
            cmsDeleteTransform(t);
            for (size_t i = 0; i < 3 * n; i++) {
                const int d = abs((int)out[i] - (int)in[gray ? i / 3 : i]);
                worst = d > worst ? d : worst;
            }
        }
    }
    pthread_mutex_unlock(&lock);
    if (from)
        cmsCloseProfile(from);
    if (srgb)
        cmsCloseProfile(srgb);
    cmsDeleteContext(ctx);
    return worst;
}

/* sRGB's encoding (IEC 61966-2-1) of linear light lin. */
static double srgb_encoded(double lin)
{
    return lin <= 0.0031308 ? 12.92 * lin : 1.055 * pow(lin, 1 / 2.4) - 0.055;
}

/* The most levels (of 255) by which profile p's tone curve tag sig moves a
 * value from sRGB's, over every 16-bit value (PNG's deepest samples; a
 * table's entries between 8-bit levels count too); 256 when it has none. */
static double trc_distance(cmsHPROFILE p, cmsTagSignature sig)
{
    const cmsToneCurve *curve = cmsReadTag(p, sig);
    double worst = 0;
    if (!curve)
        return 256;
    for (int v = 0; v < 65536; v++) {
        const double x = v / 65535.0;
        const double d = fabs(srgb_encoded(cmsEvalToneCurveFloat(curve, (cmsFloat32Number)x)) - x);
        if (!(d * 255 < 256)) /* NaN too */
            return 256;
        worst = d * 255 > worst ? d * 255 : worst;
    }
    return worst;
}

/* Opens the ICC profile prof (len bytes) in a context of its own (*ctx)
 * when it is of a gray (gray != 0) or colour PNG's colour space; NULL
 * when it is not, or lcms cannot read it (icc_srgb_distance says so). */
static cmsHPROFILE icc_open(cmsContext *ctx, const void *prof, png_uint_32 len, int gray)
{
    cmsHPROFILE p = NULL;
    if (!(*ctx = cmsCreateContext(NULL, NULL)))
        return NULL;
    cmsSetLogErrorHandlerTHR(*ctx, lcms_quiet);
    p = cmsOpenProfileFromMemTHR(*ctx, prof, len);
    if (p && cmsGetColorSpace(p) != (gray ? cmsSigGrayData : cmsSigRgbData)) {
        cmsCloseProfile(p);
        p = NULL;
    }
    if (!p)
        cmsDeleteContext(*ctx);
    return p;
}

static void icc_close(cmsContext ctx, cmsHPROFILE p)
{
    cmsCloseProfile(p);
    cmsDeleteContext(ctx);
}

/* NULL when the ICC profile prof (len bytes) of a gray (gray != 0) or
 * colour PNG is converted by its matrix and tone curves alone (lcms2's
 * cmsIsMatrixShaper; for gray, its curve); else what is wrong, in buf. A
 * table (A2B0..2, B2A0..2, D2B0..3, B2D0..3) or a cicp tag is what colour
 * managers convert by in preference (Chromium's skcms does by A2B0): a
 * table exact on any fixed sample set and inverting the colours between
 * them was taken (attack15 #11). NULL too for a profile lcms cannot read
 * or of another colour space: icc_srgb_distance says so. */
static const char *icc_structure_refused(const void *prof, png_uint_32 len, int gray, char *buf,
                                         size_t size)
{
    static const cmsTagSignature preferred[] = {
        cmsSigAToB0Tag, cmsSigAToB1Tag, cmsSigAToB2Tag, cmsSigBToA0Tag, cmsSigBToA1Tag,
        cmsSigBToA2Tag, cmsSigDToB0Tag, cmsSigDToB1Tag, cmsSigDToB2Tag, cmsSigDToB3Tag,
        cmsSigBToD0Tag, cmsSigBToD1Tag, cmsSigBToD2Tag, cmsSigBToD3Tag,
        (cmsTagSignature)0x63696370 /* cicp */};
    const char *what = NULL;
    cmsContext ctx;
    cmsHPROFILE p = icc_open(&ctx, prof, len, gray);
    if (!p)
        return NULL;
    for (size_t i = 0; !what && i < sizeof(preferred) / sizeof(preferred[0]); i++) {
        const unsigned t = (unsigned)preferred[i];
        if (cmsIsTag(p, preferred[i]))
            snprintf(buf, size, "holds an ICC colour profile (iCCP) with %s %c%c%c%c %s, which "
                     "colour managers use instead of its matrix and curves (Chromium does); "
                     "compare takes only sRGB's matrix and curves: save its pixels in sRGB, "
                     "without the iCCP chunk", t == 0x63696370 ? "a" : "an", t >> 24,
                     t >> 16 & 0xff, t >> 8 & 0xff, t & 0xff,
                     t == 0x63696370 ? "tag (coding-independent code points)" : "table"),
                what = buf;
    }
    if (!what && !cmsIsMatrixShaper(p))
        snprintf(buf, size, "holds an ICC colour profile (iCCP) that is not a matrix and curves "
                 "(%s); compare takes only sRGB's matrix and curves: save its pixels in sRGB, "
                 "without the iCCP chunk", gray ? "kTRC" : "rXYZ gXYZ bXYZ, rTRC gTRC bTRC"),
            what = buf;
    icc_close(ctx, p);
    return what;
}

/* NULL when the tone curves of the matrix/TRC profile prof (len bytes;
 * icc_structure_refused took it) are sRGB's to within ICC_SRGB_LEVELS at
 * every 16-bit value, between the 8-bit levels icc_srgb_distance samples
 * too (a 16-bit PNG's samples are there); else what is wrong, in buf. */
static const char *icc_curves_refused(const void *prof, png_uint_32 len, int gray, char *buf,
                                      size_t size)
{
    static const cmsTagSignature trcs[] = {cmsSigRedTRCTag, cmsSigGreenTRCTag, cmsSigBlueTRCTag};
    const char *what = NULL;
    cmsContext ctx;
    cmsHPROFILE p = icc_open(&ctx, prof, len, gray);
    if (!p)
        return NULL;
    for (int c = 0; !what && c < (gray ? 1 : 3); c++) {
        const double d = trc_distance(p, gray ? cmsSigGrayTRCTag : trcs[c]);
        if (d > ICC_SRGB_LEVELS)
            snprintf(buf, size, "holds an ICC colour profile (iCCP) other than sRGB, whose %s "
                     "tone curve moves a 16-bit value by %s%.0f levels of 255 (sRGB's moves none "
                     "by more than %d), by which viewers convert its colours; save its pixels "
                     "converted to sRGB, without the iCCP chunk", gray ? "gray" : c == 0 ? "red"
                     : c == 1 ? "green" : "blue", d > 255 ? "over " : "up to ",
                     d > 255 ? 255 : d, ICC_SRGB_LEVELS), what = buf;
    }
    icc_close(ctx, p);
    return what;
}

/* An iCCP's profile inflated is read up to this many bytes (libpng's own
 * bound for it here, png_set_chunk_malloc_max). */
#define ICC_MAX TEXT_CHUNK_MAX

/* The profile of the iCCP chunk c (a name of 1 to 79 bytes, a NUL, the
 * compression method 0 and a zlib stream), inflated into r->icc: its
 * length in *len; NULL when the chunk is not whole, with why (the rules
 * libpng kept it by: the profile at most ICC_MAX bytes, its header's
 * length the bytes inflated, at least a header and a tag count). */
static const png_byte *iccp_inflate(struct png_reader *r, const png_unknown_chunk *c,
                                    png_uint_32 *len, const char **why)
{
    size_t k = 0;
    while (k < c->size && k < 80 && c->data[k])
        k++;
    if (k == 0 || k >= 80 || k + 2 > c->size) {
        *why = "its name is not 1 to 79 bytes ended by a NUL";
        return NULL;
    }
    if (c->data[k + 1] != 0) {
        *why = "its compression method is not 0 (zlib)";
        return NULL;
    }
    if (!r->icc)
        r->icc = png_malloc(r->png, ICC_MAX + 1); /* out of memory: libpng's error */
    z_stream z = {.next_in = c->data + k + 2, .avail_in = (uInt)(c->size - k - 2),
                  .next_out = r->icc, .avail_out = ICC_MAX + 1};
    if (inflateInit(&z) != Z_OK) {
        r->nomem = 1;
        png_error(r->png, "out of memory"); /* zlib's only failure here */
    }
    const int end = inflate(&z, Z_FINISH) == Z_STREAM_END;
    const size_t n = ICC_MAX + 1 - z.avail_out;
    inflateEnd(&z);
    const png_byte *p = r->icc;
    if (!end)
        *why = n > ICC_MAX ? "its profile inflates to more than 256 KiB"
                           : "its zlib stream is damaged or cut short";
    else if (n < 132 || ((size_t)p[0] << 24 | (size_t)p[1] << 16 | (size_t)p[2] << 8 | p[3]) != n)
        *why = "its profile's length (its first 4 bytes) is not the bytes inflated, 132 or more";
    else
        *len = (png_uint_32)n, *why = NULL;
    return *why ? NULL : p;
}

/* NULL when the ICC profile prof (len bytes) of r's PNG shows its pixels
 * as read on an sRGB screen: a matrix/TRC profile that lcms2 converts
 * every colour by to within ICC_SRGB_LEVELS, by curves sRGB's at every
 * 16-bit value; else what is wrong, in buf. */
static const char *iccp_judged(struct png_reader *r, const png_byte *prof, png_uint_32 len,
                               char *buf, size_t size)
{
    const int gray = !(png_get_color_type(r->png, r->info) & PNG_COLOR_MASK_COLOR);
    const char *structure = icc_structure_refused(prof, len, gray, buf, size);
    if (structure)
        return structure;
    const int d = icc_srgb_distance(prof, len, gray);
    if (d <= ICC_SRGB_LEVELS)
        return icc_curves_refused(prof, len, gray, buf, size);
    if (d > 255)
        snprintf(buf, size, "holds an ICC colour profile (iCCP) that is not a usable %s "
                 "profile, by which viewers may still convert its colours; save it without "
                 "the iCCP chunk, its pixels in sRGB", gray ? "gray" : "RGB");
    else
        snprintf(buf, size, "holds an ICC colour profile (iCCP) other than sRGB, by which "
                 "viewers convert its colours (by up to %d levels of 255; sRGB's moves none "
                 "by more than %d); save its pixels converted to sRGB, without the iCCP "
                 "chunk", d, ICC_SRGB_LEVELS);
    return buf;
}

/* NULL when the PNG has no ICC profile (iCCP) before its pixels, or one
 * that shows its pixels as read on an sRGB screen (iccp_judged takes its
 * content: the ICC's own sRGB profiles are judged too, as libpng's test
 * for them binds only checksums and a length a forger sets, attack18
 * #4), whatever sRGB chunk stands before or after it (viewers convert by
 * the profile); else what is wrong, in buf: a profile libpng dropped
 * unread, more than one, one after the palette, one not whole. reader_setup keeps iCCP chunks unread by
 * libpng. *present: 1 when the PNG has a profile. */
static const char *iccp_refused(struct png_reader *r, char *buf, size_t size, int *present)
{
    png_unknown_chunkp u;
    const png_unknown_chunk *c = NULL;
    const int n = png_get_unknown_chunks(r->png, r->info, &u);
    int count = 0;
    png_uint_32 len = 0;
    const char *why = NULL;
    for (int i = 0; i < n; i++)
        if (!strcmp((const char *)u[i].name, "iCCP") && (c = c ? c : &u[i]))
            count++;
    *present = count > 0 || r->iccp_why[0];
    if (r->iccp_why[0])
        snprintf(buf, size, "holds an ICC colour profile (iCCP) that libpng does not read "
                 "(%s), by which viewers may still convert its colours; save it without the "
                 "iCCP chunk, its pixels in sRGB", r->iccp_why);
    else if (count > 1)
        snprintf(buf, size, "holds %d ICC colour profiles (iCCP chunks), where PNG allows one "
                 "and viewers convert its colours by one or another; save it with its pixels "
                 "in sRGB, without the iCCP chunks", count);
    else if (c && (c->location & (PNG_HAVE_PLTE | PNG_AFTER_IDAT)))
        snprintf(buf, size, "holds an ICC colour profile (iCCP) after its palette (PLTE), "
                 "where PNG allows none, by which viewers may still convert its colours; save "
                 "it without the iCCP chunk, its pixels in sRGB");
    else if (c && !iccp_inflate(r, c, &len, &why))
        snprintf(buf, size, "holds an ICC colour profile (iCCP) that is not whole (%s), by "
                 "which viewers may still convert its colours; save it without the iCCP chunk, "
                 "its pixels in sRGB", why);
    else
        return c ? iccp_judged(r, r->icc, len, buf, size) : NULL;
    return buf;
}

/* 1 when an sRGB chunk before the palette and the pixels says sRGB (one
 * byte: a rendering intent, 0 to 3), as libpng takes one; viewers then
 * convert by no gAMA or cHRM (but by an iCCP: iccp_refused). */
static int srgb_chunk(struct png_reader *r)
{
    png_unknown_chunkp u;
    const int n = png_get_unknown_chunks(r->png, r->info, &u);
    for (int i = 0; i < n; i++)
        if (!strcmp((const char *)u[i].name, "sRGB") && u[i].size == 1 && u[i].data[0] <= 3 &&
            !(u[i].location & (PNG_HAVE_PLTE | PNG_AFTER_IDAT)))
            return 1;
    return 0;
}

/* The first chunk named name that reader_setup kept unread by libpng;
 * NULL when there is none. */
static const png_unknown_chunk *kept_chunk(struct png_reader *r, const char *name)
{
    png_unknown_chunkp u;
    const int n = png_get_unknown_chunks(r->png, r->info, &u);
    for (int i = 0; i < n; i++)
        if (!strcmp((const char *)u[i].name, name))
            return &u[i];
    return NULL;
}

static unsigned long be32(const png_byte *d)
{
    return (unsigned long)d[0] << 24 | (unsigned long)d[1] << 16 | (unsigned long)d[2] << 8 | d[3];
}

/* The colour chunks, each of which PNG allows once, before the palette
 * (PLTE) and the pixels (IDAT), and what one holds. */
static const char *const colour_chunks[][2] = {
    {"gAMA", "gammas"}, {"cHRM", "sets of chromaticities"}, {"sRGB", "sRGB chunks"},
    {"iCCP", "ICC colour profiles"}, {"cICP", "sets of code points"}};

/* NULL when each colour chunk the PNG holds is there once, before its
 * palette and pixels; else what is wrong, in buf. libpng forgets a gAMA,
 * cHRM or sRGB written twice, or after a palette (a truecolour PNG may
 * carry a suggested one), and what stands beside it, while Chromium draws
 * the image by the first (attack18 #1). reader_setup keeps them all
 * unread by libpng; after png_read_end, those after the pixels too. */
static const char *colour_chunks_refused(struct png_reader *r, char *buf, size_t size)
{
    png_unknown_chunkp u;
    const int n = png_get_unknown_chunks(r->png, r->info, &u);
    for (size_t k = 0; k < sizeof(colour_chunks) / sizeof(colour_chunks[0]); k++) {
        const char *name = colour_chunks[k][0];
        int count = 0, late = 0;
        for (int i = 0; i < n; i++)
            if (!strcmp((const char *)u[i].name, name))
                count++, late |= u[i].location & (PNG_HAVE_PLTE | PNG_AFTER_IDAT);
        if (count > 1)
            snprintf(buf, size, "holds %d %s (%s chunks), where PNG allows one and viewers "
                     "convert its colours by one or another (Chromium by the first); save it "
                     "with one %s chunk, or with none and its pixels in sRGB", count,
                     colour_chunks[k][1], name, name);
        else if (late)
            snprintf(buf, size, "holds %s %s chunk after its %s, where PNG allows none, by "
                     "which viewers may still convert its colours; save it with the %s chunk "
                     "before PLTE and IDAT, or without it and its pixels in sRGB",
                     name[0] == 's' || name[0] == 'i' ? "an" : "a", name,
                     late & PNG_AFTER_IDAT ? "pixels (IDAT)" : "palette (PLTE)", name);
        else
            continue;
        return buf;
    }
    return NULL;
}

/* NULL when the PNG's cHRM (kept unread: reader_setup) is sRGB's (its
 * primaries and D65 white within 0.001 of PNG's recommended 0.64,0.33
 * 0.30,0.60 0.15,0.06 0.3127,0.3290) and stands without a gAMA (gama: 1
 * when the PNG has one): Chromium then draws the pixels as read. Beside a
 * gAMA, even sRGB's 1/2.2 (what ImageMagick writes), Chromium converts by
 * the pure power curve 2.2, not sRGB's, and draws levels up to 9 apart
 * (level 16 as 25; attack12 #11, measured with chromium --headless): that
 * pair is refused unless an sRGB chunk says sRGB. Else what is wrong. */
static const char *chrm_refused(struct png_reader *r, int gama)
{
    static const long srgb[8] = {31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000};
    const png_unknown_chunk *c = kept_chunk(r, "cHRM");
    if (!c)
        return NULL;
    if (c->size != 32)
        return "holds a cHRM chunk that is not 32 bytes (8 chromaticities), by which viewers "
               "may still convert its colours; save its pixels in sRGB, without the cHRM chunk";
    for (int i = 0; i < 8; i++)
        if ((long)be32(c->data + 4 * i) < srgb[i] - 100 ||
            (long)be32(c->data + 4 * i) > srgb[i] + 100)
            return "holds chromaticities (cHRM) other than sRGB's (primaries 0.64,0.33 "
                   "0.30,0.60 0.15,0.06, white 0.3127,0.3290), by which viewers convert its "
                   "colours; save its pixels in sRGB, without the cHRM chunk";
    if (gama)
        return "holds chromaticities (cHRM) beside a gamma (gAMA), by which viewers convert "
               "its colours by a pure power curve, not sRGB's (Chromium draws a gAMA of 1/2.2 "
               "up to 9 levels off: level 16 as 25); add an sRGB chunk, or save it without "
               "the gAMA and cHRM chunks (ImageMagick: -define png:exclude-chunk=gAMA,cHRM)";
    return NULL;
}

/* NULL when the PNG has no gAMA (kept unread: reader_setup), or sRGB's
 * 1/2.2 (45455 in 100000ths, within 500); else what is wrong. */
static const char *gama_refused(struct png_reader *r)
{
    const png_unknown_chunk *c = kept_chunk(r, "gAMA");
    if (!c)
        return NULL;
    if (c->size != 4)
        return "holds a gAMA chunk that is not 4 bytes, by which viewers may still convert "
               "its colours; save its pixels in sRGB, without the gAMA chunk";
    if (be32(c->data) < 44955 || be32(c->data) > 45955)
        return "holds a gamma (gAMA) other than sRGB's 1/2.2, by which viewers convert its "
               "colours";
    return NULL;
}

/* NULL when the unknown chunks kept (reader_setup) change nothing a viewer
 * shows: none, or a cICP of sRGB's code points (BT.709 primaries, sRGB
 * transfer, RGB, full range: 1 13 0 1); else what is wrong. */
static const char *unknown_refused(struct png_reader *r, char *buf, size_t size)
{
    png_unknown_chunkp u;
    const int n = png_get_unknown_chunks(r->png, r->info, &u);
    for (int i = 0; i < n; i++) {
        const char *name = (const char *)u[i].name;
        if (!strcmp(name, "acTL"))
            return "is an animated PNG (APNG: an acTL chunk), which viewers show as its "
                   "frames";
        if (!strcmp(name, "cICP")) {
            const png_byte *d = u[i].data;
            if (u[i].size == 4 && d[0] == 1 && d[1] == 13 && d[2] == 0 && d[3] == 1)
                continue;
            if (u[i].size != 4)
                snprintf(buf, size, "holds a cICP chunk of %zu bytes (4 are allowed)",
                         (size_t)u[i].size);
            else
                snprintf(buf, size, "holds coding-independent code points (cICP: primaries "
                         "%d, transfer %d, matrix %d, full range %d) other than sRGB's (1 13 0 "
                         "1), by which viewers convert its colours; save its pixels in sRGB, "
                         "without the cICP chunk", d[0], d[1], d[2], d[3]);
            return buf;
        }
        if (!strcmp(name, "mDCv") || !strcmp(name, "cLLi")) {
            snprintf(buf, size, "holds HDR %s (%s), by which viewers may map its colours; "
                     "save it without the %s chunk", name[0] == 'm' ? "mastering display "
                     "colours" : "content light levels", name, name);
            return buf;
        }
    }
    return NULL;
}

/* Reads an eXIf chunk's TIFF data x (big-endian when big), at offset p. */
#define U16(p) (big ? (unsigned)x[p] << 8 | x[(p) + 1] : (unsigned)x[(p) + 1] << 8 | x[p])
#define U32(p) ((uint32_t)U16(big ? (p) : (p) + 2) << 16 | U16(big ? (p) + 2 : (p)))

/* The first EXIF Orientation (tag 0x0112) other than 1 in the TIFF
 * directory at offset ifd of x (n bytes); 1 when it holds none other; -1
 * when the directory does not lie whole within x; -2 when the tag is not
 * one SHORT. With sub (IFD0), the Exif directory's offset (its pointer,
 * tag 0x8769) is put in *sub (0: none); -3 when that pointer is not one
 * LONG (or IFD), or is there twice. Every offset is checked against n
 * (64-bit sums: a hostile offset or count cannot wrap). */
static long exif_ifd(const png_byte *x, uint64_t n, int big, uint64_t ifd, uint64_t *sub)
{
    if (ifd < 8 || ifd + 2 > n)
        return -1;
    const uint64_t count = U16(ifd);
    if (ifd + 2 + 12 * count > n)
        return -1;
    for (uint64_t e = ifd + 2; e < ifd + 2 + 12 * count; e += 12) {
        if (U16(e) == 0x8769 && sub) {
            if (*sub || (U16(e + 2) != 4 && U16(e + 2) != 13) || U32(e + 4) != 1 ||
                !U32(e + 8))
                return -3;
            *sub = U32(e + 8);
        }
        if (U16(e) != 0x0112)
            continue;
        if (U16(e + 2) != 3 || U32(e + 4) != 1)
            return -2;
        if (U16(e + 8) != 1) /* the first that turns */
            return U16(e + 8);
    }
    return 1;
}

/* The EXIF Orientation that an eXIf chunk's data x (n bytes: a TIFF
 * header, its IFD0 and the Exif directory IFD0 points to, tag 0x8769)
 * holds: the first other than 1, in IFD0 or the Exif directory (Chromium
 * turns a PNG by one there too: attack16 #3); 1 (as read) when there is
 * none; -1 when x is not TIFF data whose IFD0 and Exif directory lie
 * whole within it; -2 when the tag is not one SHORT; -3 when the Exif
 * directory's pointer is not one LONG, or is there twice. Only these two
 * directories are read, IFD0's pointer first: no loop can form. IFD1's
 * (a thumbnail's) orientation is not one viewers apply. */
static long exif_orientation(const png_byte *x, png_uint_32 n)
{
    if (n < 8 || x[0] != x[1] || (x[0] != 'I' && x[0] != 'M'))
        return -1;
    const int big = x[0] == 'M';
    uint64_t sub = 0;
    if (U16(2) != 42)
        return -1;
    const long o = exif_ifd(x, n, big, U32(4), &sub);
    return o == 1 && sub ? exif_ifd(x, n, big, sub, NULL) : o;
}
#undef U16
#undef U32

/* NULL when the PNG's eXIf chunk (if any) turns and mirrors nothing: no
 * EXIF Orientation, or 1; else what it does, in buf. Browsers show a PNG
 * turned or mirrored by it (CSS image-orientation: from-image, the
 * default), the still image's twin of a video's display matrix
 * (attack15 #12); springpend writes none. */
static const char *exif_refused(struct png_reader *r, char *buf, size_t size)
{
    static const char *const shown[9] = {
        NULL, NULL, "mirrored left to right", "turned by 180 degrees", "mirrored top to bottom",
        "mirrored left to right and turned by 90 degrees counterclockwise (transposed)",
        "turned by 90 degrees clockwise",
        "mirrored left to right and turned by 90 degrees clockwise (transversed)",
        "turned by 90 degrees counterclockwise"};
    png_bytep exif = NULL;
    png_uint_32 n = 0;
    if (r->exif_why[0]) {
        snprintf(buf, size, "holds an eXIf chunk that libpng does not read (%s), by which "
                 "viewers may still turn or mirror it; save it without the eXIf chunk",
                 r->exif_why);
        return buf;
    }
    if (!png_get_valid(r->png, r->info, PNG_INFO_eXIf) ||
        !png_get_eXIf_1(r->png, r->info, &n, &exif) || !exif)
        return NULL;
    const long o = exif_orientation(exif, n);
    if (o == 1)
        return NULL;
    if (o < 0)
        snprintf(buf, size, "holds an eXIf chunk whose %s, by which viewers may "
                 "still turn or mirror it; save it without the eXIf chunk",
                 o == -1 ? "data is not a whole TIFF header, first directory and Exif "
                           "directory"
                 : o == -2 ? "Orientation tag is not one SHORT"
                           : "Exif directory pointer (tag 0x8769) is not one LONG, or is "
                             "there twice");
    else if (o <= 8)
        snprintf(buf, size, "holds an EXIF Orientation of %ld (an eXIf chunk), by which "
                 "viewers show it %s; save its pixels as shown, without the eXIf chunk or "
                 "with Orientation 1", o, shown[o]);
    else
        snprintf(buf, size, "holds an EXIF Orientation of %ld (an eXIf chunk), which EXIF "
                 "does not define (1 shows the pixels as read); save it without the eXIf "
                 "chunk or with Orientation 1", o);
    return buf;
}

/* Says that a viewer shows r's PNG otherwise than its pixels read, by
 * what; SP_E_INPUT. */
static int not_shown_as_read(const struct png_reader *r, const char *what)
{
    sp_log_error("%s %s; springpend reads still PNGs drawn as their pixels (as it writes "
                 "them), so it would judge pixels that no viewer shows", r->path, what);
    return SP_E_INPUT;
}

/* After png_read_info: 0 when a viewer shows the PNG as its pixels read
 * (no gamma or colour-space conversion, one image); else SP_E_INPUT,
 * said. An APNG (acTL) is shown as its animation, whose frames need not
 * include the default image compared (attack11 #21); a gAMA other than
 * sRGB's (1/2.2), a cHRM other than sRGB's without an sRGB chunk, an ICC
 * profile (iCCP) other than sRGB (attack12 #11), a cICP other than sRGB's
 * or HDR metadata (mDCv, cLLi; attack12 #10) makes browsers, and so
 * compare's own HTML report, draw other colours than the pixels compared;
 * an EXIF Orientation other than 1 (eXIf) turns or mirrors them
 * (exif_refused; sp_png_read looks again for an eXIf after the pixels).
 * springpend writes none of them. */
static int shown_as_read(struct png_reader *r)
{
    char buf[512];
    const int srgb = srgb_chunk(r);
    int icc = 0;
    const char *what = r->lost_why[0] ? buf : unknown_refused(r, buf, sizeof(buf));
    if (r->lost_why[0])
        snprintf(buf, sizeof(buf), "holds more chunks than springpend reads of the kinds "
                 "viewers show it by (iCCP, sRGB, cICP, sPLT...: libpng: %s), so that some "
                 "would go unread; save it without them", r->lost_why);
    if (!what)
        what = exif_refused(r, buf, sizeof(buf));
    if (!what)
        what = iccp_refused(r, buf, sizeof(buf), &icc);
    if (!what) /* a gAMA, cHRM, sRGB or cICP twice or after PLTE (iCCP: just above) */
        what = colour_chunks_refused(r, buf, sizeof(buf));
    /* viewers convert by an ICC profile rather than by gAMA and cHRM */
    if (!what && icc)
        return 0;
    if (!what && !srgb)
        what = chrm_refused(r, kept_chunk(r, "gAMA") != NULL);
    if (!what && !srgb)
        what = gama_refused(r);
    return what ? not_shown_as_read(r, what) : 0;
}

/* After libpng's error: closes r; SP_E_NOMEM when an allocation failed
 * (unsaid), else SP_E_INPUT (on_png_read_error has logged: a damaged PNG
 * is bad input). */
static int reader_failed(struct png_reader *r)
{
    const int nomem = r->nomem;
    reader_close(r);
    return nomem ? SP_E_NOMEM : SP_E_INPUT;
}

int sp_png_read_info_quiet(const char *path, struct sp_png_info *out)
{
    memset(out, 0, sizeof(*out));
    /* only a regular file is opened (infile.h): a FIFO or device named
     * *.png is not, nor swapped in after the walk looked */
    const char *why;
    int fd = sp_infile_try(path, &why);
    FILE *fp = NULL;
    if (fd < 0 || !(fp = fdopen(fd, "rb"))) {
        if (fd >= 0)
            close(fd);
        return SP_E_INPUT;
    }
    png_image image = {.version = PNG_IMAGE_VERSION}; /* libpng's simplified API: no
                                                         messages, the header only */
    const int ok = png_image_begin_read_from_stdio(&image, fp) != 0;
    if (ok) {
        out->width = (int)image.width;
        out->height = (int)image.height;
    }
    png_image_free(&image);
    fclose(fp);
    return ok ? 0 : SP_E_INPUT;
}

int sp_png_read_info(const char *path, struct sp_png_info *out)
{
    struct png_reader rd, *r = &rd;
    int err = reader_open(r, path);
    memset(out, 0, sizeof(*out));
    if (err)
        return err;
    if (setjmp(png_jmpbuf(r->png)))
        return reader_failed(r);
    reader_setup(r, 0);
    png_read_info(r->png, r->info);
    out->width = (int)png_get_image_width(r->png, r->info);
    out->height = (int)png_get_image_height(r->png, r->info);
    out->bit_depth = png_get_bit_depth(r->png, r->info);
    out->color_type = png_get_color_type(r->png, r->info);
    out->interlaced = png_get_interlace_type(r->png, r->info) != PNG_INTERLACE_NONE;
    reader_close(r);
    return 0;
}

int sp_png_check_size(const char *path, const struct sp_png_info *info)
{
    if ((long long)info->width * info->height > SP_PNG_MAX_PIXELS) {
        sp_log_error("%s: %dx%d is %lld pixels; springpend reads PNGs of at most %ld "
                     "pixels (%ld MB as RGBA)",
                     path, info->width, info->height, (long long)info->width * info->height,
                     SP_PNG_MAX_PIXELS, SP_PNG_MAX_PIXELS * 4 / 1000000);
        return SP_E_INPUT;
    }
    return 0;
}

int sp_png_read(const char *path, struct sp_image *img)
{
    struct png_reader rd, *r = &rd;
    struct sp_png_info hdr;
    int err = reader_open(r, path);
    memset(img, 0, sizeof(*img));
    if (err)
        return err;
    if (setjmp(png_jmpbuf(r->png))) {
        sp_image_free(img);
        return reader_failed(r);
    }
    reader_setup(r, 0);
    png_read_info(r->png, r->info);
    hdr.width = (int)png_get_image_width(r->png, r->info);
    hdr.height = (int)png_get_image_height(r->png, r->info);
    if ((err = sp_png_check_size(path, &hdr)) != 0 || (err = shown_as_read(r)) != 0) {
        reader_close(r);
        return err;
    }
    /* Every colour type to RGBA8 by value: 16-bit samples are scaled with
     * rounding (v * 255 / 65535), so v * 257 gives back v exactly; no
     * gamma or colour-space conversion. */
    int type = png_get_color_type(r->png, r->info);
    if (type == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(r->png);
    if (type == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(r->png, r->info) < 8)
        png_set_expand_gray_1_2_4_to_8(r->png);
    if (png_get_valid(r->png, r->info, PNG_INFO_tRNS))
        png_set_tRNS_to_alpha(r->png);
    if (png_get_bit_depth(r->png, r->info) == 16)
        png_set_scale_16(r->png);
    if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(r->png);
    png_set_add_alpha(r->png, 0xff, PNG_FILLER_AFTER); /* only where none */
    png_set_interlace_handling(r->png);
    png_read_update_info(r->png, r->info);
    if (png_get_rowbytes(r->png, r->info) != 4 * (size_t)hdr.width)
        png_error(r->png, "unexpected row size after conversion to RGBA8");
    if ((err = sp_image_alloc_unsaid(img, hdr.width, hdr.height)) != 0 ||
        !(r->rows = malloc(sizeof(*r->rows) * (size_t)hdr.height))) {
        sp_image_free(img);
        reader_close(r);
        return SP_E_NOMEM;
    }
    for (int y = 0; y < hdr.height; y++)
        r->rows[y] = img->pixels + (size_t)y * img->stride;
    png_read_image(r->png, r->rows);
    png_read_end(r->png, r->info); /* a missing IEND is a truncated file */
    char buf[512];
    const char *what = exif_refused(r, buf, sizeof(buf)); /* an eXIf after the pixels */
    if (!what) /* a colour chunk after them (reader_setup kept them) */
        what = colour_chunks_refused(r, buf, sizeof(buf));
    if (what) {
        sp_image_free(img);
        err = not_shown_as_read(r, what);
    }
    reader_close(r);
    return err;
}

int sp_png_read_text(const char *path, const char *key, char *buf, size_t size)
{
    struct png_reader rd, *r = &rd;
    png_textp text;
    int n, ret = reader_open(r, path);
    if (ret == SP_E_NOMEM)
        sp_log_error("%s: out of memory to read its text", path);
    if (ret)
        return ret;
    if (setjmp(png_jmpbuf(r->png))) {
        if ((ret = reader_failed(r)) == SP_E_NOMEM)
            sp_log_error("%s: out of memory to read its text", path);
        return ret;
    }
    reader_setup(r, 1);
    png_read_info(r->png, r->info); /* reads up to the first IDAT */
    n = png_get_text(r->png, r->info, &text, NULL);
    for (int i = 0; i < n && ret >= 0; i++) {
        if (strcmp(text[i].key, key))
            continue;
        /* libpng hands the text over up to its first NUL: a scene cut there
         * is refused by its reader (sp_provenance_scene_check); bytes after a NUL
         * that ends a whole scene are never read */
        const size_t len = strlen(text[i].text);
        if (ret == 1) {
            sp_log_error("%s: the text %s is there twice; springpend writes it once", path, key);
            ret = SP_E_INPUT;
        } else if (len >= size) {
            sp_log_error("%s: the text %s holds %zu bytes; at most %zu are read", path, key,
                         len, size - 1);
            ret = SP_E_INPUT;
        } else {
            memcpy(buf, text[i].text, len + 1);
            ret = 1;
        }
    }
    reader_close(r);
    return ret;
}
