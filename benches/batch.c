/* batch.c: the closed loop of benches/baseline.c over arrays of runs side by side
 * (structure of arrays), the machine's yardstick for stepping many runs at once (issue 15).
 *
 * Same loop as baseline.c, operation for operation: the paper's law (pose mode, hold
 * radius), two wheel PD servos, the torque drive with its motor torque clamp, the dynamic
 * model (15) of docs/model.md and classic RK4, 1 ms, 60 s. Goal (1, 1, 120 deg) for every
 * run. Run 0 starts at Fig. 7's start (0, 0, 0), so its final pose can be checked against
 * baseline.c's; the other runs start at seeded random poses within 2 m of the goal
 * (uniform over the disc, any heading).
 *
 * Each time step advances every run by one step, phase by phase (RK4 stages, the control
 * tick), each phase a loop over the runs: with vector instructions, 4 runs per instruction
 * (AVX2). The law's branches are written as selects
 * (both sides computed, one kept), which gives the same numbers as branching; a run that
 * diverges (non-finite state, outside the 1 km box) keeps its last state, as baseline.c's
 * loop stops there.
 *
 * Two builds (benches/compare makes both):
 *   scalar: cc -O2 -o batch benches/batch.c -lm
 *     glibc's scalar sin, cos (merged into sincos by gcc, as in baseline.c), atan2, hypot;
 *     the loops over runs stay scalar. Its batch is the exact path, bit for bit.
 *   AVX2:   cc -O3 -mavx2 -mfma -fno-math-errno -fno-trapping-math -fno-builtin-sin
 *              -fno-builtin-cos -fopenmp-simd -DWMR_SIMD -o batch-avx2 benches/batch.c -lmvec -lm
 *     WMR_SIMD declares sin, cos, atan2 and hypot `omp declare simd`, so gcc 12 calls glibc's
 *     vector math library (libmvec: _ZGVdN4v_sin, _ZGVdN4v_cos, _ZGVdN4vv_atan2,
 *     _ZGVdN4vv_hypot; within 4 ulp, not correctly rounded) on 4 runs at once, and -mfma
 *     contracts a * b + c into one rounding. The other flags change no value: without
 *     -fno-math-errno and -fno-trapping-math gcc will not if-convert (so not vectorize) the
 *     loops, and without -fno-builtin-sin/cos it merges sin and cos into sincos, whose
 *     complex result has no vector form. No -ffast-math: no reassociation, no finite-math
 *     (the divergence check stays). Every transcendental of baseline.c is evaluated, per run
 *     and step: 4 sin and 4 cos (RK4 stages), hypot, atan2 and cos (control tick); the
 *     calls sit in loops of their own, since gcc 12 does not if-convert a block with a call.
 * Each build also runs every run alone through the exact path (glibc's scalar functions,
 * no vectors, no FMA contraction: the same kernel compiled a second time with
 * fp-contract=off and no vectorizing) and prints the largest difference of a final pose
 * component, relative to max(|exact|, 1) (m, rad). The scalar build's batch is the exact
 * path, so its difference must be 0.
 *
 * Run:   ./batch [REPS] [RUNS]     (REPS timed repetitions of the 60 s, default 5; RUNS runs
 *                                   side by side, default 64)
 * Output, one line:
 *   impl=c_batch build=<scalar|avx2> runs=<n> steps=<n> x0=<m> y0=<m> theta0=<rad>
 *   median_s=<s> ns_per_run_step=<ns> live_steps=<f> max_rel_diff=<d> median_rel_diff=<d>
 *   runs_over_1e_9=<k> diverged=<k> reps=<N>
 * x0, y0, theta0: run 0's final pose, to compare with baseline.c's x, y, theta.
 * ns_per_run_step: the median time of the 60 s over runs x steps; every run is stepped every
 * step (a diverged run is stepped and its result dropped), live_steps is the fraction of
 * those steps that count (before a run diverged).
 * max_rel_diff, median_rel_diff: over the runs, of the largest difference of a final pose
 * component from the exact path's; runs_over_1e_9: how many runs differ by more than 1e-9.
 * The paper's law is chaotic from some starts (it never settles, or latches its hold radius
 * at another instant): there a last-bit difference of a transcendental grows to any size.
 * BATCH_RUNS=1 in the environment: one line per run on stderr (start, steps, final poses).
 */
