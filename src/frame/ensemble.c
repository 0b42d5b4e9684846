/* springpend: ensembles of nearby pendulums. See ensemble.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/ensemble.h"
#include "base/array.h"

/* The members' scenes and parameters: value i = centre + spread (i/(n-1) - 1/2),
 * set through the parser's own path (sp_scene_set_number), so that a single
 * run with --set KEY=VALUE (VALUE printed with %.17g) starts identically. */
static int make_members(struct sp_ensemble *e, const struct sp_scene *scene)
{
    const int n = scene->ensemble.count;
    const double centre = sp_scene_get_number(scene, scene->ensemble.key);
    e->n = n;
    snprintf(e->key, sizeof(e->key), "%.63s", scene->ensemble.key);
    e->value = calloc((size_t)n, sizeof(*e->value));
    e->scenes = calloc((size_t)n, sizeof(*e->scenes));
    e->params = calloc((size_t)n, sizeof(*e->params));
    if (!e->value || !e->scenes || !e->params) {
        sp_log_error("out of memory for an ensemble of %d", n);
        return SP_E_NOMEM;
    }
    for (int i = 0; i < n; i++) {
        struct sp_sim sim;
        e->value[i] = centre + scene->ensemble.spread * ((double)i / (n - 1) - 0.5);
        e->scenes[i] = *scene;
        e->scenes[i].ensemble.count = 0;
        if (sp_scene_set_number(&e->scenes[i], e->key, e->value[i], "[ensemble]"))
            return SP_E_INPUT; /* the parser checked both ends: not reached */
        sp_sim_init(&sim, &e->scenes[i]);
        e->params[i] = sim.p;
    }
    return 0;
}

/* A batch of the members (with the tangent: a batch of the central one). */
static int make_batch(struct sp_batch **b, const struct sp_scene *scenes, int n, int tangent)
{
    const struct sp_scene **ptr = malloc((size_t)n * sizeof(*ptr));
    int ret;
    if (!ptr) {
        sp_log_error("out of memory for an ensemble of %d", n);
        return SP_E_NOMEM;
    }
    for (int i = 0; i < n; i++)
        ptr[i] = &scenes[i];
    /* forced for all when any is: a member's arithmetic is its single run's */
    ret = sp_batch_make(b, ptr, n, tangent, 0);
    free(ptr);
    if (ret == SP_E_NOMEM)
        sp_log_error("out of memory for an ensemble of %d", n);
    return ret;
}

/* SP_E_UNSTABLE (logged) when a member has blown up. */
static int check_dead(const struct sp_ensemble *e, const struct sp_batch *b)
{
    for (int i = 0; i < b->n; i++)
        if (b->dead[i]) {
            sp_log_error("ensemble member %d of %d (%s = %.17g) became unstable before t = "
                         "%.3f s: its energy drifted or its state stopped being finite; "
                         "the whole run stops (lower integrator.dt or the spread)",
                         i + 1, e->n, e->key, e->value[i], b->t);
            return SP_E_UNSTABLE;
        }
    return 0;
}

static double spread_of(const struct sp_ensemble *e, const struct sp_batch *b)
{
    /* the planar components first (a planar ensemble's sums as before) */
    static const int comp[6] = {SP_BX, SP_BY, SP_BVX, SP_BVY, SP_BZ, SP_BVZ};
    const double w[6] = {1, 1, 1 / e->omega, 1 / e->omega, 1, 1 / e->omega};
    const int nc = b->spatial ? 6 : 4;
    double mean[6] = {0}, sum = 0;
    for (int c = 0; c < nc; c++) {
        for (int i = 0; i < b->n; i++)
            mean[c] += b->out[comp[c]][i] * w[c];
        mean[c] /= b->n;
    }
    for (int i = 0; i < b->n; i++)
        for (int c = 0; c < nc; c++) {
            const double d = b->out[comp[c]][i] * w[c] - mean[c];
            sum += d * d;
        }
    return sqrt(sum / b->n);
}

