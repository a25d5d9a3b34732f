//! A run's samples as ROS 2 messages (CDR), one [`Ros2RunEncoder`] per run.
//!
//! Frames (REP 105): `map -> odom -> base_link`. `odom -> base_link` is the pose the
//! controller used at its last tick (the `measured` pose: the sensor's, the fused pose on
//! odometry, the true pose without a `[sensor]`); `map -> odom` is then chosen so that
//! `map -> base_link` is the true pose of C. `base_link` is C on the ground, x forward, y
//! left (REP 103); the wheels turn about y at `(0, +-half_track, wheel_radius)`.

use wmr_core::{Pose2, Reference, RobotParams, Sample};
use wmr_scenario::{Columns, RunSpec, SimSpec};

use super::cdr::CdrWriter;
use super::topics::{MAP_FRAME, Topic, frame};
use crate::foxglove_topics::{LogClock, MAX_REFERENCE_SAMPLES};
use wmr_scenario::urdf::{Geometry, JOINT_NAMES};

/// The frames of one run.
struct Frames {
    odom: String,
    base_link: String,
    wheel_left: String,
    wheel_right: String,
    caster: String,
}

/// Encodes one run's ROS 2 messages.
pub struct Ros2RunEncoder {
    clock: LogClock,
    columns: Columns,
    frames: Frames,
    geometry: Geometry,
    goal: Pose2<f64>,
    /// The reference's poses on the log grid (tracking runs), until sent at the first sample.
    plan: Option<Vec<Pose2<f64>>>,
    /// The robot's URDF, for `robot_description`.
    robot_description: String,
    first: bool,
    buf: Vec<u8>,
}

/// (x, y, z, w) of a rotation by `angle` (rad) about z.
fn yaw_quaternion(angle: f64) -> [f64; 4] {
    let h = 0.5 * angle;
    [0.0, 0.0, h.sin(), h.cos()]
}

/// (x, y, z, w) of a rotation by `angle` (rad) about y.
fn pitch_quaternion(angle: f64) -> [f64; 4] {
    let h = 0.5 * angle;
    [0.0, h.sin(), 0.0, h.cos()]
}

/// `map -> odom` such that `map -> odom -> base_link` is `truth` when `odom -> base_link`
/// is `used`: truth * used^-1 (x, y, yaw).
pub fn map_to_odom(truth: Pose2<f64>, used: Pose2<f64>) -> Pose2<f64> {
    let yaw = truth.theta - used.theta;
    let (s, c) = yaw.sin_cos();
    Pose2::new(truth.x - (c * used.x - s * used.y), truth.y - (s * used.x + c * used.y), yaw)
}

fn header(w: &mut CdrWriter, ns: u64, frame_id: &str) {
    w.time(ns);
    w.string(frame_id);
}

fn transform(w: &mut CdrWriter, ns: u64, parent: &str, child: &str, t: [f64; 3], q: [f64; 4]) {
    header(w, ns, parent);
    w.string(child);
    w.f64_array(&t);
    w.f64_array(&q);
}

fn pose(w: &mut CdrWriter, p: Pose2<f64>) {
    w.f64_array(&[p.x, p.y, 0.0]);
    w.f64_array(&yaw_quaternion(p.theta));
}

impl Ros2RunEncoder {
    /// The encoder of run `run` of `runs` (`spec`), robot `robot`, simulated with `sim`,
    /// whose samples carry `columns`; `robot_description` is the robot's URDF.
    pub fn new(
        run: usize,
        runs: usize,
        spec: &RunSpec,
        robot: &RobotParams<f64>,
        columns: Columns,
        sim: &SimSpec,
        robot_description: String,
    ) -> Self {
        // The reference at the samples' times (plant step k * log_every on the loop's clock), evenly thinned as the Foxglove drawing is.
        let plan = columns.reference.as_ref().map(|reference| {
            let every = u64::from(sim.log_every());
            let clock = wmr_core::StepClock::new(sim.dt());
            let pose = |k: u64| reference.state_at(clock.time((k * every).min(sim.n_steps()))).pose;
            let n = sim.n_samples();
            let stride = n.div_ceil(MAX_REFERENCE_SAMPLES).max(1);
            let mut poses: Vec<_> = (0..n).step_by(usize::try_from(stride).unwrap_or(usize::MAX)).map(pose).collect();
            if n > 0 && !(n - 1).is_multiple_of(stride) {
                poses.push(pose(n - 1));
            }
            poses
        });
        let f = |name: &str| frame(run, runs, name);
        Self {
            clock: LogClock::new(sim.dt()),
            columns,
            frames: Frames {
                odom: f("odom"),
                base_link: f("base_link"),
                wheel_left: f("wheel_left_link"),
                wheel_right: f("wheel_right_link"),
                caster: f("caster_link"),
            },
            geometry: Geometry::of(robot),
            goal: spec.goal,
            plan,
            robot_description,
            first: true,
            buf: Vec::with_capacity(1024),
        }
    }