#ifndef BATCH_KERNEL
#define _POSIX_C_SOURCE 199309L
#define PI_F64 3.14159265358979323846264338327950288
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#ifdef WMR_SIMD
/* glibc declares these simd only under -ffast-math; declared here without it. */
#pragma omp declare simd notinbranch
extern double sin(double) __attribute__((const));
#pragma omp declare simd notinbranch
extern double cos(double) __attribute__((const));
#pragma omp declare simd notinbranch
extern double atan2(double, double) __attribute__((const));
#pragma omp declare simd notinbranch
extern double hypot(double, double) __attribute__((const));
#define BUILD "avx2"
#else
#define BUILD "scalar"
#endif

/* The paper's robot, drive, law, servo and step: baseline.c's constants (docs/model.md). */
static const double M = 5.0, RW = 0.1, RH = 0.2, D = 0.25, I_M = 0.002, I_P = 0.005;
static const double K_T = 0.1, B_V = 0.0, TAU_C = 0.0, OMEGA_EPS = 1e-3;
static const double TAU_MOTOR_MAX = 0.2;
static const double KP_TH = 2.0, KI_TH = 0.1, KP_S = 1.0, KI_S = 0.25;
static const double SERVO_KP = 14.0, SERVO_KD = 1.4;
static const double GOAL_RADIUS = 1e-3, HOLD_RADIUS = 5e-3, CONTROL_DT = 1e-3;
static const double DT = 1e-3;
static const long N_STEPS = 60000;
/* The goal of every run; its heading as f64::to_radians computes it. */
static const double GOAL_X = 1.0, GOAL_Y = 1.0, GOAL_TH_DEG = 120.0;

typedef struct {
    double x, y, th, v, om, pr, pl;
} state_t;

/* has_alpha is 0.0 or 1.0: every field a double, so a run's state is one vector lane. */
typedef struct {
    double xd, yd, thd, int_e_th, int_e_s, last_alpha, has_alpha;
} ctrl_t;

static double INV_M11, INV_M22, MD;

static void model_init(void) {
    double m11 = M + 2.0 * I_M / (RW * RW);
    double m22 = (I_P + M * D * D) + 2.0 * RH * RH * I_M / (RW * RW);
    INV_M11 = 1.0 / m11;
    INV_M22 = 1.0 / m22;
    MD = M * D;
}

/* The runs, structure of arrays. */
#define MAX_RUNS 1024
/* One cache line of padding: arrays a multiple of 4 KiB apart would put element i of every
 * array in the same L1 set (conflict misses, 4K aliasing) and cost several times the work. */
#define LANES(f) static double f[MAX_RUNS + 8] __attribute__((aligned(64)))
LANES(X); LANES(Y); LANES(TH); LANES(V); LANES(OM); LANES(PR); LANES(PL);
LANES(XD); LANES(YD); LANES(THD); LANES(IETH); LANES(IES); LANES(LA); LANES(HAS);
LANES(TR); LANES(TL); LANES(ALIVE); LANES(STEPS);
/* The starts. */
LANES(X0); LANES(Y0); LANES(TH0);

/* The kernel twice: for the batch (this file's options), then for the exact path. */
#define BATCH_KERNEL 1
#define SFX(name) name##_batch
#include "batch.c"
#undef SFX
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off", "no-tree-vectorize", "no-tree-slp-vectorize")
#define SFX(name) name##_exact
#include "batch.c"
#undef SFX
#pragma GCC pop_options

/* Scratch of one step, per run: the RK4 stage's th, v, omega, their sine and cosine, k1,
 * k2 + k3, and the control tick's distance, bearing, angle and its cosine. */
