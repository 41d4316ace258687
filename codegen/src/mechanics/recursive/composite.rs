//! M by composite bodies (CRBA) and Pi by the static recursion, over the bodies of a tree.
//!
//! Composite bodies: the inertia (m, h, I) of each body's subtree, each child's moved into
//! its parent's frame by (R, o) (`bodies::moved`). The momentum of unit motion of joint k
//! about its origin, (f, n) = (S x h, I S) (revolute) or (m S, h x S) (prismatic), is
//! carried up the tree (f <- R f, n <- R n + o x R f) and projected on each ancestor j's
//! axis: M_jk = S_j . n (revolute j) or S_j . f (prismatic j). The floating root's six
//! unit motions are translations and rotations along its axes, and its six rows of M are
//! (f, n) themselves: its spatial inertia [[m 1, -[h]x], [[h]x, I]] on the diagonal.
//!
//! Pi: the gravity vector in each body's axes, gamma_k = R_k^T gamma_p (gamma_world = g),
//! and the height term G_k = g . p_k of its origin, G_k = G_p + gamma_p . o_k;
//! Pi = -sum_k (m_k G_k + gamma_k . h_k) plus the links fixed to the world.

use crate::algebra::expr::{Arena, Id, Vec3};
use crate::algebra::matrix::Matrix;
use crate::mechanics::recursive::bodies::{Inertia, Tree, TreeBody, moved, sum};
use crate::mechanics::recursive::vector::{add, cross, dot, mul, mul_t, named, scale};

/// S_j . n (revolute) or S_j . f (prismatic): the joint force of body `b` for the force
/// and moment (f, n) about its origin, by coordinate; the floating root's six are f and n.
fn project(a: &mut Arena, b: &TreeBody, f: &Vec3, n: &Vec3) -> Vec<(usize, Id)> {
    let c = b.coordinate;
    if b.free {
        (0..3)
            .map(|i| (c + i, f[i]))
            .chain((0..3).map(|i| (c + 3 + i, n[i])))
            .collect()
    } else if b.revolute {
        vec![(c, dot(a, &b.axis, n))]
    } else {
        vec![(c, dot(a, &b.axis, f))]
    }
}

/// The momenta (f, n) of the unit motions of body `b`'s joint, for its composite inertia
/// `x`: (S x h, I S) for a revolute joint, (m S, h x S) for a prismatic one, and for the
/// floating root the three of each along its axes e_i (its spatial inertia's columns).
fn unit_momenta(a: &mut Arena, b: &TreeBody, x: &Inertia) -> Vec<(usize, Vec3, Vec3)> {
    let along = |a: &mut Arena, s: &Vec3, revolute: bool| {
        if revolute {
            (cross(a, s, &x.h), mul(a, &x.i, s))
        } else {
            (scale(a, x.m, s), cross(a, &x.h, s))
        }
    };
    if !b.free {
        let (f, n) = along(a, &b.axis, b.revolute);
        return vec![(b.coordinate, f, n)];
    }
    let mut out = Vec::with_capacity(6);
    for (k, revolute) in [(0, false), (1, true)] {
        for i in 0..3 {
            let mut e = [a.int(0); 3];
            e[i] = a.int(1);
            let (f, n) = along(a, &e, revolute);
            out.push((b.coordinate + 3 * k + i, f, n));
        }
    }
    out
}

/// M by composite bodies (module docs), n x n.
pub(crate) fn composite_mass(a: &mut Arena, tree: &Tree, n: usize) -> Matrix {
    let bodies = &tree.bodies;
    let mut composite: Vec<Inertia> = bodies.iter().map(|b| b.inertia.clone()).collect();
    for k in (0..bodies.len()).rev() {
        if let Some(p) = bodies[k].parent {
            let x = moved(a, &composite[k], &bodies[k].rotation, &bodies[k].origin);
            composite[p] = sum(a, &composite[p], &x);
        }
    }
    let mut mass = Matrix::zeros(a, n, n);
    for (k, b) in bodies.iter().enumerate() {
        for (column, f, nm) in unit_momenta(a, b, &composite[k]) {
            let f = named(a, &f);
            let nm = named(a, &nm);
            for (row, e) in project(a, b, &f, &nm) {
                mass.set(row, column, e);
            }
            carry_up(a, bodies, k, column, f, nm, &mut mass);
        }
    }
    mass
}

