//! `/odom` of `wmr-cli run --profile ros2` (issue 43 item 2): on odometry, the pose
//! covariance is the EKF's, read here from the odometry sensor of the same run stepped
//! through `wmr_scenario` (`OdometrySensor::covariance` at each logged step), placed at
//! the (x, y, yaw) rows and columns of the 6x6 row-major matrix; every other entry, the
//! twist covariance and every covariance of a run without odometry, zero.

use std::fs;
use std::process::Command;

use wmr_core::sensor::AnySensor;
use wmr_scenario::Scenario;

/// 3 s of Fig. 7 with a noisy pose sensor, the controller's pose from `pose`.
fn scenario(pose: &str) -> String {
    include_str!("fixtures/odometry-3s.toml")
        .replace("pose = \"odometry\"", &format!("pose = \"{pose}\"\nposition_noise = 0.01\nheading_noise_deg = 1.0"))
}

/// A CDR (XCDR1, little-endian) reader of the fields `/odom` has.
struct Cdr<'a> {
    data: &'a [u8],
    at: usize,
}

impl Cdr<'_> {
    fn align(&mut self, n: usize) {
        // Alignment counts from after the 4-byte encapsulation header.
        let off = self.at - 4;
        self.at += (n - off % n) % n;
    }
    fn u32(&mut self) -> u32 {
        self.align(4);
        let v = u32::from_le_bytes(self.data[self.at..self.at + 4].try_into().unwrap());
        self.at += 4;
        v
    }
    fn string(&mut self) -> String {
        let n = self.u32() as usize;
        let s = std::str::from_utf8(&self.data[self.at..self.at + n - 1]).unwrap().to_owned();
        self.at += n;
        s
    }
    fn f64s<const N: usize>(&mut self) -> [f64; N] {
        self.align(8);
        std::array::from_fn(|_| {
            let v = f64::from_le_bytes(self.data[self.at..self.at + 8].try_into().unwrap());
            self.at += 8;
            v
        })
    }
}

/// Each `/odom` message's (stamp ns, pose covariance, twist covariance).
fn odom_covariances(mcap_bytes: &[u8]) -> Vec<(u64, [f64; 36], [f64; 36])> {
    let mut out = Vec::new();
    for m in mcap::MessageStream::new(mcap_bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic != "/odom" {
            continue;
        }
        let mut r = Cdr { data: &m.data, at: 4 };
        let sec = u64::from(r.u32());
        let nanosec = u64::from(r.u32());
        assert_eq!(r.string(), "odom");
        assert_eq!(r.string(), "base_link");
        let _pose: [f64; 7] = r.f64s();
        let pose_cov: [f64; 36] = r.f64s();
        let _twist: [f64; 6] = r.f64s();
        let twist_cov: [f64; 36] = r.f64s();
        assert_eq!(r.at, m.data.len(), "the whole message read");
        out.push((sec * 1_000_000_000 + nanosec, pose_cov, twist_cov));
    }
    out
}

fn write_ros2(text: &str) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.toml");
    fs::write(&file, text).unwrap();
    let out = dir.path().join("s.mcap");
    let o = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .args(["run", file.to_str().unwrap(), "-o", out.to_str().unwrap(), "--profile", "ros2"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    fs::read(out).unwrap()
}

#[test]
fn odom_carries_the_ekf_covariance_on_odometry() {
    // 10 Hz fixes, so that the covariance falls as well as grows.
    let text = scenario("odometry").replace("encoder_counts = 4096", "encoder_counts = 4096\nfix_rate_hz = 10.0");
    let got = odom_covariances(&write_ros2(&text));

    // The EKF's covariance at each logged step, from the sensor of the same run.
    let sc = Scenario::from_toml_str(&text, "s").unwrap();
    let sim = sc.sim();
    let (n, every) = (sim.n_steps(), u64::from(sim.log_every()));
    let mut lp = sc.closed_loop(0).unwrap();
    let ekf = |lp: &wmr_scenario::RunLoop| match lp.sensor() {
        AnySensor::Odometry(s) => s.covariance().expect("a tick has run"),
        _ => panic!("the run is on odometry"),
    };
    let mut want = vec![(0u64, ekf(&lp))];
    for k in 1..=n {
        lp.step().unwrap();
        if k % every == 0 {
            want.push(((k as f64 * sim.dt() * 1e9).round() as u64, ekf(&lp)));
        }
    }
    assert_eq!(got.len(), want.len());
    let (mut grew, mut fell) = (false, false);
    for (i, ((t, pose_cov, twist_cov), (t_want, c))) in got.iter().zip(&want).enumerate() {
        assert_eq!(t, t_want);
        for (r, row) in [0, 1, 5].into_iter().zip(c) {
            for (col, v) in [0, 1, 5].into_iter().zip(row) {
                assert_eq!(pose_cov[6 * r + col].to_bits(), v.to_bits(), "sample {i}, ({r}, {col})");
            }
        }
        for r in [2, 3, 4] {
            assert!((0..6).all(|j| pose_cov[6 * r + j] == 0.0 && pose_cov[6 * j + r] == 0.0), "z, roll, pitch: 0");
        }
        assert!(twist_cov.iter().all(|v| *v == 0.0), "no twist covariance");
        assert!(c[0][0] > 0.0 && c[2][2] > 0.0, "positive variances");
        if i > 0 {
            grew |= pose_cov[0] > got[i - 1].1[0];
            fell |= pose_cov[0] < got[i - 1].1[0];
        }
    }
    assert!(grew && fell, "the odometry grows it, the fixes shrink it");
}

#[test]
fn odom_covariance_is_zero_without_odometry() {
    let got = odom_covariances(&write_ros2(&scenario("absolute")));
    assert!(!got.is_empty());
    assert!(got.iter().all(|(_, p, t)| p.iter().chain(t).all(|v| *v == 0.0)), "absolute pose: unknown, all zeros");
    let fig7 = fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/paper/fig7.toml")).unwrap();
    let got = odom_covariances(&write_ros2(&fig7.replace("t_end = ", "t_end = 0.1 # ")));
    assert!(got.iter().all(|(_, p, t)| p.iter().chain(t).all(|v| *v == 0.0)), "no sensor: all zeros");
}
