//! The expression arena: a hash-consed DAG in which each distinct subexpression is one node.
//!
//! Nodes are stored children-first, so increasing [`Id`] order is a topological order.
//! Constructors return canonical forms, so structurally equal expressions get equal ids:
//! - sums and products are flat, their operands sorted, constants folded;
//! - like terms (`2*x + 3*x = 5*x`) and like powers (`x^2 * x = x^3`) are collected;
//! - the identities `x + 0`, `1 * x`, `0 * x`, `x^0`, `x^1` are applied;
//! - a numeric factor distributes over a single sum (`2*(a + b) = 2*a + 2*b`) and an integer
//!   power over a product (`(a*b)^2 = a^2*b^2`);
//! - `sin(-x) = -sin(x)`, `tan(-x) = -tan(x)`, `cos(-x) = cos(x)`, `abs(-x) = abs(x)`;
//! - `c*u*sin(x)^2 + c*u*cos(x)^2 = c*u` (the one targeted trigonometric rule).
//!
//! Nothing is expanded beyond that: products of sums stay products, which keeps derived
//! expressions lean.

use crate::error::{AlgebraError, BudgetError};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};

use crate::algebra::budget::{Budget, Effort, PROGRESS_EVERY};
use crate::algebra::probe_table::ProbeTable;
use crate::error::{Error, Result};
use crate::number::Number;

mod operands;
mod products;
mod reachable;
mod sums;

pub use operands::Operands;

/// A scratch list of a constructor (the flattened operands of a sum or product, their
/// pairs, the result): on the stack up to eight entries, which holds nearly every sum and
/// product a derivation builds, so building one allocates nothing but its node.
pub(crate) type Short<T> = smallvec::SmallVec<[T; 8]>;

/// Index of a node in an [`Arena`]. Children always have smaller ids than their parents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Id(pub(crate) u32);

impl Id {
    /// The id of the node at `index`. Nothing checks it here: an arena that holds no such
    /// node refuses it ([`crate::error::AlgebraError::InvalidId`]).
    pub const fn new(index: u32) -> Id {
        Id(index)
    }

    /// The index as usize.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Index of a symbol in an [`Arena`]'s symbol table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SymbolId(pub(crate) u32);

impl SymbolId {
    /// The id of the symbol at `index` of a symbol table. Nothing checks it here: an arena
    /// without that symbol refuses it ([`crate::error::AlgebraError::UnknownSymbolId`]).
    pub const fn new(index: u32) -> SymbolId {
        SymbolId(index)
    }

    /// The index as usize: where the symbol's value goes in a slice of inputs indexed by
    /// symbol (see [`crate::Tape`]).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Unary functions of the language (`sqrt(x)` is stored as `x^(1/2)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Func {
    /// sin x
    Sin,
    /// cos x
    Cos,
    /// tan x
    Tan,
    /// e^x
    Exp,
    /// natural logarithm
    Ln,
    /// |x|
    Abs,
}

impl Func {
    /// The function's name in the expression language.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Abs => "abs",
        }
    }

    /// The function called `name`, if the language has it (`sqrt` and `atan2` are handled by
    /// the parser, not here).
    pub fn from_name(name: &str) -> Option<Func> {
        Some(match name {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "exp" => Func::Exp,
            "ln" => Func::Ln,
            "abs" => Func::Abs,
            _ => return None,
        })
    }

    /// f(x) in floating point.
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Exp => x.exp(),
            Func::Ln => x.ln(),
            Func::Abs => x.abs(),
        }
    }
}

/// One node of the DAG.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// A numeric constant.
    Num(Number),
    /// The constant pi.
    Pi,
    /// A symbol (coordinate, rate, parameter, time or free).
    Sym(SymbolId),
    /// n-ary sum; a numeric constant, if any, comes first; other terms sorted by their
    /// coefficient-free part.
    Add(Operands),
    /// n-ary product; a numeric coefficient, if any, comes first; other factors sorted by id.
    Mul(Operands),
    /// base ^ exponent.
    Pow(Id, Id),
    /// A unary function.
    Func(Func, Id),
    /// atan2(y, x), the angle of the point (x, y).
    Atan2(Id, Id),
    /// The value of its child, a sum, kept as one operand: the canonical sum and product
    /// treat it as an atom (a sum holding it is not flattened into it, a numeric factor is
    /// not distributed over it, no like terms are collected across it). What a recursion
    /// names once per step ([`Arena::named`]) stays one node that later steps read,
    /// instead of a sum copied and scaled into every expression above it.
    Named(Id),
}

