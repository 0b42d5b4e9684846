/* springpend: the batched integrator (see batch.h). Each stepper works on a
 * block of SP_BATCH_BLOCK trajectories held in small arrays, one loop over
 * the lanes per operation; GCC vectorises those loops. This file is built
 * with -O3 -fno-math-errno -fno-trapping-math -fopenmp-simd (sqrt and the
 * guarded divisions become vector instructions; `omp simd` keeps the
 * unroller from scalarising the hot loops first), and the project with
 * -ffp-contract=off (no fused multiply-add changes a rounding), so a lane
 * does exactly what sim.c does. The block steppers are compiled three times,
 * for AVX-512 (x86-64-v4: 8 doubles a vector, 1.3x the AVX2 clone's
 * trajectory-steps per CPU-second with tangents here; sqrt and division
 * are correctly rounded in every width, so the lanes' bits do not change),
 * for AVX2 and for the baseline, and the CPU picks at load time
 * (target_clones).
 * sin, cos and exp stay scalar libm calls, as in sim.c.
 * A third compile-time switch, `spatial` (sim.c's), adds z and vz (and the
 * tangent's dz, dvz): with it off every stepper does the planar arithmetic
 * exactly as before it existed. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/batch.h"
#include "springpend/common.h"
#include "springpend/sim.h"

#define B SP_BATCH_BLOCK
#define NC SP_BATCH_NC
#define SPECIALISED static inline __attribute__((always_inline))

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(__SANITIZE_ADDRESS__)
#define CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default"), noinline))
#else
#define CLONES __attribute__((noinline))
#endif

/* A loop over a block's lanes, vectorised whatever the unroller does first
 * (-fopenmp-simd: the pragma only, no OpenMP run time). */
#define LANES _Pragma("omp simd") for (int l = 0; l < B; l++)

/* A loop over the components a block stepper may use: the planar ones
 * (before SP_BZ) unless 3-D. The planar loops keep the 9 iterations that
 * GCC unrolls whole, so that USED() folds to a constant in each copy (over
 * all 13 the planar tangent's RK4 stages tested it at run time: 25% more
 * instructions in the hot loop). */
#define COMPS for (int c = 0; c < (spatial ? NC : SP_BZ); c++)

#define CHECK_EVERY 16          /* fixed steps between energy checks (sim.c: 4) */
/* The fast kernel's: a check over the block costs about as much as 10 of
 * its steps, so it comes every 64 (2% of the time, was 8% every 16). The
 * same test; a blow-up is still caught before the state is handed out
 * (every call of fixed_blk_impl ends on a check). */
#define CHECK_EVERY_FAST 64
_Static_assert(SP_BATCH_CHUNK % CHECK_EVERY == 0 && SP_BATCH_CHUNK % CHECK_EVERY_FAST == 0,
               "a cut must fall on an energy check");

/* One block's parameters, copied out of the batch's arrays. */
struct blk {
    double km[B], L0[B], g[B], bm[B], amp[B], om[B];
    double kl[B]; /* k / (m L0^2), 1/(s^2 m^2): the Jacobian's k L0 / (m rho^3) = kl q^3 */
};

/* A component takes part when it exists: work only when forced, the tangent
 * only when asked for, z and vz only in 3-D. */
#define USED(c, forced, tangent, spatial)                                            \
    ((c) < SP_BW || ((c) == SP_BW && (forced)) ||                                    \
     ((c) >= SP_BDX && (c) <= SP_BDVY && (tangent)) ||                               \
     (((c) == SP_BZ || (c) == SP_BVZ) && (spatial)) ||                               \
     (((c) == SP_BDZ || (c) == SP_BDVZ) && (spatial) && (tangent)))

/* The force cache's entries (a[][]): planar 6, 3-D 10. */
#define NA 10
#define NCACHE(spatial) ((spatial) ? NA : 6)
enum { A_X, A_Y, A_P, J_XX, J_XY, J_YY, A_Z, J_XZ, J_YZ, J_ZZ };

/* ---- the right-hand side, per block ------------------------------------- */

/* The pivot's velocity and acceleration per lane at times t[], as sim.c's
 * pivot_motion; lanes that share the frequency and time share one sin/cos. */
static void pivot_blk(const struct blk *p, const double *t, double *vp, double *ap)
{
    double s = 0, c = 0, last_arg = NAN;
    for (int l = 0; l < B; l++) {
        if (p->amp[l] == 0) {
            vp[l] = ap[l] = 0;
            continue;
        }
        double arg = p->om[l] * t[l];
        if (!(arg == last_arg)) {
            s = sin(arg), c = cos(arg);
            last_arg = arg;
        }
        vp[l] = p->amp[l] * p->om[l] * c;
        ap[l] = -p->amp[l] * p->om[l] * p->om[l] * s;
    }
}

