/* A firmware engineer's first loop: the plant with wheels that slip, the odometry sensor
 * with its EKF, and a law, through the C API. The run of examples/c/odometry_slip.toml:
 * the paper's robot with 12 V DC motors on wet tiles (mu = 0.3) tilted 2 deg towards
 * 30 deg, the repaired paper law (`paper_bidirectional`) steering on the pose dead-reckoned from 1024-count
 * encoders and fused with absolute fixes at 1 Hz (1 cm, 0.5 deg, 100 ms late, seed 24),
 * 45 s at dt = control_dt = 1 ms. Runs the loop in double and in float and prints the
 * final true pose, the odometry pose and the EKF's position variance as IEEE bit
 * patterns (hex).
 *
 * Host:        cc -O2 -I crates/wmr-ffi/include examples/c/odometry_slip.c target/release/libwmr_ffi.a -lm -lpthread -ldl
 * Cortex-M4F:  as examples/c/fig7.c (firmware/check builds and runs both under QEMU)
 *
 * The double line's pose equals the last row of
 * `wmr-cli run examples/c/odometry_slip.toml`, bit for bit (crates/wmr-ffi/tests/c_programs.rs);
 * host and QEMU print the same lines (firmware/check). */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "wmr.h"

#define STEPS 45000L
#define PI 3.14159265358979323846

static int failed(const char *call, wmr_status status, const wmr_error *err) {
    printf("odometry_slip: %s: %s", call, wmr_status_name(status));
    if (err != NULL && err->field[0] != '\0') printf(": %s %s", err->field, err->reason);
    printf("\n");
    return 1;
}

