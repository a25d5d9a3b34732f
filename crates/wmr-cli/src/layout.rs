//! A Foxglove layout made for one scenario (`wmr-cli layout`, `run --layout`): the keys
//! are the ones Foxglove's panels read (checked against the open-source Foxglove fork's
//! panel code: `ThreeDeeRender` and `Plot`).
//!
//! - **3D** (`3D!wmr-plane`): the plane seen from above (orthographic camera framing every
//!   start and goal and a reference's path, x to the right, y up), a grid with round spacing, and per run its
//!   `scene` (body, goal), `path` and `path_tip` topics visible; with a `[sensor]`, its
//!   `pose_meas` as an arrow, on odometry its `pose_odom` as a darker arrow, and with a
//!   `[reference]` its `reference` topic (the dashed reference path, the ghost on
//!   `runN/reference`); with obstacles its `obstacles`, under MPPI its `mppi/optimal` as a line
//!   and its `mppi/rollouts`. Frame settings where Foxglove reads them: axis scale and label
//!   size under `scene.transforms`, one `frame:<id>` entry per frame under `transforms`.
//! - **Plots**, titled with their units (`foxglovePanelTitle`): dl of every run (with a
//!   `[reference]` the tracking-error plot, as dl is then), e_theta of every run, the
//!   wheel speeds of run 0; with a `[sensor]` run 0's true and measured position, on
//!   odometry run 0's true and dead-reckoned position (the drift), with a `[reference]`
//!   run 0's reference and actual speed. A run's series has the colour of its path in the
//!   3D panel.
//!
//! For a `--profile ros2` file ([`layout`] with [`Profile::Ros2`]) the same panels name the
//! ROS 2 topics and frames: the 3D panel follows `map` and shows each run's robot from its
//! URDF (`/robot_description`, which the 3D panel draws on the `/tf` frames: the wheels
//! turn), its goal (`/goal_pose`) as an arrow and, with a `[reference]`, its `/plan`
//! (`nav_msgs/Odometry` is not a type the 3D panel draws); the plots read `/wmr/sample` (`/runN/wmr/sample`), whose
//! fields are the CSV's. A `both` file gets the Foxglove layout (its channels are complete;
//! the ROS 2 frames hang from `map`, not from `world`).

use serde_json::{Value, json};
use wmr_scenario::{Columns, Scenario};

use crate::foxglove_topics::{
    Kind, Views, WORLD_FRAME, base_link, log_positions, reference_frame, run_hex, run_rgb, topic,
};
use crate::mcap_sink::Profile;
use crate::ros2::Topic;
use crate::ros2::topics::{MAP_FRAME, frame, topic_name};

/// Id (type!name) of the 3D panel.
pub const PANEL_3D: &str = "3D!wmr-plane";

/// Length of the frame axes Foxglove draws at `axisScale` 1, m (its `Axis.ts`: shaft 0.154 +
/// head 0.046).
const AXIS_LENGTH_FOXGLOVE_M: f64 = 0.2;

/// A round grid spacing (1, 2 or 5 times a power of ten) near `span / 10`, m.
fn nice_spacing(span: f64) -> f64 {
    let raw = (span / 10.0).max(1e-3);
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    let k = if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    };
    k * p
}

