//! Scaling by a power of two moved onto the factor that depends on parameters only, or
//! that is ready first.
//!
//! A derivation leaves products such as `2 (a b)`, with the constant applied last: the
//! seed's C q' has 2 l2 qd1 qd2 sin(beta) cos(gamma), its three multiplications after the
//! sines and cosines. Multiplying by a power of two is exact (the exponent changes, the
//! significand does not), so `(2 a) b` is the same double as `2 (a b)`, and when `a` is
//! ready well before `b` (a rate, a parameter, against a sine) the scaling happens while
//! `b` is still being computed: one multiplication less on the longer chain, and a scaled
//! parameter is moved into the parameter cache with the other parameter-only values.
//!
//! | before                      | after                               | where                 |
//! |-----------------------------|-------------------------------------|-----------------------|
//! | `x = a*b; d = c*x`          | `t = c*a; d = t*b`                  | `a` parameters only, or ready 3 cycles before `b` |
//! | `x = k*b; d = c*x`          | `d = (c k)*b` (constant folded)     | `c k` a normal double |
//!
//! for a constant c = +-2^e and a product `x` that nothing else reads. The values are the
//! same to the bit unless a product overflows or falls below the normal range, where the
//! order of the scaling and the rounding matters (no mechanism comes near 1e-308).

use std::collections::HashMap;

use crate::program::instructions::{BinOp, Instr, Operand, Output, Reg, defines, read_counts};
use crate::program::latency::Ready;

/// `instrs` (in execution order) with every scaling by a power of two of a product read
/// once moved onto that product's factor that depends on parameters only (`parameter[s]`
/// tells which symbols are parameters), or else onto its earlier factor where that shortens
/// the longest chain.
pub(crate) fn scale_early(instrs: &[Instr], outputs: &[Output], parameter: &[bool]) -> Vec<Instr> {
    let uses = read_counts(instrs, outputs);
    let nregs = uses.len();
    // The position of each register's instruction; the positions whose instructions the
    // rewrite replaces (a rewritten product moves its scaling into its own position) and
    // the positions it empties. Every other position keeps its instruction.
    let mut def = vec![usize::MAX; nregs];
    let mut replaced: HashMap<usize, Vec<Instr>> = HashMap::new();
    let mut emptied = vec![false; instrs.len()];
    let mut ready = Ready::new(nregs);
    // Registers whose values depend on parameters (and constants) only.
    let mut fixed = vec![false; nregs];
    let is_fixed = |o: Operand, fixed: &[bool]| match o {
        Operand::Reg(r) => fixed.get(r.index()).copied().unwrap_or(false),
        Operand::Sym(s) => parameter.get(s.0 as usize).copied().unwrap_or(false),
        Operand::Const(_) => true,
    };
    let mut made = Made {
        next: nregs as u32,
        scaled: HashMap::new(),
    };
    for (j, i) in instrs.iter().enumerate() {
        let product = scaling(i)
            .filter(|(_, _, x)| uses[x.index()] == 1)
            .and_then(|(dst, c, x)| {
                // A register defined by a rewrite is not looked into again (MAX).
                let at = def[x.index()];
                match instrs.get(at)? {
                    &Instr::Binary {
                        op: BinOp::Mul,
                        lhs,
                        rhs,
                        ..
                    } => Some((at, dst, c, lhs, rhs)),
                    _ => None,
                }
            });
        if let Some((at, dst, c, a, b)) = product
            && let Some(moved) = rewrite(dst, c, (a, b), at, &ready, &mut made, |o| {
                is_fixed(o, &fixed)
            })
        {
            for m in &moved {
                let mut all_fixed = true;
                m.for_each_operand(|o| all_fixed &= is_fixed(o, &fixed));
                for r in defines(m).into_iter().flatten() {
                    if r.index() >= fixed.len() {
                        fixed.resize(r.index() + 1, false);
                    }
                    fixed[r.index()] = all_fixed;
                }
                ready.define(m);
            }
            replaced.insert(at, moved);
            emptied[j] = true;
            continue;
        }
        let mut all_fixed = true;
        i.for_each_operand(|o| all_fixed &= is_fixed(o, &fixed));
        for r in defines(i).into_iter().flatten() {
            def[r.index()] = j;
            fixed[r.index()] = all_fixed;
        }
        ready.define(i);
    }
    let mut out = Vec::with_capacity(instrs.len() + replaced.values().map(Vec::len).sum::<usize>());
    for (j, i) in instrs.iter().enumerate() {
        match replaced.remove(&j) {
            Some(moved) => out.extend(moved),
            None if emptied[j] => {}
            None => out.push(*i),
        }
    }
    out
}

