/* springpend: the compare command, for snapshot tests in CI. Decodes PNGs
 * (files or every PNG of two folders) or videos frame by frame, applies
 * image_compare's rule and reports; exit 0 match, 1 differ, 2 unreadable,
 * missing or resized. */
#include <dirent.h>
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/image_compare.h"
#include "springpend/png_io.h"
#include "springpend/video_read.h"

static const char compare_usage[] =
    "usage: springpend compare EXPECTED ACTUAL [options]\n"
    "\n"
    "Compares two PNG images, or every *.png in folder EXPECTED with the file of\n"
    "the same name in folder ACTUAL (subfolders are not walked), or two videos\n"
    "(any name not ending in .png: MP4 and whatever FFmpeg reads) frame by frame.\n"
    "Exit status: 0 all match, 1 some differ, 2 unreadable, missing, extra or\n"
    "resized images, or videos with different frame counts.\n"
    "\n"
    "Default rule (reftest style): a pixel differs when a channel moves by more\n"
    "than --max-diff levels of 255; the images match when at most --max-pixels\n"
    "pixels differ.\n"
    "\n"
    "options:\n"
    "  --max-diff N           levels a channel may move unnoticed (default 3)\n"
    "  --max-pixels N|P%      differing pixels allowed, a count or a percentage\n"
    "                         of the image (default 0.1%)\n"
    "  --metric rms --tol X   pytest-mpl's rule instead: pass when the RMS of the\n"
    "                         RGB differences is <= X levels (default 2)\n"
    "  --diff PATH            on a mismatch, write a diff image to PATH: the\n"
    "                         expected image in grey, differing pixels magenta,\n"
    "                         smaller changes blue. Folders: PATH is a\n"
    "                         folder (made if missing) for NAME.diff.png files;\n"
    "                         videos: the diff of the worst frame\n"
    "  --json                 print the figures as JSON\n"
    "  -q, --quiet            print failures only (no effect with --json)\n"
    "  -h, --help             this text\n";

struct compare_cli {
    struct sp_compare_opts opts;
    const char *diff; /* --diff, NULL = none */
    int json, quiet;
};

/* Parses "N" or "P%" for --max-pixels. */
static int parse_max_pixels(const char *arg, struct sp_compare_opts *o)
{
    char *end;
    double v = strtod(arg, &end);
    if (end != arg && !strcmp(end, "%") && v >= 0 && v <= 100) {
        o->max_pixels = 0;
        o->max_fraction = v / 100;
        if (v == 0)
            o->max_pixels = SP_COMPARE_NONE;
        return 0;
    }
    if (end != arg && !*end && v >= 0 && v <= LONG_MAX / 2 && v == (long)v) {
        o->max_pixels = v == 0 ? SP_COMPARE_NONE : (long)v;
        return 0;
    }
    sp_log_error("--max-pixels %s: expected a pixel count like 100 or a percentage like 0.5%%",
                 arg);
    return SP_E_INPUT;
}

static int parse_args(struct compare_cli *c, int argc, char **argv)
{
    static const struct option longopts[] = {
        {"max-diff", required_argument, 0, 'd'}, {"max-pixels", required_argument, 0, 'p'},
        {"metric", required_argument, 0, 'm'},   {"tol", required_argument, 0, 't'},
        {"diff", required_argument, 0, 'D'},     {"json", no_argument, 0, 'j'},
        {"quiet", no_argument, 0, 'q'},          {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0},
    };
    int ch;
    char *end;
    double v;
    memset(c, 0, sizeof(*c));
    optind = 1;
    opterr = 0;
    while ((ch = getopt_long(argc, argv, "qh", longopts, NULL)) != -1) {
        switch (ch) {
        case 'd':
            v = strtod(optarg, &end);
            if (end == optarg || *end || !(v >= 0 && v <= 255) || v != (int)v) {
                sp_log_error("--max-diff %s: expected an integer from 0 to 255 (levels)", optarg);
                return SP_E_INPUT;
            }
            c->opts.max_diff = v == 0 ? SP_COMPARE_NONE : (int)v;
            break;
        case 'p':
            if (parse_max_pixels(optarg, &c->opts))
                return SP_E_INPUT;
            break;
        case 'm':
            if (!strcmp(optarg, "rms") || !strcmp(optarg, "reftest")) {
                c->opts.metric = optarg[0] == 'r' && optarg[1] == 'm' ? SP_COMPARE_RMS
                                                                      : SP_COMPARE_REFTEST;
                break;
            }
            sp_log_error("--metric %s: expected reftest or rms", optarg);
            return SP_E_INPUT;
        case 't':
            v = strtod(optarg, &end);
            if (end == optarg || *end || !(v >= 0 && v <= 255)) {
                sp_log_error("--tol %s: expected an RMS from 0 to 255 (levels)", optarg);
                return SP_E_INPUT;
            }
            c->opts.tol = v == 0 ? SP_COMPARE_NONE : v;
            break;
        case 'D': c->diff = optarg; break;
        case 'j': c->json = 1; break;
        case 'q': c->quiet = 1; break;
        case 'h': fputs(compare_usage, stdout); return 1;
        default:
            sp_log_error("unknown option '%s'; see 'springpend compare --help'",
                         argv[optind - 1]);
            return SP_E_INPUT;
        }
    }
    if (argc - optind != 2) {
        sp_log_error("expected two images or folders, EXPECTED and ACTUAL; see "
                     "'springpend compare --help'");
        return SP_E_INPUT;
    }
    return 0;
}

