//! The RSSR declared with bodies and joints (`spatial_four_bar_bodies.mech`) against the
//! energy-declared one (`spatial_four_bar.mech`): M, C q', g, Phi, Phi_q and gamma agree at
//! random states.
//!
//! Tolerance 1e-12 absolute: the entries are O(0.01..10) values of the same smooth functions
//! computed with different groupings (a few dozen roundings each, ~1e-15 apart); a wrong term
//! (a missing inertia, a wrong lever arm) is off by at least m l^2 ~ 1e-3.

use mechanism_codegen::{Equations, Model, SymbolId, derive, eval_matrix, parse_model_str};

const TOL: f64 = 1e-12;

fn load(text: &str) -> (Model, Equations) {
    let mut m = parse_model_str(text).expect("parses");
    let e = derive(&mut m).expect("derives");
    (m, e)
}

/// A deterministic pseudo-random stream in [-1, 1) (xorshift64*).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Values by symbol name: coordinates and rates from `state`, parameters at their defaults.
fn env<'a>(model: &'a Model, state: &'a [(String, f64)]) -> impl Fn(SymbolId) -> Option<f64> + 'a {
    move |s| {
        let name = &model.arena.symbol_info(s).name;
        if let Some(p) = model.parameters.iter().find(|p| &p.name == name) {
            return Some(p.default);
        }
        state.iter().find(|v| &v.0 == name).map(|v| v.1)
    }
}

fn parts(e: &Equations) -> [(&'static str, &mechanism_codegen::Matrix); 6] {
    [
        ("M", &e.mass),
        ("Cq'", &e.coriolis_forces),
        ("g", &e.gravity),
        ("Phi", &e.phi),
        ("Phi_q", &e.phi_q),
        ("gamma", &e.gamma),
    ]
}

#[test]
fn body_declared_rssr_matches_energy_declared() {
    let (em, ee) = load(include_str!("../../../mechanisms/spatial_four_bar.mech"));
    let (bm, be) = load(include_str!(
        "../../../mechanisms/spatial_four_bar_bodies.mech"
    ));
    assert_eq!((be.n, be.m), (4, 3));
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..25 {
        let mut state = Vec::new();
        for c in &em.coordinates {
            state.push((c.name.clone(), 3.0 * rng.next()));
            state.push((format!("der({})", c.name), 5.0 * rng.next()));
        }
        state.push(("t".to_string(), rng.next()));
        let (env_e, env_b) = (env(&em, &state), env(&bm, &state));
        for ((name, a), (_, b)) in parts(&ee).into_iter().zip(parts(&be)) {
            let va = eval_matrix(&em.arena, a, &env_e).expect("evaluates");
            let vb = eval_matrix(&bm.arena, b, &env_b).expect("evaluates");
            assert_eq!(va.len(), vb.len(), "{name} shape");
            for (k, (x, y)) in va.iter().zip(&vb).enumerate() {
                assert!(
                    (x - y).abs() <= TOL,
                    "{name}[{k}]: energy-declared {x}, body-declared {y} at {state:?}"
                );
            }
        }
        // The energies themselves agree too (T and Pi, not only their derivatives).
        for (a, b) in [(ee.kinetic, be.kinetic), (ee.potential, be.potential)] {
            let va = mechanism_codegen::eval(&em.arena, a, &env_e).expect("evaluates");
            let vb = mechanism_codegen::eval(&bm.arena, b, &env_b).expect("evaluates");
            assert!((va - vb).abs() <= TOL, "energy {va} vs {vb}");
        }
    }
}

/// The crank's mass enters through its centre and its inertia about the centre: removing
/// the inertia changes M_phi,phi by exactly m1 l1^2/12 (the test would not notice a missing
/// rotational term otherwise).
#[test]
fn crank_inertia_contributes_its_share() {
    let full = include_str!("../../../mechanisms/spatial_four_bar_bodies.mech");
    let bare = full.replace("inertia = diag(0, m1*l1^2/12, m1*l1^2/12);", "");
    assert_ne!(full, bare);
    let (fm, fe) = load(full);
    let (bm, be) = load(&bare);
    let state = vec![
        ("phi".to_string(), 0.3),
        ("beta".to_string(), 1.2),
        ("gamma".to_string(), 1.1),
        ("psi".to_string(), -1.4),
    ];
    let a = eval_matrix(&fm.arena, &fe.mass, &env(&fm, &state)).expect("evaluates");
    let b = eval_matrix(&bm.arena, &be.mass, &env(&bm, &state)).expect("evaluates");
    let (m1, l1) = (0.5, 0.1);
    assert!((a[0] - b[0] - m1 * l1 * l1 / 12.0).abs() < 1e-15);
    for k in 1..16 {
        assert_eq!(a[k], b[k], "entry {k} must not depend on the crank inertia");
    }
}
