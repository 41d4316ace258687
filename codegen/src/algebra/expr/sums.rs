//! Sums of the arena: the canonical sum (flat, like terms collected, constants folded,
//! sin^2 + cos^2 pairs merged), its coefficients, and negation.

use smallvec::SmallVec;

use crate::algebra::expr::{Arena, Func, Id, NO_ID, Node, Operands, Overflow, Short};
use crate::number::Number;

impl Arena {
    /// Splits a term into its numeric coefficient and its coefficient-free part
    /// (`None` for a pure constant).
    pub fn split_coefficient(&mut self, id: Id) -> (Number, Option<Id>) {
        // The node is read in place (a clone of a product would copy its factors): every
        // term of every sum passes through here.
        let (c, rest) = match self.node(id) {
            Node::Num(n) => return (*n, None),
            Node::Mul(fs) => match (self.as_number(fs[0]), &**fs) {
                (Some(c), [_, rest]) => return (c, Some(*rest)),
                (Some(c), [_, rest @ ..]) => (c, rest),
                _ => return (Number::int(1), Some(id)),
            },
            _ => return (Number::int(1), Some(id)),
        };
        if let Some(&r) = self.coefficient_free.get(id.index())
            && r != NO_ID
        {
            return (c, Some(r));
        }
        let rest = Operands::from(rest);
        (c, Some(self.intern(Node::Mul(rest))))
    }

    /// c * e for a numeric c, without re-canonicalising e's factors (e is canonical and
    /// coefficient-free).
    pub(super) fn scale(&mut self, c: Number, e: Id) -> Id {
        if c.is_zero() {
            return self.int(0);
        }
        if c.is_one() {
            return e;
        }
        let cn = self.number(c);
        match self.node(e) {
            Node::Mul(fs) => {
                let mut v: Short<Id> = SmallVec::with_capacity(fs.len() + 1);
                v.push(cn);
                v.extend_from_slice(fs);
                let scaled = self.intern(Node::Mul(Operands::from(&v[..])));
                let k = scaled.index();
                if k >= self.coefficient_free.len() {
                    self.coefficient_free.resize(k + 1, NO_ID);
                }
                self.coefficient_free[k] = e;
                scaled
            }
            Node::Add(ts) => {
                let ts = ts.clone();
                let terms: Vec<Id> = ts.iter().map(|&t| self.scale_term(c, t)).collect();
                self.add(&terms)
            }
            _ => self.intern(Node::Mul(Operands::from([cn, e]))),
        }
    }

    /// c * e as one product node even when e is a sum: not the canonical form (which
    /// distributes c over e's terms, see [`Arena::mul`]), so only for expressions that are
    /// lowered to programs and never combined again (`program::factor`).
    pub(crate) fn scaled_sum(&mut self, c: Number, e: Id) -> Id {
        if c.is_one() || !matches!(self.node(e), Node::Add(_)) {
            return self.scale(c, e);
        }
        let cn = self.number(c);
        self.intern(Node::Mul(Operands::from([cn, e])))
    }

    /// The sum of `terms` as one node, in the given order, without merging or
    /// re-canonicalising them (which would distribute the coefficient of a
    /// [`Arena::scaled_sum`] term again): for lowering only, as that one.
    pub(crate) fn sum_as_is(&mut self, terms: &[Id]) -> Id {
        match terms {
            [] => self.int(0),
            [t] => *t,
            _ => self.intern(Node::Add(terms.into())),
        }
    }

    fn scale_term(&mut self, c: Number, t: Id) -> Id {
        let (k, rest) = self.split_coefficient(t);
        match rest {
            None => {
                let kc = self.fold_mul(k, c);
                self.number(kc)
            }
            Some(r) => {
                let kc = self.fold_mul(k, c);
                self.scale(kc, r)
            }
        }
    }

