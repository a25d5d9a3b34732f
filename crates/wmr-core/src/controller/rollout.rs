//! The dynamic model MPPI's rollouts predict with (`motion_model = "dynamic"`): the
//! controller's robot ((15), with its friction), the drive it commands (torque, voltage
//! and current limits, back-EMF) and the wheel stage's speed limit, stepped for
//! [`ROLLOUT_LANES`] samples at once in SIMD lanes ([`crate::lane`]).
//!
//! # The model, per sub-step of h = model_dt / `rollout_substeps`
//!
//! The wheel stage's servos track wheel speed references at 1 kHz: over a sub-step of
//! several control periods they reach them unless the drive cannot give the torque. So the
//! model is the wheel stage as an ideal speed loop bounded by what the drive can do at
//! the wheel's speed, the dynamics (15) doing the rest:
//!
//! ```text
//! w_i   = (v +- R omega) / r                                  wheel speeds, rad/s
//! wd_i  = s (v_d +- R omega_d) / r                            references; s <= 1 keeps both within
//!                                                             wheel_speed_max with the curvature kept
//! a_i   = (wd_i - w_i) / h                                    wheel accelerations that reach them in h
//! v'_d  = r (a_r + a_l) / 2,  omega'_d = r (a_r - a_l) / (2 R)
//! net_r + net_l = r (M_r11 v'_d - m d omega^2)                (15) solved for the torques
//! net_r - net_l = (r / R) (M_r22 omega'_d + m d v omega)
//! tau_i = net_i + f(w_i)                                      plus the friction it overcomes
//! tau_i <- clamp(tau_i, drive torque at -u_max and w_i, drive torque at +u_max and w_i)
//! (v', omega') = (15) under tau_i                             the plant's own derivative
//! v += h v',  omega += h omega'                               then the pose on the mean twist:
//! theta_mid = theta + h (omega_0 + omega_1) / 4
//! x += h (v_0 + v_1) / 2 cos(theta_mid),  y likewise,  theta += h (omega_0 + omega_1) / 2
//! ```
//!
//! Where the drive has the torque, the model's speeds are the references after one
//! sub-step (the kinematic model without acceleration clamps: `tests/mppi.rs` checks the
//! closed form); where it has not (a DC motor near its no-load speed, the current limit,
//! a heavy robot), the speeds lag as the robot's would, so the acceleration limits are the
//! robot's own and differ between speeding up, slowing down and turning.
//!
//! The rollouts run in `f64` lanes whatever the law's number type (one answer for the
//! CLI, Python and C; on the Cortex-M4F, whose FPU is single precision, they are
//! software doubles: its MPPI uses the kinematic model). The lanes' sin and cos are
//! [`crate::lane::Lanes`]' own: deterministic, not `libm`'s.

use crate::Real;
use crate::RobotParams;
use crate::drive::{Drive, DriveParams};
use crate::dynamics::Model;
use crate::error::ParamError;
use crate::lane::{Lane, Lanes};
use crate::math::{Pose2, Twist2, Wheels};
use crate::state::State;

/// Samples a rollout steps at once: 8 `f64`, one AVX-512 register or two AVX2. On a
/// microcontroller (`target_os = "none"`: no vector unit, and doubles in software) one, so
/// the code is an eighth; every lane computes alone, so the results are the same bits.
#[cfg(not(target_os = "none"))]
pub const ROLLOUT_LANES: usize = 8;
/// Samples a rollout steps at once (see the host's definition): one on a microcontroller.
#[cfg(target_os = "none")]
pub const ROLLOUT_LANES: usize = 1;

/// [`ROLLOUT_LANES`] numbers of `f64`, one per sample.
pub type Wide = Lanes<ROLLOUT_LANES>;

