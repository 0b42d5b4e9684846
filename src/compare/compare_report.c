/* springpend: compare's records and reporters (compare_report.h). */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/compare_report.h"
#include "springpend/infile.h"
#include "base/array.h"
#include "base/signal_name.h"
#include "base/utf8.h"
#include "frame/text.h"

struct sp_compare_record *sp_compare_report_add(struct sp_compare_report *rep)
{
    if (SP_ARRAY_RESERVE(rep->records, rep->cap, rep->n + 1, 16)) {
        /* the run's problem (a fixed text: nothing allocated), so that no
         * report of it reads as a pass (attack9 #3) */
        snprintf(rep->problem, sizeof(rep->problem), "out of memory for the comparison's "
                 "records: %d image%s listed, the rest not compared", rep->n,
                 rep->n == 1 ? "" : "s");
        sp_log_error("%s", rep->problem);
        return NULL;
    }
    struct sp_compare_record *r = &rep->records[rep->n++];
    memset(r, 0, sizeof(*r));
    r->ssim = -1;
    r->worst_frame = -1;
    return r;
}

void sp_compare_report_free(struct sp_compare_report *rep)
{
    for (int i = 0; i < rep->n; i++) {
        free(rep->records[i].before);
        free(rep->records[i].environment[0]);
        free(rep->records[i].environment[1]);
    }
    free(rep->records);
    memset(rep, 0, sizeof(*rep));
}

struct sp_compare_counts sp_compare_report_count(const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = {0};
    for (int i = 0; i < rep->n; i++) {
        const struct sp_compare_record *r = &rep->records[i];
        int resolved = r->update != SP_UPDATE_NONE;
        c.records++;
        if (r->not_compared) {
            c.not_compared++;
            continue;
        }
        c.compared += r->compared;
        c.passed += r->verdict == SP_VERDICT_PASS;
        c.failed += r->verdict == SP_VERDICT_FAIL;
        c.errors += r->verdict == SP_VERDICT_ERROR && !r->out_of_memory;
        c.out_of_memory += r->out_of_memory;
        c.updated += resolved;
        c.unresolved_failed += r->verdict == SP_VERDICT_FAIL && !resolved;
        c.unresolved_errors += r->verdict == SP_VERDICT_ERROR && !resolved;
    }
    return c;
}

int sp_compare_report_passes(const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = sp_compare_report_count(rep);
    return !c.unresolved_failed && !c.unresolved_errors && !rep->interrupted &&
           !rep->problem[0];
}

/* The run's one-word status: ok, UPDATED (passes after --update changed
 * baselines), INTERRUPTED or FAIL. */
static const char *status_word(const struct sp_compare_report *rep)
{
    return rep->interrupted ? "INTERRUPTED" : !sp_compare_report_passes(rep) ? "FAIL"
           : sp_compare_report_count(rep).updated ? "UPDATED" : "ok";
}

/* The summary line's figures (no newline). */
static void summary_line(FILE *fp, const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = sp_compare_report_count(rep);
    fprintf(fp, "%s: %d compared, %d passed, %d failed, %d missing or unreadable, "
            "%d updated", status_word(rep), c.compared, c.passed, c.failed, c.errors,
            c.updated);
    if (c.out_of_memory)
        fprintf(fp, ", %d out of memory", c.out_of_memory);
    if (rep->problem[0])
        fprintf(fp, "; %s", rep->problem);
}

static const char *update_word(enum sp_update_action u)
{
    return u == SP_UPDATE_ADDED ? "added" : u == SP_UPDATE_REPLACED ? "replaced"
           : u == SP_UPDATE_REMOVED ? "removed" : NULL;
}

static const char *verdict_word(enum sp_verdict v)
{
    return v == SP_VERDICT_PASS ? "pass" : v == SP_VERDICT_FAIL ? "fail" : "error";
}

static const char *const rule_names[3] = {
    [SP_COMPARE_REFTEST] = "reftest", [SP_COMPARE_RMS] = "rms",
    [SP_COMPARE_PIXELMATCH] = "pixelmatch"};

/* The command line's own rules checked besides the metric's (x->also):
 * each one's figures, and which decided when one failed the image. */
static void text_also(FILE *fp, const struct sp_compare_result *x)
{
    for (int k = 0; k < 3; k++) {
        if (!(x->also & (1u << k)))
            continue;
        fprintf(fp, "; and the command line's %s rule (its limits and the defaults, not "
                "compare.ini's): ", rule_names[k]);
        if (k == SP_COMPARE_REFTEST)
            fprintf(fp, "%ld pixels differ by more than %d levels (%ld allowed)",
                    x->also_reftest, x->also_max_diff, x->also_allowed);
        else if (k == SP_COMPARE_RMS)
            fprintf(fp, "rms %.3f %s tol %g", x->rms, x->rms <= x->also_tol ? "<=" : ">",
                    x->also_tol);
        else
            fprintf(fp, "%ld pixels differ (pixelmatch, threshold %g) (%ld allowed)",
                    x->also_pixelmatch, x->also_threshold, x->also_allowed);
        fputs(x->decided_by == k ? ", which decided: fail" : ", passed", fp);
    }
}

/* The figures of a compared record, as the rest of a line. */
static void text_figures(FILE *fp, const struct sp_compare_record *r)
{
    const struct sp_compare_result *x = &r->result;
    if (r->size_mismatch) {
        fprintf(fp, "expected %dx%d, actual %dx%d; images of different sizes never match",
                r->expected_w, r->expected_h, r->actual_w, r->actual_h);
    } else if (r->exact) {
        fprintf(fp, "identical pixels (%ld, sha256 %.12s)", x->pixels, r->actual_sha256);
    } else if (r->metric == SP_COMPARE_BLOCKS) {
        fprintf(fp, "%ld of %ld blocks of %dx%d px differ by more than %d levels in their "
                "mean (%ld allowed); largest difference %d; rms %.3f", x->differing, x->pixels,
                SP_COMPARE_VIDEO_BLOCK, SP_COMPARE_VIDEO_BLOCK, x->max_diff, x->allowed,
                x->max_channel_diff, x->rms);
    } else if (r->metric == SP_COMPARE_PIXELMATCH) {
        fprintf(fp, "%ld of %ld pixels differ (pixelmatch, threshold %g; %ld anti-aliased "
                "pixels not counted) (%ld allowed); largest difference %d; rms %.3f",
                x->differing, x->pixels, x->threshold, x->antialiased, x->allowed,
                x->max_channel_diff, x->rms);
    } else {
        fprintf(fp, "%ld of %ld pixels differ by more than %d levels (%ld allowed); "
                "largest difference %d; rms %.3f",
                x->differing, x->pixels, x->max_diff, x->allowed, x->max_channel_diff, x->rms);
        if (r->metric == SP_COMPARE_RMS)
            fprintf(fp, " %s tol %g", x->rms <= x->tol ? "<=" : ">", x->tol);
        if (r->ssim >= 0)
            fprintf(fp, "; ssim %.4f", r->ssim);
        if (x->differing)
            fprintf(fp, "; in x %d..%d, y %d..%d", x->bbox[0], x->bbox[2], x->bbox[1],
                    x->bbox[3]);
    }
    if (x->also && !r->size_mismatch && !r->exact && r->metric != SP_COMPARE_BLOCKS)
        text_also(fp, x);
    if (r->masked_pixels)
        fprintf(fp, "; %ld pixels masked", r->masked_pixels);
    if (r->baseline_key[0])
        fprintf(fp, "; matched the alternative baseline for %s", r->baseline_key);
    if (r->diff[0])
        fprintf(fp, "; diff: %s", r->diff);
}

/* src into dst (size bytes, cut there) as one printable line: newlines
 * as \n, what sp_fputs_printable shows as \xHH likewise, so that no name
 * can start a line of its own ("ok  everything.png"). */
