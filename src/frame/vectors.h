/* springpend (internal): [view] vectors, arrows from the bob: velocity,
 * acceleration and the forces (gravity, spring, damping, the drive's
 * inertial force, net), each in its colour, with a legend and an arrow key
 * per quantity ("2 N" drawn at its length). One scale per quantity for the
 * whole run, from the pre-pass's largest values (struct sp_view_extent), so
 * arrows compare across frames; the forces share theirs, so that net is
 * their sum on screen too. */
#ifndef SPRINGPEND_VECTORS_H
#define SPRINGPEND_VECTORS_H

#include "springpend/frame.h"
#include "canvas.h"
#include "panels.h"

/* Fraction of the frame's smaller side the largest arrow of a quantity
 * takes (at most a fifth of the view's smaller side: compose.c); the camera
 * keeps this much room around the motion. */
#define SP_VECTOR_MAX_LENGTH 0.15f

/* The three quantities and their scales. */
enum sp_vector_quantity { SP_VQ_FORCE, SP_VQ_VELOCITY, SP_VQ_ACCELERATION, SP_VQ_COUNT };

struct sp_vectors {
    unsigned bits;                 /* SP_VECTOR_* drawn */
    int driven;                    /* 1: the pivot moves (arrows in its frame) */
    int damped;                    /* 1: damping acts (b > 0) */
    double px_per[SP_VQ_COUNT];    /* px per N, per m/s, per m/s^2 */
    double key[SP_VQ_COUNT];       /* the key's value: 1, 2 or 5 x 10^k of the unit */
    float unit;                    /* px: the frame's smaller side */
};

/* Picks the scales for look's vectors from extent's largest values: the
 * largest of each quantity is max_px long (px; the room the camera keeps
 * around the motion). */
void sp_vectors_setup(struct sp_vectors *v, const struct sp_look *look,
                      const struct sp_view_extent *e, const struct sp_params *p, float unit,
                      float max_px);

/* The legend's box, px, as sp_vectors_legend draws it with font f. */
void sp_vectors_legend_size(const struct sp_font *f, const struct sp_vectors *v, float *w,
                            float *h);

/* Arrows from the bob at bob[] (px) for frame f's state. */
void sp_vectors_draw(struct sp_canvas *c, const struct sp_vectors *v, const struct sp_frame *f,
                     const float bob[2], const struct sp_palette *pal);

/* The legend and keys in the top-left corner of rect r (needs the canvas's
 * font): a box of sp_vectors_legend_size's, its padding included. */
void sp_vectors_legend(struct sp_canvas *c, const struct sp_vectors *v, const struct sp_rect *r,
                       const struct sp_palette *pal);

/* "PREFIXvectors.force.px_per_unit=..." lines for the PNG's overlay text, px
 * divided by ss (the output's pixels); appends to buf at *used. */
void sp_vectors_describe(const struct sp_vectors *v, int ss, const char *prefix, char *buf,
                         size_t size, size_t *used);

#endif
