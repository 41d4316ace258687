//! The augmented (KKT) system by a basis of the null space of Phi_q (coordinate
//! partitioning: Wehage & Haug, J. Mech. Des. 104, 1982; the null-space method of Nocedal &
//! Wright, Numerical Optimization, 2nd ed., sec. 16.2):
//!
//! ```text
//! [ M      Phi_q^T ] [ q''    ]   [ Q     ]
//! [ Phi_q  0       ] [ lambda ] = [ gamma ]
//! ```
//!
//! LU with row pivoting of the transpose, P Phi_q^T = [L1; L2] U (L1 m x m unit lower
//! triangular, U m x m upper triangular), splits the n coordinates into m dependent ones
//! (the pivot rows: for each constraint row in turn, the coordinate it moves most) and
//! d = n - m independent ones: Phi_q P^T = B [I  L1^-T L2^T] with B = U^T L1^T, the
//! dependent columns of Phi_q. The columns of Z = P^T [X; I], X = -L1^-T L2^T, span
//! null(Phi_q); with the particular solution q''_p = P^T [B^-1 gamma; 0], every
//! q'' = q''_p + Z z satisfies the constraint rows, and the first block row projected onto
//! Z is the reduced system
//!
//! ```text
//! (Z^T M Z) z = Z^T (Q - M q''_p),        q'' = q''_p + Z z,
//! ```
//!
//! symmetric positive definite exactly when M is positive definite on null(Phi_q), the
//! condition for the motion to be determined (M itself may be singular, as the seed's is).
//! The dependent rows of the first block row then give the multipliers:
//! B^T lambda = L1 U lambda = (Q - M q'')_dep.
//!
//! Cost: m^2 n for the factorisation, m d (m + d) for Z^T M Z, d^3 / 6 for its L D L^T,
//! against (n + m)^3 / 3 for LU of the whole matrix: 4-6x fewer operations for the one-degree-
//! of-freedom mechanisms (n = 3 or 4), about 1.5x fewer for a 32-bar chain.
//!
//! Accuracy: the route is backward stable when B and Z^T M Z are well conditioned. The
//! factorisation returns an indicator of both, max(max_k |Phi_q,k|_inf / |u_kk|, s / p_min): a
//! pivot u_kk is the part of constraint row k independent of the rows before it (so the first
//! term is large near redundant rows and singular positions, whatever the units of each row), s
//! is the largest |M_ii| times the largest |Z_j|^2 and p_min the smallest pivot D_jj of the L D
//! L^T factorisation of Z^T M Z (large when M is nearly singular on an allowed motion). The
//! caller hands the solve to a route with a true condition estimate when it is large.

use nalgebra::SMatrix;

mod kernel;

use kernel::Parts;

/// A null-space solve of the augmented system (see the module docs), with run-time sizes
/// ([`NullSpace`]) or static ones ([`FixedNullSpace`], which a compiled mechanism provides
/// through [`crate::System::null_space_solver`]). Matrices are column-major slices (M is
/// n x n, Phi_q is m x n). Nothing allocates in `factor` or `solve`.
pub trait NullSpaceSolve: Send + Sync + core::fmt::Debug {
    /// (n, m): the number of coordinates and of constraint rows.
    fn dims(&self) -> (usize, usize);
    /// Factors Phi_q^T and Z^T M Z. Returns the condition indicator max(max_k |Phi_q,k|_inf /
    /// |u_kk|, s / p_min) (at least 1), or `None` when there are more rows than coordinates, a
    /// pivot of Phi_q vanishes (rank below m), or Z^T M Z is not positive definite to working
    /// precision; nothing can be solved then.
    fn factor(&mut self, mass: &[f64], phi_q: &[f64]) -> Option<f64>;
    /// Solves in place: `sol` holds [Q; gamma] (n + m values) and receives [q''; lambda],
    /// from the last successful [`NullSpaceSolve::factor`].
    ///
    /// # Panics
    /// If `sol` is shorter than n + m.
    fn solve(&mut self, sol: &mut [f64]);
    /// [`NullSpaceSolve::solve`] for q'' alone: the first n values of `sol` receive q'',
    /// the last m are unspecified (an integrator's stages need no multipliers). The
    /// default solves for both.
    ///
    /// # Panics
    /// If `sol` is shorter than n + m.
    fn solve_accelerations(&mut self, sol: &mut [f64]) {
        self.solve(sol);
    }
    /// A boxed copy.
    fn clone_box(&self) -> Box<dyn NullSpaceSolve>;
}