static void field_line(char *dst, size_t size, const char *src)
{
    char seg[4096];
    FILE *m;
    dst[0] = 0;
    if (!(m = fmemopen(dst, size, "w")))
        return;
    for (const char *p = src; *p;) {
        size_t n = strcspn(p, "\n");
        snprintf(seg, sizeof(seg), "%.*s", (int)n, p);
        sp_fputs_printable(seg, m);
        if (!p[n])
            break;
        fputs("\\n", m);
        p += n + 1;
    }
    fclose(m);
    dst[size - 1] = 0;
}

/* r with every text field a printable line (field_line). */
static void printable_record(struct sp_compare_record *r)
{
    char *fields[] = {r->name, r->expected, r->actual, r->diff, r->error, r->hint};
    size_t sizes[] = {sizeof(r->name), sizeof(r->expected), sizeof(r->actual),
                      sizeof(r->diff), sizeof(r->error), sizeof(r->hint)};
    char buf[4096];
    for (size_t i = 0; i < sizeof(fields) / sizeof(fields[0]); i++) {
        field_line(buf, sizes[i], fields[i]); /* every size is at most sizeof(buf) */
        memcpy(fields[i], buf, sizes[i]);
    }
    for (int k = 0; k < r->n_notes; k++) {
        field_line(buf, sizeof(r->notes[k]), r->notes[k]);
        memcpy(r->notes[k], buf, sizeof(r->notes[k]));
    }
    for (int k = 0; k < r->n_changes; k++) {
        struct sp_scene_change *c = &r->changes[k];
        field_line(buf, sizeof(c->key), c->key);
        memcpy(c->key, buf, sizeof(c->key));
        field_line(buf, sizeof(c->expected), c->expected);
        memcpy(c->expected, buf, sizeof(c->expected));
        field_line(buf, sizeof(c->actual), c->actual);
        memcpy(c->actual, buf, sizeof(c->actual));
    }
}

static void text_lines(FILE *fp, const struct sp_compare_report *rep, int quiet, int summary)
{
    char last_hint[sizeof(rep->records[0].hint)] = "";
    struct sp_compare_record *r = malloc(sizeof(*r));
    if (!r) {
        sp_log_error("out of memory for the comparison's text");
        return;
    }
    for (int i = 0; i < rep->n; i++) {
        *r = rep->records[i];
        printable_record(r);
        const char *u = update_word(r->update);
        if (r->not_compared) {
            fprintf(fp, "NOT COMPARED %s: %s\n", r->name, r->error);
            continue;
        } else if (r->verdict == SP_VERDICT_ERROR && (r->update == SP_UPDATE_ADDED ||
                                               r->update == SP_UPDATE_REMOVED)) {
            fprintf(fp, "%-8s %s\n", u, r->expected); /* what was missing is resolved */
            continue;
        } else if (r->verdict == SP_VERDICT_ERROR) {
            fprintf(fp, "ERROR %s: %s\n", r->name, r->error);
        } else if (r->frames > 0) {
            if (quiet && r->verdict == SP_VERDICT_PASS && !u)
                continue;
            fprintf(fp, "%s %s: %d of %d frames differ", r->verdict ? "FAIL" : "ok  ", r->name,
                    r->failed_frames, r->frames);
            for (int k = 0; k < r->failed_frames && k < SP_COMPARE_MAX_FRAMES_LISTED; k++)
                fprintf(fp, "%s%d", k ? ", " : " (frames ", r->listed[k]);
            if (r->failed_frames)
                fprintf(fp, "%s)", r->failed_frames > SP_COMPARE_MAX_FRAMES_LISTED ? ", ..." : "");
            fprintf(fp, "; worst frame %d: ", r->worst_frame);
            text_figures(fp, r);
            fputc('\n', fp);
        } else if (r->compared) {
            if (quiet && r->verdict == SP_VERDICT_PASS && !u)
                continue;
            fprintf(fp, "%s %s: ", r->verdict ? "FAIL" : "ok  ", r->name);
            text_figures(fp, r);
            fputc('\n', fp);
        }
        for (int k = 0; k < r->n_notes; k++)
            fprintf(fp, "     note: %s\n", r->notes[k]);
        for (int k = 0; k < r->n_changes; k++)
            fprintf(fp, "     scene: %s = %s (expected) vs %s (actual)\n", r->changes[k].key,
                    r->changes[k].expected, r->changes[k].actual);
        if (r->more_changes)
            fprintf(fp, "     scene: and %d more keys\n", r->more_changes);
        /* A hint beneath its image, but not again when the one before said
         * the same (the --update hint, for every missing image). */
        if (r->hint[0] && strcmp(last_hint, r->hint))
            fprintf(fp, "     %s\n", r->hint);
        if (r->hint[0])
            memcpy(last_hint, r->hint, sizeof(last_hint));
        if (u)
            fprintf(fp, "%-8s %s\n", u, r->expected);
    }
    free(r);
    if (summary || rep->problem[0])
        summary_line(fp, rep), fputc('\n', fp);
    if (rep->interrupted) {
        struct sp_compare_counts c = sp_compare_report_count(rep);
        fprintf(fp, "interrupted by %s after %d images; %d not compared\n",
                sp_signal_name(rep->interrupted), c.records - c.not_compared, c.not_compared);
    }
}

void sp_compare_report_text(FILE *fp, const struct sp_compare_report *rep, int quiet,
                            int summary)
{
    /* Names, paths and PNG text reach a terminal: each field is one
     * printable line (text_lines), and the whole is shown printable. */
    char *buf = NULL;
    size_t size = 0;
    FILE *m = open_memstream(&buf, &size);
    if (!m) {
        sp_log_error("out of memory for the comparison's text");
        return;
    }
    text_lines(m, rep, quiet, summary);
    if (fclose(m) == 0)
        sp_fputs_record(buf, 1, fp); /* its names shown already (printable_record) */
    else
        sp_log_error("out of memory for the comparison's text");
    free(buf);
}

void sp_report_json_string(FILE *fp, const char *s)
{
    fputc('"', fp);
    for (size_t n; *s; s += n ? n : 1) {
        unsigned char ch = (unsigned char)*s;
        n = sp_utf8_char(s); /* JSON is UTF-8: a file name's stray byte is U+FFFD */
        if (!n)
            fputs("\\ufffd", fp);
        else if (ch == '"' || ch == '\\')
            fprintf(fp, "\\%c", ch);
        else if (ch < 0x20 || ch == 0x7f)
            fprintf(fp, "\\u%04x", ch);
        else if (n == 2 && ch == 0xC2 && (unsigned char)s[1] < 0xA0) /* C1: a terminal's */
            fprintf(fp, "\\u%04x", (unsigned char)s[1]);
        else
            fwrite(s, 1, n, fp);
    }
    fputc('"', fp);
}

/* x as a JSON number (printf's fmt), or null where JSON has no number:
 * NaN and the infinities (a video without timestamps has no rate). */
static void json_number(FILE *fp, const char *fmt, double x)
{
    if (isfinite(x))
        fprintf(fp, fmt, x);
    else
        fputs("null", fp);
}

/* s as a JSON string, or null when empty. */
static void json_maybe(FILE *fp, const char *s)
{
    if (s[0])
        sp_report_json_string(fp, s);
    else
        fputs("null", fp);
}

static void json_size(FILE *fp, int w, int h)
{
    if (w > 0)
        fprintf(fp, "[%d, %d]", w, h);
    else
        fputs("null", fp);
}

/* The command line's own rules checked besides the metric's (x->also), in
 * the tolerance object: each one's limits, figure and outcome. */