/* d/dt of u, as sim.c's rhs, plus the tangent equations. t[]: per lane. */
SPECIALISED void rhs_blk(const struct blk *p, const double *t, double u[NC][B], double d[NC][B],
                         const int forced, const int tangent, const int spatial)
{
    double vp[B], ap[B];
    if (forced)
        pivot_blk(p, t, vp, ap);
    else
        for (int l = 0; l < B; l++)
            vp[l] = ap[l] = 0;
    LANES {
        double x = u[SP_BX][l], y = u[SP_BY][l], z = spatial ? u[SP_BZ][l] : 0;
        double rho = spatial ? sqrt(x * x + y * y + z * z) : sqrt(x * x + y * y);
        double q = rho > 0 ? p->L0[l] / rho : 0;
        double c = p->km[l] * (1 - q);
        double ax = -c * x, ay = -c * y - p->g[l] - ap[l], az = -c * z;
        d[SP_BX][l] = u[SP_BVX][l];
        d[SP_BY][l] = u[SP_BVY][l];
        if (forced) {
            ax -= p->bm[l] * u[SP_BVX][l];
            ay -= p->bm[l] * (u[SP_BVY][l] + vp[l]);
            if (spatial) {
                az -= p->bm[l] * u[SP_BVZ][l];
                d[SP_BW][l] = -p->bm[l] * (u[SP_BVX][l] * u[SP_BVX][l] +
                                           u[SP_BVY][l] * (u[SP_BVY][l] + vp[l]) +
                                           u[SP_BVZ][l] * u[SP_BVZ][l]) -
                              ap[l] * u[SP_BVY][l];
            } else {
                d[SP_BW][l] = -p->bm[l] * (u[SP_BVX][l] * u[SP_BVX][l] +
                                           u[SP_BVY][l] * (u[SP_BVY][l] + vp[l])) -
                              ap[l] * u[SP_BVY][l];
            }
        }
        d[SP_BVX][l] = ax;
        d[SP_BVY][l] = ay;
        if (spatial) {
            d[SP_BZ][l] = u[SP_BVZ][l];
            d[SP_BVZ][l] = az;
        }
        if (tangent) {
            double a = p->kl[l] * q * q * q; /* k L0 / (m rho^3), no division */
            double jxx = -c - a * x * x, jxy = -a * x * y, jyy = -c - a * y * y;
            double dx = u[SP_BDX][l], dy = u[SP_BDY][l];
            d[SP_BDX][l] = u[SP_BDVX][l];
            d[SP_BDY][l] = u[SP_BDVY][l];
            d[SP_BDVX][l] = jxx * dx + jxy * dy;
            d[SP_BDVY][l] = jxy * dx + jyy * dy;
            if (spatial) {
                double jxz = -a * x * z, jyz = -a * y * z, jzz = -c - a * z * z;
                double dz = u[SP_BDZ][l];
                d[SP_BDVX][l] += jxz * dz;
                d[SP_BDVY][l] += jyz * dz;
                d[SP_BDZ][l] = u[SP_BDVZ][l];
                d[SP_BDVZ][l] = jxz * dx + jyz * dy + jzz * dz;
            }
            if (forced) {
                d[SP_BDVX][l] -= p->bm[l] * u[SP_BDVX][l];
                d[SP_BDVY][l] -= p->bm[l] * u[SP_BDVY][l];
                if (spatial)
                    d[SP_BDVZ][l] -= p->bm[l] * u[SP_BDVZ][l];
            }
        }
    }
}

/* ---- fixed-step methods, as sim.c ---------------------------------------- */

SPECIALISED void rk4_blk(const struct blk *p, double t, double u[NC][B], double h,
                         const int forced, const int tangent, const int spatial)
{
    double k1[NC][B], k2[NC][B], k3[NC][B], k4[NC][B], v[NC][B], tt[B];
    for (int l = 0; l < B; l++)
        tt[l] = t;
    rhs_blk(p, tt, u, k1, forced, tangent, spatial);
    COMPS
        if (USED(c, forced, tangent, spatial))
            for (int l = 0; l < B; l++)
                v[c][l] = u[c][l] + 0.5 * h * k1[c][l];
    for (int l = 0; l < B; l++)
        tt[l] = t + 0.5 * h;
    rhs_blk(p, tt, v, k2, forced, tangent, spatial);
    COMPS
        if (USED(c, forced, tangent, spatial))
            for (int l = 0; l < B; l++)
                v[c][l] = u[c][l] + 0.5 * h * k2[c][l];
    rhs_blk(p, tt, v, k3, forced, tangent, spatial);
    COMPS
        if (USED(c, forced, tangent, spatial))
            for (int l = 0; l < B; l++)
                v[c][l] = u[c][l] + h * k3[c][l];
    for (int l = 0; l < B; l++)
        tt[l] = t + h;
    rhs_blk(p, tt, v, k4, forced, tangent, spatial);
    COMPS
        if (USED(c, forced, tangent, spatial))
            for (int l = 0; l < B; l++)
                u[c][l] += h / 6 * (k1[c][l] + 2 * (k2[c][l] + k3[c][l]) + k4[c][l]);
}

/* ---- the fast kernel (sp_batch.fast) ------------------------------------ */

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#include <immintrin.h>
#define FAST_KERNEL 1

int sp_batch_fast_supported(void)
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("fma");
}

/* rk4_blk undamped and undriven with the tangent, n steps of the whole block
 * in registers. Undamped and undriven, the accelerations depend on the
 * positions alone (the tangent's too: J(x) dx), so RK4's stages reduce to
 * those of a second-order system (classical RK4 on q'' = A(q), the same
 * method, other roundings), with P = (x, y, dx, dy), V = (vx, vy, dvx, dvy):
 *   A1 = A(P),            X2 = P + h/2 V,      A2 = A(X2),
 *   X3 = X2 + h^2/4 A1,   X4 = P + h V + h^2/2 A2,
 *   A3 = A(X3), A4 = A(X4),
 *   P' = P + h V + h^2/6 (A1 + A2 + A3),  V' = V + h/6 (A1 + 2 A2 + 2 A3 + A4).
 * No stage velocity is formed (11 vector instructions a component pair for
 * the stages, against 14), and A1 with A2, A3 with A4 are independent: the
 * chain of latency is two evaluations a step, not four, and the block's two
 * 8-lane vectors give four evaluations to overlap.
 * Per evaluation, at a stage's (x, y, dx, dy):
 *   r2 = x^2 + y^2, r = 1/rho: vrsqrt14pd (relative error < 2^-14) refined
 *     by one step of the series 1/sqrt(1 - e) = 1 + e/2 + 3e^2/8 + 5e^3/16
 *     (e = 1 - r2 r0^2; what it leaves is 35/128 e^4 < 2^-53), so that no
 *     evaluation waits on the divider (whose correctly rounded sqrt and
 *     division alone cap RK4 with tangents at about 170 M trajectory-steps
 *     per core-second here, 40% of the FP64 peak);
 *   w = (k L0 / m) r = (k / m) q, -c = w - k/m, a = w r^2 = (k L0 / m) / rho^3;
 *   ax = -c x, ay = -c y - g;
 *   J d = -c d - a (x dx + y dy) (x, y): the Jacobian times the tangent
 *     without forming J (11 flops, against 17 through J's three entries).
 * At the pivot (r2 = 0) w and a are 0, as rhs_blk's q and kl q^3. Within a
 * few units in the last place of the exact kernel per step. Flops the
 * algorithm needs, FMA 2, 1/rho as 2 (a sqrt and a division): 22 per
 * evaluation, and classical RK4's combination of the stages, 12 per
 * component: 4 x 22 + 8 x 12 = 184 per step (the count sp_sim's RK4 does;
 * this form executes fewer). The kernel issues 136 FP vector instructions
 * per 8 trajectory-steps (objdump: 4 x 23 for the evaluations, 4 x 11 for
 * the stages). */
