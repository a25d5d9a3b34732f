//! `wmr-cli run --live`: a WebSocket client speaking Foxglove's protocol (subprotocol
//! `foxglove.sdk.v1`) subscribes to a run's transform topic and gets the very messages the
//! MCAP written at the same time holds, in time order and paced at `--speed`; the server
//! clock follows the simulation. Only 127.0.0.1; every wait has a deadline.

use std::collections::BTreeMap;
use std::fs;
use std::io::{BufRead, BufReader, Read};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use foxglove::Decode as _;
use foxglove::messages::FrameTransform;
use tungstenite::Message;
use tungstenite::client::IntoClientRequest as _;

/// Longest the whole test may wait for anything.
const DEADLINE: Duration = Duration::from_secs(120);

const SCENARIO: &str = r#"
[sim]
t_end = 2.0
log_dt = 0.01
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }
[[run]]
start = { x = -0.5, y = 0.2, theta = 0.3 }
goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }
"#;

/// Kills the child when the test fails half-way.
struct Guard(Option<Child>);

impl Drop for Guard {
    fn drop(&mut self) {
        if let Some(c) = self.0.as_mut() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// Starts `wmr-cli run FILE --live 127.0.0.1:0 ARGS` and returns it with the port it
/// announced and the rest of its stderr (collected by a thread).
fn start(dir: &Path, args: &[&str]) -> (Guard, u16, mpsc::Receiver<String>) {
    start_with(dir, SCENARIO, args)
}

/// [`start`] for the scenario `body`.
fn start_with(dir: &Path, body: &str, args: &[&str]) -> (Guard, u16, mpsc::Receiver<String>) {
    let scen = dir.join("s.toml");
    fs::write(&scen, body).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(dir)
        .args(["run", "s.toml", "--live", "127.0.0.1:0"])
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn wmr-cli");
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let guard = Guard(Some(child));
    let t0 = Instant::now();
    loop {
        let line = rx.recv_timeout(DEADLINE.saturating_sub(t0.elapsed())).expect("no `live on ws://` line in time");
        if let Some(rest) = line.split("live on ws://127.0.0.1:").nth(1) {
            let port: u16 = rest.split(|c: char| !c.is_ascii_digit()).next().unwrap().parse().unwrap();
            return (guard, port, rx);
        }
    }
}

/// The lines of stderr up to its end (the process has exited).
fn rest_of(stderr: &mpsc::Receiver<String>) -> Vec<String> {
    let t0 = Instant::now();
    let mut lines = Vec::new();
    while let Ok(line) = stderr.recv_timeout(DEADLINE.saturating_sub(t0.elapsed())) {
        lines.push(line);
    }
    lines
}

/// Channel ids by topic, from the server's `advertise` messages.
type Channels = BTreeMap<String, u64>;

type Socket = tungstenite::WebSocket<TcpStream>;

fn connect(port: u16) -> (Socket, Channels) {
    connect_to(port, 10)
}

/// [`connect`], waiting for `n` channels.
fn connect_to(port: u16, n: usize) -> (Socket, Channels) {
    let stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    let mut req = format!("ws://127.0.0.1:{port}").into_client_request().unwrap();
    req.headers_mut().insert("sec-websocket-protocol", "foxglove.sdk.v1".parse().unwrap());
    let (mut ws, resp) = tungstenite::client(req, stream).expect("WebSocket handshake");
    assert_eq!(resp.headers().get("sec-websocket-protocol").unwrap(), "foxglove.sdk.v1");
    let mut channels = Channels::new();
    let mut time_capability = false;
    while channels.len() < n {
        match ws.read().expect("serverInfo and advertise") {
            Message::Text(t) => {
                let v: serde_json::Value = serde_json::from_str(&t).unwrap();
                match v["op"].as_str() {
                    Some("serverInfo") => {
                        time_capability = v["capabilities"].as_array().unwrap().iter().any(|c| c == "time");
                    }
                    Some("advertise") => {
                        for c in v["channels"].as_array().unwrap() {
                            assert_eq!(c["encoding"], "protobuf");
                            channels.insert(c["topic"].as_str().unwrap().to_owned(), c["id"].as_u64().unwrap());
                        }
                    }
                    _ => {}
                }
            }
            Message::Ping(_) | Message::Pong(_) => {}
            other => panic!("unexpected message before subscribing: {other:?}"),
        }
    }
    assert!(time_capability, "the server must announce the time capability");
    (ws, channels)
}

/// The `/run1/tf` messages of an MCAP file: (log time, bytes).
fn mcap_topic(path: &Path, topic: &str) -> Vec<(u64, Vec<u8>)> {
    let bytes = fs::read(path).unwrap();
    mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .filter(|m| m.channel.topic == topic)
        .map(|m| (m.log_time, m.data.into_owned()))
        .collect()
}

#[test]
fn a_subscribed_client_gets_the_mcap_messages_in_time_order_at_the_given_speed() {
    let dir = tempfile::tempdir().unwrap();
    let speed = 4.0;
    let (mut guard, port, stderr) = start(dir.path(), &["--speed", "4", "-o", "live.mcap"]);
    let (mut ws, channels) = connect(port);
    let mut want: Vec<&str> = channels.keys().map(String::as_str).collect();
    want.sort();
    assert_eq!(
        want,
        [
            "/run0/path",
            "/run0/path_tip",
            "/run0/sample",
            "/run0/scene",
            "/run0/tf",
            "/run1/path",
            "/run1/path_tip",
            "/run1/sample",
            "/run1/scene",
            "/run1/tf"
        ]
    );
    let sub =
        serde_json::json!({ "op": "subscribe", "subscriptions": [{ "id": 7, "channelId": channels["/run1/tf"] }] });
    ws.send(Message::text(sub.to_string())).unwrap();
    let subscribed = Instant::now();

    let t0 = Instant::now();
    let mut got: Vec<(u64, Vec<u8>, Instant)> = Vec::new();
    let mut clock: Vec<u64> = Vec::new();
    loop {
        assert!(t0.elapsed() < DEADLINE, "the stream did not end in time");
        match ws.read() {
            Ok(Message::Binary(b)) => match b[0] {
                1 => {
                    let sub = u32::from_le_bytes(b[1..5].try_into().unwrap());
                    assert_eq!(sub, 7);
                    let t = u64::from_le_bytes(b[5..13].try_into().unwrap());
                    got.push((t, b[13..].to_vec(), Instant::now()));
                }
                2 => clock.push(u64::from_le_bytes(b[1..9].try_into().unwrap())),
                op => panic!("unexpected binary opcode {op}"),
            },
            Ok(_) => {}
            // The server closes the connection when the runs are over.
            Err(_) => break,
        }
    }
    let child = guard.0.as_mut().unwrap();
    let status = child.wait().unwrap();
    let mut out = String::new();
    child.stdout.take().unwrap().read_to_string(&mut out).unwrap();
    let log = rest_of(&stderr);
    assert!(status.success(), "wmr-cli failed: {log:?}");
    assert_eq!(out.lines().count(), 2, "one summary line per run: {out}");

    // Time order, and exactly the MCAP's messages: same log times, same bytes.
    assert!(got.windows(2).all(|w| w[0].0 < w[1].0), "log times must increase");
    let file = mcap_topic(&dir.path().join("live.mcap"), "/run1/tf");
    assert_eq!(file.len(), 201);
    // The MCAP written live holds what `wmr-cli run` writes, message for message.
    let plain = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(dir.path())
        .args(["run", "s.toml", "-o", "plain.mcap"])
        .output()
        .unwrap();
    assert!(plain.status.success());
    for topic in ["/run0/tf", "/run1/tf", "/run0/sample", "/run1/sample", "/run1/path_tip", "/run1/scene"] {
        assert_eq!(
            mcap_topic(&dir.path().join("live.mcap"), topic),
            mcap_topic(&dir.path().join("plain.mcap"), topic),
            "{topic}"
        );
    }
    assert_eq!(
        got.len(),
        file.len(),
        "every sample of run 1 arrives; got {:?}..{:?}",
        got.first().map(|g| g.0),
        got.last().map(|g| g.0)
    );
    for ((t, data, _), (ft, fdata)) in got.iter().zip(&file) {
        assert_eq!(t, ft);
        assert_eq!(data, fdata, "message at {t} ns differs from the MCAP's");
        let tf = FrameTransform::decode(&data[..]).unwrap();
        assert_eq!(tf.child_frame_id, "run1/base_link");
        let stamp = tf.timestamp.unwrap();
        assert_eq!(u64::from(stamp.sec()) * 1_000_000_000 + u64::from(stamp.nsec()), *t);
    }
    assert_eq!(got[0].0, 0);
    assert_eq!(got.last().unwrap().0, 2_000_000_000);

    // Paced: streaming starts after the subscription, and the message of simulated time t
    // is sent t / speed later, so it cannot arrive sooner (it may arrive later).
    for (t, _, arrived) in &got {
        let due = Duration::from_secs_f64(*t as f64 * 1e-9 / speed);
        assert!(
            *arrived - subscribed >= due,
            "message at {t} ns arrived {:?} after subscribing",
            *arrived - subscribed
        );
    }
    // The server clock is the simulation time.
    assert!(clock.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(clock.last(), Some(&2_000_000_000));
    assert!(log.iter().any(|l| l.contains("messages/s")), "{log:?}");
}

/// Two runs tracking a figure-eight on odometry for 2 s: every topic a run can have.
const EVERY_TOPIC: &str = include_str!("fixtures/two-runs-every-topic.toml");

/// The live server serves the topics of a run on odometry tracking a reference (the
/// dead-reckoned pose, the reference's frame and its drawing) with the MCAP's messages.
#[test]
fn the_live_server_serves_the_odometry_and_reference_topics_as_the_mcap_has_them() {
    let dir = tempfile::tempdir().unwrap();
    let (mut guard, port, stderr) = start_with(dir.path(), EVERY_TOPIC, &["--speed", "20", "-o", "live.mcap"]);
    let (mut ws, channels) = connect_to(port, 18);
    let topics: Vec<&str> = channels.keys().map(String::as_str).collect();
    let want = ["path", "path_tip", "pose_meas", "pose_odom", "reference", "sample", "scene", "tf", "tf_ref"];
    let want: Vec<String> = (0..2).flat_map(|r| want.map(|t| format!("/run{r}/{t}"))).collect();
    assert_eq!(topics, want);
    let new = ["/run1/pose_odom", "/run1/tf_ref", "/run1/reference"];
    let subs: Vec<serde_json::Value> =
        new.iter().enumerate().map(|(i, t)| serde_json::json!({ "id": i, "channelId": channels[*t] })).collect();
    ws.send(Message::text(serde_json::json!({ "op": "subscribe", "subscriptions": subs }).to_string())).unwrap();
    let t0 = Instant::now();
    let mut got: Vec<Vec<(u64, Vec<u8>)>> = vec![Vec::new(); new.len()];
    loop {
        assert!(t0.elapsed() < DEADLINE, "the stream did not end in time");
        match ws.read() {
            Ok(Message::Binary(b)) if b[0] == 1 => {
                let sub = u32::from_le_bytes(b[1..5].try_into().unwrap()) as usize;
                got[sub].push((u64::from_le_bytes(b[5..13].try_into().unwrap()), b[13..].to_vec()));
            }
            Ok(_) => {}
            Err(_) => break,
        }
    }
    let status = guard.0.as_mut().unwrap().wait().unwrap();
    assert!(status.success(), "wmr-cli failed: {:?}", rest_of(&stderr));
    for (topic, got) in new.iter().zip(&got) {
        let file = mcap_topic(&dir.path().join("live.mcap"), topic);
        assert!(!file.is_empty(), "{topic}: no message in the MCAP");
        assert_eq!(got, &file, "{topic}: the live messages are the MCAP's");
    }
    assert_eq!(got[1].len(), 201, "tf_ref: one per sample");
    assert_eq!(got[2].len(), 1, "reference: drawn once");
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_the_server_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (mut guard, port, stderr) = start(dir.path(), &["-o", "never.mcap"]);
    let child = guard.0.as_mut().unwrap();
    // The server waits for a subscription; interrupt it.
    let kill = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(t0.elapsed() < DEADLINE, "wmr-cli did not stop after Ctrl-C");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(status.code(), Some(130));
    let log = rest_of(&stderr);
    assert!(log.iter().any(|l| l.contains("interrupted, no output written")), "{log:?}");
    let mut left: Vec<_> = fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["s.toml"], "no output and no temporary file");
    assert!(TcpStream::connect(("127.0.0.1", port)).is_err(), "the server is closed");
}

#[test]
fn more_runs_than_threads_allowed_is_bad_input_and_nothing_is_served() {
    let dir = tempfile::tempdir().unwrap();
    let mut body = String::from("[sim]\nt_end = 0.1\n");
    for _ in 0..257 {
        body += "[[run]]\nstart = { x = 0.0, y = 0.0, theta = 0.0 }\ngoal = { x = 1.0, y = 0.0, theta = 0.0 }\n";
    }
    fs::write(dir.path().join("many.toml"), body).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(dir.path())
        .args(["run", "many.toml", "--live", "127.0.0.1:0", "-o", "many.mcap"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("at most 256 runs") && !err.contains("live on"), "{err}");
    let mut left: Vec<_> = fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    left.sort();
    assert_eq!(left, ["many.toml"]);
}