    /// Encodes sample `s`, handing each message to `out(topic, log time ns, bytes)`.
    pub fn sample<E>(
        &mut self,
        s: &Sample<f64>,
        out: &mut impl FnMut(Topic, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        let ns = self.clock.nanos(s.t);
        if self.first {
            self.first = false;
            self.send_once(ns, out)?;
        }
        let truth = s.state.pose();
        let used = s.measured;
        let fr = &self.frames;
        let g = &self.geometry;

        let mut w = CdrWriter::new(&mut self.buf);
        w.len(4);
        let m = map_to_odom(truth, used);
        transform(&mut w, ns, MAP_FRAME, &fr.odom, [m.x, m.y, 0.0], yaw_quaternion(m.theta));
        transform(&mut w, ns, &fr.odom, &fr.base_link, [used.x, used.y, 0.0], yaw_quaternion(used.theta));
        let wheel = g.wheel_z;
        transform(
            &mut w,
            ns,
            &fr.base_link,
            &fr.wheel_left,
            [0.0, g.half_track, wheel],
            pitch_quaternion(s.state.phi_l),
        );
        transform(
            &mut w,
            ns,
            &fr.base_link,
            &fr.wheel_right,
            [0.0, -g.half_track, wheel],
            pitch_quaternion(s.state.phi_r),
        );
        out(Topic::Tf, ns, &self.buf)?;

        let mut w = CdrWriter::new(&mut self.buf);
        header(&mut w, ns, &fr.odom);
        w.string(&fr.base_link);
        pose(&mut w, used);
        w.f64_array(&pose_covariance(s.pose_covariance));
        // The true body twist: v forward, v_lat to the left (slip runs), omega about z.
        let v_lat = if self.columns.contact { s.contact.v_lat } else { 0.0 };
        w.f64_array(&[s.state.v, v_lat, 0.0, 0.0, 0.0, s.state.omega]);
        w.f64_array(&[0.0; 36]);
        out(Topic::Odom, ns, &self.buf)?;

        let mut w = CdrWriter::new(&mut self.buf);
        header(&mut w, ns, "");
        w.len(2);
        w.string(JOINT_NAMES[0]);
        w.string(JOINT_NAMES[1]);
        w.f64_seq(&[s.state.phi_l, s.state.phi_r]);
        w.f64_seq(&[s.wheel_speeds.left, s.wheel_speeds.right]);
        w.f64_seq(&[s.torque.left, s.torque.right]);
        out(Topic::JointStates, ns, &self.buf)?;

        if self.columns.command {
            // The twist the law demanded (geometry_msgs/TwistStamped, base_link).
            let [v, omega] = wmr_scenario::command_values(s);
            let mut w = CdrWriter::new(&mut self.buf);
            header(&mut w, ns, &fr.base_link);
            w.f64_array(&[v, 0.0, 0.0, 0.0, 0.0, omega]);
            out(Topic::CmdVel, ns, &self.buf)?;
        }

        let mut w = CdrWriter::new(&mut self.buf);
        header(&mut w, ns, MAP_FRAME);
        w.f64_array(&all_values(s, &self.columns));
        out(Topic::Sample, ns, &self.buf)
    }

    /// The messages sent once, at the first sample: `robot_description`, `tf_static`, the
    /// goal, the plan.
    fn send_once<E>(&mut self, ns: u64, out: &mut impl FnMut(Topic, u64, &[u8]) -> Result<(), E>) -> Result<(), E> {
        let mut w = CdrWriter::new(&mut self.buf);
        w.string(&self.robot_description);
        out(Topic::RobotDescription, ns, &self.buf)?;

        let fr = &self.frames;
        let g = &self.geometry;
        let mut w = CdrWriter::new(&mut self.buf);
        w.len(1);
        transform(&mut w, ns, &fr.base_link, &fr.caster, [g.caster_x, 0.0, g.caster_z], [0.0, 0.0, 0.0, 1.0]);
        out(Topic::TfStatic, ns, &self.buf)?;

        let mut w = CdrWriter::new(&mut self.buf);
        header(&mut w, ns, MAP_FRAME);
        pose(&mut w, self.goal);
        out(Topic::GoalPose, ns, &self.buf)?;

        if let Some(plan) = self.plan.take() {
            let mut w = CdrWriter::new(&mut self.buf);
            header(&mut w, ns, MAP_FRAME);
            w.len(plan.len());
            for p in plan {
                header(&mut w, ns, MAP_FRAME);
                pose(&mut w, p);
            }
            out(Topic::Plan, ns, &self.buf)?;
        }
        Ok(())
    }
}

/// The 6x6 row-major covariance of a `geometry_msgs/PoseWithCovariance` (x, y, z, roll,
/// pitch, yaw) from the EKF's of (x, y, theta): its nine entries at rows and columns 0, 1
/// and 5; z, roll and pitch zero (the planar model knows them exactly). All zeros (ROS's
/// "unknown") for a sensor without an estimate (no odometry).
pub fn pose_covariance(cov: Option<[[f64; 3]; 3]>) -> [f64; 36] {
    let mut out = [0.0; 36];
    if let Some(c) = cov {
        const AT: [usize; 3] = [0, 1, 5];
        for (i, row) in c.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                out[6 * AT[i] + AT[j]] = *v;
            }
        }
    }
    out
}

