//! Issue 25 items 2-5 and 13 (live parts), issue 27 (every viewer): the live server when
//! clients misbehave or signals come. Every wait awaits an event (the process's exit, a
//! line on its stderr, a socket's reply) with a deadline; nothing sleeps and hopes.
//! Only 127.0.0.1.

use std::fs;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::os::unix::process::ExitStatusExt as _;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::wait;

use tungstenite::Message;
use tungstenite::client::IntoClientRequest as _;

/// Longest any test waits for anything.
const DEADLINE: Duration = Duration::from_secs(60);

/// Two runs, 2 s, a sample every 10 ms: a quick stream.
const SMALL: &str = "[sim]\nt_end = 2.0\nlog_dt = 0.01\n[[run]]\ngoal = { x = 1.0, y = 1.0 }\n[[run]]\n\
                     start = { x = -0.5, y = 0.2, theta = 0.3 }\ngoal = { x = 0.0 }\n";

/// Four runs of 30 s logged every ms: about 480,000 messages, 60 MB, far more than a
/// socket's buffers hold, so a client that does not read fills them.
const BIG: &str = "[sim]\nt_end = 30.0\nlog_dt = 0.001\n[[run]]\ngoal = { x = 1.0, y = 1.0 }\n[[run]]\n\
                   goal = { x = -1.0 }\n[[run]]\ngoal = { y = 1.0 }\n[[run]]\ngoal = { x = 1.0, y = -1.0 }\n";

/// Kills the child when a test fails half-way.
struct Live {
    child: Child,
    port: u16,
    stderr: mpsc::Receiver<String>,
    seen: Vec<String>,
}

impl Drop for Live {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Live {
    /// Starts `wmr-cli run s.toml --live 127.0.0.1:0 ARGS` on `scenario` in `dir` and
    /// awaits its `live on ws://` line.
    fn start(dir: &Path, scenario: &str, args: &[&str], env: &[(&str, &str)]) -> Live {
        fs::write(dir.join("s.toml"), scenario).unwrap();
        let mut child = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
            .current_dir(dir)
            .args(["run", "s.toml", "--live", "127.0.0.1:0"])
            .args(args)
            .envs(env.iter().copied())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let stderr = child.stderr.take().unwrap();
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                let _ = tx.send(line);
            }
        });
        let mut live = Live { child, port: 0, stderr: rx, seen: Vec::new() };
        let line = live.await_line("live on ws://127.0.0.1:");
        let rest = line.split("live on ws://127.0.0.1:").nth(1).unwrap();
        live.port = rest.split(|c: char| !c.is_ascii_digit()).next().unwrap().parse().unwrap();
        live
    }

    /// Awaits a line of stderr containing `what`.
    fn await_line(&mut self, what: &str) -> String {
        let t0 = Instant::now();
        loop {
            let left = DEADLINE.saturating_sub(t0.elapsed());
            match self.stderr.recv_timeout(left) {
                Ok(line) => {
                    self.seen.push(line.clone());
                    if line.contains(what) {
                        return line;
                    }
                }
                Err(_) => panic!("no stderr line with {what:?} in time; got {:?}", self.seen),
            }
        }
    }

    /// Awaits the exit within `limit`, and the rest of stderr.
    fn await_exit(&mut self, limit: Duration) -> (ExitStatus, Vec<String>) {
        let t0 = Instant::now();
        let status = loop {
            if let Some(s) = self.child.try_wait().unwrap() {
                break s;
            }
            assert!(t0.elapsed() < limit, "wmr-cli still running after {limit:?}; stderr: {:?}", self.seen);
            // Polling the exit status: the event awaited is the exit itself.
            std::thread::sleep(Duration::from_millis(10));
        };
        while let Ok(line) = self.stderr.recv_timeout(Duration::from_secs(10)) {
            self.seen.push(line);
        }
        (status, self.seen.clone())
    }

    fn signal(&self, sig: &str) {
        assert!(Command::new("kill").args([sig, &self.child.id().to_string()]).status().unwrap().success());
    }
}

type Socket = tungstenite::WebSocket<TcpStream>;

/// A WebSocket client offering `protocols`; returns the socket and the subprotocol the
/// server answered.
fn connect(port: u16, protocols: &str) -> (Socket, String) {
    let stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    let mut req = format!("ws://127.0.0.1:{port}").into_client_request().unwrap();
    req.headers_mut().insert("sec-websocket-protocol", protocols.parse().unwrap());
    let (ws, resp) = tungstenite::client(req, stream).expect("WebSocket handshake");
    let chosen = resp.headers().get("sec-websocket-protocol").unwrap().to_str().unwrap().to_owned();
    (ws, chosen)
}

