//! `wmr_py.PaperController`, `PaperBidirectionalController`, `PolarController`,
//! `LyapunovController` (point stabilization: they follow a goal) and
//! `KanayamaController`, `BacksteppingController`, `PurePursuitController` (tracking and
//! path following: they follow a [`crate::trajectory::PyReference`]): each law with its
//! wheel stage (the core's [`wmr_core::Controller`]) for loops closed in Python, one
//! robot or a batch of N.
//!
//! A batch holds N copies of the controller (N lanes), one per robot, all with the same
//! gains and goal; a call with (N, k) arrays advances every lane by one tick in Rust, so
//! a loop closed in Python costs a few Python calls per step whatever N is.

use std::sync::{Mutex, MutexGuard, PoisonError};

use numpy::{IntoPyArray, PyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyFloatingPointError;
use pyo3::prelude::*;
use pyo3::sync::MutexExt;
use pyo3::types::{PyDict, PyTuple};
use wmr_core::{ControlOutput, Measurement, Pose2, Reference, ReferenceState, StepClock, Wheels};
use wmr_scenario::BuiltController;
use wmr_scenario::reference::RunReference;

use crate::alloc::{bytes_of, check_alloc, leading_rows, vec_with_capacity, zeros2};
use crate::convert::{batch_arg, finite_array, pose_table, same_rows, type_name};
use crate::error::parameter_error;
use crate::reference::reference_arg;
use crate::robot::{PyRobot, one_run_scenario, wheels_arg};
use crate::scenario::scenario_arg;
use crate::trajectory::{PyReference, reference_table};

/// What a law class's constructor takes first: the goal (a fixed reference, the
/// stabilization laws) or a moving reference (the tracking and path-following laws).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Follows {
    Goal,
    Reference,
}

/// The controller of one law and its lanes (one per robot of a batch).
///
/// Shared between threads: the lanes are behind a lock, so one controller updated from
/// several threads raises nothing; each `update` is one tick, in the order the threads
/// take the lock. Everything that calls into Python (reading the arguments, making the
/// result) happens outside the lock, so a thread never holds it while another runs
/// Python code, and a thread that finds it taken waits with the GIL released.
pub struct Lanes {
    /// The controller at t = 0, as the scenario builds it (its run `run`'s).
    proto: BuiltController,
    /// The run whose noise stream the law draws (MPPI, `run=`); lane i of a batch draws
    /// run `run + i`'s, as run `run + i` of a scenario does.
    run: u64,
    /// The configuration, kept for a law that draws noise per run: a batch's lanes are
    /// built from it (`None` for every other law: their lanes are copies of `proto`).
    noisy: Option<Box<wmr_scenario::Setup>>,
    goal: Pose2<f64>,
    /// The moving reference of a tracking law (`None`: the goal at rest).
    reference: Option<PyReference>,
    /// The one-run scenario the controller was built from, resolved (pickling).
    scenario_toml: String,
    /// What the ticks change.
    state: Mutex<LaneState>,
}

/// The lanes and what a tick changes.
struct LaneState {
    /// One controller per robot; one for the single (1-D) calls.
    lanes: Vec<BuiltController>,
    /// The lanes before the tick being computed (a tick that fails leaves them as they were).
    next: Vec<BuiltController>,
    last: Vec<ControlOutput<f64>>,
    /// The outputs of the tick being computed.
    next_last: Vec<ControlOutput<f64>>,
    /// Control ticks since construction or reset: the time of a tick is the loop's clock
    /// ([`StepClock`]) at control_dt.
    ticks: u64,
    /// Whether the last update was batched (then `errors` is an array).
    batched: bool,
}

/// What a law class's constructor takes beside the law's keys: the obstacles on the
/// controller's map (a list of `[[world.obstacle]]` dicts), the robot's footprint radius
/// (m, `[robot] footprint_radius`) and the run whose noise the law draws. MPPI's only.
struct World<'a, 'py> {
    obstacles: Option<&'a Bound<'py, PyAny>>,
    footprint_radius: Option<&'a Bound<'py, PyAny>>,
    run: u64,
}

/// The references of an update: as given, or the law's own (the moving reference at the
/// tick's time, known once the lock is held).
enum Refs {
    Given(Vec<ReferenceState<f64>>),
    Moving,
}

