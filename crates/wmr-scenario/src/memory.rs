//! The memory a run may still take, as the operating system tells it: callers refuse
//! outputs that would not fit before allocating them.
//!
//! Four bounds, the smallest wins: the machine's `MemAvailable` (`/proc/meminfo`); the
//! process's own address-space and data limits (`RLIMIT_AS` and `RLIMIT_DATA`, read in
//! `/proc/self/limits`, less what the process already maps, `VmSize` and `VmData` of
//! `/proc/self/status`); and the memory limit of its cgroup and every cgroup above it
//! (v2 `memory.max`, v1 `memory.limit_in_bytes`, less the usage that cannot be
//! reclaimed). Why all four: under `ulimit -v`, `prlimit --as` or a container's limit,
//! an allocation that `MemAvailable` allows fails (and Rust aborts) or the kernel kills
//! the process; so a caller that checks only `MemAvailable` can still abort.

use std::path::{Path, PathBuf};

/// The memory a new allocation can still get, and which bound gives it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Headroom {
    /// Bytes.
    pub bytes: u64,
    /// The bound: `MemAvailable`, `RLIMIT_AS`, `RLIMIT_DATA` or `cgroup memory limit`.
    pub limit: &'static str,
}

/// The smallest of the bounds this process can read (see the module); `None` where none
/// is known (not Linux).
pub fn memory_headroom() -> Option<Headroom> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let mut bounds = Vec::new();
    if let Some(bytes) = read("/proc/meminfo").as_deref().and_then(mem_available) {
        bounds.push(Headroom { bytes, limit: "MemAvailable" });
    }
    if let (Some(limits), Some(status)) = (read("/proc/self/limits"), read("/proc/self/status")) {
        bounds.extend(rlimit_headroom(&limits, &status));
    }
    if let Some(cgroup) = read("/proc/self/cgroup") {
        let bytes = cgroup_headroom(&cgroup, Path::new("/sys/fs/cgroup"));
        bounds.extend(bytes.map(|bytes| Headroom { bytes, limit: "cgroup memory limit" }));
    }
    bounds.into_iter().min_by_key(|h| h.bytes)
}

/// Memory a new allocation can get, bytes: [`memory_headroom`]'s; `None` where that is
/// not known.
pub fn available_memory_bytes() -> Option<u64> {
    memory_headroom().map(|h| h.bytes)
}

/// `MemAvailable` of `/proc/meminfo`, bytes.
fn mem_available(meminfo: &str) -> Option<u64> {
    kib_field(meminfo, "MemAvailable:")
}

/// A `Name:  123 kB` line of `/proc/meminfo` or `/proc/self/status`, in bytes.
fn kib_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The soft limit of a `/proc/self/limits` line (`Max address space  unlimited ...`);
/// `None` when unlimited or absent.
fn soft_limit(limits: &str, name: &str) -> Option<u64> {
    let line = limits.lines().find(|l| l.starts_with(name))?;
    line[name.len()..].split_whitespace().next()?.parse().ok()
}

/// What `RLIMIT_AS` and `RLIMIT_DATA` leave, from `/proc/self/limits` and `/proc/self/status`.
fn rlimit_headroom(limits: &str, status: &str) -> Vec<Headroom> {
    [("Max address space", "VmSize:", "RLIMIT_AS"), ("Max data size", "VmData:", "RLIMIT_DATA")]
        .into_iter()
        .filter_map(|(name, used, limit)| {
            let max = soft_limit(limits, name)?;
            let used = kib_field(status, used).unwrap_or(0);
            Some(Headroom { bytes: max.saturating_sub(used), limit })
        })
        .collect()
}

/// A limit at or above this is "no limit" (cgroup v1 writes 2^63 rounded down to a page).
const NO_LIMIT: u64 = 1 << 60;

/// What the memory limits of the process's cgroups leave, from `/proc/self/cgroup` and
/// the cgroup file systems mounted at `root` (`/sys/fs/cgroup`): the smallest of
/// limit - (usage - reclaimable file pages) over the cgroup and its ancestors, v2 and v1.
/// `None` when no cgroup has a limit.
pub fn cgroup_headroom(cgroup: &str, root: &Path) -> Option<u64> {
    let mut best: Option<u64> = None;
    for line in cgroup.lines() {
        // `0::/path` (v2) or `4:memory:/path` (v1, controllers comma-separated).
        let mut parts = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) = (parts.next(), parts.next(), parts.next()) else { continue };
        let (base, files) = if controllers.is_empty() {
            (root.to_path_buf(), ("memory.max", "memory.current", "inactive_file"))
        } else if controllers.split(',').any(|c| c == "memory") {
            (root.join("memory"), ("memory.limit_in_bytes", "memory.usage_in_bytes", "total_inactive_file"))
        } else {
            continue;
        };
        for dir in ancestors(&base, path) {
            let read = |f: &str| std::fs::read_to_string(dir.join(f)).ok();
            let Some(limit) = read(files.0).and_then(|s| s.trim().parse::<u64>().ok()) else { continue };
            if limit >= NO_LIMIT {
                continue;
            }
            let usage = read(files.1).and_then(|s| s.trim().parse::<u64>().ok()).unwrap_or(0);
            let reclaimable = read("memory.stat")
                .and_then(|s| {
                    s.lines().find_map(|l| l.strip_prefix(files.2)?.strip_prefix(' ')?.trim().parse::<u64>().ok())
                })
                .unwrap_or(0);
            let left = limit.saturating_sub(usage.saturating_sub(reclaimable));
            best = Some(best.map_or(left, |b| b.min(left)));
        }
    }
    best
}

