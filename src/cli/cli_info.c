/* springpend: the info command. The original page's "resonance check" and
 * more: the scene's two small-oscillation frequencies, how far it is from
 * 2:1 and when the swing takes the bounce's energy, the damping's decay
 * times, the driven pivot's parametric resonance, its energies, and a step
 * the chosen method completes the run with. Prints only (text or --json). */
#include <math.h>
#include <stdio.h>

#include "cli.h"
#include "springpend/timeline.h"
#include "springpend/advice.h"
#include "springpend/compare_report.h"
#include "springpend/common.h"
#include "springpend/sim.h"

static const char info_usage[] =
    "usage: springpend info SCENE [--json] [--set SECTION.KEY=VAL ...]\n"
    "\n"
    "Prints the scene's equilibrium length l = L0 + m g / k, the spring and pendulum\n"
    "frequencies sqrt(k/m) and sqrt(g/l), their ratio and its distance from the\n"
    "2:1 resonance; near 2:1, when the swing's energy first peaks (Lynch's averaged\n"
    "equations), and for a 3-D scene (initial.azimuth_rate) the swing plane's turn\n"
    "per exchange, and whether the small-amplitude theory applies; with damping, each mode's regime and energy decay time; with a\n"
    "moving pivot, where parametric resonance lies and the swing's predicted\n"
    "growth; the energies at t = 0; and for fixed-step methods the fastest rate\n"
    "the motion reaches (a short dop853 probe of the run), the stability margin,\n"
    "whether the scene's dt completes the run, and a safe dt that does (checked\n"
    "by running it over video.duration, or its first 2e6 steps).\n"
    "It also prints the video's length: video.duration / video.speed seconds, or,\n"
    "with a [timeline] that changes the speed or pauses, how long its clock takes\n"
    "to reach video.duration, pauses included (see 'springpend render --help'),\n"
    "and its frames, round(length * fps).\n"
    "\n"
    "  --json   the same facts for scripts, SI units, null where none applies:\n"
    "           omega_spring, omega_pendulum, ratio, equilibrium_length,\n"
    "           exchange_rate, exchange_time, bounce_decay_time, swing_decay_time,\n"
    "           precession_per_exchange (rad, 3-D scenes), precession_period,\n"
    "           precession_applies,\n"
    "           drive_swing_growth, stability_margin, safe_dt, adaptive_method,\n"
    "           video_length (s of video), video_frames, ...\n"
    "  --set SECTION.KEY=VAL  override a scene key (repeatable)\n"
    "  --fps N    shorthand for video.fps (the frames a render makes)\n"
    "  --quality Q  low, medium, high or 4k: render's sizes and rates, as render\n"
    "           would take them\n"
    "  -h, --help   this text\n"
    "\n"
    "A close pass by the pivot (r < L0/2) is a pass to resolve (dt < d/v), not a rate to\n"
    "keep stable; where such passes make a fixed step impractical, info says so and\n"
    "names dop853, run to completion.\n";

/* Everything info says, in SI units; NAN where it does not apply. */
struct info {
    struct sp_physics ph;
    struct sp_energy e;
    struct sp_exchange ex;
    int near21;                 /* within 10% of 2:1 */
    int spatial;                /* the motion leaves the x-y plane */
    struct sp_precession prec;  /* valid when spatial */
    int prec_ok;                /* sp_advise_precession returned 0 */
    double ex_amplitude;        /* the start's amplitude / l (3-D: prec's) */
    int ex_beyond;              /* 1: ex_amplitude > SP_ADVISE_AMPLITUDE_MAX: the
                                   exchange is not predicted */
    struct sp_decay bounce, swing; /* valid when damped */
    int damped, driven;
    struct sp_drive_advice drive;
    struct sp_dt_advice dt;     /* fixed-step methods */
    double margin;              /* limit / dt */
    int impractical;            /* 1: close passes by the pivot hold the safe dt
                                 * down (sp_dt_advice.pass_bound) so far that
                                 * the run takes over 2e6 steps at it (or none
                                 * completed) */
    double adaptive_checked;    /* s: the passes hold the safe dt down, and
                                 * dop853 completed the run over [0,
                                 * adaptive_checked] = video.duration; NAN
                                 * otherwise */
};

static const char *regime_name(int r)
{
    return r < 0 ? "underdamped" : r == 0 ? "critically damped" : "overdamped";
}

