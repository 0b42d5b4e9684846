/* springpend: what `info` predicts about a scene: the step a fixed-step
 * method needs (found by probing the run itself), the bounce-swing exchange
 * near 2:1 (Lynch's averaged equations), the damping's decay times and the
 * driven pivot's parametric resonance. Pure: no I/O. */
#ifndef SPRINGPEND_ADVICE_H
#define SPRINGPEND_ADVICE_H

#include "springpend/sim.h"

/* A fixed-step method's step for a scene, found by running it. */
struct sp_dt_advice {
    double omega_max;    /* rad/s: the fastest rate the motion reaches over a
                          * dop853 probe of the run: sqrt(k/m), the spring's
                          * tangential rate sqrt(k/m |1 - L0/r|), the rotation
                          * |v|/r, sqrt(g/l), the drive; inside close passes
                          * (r < L0 / 2) only where steps of 1 / rate cover the
                          * run in 2e6, else see pass_distance */
    double pass_distance; /* m: where close passes were left out of omega_max,
                          * the one with the shortest r / |v|, its distance from
                          * the pivot; NAN otherwise. A fixed step follows it
                          * only with dt < pass_distance / pass_speed (no
                          * stability limit: a longer step loses some energy at
                          * each pass, which the runs for safe measure) */
    double pass_speed;   /* m/s: the bob's speed there */
    double limit;        /* s: where the method's one-step map of the damped
                          * oscillator x'' = -w^2 x - (b/m) x' first grows, at
                          * w = omega_max and at w = 0 (RK4: 2.83 / w undamped,
                          * 2.785 / (b/m) on the negative real axis; verlet takes
                          * the damping as its exact flow and keeps 2 / w;
                          * yoshida4's backward substep amplifies under damping) */
    double safe;         /* s: a step the run completed with, its drift under a
                          * tenth of the blow-up guard's; one significant digit */
    int pass_bound;      /* 1: a longer step than safe (or every step tried)
                          * was stopped losing energy at a close pass
                          * (sp_advise_failed_at_pass), not by the limit */
    double checked;      /* s: safe and the scene's dt were run over [0, checked]
                          * (t_end, or less where that takes over 2e6 steps) */
    int scene_ok;        /* 1: the scene's own dt completed over [0, scene_checked] */
    double scene_checked; /* s */
    double scene_fail_t; /* s: where the scene's dt was stopped (scene_ok 0) */
    int scene_fail_pass; /* 1: stopped losing energy at a close pass, not
                          * blowing up (sp_advise_failed_at_pass) */
};

/* Fills *out for sc's fixed-step method over [0, t_end]. Adaptive methods:
 * SP_E_INPUT (they choose their own steps). SP_E_INTERRUPTED once the
 * caller's *cancel is set (NULL = never). Otherwise 0. */
int sp_advise_dt(const struct sp_scene *sc, double t_end, const volatile sig_atomic_t *cancel,
                 struct sp_dt_advice *out);

/* 1 when sim, a fixed-step run that sp_sim_advance stopped as unstable, was
 * not blowing up but lost energy at a pass close by the pivot (r < L0 / 2)
 * that its step was too long to follow (sim->failure.pass_*), with a step
 * well inside the method's stability limit; 0 otherwise. */
int sp_advise_failed_at_pass(const struct sp_sim *sim);

/* Runs sc with dop853 (at its tolerance, at most 1e-9) over [0, t_end],
 * keeping a tenth of the guard's drift, for at most 2e7 evaluations;
 * *checked: s, how far it went (t_end, or less where the evaluations ran out).
 * 0 when it got that far; SP_E_UNSTABLE, or SP_E_INTERRUPTED once the
 * caller's *cancel is set (NULL = never). */
int sp_advise_adaptive(const struct sp_scene *sc, double t_end,
                       const volatile sig_atomic_t *cancel, double *checked);

