//! Cost program: the paper law with its wheel stage, the plant and the perfect sensor, Fig. 7
//! in f32. Plain build: its flash size; `--features qemu`: instructions and stack per
//! control update and plant step (firmware/measure).
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    wmr_firmware::cost_main::<wmr_core::PaperLaw<f32>>()
}
