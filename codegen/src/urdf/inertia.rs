//! Whether a URDF inertia can belong to a rigid body, and the repair of one that almost
//! can.
//!
//! The rotational inertia about the centre of mass is a symmetric matrix; it is physical
//! when its principal moments (eigenvalues) I1 <= I2 <= I3 are not negative and each is at
//! most the sum of the other two (the triangle inequalities: I1 + I2 >= I3 because
//! I3 = integral of (x^2 + y^2) dm <= integral of (x^2 + y^2 + 2 z^2) dm = I1 + I2 in the
//! principal axes). URDF files print their inertias to a few digits, so the tests allow a
//! slack of [`INERTIA_TOLERANCE`] times the sum of the moments' magnitudes.
//!
//! Published robot files also carry inertias that no body has but whose intent is clear:
//! round-off garbage such as a lone `ixz = 2.4e-35` (iCub), placeholder links with every
//! entry 1e-6 (ANYmal, HyQ, Unitree), or a box whose longest axis got the largest moment
//! without the others growing with it (PR2's `diag(1e-3, 1e-3, 1e-2)`). [`check_inertia`]
//! sorts an inertia into physical (kept bit for bit), negligible (a point mass: replaced by
//! zero), repairable (the two smaller moments raised until I1 + I2 = I3, in the same
//! principal axes; MuJoCo's compiler option `balanceinertia` imposes the same rule) or
//! refused (a negative moment beyond the slack, which can make the mass matrix indefinite).

/// Slack of the tests, relative to the sum of the principal moments' magnitudes
/// |I1| + |I2| + |I3| (the trace for a positive semi-definite inertia): a thin rod's I1 = 0
/// and I2 = I3 printed to 7 digits stay accepted.
pub(crate) const INERTIA_TOLERANCE: f64 = 1e-6;

/// Radius of gyration, in metres, below which a link's rotational inertia is negligible:
/// a principal moment |Ik| <= NEGLIGIBLE_RADIUS^2 * mass is that of the link's whole mass
/// within a micrometre of its centre of mass. No rigid body of a mechanism is that small
/// (a ball 1 mm across already has r = sqrt(2/5) * 0.5 mm = 0.3 mm), and the moment
/// m (1e-6 m)^2 is 1e-8 of what the same mass adds to the mass matrix at a lever of only
/// 1 cm, m (1e-2 m)^2: the link is a point mass, and moments of this size are round-off
/// (iCub's 2.4e-35 kg m^2 on a 1.3 kg head). It is also the absolute part of the slack of
/// the negative-moment and triangle tests, so that a link whose moments are all near zero
/// is judged against its mass, not only against its own moments.
pub(crate) const NEGLIGIBLE_RADIUS: f64 = 1e-6;

/// Slack of the declaration's own test of the principal moments, relative to the largest
/// entry (`mechanics::body_checks`, `MOMENTS`): an inertia within it is written as given.
const DECLARATION_SLACK: f64 = 1e-9;

/// Cyclic Jacobi sweeps at most (3x3 converges in well under 10).
const MAX_SWEEPS: usize = 50;

/// What [`check_inertia`] found of an inertia that a rigid body can have, possibly after a
/// repair. Moments are principal moments, ascending.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum InertiaCheck {
    /// Physical within the slack (or exactly zero): keep the inertia as it is, bit for bit.
    Physical,
    /// Every principal moment's magnitude is at most NEGLIGIBLE_RADIUS^2 * mass plus the
    /// slack: the link is a point mass, its inertia is to be replaced by zero.
    Negligible {
        /// The principal moments of the inertia as given.
        moments: [f64; 3],
    },
    /// The moments broke I1 >= 0 or I1 + I2 >= I3 beyond the declaration's slack: the two
    /// smaller ones, each first raised to at least 0, were raised by d = (I3 - I1 - I2) / 2
    /// (0 when the triangle held), so I1' + I2' = I3 up to rounding (a few eps * I3, far
    /// within [`DECLARATION_SLACK`]), and the matrix was rebuilt in the same principal axes
    /// R as R diag(I1', I2', I3) R^T (exactly the entries for a diagonal inertia).
    Balanced {
        /// The principal moments of the inertia as given.
        moments: [f64; 3],
        /// The principal moments after the repair, I1' = max(I1, 0) + d,
        /// I2' = max(I2, 0) + d, I3.
        balanced: [f64; 3],
        /// The repaired inertia, `ixx, ixy, ixz, iyy, iyz, izz`.
        inertia: [f64; 6],
    },
}

