//! One configuration of a closed loop, as written ([`Tables`]) and validated ([`Setup`]):
//! the robot, its drive, the ground, the sensor, and the controller with its own model of
//! the robot. A scenario has one; a sweep has one per law, and one per law and varied
//! value when it varies keys.

use toml::{Table, Value};
use wmr_core::describe::Described;
use wmr_core::{
    AnyLaw, AnySensor, Controller, ControllerParams, Drive, DriveParams, Obstacle, Obstacles, OdometryParams, Payload,
    PayloadParams, Plant, Pose2, PoseSource, PushParams, Pushes, Robot, RobotParams, SensorParams, Traction,
    TractionParams, World, WorldParams,
};

use crate::controller;
use crate::error::ScenarioError;
use crate::keys::{join, kind_of, overlay, overlay_table, read_with, to_table, unknown_key};

/// A built controller of any law, at t = 0.
pub type BuiltController = Controller<f64, AnyLaw<f64>>;

/// The tables of one configuration, as written (absent tables are empty).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tables {
    /// `[robot]`.
    pub robot: Table,
    /// `[drive]`.
    pub drive: Table,
    /// `[controller]`, with its `model` subtable if any.
    pub controller: Table,
    /// `[sensor]`, if the file has one.
    pub sensor: Option<Table>,
    /// `[world]`.
    pub world: Table,
}

impl Tables {
    /// Sets the value at a dotted scenario key (`robot.mass`, `sensor.latency`,
    /// `controller.model.wheel_radius`, `world.slope_deg`), for sweeps that vary it.
    pub fn set(&mut self, key: &str, value: Value) -> Result<(), ScenarioError> {
        let (table, rest) = key.split_once('.').unwrap_or((key, ""));
        let target = match table {
            "robot" => &mut self.robot,
            "drive" => &mut self.drive,
            "controller" => &mut self.controller,
            "sensor" => self.sensor.get_or_insert_with(Table::new),
            "world" => &mut self.world,
            _ => {
                return Err(ScenarioError::new(
                    key,
                    "only keys of [robot], [drive], [controller], [sensor] and [world] can be varied",
                ));
            }
        };
        let mut parts: Vec<&str> = rest.split('.').collect();
        let last = parts.pop().filter(|k| !k.is_empty()).ok_or_else(|| ScenarioError::new(key, "name a key"))?;
        let mut t = target;
        for p in parts {
            let entry = t.entry(p.to_owned()).or_insert_with(|| Value::Table(Table::new()));
            t = entry.as_table_mut().ok_or_else(|| ScenarioError::new(key, format!("{p} is not a table")))?;
        }
        // A whole number is written as an integer, which integer keys need
        // (`encoder_counts`) and float keys accept.
        let value = match value {
            Value::Float(x) if x.fract() == 0.0 && x.abs() < 9.0e15 => Value::Integer(x as i64),
            v => v,
        };
        t.insert(last.to_owned(), value);
        Ok(())
    }
}

/// A validated configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Setup {
    /// The true robot (`[robot]`).
    pub robot: Robot<f64>,
    /// The traction keys of `[robot]` (`traction`, `friction_coefficient`, ...).
    pub traction_params: TractionParams<f64>,
    /// The traction model they build (rolling unless `traction = "slip"`).
    pub traction: Traction<f64>,
    /// The drive (`[drive]`).
    pub drive: Drive<f64>,
    /// The ground (`[world]`).
    pub world: World<f64>,
    /// What the controller sees (`[sensor]`; every default when absent).
    pub sensor: SensorParams<f64>,
    /// Where the controller's pose comes from (`[sensor] pose`, `fix_rate_hz`,
    /// `odometry_noise`; absolute, today's sensor, by default).
    pub pose: OdometryParams<f64>,
    /// True when the file has a `[sensor]` table: outputs then carry the measured pose.
    pub has_sensor: bool,
    /// The controller's idea of the robot: `[robot]` with `[controller.model]` laid over it.
    pub model: Robot<f64>,
    /// The controller's keys (`[controller]`).
    pub controller: ControllerParams<f64>,
    /// The controller built for the model and the drive, at t = 0.
    pub built: BuiltController,
    /// The payload the plant carries and the controller does not know (`[world.payload]`;
    /// none by default).
    pub payload: Payload<f64>,
    /// The plant's robot: `robot` carrying `payload` (`robot` itself without one); with
    /// `[world.payload] t` > 0 the plant is `robot` until then.
    pub truth: Robot<f64>,
    /// The pushes on the plant (`[[world.push]]`; none by default).
    pub pushes: Pushes<f64>,
    /// The obstacles (`[[world.obstacle]]`; none by default) and the footprint radius
    /// (`[robot] footprint_radius`) that collides with them.
    pub obstacles: Obstacles<f64>,
}

