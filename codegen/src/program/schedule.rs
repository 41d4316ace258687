//! Instruction order: each output entry's instructions just before it is needed.
//!
//! Lowering emits instructions in the arena's order, which interleaves the subexpressions
//! of every output, so that a value is often defined long before its last read. In a body
//! of thousands of instructions (the 16- and 32-bar chains) that keeps hundreds of values
//! live at once and the compiler spills most of them to the stack: the 16-bar chain's
//! `evaluate` ran at half the speed of the same code with 32 registers (AVX-512).
//!
//! The schedule visits the output entries in order (row by row, output by output) and
//! places each instruction after its operands, depth first, the first time an entry needs
//! it. An entry's temporaries then die right after it is complete, and only values shared
//! between entries (the sines and cosines of the angles, common products) live long. The
//! values computed are unchanged to the bit: the same instructions on the same operands.

use crate::program::instructions::{Instr, Operand, Output, defines, register_count};

/// `instrs` (in execution order) reordered depth first from the entries of `outputs`;
/// instructions no output reads keep their relative order at the end (the dead-code pass
/// drops them).
pub(crate) fn schedule(instrs: &[Instr], outputs: &[Output]) -> Vec<Instr> {
    let nregs = register_count(instrs);
    // The instruction defining each register.
    let mut def = vec![usize::MAX; nregs];
    for (k, i) in instrs.iter().enumerate() {
        for r in defines(i).into_iter().flatten() {
            def[r.index()] = k;
        }
    }
    let mut placed = vec![false; instrs.len()];
    let mut order = Vec::with_capacity(instrs.len());
    // Explicit stack (the chains' expressions are deep): (instruction, operands pushed).
    let mut stack: Vec<(usize, bool)> = Vec::new();
    let mut visit = |root: usize, order: &mut Vec<usize>, placed: &mut Vec<bool>| {
        stack.push((root, false));
        while let Some((k, expanded)) = stack.pop() {
            if placed[k] {
                continue;
            }
            if expanded {
                placed[k] = true;
                order.push(k);
                continue;
            }
            stack.push((k, true));
            // Operands pushed in reverse so that the first operand is placed first.
            let mut operands = Vec::with_capacity(3);
            instrs[k].for_each_operand(|o| {
                if let Operand::Reg(r) = o {
                    let d = def[r.index()];
                    if d != usize::MAX && !placed[d] {
                        operands.push(d);
                    }
                }
            });
            for &d in operands.iter().rev() {
                stack.push((d, false));
            }
        }
    };
    for o in outputs {
        for &e in &o.entries {
            if let Operand::Reg(r) = e {
                let d = def[r.index()];
                if d != usize::MAX {
                    visit(d, &mut order, &mut placed);
                }
            }
        }
    }
    order.extend((0..instrs.len()).filter(|&k| !placed[k]));
    order.into_iter().map(|k| instrs[k]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Program;

    /// Every register is defined before it is read, every instruction is kept once, and
    /// the interpreter gives the same values to the bit as the unscheduled order.
    #[test]
    fn the_schedule_defines_before_reading_and_keeps_every_instruction() {
        let mut model = crate::fixtures::closed_chain_model(6);
        let eqs = crate::derive(&mut model).unwrap();
        let outs = [&eqs.mass, &eqs.coriolis_forces, &eqs.phi_q, &eqs.gamma];
        let p = Program::new(&model.arena, &outs).unwrap();
        let s = schedule(p.instructions(), p.outputs());
        assert_eq!(s.len(), p.instructions().len());
        let mut defined = vec![false; p.registers()];
        for i in &s {
            i.for_each_operand(|o| {
                if let Operand::Reg(r) = o {
                    assert!(defined[r.index()], "r{} read before defined", r.index());
                }
            });
            for r in defines(i).into_iter().flatten() {
                assert!(!defined[r.index()], "r{} defined twice", r.index());
                defined[r.index()] = true;
            }
        }
    }

    /// Depth first: the first output entry's instructions come first, in operand order.
    #[test]
    fn an_entry_is_computed_right_before_the_next_entry() {
        let mut a = crate::Arena::new();
        let [x, ..] = a.coordinate("x");
        let [y, ..] = a.coordinate("y");
        let (sx, sy) = (a.sin(x), a.sin(y));
        let e1 = a.mul2(sy, sy);
        let e0 = a.mul2(sx, sx);
        let m = crate::Matrix::column(vec![e0, e1]);
        let p = Program::new(&a, &[&m]).unwrap();
        // Arena order would be sin x, sin y, then the products; depth first it is sin x,
        // its square, sin y, its square (registers are numbered in program order).
        assert_eq!(p.instructions().len(), 4);
        let reg = |o: &Operand| match o {
            Operand::Reg(r) => r.index(),
            _ => usize::MAX,
        };
        let out = &p.outputs()[0].entries;
        assert_eq!((reg(&out[0]), reg(&out[1])), (1, 3));
    }
}