#define FV (B / 8) /* vectors a block */
_Static_assert(B % 8 == 0, "the fast kernel steps 8 lanes a vector");

/* The accelerations at positions p = (x, y, dx, dy) into acc. */
__attribute__((target("avx512f,fma"), always_inline)) static inline void
fast_acc(const __m512d p[4], __m512d acc[4], __m512d km, __m512d kL, __m512d g)
{
    const __m512d one = _mm512_set1_pd(1), half = _mm512_set1_pd(0.5),
                  e2 = _mm512_set1_pd(0.375), e3 = _mm512_set1_pd(0.3125);
    const __m512d x = p[0], y = p[1];
    const __m512d r2 = _mm512_fmadd_pd(x, x, _mm512_mul_pd(y, y));
    const __mmask8 off = _mm512_cmp_pd_mask(r2, _mm512_setzero_pd(), _CMP_GT_OQ); /* not the pivot */
    const __m512d r0 = _mm512_rsqrt14_pd(r2);
    const __m512d e = _mm512_fnmadd_pd(r2, _mm512_mul_pd(r0, r0), one);
    const __m512d s = _mm512_fmadd_pd(_mm512_fmadd_pd(e3, e, e2), e, half);
    const __m512d r = _mm512_fmadd_pd(_mm512_mul_pd(r0, e), s, r0);
    const __m512d w = _mm512_maskz_mul_pd(off, kL, r);
    const __m512d mc = _mm512_sub_pd(w, km); /* -c */
    const __m512d a = _mm512_maskz_mul_pd(off, w, _mm512_mul_pd(r, r));
    const __m512d as = _mm512_mul_pd(a, _mm512_fmadd_pd(x, p[2], _mm512_mul_pd(y, p[3])));
    acc[0] = _mm512_mul_pd(mc, x);
    acc[1] = _mm512_fmsub_pd(mc, y, g);
    acc[2] = _mm512_fnmadd_pd(as, x, _mm512_mul_pd(mc, p[2]));
    acc[3] = _mm512_fnmadd_pd(as, y, _mm512_mul_pd(mc, p[3]));
}

/* GCC schedules the loop before allocating its registers (-fschedule-insns,
 * off by default on x86, with -fsched-pressure): the four independent
 * evaluations of a phase interleave in the instruction stream, so that the
 * out-of-order window sees the other chains' work early instead of waiting
 * on one chain's latency (median 1.1x the steps per CPU-second here, up to
 * 1.4x; the same arithmetic, so the same results). */
__attribute__((target("avx512f,fma"), noinline, optimize("schedule-insns", "sched-pressure")))
static void rk4_fast_run(const struct blk *p, double u[NC][B], double h, long n)
{
    static const int pos[4] = {SP_BX, SP_BY, SP_BDX, SP_BDY},
                     vel[4] = {SP_BVX, SP_BVY, SP_BDVX, SP_BDVY};
    const __m512d h2 = _mm512_set1_pd(0.5 * h), h1 = _mm512_set1_pd(h),
                  h6 = _mm512_set1_pd(h / 6), h3 = _mm512_set1_pd(h / 3),
                  hh4 = _mm512_set1_pd(h * h / 4), hh2 = _mm512_set1_pd(h * h / 2),
                  hh6 = _mm512_set1_pd(h * h / 6);
    __m512d km[FV], kL[FV], g[FV], P[FV][4], V[FV][4];
#pragma GCC unroll 8
    for (int j = 0; j < FV; j++) {
        km[j] = _mm512_loadu_pd(p->km + 8 * j);
        kL[j] = _mm512_mul_pd(km[j], _mm512_loadu_pd(p->L0 + 8 * j));
        g[j] = _mm512_loadu_pd(p->g + 8 * j);
#pragma GCC unroll 4
        for (int c = 0; c < 4; c++) {
            P[j][c] = _mm512_loadu_pd(u[pos[c]] + 8 * j);
            V[j][c] = _mm512_loadu_pd(u[vel[c]] + 8 * j);
        }
    }
    for (long i = 0; i < n; i++) {
        __m512d A1[FV][4], A2[FV][4], A3[FV][4], A4[FV][4], X2[FV][4], X3[FV][4], X4[FV][4],
            Q[FV][4];
#pragma GCC unroll 8
        for (int j = 0; j < FV; j++) {
#pragma GCC unroll 4
            for (int c = 0; c < 4; c++)
                X2[j][c] = _mm512_fmadd_pd(h2, V[j][c], P[j][c]);
            fast_acc(P[j], A1[j], km[j], kL[j], g[j]);
            fast_acc(X2[j], A2[j], km[j], kL[j], g[j]);
        }
#pragma GCC unroll 8
        for (int j = 0; j < FV; j++)
#pragma GCC unroll 4
            for (int c = 0; c < 4; c++) {
                X3[j][c] = _mm512_fmadd_pd(hh4, A1[j][c], X2[j][c]);
                Q[j][c] = _mm512_fmadd_pd(h1, V[j][c], P[j][c]);
                X4[j][c] = _mm512_fmadd_pd(hh2, A2[j][c], Q[j][c]);
                /* P + h V + h^2/6 (A1 + A2), V + h/6 A1 + h/3 A2 */
                Q[j][c] = _mm512_fmadd_pd(hh6, A2[j][c], _mm512_fmadd_pd(hh6, A1[j][c], Q[j][c]));
                V[j][c] = _mm512_fmadd_pd(h3, A2[j][c], _mm512_fmadd_pd(h6, A1[j][c], V[j][c]));
            }
#pragma GCC unroll 8
        for (int j = 0; j < FV; j++) {
            fast_acc(X3[j], A3[j], km[j], kL[j], g[j]);
            fast_acc(X4[j], A4[j], km[j], kL[j], g[j]);
#pragma GCC unroll 4
            for (int c = 0; c < 4; c++) {
                P[j][c] = _mm512_fmadd_pd(hh6, A3[j][c], Q[j][c]);
                V[j][c] = _mm512_fmadd_pd(h6, A4[j][c], _mm512_fmadd_pd(h3, A3[j][c], V[j][c]));
            }
        }
    }
#pragma GCC unroll 8
    for (int j = 0; j < FV; j++)
#pragma GCC unroll 4
        for (int c = 0; c < 4; c++) {
            _mm512_storeu_pd(u[pos[c]] + 8 * j, P[j][c]);
            _mm512_storeu_pd(u[vel[c]] + 8 * j, V[j][c]);
        }
}
#else
int sp_batch_fast_supported(void)
{
    return 0;
}
#endif

