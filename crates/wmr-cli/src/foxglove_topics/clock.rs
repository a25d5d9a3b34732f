//! Log times: simulation time to the ns stamps of every message, exact on the plant-step
//! grid so every sample lies on the log grid.

use foxglove::messages::Timestamp;

/// Log times: simulation time (s) to ns, exact on the plant-step grid.
#[derive(Clone, Copy, Debug)]
pub struct LogClock {
    /// Plant step, s.
    dt: f64,
    /// The plant step in whole ns, when it is one.
    dt_ns: Option<u64>,
}

impl LogClock {
    /// The clock of a scenario with plant step `dt` (s).
    pub fn new(dt: f64) -> Self {
        let ns = dt * 1e9;
        let whole = ns.round();
        let dt_ns = (whole >= 1.0 && (ns - whole).abs() <= 1e-6 * whole).then_some(whole as u64);
        Self { dt, dt_ns }
    }

    /// The log time of simulation time `t` (s): `k * dt_ns` for the `k`-th step when the
    /// step is a whole number of ns, else `t * 1e9` rounded.
    pub fn nanos(&self, t: f64) -> u64 {
        match self.dt_ns {
            Some(step) => ((t / self.dt).round().max(0.0) as u64).saturating_mul(step),
            None => (t * 1e9).round().max(0.0) as u64,
        }
    }
}

pub(super) fn stamp(ns: u64) -> Timestamp {
    Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32)
}