impl Node {
    /// The node with each child c replaced by `f(c)`.
    pub(crate) fn map_children(&self, mut f: impl FnMut(Id) -> Id) -> Node {
        match self {
            Node::Num(_) | Node::Pi | Node::Sym(_) => self.clone(),
            Node::Add(v) => Node::Add(v.iter().map(|&c| f(c)).collect()),
            Node::Mul(v) => Node::Mul(v.iter().map(|&c| f(c)).collect()),
            Node::Pow(a, b) => Node::Pow(f(*a), f(*b)),
            Node::Atan2(a, b) => Node::Atan2(f(*a), f(*b)),
            Node::Func(g, a) => Node::Func(*g, f(*a)),
            Node::Named(a) => Node::Named(f(*a)),
        }
    }

    /// Calls `f` on each direct child of the node.
    pub(crate) fn for_each_child(&self, mut f: impl FnMut(Id)) {
        match self {
            Node::Num(_) | Node::Pi | Node::Sym(_) => {}
            Node::Add(v) | Node::Mul(v) => v.iter().copied().for_each(f),
            Node::Pow(a, b) | Node::Atan2(a, b) => {
                f(*a);
                f(*b);
            }
            Node::Func(_, a) | Node::Named(a) => f(*a),
        }
    }
}

/// What a symbol stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SymbolKind {
    /// A generalised coordinate q_i.
    Coordinate,
    /// A rate q_i' (written `der(q_i)`).
    Velocity,
    /// An acceleration q_i''.
    Acceleration,
    /// A parameter (a run-time constant).
    Parameter,
    /// Time t.
    Time,
    /// Anything else (used by tests and intermediate algebra).
    Free,
}

/// A symbol's name and role. `derivative` links q to q' and q' to q''.
#[derive(Clone, Debug, PartialEq)]
pub struct Symbol {
    /// Printed name (`phi`, `der(phi)`, `der2(phi)`, `t`, ...).
    pub name: String,
    /// Its role.
    pub kind: SymbolKind,
    /// The symbol of its time derivative, for coordinates and rates.
    pub derivative: Option<SymbolId>,
}

/// FxHash (rustc's): a fast, deterministic hasher for small keys.
#[derive(Default, Clone, Copy)]
pub struct FxHasher(u64);

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut b = [0u8; 8];
            b[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(b));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(x as u64);
    }
    fn write_u8(&mut self, x: u8) {
        self.write_u64(x as u64);
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
    /// The state mixed by MurmurHash3's 64-bit finaliser (Appleby), so that every bit of
    /// the key reaches the low bits. The multiply alone carries a key's high bits into the
    /// high bits only, and hash tables take the bucket from the low bits: without the mix
    /// the bit patterns of floats such as 2.0 or 640.0 (low mantissa bits zero) all hashed
    /// to multiples of 2^40 and shared one bucket.
    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
}

/// A 3-vector of expressions (world components unless said otherwise): a point, an axis
/// or a velocity of the body sections.
pub type Vec3 = [Id; 3];

/// The id no node has (a placeholder in tables indexed by id).
pub(crate) const NO_ID: Id = Id(u32::MAX);

/// A HashMap with [`FxHasher`].
pub type FxHashMap<K, V> = HashMap<K, V, BuildHasherDefault<FxHasher>>;

/// A hash set with [`FxHasher`].
pub type FxHashSet<K> = std::collections::HashSet<K, BuildHasherDefault<FxHasher>>;