/* The exact flow of the damping over h (factor f[] = exp(-b h / m) per
 * lane), where a lane has damping; as sim.c's damp. */
SPECIALISED void damp_blk(const struct blk *p, double t, double u[NC][B], const double *f,
                          const int tangent, const int spatial)
{
    double tt[B], vp[B], ap[B];
    for (int l = 0; l < B; l++)
        tt[l] = t;
    pivot_blk(p, tt, vp, ap);
    for (int l = 0; l < B; l++) {
        if (p->bm[l] == 0)
            continue;
        if (spatial) {
            double e = u[SP_BVX][l] * u[SP_BVX][l] + u[SP_BVY][l] * u[SP_BVY][l] +
                       u[SP_BVZ][l] * u[SP_BVZ][l];
            u[SP_BVX][l] *= f[l];
            u[SP_BVY][l] = (u[SP_BVY][l] + vp[l]) * f[l] - vp[l];
            u[SP_BVZ][l] *= f[l];
            u[SP_BW][l] += 0.5 * (u[SP_BVX][l] * u[SP_BVX][l] + u[SP_BVY][l] * u[SP_BVY][l] +
                                  u[SP_BVZ][l] * u[SP_BVZ][l] - e);
        } else {
            double e = u[SP_BVX][l] * u[SP_BVX][l] + u[SP_BVY][l] * u[SP_BVY][l];
            u[SP_BVX][l] *= f[l];
            u[SP_BVY][l] = (u[SP_BVY][l] + vp[l]) * f[l] - vp[l];
            u[SP_BW][l] += 0.5 * (u[SP_BVX][l] * u[SP_BVX][l] + u[SP_BVY][l] * u[SP_BVY][l] - e);
        }
        if (tangent) {
            u[SP_BDVX][l] *= f[l];
            u[SP_BDVY][l] *= f[l];
            if (spatial)
                u[SP_BDVZ][l] *= f[l];
        }
    }
}

/* A kick of h with the cached force a[] (ax, ay, a_pivot, J, and in 3-D az
 * and J's z entries); as sim.c's kick. */
SPECIALISED void kick_blk(double u[NC][B], double h, double a[NA][B], const int forced,
                          const int tangent, const int spatial)
{
    LANES {
        double vy = u[SP_BVY][l];
        u[SP_BVX][l] += h * a[A_X][l];
        u[SP_BVY][l] += h * a[A_Y][l];
        if (spatial)
            u[SP_BVZ][l] += h * a[A_Z][l];
        if (forced)
            u[SP_BW][l] -= a[A_P][l] * 0.5 * (vy + u[SP_BVY][l]) * h;
        if (tangent && spatial) {
            double dx = u[SP_BDX][l], dy = u[SP_BDY][l], dz = u[SP_BDZ][l];
            u[SP_BDVX][l] += h * (a[J_XX][l] * dx + a[J_XY][l] * dy + a[J_XZ][l] * dz);
            u[SP_BDVY][l] += h * (a[J_XY][l] * dx + a[J_YY][l] * dy + a[J_YZ][l] * dz);
            u[SP_BDVZ][l] += h * (a[J_XZ][l] * dx + a[J_YZ][l] * dy + a[J_ZZ][l] * dz);
        } else if (tangent) {
            double dx = u[SP_BDX][l], dy = u[SP_BDY][l];
            u[SP_BDVX][l] += h * (a[J_XX][l] * dx + a[J_XY][l] * dy);
            u[SP_BDVY][l] += h * (a[J_XY][l] * dx + a[J_YY][l] * dy);
        }
    }
}

/* The force cache at u for pivot accelerations a[2][] (sim.c's accel_q),
 * with the Jacobian when the tangent is integrated. */
SPECIALISED void force_blk(const struct blk *p, double u[NC][B], double a[NA][B],
                           const int tangent, const int spatial)
{
    LANES {
        double x = u[SP_BX][l], y = u[SP_BY][l], z = spatial ? u[SP_BZ][l] : 0;
        double rho = spatial ? sqrt(x * x + y * y + z * z) : sqrt(x * x + y * y);
        double q = rho > 0 ? p->L0[l] / rho : 0;
        double c = p->km[l] * (1 - q);
        a[A_X][l] = -c * x;
        a[A_Y][l] = -c * y - p->g[l] - a[A_P][l];
        if (spatial)
            a[A_Z][l] = -c * z;
        if (tangent) {
            double s = p->kl[l] * q * q * q;
            a[J_XX][l] = -c - s * x * x;
            a[J_XY][l] = -s * x * y;
            a[J_YY][l] = -c - s * y * y;
            if (spatial) {
                a[J_XZ][l] = -s * x * z;
                a[J_YZ][l] = -s * y * z;
                a[J_ZZ][l] = -c - s * z * z;
            }
        }
    }
}

/* The pivot's acceleration at t into a[2][] (0 where the pivot is fixed). */
static inline void pivot_accel_blk(const struct blk *p, double t, double a[NA][B], const int forced)
{
    double tt[B], vp[B];
    if (!forced) {
        for (int l = 0; l < B; l++)
            a[A_P][l] = 0;
        return;
    }
    for (int l = 0; l < B; l++)
        tt[l] = t;
    pivot_blk(p, tt, vp, a[A_P]);
}

#define CBRT2 1.2599210498948731648
static const double verlet_w[] = {1};
static const double yoshida_w[] = {1 / (2 - CBRT2), -CBRT2 / (2 - CBRT2), 1 / (2 - CBRT2)};

/* One symmetric composition step of n Stormer-Verlet substeps; as sim.c's
 * splitting_step. f[i][] = exp(-b (w[i] h / 2) / m) per lane. */
