//! The derivatives of the inverse dynamics of a tree of links by a recursion of their own
//! (the analytical derivatives of Newton-Euler, Carpentier & Mansard 2018, rederived for
//! this route): dtau/dq and dtau/dq' of M q'' + C q' (+ g where the links carry the
//! potential), built as expressions like every other output, O(n d) entries of a few
//! products each (d the depth of the tree) instead of the derivative of every node of the
//! recursion by every coordinate.
//!
//! Spatial vectors, linear part first: a motion m = [v; w] (v the velocity of the body
//! point at the frame's origin), a force f = [f; n] (n about the origin);
//! m1 x m2 = [w1 x v2 + v1 x w2; w1 x w2], m x* f = [w x f; v x f + w x n],
//! m . f = v.f + w.n. A body's inertia about the origin, (m, h = m c, I_O), acts as
//! I [v; w] = [m v - h x w; h x v + I_O w]; its rate along the motion,
//! dI/dt = v x* I - I v x, is the inertia (0, h', I_O') with h' = m v + w x h and
//! I_O' = [w]x I_O - I_O [w]x + 2 (h.v) 1 - v h^T - h v^T. Every quantity of body k is held in
//! k's own frame (the joint frame: origin on the axis), where its inertia is constant and
//! its joint's motion S_k = [0; a] (revolute about the unit axis a) or [a; 0] (prismatic) is
//! sparse; a motion goes down to a child's frame (R, o) as [R^T (v + w x o); R^T w], a force
//! up as [R f; R n + o x R f] (for the Panda's joints, R is a signed permutation times a
//! turn about one axis: a few operations). The dot products of the entries are taken in
//! the frame of the joint above, where S is sparse.
//!
//! Newton-Euler (parent lambda of body k; a_0 = [-g; 0] where gravity is included):
//! v_k = v_lambda + S_k q'_k, psi_k = v_lambda x S_k, a_k = a_lambda + S_k q''_k + psi_k q'_k,
//! f_k = I_k a_k + v_k x* (I_k v_k), F_k the sum of f over the subtree of k,
//! tau_k = S_k . F_k. A change of q_k turns the subtree of k rigidly about S_k, which moves
//! each motion m of it by S_k x m, each force by S_k x*, and the velocities and
//! accelerations besides by psi_k and u_k + psi_k x v_l, with
//! u_k = a_lambda x S_k + v_lambda x psi_k. With the subtree's inertia Ic, its rate Ic',
//! its momentum Hc = sum I_l v_l, and alpha_j = Ic_j S_j,
//! gamma_j = Ic'_j S_j - S_j x* Hc_j (Ic' is symmetric):
//!
//! ```text
//! dtau_j/dq_k  = alpha_j . u_k + gamma_j . psi_k          (j in the subtree of k)
//! dtau_j/dq'_k = 2 alpha_j . psi_k + gamma_j . S_k
//! dtau_i/dq_k  = S_i . (S_k x* F_k + Ic_k u_k + Ic'_k psi_k + psi_k x* Hc_k)   (i above k)
//! dtau_i/dq'_k = S_i . (2 Ic_k psi_k + Ic'_k S_k + S_k x* Hc_k)
//! ```
//!
//! Fixed links are merged into the moving link above them (their inertias moved into its
//! frame); links fixed to the world do not move and are left out.
//!
//! Every vector and inertia the passes build (velocities, accelerations, psi, u, forces,
//! the subtree sums, and alpha, gamma, w, y in each frame they are carried into) is named
//! once ([`crate::Node::Named`]): the next frame's expressions read it as one operand
//! instead of its sum being flattened into theirs, which the CSE does not undo (the
//! Panda's dtau/dq, dtau/dq': 6,956 operations per call without the names, 3,812 with).
//!
//! The same recursion gives M and the bias C q' (+ g) ([`tree_dynamics`]): M_ij =
//! S_i . alpha_j for j in the subtree of i (alpha_j carried into i's frame, as above), and
//! b_k = S_k . F0_k of a pass at q'' = 0 over the same velocities and psi, so that the
//! forward dynamics' derivatives can take q'' from the derivatives' own kinematics.

