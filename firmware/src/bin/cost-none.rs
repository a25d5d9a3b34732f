//! Cost program: nothing but the runtime (vector table, reset handler, panic handler),
//! the baseline the other programs' sizes include.
#![no_std]
#![no_main]

#[cortex_m_rt::entry]
fn main() -> ! {
    core::hint::black_box(0u32);
    wmr_firmware::halt()
}
