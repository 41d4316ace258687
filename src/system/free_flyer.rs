//! The free flyer's configuration manifold: q (+) v dt on R^3 x S^3 x R^joints
//! ([`integrate`]), and the quaternion algebra it and the floating-base routines share.

use nalgebra::SVector;

/// q (+) v dt (Pinocchio's `integrate`): the root by the exponential of SE(3), its pose
/// (R, p) moved to (R exp([w dt]x), p + R V(w dt) v dt) with the body-frame twist (v, w),
/// `V(phi) = 1 + (1 - cos t)/t^2 [phi]x + (t - sin t)/t^3 [phi]x^2` (t = |phi|); the
/// quaternion multiplied by (sin(t/2) phi/t, cos(t/2)) and normalised; each joint position
/// plus its rate times dt. Exact for a constant twist.
pub fn integrate<const NQ: usize, const NV: usize>(
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
    dt: f64,
) -> SVector<f64, NQ> {
    let mut out = *q;
    if NQ < 7 || NV < 6 || NQ != NV + 1 {
        return out;
    }
    integrate_slices(q.as_slice(), v.as_slice(), dt, out.as_mut_slice());
    out
}

/// [`integrate`] on slices: q (nq = nv + 1 entries, at least 7) and v (nv) into `out` (nq).
pub(crate) fn integrate_slices(q: &[f64], v: &[f64], dt: f64, out: &mut [f64]) {
    let nv = v.len();
    let u = [v[0] * dt, v[1] * dt, v[2] * dt];
    let phi = [v[3] * dt, v[4] * dt, v[5] * dt];
    let t2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2];
    let t = crate::math::sqrt(t2);
    // (1 - cos t)/t^2, (t - sin t)/t^3 and sin(t/2)/t, by their series below 1e-2 (the
    // first dropped term is below 1e-16 of each).
    let (b, c, s_half, c_half) = if t < 1e-2 {
        let t4 = t2 * t2;
        (
            0.5 - t2 / 24.0 + t4 / 720.0,
            1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0,
            0.5 - t2 / 48.0 + t4 / 3840.0,
            1.0 - t2 / 8.0 + t4 / 384.0,
        )
    } else {
        let (s, co) = crate::math::sin_cos(t);
        let (sh, ch) = crate::math::sin_cos(0.5 * t);
        ((1.0 - co) / t2, (t - s) / (t2 * t), sh / t, ch)
    };
    // V u = u + b phi x u + c phi x (phi x u).
    let pu = cross(&phi, &u);
    let ppu = cross(&phi, &pu);
    let du = [0, 1, 2].map(|i| u[i] + b * pu[i] + c * ppu[i]);
    let quat = [q[3], q[4], q[5], q[6]];
    let r = rotation(&quat);
    for i in 0..3 {
        out[i] = q[i] + r[i][0] * du[0] + r[i][1] * du[1] + r[i][2] * du[2];
    }
    let d = [s_half * phi[0], s_half * phi[1], s_half * phi[2], c_half];
    let mut p = product(&quat, &d);
    let norm = crate::math::sqrt(p.iter().map(|x| x * x).sum::<f64>());
    for x in &mut p {
        *x /= norm;
    }
    out[3..7].copy_from_slice(&p);
    for j in 6..nv {
        out[j + 1] = q[j + 1] + v[j] * dt;
    }
}

/// The cross product a x b.
pub(crate) fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// R of the unit quaternion (x, y, z, w), as the generated code forms it.
pub(crate) fn rotation(q: &[f64; 4]) -> [[f64; 3]; 3] {
    let [x, y, z, w] = *q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// The Hamilton product a b of quaternions (x, y, z, w).
fn product(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = *a;
    let [bx, by, bz, bw] = *b;
    [
        aw * bx + bw * ax + ay * bz - az * by,
        aw * by + bw * ay + az * bx - ax * bz,
        aw * bz + bw * az + ax * by - ay * bx,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}
