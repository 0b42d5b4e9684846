/* springpend: vector figures. See figure.h. */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/figure.h"
#include "springpend/infile.h"
#include "springpend/outfile.h"
#include "base/module.h"
#include "frame/compose.h"
#include "draw_cairo.h"

enum sp_figure_format sp_figure_format(const char *path)
{
    const char *dot = path ? strrchr(path, '.') : NULL;
    if (dot && !strcasecmp(dot, ".svg"))
        return SP_FIGURE_SVG;
    if (dot && !strcasecmp(dot, ".pdf"))
        return SP_FIGURE_PDF;
    return SP_FIGURE_NONE;
}

int sp_figure_write(const struct sp_figure_desc *d, const struct sp_frame *f)
{
    const enum sp_figure_format format = sp_figure_format(d->path);
    struct sp_compose_cells *c = NULL;
    const struct sp_canvas *cv;
    int (*write_fn)(const struct sp_draw_cairo_desc *);
    struct sp_outfile out = {.fd = -1, .slot = -1};
    struct sp_dirs dirs = {0};
    int err;

    if (!format) {
        sp_log_error("%s: a vector figure is NAME.svg or NAME.pdf", d->path);
        return SP_E_INPUT;
    }
    *(void **)&write_fn = sp_module_symbol("springpend-cairo.so", "SVG and PDF figures",
                                           "sp_draw_cairo_write");
    if (!write_fn)
        return SP_E_IO;
    err = sp_compose_cells_make(&c, &(struct sp_compose_desc){
        .width = d->width, .height = d->height, .extent = d->extent, .look = d->look},
        d->looks, d->cells);
    if (!err)
        err = sp_compose_cells_frame(c, f, &cv);
    if (!err && !sp_outfile_is_stream(d->path))
        err = sp_dirs_make(d->path, &dirs);
    if (!err) /* cairo writes front to back: a device or stdout is fine */
        err = sp_outfile_open(&out, d->path, SP_OUTFILE_STREAM);
    if (!err) {
        struct sp_draw_cairo_desc dd = {
            .canvas = cv, .font = sp_compose_cells_font(c), .width = d->width,
            .height = d->height, .page_w = d->page_w, .page_h = d->page_h, .fd = out.fd,
            .path = d->path, .format = format,
            .title = d->title, .scene_file = d->scene_file, .command = d->command,
            .cancel = d->cancel};
        memcpy(dd.background, sp_compose_cells_palette(c)->background, sizeof(dd.background));
        err = write_fn(&dd);
    }
    if (!err && d->cancel && *d->cancel) /* stopped while drawing: nothing written */
        err = SP_E_INTERRUPTED;
    if (!err) /* whole or not at all; with its partner, both or neither */
        err = d->partner ? sp_outfile_commit_pair(&out, d->partner, d->cancel)
                         : sp_outfile_commit(&out);
    if (err) {
        sp_outfile_discard(&out);
        if (d->partner)
            sp_outfile_discard(d->partner);
        sp_dirs_remove_empty(&dirs);
    }
    sp_dirs_keep(&dirs);
    sp_compose_cells_destroy(&c);
    return err;
}

/* The last occurrence of the n bytes of key in b[0..len), or NULL. */
static const char *last_of(const char *b, size_t len, const char *key)
{
    const size_t n = strlen(key);
    for (size_t i = len >= n ? len - n + 1 : 0; i-- > 0;)
        if (!memcmp(b + i, key, n))
            return b + i;
    return NULL;
}

/* Appends code point u as UTF-8 to out[*w..size-1); 0, or -1 when full. */
static int put_utf8(char *out, size_t size, size_t *w, uint32_t u)
{
    unsigned char e[4];
    int n = u < 0x80 ? (e[0] = (unsigned char)u, 1)
          : u < 0x800 ? (e[0] = (unsigned char)(0xC0 | u >> 6), 2)
          : u < 0x10000 ? (e[0] = (unsigned char)(0xE0 | u >> 12), 3)
                        : (e[0] = (unsigned char)(0xF0 | u >> 18), 4);
    for (int k = 1; k < n; k++)
        e[k] = (unsigned char)(0x80 | ((u >> (6 * (n - 1 - k))) & 0x3F));
    if (*w + (size_t)n >= size)
        return -1;
    memcpy(out + *w, e, (size_t)n);
    *w += (size_t)n;
    return 0;
}

/* A PDF string object at p (before end): <hex> or (literal), its bytes
 * into raw (room for end - p), their count into *m. 0, or -1 when damaged. */
