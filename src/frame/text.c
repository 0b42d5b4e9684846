/* springpend (internal): text layout with fontconfig, FriBidi, HarfBuzz and
 * FreeType, and the glyph cache. See text.h.
 *
 * The font is handed around as const (the draw list and the backends only
 * read it); its caches (faces opened on first use, shaped lines, the atlas)
 * are filled behind that handle, so the functions below cast the const
 * away: every struct sp_font is allocated writable by sp_font_make. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <fontconfig/fontconfig.h>
#include <fribidi.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include <hb.h>
#include <hb-ot.h>

#include "base/array.h"
#include "base/clock.h"
#include "base/digest.h"
#include "springpend/common.h"
#include "springpend/environment.h"
#include "base/embedded.h"
#include "text.h"

#define PAD 1                /* texels around each glyph in the atlas */
#define ATLAS_MAX_H 16384    /* texels: what GL implementations allow */
#define LINE_CACHE_MAX 4096  /* shaped lines kept (see lines_trim) */
#define LINE_BUCKETS 1024
#define LOAD_FLAGS (FT_LOAD_RENDER | FT_LOAD_TARGET_LIGHT | FT_LOAD_NO_BITMAP)

/* One font of the fallback list. Opened on first use. */
struct face {
    FcPattern *pat;             /* fontconfig's description (in sorted); NULL = embedded */
    const char *file;           /* FC_FILE, NULL = embedded */
    int index;                  /* face index in the file */
    FcCharSet *cs;              /* coverage (fontconfig's), NULL = ask FreeType */
    FT_Face ft;                 /* NULL until opened */
    int ft_px;                  /* the size ft is set to, px; 0 = none */
    hb_face_t *hb_face;
    hb_font_t *hb[SP_TEXT_SIZES];
    int used;                   /* laid out at least once */
    /* A file's bytes, read once when the face is opened: FreeType,
     * HarfBuzz, cairo (sp_font_face_keep) and the SHA-256 of the
     * provenance all use these, so the hash is of the very bytes drawn,
     * whatever happens to the file afterwards. NULL = embedded. */
    hb_blob_t *blob;
    char sha[65];               /* their SHA-256, "" until asked */
};

/* A rasterised glyph in the atlas; key 0 = empty slot. */
struct cached {
    uint64_t key;               /* (face + 1) << 32 | size << 28 | glyph index */
    int x, y, w, h;             /* atlas texels */
    int left, top;              /* bitmap offset from the origin, px (top: up) */
};

/* A glyph of a laid-out line as sp_font_layout draws it: its quad relative
 * to the pen start and the baseline, px (a mark already moved clear of its
 * base), and its atlas rectangle, texels. Worked out once per line, when
 * its glyphs are rasterised; a frame then only adds the pen position. */
struct placed {
    int x, y, w, h;
    float uv[4];
};

/* A shaped line, cached by (size, script hint, text). */
struct shaped {
    struct shaped *next;
    uint32_t hash;
    int size;
    hb_script_t hint;           /* the script of leading common characters; INVALID: their own */
    unsigned long used;         /* f->lookups when last looked up (the eviction rule) */
    char *text;
    size_t len;                 /* its bytes */
    hb_script_t script;         /* the script of its first run */
    int bidi;                   /* 1: it holds right-to-left or explicit-direction characters */
    int unsafe;                 /* HarfBuzz's "unsafe to concat" on its first glyph (1), on
                                 * its last (2): its shape there depends on text beside it */
    struct sp_line line;
    struct sp_glyph *g;
    struct sp_glyph_run *r;
    struct placed *place;       /* its quads; NULL until rasterised (sp_font_layout) */
    int n_place;                /* how many: its glyphs with ink */
};

struct sp_font {
    FT_Library lib;
    FcFontSet *sorted;          /* fontconfig's fallback order, owned */
    struct face *faces;         /* [0]: the requested family */
    int n_faces, cap_faces;     /* in use, room for */
    int fallback_pending;       /* the default's fallbacks are not listed yet */
    int px[SP_TEXT_SIZES];      /* em sizes, px */
    int cap[SP_TEXT_SIZES], line[SP_TEXT_SIZES]; /* px */
    /* glyph cache */
    struct cached *slots;
    size_t n_slots, used_slots; /* capacity (a power of two), filled */
    uint8_t *atlas;             /* R8, aw x ah */
    int aw, ah;
    int shelf_x, shelf_y, shelf_h; /* the packer's free corner and its row height, texels */
    unsigned version;
    int rastered;               /* glyphs rasterised */
    double raster_s;            /* seconds spent on them */
    /* shaped lines */
    struct shaped *buckets[LINE_BUCKETS];
    int n_lines;
    struct shaped *last;        /* the line line_get returned last, or NULL */
    unsigned long lookups;      /* line look-ups so far */
    int whole;                  /* 1: every line shaped whole (sp_font_desc.whole_lines) */
    int n_shaped, n_composed;   /* lines shaped whole, lines joined from cached pieces */
    hb_buffer_t *buf;
};

/* Format characters that show nothing and need no glyph: zero-width
 * space and (non-)joiners, direction marks and embeddings, word joiner
 * and invisible operators, variation selectors, the byte order mark. */
static int invisible(uint32_t cp)
{
    return (cp >= 0x200B && cp <= 0x200F) || (cp >= 0x202A && cp <= 0x202E) ||
           (cp >= 0x2060 && cp <= 0x2064) || (cp >= 0x2066 && cp <= 0x2069) ||
           (cp >= 0xFE00 && cp <= 0xFE0F) || cp == 0xFEFF || (cp >= 0xE0100 && cp <= 0xE01EF);
}

/* ---- faces ---- */

static int face_covers(const struct face *fc, uint32_t cp)
{
    if (fc->cs)
        return FcCharSetHasChar(fc->cs, cp);
    return fc->ft && FT_Get_Char_Index(fc->ft, cp) != 0;
}

static int sort_fonts(struct sp_font *f, const char *family, int verify, const char *where);

/* The first face that has cp, else -1 (the default's fallbacks listed
 * first when they are not yet). */
static int face_for(const struct sp_font *cf, uint32_t cp)
{
    struct sp_font *f = (struct sp_font *)cf; /* its caches (see the top) */
    for (int i = 0; i < f->n_faces; i++)
        if (face_covers(&f->faces[i], cp))
            return i;
    const int listed = f->n_faces;
    if (!f->fallback_pending || sort_fonts(f, SP_FONT_DEFAULT, 0, NULL))
        return -1; /* (a failure to list them was said) */
    for (int i = listed; i < f->n_faces; i++)
        if (face_covers(&f->faces[i], cp))
            return i;
    return -1;
}

/* The font file at path, read whole into a blob that owns its bytes
 * (freed with the last reference), or NULL (logged). A font file is at
 * most FONT_FILE_MAX bytes (Noto Serif CJK, the largest of Debian's, is
 * 26 MB). */
#define FONT_FILE_MAX (256L << 20)
static hb_blob_t *read_font_file(const char *path)
{
    FILE *fp = fopen(path, "rb");
    char *data = NULL;
    long n = -1;
    size_t got = 0;
    if (fp && !fseek(fp, 0, SEEK_END) && (n = ftell(fp)) >= 0 && n <= FONT_FILE_MAX &&
        !fseek(fp, 0, SEEK_SET) && (data = malloc(n ? (size_t)n : 1)))
        got = fread(data, 1, (size_t)n, fp);
    const int bad = !fp || n < 0 || n > FONT_FILE_MAX || !data || got != (size_t)n || ferror(fp);
    if (bad)
        sp_log_error("%s: cannot read the font file%s", path,
                     n > FONT_FILE_MAX ? ": larger than 256 MiB" : !data && n >= 0 && fp
                                                                 ? ": out of memory" : "");
    if (fp)
        fclose(fp);
    if (bad) {
        free(data);
        return NULL;
    }
    return hb_blob_create(data, (unsigned)n, HB_MEMORY_MODE_READONLY, data, free);
}

/* Face i's bytes: the file's as read (struct face's blob), or the
 * embedded font's. */
