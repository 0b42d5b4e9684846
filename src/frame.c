/* springpend: the frame model: the trail ring buffer and the view extent
 * found by a physics pre-pass. */
#include <math.h>
#include <stdlib.h>

#include "springpend/common.h"
#include "springpend/frame.h"

int sp_trail_make(struct sp_trail *tr, int capacity)
{
    *tr = (struct sp_trail){0};
    if (capacity <= 0)
        return 0;
    tr->points = calloc((size_t)capacity, sizeof(*tr->points));
    if (!tr->points) {
        sp_log_error("out of memory for a trail of %d points", capacity);
        return SP_E_NOMEM;
    }
    tr->capacity = capacity;
    return 0;
}

void sp_trail_destroy(struct sp_trail *tr)
{
    free(tr->points);
    *tr = (struct sp_trail){0};
}

void sp_trail_push(struct sp_trail *tr, const struct sp_state *s)
{
    if (tr->capacity == 0)
        return;
    tr->points[tr->head] = (struct sp_trail_point){
        .x = (float)s->x,
        .y = (float)s->y,
        .speed = (float)sqrt(s->vx * s->vx + s->vy * s->vy),
    };
    tr->head = (tr->head + 1) % tr->capacity;
    if (tr->count < tr->capacity)
        tr->count++;
}

const struct sp_trail_point *sp_trail_at(const struct sp_trail *tr, int i)
{
    int oldest = tr->count < tr->capacity ? 0 : tr->head;
    return &tr->points[(oldest + i) % tr->capacity];
}

int sp_view_extent_measure(const struct sp_scene *scene, double t_end,
                           struct sp_view_extent *out)
{
    struct sp_sim sim;
    sp_sim_init(&sim, scene);
    *out = (struct sp_view_extent){0};
    /* Sample every step: the camera must hold every position the bob takes. */
    for (;;) {
        const struct sp_state *s = &sim.s;
        double v = sqrt(s->vx * s->vx + s->vy * s->vy);
        out->xmin = fmin(out->xmin, s->x);
        out->xmax = fmax(out->xmax, s->x);
        out->ymin = fmin(out->ymin, s->y);
        out->ymax = fmax(out->ymax, s->y);
        out->max_speed = fmax(out->max_speed, v);
        if (s->t >= t_end)
            break;
        int ret = sp_sim_advance(&sim, fmin(t_end, s->t + sim.dt));
        if (ret)
            return ret;
    }
    if (out->max_speed <= 0)
        out->max_speed = 1;
    return 0;
}