/// One `[[world.obstacle]]` as written: `kind = "circle"` with `center` and `radius`, or
/// `kind = "polygon"` with `points`.
#[derive(Clone, Debug, Default, serde::Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
struct ObstacleFile {
    kind: String,
    #[serde(default)]
    center: Option<PointFile>,
    #[serde(default)]
    radius: Option<f64>,
    #[serde(default)]
    points: Option<Vec<[f64; 2]>>,
}

/// `center = { x = .., y = .. }`, m, world frame.
#[derive(Clone, Debug, Default, serde::Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
struct PointFile {
    x: f64,
    y: f64,
}

/// The most vertices one `[[world.obstacle]]` polygon is read with (the world holds
/// [`wmr_core::obstacle::MAX_POLYGON_POINTS`] in all).
const MAX_READ_POINTS: usize = wmr_core::obstacle::MAX_POLYGON_POINTS;

/// `[[world.obstacle]]` with the footprint radius (m): each obstacle read and checked;
/// errors name `world.obstacle[i].<key>`.
fn resolve_obstacles(given: Option<Value>, footprint_radius: f64) -> Result<Obstacles<f64>, ScenarioError> {
    use serde::Deserialize;
    let list = match given {
        None => Vec::new(),
        Some(Value::Array(a)) => a,
        Some(other) => {
            return Err(ScenarioError::new(
                "world.obstacle",
                format!("expected an array of tables ([[world.obstacle]]), got {}", other.type_str()),
            ));
        }
    };
    if list.len() > wmr_core::obstacle::MAX_OBSTACLES {
        return Err(ScenarioError::new(
            "world.obstacle",
            format!("{} obstacles: at most {} (MAX_OBSTACLES)", list.len(), wmr_core::obstacle::MAX_OBSTACLES),
        ));
    }
    let mut read = Vec::with_capacity(list.len());
    for (i, v) in list.into_iter().enumerate() {
        let path = format!("world.obstacle[{i}]");
        let o: ObstacleFile = read_with(&path, v, |d| ObstacleFile::deserialize(d))?;
        let need = |key: &str, what: &str| {
            ScenarioError::new(join(&path, key), format!("is required for kind = \"{}\" ({what})", o.kind))
        };
        let refuse = |key: &str, why: &str| ScenarioError::new(join(&path, key), why.to_owned());
        match o.kind.as_str() {
            "circle" => {
                if o.points.is_some() {
                    return Err(refuse("points", "is for kind = \"polygon\"; a circle has center and radius"));
                }
                let c = o.center.as_ref().ok_or_else(|| need("center", "{ x, y }, m"))?;
                let radius = o.radius.ok_or_else(|| need("radius", "m"))?;
                if !(c.x.is_finite() && c.y.is_finite()) {
                    return Err(refuse("center", "must be finite"));
                }
                if !(radius.is_finite() && radius > 0.0) {
                    return Err(refuse("radius", &format!("must be finite and > 0, got {radius}")));
                }
                read.push(((c.x, c.y, radius), Vec::new()));
            }
            "polygon" => {
                if o.center.is_some() || o.radius.is_some() {
                    return Err(refuse(
                        if o.center.is_some() { "center" } else { "radius" },
                        "is for kind = \"circle\"; a polygon has points",
                    ));
                }
                let points = o.points.ok_or_else(|| need("points", "[[x, y], ...], m, at least 3"))?;
                if points.len() < 3 || points.len() > MAX_READ_POINTS {
                    return Err(refuse(
                        "points",
                        &format!("needs 3 to {MAX_READ_POINTS} vertices, got {}", points.len()),
                    ));
                }
                if points.iter().flatten().any(|c| !c.is_finite()) {
                    return Err(refuse("points", "must be finite"));
                }
                read.push(((0.0, 0.0, 0.0), points.iter().map(|p| (p[0], p[1])).collect()));
            }
            other => {
                return Err(ScenarioError::new(
                    join(&path, "kind"),
                    format!("unknown kind {other:?}; the kinds are \"circle\", \"polygon\""),
                ));
            }
        }
    }
    let list: Vec<Obstacle<'_, f64>> = read
        .iter()
        .map(|((x, y, r), points)| {
            if points.is_empty() {
                Obstacle::Circle { center: (*x, *y), radius: *r }
            } else {
                Obstacle::Polygon(points)
            }
        })
        .collect();
    Obstacles::new(&list, footprint_radius).map_err(|e| match e.field {
        "footprint_radius" => ScenarioError::from_param(&e, "robot.footprint_radius"),
        _ => ScenarioError::from_param(&e, "world.obstacle"),
    })
}

