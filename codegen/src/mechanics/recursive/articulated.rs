//! Forward dynamics by the articulated-body algorithm (ABA, Featherstone, "Rigid Body
//! Dynamics Algorithms", 2008, section 7.3), written out symbolically over the bodies of a
//! tree: O(n) expressions, against the O(n d^2) of the factorisation of M for a tree of
//! depth d (`mechanics::forward_dynamics`); the routine keeps whichever counts fewer
//! operations.
//!
//! Spatial vectors about each body's origin in its axes, motion (w, v) with v the velocity
//! of the point at the origin, force (n, f); a spatial inertia acts as
//! n = A w + B v, f = B^T w + C v (a rigid body: A = I, B = [h]x, C = m 1). Moved into the
//! parent's frame by R and o: A' = R A R^T, B' = R B R^T, C' = R C R^T, then
//! A_p = A' - B' [o]x + [o]x B'^T - [o]x C' [o]x, B_p = B' + [o]x C', C_p = C'.
//!
//! 1. Forward: w_k = R^T w_p + S_w q', v_k = R^T (v_p - o x w_p) + S_v q', the velocity
//!    product c_k = v_k x (S q') and the bias force p_k = v_k x* (I_k v_k).
//! 2. Backward: U = I^A S, D = S^T U (the pivot: the articulated inertia along the axis),
//!    u = tau - S^T p^A; into the parent I_a = I^A - U U^T / D and
//!    p_a = p^A + I_a c + U u / D, moved by (R, o).
//! 3. Forward from the base's acceleration (0, -g): a'_k = X a_p + c_k,
//!    q''_k = (u - U^T a'_k) / D, a_k = a'_k + S q''_k.

use crate::algebra::expr::{Arena, Id, Vec3};
use crate::mechanics::recursive::bodies::{Tree, TreeBody};
use crate::mechanics::recursive::vector::{
    Mat3, add, cross, dot, mat_mul, mul, mul_t, named, scale, transpose, zero,
};

/// A spatial inertia about a frame's origin in its axes (module docs).
#[derive(Clone)]
struct Spatial {
    a: Mat3,
    b: Mat3,
    c: Mat3,
}

/// [v]x.
fn skew(a: &mut Arena, v: &Vec3) -> Mat3 {
    let z = a.int(0);
    let n = v.map(|x| a.neg(x));
    [[z, n[2], v[1]], [v[2], z, n[0]], [n[1], v[0], z]]
}

fn mat_add(a: &mut Arena, x: &Mat3, y: &Mat3, sign: i64) -> Mat3 {
    let s = a.int(sign);
    [0, 1, 2].map(|i| {
        [0, 1, 2].map(|j| {
            let t = a.mul2(s, y[i][j]);
            a.add2(x[i][j], t)
        })
    })
}

fn named_mat(a: &mut Arena, x: &Mat3) -> Mat3 {
    x.map(|row| row.map(|e| a.named(e)))
}

/// x moved into the parent's frame by (R, o) (module docs).
fn moved(a: &mut Arena, x: &Spatial, r: &Mat3, o: &Vec3) -> Spatial {
    let rt = transpose(r);
    let congruence = |a: &mut Arena, m: &Mat3| {
        let t = mat_mul(a, r, m);
        let t = named_mat(a, &t);
        mat_mul(a, &t, &rt)
    };
    let (ar, br, cr) = (
        congruence(a, &x.a),
        congruence(a, &x.b),
        congruence(a, &x.c),
    );
    let cr = named_mat(a, &cr);
    let br = named_mat(a, &br);
    let ox = skew(a, o);
    let oc = mat_mul(a, &ox, &cr);
    let oc = named_mat(a, &oc);
    let b = mat_add(a, &br, &oc, 1);
    let bo = mat_mul(a, &br, &ox);
    let ob = mat_mul(a, &ox, &transpose(&br));
    let oco = mat_mul(a, &oc, &ox);
    let mut am = mat_add(a, &ar, &bo, -1);
    am = mat_add(a, &am, &ob, 1);
    am = mat_add(a, &am, &oco, -1);
    Spatial {
        a: named_mat(a, &am),
        b: named_mat(a, &b),
        c: cr,
    }
}

fn sum(a: &mut Arena, x: &Spatial, y: &Spatial) -> Spatial {
    let s = |a: &mut Arena, p: &Mat3, q: &Mat3| {
        let t = mat_add(a, p, q, 1);
        named_mat(a, &t)
    };
    Spatial {
        a: s(a, &x.a, &y.a),
        b: s(a, &x.b, &y.b),
        c: s(a, &x.c, &y.c),
    }
}

