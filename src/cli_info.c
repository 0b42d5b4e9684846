/* springpend: the info command. The original page's "resonance check" and
 * more: the scene's two small-oscillation frequencies, how far it is from
 * 2:1, its energies, and the chosen method's margin. Prints only. */
#include <math.h>
#include <stdio.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/sim.h"

static const char info_usage[] =
    "usage: springpend info SCENE [--set SECTION.KEY=VAL ...]\n"
    "\n"
    "Prints the scene's equilibrium length l = L0 + m g / k, the spring and pendulum\n"
    "frequencies sqrt(k/m) and sqrt(g/l), their ratio and its distance from the\n"
    "2:1 resonance, the predicted bounce-swing energy-exchange time near 2:1, the\n"
    "energies at t = 0, and the integrator's stability margin, with a warning and\n"
    "a safe dt when the step is too large.\n";

/* The near-2:1 part: Lynch's averaged growth rate of the swing, s = (L0 / l^2)
 * omega_p B0, for a bounce of amplitude B0. */
static void print_resonance(const struct sp_scene *sc, double ell, double wp, double ratio)
{
    const double B0 = fabs(sc->initial.length - ell);
    const double th0 = fabs(sc->initial.angle);
    printf("  2:1 resonance    k L0 = 3 m g, i.e. k = %.6g N/m for this m and L0\n",
           3 * sc->pendulum.mass * sc->pendulum.gravity / sc->pendulum.natural_length);
    if (fabs(ratio / 2 - 1) > 0.1) {
        printf("  not near 2:1 (%.1f%% away): bounce and swing stay apart\n",
               100 * (ratio / 2 - 1));
        return;
    }
    double s = sc->pendulum.natural_length / (ell * ell) * wp * B0;
    printf("  near 2:1 (%+.2f%%): energy flows between bounce and swing\n",
           100 * (ratio / 2 - 1));
    if (s <= 0) {
        printf("  no bounce to start from (r0 = l): the exchange needs B0 = |r0 - l| > 0\n");
        return;
    }
    printf("  swing growth rate s = (L0/l^2) omega_p B0 = %.4g 1/s (B0 = |r0 - l| = %.4g m;"
           " Lynch)\n", s, B0);
    if (th0 > 0 && ell * th0 < B0)
        printf("  energy exchange  the swing grows from %.3g m to the bounce's size in about "
               "ln(B0 / (l theta0)) / s = %.3g s\n", ell * th0, log(B0 / (ell * th0)) / s);
    else
        printf("  energy exchange  time scale 1/s = %.3g s\n", 1 / s);
}

int sp_cmd_info(int argc, char **argv)
{
    struct sp_cli_options o;
    struct sp_scene sc;
    struct sp_sim sim;
    struct sp_energy e;
    int ret = sp_cli_parse(&o, argc, argv, info_usage, 0);
    if (ret)
        return ret > 0 ? 0 : ret;
    ret = sp_cli_load_scene(&o, &sc);
    if (ret)
        return ret;
    sp_sim_init(&sim, &sc);
    sp_state_energy(&sim.p, &sim.s, &e);
    const double k = sc.pendulum.stiffness, m = sc.pendulum.mass, g = sc.pendulum.gravity;
    const double L0 = sc.pendulum.natural_length, ell = L0 + m * g / k;
    const double ws = sqrt(k / m), wp = sqrt(g / ell), ratio = ws / wp;
    const struct sp_method_info *mi = sp_method_info(sc.integrator.method);

    printf("scene %s (%s)\n", sc.name, o.scene_path);
    printf("  pendulum         L0 = %g m, k = %g N/m, m = %g kg, g = %g m/s^2, b = %g N*s/m\n",
           L0, k, m, g, sc.pendulum.damping);
    printf("  equilibrium      l = L0 + m g / k = %.6g m (static stretch m g / k = %.6g m)\n",
           ell, m * g / k);
    printf("  omega_spring     sqrt(k/m) = %.6g rad/s, period %.6g s\n", ws, 2 * M_PI / ws);
    printf("  omega_pendulum   sqrt(g/l) = %.6g rad/s, period %.6g s (not sqrt(g/L0) = "
           "%.4g rad/s: the spring's stretch lengthens the pendulum)\n",
           wp, 2 * M_PI / wp, sqrt(g / L0));
    printf("  ratio            omega_spring / omega_pendulum = %.6g (2:1 resonance at 2)\n",
           ratio);
    print_resonance(&sc, ell, wp, ratio);
    if (sc.pendulum.damping > 0)
        printf("  damping          energy decay time m / b = %.4g s, quality factor "
               "Q = m omega_spring / b = %.4g\n", m / sc.pendulum.damping,
               m * ws / sc.pendulum.damping);
    if (sim.p.drive_amp > 0)
        printf("  pivot            A = %g m at %g Hz: Omega / omega_pendulum = %.4g "
               "(swing parametric resonance at 2), Omega / omega_spring = %.4g; energy is "
               "not conserved\n", sc.pivot.amplitude, sc.pivot.frequency,
               sim.p.drive_omega / wp, sim.p.drive_omega / ws);
    printf("  energy at t = 0  kinetic %.6g J, spring %.6g J, gravity %.6g J, total %.6g J\n",
           e.kinetic, e.spring, e.gravity, e.total);
    printf("                   bounce %.6g J, swing %.6g J (bounce + swing = total - E_eq)\n",
           e.bounce, e.swing);
    printf("  video            %g s at %g fps and speed %g: %d frames\n", sc.video.duration,
           sc.video.fps, sc.video.speed, sp_scene_frame_count(&sc));

    double w = sp_params_omega_max(&sim.p), safe;
    if (mi->adaptive) {
        printf("  integrator       %s, order %d, adaptive, tolerance %g, %s\n", mi->name,
               mi->order, sc.integrator.tolerance,
               sc.integrator.method == SP_METHOD_RKN1210
                   ? "each sample reached by one extra step (17 evaluations): best for "
                     "sparse samples; for video frames dop853's dense output is cheaper"
                   : "dense output at every sample");
        return 0;
    }
    double limit = sp_method_dt_limit(sc.integrator.method, &sim.p, &safe);
    printf("  integrator       %s, order %d, dt = %g s: dt omega_max = %.4g (omega_max = "
           "%.6g rad/s), stability limit %.4g: margin %.3gx\n", mi->name, mi->order,
           sc.integrator.dt, sc.integrator.dt * w, w, mi->stability,
           mi->stability / (sc.integrator.dt * w));
    if (sc.integrator.dt > limit)
        printf("warning: dt = %g s is above %s's stability limit %.4g s for this scene; "
               "the run will blow up. Use integrator.dt <= %g or integrator.method = "
               "dop853\n", sc.integrator.dt, mi->name, limit, safe);
    return 0;
}
