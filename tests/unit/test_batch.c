/* The batched integrator against sp_sim: bit for bit on fixed-step methods
 * (a batch of one, and a trajectory among others), within tolerance on the
 * adaptive one; the tangent equations against finite differences of two
 * trajectories; blow-ups marked per trajectory; full blocks of 16 lanes
 * with every lane (the last of each block too) checked; and the same in
 * three dimensions (initial.azimuth_rate != 0): 3-D trajectories equal
 * sp_sim's 3-D ones bit for bit, planar ones in a 3-D batch equal the
 * planar batch's, the 6-D tangent its finite differences. */
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

/* Full blocks: 33 trajectories (two blocks of SP_BATCH_BLOCK = 16 lanes and
 * one lane more), each with its own stiffness, damping and drive, so that a
 * lane skipped or shifted in a block shows; every lane is checked, the last
 * of each block (15, 31) and the lone 33rd included. Fixed steps equal sp_sim
 * (bit for bit up to the sign of zero), dop853 within 1e-8 of a fine RK4;
 * with tangents riding along; and a blow-up in lane 15 alone. */
static void full_scene(struct sp_scene *sc, int i, enum sp_method method)
{
    sp_scene_defaults(sc);
    sc->integrator.method = method;
    sc->integrator.dt = 1e-3;
    sc->integrator.tolerance = 1e-11;
    sc->pendulum.stiffness = 2 + 0.37 * i;
    sc->pendulum.damping = 0.01 + 0.003 * i;
    sc->pivot.amplitude = 0.01 + 0.002 * i, sc->pivot.frequency = 0.5 + 0.05 * i;
    sc->initial.angle = (5 + 1.3 * i) * M_PI / 180;
    sc->initial.length_rate = 0.02 * i;
}

static void test_full_blocks(enum sp_method method, const char *mname)
{
    enum { N = 2 * SP_BATCH_BLOCK + 1 };
    struct sp_scene sc[N];
    const struct sp_scene *ptr[N];
    for (int i = 0; i < N; i++)
        full_scene(&sc[i], i, method), ptr[i] = &sc[i];
    for (int tangent = 0; tangent <= 1; tangent++) {
        struct sp_batch *b;
        int ok = sp_batch_make(&b, ptr, N, 1, tangent) == 0;
        if (ok)
            sp_batch_advance(b, 2.345);
        double worst = 0;
        int worst_lane = -1, off = 0;
        for (int i = 0; ok && i < N; i++) {
            struct sp_scene ref = sc[i];
            if (method == SP_METHOD_DOP853)
                ref.integrator.method = SP_METHOD_RK4, ref.integrator.dt = 1e-4;
            struct sp_sim sim;
            sp_sim_init(&sim, &ref);
            sp_sim_advance(&sim, 2.345);
            const double want[4] = {sim.s.x, sim.s.y, sim.s.vx, sim.s.vy};
            for (int c = 0; c < 4; c++) {
                double got = b->out[SP_BX + c][i];
                double e = fabs(got - want[c]) / (fabs(want[c]) + 1);
                if (!(e <= worst))
                    worst = e, worst_lane = i;
                off += method == SP_METHOD_DOP853 ? !(e < 1e-8) : !(got == want[c]);
            }
        }
        sp_tap_ok(ok && off == 0, "%s%s: all %d trajectories (lanes 0-15, 16-31 and one more, "
                  "each its own k, b, drive) equal sp_sim%s: %d components off, worst %.2g in "
                  "trajectory %d", mname, tangent ? " with tangents" : "", N,
                  method == SP_METHOD_DOP853 ? " (RK4 at 1e-4) within 1e-8" : " exactly", off,
                  worst, worst_lane);
        sp_batch_destroy(&b);
    }
    /* the tangent of the last lane: trajectory 7 and its shift in lane 15 */
    struct sp_scene pair[SP_BATCH_BLOCK];
    const struct sp_scene *pp[SP_BATCH_BLOCK];
    const double eps = 1e-7;
    for (int i = 0; i < SP_BATCH_BLOCK; i++) {
        full_scene(&pair[i], i % 8, method);
        pair[i].pendulum.damping = 0, pair[i].pivot.amplitude = 0;
        if (i >= 8) { /* the same start shifted by eps along x, velocity kept */
            double r = pair[i].initial.length, th = pair[i].initial.angle;
            double x = r * sin(th), y = -r * cos(th), rd = pair[i].initial.length_rate;
            double vx = rd * sin(th), vy = -rd * cos(th);
            pair[i].initial.length = r = hypot(x + eps, y);
            pair[i].initial.angle = th = atan2(x + eps, -y);
            pair[i].initial.length_rate = vx * sin(th) - vy * cos(th);
            pair[i].initial.angle_rate = (vx * cos(th) + vy * sin(th)) / r;
        }
        pp[i] = &pair[i];
    }
    struct sp_batch *b;
    int ok = sp_batch_make(&b, pp, SP_BATCH_BLOCK, 1, 1) == 0;
    double worst = 0;
    if (ok)
        sp_batch_advance(b, 1.5);
    for (int i = 0; ok && i < 8; i++)
        for (int c = 0; c < 4; c++) {
            double fd = (b->out[c][8 + i] - b->out[c][i]) / eps;
            double tan = b->out[SP_BDX + c][i];
            worst = fmax(worst, fabs(fd - tan) / (fabs(tan) + 1));
        }
    sp_tap_ok(ok && worst < 1e-4, "%s: a full block of 16, trajectory 7's tangent against its "
              "shifted copy in lane 15 (worst relative %.2g)", mname, worst);
    sp_batch_destroy(&b);
}

