//! Issue 12: mutated scenario text through `check`, `run` and `sweep`. Every outcome is
//! exit 0, or exit 2 with one line that names the key (or, for text that is not TOML, the
//! line), with no control character; never a panic, an abort or a hang; `check` agrees
//! with the library. Seeded: `WMR_FUZZ_CASES` (default 2,000) and `WMR_FUZZ_SEED`
//! (default 12) choose how many and which.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use wmr_core::sensor::gaussian::Gaussian;
use wmr_scenario::Scenario;

/// The core's seeded SplitMix64 stream, enough to pick mutations (a failure replays from
/// its seed and case number).
struct Rng(Gaussian);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The seed texts: every example scenario and the bad-input corpus, and small ones.
fn seeds() -> Vec<String> {
    let mut files = Vec::new();
    for dir in ["examples", "examples/paper", "examples/tracking", "crates/wmr-cli/tests/bad"] {
        for e in std::fs::read_dir(repo().join(dir)).unwrap().flatten() {
            if e.path().extension().is_some_and(|x| x == "toml") {
                files.push(e.path());
            }
        }
    }
    files.sort();
    let mut texts: Vec<String> = files.iter().map(|f| std::fs::read_to_string(f).unwrap()).collect();
    // The same files with little work (t_end = 0.05 s, few starts), so that `run` and
    // `sweep` take them too.
    let small: Vec<String> = texts
        .iter()
        .filter(|t| t.contains("t_end"))
        .map(|t| {
            let t = t.replace("n = 1000", "n = 3").replace("n = 40,", "n = 3,").replace("nx = 21", "nx = 2");
            t.lines()
                .map(|l| if l.trim_start().starts_with("t_end") { "t_end = 0.05" } else { l })
                .collect::<Vec<_>>()
                .join("\n")
        })
        .collect();
    texts.extend(small);
    texts.push(
        "[sim]\nt_end = 0.05\n[[run]]\nstart = { x = 0.1, theta_deg = 10 }\ngoal = { x = 1.0, y = 1.0 }\n".into(),
    );
    texts.push(
        "[sim]\nt_end = 0.05\n[sweep]\ngoal = { x = 0.5 }\ncontrollers = [{ kind = \"paper\" }, { kind = \"polar\" }]\n\
         grid = { x_min = -1.0, x_max = 1.0, nx = 2, y_min = -1.0, y_max = 1.0, ny = 2, theta_deg = [0.0, 90.0] }\n"
            .into(),
    );
    // Issue 39: the surfaces the tracking references brought: a reference of each kind, a
    // reference CSV and a robot preset named inside the scenario (written beside it, and
    // mutated too: see [`NAMED`]), a sweep over references.
    for reference in [
        "kind = \"circle\"\nradius = 0.5\nspeed = 0.3",
        "kind = \"figure_eight\"\nwidth = 2.0\nheight = 1.0\nperiod = 30.0",
        "kind = \"line\"\nspeed = 0.3\nstart = { x = 0.0, y = 0.0, theta_deg = 0.0 }",
        "kind = \"waypoints\"\npoints = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]",
        "kind = \"file\"\npath = \"ref.csv\"",
    ] {
        texts.push(format!(
            "[sim]\nt_end = 0.05\n[reference]\n{reference}\n[controller]\nkind = \"kanayama\"\n\
             [[run]]\nstart = {{ x = 0.0, y = -0.5, theta_deg = 0.0 }}\n"
        ));
    }
    texts.push(
        "[robot]\nfrom = \"robots/mine.toml\"\n[sim]\nt_end = 0.05\n[[run]]\ngoal = { x = 1.0, y = 1.0 }\n".into(),
    );
    texts.push(
        "[sim]\nt_end = 0.05\n[sweep]\ncontrollers = [{ kind = \"kanayama\" }]\n\
         references = [{ kind = \"circle\" }, { kind = \"file\", path = \"ref.csv\" }, { kind = \"figure_eight\" }]\n\
         random = { n = 2, radius = 0.1 }\n"
            .into(),
    );
    texts
}

