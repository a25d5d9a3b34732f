//! Cost program: the paper's law and its wheel stage carrying the disturbance observer
//! (`[controller.observer] kind = "disturbance"`, 50 rad/s), the plant and the perfect
//! sensor, on Fig. 7 in f32. Plain build: its flash size; `--features qemu`: instructions
//! and stack per control update and plant step (firmware/measure: beside `cost-paper`,
//! the difference is what the observer adds to an update).
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    wmr_firmware::cost_observer_main::<wmr_core::PaperLaw<f32>>()
}
