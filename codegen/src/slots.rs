//! Register slots for emission in array form: liveness-based reuse of array elements.
//!
//! A [`Program`] is in SSA form, one register per value. When the emitter keeps registers in
//! one array (large programs, see [`crate::ARRAY_REGISTERS_ABOVE`]), giving every register its
//! own element makes the array as long as the program (66 KB for the 32-bar chain's
//! `evaluate`), all of it zeroed on every call and far beyond L1. A value's element is free
//! again after its last read, so the array only needs as many elements as values are live at
//! once: a linear scan over the straight-line code (no branches, so liveness is one
//! interval per register).

use crate::cse::{Instr, Operand, Program, Reg};

/// `slots[r]` is the array element of register r; `len` the array length.
#[derive(Clone, Debug)]
pub(crate) struct Slots {
    pub slots: Vec<u32>,
    pub len: usize,
}

fn dsts(i: &Instr) -> [Option<Reg>; 2] {
    match *i {
        Instr::Unary { dst, .. } | Instr::Binary { dst, .. } | Instr::Powi { dst, .. } => {
            [Some(dst), None]
        }
        Instr::SinCos { sin, cos, .. } => [Some(sin), Some(cos)],
    }
}

/// Assigns array elements to the registers of `p`, whose outputs and `ret` are read after
/// the last instruction. An instruction's operands whose last read it is release their
/// elements before its results take one, so `v[3] = v[3] * v[5]` may reuse an operand's
/// element (Rust evaluates the right side first).
pub(crate) fn assign(p: &Program, ret: Option<Operand>) -> Slots {
    let n = p.instructions().len();
    const NEVER: usize = usize::MAX;
    let mut last = vec![NEVER; p.registers()];
    let read = |o: Operand, k: usize, last: &mut [usize]| {
        if let Operand::Reg(r) = o {
            last[r.0 as usize] = k;
        }
    };
    for (k, i) in p.instructions().iter().enumerate() {
        i.for_each_operand(|o| read(o, k, &mut last));
    }
    for o in p.outputs() {
        for &e in &o.entries {
            read(e, n, &mut last);
        }
    }
    if let Some(o) = ret {
        read(o, n, &mut last);
    }
    let mut slots = vec![u32::MAX; p.registers()];
    let mut released = vec![false; p.registers()];
    let (mut free, mut len) = (Vec::new(), 0u32);
    for (k, i) in p.instructions().iter().enumerate() {
        i.for_each_operand(|o| {
            if let Operand::Reg(r) = o {
                let r = r.0 as usize;
                if last[r] == k && !released[r] {
                    released[r] = true;
                    free.push(slots[r]);
                }
            }
        });
        let d = dsts(i);
        for r in d.iter().flatten() {
            slots[r.0 as usize] = free.pop().unwrap_or_else(|| {
                len += 1;
                len - 1
            });
        }
        // A result nobody reads (the unused half of a sin/cos pair) frees its element at once.
        for r in d.iter().flatten() {
            if last[r.0 as usize] == NEVER {
                free.push(slots[r.0 as usize]);
            }
        }
    }
    Slots {
        slots,
        len: len as usize,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Replays the program on the slots: every read must find its register in its slot
    /// (nothing overwrote it while it was live), and the array is much shorter than one
    /// element per register.
    #[test]
    fn live_values_never_share_a_slot() {
        let mut model = crate::closed_chain_model(12);
        let eqs = crate::derive(&mut model).unwrap();
        let outs = [
            &eqs.mass,
            &eqs.coriolis_forces,
            &eqs.gravity,
            &eqs.phi_q,
            &eqs.gamma,
        ];
        let p = Program::new(&model.arena, &outs).unwrap();
        let s = assign(&p, None);
        let mut holder = vec![u32::MAX; s.len];
        let check = |o: Operand, holder: &[u32]| {
            if let Operand::Reg(r) = o {
                assert_eq!(
                    holder[s.slots[r.0 as usize] as usize], r.0,
                    "r{} overwritten",
                    r.0
                );
            }
        };
        for i in p.instructions() {
            i.for_each_operand(|o| check(o, &holder));
            for r in dsts(i).iter().flatten() {
                holder[s.slots[r.0 as usize] as usize] = r.0;
            }
        }
        for o in p.outputs() {
            for &e in &o.entries {
                check(e, &holder);
            }
        }
        assert!(
            s.len * 4 < p.registers(),
            "{} slots for {} registers",
            s.len,
            p.registers()
        );
    }
}
