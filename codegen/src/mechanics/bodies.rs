//! Bodies: the kinetic and potential energy and the damper forces of rigid bodies, point
//! masses, springs and dampers, derived from positions and direction-cosine matrices (the
//! seed's orthogonal projection method, Section 2.2, without writing T by hand).
//!
//! For body b with mass m_b, centre of mass r_b(q, t) (world), orientation R_b(q, t) (body to
//! world) and inertia I_b about the centre of mass in body axes:
//! - v_b = J_v q' + v_t with J_v = dr_b/dq (3 x n) and v_t = dr_b/dt;
//! - w_b = J_w q' + w_t, the body angular velocity of [w]x = R^T R'
//!   (see [`crate::Orientation::angular_jacobian`]);
//! - T = sum_b 1/2 m_b v_b^T v_b + 1/2 w_b^T I_b w_b
//!   = 1/2 q'^T M q' + b^T q' + T_0 with
//!   M = sum_b m_b J_v^T J_v + J_w^T I_b J_w (formed directly from the Jacobians: each entry
//!   one canonical sum, nothing is differentiated twice),
//!   b = sum_b m_b J_v^T v_t + J_w^T I_b w_t and T_0 = sum_b 1/2 m_b v_t^T v_t + 1/2 w_t^T I_b w_t;
//! - Pi = -sum_b m_b g . r_b + sum_springs 1/2 k (|P - Q| - L_0)^2
//!   (1/2 k |P - Q|^2 when L_0 is the constant 0: no square root);
//! - a damper between P and Q pulls along e = (P - Q)/|P - Q| with the force
//!   F_P = -c (d/dt |P - Q|) e = -F_Q; its generalised force is
//!   tau = J_P^T F_P + J_Q^T F_Q = -c (d . d') / (d . d) J_d^T d, d = P - Q, J_d = dd/dq,
//!   d' = J_d q' + dd/dt (no square root either).
//!
//! The model receives T as the expression 1/2 q'^T M q' + b^T q' + T_0 (built from the entries
//! of M, so [`crate::derive`] gets M back as the very same nodes); Pi and tau are added to
//! what the declaration wrote by hand.

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, Id, SymbolId, Vec3};
use crate::algebra::matrix::Matrix;
use crate::error::{AlgebraError, DerivationError};
use crate::error::{Error, Result};
use crate::mechanics::model::Model;

pub use crate::mechanics::rigid_body::Body;

/// A linear spring between two points: Pi = 1/2 k (|P - Q| - L_0)^2.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Spring {
    /// Name, as declared.
    pub name: String,
    /// P and Q (world).
    pub ends: [Vec3; 2],
    /// Stiffness k.
    pub stiffness: Id,
    /// Free length L_0.
    pub free_length: Id,
}

/// A linear damper between two points: F_P = -c (d/dt |P - Q|) (P - Q)/|P - Q| = -F_Q.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Damper {
    /// Name, as declared.
    pub name: String,
    /// P and Q (world).
    pub ends: [Vec3; 2],
    /// Coefficient c.
    pub coefficient: Id,
}

/// Everything the energies are derived from.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BodySystem {
    /// Bodies and point masses.
    pub bodies: Vec<Body>,
    /// Gravity acceleration vector g (world); `None`: no gravity.
    pub gravity: Option<Vec3>,
    /// Springs.
    pub springs: Vec<Spring>,
    /// Dampers.
    pub dampers: Vec<Damper>,
}

/// What [`body_terms`] derives.
#[derive(Clone, Debug)]
pub struct BodyTerms {
    /// M = sum m J_v^T J_v + J_w^T I J_w (n x n).
    pub mass: Matrix,
    /// T = 1/2 q'^T M q' + b^T q' + T_0.
    pub kinetic: Id,
    /// Pi (gravity and springs).
    pub potential: Id,
    /// Damper generalised forces tau (n entries).
    pub forces: Vec<Id>,
}