/// One `[[world.push]]` as written.
#[derive(Clone, Debug, Default, serde::Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
struct PushFile {
    t: f64,
    duration: f64,
    #[serde(default)]
    force: ForceFile,
    #[serde(default)]
    torque: f64,
}

/// `force = { x = .., y = .. }`, N, body frame.
#[derive(Clone, Debug, Default, serde::Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
struct ForceFile {
    #[serde(default)]
    x: f64,
    #[serde(default)]
    y: f64,
}

/// `[[world.push]]`: each push read and checked; errors name `world.push[i].<key>`.
fn resolve_pushes(given: Option<Value>) -> Result<Pushes<f64>, ScenarioError> {
    use serde::Deserialize;
    let list = match given {
        None => return Ok(Pushes::default()),
        Some(Value::Array(a)) => a,
        Some(other) => {
            return Err(ScenarioError::new(
                "world.push",
                format!("expected an array of tables ([[world.push]]), got {}", other.type_str()),
            ));
        }
    };
    let mut out = Vec::with_capacity(list.len());
    for (i, v) in list.into_iter().enumerate() {
        let path = format!("world.push[{i}]");
        // A push without its start or its length is refused naming the missing key.
        if let Value::Table(given) = &v
            && let Some(key) = ["t", "duration"].into_iter().find(|k| !given.contains_key(*k))
        {
            return Err(ScenarioError::new(join(&path, key), "is required (s)"));
        }
        let p: PushFile = read_with(&path, v, |d| PushFile::deserialize(d))?;
        let params =
            PushParams { t: p.t, duration: p.duration, force_x: p.force.x, force_y: p.force.y, torque: p.torque };
        params.validate().map_err(|e| {
            let key = match e.field {
                "push.force_x" => "force.x",
                "push.force_y" => "force.y",
                f => f.trim_start_matches("push."),
            };
            ScenarioError::from_param(&e, &join(&path, key))
        })?;
        out.push(params);
    }
    Pushes::new(&out).map_err(|e| ScenarioError::from_param(&e, "world.push"))
}

/// A TOML number as f64.
fn number(v: &Value) -> Option<f64> {
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

fn param_error(path: &str) -> impl Fn(wmr_core::ParamError) -> ScenarioError + '_ {
    move |e| ScenarioError::from_param(&e, &join(path, e.field))
}