/// `base/path` and each of its ancestors down to `base`, those that exist (a container
/// may show a path its own mount does not have; its root is then `base`).
fn ancestors(base: &Path, path: &str) -> Vec<PathBuf> {
    let mut out = vec![base.to_path_buf()];
    let mut dir = base.to_path_buf();
    for part in path.split('/').filter(|p| !p.is_empty() && *p != "." && *p != "..") {
        dir.push(part);
        out.push(dir.clone());
    }
    out.retain(|d| d.is_dir());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: &str = "Limit                     Soft Limit           Hard Limit           Units     \n\
Max data size             unlimited            unlimited            bytes     \n\
Max stack size            8388608              unlimited            bytes     \n\
Max address space         2500000000           unlimited            bytes     \n";
    const STATUS: &str = "Name:\tpython3\nVmPeak:\t  900000 kB\nVmSize:\t  500000 kB\nVmData:\t  300000 kB\n";

    #[test]
    fn rlimit_as_less_the_mapped_size() {
        let h = rlimit_headroom(LIMITS, STATUS);
        assert_eq!(h, vec![Headroom { bytes: 2_500_000_000 - 500_000 * 1024, limit: "RLIMIT_AS" }]);
        let data = LIMITS.replace("Max data size             unlimited", "Max data size             1000000000");
        let h = rlimit_headroom(&data, STATUS);
        assert_eq!(h[1], Headroom { bytes: 1_000_000_000 - 300_000 * 1024, limit: "RLIMIT_DATA" });
        // Above the limit already: nothing left, not a wrap-around.
        let small = LIMITS.replace("2500000000", "1000");
        assert_eq!(rlimit_headroom(&small, STATUS)[0].bytes, 0);
    }

    #[test]
    fn meminfo_available() {
        assert_eq!(mem_available("MemTotal: 100 kB\nMemFree: 10 kB\nMemAvailable:  2048 kB\n"), Some(2048 * 1024));
        assert_eq!(mem_available("MemTotal: 100 kB\n"), None);
    }

    fn write(dir: &Path, name: &str, text: &str) {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join(name), text).unwrap();
    }

    #[test]
    fn cgroup_v2_and_v1_limits_of_the_cgroup_and_its_ancestors() {
        let root = std::env::temp_dir().join(format!("wmr-cgroup-test-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        // v2: the parent limits to 3 GB (1 GB used), the process's own cgroup to 2.5 GB
        // with 2 GB used of which 0.5 GB is reclaimable page cache: 1 GB left.
        write(&root.join("user.slice"), "memory.max", "3000000000\n");
        write(&root.join("user.slice"), "memory.current", "1000000000\n");
        let own = root.join("user.slice/job");
        write(&own, "memory.max", "2500000000\n");
        write(&own, "memory.current", "2000000000\n");
        write(&own, "memory.stat", "anon 1500000000\nfile 500000000\ninactive_file 500000000\n");
        write(&root, "memory.max", "max\n");
        assert_eq!(cgroup_headroom("0::/user.slice/job\n", &root), Some(1_000_000_000));
        // No limit anywhere.
        assert_eq!(cgroup_headroom("0::/other\n", &root.join("none")), None);
        // v1: the memory hierarchy, the root unlimited (2^63 rounded to a page).
        let v1 = root.join("memory/docker/abc");
        write(&root.join("memory"), "memory.limit_in_bytes", "9223372036854771712\n");
        write(&v1, "memory.limit_in_bytes", "2000000000\n");
        write(&v1, "memory.usage_in_bytes", "1800000000\n");
        write(&v1, "memory.stat", "inactive_file 1\ntotal_inactive_file 300000000\n");
        assert_eq!(cgroup_headroom("5:cpu:/x\n4:memory:/docker/abc\n", &root), Some(500_000_000));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
