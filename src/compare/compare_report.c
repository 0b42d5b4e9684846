/* springpend: compare's records and reporters (compare_report.h). */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "springpend/common.h"
#include "springpend/compare_report.h"
#include "text.h"

struct sp_compare_record *sp_compare_report_add(struct sp_compare_report *rep)
{
    if (rep->n == rep->cap) {
        int cap = rep->cap ? 2 * rep->cap : 16;
        struct sp_compare_record *r = realloc(rep->records, sizeof(*r) * (size_t)cap);
        if (!r) {
            sp_log_error("out of memory for the comparison's records");
            return NULL;
        }
        rep->records = r, rep->cap = cap;
    }
    struct sp_compare_record *r = &rep->records[rep->n++];
    memset(r, 0, sizeof(*r));
    r->ssim = -1;
    r->worst_frame = -1;
    return r;
}

void sp_compare_report_free(struct sp_compare_report *rep)
{
    for (int i = 0; i < rep->n; i++)
        free(rep->records[i].before);
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
        c.compared += r->compared;
        c.passed += r->verdict == SP_VERDICT_PASS;
        c.failed += r->verdict == SP_VERDICT_FAIL;
        c.errors += r->verdict == SP_VERDICT_ERROR;
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
 * baselines) or FAIL. */
static const char *status_word(const struct sp_compare_report *rep)
{
    return !sp_compare_report_passes(rep) ? "FAIL"
           : sp_compare_report_count(rep).updated ? "UPDATED" : "ok";
}