SPECIALISED void splitting_blk(const struct blk *p, double t, double u[NC][B], double h,
                               const double *w, int n, double a[NA][B], double f[3][B],
                               const int forced, const int tangent, const int spatial)
{
    for (int i = 0; i < n; i++) {
        double hi = w[i] * h;
        if (forced)
            damp_blk(p, t, u, f[i], tangent, spatial);
        kick_blk(u, 0.5 * hi, a, forced, tangent, spatial);
        LANES {
            u[SP_BX][l] += hi * u[SP_BVX][l];
            u[SP_BY][l] += hi * u[SP_BVY][l];
            if (spatial)
                u[SP_BZ][l] += hi * u[SP_BVZ][l];
            if (tangent) {
                u[SP_BDX][l] += hi * u[SP_BDVX][l];
                u[SP_BDY][l] += hi * u[SP_BDVY][l];
                if (spatial)
                    u[SP_BDZ][l] += hi * u[SP_BDVZ][l];
            }
        }
        t += hi;
        pivot_accel_blk(p, t, a, forced);
        force_blk(p, u, a, tangent, spatial);
        kick_blk(u, 0.5 * hi, a, forced, tangent, spatial);
        if (forced)
            damp_blk(p, t, u, f[i], tangent, spatial);
    }
}

/* fmax(a, b) as a select, so that a loop with it vectorises (GCC calls libm's
 * fmax otherwise): a where a >= b or b is NaN, else b. The same value as
 * fmax wherever the two are not zeros of opposite sign. */
static inline double max_or_number(double a, double b)
{
    return b != b ? a : a >= b ? a : b;
}

/* sim.c's energy test per lane; marks and poisons the lanes that fail.
 * Branch-free over the lanes (it vectorises, in each clone: a fast-kernel
 * step costs about 16 times less than one check over the block); the rare
 * failure is handled after. */
SPECIALISED void check_blk(struct sp_batch *b, int base, double u[NC][B], unsigned char *dead,
                           const int forced, const int tangent, const int spatial)
{
    int bad[B], any = 0;
    LANES {
        const int i = base + l;
        double x = u[SP_BX][l], y = u[SP_BY][l], vx = u[SP_BVX][l], vy = u[SP_BVY][l];
        double z = spatial ? u[SP_BZ][l] : 0, vz = spatial ? u[SP_BVZ][l] : 0;
        double stretch = (spatial ? sqrt(x * x + y * y + z * z) : sqrt(x * x + y * y)) - b->L0[i];
        double kin = 0.5 * b->mass[i] * (spatial ? vx * vx + vy * vy + vz * vz : vx * vx + vy * vy);
        double spring = 0.5 * b->stiff[i] * stretch * stretch;
        double grav = b->mass[i] * b->g[i] * y;
        double work = forced ? b->mass[i] * u[SP_BW][l] : 0;
        double total = kin + spring + grav;
        /* sim.c's scale: the largest the energy of the motion has been (total
         * less the least the scene can hold), never below its rounding */
        double motion = max_or_number(total - b->emin[i],
                                      1e-12 * (kin + spring + fabs(grav) + fabs(b->emin[i]) +
                                               b->stiff[i] * b->L0[i] * b->L0[i]));
        double scale = max_or_number(b->escale[i], motion); /* both > 0: no signed zeros */
        double drift = (total - b->e0[i] - work) / scale;
        b->escale[i] = scale;
        /* a NaN anywhere in the state makes the drift or the tangent's sum NaN */
        double t = tangent ? u[SP_BDX][l] + u[SP_BDY][l] + u[SP_BDVX][l] + u[SP_BDVY][l] : 0;
        if (spatial && tangent)
            t += u[SP_BDZ][l] + u[SP_BDVZ][l];
        bad[l] = fabs(drift) <= b->drift_limit && t - t == 0 ? 0 : 1;
        any |= bad[l];
    }
    if (!any)
        return;
    for (int l = 0; l < B; l++)
        if (bad[l] && !dead[l]) {
            dead[l] = 1;
            for (int c = 0; c < NC; c++)
                u[c][l] = NAN;
        }
}

static void load_blk(const struct sp_batch *b, int base, struct blk *p)
{
    memcpy(p->km, b->km + base, sizeof(p->km));
    memcpy(p->L0, b->L0 + base, sizeof(p->L0));
    memcpy(p->g, b->g + base, sizeof(p->g));
    memcpy(p->bm, b->bm + base, sizeof(p->bm));
    memcpy(p->amp, b->amp + base, sizeof(p->amp));
    memcpy(p->om, b->om + base, sizeof(p->om));
    for (int l = 0; l < B; l++) {
        /* L0^2 underflows below L0 = 1.5e-154 m: kl would be +inf and the
         * Jacobian's kl q^3 inf * 0 = NaN, a false blow-up (attack10 #4).
         * There kl q^3 x^2 = k L0 x^2 / (m rho^3) <= km q, under half an ulp
         * of c = km (1 - q) while rho > 2^54 L0 (1e-137 m): 0 is exact */
        const double L2 = p->L0[l] * p->L0[l];
        p->kl[l] = L2 >= DBL_MIN ? p->km[l] / L2 : 0;
    }
}

/* Walks one block's grid from index n0 to n1 with step dt, then writes the
 * state at t_target (one short step from a copy when off the grid). */