static void test_blowup_last_lane(void)
{
    struct sp_scene sc[SP_BATCH_BLOCK];
    const struct sp_scene *ptr[SP_BATCH_BLOCK];
    for (int i = 0; i < SP_BATCH_BLOCK; i++)
        full_scene(&sc[i], i, SP_METHOD_RK4), ptr[i] = &sc[i];
    sc[SP_BATCH_BLOCK - 1].pendulum.stiffness = 5e6; /* k/m = 1e7: RK4 unstable at 1e-3 */
    struct sp_batch *b;
    int ok = sp_batch_make(&b, ptr, SP_BATCH_BLOCK, 0, 0) == 0;
    if (ok)
        sp_batch_advance(b, 2.0);
    int alive = 0;
    for (int i = 0; ok && i < SP_BATCH_BLOCK - 1; i++)
        alive += !b->dead[i] && isfinite(b->out[SP_BX][i]);
    sp_tap_ok(ok && alive == SP_BATCH_BLOCK - 1 && b->dead[SP_BATCH_BLOCK - 1] &&
              isnan(b->out[SP_BX][SP_BATCH_BLOCK - 1]),
              "a blow-up in lane 15 of a full block is marked there alone (%d of 15 others go on)",
              alive);
    sp_batch_destroy(&b);
}

/* A long call is cut every SP_BATCH_CHUNK steps to look at the cancel flag:
 * over 131.1 s (two cuts, and an end off the grid) a batch of one still
 * equals sp_sim, which is never cut, bit for bit, with the tangent and the
 * forced path riding along (the states do not depend on them). The chaotic
 * scene and the damped, driven one: any change of arithmetic grows there. */
static void test_chunked(enum sp_method method, const char *mname)
{
    struct sp_scene sc[4];
    make_scenes(sc);
    const double t_end = 131.1005; /* 131100 steps of 1 ms and a part */
    for (int i = 1; i < 3; i++) {
        sc[i].integrator.method = method;
        sc[i].integrator.dt = 1e-3;
        const struct sp_scene *one = &sc[i];
        struct sp_batch *b = NULL;
        struct sp_sim sim;
        sp_sim_init(&sim, &sc[i]);
        int ok = sp_batch_make(&b, &one, 1, 1, 1) == 0;
        ok = ok && t_end / 1e-3 > 2 * SP_BATCH_CHUNK && sp_batch_advance(b, t_end) == 0;
        sp_sim_advance(&sim, t_end);
        ok = ok && same_bits(sim.s.x, b->out[SP_BX][0]) && same_bits(sim.s.y, b->out[SP_BY][0]) &&
             same_bits(sim.s.vx, b->out[SP_BVX][0]) && same_bits(sim.s.vy, b->out[SP_BVY][0]);
        sp_tap_ok(ok, "%s, %s: one call over %.4f s, cut every %d steps, equals sp_sim bit "
                  "for bit (x %.17g vs %.17g)", mname, scene_names[i], t_end, SP_BATCH_CHUNK,
                  sim.s.x, b ? b->out[SP_BX][0] : 0.0);
        sp_batch_destroy(&b);
    }
}

