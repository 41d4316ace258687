//! The shared skeleton of the text and LaTeX printers.
//!
//! A node is rendered from its children's renderings, bottom-up over the reachable sub-DAG in
//! id order (children first), so printing needs no recursion and each shared node is rendered
//! once. The skeleton decides the layout that makes expressions readable:
//! - a sum prints its positive terms first, then the negative ones after ` - `, the constant
//!   last in its group;
//! - a product prints its numeric coefficient first; factors with a negative exponent
//!   (`x^-1`, `x^(-1/2)`, `x^(-k*y)`) and the coefficient's denominator go below a fraction
//!   bar;
//! - `x^(1/2)` prints as a square root.
//!
//! A [`Style`] supplies the spelling (plain text or LaTeX).

use crate::algebra::expr::{Arena, Func, FxHashMap, Id, Node, SymbolKind};
use crate::number::Number;
use std::borrow::Cow;

/// How tightly a rendering binds, loosest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Prec {
    /// A sum, or anything with a leading minus.
    Sum,
    /// A product or quotient.
    Product,
    /// A power.
    Power,
    /// A number, name, call or bracketed group.
    Atom,
}

/// A rendered subexpression.
#[derive(Clone, Debug)]
pub(crate) struct Rendered {
    /// The text.
    pub(crate) s: String,
    /// How tightly it binds.
    pub(crate) prec: Prec,
    /// For a function application f(x): the function's spelling and the bracketed argument
    /// (LaTeX writes a power of it as `\sin^{2}{\left(x\right)}`). Boxed: the renderer holds
    /// one rendering per node, and most have none.
    pub(crate) head: Option<Box<(String, String)>>,
}

impl Rendered {
    /// A rendering without a function head.
    pub(crate) fn new(s: String, prec: Prec) -> Self {
        Self {
            s,
            prec,
            head: None,
        }
    }
}

/// The spelling of a printer.
pub(crate) trait Style {
    /// A non-negative constant.
    fn number(&self, n: Number) -> Rendered;
    /// The constant pi.
    fn pi(&self) -> Rendered;
    /// A symbol.
    fn symbol(&self, name: &str, kind: SymbolKind) -> Rendered;
    /// f(x).
    fn func(&self, f: Func, x: &Rendered) -> Rendered;
    /// atan2(y, x).
    fn atan2(&self, y: &Rendered, x: &Rendered) -> Rendered;
    /// sqrt(x).
    fn sqrt(&self, x: &Rendered) -> Rendered;
    /// base^exp (the style parenthesises as needed).
    fn power(&self, base: &Rendered, exp: &Rendered) -> Rendered;
    /// num_1 * num_2 ... / (den_1 * den_2 ...); all parts are positive. The parts are
    /// mostly the memo's own renderings of the factors, borrowed (a copy of each factor's
    /// text per product would copy the text of every level of an expression once more).
    fn product(&self, num: &[Cow<'_, Rendered>], den: &[Cow<'_, Rendered>]) -> Rendered;
    /// x in brackets.
    fn paren(&self, s: &str) -> String;
}

/// The parts written one after the other into a string of exactly their length: the
/// printers make one string per rendered node, and `format!`'s machinery cost more than
/// the copying itself.
pub(crate) fn concat(parts: &[&str]) -> String {
    let mut s = String::with_capacity(parts.iter().map(|p| p.len()).sum());
    for p in parts {
        s.push_str(p);
    }
    s
}

/// An exponent as the renderer sees it: a plain number, or an expression's rendering.
enum Exp<'r> {
    Num(Number),
    Expr(Cow<'r, Rendered>),
}

/// The bottom-up renderer with its memo of rendered nodes.
pub(crate) struct Renderer<'a, S: Style> {
    arena: &'a Arena,
    style: S,
    /// Per node id: 0 when not rendered, [`PENDING`] while a render collects it, k + 1 when
    /// its rendering is `rendered[k]`.
    slots: Slots,
    /// The renderings, in the order they were made.
    rendered: Vec<Rendered>,
    /// What an id without a rendering prints as.
    unknown: Rendered,
    /// What [`Renderer::render`] returns that is not in the memo: an invalid id's text,
    /// or [`ELIDED`].
    scratch: Rendered,
    /// The nodes one render still has to render, and its walk's stack (kept for reuse).
    todo: Vec<Id>,
    stack: Vec<Id>,
    /// Bytes of text held in `rendered`.
    held: usize,
    /// Whether a subexpression was too long to print (see [`MAX_TEXT_BYTES`]).
    pub(crate) elided: bool,
}

