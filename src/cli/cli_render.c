/* springpend: the render and still commands. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/figure.h"
#include "springpend/outfile.h"
#include "springpend/pipeline.h"
#include "springpend/provenance.h"
#include "springpend/sim.h"
#include "springpend/sink.h"
#include "springpend/timeline.h"
#include "base/signal_name.h"

/* The end of render's and still's help: scenes side by side. */
#define SIDE_BY_SIDE_HELP \
    "Side by side: with 2 to 4 SCENE files each scene is drawn in its own cell of\n" \
    "the frame (in a row, or 2x2 for 4; in a column on a portrait frame), labelled\n" \
    "with its view.title or, without one, the keys in which the scenes differ, all\n" \
    "at one camera scale (a metre is the same length in every cell) and with the\n" \
    "same chart axes. They share the first scene's [video] width, height, fps and\n" \
    "speed, the encoder settings the output reads (crf and preset for MP4 and\n" \
    "WebM, png_level for PNG) and [view] theme, background, font, font_size and\n" \
    "font_scale (a scene that differs in one is refused; --set applies to every\n" \
    "scene); [timeline], [ensemble] and --state take one scene. Scenes of\n" \
    "different durations run to the longest: the others hold their last frame,\n" \
    "marked 'ended at t = ...'.\n" \
    "The output is named after the first scene.\n"

static const char render_usage[] =
    "usage: springpend render SCENE [SCENE ...] [-o OUTPUT] [options]\n"
    "\n"
    "Renders the scene's whole motion. The output's extension (or --format) picks\n"
    "the kind:\n"
    "  out/NAME.mp4           H.264 video (default: out/<scene>.mp4); [video] crf, preset\n"
    "  out/NAME.webm          VP9 video\n"
    "  out/NAME.gif           GIF, palette made for the content (short clips)\n"
    "  'out/frames/%05d.png'  a PNG sequence, one file per frame (numbered from 0)\n"
    "  --format raw -o -      raw RGBA8 frames (W*H*4 bytes each) to stdout\n"
    "  out/NAME.yuv           raw YUV 4:2:0 frames (I420, BT.709 limited range,\n"
    "                         W*H*3/2 bytes each; --format yuv420p -o - to stdout)\n"
    "Files are written as NAME.XXXXXX.part (springpend-XXXXXX.part beside it\n"
    "where that name would pass the folder's limit, 255 bytes) and renamed when\n"
    "complete; a device, FIFO or /dev/stdout is written through (raw frames) or\n"
    "refused. Ctrl-C (SIGINT) or SIGTERM keeps a playable file of the frames so\n"
    "far (exit 130/143); a second one stops at once and removes the .part.\n"
    "\n"
    "options:\n"
    "  -o, --output PATH      where to write\n"
    "  --format KIND          mp4, webm, gif, png, raw or yuv420p, whatever the extension\n"
    "  --quality Q            low 854x480@15, medium 1280x720@30, high 1920x1080@60,\n"
    "                         4k 3840x2160@60 (--size, --fps, --set still override)\n"
    "  --frames A:B           only frames A..B-1 (from 0; the physics still starts at 0)\n"
    "  --shard I/N            only the I-th (1..N) of N equal frame ranges; join the\n"
    "                         parts without re-encoding (outputs.md, in the guides'\n"
    "                         folder 'springpend --help' names)\n"
    "  --gl osmesa|egl        GL backend (default: OSMesa if installed, else EGL)\n"
    "  --set SECTION.KEY=VAL  override a scene key (repeatable), e.g. --set video.duration=5\n"
    "  --size WxH             shorthand for video.width and video.height\n"
    "  --fps N                shorthand for video.fps\n"
    "  -q, --quiet            no progress line, no 'wrote' line, no notes\n"
    "  -v, --verbose          print where the time went, per stage\n"
    "  -h, --help             this text\n"
    "\n"
    "The video's length. Without a [timeline] (or with captions only) it lasts\n"
    "video.duration / video.speed s: N = round(duration * fps / speed) frames,\n"
    "frame k showing simulated time k * speed / fps. A [timeline] of cues keyed by\n"
    "simulated time (TIME = caption: TEXT | speed S | pause D[: NOTE]) runs a clock\n"
    "instead: from video time 0 the speed (simulated s per video s) is video.speed;\n"
    "'speed S' at T eases, from where the clock reaches T, from the speed s0 then\n"
    "to S over 0.5 s of video as s0 + (S - s0) q(x), q(x) = 3x^2 - 2x^3, x the\n"
    "share of the 0.5 s gone (covering 0.5 (s0 + S) / 2 simulated s; a speed cue\n"
    "inside an ease starts a new one from the speed reached); 'pause D' holds the\n"
    "clock at T for D s of video (an ease resumes after it). The video lasts until\n"
    "the clock reaches video.duration, pauses included: N = round(length * fps)\n"
    "frames, frame k at video time k / fps showing the simulated time the clock\n"
    "gives there, computed for each frame in closed form (nothing summed, so no\n"
    "drift). 'springpend info SCENE' prints the length. A caption fades out over\n"
    "0.25 s of video and the next in over 0.25 s; a pause's note replaces the\n"
    "caption for the pause. The layout (caption band, speed marker, panels) is\n"
    "sized for the longest text the timeline shows and stays fixed; --frames and\n"
    "--shard pieces join into the whole video.\n"
    "\n"
    SIDE_BY_SIDE_HELP;