use crate::algebra::expr::{Arena, Id, Vec3};
use crate::algebra::matrix::Matrix;
use crate::error::Result;
use crate::mechanics::model::Model;
use crate::mechanics::tree::{Link, LinkJoint};

/// A spatial vector: linear part, angular part.
#[derive(Clone, Copy)]
struct Spatial {
    lin: Vec3,
    ang: Vec3,
}

/// A spatial inertia about the world origin in world axes: (m, h, I_O), I_O symmetric.
#[derive(Clone, Copy)]
struct Inertia {
    m: Id,
    h: Vec3,
    i: [[Id; 3]; 3],
}

/// One moving body: its parent body, coordinate, joint motion S and inertia in its own
/// frame, and that frame's rotation R (its axes in the parent's) and origin o (in the
/// parent's frame).
struct Body {
    parent: Option<usize>,
    coordinate: usize,
    s: Spatial,
    inertia: Inertia,
    rotation: [[Id; 3]; 3],
    origin: Vec3,
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

fn mat_vec(a: &mut Arena, m: &[[Id; 3]; 3], v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| {
        let t: Vec<Id> = (0..3).map(|k| a.mul2(m[i][k], v[k])).collect();
        a.add(&t)
    })
}

impl Spatial {
    /// Each component named: a sum kept as one operand of what reads it.
    fn named(&self, a: &mut Arena) -> Spatial {
        Spatial {
            lin: self.lin.map(|x| a.named(x)),
            ang: self.ang.map(|x| a.named(x)),
        }
    }

    fn zero(a: &mut Arena) -> Self {
        let z = a.int(0);
        Spatial {
            lin: [z; 3],
            ang: [z; 3],
        }
    }

    fn add(&self, a: &mut Arena, o: &Spatial) -> Spatial {
        Spatial {
            lin: add(a, &self.lin, &o.lin),
            ang: add(a, &self.ang, &o.ang),
        }
    }

    fn scale(&self, a: &mut Arena, s: Id) -> Spatial {
        Spatial {
            lin: scale(a, s, &self.lin),
            ang: scale(a, s, &self.ang),
        }
    }

    /// self x m (motion).
    fn cross(&self, a: &mut Arena, m: &Spatial) -> Spatial {
        let p = cross(a, &self.ang, &m.lin);
        let q = cross(a, &self.lin, &m.ang);
        Spatial {
            lin: add(a, &p, &q),
            ang: cross(a, &self.ang, &m.ang),
        }
    }

    /// self x* f (force).
    fn cross_force(&self, a: &mut Arena, f: &Spatial) -> Spatial {
        let p = cross(a, &self.lin, &f.lin);
        let q = cross(a, &self.ang, &f.ang);
        Spatial {
            lin: cross(a, &self.ang, &f.lin),
            ang: add(a, &p, &q),
        }
    }

    /// self . f.
    fn dot(&self, a: &mut Arena, f: &Spatial) -> Id {
        let l = dot(a, &self.lin, &f.lin);
        let r = dot(a, &self.ang, &f.ang);
        a.add2(l, r)
    }

    /// The motion `self` of the parent's frame in the frame (R, o):
    /// [R^T (v + w x o); R^T w].
    fn motion_down(&self, a: &mut Arena, b: &Body) -> Spatial {
        let wo = cross(a, &self.ang, &b.origin);
        let v = add(a, &self.lin, &wo);
        Spatial {
            lin: mat_t_vec(a, &b.rotation, &v),
            ang: mat_t_vec(a, &b.rotation, &self.ang),
        }
    }

    /// The force `self` of the frame (R, o) in the parent's frame: [R f; R n + o x R f].
    fn force_up(&self, a: &mut Arena, b: &Body) -> Spatial {
        let f = mat_vec(a, &b.rotation, &self.lin);
        let n = mat_vec(a, &b.rotation, &self.ang);
        let of = cross(a, &b.origin, &f);
        Spatial {
            lin: f,
            ang: add(a, &n, &of),
        }
    }
}

