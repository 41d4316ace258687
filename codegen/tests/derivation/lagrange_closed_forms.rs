//! Lagrange assembly on mechanisms whose equations are known in closed form, and against the
//! num-dual Lagrangian oracle (tests/common: M, h, g, Phi_q, gamma from T, Pi, Phi alone).
//!
//! Tolerance 1e-10 (relative, absolute below 1) for oracle comparisons: both sides evaluate
//! the same smooth functions of O(1) inputs with fewer than ~50 roundings, so they agree to
//! ~1e-14; any wrong term is off by O(1).

use crate::common::{
    State, assert_equations_close, bare_model, close, eval_equations, oracle_equations,
};
use mechanism_codegen::error::{AlgebraError, DeclarationError, DerivationError};
use mechanism_codegen::internals::christoffel_coriolis_forces;
use mechanism_codegen::{Arena, Error, Func, Id, Matrix, Model, SymbolKind, derive, eval_matrix};

const TOL: f64 = 1e-10;

fn param(a: &mut Arena, name: &str) -> Id {
    a.symbol(name, SymbolKind::Parameter)
}

/// Pendulum of length l in polar coordinates (r, th), th from the downward vertical:
/// T = 1/2 m (r'^2 + r^2 th'^2), Pi = -m g r cos th, Phi = r - l.
fn polar_pendulum() -> Model {
    let mut a = Arena::new();
    let (m, g, l) = (param(&mut a, "m"), param(&mut a, "g"), param(&mut a, "l"));
    let [r, rd, rdd] = a.coordinate("r");
    let [th, thd, thdd] = a.coordinate("th");
    let rd2 = a.powi(rd, 2).unwrap();
    let r2 = a.powi(r, 2).unwrap();
    let thd2 = a.powi(thd, 2).unwrap();
    let r2thd2 = a.mul2(r2, thd2);
    let v2 = a.add2(rd2, r2thd2);
    let half = a.rational(1, 2).unwrap();
    let kinetic = a.mul(&[half, m, v2]);
    let c = a.cos(th);
    let mgr = a.mul(&[m, g, r, c]);
    let potential = a.neg(mgr);
    let phi = a.sub(r, l);
    bare_model(
        a,
        &[("r", [r, rd, rdd]), ("th", [th, thd, thdd])],
        kinetic,
        potential,
        vec![phi],
    )
}

#[test]
fn polar_pendulum_closed_form() {
    let mut model = polar_pendulum();
    let eqs = derive(&mut model).unwrap();
    let a = &mut model.arena;
    let [m, g] = ["m", "g"].map(|n| a.symbol(n, SymbolKind::Parameter));
    let [r, rd, th, thd] = ["r", "der(r)", "th", "der(th)"].map(|n| a.symbol(n, SymbolKind::Free));
    let (zero, one, two) = (a.int(0), a.int(1), a.int(2));
    let r2 = a.powi(r, 2).unwrap();
    let mr2 = a.mul2(m, r2);
    assert_eq!(
        eqs.mass.data(),
        vec![m, zero, zero, mr2],
        "M = diag(m, m r^2)"
    );
    let thd2 = a.powi(thd, 2).unwrap();
    let mrw = a.mul(&[m, r, thd2]);
    let centrifugal = a.neg(mrw);
    let coriolis = a.mul(&[two, m, r, rd, thd]);
    assert_eq!(
        eqs.coriolis_forces.data(),
        vec![centrifugal, coriolis],
        "C q' = [-m r th'^2, 2 m r r' th']"
    );
    let (s, c) = (a.sin(th), a.cos(th));
    let mgc = a.mul(&[m, g, c]);
    let g0 = a.neg(mgc);
    let g1 = a.mul(&[m, g, r, s]);
    assert_eq!(
        eqs.gravity.data(),
        vec![g0, g1],
        "g = [-m g cos th, m g r sin th]"
    );
    assert_eq!(eqs.phi_q.data(), vec![one, zero]);
    assert_eq!(eqs.gamma.data(), vec![zero]);
    assert_eq!(eqs.phi_t.data(), vec![zero]);
    oracle_check(&mut model, &eqs, &[("m", 1.3), ("g", 9.81), ("l", 0.7)]);
}