/* info's text, part by part: the scene's frequencies and the 2:1 resonance. */
static void print_frequencies(const struct sp_cli_options *o, const struct sp_scene *sc,
                              const struct info *in)
{
    const double k = sc->pendulum.stiffness, m = sc->pendulum.mass, g = sc->pendulum.gravity;
    const double L0 = sc->pendulum.natural_length, ell = in->ph.ell;
    const double ws = in->ph.omega_s, wp = in->ph.omega_p, ratio = in->ph.ratio;

    sp_fprintf_line(stdout, "scene %s (%s)", sc->name, o->scene_path);
    printf("  pendulum         L0 = %g m, k = %g N/m, m = %g kg, g = %g m/s^2, b = %g N*s/m\n",
           L0, k, m, g, sc->pendulum.damping);
    printf("  equilibrium      l = L0 + m g / k = %.6g m (static stretch m g / k = %.6g m)\n",
           ell, m * g / k);
    printf("  omega_spring     sqrt(k/m) = %.6g rad/s, period %.6g s\n", ws, 2 * M_PI / ws);
    if (!(wp > 0)) { /* g = 0: nothing pulls the bob back to the vertical */
        printf("  omega_pendulum   none: without gravity (g = 0) the bob does not swing back, "
               "so no pendulum period exists\n");
        printf("  ratio            does not apply (no pendulum frequency)\n");
        printf("  2:1 resonance    does not apply: k L0 = 3 m g needs gravity; bounce and "
               "swing do not exchange energy\n");
    } else {
        printf("  omega_pendulum   sqrt(g/l) = %.6g rad/s, period %.6g s (not sqrt(g/L0) = "
               "%.4g rad/s: the spring's stretch lengthens the pendulum)\n",
               wp, 2 * M_PI / wp, sqrt(g / L0));
        printf("  ratio            omega_spring / omega_pendulum = %.6g (2:1 resonance at 2)\n",
               ratio);
        printf("  2:1 resonance    k L0 = 3 m g, i.e. k = %.6g N/m for this m and L0\n",
               3 * m * g / L0);
    }
}

/* Near 2:1: the energy exchange (Lynch's averaged equations). */
static void print_exchange(const struct sp_scene *sc, const struct info *in)
{
    const double ell = in->ph.ell, wp = in->ph.omega_p, ratio = in->ph.ratio;

    if (!(wp > 0)) {
    } else if (!in->near21) {
        printf("  not near 2:1 (%.1f%% away): bounce and swing stay apart\n",
               100 * (ratio / 2 - 1));
    } else {
        printf("  near 2:1 (%+.2f%%): energy flows between bounce and swing\n",
               100 * (ratio / 2 - 1));
        if (!in->ex_beyond)
            printf("  growth rate      s = 3 omega_p |B0| / (4 l) = %.4g 1/s of the swing at the "
                   "start (Lynch; (L0/l^2) omega_p B0 at exact 2:1), B0 = |r0 - l| = %.4g m\n",
                   in->ex.rate, fabs(sc->initial.length - ell));
        if (in->ex_beyond)
            printf("  energy exchange  not predicted: the start's amplitude is %.3g of l, and "
                   "Lynch's averaged equations hold for small amplitudes (a few %% of l): "
                   "beyond %g of l the motion is no slow exchange\n", in->ex_amplitude,
                   SP_ADVISE_AMPLITUDE_MAX);
        else if (isnan(in->ex.time))
            printf("  energy exchange  none expected: it needs both a bounce (r0 != l or a "
                   "length rate) and a seed of swing (theta0 or an angle rate)\n");
        else
            printf("  energy exchange  the swing's energy first peaks at t = %.3g s, holding "
                   "%.0f%% of the bounce + swing energy (Lynch's averaged equations): the bob "
                   "then swings widest and barely bounces; the energy flows back to the "
                   "bounce by about t = %.3g s, and so on\n",
                   in->ex.time, 100 * in->ex.swing_share, 2 * in->ex.time);
    }
}

