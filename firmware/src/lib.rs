//! The firmware's shared parts: the Fig. 7 setup in f32, the closed loop composed by hand
//! (so a program links only the law it uses), and, with the `qemu` feature, what the QEMU
//! programs need: semihosting I/O, an instruction meter (SysTick under `-icount`) and a
//! stack meter (painting).
#![no_std]

// wmr-ffi's panic handler (feature `panic-handler`) serves every program.
use wmr_ffi as _;

pub mod fig7;
#[cfg(feature = "qemu")]
pub mod meter;
#[cfg(feature = "qemu")]
pub mod semi;

/// Parks the core.
pub fn halt() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

/// The body of a cost program for law `L` (`name` as printed): the Fig. 7 loop, plain,
/// or measured and reported under QEMU.
pub fn cost_main<L: fig7::FirmwareLaw>() -> ! {
    #[cfg(not(feature = "qemu"))]
    {
        core::hint::black_box(fig7::run::<L>(&mut fig7::Plain).map(|r| (r.pose, r.steps)));
        halt()
    }
    #[cfg(feature = "qemu")]
    {
        let mut m = meter::Meter::calibrate();
        let ran = fig7::run::<L>(&mut m);
        meter::report(L::KIND, &m, ran.as_ref())
    }
}

/// The body of the observer's cost program: the Fig. 7 loop of law `L` with the
/// disturbance observer on its wheel stage, reported as `<kind>+observer`.
pub fn cost_observer_main<L: fig7::FirmwareLaw>() -> ! {
    #[cfg(not(feature = "qemu"))]
    {
        core::hint::black_box(fig7::run_with::<L, true>(&mut fig7::Plain).map(|r| (r.pose, r.steps)));
        halt()
    }
    #[cfg(feature = "qemu")]
    {
        let mut m = meter::Meter::calibrate();
        let ran = fig7::run_with::<L, true>(&mut m);
        meter::report("observer", &m, ran.as_ref())
    }
}

/// The body of the plant-only cost program.
pub fn cost_plant_main() -> ! {
    #[cfg(not(feature = "qemu"))]
    {
        core::hint::black_box(fig7::run_plant(&mut fig7::Plain).map(|r| (r.pose, r.steps)));
        halt()
    }
    #[cfg(feature = "qemu")]
    {
        let mut m = meter::Meter::calibrate();
        let ran = fig7::run_plant(&mut m);
        meter::report("plant", &m, ran.as_ref())
    }
}
