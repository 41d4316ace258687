//! The augmented system of constrained dynamics, solved by the augmented Lagrangian method:
//! well posed when the constraint Jacobian loses rank.
//!
//! ```text
//! [ M  A^T ] [ x      ]   [ Q     ]        M q'' + Phi_q^T lambda = tau - C q' - g
//! [ A  0   ] [ lambda ] = [ gamma ]        Phi_q q'' = gamma
//! ```
//!
//! With redundant constraint rows (a planar loop closed by spatial joints, Bricard's
//! linkage) or at a singular configuration passed for an instant (a chain of four-bar
//! loops lying flat), A = Phi_q has rank r < m and the matrix above is singular, yet x = q''
//! is unique whenever M is positive definite on the null space of A: the constraint forces
//! A^T lambda are unique, only lambda is not. The augmented Lagrangian formulation (Bayo,
//! García de Jalón & Serna, Comput. Methods Appl. Mech. Eng. 71, 1988; Bayo & Ledesma,
//! Nonlinear Dyn. 9, 1996; the index-3 form ALI3-P of Cuadrado et al., used by the IFToMM
//! benchmark's reference solutions) never factors that matrix. It factors
//!
//! ```text
//! N = M + alpha A^T A,
//! ```
//!
//! which is symmetric positive definite exactly when M is positive definite on the null
//! space of A (M itself may be singular: the seed's lumped rod), and iterates
//!
//! ```text
//! x_{k+1}      = x_k + N^-1 (r1 + alpha A^T r2),   r1 = Q - M x_k - A^T lambda_k,  r2 = gamma - A x_k
//! lambda_{k+1} = lambda_k + alpha (A x_{k+1} - gamma)
//! ```
//!
//! from x_0 = 0, lambda_0 = 0. (This is the classical iteration x_{k+1} = N^-1 (Q +
//! alpha A^T gamma - A^T lambda_k) written in correction form: the residuals are computed
//! from M and A, so the factorisation of N only has to be accurate enough to contract, as in
//! iterative refinement.) The error of lambda in a direction where A has singular value
//! sigma and the mass is mu shrinks by mu / (mu + alpha sigma^2) per iteration; with alpha
//! = 1e6 max M_ii / max (A^T A)_ii two or three iterations reach round-off on regular
//! configurations. Near a singular configuration sigma is small and the contraction slow:
//! when a correction shrinks by less than a factor 5, alpha is raised a hundredfold (up to
//! 1e4 times), re-factoring N and continuing from the current iterate. lambda stays in the
//! range of A, so it converges to the minimum-norm
//! multipliers; where gamma has a part outside that range (the instant of a singular
//! configuration) x still converges, since A^T never sees that part.
//!
//! N is banded for chains declared in order and is factored inside its envelope
//! ([`Envelope`]); products with A skip each row's zeros ([`RowSpans`]).

use nalgebra::DMatrix;

use crate::linalg::{Envelope, NotPositiveDefinite, RowBasis, RowSpans, inf_norm, max_nan};

/// Default penalty factor kappa: alpha = kappa max_i M_ii / max_i (A^T A)_ii.
pub const DEFAULT_PENALTY: f64 = 1e6;

/// Largest factor by which a slowly converging solve raises the penalty (in steps of 100).
const MAX_BOOST: f64 = 1e4;

/// Relative pivot below which N counts as not positive definite.
const PIVOT_TOLERANCE: f64 = 1e-13;

/// Workspace of the augmented Lagrangian solve; allocates nothing after
/// [`AugmentedLagrangian::new`].
#[derive(Clone, Debug)]
pub struct AugmentedLagrangian {
    n: usize,
    spans: RowSpans,
    matrix: Envelope,
    basis: RowBasis,
    /// gamma without its part in the null space of A^T.
    consistent: Vec<f64>,
    x: Vec<f64>,
    lambda: Vec<f64>,
    r1: Vec<f64>,
    r2: Vec<f64>,
    work: Vec<f64>,
    /// With a fixed pattern ([`AugmentedLagrangian::fix`]): the first position of each row
    /// of M's lower triangle (in the solver order) that can be nonzero (p itself for a
    /// diagonal row).
    mass_first: Option<Vec<usize>>,
    /// The coordinate at each position of the envelope (identity unless fixed in an
    /// order), and the right-hand side of its solves in that order.
    order: Vec<usize>,
    permuted: Vec<f64>,
    /// Penalty factor kappa (default [`DEFAULT_PENALTY`]).
    pub penalty: f64,
    /// Iteration limit per solve (default 60).
    pub max_iterations: usize,
    /// Iterations of the last solve.
    pub iterations: usize,
    /// Solves that reached the iteration limit before the correction of x stopped
    /// decreasing (they return the last iterate).
    pub unconverged: usize,
}

