//! Multiply-add fusion: a product read by nothing but one sum or difference becomes, with
//! it, one [`Instr::MulAdd`] (`mechanism_math::mul_add`, rounded once where the target has
//! a fused multiply-add and exactly `a * b + c` elsewhere).
//!
//! | before                        | after                                   |
//! |-------------------------------|-----------------------------------------|
//! | `p = a*b; s = p + c`          | `s = mul_add(a, b, c)`                  |
//! | `p = a*b; s = p - c`          | `s = mul_add(a, b, -c)`                 |
//! | `p = a*b; s = c - p`          | `s = mul_add(-a, b, c)`                 |
//!
//! The product's own instruction is then dead and dropped by the dead-code pass. Without a
//! fused instruction the results are those of the unfused code to the bit (negation is
//! exact and `c - p` is `c + (-p)` in IEEE arithmetic).

use crate::program::instructions::{BinOp, Instr, Operand, Output, read_counts};

/// `instrs` with every product that one addition or subtraction alone reads fused into it.
pub(crate) fn fuse_multiply_add(instrs: &[Instr], outputs: &[Output]) -> Vec<Instr> {
    let uses = read_counts(instrs, outputs);
    let nregs = uses.len();
    // The factors of each product, by its register.
    let mut product: Vec<Option<(Operand, Operand)>> = vec![None; nregs];
    let mut out = Vec::with_capacity(instrs.len());
    for i in instrs {
        let fused = match *i {
            Instr::Binary {
                dst,
                op: op @ (BinOp::Add | BinOp::Sub),
                lhs,
                rhs,
            } => {
                let single = |o: Operand| match o {
                    Operand::Reg(r) if uses[r.index()] == 1 => product[r.index()],
                    _ => None,
                };
                match (single(lhs), single(rhs)) {
                    (Some((a, b)), _) => Some(Instr::MulAdd {
                        dst,
                        a,
                        b,
                        c: rhs,
                        negate_product: false,
                        negate_addend: op == BinOp::Sub,
                    }),
                    (None, Some((a, b))) => Some(Instr::MulAdd {
                        dst,
                        a,
                        b,
                        c: lhs,
                        negate_product: op == BinOp::Sub,
                        negate_addend: false,
                    }),
                    (None, None) => None,
                }
            }
            _ => None,
        };
        if let Instr::Binary {
            dst,
            op: BinOp::Mul,
            lhs,
            rhs,
        } = *i
        {
            product[dst.index()] = Some((lhs, rhs));
        }
        out.push(fused.unwrap_or(*i));
    }
    out
}
