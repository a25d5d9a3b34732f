/* Error reports as a C caller sees them: code, NUL-terminated field name, reason, value.
 * Built and run by tests/c_programs.rs; prints one line per case, "ok" at the end. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "wmr.h"

static int bad = 0;

static void expect(const char *what, wmr_status got, wmr_status want, const wmr_error *err, const char *field) {
    int ok = got == want && (err == NULL || (err->code == want && strcmp(err->field, field) == 0));
    printf("%s %s: %s field=%s reason=%s\n", ok ? "pass" : "FAIL", what, wmr_status_name(got),
           err ? err->field : "-", err ? err->reason : "-");
    if (!ok) bad = 1;
}

int main(void) {
    wmr_error err;
    wmr_robot_params_f64 rp;
    wmr_robot_f64 robot;
    wmr_drive_params_f64 dp;
    wmr_drive_f64 drive;
    wmr_wheel_stage_params_f64 wp;
    wmr_polar_params_f64 pp;
    wmr_polar_controller_f64 ctrl;
    wmr_plant_f64 plant;
    wmr_measurement_f64 m;
    wmr_control_output_f64 out;
    const wmr_pose_f64 origin = {0, 0, 0};

    wmr_robot_params_f64_paper(&rp);
    rp.mass = -1.0;
    expect("negative mass", wmr_robot_f64_init(&robot, &rp, &err), WMR_NOT_POSITIVE, &err, "mass");
    if (err.value != -1.0) { printf("FAIL value %g\n", err.value); bad = 1; }
    rp.mass = 5.0;
    rp.half_track = NAN;
    expect("NaN half_track", wmr_robot_f64_init(&robot, &rp, &err), WMR_NOT_FINITE, &err, "half_track");
    wmr_robot_params_f64_paper(&rp);
    expect("NULL params", wmr_robot_f64_init(&robot, NULL, &err), WMR_NULL_POINTER, &err, "params");
    expect("valid robot", wmr_robot_f64_init(&robot, &rp, &err), WMR_OK, &err, "");

    wmr_drive_params_f64_default(WMR_DRIVE_TORQUE, &dp);
    dp.kind = 7;
    expect("unknown drive kind", wmr_drive_f64_init(&drive, &dp, &robot, &err), WMR_OUT_OF_RANGE, &err, "kind");
    dp.kind = WMR_DRIVE_TORQUE;
    expect("valid drive", wmr_drive_f64_init(&drive, &dp, &robot, &err), WMR_OK, &err, "");

    wmr_wheel_stage_params_f64_default(&dp, &robot, &wp);
    wmr_polar_params_f64_default(&pp);
    pp.k_beta = 0.5;
    expect("k_beta >= 0", wmr_polar_controller_f64_init(&ctrl, &pp, &wp, &robot, &drive, 1e-3, &err),
           WMR_OUT_OF_RANGE, &err, "k_beta");
    wmr_polar_params_f64_default(&pp);
    wp.servo_kp = 0.0;
    expect("servo_kp = 0", wmr_polar_controller_f64_init(&ctrl, &pp, &wp, &robot, &drive, 1e-3, &err),
           WMR_NOT_POSITIVE, &err, "servo_kp");
    wmr_wheel_stage_params_f64_default(&dp, &robot, &wp);
    expect("control_dt = 0", wmr_polar_controller_f64_init(&ctrl, &pp, &wp, &robot, &drive, 0.0, &err),
           WMR_NOT_POSITIVE, &err, "control_dt");

    /* Storage never initialized: refused, not read as a controller. */
    memset(&ctrl, 0xa5, sizeof ctrl);
    memset(&m, 0, sizeof m);
    expect("uninitialized controller", wmr_polar_controller_f64_update(&ctrl, 0.0, &m, origin, &out),
           WMR_NOT_INITIALIZED, NULL, "");
    /* A plant passed where a robot is expected: refused by its tag. */
    expect("valid plant", wmr_plant_f64_init(&plant, &robot, &drive, NULL, origin, &err), WMR_OK, &err, "");
    expect("plant as robot", wmr_drive_f64_init(&drive, &dp, (const wmr_robot_f64 *)(const void *)&plant, &err),
           WMR_NOT_INITIALIZED, &err, "robot");

    expect("valid controller", wmr_polar_controller_f64_init(&ctrl, &pp, &wp, &robot, &drive, 1e-3, &err), WMR_OK,
           &err, "");
    m.pose.x = INFINITY;
    expect("infinite measurement", wmr_polar_controller_f64_update(&ctrl, 0.0, &m, origin, &out), WMR_NOT_FINITE,
           NULL, "");
    m.pose.x = 0.0;
    expect("update", wmr_polar_controller_f64_update(&ctrl, 0.0, &m, origin, &out), WMR_OK, NULL, "");
    expect("reset", wmr_polar_controller_f64_reset(&ctrl), WMR_OK, NULL, "");
    expect("reset NULL", wmr_polar_controller_f64_reset(NULL), WMR_NULL_POINTER, NULL, "");
    if (strcmp(wmr_status_name(12345), "WMR_UNKNOWN") != 0) { printf("FAIL status name\n"); bad = 1; }
    printf("sizeof(wmr_error)=%u sizeof(wmr_plant_f32)=%u\n", (unsigned)sizeof(wmr_error), (unsigned)sizeof(wmr_plant_f32));
    printf(bad ? "FAILED\n" : "ok\n");
    return bad;
}
