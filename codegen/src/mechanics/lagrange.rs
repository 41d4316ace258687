//! Lagrange's equations with multipliers (Van Khang, Mech. Res. Commun. 38, 2011):
//!
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q^T lambda = tau(t, q, q'),   Phi(q, t) = 0,
//! Phi_q q'' = gamma.
//!
//! - M = d2T/dq'dq', upper triangle mirrored: read off the momenta dT/dq' as linear forms
//!   in the rates (`mass_matrix.rs`), or differentiated entry by entry where a momentum is
//!   not of that form;
//! - C by Khang's formula C = (dM/dq)(I_n kron q') - 1/2 [(dM/dq)(q' kron I_n)]^T, its
//!   Kronecker products contracted over the nonzeros of dM/dq (where M_ij depends on q_k);
//! - C q' as its own lean expression: per row k, the coefficient of each monomial
//!   q_i' q_j' (i <= j) is collected first,
//!   (C q')_k = sum_{i,j} (dM_ki/dq_j - 1/2 dM_ij/dq_k) q_i' q_j'
//!   (= (M' q')_k - 1/2 d(q'^T M q')/dq_k, the same vector as Khang's C times q'), so terms
//!   that cancel meet in one canonical sum and vanish before anything is multiplied out;
//! - g = dPi/dq, Phi, Phi_q = dPhi/dq, Phi_t = dPhi/dt (explicit);
//! - gamma = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt, with the Kronecker sum
//!   written over the pairs j <= k (each off-diagonal pair once, doubled).
//!
//! A kinetic energy that is not a quadratic form in q' with q-only coefficients (terms
//! linear in q', a q'-free part T0(q, t), explicit time dependence: moving frames) is handled
//! too: then `coriolis_forces` is the whole rest of the Lagrange expression
//! h = d/dt(dT/dq')|_{q''=0} - dT/dq, so that M q'' + h + g + Phi_q^T lambda = tau is still
//! exact, while `coriolis_matrix` stays Khang's C of M (and C q' differs from h by the
//! non-quadratic terms).

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, FxHashMap, Id, Node, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::{AlgebraError, DerivationError};
use crate::error::{DeclarationError, Error, Location, Result};
use crate::mechanics::equations::Equations;
use crate::mechanics::floating::check_floating;
use crate::mechanics::kinetic_form::{ModelView, check_mass, check_mass_semi_definite};
use crate::mechanics::link_route::{check_moving_mass, energies, frame_equations, quadratic_form};
use crate::mechanics::mass_matrix::mass_from_momenta;
use crate::mechanics::mass_slopes::MassSlopes;
use crate::mechanics::model::Model;
use crate::mechanics::rate_degree::is_homogeneous_quadratic;
use crate::mechanics::recursive::{TreeEquations, tree_equations};

/// The symbols of the coordinates, their rates and accelerations, and of time.
struct Symbols {
    q: Vec<SymbolId>,
    qd: Vec<SymbolId>,
    qdd: Vec<SymbolId>,
    time: Option<SymbolId>,
}

impl Symbols {
    fn of(model: &Model) -> Result<Self> {
        let arena = &model.arena;
        let sym = |id: Id, what: &str, name: &str| -> Result<SymbolId> {
            if id.index() >= arena.len() {
                return Err(Error::Algebra(AlgebraError::InvalidId {
                    id: id.0,
                    len: arena.len(),
                }));
            }
            arena.as_symbol(id).ok_or_else(|| {
                Error::Derivation(DerivationError::NotASymbol {
                    role: format!("the {what} of coordinate `{name}`"),
                })
            })
        };
        let (mut q, mut qd, mut qdd) = (Vec::new(), Vec::new(), Vec::new());
        for c in &model.coordinates {
            q.push(sym(c.q, "position", &c.name)?);
            qd.push(sym(c.qd, "rate", &c.name)?);
            qdd.push(sym(c.qdd, "acceleration", &c.name)?);
        }
        let time = (model.time.index() < arena.len())
            .then(|| arena.as_symbol(model.time))
            .flatten();
        Ok(Self { q, qd, qdd, time })
    }

    fn column(arena: &Arena, syms: &[SymbolId]) -> Matrix {
        Matrix::column(syms.iter().map(|&s| arena.symbol_node(s)).collect())
    }
}

/// Errors unless `id` is in the arena.
fn check_id(arena: &Arena, id: Id) -> Result<()> {
    if id.index() < arena.len() {
        Ok(())
    } else {
        Err(Error::Algebra(AlgebraError::InvalidId {
            id: id.0,
            len: arena.len(),
        }))
    }
}

/// Errors when `id` (the model's `what`) depends on one of `forbidden`.
fn reject_dependence(
    arena: &Arena,
    d: &mut Differentiator,
    id: Id,
    forbidden: &[SymbolId],
    what: &str,
) -> Result<()> {
    for &s in forbidden {
        if d.depends_on(arena, id, s)? {
            return Err(Error::Derivation(DerivationError::ForbiddenDependence {
                what: what.to_string(),
                symbol: arena.symbol_info(s).name.clone(),
            }));
        }
    }
    Ok(())
}

/// Which derivation [`crate::derive_with`] takes for M and C q'.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// The recursive route (composite bodies, Newton-Euler) where the links carry all of T,
    /// Khang's calculus over T otherwise.
    Auto,
    /// Khang's calculus over T always (the reference the recursive route is tested against).
    Lagrange,
}