/// Sorts `inertia` (`ixx, ixy, ixz, iyy, iyz, izz`, about the centre of mass) of a link of
/// mass `mass` (not negative; a negative one counts as 0) into an [`InertiaCheck`], or
/// refuses it, naming the negative moment.
///
/// With the principal moments I1 <= I2 <= I3 and the slack
/// s = INERTIA_TOLERANCE * (|I1| + |I2| + |I3|) + NEGLIGIBLE_RADIUS^2 * mass:
/// 1. all entries 0: [`InertiaCheck::Physical`] (a point mass already);
/// 2. |Ik| <= s for every k: [`InertiaCheck::Negligible`];
/// 3. I1 < -s: `Err` (a negative moment can make the mass matrix indefinite), unless it
///    is round-off on the robot's scale (below);
/// 4. within [`DECLARATION_SLACK`] of the largest entry of both I1 >= 0 and I1 + I2 >= I3
///    (what the declaration's own check allows): [`InertiaCheck::Physical`], kept as
///    written;
/// 5. otherwise each Ik below 0 (by at most s) is raised to 0, and if then I1 + I2 < I3,
///    [`InertiaCheck::Balanced`] with d = (I3 - I1 - I2) / 2 added to I1 and I2,
///    the principal axes kept. Of the repairs that lower no moment (no direction of the
///    body loses inertia) and keep I3, each raises I1 + I2 and the trace by at least
///    I3 - I1 - I2 and this one by exactly that; of those, the equal split is nearest the
///    file's matrix (raises d1 + d2 = 2 d: d1^2 + d2^2 >= 2 d^2, so |A' - A|_F >= sqrt(2) d)
///    and keeps the order I1' <= I2' <= I3;
///    and [`InertiaCheck::Balanced`] with d = 0 (the matrix rebuilt with the raised moments)
///    when only a moment within the slack below 0 was wrong.
///
/// `robot_scale` is the largest sum of principal moments among the robot's links (0 for a
/// link judged alone): a negative moment within INERTIA_TOLERANCE *
/// `robot_scale`, and no larger than the link's own largest moment I3 > 0, is treated as
/// round-off too (raised to 0, then balanced), not refused. Such a moment is
/// below any digit of the robot's mass matrix, whose entries are sums of the links'
/// moments (TIAGo's 1e-6 kg antenna placeholders, moments -3.5e-8, 3.5e-8, 9.1e-8 kg m^2,
/// bolted to a base of about 1 kg m^2); and a link that could still turn M indefinite is
/// caught where M is checked (`mechanics::kinetic_form`).
pub(crate) fn check_inertia(
    inertia: [f64; 6],
    mass: f64,
    robot_scale: f64,
) -> Result<InertiaCheck, String> {
    if inertia.iter().all(|&v| v == 0.0) {
        return Ok(InertiaCheck::Physical);
    }
    let (moments, axes) = principal_axes(inertia);
    let [a, b, c] = moments;
    let slack = INERTIA_TOLERANCE * (a.abs() + b.abs() + c.abs())
        + NEGLIGIBLE_RADIUS * NEGLIGIBLE_RADIUS * mass.max(0.0);
    if moments.iter().all(|m| m.abs() <= slack) {
        return Ok(InertiaCheck::Negligible { moments });
    }
    // Round-off on the robot's scale only where the link's own largest moment is positive
    // and outweighs the negative one: all three negative, or a negative moment larger than
    // the link's own (a sign error, not round-off), is refused whatever the robot.
    let robot_round_off = c > slack && -a <= c && -a <= INERTIA_TOLERANCE * robot_scale;
    if a < -slack && !robot_round_off {
        return Err(negative_moment(moments));
    }
    // The declaration the inertia is written into tests the same two conditions with a
    // slack of DECLARATION_SLACK of the largest entry (`mechanics::body_checks`): what
    // passes that is kept as written; what passes only this module's wider slack is
    // repaired as well (by at most that slack), so every imported inertia is accepted
    // where the declaration is read.
    let largest = inertia.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let strict = DECLARATION_SLACK * largest;
    if a >= -strict && a + b >= c - strict {
        return Ok(InertiaCheck::Physical);
    }
    // Here c > s >= 0 (not all moments are within the slack, and a negative I3 was refused
    // above), so only I1 and I2 can be raised to 0.
    let [a0, b0] = [a.max(0.0), b.max(0.0)];
    let d = if a0 + b0 < c {
        (c - a0 - b0) / 2.0
    } else {
        0.0
    };
    let balanced = [a0 + d, b0 + d, c];
    Ok(InertiaCheck::Balanced {
        moments,
        balanced,
        inertia: rebuild(&axes, balanced),
    })
}

