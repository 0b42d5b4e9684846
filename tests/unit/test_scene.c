/* springpend tests: scene parsing and validation (scene.c).
 * argv[1] = the tests source folder; scenes/ is beside it. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/scene.h"
#include "tap.h"

static int parse(const char *text, struct sp_scene *s)
{
    sp_scene_defaults(s);
    return sp_scene_parse(s, text, "test.ini", NULL, 0);
}

static void test_presets(const char *tests_dir)
{
    char dir[4096], path[8192];
    snprintf(dir, sizeof(dir), "%s/../scenes", tests_dir);
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d))) {
        size_t len = strlen(e->d_name);
        if (len < 5 || strcmp(e->d_name + len - 4, ".ini"))
            continue;
        struct sp_scene s;
        sp_scene_defaults(&s);
        snprintf(path, sizeof(path), "%s/%s", dir, e->d_name);
        sp_tap_ok(sp_scene_load(&s, path, NULL, 0) == 0, "scenes/%s parses", e->d_name);
        sp_scene_free(&s);
        n++;
    }
    if (d)
        closedir(d);
    sp_tap_ok(n >= 1, "found %d scene files in %s", n, dir);
}

static void test_defaults(void)
{
    struct sp_scene s;
    sp_tap_ok(parse("# nothing but a comment\n", &s) == 0 &&
              s.pendulum.natural_length == 0.5 && s.pendulum.stiffness == 2 &&
              s.pendulum.mass == 0.5 && s.initial.length == 0.55 &&
              fabs(s.initial.angle - 10 * M_PI / 180) < 1e-15 && s.integrator.dt == 0.001 &&
              s.view.trail == 600 && s.pendulum.gravity == 9.81,
              "an empty scene takes the original's defaults");
    sp_tap_ok(parse("[pendulum]\nmass = 2 # kg\n[initial]\nangle=90\n", &s) == 0 &&
              s.pendulum.mass == 2 && fabs(s.initial.angle - M_PI / 2) < 1e-15,
              "keys with inline comments; angles are degrees");
    sp_scene_defaults(&s);
    const char *ov[] = {"video.fps=30", "pendulum.stiffness=5"};
    sp_tap_ok(sp_scene_parse(&s, "[video]\nfps = 60\n", "t.ini", ov, 2) == 0 &&
              s.video.fps == 30 && s.pendulum.stiffness == 5, "--set overrides the file");
    sp_tap_ok(sp_scene_frame_count(&s) == 300, "10 s at 30 fps, speed 1: 300 frames (%d)",
              sp_scene_frame_count(&s));
}

static void test_view(void)
{
    struct sp_scene s;
    sp_tap_ok(parse("[view]\npanels = r, phase,poincare\nhud = true\ntheme = light\n"
                    "background = #FF8000\ncolormap = viridis\ntrail = all\nstrobe = 0.25\n", &s) == 0 &&
              s.view.panels == (SP_PANEL_R | SP_PANEL_PHASE_R | SP_PANEL_PHASE_THETA | SP_PANEL_POINCARE) &&
              s.view.hud == 1 && s.view.theme == SP_THEME_LIGHT && s.view.background == 0xFF8000 &&
              s.view.colormap == SP_COLORMAP_VIRIDIS && s.view.trail == SP_TRAIL_ALL &&
              s.view.strobe == 0.25, "[view] keys: panel list, hud, theme, colour, colormap, trail = all");
    sp_tap_ok(parse("[view]\npanels = all\nbackground = transparent\n", &s) == 0 &&
              s.view.panels == SP_PANEL_ALL &&
              s.view.background == SP_BACKGROUND_TRANSPARENT, "panels = all, background = transparent");
    sp_tap_ok(parse("# all defaults\n", &s) == 0 && s.view.panels == 0 && !s.view.hud &&
              s.view.background == SP_BACKGROUND_THEME && s.view.strobe == 0,
              "by default no panels, no text, the theme's background");
}

static void test_rejects(void)
{
    static const char *bad[] = {
        "[pendulum]\nmass = 0\n", "[pendulum]\nmass = -1\n", "[pendulum]\nstiffness = nan\n",
        "[pendulum]\nstiffness = inf\n", "[pendulum]\nstiffness = 2x\n",
        "[pendulum]\nmas = 1\n", "[pendel]\nmass = 1\n", "[video]\nwidth = 0\n",
        "[video]\nwidth = 100000\n", "[video]\nfps = 0\n", "[integrator]\ndt = 0\n",
        "[integrator]\nmethod = euler\n", "[pendulum]\nmass = 1\nmass = 2\n",
        "just some words\n", "[video]\nduration = 1e6\nfps = 1000\nspeed = 0.1\n",
        "mass = 1\n", "[initial]\nlength = 0\n", "[video\nwidth = 10\n",
        "", " \n\t\r\n", "[pendulum]\nmass = 1\x01\n", "[pendulum]\nmass = \xff\n",
        "[pendulum]\n# caf\xc3\n", "[pendulum]\n# \xed\xa0\x80 (a surrogate)\n",
        "[view]\npanels = r, foo\n", "[view]\npanels = none, r\n", "[view]\ntheme = blue\n",
        "[view]\nbackground = #12345\n", "[view]\nhud = maybe\n", "[view]\ntrail = some\n",
        "[view]\ncolormap = jet\n", "[view]\nstrobe = -1\n",
        /* empty entries in a list, as ",,," is */
        "[view]\npanels = r,,theta\n", "[view]\npanels = r, ,theta\n", "[view]\npanels = r,\n",
        "[view]\npanels = ,,,\n", "[view]\npanels = ,r\n",
    };
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        struct sp_scene s;
        char shown[64];
        snprintf(shown, sizeof(shown), "%s", bad[i]);
        for (char *p = shown; *p; p++)
            if (*p == '\n')
                *p = '|';
        sp_tap_ok(parse(bad[i], &s) == SP_E_INPUT, "rejected: %s", shown);
    }
}