impl Clone for Box<dyn NullSpaceSolve> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// The null-space solve for run-time sizes n and m, in storage allocated once.
#[derive(Clone, Debug)]
pub struct NullSpace {
    n: usize,
    m: usize,
    lu: Vec<f64>,
    cols: Vec<usize>,
    pm: Vec<f64>,
    x: Vec<f64>,
    w: Vec<f64>,
    r: Vec<f64>,
    u: Vec<f64>,
    v: Vec<f64>,
    z: Vec<f64>,
    inv: Vec<f64>,
}

impl NullSpace {
    /// A workspace for n coordinates and m constraint rows.
    pub fn new(n: usize, m: usize) -> Self {
        let d = n.saturating_sub(m);
        Self {
            n,
            m,
            lu: vec![0.0; m * n],
            cols: vec![0; n],
            pm: vec![0.0; n * n],
            x: vec![0.0; m * d],
            w: vec![0.0; m * d],
            r: vec![0.0; d * d],
            u: vec![0.0; n],
            v: vec![0.0; m],
            z: vec![0.0; d],
            inv: vec![0.0; n.max(m)],
        }
    }

    fn parts(&mut self) -> Parts<'_> {
        Parts {
            lu: &mut self.lu,
            cols: &mut self.cols,
            pm: &mut self.pm,
            x: &mut self.x,
            w: &mut self.w,
            r: &mut self.r,
            u: &mut self.u,
            v: &mut self.v,
            z: &mut self.z,
            inv: &mut self.inv,
        }
    }
}

impl NullSpaceSolve for NullSpace {
    fn dims(&self) -> (usize, usize) {
        (self.n, self.m)
    }
    fn factor(&mut self, mass: &[f64], phi_q: &[f64]) -> Option<f64> {
        let (n, m) = (self.n, self.m);
        kernel::factor::<0, 0>(&mut self.parts(), n, m, mass, phi_q)
    }
    fn solve(&mut self, sol: &mut [f64]) {
        let (n, m) = (self.n, self.m);
        kernel::solve::<0, 0>(&mut self.parts(), n, m, sol, true);
    }
    fn solve_accelerations(&mut self, sol: &mut [f64]) {
        let (n, m) = (self.n, self.m);
        kernel::solve::<0, 0>(&mut self.parts(), n, m, sol, false);
    }
    fn clone_box(&self) -> Box<dyn NullSpaceSolve> {
        Box::new(self.clone())
    }
}

/// The null-space solve for static sizes N and M (N x N and M x N storage, every loop with
/// a constant trip count).
#[derive(Clone, Debug)]
pub struct FixedNullSpace<const N: usize, const M: usize> {
    lu: SMatrix<f64, N, M>,
    cols: [usize; N],
    pm: SMatrix<f64, N, N>,
    x: SMatrix<f64, M, N>,
    w: SMatrix<f64, M, N>,
    r: SMatrix<f64, N, N>,
    u: [f64; N],
    v: [f64; M],
    z: [f64; N],
    inv: [f64; N],
}

impl<const N: usize, const M: usize> Default for FixedNullSpace<N, M> {
    fn default() -> Self {
        Self {
            lu: SMatrix::zeros(),
            cols: [0; N],
            pm: SMatrix::zeros(),
            x: SMatrix::zeros(),
            w: SMatrix::zeros(),
            r: SMatrix::zeros(),
            u: [0.0; N],
            v: [0.0; M],
            z: [0.0; N],
            inv: [0.0; N],
        }
    }
}

