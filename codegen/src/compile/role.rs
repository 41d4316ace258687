//! What each routine computes and which inputs its callers hand it.

use crate::algebra::expr::{Arena, SymbolId, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::compile::sources::Source;
use crate::error::{Error, ProgramError, Result};
use crate::mechanics::drawing::Drawing;
use crate::mechanics::equations::Equations;
use crate::mechanics::forward_derivatives::forward_dynamics_derivatives;
use crate::mechanics::forward_dynamics::{factorisation_updates, forward_dynamics};
use crate::mechanics::kkt_tree::kkt_parts;
use crate::mechanics::lagrange::coriolis_matrix_of;
use crate::mechanics::model::Model;
use crate::mechanics::recursive::{articulated_forward_dynamics, frame_jacobian};
use crate::mechanics::tangent::ResidualTangent;
use crate::mechanics::tree::LinkJoint;
use crate::program::cse::Program;

/// Which tangents the interpreter's routines carry ([`Role::interpreted`]). Deriving and
/// compiling the residual's tangent costs more than the rest of a large mechanism's
/// routines together, and only implicit integrators and linearisation read it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tangents {
    /// No tangent: the evaluation, the constraint rows and the drawing.
    None,
    /// The residual's tangent dF/dq, dF/dq' ([`Role::Tangent`]), for implicit integrators.
    Residual,
    /// The residual's tangent and the constraint rows' ([`Role::ConstraintTangent`]), for
    /// linearisation and mechanisms with velocity constraints.
    WithConstraints,
    /// Both tangents and the derivatives of the inverse dynamics
    /// ([`Role::InverseDynamicsDerivatives`], [`Role::ParameterDerivatives`]), for control
    /// and optimisation ([`crate::full_tangent`]); what the macro compiles.
    Derivatives,
}

impl Tangents {
    /// The tangents `tangent` carries: [`Tangents::Derivatives`] with the constraint rows'
    /// tangent and dtau_id/dp ([`crate::full_tangent`]), [`Tangents::WithConstraints`] with
    /// the rows' tangent alone, [`Tangents::Residual`] otherwise.
    pub fn of(tangent: &ResidualTangent) -> Tangents {
        match (&tangent.constraints, &tangent.dynamics.parameters) {
            (Some(_), Some(_)) => Tangents::Derivatives,
            (Some(_), None) => Tangents::WithConstraints,
            (None, _) => Tangents::Residual,
        }
    }
}