static const char still_usage[] =
    "usage: springpend still SCENE [SCENE ...] [--at SECONDS] [-o OUTPUT.png|.svg|.pdf]\n"
    "                       [options]\n"
    "\n"
    "Renders one frame at simulated time SECONDS (default 0), integrating only up\n"
    "to it; the trail holds the positions at the video's frame times before it\n"
    "(past the video's end, the frames go on at its last speed).\n"
    "With a [timeline], the caption in force at SECONDS shows at full strength (a\n"
    "pause's note, with the marker 'paused', when a pause is at SECONDS).\n"
    "Default output: out/<scene>.png. NAME.svg and NAME.pdf are vector figures of\n"
    "the same frame (cairo: real paths; the PDF keeps its text selectable).\n"
    "\n"
    "options:\n"
    "  --at SECONDS           simulated time of the frame\n"
    "  -o, --output PATH      where to write (.png, .svg or .pdf)\n"
    "  --state FILE.json      also write the bob's physics state in that frame\n"
    "                         (t, x, y, vx, vy, r, theta, energies), so CI can\n"
    "                         check the physics apart from the pixels\n"
    "  --set SECTION.KEY=VAL  override a scene key (repeatable)\n"
    "  --size WxH             shorthand for video.width and video.height (up to 7680x4320)\n"
    "  --size W[xH] with units  a figure's printed size: 8.6cm, 3.4in, 246pt, 86mm, or\n"
    "                         8.6cmx6cm (the height follows video.width:height when\n"
    "                         left out); text, lines and ticks are then in points\n"
    "                         (10 pt text, 0.8 pt axes, 3.4 pt ticks; view.font_size\n"
    "                         sets the text in pt)\n"
    "  --dpi N                a PNG figure's dots per inch with --size in units\n"
    "                         (default 300; written in its pHYs chunk)\n"
    "  --scale N              draw at N times the size (1..4) and average down:\n"
    "                         supersampled, smoother edges and text (a PNG)\n"
    "  --fps N                shorthand for video.fps (the trail's frame times)\n"
    "  --quality Q            low, medium, high or 4k: render's sizes and rates\n"
    "  --gl osmesa|egl        GL backend (default: OSMesa if installed, else EGL)\n"
    "  -q, --quiet            no 'wrote' line, no notes\n"
    "  -h, --help             this text\n"
    "\n"
    "Teaching overlays and looks come from the scene's [view] keys (panels, hud,\n"
    "theme, background, colormap, colorbar, strobe, trail = all): see 'springpend keys'.\n"
    "A transparent background writes a PNG with alpha, for slides.\n"
    "\n"
    SIDE_BY_SIDE_HELP;

/* Writes the physics of the still's frame as JSON into f, opened here at
 * path and left for the pipeline to put in place with the image, under
 * their folder's lock (attack13 #21: two runs at once left one's image
 * beside the other's state), or to discard. */
struct state_ctx {
    const char *path;
    const struct sp_scene *scene;
};