/// The refusal of the ascending principal moments `moments`, whose first is negative.
fn negative_moment([a, b, c]: [f64; 3]) -> String {
    format!("a negative principal moment ({a:e}; principal moments {a:e}, {b:e}, {c:e})")
}

/// The principal moments of the symmetric matrix A = `inertia` (`ixx, ixy, ixz, iyy, iyz,
/// izz`), ascending, and the principal axes: the rotation R whose column r_k is the unit
/// axis of moment Ik, so A = R diag(I1, I2, I3) R^T and A r_k = Ik r_k. Cyclic Jacobi
/// rotations (Golub and Van Loan, Matrix Computations, 4th ed., section 8.5.2) on the
/// matrix scaled to its largest entry, so no square overflows: A_(n+1) = J^T A_n J until
/// the off-diagonal part vanishes, and R = J_1 J_2 ... (columns then sorted with the
/// moments). R is orthogonal to rounding, and the identity for the zero matrix. The moments
/// are those the Jacobi iteration gives without R, bit for bit (R only records it).
pub(crate) fn principal_axes(inertia: [f64; 6]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut r = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale = inertia.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return ([0.0; 3], r);
    }
    let [xx, xy, xz, yy, yz, zz] = inertia.map(|v| v / scale);
    let mut a = [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]];
    for _ in 0..MAX_SWEEPS {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if off < 1e-36 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if let Some((c, s)) = rotate(&mut a, p, q) {
                // R <- R J: the same column operation as A J.
                for row in r.iter_mut() {
                    let (kp, kq) = (row[p], row[q]);
                    row[p] = c * kp - s * kq;
                    row[q] = s * kp + c * kq;
                }
            }
        }
    }
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let moments = order.map(|k| a[k][k] * scale);
    let axes = r.map(|row| order.map(|k| row[k]));
    (moments, axes)
}

