//! Links: the recursive route (composite bodies, Newton-Euler) against Khang's route over
//! the same declaration's T and Pi, and against closed forms.

use mechanism_codegen::{Equations, Model, Route, SymbolId, derive_with, eval, parse_model_str};

/// The spatial tree of `link_tree.mech` (every kind of link).
const TREE: &str = include_str!("link_tree.mech");

struct Values {
    mass: Vec<f64>,
    coriolis: Vec<f64>,
    gravity: Vec<f64>,
    inverse: Vec<f64>,
    kinetic: f64,
    potential: f64,
}

fn values(model: &Model, eqs: &Equations, state: &[(SymbolId, f64)]) -> Values {
    let env = |s: SymbolId| {
        state.iter().find(|v| v.0 == s).map(|v| v.1).or_else(|| {
            model
                .parameters
                .iter()
                .find(|p| model.arena.as_symbol(p.symbol) == Some(s))
                .map(|p| p.default)
        })
    };
    let ev = |ids: &[mechanism_codegen::Id]| -> Vec<f64> {
        ids.iter()
            .map(|&i| eval(&model.arena, i, &env).unwrap())
            .collect()
    };
    Values {
        mass: ev(eqs.mass.data()),
        coriolis: ev(eqs.coriolis_forces.data()),
        gravity: ev(eqs.gravity.data()),
        inverse: ev(eqs.inverse_dynamics.data()),
        kinetic: ev(&[eqs.kinetic])[0],
        potential: ev(&[eqs.potential])[0],
    }
}

/// The state at sample k: q, q', q'' spread over several radians and rates.
fn state(model: &Model, k: usize) -> Vec<(SymbolId, f64)> {
    let mut out = Vec::new();
    for (i, c) in model.coordinates.iter().enumerate() {
        let x = (k * 7 + i * 3) as f64;
        let sym = |id| model.arena.as_symbol(id).unwrap();
        out.push((sym(c.q), (0.37 * x).sin() * 2.5));
        out.push((sym(c.qd), (0.61 * x + 1.0).cos() * 1.7));
        out.push((sym(c.qdd), (0.23 * x + 2.0).sin() * 3.1));
    }
    out
}

fn assert_close(what: &str, a: &[f64], b: &[f64], scale: f64) {
    assert_eq!(a.len(), b.len());
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        // Both routes evaluate O(100)-term sums of values below `scale` in f64: a few
        // hundred ulps of the scale bound their difference.
        assert!(
            (x - y).abs() <= 1e-12 * scale,
            "{what}[{i}]: recursive {x} vs Khang {y}"
        );
    }
}

/// Derives `text` by both routes and compares M, C q', g, the inverse dynamics, T and Pi at
/// `states` states.
fn assert_routes_agree(text: &str, states: usize) {
    let mut tree = parse_model_str(text).unwrap();
    let mut lagrange = parse_model_str(text).unwrap();
    // The recursive route is taken for M, C q', g and Pi.
    assert!(tree.kinetic_from_links && tree.potential_from_links);
    let rec = derive_with(&mut tree, Route::Auto).unwrap();
    let kh = derive_with(&mut lagrange, Route::Lagrange).unwrap();
    for k in 0..states {
        let a = values(&tree, &rec, &state(&tree, k));
        let b = values(&lagrange, &kh, &state(&lagrange, k));
        let scale = |v: &[f64]| v.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        assert_close("M", &a.mass, &b.mass, scale(&b.mass));
        assert_close("C q'", &a.coriolis, &b.coriolis, scale(&b.coriolis));
        assert_close("g", &a.gravity, &b.gravity, scale(&b.gravity));
        assert_close("tau", &a.inverse, &b.inverse, scale(&b.inverse));
        assert_close("T", &[a.kinetic], &[b.kinetic], b.kinetic.abs().max(1.0));
        assert_close(
            "Pi",
            &[a.potential],
            &[b.potential],
            b.potential.abs().max(1.0),
        );
    }
}

#[test]
fn recursive_route_equals_khang_route_on_a_spatial_tree() {
    let tree = parse_model_str(TREE).unwrap();
    assert_eq!(tree.coordinates.len(), 5);
    // An open tree needs no `independent`: every coordinate is independent.
    assert_eq!(tree.independent.len(), 5);
    assert_routes_agree(TREE, 12);
}

/// The library's link declarations (the Panda imported from its URDF, the five-bar leg
/// closed by constraints): the recursive route equals Khang's on each.
#[test]
fn recursive_route_equals_khang_route_on_the_library_robots() {
    assert_routes_agree(include_str!("../../../mechanisms/panda.mech"), 6);
    assert_routes_agree(include_str!("../../../mechanisms/five_bar.mech"), 6);
}