static int write_state(void *ctx, const struct sp_state *st, struct sp_outfile *out)
{
    const struct state_ctx *c = ctx;
    const char *path = c->path;
    const struct sp_scene *scene = c->scene;
    struct sp_sim sim;
    struct sp_provenance prov;
    struct sp_polar pol;
    struct sp_energy e;
    struct sp_outfile f;
    int ret = sp_provenance_init(&prov, scene, NULL, NULL);
    sp_provenance_free(&prov); /* only its hash is written */
    if (ret || (ret = sp_outfile_open(&f, path, SP_OUTFILE_STREAM)) != 0)
        return ret;
    sp_sim_init(&sim, scene); /* for the parameters and the initial energy */
    /* theta signed by the side of the swing plane, as data writes it; a
     * still has no rows to continue the azimuth from: it is in (-90, 90]
     * degrees, and written, so that theta's sign can be read against it */
    const double azimuth = sim.spatial ? sp_state_azimuth(&sim.p, st) : 0;
    sp_state_polar_in(st, azimuth, &pol);
    sp_state_energy(&sim.p, st, &e);
    char spatial[160] = ""; /* a 3-D scene's: z, vz (m, m/s), azimuth (degrees) */
    if (sim.spatial)
        snprintf(spatial, sizeof(spatial),
                 "  \"z\": %.17g,\n  \"vz\": %.17g,\n  \"azimuth\": %.17g,\n", st->z, st->vz,
                 azimuth * 180 / M_PI);
    FILE *fp = sp_outfile_fdopen(&f); /* f.fd is fp's now */
    if (!fp) {
        sp_log_error("%s: %s", path, strerror(errno));
        sp_outfile_discard(&f);
        return SP_E_NOMEM;
    }
    fprintf(fp,
            "{\n  \"springpend\": \"%s\",\n  \"scene_sha256\": \"%s\",\n"
            "  \"units\": {\"t\": \"s\", \"x\": \"m\", \"y\": \"m\", \"vx\": \"m/s\", "
            "\"vy\": \"m/s\", \"r\": \"m\", \"theta\": \"rad from the downward vertical\", "
            "\"r_dot\": \"m/s\", \"theta_dot\": \"rad/s\", %s\"energy\": \"J\"},\n"
            "  \"t\": %.17g,\n  \"x\": %.17g,\n  \"y\": %.17g,\n"
            "  \"vx\": %.17g,\n  \"vy\": %.17g,\n"
            "  \"r\": %.17g,\n  \"theta\": %.17g,\n  \"r_dot\": %.17g,\n  \"theta_dot\": %.17g,\n"
            "%s"
            "  \"energy\": {\"kinetic\": %.17g, \"spring\": %.17g, \"gravity\": %.17g, "
            "\"total\": %.17g, \"initial_total\": %.17g}\n}\n",
            SP_VERSION, prov.scene_sha256,
            sim.spatial ? "\"z\": \"m\", \"vz\": \"m/s\", \"azimuth\": \"degrees: the swing "
                          "plane's angle about the vertical, from +x towards +z, in (-90, 90]\", " : "",
            st->t, st->x, st->y, st->vx, st->vy, pol.r,
            pol.theta, pol.r_dot, pol.theta_dot, spatial, e.kinetic, e.spring, e.gravity,
            e.total, sim.energy0);
    if (ferror(fp) | fclose(fp)) {
        const int sig = sp_outfile_write_was_stopped();
        if (sig)
            sp_log_error("interrupted by %s while %s waited for its reader: the state stops "
                         "short", sp_signal_name(sig), path);
        else
            sp_log_error("%s: cannot write: %s", path, strerror(errno));
        sp_outfile_discard(&f);
        return sig ? SP_E_INTERRUPTED : SP_E_IO;
    }
    *out = f; /* written; committed with the image */
    return 0;
}

/* What a still can be written as, by extension (PNG through the sink, SVG
 * and PDF through figure.c); the message lists them. */
static const char *const still_formats[] = {"png", "svg", "pdf"};

/* Refuses a still whose -o names a format that is not an image. */
static int check_still_format(const char *out)
{
    const char *base = strrchr(out, '/'), *dot;
    base = base ? base + 1 : out;
    dot = strrchr(base, '.');
    if (!strcmp(out, "-") || sp_outfile_is_stream(out))
        return 0; /* written as PNG */
    char list[128] = "";
    for (size_t i = 0; i < sizeof(still_formats) / sizeof(still_formats[0]); i++) {
        if (dot && dot != base && !strcasecmp(dot + 1, still_formats[i]))
            return 0;
        snprintf(list + strlen(list), sizeof(list) - strlen(list), "%s.%s", i ? ", " : "",
                 still_formats[i]);
    }
    sp_log_error("still -o %s: a still is one image; give a name ending in %s (for a "
                 "video use 'springpend render')", out, list);
    return SP_E_INPUT;
}

/* Refuses --state paths that would clobber an input or the image, or
 * cannot be written; and a still so late that reaching it would take a
 * fixed-step method more than 1e10 steps (scene.c's limit for videos). */