/* Once the caller's flag is set, a long advance stops at its next look:
 * fixed steps between chunks, dop853 inside its step loop. */
static void test_cancel(enum sp_method method, const char *mname)
{
    struct sp_scene sc;
    sp_scene_defaults(&sc);
    sc.integrator.method = method;
    const struct sp_scene *one = &sc;
    struct sp_batch *b = NULL;
    static volatile sig_atomic_t flag;
    int ok = sp_batch_make(&b, &one, 1, 0, 0) == 0;
    flag = 0;
    b->cancel = &flag;
    ok = ok && sp_batch_advance(b, 1.0) == 0 && b->t == 1.0;
    flag = 1;
    /* 1e9 s would take hours: it must return at once */
    int ret = ok ? sp_batch_advance(b, 1e9) : 0;
    sp_tap_ok(ok && ret == SP_E_INTERRUPTED && b->t == 1.0,
              "%s: with the cancel flag set, sp_batch_advance to 1e9 s returns "
              "SP_E_INTERRUPTED at once (%d, t %g)", mname, ret, b ? b->t : -1.0);
    sp_batch_destroy(&b);
}

/* The fast kernel (sp_batch.fast: FMA, 1/rho without the divider) against
 * the exact one on 24 trajectories of the default and the chaotic scene
 * with tangents, over 2 s at dt 1e-3: the same states to 1e-10 of their
 * scale (rounding, before chaos grows it); a damped scene takes the exact
 * path whatever fast says (the same bits). */
static void test_fast(void)
{
    if (!sp_batch_fast_supported()) {
        sp_tap_ok(1, "# SKIP the fast kernel needs AVX-512F and FMA");
        return;
    }
    struct sp_scene sc[24];
    const struct sp_scene *ptr[24];
    for (int i = 0; i < 24; i++) {
        struct sp_scene four[4];
        make_scenes(four);
        sc[i] = four[i % 2]; /* the default and the chaotic scene */
        sc[i].initial.angle += 0.05 * i;
        sc[i].integrator.dt = 1e-3;
        ptr[i] = &sc[i];
    }
    struct sp_batch *a, *b;
    int ok = sp_batch_make(&a, ptr, 24, 1, 0) == 0 && sp_batch_make(&b, ptr, 24, 1, 0) == 0;
    if (ok) {
        b->fast = 1;
        ok = sp_batch_advance(a, 2.0) == 0 && sp_batch_advance(b, 2.0) == 0;
    }
    double worst = 0;
    int same = 0;
    for (int c = 0; ok && c < SP_BZ; c++) { /* the planar components */
        if (c == SP_BW)
            continue;
        for (int i = 0; i < 24; i++) {
            const double scale = fmax(1, fabs(a->out[c][i]));
            worst = fmax(worst, fabs(a->out[c][i] - b->out[c][i]) / scale);
            same += same_bits(a->out[c][i], b->out[c][i]);
        }
    }
    sp_tap_ok(ok && worst < 1e-10 && same < 24 * 8,
              "fast kernel: 24 trajectories with tangents over 2 s within %.1e of the exact "
              "kernel (relative, %d of %d values bit-equal: not the same arithmetic)",
              worst, same, 24 * 8);
    sp_batch_destroy(&a);
    sp_batch_destroy(&b);
    /* blow-ups (k/m = 1e7: RK4 at dt 1e-3 is unstable) in lanes 5 and 20 of
     * two blocks: the fast kernel checks the energy every 64 steps, yet marks
     * them dead and NaN, and only them, as the exact kernel does, both after
     * 50 steps (fewer than 64: the check that ends every advance) and 2 s */
    sc[5].pendulum.stiffness = sc[20].pendulum.stiffness = 5e6;
    for (int k = 0; k < 2; k++) {
        const double t_end = k ? 2.0 : 0.05;
        ok = sp_batch_make(&a, ptr, 24, 1, 0) == 0 && sp_batch_make(&b, ptr, 24, 1, 0) == 0;
        if (ok) {
            b->fast = 1;
            ok = sp_batch_advance(a, t_end) == 0 && sp_batch_advance(b, t_end) == 0;
        }
        int marked = 0, finite = 0;
        for (int i = 0; ok && i < 24; i++) {
            const int bad = i == 5 || i == 20;
            marked += b->dead[i] == bad && a->dead[i] == bad;
            finite += bad ? isnan(b->out[SP_BX][i]) && isnan(b->out[SP_BDVY][i])
                          : isfinite(b->out[SP_BX][i]) && isfinite(b->out[SP_BDVY][i]);
        }
        sp_tap_ok(ok && marked == 24 && finite == 24,
                  "fast kernel: unstable lanes 5 and 20 marked dead and NaN after %g s, the other "
                  "22 not, as the exact kernel marks them (%d of 24 marked right, %d of 24 NaN or "
                  "finite as they should be)",
                  t_end, marked, finite);
        sp_batch_destroy(&a);
        sp_batch_destroy(&b);
    }
    /* forced: the exact path, bit for bit */
    struct sp_scene four[4];
    make_scenes(four);
    const struct sp_scene *dd = &four[2];
    ok = sp_batch_make(&a, &dd, 1, 1, 1) == 0 && sp_batch_make(&b, &dd, 1, 1, 1) == 0;
    if (ok) {
        b->fast = 1;
        ok = sp_batch_advance(a, 1.0) == 0 && sp_batch_advance(b, 1.0) == 0;
    }
    sp_tap_ok(ok && same_bits(a->out[SP_BX][0], b->out[SP_BX][0]) &&
                  same_bits(a->out[SP_BDVY][0], b->out[SP_BDVY][0]),
              "fast kernel: a damped, driven trajectory takes the exact path (the same bits)");
    sp_batch_destroy(&a);
    sp_batch_destroy(&b);
}