impl Lanes {
    /// Builds the controller of law `kind` the way `PaperController(goal, robot, drive,
    /// **gains)` documents it: the keys go through the scenario parser.
    #[allow(clippy::too_many_arguments)]
    fn new(
        kind: &str,
        follows: Follows,
        target: &Bound<'_, PyAny>,
        robot: Option<&Bound<'_, PyAny>>,
        drive: Option<&Bound<'_, PyAny>>,
        world: World<'_, '_>,
        gains: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let py = target.py();
        let World { obstacles, footprint_radius, run } = world;
        // Only MPPI's critic sees obstacles, and only MPPI draws noise: the other laws
        // refuse what they would ignore.
        if kind != "mppi" {
            let given = [("obstacles", obstacles.is_some()), ("footprint_radius", footprint_radius.is_some())];
            if let Some((arg, _)) = given.iter().find(|(_, g)| *g) {
                return Err(parameter_error(
                    arg,
                    format_args!(
                        "kind = \"{kind}\" does not see obstacles; MppiController does (its obstacles critic)"
                    ),
                ));
            }
            if run != 0 {
                return Err(parameter_error(
                    "run",
                    format_args!("kind = \"{kind}\" draws no noise; run selects MppiController's noise stream"),
                ));
            }
        }
        let robot = match robot {
            None => None,
            Some(r) => match r.cast::<PyRobot>() {
                Ok(r) => Some(r.call_method0("to_dict")?.cast_into::<PyDict>()?),
                Err(_) => Some(
                    r.cast::<PyDict>()
                        .map_err(|_| {
                            parameter_error("robot", format_args!("expected a Robot or a dict, got {}", type_name(r)))
                        })?
                        .clone(),
                ),
            },
        };
        let table = PyDict::new(py);
        if let Some(g) = gains {
            if let Some(k) = g.get_item("kind")?
                && k.extract::<String>().ok().as_deref() != Some(kind)
            {
                return Err(parameter_error(
                    "controller.kind",
                    format_args!("this class runs kind = \"{kind}\" (got {k}); each law has its own class"),
                ));
            }
            table.update(g.as_mapping())?;
        }
        table.set_item("kind", kind)?;
        // A one-run scenario: the scenario code parses the keys, fills the defaults
        // (servo gains by drive kind) and checks everything, as for a file. A tracking
        // law's run gives no goal: its `[reference]` is the goal.
        let sc_dict = match follows {
            Follows::Goal => {
                let goal = pose_table(target, "goal")?;
                one_run_scenario(py, robot.as_ref(), drive, Some(&table), Some(&goal))?
            }
            Follows::Reference => {
                let d = one_run_scenario(py, robot.as_ref(), drive, Some(&table), None)?;
                d.set_item("run", vec![PyDict::new(py)])?;
                d.set_item("reference", reference_table(target)?)?;
                d
            }
        };
        // The obstacles and the footprint, as `[[world.obstacle]]` and `[robot]
        // footprint_radius` of the scenario: the same keys, the same checks, errors naming
        // them (world.obstacle[0].radius).
        if let Some(list) = obstacles.filter(|o| !o.is_none()) {
            let world = PyDict::new(py);
            world.set_item("obstacle", list)?;
            sc_dict.set_item("world", world)?;
        }
        if let Some(r) = footprint_radius.filter(|r| !r.is_none()) {
            let robot = match sc_dict.get_item("robot")? {
                Some(t) => t.cast_into::<PyDict>()?.copy()?,
                None => PyDict::new(py),
            };
            robot.set_item(wmr_scenario::FOOTPRINT_RADIUS, r)?;
            sc_dict.set_item("robot", robot)?;
        }
        let sc = scenario_arg(sc_dict.as_any())?;
        Self::from_scenario(&sc, run)
    }

