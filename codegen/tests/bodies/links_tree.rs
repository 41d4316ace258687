//! Links: the recursive route (composite bodies, Newton-Euler) against Khang's route over
//! the same declaration's T and Pi, and against closed forms.

use mechanism_codegen::{Equations, Model, Route, SymbolId, derive_with, eval, parse_model_str};

/// A spatial tree with every feature of a link: offsets and rpy (exact multiples of pi/2
/// and general angles), a general revolute axis, a negative elementary axis, a prismatic
/// joint, a fixed link carrying mass below a moving one, inertial rpy, and a branch.
const TREE: &str = "
    pub struct Tree;
    parameters { g = 9.81; }
    gravity = [0, 0, -g];
    link base { xyz = [0.1, 0.2, 0.3]; rpy = [0.1, 0.2, 0.3]; mass = 2.0; com = [0.01, 0.02, 0.05];
                inertia = diag(0.01, 0.01, 0.01); }
    link l1 {
        parent = base; joint = revolute(q1, [0, 0, 1]); xyz = [0, 0, 0.333];
        mass = 4.97; com = [0.0039, 0.0021, -0.0476];
        inertia = [[0.7034, -0.0001, 0.0068], [-0.0001, 0.7066, 0.0192], [0.0068, 0.0192, 0.0091]];
    }
    link l2 {
        parent = l1; joint = revolute(q2, [0, 0, -1]); rpy = [-pi/2, 0, 0];
        mass = 0.65; com = [-0.0031, -0.0287, 0.0035]; com_rpy = [0.3, -0.2, 0.1];
        inertia = [[0.03, -0.004, 0.003], [-0.004, 0.028, 0.0007], [0.003, 0.0007, 0.0258]];
    }
    link l3 {
        parent = l2; joint = revolute(q3, [0.6, 0, 0.8]); xyz = [0, -0.316, 0]; rpy = [0.4, 0.1, -0.7];
        mass = 3.23; com = [0.0275, 0.0392, -0.0664];
        inertia = [[0.0371, -0.0048, -0.0013], [-0.0048, 0.0361, -0.0028], [-0.0013, -0.0028, 0.0308]];
    }
    link tool {
        parent = l3; joint = fixed; xyz = [0.1, 0, 0.05]; rpy = [0, pi/2, 0];
        mass = 0.7; com = [0, 0.01, 0.02];
        inertia = [[0.001, 0, 0], [0, 0.0025, 0], [0, 0, 0.0017]];
    }
    link slider {
        parent = tool; joint = prismatic(d4, [0, 1, 0]); xyz = [0, 0, 0.1]; rpy = [0.2, 0, 0];
        mass = 0.4; com = [0.01, 0.02, -0.03];
        inertia = [[0.0005, 0.0001, 0], [0.0001, 0.0007, 0], [0, 0, 0.0004]];
    }
    link branch {
        parent = l1; joint = revolute(q5, [1, 0, 0]); xyz = [0.1, 0.05, 0];
        mass = 1.1; com = [0, 0.2, 0];
        inertia = [[0.01, 0, 0], [0, 0.002, 0], [0, 0, 0.01]];
    }
";

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

#[test]
fn recursive_route_equals_khang_route_on_a_spatial_tree() {
    let mut tree = parse_model_str(TREE).unwrap();
    let mut lagrange = parse_model_str(TREE).unwrap();
    assert!(tree.kinetic_from_links && tree.potential_from_links);
    assert_eq!(tree.coordinates.len(), 5);
    // An open tree needs no `independent`: every coordinate is independent.
    assert_eq!(tree.independent.len(), 5);
    let rec = derive_with(&mut tree, Route::Auto).unwrap();
    let kh = derive_with(&mut lagrange, Route::Lagrange).unwrap();
    for k in 0..12 {
        let st = state(&tree, k);
        let st2 = state(&lagrange, k);
        let (a, b) = (values(&tree, &rec, &st), values(&lagrange, &kh, &st2));
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

/// The library's link declarations (the Panda imported from its URDF, the five-bar leg
/// closed by constraints): the recursive route equals Khang's on each.
#[test]
fn recursive_route_equals_khang_route_on_the_library_robots() {
    for text in [
        include_str!("../../../mechanisms/panda.mech"),
        include_str!("../../../mechanisms/five_bar.mech"),
    ] {
        let mut tree = parse_model_str(text).unwrap();
        let mut lagrange = parse_model_str(text).unwrap();
        assert!(tree.kinetic_from_links && tree.potential_from_links);
        let rec = derive_with(&mut tree, Route::Auto).unwrap();
        let kh = derive_with(&mut lagrange, Route::Lagrange).unwrap();
        for k in 0..6 {
            let (a, b) = (
                values(&tree, &rec, &state(&tree, k)),
                values(&lagrange, &kh, &state(&lagrange, k)),
            );
            let scale = |v: &[f64]| v.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            assert_close("M", &a.mass, &b.mass, scale(&b.mass));
            assert_close("C q'", &a.coriolis, &b.coriolis, scale(&b.coriolis));
            assert_close("g", &a.gravity, &b.gravity, scale(&b.gravity));
            assert_close("tau", &a.inverse, &b.inverse, scale(&b.inverse));
            assert_close(
                "Pi",
                &[a.potential],
                &[b.potential],
                b.potential.abs().max(1.0),
            );
        }
    }
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
