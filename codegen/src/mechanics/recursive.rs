//! The recursive route for kinematic trees declared with links: M by composite bodies
//! (CRBA), C q' and the inverse dynamics by Newton-Euler (RNEA), each O(n) expressions per
//! output entry, built symbolically over the links' frames and then shared by CSE like every
//! other output.
//!
//! A fixed link is merged into the nearest moving link above it (or into the world, where
//! it has no effect). Each moving link k then has, relative to its parent body p, the
//! rotation R_k (k axes to p axes), the origin o_k (in p) and the unit joint axis a_k (in
//! k axes), and the inertia about its origin in its axes: mass m_k, first moment h_k = m_k c_k
//! and I_k (see [`crate::mechanics::links`]).
//!
//! Newton-Euler, every vector in the axes of its own link (classical accelerations of the
//! link origin; the base moves with a_0 = -g when gravity is included):
//! - w_k = R_k^T w_p + a_k q_k' (revolute),  w_k = R_k^T w_p (prismatic);
//! - dw_k = R_k^T dw_p + a_k q_k'' + w_k x a_k q_k' (revolute),  R_k^T dw_p (prismatic);
//! - a_k = R_k^T (a_p + dw_p x o_k + w_p x (w_p x o_k)) (+ a_k q_k'' + 2 w_k x a_k q_k' when
//!   prismatic);
//! - f_k = m_k a_k + dw_k x h_k + w_k x (w_k x h_k) + sum_children R_c f_c,
//!   n_k = I_k dw_k + w_k x (I_k w_k) + h_k x a_k + sum_children (R_c n_c + o_c x R_c f_c);
//! - tau_k = a_k . n_k (revolute) or a_k . f_k (prismatic).
//!
//! Composite bodies: the composite inertia (m, h, I) of k's subtree, each child's moved into
//! k's axes by (R, o): h' = R h + m o and
//! I' = R I R^T + m (|o|^2 1 - o o^T) + 2 (o . h'') 1 - h'' o^T - o h''^T with h'' = R h
//! (the parallel-axis theorem for a body whose centre is not at its origin). The momentum
//! of unit motion of joint k, (f, n) = (a x h, I a) (revolute) or (m a, h x a)
//! (prismatic), is carried up the tree (f <- R f, n <- R n + o x R f) and projected on each
//! ancestor's axis: M_jk.

use crate::algebra::expr::{Arena, Id, Vec3};
use crate::algebra::matrix::Matrix;
use crate::error::Result;
use crate::mechanics::model::Model;
use crate::mechanics::tree::{Link, LinkJoint};

/// A spatial inertia about a frame origin, in its axes: (m, h = m c, I).
#[derive(Clone)]
struct Inertia {
    m: Id,
    h: Vec3,
    i: [[Id; 3]; 3],
}

/// A moving link with the fixed links merged into it.
struct TreeBody {
    parent: Option<usize>,
    coordinate: usize,
    revolute: bool,
    axis: Vec3,
    rotation: Matrix,
    origin: Vec3,
    inertia: Inertia,
}

/// The outputs of the recursive route (module docs).
pub(crate) struct TreeEquations {
    /// M (n x n).
    pub(crate) mass: Matrix,
    /// C q' (n x 1), without gravity.
    pub(crate) coriolis_forces: Matrix,
    /// M q'' + C q' (n x 1), without gravity.
    pub(crate) inertial_forces: Matrix,
    /// g = dPi/dq (n x 1) and Pi, when the links' gravity is all of Pi.
    pub(crate) gravity: Option<(Matrix, Id)>,
}

fn cross(a: &mut Arena, u: &Vec3, v: &Vec3) -> Vec3 {
    let t = |a: &mut Arena, i: usize, j: usize| {
        let p = a.mul2(u[i], v[j]);
        let q = a.mul2(u[j], v[i]);
        a.sub(p, q)
    };
    [t(a, 1, 2), t(a, 2, 0), t(a, 0, 1)]
}

fn dot(a: &mut Arena, u: &Vec3, v: &Vec3) -> Id {
    let t: Vec<Id> = (0..3).map(|i| a.mul2(u[i], v[i])).collect();
    a.add(&t)
}

fn add(a: &mut Arena, u: &Vec3, v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| a.add2(u[i], v[i]))
}

