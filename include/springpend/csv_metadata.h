/* springpend: what a CSV holds, beside it. Every CSV springpend writes to a
 * file is plain RFC 4180 text, one header line of column names then rows,
 * with no comment lines, so any reader takes it with no options; what the
 * columns mean and where the numbers came from is in NAME.csv-metadata.json
 * beside it, after W3C's "CSV on the Web" (Metadata Vocabulary for Tabular
 * Data): the "@context", the CSV's "url", "dc:title" and a "tableSchema"
 * whose "columns" give each column's "name", "titles", "datatype" and unit
 * ("schema:unitText"; "1" for a pure number), plus provenance as common
 * properties:
 *   "dc:creator"             "springpend 0.1.0"
 *   "schema:softwareVersion" "0.1.0"
 *   "prov:wasGeneratedBy"    the command line (command_line.h's text)
 *   "prov:used"              the --set overrides, in order
 *   "dc:source"              the effective scene as a scene file
 *                            (sp_scene_write_ini: user units, names)
 *   "schema:runtimePlatform" environment.h's text (library versions, fonts)
 *   "dc:description"         what the rows are (a sweep: its description)
 *   "schema:position"        a sweep shard's "I/N" (shards only)
 *   "dc:extent", "schema:sha256"  a shard's rows and the SHA-256 of its
 *                            CSV's bytes, so a merge refuses a copy cut
 *                            short or edited (shards only)
 * A CSV written to stdout or another stream has no metadata file. */
#ifndef SPRINGPEND_CSV_METADATA_H
#define SPRINGPEND_CSV_METADATA_H

#include "springpend/outfile.h"
#include "springpend/scene.h"

struct sp_csv_column {
    const char *name;  /* as in the CSV's header line */
    const char *title; /* what it is, in words */
    const char *unit;  /* "s", "m/s", "rad", "1" (a pure number or count) */
};

struct sp_csv_meta {
    const char *title;                 /* dc:title */
    const char *description;           /* dc:description; NULL = none */
    const struct sp_scene *scene;      /* dc:source */
    const struct sp_scene *more;       /* side by side: scenes 2 .. 1 + n_more;
                                          dc:source is then an array of them all */
    int n_more;
    const char *const *overrides;      /* prov:used */
    int n_overrides;
    const struct sp_csv_column *columns;
    int n_columns;
    const char *shard;                 /* "I/N"; NULL = not a shard */
    long rows;                         /* shards: rows after the header */
    const char *sha256;                /* shards: of the CSV's bytes, hex */
};

#define SP_CSV_METADATA_SUFFIX "-metadata.json"

/* Writes the metadata of the CSV that will appear at csv_target into
 * f's .part (csv_target + SP_CSV_METADATA_SUFFIX), for the caller to commit
 * together with the CSV (the metadata first) or discard. A stream target
 * (stdout, a FIFO) gets none: *f is left closed. Returns 0, SP_E_IO or
 * SP_E_NOMEM (logged). */
int sp_csv_metadata_write(struct sp_outfile *f, const char *csv_target,
                          const struct sp_csv_meta *m);

/* The most bytes of metadata read: what springpend writes is a few KiB
 * plus the scene (at most SP_PROVENANCE_SCENE_MAX, 256 KiB, up to six
 * bytes a character once escaped). */
#define SP_CSV_METADATA_MAX (2u << 20)

/* Reads csv_path + SP_CSV_METADATA_SUFFIX: a JSON object (jansson's
 * json_t; json_decref it), or NULL after "FILE:LINE: what is wrong" with
 * *err the SP_E_* code (SP_E_INPUT: the file's fault; SP_E_IO: out of
 * descriptors; SP_E_NOMEM). A FIFO, device or folder there is refused at
 * once, and a file over SP_CSV_METADATA_MAX unread (infile.h). */
struct json_t *sp_csv_metadata_load(const char *csv_path, int *err);

#endif
