//! MPPI's plans in an MCAP file (`/runN/mppi/optimal`, `/runN/mppi/rollouts`).
//!
//! The run's samples do not carry the law's state, so the view steps its own copy of the
//! run's closed loop (built as the run's: the same steps, bit for bit) in step with the
//! samples handed to the file, and reads the law after every planning cycle:
//!
//! - `mppi/optimal` (`foxglove.PosesInFrame`, world frame), every cycle: the measured pose
//!   the plan read, then the poses of the sequence the law just chose (u_1 first, after
//!   nav2's shift) rolled out on the law's own model ([`wmr_core::controller::mppi::MppiLaw::predict`]),
//!   one per `model_dt`: `time_steps + 1` poses.
//! - `mppi/rollouts` (`foxglove.SceneUpdate`, entity `rollouts`), every
//!   [`MPPI_ROLLOUTS_EVERY`] cycles: samples 0 .. [`MPPI_ROLLOUTS_DRAWN`] of the cycle's
//!   first iteration, rolled out as the plan rolls them
//!   ([`wmr_core::controller::mppi::MppiLaw::sampled_rollout`]), as line strips in the run's colour.
//!
//! The cost: the law planned twice, the run's and the view's (an MCAP of an MPPI law only).

use foxglove::messages::{
    LinePrimitive, Point3, Pose, PosesInFrame, SceneEntity, SceneUpdate, Vector3, line_primitive,
};
use wmr_core::controller::mppi::MppiLaw;
use wmr_core::{AnyLaw, Pose2};
use wmr_scenario::{RunLoop, Scenario, SinkError};

use super::clock::{LogClock, stamp};
use super::colour::run_color;
use super::topics::{Kind, MPPI_ROLLOUTS_DRAWN, MPPI_ROLLOUTS_EVERY, WORLD_FRAME};

/// The entity id of the drawn rollouts.
pub const ROLLOUTS_ENTITY: &str = "rollouts";

/// Line width of a drawn rollout, screen pixels.
const ROLLOUT_WIDTH_PX: f64 = 1.0;

/// Opacity of a drawn rollout.
const ROLLOUT_ALPHA: f64 = 0.35;

fn pose(p: Pose2<f64>) -> Pose {
    let h = 0.5 * p.theta;
    Pose {
        position: Some(Vector3 { x: p.x, y: p.y, z: 0.0 }),
        orientation: Some(foxglove::messages::Quaternion { x: 0.0, y: 0.0, z: h.sin(), w: h.cos() }),
    }
}

fn mppi(lp: &RunLoop) -> Option<&MppiLaw<f64>> {
    match lp.controller().law() {
        AnyLaw::Mppi(law) => Some(law),
        _ => None,
    }
}

/// One run's plans, read from a copy of its loop.
pub struct MppiView {
    run: usize,
    lp: RunLoop,
    clock: LogClock,
    /// Cycles written.
    cycles: u64,
    started: bool,
    poses: Vec<Pose2<f64>>,
    buf: Vec<u8>,
}

impl MppiView {
    /// The view of run `run` of `scenario`, whose law must be MPPI; `None` otherwise.
    pub fn new(scenario: &Scenario, run: usize) -> Result<Option<Self>, SinkError> {
        let lp = scenario.closed_loop(run).map_err(|e| SinkError::from(e.to_string()))?;
        let Some(law) = mppi(&lp) else { return Ok(None) };
        let n = law.params().time_steps as usize + 1;
        Ok(Some(Self {
            run,
            lp,
            clock: LogClock::new(scenario.sim().dt()),
            cycles: 0,
            started: false,
            poses: vec![Pose2::new(0.0, 0.0, 0.0); n],
            buf: Vec::with_capacity(8192),
        }))
    }

    /// Steps the view's loop up to time `t` (s; a sample's time), handing the messages of
    /// every plan on the way (and the one at t = 0) to `out(kind, log time ns, bytes)`.
    pub fn advance_to<E>(&mut self, t: f64, out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>) -> Result<(), E> {
        if !self.started {
            self.started = true;
            self.cycles = mppi(&self.lp).map_or(0, |law| law.cycles(0));
            self.send(None, out)?;
        }
        while self.lp.time() < t {
            let before = mppi(&self.lp).copied();
            if self.lp.step().is_err() {
                break;
            }
            let cycles = mppi(&self.lp).map_or(0, |law| law.cycles(0));
            if cycles != self.cycles {
                self.cycles = cycles;
                let drawn = (cycles - 1).is_multiple_of(MPPI_ROLLOUTS_EVERY);
                self.send(before.filter(|_| drawn), out)?;
            }
        }
        Ok(())
    }

    /// Sends the plan just made: its optimal trajectory, and with `before` (the law before
    /// the plan) a sample of its rollouts.
    fn send<E>(
        &mut self,
        before: Option<MppiLaw<f64>>,
        out: &mut impl FnMut(Kind, u64, &[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        let Some(law) = mppi(&self.lp) else { return Ok(()) };
        let tick = self.lp.last_tick();
        let m = tick.measurement;
        let ns = self.clock.nanos(tick.t);
        let ts = Some(stamp(ns));
        let Some((first, rest)) = self.poses.split_first_mut() else { return Ok(()) };
        *first = m.pose;
        let n = law.predict(0, &m, rest);
        let msg = PosesInFrame {
            timestamp: ts,
            frame_id: WORLD_FRAME.into(),
            poses: std::iter::once(&*first).chain(rest.iter().take(n)).map(|&p| pose(p)).collect(),
        };
        self.buf.clear();
        let _ = prost::Message::encode(&msg, &mut self.buf);
        out(Kind::MppiOptimal, ns, &self.buf)?;
        let Some(before) = before else { return Ok(()) };
        let colour = run_color(self.run, ROLLOUT_ALPHA);
        let mut lines = Vec::with_capacity(MPPI_ROLLOUTS_DRAWN as usize);
        for k in 0..MPPI_ROLLOUTS_DRAWN.min(before.params().batch_size) {
            let n = before.sampled_rollout(0, k, &m, rest);
            let start = std::iter::once(m.pose);
            let points = start.chain(rest.iter().take(n).copied()).map(|p| Point3 { x: p.x, y: p.y, z: 0.0 }).collect();
            lines.push(LinePrimitive {
                r#type: line_primitive::Type::LineStrip as i32,
                pose: Some(pose(Pose2::new(0.0, 0.0, 0.0))),
                thickness: ROLLOUT_WIDTH_PX,
                scale_invariant: true,
                points,
                color: Some(colour),
                ..Default::default()
            });
        }
        let update = SceneUpdate {
            deletions: vec![],
            entities: vec![SceneEntity {
                timestamp: ts,
                frame_id: WORLD_FRAME.into(),
                id: ROLLOUTS_ENTITY.into(),
                lines,
                ..Default::default()
            }],
        };
        self.buf.clear();
        let _ = prost::Message::encode(&update, &mut self.buf);
        out(Kind::MppiRollouts, ns, &self.buf)
    }
}