fn scale(a: &mut Arena, s: Id, u: &Vec3) -> Vec3 {
    u.map(|x| a.mul2(s, x))
}

/// R v.
fn rot(a: &mut Arena, r: &Matrix, v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| {
        let t: Vec<Id> = (0..3).map(|k| a.mul2(r.get(i, k), v[k])).collect();
        a.add(&t)
    })
}

/// R^T v.
fn rot_t(a: &mut Arena, r: &Matrix, v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| {
        let t: Vec<Id> = (0..3).map(|k| a.mul2(r.get(k, i), v[k])).collect();
        a.add(&t)
    })
}

fn mat_vec(a: &mut Arena, m: &[[Id; 3]; 3], v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| {
        let t: Vec<Id> = (0..3).map(|k| a.mul2(m[i][k], v[k])).collect();
        a.add(&t)
    })
}

/// `x` moved into the axes of the frame in which the frame of `x` has rotation `r` and
/// origin `o` (module docs).
fn moved(a: &mut Arena, x: &Inertia, r: &Matrix, o: &Vec3) -> Inertia {
    let rh = rot(a, r, &x.h);
    let mo = scale(a, x.m, o);
    let h = add(a, &rh, &mo);
    // R I R^T.
    let mut ri = [[a.int(0); 3]; 3];
    for (i, row) in ri.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            let t: Vec<Id> = (0..3).map(|k| a.mul2(r.get(i, k), x.i[k][j])).collect();
            *e = a.add(&t);
        }
    }
    let mut out = [[a.int(0); 3]; 3];
    let oo = dot(a, o, o);
    let oh = dot(a, o, &rh);
    for i in 0..3 {
        for j in i..3 {
            let t: Vec<Id> = (0..3).map(|k| a.mul2(ri[i][k], r.get(j, k))).collect();
            let rir = a.add(&t);
            let ooij = a.mul2(o[i], o[j]);
            let mut parts = vec![rir];
            let shift = if i == j { a.sub(oo, ooij) } else { a.neg(ooij) };
            parts.push(a.mul2(x.m, shift));
            let ho = a.mul2(rh[i], o[j]);
            let oh2 = a.mul2(o[i], rh[j]);
            parts.push(a.neg(ho));
            parts.push(a.neg(oh2));
            if i == j {
                let two = a.int(2);
                parts.push(a.mul2(two, oh));
            }
            let v = a.add(&parts);
            out[i][j] = v;
            out[j][i] = v;
        }
    }
    Inertia { m: x.m, h, i: out }
}

fn sum(a: &mut Arena, x: &Inertia, y: &Inertia) -> Inertia {
    let m = a.add2(x.m, y.m);
    let h = add(a, &x.h, &y.h);
    let i = [0, 1, 2].map(|r| [0, 1, 2].map(|c| a.add2(x.i[r][c], y.i[r][c])));
    Inertia { m, h, i }
}

fn link_inertia(l: &Link) -> Inertia {
    Inertia {
        m: l.mass,
        h: l.first_moment,
        i: [0, 1, 2].map(|r| [0, 1, 2].map(|c| l.inertia.get(r, c))),
    }
}