/// `[drive]`: `kind` (default `torque`) and its keys.
fn resolve_drive(given: &Table) -> Result<DriveParams<f64>, ScenarioError> {
    let defaults = DriveParams::<f64>::defaults();
    let kinds: Vec<&str> = defaults.iter().map(DriveParams::kind).collect();
    let kind = kind_of(given, "drive", "torque", &kinds)?;
    let default = defaults.into_iter().find(|d| d.kind() == kind).unwrap_or_default();
    let mut keys = to_table(&default);
    keys.remove("kind");
    let mut given = given.clone();
    given.remove("kind");
    let merged = overlay_table(&keys, &given, "drive")?;
    read_with("drive", Value::Table(merged), |d| default.deserialize_variant(d))
}

/// `[robot] footprint_radius`: the robot's footprint about C for collisions, m (nav2's
/// `robot_radius`); by default R, the circle through the wheels' contact points.
pub const FOOTPRINT_RADIUS: &str = "footprint_radius";

/// The keys a `[robot]` table holds, sorted: [`RobotParams`]'s and [`TractionParams`]'s,
/// and `from` when `with_from` (a scenario's, not a preset's).
pub fn robot_keys(with_from: bool) -> Vec<&'static str> {
    let own = RobotParams::<f64>::FIELDS.iter().chain(TractionParams::<f64>::FIELDS).map(|f| f.name);
    let mut keys: Vec<&str> = own.chain(with_from.then_some("from")).chain([FOOTPRINT_RADIUS]).collect();
    keys.sort_unstable();
    keys
}

/// `[robot]` split into the keys of [`RobotParams`] and those of [`TractionParams`]; a
/// key of neither (nor `from`, the preset, read before) is an error that lists them.
pub fn split_robot(robot: &Table) -> Result<(Table, Table), ScenarioError> {
    let accepted = robot_keys(true);
    if let Some(k) = robot.keys().find(|k| !accepted.contains(&k.as_str())) {
        return Err(unknown_key("robot", k, accepted));
    }
    let traction_keys: Vec<&str> = TractionParams::<f64>::FIELDS.iter().map(|f| f.name).collect();
    Ok(robot.clone().into_iter().partition(|(k, _)| !traction_keys.contains(&k.as_str())))
}

