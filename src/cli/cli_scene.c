/* springpend: the scene command. Prints the scene an output of springpend
 * carries, as a scene file: a PNG's or a video's springpend.scene-file text
 * (provenance.h), a CSV's dc:source (csv_metadata.h). */
#include <getopt.h>
#include <jansson.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli.h"
#include "base/command_line.h"
#include "base/decimal.h"
#include "base/utf8.h"
#include "springpend/common.h"
#include "springpend/csv_metadata.h"
#include "springpend/figure.h"
#include "springpend/png_io.h"
#include "springpend/provenance.h"
#include "springpend/video_read.h"

static const char scene_usage[] =
    "usage: springpend scene FILE [--cell K]\n"
    "       springpend scene FILE --command\n"
    "\n"
    "Prints the scene FILE was made from, as a scene file: every key under its\n"
    "[section] in user units (angles in degrees, names rather than codes), with\n"
    "the --set overrides of the command that made it applied. FILE is a PNG\n"
    "(its springpend.scene-file text), an MP4 or WebM (the same, as a metadata\n"
    "tag), an SVG or PDF figure (a still's or a sweep's: its <metadata>, its\n"
    "/Subject) or a CSV (dc:source in FILE-metadata.json beside it). A GIF is\n"
    "the one output that records neither the scene nor the command.\n"
    "Written to SCENE.ini under the scene's own file name, the recorded command\n"
    "(CSV: prov:wasGeneratedBy in the metadata) run again gives the same bytes.\n"
    "A side-by-side output (2 to 4 scenes) carries each of them: all are\n"
    "printed, each after a line '; scene K of N', or with --cell K the K-th\n"
    "alone, as a scene file.\n"
    "--command prints the command line FILE records instead (springpend.command;\n"
    "a CSV's prov:wasGeneratedBy), one line a POSIX shell reads back into its\n"
    "words: read into them and quoted again, so a forged record's $(...) or ;\n"
    "is a plain word; a record that is no such line is refused, exit 2.\n"
    "Outputs other than CSV record it as the option parser read it (each\n"
    "option by its full name: -qo F and --sha 1/2 as --quiet --output F and\n"
    "--shard 1/2), without the output's name (-o, --csv, --state), --threads,\n"
    "-q, --frames and --shard (a part of a PNG sequence is the whole run's; an\n"
    "MP4 or WebM piece records its own); a merged sweep figure records its\n"
    "shards' command and the merge's --size, --dpi and --format. Run it with\n"
    "-o NAME added after its command word (a scene that starts with '-' is\n"
    "recorded after '--', and every word after that is a scene; a CSV's keeps\n"
    "its own -o or --csv FILE: change FILE to NAME instead), where SCENE.ini\n"
    "is the printed scene, and NAME has the same\n"
    "bytes as FILE (a PDF: under the same SOURCE_DATE_EPOCH). A word with a\n"
    "control character, a character that shows nothing (Unicode's default\n"
    "ignorables: U+200B, U+200C, U+034F, U+FE0F, U+3164, U+FEFF; U+2800, U+2028)\n"
    "or a byte that is not UTF-8 was recorded escaped (\\xNN, \\uNNNN):\n"
    "that word must be given again by hand, and --command names it on stderr.\n"
    "A ZWNJ or ZWJ that joins letters (Persian's ZWNJ, an Indic conjunct's,\n"
    "by RFC 5892's contextual rule) changes what is drawn: it is recorded as\n"
    "it is. A backslash is shown as \\\\ (so a typed \\u200c shows as\n"
    "\\\\u200c), outside the quotes, where a shell reads it back as one\n"
    "backslash.\n"
    "What FILE carries is checked before it is printed: it must be a scene as\n"
    "springpend writes one (read back by the scene parser and written again,\n"
    "byte for byte), else it is refused, FILE: KEY:LINE, exit 2.\n";

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n > m && !strcasecmp(s + n - m, tail);
}

/* The key of cell k's scene text (1-based): the first's is
 * SP_PROVENANCE_SCENE_FILE, the others' carry ".K" (provenance.h). */
