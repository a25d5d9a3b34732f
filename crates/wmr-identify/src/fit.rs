//! The fit: linear least squares on the wheel-space form of the dynamics (15) with the
//! drive (docs/identify.md, "Method").
//!
//! With F = (tau_r - f_r + tau_l - f_l) / r and Mo = (R / r)(tau_r - f_r - (tau_l - f_l))
//! the forward force and the moment of (15) (wmr_core's `dynamics.rs`):
//!
//! ```text
//! F  = M_r11 v' - m d omega^2   = m (v' - d omega^2)          + I_m (2 / r^2) v'
//! Mo = M_r22 omega' + m d v omega = m (d^2 omega' + d v omega) + I_m (2 R^2 / r^2) omega' + I_p omega'
//! ```
//!
//! and each wheel s (+1 right, -1 left) takes tau_s - f_s = (r / 2)(F + s Mo / R), so one
//! log row gives two equations, linear in the parameters:
//!
//! ```text
//! tau_s = m    (r/2) [(v' - d omega^2) + s (d^2 omega' + d v omega) / R]     phi_m
//!       + I_m  omega_s'                                                     phi_Im
//!       + I_p  s r omega' / (2 R)                                           phi_Ip
//!       + b_v  omega_s                                                      phi_bv
//!       + tau_c tanh(omega_s / omega_eps)                                   phi_tc
//! ```
//!
//! with v = r (omega_r + omega_l) / 2, omega = r (omega_r - omega_l) / (2 R) and their
//! derivatives from the filtered wheel speeds and accelerations ([`crate::filter`]). The
//! geometry (r, R, d, k_t, omega_eps) is held: it is measured with a ruler, and d enters
//! nonlinearly. m and I_m are told apart only through the terms in d: a robot with
//! d = 0, or a log without turning while driving, determines only m + 2 I_m / r^2.
//!
//! A DC motor's voltage u gives the wheel torque k_tau (u - k_e omega_s / k_t) / (R_a k_t)
//! (current below its limit), so
//!
//! ```text
//! u_s = g tau_s + kappa omega_s,   g = R_a k_t / k_tau (V / N m),  kappa = k_e / k_t
//! ```
//!
//! linear in (g, g m, g I_m, ...): the voltage fixes the torque only up to the scale g, so
//! at least one mechanical parameter must be held (the mass, weighed), and k_tau and R_a
//! enter only as their ratio (one is held: R_a, measured with an ohmmeter).

use wmr_core::RobotParams;
use wmr_core::drive::DcMotorParams;

use crate::error::IdentifyError;
use crate::filter::local_polynomial;
use crate::linalg::{spd_inverse, symmetric_eigen};
use crate::log::{CommandKind, Log, WheelSignal};

/// A parameter the fit can estimate or hold, by its robot-file key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Param {
    /// `[robot] mass`, m, kg.
    Mass,
    /// `[robot] wheel_inertia`, I_m, kg m^2 (wheel and rotor, at the wheel).
    WheelInertia,
    /// `[robot] platform_inertia`, I_p, kg m^2 (about G).
    PlatformInertia,
    /// `[robot] viscous_friction`, b_v, N m s.
    ViscousFriction,
    /// `[robot] coulomb_friction`, tau_c, N m.
    CoulombFriction,
    /// `[drive] torque_constant`, k_tau, N m/A.
    TorqueConstant,
    /// `[drive] back_emf_constant`, k_e, V s/rad.
    BackEmfConstant,
    /// `[drive] armature_resistance`, R_a, Ohm.
    ArmatureResistance,
}

/// The mechanical parameters, in the order of the regressors.
pub const MECHANICAL: [Param; 5] =
    [Param::Mass, Param::WheelInertia, Param::PlatformInertia, Param::ViscousFriction, Param::CoulombFriction];

/// The DC motor's parameters.
pub const MOTOR: [Param; 3] = [Param::TorqueConstant, Param::BackEmfConstant, Param::ArmatureResistance];

impl Param {
    /// Every parameter, mechanical first.
    pub const ALL: [Param; 8] = [
        Param::Mass,
        Param::WheelInertia,
        Param::PlatformInertia,
        Param::ViscousFriction,
        Param::CoulombFriction,
        Param::TorqueConstant,
        Param::BackEmfConstant,
        Param::ArmatureResistance,
    ];

