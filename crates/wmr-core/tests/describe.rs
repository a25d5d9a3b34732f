//! The parameter declarations (`wmr_core::params!`): the rule text of each field is what
//! validation enforces, and `map`/`cast` visit every float field in declaration order.

use wmr_core::describe::{Described, ParamField};
use wmr_core::{
    DcMotorParams, DriveParams, ParamError, Robot, RobotParams, SensorParams, TorqueDriveParams, WorldParams,
};

/// `params` with its `k`-th float field (declaration order) replaced by `bad`.
fn with_field<P: Copy>(params: P, k: usize, bad: f64, map: impl Fn(P, &mut dyn FnMut(f64) -> f64) -> P) -> P {
    let mut i = 0;
    map(params, &mut |v| {
        let out = if i == k { bad } else { v };
        i += 1;
        out
    })
}

/// For every field whose rule starts with "> 0" (0 rejected) or ">= 0" (a negative value
/// rejected), and for NaN everywhere: validation fails and names that field.
fn rules_are_enforced<P: Copy + Described>(
    params: P,
    map: impl Fn(P, &mut dyn FnMut(f64) -> f64) -> P,
    validate: impl Fn(P) -> Result<(), ParamError>,
) {
    validate(params).expect("the defaults are valid");
    let fields: &[ParamField] = P::FIELDS;
    for (k, f) in fields.iter().enumerate() {
        let mut bad = vec![f64::NAN];
        if f.rule.starts_with("> 0") {
            bad.push(0.0);
        } else if f.rule.starts_with(">= 0") {
            bad.push(-1e-3);
        }
        for b in bad {
            let err = validate(with_field(params, k, b, &map)).expect_err(&format!("{} = {b} accepted", f.name));
            assert_eq!(err.field, f.name, "{} = {b} rejected as {err}", f.name);
        }
    }
}

#[test]
fn robot_rules_are_what_validate_checks() {
    rules_are_enforced(RobotParams::<f64>::paper(), |p, f| p.map(f), |p| p.validate().map(|_| ()));
}

#[test]
fn drive_and_world_rules_are_what_validate_checks() {
    let robot = Robot::<f64>::paper();
    rules_are_enforced(
        TorqueDriveParams::<f64>::default(),
        |p, f| p.map(f),
        |p| DriveParams::Torque(p).validate(&robot).map(|_| ()),
    );
    rules_are_enforced(
        DcMotorParams::<f64>::default(),
        |p, f| p.map(f),
        |p| DriveParams::DcMotor(p).validate(&robot).map(|_| ()),
    );
    rules_are_enforced(WorldParams::<f64>::default(), |p, f| p.map(f), |p| p.validate().map(|_| ()));
}

#[test]
fn cast_is_the_other_precisions_constructor() {
    assert_eq!(RobotParams::<f64>::paper().cast::<f32>(), RobotParams::<f32>::paper());
    assert_eq!(RobotParams::<f32>::paper().cast::<f64>(), RobotParams::<f32>::paper().map(f64::from));
    let sensor = SensorParams::<f64> { latency: 0.1, encoder_counts: 4096, seed: u64::MAX, ..Default::default() };
    let narrow: SensorParams<f32> = sensor.cast();
    assert_eq!((narrow.latency, narrow.encoder_counts, narrow.seed), (0.1f32, 4096, u64::MAX));
    assert!(narrow.rate_hz.is_infinite());
}

#[test]
fn every_field_has_a_doc_line_and_a_rule() {
    for f in RobotParams::<f64>::FIELDS.iter().chain(SensorParams::<f64>::FIELDS).chain(DcMotorParams::<f64>::FIELDS) {
        assert!(!f.doc.is_empty() && !f.doc.starts_with(' ') && !f.rule.is_empty(), "{f:?}");
    }
    let names: Vec<&str> = RobotParams::<f64>::FIELDS.iter().map(|f| f.name).collect();
    assert_eq!(names[..3], ["mass", "wheel_radius", "half_track"]);
}