/// [`crate::derive()`] with the route chosen: the module's formulas in order (M, C, C q', g, Phi,
/// Phi_q, Phi_t, gamma), sharing one Differentiator, so that derivatives are memoised
/// across them.
///
/// # Errors
/// As [`crate::derive()`].
pub fn derive_with(model: &mut Model, route: Route) -> Result<Equations> {
    let s = Symbols::of(model)?;
    let n = s.q.len();
    check_sizes(model, n)?;
    check_floating(model, route == Route::Lagrange)?;
    // The declaration's own expressions first: their dependency sets are then those of
    // the arena's early nodes, not of the whole recursion's.
    let mut d = Differentiator::new();
    check_dependences(model, &mut d, &s)?;
    let tree = if route == Route::Auto && model.kinetic_from_links {
        Some(tree_equations(model)?)
    } else {
        None
    };
    let (kinetic, potential) = match &tree {
        Some(_) => (model.kinetic, model.potential),
        None => energies(model)?,
    };
    let (momenta, mass, kinetic) = mass_and_kinetic(model, &mut d, tree.as_ref(), kinetic, &s)?;
    let view = ModelView {
        coordinates: &model.coordinates,
        parameters: &model.parameters,
        time: model.time,
        at: model.kinetic_location,
    };
    let arena = &mut model.arena;
    match &tree {
        Some(_) => check_mass_semi_definite(arena, &mass, &view)?,
        None => check_mass(arena, &mut d, &mass, &view)?,
    }
    let (coriolis_matrix, coriolis_forces) = match &tree {
        // Khang's C of a tree is derived when a routine needs it (`coriolis_matrix_of`).
        Some(t) => (None, t.coriolis_forces.clone()),
        None => {
            let slopes = MassSlopes::new(arena, &mut d, &mass, &s.q)?;
            let c = khang_coriolis_matrix(arena, &slopes, &s)?;
            let h = coriolis_forces(arena, &mut d, kinetic, &momenta, &mass, &slopes, &s)?;
            (Some(c), h)
        }
    };
    // dPi/dq of the declared potential: all of Pi but for a tree's gravity.
    let declared = Matrix::column(d.gradient(arena, potential, &s.q)?);
    let (gravity, potential) = match &tree {
        Some(t) => (
            t.gravity.add(arena, &declared)?,
            arena.add2(t.potential, potential),
        ),
        None => (declared.clone(), potential),
    };
    let forces = Matrix::column(model.forces.clone());
    let phi = Matrix::column(model.constraints.iter().map(|c| c.expr).collect());
    let (phi_q, phi_t) = constraint_jacobians(arena, &mut d, &phi, &s)?;
    let gamma = gamma(arena, &mut d, &phi_q, &phi_t, &s)?;
    let (inverse_dynamics, bias) = match &tree {
        Some(t) => {
            let id = t.inverse_dynamics.add(arena, &declared)?;
            let b = t.bias.add(arena, &declared)?;
            (id.sub(arena, &forces)?, b.sub(arena, &forces)?)
        }
        None => {
            let qdd = Symbols::column(arena, &s.qdd);
            let parts = Dynamics {
                mass: &mass,
                coriolis_forces: &coriolis_forces,
                gravity: &gravity,
                forces: &forces,
            };
            parts.inverse_and_bias(arena, &qdd)?
        }
    };
    let frames = frame_equations(&model.links);
    if let Some(o) = model.arena.take_overflow() {
        return Err(Error::Derivation(DerivationError::Overflow {
            mechanism: model.name.clone(),
            operation: o.to_string(),
        }));
    }
    Ok(Equations {
        n,
        m: phi.rows,
        velocity_rows: 0,
        mass,
        coriolis_matrix,
        coriolis_forces,
        gravity,
        forces,
        phi,
        phi_q,
        phi_t,
        gamma,
        kinetic,
        potential,
        inverse_dynamics,
        bias,
        frames,
    })
}