fn mat_t_vec(a: &mut Arena, m: &[[Id; 3]; 3], v: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| {
        let t: Vec<Id> = (0..3).map(|k| a.mul2(m[k][i], v[k])).collect();
        a.add(&t)
    })
}

impl Inertia {
    /// Each entry named (the arena interns: a symmetric pair is one named node).
    fn named(&self, a: &mut Arena) -> Inertia {
        let i = self.i.map(|row| row.map(|x| a.named(x)));
        Inertia {
            m: a.named(self.m),
            h: self.h.map(|x| a.named(x)),
            i,
        }
    }

    /// I x = [m v - h x w; h x v + I_O w].
    fn apply(&self, a: &mut Arena, x: &Spatial) -> Spatial {
        let mv = scale(a, self.m, &x.lin);
        let hw = cross(a, &self.h, &x.ang);
        let lin = [0, 1, 2].map(|i| a.sub(mv[i], hw[i]));
        let hv = cross(a, &self.h, &x.lin);
        let iw = mat_vec(a, &self.i, &x.ang);
        Spatial {
            lin,
            ang: add(a, &hv, &iw),
        }
    }

    /// The inertia of the frame (R, o) in the parent's frame: h' = R h + m o,
    /// I' = R I R^T + m (|o|^2 1 - o o^T) + 2 (o.h'') 1 - h'' o^T - o h''^T with h'' = R h
    /// (the parallel-axis theorem for a body whose centre is not at its origin).
    fn moved(&self, a: &mut Arena, b: &Body) -> Inertia {
        let (r, o) = (&b.rotation, &b.origin);
        let rh = mat_vec(a, r, &self.h);
        let mo = scale(a, self.m, o);
        let h = add(a, &rh, &mo);
        let mut ri = [[a.int(0); 3]; 3];
        for (i, row) in ri.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                let t: Vec<Id> = (0..3).map(|k| a.mul2(r[i][k], self.i[k][j])).collect();
                *e = a.add(&t);
            }
        }
        let oo = dot(a, o, o);
        let oh = dot(a, o, &rh);
        let two = a.int(2);
        let mut out = [[a.int(0); 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                let mut t: Vec<Id> = (0..3).map(|k| a.mul2(ri[i][k], r[j][k])).collect();
                let oij = a.mul2(o[i], o[j]);
                let shift = if i == j { a.sub(oo, oij) } else { a.neg(oij) };
                t.push(a.mul2(self.m, shift));
                let x = a.mul2(rh[i], o[j]);
                t.push(a.neg(x));
                let x = a.mul2(o[i], rh[j]);
                t.push(a.neg(x));
                if i == j {
                    t.push(a.mul2(two, oh));
                }
                let e = a.add(&t);
                out[i][j] = e;
                out[j][i] = e;
            }
        }
        Inertia {
            m: self.m,
            h,
            i: out,
        }
    }

    fn add(&self, a: &mut Arena, o: &Inertia) -> Inertia {
        Inertia {
            m: a.add2(self.m, o.m),
            h: add(a, &self.h, &o.h),
            i: [0, 1, 2].map(|r| [0, 1, 2].map(|c| a.add2(self.i[r][c], o.i[r][c]))),
        }
    }

    /// dI/dt along the motion `v` (module docs): (0, m v + w x h, [w]x I - I [w]x +
    /// 2 (h.v) 1 - v h^T - h v^T).
    fn rate(&self, a: &mut Arena, v: &Spatial) -> Inertia {
        let mv = scale(a, self.m, &v.lin);
        let wh = cross(a, &v.ang, &self.h);
        let h = add(a, &mv, &wh);
        let hv = dot(a, &self.h, &v.lin);
        let two = a.int(2);
        let trace = a.mul2(two, hv);
        let w = v.ang;
        let z = a.int(0);
        // [w]x as rows.
        let skew = {
            let n = |a: &mut Arena, x: Id| a.neg(x);
            let (w0, w1, w2) = (n(a, w[0]), n(a, w[1]), n(a, w[2]));
            [[z, w2, w[1]], [w[2], z, w0], [w1, w[0], z]]
        };
        let mut i = [[z; 3]; 3];
        for r in 0..3 {
            for c in r..3 {
                // ([w]x I - I [w]x)_rc = sum_k skew_rk I_kc - I_rk skew_kc.
                let mut terms = Vec::with_capacity(8);
                for (k, skew_k) in skew.iter().enumerate() {
                    terms.push(a.mul2(skew[r][k], self.i[k][c]));
                    let t = a.mul2(self.i[r][k], skew_k[c]);
                    terms.push(a.neg(t));
                }
                let vh = a.mul2(v.lin[r], self.h[c]);
                let hv2 = a.mul2(self.h[r], v.lin[c]);
                terms.push(a.neg(vh));
                terms.push(a.neg(hv2));
                if r == c {
                    terms.push(trace);
                }
                let e = a.add(&terms);
                i[r][c] = e;
                i[c][r] = e;
            }
        }
        Inertia { m: z, h, i }
    }
}