/// One Jacobi rotation in the plane (p, q): A <- J^T A J with the (p, q) entry zeroed,
/// where J is the identity but for J_pp = J_qq = c, J_pq = s, J_qp = -s. Returns (c, s),
/// or `None` (no rotation) when the entry is already 0.
fn rotate(a: &mut [[f64; 3]; 3], p: usize, q: usize) -> Option<(f64, f64)> {
    if a[p][q] == 0.0 {
        return None;
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
    Some((c, s))
}

/// R diag(`moments`) R^T for the axes R = `axes` (column k the axis of moment k), as
/// `ixx, ixy, ixz, iyy, iyz, izz`: entry (i, j) = sum over k of R_ik Ik R_jk.
fn rebuild(axes: &[[f64; 3]; 3], moments: [f64; 3]) -> [f64; 6] {
    let m =
        |i: usize, j: usize| -> f64 { (0..3).map(|k| axes[i][k] * moments[k] * axes[j][k]).sum() };
    [m(0, 0), m(0, 1), m(0, 2), m(1, 1), m(1, 2), m(2, 2)]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`check_inertia`] for a link judged alone (no robot around it).
    fn alone(inertia: [f64; 6], mass: f64) -> Result<InertiaCheck, String> {
        check_inertia(inertia, mass, 0.0)
    }

    /// The principal moments of the symmetric matrix `inertia` (`ixx, ixy, ixz, iyy, iyz,
    /// izz`), ascending (those of [`principal_axes`]).
    fn principal_moments(inertia: [f64; 6]) -> [f64; 3] {
        principal_axes(inertia).0
    }

    /// The rotation by `angle` about the axis along `axis` (not necessarily a unit vector):
    /// R = c 1 + (1 - c) n n^T + s [n]x with n = axis / |axis| (Rodrigues' formula).
    fn axis_angle(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
        let norm = axis.iter().map(|v| v * v).sum::<f64>().sqrt();
        let [x, y, z] = axis.map(|v| v / norm);
        let (s, c) = angle.sin_cos();
        [
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
        ]
    }

    /// The rotation R about the axis (1, 2, 3) by 0.7 rad.
    fn rotation() -> [[f64; 3]; 3] {
        axis_angle([1.0, 2.0, 3.0], 0.7)
    }

    /// R diag(d) R^T for [`rotation`] R.
    fn rotated(d: [f64; 3]) -> [f64; 6] {
        rebuild(&rotation(), d)
    }

    /// The symmetric matrix of `ixx, ixy, ixz, iyy, iyz, izz` times the vector `v`.
    fn times(inertia: [f64; 6], v: [f64; 3]) -> [f64; 3] {
        let [xx, xy, xz, yy, yz, zz] = inertia;
        [
            xx * v[0] + xy * v[1] + xz * v[2],
            xy * v[0] + yy * v[1] + yz * v[2],
            xz * v[0] + yz * v[1] + zz * v[2],
        ]
    }

    /// Whether `got` and `want` agree entry by entry to `relative` times the largest
    /// magnitude in `want`.
    fn close(got: &[f64], want: &[f64], relative: f64) -> bool {
        let scale = want.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        got.len() == want.len()
            && got
                .iter()
                .zip(want)
                .all(|(g, w)| (g - w).abs() <= relative * scale)
    }

    /// The [`InertiaCheck::Balanced`] result of `inertia` and `mass`, or a panic.
    fn balanced(inertia: [f64; 6], mass: f64) -> ([f64; 3], [f64; 3], [f64; 6]) {
        match alone(inertia, mass) {
            Ok(InertiaCheck::Balanced {
                moments,
                balanced,
                inertia,
            }) => (moments, balanced, inertia),
            other => panic!("expected Balanced, got {other:?}"),
        }
    }

    #[test]
    fn principal_moments_of_a_rotated_diagonal() {
        let moments = principal_moments(rotated([3.0, 1.0, 2.5]));
        for (got, want) in moments.iter().zip([1.0, 2.5, 3.0]) {
            assert!((got - want).abs() < 1e-14, "{moments:?}");
        }
    }

    #[test]
    fn principal_axes_are_the_rotation_columns() {
        // Columns of R in the order of their moments 1, 2.5, 3 (given as 3, 1, 2.5).
        let inertia = rotated([3.0, 1.0, 2.5]);
        let (moments, axes) = principal_axes(inertia);
        let r = rotation();
        for (k, column) in [1, 2, 0].into_iter().enumerate() {
            let axis = axes.map(|row| row[k]);
            let want = r.map(|row| row[column]);
            // An axis is defined up to its sign.
            let sign = if axis.iter().zip(&want).map(|(a, w)| a * w).sum::<f64>() < 0.0 {
                -1.0
            } else {
                1.0
            };
            assert!(close(&axis.map(|v| sign * v), &want, 1e-14), "{axes:?}");
            assert!(
                close(&times(inertia, axis), &axis.map(|v| moments[k] * v), 1e-14),
                "A v = I v for moment {k}"
            );
        }
        // The moments are principal_moments' own, bit for bit.
        assert_eq!(moments, principal_moments(inertia));
        assert_eq!(
            principal_axes([0.0; 6]).1,
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        );
    }

    #[test]
    fn icub_round_off_is_negligible() {
        // icub.urdf's `head` (1.33687 kg): every entry 0 but ixz = 2.40741e-35.
        let icub = [0.0, 0.0, 2.40741e-35, 0.0, 0.0, 0.0];
        for mass in [1.33687, 0.1] {
            let Ok(InertiaCheck::Negligible { moments }) = alone(icub, mass) else {
                panic!("{:?}", alone(icub, mass));
            };
            assert!(
                close(&moments, &[-2.40741e-35, 0.0, 2.40741e-35], 1e-12),
                "{moments:?}"
            );
        }
        // Without a mass the moments are judged against themselves alone, and the negative
        // one is refused: it is the mass term that makes this round-off.
        assert!(alone(icub, 0.0).is_err());
    }

    #[test]
    fn negligible_is_scaled_by_the_mass() {
        // NEGLIGIBLE_RADIUS^2 * 1 kg = 1e-12 kg m^2: a 1 kg ball with moments half of it
        // is a point mass, one with twice it (radius of gyration 1.4 micrometres) keeps its
        // inertia; the same moments on 1000 kg (0.045 micrometres) are negligible.
        let ball = |i: f64| [i, 0.0, 0.0, i, 0.0, i];
        assert!(matches!(
            alone(ball(0.5e-12), 1.0),
            Ok(InertiaCheck::Negligible { .. })
        ));
        assert_eq!(alone(ball(2e-12), 1.0), Ok(InertiaCheck::Physical));
        assert!(matches!(
            alone(ball(2e-12), 1e3),
            Ok(InertiaCheck::Negligible { .. })
        ));
        // A massless link's nonzero inertia is never negligible (the slack is then only
        // relative, a millionth of the moments), and the zero inertia is a point mass
        // already: nothing to replace.
        assert_eq!(alone(ball(1e-30), 0.0), Ok(InertiaCheck::Physical));
        assert_eq!(alone([0.0; 6], 0.0), Ok(InertiaCheck::Physical));
        assert_eq!(alone([0.0; 6], 2.0), Ok(InertiaCheck::Physical));
    }

    #[test]
    fn dummy_base_link_is_balanced() {
        // anymal, hyq, go1, b1 `base`: 1e-6 kg, every entry 1e-6 kg m^2, the matrix
        // 1e-6 * (1 1 1)(1 1 1)^T with moments 0, 0, 3e-6 (axis (1, 1, 1) / sqrt 3).
        let (moments, balanced, inertia) = balanced([1e-6; 6], 1e-6);
        assert!(close(&moments, &[0.0, 0.0, 3e-6], 1e-14), "{moments:?}");
        assert!(
            close(&balanced, &[1.5e-6, 1.5e-6, 3e-6], 1e-14),
            "{balanced:?}"
        );
        // 1.5e-6 I + 1.5e-6 n n^T with n = (1, 1, 1) / sqrt 3: diagonal 1.5e-6 + 0.5e-6,
        // off-diagonal 0.5e-6 (whatever axes Jacobi picks in the double moment 0).
        let want = [2e-6, 0.5e-6, 0.5e-6, 2e-6, 0.5e-6, 2e-6];
        assert!(close(&inertia, &want, 1e-14), "{inertia:?}");
        let n = [1.0 / 3.0_f64.sqrt(); 3];
        assert!(close(&times(inertia, n), &n.map(|v| 3e-6 * v), 1e-14));
    }

    #[test]
    fn pr2_sensor_mount_is_balanced() {
        // pr2.urdf's sensor_mount_link: 0.05 kg, diag(1e-3, 1e-3, 1e-2), positive definite
        // but 1e-3 + 1e-3 < 1e-2. d = (1e-2 - 2e-3) / 2 = 4e-3.
        let pr2 = [1e-3, 0.0, 0.0, 1e-3, 0.0, 1e-2];
        let (moments, balanced, inertia) = balanced(pr2, 0.05);
        assert_eq!(moments, [1e-3, 1e-3, 1e-2]);
        assert!(close(&balanced, &[5e-3, 5e-3, 1e-2], 1e-14), "{balanced:?}");
        // Diagonal in, diagonal out: the axes are exactly the coordinate axes.
        assert!(
            close(&inertia, &[5e-3, 0.0, 0.0, 5e-3, 0.0, 1e-2], 1e-14),
            "{inertia:?}"
        );
        assert_eq!([inertia[1], inertia[2], inertia[4]], [0.0; 3]);
        assert_eq!(inertia[5], 1e-2, "I3 is kept");
    }

    #[test]
    fn a_rotated_repair_keeps_the_principal_axes() {
        // R diag(1, 2, 5) R^T: 1 + 2 < 5, d = 1, so R diag(2, 3, 5) R^T.
        let (moments, balanced, inertia) = balanced(rotated([1.0, 2.0, 5.0]), 3.0);
        assert!(close(&moments, &[1.0, 2.0, 5.0], 1e-14), "{moments:?}");
        assert!(close(&balanced, &[2.0, 3.0, 5.0], 1e-14), "{balanced:?}");
        assert!(
            close(&inertia, &rotated([2.0, 3.0, 5.0]), 1e-12),
            "{inertia:?}"
        );
        // Each column of R is still an axis, with its balanced moment.
        let r = rotation();
        for (k, moment) in balanced.into_iter().enumerate() {
            let axis = r.map(|row| row[k]);
            assert!(close(
                &times(inertia, axis),
                &axis.map(|v| moment * v),
                1e-14
            ));
        }
    }

    #[test]
    fn a_slightly_negative_moment_is_raised_to_zero() {
        // -1e-9 is within the slack 1e-6 * 1.3: raised to 0 before the repair, so
        // d = (1 - 0.3) / 2 = 0.35, not (1 + 1e-9 - 0.3) / 2.
        let (moments, balanced, inertia) = balanced([-1e-9, 0.0, 0.0, 0.3, 0.0, 1.0], 1.0);
        assert_eq!(moments, [-1e-9, 0.3, 1.0]);
        assert!(close(&balanced, &[0.35, 0.65, 1.0], 1e-14), "{balanced:?}");
        assert!(
            close(&inertia, &[0.35, 0.0, 0.0, 0.65, 0.0, 1.0], 1e-14),
            "{inertia:?}"
        );
        // With the triangle inequality holding, it stays as written (the file's rounding).
        assert_eq!(
            alone([-1e-9, 0.0, 0.0, 1.0, 0.0, 1.0], 1.0),
            Ok(InertiaCheck::Physical)
        );
    }

    #[test]
    fn physical_inertias_are_kept() {
        // A rod of 2 kg and 0.5 m along x: diag(0, 1, 1) m l^2 / 12.
        let rod = 2.0 * 0.5 * 0.5 / 12.0;
        assert_eq!(
            alone([0.0, 0.0, 0.0, rod, 0.0, rod], 2.0),
            Ok(InertiaCheck::Physical)
        );
        // The same rod turned (its computed I1 is a rounding error, of either sign).
        assert_eq!(
            alone(rotated([0.0, rod, rod]), 2.0),
            Ok(InertiaCheck::Physical)
        );
        // A turned 3 kg box of 0.1 x 0.2 x 0.4 m: m (b^2 + c^2) / 12 and so on.
        let (m, a, b, c) = (3.0, 0.1_f64, 0.2_f64, 0.4_f64);
        let box_ = rotated([
            m * (b * b + c * c) / 12.0,
            m * (a * a + c * c) / 12.0,
            m * (a * a + b * b) / 12.0,
        ]);
        assert_eq!(alone(box_, m), Ok(InertiaCheck::Physical));
        // A triangle inequality broken within the declaration's slack (1e-9 of the largest
        // entry) is kept; broken within this module's (1e-6 of the trace) but beyond the
        // declaration's, it is balanced, by half the excess each.
        assert_eq!(
            alone([1.0, 0.0, 0.0, 1.0, 0.0, 2.000000001], 1.0),
            Ok(InertiaCheck::Physical)
        );
        let Ok(InertiaCheck::Balanced { balanced, .. }) =
            alone([1.0, 0.0, 0.0, 1.0, 0.0, 2.000001], 1.0)
        else {
            panic!("balanced");
        };
        assert!((balanced[0] - 1.0000005).abs() < 1e-12, "{balanced:?}");
    }

    #[test]
    fn a_clearly_negative_moment_is_refused() {
        let inertia = [-1e-3, 0.0, 0.0, 1e-3, 0.0, 1e-3];
        let fault = alone(inertia, 1.0).expect_err("refused");
        assert!(
            fault.starts_with("a negative principal moment (-1e-3;"),
            "{fault}"
        );
        // The slack is 1e-6 * 2e-3 + 1e-12 * 1 kg = 2.001e-9 here: just beyond it is
        // refused, just within it the moment is raised to 0 (it is beyond the declaration's
        // 1e-9 * 1e-3); 1000 kg widen the slack by 1e-9 (NEGLIGIBLE_RADIUS^2 m).
        let slightly = |i1: f64| [i1, 0.0, 0.0, 1e-3, 0.0, 1e-3];
        assert!(alone(slightly(-2.1e-9), 1.0).is_err());
        let raised = Ok(InertiaCheck::Balanced {
            moments: [-1.9e-9, 1e-3, 1e-3],
            balanced: [0.0, 1e-3, 1e-3],
            inertia: [0.0, 0.0, 0.0, 1e-3, 0.0, 1e-3],
        });
        assert_eq!(alone(slightly(-1.9e-9), 1.0), raised);
        assert!(matches!(
            alone(slightly(-2.1e-9), 1e3),
            Ok(InertiaCheck::Balanced { .. })
        ));
        // Within the declaration's slack it is kept as written.
        assert_eq!(alone(slightly(-0.9e-12), 1.0), Ok(InertiaCheck::Physical));
    }

    #[test]
    fn repaired_inertias_recheck_as_physical() {
        for (inertia, mass) in [
            ([1e-6; 6], 1e-6),
            ([1e-3, 0.0, 0.0, 1e-3, 0.0, 1e-2], 0.05),
            (rotated([1.0, 2.0, 5.0]), 3.0),
            (rotated([-1e-9, 0.3, 1.0]), 1.0),
            (rotated([0.0, 0.0, 1.0]), 1.0),
        ] {
            let (_, _, repaired) = balanced(inertia, mass);
            assert_eq!(alone(repaired, mass), Ok(InertiaCheck::Physical));
        }
    }

    #[test]
    fn repairs_meet_the_triangle_inequality_within_rounding() {
        // Random axes and broken moments over 16 decades: the balanced moments, and the
        // moments Jacobi computes of the rebuilt matrix, satisfy I1 + I2 >= I3 to 16 eps of
        // I3 (the rounding of d, the sums, the rebuilt entries and Jacobi; measured down to
        // -12.4 eps over 10^6 cases), far within the declaration's slack of 1e-9, and the
        // rebuilt matrix re-checks as physical.
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut uniform = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let axis = [uniform() - 0.5, uniform() - 0.5, uniform() - 0.5];
            let r = axis_angle(axis, std::f64::consts::PI * uniform());
            let i3 = 10f64.powf(-10.0 + 16.0 * uniform());
            let i2 = 0.499 * i3 * uniform();
            let i1 = i2 * uniform();
            // Mass 0: the slack is then a millionth of the moments, far below the gap
            // I3 - I1 - I2 >= 0.002 I3, so every case is repaired.
            let (_, balanced, inertia) = balanced(rebuild(&r, [i1, i2, i3]), 0.0);
            let tight = 16.0 * f64::EPSILON * balanced[2];
            assert!(
                balanced[0] + balanced[1] >= balanced[2] - tight,
                "{balanced:?}"
            );
            let [a, b, c] = principal_moments(inertia);
            assert!(
                a + b >= c - tight,
                "{:?} from {:?}",
                [a, b, c],
                [i1, i2, i3]
            );
            assert_eq!(alone(inertia, 0.0), Ok(InertiaCheck::Physical));
        }
    }

    /// TIAGo's antenna placeholder (1e-6 kg, principal moments -3.5e-8, 3.5e-8, 9.1e-8)
    /// is refused alone, and balanced on a robot whose largest link has moments summing
    /// to 1 kg m^2: its negative moment is below 1e-6 of that, raised to 0, and the
    /// triangle restored, (0 + d, 3.5e-8 + d, 9.1e-8) with d = 2.8e-8.
    #[test]
    fn a_negative_moment_small_on_the_robots_scale_is_balanced() {
        let antenna = [-3.5e-8, 3.5e-8, 9.1e-8];
        assert!(alone(rotated(antenna), 1e-6).is_err());
        let Ok(InertiaCheck::Balanced { balanced, .. }) =
            check_inertia(rotated(antenna), 1e-6, 1.0)
        else {
            panic!("balanced");
        };
        let expected = [2.8e-8, 6.3e-8, 9.1e-8];
        for (got, want) in balanced.iter().zip(expected) {
            assert!((got - want).abs() < 1e-20, "{balanced:?}");
        }
        // A moment of 2 % of the robot's scale is still refused.
        assert!(check_inertia(rotated([-0.02, 0.05, 0.1]), 1.0, 1.0).is_err());
        // Within the robot's round-off but larger than the link's own largest moment (a
        // sign error), or all three negative: refused.
        assert!(check_inertia(rotated([-2e-5, 1e-6, 1e-6]), 0.01, 30.0).is_err());
        assert!(check_inertia(rotated([-1e-7, -1e-7, -1e-7]), 0.01, 0.15).is_err());
    }
}
