//! The early end of a live session: the signal (SIGINT, SIGTERM, SIGHUP) that asked for it,
//! set by the signal thread of [`crate::atomic`], and waits that give up as soon as it is set.

use std::sync::atomic::{AtomicI32, Ordering};
use std::time::{Duration, Instant};

/// The signal that stopped the session (0: none yet). The first signal sets it; a second
/// one ends the process at once.
pub static STOP_SIGNAL: AtomicI32 = AtomicI32::new(0);

/// Longest sleep between two looks at [`STOP_SIGNAL`].
pub const POLL: Duration = Duration::from_millis(20);

/// A signal stopped the session.
#[derive(Debug)]
pub struct Interrupted {
    /// SIGINT, SIGTERM or SIGHUP: the process exits with 128 + it.
    pub signal: i32,
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("interrupted, no output written")
    }
}

impl std::error::Error for Interrupted {}

/// `Err` once a signal asked to stop.
pub fn check() -> Result<(), Interrupted> {
    match STOP_SIGNAL.load(Ordering::SeqCst) {
        0 => Ok(()),
        signal => Err(Interrupted { signal }),
    }
}

/// Sleeps until `due` (`None`: forever), giving up when a signal asks to stop.
pub fn wait_until(due: Option<Instant>) -> Result<(), Interrupted> {
    loop {
        check()?;
        let now = Instant::now();
        let left = match due {
            Some(d) if now >= d => return Ok(()),
            Some(d) => d - now,
            None => POLL,
        };
        std::thread::sleep(left.min(POLL));
    }
}

/// Sleeps `d`, giving up when a signal asks to stop.
pub fn wait_for(d: Duration) -> Result<(), Interrupted> {
    wait_until(Instant::now().checked_add(d))
}