/// The moving bodies of the tree, fixed links merged (module docs), and the constant part
/// of the links' potential, -sum m g . r over the links fixed to the world.
fn tree_bodies(arena: &mut Arena, model: &Model) -> Result<(Vec<TreeBody>, Id)> {
    let mut fixed_potential = arena.int(0);
    let links = &model.links;
    // For each link: (its body, or None for the world; its rotation and origin in the
    // body's frame).
    let mut place: Vec<(Option<usize>, Matrix, Vec3)> = Vec::with_capacity(links.len());
    let mut bodies: Vec<TreeBody> = Vec::new();
    for l in links {
        let (pbody, pr, po) = match l.parent {
            Some(p) => place[p].clone(),
            None => {
                let z = arena.int(0);
                (None, Matrix::identity(arena, 3), [z, z, z])
            }
        };
        // The joint frame in the parent body's frame.
        let er = pr.mul(arena, &l.origin_rotation)?;
        let eo = {
            let v = rot(arena, &pr, &l.origin);
            add(arena, &po, &v)
        };
        match &l.joint {
            LinkJoint::Fixed => {
                let x = moved(arena, &link_inertia(l), &er, &eo);
                if let Some(b) = pbody {
                    let merged = sum(arena, &bodies[b].inertia, &x);
                    bodies[b].inertia = merged;
                } else if let Some(g) = &model.gravity {
                    // Fixed to the world: -g . (m o + R h), a constant.
                    let gh = dot(arena, g, &x.h);
                    let neg = arena.neg(gh);
                    fixed_potential = arena.add2(fixed_potential, neg);
                }
                place.push((pbody, er, eo));
            }
            LinkJoint::Revolute { coordinate, axis }
            | LinkJoint::Prismatic { coordinate, axis } => {
                let q = model.coordinates[*coordinate].q;
                let revolute = matches!(l.joint, LinkJoint::Revolute { .. });
                let (rotation, origin) = if revolute {
                    // R = E J: the joint's rotation in the joint frame, whose axes are E.
                    let j = joint_matrix(arena, axis, q);
                    (er.mul(arena, &j)?, eo)
                } else {
                    let aq = scale(arena, q, axis);
                    let slide = rot(arena, &er, &aq);
                    (er, add(arena, &eo, &slide))
                };
                bodies.push(TreeBody {
                    parent: pbody,
                    coordinate: *coordinate,
                    revolute,
                    axis: *axis,
                    rotation,
                    origin,
                    inertia: link_inertia(l),
                });
                let z = arena.int(0);
                place.push((
                    Some(bodies.len() - 1),
                    Matrix::identity(arena, 3),
                    [z, z, z],
                ));
            }
        }
    }
    Ok((bodies, fixed_potential))
}

/// g = dPi/dq and Pi by the static recursion, the gravity vector carried into each body's
/// axes: gamma_k = R_k^T gamma_p (gamma_world = g); the height term G_k = g . p_k of the
/// body origin by G_k = G_p + gamma_p . o_k; Pi = -sum_k (m_k G_k + gamma_k . h_k) (+ the
/// links fixed to the world); and the generalized gravity by Newton-Euler with the base
/// accelerating at -g: f_k = -m_k gamma_k, n_k = -h_k x gamma_k, summed up the tree.
fn gravity_and_potential(
    arena: &mut Arena,
    bodies: &[TreeBody],
    n: usize,
    g: &Vec3,
    fixed_potential: Id,
) -> (Matrix, Id) {
    let z = arena.int(0);
    let nb = bodies.len();
    let mut gamma = vec![[z, z, z]; nb];
    let mut height = vec![z; nb];
    let mut f = vec![[z, z, z]; nb];
    let mut nm = vec![[z, z, z]; nb];
    let mut pi = vec![fixed_potential];
    let minus_one = arena.int(-1);
    for (k, b) in bodies.iter().enumerate() {
        let (gp, hp) = match b.parent {
            Some(p) => (gamma[p], height[p]),
            None => (*g, z),
        };
        gamma[k] = rot_t(arena, &b.rotation, &gp);
        let rise = dot(arena, &gp, &b.origin);
        height[k] = arena.add2(hp, rise);
        let x = &b.inertia;
        let mh = arena.mul2(x.m, height[k]);
        let gh = dot(arena, &gamma[k], &x.h);
        let e = arena.add2(mh, gh);
        pi.push(arena.neg(e));
        let mg = scale(arena, x.m, &gamma[k]);
        f[k] = scale(arena, minus_one, &mg);
        nm[k] = cross(arena, &gamma[k], &x.h);
    }
    let tau = backward(arena, bodies, n, f, nm);
    (Matrix::column(tau), arena.add(&pi))
}

/// The rotation of a revolute joint about its unit axis (the same matrix the link's world
/// rotation uses, so both routes share its nodes).
fn joint_matrix(arena: &mut Arena, axis: &Vec3, q: Id) -> Matrix {
    crate::mechanics::links::joint_rotation(arena, axis, q).0
}