static void json_also(FILE *fp, const struct sp_compare_result *x)
{
    fputs(", \"command_line_rules\": [", fp);
    for (int k = 0, n = 0; k < 3; k++) {
        if (!(x->also & (1u << k)))
            continue;
        const long count = k == SP_COMPARE_PIXELMATCH ? x->also_pixelmatch : x->also_reftest;
        const int pass = k == SP_COMPARE_RMS ? x->rms <= x->also_tol : count <= x->also_allowed;
        fprintf(fp, "%s{\"metric\": \"%s\", ", n++ ? ", " : "", rule_names[k]);
        if (k == SP_COMPARE_RMS) {
            fputs("\"max_rms\": ", fp);
            json_number(fp, "%g", x->also_tol);
        } else {
            if (k == SP_COMPARE_REFTEST)
                fprintf(fp, "\"max_channel_diff\": %d", x->also_max_diff);
            else
                fputs("\"threshold\": ", fp), json_number(fp, "%g", x->also_threshold);
            fprintf(fp, ", \"max_differing_pixels\": %ld, \"differing_pixels\": %ld",
                    x->also_allowed, count);
        }
        fprintf(fp, ", \"pass\": %s}", pass ? "true" : "false");
    }
    fputs("]", fp);
}

static void json_record(FILE *fp, const struct sp_compare_record *r)
{
    const struct sp_compare_result *x = &r->result;
    fputs("    {\"name\": ", fp), sp_report_json_string(fp, r->name);
    fputs(", \"expected\": ", fp), json_maybe(fp, r->expected);
    fputs(", \"actual\": ", fp), json_maybe(fp, r->actual);
    fprintf(fp, ", \"verdict\": \"%s\", \"pass\": %s, \"not_compared\": %s, "
            "\"out_of_memory\": %s", verdict_word(r->verdict),
            r->verdict == SP_VERDICT_PASS ? "true" : "false",
            r->not_compared ? "true" : "false", r->out_of_memory ? "true" : "false");
    fputs(", \"error\": ", fp), json_maybe(fp, r->error);
    fputs(", \"hint\": ", fp), json_maybe(fp, r->hint);
    fprintf(fp, ", \"update\": ");
    if (update_word(r->update))
        sp_report_json_string(fp, update_word(r->update));
    else
        fputs("null", fp);
    fprintf(fp, ", \"exact\": %s, \"size_mismatch\": %s", r->exact ? "true" : "false",
            r->size_mismatch ? "true" : "false");
    fputs(",\n     \"measured\": {\"expected_size\": ", fp);
    json_size(fp, r->expected_w, r->expected_h);
    fputs(", \"actual_size\": ", fp);
    json_size(fp, r->actual_w, r->actual_h);
    fputs(", \"expected_pixels_sha256\": ", fp), json_maybe(fp, r->expected_sha256);
    fputs(", \"actual_pixels_sha256\": ", fp), json_maybe(fp, r->actual_sha256);
    if (r->compared && !r->size_mismatch) {
        fprintf(fp, ", \"antialiased_pixels\": %ld", x->antialiased);
        fprintf(fp, ", \"pixels\": %ld, \"differing_pixels\": %ld, \"changed_pixels\": %ld, "
                "\"masked_pixels\": %ld, \"max_channel_diff\": %d, \"rms\": ",
                x->pixels, x->differing, x->changed, r->masked_pixels, x->max_channel_diff);
        json_number(fp, "%.6f", x->rms);
        fputs(", \"ssim\": ", fp);
        json_number(fp, "%.6f", r->ssim >= 0 ? r->ssim : NAN);
        if (x->differing)
            fprintf(fp, ", \"bbox\": [%d, %d, %d, %d]", x->bbox[0], x->bbox[1], x->bbox[2],
                    x->bbox[3]);
        else
            fputs(", \"bbox\": null", fp);
    }
    fputs("}", fp);
    if (r->compared && !r->size_mismatch) {
        fprintf(fp, ",\n     \"tolerance\": {\"metric\": \"%s\", \"max_channel_diff\": %d, "
                "\"max_differing_pixels\": %ld, \"max_rms\": ",
                r->metric == SP_COMPARE_RMS ? "rms" : r->metric == SP_COMPARE_PIXELMATCH
                ? "pixelmatch" : r->metric == SP_COMPARE_BLOCKS ? "blocks" : "reftest",
                x->max_diff, x->allowed);
        json_number(fp, "%g", x->tol);
        fputs(", \"threshold\": ", fp);
        json_number(fp, "%g", x->threshold);
        json_also(fp, x);
        fputs("}", fp);
    } else
        fputs(",\n     \"tolerance\": null", fp);
    if (r->frames > 0) {
        fprintf(fp, ",\n     \"video\": {\"frames\": %d, \"failed_frames\": %d, "
                "\"worst_frame\": %d, \"expected_fps\": ",
                r->frames, r->failed_frames, r->worst_frame);
        json_number(fp, "%.6g", r->expected_fps);
        fputs(", \"actual_fps\": ", fp);
        json_number(fp, "%.6g", r->actual_fps);
        fputs("}", fp);
    } else {
        fputs(",\n     \"video\": null", fp);
    }
    fputs(", \"diff\": ", fp), json_maybe(fp, r->diff);
    fprintf(fp, ", \"seconds\": %.6f, \"alternatives\": %d, \"baseline_key\": ",
            r->seconds, r->n_alternatives);
    json_maybe(fp, r->baseline_key);
    fputs(", \"candidate\": ", fp), json_maybe(fp, r->candidate);
    fputs(", \"notes\": [", fp);
    for (int k = 0; k < r->n_notes; k++)
        fputs(k ? ", " : "", fp), sp_report_json_string(fp, r->notes[k]);
    fputs("], \"environment\": {\"expected\": ", fp);
    json_maybe(fp, r->environment[0] ? r->environment[0] : "");
    fputs(", \"actual\": ", fp);
    json_maybe(fp, r->environment[1] ? r->environment[1] : "");
    fputs("}, \"scene_changes\": [", fp);
    for (int k = 0; k < r->n_changes; k++) {
        fputs(k ? ", " : "", fp);
        fputs("{\"key\": ", fp), sp_report_json_string(fp, r->changes[k].key);
        fputs(", \"expected\": ", fp), sp_report_json_string(fp, r->changes[k].expected);
        fputs(", \"actual\": ", fp), sp_report_json_string(fp, r->changes[k].actual);
        fprintf(fp, ", \"cut\": %s, \"same_text\": %s}", r->changes[k].cut ? "true" : "false",
                r->changes[k].same_text ? "true" : "false");
    }
    fprintf(fp, "], \"more_changes\": %d}", r->more_changes);
}

void sp_compare_report_json(FILE *fp, const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = sp_compare_report_count(rep);
    fprintf(fp, "{\"schema\": \"springpend-compare/1\", \"pass\": %s, \"interrupted\": %s,\n"
            " \"problem\": ", sp_compare_report_passes(rep) ? "true" : "false",
            rep->interrupted ? "true" : "false");
    json_maybe(fp, rep->problem);
    fprintf(fp, ",\n \"counts\": {\"images\": %d, \"compared\": %d, \"passed\": %d, "
            "\"failed\": %d, \"errors\": %d, \"updated\": %d, \"unresolved\": %d, "
            "\"not_compared\": %d, \"out_of_memory\": %d},\n \"results\": [\n",
            c.records, c.compared, c.passed, c.failed, c.errors, c.updated,
            c.unresolved_failed + c.unresolved_errors, c.not_compared, c.out_of_memory);
    for (int i = 0; i < rep->n; i++) {
        json_record(fp, &rep->records[i]);
        fputs(i + 1 < rep->n ? ",\n" : "\n", fp);
    }
    fputs(" ]}\n", fp);
}

/* How xml_string treats "[[": JUnit's readers (GitLab, Jenkins) act on
 * [[ATTACHMENT|path]] in the text, so a name there must not open one;
 * XML_PATH: the path inside such a directive, which a reader opens (only
 * the bidi controls escaped, a backslash as it is). */
enum { XML_PLAIN, XML_NO_DIRECTIVES, XML_PATH };
/* Or'ed into xml_string's mode for a name: a control character shown as
 * the terminal's line shows it (\n, \xHH), where XML would read a newline
 * or a tab in an attribute as a space and HTML collapses it (attack10 #8:
 * "a\nb.png" and "a b.png" were two test cases both named "a b.png"). */
enum { XML_NAME = 8 };

