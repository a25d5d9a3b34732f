//! Latency: samples in flight, oldest first, in a fixed ring of `N` (no heap). A sample
//! taken at j P reaches the controller at j P + L; the ring holds the ones on their way.

/// A delay line of values tagged with their sample index j.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DelayLine<V, const N: usize> {
    ring: [(u64, V); N],
    /// Index in `ring` of the oldest sample in flight, and how many are in flight.
    head: usize,
    len: usize,
}

impl<V: Copy + Default, const N: usize> Default for DelayLine<V, N> {
    fn default() -> Self {
        Self { ring: [(0, V::default()); N], head: 0, len: 0 }
    }
}

impl<V: Copy + Default, const N: usize> DelayLine<V, N> {
    /// Puts `value`, sample `index`, in flight. A full line drops it: the sensors size
    /// their line at construction so that it never fills (latency * rate_hz < 250).
    #[inline]
    pub fn push(&mut self, index: u64, value: V) {
        if self.len < N {
            // % N and the bound above leave no panic path on a Cortex-M (firmware/check).
            self.ring[(self.head + self.len) % N] = (index, value);
            self.len += 1;
        }
    }

    /// Takes out, oldest first, every sample whose index `arrived` accepts, up to the
    /// first it does not; returns the newest taken out (its index and value).
    #[inline]
    pub fn deliver(&mut self, arrived: impl Fn(u64) -> bool) -> Option<(u64, V)> {
        let mut newest = None;
        while self.len > 0 {
            let oldest = self.ring[self.head % N];
            if !arrived(oldest.0) {
                break;
            }
            newest = Some(oldest);
            self.head = (self.head + 1) % N;
            self.len -= 1;
        }
        newest
    }

    /// Empties the line, as at t = 0.
    pub fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
    }
}
