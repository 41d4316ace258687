//! What a singular position looks like to the motions near it: a **crossing**, which every
//! nearby motion passes through, or an **apex**, which a nearby motion can miss.
//!
//! Near a singular position q_s, write the constraints to second order on the directions
//! they leave free: with the rank of Phi_q at regular points r, the rank drop d there, and
//! N the k = n - r + d right singular directions of Phi_q whose singular values are small
//! (those the regular rows leave free), the configurations near q_s are, to second order, the
//! x in N with
//!
//!   x^T (B^T H_j B) x = 0,  H_j = sum_i u_ji d^2 Phi_i / dq^2,  j = 1..d,
//!
//! u_j the left singular directions of the rows that lose rank, B a basis of N: a cone of
//! dimension k - d = n - r, the mobility. Phi_q keeps its rank drop along the common kernel of
//! the forms, the singular set, of dimension s = k - rank[B^T H_1 B; ...; B^T H_d B]. A motion
//! moves on a set of dimension n - r; it crosses the singular set when n - r - s <= 1 (a
//! four-bar flat: two branches crossing at a point of a curve; A02: 2^N branches, all lines
//! through the point), and generically misses it when n - r - s >= 2 (the five-bar lying flat:
//! n - r = 2, s = 0; the two assembly modes are the two nappes of a cone). A motion that
//! misses an apex by b turns around it within a time of about b / |q'|, onto another branch
//! than the straight continuation a motion through it takes; a step longer than that turn
//! cannot tell the two apart.
//!
//! The forms are taken by central differences of Phi_q along B (2 k evaluations of Phi_q)
//! at the passage's closest approach, once per recorded passage; mechanisms of mobility 1
//! need none (a crossing whatever the forms).

use nalgebra::{DMatrix, SymmetricEigen};

use crate::system::System;

/// The geometry of a singular position passed: whether a nearby motion must pass through
/// it or can miss it.
///
/// With r the rank of Phi_q at regular points, d the rows that lose rank there, B a basis
/// of the k = n - r + d directions the other rows leave free and u_j the weak rows'
/// directions, the configurations nearby are to second order the x with
/// x^T B^T H_j B x = 0, H_j = sum_i u_ji d^2 Phi_i / dq^2: a cone of dimension n - r (the
/// mobility). The rank drop persists on the singular set, of dimension
/// s = k - rank[B^T H_1 B; ...; B^T H_d B]. n - r - s <= 1 is a crossing, >= 2 an apex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "files", derive(serde::Serialize))]
#[cfg_attr(feature = "files", serde(rename_all = "lowercase"))]
pub enum PassageGeometry {
    /// Branches cross there along the motion (mobility minus the singular set's dimension at
    /// most 1): every nearby motion passes through it, and the run's straight continuation
    /// is the motion's.
    Crossing,
    /// An apex: the singular set is at least two dimensions smaller than the set the motion
    /// moves on (the five-bar lying flat), so a nearby motion can miss it and then turns
    /// around it onto another branch, within about (miss) / (speed). A step that went over
    /// it ([`crate::SingularPassage::stepped_over`]) continues straight on, the motion only
    /// of an exact hit (by symmetry, say); a miss shorter than that step is not resolved.
    Apex,
    /// Not classified: more than 256 coordinates with a mobility above 1 (the test costs 2 k
    /// evaluations of Phi_q and dense eigen decompositions of order n).
    Unclassified,
}

/// Above this many coordinates (with a mobility above 1) a passage is not classified
/// ([`PassageGeometry::Unclassified`]).
pub(crate) const MAX_CLASSIFIED: usize = 256;

/// Classifies the singular position passed at (t, q), q the closest approach; `rank` is the
/// rank of Phi_q at regular points, `drop` the rows that lose rank there, `w` the weakest row
/// independence at q (the distance to the singular position, relative).
pub(crate) fn classify(
    system: &dyn System,
    t: f64,
    q: &[f64],
    rank: usize,
    drop: usize,
    w: f64,
) -> PassageGeometry {
    let n = q.len();
    let mobility = n.saturating_sub(rank);
    if mobility < 2 || drop == 0 {
        return PassageGeometry::Crossing;
    }
    if n > MAX_CLASSIFIED {
        return PassageGeometry::Unclassified;
    }
    let m = system.info().m();
    let mut phi_q = DMatrix::zeros(m, n);
    let mut phi_t = vec![0.0; m];
    system.constraint_jacobian(t, q, &mut phi_q, &mut phi_t);
    // N: the k right singular directions of smallest singular value; the rows' weak
    // directions: the m - rank + drop left ones (the rows redundant at regular points add
    // forms that vanish identically when their dependence holds everywhere, and no rank).
    let k = (n + drop).saturating_sub(rank).min(n);
    let b = smallest_eigenvectors(phi_q.transpose() * &phi_q, k);
    let u = smallest_eigenvectors(&phi_q * phi_q.transpose(), (m + drop - rank).min(m));
    if b.iter().chain(&u).any(|x| !x.is_finite()) {
        return PassageGeometry::Unclassified;
    }
    let scale = q.iter().fold(1.0f64, |a, x| a.max(x.abs()));
    let delta = 1e-5 * scale;
    let mut stacked = DMatrix::zeros(u.ncols() * k, k);
    let (mut plus, mut minus) = (DMatrix::zeros(m, n), DMatrix::zeros(m, n));
    let mut qs = q.to_vec();
    for j in 0..k {
        for (i, x) in qs.iter_mut().enumerate() {
            *x = q[i] + delta * b[(i, j)];
        }
        system.constraint_jacobian(t, &qs, &mut plus, &mut phi_t);
        for (i, x) in qs.iter_mut().enumerate() {
            *x = q[i] - delta * b[(i, j)];
        }
        system.constraint_jacobian(t, &qs, &mut minus, &mut phi_t);
        // d(Phi_q)/d(b_j), then u_a^T of it along every b_l: (B^T H_a B)[l, j].
        let derivative = (&plus - &minus) / (2.0 * delta);
        let forms = u.transpose() * derivative * &b;
        for a in 0..u.ncols() {
            for l in 0..k {
                stacked[(a * k + l, j)] = forms[(a, l)];
            }
        }
    }
    if stacked.iter().any(|x| !x.is_finite()) {
        return PassageGeometry::Unclassified;
    }
    // The forms are taken at q, a distance of order w from q_s, and to about 1e-10 by the
    // differences: a singular value of the stack below max(sqrt(w), 1e-6) of the largest is
    // one that vanishes at q_s.
    let singular = stacked.singular_values();
    let largest = singular.iter().fold(0.0f64, |a, &s| a.max(s));
    let cut = largest * w.max(0.0).sqrt().max(1e-6);
    let form_rank = singular.iter().filter(|&&s| s > cut).count();
    if largest > 0.0 && form_rank >= drop + 2 {
        PassageGeometry::Apex
    } else {
        PassageGeometry::Crossing
    }
}

