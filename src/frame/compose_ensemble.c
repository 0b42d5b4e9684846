/* springpend (internal): an ensemble's members in a frame. See compose.h. */
#include <math.h>

#include "springpend/ensemble.h"
#include "compose.h"

/* Sizes as fractions of the image's smaller side: smaller than the lone
 * bob's (0.022), as a hundred of them share the view. */
#define MEMBER_RADIUS 0.011f
#define ROD_WIDTH 0.0007f
#define TRAIL_WIDTH 0.0010f

void sp_compose_ensemble(struct sp_canvas *c, const struct sp_ensemble *e, double ox, double oy,
                         double scale, float unit, const struct sp_palette *pal)
{
    float col[4] = {0, 0, 0, 1};
    (void)pal;
    if (e->trail_count > 1) { /* oldest first, fading; each member one path */
        for (int i = 0; i < e->n; i++) {
            const float *ring = &e->trail_xy[2 * (size_t)i * e->trail_cap];
            const int oldest = e->trail_count < e->trail_cap ? 0 : e->trail_head;
            sp_ensemble_color(i, e->n, col);
            sp_canvas_path_begin(c);
            for (int j = 1; j < e->trail_count; j++) {
                const float *a = &ring[2 * ((oldest + j - 1) % e->trail_cap)];
                const float *b = &ring[2 * ((oldest + j) % e->trail_cap)];
                col[3] = 0.15f + 0.6f * (float)j / (float)(e->trail_count - 1);
                sp_canvas_line(c, (float)(ox + scale * a[0]), (float)(oy - scale * a[1]),
                               (float)(ox + scale * b[0]), (float)(oy - scale * b[1]),
                               TRAIL_WIDTH * unit, col);
            }
            sp_canvas_path_end(c);
        }
    }
    for (int i = 0; i < e->n; i++) { /* the rods under every bob */
        double x, y;
        sp_ensemble_position(e, i, &x, &y);
        sp_ensemble_color(i, e->n, col);
        col[3] = 0.45f;
        const double yp = sp_pivot_y(&e->params[i], e->t);
        sp_canvas_line(c, (float)ox, (float)(oy - scale * yp), (float)(ox + scale * x),
                       (float)(oy - scale * y), ROD_WIDTH * unit, col);
    }
    for (int i = 0; i < e->n; i++) {
        double x, y;
        sp_ensemble_position(e, i, &x, &y);
        sp_ensemble_color(i, e->n, col);
        col[3] = 1;
        sp_canvas_disc(c, (float)(ox + scale * x), (float)(oy - scale * y), MEMBER_RADIUS * unit, 1, col);
    }
}