    /// The key in a robot file.
    pub fn key(self) -> &'static str {
        match self {
            Param::Mass => "mass",
            Param::WheelInertia => "wheel_inertia",
            Param::PlatformInertia => "platform_inertia",
            Param::ViscousFriction => "viscous_friction",
            Param::CoulombFriction => "coulomb_friction",
            Param::TorqueConstant => "torque_constant",
            Param::BackEmfConstant => "back_emf_constant",
            Param::ArmatureResistance => "armature_resistance",
        }
    }

    /// The unit of the value.
    pub fn unit(self) -> &'static str {
        match self {
            Param::Mass => "kg",
            Param::WheelInertia | Param::PlatformInertia => "kg m^2",
            Param::ViscousFriction => "N m s",
            Param::CoulombFriction => "N m",
            Param::TorqueConstant => "N m/A",
            Param::BackEmfConstant => "V s/rad",
            Param::ArmatureResistance => "Ohm",
        }
    }

    /// The table the key belongs to: `robot` or `drive`.
    pub fn table(self) -> &'static str {
        if MOTOR.contains(&self) { "drive" } else { "robot" }
    }

    /// The parameter of a key, if it is one the fit knows.
    pub fn from_key(key: &str) -> Option<Param> {
        Param::ALL.into_iter().find(|p| p.key() == key)
    }

    /// Its value in `robot` or `motor`.
    pub fn get(self, robot: &RobotParams<f64>, motor: &DcMotorParams<f64>) -> f64 {
        match self {
            Param::Mass => robot.mass,
            Param::WheelInertia => robot.wheel_inertia,
            Param::PlatformInertia => robot.platform_inertia,
            Param::ViscousFriction => robot.viscous_friction,
            Param::CoulombFriction => robot.coulomb_friction,
            Param::TorqueConstant => motor.torque_constant,
            Param::BackEmfConstant => motor.back_emf_constant,
            Param::ArmatureResistance => motor.armature_resistance,
        }
    }

    /// Sets its value in `robot` or `motor` to `v`.
    pub fn set(self, robot: &mut RobotParams<f64>, motor: &mut DcMotorParams<f64>, v: f64) {
        match self {
            Param::Mass => robot.mass = v,
            Param::WheelInertia => robot.wheel_inertia = v,
            Param::PlatformInertia => robot.platform_inertia = v,
            Param::ViscousFriction => robot.viscous_friction = v,
            Param::CoulombFriction => robot.coulomb_friction = v,
            Param::TorqueConstant => motor.torque_constant = v,
            Param::BackEmfConstant => motor.back_emf_constant = v,
            Param::ArmatureResistance => motor.armature_resistance = v,
        }
    }
}

/// How to fit: the robot's geometry and held values, what to hold, the filter.
#[derive(Clone, Debug, PartialEq)]
pub struct FitSettings {
    /// The robot: its geometry (wheel_radius, half_track, com_offset, gear_ratio,
    /// coulomb_speed) is always held; the values of held parameters come from here.
    pub robot: RobotParams<f64>,
    /// The DC motor (voltage logs): its held values (and voltage_max, current_max,
    /// deadband, written unchanged).
    pub motor: DcMotorParams<f64>,
    /// The parameters held at their value in `robot` / `motor` rather than fitted.
    pub hold: Vec<Param>,
    /// Half-width of the derivative filter's window, s (the window spans 2 x this).
    pub half_window_s: f64,
    /// Rows where a wheel turns slower than this fraction of the log's fastest wheel
    /// speed are left out (the Coulomb term's sign is unknown there).
    pub still_fraction: f64,
    /// A change of a command between two samples larger than this fraction of the
    /// largest command is a jump: rows whose filter window spans it are left out.
    pub jump_fraction: f64,
    /// The largest condition number of the column-scaled regressor accepted; above it
    /// the parameters along the weakest direction are refused as not identifiable.
    pub max_condition: f64,
    /// How many times the filter's noise in a regressor its own part (the part the
    /// other regressors cannot explain) must be; below it the parameter is refused.
    pub min_excitation: f64,
}

impl FitSettings {
    /// The defaults for a log of `kind`, on `robot` (and `motor` for voltage logs): hold
    /// nothing for torque logs; for voltage logs hold mass, viscous_friction and
    /// armature_resistance (the scale, the friction beside the back-EMF, and the ratio
    /// k_tau / R_a, which the voltage alone cannot split).
    pub fn new(kind: CommandKind, robot: RobotParams<f64>, motor: DcMotorParams<f64>) -> Self {
        let hold = match kind {
            CommandKind::Torque => Vec::new(),
            CommandKind::Voltage => vec![Param::Mass, Param::ViscousFriction, Param::ArmatureResistance],
        };
        Self {
            robot,
            motor,
            hold,
            half_window_s: 0.15,
            still_fraction: 0.02,
            jump_fraction: 0.05,
            max_condition: 1e3,
            min_excitation: 5.0,
        }
    }
}

