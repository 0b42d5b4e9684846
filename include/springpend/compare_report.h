/* springpend: what `springpend compare` found, as records, and the
 * reporters that print them: text lines, JSON, JUnit XML and an HTML
 * page. Comparing fills records; reporters only read them. */
#ifndef SPRINGPEND_COMPARE_REPORT_H
#define SPRINGPEND_COMPARE_REPORT_H

#include <stdio.h>

#include "springpend/image_compare.h"

enum sp_verdict {
    SP_VERDICT_PASS = 0,  /* matches (exactly, or within tolerance) */
    SP_VERDICT_FAIL,      /* differs beyond tolerance, or in size: exit 1 */
    SP_VERDICT_ERROR,     /* cannot be compared (unreadable, missing): exit 2 */
};

/* What --update did to the baseline. */
enum sp_update_action {
    SP_UPDATE_NONE = 0,
    SP_UPDATE_ADDED,    /* copied: there was no baseline */
    SP_UPDATE_REPLACED, /* copied over a baseline that differed */
    SP_UPDATE_REMOVED,  /* baseline deleted: no actual image (--update=all) */
};

#define SP_COMPARE_MAX_CHANGES 16
#define SP_COMPARE_MAX_FRAMES_LISTED 10
#define SP_COMPARE_MAX_NOTES 4

/* The most bytes of a changed scene value a report shows: a longer one
 * is cut around the first difference, "…" where it is cut. */
#define SP_SCENE_CHANGE_SHOWN 100
#define SP_SCENE_CHANGE_SLACK 24 /* shown too where that reaches the end */

/* A scene key whose value differs between the two images' provenance
 * (the whole values compared): each value as shown, whole or cut (at most
 * SP_SCENE_CHANGE_SHOWN + SP_SCENE_CHANGE_SLACK bytes of it, at a
 * character's boundary, and the ellipses), with room for the shown form's escapes (a \u200b for 3 bytes,
 * a \U000e0001 for 4, a \\ for 1). */
struct sp_scene_change {
    char key[64];
    char expected[5 * (SP_SCENE_CHANGE_SHOWN + SP_SCENE_CHANGE_SLACK) / 2 + 16];
    char actual[5 * (SP_SCENE_CHANGE_SHOWN + SP_SCENE_CHANGE_SLACK) / 2 + 16];
    int cut; /* 1: expected or actual is cut */
    int same_text; /* 1: the two are the same text in other Unicode normal
                      forms (their NFD equal): each shown value ends with
                      its form, " (NFC)", " (NFD)" or " (neither NFC nor NFD)" */
};

/* One comparison: an image pair, or two videos. */
struct sp_compare_record {
    char name[4096];          /* the file name (folders: its path under the
                                 folder, whole: any that the walk lists, as
                                 PATH_MAX bounds FOLDER/NAME; attack17 #3)
                                 or the actual path */
    char expected[4096];      /* path, "" when there is none */
    char actual[4096];        /* path, "" when there is none */
    char diff[4096];          /* diff image written, "" when none */
    enum sp_verdict verdict;
    enum sp_update_action update;
    char error[512];          /* why it could not be compared; "" when it was */
    char hint[512];           /* what to do about it, "" when nothing */
    int not_compared;         /* 1: never looked at: the run was interrupted
                                 first (verdict ERROR, counted apart) */
    int expected_png, actual_png; /* 1: read as a PNG (its header at least):
                                     only these are embedded in --report */
    int compared;             /* 1: result below holds figures */
    int out_of_memory;        /* 1: error holds "out of memory": not the
                                 files' fault (the run exits 1, not 2) */
    int retry_alone;          /* 1: compare_run compares it again alone
                                 (a video a decoder refused on a thread
                                 among others: it may be memory) */
    int exact;                /* the decoded pixels are identical (equal hashes) */
    char expected_sha256[65]; /* of the decoded pixels, "" when not read */
    char actual_sha256[65];
    int expected_w, expected_h, actual_w, actual_h; /* px; 0 unknown */
    int size_mismatch;        /* 1: sizes differ (a failure) */
    struct sp_compare_result result; /* measured figures and the applied rule */
    enum sp_compare_metric metric;
    double ssim;              /* perceptual, not in the verdict; < 0 not computed */
    long masked_pixels;       /* pixels ignored by compare.ini masks */
    /* Videos (frames > 0): figures above are the worst frame's. */
    int frames, failed_frames, worst_frame;
    int listed[SP_COMPARE_MAX_FRAMES_LISTED]; /* first failing frames */
    double expected_fps, actual_fps; /* from the timestamps; 0 unknown */
    /* Provenance (PNG text chunks) that differs, pass or fail. */
    char notes[SP_COMPARE_MAX_NOTES][640];
    int n_notes;
    double seconds;           /* wall time the comparison took, s */
    int n_alternatives;       /* baselines per environment beside the plain one */
    char baseline_key[64];    /* the alternative that matched (NAME.KEY.png's KEY);
                                 "" the plain baseline, or none matched */
    int refused;              /* a link out of the folders, or a baseline
                                 NAME.KEY.KEY.png: never updated */
    struct sp_compare_mask masks[32]; /* compare.ini's masks (the first 32), drawn */
    int n_masks;
    char candidate[4096];     /* --candidates wrote the actual image here; "" none */
    /* --update=changed|all replaced the baseline: its bytes before (owned,
     * free with sp_compare_report_free), so reports show what was replaced. */
    unsigned char *before;
    size_t before_size;
    /* The springpend.environment text each image records (environment.h:
     * springpend, renderer, Mesa, LLVM, the libraries, the font), whole:
     * [0] the expected image's, [1] the actual's; owned (freed with
     * sp_compare_report_free), NULL when the image has none. */
    char *environment[2];
    struct sp_scene_change changes[SP_COMPARE_MAX_CHANGES];
    int n_changes, more_changes;
};

