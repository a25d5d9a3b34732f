//! Costs measured on the emulated Cortex-M4F (QEMU `mps2-an386`, `-icount shift=0`):
//!
//! - **Instructions.** Under `-icount shift=0` QEMU advances its virtual clock by 1 ns
//!   per executed instruction, and the SysTick timer, clocked from the CPU clock of the
//!   board model (25 MHz), counts that virtual time. So a SysTick tick is a fixed number
//!   of instructions; [`Meter::calibrate`] measures it on a block of 1,000 `nop`s. A call's
//!   count is the SysTick difference across it minus the same for an empty call. One
//!   reading resolves one tick (about 40 instructions); the start of each call is
//!   dithered, so means over many calls are exact to a fraction of an instruction. QEMU does not model the pipeline, flash wait states
//!   or FPU latencies: these are instruction counts, not cycles.
//! - **Stack.** Before each call the stack below the caller is painted with a pattern;
//!   after it, the deepest overwritten word gives the bytes the call used.

use core::arch::asm;
use core::ptr::{read_volatile, write_volatile};

use wmr_core::{ControlOutput, Termination};

use crate::fig7;

core::arch::global_asm!(
    ".section .text.wmr_nops, \"ax\"",
    ".global wmr_nops_1000",
    ".type wmr_nops_1000, %function",
    ".thumb_func",
    "wmr_nops_1000:",
    ".rept 1000",
    "nop",
    ".endr",
    "bx lr",
    ".global wmr_nops_0",
    ".type wmr_nops_0, %function",
    ".thumb_func",
    "wmr_nops_0:",
    "bx lr",
);

unsafe extern "C" {
    fn wmr_nops_1000();
    fn wmr_nops_0();
    /// Top of the stack (cortex-m-rt's link.x).
    static _stack_start: u32;
}

const SYST_CSR: *mut u32 = 0xE000_E010 as *mut u32;
const SYST_RVR: *mut u32 = 0xE000_E014 as *mut u32;
const SYST_CVR: *mut u32 = 0xE000_E018 as *mut u32;

/// Bytes of stack painted below the caller: more than the 2 KB budget, so an overrun shows.
const PAINT_BYTES: usize = 3072;
const PATTERN: u32 = 0x5AA5_C33C;

/// Starts SysTick from the processor clock, free-running over 24 bits.
fn start_systick() {
    // SAFETY: the System Control Space registers of every Cortex-M.
    unsafe {
        write_volatile(SYST_CSR, 0);
        write_volatile(SYST_RVR, 0x00FF_FFFF);
        write_volatile(SYST_CVR, 0);
        write_volatile(SYST_CSR, 0b101); // CLKSOURCE = processor clock, ENABLE
    }
}

#[inline(always)]
fn now() -> u32 {
    // SAFETY: a read of SYST_CVR.
    unsafe { read_volatile(SYST_CVR) }
}

/// SysTick ticks from `a` to `b` (it counts down, 24 bits).
#[inline(always)]
fn ticks(a: u32, b: u32) -> u32 {
    a.wrapping_sub(b) & 0x00FF_FFFF
}

#[inline(always)]
fn sp() -> usize {
    let sp: usize;
    // SAFETY: reads the stack pointer.
    unsafe { asm!("mov {}, sp", out(reg) sp, options(nomem, nostack, preserves_flags)) };
    sp
}

/// Mean and largest of a call's instructions and largest stack use.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stat {
    /// Calls measured.
    pub calls: u32,
    /// Sum of SysTick ticks over the calls.
    pub ticks: u64,
    /// Largest SysTick ticks of one call.
    pub max_ticks: u32,
    /// Largest stack use of one call, bytes.
    pub max_stack: u32,
    /// State of the dither's generator.
    pub seed: u32,
    /// Largest stack depth during a call, from the top of the stack, bytes: the whole
    /// program's peak while it runs this call.
    pub max_depth: u32,
}

