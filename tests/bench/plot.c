/* springpend benchmark: the plot (see plot.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "plot.h"

#ifdef HAVE_FREETYPE
#include <ft2build.h>
#include FT_FREETYPE_H
static FT_Library ft;
#endif

static const char *const font_paths[] = {
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
};

int plot_make(struct plot *p, int width, int height)
{
    memset(p, 0, sizeof(*p));
    if (sp_image_alloc(&p->img, width, height))
        return -1;
    plot_rect(p, 0, 0, width, height, 0xffffff);
#ifdef HAVE_FREETYPE
    FT_Face face = NULL;
    if (!ft && FT_Init_FreeType(&ft))
        return 0;
    for (size_t i = 0; i < sizeof(font_paths) / sizeof(font_paths[0]) && !face; i++)
        if (FT_New_Face(ft, font_paths[i], 0, &face))
            face = NULL;
    p->font = face;
#else
    (void)font_paths;
#endif
    return 0;
}

void plot_destroy(struct plot *p)
{
#ifdef HAVE_FREETYPE
    if (p->font)
        FT_Done_Face((FT_Face)p->font);
#endif
    sp_image_free(&p->img);
}

/* Blends colour rgb at coverage a (0..1) into pixel (x, y). */
static void blend(struct plot *p, int x, int y, uint32_t rgb, double a)
{
    if (x < 0 || y < 0 || x >= p->img.width || y >= p->img.height || a <= 0)
        return;
    uint8_t *px = p->img.pixels + (size_t)y * p->img.stride + 4 * (size_t)x;
    const int c[3] = {(rgb >> 16) & 255, (rgb >> 8) & 255, rgb & 255};
    if (a > 1)
        a = 1;
    for (int i = 0; i < 3; i++)
        px[i] = (uint8_t)lround(px[i] + a * (c[i] - px[i]));
    px[3] = 255;
}

void plot_rect(struct plot *p, int x, int y, int w, int h, uint32_t rgb)
{
    for (int j = y; j < y + h; j++)
        for (int i = x; i < x + w; i++)
            blend(p, i, j, rgb, 1);
}

/* An antialiased segment of width `width` px: coverage from the distance of
 * each pixel centre to the segment. */
static void segment(struct plot *p, double x0, double y0, double x1, double y1,
                    double width, uint32_t rgb)
{
    double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy, r = width / 2;
    int xa = (int)floor(fmin(x0, x1) - r - 1), xb = (int)ceil(fmax(x0, x1) + r + 1);
    int ya = (int)floor(fmin(y0, y1) - r - 1), yb = (int)ceil(fmax(y0, y1) + r + 1);
    for (int y = ya; y <= yb; y++)
        for (int x = xa; x <= xb; x++) {
            double u = len2 > 0 ? ((x - x0) * dx + (y - y0) * dy) / len2 : 0;
            u = fmin(1, fmax(0, u));
            double d = hypot(x - (x0 + u * dx), y - (y0 + u * dy));
            blend(p, x, y, rgb, r + 0.5 - d);
        }
}

static double map_x(const struct plot_panel *pn, double v)
{
    return pn->x0 + (log10(v) - pn->lx0) / (pn->lx1 - pn->lx0) * pn->w;
}

static double map_y(const struct plot_panel *pn, double v)
{
    return pn->y0 + pn->h - (log10(v) - pn->ly0) / (pn->ly1 - pn->ly0) * pn->h;
}

void plot_text(struct plot *p, int x, int y, int px, uint32_t rgb, const char *s)
{
#ifdef HAVE_FREETYPE
    FT_Face face = p->font;
    if (!face || FT_Set_Pixel_Sizes(face, 0, (FT_UInt)px))
        return;
    int pen = x, base = y + (int)(face->size->metrics.ascender >> 6);
    for (; *s; s++) {
        if (FT_Load_Char(face, (unsigned char)*s, FT_LOAD_RENDER))
            continue;
        FT_GlyphSlot g = face->glyph;
        for (unsigned j = 0; j < g->bitmap.rows; j++)
            for (unsigned i = 0; i < g->bitmap.width; i++)
                blend(p, pen + g->bitmap_left + (int)i, base - g->bitmap_top + (int)j, rgb,
                      g->bitmap.buffer[j * g->bitmap.pitch + i] / 255.0);
        pen += (int)(g->advance.x >> 6);
    }
#else
    (void)p, (void)x, (void)y, (void)px, (void)rgb, (void)s;
#endif
}

void plot_axes(struct plot *p, const struct plot_panel *pn, const char *title,
               const char *xlabel, const char *ylabel)
{
    char buf[32];
    for (int e = (int)ceil(pn->lx0); e <= (int)floor(pn->lx1); e++) {
        double x = map_x(pn, pow(10, e));
        segment(p, x, pn->y0, x, pn->y0 + pn->h, 1, 0xdddddd);
        snprintf(buf, sizeof(buf), "1e%d", e);
        plot_text(p, (int)x - 12, pn->y0 + pn->h + 6, 14, 0x333333, buf);
    }
    for (int e = (int)ceil(pn->ly0); e <= (int)floor(pn->ly1); e++) {
        double y = map_y(pn, pow(10, e));
        segment(p, pn->x0, y, pn->x0 + pn->w, y, 1, 0xdddddd);
        if ((e - (int)ceil(pn->ly0)) % 2 == 0) {
            snprintf(buf, sizeof(buf), "1e%d", e);
            plot_text(p, pn->x0 - 46, (int)y - 9, 14, 0x333333, buf);
        }
    }
    segment(p, pn->x0, pn->y0 + pn->h, pn->x0 + pn->w, pn->y0 + pn->h, 1.5, 0x000000);
    segment(p, pn->x0, pn->y0, pn->x0, pn->y0 + pn->h, 1.5, 0x000000);
    plot_text(p, pn->x0, pn->y0 - 26, 18, 0x000000, title);
    plot_text(p, pn->x0 + pn->w / 2 - 60, pn->y0 + pn->h + 26, 15, 0x000000, xlabel);
    plot_text(p, pn->x0 + 6, pn->y0 + 4, 14, 0x000000, ylabel);
}

void plot_series(struct plot *p, const struct plot_panel *pn, const double *x,
                 const double *y, int n, uint32_t rgb, int dash)
{
    int prev = -1;
    for (int i = 0; i < n; i++) {
        if (!(x[i] > 0 && y[i] > 0 && isfinite(x[i]) && isfinite(y[i])))
            continue;
        double px = map_x(pn, x[i]), py = map_y(pn, y[i]);
        if (prev >= 0) {
            double qx = map_x(pn, x[prev]), qy = map_y(pn, y[prev]);
            if (!dash) {
                segment(p, qx, qy, px, py, 2.2, rgb);
            } else {
                double len = hypot(px - qx, py - qy);
                for (double s = 0; s < len; s += 12)
                    segment(p, qx + (px - qx) * s / len, qy + (py - qy) * s / len,
                            qx + (px - qx) * fmin(len, s + 7) / len,
                            qy + (py - qy) * fmin(len, s + 7) / len, 2.2, rgb);
            }
        }
        if (dash)
            segment(p, px - 4, py - 4, px + 4, py + 4, 2, rgb),
                segment(p, px - 4, py + 4, px + 4, py - 4, 2, rgb);
        else
            segment(p, px, py, px, py, 7, rgb);
        prev = i;
    }
}
