/* springpend: vector figures. See figure.h. */
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "springpend/common.h"
#include "springpend/figure.h"
#include "av_module.h"
#include "compose.h"
#include "draw_cairo.h"
#include "sink_impl.h"

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
    struct sp_composer *c = NULL;
    const struct sp_canvas *cv;
    int (*write_fn)(const struct sp_draw_cairo_desc *);
    char *part = NULL;
    int err;

    if (!format) {
        sp_log_error("%s: a vector figure is NAME.svg or NAME.pdf", d->path);
        return SP_E_INPUT;
    }
    *(void **)&write_fn = sp_module_symbol("springpend-cairo.so", "SVG and PDF figures",
                                           "sp_draw_cairo_write");
    if (!write_fn)
        return SP_E_IO;
    err = sp_compose_make(&c, &(struct sp_compose_desc){
        .width = d->width, .height = d->height, .extent = d->extent, .scene = d->scene});
    if (!err)
        err = sp_compose_frame(c, f, &cv);
    if (!err)
        err = sp_sink_part_path(d->path, &part);
    if (!err)
        err = sp_sink_make_parents(d->path);
    if (!err) {
        struct sp_draw_cairo_desc dd = {
            .canvas = cv, .font = sp_compose_font(c), .width = d->width,
            .height = d->height, .path = part, .format = format,
            .title = d->scene ? d->scene->name : NULL};
        memcpy(dd.background, sp_compose_palette(c)->background, sizeof(dd.background));
        err = write_fn(&dd);
    }
    if (!err)
        err = sp_sink_commit(part, d->path);
    if (err && part)
        sp_sink_discard(part);
    free(part);
    sp_compose_destroy(&c);
    return err;
}