/// A point mass on a circle in Cartesian coordinates: T = 1/2 m (x'^2 + y'^2), Pi = m g y,
/// Phi = x^2 + y^2 - l^2.
#[test]
fn cartesian_particle_closed_form() {
    let mut a = Arena::new();
    let (m, g, l) = (param(&mut a, "m"), param(&mut a, "g"), param(&mut a, "l"));
    let [x, xd, xdd] = a.coordinate("x");
    let [y, yd, ydd] = a.coordinate("y");
    let (xd2, yd2) = (a.powi(xd, 2).unwrap(), a.powi(yd, 2).unwrap());
    let v2 = a.add2(xd2, yd2);
    let half = a.rational(1, 2).unwrap();
    let kinetic = a.mul(&[half, m, v2]);
    let potential = a.mul(&[m, g, y]);
    let (x2, y2, l2) = (
        a.powi(x, 2).unwrap(),
        a.powi(y, 2).unwrap(),
        a.powi(l, 2).unwrap(),
    );
    let r2 = a.add2(x2, y2);
    let phi = a.sub(r2, l2);
    let mut model = bare_model(
        a,
        &[("x", [x, xd, xdd]), ("y", [y, yd, ydd])],
        kinetic,
        potential,
        vec![phi],
    );
    let eqs = derive(&mut model).unwrap();
    let a = &mut model.arena;
    let (zero, two) = (a.int(0), a.int(2));
    assert_eq!(eqs.mass.data(), vec![m, zero, zero, m]);
    assert!(
        eqs.coriolis_forces.is_zero(a)
            && eqs.coriolis_matrix.as_ref().is_some_and(|c| c.is_zero(a))
    );
    let mg = a.mul2(m, g);
    assert_eq!(eqs.gravity.data(), vec![zero, mg]);
    let (tx, ty) = (a.mul2(two, x), a.mul2(two, y));
    assert_eq!(eqs.phi_q.data(), vec![tx, ty]);
    let v2x2 = a.mul2(two, v2);
    assert_eq!(
        eqs.gamma.data(),
        vec![a.neg(v2x2)],
        "gamma = -2 (x'^2 + y'^2)"
    );
    oracle_check(&mut model, &eqs, &[("m", 0.8), ("g", 9.81), ("l", 1.1)]);
}

/// The seed crank-slider, q = [phi, beta, gamma, x_c] (seed paper Section II,
/// with a1 = l1/2 and g derived from Pi).
fn crank_slider() -> Model {
    let mut a = Arena::new();
    let p: Vec<Id> = [
        "h", "l1", "l2", "d", "alpha", "m1", "m2", "m3", "J1", "a1", "g", "tau0", "Omega",
    ]
    .iter()
    .map(|n| param(&mut a, n))
    .collect();
    let [h, l1, l2, d, alpha, m1, m2, m3, j1, a1, g, tau0, omega] = p[..] else {
        unreachable!()
    };
    let coords = ["phi", "beta", "gamma", "x_c"].map(|n| (n, a.coordinate(n)));
    let [phi, beta, gam, xc] = coords.map(|c| c.1[0]);
    let [phid, _, _, xcd] = coords.map(|c| c.1[1]);
    let half = a.rational(1, 2).unwrap();
    // T = 1/2 (J1 + m2/2 l1^2) phi'^2 + 1/2 (m2/2 + m3) x_c'^2
    let l1sq = a.powi(l1, 2).unwrap();
    let m2l1 = a.mul(&[half, m2, l1sq]);
    let i1 = a.add2(j1, m2l1);
    let phid2 = a.powi(phid, 2).unwrap();
    let t1 = a.mul(&[half, i1, phid2]);
    let hm2 = a.mul2(half, m2);
    let i3 = a.add2(hm2, m3);
    let xcd2 = a.powi(xcd, 2).unwrap();
    let t3 = a.mul(&[half, i3, xcd2]);
    let kinetic = a.add2(t1, t3);
    // Pi = m1 g (a1 cos phi + h) + m2/2 g (l1 cos phi + h)
    let cphi = a.cos(phi);
    let a1c = a.mul2(a1, cphi);
    let s1 = a.add2(a1c, h);
    let p1 = a.mul(&[m1, g, s1]);
    let l1c = a.mul2(l1, cphi);
    let s2 = a.add2(l1c, h);
    let p2 = a.mul(&[half, m2, g, s2]);
    let potential = a.add2(p1, p2);
    // constraints
    let (sphi, salpha, calpha) = (a.sin(phi), a.sin(alpha), a.cos(alpha));
    let (sg, cg, sb, cb) = (a.sin(gam), a.cos(gam), a.sin(beta), a.cos(beta));
    let r1 = [a.mul(&[l1, sphi, salpha]), a.mul(&[l2, sg, cb]), a.neg(xc)];
    let e1 = a.add(&r1);
    let u = a.mul(&[l1, sphi, calpha]);
    let r2 = [a.neg(u), a.mul(&[l2, sg, sb]), a.neg(d)];
    let e2 = a.add(&r2);
    let l2cg = a.mul2(l2, cg);
    let r3 = [h, l1c, a.neg(l2cg)];
    let e3 = a.add(&r3);
    let mut model = bare_model(a, &coords, kinetic, potential, vec![e1, e2, e3]);
    let t = model.time;
    let wt = model.arena.mul2(omega, t);
    let swt = model.arena.sin(wt);
    model.forces[0] = model.arena.mul2(tau0, swt);
    model
}

