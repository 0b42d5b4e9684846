/* springpend (internal): shaped text drawn with cairo. See cairo_text.h. */
#include <stdlib.h>
#include <string.h>

#include <cairo-pdf.h>
#include <cairo-ft.h>
#include <ft2build.h>
#include FT_FREETYPE_H

#include "springpend/common.h"
#include "base/array.h"
#include "cairo_text.h"

/* A cairo face's FreeType face and what keeps its bytes alive. */
struct ft_kept {
    FT_Face face;
    void *keep; /* sp_font_face_keep's */
};

static void ft_face_done(void *p)
{
    struct ft_kept *k = p;
    FT_Done_Face(k->face);
    sp_font_face_release(k->keep); /* after FreeType, which reads them */
    free(k);
}

/* Face i of the font as a cairo face, made on first use: its own FT_Face
 * (which cairo sizes as it likes) on the bytes the font drew with and
 * hashed (sp_font_face_file: the file is not read again), freed with
 * them when cairo lets go of the face. NULL when it cannot be made
 * (logged). */
static cairo_font_face_t *face_of(struct sp_cairo_faces *fs, int i)
{
    static FT_Library lib; /* for the process: cairo's caches may outlive a document */
    static const cairo_user_data_key_t key;
    const unsigned char *data;
    size_t size;
    int index;
    FT_Face face;
    if (i >= fs->n) { /* a fallback face added since the faces were made */
        if (SP_ARRAY_RESERVE(fs->face, fs->cap, (size_t)i + 1, 0)) {
            sp_log_error("out of memory for the fonts");
            return NULL;
        }
        memset(fs->face + fs->n, 0, (size_t)(i + 1 - fs->n) * sizeof(*fs->face));
        fs->n = i + 1;
    }
    if (fs->face[i])
        return fs->face[i];
    const char *file = sp_font_face_file(fs->font, i, &index, &data, &size);
    struct ft_kept *k;
    if (!data) /* said */
        return NULL;
    if (!(k = calloc(1, sizeof(*k)))) {
        sp_log_error("out of memory for the fonts");
        return NULL;
    }
    if ((!lib && FT_Init_FreeType(&lib)) ||
        FT_New_Memory_Face(lib, data, (FT_Long)size, index, &face)) {
        sp_log_error("FreeType cannot open the font %s", file ? file : SP_FONT_EMBEDDED);
        free(k);
        return NULL;
    }
    k->face = face;
    k->keep = sp_font_face_keep(fs->font, i);
    cairo_font_face_t *cf = cairo_ft_font_face_create_for_ft_face(face, FT_LOAD_NO_HINTING);
    if (cairo_font_face_status(cf) ||
        cairo_font_face_set_user_data(cf, &key, k, ft_face_done)) {
        sp_log_error("cairo cannot use the font %s: %s", file ? file : SP_FONT_EMBEDDED,
                     cairo_status_to_string(cairo_font_face_status(cf)));
        cairo_font_face_destroy(cf);
        ft_face_done(k);
        return NULL;
    }
    return fs->face[i] = cf;
}

int sp_cairo_faces_make(struct sp_cairo_faces *fs, const struct sp_font *f, cairo_t *cr)
{
    fs->font = f;
    fs->n = sp_font_faces(f);
    fs->face = calloc((size_t)fs->n + 1, sizeof(*fs->face));
    fs->cap = fs->n + 1;
    if (!fs->face) {
        sp_log_error("out of memory for the fonts");
        return SP_E_NOMEM;
    }
    cairo_font_options_t *fo = cairo_font_options_create();
    cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_NONE);
    cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
    cairo_set_font_options(cr, fo);
    cairo_font_options_destroy(fo);
    return 0;
}

void sp_cairo_faces_destroy(struct sp_cairo_faces *fs)
{
    for (int i = 0; fs->face && i < fs->n; i++)
        cairo_font_face_destroy(fs->face[i]); /* cairo keeps what it still uses */
    free(fs->face);
    fs->face = NULL, fs->n = fs->cap = 0;
}

/* Whether run r stands for its whole stretch (sp_glyph_run): on a PDF page,
 * a stretch of several runs of one face is drawn once, by the run that
 * starts it, as one cluster: its glyphs left to right and its text in the
 * string's order, which cairo writes as one /ActualText. poppler's
 * pdftotext (22.12) puts a right-to-left line's text back in order from
 * where its characters lie, and keeps a stretch of digits, Latin and the
 * spaces between them in page order: "2 m/s" drawn as "m/s 2" (the
 * bidirectional algorithm's order) comes back as "m/s 2", but as "2 m/s"
 * from the ActualText, which it spreads left to right over the stretch.
 * Only a PDF keeps clusters; an SVG draws the same glyphs either way, run
 * by run as before. *first, *last: the stretch's runs (left to right);
 * 0 for a run drawn alone. */