static const char *face_bytes(const struct face *fc, unsigned *n)
{
    if (!fc->file) {
        *n = (unsigned)sp_embed_DejaVuSans_ttf_size;
        return (const char *)sp_embed_DejaVuSans_ttf;
    }
    return hb_blob_get_data(fc->blob, n);
}

/* Opens face i for FreeType and HarfBuzz (once), both from the same bytes
 * in memory (read_font_file). */
static int face_open(struct sp_font *f, int i)
{
    struct face *fc = &f->faces[i];
    hb_blob_t *blob;
    unsigned n;
    if (fc->hb_face)
        return 0;
    if (fc->file && !fc->blob && !(fc->blob = read_font_file(fc->file)))
        return SP_E_IO;
    const char *data = face_bytes(fc, &n);
    if (!fc->ft) {
        FT_Error e = FT_New_Memory_Face(f->lib, (const FT_Byte *)data, (FT_Long)n,
                                        fc->file ? fc->index : 0, &fc->ft);
        if (e) {
            sp_log_error("FreeType cannot open the font %s: %s",
                         fc->file ? fc->file : SP_FONT_EMBEDDED, FT_Error_String(e) ? FT_Error_String(e) : "error");
            fc->ft = NULL;
            return SP_E_IO;
        }
    }
    blob = fc->file ? hb_blob_reference(fc->blob)
                    : hb_blob_create(data, n, HB_MEMORY_MODE_READONLY, NULL, NULL);
    fc->hb_face = hb_face_create(blob, (unsigned)fc->index);
    hb_blob_destroy(blob);
    for (int s = 0; s < SP_TEXT_SIZES; s++) {
        fc->hb[s] = hb_font_create(fc->hb_face);
        hb_font_set_scale(fc->hb[s], f->px[s] * 64, f->px[s] * 64); /* 26.6 px */
    }
    if (!hb_face_get_glyph_count(fc->hb_face)) {
        sp_log_error("HarfBuzz cannot read the font %s", fc->file ? fc->file : "DejaVu Sans");
        return SP_E_IO;
    }
    return 0;
}

static void face_close(struct face *fc)
{
    for (int s = 0; s < SP_TEXT_SIZES; s++)
        hb_font_destroy(fc->hb[s]);
    hb_face_destroy(fc->hb_face);
    if (fc->ft)
        FT_Done_Face(fc->ft);
    hb_blob_destroy(fc->blob); /* after FreeType, which reads it */
}

/* The family name of face i, for messages. */
static const char *face_family(const struct sp_font *f, int i)
{
    FcChar8 *name = NULL;
    if (!f->faces[i].pat)
        return SP_FONT_DEFAULT;
    FcPatternGetString(f->faces[i].pat, FC_FAMILY, 0, &name);
    return name ? (const char *)name : "?";
}

/* Levenshtein distance of two short strings, case ignored. */
static int distance(const char *a, const char *b)
{
    int la = (int)strlen(a), lb = (int)strlen(b), row[128];
    if (la > 127 || lb > 127)
        return 1000;
    for (int j = 0; j <= lb; j++)
        row[j] = j;
    for (int i = 1; i <= la; i++) {
        int diag = row[0];
        row[0] = i;
        for (int j = 1; j <= lb; j++) {
            const int up = row[j];
            const int same = FcToLower((FcChar8)a[i - 1]) == FcToLower((FcChar8)b[j - 1]);
            int v = diag + !same;
            v = up + 1 < v ? up + 1 : v;
            v = row[j - 1] + 1 < v ? row[j - 1] + 1 : v;
            row[j] = v;
            diag = up;
        }
    }
    return row[lb];
}

/* Logs that the font key's `value` is wrong: `why`, or (why NULL) that its
 * name `family` is not installed, with up to six installed families nearest
 * to it (a prefix or part of the name counts as near). */
static void unknown_family(const char *value, const char *family, const char *where,
                           const char *why)
{
    char label[1024]; /* as the scene's messages name a key */
    if (where && !strncmp(where, "--set ", 6))
        snprintf(label, sizeof(label), "%s = \"%s\"", where, value);
    else
        snprintf(label, sizeof(label), "%s%s[view] font = \"%s\"", where ? where : "",
                 where ? ": " : "", value);
    if (strcmp(value, family)) /* a list: which of its names */
        snprintf(label + strlen(label), sizeof(label) - strlen(label), ", its name \"%s\"", family);
    if (why) {
        sp_log_error("%s: %s", label, why);
        return;
    }
    FcPattern *all = FcPatternCreate();
    FcObjectSet *os = FcObjectSetBuild(FC_FAMILY, (char *)NULL);
    FcFontSet *list = all && os ? FcFontList(NULL, all, os) : NULL;
    const char *best[6] = {0};
    int score[6], nb = 0;
    char msg[1024] = "";
    for (int i = 0; list && i < list->nfont; i++) {
        FcChar8 *name;
        for (int k = 0; FcPatternGetString(list->fonts[i], FC_FAMILY, k, &name) == FcResultMatch; k++) {
            const char *n = (const char *)name;
            int d = distance(family, n);
            if (strcasestr(n, family) || strcasestr(family, n))
                d = d < 3 ? d : 3;
            if (d > 3 && d > (int)strlen(family) / 3)
                continue;
            int dup = 0;
            for (int j = 0; j < nb; j++)
                dup |= !strcasecmp(best[j], n);
            if (dup)
                continue;
            int at;
            if (nb < 6)
                at = nb++;
            else if (d >= score[5])
                continue; /* no better than the sixth best */
            else
                at = 5;
            best[at] = n, score[at] = d;
            for (int j = at; j > 0 && score[j] < score[j - 1]; j--) { /* keep sorted */
                const char *tn = best[j]; int ts = score[j];
                best[j] = best[j - 1], score[j] = score[j - 1];
                best[j - 1] = tn, score[j - 1] = ts;
            }
        }
    }
    for (int j = 0; j < nb; j++)
        snprintf(msg + strlen(msg), sizeof(msg) - strlen(msg), "%s\"%s\"", j ? ", " : "", best[j]);
    if (nb)
        sp_log_error("%s: no such font family is installed; close matches: %s (fc-list : "
                     "family lists them all)", label, msg);
    else
        sp_log_error("%s: no such font family is installed, nor one with a similar name "
                     "(fc-list : family lists them all)", label);
    if (list)
        FcFontSetDestroy(list);
    if (os)
        FcObjectSetDestroy(os);
    if (all)
        FcPatternDestroy(all);
}

/* 1 when the pattern's family names include `family` (blanks and case
 * ignored: "latin modern roman" is Latin Modern Roman). */
static int same_name(const char *a, const char *b)
{
    for (;; a++, b++) {
        while (*a == ' ')
            a++;
        while (*b == ' ')
            b++;
        if (FcToLower((FcChar8)*a) != FcToLower((FcChar8)*b))
            return 0;
        if (!*a)
            return 1;
    }
}

/* 1 for fontconfig's generic names, which its configuration maps to an
 * installed family (which one is recorded in the provenance's fonts). */
static int generic_family(const char *family)
{
    static const char *const generic[] = {"sans-serif", "sans", "serif", "monospace", "mono"};
    for (size_t i = 0; i < sizeof(generic) / sizeof(*generic); i++)
        if (!strcasecmp(family, generic[i]))
            return 1;
    return 0;
}

static int has_family(FcPattern *p, const char *family)
{
    FcChar8 *name;
    for (int k = 0; FcPatternGetString(p, FC_FAMILY, k, &name) == FcResultMatch; k++)
        if (same_name((const char *)name, family))
            return 1;
    return 0;
}

/* The n-th name of a family list "A, B, serif" (blanks around each name
 * dropped) into out[size]; 0 past the last name. */
static int list_name(const char *family, int n, char *out, size_t size)
{
    for (; n > 0 && family; n--)
        if ((family = strchr(family, ',')))
            family++;
    if (!family)
        return 0;
    while (*family == ' ')
        family++;
    size_t len = strcspn(family, ",");
    while (len && family[len - 1] == ' ')
        len--;
    snprintf(out, size, "%.*s", (int)len, family);
    return 1;
}

