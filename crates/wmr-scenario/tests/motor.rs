//! Issue 24 (motors from a datasheet): the default DC motor changed (Pololu 37D 50:1,
//! `wmr_core::DcMotorParams`) and with it the DC servo gains; a scenario that names every
//! motor key and the servo gains keeps its results.

use wmr_scenario::Scenario;

/// Fig. 7's manoeuvre with the earlier default motor (maxon RE 40 24 V) and its servo
/// gains named key by key.
const OLD_MOTOR: &str = r#"
[drive]
kind = "dc_motor"
voltage_max = 24.0
torque_constant = 0.0302
back_emf_constant = 0.0302
armature_resistance = 0.299
current_max = inf
[controller]
servo_kp = 14.0
servo_kd = 1.1
[sim]
t_end = 20.0
log_dt = 0.01
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }
"#;

/// The last sample at t = 20 s, as `wmr-cli run` of commit 96ef285 (before the new
/// defaults) wrote it to CSV (shortest round-trip decimals, so these are its exact bits):
/// x, y, theta, v, omega, phi_r, phi_l.
const OLD_FINAL: [f64; 7] = [
    1.109267842589111,
    0.9328561027640705,
    2.443510823835571,
    0.014849661231327667,
    0.04421237101129759,
    24.47650129555744,
    14.702458000215083,
];

#[test]
fn issue_24_a_scenario_naming_every_motor_key_keeps_its_results() {
    let s = Scenario::from_toml_str(OLD_MOTOR, "old-motor").unwrap();
    let mut last = None;
    s.run(0, |sample| last = Some(*sample)).unwrap();
    let st = last.expect("samples").state;
    let got = [st.x, st.y, st.theta, st.v, st.omega, st.phi_r, st.phi_l];
    assert_eq!(got.map(f64::to_bits), OLD_FINAL.map(f64::to_bits), "{got:?}");
    // The new defaults are a different motor: without its voltage key the run differs.
    let new = Scenario::from_toml_str(&OLD_MOTOR.replace("voltage_max = 24.0\n", ""), "new").unwrap();
    let mut last_new = None;
    new.run(0, |sample| last_new = Some(*sample)).unwrap();
    assert_ne!(last_new.unwrap().state.x.to_bits(), OLD_FINAL[0].to_bits());
}
