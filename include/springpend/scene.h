/* springpend: scene description, parsed from an INI file plus --set overrides.
 * Pure: no GL, no rendering, no output files. Units are SI; angles are stored
 * in radians (scene files give degrees). */
#ifndef SPRINGPEND_SCENE_H
#define SPRINGPEND_SCENE_H

#include <stdbool.h>
#include <stddef.h>

enum sp_method {
    SP_METHOD_RK4 = 0, /* classical Runge-Kutta, fixed dt */
    SP_METHOD_VERLET,  /* Stormer-Verlet, fixed dt, symplectic, order 2 */
    SP_METHOD_YOSHIDA4, /* Yoshida's triple jump, fixed dt, symplectic, order 4 */
    SP_METHOD_DOPRI5,  /* Dormand-Prince 5(4), adaptive, dense output */
    SP_METHOD_DOP853,  /* Dormand-Prince 8(5,3), adaptive, dense output */
    SP_METHOD_RKN1210, /* Runge-Kutta-Nystrom 12(10), adaptive, no damping or drive */
};

/* [view] panels: which charts are drawn beside the pendulum. */
enum sp_panel {
    SP_PANEL_R = 1 << 0,           /* r(t) strip chart */
    SP_PANEL_THETA = 1 << 1,       /* theta(t) */
    SP_PANEL_ENERGY = 1 << 2,      /* total energy and its kinetic/spring/gravity split */
    SP_PANEL_EXTENSION = 1 << 3,   /* r - L0 */
    SP_PANEL_PHASE_R = 1 << 4,     /* phase portrait r against dr/dt ("phase") */
    SP_PANEL_PHASE_THETA = 1 << 5, /* theta against dtheta/dt ("phase") */
    SP_PANEL_POINCARE = 1 << 6,    /* (r, dr/dt) where theta = 0 with dtheta/dt > 0 */
    SP_PANEL_MODES = 1 << 7,       /* energy split into bounce and swing */
    SP_PANEL_SPREAD = 1 << 8,      /* [ensemble]: log10 of the members' spread against t
                                      (not part of "all": it needs an ensemble) */
    SP_PANEL_AZIMUTH = 1 << 9,     /* the swing plane's azimuth against t (3-D; not in "all") */
    SP_PANEL_TOP = 1 << 10,        /* top view: the bob's path in (x, z) (3-D; not in "all") */
    SP_PANEL_ENERGY_BARS = 1 << 11, /* bars of the energies now on one fixed axis
                                       (not part of "all": "energy_bars") */
    SP_PANEL_COUNT = 12,
    SP_PANEL_ALL = SP_PANEL_SPREAD - 1, /* "all": every panel but spread, azimuth, top and
                                           energy_bars */
};
/* [view] vectors: arrows drawn from the bob. */
enum sp_vector {
    SP_VECTOR_VELOCITY = 1 << 0,     /* m/s, relative to the pivot */
    SP_VECTOR_ACCELERATION = 1 << 1, /* m/s^2, relative to the pivot */
    SP_VECTOR_GRAVITY = 1 << 2,      /* N: -m g */
    SP_VECTOR_SPRING = 1 << 3,       /* N: -k (r - L0) along the spring */
    SP_VECTOR_DAMPING = 1 << 4,      /* N: -b v, v relative to the air (the lab) */
    SP_VECTOR_DRIVE = 1 << 5,        /* N: the inertial force -m a_pivot of the
                                        pivot's frame (a driven pivot only) */
    SP_VECTOR_NET = 1 << 6,          /* N: their sum, m times the acceleration */
    SP_VECTOR_COUNT = 7,
    SP_VECTOR_FORCES = SP_VECTOR_GRAVITY | SP_VECTOR_SPRING | SP_VECTOR_DAMPING |
                       SP_VECTOR_DRIVE | SP_VECTOR_NET, /* "forces" */
};

