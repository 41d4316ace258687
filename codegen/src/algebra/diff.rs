//! Symbolic differentiation: partial derivatives memoised per (node, symbol), and the total
//! time derivative by Van Khang's Theorem 1.
//!
//! Every derivative is built with the arena's canonical constructors, so like terms of a
//! derivative collect (and cancel) as it is formed. A per-node dependency set
//! (`algebra::dependencies`) tells in O(log k) whether a subexpression depends on a symbol at
//! all; independent subtrees are never visited, which keeps the cost of d/dq_k of a big
//! expression proportional to the part that mentions q_k. The terms of a wide sum or product
//! that depend on the symbol come from an index of its children by symbol
//! (`algebra::wide_children`) once it is differentiated a second time, instead of one look-up
//! per term.
//!
//! The walk is iterative (the nodes to differentiate are collected, then processed in
//! increasing id order, which is topological), so deep expressions cannot overflow the stack.

use crate::algebra::dependencies::DependencySets;
use crate::algebra::expr::{Arena, Func, Id, Node, Short, SymbolId, SymbolKind};
use crate::algebra::memo_table::MemoTable;
use crate::algebra::visit_marks::VisitMarks;
use crate::algebra::wide_children::WideChildren;
use crate::error::AlgebraError;
use crate::error::{Error, Result};
use crate::number::Number;

/// A memoising differentiator for one [`Arena`].
///
/// `diff(e, s)` is the partial derivative de/ds; results are cached per (node, symbol), so
/// differentiating many expressions that share subexpressions (the entries of a matrix)
/// differentiates each shared node once. Use one `Differentiator` per arena (the arena may
/// grow between calls; a differentiator handed a different arena may give wrong results).
///
/// # Example
/// ```
/// use mechanism_codegen::{Arena, Differentiator, SymbolKind};
/// let mut a = Arena::new();
/// let x = a.symbol("x", SymbolKind::Free);
/// let sx = a.lookup("x").unwrap();
/// let e = a.sin(x);
/// let mut d = Differentiator::new();
/// let de = d.diff(&mut a, e, sx).unwrap();
/// assert_eq!(de, a.cos(x)); // d sin(x)/dx = cos(x)
/// ```
#[derive(Clone, Debug, Default)]
pub struct Differentiator {
    memo: MemoTable,
    deps: DependencySets,
    wide: WideChildren,
    /// Scratch for the positions of a node's dependent children.
    positions: Vec<u32>,
    /// Scratch of [`Differentiator::diff`]'s walk (the nodes to differentiate, the nodes
    /// still to visit, and which were visited), kept between calls: a matrix's derivative
    /// is many calls, each of a few nodes.
    todo: Vec<Id>,
    stack: Vec<Id>,
    visited: VisitMarks,
}

impl Differentiator {
    /// A differentiator with an empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// Brings the dependency sets up to date. An arena with fewer nodes than seen before is
    /// not the arena this differentiator was used with: the caches are dropped rather than
    /// hand out ids that do not exist there.
    /// Brings the dependency sets up to `id` (the nodes a query about `id` reads), or
    /// starts them afresh for an arena shorter than they cover (another arena).
    fn sync(&mut self, arena: &Arena, id: Id) {
        if arena.len() < self.deps.covered() {
            self.memo.clear();
            self.deps = DependencySets::default();
            self.wide.clear();
        }
        self.deps.sync_to(arena, id.index() + 1);
    }

    fn check(arena: &Arena, id: Id) -> Result<()> {
        if id.index() < arena.len() {
            Ok(())
        } else {
            Err(Error::Algebra(AlgebraError::InvalidId {
                id: id.0,
                len: arena.len(),
            }))
        }
    }

    fn check_symbol(arena: &Arena, s: SymbolId) -> Result<()> {
        if (s.0 as usize) < arena.symbols().len() {
            Ok(())
        } else {
            Err(Error::Algebra(AlgebraError::UnknownSymbolId {
                id: s.0,
                symbols: arena.symbols().len(),
            }))
        }
    }