/// The arena: nodes, their intern table and the symbol table.
#[derive(Clone, Default)]
pub struct Arena {
    nodes: Vec<Node>,
    /// The intern table: node ids by a 32-bit node hash, nodes of one hash told apart by
    /// value. A node is stored once, in `nodes`; the table holds its id, 8 bytes a slot
    /// (the table is the largest structure of a large derivation after the nodes).
    intern: ProbeTable,
    symbols: Vec<Symbol>,
    symbol_nodes: Vec<Id>,
    by_name: FxHashMap<String, SymbolId>,
    /// The first folding of constants that overflowed (see [`Arena::take_overflow`]).
    overflow: Option<Overflow>,
    /// The size of the graph: one per node plus one per child reference (an n-term sum
    /// counts n + 1), what the derivation and the lowering to programs spend memory on.
    size: usize,
    /// Calls of the constructors (found or new): what the derivation spends time on.
    work: u64,
    /// For a product c * f1 * ... * fk (k >= 2) built by scaling the product f1 * ... * fk,
    /// that product, by the id of the scaled one (`NO_ID` elsewhere): so splitting a
    /// term into coefficient and rest, which every sum does to each of its terms, is a
    /// look-up instead of building and interning the rest again.
    coefficient_free: Vec<Id>,
    /// The constants made so far, by value: constants are a derivation's commonest
    /// constructor call (each coefficient scaled, each factor's exponent 1), and these few
    /// (thousands at most) are found here without a look-up in the intern table.
    numbers: FxHashMap<Number, Id>,
    /// The limits on size and work, and who hears of the progress.
    budget: Budget,
}

/// A sum or product of two constants beyond the range of f64 (about 1.8e308), met while
/// folding constants: the folded value would be infinite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Overflow {
    /// The left operand.
    pub lhs: Number,
    /// `+` or `*`.
    pub op: char,
    /// The right operand.
    pub rhs: Number,
}

impl std::fmt::Display for Overflow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {} {}", self.lhs, self.op, self.rhs)
    }
}

impl std::fmt::Debug for Arena {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Arena({} nodes, {} symbols)",
            self.nodes.len(),
            self.symbols.len()
        )
    }
}

impl Arena {
    /// An empty arena.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The size of the graph: its nodes plus their child references (within
    /// [`Budget::size`] in a derivation).
    pub fn size(&self) -> usize {
        self.size
    }

    /// What the arena has spent: its work (constructor calls) and size.
    pub fn effort(&self) -> Effort {
        Effort {
            work: self.work,
            size: self.size,
        }
    }

    /// The budget the derivations on this arena keep to.
    pub fn budget(&self) -> &Budget {
        &self.budget
    }

    /// Sets the budget (the macro and the command-line tool set it from the environment).
    pub fn set_budget(&mut self, budget: Budget) {
        self.budget = budget;
    }

    /// [`crate::error::BudgetError::Size`] when the graph is beyond [`Budget::size`],
    /// [`crate::error::BudgetError::Work`] when the work is beyond [`Budget::work`]. Every
    /// derivative and every compiled program checks it, so a runaway derivation stops within
    /// one derivative's growth of the limit.
    pub fn check_budget(&self) -> Result<()> {
        if self.size > self.budget.size {
            return Err(Error::Budget(BudgetError::Size {
                size: self.size,
                budget: self.budget.size,
                links: None,
            }));
        }
        if self.work > self.budget.work {
            return Err(Error::Budget(BudgetError::Work {
                work: self.work,
                budget: self.budget.work,
                links: None,
            }));
        }
        Ok(())
    }

    /// True when no node exists.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node behind `id`.
    pub fn node(&self, id: Id) -> &Node {
        &self.nodes[id.index()]
    }

    /// All nodes, in id (topological) order.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Counts one constructor call as work, and reports progress every
    /// [`PROGRESS_EVERY`] calls.
    fn tick(&mut self) {
        self.work += 1;
        if self.work.is_multiple_of(PROGRESS_EVERY)
            && let Some(progress) = self.budget.progress
        {
            progress(self.effort());
        }
    }

    fn intern(&mut self, node: Node) -> Id {
        self.tick();
        let hash = node_hash(&node);
        let id = Id(self.nodes.len() as u32);
        let nodes = &self.nodes;
        if let Some(found) = self
            .intern
            .find_or_insert(hash, id.0, |k| nodes[k as usize] == node)
        {
            return Id(found);
        }
        let mut children = 0;
        node.for_each_child(|_| children += 1);
        self.size += 1 + children;
        self.nodes.push(node);
        id
    }

    // ----- symbols -----

    /// The symbol called `name`, created with `kind` if new. An existing symbol keeps its kind.
    pub fn symbol(&mut self, name: &str, kind: SymbolKind) -> Id {
        let s = self.symbol_id(name, kind);
        self.symbol_nodes[s.0 as usize]
    }

