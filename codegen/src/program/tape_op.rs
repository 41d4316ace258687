//! The operations of a [`Tape`](crate::program::tape::Tape) and their layout for
//! [`Tape::execute_lanes`](crate::program::tape::Tape::execute_lanes): one operation names
//! its operands' and its result's slots of the register file; the lane layout renumbers
//! the slots so that a value's slot is reused after its last reader. Apart from both tape
//! files, which read it, so that neither imports the other.

/// One tape operation; operands and destinations are register-file slots.
#[derive(Clone, Copy, Debug)]
pub(super) enum Op {
    Add(u32, u32, u32),
    Sub(u32, u32, u32),
    Mul(u32, u32, u32),
    Div(u32, u32, u32),
    Atan2(u32, u32, u32),
    Powf(u32, u32, u32),
    Neg(u32, u32),
    Sin(u32, u32),
    Cos(u32, u32),
    Tan(u32, u32),
    Exp(u32, u32),
    Ln(u32, u32),
    Sqrt(u32, u32),
    Abs(u32, u32),
    Powi(u32, i32, u32),
    SinCos(u32, u32, u32),
    /// dst = (+-a) b + (+-c): (a, b, c, dst, negate product, negate addend).
    MulAdd(u32, u32, u32, u32, bool, bool),
}

/// The operations of a tape with its registers' slots reused after their last use: a
/// linear scan over the operations that frees a slot after the operation that reads it
/// last (unless it holds an output) and gives each result the slot freed most recently
/// (still in the cache), a new one when none is free. Constants and inputs keep their
/// slots.
#[derive(Clone, Debug)]
pub(super) struct LaneLayout {
    pub(super) ops: Vec<Op>,
    /// The number of slots.
    pub(super) registers: usize,
    /// The slot of each tape slot that holds a value at the end (constants, inputs,
    /// outputs); `u32::MAX` for the others.
    pub(super) slot: Vec<u32>,
}

impl Op {
    /// The operation with each slot `s` read or written replaced by `f(s, written)`, the
    /// reads first, in order.
    fn map_slots(self, mut f: impl FnMut(u32, bool) -> u32) -> Op {
        match self {
            Op::Add(a, b, t) => Op::Add(f(a, false), f(b, false), f(t, true)),
            Op::Sub(a, b, t) => Op::Sub(f(a, false), f(b, false), f(t, true)),
            Op::Mul(a, b, t) => Op::Mul(f(a, false), f(b, false), f(t, true)),
            Op::Div(a, b, t) => Op::Div(f(a, false), f(b, false), f(t, true)),
            Op::Atan2(a, b, t) => Op::Atan2(f(a, false), f(b, false), f(t, true)),
            Op::Powf(a, b, t) => Op::Powf(f(a, false), f(b, false), f(t, true)),
            Op::Neg(a, t) => Op::Neg(f(a, false), f(t, true)),
            Op::Sin(a, t) => Op::Sin(f(a, false), f(t, true)),
            Op::Cos(a, t) => Op::Cos(f(a, false), f(t, true)),
            Op::Tan(a, t) => Op::Tan(f(a, false), f(t, true)),
            Op::Exp(a, t) => Op::Exp(f(a, false), f(t, true)),
            Op::Ln(a, t) => Op::Ln(f(a, false), f(t, true)),
            Op::Sqrt(a, t) => Op::Sqrt(f(a, false), f(t, true)),
            Op::Abs(a, t) => Op::Abs(f(a, false), f(t, true)),
            Op::Powi(a, k, t) => Op::Powi(f(a, false), k, f(t, true)),
            Op::SinCos(a, s, c) => Op::SinCos(f(a, false), f(s, true), f(c, true)),
            Op::MulAdd(a, b, c, t, np, na) => {
                Op::MulAdd(f(a, false), f(b, false), f(c, false), f(t, true), np, na)
            }
        }
    }
}

impl LaneLayout {
    /// The layout of `ops`, whose slots below `base` are constants and inputs, whose
    /// results `outputs` must survive to the end, in a file of `registers` slots.
    pub(super) fn of(ops: &[Op], base: usize, outputs: &[u32], registers: usize) -> Self {
        // The index of the last operation that reads each slot.
        let mut last = vec![usize::MAX; registers];
        for (i, op) in ops.iter().enumerate() {
            op.map_slots(|s, written| {
                if !written {
                    last[s as usize] = i;
                }
                s
            });
        }
        let mut kept = vec![false; registers];
        for &o in outputs {
            kept[o as usize] = true;
        }
        let mut slot: Vec<u32> = (0..registers)
            .map(|s| if s < base { s as u32 } else { u32::MAX })
            .collect();
        // Free slots, the most recently freed last (popped first).
        let mut free: Vec<u32> = Vec::new();
        let mut used = base;
        let mut lane_ops = Vec::with_capacity(ops.len());
        for (i, op) in ops.iter().enumerate() {
            let mut dying: [u32; 3] = [u32::MAX; 3];
            let mut dead = 0;
            let renamed = op.map_slots(|s, written| {
                let su = s as usize;
                if !written {
                    let at = slot[su];
                    if su >= base && last[su] == i && !kept[su] && !dying[..dead].contains(&at) {
                        dying[dead] = at;
                        dead += 1;
                    }
                    return at;
                }
                // The operands are read before a result is written, so a result may take
                // the slot of an operand that dies here: free those first.
                for &d in &dying[..dead] {
                    free.push(d);
                }
                dead = 0;
                let at = free.pop().unwrap_or_else(|| {
                    used += 1;
                    (used - 1) as u32
                });
                slot[su] = at;
                if last[su] == usize::MAX && !kept[su] {
                    // Never read: its slot is free again after this operation.
                    dying[dead] = at;
                    dead += 1;
                }
                at
            });
            for &d in &dying[..dead] {
                free.push(d);
            }
            lane_ops.push(renamed);
        }
        for (s, k) in slot.iter_mut().zip(&kept) {
            if !k && (*s as usize) >= base {
                *s = u32::MAX;
            }
        }
        LaneLayout {
            ops: lane_ops,
            registers: used,
            slot,
        }
    }
}
