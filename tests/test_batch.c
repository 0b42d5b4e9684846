/* The batched integrator against sp_sim: bit for bit on fixed-step methods
 * (a batch of one, and a trajectory among others), within tolerance on the
 * adaptive one; the tangent equations against finite differences of two
 * trajectories; blow-ups marked per trajectory. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "springpend/batch.h"
#include "springpend/common.h"
#include "springpend/sim.h"
#include "tap.h"

static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof(a)) == 0;
}

/* Four scenes: the default, a chaotic one, a damped and driven one, a driven
 * one without damping. */
static void make_scenes(struct sp_scene sc[4])
{
    for (int i = 0; i < 4; i++)
        sp_scene_defaults(&sc[i]);
    sc[1].pendulum.mass = 1, sc[1].pendulum.stiffness = 39.24;
    sc[1].pendulum.natural_length = 0.75;
    sc[1].initial.length = 1.2, sc[1].initial.angle = 1.5;
    sc[2].pendulum.damping = 0.05, sc[2].pivot.amplitude = 0.1, sc[2].pivot.frequency = 0.6;
    sc[2].initial.angle_rate = 0.3;
    sc[3].pivot.amplitude = 0.05, sc[3].pivot.frequency = 1.3;
}

static const char *const scene_names[4] = {"default", "chaotic", "damped+driven", "driven"};

static void test_bitwise(enum sp_method method, const char *mname)
{
    struct sp_scene sc[4];
    make_scenes(sc);
    for (int i = 0; i < 4; i++) {
        sc[i].integrator.method = method;
        sc[i].integrator.dt = 1e-3;
        /* alone */
        const struct sp_scene *one = &sc[i];
        struct sp_batch *b;
        struct sp_sim sim;
        sp_sim_init(&sim, &sc[i]);
        int ok = sp_batch_make(&b, &one, 1, 0, 0) == 0;
        long mismatches = 0;
        /* on the grid and between grid points, as frames are */
        const double times[] = {0.5, 1.0 / 60, 2.0 / 60, 1.0, 3.3337, 7.0, 10.0};
        double t = 0;
        for (int k = 0; ok && k < 7; k++) {
            t = fmax(t, times[k]);
            sp_sim_advance(&sim, t);
            sp_batch_advance(b, t);
            mismatches += !same_bits(sim.s.x, b->out[SP_BX][0]) +
                          !same_bits(sim.s.y, b->out[SP_BY][0]) +
                          !same_bits(sim.s.vx, b->out[SP_BVX][0]) +
                          !same_bits(sim.s.vy, b->out[SP_BVY][0]);
        }
        sp_tap_ok(ok && mismatches == 0, "%s, %s: a batch of one equals sp_sim bit for bit "
                  "(%ld components differ; x %.17g vs %.17g)", mname, scene_names[i],
                  mismatches, sim.s.x, b ? b->out[SP_BX][0] : 0.0);
        sp_batch_destroy(&b);
    }
    /* among others, with the tangent riding along: the state is unchanged */
    const struct sp_scene *many[11];
    for (int i = 0; i < 11; i++)
        many[i] = &sc[i % 4];
    struct sp_batch *b;
    int ok = sp_batch_make(&b, many, 11, 1, 1) == 0;
    if (ok)
        sp_batch_advance(b, 4.321);
    long mismatches = 0;
    for (int i = 0; ok && i < 11; i++) {
        struct sp_sim sim;
        sp_sim_init(&sim, many[i]);
        sp_sim_advance(&sim, 4.321);
        if (!sim.forced)
            continue; /* batched as forced: sim.c's unforced path differs in -0 only */
        mismatches += !same_bits(sim.s.x, b->out[SP_BX][i]) +
                      !same_bits(sim.s.vy, b->out[SP_BVY][i]);
    }
    sp_tap_ok(ok && mismatches == 0, "%s: forced trajectories in a batch of 11 with tangents "
              "equal sp_sim bit for bit", mname);
    sp_batch_destroy(&b);
}