    /// Whether the expression `id` depends on the symbol `s` (O(1) after the first query on
    /// a grown arena).
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::InvalidId`] when `id` is not in `arena`.
    pub fn depends_on(&mut self, arena: &Arena, id: Id, s: SymbolId) -> Result<bool> {
        Self::check(arena, id)?;
        self.sync(arena, id);
        Ok(self.deps.contains(id, s))
    }

    /// Whether `id` depends on a symbol marked in `marked` (indexed by
    /// [`SymbolId::index`]; a symbol past its end is unmarked): one pass over the node's
    /// own set, not a search per marked symbol.
    ///
    /// # Errors
    /// [`Error::InvalidId`] when `id` is not in `arena`.
    pub(crate) fn depends_on_any(
        &mut self,
        arena: &Arena,
        id: Id,
        marked: &[bool],
    ) -> Result<bool> {
        Self::check(arena, id)?;
        self.sync(arena, id);
        Ok(self
            .deps
            .set(id)
            .iter()
            .any(|s| marked.get(s.index()).copied().unwrap_or(false)))
    }

    /// The symbols the expression `id` depends on, in increasing [`SymbolId`] order.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::InvalidId`] when `id` is not in `arena`.
    pub fn symbols_of(&mut self, arena: &Arena, id: Id) -> Result<Vec<SymbolId>> {
        Self::check(arena, id)?;
        self.sync(arena, id);
        Ok(self.deps.symbols(id))
    }

    /// The partial derivative d(id)/d(sym), every other symbol held constant.
    ///
    /// Rules: sums term by term; products by the n-ary product rule
    /// d(f_1 ... f_k) = sum_i f_1 .. df_i .. f_k; u^c = c u^(c-1) u' for c free of `sym`;
    /// c^v = c^v ln(c) v'; u^v = u^v (v' ln u + v u'/u); sin, cos, tan' = 1 + tan^2,
    /// exp, ln' = u'/u, |u|' = u/|u| u'; atan2(y, x)' = (x y' - y x')/(x^2 + y^2).
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::InvalidId`] or
    /// [`crate::error::AlgebraError::UnknownSymbolId`] for an id or symbol not in `arena`;
    /// [`crate::error::AlgebraError::Domain`] for d(c^v) with a constant base c <= 0 (ln c
    /// undefined); [`crate::error::BudgetError::Size`] once the arena is beyond its budget.
    pub fn diff(&mut self, arena: &mut Arena, id: Id, sym: SymbolId) -> Result<Id> {
        Self::check(arena, id)?;
        Self::check_symbol(arena, sym)?;
        // Every derivation goes through here: the budget stops a runaway one within one
        // derivative's growth of the limit.
        arena.check_budget()?;
        self.sync(arena, id);
        if !self.deps.contains(id, sym) {
            return Ok(arena.int(0));
        }
        if let Some(d) = self.memo.get(id, sym) {
            return Ok(d);
        }
        // Collect the nodes below `id` that depend on `sym` and are not cached yet.
        let mut todo = std::mem::take(&mut self.todo);
        let mut stack = std::mem::take(&mut self.stack);
        todo.clear();
        stack.clear();
        stack.push(id);
        self.visited.start();
        while let Some(n) = stack.pop() {
            if !self.visited.first_visit(n.index()) || self.memo.get(n, sym).is_some() {
                continue;
            }
            todo.push(n);
            let children = arena.child_list(n);
            self.dependent_children(n, &children, sym);
            stack.extend(self.positions.iter().map(|&k| children[k as usize]));
        }
        todo.sort_unstable();
        self.stack = stack;
        for &n in &todo {
            let d = self.rule(arena, n, sym)?;
            self.memo.insert(n, sym, d);
        }
        self.todo = todo;
        self.memo
            .get(id, sym)
            .ok_or(Error::Algebra(AlgebraError::InvalidId {
                id: id.0,
                len: arena.len(),
            }))
    }

    /// The positions of `node`'s children (`children`) that depend on `sym`, in increasing
    /// order, into `self.positions`.
    fn dependent_children(&mut self, node: Id, children: &[Id], sym: SymbolId) {
        let mut out = std::mem::take(&mut self.positions);
        self.wide
            .positions(&self.deps, node, children, sym, &mut out);
        self.positions = out;
    }

    /// The cached derivative of a child (0 when it does not depend on `sym`).
    fn child(&self, arena: &mut Arena, c: Id, sym: SymbolId) -> Id {
        if !self.deps.contains(c, sym) {
            return arena.int(0);
        }
        match self.memo.get(c, sym) {
            Some(d) => d,
            None => arena.int(0), // unreachable: children are processed first
        }
    }

    /// One differentiation rule, the children's derivatives being cached.
    fn rule(&mut self, arena: &mut Arena, n: Id, sym: SymbolId) -> Result<Id> {
        let node = match arena.node(n) {
            Node::Add(ts) => {
                // Only the terms that depend on `sym`: the others' derivatives are zeros the
                // sum would drop (a row of a large residual reads each coordinate in a few
                // of its terms). Only they are copied out, not the whole sum: a kinetic
                // energy of n^2 terms differentiated by each of n rates would copy n^3 ids.
                self.dependent_children(n, ts, sym);
                Node::Add(self.positions.iter().map(|&k| ts[k as usize]).collect())
            }
            other => other.clone(),
        };
        Ok(match node {
            Node::Num(_) | Node::Pi => arena.int(0),
            Node::Sym(s) => arena.int(i64::from(s == sym)),
            Node::Add(dependent) => {
                let ds: Short<Id> = dependent
                    .iter()
                    .map(|&t| self.child(arena, t, sym))
                    .collect();
                arena.add(&ds)
            }
            Node::Mul(fs) => {
                let mut terms: Short<Id> = Short::new();
                self.dependent_children(n, &fs, sym);
                for i in std::mem::take(&mut self.positions) {
                    let (i, f) = (i as usize, fs[i as usize]);
                    let df = self.child(arena, f, sym);
                    if arena.is_zero(df) {
                        continue;
                    }
                    let mut factors: Short<Id> = Short::with_capacity(fs.len());
                    factors.extend(
                        fs.iter()
                            .enumerate()
                            .filter(|&(j, _)| j != i)
                            .map(|(_, &g)| g),
                    );
                    factors.push(df);
                    terms.push(arena.mul(&factors));
                }
                arena.add(&terms)
            }
            Node::Pow(b, e) => self.pow_rule(arena, n, b, e, sym)?,
            Node::Func(f, u) => {
                let du = self.child(arena, u, sym);
                let outer = match f {
                    Func::Sin => arena.cos(u),
                    Func::Cos => {
                        let s = arena.sin(u);
                        arena.neg(s)
                    }
                    Func::Tan => {
                        let one = arena.int(1);
                        let t2 = arena.powi(n, 2)?;
                        arena.add2(one, t2)
                    }
                    Func::Exp => n,
                    Func::Ln => arena.powi(u, -1)?,
                    Func::Abs => {
                        let inv = arena.powi(n, -1)?;
                        arena.mul2(u, inv)
                    }
                };
                arena.mul2(outer, du)
            }
            // d(named x) = named dx: a recursion's named steps keep named derivatives.
            Node::Named(x) => {
                let dx = self.child(arena, x, sym);
                arena.named(dx)
            }
            Node::Atan2(y, x) => {
                let dy = self.child(arena, y, sym);
                let dx = self.child(arena, x, sym);
                let a = arena.mul2(x, dy);
                let b = arena.mul2(y, dx);
                let num = arena.sub(a, b);
                let x2 = arena.powi(x, 2)?;
                let y2 = arena.powi(y, 2)?;
                let den = arena.add2(x2, y2);
                arena.div(num, den)?
            }
        })
    }

    /// d(b^e)/d(sym) for the node `n` = b^e.
    fn pow_rule(&mut self, arena: &mut Arena, n: Id, b: Id, e: Id, sym: SymbolId) -> Result<Id> {
        let db = self.child(arena, b, sym);
        if !self.deps.contains(e, sym) {
            // e u^(e-1) u'
            let em1 = match arena.as_number(e) {
                Some(k) => {
                    let km1 = arena.fold_add(k, Number::int(-1));
                    arena.number(km1)
                }
                None => {
                    let m1 = arena.int(-1);
                    arena.add2(e, m1)
                }
            };
            let p = arena.pow(b, em1)?;
            return Ok(arena.mul(&[e, p, db]));
        }
        let de = self.child(arena, e, sym);
        let ln_b = arena.func(Func::Ln, b)?;
        if !self.deps.contains(b, sym) {
            // b^e ln(b) e'
            return Ok(arena.mul(&[n, ln_b, de]));
        }
        // b^e (e' ln b + e b'/b)
        let t1 = arena.mul2(de, ln_b);
        let inv_b = arena.powi(b, -1)?;
        let t2 = arena.mul(&[e, db, inv_b]);
        let inner = arena.add2(t1, t2);
        Ok(arena.mul2(n, inner))
    }

    /// The gradient [d(id)/d(x_1), ..., d(id)/d(x_n)].
    ///
    /// # Errors
    /// As [`Differentiator::diff`].
    pub fn gradient(&mut self, arena: &mut Arena, id: Id, x: &[SymbolId]) -> Result<Vec<Id>> {
        x.iter().map(|&s| self.diff(arena, id, s)).collect()
    }

    /// The total time derivative by Theorem 1 (Van Khang 2010):
    /// de/dt = sum_i (de/dq_i q_i' + de/dq_i' q_i'') + de/dt, i.e. each symbol with a
    /// `derivative` link contributes (de/ds) s', time contributes the explicit de/dt, and
    /// parameters and unlinked free symbols are constants.
    ///
    /// # Errors
    /// As [`Differentiator::diff`]; [`crate::error::AlgebraError::ThirdDerivative`] when `id`
    /// depends on an acceleration (its time derivative, a third derivative, is not a symbol of
    /// the language).
    pub fn time_derivative(&mut self, arena: &mut Arena, id: Id) -> Result<Id> {
        self.time_derivative_impl(arena, id, true)
    }

    /// The time derivative with the accelerations set to zero afterwards:
    /// sum_i de/dq_i q_i' + de/dt, the q'' terms of [`Differentiator::time_derivative`]
    /// dropped (the "convective" part, e.g. d/dt(Phi_q q') at q'' = 0 in gamma).
    ///
    /// # Errors
    /// As [`Differentiator::time_derivative`].
    pub fn convective_derivative(&mut self, arena: &mut Arena, id: Id) -> Result<Id> {
        self.time_derivative_impl(arena, id, false)
    }

    fn time_derivative_impl(
        &mut self,
        arena: &mut Arena,
        id: Id,
        with_acceleration: bool,
    ) -> Result<Id> {
        Self::check(arena, id)?;
        self.sync(arena, id);
        let mut terms = Vec::new();
        for s in self.deps.symbols(id) {
            let info = arena.symbol_info(s).clone();
            match (info.kind, info.derivative) {
                (SymbolKind::Time, _) => terms.push(self.diff(arena, id, s)?),
                (SymbolKind::Acceleration, None) => {
                    return Err(Error::Algebra(AlgebraError::ThirdDerivative {
                        name: info.name.clone(),
                    }));
                }
                (_, Some(sd)) => {
                    if !with_acceleration && arena.symbol_info(sd).kind == SymbolKind::Acceleration
                    {
                        continue;
                    }
                    let d = self.diff(arena, id, s)?;
                    let rate = arena.symbol_node(sd);
                    terms.push(arena.mul2(d, rate));
                }
                _ => {}
            }
        }
        Ok(arena.add(&terms))
    }
}