/* A 3-D scene: the swing plane's precession. */
static void print_spatial(const struct sp_scene *sc, const struct sp_sim *sim,
                          const struct info *in)
{
    const double m = sc->pendulum.mass;
    const struct sp_precession *pr = &in->prec;
    printf("  3-D              azimuth_rate = %g rad/s: the bob starts turning about the "
           "vertical, L_y = m (z vx - x vz) = %.4g kg m^2/s\n", sc->initial.azimuth_rate,
           m * sp_state_angular_momentum_y(&sim->s));
    if (!in->prec_ok)
        printf("  precession       not predicted: %s\n", pr->why);
    else if (isnan(pr->angle))
        printf("  precession       none predicted: %s\n", pr->why);
    else
        printf("  precession       the swing's plane turns by %+.3g degrees per exchange, "
               "every %.3g s (first swing peak at t = %.3g s), by the averaged three-wave "
               "equations (Lynch and Houghton); amplitude %.3g of l: %s\n",
               pr->angle * 180 / M_PI, pr->period, pr->first_peak, pr->epsilon,
               pr->applies ? "within 4% of the full motion's where measured (physics.md: amplitudes up "
                             "to 0.065 l, within 1% of 2:1)"
                           : pr->why);
}

/* With damping: each mode's regime and decay time. */
static void print_damping(const struct info *in)
{
    const struct sp_decay *d[2] = {&in->bounce, &in->swing};
    const char *name[2] = {"bounce", "swing"};
    for (int i = 0; i < 2; i++)
        printf("  damping %-8s %s (Q = omega / (b/m) = %.3g): its energy falls by e every "
               "%.4g s%s\n", name[i], regime_name(d[i]->regime), d[i]->q, d[i]->energy_time,
               d[i]->regime < 0    ? " (m / b)"
               : d[i]->regime == 0 ? " (m / b, times (1 + omega t)^2)"
                                   : " (1 / (2 s_slow), the slow root; m / b would be "
                                     "too short)");
}

/* A moving pivot: the parametric resonance and the swing's growth. */
static void print_drive(const struct sp_scene *sc, const struct sp_sim *sim,
                        const struct info *in)
{
    const double ws = in->ph.omega_s, wp = in->ph.omega_p;
    const struct sp_drive_advice *dv = &in->drive;
    const double W = sim->p.drive_omega;
    printf("  pivot            A = %g m at %g Hz: Omega = %.4g rad/s; energies are in the "
           "pivot's frame, not conserved\n", sc->pivot.amplitude, sc->pivot.frequency, W);
    printf("  swing resonance  parametric at Omega = 2 omega_p = %.4g rad/s (here Omega / "
           "omega_p = %.4g); it grows where |Omega/2 - omega_p| < omega_p h / 4 = %.3g "
           "rad/s, h = %.3g the modulation of the swing's stiffness by the forced bounce\n",
           2 * wp, W / wp, dv->tongue, dv->h);
    printf("  bounce           forced directly, amplitude %.3g m (resonant at Omega = "
           "omega_s = %.4g rad/s; a vertical pivot leaves the spring's stiffness alone, "
           "so there is no parametric resonance of the bounce at 2 omega_s = %.4g rad/s)\n",
           dv->bounce_amp, ws, 2 * ws);
    if (dv->growth > 0 && !isnan(dv->time_10x))
        printf("  swing growth     expected: amplitude grows as exp(%.3g t) (damping "
               "included); %.2g%% of the start's swing is in the growing mode, so it "
               "reaches 10 times its start by about t = %.3g s\n", dv->growth,
               100 * dv->seed_share, dv->time_10x);
    else if (dv->growth > 0)
        printf("  swing growth     possible at exp(%.3g t), but the scene starts with no "
               "swing (theta0 = 0, no angle rate): nothing to amplify\n", dv->growth);
    else
        printf("  swing growth     none expected: %s\n",
               dv->tongue > fabs(dv->detuning)
                   ? "the damping outweighs the drive's pumping"
                   : "Omega is outside the resonance tongue (too far from 2 omega_p)");
}

/* The energies at t = 0 and the video's length. */
static void print_energy_video(const struct sp_scene *sc, const struct info *in)
{
    printf("  energy at t = 0  kinetic %.6g J, spring %.6g J, gravity %.6g J, total %.6g J\n",
           in->e.kinetic, in->e.spring, in->e.gravity, in->e.total);
    printf("                   bounce %.6g J, swing %.6g J (bounce + swing = total - E_eq)\n",
           in->e.bounce, in->e.swing);
    if (sc->timeline && sc->timeline->clocked)
        printf("  video            %g s of video: %g simulated s at %g fps, speed %g to %g "
               "and pauses by the [timeline]: %d frames\n", sp_timeline_length(sc),
               sc->video.duration, sc->video.fps, sc->timeline->speed_min,
               sc->timeline->speed_max, sp_timeline_frames(sc));
    else
        printf("  video            %g s at %g fps and speed %g: %d frames, %g s of video\n",
               sc->video.duration, sc->video.fps, sc->video.speed, sp_scene_frame_count(sc),
               sp_timeline_length(sc));
}