double sp_ensemble_spread(const struct sp_ensemble *e)
{
    return spread_of(e, e->batch);
}

void sp_ensemble_position(const struct sp_ensemble *e, int i, double *x, double *y, double *z)
{
    *x = e->batch->out[SP_BX][i];
    *y = e->batch->out[SP_BY][i] + sp_pivot_y(&e->params[i], e->t);
    *z = e->batch->spatial ? e->batch->out[SP_BZ][i] : 0;
}

void sp_ensemble_color(int i, int n, float rgb[3])
{
    /* hue by the key's order (a rainbow across the spread), light and
     * saturated enough for dark and light themes alike */
    const float h = 0.83f * (float)i / (float)(n > 1 ? n - 1 : 1);
    for (int k = 0; k < 3; k++) {
        float x = fmodf(h * 6.0f + (float)(4 - 2 * k + 6), 6.0f); /* r: 4 -> 0, g: 2, b: 0 */
        x = fminf(fmaxf(fabsf(x - 3.0f) - 1.0f, 0.0f), 1.0f);
        rgb[k] = 0.15f + 0.8f * x;
    }
}

/* The central scene's largest Lyapunov exponent over [0, t_end], 1/s:
 * Benettin's renormalisation about every second (on the step grid for fixed
 * methods), as sweep's lyapunov measure does. */
static int lyapunov(const struct sp_scene *scene, double t_end, double *lambda)
{
    struct sp_batch *b = NULL;
    struct sp_scene centre = *scene;
    double sum = 0, growth;
    centre.ensemble.count = 0;
    int ret = make_batch(&b, &centre, 1, 1);
    if (ret)
        return ret;
    const int fixed = b->method != SP_METHOD_DOP853;
    const long m = fixed ? lround(fmax(1.0, 1.0 / b->dt)) : 1;
    const double tau = fixed ? (double)m * b->dt : 1.0;
    const long K = (long)fmax(1, lround(t_end / tau)); /* the video's span, to the second */
    for (long k = 1; k <= K && !b->dead[0]; k++) {
        sp_batch_advance(b, fixed ? (double)(k * m) * b->dt : (double)k * tau);
        sp_batch_renormalise(b, &growth);
        sum += growth;
    }
    if (b->dead[0]) { /* the members ran: only the tangent's arithmetic differs */
        sp_log_error("the ensemble's central scene became unstable before t = %.3f s while "
                     "its Lyapunov exponent was measured (lower integrator.dt)", b->t);
        ret = SP_E_UNSTABLE;
    }
    *lambda = sum / (K * tau);
    sp_batch_destroy(&b);
    return ret;
}

