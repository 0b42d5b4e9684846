/* springpend: the compare command, for snapshot tests in CI. Decodes PNGs
 * (files or every PNG of two folders) or videos frame by frame, applies
 * image_compare's rule (exact pixels first, the tolerance second) and
 * records each outcome; compare_report.c's reporters print the records.
 * Exit 0 match, 1 differ, 2 unreadable or missing, 128 + signal. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <libgen.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/compare_config.h"
#include "springpend/compare_report.h"
#include "springpend/image_compare.h"
#include "springpend/outfile.h"
#include "springpend/png_io.h"
#include "springpend/scene.h"
#include "springpend/video_read.h"
#include "signals.h"

static const char compare_usage[] =
    "usage: springpend compare EXPECTED ACTUAL [options]\n"
    "\n"
    "Compares two PNG images, or every *.png in folder EXPECTED with the file of\n"
    "the same name in folder ACTUAL (subfolders are not walked), or two videos\n"
    "(any name not ending in .png: MP4 and whatever FFmpeg reads) frame by frame,\n"
    "frame times included.\n"
    "Exit status: 0 all match, 1 some differ (in pixels, size or timing), 2\n"
    "unreadable, missing or extra images, or videos with different frame\n"
    "counts; 128 + signal when interrupted.\n"
    "\n"
    "Identical decoded pixels (equal SHA-256) match at once. Otherwise the\n"
    "default rule (reftest style): a pixel differs when a channel moves by more\n"
    "than --max-diff levels of 255; the images match when at most --max-pixels\n"
    "pixels differ. SSIM is printed beside the counts; it never decides.\n"
    "A compare.ini beside the baselines sets tolerances and masks per image.\n"
    "\n"
    "options:\n"
    "  --max-diff N           levels a channel may move unnoticed (default 3)\n"
    "  --max-pixels N|P%      differing pixels allowed, a count or a percentage\n"
    "                         of the image (default 0.1%)\n"
    "  --metric rms --tol X   pytest-mpl's rule instead: pass when the RMS of the\n"
    "                         RGB differences is <= X levels (default 2)\n"
    "  --diff PATH            on a mismatch, write a diff image to PATH: the\n"
    "                         expected image in grey, differing pixels magenta,\n"
    "                         smaller changes blue; both side by side when the\n"
    "                         sizes differ. Folders: PATH is a folder (made if\n"
    "                         missing) for NAME.diff.png files; videos: the diff\n"
    "                         of the worst frame\n"
    "  --update=MODE          copy ACTUAL over EXPECTED: missing (new images),\n"
    "                         changed (and failing ones), all (and every image\n"
    "                         whose file differs; deletes baselines that have no\n"
    "                         actual image, listing them)\n"
    "  --report FILE.html     one self-contained HTML page: expected, actual and\n"
    "                         diff side by side, a flip control, failures first\n"
    "  --junit FILE.xml       JUnit XML, a test case per image\n"
    "  --json                 print the records as JSON (schema in the README)\n"
    "  -q, --quiet            print failures only (no effect with --json)\n"
    "  -h, --help             this text\n";

enum update_mode { UPDATE_NONE, UPDATE_MISSING, UPDATE_CHANGED, UPDATE_ALL };

struct compare_cli {
    struct sp_compare_rule base;   /* the command line's rule */
    struct sp_compare_config cfg;  /* compare.ini beside the baselines; rules
                                      note which images used them */
    const char *diff;              /* --diff, NULL = none */
    const char *html, *junit;      /* --report, --junit, NULL = none */
    enum update_mode update;
    int json, quiet;
    unsigned diff_links;           /* write_whole's flags for diff images:
                                      SP_OUTFILE_REPLACE_LINK in folder mode */
};

