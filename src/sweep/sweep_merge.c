/* springpend: the merge of a sweep's shards (sweep_merge.h). */
#include <errno.h>
#include <fcntl.h>
#include <float.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/digest.h"
#include "springpend/common.h"
#include "springpend/csv_metadata.h"
#include "springpend/infile.h"
#include "springpend/provenance.h"
#include "springpend/timeline.h"
#include "sweep_format.h"
#include "sweep_merge.h"

/* A shard's CSV and what its metadata says. */
struct sp_sweep_shard {
    const char *path;
    FILE *fp;              /* the CSV, after its header line */
    json_t *meta;          /* its CSV.csv-metadata.json */
    const char *description, *scene, *version;
    json_t *overrides;     /* array of strings */
    int i, n;              /* shard I of N */
    long rows;
    const char *sha256;
};

/* The string member key of obj, or NULL. */
static const char *member(json_t *obj, const char *key)
{
    return json_string_value(json_object_get(obj, key));
}

/* Reads the shard's metadata; messages name it. 0 or SP_E_*. */
static int read_shard_meta(struct sp_sweep_shard *s)
{
    int used = 0, err;
    if (!(s->meta = sp_csv_metadata_load(s->path, &err)))
        return err;
    s->description = member(s->meta, "dc:description");
    s->scene = member(s->meta, "dc:source");
    s->version = member(s->meta, "schema:softwareVersion");
    s->overrides = json_object_get(s->meta, "prov:used");
    s->sha256 = member(s->meta, "schema:sha256");
    json_t *rows = json_object_get(s->meta, "dc:extent");
    const char *pos = member(s->meta, "schema:position");
    s->rows = json_is_integer(rows) ? (long)json_integer_value(rows) : -1;
    if (!s->description || !s->scene || !s->version || !json_is_array(s->overrides) ||
        !s->sha256 || s->rows < 0 || !pos ||
        sscanf(pos, "%d/%d%n", &s->i, &s->n, &used) != 2 || pos[used]) {
        sp_log_error("%s" SP_CSV_METADATA_SUFFIX ": not a sweep shard's metadata (it needs "
                     "dc:description, dc:source, schema:softwareVersion, prov:used, "
                     "schema:position, dc:extent and schema:sha256, as 'springpend sweep "
                     "--shard I/N --csv FILE' writes them)", s->path);
        return SP_E_INPUT;
    }
    return 0;
}

/* The first line where scene texts a and b differ, as "[section] line", into
 * wa and wb. */
static void first_difference(const char *a, const char *b, char *wa, char *wb, size_t size)
{
    char section[64] = "";
    while (*a || *b) {
        const size_t na = strcspn(a, "\n"), nb = strcspn(b, "\n");
        if (na != nb || strncmp(a, b, na)) {
            snprintf(wa, size, "%s%.*s", section, (int)na, a);
            snprintf(wb, size, "%s%.*s", section, (int)nb, b);
            return;
        }
        if (*a == '[')
            snprintf(section, sizeof(section), "%.*s ", (int)na, a);
        a += na + (a[na] == '\n');
        b += nb + (b[nb] == '\n');
    }
    snprintf(wa, size, "?");
    snprintf(wb, size, "?");
}

/* The value of the k-th word "key=VALUE" (k counts the words with that
 * key: vary is there once per axis) of description d, n bytes into *v;
 * NULL when there is none. */
static const char *description_value(const char *d, const char *key, size_t klen, int k,
                                     size_t *n)
{
    for (const char *w = d; *w; w += strspn(w, " ")) {
        const size_t len = strcspn(w, " ");
        if (len > klen && w[klen] == '=' && !strncmp(w, key, klen) && k-- == 0) {
            *n = len - klen - 1;
            return w + klen + 1;
        }
        w += len;
    }
    return NULL;
}

/* One side of a difference of descriptions: "key=VALUE", or the value a
 * word left out stands for (kernel=exact, continue=none), or "no key". */