static int check_still(const struct sp_cli_options *o, const struct sp_scene *scene,
                       const char *out)
{
    if (scene->integrator.method <= SP_METHOD_YOSHIDA4 && o->still.at / scene->integrator.dt > 1e10) {
        sp_log_error("--at %g: reaching it takes %.3g steps of integrator.dt = %g s; at most "
                     "1e10 are allowed", o->still.at, o->still.at / scene->integrator.dt,
                     scene->integrator.dt);
        return SP_E_INPUT;
    }
    int ret = check_still_format(out);
    if (!ret && o->still.scale > 1 && sp_figure_format(out) != SP_FIGURE_NONE) {
        /* a vector figure has no pixels to supersample (attack13 #8) */
        sp_log_error("--scale %d: %s is a vector figure, drawn as lines and text at any "
                     "zoom; --scale supersamples a PNG: leave it out", o->still.scale, out);
        return SP_E_INPUT;
    }
    if (ret || !o->still.state)
        return ret;
    int clash = 0; /* every scene side by side; the image by its name too, made or not
                    * (./s.png, d//s.png, its absolute path: attack15 #14) */
    for (int i = 0; i < o->n_scenes; i++)
        clash |= sp_outfile_same_file(o->still.state, o->scene_paths[i]);
    if (clash || sp_outfile_same_output(o->still.state, out)) {
        sp_log_error("--state %s would overwrite the scene or the image; choose another path",
                     o->still.state);
        return SP_E_INPUT;
    }
    return sp_outfile_check_writable(o->still.state, "--state");
}

/* Scenes side by side share the first one's frame and text: the keys in
 * which another may not differ. */
/* What a still or video would draw nothing for, refused where it was given
 * (FILE:LINE or --set; the parser accepts it, since info, data and sweep
 * draw no panels and a sweep's map always has a colour bar):
 * - view.colorbar_label without view.colorbar = true (no bar to name);
 * - the azimuth and top panels of a planar scene (a flat 0 and a line);
 * - with an [ensemble], which draws its members and not the one bob: the
 *   bob's force and velocity arrows, strobe images, trail and colour bar
 *   (attack13 #7), when a scene line or --set asks for them. */
static int check_drawn(const struct sp_cli_options *o, const struct sp_scene *s, int n)
{
    char where[4200], rate[4200];
    for (int i = 0; i < n; i++) {
        const struct sp_view *v = &s[i].view;
        if (s[i].ensemble.count > 1) {
            static const char *const bob_only[] = {"view.vectors", "view.strobe", "view.trail",
                                                   "view.colorbar"};
            const int asked[] = {v->vectors != 0, v->strobe > 0, v->trail != 0, v->colorbar};
            /* refused where given with the ensemble or after it: a scene's
             * own trail gives way to an ensemble added by --set */
            sp_scene_key_where(&s[i], "ensemble.count", o->scene_paths[i], rate, sizeof(rate));
            const int count_set = !strncmp(rate, "--set", 5);
            for (size_t k = 0; k < sizeof(bob_only) / sizeof(bob_only[0]); k++) {
                sp_scene_key_where(&s[i], bob_only[k], o->scene_paths[i], where, sizeof(where));
                if (!asked[k] || !strcmp(where, o->scene_paths[i]) || /* off, or the default */
                    (count_set && strncmp(where, "--set", 5)))
                    continue;
                sp_fprintf_line(stderr, "%s: %s is drawn for the one pendulum, but the scene's "
                                "[ensemble] (count = %d) draws its members instead; leave %s out "
                                "(ensemble.trails = true gives each member a trail), or "
                                "ensemble.count = 1", where, bob_only[k], s[i].ensemble.count,
                                bob_only[k]);
                return SP_E_INPUT;
            }
        }
        const unsigned planar = s[i].initial.azimuth_rate == 0
                                    ? v->panels & (SP_PANEL_AZIMUTH | SP_PANEL_TOP) : 0;
        if (v->colorbar_label[0] && !v->colorbar) {
            sp_scene_key_where(&s[i], "view.colorbar_label", o->scene_paths[i], where,
                               sizeof(where));
            sp_fprintf_line(stderr, "%s: view.colorbar_label = '%s' names the colour bar, but "
                            "view.colorbar = false draws none; allowed: a colorbar_label with "
                            "view.colorbar = true, or none", where, v->colorbar_label);
            return SP_E_INPUT;
        }
        if (planar) {
            sp_scene_key_where(&s[i], "view.panels", o->scene_paths[i], where, sizeof(where));
            sp_scene_key_where(&s[i], "initial.azimuth_rate", o->scene_paths[i], rate,
                               sizeof(rate));
            sp_fprintf_line(stderr, "%s: view.panels holds %s, which show%s the third "
                            "dimension, but the scene is planar (initial.azimuth_rate = 0%s%s): "
                            "its azimuth is 0 and its top view a line; allowed on a planar "
                            "scene: r, theta, energy, extension, phase, poincare, modes, spread, "
                            "energy_bars (azimuth and top need initial.azimuth_rate != 0)", where,
                            planar == SP_PANEL_AZIMUTH ? "azimuth" : planar == SP_PANEL_TOP ? "top"
                            : "azimuth and top", planar == (SP_PANEL_AZIMUTH | SP_PANEL_TOP) ? "" : "s",
                            strcmp(rate, o->scene_paths[i]) ? ", at " : "",
                            strcmp(rate, o->scene_paths[i]) ? rate : "");
            return SP_E_INPUT;
        }
    }
    return 0;
}

