/* baseline.c: a flat, hand-written C loop of wmr's closed loop, the yardstick for
 * `benches/compare` (issue 6).
 *
 * Same closed loop as wmr-core's `ClosedLoop<f64, PaperController<f64>>` with every
 * default of docs/model.md (robot, drive, the paper's law): the paper's controller (pose mode, hold radius),
 * two wheel PD servos, the torque drive with its motor torque clamp, the dynamic model
 * (15) (docs/model.md) and classic RK4. Fig. 7 scenario: (0, 0, 0) -> (1, 1, 120 deg),
 * 60 s at dt = control_dt = 1 ms.
 *
 * The operation order mirrors crates/wmr-core/src/{controller/paper.rs,
 * controller/servo.rs, drive/torque.rs, dynamics.rs, integrator.rs, sim.rs}, so the final
 * pose agrees with the Rust core to rounding of the math library (the script checks it).
 * Parameters are compile-time constants, as a hand-written loop would have them: the
 * compiler may fold every invariant. Like the core, the Coulomb tanh is skipped when
 * tau_c is zero. The divergence check (finite state, 1 km box) is kept, as the core's
 * `step()` does it.
 *
 * Build: cc -O2 -o baseline benches/baseline.c -lm
 * Run:   ./baseline N        (N timed repetitions of the whole 60 s run, default 5)
 * Output, one line:
 *   impl=c x=<m> y=<m> theta=<rad> steps=<n> median_run_s=<s> median_step_ns=<ns> reps=<N>
 */
#define _POSIX_C_SOURCE 199309L
/* pi as core::f64::consts::PI (PI_F64 is not in strict POSIX). */
#define PI_F64 3.14159265358979323846264338327950288
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

/* The paper's robot (docs/model.md). */
static const double M = 5.0, RW = 0.1, RH = 0.2, D = 0.25, I_M = 0.002, I_P = 0.005;
static const double K_T = 0.1, B_V = 0.0, TAU_C = 0.0, OMEGA_EPS = 1e-3;
/* Torque drive (docs/model.md, Drives). */
static const double TAU_MOTOR_MAX = 0.2;
/* The paper's gains, servo, radii, period (docs/model.md). */
static const double KP_TH = 2.0, KI_TH = 0.1, KP_S = 1.0, KI_S = 0.25;
static const double SERVO_KP = 14.0, SERVO_KD = 1.4;
static const double GOAL_RADIUS = 1e-3, HOLD_RADIUS = 5e-3, CONTROL_DT = 1e-3;
static const double DT = 1e-3;
static const long N_STEPS = 60000;

typedef struct {
    double x, y, th, v, om, pr, pl;
} state_t;

typedef struct {
    double xd, yd, thd;
    double int_e_th, int_e_s;
    double last_alpha;
    int has_alpha;
} ctrl_t;

/* Constants of the model, computed as the core's RobotParams::validate does. */
static double INV_M11, INV_M22, MD;

static void model_init(void) {
    double m11 = M + 2.0 * I_M / (RW * RW);
    double m22 = (I_P + M * D * D) + 2.0 * RH * RH * I_M / (RW * RW);
    INV_M11 = 1.0 / m11;
    INV_M22 = 1.0 / m22;
    MD = M * D;
}

static inline double friction(double w) {
    double f = B_V * w;
    if (TAU_C != 0.0) f = f + TAU_C * tanh(w / OMEGA_EPS);
    return f;
}

static inline void deriv(const state_t *s, double tr, double tl, state_t *o) {
    double wr = (s->v + RH * s->om) / RW;
    double wl = (s->v - RH * s->om) / RW;
    double nr = tr - friction(wr);
    double nl = tl - friction(wl);
    double sn = sin(s->th), cs = cos(s->th);
    o->x = s->v * cs;
    o->y = s->v * sn;
    o->th = s->om;
    o->v = ((nr + nl) / RW + MD * s->om * s->om) * INV_M11;
    o->om = (RH / RW * (nr - nl) - MD * s->v * s->om) * INV_M22;
    o->pr = wr;
    o->pl = wl;
}

static inline double wrap(double a) {
    const double pi = PI_F64, two_pi = pi + pi;
    double w = a - two_pi * floor((a + pi) / two_pi);
    if (w <= -pi) w = w + two_pi;
    return w;
}

static inline double drive(double demand) {
    /* Clamp as max(-lim).min(lim); ternaries, not fmin/fmax, which -O2 leaves as calls. */
    double motor = demand * K_T;
    motor = motor < -TAU_MOTOR_MAX ? -TAU_MOTOR_MAX : motor;
    motor = motor > TAU_MOTOR_MAX ? TAU_MOTOR_MAX : motor;
    return motor / K_T;
}

