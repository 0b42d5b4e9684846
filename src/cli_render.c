/* springpend: the render and still commands. */
#include <stdio.h>
#include <unistd.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/pipeline.h"

static const char render_usage[] =
    "usage: springpend render SCENE [-o OUTPUT] [options]\n"
    "\n"
    "Renders the scene's whole motion. The output's extension (or --format) picks\n"
    "the kind:\n"
    "  out/NAME.mp4           H.264 video (default: out/<scene>.mp4); [video] crf, preset\n"
    "  out/NAME.webm          VP9 video\n"
    "  out/NAME.gif           GIF, palette made for the content (short clips)\n"
    "  'out/frames/%05d.png'  a PNG sequence, one file per frame (numbered from 0)\n"
    "  --format raw -o -      raw RGBA8 frames (W*H*4 bytes each) to stdout\n"
    "Files are written as NAME.part and renamed when complete. Ctrl-C (SIGINT) or\n"
    "SIGTERM keeps a playable file of the frames so far (exit 130/143); a second\n"
    "one stops at once and removes the .part.\n"
    "\n"
    "options:\n"
    "  -o, --output PATH      where to write\n"
    "  --format KIND          mp4, webm, gif, png or raw, whatever the extension\n"
    "  --quality Q            low 854x480@15, medium 1280x720@30, high 1920x1080@60,\n"
    "                         4k 3840x2160@60 (--size, --fps, --set still override)\n"
    "  --frames A:B           only frames A..B-1 (from 0; the physics still starts at 0)\n"
    "  --shard I/N            only the I-th (1..N) of N equal frame ranges; join the\n"
    "                         parts without re-encoding (see the README)\n"
    "  --gl osmesa|egl        GL backend (default: OSMesa if installed, else EGL)\n"
    "  --set SECTION.KEY=VAL  override a scene key (repeatable), e.g. --set video.duration=5\n"
    "  --size WxH             shorthand for video.width and video.height\n"
    "  --fps N                shorthand for video.fps\n"
    "  -q, --quiet            no progress line, no 'wrote' line\n"
    "  -v, --verbose          print where the time went, per stage\n"
    "  -h, --help             this text\n";

static const char still_usage[] =
    "usage: springpend still SCENE [--at SECONDS] [-o OUTPUT.png] [options]\n"
    "\n"
    "Renders one frame at simulated time SECONDS (default 0), integrating only up\n"
    "to it; the trail holds the positions at the video's frame times before it.\n"
    "Default output: out/<scene>.png.\n"
    "\n"
    "options:\n"
    "  --at SECONDS           simulated time of the frame\n"
    "  -o, --output PATH      where to write (.png)\n"
    "  --set SECTION.KEY=VAL  override a scene key (repeatable)\n"
    "  --size WxH             shorthand for video.width and video.height (up to 7680x4320)\n"
    "  --scale N              draw at N times the size (1..4) and average down:\n"
    "                         supersampled, smoother edges and text\n"
    "  --gl osmesa|egl        GL backend (default: OSMesa if installed, else EGL)\n"
    "  -h, --help             this text\n"
    "\n"
    "Teaching overlays and looks come from the scene's [view] keys (panels, hud,\n"
    "theme, background, colormap, colorbar, strobe, trail = all): see 'springpend keys'.\n"
    "A transparent background writes a PNG with alpha, for slides.\n";

static int run(int argc, char **argv, int still)
{
    struct sp_cli_options o;
    struct sp_scene scene;
    char out[4096], ext[16] = ".mp4";
    int first = 0, last = 0, ret = sp_cli_parse(&o, argc, argv, still ? still_usage : render_usage, still);
    if (ret)
        return ret > 0 ? 0 : ret;
    ret = sp_cli_load_scene(&o, &scene);
    if (o.format)
        snprintf(ext, sizeof(ext), ".%s", o.format);
    if (!ret)
        ret = sp_cli_output_path(&o, &scene, still ? ".png" : ext, out, sizeof(out));
    if (!ret && !still)
        ret = sp_cli_frame_range(&o, sp_scene_frame_count(&scene), &first, &last);
    if (ret)
        return ret;
    ret = sp_pipeline_run(&(struct sp_pipeline_desc){
        .scene = &scene, .output = out, .format = still ? NULL : o.format,
        .still = still, .still_at = o.at < 0 ? 0 : o.at, .first = first,
        .last = last, .gl = (enum sp_gl)o.gl, .verbose = o.verbose,
        .handle_signals = !still, .supersample = o.scale,
        .progress = !o.quiet && !still && isatty(2)});
    if ((!ret || ret == SP_E_INTERRUPTED) && !o.quiet)
        fprintf(stderr, "wrote %s\n", out);
    return ret;
}

int sp_cmd_render(int argc, char **argv) { return run(argc, argv, 0); }
int sp_cmd_still(int argc, char **argv) { return run(argc, argv, 1); }