impl<const N: usize, const M: usize> FixedNullSpace<N, M> {
    fn parts(&mut self) -> Parts<'_> {
        Parts {
            lu: self.lu.as_mut_slice(),
            cols: &mut self.cols,
            pm: self.pm.as_mut_slice(),
            x: self.x.as_mut_slice(),
            w: self.w.as_mut_slice(),
            r: self.r.as_mut_slice(),
            u: &mut self.u,
            v: &mut self.v,
            z: &mut self.z,
            inv: &mut self.inv,
        }
    }
}

impl<const N: usize, const M: usize> NullSpaceSolve for FixedNullSpace<N, M> {
    fn dims(&self) -> (usize, usize) {
        (N, M)
    }
    fn factor(&mut self, mass: &[f64], phi_q: &[f64]) -> Option<f64> {
        // A size of 0 means "run-time" to the kernel: M = 0 takes that path with m = 0.
        kernel::factor::<N, M>(&mut self.parts(), N, M, mass, phi_q)
    }
    fn solve(&mut self, sol: &mut [f64]) {
        kernel::solve::<N, M>(&mut self.parts(), N, M, sol, true);
    }
    fn solve_accelerations(&mut self, sol: &mut [f64]) {
        kernel::solve::<N, M>(&mut self.parts(), N, M, sol, false);
    }
    fn clone_box(&self) -> Box<dyn NullSpaceSolve> {
        Box::new(self.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// The augmented matrix [M J^T; J 0].
    fn kkt(mass: &DMatrix<f64>, j: &DMatrix<f64>) -> DMatrix<f64> {
        let (n, m) = (mass.nrows(), j.nrows());
        let mut a = DMatrix::zeros(n + m, n + m);
        a.view_mut((0, 0), (n, n)).copy_from(mass);
        a.view_mut((n, 0), (m, n)).copy_from(j);
        a.view_mut((0, n), (n, m)).copy_from(&j.transpose());
        a
    }

    /// Against nalgebra's LU of the whole matrix, with a singular M (zero rows as the seed's)
    /// and a dense one, for every d = n - m from 0 to n.
    #[test]
    fn matches_the_whole_lu() {
        for n in 1..=7 {
            for m in 0..=n {
                for singular in [false, true] {
                    let mass = DMatrix::from_fn(n, n, |i, j| {
                        let zero = singular && (i == 1 || j == 1) && n > m;
                        if zero {
                            0.0
                        } else {
                            (if i == j { 3.0 } else { 0.0 }) + 0.3 / (1.0 + (i + j) as f64)
                        }
                    });
                    let j = DMatrix::from_fn(m, n, |r, c| {
                        (((r * 5 + c * 3 + n) % 7) as f64 - 3.0) * 0.25
                            + if r == c { 1.0 } else { 0.0 }
                    });
                    let a = kkt(&mass, &j);
                    let Some(inv) = a.clone().lu().try_inverse() else {
                        continue;
                    };
                    let rhs: Vec<f64> = (0..n + m).map(|i| 1.0 - 0.3 * i as f64).collect();
                    let want = &inv * DVector::from_column_slice(&rhs);
                    let mut ns = NullSpace::new(n, m);
                    let Some(kappa) = ns.factor(mass.as_slice(), j.as_slice()) else {
                        panic!("n {n} m {m} singular {singular}: not factored");
                    };
                    assert!((1.0..1e6).contains(&kappa), "kappa {kappa}");
                    let mut sol = rhs.clone();
                    ns.solve(&mut sol);
                    // q'' alone, as the integrator's stages ask: the same values, bit for bit.
                    let mut acc = rhs.clone();
                    ns.solve_accelerations(&mut acc);
                    assert_eq!(acc[..n], sol[..n], "n {n} m {m} singular {singular}");
                    let scale = want.amax().max(1.0);
                    for i in 0..n + m {
                        assert!(
                            (sol[i] - want[i]).abs() <= 1e-12 * scale,
                            "n {n} m {m} singular {singular} entry {i}: {} vs {}",
                            sol[i],
                            want[i]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn redundant_rows_and_undetermined_motion_are_refused() {
        let mass = DMatrix::identity(3, 3);
        let j = DMatrix::from_row_slice(2, 3, &[1.0, 2.0, 0.0, 2.0, 4.0, 0.0]);
        let factor = |n, m, mass: &DMatrix<f64>, j: &DMatrix<f64>| {
            NullSpace::new(n, m).factor(mass.as_slice(), j.as_slice())
        };
        assert!(factor(3, 2, &mass, &j).is_none());
        // M zero on the one free direction (the third coordinate).
        let mass = DMatrix::from_diagonal(&DVector::from_column_slice(&[1.0, 1.0, 0.0]));
        let j = DMatrix::from_row_slice(2, 3, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        assert!(factor(3, 2, &mass, &j).is_none());
        // More rows than coordinates.
        assert!(factor(1, 2, &DMatrix::identity(1, 1), &DMatrix::zeros(2, 1)).is_none());
    }

    /// The static-size kernel gives the run-time kernel's result to the bit.
    #[test]
    fn fixed_sizes_match_run_time_sizes() {
        let mass = DMatrix::from_fn(4, 4, |i, j| {
            if i == j && i != 1 {
                2.0 + i as f64
            } else {
                0.0
            }
        });
        let j = DMatrix::from_fn(3, 4, |r, c| ((r * 3 + c * 5) % 7) as f64 * 0.3 - 0.8);
        let mut a = NullSpace::new(4, 3);
        let mut b = FixedNullSpace::<4, 3>::default();
        assert_eq!(
            a.factor(mass.as_slice(), j.as_slice()),
            b.factor(mass.as_slice(), j.as_slice())
        );
        let (mut x, mut y) = ([1.0, -2.0, 0.5, 0.25, 3.0, -1.0, 0.1], [0.0; 7]);
        y.copy_from_slice(&x);
        a.solve(&mut x);
        b.solve(&mut y);
        assert_eq!(x, y);
    }

    /// What `Dynamics::solve` relies on to check its inputs only on failure: a NaN or an
    /// infinity in any entry of M (a symmetric pair), Phi_q or the right-hand side makes
    /// `factor` decline (`None`, or an indicator that is not a finite number) or leaves a
    /// non-finite value in the solution. Every entry of each input, for every d = n - m,
    /// singular M or not.
    #[test]
    fn a_non_finite_input_never_gives_a_finite_solution() {
        for n in 1..=5 {
            for m in 0..=n {
                let mass = DMatrix::from_fn(n, n, |i, j| {
                    (if i == j && (i != 0 || m == 0) {
                        2.0
                    } else {
                        0.0
                    }) + 0.1 / (1.0 + (i + j) as f64)
                });
                let j = DMatrix::from_fn(m, n, |r, c| {
                    (((r * 5 + c * 3 + n) % 7) as f64 - 3.0) * 0.25 + if r == c { 1.0 } else { 0.0 }
                });
                let rhs: Vec<f64> = (0..n + m).map(|i| 1.0 - 0.3 * i as f64).collect();
                let declines_or_not_finite =
                    |mass: &DMatrix<f64>, j: &DMatrix<f64>, rhs: &[f64]| {
                        let mut ns = NullSpace::new(n, m);
                        match ns.factor(mass.as_slice(), j.as_slice()) {
                            Some(kappa) if kappa.is_finite() => {
                                let mut sol = rhs.to_vec();
                                ns.solve(&mut sol);
                                sol.iter().any(|v| !v.is_finite())
                            }
                            _ => true,
                        }
                    };
                assert!(!declines_or_not_finite(&mass, &j, &rhs), "n {n} m {m}");
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    // M is symmetric (the derivation makes it so): a bad entry is a bad pair.
                    for (a, b) in (0..n).flat_map(|a| (0..=a).map(move |b| (a, b))) {
                        let mut mass = mass.clone();
                        mass[(a, b)] = bad;
                        mass[(b, a)] = bad;
                        assert!(
                            declines_or_not_finite(&mass, &j, &rhs),
                            "n {n} m {m} M[{a}, {b}] {bad}"
                        );
                    }
                    for k in 0..m * n {
                        let mut j = j.clone();
                        j.as_mut_slice()[k] = bad;
                        assert!(declines_or_not_finite(&mass, &j, &rhs), "Phi_q[{k}] {bad}");
                    }
                    for k in 0..n + m {
                        let mut rhs = rhs.clone();
                        rhs[k] = bad;
                        assert!(declines_or_not_finite(&mass, &j, &rhs), "rhs[{k}] {bad}");
                    }
                }
            }
        }
    }

    /// The static sizes (their small elimination runs on a local array with selects for the
    /// row swaps, the larger ones on the run-time code) give the run-time results bit for
    /// bit, NaN for NaN: indicator, q'' and lambda, for matrices that need row swaps, with a
    /// singular M, and with a NaN or an infinity in each entry of Phi_q.
    fn fixed_agrees<const N: usize, const M: usize>() {
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for shift in 0..7 {
            let mass = DMatrix::from_fn(N, N, |i, j| {
                (if i == j && (i != shift % N || M == 0) {
                    2.0 + i as f64
                } else {
                    0.0
                }) + 0.1 / (1.0 + (i + j) as f64)
            });
            let base = DMatrix::from_fn(M, N, |r, c| {
                (((r * 5 + c * 3 + shift) % 7) as f64 - 3.0) * 0.25
            });
            let mut cases = vec![base.clone()];
            for k in 0..M * N {
                for bad in [f64::NAN, f64::INFINITY] {
                    let mut j = base.clone();
                    j.as_mut_slice()[k] = bad;
                    cases.push(j);
                }
            }
            for j in cases {
                let mut a = NullSpace::new(N, M);
                let mut b = FixedNullSpace::<N, M>::default();
                let (ka, kb) = (
                    a.factor(mass.as_slice(), j.as_slice()),
                    b.factor(mass.as_slice(), j.as_slice()),
                );
                match (ka, kb) {
                    (None, None) => continue,
                    (Some(x), Some(y)) => assert!(same(x, y), "{N} {M}: kappa {x} vs {y}"),
                    _ => panic!("{N} {M} shift {shift}: {ka:?} vs {kb:?}"),
                }
                let rhs: Vec<f64> = (0..N + M).map(|i| 1.0 - 0.3 * i as f64).collect();
                let (mut x, mut y) = (rhs.clone(), rhs.clone());
                a.solve(&mut x);
                b.solve(&mut y);
                assert!(
                    x.iter().zip(&y).all(|(u, v)| same(*u, *v)),
                    "{N} {M}: {x:?} vs {y:?}"
                );
                let mut z = rhs.clone();
                b.solve_accelerations(&mut z);
                assert!(x[..N].iter().zip(&z).all(|(u, v)| same(*u, *v)), "{N} {M}");
            }
        }
    }

    #[test]
    fn static_sizes_give_the_run_time_results() {
        fixed_agrees::<1, 1>();
        fixed_agrees::<2, 1>();
        fixed_agrees::<3, 2>();
        fixed_agrees::<4, 3>();
        fixed_agrees::<4, 1>();
        fixed_agrees::<5, 3>();
        fixed_agrees::<6, 4>();
        fixed_agrees::<8, 2>();
        // Beyond the local elimination's bound.
        fixed_agrees::<7, 4>();
        fixed_agrees::<9, 3>();
    }
}