/// Run `run`'s colour mixed with grey level `to` (0 black, 1 white) by `f` (0..1), as
/// `#rrggbb`: the second series of a one-run plot, in a shade of the run's colour.
fn shade(run: usize, to: f64, f: f64) -> String {
    let mix = |c: u8| (f64::from(c) * (1.0 - f) + 255.0 * to * f).round() as u8;
    let [r, g, b] = run_rgb(run).map(mix);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// Rounds to 6 decimals, so the JSON shows 0.3 and not 0.30000000000000004.
fn r6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

fn plot(title: &str, paths: Vec<Value>) -> Value {
    let legend = if paths.len() <= 8 { "floating" } else { "left" };
    json!({
        "foxglovePanelTitle": title,
        "paths": paths,
        "showXAxisLabels": true,
        "showYAxisLabels": true,
        "showLegend": true,
        "legendDisplay": legend,
        "showPlotValuesInLegend": false,
        "isSynced": true,
        "xAxisVal": "timestamp",
        "sidebarDimension": 240
    })
}

/// Where a layout finds a run's samples and frames: the Foxglove profile's names or the
/// ROS 2 profile's.
#[derive(Clone, Copy)]
struct Names {
    ros2: bool,
    runs: usize,
}

impl Names {
    /// The topic of run `run`'s samples (every CSV column as a field).
    fn sample(self, run: usize) -> String {
        if self.ros2 { topic_name(run, self.runs, Topic::Sample) } else { topic(run, Kind::Sample) }
    }

    /// The fixed frame the 3D panel draws in.
    fn fixed_frame(self) -> &'static str {
        if self.ros2 { MAP_FRAME } else { WORLD_FRAME }
    }

    /// Run `run`'s body frame.
    fn base_link(self, run: usize) -> String {
        if self.ros2 { frame(run, self.runs, "base_link") } else { base_link(run) }
    }
}

fn series(sample_topic: &str, field: &str, label: String, color: String) -> Value {
    json!({
        "value": format!("{sample_topic}.{field}"),
        "enabled": true,
        "timestampMethod": "receiveTime",
        "label": label,
        "color": color
    })
}

/// Panels stacked in a column, evenly.
fn column(ids: &[&str]) -> Value {
    match ids {
        [] => Value::Null,
        [one] => json!(one),
        [first, rest @ ..] => json!({
            "first": first,
            "second": column(rest),
            "direction": "column",
            "splitPercentage": r6(100.0 / ids.len() as f64)
        }),
    }
}