/// One routine of a compiled mechanism: what its program computes. The macro emits one
/// method (or one arm of a method) per role; the interpreter runs one tape per role it
/// serves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Role {
    /// M (n x n): `mass_matrix`.
    Mass,
    /// Khang's C (n x n): `coriolis_matrix`.
    CoriolisMatrix,
    /// C q' (n x 1): `coriolis_forces`.
    CoriolisForces,
    /// g (n x 1): `gravity`.
    Gravity,
    /// tau (n x 1): `generalized_forces`.
    Forces,
    /// Phi (m x 1): `constraints`.
    Constraints,
    /// Phi_q (m x n): `constraint_jacobian`.
    ConstraintJacobian,
    /// Phi_t (m x 1): `constraint_time_derivative`.
    ConstraintTimeDerivative,
    /// gamma (m x 1): `constraint_gamma`.
    Gamma,
    /// T (1 x 1): `kinetic_energy`.
    Kinetic,
    /// Pi (1 x 1): `potential_energy`.
    Potential,
    /// M, C q', g, tau, Phi, Phi_q, Phi_t, gamma, T, Pi in one program, in
    /// [`crate::EvaluationOutput::ORDER`]: `evaluate_into` and the interpreter's `evaluate`.
    Evaluation,
    /// dF/dq and dF/dq' of the residual F = M q'' + C q' + g + Phi_q^T lambda - tau (two
    /// n x n outputs): `residual_tangent`.
    Tangent,
    /// The constraint rows' tangents D, R_q, R_q' (three m x n outputs, see
    /// [`crate::ConstraintTangent`]), for linearisation; compiled (after the tangent)
    /// when the tangent carries them: for a model with velocity constraints, or on
    /// request. The interpreter runs it; the macro emits no method for it.
    ConstraintTangent,
    /// M (n x n) and the bias b = C q' + g - tau (n x 1) in one program: `mass_and_bias`.
    MassAndBias,
    /// The bias b = C q' + g - tau (n x 1) alone, M-free (for links one Newton-Euler pass
    /// with the base accelerating at -g): `bias`.
    Bias,
    /// M q'' + C q' + g - tau (n x 1): `inverse_dynamics`.
    InverseDynamics,
    /// q'' = M^-1 (u - b) for the effort u (read from `effort`), the pivots D of
    /// M = L^T D L and M's diagonal in the same order (three n x 1 outputs), by the
    /// factorisation that follows M's pattern (`mechanics::forward_dynamics`):
    /// `forward_dynamics`, which refuses q'' when a pivot is not above 1e-14 of its
    /// diagonal entry. Compiled for a mechanism without constraint rows only.
    ForwardDynamics,
    /// The parts of the KKT solve that follow M's pattern (`mechanics::kkt_tree`):
    /// u = M^-1 Q (n x 1), Y = M^-1 Phi_q^T (n x m), S = Phi_q M^-1 Phi_q^T (m x m),
    /// c = Phi_q u - gamma (m x 1), the pivots D of M = L^T D L and M's diagonal in the
    /// same order (n x 1 each): `constrained_dynamics`, which finishes S lambda = c,
    /// q'' = u - Y lambda at run time. Compiled for a mechanism with constraint rows;
    /// without outputs (and no method emitted) where the dense solve
    /// ([`dense_kkt_operations`] with the evaluation) counts fewer operations or a pivot is
    /// identically 0.
    ConstrainedDynamics,
    /// dtau_id/dq and dtau_id/dq' of the inverse dynamics tau_id = M q'' + C q' + g - tau
    /// (two n x n outputs, [`crate::InverseDynamicsDerivatives`]): `inverse_dynamics_derivatives`.
    /// Compiled with [`Tangents::Derivatives`].
    InverseDynamicsDerivatives,
    /// dq''/dq, dq''/dq' and M^-1 (three n x n outputs) at the effort u (read from
    /// `effort`), then the pivots D of M = L^T D L and M's diagonal in the same order (two
    /// n x 1 outputs), in one program through the factorisation that follows M's pattern
    /// (`mechanics::forward_derivatives`): `forward_dynamics_derivatives`. Compiled with
    /// [`Tangents::Derivatives`] for a mechanism without constraint rows only.
    ForwardDynamicsDerivatives,
    /// dtau_id/dp (n x p, the declared parameters in declaration order):
    /// `inverse_dynamics_parameter_derivatives`. Compiled with [`Tangents::Derivatives`].
    ParameterDerivatives,
    /// R (3 x 3) and p (3 x 1) of link frame k: `frame_placement`.
    FramePlacement(usize),
    /// J (6 x n) of link frame k: `frame_jacobian`.
    FrameJacobian(usize),
    /// The drawn points' world positions, x, y, z per point in drawing order (3 x points,
    /// one column): `draw_points`. Only for a model that draws.
    Draw,
    /// The values that depend on parameters only, one column in cache-slot order: the
    /// emitted `parameter_cache`, run once per parameter set.
    ParameterCache,
    /// The declared initial values at the current parameter values, two columns: the n
    /// initial guesses of q, then the position and rate of each independent coordinate in
    /// turn (2 k entries): the emitted `initial_guess` and `independent`. Like the cache it
    /// reads the parameters only, but it is not hoisted into it: it is run when asked
    /// (once per parameter set), from the parameters as they are, so that a parameter
    /// changed through a field is followed without a `refresh`.
    InitialValues,
}

