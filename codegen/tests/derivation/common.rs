//! Shared test support (calculus tests; others may reuse it with `mod common;`):
//!
//! - [`Ast`] and [`ast`]: a proptest strategy for random expression trees over three symbols
//!   x, y, z (numbers, sums, products, small integer powers, sin, cos, exp, sqrt(1 + u^2),
//!   atan2, ln(1 + u^2) and (1 + u^2)^v), so every generated expression is defined wherever
//!   its powers' bases are nonzero;
//! - [`build`]: the tree as an arena expression, through the canonical constructors;
//! - [`eval_ast`]: the tree evaluated in any num-dual number type (`Dual64` for first
//!   derivatives, `HyperDual64` or `Dual2_64` for second ones): the derivative oracle that
//!   shares no code with the crate;
//! - [`eval_node`]: any arena expression evaluated in a num-dual type from a symbol table (to
//!   differentiate an arena expression along a trajectory q(t) without our differentiator);
//! - [`close`]: the relative comparison the tests use.
#![allow(dead_code)]

use mechanism_codegen::{Arena, Func, Id, Node, Number, SymbolId};
use num_dual::DualNum;
use proptest::prelude::*;

/// A random expression tree over the symbols x, y, z (indices 0, 1, 2).
#[derive(Clone, Debug)]
pub enum Ast {
    /// The rational k/2.
    Num(i64),
    /// Symbol 0, 1 or 2.
    Sym(usize),
    /// a + b
    Add(Box<Ast>, Box<Ast>),
    /// a b
    Mul(Box<Ast>, Box<Ast>),
    /// a^k for a small integer k (-2..=3, k != 0)
    Pow(Box<Ast>, i32),
    /// sin a
    Sin(Box<Ast>),
    /// cos a
    Cos(Box<Ast>),
    /// exp a
    Exp(Box<Ast>),
    /// sqrt(1 + a^2)
    SqrtPos(Box<Ast>),
    /// atan2(a, b)
    Atan2(Box<Ast>, Box<Ast>),
    /// ln(1 + a^2)
    LnPos(Box<Ast>),
    /// (1 + a^2)^b, a symbolic exponent
    PowPos(Box<Ast>, Box<Ast>),
}

/// Random trees of depth at most 4 and about 24 nodes.
pub fn ast() -> impl Strategy<Value = Ast> {
    let leaf = prop_oneof![
        (-6i64..=6).prop_map(Ast::Num),
        (0usize..3).prop_map(Ast::Sym),
        (0usize..3).prop_map(Ast::Sym)
    ];
    leaf.prop_recursive(4, 24, 2, |inner| {
        let b = |a: Ast| Box::new(a);
        prop_oneof![
            3 => (inner.clone(), inner.clone()).prop_map(move |(x, y)| Ast::Add(b(x), b(y))),
            3 => (inner.clone(), inner.clone()).prop_map(move |(x, y)| Ast::Mul(b(x), b(y))),
            2 => (inner.clone(), prop_oneof![Just(-2), Just(-1), Just(2), Just(3)]).prop_map(move |(x, k)| Ast::Pow(b(x), k)),
            2 => inner.clone().prop_map(move |x| Ast::Sin(b(x))),
            2 => inner.clone().prop_map(move |x| Ast::Cos(b(x))),
            1 => inner.clone().prop_map(move |x| Ast::Exp(b(x))),
            1 => inner.clone().prop_map(move |x| Ast::SqrtPos(b(x))),
            1 => (inner.clone(), inner.clone()).prop_map(move |(x, y)| Ast::Atan2(b(x), b(y))),
            1 => inner.clone().prop_map(move |x| Ast::LnPos(b(x))),
            1 => (inner.clone(), inner.clone()).prop_map(move |(x, y)| Ast::PowPos(b(x), b(y))),
        ]
    })
}

/// 1 + u^2 in the arena.
fn one_plus_square(a: &mut Arena, u: Id) -> Id {
    let one = a.int(1);
    let u2 = a.mul2(u, u);
    a.add2(one, u2)
}