/// The coordinate, rate and time symbols of a model.
struct Symbols {
    q: Vec<SymbolId>,
    qd: Vec<Id>,
    time: Option<SymbolId>,
}

impl Symbols {
    fn of(model: &Model) -> Result<Self> {
        let arena = &model.arena;
        let mut q = Vec::new();
        let mut qd = Vec::new();
        for c in &model.coordinates {
            let s = (c.q.index() < arena.len())
                .then(|| arena.as_symbol(c.q))
                .flatten()
                .ok_or_else(|| {
                    Error::Derivation(DerivationError::NotASymbol {
                        role: format!("coordinate `{}`", c.name),
                    })
                })?;
            if c.qd.index() >= arena.len() {
                return Err(Error::Algebra(AlgebraError::InvalidId {
                    id: c.qd.0,
                    len: arena.len(),
                }));
            }
            q.push(s);
            qd.push(c.qd);
        }
        let time = (model.time.index() < arena.len())
            .then(|| arena.as_symbol(model.time))
            .flatten();
        Ok(Self { q, qd, time })
    }
}

/// dot(a, b) = sum a_i b_i.
pub(crate) fn dot(arena: &mut Arena, a: &[Id], b: &[Id]) -> Id {
    let terms: Vec<Id> = a.iter().zip(b).map(|(&x, &y)| arena.mul2(x, y)).collect();
    arena.add(&terms)
}

/// a - b componentwise.
pub(crate) fn sub3(arena: &mut Arena, a: &Vec3, b: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| arena.sub(a[i], b[i]))
}

/// The Jacobian dv/dq (3 x n) and dv/dt of a vector v(q, t).
fn jacobian(
    arena: &mut Arena,
    d: &mut Differentiator,
    v: &Vec3,
    s: &Symbols,
) -> Result<(Matrix, Vec3)> {
    let n = s.q.len();
    let mut j = Matrix::zeros(arena, 3, n);
    let mut vt = [arena.int(0); 3];
    for i in 0..3 {
        for (k, &qk) in s.q.iter().enumerate() {
            let e = d.diff(arena, v[i], qk)?;
            j.set(i, k, e);
        }
        if let Some(t) = s.time {
            vt[i] = d.diff(arena, v[i], t)?;
        }
    }
    Ok((j, vt))
}

/// Errors unless `id` is free of the rates and accelerations of the model.
fn check_position_level(arena: &Arena, model: &Model, id: Id, what: &str) -> Result<()> {
    if id.index() >= arena.len() {
        return Err(Error::Algebra(AlgebraError::InvalidId {
            id: id.0,
            len: arena.len(),
        }));
    }
    for c in &model.coordinates {
        for r in [c.qd, c.qdd] {
            if let Some(s) = arena.as_symbol(r)
                && arena.depends_on(id, s)
            {
                return Err(Error::Derivation(DerivationError::NotPositionLevel {
                    what: what.to_string(),
                    symbol: arena.symbol_info(s).name.clone(),
                }));
            }
        }
    }
    Ok(())
}