/// `(dst, c, x)` for `dst = c * x` with c a power of two (either side) and x a register.
fn scaling(i: &Instr) -> Option<(Reg, f64, Reg)> {
    match *i {
        Instr::Binary {
            dst,
            op: BinOp::Mul,
            lhs: Operand::Const(c),
            rhs: Operand::Reg(x),
        }
        | Instr::Binary {
            dst,
            op: BinOp::Mul,
            lhs: Operand::Reg(x),
            rhs: Operand::Const(c),
        } if power_of_two(c) => Some((dst, c, x)),
        _ => None,
    }
}

/// Whether c = +-2^e for a normal double (its significand bits all zero).
fn power_of_two(c: f64) -> bool {
    c.is_normal() && c.to_bits() & ((1 << 52) - 1) == 0
}

/// The registers the rewrite defines.
struct Made {
    /// The next free register.
    next: u32,
    /// `c * o` already computed: (c's bits, o) to (its register, its position).
    scaled: HashMap<(u64, Key), (Reg, usize)>,
}

/// An operand as a hash key.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Reg(u32),
    Sym(u32),
}

/// The instructions computing `dst = c (a b)` at position `at` with the scaling on the
/// factor that depends on parameters only (`fixed`), else on the earlier factor; `None`
/// where neither applies, or the scaling would not shorten the chain. A scaling of the same
/// factor made at an earlier position is read rather than computed again.
fn rewrite(
    dst: Reg,
    c: f64,
    (a, b): (Operand, Operand),
    at: usize,
    ready: &Ready,
    made: &mut Made,
    fixed: impl Fn(Operand) -> bool,
) -> Option<Vec<Instr>> {
    let mul = |dst, lhs, rhs| Instr::Binary {
        dst,
        op: BinOp::Mul,
        lhs,
        rhs,
    };
    if let (Operand::Const(k), o) | (o, Operand::Const(k)) = (a, b) {
        let folded = c * k;
        return folded
            .is_normal()
            .then(|| vec![mul(dst, Operand::Const(folded), o)]);
    }
    let (early, late) = match (fixed(a), fixed(b)) {
        // Scaled with the other parameter-only values (cached once per parameter set where
        // the program's are): one multiplication fewer per call.
        (true, false) => (a, b),
        (false, true) => (b, a),
        _ => {
            let (early, late) = if ready.of(a) <= ready.of(b) {
                (a, b)
            } else {
                (b, a)
            };
            // The scaling fits before `late` is ready: one multiplication off the chain.
            if ready.of(early) + 3 > ready.of(late) {
                return None;
            }
            (early, late)
        }
    };
    let key = match early {
        Operand::Reg(r) => Key::Reg(r.0),
        Operand::Sym(s) => Key::Sym(s.0),
        Operand::Const(_) => return None,
    };
    if let Some(&(t, made_at)) = made.scaled.get(&(c.to_bits(), key))
        && made_at < at
    {
        return Some(vec![mul(dst, Operand::Reg(t), late)]);
    }
    let t = Reg(made.next);
    made.next += 1;
    made.scaled.insert((c.to_bits(), key), (t, at));
    Some(vec![
        mul(t, Operand::Const(c), early),
        mul(dst, Operand::Reg(t), late),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::expr::{Arena, SymbolKind};
    use crate::program::instructions::UnOp;
    use crate::{Program, Tape};

    fn mul(dst: u32, lhs: Operand, rhs: Operand) -> Instr {
        Instr::Binary {
            dst: Reg(dst),
            op: BinOp::Mul,
            lhs,
            rhs,
        }
    }

    fn reg(k: u32) -> Operand {
        Operand::Reg(Reg(k))
    }

    /// The values of `instrs` computing the column `entries`, at inputs (l, u, v).
    fn values(arena: &Arena, instrs: &[Instr], entries: &[Operand], at: [f64; 3]) -> Vec<u64> {
        let program = Program::from_parts(arena, instrs, entries_output(entries));
        let mut out = vec![0.0; entries.len()];
        Tape::new(&program).eval(&at, &mut out).unwrap();
        out.into_iter().map(f64::to_bits).collect()
    }

    /// The instruction defining register `k` in `instrs`.
    fn def_of(instrs: &[Instr], k: u32) -> Instr {
        *instrs
            .iter()
            .find(|i| defines(i).contains(&Some(Reg(k))))
            .unwrap()
    }

    #[test]
    fn scalings_move_where_they_shorten_or_cache_and_keep_every_bit() {
        let mut arena = Arena::new();
        let l = Operand::Sym(arena.symbol_id("l", SymbolKind::Parameter));
        let u = Operand::Sym(arena.symbol_id("u", SymbolKind::Free));
        let v = Operand::Sym(arena.symbol_id("v", SymbolKind::Free));
        let parameter = [true, false, false];
        let instrs = [
            // r1 = 0.5 (l u): onto the parameter.
            mul(0, l, u),
            mul(1, Operand::Const(0.5), reg(0)),
            // r5 = 2 (w sin v), w = u u: onto w, ready long before the sine.
            Instr::Unary {
                dst: Reg(2),
                op: UnOp::Sin,
                arg: v,
            },
            mul(3, u, u),
            mul(4, reg(3), reg(2)),
            mul(5, reg(4), Operand::Const(2.0)),
            // r7 = 0.25 (3 u): folded into 0.75 u.
            mul(6, Operand::Const(3.0), u),
            mul(7, Operand::Const(0.25), reg(6)),
            // r9 = 2 (u v): left, both factors are ready together.
            mul(8, u, v),
            mul(9, Operand::Const(2.0), reg(8)),
            // r11 = -2 (l v), l v read twice: left.
            mul(10, l, v),
            mul(11, Operand::Const(-2.0), reg(10)),
            // r12 = 3 (u v) is no power of two: left.
            mul(12, Operand::Const(3.0), reg(8)),
        ];
        let entries = [reg(1), reg(5), reg(7), reg(9), reg(10), reg(11), reg(12)];
        let scaled = scale_early(&instrs, &entries_output(&entries), &parameter);
        let shape = |k: u32| match def_of(&scaled, k) {
            Instr::Binary {
                op: BinOp::Mul,
                lhs,
                rhs,
                ..
            } => (lhs, rhs),
            other => panic!("r{k}: {other:?}"),
        };
        // Onto the parameter and onto w: (c x) times the other factor.
        for (k, early, late) in [(1, l, u), (5, reg(3), reg(2))] {
            let (t, other) = shape(k);
            let Operand::Reg(t) = t else {
                panic!("r{k}: {t:?}")
            };
            assert_eq!(other, late, "r{k}");
            assert!(
                matches!(def_of(&scaled, t.0), Instr::Binary { lhs: Operand::Const(_), rhs, .. } if rhs == early)
            );
        }
        assert_eq!(shape(7), (Operand::Const(0.75), u));
        assert_eq!(shape(9), (Operand::Const(2.0), reg(8)));
        assert_eq!(shape(11), (Operand::Const(-2.0), reg(10)));
        assert_eq!(shape(12), (Operand::Const(3.0), reg(8)));
        assert_eq!(
            scaled.len(),
            instrs.len() - 1,
            "moved, not added; one folded"
        );
        for at in [[0.3, -1.7, 2.9], [1e-3, 7.5, -0.4], [123.0, 0.1, 1e5]] {
            assert_eq!(
                values(&arena, &scaled, &entries, at),
                values(&arena, &instrs, &entries, at),
                "{at:?}"
            );
        }
    }

    /// One output, the column `entries`.
    fn entries_output(entries: &[Operand]) -> Vec<Output> {
        vec![Output {
            rows: entries.len(),
            cols: 1,
            entries: entries.to_vec(),
        }]
    }
}