/* The encoder settings the output reads, as the sink picks it (--format,
 * else the extension; render's default MP4, still's PNG): crf and preset
 * for MP4 and WebM, png_level for a PNG (a still or a sequence), none for
 * a GIF, raw frames or an SVG or PDF figure. Bits: ENC_CRF, ENC_PRESET,
 * ENC_PNG_LEVEL. */
enum { ENC_CRF = 1, ENC_PRESET = 2, ENC_PNG_LEVEL = 4, ENC_VP9 = 8 /* WebM: VP9's automatic crf */ };
static unsigned encoder_keys(const struct sp_cli_options *o, int still)
{
    const char *out = o->output, *kind = still ? "png" : "mp4";
    if (still)
        return out && sp_figure_format(out) != SP_FIGURE_NONE ? 0 : ENC_PNG_LEVEL;
    if (o->video.format) {
        kind = o->video.format;
    } else if (out) {
        const char *base = strrchr(out, '/') ? strrchr(out, '/') + 1 : out;
        const char *dot = strrchr(base, '.');
        kind = dot && dot != base ? dot + 1 : "";
    }
    if (!strcasecmp(kind, "mp4") || !strcasecmp(kind, "webm"))
        return ENC_CRF | ENC_PRESET | (strcasecmp(kind, "webm") ? 0 : ENC_VP9);
    return !strcasecmp(kind, "png") ? ENC_PNG_LEVEL : 0;
}