LANES(ST); LANES(SV); LANES(SOM); LANES(SN); LANES(CS);
LANES(K1X); LANES(K1Y); LANES(K1TH); LANES(K1V); LANES(K1OM); LANES(K1PR); LANES(K1PL);
LANES(KSX); LANES(KSY); LANES(KSTH); LANES(KSV); LANES(KSOM); LANES(KSPR); LANES(KSPL);
LANES(DL); LANES(TOW); LANES(DIFF); LANES(CD);

/* The transcendental calls sit in loops of their own, without branches: gcc 12 vectorizes a
 * loop only when it can if-convert it, and it does not if-convert a block holding a call. */
static void sincos_runs(int n) {
#pragma omp simd
    for (int i = 0; i < n; i++) {
        SN[i] = sin(ST[i]);
        CS[i] = cos(ST[i]);
    }
}

/* RK4 stage `stage` (1 to 4) of every run: its derivative from (ST, SV, SOM, SN, CS), kept
 * as baseline.c's COMB needs it, and the next stage's th, v, omega (y + hh k). */
__attribute__((always_inline)) static inline void stage_runs(int n, int stage, double hh) {
#pragma omp simd
    for (int i = 0; i < n; i++) {
        double v = SV[i], om = SOM[i], tr = TR[i], tl = TL[i];
        /* deriv() of baseline.c */
        double wr = (v + RH * om) / RW;
        double wl = (v - RH * om) / RW;
        double nr = tr - friction_batch(wr);
        double nl = tl - friction_batch(wl);
        double kx = v * CS[i], ky = v * SN[i], kth = om;
        double kv = ((nr + nl) / RW + MD * om * om) * INV_M11;
        double kom = (RH / RW * (nr - nl) - MD * v * om) * INV_M22;
        double kpr = wr, kpl = wl;
        if (stage == 1) {
            K1X[i] = kx; K1Y[i] = ky; K1TH[i] = kth; K1V[i] = kv; K1OM[i] = kom; K1PR[i] = kpr; K1PL[i] = kpl;
        } else if (stage == 2) {
            KSX[i] = kx; KSY[i] = ky; KSTH[i] = kth; KSV[i] = kv; KSOM[i] = kom; KSPR[i] = kpr; KSPL[i] = kpl;
        } else {
            /* (k2 + k3) */
            KSX[i] = KSX[i] + kx; KSY[i] = KSY[i] + ky; KSTH[i] = KSTH[i] + kth; KSV[i] = KSV[i] + kv;
            KSOM[i] = KSOM[i] + kom; KSPR[i] = KSPR[i] + kpr; KSPL[i] = KSPL[i] + kpl;
        }
        ST[i] = TH[i] + hh * kth;
        SV[i] = V[i] + hh * kv;
        SOM[i] = OM[i] + hh * kom;
    }
}

/* The last stage: y + h/6 (k1 + 2 (k2 + k3) + k4), the divergence check (a diverged run
 * keeps its state), and the control tick's distance to the goal. */
