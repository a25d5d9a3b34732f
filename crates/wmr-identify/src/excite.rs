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

/// The body twist that stands for the test on a base driven by `/cmd_vel` (its own wheel
/// speed loop) instead of by wheel commands: each wheel's rim speed, m/s, is
/// `speed_max_m_s` times its command over `command_max` (a quasistatic ramp becomes a slow
/// speed ramp, a dynamic step a speed step the base accelerates to as hard as it can),
/// and the twist is the differential drive's of those rim speeds:
/// `v = (w_r + w_l) / 2` (m/s, along base_link's x) and `omega = (w_r - w_l) / (2 R)`
/// (rad/s, about z, counter-clockwise; REP 103), R = `half_track_m`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwistProfile {
    /// The rim speed a wheel gets at the largest command, m/s.
    pub speed_max_m_s: f64,
    /// Half the distance between the wheels, m.
    pub half_track_m: f64,
}

impl TwistProfile {
    /// Refuses a speed that is not finite and positive, naming it (`speed_max`).
    pub fn check(&self) -> Result<(), IdentifyError> {
        for (key, v) in [("speed_max", self.speed_max_m_s), ("half_track", self.half_track_m)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(IdentifyError::BadSetting {
                    key: key.to_owned(),
                    detail: format!("must be > 0 and finite, got {v}"),
                });
            }
        }
        Ok(())
    }

    /// (v m/s, omega rad/s) for the right, left commands `c` (N m or V) of settings `s`.
    pub fn twist(&self, c: [f64; 2], s: &ExciteSettings) -> [f64; 2] {
        let w_r = self.speed_max_m_s * c[0] / s.command_max;
        let w_l = self.speed_max_m_s * c[1] / s.command_max;
        [0.5 * (w_r + w_l), (w_r - w_l) / (2.0 * self.half_track_m)]
    }

    /// The test's stamps (every `dt_s` from 0) and twists (v, omega), then one zero twist
    /// `dt_s` after the last, so the base is told to stop rather than left to its
    /// command timeout.
    pub fn profile(&self, test: &Test, s: &ExciteSettings) -> (Vec<f64>, [Vec<f64>; 2]) {
        let (mut t, c) = test.profile(s);
        let n = t.len();
        let mut out = [Vec::with_capacity(n + 1), Vec::with_capacity(n + 1)];
        for i in 0..n {
            let [v, omega] = self.twist([c[0][i], c[1][i]], s);
            out[0].push(v);
            out[1].push(omega);
        }
        t.push(n as f64 * s.dt_s);
        out[0].push(0.0);
        out[1].push(0.0);
        (t, out)
    }

    /// The room the test needs on a base that follows the twists exactly (each held for
    /// one step, integrated in closed form on its arc): the farthest C gets from its
    /// start at a sample, m, plus the wheel's reach beyond C (`half_track_m`).
    pub fn safe_distance_m(&self, test: &Test, s: &ExciteSettings) -> f64 {
        let (t, tw) = self.profile(test, s);
        let (mut x, mut y, mut theta) = (0.0f64, 0.0f64, 0.0f64);
        let mut far = 0.0f64;
        for i in 0..t.len().saturating_sub(1) {
            let dt = t[i + 1] - t[i];
            let (v, omega) = (tw[0][i], tw[1][i]);
            let dtheta = omega * dt;
            if dtheta.abs() > 1e-12 {
                // On the arc of radius v / omega: exact.
                x += v / omega * ((theta + dtheta).sin() - theta.sin());
                y -= v / omega * ((theta + dtheta).cos() - theta.cos());
            } else {
                x += v * dt * theta.cos();
                y += v * dt * theta.sin();
            }
            theta += dtheta;
            far = far.max(x.hypot(y));
        }
        far + self.half_track_m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The twists against the differential drive's kinematics by hand: straight tests
    /// have no omega, turning ones no v, arcs (left a third of the right) v = 2/3 w_r and
    /// omega = w_r / (3 R), a circle of radius 2 R.
    #[test]
    fn twists_are_the_rim_speeds_kinematics() {
        let s = ExciteSettings::new(12.0);
        let p = TwistProfile { speed_max_m_s: 0.6, half_track_m: 0.2 };
        let step = 0.6 * 7.0 / 12.0;
        let at = |motion, direction| {
            let test = Test { shape: Shape::Dynamic, motion, direction };
            p.twist(test.command(1.0, &s), &s)
        };
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-15 && (a[1] - b[1]).abs() < 1e-15;
        assert!(close(at(Motion::Linear, -1.0), [-step, 0.0]));
        assert!(close(at(Motion::Turning, 1.0), [0.0, step / 0.2]));
        assert!(close(at(Motion::Arc, 1.0), [2.0 / 3.0 * step, step / 0.6]));
    }

    /// A straight ramp's room: the sum of v dt over the held steps, v_k = speed_max *
    /// ramp_per_s * k dt (a closed form: speed_max * ramp * dt^2 * n (n - 1) / 2 for n
    /// samples), plus half the track; the profile ends on a zero twist.
    #[test]
    fn a_straight_ramps_room_is_its_travel() {
        let s = ExciteSettings::new(5.0);
        let p = TwistProfile { speed_max_m_s: 0.5, half_track_m: 0.15 };
        let test = Test { shape: Shape::Quasistatic, motion: Motion::Linear, direction: 1.0 };
        let (t, tw) = p.profile(&test, &s);
        let n = (s.quasistatic_s / s.dt_s).round() + 1.0;
        assert_eq!(t.len() as f64, n + 1.0);
        assert_eq!((tw[0][t.len() - 1], tw[1][t.len() - 1]), (0.0, 0.0));
        let travel = 0.5 * s.ramp_per_s * s.dt_s * s.dt_s * n * (n - 1.0) / 2.0;
        let d = p.safe_distance_m(&test, &s);
        assert!((d - (travel + 0.15)).abs() < 1e-12, "{d} against {}", travel + 0.15);
        // An arc turning past half a circle (here 6.7 rad) reaches the far side of its
        // circle: 2 x 2 R, plus R.
        let fast = TwistProfile { speed_max_m_s: 2.0, ..p };
        let arc = Test { shape: Shape::Quasistatic, motion: Motion::Arc, direction: 1.0 };
        let d = fast.safe_distance_m(&arc, &s);
        assert!((d - 5.0 * 0.15).abs() < 1e-3, "{d}");
    }
}