static void cell_key(int k, char key[64])
{
    if (k == 1)
        snprintf(key, 64, "%s", SP_PROVENANCE_SCENE_FILE);
    else
        snprintf(key, 64, "%s.%d", SP_PROVENANCE_SCENE_FILE, k);
}

/* Prints scene k of n (1-based): with a heading when all of several are. */
static void print_scene(const char *text, int k, int n, int all)
{
    if (all && n > 1)
        printf("%s; scene %d of %d (side by side, cell %d)\n", k > 1 ? "\n" : "", k, n, k);
    fputs(text, stdout);
}

/* The scenes of a CSV: dc:source in its metadata, one string, or an array
 * of 2 to 4 (side by side). */
static int scene_of_csv(const char *path, int cell)
{
    json_t *meta = sp_csv_metadata_load(path);
    if (!meta)
        return SP_E_INPUT;
    json_t *src = json_object_get(meta, "dc:source");
    int n = json_is_array(src) ? (int)json_array_size(src) : json_is_string(src) ? 1 : 0;
    int ret = 0;
    if (!n || (json_is_array(src) && (n < 2 || n > SP_PROVENANCE_MAX_SCENES))) {
        sp_log_error("%s" SP_CSV_METADATA_SUFFIX ":1: dc:source: %s; springpend writes the "
                     "scene there, a string (or 2 to %d strings, side by side)", path,
                     src ? "not a string, nor 2 to 4 strings" : "missing", SP_PROVENANCE_MAX_SCENES);
        ret = SP_E_INPUT;
    }
    if (!ret && cell > n) {
        sp_log_error("--cell %d: %s holds %d scene%s", cell, path, n, n == 1 ? "" : "s");
        ret = SP_E_INPUT;
    }
    for (int k = 1; !ret && k <= n; k++) {
        json_t *t = json_is_array(src) ? json_array_get(src, (size_t)k - 1) : src;
        char key[64];
        snprintf(key, sizeof(key), n > 1 ? "dc:source[%d]" : "dc:source", k - 1);
        if (!json_is_string(t)) {
            sp_log_error("%s" SP_CSV_METADATA_SUFFIX ":1: %s: not a string", path, key);
            ret = SP_E_INPUT;
        } else {
            ret = sp_provenance_scene_check(path, key, json_string_value(t), json_string_length(t));
        }
    }
    for (int k = 1; !ret && k <= n; k++)
        if (!cell || cell == k)
            print_scene(json_string_value(json_is_array(src) ? json_array_get(src, (size_t)k - 1)
                                                            : src), k, n, !cell);
    json_decref(meta);
    return ret;
}

/* Says on stderr each word of the recorded line that holds a character
 * recorded as an escape (\uHHHH, \xHH, \n: a shell reads those back as
 * the typed text, not as the character), with those characters (the first
 * 4), so that the user knows what to retype (attack8 #12). */
static void say_escaped_words(struct sp_command_line *r)
{
    int argc = 0;
    char **w = sp_command_line_words(r, &argc);
    for (int i = 0; i < argc; i++) {
        char what[160] = "";
        size_t used = 0;
        int k = 0;
        for (const char *at = sp_text_next_escaped(w[i], w[i]); at;
             at = sp_text_next_escaped(w[i], at + (sp_utf8_char(at) ? sp_utf8_char(at) : 1))) {
            size_t n;
            const uint32_t u = sp_utf8_char(at) ? sp_utf8_decode(at, &n) : 0;
            char one[48];
            if (!sp_utf8_char(at))
                snprintf(one, sizeof(one), "the byte 0x%02x (not UTF-8)", (unsigned char)*at);
            else if (u < 0x80)
                snprintf(one, sizeof(one), "the control character 0x%02x", (unsigned)u);
            else
                snprintf(one, sizeof(one), "U+%04X", (unsigned)u);
            if (strstr(what, one))
                continue; /* said already */
            if (k++ == 4) {
                snprintf(what + used, sizeof(what) - used, ", ...");
                break;
            }
            used += (size_t)snprintf(what + used, sizeof(what) - used, "%s%s", k > 1 ? ", " : "",
                                     one);
            used = used < sizeof(what) ? used : sizeof(what) - 1;
        }
        if (k)
            sp_log_note("word %d of that command, %s, holds %s: the record writes such a "
                        "character as an escape, which a shell reads back as the escape's own "
                        "letters, not as the character; retype that word with the character "
                        "itself (bash's $'...' quotes read the escapes)", i + 2, w[i], what);
    }
}