enum sp_theme { SP_THEME_DARK = 0, SP_THEME_LIGHT = 1 };
enum sp_colormap { SP_COLORMAP_INFERNO = 0, SP_COLORMAP_VIRIDIS = 1, SP_COLORMAP_MAGMA = 2,
                   SP_COLORMAP_CIVIDIS = 3, SP_COLORMAP_GRAY = 4 };
/* [view] cursor: the video's marks of the present. */
enum sp_cursor { SP_CURSOR_AUTO = 0, /* in videos and frames, not in stills */
                 SP_CURSOR_SHOWN = 1, SP_CURSOR_HIDDEN = 2 };
#define SP_TRAIL_ALL (-1)
/* [view] trail given as a duration ("5s"): see view.trail_duration. */
#define SP_TRAIL_DURATION (-2)

/* Bytes of a short text key ([view] font, [ensemble] key), with the
 * terminating NUL. [view] title and caption have no byte limit: they are
 * heap strings (struct sp_scene's texts), held only to the frame they must
 * fit in (the composer's "cannot fit"). */
#define SP_VIEW_TEXT_BYTES 256
#define SP_BACKGROUND_THEME (-1)
/* [view] camera: how the pendulum is seen. */
enum sp_camera_mode {
    SP_CAMERA_AUTO = 0,  /* the front view for a planar scene, a perspective
                            from SP_CAMERA_AUTO_AZIMUTH, _ELEVATION for a 3-D one */
    SP_CAMERA_FRONT = 1, /* the front view: x right, y up, looking along -z,
                            no perspective (a planar scene's only view before) */
    SP_CAMERA_SET = 2,   /* a perspective from view.camera_azimuth, _elevation,
                            _distance */
};
#define SP_CAMERA_AUTO_AZIMUTH 35.0   /* degrees */
#define SP_CAMERA_AUTO_ELEVATION 25.0 /* degrees */
#define SP_BACKGROUND_TRANSPARENT (-2)

#define SP_SCENE_MAX_KEYS 96 /* room for the key table (scene.c checks it) */

