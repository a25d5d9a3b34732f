//! Replays a control trace (`wmr-cli trace FILE.toml -o run.bin`) on the Cortex-M4F under
//! QEMU and checks every tick bit for bit in f32: the reference, rebuilt here from the
//! trace's config, must give the recorded reference state (a goal at rest, or a moving
//! reference: its pose, twist and acceleration); the controller, fed the recorded
//! measurement and that reference (with its path, for a path-following law), must give
//! the recorded command and errors; the plant, driven from the start pose by the
//! commands, must reach every recorded state.
//!
//! `qemu-system-arm ... -semihosting-config enable=on,target=native,arg=replay,arg=run.bin
//! -kernel replay`; prints one `replay` line, exits 0 when every tick matched.
#![no_std]
#![no_main]

use wmr_core::reference::Reference as _;
use wmr_core::trace::{self, CONFIG_WORDS, Config, HEADER_WORDS, RECORD_WORDS, Record};
use wmr_core::{Controller, Measurement, Plant, Pose2, WheelStage, Wheels};
use wmr_firmware::semi::{self, File};

fn fail(what: &str) -> ! {
    semi::println(format_args!("replay error: {what}"));
    semi::exit(false)
}

fn words<const N: usize>(file: &mut File) -> Option<[u32; N]> {
    // The longest read is the config.
    let mut bytes = [0u8; 4 * CONFIG_WORDS];
    let buf = bytes.get_mut(..4 * N)?;
    if !file.read_exact(buf) {
        return None;
    }
    trace::words_le::<N>(buf)
}

fn bits<const N: usize>(v: [f32; N]) -> [u32; N] {
    v.map(f32::to_bits)
}

#[cortex_m_rt::entry]
fn main() -> ! {
    let mut line = [0u8; 256];
    let Some(cmd) = semi::cmdline(&mut line) else { fail("no semihosting command line") };
    let Some(path) = cmd.split(' ').filter(|a| !a.is_empty()).nth(1) else { fail("usage: replay TRACE.bin") };
    let Some(mut file) = File::open(path) else { fail("cannot open the trace file") };
    let Some(header) = words::<HEADER_WORDS>(&mut file) else { fail("short header") };
    let ticks = match trace::read_header(&header) {
        Ok(n) => n,
        Err(e) => fail(e.0),
    };
    let Some(cw) = words::<CONFIG_WORDS>(&mut file) else { fail("short config") };
    let c = match Config::decode(&cw) {
        Ok(c) => c,
        Err(e) => fail(e.0),
    };
    let built = (|| {
        let robot = c.robot.validate().ok()?;
        let model = c.model.validate().ok()?;
        let drive = c.drive.validate(&robot).ok()?;
        let plant = Plant::on(robot, drive, c.world.validate().ok()?, c.start).ok()?;
        let law = c.law.build(model.params(), c.control_dt).ok()?;
        let wheels = WheelStage::new(&c.wheels, model.params(), &drive, c.control_dt).ok()?;
        let reference = c.reference.build().ok()?;
        Some((plant, Controller::new(law, wheels), reference))
    })();
    let Some((mut plant, mut ctrl, reference)) = built else { fail("the trace's parameters are refused in f32") };

    let (mut reference_ok, mut controller_ok, mut plant_ok) = (0u32, 0u32, 0u32);
    let mut first_bad: Option<(u32, &str)> = None;
    let mut step: u64 = 0;
    for k in 0..ticks {
        let Some(rw) = words::<RECORD_WORDS>(&mut file) else { fail("short record") };
        let r = Record::decode(&rw);
        if k > 0 {
            for _ in 0..c.steps_per_tick {
                let t = (step as f64) as f32 * c.dt;
                if plant.step(t, c.dt).is_err() {
                    fail("the plant diverged where the trace did not");
                }
                step += 1;
            }
        }
        if bits(plant.state().to_array()) == bits(r.state) {
            plant_ok += 1;
        } else if first_bad.is_none() {
            first_bad = Some((k, "plant state"));
        }
        let [mt, x, y, theta, ar, al, wr, wl] = r.measurement;
        let m = Measurement {
            t: mt,
            pose: Pose2::new(x, y, theta),
            wheel_angles: Wheels::new(ar, al),
            wheel_speeds: Wheels::new(wr, wl),
        };
        // The reference at the tick's time, as the traced loop asked it.
        let at = reference.state_at(r.t);
        if bits(trace::reference_values(&at)) == bits(r.reference) {
            reference_ok += 1;
        } else if first_bad.is_none() {
            first_bad = Some((k, "reference state"));
        }
        let out = match reference.path() {
            Some(path) => ctrl.update_on_path(r.t, &m, &at, path),
            None => ctrl.update(r.t, &m, &at),
        };
        let got = [out.command.right, out.command.left, out.errors.e_s, out.errors.e_theta, out.errors.dl];
        let want = [r.command[0], r.command[1], r.errors[0], r.errors[1], r.errors[2]];
        if bits(got) == bits(want) {
            controller_ok += 1;
        } else if first_bad.is_none() {
            first_bad = Some((k, "controller output"));
        }
        // Hold the recorded command, as the traced loop did.
        plant.apply(Wheels::new(r.command[0], r.command[1]));
    }
    let (bad_tick, bad_what) = first_bad.map_or((-1i64, "none"), |(k, w)| (i64::from(k), w));
    semi::println(format_args!(
        "replay law={} reference={} ticks={ticks} reference_ok={reference_ok} controller_ok={controller_ok} plant_ok={plant_ok} first_mismatch_tick={bad_tick} first_mismatch={bad_what}",
        c.law.kind(),
        reference.kind()
    ));
    semi::exit(reference_ok == ticks && controller_ok == ticks && plant_ok == ticks)
}