/* Whether the words w (argc of them, w[0] the command: render, still,
 * data or sweep) hold what springpend never records for a PNG, video or
 * figure: an output (-o, --output, --csv, --state), --merge, or an option
 * the command does not take. Read as the command reads them, with its own
 * option table (so --cs=FILE, -oFILE and --out FILE are the options they
 * abbreviate), every word whatever the environment says (a '-' before the
 * short options: POSIXLY_CORRECT would stop GNU getopt at the scene file,
 * leaving a --state FILE after it unread: attack11 #3). For a CSV's record
 * (csv 1), what springpend writes there: `data ... -o FILE` (one output)
 * or `sweep ... --csv FILE` (once) with perhaps its figure `-o FIGURE` and
 * a merge's --merge, nothing else (attack11 #2: a forged `still ... --state
 * FILE` passed, and the CSV recipe overwrote FILE); *figure then tells
 * whether a sweep's record writes a figure too. 0; SP_E_INPUT after a
 * message naming the word (attack10 #2: a forged `sweep ... --csv FILE`
 * record, re-run as doc/ci.md says, overwrote FILE); SP_E_NOMEM. */
static int names_output(const char *path, const char *where, char *const *w, int argc, int csv,
                        int *figure)
{
    static const char *const outputs[] = {"output", "csv", "state", "merge"};
    const int sweep = !strcmp(w[0], "sweep");
    const char *shortopts;
    const struct option *opts = sweep ? sp_cli_sweep_options(&shortopts)
                                      : sp_cli_options(&shortopts);
    char **copy = malloc((size_t)(argc + 1) * sizeof(*copy)); /* getopt permutes it */
    char in_order[32];
    if (!copy) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    memcpy(copy, w, (size_t)(argc + 1) * sizeof(*copy));
    snprintf(in_order, sizeof(in_order), "-%s", shortopts); /* operands as 1, in order */
    if (csv && !sweep && strcmp(w[0], "data")) {
        sp_log_error("%s: its %s is a '%s' command, which writes no CSV; not printed", path,
                     where, w[0]);
        free(copy);
        return SP_E_INPUT;
    }
    const int saved = opterr;
    int c, idx, ret = 0, n_output = 0, n_csv = 0;
    opterr = 0;
    optind = 0; /* GNU getopt: start again on these words */
    while (!ret && (idx = -1, c = getopt_long(argc, copy, in_order, opts, &idx)) != -1) {
        if (c == 1)
            continue; /* an operand */
        const char *name = idx >= 0 ? opts[idx].name : c == 'o' ? "output" : NULL;
        int output = 0;
        for (size_t k = 0; name && k < sizeof(outputs) / sizeof(outputs[0]); k++)
            output |= !strcmp(name, outputs[k]);
        if (csv && output) { /* a CSV's own: data's -o, sweep's --csv (and -o, --merge) */
            n_output += !strcmp(name, "output"), n_csv += !strcmp(name, "csv");
            output = !strcmp(name, "state") || (!sweep && strcmp(name, "output")) ||
                     n_output > 1 || n_csv > 1;
        }
        if (c == '?' || c == ':')
            sp_log_error("%s: its %s holds %s, which is no option of 'springpend %s' that an "
                         "output records; not printed", path, where, copy[optind - 1], w[0]);
        else if (output && csv)
            sp_log_error("%s: its %s holds --%s, which springpend never records for a CSV (a "
                         "data command's one -o FILE, a sweep's one --csv FILE and its figure's "
                         "one -o; re-run, it would write or read a file the record names); not "
                         "printed", path, where, name);
        else if (output)
            sp_log_error("%s: its %s holds --%s, %s springpend never records for a PNG, video "
                         "or figure (re-run, it would write or read a file the record names); "
                         "not printed", path, where, name,
                         strcmp(name, "merge") ? "an output that" : "a reading of shards that");
        ret = c == '?' || c == ':' || output ? SP_E_INPUT : 0;
    }
    if (!ret && csv && (sweep ? n_csv : n_output) != 1) {
        sp_log_error("%s: its %s names no CSV (%s); not printed", path, where,
                     sweep ? "a sweep's --csv FILE" : "a data command's -o FILE");
        ret = SP_E_INPUT;
    }
    if (figure)
        *figure = sweep && n_output;
    opterr = saved;
    free(copy);
    return ret;
}

