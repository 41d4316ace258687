//! The one error type of the runtime: every failure a solver can meet, with the time, the
//! configuration and the number that made it fail, worded for a mechanical engineer.
//!
//! No solver panics on bad numbers and none returns a silent NaN: a non-finite value, a
//! locked configuration or a Newton iteration that stalls all end in one of these variants.

/// What went wrong in assembly, simulation, inverse dynamics, linearisation or a sweep.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Newton's method on the position constraints Phi(q, t) = 0 stopped before both the
    /// residual and the step were small.
    #[error(
        "the loop constraints could not be closed at t = {t} s: Newton stopped after \
         {iterations} iterations with |Phi|_inf = {residual:e} (q = {q:?}); \
         start from a closer guess or check the link lengths"
    )]
    NewtonDidNotConverge {
        /// Time of the attempt (s).
        t: f64,
        /// Iterations performed.
        iterations: usize,
        /// Last residual |Phi|_inf.
        residual: f64,
        /// Last iterate q.
        q: Vec<f64>,
    },
    /// A kinematic solve cannot continue: the coordinates it solves for are not determined
    /// at this configuration (the mechanism is locked, at a dead point, at a bifurcation of
    /// its assembly branches, or a prescribed motion takes it out of reach).
    ///
    /// Every test for a singular configuration, in one place (the book's chapter
    /// "Overconstrained mechanisms and singular positions", `docs/src/overconstrained.md`,
    /// summarises it):
    /// - **Velocity and acceleration solves** ([`crate::solve_velocities`],
    ///   [`crate::solve_accelerations`], kinematic analysis, inverse dynamics): the
    ///   constraint Jacobian of the dependent coordinates, Phi_v, has numerical rank below
    ///   their number, by SVD with singular values at most
    ///   [`crate::AssemblyOptions::rank_tolerance`] (1e-10) times the largest counting as
    ///   zero; `condition` is sigma_max / sigma_min.
    /// - **Position solves** ([`crate::solve_positions`], kinematic analysis, inverse
    ///   dynamics), once Newton has failed: Phi_v has a condition above
    ///   [`crate::AssemblyOptions::singular_condition`] (1e6), or more than 90 % of the
    ///   residual Phi lies outside the span of its well-conditioned left singular vectors
    ///   while its condition exceeds 4 (Gauss-Newton creeping towards a fold of the
    ///   constraint manifold). At assembly ([`crate::assemble_from`]) there is no motion to
    ///   be singular, and the same finding is [`Error::ConstraintsUnsatisfiable`].
    /// - **HHT**: its Newton matrix has an exactly zero or non-finite pivot (`condition`
    ///   infinite).
    ///
    /// Not errors: the forward dynamics integrates through singular positions (the LU route of
    /// [`crate::Dynamics`] hands over to the augmented Lagrangian route when its condition
    /// estimate exceeds [`crate::DEFAULT_CONDITION_LIMIT`], 1e8). Where a motion passes one is
    /// recorded ([`crate::SingularPassage`]) by the row-independence test of the rank basis of
    /// the constraint rows (`linalg::RowBasis`), the one that also finds redundant rows
    /// ([`crate::mobility()`], [`Error::ConflictingDrives`]): a row's distance to the span of
    /// the rows before it, relative to its norm, is at most 1e-6 for a redundant row, and a
    /// passage is recorded where the weakest independence falls below 1e-3.
    #[error(
        "singular configuration at t = {t} s (condition estimate {condition:e}): the mechanism \
         is at a dead point, locked, or its constraints lose rank; q = {q:?}"
    )]
    SingularConfiguration {
        /// Time (s).
        t: f64,
        /// Configuration q.
        q: Vec<f64>,
        /// 1-norm condition estimate of the matrix that failed (infinite for a zero pivot).
        condition: f64,
    },
    /// The accelerations are not determined: the mass matrix is singular (or indefinite) on
    /// a motion the constraints allow, so M + alpha Phi_q^T Phi_q is not positive definite.
    /// A body or coordinate without mass or inertia that the constraints leave free.
    #[error(
        "the motion is undetermined at t = {t} s: the mass matrix gives no inertia to an \
         allowed motion of {coordinates:?} (no mass or inertia on it, and the constraints do \
         not fix it); q = {q:?}"
    )]
    UndeterminedMotion {
        /// Time (s).
        t: f64,
        /// The coordinates that move in that motion (largest share first).
        coordinates: Vec<String>,
        /// Configuration q.
        q: Vec<f64>,
    },
    /// The motion is undetermined because the coordinates are singular there, not for want
    /// of inertia: a step of `coordinate` away from `value` gives the allowed motions their
    /// inertia back (`algorithms/coordinate_singularity.rs`). Orientation angles whose axes
    /// line up (a disc or a bicycle frame lying flat in yaw, lean, spin) are the common
    /// case, named with the body and its rotation sequence in `orientation`.
    #[error("{}", coordinate_singularity(*t, coordinate, *value, moving, orientation.as_deref()))]
    CoordinateSingularity {
        /// Time (s).
        t: f64,
        /// The coordinate at its singular value (`phi`, the lean).
        coordinate: String,
        /// Its value there.
        value: f64,
        /// The coordinates whose rates are not determined (they move in the direction
        /// without inertia).
        moving: Vec<String>,
        /// The body whose declared orientation angles are singular, when the coordinates
        /// are such angles.
        orientation: Option<Box<OrientationSingularity>>,
    },
    /// The constraints cannot be satisfied near the initial guess: Newton stalls at a point
    /// where Phi != 0 and cannot be decreased (a link too short to close the loop, a
    /// position out of reach).
    #[error(
        "the constraints cannot be satisfied near the initial guess at t = {t} s: \
         |Phi|_inf stays at {residual:e} (rows {rows:?}); check the lengths and the guesses \
         (q = {q:?})"
    )]
    ConstraintsUnsatisfiable {
        /// Time (s).
        t: f64,
        /// The residual |Phi|_inf that cannot be reduced.
        residual: f64,
        /// The rows with the largest residuals, by label.
        rows: Vec<String>,
        /// Where Newton stopped.
        q: Vec<f64>,
    },
    /// The given values of the independent coordinates admit no position: with them fixed,
    /// the residual |Phi| has a minimum above zero over the other coordinates, and with them
    /// free too, the constraints close at `nearest` (the reason is in
    /// `algorithms/reach.rs`). Where Newton only lost its way from the guess, the error is
    /// [`Error::NewtonDidNotConverge`] instead.
    #[error(
        "the given values admit no position at t = {t} s: with {} the constraints cannot be \
         closed (over the other coordinates their residual |Phi|_inf has a minimum of \
         {residual:.3e}, rows {rows:?}, at q = {q:?}); the nearest values that admit one are \
         {}: give values within the mechanism's reach (a position on another assembly \
         branch, far from this one, is not excluded)",
        values.iter().map(|(c, v, _)| format!("{c} = {v}")).collect::<Vec<_>>().join(", "),
        values.iter().map(|(c, _, v)| format!("{c} = {v}")).collect::<Vec<_>>().join(", ")
    )]
    GivenOutOfReach {
        /// Time (s).
        t: f64,
        /// Each given coordinate that admits no position: its name, the value given, and
        /// the nearest value that admits one (to 7 significant digits: the constraints
        /// hold there to the assembly tolerance, not to the last bit).
        values: Vec<(String, f64, f64)>,
        /// The least |Phi|_inf with the given values.
        residual: f64,
        /// The rows with the largest residuals there, by label.
        rows: Vec<String>,
        /// Where the residual is least.
        q: Vec<f64>,
    },
    /// The independent coordinates chosen by the user leave the others undetermined: the
    /// constraint Jacobian restricted to the dependent coordinates has rank below their count.
    #[error(
        "the independent coordinates {independent:?} do not determine the others: \
         {dependent} dependent coordinates but the constraints fix only {rank} of them; \
         choose {} more independent coordinate(s) or other ones", dependent - rank
    )]
    IndependentSetDoesNotDetermine {
        /// Names of the independent coordinates given.
        independent: Vec<String>,
        /// Number of dependent coordinates n - k.
        dependent: usize,
        /// Rank of Phi_q restricted to the dependent columns.
        rank: usize,
    },
    /// More independent coordinates given than the mechanism has degrees of freedom: the
    /// constraints fix the rest of them. Refused whether the values agree with the
    /// constraints or not; when every coordinate is given, `violated` names the rows they
    /// break (`constraint 2 by 3.0e-1`), i.e. which values conflict.
    #[error(
        "`independent` gives {} coordinates ({}), but the mechanism has {degrees_of_freedom} \
         degree(s) of freedom: the constraints fix the other {}{}; give {degrees_of_freedom} \
         of them and let the assembly find the rest",
        given.len(), given.join(", "), given.len() - degrees_of_freedom,
        if violated.is_empty() { String::new() } else {
            format!(", and these values break {}", violated.join(", "))
        }
    )]
    OverSpecified {
        /// The coordinates given.
        given: Vec<String>,
        /// The degrees of freedom, n - rank Phi_q.
        degrees_of_freedom: usize,
        /// The constraint rows the values break, with their residuals (all coordinates given).
        violated: Vec<String>,
    },
    /// A drive that the constraints and the drives before it already fix: its driving
    /// force is not determined (more drives than degrees of freedom, or a drive on a
    /// coordinate the loop closure fixes).
    #[error("{}", conflicting_drives(*.t, .drives, *.drives_given, *.degrees_of_freedom))]
    ConflictingDrives {
        /// Time (s).
        t: f64,
        /// The driven coordinates whose drives are redundant.
        drives: Vec<String>,
        /// Number of drives given.
        drives_given: usize,
        /// Degrees of freedom of the undriven mechanism (n - rank Phi_q).
        degrees_of_freedom: usize,
    },
    /// A prescribed motion leaves the positions the mechanism can reach: after the samples
    /// up to `t_last` were solved, no configuration satisfies the constraints with the
    /// drives' values at t (Newton's residual |Phi|_inf stays at `residual`, above the
    /// assembly tolerance). Raised instead of a singular configuration, a conflict of the
    /// drives or a Newton failure when the residual left shows the drives out of reach.
    #[error(
        "the prescribed motion leaves the positions the mechanism can reach at t = {t} s: no \
         configuration satisfies the constraints with {values} (|Phi|_inf stays at \
         {residual:.3e}){}; keep the drive within the mechanism's reach",
        match t_last { Some(s) => format!("; the last sample solved is at t = {s} s, where \
         the mechanism was at or near the edge of its reach"), None => " at the start, from \
         the declared guesses".to_string() }
    )]
    DriveOutOfReach {
        /// Time of the sample that cannot be solved (s).
        t: f64,
        /// The last sample solved (s), `None` at the first sample.
        t_last: Option<f64>,
        /// The drives' values there, `x = 1.01, ...`.
        values: String,
        /// |Phi|_inf where Newton stopped.
        residual: f64,
    },
    /// A drive's rate f' jumps at t (a kink of f, e.g. `abs(t - 0.5)`): its acceleration
    /// and the driving force are infinite there (an impulse), whether t falls on a sample or
    /// between two (`algorithms::kink` has the test).
    #[error(
        "the drive of {coordinate} has a kink at t = {t} s: its rate jumps from {before} to \
         {after}, so its acceleration and the driving force are infinite there; smooth the \
         drive (blend the two pieces over a short interval)"
    )]
    DriveKink {
        /// The driven coordinate.
        coordinate: String,
        /// Where the rate jumps (s).
        t: f64,
        /// The rate just before.
        before: f64,
        /// The rate just after.
        after: f64,
    },
    /// The adaptive step size fell below the smallest allowed value.
    #[error(
        "step size underflow at t = {t} s: h = {h:e} s is below the minimum; the motion is \
         too fast or stiff for the tolerance (try HHT or a looser tolerance)"
    )]
    StepSizeUnderflow {
        /// Time (s).
        t: f64,
        /// Rejected step size (s).
        h: f64,
    },
    /// The adaptive step size collapsed (below the minimum, or as
    /// [`Error::StepSizeCollapse`]) next to a singular position of the constraints: the
    /// weakest row independence w of Phi_q (a row's distance to the span of the rows
    /// before it, over the largest norm that row has had in the run:
    /// `simulation/singular.rs`) was below 0.3 at the last accepted step. Near one, an error eps in Phi (the drift left by the
    /// stabilisation, or a stage's truncation error) changes q'' by about eps / w^3, and a
    /// step whose stages come that close measures that noise instead of its truncation
    /// error. `remedy` names what passes it for the run's settings.
    #[error(
        "the step size collapsed to h = {h:.3e} s at t = {t} s next to a singular position \
         of the constraints (Phi_q loses rank{}{}; weakest row independence {independence:.1e}; \
         {passages} singular position(s) recorded so far): {remedy}",
        match t_singular { Some(s) => format!(" at t = {s:.6} s"), None => String::new() },
        if rows.is_empty() { String::new() } else { format!(" in {rows}") }
    )]
    StuckAtSingularPosition {
        /// Time reached (s).
        t: f64,
        /// The step size at the failure (s).
        h: f64,
        /// The predicted time of the singular position (s), when w was still falling.
        t_singular: Option<f64>,
        /// The rows of Phi that lose rank there, by their joint and component (`; `
        /// between rows; `Box<str>` like `remedy`, to keep `Error` small).
        rows: Box<str>,
        /// The weakest row independence at the last accepted step.
        independence: f64,
        /// Singular positions recorded so far in this run (the one it stopped at among them
        /// when it was recorded on the way in).
        passages: usize,
        /// What passes it with these settings.
        remedy: Box<str>,
    },
    /// The integrator reached its step limit before the end time.
    #[error("too many steps: {max_steps} steps reached at t = {t} s before the end time")]
    TooManySteps {
        /// Time reached (s).
        t: f64,
        /// The limit.
        max_steps: usize,
    },
    /// The adaptive step size collapsed: at the mean size of the last 100 accepted steps,
    /// the steps still needed to reach the end time, (t_end - t) / h, plus those taken
    /// exceed 10 times the step limit (`IntegratorOptions::max_steps`). Tested from the
    /// 1000th step on (the first ones say little about the rest), so a doomed run stops in
    /// about a thousand steps instead of running into the limit; a run that would need the
    /// step to grow more than tenfold on average to finish cannot be told apart from one
    /// that never will. Thresholds: `WINDOW`, `MIN_STEPS`, `COLLAPSE_FACTOR` of
    /// `src/simulation/fail_fast.rs`.
    #[error(
        "the step size collapsed to h = {h:.3e} s at t = {t} s (mean of the last 100 steps): \
         reaching the end time would take {} more steps, more than 10 \
         times the limit of {max_steps}; the motion is too fast or stiff for the method and \
         tolerance, or a parameter or force is far out of scale (try HHT, a looser \
         tolerance, or check the parameters)",
        about_steps(*.steps_needed)
    )]
    StepSizeCollapse {
        /// Time reached (s).
        t: f64,
        /// Mean size of the last 100 accepted steps (s).
        h: f64,
        /// (t_end - t) / h.
        steps_needed: f64,
        /// The step limit.
        max_steps: usize,
    },
    /// A fixed step (RK4, HHT) that cannot reach the end time within the step limit:
    /// ceil((t_end - t0) / h) > `IntegratorOptions::max_steps`. Refused by
    /// [`crate::Simulator::new`] before any work.
    #[error(
        "a fixed step of h = {h:e} s over {span} s takes {steps:.1e} steps, more than the \
         limit of {max_steps}: choose a step of at least {:e} s or an adaptive method",
        span / *max_steps as f64
    )]
    FixedStepTooSmall {
        /// The step (s).
        h: f64,
        /// t_end - t0 (s).
        span: f64,
        /// Steps needed.
        steps: f64,
        /// The step limit.
        max_steps: usize,
    },
    /// A fixed step (RK4, HHT) too large for the motion: within one step the states left
    /// the constraints so far (|Phi|_inf = `residual` at t, at a step's end, a stage or a
    /// sample of the dense output between two step ends) that the projection (or HHT's
    /// Newton iteration) could not bring them back.
    #[error(
        "the fixed step h = {h:e} s of {method} is too large for this motion: at t = {t} s \
         the projection could not bring its state back onto the constraints (|Phi|_inf \
         stays at {residual:.3e}); choose a smaller --step, or an adaptive method (dopri5, \
         dop853) that sizes its steps"
    )]
    StepTooLarge {
        /// Time of the failed projection (s).
        t: f64,
        /// The step (s).
        h: f64,
        /// The method, `rk4` or `hht`.
        method: &'static str,
        /// |Phi|_inf where the projection stopped.
        residual: f64,
    },
    /// The time span is too long for the step size the motion needs: the mean of the last
    /// 100 accepted steps, h, is steady (at least a tenth of the mean step of the whole
    /// run, so it has not collapsed), yet the steps still needed, (t_end - t) / h, plus those
    /// taken exceed 10 times the step limit. The output rate does not set the step: the
    /// motion does. Tested like [`Error::StepSizeCollapse`], from the 1000th step on.
    #[error(
        "the time span is too long for this motion: its steps are a steady h = {h:.3e} s \
         (mean of the last 100; {h_run:.3e} s over the whole run), so reaching t_end = \
         {t_end} s from t = {t} s would take {} more steps, more than \
         10 times the limit of {max_steps} (the output rate does not set the step); shorten \
         --t-end, or check the parameters if a step this small is unexpected",
        about_steps(*.steps_needed)
    )]
    SpanTooLong {
        /// Time reached (s).
        t: f64,
        /// The end time (s).
        t_end: f64,
        /// Mean size of the last 100 accepted steps (s).
        h: f64,
        /// Mean size of all accepted steps (s).
        h_run: f64,
        /// (t_end - t) / h.
        steps_needed: f64,
        /// The step limit.
        max_steps: usize,
    },
    /// The motion diverged: after an accepted step (or at a stage of a step, where an entry
    /// of the equations overflowed) a coordinate or a rate is NaN, infinite
    /// or beyond 1e12 times its scale at the start (positions: the largest of 1,
    /// |q(t0)|_inf and |q'(t0)|_inf (t_end - t0); rates: the larger of 1 and
    /// |q'(t0)|_inf). A factor of 1e12 leaves every physical range and 12 of the 16 digits
    /// of f64, so nothing after it means anything; an unstable integration (a fixed step
    /// too large for a stiff spring) or a force far out of scale ends here.
    #[error(
        "the motion diverged at t = {t} s: {quantity} of {coordinate} is {value:.3e}, beyond \
         {limit:.3e} (1e12 times its scale at the start); the integration is unstable or a \
         force or parameter is far out of scale (try a smaller step or tolerance, or check \
         the parameters)"
    )]
    Diverged {
        /// Time of the step's end (s).
        t: f64,
        /// `q` or `q'`.
        quantity: &'static str,
        /// The coordinate.
        coordinate: String,
        /// Its value (NaN or infinite included).
        value: f64,
        /// The bound it crossed.
        limit: f64,
    },
    /// A parameter, a state component or a computed quantity is NaN or infinite.
    #[error("non-finite value: {what} at t = {t} s")]
    NonFinite {
        /// Which quantity (e.g. "parameter l1", "q'' of x_c").
        what: String,
        /// Time (s).
        t: f64,
    },
    /// One entry of the equations (M, C q', g, tau, Phi, Phi_q, Phi_t or gamma) evaluated to
    /// NaN or infinity at (t, q): the expression behind it is undefined there (a logarithm
    /// or a square root of a negative number, a division by zero) or overflows. `term` names
    /// the entry: `Phi row 2 (constraint 2)`, `gamma row 1 (revolute(B1, B2, z, z) x)`
    /// (1-based row and its label, [`crate::SystemInfo::constraint_label`]),
    /// `Phi_q[constraint 1, th3]`, `M[th1, th2]`, `tau of th1`, `C q' of th2`, `g of th1`.
    /// Raised by the assembly, the projections, [`crate::Dynamics::solve`], HHT and the
    /// inverse dynamics, before any solve uses the value.
    #[error(
        "{term} is {value} at t = {t} s, q = {q:?}: its expression is undefined or overflows \
         there (a logarithm or square root of a negative number, a division by zero, a huge \
         parameter or rate)"
    )]
    NonFiniteTerm {
        /// The entry, named as above.
        term: String,
        /// Its value: NaN, inf or -inf.
        value: f64,
        /// Time (s).
        t: f64,
        /// The configuration where it was evaluated.
        q: Vec<f64>,
    },
    /// A coordinate name that the mechanism does not declare.
    #[error("unknown coordinate '{name}'; the coordinates are {known:?}")]
    UnknownCoordinate {
        /// The name asked for.
        name: String,
        /// The declared coordinate names.
        known: Vec<String>,
    },
    /// A parameter name that the mechanism does not declare.
    #[error("unknown parameter '{name}'; the parameters are {known:?}")]
    UnknownParameter {
        /// The name asked for.
        name: String,
        /// The declared parameter names.
        known: Vec<String>,
    },
    /// A parameter value outside the range the declaration gives the parameter
    /// (`r = 0.1 positive;`).
    #[error(
        "parameter '{name}' = {value} is outside its declared range: it must be {} (declared `{}`)",
        range.describe(), range.keyword()
    )]
    ParameterOutOfRange {
        /// The parameter.
        name: String,
        /// The value refused.
        value: f64,
        /// Its declared range.
        range: crate::system::ParameterRange,
    },
    /// A driver (prescribed motion) on a coordinate index outside 0..n, or twice on one.
    #[error("driver on unknown coordinate index {coordinate} (the mechanism has {n} coordinates)")]
    UnknownDriver {
        /// The coordinate index given.
        coordinate: usize,
        /// Number of coordinates n.
        n: usize,
    },
    /// One coordinate given twice among the drives or the independent coordinates.
    #[error(
        "coordinate `{name}` is given twice (as a drive or an independent coordinate); give it once"
    )]
    RepeatedCoordinate {
        /// Its name.
        name: String,
    },
    /// Inverse dynamics with fewer drives than the mechanism has degrees of freedom: the
    /// drives leave coordinates free, so the motion is not prescribed.
    #[error(
        "the drives of {drives:?} leave {missing} degree(s) of freedom free at t = {t} s: \
         the motion is not prescribed; add {missing} drive(s)"
    )]
    TooFewDrives {
        /// Time (s).
        t: f64,
        /// The driven coordinates.
        drives: Vec<String>,
        /// How many more drives are needed.
        missing: usize,
    },
    /// The starting quaternion of a floating base is not unit: its norm differs from 1 by
    /// more than `QUATERNION_NORM_TOLERANCE` (1e-9).
    #[error(
        "the root's quaternion (x, y, z, w) = {quaternion:?} has norm {norm}, not 1: give a unit quaternion (within 1e-9), e.g. [0, 0, 0, 1] for the world's axes"
    )]
    QuaternionNotUnit {
        /// The quaternion given.
        quaternion: [f64; 4],
        /// Its norm.
        norm: f64,
    },
    /// A numeric option outside its allowed range.
    #[error("invalid option: {option} = {value} (allowed: {allowed})")]
    InvalidOption {
        /// The option (`t_end`, `output_rate`, `rtol`, `atol`, `h`, `alpha`).
        option: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// A linearisation requested at a state that is not a steady motion.
    #[error(
        "the state is not a steady motion: {reason}; linearise at an equilibrium or a steady \
         motion (q'' = 0, the moving coordinates cyclic)"
    )]
    NotSteady {
        /// What is not steady.
        reason: String,
    },
    /// A linearisation that cannot be formed (no exact tangents, dependent rows).
    #[error("cannot linearise: {reason}")]
    Linearization {
        /// Why.
        reason: String,
    },
    /// A routine the solver needs is not provided by the system: an exact tangent of the
    /// equations for their derivatives ([`crate::DynamicsDerivatives`]), which
    /// [`crate::Interpreted`] compiles only when asked ([`crate::Interpreted::for_derivatives`])
    /// and a hand-written [`crate::Mechanism`] may not provide.
    #[error(
        "{what} is not provided: build the system with Interpreted::for_derivatives, or \
         compile it with mechanism!"
    )]
    NotProvided {
        /// What is missing (`the residual's tangent of `FiveBar``).
        what: String,
    },
    /// A vector given with the wrong number of entries.
    #[error("{what} has {got} entries; the mechanism has {expected}")]
    WrongLength {
        /// Which vector (`q`, `q'`, `guess`).
        what: &'static str,
        /// Entries needed.
        expected: usize,
        /// Entries given.
        got: usize,
    },
    /// The output the run would keep in memory is larger than
    /// [`crate::MAX_OUTPUT_BYTES`]: samples x values per sample x 8 bytes (plus the
    /// per-sample bookkeeping where samples are kept as vectors). Refused before any work.
    #[error(
        "{samples} samples of {columns} values would take about {:.2} GB of memory, more \
         than the {:.2} GB a run may use: lower the output rate or shorten the time span",
        *bytes / 1e9, *limit as f64 / 1e9
    )]
    TooMuchOutput {
        /// Samples that would be recorded.
        samples: usize,
        /// Values per sample.
        columns: usize,
        /// Estimated bytes.
        bytes: f64,
        /// The limit in bytes.
        limit: usize,
    },
    /// The run would record more output samples than allowed.
    #[error(
        "{span} s at {rate} samples per second would record {samples:e} samples, more than \
         the {limit:e} a run allows: shorten the time span or lower the output rate"
    )]
    TooManySamples {
        /// Time span (s).
        span: f64,
        /// Output rate (1/s).
        rate: f64,
        /// Samples that would be recorded.
        samples: f64,
        /// The limit.
        limit: usize,
    },
    /// A velocity constraint row A_j q' + a_j = 0 that is a combination of the rows above it
    /// (A_j = c^T B, a_j = c^T b at the assembled configuration): it restricts nothing, like
    /// the time derivative of a position row or a repeated row (`algorithms::velocity_rows`).
    #[error(
        "the velocity row `{row}` is redundant at t = {t} s: it is a combination of \
         {} (a time derivative of position rows, or a repeat), so it restricts no rate; \
         remove it, or declare an integrable row as a position constraint",
        rows_named(of)
    )]
    VelocityRowRedundant {
        /// Time (s).
        t: f64,
        /// The velocity row, by label.
        row: String,
        /// The rows above it that it combines, by label.
        of: Vec<String>,
    },
    /// A velocity constraint row whose A_j is a combination c^T B of the rows above it but
    /// whose a_j is not the same combination of theirs: d = a_j - c^T b != 0, and no rates
    /// satisfy all of them (`algorithms::velocity_rows`).
    #[error(
        "the velocity row `{row}` contradicts {} at t = {t} s: its rates are a \
         combination of theirs but its right-hand side differs by {mismatch:.3e}, so no \
         rates satisfy all of them; remove it or make it agree",
        rows_named(of)
    )]
    VelocityRowContradicts {
        /// Time (s).
        t: f64,
        /// The velocity row, by label.
        row: String,
        /// The rows above it whose combination it contradicts, by label.
        of: Vec<String>,
        /// d = a_j - c^T b (in the row's units).
        mismatch: f64,
    },
    /// A start state given as consistent is not: Phi or Phi_q q' + Phi_t is above 1e-8.
    #[error(
        "the given initial state is not consistent: |Phi| = {residual:e}, \
         |Phi_q q' + Phi_t| = {velocity_residual:e} (at most 1e-8 allowed)"
    )]
    InconsistentInitialState {
        /// |Phi|_inf.
        residual: f64,
        /// |Phi_q q' + Phi_t|_inf.
        velocity_residual: f64,
    },
}