impl Setup {
    /// Reads and validates `t`; the controller table's path is `controller_path`
    /// (`controller`, `sweep.controllers[1]`) and its control period must divide into
    /// the sensor's timing.
    pub fn resolve(t: &Tables, controller_path: &str) -> Result<Self, ScenarioError> {
        let mut robot_table = t.robot.clone();
        let footprint = robot_table.remove(FOOTPRINT_RADIUS);
        let (robot_keys, traction_keys) = split_robot(&robot_table)?;
        let robot_params = overlay(&RobotParams::<f64>::paper(), &robot_keys, "robot")?;
        let robot = robot_params.validate().map_err(param_error("robot"))?;
        let drive_params = resolve_drive(&t.drive)?;
        let drive = drive_params.validate(&robot).map_err(param_error("drive"))?;
        let mut world_keys = t.world.clone();
        let pushes = resolve_pushes(world_keys.remove("push"))?;
        let footprint_radius = match footprint {
            None => robot.params().half_track,
            Some(v) => read_with("robot.footprint_radius", v, |d| <f64 as serde::Deserialize>::deserialize(d))?,
        };
        let obstacles = resolve_obstacles(world_keys.remove("obstacle"), footprint_radius)?;
        let payload = match world_keys.remove("payload") {
            None => Payload::none(),
            Some(Value::Table(p)) => overlay(&PayloadParams::<f64>::default(), &p, "world.payload")?
                .validate()
                .map_err(param_error("world"))?,
            Some(other) => {
                return Err(ScenarioError::new("world.payload", format!("expected a table, got {}", other.type_str())));
            }
        };
        let world =
            overlay(&WorldParams::<f64>::default(), &world_keys, "world")?.validate().map_err(param_error("world"))?;
        let truth = payload.carried_by(&robot).map_err(param_error("world"))?;
        let traction_params = overlay(&TractionParams::<f64>::default(), &traction_keys, "robot")?;
        let traction = traction_params.validate(&truth, &world).map_err(|e| match e.field {
            "payload.y" => ScenarioError::from_param(&e, "world.payload.y"),
            _ => ScenarioError::from_param(&e, &join("robot", e.field)),
        })?;
        if payload.appears_later() && matches!(traction, wmr_core::Traction::Slip(_)) {
            return Err(ScenarioError::new(
                "world.payload.t",
                "must be 0 with robot.traction = \"slip\" (the slip plant does not step a payload that appears)",
            ));
        }
        // `[sensor]` holds the keys of two types: the pose source's, and the sensor's.
        let (sensor, pose) = match &t.sensor {
            Some(s) => {
                let is_pose_key = |k: &str| OdometryParams::<f64>::FIELDS.iter().any(|f| f.name == k);
                let names = || SensorParams::<f64>::FIELDS.iter().chain(OdometryParams::<f64>::FIELDS).map(|f| f.name);
                if let Some(k) = s.keys().find(|k| !names().any(|n| n == k.as_str())) {
                    return Err(unknown_key("sensor", k, names()));
                }
                let (pose_keys, sensor_keys): (Table, Table) = s.clone().into_iter().partition(|(k, _)| is_pose_key(k));
                (
                    overlay(&SensorParams::<f64>::default(), &sensor_keys, "sensor")?,
                    overlay(&OdometryParams::<f64>::default(), &pose_keys, "sensor")?,
                )
            }
            None => (SensorParams::default(), OdometryParams::default()),
        };
        let mut table = t.controller.clone();
        let model_path = join(controller_path, "model");
        let model = match table.remove("model") {
            None => robot,
            Some(Value::Table(m)) => {
                overlay(robot.params(), &m, &model_path)?.validate().map_err(param_error(&model_path))?
            }
            Some(other) => {
                return Err(ScenarioError::new(model_path, format!("expected a table, got {}", other.type_str())));
            }
        };
        let controller = controller::resolve(&table, controller_path, &drive_params, model.params())?;
        let built =
            controller.build_lanes_in(model.params(), &drive, &obstacles).map_err(param_error(controller_path))?;
        AnySensor::<f64>::new(sensor, pose, model.params(), controller.control_dt, 0).map_err(param_error("sensor"))?;
        Ok(Self {
            robot,
            traction_params,
            traction,
            drive,
            world,
            sensor,
            pose,
            has_sensor: t.sensor.is_some(),
            model,
            controller,
            built,
            payload,
            truth,
            pushes,
            obstacles,
        })
    }

    /// The plant at rest at `start` (m, m, rad).
    pub fn plant(&self, start: Pose2<f64>) -> Result<Plant<f64>, wmr_core::ParamError> {
        if self.payload.appears_later() {
            // The robot alone until the payload appears, then `truth` ([`Plant::with_payload_at`]).
            let plant = Plant::on(self.robot, self.drive, self.world, start)?;
            return plant
                .with_traction(self.traction)
                .with_pushes(self.pushes)
                .with_payload_at(self.payload.t(), self.truth);
        }
        Ok(Plant::on(self.truth, self.drive, self.world, start)?.with_traction(self.traction).with_pushes(self.pushes))
    }

    /// True when the wheels slip (`robot.traction = "slip"`): outputs then carry the
    /// contact columns, and the fast path's lanes (rolling only) are not used.
    pub fn slips(&self) -> bool {
        matches!(self.traction, Traction::Slip(_))
    }