/* The bounce-swing exchange near 2:1, from Lynch's averaged equations for the
 * complex amplitudes of the swing, x = Re(A e^{i w_p t}) (x = l theta), and of
 * the bounce, r - l = Re(B e^{i w_s t}):
 *   A' = i k_A B A* e^{i d t},  B' = i k_B A^2 e^{-i d t},
 *   k_A = 3 w_p / (4 l),  k_B = k_A w_p^2 / w_s^2,  d = w_s - 2 w_p,
 * so |A| first grows at Lynch's rate s = k_A |B0| = (L0 / l^2) w_p B0 at 2:1. */
struct sp_exchange {
    double rate;        /* 1/s: s = 3 w_p |B0| / (4 l), the start's growth rate */
    double time;        /* s: the first maximum of the swing energy, NAN if none
                         * is expected (no swing or no bounce to start from) */
    double swing_share; /* swing energy / (swing + bounce) at that maximum */
    double epsilon;     /* the start's amplitude as a fraction of l, max(|A|, |B|) / l
                         * of the plane's swing and the bounce (NAN when not near 2:1) */
};

/* The largest start amplitude, as a fraction of l (sp_exchange's and
 * sp_precession's epsilon), at which info states the averaged equations'
 * predictions at all: they expand in small amplitudes (accurate to a few %
 * up to 0.065 l, doc/physics.md), and beyond half of l the motion is no slow
 * exchange (chaotic.ini, 1.5 rad, or a bob flung out by a huge
 * azimuth_rate): info then says they do not apply. */
#define SP_ADVISE_AMPLITUDE_MAX 0.5

/* Fills *out for the motion starting at s0 (t = 0). 0, or SP_E_INPUT when the
 * scene is not within 10% of 2:1 (no exchange: out->time is NAN). */
int sp_advise_exchange(const struct sp_params *p, const struct sp_state *s0,
                       struct sp_exchange *out);

/* The swinging spring's stepwise precession (Lynch 2002; Lynch and
 * Houghton, Physica D 2004), from the same averaged (three-wave) equations
 * in three dimensions: the horizontal swing h = (x, z) = Re(A e^{i w_p t})
 * with A = (A_x, A_z) complex, the bounce r - l = Re(B e^{i w_s t}):
 *   A' = i k_A B conj(A) e^{i d t},  B' = i k_B (A_x^2 + A_z^2) e^{-i d t}
 * (k_A, k_B, d as for sp_exchange), integrated numerically over several
 * exchanges. The swing plane's azimuth is the major axis of
 * Re(A) Re(A)^T + Im(A) Im(A)^T (sim.h's sp_state_azimuth for the averaged
 * motion); the precession per exchange is its turn between successive
 * maxima of the swing |A|^2. The theory applies to small amplitudes near
 * 2:1 without damping or drive; `applies` says whether this scene is
 * within what doc/physics.md's table measured (its accuracy there), and `why`
 * what puts it outside. */
struct sp_precession {
    int applies;       /* 1: amplitudes up to 0.065 l, within 1% of 2:1, no
                        * damping or drive, and an exchange to measure */
    const char *why;   /* applies 0: what puts the scene outside, in words */
    double epsilon;    /* the start's amplitude about the hanging equilibrium
                        * as a fraction of l: max(|A|, |B|) / l with |A| = l
                        * sqrt(th^2 + (v_t / (r w_p))^2), th the angle from
                        * the downward vertical, v_t the velocity across the
                        * spring (a start near the top is far from small) */
    double angle;      /* rad: the swing plane's turn per exchange (from
                        * +x towards +z), NAN when there is no exchange */
    double period;     /* s: between successive maxima of the swing */
    double first_peak; /* s: the first maximum of the swing after t = 0 */
    int exchanges;     /* maxima found (the angle averages over them, - 1) */
    double swing_share; /* swing energy / (swing + bounce) at the first maximum */
};

/* Fills *out for the motion starting at s0 (t = 0); 0, or SP_E_INPUT when
 * there is nothing to predict (no gravity, or further than 10% from 2:1:
 * out->why says). */
int sp_advise_precession(const struct sp_params *p, const struct sp_state *s0,
                         struct sp_precession *out);