/// Carries the momentum (f, n) of the unit motion of coordinate `column` (of body `k`) up
/// the tree, projecting it on every ancestor's joint: M's entries of that column above
/// body k, and their mirror images.
fn carry_up(
    a: &mut Arena,
    bodies: &[TreeBody],
    k: usize,
    column: usize,
    mut f: Vec3,
    mut nm: Vec3,
    mass: &mut Matrix,
) {
    let mut j = k;
    while let Some(p) = bodies[j].parent {
        // Named where the carry goes on: at the last ancestor the projection reads
        // them once, and the moment's terms merge with the force's.
        let further = bodies[p].parent.is_some();
        let keep = |a: &mut Arena, v: Vec3| if further { named(a, &v) } else { v };
        let rf = mul(a, &bodies[j].rotation, &f);
        let rf = keep(a, rf);
        let rn = mul(a, &bodies[j].rotation, &nm);
        let orf = cross(a, &bodies[j].origin, &rf);
        f = rf;
        let s = add(a, &rn, &orf);
        nm = keep(a, s);
        j = p;
        for (row, e) in project(a, &bodies[j], &f, &nm) {
            mass.set(row, column, e);
            mass.set(column, row, e);
        }
    }
}

/// Pi of the links' gravity (module docs), for the gravity vector `g` (world axes).
pub(crate) fn potential(a: &mut Arena, tree: &Tree, g: &Vec3) -> Id {
    let z = a.int(0);
    let nb = tree.bodies.len();
    let mut gamma = vec![[z, z, z]; nb];
    let mut height = vec![z; nb];
    let mut pi = vec![tree.fixed_potential];
    for (k, b) in tree.bodies.iter().enumerate() {
        let (gp, hp) = match b.parent {
            Some(p) => (gamma[p], height[p]),
            None => (*g, z),
        };
        gamma[k] = {
            let t = mul_t(a, &b.rotation, &gp);
            named(a, &t)
        };
        let rise = dot(a, &gp, &b.origin);
        let h = a.add2(hp, rise);
        height[k] = a.named(h);
        let x = &b.inertia;
        let mh = a.mul2(x.m, height[k]);
        let gh = dot(a, &gamma[k], &x.h);
        let e = a.add2(mh, gh);
        pi.push(a.neg(e));
    }
    a.add(&pi)
}

/// g = dPi/dq of the links' gravity by composite first moments: with gamma_k = R_k^T
/// gamma_p the gravity vector in body k's axes (gamma_world = g) and (m_k^C, h_k^C) the
/// mass and first moment of k's subtree about k's origin (h_p^C = h_p + sum_c (R_c h_c^C +
/// m_c^C o_c)), g_k = S_k . (gamma_k x h_k^C) for a revolute joint (the moment of the
/// subtree's weight about the axis) and -m_k^C S_k . gamma_k for a prismatic one.
pub(crate) fn composite_gravity(a: &mut Arena, tree: &Tree, n: usize, g: &Vec3) -> Vec<Id> {
    let bodies = &tree.bodies;
    let z = a.int(0);
    let mut gamma = vec![[z, z, z]; bodies.len()];
    for (k, b) in bodies.iter().enumerate() {
        let gp = b.parent.map_or(*g, |p| gamma[p]);
        let t = mul_t(a, &b.rotation, &gp);
        gamma[k] = named(a, &t);
    }
    let mut mass: Vec<Id> = bodies.iter().map(|b| b.inertia.m).collect();
    let mut first: Vec<Vec3> = bodies.iter().map(|b| b.inertia.h).collect();
    let mut tau = vec![z; n];
    for k in (0..bodies.len()).rev() {
        let b = &bodies[k];
        let m = a.named(mass[k]);
        let h = named(a, &first[k]);
        if b.free {
            // The subtree's weight against the root: -m gamma and the moment gamma x h.
            let moment = cross(a, &gamma[k], &h);
            for i in 0..3 {
                let mg = a.mul2(m, gamma[k][i]);
                tau[b.coordinate + i] = a.neg(mg);
                tau[b.coordinate + 3 + i] = moment[i];
            }
        } else if b.revolute {
            let t = cross(a, &gamma[k], &h);
            tau[b.coordinate] = dot(a, &b.axis, &t);
        } else {
            let t = dot(a, &b.axis, &gamma[k]);
            let mt = a.mul2(m, t);
            tau[b.coordinate] = a.neg(mt);
        }
        if let Some(p) = b.parent {
            let rh = mul(a, &b.rotation, &h);
            let mo = scale(a, m, &b.origin);
            let moved = add(a, &rh, &mo);
            first[p] = add(a, &first[p], &moved);
            mass[p] = a.add2(mass[p], m);
        }
    }
    tau
}