#define CHECK(call, err)                                  \
    do {                                                  \
        wmr_status s_ = (call);                           \
        if (s_ != WMR_OK) return failed(#call, s_, (err)); \
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

/* One function per precision, written once: S is the scalar type, P the name suffix. */
#define DEFINE_RUN(S, P)                                                                               \
    static int run_##P(wmr_state_##P *final_state, wmr_odometry_estimate_##P *estimate) {             \
        wmr_error err;                                                                                 \
        wmr_robot_params_##P robot_params;                                                             \
        wmr_drive_params_##P drive_params;                                                             \
        wmr_world_params_##P world = {0};                                                              \
        wmr_traction_params_##P traction;                                                              \
        wmr_sensor_params_##P sensor_params;                                                           \
        wmr_odometry_params_##P odometry;                                                              \
        wmr_wheel_stage_params_##P wheel_params;                                                       \
        wmr_paper_bidirectional_params_##P law_params;                                                 \
        wmr_robot_##P robot;                                                                           \
        wmr_drive_##P drive;                                                                           \
        wmr_plant_##P plant;                                                                           \
        wmr_sensor_##P sensor;                                                                         \
        wmr_paper_bidirectional_controller_##P ctrl;                                                   \
        wmr_measurement_##P m;                                                                         \
        wmr_control_output_##P out;                                                                    \
        const S dt = (S)1e-3; /* plant step = control period, s */                                    \
        const wmr_pose_##P start = {0, 0, 0};                                                          \
        const wmr_pose_##P goal = {1, 1, (S)(120.0 * (PI / 180.0))};                                   \
        long k;                                                                                        \
        CHECK(wmr_robot_params_##P##_paper(&robot_params), NULL);                                      \
        CHECK(wmr_robot_##P##_init(&robot, &robot_params, &err), &err);                                \
        CHECK(wmr_drive_params_##P##_default(WMR_DRIVE_DC_MOTOR, &drive_params), NULL);                  \
        CHECK(wmr_drive_##P##_init(&drive, &drive_params, &robot, &err), &err);                        \
        world.slope_deg = 2;               /* deg */                                                   \
        world.slope_direction_deg = 30;    /* deg: the direction the ground descends */                \
        CHECK(wmr_traction_params_##P##_default(&traction), NULL);                                     \
        traction.traction = WMR_TRACTION_SLIP;                                                         \
        traction.friction_coefficient = (S)0.3; /* wet tiles */                                        \
        CHECK(wmr_plant_##P##_init_traction(&plant, &robot, &drive, &world, &traction, start, &err),   \
              &err);                                                                                   \
        CHECK(wmr_sensor_params_##P##_default(&sensor_params), NULL);                                  \
        sensor_params.encoder_counts = 1024;                                                           \
        sensor_params.position_noise = (S)0.01;  /* m, of each fix */                                  \
        sensor_params.heading_noise_deg = (S)0.5;                                                      \
        sensor_params.latency = (S)0.1;          /* s, of each fix */                                  \
        sensor_params.seed = 24;                                                                       \
        CHECK(wmr_odometry_params_##P##_default(&odometry), NULL);                                     \
        odometry.fix_rate_hz = 1;                                                                      \
        /* The controller's model is the robot itself; run 0's noise stream. */                       \
        CHECK(wmr_sensor_##P##_init_odometry(&sensor, &sensor_params, &odometry, &robot, dt, 0, &err), \
              &err);                                                                                   \
        CHECK(wmr_wheel_stage_params_##P##_default(&drive_params, &robot, &wheel_params), NULL);       \
        CHECK(wmr_paper_bidirectional_params_##P##_default(&law_params), NULL);                        \
        CHECK(wmr_paper_bidirectional_controller_##P##_init(&ctrl, &law_params, &wheel_params, &robot, \
                                                            &drive, dt, &err),                         \
              &err);                                                                                   \
        /* The speed guard acts on a slipping wheel's own inertia, as a scenario run sets it. */     \
        CHECK(wmr_paper_bidirectional_controller_##P##_for_plant(&ctrl, &plant), NULL);                \
        for (k = 0;; k++) {                                                                            \
            const S t = (S)k * dt; /* s, from the step count: no drift */                             \
            /* Control tick: measure (encoders, odometry, EKF), update, hold the command. */          \
            CHECK(wmr_sensor_##P##_measure(&sensor, t, &plant, &m), NULL);                             \
            CHECK(wmr_paper_bidirectional_controller_##P##_update(&ctrl, t, &m, goal, &out), NULL);    \
            CHECK(wmr_plant_##P##_apply(&plant, out.command), NULL);                                   \
            if (k == STEPS) break;                                                                     \
            CHECK(wmr_plant_##P##_step(&plant, t, dt), NULL);                                          \
        }                                                                                              \
        CHECK(wmr_plant_##P##_state(&plant, final_state), NULL);                                       \
        CHECK(wmr_sensor_##P##_odometry(&sensor, estimate), NULL);                                     \
        return 0;                                                                                      \
    }

DEFINE_RUN(double, f64)
DEFINE_RUN(float, f32)

int main(void) {
    wmr_state_f64 s64;
    wmr_state_f32 s32;
    wmr_odometry_estimate_f64 e64;
    wmr_odometry_estimate_f32 e32;
    if (wmr_abi_version() != WMR_ABI_VERSION) {
        printf("odometry_slip: library ABI %lu, header ABI %d\n", (unsigned long)wmr_abi_version(), WMR_ABI_VERSION);
        return 1;
    }
    if (run_f64(&s64, &e64) != 0) return 1;
    printf("impl=c-f64");
    print_bits64("x", s64.x);
    print_bits64("y", s64.y);
    print_bits64("theta", s64.theta);
    print_bits64("odom_x", e64.dead_reckoning.x);
    print_bits64("odom_y", e64.dead_reckoning.y);
    print_bits64("odom_theta", e64.dead_reckoning.theta);
    print_bits64("var_x", e64.covariance[0]);
    printf("\n");
    if (run_f32(&s32, &e32) != 0) return 1;
    printf("impl=c-f32");
    print_bits32("x", s32.x);
    print_bits32("y", s32.y);
    print_bits32("theta", s32.theta);
    print_bits32("odom_x", e32.dead_reckoning.x);
    print_bits32("odom_y", e32.dead_reckoning.y);
    print_bits32("odom_theta", e32.dead_reckoning.theta);
    print_bits32("var_x", e32.covariance[0]);
    printf("\n");
    return 0;
}