struct sp_scene {
    char name[64];  /* file stem ("default" for scenes/default.ini) */
    struct {
        double natural_length; /* L0, m */
        double stiffness;      /* k, N/m */
        double mass;           /* m, kg */
        double gravity;        /* g, m/s^2 */
        double damping;        /* b, N*s/m (linear, on the bob's velocity) */
    } pendulum;
    struct {
        double length;      /* r0, m */
        double angle;       /* theta0, rad from the downward vertical */
        double length_rate; /* dr/dt at t = 0, m/s */
        double angle_rate;  /* dtheta/dt at t = 0, rad/s */
        double azimuth_rate; /* dphi/dt at t = 0, rad/s: the start's turning
                                about the vertical, phi from +x towards +z;
                                0 = the motion stays in the x-y plane */
    } initial;
    struct {
        enum sp_method method;
        double dt;        /* fixed step, s */
        double tolerance; /* adaptive methods' relative tolerance */
    } integrator;
    struct {
        double amplitude; /* vertical oscillation of the pivot, m */
        double frequency; /* Hz */
    } pivot;
    struct {
        int width, height; /* px */
        double fps;        /* video frames per second */
        double duration;   /* simulated seconds covered by the video */
        double speed;      /* simulated seconds per second of video */
        int crf;           /* encoder quality, 0 = the format's default */
        int preset;        /* encoder speed, index of [video] preset's
                              names; 0 = auto (the format's default) */
        int png_level;     /* PNG compression level 1..9 */
    } video;
    struct sp_view { /* named: the composer is handed this part alone (sp_look) */
        int trail;       /* trail length in frames, 0 = none, SP_TRAIL_ALL = whole
                            run, SP_TRAIL_DURATION = trail_duration */
        double trail_duration; /* simulated s of motion the trail shows, when
                                  trail = SP_TRAIL_DURATION */
        unsigned panels; /* SP_PANEL_* bits, 0 = none */
        signed char panel_order[SP_PANEL_COUNT]; /* bit numbers of panels in the order
                                                    the key listed them, -1 after the
                                                    last (see sp_scene_panel_order) */
        unsigned vectors; /* SP_VECTOR_* bits, 0 = none: arrows from the bob */
        int hud;         /* 1: time, parameters and resonance check as text */
        int theme;       /* enum sp_theme */
        int panel_background; /* 0 = the theme's panel colour; 1 = none: panels
                                 (and the arrows' legend) drawn on the frame's
                                 background, transparent in a transparent still */
        int background;  /* 0xRRGGBB, or SP_BACKGROUND_THEME / _TRANSPARENT */
        int colormap;    /* enum sp_colormap, for the trail's speed */
        int colorbar;    /* 1: a colourbar for the trail's speed */
        double strobe;   /* s between stroboscopic images of the bob, 0 = off */
        int pendulum;    /* 1: the pendulum is drawn; 0: the panels fill the frame */
        int fade;        /* 1: old trail and phase curves fade; 0: full strength */
        double font_scale; /* text size factor, 1 = default */
        double font_size;  /* body text, pt (1 pt = 1 px: see doc/teaching.md); 0 = from
                              the frame's size; font_scale multiplies it */
        char font[SP_VIEW_TEXT_BYTES]; /* fontconfig family, "" = DejaVu Sans (embedded) */
        /* Never NULL; any length. A scene's point into its texts (below);
         * a look's may point elsewhere (side by side's cell labels). */
        const char *title;   /* UTF-8, "" = none: above everything */
        const char *caption; /* UTF-8, "" = none: below everything */
        /* Where each was set, for messages: "FILE:LINE" or "--set view.title";
         * "" = nowhere (the default, or a cell label). Never NULL. */
        const char *title_where, *caption_where;
        /* A figure's style (stills and sweep figures alike; each is left out of
         * sp_scene_canonical at its default, so older PNGs keep their bytes): */
        int cursor;        /* enum sp_cursor: strip charts' time cursor, the dot at
                              the current state, the latest crossing, and their
                              "now" / "latest" legend entries */
        int legend;        /* 0 = auto (legends where a panel has series), 1 = none */
        int panel_titles;  /* 1: each panel (a sweep figure: the figure) has its
                              title; 0 = none */
        int panel_labels;  /* 0 = none, 1 = (a), (b), ..., 2 = (A), (B), ... in
                              the order panels lists them */
        double marker_size; /* pt, a marker's diameter (Poincare and sweep dots,
                               the current state); 0 = each figure's own */
        int palette;       /* series colours: 0 = the theme's, 1 = Okabe-Ito's
                              colour-blind-safe set */
        char xlabel[SP_VIEW_TEXT_BYTES];  /* "" = each axis's own name; several
                                             panels: one per panel, '|' between */
        char ylabel[SP_VIEW_TEXT_BYTES];  /* as xlabel */
        char colorbar_label[SP_VIEW_TEXT_BYTES]; /* "" = the colour bar's own name */
        /* Where xlabel, ylabel and colorbar_label (in that order) were set,
         * for the refusals of a label that cannot fit: "FILE:LINE" or
         * "--set view.xlabel"; "" = nowhere (the default). */
        char label_where[3][SP_VIEW_TEXT_BYTES];
        int camera;              /* enum sp_camera_mode */
        double camera_azimuth;   /* rad, SP_CAMERA_SET: the eye turned about the
                                    vertical from +z (the front) towards +x */
        double camera_elevation; /* rad, SP_CAMERA_SET: the eye above the
                                    horizontal, in (-90, 90) degrees */
        double camera_distance;  /* m, SP_CAMERA_SET: from the eye to the middle
                                    of the motion; 0 = fitted to the motion */
        char camera_where[SP_VIEW_TEXT_BYTES]; /* where view.camera was set, for
                                    the refusals that need the motion:
                                    "FILE:LINE" or "--set view.camera"; "" =
                                    nowhere (the default) */
        char text_size_where[SP_VIEW_TEXT_BYTES]; /* where font_size or font_scale
                                    was last set, as camera_where */
        char font_where[SP_VIEW_TEXT_BYTES]; /* where font was set, as camera_where */
    } view;
    struct {
        int count;     /* pendulums drawn together, 0 or 1 = no ensemble */
        char key[SP_VIEW_TEXT_BYTES]; /* the numeric physics key they differ in */
        double spread; /* total range of the key's values, in its file units */
        int trails;    /* 1: every member draws a short thin trail */
    } ensemble;
    /* [timeline] (timeline.h): captions, speed changes and pauses keyed by
     * simulated time; NULL = none. Owned by the scene sp_scene_parse filled
     * (free it with sp_scene_free); copies of the scene share it. */
    struct sp_timeline *timeline;
    /* The heap blocks view.title and view.caption (and their _where) point
     * into (NULL while the key is ""): owned by the scene sp_scene_parse
     * filled, freed by sp_scene_free; copies of the scene share them, as the
     * timeline. */
    char *texts[2];
    /* Where each key got its value, by its place in the key table: its line
     * in the scene file, -1 = a --set, 0 = its default. Read through
     * sp_scene_key_where. */
    int key_lines[SP_SCENE_MAX_KEYS];
};