    /// The canonical sum of `terms`.
    pub fn add(&mut self, terms: &[Id]) -> Id {
        let mut flat: Short<Id> = SmallVec::with_capacity(terms.len());
        for &t in terms {
            match self.node(t) {
                Node::Add(ts) => flat.extend_from_slice(ts),
                _ => flat.push(t),
            }
        }
        let mut constant = Number::int(0);
        // (coefficient-free part, coefficient, the term itself while no like term merged
        // into it: `scale` would build that very node again, at the cost of two look-ups).
        let mut pairs: Short<(Id, Number, Id)> = SmallVec::with_capacity(flat.len());
        for &t in flat.iter() {
            let (c, rest) = self.split_coefficient(t);
            match rest {
                None => constant = self.fold_add(constant, c),
                Some(r) => {
                    // c * (a sum) is a sum again, distributed, not the term (only a
                    // lowering's `scaled_sum` makes such a term).
                    let same = if matches!(self.node(r), Node::Add(_)) {
                        NO_ID
                    } else {
                        t
                    };
                    pairs.push((r, c, same));
                }
            }
        }
        pairs.sort_by_key(|p| p.0);
        // Like terms merged in place: `merged` is the first `kept` pairs.
        let mut kept: usize = 0;
        for k in 0..pairs.len() {
            let (r, c, same) = pairs[k];
            match kept.checked_sub(1).map(|last| &mut pairs[last]) {
                Some((lr, lc, lsame)) if *lr == r => {
                    *lsame = NO_ID;
                    *lc = lc.checked_add(c).unwrap_or_else(|| {
                        self.overflow.get_or_insert(Overflow {
                            lhs: *lc,
                            op: '+',
                            rhs: c,
                        });
                        Number::int(0)
                    })
                }
                _ => {
                    pairs[kept] = (r, c, same);
                    kept += 1;
                }
            }
        }
        pairs.truncate(kept);
        // Borrowed, not moved: a move of the list copies its inline storage.
        let merged = &mut pairs;
        merged.retain(|(_, c, _)| !c.is_zero());
        if let Some(extra) = self.pythagoras(merged) {
            // sin^2 + cos^2 pairs were replaced; re-add so the survivors merge again.
            let mut again: Vec<Id> = merged.iter().map(|&(r, c, _)| self.scale(c, r)).collect();
            again.extend(extra);
            let k = self.number(constant);
            again.push(k);
            return self.add(&again);
        }
        let mut out: Short<Id> =
            SmallVec::with_capacity(merged.len() + usize::from(!constant.is_zero()));
        if !constant.is_zero() {
            out.push(self.number(constant));
        }
        for &(r, c, same) in merged.iter() {
            out.push(if same == NO_ID {
                self.scale(c, r)
            } else {
                same
            });
        }
        match out.len() {
            0 => self.int(0),
            1 => out[0],
            _ => self.intern(Node::Add(Operands::from(out))),
        }
    }

    /// Finds pairs c*u*sin(x)^2 and c*u*cos(x)^2 in `terms` (coefficient-free part,
    /// coefficient, the kept term or `NO_ID`), removes both and returns the replacements c*u.
    /// `None` when there is no pair.
    fn pythagoras(&mut self, terms: &mut Short<(Id, Number, Id)>) -> Option<Vec<Id>> {
        let two = Number::int(2);
        // Most sums have no sin(x)^2 factor: tell so without the scratch lists below.
        let sin_squared = |f: Id| match *self.node(f) {
            Node::Pow(b, e) => {
                self.as_number(e) == Some(two) && matches!(self.node(b), Node::Func(Func::Sin, _))
            }
            _ => false,
        };
        let any = terms.iter().any(|&(r, _, _)| match self.node(r) {
            Node::Mul(fs) => fs.iter().any(|&f| sin_squared(f)),
            _ => sin_squared(r),
        });
        if !any {
            return None;
        }
        let mut found = Vec::new();
        let mut removed = vec![false; terms.len()];
        for i in 0..terms.len() {
            if removed[i] {
                continue;
            }
            let (r, c, _) = terms[i];
            let factors: Vec<Id> = match self.node(r) {
                Node::Mul(fs) => fs.to_vec(),
                _ => vec![r],
            };
            for (k, &f) in factors.iter().enumerate() {
                let Node::Pow(b, e) = *self.node(f) else {
                    continue;
                };
                if self.as_number(e) != Some(two) {
                    continue;
                }
                let Node::Func(Func::Sin, x) = *self.node(b) else {
                    continue;
                };
                let cos = self.func_raw(Func::Cos, x);
                let cos2 = self.intern(Node::Pow(cos, e));
                let mut partner: Vec<Id> = factors.clone();
                partner[k] = cos2;
                partner.sort();
                let pkey = if partner.len() == 1 {
                    partner[0]
                } else {
                    self.intern(Node::Mul(partner.into()))
                };
                let hit = terms
                    .iter()
                    .enumerate()
                    .position(|(j, &(pr, pc, _))| !removed[j] && j != i && pr == pkey && pc == c);
                if let Some(j) = hit {
                    removed[i] = true;
                    removed[j] = true;
                    let mut rest = factors.clone();
                    rest.remove(k);
                    let cn = self.number(c);
                    rest.push(cn);
                    found.push(self.mul(&rest));
                    break;
                }
            }
        }
        if found.is_empty() {
            return None;
        }
        let mut i = 0;
        terms.retain(|_| {
            i += 1;
            !removed[i - 1]
        });
        Some(found)
    }

    /// a + b.
    pub fn add2(&mut self, a: Id, b: Id) -> Id {
        self.add(&[a, b])
    }

    /// a - b.
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        let nb = self.neg(b);
        self.add(&[a, nb])
    }

    /// -a.
    pub fn neg(&mut self, a: Id) -> Id {
        self.scale_term(Number::int(-1), a)
    }
}