/// The slot of a node collected by the render under way (see `Renderer::slots`).
const PENDING: u32 = u32::MAX;

/// A renderer's slot per node id, 0 for a node without one.
enum Slots {
    /// Indexed by id, every node of the arena: for whole equations.
    Table(Vec<u32>),
    /// Only the nodes given a slot: for single expressions of a possibly large arena.
    Map(FxHashMap<Id, u32>),
}

impl Slots {
    fn get(&self, id: Id) -> u32 {
        match self {
            Slots::Table(t) => t.get(id.index()).copied().unwrap_or(0),
            Slots::Map(m) => m.get(&id).copied().unwrap_or(0),
        }
    }

    /// Sets the slot of `id`, a node of the renderer's arena (the table covers them all).
    fn set(&mut self, id: Id, slot: u32) {
        match self {
            Slots::Table(t) => {
                if let Some(s) = t.get_mut(id.index()) {
                    *s = slot;
                }
            }
            Slots::Map(m) => {
                m.insert(id, slot);
            }
        }
    }
}

/// The text the printers hold at most (64 MiB). A tree printed from a DAG repeats every
/// shared subexpression at each use, so its text can grow exponentially with the size of
/// the equations (a body turned by 16 chained rotations: 36,000 nodes, 1.5 GB of text). Past
/// this budget every further subexpression prints as [`ELIDED`]; the largest equations of
/// the benchmarks (the 32-bar chain) print in 0.4 MB.
pub const MAX_TEXT_BYTES: usize = 64 << 20;

/// What a subexpression prints as once the text budget is spent.
pub const ELIDED: &str = "<...>";

/// The note the equation printers end with when they elided subexpressions.
pub(crate) fn elided_note() -> String {
    format!(
        "the equations are too long to print in full: written out as trees they repeat every shared subexpression, and past {} MiB of text the rest print as {ELIDED}; the generated code computes each subexpression once and is complete",
        MAX_TEXT_BYTES >> 20
    )
}

impl<'a, S: Style> Renderer<'a, S> {
    /// A renderer over `arena`, for a few expressions (see [`Renderer::for_equations`]).
    pub(crate) fn new(arena: &'a Arena, style: S) -> Self {
        Self {
            arena,
            style,
            slots: Slots::Map(FxHashMap::default()),
            rendered: Vec::new(),
            unknown: Rendered::new(String::from("?"), Prec::Atom),
            scratch: Rendered::new(String::new(), Prec::Atom),
            todo: Vec::new(),
            stack: Vec::new(),
            held: 0,
            elided: false,
        }
    }

    /// A renderer for the equations of a whole model, which reach most of `arena`: its
    /// slots are a table indexed by node id (4 bytes per node of the arena, made once)
    /// instead of [`Renderer::new`]'s map, which costs nothing to make and holds only the
    /// nodes one expression reaches.
    pub(crate) fn for_equations(arena: &'a Arena, style: S) -> Self {
        Self {
            slots: Slots::Table(vec![0; arena.len()]),
            ..Self::new(arena, style)
        }
    }

