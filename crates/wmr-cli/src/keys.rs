//! The long help: every scenario key with its unit and default (docs/scenario.md has more).

/// Shown by `wmr-cli --help`, `wmr-cli run --help` and `wmr-cli check --help`.
pub const KEYS_HELP: &str = r#"SCENARIO FILE (TOML; every key optional except [[run]]; unknown keys are errors)

name = "fig7"                  scenario name (default: the file's stem)

[robot]                        SI units
  mass = 5.0                   m, total mass, kg (> 0)
  wheel_radius = 0.1           r, m (> 0)
  half_track = 0.2             R, axle midpoint C to each wheel, m (> 0)
  com_offset = 0.25            d, C forward to the centre of mass G, m (any sign)
  wheel_inertia = 0.002        I_m, one wheel plus its motor rotor, kg m^2 (>= 0)
  platform_inertia = 0.005     I_p, platform about G, kg m^2 (>= 0; I_p + m d^2 > 0)
  gear_ratio = 0.1             k_t, wheel speed = k_t * motor speed (> 0)
  viscous_friction = 0.0       b_v, N m s per wheel (>= 0)
  coulomb_friction = 0.0       tau_c, N m per wheel (>= 0)
  coulomb_speed = 0.001        omega_eps, rad/s, tanh smoothing of Coulomb friction (> 0)

[drive]
  kind = "torque"              "torque" (default) or "dc_motor"
  kind = "torque":
    motor_torque_max = 0.2     |motor torque| limit, N m at the motor (> 0, inf allowed)
  kind = "dc_motor":           defaults: maxon RE 40 148867, 24 V winding
    voltage_max = 24.0         u_max, V (> 0)
    torque_constant = 0.0302   k_tau, N m/A (> 0)
    back_emf_constant = 0.0302 k_e, V s/rad at the motor shaft (>= 0)
    armature_resistance = 0.299  R_a, Ohm (> 0)
    current_max = inf          A, armature current limit of the driver (> 0, inf = none)

[controller]                   an outer law (kind) and a wheel stage; each kind accepts only its
                               own law keys plus the wheel-stage keys and control_dt
  kind = "paper"               "paper" (the paper's law), "paper_bidirectional" (the paper's law
                               repaired, docs/model.md), "polar" (Astolfi) or "lyapunov" (Aicardi)
  kind = "paper":
    mode = "pose"              "pose" (reach x, y, theta) or "position" (heading free)
    kp_theta = 2.0             Kp_theta, rad/rad (>= 0)
    ki_theta = 0.1             Ki_theta, 1/s (>= 0)
    kp_s = 1.0                 Kp_s, m/m (>= 0)
    ki_s = 0.25                Ki_s, 1/s (>= 0)
    goal_radius = 0.001        m: inside it alpha keeps its last value (>= 0)
    hold_radius = 0.005        m: inside it the outer loop holds; 0 = off (>= 0)
    hold = "auto"              "auto" (zero_errors in pose mode, freeze in position mode),
                               "zero_errors" (errors zeroed, references step on entry)
                               or "freeze" (bumpless: keep the last wheel references)
  kind = "paper_bidirectional":  the paper's structure; e_s = (x_d - x) cos theta + (y_d - y) sin theta
    kp_theta = 0.0             Kp_theta, rad/rad (>= 0)
    ki_theta = 1.0             Ki_theta, 1/s (> ki_s (1 - kp_theta) / (1 + kp_s))
    kp_s = 0.0                 Kp_s, m/m (>= 0)
    ki_s = 0.25                Ki_s, 1/s (> 0)
    goal_radius = 0.001        m: inside it alpha keeps its last value (>= 0)
    hold_radius = 0.005        m: inside it the outer loop holds; 0 = off (>= 0)
    hold = "freeze"            "freeze" (bumpless; "auto" is the same) or "zero_errors"
  kind = "polar":              v = k_rho rho, omega = k_alpha alpha + k_beta beta
    k_rho = 0.5                1/s (> 0)
    k_alpha = 3.0              1/s (> k_rho; k_alpha + 5/3 k_beta - 2/pi k_rho > 0)
    k_beta = -1.2              1/s (< 0)
    reverse = true             back up when the goal is behind
    reverse_hysteresis = 0.5235987755982989
                               rad, overshoot of |alpha| past pi/2 before a switch ([0, pi/2))
    goal_radius = 0.001        m: inside it the law stops, resumes beyond twice that (>= 0)
  kind = "lyapunov":           Aicardi et al. 1995; also reaches the goal heading
    gamma = 0.5                1/s (> 0)
    k = 3.0                    1/s (> 0)
    h = 9.0                    weight of theta_A against alpha (> 0)
    reverse = true             back up when the goal is behind
    reverse_hysteresis = 0.5235987755982989
                               rad ([0, pi/2))
    goal_radius = 0.001        m (>= 0)
  every kind (the wheel stage):
    servo_kp = 14.0            wheel servo Kp: N m/rad (torque), V/rad (dc_motor) (> 0)
    servo_kd = 1.4             wheel servo Kd: N m s/rad; dc_motor default 1.1 V s/rad (>= 0)
    servo_ki = 0.0             wheel servo Ki: N m/(rad s) or V/(rad s) (>= 0)
    wheel_speed_max = inf      rad/s, limit on the wheel speeds (measured within 2 %), curvature
                               kept (> 0)
    control_dt = 0.001         s, control period; a whole multiple of sim.dt (> 0)

[controller.model]             what the controller believes about the robot: any [robot] key;
                               a key not given takes the [robot] value (e.g. wheel_radius = 0.105)

[sensor]                       what the controller sees; no table = perfect and instant
  rate_hz = inf                pose samples per second; 1/rate_hz a whole multiple of control_dt
                               (inf: every control tick)
  latency = 0.0                s, a sample taken at t is used from t + latency on; a whole
                               multiple of control_dt (>= 0)
  position_noise = 0.0         m, std. dev. of Gaussian noise on x and on y of each sample (>= 0)
  heading_noise_deg = 0.0      deg, std. dev. of Gaussian noise on theta of each sample (>= 0)
  encoder_counts = 0           counts per wheel revolution (0 = ideal encoders)
  seed = 0                     the noise is a function of (seed, run index)

[world]
  slope_deg = 0.0              deg, tilt of the ground plane (|slope| < 90); x, y lie in the plane
  slope_direction_deg = 0.0    deg, world direction in which the ground descends

[sim]
  t_end = 60.0                 s per run; a whole multiple of dt; <= 1e6 s and <= 1e9 steps
  dt = 1e-3                    s, RK4 step (default: controller.control_dt)
  log_dt = 0.01                s, output sample period; a whole multiple of dt
  stop_when_settled = false    stop a run once settled: law holding, at rest within 1 cm

[[run]]                        one or more
  label = "..."                text for the summary (default: built from start and goal)
  start = { x = 0.0, y = 0.0, theta_deg = 0.0 }   m, m, and theta (rad) or theta_deg, not both; default 0
  goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }  required; missing x, y, theta are 0