/// One parameter's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Which.
    pub param: Param,
    /// Value (fitted, or the held one), in [`Param::unit`].
    pub value: f64,
    /// Standard error from the residual covariance (0 when held): sigma^2 (A^T A)^-1 with
    /// sigma^2 = RSS / (rows - parameters); through g by the delta method for a DC motor.
    pub std_err: f64,
    /// True when held at the given value.
    pub held: bool,
    /// True when the fit came out below zero, within 3 standard errors of it, and was
    /// set to 0 (every parameter is >= 0); `std_err` is the fit's.
    pub zeroed: bool,
}

/// The result of a fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    /// Every parameter of the drive kind (mechanical, then the motor's for voltage logs).
    pub estimates: Vec<Estimate>,
    /// The robot with the fitted values.
    pub robot: RobotParams<f64>,
    /// The motor with the fitted values (voltage logs; otherwise the settings' motor).
    pub motor: DcMotorParams<f64>,
    /// What the commands were.
    pub command: CommandKind,
    /// Equations used (two per row kept).
    pub equations: usize,
    /// Rows of the log used, and in total.
    pub rows_used: usize,
    /// Rows in the log.
    pub rows_total: usize,
    /// RMS of the residual, N m (torque) or V (voltage).
    pub rms_residual: f64,
    /// Condition number of the column-scaled regressor.
    pub condition: f64,
    /// The filter's half-width in samples, per run.
    pub half_window: Vec<usize>,
}

impl Fit {
    /// The estimate of `p`, if the drive kind has it.
    pub fn get(&self, p: Param) -> Option<&Estimate> {
        self.estimates.iter().find(|e| e.param == p)
    }
}

/// Degree of the local polynomial fitted to wheel angles ([`crate::filter`]): 5, so
/// the acceleration's bias comes from the sixth derivative (docs/identify.md).
pub const ANGLE_DEGREE: usize = 5;

/// Degree of the local polynomial fitted to wheel speeds: 4, the angle's 5 differentiated once.
pub const SPEED_DEGREE: usize = 4;

/// Filtered wheel speeds and accelerations of one run, rad/s and rad/s^2.
struct RunSignals {
    speed: [Vec<f64>; 2],
    accel: [Vec<f64>; 2],
    half: usize,
    /// The variance of each wheel's samples about the filter's local fits.
    noise_var: [f64; 2],
}

fn signals(
    run: &crate::log::Run,
    wheel: &[Vec<f64>; 2],
    signal: WheelSignal,
    half_window_s: f64,
) -> Result<RunSignals, IdentifyError> {
    let n = run.t_s.len();
    let mut dts: Vec<f64> = run.t_s.windows(2).map(|w| w[1] - w[0]).collect();
    dts.sort_by(f64::total_cmp);
    let median_dt = dts.get(dts.len() / 2).copied().unwrap_or(f64::NAN);
    let half = ((half_window_s / median_dt).round() as usize).max(3);
    let needed = 2 * half + 2;
    if n < needed {
        return Err(IdentifyError::TooShort { run: run.index, rows: n, needed });
    }
    let mut out = RunSignals { speed: Default::default(), accel: Default::default(), half, noise_var: [0.0; 2] };
    for w in 0..2 {
        let d = match signal {
            WheelSignal::Angle => local_polynomial(&run.t_s, &wheel[w], half, ANGLE_DEGREE),
            WheelSignal::Speed => local_polynomial(&run.t_s, &wheel[w], half, SPEED_DEGREE),
        };
        out.noise_var[w] = d.noise_var;
        (out.speed[w], out.accel[w]) = match signal {
            WheelSignal::Angle => (d.d1, d.d2),
            WheelSignal::Speed => (d.value, d.d1),
        };
    }
    Ok(out)
}

/// The rows of each run the fit uses: a centred filter window, both wheels turning
/// faster than `still` (rad/s), no command jump larger than `jump` inside the window.
fn row_masks(log: &Log, sigs: &[RunSignals], still: f64, jump: f64) -> Vec<Vec<bool>> {
    log.runs
        .iter()
        .zip(sigs)
        .map(|(run, sig)| {
            let n = run.t_s.len();
            let h = sig.half;
            let mut keep = vec![false; n];
            for (i, k) in keep.iter_mut().enumerate().take(n - h).skip(h) {
                let w = [sig.speed[0][i], sig.speed[1][i], sig.accel[0][i], sig.accel[1][i]];
                *k = w.iter().all(|x| x.is_finite()) && w[0].abs() >= still && w[1].abs() >= still;
            }
            for j in 0..n - 1 {
                if (0..2).any(|w| (run.command[w][j + 1] - run.command[w][j]).abs() > jump) {
                    for k in j.saturating_sub(h)..=(j + 1 + h).min(n - 1) {
                        keep[k] = false;
                    }
                }
            }
            keep
        })
        .collect()
}