int sp_ensemble_make(struct sp_ensemble **out, const struct sp_scene *scene, double t_end,
                     const volatile sig_atomic_t *cancel,
                     void (*progress)(void *ctx, double t), void *progress_ctx,
                     struct sp_view_extent *extent)
{
    struct sp_ensemble *e = calloc(1, sizeof(*e));
    struct sp_batch *pre = NULL;
    int ret;
    *out = NULL;
    if (!e) {
        sp_log_error("out of memory for an ensemble");
        return SP_E_NOMEM;
    }
    ret = make_members(e, scene);
    if (!ret)
        ret = make_batch(&pre, e->scenes, e->n, 0);
    if (ret)
        goto fail;
    e->omega = sp_params_omega_max(&e->params[0]);
    e->log_spread = (struct sp_range){INFINITY, -INFINITY};
    /* the pre-pass: every step (fixed) or every 1/200 of the fastest period */
    const double h = pre->method != SP_METHOD_DOP853 ? pre->dt : 0.03 / e->omega;
    const long steps = (long)ceil(t_end / h - 1e-9);
    for (long k = 0; k <= steps; k++) {
        if (k)
            sp_batch_advance(pre, k == steps ? t_end : (pre->method != SP_METHOD_DOP853 ? k * pre->dt : k * h));
        if ((ret = check_dead(e, pre)) != 0)
            goto fail;
        const double lg = log10(fmax(spread_of(e, pre), 1e-300));
        if (k == 0)
            e->log_spread0 = lg;
        e->log_spread.lo = fmin(e->log_spread.lo, lg);
        e->log_spread.hi = fmax(e->log_spread.hi, lg);
        for (int i = 0; i < e->n; i++) {
            const double x = pre->out[SP_BX][i], yp = sp_pivot_y(&e->params[i], pre->t);
            const double y = pre->out[SP_BY][i] + yp;
            const double vx = pre->out[SP_BVX][i], vy = pre->out[SP_BVY][i];
            const double z = pre->spatial ? pre->out[SP_BZ][i] : 0;
            const double vz = pre->spatial ? pre->out[SP_BVZ][i] : 0;
            extent->xmin = fmin(extent->xmin, x);
            extent->xmax = fmax(extent->xmax, x);
            extent->ymin = fmin(extent->ymin, fmin(y, yp));
            extent->ymax = fmax(extent->ymax, fmax(y, yp));
            extent->zmin = fmin(extent->zmin, z);
            extent->zmax = fmax(extent->zmax, z);
            extent->max_speed = fmax(extent->max_speed, sqrt(vx * vx + vy * vy + vz * vz));
        }
        if (cancel && *cancel) {
            ret = SP_E_INTERRUPTED;
            goto fail;
        }
        if (progress)
            progress(progress_ctx, pre->t);
    }
    sp_batch_destroy(&pre);
    /* the axis reaches the size of the motion: a spread that saturates there
     * has spread over all of it, one far below has not */
    e->log_spread.hi = fmax(e->log_spread.hi, log10(fmax(extent->xmax - extent->xmin,
                                                         extent->ymax - extent->ymin)));
    ret = lyapunov(scene, t_end, &e->lambda);
    if (!ret)
        ret = make_batch(&e->batch, e->scenes, e->n, 0);
    if (ret)
        goto fail;
    if (scene->ensemble.trails) {
        /* at most about 3000 trail segments per frame in all */
        e->trail_cap = (int)fmin(SP_ENSEMBLE_TRAIL, fmax(8, 3000.0 / e->n));
        e->trail_xyz = calloc((size_t)e->n * e->trail_cap * 3, sizeof(*e->trail_xyz));
        if (!e->trail_xyz) {
            sp_log_error("out of memory for %d trails", e->n);
            ret = SP_E_NOMEM;
            goto fail;
        }
    }
    *out = e;
    return 0;
fail:
    sp_batch_destroy(&pre);
    sp_ensemble_destroy(&e);
    return ret;
}

int sp_ensemble_advance(struct sp_ensemble *e, double t)
{
    int ret;
    if (t > e->batch->t || e->n_spread == 0) {
        if (t > e->batch->t)
            sp_batch_advance(e->batch, t);
        e->t = e->batch->t;
        if ((ret = check_dead(e, e->batch)) != 0)
            return ret;
    } else {
        return 0;
    }
    int cap_t = e->cap_spread, cap_log = e->cap_spread; /* both grow alike */
    if (SP_ARRAY_RESERVE(e->spread_t, cap_t, e->n_spread + 1, 1024) ||
        SP_ARRAY_RESERVE(e->spread_log, cap_log, e->n_spread + 1, 1024)) {
        sp_log_error("out of memory for %d spread samples", e->n_spread + 1);
        return SP_E_NOMEM;
    }
    e->cap_spread = cap_log;
    e->spread_t[e->n_spread] = (float)e->t;
    e->spread_log[e->n_spread++] = (float)log10(fmax(sp_ensemble_spread(e), 1e-300));
    if (e->trail_cap) {
        for (int i = 0; i < e->n; i++) {
            double x, y, z;
            sp_ensemble_position(e, i, &x, &y, &z);
            float *p = &e->trail_xyz[3 * ((size_t)i * e->trail_cap + e->trail_head)];
            p[0] = (float)x, p[1] = (float)y, p[2] = (float)z;
        }
        e->trail_head = (e->trail_head + 1) % e->trail_cap;
        if (e->trail_count < e->trail_cap)
            e->trail_count++;
    }
    return 0;
}

