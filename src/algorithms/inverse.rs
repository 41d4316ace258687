//! Inverse dynamics: the generalised forces that make chosen coordinates follow a prescribed
//! motion, and the constraint multipliers (joint reactions) along it.
//!
//! Each driven coordinate q_k gets the driver constraint q_k - f(t) = 0 (Haug 1989,
//! sec. 6.3), whose Jacobian row is the unit row e_k and whose acceleration right-hand side
//! is f''(t). The driving force replaces whatever force the declaration puts on q_k (tau_k
//! is zeroed); forces on the other coordinates stay. At each time:
//!
//! ```text
//! kinematics   Phi(q, t) = 0, q_k = f(t)     (Newton, continued from the previous sample;
//!                                             with velocity rows, from q carried along
//!                                             the motion since it: `rolling_positions`)
//!              Phi_q q' = -Phi_t, q_k' = f'(t)
//! dynamics     [ M      Phi_q^T  E^T ] [ q''      ]   [ tau* - C q' - g ]
//!              [ Phi_q  0        0   ] [ lambda   ] = [ gamma           ]
//!              [ E      0        0   ] [ lambda_d ]   [ f''(t)          ]
//! ```
//!
//! with E the unit rows of the driven coordinates and tau* the declared forces with the driven
//! entries set to zero. The system is solved by the augmented Lagrangian route
//! ([`AugmentedLagrangian`]) with the rows [Phi_q; E], so redundant constraint rows are
//! accepted: their multipliers are reported as the minimum-norm choice. The driving forces stay
//! unique as long as no drive row lies in the span of the other rows; a drive that the
//! constraints and the other drives already fix is [`Error::ConflictingDrives`]. Row k of the
//! first block reads (M q'' + C q' + g + Phi_q^T lambda)_k + lambda_d = 0, so the actuator must
//! supply **tau_k = -lambda_d**: the total generalised force on q_k (N m for an angle, N for a
//! length).
//!
//! # What lambda means
//! With the sign convention M q'' + ... + Phi_q^T lambda = tau, the constraint forces on the
//! coordinates are -Phi_q^T lambda. When a loop is closed by a vector equation
//! Phi = r_C(via chain 1) - r_C(via chain 2) = 0 (the loop cut at joint C), the virtual work of
//! a joint force F acting on chain 1 at C and -F on chain 2 is F . dPhi = (Phi_q^T F) . dq, so
//! F = -lambda: **-lambda is the force chain 2 exerts on chain 1 at the cut joint, and +lambda
//! the force chain 1 exerts on chain 2**, in the components in which Phi is written (N when
//! Phi is a length, N m when it is an angle; scaling a constraint row by c scales its lambda
//! by 1/c). For the seed crank-slider, Phi = r_C(crank and rod) - r_C(slider), so lambda is
//! the force of the connecting rod on the slider at the spherical joint C, in x, y, z.

use nalgebra::DMatrix;

use crate::algorithms::augmented_lagrangian::AugmentedLagrangian;
use crate::algorithms::finite;
use crate::algorithms::kinematics::{
    AssemblyOptions, Drive, check_fixed, solve_positions, solve_velocities,
};
use crate::algorithms::kink;
use crate::algorithms::rolling_positions;
use crate::error::Error;
use crate::limits::check_output_memory;
use crate::linalg::RowBasis;
use crate::system::{Evaluation, System, SystemInfo};

/// One sample of an inverse-dynamics run.
#[derive(Clone, Debug, PartialEq)]
pub struct InverseSample {
    /// Time (s).
    pub t: f64,
    /// Positions.
    pub q: Vec<f64>,
    /// Rates.
    pub qd: Vec<f64>,
    /// Accelerations.
    pub qdd: Vec<f64>,
    /// Driving generalised force on each driven coordinate (drive order): tau_k = -lambda_d.
    pub driving: Vec<f64>,
    /// Loop-constraint multipliers lambda_1..lambda_m (see the module docs for the sign).
    pub lambda: Vec<f64>,
}

/// Inverse dynamics along a prescribed motion; reuses its buffers from sample to sample and
/// continues the assembly branch from the previous configuration.
pub struct InverseDynamics {
    drives: Vec<Drive>,
    fixed: Vec<usize>,
    q: Vec<f64>,
    eval: Evaluation,
    rows: DMatrix<f64>,
    augmented: AugmentedLagrangian,
    basis: RowBasis,
    rhs: Vec<f64>,
    gamma: Vec<f64>,
    lambda: Vec<f64>,
    /// Newton options of the position solve.
    pub assembly: AssemblyOptions,
    /// The time of the last sample solved.
    t_last: Option<f64>,
}