/// The layout for `scenario`'s runs in a file of `profile` ([module doc](self)).
pub fn layout(scenario: &Scenario, profile: Profile) -> Value {
    let runs = scenario.runs();
    let names = Names { ros2: profile == Profile::Ros2, runs: runs.len() };
    let robot = scenario.robot().params();
    let columns = Columns::of(scenario);
    let views = Views::of(scenario);
    let tracking = columns.reference.is_some();

    // Frame every start and goal (and a reference's path, at the log times, thinned to a
    // bounded count as the drawing is) with a margin of a robot length and 15 %.
    let sim = scenario.sim();
    let reference_path: Vec<(f64, f64)> = columns.reference.map(|r| log_positions(&r, sim)).unwrap_or_default();
    let body = (2.0 * robot.com_offset.abs()).max(2.0 * robot.wheel_radius) + 2.0 * robot.wheel_radius;
    let reach = body.max(2.0 * robot.half_track);
    let (mut x0, mut y0, mut x1, mut y1) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for (x, y) in runs.iter().flat_map(|r| [(r.start.x, r.start.y), (r.goal.x, r.goal.y)]).chain(reference_path) {
        x0 = x0.min(x);
        y0 = y0.min(y);
        x1 = x1.max(x);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        (x0, y0, x1, y1) = (0.0, 0.0, 0.0, 0.0);
    }
    let span = (x1 - x0).max(y1 - y0) + 2.0 * reach;
    let span = span * 1.15;
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let spacing = nice_spacing(span);
    let cells = (span / spacing).ceil() + 2.0;
    let grid_size = cells * spacing;

    let mut transforms = serde_json::Map::new();
    transforms.insert(format!("frame:{}", names.fixed_frame()), json!({ "visible": true }));
    let mut topics = serde_json::Map::new();
    for i in 0..runs.len() {
        transforms.insert(format!("frame:{}", names.base_link(i)), json!({ "visible": true }));
        // A pose as an arrow (ThreeDeeRender's PoseInFrame settings: type, arrowScale, color).
        let s = robot.half_track;
        let arrow = |color: String| {
            json!({
                "visible": true,
                "type": "arrow",
                "arrowScale": [r6(1.2 * s), r6(0.08 * s), r6(0.08 * s)],
                "color": format!("{color}ff")
            })
        };
        if names.ros2 {
            // The URDF on the /tf frames (Foxglove's Urdfs: hidden unless set visible).
            topics.insert(topic_name(i, runs.len(), Topic::RobotDescription), json!({ "visible": true }));
            topics.insert(topic_name(i, runs.len(), Topic::GoalPose), arrow(shade(i, 1.0, 0.5)));
            if tracking {
                topics.insert(topic_name(i, runs.len(), Topic::Plan), json!({ "visible": true }));
            }
            continue;
        }
        for kind in [Kind::Scene, Kind::Path, Kind::PathTip] {
            topics.insert(topic(i, kind), json!({ "visible": true }));
        }
        if columns.measured {
            topics.insert(topic(i, Kind::PoseMeas), arrow(run_hex(i)));
        }
        if columns.odometry {
            topics.insert(topic(i, Kind::PoseOdom), arrow(shade(i, 0.0, 0.45)));
        }
        if tracking {
            transforms.insert(format!("frame:{}", reference_frame(i)), json!({ "visible": true }));
            topics.insert(topic(i, Kind::Reference), json!({ "visible": true }));
        }
        if views.obstacles {
            topics.insert(topic(i, Kind::Obstacles), json!({ "visible": true }));
        }
        if views.mppi {
            // The optimal trajectory as a line (ThreeDeeRender's PoseArray settings: type
            // "line", lineWidth, a gradient from its start to its end), the rollouts as sent.
            topics.insert(
                topic(i, Kind::MppiOptimal),
                json!({
                    "visible": true,
                    "type": "line",
                    "lineWidth": r6(0.1 * s),
                    "gradient": [format!("{}ff", shade(i, 0.0, 0.3)), format!("{}80", shade(i, 1.0, 0.5))]
                }),
            );
            topics.insert(topic(i, Kind::MppiRollouts), json!({ "visible": true }));
        }
    }

    let three_d = json!({
        "foxglovePanelTitle": if names.ros2 {
            "the plane from above (m, frame map): every run's robot and goal"
        } else {
            "the plane from above (m, frame world): every run's path, body and goal"
        },
        "cameraState": {
            "perspective": false,
            "distance": r6(span),
            "phi": 0,
            "thetaOffset": 0,
            "targetOffset": [r6(cx), r6(cy), 0],
            "target": [0, 0, 0],
            "targetOrientation": [0, 0, 0, 1],
            "fovy": 45,
            "near": 0.01,
            "far": 5000
        },
        "followMode": "follow-none",
        "followTf": names.fixed_frame(),
        "scene": {
            "backgroundColor": "#ffffff",
            "transforms": {
                "showLabel": true,
                "labelSize": r6(span / 60.0),
                "axisScale": r6(robot.half_track / AXIS_LENGTH_FOXGLOVE_M),
                "enablePreloading": true
            }
        },
        "transforms": transforms,
        "topics": topics,
        "layers": {
            "grid": {
                "visible": true,
                "layerId": "foxglove.Grid",
                "frameId": names.fixed_frame(),
                "size": r6(grid_size),
                "divisions": cells as u64,
                "lineWidth": 1,
                "color": "#c8c8c8ff",
                "position": [r6((cx / spacing).round() * spacing), r6((cy / spacing).round() * spacing), 0],
                "rotation": [0, 0, 0],
                "order": 1
            }
        },
        "publish": {
            "type": "point",
            "poseTopic": "/move_base_simple/goal",
            "pointTopic": "/clicked_point",
            "poseEstimateTopic": "/initialpose",
            "poseEstimateXDeviation": 0.5,
            "poseEstimateYDeviation": 0.5,
            "poseEstimateThetaDeviation": 0.26179939
        },
        "imageMode": {}
    });

    let every = |field: &str| -> Vec<Value> {
        (0..runs.len()).map(|i| series(&names.sample(i), field, format!("run {i}"), run_hex(i))).collect()
    };
    let run0 = names.sample(0);
    let mut config = serde_json::Map::new();
    config.insert(PANEL_3D.into(), three_d);
    // A tracking run's dl is its tracking error: the plot of dl becomes the tracking-error plot.
    let (dl_id, dl_title) = if tracking {
        (
            "Plot!wmr-tracking-error",
            "tracking error dl (m): distance of C to C_ref (to the path, for pure_pursuit), every run",
        )
    } else {
        ("Plot!wmr-dl", "dl (m): distance of C to the goal, every run")
    };
    config.insert(dl_id.into(), plot(dl_title, every("dl")));
    config.insert("Plot!wmr-heading".into(), plot("e_theta (rad): heading error, every run", every("e_theta")));
    config.insert(
        "Plot!wmr-wheels".into(),
        plot(
            "run 0: wheel speeds omega_r, omega_l (rad/s)",
            vec![
                series(&run0, "omega_r", "omega_r (rad/s)".into(), run_hex(0)),
                series(&run0, "omega_l", "omega_l (rad/s)".into(), shade(0, 0.0, 0.45)),
            ],
        ),
    );
    let mut plots = vec![dl_id, "Plot!wmr-heading", "Plot!wmr-wheels"];
    // Run 0's true position against another estimate of it (columns `x_{suffix}`, `y_{suffix}`).
    let true_and = |what: &str, suffix: &str| {
        let (x, y) = (format!("x_{suffix}"), format!("y_{suffix}"));
        plot(
            &format!("run 0: {what} position x, {x}, y, {y} (m)"),
            vec![
                series(&run0, "x", "x (m)".into(), run_hex(0)),
                series(&run0, &x, format!("{x} (m)"), shade(0, 1.0, 0.5)),
                series(&run0, "y", "y (m)".into(), shade(0, 0.0, 0.45)),
                series(&run0, &y, format!("{y} (m)"), shade(0, 0.0, 0.75)),
            ],
        )
    };
    if columns.measured {
        config.insert("Plot!wmr-sensor".into(), true_and("true and measured", "meas"));
        plots.push("Plot!wmr-sensor");
    }
    if columns.odometry {
        config.insert("Plot!wmr-odometry".into(), true_and("odometry drift, true and dead-reckoned", "odom"));
        plots.push("Plot!wmr-odometry");
    }
    if tracking {
        config.insert(
            "Plot!wmr-speed".into(),
            plot(
                "run 0: reference and actual speed v_ref, v (m/s)",
                vec![
                    series(&run0, "v_ref", "v_ref (m/s)".into(), shade(0, 1.0, 0.5)),
                    series(&run0, "v", "v (m/s)".into(), run_hex(0)),
                ],
            ),
        );
        plots.push("Plot!wmr-speed");
    }

    json!({
        "configById": config,
        "globalVariables": {},
        "userNodes": {},
        "linkedGlobalVariables": [],
        "playbackConfig": { "speed": 1 },
        "layout": {
            "first": PANEL_3D,
            "second": column(&plots),
            "direction": "row",
            "splitPercentage": 55
        }
    })
}

/// The layout as pretty JSON text, ending in a newline.
pub fn layout_text(scenario: &Scenario, profile: Profile) -> String {
    let mut s = serde_json::to_string_pretty(&layout(scenario, profile)).unwrap_or_default();
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::nice_spacing;

    #[test]
    fn grid_spacing_is_round() {
        for (span, want) in [(1.6, 0.2), (1.0, 0.1), (3.2, 0.2), (4.0, 0.5), (40.0, 5.0), (0.05, 0.005)] {
            assert!((nice_spacing(span) - want).abs() < 1e-12, "{span}: {}", nice_spacing(span));
        }
    }
}