/* The summary line's figures (no newline). */
static void summary_line(FILE *fp, const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = sp_compare_report_count(rep);
    fprintf(fp, "%s: %d compared, %d passed, %d failed, %d missing or unreadable, "
            "%d updated", status_word(rep), c.compared, c.passed, c.failed, c.errors,
            c.updated);
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

/* The figures of a compared record, as the rest of a line. */
static void text_figures(FILE *fp, const struct sp_compare_record *r)
{
    const struct sp_compare_result *x = &r->result;
    if (r->size_mismatch) {
        fprintf(fp, "expected %dx%d, actual %dx%d; images of different sizes never match",
                r->expected_w, r->expected_h, r->actual_w, r->actual_h);
    } else if (r->exact) {
        fprintf(fp, "identical pixels (%ld, sha256 %.12s)", x->pixels, r->actual_sha256);
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
    if (r->masked_pixels)
        fprintf(fp, "; %ld pixels masked", r->masked_pixels);
    if (r->diff[0])
        fprintf(fp, "; diff: %s", r->diff);
}

void sp_compare_report_text(FILE *fp, const struct sp_compare_report *rep, int quiet,
                            int summary)
{
    for (int i = 0; i < rep->n; i++) {
        const struct sp_compare_record *r = &rep->records[i];
        const char *u = update_word(r->update);
        if (r->verdict == SP_VERDICT_ERROR && (r->update == SP_UPDATE_ADDED ||
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
        if (u)
            fprintf(fp, "%-8s %s\n", u, r->expected);
    }
    /* Each hint once, not once per missing image. */
    for (int i = 0, shown = -1; i < rep->n; i++) {
        const struct sp_compare_record *r = &rep->records[i];
        if (!r->hint[0] || r->update != SP_UPDATE_NONE ||
            (shown >= 0 && !strcmp(rep->records[shown].hint, r->hint)))
            continue;
        fprintf(fp, "%s\n", r->hint);
        shown = i;
    }
    if (summary || rep->problem[0])
        summary_line(fp, rep), fputc('\n', fp);
    if (summary && rep->interrupted)
        fprintf(fp, "interrupted after %d images\n", rep->n);
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
        else if (ch < 0x20)
            fprintf(fp, "\\u%04x", ch);
        else
            fwrite(s, 1, n, fp);
    }
    fputc('"', fp);
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

static void json_record(FILE *fp, const struct sp_compare_record *r)
{
    const struct sp_compare_result *x = &r->result;
    fputs("    {\"name\": ", fp), sp_report_json_string(fp, r->name);
    fputs(", \"expected\": ", fp), json_maybe(fp, r->expected);
    fputs(", \"actual\": ", fp), json_maybe(fp, r->actual);
    fprintf(fp, ", \"verdict\": \"%s\", \"pass\": %s", verdict_word(r->verdict),
            r->verdict == SP_VERDICT_PASS ? "true" : "false");
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
        fprintf(fp, ", \"pixels\": %ld, \"differing_pixels\": %ld, \"changed_pixels\": %ld, "
                "\"masked_pixels\": %ld, \"max_channel_diff\": %d, \"rms\": %.6f, \"ssim\": ",
                x->pixels, x->differing, x->changed, r->masked_pixels, x->max_channel_diff,
                x->rms);
        if (r->ssim >= 0)
            fprintf(fp, "%.6f", r->ssim);
        else
            fputs("null", fp);
        if (x->differing)
            fprintf(fp, ", \"bbox\": [%d, %d, %d, %d]", x->bbox[0], x->bbox[1], x->bbox[2],
                    x->bbox[3]);
        else
            fputs(", \"bbox\": null", fp);
    }
    fputs("}", fp);
    if (r->compared && !r->size_mismatch)
        fprintf(fp, ",\n     \"tolerance\": {\"metric\": \"%s\", \"max_channel_diff\": %d, "
                "\"max_differing_pixels\": %ld, \"max_rms\": %g}",
                r->metric == SP_COMPARE_RMS ? "rms" : "reftest", x->max_diff, x->allowed,
                x->tol);
    else
        fputs(",\n     \"tolerance\": null", fp);
    if (r->frames > 0) {
        fprintf(fp, ",\n     \"video\": {\"frames\": %d, \"failed_frames\": %d, "
                "\"worst_frame\": %d, \"expected_fps\": %.6g, \"actual_fps\": %.6g}",
                r->frames, r->failed_frames, r->worst_frame, r->expected_fps, r->actual_fps);
    } else {
        fputs(",\n     \"video\": null", fp);
    }
    fputs(", \"diff\": ", fp), json_maybe(fp, r->diff);
    fprintf(fp, ", \"seconds\": %.6f", r->seconds);
    fputs(", \"notes\": [", fp);
    for (int k = 0; k < r->n_notes; k++)
        fputs(k ? ", " : "", fp), sp_report_json_string(fp, r->notes[k]);
    fputs("], \"scene_changes\": [", fp);
    for (int k = 0; k < r->n_changes; k++) {
        fputs(k ? ", " : "", fp);
        fputs("{\"key\": ", fp), sp_report_json_string(fp, r->changes[k].key);
        fputs(", \"expected\": ", fp), sp_report_json_string(fp, r->changes[k].expected);
        fputs(", \"actual\": ", fp), sp_report_json_string(fp, r->changes[k].actual);
        fputs("}", fp);
    }
    fputs("]}", fp);
}

void sp_compare_report_json(FILE *fp, const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = sp_compare_report_count(rep);
    fprintf(fp, "{\"schema\": \"springpend-compare/1\", \"pass\": %s, \"interrupted\": %s,\n"
            " \"problem\": ", sp_compare_report_passes(rep) ? "true" : "false",
            rep->interrupted ? "true" : "false");
    json_maybe(fp, rep->problem);
    fprintf(fp, ",\n \"counts\": {\"images\": %d, \"compared\": %d, \"passed\": %d, "
            "\"failed\": %d, \"errors\": %d, \"updated\": %d, \"unresolved\": %d},\n"
            " \"results\": [\n",
            c.records, c.compared, c.passed, c.failed, c.errors, c.updated,
            c.unresolved_failed + c.unresolved_errors);
    for (int i = 0; i < rep->n; i++) {
        json_record(fp, &rep->records[i]);
        fputs(i + 1 < rep->n ? ",\n" : "\n", fp);
    }
    fputs(" ]}\n", fp);
}

/* s with XML's five special characters escaped. */
static void xml_string(FILE *fp, const char *s)
{
    for (size_t n; *s; s += n ? n : 1) {
        if ((n = sp_utf8_char(s)) != 1) { /* XML is UTF-8: a stray byte is U+FFFD */
            fwrite(n ? s : "\xEF\xBF\xBD", 1, n ? n : 3, fp);
            continue;
        }
        switch (*s) {
        case '<': fputs("&lt;", fp); break;
        case '>': fputs("&gt;", fp); break;
        case '&': fputs("&amp;", fp); break;
        case '"': fputs("&quot;", fp); break;
        case '\'': fputs("&#39;", fp); break;
        default:
            if ((unsigned char)*s >= 0x20 || *s == '\n' || *s == '\t')
                fputc(*s, fp);
        }
    }
}

/* One record's text line, for messages inside XML and HTML. */
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
    fclose(m);
    buf[size - 1] = 0;
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

/* A suite's name: rep's suite (the EXPECTED folder), then the subfolder. */
static void suite_name(FILE *fp, const struct sp_compare_report *rep,
                       const struct sp_compare_record *r)
{
    char name[4096 + 300];
    int n = folder_len(r);
    snprintf(name, sizeof(name), "%s%s%.*s", rep->suite ? rep->suite : "springpend compare",
             n ? "/" : "", n, r->name);
    xml_string(fp, name);
}

static void junit_case(FILE *fp, const struct sp_compare_report *rep,
                       const struct sp_compare_record *r)
{
    char line[4096];
    const char *u = update_word(r->update);
    record_line(r, line, sizeof(line));
    fputs("    <testcase classname=\"", fp);
    suite_name(fp, rep, r);
    fputs("\" name=\"", fp);
    xml_string(fp, r->name + folder_len(r) + (folder_len(r) > 0));
    fprintf(fp, "\" time=\"%.6f\">\n", r->seconds);
    if (r->verdict != SP_VERDICT_PASS && r->update == SP_UPDATE_NONE) {
        const char *tag = r->verdict == SP_VERDICT_FAIL ? "failure" : "error";
        fprintf(fp, "      <%s message=\"", tag);
        xml_string(fp, line);
        fprintf(fp, "\" type=\"%s\">", r->size_mismatch ? "size" : tag);
        xml_string(fp, line);
        if (r->hint[0])
            fputs("\n", fp), xml_string(fp, r->hint);
        fprintf(fp, "</%s>\n", tag);
    }
    fputs("      <system-out>", fp);
    if (u) { /* what --update did, first: a reader sees why a failure passed */
        fprintf(fp, "%s baseline ", u);
        xml_string(fp, r->expected);
        fprintf(fp, " (verdict before the update: %s)\n", verdict_word(r->verdict));
    }
    xml_string(fp, line);
    if (r->diff[0]) /* GitLab and Jenkins attach this file */
        fputs("\n[[ATTACHMENT|", fp), xml_string(fp, r->diff), fputs("]]", fp);
    fputs("</system-out>\n    </testcase>\n", fp);
}

void sp_compare_report_junit(FILE *fp, const struct sp_compare_report *rep)
{
    struct sp_compare_counts c = sp_compare_report_count(rep);
    double total = 0;
    for (int i = 0; i < rep->n; i++)
        total += rep->records[i].seconds;
    fputs("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"", fp);
    xml_string(fp, rep->suite ? rep->suite : "springpend compare");
    fprintf(fp, "\" tests=\"%d\" failures=\"%d\" errors=\"%d\" time=\"%.6f\">\n",
            c.records + !!rep->problem[0], c.unresolved_failed,
            c.unresolved_errors + !!rep->problem[0], total);
    if (rep->problem[0]) { /* no images at all: an error a test reporter shows */
        fputs("  <testsuite name=\"", fp);
        xml_string(fp, rep->suite ? rep->suite : "springpend compare");
        fputs("\" tests=\"1\" failures=\"0\" errors=\"1\" skipped=\"0\" time=\"0\">\n"
              "    <testcase classname=\"springpend.compare\" name=\"images\" time=\"0\">\n"
              "      <error type=\"error\" message=\"", fp);
        xml_string(fp, rep->problem);
        fputs("\"/>\n    </testcase>\n  </testsuite>\n", fp);
    }
    /* A suite per folder, in the order the folders first appear. */
    for (int i = 0; i < rep->n; i++) {
        const struct sp_compare_record *first = &rep->records[i];
        int seen = 0, tests = 0, failures = 0, errors = 0;
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
            failures += r->verdict == SP_VERDICT_FAIL && r->update == SP_UPDATE_NONE;
            errors += r->verdict == SP_VERDICT_ERROR && r->update == SP_UPDATE_NONE;
        }
        fputs("  <testsuite name=\"", fp);
        suite_name(fp, rep, first);
        fprintf(fp, "\" tests=\"%d\" failures=\"%d\" errors=\"%d\" skipped=\"0\" "
                "time=\"%.6f\">\n", tests, failures, errors, t);
        for (int k = i; k < rep->n; k++)
            if (same_suite(&rep->records[k], first))
                junit_case(fp, rep, &rep->records[k]);
        fputs("  </testsuite>\n", fp);
    }
    fputs("</testsuites>\n", fp);
}

/* Writes n bytes as base64. */
static void base64(FILE *fp, const unsigned char *in, size_t n)
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
        if (o == sizeof(out))
            fwrite(out, 1, o, fp), o = 0;
    }
    fwrite(out, 1, o, fp);
}

/* Writes path's bytes as a data: URL (base64), or nothing when it cannot
 * be read. Returns 0, or SP_E_NOMEM. */
static int data_url(FILE *fp, const char *path)
{
    unsigned char in[3 * 1024];
    size_t n;
    FILE *f = path[0] ? fopen(path, "rb") : NULL;
    if (!f)
        return 0;
    fputs("data:image/png;base64,", fp);
    while ((n = fread(in, 1, sizeof(in), f)) > 0)
        base64(fp, in, n);
    fclose(f);
    return 0;
}

/* The order rows are shown in: errors, failures, then passes. */
static int row_rank(const struct sp_compare_record *r)
{
    return r->verdict == SP_VERDICT_ERROR ? 0 : r->verdict == SP_VERDICT_FAIL ? 1 : 2;
}

/* An image cell: path's image, or bytes (a replaced baseline's, from
 * memory) when not NULL. */
static void html_image(FILE *fp, const char *cls, const char *path, const unsigned char *bytes,
                       size_t size)
{
    size_t n = strlen(path);
    if (bytes) {
        fprintf(fp, "<td class=\"%s\"><img alt=\"%s\" src=\"data:image/png;base64,", cls,
                cls);
        base64(fp, bytes, size);
        fputs("\"><div class=\"replaced\">replaced by the actual image</div></td>", fp);
        return;
    }
    if (!path[0]) {
        fprintf(fp, "<td class=\"%s none\">none</td>", cls);
        return;
    }
    if (n < 4 || strcasecmp(path + n - 4, ".png")) { /* a video: named, not shown */
        fprintf(fp, "<td class=\"%s\"><a href=\"", cls);
        xml_string(fp, path);
        fputs("\">", fp);
        xml_string(fp, path);
        fputs("</a></td>", fp);
        return;
    }
    fprintf(fp, "<td class=\"%s\"><img alt=\"%s\" src=\"", cls, cls);
    data_url(fp, path);
    fputs("\"></td>", fp);
}

int sp_compare_report_html(FILE *fp, const struct sp_compare_report *rep)
{
    char line[4096];
    fputs("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
          "<title>springpend compare</title>\n<style>\n"
          "body{font:14px/1.4 sans-serif;margin:1em;background:#fafafa;color:#222}\n"
          "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:6px;"
          "vertical-align:top;text-align:left}\n"
          "img{max-width:280px;image-rendering:pixelated;display:block;background:"
          "repeating-conic-gradient(#ddd 0 25%,#fff 0 50%) 0 0/16px 16px}\n"
          ".v-fail{background:#fde0e0}.v-error{background:#fff0c0}.v-pass{background:#e4f6e4}\n"
          ".update,.replaced{font-weight:bold;color:#a04000}\n"
          ".verdict{font-weight:bold;text-transform:uppercase}.figures{width:18em;font-size:12px;word-break:break-word}.none{color:#999}\n"
          "</style></head><body>\n<h1>springpend compare</h1>\n", fp);
    fputs("<p id=\"summary\">", fp);
    {
        char line[1024];
        FILE *m = fmemopen(line, sizeof(line), "w");
        line[0] = 0;
        if (m)
            summary_line(m, rep), fclose(m);
        line[sizeof(line) - 1] = 0;
        xml_string(fp, line);
    }
    fputs("</p>\n", fp);
    fputs("<table>\n<tr><th>image, verdict, figures</th><th>expected</th><th>actual</th><th>diff</th>"
          "<th>flip</th></tr>\n", fp);
    for (int rank = 0; rank < 3; rank++)
        for (int i = 0; i < rep->n; i++) {
            const struct sp_compare_record *r = &rep->records[i];
            if (row_rank(r) != rank)
                continue;
            record_line(r, line, sizeof(line));
            fprintf(fp, "<tr class=\"row v-%s\"><td class=\"figures\"><div class=\"name\">",
                    verdict_word(r->verdict));
            xml_string(fp, r->name);
            fprintf(fp, "</div><div class=\"verdict\">%s</div>", verdict_word(r->verdict));
            if (update_word(r->update)) {
                fprintf(fp, "<div class=\"update\">%s: ", update_word(r->update));
                xml_string(fp, r->expected);
                fputs("</div>", fp);
            }
            xml_string(fp, line);
            if (r->hint[0])
                fputs("<br>", fp), xml_string(fp, r->hint);
            fputs("</td>", fp);
            html_image(fp, "expected", r->expected, r->before, r->before_size);
            html_image(fp, "actual", r->actual, NULL, 0);
            html_image(fp, "diff", r->diff, NULL, 0);
            if (r->expected[0] && r->actual[0] && r->frames == 0)
                fputs("<td class=\"flipcell\"><button class=\"flip\" type=\"button\">"
                      "show expected</button><img class=\"flipimg\" alt=\"actual\" src=\"\">"
                      "<div class=\"showing\">actual</div></td>", fp);
            else
                fputs("<td class=\"none\">-</td>", fp);
            fputs("</tr>\n", fp);
        }
    /* The flip cell starts as the actual image; the button (or a click on
     * the image) swaps in the expected one, so a change blinks in place.
     * #flip in the URL flips every row once, for a quick look. */
    fputs("</table>\n<script>\n"
          "for (const td of document.querySelectorAll('td.flipcell')) {\n"
          "  const row = td.parentElement, img = td.querySelector('img');\n"
          "  const b = td.querySelector('button'), label = td.querySelector('.showing');\n"
          "  const src = {expected: row.querySelector('td.expected img').src,\n"
          "               actual: row.querySelector('td.actual img').src};\n"
          "  let shown = 'actual';\n"
          "  const show = w => { shown = w; img.src = src[w]; img.alt = w; label.textContent = w;\n"
          "    b.textContent = 'show ' + (w == 'actual' ? 'expected' : 'actual'); };\n"
          "  const flip = () => show(shown == 'actual' ? 'expected' : 'actual');\n"
          "  b.addEventListener('click', flip); img.addEventListener('click', flip);\n"
          "  show('actual');\n"
          "  if (location.hash == '#flip') flip();\n"
          "}\n</script>\n</body></html>\n", fp);
    return ferror(fp) ? SP_E_IO : 0;
}