/* s with XML's five special characters escaped; what XML 1.0 cannot hold
 * (C0 controls but tab and newline, U+FFFE, U+FFFF, bytes that are not
 * UTF-8) as U+FFFD, shown rather than dropped; a character that shows
 * nothing, a C1 control or a noncharacter (utf8.h's sp_utf8_is_hidden)
 * as \uHHHH and a backslash as \\, as messages show them (common.h). */
static void xml_string(FILE *fp, const char *s, int mode)
{
    static const char replacement[] = "\xEF\xBF\xBD";
    const char *start = s;
    const int name = mode & XML_NAME;
    mode &= ~XML_NAME;
    for (size_t n; *s; s += n ? n : 1) {
        n = sp_utf8_char(s);
        if (!n || (n == 3 && (unsigned char)s[0] == 0xEF && (unsigned char)s[1] == 0xBF &&
                   (unsigned char)s[2] >= 0xBE)) {
            fputs(replacement, fp);
            continue;
        }
        if (n != 1) {
            uint32_t u = sp_utf8_decode(s, &n);
            if (mode == XML_PATH ? sp_utf8_is_bidi_control(u) : sp_utf8_hidden_at(start, s))
                fprintf(fp, u > 0xffff ? "\\U%08x" : "\\u%04x",
                        (unsigned)u); /* shown, never reordering the name */
            else
                fwrite(s, 1, n, fp);
            continue;
        }
        switch (*s) {
        case '<': fputs("&lt;", fp); break;
        case '>': fputs("&gt;", fp); break;
        case '&': fputs("&amp;", fp); break;
        case '"': fputs("&quot;", fp); break;
        case '\'': fputs("&#39;", fp); break;
        case '\\': fputs(mode == XML_PATH ? "\\" : "\\\\", fp); break;
        case '[':
            fputs(mode == XML_NO_DIRECTIVES && s[1] == '[' ? "[ " : "[", fp);
            break;
        default:
            if (name && *s == '\n')
                fputs("\\n", fp);
            else if (name && (unsigned char)*s < 0x20)
                fprintf(fp, "\\x%02x", (unsigned char)*s);
            else if ((unsigned char)*s >= 0x20 || *s == '\n' || *s == '\t')
                fputc(*s, fp);
            else
                fputs(replacement, fp);
        }
    }
}

/* Room for record_line: the figures, four notes and 16 scene changes. */
#define RECORD_LINE_MAX 16384

/* One record's text line, for messages inside XML and HTML (cut, where
 * size is too small, at a character's boundary). */
static void record_line(const struct sp_compare_record *r, char *buf, size_t size)
{
    FILE *m = fmemopen(buf, size, "w");
    buf[0] = 0;
    if (!m)
        return;
    if (r->verdict == SP_VERDICT_ERROR)
        fprintf(m, "%s", r->error);
    else if (r->frames > 0)
        fprintf(m, "%d of %d frames differ; worst frame %d: ", r->failed_frames, r->frames,
                r->worst_frame);
    if (r->verdict != SP_VERDICT_ERROR && r->compared)
        text_figures(m, r);
    for (int k = 0; k < r->n_notes; k++)
        fprintf(m, "; %s", r->notes[k]);
    for (int k = 0; k < r->n_changes; k++)
        fprintf(m, "%sscene %s: %s vs %s", k || r->compared ? "; " : "", r->changes[k].key,
                r->changes[k].expected, r->changes[k].actual);
    if (r->more_changes)
        fprintf(m, "; and %d more scene keys changed (not listed)", r->more_changes);
    fclose(m);
    buf[size - 1] = 0;
    size_t n = strlen(buf), q = n;
    while (n == size - 1 && q > 0 && n - q < 3 && ((unsigned char)buf[q - 1] & 0xC0) == 0x80)
        q--; /* cut: the last character's start, which must hold it whole */
    if (q > 0 && ((unsigned char)buf[q - 1] & 0xC0) == 0xC0 && sp_utf8_char(buf + q - 1) == 0)
        buf[q - 1] = 0;
}

/* 1 when path can stand in [[ATTACHMENT|path]] whole: nothing that ends
 * the directive or starts another, nothing XML would change, nothing
 * xml_string's XML_PATH would show escaped (a bidi control: the directive
 * would name another file; attack9 #7). */
static int attachable(const char *path)
{
    for (size_t n; *path; path += n) {
        n = sp_utf8_char(path);
        if (!n || (unsigned char)*path < 0x20 || strchr("[]|<>&\"'", *path) ||
            (n == 3 && !memcmp(path, "\xEF\xBF", 2) && (unsigned char)path[2] >= 0xBE) ||
            (n > 1 && sp_utf8_is_bidi_control(sp_utf8_decode(path, &n))))
            return 0;
    }
    return 1;
}

/* The line that says a run was interrupted, into buf. */
static void interrupted_line(const struct sp_compare_report *rep,
                             const struct sp_compare_counts *c, char *buf, size_t size)
{
    snprintf(buf, size, "interrupted by %s after %d images; %d never compared: this is not "
             "a pass", sp_signal_name(rep->interrupted), c->records - c->not_compared,
             c->not_compared);
}

/* The folder part of a record's name ("" for a name without '/'). */
static int folder_len(const struct sp_compare_record *r)
{
    const char *slash = strrchr(r->name, '/');
    return slash ? (int)(slash - r->name) : 0;
}

/* 1 when records a and b belong to the same JUnit suite (folder). */
static int same_suite(const struct sp_compare_record *a, const struct sp_compare_record *b)
{
    int n = folder_len(a);
    return n == folder_len(b) && !strncmp(a->name, b->name, (size_t)n);
}

/* A suite's name: rep's suite (the EXPECTED folder), then the subfolder;
 * r NULL: rep's suite alone. */
static void suite_name(FILE *fp, const struct sp_compare_report *rep,
                       const struct sp_compare_record *r)
{
    char name[4096 + 300];
    int n = r ? folder_len(r) : 0;
    snprintf(name, sizeof(name), "%s%s%.*s", rep->suite ? rep->suite : "springpend compare",
             n ? "/" : "", n, r ? r->name : "");
    xml_string(fp, name, XML_NO_DIRECTIVES | XML_NAME);
}

static void junit_case(FILE *fp, const struct sp_compare_report *rep,
                       const struct sp_compare_record *r)
{
    char line[RECORD_LINE_MAX];
    const char *u = update_word(r->update);
    record_line(r, line, sizeof(line));
    fputs("    <testcase classname=\"", fp);
    suite_name(fp, rep, r);
    fputs("\" name=\"", fp);
    xml_string(fp, r->name + folder_len(r) + (folder_len(r) > 0), XML_NO_DIRECTIVES | XML_NAME);
    fprintf(fp, "\" time=\"%.6f\">\n", r->seconds);
    if (r->not_compared) {
        fputs("      <skipped message=\"", fp);
        xml_string(fp, line, XML_NO_DIRECTIVES);
        fputs("\"/>\n    </testcase>\n", fp);
        return;
    }
    if (r->verdict != SP_VERDICT_PASS && r->update == SP_UPDATE_NONE) {
        const char *tag = r->verdict == SP_VERDICT_FAIL ? "failure" : "error";
        fprintf(fp, "      <%s message=\"", tag);
        xml_string(fp, line, XML_NO_DIRECTIVES);
        fprintf(fp, "\" type=\"%s\">", r->size_mismatch ? "size" : tag);
        xml_string(fp, line, XML_NO_DIRECTIVES);
        if (r->hint[0])
            fputs("\n", fp), xml_string(fp, r->hint, XML_NO_DIRECTIVES);
        fprintf(fp, "</%s>\n", tag);
    }
    fputs("      <system-out>", fp);
    if (u) { /* what --update did, first: a reader sees why a failure passed */
        fprintf(fp, "%s baseline ", u);
        xml_string(fp, r->expected, XML_NO_DIRECTIVES);
        fprintf(fp, " (verdict before the update: %s)\n", verdict_word(r->verdict));
    }
    xml_string(fp, line, XML_NO_DIRECTIVES);
    /* GitLab and Jenkins attach this file; a path that could end the
     * directive early is named in the line above only. */
    if (r->diff[0] && attachable(r->diff))
        fputs("\n[[ATTACHMENT|", fp), xml_string(fp, r->diff, XML_PATH), fputs("]]", fp);
    fputs("</system-out>\n    </testcase>\n", fp);
}