/// The controller's robot, drive and wheel speed limit, ready to roll out (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DynamicModel {
    model: Model<f64>,
    drive: Drive<f64>,
    /// r, R (m), 1 / r (1/m).
    r: f64,
    big_r: f64,
    inv_r: f64,
    /// M_r11 (kg), M_r22 (kg m^2), m d (kg m).
    m11: f64,
    m22: f64,
    md: f64,
    /// The wheel stage's speed limit, rad/s (infinite: none).
    wheel_speed_max: f64,
    /// The drive's largest command (N m or V).
    command_limit: f64,
    /// Sub-steps per model step, and their length h (s).
    substeps: u32,
    h: f64,
}

/// Casts a drive's parameters to `f64`.
fn drive_f64<T: Real>(d: &DriveParams<T>) -> DriveParams<f64> {
    match d {
        DriveParams::Torque(p) => DriveParams::Torque(p.cast()),
        DriveParams::DcMotor(p) => DriveParams::DcMotor(p.cast()),
    }
}

impl DynamicModel {
    /// The model of `robot` driven by `drive` with the wheel stage's `wheel_speed_max`
    /// (rad/s, infinite: none), stepped `substeps` times per `model_dt` (s). Errors name
    /// the robot's or the drive's key.
    pub fn new<T: Real>(
        robot: &RobotParams<T>,
        drive: &DriveParams<T>,
        wheel_speed_max: T,
        model_dt: T,
        substeps: u32,
    ) -> Result<Self, ParamError> {
        let robot = robot.cast::<f64>().validate()?;
        let drive = drive_f64(drive).validate(&robot)?;
        let p = *robot.params();
        let (m11, m22) = robot.reduced_inertia();
        let n = substeps.max(1);
        Ok(Self {
            model: Model::new(&robot),
            drive,
            r: p.wheel_radius,
            big_r: p.half_track,
            inv_r: 1.0 / p.wheel_radius,
            m11,
            m22,
            md: robot.mass_offset(),
            wheel_speed_max: wheel_speed_max.to_f64_lossless(),
            command_limit: drive.command_limit(),
            substeps: n,
            h: model_dt.to_f64_lossless() / f64::from(n),
        })
    }

    /// Rolls [`ROLLOUT_LANES`] samples out from `pose` (world frame) at the speed
    /// `speed` (m/s, rad/s, measured) over `demand.len()` model steps: step i is driven by
    /// the twist demand `demand(i)` (m/s, rad/s, one per lane). Calls
    /// `visit(i, pose_i, twist_i)` with the pose and the twist at the end of step i.
    #[inline(always)]
    pub fn rollout(
        &self,
        pose: Pose2<f64>,
        speed: Twist2<f64>,
        steps: usize,
        demand: impl Fn(usize) -> Twist2<Wide>,
        visit: impl FnMut(usize, Pose2<Wide>, Twist2<Wide>),
    ) {
        if self.model.has_coulomb() {
            self.rollout_with::<true>(pose, speed, steps, demand, visit);
        } else {
            self.rollout_with::<false>(pose, speed, steps, demand, visit);
        }
    }

    // One copy on the firmware (soft doubles: eight lanes of calls), inlined on hosts.
    #[cfg_attr(target_os = "none", inline(never))]
    #[cfg_attr(not(target_os = "none"), inline(always))]
    fn rollout_with<const COULOMB: bool>(
        &self,
        pose: Pose2<f64>,
        speed: Twist2<f64>,
        steps: usize,
        demand: impl Fn(usize) -> Twist2<Wide>,
        mut visit: impl FnMut(usize, Pose2<Wide>, Twist2<Wide>),
    ) {
        let mut s = State {
            x: Wide::splat(pose.x),
            y: Wide::splat(pose.y),
            theta: Wide::splat(pose.theta),
            v: Wide::splat(speed.v),
            omega: Wide::splat(speed.omega),
            phi_r: Wide::default(),
            phi_l: Wide::default(),
        };
        for i in 0..steps {
            let d = demand(i);
            let (w_r, w_l) = self.references(d);
            for _ in 0..self.substeps {
                s = self.substep::<COULOMB>(&s, w_r, w_l);
            }
            visit(i, Pose2 { x: s.x, y: s.y, theta: s.theta }, Twist2 { v: s.v, omega: s.omega });
        }
    }