    fn from_scenario(sc: &wmr_scenario::Scenario, run: u64) -> PyResult<Self> {
        let goal = sc.runs().first().map(|r| r.goal).unwrap_or_default();
        let setup = sc.setup();
        let noisy = setup.samples_noise().then(|| Box::new(setup.clone()));
        let proto = Self::built_for(setup, run, "run")?;
        let reference = sc.tracking().map(|t| PyReference::from_spec(t.reference.clone()));
        Ok(Self {
            proto,
            run,
            noisy,
            goal,
            reference,
            scenario_toml: sc.to_toml(),
            state: Mutex::new(LaneState {
                lanes: vec![proto],
                next: Vec::new(),
                last: vec![ControlOutput::default()],
                next_last: Vec::new(),
                ticks: 0,
                batched: false,
            }),
        })
    }

    /// The controller of run `run` (`arg` names the argument that asked for it).
    fn built_for(setup: &wmr_scenario::Setup, run: u64, arg: &str) -> PyResult<BuiltController> {
        setup
            .controller_for(run)
            .map_err(|e| parameter_error(arg, format_args!("the controller of run {run}: {} {}", e.field, e.reason)))
    }

    /// Rebuilds a controller from the resolved scenario and the run its `__reduce__` gave.
    pub fn from_toml(kind: &str, text: &str, run: u64) -> PyResult<Self> {
        let sc = wmr_scenario::Scenario::from_toml_str(text, "controller")
            .map_err(|e| crate::error::from_scenario(&e, None))?;
        let lanes = Self::from_scenario(&sc, run)?;
        if lanes.proto.law().kind() != kind {
            return Err(parameter_error("controller.kind", format_args!("expected kind = \"{kind}\"")));
        }
        Ok(lanes)
    }