/// The inertia of link `l` about its origin in its axes.
fn link_inertia(l: &Link) -> Inertia {
    Inertia {
        m: l.mass,
        h: l.first_moment,
        i: [0, 1, 2].map(|r| [0, 1, 2].map(|c| l.inertia.get(r, c))),
    }
}

/// The moving bodies of `model`'s links in their own frames, fixed links merged (module
/// docs).
fn bodies(a: &mut Arena, model: &Model) -> Result<Vec<Body>> {
    // For each link: its body (None: the world), its axes and origin in that body's frame.
    let mut place: Vec<(Option<usize>, Matrix, Vec3)> = Vec::with_capacity(model.links.len());
    let mut bodies: Vec<Body> = Vec::new();
    let zero = a.int(0);
    for l in &model.links {
        let (pbody, pr, po) = match l.parent {
            Some(p) => place[p].clone(),
            None => (None, Matrix::identity(a, 3), [zero; 3]),
        };
        // The joint frame in the parent body's frame.
        let er = pr.mul(a, &l.origin_rotation)?;
        let eo = {
            let prm = [0, 1, 2].map(|i| [0, 1, 2].map(|j| pr.get(i, j)));
            let v = mat_vec(a, &prm, &l.origin);
            add(a, &po, &v)
        };
        let (coordinate, axis, revolute) = match &l.joint {
            LinkJoint::Fixed => {
                if let Some(b) = pbody {
                    let frame = Body {
                        parent: None,
                        coordinate: 0,
                        s: Spatial::zero(a),
                        inertia: link_inertia(l),
                        rotation: [0, 1, 2].map(|i| [0, 1, 2].map(|j| er.get(i, j))),
                        origin: eo,
                    };
                    let x = frame.inertia.moved(a, &frame);
                    bodies[b].inertia = bodies[b].inertia.add(a, &x);
                }
                place.push((pbody, er, eo));
                continue;
            }
            LinkJoint::Revolute { coordinate, axis } => (*coordinate, *axis, true),
            LinkJoint::Prismatic { coordinate, axis } => (*coordinate, *axis, false),
            // The derivatives are of q' = dq/dt dynamics; a floating root's v is not the
            // rate of its configuration, and its derivatives are not derived.
            LinkJoint::Floating { .. } => {
                return Err(crate::Error::Derivation(
                    crate::error::DerivationError::FloatingBase {
                        mechanism: model.name.clone(),
                        what: "the derivatives of the dynamics".to_string(),
                        nq: model.configuration_size(),
                        nv: model.coordinates.len(),
                    },
                ));
            }
        };
        let q = model.coordinates[coordinate].q;
        let (rotation, origin, s) = if revolute {
            let j = crate::mechanics::links::joint_rotation(a, &axis, q).0;
            let r = er.mul(a, &j)?;
            let s = Spatial {
                lin: [zero; 3],
                ang: axis,
            };
            (r, eo, s)
        } else {
            let aq = scale(a, q, &axis);
            let erm = [0, 1, 2].map(|i| [0, 1, 2].map(|j| er.get(i, j)));
            let slide = mat_vec(a, &erm, &aq);
            let s = Spatial {
                lin: axis,
                ang: [zero; 3],
            };
            (er, add(a, &eo, &slide), s)
        };
        bodies.push(Body {
            parent: pbody,
            coordinate,
            s,
            inertia: link_inertia(l),
            rotation: [0, 1, 2].map(|i| [0, 1, 2].map(|j| rotation.get(i, j))),
            origin,
        });
        place.push((Some(bodies.len() - 1), Matrix::identity(a, 3), [zero; 3]));
    }
    Ok(bodies)
}

