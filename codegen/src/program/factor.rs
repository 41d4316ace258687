//! Sums rewritten by their most frequent factor (a greedy multivariate Horner scheme) before
//! they are lowered to instructions.
//!
//! The derivation leaves sums of products that share factors. In a closed chain,
//! (C q')_i = sum_j qd_j^2 (w_ij sin th_i cos th_j - w_ij cos th_i sin th_j) costs about
//! five operations per pair (i, j); expanded and factored by sin th_i and cos th_i it is
//! sin th_i sum_j w_ij (cos th_j qd_j^2) - cos th_i sum_j w_ij (sin th_j qd_j^2), two
//! multiply-adds per pair, and the products cos th_j qd_j^2 are shared by every row. The
//! rewrite is the classical one of code optimisers for large polynomials (Horner schemes
//! in several variables): expand a sum into monomials, take out the factor that most of
//! them contain, and repeat on the quotient and on the rest.
//!
//! What it does not do: look inside a function or a power (`sin(u)`, `x^(1/2)`, `1/(a + b)`
//! are factors as they stand), distribute a product over a sum that something else reads
//! too (that sum is computed once anyway: in the bodies' rotation matrices such sums are read
//! by many entries), or expand a sum whose monomials would outnumber
//! [`EXPANSION_LIMIT`], or once all expansions together have reached a budget proportional
//! to the program's size (its terms are then factored as they stand). Values are unchanged up
//! to rounding: the coefficients of the expansion are exact products of rationals (of
//! floats, for declarations with decimal constants, rounded once each).
//!
//! The choice of factor is greedy and sees one sum at a time, so the rewrite can still cost
//! more than it saves. [`crate::Program::new`] keeps the derived or the factored form,
//! whichever has fewer operations per call, lowering only one of them where an estimate read
//! off the two graphs decides. The A02 N four-bar's Phi_q stays as derived; its combined
//! program and every shipped mechanism's are factored.

use crate::algebra::expr::{Arena, FxHashMap, Id, NO_ID, Node, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::number::Number;
use crate::program::factor_counts::{FactorCounts, Tier};

/// Most monomials one sum may expand into (a larger one keeps its terms as they are).
pub(crate) const EXPANSION_LIMIT: usize = 2048;
/// All expansions of one program together produce at most `TOTAL_FACTOR` monomials per
/// unit of the graph's size ([`Arena::size`]) plus `TOTAL_BASE`: the rewrite's memory
/// stays proportional to the program's.
const TOTAL_FACTOR: usize = 4;
const TOTAL_BASE: usize = 1 << 16;

/// A product: its numeric coefficient and its other factors, sorted and canonical.
#[derive(Clone, Debug)]
struct Monomial {
    coef: Number,
    factors: Vec<Id>,
}

/// A new arena holding what `outputs` reach (see [`Arena::reachable`]), the outputs there
/// with every sum rewritten, and whether any entry changed: the factored forms are for
/// lowering only, and the caller's arena stays as the derivation left it.
pub(crate) fn factored_copy(arena: &Arena, outputs: &[&Matrix]) -> (Arena, Vec<Matrix>, bool) {
    let roots: Vec<Id> = outputs
        .iter()
        .flat_map(|m| m.data.iter().copied())
        .collect();
    let (mut local, roots) = arena.reachable(&roots);
    let mut rest = &roots[..];
    let copied: Vec<Matrix> = outputs
        .iter()
        .map(|m| {
            let (data, tail) = rest.split_at(m.data.len());
            rest = tail;
            Matrix {
                rows: m.rows,
                cols: m.cols,
                data: data.to_vec(),
            }
        })
        .collect();
    let copied: Vec<&Matrix> = copied.iter().collect();
    let factored = factor_sums(&mut local, &copied);
    let rewritten = factored.iter().zip(&copied).any(|(f, c)| f.data != c.data);
    (local, factored, rewritten)
}

/// The matrices `outputs` with every sum rewritten (see the module docs), in `arena`.
pub(crate) fn factor_sums(arena: &mut Arena, outputs: &[&Matrix]) -> Vec<Matrix> {
    let budget = TOTAL_FACTOR * arena.size() + TOTAL_BASE;
    let mut readers = vec![0u32; arena.len()];
    for node in arena.nodes() {
        node.for_each_child(|c| readers[c.index()] += 1);
    }
    for e in outputs.iter().flat_map(|m| m.data.iter()) {
        readers[e.index()] += 1;
    }
    let mut f = Factoring {
        readers,
        arena,
        done: Vec::new(),
        invariant: Vec::new(),
        budget,
    };
    outputs
        .iter()
        .map(|m| Matrix {
            rows: m.rows,
            cols: m.cols,
            data: m.data.iter().map(|&e| f.rewrite(e)).collect(),
        })
        .collect()
}

/// Whether a fact holds of a node: not yet worked out, yes or no.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Known {
    Unknown,
    Yes,
    No,
}

