//! Per-run outcome figures, accumulated step by step without allocating.

use crate::Real;
use crate::math::{Pose2, wrap_angle};
use crate::sim::Sample;

/// Distance to the goal (m) below which a run counts as arrived: 1 cm (SPEC section 6).
pub const ARRIVAL_RADIUS_M: f64 = 0.01;

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// Reached t_end with a finite state inside the box.
    Completed,
    /// The next state was not finite; the run stopped at the last finite one.
    NonFinite,
    /// Point C left the 1 km box around the origin.
    LeftBox,
}

impl Termination {
    /// True for the two divergence cases.
    pub fn diverged(self) -> bool {
        !matches!(self, Termination::Completed)
    }
}

/// Outcome of one run. Integrals are left Riemann sums over the plant steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome<T> {
    /// How the run ended.
    pub termination: Termination,
    /// Time of the last state, s (t_end unless diverged).
    pub t_final: T,
    /// Final pose of C.
    pub final_pose: Pose2<T>,
    /// Final distance to the goal position, m.
    pub final_dl: T,
    /// Final heading error wrap(theta_d - theta), rad.
    pub final_heading_error: T,
    /// First time from which dl stays below [`ARRIVAL_RADIUS_M`] to the end, s; `None` if never.
    pub time_to_arrival: Option<T>,
    /// Largest |wheel speed| seen, rad/s.
    pub peak_wheel_speed: T,
    /// Path length of C, m: int |v| dt.
    pub path_length: T,
    /// Mechanical energy the drives put into the wheels, J: int (|tau_r omega_r| + |tau_l omega_l|) dt.
    pub energy: T,
}

/// Accumulates an [`Outcome`] from the samples of every plant step.
#[derive(Clone, Copy, Debug)]
pub struct Metrics<T> {
    goal: Pose2<T>,
    arrival_radius: T,
    arrived_since: Option<T>,
    peak_wheel_speed: T,
    path_length: T,
    energy: T,
}

impl<T: Real> Metrics<T> {
    /// Starts accumulating for a run towards `goal`.
    pub fn new(goal: Pose2<T>) -> Self {
        let z = T::zero();
        Self {
            goal,
            arrival_radius: T::lit(ARRIVAL_RADIUS_M),
            arrived_since: None,
            peak_wheel_speed: z,
            path_length: z,
            energy: z,
        }
    }

    /// Adds the sample at the start of a plant step of length `dt`.
    #[inline(always)]
    pub fn add_step(&mut self, s: &Sample<T>, dt: T) {
        self.observe(s);
        self.path_length = self.path_length + s.state.v.abs() * dt;
        let power = (s.torque.right * s.wheel_speeds.right).abs() + (s.torque.left * s.wheel_speeds.left).abs();
        self.energy = self.energy + power * dt;
    }

    /// Sees a sample's distance and wheel speeds (also for the final sample).
    #[inline(always)]
    pub fn observe(&mut self, s: &Sample<T>) {
        if s.errors.dl < self.arrival_radius {
            if self.arrived_since.is_none() {
                self.arrived_since = Some(s.t);
            }
        } else {
            self.arrived_since = None;
        }
        let w = s.wheel_speeds.right.abs().max(s.wheel_speeds.left.abs());
        self.peak_wheel_speed = self.peak_wheel_speed.max(w);
    }

    /// The outcome, given the last sample and how the run ended.
    pub fn finish(&self, last: &Sample<T>, termination: Termination) -> Outcome<T> {
        let pose = last.state.pose();
        Outcome {
            termination,
            t_final: last.t,
            final_pose: pose,
            final_dl: (self.goal.x - pose.x).hypot_libm(self.goal.y - pose.y),
            final_heading_error: wrap_angle(self.goal.theta - pose.theta),
            time_to_arrival: self.arrived_since,
            peak_wheel_speed: self.peak_wheel_speed,
            path_length: self.path_length,
            energy: self.energy,
        }
    }
}
