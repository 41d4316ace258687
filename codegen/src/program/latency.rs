//! How long each value of a program takes to compute, counted along its longest chain of
//! dependent instructions: what [`super::scale`] shortens. The cycle counts are those of a
//! current x86-64 core (Zen 3, Ice Lake: a sum or product 3 to 4 cycles, a fused
//! multiply-add 4, a division about 13, a square root about 15); only their relative sizes
//! matter here, and a call to a real function, `sin_cos` included, is long against all of
//! them.

use crate::program::instructions::{BinOp, Instr, Operand, UnOp, defines};

/// Cycles from the last operand of `i` to its result.
pub(crate) fn cycles(i: &Instr) -> u32 {
    match *i {
        Instr::Unary {
            op: UnOp::Neg | UnOp::Abs,
            ..
        } => 1,
        Instr::Unary { op: UnOp::Sqrt, .. } => 15,
        Instr::Binary {
            op: BinOp::Add | BinOp::Sub | BinOp::Mul,
            ..
        } => 3,
        Instr::Binary { op: BinOp::Div, .. } => 13,
        Instr::MulAdd { .. } => 4,
        Instr::Unary { .. } | Instr::Binary { .. } | Instr::Powi { .. } | Instr::SinCos { .. } => {
            40
        }
    }
}

/// The cycle at which each register's value is ready, inputs and constants at 0.
#[derive(Clone, Debug)]
pub(crate) struct Ready(Vec<u32>);

impl Ready {
    /// Room for registers `0..nregs`, none computed yet.
    pub(crate) fn new(nregs: usize) -> Self {
        Self(vec![0; nregs])
    }

    /// When `o` is ready.
    pub(crate) fn of(&self, o: Operand) -> u32 {
        match o {
            Operand::Reg(r) => self.0.get(r.index()).copied().unwrap_or(0),
            Operand::Sym(_) | Operand::Const(_) => 0,
        }
    }

    /// Records the registers of `i`, which starts when its last operand is ready.
    pub(crate) fn define(&mut self, i: &Instr) {
        let mut start = 0;
        i.for_each_operand(|o| start = start.max(self.of(o)));
        for r in defines(i).into_iter().flatten() {
            if r.index() >= self.0.len() {
                self.0.resize(r.index() + 1, 0);
            }
            self.0[r.index()] = start + cycles(i);
        }
    }
}