struct Factoring<'a> {
    arena: &'a mut Arena,
    /// How many nodes and output entries read each node of the arena as given.
    readers: Vec<u32>,
    /// Rewritten node by node id (`NO_ID`: not yet rewritten); a table indexed by id, as
    /// every node the outputs reach is looked up.
    done: Vec<Id>,
    /// Whether a node depends on parameters and constants only, by node id.
    invariant: Vec<Known>,
    /// Monomials all expansions together may still produce.
    budget: usize,
}

impl Factoring<'_> {
    /// `id` with its sums factored: a sum as a whole, a product factor by factor, anything
    /// else as it stands.
    fn rewrite(&mut self, id: Id) -> Id {
        if let Some(&r) = self.done.get(id.index())
            && r != NO_ID
        {
            return r;
        }
        let r = match self.arena.node(id).clone() {
            Node::Add(terms) => {
                let monomials = match self.expand(id, EXPANSION_LIMIT.min(self.budget)) {
                    Some(m) => m,
                    None => terms.iter().map(|&t| self.as_monomial(t)).collect(),
                };
                self.horner(monomials)
            }
            Node::Mul(fs) => {
                let parts: Vec<Id> = fs.iter().map(|&f| self.rewrite(f)).collect();
                self.arena.mul(&parts)
            }
            // A named sum is factored on its own and stays one factor of what reads it.
            Node::Named(x) => {
                let r = self.rewrite(x);
                self.arena.named(r)
            }
            _ => id,
        };
        if self.done.len() <= id.index() {
            self.done.resize(self.arena.len(), NO_ID);
        }
        self.done[id.index()] = r;
        r
    }

    /// A term kept whole: its coefficient, and its factors with their sums rewritten.
    fn as_monomial(&mut self, t: Id) -> Monomial {
        let (coef, rest) = self.arena.split_coefficient(t);
        let factors = match rest {
            None => vec![],
            Some(r) => match self.arena.node(r).clone() {
                Node::Mul(fs) => fs.iter().map(|&f| self.rewrite(f)).collect(),
                _ => vec![self.rewrite(r)],
            },
        };
        Monomial { coef, factors }
    }

    /// The monomials of `id` with products distributed over sums, like ones merged;
    /// `None` when there would be more than `limit` (or an exact coefficient overflows).
    fn expand(&mut self, id: Id, limit: usize) -> Option<Vec<Monomial>> {
        let raw = self.distribute(id, limit)?;
        self.budget = self.budget.saturating_sub(raw.len());
        // Canonical products (x * x is x^2), then like monomials merged.
        let mut merged: Vec<Monomial> = Vec::with_capacity(raw.len());
        let mut index: FxHashMap<Vec<Id>, usize> = FxHashMap::default();
        for m in raw {
            let m = self.canonical(m);
            match index.get(&m.factors) {
                Some(&k) => merged[k].coef = merged[k].coef.checked_add(m.coef)?,
                None => {
                    index.insert(m.factors.clone(), merged.len());
                    merged.push(m);
                }
            }
        }
        merged.retain(|m| !m.coef.is_zero());
        Some(merged)
    }

    fn distribute(&mut self, id: Id, limit: usize) -> Option<Vec<Monomial>> {
        match self.arena.node(id).clone() {
            Node::Num(n) => Some(vec![Monomial {
                coef: n,
                factors: vec![],
            }]),
            Node::Add(terms) => {
                let mut all = Vec::new();
                for &t in terms.iter() {
                    all.extend(self.distribute(t, limit)?);
                    if all.len() > limit {
                        return None;
                    }
                }
                Some(all)
            }
            Node::Mul(fs) => {
                let mut acc = vec![Monomial {
                    coef: Number::int(1),
                    factors: vec![],
                }];
                for &f in fs.iter() {
                    // A sum that other expressions read too is computed once anyway:
                    // distributing a product over it would compute its terms again.
                    let parts = if self.is_shared_sum(f) {
                        vec![Monomial {
                            coef: Number::int(1),
                            factors: vec![self.rewrite(f)],
                        }]
                    } else {
                        self.distribute(f, limit)?
                    };
                    if acc.len() * parts.len() > limit {
                        return None;
                    }
                    let mut next = Vec::with_capacity(acc.len() * parts.len());
                    for a in &acc {
                        for p in &parts {
                            let mut factors = a.factors.clone();
                            factors.extend_from_slice(&p.factors);
                            next.push(Monomial {
                                coef: a.coef.checked_mul(p.coef)?,
                                factors,
                            });
                        }
                    }
                    acc = next;
                }
                Some(acc)
            }
            Node::Named(_) => Some(vec![Monomial {
                coef: Number::int(1),
                factors: vec![self.rewrite(id)],
            }]),
            _ => Some(vec![Monomial {
                coef: Number::int(1),
                factors: vec![id],
            }]),
        }
    }

    /// Whether `id` is a sum read by more than one node or output entry.
    fn is_shared_sum(&self, id: Id) -> bool {
        matches!(self.arena.node(id), Node::Add(_))
            && self.readers.get(id.index()).is_some_and(|&n| n >= 2)
    }

    /// The monomial as the arena writes the product of its factors (powers collected).
    fn canonical(&mut self, m: Monomial) -> Monomial {
        if m.factors.len() < 2 {
            return m;
        }
        let p = self.arena.mul(&m.factors);
        let (c, rest) = self.arena.split_coefficient(p);
        let factors = match rest {
            None => vec![],
            Some(r) => match self.arena.node(r) {
                Node::Mul(fs) => fs.to_vec(),
                _ => vec![r],
            },
        };
        match m.coef.checked_mul(c) {
            Some(coef) => Monomial { coef, factors },
            None => m,
        }
    }

    /// The sum of `monomials`, the most frequent factor taken out while one is shared by
    /// two or more: sum = f * (the quotients) + (the rest), the quotients factored again.
    /// The counts are kept as monomials leave (`factor_counts.rs`), not made afresh per
    /// choice; the monomials left are split by the chosen factor in one pass per choice.
    fn horner(&mut self, monomials: Vec<Monomial>) -> Id {
        let mut terms: Vec<Id> = Vec::new();
        let mut left: Vec<(Monomial, Vec<(Id, Tier)>)> = monomials
            .into_iter()
            .map(|m| {
                let counted = self.counted_factors(&m);
                (m, counted)
            })
            .collect();
        let mut counts = FactorCounts::new(left.iter().map(|(_, c)| c.as_slice()));
        while left.len() > 1 {
            let Some(f) = counts.best() else {
                break;
            };
            let (with, without): (Vec<_>, Vec<_>) =
                left.into_iter().partition(|(m, _)| m.factors.contains(&f));
            let quotients: Vec<Monomial> = with
                .into_iter()
                .map(|(mut m, counted)| {
                    counts.remove(&counted);
                    let k = m.factors.iter().position(|&x| x == f);
                    if let Some(k) = k {
                        m.factors.remove(k);
                    }
                    m
                })
                .collect();
            let inner = self.horner(quotients);
            terms.push(self.arena.mul2(f, inner));
            left = without;
        }
        let monomials: Vec<Monomial> = left.into_iter().map(|(m, _)| m).collect();
        let (rest, scaled) = self.common_coefficient(monomials);
        if scaled {
            // The canonical sum would distribute the coefficient again.
            if !self.arena.is_zero(rest) {
                terms.push(rest);
            }
            return self.arena.sum_as_is(&terms);
        }
        terms.push(rest);
        self.arena.add(&terms)
    }

    /// The sum of `monomials` with no factor in common; when their coefficients are all
    /// c or -c (|c| != 1), c is taken out: c (x y + z w) is one multiplication fewer than
    /// c x y + c z w (a mass matrix entry of a chain, w (sin a sin b + cos a cos b)).
    /// Returns the sum and whether it is such a scaled sum.
    fn common_coefficient(&mut self, monomials: Vec<Monomial>) -> (Id, bool) {
        let c = monomials.first().map(|m| m.coef.abs());
        let shared = monomials.len() >= 2
            && monomials.iter().all(|m| Some(m.coef.abs()) == c)
            && c.is_some_and(|c| !c.is_one());
        match c {
            Some(c) if shared => {
                let mut terms = Vec::with_capacity(monomials.len());
                for m in &monomials {
                    let unit = if m.coef.is_negative() { -1 } else { 1 };
                    terms.push(self.product(&Monomial {
                        coef: Number::int(unit),
                        factors: m.factors.clone(),
                    }));
                }
                let sum = self.arena.add(&terms);
                (self.arena.scaled_sum(c, sum), true)
            }
            _ => {
                let terms: Vec<Id> = monomials.iter().map(|m| self.product(m)).collect();
                (self.arena.add(&terms), false)
            }
        }
    }

    fn product(&mut self, m: &Monomial) -> Id {
        let mut parts = Vec::with_capacity(m.factors.len() + 1);
        parts.push(self.arena.number(m.coef));
        parts.extend_from_slice(&m.factors);
        self.arena.mul(&parts)
    }

    /// The factors of `m` that count towards the choice of the factor to take out, each
    /// once: the one contained in the most monomials is taken out, if two or more contain
    /// it, preferring factors that are not parameter-only (ties: the smallest id, so that
    /// the result does not depend on hash order). Parameter-only values are computed once
    /// per parameter set (the cache), so a parameter-only factor is taken out only of
    /// monomials that also have a varying factor, where it saves a multiplication per call;
    /// among parameter-only monomials it would only split what the cache folds into one
    /// constant.
    fn counted_factors(&mut self, m: &Monomial) -> Vec<(Id, Tier)> {
        let fixed: Vec<bool> = m.factors.iter().map(|&f| self.is_invariant(f)).collect();
        let varies = fixed.iter().any(|i| !i);
        let mut out = Vec::with_capacity(m.factors.len());
        for (k, &f) in m.factors.iter().enumerate() {
            if m.factors[..k].contains(&f) {
                continue;
            }
            if !fixed[k] {
                out.push((f, Tier::Varying));
            } else if varies {
                out.push((f, Tier::Invariant));
            }
        }
        out
    }

    /// Whether `id` depends on parameters and constants only.
    fn is_invariant(&mut self, id: Id) -> bool {
        match self.invariant.get(id.index()) {
            Some(Known::Yes) => return true,
            Some(Known::No) => return false,
            _ => {}
        }
        let v = match self.arena.node(id) {
            Node::Num(_) | Node::Pi => true,
            &Node::Sym(s) => self.arena.symbol_info(s).kind == SymbolKind::Parameter,
            node => {
                let mut children = Vec::new();
                node.for_each_child(|c| children.push(c));
                children.into_iter().all(|c| self.is_invariant(c))
            }
        };
        if self.invariant.len() <= id.index() {
            self.invariant.resize(self.arena.len(), Known::Unknown);
        }
        self.invariant[id.index()] = if v { Known::Yes } else { Known::No };
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Program;
    use crate::algebra::eval::eval;
    use crate::algebra::expr::{Func, SymbolId};

    /// The value of `id` with symbol k set to `x[k]`.
    fn value(a: &Arena, id: Id, x: &[f64]) -> f64 {
        let env = |s: SymbolId| x.get(s.index()).copied();
        eval(a, id, &env).expect("finite")
    }

    fn factored(a: &mut Arena, e: Id) -> Id {
        factor_sums(a, &[&Matrix::column(vec![e])])[0].data[0]
    }

    /// How many nodes of the DAG under `id` are `target` (each node once).
    fn occurrences(a: &Arena, id: Id, target: Id) -> usize {
        let mut seen = vec![false; a.len()];
        let mut stack = vec![id];
        let mut n = 0;
        while let Some(i) = stack.pop() {
            if std::mem::replace(&mut seen[i.index()], true) {
                continue;
            }
            n += usize::from(i == target);
            a.node(i).for_each_child(|c| stack.push(c));
        }
        n
    }

    /// A point with distinct, generic values for every symbol.
    fn point(a: &Arena) -> Vec<f64> {
        (0..a.symbols().len())
            .map(|k| 0.3 + 0.71 * k as f64 - 0.05 * (k * k) as f64)
            .collect()
    }

    /// Row 1 of a closed chain's C q' as the derivation writes it,
    /// sum_j qd_j^2 (w_j sin th1 cos th_j - w_j cos th1 sin th_j), becomes
    /// sin th1 (...) + cos th1 (...): each of sin th1 and cos th1 read once instead of once
    /// per pair, and the value is unchanged up to rounding.
    #[test]
    fn a_chain_coriolis_row_is_factored_by_its_own_angle() {
        let mut a = Arena::new();
        let th: Vec<[Id; 3]> = (1..=5).map(|k| a.coordinate(&format!("th{k}"))).collect();
        let (s1, c1) = (a.sin(th[0][0]), a.cos(th[0][0]));
        let mut terms = vec![];
        for (j, t) in th.iter().enumerate().skip(1) {
            let (sj, cj) = (a.sin(t[0]), a.cos(t[0]));
            let w = a.rational(2 * (5 - j as i64) + 1, 2).unwrap();
            let x = a.mul(&[w, s1, cj]);
            let y = a.mul(&[w, c1, sj]);
            let pair = a.sub(x, y);
            let qd2 = a.powi(t[1], 2).unwrap();
            terms.push(a.mul(&[qd2, pair]));
        }
        let e = a.add(&terms);
        assert_eq!(occurrences(&a, e, s1), 1);
        let before = terms.len();
        let f = factored(&mut a, e);
        let Node::Add(top) = a.node(f).clone() else {
            panic!("a sum of two products: {:?}", a.node(f))
        };
        assert_eq!(
            top.len(),
            2,
            "sin th1 (...) + cos th1 (...), was {before} terms"
        );
        for (t, want) in top.iter().zip([s1, c1]) {
            let Node::Mul(fs) = a.node(*t) else {
                panic!("a product")
            };
            assert!(fs.contains(&want), "{:?}", a.node(*t));
        }
        let x = point(&a);
        let (v0, v1) = (value(&a, e, &x), value(&a, f, &x));
        // At this point the eight terms' magnitudes sum to about 54 (w <= 9/2, qd^2 <= 8).
        // Each form rounds a term at most 10 times (3 products, 7 additions), so the two
        // differ by at most 20 eps x 54 to first order; 640 eps is inside that worst case,
        // and a wrong factor would be off by order 1.
        assert!(
            (v0 - v1).abs() <= 64.0 * f64::EPSILON * 10.0,
            "{v0} vs {v1}"
        );
    }

    /// 5/2 sin a sin b + 5/2 cos a cos b, a mass-matrix entry of a chain, is written as
    /// 5/2 (sin a sin b + cos a cos b): one multiplication fewer.
    #[test]
    fn a_shared_coefficient_is_taken_out() {
        let mut a = Arena::new();
        let [p, ..] = a.coordinate("a");
        let [q, ..] = a.coordinate("b");
        let (sa, ca, sb, cb) = (a.sin(p), a.cos(p), a.sin(q), a.cos(q));
        let k = a.rational(5, 2).unwrap();
        let x = a.mul(&[k, sa, sb]);
        let y = a.mul(&[k, ca, cb]);
        let e = a.add2(x, y);
        let f = factored(&mut a, e);
        let Node::Mul(fs) = a.node(f).clone() else {
            panic!("a product: {:?}", a.node(f))
        };
        assert_eq!(a.as_number(fs[0]), Number::rational(5, 2));
        assert!(matches!(a.node(fs[1]), Node::Add(ts) if ts.len() == 2));
        let x = point(&a);
        // |5/2 sin a sin b| + |5/2 cos a cos b| <= 5; each form rounds at most 3 times.
        assert!((value(&a, e, &x) - value(&a, f, &x)).abs() <= 4.0 * f64::EPSILON * 5.0);
    }

    /// Parameter-only factors stay with the coefficients where the cache folds them
    /// (J qd^2 + m l^2 qd^2 = qd^2 (J + m l^2), not J qd^2 + m (l^2 qd^2)), and are taken
    /// out of monomials that vary (l u^2 + l v^2 = l (u^2 + v^2)), never out of
    /// parameter-only ones (J m + J l stays).
    #[test]
    fn parameter_factors_stay_with_the_coefficients() {
        let mut a = Arena::new();
        let [_, qd, _] = a.coordinate("q");
        let [_, u, _] = a.coordinate("u");
        let [_, v, _] = a.coordinate("v");
        let [j, m, l] = ["J", "m", "l"].map(|n| a.symbol(n, SymbolKind::Parameter));
        let qd2 = a.powi(qd, 2).unwrap();
        let l2 = a.powi(l, 2).unwrap();
        let t1 = a.mul(&[j, qd2]);
        let t2 = a.mul(&[m, l2, qd2]);
        let kinetic = a.add2(t1, t2);
        let f = factored(&mut a, kinetic);
        let Node::Mul(fs) = a.node(f).clone() else {
            panic!("qd^2 (J + m l^2): {:?}", a.node(f))
        };
        assert!(fs.contains(&qd2) && fs.len() == 2);

        let (u2, v2) = (a.powi(u, 2).unwrap(), a.powi(v, 2).unwrap());
        let t1 = a.mul(&[l, u2]);
        let t2 = a.mul(&[l, v2]);
        let e = a.add2(t1, t2);
        let f = factored(&mut a, e);
        assert_eq!(occurrences(&a, f, l), 1);
        assert!(matches!(a.node(f), Node::Mul(fs) if fs.contains(&l)));

        let t1 = a.mul(&[j, m]);
        let t2 = a.mul(&[j, l]);
        let e = a.add2(t1, t2);
        assert_eq!(factored(&mut a, e), e);
    }

    /// A product of two 50-term sums would expand into 2500 > EXPANSION_LIMIT monomials:
    /// it stays a product, and its factors keep their own form.
    #[test]
    fn a_sum_beyond_the_expansion_limit_stays_as_it_is() {
        let mut a = Arena::new();
        let mut sums = vec![];
        for name in ["x", "y"] {
            let terms: Vec<Id> = (0..50)
                .map(|k| {
                    let [q, ..] = a.coordinate(&format!("{name}{k}"));
                    a.func(Func::Sin, q).unwrap()
                })
                .collect();
            sums.push(a.add(&terms));
        }
        const { assert!(50 * 50 > EXPANSION_LIMIT) };
        let z = a.symbol("z", SymbolKind::Coordinate);
        let p = a.mul(&[sums[0], sums[1]]);
        let e = a.add2(p, z);
        let f = factored(&mut a, e);
        assert_eq!(f, e);
    }

    /// A product is not distributed over a sum that another expression reads too:
    /// S (u + v) and S (u + w) with S = x + y + z keep S as a factor (expanded, u S would be
    /// x u + y u + z u, the sum's work done again in every product).
    #[test]
    fn products_are_not_distributed_over_shared_sums() {
        let mut a = Arena::new();
        let [x, y, z, u, v, w] =
            ["x", "y", "z", "u", "v", "w"].map(|n| a.symbol(n, SymbolKind::Coordinate));
        let s = a.add(&[x, y, z]);
        let t1 = a.add2(u, v);
        let t2 = a.add2(u, w);
        let p1 = a.mul2(s, t1);
        let p2 = a.mul2(s, t2);
        let e1 = a.add2(p1, x);
        let e2 = a.add2(p2, y);
        let out = factor_sums(&mut a, &[&Matrix::column(vec![e1, e2])]);
        for (&f, &e) in out[0].data.iter().zip(&[e1, e2]) {
            assert_eq!(occurrences(&a, f, s), 1, "{:?}", a.node(f));
            let pt = point(&a);
            assert!((value(&a, e, &pt) - value(&a, f, &pt)).abs() <= 1e-13);
        }
    }

    /// The greedy factoring can lose: in the A02 N four-bar's Phi_q (N = 40), expanding the
    /// products of shared sums costs more than the factors save. `Program::new` keeps the
    /// derived one there.
    #[test]
    fn the_derived_form_is_kept_where_factoring_costs_more() {
        let source = include_str!("../../../mechanisms/n_four_bar.mech");
        let mut model = crate::parse_model_str(source).expect("parses");
        let eqs = crate::derive(&mut model).expect("derived");
        let a = &model.arena;
        let plain = crate::compile::passes::lower(a, &[&eqs.phi_q]).expect("program");
        let (local, f, _) = factored_copy(a, &[&eqs.phi_q]);
        let factored = crate::compile::passes::lower(&local, &[&f[0]]).expect("program");
        assert!(
            factored.ops_per_call(a) > plain.ops_per_call(a),
            "{} vs {}",
            factored.ops_per_call(a),
            plain.ops_per_call(a)
        );
        assert_eq!(Program::new(a, &[&eqs.phi_q]).expect("program"), plain);
    }

    /// A constant that overflows while factoring never reaches a program: x^E (x^E + y) +
    /// x^E (x^E + z) with E = 1e308 expands to 2 x^(2E) + ..., whose exponent overflows
    /// and folds to 0 (x^0 = 1: wrong at x = 0). That form would be the shorter one;
    /// `Program::new` keeps the derived program.
    #[test]
    fn an_overflow_while_factoring_keeps_the_derived_form() {
        let mut a = Arena::new();
        let [x, y, z] = ["x", "y", "z"].map(|n| a.symbol(n, SymbolKind::Coordinate));
        let big = a.float(1e308).unwrap();
        let p = a.pow(x, big).unwrap();
        let s1 = a.add2(p, y);
        let s2 = a.add2(p, z);
        let t1 = a.mul2(p, s1);
        let t2 = a.mul2(p, s2);
        let e = a.add2(t1, t2);
        let m = Matrix::column(vec![e]);
        let (mut local, f, _) = factored_copy(&a, &[&m]);
        assert!(local.take_overflow().is_some());
        let factored = crate::compile::passes::lower(&local, &[&f[0]]).expect("program");
        let plain = crate::compile::passes::lower(&a, &[&m]).expect("program");
        assert!(factored.ops_per_call(&a) < plain.ops_per_call(&a));
        assert_eq!(Program::new(&a, &[&m]).expect("program"), plain);
    }

    /// The copy of what the roots reach evaluates as the original, with the symbols in
    /// place, and holds no unreachable node.
    #[test]
    fn the_reachable_copy_evaluates_as_the_original() {
        let mut a = Arena::new();
        let [q, qd, _] = a.coordinate("q");
        let unused = a.symbol("unused", SymbolKind::Parameter);
        let s = a.sin(q);
        let _dead = a.mul(&[s, unused, qd]);
        let e = a.mul(&[s, qd]);
        let (b, roots) = a.reachable(&[e]);
        let x = point(&a);
        assert_eq!(
            value(&a, e, &x).to_bits(),
            value(&b, roots[0], &x).to_bits()
        );
        assert_eq!(b.symbols().len(), a.symbols().len());
        assert_eq!(
            b.len(),
            a.symbols().len() + 2,
            "the symbols, sin q and the product"
        );
    }
}