SPECIALISED void fixed_blk_impl(struct sp_batch *b, int base, long n0, long n1, double t_target,
                                const int forced, const int tangent, const int spatial)
{
    struct blk p;
    double u[NC][B], a[NA][B], f[3][B], fs[3][B];
    unsigned char dead[B];
    const int split = b->method != SP_METHOD_RK4;
#ifdef FAST_KERNEL
    /* (b->fast: where supported) */
    const int fast = b->fast && !split && !forced && tangent && !spatial;
    const long every = fast ? CHECK_EVERY_FAST : CHECK_EVERY;
#else
    const long every = CHECK_EVERY;
#endif
    const double *w = b->method == SP_METHOD_VERLET ? verlet_w : yoshida_w;
    const int nw = b->method == SP_METHOD_VERLET ? 1 : 3;
    load_blk(b, base, &p);
    memcpy(dead, b->dead + base, sizeof(dead));
    for (int c = 0; c < NC; c++)
        memcpy(u[c], b->u[c] + base, sizeof(u[c]));
    if (split) {
        for (int c = 0; c < NCACHE(spatial); c++)
            memcpy(a[c], b->cache[c] + base, sizeof(a[c]));
        if (forced)
            for (int i = 0; i < nw; i++)
                for (int l = 0; l < B; l++)
                    f[i][l] = exp(-p.bm[l] * (0.5 * (w[i] * b->dt)));
    }
    for (long n = n0; n < n1; n++) {
        if (split)
            splitting_blk(&p, (double)n * b->dt, u, b->dt, w, nw, a, f, forced, tangent, spatial);
#ifdef FAST_KERNEL
        else if (fast) {
            /* to the next energy check (or n1) in one call */
            const long m = (n / every + 1) * every < n1 ? (n / every + 1) * every - n : n1 - n;
            rk4_fast_run(&p, u, b->dt, m);
            n += m - 1;
        }
#endif
        else
            rk4_blk(&p, (double)n * b->dt, u, b->dt, forced, tangent, spatial);
        if ((n + 1) % every == 0)
            check_blk(b, base, u, dead, forced, tangent, spatial);
    }
    check_blk(b, base, u, dead, forced, tangent, spatial);
    for (int c = 0; c < NC; c++)
        memcpy(b->u[c] + base, u[c], sizeof(u[c]));
    memcpy(b->dead + base, dead, sizeof(dead));
    if (split)
        for (int c = 0; c < NCACHE(spatial); c++)
            memcpy(b->cache[c] + base, a[c], sizeof(a[c]));
    double t1 = (double)n1 * b->dt;
    if (t_target > t1) {
        double h = t_target - t1;
        if (split) {
            if (forced)
                for (int i = 0; i < nw; i++)
                    for (int l = 0; l < B; l++)
                        fs[i][l] = exp(-p.bm[l] * (0.5 * (w[i] * h)));
            splitting_blk(&p, t1, u, h, w, nw, a, fs, forced, tangent, spatial);
        } else {
            rk4_blk(&p, t1, u, h, forced, tangent, spatial);
        }
        check_blk(b, base, u, dead, forced, tangent, spatial);
        memcpy(b->dead + base, dead, sizeof(dead));
    }
    for (int c = 0; c < NC; c++)
        memcpy(b->out[c] + base, u[c], sizeof(u[c]));
}

/* One specialised (and cloned) copy per forced, tangent, spatial. */
#define FIXED(F, T, S)                                                                    \
    CLONES static void fixed_blk_##F##T##S(struct sp_batch *b, int base, long n0, long n1, \
                                           double t)                                      \
    {                                                                                     \
        fixed_blk_impl(b, base, n0, n1, t, F, T, S);                                      \
    }
FIXED(0, 0, 0) FIXED(0, 1, 0) FIXED(1, 0, 0) FIXED(1, 1, 0)
FIXED(0, 0, 1) FIXED(0, 1, 1) FIXED(1, 0, 1) FIXED(1, 1, 1)

/* ---- the adaptive method: DOP853, per-lane step control ------------------ */

#include "sim_tableaus.h"

/* The DOP853 error norm of sim.c (Hairer's), per lane: e5, e3 are the two
 * embedded error estimates (without the factor h). */
static inline double dop853_err(double h, double n5, double n3)
{
    if (n5 == 0 && n3 == 0)
        return 0;
    return fabs(h) * n5 * n5 / sqrt(n5 * n5 + 0.01 * n3 * n3);
}

/* Advances block `base` (B lanes) to t_target with DOP853, each lane with
 * its own step h (b->h), accepted or rejected by its own error norm; dead
 * lanes stay where they stopped.
 * Long: one step loop (stages, error norm, step control) over stack arrays
 * of 12 stages x NC x B doubles, the hot path of adaptive sweeps; it was
 * measured whole (doc/sweeps.md), and a split needs that benchmark again. */