/// The tree as an arena expression over the symbol nodes `syms` (x, y, z). `None` when a
/// constructor reports an error (a power of an expression that simplified to 0).
pub fn build(a: &mut Arena, e: &Ast, syms: &[Id; 3]) -> Option<Id> {
    Some(match e {
        Ast::Num(k) => a.rational(*k, 2).ok()?,
        Ast::Sym(i) => syms[*i],
        Ast::Add(x, y) => {
            let (x, y) = (build(a, x, syms)?, build(a, y, syms)?);
            a.add2(x, y)
        }
        Ast::Mul(x, y) => {
            let (x, y) = (build(a, x, syms)?, build(a, y, syms)?);
            a.mul2(x, y)
        }
        Ast::Pow(x, k) => {
            let x = build(a, x, syms)?;
            a.powi(x, i64::from(*k)).ok()?
        }
        Ast::Sin(x) => {
            let x = build(a, x, syms)?;
            a.sin(x)
        }
        Ast::Cos(x) => {
            let x = build(a, x, syms)?;
            a.cos(x)
        }
        Ast::Exp(x) => {
            let x = build(a, x, syms)?;
            a.func(Func::Exp, x).ok()?
        }
        Ast::SqrtPos(x) => {
            let x = build(a, x, syms)?;
            let p = one_plus_square(a, x);
            a.sqrt(p).ok()?
        }
        Ast::Atan2(y, x) => {
            let (y, x) = (build(a, y, syms)?, build(a, x, syms)?);
            a.atan2(y, x)
        }
        Ast::LnPos(x) => {
            let x = build(a, x, syms)?;
            let p = one_plus_square(a, x);
            a.func(Func::Ln, p).ok()?
        }
        Ast::PowPos(x, y) => {
            let (x, y) = (build(a, x, syms)?, build(a, y, syms)?);
            let p = one_plus_square(a, x);
            a.pow(p, y).ok()?
        }
    })
}

/// Beyond this magnitude an angle is NaN to [`eval_ast`]: a relative rounding error e of
/// the angle u moves sin u and cos u by up to e |u|, so two operation orders (the oracle's
/// and the arena's, e.g. `exp(7.25^3)` folded exactly there and through `powd` here) disagree
/// by more than any tolerance once |u| is large (at 1e165 they share no digit). 1e4 is the
/// bound the property tests put on values.
const TRIG_ARGUMENT_LIMIT: f64 = 1e4;

/// `u` when a trigonometric function of it is well-conditioned, else NaN (the tests skip
/// non-finite oracle values).
fn trig_argument<D: DualNum<Primitive = f64> + Copy>(u: D) -> D {
    if u.re().abs() > TRIG_ARGUMENT_LIMIT {
        D::from(f64::NAN)
    } else {
        u
    }
}

/// The tree evaluated in the number type `D` at (x, y, z) = `v` (NaN where a sine or cosine
/// would be ill-conditioned, see [`TRIG_ARGUMENT_LIMIT`]).
pub fn eval_ast<D: DualNum<Primitive = f64> + Copy>(e: &Ast, v: &[D; 3]) -> D {
    let one = D::from(1.0);
    match e {
        Ast::Num(k) => D::from(*k as f64 / 2.0),
        Ast::Sym(i) => v[*i],
        Ast::Add(x, y) => eval_ast(x, v) + eval_ast(y, v),
        Ast::Mul(x, y) => eval_ast(x, v) * eval_ast(y, v),
        Ast::Pow(x, k) => eval_ast(x, v).powi(*k),
        Ast::Sin(x) => trig_argument(eval_ast(x, v)).sin(),
        Ast::Cos(x) => trig_argument(eval_ast(x, v)).cos(),
        Ast::Exp(x) => eval_ast(x, v).exp(),
        Ast::SqrtPos(x) => {
            let u = eval_ast(x, v);
            (one + u * u).sqrt()
        }
        // `+ 0` turns a -0.0 (from folding, e.g. -1/2 * 0) into +0.0: the arena folds exact
        // zeros to +0, and atan2 jumps by 2 pi across its cut y = 0, x < 0.
        Ast::Atan2(y, x) => (eval_ast(y, v) + D::from(0.0)).atan2(eval_ast(x, v)),
        Ast::LnPos(x) => {
            let u = eval_ast(x, v);
            (one + u * u).ln()
        }
        Ast::PowPos(x, y) => {
            let u = eval_ast(x, v);
            (one + u * u).powd(eval_ast(y, v))
        }
    }
}

