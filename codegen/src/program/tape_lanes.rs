//! A [`Tape`] over a block of L states side by side: the register file holds L lanes per
//! slot (structure of arrays, `[[f64; L]]`), and each operation is applied to all L lanes
//! before the next is decoded. The `match` on the operation, the operand indices and their
//! bounds checks are then paid once per block instead of once per state, and the lane loops
//! are straight-line arithmetic on contiguous arrays that the compiler vectorises.
//!
//! The lane register file is as small as the values live at once allow (`LaneLayout`):
//! a value's slot is reused once its last reader has run, so that L lanes of a large tape
//! (the Panda's Newton-Euler) stay in the first-level cache. Constants and inputs keep
//! their slots ([`Tape::input_slots`]); an output's lane slot is
//! [`Tape::lane_output_slot`].
//!
//! Each lane computes exactly what [`Tape::execute`] computes for its state, bit for bit:
//! every operation is the same f64 operation on the same operands (sums, products,
//! quotients and square roots are correctly rounded; [`mechanism_math::mul_add`] rounds as it
//! does for one state; the other functions are the same calls, lane by lane), and sin and
//! cos come from [`mechanism_math::sin_cos_lanes`], whose every lane is bit for bit
//! [`mechanism_math::sin_cos`]. On an x86-64 build without AVX2 the block runs in a copy
//! compiled with `avx2` where the CPU has it (chosen once per block), which changes the
//! width of the vector registers and nothing in the arithmetic (`avx2` does not enable
//! `fma`).

use crate::program::tape::Tape;
use crate::program::tape_op::Op;
use mechanism_math::{Baseline, Isa, mul_add};

impl Tape {
    /// Length of the lane register file [`Tape::execute_lanes`] works in (at most
    /// [`Tape::register_len`]: slots are reused, see `LaneLayout`).
    pub fn lane_register_len(&self) -> usize {
        self.lanes.registers
    }

    /// The lane register-file slot of output entry `k` after [`Tape::execute_lanes`], or
    /// `None` past the last.
    pub fn lane_output_slot(&self, k: usize) -> Option<usize> {
        self.output_slot(k).and_then(|s| self.lane_slot(s))
    }

    /// The lane register-file slot of tape slot `slot` (a constant's, an input's or an
    /// output's, as [`Tape::output_slot`] gives it); `None` for a slot that holds none of
    /// these at the end.
    pub fn lane_slot(&self, slot: usize) -> Option<usize> {
        match self.lanes.slot.get(slot) {
            Some(&s) if s != u32::MAX => Some(s as usize),
            _ => None,
        }
    }

    /// Runs the tape on L states at once: `registers[slot][lane]` is slot `slot` of lane
    /// `lane`'s register file ([`Tape::lane_register_len`] slots), whose
    /// [`Tape::input_slots`] already hold each lane's inputs. Afterwards output entry k of
    /// lane l is at `registers[lane_output_slot(k)][l]`, bit for bit what
    /// [`Tape::execute`] leaves at `output_slot(k)` for that lane's inputs (see the module
    /// docs). Nothing is checked or allocated.
    ///
    /// # Panics
    /// When `registers` is shorter than [`Tape::lane_register_len`].
    ///
    /// # Example
    /// ```
    /// use mechanism_codegen::{Arena, Matrix, Program, SymbolKind, Tape};
    ///
    /// let mut a = Arena::new();
    /// let x = a.symbol("x", SymbolKind::Free);
    /// let m = Matrix::column(vec![a.sin(x)]);
    /// let tape = Tape::new(&Program::new(&a, &[&m]).unwrap());
    /// let mut regs = vec![[0.0; 4]; tape.lane_register_len()];
    /// let (_, slot) = tape.input_slots().next().unwrap();
    /// regs[slot] = [0.0, 0.5, 1.0, 2.0];
    /// tape.execute_lanes(&mut regs);
    /// let out = regs[tape.lane_output_slot(0).unwrap()];
    /// assert_eq!(out[2], mechanism_math::sin_cos(1.0).0);
    /// ```
    pub fn execute_lanes<const L: usize>(&self, registers: &mut [[f64; L]]) {
        #[cfg(all(target_arch = "x86_64", not(target_feature = "avx2")))]
        if let Some(isa) = mechanism_math::avx2::Avx2::detected() {
            // SAFETY: an `Avx2` exists only where the CPU has AVX2.
            return unsafe { execute_avx2(self, registers, isa) };
        }
        execute(self, registers, Baseline);
    }
}

