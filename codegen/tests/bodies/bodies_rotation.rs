//! The body angular velocity and the body energies against their definitions:
//! [w]x = R^T R' (with R' = sum_k dR/dq_k q_k' + dR/dt, Theorem 1), T = 1/2 m v.v + 1/2 w.I w,
//! and the damper force -c (d/dt |d|) d/|d| mapped through the Jacobian.
//!
//! Tolerance 1e-12: both sides are O(1) values of the same smooth functions evaluated with
//! different groupings (~1e-15 apart); a wrong factor order or a world/body mix-up is O(1).

use mechanism_codegen::internals::{
    Axis, Body, BodySystem, Damper, Orientation, RotationFactor, body_terms, elementary_rotation,
};
use mechanism_codegen::{
    Arena, Differentiator, Matrix, SymbolId, SymbolKind, eval, eval_matrix, parse_model_str,
};

const TOL: f64 = 1e-12;

fn values(a: &Arena, state: &[(&str, f64)]) -> impl Fn(SymbolId) -> Option<f64> + use<> {
    let names: Vec<(String, f64)> = state.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    let table: Vec<(SymbolId, f64)> = names
        .iter()
        .filter_map(|(n, v)| a.lookup(n).map(|s| (s, *v)))
        .collect();
    move |s| table.iter().find(|e| e.0 == s).map(|e| e.1)
}

/// R = rot_z(a) F(b) rot_x(a c) rot_y(Omega t) with F an explicit rot_y(b) matrix: J_w q' + w_t
/// equals vee(R^T R') computed from the entries of R and their partial derivatives.
#[test]
fn angular_velocity_is_vee_of_rt_rdot() {
    let mut a = Arena::new();
    let [qa, _, _] = a.coordinate("a");
    let [qb, _, _] = a.coordinate("b");
    let [qc, _, _] = a.coordinate("c");
    let omega = a.symbol("Omega", SymbolKind::Parameter);
    let t = a.symbol("t", SymbolKind::Time);
    let q: Vec<SymbolId> = ["a", "b", "c"]
        .iter()
        .map(|n| a.lookup(n).unwrap())
        .collect();
    let ts = a.lookup("t").unwrap();
    let explicit = elementary_rotation(&mut a, Axis::Y, qb);
    let ac = a.mul2(qa, qc);
    let ot = a.mul2(omega, t);
    let o = Orientation {
        factors: vec![
            RotationFactor::Elementary(Axis::Z, qa),
            RotationFactor::Explicit(explicit),
            RotationFactor::Elementary(Axis::X, ac),
            RotationFactor::Elementary(Axis::Y, ot),
        ],
    };
    let mut d = Differentiator::new();
    let (jw, wt) = o.angular_jacobian(&mut a, &mut d, &q, Some(ts)).unwrap();
    let r = o.matrix(&mut a).unwrap();
    // dR/dq_k and dR/dt, entrywise.
    let mut partials: Vec<Matrix> = Vec::new();
    for &s in q.iter().chain([&ts]) {
        let m = Matrix::from_fn(r.rows(), r.cols(), |i, j| {
            d.diff(&mut a, r.get(i, j), s).unwrap()
        });
        partials.push(m);
    }
    let state = [
        ("a", 0.7),
        ("b", -0.4),
        ("c", 1.3),
        ("Omega", 2.5),
        ("t", 0.37),
    ];
    let rates = [0.9, -1.7, 0.45];
    let env = values(&a, &state);
    let rv = eval_matrix(&a, &r, &env).unwrap();
    let mut rdot = [0.0; 9];
    for (k, p) in partials.iter().enumerate() {
        let pv = eval_matrix(&a, p, &env).unwrap();
        let rate = rates.get(k).copied().unwrap_or(1.0); // dt/dt = 1
        for (x, y) in rdot.iter_mut().zip(&pv) {
            *x += y * rate;
        }
    }
    // S = R^T R'.
    let s = |i: usize, j: usize| (0..3).map(|k| rv[k * 3 + i] * rdot[k * 3 + j]).sum::<f64>();
    let w_def = [s(2, 1), s(0, 2), s(1, 0)];
    // S is skew (R orthogonal): a check on the test itself.
    assert!((s(1, 2) + s(2, 1)).abs() < TOL && (s(0, 0)).abs() < TOL);
    let jv = eval_matrix(&a, &jw, &env).unwrap();
    for i in 0..3 {
        let wt_i = eval(&a, wt[i], &env).unwrap();
        let w = (0..3).map(|k| jv[i * 3 + k] * rates[k]).sum::<f64>() + wt_i;
        assert!(
            (w - w_def[i]).abs() < TOL,
            "w[{i}] = {w}, vee(R^T R') = {}",
            w_def[i]
        );
    }
}

