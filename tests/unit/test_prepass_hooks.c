/* springpend tests: the camera pre-passes take their caller's hooks like the
 * sim does. sp_view_extent_measure stops on the cancel flag it is handed and
 * reports progress through the callback it is handed; sp_ensemble_make's
 * pre-pass stops on its caller's flag and reports its progress too. Neither reads the process-wide
 * signal flag (no signal is raised here). */
#include <math.h>
#include <signal.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/ensemble.h"
#include "springpend/frame.h"
#include "tap.h"

struct seen {
    int calls, backwards;
    double last_t;
    void *ctx;
};

static void on_progress(void *ctx, double t)
{
    struct seen *s = ctx;
    if (s->calls++ && t < s->last_t)
        s->backwards++;
    s->last_t = t;
    s->ctx = ctx;
}

int main(void)
{
    struct sp_scene sc;
    struct sp_view_extent e;
    sp_scene_defaults(&sc);

    volatile sig_atomic_t flag = 1;
    int ret = sp_view_extent_measure(&sc, 2.0, &flag, NULL, NULL, &e);
    sp_tap_ok(ret == SP_E_INTERRUPTED,
              "a set cancel flag stops sp_view_extent_measure with SP_E_INTERRUPTED (ret %d)", ret);

    struct seen seen = {0};
    flag = 0;
    ret = sp_view_extent_measure(&sc, 2.0, &flag, on_progress, &seen, &e);
    sp_tap_ok(ret == 0 && seen.calls >= 100 && !seen.backwards && seen.ctx == &seen &&
              fabs(seen.last_t - 2.0) < 1e-9,
              "cleared, it runs to t = 2 s and its progress callback sees the steps with its "
              "context (ret %d, %d calls, last %.17g s)", ret, seen.calls, seen.last_t);
    sp_tap_ok(sp_view_extent_measure(&sc, 2.0, NULL, NULL, NULL, &e) == 0 && e.xmax > e.xmin &&
              e.max_speed > 0, "with no hooks it runs too and measures a motion (x %g .. %g m)",
              e.xmin, e.xmax);

    struct sp_ensemble *ens = (struct sp_ensemble *)1;
    sc.ensemble.count = 5;
    strcpy(sc.ensemble.key, "initial.angle");
    sc.ensemble.spread = 0.1;
    flag = 1;
    ret = sp_ensemble_make(&ens, &sc, 2.0, &flag, NULL, NULL, &e);
    sp_tap_ok(ret == SP_E_INTERRUPTED && !ens,
              "a set cancel flag stops sp_ensemble_make's pre-pass, nothing made (ret %d)", ret);
    flag = 0;
    memset(&seen, 0, sizeof(seen));
    ret = sp_ensemble_make(&ens, &sc, 2.0, &flag, on_progress, &seen, &e);
    sp_tap_ok(ret == 0 && ens, "cleared, the ensemble is made (ret %d)", ret);
    sp_tap_ok(seen.calls >= 100 && !seen.backwards && seen.ctx == &seen &&
              fabs(seen.last_t - 2.0) < 1e-9,
              "its members' pre-pass reports progress through the callback with its context "
              "(%d calls, last %.17g s)", seen.calls, seen.last_t);
    sp_ensemble_destroy(&ens);
    return sp_tap_done();
}