/* What `info` and the heads-up text state about a scene's start, decided
 * once, here, so that the two never disagree: the frequencies, whether a
 * pendulum frequency (and so a ratio and a 2:1 check) exists at all, the
 * exchange and, in 3-D, the precession, with the small-amplitude rule
 * applied: beyond SP_ADVISE_AMPLITUDE_MAX of l (the amplitude measured about
 * the hanging equilibrium, sp_precession.epsilon) neither is predicted. */
struct sp_prediction {
    struct sp_physics ph;
    int swings;        /* 1: g > 0: omega_p, the ratio and the 2:1 check exist;
                        * 0: none of them does (no pendulum frequency) */
    int near21;        /* within 10% of 2:1 (sp_advise_exchange returned 0) */
    struct sp_exchange ex; /* time and swing_share NAN where not predicted; in
                            * 3-D the three-wave motion's first swing peak */
    double amplitude;  /* the start's amplitude / l (3-D: prec.epsilon) */
    int ex_beyond;     /* 1: near 2:1 but amplitude > SP_ADVISE_AMPLITUDE_MAX:
                        * the exchange is not predicted */
    int spatial;       /* 1: a 3-D scene: prec below is filled */
    struct sp_precession prec; /* angle NAN and applies 0 where not predicted */
    int prec_ok;       /* 1: a precession is stated (prec.angle, maybe NAN
                        * with prec.why when there is no exchange); 0: not
                        * predicted, prec.why says why */
    const char *brief; /* 3-D: "" when prec.angle is stated, else why not in a
                        * few words (the HUD's); NULL for a planar scene */
};

/* Fills *out for the motion starting at s0 (spatial: a 3-D scene). 0. */
int sp_advise_predict(const struct sp_params *p, const struct sp_state *s0, int spatial,
                      struct sp_prediction *out);

/* Linear damping of one mode of angular frequency omega, gamma = b/m. */
struct sp_decay {
    int regime;         /* -1 underdamped, 0 critical (within 1%), 1 overdamped */
    double energy_time; /* s: the e-folding time of the mode's energy: 1/gamma
                         * under- and critically damped (times (1 + omega t)^2
                         * at critical), 1/(2 s_slow) overdamped with the slow
                         * root s_slow = gamma/2 - sqrt(gamma^2/4 - omega^2) */
    double q;           /* quality factor omega / gamma */
};

void sp_advise_decay(double omega, double gamma, struct sp_decay *out);

/* The driven pivot, y_p = A sin(Omega t). The bounce is forced directly
 * (amplitude |Z| below, resonant at Omega = omega_s; a vertical drive leaves
 * the spring's stiffness alone, so there is no parametric resonance of the
 * bounce at 2 omega_s). The swing, x, obeys
 *   x'' + gamma x' + (w_p^2 + w_s^2 (L0 / l^2) z(t)) x = 0
 * with z the forced bounce: a Mathieu equation, parametric resonance at
 * Omega = 2 w_p, amplitude growth rate sqrt((w_p h / 4)^2 - detuning^2) -
 * gamma / 2 with h = w_s^2 L0 |Z| / (g l) (exact at small swing). */
struct sp_drive_advice {
    double bounce_amp;  /* m: |Z|, the forced bounce */
    double h;           /* the swing stiffness' relative modulation */
    double detuning;    /* rad/s: (w_p^2 - (Omega/2)^2) / Omega */
    double growth;      /* 1/s: the swing amplitude's growth rate; <= 0: none */
    double tongue;      /* rad/s: |Omega/2 - w_p| below which growth is possible
                         * undamped, w_p h / 4 */
    double seed_share;  /* the start's swing in the growing mode, as a fraction
                         * of its amplitude (the rest decays first) */
    double time_10x;    /* s: until the swing is 10 times its start, NAN if it
                         * does not grow */
};

/* Fills *out; SP_E_INPUT (nothing filled) when the pivot is fixed. */
int sp_advise_drive(const struct sp_params *p, const struct sp_state *s0,
                    struct sp_drive_advice *out);

#endif
