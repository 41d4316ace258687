//! The recorded output of a simulation: one row per output sample, stored flat so that
//! recording a sample only grows one buffer.

use crate::algorithms::mobility::Mobility;
use crate::simulation::singular::SingularPassage;
use crate::system::SystemInfo;

/// One recorded sample, borrowed from a [`Trajectory`].
#[derive(Clone, Copy, Debug)]
pub struct Sample<'a> {
    /// Time t (s).
    pub t: f64,
    /// Coordinates q (units as declared: m or rad).
    pub q: &'a [f64],
    /// Rates q'.
    pub qd: &'a [f64],
    /// Accelerations q''.
    pub qdd: &'a [f64],
    /// Lagrange multipliers lambda (sign convention: M q'' + ... + Phi_q^T lambda = tau).
    pub lambda: &'a [f64],
    /// |Phi(q, t)|_inf.
    pub constraint_error: f64,
    /// |Phi_q q' + Phi_t|_inf.
    pub velocity_constraint_error: f64,
    /// Kinetic energy T.
    pub kinetic: f64,
    /// Potential energy Pi.
    pub potential: f64,
    /// Work done since t = 0 by tau and by the constraint rows that move with t: the
    /// integral of tau . q' + lambda . Phi_t dt ([`crate::Dynamics::constraint_power`]), so
    /// that T + Pi - W stays constant.
    pub work: f64,
}

/// Counters of one integration run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolverStats {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (adaptive integrators).
    pub rejected_steps: usize,
    /// Evaluations of the right-hand side (augmented solves).
    pub rhs_evaluations: usize,
    /// Wall-clock time of the run (s).
    pub wall_time_s: f64,
    /// Right-hand sides solved by the augmented Lagrangian route (redundant rows, large
    /// systems, near-singular configurations) rather than by LU.
    pub augmented_solves: usize,
    /// Right-hand sides solved by the banded direct route (chains and windows whose rows
    /// order into a narrow band).
    pub banded_solves: usize,
    /// Right-hand sides solved by the system's generated forward dynamics (a mechanism
    /// without constraint rows: no M evaluated or factored).
    pub generated_solves: usize,
    /// Multiply-adds of the run's rank factorisations of Phi_q (`RowBasis`) and of its
    /// projections' Gram matrices Phi_q Phi_q^T: the counted work of the structures whose
    /// cost depends on the solvers' coordinate order (a count, the same on every machine).
    pub factor_work: u64,
}

/// A recorded trajectory: rows of [t, q, q', q'', lambda, |Phi|, |Phi_q q' + Phi_t|, T, Pi, W].
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// Names and sizes of the system simulated.
    pub info: SystemInfo,
    /// Run counters.
    pub stats: SolverStats,
    /// Mobility at the first sample (rank of Phi_q, redundant rows).
    pub mobility: Option<Mobility>,
    /// Singular configurations passed through, in time order.
    pub singular_passages: Vec<SingularPassage>,
    data: Vec<f64>,
}

impl Trajectory {
    /// An empty trajectory for `info`, with room for `capacity` samples.
    pub fn with_capacity(info: SystemInfo, capacity: usize) -> Self {
        let stride = Self::stride_of(&info);
        Self {
            info,
            stats: SolverStats::default(),
            mobility: None,
            singular_passages: Vec::new(),
            data: Vec::with_capacity(capacity * stride),
        }
    }

    /// Values per row for a system with the sizes of `info`: 1 + 3n + m + 5.
    pub(crate) fn stride_of(info: &SystemInfo) -> usize {
        1 + 3 * info.n() + info.m() + 5
    }

    /// Number of f64 values per row.
    pub fn stride(&self) -> usize {
        Self::stride_of(&self.info)
    }

    /// Appends one sample. The slices must have lengths n, n, n, m.
    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        lambda: &[f64],
        constraint_error: f64,
        velocity_constraint_error: f64,
        energies: [f64; 3],
    ) {
        debug_assert_eq!(q.len(), self.info.n());
        debug_assert_eq!(lambda.len(), self.info.m());
        self.data.push(t);
        self.data.extend_from_slice(q);
        self.data.extend_from_slice(qd);
        self.data.extend_from_slice(qdd);
        self.data.extend_from_slice(lambda);
        self.data
            .extend_from_slice(&[constraint_error, velocity_constraint_error]);
        self.data.extend_from_slice(&energies);
    }

    /// Keeps the first `len` samples (the others came from a step that failed).
    pub(crate) fn truncate(&mut self, len: usize) {
        let stride = self.stride();
        self.data.truncate(len * stride);
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.data.len() / self.stride()
    }

    /// True when no sample is recorded.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Sample `i` (panics out of range, like slice indexing).
    pub fn sample(&self, i: usize) -> Sample<'_> {
        let (n, m) = (self.info.n(), self.info.m());
        let row = &self.data[i * self.stride()..(i + 1) * self.stride()];
        let tail = &row[1 + 3 * n + m..];
        Sample {
            t: row[0],
            q: &row[1..1 + n],
            qd: &row[1 + n..1 + 2 * n],
            qdd: &row[1 + 2 * n..1 + 3 * n],
            lambda: &row[1 + 3 * n..1 + 3 * n + m],
            constraint_error: tail[0],
            velocity_constraint_error: tail[1],
            kinetic: tail[2],
            potential: tail[3],
            work: tail[4],
        }
    }

    /// Iterates over the samples in time order.
    pub fn samples(&self) -> impl Iterator<Item = Sample<'_>> + '_ {
        (0..self.len()).map(|i| self.sample(i))
    }

    /// The last sample, if any.
    pub fn last(&self) -> Option<Sample<'_>> {
        self.len().checked_sub(1).map(|i| self.sample(i))
    }

    /// Column headers matching [`Trajectory::row`]: t, q names, `<q>_dot`, `<q>_ddot`,
    /// lambda_1..lambda_m, constraint_error, velocity_constraint_error, kinetic, potential, work.
    pub fn headers(&self) -> Vec<String> {
        let c = &self.info.coordinates;
        let mut h = vec!["t".to_string()];
        h.extend(c.iter().cloned());
        h.extend(c.iter().map(|x| format!("{x}_dot")));
        h.extend(c.iter().map(|x| format!("{x}_ddot")));
        h.extend((1..=self.info.m()).map(|i| format!("lambda_{i}")));
        for s in [
            "constraint_error",
            "velocity_constraint_error",
            "kinetic",
            "potential",
            "work",
        ] {
            h.push(s.to_string());
        }
        h
    }

    /// Row `i` as the flat values in [`Trajectory::headers`] order.
    pub fn row(&self, i: usize) -> &[f64] {
        &self.data[i * self.stride()..(i + 1) * self.stride()]
    }
}