impl Role {
    /// The roles the interpreter runs, in compilation order: the evaluation, the
    /// constraint rows, the drawing for a model that draws, then the tangents `tangents`
    /// asks for (the residual's, then the constraint rows', then the inverse dynamics'
    /// derivatives by the motion and by the parameters). They are the first roles of
    /// [`Role::compiled`] (with the tangents last, so that each shorter list is a prefix of
    /// a longer one), so hoisting numbers their cache slots alike in every list and their
    /// programs are the same (see [`crate::compile_interpreted`]).
    pub fn interpreted(drawing: &Drawing, tangents: Tangents) -> Vec<Role> {
        let mut roles = vec![
            Role::Evaluation,
            Role::Constraints,
            Role::ConstraintJacobian,
            Role::ConstraintTimeDerivative,
        ];
        if !drawing.points.is_empty() {
            roles.push(Role::Draw);
        }
        if tangents != Tangents::None {
            roles.push(Role::Tangent);
        }
        if matches!(tangents, Tangents::WithConstraints | Tangents::Derivatives) {
            roles.push(Role::ConstraintTangent);
        }
        if tangents == Tangents::Derivatives {
            roles.extend([Role::InverseDynamicsDerivatives, Role::ParameterDerivatives]);
        }
        roles
    }

    /// The roles of the constraint rows alone: Phi, Phi_q and Phi_t, in [`Role::compiled`]
    /// order. What assembly and the mobility read (see [`crate::compile_constraints`]).
    pub fn constraint_rows() -> [Role; 3] {
        [
            Role::Constraints,
            Role::ConstraintJacobian,
            Role::ConstraintTimeDerivative,
        ]
    }

    /// The roles a robot's run-time user reads besides the evaluation: the inverse dynamics
    /// (Newton-Euler for a tree of links) and each link frame's placement and Jacobian, in
    /// [`Role::compiled`] order. What [`crate::compile_robotics`] compiles; the
    /// interpreter's [`Role::interpreted`] leaves them out.
    pub fn robotics(eqs: &Equations) -> Vec<Role> {
        let mut roles = vec![Role::InverseDynamics];
        roles.extend((0..eqs.frames.len()).map(Role::FramePlacement));
        roles.extend((0..eqs.frames.len()).map(Role::FrameJacobian));
        roles
    }

    /// Every role compiled for equations `eqs`, a model's `drawing` and the tangents
    /// `tangents` (at least [`Tangents::Residual`]: [`Tangents::None`] counts as that), in
    /// compilation order (the order in which hoisting numbers the cache slots): the roles
    /// of [`Role::interpreted`], then the single outputs the macro alone emits, the
    /// robotics roles (the forward dynamics for a mechanism without constraint rows only)
    /// and the frames. The parameter cache, made from all of them, is not in the list.
    pub fn compiled(eqs: &Equations, drawing: &Drawing, tangents: Tangents) -> Vec<Role> {
        let tangents = match tangents {
            Tangents::None => Tangents::Residual,
            other => other,
        };
        let mut roles = Role::interpreted(drawing, tangents);
        roles.extend([
            Role::Mass,
            Role::CoriolisMatrix,
            Role::CoriolisForces,
            Role::Gravity,
            Role::Forces,
            Role::Gamma,
            Role::Kinetic,
            Role::Potential,
            Role::MassAndBias,
            Role::InverseDynamics,
            Role::Bias,
        ]);
        if eqs.m == 0 {
            roles.push(Role::ForwardDynamics);
            if tangents == Tangents::Derivatives {
                roles.push(Role::ForwardDynamicsDerivatives);
            }
        } else {
            roles.push(Role::ConstrainedDynamics);
        }
        roles.extend((0..eqs.frames.len()).map(Role::FramePlacement));
        roles.extend((0..eqs.frames.len()).map(Role::FrameJacobian));
        roles
    }

