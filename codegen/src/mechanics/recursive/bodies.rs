//! The moving bodies of a link tree, as the recursive route reads them: fixed links merged
//! into the moving link above them, and each moving link's frame turned so that its joint
//! axis is z.
//!
//! A moving link l with a numeric unit axis a (link frame L) becomes a body whose frame is
//! B = L A, with A a constant rotation whose third column is a: rot(a, q) = A rot_z(q) A^T,
//! so relative to its parent's body frame the body is placed by R = E A rot_z(q) (E the
//! joint origin's constant rotation, carried into the parent's body axes) and its axis is
//! e_z: the joint rotation is an elementary one, the joint force is a component of the
//! moment, and the rate enters the angular velocity in one component. What the link
//! carries in its own frame moves into B by A^T (h_B = A^T h, I_B = A^T I A), and so do its
//! children's joint origins. For a = +-e_k, A is a signed permutation (exact); for another
//! numeric axis, a rotation of floats. An axis written with parameters keeps its link's
//! frame (A = 1) and Rodrigues' rotation.

use crate::algebra::expr::{Arena, Id, Vec3};
use crate::error::Result;
use crate::mechanics::links::{joint_rotation, quaternion_matrix};
use crate::mechanics::model::Model;
use crate::mechanics::recursive::vector::{
    Mat3, add, dot, identity, mat_mul, mat3, mul, named, scale, transpose, zero,
};
use crate::mechanics::tree::{Link, LinkJoint};

/// A rigid body's inertia about a frame's origin, in that frame's axes: mass m, first
/// moment h = m c and the rotational inertia I about the origin.
#[derive(Clone)]
pub(crate) struct Inertia {
    pub(crate) m: Id,
    pub(crate) h: Vec3,
    pub(crate) i: Mat3,
}

/// A moving link with the fixed links below it merged in, in its body frame.
pub(crate) struct TreeBody {
    /// The parent body; `None`: the world.
    pub(crate) parent: Option<usize>,
    /// Its coordinate's index in q.
    pub(crate) coordinate: usize,
    /// True for a revolute joint, false for a prismatic or floating one.
    pub(crate) revolute: bool,
    /// True for the floating root (`LinkJoint::Floating`): six coordinates from
    /// `coordinate` on, the velocity of its origin and its angular velocity in its axes;
    /// its rotation is R(quaternion) and its origin p, both relative to the world.
    pub(crate) free: bool,
    /// The unit joint axis S in the body's axes (e_z unless written with parameters).
    pub(crate) axis: Vec3,
    /// R: the body's axes in its parent's axes, E rot(S, q) (E for a prismatic joint).
    pub(crate) rotation: Mat3,
    /// o: the body origin in its parent's frame (o_0 + E S q for a prismatic joint).
    pub(crate) origin: Vec3,
    /// Its own inertia and that of the fixed links merged into it, in its frame.
    pub(crate) inertia: Inertia,
}

/// The bodies of a tree, parents first, and the constant potential of the links fixed to
/// the world, -sum m g . c over them (0 without gravity).
pub(crate) struct Tree {
    pub(crate) bodies: Vec<TreeBody>,
    pub(crate) fixed_potential: Id,
}

/// `x` moved into the frame in which the frame of `x` has axes `r` and origin `o`:
/// h' = R h + m o and, with h'' = R h,
/// I' = R I R^T + m (|o|^2 1 - o o^T) + 2 (o . h'') 1 - h'' o^T - o h''^T
/// (the parallel-axis theorem for a body whose centre is not at its origin). Each result
/// is named: the sum of a subtree's inertias is read by every entry of M above it.
pub(crate) fn moved(a: &mut Arena, x: &Inertia, r: &Mat3, o: &Vec3) -> Inertia {
    let rh = {
        let t = mul(a, r, &x.h);
        named(a, &t)
    };
    let mo = scale(a, x.m, o);
    let h = {
        let t = add(a, &rh, &mo);
        named(a, &t)
    };
    let ri = mat_mul(a, r, &x.i);
    let ri = ri.map(|row| row.map(|e| a.named(e)));
    let oo = dot(a, o, o);
    let oh = dot(a, o, &rh);
    let mut i = [[a.int(0); 3]; 3];
    for r_ in 0..3 {
        for c in r_..3 {
            let t: [Id; 3] = [0, 1, 2].map(|k| a.mul2(ri[r_][k], r[c][k]));
            let mut parts = vec![a.add(&t)];
            let ooij = a.mul2(o[r_], o[c]);
            let shift = if r_ == c {
                a.sub(oo, ooij)
            } else {
                a.neg(ooij)
            };
            parts.push(a.mul2(x.m, shift));
            let (ho, oh2) = (a.mul2(rh[r_], o[c]), a.mul2(o[r_], rh[c]));
            parts.push(a.neg(ho));
            parts.push(a.neg(oh2));
            if r_ == c {
                let two = a.int(2);
                parts.push(a.mul2(two, oh));
            }
            let sum = a.add(&parts);
            let v = a.named(sum);
            i[r_][c] = v;
            i[c][r_] = v;
        }
    }
    Inertia { m: x.m, h, i }
}