    /// The rendering of `id` (`<invalid id N>` when `id` is not a node of the arena),
    /// borrowed from the memo: printing it writes it out without a copy.
    pub(crate) fn render(&mut self, id: Id) -> &Rendered {
        if id.index() >= self.arena.len() {
            self.scratch = Rendered::new(format!("<invalid id {}>", id.0), Prec::Atom);
            return &self.scratch;
        }
        if self.held > MAX_TEXT_BYTES && !self.is_rendered(id) {
            // Past the budget every node not rendered yet prints as ELIDED, this one too:
            // its subexpressions need not be collected (a large mechanism's last entries).
            self.elided = true;
            self.scratch = Rendered::new(ELIDED.to_string(), Prec::Atom);
            return &self.scratch;
        }
        let (mut todo, mut stack) = (
            std::mem::take(&mut self.todo),
            std::mem::take(&mut self.stack),
        );
        stack.push(id);
        while let Some(n) = stack.pop() {
            if self.slots.get(n) != 0 {
                continue; // rendered, or already collected
            }
            self.slots.set(n, PENDING);
            todo.push(n);
            self.arena.node(n).for_each_child(|c| stack.push(c));
        }
        // Children have smaller ids than their parents: in id order, each node's children
        // are rendered before it.
        todo.sort_unstable();
        for &n in &todo {
            let r = if self.held > MAX_TEXT_BYTES {
                self.elided = true;
                Rendered::new(ELIDED.to_string(), Prec::Atom)
            } else {
                self.node(n)
            };
            self.held += r.s.len();
            self.keep(n, r);
        }
        todo.clear();
        (self.todo, self.stack) = (todo, stack);
        self.get(id)
    }

    /// From now on `id` prints as `name` (a shared subexpression defined once, above the
    /// equations that use it).
    pub(crate) fn name(&mut self, id: Id, name: String) {
        if id.index() < self.arena.len() {
            self.keep(id, Rendered::new(name, Prec::Atom));
        }
    }

    /// True when `id` is a node of the arena and the constant 0.
    pub(crate) fn is_zero(&self, id: Id) -> bool {
        id.index() < self.arena.len() && self.arena.is_zero(id)
    }

    /// Records `r` as the rendering of `id` (a node of the arena).
    fn keep(&mut self, id: Id, r: Rendered) {
        self.rendered.push(r);
        // At most one rendering per node and one per name, so fewer than PENDING: the
        // arena's ids are 32-bit and its size budget keeps it far below 2^31 nodes.
        self.slots.set(id, self.rendered.len() as u32);
    }

    /// Whether `id` has a rendering (or a name).
    fn is_rendered(&self, id: Id) -> bool {
        !matches!(self.slots.get(id), 0 | PENDING)
    }

    fn get(&self, id: Id) -> &Rendered {
        match self.slots.get(id) {
            0 | PENDING => &self.unknown,
            k => &self.rendered[k as usize - 1],
        }
    }

    fn node(&self, id: Id) -> Rendered {
        match self.arena.node(id) {
            Node::Num(n) => self.signed_number(*n),
            Node::Pi => self.style.pi(),
            Node::Sym(s) => {
                let info = self.arena.symbol_info(*s);
                self.style.symbol(&info.name, info.kind)
            }
            Node::Func(f, x) => self.style.func(*f, self.get(*x)),
            Node::Atan2(y, x) => self.style.atan2(self.get(*y), self.get(*x)),
            Node::Pow(..) => self.product(Number::int(1), &[id]),
            Node::Mul(fs) => match self.arena.as_number(fs[0]) {
                Some(c) if c.is_negative() => self.negate(self.product(-c, &fs[1..])),
                Some(c) => self.product(c, &fs[1..]),
                None => self.product(Number::int(1), fs),
            },
            Node::Add(ts) => self.sum(ts),
            Node::Named(x) => self.get(*x).clone(),
        }
    }

    fn signed_number(&self, n: Number) -> Rendered {
        if n.is_negative() {
            self.negate(self.style.number(-n))
        } else {
            self.style.number(n)
        }
    }

    fn negate(&self, x: Rendered) -> Rendered {
        let body = if x.prec == Prec::Sum {
            self.style.paren(&x.s)
        } else {
            x.s
        };
        // A unary minus binds to the first factor only, and the arena distributes -1 over a
        // sum: `-(a + b)*c` would read back as (-a - b)*c. `-1*(a + b)*c` reads back as written.
        if body.starts_with('(') {
            return Rendered::new(concat(&["-1*", &body]), Prec::Sum);
        }
        Rendered::new(concat(&["-", &body]), Prec::Sum)
    }

