//! The `reference=` argument of the controllers' `update`: the reference state (pose,
//! twist, acceleration) the law tracks at this tick, the goal at rest when omitted.

use numpy::PyUntypedArrayMethods;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use wmr_core::{Pose2, ReferenceState, Twist2};

use crate::alloc::{bytes_of, check_alloc, vec_with_capacity};
use crate::convert::{batch_arg, finite_array, real_number};
use crate::error::parameter_error;

/// The reference's seven numbers, in the order of a row: the pose (x m, y m, theta rad),
/// the twist (v m/s, omega rad/s) and the acceleration (v' m/s^2, omega' rad/s^2).
pub const REFERENCE_FIELDS: [&str; 7] = [
    "reference.pose.x",
    "reference.pose.y",
    "reference.pose.theta",
    "reference.twist.v",
    "reference.twist.omega",
    "reference.accel.v",
    "reference.accel.omega",
];

fn from_row(r: [f64; 7]) -> ReferenceState<f64> {
    ReferenceState {
        pose: Pose2::new(r[0], r[1], r[2]),
        twist: Twist2 { v: r[3], omega: r[4] },
        accel: Twist2 { v: r[5], omega: r[6] },
    }
}

/// One part (`pose`, `twist` or `accel`) of a dict reference: a dict of its fields or a
/// sequence of them, each a finite real number.
fn part<const K: usize>(obj: &Bound<'_, PyAny>, names: [&str; K]) -> PyResult<[f64; K]> {
    let Ok(d) = obj.cast::<PyDict>() else {
        let arg = names[0].rsplit_once('.').map_or(names[0], |(p, _)| p);
        return finite_array(obj, arg, names);
    };
    let mut out = [0.0; K];
    for (v, name) in out.iter_mut().zip(names) {
        let short = name.rsplit('.').next().unwrap_or(name);
        let item = d.get_item(short)?.ok_or_else(|| parameter_error(name, "missing"))?;
        *v = real_number(&item, name)?;
        if !v.is_finite() {
            return Err(parameter_error(name, format_args!("must be a finite number (got {v})")));
        }
    }
    for key in d.keys() {
        let key: String = key.str()?.extract()?;
        if !names.iter().any(|n| n.rsplit('.').next() == Some(key.as_str())) {
            let arg = names[0].rsplit_once('.').map_or(names[0], |(p, _)| p);
            return Err(parameter_error(&format!("{arg}.{key}"), "unknown field"));
        }
    }
    Ok(out)
}

/// The references of an update of `n` robots: one (broadcast to every robot) or `n`.
///
/// `None`: the goal at rest. A dict `{"pose": .., "twist": .., "accel": ..}` (each part a
/// dict of its fields or a sequence; a missing part is the goal's pose, or zero twist or
/// acceleration); a row of 7 numbers (x, y, theta, v, omega, v', omega'); or an (N, 7)
/// or (1, 7) array. Bad or non-finite values raise ParameterError naming the field.
pub fn reference_arg(obj: Option<&Bound<'_, PyAny>>, goal: Pose2<f64>, n: usize) -> PyResult<Vec<ReferenceState<f64>>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(vec![ReferenceState::at_rest(goal)]);
    };
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut r = ReferenceState::at_rest(goal);
        for (key, value) in d.iter() {
            let key: String = key.str()?.extract()?;
            match key.as_str() {
                "pose" => {
                    let [x, y, theta] = part(&value, [REFERENCE_FIELDS[0], REFERENCE_FIELDS[1], REFERENCE_FIELDS[2]])?;
                    r.pose = Pose2::new(x, y, theta);
                }
                "twist" => {
                    let [v, omega] = part(&value, [REFERENCE_FIELDS[3], REFERENCE_FIELDS[4]])?;
                    r.twist = Twist2 { v, omega };
                }
                "accel" => {
                    let [v, omega] = part(&value, [REFERENCE_FIELDS[5], REFERENCE_FIELDS[6]])?;
                    r.accel = Twist2 { v, omega };
                }
                other => {
                    return Err(parameter_error(
                        &format!("reference.{other}"),
                        "unknown part: expected pose, twist and accel",
                    ));
                }
            }
        }
        return Ok(vec![r]);
    }
    if let Some(a) = batch_arg(obj, "reference", REFERENCE_FIELDS)? {
        let rows = a.shape()[0];
        if rows != 1 && rows != n {
            return Err(parameter_error(
                "reference",
                format_args!("has {rows} rows: expected 1 (for every robot) or {n} (one per robot)"),
            ));
        }
        let a = a.as_array();
        check_alloc(bytes_of::<ReferenceState<f64>>(rows), "reference", || format!("{rows} reference states"))?;
        let mut out = vec_with_capacity(rows, "reference", "reference states")?;
        out.extend(a.rows().into_iter().map(|r| from_row(std::array::from_fn(|j| r[j]))));
        return Ok(out);
    }
    Ok(vec![from_row(finite_array(obj, "reference", REFERENCE_FIELDS)?)])
}