    /// The roles of a floating-base model (`mechanics::floating`), in compilation order:
    /// M, C v, g, tau, T, Pi, the robotics roles, the forward dynamics and the frames (and
    /// the drawing); none of the roles written for q' = dq/dt.
    pub fn floating(eqs: &Equations, drawing: &Drawing) -> Vec<Role> {
        let mut roles = vec![
            Role::Mass,
            Role::CoriolisForces,
            Role::Gravity,
            Role::Forces,
            Role::Kinetic,
            Role::Potential,
            Role::MassAndBias,
            Role::InverseDynamics,
            Role::Bias,
            Role::ForwardDynamics,
        ];
        if !drawing.points.is_empty() {
            roles.push(Role::Draw);
        }
        roles.extend((0..eqs.frames.len()).map(Role::FramePlacement));
        roles.extend((0..eqs.frames.len()).map(Role::FrameJacobian));
        roles
    }

    /// Whether the routine of this role may read a value from `source`: parameters and
    /// cached values always (the cache itself reads parameters only); t, q and q' in every
    /// other routine; q'' in the tangents, the inverse dynamics and its derivatives; the
    /// multipliers in the tangent; the efforts in the forward dynamics.
    pub fn provides(self, source: Source) -> bool {
        match (self, source) {
            (Role::ParameterCache | Role::InitialValues, s) => matches!(s, Source::Parameter(_)),
            (_, Source::Parameter(_) | Source::Cache(_)) => true,
            (_, Source::Time | Source::Coordinate(_) | Source::Rate(_)) => true,
            (
                Role::Tangent
                | Role::InverseDynamics
                | Role::ConstraintTangent
                | Role::InverseDynamicsDerivatives
                | Role::ParameterDerivatives,
                Source::Acceleration(_),
            ) => true,
            (Role::Tangent, Source::Multiplier(_)) => true,
            (Role::ForwardDynamics | Role::ForwardDynamicsDerivatives, Source::Effort(_)) => true,
            _ => false,
        }
    }

    /// The matrices this role's program computes, in output order (not for
    /// [`Role::ParameterCache`], which hoisting makes, nor for [`Role::InitialValues`], made
    /// from the model by `compile`), built in `model`'s arena where `derive` leaves them to
    /// the routines that need them: Khang's C of a tree of links and the frames' Jacobians.
    /// A frame past `eqs.frames` has none.
    pub(crate) fn outputs(
        self,
        model: &mut Model,
        eqs: &Equations,
        tangent: Option<&ResidualTangent>,
    ) -> Result<Vec<Matrix>> {
        let frame = |k: usize| eqs.frames.get(k);
        let no_tangent = || {
            Error::Program(ProgramError::NoSuchRoutine {
                role: format!("{self:?} (no tangent was derived)"),
            })
        };
        Ok(match self {
            Role::Mass => vec![eqs.mass.clone()],
            Role::CoriolisMatrix => vec![match &eqs.coriolis_matrix {
                Some(c) => c.clone(),
                None => coriolis_matrix_of(model, &eqs.mass)?,
            }],
            Role::CoriolisForces => vec![eqs.coriolis_forces.clone()],
            Role::Gravity => vec![eqs.gravity.clone()],
            Role::Forces => vec![eqs.forces.clone()],
            Role::Constraints => vec![eqs.phi.clone()],
            Role::ConstraintJacobian => vec![eqs.phi_q.clone()],
            Role::ConstraintTimeDerivative => vec![eqs.phi_t.clone()],
            Role::Gamma => vec![eqs.gamma.clone()],
            Role::Kinetic => vec![Matrix::column(vec![eqs.kinetic])],
            Role::Potential => vec![Matrix::column(vec![eqs.potential])],
            Role::Evaluation => eqs.evaluation_outputs(),
            Role::Tangent => {
                let tangent = tangent.ok_or_else(no_tangent)?;
                vec![tangent.stiffness.clone(), tangent.damping.clone()]
            }
            Role::ConstraintTangent => tangent
                .ok_or_else(no_tangent)?
                .constraints
                .iter()
                .flat_map(|c| [c.velocity.clone(), c.stiffness.clone(), c.damping.clone()])
                .collect(),
            Role::MassAndBias => vec![eqs.mass.clone(), eqs.bias.clone()],
            Role::Bias => vec![eqs.bias.clone()],
            Role::InverseDynamics => vec![eqs.inverse_dynamics.clone()],
            Role::ForwardDynamics => forward_dynamics_outputs(model, eqs)?,
            Role::ConstrainedDynamics => constrained_dynamics_outputs(model, eqs)?,
            Role::InverseDynamicsDerivatives => {
                let dynamics = &tangent.ok_or_else(no_tangent)?.dynamics;
                vec![dynamics.position.clone(), dynamics.velocity.clone()]
            }
            Role::ForwardDynamicsDerivatives => {
                let dynamics = &tangent.ok_or_else(no_tangent)?.dynamics;
                let effort: Vec<_> = effort_symbols(&mut model.arena, eqs.n)
                    .into_iter()
                    .map(|s| model.arena.symbol_node(s))
                    .collect();
                let order = elimination_order(model);
                forward_dynamics_derivatives(model, eqs, dynamics, &effort, &order)?
            }
            Role::ParameterDerivatives => {
                let dynamics = &tangent.ok_or_else(no_tangent)?.dynamics;
                vec![dynamics.parameters.clone().ok_or_else(no_tangent)?]
            }
            Role::FramePlacement(k) => frame(k)
                .map(|f| vec![f.rotation.clone(), f.position.clone()])
                .unwrap_or_default(),
            Role::FrameJacobian(k) if k < eqs.frames.len() => {
                vec![frame_jacobian(&mut model.arena, &model.links, k, eqs.n)]
            }
            Role::FrameJacobian(_) => vec![],
            Role::Draw => {
                let entries = model.drawing.points.iter().flat_map(|p| p.position);
                vec![Matrix::column(entries.collect())]
            }
            Role::ParameterCache | Role::InitialValues => vec![],
        })
    }
}

