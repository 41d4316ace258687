//! The parts of the augmented (KKT) solve of a mechanism with constraint rows that follow
//! M's pattern, as straight-line expressions:
//!
//! ```text
//! [ M      Phi_q^T ] [ q''    ]   [ Q     ]       Q = -b = tau - C q' - g
//! [ Phi_q  0       ] [ lambda ] = [ gamma ]
//! ```
//!
//! With M = L^T D L factored over its pattern ([`super::forward_dynamics::Factor`], the
//! factorisation the forward dynamics of a tree uses) and W = L^-T Phi_q^T (each column
//! fills only the chains of its row's coordinates: a mimic row's two joints and their
//! ancestors):
//!
//! ```text
//! u = M^-1 Q,   Y = M^-1 Phi_q^T = L^-1 D^-1 W,   S = Phi_q M^-1 Phi_q^T = W^T D^-1 W,
//! c = Phi_q u - gamma
//! ```
//!
//! and the run time finishes with the m x m Schur complement, S lambda = c,
//! q'' = u - Y lambda (`mechanism::fixed::kkt_tree_solve`, which drops S's redundant rows
//! as the dense solve does). The pivots D are an output: the caller takes this route only
//! where every pivot is positive beyond round-off (M positive definite), and the dense
//! augmented-Lagrangian solve, which also handles an M singular off the constraint
//! manifold, otherwise.

use super::forward_dynamics::Factor;
use crate::algebra::expr::{Arena, Id};
use crate::algebra::matrix::Matrix;
use crate::error::Result;

/// u (n x 1), Y (n x m), S (m x m), c (m x 1) and the pivots D (n x 1, elimination order).
pub(crate) struct KktParts {
    pub(crate) u: Matrix,
    pub(crate) y: Matrix,
    pub(crate) s: Matrix,
    pub(crate) c: Matrix,
    pub(crate) pivots: Matrix,
}

/// The parts of the module docs for M = `mass`, b = `bias`, Phi_q = `phi_q`, gamma =
/// `gamma`, with the coordinates eliminated in `order` (parents before children).
pub(crate) fn kkt_parts(
    a: &mut Arena,
    mass: &Matrix,
    bias: &Matrix,
    phi_q: &Matrix,
    gamma: &Matrix,
    order: &[usize],
) -> Result<KktParts> {
    let (n, m) = (order.len(), phi_q.rows());
    let f = Factor::new(a, mass, order)?;
    let q: Vec<Id> = (0..n).map(|c| a.neg(bias.get(c, 0))).collect();
    let wq = f.upward(a, &q);
    let u = f.downward(a, &wq);
    let w: Vec<Vec<Id>> = (0..m)
        .map(|i| {
            let row: Vec<Id> = (0..n).map(|c| phi_q.get(i, c)).collect();
            f.upward(a, &row)
        })
        .collect();
    let mut y = Matrix::zeros(a, n, m);
    for (i, wi) in w.iter().enumerate() {
        for (c, x) in f.downward(a, wi).into_iter().enumerate() {
            y.set(c, i, x);
        }
    }
    let inverse = f.inverse_pivots().to_vec();
    let mut s = Matrix::zeros(a, m, m);
    for i in 0..m {
        for j in 0..=i {
            let mut terms = Vec::new();
            for k in 0..n {
                if !a.is_zero(w[i][k]) && !a.is_zero(w[j][k]) {
                    terms.push(a.mul(&[w[i][k], w[j][k], inverse[k]]));
                }
            }
            let sum = a.add(&terms);
            let sum = a.named(sum);
            s.set(i, j, sum);
            s.set(j, i, sum);
        }
    }
    let c: Vec<Id> = (0..m)
        .map(|i| {
            let nonzero: Vec<usize> = (0..n).filter(|&k| !a.is_zero(phi_q.get(i, k))).collect();
            let mut terms: Vec<Id> = nonzero
                .into_iter()
                .map(|k| a.mul2(phi_q.get(i, k), u[k]))
                .collect();
            terms.push(a.neg(gamma.get(i, 0)));
            a.add(&terms)
        })
        .collect();
    Ok(KktParts {
        u: Matrix::column(u),
        y,
        s,
        c: Matrix::column(c),
        pivots: f.pivots(),
    })
}
