//! Open-loop simulation of a log's commands on a wmr plant: what the replay compares with
//! the log, and how the tests and `wmr-cli excite` make logs of a known robot.

use wmr_core::{Drive, Plant, Pose2, Robot, State, Wheels};

use crate::error::IdentifyError;

/// The plant's true signals at each stamp.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Simulated {
    /// Sample times, s.
    pub t_s: Vec<f64>,
    /// Right, left wheel angle, rad (zero at the start).
    pub phi: [Vec<f64>; 2],
    /// Right, left wheel speed, rad/s.
    pub omega: [Vec<f64>; 2],
    /// Right, left wheel torque the drive gives from the stamp on, N m.
    pub torque: [Vec<f64>; 2],
    /// x, y (m), theta (rad) of C, world frame (the start at the origin, heading x).
    pub pose: [Vec<f64>; 3],
}

/// Runs `robot` with `drive` from rest at `start`, holding command k (N m or V per wheel,
/// by drive) from `t_s[k]` to `t_s[k + 1]`; each interval is integrated in RK4 steps no
/// longer than 1 ms nor half the plant's stability limit. Sample k is the state at
/// `t_s[k]`, before command k acts.
pub fn simulate(
    robot: Robot<f64>,
    drive: Drive<f64>,
    start: Pose2<f64>,
    t_s: &[f64],
    command: [&[f64]; 2],
) -> Result<Simulated, IdentifyError> {
    simulate_from(robot, drive, State::at_rest(start), t_s, command)
}

/// [`simulate`] from the state `start` (pose, speeds and wheel angles) at `t_s[0]`.
pub fn simulate_from(
    robot: Robot<f64>,
    drive: Drive<f64>,
    start: State<f64>,
    t_s: &[f64],
    command: [&[f64]; 2],
) -> Result<Simulated, IdentifyError> {
    let mut plant = Plant::new(robot, drive, start.pose())
        .map_err(|e| IdentifyError::BadSetting { key: "start".to_owned(), detail: e.to_string() })?;
    plant.set_state(start);
    let h_max = (0.5 * plant.max_stable_dt()).min(1e-3);
    let mut out = Simulated { t_s: t_s.to_vec(), ..Default::default() };
    for k in 0..t_s.len() {
        plant.apply(Wheels::new(command[0][k], command[1][k]));
        let s = *plant.state();
        let w = plant.wheel_speeds();
        let tau = plant.wheel_torque();
        out.phi[0].push(s.phi_r);
        out.phi[1].push(s.phi_l);
        out.omega[0].push(w.right);
        out.omega[1].push(w.left);
        out.torque[0].push(tau.right);
        out.torque[1].push(tau.left);
        out.pose[0].push(s.x);
        out.pose[1].push(s.y);
        out.pose[2].push(s.theta);
        if k + 1 < t_s.len() {
            let span = t_s[k + 1] - t_s[k];
            let n = (span / h_max).ceil().max(1.0);
            let h = span / n;
            for j in 0..n as usize {
                plant.step(t_s[k] + j as f64 * h, h).map_err(|e| IdentifyError::BadSetting {
                    key: "simulation".to_owned(),
                    detail: format!("the plant stopped at t = {} s: {e:?}", t_s[k] + j as f64 * h),
                })?;
            }
        }
    }
    Ok(out)
}

/// The imperfections of a made-up log ([`log_table`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LogNoise {
    /// Encoder noise: each logged wheel angle gets Gaussian noise whose standard deviation
    /// is this fraction of the wheels' mean travel per sample over the log (0.01: "1 %",
    /// about a 4096-count encoder at a few rad/s and 100 Hz).
    pub encoder_fraction: f64,
    /// Timing jitter, s: each sample is taken (and stamped) up to this late after its
    /// nominal time, uniformly (so the stamps are uneven but increasing).
    pub jitter_s: f64,
    /// Seed of the noise.
    pub seed: u64,
}

impl LogNoise {
    /// No noise, no jitter.
    pub const NONE: LogNoise = LogNoise { encoder_fraction: 0.0, jitter_s: 0.0, seed: 0 };
}

/// A log of `robot` with `drive` playing `tests` (one run each, from rest at the origin),
/// as a table with the columns a wmr run's CSV has (`run`, `t`, the commands `tau_r`,
/// `tau_l` for the torque drive or `u_r`, `u_l` (V) for a DC motor, `phi_r`, `phi_l`,
/// `omega_r`, `omega_l`, `x`, `y`, `theta`), the angles with `noise`. The command of each
/// sample is the test's command at the sample's (jittered) time, held to the next.
pub fn log_table(
    robot: Robot<f64>,
    drive: Drive<f64>,
    tests: &[crate::excite::Test],
    settings: &crate::excite::ExciteSettings,
    noise: LogNoise,
) -> Result<crate::Table, IdentifyError> {
    let voltage = matches!(drive, Drive::DcMotor(_));
    let mut rng = noise.seed;
    let mut uniform = move || {
        rng = rng.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = rng;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 12];
    let mut t_offset = 0.0;
    for (k, test) in tests.iter().enumerate() {
        let n = (test.duration_s(settings) / settings.dt_s).round() as usize + 1;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * settings.dt_s + noise.jitter_s * uniform()).collect();
        let mut c = [Vec::with_capacity(n), Vec::with_capacity(n)];
        for &tk in &t {
            let [r, l] = test.command(tk, settings);
            c[0].push(r);
            c[1].push(l);
        }
        let sim = simulate(robot, drive, Pose2::new(0.0, 0.0, 0.0), &t, [&c[0], &c[1]])?;
        for i in 0..n {
            let row = [
                k as f64,
                t_offset + t[i],
                c[0][i],
                c[1][i],
                sim.phi[0][i],
                sim.phi[1][i],
                sim.omega[0][i],
                sim.omega[1][i],
                sim.pose[0][i],
                sim.pose[1][i],
                sim.pose[2][i],
                0.0,
            ];
            for (col, v) in cols.iter_mut().zip(row) {
                col.push(v);
            }
        }
        t_offset += t[n - 1] + settings.dt_s;
    }
    // Encoder noise: a fraction of the mean travel per sample.
    if noise.encoder_fraction > 0.0 {
        let mut travel = 0.0;
        let mut steps = 0usize;
        for w in 4..6 {
            for i in 1..cols[w].len() {
                if cols[0][i] == cols[0][i - 1] {
                    travel += (cols[w][i] - cols[w][i - 1]).abs();
                    steps += 1;
                }
            }
        }
        let sd = noise.encoder_fraction * travel / steps.max(1) as f64;
        for w in 4..6 {
            for i in 0..cols[w].len() {
                let (u1, u2) = (uniform().max(1e-300), uniform());
                cols[w][i] += sd * (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
            }
        }
    }
    let names = if voltage {
        ["run", "t", "u_r", "u_l", "phi_r", "phi_l", "omega_r", "omega_l", "x", "y", "theta"]
    } else {
        ["run", "t", "tau_r", "tau_l", "phi_r", "phi_l", "omega_r", "omega_l", "x", "y", "theta"]
    };
    let mut table = crate::Table::new();
    for (name, col) in names.iter().zip(cols) {
        table.push(name, col)?;
    }
    Ok(table)
}