impl AugmentedLagrangian {
    /// Workspace for n coordinates and m constraint rows.
    pub fn new(n: usize, m: usize) -> Self {
        Self {
            n,
            spans: RowSpans::new(m, n),
            matrix: Envelope::new(n),
            basis: RowBasis::new(m, n),
            consistent: vec![0.0; m],
            x: vec![0.0; n],
            lambda: vec![0.0; m],
            r1: vec![0.0; n],
            r2: vec![0.0; m],
            work: vec![0.0; n],
            mass_first: None,
            order: (0..n).collect(),
            permuted: vec![0.0; n],
            penalty: DEFAULT_PENALTY,
            max_iterations: 60,
            iterations: 0,
            unconverged: 0,
        }
    }

    /// Fixes the structural nonzeros of every M and A to come, (row, column) pairs: A's
    /// row spans and Gram pairs are no longer scanned per solve, nor M's envelope
    /// (see [`RowSpans::fix`]). Allocates (once).
    #[cfg(test)]
    pub fn fix(&mut self, mass: &[(usize, usize)], a: &[(usize, usize)]) {
        let order: Vec<usize> = (0..self.n).collect();
        self.fix_ordered(mass, a, &order);
    }

    /// [`AugmentedLagrangian::fix`] in the coordinate order `order` (the mechanism's
    /// `Sparsity::order`, the coordinate at each position): the envelope of
    /// M + alpha A^T A is stored and factored in that order, A's spans and rank basis
    /// too, so a declaration that scatters the coordinates of a row costs what the
    /// pattern's band allows. The solution is the same up to round-off. Allocates (once).
    pub fn fix_ordered(&mut self, mass: &[(usize, usize)], a: &[(usize, usize)], order: &[usize]) {
        self.spans.fix_ordered(a, order);
        self.basis.fix_ordered(a, order);
        self.order = order.to_vec();
        let mut place = vec![0; self.n];
        for (p, &i) in order.iter().enumerate() {
            place[i] = p;
        }
        let mut first: Vec<usize> = (0..self.n).collect();
        for &(i, j) in mass {
            let (pi, pj) = (place[i], place[j]);
            let (hi, lo) = (pi.max(pj), pi.min(pj));
            first[hi] = first[hi].min(lo);
        }
        self.matrix
            .reserve(&self.spans.normal_profile(first.clone()));
        self.mass_first = Some(first);
    }

    /// Solves the augmented system for x and lambda (see the module docs). `mass` is n x n
    /// and symmetric (its upper triangle is read), `a` is m x n.
    ///
    /// Fails with [`NotPositiveDefinite`] when N = M + alpha A^T A is not positive definite:
    /// M is singular or indefinite on the motions the constraints allow, so the
    /// accelerations are not determined. [`AugmentedLagrangian::undetermined_direction`]
    /// then gives that motion.
    pub fn solve(
        &mut self,
        mass: &DMatrix<f64>,
        a: &DMatrix<f64>,
        q: &[f64],
        gamma: &[f64],
    ) -> Result<(), NotPositiveDefinite> {
        self.spans.scan(a);
        // Redundant rows: the part of gamma in the null space of A^T (zero in exact
        // arithmetic, round-off and velocity error in practice) would make lambda grow
        // without bound along it and, through rounding, drag x. Solve with the consistent
        // part.
        self.consistent.copy_from_slice(gamma);
        if self.basis.factor(a) < self.consistent.len() {
            self.basis.min_norm(&mut self.consistent);
        }
        let consistent = std::mem::take(&mut self.consistent);
        let result = self.iterate(mass, a, q, &consistent);
        self.consistent = consistent;
        result
    }