/// The momenta dT/dq', M and T: for a tree of links, M from its recursion (refused when
/// identically 0) and T = 1/2 q'^T M q' from the same entries (the links' T is this
/// quadratic form), no momenta; else from `kinetic` ([`mass_by_momenta`]).
fn mass_and_kinetic(
    model: &mut Model,
    d: &mut Differentiator,
    tree: Option<&TreeEquations>,
    kinetic: Id,
    s: &Symbols,
) -> Result<(Vec<Id>, Matrix, Id)> {
    match tree {
        Some(t) => {
            check_moving_mass(model, &t.mass)?;
            let kinetic = quadratic_form(&mut model.arena, &t.mass, &s.qd);
            Ok((Vec::new(), t.mass.clone(), kinetic))
        }
        None => {
            let (momenta, mass) = mass_by_momenta(&mut model.arena, d, kinetic, s)?;
            Ok((momenta, mass, kinetic))
        }
    }
}

/// Errors unless `model` has coordinates and one force per coordinate.
fn check_sizes(model: &Model, n: usize) -> Result<()> {
    if n == 0 {
        let kind = DeclarationError::NoCoordinates {
            mechanism: model.name.clone(),
            empty_section: false,
        };
        return Err(Error::declaration(kind, Location::default()));
    }
    if model.forces.len() != n {
        return Err(Error::Derivation(DerivationError::ForceCount {
            forces: model.forces.len(),
            coordinates: n,
        }));
    }
    Ok(())
}

/// M, C q', g and tau of the energy route.
struct Dynamics<'a> {
    mass: &'a Matrix,
    coriolis_forces: &'a Matrix,
    gravity: &'a Matrix,
    forces: &'a Matrix,
}

impl Dynamics<'_> {
    /// tau_id = M q'' + C q' + g - tau and the bias b = C q' + g - tau, for the column of
    /// accelerations `qdd` (a tree of links has both from Newton-Euler instead).
    fn inverse_and_bias(&self, arena: &mut Arena, qdd: &Matrix) -> Result<(Matrix, Matrix)> {
        let inertial = self
            .mass
            .mul(arena, qdd)?
            .add(arena, self.coriolis_forces)?;
        let id = inertial.add(arena, self.gravity)?.sub(arena, self.forces)?;
        let b = self.coriolis_forces.add(arena, self.gravity)?;
        Ok((id, b.sub(arena, self.forces)?))
    }
}