/// The files the seed scenarios name (`reference.path`, `robot.from`), relative to the
/// scenario, and their text: written beside each case, mutated in some cases.
const NAMED: [(&str, &str); 2] = [
    ("ref.csv", "t,x,y\n0,0,0\n1,0.3,0\n2,0.6,0.1\n3,0.9,0.3\n"),
    (
        "robots/mine.toml",
        "[robot]\nmass = 4.0\nhalf_track = 0.15\n[drive]\nkind = \"torque\"\nmotor_torque_max = 0.2\n",
    ),
];

const VALUES: [&str; 25] = [
    "1e300",
    "1e-300",
    "1e25",
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1.7e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "99999999999999999999",
    "4294967296",
    "2147483648",
    "-0.0",
    "\"text\"",
    "true",
    "[1, 2, 3]",
    "{ x = 1 }",
    "[]",
    "{}",
    "\"\\u001b[31m\\u202e\"",
    "1e6",
    "0.003",
];

/// One mutation of `text`.
fn mutate(text: &str, rng: &mut Rng) -> Vec<u8> {
    let mut bytes = text.as_bytes().to_vec();
    match rng.below(11) {
        // A number (or the value after `=`) replaced.
        0..=3 => {
            let places: Vec<usize> = text
                .match_indices("= ")
                .map(|(i, _)| i + 2)
                .chain(text.match_indices(['0', '1', '2', '5'].as_slice()).map(|(i, _)| i))
                .collect();
            if let Some(&at) = places.get(rng.below(places.len())) {
                let end = text[at..].find([',', '}', '\n', ' ', ']']).map_or(text.len(), |e| at + e);
                let mut out = text[..at].to_owned();
                let v: &str = VALUES[rng.below(VALUES.len())];
                out.push_str(v);
                out.push_str(&text[end..]);
                bytes = out.into_bytes();
            }
        }
        // A key renamed: a character dropped or doubled.
        4 => {
            if !bytes.is_empty() {
                let at = rng.below(bytes.len());
                if rng.below(2) == 0 {
                    bytes.remove(at);
                } else {
                    bytes.insert(at, bytes[at]);
                }
            }
        }
        // Truncated at a random offset.
        5 => bytes.truncate(rng.below(bytes.len() + 1)),
        // Random bytes (control characters, invalid UTF-8) inserted.
        6 => {
            let at = rng.below(bytes.len() + 1);
            let n = 1 + rng.below(8);
            let junk: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
            bytes.splice(at..at, junk);
        }
        // Deep nesting.
        7 => {
            let depth = 1 + rng.below(3000);
            let nest = if rng.below(2) == 0 {
                format!("{}1{}", "[".repeat(depth), "]".repeat(depth))
            } else {
                format!("{}1{}", "{ a = ".repeat(depth), " }".repeat(depth))
            };
            bytes = format!("{text}\nname = {nest}\n").into_bytes();
        }
        // Many runs.
        8 => {
            let n = 1 + rng.below(500);
            let mut out = text.to_owned();
            for i in 0..n {
                out.push_str(&format!("[[run]]\ngoal = {{ x = {} }}\n", (i % 7) as f64 * 0.1));
            }
            bytes = out.into_bytes();
        }
        // `[[run]]` as `[run]`, tables duplicated.
        9 => bytes = text.replacen("[[run]]", "[run]", 1).into_bytes(),
        _ => {
            let lines: Vec<&str> = text.lines().collect();
            if !lines.is_empty() {
                let l = lines[rng.below(lines.len())];
                bytes = format!("{text}\n{l}\n").into_bytes();
            }
        }
    }
    bytes
}

/// Plant steps the CLI would run for this text, if it is a valid scenario.
fn work(text: &[u8], dir: &Path) -> Option<u128> {
    let text = std::str::from_utf8(text).ok()?;
    let sc = Scenario::from_toml_str_in(text, "fuzz", dir).ok()?;
    Some(wmr_scenario::total_steps(&sc))
}