/* 1 when fontconfig has a font of `family` installed (whether or not it
 * adds a character to the names before it in a list, which the trimmed
 * sort leaves out). */
static int installed(const char *family)
{
    FcPattern *p = FcPatternCreate();
    FcObjectSet *os = FcObjectSetBuild(FC_FAMILY, (char *)NULL);
    FcFontSet *set = NULL;
    int found = 0;
    if (p && os && FcPatternAddString(p, FC_FAMILY, (const FcChar8 *)family) &&
        (set = FcFontList(NULL, p, os)) != NULL)
        for (int i = 0; i < set->nfont && !found; i++)
            found = has_family(set->fonts[i], family);
    if (set)
        FcFontSetDestroy(set);
    if (os)
        FcObjectSetDestroy(os);
    if (p)
        FcPatternDestroy(p);
    return found;
}

/* Appends fontconfig's order for `family` to the faces (fonts without
 * outlines, and the embedded font's own file, left out). `family` may be a
 * list, "Latin Modern Roman, serif": fontconfig tries the names in order,
 * so a character the first lacks comes from the next (a serif Greek for a
 * serif family, where fontconfig alone would fall back to sans). With
 * `verify`, a name that fontconfig does not have, or an empty one, is
 * SP_E_INPUT (said). */
static int sort_fonts(struct sp_font *f, const char *family, int verify, const char *where)
{
    FcPattern *pat = NULL;
    FcResult res;
    char name[256]; /* one name of the list (the font key holds 255 bytes) */
    int err = 0;

    f->fallback_pending = 0;
    if (!FcInit()) {
        sp_log_error("fontconfig cannot load its configuration");
        return SP_E_IO;
    }
    if (!(pat = FcPatternCreate())) {
        sp_log_error("out of memory for a font pattern");
        return SP_E_NOMEM;
    }
    for (int n = 0; list_name(family, n, name, sizeof(name)); n++) {
        if (!*name) {
            unknown_family(family, family, where, "an empty name in the font list; write "
                   "family names with one comma between two, as \"Latin Modern Roman, serif\"");
            err = SP_E_INPUT;
            goto done;
        }
        if (!FcPatternAddString(pat, FC_FAMILY, (const FcChar8 *)name)) {
            sp_log_error("out of memory for a font pattern");
            err = SP_E_NOMEM;
            goto done;
        }
    }
    FcConfigSubstitute(NULL, pat, FcMatchPattern);
    FcDefaultSubstitute(pat);
    f->sorted = FcFontSort(NULL, pat, FcTrue, NULL, &res);
    for (int n = 0; verify && list_name(family, n, name, sizeof(name)); n++) {
        /* the first name must be what fontconfig picked first; a later
         * one, installed */
        const int found = generic_family(name) ||
                          (n ? installed(name)
                             : f->sorted && f->sorted->nfont && has_family(f->sorted->fonts[0], name));
        if (!found) {
            unknown_family(family, name, where, NULL);
            err = SP_E_INPUT;
            goto done;
        }
    }
    if (SP_ARRAY_RESERVE(f->faces, f->cap_faces,
                         (size_t)(f->sorted ? f->sorted->nfont : 0) + 1 + (size_t)f->n_faces, 0)) {
        sp_log_error("out of memory for the font list");
        err = SP_E_NOMEM;
        goto done;
    }
    for (int i = 0; f->sorted && i < f->sorted->nfont; i++) {
        FcPattern *p = f->sorted->fonts[i];
        FcChar8 *file = NULL;
        FcBool outline = FcTrue;
        FcCharSet *cs = NULL;
        int index = 0;
        FcPatternGetBool(p, FC_OUTLINE, 0, &outline);
        if (FcPatternGetString(p, FC_FILE, 0, &file) != FcResultMatch || !outline ||
            FcPatternGetCharSet(p, FC_CHARSET, 0, &cs) != FcResultMatch)
            continue;
        FcPatternGetInteger(p, FC_INDEX, 0, &index);
        if (!verify && !strcmp((const char *)file, SP_FONT_FILE))
            continue; /* the embedded one */
        f->faces[f->n_faces++] = (struct face){.pat = p, .file = (const char *)file,
                                               .index = index, .cs = cs};
    }
done:
    if (pat)
        FcPatternDestroy(pat);
    return err;
}

/* The fallback list: the family and then fontconfig's order for it. The
 * default is the embedded DejaVu Sans, and fontconfig is asked only when
 * a character is not in it (so most scenes never load fontconfig). */
static int find_faces(struct sp_font *f, const char *family, const char *where)
{
    int err;
    if (!family || !*family || same_name(family, SP_FONT_DEFAULT)) {
        if (!(f->faces = calloc(1, sizeof(*f->faces)))) {
            sp_log_error("out of memory for the font list");
            return SP_E_NOMEM;
        }
        f->n_faces = f->cap_faces = 1;
        f->fallback_pending = 1;
    } else if ((err = sort_fonts(f, family, 1, where && *where ? where : NULL)) != 0) {
        return err;
    }
    return face_open(f, 0);
}

/* ---- the glyph cache ---- */

static uint64_t glyph_key(int face, int size, unsigned index)
{
    return (uint64_t)(face + 1) << 32 | (uint64_t)size << 28 | (index & 0x0FFFFFFFu);
}

static struct cached *slot_of(const struct sp_font *f, uint64_t key)
{
    size_t i = (size_t)(key * 0x9E3779B97F4A7C15ull >> 20) & (f->n_slots - 1);
    while (f->slots[i].key && f->slots[i].key != key)
        i = (i + 1) & (f->n_slots - 1);
    return &f->slots[i];
}

/* Room for one more entry in the table (doubled at half load). */
static int slots_reserve(struct sp_font *f)
{
    if (2 * (f->used_slots + 1) <= f->n_slots)
        return 0;
    const size_t n = f->n_slots ? 2 * f->n_slots : 1024;
    struct cached *old = f->slots;
    const size_t n_old = f->n_slots;
    f->slots = calloc(n, sizeof(*f->slots));
    if (!f->slots) {
        f->slots = old;
        sp_log_error("out of memory for the glyph cache");
        return SP_E_NOMEM;
    }
    f->n_slots = n;
    for (size_t i = 0; i < n_old; i++)
        if (old[i].key)
            *slot_of(f, old[i].key) = old[i];
    free(old);
    return 0;
}

/* A w x h texel place in the atlas (which grows downwards). */
static int atlas_place(struct sp_font *f, int w, int h, int *x, int *y)
{
    if (f->shelf_x + w + PAD > f->aw) {
        f->shelf_x = PAD;
        f->shelf_y += f->shelf_h + PAD;
        f->shelf_h = 0;
    }
    if (w + 2 * PAD > f->aw)
        return SP_E_INPUT;
    while (f->shelf_y + h + PAD > f->ah) {
        const int nh = f->ah ? 2 * f->ah : 256;
        size_t room = (size_t)f->aw * f->ah; /* bytes at f->atlas */
        if (nh > ATLAS_MAX_H || SP_ARRAY_RESERVE(f->atlas, room, (size_t)f->aw * nh, 0)) {
            sp_log_error("the glyph cache is full (%dx%d texels): too many different glyphs "
                         "or sizes", f->aw, f->ah);
            return SP_E_NOMEM;
        }
        memset(f->atlas + (size_t)f->aw * f->ah, 0, (size_t)f->aw * (nh - f->ah));
        f->ah = nh;
    }
    *x = f->shelf_x;
    *y = f->shelf_y;
    f->shelf_x += w + PAD;
    f->shelf_h = h > f->shelf_h ? h : f->shelf_h;
    return 0;
}