static int check_side_by_side(const struct sp_cli_options *o, const struct sp_scene *s, int n,
                              int still)
{
    /* one encoder: the settings it reads too (attack11 #23: a second scene's
     * crf was used or not by the order of the scenes, without a word); the
     * ones it does not read may differ (attack12 #16: a still refused for
     * crf) */
    static const char *const shared[] = {"video.width", "video.height", "video.fps", "video.speed",
                                         "video.crf", "video.png_level", "view.font_size",
                                         "view.font_scale"};
    const unsigned enc = encoder_keys(o, still);
    const char *const reads = enc & ENC_CRF ? ", the encoder's crf and preset (an MP4 or WebM)"
                              : enc & ENC_PNG_LEVEL ? ", the encoder's png_level (a PNG)" : "";
    int bad = 0;
    for (int i = 1; i < n; i++) {
        for (size_t k = 0; k < sizeof(shared) / sizeof(shared[0]); k++) {
            const double a = sp_scene_get_number(&s[0], shared[k]);
            const double b = sp_scene_get_number(&s[i], shared[k]);
            char na[64], nb[64], va[64], vb[64]; /* the numbers, then as a scene shows them */
            const int crf = !strcmp(shared[k], "video.crf");
            /* what the encoder gets: crf 0 is the codec's own (attack14 #5) */
            const double auto_crf = enc & ENC_VP9 ? SP_SINK_CRF_VP9 : SP_SINK_CRF_H264;
            if ((crf && (a ? a : auto_crf) == (b ? b : auto_crf)) || a == b || (isnan(a) && isnan(b)) || (crf && !(enc & ENC_CRF)) ||
                (!strcmp(shared[k], "video.png_level") && !(enc & ENC_PNG_LEVEL)))
                continue;
            char auto_name[64];
            snprintf(auto_name, sizeof(auto_name), " (automatic: %g for %s)", auto_crf,
                     enc & ENC_VP9 ? "VP9" : "H.264");
            snprintf(na, sizeof(na), "%.17g", a);
            snprintf(nb, sizeof(nb), "%.17g", b);
            sp_scene_canonical_display(shared[k], na, va, sizeof(va));
            sp_scene_canonical_display(shared[k], nb, vb, sizeof(vb));
            sp_log_error("%s: %s = %s%s, but %s has %s%s; scenes side by side share the first's "
                         "[video] width, height, fps and speed%s and [view] theme, background, "
                         "font, font_size and font_scale: give them the same (--set applies to "
                         "every scene)", o->scene_paths[i], shared[k], vb,
                         crf && b == 0 ? auto_name : "", o->scene_paths[0], va,
                         crf && a == 0 ? auto_name : "", reads);
            bad = 1;
        }
        const char *pa = sp_scene_preset_name(&s[0]), *pb = sp_scene_preset_name(&s[i]);
        const char *ea = pa ? pa : SP_SINK_PRESET_DEFAULT, *eb = pb ? pb : SP_SINK_PRESET_DEFAULT;
        if ((enc & ENC_PRESET) && strcmp(ea, eb)) { /* auto is superfast (attack14 #5) */
            sp_log_error("%s: video.preset = %s, but %s has %s; scenes side by side share the "
                         "first's encoder", o->scene_paths[i],
                         pb ? pb : "auto (" SP_SINK_PRESET_DEFAULT ")", o->scene_paths[0],
                         pa ? pa : "auto (" SP_SINK_PRESET_DEFAULT ")");
            bad = 1;
        }
        if (s[i].view.theme != s[0].view.theme || s[i].view.background != s[0].view.background) {
            sp_log_error("%s: another view.theme or view.background than %s's; scenes side by "
                         "side share the first's", o->scene_paths[i], o->scene_paths[0]);
            bad = 1;
        }
        if (!sp_text_same_name(s[i].view.font, s[0].view.font)) { /* one list */
            sp_log_error("%s: view.font = \"%s\", but %s has \"%s\"; scenes side by side "
                         "share the first's fonts", o->scene_paths[i], s[i].view.font,
                         o->scene_paths[0], s[0].view.font);
            bad = 1;
        }
    }
    for (int i = 0; i < n; i++)
        if (s[i].timeline || s[i].ensemble.count > 1) {
            sp_log_error("%s: a scene with %s is shown alone, not side by side", o->scene_paths[i],
                         s[i].timeline ? "a [timeline]" : "an [ensemble]");
            bad = 1;
        }
    if (o->still.state) {
        sp_log_error("--state writes one scene's state; give one SCENE with it");
        bad = 1;
    }
    return bad ? SP_E_INPUT : 0;
}

/* An SVG or PDF figure of physical size is drawn at this many px per pt
 * before cairo scales it onto the page: whole-px text sizes and positions
 * then land on quarter points. */
#define VECTOR_PX_PER_PT SP_FIGURE_PX_PER_PT
#define PNG_DPI_DEFAULT 300.0

/* A still of physical size (--size 8.6cm, --dpi): its page (pt), the scale
 * it is drawn at (pt_px) and the scene's video.width and height in px. */
static int paper_still(const struct sp_cli_options *o, struct sp_scene *scene, const char *out,
                       struct sp_pipeline_desc *pd)
{
    const int vector = sp_figure_format(out) != SP_FIGURE_NONE;
    if (vector && o->still.dpi) {
        sp_log_error("--dpi %g: %s is a vector figure (its size is --size's alone); --dpi is "
                     "for a PNG", o->still.dpi, out);
        return SP_E_INPUT;
    }
    pd->page_w = o->still.paper_w;
    pd->page_h = o->still.paper_h > 0 ? o->still.paper_h
                                : o->still.paper_w * scene->video.height / scene->video.width;
    pd->pt_px = vector ? VECTOR_PX_PER_PT : (o->still.dpi ? o->still.dpi : PNG_DPI_DEFAULT) / 72;
    int w = (int)round(pd->page_w * pd->pt_px), h = (int)round(pd->page_h * pd->pt_px);
    if (!vector && sp_cli_png_pixels(pd->page_w, pd->page_h, pd->pt_px * 72, "a PNG still", &w,
                                     &h))
        return SP_E_INPUT;
    if (h < 16) {
        sp_log_error("--size: the height the scene's aspect gives, %.3g pt, is too small; give "
                     "WIDTHxHEIGHT", pd->page_h);
        return SP_E_INPUT;
    }
    scene->video.width = w, scene->video.height = h;
    return 0;
}

