//! Compile: the derived equations as the routines both back ends run.
//!
//! Enters: a [`Model`](crate::Model), its [`Equations`](crate::Equations) and their
//! [`ResidualTangent`](crate::ResidualTangent). Leaves: [`Routines`], one [`Program`] per
//! [`Role`] plus the parameter cache, and the [`Sources`] table saying where the value of
//! every symbol they read comes from. The stage runs, in this order:
//!
//! 1. each role's outputs (`role.rs`), in [`Role::compiled`] order;
//! 2. each role's program through the passes of [`passes`] (checks, factoring, instruction
//!    selection with CSE, dead-code elimination, early scaling, multiply-add fusion,
//!    depth-first scheduling, renumbering);
//! 3. hoisting (`program::hoist`): the values that depend on parameters only move out of
//!    every program into one cache program, [`Role::ParameterCache`];
//! 4. the declared initial values at the current parameters, [`Role::InitialValues`]
//!    (`initial_values.rs`: not hoisted, they read the parameters themselves);
//! 5. the symbol-source table (`sources.rs`), with one [`Source::Cache`] per cache slot;
//! 6. the check that every symbol each program reads has a source its role provides.
//!
//! The structural pattern of M and Phi_q ([`Sparsity`], `sparsity.rs`) is read off the
//! evaluation program afterwards, for both back ends.
//!
//! The macro emits its methods from [`Routines`] (through `emit`) and the interpreter builds
//! its tapes from them (through `Tape`): both run the same programs, so they compute the
//! same bits. Imports: `algebra`, `mechanics` and `program`; nothing here knows `emit`.

mod initial_values;
pub(crate) mod passes;
pub(crate) mod role;
pub(crate) mod sources;
pub(crate) mod sparsity;

use crate::error::{DerivationError, EvalError, ProgramError};
use std::hash::{Hash, Hasher};

use crate::algebra::expr::SymbolId;
use crate::algebra::matrix::Matrix;
use crate::error::{Error, Result};
use crate::mechanics::equations::Equations;
use crate::mechanics::floating_derivatives::floating_tangent;
use crate::mechanics::link_route::for_links;
use crate::mechanics::model::Model;
use crate::mechanics::tangent::{ResidualTangent, multiplier_symbols};
use crate::program::cse::Program;
use crate::program::hoist::hoist_parameters;
use role::effort_symbols;

pub use role::{Role, Tangents, dense_kkt_operations};
pub use sources::{Source, Sources};
pub use sparsity::Sparsity;
pub(crate) use sparsity::structural_zero;

/// The compiled routines of one mechanism: a program per role, the parameter cache, and
/// where each symbol they read comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct Routines {
    /// Every role's program, in [`Role::compiled`] order, then the parameter cache and the
    /// initial values.
    programs: Vec<(Role, Program)>,
    /// The source of every symbol the programs read.
    sources: Sources,
    /// The number of cached parameter-only values.
    cache_len: usize,
}

/// Compiles the equations `eqs` of `model`, with their tangent, into [`Routines`] (the
/// stage's steps in the module docs): the roles of [`Role::compiled`] for the tangents
/// `tangent` carries ([`Tangents::of`]; the macro passes [`crate::full_tangent`]'s). The cache slots are new symbols of `model.arena`
/// (`cache[k]`), and so is the bias of [`Role::MassAndBias`].
///
/// # Errors
/// What [`Program::new`] and hoisting report; [`crate::error::DerivationError::NotASymbol`] for
/// a hand-built model whose parameter or coordinate entry is not a symbol;
/// [`crate::error::EvalError::MissingValue`] for a program that reads a symbol without a source
/// its role provides (equations reading a symbol the model does not declare).
///
/// # Example
/// ```
/// use mechanism_codegen::{Role, compile, derive, parse_model_str, residual_tangent};
///
/// let mut model = parse_model_str(
///     "pub struct Pendulum;
///      parameters { m = 1.0; l = 0.5; g = 9.81; }
///      coordinates { phi = 0.1; }
///      independent { phi = 0.1; der(phi) = 0.0; }
///      kinetic = 1/2*m*l^2*der(phi)^2;
///      potential = -m*g*l*cos(phi);",
/// )?;
/// let eqs = derive(&mut model)?;
/// let tangent = residual_tangent(&mut model, &eqs)?;
/// let routines = compile(&mut model, &eqs, &tangent)?;
/// // M = m l^2 depends on parameters only: the cache computes it, M reads one slot.
/// assert_eq!(routines.program(Role::Mass)?.op_counts().total(), 0);
/// assert!(routines.cache_len() > 0);
/// # Ok::<(), mechanism_codegen::Error>(())
/// ```
pub fn compile(model: &mut Model, eqs: &Equations, tangent: &ResidualTangent) -> Result<Routines> {
    refuse_floating(model, "compiling the `Mechanism` routines")?;
    let roles = Role::compiled(eqs, &model.drawing, Tangents::of(tangent));
    compile_roles(model, eqs, Some(tangent), &roles)
}