/// Reads serverInfo and advertise; returns every channel id.
fn channels(ws: &mut Socket) -> Vec<u64> {
    loop {
        if let Message::Text(t) = ws.read().expect("advertise") {
            let v: serde_json::Value = serde_json::from_str(&t).unwrap();
            if v["op"] == "advertise" {
                return v["channels"].as_array().unwrap().iter().map(|c| c["id"].as_u64().unwrap()).collect();
            }
        }
    }
}

/// Subscribes to every channel.
fn subscribe_all(ws: &mut Socket) {
    let ids = channels(ws);
    let subs: Vec<_> = ids.iter().enumerate().map(|(k, id)| serde_json::json!({ "id": k, "channelId": id })).collect();
    ws.send(Message::text(serde_json::json!({ "op": "subscribe", "subscriptions": subs }).to_string())).unwrap();
}

/// Reads until the server closes; returns the message-data frames received.
fn read_to_end(ws: &mut Socket) -> usize {
    let t0 = Instant::now();
    let mut n = 0;
    loop {
        assert!(t0.elapsed() < DEADLINE, "the stream did not end in time");
        match ws.read() {
            Ok(Message::Binary(b)) if b[0] == 1 => n += 1,
            Ok(_) => {}
            Err(_) => return n,
        }
    }
}

/// An HTTP upgrade request with `protocol_header` (a whole header line, or nothing); the
/// server's whole reply (it closes after a refusal).
fn raw_upgrade(port: u16, protocol_header: &str) -> String {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    let req = format!(
        "GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n{protocol_header}\r\n"
    );
    s.write_all(req.as_bytes()).unwrap();
    let mut reply = String::new();
    let _ = s.read_to_string(&mut reply);
    reply
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<_> =
        fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

/// Issue 25 item 2: a client that subscribes and never reads used to keep the process up
/// long after the runs (and Ctrl-C ignored). Now the session ends with the runs; a client
/// that reads gets every message even so.
#[test]
fn regression_25_2_a_client_that_never_reads_does_not_hold_the_server() {
    let dir = tempfile::tempdir().unwrap();
    let mut live = Live::start(dir.path(), BIG, &["--speed", "1000000", "-o", "out.mcap"], &[]);
    let (mut lazy, _) = connect(live.port, "foxglove.sdk.v1");
    subscribe_all(&mut lazy); // and never read again
    let (mut reader, _) = connect(live.port, "foxglove.sdk.v1");
    subscribe_all(&mut reader);
    let got = read_to_end(&mut reader);
    let (status, log) = live.await_exit(DEADLINE);
    assert!(status.success(), "{status:?} {log:?}");
    assert!(got > 0);
    assert_eq!(entries(dir.path()), ["out.mcap", "s.toml"]);
    let end = log.iter().find(|l| l.contains("client connection(s)")).expect("the live summary line");
    assert!(end.contains("2 client connection(s)"), "{end}");
    drop(lazy);
}

/// Issue 25 item 2 and 5: Ctrl-C mid-stream with clients that do not read stops at once,
/// exit 130, no output and no temporary file.
#[test]
fn regression_25_2_ctrl_c_mid_stream_with_stuck_clients_exits_130_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut live = Live::start(dir.path(), BIG, &["--speed", "1000000", "-o", "out.mcap"], &[]);
    let mut lazy = Vec::new();
    for _ in 0..3 {
        let (mut ws, _) = connect(live.port, "foxglove.sdk.v1");
        subscribe_all(&mut ws);
        lazy.push(ws);
    }
    // Await the stream: the first message reaches a client that reads once.
    let (mut one, _) = connect(live.port, "foxglove.sdk.v1");
    subscribe_all(&mut one);
    loop {
        if let Message::Binary(b) = one.read().expect("a message")
            && b[0] == 1
        {
            break;
        }
    }
    live.signal("-INT");
    let (status, log) = live.await_exit(DEADLINE);
    assert_eq!(status.code(), Some(130), "{log:?}");
    assert_eq!(entries(dir.path()), ["s.toml"], "no output, no temporary file");
    drop(lazy);
}

/// Issue 25 item 4: Ctrl-C while the server waits for a run's next sample (1e9 plant
/// steps away) used to be ignored.
#[test]
fn regression_25_4_ctrl_c_between_two_far_apart_samples() {
    let dir = tempfile::tempdir().unwrap();
    let far = "[sim]\nt_end = 1e6\nlog_dt = 1e6\n[[run]]\ngoal = { x = 1.0 }\n";
    let mut live = Live::start(dir.path(), far, &["--speed", "1000000"], &[]);
    let (mut ws, _) = connect(live.port, "foxglove.sdk.v1");
    subscribe_all(&mut ws);
    loop {
        if let Message::Binary(b) = ws.read().expect("the first sample")
            && b[0] == 1
        {
            break;
        }
    }
    live.signal("-INT");
    let (status, log) = live.await_exit(DEADLINE);
    assert_eq!(status.code(), Some(130), "{log:?}");
}

