//! Ctrl-C during a run, and memory a run would need.
//!
//! Runs go without the GIL on a worker thread while the calling thread waits for them
//! in slices of [`SIGNAL_CHECK_PERIOD`]; between two slices it takes the GIL and asks
//! Python for pending signals (`PyErr_CheckSignals`). A `KeyboardInterrupt` (or whatever
//! a signal handler raises) sets a flag the runs poll every 1,024 plant steps, so the
//! call returns that exception within about [`SIGNAL_CHECK_PERIOD`] plus a millisecond
//! of work, instead of at the end of the run.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use numpy::PyArray1;
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;

use crate::error::parameter_error;

/// How often pending signals are checked while a run goes on.
pub const SIGNAL_CHECK_PERIOD: Duration = Duration::from_millis(50);

/// A flag the runs poll: set when the caller was interrupted.
#[derive(Default)]
pub struct Stop(AtomicBool);

impl Stop {
    /// A flag nobody sets (work that is not interrupted).
    pub fn new() -> Self {
        Self(AtomicBool::new(false))
    }

    /// True once the runs should give up.
    pub fn requested(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Runs `work` without the GIL on a worker thread and returns its value; a pending
/// signal that raises (Ctrl-C: `KeyboardInterrupt`) stops it and is returned instead.
/// `work` must end soon after [`Stop::requested`] turns true.
pub fn interruptible<T: Send>(py: Python<'_>, work: impl FnOnce(&Stop) -> T + Send) -> PyResult<T> {
    interruptible_with(py, None, work)
}

/// A progress report: `callback(done)` is called with the count `done` holds (the work
/// adds to it), from the waiting thread between two slices of [`SIGNAL_CHECK_PERIOD`]
/// and once at the end. The runs only add to an atomic counter: progress costs them
/// nothing measurable, however slow the callback (a tqdm bar) is.
pub struct Progress<'a, 'py> {
    /// What the work has done so far (runs, samples).
    pub done: &'a AtomicUsize,
    /// Called with the count when it changed; an exception it raises stops the work.
    pub callback: &'a Bound<'py, PyAny>,
}

impl Progress<'_, '_> {
    fn report(&self, last: &mut usize) -> PyResult<()> {
        let now = self.done.load(Ordering::Relaxed);
        if now != *last {
            *last = now;
            self.callback.call1((now,))?;
        }
        Ok(())
    }
}

/// [`interruptible`] with an optional [`Progress`] report.
pub fn interruptible_with<T: Send>(
    py: Python<'_>,
    progress: Option<Progress<'_, '_>>,
    work: impl FnOnce(&Stop) -> T + Send,
) -> PyResult<T> {
    let stop = Stop::new();
    let mut reported = 0;
    // Set by the worker when it is done; the waiting thread sleeps on the condvar.
    let done = (Mutex::new(false), Condvar::new());
    std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let out = work(&stop);
            *done.0.lock().unwrap_or_else(|p| p.into_inner()) = true;
            done.1.notify_all();
            out
        });
        let join = |worker: std::thread::ScopedJoinHandle<'_, T>| match worker.join() {
            Ok(v) => v,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        loop {
            let finished = py.detach(|| {
                let guard = done.0.lock().unwrap_or_else(|p| p.into_inner());
                let (guard, _) =
                    done.1.wait_timeout_while(guard, SIGNAL_CHECK_PERIOD, |d| !*d).unwrap_or_else(|p| p.into_inner());
                *guard
            });
            if finished {
                // A signal that came during the last slice still counts.
                let value = join(worker);
                py.check_signals()?;
                if let Some(p) = &progress {
                    p.report(&mut reported)?;
                }
                return Ok(value);
            }
            let reported_ok = progress.as_ref().map_or(Ok(()), |p| p.report(&mut reported));
            if let Err(e) = py.check_signals().and(reported_ok) {
                stop.0.store(true, Ordering::Relaxed);
                py.detach(|| drop(join(worker)));
                return Err(e);
            }
        }
    })
}

/// Imports numpy and loads its C API (see the module init in `lib.rs`).
pub fn load_numpy_api(py: Python<'_>) -> PyResult<()> {
    py.import("numpy")?;
    // The first array made loads the API capsule; numpy is imported, so this succeeds.
    let _ = PyArray1::<f64>::zeros(py, 0, false);
    Ok(())
}

/// Refuses, before anything is allocated, columns of `bytes` that this process cannot
/// hold (`wmr_scenario::memory_headroom`: `MemAvailable`, its `RLIMIT_AS` and
/// `RLIMIT_DATA`, its cgroup's limit): a `ParameterError` naming `key` (the setting to
/// change), with the value that would fit when `fit` can say it.
pub fn check_memory(bytes: u128, key: &str, fit: impl FnOnce(f64) -> String) -> PyResult<()> {
    let Some(h) = wmr_scenario::memory_headroom() else { return Ok(()) };
    if bytes <= u128::from(h.bytes) {
        return Ok(());
    }
    let gb = |b: f64| b / 1e9;
    Err(parameter_error(
        key,
        format_args!(
            "the results would take {:.1} GB of memory but only {:.1} GB are available ({}): {}",
            gb(bytes as f64),
            gb(h.bytes as f64),
            h.limit,
            fit(h.bytes as f64 / bytes as f64)
        ),
    ))
}

/// A vector of `n` values, or `MemoryError` when they cannot be had (instead of the
/// abort of a failed allocation).
pub fn try_vec<T>(n: usize) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        PyMemoryError::new_err(format!("cannot allocate {n} values of {} bytes", std::mem::size_of::<T>()))
    })?;
    Ok(v)
}