/* The figures of one comparison, as the rest of a text line. */
static void print_figures(const struct compare_cli *c, const struct sp_compare_result *r,
                          const char *diff)
{
    printf("%ld of %ld pixels differ by more than %d levels (%ld allowed); "
           "largest difference %d; rms %.3f",
           r->differing, r->pixels, r->max_diff, r->allowed, r->max_channel_diff, r->rms);
    if (c->opts.metric == SP_COMPARE_RMS)
        printf(" %s tol %g", r->pass ? "<=" : ">", r->tol);
    if (r->differing)
        printf("; in x %d..%d, y %d..%d", r->bbox[0], r->bbox[2], r->bbox[1], r->bbox[3]);
    if (diff)
        printf("; diff: %s", diff);
    putchar('\n');
}

/* The provenance.h chunks that, when they differ, explain a mismatch. */
static const char *const provenance_keys[][2] = {
    {"springpend.scene-sha256", "the scene differs (springpend.scene-sha256)"},
    {"Software", "made by another springpend (Software)"},
    {"Source", "made by another GL renderer (Source)"},
};

/* Prints a note (text) or a "notes" array (JSON) for each provenance
 * chunk that both images carry with different values. */
static void report_provenance(const struct compare_cli *c, const char *expected,
                              const char *actual)
{
    int n = 0;
    for (size_t i = 0; i < sizeof(provenance_keys) / sizeof(provenance_keys[0]); i++) {
        char e[256], a[256];
        if (sp_png_read_text(expected, provenance_keys[i][0], e, sizeof(e)) != 1 ||
            sp_png_read_text(actual, provenance_keys[i][0], a, sizeof(a)) != 1 || !strcmp(e, a))
            continue;
        if (c->json) {
            printf("%s", n ? ", " : ", \"notes\": [");
            sp_cli_json_string(provenance_keys[i][1]);
        } else {
            printf("     note: %s: %s vs %s\n", provenance_keys[i][1], e, a);
        }
        n++;
    }
    if (c->json && n)
        printf("]");
}

/* One comparison's report: a line of text or a JSON object. `status` is 0
 * (compared, see r), or the SP_E_* code of why it could not be. pngs, when
 * not NULL, names the expected and actual PNGs of a failed comparison,
 * whose differing provenance is noted. */
static void report(const struct compare_cli *c, const char *name, int status,
                   const char *why, const struct sp_compare_result *r, const char *diff,
                   const char *const pngs[2])
{
    if (c->json) {
        printf("{\"name\": ");
        sp_cli_json_string(name);
        if (status) {
            printf(", \"pass\": false, \"error\": ");
            sp_cli_json_string(why);
            printf("}");
            return;
        }
        printf(", \"pass\": %s, \"metric\": \"%s\", \"pixels\": %ld, \"differing\": %ld, "
               "\"changed\": %ld, \"max_diff\": %d, \"allowed\": %ld, \"tol\": %g, "
               "\"max_channel_diff\": %d, \"rms\": %.6f, \"bbox\": ",
               r->pass ? "true" : "false",
               c->opts.metric == SP_COMPARE_RMS ? "rms" : "reftest", r->pixels, r->differing,
               r->changed, r->max_diff, r->allowed, r->tol, r->max_channel_diff, r->rms);
        if (r->differing)
            printf("[%d, %d, %d, %d]", r->bbox[0], r->bbox[1], r->bbox[2], r->bbox[3]);
        else
            printf("null");
        printf(", \"diff\": ");
        if (diff)
            sp_cli_json_string(diff);
        else
            printf("null");
        if (pngs && !r->pass)
            report_provenance(c, pngs[0], pngs[1]);
        printf("}");
        return;
    }
    if (status) {
        printf("ERROR %s: %s\n", name, why);
        return;
    }
    if (c->quiet && r->pass)
        return;
    printf("%s %s: ", r->pass ? "ok  " : "FAIL", name);
    print_figures(c, r, diff);
    if (pngs && !r->pass)
        report_provenance(c, pngs[0], pngs[1]);
}