/// Issue 25 item 13: in live view SIGTERM and SIGHUP exit 143 and 129 (they exited 130),
/// in every state: waiting for a client, and streaming.
#[test]
fn regression_25_13_sigterm_and_sighup_exit_143_and_129_in_live_view() {
    for (sig, code) in [("-TERM", 143), ("-HUP", 129), ("-INT", 130)] {
        let dir = tempfile::tempdir().unwrap();
        let mut live = Live::start(dir.path(), SMALL, &["-o", "out.mcap"], &[]);
        live.signal(sig);
        let (status, log) = live.await_exit(DEADLINE);
        assert_eq!(status.code(), Some(code), "{sig}: {status:?} {log:?}");
        assert!(log.iter().any(|l| l.contains("interrupted, no output written")), "{log:?}");
        assert_eq!(entries(dir.path()), ["s.toml"]);
    }
}

/// Issue 25 item 2: a second Ctrl-C ends the process at once by the signal, and still
/// leaves no temporary file.
#[test]
fn a_second_signal_ends_at_once_and_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut live = Live::start(dir.path(), SMALL, &["-o", "out.mcap"], &[]);
    // Two signals in a row: the first asks the session to stop, the second ends it.
    live.signal("-INT");
    live.signal("-INT");
    let (status, log) = live.await_exit(DEADLINE);
    assert!(status.code() == Some(130) || status.signal() == Some(2), "{status:?} {log:?}");
    assert_eq!(entries(dir.path()), ["s.toml"]);
}

/// Issue 25 item 3: speeds whose pacing overflowed a Duration panicked (exit 101) once a
/// client subscribed; now refused on the command line, naming `--speed` and the range.
#[test]
fn regression_25_3_absurd_speeds_are_refused_at_parse_time() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("s.toml"), SMALL).unwrap();
    for speed in ["1e-300", "5e-324", "1e-21", "0", "-1", "nan", "inf", "1e7", "x"] {
        // Accepted, the old code waited for a client: awaited with a deadline.
        let mut child = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
            .current_dir(dir.path())
            .args(["run", "s.toml", "--live", "127.0.0.1:0", &format!("--speed={speed}")])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let what = format!("--speed {speed} was accepted");
        let (status, err) = wait::exit_within(&mut child, Duration::from_secs(20), &what);
        assert_eq!(status.code(), Some(2), "--speed {speed}: {err}");
        assert!(err.contains("--speed") && err.contains("1e-3") && err.contains("1e6"), "{speed}: {err}");
        assert!(!err.contains("live on"), "{err}");
    }
}

/// Issue 25 item 13: a bind failure exited 1 after `--layout` was written; multicast and
/// broadcast addresses bound silently. Now exit 2 and nothing written.
#[test]
fn regression_25_13_bind_failures_exit_2_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("s.toml"), SMALL).unwrap();
    let taken = TcpListener::bind("127.0.0.1:0").unwrap();
    let busy = taken.local_addr().unwrap().to_string();
    for addr in [busy.as_str(), "224.0.0.1:8765", "255.255.255.255:8765", "[ff02::1]:8765"] {
        let o = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
            .current_dir(dir.path())
            .args(["run", "s.toml", "--live", addr, "--layout", "l.json", "-o", "o.mcap"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{addr}: {err}");
        assert!(err.contains(addr.rsplit_once(':').unwrap().0.trim_matches(['[', ']'])), "{addr}: {err}");
        assert_eq!(entries(dir.path()), ["s.toml"], "{addr}: nothing written");
    }
}

/// Issue 27: both names of the protocol are served, a stream to each; a client offering
/// neither is told what it offered and what is accepted (it was told the header was
/// missing).
#[test]
fn regression_27_both_subprotocols_are_served_and_a_refusal_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let mut live = Live::start(dir.path(), SMALL, &["--speed", "20"], &[]);
    let no_header = raw_upgrade(live.port, "");
    assert!(no_header.starts_with("HTTP/1.1 400"), "{no_header}");
    assert!(no_header.contains("no subprotocol") && no_header.contains("foxglove.websocket.v1"), "{no_header}");
    let wrong = raw_upgrade(live.port, "Sec-WebSocket-Protocol: foo.v9, bar\r\n");
    assert!(wrong.starts_with("HTTP/1.1 400"), "{wrong}");
    assert!(
        wrong.contains("foo.v9, bar") && wrong.contains("foxglove.sdk.v1") && wrong.contains("foxglove.websocket.v1"),
        "{wrong}"
    );
    let (mut old, chosen_old) = connect(live.port, "foxglove.websocket.v1");
    assert_eq!(chosen_old, "foxglove.websocket.v1");
    let (mut sdk, chosen_sdk) = connect(live.port, "foxglove.websocket.v1, foxglove.sdk.v1");
    assert_eq!(chosen_sdk, "foxglove.sdk.v1");
    subscribe_all(&mut old);
    subscribe_all(&mut sdk);
    let (a, b) = (read_to_end(&mut old), read_to_end(&mut sdk));
    let (status, log) = live.await_exit(DEADLINE);
    assert!(status.success(), "{log:?}");
    // Both get every message of both runs (2 x 201 samples on tf and sample at least).
    assert!(a >= 804 && a == b, "{a} vs {b}");
}