/// Validates every expression of `system` against `model` (ids in the arena, no rates in
/// positions, orientations, inertias, masses, stiffnesses).
fn check_system(model: &Model, system: &BodySystem) -> Result<()> {
    let a = &model.arena;
    for b in &system.bodies {
        let what = format!("position of body `{}`", b.name);
        for &e in &b.position {
            check_position_level(a, model, e, &what)?;
        }
        check_position_level(a, model, b.mass, &format!("mass of body `{}`", b.name))?;
        if let Some(i) = &b.inertia {
            if (i.rows, i.cols) != (3, 3) {
                return Err(Error::Derivation(DerivationError::InertiaShape {
                    body: b.name.clone(),
                    rows: i.rows,
                    cols: i.cols,
                }));
            }
            i.validate(a)?;
            for &e in &i.data {
                check_position_level(a, model, e, &format!("inertia of body `{}`", b.name))?;
            }
        }
        if let Some(o) = &b.orientation {
            for f in &o.factors {
                let ids: Vec<Id> = match f {
                    crate::algebra::rotation::RotationFactor::Elementary(_, x) => vec![*x],
                    crate::algebra::rotation::RotationFactor::Explicit(m) => {
                        m.validate(a)?;
                        m.data.clone()
                    }
                };
                for e in ids {
                    check_position_level(
                        a,
                        model,
                        e,
                        &format!("orientation of body `{}`", b.name),
                    )?;
                }
            }
        }
    }
    for &e in system.gravity.iter().flatten() {
        check_position_level(a, model, e, "gravity vector")?;
    }
    for s in &system.springs {
        for &e in s
            .ends
            .iter()
            .flatten()
            .chain([&s.stiffness, &s.free_length])
        {
            check_position_level(a, model, e, &format!("spring `{}`", s.name))?;
        }
    }
    for s in &system.dampers {
        for &e in s.ends.iter().flatten().chain([&s.coefficient]) {
            check_position_level(a, model, e, &format!("damper `{}`", s.name))?;
        }
    }
    Ok(())
}

/// Derives M, T, Pi and the damper forces of `system` in the coordinates of `model` (the
/// formulas are in the module documentation). All expressions are built in `model.arena`;
/// the model itself is not changed.
///
/// # Errors
/// [`crate::error::DerivationError::NotASymbol`] when a coordinate is not a symbol,
/// [`crate::error::DerivationError::NotPositionLevel`] when a position, orientation, mass,
/// inertia, gravity, spring or damper expression depends on a rate or an acceleration,
/// [`crate::error::DerivationError::InertiaShape`] when an inertia is not 3x3;
/// [`crate::error::AlgebraError::InvalidId`] for a foreign id; differentiation errors.
pub fn body_terms(model: &mut Model, system: &BodySystem) -> Result<BodyTerms> {
    check_system(model, system)?;
    let s = Symbols::of(model)?;
    let n = s.q.len();
    let arena = &mut model.arena;
    let mut d = Differentiator::new();
    let half = arena.rational(1, 2)?;
    let mut quadratic = QuadraticTerms {
        m: vec![Vec::new(); n * n],
        b: vec![Vec::new(); n],
        t0: Vec::new(),
    };
    let mut pi_terms = body_kinetic_and_gravity(arena, &mut d, system, &s, &mut quadratic)?;
    pi_terms.extend(spring_potentials(arena, system, half)?);
    let (mass, kinetic) = quadratic.mass_and_kinetic(arena, &s, half)?;
    let potential = arena.add(&pi_terms);
    let forces = damper_forces(arena, &mut d, system, &s)?;
    Ok(BodyTerms {
        mass,
        kinetic,
        potential,
        forces,
    })
}

/// The terms of T = 1/2 q'^T M q' + b . q' + T_0 as lists: entry (i, j), i <= j, of M
/// (`m`, row-major n x n), of b and of T_0.
struct QuadraticTerms {
    m: Vec<Vec<Id>>,
    b: Vec<Vec<Id>>,
    t0: Vec<Id>,
}

impl QuadraticTerms {
    /// Adds 1/2 (J q' + x_t)^T W (J q' + x_t) ([`add_quadratic`]).
    fn add(&mut self, arena: &mut Arena, j: &Matrix, xt: &Vec3, w: &Weight<'_>) -> Result<()> {
        add_quadratic(arena, &mut self.m, &mut self.b, &mut self.t0, j, xt, w)
    }