const SEED: [(&str, f64); 13] = [
    ("h", 0.12),
    ("l1", 0.08),
    ("l2", 0.3),
    ("d", 0.1),
    ("alpha", 0.0),
    ("m1", 0.12),
    ("m2", 0.5),
    ("m3", 2.0),
    ("J1", 1e-4),
    ("a1", 0.04),
    ("g", 9.81),
    ("tau0", 0.005),
    ("Omega", std::f64::consts::TAU),
];

#[test]
fn crank_slider_structure_and_gravity_sign() {
    let mut model = crank_slider();
    let eqs = derive(&mut model).unwrap();
    let a = &model.arena;
    // M has zero rows and columns for beta and gamma (the rod is two point masses); only M11
    // and M44.
    for i in 0..4 {
        for j in 0..4 {
            let zero = a.is_zero(eqs.mass.get(i, j));
            assert_eq!(zero, !(i == j && (i == 0 || i == 3)), "M[{i},{j}]");
        }
    }
    assert!(
        eqs.coriolis_forces.is_zero(a)
            && eqs.coriolis_matrix.as_ref().is_some_and(|c| c.is_zero(a)),
        "constant M: no Coriolis terms"
    );
    assert!((1..4).all(|k| a.is_zero(eqs.gravity.data()[k])));
    assert_eq!(eqs.forces.data(), model.forces);
    // g_phi = -(m1 a1 + m2 l1/2) g sin(phi): the paper prints the opposite sign.
    let env_at = |phi: f64| {
        let syms: Vec<_> = SEED
            .iter()
            .map(|(n, v)| (a.lookup(n).unwrap(), *v))
            .chain([(a.lookup("phi").unwrap(), phi)])
            .collect();
        move |s| syms.iter().find(|p| p.0 == s).map(|p| p.1)
    };
    for phi in [0.3, 1.2, 2.5, -0.7] {
        let ours = eval_matrix(a, &eqs.gravity, &env_at(phi)).unwrap()[0];
        let expected = -(0.12 * 0.04 + 0.5 * 0.08 / 2.0) * 9.81 * f64::sin(phi);
        assert!(
            close(ours, expected, 1e-14),
            "g_phi({phi}) = {ours}, expected {expected}"
        );
    }
    let at = eval_matrix(a, &eqs.gravity, &env_at(0.3)).unwrap()[0];
    assert!(
        at < 0.0,
        "g_phi < 0 for phi in (0, pi): gravity pulls the crank back down"
    );
    let mut params = SEED.to_vec();
    params.retain(|p| p.0 != "alpha");
    params.push(("alpha", 0.3)); // a tilted guide exercises the alpha terms
    oracle_check(&mut model, &eqs, &params);
}

