//! Issue 42, docking outcomes: `wmr-cli sweep` prints each law's share docked and the
//! percentiles of its final errors; both are checked against a count made here, from
//! the sweep CSV's `final_dl_m`, `final_heading_error_deg` and `status` columns alone.

use std::process::Command;

/// Three laws from 40 starts within 1.5 m, on a robot with Coulomb friction, judged at
/// 4 mm and 0.3 deg: some runs dock and some do not.
const SWEEP: &str = r#"
[robot]
coulomb_friction = 0.05
[sim]
t_end = 20.0
stop_when_settled = true
xy_goal_tolerance = 0.004
yaw_goal_tolerance_deg = 0.3
[sweep]
goal = { x = 0.5, y = -0.25, theta_deg = 30.0 }
controllers = [{ kind = "paper_bidirectional" }, { kind = "lyapunov" }, { kind = "polar" }]
random = { n = 40, seed = 11, radius = 1.5 }
"#;

/// Nearest-rank percentile of ascending `v`: the smallest value with at least p % of
/// the values at or below it.
fn nearest_rank(v: &[f64], p: f64) -> f64 {
    let k = (p / 100.0 * v.len() as f64).ceil() as usize;
    v[k.max(1) - 1]
}

#[test]
fn share_docked_and_final_error_percentiles_agree_with_a_count_over_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("dock.toml");
    std::fs::write(&file, SWEEP).unwrap();
    let csv = dir.path().join("dock.csv");
    let out = Command::new(env!("CARGO_BIN_EXE_wmr-cli")).arg("sweep").arg(&file).arg("-o").arg(&csv).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8(out.stdout).unwrap();

    // The count from the CSV, by the rule of nav2's SimpleGoalChecker (bounds included),
    // on the columns every sweep CSV had before `docked`.
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|c| *c == name).unwrap_or_else(|| panic!("no column {name}"));
    let (law, status, dl, th, docked) =
        (col("law"), col("status"), col("final_dl_m"), col("final_heading_error_deg"), col("docked"));
    assert_eq!(docked, th + 1, "docked stands beside final_dl_m and final_heading_error_deg");
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 120);

    let table = stdout.split("docked within 0.004 m and 0.3 deg at the end").nth(1).expect("the docking table");
    let mut printed = table.lines().skip(2);
    let mut some_docked_some_not = (false, false);
    for name in ["paper_bidirectional", "lyapunov", "polar"] {
        let mine: Vec<&Vec<&str>> = rows.iter().filter(|r| r[law] == name).collect();
        let n = mine.len();
        let is_docked = |r: &Vec<&str>| {
            let (d, h): (f64, f64) = (r[dl].parse().unwrap(), r[th].parse().unwrap());
            r[status] != "diverged" && d <= 0.004 && h.abs() <= 0.3
        };
        let count = mine.iter().filter(|r| is_docked(r)).count();
        for r in &mine {
            assert_eq!(r[docked], if is_docked(r) { "1" } else { "0" }, "{r:?}");
        }
        some_docked_some_not.0 |= count > 0;
        some_docked_some_not.1 |= count < n;
        let mut dls: Vec<f64> = mine.iter().map(|r| r[dl].parse::<f64>().unwrap() * 1000.0).collect();
        let mut ths: Vec<f64> = mine.iter().map(|r| r[th].parse::<f64>().unwrap().abs()).collect();
        dls.sort_by(f64::total_cmp);
        ths.sort_by(f64::total_cmp);
        let expect = |v: &[f64], prec: usize| -> Vec<String> {
            [50.0, 95.0, 99.0, 100.0].iter().map(|&p| format!("{:.prec$}", nearest_rank(v, p))).collect()
        };
        let row = printed.next().expect("a row per law");
        let cells: Vec<&str> = row.split_whitespace().filter(|c| *c != "/").collect();
        assert_eq!(cells[0], name, "{row}");
        assert_eq!(cells[1], n.to_string(), "{row}");
        assert_eq!(cells[2], format!("{:.2}%", 100.0 * count as f64 / n as f64), "{row}");
        assert_eq!(cells[3..7], expect(&dls, 2)[..], "final dl mm: {row}");
        assert_eq!(cells[7..11], expect(&ths, 3)[..], "|e_th| deg: {row}");
    }
    assert_eq!(some_docked_some_not, (true, true), "the sweep must have runs on both sides\n{stdout}");
}