/// The routines of [`Role::interpreted`] only: what the interpreter runs, without the
/// single outputs, robotics roles and frames that only the macro emits (on a large
/// mechanism they are half of the stage's work), and with the tangents `tangent` carries:
/// none for `None` (the multiplier symbols are still created, as [`crate::residual_tangent`]
/// creates them, so that symbol ids agree). These roles come first in [`Role::compiled`]
/// and hoisting numbers cache slots in role order, so every program here equals the
/// program of the same role in [`compile`]'s routines, and the parameter cache computes
/// the first [`Routines::cache_len`] slots of that one, with the same instructions.
///
/// # Errors
/// As [`compile`].
pub fn compile_interpreted(
    model: &mut Model,
    eqs: &Equations,
    tangent: Option<&ResidualTangent>,
) -> Result<Routines> {
    refuse_floating(model, "the interpreter route")?;
    let tangents = tangent.map_or(Tangents::None, Tangents::of);
    let roles = Role::interpreted(&model.drawing, tangents);
    compile_roles(model, eqs, tangent, &roles)
}

/// The routines of the constraint rows alone ([`Role::constraint_rows`]: Phi, Phi_q, Phi_t)
/// and their parameter cache: what assembly and the mobility need, without M, C q', g and
/// the rest of the evaluation, which on a large mechanism are almost all of the stage's
/// work. Their cache slots are numbered among these roles only, so the programs equal
/// [`compile`]'s for the same roles only up to the slot numbers; they compute the same
/// values. [`Routines::sparsity`] reads Phi_q's pattern off the Jacobian's program.
///
/// # Errors
/// As [`compile`].
///
/// # Example
/// ```
/// use mechanism_codegen::{EvaluationOutput, Role, compile_constraints, derive, parse_model_str};
///
/// let mut model = parse_model_str(
///     "pub struct Pair;
///      coordinates { x0 = 0.0; x1 = 1.0; }
///      independent { x0 = 0.0; }
///      kinetic = der(x0)^2/2 + der(x1)^2;
///      potential = 0;
///      constraints { x1 - x0 - 1; }",
/// )?;
/// let eqs = derive(&mut model)?;
/// let routines = compile_constraints(&mut model, &eqs)?;
/// assert!(routines.get(Role::Evaluation).is_none());
/// assert_eq!(routines.sparsity(EvaluationOutput::PhiQ)?.entries, [(0, 0), (0, 1)]);
/// # Ok::<(), mechanism_codegen::Error>(())
/// ```
pub fn compile_constraints(model: &mut Model, eqs: &Equations) -> Result<Routines> {
    refuse_floating(model, "the constraint rows' routines")?;
    compile_roles(model, eqs, None, &Role::constraint_rows())
}

