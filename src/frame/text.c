/* springpend (internal): FreeType glyph atlas and UTF-8 layout. See text.h. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <ft2build.h>
#include FT_FREETYPE_H

#include "springpend/common.h"
#include "embedded.h"
#include "text.h"

/* Code points in the atlas besides printable ASCII: Greek and math for the
 * labels (theta, omega, Delta, ell, sub/superscripts, the combining dot of
 * theta-dot, which layout centres over the glyph before it), a few accented
 * letters (Poincaré). Anything else is drawn as the font's missing-glyph box. */
static const uint32_t EXTRA[] = {
    0x00E0, 0x00E1, 0x00E4, 0x00E7, 0x00E8, 0x00E9, 0x00EA, 0x00F6, 0x00FC, /* à á ä ç è é ê ö ü */
    0x00B0, 0x00B1, 0x00B2, 0x00B3, 0x00B7, 0x00D7, 0x0394, 0x03A9, 0x03B8, 0x03C0,
    0x03C9, 0x0307, 0x1E59, 0x2080, 0x2081, 0x2082, 0x209A, 0x209B, 0x2113,
    0x2212, 0x2248, 0x2264, 0x2265, 0x221A, 0x2713, 0x2026, 0x2192, 0x2014,
};
#define N_ASCII (127 - 32)
#define N_EXTRA ((int)(sizeof(EXTRA) / sizeof(EXTRA[0])))
#define N_GLYPHS (N_ASCII + N_EXTRA + 1) /* + the missing-glyph box */
#define PAD 1                            /* texels between glyphs */

struct glyph {
    int x, y, w, h;  /* atlas texels */
    int left, top;   /* bitmap offset from the pen, px (top: up) */
    int advance;     /* px */
    int present;     /* the font has it */
    unsigned index;  /* the font's glyph index (0: missing) */
};

struct sp_font {
    struct glyph g[SP_TEXT_SIZES][N_GLYPHS];
    int cap[SP_TEXT_SIZES], line[SP_TEXT_SIZES]; /* px */
    int px[SP_TEXT_SIZES];                       /* em size, px */
    uint8_t *atlas;                              /* R8 */
    int aw, ah;                                  /* texels */
};

static int glyph_slot(uint32_t cp)
{
    if (cp >= 32 && cp < 127)
        return (int)cp - 32;
    for (int i = 0; i < N_EXTRA; i++)
        if (EXTRA[i] == cp)
            return N_ASCII + i;
    return N_GLYPHS - 1;
}

static uint32_t slot_codepoint(int i)
{
    return i < N_ASCII ? (uint32_t)(i + 32) : i < N_ASCII + N_EXTRA ? EXTRA[i - N_ASCII] : 0;
}

/* Next code point of a UTF-8 string; malformed bytes read as U+FFFD. */
static uint32_t utf8_next(const char **sp)
{
    const unsigned char *s = (const unsigned char *)*sp;
    uint32_t cp;
    int n;
    if (s[0] < 0x80)
        cp = s[0], n = 1;
    else if ((s[0] & 0xE0) == 0xC0 && (s[1] & 0xC0) == 0x80)
        cp = ((s[0] & 0x1Fu) << 6) | (s[1] & 0x3Fu), n = 2;
    else if ((s[0] & 0xF0) == 0xE0 && (s[1] & 0xC0) == 0x80 && (s[2] & 0xC0) == 0x80)
        cp = ((s[0] & 0x0Fu) << 12) | ((s[1] & 0x3Fu) << 6) | (s[2] & 0x3Fu), n = 3;
    else
        cp = 0xFFFD, n = 1;
    *sp += n;
    return cp;
}