    /// Like [`Arena::symbol`], returning the symbol's id.
    pub fn symbol_id(&mut self, name: &str, kind: SymbolKind) -> SymbolId {
        if let Some(&s) = self.by_name.get(name) {
            return s;
        }
        let s = SymbolId(self.symbols.len() as u32);
        self.symbols.push(Symbol {
            name: name.to_string(),
            kind,
            derivative: None,
        });
        self.by_name.insert(name.to_string(), s);
        let id = self.intern(Node::Sym(s));
        self.symbol_nodes.push(id);
        s
    }

    /// Declares a coordinate `name` with its rate `der(name)` and acceleration `der2(name)`.
    /// Returns the three symbols' node ids.
    pub fn coordinate(&mut self, name: &str) -> [Id; 3] {
        let q = self.symbol_id(name, SymbolKind::Coordinate);
        let v = self.symbol_id(&format!("der({name})"), SymbolKind::Velocity);
        let a = self.symbol_id(&format!("der2({name})"), SymbolKind::Acceleration);
        self.symbols[q.0 as usize].derivative = Some(v);
        self.symbols[v.0 as usize].derivative = Some(a);
        [q, v, a].map(|s| self.symbol_nodes[s.0 as usize])
    }

    /// The symbol called `name`, if declared.
    pub fn lookup(&self, name: &str) -> Option<SymbolId> {
        self.by_name.get(name).copied()
    }

    /// The symbol table entry of `s`.
    pub fn symbol_info(&self, s: SymbolId) -> &Symbol {
        &self.symbols[s.0 as usize]
    }

    /// All symbols, indexed by [`SymbolId`].
    pub fn symbols(&self) -> &[Symbol] {
        &self.symbols
    }

    /// The node of symbol `s`.
    pub fn symbol_node(&self, s: SymbolId) -> Id {
        self.symbol_nodes[s.0 as usize]
    }

    /// The symbol at node `id`, if it is one.
    pub fn as_symbol(&self, id: Id) -> Option<SymbolId> {
        match self.node(id) {
            Node::Sym(s) => Some(*s),
            _ => None,
        }
    }

    // ----- constants -----

    /// a + b of constants. An overflow is recorded for [`Arena::take_overflow`] and folds
    /// to 0 meanwhile: whoever builds from a declaration must take it and report it.
    pub(crate) fn fold_add(&mut self, a: Number, b: Number) -> Number {
        a.checked_add(b)
            .unwrap_or_else(|| self.overflowed(a, '+', b))
    }

    /// a * b of constants; an overflow as in [`Arena::fold_add`].
    pub(crate) fn fold_mul(&mut self, a: Number, b: Number) -> Number {
        a.checked_mul(b)
            .unwrap_or_else(|| self.overflowed(a, '*', b))
    }

    fn overflowed(&mut self, lhs: Number, op: char, rhs: Number) -> Number {
        self.overflow.get_or_insert(Overflow { lhs, op, rhs });
        Number::int(0)
    }

    /// The first folding of constants that overflowed since the last call, if any (and
    /// clears it). Expressions built while it was set contain a 0 in its place: they are
    /// wrong, and the caller must report the overflow instead of using them.
    pub fn take_overflow(&mut self) -> Option<Overflow> {
        self.overflow.take()
    }

    /// A numeric constant.
    pub fn number(&mut self, n: Number) -> Id {
        if let Some(&id) = self.numbers.get(&n) {
            self.tick();
            return id;
        }
        let id = self.intern(Node::Num(n));
        self.numbers.insert(n, id);
        id
    }

    /// The integer n.
    pub fn int(&mut self, n: i64) -> Id {
        self.number(Number::int(n))
    }

    /// The exact rational num/den; division by zero is an error.
    pub fn rational(&mut self, num: i64, den: i64) -> Result<Id> {
        let n = Number::rational(num, den).ok_or_else(|| {
            Error::Algebra(AlgebraError::DivisionByZero {
                operation: format!("{num}/{den}"),
            })
        })?;
        Ok(self.number(n))
    }

