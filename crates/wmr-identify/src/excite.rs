//! Excitation: the command profiles a user plays on a robot for a good fit, after WPILib
//! SysId's tests (quasistatic ramps and dynamic steps, each forward and backward) for
//! straight-line and turning motion, plus arcs (one wheel three times the other), which
//! wmr needs to tell the mass from the wheel inertia (docs/identify.md, "Which test
//! excites what").

use wmr_core::{Drive, Pose2, Robot};

use crate::error::IdentifyError;
use crate::sim::simulate;

/// The shape of a test's command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// A ramp from zero at `ramp_per_s` (a fraction of the largest command per second):
    /// slow enough that the acceleration stays small, so friction shows on its own.
    Quasistatic,
    /// A step to `step_fraction` of the largest command: the acceleration shows the inertias.
    Dynamic,
}

/// Which way the wheels are driven.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// Both wheels the same command: straight ahead (v, no omega).
    Linear,
    /// Opposite commands: turning on the spot (omega, no v).
    Turning,
    /// Right wheel the command, left a third of it: driving and turning at once (the
    /// Coriolis and centripetal terms in d).
    Arc,
}

/// One test of a profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Test {
    /// Ramp or step.
    pub shape: Shape,
    /// Straight, turning or arc.
    pub motion: Motion,
    /// +1 forward (counter-clockwise when turning), -1 backward.
    pub direction: f64,
}

/// The settings of `wmr-cli excite`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExciteSettings {
    /// The largest command, N m at the wheel (torque drive) or V (DC motor).
    pub command_max: f64,
    /// The quasistatic ramp's rate, a fraction of `command_max` per second (SysId's default,
    /// 1 V/s on a 12 V robot, is 0.083).
    pub ramp_per_s: f64,
    /// The dynamic step, a fraction of `command_max` (SysId's 7 V on 12 V: 0.58).
    pub step_fraction: f64,
    /// How long each quasistatic test runs, s.
    pub quasistatic_s: f64,
    /// How long each dynamic test runs, s.
    pub dynamic_s: f64,
    /// Sample period of the profile, s.
    pub dt_s: f64,
}

impl ExciteSettings {
    /// SysId's shape for a largest command of `command_max`: a ramp of 1/12 of it per
    /// second for 6 s, a step of 7/12 of it for 2 s, at 100 Hz.
    pub fn new(command_max: f64) -> Self {
        Self {
            command_max,
            ramp_per_s: 1.0 / 12.0,
            step_fraction: 7.0 / 12.0,
            quasistatic_s: 6.0,
            dynamic_s: 2.0,
            dt_s: 0.01,
        }
    }

    /// Refuses a setting that is not finite and positive, naming it.
    pub fn check(&self) -> Result<(), IdentifyError> {
        for (key, v) in [
            ("command_max", self.command_max),
            ("ramp_per_s", self.ramp_per_s),
            ("step_fraction", self.step_fraction),
            ("quasistatic_s", self.quasistatic_s),
            ("dynamic_s", self.dynamic_s),
            ("dt_s", self.dt_s),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(IdentifyError::BadSetting {
                    key: key.to_owned(),
                    detail: format!("must be > 0 and finite, got {v}"),
                });
            }
        }
        Ok(())
    }
}

impl Test {
    /// Every test, in the order a user runs them: quasistatic then dynamic; linear,
    /// turning, arc; forward then backward.
    pub fn all() -> Vec<Test> {
        let mut out = Vec::new();
        for shape in [Shape::Quasistatic, Shape::Dynamic] {
            for motion in [Motion::Linear, Motion::Turning, Motion::Arc] {
                for direction in [1.0, -1.0] {
                    out.push(Test { shape, motion, direction });
                }
            }
        }
        out
    }

    /// Its name, e.g. `quasistatic-linear-forward`.
    pub fn name(&self) -> String {
        let shape = match self.shape {
            Shape::Quasistatic => "quasistatic",
            Shape::Dynamic => "dynamic",
        };
        let motion = match self.motion {
            Motion::Linear => "linear",
            Motion::Turning => "turning",
            Motion::Arc => "arc",
        };
        let dir = if self.direction > 0.0 { "forward" } else { "backward" };
        format!("{shape}-{motion}-{dir}")
    }

    /// How long it runs, s.
    pub fn duration_s(&self, s: &ExciteSettings) -> f64 {
        match self.shape {
            Shape::Quasistatic => s.quasistatic_s,
            Shape::Dynamic => s.dynamic_s,
        }
    }

    /// The right, left command at `t` s into the test (N m or V).
    pub fn command(&self, t: f64, s: &ExciteSettings) -> [f64; 2] {
        let c = self.direction
            * s.command_max
            * match self.shape {
                Shape::Quasistatic => (s.ramp_per_s * t).min(1.0),
                Shape::Dynamic => s.step_fraction,
            };
        match self.motion {
            Motion::Linear => [c, c],
            Motion::Turning => [c, -c],
            Motion::Arc => [c, c / 3.0],
        }
    }

    /// The test's stamps (every `dt_s` from 0) and commands.
    pub fn profile(&self, s: &ExciteSettings) -> (Vec<f64>, [Vec<f64>; 2]) {
        let n = (self.duration_s(s) / s.dt_s).round() as usize + 1;
        let t: Vec<f64> = (0..n).map(|k| k as f64 * s.dt_s).collect();
        let mut c = [Vec::with_capacity(n), Vec::with_capacity(n)];
        for &tk in &t {
            let [r, l] = self.command(tk, s);
            c[0].push(r);
            c[1].push(l);
        }
        (t, c)
    }

    /// The room the test needs on `robot` with `drive`: the farthest C gets from its
    /// start, m (simulated from rest; a real robot with more friction needs less), plus
    /// the wheel's reach beyond C (half_track) for the turning ones.
    pub fn safe_distance_m(
        &self,
        s: &ExciteSettings,
        robot: Robot<f64>,
        drive: Drive<f64>,
    ) -> Result<f64, IdentifyError> {
        let (t, c) = self.profile(s);
        let sim = simulate(robot, drive, Pose2::new(0.0, 0.0, 0.0), &t, [&c[0], &c[1]])?;
        let far = sim.pose[0].iter().zip(&sim.pose[1]).map(|(x, y)| x.hypot(*y)).fold(0.0f64, f64::max);
        Ok(far + robot.params().half_track)
    }
}
