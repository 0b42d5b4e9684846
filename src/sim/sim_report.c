/* springpend: the words for a simulation that failed (sim_report.h). */
#include <math.h>
#include <stdio.h>

#include "springpend/advice.h"
#include "springpend/common.h"
#include "sim_report.h"

void sp_sim_explain(const struct sp_sim *sim)
{
    const struct sp_method_info *mi = sp_method_info(sim->method);
    const struct sp_state *s = &sim->failure.s;
    struct sp_dt_advice a;
    sp_log_error("the simulation became unstable at t = %.6g s (%s): "
                 "x = %.6g m, y = %.6g m, vx = %.6g m/s, vy = %.6g m/s, "
                 "energy %.6g J vs %.6g J at t = 0 (%.6g J of it work by damping "
                 "and drive)",
                 s->t, sim->failure.what, s->x, s->y, s->vx, s->vy, sim->failure.energy,
                 sim->energy0, sim->work);
    if (mi->adaptive)
        fprintf(stderr, "  %s with tolerance %g cannot follow this motion; try "
                "integrator.tolerance = %g\n", mi->name, sim->tol, sim->tol * 1e-3);
    /* a step suggested is one the run was seen to complete with */
    else if (sp_advise_dt(sim->scene, fmax(sim->scene->video.duration, s->t), &a) == 0 &&
             !isnan(a.safe))
        fprintf(stderr, "  dt = %g s is too coarse for this motion (it reaches omega_max = "
                "%.4g rad/s, where %s's stability limit is %.3g s); use integrator.dt = %g "
                "(the run completes with it over [0, %g] s) or integrator.method = dop853\n",
                sim->dt, a.omega_max, mi->name, a.limit, a.safe, a.checked);
    else
        fprintf(stderr, "  dt = %g s is too coarse for this motion; use integrator.method = "
                "dop853\n", sim->dt);
}