impl InverseDynamics {
    /// Prepares inverse dynamics of `system` for `drives` (unknown or repeated coordinates
    /// give [`Error::UnknownDriver`]). Starts from the declared initial guesses.
    pub fn new(
        system: &dyn System,
        drives: Vec<Drive>,
        assembly: AssemblyOptions,
    ) -> Result<Self, Error> {
        let info = system.info();
        let fixed: Vec<usize> = drives.iter().map(|d| d.coordinate).collect();
        check_fixed(info, &fixed)?;
        let (n, m, k) = (info.n(), info.m(), fixed.len());
        Ok(Self {
            drives,
            fixed,
            q: info.initial_guess.clone(),
            eval: Evaluation::zeros(n, m),
            rows: DMatrix::zeros(m + k, n),
            augmented: AugmentedLagrangian::new(n, m + k),
            basis: RowBasis::new(m + k, n),
            rhs: vec![0.0; n],
            gamma: vec![0.0; m + k],
            lambda: vec![0.0; m + k],
            assembly,
            t_last: None,
        })
    }

    /// Kinematics and the driven augmented system at time t (see the module equations).
    pub fn solve_at(&mut self, system: &dyn System, t: f64) -> Result<InverseSample, Error> {
        let info = system.info();
        let (n, m, k) = (info.n(), info.m(), self.fixed.len());
        let mut qd = vec![0.0; n];
        let mut fdd = vec![0.0; k];
        self.check_kinks(info, t)?;
        if let Some(a) = self.t_last.filter(|_| info.velocity_rows > 0) {
            // Velocity rows leave positions to the motion: carried from the last sample.
            rolling_positions::advance(system, &self.drives, &mut self.q, (a, t), &self.assembly)?;
        }
        self.prescribe(info, t, &mut qd, &mut fdd)?;
        // The drives are tested where the drives' values meet the previous configuration
        // (the guesses at the first sample), to name too many drives when the positions
        // cannot be solved, and again where they are solved: off the constraint manifold a
        // row that the others imply only on it (x^2 + y^2 = L^2 beside x = L sin th,
        // y = -L cos th) looks independent, and a drive seen independent there can be at a
        // dead point where the positions land (the slider of a slider-crank driven to the
        // end of its stroke). There the drive rows depend on the constraint rows, and the
        // rates tell the two folds apart: a drive that turns back at the fold (its rate
        // consistent with the rows) passes a dead point, where its force is not
        // determined; one whose rate pushes on leaves the reach, which the next sample
        // names (`out_of_reach`).
        let conflict = self.check_drives(system, t);
        if let Err(e) = solve_positions(system, t, &self.fixed, &mut self.q, &self.assembly) {
            return Err(match (self.t_last, conflict, e) {
                // At the first sample the conflict names the cause (too many drives).
                (None, Err(c), _) => c,
                (
                    _,
                    _,
                    Error::IndependentSetDoesNotDetermine {
                        independent,
                        dependent,
                        rank,
                    },
                ) => Error::TooFewDrives {
                    t,
                    drives: independent,
                    missing: dependent - rank,
                },
                (_, _, e) => self.out_of_reach(system, t).unwrap_or(e),
            });
        }
        if let Err(e) = self.check_drives(system, t)
            && (self.t_last.is_none() || self.rates_consistent(system, t))
        {
            return Err(e);
        }
        self.t_last = Some(t);
        solve_velocities(system, t, &self.q, &self.fixed, &mut qd, &self.assembly)?;
        system.evaluate(t, &self.q, &qd, &mut self.eval);
        self.assemble(info, (t, &qd), &fdd)?;
        let mut qdd = self.accelerations(info, t)?;
        // The solve meets E q'' = f'' to round-off (4e-23 for f'' = 0); the prescribed
        // value is exact.
        for (d, &f2) in self.drives.iter().zip(&fdd) {
            qdd[d.coordinate] = f2;
        }
        self.multipliers(&qdd);
        Error::check_finite(&qdd, "q''", &info.coordinates, t)?;
        Ok(InverseSample {
            t,
            q: self.q.clone(),
            qd,
            qdd,
            driving: self.lambda[m..].iter().map(|l| -l).collect(),
            lambda: self.lambda[..m].to_vec(),
        })
    }

    /// The kinks of the drives since the last sample (or at t, for the first).
    fn check_kinks(&self, info: &SystemInfo, t: f64) -> Result<(), Error> {
        for d in &self.drives {
            let name = &info.coordinates[d.coordinate];
            match self.t_last {
                Some(a) => kink::check_kink(d, name, a, t)?,
                None => kink::check_kink_at(d, name, t)?,
            }
        }
        Ok(())
    }