/// gamma equals -(d/dt Phi_q) q' along a trajectory, by central finite differences of the
/// evaluated Phi_q (h = 1e-5: truncation ~h^2 = 1e-10 times O(1) third derivatives, rounding
/// ~1e-16/h = 1e-11; tolerance 1e-7).
#[test]
fn crank_slider_gamma_by_finite_differences() {
    let mut model = crank_slider();
    let eqs = derive(&mut model).unwrap();
    let a = &model.arena;
    let traj = |t: f64| -> ([f64; 4], [f64; 4]) {
        let q = [
            0.3 + 2.0 * t,
            0.46 + 0.1 * t.sin(),
            0.84 - 0.2 * t * t,
            0.2 + 0.05 * t,
        ];
        let qd = [2.0, 0.1 * t.cos(), -0.4 * t, 0.05];
        (q, qd)
    };
    let env = |q: [f64; 4], qd: [f64; 4]| {
        let mut syms: Vec<_> = SEED
            .iter()
            .map(|(n, v)| (a.lookup(n).unwrap(), *v))
            .collect();
        for (k, c) in model.coordinates.iter().enumerate() {
            syms.push((a.as_symbol(c.q).unwrap(), q[k]));
            syms.push((a.as_symbol(c.qd).unwrap(), qd[k]));
        }
        move |s| syms.iter().find(|p| p.0 == s).map(|p| p.1)
    };
    for t0 in [0.0, 0.4, 1.3] {
        let h = 1e-5;
        let (qp, qdp) = traj(t0 + h);
        let (qm, qdm) = traj(t0 - h);
        let jp = eval_matrix(a, &eqs.phi_q, &env(qp, qdp)).unwrap();
        let jm = eval_matrix(a, &eqs.phi_q, &env(qm, qdm)).unwrap();
        let (q, qd) = traj(t0);
        let gamma = eval_matrix(a, &eqs.gamma, &env(q, qd)).unwrap();
        for r in 0..3 {
            let fd: f64 = (0..4)
                .map(|j| -(jp[r * 4 + j] - jm[r * 4 + j]) / (2.0 * h) * qd[j])
                .sum();
            assert!(
                close(gamma[r], fd, 1e-7),
                "gamma[{r}] at t = {t0}: {} vs {fd}",
                gamma[r]
            );
        }
    }
}

#[test]
fn crank_slider_christoffel_route_agrees() {
    let mut model = crank_slider();
    let eqs = derive(&mut model).unwrap();
    let chr = christoffel_coriolis_forces(&mut model, &eqs).unwrap();
    assert!(chr.is_zero(&model.arena));
}

/// A driven, rheonomic constraint: Phi = [x - A sin(w t), y - t x^2]: gamma carries the
/// -2 Phi_qt q' and -Phi_tt terms.
#[test]
fn time_dependent_constraints() {
    let mut a = Arena::new();
    let (amp, w) = (param(&mut a, "A"), param(&mut a, "w"));
    let [x, xd, xdd] = a.coordinate("x");
    let [y, yd, ydd] = a.coordinate("y");
    let t = a.symbol("t", SymbolKind::Time);
    let (xd2, yd2) = (a.powi(xd, 2).unwrap(), a.powi(yd, 2).unwrap());
    let kinetic = a.add2(xd2, yd2);
    let potential = a.int(0);
    let wt = a.mul2(w, t);
    let s = a.sin(wt);
    let drive = a.mul2(amp, s);
    let phi1 = a.sub(x, drive);
    let x2 = a.powi(x, 2).unwrap();
    let tx2 = a.mul2(t, x2);
    let phi2 = a.sub(y, tx2);
    let mut model = bare_model(
        a,
        &[("x", [x, xd, xdd]), ("y", [y, yd, ydd])],
        kinetic,
        potential,
        vec![phi1, phi2],
    );
    let eqs = derive(&mut model).unwrap();
    let a = &mut model.arena;
    // gamma_1 = -Phi_tt = -A w^2 sin(w t)
    let w2 = a.powi(w, 2).unwrap();
    let g1 = a.mul(&[amp, w2, s]);
    assert_eq!(eqs.gamma.data()[0], a.neg(g1));
    // gamma_2 = 2 t x'^2 + 4 x x' (from -(-2t) x'^2 and -2 (-2x) x')
    let (two, four) = (a.int(2), a.int(4));
    let terms = [a.mul(&[two, t, xd2]), a.mul(&[four, x, xd])];
    assert_eq!(eqs.gamma.data()[1], a.add(&terms));
    oracle_check(&mut model, &eqs, &[("A", 0.4), ("w", 3.0)]);
}