/// The equations of the kept rows: the commands and the regressors of the five
/// mechanical parameters (module docs), two equations (right, left) per row.
struct Equations {
    y: Vec<f64>,
    mech: [Vec<f64>; 5],
    wheel_speed: Vec<f64>,
}

fn equations(log: &Log, sigs: &[RunSignals], masks: &[Vec<bool>], robot: &RobotParams<f64>) -> Equations {
    let (r, big_r, d, eps) = (robot.wheel_radius, robot.half_track, robot.com_offset, robot.coulomb_speed);
    let mut e = Equations { y: Vec::new(), mech: Default::default(), wheel_speed: Vec::new() };
    for ((run, sig), mask) in log.runs.iter().zip(sigs).zip(masks) {
        for i in (0..run.t_s.len()).filter(|&i| mask[i]) {
            let (wr, wl) = (sig.speed[0][i], sig.speed[1][i]);
            let (ar, al) = (sig.accel[0][i], sig.accel[1][i]);
            let v = r * (wr + wl) / 2.0;
            let om = r * (wr - wl) / (2.0 * big_r);
            let dv = r * (ar + al) / 2.0;
            let dom = r * (ar - al) / (2.0 * big_r);
            for (w, s) in [(0usize, 1.0f64), (1, -1.0)] {
                let ws = sig.speed[w][i];
                e.mech[0].push((r / 2.0) * ((dv - d * om * om) + s * (d * d * dom + d * v * om) / big_r));
                e.mech[1].push(sig.accel[w][i]);
                e.mech[2].push(s * r * dom / (2.0 * big_r));
                e.mech[3].push(ws);
                e.mech[4].push((ws / eps).tanh());
                e.wheel_speed.push(ws);
                e.y.push(run.command[w][i]);
            }
        }
    }
    e
}

/// One unknown of the linear problem: the physical parameter it stands for (named in
/// refusals) and its regressor column.
struct Unknown {
    name: Param,
    column: Vec<f64>,
}

/// The unknowns and the known side of the linear problem for `e` (module docs): held
/// parameters move to the known side; for a voltage log the first unknown is g.
fn assemble(
    mut e: Equations,
    settings: &FitSettings,
    voltage: bool,
) -> Result<(Vec<Unknown>, Vec<f64>), IdentifyError> {
    let held = |q: Param| settings.hold.contains(&q);
    let mut y = e.y;
    let mut unknowns: Vec<Unknown> = Vec::new();
    if !voltage {
        for (k, q) in MECHANICAL.into_iter().enumerate() {
            if held(q) {
                let v = q.get(&settings.robot, &settings.motor);
                for (yi, phi) in y.iter_mut().zip(&e.mech[k]) {
                    *yi -= v * phi;
                }
            } else {
                unknowns.push(Unknown { name: q, column: std::mem::take(&mut e.mech[k]) });
            }
        }
        return Ok((unknowns, y));
    }
    // u = g (sum_held q phi_q) + sum_free (g q) phi_q + kappa omega_s.
    let mut g_col = vec![0.0; y.len()];
    let mut held_any = false;
    let mut free = Vec::new();
    for (k, q) in MECHANICAL.into_iter().enumerate() {
        if held(q) {
            let v = q.get(&settings.robot, &settings.motor);
            held_any |= v != 0.0;
            for (gi, phi) in g_col.iter_mut().zip(&e.mech[k]) {
                *gi += v * phi;
            }
        } else {
            free.push(k);
        }
    }
    if !held_any {
        return Err(IdentifyError::NotIdentifiable {
            parameter: "mass".to_owned(),
            detail: "a voltage fixes the torque only up to the motor's scale R_a k_t / k_tau: hold at least one mechanical parameter at a nonzero value, the mass (weighed) by default".to_owned(),
        });
    }
    if !held(Param::ArmatureResistance) && !held(Param::TorqueConstant) {
        return Err(IdentifyError::NotIdentifiable {
            parameter: "armature_resistance, torque_constant".to_owned(),
            detail: "a voltage log without currents gives only their ratio k_tau / R_a: hold one (R_a measured with an ohmmeter)".to_owned(),
        });
    }
    let g_name = if held(Param::ArmatureResistance) { Param::TorqueConstant } else { Param::ArmatureResistance };
    unknowns.push(Unknown { name: g_name, column: g_col });
    for k in free {
        unknowns.push(Unknown { name: MECHANICAL[k], column: std::mem::take(&mut e.mech[k]) });
    }
    if held(Param::BackEmfConstant) {
        let kappa = settings.motor.back_emf_constant / settings.robot.gear_ratio;
        for (yi, ws) in y.iter_mut().zip(&e.wheel_speed) {
            *yi -= kappa * ws;
        }
    } else {
        unknowns.push(Unknown { name: Param::BackEmfConstant, column: e.wheel_speed });
    }
    Ok((unknowns, y))
}