/// Newton-Euler over the bodies without gravity (the base at rest): the joint forces for
/// rates `qd` and accelerations `qdd` (`None`: zero).
fn newton_euler(
    arena: &mut Arena,
    bodies: &[TreeBody],
    n: usize,
    qd: &[Id],
    qdd: Option<&[Id]>,
) -> Vec<Id> {
    let z = arena.int(0);
    let zero = [z, z, z];
    let nb = bodies.len();
    let mut w = vec![zero; nb];
    let mut dw = vec![zero; nb];
    let mut acc = vec![zero; nb];
    let mut f = vec![zero; nb];
    let mut nm = vec![zero; nb];
    for (k, b) in bodies.iter().enumerate() {
        let (wp, dwp, ap) = match b.parent {
            Some(p) => (w[p], dw[p], acc[p]),
            None => (zero, zero, zero),
        };
        let rate = qd[b.coordinate];
        let accel = qdd.map(|a| a[b.coordinate]);
        let wr = rot_t(arena, &b.rotation, &wp);
        let dwr = rot_t(arena, &b.rotation, &dwp);
        // a_p + dw_p x o + w_p x (w_p x o), then into k's axes.
        let t1 = cross(arena, &dwp, &b.origin);
        let wo = cross(arena, &wp, &b.origin);
        let t2 = cross(arena, &wp, &wo);
        let s = add(arena, &ap, &t1);
        let s = add(arena, &s, &t2);
        let mut ak = rot_t(arena, &b.rotation, &s);
        let aqd = scale(arena, rate, &b.axis);
        if b.revolute {
            w[k] = add(arena, &wr, &aqd);
            let c = cross(arena, &w[k], &aqd);
            let mut d = add(arena, &dwr, &c);
            if let Some(qa) = accel {
                let aqa = scale(arena, qa, &b.axis);
                d = add(arena, &d, &aqa);
            }
            dw[k] = d;
        } else {
            w[k] = wr;
            dw[k] = dwr;
            let c = cross(arena, &w[k], &aqd);
            let two = arena.int(2);
            let c2 = scale(arena, two, &c);
            ak = add(arena, &ak, &c2);
            if let Some(qa) = accel {
                let aqa = scale(arena, qa, &b.axis);
                ak = add(arena, &ak, &aqa);
            }
        }
        acc[k] = ak;
        let x = &b.inertia;
        let ma = scale(arena, x.m, &acc[k]);
        let dwh = cross(arena, &dw[k], &x.h);
        let wh = cross(arena, &w[k], &x.h);
        let wwh = cross(arena, &w[k], &wh);
        f[k] = add(arena, &ma, &dwh);
        f[k] = add(arena, &f[k], &wwh);
        let idw = mat_vec(arena, &x.i, &dw[k]);
        let iw = mat_vec(arena, &x.i, &w[k]);
        let wiw = cross(arena, &w[k], &iw);
        let ha = cross(arena, &x.h, &acc[k]);
        nm[k] = add(arena, &idw, &wiw);
        nm[k] = add(arena, &nm[k], &ha);
    }
    backward(arena, bodies, n, f, nm)
}

/// The backward pass of Newton-Euler: each body's force f and moment n (about its origin,
/// its axes) projected on its joint axis, then added into its parent's, moved by (R, o):
/// f_p += R f, n_p += R n + o x R f. The joint forces, by coordinate.
fn backward(
    arena: &mut Arena,
    bodies: &[TreeBody],
    n: usize,
    mut f: Vec<Vec3>,
    mut nm: Vec<Vec3>,
) -> Vec<Id> {
    let z = arena.int(0);
    let mut tau = vec![z; n];
    for k in (0..bodies.len()).rev() {
        let b = &bodies[k];
        tau[b.coordinate] = if b.revolute {
            dot(arena, &b.axis, &nm[k])
        } else {
            dot(arena, &b.axis, &f[k])
        };
        if let Some(p) = b.parent {
            let rf = rot(arena, &b.rotation, &f[k]);
            let rn = rot(arena, &b.rotation, &nm[k]);
            let orf = cross(arena, &b.origin, &rf);
            f[p] = add(arena, &f[p], &rf);
            let s = add(arena, &nm[p], &rn);
            nm[p] = add(arena, &s, &orf);
        }
    }
    tau
}

