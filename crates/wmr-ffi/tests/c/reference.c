/* The reference as a C caller passes it: `_update_reference` with the reference at rest
 * at the goal gives the same bits as `_update` with that goal, tick after tick of the
 * Fig. 7 loop (f64 and f32); a NaN in reference.accel.omega is refused with that field
 * name. Built and run by tests/c_programs.rs; prints "ok" at the end. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "wmr.h"

static int bad = 0;

#define CHECK(call)                                                   \
    do {                                                              \
        wmr_status s_ = (call);                                       \
        if (s_ != WMR_OK) {                                           \
            printf("FAIL %s: %s\n", #call, wmr_status_name(s_));      \
            return 1;                                                 \
        }                                                             \
    } while (0)

#define AT_REST(P, T)                                                                          \
    static int at_rest_##P(void) {                                                             \
        wmr_error err;                                                                         \
        wmr_robot_params_##P rp;                                                               \
        wmr_robot_##P robot;                                                                   \
        wmr_drive_params_##P dp;                                                               \
        wmr_drive_##P drive;                                                                   \
        wmr_wheel_stage_params_##P wp;                                                         \
        wmr_paper_params_##P lp;                                                               \
        wmr_paper_controller_##P a, b;                                                         \
        wmr_plant_##P plant;                                                                   \
        wmr_sensor_##P sensor;                                                                 \
        wmr_measurement_##P m;                                                                 \
        wmr_control_output_##P out_a, out_b, kept;                                             \
        const wmr_pose_##P start = {0, 0, 0};                                                  \
        const wmr_pose_##P goal = {1, 1, (T)(120.0 * 3.14159265358979323846 / 180.0)};         \
        wmr_reference_state_##P ref;                                                           \
        const T dt = (T)1e-3;                                                                  \
        long k;                                                                                \
        CHECK(wmr_robot_params_##P##_paper(&rp));                                              \
        CHECK(wmr_robot_##P##_init(&robot, &rp, &err));                                        \
        CHECK(wmr_drive_params_##P##_default(WMR_DRIVE_TORQUE, &dp));                          \
        CHECK(wmr_drive_##P##_init(&drive, &dp, &robot, &err));                                \
        CHECK(wmr_wheel_stage_params_##P##_default(&dp, &robot, &wp));                         \
        CHECK(wmr_paper_params_##P##_default(&lp));                                            \
        CHECK(wmr_paper_controller_##P##_init(&a, &lp, &wp, &robot, &drive, dt, &err));        \
        CHECK(wmr_paper_controller_##P##_init(&b, &lp, &wp, &robot, &drive, dt, &err));        \
        CHECK(wmr_plant_##P##_init(&plant, &robot, &drive, NULL, start, &err));                \
        CHECK(wmr_sensor_##P##_init_perfect(&sensor));                                         \
        memset(&ref, 0, sizeof ref);                                                           \
        ref.pose = goal;                                                                       \
        for (k = 0; k < 20000; ++k) {                                                          \
            const T t = (T)k * dt;                                                             \
            CHECK(wmr_sensor_##P##_measure(&sensor, t, &plant, &m));                           \
            CHECK(wmr_paper_controller_##P##_update(&a, t, &m, goal, &out_a));                 \
            CHECK(wmr_paper_controller_##P##_update_reference(&b, t, &m, &ref, &out_b, &err)); \
            if (memcmp(&out_a, &out_b, sizeof out_a) != 0) {                                   \
                printf("FAIL " #P " tick %ld: update_reference differs from update\n", k);     \
                return 1;                                                                      \
            }                                                                                  \
            CHECK(wmr_plant_##P##_apply(&plant, out_a.command));                               \
            CHECK(wmr_plant_##P##_step(&plant, t, dt));                                        \
        }                                                                                      \
        ref.accel.omega = (T)NAN;                                                              \
        kept = out_b;                                                                          \
        if (wmr_paper_controller_##P##_update_reference(&b, 0, &m, &ref, &kept, &err)          \
                != WMR_NOT_FINITE ||                                                           \
            err.code != WMR_NOT_FINITE || strcmp(err.field, "reference.accel.omega") != 0 ||   \
            memcmp(&kept, &out_b, sizeof kept) != 0) {                                         \
            printf("FAIL " #P " NaN reference.accel.omega: %s field=%s\n",                     \
                   wmr_status_name(err.code), err.field);                                      \
            return 1;                                                                          \
        }                                                                                      \
        printf("pass " #P ": 20000 ticks identical; NaN refused: %s field=%s\n",              \
               wmr_status_name(err.code), err.field);                                          \
        return 0;                                                                              \
    }

AT_REST(f64, double)
AT_REST(f32, float)

int main(void) {
    bad |= at_rest_f64();
    bad |= at_rest_f32();
    printf(bad ? "FAILED\n" : "ok\n");
    return bad;
}