/* UTF-8 text is fine in comments; a canonical text ignores layout. */
static void test_text(void)
{
    struct sp_scene a, b;
    char ca[2048], cb[2048];
    sp_tap_ok(parse("# Résumé: a ½ kg bob, θ₀ = 10°\n[pendulum]\nmass = 0.5\n", &a) == 0,
              "UTF-8 comments are accepted");
    parse("[video]\nwidth=1280\n", &b);
    int na = sp_scene_canonical(&a, ca, sizeof(ca)), nb = sp_scene_canonical(&b, cb, sizeof(cb));
    sp_tap_ok(na > 0 && na < (int)sizeof(ca) && na == nb && !strcmp(ca, cb),
              "two layouts of the default scene give the same canonical text (%d bytes)", na);
    const char *ov[] = {"pendulum.mass=0.25"};
    sp_scene_defaults(&b);
    sp_scene_parse(&b, "[video]\nwidth=1280\n", "t.ini", ov, 1);
    sp_scene_canonical(&b, cb, sizeof(cb));
    sp_tap_ok(strcmp(ca, cb) != 0 && strstr(cb, "pendulum.mass=0.25\n"),
              "an override changes the canonical text");
    parse("[view]\nhud = true\ntrail = all\npanels = r\nstrobe = 0.5\n", &b);
    sp_scene_canonical(&b, cb, sizeof(cb));
    sp_tap_ok(strstr(cb, "view.hud=1\n") && strstr(cb, "view.trail=-1\n") &&
              strstr(cb, "view.strobe=0.5\n") && strstr(ca, "view.panels=0\n") &&
              strstr(cb, "view.panels=0x"),
              "every kind of key is written with its own type");
    sp_tap_ok(sp_scene_canonical(&a, ca, 10) == na && strlen(ca) == 9,
              "a short buffer is truncated and the full length returned");
}

/* Titles and captions are never cut silently: inih would end them at ' #'
 * or ' ;' (an inline comment, as after a number). Quoted text is whole;
 * unquoted text with ' #' or ' ;' is refused. Title and caption have no byte
 * limit (the frame is theirs), in a scene line and in --set alike; view.font
 * keeps its 255 bytes. */
