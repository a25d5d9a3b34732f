//! The memory a run may still take, as the operating system tells it: callers refuse
//! outputs that would not fit before allocating them.

/// Memory the operating system says a new allocation can get without swapping, bytes
/// (`MemAvailable` of `/proc/meminfo`); `None` where that is not known.
pub fn available_memory_bytes() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}
