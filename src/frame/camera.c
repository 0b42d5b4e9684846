/* springpend (internal): the perspective camera. See camera.h. */
#include <math.h>
#include <string.h>

#include "springpend/common.h"
#include "camera.h"

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The 8 corners of lo..hi and the floor grid's 4, m. */
static int corners(const struct sp_camera *c, const double lo[3], const double hi[3],
                   double out[12][3])
{
    int n = 0;
    for (int i = 0; i < 8; i++, n++) {
        out[n][0] = i & 1 ? hi[0] : lo[0];
        out[n][1] = i & 2 ? hi[1] : lo[1];
        out[n][2] = i & 4 ? hi[2] : lo[2];
    }
    for (int i = 0; i < 4; i++, n++) {
        out[n][0] = c->target[0] + (i & 1 ? 1 : -1) * c->grid_half;
        out[n][1] = c->floor_y;
        out[n][2] = c->target[2] + (i & 2 ? 1 : -1) * c->grid_half;
    }
    return n;
}

/* 1, 2 or 5 times a power of ten, the nearest at or above x > 0. */
static double nice_step(double x)
{
    const double p = pow(10, floor(log10(x)));
    return x <= p ? p : x <= 2 * p ? 2 * p : x <= 5 * p ? 5 * p : 10 * p;
}

int sp_camera_aim(struct sp_camera *c, const struct sp_view *view, const double lo[3],
                  const double hi[3])
{
    const int set = view->camera == SP_CAMERA_SET;
    double half[3], box[12][3];
    *c = (struct sp_camera){0};
    c->azimuth = set ? view->camera_azimuth : SP_CAMERA_AUTO_AZIMUTH * (M_PI / 180);
    c->elevation = set ? view->camera_elevation : SP_CAMERA_AUTO_ELEVATION * (M_PI / 180);
    for (int k = 0; k < 3; k++) {
        c->box_lo[k] = lo[k], c->box_hi[k] = hi[k];
        c->target[k] = 0.5 * (lo[k] + hi[k]);
        half[k] = 0.5 * (hi[k] - lo[k]);
    }
    /* the floor a little below the lowest point, its grid wider than the swing */
    const double height = fmax(hi[1] - lo[1], 1e-3);
    c->floor_y = lo[1] - 0.08 * height;
    const double reach = fmax(1.3 * fmax(half[0], half[2]), 0.3 * height);
    c->grid_step = nice_step(2 * reach / 8);
    c->grid_half = ceil(reach / c->grid_step - 1e-9) * c->grid_step;
    c->target[1] = 0.5 * (hi[1] + c->floor_y);
    const double radius = sqrt(half[0] * half[0] + 0.25 * (hi[1] - c->floor_y) * (hi[1] - c->floor_y) +
                               half[2] * half[2]);
    c->distance = set && view->camera_distance > 0 ? view->camera_distance : 3.2 * fmax(radius, 1e-3);
    const double ce = cos(c->elevation), d[3] = {sin(c->azimuth) * ce, sin(c->elevation),
                                                 cos(c->azimuth) * ce};
    for (int k = 0; k < 3; k++) {
        c->eye[k] = c->target[k] + c->distance * d[k];
        c->forward[k] = -d[k];
    }
    /* right = forward x y, up = right x forward: no roll */
    const double rl = hypot(c->forward[2], c->forward[0]);
    c->right[0] = -c->forward[2] / rl, c->right[1] = 0, c->right[2] = c->forward[0] / rl;
    c->up[0] = c->right[1] * c->forward[2] - c->right[2] * c->forward[1];
    c->up[1] = c->right[2] * c->forward[0] - c->right[0] * c->forward[2];
    c->up[2] = c->right[0] * c->forward[1] - c->right[1] * c->forward[0];
    const int n = corners(c, lo, hi, box);
    double nearest = INFINITY;
    for (int i = 0; i < n; i++)
        nearest = fmin(nearest, sp_camera_depth(c, box[i]));
    if (!(nearest >= 0.2 * c->distance)) {
        /* a corner's depth is (p - target) . forward + D, the corners do not
         * move with D: D works from D* = -min((p - target) . forward) / 0.8
         * on; suggested above it in 4 significant digits (under 0.1% more) */
        const double least = -(nearest - c->distance) / 0.8;
        const double q = pow(10, floor(log10(least)) - 3);
        /* "FILE:LINE: view.camera", or "--set view.camera" (which names the key) */
        const char *where = view->camera_where;
        const int set = !where[0] || !strncmp(where, "--set ", 6);
        sp_log_error("%s%sview.camera: from %g m the eye is inside or too near the motion and "
                     "its floor (they reach %.3g m from the middle); allowed: a distance that "
                     "keeps every corner of them at least a fifth of it in front, here at least "
                     "%.4g m, or no distance (fitted)",
                     where[0] && !set ? where : where[0] ? "--set " : "",
                     where[0] && !set ? ": " : "", c->distance, radius,
                     (floor(least / q) + 1) * q);
        return SP_E_INPUT;
    }
    c->focal = 1;
    return 0;
}

void sp_camera_fit(struct sp_camera *c, float x0, float y0, float x1, float y1, float margin)
{
    double box[12][3], u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    const int n = corners(c, c->box_lo, c->box_hi, box);
    for (int i = 0; i < n; i++) {
        double q[3];
        for (int k = 0; k < 3; k++)
            q[k] = box[i][k] - c->eye[k];
        const double d = dot(q, c->forward);
        const double u = dot(q, c->right) / d, v = dot(q, c->up) / d;
        u0 = fmin(u0, u), u1 = fmax(u1, u), v0 = fmin(v0, v), v1 = fmax(v1, v);
    }
    const double aw = fmax(x1 - x0 - 2 * margin, 1), ah = fmax(y1 - y0 - 2 * margin, 1);
    c->focal = fmin(aw / fmax(u1 - u0, 1e-9), ah / fmax(v1 - v0, 1e-9));
    c->centre[0] = 0.5 * (x0 + x1) - c->focal * 0.5 * (u0 + u1);
    c->centre[1] = 0.5 * (y0 + y1) + c->focal * 0.5 * (v0 + v1);
}

double sp_camera_depth(const struct sp_camera *c, const double p[3])
{
    const double q[3] = {p[0] - c->eye[0], p[1] - c->eye[1], p[2] - c->eye[2]};
    return dot(q, c->forward);
}

double sp_camera_project(const struct sp_camera *c, const double p[3], float px[2])
{
    const double q[3] = {p[0] - c->eye[0], p[1] - c->eye[1], p[2] - c->eye[2]};
    const double d = dot(q, c->forward);
    if (!(d > 1e-9 * c->distance))
        return 0;
    px[0] = (float)(c->centre[0] + c->focal * dot(q, c->right) / d);
    px[1] = (float)(c->centre[1] - c->focal * dot(q, c->up) / d);
    return c->focal / d;
}

double sp_camera_scale(const struct sp_camera *c)
{
    return c->focal / c->distance;
}
