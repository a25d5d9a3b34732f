//! Issue 44: a bad log is refused naming the column or the time (missing column,
//! non-monotonic time, NaN, no excitation).

use wmr_core::DcMotorParams;
use wmr_core::RobotParams;
use wmr_identify::{ColumnNames, CommandKind, FitSettings, IdentifyError, Log, Table, fit};

fn csv(text: &str) -> Table {
    Table::read_csv(text.as_bytes()).unwrap()
}

fn read(text: &str) -> Result<Log, IdentifyError> {
    Log::from_table(&csv(text), &ColumnNames::default(), CommandKind::Torque)
}

#[test]
fn issue_44_missing_column_is_named() {
    let e = read("t,tau_r,tau_l,phi_r\n0,1,1,0\n").unwrap_err();
    assert_eq!(e.to_string(), "log: missing column `phi_l or position_l (or omega_l or velocity_l)`");
    let e = read("t,tau_r,phi_r,phi_l\n0,1,0,0\n").unwrap_err();
    assert!(e.to_string().contains("`tau_l or effort_l`"), "{e}");
    let e =
        Log::from_table(&csv("t,tau_r,tau_l,phi_r,phi_l\n0,1,1,0,0\n"), &ColumnNames::default(), CommandKind::Voltage)
            .unwrap_err();
    assert!(e.to_string().contains("`u_r or voltage_r`"), "{e}");
}

#[test]
fn issue_44_time_going_back_is_named_with_its_time() {
    let e = read("t,tau_r,tau_l,phi_r,phi_l\n0,1,1,0,0\n0.01,1,1,0,0\n0.01,1,1,0,0\n").unwrap_err();
    assert_eq!(
        e.to_string(),
        "log: column `t` at t = 0.01 s (row 3): time does not increase (the row before is at 0.01 s)"
    );
    // A new run may start its time again.
    let ok = read("run,t,tau_r,tau_l,phi_r,phi_l\n0,0,1,1,0,0\n0,0.01,1,1,0,0\n1,0,1,1,0,0\n").unwrap();
    assert_eq!(ok.runs.len(), 2);
}

#[test]
fn issue_44_nan_is_named_with_its_column_and_time() {
    let e = read("t,tau_r,tau_l,phi_r,phi_l\n0,1,1,0,0\n0.01,1,1,NaN,0\n").unwrap_err();
    assert_eq!(e.to_string(), "log: column `phi_r` at t = 0.01 s (row 2): not a finite number");
    let e = read("t,tau_r,tau_l,phi_r,phi_l\n0,1,1,0,0\n0.01,1,,0,0\n").unwrap_err();
    assert!(e.to_string().starts_with("log: column `tau_l` at t = 0.01 s"), "{e}");
    let e = Table::read_csv("t,tau_r,tau_l,phi_r,phi_l\n0,1,1,0,0\nx,1,1,0,0\n".as_bytes()).unwrap_err();
    assert!(e.to_string().contains("column `t` row 2: `x` is not a number"), "{e}");
}

fn steady(cmd: f64, speed: f64) -> String {
    let mut s = String::from("t,tau_r,tau_l,phi_r,phi_l\n");
    for i in 0..200 {
        let t = i as f64 * 0.01;
        s += &format!("{t},{cmd},{cmd},{},{}\n", speed * t, speed * t);
    }
    s
}

#[test]
fn issue_44_a_log_without_excitation_is_refused() {
    let settings = FitSettings::new(CommandKind::Torque, RobotParams::paper(), DcMotorParams::default());
    let e = fit(&read(&steady(0.0, 1.0)).unwrap(), &settings).unwrap_err();
    assert_eq!(e.to_string(), "log: no excitation in column `tau_r`: every command (tau_r and tau_l) is zero");
    let e = fit(&read(&steady(1.0, 0.0)).unwrap(), &settings).unwrap_err();
    assert_eq!(e.to_string(), "log: no excitation in column `phi_r`: the wheels never turn");
    // Turning at a steady speed: nothing accelerates, so no inertia can be told.
    let e = fit(&read(&steady(1.0, 2.0)).unwrap(), &settings).unwrap_err();
    assert!(matches!(e, IdentifyError::NotIdentifiable { .. }), "{e}");
}