/// What the forward pass gives each body (in its frame).
struct Motion {
    v: Spatial,
    acc: Spatial,
    psi: Spatial,
    u: Spatial,
    f: Spatial,
    h: Spatial,
    rate: Inertia,
}

/// dtau/dq and dtau/dq' (n x n each) of M q'' + C q', plus the links' gravity when
/// `gravity` is given (module docs), for a model whose links carry all of T.
///
/// # Errors
/// None in practice (every product is of 3 x 3 matrices); a matrix error otherwise.
pub(crate) fn tree_derivatives(model: &mut Model, gravity: Option<Vec3>) -> Result<[Matrix; 2]> {
    let mut arena = std::mem::take(&mut model.arena);
    let result = derivatives_in(&mut arena, model, gravity, false);
    model.arena = arena;
    Ok(result?.derivatives)
}

/// The recursion's derivatives and, from the same kinematics, M and the bias: what the
/// forward dynamics' derivatives read ([`tree_dynamics`]).
pub(crate) struct TreeDynamics {
    /// dtau/dq and dtau/dq' (n x n each), in the acceleration symbols.
    pub(crate) derivatives: [Matrix; 2],
    /// M (n x n): M_ij = S_i . Ic_j S_j for j in the subtree of i, alpha_j = Ic_j S_j
    /// carried up into i's frame as the derivatives carry it.
    pub(crate) mass: Matrix,
    /// C q' (+ g with `gravity`) (n x 1): S_k . F0_k, F0 the subtree forces of a
    /// Newton-Euler pass at q'' = 0 over the same velocities and psi.
    pub(crate) bias: Matrix,
}

/// [`tree_derivatives`] with M and the bias from the same recursion ([`TreeDynamics`]):
/// q'' = M^-1 (u - b) and the derivatives at that q'' then share the bodies' velocities,
/// rotations, subtree inertias and momenta, instead of q'' being computed by a route of
/// its own (the recursive route's M by composite bodies and b by Newton-Euler, in other
/// frames).
///
/// # Errors
/// As [`tree_derivatives`].
pub(crate) fn tree_dynamics(model: &mut Model, gravity: Option<Vec3>) -> Result<TreeDynamics> {
    let mut arena = std::mem::take(&mut model.arena);
    let result = derivatives_in(&mut arena, model, gravity, true);
    model.arena = arena;
    result
}

