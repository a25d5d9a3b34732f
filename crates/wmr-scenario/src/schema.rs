//! Every key the parser accepts, listed from the types that read them, with the unit,
//! rule and doc line each type declares (`wmr_core::params!`): what `wmr-cli help keys` and the
//! `docs/scenario.md` tables are generated from, and the Python stubs checked against.

use std::borrow::Cow;

use toml::Value;
use wmr_core::describe::{Described, ParamField};
use wmr_core::{
    DriveParams, LawParams, OdometryParams, RobotParams, SensorParams, TractionParams, WheelStageParams, WorldParams,
};

use crate::file::{GridFile, PoseFile, RandomFile, RunFile, ScenarioFile, SimFile, SweepFile};
use crate::keys::{fields_of, to_table};
use crate::vary::VaryFile;

/// One accepted key.
#[derive(Clone, Debug, PartialEq)]
pub struct SchemaKey {
    /// The table it belongs to: `""` (top level), `robot`, `drive`, `controller`, `sensor`,
    /// `world`, `sim`, `run`, `pose` (the `start`/`goal` tables), `sweep`, `sweep.grid`,
    /// `sweep.random`, `sweep.vary`. `controller.model` takes the `robot` keys.
    pub table: &'static str,
    /// For `[drive]` and `[controller]`: the `kind` it belongs to; `None` for keys every
    /// kind accepts.
    pub kind: Option<&'static str>,
    /// The key.
    pub key: &'static str,
    /// Its default (as the file would write it), where it has a fixed one.
    pub default: Option<Value>,
    /// Where the default follows the drive (the wheel servo gains): each drive kind with
    /// its default; empty otherwise.
    pub default_by_drive: Vec<(&'static str, Value)>,
    /// Unit, doc line and rule, as declared; empty for keys of the tables the core does
    /// not declare (`[sim]`, `[[run]]`, `[sweep]`).
    pub unit: &'static str,
    /// See [`SchemaKey::unit`].
    pub doc: &'static str,
    /// See [`SchemaKey::unit`].
    pub rule: Cow<'static, str>,
}

impl SchemaKey {
    fn bare(table: &'static str, key: &'static str) -> Self {
        SchemaKey {
            table,
            kind: None,
            key,
            default: None,
            default_by_drive: Vec::new(),
            unit: "",
            doc: "",
            rule: Cow::Borrowed(""),
        }
    }

    fn described(table: &'static str, kind: Option<&'static str>, f: &ParamField, default: Option<Value>) -> Self {
        SchemaKey { kind, default, unit: f.unit, doc: f.doc, rule: Cow::Borrowed(f.rule), ..Self::bare(table, f.name) }
    }