/* Compares two PNG files and reports. Returns 0, SP_E_MISMATCH, or
 * SP_E_INPUT when they cannot be compared (unreadable or resized). */
static int compare_files(const struct compare_cli *c, const char *name, const char *expected,
                         const char *actual, const char *diff_path)
{
    struct sp_image e = {0}, a = {0}, d = {0};
    struct sp_compare_result r;
    char why[256] = "";
    int ret = sp_png_read(expected, &e);
    if (ret) {
        snprintf(why, sizeof(why), "cannot read %s", expected);
        goto done;
    }
    ret = sp_png_read(actual, &a);
    if (ret) {
        snprintf(why, sizeof(why), "cannot read %s", actual);
        goto done;
    }
    if (e.width != a.width || e.height != a.height) {
        snprintf(why, sizeof(why), "expected %dx%d, actual %dx%d", e.width, e.height, a.width,
                 a.height);
        sp_log_error("%s is %dx%d but %s is %dx%d; images of different sizes never match",
                     expected, e.width, e.height, actual, a.width, a.height);
        ret = SP_E_INPUT;
        goto done;
    }
    ret = sp_compare_images(&e, &a, &c->opts, &r, diff_path ? &d : NULL);
    if (ret) {
        snprintf(why, sizeof(why), "comparison failed");
        goto done;
    }
    if (!r.pass && diff_path && sp_png_write(diff_path, &d, SP_PNG_LEVEL_DEFAULT) != 0) {
        remove(diff_path); /* logged; the verdict stands */
        diff_path = NULL;
    }
    ret = r.pass ? 0 : SP_E_MISMATCH;
done:
    /* Unreadable or missing input is the caller's mistake: exit 2. */
    if (ret && ret != SP_E_MISMATCH)
        ret = ret == SP_E_NOMEM ? ret : SP_E_INPUT;
    report(c, name, ret == SP_E_MISMATCH ? 0 : ret, why, &r,
           ret == SP_E_MISMATCH ? diff_path : NULL, (const char *const[2]){expected, actual});
    sp_image_free(&e);
    sp_image_free(&a);
    sp_image_free(&d);
    return ret;
}

/* Compares two videos frame by frame: each frame pair under the rule; the
 * videos match when every frame does. Prints the failing frames (text) and
 * a summary with the worst frame; --diff gets the worst frame's diff. */