/// Khang's C of `mass`, the mass matrix of `model` ([`khang_coriolis_matrix`]): what
/// `derive` leaves out for a tree of links (`Equations::coriolis_matrix` is then `None`)
/// and compiling the macro's `coriolis_matrix` asks for.
///
/// # Errors
/// What differentiation reports; [`crate::error::BudgetError`] beyond the arena's budget.
pub(crate) fn coriolis_matrix_of(model: &mut Model, mass: &Matrix) -> Result<Matrix> {
    let s = Symbols::of(model)?;
    let mut d = Differentiator::new();
    let slopes = MassSlopes::new(&mut model.arena, &mut d, mass, &s.q)?;
    khang_coriolis_matrix(&mut model.arena, &slopes, &s)
}

/// Errors when an expression of `model` depends on what it may not: the potential or a
/// constraint on a rate or an acceleration, T or a force on an acceleration; or when one is
/// not a node of the arena.
fn check_dependences(model: &Model, d: &mut Differentiator, s: &Symbols) -> Result<()> {
    let arena = &model.arena;
    let (kinetic, potential) = (model.kinetic, model.potential);
    for &id in [kinetic, potential]
        .iter()
        .chain(&model.forces)
        .chain(model.constraints.iter().map(|c| &c.expr))
    {
        check_id(arena, id)?;
    }
    let rates: Vec<SymbolId> = s.qd.iter().chain(&s.qdd).copied().collect();
    reject_dependence(arena, d, potential, &rates, "potential energy")?;
    reject_dependence(arena, d, kinetic, &s.qdd, "kinetic energy")?;
    for &f in &model.forces {
        reject_dependence(arena, d, f, &s.qdd, "generalised force")?;
    }
    for c in &model.constraints {
        reject_dependence(arena, d, c.expr, &rates, "constraint")?;
    }
    Ok(())
}

/// The momenta p = dT/dq' and M = d2T/dq'dq' (upper triangle, mirrored): M read off the
/// momenta as linear forms in the rates (mass_matrix.rs), or, for a momentum not of that
/// form, by differentiation, only by the rates each momentum depends on (M_ij = 0 where
/// p_i is free of q_j').
fn mass_by_momenta(
    arena: &mut Arena,
    d: &mut Differentiator,
    kinetic: Id,
    s: &Symbols,
) -> Result<(Vec<Id>, Matrix)> {
    let n = s.q.len();
    let momenta = d.gradient(arena, kinetic, &s.qd)?;
    if let Some(mass) = mass_from_momenta(arena, d, &momenta, &s.qd)? {
        return Ok((momenta, mass));
    }
    let mut mass = Matrix::zeros(arena, n, n);
    let rate_index: FxHashMap<SymbolId, usize> =
        s.qd.iter().enumerate().map(|(j, &v)| (v, j)).collect();
    let mut columns = Vec::new();
    for (i, &p) in momenta.iter().enumerate() {
        columns.clear();
        for v in d.symbols_of(arena, p)? {
            columns.extend(rate_index.get(&v).filter(|&&j| j >= i));
        }
        columns.sort_unstable();
        for &j in &columns {
            let mij = d.diff(arena, p, s.qd[j])?;
            mass.set(i, j, mij);
            mass.set(j, i, mij);
        }
    }
    Ok((momenta, mass))
}

/// C q' without links: the lean sum of [`lean_coriolis_forces`] when T is a quadratic form
/// in q', else the whole rest of the Lagrange expression,
/// h_i = d/dt(dT/dq_i')|_{q''=0} - dT/dq_i.
fn coriolis_forces(
    arena: &mut Arena,
    d: &mut Differentiator,
    kinetic: Id,
    momenta: &[Id],
    mass: &Matrix,
    slopes: &MassSlopes,
    s: &Symbols,
) -> Result<Matrix> {
    if is_quadratic_form(arena, d, kinetic, momenta, mass, s)? {
        return lean_coriolis_forces(arena, slopes, s);
    }
    let mut h = Vec::with_capacity(momenta.len());
    for (&p, &q) in momenta.iter().zip(&s.q) {
        let dp = d.convective_derivative(arena, p)?;
        let dtq = d.diff(arena, kinetic, q)?;
        h.push(arena.sub(dp, dtq));
    }
    Ok(Matrix::column(h))
}

