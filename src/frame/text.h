/* springpend (internal): text layout, the one place where strings become
 * glyphs. CPU only (no GL, no cairo), shared by every backend:
 *   - fonts: a fontconfig family (the default: DejaVu Sans, embedded at
 *     build time so that every machine draws the same glyphs) and, for a
 *     character it lacks, the next font that fontconfig offers for it
 *     (FcFontSort: fonts-noto-core, fonts-noto-cjk...);
 *   - bidirectional text: FriBidi's embedding levels and reordering;
 *   - shaping: HarfBuzz, run by run (one font, script and direction each),
 *     so Arabic letters join, Devanagari clusters form and marks sit on
 *     their bases;
 *   - glyphs: FreeType rasterises each (font, size, glyph) once, on first
 *     use, into a glyph cache (an R8 atlas that grows), from which the GL
 *     backend draws textured quads (draw_gl.c); cairo draws the same glyphs'
 *     outlines at the same pen positions with their text (draw_cairo.c).
 * Positions are whole pixels (each advance rounded), so the same string
 * always gives the same pixels. Strings are laid out on one line;
 * sp_font_wrap breaks a text into lines of a width.
 * Shared with: compare, render, sweep (layout and shaping for reports,
 * figures and their titles). */
#ifndef SPRINGPEND_TEXT_H
#define SPRINGPEND_TEXT_H

#include <stddef.h>
#include <stdint.h>

enum sp_text_size { SP_TEXT_SMALL, SP_TEXT_NORMAL, SP_TEXT_LARGE, SP_TEXT_TITLE, SP_TEXT_SIZES };

/* The default family: the embedded DejaVu Sans. */
#define SP_FONT_DEFAULT "DejaVu Sans"
/* How provenance names it (springpend.fonts, a PDF's /Keywords, the
 * environment's font line): no file of the system. */
#define SP_FONT_EMBEDDED "DejaVu Sans (embedded in springpend)"

/* One glyph on screen; layout matches the attributes of shaders/text.vert. */
struct sp_glyph_quad {
    float rect[4];  /* x0, y0, x1, y1: px, y down from the top-left corner */
    float uv[4];    /* the atlas rectangle, texels */
    float color[4]; /* straight RGBA, 0..1 */
};

#include "base/utf8.h"

struct sp_font;

struct sp_font_desc {
    const char *family;    /* fontconfig family; NULL or "" = SP_FONT_DEFAULT */
    const char *where;     /* where family was set ("FILE:LINE", "--set view.font"),
                              for the refusal; NULL or "" = "[view] font" */
    int px[SP_TEXT_SIZES]; /* em sizes, px, each 4..400 */
    int whole_lines;       /* 1: every line shaped whole, never joined from
                            * cached pieces (for tests and benchmarks: the
                            * glyphs are the same) */
};


/* Finds the family and its fallbacks. 0; SP_E_INPUT for a size outside
 * 4..400 or a family that fontconfig does not know (the message lists the
 * installed families nearest to it); SP_E_NOMEM / SP_E_IO (the library's
 * words logged). */
int sp_font_make(struct sp_font **out, const struct sp_font_desc *d);

/* Frees the font and sets *f to NULL. Safe on NULL. */
void sp_font_destroy(struct sp_font **f);

/* 1 when some font of the family's fallback list has a glyph for cp. */
int sp_font_has(const struct sp_font *f, uint32_t cp);

/* 0 when every character of utf8 has a glyph in some installed font (the
 * invisible format characters need none); else SP_E_INPUT, having logged
 * "WHAT: U+XXXX ('c') is in no installed font (tried: A, B, ...)". Also
 * SP_E_INPUT for malformed UTF-8. */
int sp_font_check(const struct sp_font *f, const char *what, const char *utf8);

/* One glyph of a laid-out line. */
struct sp_glyph {
    unsigned index; /* the glyph's index in its face */
    int face;       /* which face (sp_font_face_file) */
    int x, y;       /* its origin, px from the pen start on the baseline, y down */
    int cluster;    /* byte offset in the string of the first character it shows */
    int mark;       /* 1: a mark (GDEF) placed on the glyph before it */
};

/* A run of glyphs from one face in one direction. */
struct sp_glyph_run {
    int first, count; /* its glyphs */
    int rtl;          /* 1: its glyphs, left to right, show its text backwards */
    int start, end;   /* its bytes of the string, [start, end) */
    /* The stretch of the string it belongs to, bytes: runs of a left-to-right
     * stretch inside a right-to-left line, and the spaces between them (a
     * number and a unit, "2 m/s" in "البندول 2 m/s", which is "m/s", " ", "2"
     * on the line), all have the stretch's [span_start, span_end): contiguous
     * in the string, and on the line but where an isolate's deeper level splits
     * it (an LRM, then an LRI's digits: cairo_text.c then draws each run alone).
     * Every other run has its own [start, end). */
    int span_start, span_end;
};

/* A string laid out on one line: glyphs and runs left to right (visual
 * order). Owned by the font; valid until the next call on it. */
