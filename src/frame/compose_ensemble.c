/* springpend (internal): an ensemble's members in a frame. See compose.h. */
#include <math.h>
#include <stdlib.h>

#include "springpend/ensemble.h"
#include "camera.h"
#include "compose.h"

/* Sizes as fractions of the image's smaller side: smaller than the lone
 * bob's (0.022), as a hundred of them share the view. */
#define MEMBER_RADIUS 0.011f
#define ROD_WIDTH 0.0007f
#define TRAIL_WIDTH 0.0010f

/* The world point (x, y, z) m in px: through cam when there is one (its px
 * per m there returned), else the front view's (z left out; scale). */
static double project(const struct sp_camera *cam, double ox, double oy, double scale, double x,
                      double y, double z, float p[2])
{
    if (cam)
        return sp_camera_project(cam, (const double[3]){x, y, z}, p);
    p[0] = (float)(ox + scale * x), p[1] = (float)(oy - scale * y);
    return scale;
}

/* A member and its depth, m: sorted farthest first. */
struct deep {
    double depth;
    int i;
};

static int by_depth(const void *a, const void *b)
{
    const struct deep *p = a, *q = b;
    if (p->depth != q->depth)
        return (p->depth < q->depth) - (p->depth > q->depth);
    return (p->i > q->i) - (p->i < q->i);
}

void sp_compose_ensemble(struct sp_canvas *c, const struct sp_ensemble *e, double ox, double oy,
                         double scale, float unit, const struct sp_palette *pal,
                         const struct sp_camera *cam)
{
    float col[4] = {0, 0, 0, 1}, a[2], b[2];
    (void)pal;
    if (e->trail_count > 1) { /* oldest first, fading; each member one path */
        for (int i = 0; i < e->n; i++) {
            const float *ring = &e->trail_xyz[3 * (size_t)i * e->trail_cap];
            const int oldest = e->trail_count < e->trail_cap ? 0 : e->trail_head;
            sp_ensemble_color(i, e->n, col);
            sp_canvas_path_begin(c);
            for (int j = 1; j < e->trail_count; j++) {
                const float *p = &ring[3 * ((oldest + j - 1) % e->trail_cap)];
                const float *q = &ring[3 * ((oldest + j) % e->trail_cap)];
                col[3] = 0.15f + 0.6f * (float)j / (float)(e->trail_count - 1);
                if (project(cam, ox, oy, scale, p[0], p[1], p[2], a) > 0 &&
                    project(cam, ox, oy, scale, q[0], q[1], q[2], b) > 0)
                    sp_canvas_line(c, a[0], a[1], b[0], b[1], TRAIL_WIDTH * unit, col);
            }
            sp_canvas_path_end(c);
        }
    }
    /* in perspective the nearer members cover the farther: drawn far to
     * near (the front view keeps the members' order) */
    struct deep *order = cam ? malloc(sizeof(*order) * (size_t)e->n) : NULL;
    for (int i = 0; order && i < e->n; i++) {
        double x, y, z;
        sp_ensemble_position(e, i, &x, &y, &z);
        order[i] = (struct deep){sp_camera_depth(cam, (const double[3]){x, y, z}), i};
    }
    if (order) /* (out of memory: the members' own order) */
        qsort(order, (size_t)e->n, sizeof(*order), by_depth);
    for (int i = 0; i < e->n; i++) { /* the rods under every bob */
        double x, y, z;
        sp_ensemble_position(e, i, &x, &y, &z);
        sp_ensemble_color(i, e->n, col);
        col[3] = 0.45f;
        const double yp = sp_pivot_y(&e->params[i], e->t);
        if (project(cam, ox, oy, scale, 0, yp, 0, a) > 0 &&
            project(cam, ox, oy, scale, x, y, z, b) > 0)
            sp_canvas_line(c, a[0], a[1], b[0], b[1], ROD_WIDTH * unit, col);
    }
    for (int k = 0; k < e->n; k++) {
        const int i = order ? order[k].i : k;
        double x, y, z;
        sp_ensemble_position(e, i, &x, &y, &z);
        sp_ensemble_color(i, e->n, col);
        col[3] = 1;
        /* in perspective the size follows 1/depth, as the lone bob's */
        const double px_m = project(cam, ox, oy, scale, x, y, z, a);
        if (px_m > 0)
            sp_canvas_disc(c, a[0], a[1], MEMBER_RADIUS * unit * (float)(px_m / scale), 1, col);
    }
    free(order);
}