/* The cached glyph (rasterised now when new), or NULL (logged). */
static const struct cached *glyph_get(struct sp_font *f, int face, int size, unsigned index)
{
    const uint64_t key = glyph_key(face, size, index);
    struct cached *c = f->n_slots ? slot_of(f, key) : NULL;
    struct face *fc = &f->faces[face];
    FT_Error e;
    if (c && c->key)
        return c;
    const double t0 = sp_clock_s();
    if (slots_reserve(f) || face_open(f, face))
        return NULL;
    if (fc->ft_px != f->px[size] && FT_Set_Pixel_Sizes(fc->ft, 0, (FT_UInt)f->px[size])) {
        sp_log_error("FreeType cannot size %s to %d px", face_family(f, face), f->px[size]);
        return NULL;
    }
    fc->ft_px = f->px[size];
    if ((e = FT_Load_Glyph(fc->ft, index, LOAD_FLAGS)) != 0 ||
        (fc->ft->glyph->format != FT_GLYPH_FORMAT_BITMAP &&
         (e = FT_Render_Glyph(fc->ft->glyph, FT_RENDER_MODE_LIGHT)) != 0)) {
        sp_log_error("FreeType cannot render glyph %u of %s: %s", index, face_family(f, face),
                     FT_Error_String(e) ? FT_Error_String(e) : "error");
        return NULL;
    }
    const FT_Bitmap *bm = &fc->ft->glyph->bitmap;
    struct cached g = {key, 0, 0, (int)bm->width, (int)bm->rows, fc->ft->glyph->bitmap_left,
                       fc->ft->glyph->bitmap_top};
    if (g.w > 0 && g.h > 0) {
        if (bm->pixel_mode != FT_PIXEL_MODE_GRAY) {
            sp_log_error("%s: glyph %u is not a grey bitmap", face_family(f, face), index);
            return NULL;
        }
        if (atlas_place(f, g.w, g.h, &g.x, &g.y))
            return NULL;
        for (int r = 0; r < g.h; r++)
            memcpy(f->atlas + (size_t)(g.y + r) * f->aw + g.x, bm->buffer + (ptrdiff_t)r * bm->pitch,
                   (size_t)g.w);
        f->version++;
    }
    c = slot_of(f, key);
    *c = g;
    f->used_slots++;
    f->rastered++;
    f->raster_s += sp_clock_s() - t0;
    return c;
}

/* ---- shaping ---- */

/* The line cache's hash of (size, hint, text of len bytes): eight bytes at
 * a step (every frame looks up some hundreds of lines). */
static uint32_t hash_of(int size, hb_script_t hint, const char *s, size_t len)
{
    uint64_t h = ((uint64_t)(unsigned)size << 32 ^ (uint32_t)hint ^ len) * 0x9E3779B97F4A7C15u;
    for (; len >= 8; s += 8, len -= 8) {
        uint64_t w;
        memcpy(&w, s, 8);
        h = (h ^ w) * 0x9E3779B97F4A7C15u;
        h ^= h >> 29;
    }
    uint64_t w = 0;
    for (size_t i = 0; i < len; i++)
        w |= (uint64_t)(unsigned char)s[i] << (8 * i);
    h = (h ^ w) * 0x9E3779B97F4A7C15u;
    return (uint32_t)(h >> 32 ^ h);
}

static void line_free(struct shaped *l)
{
    free(l->text), free(l->g), free(l->r), free(l->place), free(l);
}

/* Drops the lines not looked up during the last `keep` look-ups (all of
 * them for keep 0). The lines kept are the most recently used ones, at most
 * `keep` of them (each look-up stamps one line). */
static void lines_drop(struct sp_font *f, unsigned long keep)
{
    for (int b = 0; b < LINE_BUCKETS; b++)
        for (struct shaped **p = &f->buckets[b]; *p;) {
            struct shaped *l = *p;
            if (keep && l->used + keep > f->lookups) {
                p = &l->next;
                continue;
            }
            *p = l->next;
            if (f->last == l)
                f->last = NULL;
            line_free(l);
            f->n_lines--;
        }
}

/* The eviction rule: once LINE_CACHE_MAX lines are cached, the lines not
 * used during the last LINE_CACHE_MAX / 2 look-ups are dropped, so text
 * drawn every frame stays and one-off strings (a clock's readings) go. */
static void lines_trim(struct sp_font *f)
{
    if (f->n_lines >= LINE_CACHE_MAX)
        lines_drop(f, LINE_CACHE_MAX / 2);
}

/* A run of characters being itemised: [a, b) of the code points. */
struct item {
    int a, b, level, face, vis; /* vis: its leftmost visual position */
    hb_script_t script;
    int span_a, span_b; /* the stretch it belongs to (see sp_glyph_run), code points */
};

static int by_vis(const void *x, const void *y)
{
    const struct item *a = x, *b = y;
    return (a->vis > b->vis) - (a->vis < b->vis);
}

/* The bidi levels of the n characters cp (rule L1 applied by the
 * reordering) into levels, their visual order into map and their classes
 * into types (brackets: room for FriBidi's), the line's own level (0 left
 * to right, 1 right to left) into *base; *bidi = 1 when the line has a
 * right-to-left letter, an Arabic number or an explicit direction: a line
 * with none is all level 0 in its own order, which FriBidi is not asked
 * to confirm. 0, or SP_E_NOMEM (said). */
static int bidi_order(const uint32_t *cp, int n, FriBidiCharType *types,
                      FriBidiBracketType *brackets, FriBidiStrIndex *map, FriBidiLevel *levels,
                      int *bidi, int *base_level)
{
    FriBidiParType base = FRIBIDI_PAR_ON;
    *bidi = *base_level = 0;
    fribidi_get_bidi_types(cp, n, types);
    for (int i = 0; i < n; i++) {
        map[i] = i, levels[i] = 0;
        *bidi |= FRIBIDI_IS_RTL(types[i]) || FRIBIDI_IS_EXPLICIT(types[i]) || FRIBIDI_IS_ISOLATE(types[i]) ||
                 types[i] == FRIBIDI_TYPE_AN;
    }
    if (*bidi) {
        fribidi_get_bracket_types(cp, n, types, brackets);
        if (!fribidi_get_par_embedding_levels_ex(types, brackets, n, &base, levels) ||
            !fribidi_reorder_line(0, types, n, 0, base, levels, NULL, map)) {
            sp_log_error("FriBidi cannot order a string of %d characters", n);
            return SP_E_NOMEM;
        }
        *base_level = FRIBIDI_IS_RTL(base) ? 1 : 0;
    }
    return 0;
}

/* The stretches of the n_items items (in the string's order, levels from
 * a line of level base) into their span_a, span_b: in a right-to-left line,
 * items one level up (left to right: numbers, Latin) and the items between
 * them at the line's level with no letter (spaces, punctuation) are one
 * stretch, from the first such item to the last; every other item is its
 * own. The stretch reads left to right on the line, as one piece: a PDF
 * states its text once, in the string's order, for a reader that puts a
 * line's text back in order from where its characters lie (see
 * cairo_text.c). */
static void stretches_of(struct item *items, int n_items, int base, const FriBidiCharType *types)
{
    for (int k = 0; k < n_items; k++)
        items[k].span_a = items[k].a, items[k].span_b = items[k].b;
    if (!(base & 1))
        return;
    for (int k = 0; k < n_items; k++) {
        if (items[k].level != base + 1)
            continue;
        int last = k; /* the stretch's last item one level up */
        for (int j = k + 1; j < n_items; j++) {
            int glue = items[j].level == base;
            for (int i = items[j].a; glue && i < items[j].b; i++)
                glue = !FRIBIDI_IS_STRONG(types[i]);
            if (items[j].level == base + 1)
                last = j;
            else if (!glue)
                break;
        }
        for (int j = k; j <= last; j++)
            items[j].span_a = items[k].a, items[j].span_b = items[last].b;
        k = last;
    }
}

/* The script of each of the n characters cp into script: common and
 * inherited characters take their neighbours' (those before the first
 * with a script of its own take hint's, when not HB_SCRIPT_INVALID). */
