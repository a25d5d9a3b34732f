//! Issue 25, item 8: the pose sensor accepts in f32 the periods it accepts in f64. With
//! the f64 check's relative tolerance of 1e-9, `rate_hz = 50` against a 1 ms control
//! period was refused in f32 (1 / 50 is 0.0199999995 there, 20 ms is 0.0200000009): a
//! firmware could not have a 50 Hz pose, and `wmr-cli trace` refused most real sensors.
//!
//! The truth is integer arithmetic: a sample every P = 1000 / (rate_hz dt_ms) ticks,
//! arriving L = latency_ms / dt_ms ticks late, so at tick k the sensor shows the truth of
//! tick P floor((k - L) / P) (the start, tick 0, before the first arrives).

use wmr_core::{Pose2, PoseSensor, RobotParams, Sensor, SensorParams, State};

const RATES_HZ: [u32; 11] = [1000, 500, 250, 200, 125, 100, 50, 40, 25, 20, 10];
const LATENCIES_MS: [u32; 8] = [0, 2, 5, 10, 20, 30, 50, 100];
const DTS_MS: [u32; 4] = [1, 2, 5, 10];

/// The tick whose truth the sensor shows at tick k.
fn seen_tick(k: u32, p: u32, l: u32) -> u32 {
    if k < l { 0 } else { p * ((k - l) / p) }
}

/// Runs the sensor for 400 ticks over a truth whose x is the tick index and checks the
/// tick it shows against [`seen_tick`]; `Err` when `new` refuses the settings.
macro_rules! check_precision {
    ($t:ty, $rate:expr, $latency_ms:expr, $dt_ms:expr) => {{
        let dt = $dt_ms as $t / 1000.0;
        let params =
            SensorParams::<$t> { rate_hz: $rate as $t, latency: $latency_ms as $t / 1000.0, ..SensorParams::default() };
        PoseSensor::<$t>::new(params, dt, 0).map(|mut sensor| {
            let robot = RobotParams::<$t>::paper();
            let (p, l) = (1000 / ($rate * $dt_ms), $latency_ms / $dt_ms);
            for k in 0..400u32 {
                let truth = State::at_rest(Pose2::new(k as $t, 0.0, 0.0));
                let m = sensor.measure(k as $t * dt, &truth, &robot);
                assert_eq!(
                    m.pose.x,
                    seen_tick(k, p, l) as $t,
                    "{} Hz, {} ms late, dt {} ms: tick {k}",
                    $rate,
                    $latency_ms,
                    $dt_ms
                );
            }
        })
    }};
}

#[test]
fn issue25_8_f32_accepts_the_sensor_periods_of_f64() {
    let (mut cases, mut whole) = (0, 0);
    for dt_ms in DTS_MS {
        for rate in RATES_HZ {
            for latency_ms in LATENCIES_MS {
                cases += 1;
                // Settings that are whole numbers of ticks (and fit the ring) must be
                // accepted in both precisions and behave as the integer rule says.
                let is_whole = (1000 % (rate * dt_ms) == 0) && latency_ms % dt_ms == 0;
                let f64_ok = check_precision!(f64, rate, latency_ms, dt_ms);
                let f32_ok = check_precision!(f32, rate, latency_ms, dt_ms);
                assert_eq!(f64_ok.is_ok(), is_whole, "f64: {rate} Hz, {latency_ms} ms, dt {dt_ms} ms: {f64_ok:?}");
                assert_eq!(
                    f32_ok.is_ok(),
                    f64_ok.is_ok(),
                    "f32 vs f64: {rate} Hz, {latency_ms} ms, dt {dt_ms} ms: {f32_ok:?}"
                );
                whole += usize::from(is_whole);
            }
        }
    }
    assert_eq!(cases, 352);
    assert!(whole > 150, "{whole} whole settings");
}

/// What is not a whole multiple stays refused in f32 by the field's name: a period that
/// is 1.5 ticks, or a hair more than one tick (past f32 rounding).
#[test]
fn f32_still_refuses_periods_that_are_not_whole_multiples() {
    let dt = 1e-3f32;
    for (rate_hz, latency, field) in
        [(666.0f32, 0.0f32, "rate_hz"), (999.0, 0.0, "rate_hz"), (50.0, 0.0015, "latency"), (50.0, 0.001001, "latency")]
    {
        let params = SensorParams::<f32> { rate_hz, latency, ..SensorParams::default() };
        let e = PoseSensor::<f32>::new(params, dt, 0).unwrap_err();
        assert_eq!(e.field, field, "{rate_hz} Hz, {latency} s");
    }
}