    /// -t for a term t in negative form (a negative constant, or a product with a negative
    /// coefficient); `None` for other terms.
    fn negated(&self, t: Id) -> Option<Rendered> {
        match self.arena.node(t) {
            Node::Num(n) if n.is_negative() => Some(self.style.number(-*n)),
            Node::Mul(fs) => match self.arena.as_number(fs[0]) {
                // `a - 1.0*x` would read back as a - x (a rational -1): keep -1.0 with its term.
                Some(c) if c.is_float() && (-c).is_one() => None,
                Some(c) if c.is_negative() => Some(self.product(-c, &fs[1..])),
                _ => None,
            },
            _ => None,
        }
    }

    fn sum(&self, ts: &[Id]) -> Rendered {
        let is_const = |t: &Id| self.arena.as_number(*t).is_some();
        let mut pos: Vec<&Rendered> = Vec::new();
        let mut neg: Vec<Rendered> = Vec::new();
        // Non-constant terms first, the constant last within its sign group.
        for &t in ts
            .iter()
            .filter(|t| !is_const(t))
            .chain(ts.iter().filter(|t| is_const(t)))
        {
            match self.negated(t) {
                Some(r) => neg.push(r),
                None => pos.push(self.get(t)),
            }
        }
        let wrap = |s: &mut String, r: &Rendered| {
            if r.prec == Prec::Sum {
                s.push_str(&self.style.paren(&r.s));
            } else {
                s.push_str(&r.s);
            }
        };
        // Each term with its separator and possible brackets (sized once: the text of a
        // large entry is written into one buffer).
        let len = pos.iter().map(|r| r.s.len() + 5).sum::<usize>()
            + neg.iter().map(|r| r.s.len() + 5).sum::<usize>();
        let mut s = String::with_capacity(len);
        let mut first = true;
        for r in pos {
            if !first {
                s.push_str(" + ");
            }
            wrap(&mut s, r);
            first = false;
        }
        for r in neg {
            if first {
                s.push_str(&self.negate(r).s);
            } else {
                s.push_str(" - ");
                wrap(&mut s, &r);
            }
            first = false;
        }
        Rendered::new(s, Prec::Sum)
    }

    /// The exponent -e when e is in negative form, for a factor that goes below the bar.
    fn negated_exponent(&self, e: Id) -> Option<Exp<'_>> {
        match self.arena.node(e) {
            // x^-1.0 stays as written: the arena folds x^1.0 to x, so `1/x^1.0` would read
            // back as x^-1, another node.
            Node::Num(n) if n.is_float() && (-*n).is_one() => None,
            Node::Num(n) if n.is_negative() => Some(Exp::Num(-*n)),
            Node::Mul(_) => self.negated(e).map(|r| Exp::Expr(Cow::Owned(r))),
            _ => None,
        }
    }

    /// c * factors for a positive coefficient c, factors with a negative exponent below the
    /// fraction bar.
    fn product(&self, c: Number, factors: &[Id]) -> Rendered {
        let mut num: Vec<Cow<'_, Rendered>> = Vec::new();
        let mut den: Vec<Cow<'_, Rendered>> = Vec::new();
        match c {
            Number::Rational(p, q) => {
                if p != 1 {
                    num.push(Cow::Owned(self.style.number(Number::int(p))));
                }
                if q != 1 {
                    den.push(Cow::Owned(self.style.number(Number::int(q))));
                }
            }
            // A float coefficient always prints, even 1.0 (from -1.0): `-1.0*x` is not `-x`.
            Number::Float(_) => num.push(Cow::Owned(self.style.number(c))),
        }
        for &f in factors {
            if let Node::Pow(b, e) = *self.arena.node(f) {
                // A constant power the arena could not fold (it overflowed) stays as written:
                // c^|e| would fold, maybe underflow to 0 (`1/0.5^10000.0`). Only rational
                // roots like 2^(-1/2) are never folded and may go below the bar.
                let folds = match (self.arena.as_number(b), self.arena.as_number(e)) {
                    (Some(Number::Rational(..)), Some(Number::Rational(_, d))) => d == 1,
                    (Some(_), Some(_)) => true,
                    _ => false,
                };
                if let Some(ne) = self.negated_exponent(e).filter(|_| !folds) {
                    den.push(self.power(b, ne));
                    continue;
                }
                let exp = match self.arena.as_number(e) {
                    Some(n) => Exp::Num(n),
                    None => Exp::Expr(Cow::Borrowed(self.get(e))),
                };
                num.push(self.power(b, exp));
                continue;
            }
            num.push(Cow::Borrowed(self.get(f)));
        }
        self.style.product(&num, &den)
    }

    /// b^e; the base's own rendering when e is exactly 1.
    fn power(&self, b: Id, e: Exp<'_>) -> Cow<'_, Rendered> {
        let base = self.get(b);
        Cow::Owned(match e {
            // Only the exact 1: `x^-1.0` must print as `1/x^1.0` to read back as itself.
            Exp::Num(Number::Rational(1, 1)) => return Cow::Borrowed(base),
            Exp::Num(Number::Rational(1, 2)) => self.style.sqrt(base),
            Exp::Num(n) => self.style.power(base, &self.signed_number(n)),
            Exp::Expr(r) => self.style.power(base, &r),
        })
    }
}