static void test_whole_text(void)
{
    struct sp_scene s;
    int r = parse("[view]\ntitle = \"Run #3 ; final\"  # a comment\n"
                  "caption = \"  a ; b # c \"\n", &s);
    sp_tap_ok(r == 0 && !strcmp(s.view.title, "Run #3 ; final") && !strcmp(s.view.caption, "  a ; b # c "),
              "quoted title and caption keep ' #' and ' ;' (title '%s', caption '%s')",
              r ? "" : s.view.title, r ? "" : s.view.caption);
    sp_scene_free(&s);
    r = parse("[view]\ntitle: #1 run\n[pendulum]\nmass = 2 # kg\n", &s);
    sp_tap_ok(r == 0 && !strcmp(s.view.title, "#1 run") && s.pendulum.mass == 2,
              "a title that starts with '#' is text; a number's inline comment still goes");
    sp_scene_free(&s);
    sp_tap_ok(parse("[view]\ntitle = Run #3\n", &s) == SP_E_INPUT &&
              parse("[view]\ncaption = a ; b\n", &s) == SP_E_INPUT &&
              parse("[view]\ntitle = \"Run\" 3\n", &s) == SP_E_INPUT,
              "unquoted ' #' or ' ;' in a title or caption, and text after the quotes, are refused");
    /* far beyond the 255 bytes of before, and beyond inih's 200-byte lines */
    static const int lengths[] = {255, 256, 1000, 100000};
    for (size_t i = 0; i < sizeof(lengths) / sizeof(lengths[0]); i++) {
        const int n = lengths[i];
        const size_t room = 2 * (size_t)n + 64;
        char *text = malloc(room), *set = malloc(room), *want = malloc(room);
        for (int j = 0; j < n; j++) /* words, with a UTF-8 letter */
            want[j] = j % 7 == 6 ? ' ' : j % 7 == 0 && j + 2 <= n ? '\xc3' : 'a';
        want[n] = 0;
        for (int j = 0; j + 1 < n; j++) /* \xc3 \xbc = u-umlaut */
            if (want[j] == '\xc3')
                want[j + 1] = '\xbc';
        if (n && want[n - 1] == '\xc3')
            want[n - 1] = 'a';
        snprintf(text, room, "[view]\ncaption = \"%s\"\ntitle = %s\n", want, want);
        snprintf(set, room, "view.caption=%s", want);
        const char *ov[] = {set};
        struct sp_scene t;
        sp_scene_defaults(&t);
        const int a = parse(text, &s), b = sp_scene_parse(&t, "# --set only\n", "t.ini", ov, 1);
        /* trailing blanks of an unquoted title are not part of it */
        char *trimmed = strdup(want);
        for (size_t k = strlen(trimmed); k && trimmed[k - 1] == ' ';)
            trimmed[--k] = 0;
        sp_tap_ok(a == 0 && b == 0 && !strcmp(s.view.caption, want) && !strcmp(s.view.title, trimmed) &&
                      !strcmp(t.view.caption, want) && sp_scene_canonical(&s, NULL, 0) > 2 * n,
                  "a %d-byte title and caption are taken whole, in a scene line and in --set alike", n);
        sp_scene_free(&s);
        sp_tap_ok(!s.texts[0] && !s.texts[1] && !strcmp(s.view.title, "") && !strcmp(s.view.caption, ""),
                  "sp_scene_free releases the %d-byte texts", n);
        sp_scene_free(&t);
        free(trimmed), free(text), free(set), free(want);
    }
    char text[1024];
    snprintf(text, sizeof(text), "[view]\nfont = %0*d\n", SP_VIEW_TEXT_BYTES, 0);
    sp_tap_ok(parse(text, &s) == SP_E_INPUT, "a font family of %d bytes is refused (at most %d)",
              SP_VIEW_TEXT_BYTES, SP_VIEW_TEXT_BYTES - 1);
}

int main(int argc, char **argv)
{
    test_whole_text();
    test_defaults();
    test_view();
    test_text();
    test_rejects();
    test_presets(argc > 1 ? argv[1] : "tests");
    return sp_tap_done();
}