static void finish_runs(int n) {
    const double sixth_h = DT / 6.0;
#pragma omp simd
    for (int i = 0; i < n; i++) {
        double v = SV[i], om = SOM[i], tr = TR[i], tl = TL[i];
        double wr = (v + RH * om) / RW;
        double wl = (v - RH * om) / RW;
        double nr = tr - friction_batch(wr);
        double nl = tl - friction_batch(wl);
        double kx = v * CS[i], ky = v * SN[i], kth = om;
        double kv = ((nr + nl) / RW + MD * om * om) * INV_M11;
        double kom = (RH / RW * (nr - nl) - MD * v * om) * INV_M22;
        double kpr = wr, kpl = wl;
        state_t nx;
        nx.x = X[i] + sixth_h * (K1X[i] + 2.0 * KSX[i] + kx);
        nx.y = Y[i] + sixth_h * (K1Y[i] + 2.0 * KSY[i] + ky);
        nx.th = TH[i] + sixth_h * (K1TH[i] + 2.0 * KSTH[i] + kth);
        nx.v = V[i] + sixth_h * (K1V[i] + 2.0 * KSV[i] + kv);
        nx.om = OM[i] + sixth_h * (K1OM[i] + 2.0 * KSOM[i] + kom);
        nx.pr = PR[i] + sixth_h * (K1PR[i] + 2.0 * KSPR[i] + kpr);
        nx.pl = PL[i] + sixth_h * (K1PL[i] + 2.0 * KSPL[i] + kpl);
        int ok = isfinite(nx.x) & isfinite(nx.y) & isfinite(nx.th) & isfinite(nx.v) & isfinite(nx.om) &
                 isfinite(nx.pr) & isfinite(nx.pl) & !((fabs(nx.x) > 1000.0) | (fabs(nx.y) > 1000.0));
        double go = ok & (ALIVE[i] != 0.0) ? 1.0 : 0.0;
        X[i] = go != 0.0 ? nx.x : X[i];
        Y[i] = go != 0.0 ? nx.y : Y[i];
        TH[i] = go != 0.0 ? nx.th : TH[i];
        V[i] = go != 0.0 ? nx.v : V[i];
        OM[i] = go != 0.0 ? nx.om : OM[i];
        PR[i] = go != 0.0 ? nx.pr : PR[i];
        PL[i] = go != 0.0 ? nx.pl : PL[i];
        ALIVE[i] = go;
        STEPS[i] += go;
    }
}

/* The control tick of every run (control_every = 1): baseline.c's control() in phases. */
static void control_runs(int n) {
#pragma omp simd
    for (int i = 0; i < n; i++) {
        double dx = XD[i] - X[i], dy = YD[i] - Y[i];
        DL[i] = hypot(dx, dy);
        TOW[i] = atan2(dy, dx);
    }
#pragma omp simd
    for (int i = 0; i < n; i++) {
        int far = DL[i] > GOAL_RADIUS;
        double kept = HAS[i] != 0.0 ? LA[i] : THD[i];
        double alpha = far ? TOW[i] : kept;
        LA[i] = far ? TOW[i] : LA[i];
        HAS[i] = far ? 1.0 : HAS[i];
        double th_ref = alpha + alpha - THD[i];
        DIFF[i] = th_ref - TH[i];
    }
#pragma omp simd
    for (int i = 0; i < n; i++) CD[i] = cos(DIFF[i]);
#pragma omp simd
    for (int i = 0; i < n; i++) {
        double dl = DL[i], diff = DIFF[i];
        int hold = (HOLD_RADIUS > 0.0) & (dl < HOLD_RADIUS);
        double e_s = hold ? 0.0 : dl * CD[i];
        double e_th = hold ? 0.0 : wrap_batch(diff);
        double ies = hold ? IES[i] : IES[i] + e_s * CONTROL_DT;
        double ieth = hold ? IETH[i] : IETH[i] + e_th * CONTROL_DT;
        IES[i] = ies;
        IETH[i] = ieth;
        double u_s = KP_S * e_s + KI_S * ies;
        double u_th = KP_TH * e_th + KI_TH * ieth;
        double turn = RH * u_th;
        double ref_r = (u_s + turn) / RW, ref_l = (u_s - turn) / RW;
        double wr = (V[i] + RH * OM[i]) / RW, wl = (V[i] - RH * OM[i]) / RW;
        TR[i] = drive_batch(SERVO_KP * (ref_r - PR[i]) + 0.0 - SERVO_KD * wr);
        TL[i] = drive_batch(SERVO_KP * (ref_l - PL[i]) + 0.0 - SERVO_KD * wl);
    }
}

