//! The register file in which interpreted tapes run ([`mechanism_codegen::Tape::run`]).
//!
//! A tape needs a scratch array for its registers and outputs, and the [`System`] methods
//! that run one take `&self` and the caller's output buffers only. One register file per
//! thread, grown to the largest tape the thread has run, serves every tape of that thread:
//! an evaluation then neither allocates (after its first on the thread) nor locks, and
//! threads sharing one system (parameter sweeps) do not wait on each other. A second file,
//! [`LANES`] values per slot, serves the evaluation of a batch's rows side by side.
//!
//! [`System`]: crate::System

use std::cell::RefCell;

/// The states a batch evaluation runs side by side ([`with_lanes`]): enough to pay the
/// decoding of each tape operation once for many states and to fill vector registers,
/// few enough that the lane register file stays in the first-level cache (the Panda's
/// Newton-Euler tape: 336 lane slots, its one-state file 1,312; 43 KB at 16 lanes). On the
/// Panda's inverse dynamics (20,000 states in one call, the machine shared) 8 lanes took
/// 1.3 times as long as 16, 32 about as long, 64 1.2 to 1.3 times; 16 lanes: 0.27 us per
/// state on one core.
pub(crate) const LANES: usize = 16;

thread_local! {
    static REGISTERS: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
    static LANE_REGISTERS: RefCell<Vec<[f64; LANES]>> = const { RefCell::new(Vec::new()) };
}

/// Calls `f` with this thread's register file, at least `registers` long, and an output
/// array of exactly `outputs` entries beside it. Allocates only when the thread's file is
/// too short (its first use, or a larger tape than any before).
pub(crate) fn with_registers<R>(
    registers: usize,
    outputs: usize,
    f: impl FnOnce(&mut [f64], &mut [f64]) -> R,
) -> R {
    REGISTERS.with_borrow_mut(|file| {
        let len = registers + outputs;
        if file.len() < len {
            file.resize(len, 0.0);
        }
        let (regs, out) = file[..len].split_at_mut(registers);
        f(regs, out)
    })
}

/// Calls `f` with this thread's lane register file ([`LANES`] lanes per slot), exactly
/// `registers` slots long. Allocates only when the thread's file is too short, as
/// [`with_registers`].
pub(crate) fn with_lanes<R>(registers: usize, f: impl FnOnce(&mut [[f64; LANES]]) -> R) -> R {
    LANE_REGISTERS.with_borrow_mut(|file| {
        if file.len() < registers {
            file.resize(registers, [0.0; LANES]);
        }
        f(&mut file[..registers])
    })
}
