/* springpend: vector figures. See figure.h. */
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "springpend/common.h"
#include "springpend/figure.h"
#include "springpend/outfile.h"
#include "av_module.h"
#include "compose.h"
#include "draw_cairo.h"
#include "signals.h"

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
            .title = d->title};
        memcpy(dd.background, sp_compose_cells_palette(c)->background, sizeof(dd.background));
        err = write_fn(&dd);
    }
    if (!err && sp_signal_seen()) /* a signal while drawing: nothing written */
        err = SP_E_INTERRUPTED;
    if (!err)
        err = sp_outfile_commit(&out); /* whole or not at all */
    if (err) {
        sp_outfile_discard(&out);
        sp_dirs_remove_empty(&dirs);
    }
    sp_dirs_keep(&dirs);
    sp_compose_cells_destroy(&c);
    return err;
}
