/* springpend: a sweep's numbers on a stream (see sweep_format.h): the CSV as
 * it is, or JSON (RFC 8259; NaN, which JSON lacks, as null). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis.h"
#include "springpend/common.h"
#include "sweep_format.h"

/* A JSON string of s (the keys and names are plain words; escaped anyway). */
static void json_string(FILE *out, const char *s)
{
    fputc('"', out);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(out, "\\%c", c);
        else if (c < 0x20)
            fprintf(out, "\\u%04x", c);
        else
            fputc(c, out);
    }
    fputc('"', out);
}

static void json_number(FILE *out, double v)
{
    if (isfinite(v))
        fprintf(out, "%.10g", v);
    else
        fputs("null", out);
}

/* One CSV row as a JSON array of numbers; returns the fields read. */
static int json_row(FILE *out, const char *line)
{
    const char *p = line;
    char *end;
    int n = 0;
    fputc('[', out);
    for (;;) {
        double v = strtod(p, &end);
        if (end == p)
            break;
        fputs(n++ ? ", " : "", out);
        json_number(out, v);
        if (*end != ',')
            break;
        p = end + 1;
    }
    fputc(']', out);
    return n;
}

/* The point number at the start of a row. */
static long row_point(const char *line)
{
    return strtol(line, NULL, 10);
}

static void basins_json(FILE *out, FILE *rows, long at, const struct sp_sweep_desc *d)
{
    struct sp_basin_map map;
    fseek(rows, at, SEEK_SET);
    if (sp_basins_read(rows, d, &map))
        return;
    long all = 0;
    for (int a = 0; a < map.n_attractors; a++)
        all += map.att[a].count;
    fputs(",\n  \"attractors\": [", out);
    for (int a = 0; a < map.n_attractors; a++) {
        const struct sp_attractor *t = &map.att[a];
        fputs(a ? ",\n    {" : "\n    {", out);
        fprintf(out, "\"index\": %d, \"label\": ", a);
        json_string(out, t->label);
        fprintf(out, ", \"period\": %d, \"winding\": %d, \"theta\": ", t->period, t->winding);
        json_number(out, t->theta);
        fputs(", \"r\": ", out);
        json_number(out, t->r);
        fputs(", \"theta_dot\": ", out);
        json_number(out, t->theta_dot);
        fputs(", \"r_dot\": ", out);
        json_number(out, t->r_dot);
        fprintf(out, ", \"points\": %ld, \"fraction\": ", t->count);
        json_number(out, all ? (double)t->count / all : NAN);
        fputc('}', out);
    }
    fputs("\n  ],\n  \"labels\": [", out); /* each point's attractor, -1: blown up */
    for (long p = 0; p < (long)map.nx * map.ny; p++)
        fprintf(out, "%s%d", p ? (p % map.nx ? ", " : ",\n    ") : "\n    ", map.label[p]);
    /* entropy_boxes: whole 5x5 boxes along each key (the rest of the grid
     * left out); basin_entropy null when there is none */
    fprintf(out, "\n  ],\n  \"blown_up\": %ld,\n  \"entropy_box\": %d,\n  \"entropy_boxes\": "
            "[%d, %d],\n  \"basin_entropy\": ", map.blown_up, map.box, map.boxes_x, map.boxes_y);
    json_number(out, map.entropy);
    fputs(",\n  \"boundary_basin_entropy\": ", out);
    json_number(out, map.boundary_entropy);
    sp_basins_free(&map);
}

