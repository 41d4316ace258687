//! Sines and cosines computed side by side: which instructions of a body the emitter
//! writes as one `math::sin_cos_lanes([a, b, c, d])` call.
//!
//! `mechanism_math::sin_cos_lanes` computes each lane bit for bit as `sin_cos` does, two
//! or four lanes per vector instruction, so grouping changes no value and executes fewer
//! instructions. A group starts at a sine or cosine (a `SinCos` pair, or a lone `Sin` or
//! `Cos`) and takes the next ones in the body whose argument is already at hand there (a
//! symbol, a constant, or a register defined before that point), so moving them up is
//! safe: nothing between reads them, and they read nothing defined in between. An argument
//! one arithmetic instruction away from operands at hand (the seed's Omega t) is computed
//! first, that instruction moved up before the group. At most [`LANES`] to a group: more
//! would outgrow the 16 vector registers of the x86-64 baseline.
//!
//! Every body is grouped, the one-degree-of-freedom mechanisms' included: a group of four
//! lanes is one pass of `sin_cos_lanes`'s vector instructions (written with the
//! instructions themselves, four lanes to an AVX2 register, two to an SSE2 one), where the
//! lanes one by one are four passes of the scalar code. The timings: BENCHMARKS.md.

use crate::program::instructions::{Instr, Operand, Reg, UnOp, defines};

/// Most lanes in one group.
pub(crate) const LANES: usize = 4;

/// What a trigonometric instruction defines: its (sin, cos) registers, either may be absent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Lane {
    /// The argument.
    pub arg: Operand,
    /// The register receiving sin arg, if the instruction needs it.
    pub sin: Option<Reg>,
    /// The register receiving cos arg, if the instruction needs it.
    pub cos: Option<Reg>,
}

/// One statement of the body: an instruction, or a group of sines and cosines.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    /// The instruction at this index, emitted alone.
    Single(usize),
    /// The instructions at these indices (two to [`LANES`]), as one lanes call.
    Group(Vec<usize>),
}

/// The lane of a sine, cosine or (sine, cosine) instruction; `None` for other instructions.
pub(crate) fn lane(i: &Instr) -> Option<Lane> {
    match *i {
        Instr::SinCos { sin, cos, arg } => Some(Lane {
            arg,
            sin: Some(sin),
            cos: Some(cos),
        }),
        Instr::Unary {
            dst,
            op: UnOp::Sin,
            arg,
        } => Some(Lane {
            arg,
            sin: Some(dst),
            cos: None,
        }),
        Instr::Unary {
            dst,
            op: UnOp::Cos,
            arg,
        } => Some(Lane {
            arg,
            sin: None,
            cos: Some(dst),
        }),
        _ => None,
    }
}

/// The statements of `instrs` in emission order (see the module docs). `defined[r]` tells
/// whether register r is defined before the first of `instrs` (values of earlier blocks);
/// it is updated as statements are planned. Without `group`, every instruction is a
/// [`Step::Single`] in program order.
pub(crate) fn plan(instrs: &[Instr], defined: &mut [bool], group: bool) -> Vec<Step> {
    let define = |i: &Instr, defined: &mut [bool]| {
        for r in defines(i).into_iter().flatten() {
            if let Some(d) = defined.get_mut(r.index()) {
                *d = true;
            }
        }
    };
    let mut done = vec![false; instrs.len()];
    let mut steps = Vec::with_capacity(instrs.len());
    for k in 0..instrs.len() {
        if done[k] {
            continue;
        }
        done[k] = true;
        let mut members = vec![k];
        if group && lane(&instrs[k]).is_some() {
            for j in k + 1..instrs.len() {
                if members.len() == LANES {
                    break;
                }
                let Some(l) = lane(&instrs[j]).filter(|_| !done[j]) else {
                    continue;
                };
                if !at_hand(l.arg, defined) {
                    // One arithmetic instruction of operands at hand (the seed's
                    // Omega t) moves up, before the group.
                    let Some(d) = movable_definition(instrs, k + 1..j, l.arg, &done, defined)
                    else {
                        continue;
                    };
                    done[d] = true;
                    define(&instrs[d], defined);
                    steps.push(Step::Single(d));
                }
                done[j] = true;
                members.push(j);
            }
        }
        for &m in &members {
            define(&instrs[m], defined);
        }
        steps.push(if members.len() == 1 {
            Step::Single(k)
        } else {
            Step::Group(members)
        });
    }
    steps
}