impl Error {
    /// Checks that every value is finite, or names the first that is not.
    pub(crate) fn check_finite(
        values: &[f64],
        what: &str,
        names: &[String],
        t: f64,
    ) -> Result<(), Error> {
        match values.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(i) => Err(Error::NonFinite {
                what: format!("{what} of {}", names.get(i).map_or("?", |s| s.as_str())),
                t,
            }),
        }
    }
}

/// The rows a dependent velocity row combines, by label; for a row whose coefficients of
/// the rates all vanish at the configuration (the empty combination), that fact.
fn rows_named(of: &[String]) -> String {
    if of.is_empty() {
        "no row (its coefficients of the rates all vanish at this configuration)".to_string()
    } else {
        of.join(", ")
    }
}

/// The message of [`Error::ConflictingDrives`]: more drives than degrees of freedom, or, with
/// no more drives than that, a drive that the constraints fix at this configuration only (a
/// dead point, where the mechanism's reach folds).
fn conflicting_drives(t: f64, drives: &[String], given: usize, freedom: usize) -> String {
    if given > freedom {
        format!(
            "conflicting drives at t = {t} s: the motion of {drives:?} is already fixed by the \
             constraints and the other drives ({given} drive(s) on a mechanism with {freedom} \
             degree(s) of freedom), so its driving force is not determined"
        )
    } else {
        format!(
            "the drive of {drives:?} is at a singular position at t = {t} s: there the \
             constraints fix its motion (a dead point of the mechanism), so its driving force \
             is not determined; drive another coordinate through this position"
        )
    }
}

