/* springpend: a CSV's metadata file, W3C CSV on the Web (csv_metadata.h).
 * jansson builds and writes the JSON. */
#include <errno.h>
#include <jansson.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/command_line.h"
#include "base/utf8.h"
#include "springpend/common.h"
#include "springpend/csv_metadata.h"
#include "springpend/environment.h"
#include "springpend/infile.h"

/* A JSON string of s, which JSON holds to UTF-8: a byte that is not
 * (a file name in Latin-1) becomes U+FFFD. NULL when out of memory. */
static json_t *text(const char *s)
{
    json_t *j = json_string(s);
    if (j)
        return j;
    char *copy = malloc(3 * strlen(s) + 1), *o = copy;
    if (!copy)
        return NULL;
    while (*s) {
        const size_t n = sp_utf8_char(s);
        if (n) {
            memcpy(o, s, n), o += n, s += n;
        } else {
            memcpy(o, "\xef\xbf\xbd", 3), o += 3, s++;
        }
    }
    *o = 0;
    j = json_string(copy);
    free(copy);
    return j;
}

/* The CSV's file name as CSV on the Web resolves `url`: a URL relative to
 * the metadata file (W3C tabular metadata, 5.3), so every byte but RFC
 * 3986's unreserved ones is percent-encoded ("run #3.csv" is
 * "run%20%233.csv"; a name that is not UTF-8 stays exact). */