/* A suite of one test case that errs: the run's problem or interruption. */
static void junit_run_error(FILE *fp, const struct sp_compare_report *rep, const char *name,
                            const char *type, const char *line)
{
    fputs("  <testsuite name=\"", fp);
    suite_name(fp, rep, NULL);
    fprintf(fp, "\" tests=\"1\" failures=\"0\" errors=\"1\" skipped=\"0\" time=\"0\">\n"
            "    <testcase classname=\"springpend.compare\" name=\"%s\" time=\"0\">\n"
            "      <error type=\"%s\" message=\"", name, type);
    xml_string(fp, line, XML_NO_DIRECTIVES);
    fputs("\">", fp);
    xml_string(fp, line, XML_NO_DIRECTIVES);
    fputs("</error>\n    </testcase>\n  </testsuite>\n", fp);
}

void sp_compare_report_junit(FILE *fp, const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = sp_compare_report_count(rep);
    char line[2048];
    double total = 0;
    int extra = !!rep->problem[0] + !!rep->interrupted; /* run-level errors */
    for (int i = 0; i < rep->n; i++)
        total += rep->records[i].seconds;
    fputs("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"", fp);
    suite_name(fp, rep, NULL);
    fprintf(fp, "\" tests=\"%d\" failures=\"%d\" errors=\"%d\" skipped=\"%d\" "
            "time=\"%.6f\">\n", c.records + extra, c.unresolved_failed,
            c.unresolved_errors + extra, c.not_compared, total);
    if (rep->problem[0]) /* no images at all: an error a test reporter shows */
        junit_run_error(fp, rep, "(images)", "error", rep->problem);
    if (rep->interrupted) {
        interrupted_line(rep, &c, line, sizeof(line));
        junit_run_error(fp, rep, "(interrupted)", "interrupted", line);
    }
    /* A suite per folder, in the order the folders first appear. */
    for (int i = 0; i < rep->n; i++) {
        const struct sp_compare_record *first = &rep->records[i];
        int seen = 0, tests = 0, failures = 0, errors = 0, skipped = 0;
        double t = 0;
        for (int k = 0; k < i && !seen; k++)
            seen = same_suite(&rep->records[k], first);
        if (seen)
            continue;
        for (int k = i; k < rep->n; k++) {
            const struct sp_compare_record *r = &rep->records[k];
            if (!same_suite(r, first))
                continue;
            tests++, t += r->seconds;
            skipped += r->not_compared;
            failures += !r->not_compared && r->verdict == SP_VERDICT_FAIL &&
                        r->update == SP_UPDATE_NONE;
            errors += !r->not_compared && r->verdict == SP_VERDICT_ERROR &&
                      r->update == SP_UPDATE_NONE;
        }
        fputs("  <testsuite name=\"", fp);
        suite_name(fp, rep, first);
        fprintf(fp, "\" tests=\"%d\" failures=\"%d\" errors=\"%d\" skipped=\"%d\" "
                "time=\"%.6f\">\n", tests, failures, errors, skipped, t);
        for (int k = i; k < rep->n; k++)
            if (same_suite(&rep->records[k], first))
                junit_case(fp, rep, &rep->records[k]);
        fputs("  </testsuite>\n", fp);
    }
    fputs("</testsuites>\n", fp);
}

/* Writes n bytes as base64. Returns 0, or SP_E_IO when a write failed
 * (the caller reports the stream's error). */
static int base64(FILE *fp, const unsigned char *in, size_t n)
{
    static const char b64[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char out[4 * 1024];
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)in[i] << 16 | (i + 1 < n ? in[i + 1] << 8 : 0) |
                     (i + 2 < n ? in[i + 2] : 0);
        out[o++] = b64[v >> 18 & 63];
        out[o++] = b64[v >> 12 & 63];
        out[o++] = i + 1 < n ? b64[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? b64[v & 63] : '=';
        if (o == sizeof(out)) {
            if (fwrite(out, 1, o, fp) != o)
                return SP_E_IO;
            o = 0;
        }
    }
    return fwrite(out, 1, o, fp) == o ? 0 : SP_E_IO;
}

/* A PNG larger than this is named in the report, not embedded, bytes. */
#define EMBED_MAX_BYTES (64L << 20)

/* Writes head, then path's bytes as a data: URL (base64), and nothing at
 * all otherwise, when path is a regular file of at most EMBED_MAX_BYTES that starts with
 * PNG's signature; else *why says why not. Opened without blocking or
 * following a FIFO's writer; reads at most the size fstat gave (a file
 * that grows is cut there). Returns 0, or SP_E_IO when a write or read
 * failed. */
static int data_url(FILE *fp, const char *head, const char *path, const char **why)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char in[3 * 1024];
    struct stat st;
    int err = 0;
    int fd = sp_infile_try(path, why);
    if (fd < 0)
        return 0;
    if (fstat(fd, &st) != 0)
        *why = "cannot be opened";
    else if (st.st_size > EMBED_MAX_BYTES)
        *why = "too large to embed";
    else if (pread(fd, in, sizeof(sig), 0) != (ssize_t)sizeof(sig) || memcmp(in, sig, sizeof(sig)))
        *why = "not a PNG";
    if (*why) {
        close(fd);
        return 0;
    }
    fputs(head, fp);
    fputs("data:image/png;base64,", fp);
    for (off_t left = st.st_size; left > 0 && !err;) {
        ssize_t n = read(fd, in, (size_t)(left < (off_t)sizeof(in) ? left : (off_t)sizeof(in)));
        if (n <= 0) {
            sp_log_error("%s: cannot read for the report: %s", path,
                         n < 0 ? strerror(errno) : "it became shorter");
            err = SP_E_IO;
            break;
        }
        left -= n;
        err = base64(fp, in, (size_t)n);
    }
    close(fd);
    return err;
}

/* The order rows are shown in: errors, failures, images never compared,
 * then passes. */
static int row_rank(const struct sp_compare_record *r)
{
    return r->not_compared ? 2 : r->verdict == SP_VERDICT_ERROR ? 0
           : r->verdict == SP_VERDICT_FAIL ? 1 : 3;
}

/* path as a relative or file: URL: every byte but unreserved ones and '/'
 * percent-encoded, so no name ("javascript:...") can be a scheme. */
/* path as seen from the folder of file `from` (both as the command line
 * gave them), into out: "../vid/e/a.mp4" for a report in rep/ of a video
 * in vid/e/. 0 when either cannot be resolved. */
static int relative_to(const char *from, const char *path, char *out, size_t size)
{
    char dir[PATH_MAX];
    const char *slash = strrchr(from, '/');
    snprintf(dir, sizeof(dir), "%.*s", slash ? (int)(slash - from) + (slash == from) : 1,
             slash ? from : ".");
    char *d = realpath(dir, NULL), *p = realpath(path, NULL);
    int ok = d && p;
    if (ok) {
        size_t k = 0; /* d[0..k) is the folder both lie in */
        if (strcmp(d, "/"))
            for (size_t i = 1;; i++) {
                if ((d[i] == '/' || !d[i]) && p[i] == '/' && !strncmp(d, p, i))
                    k = i;
                if (!d[i] || d[i] != p[i])
                    break;
            }
        size_t at = 0;
        for (const char *q = d + k; *q && at < size; q++)
            if (*q == '/')
                at += (size_t)snprintf(out + at, size - at, "../");
        ok = at < size && (size_t)snprintf(out + at, size - at, "%s", p + k + 1) < size - at;
    }
    free(d);
    free(p);
    return ok;
}