/// splitmix64 and Box-Muller: the fixed noise the identifiability check adds to a copy
/// of the log (seeded, so a fit gives the same answer every time).
fn gaussians(seed: u64, n: usize) -> Vec<f64> {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let (u1, u2) = (next().max(1e-300), next());
            (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
        })
        .collect()
}

/// Fits `log` under `settings`.
pub fn fit(log: &Log, settings: &FitSettings) -> Result<Fit, IdentifyError> {
    check_settings(settings)?;
    let held = |q: Param| settings.hold.contains(&q);
    let voltage = log.command == CommandKind::Voltage;
    // Excitation: some command and some wheel motion.
    let cmd_names = [&log.columns_used[1], &log.columns_used[2]];
    let max_cmd = log.runs.iter().flat_map(|r| r.command.iter().flatten()).fold(0.0f64, |a, &c| a.max(c.abs()));
    if max_cmd == 0.0 {
        return Err(IdentifyError::NoExcitation {
            column: cmd_names[0].clone(),
            detail: format!("every command ({} and {}) is zero", cmd_names[0], cmd_names[1]),
        });
    }
    let sigs: Vec<RunSignals> = log
        .runs
        .iter()
        .map(|run| signals(run, &run.wheel, log.wheel, settings.half_window_s))
        .collect::<Result<_, _>>()?;
    let max_speed = sigs
        .iter()
        .flat_map(|s| s.speed.iter().flatten())
        .filter(|v| v.is_finite())
        .fold(0.0f64, |a, &v| a.max(v.abs()));
    if max_speed == 0.0 {
        return Err(IdentifyError::NoExcitation {
            column: log.columns_used[3].clone(),
            detail: "the wheels never turn".to_owned(),
        });
    }
    let still = settings.still_fraction * max_speed;
    let masks = row_masks(log, &sigs, still, settings.jump_fraction * max_cmd);
    let rows_used: usize = masks.iter().map(|m| m.iter().filter(|&&k| k).count()).sum();
    let rows_total = log.samples();
    let (unknowns, y) = assemble(equations(log, &sigs, &masks, &settings.robot), settings, voltage)?;
    let n_eq = y.len();
    let np = unknowns.len();
    if np == 0 {
        return Err(IdentifyError::BadSetting {
            key: "hold".to_owned(),
            detail: "every parameter is held: nothing to fit".to_owned(),
        });
    }
    if n_eq < 2 * np + 2 {
        return Err(IdentifyError::NoExcitation {
            column: log.columns_used[3].clone(),
            detail: format!(
                "{rows_used} rows with both wheels turning faster than {still:.3e} rad/s away from command jumps, too few for {np} parameters"
            ),
        });
    }
    // 1. A regressor that is zero over the rows used: the log does not excite it.
    let scales: Vec<f64> = unknowns.iter().map(|u| u.column.iter().map(|x| x * x).sum::<f64>().sqrt()).collect();
    for (u, &norm) in unknowns.iter().zip(&scales) {
        if !(norm > 1e-12 * (n_eq as f64).sqrt()) {
            return Err(IdentifyError::NotIdentifiable {
                parameter: u.name.key().to_owned(),
                detail: format!("its regressor is zero over the {rows_used} rows used: {}", why_zero(u.name)),
            });
        }
    }
    // 2. The column-scaled Gram matrix's condition number and, when too large, the
    //    weakest direction (the parameters it mixes).
    let mut gram = vec![vec![0.0; np]; np];
    let mut aty = vec![0.0; np];
    for a in 0..np {
        for b in a..np {
            let s: f64 = unknowns[a].column.iter().zip(&unknowns[b].column).map(|(x, z)| x * z).sum();
            gram[a][b] = s / (scales[a] * scales[b]);
            gram[b][a] = gram[a][b];
        }
        aty[a] = unknowns[a].column.iter().zip(&y).map(|(x, z)| x * z).sum::<f64>() / scales[a];
    }
    let (vals, vecs) = symmetric_eigen(&gram);
    let (kmin, &lmin) = vals.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).expect("np > 0");
    let lmax = vals.iter().copied().fold(0.0f64, f64::max);
    let condition = if lmin > 0.0 { (lmax / lmin).sqrt() } else { f64::INFINITY };
    if !(condition <= settings.max_condition) {
        let mut mix: Vec<(f64, usize)> = (0..np).map(|a| (vecs[a][kmin].abs(), a)).filter(|(c, _)| *c > 0.2).collect();
        mix.sort_by(|x, y| y.0.total_cmp(&x.0));
        let parts: Vec<Param> = mix.iter().map(|&(_, a)| unknowns[a].name).collect();
        return Err(IdentifyError::NotIdentifiable {
            parameter: names(&parts),
            detail: format!(
                "their regressors are nearly dependent: condition number {condition:.3e} > {:.0e}{}",
                settings.max_condition,
                why_dependent(&parts, settings.robot.com_offset)
            ),
        });
    }
    let inv = spd_inverse(&vals, &vecs);
    // 3. Excitation against noise: each unknown's part of its regressor that the others
    //    cannot explain, 1 / sqrt([(A^T A)^-1]_jj), must stand above the noise the filter
    //    leaves in that regressor. That noise is measured by filtering a copy of the log
    //    with as much noise again (the variance about the filter's own local fits) and
    //    taking the change of the regressor: a yaw acceleration made only of encoder
    //    noise (straight-line runs) is refused here, where the condition number cannot see it.
    let noisy: Vec<RunSignals> = log
        .runs
        .iter()
        .zip(&sigs)
        .enumerate()
        .map(|(k, (run, sig))| {
            let wheel: [Vec<f64>; 2] = std::array::from_fn(|w| {
                let sd = sig.noise_var[w].max(0.0).sqrt();
                let z = gaussians(0x5EED_0000 + (2 * k + w) as u64, run.wheel[w].len());
                run.wheel[w].iter().zip(z).map(|(x, z)| x + sd * z).collect()
            });
            signals(run, &wheel, log.wheel, settings.half_window_s)
        })
        .collect::<Result<_, _>>()?;
    let (noisy_unknowns, _) = assemble(equations(log, &noisy, &masks, &settings.robot), settings, voltage)?;
    for (a, (u, nu)) in unknowns.iter().zip(&noisy_unknowns).enumerate() {
        let own = scales[a] / inv[a][a].sqrt();
        let noise = u.column.iter().zip(&nu.column).map(|(x, z)| (z - x).powi(2)).sum::<f64>().sqrt();
        if own < settings.min_excitation * noise {
            return Err(IdentifyError::NotIdentifiable {
                parameter: u.name.key().to_owned(),
                detail: format!(
                    "its regressor's own part ({own:.3e}) is within {}x the filter's noise in it ({noise:.3e}): {}",
                    settings.min_excitation,
                    why_noise(u.name)
                ),
            });
        }
    }
    let beta: Vec<f64> = (0..np).map(|a| (0..np).map(|b| inv[a][b] * aty[b]).sum()).collect();
    let theta: Vec<f64> = (0..np).map(|a| beta[a] / scales[a]).collect();
    let rss: f64 = (0..n_eq)
        .map(|i| {
            let pred: f64 = (0..np).map(|a| theta[a] * unknowns[a].column[i]).sum();
            (y[i] - pred).powi(2)
        })
        .sum();
    let sigma2 = rss / (n_eq - np) as f64;
    let cov: Vec<Vec<f64>> =
        (0..np).map(|a| (0..np).map(|b| sigma2 * inv[a][b] / (scales[a] * scales[b])).collect()).collect();
    let pos = |q: Param| unknowns.iter().position(|u| u.name == q);

    let mut robot = settings.robot;
    let mut motor = settings.motor;
    let mut estimates = Vec::new();
    let held_estimate = |q: Param| Estimate {
        param: q,
        value: q.get(&settings.robot, &settings.motor),
        std_err: 0.0,
        held: true,
        zeroed: false,
    };
    if !voltage {
        for q in MECHANICAL {
            match pos(q) {
                Some(a) => {
                    let e =
                        Estimate { param: q, value: theta[a], std_err: cov[a][a].sqrt(), held: false, zeroed: false };
                    q.set(&mut robot, &mut motor, e.value);
                    estimates.push(e);
                }
                None => estimates.push(held_estimate(q)),
            }
        }
    } else {
        // theta[0] = g = R_a k_t / k_tau; theta[a] = g q for a free mechanical q; kappa = k_e / k_t.
        let g = theta[0];
        let var_g = cov[0][0];
        for q in MECHANICAL {
            match pos(q) {
                Some(a) => {
                    // q = alpha / g: dq/dalpha = 1 / g, dq/dg = -alpha / g^2.
                    let (ja, jg) = (1.0 / g, -theta[a] / (g * g));
                    let var = ja * ja * cov[a][a] + jg * jg * var_g + 2.0 * ja * jg * cov[a][0];
                    let e = Estimate {
                        param: q,
                        value: theta[a] / g,
                        std_err: var.max(0.0).sqrt(),
                        held: false,
                        zeroed: false,
                    };
                    q.set(&mut robot, &mut motor, e.value);
                    estimates.push(e);
                }
                None => estimates.push(held_estimate(q)),
            }
        }
        let k_t = settings.robot.gear_ratio;
        let mut push = |e: Estimate, motor: &mut DcMotorParams<f64>| {
            if !e.held {
                e.param.set(&mut robot, motor, e.value);
            }
            estimates.push(e);
        };
        if held(Param::ArmatureResistance) {
            let r_a = settings.motor.armature_resistance;
            let (v, se) = (r_a * k_t / g, r_a * k_t / (g * g) * var_g.sqrt());
            push(
                Estimate { param: Param::TorqueConstant, value: v, std_err: se, held: false, zeroed: false },
                &mut motor,
            );
        } else {
            push(held_estimate(Param::TorqueConstant), &mut motor);
        }
        match pos(Param::BackEmfConstant) {
            Some(a) => push(
                Estimate {
                    param: Param::BackEmfConstant,
                    value: theta[a] * k_t,
                    std_err: cov[a][a].sqrt() * k_t,
                    held: false,
                    zeroed: false,
                },
                &mut motor,
            ),
            None => push(held_estimate(Param::BackEmfConstant), &mut motor),
        }
        if held(Param::ArmatureResistance) {
            push(held_estimate(Param::ArmatureResistance), &mut motor);
        } else {
            let k_tau = settings.motor.torque_constant;
            let (v, se) = (g * k_tau / k_t, var_g.sqrt() * k_tau / k_t);
            push(
                Estimate { param: Param::ArmatureResistance, value: v, std_err: se, held: false, zeroed: false },
                &mut motor,
            );
        }
    }
    // Every parameter is >= 0: a value below zero within 3 standard errors of it is a
    // zero the noise moved (a robot without that friction); one further below is a model
    // that does not fit the log, refused.
    for e in estimates.iter_mut().filter(|e| !e.held && e.value < 0.0) {
        if e.value >= -3.0 * e.std_err {
            e.value = 0.0;
            e.zeroed = true;
            e.param.set(&mut robot, &mut motor, 0.0);
        } else {
            return Err(IdentifyError::Unphysical {
                parameter: e.param.key().to_owned(),
                value: e.value,
                std_err: e.std_err,
            });
        }
    }
    settling_check(log, &robot, &motor, voltage, &held)?;
    Ok(Fit {
        estimates,
        robot,
        motor,
        command: log.command,
        equations: n_eq,
        rows_used,
        rows_total,
        rms_residual: (rss / n_eq as f64).sqrt(),
        condition,
        half_window: sigs.iter().map(|s| s.half).collect(),
    })
}

