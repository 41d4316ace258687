//! Newton-Euler over the bodies of a tree (the recursive route's C q', g, bias and inverse
//! dynamics), every vector in its own body's axes, each link's results named once.
//!
//! Forward, body k below p with R, o and axis S (see `bodies.rs`), rates q' and
//! accelerations q'' (zero where not given), the base moving with dw_0 = 0 and the linear
//! acceleration dv_0 = -g when gravity is included:
//! - u_k = R^T w_p, w_k = u_k + S q_k' (revolute) or u_k (prismatic);
//! - dw_k = R^T dw_p + S q_k'' + u_k x S q_k' (revolute) or R^T dw_p (prismatic);
//! - U_p = [dw_p]x + [w_p]x [w_p]x, so that dw_p x o + w_p x (w_p x o) = U_p o (one matrix
//!   read by every child's origin and by the body's own first moment);
//! - dv_k = R^T (dv_p + U_p o) (+ S q_k'' + 2 w_k x S q_k' when prismatic), the acceleration
//!   of the body origin;
//! - F_k = m dv_k + U_k h, N_k = I dw_k + w_k x (I w_k) + h x dv_k (the force and the moment
//!   about the origin that the body's motion needs, h = m c its first moment, I its
//!   inertia about the origin).
//!
//! The floating root (`free`, six coordinates from its first, Pinocchio's free flyer) moves
//! with the velocity v of its origin and the angular velocity w, both in its axes, and
//! their rates of change a and dw: w_0 = w, dw_0 = dw and
//! dv_0 = R^T (-g) + a + w x v (the acceleration of the origin in the root's axes:
//! d/dt (R v) = R (a + w x v)). Its six joint forces are the force and the moment about
//! its origin, (f_0, n_0), in its axes.
//!
//! Backward, children before parents: f_k = F_k + sum_c R_c f_c,
//! n_k = N_k + sum_c (R_c n_c + o_c x R_c f_c), and tau_k = S . n_k (revolute) or S . f_k
//! (prismatic).

use crate::algebra::expr::{Arena, Id, Vec3};
use crate::mechanics::recursive::bodies::{Tree, TreeBody};
use crate::mechanics::recursive::vector::{Mat3, add, cross, dot, mul, mul_t, named, scale, zero};

/// What a Newton-Euler pass is given: the rates and accelerations by coordinate (`None`:
/// zero) and the gravity vector (world axes) when its forces are included.
pub(crate) struct Motion<'a> {
    pub(crate) rates: Option<&'a [Id]>,
    pub(crate) accelerations: Option<&'a [Id]>,
    pub(crate) gravity: Option<&'a Vec3>,
}

/// One body's motion: angular velocity w, angular acceleration dw, the acceleration dv of
/// its origin, and U = [dw]x + [w]x [w]x.
#[derive(Clone)]
struct Kinematics {
    w: Vec3,
    dw: Vec3,
    dv: Vec3,
    u: Mat3,
}

/// U = [dw]x + [w]x [w]x = [dw]x + w w^T - |w|^2 1, each entry named.
fn u_matrix(a: &mut Arena, w: &Vec3, dw: &Vec3) -> Mat3 {
    let sq = w.map(|x| a.mul2(x, x));
    let mut m = [[a.int(0); 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            let v = if i == j {
                // -(w_j^2 + w_k^2) for the other two components j, k.
                let s = a.add2(sq[(i + 1) % 3], sq[(i + 2) % 3]);
                a.neg(s)
            } else {
                // w_i w_j + [dw]x_ij, [dw]x_ij = -e_ijk dw_k.
                let k = 3 - i - j;
                let ww = a.mul2(w[i], w[j]);
                let d = if (j + 3 - i) % 3 == 1 {
                    a.neg(dw[k])
                } else {
                    dw[k]
                };
                a.add2(ww, d)
            };
            *e = a.named(v);
        }
    }
    m
}

/// The kinematics of body `b` from its parent's `p`.
fn child_kinematics(
    a: &mut Arena,
    b: &TreeBody,
    p: &Kinematics,
    rate: Option<Id>,
    accel: Option<Id>,
) -> Kinematics {
    let u = {
        let t = mul_t(a, &b.rotation, &p.w);
        named(a, &t)
    };
    let dwr = mul_t(a, &b.rotation, &p.dw);
    let uo = mul(a, &p.u, &b.origin);
    let s = add(a, &p.dv, &uo);
    let mut dv = mul_t(a, &b.rotation, &s);
    let (mut w, mut dw) = (u, dwr);
    let sqd = rate.map(|r| scale(a, r, &b.axis));
    let sqdd = accel.map(|r| scale(a, r, &b.axis));
    if b.revolute {
        if let Some(sqd) = &sqd {
            w = add(a, &u, sqd);
            let c = cross(a, &u, sqd);
            dw = add(a, &dw, &c);
        }
        if let Some(sqdd) = &sqdd {
            dw = add(a, &dw, sqdd);
        }
    } else {
        if let Some(sqd) = &sqd {
            let c = cross(a, &w, sqd);
            let two = a.int(2);
            let c2 = scale(a, two, &c);
            dv = add(a, &dv, &c2);
        }
        if let Some(sqdd) = &sqdd {
            dv = add(a, &dv, sqdd);
        }
    }
    let w = named(a, &w);
    let dw = named(a, &dw);
    let dv = named(a, &dv);
    let u = u_matrix(a, &w, &dw);
    Kinematics { w, dw, dv, u }
}