struct sp_line {
    int width;   /* the advance of the whole line, px */
    int missing; /* characters no font has (drawn as the primary font's missing glyph) */
    int n_glyphs, n_runs;
    const struct sp_glyph *glyphs;
    const struct sp_glyph_run *runs;
};

/* Lays utf8 out at a text size. Results are cached by (size, string), in
 * the font: at most 4096 lines (and the pieces of one); when full, the lines
 * not used during the last 2048 look-ups are dropped. A new line that
 * differs from cached ones in its digits (a clock) is joined from cached
 * pieces where HarfBuzz says that gives the same glyphs as shaping it whole
 * (see compose in text.c). 0 or SP_E_NOMEM. A character no font has shows the primary font's
 * missing glyph and counts in out->missing. */
int sp_font_shape(const struct sp_font *f, int size, const char *utf8, struct sp_line *out);

/* Advance width of a UTF-8 string, px. */
int sp_font_width(const struct sp_font *f, int size, const char *utf8);

/* Wraps utf8 into lines of at most max_width px at text size `size`: at
 * spaces, and a word wider than a line between its characters (never
 * before a mark or joiner), so CJK, which has no spaces, wraps too. A
 * character too wide alone stays whole, wider than max_width (the caller
 * measures each line and refuses). Stops once it has more than max_lines
 * lines (the caller refuses those too), so one long word costs no more than
 * the lines that could be shown. *out holds the lines one after another,
 * each NUL-terminated (malloc'd: free it); *n_out their count. 0 or
 * SP_E_NOMEM (logged). */
int sp_font_wrap(const struct sp_font *f, int size, const char *utf8, float max_width,
                 int max_lines, char **out, int *n_out);

/* Height of a capital letter above the baseline, and the line spacing, px
 * (of the requested family). */
int sp_font_cap(const struct sp_font *f, int size);
int sp_font_line(const struct sp_font *f, int size);

/* Lays out utf8 with its pen starting at (x, baseline) (rounded to whole px)
 * into out[0..max), rasterising glyphs not yet in the cache. Returns how
 * many quads the string needs (which may exceed max: then only max were
 * written), or a negative SP_E_* code (out of memory, or the atlas larger
 * than 2048 x 16384). */
int sp_font_layout(const struct sp_font *f, int size, const char *utf8, float x,
                   float baseline, const float color[4], struct sp_glyph_quad *out,
                   int max);

/* The em size of a text size, px. */
int sp_font_px(const struct sp_font *f, int size);

/* How many faces the fallback list holds (sp_glyph.face is below it). */
int sp_font_faces(const struct sp_font *f);

/* Face i's font file (NULL: the embedded DejaVu Sans), its index in it,
 * and the bytes it is drawn from, *data (*size bytes): the file as read
 * once when the face was opened (opened now if it was not), which the
 * provenance's SHA-256 is of; *data = NULL when it cannot be read
 * (logged). They live as long as the font, or as a sp_font_face_keep. */
const char *sp_font_face_file(const struct sp_font *f, int face, int *index,
                              const unsigned char **data, size_t *size);

/* A reference that keeps face i's bytes alive beyond the font (cairo's
 * caches may outlive it), NULL for the embedded one (static); give it back
 * with sp_font_face_release (NULL is fine). */
void *sp_font_face_keep(const struct sp_font *f, int face);
void sp_font_face_release(void *keep);

/* The files of the faces laid out so far, "DejaVu Sans (embedded in
 * springpend), /usr/share/.../NotoSansArabic-Regular.ttf" (SP_FONT_EMBEDDED
 * for the built-in one), into buf (cut to size). */
void sp_font_files(const struct sp_font *f, char *buf, size_t size);

/* Adds a "font NAME: sha256 ..." line to the environment text in buf for
 * each font file that sp_font_files names (the embedded font has its own
 * line already), the hash of the bytes the face is drawn from
 * (sp_font_face_file's), taken once per font: sp_environment_add_font. 0,
 * or its SP_E_* code. */
int sp_font_environment(const struct sp_font *f, char *buf, size_t size);

/* The R8 glyph cache: *w x *h bytes, row 0 first. Owned by f; it grows and
 * gains glyphs as strings are laid out: *version changes whenever its
 * contents or size did. */
const uint8_t *sp_font_atlas(const struct sp_font *f, int *w, int *h, unsigned *version);

/* Glyphs rasterised so far and the seconds that took. */
void sp_font_raster_stats(const struct sp_font *f, int *glyphs, double *seconds);

/* Lines laid out so far: shaped whole by HarfBuzz, and joined from cached
 * pieces (sp_font_shape). */
void sp_font_shape_stats(const struct sp_font *f, int *shaped, int *composed);

/* Draws quads into an 8-bit coverage image (w x h, stride w) on the CPU by
 * copying atlas texels, the way the GL pass samples them (nearest). For tests. */
void sp_font_blit(const struct sp_font *f, const struct sp_glyph_quad *q, int n,
                  uint8_t *img, int w, int h);

#endif
