/* springpend (internal): the perspective camera of [view] camera, which the
 * composer draws a 3-D scene through. World coordinates are the lab's, m:
 * x horizontal in the starting plane, y up, z out of it (x-y-z right-handed),
 * the pivot's rest position at the origin. Output in px, y down from the
 * top-left corner. A pinhole: a point p at depth d = (p - eye) . forward
 * lands at centre + focal * ((p - eye) . right, -(p - eye) . up) / d.
 * Pure arithmetic: no GL, no I/O. */
#ifndef SPRINGPEND_CAMERA_H
#define SPRINGPEND_CAMERA_H

#include "springpend/frame.h"

struct sp_camera {
    double azimuth, elevation; /* rad: the eye turned from +z towards +x about the
                                  vertical, and raised above the horizontal */
    double distance;           /* m: from the eye to the target */
    double target[3];          /* m: the middle of the motion, at the image's centre */
    double eye[3];             /* m */
    double right[3], up[3], forward[3]; /* unit vectors; forward points at the target */
    double focal;              /* px: the image of 1 m seen from 1 m away */
    double centre[2];          /* px: where the target lands */
    double floor_y;            /* m: the height of the floor the shadow falls on */
    double grid_step;          /* m: the floor grid's spacing */
    double grid_half;          /* m: the grid spans +-grid_half about the target in x and z */
    double box_lo[3], box_hi[3]; /* m: the motion's box aimed at */
};

/* Aims c at the box lo..hi (m, the motion's extent) from view's angles (or
 * the auto ones), from view.camera_distance or, when that is 0, from 3.2
 * times the box's half diagonal; places the floor below the box and its grid
 * around it. 0, or SP_E_INPUT (said) when the eye is inside or too near the
 * box: every corner must lie at least a fifth of the distance in front. */
int sp_camera_aim(struct sp_camera *c, const struct sp_view *view, const double lo[3],
                  const double hi[3]);

/* Fits the box and the floor grid into the rectangle x0..x1, y0..y1 (px)
 * less margin px on each side, centred: sets focal and centre. */
void sp_camera_fit(struct sp_camera *c, float x0, float y0, float x1, float y1, float margin);

/* Projects the world point p (m) to px; returns px per m at p's depth (the
 * size of a small object there), or 0 when p is not in front of the eye. */
double sp_camera_project(const struct sp_camera *c, const double p[3], float px[2]);

/* Depth of p along forward, m (larger = farther). */
double sp_camera_depth(const struct sp_camera *c, const double p[3]);

/* px per m at the target's depth. */
double sp_camera_scale(const struct sp_camera *c);

#endif