    /// [`Error::DriveOutOfReach`] when the position solve at t left |Phi|_inf above 1e3
    /// times the assembly tolerance (1e-7 m by default): Newton found no configuration
    /// with the drives' values, rather than one it could not resolve (a dead point).
    fn out_of_reach(&self, system: &dyn System, t: f64) -> Option<Error> {
        let info = system.info();
        let mut phi = vec![0.0; info.m()];
        system.constraints(t, &self.q, &mut phi);
        let residual = crate::linalg::inf_norm(&phi);
        if !residual.is_finite() || residual <= 1e3 * self.assembly.tolerance {
            return None;
        }
        let values = self
            .drives
            .iter()
            .map(|d| format!("{} = {}", info.coordinates[d.coordinate], (d.f)(t)[0]))
            .collect::<Vec<_>>()
            .join(", ");
        Some(Error::DriveOutOfReach {
            t,
            t_last: self.t_last,
            values,
            residual,
        })
    }

    /// The prescribed motion at t: q_k = f(t) into the positions, f'(t) into `qd` and
    /// f''(t) into `fdd` (drive order).
    fn prescribe(
        &mut self,
        info: &SystemInfo,
        t: f64,
        qd: &mut [f64],
        fdd: &mut [f64],
    ) -> Result<(), Error> {
        for (j, d) in self.drives.iter().enumerate() {
            let [f, fd, f2] = (d.f)(t);
            if !(f.is_finite() && fd.is_finite() && f2.is_finite()) {
                return Err(Error::NonFinite {
                    what: format!("drive of {}", info.coordinates[d.coordinate]),
                    t,
                });
            }
            self.q[d.coordinate] = f;
            qd[d.coordinate] = fd;
            fdd[j] = f2;
        }
        Ok(())
    }

    /// The driven system from the evaluation at the solved state: the rows [Phi_q; E], the
    /// force side tau* - C q' - g (driven entries of tau zeroed) and [gamma; f''].
    /// A non-finite term is [`Error::NonFiniteTerm`] naming the entry, at (t, q, q').
    fn assemble(
        &mut self,
        info: &SystemInfo,
        (t, qd): (f64, &[f64]),
        fdd: &[f64],
    ) -> Result<(), Error> {
        let e = &self.eval;
        let m = e.phi.len();
        driven_rows(&mut self.rows, &e.phi_q, &self.fixed);
        for (i, rhs) in self.rhs.iter_mut().enumerate() {
            let tau = if self.fixed.contains(&i) {
                0.0
            } else {
                e.forces[i]
            };
            *rhs = tau - e.coriolis[i] - e.gravity[i];
        }
        self.gamma[..m].copy_from_slice(e.gamma.as_slice());
        self.gamma[m..].copy_from_slice(fdd);
        if self.rhs.iter().chain(&self.gamma).any(|v| !v.is_finite())
            || e.mass.iter().any(|v| !v.is_finite())
        {
            return Err(finite::evaluation_error(
                e,
                info,
                (t, &self.q, qd),
                "the equations of motion along the prescribed motion",
            ));
        }
        Ok(())
    }

    /// q'' of the driven system by the augmented Lagrangian route; a motion the system
    /// leaves undetermined is [`Error::UndeterminedMotion`], naming the coordinates that
    /// move freely (largest first).
    fn accelerations(&mut self, info: &SystemInfo, t: f64) -> Result<Vec<f64>, Error> {
        let n = info.n();
        let solved = self
            .augmented
            .solve(&self.eval.mass, &self.rows, &self.rhs, &self.gamma);
        if let Err(failure) = solved {
            let mut v = vec![0.0; n];
            self.augmented.undetermined_direction(failure, &mut v);
            let mut moving: Vec<usize> = (0..n).filter(|&i| v[i].abs() > 1e-6).collect();
            moving.sort_by(|&x, &y| v[y].abs().total_cmp(&v[x].abs()));
            return Err(Error::UndeterminedMotion {
                t,
                coordinates: moving
                    .iter()
                    .map(|&i| info.coordinates[i].clone())
                    .collect(),
                q: self.q.clone(),
            });
        }
        Ok(self.augmented.solution().to_vec())
    }

    /// lambda from the force balance [Phi_q; E]^T lambda = Q - M q'' (minimum norm), where
    /// `rhs` holds Q = tau* - C q' - g.
    fn multipliers(&mut self, qdd: &[f64]) {
        self.basis.factor(&self.rows);
        let mass = &self.eval.mass;
        for (i, rhs) in self.rhs.iter_mut().enumerate() {
            let mx: f64 = (0..qdd.len()).map(|j| mass[(i, j)] * qdd[j]).sum();
            *rhs -= mx;
        }
        self.basis
            .multipliers_for(&self.rows, &self.rhs, &mut self.lambda);
    }
}