/// Phi_q = dPhi/dq (m x n) and Phi_t = dPhi/dt (explicit; m x 1, zeros without time).
fn constraint_jacobians(
    arena: &mut Arena,
    d: &mut Differentiator,
    phi: &Matrix,
    s: &Symbols,
) -> Result<(Matrix, Matrix)> {
    let (m, n) = (phi.rows, s.q.len());
    let mut phi_q = Matrix::zeros(arena, m, n);
    let mut phi_t = Matrix::zeros(arena, m, 1);
    for r in 0..m {
        for j in 0..n {
            let e = d.diff(arena, phi.data[r], s.q[j])?;
            phi_q.set(r, j, e);
        }
        if let Some(t) = s.time {
            let e = d.diff(arena, phi.data[r], t)?;
            phi_t.set(r, 0, e);
        }
    }
    Ok((phi_q, phi_t))
}

/// Khang's C = (dM/dq)(I_n kron q') - 1/2 [(dM/dq)(q' kron I_n)]^T
/// (Van Khang 2011). With this C only q'^T (M' - 2 C) q' = 0 holds; M' - 2 C is not
/// skew-symmetric (the Christoffel C is).
///
/// The products are contracted entry by entry over the nonzeros of dM/dq only:
/// C_ij = sum_k dM_ij/dq_k q_k' - 1/2 sum_k dM_jk/dq_i q_k', each sum over the k where the
/// entry depends on that coordinate. The n x n^2 matrices are never formed, so the work is
/// the number of such (entry, coordinate) pairs (2 n^2 for a chain in absolute angles, 0
/// for an M free of q) plus the n^2 entries of C.
fn khang_coriolis_matrix(arena: &mut Arena, slopes: &MassSlopes, s: &Symbols) -> Result<Matrix> {
    let n = s.q.len();
    // The slopes were formed first; the passes below run in the order of the dense
    // products they replace (the first product row by row, the second, then entry by
    // entry the scaling and the difference), so the expressions are created in that order
    // and print the same.
    let zero = arena.int(0);
    if slopes.is_empty() {
        // M is free of q: C = 0, without the passes' n x n scratch (at 5,000 coordinates
        // each is 100 MB).
        return Ok(Matrix::zeros(arena, n, n));
    }
    let mut acc: Vec<Vec<Id>> = vec![Vec::new(); n];
    // (dM/dq)(I kron q')_ij = sum_k dM_ij/dq_k q_k'.
    let mut first = vec![zero; n * n];
    for i in 0..n {
        for (j, column) in acc.iter_mut().enumerate() {
            for (k, e) in slopes.of(i, j) {
                let v = arena.symbol_node(s.qd[k]);
                column.push(arena.mul2(e, v));
            }
        }
        for (j, terms) in acc.iter_mut().enumerate() {
            if !terms.is_empty() {
                first[i * n + j] = arena.add(terms);
                terms.clear();
            }
        }
    }
    // (dM/dq)(q' kron I)_ij = sum_k dM_ik/dq_j q_k'.
    let mut second = vec![zero; n * n];
    for i in 0..n {
        for k in 0..n {
            for (j, e) in slopes.of(i, k) {
                let v = arena.symbol_node(s.qd[k]);
                acc[j].push(arena.mul2(e, v));
            }
        }
        for (j, terms) in acc.iter_mut().enumerate() {
            if !terms.is_empty() {
                second[i * n + j] = arena.add(terms);
                terms.clear();
            }
        }
    }
    // C = first - 1/2 second^T: -1/2 distributed over each sum once (not 1/2, then -1).
    let minus_half = arena.rational(-1, 2)?;
    let mut data = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (first[i * n + j], second[j * n + i]);
            data.push(if b == zero {
                a
            } else {
                let scaled = arena.mul2(minus_half, b);
                arena.add2(a, scaled)
            });
        }
    }
    Matrix::new(n, n, data)
}