/* The integrator: an adaptive one's tolerance, or a fixed step's margin,
 * close passes and safe dt. */
static void print_integrator(const struct sp_scene *sc, const struct sp_sim *sim,
                             const struct info *in)
{
    const double L0 = sc->pendulum.natural_length;
    const struct sp_method_info *mi = sp_method_info(sc->integrator.method);

    if (mi->adaptive) {
        printf("  integrator       %s, order %d, adaptive, tolerance %g, %s\n", mi->name,
               mi->order, sc->integrator.tolerance,
               sc->integrator.method == SP_METHOD_RKN1210
                   ? "each sample reached by one extra step (17 evaluations): best for "
                     "sparse samples; for video frames dop853's dense output is cheaper"
                   : "dense output at every sample");
        return;
    }
    const struct sp_dt_advice *a = &in->dt;
    printf("  integrator       %s, order %d, dt = %g s; the motion reaches omega_max = %.4g "
           "rad/s (a dop853 probe of the run: spring, near-pivot and rotation rates, drive%s), "
           "stability limit dt <= %.4g s (%s's step for a damped oscillator at omega_max, "
           "b/m = %g 1/s): margin %.3gx\n", mi->name, mi->order, sc->integrator.dt,
           a->omega_max, isnan(a->pass_distance) ? "" : "; close passes by the pivot left out",
           a->limit, mi->name, sim->p.b_over_m, in->margin);
    if (!isnan(a->pass_distance))
        printf("  close pass       the probe's bob passes %.3g m from the pivot at %.3g m/s, "
               "where the spring's push (at most k L0 = %.3g N, so no rate to keep stable) "
               "turns round within d / v = %.2g s; a fixed step follows such a pass only "
               "with dt < %.2g s (about %.2g steps over the run: impractical, so the pass is "
               "left out of omega_max) and loses some energy at each pass it steps over\n",
               a->pass_distance, a->pass_speed, sc->pendulum.stiffness * L0,
               a->pass_distance / a->pass_speed, a->pass_distance / a->pass_speed,
               sc->video.duration * a->pass_speed / a->pass_distance);
    if (a->scene_ok)
        printf("  this dt          completes the run (checked over [0, %g] s)\n",
               a->scene_checked);
    if (!isnan(in->adaptive_checked)) {
        if (!a->scene_ok)
            printf("warning: dt = %g s is stopped at t = %.4g s%s\n", sc->integrator.dt,
                   a->scene_fail_t, a->scene_fail_pass ? ": not a blow-up, it lost energy at a "
                   "close pass by the pivot that it stepped over" : " as unstable");
        if (isnan(a->safe))
            printf("  fixed step       impractical: no step down to 1e-12 of the stability "
                   "limit completed past the close passes by the pivot\n");
        else if (in->impractical)
            printf("  fixed step       impractical: past the close passes by the pivot it needs "
                   "dt = %g s to keep drift under %g%% (checked over [0, %g] s only; the run "
                   "would take %.3g steps)\n", a->safe, 100 * 0.1 * SP_SIM_DRIFT_LIMIT,
                   a->checked, sc->video.duration / a->safe);
        else
            printf("  safe dt          %g s (completes the run over [0, %g] s with drift under "
                   "%g%%), held down by close passes by the pivot (a longer step lost energy "
                   "at one): a longer or other run may pass closer and need less\n", a->safe,
                   a->checked, 100 * 0.1 * SP_SIM_DRIFT_LIMIT);
        printf("  use              integrator.method = dop853: its steps shrink at each pass "
               "(the run completes with it over [0, %g] s with drift under %g%%)\n",
               in->adaptive_checked, 100 * 0.1 * SP_SIM_DRIFT_LIMIT);
        return;
    }
    if (!a->scene_ok && !isnan(a->safe))
        printf("warning: dt = %g s is stopped as unstable at t = %.4g s. Use integrator.dt = "
               "%g (it completes the run over [0, %g] s with drift under %g%%) or "
               "integrator.method = dop853\n", sc->integrator.dt, a->scene_fail_t, a->safe,
               a->checked, 100 * 0.1 * SP_SIM_DRIFT_LIMIT);
    else if (!a->scene_ok)
        printf("warning: dt = %g s is stopped as unstable at t = %.4g s, and no step down to "
               "1e-12 of it completed; use integrator.method = dop853\n", sc->integrator.dt,
               a->scene_fail_t);
    else if (!isnan(a->safe))
        printf("  safe dt          %g s (completes the run over [0, %g] s with drift under "
               "%g%%)\n", a->safe, a->checked, 100 * 0.1 * SP_SIM_DRIFT_LIMIT);
}