/* ---- three dimensions ---------------------------------------------------- */

/* Four 3-D scenes: the swinging spring (scenes/swinging-spring.ini), the
 * chaotic one turning, a damped and driven one turning, and a fast turn. */
static void make_scenes3(struct sp_scene sc[4])
{
    make_scenes(sc);
    sc[0].pendulum.mass = 1, sc[0].pendulum.stiffness = 39.24;
    sc[0].pendulum.natural_length = 0.75;
    sc[0].initial.length = 1.05, sc[0].initial.angle = M_PI / 180;
    sc[0].initial.azimuth_rate = 1;
    sc[1].initial.azimuth_rate = 0.5;
    sc[2].initial.azimuth_rate = 0.3;
    sc[3].initial.azimuth_rate = -2;
}

static const char *const scene3_names[4] = {"swinging spring", "chaotic, turning",
                                            "damped+driven, turning", "driven, fast turn"};

/* The six components of sp_sim's state against lane i of b: how many differ
 * (bitwise when bits, else by value, the sign of zero aside). */
static long state_diff(const struct sp_sim *sim, const struct sp_batch *b, int i, int bits)
{
    const double want[6] = {sim->s.x, sim->s.y, sim->s.vx, sim->s.vy, sim->s.z, sim->s.vz};
    const int comp[6] = {SP_BX, SP_BY, SP_BVX, SP_BVY, SP_BZ, SP_BVZ};
    long off = 0;
    for (int c = 0; c < 6; c++)
        off += bits ? !same_bits(want[c], b->out[comp[c]][i]) : !(want[c] == b->out[comp[c]][i]);
    return off;
}