/// A point mass on a moving track, r = (x + v0 t, 0, h), and a body turning with an imposed
/// rate on top of its coordinate (R = rot_z(a + Omega t)): T is not a quadratic form in q';
/// it must equal 1/2 m |v|^2 + 1/2 I_zz (a' + Omega)^2 with the explicit-time parts.
#[test]
fn time_dependent_positions_and_orientations_give_the_full_kinetic_energy() {
    let text = "
        /// Moving frames.
        pub struct Moving;
        parameters { m = 2.0; v0 = 0.3; h = 1.0; Izz = 0.4; Omega = 1.5; }
        coordinates { x = 0.0; a = 0.0; }
        independent { x = 0.0; der(x) = 0.0; a = 0.0; der(a) = 0.0; }
        body cart { mass = m; position = [x + v0*t, 0, h]; }
        body wheel {
            mass = 0;
            position = [0, 0, 0];
            orientation = rot_z(a + Omega*t);
            inertia = diag(1, 1, Izz);
        }
    ";
    let model = parse_model_str(text).unwrap();
    let env = values(
        &model.arena,
        &[
            ("m", 2.0),
            ("v0", 0.3),
            ("h", 1.0),
            ("Izz", 0.4),
            ("Omega", 1.5),
            ("x", 0.2),
            ("a", 0.1),
            ("der(x)", -0.8),
            ("der(a)", 0.6),
            ("t", 0.9),
        ],
    );
    let t = eval(&model.arena, model.kinetic, &env).unwrap();
    let expected = 0.5 * 2.0 * (-0.8_f64 + 0.3).powi(2) + 0.5 * 0.4 * (0.6_f64 + 1.5).powi(2);
    assert!((t - expected).abs() < TOL, "T = {t}, expected {expected}");
}

/// The damper between a moving point P(q) and a fixed Q: tau = J_P^T F with
/// F = -c (d . d')/(d . d) d, d = P - Q, checked against that formula evaluated by hand for a
/// two-link arm's tip.
#[test]
fn damper_force_maps_through_the_jacobian() {
    let mut a = Arena::new();
    let [q1, _, _] = a.coordinate("q1");
    let [q2, _, _] = a.coordinate("q2");
    let c = a.symbol("c", SymbolKind::Parameter);
    let (c1, s1) = (a.cos(q1), a.sin(q1));
    let q12 = a.add2(q1, q2);
    let (c12, s12) = (a.cos(q12), a.sin(q12));
    let px = a.add2(c1, c12);
    let py = a.add2(s1, s12);
    let zero = a.int(0);
    let two = a.int(2);
    let mut model = two_coordinate_model_in(a, "q1", "q2");
    let system = BodySystem {
        dampers: vec![Damper {
            name: "d".into(),
            ends: [[px, py, zero], [two, zero, zero]],
            coefficient: c,
        }],
        bodies: vec![Body {
            name: "tip".into(),
            mass: zero,
            position: [px, py, zero],
            orientation: None,
            inertia: None,
        }],
        ..Default::default()
    };
    let terms = body_terms(&mut model, &system).unwrap();
    let (x1, x2, w1, w2, cv) = (0.4_f64, 0.9_f64, 1.1_f64, -0.7_f64, 0.35_f64);
    let env = values(
        &model.arena,
        &[
            ("q1", x1),
            ("q2", x2),
            ("der(q1)", w1),
            ("der(q2)", w2),
            ("c", cv),
        ],
    );
    // By hand: P = (cos q1 + cos(q1+q2), sin q1 + sin(q1+q2)), J columns, d = P - (2, 0).
    let j1 = [-x1.sin() - (x1 + x2).sin(), x1.cos() + (x1 + x2).cos()];
    let j2 = [-(x1 + x2).sin(), (x1 + x2).cos()];
    let d = [x1.cos() + (x1 + x2).cos() - 2.0, x1.sin() + (x1 + x2).sin()];
    let dd = [j1[0] * w1 + j2[0] * w2, j1[1] * w1 + j2[1] * w2];
    let dot = |u: [f64; 2], v: [f64; 2]| u[0] * v[0] + u[1] * v[1];
    let scale = -cv * dot(d, dd) / dot(d, d);
    let expected = [scale * dot(j1, d), scale * dot(j2, d)];
    for (k, &f) in terms.forces.iter().enumerate() {
        let v = eval(&model.arena, f, &env).unwrap();
        assert!(
            (v - expected[k]).abs() < TOL,
            "tau[{k}] = {v}, by hand {}",
            expected[k]
        );
    }
    // Power: the damper only dissipates, tau . q' = -c (d/dt |d|)^2 <= 0.
    let power: f64 = terms
        .forces
        .iter()
        .zip([w1, w2])
        .map(|(&f, w)| eval(&model.arena, f, &env).unwrap() * w)
        .sum();
    let ldot = dot(d, dd) / dot(d, d).sqrt();
    assert!((power + cv * ldot * ldot).abs() < TOL);
}