/// The index in `range` of the instruction defining register `arg`, if it is not planned
/// yet, is no sine or cosine, and reads only operands at hand: it can move up to the
/// start of `range`.
fn movable_definition(
    instrs: &[Instr],
    range: core::ops::Range<usize>,
    arg: Operand,
    done: &[bool],
    defined: &[bool],
) -> Option<usize> {
    let Operand::Reg(r) = arg else {
        return None;
    };
    let d = range
        .into_iter()
        .find(|&d| defines(&instrs[d]).contains(&Some(r)))?;
    let mut ready = !done[d] && lane(&instrs[d]).is_none();
    instrs[d].for_each_operand(|o| ready &= at_hand(o, defined));
    ready.then_some(d)
}

/// Whether operand `o` has its value at this point: a symbol, a constant, or a register
/// that `defined` marks.
fn at_hand(o: Operand, defined: &[bool]) -> bool {
    match o {
        Operand::Reg(r) => defined.get(r.index()).copied().unwrap_or(false),
        Operand::Sym(_) | Operand::Const(_) => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::program::instructions::BinOp;

    fn r(k: u32) -> Reg {
        Reg(k)
    }

    fn sym(k: u32) -> Operand {
        Operand::Sym(crate::algebra::expr::SymbolId(k))
    }

    fn pair(sin: u32, cos: u32, arg: Operand) -> Instr {
        Instr::SinCos {
            sin: r(sin),
            cos: r(cos),
            arg,
        }
    }

    fn unary(dst: u32, op: UnOp, arg: Operand) -> Instr {
        Instr::Unary {
            dst: r(dst),
            op,
            arg,
        }
    }

    fn mul(dst: u32, lhs: Operand, rhs: Operand) -> Instr {
        Instr::Binary {
            dst: r(dst),
            op: BinOp::Mul,
            lhs,
            rhs,
        }
    }

    /// Sines of symbols group from the first; a sine whose argument is defined later waits
    /// for it; a product between them stays in place.
    #[test]
    fn groups_take_only_arguments_at_hand() {
        let instrs = [
            pair(0, 1, sym(0)),
            mul(2, Operand::Reg(r(0)), sym(1)),
            // Reads r2, defined just above it: not at hand at instruction 0.
            unary(3, UnOp::Sin, Operand::Reg(r(2))),
            unary(4, UnOp::Cos, sym(2)),
            pair(5, 6, Operand::Reg(r(2))),
        ];
        let mut defined = vec![false; 7];
        let steps = plan(&instrs, &mut defined, true);
        assert_eq!(
            steps,
            vec![
                Step::Group(vec![0, 3]),
                Step::Single(1),
                Step::Group(vec![2, 4]),
            ]
        );
        assert!(defined.iter().all(|d| *d));
        let mut defined = vec![false; 7];
        let single: Vec<Step> = (0..5).map(Step::Single).collect();
        assert_eq!(plan(&instrs, &mut defined, false), single);
    }

    /// The sine of a product of symbols (the seed's sin(Omega t)) joins the group, the
    /// product moved up before it; the sine of a product that reads a register defined
    /// later does not, and stays where it is.
    #[test]
    fn one_instruction_of_operands_at_hand_moves_up() {
        let instrs = [
            pair(0, 1, sym(0)),
            mul(2, sym(1), sym(2)),
            mul(3, Operand::Reg(r(0)), sym(2)),
            unary(4, UnOp::Sin, Operand::Reg(r(3))),
            unary(5, UnOp::Sin, Operand::Reg(r(2))),
        ];
        let mut defined = vec![false; 6];
        let steps = plan(&instrs, &mut defined, true);
        assert_eq!(
            steps,
            vec![
                Step::Single(1),
                Step::Group(vec![0, 4]),
                Step::Single(2),
                Step::Single(3),
            ]
        );
        assert!(defined.iter().all(|d| *d));
    }

    /// No group is longer than LANES, and every instruction is planned once.
    #[test]
    fn groups_hold_at_most_lanes() {
        let instrs: Vec<Instr> = (0..10)
            .map(|k| unary(k, UnOp::Sin, Operand::Const(k as f64)))
            .collect();
        let mut defined = vec![false; 10];
        let steps = plan(&instrs, &mut defined, true);
        assert_eq!(
            steps,
            vec![
                Step::Group(vec![0, 1, 2, 3]),
                Step::Group(vec![4, 5, 6, 7]),
                Step::Group(vec![8, 9]),
            ]
        );
    }
}