/// Any arena expression evaluated in the number type `D`, each symbol s bound to `env(s)`
/// (`None` when a symbol is unbound). Independent of the crate's evaluators.
pub fn eval_node<D: DualNum<Primitive = f64> + Copy>(
    a: &Arena,
    id: Id,
    env: &dyn Fn(SymbolId) -> Option<D>,
) -> Option<D> {
    let mut memo: std::collections::HashMap<Id, D> = std::collections::HashMap::new();
    eval_rec(a, id, env, &mut memo)
}

fn eval_rec<D: DualNum<Primitive = f64> + Copy>(
    a: &Arena,
    id: Id,
    env: &dyn Fn(SymbolId) -> Option<D>,
    memo: &mut std::collections::HashMap<Id, D>,
) -> Option<D> {
    if let Some(v) = memo.get(&id) {
        return Some(*v);
    }
    let v = match a.node(id).clone() {
        Node::Num(n) => D::from(n.to_f64()),
        Node::Pi => D::from(std::f64::consts::PI),
        Node::Sym(s) => env(s)?,
        Node::Add(ts) => {
            let mut acc = D::from(0.0);
            for t in ts.iter() {
                acc += eval_rec(a, *t, env, memo)?;
            }
            acc
        }
        Node::Mul(fs) => {
            let mut acc = D::from(1.0);
            for f in fs.iter() {
                acc *= eval_rec(a, *f, env, memo)?;
            }
            acc
        }
        Node::Pow(b, e) => {
            let base = eval_rec(a, b, env, memo)?;
            match a.as_number(e) {
                Some(Number::Rational(k, 1)) => base.powi(k as i32),
                Some(n) => base.powf(n.to_f64()),
                None => base.powd(eval_rec(a, e, env, memo)?),
            }
        }
        Node::Func(f, u) => {
            let u = eval_rec(a, u, env, memo)?;
            match f {
                Func::Sin => u.sin(),
                Func::Cos => u.cos(),
                Func::Tan => u.tan(),
                Func::Exp => u.exp(),
                Func::Ln => u.ln(),
                Func::Abs => u.abs(),
            }
        }
        Node::Named(x) => eval_rec(a, x, env, memo)?,
        Node::Atan2(y, x) => {
            let y = eval_rec(a, y, env, memo)? + D::from(0.0); // -0.0 -> +0.0, as in eval_ast
            let x = eval_rec(a, x, env, memo)?;
            y.atan2(x)
        }
    };
    memo.insert(id, v);
    Some(v)
}

/// |a - b| <= tol max(1, |a|, |b|): relative for large values, absolute below 1.
pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * 1f64.max(a.abs()).max(b.abs())
}

/// A small deterministic generator (splitmix64) for random states in plain tests.
pub struct Rng(pub u64);

impl Rng {
    /// The next value, uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

// ----- models and the Lagrangian oracle -----

use mechanism_codegen::{Constraint, Coordinate, Equations, Location, Model, SymbolKind};
use num_dual::{Dual2_64, Dual64, HyperDual64};

/// A model over `arena` with the given coordinates (name and `arena.coordinate` ids), energies
/// and constraints; forces zero, no parameters list (parameters are plain symbols here).
pub fn bare_model(
    arena: Arena,
    coords: &[(&str, [Id; 3])],
    kinetic: Id,
    potential: Id,
    constraints: Vec<Id>,
) -> Model {
    let mut arena = arena;
    let time = arena.symbol("t", SymbolKind::Time);
    let zero = arena.int(0);
    Model {
        name: "Test".into(),
        doc: vec![],
        public: true,
        arena,
        time,
        parameters: vec![],
        coordinates: coords
            .iter()
            .map(|(name, [q, qd, qdd])| Coordinate {
                name: name.to_string(),
                q: *q,
                qd: *qd,
                qdd: *qdd,
                guess: 0.0,
                guess_expr: zero,
                location: Location::default(),
            })
            .collect(),
        independent: vec![],
        kinetic,
        kinetic_location: Location::default(),
        potential,
        constraints: constraints
            .into_iter()
            .enumerate()
            .map(|(k, expr)| Constraint {
                expr,
                location: Location::default(),
                joint: format!("constraint {}", k + 1),
                component: String::new(),
            })
            .collect(),
        vanished_rows: vec![],
        velocity_constraints: vec![],
        forces: vec![zero; coords.len()],
        drawing: Default::default(),
        links: Vec::new(),
        kinetic_from_links: false,
        potential_from_links: false,
        gravity: None,
        rotations: Vec::new(),
        link_bodies: Vec::new(),
    }
}

/// A state at which to compare: values of q, q', t and of other named symbols (parameters).
pub struct State<'a> {
    /// q
    pub q: &'a [f64],
    /// q'
    pub qd: &'a [f64],
    /// t
    pub t: f64,
    /// (parameter name, value)
    pub params: &'a [(&'a str, f64)],
}

