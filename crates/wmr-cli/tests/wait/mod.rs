//! Awaiting a child process with a deadline (shared by the CLI tests): the exit is the
//! event; past the deadline the child is killed and the test fails, never hangs.

use std::io::Read;
use std::process::{Child, ExitStatus};
use std::time::{Duration, Instant};

/// Waits for `child` to exit within `limit` and returns its status and its piped stderr;
/// kills it and panics with `what` when it is still running then.
pub fn exit_within(child: &mut Child, limit: Duration, what: &str) -> (ExitStatus, String) {
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            panic!("{what}: still running after {} s", limit.as_secs());
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        e.read_to_string(&mut err).unwrap();
    }
    (status, err)
}