static void scripts_of(hb_unicode_funcs_t *uf, const uint32_t *cp, int n, hb_script_t hint,
                       hb_script_t *script)
{
    hb_script_t last = hint;
    for (int i = 0; i < n; i++) {
        const hb_script_t s = hb_unicode_script(uf, cp[i]);
        const int weak = s == HB_SCRIPT_COMMON || s == HB_SCRIPT_INHERITED || s == HB_SCRIPT_UNKNOWN;
        script[i] = weak ? last : s;
        if (!weak && last == HB_SCRIPT_INVALID)
            for (int j = 0; j < i; j++)
                script[j] = s;
        if (!weak)
            last = s;
    }
    for (int i = 0; i < n; i++)
        if (script[i] == HB_SCRIPT_INVALID)
            script[i] = HB_SCRIPT_COMMON;
}

/* The face of each of the n characters cp into face: the first that has
 * the character; marks and joiners stay in the font of the character they
 * belong to when it has them. Returns how many no face has (face 0, its
 * missing glyph). */
static int faces_of(struct sp_font *f, hb_unicode_funcs_t *uf, const uint32_t *cp, int n,
                    int *face)
{
    int missing = 0;
    for (int i = 0; i < n; i++) {
        const int inherited = hb_unicode_script(uf, cp[i]) == HB_SCRIPT_INHERITED;
        if (i && (invisible(cp[i]) || (inherited && face_covers(&f->faces[face[i - 1]], cp[i])))) {
            face[i] = face[i - 1];
            continue;
        }
        face[i] = invisible(cp[i]) ? 0 : face_for(f, cp[i]);
        if (face[i] < 0) {
            missing++;
            face[i] = 0; /* its missing glyph, counted */
        }
    }
    return missing;
}

/* Shapes text into l (its glyphs and runs allocated). Common and inherited
 * characters before the first with a script of its own take hint's script
 * (when not HB_SCRIPT_INVALID) as they would take their neighbours'. */
static int shape(struct sp_font *f, int size, const char *text, hb_script_t hint, struct shaped *l)
{
    const int bytes = (int)strlen(text);
    const size_t m = (size_t)bytes + 2; /* code points at most, and one over */
    /* one block for the per-character arrays (widest element first) */
    struct item *items = malloc(m * (sizeof(struct item) + sizeof(hb_script_t) + sizeof(uint32_t) +
                                     2 * sizeof(int) + sizeof(FriBidiCharType) +
                                     sizeof(FriBidiBracketType) + sizeof(FriBidiStrIndex) +
                                     sizeof(FriBidiLevel)));
    hb_script_t *script = (hb_script_t *)(items + m);
    uint32_t *cp = (uint32_t *)(script + m);
    int *off = (int *)(cp + m), *face = off + m;
    FriBidiCharType *types = (FriBidiCharType *)(face + m);
    FriBidiBracketType *brackets = (FriBidiBracketType *)(types + m);
    FriBidiStrIndex *map = (FriBidiStrIndex *)(brackets + m);
    FriBidiLevel *levels = (FriBidiLevel *)(map + m);
    hb_unicode_funcs_t *uf = hb_unicode_funcs_get_default();
    int n = 0, n_items = 0, n_glyphs = 0, missing = 0, err = 0, base = 0;

    if (!items) {
        sp_log_error("out of memory to lay out a string of %d bytes", bytes);
        return SP_E_NOMEM;
    }
    for (int i = 0; i < bytes;) {
        size_t len;
        off[n] = i;
        cp[n++] = sp_utf8_decode(text + i, &len);
        i += (int)len;
    }
    off[n] = bytes;
    if ((err = bidi_order(cp, n, types, brackets, map, levels, &l->bidi, &base)) != 0)
        goto done;
    scripts_of(uf, cp, n, hint, script);
    missing = faces_of(f, uf, cp, n, face);
    /* runs of one level, script and font */
    for (int i = 0; i < n; i++) {
        if (!n_items || levels[i] != items[n_items - 1].level || script[i] != items[n_items - 1].script ||
            face[i] != items[n_items - 1].face)
            items[n_items++] = (struct item){i, i, levels[i], face[i], n, script[i], 0, 0};
        items[n_items - 1].b = i + 1;
    }
    stretches_of(items, n_items, base, types);
    for (int v = 0; v < n; v++) /* each run's leftmost place */
        for (int k = 0; k < n_items; k++)
            if (map[v] >= items[k].a && map[v] < items[k].b && v < items[k].vis)
                items[k].vis = v;
    qsort(items, (size_t)n_items, sizeof(*items), by_vis);
    /* shape each run */
    l->r = malloc(((size_t)n_items + 1) * sizeof(*l->r));
    l->g = NULL;
    if (!l->r) {
        sp_log_error("out of memory for a line of %d runs", n_items);
        err = SP_E_NOMEM;
        goto done;
    }
    int pen = 0;
    size_t g_room = 0; /* glyphs l->g has room for */
    for (int k = 0; k < n_items; k++) {
        const struct item *it = &items[k];
        if ((err = face_open(f, it->face)) != 0)
            goto done;
        f->faces[it->face].used = 1;
        hb_buffer_clear_contents(f->buf);
        hb_buffer_add_utf8(f->buf, text, bytes, (unsigned)off[it->a], off[it->b] - off[it->a]);
        hb_buffer_set_direction(f->buf, it->level & 1 ? HB_DIRECTION_RTL : HB_DIRECTION_LTR);
        hb_buffer_set_script(f->buf, it->script);
        hb_buffer_set_language(f->buf, hb_language_get_default());
        hb_buffer_set_flags(f->buf, HB_BUFFER_FLAG_PRODUCE_UNSAFE_TO_CONCAT);
        hb_shape(f->faces[it->face].hb[size], f->buf, NULL, 0);
        unsigned ng;
        const hb_glyph_info_t *gi = hb_buffer_get_glyph_infos(f->buf, &ng);
        const hb_glyph_position_t *gp = hb_buffer_get_glyph_positions(f->buf, NULL);
        if (!hb_buffer_allocation_successful(f->buf) ||
            SP_ARRAY_RESERVE(l->g, g_room, (size_t)n_glyphs + ng + 1, 0)) {
            sp_log_error("out of memory to shape a string of %d bytes", bytes);
            err = SP_E_NOMEM;
            goto done;
        }
        struct sp_glyph *g = l->g;
        l->r[k] = (struct sp_glyph_run){n_glyphs,   (int)ng,    it->level & 1,   off[it->a],
                                        off[it->b], off[it->span_a], off[it->span_b]};
        for (unsigned j = 0; j < ng; j++) {
            const int flagged = (hb_glyph_info_get_glyph_flags(&gi[j]) & HB_GLYPH_FLAG_UNSAFE_TO_CONCAT) != 0;
            l->unsafe = (l->unsafe & 1) | (!n_glyphs && flagged) | (flagged ? 2 : 0);
            g[n_glyphs++] = (struct sp_glyph){
                gi[j].codepoint, it->face, pen + (int)lround(gp[j].x_offset / 64.0),
                -(int)lround(gp[j].y_offset / 64.0), (int)gi[j].cluster,
                hb_ot_layout_get_glyph_class(f->faces[it->face].hb_face, gi[j].codepoint) ==
                    HB_OT_LAYOUT_GLYPH_CLASS_MARK};
            pen += (int)lround(gp[j].x_advance / 64.0);
        }
    }
    l->line = (struct sp_line){pen, missing, n_glyphs, n_items, l->g, l->r};
    l->script = n_items ? items[0].script : HB_SCRIPT_COMMON;
    f->n_shaped++;
done:
    free(items);
    return err;
}

static struct shaped *line_find(struct sp_font *f, int size, hb_script_t hint, const char *text);

static int weak_script(hb_script_t s)
{
    return s == HB_SCRIPT_COMMON || s == HB_SCRIPT_INHERITED || s == HB_SCRIPT_UNKNOWN;
}

/* 1 when the character at s may start a piece of a line (compose): not a
 * mark, joiner or other character that goes with the one before it. */
