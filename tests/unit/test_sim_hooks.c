/* springpend tests: the sim is pure. It stops when its caller's cancel flag
 * is set, reports progress through its caller's callback, and on a blow-up
 * records what and where in sim->failure without writing a byte to stderr
 * (the caller words it: sim_report.c). */
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/sim.h"
#include "tap.h"

struct seen {
    int calls, backwards;
    double last_t, first_t;
};

static void on_progress(void *ctx, double t)
{
    struct seen *s = ctx;
    if (!s->calls++)
        s->first_t = t;
    else if (t < s->last_t)
        s->backwards++;
    s->last_t = t;
}

int main(void)
{
    struct sp_scene sc;
    struct sp_sim sim;

    /* cancel: a flag already set stops the first step; cleared, the run
     * goes on from where it stood */
    sp_scene_defaults(&sc);
    sp_sim_init(&sim, &sc);
    sp_tap_ok(!sim.cancel && !sim.progress, "sp_sim_init leaves no cancel flag or callback");
    volatile sig_atomic_t flag = 1;
    sim.cancel = &flag;
    int ret = sp_sim_advance(&sim, 1.0);
    sp_tap_ok(ret == SP_E_INTERRUPTED && sim.s.t < 1.0,
              "a set cancel flag stops sp_sim_advance with SP_E_INTERRUPTED (ret %d, t %g)",
              ret, sim.s.t);
    flag = 0;
    ret = sp_sim_advance(&sim, 1.0);
    sp_tap_ok(ret == 0 && sim.s.t == 1.0, "cleared, it reaches t = 1 s (ret %d)", ret);

    /* progress: after each checked step (the fixed-step methods check every
     * few steps), with times that grow to the target */
    struct seen seen = {0};
    sp_sim_init(&sim, &sc);
    sim.progress = on_progress;
    sim.progress_ctx = &seen;
    ret = sp_sim_advance(&sim, 2.0);
    sp_tap_ok(ret == 0 && seen.calls >= 100 && !seen.backwards &&
              seen.first_t > 0 && fabs(seen.last_t - 2.0) < 1e-9,
              "the progress callback sees every step up to t = 2 s (ret %d, %d calls, %.17g .. %.17g s, dt %g)", ret,
              seen.calls, seen.first_t, seen.last_t, sc.integrator.dt);

    /* a blow-up (verlet at 10x its stability limit): recorded, not printed */
    sc.integrator.method = SP_METHOD_VERLET;
    sc.integrator.dt = 0.5;
    sp_sim_init(&sim, &sc);
    char path[] = "/tmp/springpend-sim-hooks-XXXXXX";
    int fd = mkstemp(path), saved = dup(2);
    fflush(stderr);
    dup2(fd, 2);
    ret = sp_sim_advance(&sim, 60.0);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    struct stat st;
    fstat(fd, &st);
    close(fd);
    unlink(path);
    sp_tap_ok(ret == SP_E_UNSTABLE, "dt = 0.5 s with verlet is unstable (ret %d)", ret);
    sp_tap_ok(st.st_size == 0, "the sim wrote nothing to stderr (%lld bytes)", (long long)st.st_size);
    sp_tap_ok(sim.failure.what[0] && sim.failure.s.t > 0 && sim.failure.s.t <= 60.0 &&
              sim.failure.s.t == sim.s.t,
              "sim->failure says what (\"%s\") and when (t = %g s, the last state checked)",
              sim.failure.what, sim.failure.s.t);
    return sp_tap_done();
}