    /// The iteration of [`AugmentedLagrangian::solve`] with a consistent gamma.
    fn iterate(
        &mut self,
        mass: &DMatrix<f64>,
        a: &DMatrix<f64>,
        q: &[f64],
        gamma: &[f64],
    ) -> Result<(), NotPositiveDefinite> {
        let n = self.n;
        let mut boost = 1.0;
        let mut alpha = self.assemble(mass, a, boost);
        self.matrix.factor(PIVOT_TOLERANCE)?;
        self.x.fill(0.0);
        self.lambda.fill(0.0);
        let mut last = f64::INFINITY;
        self.iterations = 0;
        loop {
            self.iterations += 1;
            // r1 = Q - M x - A^T lambda, r2 = gamma - A x.
            self.mass_times_x(mass);
            self.spans.mul_transpose(a, &self.lambda, &mut self.r1);
            for ((r1, qi), mx) in self.r1.iter_mut().zip(q).zip(&self.work) {
                *r1 = qi - mx - *r1;
            }
            self.spans.mul(a, &self.x, &mut self.r2);
            for (r2, g) in self.r2.iter_mut().zip(gamma) {
                *r2 = g - *r2;
            }
            // delta = N^-1 (r1 + alpha A^T r2), kept in `work`.
            self.spans.mul_transpose(a, &self.r2, &mut self.work);
            for i in 0..n {
                self.work[i] = self.r1[i] + alpha * self.work[i];
            }
            for (v, &i) in self.permuted.iter_mut().zip(&self.order) {
                *v = self.work[i];
            }
            self.matrix.solve(&mut self.permuted);
            for (&v, &i) in self.permuted.iter().zip(&self.order) {
                self.work[i] = v;
            }
            let step = inf_norm(&self.work);
            for i in 0..n {
                self.x[i] += self.work[i];
            }
            // lambda += alpha (A x - gamma).
            self.spans.mul(a, &self.x, &mut self.r2);
            for ((l, ax), g) in self.lambda.iter_mut().zip(&self.r2).zip(gamma) {
                *l += alpha * (ax - g);
            }
            let size = inf_norm(&self.x);
            // Converged when the correction is at round-off, or has stopped shrinking near it.
            let done = step <= 1e-15 * size
                || step == 0.0
                || (self.iterations > 1 && step >= 0.5 * last && step <= 1e-11 * size);
            if done {
                return Ok(());
            }
            if self.iterations >= self.max_iterations || !step.is_finite() {
                self.unconverged += 1;
                return Ok(());
            }
            // Slow contraction: a constraint direction with a small singular value (near a
            // singular configuration). A larger penalty speeds it up; the residual form keeps
            // the iterate, and the factor stays accurate enough to refine while kappa is
            // below about 1e10. A correction that does not shrink at all (ratio > 0.999) is not
            // slow convergence but round-off in a redundant direction: no boost for that.
            let ratio = step / last;
            if self.iterations >= 3
                && ratio > 0.2
                && ratio < 0.999
                && step > 1e-8 * size
                && boost < MAX_BOOST
            {
                boost *= 100.0;
                alpha = self.assemble(mass, a, boost);
                if self.matrix.factor(PIVOT_TOLERANCE).is_err() {
                    boost /= 100.0;
                    alpha = self.assemble(mass, a, boost);
                    self.matrix.factor(PIVOT_TOLERANCE)?;
                    boost = MAX_BOOST;
                }
            }
            last = step;
        }
    }

    /// N = M + alpha A^T A into the envelope, alpha = boost kappa max M_ii / max (A^T A)_ii;
    /// returns alpha.
    fn assemble(&mut self, mass: &DMatrix<f64>, a: &DMatrix<f64>, boost: f64) -> f64 {
        let n = self.n;
        let env = &mut self.matrix;
        env.clear();
        let ms = mass.as_slice();
        let mut mass_scale = 0.0f64;
        for i in 0..n {
            mass_scale = max_nan(mass_scale, ms[i + i * n].abs());
            // Without a fixed pattern the order is the declaration's (positions are columns).
            let first = match &self.mass_first {
                Some(f) => Some(f[i]),
                None => (0..i).find(|&j| ms[j + i * n] != 0.0),
            };
            if let Some(j) = first {
                env.widen(i, j);
            }
        }
        // max_i (A^T A)_ii = max_i sum_r A_ri^2.
        self.work.fill(0.0);
        self.spans.column_squares(a, &mut self.work);
        let constraint_scale = inf_norm(&self.work);
        if mass_scale == 0.0 {
            mass_scale = 1.0;
        }
        let alpha = if constraint_scale > 0.0 {
            boost * self.penalty * mass_scale / constraint_scale
        } else {
            0.0
        };
        self.spans.add_gram_transpose(a, alpha, env);
        for p in 0..n {
            let i = self.order[p];
            for pj in env.first(p)..=p {
                let j = self.order[pj];
                let v = ms[i.min(j) + i.max(j) * n];
                if v != 0.0 {
                    env.add(p, pj, v);
                }
            }
        }
        alpha
    }

