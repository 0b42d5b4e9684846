/* springpend tests: real renders compared with reviewed golden PNGs, once
 * per GL backend this machine has (OSMesa, EGL); the same goldens for both.
 * usage: test_golden TESTS_SOURCE_DIR OUTPUT_DIR
 * On a mismatch, OUTPUT_DIR/NAME.actual.png and NAME.diff.png are written.
 * SP_UPDATE_GOLDEN=1 replaces the golden files with the actual renders
 * (review them before committing). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/image_compare.h"
#include "springpend/pipeline.h"
#include "springpend/png_io.h"
#include "render/gl_context.h"
#include "tap.h"

/* Both backends here reproduce the goldens exactly, so the rule is ten times
 * tighter than `springpend compare`'s default (0.1% of the pixels more than
 * 3 levels off): at most 0.01% of the pixels may have a channel more than 1
 * level off. A small picture change must fail it by a wide margin: the same
 * frame 4 ms later (the bob moved by about a pixel)
 * differs in at least 3 times the pixels allowed, and so does a start 0.5
 * degrees off, 1% more mass, another colour map (check_margin). */
static const struct sp_compare_opts golden_rule = {.max_diff = 1, .max_fraction = 1e-4};

struct golden_case {
    const char *name;       /* golden file stem */
    const char *scene;      /* file under scenes/ */
    double at;              /* simulated s */
    const char *overrides[12];
};

#define SMALL "video.width=640", "video.height=360"

static const struct golden_case cases[] = {
    /* the pendulum alone; default.ini itself shows panels (default_panels) */
#define ALONE "view.panels=none", "view.hud=false", "view.colorbar=false"
    {"default_t3", "default.ini", 3.0, {"video.width=640", "video.height=360", ALONE}},
    {"default_t0_notrail", "default.ini", 0.0, {"video.width=320", "video.height=240",
                                                 "view.trail=0", ALONE}},
    {"default_panels", "default.ini", 8.5, {SMALL}},
    /* one per panel kind, with the heads-up text and colourbar in some */
    {"panel_r", "default.ini", 4.0, {SMALL, "view.panels=r", "view.hud=true", "view.colorbar=false"}},
    {"panel_theta", "default.ini", 4.0, {SMALL, "view.panels=theta", "view.hud=false",
                                         "view.colorbar=true"}},
    {"panel_energy", "damped.ini", 6.0, {SMALL, "view.panels=energy"}},
    {"panel_extension", "default.ini", 4.0, {SMALL, "view.panels=extension", "view.theme=light",
                                             "view.hud=false", "view.colorbar=false"}},
    {"panel_phase", "resonance.ini", 12.0, {SMALL, "view.panels=phase", "view.hud=false",
                                             "view.colorbar=false"}},
    {"panel_poincare", "resonance.ini", 30.0, {SMALL, "view.panels=poincare", "view.hud=false",
                                                "view.colorbar=false"}},
    {"panel_modes_driven", "driven.ini", 20.0, {SMALL, "view.panels=modes", "view.hud=true"}},
    {"all_portrait", "resonance.ini", 20.0, {"video.width=360", "video.height=640"}},
    /* alpha in the PNG: the background is see-through, the pendulum opaque */
    {"transparent", "chaotic.ini", 8.0, {SMALL, "view.background=transparent", "view.panels=none",
                                          "view.hud=false", "view.colorbar=false"}},
    {"strobe_light", "pure_swing.ini", 2.0, {SMALL, "view.panels=none", "view.hud=false",
                                              "view.strobe=0.1", "view.theme=light"}},
    /* legibility: every panel at the sizes people use, 4:3, 16:9 and 9:16 */
#define ALL_AT(w, h) {"size_" #w "x" #h, "resonance.ini", 20.0, {"video.width=" #w, \
                      "video.height=" #h, "view.panels=all", "view.colorbar=true"}}
    ALL_AT(320, 240), ALL_AT(640, 360), ALL_AT(854, 480), ALL_AT(1024, 768),
    ALL_AT(1920, 1080), ALL_AT(1080, 1920),
    /* figure layout: no pendulum, a title, a caption, the speed marker */
    {"figure_tiles", "resonance.ini", 20.0, {SMALL, "view.pendulum=false", "view.panels=all",
                                             "view.hud=false", "view.title=Spring pendulum at 2:1",
                                             "view.caption=Energy flows from bounce to swing",
                                             "video.speed=0.25", "view.theme=light"}},
};

