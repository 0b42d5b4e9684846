/* springpend: PNG files through libpng. Writing uses the full API (so we
 * choose the filter, zlib level and text chunks); reading uses the simplified
 * API, which converts any PNG to RGBA8. */
#include <errno.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/outfile.h"
#include "springpend/png_io.h"

/* Rows are filtered with UP alone: one fixed filter skips libpng's per-row
 * trial of every candidate (2.6x faster than PNG_ALL_FILTERS at 1080p), and
 * on rendered frames (flat background, thin curves) UP gave smaller files
 * than SUB or NONE at the same speed. */

/* libpng's error callback: error_ptr is the destination's name. Logs and
 * jumps back to the setjmp in the writer; never returns. */
static void on_png_error(png_structp png, png_const_charp msg)
{
    sp_log_error("%s: libpng: %s", (const char *)png_get_error_ptr(png), msg);
    png_longjmp(png, 1);
}

/* libpng's write callback: stdio, with the OS's reason on failure (e.g.
 * "No space left on device"); jumps back like on_png_error. */
static void on_png_write(png_structp png, png_bytep data, size_t n)
{
    if (fwrite(data, 1, n, (FILE *)png_get_io_ptr(png)) != n) {
        sp_log_error("%s: cannot write: %s", (const char *)png_get_error_ptr(png),
                     strerror(errno));
        png_longjmp(png, 1);
    }
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
        err = SP_E_IO; /* on_png_error has logged */
        goto done;
    }

    png_set_write_fn(png, fp, on_png_write, on_png_flush);
    png_set_compression_level(png, opts->level);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
    png_set_IHDR(png, info, (png_uint_32)img->width, (png_uint_32)img->height,
                 8, opts->opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA,
                 PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    for (int i = 0; i < opts->n_text; i++) {
        /* libpng copies key and text into info. */
        png_text t = {
            .compression = PNG_TEXT_COMPRESSION_NONE,
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
        sp_log_error("%s: cannot write: %s", what, strerror(errno));
        err = SP_E_IO;
    }
done:
    png_destroy_write_struct(&png, &info);
    return err;
}

int sp_png_write_outfile(struct sp_outfile *f, const struct sp_image *img,
                         const struct sp_png_write_opts *opts)
{
    FILE *fp = fdopen(f->fd, "wb");
    if (!fp) {
        sp_log_error("%s: %s", f->target, strerror(errno));
        return SP_E_NOMEM;
    }
    f->fd = -1; /* fp owns it now */
    int err = sp_png_write_stream_opts(fp, img, opts, f->target);
    if (fclose(fp) != 0 && !err) {
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

int sp_png_read(const char *path, struct sp_image *img)
{
    /* The simplified API owns its decoder state in pi.opaque and frees it
     * on every error and at the end of png_image_finish_read. */
    png_image pi;
    memset(&pi, 0, sizeof(pi));
    pi.version = PNG_IMAGE_VERSION;
    memset(img, 0, sizeof(*img));

    if (!png_image_begin_read_from_file(&pi, path)) {
        sp_log_error("%s: cannot read PNG: %s", path, pi.message);
        return SP_E_IO;
    }
    pi.format = PNG_FORMAT_RGBA;
    int err = sp_image_alloc(img, (int)pi.width, (int)pi.height);
    if (err) {
        png_image_free(&pi);
        return err;
    }
    if (!png_image_finish_read(&pi, NULL, img->pixels, img->stride, NULL)) {
        sp_log_error("%s: cannot read PNG: %s", path, pi.message);
        sp_image_free(img);
        png_image_free(&pi);
        return SP_E_IO;
    }
    return 0;
}

int sp_png_read_text(const char *path, const char *key, char *buf, size_t size)
{
    /* Owned here, destroyed at `done`; set before setjmp, never changed. */
    png_structp png = NULL;
    png_infop info = NULL;
    FILE *fp = fopen(path, "rb");
    png_textp text;
    int n, ret = 0;
    if (!fp) {
        sp_log_error("%s: cannot open: %s", path, strerror(errno));
        return SP_E_IO;
    }
    png = png_create_read_struct(PNG_LIBPNG_VER_STRING, (png_voidp)path, on_png_error,
                                 on_png_warning);
    if (png)
        info = png_create_info_struct(png);
    if (!png || !info) {
        sp_log_error("%s: out of memory for the PNG reader", path);
        ret = SP_E_NOMEM;
        goto done;
    }
    if (setjmp(png_jmpbuf(png))) {
        ret = SP_E_IO; /* on_png_error has logged */
        goto done;
    }
    png_init_io(png, fp);
    png_read_info(png, info); /* reads up to the first IDAT */
    n = png_get_text(png, info, &text, NULL);
    for (int i = 0; i < n && !ret; i++)
        if (!strcmp(text[i].key, key)) {
            snprintf(buf, size, "%s", text[i].text);
            ret = 1;
        }
done:
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return ret;
}