/* Advances runs [0, n) by one step each: RK4 (4 stages), then the control tick. */
static void step_runs(int n) {
    const double h = DT, half_h = h / 2.0;
    for (int i = 0; i < n; i++) {
        ST[i] = TH[i];
        SV[i] = V[i];
        SOM[i] = OM[i];
    }
    sincos_runs(n);
    stage_runs(n, 1, half_h);
    sincos_runs(n);
    stage_runs(n, 2, half_h);
    sincos_runs(n);
    stage_runs(n, 3, h);
    sincos_runs(n);
    finish_runs(n);
    control_runs(n);
}

static void start_runs(int n) {
    const double thd = GOAL_TH_DEG * (PI_F64 / 180.0);
    for (int i = 0; i < n; i++) {
        state_t y = {X0[i], Y0[i], TH0[i], 0.0, 0.0, 0.0, 0.0};
        ctrl_t c = {GOAL_X, GOAL_Y, thd, 0.0, 0.0, 0.0, 0.0};
        double tr, tl;
        control_batch(&c, &y, &tr, &tl);
        X[i] = y.x; Y[i] = y.y; TH[i] = y.th; V[i] = y.v; OM[i] = y.om; PR[i] = y.pr; PL[i] = y.pl;
        XD[i] = c.xd; YD[i] = c.yd; THD[i] = c.thd;
        IETH[i] = c.int_e_th; IES[i] = c.int_e_s; LA[i] = c.last_alpha; HAS[i] = c.has_alpha;
        TR[i] = tr; TL[i] = tl;
        ALIVE[i] = 1.0;
        STEPS[i] = 0.0;
    }
}

