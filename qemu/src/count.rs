//! Instructions executed, measured with SysTick.
//!
//! Under `-icount shift=0` QEMU advances virtual time by 1 ns per instruction, and it clocks
//! the SysTick of mps2-an386 from the 25 MHz system clock: one tick per 40 instructions. The
//! ratio is checked on a loop of known length at start, so that a run without `-icount`
//! (where ticks follow the host's clock) fails instead of printing a wrong count.

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;

/// Instructions per SysTick tick: 1 ns per instruction, 40 ns per tick.
pub const INSTRUCTIONS_PER_TICK: u64 = 40;

/// The 24-bit counter's full range: one measurement may last up to 2^24 ticks (671 M
/// instructions).
const RELOAD: u32 = 0xFF_FFFF;

/// SysTick, free-running over its full range.
pub struct Instructions(SYST);

impl Instructions {
    /// Starts SysTick and checks the instructions per tick.
    pub fn new(mut syst: SYST) -> Self {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.enable_counter();
        let counter = Instructions(syst);
        let loops = 1_000_000;
        let ((), ticks) = counter.ticks(|| spin(loops));
        // The loop runs two instructions per pass.
        let expected = 2 * loops as u64 / INSTRUCTIONS_PER_TICK;
        assert!(
            ticks.abs_diff(expected) * 100 <= expected,
            "SysTick counted {ticks} ticks for {expected} ticks of instructions: run QEMU with -icount shift=0"
        );
        counter
    }

    /// Runs `f` and returns its result and the instructions it took, to within a tick.
    pub fn measure<T>(&self, f: impl FnOnce() -> T) -> (T, u64) {
        let (r, ticks) = self.ticks(f);
        (r, ticks * INSTRUCTIONS_PER_TICK)
    }

    fn ticks<T>(&self, f: impl FnOnce() -> T) -> (T, u64) {
        let start = SYST::get_current();
        // The work may not move across the counter's reads: its input and output go through
        // black_box, which the compiler must treat as touching memory there.
        let r = core::hint::black_box(f());
        let end = SYST::get_current();
        (r, (start.wrapping_sub(end) & RELOAD) as u64)
    }
}

/// Exactly `2 n` instructions of a count-down loop, plus its set-up.
fn spin(n: u32) {
    // SAFETY: only the named register and the flags are changed.
    unsafe { core::arch::asm!("1:", "subs {0}, #1", "bne 1b", inout(reg) n => _) };
}