static void url_path(FILE *fp, const char *path, const char *report)
{
    char rel[PATH_MAX];
    if (report && path[0] != '/' && relative_to(report, path, rel, sizeof(rel)))
        path = rel; /* a browser resolves a link from the report's folder */
    fputs(path[0] == '/' ? "file://" : "./", fp);
    for (const unsigned char *p = (const unsigned char *)path; *p; p++)
        if ((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
            strchr("-._~/", *p))
            fputc(*p, fp);
        else
            fprintf(fp, "%%%02X", *p);
}

/* One image cell: an embedded PNG when is_png said it was read as one (and
 * data_url agrees), or bytes (a replaced baseline's, read as a PNG before it
 * was replaced) when not NULL, a link for a video, else the path and why it
 * is not shown. Returns 0 or SP_E_IO. */
/* compare.ini's masks over an image of w x h px, as boxes placed in percent
 * of its size (so they follow the zoom). */
static void html_masks(FILE *fp, const struct sp_compare_record *r, int w, int h)
{
    for (int k = 0; k < r->n_masks && w > 0 && h > 0; k++) {
        const struct sp_compare_mask *m = &r->masks[k];
        fprintf(fp, "<div class=\"mask\" title=\"masked: %d, %d, %d, %d\" style=\"left:%.4f%%;"
                "top:%.4f%%;width:%.4f%%;height:%.4f%%\"></div>", m->x, m->y, m->w, m->h,
                100.0 * m->x / w, 100.0 * m->y / h,
                100.0 * (m->x + m->w > w ? w - m->x : m->w) / w,
                100.0 * (m->y + m->h > h ? h - m->y : m->h) / h);
    }
}

static int html_image(FILE *fp, const char *cls, const char *path, int is_png,
                      const unsigned char *bytes, size_t size,
                      const struct sp_compare_record *r, const char *report)
{
    size_t n = strlen(path);
    const char *why = "not read as an image";
    int err = 0;
    if (bytes && is_png && size > 8 && !memcmp(bytes, "\x89PNG\r\n\x1a\n", 8)) {
        fprintf(fp, "<td class=\"%s\"><div class=\"pic\"><img alt=\"%s\" "
                "src=\"data:image/png;base64,", cls, cls);
        if ((err = base64(fp, bytes, size)) != 0)
            return err;
        fputs("\">", fp);
        html_masks(fp, r, r->expected_w, r->expected_h);
        fputs("</div><div class=\"replaced\">the baseline as it was; replaced by the "
              "actual image</div></td>", fp);
        return 0;
    }
    if (!path[0]) {
        fprintf(fp, "<td class=\"%s none\">none</td>", cls);
        return 0;
    }
    if (n < 4 || strcasecmp(path + n - 4, ".png")) { /* a video: named, not shown */
        fprintf(fp, "<td class=\"%s\"><a href=\"", cls);
        url_path(fp, path, report);
        fputs("\">", fp);
        xml_string(fp, path, XML_PLAIN);
        fputs("</a></td>", fp);
        return 0;
    }
    if (is_png) {
        char head[128];
        snprintf(head, sizeof(head), "<td class=\"%s\"><div class=\"pic\"><img alt=\"%s\" "
                 "src=\"", cls, cls);
        if ((err = data_url(fp, head, path, &why)) != 0)
            return err;
        if (!why) {
            fputs("\">", fp);
            html_masks(fp, r, r->expected_w, r->expected_h);
            fputs("</div></td>", fp);
            return 0;
        }
    }
    fprintf(fp, "<td class=\"%s none\">", cls);
    xml_string(fp, path, XML_PLAIN);
    fprintf(fp, "<br>not shown: %s</td>", why);
    return 0;
}

#define HTML_MAX_ENVIRONMENTS 64

/* The distinct springpend.environment texts of rep's images, in the order
 * first met (expected before actual), at most HTML_MAX_ENVIRONMENTS, into
 * envs; returns how many. */
static int distinct_environments(const struct sp_compare_report *rep, const char **envs)
{
    int n = 0;
    for (int i = 0; i < rep->n; i++)
        for (int k = 0; k < 2; k++) {
            const char *e = rep->records[i].environment[k];
            int j = 0;
            while (e && j < n && strcmp(envs[j], e))
                j++;
            if (e && j == n && n < HTML_MAX_ENVIRONMENTS)
                envs[n++] = e;
        }
    return n;
}

/* 1 + e's index among envs, 0 when e is NULL or not listed. */
static int environment_number(const char *const *envs, int n, const char *e)
{
    for (int j = 0; e && j < n; j++)
        if (!strcmp(envs[j], e))
            return j + 1;
    return 0;
}

/* The page's list of environments: each text whole, with how many expected
 * and actual images record it; rows link to them (#env-N). */
static void html_environments(FILE *fp, const struct sp_compare_report *rep,
                              const char *const *envs, int n)
{
    fputs("<h2 id=\"environments\">Environments</h2>\n<p>What each image records in its "
          "<code>springpend.environment</code> chunk (what <code>springpend version "
          "--verbose</code> printed where it was made), whole", fp);
    if (!n) {
        fputs(": no image records one.</p>\n", fp);
        return;
    }
    fputs(":</p>\n", fp);
    for (int j = 0; j < n; j++) {
        int in[2] = {0, 0};
        for (int i = 0; i < rep->n; i++)
            for (int k = 0; k < 2; k++)
                in[k] += environment_number(envs, n, rep->records[i].environment[k]) == j + 1;
        fprintf(fp, "<div class=\"env\" id=\"env-%d\"><h3>E%d: %d expected image%s, %d actual "
                "image%s</h3><pre>", j + 1, j + 1, in[0], in[0] == 1 ? "" : "s", in[1],
                in[1] == 1 ? "" : "s");
        xml_string(fp, envs[j], XML_PLAIN);
        fputs("</pre></div>\n", fp);
    }
}

/* A row's "made in: expected E1, actual E2". */
static void html_made_in(FILE *fp, const struct sp_compare_record *r, const char *const *envs,
                         int n)
{
    static const char *const side[] = {"expected", "actual"};
    fputs("<div class=\"made\">made in:", fp);
    for (int k = 0; k < 2; k++) {
        const int e = environment_number(envs, n, r->environment[k]);
        if (e)
            fprintf(fp, "%s %s <a href=\"#env-%d\">E%d</a>", k ? "," : "", side[k], e, e);
        else
            fprintf(fp, "%s %s %s", k ? "," : "", side[k],
                    r->environment[k] ? "(not listed)" : "(not recorded)");
    }
    fputs("</div>", fp);
}

/* The HTML report's script: the flip cells and the zoom buttons. */
static void html_script(FILE *fp)
{
    fputs("<script>\n"
          "for (const td of document.querySelectorAll('td.flipcell')) {\n"
          "  const row = td.parentElement, img = td.querySelector('img');\n"
          "  const b = td.querySelector('button'), label = td.querySelector('.showing');\n"
          "  const ie = row.querySelector('td.expected img'), ia = row.querySelector('td.actual img');\n"
          "  if (!ie || !ia) { td.textContent = '-'; continue; }\n"
          "  const src = {expected: ie.src, actual: ia.src};\n"
          "  let shown = 'actual';\n"
          "  const show = w => { shown = w; img.src = src[w]; img.alt = w; label.textContent = w;\n"
          "    b.textContent = 'show ' + (w == 'actual' ? 'expected' : 'actual'); };\n"
          "  const flip = () => show(shown == 'actual' ? 'expected' : 'actual');\n"
          "  b.addEventListener('click', flip); img.addEventListener('click', flip);\n"
          "  show('actual');\n"
          "  if (location.hash == '#flip') flip();\n"
          "}\n"
          "/* Zoom: every image at its own size times z, or fitted (z 0). */\n"
          "const setZoom = z => {\n"
          "  for (const im of document.querySelectorAll('.pic img, img.flipimg')) {\n"
          "    im.style.width = z ? im.naturalWidth * z + 'px' : '';\n"
          "    im.style.maxWidth = z ? 'none' : '280px'; }\n"
          "  for (const b of document.querySelectorAll('#zoom button'))\n"
          "    b.classList.toggle('on', +b.dataset.z == z); };\n"
          "for (const b of document.querySelectorAll('#zoom button'))\n"
          "  b.addEventListener('click', () => setZoom(+b.dataset.z));\n"
          "</script>\n</body></html>\n", fp);
}

/* One row of the HTML report: record r's name, verdict and figures, its
 * images and the flip cell (line: room for its figures, size bytes).
 * 0, or SP_E_IO. */
static int html_row(FILE *fp, const struct sp_compare_report *rep,
                    const struct sp_compare_record *r, const char *v, const char **envs,
                    int n_envs, char *line, size_t size)
{
    record_line(r, line, size);
    fprintf(fp, "<tr class=\"row v-%s\"><td class=\"figures\"><div class=\"name\">", v);
    xml_string(fp, r->name, XML_PLAIN | XML_NAME);
    fprintf(fp, "</div><div class=\"verdict\">%s</div>",
            r->not_compared ? "not compared" : v);
    if (update_word(r->update)) {
        fprintf(fp, "<div class=\"update\">%s: ", update_word(r->update));
        xml_string(fp, r->expected, XML_PLAIN);
        fputs("</div>", fp);
    }
    xml_string(fp, line, XML_PLAIN);
    if (r->hint[0])
        fputs("<br>", fp), xml_string(fp, r->hint, XML_PLAIN);
    html_made_in(fp, r, envs, n_envs);
    fputs("</td>", fp);
    /* Identical pixels: the image once, not twice. */
    int same = r->exact && !r->before;
    if (html_image(fp, "expected", r->expected, r->expected_png, r->before,
                   r->before_size, r, rep->report_path))
        return SP_E_IO;
    if (same) {
        fprintf(fp, "<td class=\"actual same\">identical pixels to the expected "
                "image (sha256 %.12s&hellip;)</td>", r->actual_sha256);
    } else if (html_image(fp, "actual", r->actual, r->actual_png, NULL, 0, r,
                          rep->report_path)) {
        return SP_E_IO;
    }
    if (html_image(fp, "diff", r->diff, r->diff[0] != 0, NULL, 0, r, rep->report_path))
        return SP_E_IO;
    /* The flip cell needs both images embedded. */
    if (r->expected_png && r->actual_png && r->frames == 0 && !same)
        fputs("<td class=\"flipcell\"><button class=\"flip\" type=\"button\">"
              "show expected</button><img class=\"flipimg\" alt=\"actual\" src=\"\">"
              "<div class=\"showing\">actual</div></td>", fp);
    else
        fputs("<td class=\"none\">-</td>", fp);
    fputs("</tr>\n", fp);
    return 0;
}

int sp_compare_report_html(FILE *fp, const struct sp_compare_report *rep)
{
    char line[RECORD_LINE_MAX];
    const char *envs[HTML_MAX_ENVIRONMENTS];
    const int n_envs = distinct_environments(rep, envs);
    fputs("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
          "<title>springpend compare</title>\n<style>\n"
          "body{font:14px/1.4 sans-serif;margin:1em;background:#fafafa;color:#222}\n"
          "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:6px;"
          "vertical-align:top;text-align:left}\n"
          ".pic{position:relative;display:inline-block}.pic img{display:block}\n"
          ".mask{position:absolute;box-sizing:border-box;border:2px dashed #0a0;"
          "background:rgba(0,170,0,.18);pointer-events:none}\n"
          "td.expected,td.actual,td.diff,td.flipcell{max-width:45vw;overflow:auto}\n"
          "#zoom button.on{font-weight:bold}\n"
          "img{image-rendering:pixelated;display:block;background:"
          "repeating-conic-gradient(#ddd 0 25%,#fff 0 50%) 0 0/16px 16px}\n"
          ".v-fail{background:#fde0e0}.v-error{background:#fff0c0}.v-pass{background:#e4f6e4}\n"
          ".update,.replaced{font-weight:bold;color:#a04000}\n"
          ".v-not-compared{background:#e8e8e8}#interrupted{font-weight:bold;color:#a00}\n"
          ".env pre{background:#fff;border:1px solid #ccc;padding:6px;margin:0 0 1em}.made{margin-top:4px}\n"
          ".verdict{font-weight:bold;text-transform:uppercase}.figures{width:18em;min-width:16em;font-size:12px;word-break:break-word}.none{color:#999}\n"
          "</style></head><body>\n<h1>springpend compare</h1>\n"
          "<p id=\"zoom\">images at <button type=\"button\" data-z=\"1\" class=\"on\">1&times;"
          "</button> <button type=\"button\" data-z=\"2\">2&times;</button> <button "
          "type=\"button\" data-z=\"4\">4&times;</button> <button type=\"button\" "
          "data-z=\"8\">8&times;</button> <button type=\"button\" data-z=\"0\">fit</button>"
          " (pixels stay sharp; compare.ini's masks are the dashed green boxes)</p>\n", fp);
    fputs("<p id=\"summary\">", fp);
    {
        char sum[1024];
        FILE *m = fmemopen(sum, sizeof(sum), "w");
        sum[0] = 0;
        if (m)
            summary_line(m, rep), fclose(m);
        sum[sizeof(sum) - 1] = 0;
        xml_string(fp, sum, XML_PLAIN);
    }
    fputs(rep->interrupted ? ", the rest never compared</p>\n" : "</p>\n", fp);
    if (rep->interrupted) {
        struct sp_compare_counts c = sp_compare_report_count(rep);
        interrupted_line(rep, &c, line, sizeof(line));
        fputs("<p id=\"interrupted\">", fp);
        xml_string(fp, line, XML_PLAIN);
        fputs("</p>\n", fp);
    }
    fputs("<table>\n<tr><th>image, verdict, figures</th><th>expected</th><th>actual</th><th>diff</th>"
          "<th>flip</th></tr>\n", fp);
    int hidden = 0;
    for (int rank = 0; rank < 4; rank++)
        for (int i = 0; i < rep->n && !ferror(fp); i++) {
            const struct sp_compare_record *r = &rep->records[i];
            const char *v = r->not_compared ? "not-compared" : verdict_word(r->verdict);
            if (row_rank(r) != rank)
                continue;
            if (rep->failures_only && rank == 3 && r->update == SP_UPDATE_NONE) {
                hidden++; /* --report-failures-only */
                continue;
            }
            if (html_row(fp, rep, r, v, envs, n_envs, line, sizeof(line)))
                return SP_E_IO;
        }
    /* The flip cell starts as the actual image; the button (or a click on
     * the image) swaps in the expected one, so a change blinks in place.
     * #flip in the URL flips every row once, for a quick look. A row whose
     * image was not embedded has no flip. */
    fputs("</table>\n", fp);
    html_environments(fp, rep, envs, n_envs); /* below: the images come first */
    if (hidden)
        fprintf(fp, "<p id=\"hidden\">%d passing image%s not shown "
                "(--report-failures-only)</p>\n", hidden, hidden == 1 ? "" : "s");
    html_script(fp);
    return ferror(fp) ? SP_E_IO : 0;
}

/* s inside a Markdown table cell: what Markdown or HTML would read as
 * markup escaped, a newline as a space; in a name (name 1) a control
 * character as the terminal shows it (\\n, \\xHH: xml_string's XML_NAME). */
static void md_text(FILE *fp, const char *s, int name)
{
    const char *start = s;
    for (size_t n; *s; s += n ? n : 1) {
        n = sp_utf8_char(s);
        uint32_t u = n > 1 ? sp_utf8_decode(s, &n) : 0;
        if (name && n == 1 && (unsigned char)*s < 0x20)
            fprintf(fp, *s == '\n' ? "\\\\n" : "\\\\x%02x", (unsigned char)*s);
        else if (!n || (unsigned char)*s < 0x20)
            fputc(n ? ' ' : '?', fp);
        else if (n > 1 && sp_utf8_hidden_at(start, s)) /* as messages show it; the \ as \\ */
            fprintf(fp, u > 0xffff ? "\\\\U%08x" : "\\\\u%04x", (unsigned)u);
        else if (*s == '\\') /* \\ shows it (the shown form's); \\\\ in Markdown */
            fputs("\\\\\\\\", fp);
        else if (*s == '@') /* no mention of a user or team from the bot's comment */
            fputs("@&#8203;", fp);
        else if (*s == '~')
            fputs("\\~", fp);
        else if (*s == '.' && s - start >= 3 && !strncasecmp(s - 3, "www", 3))
            fputs("&#8203;.", fp); /* "www." and "://" start no autolink */
        else if (*s == ':') /* no "://" autolink, no :ok: or :+1: emoji (GitHub) */
            fputs("&#58;", fp);
        else if (*s == '$') /* no $x^2$ math (GitHub's Markdown since 2022) */
            fputs("&#36;", fp);
        else if (*s == '<')
            fputs("&lt;", fp);
        else if (*s == '>')
            fputs("&gt;", fp);
        else if (*s == '&')
            fputs("&amp;", fp);
        else if (strchr("|\\`*_[]#!", *s))
            fprintf(fp, "\\%c", *s);
        else
            fwrite(s, 1, n, fp);
    }
}

static void md_cell(FILE *fp, const char *s)
{
    md_text(fp, s, 0);
}

/* What was measured and what was allowed, for the summary's table. */
static void md_figures(FILE *fp, const struct sp_compare_record *r)
{
    const struct sp_compare_result *x = &r->result;
    char m[256] = "", a[128] = "";
    if (r->verdict == SP_VERDICT_ERROR || !r->compared) {
        fputs(" | ", fp), md_cell(fp, r->error), fputs(" | |", fp);
        return;
    }
    if (r->size_mismatch) {
        snprintf(m, sizeof(m), "%dx%d, expected %dx%d", r->actual_w, r->actual_h,
                 r->expected_w, r->expected_h);
        snprintf(a, sizeof(a), "the same size");
    } else if (r->metric == SP_COMPARE_PIXELMATCH) {
        snprintf(m, sizeof(m), "%ld px differ (pixelmatch, threshold %g)", x->differing,
                 x->threshold);
        snprintf(a, sizeof(a), "%ld px", x->allowed);
    } else if (r->metric == SP_COMPARE_RMS) {
        snprintf(m, sizeof(m), "rms %.3f", x->rms);
        snprintf(a, sizeof(a), "rms ≤ %g", x->tol);
    } else {
        snprintf(m, sizeof(m), "%ld %s differ by > %d levels (largest %d)", x->differing,
                 r->metric == SP_COMPARE_BLOCKS ? "8x8 blocks" : "px", x->max_diff,
                 x->max_channel_diff);
        snprintf(a, sizeof(a), "%ld %s", x->allowed,
                 r->metric == SP_COMPARE_BLOCKS ? "blocks" : "px");
    }
    if (x->also && x->decided_by >= 0 && x->decided_by < 3 && !r->size_mismatch)
        snprintf(m + strlen(m), sizeof(m) - strlen(m), "; the command line's %s rule "
                 "decided", rule_names[x->decided_by]);
    fputs(" | ", fp);
    if (r->frames > 0)
        fprintf(fp, "%d of %d frames; worst frame %d: ", r->failed_frames, r->frames,
                r->worst_frame);
    md_cell(fp, m);
    fputs(" | ", fp), md_cell(fp, a), fputs(" |", fp);
}

/* 1 when a scene key draws text: a title, caption, axis name or cue. */
static int draws_text(const char *key)
{
    static const char *const keys[] = {"view.title", "view.caption", "view.xlabel",
                                       "view.ylabel", "view.colorbar_label"};
    for (size_t i = 0; i < sizeof(keys) / sizeof(keys[0]); i++)
        if (!strcmp(key, keys[i]))
            return 1;
    return !strncmp(key, "timeline", 8);
}

static void md_text_changes_head(FILE *fp)
{
    fputs("\nPassed, but drawn with other text than the baseline (a pixel rule may "
          "not see a changed word or digit; look at them):\n\n| image | key | "
          "expected | actual |\n|---|---|---|---|\n", fp);
}

/* Passing images whose recorded scene differs in a key that draws text: a
 * block or pixel rule can pass a changed word or digit in 12 px text
 * (attack15 #17), so the reviewer is shown the keys (at most 50 rows). */
static void md_text_changes(FILE *fp, const struct sp_compare_report *rep)
{
    int rows = 0;
    for (int i = 0; i < rep->n && rows < 50; i++) {
        const struct sp_compare_record *r = &rep->records[i];
        for (int k = 0; r->verdict == SP_VERDICT_PASS && r->compared && k < r->n_changes &&
                        rows < 50; k++) {
            if (!draws_text(r->changes[k].key))
                continue;
            if (!rows++)
                md_text_changes_head(fp);
            fputs("| ", fp), md_text(fp, r->name, 1), fputs(" | ", fp);
            md_cell(fp, r->changes[k].key), fputs(" | ", fp);
            md_cell(fp, r->changes[k].expected), fputs(" | ", fp);
            md_cell(fp, r->changes[k].actual), fputs(" |\n", fp);
        }
        if (r->verdict == SP_VERDICT_PASS && r->compared && r->more_changes && rows < 50) {
            /* which keys is not recorded: any of them may draw text */
            if (!rows++)
                md_text_changes_head(fp);
            fputs("| ", fp), md_text(fp, r->name, 1);
            fprintf(fp, " | and %d more scene keys changed (not listed) | | |\n", r->more_changes);
        }
    }
}

void sp_compare_report_markdown(FILE *fp, const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = sp_compare_report_count(rep);
    const int max_rows = 50;
    int rows = 0, more = 0;
    fprintf(fp, "### springpend compare: %s\n\n", status_word(rep));
    fprintf(fp, "%d images: %d compared, %d passed, %d failed, %d missing or unreadable, "
            "%d updated", c.records, c.compared, c.passed, c.failed, c.errors, c.updated);
    if (c.out_of_memory)
        fprintf(fp, ", %d out of memory", c.out_of_memory);
    if (c.not_compared)
        fprintf(fp, ", %d not compared (interrupted)", c.not_compared);
    fputs(".\n", fp);
    if (rep->problem[0])
        fputs("\n", fp), md_cell(fp, rep->problem), fputs("\n", fp);
    for (int i = 0; i < rep->n; i++) {
        const struct sp_compare_record *r = &rep->records[i];
        if (r->verdict == SP_VERDICT_PASS || r->update != SP_UPDATE_NONE || r->not_compared)
            continue;
        if (rows == max_rows) {
            more++;
            continue;
        }
        if (!rows++)
            fputs("\n| image | verdict | measured | allowed |\n|---|---|---|---|\n", fp);
        fputs("| ", fp), md_text(fp, r->name, 1);
        fprintf(fp, " | %s", verdict_word(r->verdict));
        md_figures(fp, r);
        fputc('\n', fp);
    }
    /* where the rest are: the report, when there is one (attack13 #24) */
    if (more && rep->report_path) {
        fprintf(fp, "\nand %d more failures and errors: see the report.\n", more);
    } else if (more && rep->junit_path) {
        fprintf(fp, "\nand %d more failures and errors, not listed here: the JUnit file `", more);
        for (const char *p = rep->junit_path; *p; p++)
            fputc(*p == '`' || (unsigned char)*p < 0x20 ? '?' : *p, fp);
        fputs("` and compare's output list them.\n", fp);
    } else if (more) {
        fprintf(fp, "\nand %d more failures and errors, not listed here: compare's output "
                "lists them (with --report FILE.html, a page shows them all).\n", more);
    }
    md_text_changes(fp, rep);
    if (rep->report_path) {
        fputs("\nReport: `", fp);
        for (const char *p = rep->report_path; *p; p++)
            fputc(*p == '`' || (unsigned char)*p < 0x20 ? '?' : *p, fp);
        fputs("` (expected, actual and diff side by side).\n", fp);
    }
}
