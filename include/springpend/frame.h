/* springpend: the frame model, what one rendered frame shows. Built from sim
 * samples, consumed by render; knows nothing of GL or files. */
#ifndef SPRINGPEND_FRAME_H
#define SPRINGPEND_FRAME_H

#include "springpend/advice.h"
#include "springpend/sim.h"

struct sp_history;
struct sp_ensemble;
struct sp_moment;
struct sp_timeline;

/* A trail point: where the bob was, when, and how fast it went. */
struct sp_trail_point {
    float x, y;  /* m */
    float z;     /* m, out of the starting plane (0 planar) */
    float speed; /* m/s */
    double t;    /* s */
};

/* Ring buffer of the last `capacity` bob positions, oldest first on read. */
struct sp_trail {
    struct sp_trail_point *points; /* capacity entries, owned */
    int capacity;                  /* 0 = no trail, nothing allocated */
    int count;                     /* valid points, <= capacity */
    int head;                      /* index where the next point goes */
};

int sp_trail_make(struct sp_trail *tr, int capacity);
void sp_trail_destroy(struct sp_trail *tr);
void sp_trail_push(struct sp_trail *tr, const struct sp_state *s);
/* The same with the pivot at height pivot_y (m): the trail is kept in the lab. */
void sp_trail_push_at(struct sp_trail *tr, const struct sp_state *s, double pivot_y);
/* Advances sim to t_target through sp_history_follow in `substeps` equal
 * steps, pushing a trail point (pivot at its height) after each, so that the
 * trail follows the motion between frames. 0 or sp_sim_advance's error. */
int sp_trail_follow(struct sp_trail *tr, struct sp_history *h, struct sp_sim *sim,
                    double t_target, int substeps);

/* Substeps per frame interval dt (s) for a trail drawn at px_per_m whose
 * bob accelerates at most by accel (m/s^2): chords then stay within half a
 * pixel of the path (sagitta a h^2 / 8). At least 1, at most 64. */
int sp_trail_substeps(double dt, double accel, double px_per_m);

/* i-th point, 0 = oldest, count-1 = newest. */
const struct sp_trail_point *sp_trail_at(const struct sp_trail *tr, int i);

struct sp_range {
    double lo, hi;
};

/* The world rectangle the camera must keep in view, m, the speed range that
 * the trail's colormap spans, m/s, and the ranges the panels' axes span (so
 * they do not jump). Found by a physics pre-pass over every step. */
struct sp_view_extent {
    double xmin, xmax, ymin, ymax; /* m, in the lab: the pivot's rest position at
                                      (0,0), its whole travel and the bob's */
    double zmin, zmax;             /* m: the bob's, out of the plane (0 planar) */
    double max_speed;              /* m/s, > 0 */
    double t_end;                  /* s, the time axis spans [0, t_end] */
    struct sp_range r;             /* m */
    struct sp_range theta;         /* rad */
    struct sp_range r_dot;         /* m/s */
    struct sp_range theta_dot;     /* rad/s */
    struct sp_range energy;        /* J, of total, kinetic, spring and gravity,
                                      gravity (and so the total) from y_low */
    struct sp_range modes;         /* J, of the bounce and swing energies */
    /* [view] vectors (0 when none is drawn): the largest each arrow gets */
    double max_accel;              /* m/s^2, relative to the pivot */
    double max_force;              /* N, of the forces [view] vectors draws */
    /* the energy and energy_bars panels (y_low 0 when neither is shown) */
    double y_low;                  /* m: the lowest the bob goes relative to the
                                      pivot; its gravity energy is 0 there, in
                                      both panels */
    struct sp_range bars;          /* J: every bar, gravity from y_low, within it */
    struct sp_range azimuth;       /* rad, the swing plane's (continuous) */
    double horizontal;             /* m: the largest |x| and |z| (the top view) */
};

/* Runs the scene's physics from 0 to t_end (cheaply, no rendering) and
 * returns the extent of the bob and pivot. The sim's hooks are the caller's
 * (see struct sp_sim): cancel (NULL = never) stops it with
 * SP_E_INTERRUPTED, progress (NULL = none) hears the simulated time with
 * progress_ctx. Fails with SP_E_UNSTABLE like sp_sim_advance. */
int sp_view_extent_measure(const struct sp_scene *scene, double t_end,
                           const volatile sig_atomic_t *cancel,
                           void (*progress)(void *ctx, double t), void *progress_ctx,
                           struct sp_view_extent *out);

/* What a frame's look is made of, all the composer reads of a scene: its
 * [view], two [video] numbers (the trail's length in frames) and whether
 * an ensemble is drawn. */
struct sp_look {
    struct sp_view view;
    double fps;         /* [video] fps: frames per second of video */
    double speed;       /* [video] speed: simulated s per s of video */
    int ensemble_count; /* [ensemble] count: > 1 draws its members */
    double pt_px;       /* a figure of physical size (still --size 8.6cm): output px
                           per pt, and text, lines, ticks and markers are set in
                           pt (print defaults: 10 pt text, 0.8 pt axes, 3.5 pt
                           ticks); 0 = a video frame, sizes follow the frame */
    int still;          /* 1: a still (still command): view.cursor = auto leaves
                           the video's marks of now out */
    const struct sp_timeline *timeline; /* [timeline], NULL = none: the caption
                                           band holds its largest text, the
                                           frame's sp_moment says what shows */
    char differs[SP_VIEW_TEXT_BYTES];   /* side by side: the keys in which this
                                           scene differs from the others, with
                                           its values ("stiffness = 5"), listed
                                           in the HUD; "" = alone */
    const char *title_what; /* what view.title is, for messages; NULL = the
                               scene's "[view] title" (side by side: the
                               cell's automatic label) */
    int perspective;    /* 1: the pendulum is drawn through view.camera's
                           perspective (sp_scene_perspective) */
    int spatial;        /* 1: a 3-D scene (initial.azimuth_rate != 0) */
    struct sp_prediction predict; /* with view.hud: what the HUD may state
                                     of the frequencies, the 2:1 check and a
                                     3-D scene's precession, by info's rules
                                     (sp_advise_predict) */
};