/// T = 1/2 m ((x' - w y)^2 + (y' + w x)^2): a particle of mass m seen from a frame rotating
/// at the rate w (`x`, `y`: each coordinate and its rate).
fn rotating_frame(a: &mut Arena, m: Id, w: Id, [x, xd]: [Id; 2], [y, yd]: [Id; 2]) -> Id {
    let wy = a.mul2(w, y);
    let wx = a.mul2(w, x);
    let vx = a.sub(xd, wy);
    let vy = a.add2(yd, wx);
    let (vx2, vy2) = (a.powi(vx, 2).unwrap(), a.powi(vy, 2).unwrap());
    let v2 = a.add2(vx2, vy2);
    let half = a.rational(1, 2).unwrap();
    a.mul(&[half, m, v2])
}

/// T with parts linear in q' and a q'-free part (a particle seen from a frame rotating at
/// rate w) and an explicitly time-dependent inertia: coriolis_forces is the full
/// h = d/dt(dT/dq')|_{q''=0} - dT/dq.
#[test]
fn general_kinetic_energy() {
    let mut a = Arena::new();
    let (m, w) = (param(&mut a, "m"), param(&mut a, "w"));
    let [x, xd, xdd] = a.coordinate("x");
    let [y, yd, ydd] = a.coordinate("y");
    let [z, zd, zdd] = a.coordinate("z");
    let t = a.symbol("t", SymbolKind::Time);
    let rot = rotating_frame(&mut a, m, w, [x, xd], [y, yd]);
    let half = a.rational(1, 2).unwrap();
    // + 1/2 (1 + t^2) exp(z) z'^2
    let one = a.int(1);
    let t2 = a.powi(t, 2).unwrap();
    let inertia = a.add2(one, t2);
    let ez = a.func(Func::Exp, z).unwrap();
    let zd2 = a.powi(zd, 2).unwrap();
    let tz = a.mul(&[half, inertia, ez, zd2]);
    let kinetic = a.add2(rot, tz);
    let potential = a.int(0);
    let mut model = bare_model(
        a,
        &[
            ("x", [x, xd, xdd]),
            ("y", [y, yd, ydd]),
            ("z", [z, zd, zdd]),
        ],
        kinetic,
        potential,
        vec![],
    );
    let eqs = derive(&mut model).unwrap();
    let a = &mut model.arena;
    // h_x = -2 m w y' - m w^2 x, h_y = 2 m w x' - m w^2 y
    let env = |vals: [f64; 9]| {
        let names = ["m", "w", "x", "y", "z", "der(x)", "der(y)", "der(z)", "t"];
        let syms: Vec<_> = names
            .iter()
            .zip(vals)
            .map(|(n, v)| (a.lookup(n).unwrap(), v))
            .collect();
        move |s| syms.iter().find(|p: &&(_, f64)| p.0 == s).map(|p| p.1)
    };
    let vals = [1.5, 0.7, 0.3, -0.4, 0.2, 0.9, -1.1, 0.6, 0.8];
    let [mv, wv, xv, yv, zv, xdv, ydv, zdv, tv] = vals;
    let h = eval_matrix(a, &eqs.coriolis_forces, &env(vals)).unwrap();
    assert!(close(h[0], -2.0 * mv * wv * ydv - mv * wv * wv * xv, TOL));
    assert!(close(h[1], 2.0 * mv * wv * xdv - mv * wv * wv * yv, TOL));
    // h_z = d/dt((1 + t^2) e^z z') - 1/2 (1 + t^2) e^z z'^2 at z'' = 0
    let hz = 2.0 * tv * zv.exp() * zdv + 0.5 * (1.0 + tv * tv) * zv.exp() * zdv * zdv;
    assert!(close(h[2], hz, TOL), "{} vs {hz}", h[2]);
    oracle_check(&mut model, &eqs, &[("m", 1.5), ("w", 0.7)]);
}

