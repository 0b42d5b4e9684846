/* springpend: the compare command: parses argv into a compare run's desc
 * (compare_run.h) and runs it. Exit 0 match, 1 differ, 2 unreadable or
 * missing, 128 + signal. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/compare_config.h"
#include "springpend/compare_run.h"
#include "base/cpu_count.h"
#include "base/decimal.h"

static const char compare_usage[] =
    "usage: springpend compare EXPECTED ACTUAL [options]\n"
    "       springpend compare --approve CANDIDATES BASELINES [--env KEY]\n"
    "\n"
    "Compares two PNG images, or every PNG and video (.mp4 .webm .mkv .mov .gif)\n"
    "under folder EXPECTED, subfolders too, with the file of the same path under\n"
    "folder ACTUAL, or two videos (any name not ending in .png: MP4 and whatever\n"
    "FFmpeg reads) frame by frame, frame times included, in RGBA: a WebM's\n"
    "alpha too (a file with two video streams is refused).\n"
    "A baseline NAME.png may have alternatives NAME.KEY.png beside it (one per\n"
    "environment: a.llvm19.png) for each KEY that compare.ini declares at its\n"
    "top ('envs = llvm19, arm64'); a match with any one passes. Other dotted\n"
    "names (fig.1.png) are images of their own.\n"
    "Exit status: 0 all match, 1 some differ (in pixels, size or timing) or\n"
    "ran out of memory, 2 unreadable, missing or extra images, or videos with\n"
    "different frame counts; 128 + signal when interrupted.\n"
    "\n"
    "Identical decoded pixels (equal SHA-256) match at once. Otherwise the\n"
    "default rule (reftest style): a pixel differs when a channel moves by more\n"
    "than --max-diff levels of 255; the images match when at most --max-pixels\n"
    "pixels differ. SSIM is printed beside the counts; it never decides.\n"
    "A compare.ini beside the baselines sets tolerances and masks per image;\n"
    "options given here are limits it cannot loosen: their own rule, built\n"
    "from them and the defaults alone, is checked too (both must pass), and\n"
    "compare.ini's masks may then hide at most half an image (else an error).\n"
    "\n"
    "options:\n"
    "  --max-diff N           levels a channel may move unnoticed (default 3)\n"
    "  --max-pixels N|P%      differing pixels allowed, a count or a percentage\n"
    "                         of the image (default 0.1%)\n"
    "  --metric rms --tol X   pytest-mpl's rule instead: pass when the RMS of the\n"
    "                         RGB differences is <= X levels (default 2)\n"
    "  --metric pixelmatch --threshold T  mapbox/pixelmatch's perceptual rule: a\n"
    "                         pixel differs when its YIQ colour distance exceeds\n"
    "                         35215 T^2 (T from 0 to 1, default 0.1) and it is not\n"
    "                         anti-aliasing; --max-pixels then applies\n"
    "                         (an option no rule in force reads is refused)\n"
    "  --diff PATH            on a mismatch, write a diff image to PATH: the\n"
    "                         expected image in grey, differing pixels magenta,\n"
    "                         smaller changes blue; both side by side when the\n"
    "                         sizes differ. Folders: PATH is a folder (made if\n"
    "                         missing) for NAME.diff.png files; videos: the diff\n"
    "                         of the worst frame\n"
    "  --update=MODE          copy ACTUAL over EXPECTED: missing (new images),\n"
    "                         changed (and failing ones), all (and every image\n"
    "                         whose pixels differ; deletes baselines that have no\n"
    "                         actual image, listing them). A baseline whose pixels\n"
    "                         are unchanged is never rewritten\n"
    "  --env KEY              --update and --candidates write NAME.KEY.png, an\n"
    "                         alternative baseline, instead of NAME.png (only\n"
    "                         beside a NAME.png baseline); KEY must be declared\n"
    "                         in compare.ini's envs line\n"
    "  --candidates DIR       write the would-be baselines (failing and new images\n"
    "                         only) and their diffs to DIR, new or empty; the\n"
    "                         run still fails\n"
    "  --approve DIR BASELINES  copy what --candidates wrote into the baselines\n"
    "                         (not the diffs; unchanged pixels left untouched);\n"
    "                         a candidate named like an alternative NAME.KEY.png\n"
    "                         only with --env KEY and beside its NAME.png; no\n"
    "                         other option goes with it\n"
    "  --report FILE.html     one self-contained HTML page: expected, actual and\n"
    "                         diff side by side at full size with zoom, masks\n"
    "                         drawn, a flip control, failures first\n"
    "  --report-failures-only the HTML page (--report) without the passing images\n"
    "  --summary FILE.md      a Markdown summary for a pull request or\n"
    "                         $GITHUB_STEP_SUMMARY: counts and a table of failures\n"
    "  --jobs N               compare a folder's images on N threads (default:\n"
    "                         every CPU the process may use; fewer when 12 bytes\n"
    "                         a pixel of the largest PNG, or 24 of the largest\n"
    "                         video frame, and each thread's stack and malloc\n"
    "                         arena would pass half the memory it may use)\n"
    "  --junit FILE.xml       JUnit XML, a test case per image\n"
    "  --json                 print the records as JSON (schema in ci.md, in the\n"
    "                         guides' folder 'springpend --help' names)\n"
    "  -q, --quiet            print failures only (no effect with --json)\n"
    "  -h, --help             this text\n";

/* The command line: a run's desc, and whether it asks for --approve. */
struct compare_options {
    struct sp_compare_desc run;
    int approve; /* --approve DIR BASELINES */
};