/// The wheels' mechanical time constants with the fitted values, s: (straight-line,
/// turning). Per wheel, a straight-line motion is (M_r11 r^2 / 2) omega_s' = tau - c omega_s
/// and a turning one (M_r22 r^2 / (2 R^2)) omega_s' = tau - c omega_s, where the damping c
/// is the viscous friction plus, for a DC motor, the back-EMF's k_tau k_e / (R_a k_t^2)
/// (N m s). Infinite without damping.
pub fn time_constants(robot: &RobotParams<f64>, motor: &DcMotorParams<f64>, voltage: bool) -> (f64, f64) {
    let (r, big_r, k_t) = (robot.wheel_radius, robot.half_track, robot.gear_ratio);
    let emf = if voltage {
        motor.torque_constant * motor.back_emf_constant / (motor.armature_resistance * k_t * k_t)
    } else {
        0.0
    };
    let c = robot.viscous_friction + emf;
    let m11 = robot.mass + 2.0 * robot.wheel_inertia / (r * r);
    let m22 = robot.platform_inertia
        + robot.mass * robot.com_offset * robot.com_offset
        + 2.0 * big_r * big_r * robot.wheel_inertia / (r * r);
    if !(c > 0.0) {
        return (f64::INFINITY, f64::INFINITY);
    }
    (m11 * r * r / (2.0 * c), m22 * r * r / (2.0 * big_r * big_r * c))
}