/// [`execute`] compiled with `avx2`.
///
/// # Safety
/// Call only where the CPU has AVX2 (an [`mechanism_math::avx2::Avx2`] proves it).
#[cfg(all(target_arch = "x86_64", not(target_feature = "avx2")))]
#[target_feature(enable = "avx2")]
unsafe fn execute_avx2<const L: usize>(
    tape: &Tape,
    registers: &mut [[f64; L]],
    isa: mechanism_math::avx2::Avx2,
) {
    execute(tape, registers, isa);
}

/// f applied lane by lane.
#[inline(always)]
fn map<const L: usize>(x: [f64; L], f: impl Fn(f64) -> f64) -> [f64; L] {
    core::array::from_fn(|i| f(x[i]))
}

/// f applied lane by lane to two operands.
#[inline(always)]
fn zip<const L: usize>(x: [f64; L], y: [f64; L], f: impl Fn(f64, f64) -> f64) -> [f64; L] {
    core::array::from_fn(|i| f(x[i], y[i]))
}

/// The operations of `tape` over the lanes of `r`, with the vector instructions of `isa`.
#[inline(always)]
fn execute<const L: usize, I: Isa>(tape: &Tape, r: &mut [[f64; L]], isa: I) {
    for (slot, &c) in r.iter_mut().zip(&tape.constants) {
        *slot = [c; L];
    }
    for op in &tape.lanes.ops {
        match *op {
            Op::Add(a, b, t) => r[t as usize] = zip(r[a as usize], r[b as usize], |x, y| x + y),
            Op::Sub(a, b, t) => r[t as usize] = zip(r[a as usize], r[b as usize], |x, y| x - y),
            Op::Mul(a, b, t) => r[t as usize] = zip(r[a as usize], r[b as usize], |x, y| x * y),
            Op::Div(a, b, t) => r[t as usize] = zip(r[a as usize], r[b as usize], |x, y| x / y),
            Op::Atan2(a, b, t) => r[t as usize] = zip(r[a as usize], r[b as usize], f64::atan2),
            Op::Powf(a, b, t) => r[t as usize] = zip(r[a as usize], r[b as usize], f64::powf),
            Op::Neg(a, t) => r[t as usize] = map(r[a as usize], |x| -x),
            Op::Sin(a, t) => r[t as usize] = isa.sin_cos_lanes(r[a as usize]).0,
            Op::Cos(a, t) => r[t as usize] = isa.sin_cos_lanes(r[a as usize]).1,
            Op::Tan(a, t) => r[t as usize] = map(r[a as usize], f64::tan),
            Op::Exp(a, t) => r[t as usize] = map(r[a as usize], f64::exp),
            Op::Ln(a, t) => r[t as usize] = map(r[a as usize], f64::ln),
            Op::Sqrt(a, t) => r[t as usize] = map(r[a as usize], f64::sqrt),
            Op::Abs(a, t) => r[t as usize] = map(r[a as usize], f64::abs),
            Op::Powi(a, k, t) => r[t as usize] = map(r[a as usize], |x| x.powi(k)),
            Op::SinCos(a, s, c) => {
                let (x, y) = isa.sin_cos_lanes(r[a as usize]);
                r[s as usize] = x;
                r[c as usize] = y;
            }
            Op::MulAdd(a, b, c, t, negate_product, negate_addend) => {
                let (x, y, z) = (r[a as usize], r[b as usize], r[c as usize]);
                // The signs are chosen outside the lane loop: one loop per combination.
                r[t as usize] = match (negate_product, negate_addend) {
                    (false, false) => core::array::from_fn(|i| mul_add(x[i], y[i], z[i])),
                    (true, false) => core::array::from_fn(|i| mul_add(-x[i], y[i], z[i])),
                    (false, true) => core::array::from_fn(|i| mul_add(x[i], y[i], -z[i])),
                    (true, true) => core::array::from_fn(|i| mul_add(-x[i], y[i], -z[i])),
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::algebra::expr::{Arena, Func};
    use crate::{Matrix, Program, SymbolKind, Tape};

    /// Every operation kind, the fused products with each sign, and sin/cos on arguments
    /// near multiples of pi/2 (the routine's slow path): each lane of a block equals the
    /// one-state tape bit for bit, for lane counts that fill and that do not fill a vector
    /// register.
    #[test]
    fn lanes_equal_one_state_bit_for_bit() {
        let mut a = Arena::new();
        let x = a.symbol("x", SymbolKind::Free);
        let y = a.symbol("y", SymbolKind::Free);
        let xy = a.mul2(x, y);
        let sx = a.sin(x);
        let cy = a.cos(y);
        let ex = a.func(Func::Exp, y).unwrap();
        let sq = a.mul2(x, x);
        let root = a.sqrt(sq).unwrap();
        let q = a.div(sx, ex).unwrap();
        let t = a.atan2(y, x);
        let sum = a.add2(xy, cy);
        let diff = a.sub(root, xy);
        let p3 = a.powi(sum, 3).unwrap();
        let neg = a.neg(q);
        let pw = a.pow(ex, y).unwrap();
        let tn = a.func(Func::Tan, x).unwrap();
        let ln = a.func(Func::Ln, ex).unwrap();
        let ab = a.func(Func::Abs, y).unwrap();
        let m = Matrix::column(vec![
            xy, sx, cy, ex, root, q, t, sum, diff, p3, neg, pw, tn, ln, ab,
        ]);
        let mut tape = Tape::new(&Program::new(&a, &[&m]).unwrap());
        let xs = [
            0.3,
            -1.2,
            std::f64::consts::FRAC_PI_2,
            3.0,
            1e-3,
            -7.5,
            0.0,
            2.2,
        ];
        let ys = [1.1, 0.4, -2.0, std::f64::consts::PI, -0.6, 5.0, 1.0, -3.3];
        check_lanes::<8>(&mut tape, &xs, &ys);
        check_lanes::<3>(&mut tape, &xs[..3], &ys[..3]);
    }

    fn check_lanes<const L: usize>(tape: &mut Tape, xs: &[f64], ys: &[f64]) {
        // Slots are reused: fewer than the one-state file's.
        assert!(tape.lane_register_len() < tape.register_len());
        let mut regs = vec![[0.0; L]; tape.lane_register_len()];
        let slots: Vec<usize> = tape.input_slots().map(|(_, s)| s).collect();
        for (lane, (&x, &y)) in xs.iter().zip(ys).enumerate() {
            regs[slots[0]][lane] = x;
            regs[slots[1]][lane] = y;
        }
        tape.execute_lanes(&mut regs);
        for (lane, (&x, &y)) in xs.iter().zip(ys).enumerate() {
            let mut one = vec![0.0; tape.register_len()];
            one[slots[0]] = x;
            one[slots[1]] = y;
            tape.execute(&mut one);
            for k in 0..tape.output_len() {
                let (slot, lane_slot) = (tape.output_slot(k), tape.lane_output_slot(k));
                assert_eq!(
                    regs[lane_slot.unwrap()][lane].to_bits(),
                    one[slot.unwrap()].to_bits(),
                    "lane {lane}, output {k}: x = {x}, y = {y}"
                );
            }
        }
    }
}