static void test_bitwise3(enum sp_method method, const char *mname)
{
    struct sp_scene sc[4];
    make_scenes3(sc);
    for (int i = 0; i < 4; i++) {
        sc[i].integrator.method = method;
        sc[i].integrator.dt = 1e-3;
        const struct sp_scene *one = &sc[i];
        struct sp_batch *b = NULL;
        struct sp_sim sim;
        sp_sim_init(&sim, &sc[i]);
        int ok = sim.spatial && sp_batch_make(&b, &one, 1, 0, 0) == 0 && b->spatial;
        long off = 0;
        const double times[] = {0.5, 1.0 / 60, 2.0 / 60, 1.0, 3.3337, 7.0, 10.0};
        double t = 0;
        for (int k = 0; ok && k < 7; k++) {
            t = fmax(t, times[k]);
            sp_sim_advance(&sim, t);
            sp_batch_advance(b, t);
            off += state_diff(&sim, b, 0, 1);
        }
        sp_tap_ok(ok && off == 0 && sim.s.z != 0, "3-D %s, %s: a batch of one equals sp_sim's "
                  "3-D run bit for bit (%ld components differ; z %.17g vs %.17g)", mname,
                  scene3_names[i], off, sim.s.z, b ? b->out[SP_BZ][0] : 0.0);
        sp_batch_destroy(&b);
    }
}

/* 33 trajectories, 3-D and planar mixed (every third planar), each its own
 * k, b and drive, with and without the tangent: the 3-D ones equal sp_sim's
 * 3-D run, the planar ones sp_sim's planar run (and the planar batch's),
 * every lane checked. */
static void test_full_blocks3(enum sp_method method, const char *mname)
{
    enum { N = 2 * SP_BATCH_BLOCK + 1 };
    struct sp_scene sc[N];
    const struct sp_scene *ptr[N], *planar[N];
    int np = 0;
    for (int i = 0; i < N; i++) {
        full_scene(&sc[i], i, method);
        sc[i].initial.azimuth_rate = i % 3 == 2 ? 0 : 0.2 + 0.05 * i;
        ptr[i] = &sc[i];
        if (i % 3 == 2)
            planar[np++] = &sc[i];
    }
    for (int tangent = 0; tangent <= 1; tangent++) {
        struct sp_batch *b = NULL, *pb = NULL;
        int ok = sp_batch_make(&b, ptr, N, tangent, 1) == 0 &&
                 sp_batch_make(&pb, planar, np, tangent, 1) == 0 && b->spatial && !pb->spatial;
        if (ok)
            sp_batch_advance(b, 2.345), sp_batch_advance(pb, 2.345);
        double worst = 0;
        long off = 0, off_planar = 0;
        for (int i = 0, j = 0; ok && i < N; i++) {
            struct sp_scene ref = sc[i];
            if (method == SP_METHOD_DOP853)
                ref.integrator.method = SP_METHOD_RK4, ref.integrator.dt = 1e-4;
            struct sp_sim sim;
            sp_sim_init(&sim, &ref);
            sp_sim_advance(&sim, 2.345);
            if (method == SP_METHOD_DOP853) {
                const double want[6] = {sim.s.x, sim.s.y, sim.s.vx, sim.s.vy, sim.s.z, sim.s.vz};
                const int comp[6] = {SP_BX, SP_BY, SP_BVX, SP_BVY, SP_BZ, SP_BVZ};
                for (int c = 0; c < 6; c++) {
                    double e = fabs(b->out[comp[c]][i] - want[c]) / (fabs(want[c]) + 1);
                    worst = fmax(worst, e);
                    off += !(e < 1e-8);
                }
            } else {
                off += state_diff(&sim, b, i, 0);
            }
            if (i % 3 == 2) { /* planar: the planar batch's numbers, tangent and all */
                for (int c = 0; c < SP_BZ; c++)
                    off_planar += c != SP_BW && !(b->out[c][i] == pb->out[c][j]);
                off_planar += b->out[SP_BZ][i] != 0 || b->out[SP_BVZ][i] != 0;
                j++;
            }
        }
        sp_tap_ok(ok && off == 0 && off_planar == 0,
                  "3-D %s%s: all %d trajectories (3-D and planar mixed, lanes 0-15, 16-31 and "
                  "one more) equal sp_sim%s: %ld components off (worst %.2g); the %d planar ones "
                  "equal the planar batch's%s: %ld off", mname, tangent ? " with tangents" : "",
                  N, method == SP_METHOD_DOP853 ? " (RK4 at 1e-4) within 1e-8" : " exactly",
                  off, worst, np, tangent ? " (tangents too)" : "", off_planar);
        sp_batch_destroy(&b);
        sp_batch_destroy(&pb);
    }
}