/// The routines of [`Role::robotics`] alone (the inverse dynamics, each link frame's
/// placement and Jacobian) and their parameter cache: what a run-time caller of a robot's
/// inverse dynamics, frames and Jacobians needs beside [`compile_interpreted`]'s routines.
/// As for [`compile_constraints`], the cache slots are numbered among these roles only, so
/// the programs equal [`compile`]'s for the same roles up to the slot numbers; they compute
/// the same values.
///
/// # Errors
/// As [`compile`].
///
/// # Example
/// ```
/// use mechanism_codegen::{Role, compile_robotics, derive, parse_model_str};
///
/// let mut model = parse_model_str(
///     "pub struct Arm;
///      parameters { m = 1.0; l = 0.5; }
///      link upper {
///          joint = revolute(th, [0, 0, 1]);
///          mass = m; com = [l/2, 0, 0]; inertia = diag(0, m*l^2/12, m*l^2/12);
///      }",
/// )?;
/// let eqs = derive(&mut model)?;
/// let routines = compile_robotics(&mut model, &eqs)?;
/// assert!(routines.get(Role::InverseDynamics).is_some());
/// assert!(routines.get(Role::FrameJacobian(0)).is_some());
/// assert!(routines.get(Role::Evaluation).is_none());
/// # Ok::<(), mechanism_codegen::Error>(())
/// ```
pub fn compile_robotics(model: &mut Model, eqs: &Equations) -> Result<Routines> {
    refuse_floating(model, "the run-time robotics routines")?;
    compile_roles(model, eqs, None, &Role::robotics(eqs))
}

/// The routines of a floating-base model ([`Role::floating`]: M, the bias, the inverse
/// and forward dynamics, T, Pi and the frames, each in v; `mechanics::floating`), with q
/// read in the configuration's layout (NQ entries) and q', q'', the efforts in v's (NV).
///
/// # Errors
/// As [`compile`]; [`crate::error::DerivationError::FloatingBase`] for a model without a
/// floating root.
pub fn compile_floating(model: &mut Model, eqs: &Equations) -> Result<Routines> {
    if model.floating_root().is_none() {
        return Err(Error::Derivation(DerivationError::FloatingBase {
            mechanism: model.name.clone(),
            what: "(it has none) `compile_floating`".into(),
            nq: model.configuration_size(),
            nv: eqs.n,
        }));
    }
    compile_roles(model, eqs, None, &Role::floating(eqs, &model.drawing))
}

/// [`compile_floating`]'s routines and [`Role::InverseDynamicsDerivatives`]: dtau_id/dq by
/// the tangent of the configuration manifold and dtau_id/dv (NV x NV each,
/// `mechanics::floating_derivatives`), q'' read as a.
///
/// # Errors
/// As [`compile_floating`].
pub fn compile_floating_with_derivatives(model: &mut Model, eqs: &Equations) -> Result<Routines> {
    let tangent = floating_tangent(model, eqs).map_err(|e| for_links(model, e))?;
    let mut roles = Role::floating(eqs, &model.drawing);
    roles.push(Role::InverseDynamicsDerivatives);
    compile_roles(model, eqs, Some(&tangent), &roles)
}

/// Refuses a floating-base model where `what` assumes q' = dq/dt.
fn refuse_floating(model: &Model, what: &str) -> Result<()> {
    if model.floating_root().is_none() {
        return Ok(());
    }
    Err(Error::Derivation(DerivationError::FloatingBase {
        mechanism: model.name.clone(),
        what: what.to_string(),
        nq: model.configuration_size(),
        nv: model.coordinates.len(),
    }))
}

/// The routines of the generated forward dynamics alone ([`Role::ForwardDynamics`]: q'',
/// the pivots and their references, for a mechanism without constraint rows) and tau
/// ([`Role::Forces`], for the power tau . q' an integration also needs), with their
/// parameter cache: what the interpreter's right-hand side runs instead of evaluating the
/// dense M and factoring it. `None` for a mechanism with constraint rows. As for
/// [`compile_robotics`], the cache slots are numbered among these roles only, so the
/// programs equal [`compile`]'s for the same roles up to the slot numbers.
///
/// # Errors
/// As [`compile`]; [`crate::error::DerivationError::FloatingBase`] for a floating-base
/// model (its q' is not dq/dt: [`compile_floating`] has its forward dynamics).
///
/// # Example
/// ```
/// use mechanism_codegen::{Role, compile_forward_dynamics, derive, parse_model_str};
///
/// let mut model = parse_model_str(
///     "pub struct Arm;
///      parameters { m = 1.0; l = 0.5; }
///      link upper {
///          joint = revolute(th, [0, 0, 1]);
///          mass = m; com = [l/2, 0, 0]; inertia = diag(0, m*l^2/12, m*l^2/12);
///      }",
/// )?;
/// let eqs = derive(&mut model)?;
/// let routines = compile_forward_dynamics(&mut model, &eqs)?.expect("no constraint rows");
/// assert!(routines.get(Role::ForwardDynamics).is_some());
/// assert!(routines.get(Role::Evaluation).is_none());
/// # Ok::<(), mechanism_codegen::Error>(())
/// ```
pub fn compile_forward_dynamics(model: &mut Model, eqs: &Equations) -> Result<Option<Routines>> {
    refuse_floating(model, "the run-time forward dynamics")?;
    if eqs.m > 0 {
        return Ok(None);
    }
    compile_roles(model, eqs, None, &[Role::ForwardDynamics, Role::Forces]).map(Some)
}