/* Prints a recorded command line as springpend writes one: read into its
 * words (sp_command_line_read: springpend's own quoting, a command whose
 * outputs record one) and written again from them, quoted, shown as
 * messages are (sp_command_line_text), so that what reaches a shell that
 * runs it is those words and nothing else, whoever forged the file
 * (attack9 #8: a record's $(...) ran in doc/ci.md's eval recipe); then
 * says which words must be retyped (say_escaped_words). 0, SP_E_NOMEM, or
 * SP_E_INPUT (logged) when there is none or it is no such line, or when
 * a PNG's, video's or figure's record (csv 0) holds what such a record never
 * does, or a CSV's (csv 1) what springpend never writes there (names_output:
 * a CSV's record keeps its own output; *figure, when not NULL, gets whether
 * it writes a sweep's figure too). */
static int print_command(const char *path, const char *where, const char *line, int csv,
                         int *figure)
{
    static const char *const recording[] = {"render", "still", "data", "sweep"};
    if (!line || !line[0]) {
        sp_log_error("%s carries no command (no %s); springpend records the command line that "
                     "made an output but a GIF (an older springpend's do not)", path, where);
        return SP_E_INPUT;
    }
    struct sp_command_line *r = sp_command_line_read(line);
    int argc = 0, known = 0;
    char **w = r ? sp_command_line_words(r, &argc) : NULL;
    for (size_t k = 0; w && k < sizeof(recording) / sizeof(recording[0]); k++)
        known |= !strcmp(w[0], recording[k]);
    if (!known) {
        sp_log_error("%s: its %s is not a command line springpend writes (the words of a "
                     "render, still, data or sweep command, quoted as springpend quotes them); "
                     "not printed", path, where);
        sp_command_line_free(r);
        return SP_E_INPUT;
    }
    int ret = names_output(path, where, w, argc, csv, figure);
    if (ret) {
        sp_command_line_free(r);
        return ret;
    }
    char *again = sp_command_line_text(r);
    if (!again) {
        sp_command_line_free(r);
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    sp_fputs_record(again, 0, stdout);
    putchar('\n');
    fflush(stdout); /* the line before what is said about it */
    say_escaped_words(r);
    free(again);
    sp_command_line_free(r);
    return 0;
}

/* A CSV's command: prov:wasGeneratedBy in its metadata, -o FILE included. */
static int command_of_csv(const char *path)
{
    json_t *meta = sp_csv_metadata_load(path);
    if (!meta)
        return SP_E_INPUT;
    int figure = 0;
    const int ret = print_command(path, "prov:wasGeneratedBy in " SP_CSV_METADATA_SUFFIX,
                                  json_string_value(json_object_get(meta, "prov:wasGeneratedBy")), 1,
                                  &figure);
    json_decref(meta);
    if (!ret) /* the other records leave it out: "add -o NAME" would give it twice */
        sp_log_note("a CSV's command keeps its own output (-o or --csv FILE): to make the CSV "
                    "again as NAME, change that FILE to NAME, rather than adding -o NAME%s",
                    figure ? "; it writes its figure too (-o FIGURE): change that name as well"
                           : "");
    return ret;
}

/* The command a PNG, a video (springpend.command) or a figure records. */
static int command_of(const char *path, int figure, int video)
{
    char *text = malloc(SP_PROVENANCE_SCENE_MAX);
    if (!text) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    const int found = figure ? sp_figure_read_command(path, text, SP_PROVENANCE_SCENE_MAX)
                    : video ? sp_video_read_text(path, SP_PROVENANCE_COMMAND, text,
                                                 SP_PROVENANCE_SCENE_MAX)
                            : sp_png_read_text(path, SP_PROVENANCE_COMMAND, text,
                                               SP_PROVENANCE_SCENE_MAX);
    const int ret = found < 0 ? found
                    : print_command(path, figure ? "command record" : SP_PROVENANCE_COMMAND " text",
                                    found ? text : NULL, 0, NULL);
    free(text);
    return ret;
}

int sp_cmd_scene(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    static const struct option longopts[] = {
        {"cell", required_argument, 0, 'c'}, {"command", no_argument, 0, 'C'},
        {"help", no_argument, 0, 'h'}, {0, 0, 0, 0},
    };
    const char *first[128] = {0};
    int cell = 0, command = 0, c;
    (void)cancel; /* reads one file: nothing runs long */
    optind = 1;
    opterr = 0;
    /* getopt_long, as every command: options before or after FILE, '--'
     * ends them (a file named -x.png) */
    while ((c = getopt_long(argc, argv, ":h", longopts, NULL)) != -1) {
        double v;
        if (sp_cli_once(c, longopts, "", first))
            return SP_E_INPUT;
        switch (c) {
        case 'h':
            fputs(scene_usage, stdout);
            return 0;
        case 'c':
            if (sp_cli_number("--cell", optarg, 1, SP_PROVENANCE_MAX_SCENES, SP_DECIMAL_INTEGER,
                              "a side-by-side cell, an integer from 1 to 4", &v))
                return SP_E_INPUT;
            cell = (int)v;
            break;
        case 'C':
            command = 1;
            break;
        case ':':
            sp_log_error("option '%s' needs a value; see 'springpend scene --help'",
                         argv[optind - 1]);
            return SP_E_INPUT;
        default:
            sp_cli_bad_option(argv[optind - 1], longopts, "scene");
            return SP_E_INPUT;
        }
    }
    if (argc - optind != 1 || (command && cell)) {
        sp_log_error("expected one FILE (a PNG, video, SVG, PDF or CSV springpend wrote) and perhaps "
                     "--cell K or --command; see 'springpend scene --help'");
        return SP_E_INPUT;
    }
    const char *path = argv[optind];
    if (ends_with(path, ".csv"))
        return command ? command_of_csv(path) : scene_of_csv(path, cell);
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
    if (command)
        return command_of(path, figure, video);
    char *texts[SP_PROVENANCE_MAX_SCENES] = {0};
    int n = 0, found = 1;
    for (int k = 1; k <= SP_PROVENANCE_MAX_SCENES && found == 1; k++) {
        char key[64];
        cell_key(k, key);
        if (!(texts[k - 1] = malloc(SP_PROVENANCE_SCENE_MAX))) {
            sp_log_error("out of memory");
            found = SP_E_NOMEM;
            break;
        }
        if (figure && k > 1)
            break; /* an SVG or PDF records its (first) scene alone */
        found = figure ? sp_figure_read_scene(path, texts[k - 1], SP_PROVENANCE_SCENE_MAX)
                : !video ? sp_png_read_text(path, key, texts[k - 1], SP_PROVENANCE_SCENE_MAX)
                         : sp_video_read_text(path, key, texts[k - 1], SP_PROVENANCE_SCENE_MAX);
        if (found == 1 && (n = k, sp_provenance_scene_check(path, key, texts[k - 1],
                                                  strlen(texts[k - 1]))))
            found = SP_E_INPUT;
    }
    int ret = found < 0 ? found : 0;
    if (!ret && !n) {
        sp_log_error("%s carries no scene (no %s text); springpend's PNGs, MP4 and WebM "
                     "videos, SVGs, PDFs and CSVs do, a GIF never (nor an older springpend's "
                     "outputs)", path, SP_PROVENANCE_SCENE_FILE);
        ret = SP_E_INPUT;
    }
    if (!ret && cell > n) {
        sp_log_error("--cell %d: %s holds %d scene%s", cell, path, n, n == 1 ? "" : "s");
        ret = SP_E_INPUT;
    }
    for (int k = 1; !ret && k <= n; k++)
        if (!cell || cell == k)
            print_scene(texts[k - 1], k, n, !cell);
    for (int k = 0; k < SP_PROVENANCE_MAX_SCENES; k++)
        free(texts[k]);
    return ret;
}