/* The look of scene, or of the default scene when scene is NULL. */
void sp_look_of(const struct sp_scene *scene, struct sp_look *out);

/* What the panels plot, sampled at each frame time (and between frames that
 * are far apart for the motion). */
struct sp_history_sample {
    float t;                        /* s */
    float x, y;                     /* m, bob in the lab (for stroboscopic images) */
    float r, theta;                 /* m, rad */
    float r_dot, theta_dot;         /* m/s, rad/s */
    float kinetic, spring, gravity; /* J */
    float bounce, swing;            /* J, see struct sp_energy */
    float z;                        /* m, out of the starting plane (0 planar) */
    float azimuth;                  /* rad, the swing plane's (sim.h), continuous */
};

/* A Poincare point: the bob passing theta = 0 with dtheta/dt > 0. */
struct sp_crossing {
    double t;         /* s */
    double r;         /* m */
    double r_dot;     /* m/s */
    double theta_dot; /* rad/s, > 0 */
};

/* The panels' memory: samples at frame times and every Poincare crossing so
 * far. Allocated only when the scene asks for panels or a strobe. */
/* The swing plane's turn per exchange measured from the run so far (a 3-D
 * scene's heads-up text): the swing energy is averaged over one pendulum
 * period 2 pi / omega_p (a window ending at each new sample); a maximum of
 * that mean counts once the mean has fallen back by a quarter of the
 * exchange's depth (and the depth is over a tenth of the maximum, so a
 * motion without exchange counts none); the plane's azimuth there is the
 * samples' (sp_state_azimuth, continuous) at the window's middle. A maximum
 * at the start counts only after a trough. */
struct sp_precession_meter {
    double window;    /* s: one pendulum period; 0 = not measured */
    double sum;       /* J s: the swing energy's integral over the window */
    int lo, mid;      /* the window's oldest sample; the last at or before its middle */
    int started;      /* 1: a full window has been seen */
    int rising;       /* 1: past a trough, looking for the next maximum */
    double top, top_az, top_t; /* J, rad, s: the candidate maximum */
    double low, high; /* J: the trough since the last maximum; the last maximum */
    int peaks;        /* maxima confirmed */
    double first_az, last_az; /* rad: the plane's azimuth at the first and last */
    double last_t;    /* s: the last confirmed maximum */
};

struct sp_history {
    int active;                        /* 0: nothing kept, nothing sampled */
    int poincare;                      /* 1: crossings are looked for */
    int crossings_only;                /* 1: no samples kept (data --poincare) */
    struct sp_history_sample *samples; /* count valid, oldest first, owned */
    int count, capacity;
    struct sp_crossing *crossings;     /* n_crossings valid, in time order, owned */
    int n_crossings, cap_crossings;
    double max_step;                   /* s: longest interval interpolated over */
    double loss;                       /* J: energy lost to damping up to the newest
                                          sample (trapezoid rule over the samples) */
    double azimuth;                    /* rad: the newest sample's azimuth, unrounded */
    int measure;                       /* 1: meter runs (3-D, heads-up text on) */
    struct sp_precession_meter meter;  /* the precession measured so far */
};

/* The measured turn per exchange so far, rad (mean over the completed
 * exchanges between the first and the last maximum counted); NAN before
 * two maxima. *peaks (may be NULL): the maxima counted. */
double sp_history_precession(const struct sp_history *h, int *peaks);

/* Sets h up for scene: active when view.panels or view.strobe ask for it,
 * or the heads-up text of a 3-D scene (its measured precession), looking
 * for crossings when the Poincare panel is shown. 0 or SP_E_NOMEM. */
int sp_history_make(struct sp_history *h, const struct sp_scene *scene);
void sp_history_destroy(struct sp_history *h);

/* Advances sim to t_target (as sp_sim_advance does) and, when h is active,
 * records samples up to t_target (at least one every h->max_step, a tenth of a
 * radian of the fastest oscillation: the sim is stopped more often only when
 * frames are farther apart than that) and every crossing on the way, located
 * on the quintic Hermite interpolant (positions, velocities and accelerations
 * at both ends) of each interval. */
int sp_history_follow(struct sp_history *h, struct sp_sim *sim, double t_target);

struct sp_frame {
    struct sp_state state;        /* the bob now */
    const struct sp_params *params;
    const struct sp_trail *trail; /* may be NULL or empty */
    const struct sp_history *history; /* may be NULL or inactive */
    const struct sp_ensemble *ensemble; /* NULL, or [ensemble]'s members drawn
                                           instead of the one bob (ensemble.h) */
    const struct sp_moment *moment; /* NULL, or what the [timeline] shows now: the
                                       caption band's text and the speed marker
                                       (timeline.h) */
    double work;    /* J: done on the bob by damping and the drive since t = 0 (sp_sim) */
    int ended;      /* side by side: this scene's video ended before the longest's;
                       it holds its last frame, marked as ended */
    double energy0; /* J: the total energy at t = 0 (sp_sim) */
};

#endif