/// The number of fields of `wmr_msgs/Sample` after its header: every CSV column of every group.
pub const SAMPLE_FIELDS: usize = wmr_scenario::SAMPLE_COLUMNS.len()
    + wmr_scenario::MEASURED_COLUMNS.len()
    + wmr_scenario::ODOMETRY_COLUMNS.len()
    + wmr_scenario::CONTACT_COLUMNS.len()
    + wmr_scenario::REFERENCE_COLUMNS.len()
    + wmr_scenario::COMMAND_COLUMNS.len()
    + wmr_scenario::DISTURBANCE_COLUMNS.len();

/// Every field of `wmr_msgs/Sample`: the CSV columns of every group in order, NaN for the
/// groups `columns` does not carry.
fn all_values(s: &Sample<f64>, columns: &Columns) -> [f64; SAMPLE_FIELDS] {
    let mut out = [f64::NAN; SAMPLE_FIELDS];
    let mut at = 0;
    let mut put = |on: bool, values: &[f64]| {
        if on {
            out[at..at + values.len()].copy_from_slice(values);
        }
        at += values.len();
    };
    put(true, &wmr_scenario::sample_values(s));
    put(columns.measured, &wmr_scenario::measured_values(s));
    put(columns.odometry, &wmr_scenario::odometry_values(s));
    put(columns.contact, &wmr_scenario::contact_values(s));
    match &columns.reference {
        Some(r) => put(true, &wmr_scenario::reference_values(&r.state_at(s.t))),
        None => put(false, &[0.0; 5]),
    }
    put(columns.command, &wmr_scenario::command_values(s));
    put(columns.disturbance, &wmr_scenario::disturbance_values(s));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_to_odom_composes_with_the_used_pose_to_the_truth() {
        let truth = Pose2::new(1.0, -2.0, 0.7);
        let used = Pose2::new(1.1, -1.9, 0.65);
        let m = map_to_odom(truth, used);
        let (s, c) = m.theta.sin_cos();
        let x = m.x + c * used.x - s * used.y;
        let y = m.y + s * used.x + c * used.y;
        assert!((x - truth.x).abs() < 1e-15 && (y - truth.y).abs() < 1e-15);
        assert!((m.theta + used.theta - truth.theta).abs() < 1e-15);
        let same = map_to_odom(truth, truth);
        assert!(same.x.abs() < 1e-15 && same.y.abs() < 1e-15 && same.theta == 0.0);
    }
}