    /// The lanes, locked: at once when free, else waiting with the GIL released (the
    /// thread that holds the lock may need the GIL to finish). A lock poisoned by a panic
    /// is taken as it is: a tick changes the lanes all at once or not at all.
    fn lock(&self, py: Python<'_>) -> MutexGuard<'_, LaneState> {
        self.state.lock_py_attached(py).unwrap_or_else(PoisonError::into_inner)
    }

    /// The time of tick `ticks`, s: the loop's own clock at control_dt, the bits a
    /// scenario run gives the law at this tick.
    fn tick_time(&self, ticks: u64) -> f64 {
        StepClock::new(self.proto.control_dt()).time(ticks)
    }

    /// The references of the next tick: `reference` as given, or when `None` the moving
    /// reference's state at the tick's time (a tracking law, [`Refs::Moving`]), or the
    /// goal at rest. Reads Python objects: called before the lock is taken.
    fn references(&self, reference: Option<&Bound<'_, PyAny>>, n: usize) -> PyResult<Refs> {
        match (&self.reference, reference.filter(|r| !r.is_none())) {
            (Some(_), None) => Ok(Refs::Moving),
            (_, given) => Ok(Refs::Given(reference_arg(given, self.goal, n)?)),
        }
    }

    /// Bytes of a batch of `n` robots: the lanes and the tick's copy of them, the
    /// outputs and the tick's, the result's row.
    fn batch_bytes(n: usize) -> u128 {
        let lane = 2 * bytes_of::<BuiltController>(1) + 2 * bytes_of::<ControlOutput<f64>>(1) + bytes_of::<[f64; 3]>(1);
        lane * n as u128
    }

    /// Makes room for `n` lanes: allowed at t = 0 only (the lanes of a running batch
    /// hold their integrators). The memory of a new batch (the lanes, the tick's copy,
    /// the outputs) is checked first: a batch too large raises `MemoryError` naming `arg`.
    fn lanes_for(&self, st: &mut LaneState, n: usize, arg: &str) -> PyResult<()> {
        if st.lanes.len() == n {
            return Ok(());
        }
        if st.ticks != 0 {
            return Err(parameter_error(
                arg,
                format_args!(
                    "{n} robots, but the controller runs {} since its first update; call reset() to change the batch",
                    st.lanes.len()
                ),
            ));
        }
        check_alloc(Self::batch_bytes(n), arg, || format!("a batch of {n} robots"))?;
        let mut lanes = vec_with_capacity(n, arg, "the lanes")?;
        match &self.noisy {
            // Lane i draws run `run + i`'s noise.
            Some(setup) => {
                for i in 0..n as u64 {
                    lanes.push(Self::built_for(setup, self.run.saturating_add(i), arg)?);
                }
            }
            None => lanes.resize(n, self.proto),
        }
        let mut last = vec_with_capacity(n, arg, "the outputs")?;
        last.resize(n, ControlOutput::default());
        let next = vec_with_capacity(n, arg, "the lanes")?;
        let next_last = vec_with_capacity(n, arg, "the outputs")?;
        (st.lanes, st.last, st.next, st.next_last) = (lanes, last, next, next_last);
        Ok(())
    }

    /// One tick of every lane, from the measurement of lane i given by `m(i)`. All or
    /// nothing: a tick whose commands or errors are not finite leaves every lane as it was.
    fn tick(
        &self,
        st: &mut LaneState,
        n: usize,
        refs: &Refs,
        m: impl Fn(usize, f64) -> Measurement<f64>,
    ) -> PyResult<()> {
        let t = self.tick_time(st.ticks);
        // A path-following law steers by the reference's path, as the scenario loop does
        // (wmr_core::ClosedLoop): every law is given the path when the reference has one.
        let moving: Option<RunReference> = self.reference.as_ref().map(PyReference::built);
        let own;
        let refs: &[ReferenceState<f64>] = match (refs, &moving) {
            (Refs::Given(r), _) => r,
            (Refs::Moving, Some(r)) => {
                own = [r.state_at(t)];
                &own
            }
            (Refs::Moving, None) => {
                own = [ReferenceState::at_rest(self.goal)];
                &own
            }
        };
        // The tick is computed into `next` and `next_last` and swapped in when every lane
        // is finite; the buffers are kept, so a tick allocates nothing after the first.
        st.next.clear();
        st.next.extend_from_slice(&st.lanes[..n]);
        st.next_last.clear();
        for (i, lane) in st.next.iter_mut().enumerate() {
            // One reference for every robot, or one each (`reference_arg` gives 1 or n).
            let (mi, ri) = (m(i, t), &refs[i % refs.len()]);
            let out = match moving.as_ref().and_then(|r| r.path()) {
                Some(path) => lane.update_on_path(t, &mi, ri, path),
                None => lane.update(t, &mi, ri),
            };
            let e = out.errors;
            if ![out.command.right, out.command.left, e.e_s, e.e_theta, e.dl].iter().all(|v| v.is_finite()) {
                return Err(PyFloatingPointError::new_err(format!(
                    "the wheel commands of robot {i} are not finite ({}, {}): the measurement is too large for the controller",
                    out.command.right, out.command.left
                )));
            }
            st.next_last.push(out);
        }
        let LaneState { lanes, next, last, next_last, .. } = st;
        std::mem::swap(lanes, next);
        std::mem::swap(last, next_last);
        st.ticks += 1;
        Ok(())
    }

    fn update<'py>(
        &self,
        pose: &Bound<'py, PyAny>,
        wheel_angles: &Bound<'py, PyAny>,
        wheel_speeds: &Bound<'py, PyAny>,
        reference: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let py = pose.py();
        // A new batch's memory, checked before the arguments' values are read.
        if let Some(n) = leading_rows(pose)
            && n != self.counts(py).0
        {
            check_alloc(Self::batch_bytes(n), "pose", || format!("a batch of {n} robots"))?;
        }
        if let Some(p) = batch_arg(pose, "pose", ["x", "y", "theta"])? {
            let n = p.shape()[0];
            let a = batch_arg(wheel_angles, "wheel_angles", ["phi_r", "phi_l"])?.ok_or_else(|| {
                parameter_error("wheel_angles", format_args!("expected shape (N, 2) like pose's (N, 3)"))
            })?;
            let w = batch_arg(wheel_speeds, "wheel_speeds", ["omega_r", "omega_l"])?.ok_or_else(|| {
                parameter_error("wheel_speeds", format_args!("expected shape (N, 2) like pose's (N, 3)"))
            })?;
            same_rows(&a, "wheel_angles", n, "pose")?;
            same_rows(&w, "wheel_speeds", n, "pose")?;
            let refs = self.references(reference, n)?;
            let (p, a, w) = (p.as_array(), a.as_array(), w.as_array());
            let out = {
                let mut st = self.lock(py);
                self.lanes_for(&mut st, n, "pose")?;
                self.tick(&mut st, n, &refs, |i, t| Measurement {
                    t,
                    pose: Pose2::new(p[[i, 0]], p[[i, 1]], p[[i, 2]]),
                    wheel_angles: Wheels::new(a[[i, 0]], a[[i, 1]]),
                    wheel_speeds: Wheels::new(w[[i, 0]], w[[i, 1]]),
                })?;
                st.batched = true;
                let mut out = zeros2(n, 2, "pose", "wheel commands")?;
                for (mut row, o) in out.rows_mut().into_iter().zip(&st.last) {
                    row[0] = o.command.right;
                    row[1] = o.command.left;
                }
                out
            };
            return Ok(out.into_pyarray(py).into_any().unbind());
        }
        let [x, y, theta] = finite_array(pose, "pose", ["x", "y", "theta"])?;
        let angles = wheels_arg(wheel_angles, "wheel_angles", ["phi_r", "phi_l"])?;
        let speeds = wheels_arg(wheel_speeds, "wheel_speeds", ["omega_r", "omega_l"])?;
        let refs = self.references(reference, 1)?;
        let c = {
            let mut st = self.lock(py);
            self.lanes_for(&mut st, 1, "pose")?;
            self.tick(&mut st, 1, &refs, |_, t| Measurement {
                t,
                pose: Pose2::new(x, y, theta),
                wheel_angles: angles,
                wheel_speeds: speeds,
            })?;
            st.batched = false;
            st.last[0].command
        };
        Ok((c.right, c.left).into_pyobject(py)?.into_any().unbind())
    }