static int parse_args(struct compare_cli *c, int argc, char **argv)
{
    static const struct option longopts[] = {
        {"max-diff", required_argument, 0, 'd'}, {"max-pixels", required_argument, 0, 'p'},
        {"metric", required_argument, 0, 'm'},   {"tol", required_argument, 0, 't'},
        {"diff", required_argument, 0, 'D'},     {"json", no_argument, 0, 'j'},
        {"update", required_argument, 0, 'u'},   {"report", required_argument, 0, 'R'},
        {"junit", required_argument, 0, 'J'},    {"quiet", no_argument, 0, 'q'},
        {"help", no_argument, 0, 'h'},           {0, 0, 0, 0},
    };
    int ch, idx;
    char why[1024];
    memset(c, 0, sizeof(*c));
    optind = 1;
    opterr = 0;
    while ((ch = getopt_long(argc, argv, ":qh", longopts, &idx)) != -1) {
        switch (ch) {
        case 'd': case 'p': case 'm': case 't':
            if (sp_compare_rule_set(&c->base, longopts[idx].name, optarg, why, sizeof(why))) {
                sp_log_error("--%s", why);
                return SP_E_INPUT;
            }
            break;
        case 'u':
            c->update = !strcmp(optarg, "missing") ? UPDATE_MISSING
                        : !strcmp(optarg, "changed") ? UPDATE_CHANGED
                        : !strcmp(optarg, "all")     ? UPDATE_ALL
                                                     : UPDATE_NONE;
            if (c->update == UPDATE_NONE && strcmp(optarg, "none")) {
                sp_log_error("--update=%s: expected missing, changed, all or none", optarg);
                return SP_E_INPUT;
            }
            break;
        case 'D': c->diff = optarg; break;
        case 'R': c->html = optarg; break;
        case 'J': c->junit = optarg; break;
        case 'j': c->json = 1; break;
        case 'q': c->quiet = 1; break;
        case 'h': fputs(compare_usage, stdout); return 1;
        case ':':
            sp_log_error("%s needs a value; see 'springpend compare --help'", argv[optind - 1]);
            return SP_E_INPUT;
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

/* Writes path whole or not at all through outfile.h (a unique .part in the
 * signal table, renamed over path when complete and removed when not).
 * Only a regular file or a new name is replaced; a folder or device at path
 * is refused (SP_E_INPUT). flags: sp_outfile_open's. */
static int write_whole(const char *path, unsigned flags, int (*fill)(FILE *, void *),
                       void *arg)
{
    struct sp_outfile f;
    int err = sp_outfile_open(&f, path, flags);
    if (err)
        return err;
    FILE *fp = fdopen(f.fd, "wb");
    if (!fp) {
        sp_log_error("%s: %s", path, strerror(errno));
        sp_outfile_discard(&f);
        return SP_E_NOMEM;
    }
    f.fd = -1; /* fp owns it now */
    err = fill(fp, arg);
    if (fclose(fp) != 0 && !err) {
        sp_log_error("%s: cannot write: %s", path, strerror(errno));
        err = SP_E_IO;
    }
    if (err) {
        sp_outfile_discard(&f);
        return err;
    }
    return sp_outfile_commit(&f);
}

/* An image to write and the path it goes to, for messages. */
struct png_out {
    const struct sp_image *img;
    const char *path;
};

static int fill_png(FILE *fp, void *out)
{
    const struct png_out *o = out;
    return sp_png_write_stream(fp, o->img, SP_PNG_LEVEL_DEFAULT, o->path);
}

/* Copies the regular file at src (opened without blocking, so a FIFO is
 * refused rather than waited on). */
static int fill_copy(FILE *fp, void *src)
{
    struct stat st;
    char buf[65536];
    ssize_t n;
    int fd = open(src, O_RDONLY | O_NONBLOCK | O_CLOEXEC), err = 0;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        sp_log_error("%s: %s", (const char *)src,
                     fd < 0 ? strerror(errno) : "not a regular file; not copied");
        if (fd >= 0)
            close(fd);
        return SP_E_INPUT;
    }
    while ((n = read(fd, buf, sizeof(buf))) > 0)
        if (fwrite(buf, 1, (size_t)n, fp) != (size_t)n) {
            sp_log_error("cannot write a copy of %s: %s", (const char *)src, strerror(errno));
            err = SP_E_IO;
            break;
        }
    if (n < 0) {
        sp_log_error("%s: cannot read: %s", (const char *)src, strerror(errno));
        err = SP_E_IO;
    }
    close(fd);
    return err;
}

/* 1 when both regular files hold the same bytes. */
static int same_bytes(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    int same = fa && fb;
    char x[65536], y[65536];
    while (same) {
        size_t n = fread(x, 1, sizeof(x), fa), m = fread(y, 1, sizeof(y), fb);
        same = n == m && !memcmp(x, y, n);
        if (!n)
            break;
    }
    if (fa)
        fclose(fa);
    if (fb)
        fclose(fb);
    return same;
}

/* --update: copies the actual image over (or to) target, or removes
 * target, as the mode says for what the record found. */
static void apply_update(const struct compare_cli *c, struct sp_compare_record *r,
                         const char *target)
{
    enum sp_update_action act = SP_UPDATE_NONE;
    int missing = !r->expected[0], gone = !r->actual[0];
    if (c->update == UPDATE_NONE || (missing && gone))
        return;
    if (missing)
        act = SP_UPDATE_ADDED;
    else if (gone)
        act = c->update == UPDATE_ALL ? SP_UPDATE_REMOVED : SP_UPDATE_NONE;
    else if (r->verdict == SP_VERDICT_FAIL && c->update >= UPDATE_CHANGED)
        act = SP_UPDATE_REPLACED;
    else if (r->verdict == SP_VERDICT_PASS && c->update == UPDATE_ALL &&
             !same_bytes(r->expected, r->actual))
        act = SP_UPDATE_REPLACED;
    if (act == SP_UPDATE_NONE)
        return;
    if (act == SP_UPDATE_REMOVED) {
        if (unlink(target) != 0) {
            sp_log_error("%s: cannot remove: %s", target, strerror(errno));
            return;
        }
    } else if (write_whole(target, SP_OUTFILE_REPLACE_LINK, fill_copy, r->actual) != 0) {
        return; /* a link is replaced by the file, never written through */
    }
    snprintf(r->expected, sizeof(r->expected), "%s", target);
    r->update = act;
}

/* The provenance chunks that, when they differ, explain a mismatch. */
static const char *const provenance_keys[][2] = {
    {"springpend.scene-sha256", "the scene differs (springpend.scene-sha256)"},
    {"Software", "made by another springpend (Software)"},
    {"Source", "made by another GL renderer (Source)"},
};

/* The value of key in canonical scene text ("key=value\n" lines), into
 * val; 0 when absent. */
static int scene_value(const char *text, const char *key, char *val, size_t size)
{
    size_t n = strlen(key);
    for (const char *p = text; *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : p + strlen(p))
        if (!strncmp(p, key, n) && p[n] == '=') {
            snprintf(val, size, "%.*s", (int)strcspn(p + n + 1, "\n"), p + n + 1);
            return 1;
        }
    return 0;
}

/* Notes the provenance chunks that differ, and the scene keys that
 * changed (from springpend.scene) with both values. */
static void note_provenance(struct sp_compare_record *r)
{
    static char se[16384], sa[16384]; /* canonical scene texts */
    for (size_t i = 0; i < sizeof(provenance_keys) / sizeof(provenance_keys[0]); i++) {
        char e[256], a[256];
        if (sp_png_read_text(r->expected, provenance_keys[i][0], e, sizeof(e)) != 1 ||
            sp_png_read_text(r->actual, provenance_keys[i][0], a, sizeof(a)) != 1 ||
            !strcmp(e, a))
            continue;
        snprintf(r->notes[r->n_notes++], sizeof(r->notes[0]), "%s: %.16s vs %.16s",
                 provenance_keys[i][1], e, a);
    }
    if (sp_png_read_text(r->expected, "springpend.scene", se, sizeof(se)) != 1 ||
        sp_png_read_text(r->actual, "springpend.scene", sa, sizeof(sa)) != 1)
        return;
    for (const char *p = se; *p;) {
        size_t eq = strcspn(p, "=\n"), len = strcspn(p, "\n");
        char key[64], ve[48], va[48] = "(none)";
        if (p[eq] == '=' && eq < sizeof(key)) {
            snprintf(key, sizeof(key), "%.*s", (int)eq, p);
            snprintf(ve, sizeof(ve), "%.*s", (int)(len - eq - 1), p + eq + 1);
            if (!scene_value(sa, key, va, sizeof(va)) || strcmp(ve, va)) {
                if (r->n_changes < SP_COMPARE_MAX_CHANGES) {
                    struct sp_scene_change *ch = &r->changes[r->n_changes++];
                    snprintf(ch->key, sizeof(ch->key), "%s", key);
                    sp_scene_canonical_display(key, ve, ch->expected, sizeof(ch->expected));
                    sp_scene_canonical_display(key, va, ch->actual, sizeof(ch->actual));
                } else {
                    r->more_changes++;
                }
            }
        }
        p += len + (p[len] == '\n');
    }
}

/* Marks r as not comparable. */
static int record_error(struct sp_compare_record *r, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static int record_error(struct sp_compare_record *r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->error, sizeof(r->error), fmt, ap);
    va_end(ap);
    r->verdict = SP_VERDICT_ERROR;
    return SP_E_INPUT;
}

/* Reads the header of path; refuses what is too large to decode. */
static int check_header(struct sp_compare_record *r, const char *path, int *w, int *h)
{
    struct sp_png_info info;
    int err = sp_png_read_info(path, &info);
    if (err)
        return record_error(r, err == SP_E_INPUT ? "%s is not a regular file"
                                                 : "cannot read %s as a PNG", path);
    *w = info.width, *h = info.height;
    if (sp_png_check_size(path, &info) != 0)
        return record_error(r, "%s is %dx%d, beyond the %ld-pixel limit", path, info.width,
                            info.height, SP_PNG_MAX_PIXELS);
    return 0;
}

/* Compares two PNG files into record r. diff_path may be NULL. */
static void compare_files(struct compare_cli *c, struct sp_compare_record *r,
                          const char *name, const char *expected, const char *actual,
                          const char *diff_path)
{
    struct sp_image e = {0}, a = {0}, d = {0};
    struct sp_compare_opts opts;
    const struct sp_compare_mask *masks, *star_masks;
    int n_masks, n_star_masks;

    snprintf(r->name, sizeof(r->name), "%s", name);
    snprintf(r->expected, sizeof(r->expected), "%s", expected);
    snprintf(r->actual, sizeof(r->actual), "%s", actual);
    /* compare.ini names images by the baseline's file name. */
    const char *slash = strrchr(expected, '/');
    sp_compare_config_resolve(&c->cfg, slash ? slash + 1 : expected, &c->base.opts, &opts,
                              &masks, &n_masks, &star_masks, &n_star_masks);
    r->metric = opts.metric;
    /* Both headers first: nothing is decoded that is too large. */
    if (check_header(r, expected, &r->expected_w, &r->expected_h)) {
        struct sp_png_info info; /* the actual image may still be shown */
        r->actual_png = sp_png_read_info(actual, &info) == 0;
        goto done;
    }
    r->expected_png = 1;
    if (check_header(r, actual, &r->actual_w, &r->actual_h))
        goto done;
    r->actual_png = 1;
    if ((r->expected_w != r->actual_w || r->expected_h != r->actual_h) && !diff_path) {
        /* The headers decide; only a diff image would need the pixels. */
        r->compared = r->size_mismatch = 1;
        r->verdict = SP_VERDICT_FAIL;
        note_provenance(r);
        goto done;
    }
    if (sp_png_read(expected, &e) != 0) {
        record_error(r, "cannot read %s", expected);
        goto done;
    }
    if (sp_png_read(actual, &a) != 0) {
        record_error(r, "cannot read %s", actual);
        goto done;
    }
    if (sp_compare_pixel_hash(&e, r->expected_sha256) ||
        sp_compare_pixel_hash(&a, r->actual_sha256)) {
        record_error(r, "out of memory");
        goto done;
    }
    r->compared = 1;
    if (!strcmp(r->expected_sha256, r->actual_sha256)) {
        /* Exact first: identical pixels need no rule. */
        r->exact = 1;
        r->result.pixels = (long)e.width * e.height;
        r->result.bbox[0] = r->result.bbox[1] = r->result.bbox[2] = r->result.bbox[3] = -1;
        r->ssim = 1;
        r->verdict = SP_VERDICT_PASS;
        goto done;
    }
    if (e.width != a.width || e.height != a.height) {
        r->size_mismatch = 1;
        r->verdict = SP_VERDICT_FAIL;
        if (diff_path && sp_compare_size_diff(&e, &a, &d) != 0)
            diff_path = NULL;
    } else {
        sp_compare_apply_masks(&e, &a, star_masks, n_star_masks);
        sp_compare_apply_masks(&e, &a, masks, n_masks);
        r->masked_pixels = sp_compare_masked_pixels(e.width, e.height, star_masks,
                                                    n_star_masks, masks, n_masks);
        if (sp_compare_images(&e, &a, &opts, &r->result, diff_path ? &d : NULL) != 0) {
            record_error(r, "comparison failed");
            goto done;
        }
        r->ssim = sp_compare_ssim(&e, &a);
        r->verdict = r->result.pass ? SP_VERDICT_PASS : SP_VERDICT_FAIL;
    }
    if (r->verdict == SP_VERDICT_FAIL) {
        /* A diff image in a folder replaces a link there, never follows it. */
        if (diff_path && write_whole(diff_path, c->diff_links, fill_png,
                                     &(struct png_out){&d, diff_path}) == 0)
            snprintf(r->diff, sizeof(r->diff), "%s", diff_path);
        note_provenance(r);
    }
done:
    sp_image_free(&e);
    sp_image_free(&a);
    sp_image_free(&d);
}

/* One frame read on another thread. */
struct read_job {
    struct sp_video_reader *r;
    struct sp_image img; /* the frame, owned by r */
    double t;            /* its time, s */
    int ret;             /* sp_video_reader_read's */
};

static void *read_job_run(void *arg)
{
    struct read_job *j = arg;
    j->ret = sp_video_reader_read(j->r, &j->img, &j->t);
    return NULL;
}

/* Frame times that differ by more than this are a failure, s: well under
 * a frame at any rate a video has. */
#define FRAME_TIME_SLACK 5e-4

/* Compares two videos frame by frame, times included, into record r: the
 * figures are the worst frame's; --diff gets its diff image. */
static int compare_videos(struct compare_cli *c, struct sp_compare_record *r,
                          const char *expected, const char *actual, const char *diff_path)
{
    struct sp_video_reader *ve = NULL, *va = NULL;
    struct sp_image fe, fa, d = {0}, worst_diff = {0};
    struct sp_compare_result res;
    int ret, ge, ga = 0, timing_noted = 0;
    double worst_score = -1, te = 0, ta = 0, te0 = NAN, ta0 = NAN;

    struct sp_compare_opts opts;
    const struct sp_compare_mask *masks, *star_masks;
    int n_masks, n_star_masks;
    const char *slash = strrchr(expected, '/');
    snprintf(r->name, sizeof(r->name), "%s", actual);
    snprintf(r->expected, sizeof(r->expected), "%s", expected);
    snprintf(r->actual, sizeof(r->actual), "%s", actual);
    sp_compare_config_resolve(&c->cfg, slash ? slash + 1 : expected, &c->base.opts, &opts,
                              &masks, &n_masks, &star_masks, &n_star_masks);
    r->metric = opts.metric;
    if ((ret = sp_video_reader_open(&ve, expected)) != 0 ||
        (ret = sp_video_reader_open(&va, actual)) != 0) {
        ret = record_error(r, "cannot read %s", ve ? actual : expected);
        goto done;
    }
    for (;;) {
        /* The two decoders run at once, one on a thread of its own: the
         * decoding and conversion are most of the time. */
        struct read_job job = {.r = ve};
        pthread_t th;
        int threaded = pthread_create(&th, NULL, read_job_run, &job) == 0;
        if (!threaded)
            read_job_run(&job);
        ga = sp_video_reader_read(va, &fa, &ta);
        if (threaded)
            pthread_join(th, NULL);
        ge = job.ret, fe = job.img, te = job.t;
        if (ge != 1 || ga != 1)
            break;
        if (sp_signal_seen()) {
            record_error(r, "interrupted at frame %d", r->frames);
            ret = SP_E_INTERRUPTED;
            goto done;
        }
        if (fe.width != fa.width || fe.height != fa.height) {
            ret = record_error(r, "frame %d: expected %dx%d, actual %dx%d", r->frames,
                               fe.width, fe.height, fa.width, fa.height);
            goto done;
        }
        if (r->frames == 0)
            te0 = te, ta0 = ta;
        else if (r->frames == 1)
            r->expected_fps = 1 / (te - te0), r->actual_fps = 1 / (ta - ta0);
        int late = !(fabs(te - ta) <= FRAME_TIME_SLACK) && !(isnan(te) && isnan(ta));
        if (late && !timing_noted++)
            snprintf(r->notes[r->n_notes++], sizeof(r->notes[0]),
                     "frame %d is at %.4f s in the expected video, %.4f s in the actual one",
                     r->frames, te, ta);
        /* The reader owns fa's pixels until its next read: masks may
         * overwrite them. */
        sp_compare_apply_masks(&fe, &fa, star_masks, n_star_masks);
        sp_compare_apply_masks(&fe, &fa, masks, n_masks);
        r->masked_pixels = sp_compare_masked_pixels(fe.width, fe.height, star_masks,
                                                    n_star_masks, masks, n_masks);
        ret = sp_compare_images(&fe, &fa, &opts, &res, diff_path ? &d : NULL);
        if (ret) {
            ret = record_error(r, "comparison failed");
            goto done;
        }
        double score = r->metric == SP_COMPARE_RMS ? res.rms : (double)res.differing + res.rms * 1e-9;
        if (score > worst_score) {
            worst_score = score, r->result = res, r->worst_frame = r->frames;
            sp_image_free(&worst_diff);
            worst_diff = d;
            d = (struct sp_image){0};
        }
        sp_image_free(&d);
        if (!res.pass || late) {
            if (r->failed_frames < SP_COMPARE_MAX_FRAMES_LISTED)
                r->listed[r->failed_frames] = r->frames;
            r->failed_frames++;
        }
        r->frames++;
    }
    if (ge < 0 || ga < 0) {
        ret = record_error(r, "cannot decode %s", ge < 0 ? expected : actual);
        goto done;
    }
    if (ge != ga) {
        if (ge == 1)
            ret = record_error(r, "%s ends after %d frames; %s has more", actual, r->frames,
                               expected);
        else
            ret = record_error(r, "%s has more than the %d frames of %s", actual, r->frames,
                               expected);
        sp_log_error("%s", r->error);
        goto done;
    }
    if (!r->frames) {
        ret = record_error(r, "no frames in %s", expected);
        goto done;
    }
    r->compared = 1;
    r->verdict = r->failed_frames ? SP_VERDICT_FAIL : SP_VERDICT_PASS;
    if (r->failed_frames && diff_path && worst_diff.pixels &&
        write_whole(diff_path, 0, fill_png, &(struct png_out){&worst_diff, diff_path}) == 0)
        snprintf(r->diff, sizeof(r->diff), "%s", diff_path);
    ret = 0;
done:
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

/* Refuses (an error in r, returning 1) a folder entry path that is a
 * symbolic link to a file outside folder dir: a *.png in a pull request
 * could otherwise point at a secret that --report embeds, or at a file
 * --update would replace. 0 for anything else, links within dir too. */
static int link_out(struct sp_compare_record *r, const char *name, const char *path,
                    const char *dir)
{
    struct stat st;
    char *to, *in;
    if (lstat(path, &st) != 0 || !S_ISLNK(st.st_mode))
        return 0;
    to = realpath(path, NULL);
    in = realpath(dir, NULL);
    size_t n = in ? strlen(in) : 0;
    int out = !to || !in || strncmp(to, in, n) || to[n] != '/';
    if (out) {
        char target[PATH_MAX];
        ssize_t len = readlink(path, target, sizeof(target) - 1);
        target[len > 0 ? len : 0] = 0;
        snprintf(r->name, sizeof(r->name), "%s", name);
        record_error(r, "%s is a link to %s, outside %s: not read", path,
                     to ? to : target, dir);
        snprintf(r->hint, sizeof(r->hint), "put the image itself in %s, or link within it",
                 dir);
    }
    free(to);
    free(in);
    return out;
}

/* The command that adds missing baselines, for messages. */
static void add_hint(struct sp_compare_record *r, const char *e, const char *a)
{
    snprintf(r->hint, sizeof(r->hint),
             "to add it as the baseline: springpend compare %s %s --update=missing", e, a);
}

/* Compares every PNG of folder dir_e with its namesake in dir_a; a PNG in
 * only one of them is an error (a missing render or a missing baseline). */
static int compare_folders(struct compare_cli *c, struct sp_compare_report *rep,
                           const char *dir_e, const char *dir_a)
{
    struct dirent **le = NULL, **la = NULL;
    int ne = scandir(dir_e, &le, is_png_name, alphasort);
    int ret = 0;
    if (ne < 0 && errno == ENOENT) /* no baselines yet: all are missing */
        ne = 0;
    int na = ne < 0 ? -1 : scandir(dir_a, &la, is_png_name, alphasort);
    if (ne < 0 || na < 0) {
        sp_log_error("cannot list %s: %s", ne < 0 ? dir_e : dir_a, strerror(errno));
        ret = SP_E_INPUT;
        goto done;
    }
    /* Both lists are sorted: walk them like a merge. */
    for (int i = 0, j = 0; i < ne || j < na;) {
        int cmp = i >= ne ? 1 : j >= na ? -1 : strcmp(le[i]->d_name, la[j]->d_name);
        const char *name = cmp <= 0 ? le[i]->d_name : la[j]->d_name;
        char pe[PATH_MAX], pa[PATH_MAX], pd[PATH_MAX];
        struct sp_compare_record *r;
        int refused = 0; /* a link out of the folders: nothing is updated */
        if (!(r = sp_compare_report_add(rep))) {
            ret = SP_E_NOMEM;
            goto done;
        }
        snprintf(pe, sizeof(pe), "%s/%s", dir_e, name);
        snprintf(pa, sizeof(pa), "%s/%s", dir_a, name);
        if (sp_signal_seen()) {
            /* Every image left is listed as never compared: a report of
             * an interrupted run must not read as a pass. */
            rep->interrupted = sp_signal_seen();
            ret = SP_E_INTERRUPTED;
            snprintf(r->name, sizeof(r->name), "%s", name);
            record_error(r, "not compared: the run was interrupted by %s first",
                         sp_signal_name(rep->interrupted));
            r->not_compared = 1;
        } else if (link_out(r, name, pe, dir_e) || link_out(r, name, pa, dir_a)) {
            refused = 1; /* recorded as an error */
        } else if (cmp) {
            snprintf(r->name, sizeof(r->name), "%s", name);
            snprintf(cmp < 0 ? r->expected : r->actual, sizeof(r->actual), "%s",
                     cmp < 0 ? pe : pa);
            record_error(r, cmp < 0 ? "no actual image in %s" : "no baseline in %s",
                         cmp < 0 ? dir_a : dir_e);
            if (cmp > 0)
                add_hint(r, dir_e, dir_a);
        } else {
            if (c->diff)
                snprintf(pd, sizeof(pd), "%s/%.*s.diff.png", c->diff, (int)strlen(name) - 4, name);
            compare_files(c, r, name, pe, pa, c->diff ? pd : NULL);
        }
        if (!r->not_compared && !refused) {
            if (c->update != UPDATE_NONE && cmp > 0 && mkdir(dir_e, 0777) != 0 &&
                errno != EEXIST)
                sp_log_error("cannot create the baseline folder %s: %s", dir_e,
                             strerror(errno));
            apply_update(c, r, pe);
        }
        i += cmp <= 0;
        j += cmp >= 0;
    }
    if (ne + na == 0) {
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

/* A report and the file it goes to, for messages. */
struct report_out {
    const struct sp_compare_report *rep;
    const char *path;
};

/* Every write of a report is checked: the first that fails (a full disk,
 * a file size limit) stops it, with a message; write_whole removes the
 * .part. */
static int report_failed(const struct report_out *o, int err)
{
    if (err)
        sp_log_error("%s: cannot write the report: %s", o->path,
                     errno ? strerror(errno) : "write error");
    return err;
}

static int fill_html(FILE *fp, void *out)
{
    const struct report_out *o = out;
    errno = 0;
    return report_failed(o, sp_compare_report_html(fp, o->rep));
}

static int fill_junit(FILE *fp, void *out)
{
    const struct report_out *o = out;
    errno = 0;
    sp_compare_report_junit(fp, o->rep);
    return report_failed(o, fflush(fp) || ferror(fp) ? SP_E_IO : 0);
}

/* 1 when writing path would put a file where folder mode reads one: a
 * *.png name or compare.ini in folder dir (links resolved). */
static int lands_in(const char *path, const char *dir)
{
    char buf[PATH_MAX], *real = realpath(path, NULL), parent[PATH_MAX];
    const char *name;
    int in;
    if (real) { /* an existing file, or the file a link points at */
        snprintf(buf, sizeof(buf), "%s", real);
        free(real);
    } else {
        snprintf(buf, sizeof(buf), "%s", path);
    }
    name = strrchr(buf, '/') ? strrchr(buf, '/') + 1 : buf;
    snprintf(parent, sizeof(parent), "%.*s", (int)(name - buf), buf);
    if (!parent[0])
        snprintf(parent, sizeof(parent), ".");
    in = sp_cli_same_file(parent, dir);
    size_t n = strlen(name);
    return in && ((n > 4 && !strcasecmp(name + n - 4, ".png") && name[0] != '.') ||
                  !strcmp(name, SP_COMPARE_CONFIG_NAME));
}

/* Checks the output paths before anything runs. */
static int check_outputs(const struct compare_cli *c, const char *e, const char *a, int folders)
{
    const char *outs[3][2] = {{c->diff, "--diff"}, {c->html, "--report"}, {c->junit, "--junit"}};
    for (int i = 0; i < 3; i++) {
        const char *p = outs[i][0];
        if (!p)
            continue;
        if (sp_cli_same_file(p, e) || sp_cli_same_file(p, a) ||
            (folders && i > 0 && (lands_in(p, e) || lands_in(p, a)))) {
            sp_log_error("%s %s would overwrite an input; choose another path", outs[i][1], p);
            return SP_E_INPUT;
        }
        if (i == 0 && folders)
            continue;
        if (sp_cli_check_writable(p, outs[i][1]))
            return SP_E_INPUT;
    }
    return 0;
}

int sp_cmd_compare(int argc, char **argv)
{
    struct compare_cli c;
    struct sp_compare_report rep = {0};
    char dir[PATH_MAX];
    int ret = parse_args(&c, argc, argv);
    if (ret)
        return ret > 0 ? 0 : ret;
    const char *e = argv[optind], *a = argv[optind + 1];
    struct stat st;
    int da = is_dir(a), de = is_dir(e) || (da && stat(e, &st) != 0 && errno == ENOENT);
    if (de != da) {
        sp_log_error("%s is a folder but %s is not; compare two images or two folders",
                     de ? e : a, de ? a : e);
        return SP_E_INPUT;
    }
    if ((ret = check_outputs(&c, e, a, de)) != 0)
        return ret;
    if (!de && is_png_path(e) != is_png_path(a)) {
        sp_log_error("%s and %s: compare two PNG images or two videos", e, a);
        return SP_E_INPUT;
    }
    snprintf(dir, sizeof(dir), "%s", e);
    if ((ret = sp_compare_config_load(&c.cfg, de ? e : dirname(dir))) != 0)
        return ret;
    if (de) {
        if (c.diff && !is_dir(c.diff) && mkdir(c.diff, 0777) != 0) {
            sp_log_error("--diff %s: cannot create the folder for the diff images: %s",
                         c.diff, strerror(errno));
            ret = SP_E_INPUT;
            goto done;
        }
        c.diff_links = SP_OUTFILE_REPLACE_LINK;
        ret = compare_folders(&c, &rep, e, a);
    } else {
        struct sp_compare_record *r = sp_compare_report_add(&rep);
        if (!r) {
            ret = SP_E_NOMEM;
            goto done;
        }
        if (stat(e, &st) != 0 && errno == ENOENT && stat(a, &st) == 0) {
            snprintf(r->name, sizeof(r->name), "%s", a);
            snprintf(r->actual, sizeof(r->actual), "%s", a);
            record_error(r, "no baseline %s", e);
            add_hint(r, e, a);
        } else if (is_png_path(e)) {
            compare_files(&c, r, a, e, a, c.diff);
        } else {
            ret = compare_videos(&c, r, e, a, c.diff);
            rep.interrupted = ret == SP_E_INTERRUPTED ? sp_signal_seen() : 0;
        }
        apply_update(&c, r, e);
    }
    if (!rep.interrupted)
        sp_compare_config_warn_unused(&c.cfg);
    if (c.json)
        sp_compare_report_json(stdout, &rep);
    else
        sp_compare_report_text(stdout, &rep, c.quiet, de);
    if ((c.html && write_whole(c.html, 0, fill_html, &(struct report_out){&rep, c.html})) ||
        (c.junit && write_whole(c.junit, 0, fill_junit, &(struct report_out){&rep, c.junit})))
        ret = ret ? ret : SP_E_IO;
    if (!ret) {
        struct sp_compare_counts n = sp_compare_report_count(&rep);
        ret = n.errors ? SP_E_INPUT : n.failed ? SP_E_MISMATCH : 0;
    }
done:
    if (fflush(stdout) != 0 || ferror(stdout)) {
        sp_log_error("cannot write the results to stdout: %s", strerror(errno));
        if (!ret || ret == SP_E_MISMATCH)
            ret = SP_E_IO;
    }
    sp_compare_config_free(&c.cfg);
    sp_compare_report_free(&rep);
    return ret;
}