/// M by composite bodies (module docs).
fn composite_mass(arena: &mut Arena, bodies: &[TreeBody], n: usize) -> Matrix {
    let mut composite: Vec<Inertia> = bodies.iter().map(|b| b.inertia.clone()).collect();
    for k in (0..bodies.len()).rev() {
        if let Some(p) = bodies[k].parent {
            let x = moved(arena, &composite[k], &bodies[k].rotation, &bodies[k].origin);
            composite[p] = sum(arena, &composite[p], &x);
        }
    }
    let mut mass = Matrix::zeros(arena, n, n);
    for (k, b) in bodies.iter().enumerate() {
        let x = &composite[k];
        let (mut f, mut nm) = if b.revolute {
            (cross(arena, &b.axis, &x.h), mat_vec(arena, &x.i, &b.axis))
        } else {
            (scale(arena, x.m, &b.axis), cross(arena, &x.h, &b.axis))
        };
        let project = |arena: &mut Arena, body: &TreeBody, f: &Vec3, nm: &Vec3| {
            if body.revolute {
                dot(arena, &body.axis, nm)
            } else {
                dot(arena, &body.axis, f)
            }
        };
        let diag = project(arena, b, &f, &nm);
        mass.set(b.coordinate, b.coordinate, diag);
        let mut j = k;
        while let Some(p) = bodies[j].parent {
            let rf = rot(arena, &bodies[j].rotation, &f);
            let rn = rot(arena, &bodies[j].rotation, &nm);
            let orf = cross(arena, &bodies[j].origin, &rf);
            f = rf;
            nm = add(arena, &rn, &orf);
            j = p;
            let e = project(arena, &bodies[j], &f, &nm);
            mass.set(bodies[j].coordinate, b.coordinate, e);
            mass.set(b.coordinate, bodies[j].coordinate, e);
        }
    }
    mass
}

/// M, C q' and M q'' + C q' of a model whose links carry all its kinetic energy.
pub(crate) fn tree_equations(model: &mut Model) -> Result<TreeEquations> {
    let n = model.coordinates.len();
    let qd: Vec<Id> = model.coordinates.iter().map(|c| c.qd).collect();
    let qdd: Vec<Id> = model.coordinates.iter().map(|c| c.qdd).collect();
    let mut arena = std::mem::take(&mut model.arena);
    let result = (|| {
        let (bodies, fixed_potential) = tree_bodies(&mut arena, model)?;
        let mass = composite_mass(&mut arena, &bodies, n);
        let coriolis = newton_euler(&mut arena, &bodies, n, &qd, None);
        let inertial = newton_euler(&mut arena, &bodies, n, &qd, Some(&qdd));
        let gravity = match (model.potential_from_links, &model.gravity) {
            (true, Some(g)) => Some(gravity_and_potential(
                &mut arena,
                &bodies,
                n,
                g,
                fixed_potential,
            )),
            _ => None,
        };
        Ok(TreeEquations {
            mass,
            coriolis_forces: Matrix::column(coriolis),
            inertial_forces: Matrix::column(inertial),
            gravity,
        })
    })();
    model.arena = arena;
    result
}

/// The frame Jacobian of link `l` at its origin, world axes (6 x n): rows 0..3 the
/// velocity of the origin, rows 3..6 the angular velocity; column of joint j (an ancestor
/// of l or l itself), with z_j = R_w,j a_j: [z_j x (p_l - p_j); z_j] (revolute),
/// [z_j; 0] (prismatic).
pub(crate) fn frame_jacobian(arena: &mut Arena, links: &[Link], l: usize, n: usize) -> Matrix {
    let mut jac = Matrix::zeros(arena, 6, n);
    let target = links[l].position;
    let mut cur = Some(l);
    while let Some(j) = cur {
        let link = &links[j];
        match &link.joint {
            LinkJoint::Fixed => {}
            LinkJoint::Revolute { coordinate, axis } => {
                let z = rot(arena, &link.rotation, axis);
                let d = [0, 1, 2].map(|i| arena.sub(target[i], link.position[i]));
                let v = cross(arena, &z, &d);
                for i in 0..3 {
                    jac.set(i, *coordinate, v[i]);
                    jac.set(3 + i, *coordinate, z[i]);
                }
            }
            LinkJoint::Prismatic { coordinate, axis } => {
                let z = rot(arena, &link.rotation, axis);
                for (i, zi) in z.into_iter().enumerate() {
                    jac.set(i, *coordinate, zi);
                }
            }
        }
        cur = link.parent;
    }
    jac
}