    fn errors(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let out = {
            let st = self.lock(py);
            if !st.batched {
                let e = st.last.first().map(|o| o.errors).unwrap_or_default();
                drop(st);
                return Ok((e.e_s, e.e_theta, e.dl).into_pyobject(py)?.into_any().unbind());
            }
            let mut out = zeros2(st.last.len(), 3, "errors", "errors")?;
            for (mut row, o) in out.rows_mut().into_iter().zip(&st.last) {
                row[0] = o.errors.e_s;
                row[1] = o.errors.e_theta;
                row[2] = o.errors.dl;
            }
            out
        };
        let arr: Bound<'_, PyArray2<f64>> = out.into_pyarray(py);
        Ok(arr.into_any().unbind())
    }

    fn reset(&self, py: Python<'_>) {
        let mut st = self.lock(py);
        st.lanes = vec![self.proto];
        st.last = vec![ControlOutput::default()];
        st.ticks = 0;
        st.batched = false;
    }

    /// Robots in the batch and ticks run: (n, ticks).
    fn counts(&self, py: Python<'_>) -> (usize, u64) {
        let st = self.lock(py);
        (st.lanes.len(), st.ticks)
    }

    /// `(wmr_py._restore_controller, (class name, resolved scenario))`; refused once the
    /// controller has run, because its integrators have no portable form yet.
    fn reduce<'py>(&self, py: Python<'py>, class: &str) -> PyResult<Bound<'py, PyTuple>> {
        let (_, ticks) = self.counts(py);
        if ticks != 0 {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "cannot pickle a {class} that has run ({ticks} ticks): its integrator state is not picklable; \
                 pickle it before the first update() or after reset()"
            )));
        }
        let restore = py.import("wmr_py")?.getattr("_restore_controller")?;
        let args = (class, self.scenario_toml.as_str(), self.run).into_pyobject(py)?;
        PyTuple::new(py, [restore, args.into_any()])
    }
}