static json_t *url_of(const char *name)
{
    static const char hex[] = "0123456789ABCDEF";
    size_t n = strlen(name);
    char *u = malloc(3 * n + 1), *o = u;
    if (!u)
        return NULL;
    for (const unsigned char *p = (const unsigned char *)name; *p; p++)
        if ((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') ||
            strchr("-._~", *p))
            *o++ = (char)*p;
        else
            *o++ = '%', *o++ = hex[*p >> 4], *o++ = hex[*p & 15];
    *o = 0;
    json_t *j = json_string(u);
    free(u);
    return j;
}

/* The command line into obj: every word as given (its -o too), shown as
 * every other record shows it (command_line.h: a byte that is not UTF-8 as
 * \xNN, not replaced). 0 or SP_E_NOMEM. */
static int add_command(json_t *obj)
{
    char *line = sp_command_line_whole();
    int err = !line || json_object_set_new(obj, "prov:wasGeneratedBy", json_string(line));
    free(line);
    return err ? SP_E_NOMEM : 0;
}

/* dc:source of a side-by-side CSV: every scene's text, first to last
 * (NULL when out of memory). */
static json_t *sources(const char *first, const struct sp_csv_meta *m)
{
    json_t *all = json_array();
    int err = !all || json_array_append_new(all, text(first));
    for (int i = 0; !err && i < m->n_more; i++) {
        char *ini = sp_scene_ini(&m->more[i]);
        err = !ini || json_array_append_new(all, text(ini));
        free(ini);
    }
    if (err) {
        json_decref(all);
        return NULL;
    }
    return all;
}

static json_t *build(const char *csv_target, const struct sp_csv_meta *m)
{
    const char *base = strrchr(csv_target, '/');
    char env[SP_ENVIRONMENT_MAX];
    char *scene = sp_scene_ini(m->scene);
    json_t *root = json_object(), *schema = json_object(), *columns = json_array(),
           *used = json_array();
    int err = !scene || !root || !schema || !columns || !used;
    for (int i = 0; !err && i < m->n_columns; i++) {
        const struct sp_csv_column *c = &m->columns[i];
        err = json_array_append_new(columns, json_pack("{s:s, s:s, s:s, s:s, s:s}",
                                                       "name", c->name, "titles", c->name,
                                                       "dc:description", c->title,
                                                       "datatype", "double",
                                                       "schema:unitText", c->unit));
    }
    for (int i = 0; !err && i < m->n_overrides; i++)
        err = json_array_append_new(used, text(m->overrides[i]));
    sp_environment_numbers(env, sizeof(env));
    err = err || json_object_set_new(root, "@context", json_string("http://www.w3.org/ns/csvw")) ||
          json_object_set_new(root, "url", url_of(base ? base + 1 : csv_target)) ||
          json_object_set_new(root, "dc:title", text(m->title)) ||
          (m->description &&
           json_object_set_new(root, "dc:description", text(m->description))) ||
          json_object_set_new(root, "dc:creator", json_string("springpend " SP_VERSION)) ||
          json_object_set_new(root, "schema:softwareVersion", json_string(SP_VERSION)) ||
          add_command(root) || json_object_set(root, "prov:used", used) ||
          json_object_set_new(root, "dc:source", m->n_more ? sources(scene, m) : text(scene)) ||
          json_object_set_new(root, "schema:runtimePlatform", text(env)) ||
          (m->shard && (json_object_set_new(root, "schema:position", json_string(m->shard)) ||
                        json_object_set_new(root, "dc:extent", json_integer(m->rows)) ||
                        json_object_set_new(root, "schema:sha256", json_string(m->sha256)))) ||
          json_object_set(schema, "columns", columns) ||
          json_object_set(root, "tableSchema", schema);
    free(scene);
    json_decref(schema);
    json_decref(columns);
    json_decref(used);
    if (err) {
        json_decref(root);
        return NULL;
    }
    return root;
}

int sp_csv_metadata_write(struct sp_outfile *f, const char *csv_target,
                          const struct sp_csv_meta *m)
{
    *f = (struct sp_outfile){.fd = -1, .slot = -1};
    if (sp_outfile_is_stream(csv_target))
        return 0;
    char *path = NULL, *text = NULL;
    json_t *root = build(csv_target, m);
    if (root)
        text = json_dumps(root, JSON_INDENT(2) | JSON_PRESERVE_ORDER);
    json_decref(root);
    if (!text || asprintf(&path, "%s" SP_CSV_METADATA_SUFFIX, csv_target) < 0) {
        free(text);
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    int ret = sp_outfile_open(f, path, 0);
    size_t n = strlen(text), done = 0;
    text[n++] = '\n'; /* json_dumps leaves no newline; its NUL becomes one */
    while (!ret && done < n) {
        ssize_t w = write(f->fd, text + done, n - done);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            sp_log_error("cannot write %s: %s", f->path, strerror(errno));
            sp_outfile_discard(f);
            ret = SP_E_IO;
        } else {
            done += (size_t)w;
        }
    }
    free(path);
    free(text);
    return ret;
}

json_t *sp_csv_metadata_load(const char *csv_path, int *err)
{
    json_error_t e;
    char *path = NULL, *bytes = NULL;
    size_t size = 0;
    int read_err = 0;
    *err = SP_E_INPUT;
    if (asprintf(&path, "%s" SP_CSV_METADATA_SUFFIX, csv_path) < 0) {
        sp_log_error("out of memory");
        *err = SP_E_NOMEM;
        return NULL;
    }
    /* a regular file, bounded: a FIFO there must not hang the reader, nor
     * a forged file of gigabytes fill its memory */
    json_t *root = NULL;
    if (access(path, F_OK) != 0 && errno == ENOENT)
        sp_log_error("%s: no such file; springpend writes it beside every CSV file it writes "
                     "(data, sweep --csv), and reads the scene and the columns from it",
                     path);
    else if (!(read_err = sp_infile_read(path, SP_CSV_METADATA_MAX, "the metadata springpend "
                                         "writes beside a CSV is a file", &bytes, &size)) &&
             !(root = json_loadb(bytes, size, JSON_REJECT_DUPLICATES, &e))) {
        /* jansson quotes the token it stopped at ("near 'root'"): from a file
         * linked there (/etc/shadow) or forged (terminal escapes), it is not
         * for the terminal: the line and what was expected say enough */
        char *near = strstr(e.text, " near '");
        if (near)
            *near = 0;
        sp_log_error("%s:%d: %s; springpend writes it beside %s", path, e.line < 1 ? 1 : e.line,
                     e.text, csv_path);
    }
    if (root && !json_is_object(root)) {
        sp_log_error("%s:1: not a JSON object; springpend writes it beside %s", path, csv_path);
        json_decref(root);
        root = NULL;
    }
    if (!root && read_err)
        *err = read_err; /* out of descriptors or memory, or interrupted */
    free(bytes);
    free(path);
    return root;
}