#[test]
fn two_link_planar_arm_matches_its_closed_form() {
    // Two uniform rods of mass m_i and length l_i turning about z, gravity along -y.
    let src = "
        pub struct Arm;
        parameters { m1 = 1.3; m2 = 0.8; l1 = 0.7; l2 = 0.5; g = 9.81; }
        gravity = [0, -g, 0];
        link a { joint = revolute(th1, [0, 0, 1]); mass = m1; com = [l1/2, 0, 0];
                 inertia = diag(0, m1*l1^2/12, m1*l1^2/12); }
        link b { parent = a; joint = revolute(th2, [0, 0, 1]); xyz = [l1, 0, 0];
                 mass = m2; com = [l2/2, 0, 0]; inertia = diag(0, m2*l2^2/12, m2*l2^2/12); }
    ";
    let mut model = parse_model_str(src).unwrap();
    let eqs = derive_with(&mut model, Route::Auto).unwrap();
    let (m1, m2, l1, l2, g) = (1.3, 0.8, 0.7, 0.5, 9.81);
    for k in 0..6 {
        let st = state(&model, k);
        let v = values(&model, &eqs, &st);
        let (t2, d1, d2) = (st[3].1, st[1].1, st[4].1);
        let t1 = st[0].1;
        let c2 = t2.cos();
        let m22 = m2 * l2 * l2 / 3.0;
        let m12 = m22 + m2 * l1 * l2 / 2.0 * c2;
        let m11 = m1 * l1 * l1 / 3.0 + m2 * (l1 * l1 + l2 * l2 / 3.0 + l1 * l2 * c2);
        let hh = m2 * l1 * l2 / 2.0 * t2.sin();
        let c = [-hh * (2.0 * d1 * d2 + d2 * d2), hh * d1 * d1];
        let gr = [
            (m1 * l1 / 2.0 + m2 * l1) * g * t1.cos() + m2 * l2 / 2.0 * g * (t1 + t2).cos(),
            m2 * l2 / 2.0 * g * (t1 + t2).cos(),
        ];
        assert_close("M", &v.mass, &[m11, m12, m12, m22], 1.0);
        assert_close("C q'", &v.coriolis, &c, 1.0);
        assert_close("g", &v.gravity, &gr, 10.0);
    }
}

/// A serial chain of `n` links, alternating z and y axes, each offset and with a full
/// inertia: what a real arm looks like to the recursive route.
fn chain(n: usize) -> String {
    let mut s =
        String::from("pub struct Chain;\nparameters { g = 9.81; }\ngravity = [0, 0, -g];\n");
    for k in 0..n {
        let parent = if k == 0 {
            String::new()
        } else {
            format!("parent = l{}; ", k - 1)
        };
        let axis = if k % 2 == 0 { "[0, 0, 1]" } else { "[0, 1, 0]" };
        s.push_str(&format!(
            "link l{k} {{ {parent}joint = revolute(q{k}, {axis}); xyz = [0.1, 0.02, 0.3]; \
             mass = 1.5; com = [0.03, 0.01, 0.12]; \
             inertia = [[0.02, 0.001, 0.002], [0.001, 0.03, 0.003], [0.002, 0.003, 0.025]]; }}\n"
        ));
    }
    s
}

/// Each link adds the same operations to the inverse dynamics and to the bias, and each
/// entry of M the same too (its operations grow with the square of n): every link's
/// velocities, accelerations, forces and composite inertia are named once, so the
/// expressions of a link read its parent's as operands instead of growing with the depth.
/// Counted on chains of 8, 16, 24 and 32 links (the axes repeat every two links): the
/// first differences of the inverse dynamics' and the bias' operations are equal, and so
/// are the second differences of M's.
#[test]
fn each_link_adds_the_same_operations_along_a_chain() {
    let ops = |n: usize| {
        let mut model = parse_model_str(&chain(n)).unwrap();
        let eqs = derive_with(&mut model, Route::Auto).unwrap();
        let count = |m: &mechanism_codegen::Matrix| {
            let p = mechanism_codegen::Program::new(&model.arena, &[m]).unwrap();
            p.op_counts().total() as i64
        };
        [
            count(&eqs.inverse_dynamics),
            count(&eqs.bias),
            count(&eqs.mass),
        ]
    };
    let counts: Vec<[i64; 3]> = [8, 16, 24, 32].into_iter().map(ops).collect();
    eprintln!("inverse dynamics, bias, M: {counts:?}");
    let first = |k: usize, i: usize| counts[i + 1][k] - counts[i][k];
    for k in 0..2 {
        assert_eq!(first(k, 0), first(k, 1), "{counts:?}");
        assert_eq!(first(k, 1), first(k, 2), "{counts:?}");
    }
    assert_eq!(
        first(2, 1) - first(2, 0),
        first(2, 2) - first(2, 1),
        "{counts:?}"
    );
}

/// A chain whose derivation exceeds a size budget says what applies to links: lock joints
/// (or raise the budget), not fewer chained rotations.
#[test]
fn a_budget_met_by_links_names_what_links_can_do() {
    let budget = mechanism_codegen::Budget {
        size: 20_000,
        ..Default::default()
    };
    let mut model = mechanism_codegen::parse_model_str_with(&chain(40), budget).unwrap();
    let e = derive_with(&mut model, Route::Auto).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("these 40 moving links"), "{text}");
    assert!(text.contains("mechanism import --lock JOINT"), "{text}");
    assert!(!text.contains("chained rotations"), "{text}");
    assert!(text.contains("MECHANISM_MAX_SIZE="), "{text}");
}

/// A joint axis written with a parameter stays a unit vector when the parameter changes:
/// for a body of inertia diag(1, 2, 3) (kg m^2, about its origin) turning about
/// n = (a, 0, 1)/sqrt(a^2 + 1), M = n^T I n = (a^2 + 3)/(a^2 + 1): 2 at a = 1, 1.2 at a = 3.
#[test]
fn a_parametric_joint_axis_is_normalised_for_every_value() {
    let src = "
        pub struct Spinner;
        parameters { a = 1.0; }
        link body { joint = revolute(th, [a, 0, 1]); mass = 1.0; inertia = diag(1, 2, 3); }
    ";
    let mut model = parse_model_str(src).unwrap();
    let eqs = derive_with(&mut model, Route::Auto).unwrap();
    let a = model.arena.as_symbol(model.parameters[0].symbol).unwrap();
    for (value, expected) in [(1.0, 2.0), (3.0, 1.2)] {
        let env = |s: SymbolId| if s == a { Some(value) } else { Some(0.4) };
        let m = eval(&model.arena, eqs.mass.get(0, 0), &env).unwrap();
        // A handful of roundings of values near 1.
        assert!((m - expected).abs() < 1e-14, "a = {value}: M = {m}");
    }
}
