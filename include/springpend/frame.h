/* springpend: the frame model, what one rendered frame shows. Built from sim
 * samples, consumed by render; knows nothing of GL or files. */
#ifndef SPRINGPEND_FRAME_H
#define SPRINGPEND_FRAME_H

#include "springpend/sim.h"

/* A trail point: where the bob was, and how fast it went. */
struct sp_trail_point {
    float x, y;  /* m */
    float speed; /* m/s */
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
/* i-th point, 0 = oldest, count-1 = newest. */
const struct sp_trail_point *sp_trail_at(const struct sp_trail *tr, int i);

/* The world rectangle the camera must keep in view, m, and the speed range
 * that the trail's colormap spans, m/s. Found by a physics pre-pass. */
struct sp_view_extent {
    double xmin, xmax, ymin, ymax; /* m, pivot at (0,0) included */
    double max_speed;              /* m/s, > 0 */
};

/* Runs the scene's physics from 0 to t_end (cheaply, no rendering) and
 * returns the extent of the bob and pivot. Fails with SP_E_UNSTABLE like
 * sp_sim_advance. */
int sp_view_extent_measure(const struct sp_scene *scene, double t_end,
                           struct sp_view_extent *out);

struct sp_frame {
    struct sp_state state;        /* the bob now */
    const struct sp_params *params;
    const struct sp_trail *trail; /* may be NULL or empty */
};

#endif