static void description_side(char *out, size_t size, const char *key, size_t klen,
                             const char *v, size_t n)
{
    static const char *const absent[][2] = {{"kernel", "exact"}, {"continue", "none"}};
    if (v) {
        snprintf(out, size, "%.*s=%.*s", (int)klen, key, (int)n, v);
        return;
    }
    for (size_t i = 0; i < sizeof(absent) / sizeof(absent[0]); i++)
        if (strlen(absent[i][0]) == klen && !strncmp(key, absent[i][0], klen)) {
            snprintf(out, size, "%s=%s", absent[i][0], absent[i][1]);
            return;
        }
    snprintf(out, size, "no %.*s", (int)klen, key);
}

/* The first key where descriptions a and b ("key=VALUE" words) differ, as
 * "key=A" into wa and "key=B" into wb: words are paired by their key (the
 * k-th vary with the k-th), not by place, since optional words (kernel,
 * continue, peak) shift the rest. */
static void first_word_difference(const char *a, const char *b, char *wa, char *wb, size_t size)
{
    for (int side = 0; side < 2; side++) {
        const char *d = side ? b : a;
        for (const char *w = d; *w; w += strspn(w, " ")) {
            const size_t len = strcspn(w, " "), klen = strcspn(w, "= ");
            int k = 0; /* this word is the k-th with its key */
            for (const char *x = d; x < w; x += strspn(x, " ")) {
                const size_t xl = strcspn(x, " ");
                k += xl > klen && x[klen] == '=' && !strncmp(x, w, klen);
                x += xl;
            }
            size_t na = 0, nb = 0;
            const char *va = description_value(a, w, klen, k, &na);
            const char *vb = description_value(b, w, klen, k, &nb);
            if (!va || !vb || na != nb || strncmp(va, vb, na)) {
                description_side(wa, size, w, klen, va, na);
                description_side(wb, size, w, klen, vb, nb);
                return;
            }
            w += len;
        }
    }
    snprintf(wa, size, "?");
    snprintf(wb, size, "?");
}

/* The overrides as one "--set A --set B" text (or "no --set"). */
static void overrides_text(json_t *arr, char *buf, size_t size)
{
    size_t used = 0, i;
    json_t *v;
    buf[0] = 0;
    json_array_foreach(arr, i, v)
        if (used < size)
            used += (size_t)snprintf(buf + used, size - used, "%s--set %s", i ? " " : "",
                                     json_string_value(v) ? json_string_value(v) : "?");
    if (!used)
        snprintf(buf, size, "no --set");
}

/* Shard b must come from the same sweep as shard a: the same springpend,
 * scene, overrides, grid and measure, and the same N. Names the first
 * difference. 0 or SP_E_INPUT. */
static int same_sweep(const struct sp_sweep_shard *a, const struct sp_sweep_shard *b)
{
    char wa[1024], wb[1024];
    const char *what = NULL;
    if (strcmp(a->version, b->version)) {
        what = "springpend's version differs";
        snprintf(wa, sizeof(wa), "%s", a->version);
        snprintf(wb, sizeof(wb), "%s", b->version);
    } else if (!json_equal(a->overrides, b->overrides)) {
        what = "the --set overrides differ";
        overrides_text(a->overrides, wa, sizeof(wa));
        overrides_text(b->overrides, wb, sizeof(wb));
    } else if (strcmp(a->scene, b->scene)) {
        what = "the scene differs";
        first_difference(a->scene, b->scene, wa, wb, sizeof(wa));
    } else if (strcmp(a->description, b->description)) {
        what = "the sweep (grid, measure or span) differs";
        first_word_difference(a->description, b->description, wa, wb, sizeof(wa));
    } else if (a->n != b->n) {
        what = "the number of shards differs";
        snprintf(wa, sizeof(wa), "%d", a->n);
        snprintf(wb, sizeof(wb), "%d", b->n);
    }
    if (!what)
        return 0;
    sp_log_error("%s" SP_CSV_METADATA_SUFFIX ": from another sweep than %s: %s "
                 "(%s: %s; %s: %s); merge only the shards of one run of 'springpend sweep "
                 "... --shard I/N'", b->path, a->path, what, a->path, wa, b->path, wb);
    return SP_E_INPUT;
}

