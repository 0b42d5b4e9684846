/* springpend benchmark: a small log-log line plot rasterised into an
 * sp_image. Text through FreeType when the build found it (HAVE_FREETYPE),
 * else the plot has no labels and the doc/ pages name the colours. */
#ifndef SPRINGPEND_BENCH_PLOT_H
#define SPRINGPEND_BENCH_PLOT_H

#include <stdint.h>
#include "springpend/image.h"

struct plot_panel {
    int x0, y0, w, h;          /* the data area in the image, px */
    double lx0, lx1, ly0, ly1; /* log10 ranges on x and y */
};

struct plot {
    struct sp_image img;
    void *font; /* FreeType face, or NULL */
};

int plot_make(struct plot *p, int width, int height);
void plot_destroy(struct plot *p);
/* A filled rectangle, px. */
void plot_rect(struct plot *p, int x, int y, int w, int h, uint32_t rgb);
/* Axes with decade ticks and labels, title and axis names. */
void plot_axes(struct plot *p, const struct plot_panel *pn, const char *title,
               const char *xlabel, const char *ylabel);
/* A polyline through (x[i], y[i]) in data units (log-scaled here); dashed
 * when dash, with a marker at each point. Points <= 0 are skipped. */
void plot_series(struct plot *p, const struct plot_panel *pn, const double *x,
                 const double *y, int n, uint32_t rgb, int dash);
/* Text with its top-left at (x, y), px high; nothing without FreeType. */
void plot_text(struct plot *p, int x, int y, int px, uint32_t rgb, const char *s);

#endif