/// Refuses the inertias of a motion whose wheels settle within one sample of the log
/// (their mechanical time constant, [`time_constants`], below the log's median sample
/// period): such a log shows the speeds the commands hold, not the accelerations that
/// carry the inertias (docs/identify.md, "When a parameter is refused").
fn settling_check(
    log: &Log,
    robot: &RobotParams<f64>,
    motor: &DcMotorParams<f64>,
    voltage: bool,
    held: &dyn Fn(Param) -> bool,
) -> Result<(), IdentifyError> {
    let mut dts: Vec<f64> = log.runs.iter().flat_map(|r| r.t_s.windows(2).map(|w| w[1] - w[0])).collect();
    if dts.is_empty() {
        return Ok(());
    }
    dts.sort_by(f64::total_cmp);
    let dt = dts[dts.len() / 2];
    let (tau_lin, tau_turn) = time_constants(robot, motor, voltage);
    let damping = if voltage { "viscous friction and back-EMF" } else { "viscous friction" };
    for (tau, motion, params) in [
        (tau_turn, "turning", &[Param::PlatformInertia][..]),
        (tau_lin, "straight-line", &[Param::WheelInertia, Param::Mass][..]),
    ] {
        let named: Vec<Param> = params.iter().copied().filter(|&q| !held(q)).collect();
        if tau < dt && !named.is_empty() {
            return Err(IdentifyError::NotIdentifiable {
                parameter: names(&named),
                detail: format!(
                    "the wheels settle faster than one sample: the {motion} motion's mechanical time constant, \
                     {tau:.3e} s with the fitted values (inertia over the {damping} damping), is below the log's \
                     sample period {dt:.3e} s, so the log shows speeds but not the accelerations that carry the \
                     inertia; log faster than every {tau:.1e} s"
                ),
            });
        }
    }
    Ok(())
}