static int stretch_of(cairo_t *cr, const struct sp_line *l, int r, int *first, int *last)
{
    const struct sp_glyph_run *run = &l->runs[r];
    if ((run->span_start == run->start && run->span_end == run->end) ||
        cairo_surface_get_type(cairo_get_target(cr)) != CAIRO_SURFACE_TYPE_PDF)
        return 0;
    *first = *last = r;
    while (*first > 0 && l->runs[*first - 1].span_start == run->span_start)
        --*first;
    while (*last + 1 < l->n_runs && l->runs[*last + 1].span_start == run->span_start)
        ++*last;
    /* whole only when its neighbours on the line hold all its text: a
     * stretch that an isolate's deeper level splits on the line (an LRM,
     * then an LRI's digits, in a right-to-left line) is drawn run by run,
     * every run of it, or the pieces the starting run does not reach would
     * be lost (attack10 #1) */
    int bytes = 0;
    for (int k = *first; k <= *last; k++)
        bytes += l->runs[k].end - l->runs[k].start;
    if (bytes != run->span_end - run->span_start)
        return 0;
    const struct sp_glyph *g = l->glyphs + l->runs[*first].first;
    const int n = l->runs[*last].first + l->runs[*last].count - l->runs[*first].first;
    for (int k = 1; k < n; k++)
        if (g[k].face != g[0].face)
            return 0;
    return n > 0;
}

int sp_cairo_text_show(cairo_t *cr, struct sp_cairo_faces *fs, int size, double x, double y,
                       const char *utf8)
{
    struct sp_line l;
    int err = sp_font_shape(fs->font, size, utf8, &l);
    cairo_glyph_t *g = malloc((size_t)(l.n_glyphs + 1) * sizeof(*g));
    cairo_text_cluster_t *cl = malloc((size_t)(l.n_glyphs + 1) * sizeof(*cl));
    if (!err && (!g || !cl)) {
        sp_log_error("out of memory for a text run");
        err = SP_E_NOMEM;
    }
    cairo_set_font_size(cr, sp_font_px(fs->font, size));
    /* runs in the text's order, so that a PDF holds the text as written
     * (pdftotext -raw returns it whole; the layout itself is visual) */
    for (int r = 0, from = -1; r < l.n_runs && !err; r++) {
        const struct sp_glyph_run *run = NULL;
        for (int k = 0; k < l.n_runs; k++)
            if (l.runs[k].start > from && (!run || l.runs[k].start < run->start))
                run = &l.runs[k];
        from = run->start;
        const struct sp_glyph *rg = l.glyphs + run->first;
        cairo_font_face_t *face = face_of(fs, rg[0].face);
        int n_cl = 0, first, last;
        if (!face) {
            err = SP_E_IO;
            break;
        }
        if (stretch_of(cr, &l, (int)(run - l.runs), &first, &last)) {
            if (run->start != run->span_start)
                continue; /* drawn with the run that starts its stretch */
            const struct sp_glyph *sg = l.glyphs + l.runs[first].first;
            const int n = l.runs[last].first + l.runs[last].count - l.runs[first].first;
            for (int k = 0; k < n; k++)
                g[k] = (cairo_glyph_t){sg[k].index, x + sg[k].x, y + sg[k].y};
            cl[0] = (cairo_text_cluster_t){run->span_end - run->span_start, n};
            cairo_set_font_face(cr, face);
            cairo_show_text_glyphs(cr, utf8 + run->span_start, run->span_end - run->span_start, g,
                                   n, cl, 1, 0);
            continue;
        }
        /* glyphs in the text's order (a right-to-left run's from its
         * right end: cairo 1.16 checks backward clusters' UTF-8 from the
         * wrong end), each cluster its glyphs and the text up to the next */
        for (int k = 0; k < run->count; k++) {
            const struct sp_glyph *gk = &rg[run->rtl ? run->count - 1 - k : k];
            g[k] = (cairo_glyph_t){gk->index, x + gk->x, y + gk->y};
            if (k && gk->cluster == (gk + (run->rtl ? 1 : -1))->cluster) {
                cl[n_cl - 1].num_glyphs++;
                continue;
            }
            int end = run->end; /* where this cluster's text stops */
            for (int j = k + 1; j < run->count; j++) {
                const struct sp_glyph *gj = &rg[run->rtl ? run->count - 1 - j : j];
                if (gj->cluster != gk->cluster) {
                    end = gj->cluster;
                    break;
                }
            }
            cl[n_cl++] = (cairo_text_cluster_t){end - gk->cluster, 1};
        }
        cairo_set_font_face(cr, face);
        cairo_show_text_glyphs(cr, utf8 + run->start, run->end - run->start, g, run->count, cl,
                               n_cl, 0);
    }
    free(g), free(cl);
    return err;
}

void sp_cairo_pdf_fonts(cairo_surface_t *pdf, const struct sp_font *f)
{
    char names[2048];
    sp_cairo_font_names(f, names, sizeof(names));
    cairo_pdf_surface_set_metadata(pdf, CAIRO_PDF_METADATA_KEYWORDS, names);
}

void sp_cairo_font_names(const struct sp_font *f, char *names, size_t size)
{
    char files[2048];
    size_t n = (size_t)snprintf(names, size, "fonts: ");
    sp_font_files(f, files, sizeof(files));
    for (char *e = files; *e;) { /* ", "-separated paths, each cut to its name */
        char *end = strstr(e, ", "), *name = e;
        if (end)
            *end = 0;
        for (char *c = e; *c; c++)
            if (*c == '/')
                name = c + 1;
        char shown[1024]; /* a file name need not be UTF-8; cairo takes only UTF-8 */
        sp_text_shown(name, 0, shown, sizeof(shown));
        const int w = snprintf(names + n, size - n, "%s%s", e == files ? "" : ", ", shown);
        n += w > 0 && (size_t)w < size - n ? (size_t)w : 0;
        e = end ? end + 2 : e + strlen(e);
    }
}
