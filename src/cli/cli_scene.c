/* springpend: the scene command. Prints the scene an output of springpend
 * carries, as a scene file: a PNG's or a video's springpend.scene-file text
 * (provenance.h), a CSV's dc:source (csv_metadata.h). */
#include <jansson.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/csv_metadata.h"
#include "springpend/figure.h"
#include "springpend/png_io.h"
#include "springpend/provenance.h"
#include "springpend/video_read.h"

static const char scene_usage[] =
    "usage: springpend scene FILE\n"
    "\n"
    "Prints the scene FILE was made from, as a scene file: every key under its\n"
    "[section] in user units (angles in degrees, names rather than codes), with\n"
    "the --set overrides of the command that made it applied. FILE is a PNG\n"
    "(its springpend.scene-file text), an MP4, WebM or GIF (the same, as a\n"
    "metadata tag), an SVG or PDF figure (a still's or a sweep's: its <metadata>,\n"
    "its /Subject) or a CSV (dc:source in FILE-metadata.json beside it).\n"
    "Written to SCENE.ini under the scene's own file name, the recorded command\n"
    "(CSV: prov:wasGeneratedBy in the metadata) run again gives the same bytes.\n";

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n > m && !strcasecmp(s + n - m, tail);
}

int sp_cmd_scene(int argc, char **argv)
{
    if (argc == 2 && (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help"))) {
        fputs(scene_usage, stdout);
        return 0;
    }
    if (argc != 2 || argv[1][0] == '-') {
        sp_log_error("expected one FILE (a PNG, video or CSV springpend wrote); see "
                     "'springpend scene --help'");
        return SP_E_INPUT;
    }
    const char *path = argv[1];
    if (ends_with(path, ".csv")) {
        json_t *meta = sp_csv_metadata_load(path);
        const char *text = meta ? json_string_value(json_object_get(meta, "dc:source")) : NULL;
        if (meta && !text)
            sp_log_error("%s" SP_CSV_METADATA_SUFFIX ": no dc:source (the scene); expected "
                         "the metadata springpend writes beside a CSV", path);
        if (text)
            fputs(text, stdout);
        json_decref(meta);
        return text ? 0 : SP_E_INPUT;
    }
    static const char *const videos[] = {".mp4", ".m4v", ".mov", ".webm", ".mkv", ".gif"};
    int video = 0;
    for (size_t i = 0; i < sizeof(videos) / sizeof(videos[0]); i++)
        video |= ends_with(path, videos[i]);
    const int figure = ends_with(path, ".svg") || ends_with(path, ".pdf");
    if (!video && !figure && !ends_with(path, ".png")) {
        sp_log_error("%s: not a PNG, video (.mp4, .m4v, .mov, .webm, .mkv, .gif), SVG, PDF "
                     "or CSV; the scene is read from what springpend wrote", path);
        return SP_E_INPUT;
    }
    char *text = malloc(SP_PROVENANCE_SCENE_MAX);
    if (!text) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    int found = figure ? sp_figure_read_scene(path, text, SP_PROVENANCE_SCENE_MAX)
                : !video
                    ? sp_png_read_text(path, SP_PROVENANCE_SCENE_FILE, text, SP_PROVENANCE_SCENE_MAX)
                    : sp_video_read_text(path, SP_PROVENANCE_SCENE_FILE, text,
                                         SP_PROVENANCE_SCENE_MAX);
    if (found == 1 && !text[0])
        found = 0; /* an empty record is no scene (an older springpend's long scenes) */
    if (found == 1)
        fputs(text, stdout);
    else if (found == 0)
        sp_log_error("%s carries no scene (no %s text); springpend's PNGs, videos and CSVs "
                     "do (an older springpend's do not)", path, SP_PROVENANCE_SCENE_FILE);
    free(text);
    return found == 1 ? 0 : found == 0 ? SP_E_INPUT : found;
}
