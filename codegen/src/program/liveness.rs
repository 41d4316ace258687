//! Liveness in a straight-line [`Program`]: the index of each register's last read, and the
//! registers a range of instructions must hand on to the code after it.
//!
//! Large bodies are emitted as nested blocks of `let`s (see [`crate::BLOCK_LETS_ABOVE`]); a
//! block returns exactly the values it defines that are read after it.

use crate::program::cse::Program;
use crate::program::instructions::{Operand, Reg, defines as defs};

/// `last[r]`: the index of the last instruction reading register r, or of the instruction
/// defining it when nothing else reads it but an output (the emitter writes an output right
/// after its instruction); n (the instruction count) when one of `at_end` reads it (the
/// returned operand, the entries of outputs written once at the end); `None` when nothing
/// does.
pub(crate) fn last_reads(p: &Program, at_end: &[Operand]) -> Vec<Option<usize>> {
    let n = p.instructions().len();
    let mut last = vec![None; p.registers()];
    for (k, i) in p.instructions().iter().enumerate() {
        for r in defs(i).into_iter().flatten() {
            last[r.0 as usize] = Some(k);
        }
    }
    let mut written = vec![false; p.registers()];
    for o in p.outputs() {
        for &e in &o.entries {
            if let Operand::Reg(r) = e {
                written[r.0 as usize] = true;
            }
        }
    }
    // A register that is neither read nor written is dead: no last read.
    for (r, l) in last.iter_mut().enumerate() {
        if !written[r] {
            *l = None;
        }
    }
    let mut read = |o: Operand, k: usize| {
        if let Operand::Reg(r) = o {
            last[r.0 as usize] = Some(k);
        }
    };
    for (k, i) in p.instructions().iter().enumerate() {
        i.for_each_operand(|o| read(o, k));
    }
    for &o in at_end {
        read(o, n);
    }
    last
}

/// The registers defined by instructions `range` that are read at or after `range.end`, in
/// definition order.
pub(crate) fn live_out(
    p: &Program,
    last: &[Option<usize>],
    range: std::ops::Range<usize>,
) -> Vec<Reg> {
    let end = range.end;
    p.instructions()[range]
        .iter()
        .flat_map(defs)
        .flatten()
        .filter(|r| last[r.0 as usize].is_some_and(|k| k >= end))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Replays block-structured scoping: inside a block only its own definitions and what
    /// earlier blocks handed on are visible. Every read, and every output at the end, must
    /// find its register visible; and blocks hand on only a fraction of what they define.
    #[test]
    fn blocks_hand_on_every_value_read_later() {
        let mut model = crate::fixtures::closed_chain_model(12);
        let eqs = crate::derive(&mut model).unwrap();
        let outs = [
            &eqs.mass,
            &eqs.coriolis_forces,
            &eqs.gravity,
            &eqs.phi_q,
            &eqs.gamma,
        ];
        let p = Program::new(&model.arena, &outs).unwrap();
        let last = last_reads(&p, &[]);
        let n = p.instructions().len();
        let mut visible = vec![false; p.registers()];
        let (mut handed, mut defined) = (0, 0);
        for start in (0..n).step_by(100) {
            let range = start..(start + 100).min(n);
            let mut local = visible.clone();
            for i in &p.instructions()[range.clone()] {
                i.for_each_operand(|o| {
                    if let Operand::Reg(r) = o {
                        assert!(local[r.0 as usize], "r{} read but not in scope", r.0);
                    }
                });
                for r in defs(i).into_iter().flatten() {
                    local[r.0 as usize] = true;
                    defined += 1;
                }
            }
            for r in live_out(&p, &last, range) {
                visible[r.0 as usize] = true;
                handed += 1;
            }
        }
        // Outputs are written right after their instruction, inside its block: none needs
        // handing on unless an instruction after the block reads it.
        for o in p.outputs() {
            for e in &o.entries {
                if let Operand::Reg(r) = e {
                    let def = p
                        .instructions()
                        .iter()
                        .position(|i| defs(i).contains(&Some(*r)))
                        .unwrap();
                    assert!(last[r.0 as usize].is_some_and(|k| k >= def));
                }
            }
        }
        assert!(handed * 2 < defined, "{handed} of {defined} handed on");
    }
}