/// One CLI call: exit 0 or exit 2 with one clean line; `Err` describes anything else.
fn call(dir: &Path, args: &[&str]) -> Result<Output, String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(dir)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let started = Instant::now();
    while child.try_wait().map_err(|e| e.to_string())?.is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            return Err(format!("{args:?}: still running after 60 s"));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let o = child.wait_with_output().map_err(|e| e.to_string())?;
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    match o.status.code() {
        Some(0) => {}
        Some(2) => {
            let lines: Vec<&str> = err.lines().filter(|l| !l.starts_with("wmr-cli: warning: ")).collect();
            if lines.len() != 1 {
                return Err(format!("{args:?}: not one line: {err:?}"));
            }
            let line = lines[0];
            if !line.starts_with("wmr-cli: error: ") {
                return Err(format!("{args:?}: {err:?}"));
            }
            if line.chars().any(|c| c.is_control() || ('\u{202a}'..='\u{202e}').contains(&c)) {
                return Err(format!("{args:?}: raw control character: {err:?}"));
            }
            // `FILE: [line L: ]KEY: reason`, or a file or syntax error without a key.
            let after = line.split_once("case.toml: ").map(|(_, r)| r).unwrap_or("");
            let after = after.split_once(": ").filter(|(l, _)| l.starts_with("line ")).map_or(after, |(_, r)| r);
            let names_key = after.split_once(": ").is_some_and(|(k, _)| {
                !k.is_empty() && k.chars().all(|c| c.is_ascii_alphanumeric() || "_.[]#-".contains(c))
            });
            let keyless = after.starts_with("bad TOML: ") || after.contains("is not UTF-8 text");
            if !(names_key || keyless) {
                return Err(format!("{args:?}: names no key: {err:?}"));
            }
        }
        code => return Err(format!("{args:?}: exit {code:?} (signal?): {err:?}")),
    }
    if err.contains("panicked") {
        return Err(format!("{args:?}: panic: {err}"));
    }
    Ok(o)
}

#[test]
fn mutated_scenarios_exit_0_or_2_with_one_line_naming_the_key() {
    let cases: usize = std::env::var("WMR_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(2000);
    let seed: u64 = std::env::var("WMR_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(12);
    let seeds = seeds();
    let next = AtomicUsize::new(0);
    let started = Instant::now();
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()).min(4);
    let failures: Vec<String> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let dir = tempfile::tempdir().unwrap();
                    let mut found = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= cases {
                            break;
                        }
                        let mut rng = Rng(Gaussian::new(seed, i as u64));
                        let base = rng.pick(&seeds).clone();
                        let mut text = mutate(&base, &mut rng);
                        if rng.below(3) == 0 {
                            text = mutate(&String::from_utf8_lossy(&text), &mut rng);
                        }
                        let t0 = Instant::now();
                        let file = dir.path().join("case.toml");
                        std::fs::write(&file, &text).unwrap();
                        // The named files, one of them mutated in a case of four.
                        let mutated = (rng.below(4) == 0).then(|| rng.below(NAMED.len()));
                        for (k, (name, body)) in NAMED.iter().enumerate() {
                            let path = dir.path().join(name);
                            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                            let body =
                                if mutated == Some(k) { mutate(body, &mut rng) } else { body.as_bytes().to_vec() };
                            std::fs::write(path, body).unwrap();
                        }
                        let lib_ok = work(&text, dir.path());
                        let mut fail = |what: String| found.push(format!("case {i} (seed {seed}): {what}"));
                        match call(dir.path(), &["check", "case.toml"]) {
                            Ok(o) => {
                                if lib_ok.is_some() != o.status.success() {
                                    fail(format!("check exit {:?} but the library says {lib_ok:?}", o.status.code()));
                                }
                            }
                            Err(e) => fail(e),
                        }
                        // Small work only: run and sweep what takes at most 20,000 plant steps.
                        if lib_ok.is_some_and(|w| w <= 20_000) {
                            for args in [["run", "case.toml", "-o", "out.csv"], ["sweep", "case.toml", "-o", "out.csv"]]
                            {
                                if let Err(e) = call(dir.path(), &args) {
                                    fail(e);
                                }
                            }
                        }
                        let left: Vec<String> = std::fs::read_dir(dir.path())
                            .unwrap()
                            .flatten()
                            .map(|e| e.file_name().to_string_lossy().into_owned())
                            .filter(|n| n.ends_with(".tmp"))
                            .collect();
                        if !left.is_empty() {
                            fail(format!("temporary files left: {left:?}"));
                        }
                        if std::env::var("WMR_FUZZ_SLOW").is_ok() && t0.elapsed() > Duration::from_millis(150) {
                            eprintln!(
                                "slow case {i}: {:?} {:?}",
                                t0.elapsed(),
                                String::from_utf8_lossy(&text[..text.len().min(120)])
                            );
                        }
                        if !found.is_empty() && found.len() < 3 {
                            let keep = dir.path().join(format!("failed-{i}.toml"));
                            let _ = std::fs::copy(&file, keep);
                        }
                    }
                    found
                })
            })
            .collect();
        workers.into_iter().flat_map(|w| w.join().unwrap()).collect()
    });
    eprintln!("{cases} cases in {:.1} s", started.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}