/// (A w + B v, B^T w + C v).
fn apply(a: &mut Arena, x: &Spatial, w: &Vec3, v: &Vec3) -> (Vec3, Vec3) {
    let aw = mul(a, &x.a, w);
    let bv = mul(a, &x.b, v);
    let btw = mul_t(a, &x.b, w);
    let cv = mul(a, &x.c, v);
    (add(a, &aw, &bv), add(a, &btw, &cv))
}

/// The rigid inertia of body `b` as a spatial inertia.
fn rigid(a: &mut Arena, b: &TreeBody) -> Spatial {
    let x = &b.inertia;
    let z = a.int(0);
    Spatial {
        a: x.i,
        b: skew(a, &x.h),
        c: [[x.m, z, z], [z, x.m, z], [z, z, x.m]],
    }
}

/// The motion (w, v) of the joint's unit motion S, for an axis `s`.
fn subspace(a: &mut Arena, b: &TreeBody) -> (Vec3, Vec3) {
    let z = zero(a);
    if b.revolute { (b.axis, z) } else { (z, b.axis) }
}

/// What the first pass leaves for the others, per body.
struct Pass {
    inertia: Vec<Spatial>,
    bias: Vec<(Vec3, Vec3)>,
    velocity_products: Vec<(Vec3, Vec3)>,
}

/// Pass 1 (module docs).
fn velocities(a: &mut Arena, tree: &Tree, rates: &[Id]) -> Pass {
    let z = zero(a);
    let mut vel: Vec<(Vec3, Vec3)> = Vec::with_capacity(tree.bodies.len());
    let mut inertia = Vec::new();
    let mut bias = Vec::new();
    let mut products = Vec::new();
    for b in &tree.bodies {
        let (wp, vp) = b.parent.map_or((z, z), |p| vel[p]);
        let w = mul_t(a, &b.rotation, &wp);
        let ow = cross(a, &b.origin, &wp);
        let now = scale_neg(a, &ow);
        let d = add(a, &vp, &now);
        let v = mul_t(a, &b.rotation, &d);
        let (sw, sv) = subspace(a, b);
        let qd = rates[b.coordinate];
        let (sw, sv) = (scale(a, qd, &sw), scale(a, qd, &sv));
        let w = add(a, &w, &sw);
        let w = named(a, &w);
        let v = add(a, &v, &sv);
        let v = named(a, &v);
        // c = (w, v) x (S q') = (w x Sw, w x Sv + v x Sw).
        let c1 = cross(a, &w, &sw);
        let c2 = {
            let x = cross(a, &w, &sv);
            let y = cross(a, &v, &sw);
            add(a, &x, &y)
        };
        let c1 = named(a, &c1);
        let c2 = named(a, &c2);
        products.push((c1, c2));
        let body = rigid(a, b);
        let (n, f) = apply(a, &body, &w, &v);
        let n = named(a, &n);
        let f = named(a, &f);
        // (w, v) x* (n, f) = (w x n + v x f, w x f).
        let p1 = {
            let x = cross(a, &w, &n);
            let y = cross(a, &v, &f);
            add(a, &x, &y)
        };
        let p2 = cross(a, &w, &f);
        bias.push((p1, p2));
        inertia.push(body);
        vel.push((w, v));
    }
    Pass {
        inertia,
        bias,
        velocity_products: products,
    }
}

fn scale_neg(a: &mut Arena, v: &Vec3) -> Vec3 {
    v.map(|x| a.neg(x))
}