/// [Phi_q; E] into `rows`: the constraint rows, then the unit row of each driven coordinate.
fn driven_rows(rows: &mut DMatrix<f64>, phi_q: &DMatrix<f64>, fixed: &[usize]) {
    let (m, n) = phi_q.shape();
    rows.fill(0.0);
    rows.view_mut((0, 0), (m, n)).copy_from(phi_q);
    for (j, &c) in fixed.iter().enumerate() {
        rows[(m + j, c)] = 1.0;
    }
}

impl InverseDynamics {
    /// Whether the velocity equations [Phi_q; E] q' = [-Phi_t; f'(t)] have a solution at the
    /// current configuration (least squares by SVD, singular values below 1e-6 of the
    /// largest dropped as the rank test drops rows: residual within 1e-6 of the right-hand
    /// side, or of 1 where it vanishes).
    fn rates_consistent(&self, system: &dyn System, t: f64) -> bool {
        let info = system.info();
        let (n, m) = (info.n(), info.m());
        let mut phi_t = vec![0.0; m];
        let mut phi_q = DMatrix::zeros(m, n);
        system.constraint_jacobian(t, &self.q, &mut phi_q, &mut phi_t);
        let mut rows = DMatrix::zeros(m + self.fixed.len(), n);
        driven_rows(&mut rows, &phi_q, &self.fixed);
        let rhs: Vec<f64> = phi_t
            .iter()
            .map(|v| -v)
            .chain(self.drives.iter().map(|d| (d.f)(t)[1]))
            .collect();
        let x = crate::linalg::least_squares(&rows, &rhs, 1e-6);
        let residual = (&rows * nalgebra::DVector::from_column_slice(&x)
            - nalgebra::DVector::from_column_slice(&rhs))
        .amax();
        residual <= 1e-6 * (1.0 + crate::linalg::inf_norm(&rhs))
    }

    /// Drives must be independent of the constraints and of each other, else their forces
    /// are not unique (and their positions generally not reachable): the rows [Phi_q; E] at
    /// the current configuration (the previous sample's, or the guesses) are tested with
    /// the rank test of [`crate::mobility()`].
    fn check_drives(&mut self, system: &dyn System, t: f64) -> Result<(), Error> {
        let info = system.info();
        let (n, m, k) = (info.n(), info.m(), self.fixed.len());
        let mut phi_t = vec![0.0; m];
        let mut phi_q = nalgebra::DMatrix::zeros(m, n);
        system.constraint_jacobian(t, &self.q, &mut phi_q, &mut phi_t);
        driven_rows(&mut self.rows, &phi_q, &self.fixed);
        self.basis.factor(&self.rows);
        let conflicting: Vec<String> = (0..k)
            .filter(|&j| self.basis.is_redundant(m + j))
            .map(|j| info.coordinates[self.fixed[j]].clone())
            .collect();
        if conflicting.is_empty() {
            return Ok(());
        }
        Err(Error::ConflictingDrives {
            t,
            drives: conflicting,
            drives_given: k,
            degrees_of_freedom: n - (0..m).filter(|&r| !self.basis.is_redundant(r)).count(),
        })
    }
}

/// Bytes an [`InverseSample`] takes beyond its values: five vectors, each a 24-byte header
/// and a heap block (about 16 bytes of allocator bookkeeping).
const SAMPLE_OVERHEAD: usize = 5 * (24 + 16);

/// Inverse dynamics at each of `times` (in order). More samples than
/// [`crate::MAX_OUTPUT_BYTES`] can hold are refused before any work
/// ([`Error::TooMuchOutput`]). The error of the first failing sample is
/// returned, e.g. [`Error::DriveOutOfReach`] where the prescribed motion takes the mechanism
/// beyond its reach (past a dead point it cannot pass), [`Error::DriveKink`] where a drive's
/// rate jumps.
pub fn inverse_dynamics(
    system: &dyn System,
    drives: Vec<Drive>,
    times: &[f64],
    assembly: &AssemblyOptions,
) -> Result<InverseResult, Error> {
    let guess = system.info().initial_guess.clone();
    inverse_dynamics_from(system, drives, &guess, times, assembly)
}

