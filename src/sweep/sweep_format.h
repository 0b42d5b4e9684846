/* springpend (internal): a sweep's numbers without a figure.
 * Shared with: cli. */
#ifndef SPRINGPEND_SWEEP_FORMAT_H
#define SPRINGPEND_SWEEP_FORMAT_H

#include <stdio.h>

/* Writes the sweep CSV in rows (read from its start) to out: as it is
 * (json = 0), or as one JSON object (json = 1): the description, "columns",
 * "rows" (arrays of numbers, NaN as null; a spectrum's last row per point,
 * with all of them in "running"), and for a basin map "attractors" (label,
 * period, winding, representative state, points, fraction), "labels" (each
 * grid point's attractor index in the grid's order, -1: blown up), "basin_entropy"
 * and "boundary_basin_entropy" (nats). name: for messages. Returns 0,
 * SP_E_INPUT or SP_E_IO. */
int sp_sweep_print(FILE *rows, const char *name, int json, FILE *out);

/* A basin map's legend (its attractors, their fractions, S_b and S_bb) as
 * lines on out; nothing for other sweeps. */
void sp_sweep_print_legend(FILE *rows, FILE *out);

#endif