/// The kinematics of the floating root `b` (module docs) with the world's `p` as parent
/// (w = 0, dw = 0, dv = -g or 0).
fn free_kinematics(a: &mut Arena, b: &TreeBody, p: &Kinematics, m: &Motion<'_>) -> Kinematics {
    let c = b.coordinate;
    let part = |r: Option<&[Id]>, from: usize| r.map(|r| [r[from], r[from + 1], r[from + 2]]);
    let z = zero(a);
    let (v, w) = (part(m.rates, c), part(m.rates, c + 3));
    let (dv_own, dw) = (part(m.accelerations, c), part(m.accelerations, c + 3));
    let mut dv = mul_t(a, &b.rotation, &p.dv);
    if let Some(x) = dv_own {
        dv = add(a, &dv, &x);
    }
    if let (Some(v), Some(w)) = (v, w) {
        let wv = cross(a, &w, &v);
        dv = add(a, &dv, &wv);
    }
    let w = named(a, &w.unwrap_or(z));
    let dw = named(a, &dw.unwrap_or(z));
    let dv = named(a, &dv);
    let u = u_matrix(a, &w, &dw);
    Kinematics { w, dw, dv, u }
}

/// F = m dv + U h and N = I dw + w x (I w) + h x dv (module docs).
fn body_forces(a: &mut Arena, b: &TreeBody, k: &Kinematics) -> (Vec3, Vec3) {
    let x = &b.inertia;
    let mdv = scale(a, x.m, &k.dv);
    let uh = mul(a, &k.u, &x.h);
    let f = {
        let t = add(a, &mdv, &uh);
        named(a, &t)
    };
    let idw = mul(a, &x.i, &k.dw);
    let iw = {
        let t = mul(a, &x.i, &k.w);
        named(a, &t)
    };
    let wiw = cross(a, &k.w, &iw);
    let hdv = cross(a, &x.h, &k.dv);
    let n = add(a, &idw, &wiw);
    let n = {
        let t = add(a, &n, &hdv);
        named(a, &t)
    };
    (f, n)
}

/// The joint forces tau (by coordinate, n of them) of the motion `m` (module docs).
pub(crate) fn newton_euler(a: &mut Arena, tree: &Tree, n: usize, m: &Motion<'_>) -> Vec<Id> {
    let z = zero(a);
    let zero_u = [z, z, z];
    let base_dv = match m.gravity {
        Some(g) => g.map(|x| a.neg(x)),
        None => z,
    };
    let base = Kinematics {
        w: z,
        dw: z,
        dv: base_dv,
        u: zero_u,
    };
    let mut kin: Vec<Kinematics> = Vec::with_capacity(tree.bodies.len());
    let mut f = Vec::with_capacity(tree.bodies.len());
    let mut nm = Vec::with_capacity(tree.bodies.len());
    for b in &tree.bodies {
        let p = b.parent.map_or(&base, |p| &kin[p]);
        let rate = m.rates.map(|r| r[b.coordinate]);
        let accel = m.accelerations.map(|r| r[b.coordinate]);
        let k = if b.free {
            free_kinematics(a, b, p, m)
        } else {
            child_kinematics(a, b, p, rate, accel)
        };
        let (fk, nk) = body_forces(a, b, &k);
        kin.push(k);
        f.push(fk);
        nm.push(nk);
    }
    backward(a, &tree.bodies, n, f, nm)
}

/// The backward pass: each body's force f and moment n (about its origin, in its axes,
/// complete once its children are added) projected on its axis, then moved into its
/// parent's: f_p += R f, n_p += R n + o x R f. The joint forces, by coordinate.
pub(crate) fn backward(
    a: &mut Arena,
    bodies: &[TreeBody],
    n: usize,
    mut f: Vec<Vec3>,
    mut nm: Vec<Vec3>,
) -> Vec<Id> {
    let z = a.int(0);
    let mut tau = vec![z; n];
    for k in (0..bodies.len()).rev() {
        let b = &bodies[k];
        let fk = named(a, &f[k]);
        let nk = named(a, &nm[k]);
        if b.free {
            for i in 0..3 {
                tau[b.coordinate + i] = fk[i];
                tau[b.coordinate + 3 + i] = nk[i];
            }
        } else if b.revolute {
            tau[b.coordinate] = dot(a, &b.axis, &nk);
        } else {
            tau[b.coordinate] = dot(a, &b.axis, &fk);
        }
        if let Some(p) = b.parent {
            let rf = {
                let t = mul(a, &b.rotation, &fk);
                named(a, &t)
            };
            let rn = mul(a, &b.rotation, &nk);
            let orf = cross(a, &b.origin, &rf);
            f[p] = add(a, &f[p], &rf);
            let s = add(a, &nm[p], &rn);
            nm[p] = add(a, &s, &orf);
        }
    }
    tau
}
