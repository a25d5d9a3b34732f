//! Whether the processor has AVX2, found once without `std`: MPPI's planner, compiled a
//! second time for AVX2, runs there 1.3 (kinematic) to 1.6 (dynamic) times as fast (one
//! cycle at nav2's defaults, 1.21 -> 0.93 ms and 2.25 -> 1.44 ms, best of 5 x 100 cycles,
//! AMD EPYC Zen 4, load average 6.5, 2026-12-07) and gives the same bits, as the lanes of
//! `wmr-cli sweep --fast` do (no FMA contraction, the same operations in the same order).
//! On other processors and targets the baseline build runs.

/// True when the processor and the operating system let code use AVX2 (CPUID leaf 7's
/// AVX2 bit, leaf 1's AVX and OSXSAVE bits, and XCR0 saving the SSE and AVX state), asked
/// once and remembered.
#[cfg(all(target_arch = "x86_64", not(target_os = "none")))]
pub fn has_avx2() -> bool {
    use core::sync::atomic::{AtomicU8, Ordering};
    /// 0: not asked yet, 1: no, 2: yes.
    static KNOWN: AtomicU8 = AtomicU8::new(0);
    match KNOWN.load(Ordering::Relaxed) {
        1 => false,
        2 => true,
        _ => {
            let yes = detect_avx2();
            KNOWN.store(if yes { 2 } else { 1 }, Ordering::Relaxed);
            yes
        }
    }
}

/// Without an x86-64 host: never.
#[cfg(not(all(target_arch = "x86_64", not(target_os = "none"))))]
pub fn has_avx2() -> bool {
    false
}

#[cfg(all(target_arch = "x86_64", not(target_os = "none")))]
// CPUID is a safe intrinsic in the toolchain of 2026-12 and an unsafe one in older ones (MSRV 1.90).
#[allow(unsafe_code, unused_unsafe)]
fn detect_avx2() -> bool {
    use core::arch::x86_64::{__cpuid, __cpuid_count};
    // SAFETY: CPUID exists on every x86-64 processor; it only reads identification registers.
    let (max_leaf, leaf1) = unsafe { (__cpuid(0).eax, __cpuid(1)) };
    let (osxsave, avx) = (leaf1.ecx & (1 << 27) != 0, leaf1.ecx & (1 << 28) != 0);
    if max_leaf < 7 || !osxsave || !avx {
        return false;
    }
    // SAFETY: OSXSAVE is set (checked above), so XGETBV exists.
    let xcr0 = unsafe { xgetbv0() };
    // SAFETY: as above; leaf 7 exists (max_leaf >= 7).
    let leaf7 = unsafe { __cpuid_count(7, 0) };
    xcr0 & 0b110 == 0b110 && leaf7.ebx & (1 << 5) != 0
}

/// XCR0: which register states the operating system saves.
#[cfg(all(target_arch = "x86_64", not(target_os = "none")))]
#[allow(unsafe_code)]
#[target_feature(enable = "xsave")]
unsafe fn xgetbv0() -> u64 {
    // SAFETY: the caller checked OSXSAVE.
    unsafe { core::arch::x86_64::_xgetbv(0) }
}

#[cfg(test)]
mod tests {
    extern crate std;

    /// The detection agrees with the standard library's.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn agrees_with_std() {
        assert_eq!(super::has_avx2(), std::is_x86_feature_detected!("avx2"));
    }
}