    /// The wheel speed references (rad/s) of a twist demand, scaled together into the
    /// wheel stage's speed limit (the curvature kept).
    #[inline(always)]
    fn references(&self, d: Twist2<Wide>) -> (Wide, Wide) {
        let (big_r, inv_r) = (Wide::splat(self.big_r), Wide::splat(self.inv_r));
        let w_r = (d.v + big_r * d.omega) * inv_r;
        let w_l = (d.v - big_r * d.omega) * inv_r;
        if !self.wheel_speed_max.is_finite() {
            return (w_r, w_l);
        }
        let fastest = w_r.abs().max(w_l.abs());
        let limit = Wide::splat(self.wheel_speed_max);
        let scale = Wide::select(limit.lt(fastest), limit / fastest, Wide::splat(1.0));
        (w_r * scale, w_l * scale)
    }

    /// One sub-step of h towards the wheel speed references `w_r`, `w_l` (module docs).
    #[inline(always)]
    fn substep<const COULOMB: bool>(&self, s: &State<Wide>, ref_r: Wide, ref_l: Wide) -> State<Wide> {
        let (r, big_r, inv_r) = (Wide::splat(self.r), Wide::splat(self.big_r), Wide::splat(self.inv_r));
        let half = Wide::splat(0.5);
        let h = Wide::splat(self.h);
        let inv_h = Wide::splat(1.0 / self.h);
        let md = Wide::splat(self.md);
        let w_r = (s.v + big_r * s.omega) * inv_r;
        let w_l = (s.v - big_r * s.omega) * inv_r;
        let (a_r, a_l) = ((ref_r - w_r) * inv_h, (ref_l - w_l) * inv_h);
        let v_dot = r * (a_r + a_l) * half;
        let omega_dot = r * (a_r - a_l) * half * Wide::splat(1.0 / self.big_r);
        let sum = r * (Wide::splat(self.m11) * v_dot - md * s.omega * s.omega);
        let diff = Wide::splat(self.r / self.big_r) * (Wide::splat(self.m22) * omega_dot + md * s.v * s.omega);
        let tau_r = (sum + diff) * half + self.model.friction_torque_with::<Wide, COULOMB>(w_r);
        let tau_l = (sum - diff) * half + self.model.friction_torque_with::<Wide, COULOMB>(w_l);
        let tau = Wheels::new(self.clamp_torque(tau_r, w_r), self.clamp_torque(tau_l, w_l));
        // The heading's sin and cos do not enter (15) on flat ground.
        let d = self.model.derivative_at_heading::<Wide, COULOMB, false>(s, tau, (Wide::default(), Wide::default()));
        let v = s.v + h * d.v;
        let omega = s.omega + h * d.omega;
        let turn = h * (s.omega + omega) * half;
        let (sin, cos) = (s.theta + turn * half).sin_cos();
        let ds = h * (s.v + v) * half;
        State { x: s.x + ds * cos, y: s.y + ds * sin, theta: s.theta + turn, v, omega, phi_r: s.phi_r, phi_l: s.phi_l }
    }

    /// `tau` (N m) within what the drive gives at wheel speed `w` (rad/s): its torque at
    /// the largest command either way (a DC motor's falls with the speed: back-EMF, and
    /// is cut by the current limit).
    #[inline(always)]
    fn clamp_torque(&self, tau: Wide, w: Wide) -> Wide {
        let u = Wide::splat(self.command_limit);
        let hi = self.drive.wheel_torque(u, w);
        let lo = self.drive.wheel_torque(-u, w);
        tau.max(lo).min(hi)
    }
}