    /// A float constant (non-finite values are a domain error).
    pub fn float(&mut self, x: f64) -> Result<Id> {
        let n = Number::float(x).ok_or_else(|| {
            Error::Algebra(AlgebraError::Domain {
                function: "float",
                argument: format!("{x}"),
            })
        })?;
        Ok(self.number(n))
    }

    /// The constant pi.
    pub fn pi(&mut self) -> Id {
        self.intern(Node::Pi)
    }

    /// The constant at `id`, if it is a number.
    pub fn as_number(&self, id: Id) -> Option<Number> {
        match self.node(id) {
            Node::Num(n) => Some(*n),
            _ => None,
        }
    }

    /// True when `id` is the constant 0.
    pub fn is_zero(&self, id: Id) -> bool {
        self.as_number(id).is_some_and(Number::is_zero)
    }

    // ----- functions -----

    /// True when `id` is in "negative form": a negative constant, a product with a negative
    /// coefficient, or a sum whose first non-constant term is. Negating flips it, so
    /// `f(-x)` rules can pick one of x and -x canonically.
    pub fn is_negative_form(&self, id: Id) -> bool {
        match self.node(id) {
            Node::Num(n) => n.is_negative(),
            Node::Mul(fs) => self.as_number(fs[0]).is_some_and(Number::is_negative),
            Node::Add(ts) => {
                let first = if self.as_number(ts[0]).is_some() {
                    ts.get(1)
                } else {
                    ts.first()
                };
                first.is_some_and(|&t| self.is_negative_form(t))
            }
            _ => false,
        }
    }

    fn func_raw(&mut self, f: Func, x: Id) -> Id {
        self.intern(Node::Func(f, x))
    }

    /// f(x), canonical: constant folding for floats and the trivial points (sin 0 = 0,
    /// cos 0 = 1, exp 0 = 1, ln 1 = 0), and the parity rules. ln of a constant <= 0 is a
    /// domain error.
    pub fn func(&mut self, f: Func, x: Id) -> Result<Id> {
        if let Some(n) = self.as_number(x) {
            let v = n.to_f64();
            match f {
                Func::Ln if v <= 0.0 => {
                    return Err(Error::Algebra(AlgebraError::Domain {
                        function: "ln",
                        argument: n.to_string(),
                    }));
                }
                Func::Abs => {
                    let a = if n.is_negative() { -n } else { n };
                    return Ok(self.number(a));
                }
                _ => {}
            }
            let trivial = match (f, v == 0.0, v == 1.0) {
                (Func::Sin | Func::Tan, true, _) => Some(0),
                (Func::Cos | Func::Exp, true, _) => Some(1),
                (Func::Ln, _, true) => Some(0),
                _ => None,
            };
            if let Some(k) = trivial {
                return Ok(self.int(k));
            }
            if n.is_float()
                && let Some(r) = Number::float(f.apply(v))
            {
                return Ok(self.number(r));
            }
        }
        if let Some(k) = self.half_pi_multiple(x)
            && let Some(v) = exact_trig(f, k)
        {
            return Ok(self.int(v));
        }
        if self.is_negative_form(x) && matches!(f, Func::Sin | Func::Tan | Func::Cos | Func::Abs) {
            let nx = self.neg(x);
            let inner = self.func_raw(f, nx);
            return Ok(match f {
                Func::Sin | Func::Tan => self.neg(inner),
                _ => inner,
            });
        }
        Ok(self.func_raw(f, x))
    }

    /// k when `x` is exactly k pi/2 for an integer k (`pi`, `-pi/2`, `3*pi/2`; a float
    /// coefficient counts when twice it is a whole number, as `-1.0*pi` or `0.5*pi`: such a
    /// float is exact, and the printed form `-pi` reads back as the rational -1).
    fn half_pi_multiple(&self, x: Id) -> Option<i64> {
        match self.node(x) {
            Node::Pi => Some(2),
            Node::Mul(fs) if fs.len() == 2 && matches!(self.node(fs[1]), Node::Pi) => {
                let c = self.as_number(fs[0])?;
                if c.is_float() {
                    let twice = 2.0 * c.to_f64();
                    return (twice.fract() == 0.0 && twice.abs() < 9.0e15).then_some(twice as i64);
                }
                c.checked_mul(Number::int(2))?.as_integer()
            }
            _ => None,
        }
    }