/// A particle seen from a frame rotating at the constant rate w, without time in T:
/// T = 1/2 m ((x' - w y)^2 + (y' + w x)^2) has parts linear in q' and free of q', and M = m I
/// is constant. The shortcut for quadratic forms (whose C q' comes from dM/dq alone, here
/// zero) must not be taken: h_x = -2 m w y' - m w^2 x and h_y = 2 m w x' - m w^2 y are the
/// Coriolis and centrifugal forces.
#[test]
fn rotating_frame_without_time_is_not_a_quadratic_form() {
    let mut a = Arena::new();
    let (m, w) = (param(&mut a, "m"), param(&mut a, "w"));
    let [x, xd, xdd] = a.coordinate("x");
    let [y, yd, ydd] = a.coordinate("y");
    let kinetic = rotating_frame(&mut a, m, w, [x, xd], [y, yd]);
    let potential = a.int(0);
    let coordinates = [("x", [x, xd, xdd]), ("y", [y, yd, ydd])];
    let mut model = bare_model(a, &coordinates, kinetic, potential, vec![]);
    let eqs = derive(&mut model).unwrap();
    let a = &model.arena;
    let vals = [
        ("m", 1.5),
        ("w", 0.7),
        ("x", 0.3),
        ("y", -0.4),
        ("der(x)", 0.9),
        ("der(y)", -1.1),
    ];
    let env = |s| {
        vals.iter()
            .find(|(n, _)| a.lookup(n) == Some(s))
            .map(|p| p.1)
    };
    let [mv, wv, xv, yv, xdv, ydv] = vals.map(|p| p.1);
    let h = eval_matrix(a, &eqs.coriolis_forces, &env).unwrap();
    assert!(
        close(h[0], -2.0 * mv * wv * ydv - mv * wv * wv * xv, TOL),
        "{h:?}"
    );
    assert!(
        close(h[1], 2.0 * mv * wv * xdv - mv * wv * wv * yv, TOL),
        "{h:?}"
    );
    oracle_check(&mut model, &eqs, &[("m", 1.5), ("w", 0.7)]);
}

#[test]
fn malformed_models_are_typed_errors() {
    let base = polar_pendulum;
    let mut empty = base();
    empty.coordinates.clear();
    empty.forces.clear();
    let error = derive(&mut empty).unwrap_err();
    assert!(
        matches!(&error, Error::Declaration { kind, .. }
            if matches!(**kind, DeclarationError::NoCoordinates { empty_section: false, .. })),
        "{error:?}"
    );
    // A model built by hand has no place in a declaration: no line 0 reported.
    assert_eq!(error.location(), None);
    let mut forces = base();
    forces.forces.pop();
    assert!(matches!(
        derive(&mut forces),
        Err(Error::Derivation(DerivationError::ForceCount { .. }))
    ));
    let mut bad_id = base();
    bad_id.kinetic = Id::new(1_000_000);
    assert!(matches!(
        derive(&mut bad_id),
        Err(Error::Algebra(AlgebraError::InvalidId { .. }))
    ));
    let mut rate_in_pi = base();
    rate_in_pi.potential = rate_in_pi.coordinates[0].qd;
    assert!(matches!(
        derive(&mut rate_in_pi),
        Err(Error::Derivation(
            DerivationError::ForbiddenDependence { .. }
        ))
    ));
    let mut rate_in_phi = base();
    rate_in_phi.constraints[0].expr = rate_in_phi.coordinates[1].qd;
    assert!(matches!(
        derive(&mut rate_in_phi),
        Err(Error::Derivation(
            DerivationError::ForbiddenDependence { .. }
        ))
    ));
    let mut acc_in_t = base();
    acc_in_t.kinetic = acc_in_t.coordinates[1].qdd;
    assert!(matches!(
        derive(&mut acc_in_t),
        Err(Error::Derivation(
            DerivationError::ForbiddenDependence { .. }
        ))
    ));
    let mut not_symbol = base();
    not_symbol.coordinates[0].q = not_symbol.potential;
    assert!(matches!(
        derive(&mut not_symbol),
        Err(Error::Derivation(DerivationError::NotASymbol { .. }))
    ));
}