int sp_ensemble_write_csv(FILE *fp, const struct sp_scene *scene, double every,
                          const volatile sig_atomic_t *cancel)
{
    struct sp_ensemble e = {0};
    struct sp_batch *b = NULL;
    const long n = every > 0 ? (long)floor(scene->video.duration / every * (1 + 1e-12)) + 1
                             : sp_scene_frame_count(scene);
    double *azimuth = NULL; /* rad: each member's, continued from row to row */
    int ret = make_members(&e, scene);
    if (!ret)
        ret = make_batch(&b, e.scenes, e.n, 0);
    if (!ret && !(azimuth = calloc((size_t)e.n, sizeof(*azimuth)))) {
        sp_log_error("out of memory for an ensemble of %d", e.n);
        ret = SP_E_NOMEM;
    }
    if (!ret && fprintf(fp, "t,member,%s,x,y,vx,vy%s\n", e.key,
                        b->spatial ? ",z,vz,azimuth" : "") < 0)
        ret = SP_E_IO;
    for (long k = 0; k < n && !ret; k++) {
        const double t = every > 0 ? k * every : sp_scene_frame_time(scene, (int)k);
        if (cancel && *cancel) {
            ret = SP_E_INTERRUPTED;
            break;
        }
        sp_batch_advance(b, t);
        e.batch = b;
        if ((ret = check_dead(&e, b)) != 0)
            break;
        for (int i = 0; i < e.n && !ret; i++) {
            if (fprintf(fp, "%.10g,%d,%.17g,%.15g,%.15g,%.15g,%.15g", t, i, e.value[i],
                        b->out[SP_BX][i], b->out[SP_BY][i], b->out[SP_BVX][i],
                        b->out[SP_BVY][i]) < 0)
                ret = SP_E_IO;
            if (b->spatial) { /* as data's write_row */
                const struct sp_state s = {t, b->out[SP_BX][i], b->out[SP_BY][i],
                                           b->out[SP_BVX][i], b->out[SP_BVY][i],
                                           b->out[SP_BZ][i], b->out[SP_BVZ][i]};
                azimuth[i] = sp_azimuth_unwrap(azimuth[i], sp_state_azimuth(&e.params[i], &s));
                if (fprintf(fp, ",%.15g,%.15g,%.15g", s.z, s.vz, azimuth[i] * 180 / M_PI) < 0)
                    ret = SP_E_IO;
            }
            if (fputc('\n', fp) == EOF)
                ret = SP_E_IO;
        }
    }
    free(azimuth);
    sp_batch_destroy(&b);
    e.batch = NULL;
    free(e.value);
    free(e.scenes);
    free(e.params);
    return ret;
}

int sp_ensemble_spatial(const struct sp_scene *scene)
{
    struct sp_ensemble e = {0};
    int spatial = 0;
    if (!make_members(&e, scene))
        for (int i = 0; i < e.n; i++)
            spatial |= e.scenes[i].initial.azimuth_rate != 0;
    free(e.value);
    free(e.scenes);
    free(e.params);
    return spatial;
}

void sp_ensemble_destroy(struct sp_ensemble **ep)
{
    struct sp_ensemble *e = *ep;
    if (!e)
        return;
    sp_batch_destroy(&e->batch);
    free(e->value);
    free(e->scenes);
    free(e->params);
    free(e->spread_t);
    free(e->spread_log);
    free(e->trail_xyz);
    free(e);
    *ep = NULL;
}