/// x + y, each sum named.
pub(crate) fn sum(a: &mut Arena, x: &Inertia, y: &Inertia) -> Inertia {
    let m = a.add2(x.m, y.m);
    let m = a.named(m);
    let h = {
        let t = add(a, &x.h, &y.h);
        named(a, &t)
    };
    let i = [0, 1, 2].map(|r| {
        [0, 1, 2].map(|c| {
            let s = a.add2(x.i[r][c], y.i[r][c]);
            a.named(s)
        })
    });
    Inertia { m, h, i }
}

fn link_inertia(l: &Link) -> Inertia {
    Inertia {
        m: l.mass,
        h: l.first_moment,
        i: mat3(&l.inertia),
    }
}

/// A, the rotation whose third column is the numeric unit axis `axis` (see the module
/// docs): a signed permutation for +-e_k, floats otherwise; `None` for an axis that is not
/// numeric (written with parameters).
fn axis_frame(a: &mut Arena, axis: &Vec3) -> Option<Mat3> {
    let v: Vec<f64> = axis
        .iter()
        .map(|&x| a.as_number(x).map(|n| n.to_f64()))
        .collect::<Option<_>>()?;
    let columns: [[f64; 3]; 3] = match v.iter().filter(|x| **x != 0.0).count() {
        1 => {
            // a = s e_k: x' = e_(k+1), y' = s e_(k+2), z' = s e_k.
            let k = v.iter().position(|x| *x != 0.0)?;
            let s = v[k].signum();
            let mut cols = [[0.0; 3]; 3];
            cols[0][(k + 1) % 3] = 1.0;
            cols[1][(k + 2) % 3] = s;
            cols[2][k] = s;
            cols
        }
        _ => {
            // x' = the coordinate axis least aligned with a, made normal to it; y' = a x x'.
            let i = (0..3)
                .min_by(|&p, &q| v[p].abs().total_cmp(&v[q].abs()))
                .unwrap_or(0);
            let mut x = [0.0; 3];
            x[i] = 1.0;
            let along = v[i];
            let mut xs = [0.0; 3];
            for k in 0..3 {
                xs[k] = x[k] - along * v[k];
            }
            let len = (xs[0] * xs[0] + xs[1] * xs[1] + xs[2] * xs[2]).sqrt();
            let xs = xs.map(|c| c / len);
            let y = [
                v[1] * xs[2] - v[2] * xs[1],
                v[2] * xs[0] - v[0] * xs[2],
                v[0] * xs[1] - v[1] * xs[0],
            ];
            [xs, y, [v[0], v[1], v[2]]]
        }
    };
    let mut m = identity(a);
    for (c, col) in columns.iter().enumerate() {
        for (r, &x) in col.iter().enumerate() {
            m[r][c] = if x == 0.0 {
                a.int(0)
            } else if x.abs() == 1.0 {
                a.int(x as i64)
            } else {
                a.float(x).ok()?
            };
        }
    }
    Some(m)
}