/// Binds q, q', t and the parameters; `over(s)` gives the dual seed of symbol s, if any.
fn bind<D: DualNum<Primitive = f64> + Copy>(
    model: &Model,
    st: &State,
    over: &dyn Fn(SymbolId, f64) -> Option<D>,
) -> impl Fn(SymbolId) -> Option<D> + use<D> {
    let a = &model.arena;
    let mut table: Vec<(SymbolId, f64)> = Vec::new();
    for (k, c) in model.coordinates.iter().enumerate() {
        table.push((a.as_symbol(c.q).unwrap(), st.q[k]));
        table.push((a.as_symbol(c.qd).unwrap(), st.qd[k]));
    }
    table.push((a.as_symbol(model.time).unwrap(), st.t));
    for (name, v) in st.params {
        table.push((a.lookup(name).unwrap(), *v));
    }
    let seeds: Vec<(SymbolId, D)> = table
        .iter()
        .map(|&(s, v)| (s, over(s, v).unwrap_or(D::from(v))))
        .collect();
    move |s| seeds.iter().find(|p| p.0 == s).map(|p| p.1)
}

/// Our equations evaluated at a state, with the crate's evaluator (q'' unbound).
pub fn eval_equations(model: &Model, eqs: &Equations, st: &State) -> EvaluatedEquations {
    try_eval_equations(model, eqs, st).expect("the equations evaluate at this state")
}

/// As [`eval_equations`]; `None` where the evaluator reports an error (e.g. a division by
/// zero at this state).
pub fn try_eval_equations(
    model: &Model,
    eqs: &Equations,
    st: &State,
) -> Option<EvaluatedEquations> {
    let env = bind::<f64>(model, st, &|_, _| None);
    let ev =
        |m: &mechanism_codegen::Matrix| mechanism_codegen::eval_matrix(&model.arena, m, &env).ok();
    Some(EvaluatedEquations {
        mass: ev(&eqs.mass)?,
        // Khang's C of a tree of links is derived only where a routine needs it.
        coriolis_matrix: match &eqs.coriolis_matrix {
            Some(c) => ev(c)?,
            None => Vec::new(),
        },
        coriolis_forces: ev(&eqs.coriolis_forces)?,
        gravity: ev(&eqs.gravity)?,
        phi: ev(&eqs.phi)?,
        phi_q: ev(&eqs.phi_q)?,
        phi_t: ev(&eqs.phi_t)?,
        gamma: ev(&eqs.gamma)?,
    })
}

/// Numeric values of the derived equations (row-major).
#[derive(Debug, Clone)]
pub struct EvaluatedEquations {
    /// M
    pub mass: Vec<f64>,
    /// Khang's C
    pub coriolis_matrix: Vec<f64>,
    /// C q' (or h)
    pub coriolis_forces: Vec<f64>,
    /// g
    pub gravity: Vec<f64>,
    /// Phi
    pub phi: Vec<f64>,
    /// Phi_q
    pub phi_q: Vec<f64>,
    /// Phi_t
    pub phi_t: Vec<f64>,
    /// gamma
    pub gamma: Vec<f64>,
}

