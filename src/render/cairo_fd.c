/* springpend (internal): cairo's output to a file descriptor. See cairo_fd.h. */
#include <cairo-pdf.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cairo_fd.h"
#include "springpend/common.h"
#include "springpend/figure.h"
#include "springpend/outfile.h"

cairo_status_t sp_cairo_fd_write(void *closure, const unsigned char *data, unsigned int length)
{
    struct sp_cairo_fd *k = closure;
    static const char end[] = "</svg>\n";
    const unsigned int n_end = sizeof(end) - 1;
    if (k->svg_metadata && length >= n_end && !memcmp(data + length - n_end, end, n_end)) {
        const char *meta = k->svg_metadata;
        k->svg_metadata = NULL; /* once: then the closing tag */
        sp_cairo_fd_write(k, data, length - n_end);
        sp_cairo_fd_write(k, (const unsigned char *)meta, (unsigned int)strlen(meta));
        data += length - n_end, length = n_end;
    }
    /* a FIFO whose reader does not read waits with the stop flag in view */
    if (length && !k->err && sp_outfile_write_all(k->fd, data, length) != 0)
        k->err = errno;
    return k->err ? CAIRO_STATUS_WRITE_ERROR : CAIRO_STATUS_SUCCESS;
}

int sp_cairo_pdf_date(cairo_surface_t *pdf)
{
    const char *env = getenv("SOURCE_DATE_EPOCH");
    char iso[32] = ""; /* empty: cairo writes no /CreationDate */
    if (env) {
        char *end;
        errno = 0;
        long long t = strtoll(env, &end, 10);
        struct tm tm;
        time_t tt = (time_t)t;
        if (!*env || *end || errno || t < 0 || t > 253402300799LL || *env < '0' || *env > '9' ||
            !gmtime_r(&tt, &tm)) {
            sp_log_error("SOURCE_DATE_EPOCH='%s' is not a time; expected whole seconds since "
                         "1970-01-01 UTC, 0 to 253402300799 (or leave it unset: no date is written)",
                         env);
            return SP_E_INPUT;
        }
        strftime(iso, sizeof iso, "%Y-%m-%dT%H:%M:%SZ", &tm);
    }
    cairo_pdf_surface_set_metadata(pdf, CAIRO_PDF_METADATA_CREATE_DATE, iso);
    return 0;
}

void sp_cairo_pdf_scene(cairo_surface_t *pdf, const char *scene_file, const char *command)
{
    if (!scene_file || !scene_file[0])
        return;
    const size_t n = strlen(SP_FIGURE_SCENE_MARK) + strlen(SP_FIGURE_COMMAND_MARK) +
                     (command ? strlen(command) + 1 : 0) + strlen(scene_file) + 1;
    char *text = malloc(n);
    if (!text)
        return; /* the figure without its scene rather than none */
    snprintf(text, n, "%s%s%s%s%s", SP_FIGURE_SCENE_MARK, command ? SP_FIGURE_COMMAND_MARK : "",
             command ? command : "", command ? "\n" : "", scene_file);
    cairo_pdf_surface_set_metadata(pdf, CAIRO_PDF_METADATA_SUBJECT, text);
    free(text);
}

/* Writes text XML-escaped at w; returns the bytes written. */
static size_t xml_text(char *w, const char *text)
{
    char *at = w;
    for (const char *c = text; *c; c++)
        at += *c == '&' ? sprintf(at, "&amp;") : *c == '<' ? sprintf(at, "&lt;")
              : *c == '>' ? sprintf(at, "&gt;") : (*at = *c, 1);
    *at = 0;
    return (size_t)(at - w);
}

char *sp_cairo_svg_metadata(const char *scene_file, const char *command, const char *fonts)
{
    static const char head[] = "<metadata id=\"springpend.version\">springpend " SP_VERSION
                               "</metadata>\n<metadata id=\"springpend.renderer\">cairo "
                               CAIRO_VERSION_STRING "</metadata>\n<metadata "
                               "id=\"springpend.fonts\">";
    static const char cmd[] = "</metadata>\n<metadata id=\"springpend.command\">";
    static const char mid[] = "</metadata>\n<metadata id=\"" SP_FIGURE_SCENE_ID "\">";
    static const char tail[] = "</metadata>\n";
    if (!scene_file)
        return NULL;
    const size_t len = strlen(scene_file) + (command ? strlen(command) : 0) +
                       (fonts ? strlen(fonts) : 0);
    char *out = malloc(sizeof(head) + sizeof(cmd) + sizeof(mid) + 5 * len + sizeof(tail)), *w = out;
    if (!out) {
        sp_log_error("out of memory for the SVG's metadata");
        return NULL;
    }
    w += sprintf(w, "%s", head);
    w += xml_text(w, fonts ? fonts : "");
    w += sprintf(w, "%s", cmd);
    w += xml_text(w, command ? command : "");
    w += sprintf(w, "%s", mid);
    w += xml_text(w, scene_file);
    sprintf(w, "%s", tail);
    return out;
}
