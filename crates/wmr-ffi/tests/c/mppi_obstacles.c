/* MPPI with obstacles and a run's own noise through the C API (issue 41):
 * tests/c/mppi_obstacles.toml, a post and a box beside the way to the goal, run 1 (its
 * own noise stream), 3 s at dt = control_dt = 1 ms. Prints the final pose of run 1 with
 * the obstacles, of run 0 with them and of run 1 without them, as IEEE bit patterns
 * (double; float runs too); tests/c_programs.rs compares them with the CLI's scenario
 * runner. Then the refusals: a bad radius named `obstacle.radius`, a 17th obstacle named
 * `obstacle`, a polygon of 2 vertices named `obstacle.points`, a negative footprint.
 * Built and run by tests/c_programs.rs; prints "ok" at the end. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "wmr.h"

#define STEPS 3000L

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

#define print_bits_f64 print_bits64
#define print_bits_f32 print_bits32

/* One run of the scenario's loop: measure, update, apply, step; prints the final pose
 * with `tag`. `obstacles` may be NULL. */
#define DEFINE_RUN(S, P)                                                                                   \
    static int run_##P(const char *tag, const wmr_obstacles_##P *obstacles, uint64_t run) {                \
        wmr_error err;                                                                                     \
        wmr_robot_params_##P rp;                                                                           \
        wmr_drive_params_##P dp;                                                                           \
        wmr_wheel_stage_params_##P wp;                                                                     \
        wmr_mppi_params_##P lp;                                                                            \
        wmr_world_params_##P world;                                                                        \
        wmr_robot_##P robot;                                                                               \
        wmr_drive_##P drive;                                                                               \
        wmr_plant_##P plant;                                                                               \
        wmr_sensor_##P sensor;                                                                             \
        wmr_mppi_controller_##P ctrl;                                                                      \
        wmr_measurement_##P m;                                                                             \
        wmr_control_output_##P out;                                                                        \
        wmr_state_##P s;                                                                                   \
        const S dt = (S)1e-3;                                                                              \
        const wmr_pose_##P start = {0, 0, 0};                                                              \
        const wmr_pose_##P goal = {1, 0, 0};                                                               \
        long k;                                                                                            \
        CHECK(wmr_robot_params_##P##_paper(&rp), NULL);                                                    \
        CHECK(wmr_robot_##P##_init(&robot, &rp, &err), &err);                                              \
        CHECK(wmr_drive_params_##P##_default(WMR_DRIVE_TORQUE, &dp), NULL);                                \
        CHECK(wmr_drive_##P##_init(&drive, &dp, &robot, &err), &err);                                      \
        CHECK(wmr_wheel_stage_params_##P##_default(&dp, &robot, &wp), NULL);                               \
        CHECK(wmr_mppi_params_##P##_default(&lp), NULL);                                                   \
        lp.batch_size = 32;                                                                                \
        lp.time_steps = 16;                                                                                \
        lp.seed = 11;                                                                                      \
        CHECK(wmr_mppi_controller_##P##_init_in(&ctrl, &lp, &wp, &robot, &drive, dt, obstacles, run, &err), \
              &err);                                                                                       \
        memset(&world, 0, sizeof world);                                                                   \
        CHECK(wmr_plant_##P##_init(&plant, &robot, &drive, &world, start, &err), &err);                    \
        CHECK(wmr_sensor_##P##_init_perfect(&sensor), NULL);                                               \
        for (k = 0;; k++) {                                                                                \
            const S t = (S)k * dt;                                                                         \
            CHECK(wmr_sensor_##P##_measure(&sensor, t, &plant, &m), NULL);                                 \
            CHECK(wmr_mppi_controller_##P##_update(&ctrl, t, &m, goal, &out), NULL);                       \
            CHECK(wmr_plant_##P##_apply(&plant, out.command), NULL);                                       \
            if (k == STEPS) break;                                                                         \
            CHECK(wmr_plant_##P##_step(&plant, t, dt), NULL);                                              \
        }                                                                                                  \
        CHECK(wmr_plant_##P##_state(&plant, &s), NULL);                                                    \
        printf("impl=%s-" #P, tag);                                                                        \
        print_bits_##P("x", s.x);                                                                          \
        print_bits_##P("y", s.y);                                                                          \
        print_bits_##P("theta", s.theta);                                                                  \
        printf(" steps=%ld\n", k);                                                                         \
        return 0;                                                                                          \
    }                                                                                                      \
                                                                                                           \
    /* The scenario's obstacles: the post, then the box. */                                                \
    static int obstacles_##P(wmr_obstacles_##P *o) {                                                      \
        wmr_error err;                                                                                     \
        const S box[4][2] = {{(S)0.3, (S)-0.55}, {(S)0.7, (S)-0.55}, {(S)0.7, (S)-0.3}, {(S)0.3, (S)-0.3}}; \
        CHECK(wmr_obstacles_##P##_init(o, (S)0.22, &err), &err);                                           \
        CHECK(wmr_obstacles_##P##_add_polygon(o, box, 4, &err), &err);                                     \
        CHECK(wmr_obstacles_##P##_add_circle(o, (S)0.55, (S)0.3, (S)0.1, &err), &err);                     \
        return 0;                                                                                          \
    }                                                                                                      \
                                                                                                           \
    static int refusals_##P(void) {                                                                        \
        wmr_error err;                                                                                     \
        wmr_obstacles_##P o;                                                                               \
        const S two[2][2] = {{0, 0}, {1, 0}};                                                              \
        int i;                                                                                             \
        EXPECT(wmr_obstacles_##P##_init(&o, (S)-1, &err) == WMR_NEGATIVE);                                 \
        EXPECT(strcmp(err.field, "footprint_radius") == 0);                                                \
        CHECK(wmr_obstacles_##P##_init(&o, (S)0.2, &err), &err);                                           \
        EXPECT(wmr_obstacles_##P##_add_circle(&o, 0, 0, 0, &err) == WMR_OUT_OF_RANGE);                     \
        EXPECT(strcmp(err.field, "obstacle.radius") == 0);                                                 \
        EXPECT(wmr_obstacles_##P##_add_polygon(&o, two, 2, &err) == WMR_OUT_OF_RANGE);                     \
        EXPECT(strcmp(err.field, "obstacle.points") == 0);                                                 \
        EXPECT(wmr_obstacles_##P##_add_polygon(&o, NULL, 3, &err) == WMR_NULL_POINTER);                    \
        for (i = 0; i < 16; i++) CHECK(wmr_obstacles_##P##_add_circle(&o, (S)i, 0, 1, &err), &err);        \
        EXPECT(wmr_obstacles_##P##_add_circle(&o, 0, 0, 1, &err) == WMR_OUT_OF_RANGE);                     \
        EXPECT(strcmp(err.field, "obstacle") == 0);                                                        \
        EXPECT(wmr_obstacles_##P##_add_circle(NULL, 0, 0, 1, &err) == WMR_NULL_POINTER);                   \
        printf("pass " #P ": refusals\n");                                                                 \
        return 0;                                                                                          \
    }

DEFINE_RUN(double, f64)
DEFINE_RUN(float, f32)

int main(void) {
    wmr_obstacles_f64 o64;
    wmr_obstacles_f32 o32;
    if (obstacles_f64(&o64) != 0 || obstacles_f32(&o32) != 0) return 1;
    if (run_f64("run1", &o64, 1) != 0 || run_f64("run0", &o64, 0) != 0 || run_f64("blind", NULL, 1) != 0) return 1;
    if (run_f32("run1", &o32, 1) != 0) return 1;
    if (refusals_f64() != 0 || refusals_f32() != 0) return 1;
    printf("ok\n");
    return 0;
}
