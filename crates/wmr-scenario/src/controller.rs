//! `[controller]`: `kind` picks the law; the table holds, flat, the law's keys, the wheel
//! stage's keys and `control_dt`. Which key belongs to which part is read from the
//! core's types ([`LawParams`], [`WheelStageParams`]), so a new law or wheel-stage key
//! needs no change here.

use serde::Deserialize;
use toml::{Table, Value};
use wmr_core::{ControllerParams, DisturbanceObserverParams, DriveParams, LawParams, RobotParams, WheelStageParams};

use crate::error::ScenarioError;
use crate::keys::{
    fields_of, fields_read_by, join, kind_of, overlay, overlay_table, read_with, to_table, toml_f64, unknown_key,
    write_keys_noted,
};

/// The `kind` names of every law, in documentation order.
pub fn law_kinds() -> Vec<&'static str> {
    LawParams::<f64>::defaults().iter().map(LawParams::kind).collect()
}

/// The point-stabilization laws' `kind` names: a `[sweep]` without `controllers` and
/// without a `[reference]` compares these.
pub fn stabilization_law_kinds() -> Vec<&'static str> {
    LawParams::<f64>::defaults().iter().filter(|l| !l.follows().needs_reference()).map(LawParams::kind).collect()
}

/// The laws that may follow a `[reference]` (the tracking and path-following laws, and
/// MPPI, which follows a goal or a path).
pub fn reference_law_kinds() -> Vec<&'static str> {
    LawParams::<f64>::defaults().iter().filter(|l| l.follows().accepts_reference()).map(LawParams::kind).collect()
}

/// The tracking and path-following laws' `kind` names (they need a `[reference]`).
pub fn tracking_law_kinds() -> Vec<&'static str> {
    LawParams::<f64>::defaults().iter().filter(|l| l.follows().needs_reference()).map(LawParams::kind).collect()
}

/// The keys of law `kind` (without `kind`), the wheel stage's keys and `control_dt`:
/// everything a `[controller]` table of that kind accepts besides `kind`.
pub fn controller_keys(kind: &str) -> Vec<String> {
    let law = LawParams::<f64>::defaults().into_iter().find(|d| d.kind() == kind);
    let mut keys: Vec<String> = law.map(|l| law_table(&l).keys().cloned().collect()).unwrap_or_default();
    keys.extend(to_table(&WheelStageParams::<f64>::default()).keys().cloned());
    keys.push("control_dt".to_owned());
    keys.push("model".to_owned());
    keys.push("observer".to_owned());
    keys
}

/// The `kind` names of `[controller.observer]`.
pub const OBSERVER_KINDS: [&str; 1] = ["disturbance"];

/// `[controller.observer]` (or `observer = { .. }` inline) at `path`
/// (`controller.observer`): `kind = "disturbance"` (the default) and its keys
/// ([`DisturbanceObserverParams`]); the build checks the values (`path.bandwidth`).
fn resolve_observer(given: Value, path: &str) -> Result<DisturbanceObserverParams<f64>, ScenarioError> {
    let Value::Table(mut table) = given else {
        return Err(ScenarioError::new(path, format!("expected a table, got {}", given.type_str())));
    };
    kind_of(&table, path, OBSERVER_KINDS[0], &OBSERVER_KINDS)?;
    table.remove("kind");
    overlay(&DisturbanceObserverParams::<f64>::default(), &table, path)
}

/// A law's keys and defaults as a table, without `kind`.
fn law_table(law: &LawParams<f64>) -> Table {
    let mut t = to_table(law);
    t.remove("kind");
    t
}

/// Reads a `[controller]` table at `path` (`controller`, `sweep.controllers[1]`); the
/// wheel stage's defaults follow the drive and the controller's robot `model`.
pub fn resolve(
    given: &Table,
    path: &str,
    drive: &DriveParams<f64>,
    model: &RobotParams<f64>,
) -> Result<ControllerParams<f64>, ScenarioError> {
    let kinds = law_kinds();
    let kind = kind_of(given, path, "paper", &kinds)?;
    let law_default = LawParams::<f64>::defaults()
        .into_iter()
        .find(|d| d.kind() == kind)
        .ok_or_else(|| ScenarioError::new(join(path, "kind"), "unknown kind"))?;
    let law_defaults = law_table(&law_default);
    let wheels_default = WheelStageParams::for_drive(drive, model);
    let wheel_defaults = to_table(&wheels_default);
    let (mut law_given, mut wheels_given, mut control_dt) = (Table::new(), Table::new(), None);
    let mut observer = None;
    for (k, v) in given {
        if k == "kind" {
            continue;
        } else if law_defaults.contains_key(k) {
            law_given.insert(k.clone(), v.clone());
        } else if wheel_defaults.contains_key(k) {
            wheels_given.insert(k.clone(), v.clone());
        } else if k == "control_dt" {
            control_dt = Some(v.clone());
        } else if k == "observer" {
            observer = Some(resolve_observer(v.clone(), &join(path, "observer"))?);
        } else {
            let accepted = controller_keys(kind);
            return Err(unknown_key(path, k, accepted.iter().map(String::as_str)));
        }
    }
    let law_merged = overlay_table(&law_defaults, &law_given, path)?;
    let law = read_with(path, Value::Table(law_merged), |d| law_default.deserialize_variant(d))?;
    let wheels = overlay(&wheels_default, &wheels_given, path)?;
    let control_dt = match control_dt {
        None => ControllerParams::<f64>::default_control_dt(),
        Some(v) => read_with(&join(path, "control_dt"), v, |d| f64::deserialize(d))?,
    };
    Ok(ControllerParams { law, wheels, control_dt, observer })
}