static int pdf_string(const char *p, const char *end, unsigned char *raw, size_t *m)
{
    *m = 0;
    if (p < end && *p == '<') {
        int half = -1;
        for (p++; p < end && *p != '>'; p++) {
            const char c = *p;
            const int v = c >= '0' && c <= '9' ? c - '0' : c >= 'A' && c <= 'F' ? c - 'A' + 10
                        : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
            if (v < 0 && (c == ' ' || c == '\n' || c == '\r' || c == '\t'))
                continue;
            if (v < 0)
                return -1;
            if (half < 0)
                half = v;
            else
                raw[(*m)++] = (unsigned char)(half << 4 | v), half = -1;
        }
        if (half >= 0) /* an odd digit count: a trailing 0 (PDF 7.3.4.3) */
            raw[(*m)++] = (unsigned char)(half << 4);
        return p < end ? 0 : -1;
    }
    if (p >= end || *p != '(')
        return -1;
    int depth = 1;
    for (p++; p < end; p++) {
        unsigned char c = (unsigned char)*p;
        if (c == '\\' && p + 1 < end) {
            const char e = *++p;
            if (e >= '0' && e <= '7') { /* \ddd */
                int v = 0;
                for (int k = 0; k < 3 && p < end && *p >= '0' && *p <= '7'; k++, p++)
                    v = v * 8 + (*p - '0');
                p--;
                c = (unsigned char)v;
            } else if (e == '\n' || e == '\r') {
                continue; /* a line continued */
            } else {
                c = (unsigned char)(e == 'n' ? '\n' : e == 'r' ? '\r' : e == 't' ? '\t'
                                    : e == 'b' ? '\b' : e == 'f' ? '\f' : e);
            }
        } else if (c == '(') {
            depth++;
        } else if (c == ')' && --depth == 0) {
            return 0;
        }
        raw[(*m)++] = c;
    }
    return -1;
}

/* The PDF's /Subject (the last one: an updated file's newest) as UTF-8:
 * its scene, or with command its "# command: " line's text instead. 1,
 * 0 (none, or not springpend's), -1 (damaged), -2 (too long). */
static int pdf_scene(const char *b, size_t len, char *text, size_t size, int command)
{
    const char *at = last_of(b, len, "/Subject");
    if (!at)
        return 0;
    const char *p = at + 8, *end = b + len;
    while (p < end && (*p == ' ' || *p == '\n' || *p == '\r' || *p == '\t'))
        p++;
    unsigned char *raw = malloc((size_t)(end - p) + 1);
    size_t m = 0, w = 0;
    int ret = raw && !pdf_string(p, end, raw, &m) ? 1 : -1;
    if (ret == 1 && m >= 2 && raw[0] == 0xFE && raw[1] == 0xFF) { /* UTF-16BE */
        for (size_t i = 2; ret == 1 && i + 1 < m; i += 2) {
            uint32_t u = (uint32_t)raw[i] << 8 | raw[i + 1];
            if (u >= 0xD800 && u < 0xDC00 && i + 3 < m) {
                const uint32_t lo = (uint32_t)raw[i + 2] << 8 | raw[i + 3];
                if (lo >= 0xDC00 && lo < 0xE000)
                    u = 0x10000 + ((u - 0xD800) << 10) + (lo - 0xDC00), i += 2;
            }
            if (put_utf8(text, size, &w, u))
                ret = -2;
        }
    } else if (ret == 1) { /* PDFDocEncoding: the ASCII springpend writes */
        if (m >= size)
            ret = -2;
        else
            memcpy(text, raw, m), w = m;
    }
    free(raw);
    if (ret != 1)
        return ret;
    text[w] = 0;
    const size_t mark = strlen(SP_FIGURE_SCENE_MARK);
    if (strncmp(text, SP_FIGURE_SCENE_MARK, mark))
        return 0; /* a subject, not springpend's scene */
    memmove(text, text + mark, w - mark + 1);
    const size_t cmd = strlen(SP_FIGURE_COMMAND_MARK);
    if (!strncmp(text, SP_FIGURE_COMMAND_MARK, cmd)) {
        char *nl = strchr(text, '\n'); /* the command: not part of the scene */
        if (!nl)
            return -1;
        if (command) {
            *nl = 0;
            memmove(text, text + cmd, strlen(text + cmd) + 1);
        } else {
            memmove(text, nl + 1, strlen(nl + 1) + 1);
        }
    } else if (command) {
        return 0;
    }
    return 1;
}

/* The code point of the character reference "&#N;" or "&#xH;" of n bytes
 * at p (before the ';'), or 0 when it is none: digits only, no sign or
 * blank, and a Unicode scalar value U+0001..U+10FFFF (no surrogate). */
static uint32_t char_ref(const char *p, size_t n)
{
    const int hex = n > 2 && p[2] == 'x';
    size_t i = 2 + (size_t)hex;
    uint32_t u = 0;
    if (i == n)
        return 0;
    for (; i < n; i++) {
        const char ch = p[i];
        const int d = ch >= '0' && ch <= '9' ? ch - '0'
                    : hex && ch >= 'a' && ch <= 'f' ? ch - 'a' + 10
                    : hex && ch >= 'A' && ch <= 'F' ? ch - 'A' + 10 : -1;
        if (d < 0)
            return 0;
        u = u * (hex ? 16 : 10) + (uint32_t)d;
        if (u > 0x10FFFF)
            return 0; /* before it can wrap */
    }
    return u >= 0xD800 && u < 0xE000 ? 0 : u;
}

/* The SVG's <metadata id="springpend.scene-file"> text (with command: its
 * "springpend.command"), unescaped. 1, 0 (none), -1 (damaged), -2 (too
 * long), -3 (a reference that is neither one of XML's five entities nor a
 * character: copied, cut, into bad), -4 (the element is there twice), -5
 * (not inside the root element: springpend writes it just before the
 * closing </svg>, which only blanks follow). */
