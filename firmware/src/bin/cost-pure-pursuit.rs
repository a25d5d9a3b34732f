//! Cost program: regulated pure pursuit with its wheel stage, the plant and the perfect sensor, on the
//! figure-eight of examples/tracking in f32. Plain build: its flash size; `--features
//! qemu`: instructions and stack per control update (reference state included) and plant
//! step (firmware/measure).
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    wmr_firmware::cost_main::<wmr_core::PurePursuitLaw<f32>>()
}