/// The effort symbols `effort[1]`..`effort[n]` of `arena` (made on first use): the input
/// of [`Role::ForwardDynamics`], M q'' + b = u.
pub(crate) fn effort_symbols(arena: &mut Arena, n: usize) -> Vec<SymbolId> {
    (0..n)
        .map(|k| arena.symbol_id(&format!("effort[{}]", k + 1), SymbolKind::Free))
        .collect()
}

/// The coordinates in the order the forward dynamics eliminates them from the last: the
/// links' moving joints in declaration order (each after its parent's), then any other
/// coordinate in declared order.
fn elimination_order(model: &Model) -> Vec<usize> {
    let n = model.coordinates.len();
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for l in &model.links {
        let width = match l.joint {
            LinkJoint::Floating { .. } => 6,
            _ => 1,
        };
        for c in l.joint.coordinate().map_or(0..0, |c| c..c + width) {
            if c < n && !std::mem::replace(&mut seen[c], true) {
                order.push(c);
            }
        }
    }
    order.extend((0..n).filter(|&c| !seen[c]));
    order
}

/// The outputs of [`Role::ForwardDynamics`]: q'', the pivots and the references they must
/// exceed 1e-14 of, from whichever of two routes counts fewer operations once compiled:
/// the factorisation M = L^T D L over M's pattern (references: M's diagonal), or for a
/// tree of links the articulated-body algorithm (references: 0, its pivots being the
/// articulated inertias along the axes). The factorisation wins on short trees (O(n d^2)
/// for depth d), the recursion on long chains (O(n)).
fn forward_dynamics_outputs(model: &mut Model, eqs: &Equations) -> Result<Vec<Matrix>> {
    let effort: Vec<_> = effort_symbols(&mut model.arena, eqs.n)
        .into_iter()
        .map(|s| model.arena.symbol_node(s))
        .collect();
    let order = elimination_order(model);
    let factored = |model: &mut Model| -> Result<Vec<Matrix>> {
        let a = &mut model.arena;
        let fd = forward_dynamics(a, &eqs.mass, &eqs.bias, &effort, &order)?;
        let diagonal = order.iter().map(|&c| eqs.mass.get(c, c)).collect();
        Ok(vec![fd.accelerations, fd.pivots, Matrix::column(diagonal)])
    };
    // The recursion is written for one-coordinate joints: a floating root factors M.
    if !model.kinetic_from_links || model.floating_root().is_some() {
        return factored(model);
    }
    let (qdd, pivots) = articulated_forward_dynamics(model, &effort)?;
    let zeros = Matrix::zeros(&mut model.arena, eqs.n, 1);
    let recursive = vec![qdd, pivots, zeros];
    let ops = |model: &Model, outputs: &[Matrix]| -> Result<usize> {
        let outputs: Vec<&Matrix> = outputs.iter().collect();
        Ok(Program::new(&model.arena, &outputs)?.op_counts().total())
    };
    let recursive_ops = ops(model, &recursive)?;
    // The factorisation's updates alone (a lower bound of its operations, about n^3 / 6
    // on a chain) already cost more than the whole recursion: writing them out (their
    // expressions grow as n^3, past the size budget at 200 links) cannot change the
    // choice, which keeps the recursion only when it is strictly leaner.
    if factorisation_updates(&model.arena, &eqs.mass, &order) > recursive_ops {
        return Ok(recursive);
    }
    let factored = factored(model)?;
    let recursive_is_leaner = recursive_ops < ops(model, &factored)?;
    Ok(if recursive_is_leaner {
        recursive
    } else {
        factored
    })
}