    /// M (symmetric) and T = 1/2 sum_i M_ii q_i'^2 + sum_{i<j} M_ij q_i' q_j' + b . q' + T_0.
    fn mass_and_kinetic(&self, arena: &mut Arena, s: &Symbols, half: Id) -> Result<(Matrix, Id)> {
        let n = s.qd.len();
        let mut mass = Matrix::zeros(arena, n, n);
        for i in 0..n {
            for j in i..n {
                let e = arena.add(&self.m[i * n + j]);
                mass.set(i, j, e);
                mass.set(j, i, e);
            }
        }
        let mut t_terms = Vec::new();
        for (i, terms) in self.b.iter().enumerate() {
            let vi = s.qd[i];
            let mii = mass.get(i, i);
            if !arena.is_zero(mii) {
                let v2 = arena.powi(vi, 2)?;
                t_terms.push(arena.mul(&[half, mii, v2]));
            }
            for j in i + 1..n {
                let mij = mass.get(i, j);
                if !arena.is_zero(mij) {
                    t_terms.push(arena.mul(&[mij, vi, s.qd[j]]));
                }
            }
            let bi = arena.add(terms);
            if !arena.is_zero(bi) {
                t_terms.push(arena.mul2(bi, vi));
            }
        }
        let t0 = arena.add(&self.t0);
        t_terms.push(t0);
        let kinetic = arena.add(&t_terms);
        Ok((mass, kinetic))
    }
}

/// Each body's 1/2 m v^T v and 1/2 w^T I w into `quadratic`; returns its gravity terms of
/// Pi, -m g . r.
fn body_kinetic_and_gravity(
    arena: &mut Arena,
    d: &mut Differentiator,
    system: &BodySystem,
    s: &Symbols,
    quadratic: &mut QuadraticTerms,
) -> Result<Vec<Id>> {
    let mut pi_terms = Vec::new();
    for body in &system.bodies {
        let m = body.mass;
        if arena.is_zero(m) && body.inertia.is_none() {
            continue;
        }
        let (jv, vt) = jacobian(arena, d, &body.position, s)?;
        quadratic.add(arena, &jv, &vt, &Weight::Scalar(m))?;
        if let (Some(o), Some(inertia)) = (&body.orientation, &body.inertia)
            && !inertia.is_zero(arena)
        {
            let (jw, wt) = o.angular_jacobian(arena, d, &s.q, s.time)?;
            quadratic.add(arena, &jw, &wt, &Weight::Tensor(inertia))?;
        }
        if let Some(g) = &system.gravity {
            let gr = dot(arena, g, &body.position);
            let minus_one = arena.int(-1);
            let e = arena.mul(&[minus_one, m, gr]);
            pi_terms.push(e);
        }
    }
    Ok(pi_terms)
}

/// Each spring's 1/2 k (|d| - l_0)^2 (1/2 k |d|^2 when l_0 = 0), d the difference of its
/// ends.
fn spring_potentials(arena: &mut Arena, system: &BodySystem, half: Id) -> Result<Vec<Id>> {
    let mut pi_terms = Vec::new();
    for sp in &system.springs {
        let dvec = sub3(arena, &sp.ends[0], &sp.ends[1]);
        let dd = dot(arena, &dvec, &dvec);
        let stretch2 = if arena.is_zero(sp.free_length) {
            dd
        } else {
            let len = arena.sqrt(dd)?;
            let st = arena.sub(len, sp.free_length);
            arena.powi(st, 2)?
        };
        pi_terms.push(arena.mul(&[half, sp.stiffness, stretch2]));
    }
    Ok(pi_terms)
}

/// The generalised forces of the dampers: Q_k = -c (d . d' / d . d) (J_d,k . d) for each,
/// with d' = J_d q' + dd/dt.
fn damper_forces(
    arena: &mut Arena,
    d: &mut Differentiator,
    system: &BodySystem,
    s: &Symbols,
) -> Result<Vec<Id>> {
    let n = s.qd.len();
    let zero = arena.int(0);
    let mut forces = vec![zero; n];
    for dp in &system.dampers {
        let dvec = sub3(arena, &dp.ends[0], &dp.ends[1]);
        let (jd, dt) = jacobian(arena, d, &dvec, s)?;
        let mut rate = dt;
        for (i, r) in rate.iter_mut().enumerate() {
            let mut terms = vec![*r];
            for k in 0..n {
                terms.push(arena.mul2(jd.get(i, k), s.qd[k]));
            }
            *r = arena.add(&terms);
        }
        let num = dot(arena, &dvec, &rate);
        let den = dot(arena, &dvec, &dvec);
        let inv = arena.powi(den, -1)?;
        let mc = arena.neg(dp.coefficient);
        let scale = arena.mul(&[mc, num, inv]);
        for (k, f) in forces.iter_mut().enumerate() {
            let col = [jd.get(0, k), jd.get(1, k), jd.get(2, k)];
            let proj = dot(arena, &col, &dvec);
            if arena.is_zero(proj) {
                continue;
            }
            let e = arena.mul2(scale, proj);
            *f = arena.add2(*f, e);
        }
    }
    Ok(forces)
}