    /// work = M x over the envelope (M symmetric; its upper triangle is read).
    fn mass_times_x(&mut self, mass: &DMatrix<f64>) {
        let n = self.n;
        let ms = mass.as_slice();
        self.work.fill(0.0);
        for p in 0..n {
            let i = self.order[p];
            let xi = self.x[i];
            let mut acc = ms[i + i * n] * xi;
            for pj in self.matrix.first(p)..p {
                let j = self.order[pj];
                let v = ms[i.min(j) + i.max(j) * n];
                acc += v * self.x[j];
                self.work[j] += v * xi;
            }
            self.work[i] += acc;
        }
    }

    /// Entries below the diagonal in the envelope of N at the last solve.
    #[cfg(test)]
    pub fn profile(&self) -> usize {
        self.matrix.profile()
    }

    /// x (q'') of the last solve.
    pub fn solution(&self) -> &[f64] {
        &self.x
    }

    /// lambda of the last solve.
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }

    /// After a failed solve: the motion v (length n, largest entry 1 in magnitude) on which
    /// M + alpha A^T A is singular, i.e. an allowed motion (A v ~ 0) with no inertia.
    pub fn undetermined_direction(&mut self, failure: NotPositiveDefinite, v: &mut [f64]) {
        self.matrix.null_direction(failure.row, &mut self.permuted);
        for (&x, &i) in self.permuted.iter().zip(&self.order) {
            v[i] = x;
        }
        let s = inf_norm(v);
        if s > 0.0 {
            v.iter_mut().for_each(|x| *x /= s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact KKT solution by nalgebra's LU, for a regular system.
    fn reference(mass: &DMatrix<f64>, a: &DMatrix<f64>, q: &[f64], g: &[f64]) -> Vec<f64> {
        let (n, m) = (mass.nrows(), a.nrows());
        let mut k = DMatrix::zeros(n + m, n + m);
        k.view_mut((0, 0), (n, n)).copy_from(mass);
        k.view_mut((n, 0), (m, n)).copy_from(a);
        k.view_mut((0, n), (n, m)).copy_from(&a.transpose());
        let mut rhs = nalgebra::DVector::zeros(n + m);
        rhs.rows_mut(0, n).copy_from_slice(q);
        rhs.rows_mut(n, m).copy_from_slice(g);
        k.lu().solve(&rhs).unwrap().iter().copied().collect()
    }

    #[test]
    fn regular_system_matches_lu_with_singular_mass() {
        // M singular (zero rows for coordinates 2 and 3), regular on null(A): the seed's case.
        let mass = DMatrix::from_row_slice(
            4,
            4,
            &[
                2.0, 0.0, 0.0, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.3, 0.0, 0.0, 1.5,
            ],
        );
        let a = DMatrix::from_row_slice(
            3,
            4,
            &[1.0, 0.2, 0.0, -1.0, 0.3, 0.0, 0.7, 0.1, -0.4, 0.5, 0.6, 0.0],
        );
        let (q, g) = ([0.3, -1.0, 0.2, 2.0], [0.5, -0.25, 1.0]);
        let want = reference(&mass, &a, &q, &g);
        let mut al = AugmentedLagrangian::new(4, 3);
        al.solve(&mass, &a, &q, &g).unwrap();
        for (x, w) in al.solution().iter().zip(&want[..4]) {
            assert!((x - w).abs() < 1e-12, "{x} vs {w}");
        }
        // The iteration's own lambda carries the penalty's kappa eps = 1e-10 relative
        // (Dynamics recovers exact multipliers from the force balance instead).
        for (l, w) in al.multipliers().iter().zip(&want[4..]) {
            assert!((l - w).abs() < 1e-9 * w.abs().max(1.0), "{l} vs {w}");
        }
        assert!(al.iterations <= 6, "{} iterations", al.iterations);
    }

    #[test]
    fn fixed_pattern_gives_the_scanned_solution_on_random_windows() {
        // A02-like windows: M tridiagonal SPD, each row of A nonzero on a window of up to
        // four columns sliding along the chain (m = n - 1 rows, full rank), some pattern
        // entries numerically zero at this state. The solve with the pattern fixed must give
        // the scanned solve's bits (same spans, same order of operations) and the dense LU's
        // solution to round-off.
        let mut seed = 0x28u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for n in [6, 21, 60] {
            let m = n - 1;
            let mut mass = DMatrix::zeros(n, n);
            let mut mass_pattern = Vec::new();
            for i in 0..n {
                mass[(i, i)] = 2.0;
                mass_pattern.push((i, i));
                if i + 1 < n {
                    let v = 0.4 * next();
                    mass[(i, i + 1)] = v;
                    mass[(i + 1, i)] = v;
                    mass_pattern.extend([(i, i + 1), (i + 1, i)]);
                }
            }
            let mut a = DMatrix::zeros(m, n);
            let mut a_pattern = Vec::new();
            for r in 0..m {
                // Window r..r+4 (clipped), dominant entry on column r + 1: full row rank.
                for j in r..(r + 4).min(n) {
                    a_pattern.push((r, j));
                    a[(r, j)] = if j == r + 1 {
                        3.0
                    } else if j == r + 3 {
                        0.0
                    } else {
                        next()
                    };
                }
            }
            let q: Vec<f64> = (0..n).map(|_| next()).collect();
            let g: Vec<f64> = (0..m).map(|_| next()).collect();
            let want = reference(&mass, &a, &q, &g);
            let mut scanned = AugmentedLagrangian::new(n, m);
            scanned.solve(&mass, &a, &q, &g).unwrap();
            let mut fixed = AugmentedLagrangian::new(n, m);
            fixed.fix(&mass_pattern, &a_pattern);
            fixed.solve(&mass, &a, &q, &g).unwrap();
            // The band of N = M + alpha A^T A is 3 wide: its profile is linear in n.
            assert!(fixed.profile() <= 3 * n, "profile {}", fixed.profile());
            // A well-conditioned system (diagonally dominant M, A with a dominant 3 per row),
            // |x| of order 1: 1e-11 absolute bounds the iteration's round-off.
            for (k, w) in want[..n].iter().enumerate() {
                let (s, f) = (scanned.solution()[k], fixed.solution()[k]);
                assert!((f - w).abs() < 1e-11, "n {n}: x[{k}] {f} vs {w}");
                assert!(
                    (f - s).abs() <= 1e-14 * w.abs().max(1.0),
                    "n {n}: {f} vs {s}"
                );
            }
        }
    }

    #[test]
    fn repeated_rows_give_unique_accelerations_and_minimum_norm_multipliers() {
        // Point mass in the plane on x = 0, declared twice (once scaled by 2).
        let mass = DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(&[3.0, 3.0]));
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 2.0, 0.0]);
        let (q, g) = ([6.0, -9.0], [0.0, 0.0]);
        let mut al = AugmentedLagrangian::new(2, 2);
        al.solve(&mass, &a, &q, &g).unwrap();
        // x'' = 0, y'' = -3; force A^T lambda = 6 on x, split minimum-norm: lambda = 6 (1, 2)/5.
        let (x, l) = (al.solution(), al.multipliers());
        assert!(x[0].abs() < 1e-13 && (x[1] + 3.0).abs() < 1e-13, "{x:?}");
        assert!(
            (l[0] - 1.2).abs() < 1e-9 && (l[1] - 2.4).abs() < 1e-9,
            "{l:?}"
        );
    }

    #[test]
    fn no_inertia_on_an_allowed_motion_is_reported() {
        // Two coordinates, one constraint x0 = 0, no mass on x1: x1'' undetermined.
        let mass = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 0.0]);
        let a = DMatrix::from_row_slice(1, 2, &[1.0, 0.0]);
        let mut al = AugmentedLagrangian::new(2, 1);
        let err = al.solve(&mass, &a, &[1.0, 1.0], &[0.0]).unwrap_err();
        let mut v = [0.0; 2];
        al.undetermined_direction(err, &mut v);
        assert_eq!(err.row, 1);
        assert!(
            v[0].abs() < 1e-15 && (v[1].abs() - 1.0).abs() < 1e-15,
            "{v:?}"
        );
    }
}
