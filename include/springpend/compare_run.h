/* springpend: a compare run, for snapshot tests in CI: the engine behind
 * `springpend compare`. Decodes PNGs (files or every PNG of two folders)
 * or videos frame by frame, applies image_compare's rule (exact pixels
 * first, the tolerance second), records each outcome and prints the
 * records with compare_report.h's reporters. Commands fill a desc and call
 * it; nothing here parses arguments. */
#ifndef SPRINGPEND_COMPARE_RUN_H
#define SPRINGPEND_COMPARE_RUN_H

#include <signal.h>

#include "springpend/compare_config.h"

/* --update: which baselines the actual images replace. */
enum sp_compare_update {
    SP_COMPARE_UPDATE_NONE,
    SP_COMPARE_UPDATE_MISSING, /* new images only */
    SP_COMPARE_UPDATE_CHANGED, /* and failing ones */
    SP_COMPARE_UPDATE_ALL,     /* and every image whose pixels differ; removes
                                  baselines without an actual image */
};

struct sp_compare_desc {
    const char *expected, *actual; /* two PNGs, two videos or two folders */
    struct sp_compare_rule base;   /* the command line's rule: limits that a
                                      compare.ini beside the baselines cannot
                                      loosen */
    const char *diff;              /* diff image (files) or folder, NULL = none */
    const char *html, *junit;      /* HTML page, JUnit XML, NULL = none */
    const char *summary;           /* Markdown summary, NULL = none */
    const char *env;               /* KEY: --update and candidates write
                                      NAME.KEY.png; NULL = NAME.png */
    const char *candidates;        /* folder for would-be baselines, NULL = none */
    enum sp_compare_update update;
    int json;                      /* 1: the records as JSON on stdout */
    int quiet;                     /* 1: text lines of failures only */
    int failures_only;             /* 1: the HTML page without passing images */
    int jobs;                      /* threads comparing a folder's images, >= 1 */
    const volatile sig_atomic_t *cancel; /* the caller's stop flag (the signal's
                                            number once one arrived; NULL =
                                            never): the images left are
                                            reported as not compared */
};

/* Compares d->expected with d->actual and prints the records on stdout
 * (text or JSON), writes the reports asked for, updates baselines and
 * writes candidates. Checks every path first (an output that would
 * overwrite an input, or cannot be written, is refused before anything
 * runs). Returns 0 when all match, SP_E_MISMATCH when some differ,
 * SP_E_INPUT when some are unreadable or missing (or the arguments are
 * wrong, after a message), SP_E_IO, SP_E_INTERRUPTED. */
int sp_compare_run(const struct sp_compare_desc *d);

/* compare --approve: copies what d->candidates wrote (every PNG and video
 * under it, subfolders too, but the NAME.diff.png diffs) into d->expected
 * (the baselines), each to the same relative path; a baseline whose pixels
 * equal its candidate's is left untouched. Lists each on stdout. 0,
 * SP_E_INPUT, SP_E_IO or SP_E_INTERRUPTED (d->cancel). */
int sp_compare_approve(const struct sp_compare_desc *d);

#endif