SPECIALISED void adaptive_blk_impl(struct sp_batch *b, int base, double t_target,
                                   const int forced, const int tangent, const int spatial)
{
    struct blk p;
    double y[NC][B], u[NC][B], v[NC][B], k[12][NC][B];
    double tl[B], hh[B], tt[B], err[B];
    unsigned char dead[B], rejected[B];
    load_blk(b, base, &p);
    memcpy(dead, b->dead + base, sizeof(dead));
    memset(rejected, 0, sizeof(rejected));
    for (int c = 0; c < NC; c++)
        memcpy(y[c], b->u[c] + base, sizeof(y[c]));
    for (int l = 0; l < B; l++)
        tl[l] = dead[l] ? t_target : b->t;
    for (;;) {
        int active = 0;
        if (b->cancel && *b->cancel)
            break; /* part-way: sp_batch_advance says so */
        for (int l = 0; l < B; l++) {
            double h = b->h[base + l];
            hh[l] = tl[l] < t_target ? fmin(h, t_target - tl[l]) : 0;
            if (tl[l] < t_target && !(hh[l] > 1e-14 * fmax(1, fabs(tl[l])))) {
                dead[l] = 1, tl[l] = t_target, hh[l] = 0; /* the step collapsed */
                for (int c = 0; c < NC; c++)
                    y[c][l] = NAN;
            }
            active |= hh[l] > 0;
        }
        if (!active)
            break;
        rhs_blk(&p, tl, y, k[0], forced, tangent, spatial);
        for (int s = 1; s < 13; s++) {
            double(*dst)[B] = s < 12 ? v : u;
            COMPS {
                if (!USED(c, forced, tangent, spatial))
                    continue;
                for (int l = 0; l < B; l++) {
                    double acc = 0;
                    for (int j = 0; j < s; j++)
                        acc += d8_a[s][j] * k[j][c][l];
                    dst[c][l] = y[c][l] + hh[l] * acc;
                }
            }
            if (s < 12) {
                for (int l = 0; l < B; l++)
                    tt[l] = tl[l] + d8_c[s] * hh[l];
                rhs_blk(&p, tt, v, k[s], forced, tangent, spatial);
            }
        }
        /* over the physical components, as sim.c's err_norm: x, y, vx, vy,
         * and z, vz in 3-D (a planar trajectory's are 0, and it divides by 4) */
        static const int phys[6] = {SP_BX, SP_BY, SP_BVX, SP_BVY, SP_BZ, SP_BVZ};
        for (int l = 0; l < B; l++) {
            double n5 = 0, n3 = 0;
            for (int i = 0; i < (spatial ? 6 : 4); i++) {
                const int c = phys[i];
                double e5 = 0, e3 = 0;
                for (int j = 0; j < 12; j++) {
                    e5 += d8_e5[j] * k[j][c][l];
                    e3 += d8_e3[j] * k[j][c][l];
                }
                double at = c == SP_BX || c == SP_BY || c == SP_BZ ? b->atol_q[base + l]
                                                                   : b->atol_v[base + l];
                double sc = at + b->tol * fmax(fabs(y[c][l]), fabs(u[c][l]));
                n5 += (e5 / sc) * (e5 / sc);
                n3 += (e3 / sc) * (e3 / sc);
            }
            const double np = spatial ? b->nphys[base + l] : 4;
            err[l] = dop853_err(hh[l], sqrt(n5 / np), sqrt(n3 / np));
        }
        for (int l = 0; l < B; l++) {
            if (!(hh[l] > 0))
                continue;
            double *h = &b->h[base + l];
            if (err[l] <= 1) {
                double fac = err[l] == 0 ? 6 : fmin(6, fmax(0.333, 0.9 / sqrt(sqrt(sqrt(err[l])))));
                if (rejected[l])
                    fac = fmin(fac, 1);
                rejected[l] = 0;
                int cut = hh[l] < *h; /* shortened to land on t_target */
                tl[l] = cut ? t_target : tl[l] + hh[l];
                *h = cut ? fmax(*h, hh[l] * fac) : hh[l] * fac;
                COMPS
                    y[c][l] = USED(c, forced, tangent, spatial) ? u[c][l] : y[c][l];
                b->steps++;
            } else {
                *h = hh[l] * (isfinite(err[l]) ? fmax(0.333, 0.9 / sqrt(sqrt(sqrt(err[l]))))
                                               : 0.333);
                rejected[l] = 1;
            }
        }
        check_blk(b, base, y, dead, forced, tangent, spatial);
        for (int l = 0; l < B; l++)
            if (dead[l])
                tl[l] = t_target;
    }
    for (int c = 0; c < NC; c++) {
        memcpy(b->u[c] + base, y[c], sizeof(y[c]));
        memcpy(b->out[c] + base, y[c], sizeof(y[c]));
    }
    memcpy(b->dead + base, dead, sizeof(dead));
}

#define ADAPTIVE(F, T, S)                                                          \
    CLONES static void adaptive_blk_##F##T##S(struct sp_batch *b, int base, double t) \
    {                                                                              \
        adaptive_blk_impl(b, base, t, F, T, S);                                    \
    }
ADAPTIVE(0, 0, 0) ADAPTIVE(0, 1, 0) ADAPTIVE(1, 0, 0) ADAPTIVE(1, 1, 0)
ADAPTIVE(0, 0, 1) ADAPTIVE(0, 1, 1) ADAPTIVE(1, 0, 1) ADAPTIVE(1, 1, 1)

/* ---- the batch ----------------------------------------------------------- */

int sp_batch_advance(struct sp_batch *b, double t_target)
{
    const int sel = b->spatial * 4 + b->forced * 2 + b->tangent;
    if (b->method == SP_METHOD_DOP853) {
        static void (*const fn[8])(struct sp_batch *, int, double) = {
            adaptive_blk_000, adaptive_blk_010, adaptive_blk_100, adaptive_blk_110,
            adaptive_blk_001, adaptive_blk_011, adaptive_blk_101, adaptive_blk_111};
        if (t_target > b->t)
            for (int base = 0; base < b->cap; base += B) {
                fn[sel](b, base, t_target);
                if (b->cancel && *b->cancel)
                    return SP_E_INTERRUPTED;
            }
    } else {
        static void (*const fn[8])(struct sp_batch *, int, long, long, double) = {
            fixed_blk_000, fixed_blk_010, fixed_blk_100, fixed_blk_110,
            fixed_blk_001, fixed_blk_011, fixed_blk_101, fixed_blk_111};
        long n1 = b->grid;
        const double guess = floor(t_target / b->dt) - 1; /* then exact below */
        if (guess > (double)n1 && guess < 0x1p52)
            n1 = (long)guess;
        while ((double)(n1 + 1) * b->dt <= t_target)
            n1++;
        /* whole chunks on the grid first (their states are the grid's, and
         * their ends fall on energy checks), then the rest to t_target */
        for (long c = (b->grid / SP_BATCH_CHUNK + 1) * SP_BATCH_CHUNK; c < n1;
             c += SP_BATCH_CHUNK) {
            if (b->cancel && *b->cancel)
                return SP_E_INTERRUPTED;
            for (int base = 0; base < b->cap; base += B)
                fn[sel](b, base, b->grid, c, (double)c * b->dt);
            b->steps += c - b->grid;
            b->grid = c;
        }
        if (b->cancel && *b->cancel)
            return SP_E_INTERRUPTED;
        for (int base = 0; base < b->cap; base += B)
            fn[sel](b, base, b->grid, n1, t_target);
        b->steps += n1 - b->grid;
        b->grid = n1;
    }
    b->t = t_target;
    return 0;
}

void sp_batch_renormalise(struct sp_batch *b, double *growth)
{
    static const int tan_c[6] = {SP_BDX, SP_BDY, SP_BDVX, SP_BDVY, SP_BDZ, SP_BDVZ};
    const int nt = b->spatial ? 6 : 4;
    for (int i = 0; i < b->n; i++) {
        double *u[NC], *o[NC];
        for (int c = 0; c < NC; c++)
            u[c] = &b->u[c][i], o[c] = &b->out[c][i];
        /* summed left to right from the first: the planar sum's bits */
        double n2 = 0;
        for (int k = 0; k < nt; k++)
            n2 += *u[tan_c[k]] * *u[tan_c[k]];
        double nrm = sqrt(n2);
        growth[i] = log(nrm);
        for (int k = 0; k < nt; k++) {
            *u[tan_c[k]] /= nrm;
            *o[tan_c[k]] = *u[tan_c[k]];
        }
    }
}

