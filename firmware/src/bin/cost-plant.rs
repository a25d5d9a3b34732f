//! Cost program: the plant alone (robot, torque drive, RK4) under a held command.
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    wmr_firmware::cost_plant_main()
}