/// True when T = 1/2 q'^T M(q) q' exactly: T and M free of t, M free of q', and T and
/// dT/dq' vanish at q' = 0 (no q'-free part, no part linear in q').
fn is_quadratic_form(
    arena: &mut Arena,
    d: &mut Differentiator,
    kinetic: Id,
    momenta: &[Id],
    mass: &Matrix,
    s: &Symbols,
) -> Result<bool> {
    let mut varying: Vec<SymbolId> = s.qd.clone();
    varying.extend(s.time);
    if let Some(t) = s.time
        && d.depends_on(arena, kinetic, t)?
    {
        return Ok(false);
    }
    // One look-up of each entry's symbols (constant entries have none), not one per
    // (entry, rate) pair: n^2 entries times n rates is the cost of large mechanisms.
    let mut is_varying = vec![false; arena.symbols().len()];
    for v in &varying {
        is_varying[v.index()] = true;
    }
    for &e in &mass.data {
        if arena.as_number(e).is_none() && d.depends_on_any(arena, e, &is_varying)? {
            return Ok(false);
        }
    }
    // Every monomial of degree 2 in q' proves it in one pass over T's graph; the
    // substitution below is exact also where a q'-free or linear part cancels, but it
    // rebuilds T and every momentum (n^2 terms in a chain).
    let mut is_rate = vec![false; arena.symbols().len()];
    for v in &s.qd {
        is_rate[v.index()] = true;
    }
    if is_homogeneous_quadratic(arena, kinetic, &is_rate) {
        return Ok(true);
    }
    let zero = arena.int(0);
    let at_rest: FxHashMap<SymbolId, Id> = s.qd.iter().map(|&v| (v, zero)).collect();
    let roots: Vec<Id> = std::iter::once(kinetic)
        .chain(momenta.iter().copied())
        .collect();
    Ok(match substitute_all(arena, d, &roots, &at_rest) {
        Ok(images) => images.iter().all(|&z| arena.is_zero(z)),
        Err(_) => false,
    })
}

/// `id` with each symbol of `map` replaced by its image, rebuilt with the canonical
/// constructors (children first).
pub(crate) fn substitute(
    arena: &mut Arena,
    d: &mut Differentiator,
    id: Id,
    map: &FxHashMap<SymbolId, Id>,
) -> Result<Id> {
    Ok(substitute_all(arena, d, &[id], map)?[0])
}

/// [`substitute`] for each of `ids`, every shared subexpression rebuilt once (the momenta of
/// a chain share the bars' velocities: one by one they would be rebuilt once per momentum).
pub(crate) fn substitute_all(
    arena: &mut Arena,
    d: &mut Differentiator,
    ids: &[Id],
    map: &FxHashMap<SymbolId, Id>,
) -> Result<Vec<Id>> {
    let mut marked = vec![false; arena.symbols().len()];
    for k in map.keys() {
        if let Some(m) = marked.get_mut(k.index()) {
            *m = true;
        }
    }
    let mut todo = Vec::new();
    let mut stack = ids.to_vec();
    let mut seen: FxHashMap<Id, ()> = FxHashMap::default();
    while let Some(n) = stack.pop() {
        if seen.insert(n, ()).is_some() || !d.depends_on_any(arena, n, &marked)? {
            continue;
        }
        todo.push(n);
        stack.extend(arena.children(n));
    }
    todo.sort_unstable();
    let mut image: FxHashMap<Id, Id> = FxHashMap::default();
    for n in todo {
        let get = |c: Id| image.get(&c).copied().unwrap_or(c);
        let new = match arena.node(n).clone() {
            Node::Sym(x) => map.get(&x).copied().unwrap_or(n),
            Node::Add(v) => {
                let v: Vec<Id> = v.iter().map(|&c| get(c)).collect();
                arena.add(&v)
            }
            Node::Mul(v) => {
                let v: Vec<Id> = v.iter().map(|&c| get(c)).collect();
                arena.mul(&v)
            }
            Node::Pow(b, e) => arena.pow(get(b), get(e))?,
            Node::Func(f, u) => arena.func(f, get(u))?,
            Node::Atan2(y, x) => arena.atan2(get(y), get(x)),
            Node::Named(x) => arena.named(get(x)),
            Node::Num(_) | Node::Pi => n,
        };
        image.insert(n, new);
    }
    Ok(ids
        .iter()
        .map(|id| image.get(id).copied().unwrap_or(*id))
        .collect())
}