fn names(ps: &[Param]) -> String {
    ps.iter().map(|p| p.key()).collect::<Vec<_>>().join(", ")
}

/// Why a parameter's regressor can vanish.
fn why_zero(q: Param) -> &'static str {
    match q {
        Param::PlatformInertia => "the robot never accelerates its turning (straight-line runs only)",
        Param::Mass | Param::WheelInertia => "the wheels never accelerate",
        Param::CoulombFriction | Param::ViscousFriction | Param::BackEmfConstant => "the wheels never turn",
        Param::TorqueConstant | Param::ArmatureResistance => "the held parameters exert no torque",
    }
}

/// Why a parameter's regressor can be lost in the noise.
fn why_noise(q: Param) -> &'static str {
    match q {
        Param::PlatformInertia => "the log barely accelerates the turning (straight-line runs only?)",
        _ => {
            "its share of the motion is too small for this log's encoder noise (a harder or longer excitation, a finer encoder, or hold it)"
        }
    }
}

/// Why regressors can be dependent, for the pairs the model knows.
fn why_dependent(parts: &[Param], d: f64) -> String {
    let has = |q| parts.contains(&q);
    if has(Param::Mass) && has(Param::WheelInertia) {
        if d == 0.0 {
            " (with com_offset = 0 they enter only as m + 2 I_m / r^2)".to_owned()
        } else {
            " (they are told apart only through the terms in com_offset d: the log needs turning while driving)"
                .to_owned()
        }
    } else if has(Param::ViscousFriction) && has(Param::BackEmfConstant) {
        " (both multiply the wheel speed)".to_owned()
    } else if has(Param::ViscousFriction) && has(Param::CoulombFriction) {
        " (the log needs several wheel speeds)".to_owned()
    } else {
        String::new()
    }
}

fn check_settings(s: &FitSettings) -> Result<(), IdentifyError> {
    let bad =
        |key: &str, detail: &str| Err(IdentifyError::BadSetting { key: key.to_owned(), detail: detail.to_owned() });
    if !(s.half_window_s > 0.0 && s.half_window_s.is_finite()) {
        return bad("half_window_s", "must be > 0 and finite");
    }
    if !(0.0..1.0).contains(&s.still_fraction) {
        return bad("still_fraction", "must be in [0, 1)");
    }
    if !(s.jump_fraction > 0.0) {
        return bad("jump_fraction", "must be > 0");
    }
    if !(s.min_excitation >= 0.0 && s.min_excitation.is_finite()) {
        return bad("min_excitation", "must be >= 0 and finite");
    }
    if !(s.max_condition >= 1.0) {
        return bad("max_condition", "must be >= 1");
    }
    // The geometry and the held values must be a valid robot; the starting values of
    // the fitted parameters do not matter (they are replaced), so they are set to 1 here.
    let mut probe = s.robot;
    let mut motor = s.motor;
    for q in Param::ALL.into_iter().filter(|q| !s.hold.contains(q)) {
        q.set(&mut probe, &mut motor, 1.0);
    }
    probe.validate().map_err(|e| IdentifyError::BadSetting { key: "robot".to_owned(), detail: e.to_string() })?;
    Ok(())
}