/// Issue 25: the live server under seeded abuse: garbage instead of HTTP, random
/// subprotocols, malformed and oversized frames after the handshake, random requests,
/// client messages, clients that subscribe and never read, bursts of connections past the
/// limit. After every case the server still runs; at the end a proper client still gets
/// the stream, and Ctrl-C still ends it (exit 130). `WMR_FUZZ_LIVE_CASES` (default 300)
/// and `WMR_FUZZ_SEED` choose how many and which. Every wait has a deadline and awaits an
/// event (a reply, the server closing the socket, the process's exit).
#[test]
fn live_server_survives_malformed_frames_slow_clients_and_many_connections() {
    use std::io::{BufRead as _, BufReader, Read as _, Write as _};
    use std::net::TcpStream;
    use tungstenite::Message;
    use tungstenite::client::IntoClientRequest as _;

    let cases: usize = std::env::var("WMR_FUZZ_LIVE_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(300);
    let seed: u64 = std::env::var("WMR_FUZZ_SEED").ok().and_then(|v| v.parse().ok()).unwrap_or(12);
    let dir = tempfile::tempdir().unwrap();
    // 3,000 s of simulated time at speed 10: the stream outlasts the cases.
    std::fs::write(dir.path().join("s.toml"), "[sim]\nt_end = 3000.0\nlog_dt = 0.1\n[[run]]\ngoal = { x = 1.0 }\n")
        .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_wmr-cli"))
        .current_dir(dir.path())
        .args(["run", "s.toml", "--live", "127.0.0.1:0", "--speed", "10"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (tx, stderr) = std::sync::mpsc::channel();
    let pipe = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(pipe).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let port: u16 = loop {
        let line = stderr.recv_timeout(Duration::from_secs(60)).expect("the `live on` line");
        if let Some(rest) = line.split("live on ws://127.0.0.1:").nth(1) {
            break rest.split(|c: char| !c.is_ascii_digit()).next().unwrap().parse().unwrap();
        }
    };
    let timeout = Some(Duration::from_secs(10));
    let tcp = || {
        let s = TcpStream::connect(("127.0.0.1", port)).unwrap();
        s.set_read_timeout(timeout).unwrap();
        s.set_write_timeout(timeout).unwrap();
        s
    };
    // Reads until the server closes (EOF or reset): the event a bad client awaits.
    let await_close = |s: &mut TcpStream| -> Result<(), String> {
        let mut buf = [0u8; 65536];
        let t0 = Instant::now();
        loop {
            match s.read(&mut buf) {
                Ok(0) | Err(_) if t0.elapsed() < Duration::from_secs(10) => return Ok(()),
                Ok(_) if t0.elapsed() < Duration::from_secs(10) => {}
                _ => return Err("the server did not close the connection within 10 s".into()),
            }
        }
    };
    // A 503 (every slot held by clients younger than the server's grace: the half-sent
    // requests and idle clients below) is retried until a slot frees, at most 10 s.
    let handshake = |protocols: &str| -> Result<tungstenite::WebSocket<TcpStream>, String> {
        let t0 = Instant::now();
        loop {
            let mut req = format!("ws://127.0.0.1:{port}").into_client_request().unwrap();
            req.headers_mut().insert("sec-websocket-protocol", protocols.parse().unwrap());
            match tungstenite::client(req, tcp()) {
                Ok((ws, _)) => return Ok(ws),
                Err(e) if e.to_string().contains("503") && t0.elapsed() < Duration::from_secs(10) => {
                    std::thread::sleep(Duration::from_millis(20))
                }
                Err(e) => return Err(format!("handshake: {e}")),
            }
        }
    };
    // A ping answered proves the client's thread alive after what it was sent.
    let await_pong = |ws: &mut tungstenite::WebSocket<TcpStream>| -> Result<(), String> {
        ws.send(Message::Ping(b"fuzz".to_vec().into())).map_err(|e| format!("ping: {e}"))?;
        loop {
            match ws.read() {
                Ok(Message::Pong(p)) if &p[..] == b"fuzz" => return Ok(()),
                Ok(_) => {}
                Err(e) => return Err(format!("no pong: {e}")),
            }
        }
    };
    let words = ["subscribe", "unsubscribe", "advertise", "getParameters", "", "op", "\u{0}", "\u{202e}"];
    let mut slow = Vec::new();
    let (mut partial, mut idle) = (Vec::new(), Vec::new());
    let mut failures = Vec::new();
    let started = Instant::now();
    for i in 0..cases {
        let mut rng = Rng(Gaussian::new(seed, 0x11fe ^ i as u64));
        let kind = rng.below(9);
        let outcome: Result<(), String> = (|| match kind {
            // Garbage instead of an HTTP request, then our side closed.
            0 => {
                let mut s = tcp();
                let n = rng.below(2000);
                let junk: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
                let _ = s.write_all(&junk);
                let _ = s.shutdown(std::net::Shutdown::Write);
                await_close(&mut s)
            }
            // Random subprotocol lists: served (101) with one of ours, or refused (400).
            1 => {
                // Up to 20 offers (issue 39: the 17th was never looked at).
                let n = if rng.below(4) == 0 { 16 + rng.below(5) } else { rng.below(4) };
                let offer: Vec<&str> = (0..n)
                    .map(|_| *rng.pick(&["foxglove.sdk.v1", "foxglove.websocket.v1", "foxglove.sdk.v1.1", "x", "a b"]))
                    .collect();
                let offer = if offer.is_empty() { "none".to_owned() } else { offer.join(", ") };
                let ours = offer.split(", ").any(|p| p == "foxglove.sdk.v1" || p == "foxglove.websocket.v1");
                match (handshake(&offer), ours) {
                    (Ok(mut ws), true) => await_pong(&mut ws),
                    (Ok(_), false) => Err(format!("served though offered {offer:?}")),
                    (Err(e), false) if e.contains("400") => Ok(()),
                    (Err(e), _) => Err(format!("offered {offer:?}: {e}")),
                }
            }
            // Malformed frames after the handshake: the server closes the connection.
            2 => {
                let mut ws = handshake("foxglove.sdk.v1")?;
                let s = ws.get_mut();
                let frame = if rng.below(2) == 0 {
                    // A header claiming 2^62 bytes.
                    vec![0x82, 0xFF, 0x40, 0, 0, 0, 0, 0, 0, 0, 1, 2, 3, 4]
                } else {
                    // A whole masked frame with reserved bits set: always a protocol error.
                    let n = rng.below(100);
                    let mut f = vec![0x80 | 0x30 | (rng.next() as u8 & 0x0F), 0x80 | n as u8];
                    f.extend((0..4 + n).map(|_| rng.next() as u8));
                    f
                };
                let _ = s.write_all(&frame);
                await_close(s)
            }
            // Random requests: answered (or not), the client served on.
            3 => {
                let mut ws = handshake("foxglove.websocket.v1")?;
                for _ in 0..rng.below(5) + 1 {
                    let op = rng.pick(&words);
                    let id = rng.pick(&["0", "-1", "4294967296", "1e300", "\"x\"", "null", "7"]);
                    let ch = rng.pick(&["0", "1", "99999999999999999999", "-3", "[]", "2"]);
                    let text = match rng.below(3) {
                        0 => format!("{{\"op\":\"{op}\",\"subscriptions\":[{{\"id\":{id},\"channelId\":{ch}}}]}}"),
                        1 => format!("{{\"op\":\"{op}\",\"subscriptionIds\":[{id}]}}"),
                        _ => (0..rng.below(200)).map(|_| char::from(32 + (rng.next() % 95) as u8)).collect(),
                    };
                    ws.send(Message::text(text)).map_err(|e| format!("send: {e}"))?;
                }
                if rng.below(2) == 0 {
                    ws.send(Message::binary(vec![1u8; rng.below(100)])).map_err(|e| format!("send: {e}"))?;
                }
                await_pong(&mut ws)
            }
            // A client that subscribes to everything and never reads (kept open a while).
            4 => {
                let mut ws = handshake("foxglove.sdk.v1")?;
                let subs: Vec<String> = (0..6).map(|c| format!("{{\"id\":{c},\"channelId\":{c}}}")).collect();
                ws.send(Message::text(format!("{{\"op\":\"subscribe\",\"subscriptions\":[{}]}}", subs.join(","))))
                    .map_err(|e| format!("send: {e}"))?;
                slow.push(ws);
                if slow.len() > 6 {
                    slow.remove(0);
                }
                Ok(())
            }
            // A burst of connections past the limit: each gets served or a 503 that says why.
            5 => {
                let mut burst: Vec<TcpStream> = (0..rng.below(24) + 1).map(|_| tcp()).collect();
                for s in &mut burst {
                    let _ = s.write_all(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n");
                }
                for mut s in burst {
                    let mut reply = String::new();
                    let _ = s.read_to_string(&mut reply);
                    if !(reply.starts_with("HTTP/1.1 400") || reply.starts_with("HTTP/1.1 503")) {
                        return Err(format!("burst: unexpected reply {reply:?}"));
                    }
                    if reply.starts_with("HTTP/1.1 503") && !reply.contains("too many connections") {
                        return Err(format!("a refusal must say why: {reply:?}"));
                    }
                }
                Ok(())
            }
            // Issue 39: a request sent in part and never finished, kept open (the server
            // ends it at its handshake deadline, or gives its slot to a new connection).
            7 => {
                let mut s = tcp();
                let cut = 1 + rng.below(40);
                let _ = s.write_all(&b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"[..cut]);
                partial.push(s);
                if partial.len() > 20 {
                    partial.remove(0);
                }
                Ok(())
            }
            // Issue 39: a client that completes the handshake and never subscribes, kept
            // open (sent away at the idle limit or for a new connection).
            8 => {
                idle.push(handshake("foxglove.sdk.v1")?);
                if idle.len() > 20 {
                    idle.remove(0);
                }
                Ok(())
            }
            // A valid handshake, then the connection dropped mid-frame.
            _ => {
                let mut ws = handshake("foxglove.sdk.v1")?;
                let _ = ws.get_mut().write_all(&[0x81, 0xFE, 0x01]);
                Ok(())
            }
        })();
        if let Err(e) = outcome {
            failures.push(format!("case {i} (kind {kind}, seed {seed}): {e}"));
        }
        if let Some(status) = child.try_wait().unwrap() {
            let log: Vec<String> = stderr.try_iter().collect();
            panic!("the server exited ({status:?}) after case {i} (kind {kind}): {log:?}; failures {failures:?}");
        }
    }
    drop(slow);
    // A proper client still gets the stream, past the half-sent requests and idle clients
    // still open.
    let mut ws = handshake("foxglove.sdk.v1").expect("a proper client after the fuzz");
    ws.send(Message::text(r#"{"op":"subscribe","subscriptions":[{"id":1,"channelId":0}]}"#)).unwrap();
    let mut got = 0;
    while got < 3 {
        if let Message::Binary(b) = ws.read().expect("messages after the fuzz")
            && b[0] == 1
        {
            got += 1;
        }
    }
    drop((partial, idle));
    assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(t0.elapsed() < Duration::from_secs(10), "Ctrl-C after the fuzz did not stop the server");
        std::thread::sleep(Duration::from_millis(10));
    };
    let log: Vec<String> = stderr.try_iter().collect();
    assert_eq!(status.code(), Some(130), "{log:?}");
    assert!(!log.iter().any(|l| l.contains("panicked")), "{log:?}");
    eprintln!("{cases} live cases in {:.1} s", started.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}
