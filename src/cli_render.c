/* springpend: the render and still commands. */
#include <stdio.h>
#include <unistd.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/pipeline.h"

static const char render_usage[] =
    "usage: springpend render SCENE [-o OUTPUT] [options]\n"
    "\n"
    "Renders the scene's whole motion. The output's extension picks the kind:\n"
    "  out/NAME.mp4           H.264 video (default: out/<scene>.mp4)\n"
    "  'out/frames/%05d.png'  a PNG sequence, one file per frame\n"
    "\n"
    "options:\n"
    "  -o, --output PATH      where to write\n"
    "  --set SECTION.KEY=VAL  override a scene key (repeatable), e.g. --set video.duration=5\n"
    "  --size WxH             shorthand for video.width and video.height\n"
    "  --fps N                shorthand for video.fps\n"
    "  -q, --quiet            no progress line\n"
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
    "  -h, --help             this text\n"
    "\n"
    "Teaching overlays and looks come from the scene's [view] keys (panels, hud,\n"
    "theme, background, colormap, colorbar, strobe, trail = all): see 'springpend keys'.\n"
    "A transparent background writes a PNG with alpha, for slides.\n";

static int run(int argc, char **argv, int still)
{
    struct sp_cli_options o;
    struct sp_scene scene;
    char out[4096];
    int ret = sp_cli_parse(&o, argc, argv, still ? still_usage : render_usage, still);
    if (ret)
        return ret > 0 ? 0 : ret;
    ret = sp_cli_load_scene(&o, &scene);
    if (!ret)
        ret = sp_cli_output_path(&o, &scene, still ? ".png" : ".mp4", out, sizeof(out));
    if (ret)
        return ret;
    ret = sp_pipeline_run(&(struct sp_pipeline_desc){
        .scene = &scene, .output = out, .still = still,
        .still_at = o.at < 0 ? 0 : o.at,
        .progress = !o.quiet && !still && isatty(2), .supersample = o.scale});
    if (!ret && !o.quiet)
        fprintf(stderr, "wrote %s\n", out);
    return ret;
}

int sp_cmd_render(int argc, char **argv) { return run(argc, argv, 0); }
int sp_cmd_still(int argc, char **argv) { return run(argc, argv, 1); }
