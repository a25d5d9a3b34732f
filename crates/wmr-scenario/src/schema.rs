//! Every key the parser accepts, listed from the types that read them: what `--help`,
//! `docs/scenario.md` and the Python stubs are checked against.

use toml::Value;
use wmr_core::{DriveParams, LawParams, RobotParams, SensorParams, WheelStageParams, WorldParams};

use crate::file::{GridFile, PoseFile, RandomFile, RunFile, ScenarioFile, SimFile, SweepFile};
use crate::keys::{fields_of, fields_read_by, to_table};
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
}

fn plain(table: &'static str, keys: &'static [&'static str]) -> impl Iterator<Item = SchemaKey> {
    keys.iter().map(move |&key| SchemaKey { table, kind: None, key, default: None })
}

/// Every key of every table, in file order.
pub fn schema() -> Vec<SchemaKey> {
    let mut out: Vec<SchemaKey> = Vec::new();
    out.extend(plain("", fields_of::<ScenarioFile>()).filter(|k| k.key == "name"));
    let robot = to_table(&RobotParams::<f64>::paper());
    out.extend(fields_of::<RobotParams<f64>>().iter().map(|&key| SchemaKey {
        table: "robot",
        kind: None,
        key,
        default: robot.get(key).cloned(),
    }));
    out.push(SchemaKey { table: "drive", kind: None, key: "kind", default: Some(Value::from("torque")) });
    for d in DriveParams::<f64>::defaults() {
        let t = to_table(&d);
        let fields = fields_read_by(|p| d.deserialize_variant(p).map(|_| ()));
        out.extend(fields.iter().map(|&key| SchemaKey {
            table: "drive",
            kind: Some(d.kind()),
            key,
            default: t.get(key).cloned(),
        }));
    }
    out.push(SchemaKey { table: "controller", kind: None, key: "kind", default: Some(Value::from("paper")) });
    for law in LawParams::<f64>::defaults() {
        let t = to_table(&law);
        let fields = fields_read_by(|p| law.deserialize_variant(p).map(|_| ()));
        out.extend(fields.iter().map(|&key| SchemaKey {
            table: "controller",
            kind: Some(law.kind()),
            key,
            default: t.get(key).cloned(),
        }));
    }
    // Servo defaults follow the drive: only the limit has one fixed default.
    let wheels = to_table(&WheelStageParams::<f64>::default());
    out.extend(fields_of::<WheelStageParams<f64>>().iter().map(|&key| SchemaKey {
        table: "controller",
        kind: None,
        key,
        default: (key == "wheel_speed_max").then(|| wheels.get(key).cloned()).flatten(),
    }));
    out.push(SchemaKey {
        table: "controller",
        kind: None,
        key: "control_dt",
        default: Some(Value::Float(wmr_core::ControllerParams::<f64>::default_control_dt())),
    });
    out.push(SchemaKey { table: "controller", kind: None, key: "model", default: None });
    let sensor = to_table(&SensorParams::<f64>::default());
    out.extend(fields_of::<SensorParams<f64>>().iter().map(|&key| SchemaKey {
        table: "sensor",
        kind: None,
        key,
        default: sensor.get(key).cloned(),
    }));
    let world = to_table(&WorldParams::<f64>::default());
    out.extend(fields_of::<WorldParams<f64>>().iter().map(|&key| SchemaKey {
        table: "world",
        kind: None,
        key,
        default: world.get(key).cloned(),
    }));
    out.extend(plain("sim", fields_of::<SimFile>()));
    out.extend(plain("run", fields_of::<RunFile>()));
    out.extend(plain("pose", fields_of::<PoseFile>()));
    out.extend(plain("sweep", fields_of::<SweepFile>()));
    out.extend(plain("sweep.grid", fields_of::<GridFile>()));
    out.extend(plain("sweep.random", fields_of::<RandomFile>()));
    out.extend(plain("sweep.vary", fields_of::<VaryFile>()));
    out
}
