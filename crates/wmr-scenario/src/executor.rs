//! Ordered parallel runs, the one runner of the CLI, sweeps and Python: one task per
//! index on rayon's pool, results handed on in index order, so what comes out does not
//! depend on the thread count.

use rayon::prelude::*;

/// Runs `job(i)` for every `i < n` in parallel, `batch` at a time (at least 1), and hands
/// each result to `consume` in index order. Stops at the first error `consume` returns.
pub fn for_each_ordered<R: Send, E>(
    n: usize,
    batch: usize,
    job: impl Fn(usize) -> R + Sync + Send,
    mut consume: impl FnMut(usize, R) -> Result<(), E>,
) -> Result<(), E> {
    let batch = batch.max(1);
    let mut first = 0;
    while first < n {
        let last = first.saturating_add(batch).min(n);
        let done: Vec<R> = (first..last).into_par_iter().map(&job).collect();
        for (i, r) in (first..last).zip(done) {
            consume(i, r)?;
        }
        first = last;
    }
    Ok(())
}

/// Every `job(i)` for `i < n`, run in parallel, in index order.
pub fn map_ordered<R: Send>(n: usize, job: impl Fn(usize) -> R + Sync + Send) -> Vec<R> {
    (0..n).into_par_iter().map(job).collect()
}