/// Pushes the floating root link `l` (its first coordinate and configuration symbols) as a
/// body, R(quaternion) and p relative to the world with its inertia in its own frame (no
/// axis to turn to z), and its frame's place in that body.
fn push_floating(
    a: &mut Arena,
    l: &Link,
    (coordinate, configuration): (usize, &[Id; 7]),
    bodies: &mut Vec<TreeBody>,
    place: &mut Vec<Place>,
) {
    bodies.push(TreeBody {
        parent: None,
        coordinate,
        revolute: false,
        free: true,
        axis: zero(a),
        rotation: mat3(&quaternion_matrix(a, configuration)),
        origin: [configuration[0], configuration[1], configuration[2]],
        inertia: link_inertia(l),
    });
    place.push(Place {
        body: Some(bodies.len() - 1),
        rotation: identity(a),
        origin: zero(a),
    });
}

/// Where a link's frame is: the body it moves with (`None`: the world) and its axes and
/// origin in that body's frame.
#[derive(Clone)]
struct Place {
    body: Option<usize>,
    rotation: Mat3,
    origin: Vec3,
}

/// The moving bodies of `model`'s links (module docs) and the potential of the links fixed
/// to the world.
pub(crate) fn tree_bodies(a: &mut Arena, model: &Model) -> Result<Tree> {
    let mut fixed_potential = a.int(0);
    let mut place: Vec<Place> = Vec::with_capacity(model.links.len());
    let mut bodies: Vec<TreeBody> = Vec::new();
    for l in &model.links {
        let parent = match l.parent {
            Some(p) => place[p].clone(),
            None => Place {
                body: None,
                rotation: identity(a),
                origin: zero(a),
            },
        };
        // The joint frame in the parent body's frame.
        let er = mat_mul(a, &parent.rotation, &mat3(&l.origin_rotation));
        let eo = {
            let v = mul(a, &parent.rotation, &l.origin);
            add(a, &parent.origin, &v)
        };
        let (coordinate, axis, revolute) = match &l.joint {
            LinkJoint::Fixed => {
                let x = moved(a, &link_inertia(l), &er, &eo);
                match parent.body {
                    Some(b) => bodies[b].inertia = sum(a, &bodies[b].inertia, &x),
                    None => {
                        if let Some(g) = &model.gravity {
                            // Fixed to the world: -g . (m o + R h), a constant.
                            let gh = dot(a, g, &x.h);
                            let neg = a.neg(gh);
                            fixed_potential = a.add2(fixed_potential, neg);
                        }
                    }
                }
                place.push(Place {
                    body: parent.body,
                    rotation: er,
                    origin: eo,
                });
                continue;
            }
            LinkJoint::Floating {
                coordinate,
                configuration,
            } => {
                push_floating(a, l, (*coordinate, configuration), &mut bodies, &mut place);
                continue;
            }
            LinkJoint::Revolute { coordinate, axis } => (*coordinate, axis, true),
            LinkJoint::Prismatic { coordinate, axis } => (*coordinate, axis, false),
        };
        let frame = axis_frame(a, axis);
        let (e, axis) = match &frame {
            Some(f) => {
                let z = a.int(0);
                let one = a.int(1);
                (mat_mul(a, &er, f), [z, z, one])
            }
            None => (er, *axis),
        };
        let q = model.coordinates[coordinate].q;
        let (rotation, origin) = if revolute {
            let j = joint_rotation(a, &axis, q).0;
            (mat_mul(a, &e, &mat3(&j)), eo)
        } else {
            let slide = scale(a, q, &axis);
            let moved_by = mul(a, &e, &slide);
            (e, add(a, &eo, &moved_by))
        };
        let own = link_inertia(l);
        // The link frame in the body frame: axes A^T (L = B A^T), origin 0.
        let to_body = frame.map(|f| transpose(&f));
        let inertia = match &to_body {
            Some(t) => {
                let z = zero(a);
                moved(a, &own, t, &z)
            }
            None => own,
        };
        bodies.push(TreeBody {
            parent: parent.body,
            coordinate,
            revolute,
            free: false,
            axis,
            rotation,
            origin,
            inertia,
        });
        place.push(Place {
            body: Some(bodies.len() - 1),
            rotation: to_body.unwrap_or_else(|| identity(a)),
            origin: zero(a),
        });
    }
    Ok(Tree {
        bodies,
        fixed_potential,
    })
}
