/* The disturbance observer through the C API (issue 42): tests/c/observer.toml, Fig. 7 on
 * a 3 deg slope with Coulomb friction at the wheels, the paper's law with the observer at
 * its default bandwidth, 20 s at dt = control_dt = 1 ms, in double and in float. Prints
 * the final pose and the observer's last estimate (N m per wheel) as IEEE bit patterns;
 * tests/c_programs.rs compares them with the CLI's scenario runner (double) and the Rust
 * core's closed loop (float). Then the refusals: a bad bandwidth named
 * `observer.bandwidth`, a NULL observer, the estimate of a controller without one.
 * Built and run by tests/c_programs.rs; prints "ok" at the end. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "wmr.h"

#define STEPS 20000L

static int failed(const char *call, wmr_status status, const wmr_error *err) {
    printf("FAIL %s: %s", call, wmr_status_name(status));
    if (err != NULL && err->field[0] != '\0') printf(": %s %s", err->field, err->reason);
    printf("\n");
    return 1;
}

#define CHECK(call, err)                                  \
    do {                                                  \
        wmr_status s_ = (call);                           \
        if (s_ != WMR_OK) return failed(#call, s_, (err)); \
    } while (0)

#define EXPECT(cond)                             \
    do {                                         \
        if (!(cond)) {                           \
            printf("FAIL %s\n", #cond);          \
            return 1;                            \
        }                                        \
    } while (0)

static void print_bits32(const char *name, float v) {
    uint32_t b;
    memcpy(&b, &v, sizeof b);
    printf(" %s_bits=%08lx", name, (unsigned long)b);
}

static void print_bits64(const char *name, double v) {
    uint64_t b;
    memcpy(&b, &v, sizeof b);
    printf(" %s_bits=%08lx%08lx", name, (unsigned long)(b >> 32), (unsigned long)(b & 0xffffffffu));
}

#define DEFINE_RUN(S, P)                                                                                   \
    static int run_##P(void) {                                                                             \
        wmr_error err;                                                                                     \
        wmr_robot_params_##P rp;                                                                           \
        wmr_drive_params_##P dp;                                                                           \
        wmr_wheel_stage_params_##P wp;                                                                     \
        wmr_paper_params_##P lp;                                                                           \
        wmr_disturbance_observer_params_##P op;                                                            \
        wmr_world_params_##P world;                                                                        \
        wmr_robot_##P robot;                                                                               \
        wmr_drive_##P drive;                                                                               \
        wmr_plant_##P plant;                                                                               \
        wmr_sensor_##P sensor;                                                                             \
        wmr_paper_controller_##P ctrl, plain;                                                              \
        wmr_measurement_##P m;                                                                             \
        wmr_control_output_##P out;                                                                        \
        wmr_state_##P s;                                                                                   \
        wmr_wheels_##P d;                                                                                  \
        const S dt = (S)1e-3;                                                                              \
        const wmr_pose_##P start = {0, 0, 0};                                                              \
        const wmr_pose_##P goal = {1, 1, (S)(120.0 * (3.14159265358979323846 / 180.0))};                  \
        long k;                                                                                            \
        CHECK(wmr_robot_params_##P##_paper(&rp), NULL);                                                    \
        rp.coulomb_friction = (S)0.05;                                                                     \
        CHECK(wmr_robot_##P##_init(&robot, &rp, &err), &err);                                              \
        CHECK(wmr_drive_params_##P##_default(WMR_DRIVE_TORQUE, &dp), NULL);                                \
        CHECK(wmr_drive_##P##_init(&drive, &dp, &robot, &err), &err);                                      \
        CHECK(wmr_wheel_stage_params_##P##_default(&dp, &robot, &wp), NULL);                               \
        CHECK(wmr_paper_params_##P##_default(&lp), NULL);                                                  \
        CHECK(wmr_disturbance_observer_params_##P##_default(&op), NULL);                                   \
        EXPECT(op.bandwidth == (S)50);                                                                     \
        EXPECT(op.deadband == 0 && op.static_friction == 0 && op.precompensation_band == (S)0.5);          \
        CHECK(wmr_paper_controller_##P##_init_observer(&ctrl, &lp, &wp, &op, &robot, &drive, dt, &err),    \
              &err);                                                                                       \
        memset(&world, 0, sizeof world);                                                                   \
        world.slope_deg = (S)3;                                                                            \
        world.slope_direction_deg = (S)30;                                                                 \
        CHECK(wmr_plant_##P##_init(&plant, &robot, &drive, &world, start, &err), &err);                    \
        CHECK(wmr_sensor_##P##_init_perfect(&sensor), NULL);                                               \
        /* Before the first tick the estimate is 0. */                                                     \
        CHECK(wmr_paper_controller_##P##_disturbance(&ctrl, &d), NULL);                                    \
        EXPECT(d.right == 0 && d.left == 0);                                                               \
        for (k = 0;; k++) {                                                                                \
            const S t = (S)k * dt;                                                                         \
            CHECK(wmr_sensor_##P##_measure(&sensor, t, &plant, &m), NULL);                                 \
            CHECK(wmr_paper_controller_##P##_update(&ctrl, t, &m, goal, &out), NULL);                      \
            CHECK(wmr_plant_##P##_apply(&plant, out.command), NULL);                                       \
            if (k == STEPS) break;                                                                         \
            CHECK(wmr_plant_##P##_step(&plant, t, dt), NULL);                                              \
        }                                                                                                  \
        CHECK(wmr_plant_##P##_state(&plant, &s), NULL);                                                    \
        CHECK(wmr_paper_controller_##P##_disturbance(&ctrl, &d), NULL);                                    \
        printf("impl=c-" #P);                                                                              \
        print_bits_##P("x", s.x);                                                                          \
        print_bits_##P("y", s.y);                                                                          \
        print_bits_##P("theta", s.theta);                                                                  \
        print_bits_##P("tau_dist_r", d.right);                                                             \
        print_bits_##P("tau_dist_l", d.left);                                                              \
        printf(" steps=%ld\n", k);                                                                         \
        /* A bad bandwidth is refused by its name; so is a NULL observer. */                               \
        op.bandwidth = 0;                                                                                  \
        EXPECT(wmr_paper_controller_##P##_init_observer(&plain, &lp, &wp, &op, &robot, &drive, dt, &err)   \
               == WMR_NOT_POSITIVE);                                                                       \
        EXPECT(strcmp(err.field, "observer.bandwidth") == 0);                                              \
        op.bandwidth = (S)50;                                                                              \
        op.deadband = (S)1;                                                                                \
        EXPECT(wmr_paper_controller_##P##_init_observer(&plain, &lp, &wp, &op, &robot, &drive, dt, &err)   \
               == WMR_OUT_OF_RANGE);                                                                       \
        EXPECT(strcmp(err.field, "observer.deadband") == 0);                                               \
        EXPECT(wmr_paper_controller_##P##_init_observer(&plain, &lp, &wp, NULL, &robot, &drive, dt, &err)  \
               == WMR_NULL_POINTER);                                                                       \
        EXPECT(strcmp(err.field, "observer") == 0);                                                        \
        /* A controller without an observer has no estimate to give. */                                    \
        CHECK(wmr_paper_controller_##P##_init(&plain, &lp, &wp, &robot, &drive, dt, &err), &err);          \
        d.right = d.left = (S)7;                                                                           \
        EXPECT(wmr_paper_controller_##P##_disturbance(&plain, &d) == WMR_OUT_OF_RANGE);                    \
        EXPECT(d.right == (S)7 && d.left == (S)7);                                                         \
        EXPECT(wmr_paper_controller_##P##_disturbance(NULL, &d) == WMR_NULL_POINTER);                      \
        printf("pass " #P ": refusals\n");                                                                 \
        return 0;                                                                                          \
    }

#define print_bits_f64 print_bits64
#define print_bits_f32 print_bits32

DEFINE_RUN(double, f64)
DEFINE_RUN(float, f32)

int main(void) {
    if (run_f64() != 0 || run_f32() != 0) return 1;
    printf("ok\n");
    return 0;
}