    /// A slip plant's RK4 sub-steps per plant step `dt` (s) with the dt * stiffness they
    /// come from ([`Plant::substeps`]: one while dt * stiffness < 2.785, else
    /// ceil(dt * stiffness / (0.9 x 2.785))); `None` for a rolling plant or a step
    /// [`Setup::check_step`] refuses.
    pub fn slip_substeps(&self, dt: f64) -> Option<(u32, f64)> {
        let plant = self.plant(Pose2::default()).ok()?;
        if !plant.slips() {
            return None;
        }
        Some((plant.substeps(dt)?, dt * plant.stiffness()))
    }

    /// Checks the plant step `dt` (s, `sim.dt`) against the plant's stiffness: RK4 is
    /// unstable beyond it. A Coulomb friction too sharp for the step names
    /// `robot.coulomb_speed` and says what would do. A slip plant splits a step its
    /// contacts are too stiff for into sub-steps ([`Setup::slip_substeps`]); a step
    /// that would need more than 1000 names `robot.slip_speed`.
    pub fn check_step(&self, dt: f64) -> Result<(), ScenarioError> {
        let plant = self.plant(Pose2::default()).map_err(param_error("run"))?;
        if plant.substeps(dt).is_some() {
            return Ok(());
        }
        let max_dt = plant.max_step_dt();
        if let Traction::Slip(_) = &self.traction {
            // The slip's stiffness (Slip::stiffness) falls as slip_speed (the contacts'
            // damping) or stiction_length (their spring) grows, though not in proportion:
            // the first value of either, raised by steps of 1 %, that the plant steps in
            // at most 1000 sub-steps at this dt, if one within a factor of 1000 does.
            let tp = &self.traction_params;
            let fits = |candidate: TractionParams<f64>| {
                candidate.validate(&self.truth, &self.world).is_ok_and(|t| {
                    Plant::on(self.truth, self.drive, self.world, Pose2::default())
                        .is_ok_and(|p| p.with_traction(t).substeps(dt).is_some())
                })
            };
            let raised = |value: f64, with: &dyn Fn(f64) -> TractionParams<f64>| {
                (1..=700).map(|k| value * 1.01f64.powi(k)).find(|&v| fits(with(v)))
            };
            let advice = if let Some(v) = raised(tp.slip_speed, &|v| TractionParams { slip_speed: v, ..*tp }) {
                format!("raise robot.slip_speed to {v:.3e} m/s or more, or lower sim.dt below {max_dt:.3e} s")
            } else if let Some(l) = raised(tp.stiction_length, &|l| TractionParams { stiction_length: l, ..*tp }) {
                format!("raise robot.stiction_length to {l:.3e} m or more, or lower sim.dt below {max_dt:.3e} s")
            } else {
                format!("lower sim.dt below {max_dt:.3e} s")
            };
            return Err(ScenarioError::new(
                "robot.slip_speed",
                format!(
                    "with friction_coefficient = {}, slip_speed = {} m/s, stiction_length = {} m and sim.dt = {dt} s \
                     the slip is too stiff for RK4 in {} sub-steps (dt * stiffness = {:.3} must be <= {:.1}, \
                     stiffness = {:.4e} 1/s): {advice}",
                    tp.friction_coefficient,
                    tp.slip_speed,
                    tp.stiction_length,
                    wmr_core::plant::MAX_SLIP_SUBSTEPS,
                    dt * plant.stiffness(),
                    f64::from(wmr_core::plant::MAX_SLIP_SUBSTEPS)
                        * wmr_core::plant::SLIP_SUBSTEP_SHARE
                        * wmr_core::integrator::RK4_REAL_STABILITY_LIMIT,
                    plant.stiffness()
                ),
            ));
        }
        let p = self.robot.params();
        let key = if p.coulomb_friction > 0.0 { "robot.coulomb_speed" } else { "sim.dt" };
        // stiffness = k b with b = b_v + tau_c / omega_eps + drive damping (Plant::stiffness):
        // the coulomb_speed that brings it to 90 % of the limit at this dt, if any does.
        let b_other = p.viscous_friction + self.drive.speed_damping();
        let b = b_other + p.coulomb_friction / p.coulomb_speed;
        let k = plant.stiffness() / b;
        let b_target = 0.9 * wmr_core::integrator::RK4_REAL_STABILITY_LIMIT / dt / k;
        let needed =
            (p.coulomb_friction > 0.0 && b_target > b_other).then(|| p.coulomb_friction / (b_target - b_other));
        let advice = match needed {
            Some(w) => format!("raise coulomb_speed to {w:.3e} rad/s or more, or lower sim.dt below {max_dt:.3e} s"),
            None => format!("lower sim.dt below {max_dt:.3e} s"),
        };
        Err(ScenarioError::new(
            key,
            format!(
                "with coulomb_friction = {} N m, coulomb_speed = {} rad/s and sim.dt = {dt} s the friction is too stiff \
                 for RK4 (dt * stiffness = {:.3} must be < 2.785, stiffness = {:.4e} 1/s): {advice}",
                p.coulomb_friction,
                p.coulomb_speed,
                dt * plant.stiffness(),
                plant.stiffness()
            ),
        ))
    }