/// `derive` differentiates T = 1/2 q'^T M q' + ... twice and gets back the very nodes of the
/// M formed from the Jacobians (hash-consing: no second, swollen copy of M), for a spinning,
/// swinging body in two coordinates.
#[test]
fn derive_recovers_the_jacobian_mass_matrix_node_for_node() {
    let mut model = two_coordinate_model("a", "b");
    let (qa, qb) = (model.coordinates[0].q, model.coordinates[1].q);
    let a = &mut model.arena;
    let l = a.symbol("l", SymbolKind::Parameter);
    let m = a.symbol("m", SymbolKind::Parameter);
    let o = Orientation {
        factors: vec![
            RotationFactor::Elementary(Axis::Z, qa),
            RotationFactor::Elementary(Axis::X, qb),
        ],
    };
    let r = o.matrix(a).unwrap();
    let zero = a.int(0);
    let tip = r
        .mul(a, &Matrix::column(vec![zero, zero, l]))
        .unwrap()
        .data()
        .to_vec();
    let inertia = elementary_rotation(a, Axis::Z, zero); // the identity, as a 3x3 tensor
    let system = BodySystem {
        bodies: vec![Body {
            name: "bob".into(),
            mass: m,
            position: [tip[0], tip[1], tip[2]],
            orientation: Some(o),
            inertia: Some(inertia),
        }],
        ..Default::default()
    };
    let terms = mechanism_codegen::internals::add_body_terms(&mut model, &system).unwrap();
    let eqs = mechanism_codegen::derive(&mut model).unwrap();
    assert_eq!(eqs.mass, terms.mass);
    assert!(!terms.mass.is_zero(&model.arena));
}

/// A model with coordinates `x`, `y` (fresh arena), T = Pi = 0, no constraints.
fn two_coordinate_model(x: &str, y: &str) -> mechanism_codegen::Model {
    let mut a = Arena::new();
    a.coordinate(x);
    a.coordinate(y);
    two_coordinate_model_in(a, x, y)
}

/// A model over `arena` (where `x` and `y` are coordinates), T = Pi = 0, no constraints.
fn two_coordinate_model_in(mut arena: Arena, x: &str, y: &str) -> mechanism_codegen::Model {
    let zero = arena.int(0);
    let time = arena.symbol("t", SymbolKind::Time);
    let coordinates = [x, y]
        .iter()
        .map(|name| {
            let [q, qd, qdd] = arena.coordinate(name);
            mechanism_codegen::Coordinate {
                name: name.to_string(),
                q,
                qd,
                qdd,
                guess: 0.0,
                guess_expr: zero,
                location: Default::default(),
            }
        })
        .collect();
    mechanism_codegen::Model {
        name: "Test".into(),
        doc: vec![],
        public: true,
        arena,
        time,
        parameters: vec![],
        coordinates,
        independent: vec![],
        kinetic: zero,
        kinetic_location: Default::default(),
        potential: zero,
        constraints: vec![],
        vanished_rows: vec![],
        velocity_constraints: vec![],
        forces: vec![zero, zero],
        drawing: Default::default(),
        links: Vec::new(),
        kinetic_from_links: false,
        potential_from_links: false,
        gravity: None,
        rotations: Vec::new(),
        link_bodies: Vec::new(),
    }
}
