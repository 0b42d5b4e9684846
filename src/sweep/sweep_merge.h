/* springpend (internal): the merge of a sweep's shards (sweep --merge). The
 * CSVs that `springpend sweep ... --shard I/N --csv FILE` wrote, each with
 * its FILE-metadata.json, are read and checked: every shard from the same
 * sweep (springpend's version, scene, overrides, grid, measure and N), each
 * once, and each whole (its rows as the sweep writes them, as many and
 * with the SHA-256 its metadata records). The whole's rows, in the grid's
 * order, are then written as one sweep's rows; the command draws and
 * writes them as it does a sweep's own.
 * Shared with: cli. */
#ifndef SPRINGPEND_SWEEP_MERGE_H
#define SPRINGPEND_SWEEP_MERGE_H

#include <signal.h>
#include <stdio.h>

#include "springpend/scene.h"
#include "sweep.h"

#define SP_SWEEP_MERGE_MAX_OVERRIDES 64 /* the shards' --set, as the command takes */

struct sp_sweep_merge_desc {
    const char *const *parts; /* the shards' CSV paths, n_parts of them */
    int n_parts;
    const volatile sig_atomic_t *cancel; /* the caller's stop flag (NULL =
                                            never): reading stops with
                                            SP_E_INTERRUPTED */
};

struct sp_sweep_shard;

/* The shards, once read and checked. */
struct sp_sweep_merge {
    struct sp_sweep_desc d;   /* the sweep, from the shards' description */
    struct sp_scene scene;    /* its scene (dc:source), overrides applied */
    const char *overrides[SP_SWEEP_MERGE_MAX_OVERRIDES]; /* the shards' --set
                                                            (into their metadata) */
    int n_overrides;
    const char *command;      /* the first shard's prov:wasGeneratedBy (the command
                                 a merged figure records, less its --shard and
                                 --csv: command_line.h, once the caller has checked
                                 it against the shard); NULL = none */
    const char *command_path; /* the shard it is from (its CSV) */
    int command_shard;        /* that shard's I (schema:position I/N) */
    char header[1100];        /* "# springpend sweep DESCRIPTION" */
    char columns[1024];       /* the column names' line, "\n"-ended */
    struct sp_sweep_shard *shards, **order; /* as given; by I */
    int n;
};

/* Opens and checks every shard of desc into *m. Messages name the file and
 * what is wrong (FILE:LINE where a line is). 0, SP_E_INPUT, SP_E_NOMEM or
 * SP_E_INTERRUPTED; sp_sweep_merge_close in every case. */
int sp_sweep_merge_open(struct sp_sweep_merge *m, const struct sp_sweep_merge_desc *desc);

/* Writes the whole's description line, column names and every shard's rows
 * in the grid's order to out (unchecked: the caller flushes and checks). */
void sp_sweep_merge_write(struct sp_sweep_merge *m, FILE *out);

/* Closes the shards and frees what open kept; m's scene and overrides are
 * gone after. */
void sp_sweep_merge_close(struct sp_sweep_merge *m);

#endif