/// C q' as one lean expression per row: (C q')_k = sum_{i <= j} c_kij q_i' q_j' with
/// c_kij = dM_ki/dq_j + dM_kj/dq_i - dM_ij/dq_k for i < j and
/// c_kii = dM_ki/dq_i - 1/2 dM_ii/dq_k, each coefficient one canonical sum.
fn lean_coriolis_forces(arena: &mut Arena, slopes: &MassSlopes, s: &Symbols) -> Result<Matrix> {
    let n = s.q.len();
    if slopes.is_empty() {
        // M is free of q: C q' = 0.
        return Ok(Matrix::zeros(arena, n, 1));
    }
    // by_coord[k]: the upper entries (i, j) of M that depend on q_k, and dM_ij/dq_k.
    let mut by_coord: Vec<Vec<(usize, usize, Id)>> = vec![Vec::new(); n];
    for i in 0..n {
        for j in i..n {
            for (k, e) in slopes.of(i, j) {
                by_coord[k].push((i, j, e));
            }
        }
    }
    // Each part is (pair, slope, weight in halves). Parts of one pair with the same slope
    // are added up before any node is made: M is symmetric, so for j = k the parts
    // dM_ki/dq_k and -dM_ik/dq_k are one node and cancel (half of a chain's parts).
    let mut out = Vec::with_capacity(n);
    let mut parts: Vec<((usize, usize), Id, i32)> = Vec::new();
    let mut group = Vec::new();
    for (k, upper) in by_coord.iter().enumerate() {
        parts.clear();
        for i in 0..n {
            for (j, e) in slopes.of(k, i) {
                parts.push(((i.min(j), i.max(j)), e, 2));
            }
        }
        for &(i, j, e) in upper {
            parts.push(((i, j), e, if i == j { -1 } else { -2 }));
        }
        parts.sort_by_key(|p| (p.0, p.1));
        let mut terms = Vec::new();
        let mut a = 0;
        while a < parts.len() {
            let pair = parts[a].0;
            group.clear();
            while a < parts.len() && parts[a].0 == pair {
                let (e, mut halves) = (parts[a].1, 0);
                while a < parts.len() && parts[a].0 == pair && parts[a].1 == e {
                    halves += parts[a].2;
                    a += 1;
                }
                match halves {
                    0 => {}
                    2 => group.push(e),
                    _ => {
                        let w = arena.rational(i64::from(halves), 2)?;
                        group.push(arena.mul2(w, e));
                    }
                }
            }
            if group.is_empty() {
                continue;
            }
            let coef = arena.add(&group);
            if !arena.is_zero(coef) {
                let (vi, vj) = (
                    arena.symbol_node(s.qd[pair.0]),
                    arena.symbol_node(s.qd[pair.1]),
                );
                terms.push(arena.mul(&[coef, vi, vj]));
            }
        }
        out.push(arena.add(&terms));
    }
    Ok(Matrix::column(out))
}