static int compare_videos(const struct compare_cli *c, const char *expected, const char *actual,
                          const char *diff_path)
{
    struct sp_video_reader *ve = NULL, *va = NULL;
    struct sp_image fe, fa, d = {0}, worst_diff = {0};
    struct sp_compare_result r, worst = {0};
    char why[512] = "", label[PATH_MAX + 32];
    int frames = 0, failed = 0, worst_frame = -1, ret, ge, ga = 0;
    double worst_score = -1;

    if ((ret = sp_video_reader_open(&ve, expected)) != 0 ||
        (ret = sp_video_reader_open(&va, actual)) != 0) {
        snprintf(why, sizeof(why), "cannot read %s", ve ? actual : expected);
        goto done;
    }
    if (c->json)
        printf("{\"name\": "), sp_cli_json_string(actual), printf(", \"failed_frames\": [");
    while ((ge = sp_video_reader_read(ve, &fe)) == 1 && (ga = sp_video_reader_read(va, &fa)) == 1) {
        if (sp_interrupted()) {
            snprintf(why, sizeof(why), "interrupted at frame %d", frames);
            ret = SP_E_INTERRUPTED;
            goto done;
        }
        if (fe.width != fa.width || fe.height != fa.height) {
            snprintf(why, sizeof(why), "frame %d: expected %dx%d, actual %dx%d", frames,
                     fe.width, fe.height, fa.width, fa.height);
            ret = SP_E_INPUT;
            goto done;
        }
        ret = sp_compare_images(&fe, &fa, &c->opts, &r, diff_path ? &d : NULL);
        if (ret)
            goto done;
        double score = c->opts.metric == SP_COMPARE_RMS ? r.rms : (double)r.differing + r.rms * 1e-9;
        if (score > worst_score) {
            worst_score = score, worst = r, worst_frame = frames;
            sp_image_free(&worst_diff);
            worst_diff = d;
            d = (struct sp_image){0};
        }
        sp_image_free(&d);
        if (!r.pass) {
            if (c->json)
                printf("%s%d", failed ? ", " : "", frames);
            else if (failed < 10) {
                snprintf(label, sizeof(label), "%s frame %d", actual, frames);
                report(c, label, 0, NULL, &r, NULL, NULL);
            }
            failed++;
        }
        frames++;
    }
    if (ge < 0 || (ge == 1 && ga < 0)) {
        ret = ge < 0 ? ge : ga;
        snprintf(why, sizeof(why), "cannot decode %s", ge < 0 ? expected : actual);
        goto done;
    }
    if (ge == 1 || (ge == 0 && sp_video_reader_read(va, &fa) == 1)) {
        if (ge == 1)
            snprintf(why, sizeof(why), "%s ends after %d frames; %s has more", actual, frames,
                     expected);
        else
            snprintf(why, sizeof(why), "%s has more than the %d frames of %s", actual, frames,
                     expected);
        sp_log_error("%s", why);
        ret = SP_E_INPUT;
        goto done;
    }
    if (!frames) {
        snprintf(why, sizeof(why), "no frames in %s", expected);
        ret = SP_E_INPUT;
        goto done;
    }
    if (failed && diff_path && sp_png_write(diff_path, &worst_diff, SP_PNG_LEVEL_DEFAULT) != 0) {
        remove(diff_path);
        diff_path = NULL;
    }
    ret = failed ? SP_E_MISMATCH : 0;
done:
    if (ret && ret != SP_E_MISMATCH && ret != SP_E_NOMEM)
        ret = SP_E_INPUT;
    if (c->json) {
        if (!ve || !va)
            printf("{\"name\": "), sp_cli_json_string(actual), printf(", \"failed_frames\": [");
        printf("], \"frames\": %d, \"pass\": %s", frames, ret ? "false" : "true");
        if (why[0])
            printf(", \"error\": "), sp_cli_json_string(why);
        if (worst_frame >= 0) {
            printf(", \"worst_frame\": %d, \"worst\": ", worst_frame);
            report(c, actual, 0, NULL, &worst, ret == SP_E_MISMATCH ? diff_path : NULL, NULL);
        }
        printf("}\n");
    } else if (why[0]) {
        printf("ERROR %s: %s\n", actual, why);
    } else if (!c->quiet || ret) {
        printf("%s %s: %d of %d frames differ; worst frame %d: ", ret ? "FAIL" : "ok  ",
               actual, failed, frames, worst_frame);
        print_figures(c, &worst, ret == SP_E_MISMATCH ? diff_path : NULL);
    }
    sp_image_free(&d);
    sp_image_free(&worst_diff);
    sp_video_reader_destroy(&ve);
    sp_video_reader_destroy(&va);
    return ret;
}

static int is_png_path(const char *path)
{
    size_t n = strlen(path);
    return n > 4 && !strcasecmp(path + n - 4, ".png");
}

static int is_png_name(const struct dirent *d)
{
    size_t n = strlen(d->d_name);
    return d->d_name[0] != '.' && n > 4 && !strcasecmp(d->d_name + n - 4, ".png");
}

/* The worse of two outcomes: input errors over mismatches over success. */
static int worse(int a, int b)
{
    if (a == SP_E_INPUT || b == SP_E_INPUT)
        return SP_E_INPUT;
    return a ? a : b;
}

/* Compares every PNG of folder dir_e with its namesake in dir_a; a PNG in
 * only one of them is an error (a missing render or a missing baseline). */