    /// True for the keys a parameter struct of the core declares.
    pub fn is_described(&self) -> bool {
        !self.doc.is_empty()
    }
}

/// The keys a file names that are no field of a core parameter struct (`kind`,
/// `control_dt`, `model`), described here.
const CONTROL_DT: ParamField = ParamField {
    name: "control_dt",
    ty: "T",
    unit: "s",
    doc: "Control period: the law, the servos and the sensor tick at this rate.",
    rule: "> 0, a whole multiple of sim.dt",
};
const MODEL: ParamField = ParamField {
    name: "model",
    ty: "table",
    unit: "",
    doc: "The subtable [controller.model]: what the controller believes about the robot (any [robot] key; a key not given takes the [robot] value).",
    rule: "[robot] keys",
};

/// `[controller.observer]`'s `kind`, written `observer.kind` in the `[controller]` tables.
const OBSERVER_KIND: ParamField = ParamField {
    name: "observer.kind",
    ty: "string",
    unit: "",
    doc: "[controller.observer] (or observer = { .. } inline): \"disturbance\", a disturbance observer on the wheels whose estimate is subtracted from the commands (any law; no table: off).",
    rule: "\"disturbance\"",
};

/// The keys of one `[[world.push]]` (`wmr_core::push`), written `push.<key>` in the
/// `[world]` tables.
const PUSH_KEYS: [(ParamField, Option<&str>); 4] = [
    (
        ParamField {
            name: "push.t",
            ty: "T",
            unit: "s",
            doc: "[[world.push]]: when the push starts.",
            rule: "required, >= 0",
        },
        None,
    ),
    (
        ParamField {
            name: "push.duration",
            ty: "T",
            unit: "s",
            doc: "[[world.push]]: how long it lasts (pushes may overlap; they add).",
            rule: "required, > 0",
        },
        None,
    ),
    (
        ParamField {
            name: "push.force",
            ty: "table",
            unit: "N",
            doc: "[[world.push]]: the force at C, body frame (x forward, y left); the rolling plant's wheels take y.",
            rule: "{ x, y }, finite",
        },
        Some("{ x = 0.0, y = 0.0 }"),
    ),
    (
        ParamField {
            name: "push.torque",
            ty: "T",
            unit: "N m",
            doc: "[[world.push]]: the torque about the vertical (counter-clockwise +).",
            rule: "finite",
        },
        Some("0.0"),
    ),
];

/// `[robot] footprint_radius` (read by the scenario, not a field of `RobotParams`).
const FOOTPRINT_KEY: ParamField = ParamField {
    name: "footprint_radius",
    ty: "T",
    unit: "m",
    doc: "The robot's footprint for collisions with [[world.obstacle]]: a circle about C (nav2's robot_radius); by default half_track, the circle through the wheels' contact points.",
    rule: "finite, >= 0",
};

/// The keys of one `[[world.obstacle]]` (`wmr_core::obstacle`), written
/// `obstacle.<key>` in the `[world]` tables.
const OBSTACLE_KEYS: [(ParamField, Option<&str>); 4] = [
    (
        ParamField {
            name: "obstacle.kind",
            ty: "string",
            unit: "",
            doc: "[[world.obstacle]]: \"circle\" (center, radius) or \"polygon\" (points); a run whose footprint touches one ends collided.",
            rule: "required, \"circle\" or \"polygon\"",
        },
        None,
    ),
    (
        ParamField {
            name: "obstacle.center",
            ty: "table",
            unit: "m",
            doc: "[[world.obstacle]] circle: its centre, world frame.",
            rule: "{ x, y }, finite",
        },
        None,
    ),
    (
        ParamField {
            name: "obstacle.radius",
            ty: "T",
            unit: "m",
            doc: "[[world.obstacle]] circle: its radius.",
            rule: "> 0",
        },
        None,
    ),
    (
        ParamField {
            name: "obstacle.points",
            ty: "array",
            unit: "m",
            doc: "[[world.obstacle]] polygon: its vertices [[x, y], ...] in order, world frame (at most 16 obstacles and 32 polygon vertices in all).",
            rule: "3 to 32 vertices, finite",
        },
        None,
    ),
];

/// The `kind` key of a tagged table whose kinds are `kinds` (the first the default).
fn kind_key(table: &'static str, doc: &'static str, kinds: &[&'static str]) -> SchemaKey {
    let quoted: Vec<String> = kinds.iter().map(|k| format!("\"{k}\"")).collect();
    let rule = match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => quoted.join(""),
    };
    SchemaKey {
        default: kinds.first().map(|&k| Value::from(k)),
        doc,
        rule: Cow::Owned(rule),
        ..SchemaKey::bare(table, "kind")
    }
}

/// The keys of a declared struct with the defaults of `defaults`.
fn declared<P: serde::Serialize>(
    table: &'static str,
    kind: Option<&'static str>,
    fields: &'static [ParamField],
    defaults: &P,
) -> impl Iterator<Item = SchemaKey> {
    let t = to_table(defaults);
    fields.iter().map(move |f| SchemaKey::described(table, kind, f, t.get(f.name).cloned()))
}

/// The keys of `[reference]` ([`crate::reference::REFERENCE_KEYS`]); the rule names the
/// kinds that read each key.
fn reference_keys() -> impl Iterator<Item = SchemaKey> {
    crate::reference::REFERENCE_KEYS.iter().map(|k| {
        let default = (!k.default.is_empty())
            .then(|| toml::from_str::<toml::Table>(&format!("v = {}", k.default)).ok()?.remove("v"))
            .flatten();
        SchemaKey {
            default,
            unit: k.unit,
            doc: k.doc,
            rule: Cow::Owned(if k.kinds == "all" { "required".to_owned() } else { format!("kind = {}", k.kinds) }),
            ..SchemaKey::bare("reference", k.name)
        }
    })
}

/// Every key of every table, in file order.
pub fn schema() -> Vec<SchemaKey> {
    let plain = |table, keys: &'static [&'static str]| keys.iter().map(move |&key| SchemaKey::bare(table, key));
    let mut out: Vec<SchemaKey> = Vec::new();
    out.extend(plain("", fields_of::<ScenarioFile>()).filter(|k| k.key == "name"));
    out.extend(declared("robot", None, RobotParams::<f64>::FIELDS, &RobotParams::<f64>::paper()));
    out.extend(declared("robot", None, TractionParams::<f64>::FIELDS, &TractionParams::<f64>::default()));
    out.push(SchemaKey::described("robot", None, &FOOTPRINT_KEY, None));
    let drives = DriveParams::<f64>::defaults();
    out.push(kind_key(
        "drive",
        "The drive model: what turns a servo command into a wheel torque.",
        &drives.map(|d| d.kind()),
    ));
    for d in drives {
        out.extend(declared("drive", Some(d.kind()), d.fields(), &d));
    }
    let laws = LawParams::<f64>::defaults();
    out.push(kind_key("controller", "The outer law.", &laws.map(|l| l.kind())));
    for law in laws {
        out.extend(declared("controller", Some(law.kind()), law.fields(), &law));
    }
    // The wheel stage's defaults follow the drive (on the paper's robot: a DC motor's
    // depend on the gear ratio too): fixed where every drive agrees.
    let robot = wmr_core::RobotParams::paper();
    let by_drive: Vec<(&'static str, toml::Table)> =
        drives.iter().map(|d| (d.kind(), to_table(&WheelStageParams::for_drive(d, &robot)))).collect();
    for f in WheelStageParams::<f64>::FIELDS {
        let values: Vec<(&'static str, Value)> =
            by_drive.iter().filter_map(|(kind, t)| Some((*kind, t.get(f.name)?.clone()))).collect();
        let same = values.windows(2).all(|w| w[0].1 == w[1].1);
        let mut key = SchemaKey::described("controller", None, f, None);
        if same {
            key.default = values.first().map(|(_, v)| v.clone());
        } else {
            key.default_by_drive = values;
        }
        out.push(key);
    }
    let control_dt = Value::Float(wmr_core::ControllerParams::<f64>::default_control_dt());
    out.push(SchemaKey::described("controller", None, &CONTROL_DT, Some(control_dt)));
    out.push(SchemaKey::described("controller", None, &MODEL, None));
    // `[controller.observer]`, written `observer.bandwidth` and so on in `[controller]`.
    out.push(SchemaKey::described("controller", None, &OBSERVER_KIND, Some(Value::String("disturbance".to_owned()))));
    let observer = wmr_core::DisturbanceObserverParams::<f64>::default();
    out.extend(declared("controller", None, wmr_core::DisturbanceObserverParams::<f64>::FIELDS, &observer).map(
        |mut k| {
            k.key = wmr_core::DisturbanceObserverParams::<f64>::scenario_field(k.key);
            k
        },
    ));
    out.extend(declared("sensor", None, SensorParams::<f64>::FIELDS, &SensorParams::<f64>::default()));
    out.extend(declared("sensor", None, OdometryParams::<f64>::FIELDS, &OdometryParams::<f64>::default()));
    out.extend(declared("world", None, WorldParams::<f64>::FIELDS, &WorldParams::<f64>::default()));
    // `[world.payload]`, written `payload.mass` and so on (TOML's dotted keys) in `[world]`.
    out.extend(
        declared("world", None, wmr_core::PayloadParams::<f64>::FIELDS, &wmr_core::PayloadParams::<f64>::default())
            .map(|mut k| {
                k.key = match k.key {
                    "mass" => "payload.mass",
                    "x" => "payload.x",
                    "y" => "payload.y",
                    _ => "payload.t",
                };
                k
            }),
    );
    out.extend(PUSH_KEYS.iter().map(|(f, default)| {
        let default = default.and_then(|d| toml::from_str::<toml::Table>(&format!("v = {d}")).ok()?.remove("v"));
        SchemaKey::described("world", None, f, default)
    }));
    out.extend(OBSTACLE_KEYS.iter().map(|(f, default)| {
        let default = default.and_then(|d| toml::from_str::<toml::Table>(&format!("v = {d}")).ok()?.remove("v"));
        SchemaKey::described("world", None, f, default)
    }));
    out.extend(reference_keys());
    out.extend(plain("sim", fields_of::<SimFile>()));
    out.extend(plain("run", fields_of::<RunFile>()));
    out.extend(plain("pose", fields_of::<PoseFile>()));
    out.extend(plain("sweep", fields_of::<SweepFile>()));
    out.extend(plain("sweep.grid", fields_of::<GridFile>()));
    out.extend(plain("sweep.random", fields_of::<RandomFile>()));
    out.extend(plain("sweep.vary", fields_of::<VaryFile>()));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keys::fields_read_by;

    fn names(fields: &[ParamField]) -> Vec<&'static str> {
        fields.iter().map(|f| f.name).collect()
    }

    /// The declared fields are the keys serde reads, in the same order: the parser
    /// accepts exactly what the tables document.
    #[test]
    fn declared_fields_are_the_keys_serde_reads() {
        assert_eq!(names(RobotParams::<f64>::FIELDS), fields_of::<RobotParams<f64>>());
        assert_eq!(names(TractionParams::<f64>::FIELDS), fields_of::<TractionParams<f64>>());
        assert_eq!(names(SensorParams::<f64>::FIELDS), fields_of::<SensorParams<f64>>());
        assert_eq!(names(OdometryParams::<f64>::FIELDS), fields_of::<OdometryParams<f64>>());
        assert_eq!(names(WorldParams::<f64>::FIELDS), fields_of::<WorldParams<f64>>());
        assert_eq!(names(WheelStageParams::<f64>::FIELDS), fields_of::<WheelStageParams<f64>>());
        for d in DriveParams::<f64>::defaults() {
            assert_eq!(names(d.fields()), fields_read_by(|p| d.deserialize_variant(p).map(|_| ())), "{}", d.kind());
        }
        for law in LawParams::<f64>::defaults() {
            let read = fields_read_by(|p| law.deserialize_variant(p).map(|_| ()));
            assert_eq!(names(law.fields()), read, "{}", law.kind());
        }
    }

    #[test]
    fn servo_defaults_and_the_limit_follow_the_drive() {
        let keys = schema();
        let key = |name: &str| keys.iter().find(|k| k.key == name).unwrap();
        let near = |v: &Value, want: f64| v.as_float().is_some_and(|v| (v - want).abs() < 0.01 * want);
        for (name, torque, dc) in
            [("servo_kp", 14.0, 81.5), ("servo_kd", 1.4, 7.58), ("wheel_speed_max", f64::INFINITY, 20.94)]
        {
            let by = &key(name).default_by_drive;
            assert_eq!(key(name).default, None, "{name}");
            assert_eq!((by[0].0, by[1].0), ("torque", "dc_motor"), "{name}");
            assert_eq!(by[0].1, Value::Float(torque), "{name}");
            assert!(near(&by[1].1, dc), "{name}: {by:?}");
        }
    }
}