/// gamma = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt, per row
/// -sum_{j <= k} w_jk d(Phi_q)_rj/dq_k q_j' q_k' (w = 1 on the diagonal, 2 off it)
/// - 2 sum_j d(Phi_q)_rj/dt q_j' - d(Phi_t)_r/dt.
fn gamma(
    arena: &mut Arena,
    d: &mut Differentiator,
    phi_q: &Matrix,
    phi_t: &Matrix,
    s: &Symbols,
) -> Result<Matrix> {
    let n = s.q.len();
    let (m1, m2) = (arena.int(-1), arena.int(-2));
    // The coordinate index of each symbol: an entry is differentiated by the coordinates
    // its dependency set holds, not tried against all n (m n^2 look-ups on A02).
    let mut coordinate_of = vec![None; arena.symbols().len()];
    for (k, q) in s.q.iter().enumerate() {
        coordinate_of[q.index()] = Some(k);
    }
    let mut out = Vec::with_capacity(phi_q.rows);
    let mut ks: Vec<usize> = Vec::new();
    for r in 0..phi_q.rows {
        let mut terms = Vec::new();
        for j in 0..n {
            let e = phi_q.get(r, j);
            let vj = arena.symbol_node(s.qd[j]);
            ks.clear();
            ks.extend(
                d.symbols_of(arena, e)?
                    .iter()
                    .filter_map(|x| coordinate_of.get(x.index()).copied().flatten())
                    .filter(|&k| k >= j),
            );
            ks.sort_unstable();
            for &k in &ks {
                let h = d.diff(arena, e, s.q[k])?;
                let vk = arena.symbol_node(s.qd[k]);
                let w = if j == k { m1 } else { m2 };
                terms.push(arena.mul(&[w, h, vj, vk]));
            }
            if let Some(t) = s.time {
                let et = d.diff(arena, e, t)?;
                if !arena.is_zero(et) {
                    terms.push(arena.mul(&[m2, et, vj]));
                }
            }
        }
        if let Some(t) = s.time {
            let tt = d.diff(arena, phi_t.get(r, 0), t)?;
            terms.push(arena.neg(tt));
        }
        out.push(arena.add(&terms));
    }
    Ok(Matrix::column(out))
}

/// The Christoffel-symbol factorisation (the second route for C):
/// C_ij = sum_k Gamma_ijk q_k', Gamma_ijk = 1/2 (dM_ij/dq_k + dM_ik/dq_j - dM_jk/dq_i).
/// With it, M' - 2C is skew-symmetric, and C q' equals Khang's C q'.
///
/// # Errors
/// [`crate::error::AlgebraError::Shape`] when `eqs.mass` is not n x n for the model's n
/// coordinates; as [`crate::derive()`] otherwise.
pub fn christoffel_coriolis_matrix(model: &mut Model, eqs: &Equations) -> Result<Matrix> {
    let s = Symbols::of(model)?;
    let n = s.q.len();
    let arena = &mut model.arena;
    let mass = &eqs.mass;
    mass.validate(arena)?;
    if mass.rows != n || mass.cols != n {
        return Err(Error::Algebra(AlgebraError::Shape {
            operation: "christoffel",
            left_rows: mass.rows,
            left_cols: mass.cols,
            right_rows: n,
            right_cols: n,
        }));
    }
    let mut d = Differentiator::new();
    let half = arena.rational(1, 2)?;
    let mut c = Matrix::zeros(arena, n, n);
    for i in 0..n {
        for j in 0..n {
            let mut terms = Vec::new();
            for k in 0..n {
                let a = d.diff(arena, mass.get(i, j), s.q[k])?;
                let b = d.diff(arena, mass.get(i, k), s.q[j])?;
                let e = d.diff(arena, mass.get(j, k), s.q[i])?;
                let sum = arena.add(&[a, b]);
                let g = arena.sub(sum, e);
                if arena.is_zero(g) {
                    continue;
                }
                let v = arena.symbol_node(s.qd[k]);
                terms.push(arena.mul(&[half, g, v]));
            }
            let cij = arena.add(&terms);
            c.set(i, j, cij);
        }
    }
    Ok(c)
}

/// C q' with the Christoffel C of [`christoffel_coriolis_matrix`] (n x 1): the second route
/// to `eqs.coriolis_forces`.
///
/// # Errors
/// As [`christoffel_coriolis_matrix`].
pub fn christoffel_coriolis_forces(model: &mut Model, eqs: &Equations) -> Result<Matrix> {
    let c = christoffel_coriolis_matrix(model, eqs)?;
    let s = Symbols::of(model)?;
    let qd = Symbols::column(&model.arena, &s.qd);
    c.mul(&mut model.arena, &qd)
}