/* --approve copies candidates and nothing else: an option it does not use
 * (a report, --jobs, a rule...) is refused (--env KEY it takes: it lets
 * an alternative NAME.KEY.png be copied), all of them named, with
 * 1 (logged); 0 when none was given. seen: the options given, by letter. */
static int refuse_with_approve(const unsigned char seen[128], const struct option *opts)
{
    char names[512] = "";
    int n = 0;
    for (const struct option *p = opts; p->name; p++)
        if (p->val > 0 && p->val < 128 && seen[p->val] && p->val != 'A' && p->val != 'h' &&
            p->val != 'E') {
            snprintf(names + strlen(names), sizeof(names) - strlen(names), "%s--%s",
                     n++ ? ", " : "", p->name);
        }
    if (!n)
        return 0;
    sp_log_error("--approve copies reviewed candidates into the baselines and uses no other "
                 "option but --env KEY: %s given; compare first (with --candidates), then run "
                 "--approve CANDIDATES BASELINES alone (with --env KEY for the alternatives "
                 "NAME.KEY.png that --candidates --env KEY wrote)", names);
    return 1;
}

/* Parses argv into *o. 0, 1 after --help, or SP_E_INPUT after a message. */
static int parse_args(struct compare_options *o, int argc, char **argv)
{
    static const struct option longopts[] = {
        {"max-diff", required_argument, 0, 'd'}, {"max-pixels", required_argument, 0, 'p'},
        {"metric", required_argument, 0, 'm'},   {"tol", required_argument, 0, 't'},
        {"threshold", required_argument, 0, 'T'},
        {"diff", required_argument, 0, 'D'},     {"json", no_argument, 0, 'j'},
        {"update", required_argument, 0, 'u'},   {"report", required_argument, 0, 'R'},
        {"junit", required_argument, 0, 'J'},    {"quiet", no_argument, 0, 'q'},
        {"summary", required_argument, 0, 'S'},  {"env", required_argument, 0, 'E'},
        {"candidates", required_argument, 0, 'C'}, {"jobs", required_argument, 0, 'N'},
        {"approve", no_argument, 0, 'A'},
        {"report-failures-only", no_argument, 0, 'F'},
        {"help", no_argument, 0, 'h'},           {0, 0, 0, 0},
    };
    int ch, idx;
    char why[1024];
    const char *first[128] = {0};
    unsigned char seen[128] = {0}; /* the options given, by their letter */
    struct sp_compare_desc *c = &o->run;
    memset(o, 0, sizeof(*o));
    c->jobs = sp_cpu_count(); /* those this process may use */
    optind = 1;
    opterr = 0;
    while ((ch = getopt_long(argc, argv, ":qh", longopts, &idx)) != -1) {
        if (sp_cli_once(ch, longopts, "", first))
            return SP_E_INPUT;
        if (ch > 0 && ch < 128)
            seen[ch] = 1;
        switch (ch) {
        case 'd': case 'p': case 'm': case 't': case 'T':
            if (sp_compare_rule_set(&c->base, longopts[idx].name, optarg, why, sizeof(why))) {
                sp_log_error("--%s", why);
                return SP_E_INPUT;
            }
            break;
        case 'u':
            c->update = !strcmp(optarg, "missing") ? SP_COMPARE_UPDATE_MISSING
                        : !strcmp(optarg, "changed") ? SP_COMPARE_UPDATE_CHANGED
                        : !strcmp(optarg, "all")     ? SP_COMPARE_UPDATE_ALL
                                                     : SP_COMPARE_UPDATE_NONE;
            if (c->update == SP_COMPARE_UPDATE_NONE && strcmp(optarg, "none")) {
                sp_log_error("--update=%s: expected missing, changed, all or none", optarg);
                return SP_E_INPUT;
            }
            break;
        case 'D': c->diff = optarg; break;
        case 'S': c->summary = optarg; break;
        case 'C': c->candidates = optarg; break;
        case 'A': o->approve = 1; break;
        case 'F': c->failures_only = 1; break;
        case 'E':
            if (sp_compare_env_key_check(optarg)) {
                sp_log_error("--env %s: %s; it names the baseline NAME.KEY.png", optarg,
                             sp_compare_env_key_check(optarg));
                return SP_E_INPUT;
            }
            c->env = optarg;
            break;
        case 'N': {
            double v;
            const char *bad = sp_decimal_in(optarg, 1, 256, SP_DECIMAL_INTEGER, &v);
            if (bad) {
                sp_log_error("--jobs %s: %s; expected an integer from 1 to 256", optarg, bad);
                return SP_E_INPUT;
            }
            c->jobs = (int)v;
            break;
        }
        case 'R': c->html = optarg; break;
        case 'J': c->junit = optarg; break;
        case 'j': c->json = 1; break;
        case 'q': c->quiet = 1; break;
        case 'h': fputs(compare_usage, stdout); return 1;
        case ':':
            sp_log_error("%s needs a value; see 'springpend compare --help'", argv[optind - 1]);
            return SP_E_INPUT;
        default:
            sp_cli_bad_option(argv[optind - 1], longopts, "compare");
            return SP_E_INPUT;
        }
    }
    if (o->approve && refuse_with_approve(seen, longopts))
        return SP_E_INPUT;
    if (c->failures_only && !c->html) { /* attack13 #16: it would change nothing */
        sp_log_error("--report-failures-only shapes the HTML page: it needs --report "
                     "FILE.html; give both, or leave it out");
        return SP_E_INPUT;
    }
    if (argc - optind != 2) {
        sp_log_error("expected two images or folders, EXPECTED and ACTUAL; see "
                     "'springpend compare --help'");
        return SP_E_INPUT;
    }
    c->expected = argv[optind];
    c->actual = argv[optind + 1];
    return 0;
}

int sp_cmd_compare(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    struct compare_options o;
    int ret = parse_args(&o, argc, argv);
    if (ret)
        return ret > 0 ? 0 : ret;
    o.run.cancel = cancel;
    return o.approve ? sp_compare_approve(&o.run) : sp_compare_run(&o.run);
}