/* A shard's CSV, from its column names to its end, must be whole: the
 * columns the sweep has, every row as the sweep writes it
 * (sp_sweep_row_check), and as many rows, and the same SHA-256 of its
 * bytes, as its metadata says. A copy cut short or edited would otherwise
 * be drawn without a word. fp is left after the column names.
 * SP_E_INPUT with FILE:LINE, or SP_E_INTERRUPTED. */
static int check_rows(struct sp_sweep_shard *s, const char *columns, const struct sp_sweep_desc *d,
                      const struct sp_scene *base, long first, long last,
                      const volatile sig_atomic_t *cancel)
{
    char line[1024], hex[65];
    struct sp_sweep_rows r = {.d = d, .base = base, .first = first, .last = last, .point = -1};
    struct sha256_ctx sha;
    long lineno = 1, at;
    const char *wrong = NULL;
    sha256_init(&sha);
    if (!fgets(line, sizeof(line), s->fp) || strcmp(line, columns))
        wrong = "not the sweep's column names";
    else
        sha256_update(&sha, strlen(line), (const uint8_t *)line);
    at = ftell(s->fp);
    while (!wrong && fgets(line, sizeof(line), s->fp)) {
        lineno++;
        if (lineno % 4096 == 0 && cancel && *cancel)
            return SP_E_INTERRUPTED;
        wrong = sp_sweep_row_check(&r, line);
        sha256_update(&sha, strlen(line), (const uint8_t *)line);
    }
    sp_digest_hex(&sha, hex);
    if (!wrong && (r.rows != s->rows || strcmp(hex, s->sha256)))
        wrong = "the rows are not those the metadata counts (dc:extent) and hashes "
                "(schema:sha256)", lineno++;
    if (!wrong && (d->measure == SP_MEASURE_LYAPUNOV || d->measure == SP_MEASURE_BASINS ||
                   d->measure == SP_MEASURE_PRECESSION) && r.rows != last - first)
        wrong = "fewer rows than the shard's points (allowed: one row per point)";
    if (!wrong) /* the last point whole, none after it missing (sweep_rows.c) */
        wrong = sp_sweep_rows_end(&r);
    if (wrong) {
        sp_log_error("%s:%ld: %s; the file was cut short or edited: write it again with "
                     "'springpend sweep ... --shard I/N --csv FILE'", s->path, lineno, wrong);
        return SP_E_INPUT;
    }
    if (ferror(s->fp) || fseek(s->fp, at, SEEK_SET) != 0) {
        sp_log_error("cannot read %s: %s", s->path, strerror(errno));
        return SP_E_INPUT;
    }
    return 0;
}

/* Opens a shard for reading: a regular file only (infile.h: a FIFO would
 * block the merge until a writer comes, a device would never end). NULL
 * after a message, *err saying whose fault (SP_E_INPUT: the file's;
 * SP_E_IO: out of descriptors or memory). */
static FILE *open_shard(const char *path, int *err)
{
    int fd = sp_infile_open(path, "give the CSV files that 'springpend sweep --shard I/N "
                                  "--csv FILE' wrote");
    FILE *fp = fd < 0 ? NULL : fdopen(fd, "r");
    *err = fd < 0 ? fd : SP_E_IO;
    if (fd >= 0 && !fp) {
        sp_log_error("cannot read %s: %s", path, strerror(errno));
        close(fd);
    }
    return fp;
}


/* Reads shard k (the first: the sweep's description, columns and scene
 * too) and checks it against the first. 0 or SP_E_*. */
