/* springpend (internal): the words for a simulation that failed. The sim (sim.h) only
 * records what went wrong; the command that ran it says so here.
 * Shared with: cli, frame, pipeline (each words the blow-up of the sim it
 * ran). */
#ifndef SPRINGPEND_SIM_REPORT_H
#define SPRINGPEND_SIM_REPORT_H

#include "springpend/sim.h"

/* After sp_sim_advance returned SP_E_UNSTABLE: prints on stderr when, where
 * (the state), the energy against t = 0 and the work of damping and drive,
 * then a fix: a smaller tolerance (adaptive methods), or a step the run was
 * seen to complete with (fixed-step ones, found by sp_advise_dt). */
void sp_sim_explain(const struct sp_sim *sim);

#endif