static void print_text(const struct sp_cli_options *o, const struct sp_scene *sc,
                       const struct sp_sim *sim, const struct info *in)
{
    print_frequencies(o, sc, in);
    print_exchange(sc, in);
    if (in->spatial)
        print_spatial(sc, sim, in);
    if (in->damped)
        print_damping(in);
    if (in->driven)
        print_drive(sc, sim, in);
    print_energy_video(sc, in);
    print_integrator(sc, sim, in);
}

/* A number, or null where it does not apply. */
static void json_num(const char *key, double v, int last)
{
    if (isfinite(v))
        printf("  \"%s\": %.10g%s\n", key, v, last ? "" : ",");
    else
        printf("  \"%s\": null%s\n", key, last ? "" : ",");
}

static void print_json(const struct sp_scene *sc, const struct sp_sim *sim,
                       const struct info *in)
{
    const int fixed = !sp_method_info(sc->integrator.method)->adaptive;
    printf("{\n  \"scene\": ");
    sp_report_json_string(stdout, sc->name);
    printf(",\n");
    json_num("equilibrium_length", in->ph.ell, 0);
    json_num("omega_spring", in->ph.omega_s, 0);
    json_num("omega_pendulum", in->ph.omega_p, 0);
    json_num("ratio", in->ph.ratio, 0);
    printf("  \"near_2_1\": %s,\n", in->near21 ? "true" : "false");
    json_num("exchange_rate", in->near21 && !in->ex_beyond ? in->ex.rate : NAN, 0);
    json_num("exchange_time", in->ex.time, 0);
    json_num("exchange_swing_share", in->ex.swing_share, 0);
    const int prec = in->spatial && in->prec_ok;
    json_num("precession_per_exchange", prec ? in->prec.angle : NAN, 0);
    json_num("precession_period", prec ? in->prec.period : NAN, 0);
    printf("  \"precession_applies\": %s,\n",
           !prec || isnan(in->prec.angle) ? "null" : in->prec.applies ? "true" : "false");
    printf("  \"bounce_regime\": %s%s%s,\n", in->damped ? "\"" : "",
           in->damped ? regime_name(in->bounce.regime) : "null", in->damped ? "\"" : "");
    printf("  \"swing_regime\": %s%s%s,\n", in->damped ? "\"" : "",
           in->damped ? regime_name(in->swing.regime) : "null", in->damped ? "\"" : "");
    json_num("bounce_decay_time", in->damped ? in->bounce.energy_time : NAN, 0);
    json_num("swing_decay_time", in->damped ? in->swing.energy_time : NAN, 0);
    json_num("drive_omega", in->driven ? sim->p.drive_omega : NAN, 0);
    json_num("drive_bounce_amplitude", in->driven ? in->drive.bounce_amp : NAN, 0);
    json_num("drive_modulation", in->driven ? in->drive.h : NAN, 0);
    json_num("drive_swing_growth", in->driven ? in->drive.growth : NAN, 0);
    json_num("drive_seed_share", in->driven ? in->drive.seed_share : NAN, 0);
    json_num("drive_time_10x", in->driven ? in->drive.time_10x : NAN, 0);
    json_num("energy_kinetic", in->e.kinetic, 0);
    json_num("energy_spring", in->e.spring, 0);
    json_num("energy_gravity", in->e.gravity, 0);
    json_num("energy_total", in->e.total, 0);
    json_num("energy_bounce", in->e.bounce, 0);
    json_num("energy_swing", in->e.swing, 0);
    json_num("video_length", sp_timeline_length(sc), 0);
    printf("  \"video_frames\": %d,\n", sp_timeline_frames(sc));
    printf("  \"method\": \"%s\",\n", sp_method_info(sc->integrator.method)->name);
    json_num("dt", fixed ? sc->integrator.dt : NAN, 0);
    json_num("omega_max", fixed ? in->dt.omega_max : NAN, 0);
    json_num("stability_limit", fixed ? in->dt.limit : NAN, 0);
    json_num("stability_margin", fixed ? in->margin : NAN, 0);
    printf("  \"dt_completes\": %s,\n", !fixed ? "null" : in->dt.scene_ok ? "true" : "false");
    json_num("dt_checked_until", fixed ? in->dt.scene_checked : NAN, 0);
    json_num("safe_dt", fixed ? in->dt.safe : NAN, 0);
    json_num("safe_dt_checked_until", fixed && !isnan(in->dt.safe) ? in->dt.checked : NAN, 0);
    json_num("pass_distance", fixed ? in->dt.pass_distance : NAN, 0);
    json_num("pass_speed", fixed ? in->dt.pass_speed : NAN, 0);
    printf("  \"adaptive_method\": %s,\n", isnan(in->adaptive_checked) ? "null" : "\"dop853\"");
    json_num("adaptive_checked_until", in->adaptive_checked, 1);
    printf("}\n");
}

