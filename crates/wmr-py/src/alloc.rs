//! Allocations sized by the caller (an array of N times, a batch of N robots, N starts):
//! checked against the memory this process may still take before they happen, and made
//! fallibly, so that a call too large raises `MemoryError` naming the argument, as numpy
//! does, instead of aborting the interpreter (Rust aborts when an allocation fails).
//!
//! The bound is `wmr_scenario::memory_headroom`: the smallest of `MemAvailable`, the
//! process's `RLIMIT_AS` and `RLIMIT_DATA` and its cgroup's memory limit.

use numpy::ndarray::Array2;
use pyo3::prelude::*;

use crate::error::memory_error;

/// Requests below this are not compared with the headroom: reading it costs a few
/// `/proc` files (tens of microseconds), which a loop of small batched steps must not
/// pay. They are still allocated fallibly, so a failure is a `MemoryError` too.
const CHECK_ABOVE_BYTES: u128 = 64 << 20;

fn gb(bytes: f64) -> f64 {
    bytes / 1e9
}

/// Refuses `bytes` (for `what`, sized by the argument `key`) that this process cannot
/// have: `MemoryError("{key}: {what} would take 3.4 GB of memory but this process may
/// take only 1.9 GB more (RLIMIT_AS)")`.
pub fn check_alloc(bytes: u128, key: &str, what: impl FnOnce() -> String) -> PyResult<()> {
    if bytes < CHECK_ABOVE_BYTES {
        return Ok(());
    }
    let Some(h) = wmr_scenario::memory_headroom() else { return Ok(()) };
    if bytes <= u128::from(h.bytes) {
        return Ok(());
    }
    Err(memory_error(
        key,
        format_args!(
            "{} would take {:.1} GB of memory but this process may take only {:.1} GB more ({})",
            what(),
            gb(bytes as f64),
            gb(h.bytes as f64),
            h.limit
        ),
    ))
}

/// Bytes of `n` values of `T`, without overflow.
pub fn bytes_of<T>(n: usize) -> u128 {
    n as u128 * std::mem::size_of::<T>() as u128
}

/// An empty vector with room for `n` values of `T`, fallibly: `MemoryError` naming `key`
/// when the allocation fails. (The caller checks the whole call's memory first with
/// [`check_alloc`].)
pub fn vec_with_capacity<T>(n: usize, key: &str, what: &str) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        memory_error(key, format_args!("{what}: cannot allocate {:.1} GB of memory", gb(bytes_of::<T>(n) as f64)))
    })?;
    Ok(v)
}

/// A `rows` x `cols` array of zeros, checked against the headroom and made fallibly; the
/// error names `key` and says `what` the array is.
pub fn zeros2(rows: usize, cols: usize, key: &str, what: &str) -> PyResult<Array2<f64>> {
    let n = rows.checked_mul(cols).ok_or_else(|| memory_error(key, format_args!("{what}: too many values")))?;
    check_alloc(bytes_of::<f64>(n), key, || format!("the ({rows}, {cols}) array of {what}"))?;
    let mut v = vec_with_capacity::<f64>(n, key, what)?;
    v.resize(n, 0.0);
    Array2::from_shape_vec((rows, cols), v).map_err(|e| memory_error(key, format_args!("{what}: {e}")))
}

/// The number of rows of a 2-D array argument (its `shape[0]`), read before the values
/// are: a call too large is refused at once, not after a scan of every value.
pub fn leading_rows(obj: &Bound<'_, PyAny>) -> Option<usize> {
    let shape: Vec<usize> = obj.getattr("shape").ok()?.extract().ok()?;
    (shape.len() == 2).then(|| shape[0])
}