static int svg_scene(const char *b, size_t len, char *text, size_t size, char *bad,
                     size_t bad_size, int command)
{
    const char *tag = command ? "<metadata id=\"springpend.command\">"
                              : "<metadata id=\"" SP_FIGURE_SCENE_ID "\">";
    const char *open = last_of(b, len, tag), *root_end = last_of(b, len, "</svg>");
    if (!open)
        return 0;
    if (memmem(b, len, tag, strlen(tag)) != open)
        return -4;
    const char *p = strchr(open, '>') + 1, *close = strstr(p, "</metadata>");
    if (!close)
        return -1;
    if (!root_end || root_end < close ||
        strspn(root_end + 6, " \t\r\n") != len - (size_t)(root_end + 6 - b))
        return -5;
    size_t w = 0;
    while (p < close) {
        uint32_t u = (unsigned char)*p;
        if (*p == '&') {
            const char *semi = memchr(p, ';', (size_t)(close - p));
            const size_t n = semi ? (size_t)(semi - p) : 0;
            if (n == 3 && !strncmp(p, "&lt", 3))
                u = '<';
            else if (n == 3 && !strncmp(p, "&gt", 3))
                u = '>';
            else if (n == 4 && !strncmp(p, "&amp", 4))
                u = '&';
            else if (n == 5 && !strncmp(p, "&quot", 5))
                u = '"';
            else if (n == 5 && !strncmp(p, "&apos", 5))
                u = '\'';
            else
                u = n > 2 && p[1] == '#' ? char_ref(p, n) : 0;
            if (!u) {
                const size_t shown = semi ? n + 1 : strcspn(p, " \n<");
                snprintf(bad, bad_size, "%.*s%s", (int)(shown < 24 ? shown : 24), p,
                         shown > 24 ? "..." : "");
                return -3;
            }
            if (put_utf8(text, size, &w, u))
                return -2;
            p = semi + 1;
            continue;
        }
        if (w + 1 >= size)
            return -2;
        text[w++] = *p++;
    }
    text[w] = 0;
    return 1;
}

/* sp_figure_read_scene, or with command sp_figure_read_command. */
static int read_record(const char *path, char *text, size_t size, int command)
{
    /* the record is near the end (cairo writes a PDF's /Info last, the SVG's
     * metadata goes before </svg>): read the last 8 bytes per byte of text */
    const off_t max = (off_t)(8 * size + 65536);
    const int fd = sp_infile_open(path, "an SVG or PDF must be a file");
    if (fd < 0)
        return fd; /* not a regular file (a FIFO would block): logged */
    struct stat st;
    const off_t end = fstat(fd, &st) ? -1 : st.st_size;
    const off_t from = end > max ? end - max : 0;
    char *b = end >= 0 ? malloc((size_t)(end - from) + 1) : NULL;
    size_t n = 0;
    int bad = !b;
    while (b && n < (size_t)(end - from)) {
        const ssize_t got = pread(fd, b + n, (size_t)(end - from) - n, from + (off_t)n);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0) {
            bad = 1, errno = got ? errno : EIO; /* cut short while read */
            break;
        }
        n += (size_t)got;
    }
    const int why = errno;
    close(fd);
    if (bad) {
        sp_log_error("%s: cannot read: %s", path, b ? strerror(why ? why : EIO) : "out of memory");
        free(b);
        return SP_E_IO;
    }
    b[n] = 0;
    char ref[32] = "";
    const char *what = command ? "command" : "scene";
    const int got = sp_figure_format(path) == SP_FIGURE_PDF
                        ? pdf_scene(b, n, text, size, command)
                        : svg_scene(b, n, text, size, ref, sizeof(ref), command);
    free(b);
    if (got == -3)
        sp_log_error("%s: its %s record holds '%s', which is neither one of XML's five entities nor a "
                     "character reference; allowed: "
                     "&lt; &gt; &amp; &quot; &apos; and &#N; or &#xH; of a character "
                     "U+0001..U+10FFFF (not a surrogate), as springpend writes", path, what, ref);
    else if (got == -1)
        sp_log_error("%s: its %s record is damaged; springpend writes it whole", path, what);
    else if (got == -2)
        sp_log_error("%s: its %s record is longer than %zu bytes, more than springpend writes",
                     path, what, size - 1);
    else if (got == -4)
        sp_log_error("%s: its %s record (<metadata id=\"springpend.%s\">) is there twice; "
                     "springpend writes it once", path, what, command ? "command" : "scene-file");
    else if (got == -5)
        sp_log_error("%s: its %s record is not inside the <svg> root element (or something "
                     "follows </svg>); springpend writes it last inside <svg>", path, what);
    return got < 0 ? SP_E_INPUT : got;
}

int sp_figure_read_scene(const char *path, char *text, size_t size)
{
    return read_record(path, text, size, 0);
}

int sp_figure_read_command(const char *path, char *text, size_t size)
{
    return read_record(path, text, size, 1);
}