/// [`inverse_dynamics`] with the first position solve started from `guess` (n values; the
/// driven coordinates' are replaced by their drives) instead of the declared guesses: the
/// assembly branch the motion follows (elbow up or down, a four-bar's open or crossed
/// circuit) is the one nearest `guess`.
///
/// # Errors
/// [`Error::WrongLength`] for a `guess` of other than n values; those of
/// [`inverse_dynamics`].
pub fn inverse_dynamics_from(
    system: &dyn System,
    drives: Vec<Drive>,
    guess: &[f64],
    times: &[f64],
    assembly: &AssemblyOptions,
) -> Result<InverseResult, Error> {
    let info = system.info();
    if guess.len() != info.n() {
        return Err(Error::WrongLength {
            what: "guess",
            expected: info.n(),
            got: guess.len(),
        });
    }
    check_inverse_dynamics(system, &drives, times)?;
    let coordinates = drives.iter().map(|d| d.coordinate).collect();
    let mut inv = InverseDynamics::new(system, drives, *assembly)?;
    inv.q.copy_from_slice(guess);
    // Reserved exactly: a growing vector would hold up to twice the room it needs.
    let mut samples = Vec::with_capacity(times.len());
    for &t in times {
        samples.push(inv.solve_at(system, t)?);
    }
    Ok(InverseResult {
        info: system.info().clone(),
        driven: coordinates,
        samples,
    })
}

/// The refusals [`inverse_dynamics_from`] makes before any work, alone: a drive of an
/// unknown coordinate or one driven twice ([`Error::UnknownDriver`],
/// [`Error::RepeatedCoordinate`]), and more samples than [`crate::MAX_OUTPUT_BYTES`] hold
/// ([`Error::TooMuchOutput`]). It solves nothing, so a caller can refuse a run before it
/// claims anything for it (the command-line tool, before it touches the output folder).
///
/// # Errors
/// Those above.
pub fn check_inverse_dynamics(
    system: &dyn System,
    drives: &[Drive],
    times: &[f64],
) -> Result<(), Error> {
    let info = system.info();
    let fixed: Vec<usize> = drives.iter().map(|d| d.coordinate).collect();
    check_fixed(info, &fixed)?;
    let columns = 1 + 3 * info.n() + drives.len() + info.m();
    check_output_memory(times.len(), columns, SAMPLE_OVERHEAD)
}

/// Sample times t_start, t_start + 1/rate, ..., ending exactly at t_end.
pub fn sample_times(t_start: f64, t_end: f64, rate: f64) -> Vec<f64> {
    let k = (((t_end - t_start) * rate) - 1e-9).ceil().max(0.0) as usize;
    (0..=k)
        .map(|i| {
            if i == k {
                t_end
            } else {
                t_start + i as f64 / rate
            }
        })
        .collect()
}

/// The result of [`inverse_dynamics`].
#[derive(Clone, Debug, PartialEq)]
pub struct InverseResult {
    /// The system's names and sizes.
    pub info: SystemInfo,
    /// Driven coordinate indices, in drive order.
    pub driven: Vec<usize>,
    /// One entry per time.
    pub samples: Vec<InverseSample>,
}

impl InverseResult {
    /// Column headers: t, q, `<q>_dot`, `<q>_ddot`, `tau_<driven>`, lambda_1..lambda_m.
    pub fn headers(&self) -> Vec<String> {
        let c = &self.info.coordinates;
        let mut h = vec!["t".to_string()];
        h.extend(c.iter().cloned());
        h.extend(c.iter().map(|x| format!("{x}_dot")));
        h.extend(c.iter().map(|x| format!("{x}_ddot")));
        h.extend(self.driven.iter().map(|&k| format!("tau_{}", c[k])));
        h.extend((1..=self.info.m()).map(|i| format!("lambda_{i}")));
        h
    }

    /// The samples as rows in [`InverseResult::headers`] order.
    pub fn rows(&self) -> Vec<Vec<f64>> {
        self.samples.iter().map(InverseSample::row).collect()
    }

    /// [`InverseResult::rows`], consuming the samples one by one (so that the rows take the
    /// memory the samples free, instead of doubling it).
    pub fn into_rows(self) -> Vec<Vec<f64>> {
        self.samples.into_iter().map(|s| s.row()).collect()
    }
}

impl InverseSample {
    /// The sample as one row in [`InverseResult::headers`] order.
    pub fn row(&self) -> Vec<f64> {
        let parts = [&self.q, &self.qd, &self.qdd, &self.driving, &self.lambda];
        let mut r = Vec::with_capacity(1 + parts.iter().map(|p| p.len()).sum::<usize>());
        r.push(self.t);
        for part in parts {
            r.extend_from_slice(part);
        }
        r
    }
}