static int piece_may_start(const char *s)
{
    size_t n;
    const uint32_t cp = sp_utf8_decode(s, &n);
    hb_unicode_funcs_t *uf = hb_unicode_funcs_get_default();
    const hb_unicode_general_category_t gc = hb_unicode_general_category(uf, cp);
    return !invisible(cp) && hb_unicode_script(uf, cp) != HB_SCRIPT_INHERITED &&
           gc != HB_UNICODE_GENERAL_CATEGORY_NON_SPACING_MARK &&
           gc != HB_UNICODE_GENERAL_CATEGORY_SPACING_MARK &&
           gc != HB_UNICODE_GENERAL_CATEGORY_ENCLOSING_MARK;
}

/* The shape cache's path for text that changes in its digits (a clock, a
 * readout): "t = 12.34 s" is laid out from the cached lines "t = ", "1",
 * "2", ".", "3", "4" and " s" (each digit a piece, the text between digits
 * another), each shaped alone with the script its first character has in
 * the whole line, put side by side. That is exactly what shaping the whole
 * line gives when the line is one left-to-right run (one font and script,
 * no right-to-left or explicit-direction character, no missing glyph) and
 * HarfBuzz marks no glyph at a join "unsafe to concat"
 * (HB_GLYPH_FLAG_UNSAFE_TO_CONCAT, which HarfBuzz sets on every glyph that
 * a lookup reaching past the text's end or start took part in, as a
 * kerning pair, a ligature or Arabic joining would: a piece's last glyph
 * before a join, the next piece's first glyph after it). Returns 0
 * (composed into l), 1 (the line is to be shaped whole) or SP_E_NOMEM. */
static int compose(struct sp_font *f, int size, const char *text, struct shaped *l)
{
    const int bytes = (int)strlen(text);
    hb_unicode_funcs_t *uf = hb_unicode_funcs_get_default();
    int digits = 0, cuts = 0;
    for (int i = 0; i < bytes; i++)
        digits += text[i] >= '0' && text[i] <= '9';
    if (f->whole || !digits || bytes < 2)
        return 1;
    char *piece = malloc((size_t)bytes + 1);
    int *cut = malloc(((size_t)bytes + 2) * sizeof(*cut));          /* pieces' first bytes */
    hb_script_t *hint = malloc(((size_t)bytes + 1) * sizeof(*hint)); /* and their hints */
    struct shaped **part = malloc(((size_t)bytes + 1) * sizeof(*part));
    int ret = 0, n_glyphs = 0, face = -1;
    hb_script_t script = HB_SCRIPT_INVALID, last = HB_SCRIPT_INVALID;
    if (!piece || !cut || !hint || !part) {
        sp_log_error("out of memory to lay out a string of %d bytes", bytes);
        ret = SP_E_NOMEM;
        goto done;
    }
    /* cut before and after each digit; a piece starting with a common
     * character is hinted with the script shape() gives that character in
     * the whole line: the last script before it, else the line's first
     * (HB_SCRIPT_INVALID until known), else COMMON */
    for (int i = 0; i < bytes;) {
        size_t len;
        const hb_script_t s = hb_unicode_script(uf, sp_utf8_decode(text + i, &len));
        const int digit = text[i] >= '0' && text[i] <= '9';
        if (!i || ((digit || (text[i - 1] >= '0' && text[i - 1] <= '9')) && piece_may_start(text + i))) {
            cut[cuts] = i;
            hint[cuts++] = weak_script(s) ? last : HB_SCRIPT_COMMON; /* COMMON: a script of its own */
        }
        if (!weak_script(s)) {
            if (last == HB_SCRIPT_INVALID) /* the line's first script */
                for (int k = 0; k < cuts; k++)
                    if (hint[k] == HB_SCRIPT_INVALID)
                        hint[k] = s;
            last = s;
        }
        i += (int)len;
    }
    cut[cuts] = bytes;
    if (cuts < 2) {
        ret = 1;
        goto done;
    }
    for (int k = 0; k < cuts; k++) {
        size_t len;
        const int own = !weak_script(hb_unicode_script(uf, sp_utf8_decode(text + cut[k], &len)));
        const hb_script_t h = own ? HB_SCRIPT_INVALID
                                  : hint[k] == HB_SCRIPT_INVALID ? HB_SCRIPT_COMMON : hint[k];
        memcpy(piece, text + cut[k], (size_t)(cut[k + 1] - cut[k]));
        piece[cut[k + 1] - cut[k]] = 0;
        const struct shaped *p = part[k] = line_find(f, size, h, piece);
        if (!p) {
            ret = SP_E_NOMEM;
            goto done;
        }
        if (p->bidi || (k && (p->unsafe & 1)) || (k + 1 < cuts && (p->unsafe & 2)) || p->line.missing || p->line.n_runs != 1 || p->line.runs[0].rtl ||
            (p->line.n_glyphs && face >= 0 && (p->line.glyphs[0].face != face || p->script != script))) {
            ret = 1; /* shaped whole */
            goto done;
        }
        if (p->line.n_glyphs)
            face = p->line.glyphs[0].face, script = p->script;
        n_glyphs += p->line.n_glyphs;
    }
    l->g = malloc(((size_t)n_glyphs + 1) * sizeof(*l->g));
    l->r = malloc(sizeof(*l->r));
    if (!l->g || !l->r) {
        sp_log_error("out of memory to lay out a string of %d bytes", bytes);
        ret = SP_E_NOMEM;
        goto done;
    }
    int pen = 0, n = 0;
    for (int k = 0; k < cuts; k++) {
        const struct sp_line *pl = &part[k]->line;
        for (int j = 0; j < pl->n_glyphs; j++) {
            l->g[n] = pl->glyphs[j];
            l->g[n].x += pen;
            l->g[n++].cluster += cut[k];
        }
        pen += pl->width;
    }
    l->r[0] = (struct sp_glyph_run){0, n, 0, 0, bytes, 0, bytes};
    l->line = (struct sp_line){pen, 0, n, 1, l->g, l->r};
    l->script = script == HB_SCRIPT_INVALID ? HB_SCRIPT_COMMON : script;
    f->n_composed++;
done:
    free(piece), free(cut), free(hint), free(part);
    return ret;
}

/* A line not in the cache: laid out now (compose, else shape) and cached
 * with its hash h and length len; NULL (said) when out of memory. Apart
 * from line_find so that a look-up that finds its line (most of them:
 * the same strings are measured and drawn every frame) is a short call. */
static __attribute__((noinline)) struct shaped *line_add(struct sp_font *f, int size,
                                                         hb_script_t hint, const char *text,
                                                         size_t len, uint32_t h)
{
    struct shaped *l = calloc(1, sizeof(*l));
    if (!l || !(l->text = strdup(text))) {
        free(l);
        sp_log_error("out of memory to lay out text");
        return NULL;
    }
    l->hash = h;
    l->len = len;
    l->size = size;
    l->hint = hint;
    int err = hint == HB_SCRIPT_INVALID ? compose(f, size, text, l) : 1;
    if (err == 1) {
        free(l->g), free(l->r);
        l->g = NULL, l->r = NULL;
        l->unsafe = 0;
        err = shape(f, size, text, hint, l);
    }
    if (err) {
        line_free(l);
        return NULL;
    }
    l->used = f->lookups;
    l->next = f->buckets[h % LINE_BUCKETS]; /* (compose may have added lines to b) */
    f->buckets[h % LINE_BUCKETS] = l;
    f->n_lines++;
    return f->last = l;
}

/* The shaped line of (size, hint, text) from the cache, or laid out now
 * (line_add); NULL (said) when out of memory. Drops no line (lines_trim
 * does, before a look-up from outside). */
static struct shaped *line_find(struct sp_font *f, int size, hb_script_t hint, const char *text)
{
    const size_t len = strlen(text);
    f->lookups++;
    /* the line asked for last: a string is often measured, then drawn */
    if (f->last && f->last->len == len && f->last->size == size && f->last->hint == hint &&
        !memcmp(f->last->text, text, len)) {
        f->last->used = f->lookups;
        return f->last;
    }
    const uint32_t h = hash_of(size, hint, text, len);
    for (struct shaped *l = f->buckets[h % LINE_BUCKETS]; l; l = l->next)
        if (l->hash == h && l->len == len && l->size == size && l->hint == hint &&
            !memcmp(l->text, text, len)) {
            l->used = f->lookups;
            return f->last = l;
        }
    return line_add(f, size, hint, text, len, h);
}

