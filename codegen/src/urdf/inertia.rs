//! Whether a URDF inertia can belong to a rigid body.
//!
//! The rotational inertia about the centre of mass is a symmetric matrix; it is physical
//! when its principal moments (eigenvalues) I1, I2, I3 are not negative and each is at most
//! the sum of the other two (the triangle inequalities: I1 + I2 >= I3 because
//! I3 = integral of (x^2 + y^2) dm <= integral of (x^2 + y^2 + 2 z^2) dm = I1 + I2 in the
//! principal axes). URDF files print their inertias to a few digits, so both tests allow
//! a slack of [`INERTIA_TOLERANCE`] times the trace.

/// Slack of the tests, relative to the trace I1 + I2 + I3 (a thin rod's I1 = 0 and
/// I2 = I3 printed to 7 digits stay accepted).
pub(crate) const INERTIA_TOLERANCE: f64 = 1e-6;

/// Cyclic Jacobi sweeps at most (3x3 converges in well under 10).
const MAX_SWEEPS: usize = 50;

/// Why an inertia is not physical, in a sentence (`None` when it is physical).
///
/// `inertia` is `ixx, ixy, ixz, iyy, iyz, izz`.
pub(crate) fn inertia_fault(inertia: [f64; 6]) -> Option<String> {
    let moments = principal_moments(inertia);
    let [a, b, c] = moments;
    let tolerance = INERTIA_TOLERANCE * (a.abs() + b.abs() + c.abs());
    if a < -tolerance {
        return Some(format!(
            "a negative principal moment ({a:e}; principal moments {a:e}, {b:e}, {c:e})"
        ));
    }
    if a + b < c - tolerance {
        return Some(format!(
            "principal moments {a:e}, {b:e}, {c:e} break the triangle inequality \
             {a:e} + {b:e} >= {c:e} (no rigid body has them)"
        ));
    }
    None
}

/// The principal moments of the symmetric matrix `inertia` (`ixx, ixy, ixz, iyy, iyz,
/// izz`), ascending: cyclic Jacobi rotations (Golub and Van Loan, Matrix Computations,
/// 4th ed., section 8.5.2) on the matrix scaled to its largest entry, so no square
/// overflows.
pub(crate) fn principal_moments(inertia: [f64; 6]) -> [f64; 3] {
    let scale = inertia.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return [0.0; 3];
    }
    let [xx, xy, xz, yy, yz, zz] = inertia.map(|v| v / scale);
    let mut a = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
    for _ in 0..MAX_SWEEPS {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if off < 1e-36 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            rotate(&mut a, p, q);
        }
    }
    let mut moments = [a[0][0] * scale, a[1][1] * scale, a[2][2] * scale];
    moments.sort_by(f64::total_cmp);
    moments
}

/// One Jacobi rotation in the plane (p, q): A <- J^T A J with the (p, q) entry zeroed.
fn rotate(a: &mut [[f64; 3]; 3], p: usize, q: usize) {
    if a[p][q] == 0.0 {
        return;
    }
    let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
    let t = if theta.abs() > 1e150 {
        0.5 / theta
    } else {
        theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
    };
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    for row in a.iter_mut() {
        let (kp, kq) = (row[p], row[q]);
        row[p] = c * kp - s * kq;
        row[q] = s * kp + c * kq;
    }
    let (row_p, row_q) = (a[p], a[q]);
    a[p] = std::array::from_fn(|k| c * row_p[k] - s * row_q[k]);
    a[q] = std::array::from_fn(|k| s * row_p[k] + c * row_q[k]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// R diag(d) R^T for a rotation R about (1, 2, 3) / |.| by 0.7 rad.
    fn rotated(d: [f64; 3]) -> [f64; 6] {
        let n = (14.0_f64).sqrt();
        let (x, y, z) = (1.0 / n, 2.0 / n, 3.0 / n);
        let (s, c) = 0.7_f64.sin_cos();
        let r = [
            [
                c + x * x * (1.0 - c),
                x * y * (1.0 - c) - z * s,
                x * z * (1.0 - c) + y * s,
            ],
            [
                y * x * (1.0 - c) + z * s,
                c + y * y * (1.0 - c),
                y * z * (1.0 - c) - x * s,
            ],
            [
                z * x * (1.0 - c) - y * s,
                z * y * (1.0 - c) + x * s,
                c + z * z * (1.0 - c),
            ],
        ];
        let m = |i: usize, j: usize| (0..3).map(|k| r[i][k] * d[k] * r[j][k]).sum::<f64>();
        [m(0, 0), m(0, 1), m(0, 2), m(1, 1), m(1, 2), m(2, 2)]
    }

    #[test]
    fn principal_moments_of_a_rotated_diagonal() {
        let moments = principal_moments(rotated([3.0, 1.0, 2.5]));
        for (got, want) in moments.iter().zip([1.0, 2.5, 3.0]) {
            assert!((got - want).abs() < 1e-14, "{moments:?}");
        }
    }

    #[test]
    fn physical_and_unphysical_inertias() {
        assert_eq!(inertia_fault([0.0; 6]), None, "a point mass");
        assert_eq!(inertia_fault(rotated([0.0, 1.0, 1.0])), None, "a thin rod");
        assert_eq!(
            inertia_fault([1.0, 0.0, 0.0, 1.0, 0.0, 2.000001]),
            None,
            "rounded"
        );
        let triangle = inertia_fault(rotated([1.0, 1.0, 2.5])).expect("refused");
        assert!(triangle.contains("triangle inequality"), "{triangle}");
        let negative = inertia_fault([1.0, 2.0, 0.0, 1.0, 0.0, 1.0]).expect("refused");
        assert!(negative.contains("negative principal moment"), "{negative}");
    }
}