/* One control tick: outer PI loops, inverse of (20), servos, drive -> wheel torques. */
static inline void control(ctrl_t *c, const state_t *s, double *tr, double *tl) {
    double dx = c->xd - s->x, dy = c->yd - s->y;
    double dl = hypot(dx, dy);
    double alpha;
    if (dl > GOAL_RADIUS) {
        alpha = atan2(dy, dx);
        c->last_alpha = alpha;
        c->has_alpha = 1;
    } else {
        alpha = c->has_alpha ? c->last_alpha : c->thd;
    }
    double th_ref = alpha + alpha - c->thd;
    double e_s, e_th;
    if (HOLD_RADIUS > 0.0 && dl < HOLD_RADIUS) {
        e_s = 0.0;
        e_th = 0.0;
    } else {
        double diff = th_ref - s->th;
        e_s = dl * cos(diff);
        e_th = wrap(diff);
        c->int_e_s = c->int_e_s + e_s * CONTROL_DT;
        c->int_e_th = c->int_e_th + e_th * CONTROL_DT;
    }
    double u_s = KP_S * e_s + KI_S * c->int_e_s;
    double u_th = KP_TH * e_th + KI_TH * c->int_e_th;
    double turn = RH * u_th;
    double ref_r = (u_s + turn) / RW, ref_l = (u_s - turn) / RW;
    double wr = (s->v + RH * s->om) / RW, wl = (s->v - RH * s->om) / RW;
    /* Servo: Kp e + Ki int e - Kd omega, with Ki = 0 (the core adds a zero I term). */
    double cmd_r = SERVO_KP * (ref_r - s->pr) + 0.0 - SERVO_KD * wr;
    double cmd_l = SERVO_KP * (ref_l - s->pl) + 0.0 - SERVO_KD * wl;
    *tr = drive(cmd_r);
    *tl = drive(cmd_l);
}

#define AXPY(dst, a, h, k)          \
    do {                            \
        (dst).x = (a).x + (h) * (k).x;    \
        (dst).y = (a).y + (h) * (k).y;    \
        (dst).th = (a).th + (h) * (k).th; \
        (dst).v = (a).v + (h) * (k).v;    \
        (dst).om = (a).om + (h) * (k).om; \
        (dst).pr = (a).pr + (h) * (k).pr; \
        (dst).pl = (a).pl + (h) * (k).pl; \
    } while (0)

#define COMB(f) (y.f + sixth_h * (k1.f + 2.0 * (k2.f + k3.f) + k4.f))

/* The whole run; returns the number of steps taken (fewer if it diverged). */
static long run(state_t *out) {
    state_t y = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    /* The goal heading as f64::to_radians computes it: 120 * (pi / 180). */
    ctrl_t c = {1.0, 1.0, 120.0 * (PI_F64 / 180.0), 0.0, 0.0, 0.0, 0};
    double tr, tl;
    const double h = DT, half_h = h / 2.0, sixth_h = h / 6.0;
    control(&c, &y, &tr, &tl);
    long n;
    for (n = 0; n < N_STEPS; n++) {
        state_t k1, k2, k3, k4, y2, y3, y4, nx;
        deriv(&y, tr, tl, &k1);
        AXPY(y2, y, half_h, k1);
        deriv(&y2, tr, tl, &k2);
        AXPY(y3, y, half_h, k2);
        deriv(&y3, tr, tl, &k3);
        AXPY(y4, y, h, k3);
        deriv(&y4, tr, tl, &k4);
        nx.x = COMB(x);
        nx.y = COMB(y);
        nx.th = COMB(th);
        nx.v = COMB(v);
        nx.om = COMB(om);
        nx.pr = COMB(pr);
        nx.pl = COMB(pl);
        if (!(isfinite(nx.x) && isfinite(nx.y) && isfinite(nx.th) && isfinite(nx.v) && isfinite(nx.om) &&
              isfinite(nx.pr) && isfinite(nx.pl)) ||
            fabs(nx.x) > 1000.0 || fabs(nx.y) > 1000.0)
            break;
        y = nx;
        control(&c, &y, &tr, &tl); /* control_every = 1 */
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

int main(int argc, char **argv) {
    int reps = argc > 1 ? atoi(argv[1]) : 5;
    if (reps < 1) reps = 1;
    model_init();
    double *t = malloc(sizeof(double) * (size_t)reps);
    if (!t) return 1;
    state_t s;
    long steps = 0;
    run(&s); /* warm-up */
    for (int i = 0; i < reps; i++) {
        double t0 = now_s();
        steps = run(&s);
        t[i] = now_s() - t0;
        /* Keep the result observable so the runs are not merged. */
        __asm__ volatile("" : : "g"(&s) : "memory");
    }
    qsort(t, (size_t)reps, sizeof(double), cmp_double);
    double med = reps % 2 ? t[reps / 2] : 0.5 * (t[reps / 2 - 1] + t[reps / 2]);
    printf("impl=c x=%.17g y=%.17g theta=%.17g steps=%ld median_run_s=%.6e median_step_ns=%.3f reps=%d\n", s.x, s.y,
           s.th, steps, med, med / (double)steps * 1e9, reps);
    free(t);
    return 0;
}