/// The `count` unit eigenvectors of the symmetric `a` with the smallest eigenvalues, as
/// columns.
fn smallest_eigenvectors(a: DMatrix<f64>, count: usize) -> DMatrix<f64> {
    let eigen = SymmetricEigen::new(a);
    let mut order: Vec<usize> = (0..eigen.eigenvalues.len()).collect();
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    let columns: Vec<_> = order
        .iter()
        .take(count)
        .map(|&i| eigen.eigenvectors.column(i).into_owned())
        .collect();
    if columns.is_empty() {
        DMatrix::zeros(eigen.eigenvectors.nrows(), 0)
    } else {
        DMatrix::from_columns(&columns)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Interpreted;
    use std::f64::consts::PI;

    /// A rhombus window of A02 in rocker and coupler angles (1 m bars, 1 kg), with a fourth
    /// coordinate x: free beside it (`ground = "1"`) or in the ground bar's length
    /// (`"1 + x^2"`).
    fn rhombus(ground: &str) -> Interpreted {
        let text = format!(
            "pub struct Rhombus;\nparameters {{ g = 9.81; }}\n\
             coordinates {{ th0 = 1.5707963267948966; ps1 = 0.0; th1 = 1.5707963267948966; x = 0.0; }}\n\
             independent {{ th0 = 1.5707963267948966; x = 0.0; }}\n\
             kinetic = der(th0)^2/6 + der(th1)^2/6 + der(th0)^2/2 \
             + cos(th0 - ps1)*der(th0)*der(ps1)/2 + der(ps1)^2/6 + der(x)^2/2;\n\
             potential = g*sin(th0)/2 + g*sin(th1)/2 + g*(sin(th0) + sin(ps1)/2);\n\
             constraints {{\n    cos(th0) + cos(ps1) - ({ground}) - cos(th1);\n    \
             sin(th0) + sin(ps1) - sin(th1);\n}}\n"
        );
        Interpreted::from_source(&text).unwrap()
    }

    /// The five-bar lying flat (both legs folded onto the x axis, the foot at the origin:
    /// th1 = pi, ph1 = -pi, th2 = 0, ph2 = pi) is an apex: mobility 2 and a singular set of
    /// one point (its two assembly modes are a cone's nappes), exactly there and 1e-4 rad
    /// away along th1, as at a closest approach.
    #[test]
    fn the_five_bar_lying_flat_is_an_apex() {
        let five_bar =
            Interpreted::from_source(include_str!("../../mechanisms/five_bar.mech")).unwrap();
        for off in [0.0, 1e-4] {
            let q = [PI + off, -PI, 0.0, PI];
            let g = classify(&five_bar, 0.0, &q, 2, 1, off);
            assert_eq!(g, PassageGeometry::Apex, "{off}");
        }
    }

    /// A rhombus lying flat (th0 = ps1 = th1 = 0) is a crossing of its parallelogram and
    /// folded branches. With a free coordinate beside it the mobility is 2, but the rank
    /// drop holds along x (the singular set is a line), so every motion crosses it: a
    /// crossing. With a ground bar of length 1 + x^2 the window is a rhombus only at x = 0
    /// (a four-bar folds only where two of its lengths sum to the other two) and the
    /// singular set is a point of the two-dimensional configuration set: an apex.
    #[test]
    fn a_crossing_with_a_free_coordinate_beside_it_stays_a_crossing() {
        let q = [0.0, 0.0, 0.0, 0.0];
        let free = classify(&rhombus("1"), 0.0, &q, 2, 1, 0.0);
        assert_eq!(free, PassageGeometry::Crossing);
        let sliding = classify(&rhombus("1 + x^2"), 0.0, &q, 2, 1, 0.0);
        assert_eq!(sliding, PassageGeometry::Apex);
    }

    /// Mobility 1 is a crossing without any form evaluated; past [`MAX_CLASSIFIED`]
    /// coordinates a mobility above 1 is left unclassified.
    #[test]
    fn mobility_one_is_a_crossing_and_large_systems_are_not_classified() {
        let q = [0.0; 4];
        assert_eq!(
            classify(&rhombus("1"), 0.0, &q, 3, 1, 0.0),
            PassageGeometry::Crossing
        );
        let big = vec![0.0; MAX_CLASSIFIED + 1];
        assert_eq!(
            classify(&rhombus("1"), 0.0, &big, 2, 1, 0.0),
            PassageGeometry::Unclassified
        );
    }
}