/// One Python class per law: the constructor fixes `kind` and what the law follows (its
/// first argument, `goal` or `reference`); the rest is [`Lanes`]. The class is named
/// after the Rust struct (`PaperController`).
macro_rules! law_class {
    ($(#[$doc:meta])* $rust:ident, $kind:expr, $arg:ident => $follows:ident) => {
        $(#[$doc])*
        #[pyclass(module = "wmr_py", frozen)]
        pub struct $rust {
            inner: Lanes,
        }

        impl $rust {
            /// The controller rebuilt from its resolved one-run scenario and run (unpickling).
            pub fn from_toml(text: &str, run: u64) -> PyResult<Self> {
                Ok(Self { inner: Lanes::from_toml($kind, text, run)? })
            }
        }

        #[pymethods]
        impl $rust {
            #[new]
            #[pyo3(signature = ($arg, robot=None, drive=None, *, obstacles=None, footprint_radius=None, run=0, **gains))]
            #[allow(clippy::too_many_arguments)]
            fn new(
                $arg: &Bound<'_, PyAny>,
                robot: Option<&Bound<'_, PyAny>>,
                drive: Option<&Bound<'_, PyAny>>,
                obstacles: Option<&Bound<'_, PyAny>>,
                footprint_radius: Option<&Bound<'_, PyAny>>,
                run: u64,
                gains: Option<&Bound<'_, PyDict>>,
            ) -> PyResult<Self> {
                let world = World { obstacles, footprint_radius, run };
                Ok(Self { inner: Lanes::new($kind, Follows::$follows, $arg, robot, drive, world, gains)? })
            }

            /// The run whose noise stream the law draws (MPPI; 0 for the others): lane i
            /// of a batch draws run ``run + i``'s, as a scenario's run ``run + i`` does.
            #[getter]
            fn run(&self) -> u64 {
                self.inner.run
            }

            /// One control tick: the wheel commands from the measured pose (x_m, y_m,
            /// theta_rad) of C, the wheel angles (phi_r, phi_l) in rad and the wheel speeds
            /// (omega_r, omega_l) in rad/s; advances the integrators by control_dt.
            ///
            /// One robot: 1-D arguments, returns (tau_r, tau_l). A batch of N robots:
            /// arrays of shape (N, 3), (N, 2), (N, 2), returns an (N, 2) array; the first
            /// batched call (or the first after reset()) fixes N. With the torque drive the
            /// commands are wheel torque demands in N m before the drive's clamp
            /// (|tau| <= motor_torque_max / gear_ratio); with dc_motor, volts.
            ///
            /// reference: what the law tracks at this tick; when None, the goal at rest (a
            /// stabilization law) or the state of the class's Reference at the tick's time
            /// (a tracking law; the path of a path-following law is always the Reference's):
            /// a dict {"pose": (x_m, y_m, theta_rad), "twist": (v m/s, omega rad/s),
            /// "accel": (v' m/s^2, omega' rad/s^2)} (parts as dicts or sequences; a
            /// missing part is the goal's pose or zero), a row of those 7 numbers, or for
            /// a batch an (N, 7) array (one row for every robot also works). A bad or
            /// non-finite value raises ParameterError naming it (reference.twist.v).
            #[pyo3(signature = (pose, wheel_angles, wheel_speeds, reference=None))]
            fn update(
                &self,
                pose: &Bound<'_, PyAny>,
                wheel_angles: &Bound<'_, PyAny>,
                wheel_speeds: &Bound<'_, PyAny>,
                reference: Option<&Bound<'_, PyAny>>,
            ) -> PyResult<Py<PyAny>> {
                self.inner.update(pose, wheel_angles, wheel_speeds, reference)
            }

            /// Errors of the last update, (e_s in m, e_theta in rad, dl in m) (docs/model.md,
            /// eqs. (18), (21), (16) for the paper's law); an (N, 3) array after a batched update.
            #[getter]
            fn errors(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
                self.inner.errors(py)
            }

            /// Clears the integrators and memories, as at t = 0 (and the batch size).
            fn reset(&self, py: Python<'_>) {
                self.inner.reset(py)
            }

            /// Control period, s: call update() this often.
            #[getter]
            fn control_dt(&self) -> f64 {
                self.inner.proto.control_dt()
            }

            /// The goal (x_m, y_m, theta_rad) of C; None for a tracking law (it follows
            /// `reference`).
            #[getter]
            fn goal(&self) -> Option<(f64, f64, f64)> {
                let g = self.inner.goal;
                self.inner.reference.is_none().then_some((g.x, g.y, g.theta))
            }

            /// The Reference a tracking law follows; None for a stabilization law (it
            /// follows `goal`).
            #[getter]
            fn reference(&self) -> Option<PyReference> {
                self.inner.reference.clone()
            }

            /// The law's `kind` in a scenario's `[controller]`.
            #[getter]
            fn kind(&self) -> &'static str {
                $kind
            }

            /// Robots in the batch (1 for single calls).
            #[getter]
            fn n(&self, py: Python<'_>) -> usize {
                self.inner.counts(py).0
            }

            /// The resolved `[controller]` (with `[robot]` and `[drive]`) as TOML.
            #[getter]
            fn scenario_toml(&self) -> &str {
                &self.inner.scenario_toml
            }

            fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
                self.inner.reduce(py, stringify!($rust))
            }

            fn __repr__(&self, py: Python<'_>) -> String {
                let g = self.inner.goal;
                let (n, ticks) = self.inner.counts(py);
                let follows = match &self.inner.reference {
                    Some(r) => format!("reference={:?}", r.built().kind()),
                    None => format!("goal=({}, {}, {})", g.x, g.y, g.theta),
                };
                format!("{}({follows}, n={n}, ticks={ticks})", stringify!($rust))
            }
        }
    };
}