/// A count of steps still needed, `about 1.5e8`; one beyond f64 (a step that underflowed to
/// zero) is `more than 1e308`, not `inf`.
fn about_steps(steps: f64) -> String {
    if steps.is_finite() {
        format!("about {steps:.1e}")
    } else {
        "more than 1e308".to_string()
    }
}

/// A singularity of a body's declared orientation angles (see
/// [`Error::CoordinateSingularity`]).
#[derive(Clone, Debug, PartialEq)]
pub struct OrientationSingularity {
    /// The body.
    pub body: String,
    /// Its rotation sequence as declared, `rot_z(psi) rot_x(phi) rot_y(th)` (`R` for an
    /// explicit factor, `..` for an angle that is no coordinate).
    pub sequence: String,
    /// The two angles whose axes line up.
    pub in_line: [String; 2],
    /// What lines up, when the two are the first and the last factor: `its y axis lies
    /// along the world z axis`.
    pub along: Option<String>,
}

/// The message of [`Error::CoordinateSingularity`].
fn coordinate_singularity(
    t: f64,
    coordinate: &str,
    value: f64,
    moving: &[String],
    orientation: Option<&OrientationSingularity>,
) -> String {
    let moving = moving.join(", ");
    match orientation {
        Some(o) => format!(
            "a coordinate singularity of the orientation angles at t = {t} s, {coordinate} = \
             {value} ({:.2} deg): in body `{}`'s {} the axes of {} and {} line up{}, so the \
             rates of {moving} are not determined (the mass matrix gives that motion no \
             inertia); three angles cannot follow every attitude: end the run before this \
             one, or declare the orientation with a sequence whose singular attitude the \
             motion does not reach",
            value.to_degrees(),
            o.body,
            o.sequence,
            o.in_line[0],
            o.in_line[1],
            o.along
                .as_ref()
                .map_or(String::new(), |a| format!(" ({a})")),
        ),
        None => format!(
            "a coordinate singularity at t = {t} s, {coordinate} = {value}: the coordinates \
             {moving} do not determine the motion there (the mass matrix gives their motion \
             no inertia, and a change of {coordinate} gives it back); end the run before this \
             configuration, or choose coordinates that stay regular through it"
        ),
    }
}