int sp_sweep_print(FILE *rows, const char *name, int json, FILE *out)
{
    char line[1024];
    struct sp_sweep_desc d;
    rewind(rows);
    if (!fgets(line, sizeof(line), rows) || (line[strcspn(line, "\n")] = 0, 0) ||
        sp_sweep_parse_header(line, &d)) {
        sp_log_error("%s:1: not a sweep CSV", name);
        return SP_E_INPUT;
    }
    if (!json) { /* plain CSV: the column names, the rows (no description) */
        size_t got;
        while ((got = fread(line, 1, sizeof(line), rows)) > 0)
            fwrite(line, 1, got, out);
        return ferror(rows) ? SP_E_IO : 0;
    }
    if (!fgets(line, sizeof(line), rows)) /* the column names */
        return SP_E_INPUT;
    line[strcspn(line, "\n")] = 0;
    long at = ftell(rows);
    fputs("{\n  \"scene\": ", out);
    json_string(out, d.scene);
    fputs(",\n  \"measure\": ", out);
    json_string(out, sp_sweep_measure_name(d.measure));
    fputs(",\n  \"time\": ", out);
    json_number(out, d.time);
    fputs(",\n  \"transient\": ", out);
    json_number(out, d.transient);
    fputs(",\n  \"method\": ", out);
    json_string(out, d.method);
    fputs(",\n  \"dt\": ", out);
    json_number(out, d.dt);
    fputs(",\n  \"vary\": [", out);
    for (int a = 0; a < d.n_axes; a++) {
        fputs(a ? ", {\"key\": " : "{\"key\": ", out);
        json_string(out, d.axis[a].key);
        fprintf(out, ", \"from\": %.17g, \"to\": %.17g, \"count\": %d}", d.axis[a].from,
                d.axis[a].to, d.axis[a].count);
    }
    fputs("],\n  \"columns\": [", out);
    char *save = NULL;
    int nc = 0;
    for (char *w = strtok_r(line, ",", &save); w; w = strtok_r(NULL, ",", &save)) {
        fputs(nc++ ? ", " : "", out);
        json_string(out, w);
    }
    /* a spectrum's rows are running values: "rows" holds each point's last
     * (T = time), "running" all of them */
    const int spectrum = d.measure == SP_MEASURE_SPECTRUM;
    for (int pass = 0; pass < 1 + spectrum; pass++) {
        fseek(rows, at, SEEK_SET);
        fputs(pass ? "],\n  \"running\": [" : "],\n  \"rows\": [", out);
        int first = 1;
        char next[1024];
        int have = fgets(line, sizeof(line), rows) != NULL;
        while (have) {
            have = fgets(next, sizeof(next), rows) != NULL;
            if (!spectrum || pass || !have || row_point(next) != row_point(line)) {
                fputs(first ? "\n    " : ",\n    ", out);
                json_row(out, line);
                first = 0;
            }
            memcpy(line, next, sizeof(line));
        }
        fputs(first ? "" : "\n  ", out);
    }
    fputc(']', out);
    if (d.measure == SP_MEASURE_BASINS)
        basins_json(out, rows, at, &d);
    fputs("\n}\n", out);
    return ferror(rows) ? SP_E_IO : 0;
}

void sp_sweep_print_legend(FILE *rows, FILE *out)
{
    char line[1024];
    struct sp_sweep_desc d;
    struct sp_basin_map map;
    rewind(rows);
    if (!fgets(line, sizeof(line), rows) || (line[strcspn(line, "\n")] = 0, 0) ||
        sp_sweep_parse_header(line, &d) || d.measure != SP_MEASURE_BASINS ||
        !fgets(line, sizeof(line), rows) || sp_basins_read(rows, &d, &map))
        return;
    long all = 0;
    for (int a = 0; a < map.n_attractors; a++)
        all += map.att[a].count;
    for (int a = 0; a < map.n_attractors; a++)
        fprintf(out, "attractor %d: %s: %.2f%% of the map\n", a, map.att[a].label,
                all ? 100.0 * map.att[a].count / all : 0.0);
    char how[200];
    sp_basins_box_text(&map, how, sizeof(how));
    if (isfinite(map.entropy))
        fprintf(out, "basin entropy S_b = %.4f, boundary basin entropy S_bb = %.4f (nats, %s)\n",
                map.entropy, map.boundary_entropy, how);
    else
        fprintf(out, "basin entropy S_b, boundary basin entropy S_bb: %s\n", how);
    sp_basins_free(&map);
}