/// The `[controller]` table's lines, every key written: `kind`, the law's keys, the
/// wheel stage's keys, `control_dt`.
pub fn write(params: &ControllerParams<f64>, out: &mut String, note: impl Fn(&str) -> Option<String>) {
    let mut t = Table::new();
    t.insert("kind".to_owned(), Value::String(params.law.kind().to_owned()));
    write_keys_noted(out, &t, &[], &note);
    let law_order = fields_read_by(|probe| params.law.deserialize_variant(probe).map(|_| ()));
    write_keys_noted(out, &law_table(&params.law), law_order, &note);
    write_keys_noted(out, &to_table(&params.wheels), fields_of::<WheelStageParams<f64>>(), &note);
    t.clear();
    t.insert("control_dt".to_owned(), Value::Float(params.control_dt));
    write_keys_noted(out, &t, &[], &note);
    if let Some(o) = &params.observer {
        // The pre-compensation's keys only when it is on (the line as before when off).
        let pre = if o.deadband != 0.0 || o.static_friction != 0.0 {
            format!(
                ", deadband = {}, static_friction = {}, precompensation_band = {}",
                toml_f64(o.deadband),
                toml_f64(o.static_friction),
                toml_f64(o.precompensation_band)
            )
        } else {
            String::new()
        };
        let line =
            format!("observer = {{ kind = \"{}\", bandwidth = {}{pre} }}", OBSERVER_KINDS[0], toml_f64(o.bandwidth));
        match note("observer") {
            Some(n) => out.push_str(&format!("{line:<32}# {n}\n")),
            None => out.push_str(&format!("{line}\n")),
        }
    }
}

/// [`write`] for `wmr-cli check`: each key noted by `note` (where its value came from),
/// except the wheel stage's keys at the value the drive and the controller's robot
/// `model` derive, noted with the rule ([`derived_note`]) and commented out.
pub fn write_noted(
    params: &ControllerParams<f64>,
    drive: &DriveParams<f64>,
    model: &RobotParams<f64>,
    out: &mut String,
    note: impl Fn(&str) -> Option<String>,
) {
    let derived = to_table(&WheelStageParams::for_drive(drive, model));
    let wheels = to_table(&params.wheels);
    let rule = |k: &str| derived.contains_key(k) && derived.get(k) == wheels.get(k);
    let mut own = String::new();
    write(params, &mut own, |k| rule(k).then(|| derived_note(k, drive, model)).flatten().or_else(|| note(k)));
    // A derived key is written commented out: read back, it is derived again from the run's
    // drive and model (a sweep that varies controller.model re-derives its gains; a value
    // written out would hold them fixed).
    for line in own.lines() {
        let key = line.split(" = ").next().unwrap_or_default();
        let commented = rule(key) && derived_note(key, drive, model).is_some();
        out.push_str(if commented { "# " } else { "" });
        out.push_str(line);
        out.push('\n');
    }
}

/// The rule a derived wheel-stage default follows ([`WheelStageParams::for_drive`]), with
/// its figures, for `wmr-cli check`: the paper's robot's 14 N m/rad and 1.4 N m s/rad
/// scaled by the robot's inertia at the wheel J_w, through the motor where there is one.
fn derived_note(key: &str, drive: &DriveParams<f64>, model: &RobotParams<f64>) -> Option<String> {
    let j = model.validate().ok()?.driven_wheel_inertia();
    let j_paper = wmr_core::Robot::<f64>::paper().driven_wheel_inertia();
    let scale = format!("x J_w / {j_paper:.4} kg m^2 (J_w = {j:.4} kg m^2: the robot's inertia at the wheel)");
    match (drive, key) {
        (DriveParams::Torque(_), "servo_kp") => Some(format!("derived: 14 N m/rad {scale}")),
        (DriveParams::Torque(_), "servo_kd") => Some(format!("derived: 1.4 N m s/rad {scale}")),
        (DriveParams::DcMotor(m), _) => {
            let b = m.torque_constant / (m.armature_resistance * model.gear_ratio);
            let emf = b * m.back_emf_constant / model.gear_ratio;
            let via = format!("b = {b:.4} N m/V at the wheel");
            match key {
                "servo_kp" => {
                    let w_b = wmr_core::ServoGains::<f64>::paper_bandwidth();
                    Some(format!("derived: max(14 N m/rad {scale}, {emf:.4} back-EMF x {w_b:.2} rad/s) / b, {via}"))
                }
                "servo_kd" => {
                    Some(format!("derived: max(1.4 N m s/rad x J_w / {j_paper:.4} - {emf:.4} back-EMF, 0) / b, {via}"))
                }
                "wheel_speed_max" => {
                    Some("derived: the motor's no-load speed at the wheel, voltage_max k_t / k_e".to_owned())
                }
                _ => None,
            }
        }
        _ => None,
    }
}