void sp_batch_reset_tangent(struct sp_batch *b)
{
    for (int i = 0; i < b->cap; i++) {
        int dead = b->dead[i];
        b->u[SP_BDX][i] = b->out[SP_BDX][i] = dead ? NAN : 1;
        b->u[SP_BDY][i] = b->out[SP_BDY][i] = dead ? NAN : 0;
        b->u[SP_BDVX][i] = b->out[SP_BDVX][i] = dead ? NAN : 0;
        b->u[SP_BDVY][i] = b->out[SP_BDVY][i] = dead ? NAN : 0;
        if (b->spatial)
            b->u[SP_BDZ][i] = b->out[SP_BDZ][i] = b->u[SP_BDVZ][i] = b->out[SP_BDVZ][i] =
                dead ? NAN : 0;
    }
    /* the splitting methods' cached Jacobian is of the position, unchanged */
}

void sp_batch_set_tangent(struct sp_batch *b, int i, const double d[4])
{
    for (int c = 0; c < 4; c++)
        b->u[SP_BDX + c][i] = b->out[SP_BDX + c][i] = b->dead[i] ? NAN : d[c];
}

void sp_batch_destroy(struct sp_batch **b)
{
    if (!*b)
        return;
    free((*b)->mem);
    free(*b);
    *b = NULL;
}

int sp_batch_make(struct sp_batch **out, const struct sp_scene *const *scenes, int n,
                  int tangent, int force_forced)
{
    const struct sp_scene *s0 = scenes[0];
    struct sp_batch *b = calloc(1, sizeof(*b));
    *out = NULL;
    if (s0->integrator.method == SP_METHOD_RKN1210) {
        sp_log_error("rkn1210 is not available for many trajectories at once; "
                     "use rk4, verlet, yoshida4, dopri5 or dop853");
        free(b);
        return SP_E_INPUT;
    }
    if (!b)
        goto nomem;
    b->n = n;
    b->cap = (n + B - 1) / B * B;
    b->method = s0->integrator.method == SP_METHOD_DOPRI5 ? SP_METHOD_DOP853
                                                          : s0->integrator.method;
    b->tangent = tangent;
    b->dt = s0->integrator.dt;
    b->tol = s0->integrator.tolerance;
    /* 2 NC state arrays, NA cache, 15 per-trajectory values, dead bytes */
    const int n_arrays = 2 * NC + NA + 16;
    b->mem = calloc((size_t)b->cap * n_arrays + (size_t)b->cap / 8 + 1, sizeof(double));
    if (!b->mem)
        goto nomem;
    double *m = b->mem;
    for (int c = 0; c < NC; c++)
        b->u[c] = m, m += b->cap, b->out[c] = m, m += b->cap;
    for (int c = 0; c < NA; c++)
        b->cache[c] = m, m += b->cap;
    double **arr[] = {&b->km, &b->L0, &b->g, &b->bm, &b->amp, &b->om, &b->mass, &b->stiff,
                      &b->e0, &b->escale, &b->emin, &b->atol_q, &b->atol_v, &b->h, &b->nphys};
    for (size_t i = 0; i < sizeof(arr) / sizeof(arr[0]); i++)
        *arr[i] = m, m += b->cap;
    b->dead = (unsigned char *)m;
    b->forced = force_forced;
    for (int i = 0; i < n; i++) {
        struct sp_sim sim;
        sp_sim_init(&sim, scenes[i]);
        b->spatial |= sim.spatial;
    }
    for (int i = 0; i < b->cap; i++) {
        /* sp_sim_init derives everything a trajectory starts from */
        struct sp_sim sim;
        const struct sp_scene *sc = scenes[i < n ? i : n - 1];
        sp_sim_init(&sim, sc);
        b->km[i] = sim.p.k_over_m, b->L0[i] = sim.p.L0, b->g[i] = sim.p.g;
        b->bm[i] = sim.p.b_over_m, b->amp[i] = sim.p.drive_amp, b->om[i] = sim.p.drive_omega;
        b->mass[i] = sim.p.mass, b->stiff[i] = sim.p.stiffness;
        b->e0[i] = sim.energy0, b->escale[i] = sim.energy_scale, b->emin[i] = sim.energy_min;
        b->drift_limit = sim.drift_limit;
        b->atol_q[i] = sim.atol[0], b->atol_v[i] = sim.atol[2];
        b->h[i] = sim.h;
        b->nphys[i] = sim.spatial ? 6 : 4;
        b->forced |= sim.forced;
        b->u[SP_BX][i] = sim.s.x, b->u[SP_BY][i] = sim.s.y;
        b->u[SP_BVX][i] = sim.s.vx, b->u[SP_BVY][i] = sim.s.vy;
        b->u[SP_BZ][i] = sim.s.z, b->u[SP_BVZ][i] = sim.s.vz;
        b->u[SP_BDX][i] = 1;
        for (int c = 0; c < NC; c++)
            b->out[c][i] = b->u[c][i];
        for (int c = 0; c < 3; c++)
            b->cache[c][i] = sim.force[c];
        /* sim.c's az (force[3]), which a planar trajectory's z = 0 makes
         * (+ or -) 0 */
        b->cache[A_Z][i] = sim.spatial ? sim.force[3] : 0;
    }
    /* the Jacobian part of the splitting methods' cache */
    for (int base = 0; base < b->cap; base += B) {
        struct blk p;
        double u[NC][B], a[NA][B];
        load_blk(b, base, &p);
        for (int c = 0; c < NC; c++)
            memcpy(u[c], b->u[c] + base, sizeof(u[c]));
        for (int l = 0; l < B; l++)
            a[A_P][l] = b->cache[A_P][base + l];
        if (b->spatial)
            force_blk(&p, u, a, 1, 1);
        else
            force_blk(&p, u, a, 1, 0);
        for (int c = J_XX; c < NCACHE(b->spatial); c++)
            if (c != A_Z)
                memcpy(b->cache[c] + base, a[c], sizeof(a[c]));
    }
    *out = b;
    return 0;
nomem:
    sp_log_error("out of memory for a batch of %d trajectories", n);
    sp_batch_destroy(&b);
    return SP_E_NOMEM;
}