static void run_case(const char *src, const char *outdir, const struct golden_case *gc,
                     enum sp_gl gl, const char *gl_name)
{
    char scene_path[4096], golden[4096], actual[4096], diffp[4096];
    struct sp_scene scene;
    struct sp_image want = {0}, got = {0}, diff = {0};
    int n = 0;
    const char *overrides[13];
    while (n < 12 && gc->overrides[n])
        overrides[n] = gc->overrides[n], n++;
    /* the goldens are the video's frames: with its marks of now, which a
     * still leaves out by default (view.cursor = auto) */
    overrides[n++] = "view.cursor=true";
    snprintf(scene_path, sizeof(scene_path), "%s/../scenes/%s", src, gc->scene);
    snprintf(golden, sizeof(golden), "%s/golden/%s.png", src, gc->name);
    snprintf(actual, sizeof(actual), "%s/%s.%s.actual.png", outdir, gc->name, gl_name);
    snprintf(diffp, sizeof(diffp), "%s/%s.%s.diff.png", outdir, gc->name, gl_name);
    sp_scene_defaults(&scene);
    if (!sp_tap_ok(sp_scene_load(&scene, scene_path, overrides, n) == 0 &&
                   sp_pipeline_run(&(struct sp_pipeline_desc){
                       .scene = &scene, .output = actual, .still = 1,
                       .still_at = gc->at, .gl = gl}) == 0,
                   "%s: rendered with %s", gc->name, gl_name)) {
        sp_scene_free(&scene);
        return;
    }
    if (getenv("SP_UPDATE_GOLDEN") && gl == SP_GL_OSMESA) {
        struct sp_image img;
        sp_png_read(actual, &img);
        sp_png_write(golden, &img, 9);
        sp_image_free(&img);
        sp_tap_diag("%s: golden updated from %s", gc->name, actual);
    }
    if (!sp_tap_ok(sp_png_read(golden, &want) == 0 && sp_png_read(actual, &got) == 0,
                   "%s: golden and actual read", gc->name))
        goto done;
    if (strstr(gc->overrides[2] ? gc->overrides[2] : "", "transparent")) {
        int opaque = 0;
        for (int i = 0; i < got.width * got.height; i++)
            opaque += got.pixels[4 * i + 3] == 255;
        sp_tap_ok(got.pixels[3] == 0 && opaque > 200, "%s: see-through corner, %d opaque pixels "
                  "(bob, spring)", gc->name, opaque);
    }
    if (!sp_tap_ok(want.width == got.width && want.height == got.height,
                   "%s: size %dx%d matches golden %dx%d", gc->name, got.width, got.height,
                   want.width, want.height))
        goto done;
    struct sp_compare_result r;
    if (!sp_tap_ok(sp_compare_images(&want, &got, &golden_rule, &r, &diff) == 0,
                   "%s (%s): compared", gc->name, gl_name))
        goto done;
    if (!sp_tap_ok(r.pass, "%s (%s): %ld pixels differ by more than %d levels (allowed %ld; "
                   "largest difference %d)", gc->name, gl_name, r.differing, r.max_diff, r.allowed,
                   r.max_channel_diff)) {
        sp_png_write(diffp, &diff, 6);
        sp_tap_diag("actual: %s, diff: %s", actual, diffp);
    } else {
        remove(actual);
    }
done:
    sp_scene_free(&scene);
    sp_image_free(&want);
    sp_image_free(&got);
    sp_image_free(&diff);
}

/* A deliberate small change of golden case gc (extra overrides, or the frame
 * dt_s later) against its golden: fails the golden rule, with at least 3
 * times the pixels it allows. */
static void check_margin(const char *src, const char *outdir, const struct golden_case *gc,
                         const char *change, double dt_s, const char *what)
{
    char scene_path[4096], golden[4096], actual[4096];
    const char *ov[14];
    int n = 0;
    while (n < 12 && gc->overrides[n])
        ov[n] = gc->overrides[n], n++;
    ov[n++] = "view.cursor=true"; /* as run_case */
    if (change)
        ov[n++] = change;
    snprintf(scene_path, sizeof(scene_path), "%s/../scenes/%s", src, gc->scene);
    snprintf(golden, sizeof(golden), "%s/golden/%s.png", src, gc->name);
    snprintf(actual, sizeof(actual), "%s/%s.margin.png", outdir, gc->name);
    struct sp_scene scene;
    struct sp_image want = {0}, got = {0};
    struct sp_compare_result r = {0};
    sp_scene_defaults(&scene);
    int ok = sp_scene_load(&scene, scene_path, ov, n) == 0 &&
             sp_pipeline_run(&(struct sp_pipeline_desc){.scene = &scene, .output = actual,
                                                          .still = 1, .still_at = gc->at + dt_s,
                                                          .gl = SP_GL_OSMESA}) == 0 &&
             sp_png_read(golden, &want) == 0 && sp_png_read(actual, &got) == 0 &&
             sp_compare_images(&want, &got, &golden_rule, &r, NULL) == 0;
    sp_tap_ok(ok && !r.pass && r.differing >= 3 * r.allowed,
              "%s, %s: the golden rule fails it by a margin: %ld pixels differ (allowed %ld)",
              gc->name, what, r.differing, r.allowed);
    remove(actual);
    sp_scene_free(&scene);
    sp_image_free(&want);
    sp_image_free(&got);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: %s TESTS_SOURCE_DIR OUTPUT_DIR\n", argv[0]);
        return 2;
    }
    static const struct { enum sp_gl gl; const char *name; } backends[] = {
        {SP_GL_OSMESA, "osmesa"}, {SP_GL_EGL, "egl"},
    };
    int tested = 0;
    struct sp_gl_context *osmesa = NULL;
    if (sp_gl_context_make(&osmesa, 64, 64, SP_GL_OSMESA) == 0) {
        sp_gl_context_destroy(&osmesa);
        check_margin(argv[1], argv[2], &cases[0], NULL, 0.004, "4 ms later");
        check_margin(argv[1], argv[2], &cases[1], "initial.angle=10.5", 0, "0.5 degrees more");
        check_margin(argv[1], argv[2], &cases[3], "pendulum.mass=0.505", 0, "1% more mass");
        check_margin(argv[1], argv[2], &cases[7], "view.colormap=viridis", 0, "another colormap");
    }
    for (size_t b = 0; b < sizeof(backends) / sizeof(backends[0]); b++) {
        struct sp_gl_context *probe = NULL;
        if (sp_gl_context_make(&probe, 64, 64, backends[b].gl)) {
            sp_tap_diag("GL backend %s is not available here: not tested", backends[b].name);
            continue;
        }
        sp_gl_context_destroy(&probe);
        tested++;
        for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++)
            run_case(argv[1], argv[2], &cases[i], backends[b].gl, backends[b].name);
    }
    if (!tested)
        SP_TAP_SKIP_ALL("no GL backend");
    return sp_tap_done();
}