/* A still refuses a video encoder's --set keys (attack13 #5). */
static int check_still_keys(const struct sp_cli_options *o)
{
    static const char *const encoder[] = {"video.crf", "video.preset"};
    return sp_cli_check_set_read(o, "still", encoder, 2, 1,
                                 "every key but video.crf and video.preset (a video encoder's; "
                                 "a still is a PNG, SVG or PDF)");
}

/* 1 when the output is an MP4 or WebM video (--format, else the extension,
 * as the sink picks it): a piece of one records its part. */
static int video_kind(const char *out, const char *format)
{
    const char *base = strrchr(out, '/'), *dot;
    base = base ? base + 1 : out;
    dot = strrchr(base, '.');
    const char *kind = format ? format : dot && dot != base ? dot + 1 : "";
    return !strcasecmp(kind, "mp4") || !strcasecmp(kind, "webm");
}

/* Side by side, each scene is held at its own last frame ("Durations" in
 * doc/teaching.md): a still past the longest one's drew every cell ended
 * and charts stretched to --at, empty past the end (attack15 #9). Alone, a
 * still past the end goes on (pipeline.c still_past_end). */
static int check_still_side_end(const struct sp_cli_options *o, const struct sp_scene *scenes)
{
    double end = 0; /* the longest scene's simulated end */
    for (int i = 0; i < o->n_scenes; i++)
        end = fmax(end, scenes[i].video.duration);
    if (o->still.at <= end)
        return 0;
    sp_log_error("--at %.15g: side by side, each scene is held at its own end, and the longest "
                 "ends at t = %.15g s (video.duration); allowed: --at up to %.15g, or a longer "
                 "video.duration (--set video.duration=%g)", o->still.at, end, end,
                 ceil(o->still.at));
    return SP_E_INPUT;
}

/* The longest video render and still make and show, frames. */
#define SP_MAX_VIDEO_FRAMES 1000000