/// The same quantities from T, Pi and Phi by forward-mode num-dual alone (no symbolic
/// derivative): M_ij = d2T/dq_i'dq_j' (hyper-dual), h_i = d/dt(dT/dq_i')|_{q''=0} - dT/dq_i
/// (hyper-dual with eps1 on q_i' and eps2 along (q + e q', t + e)), g_i = dPi/dq_i,
/// Phi_q and Phi_t (duals), gamma = -d2/de2 Phi(q + e q', t + e) (second-order dual).
pub fn oracle_equations(model: &Model, st: &State) -> EvaluatedEquations {
    let a = &model.arena;
    let n = model.coordinates.len();
    let qs: Vec<SymbolId> = model
        .coordinates
        .iter()
        .map(|c| a.as_symbol(c.q).unwrap())
        .collect();
    let vs: Vec<SymbolId> = model
        .coordinates
        .iter()
        .map(|c| a.as_symbol(c.qd).unwrap())
        .collect();
    let ts = a.as_symbol(model.time).unwrap();
    let mut mass = vec![0.0; n * n];
    let mut h = vec![0.0; n];
    let mut gravity = vec![0.0; n];
    for i in 0..n {
        for j in 0..n {
            let env = bind::<HyperDual64>(model, st, &|s, v| {
                let e1 = if s == vs[i] { 1.0 } else { 0.0 };
                let e2 = if s == vs[j] { 1.0 } else { 0.0 };
                Some(HyperDual64::new(v, e1, e2, 0.0))
            });
            mass[i * n + j] = eval_node(a, model.kinetic, &env).unwrap().eps1eps2;
        }
        let env = bind::<HyperDual64>(model, st, &|s, v| {
            let e1 = if s == vs[i] { 1.0 } else { 0.0 };
            let e2 = qs
                .iter()
                .position(|&q| q == s)
                .map_or(if s == ts { 1.0 } else { 0.0 }, |k| st.qd[k]);
            Some(HyperDual64::new(v, e1, e2, 0.0))
        });
        let ddt_p = eval_node(a, model.kinetic, &env).unwrap().eps1eps2;
        let env = bind::<Dual64>(model, st, &|s, v| {
            Some(Dual64::new(v, if s == qs[i] { 1.0 } else { 0.0 }))
        });
        let dtdq = eval_node(a, model.kinetic, &env).unwrap().eps;
        h[i] = ddt_p - dtdq;
        gravity[i] = eval_node(a, model.potential, &env).unwrap().eps;
    }
    let m = model.constraints.len();
    let (mut phi, mut phi_q, mut phi_t, mut gamma) =
        (vec![0.0; m], vec![0.0; m * n], vec![0.0; m], vec![0.0; m]);
    for (r, c) in model.constraints.iter().enumerate() {
        let env = bind::<f64>(model, st, &|_, _| None);
        phi[r] = eval_node(a, c.expr, &env).unwrap();
        for j in 0..n {
            let env = bind::<Dual64>(model, st, &|s, v| {
                Some(Dual64::new(v, if s == qs[j] { 1.0 } else { 0.0 }))
            });
            phi_q[r * n + j] = eval_node(a, c.expr, &env).unwrap().eps;
        }
        let env = bind::<Dual64>(model, st, &|s, v| {
            Some(Dual64::new(v, if s == ts { 1.0 } else { 0.0 }))
        });
        phi_t[r] = eval_node(a, c.expr, &env).unwrap().eps;
        let env = bind::<Dual2_64>(model, st, &|s, v| {
            let d = qs
                .iter()
                .position(|&q| q == s)
                .map_or(if s == ts { 1.0 } else { 0.0 }, |k| st.qd[k]);
            Some(Dual2_64::new(v, d, 0.0))
        });
        gamma[r] = -eval_node(a, c.expr, &env).unwrap().v2;
    }
    EvaluatedEquations {
        mass,
        coriolis_matrix: vec![],
        coriolis_forces: h,
        gravity,
        phi,
        phi_q,
        phi_t,
        gamma,
    }
}

/// Asserts that `ours` and `oracle` agree entrywise (skipping the oracle's empty fields).
pub fn assert_equations_close(ours: &EvaluatedEquations, oracle: &EvaluatedEquations, tol: f64) {
    let pairs: [(&str, &Vec<f64>, &Vec<f64>); 7] = [
        ("M", &ours.mass, &oracle.mass),
        ("C q'", &ours.coriolis_forces, &oracle.coriolis_forces),
        ("g", &ours.gravity, &oracle.gravity),
        ("Phi", &ours.phi, &oracle.phi),
        ("Phi_q", &ours.phi_q, &oracle.phi_q),
        ("Phi_t", &ours.phi_t, &oracle.phi_t),
        ("gamma", &ours.gamma, &oracle.gamma),
    ];
    for (name, x, y) in pairs {
        assert_eq!(x.len(), y.len(), "{name}: sizes");
        for (k, (a, b)) in x.iter().zip(y.iter()).enumerate() {
            assert!(close(*a, *b, tol), "{name}[{k}]: ours {a} vs oracle {b}");
        }
    }
}

/// y = A x for a row-major n x n A.
pub fn mat_vec(a: &[f64], x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..a.len() / n)
        .map(|i| (0..n).map(|j| a[i * n + j] * x[j]).sum())
        .collect()
}