/// Runs `f` through one indirect call (so its frame lies below the measuring frame),
/// measuring ticks and stack into `stat`.
#[inline(never)]
fn measured<R>(stat: &mut Stat, f: &mut dyn FnMut() -> R) -> R {
    // Dither: a pseudo-random 0..31 loop turns before the reading, so the call starts at
    // any phase of the 40-instruction SysTick tick and one-tick rounding averages out
    // (a loop of fixed length would lock the phase and bias every reading alike).
    stat.seed = stat.seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
    for _ in 0..(stat.seed >> 27) {
        // SAFETY: a nop.
        unsafe { asm!("nop", options(nomem, nostack, preserves_flags)) };
    }
    let top = sp() & !3;
    let bottom = top - PAINT_BYTES;
    // Paint [bottom, top): below this frame; no interrupt is enabled to use it.
    let mut a = bottom;
    while a < top {
        // SAFETY: RAM below the live stack, unused until the call.
        unsafe { write_volatile(a as *mut u32, PATTERN) };
        a += 4;
    }
    let t0 = now();
    let r = f();
    let t1 = now();
    let mut low = bottom;
    // SAFETY: reading back the painted words.
    while low < top && unsafe { read_volatile(low as *const u32) } == PATTERN {
        low += 4;
    }
    let used = (top - low) as u32;
    // SAFETY: the linker script's symbol; only its address is taken.
    let start = core::ptr::addr_of!(_stack_start) as usize;
    stat.max_depth = stat.max_depth.max((start - top) as u32 + used);
    let dt = ticks(t0, t1);
    stat.calls += 1;
    stat.ticks += u64::from(dt);
    stat.max_ticks = stat.max_ticks.max(dt);
    stat.max_stack = stat.max_stack.max(used);
    r
}

/// The instruction and stack meter of the cost programs.
pub struct Meter {
    /// Control updates.
    pub update: Stat,
    /// Plant steps.
    pub step: Stat,
    /// Empty calls through the same path: the measuring overhead.
    pub empty: Stat,
    /// Instructions per SysTick tick, times 1000.
    pub milli_insn_per_tick: u64,
}

impl Meter {
    /// Starts SysTick and calibrates.
    pub fn calibrate() -> Self {
        start_systick();
        // 100 calls of a function of 1,000 nops against 100 calls of an empty one:
        // exactly 100,000 instructions apart.
        let time = |f: unsafe extern "C" fn()| {
            let t0 = now();
            for _ in 0..core::hint::black_box(100u32) {
                // SAFETY: the functions only run nops.
                unsafe { f() };
            }
            ticks(t0, now())
        };
        let (full, empty) = (time(wmr_nops_1000), time(wmr_nops_0));
        let per_tick = 100_000_000u64 / u64::from(full.saturating_sub(empty).max(1));
        let mut m = Meter {
            update: Stat::default(),
            step: Stat::default(),
            empty: Stat::default(),
            milli_insn_per_tick: per_tick,
        };
        for _ in 0..20_000 {
            measured(&mut m.empty, &mut || core::hint::black_box(0u32));
        }
        m
    }

    /// Mean instructions of a call of `s`, times 10, the empty call subtracted.
    pub fn deci_mean_insn(&self, s: &Stat) -> i64 {
        let per = |st: &Stat| (st.ticks * self.milli_insn_per_tick) as i128 * 10 / 1000 / i128::from(st.calls.max(1));
        (per(s) - per(&self.empty)) as i64
    }

    /// Largest instructions of one call of `s` (one reading: +-1 tick).
    pub fn max_insn(&self, s: &Stat) -> u64 {
        u64::from(s.max_ticks) * self.milli_insn_per_tick / 1000
    }
}

impl fig7::Meter for Meter {
    fn update(&mut self, f: &mut dyn FnMut() -> ControlOutput<f32>) -> ControlOutput<f32> {
        measured(&mut self.update, f)
    }

    fn step(&mut self, f: &mut dyn FnMut() -> Result<(), Termination>) -> Result<(), Termination> {
        measured(&mut self.step, f)
    }
}

/// Prints one `cost` line for program `name` and exits QEMU.
pub fn report(name: &str, m: &Meter, ran: Option<&fig7::Ran>) -> ! {
    let d = |v: i64| (v / 10, (v % 10).unsigned_abs());
    let (um, uf) = d(m.deci_mean_insn(&m.update));
    let (sm, sf) = d(m.deci_mean_insn(&m.step));
    let steps = ran.map_or(0, |r| r.steps);
    crate::semi::println(format_args!(
        "cost program={name} insn_per_tick={}.{:03} updates={} update_insn_mean={um}.{uf} update_insn_max={} update_stack={} \
         program_stack={} steps={} step_insn_mean={sm}.{sf} step_insn_max={} step_stack={} empty_call_ticks={}/{}",
        m.milli_insn_per_tick / 1000,
        m.milli_insn_per_tick % 1000,
        m.update.calls,
        m.max_insn(&m.update),
        m.update.max_stack,
        m.update.max_depth.max(m.step.max_depth),
        steps,
        m.max_insn(&m.step),
        m.step.max_stack,
        m.empty.ticks,
        m.empty.calls,
    ));
    crate::semi::exit(ran.is_some())
}