/// [`tree_dynamics`] in `a`, the arena taken out of `model`; M and the bias are built
/// only `with_dynamics` (zeros otherwise: nodes no one reads would renumber the arena).
fn derivatives_in(
    a: &mut Arena,
    model: &Model,
    gravity: Option<Vec3>,
    with_dynamics: bool,
) -> Result<TreeDynamics> {
    let n = model.coordinates.len();
    let bodies = bodies(a, model)?;
    let zero = Spatial::zero(a);
    let base = match gravity {
        Some(g) => Spatial {
            lin: g.map(|x| a.neg(x)),
            ang: zero.ang,
        },
        None => zero,
    };
    let motion = forward(a, model, &bodies, base, true);
    let subtrees = Subtrees::of(a, &bodies, &motion);
    let mut dq = Matrix::zeros(a, n, n);
    let mut dqd = Matrix::zeros(a, n, n);
    let mut mass = Matrix::zeros(a, n, n);
    let mut bias = Matrix::zeros(a, n, 1);
    for k in 0..bodies.len() {
        let m = with_dynamics.then_some(&mut mass);
        entries(a, (&bodies, &motion, &subtrees), k, (&mut dq, &mut dqd, m));
    }
    if with_dynamics {
        // The pass at q'' = 0 reads the same velocities, psi and momenta (the same nodes).
        let rest = forward(a, model, &bodies, base, false);
        let mut force: Vec<Spatial> = rest.iter().map(|m| m.f).collect();
        for k in (0..bodies.len()).rev() {
            if let Some(p) = bodies[k].parent {
                let f = force[k].force_up(a, &bodies[k]);
                force[p] = force[p].add(a, &f);
            }
        }
        for (b, f) in bodies.iter().zip(&force) {
            bias.set(b.coordinate, 0, b.s.dot(a, f));
        }
    }
    Ok(TreeDynamics {
        derivatives: [dq, dqd],
        mass,
        bias,
    })
}

/// The forward pass of Newton-Euler in each body's frame (the base accelerating at
/// `base`): velocities, psi and u, forces and the inertias' rates; the accelerations
/// include S q'' only `with_accelerations` (else q'' = 0: the bias's pass).
fn forward(
    a: &mut Arena,
    model: &Model,
    bodies: &[Body],
    base: Spatial,
    with_accelerations: bool,
) -> Vec<Motion> {
    let zero = Spatial::zero(a);
    let mut motion: Vec<Motion> = Vec::with_capacity(bodies.len());
    for b in bodies {
        let (vp, ap) = match b.parent {
            Some(p) => (motion[p].v, motion[p].acc),
            None => (zero, base),
        };
        let (vp, ap) = (vp.motion_down(a, b).named(a), ap.motion_down(a, b).named(a));
        let c = &model.coordinates[b.coordinate];
        let sq = b.s.scale(a, c.qd);
        let v = vp.add(a, &sq).named(a);
        let psi = vp.cross(a, &b.s).named(a);
        let pq = psi.scale(a, c.qd);
        let acc = if with_accelerations {
            let sa = b.s.scale(a, c.qdd);
            ap.add(a, &sa).add(a, &pq).named(a)
        } else {
            ap.add(a, &pq).named(a)
        };
        let x = ap.cross(a, &b.s);
        let y = vp.cross(a, &psi);
        let u = x.add(a, &y).named(a);
        let h = b.inertia.apply(a, &v).named(a);
        let ia = b.inertia.apply(a, &acc);
        let vh = v.cross_force(a, &h);
        let f = ia.add(a, &vh).named(a);
        let rate = b.inertia.rate(a, &v).named(a);
        motion.push(Motion {
            v,
            acc,
            psi,
            u,
            f,
            h,
            rate,
        });
    }
    motion
}

/// Each subtree's inertia, its rate, its momentum and its force, in its root body's frame.
struct Subtrees {
    inertia: Vec<Inertia>,
    rate: Vec<Inertia>,
    momentum: Vec<Spatial>,
    force: Vec<Spatial>,
}

impl Subtrees {
    /// The backward pass: each body's sums moved into its parent's frame and added there.
    fn of(a: &mut Arena, bodies: &[Body], motion: &[Motion]) -> Subtrees {
        let mut ic: Vec<Inertia> = bodies.iter().map(|b| b.inertia).collect();
        let mut rc: Vec<Inertia> = motion.iter().map(|m| m.rate).collect();
        let mut hc: Vec<Spatial> = motion.iter().map(|m| m.h).collect();
        let mut fc: Vec<Spatial> = motion.iter().map(|m| m.f).collect();
        for k in (0..bodies.len()).rev() {
            if let Some(p) = bodies[k].parent {
                let b = &bodies[k];
                let (i, r) = (ic[k].moved(a, b), rc[k].moved(a, b));
                let (h, f) = (hc[k].force_up(a, b), fc[k].force_up(a, b));
                ic[p] = ic[p].add(a, &i).named(a);
                rc[p] = rc[p].add(a, &r).named(a);
                hc[p] = hc[p].add(a, &h).named(a);
                fc[p] = fc[p].add(a, &f).named(a);
            }
        }
        Subtrees {
            inertia: ic,
            rate: rc,
            momentum: hc,
            force: fc,
        }
    }
}