/* Fills s with the original simulator's defaults (see scenes/default.ini). */
void sp_scene_defaults(struct sp_scene *s);

/* Parses INI text. `origin` names it in messages ("scenes/x.ini"). Each
 * override is "section.key=value", applied after the text. Numbers are read
 * whole and in decimal ([+-] digits [. digits] [e [+-] digits]: no hex, inf,
 * nan or blanks), in the text and in overrides alike. Every problem is
 * printed to stderr as "ORIGIN:LINE: message" (or "--set ARG: message") and
 * the call returns SP_E_INPUT after reporting all of them; s is then
 * unspecified. No I/O besides stderr, no exit. */
int sp_scene_parse(struct sp_scene *s, const char *text, const char *origin,
                   const char *const *overrides, int n_overrides);

/* Frees what sp_scene_parse allocated (the timeline, the title's and the
 * caption's text) and sets it to NULL (title and caption to ""); the other
 * keys stay. Safe on a scene without them. A failed parse frees them. Only
 * the timeline: sp_timeline_destroy(&s->timeline). */
void sp_scene_free(struct sp_scene *s);

/* Reads path and calls sp_scene_parse; the scene name is the file stem.
 * Whatever it returns, sp_scene_free(s) may follow. */
int sp_scene_load(struct sp_scene *s, const char *path,
                  const char *const *overrides, int n_overrides);

/* As sp_scene_load for the size bytes at text (NUL-terminated), which the
 * caller read from path: a NUL among them is refused; the scene name is
 * path's stem. */
int sp_scene_load_text(struct sp_scene *s, const char *path, const char *text, size_t size,
                       const char *const *overrides, int n_overrides);

/* Whether the commands that parse scenes from now on draw the scene's view
 * (render, still: 1, the default) or not (sweep, data, info, scene: 0). The
 * combinations only a drawing cannot show (a poincare panel or view.vectors
 * with a 3-D scene or a perspective camera) are refused only where it is
 * drawn; a sweep of chaotic.ini's physics in 3-D takes its [view] as it is. */
void sp_scene_view_drawn(int drawn);

/* 1 when the scene's pendulum is drawn in perspective: view.camera set, or
 * auto on a 3-D scene (initial.azimuth_rate != 0). */
int sp_scene_perspective(const struct sp_scene *s);

/* Frame times are indexed by int: a scene (its [timeline] included) makes
 * at most this many; what a command makes of them has its own limit
 * (render: video frames, data: rows). */
#define SP_MAX_FRAMES 1000000000

/* Number of video frames, N = round(duration * fps / speed), without the
 * timeline ([timeline] changes it for render and still: timeline.h;
 * data and sweep use this). */
int sp_scene_frame_count(const struct sp_scene *s);

/* Simulated time shown by frame k: k * speed / fps, s. */
double sp_scene_frame_time(const struct sp_scene *s, int k);

/* The encoder speed presets a scene can name ([video] preset, after
 * "auto"), fastest first: x264's names, which sink_video.c also maps to
 * VP9's cpu-used. The one list of them: X(name) once per preset. */