/* The 6-D tangent after 2 s against finite differences: each 3-D scene and
 * copies of it shifted by eps along x and along z (set in the state before
 * the first step), each copy's difference against the tangent started along
 * that axis. */
static void test_tangent3(enum sp_method method, const char *mname)
{
    struct sp_scene sc[4];
    make_scenes3(sc);
    const struct sp_scene *ptr[12];
    for (int i = 0; i < 4; i++) {
        sc[i].integrator.method = method;
        sc[i].integrator.dt = 1e-3;
        sc[i].integrator.tolerance = 1e-12;
        ptr[i] = ptr[4 + i] = ptr[8 + i] = &sc[i];
    }
    const double eps = 1e-7;
    struct sp_batch *b = NULL;
    int ok = sp_batch_make(&b, ptr, 12, 1, 1) == 0 && b->spatial;
    for (int i = 0; ok && i < 4; i++) {
        /* lanes 0-3: tangent along z; 4-7 shifted by eps in x; 8-11 in z */
        b->u[SP_BDX][i] = b->out[SP_BDX][i] = 0;
        b->u[SP_BDZ][i] = b->out[SP_BDZ][i] = 1;
        b->u[SP_BX][4 + i] += eps;
        b->u[SP_BZ][8 + i] += eps;
    }
    struct sp_batch *bx = NULL; /* the tangent along x, for the x shift */
    ok = ok && sp_batch_make(&bx, ptr, 4, 1, 1) == 0;
    if (ok && method != SP_METHOD_RK4 && method != SP_METHOD_DOP853)
        ok = 0; /* the splitting methods' force cache would need the shift too */
    if (ok)
        sp_batch_advance(b, 2.0), sp_batch_advance(bx, 2.0);
    double worst = 0;
    const int st[6] = {SP_BX, SP_BY, SP_BVX, SP_BVY, SP_BZ, SP_BVZ};
    const int tg[6] = {SP_BDX, SP_BDY, SP_BDVX, SP_BDVY, SP_BDZ, SP_BDVZ};
    for (int i = 0; ok && i < 4; i++)
        for (int c = 0; c < 6; c++) {
            double fdz = (b->out[st[c]][8 + i] - b->out[st[c]][i]) / eps;
            double fdx = (b->out[st[c]][4 + i] - b->out[st[c]][i]) / eps;
            worst = fmax(worst, fabs(fdz - b->out[tg[c]][i]) / (fabs(b->out[tg[c]][i]) + 1));
            worst = fmax(worst, fabs(fdx - bx->out[tg[c]][i]) / (fabs(bx->out[tg[c]][i]) + 1));
        }
    sp_tap_ok(ok && worst < 1e-4, "3-D %s: the 6-D tangent, started along x and along z, "
              "equals the finite differences of shifted trajectories (worst relative %.2g)",
              mname, worst);
    sp_batch_destroy(&b);
    sp_batch_destroy(&bx);
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
    test_full_blocks(SP_METHOD_RK4, "rk4");
    test_full_blocks(SP_METHOD_VERLET, "verlet");
    test_full_blocks(SP_METHOD_YOSHIDA4, "yoshida4");
    test_full_blocks(SP_METHOD_DOP853, "dop853");
    test_blowup_last_lane();
    test_chunked(SP_METHOD_RK4, "rk4");
    test_chunked(SP_METHOD_VERLET, "verlet");
    test_chunked(SP_METHOD_YOSHIDA4, "yoshida4");
    test_cancel(SP_METHOD_RK4, "rk4");
    test_cancel(SP_METHOD_DOP853, "dop853");
    test_fast();
    test_bitwise3(SP_METHOD_RK4, "rk4");
    test_bitwise3(SP_METHOD_YOSHIDA4, "yoshida4");
    test_bitwise3(SP_METHOD_VERLET, "verlet");
    test_full_blocks3(SP_METHOD_RK4, "rk4");
    test_full_blocks3(SP_METHOD_VERLET, "verlet");
    test_full_blocks3(SP_METHOD_YOSHIDA4, "yoshida4");
    test_full_blocks3(SP_METHOD_DOP853, "dop853");
    test_tangent3(SP_METHOD_RK4, "rk4");
    test_tangent3(SP_METHOD_DOP853, "dop853");
    return sp_tap_done();
}