/* A line looked up from outside: the cache trimmed first (lines_trim). */
static struct shaped *line_get(struct sp_font *f, int size, const char *text)
{
    lines_trim(f);
    return line_find(f, size, HB_SCRIPT_INVALID, text);
}

int sp_font_shape(const struct sp_font *cf, int size, const char *text, struct sp_line *out)
{
    struct shaped *l = line_get((struct sp_font *)cf, size, text); /* its caches (see the top) */
    *out = l ? l->line : (struct sp_line){0};
    return l ? 0 : SP_E_NOMEM;
}

/* ---- the font ---- */

int sp_font_make(struct sp_font **out, const struct sp_font_desc *d)
{
    struct sp_font *f = NULL;
    int err = SP_E_IO;

    *out = NULL;
    for (int s = 0; s < SP_TEXT_SIZES; s++)
        if (d->px[s] < 4 || d->px[s] > 400) {
            sp_log_error("a text size of %d px is outside 4..400", d->px[s]);
            return SP_E_INPUT;
        }
    f = calloc(1, sizeof(*f));
    if (!f) {
        sp_log_error("out of memory for the font");
        return SP_E_NOMEM;
    }
    memcpy(f->px, d->px, sizeof(f->px));
    f->whole = d->whole_lines;
    f->buf = hb_buffer_create();
    if (FT_Init_FreeType(&f->lib)) {
        sp_log_error("FreeType cannot start");
        f->lib = NULL;
        goto done;
    }
    if ((err = find_faces(f, d->family, d->where)) != 0)
        goto done;
    f->aw = f->px[SP_TEXT_TITLE] > 64 || f->px[SP_TEXT_LARGE] > 48 ? 2048 : 1024;
    f->shelf_x = f->shelf_y = PAD;
    struct face *fc = &f->faces[0];
    for (int s = 0; s < SP_TEXT_SIZES; s++) {
        const struct cached *H;
        if (FT_Set_Pixel_Sizes(fc->ft, 0, (FT_UInt)f->px[s])) {
            sp_log_error("FreeType cannot size %s to %d px", face_family(f, 0), f->px[s]);
            err = SP_E_IO;
            goto done;
        }
        fc->ft_px = f->px[s];
        f->line[s] = (int)((fc->ft->size->metrics.height + 63) >> 6);
        if (!(H = glyph_get(f, 0, s, FT_Get_Char_Index(fc->ft, 'H')))) {
            err = SP_E_IO;
            goto done;
        }
        f->cap[s] = H->top;
    }
    err = 0;
done:
    if (err)
        sp_font_destroy(&f);
    *out = f;
    return err;
}

void sp_font_destroy(struct sp_font **fp)
{
    struct sp_font *f = *fp;
    if (!f)
        return;
    lines_drop(f, 0);
    for (int i = 0; i < f->n_faces; i++)
        face_close(&f->faces[i]);
    free(f->faces);
    if (f->sorted)
        FcFontSetDestroy(f->sorted);
    hb_buffer_destroy(f->buf);
    if (f->lib)
        FT_Done_FreeType(f->lib);
    free(f->slots);
    free(f->atlas);
    free(f);
    *fp = NULL;
}

int sp_font_has(const struct sp_font *f, uint32_t cp)
{
    return face_for(f, cp) >= 0;
}

int sp_font_check(const struct sp_font *f, const char *what, const char *s)
{
    char names[1024] = "", chars[512] = "";
    int bad = 0;
    for (size_t i = 0, len; s[i]; i += len) {
        const uint32_t cp = sp_utf8_decode(s + i, &len);
        if (!sp_utf8_char(s + i)) {
            sp_log_error("%s: malformed UTF-8 at byte %zu; text is UTF-8", what, i);
            return SP_E_INPUT;
        }
        if (invisible(cp) || face_for(f, cp) >= 0)
            continue;
        /* noncharacters and controls are named only by number */
        const int shown = cp >= 0x20 && !(cp >= 0x7F && cp < 0xA0) && (cp & 0xFFFE) != 0xFFFE &&
                          !(cp >= 0xFDD0 && cp <= 0xFDEF);
        if (bad++ < 8)
            snprintf(chars + strlen(chars), sizeof(chars) - strlen(chars), "%sU+%04X%s%.*s%s",
                     bad > 1 ? ", " : "", cp, shown ? " (" : "", shown ? (int)len : 0, s + i,
                     shown ? ")" : "");
    }
    if (!bad)
        return 0;
    int listed = 0;
    for (int i = 0; i < f->n_faces && listed < 8; i++) {
        const char *name = face_family(f, i);
        if (!strstr(names, name)) {
            snprintf(names + strlen(names), sizeof(names) - strlen(names), "%s%s",
                     listed++ ? ", " : "", name);
        }
    }
    sp_log_error("%s: %s %s in no installed font (tried %s%s%d fonts in all); remove %s or "
                 "install a font that has %s", what, chars, bad > 1 ? "are" : "is", names,
                 f->n_faces > listed ? " and others: " : ": ", f->n_faces,
                 bad > 1 ? "them" : "it", bad > 1 ? "them" : "it");
    return SP_E_INPUT;
}

int sp_font_width(const struct sp_font *f, int size, const char *s)
{
    const struct shaped *l = line_get((struct sp_font *)f, size, s); /* its caches */
    return l ? l->line.width : 0;
}

/* ---- wrapping ---- */

/* 1 when a line may break before the character at s: not before a mark
 * (it belongs to the character before it) nor a joiner. */
static int may_break_before(const char *s)
{
    const unsigned char *u = (const unsigned char *)s;
    if ((u[0] & 0xC0) == 0x80)
        return 0; /* inside a character */
    /* combining marks U+0300-036F, U+0483-0489, U+0591-05C7, U+0610-061A,
     * U+064B-065F, U+0670, U+06D6-06ED, the Indic signs and vowel marks
     * (U+0900-0DFF blocks' dependent signs), U+200C/U+200D, U+20D0-20FF */
    size_t n;
    const uint32_t cp = sp_utf8_decode(s, &n); /* U+FFFD, malformed: may break */
    if ((cp >= 0x0300 && cp <= 0x036F) || (cp >= 0x0483 && cp <= 0x0489) ||
        (cp >= 0x0591 && cp <= 0x05C7) || (cp >= 0x0610 && cp <= 0x061A) ||
        (cp >= 0x064B && cp <= 0x065F) || cp == 0x0670 || (cp >= 0x06D6 && cp <= 0x06ED) ||
        cp == 0x200C || cp == 0x200D || (cp >= 0x20D0 && cp <= 0x20FF) || (cp >= 0xFE00 && cp <= 0xFE0F))
        return 0;
    if (cp >= 0x0900 && cp <= 0x0DFF) { /* Indic: not before a dependent sign or virama */
        const int k = (int)(cp & 0x7F);
        return !(k <= 0x03 || (k >= 0x3A && k <= 0x4F) || (k >= 0x51 && k <= 0x57) ||
                 k == 0x62 || k == 0x63);
    }
    return 1;
}

/* A line is never measured longer than this many bytes: no frame (7680 px)
 * holds 64 KiB of glyphs on a line, and without the bound one long word
 * would be shaped whole once per line (quadratic in its length). */
#define WRAP_LINE_BYTES_MAX 65536

/* The candidate ends of a line starting at text: with chars = 0, each space
 * and the end (up to WRAP_LINE_BYTES_MAX); with chars = 1, where a character
 * may break (may_break_before) inside the first word. Returns the longest
 * that fits max_width, 0 when none does; try holds len + 1 bytes. Widths
 * grow with the prefix, so the bisection finds what a scan would. */