struct sp_compare_report {
    struct sp_compare_record *records; /* owned */
    int n, cap;
    int interrupted;                   /* the signal that stopped the run, 0 none */
    char problem[512];                 /* what went wrong with the run as a whole
                                          (no images at all); "" when nothing */
    const char *suite;                 /* JUnit suite name prefix: the EXPECTED
                                          folder's or file's name */
    const char *report_path;           /* the HTML report, for the summary; NULL */
    const char *junit_path;            /* the JUnit file, for the summary; NULL */
    int failures_only;                 /* HTML: rows of failures and errors only */
};

/* A new zeroed record at the end of rep (ssim -1, worst_frame -1); NULL
 * (logged) when out of memory, with rep->problem set to say so: a run
 * without its records never reports a pass. */
struct sp_compare_record *sp_compare_report_add(struct sp_compare_report *rep);
void sp_compare_report_free(struct sp_compare_report *rep);

/* Counts of rep's records. passed, failed and errors count verdicts as
 * found (before any --update); compared counts the records whose images were
 * compared (not the missing or unreadable); updated counts the baselines
 * --update added, replaced or removed; unresolved counts the failures and
 * errors --update did not resolve: the run passes when it is 0 (and the run
 * was not interrupted and has no problem). A record never compared (the run
 * was interrupted first) counts as not_compared only; one that ran out of
 * memory counts as out_of_memory, not among the errors (an unreadable or
 * missing image), but as unresolved. */
struct sp_compare_counts {
    int records, compared, passed, failed, errors, updated, not_compared, out_of_memory;
    int unresolved_failed, unresolved_errors;
};

/* 1 when the run passes: nothing unresolved, not interrupted, no problem. */
int sp_compare_report_passes(const struct sp_compare_report *rep);
struct sp_compare_counts sp_compare_report_count(const struct sp_compare_report *rep);

/* Text: one line per record (failures only when quiet), notes, hints and
 * updates beneath, then a summary line when `summary` (folders). Control
 * characters from names are shown, never sent (sp_fputs_printable). */
void sp_compare_report_text(FILE *fp, const struct sp_compare_report *rep, int quiet,
                            int summary);

/* JSON, one schema always (see doc/ci.md): {"schema": "springpend-compare/1",
 * "pass": ..., "counts": {...}, "results": [ ... ]}. */
void sp_compare_report_json(FILE *fp, const struct sp_compare_report *rep);

/* A summary in Markdown, short enough for a pull request comment or
 * $GITHUB_STEP_SUMMARY: the status and counts, a table of at most 50 failures
 * and errors with what was measured against what was allowed, and where the
 * HTML report is. */
void sp_compare_report_markdown(FILE *fp, const struct sp_compare_report *rep);

/* JUnit XML: one testsuite, a testcase per record, <failure> or <error>;
 * what XML cannot hold (C0 controls, U+FFFE, U+FFFF, stray bytes) becomes
 * U+FFFD, and "[[" in names becomes "[ [" so that only springpend's own
 * [[ATTACHMENT|diff]] lines reach GitLab and Jenkins. An interrupted run
 * adds an <error> test case naming the signal and a <skipped> one for
 * each image never compared. */
void sp_compare_report_junit(FILE *fp, const struct sp_compare_report *rep);

/* One self-contained HTML page: the images embedded as data: URLs, a row
 * per record, failures first, expected | actual | diff side by side, a
 * button (or a click on the image) flipping between expected and actual,
 * the figures and the verdict. Only regular files that start like a PNG
 * and were read as one are embedded (never FIFOs, devices or other files
 * a *.png name points at); a video is a relative link, never a URL scheme.
 * Returns 0, or SP_E_IO at the first write that fails (a full disk, a
 * file size limit). */
int sp_compare_report_html(FILE *fp, const struct sp_compare_report *rep);

/* Writes s to fp as a JSON string: quoted, with quotes, backslashes and
 * control characters escaped (every JSON printer's strings, info's too). */
void sp_report_json_string(FILE *fp, const char *s);

#endif