/// The sums and products that more than one node reachable from `roots` reads (or
/// that two roots are), in increasing id order, so that each one's definition reads only
/// names defined before it. Powers are left out: a product prints its factors' powers
/// itself (`m2*l1^2`), so a name for `l1^2` would never be read.
pub(crate) fn shared_nodes(arena: &Arena, roots: &[Id]) -> Vec<Id> {
    let mut uses = vec![0u32; arena.len()];
    let mut seen = vec![false; arena.len()];
    let mut stack: Vec<Id> = Vec::new();
    for &root in roots {
        if root.index() < arena.len() {
            uses[root.index()] += 1;
            stack.push(root);
        }
    }
    while let Some(n) = stack.pop() {
        if std::mem::replace(&mut seen[n.index()], true) {
            continue;
        }
        for c in arena.children(n) {
            uses[c.index()] += 1;
            stack.push(c);
        }
    }
    (0..arena.len())
        .filter(|&i| uses[i] > 1)
        .map(|i| Id::new(i as u32))
        .filter(|&id| matches!(arena.node(id), Node::Add(_) | Node::Mul(_) | Node::Named(_)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::print::text::Text;

    /// Past the text budget a node rendered before still prints in full, and one not
    /// rendered yet prints as ELIDED without its subexpressions being collected.
    #[test]
    fn past_the_budget_only_rendered_nodes_print() {
        let mut a = Arena::new();
        let [x, ..] = a.coordinate("x");
        let [y, ..] = a.coordinate("y");
        let shared = a.sin(x);
        let mut e = shared;
        // A tree of 2^60 copies of sin(x): far past the budget when printed.
        for _ in 0..60 {
            let p = a.mul2(e, y);
            e = a.add(&[e, p]);
        }
        let fresh = a.cos(y);
        // Both kinds of slots: the map of single expressions, the table of equations.
        for mut r in [Renderer::new(&a, Text), Renderer::for_equations(&a, Text)] {
            assert_eq!(r.render(shared).s, "sin(x)");
            assert!(!r.elided);
            assert!(r.render(e).s.contains(ELIDED));
            assert!(r.elided && r.held > MAX_TEXT_BYTES);
            assert_eq!(r.render(shared).s, "sin(x)");
            assert_eq!(r.render(fresh).s, ELIDED);
            // Not collected: no rendering was kept for cos(y) or its argument.
            assert!(!r.is_rendered(fresh));
        }
    }

    /// A renderer for one expression holds slots for that expression's nodes only, not
    /// one per node of the arena: printing an early node of a large arena reads it alone.
    #[test]
    fn one_expression_holds_only_its_nodes() {
        let mut a = Arena::new();
        let [x, ..] = a.coordinate("x");
        let early = a.sin(x);
        for k in 0..10_000 {
            let c = a.int(k + 2);
            a.mul2(c, x);
        }
        let mut r = Renderer::new(&a, Text);
        assert_eq!(r.render(early).s, "sin(x)");
        let Slots::Map(m) = &r.slots else {
            panic!("a single expression's slots are a map")
        };
        assert_eq!(m.len(), 2, "sin(x) and x");
    }
}