static int run(int argc, char **argv, int still, const volatile sig_atomic_t *cancel)
{
    struct sp_cli_options o;
    static struct sp_scene scenes[SP_CLI_MAX_SCENES]; /* big: not on the stack */
    struct sp_scene *const sp = scenes;
    char out[4096], ext[16] = ".mp4";
    int first = 0, last = 0, ret = sp_cli_parse(&o, argc, argv, still ? still_usage : render_usage,
                                                (still ? SP_CLI_TAKES_STILL : SP_CLI_TAKES_VIDEO) |
                                                    SP_CLI_TAKES_SCENES);
    if (ret)
        return ret > 0 ? 0 : ret;
    ret = still ? check_still_keys(&o) : 0;
    if (!ret)
        ret = sp_cli_load_scenes(&o, scenes);
    if (!ret)
        ret = check_drawn(&o, scenes, o.n_scenes);
    if (!ret && o.n_scenes > 1)
        ret = check_side_by_side(&o, scenes, o.n_scenes, still);

    if (o.video.format)
        snprintf(ext, sizeof(ext), ".%s", o.video.format);
    if (!ret)
        ret = sp_cli_output_path(&o, &scenes[0], still ? ".png" : ext, out, sizeof(out));
    /* a still too: its camera, trail and charts span the video's frames */
    const int clocked = scenes[0].timeline && scenes[0].timeline->clocked;
    if (!ret && !clocked && sp_scene_frame_count(&scenes[0]) > SP_MAX_VIDEO_FRAMES) {
        sp_log_error("video.duration * video.fps / video.speed = %d frames; at most %d are "
                     "allowed in a video (about 4.6 hours at 60 fps)%s",
                     sp_scene_frame_count(&scenes[0]), SP_MAX_VIDEO_FRAMES,
                     still ? "; a still's charts, trail and camera span the scene's video, so "
                             "the same limit holds: a shorter video.duration (at least --at) "
                             "or a lower video.fps draws it" : "");
        ret = SP_E_INPUT;
    } else if (!ret && clocked && sp_timeline_length(&scenes[0]) * scenes[0].video.fps > SP_MAX_VIDEO_FRAMES) {
        sp_log_error("the [timeline]'s speeds and pauses make the video %g s long at %g fps: "
                     "%.4g frames; at most %d are allowed in a video (about 4.6 hours at 60 fps)",
                     sp_timeline_length(&scenes[0]), scenes[0].video.fps,
                     round(sp_timeline_length(&scenes[0]) * scenes[0].video.fps), SP_MAX_VIDEO_FRAMES);
        ret = SP_E_INPUT;
    }
    int n_frames = sp_timeline_frames(&scenes[0]); /* side by side: the longest */
    for (int i = 1; !ret && i < o.n_scenes; i++) {
        n_frames = n_frames > sp_timeline_frames(&sp[i]) ? n_frames : sp_timeline_frames(&sp[i]);
        if (sp_scene_frame_count(&sp[i]) > SP_MAX_VIDEO_FRAMES) {
            sp_log_error("%s: video.duration * video.fps / video.speed = %d frames; at most %d "
                         "are allowed in a video", o.scene_paths[i], sp_scene_frame_count(&sp[i]),
                         SP_MAX_VIDEO_FRAMES);
            ret = SP_E_INPUT;
        }
    }
    if (!ret && !still)
        ret = sp_cli_frame_range(&o, n_frames, &first, &last);
    if (!ret && still)
        ret = check_still(&o, &scenes[0], out);
    if (!ret && still && o.n_scenes > 1)
        ret = check_still_side_end(&o, scenes);
    struct sp_pipeline_desc pd = {0};
    const struct sp_scene recorded = scenes[0]; /* before --size 8.6cm sets its px */
    if (!ret && still && o.still.paper_w)
        ret = paper_still(&o, &scenes[0], out, &pd);
    struct sp_moment end;
    if (!ret)
        sp_timeline_frame(&scenes[0], sp_timeline_frames(&scenes[0]) - 1, &end);
    if (!ret)
        ret = sp_cli_check_work(&o, &scenes[0], still ? fmax(end.t, o.still.at) : end.t, 1, cancel);
    for (int i = 1; !ret && i < o.n_scenes; i++)
        ret = sp_cli_check_work(&o, &sp[i], sp_scene_frame_time(&sp[i], sp_timeline_frames(&sp[i]) - 1), 1, cancel);
    const struct sp_scene *more[SP_CLI_MAX_SCENES - 1];
    for (int i = 1; i < o.n_scenes; i++)
        more[i - 1] = &sp[i];
    if (ret) {
        for (int i = 0; i < o.n_scenes; i++)
            sp_scene_free(&sp[i]);
        return ret;
    }
    struct sp_outfile state_file = {.fd = -1, .slot = -1};
    struct state_ctx state_ctx = {o.still.state, &scenes[0]};
    ret = sp_pipeline_run(&(struct sp_pipeline_desc){
        .scene = &scenes[0], .output = out, .format = still ? "png" : o.video.format,
        .still = still, .still_at = o.still.at < 0 ? 0 : o.still.at, .first = first,
        .last = last, .gl = (enum sp_gl)o.gl, .verbose = o.verbose,
        .handle_signals = !still, .supersample = o.still.scale,
        .write_partner = o.still.state ? write_state : NULL, .partner_ctx = &state_ctx,
        .partner = &state_file,
        .progress = !o.quiet && !(!strcmp(out, "-") && sp_stderr_is_stdout()), .pt_px = pd.pt_px, .page_w = pd.page_w,
        .page_h = pd.page_h, .size_unit = {o.still.paper_unit[0], o.still.paper_unit[1]},
        .more = more, .n_more = o.n_scenes - 1,
        .recorded = pd.pt_px > 0 ? &recorded : NULL,
        .part = o.video.frames || o.video.shard,
        .piece = !still && (o.video.frames || o.video.shard) && video_kind(out, o.video.format)});
    sp_outfile_discard(&state_file); /* when the run failed before it went in */
    for (int i = 0; i < o.n_scenes; i++)
        sp_scene_free(&sp[i]);
    /* An interrupted render keeps the frames so far, when there were any. */
    int kept = ret == SP_E_INTERRUPTED && !still && strcmp(out, "-") && access(out, F_OK) == 0;
    if ((!ret || kept) && !o.quiet)
        sp_fprintf_line(stderr, "wrote %s%s%s", strcmp(out, "-") ? out : "stdout", o.still.state ? " and " : "",
                o.still.state ? o.still.state : "");
    return ret;
}

/* The pipeline owns the signals while it runs (sp_signals_hold): it reads
 * the flag that main's cancel points to itself; before it, cancel stops the
 * work estimate's probe. */
int sp_cmd_render(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    return run(argc, argv, 0, cancel);
}

int sp_cmd_still(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    return run(argc, argv, 1, cancel);
}