    /// The value of a dotted numeric key in this configuration (`robot.mass`,
    /// `controller.model.wheel_radius`, `sensor.latency`, `controller.k_rho`), if it has one.
    pub fn value_of(&self, key: &str) -> Option<f64> {
        let (table, rest) = key.split_once('.')?;
        let t = match table {
            "robot" => {
                let mut t = to_table(self.robot.params());
                t.extend(to_table(&self.traction_params));
                t
            }
            "drive" => to_table(&self.drive.params()),
            "world" => match rest.strip_prefix("payload.") {
                Some(k) => return number(to_table(self.payload.params()).get(k)?),
                None => to_table(self.world.params()),
            },
            "sensor" => {
                let mut t = to_table(&self.sensor);
                t.extend(to_table(&self.pose));
                t
            }
            "controller" => match rest.strip_prefix("model.") {
                Some(k) => return number(to_table(self.model.params()).get(k)?),
                None => {
                    let mut t = to_table(&self.controller.law);
                    t.extend(to_table(&self.controller.wheels));
                    t.insert("control_dt".to_owned(), Value::Float(self.controller.control_dt));
                    t
                }
            },
            _ => return None,
        };
        number(t.get(rest)?)
    }

    /// The sensor of run `run` (its noise stream): the pose sensor, or odometry with the
    /// controller's model.
    pub fn sensor_for(&self, run: u64) -> Result<AnySensor<f64>, wmr_core::ParamError> {
        AnySensor::new(self.sensor, self.pose, self.model.params(), self.controller.control_dt, run)
    }

    /// The controller of run `run`: [`Setup::built`] (run 0's), or for a law that samples
    /// noise (MPPI) the controller drawing run `run`'s stream
    /// ([`wmr_core::controller::LawContext::run`], as [`Setup::sensor_for`] selects the sensor's).
    pub fn controller_for(&self, run: u64) -> Result<BuiltController, wmr_core::ParamError> {
        if run == 0 || !self.samples_noise() {
            return Ok(self.built);
        }
        self.controller.build_lanes_for_run(self.model.params(), &self.drive, &self.obstacles, run)
    }

    /// True when the law draws noise of its own, seeded per run (MPPI's samples): each
    /// run then has its own controller ([`Setup::controller_for`]), and the lanes of the
    /// fast path, which share one, do not run it.
    pub fn samples_noise(&self) -> bool {
        matches!(self.controller.law, wmr_core::LawParams::Mppi(_))
    }

    /// True when the controller's pose is dead reckoning (`[sensor] pose = "odometry"`):
    /// outputs then carry the odometry pose beside the fused one.
    pub fn odometry(&self) -> bool {
        self.pose.pose == PoseSource::Odometry
    }

    /// True when the controller sees the true state at every tick (the paper's sensor):
    /// what the lanes of the fast path assume.
    pub fn sensor_is_perfect(&self) -> bool {
        self.sensor.is_perfect() && !self.odometry()
    }
}