static void test_adaptive(void)
{
    struct sp_scene sc[4];
    make_scenes(sc);
    const struct sp_scene *ptr[4];
    for (int i = 0; i < 4; i++) {
        sc[i].integrator.method = SP_METHOD_DOP853;
        sc[i].integrator.tolerance = 1e-11;
        ptr[i] = &sc[i];
    }
    struct sp_batch *b;
    int ok = sp_batch_make(&b, ptr, 4, 0, 0) == 0;
    double worst = 0;
    const double times[] = {0.37, 1.0, 4.0, 6.5};
    for (int k = 0; ok && k < 4; k++) {
        sp_batch_advance(b, times[k]);
        for (int i = 0; i < 4; i++) {
            /* the reference: sp_sim's RK4 at a small step, an independent path */
            struct sp_scene ref = sc[i];
            ref.integrator.method = SP_METHOD_RK4;
            ref.integrator.dt = 1e-4;
            struct sp_sim sim;
            sp_sim_init(&sim, &ref);
            sp_sim_advance(&sim, times[k]);
            double scale = fabs(sim.s.x) + fabs(sim.s.y) + 1;
            double e = fmax(fabs(sim.s.x - b->out[SP_BX][i]), fabs(sim.s.y - b->out[SP_BY][i]));
            worst = fmax(worst, e / scale);
        }
    }
    sp_tap_ok(ok && worst < 1e-8, "dop853 with per-trajectory steps agrees with a fine RK4 "
              "within 1e-8 (worst %.2g)", worst);
    sp_tap_ok(ok && b->steps > 0 && b->steps < 4 * 7000,
              "dop853 took %ld steps over 4 trajectories for 6.5 s", ok ? b->steps : 0);
    sp_batch_destroy(&b);
}

/* The tangent after 2 s against the difference of two trajectories started
 * eps apart in x. */
static void test_tangent(enum sp_method method, const char *mname)
{
    struct sp_scene sc[4], shifted[4];
    make_scenes(sc);
    const double eps = 1e-7;
    double worst = 0;
    for (int i = 0; i < 4; i++) {
        sc[i].integrator.method = method;
        sc[i].integrator.dt = 1e-3;
        sc[i].integrator.tolerance = 1e-12;
        shifted[i] = sc[i];
        /* x0 = r sin(theta): shift by eps along x keeping y, vx, vy */
        double x = sc[i].initial.length * sin(sc[i].initial.angle);
        double y = -sc[i].initial.length * cos(sc[i].initial.angle);
        shifted[i].initial.length = hypot(x + eps, y);
        shifted[i].initial.angle = atan2(x + eps, -y);
        /* keep the velocity: rates for the shifted polar position */
        double vx = sc[i].initial.length_rate * sin(sc[i].initial.angle) +
                    sc[i].initial.length * sc[i].initial.angle_rate * cos(sc[i].initial.angle);
        double vy = -sc[i].initial.length_rate * cos(sc[i].initial.angle) +
                    sc[i].initial.length * sc[i].initial.angle_rate * sin(sc[i].initial.angle);
        double r = shifted[i].initial.length, th = shifted[i].initial.angle;
        shifted[i].initial.length_rate = vx * sin(th) - vy * cos(th);
        shifted[i].initial.angle_rate = (vx * cos(th) + vy * sin(th)) / r;
    }
    const struct sp_scene *ptr[8];
    for (int i = 0; i < 4; i++)
        ptr[i] = &sc[i], ptr[4 + i] = &shifted[i];
    struct sp_batch *b;
    int ok = sp_batch_make(&b, ptr, 8, 1, 1) == 0;
    if (ok)
        sp_batch_advance(b, 2.0);
    for (int i = 0; ok && i < 4; i++)
        for (int c = 0; c < 4; c++) {
            double fd = (b->out[c][4 + i] - b->out[c][i]) / eps;
            double tan = b->out[SP_BDX + c][i];
            worst = fmax(worst, fabs(fd - tan) / (fabs(tan) + 1));
        }
    sp_tap_ok(ok && worst < 1e-4, "%s: the tangent equals the finite difference of two "
              "trajectories (worst relative %.2g)", mname, worst);
    sp_batch_destroy(&b);
}

static void test_blowup(void)
{
    struct sp_scene sc[2];
    sp_scene_defaults(&sc[0]);
    sp_scene_defaults(&sc[1]);
    sc[1].pendulum.stiffness = 5e6; /* k/m = 1e7: RK4 at dt = 1e-3 is unstable */
    const struct sp_scene *ptr[2] = {&sc[0], &sc[1]};
    struct sp_batch *b;
    int ok = sp_batch_make(&b, ptr, 2, 0, 0) == 0;
    if (ok)
        sp_batch_advance(b, 2.0);
    sp_tap_ok(ok && !b->dead[0] && b->dead[1] && isnan(b->out[SP_BX][1]) &&
              isfinite(b->out[SP_BX][0]),
              "an unstable trajectory is marked dead and NaN; its neighbour goes on");
    sp_batch_destroy(&b);
}

int main(void)
{
    test_bitwise(SP_METHOD_RK4, "rk4");
    test_bitwise(SP_METHOD_YOSHIDA4, "yoshida4");
    test_bitwise(SP_METHOD_VERLET, "verlet");
    test_adaptive();
    test_tangent(SP_METHOD_RK4, "rk4");
    test_tangent(SP_METHOD_YOSHIDA4, "yoshida4");
    test_tangent(SP_METHOD_DOP853, "dop853");
    test_blowup();
    return sp_tap_done();
}