/// The stage's steps (module docs) for `roles`, in their order; a budget error of a tree
/// of links says what applies to links.
fn compile_roles(
    model: &mut Model,
    eqs: &Equations,
    tangent: Option<&ResidualTangent>,
    roles: &[Role],
) -> Result<Routines> {
    compile_steps(model, eqs, tangent, roles).map_err(|e| for_links(model, e))
}

/// [`compile_roles`]' steps.
fn compile_steps(
    model: &mut Model,
    eqs: &Equations,
    tangent: Option<&ResidualTangent>,
    roles: &[Role],
) -> Result<Routines> {
    let lambda = match tangent {
        Some(t) => t.lambda.clone(),
        None => multiplier_symbols(&mut model.arena, eqs.m),
    };
    // Made for every list of roles, as the multipliers are, so that symbol ids agree.
    let effort = effort_symbols(&mut model.arena, eqs.n);
    let mut programs: Vec<Program> = Vec::with_capacity(roles.len());
    // The residual's tangent, kept: without constraint rows the inverse dynamics'
    // derivatives are the same matrices, and get a copy of its program rather than a
    // second lowering.
    let mut tangent_program: Option<(Vec<Matrix>, usize)> = None;
    for &role in roles {
        let outputs = role.outputs(model, eqs, tangent)?;
        let program = match &tangent_program {
            Some((o, k)) if *o == outputs => programs[*k].clone(),
            _ => Program::new(&model.arena, &outputs.iter().collect::<Vec<_>>())?,
        };
        if role == Role::Tangent {
            tangent_program = Some((outputs, programs.len()));
        }
        programs.push(program);
    }
    let all: Vec<&Program> = programs.iter().collect();
    let hoisted = hoist_parameters(&mut model.arena, &all)?;
    let sources = Sources::new(model, &lambda, &effort, &hoisted.slots)?;
    let mut programs: Vec<(Role, Program)> = roles.iter().copied().zip(hoisted.programs).collect();
    programs.push((Role::ParameterCache, hoisted.cache));
    let initial = initial_values::outputs(model);
    let initial: Vec<_> = initial.iter().collect();
    programs.push((Role::InitialValues, Program::new(&model.arena, &initial)?));
    for (role, program) in &programs {
        check_sources(*role, program, &sources)?;
    }
    Ok(Routines {
        programs,
        sources,
        cache_len: hoisted.slots.len(),
    })
}

/// Every symbol `program` reads has a source that `role` provides.
fn check_sources(role: Role, program: &Program, sources: &Sources) -> Result<()> {
    for (symbol, name) in program.symbols() {
        match sources.get(*symbol) {
            Some(source) if role.provides(source) => {}
            _ => return Err(Error::Eval(EvalError::MissingValue { name: name.clone() })),
        }
    }
    Ok(())
}

impl Routines {
    /// The program of `role`, `None` for a role not compiled (a frame past the last, the
    /// drawing of a model that draws nothing).
    pub fn get(&self, role: Role) -> Option<&Program> {
        self.programs
            .iter()
            .find(|(r, _)| *r == role)
            .map(|(_, p)| p)
    }

    /// The program of `role`.
    ///
    /// # Errors
    /// [`crate::error::ProgramError::NoSuchRoutine`] for a role not compiled.
    pub fn program(&self, role: Role) -> Result<&Program> {
        self.get(role)
            .ok_or(Error::Program(ProgramError::NoSuchRoutine {
                role: format!("{role:?}"),
            }))
    }

