/* springpend: the data export, the engine behind `springpend data`: the
 * motion as CSV, one row per sample (at the frame times, or every `every`
 * simulated seconds), or the Poincare section's crossings, with its
 * CSV-metadata.json beside it (csv_metadata.h). Commands fill a desc and
 * call it; nothing here parses arguments or checks limits. */
#ifndef SPRINGPEND_DATA_EXPORT_H
#define SPRINGPEND_DATA_EXPORT_H

#include <signal.h>

#include "springpend/scene.h"

struct sp_data_desc {
    const struct sp_scene *scenes; /* 1 to 4; several: each scene's rows in
                                      turn, each row led by its name */
    int n_scenes;
    const char *const *names;      /* the scene column, one per scene (used
                                      when n_scenes > 1), as it is written */
    const char *const *overrides;  /* the --set overrides, for the metadata */
    int n_overrides;
    double every;                  /* simulated s between rows; <= 0: the
                                      frame times */
    int poincare;                  /* 1: the crossings theta = 0, dtheta/dt > 0
                                      (one planar scene) instead of samples */
    const char *output;            /* the CSV's path, "-" = stdout; a stream
                                      gets no metadata file */
    double t_end;                  /* simulated s the longest scene runs to:
                                      the progress line's end */
    int quiet;                     /* 1: no progress line, no 'wrote' line */
    const volatile sig_atomic_t *cancel; /* the caller's stop flag (NULL =
                                            never): stops with
                                            SP_E_INTERRUPTED, nothing kept */
};

/* Integrates each scene and writes the CSV (whole or not at all: a .part
 * renamed into place, the metadata first) and its metadata. Messages on
 * stderr. 0, SP_E_IO, SP_E_UNSTABLE (explained), SP_E_NOMEM or
 * SP_E_INTERRUPTED. */
int sp_data_run(const struct sp_data_desc *d);

#endif