/// q'' (by coordinate) and the pivots D (by body) of the joint forces `torques` (by
/// coordinate), by the articulated-body algorithm (module docs).
pub(crate) fn forward_dynamics(
    a: &mut Arena,
    tree: &Tree,
    n: usize,
    rates: &[Id],
    torques: &[Id],
    gravity: Option<&Vec3>,
) -> (Vec<Id>, Vec<Id>) {
    let bodies = &tree.bodies;
    let mut pass = velocities(a, tree, rates);
    let nb = bodies.len();
    let z = a.int(0);
    let mut u_vec = vec![(zero(a), zero(a)); nb];
    let mut d = vec![z; nb];
    let mut inverse = vec![z; nb];
    let mut u = vec![z; nb];
    for k in (0..nb).rev() {
        let b = &bodies[k];
        let ia = pass.inertia[k].clone();
        let (pn, pf) = pass.bias[k];
        let pn = named(a, &pn);
        let pf = named(a, &pf);
        let (sw, sv) = subspace(a, b);
        let (un, uf) = apply(a, &ia, &sw, &sv);
        let un = named(a, &un);
        let uf = named(a, &uf);
        let dk = {
            let x = dot(a, &sw, &un);
            let y = dot(a, &sv, &uf);
            a.add2(x, y)
        };
        d[k] = a.named(dk);
        if !a.is_zero(d[k]) {
            inverse[k] = a.powi(d[k], -1).unwrap_or(z);
        }
        let sp = {
            let x = dot(a, &sw, &pn);
            let y = dot(a, &sv, &pf);
            a.add2(x, y)
        };
        let uk = a.sub(torques[b.coordinate], sp);
        u[k] = a.named(uk);
        u_vec[k] = (un, uf);
        let Some(p) = b.parent else {
            continue;
        };
        // I_a = I^A - U U^T / D, p_a = p^A + I_a c + U u / D.
        let outer = |a: &mut Arena, x: &Vec3, y: &Vec3| -> Mat3 {
            [0, 1, 2].map(|i| [0, 1, 2].map(|j| a.mul(&[x[i], y[j], inverse[k]])))
        };
        let (uu_a, uu_b, uu_c) = (outer(a, &un, &un), outer(a, &un, &uf), outer(a, &uf, &uf));
        let less = |a: &mut Arena, x: &Mat3, y: &Mat3| {
            let t = mat_add(a, x, y, -1);
            named_mat(a, &t)
        };
        let ia_art = Spatial {
            a: less(a, &ia.a, &uu_a),
            b: less(a, &ia.b, &uu_b),
            c: less(a, &ia.c, &uu_c),
        };
        let (c1, c2) = pass.velocity_products[k];
        let (icn, icf) = apply(a, &ia_art, &c1, &c2);
        let ud = a.mul2(u[k], inverse[k]);
        let three = |a: &mut Arena, x: &Vec3, y: &Vec3, s: &Vec3| {
            let t = add(a, x, y);
            let us = scale(a, ud, s);
            let t = add(a, &t, &us);
            named(a, &t)
        };
        let pa_n = three(a, &pn, &icn, &un);
        let pa_f = three(a, &pf, &icf, &uf);
        let moved_inertia = moved(a, &ia_art, &b.rotation, &b.origin);
        pass.inertia[p] = sum(a, &pass.inertia[p], &moved_inertia);
        let rf = mul(a, &b.rotation, &pa_f);
        let rf = named(a, &rf);
        let rn = mul(a, &b.rotation, &pa_n);
        let orf = cross(a, &b.origin, &rf);
        let (bn, bf) = pass.bias[p];
        let bn = add(a, &bn, &rn);
        pass.bias[p] = (add(a, &bn, &orf), add(a, &bf, &rf));
    }
    let qdd = accelerations(
        a,
        tree,
        n,
        &pass.velocity_products,
        (&u_vec, &u, &inverse),
        gravity,
    );
    (qdd, d)
}

/// Pass 3 of the articulated-body algorithm: from the base (accelerating at -g) to the
/// leaves, q''_k = (u_k - U_k . a_k) / D_k and each body's acceleration a_k + S_k q''_k,
/// with `articulated` = (U, u, 1/D) by body from pass 2.
fn accelerations(
    a: &mut Arena,
    tree: &Tree,
    n: usize,
    products: &[(Vec3, Vec3)],
    articulated: (&[(Vec3, Vec3)], &[Id], &[Id]),
    gravity: Option<&Vec3>,
) -> Vec<Id> {
    let (u_vec, u, inverse) = articulated;
    let bodies = &tree.bodies;
    let nb = bodies.len();
    let z = a.int(0);
    let zv = zero(a);
    let base = (zv, gravity.map_or(zv, |g| g.map(|x| a.neg(x))));
    let mut acc: Vec<(Vec3, Vec3)> = Vec::with_capacity(nb);
    let mut qdd = vec![z; n];
    for (k, b) in bodies.iter().enumerate() {
        let (dwp, dvp) = b.parent.map_or(base, |p| acc[p]);
        let dw = mul_t(a, &b.rotation, &dwp);
        let odw = cross(a, &b.origin, &dwp);
        let nodw = scale_neg(a, &odw);
        let s = add(a, &dvp, &nodw);
        let dv = mul_t(a, &b.rotation, &s);
        let (c1, c2) = products[k];
        let dw = add(a, &dw, &c1);
        let dw = named(a, &dw);
        let dv = add(a, &dv, &c2);
        let dv = named(a, &dv);
        let (un, uf) = u_vec[k];
        let ua = {
            let x = dot(a, &un, &dw);
            let y = dot(a, &uf, &dv);
            a.add2(x, y)
        };
        let diff = a.sub(u[k], ua);
        let q = a.mul2(diff, inverse[k]);
        let q = a.named(q);
        qdd[b.coordinate] = q;
        let (sw, sv) = subspace(a, b);
        let (sw, sv) = (scale(a, q, &sw), scale(a, q, &sv));
        let dw = add(a, &dw, &sw);
        let dv = add(a, &dv, &sv);
        acc.push((named(a, &dw), named(a, &dv)));
    }
    qdd
}