    /// sin x.
    pub fn sin(&mut self, x: Id) -> Id {
        self.func(Func::Sin, x)
            .unwrap_or_else(|_| self.func_raw(Func::Sin, x))
    }

    /// cos x.
    pub fn cos(&mut self, x: Id) -> Id {
        self.func(Func::Cos, x)
            .unwrap_or_else(|_| self.func_raw(Func::Cos, x))
    }

    /// atan2(y, x): the angle of the point (x, y) in (-pi, pi].
    pub fn atan2(&mut self, y: Id, x: Id) -> Id {
        if let (Some(a), Some(b)) = (self.as_number(y), self.as_number(x))
            && (a.is_float() || b.is_float())
            && let Some(r) = Number::float(a.to_f64().atan2(b.to_f64()))
        {
            return self.number(r);
        }
        self.intern(Node::Atan2(y, x))
    }

    /// `x` named ([`Node::Named`]) when it is a sum, `x` itself otherwise: a product, a
    /// power or a function is one operand of a sum already, and a numeric factor scales a
    /// product's coefficient without copying it. A sum's constant term stays outside the
    /// name, `c + named(rest)`, so that constants added later still fold into one.
    pub fn named(&mut self, x: Id) -> Id {
        let Node::Add(ts) = self.node(x) else {
            return x;
        };
        match (self.as_number(ts[0]), ts.len()) {
            (Some(_), 2) => x,
            (Some(c), _) => {
                let rest = Operands::from(&ts[1..]);
                let rest = self.intern(Node::Add(rest));
                let named = self.intern(Node::Named(rest));
                let c = self.number(c);
                self.add(&[c, named])
            }
            (None, _) => self.intern(Node::Named(x)),
        }
    }

    /// Ids of the direct children of `id`.
    pub fn children(&self, id: Id) -> Vec<Id> {
        self.child_list(id).into_vec()
    }

    /// The direct children of `id`, on the stack (up to eight): for walks that visit many
    /// nodes and would otherwise allocate a list per node.
    pub(crate) fn child_list(&self, id: Id) -> Short<Id> {
        match self.node(id) {
            Node::Num(_) | Node::Pi | Node::Sym(_) => Short::new(),
            Node::Add(v) | Node::Mul(v) => Short::from_slice(v),
            Node::Pow(a, b) | Node::Atan2(a, b) => Short::from_slice(&[*a, *b]),
            Node::Func(_, a) | Node::Named(a) => Short::from_slice(&[*a]),
        }
    }

    /// Whether `id` depends on the symbol `s` (a walk over the sub-DAG).
    pub fn depends_on(&self, id: Id, s: SymbolId) -> bool {
        self.depends_on_any(id, |x| x == s)
    }

    /// Whether the expression `id` contains a symbol for which `wanted` holds: one walk of
    /// its subtree (each shared node once), whose cost is the subtree's, not the arena's.
    pub(crate) fn depends_on_any(&self, id: Id, wanted: impl Fn(SymbolId) -> bool) -> bool {
        let mut stack = vec![id];
        let mut seen: FxHashSet<Id> = FxHashSet::default();
        while let Some(n) = stack.pop() {
            if !seen.insert(n) {
                continue;
            }
            match self.node(n) {
                Node::Sym(x) if wanted(*x) => return true,
                node => node.for_each_child(|c| stack.push(c)),
            }
        }
        false
    }
}

/// sin, cos and tan of k pi/2, exactly: 0, 1 or -1 (tan only at multiples of pi, where it
/// is 0; at odd multiples of pi/2 it has a pole and stays symbolic, for evaluation to report).
fn exact_trig(f: Func, k: i64) -> Option<i64> {
    let r = k.rem_euclid(4);
    match f {
        Func::Sin => Some([0, 1, 0, -1][r as usize]),
        Func::Cos => Some([1, 0, -1, 0][r as usize]),
        Func::Tan if r % 2 == 0 => Some(0),
        _ => None,
    }
}

/// The intern table's key of `node`: its FxHash folded to 32 bits.
fn node_hash(node: &Node) -> u32 {
    let mut h = FxHasher::default();
    node.hash(&mut h);
    let h = h.finish();
    (h ^ (h >> 32)) as u32
}

#[cfg(test)]
mod tests;