/// Compares everything derive gives with the num-dual oracle at a few random states.
fn oracle_check(model: &mut Model, eqs: &mechanism_codegen::Equations, params: &[(&str, f64)]) {
    let mut rng = crate::common::Rng(42);
    let n = model.coordinates.len();
    for _ in 0..5 {
        let q: Vec<f64> = (0..n).map(|_| rng.uniform(-1.5, 1.5)).collect();
        let qd: Vec<f64> = (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let st = State {
            q: &q,
            qd: &qd,
            t: rng.uniform(0.0, 2.0),
            params,
        };
        let ours = eval_equations(model, eqs, &st);
        let oracle = oracle_equations(model, &st);
        assert_equations_close(&ours, &oracle, TOL);
    }
}

/// gamma (Khang's Kronecker form, summed over pairs j <= k) equals the other route
/// -(d/dt (Phi_q q' + Phi_t)) at q'' = 0, numerically at random states.
#[test]
fn gamma_equals_minus_convective_derivative_of_velocity_constraint() {
    let mut models = vec![crank_slider()];
    models.push({
        let mut a = Arena::new();
        let w = param(&mut a, "w");
        let [x, xd, xdd] = a.coordinate("x");
        let [y, yd, ydd] = a.coordinate("y");
        let t = a.symbol("t", SymbolKind::Time);
        let xy = a.mul2(x, y);
        let wt = a.mul2(w, t);
        let c = a.cos(wt);
        let e1 = a.mul2(xy, c);
        let sy = a.sin(y);
        let e2 = a.atan2(sy, x);
        let kinetic = a.mul2(xd, xd);
        let zero = a.int(0);
        bare_model(
            a,
            &[("x", [x, xd, xdd]), ("y", [y, yd, ydd])],
            kinetic,
            zero,
            vec![e1, e2],
        )
    });
    let params: Vec<(&str, f64)> = SEED.iter().copied().chain([("w", 1.7)]).collect();
    for mut model in models {
        let eqs = derive(&mut model).unwrap();
        let mut d = mechanism_codegen::Differentiator::new();
        let a = &mut model.arena;
        let mut other = Vec::new();
        for r in 0..eqs.m {
            let mut terms: Vec<Id> = (0..eqs.n)
                .map(|j| a.mul2(eqs.phi_q.get(r, j), model.coordinates[j].qd))
                .collect();
            terms.push(eqs.phi_t.data()[r]);
            let v = a.add(&terms);
            let dv = d.convective_derivative(a, v).unwrap();
            other.push(a.neg(dv));
        }
        let other = Matrix::column(other);
        let mut rng = crate::common::Rng(5);
        for _ in 0..5 {
            let table: Vec<(mechanism_codegen::SymbolId, f64)> = model
                .coordinates
                .iter()
                .flat_map(|c| [c.q, c.qd])
                .chain([model.time])
                .map(|id| (a.as_symbol(id).unwrap(), rng.uniform(0.2, 1.4)))
                .chain(
                    params
                        .iter()
                        .filter_map(|(n, v)| a.lookup(n).map(|s| (s, *v))),
                )
                .collect();
            let env = |s| table.iter().find(|e| e.0 == s).map(|e| e.1);
            let g1 = eval_matrix(a, &eqs.gamma, &env).unwrap();
            let g2 = eval_matrix(a, &other, &env).unwrap();
            for (x, y) in g1.iter().zip(&g2) {
                assert!(
                    close(*x, *y, TOL),
                    "gamma {x} vs -d/dt(Phi_q q' + Phi_t) {y}"
                );
            }
        }
    }
}