size_t sp_utf8_char(const char *s)
{
    const unsigned char *u = (const unsigned char *)s;
    size_t n = u[0] < 0x80 ? 1 : u[0] >= 0xC2 && u[0] <= 0xDF ? 2 : u[0] >= 0xE0 && u[0] <= 0xEF ? 3
             : u[0] >= 0xF0 && u[0] <= 0xF4 ? 4 : 0;
    uint32_t cp = n == 1 ? u[0] : u[0] & (0x7Fu >> n);
    for (size_t i = 1; i < n; i++) {
        if ((u[i] & 0xC0) != 0x80)
            return 0;
        cp = cp << 6 | (u[i] & 0x3Fu);
    }
    if (!u[0] || (n == 3 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
        (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
        return 0;
    return n;
}

/* Renders every glyph of every size; with atlas == NULL it only measures and
 * places them on shelves of width f->aw, setting f->ah. */
static int raster_all(struct sp_font *f, FT_Face face, const int px[SP_TEXT_SIZES])
{
    int x = PAD, y = PAD, shelf = 0;
    for (int s = 0; s < SP_TEXT_SIZES; s++) {
        if (FT_Set_Pixel_Sizes(face, 0, (FT_UInt)px[s])) {
            sp_log_error("FreeType cannot size the font to %d px", px[s]);
            return SP_E_IO;
        }
        f->line[s] = (int)((face->size->metrics.height + 63) >> 6);
        for (int i = 0; i < N_GLYPHS; i++) {
            struct glyph *g = &f->g[s][i];
            FT_UInt index = FT_Get_Char_Index(face, slot_codepoint(i));
            if (FT_Load_Glyph(face, index, FT_LOAD_RENDER | FT_LOAD_TARGET_LIGHT)) {
                sp_log_error("FreeType cannot render U+%04X", slot_codepoint(i));
                return SP_E_IO;
            }
            FT_Bitmap *bm = &face->glyph->bitmap;
            if (x + (int)bm->width + PAD > f->aw) {
                x = PAD;
                y += shelf + PAD;
                shelf = 0;
            }
            *g = (struct glyph){x, y, (int)bm->width, (int)bm->rows, face->glyph->bitmap_left,
                                face->glyph->bitmap_top,
                                (int)((face->glyph->advance.x + 32) >> 6), index != 0, index};
            if (f->atlas)
                for (unsigned r = 0; r < bm->rows; r++)
                    memcpy(f->atlas + (size_t)(y + r) * f->aw + x,
                           bm->buffer + (ptrdiff_t)r * bm->pitch, bm->width);
            x += (int)bm->width + PAD;
            shelf = (int)bm->rows > shelf ? (int)bm->rows : shelf;
        }
        f->cap[s] = f->g[s][glyph_slot('H')].top;
    }
    f->ah = y + shelf + PAD;
    return 0;
}

int sp_font_make(struct sp_font **out, const int px[SP_TEXT_SIZES])
{
    struct sp_font *f = NULL;
    FT_Library lib = NULL;
    FT_Face face = NULL;
    int err = SP_E_IO;

    *out = NULL;
    for (int s = 0; s < SP_TEXT_SIZES; s++)
        if (px[s] < 4 || px[s] > 400) {
            sp_log_error("a text size of %d px is outside 4..400", px[s]);
            return SP_E_INPUT;
        }
    f = calloc(1, sizeof(*f));
    if (!f) {
        sp_log_error("out of memory for the font");
        return SP_E_NOMEM;
    }
    if (FT_Init_FreeType(&lib) ||
        FT_New_Memory_Face(lib, (const FT_Byte *)sp_embed_DejaVuSans_ttf,
                           (FT_Long)sp_embed_DejaVuSans_ttf_size, 0, &face)) {
        sp_log_error("FreeType cannot open the embedded DejaVu Sans");
        goto done;
    }
    memcpy(f->px, px, sizeof(f->px));
    f->aw = px[SP_TEXT_LARGE] > 48 ? 2048 : 1024;
    err = raster_all(f, face, px); /* measure */
    if (err)
        goto done;
    f->atlas = calloc((size_t)f->aw * f->ah, 1);
    if (!f->atlas) {
        sp_log_error("out of memory for a %dx%d glyph atlas", f->aw, f->ah);
        err = SP_E_NOMEM;
        goto done;
    }
    err = raster_all(f, face, px); /* draw */
done:
    if (face)
        FT_Done_Face(face);
    if (lib)
        FT_Done_FreeType(lib);
    if (err)
        sp_font_destroy(&f);
    *out = f;
    return err;
}

void sp_font_destroy(struct sp_font **fp)
{
    if (!*fp)
        return;
    free((*fp)->atlas);
    free(*fp);
    *fp = NULL;
}

int sp_font_has(const struct sp_font *f, uint32_t cp)
{
    int slot = glyph_slot(cp);
    return slot < N_GLYPHS - 1 && f->g[0][slot].present;
}

int sp_font_width(const struct sp_font *f, int size, const char *s)
{
    int w = 0;
    while (*s) {
        const uint32_t cp = utf8_next(&s);
        if (cp < 0x0300 || cp >= 0x0370)
            w += f->g[size][glyph_slot(cp)].advance;
    }
    return w;
}

int sp_font_cap(const struct sp_font *f, int size) { return f->cap[size]; }
int sp_font_line(const struct sp_font *f, int size) { return f->line[size]; }

int sp_font_px(const struct sp_font *f, int size) { return f->px[size]; }

/* Places the glyphs of s with the pen starting at (x, baseline): calls
 * put(g, bitmap x, bitmap y, bytes of its code point) for each code point in
 * order (combining marks centred over the glyph before them, just above it). */
static void place(const struct sp_font *f, int size, const char *s, float x, float baseline,
                  void (*put)(void *ctx, const struct glyph *g, int gx, int gy, int bytes),
                  void *ctx)
{
    int pen = (int)lroundf(x), base = (int)lroundf(baseline);
    const struct glyph *prev = NULL;
    int prev_pen = pen;
    while (*s) {
        const char *start = s;
        const uint32_t cp = utf8_next(&s);
        const struct glyph *g = &f->g[size][glyph_slot(cp)];
        const int combining = cp >= 0x0300 && cp < 0x0370 && prev;
        int gx = pen + g->left, gy = base - g->top;
        if (combining) {
            gx = prev_pen + prev->left + (prev->w - g->w) / 2;
            gy = base - prev->top - g->h - (f->cap[size] + 9) / 10;
        }
        put(ctx, g, gx, gy, (int)(s - start));
        if (combining)
            continue;
        prev = g;
        prev_pen = pen;
        pen += g->advance;
    }
}

struct quad_ctx {
    const float *color;
    struct sp_glyph_quad *out;
    int max, n;
};

static void put_quad(void *ctx, const struct glyph *g, int gx, int gy, int bytes)
{
    struct quad_ctx *q = ctx;
    (void)bytes;
    if (g->w <= 0 || g->h <= 0)
        return;
    if (q->n < q->max) {
        const float x0 = (float)gx, y0 = (float)gy;
        q->out[q->n] = (struct sp_glyph_quad){
            {x0, y0, x0 + g->w, y0 + g->h},
            {(float)g->x, (float)g->y, (float)(g->x + g->w), (float)(g->y + g->h)},
            {q->color[0], q->color[1], q->color[2], q->color[3]}};
    }
    q->n++;
}

int sp_font_layout(const struct sp_font *f, int size, const char *s, float x,
                   float baseline, const float color[4], struct sp_glyph_quad *out, int max)
{
    struct quad_ctx q = {color, out, max, 0};
    place(f, size, s, x, baseline, put_quad, &q);
    return q.n;
}

struct pos_ctx {
    struct sp_glyph_pos *out;
    int max, n;
};

static void put_pos(void *ctx, const struct glyph *g, int gx, int gy, int bytes)
{
    struct pos_ctx *q = ctx;
    if (q->n < q->max) /* the outline's origin, where its bitmap would sit at gx, gy */
        q->out[q->n] = (struct sp_glyph_pos){g->index, (float)(gx - g->left),
                                             (float)(gy + g->top), bytes};
    q->n++;
}

int sp_font_glyphs(const struct sp_font *f, int size, const char *s, float x, float baseline,
                   struct sp_glyph_pos *out, int max)
{
    struct pos_ctx q = {out, max, 0};
    place(f, size, s, x, baseline, put_pos, &q);
    return q.n;
}

const uint8_t *sp_font_atlas(const struct sp_font *f, int *w, int *h)
{
    *w = f->aw;
    *h = f->ah;
    return f->atlas;
}

void sp_font_blit(const struct sp_font *f, const struct sp_glyph_quad *q, int n,
                  uint8_t *img, int w, int h)
{
    for (int i = 0; i < n; i++) {
        const int x0 = (int)q[i].rect[0], y0 = (int)q[i].rect[1];
        const int u0 = (int)q[i].uv[0], v0 = (int)q[i].uv[1];
        const int gw = (int)(q[i].uv[2] - q[i].uv[0]), gh = (int)(q[i].uv[3] - q[i].uv[1]);
        for (int y = 0; y < gh; y++)
            for (int x = 0; x < gw; x++) {
                if (x0 + x < 0 || x0 + x >= w || y0 + y < 0 || y0 + y >= h)
                    continue;
                uint8_t *d = img + (size_t)(y0 + y) * w + x0 + x;
                const uint8_t a = f->atlas[(size_t)(v0 + y) * f->aw + u0 + x];
                *d = a > *d ? a : *d;
            }
    }
}
