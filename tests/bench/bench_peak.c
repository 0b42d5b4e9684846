/* What one core of this machine can issue in double precision (issue 25's
 * "divide by what the core can issue"), measured, not taken from a data
 * sheet: the throughput of fused multiply-adds (12 independent chains, so
 * latency does not limit them) on 512-bit and 256-bit vectors, and of the
 * square root and division (the divider; 12 independent chains too), per
 * second of this thread's own CPU time, so that other processes on a shared
 * machine are not counted. From them: the FP64 peak (flops per s, an FMA
 * being 2), and the most RK4 steps with the tangent equations per second
 * that one square root and one division per evaluation (4 of each per step)
 * leave room for. Prints key = value lines; x86-64 with AVX-512F or AVX2
 * and FMA only (else says so and exits 77).
 * usage: bench_peak [SECONDS_PER_TEST] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#define CH 12 /* independent chains: more than latency x ports */

static double thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Each measures n rounds of CH instructions and returns CPU s; the chains'
 * sum goes to *sink so nothing is optimised away. */
__attribute__((target("avx512f"), noinline)) static double fma512(long n, double *sink)
{
    __m512d a[CH], m = _mm512_set1_pd(0.9999999), c = _mm512_set1_pd(1e-9);
    for (int i = 0; i < CH; i++)
        a[i] = _mm512_set1_pd(1.0 + i);
    double t0 = thread_cpu();
    for (long k = 0; k < n; k++)
#pragma GCC unroll 16
        for (int i = 0; i < CH; i++)
            a[i] = _mm512_fmadd_pd(a[i], m, c);
    double t = thread_cpu() - t0;
    for (int i = 0; i < CH; i++)
        *sink += _mm512_reduce_add_pd(a[i]);
    return t;
}

__attribute__((target("avx2,fma"), noinline)) static double fma256(long n, double *sink)
{
    __m256d a[CH], m = _mm256_set1_pd(0.9999999), c = _mm256_set1_pd(1e-9);
    for (int i = 0; i < CH; i++)
        a[i] = _mm256_set1_pd(1.0 + i);
    double t0 = thread_cpu();
    for (long k = 0; k < n; k++)
#pragma GCC unroll 16
        for (int i = 0; i < CH; i++)
            a[i] = _mm256_fmadd_pd(a[i], m, c);
    double t = thread_cpu() - t0;
    for (int i = 0; i < CH; i++)
        *sink += a[i][0] + a[i][3];
    return t;
}

__attribute__((target("avx512f"), noinline)) static double sqrt512(long n, int div, double *sink)
{
    __m512d a[CH], b = _mm512_set1_pd(1.0000001);
    for (int i = 0; i < CH; i++)
        a[i] = _mm512_set1_pd(2.0 + i);
    double t0 = thread_cpu();
    for (long k = 0; k < n; k++)
#pragma GCC unroll 16
        for (int i = 0; i < CH; i++)
            a[i] = div ? _mm512_div_pd(b, a[i]) : _mm512_sqrt_pd(a[i]);
    double t = thread_cpu() - t0;
    for (int i = 0; i < CH; i++)
        *sink += _mm512_reduce_add_pd(a[i]);
    return t;
}

__attribute__((target("avx2"), noinline)) static double sqrt256(long n, int div, double *sink)
{
    __m256d a[CH], b = _mm256_set1_pd(1.0000001);
    for (int i = 0; i < CH; i++)
        a[i] = _mm256_set1_pd(2.0 + i);
    double t0 = thread_cpu();
    for (long k = 0; k < n; k++)
#pragma GCC unroll 16
        for (int i = 0; i < CH; i++)
            a[i] = div ? _mm256_div_pd(b, a[i]) : _mm256_sqrt_pd(a[i]);
    double t = thread_cpu() - t0;
    for (int i = 0; i < CH; i++)
        *sink += a[i][0] + a[i][3];
    return t;
}

/* The best of 5 runs of about `secs` s each: n rounds per run. */
static double best(double (*f)(long, double *), long n, double *sink)
{
    double t = INFINITY;
    for (int r = 0; r < 5; r++)
        t = fmin(t, f(n, sink));
    return t;
}

static double best_div(double (*f)(long, int, double *), long n, int div, double *sink)
{
    double t = INFINITY;
    for (int r = 0; r < 5; r++)
        t = fmin(t, f(n, div, sink));
    return t;
}

int main(int argc, char **argv)
{
    double secs = argc > 1 ? atof(argv[1]) : 0.2, sink = 0;
    __builtin_cpu_init();
    const int avx512 = __builtin_cpu_supports("avx512f");
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
        printf("1..0 # SKIP no AVX2 and FMA\n");
        return 77;
    }
    const long n_fma = (long)(secs * 3e8 / CH), n_div = (long)(secs * 4e7 / CH);
    double f256 = 8.0 * CH * n_fma / best(fma256, n_fma, &sink); /* 4 lanes x 2 flops */
    printf("fma256_gflops = %.4g\n", f256 / 1e9);
    double peak = f256, s = 0, d = 0;
    int lanes = 4;
    if (avx512) {
        double f512 = 16.0 * CH * n_fma / best(fma512, n_fma, &sink);
        printf("fma512_gflops = %.4g\n", f512 / 1e9);
        peak = fmax(peak, f512);
    }
    /* the divider at the width the batch's AVX-512 clone uses (8 lanes),
     * else 4; ns per instruction */
    if (avx512) {
        s = best_div(sqrt512, n_div, 0, &sink) / (CH * (double)n_div);
        d = best_div(sqrt512, n_div, 1, &sink) / (CH * (double)n_div);
        lanes = 8;
    } else {
        s = best_div(sqrt256, n_div, 0, &sink) / (CH * (double)n_div);
        d = best_div(sqrt256, n_div, 1, &sink) / (CH * (double)n_div);
    }
    printf("sqrt_ns = %.4g\ndiv_ns = %.4g\nlanes = %d\n", s * 1e9, d * 1e9, lanes);
    printf("peak_gflops = %.4g\n", peak / 1e9);
    /* an RK4 step with tangents: 4 evaluations, each one sqrt and one div */
    const double ceiling = lanes / (4 * (s + d));
    printf("divider_ceiling_steps = %.4g\n", ceiling);
    printf("divider_ceiling_share_204 = %.4g\n", ceiling * 204 / peak);
    if (sink != sink) /* never: the chains' results are used */
        printf("nan\n");
    return 0;
}
#else
int main(void)
{
    printf("1..0 # SKIP not x86-64 with GCC\n");
    return 77;
}
#endif