/* Run i alone through the exact path, as baseline.c's run(); returns the steps taken. */
__attribute__((noinline, optimize("fp-contract=off", "no-tree-vectorize", "no-tree-slp-vectorize")))
static long run_exact(int i, state_t *out) {
    state_t y = {X0[i], Y0[i], TH0[i], 0.0, 0.0, 0.0, 0.0};
    ctrl_t c = {GOAL_X, GOAL_Y, GOAL_TH_DEG * (PI_F64 / 180.0), 0.0, 0.0, 0.0, 0.0};
    double tr, tl;
    control_exact(&c, &y, &tr, &tl);
    long n;
    for (n = 0; n < N_STEPS; n++) {
        state_t nx;
        if (!rk4_exact(&y, tr, tl, &nx)) break;
        y = nx;
        control_exact(&c, &y, &tr, &tl);
    }
    *out = y;
    return n;
}

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* splitmix64: the starts, the same on every machine. */
static unsigned long long rng = 0x15u;
static double uniform(void) {
    unsigned long long z = (rng += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

static double rel_diff(double got, double want) {
    double scale = fabs(want) > 1.0 ? fabs(want) : 1.0;
    return fabs(got - want) / scale;
}

int main(int argc, char **argv) {
    int reps = argc > 1 ? atoi(argv[1]) : 5;
    int n = argc > 2 ? atoi(argv[2]) : 64;
    if (reps < 1) reps = 1;
    if (n < 1 || n > MAX_RUNS) {
        fprintf(stderr, "batch: RUNS must be 1 to %d\n", MAX_RUNS);
        return 2;
    }
    model_init();
    X0[0] = 0.0, Y0[0] = 0.0, TH0[0] = 0.0; /* Fig. 7 */
    for (int i = 1; i < n; i++) {
        double r = 2.0 * sqrt(uniform()), a = 2.0 * PI_F64 * uniform();
        X0[i] = GOAL_X + r * cos(a);
        Y0[i] = GOAL_Y + r * sin(a);
        TH0[i] = PI_F64 * (2.0 * uniform() - 1.0);
    }
    double *t = malloc(sizeof(double) * (size_t)reps);
    if (!t) return 1;
    start_runs(n); /* warm-up */
    for (long k = 0; k < N_STEPS; k++) step_runs(n);
    for (int r = 0; r < reps; r++) {
        double t0 = now_s();
        start_runs(n);
        for (long k = 0; k < N_STEPS; k++) step_runs(n);
        t[r] = now_s() - t0;
        __asm__ volatile("" : : "g"(X) : "memory");
    }
    qsort(t, (size_t)reps, sizeof(double), cmp_double);
    double med = reps % 2 ? t[reps / 2] : 0.5 * (t[reps / 2 - 1] + t[reps / 2]);

    double worst = 0.0, live = 0.0;
    double *diffs = malloc(sizeof(double) * (size_t)n);
    if (!diffs) return 1;
    int diverged = 0, over = 0;
    for (int i = 0; i < n; i++) {
        state_t e;
        long steps = run_exact(i, &e);
        if (steps != (long)STEPS[i]) {
            fprintf(stderr, "batch: run %d: %ld steps exact, %.0f in the batch\n", i, steps, STEPS[i]);
            worst = INFINITY;
        }
        diverged += steps < N_STEPS;
        double d[3] = {rel_diff(X[i], e.x), rel_diff(Y[i], e.y), rel_diff(TH[i], e.th)};
        diffs[i] = fmax(d[0], fmax(d[1], d[2]));
        worst = diffs[i] > worst ? diffs[i] : worst;
        over += diffs[i] > 1e-9;
        live += STEPS[i];
        if (getenv("BATCH_RUNS"))
            fprintf(stderr, "run=%d start=(%.4f,%.4f,%.4f) steps=%ld exact=(%.17g,%.17g,%.17g) batch=(%.17g,%.17g,%.17g) "
                    "exact_dl=%.3e rel_diff=%.2e\n", i, X0[i], Y0[i], TH0[i], steps, e.x, e.y, e.th, X[i], Y[i],
                    TH[i], hypot(e.x - GOAL_X, e.y - GOAL_Y), diffs[i]);
    }
    qsort(diffs, (size_t)n, sizeof(double), cmp_double);
    double med_diff = n % 2 ? diffs[n / 2] : 0.5 * (diffs[n / 2 - 1] + diffs[n / 2]);
    printf("impl=c_batch build=%s runs=%d steps=%ld x0=%.17g y0=%.17g theta0=%.17g median_s=%.6e "
           "ns_per_run_step=%.3f live_steps=%.4f max_rel_diff=%.3e median_rel_diff=%.3e runs_over_1e_9=%d "
           "diverged=%d reps=%d\n",
           BUILD, n, N_STEPS, X[0], Y[0], TH[0], med, med / ((double)N_STEPS * n) * 1e9, live / ((double)N_STEPS * n),
           worst, med_diff, over, diverged, reps);
    free(diffs);
    free(t);
    return 0;
}

#else /* BATCH_KERNEL: the loop's functions, named by SFX */

static inline double SFX(friction)(double w) {
    double f = B_V * w;
    if (TAU_C != 0.0) f = f + TAU_C * tanh(w / OMEGA_EPS);
    return f;
}

static inline void SFX(deriv)(const state_t *s, double tr, double tl, state_t *o) {
    double wr = (s->v + RH * s->om) / RW;
    double wl = (s->v - RH * s->om) / RW;
    double nr = tr - SFX(friction)(wr);
    double nl = tl - SFX(friction)(wl);
    double sn = sin(s->th), cs = cos(s->th);
    o->x = s->v * cs;
    o->y = s->v * sn;
    o->th = s->om;
    o->v = ((nr + nl) / RW + MD * s->om * s->om) * INV_M11;
    o->om = (RH / RW * (nr - nl) - MD * s->v * s->om) * INV_M22;
    o->pr = wr;
    o->pl = wl;
}

static inline double SFX(wrap)(double a) {
    const double pi = PI_F64, two_pi = pi + pi;
    double w = a - two_pi * floor((a + pi) / two_pi);
    w = w <= -pi ? w + two_pi : w;
    return w;
}

static inline double SFX(drive)(double demand) {
    double motor = demand * K_T;
    motor = motor < -TAU_MOTOR_MAX ? -TAU_MOTOR_MAX : motor;
    motor = motor > TAU_MOTOR_MAX ? TAU_MOTOR_MAX : motor;
    return motor / K_T;
}

/* baseline.c's control() with selects for its branches: the same values. */
static inline void SFX(control)(ctrl_t *c, const state_t *s, double *tr, double *tl) {
    double dx = c->xd - s->x, dy = c->yd - s->y;
    double dl = hypot(dx, dy);
    double toward = atan2(dy, dx);
    int far = dl > GOAL_RADIUS;
    double kept = c->has_alpha != 0.0 ? c->last_alpha : c->thd;
    double alpha = far ? toward : kept;
    c->last_alpha = far ? toward : c->last_alpha;
    c->has_alpha = far ? 1.0 : c->has_alpha;
    double th_ref = alpha + alpha - c->thd;
    int hold = (HOLD_RADIUS > 0.0) & (dl < HOLD_RADIUS);
    double diff = th_ref - s->th;
    double e_s = hold ? 0.0 : dl * cos(diff);
    double e_th = hold ? 0.0 : SFX(wrap)(diff);
    c->int_e_s = hold ? c->int_e_s : c->int_e_s + e_s * CONTROL_DT;
    c->int_e_th = hold ? c->int_e_th : c->int_e_th + e_th * CONTROL_DT;
    double u_s = KP_S * e_s + KI_S * c->int_e_s;
    double u_th = KP_TH * e_th + KI_TH * c->int_e_th;
    double turn = RH * u_th;
    double ref_r = (u_s + turn) / RW, ref_l = (u_s - turn) / RW;
    double wr = (s->v + RH * s->om) / RW, wl = (s->v - RH * s->om) / RW;
    double cmd_r = SFX(drive)(SERVO_KP * (ref_r - s->pr) + 0.0 - SERVO_KD * wr);
    double cmd_l = SFX(drive)(SERVO_KP * (ref_l - s->pl) + 0.0 - SERVO_KD * wl);
    *tr = cmd_r;
    *tl = cmd_l;
}

/* One RK4 step from y into nx; 0 when nx left the finite 1 km box (baseline.c's break). */
static inline int SFX(rk4)(const state_t *y, double tr, double tl, state_t *nx) {
    const double h = DT, half_h = h / 2.0, sixth_h = h / 6.0;
    state_t k1, k2, k3, k4, y2, y3, y4;
    SFX(deriv)(y, tr, tl, &k1);
#define AXPY(dst, a, hh, k)                   \
    do {                                      \
        (dst).x = (a)->x + (hh) * (k).x;      \
        (dst).y = (a)->y + (hh) * (k).y;      \
        (dst).th = (a)->th + (hh) * (k).th;   \
        (dst).v = (a)->v + (hh) * (k).v;      \
        (dst).om = (a)->om + (hh) * (k).om;   \
        (dst).pr = (a)->pr + (hh) * (k).pr;   \
        (dst).pl = (a)->pl + (hh) * (k).pl;   \
    } while (0)
#define COMB(f) (y->f + sixth_h * (k1.f + 2.0 * (k2.f + k3.f) + k4.f))
    AXPY(y2, y, half_h, k1);
    SFX(deriv)(&y2, tr, tl, &k2);
    AXPY(y3, y, half_h, k2);
    SFX(deriv)(&y3, tr, tl, &k3);
    AXPY(y4, y, h, k3);
    SFX(deriv)(&y4, tr, tl, &k4);
    nx->x = COMB(x);
    nx->y = COMB(y);
    nx->th = COMB(th);
    nx->v = COMB(v);
    nx->om = COMB(om);
    nx->pr = COMB(pr);
    nx->pl = COMB(pl);
#undef AXPY
#undef COMB
    /* & rather than &&: no branches, so the loop over runs can be vectorized. */
    return isfinite(nx->x) & isfinite(nx->y) & isfinite(nx->th) & isfinite(nx->v) & isfinite(nx->om) &
           isfinite(nx->pr) & isfinite(nx->pl) & !((fabs(nx->x) > 1000.0) | (fabs(nx->y) > 1000.0));
}

#endif /* BATCH_KERNEL */