static size_t fit_prefix(const struct sp_font *f, int size, const char *text, float max_width,
                         char *try, int chars)
{
    size_t lo = 0, hi = 0, cap = 0, n = 0, *ends = NULL, fit = 0;
    for (size_t i = chars; i <= WRAP_LINE_BYTES_MAX; i++) {
        if (chars && (!text[i] || text[i] == ' '))
            break; /* the word's end: the space pass tried it */
        if (chars ? may_break_before(text + i) : (text[i] == ' ' || !text[i])) {
            if (SP_ARRAY_RESERVE(ends, cap, n + 1, 64))
                break; /* out of memory: the candidates so far */
            ends[n++] = i;
        }
        if (!text[i])
            break;
    }
    hi = n;
    while (lo < hi) { /* ends[0..lo) fit, ends[hi..n) do not */
        const size_t mid = lo + (hi - lo) / 2, i = ends[mid];
        memcpy(try, text, i);
        try[i] = 0;
        if (sp_font_width(f, size, try) > max_width) {
            hi = mid;
        } else {
            lo = mid + 1;
            fit = i;
        }
    }
    free(ends);
    return fit;
}

int sp_font_wrap(const struct sp_font *f, int size, const char *text, float max_width,
                int max_lines, char **out, int *n_out)
{
    const size_t len = strlen(text);
    char *buf = malloc(2 * len + 2), *w = buf, *try = malloc(len + 1);
    int n = 0;
    *out = NULL;
    *n_out = 0;
    if (!buf || !try) {
        free(buf), free(try);
        sp_log_error("out of memory to wrap %zu bytes of text", len);
        return SP_E_NOMEM;
    }
    text += strspn(text, " ");
    while (*text) {
        /* the longest prefix ending at a space (or the end) that fits, or
         * else (the first word alone is too wide) the longest ending where a
         * character may break: each found by bisection over its candidate
         * ends, so a line costs about log2(candidates) shapings, not one per
         * candidate (a 64 KB run of zero-width characters was quadratic) */
        size_t fit = fit_prefix(f, size, text, max_width, try, 0);
        if (!fit)
            fit = fit_prefix(f, size, text, max_width, try, 1);
        if (!fit) /* not even one character: it stays whole, and overflows */
            for (fit = 1; text[fit] && !may_break_before(text + fit); fit++)
                ;
        while (fit && text[fit - 1] == ' ')
            fit--;
        memcpy(w, text, fit);
        w[fit] = 0;
        w += fit + 1;
        n++;
        text += fit;
        text += strspn(text, " ");
        if (n > max_lines) /* already more than the frame can take: the caller refuses */
            break;
    }
    free(try);
    *out = buf;
    *n_out = n;
    return 0;
}


int sp_font_cap(const struct sp_font *f, int size) { return f->cap[size]; }
int sp_font_line(const struct sp_font *f, int size) { return f->line[size]; }
int sp_font_px(const struct sp_font *f, int size) { return f->px[size]; }

/* Rasterises line l's glyphs not yet in the glyph cache and works out its
 * quads (l->place, l->n_place), relative to the pen start and baseline:
 * once per line, so a frame that draws it again only copies them. 0 or
 * SP_E_NOMEM (said). */
static int line_place(struct sp_font *f, int size, struct shaped *l)
{
    struct placed *q = malloc(((size_t)l->line.n_glyphs + 1) * sizeof(*q));
    int n = 0, base_top = 0, base_mid = 0; /* px from the baseline */
    if (!q) {
        sp_log_error("out of memory to place %d glyphs", l->line.n_glyphs);
        return SP_E_NOMEM;
    }
    for (int i = 0; i < l->line.n_glyphs; i++) {
        /* l stays valid: rasterising does not touch the line cache */
        const struct sp_glyph *g = &l->g[i];
        const struct cached *c = glyph_get(f, g->face, size, g->index);
        if (!c) {
            free(q);
            return SP_E_NOMEM;
        }
        if (c->w <= 0 || c->h <= 0)
            continue;
        int y0 = g->y - c->top;
        if (!g->mark) {
            base_top = y0, base_mid = y0 + c->h / 2;
        } else if (y0 + c->h / 2 < base_mid && y0 + c->h >= base_top) {
            /* a mark above its base: hinting grew the base's bitmap into
             * it (the outlines do not touch), so keep one pixel between */
            y0 = base_top - 1 - c->h;
        }
        q[n++] = (struct placed){g->x + c->left, y0, c->w, c->h,
                                 {(float)c->x, (float)c->y, (float)(c->x + c->w), (float)(c->y + c->h)}};
    }
    l->place = q;
    l->n_place = n;
    return 0;
}

int sp_font_layout(const struct sp_font *cf, int size, const char *s, float x,
                   float baseline, const float color[4], struct sp_glyph_quad *out, int max)
{
    struct sp_font *f = (struct sp_font *)cf; /* its caches (see the top) */
    const int pen = (int)lroundf(x), base = (int)lroundf(baseline);
    struct shaped *l = line_get(f, size, s);
    int err;
    if (!l)
        return SP_E_NOMEM;
    if (!l->place && (err = line_place(f, size, l)) != 0)
        return err;
    const struct placed *q = l->place;
    for (int i = 0; i < l->n_place && i < max; i++) {
        const float x0 = (float)(pen + q[i].x);
        const int y0 = base + q[i].y;
        out[i] = (struct sp_glyph_quad){{x0, (float)y0, x0 + q[i].w, (float)(y0 + q[i].h)},
                                        {q[i].uv[0], q[i].uv[1], q[i].uv[2], q[i].uv[3]},
                                        {color[0], color[1], color[2], color[3]}};
    }
    return l->n_place;
}

int sp_font_faces(const struct sp_font *f) { return f->n_faces; }

const char *sp_font_face_file(const struct sp_font *f, int face, int *index,
                              const unsigned char **data, size_t *size)
{
    const struct face *fc = &f->faces[face];
    unsigned n = 0;
    *index = fc->index;
    /* opened (and read) on first use, as laying text out does */
    *data = face_open((struct sp_font *)f, face) ? NULL
                                                : (const unsigned char *)face_bytes(fc, &n);
    *size = *data ? n : 0;
    return fc->file;
}

void *sp_font_face_keep(const struct sp_font *f, int face)
{
    return f->faces[face].blob ? hb_blob_reference(f->faces[face].blob) : NULL;
}

void sp_font_face_release(void *keep)
{
    hb_blob_destroy(keep);
}

void sp_font_files(const struct sp_font *f, char *buf, size_t size)
{
    size_t n = 0;
    if (size)
        buf[0] = 0;
    for (int i = 0; i < f->n_faces && n < size; i++) {
        if (!f->faces[i].used && i)
            continue;
        const int w = snprintf(buf + n, size - n, "%s%s", n ? ", " : "",
                               f->faces[i].file ? f->faces[i].file : SP_FONT_EMBEDDED);
        n += w > 0 ? (size_t)w : 0;
    }
}

int sp_font_environment(const struct sp_font *f, char *buf, size_t size)
{
    int ret = 0;
    for (int i = 0; i < f->n_faces && !ret; i++) {
        struct face *fc = &((struct sp_font *)f)->faces[i]; /* its hash is a cache */
        if (!(fc->used || !i) || !fc->file)
            continue;
        if ((ret = face_open((struct sp_font *)f, i)))
            break;
        unsigned n;
        const char *data = face_bytes(fc, &n);
        if (!fc->sha[0]) { /* the bytes FreeType and HarfBuzz draw from */
            struct sha256_ctx sha;
            sha256_init(&sha);
            sha256_update(&sha, n, (const uint8_t *)data);
            sp_digest_hex(&sha, fc->sha);
        }
        ret = sp_environment_add_font(buf, size, fc->file, fc->sha, (long long)n);
    }
    return ret;
}

const uint8_t *sp_font_atlas(const struct sp_font *f, int *w, int *h, unsigned *version)
{
    *w = f->aw;
    *h = f->ah;
    if (version)
        *version = f->version;
    return f->atlas;
}

void sp_font_raster_stats(const struct sp_font *f, int *glyphs, double *seconds)
{
    *glyphs = f->rastered;
    *seconds = f->raster_s;
}

void sp_font_shape_stats(const struct sp_font *f, int *shaped, int *composed)
{
    *shaped = f->n_shaped;
    *composed = f->n_composed;
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