    /// Every (role, program) pair, in [`Role::compiled`] order, then the parameter cache and
    /// the initial values.
    pub fn iter(&self) -> impl Iterator<Item = (Role, &Program)> + '_ {
        self.programs.iter().map(|(r, p)| (*r, p))
    }

    /// The symbol-source table.
    pub fn sources(&self) -> &Sources {
        &self.sources
    }

    /// The number of cached parameter-only values (the rows of the
    /// [`Role::ParameterCache`] program's one output).
    pub fn cache_len(&self) -> usize {
        self.cache_len
    }

    /// These routines cut down to `roles` (kept in their order here): their programs, the
    /// parameter cache computing only the slots they read (the first ones, when `roles`
    /// begin [`Role::compiled`] as [`Role::interpreted`] do), the initial values, and the
    /// source table without the other slots. For [`Role::interpreted`], what
    /// [`compile_interpreted`] returns.
    pub fn restricted(&self, roles: &[Role]) -> Routines {
        let programs: Vec<(Role, Program)> = self
            .programs
            .iter()
            .filter(|(r, _)| {
                roles.contains(r) && !matches!(r, Role::ParameterCache | Role::InitialValues)
            })
            .cloned()
            .collect();
        let slot = |s: SymbolId| match self.sources.get(s) {
            Some(Source::Cache(k)) => Some(k),
            _ => None,
        };
        let cache_len = programs
            .iter()
            .flat_map(|(_, p)| p.symbols().iter().filter_map(|(s, _)| slot(*s)))
            .map(|k| k + 1)
            .max()
            .unwrap_or(0);
        let mut programs = programs;
        if let Some(cache) = self.get(Role::ParameterCache) {
            programs.push((Role::ParameterCache, cache.first_rows(cache_len)));
        }
        if let Some(initial) = self.get(Role::InitialValues) {
            programs.push((Role::InitialValues, initial.clone()));
        }
        let sources = self
            .sources
            .iter()
            .filter(|&(_, source)| !matches!(source, Source::Cache(k) if k >= cache_len))
            .collect();
        Routines {
            programs,
            sources,
            cache_len,
        }
    }

    /// A 64-bit FNV-1a hash of the roles, their programs (instructions, outputs, symbols)
    /// and the source table: equal routines have equal fingerprints, on every platform
    /// (every integer enters as its 8 little-endian bytes, a constant as its bits). The
    /// macro emits it and the interpreter records it, so a test can check that both routes
    /// were built from the same routines.
    pub fn fingerprint(&self) -> u64 {
        let mut h = Fnv(0xcbf2_9ce4_8422_2325);
        self.programs.hash(&mut h);
        self.sources.hash(&mut h);
        h.0
    }
}

/// The 64-bit FNV-1a hash of the bytes written into it, with every integer widened to 8
/// little-endian bytes, so that the hash of a value is the same on 32- and 64-bit and on
/// big- and little-endian machines (the macro's host and the interpreter's target).
struct Fnv(u64);

impl Fnv {
    fn integer(&mut self, x: u64) {
        self.write(&x.to_le_bytes());
    }
}

impl Hasher for Fnv {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn write_u8(&mut self, x: u8) {
        self.integer(x.into());
    }
    fn write_u16(&mut self, x: u16) {
        self.integer(x.into());
    }
    fn write_u32(&mut self, x: u32) {
        self.integer(x.into());
    }
    fn write_u64(&mut self, x: u64) {
        self.integer(x);
    }
    fn write_usize(&mut self, x: usize) {
        self.integer(x as u64);
    }
    fn write_i8(&mut self, x: i8) {
        self.integer(x as u64);
    }
    fn write_i16(&mut self, x: i16) {
        self.integer(x as u64);
    }
    fn write_i32(&mut self, x: i32) {
        self.integer(x as u64);
    }
    fn write_i64(&mut self, x: i64) {
        self.integer(x as u64);
    }
    fn write_isize(&mut self, x: isize) {
        self.integer(x as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}