/// One class per law of the registry (`wmr_core::for_each_law!`): its doc is the
/// registry line's, then how to call it, by what the law follows.
macro_rules! law_classes {
    (@doc GoalOrPath) => {
        law_classes!(@doc Goal)
    };
    (@doc Goal) => {
        "\n\n(goal, robot=None, drive=None, **gains)\n\n\
goal: the goal pose of C, (x_m, y_m, theta_rad) or a dict with x, y and theta (rad) or \
theta_deg (degrees). robot: a Robot or a dict of `[robot]` keys (default: the paper's). \
drive: a dict of `[drive]` keys (default: the torque drive); it sets the servo's defaults \
and anti-windup bound. gains: the scenario's `[controller]` keys of this kind (listed with \
their defaults in the stubs and `wmr-cli help keys controller`), parsed and checked by the \
scenario code: a bad or unknown key raises ScenarioError naming it (``controller.kp_s``).\n\n\
Call update() once every control_dt seconds and hold its output in between; it takes one \
robot (1-D arguments) or a batch of N ((N, 3), (N, 2), (N, 2) arrays)."
    };
    (@doc $other:ident) => {
        "\n\n(reference, robot=None, drive=None, **gains)\n\n\
reference: the Reference it follows (or a dict of `[reference]` keys); at each update \
without `reference=` the law follows its state at the tick's time (tick k at k control_dt, \
the scenario loop's clock). robot, drive, gains: as for PaperController."
    };
    (@class Goal, $(#[$m:meta])* $rust:ident, $kind:expr) => {
        law_class!($(#[$m])* $rust, $kind, goal => Goal);
    };
    // A law that follows a goal or a path is stepped by hand towards a goal (the scenario
    // gives it a path: `simulate` with a `[reference]`).
    (@class GoalOrPath, $(#[$m:meta])* $rust:ident, $kind:expr) => {
        law_class!($(#[$m])* $rust, $kind, goal => Goal);
    };
    (@class $other:ident, $(#[$m:meta])* $rust:ident, $kind:expr) => {
        law_class!($(#[$m])* $rust, $kind, reference => Reference);
    };
    ($krate:tt; $( $(#[doc = $doc:literal])* $variant:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => { paste::paste! {
        $(
            law_classes!(
                @class $follows,
                $(#[doc = $doc])*
                #[doc = concat!("\n\nkind \"", stringify!($kind), "\" with its wheel stage.", law_classes!(@doc $follows))]
                [<$variant Controller>],
                stringify!($kind)
            );
        )+

        /// Adds every law's class to the module.
        pub fn add_law_classes(m: &Bound<'_, pyo3::types::PyModule>) -> PyResult<()> {
            use pyo3::types::PyModuleMethods as _;
            $( m.add_class::<[<$variant Controller>]>()?; )+
            Ok(())
        }

        /// Rebuilds a controller of class `class` from its resolved scenario (pickle's restore).
        #[pyfunction(name = "_controller_from_toml")]
        #[pyo3(signature = (class_name, text, run=0))]
        pub fn controller_from_toml(py: Python<'_>, class_name: &str, text: &str, run: u64) -> PyResult<Py<PyAny>> {
            $(
                if class_name == stringify!([<$variant Controller>]) {
                    return Ok(Py::new(py, [<$variant Controller>]::from_toml(text, run)?)?.into_any());
                }
            )+
            Err(parameter_error("class", format_args!("no controller class {class_name:?}")))
        }
    } };
}

wmr_core::for_each_law!(law_classes);