static int compare_folders(const struct compare_cli *c, const char *dir_e, const char *dir_a)
{
    struct dirent **le = NULL, **la = NULL;
    int ne = scandir(dir_e, &le, is_png_name, alphasort);
    int na = ne < 0 ? -1 : scandir(dir_a, &la, is_png_name, alphasort);
    int ret = 0, n_ok = 0, n_fail = 0, n_err = 0, first = 1;
    if (ne < 0 || na < 0) {
        sp_log_error("cannot list %s", ne < 0 ? dir_e : dir_a);
        ret = SP_E_INPUT;
        goto done;
    }
    if (c->json)
        printf("{\"files\": [");
    /* Both lists are sorted: walk them like a merge. */
    for (int i = 0, j = 0; i < ne || j < na;) {
        int cmp = i >= ne ? 1 : j >= na ? -1 : strcmp(le[i]->d_name, la[j]->d_name);
        const char *name = cmp <= 0 ? le[i]->d_name : la[j]->d_name;
        char pe[PATH_MAX], pa[PATH_MAX], pd[PATH_MAX];
        int r;
        if (c->json && !first)
            printf(", ");
        first = 0;
        if (cmp) {
            char why[PATH_MAX + 64];
            snprintf(why, sizeof(why), cmp < 0 ? "no actual image in %s" : "no baseline in %s",
                     cmp < 0 ? dir_a : dir_e);
            report(c, name, SP_E_INPUT, why, NULL, NULL, NULL);
            r = SP_E_INPUT;
        } else {
            snprintf(pe, sizeof(pe), "%s/%s", dir_e, name);
            snprintf(pa, sizeof(pa), "%s/%s", dir_a, name);
            if (c->diff)
                snprintf(pd, sizeof(pd), "%s/%.*s.diff.png", c->diff, (int)strlen(name) - 4, name);
            r = compare_files(c, name, pe, pa, c->diff ? pd : NULL);
        }
        n_ok += r == 0;
        n_fail += r == SP_E_MISMATCH;
        n_err += r != 0 && r != SP_E_MISMATCH;
        ret = worse(ret, r);
        i += cmp <= 0;
        j += cmp >= 0;
    }
    if (c->json)
        printf("], \"pass\": %s, \"passed\": %d, \"failed\": %d, \"errors\": %d}\n",
               ret ? "false" : "true", n_ok, n_fail, n_err);
    else
        printf("%s: %d compared, %d passed, %d failed, %d missing or unreadable\n",
               ret ? "FAIL" : "ok", n_ok + n_fail + n_err, n_ok, n_fail, n_err);
    if (n_ok + n_fail + n_err == 0) {
        sp_log_error("no PNG files in %s or %s", dir_e, dir_a);
        ret = SP_E_INPUT;
    }
done:
    for (int i = 0; i < ne; i++)
        free(le[i]);
    for (int i = 0; i < na; i++)
        free(la[i]);
    free(le);
    free(la);
    return ret;
}

static int is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

int sp_cmd_compare(int argc, char **argv)
{
    struct compare_cli c;
    int ret = parse_args(&c, argc, argv);
    if (ret)
        return ret > 0 ? 0 : ret;
    const char *e = argv[optind], *a = argv[optind + 1];
    int de = is_dir(e), da = is_dir(a);
    if (de != da) {
        sp_log_error("%s is a %s but %s is not; compare two images or two folders",
                     de ? e : a, "folder", de ? a : e);
        return SP_E_INPUT;
    }
    if (c.diff && (sp_cli_same_file(c.diff, e) || sp_cli_same_file(c.diff, a))) {
        sp_log_error("--diff %s would overwrite an input; choose another path", c.diff);
        return SP_E_INPUT;
    }
    if (de) {
        if (c.diff && !is_dir(c.diff) && mkdir(c.diff, 0777) != 0) {
            sp_log_error("--diff %s: cannot create the folder for the diff images: %s",
                         c.diff, strerror(errno));
            return SP_E_INPUT;
        }
        return compare_folders(&c, e, a);
    }
    if (is_png_path(e) != is_png_path(a)) {
        sp_log_error("%s and %s: compare two PNG images or two videos", e, a);
        return SP_E_INPUT;
    }
    if (!is_png_path(e))
        return compare_videos(&c, e, a, c.diff);
    ret = compare_files(&c, a, e, a, c.diff);
    if (c.json)
        putchar('\n');
    return ret;
}