static int open_one(struct sp_sweep_merge *m, int k, const struct sp_sweep_merge_desc *desc)
{
    struct sp_sweep_shard *s = &m->shards[k];
    const int n = m->n;
    int ret;
    s->path = desc->parts[k];
    if (!(s->fp = open_shard(s->path, &ret)))
        return desc->cancel && *desc->cancel ? SP_E_INTERRUPTED : ret;
    if ((ret = read_shard_meta(s)))
        return ret;
    if (k == 0) {
        snprintf(m->header, sizeof(m->header), "# springpend sweep %s", s->description);
        char *text = NULL;
        size_t size = 0;
        FILE *mem = open_memstream(&text, &size);
        struct sp_sweep_desc *d = &m->d;
        /* as springpend writes it, word for word, and in the ranges
         * its options allow: a forged "time=1e300" is refused */
        if (sp_sweep_parse_header(m->header, d) || !mem ||
            sp_sweep_write_header(mem, d, NULL) || fclose(mem) != 0 ||
            !strchr(text, '\n') ||
            strncmp(text, m->header, strlen(m->header)) || text[strlen(m->header)] != '\n' ||
            !(d->time > 0 && d->time <= 1e7) || !(d->transient >= 0 && d->transient <= DBL_MAX) ||
            !isfinite(d->energy) || !(d->dt >= 0 && d->dt <= DBL_MAX)) {
            sp_log_error("%s" SP_CSV_METADATA_SUFFIX ":1: dc:description is not a sweep's "
                         "description as springpend writes it (its words in order, "
                         "numbers as %%.17g, 0 < time <= 1e7, transient >= 0)", s->path);
            free(text);
            return SP_E_INPUT;
        }
        snprintf(m->columns, sizeof(m->columns), "%s", strchr(text, '\n') + 1);
        free(text);
        /* kept until sp_sweep_merge_close: its [view] is the figure's look
         * (title, font, sizes), as in the one-piece run */
        if (sp_provenance_scene_check(s->path, "dc:source", s->scene, strlen(s->scene)) ||
            sp_scene_parse(&m->scene, s->scene, s->path, NULL, 0))
            return SP_E_INPUT;
        sp_timeline_destroy(&m->scene.timeline); /* presentation: sweeps ignore it */
        if (s->n != n) {
            sp_log_error("%s is shard %d of %d, but %d files were given; give all %d",
                         s->path, s->i, s->n, n, s->n);
            return SP_E_INPUT;
        }
    } else if ((ret = same_sweep(&m->shards[0], s))) {
        return ret;
    }
    if (s->i < 1 || s->i > n || m->order[s->i - 1]) {
        sp_log_error("%s" SP_CSV_METADATA_SUFFIX ": shard %d/%d is given twice or out of "
                     "range", s->path, s->i, s->n);
        return SP_E_INPUT;
    }
    m->order[s->i - 1] = s;
    const long points = sp_sweep_points(&m->d);
    return check_rows(s, m->columns, &m->d, &m->scene, points * (s->i - 1) / n,
                      points * s->i / n, desc->cancel);
}

int sp_sweep_merge_open(struct sp_sweep_merge *m, const struct sp_sweep_merge_desc *desc)
{
    int ret = 0;
    memset(m, 0, sizeof(*m));
    m->n = desc->n_parts;
    m->shards = calloc((size_t)m->n, sizeof(*m->shards));
    m->order = calloc((size_t)m->n, sizeof(*m->order));
    if (!m->shards || !m->order) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    sp_scene_defaults(&m->scene);
    for (int k = 0; !ret && k < m->n; k++)
        ret = open_one(m, k, desc);
    if (!ret) { /* the shards' overrides, which the whole's scene has applied */
        size_t i;
        json_t *v;
        json_array_foreach(m->shards[0].overrides, i, v)
            if (m->n_overrides < SP_SWEEP_MERGE_MAX_OVERRIDES && json_string_value(v))
                m->overrides[m->n_overrides++] = json_string_value(v);
        m->command = member(m->shards[0].meta, "prov:wasGeneratedBy");
        m->command_path = m->shards[0].path;
        m->command_shard = m->shards[0].i;
    }
    return ret;
}

void sp_sweep_merge_write(struct sp_sweep_merge *m, FILE *out)
{
    static char buf[1 << 16];
    fprintf(out, "%s\n%s", m->header, m->columns);
    for (int i = 0; i < m->n; i++) { /* the rows after the column names */
        size_t got;
        while ((got = fread(buf, 1, sizeof(buf), m->order[i]->fp)) > 0)
            fwrite(buf, 1, got, out);
    }
}

void sp_sweep_merge_close(struct sp_sweep_merge *m)
{
    sp_scene_free(&m->scene);
    for (int k = 0; m->shards && k < m->n; k++) {
        if (m->shards[k].fp)
            fclose(m->shards[k].fp);
        json_decref(m->shards[k].meta);
    }
    free(m->shards);
    free(m->order);
    m->shards = NULL;
    m->order = NULL;
}