[sweep]                        wmr-cli sweep: every law from every start ([[run]] optional)
  goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }    goal pose of C (default origin, 0)
  controllers = [{ kind = "paper" }, { kind = "paper_bidirectional" }, { kind = "polar" }, { kind = "lyapunov" }]
                               laws to compare, each with its [controller] keys (default: these)
  grid = { x_min = -2.0, x_max = 2.0, nx = 21, y_min = -2.0, y_max = 2.0, ny = 21, theta_deg = [0.0] }
  random = { n = 1000, seed = 1, radius = 2.0, min_radius = 0.1 }
  vary = [{ key = "sensor.latency", values = [0.0, 0.05] }, { key = "world.slope_deg", uniform = [0, 5] }]
                               robustness: vary keys of [robot], [drive], [controller] (and
                               controller.model), [sensor], [world]: values one at a time, or
                               uniform = [low, high] / normal = [mean, std] drawn per run
  trials = 1                   runs per (law, start, value), each with its own noise and draws
  seed = 0                     seed of the per-run draws
                               exactly one of grid (m, deg) and random (m; heading uniform)

OUTPUTS
  CSV:  run,t,x,y,theta,v,omega,phi_r,phi_l,omega_r,omega_l,tau_r,tau_l,e_s,e_theta,dl
        one row per run and sample (t = 0, every log_dt, and the last); SI units, radians.
  MCAP: per run N: /runN/tf (foxglove.FrameTransform world -> runN/base_link),
        /runN/pose (foxglove.PoseInFrame), /runN/path (foxglove.SceneUpdate),
        /runN/sample (JSON wmr.Sample, every CSV column), /runN/goal (foxglove.PoseInFrame, once),
        /runN/robot (foxglove.SceneUpdate, once); log time = simulation time.
  Summary (stdout, one line per run): label, final dl (m), final heading error (deg),
        time from which dl < 1 cm (s or "never"), converged / diverged / unsettled.
        Converged = not diverged and final dl < 1 cm; unsettled = neither by t_end.
  sweep: CSV law,start,x0,y0,theta0_deg,status,time_to_1cm_s,final_dl_m,
        final_heading_error_deg,peak_wheel_speed_rad_s,path_length_m,energy_j; a comparison
        table on stdout; --plots DIR: region-<law>.svg per law; --fast: runs in SIMD
        lanes, not bit-identical (docs/scenario.md, "The fast path").
  plot:  DIR/paths.svg, DIR/run<i>-wheel-speeds.svg, DIR/run<i>-errors.svg.

A diverged run (state not finite, or C outside a 1 km box) keeps its rows up to that
point, is reported as diverged, and the exit code stays 0. Bad input exits with 2 and
one message naming the key; no output file is written. A failed write (full disk) exits
with 1; SIGINT, SIGTERM and SIGHUP leave OUT as it was. OUT may be `-` (stdout), a device
or a FIFO (streamed); its directory must exist. Limits: 16 MiB per file, 1e11 plant steps
per scenario, starts and goals within 1000 m. Full reference: docs/scenario.md
"#;