static int info_scene(const struct sp_cli_options *o, const struct sp_scene *sc,
                      const volatile sig_atomic_t *cancel);

int sp_cmd_info(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    struct sp_cli_options o;
    struct sp_scene sc;
    int ret = sp_cli_parse(&o, argc, argv, info_usage, SP_CLI_TAKES_JSON);
    if (ret)
        return ret > 0 ? 0 : ret;
    /* a --set key info does not read is refused, as data refuses one
     * (attack15 #13): it prints the physics and the video's length */
    static const char *const read[] = {"pendulum", "initial", "pivot", "integrator",
                                       "video.duration", "video.fps", "video.speed"};
    ret = sp_cli_check_set_read(&o, "info", read, sizeof(read) / sizeof(read[0]), 0,
                                "the [pendulum], [initial], [pivot] and [integrator] keys and "
                                "video.duration, fps and speed (the video's length); it draws "
                                "nothing");
    if (!ret)
        ret = sp_cli_load_scene(&o, &sc);
    if (ret)
        return ret;
    ret = info_scene(&o, &sc, cancel);
    sp_scene_free(&sc);
    return ret;
}

/* info on a loaded scene. */
static int info_scene(const struct sp_cli_options *op, const struct sp_scene *scene,
                      const volatile sig_atomic_t *cancel)
{
    const struct sp_cli_options o = *op;
    const struct sp_scene sc = *scene; /* shares the timeline: freed by the caller */
    struct sp_sim sim;
    struct info in = {.adaptive_checked = NAN};
    int ret;
    sp_sim_init(&sim, &sc);
    sp_state_energy(&sim.p, &sim.s, &in.e);
    sp_params_physics(&sim.p, &in.ph);
    /* the exchange and precession by the rules the HUD uses too */
    struct sp_prediction pd;
    sp_advise_predict(&sim.p, &sim.s, sim.spatial, &pd);
    in.near21 = pd.near21;
    in.ex = pd.ex;
    in.spatial = pd.spatial;
    in.prec = pd.prec;
    in.prec_ok = pd.prec_ok;
    in.ex_amplitude = pd.amplitude;
    in.ex_beyond = pd.ex_beyond;
    in.damped = sim.p.b_over_m > 0;
    if (in.damped) {
        sp_advise_decay(in.ph.omega_s, sim.p.b_over_m, &in.bounce);
        sp_advise_decay(in.ph.omega_p, sim.p.b_over_m, &in.swing);
    }
    in.driven = sp_advise_drive(&sim.p, &sim.s, &in.drive) == 0;
    if (!sp_method_info(sc.integrator.method)->adaptive) {
        ret = sp_advise_dt(&sc, sc.video.duration, cancel, &in.dt);
        if (ret)
            return ret;
        in.margin = in.dt.limit / sc.integrator.dt;
        /* the safe dt held down by the passes, not the limit: dop853 */
        in.impractical = in.dt.pass_bound &&
                         (isnan(in.dt.safe) || in.dt.checked < sc.video.duration);
        double checked;
        if (in.dt.pass_bound) {
            ret = sp_advise_adaptive(&sc, sc.video.duration, cancel, &checked);
            if (ret == SP_E_INTERRUPTED)
                return ret;
            if (ret == 0 && checked >= sc.video.duration)
                in.adaptive_checked = checked;
        }
    }
    if (o.info.json)
        print_json(&sc, &sim, &in);
    else
        print_text(&o, &sc, &sim, &in);
    return 0;
}