#define SP_VIDEO_PRESETS(X) X("ultrafast") X("superfast") X("veryfast") X("faster") \
    X("fast") X("medium") X("slow") X("slower") X("veryslow")

/* The [video] preset's name ("superfast", ...), or NULL for auto. */
const char *sp_scene_preset_name(const struct sp_scene *s);

/* Writes every key's value as "section.key=value\n" lines in the key
 * table's order (numbers with %.17g in stored units: angles in radians),
 * so two scenes that simulate and render alike give the same text whatever
 * their files' layout, comments or overrides. The name is left out.
 * Returns the length snprintf would need (write again if >= size). */
int sp_scene_canonical(const struct sp_scene *s, char *buf, size_t size);

/* Writes the scene as a scene file that sp_scene_parse reads back into the
 * same keys and timeline, bit for bit: every key under its [section], in
 * the key table's order, in file units (angles in degrees), choices and
 * panels by name, text in double quotes, numbers as the shortest decimal
 * that reads back exactly. The name is left out (a file's stem gives it).
 * Returns the length snprintf would need (write again if >= size). */
int sp_scene_write_ini(const struct sp_scene *s, char *buf, size_t size);

/* sp_scene_write_ini's text in a malloc'd string (free it), or NULL when
 * out of memory. */
char *sp_scene_ini(const struct sp_scene *s);

/* One canonical line's value as a scene file spells it, into buf: numbers
 * to 10 digits, angles in degrees, choices and panels by name, booleans
 * true/false, colours #rrggbb, theme or transparent. key is "section.name";
 * an unknown key or value is copied as it is. For messages (compare names
 * the keys that changed between two images' scenes). */
void sp_scene_canonical_display(const char *key, const char *value, char *buf, size_t size);

/* The unit of a numeric key "section.key" (KEY_REAL, degrees or integer), or
 * NULL when there is no such numeric key. */
const char *sp_scene_key_unit(const char *key);

/* Checks the text value as the parser reads the numeric key "section.key"
 * (decimal, a whole number for integer keys, the key's range; not the
 * whole-scene checks), printing a problem as "ORIGIN: message": for the
 * options that stand for a key (--fps, --size). 0 or SP_E_INPUT. */
int sp_scene_check_value(const char *key, const char *value, const char *origin);

/* Sets the numeric key "section.key" to value, in file units (degrees for
 * angles), with the parser's range checks and whole-scene checks; problems
 * are printed as "ORIGIN: message" and SP_E_INPUT is returned. */
int sp_scene_set_number(struct sp_scene *s, const char *key, double value, const char *origin);

/* The numeric key "section.key"'s value in file units (degrees for angles),
 * or NAN when there is no such numeric key. */
double sp_scene_get_number(const struct sp_scene *s, const char *key);

/* The bit numbers of view's panels in the order its panels key listed
 * them (bits listed by no name, such as those a command adds, after them in
 * bit order) into order[0..SP_PANEL_COUNT); returns how many. */
int sp_scene_panel_order(const struct sp_view *view, int order[SP_PANEL_COUNT]);

/* Where key ("view.panels") of the scene parsed from path got its value,
 * for a message that a command (not the parser) gives about it: "PATH:LINE",
 * "--set KEY", or "PATH" at its default; into buf. */
void sp_scene_key_where(const struct sp_scene *s, const char *key, const char *path, char *buf,
                        size_t size);

/* The name of the plot panels bit `bit` draws ("phase r", "phase theta":
 * the panel phase is two plots), for messages. */
const char *sp_scene_plot_name(int bit);

/* The i-th of n '|'-separated entries of a [view] label (xlabel, ylabel),
 * blanks around it removed, into buf: one entry serves every panel; an
 * empty one, or none for panel i, gives "". */
void sp_scene_label_part(const char *label, int i, char *buf, size_t size);

/* Prints every key with its default, unit and accepted range (for --help). */
void sp_scene_print_keys(void);

#endif
