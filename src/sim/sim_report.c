/* springpend: the words for a simulation that failed (sim_report.h). */
#include <math.h>
#include <stdio.h>

#include "springpend/advice.h"
#include "springpend/common.h"
#include "sim_report.h"

/* The words for sp_advise_failed_at_pass, and the method that completes the run. */
static void explain_pass(const struct sp_sim *sim)
{
    const struct sp_state *s = &sim->failure.s;
    const double d = sim->failure.pass_distance, v = sim->failure.pass_speed;
    const double t_end = fmax(sim->scene->video.duration, s->t);
    double checked;
    sp_log_error("the run lost accuracy at t = %.6g s, passing close by the pivot (%s): "
                 "x = %.6g m, y = %.6g m, vx = %.6g m/s, vy = %.6g m/s, "
                 "energy %.6g J vs %.6g J at t = 0 (%.6g J of it work by damping "
                 "and drive)",
                 s->t, sim->failure.what, s->x, s->y, s->vx, s->vy, sim->failure.energy,
                 sim->energy0, sim->work);
    fprintf(stderr, "  not a blow-up: the bob passed %.3g m from the pivot at %.3g m/s, where "
            "the spring's push turns round within %.2g s, less than dt = %g s; a fixed step "
            "follows a pass only when shorter than that, so each closer pass cost it some "
            "energy, and the losses added up past the guard's %g%%\n",
            d, v, d / v, sim->dt, 100 * sim->drift_limit);
    int ret = sp_advise_adaptive(sim->scene, t_end, sim->cancel, &checked);
    if (ret == 0)
        fprintf(stderr, "  use integrator.method = dop853: its steps shrink at each pass (the "
                "run completes with it over [0, %g] s)\n", checked);
    else
        fprintf(stderr, "  use integrator.method = dop853 with a smaller integrator.tolerance: "
                "its steps shrink at each pass\n");
}

void sp_sim_explain(const struct sp_sim *sim)
{
    const struct sp_method_info *mi = sp_method_info(sim->method);
    const struct sp_state *s = &sim->failure.s;
    struct sp_dt_advice a;
    const double t_end = fmax(sim->scene->video.duration, s->t);
    if (sp_advise_failed_at_pass(sim)) {
        explain_pass(sim);
        return;
    }
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
    else if (sp_advise_dt(sim->scene, t_end, sim->cancel, &a) == 0 && !isnan(a.safe)) {
        fprintf(stderr, "  dt = %g s is too coarse for this motion (it reaches omega_max = "
                "%.4g rad/s, where %s's stability limit is %.3g s); ", sim->dt, a.omega_max,
                mi->name, a.limit);
        /* a step too small to check the whole run, or held down by close
         * passes by the pivot (a closer one may come): dop853 first, if it
         * completes */
        double checked;
        if ((a.checked < t_end || a.pass_bound) &&
            sp_advise_adaptive(sim->scene, t_end, sim->cancel, &checked) == 0 && checked >= t_end)
            fprintf(stderr, "use integrator.method = dop853 (the run completes with it over "
                    "[0, %g] s) or integrator.dt = %g (%s [0, %g] s%s)\n", checked, a.safe,
                    a.checked < t_end ? "checked over" : "it completes the run over", a.checked,
                    a.checked < t_end ? " only" : ", held down by close passes by the pivot");
        else
            fprintf(stderr, "use integrator.dt = %g (the run completes with it over [0, %g] "
                    "s) or integrator.method = dop853\n", a.safe, a.checked);
    } else
        fprintf(stderr, "  dt = %g s is too coarse for this motion; use integrator.method = "
                "dop853\n", sim->dt);
}
