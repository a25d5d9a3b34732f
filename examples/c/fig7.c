/* Fig. 7 of the paper through the C API: start (0, 0, 0), goal (1, 1, 120 deg), the
 * paper's law with its wheel servos, the torque drive and the dynamic model, 60 s at
 * dt = control_dt = 1 ms, every default. Runs the loop in double and in float and prints
 * each final pose as IEEE bit patterns (hex), so runs on different machines compare exactly,
 * and in decimal beside them (m, m, rad), for a reader.
 *
 * Host:        cc -O2 -I crates/wmr-ffi/include examples/c/fig7.c target/release/libwmr_ffi.a -lm -lpthread -ldl
 * Cortex-M4F:  examples/c/mps2/build (arm-none-eabi-gcc), run with qemu-system-arm -M mps2-an386
 *
 * The double line equals the last row of `wmr-cli run examples/paper/fig7.toml`, bit for
 * bit; the float line equals the Rust firmware's f32 run (firmware/), on either machine. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "wmr.h"

#define STEPS 60000L

static int failed(const char *call, wmr_status status, const wmr_error *err) {
    printf("fig7: %s: %s", call, wmr_status_name(status));
    if (err != NULL && err->field[0] != '\0') printf(": %s %s", err->field, err->reason);
    printf("\n");
    return 1;
}

#define CHECK(call, err)                                             \
    do {                                                             \
        wmr_status s_ = (call);                                      \
        if (s_ != WMR_OK) return failed(#call, s_, (err));            \
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

/* The pose in decimal beside the bits, for a reader: x and y in m, theta in rad, 6
 * decimals. Integer arithmetic, so newlib-nano's printf (no %f without _printf_float)
 * prints it on the Cortex-M4F too; |v| < 2000 holds for any pose in wmr's 1 km box. */
static void print_decimal(const char *name, double v, const char *unit) {
    long micro = (long)(v * 1e6 + (v < 0 ? -0.5 : 0.5));
    long whole = micro / 1000000L, frac = micro % 1000000L;
    printf(" %s=%s%ld.%06ld%s", name, micro < 0 ? "-" : "", whole < 0 ? -whole : whole, frac < 0 ? -frac : frac, unit);
}

/* One function per precision, written once: S is the scalar type, P the name suffix. */
#define DEFINE_FIG7(S, P)                                                                        \
    static int fig7_##P(wmr_state_##P *final_state, long *steps) {                              \
        wmr_error err;                                                                           \
        wmr_robot_params_##P robot_params;                                                       \
        wmr_drive_params_##P drive_params;                                                       \
        wmr_wheel_stage_params_##P wheel_params;                                                 \
        wmr_paper_params_##P law_params;                                                         \
        wmr_robot_##P robot;                                                                     \
        wmr_drive_##P drive;                                                                     \
        wmr_plant_##P plant;                                                                     \
        wmr_sensor_##P sensor;                                                                   \
        wmr_paper_controller_##P ctrl;                                                           \
        wmr_measurement_##P m;                                                                   \
        wmr_control_output_##P out;                                                              \
        const S dt = (S)1e-3; /* plant step = control period, s */                              \
        const wmr_pose_##P start = {0, 0, 0};                                                    \
        const wmr_pose_##P goal = {1, 1, (S)(120.0 * (3.14159265358979323846 / 180.0))};        \
        long k;                                                                                  \
        CHECK(wmr_robot_params_##P##_paper(&robot_params), NULL);                                \
        CHECK(wmr_robot_##P##_init(&robot, &robot_params, &err), &err);                          \
        CHECK(wmr_drive_params_##P##_default(WMR_DRIVE_TORQUE, &drive_params), NULL);            \
        CHECK(wmr_drive_##P##_init(&drive, &drive_params, &robot, &err), &err);                  \
        CHECK(wmr_wheel_stage_params_##P##_default(&drive_params, &robot, &wheel_params), NULL); \
        CHECK(wmr_paper_params_##P##_default(&law_params), NULL);                                \
        CHECK(wmr_paper_controller_##P##_init(&ctrl, &law_params, &wheel_params, &robot, &drive, \
                                              dt, &err),                                         \
              &err);                                                                             \
        CHECK(wmr_plant_##P##_init(&plant, &robot, &drive, NULL, start, &err), &err);                  \
        CHECK(wmr_sensor_##P##_init_perfect(&sensor), NULL);                                     \
        for (k = 0;; k++) {                                                                      \
            const S t = (S)k * dt; /* s, from the step count: no drift */                       \
            /* Control tick: measure, update, hold the command for the next step. */            \
            CHECK(wmr_sensor_##P##_measure(&sensor, t, &plant, &m), NULL);                       \
            CHECK(wmr_paper_controller_##P##_update(&ctrl, t, &m, goal, &out), NULL);            \
            CHECK(wmr_plant_##P##_apply(&plant, out.command), NULL);                             \
            if (k == STEPS) break;                                                               \
            CHECK(wmr_plant_##P##_step(&plant, t, dt), NULL);                                    \
        }                                                                                        \
        *steps = k;                                                                              \
        CHECK(wmr_plant_##P##_state(&plant, final_state), NULL);                                 \
        return 0;                                                                                \
    }

DEFINE_FIG7(double, f64)
DEFINE_FIG7(float, f32)

int main(void) {
    wmr_state_f64 s64;
    wmr_state_f32 s32;
    long steps;
    if (wmr_abi_version() != WMR_ABI_VERSION) {
        printf("fig7: library ABI %lu, header ABI %d\n", (unsigned long)wmr_abi_version(), WMR_ABI_VERSION);
        return 1;
    }
    if (fig7_f64(&s64, &steps) != 0) return 1;
    printf("impl=c-f64");
    print_bits64("x", s64.x);
    print_bits64("y", s64.y);
    print_bits64("theta", s64.theta);
    printf(" steps=%ld", steps);
    print_decimal("x", s64.x, "m");
    print_decimal("y", s64.y, "m");
    print_decimal("theta", s64.theta, "rad");
    printf("\n");
    if (fig7_f32(&s32, &steps) != 0) return 1;
    printf("impl=c-f32");
    print_bits32("x", s32.x);
    print_bits32("y", s32.y);
    print_bits32("theta", s32.theta);
    printf(" steps=%ld", steps);
    print_decimal("x", (double)s32.x, "m");
    print_decimal("y", (double)s32.y, "m");
    print_decimal("theta", (double)s32.theta, "rad");
    printf("\n");
    return 0;
}