/// Issue 25 item 5: connections are limited (a clear refusal beyond), queues are bounded
/// in bytes with the oldest dropped and counted, and memory stays bounded whatever the
/// number of clients that do not read (200 took 786 MB and growing).
#[test]
fn regression_25_5_connections_are_limited_and_memory_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let mut live = Live::start(dir.path(), BIG, &["--speed", "1000000"], &[]);
    let mut lazy = Vec::new();
    for _ in 0..16 {
        let (mut ws, _) = connect(live.port, "foxglove.sdk.v1");
        subscribe_all(&mut ws);
        lazy.push(ws);
    }
    // The 17th to 200th: refused with a reply that says why.
    let reply = raw_upgrade(live.port, "Sec-WebSocket-Protocol: foxglove.sdk.v1\r\n");
    assert!(reply.starts_with("HTTP/1.1 503"), "{reply}");
    assert!(reply.contains("too many connections") && reply.contains("at most 16"), "{reply}");
    let mut refused = Vec::new();
    for _ in 0..183 {
        refused.push(TcpStream::connect(("127.0.0.1", live.port)).unwrap());
    }
    let pid = live.child.id();
    let mut peak_kb = 0u64;
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = live.child.try_wait().unwrap() {
            break s;
        }
        assert!(t0.elapsed() < DEADLINE, "still running");
        // The peak so far (VmHWM only grows): read while the process lives.
        if let Ok(st) = fs::read_to_string(format!("/proc/{pid}/status"))
            && let Some(kb) = st.lines().find_map(|l| l.strip_prefix("VmHWM:"))
        {
            peak_kb = peak_kb.max(kb.trim().trim_end_matches(" kB").trim().parse().unwrap_or(0));
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let (_, log) = live.await_exit(DEADLINE);
    assert!(status.success(), "{log:?}");
    let end = log.iter().find(|l| l.contains("client connection(s)")).expect("the live summary line");
    assert!(end.contains("16 client connection(s)") && end.contains("refused"), "{end}");
    assert!(end.contains("dropped, oldest first"), "16 clients not reading 60 MB each must drop: {end}");
    // 16 queues of 4 MiB, the runs' queues and the binary: well under 200 MB.
    assert!(peak_kb > 1000 && peak_kb < 200_000, "peak resident memory {peak_kb} kB");
    eprintln!("peak resident memory with 16 stuck clients and 184 refused: {peak_kb} kB");
    drop((lazy, refused));
}

/// Issue 26 (27's leftover): with no viewer a `--live` session waited for one for ever,
/// so the documented command hung the docs test for 10 min. With
/// `WMR_LIVE_START_AFTER_S` it streams after that long without a client and ends when its
/// runs end (exit 0, the MCAP file written); a value that is no such number is refused
/// by name (exit 2).
#[test]
fn regression_26_a_live_session_without_a_viewer_ends_when_asked_to_start_anyway() {
    let dir = tempfile::tempdir().unwrap();
    let mut live =
        Live::start(dir.path(), SMALL, &["--speed", "100", "-o", "o.mcap"], &[("WMR_LIVE_START_AFTER_S", "0.2")]);
    let (status, err) = live.await_exit(DEADLINE);
    assert!(status.success(), "{err:?}");
    assert!(fs::metadata(dir.path().join("o.mcap")).unwrap().len() > 0);
    for bad in ["-1", "nan", "x", "1e7"] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
            .current_dir(dir.path())
            .args(["run", "s.toml", "--live", "127.0.0.1:0"])
            .env("WMR_LIVE_START_AFTER_S", bad)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let (status, err) = wait::exit_within(&mut child, Duration::from_secs(20), bad);
        assert_eq!(status.code(), Some(2), "{bad}: {err}");
        assert!(err.contains("WMR_LIVE_START_AFTER_S") && !err.contains("live on"), "{bad}: {err}");
    }
}