/// The weight of a quadratic form: a scalar mass or a 3x3 inertia tensor.
enum Weight<'a> {
    Scalar(Id),
    Tensor(&'a Matrix),
}

/// Adds the terms of 1/2 (J q' + x_t)^T W (J q' + x_t) to M (upper triangle), b and T_0.
fn add_quadratic(
    arena: &mut Arena,
    m_terms: &mut [Vec<Id>],
    b_terms: &mut [Vec<Id>],
    t0_terms: &mut Vec<Id>,
    j: &Matrix,
    xt: &Vec3,
    w: &Weight<'_>,
) -> Result<()> {
    let n = j.cols;
    // WJ (3 x n) and W x_t.
    let (wj, wxt) = match w {
        Weight::Scalar(m) => {
            let wj = j.scale(arena, *m)?;
            let wxt = xt.map(|x| arena.mul2(*m, x));
            (wj, wxt)
        }
        Weight::Tensor(i) => {
            let wj = i.mul(arena, j)?;
            let col = i.mul(arena, &Matrix::column(xt.to_vec()))?;
            (wj, [col.data[0], col.data[1], col.data[2]])
        }
    };
    for a in 0..n {
        let ja = [j.get(0, a), j.get(1, a), j.get(2, a)];
        for b in a..n {
            let wjb = [wj.get(0, b), wj.get(1, b), wj.get(2, b)];
            let e = dot(arena, &ja, &wjb);
            if !arena.is_zero(e) {
                m_terms[a * n + b].push(e);
            }
        }
        let e = dot(arena, &ja, &wxt);
        if !arena.is_zero(e) {
            b_terms[a].push(e);
        }
    }
    let e = dot(arena, xt, &wxt);
    if !arena.is_zero(e) {
        let half = arena.rational(1, 2)?;
        t0_terms.push(arena.mul2(half, e));
    }
    Ok(())
}

/// Adds the derived terms of `system` to `model`: T += 1/2 q'^T M q' + b^T q' + T_0,
/// Pi += the gravity and spring potential, tau_k += the damper forces. Returns the terms.
///
/// # Errors
/// As [`body_terms`]; [`crate::error::DerivationError::ForceCount`] when the model has a
/// different number of forces than coordinates.
pub fn add_body_terms(model: &mut Model, system: &BodySystem) -> Result<BodyTerms> {
    if model.forces.len() != model.coordinates.len() {
        return Err(Error::Derivation(DerivationError::ForceCount {
            forces: model.forces.len(),
            coordinates: model.coordinates.len(),
        }));
    }
    let terms = body_terms(model, system)?;
    let arena = &mut model.arena;
    for id in [model.kinetic, model.potential].iter().chain(&model.forces) {
        if id.index() >= arena.len() {
            return Err(Error::Algebra(AlgebraError::InvalidId {
                id: id.0,
                len: arena.len(),
            }));
        }
    }
    model.kinetic = arena.add2(model.kinetic, terms.kinetic);
    model.potential = arena.add2(model.potential, terms.potential);
    for (f, &e) in model.forces.iter_mut().zip(&terms.forces) {
        *f = arena.add2(*f, e);
    }
    Ok(terms)
}