/// The operations of the dense KKT solve at run time for n coordinates and m rows
/// (`mechanism::fixed::kkt_solve`, multiplications and additions of its loops as written):
/// Phi_q^T Phi_q twice (the augmented M~ and the refinement's residual, 2 n^2 m each), the
/// Cholesky factor of M~ (n^3 / 3) and of Phi_q Y (m^3 / 3), Y = M~^-1 Phi_q^T
/// (2 m n^2), Phi_q Y (2 m^2 n), and the two solves with their products (about
/// 8 n^2 + 12 n m + 4 m^2).
pub fn dense_kkt_operations(n: usize, m: usize) -> usize {
    4 * n * n * m
        + n * n * n / 3
        + m * m * m / 3
        + 2 * m * n * n
        + 2 * m * m * n
        + 8 * n * n
        + 12 * n * m
        + 4 * m * m
}

/// The outputs of [`Role::ConstrainedDynamics`] (u, Y, S, c, the pivots, M's diagonal in
/// elimination order), or none, leaving the dense solve, where that counts fewer
/// operations (the evaluation's program plus [`dense_kkt_operations`], against this
/// program plus the m x m finish: m^3 / 3 + 2 m^2 + 2 n m) or where a pivot is
/// identically 0 (M singular at every q, as for coordinates that carry no mass).
fn constrained_dynamics_outputs(model: &mut Model, eqs: &Equations) -> Result<Vec<Matrix>> {
    let order = elimination_order(model);
    let a = &mut model.arena;
    let parts = kkt_parts(a, &eqs.mass, &eqs.bias, &eqs.phi_q, &eqs.gamma, &order)?;
    if parts.pivots.data().iter().any(|&d| a.is_zero(d)) {
        return Ok(vec![]);
    }
    let diagonal = order.iter().map(|&c| eqs.mass.get(c, c)).collect();
    let outputs = vec![
        parts.u,
        parts.y,
        parts.s,
        parts.c,
        parts.pivots,
        Matrix::column(diagonal),
    ];
    let ops = |outputs: &[Matrix]| -> Result<usize> {
        let outputs: Vec<&Matrix> = outputs.iter().collect();
        Ok(Program::new(&model.arena, &outputs)?.op_counts().total())
    };
    let (n, m) = (eqs.n, eqs.m);
    let tree = ops(&outputs)? + m * m * m / 3 + 2 * m * m + 2 * n * m;
    let dense = ops(&eqs.evaluation_outputs())? + dense_kkt_operations(n, m);
    Ok(if tree < dense { outputs } else { vec![] })
}