/// The entries of body k (module docs): its row against k and each joint above it, and its
/// column against each joint strictly above it; with `mass`, M's entries of k's row and
/// column (S_j . alpha_k in j's frame).
fn entries(
    a: &mut Arena,
    (bodies, motion, sub): (&[Body], &[Motion], &Subtrees),
    k: usize,
    (dq, dqd, mut mass): (&mut Matrix, &mut Matrix, Option<&mut Matrix>),
) {
    let (b, m, s) = (&bodies[k], &motion[k], bodies[k].s);
    let (ic, rc, hc) = (&sub.inertia[k], &sub.rate[k], &sub.momentum[k]);
    let two = a.int(2);
    // alpha_k = Ic S, gamma_k = Ic' S - S x* Hc, carried up into each joint j's frame.
    let mut alpha = ic.apply(a, &s).named(a);
    let rs = rc.apply(a, &s).named(a);
    let sh = s.cross_force(a, hc).named(a);
    let mut gamma = Spatial {
        lin: [0, 1, 2].map(|i| a.sub(rs.lin[i], sh.lin[i])),
        ang: [0, 1, 2].map(|i| a.sub(rs.ang[i], sh.ang[i])),
    }
    .named(a);
    let mut j = k;
    loop {
        let mj = &motion[j];
        let (cj, ck) = (bodies[j].coordinate, b.coordinate);
        let x = alpha.dot(a, &mj.u);
        let y = gamma.dot(a, &mj.psi);
        dq.set(ck, cj, a.add2(x, y));
        let alpha2 = alpha.scale(a, two);
        let x = alpha2.dot(a, &mj.psi);
        let y = gamma.dot(a, &bodies[j].s);
        dqd.set(ck, cj, a.add2(x, y));
        if let Some(mass) = mass.as_deref_mut() {
            let e = bodies[j].s.dot(a, &alpha);
            mass.set(ck, cj, e);
            mass.set(cj, ck, e);
        }
        let Some(p) = bodies[j].parent else { break };
        alpha = alpha.force_up(a, &bodies[j]).named(a);
        gamma = gamma.force_up(a, &bodies[j]).named(a);
        j = p;
    }
    // w_k and y_k, carried up into each joint i's frame above k.
    let sf = s.cross_force(a, &sub.force[k]);
    let iu = ic.apply(a, &m.u);
    let rpsi = rc.apply(a, &m.psi);
    let ph = m.psi.cross_force(a, hc);
    let mut w = sf.add(a, &iu).add(a, &rpsi).add(a, &ph).named(a);
    let ipsi = ic.apply(a, &m.psi);
    let ipsi2 = ipsi.scale(a, two);
    let mut y = ipsi2.add(a, &rs).add(a, &sh).named(a);
    let mut i = k;
    while let Some(p) = bodies[i].parent {
        w = w.force_up(a, &bodies[i]).named(a);
        y = y.force_up(a, &bodies[i]).named(a);
        let (sp, cp) = (bodies[p].s, bodies[p].coordinate);
        dq.set(cp, b.coordinate, sp.dot(a, &w));
        dqd.set(cp, b.coordinate, sp.dot(a, &y));
        i = p;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::diff::Differentiator;
    use crate::algebra::eval::eval_matrix;
    use crate::algebra::expr::{SymbolId, SymbolKind};
    use crate::mechanics::motion_jacobians::row_jacobians;
    use crate::urdf::{UrdfOptions, urdf_to_mech};

    /// The recursion's derivatives equal those of the traced inverse dynamics (the
    /// differentiator on `Equations::inverse_dynamics`) at a state away from every
    /// symmetry, to round-off (1e-11 of the largest entry: both sum O(100) products of O(1)
    /// to O(10) terms).
    fn agrees(source: &str) {
        let mut model = crate::pipeline::parse_model_str(source).unwrap();
        let eqs = crate::derive(&mut model).unwrap();
        assert!(model.kinetic_from_links);
        let symbol = |id| model.arena.as_symbol(id).unwrap();
        let q: Vec<_> = model.coordinates.iter().map(|c| symbol(c.q)).collect();
        let qd: Vec<_> = model.coordinates.iter().map(|c| symbol(c.qd)).collect();
        let gravity = model.gravity.filter(|_| model.potential_from_links);
        let [dq, dqd] = tree_derivatives(&mut model, gravity).unwrap();
        // M and the bias of the same recursion against the dynamics' (the recursive
        // route's composite bodies and Newton-Euler, other frames and another pass).
        let tree =
            crate::mechanics::dynamics_derivatives::recursion_dynamics(&mut model, &eqs).unwrap();
        let mut d = Differentiator::new();
        let arena = &mut model.arena;
        // What the recursion leaves out: g where the links do not carry the potential.
        let rows: Vec<Id> = (0..eqs.n)
            .map(|i| {
                let id = eqs.inverse_dynamics.get(i, 0);
                let tau = eqs.forces.get(i, 0);
                let id = arena.add2(id, tau);
                match gravity {
                    Some(_) => id,
                    None => arena.sub(id, eqs.gravity.get(i, 0)),
                }
            })
            .collect();
        let [tq, tqd] = row_jacobians(arena, &mut d, &rows, [&q, &qd]).unwrap();
        let params: Vec<(SymbolId, f64)> = (model.parameters.iter())
            .map(|p| (model.arena.as_symbol(p.symbol).unwrap(), p.default))
            .collect();
        let env = |s: SymbolId| {
            if let Some((_, v)) = params.iter().find(|(p, _)| *p == s) {
                return Some(*v);
            }
            let info = model.arena.symbol_info(s);
            let k = s.index() as f64;
            Some(match info.kind {
                SymbolKind::Coordinate => 0.3 + 0.37 * (k * 1.7).sin(),
                SymbolKind::Velocity => -0.8 + 0.53 * (k * 0.9).cos(),
                SymbolKind::Acceleration => 1.1 - 0.61 * (k * 1.3).sin(),
                _ => 0.45,
            })
        };
        let pairs = [
            (&dq, &tq),
            (&dqd, &tqd),
            (&tree.mass, &eqs.mass),
            (&tree.bias, &eqs.bias),
        ];
        for (ours, traced) in pairs {
            let a = eval_matrix(&model.arena, ours, &env).unwrap();
            let b = eval_matrix(&model.arena, traced, &env).unwrap();
            let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
            let err = a
                .iter()
                .zip(&b)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(err <= 1e-11 * scale, "{err:e} of {scale:e}");
        }
    }

    fn urdf(text: &str, lock: &[&str]) -> String {
        let options = UrdfOptions {
            file_name: "robot.urdf".into(),
            struct_name: None,
            lock: lock.iter().map(|s| s.to_string()).collect(),
            damping: true,
            snap_angles: None,
            floating: false,
        };
        urdf_to_mech(text, &options).unwrap()
    }

    #[test]
    fn a_chain_with_fixed_links_and_declared_damping() {
        // The Panda with its fingers free: two prismatic joints (one held to the other by a
        // constraint row), fixed links, and the joints' damping as declared forces.
        agrees(&urdf(
            include_str!("../../../mechanisms/urdf/panda.urdf"),
            &[],
        ));
    }

    #[test]
    fn a_branching_tree() {
        // Solo12 with its base fixed: four legs of three joints about x and y.
        agrees(&urdf(
            include_str!("../../../mechanisms/urdf/solo12.urdf"),
            &[],
        ));
    }

    #[test]
    fn a_closed_loop_of_links() {
        // The five-bar: two chains with loop rows, gravity from the links.
        agrees(include_str!("../../../mechanisms/five_bar.mech"));
    }
}
