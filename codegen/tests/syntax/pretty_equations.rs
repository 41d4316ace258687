//! The derived equations as text: sections in order, one line per non-zero entry, and every
//! printed entry reads back to the entry itself.

use mechanism_codegen::internals::matrix_to_text;
use mechanism_codegen::{
    Arena, Matrix, SymbolKind, derive, equations_text, parse_expr, parse_model_str,
};

#[test]
fn seed_equations_text_has_every_section_in_order() {
    let mut m = parse_model_str(crate::parse_support::SEED).unwrap();
    let eqs = derive(&mut m).unwrap();
    let text = equations_text(&m, &eqs);
    assert!(
        text.starts_with("SpatialCrankSlider: Lagrange equations with multipliers\n"),
        "{text}"
    );
    assert!(
        text.contains("q = [phi, beta, gamma, x_c]  (n = 4 coordinates, m = 3 constraint rows)"),
        "{text}"
    );
    let headers = [
        "M = d2T/dq'dq'",
        "C = (dM/dq)(I_n kron q')",
        "C q'",
        "g = dPi/dq",
        "tau,",
        "Phi, the constraints",
        "Phi_q = dPhi/dq",
        "Phi_t = dPhi/dt",
        "gamma = -(dPhi_q/dq)",
        "T, the kinetic energy",
        "Pi, the potential energy",
    ];
    let mut from = 0;
    for h in headers {
        let at = text[from..]
            .find(&format!("\n{h}"))
            .unwrap_or_else(|| panic!("section {h:?} missing or out of order"));
        from += at + 1;
    }
    // The mass matrix of the seed has exactly two non-zero entries (the connecting
    // rod is lumped into two point masses, so M has zero rows for beta and gamma).
    assert!(
        text.contains("  M[1,1] = J1 + m2*l1^2/2\n  M[4,4] = m2/2 + m3\n  (all other entries 0)\n"),
        "{text}"
    );
    // dPi/dphi = -(m1 a1 + m2 l1/2) g sin(phi), derived; the seed paper prints the opposite sign.
    assert!(
        text.contains("  g[1] = -m1*a1*g*sin(phi) - l1*m2*g*sin(phi)/2\n"),
        "{text}"
    );
    assert!(text.contains("  tau[1] = tau0*sin(Omega*t)\n"), "{text}");
    assert!(text.contains("  Phi_q[1,4] = -1\n"), "{text}");
}

#[test]
fn every_printed_entry_reads_back_to_the_entry() {
    let mut m = parse_model_str(crate::parse_support::SEED).unwrap();
    let eqs = derive(&mut m).unwrap();
    let text = equations_text(&m, &eqs);
    let mut arena = m.arena.clone();
    let matrices: [(&str, &Matrix); 9] = [
        ("M", &eqs.mass),
        ("C", eqs.coriolis_matrix.as_ref().expect("the seed's C")),
        ("Cq'", &eqs.coriolis_forces),
        ("g", &eqs.gravity),
        ("tau", &eqs.forces),
        ("Phi", &eqs.phi),
        ("Phi_q", &eqs.phi_q),
        ("Phi_t", &eqs.phi_t),
        ("gamma", &eqs.gamma),
    ];
    let mut checked = 0;
    for line in text.lines() {
        let Some((lhs, rhs)) = line.trim().split_once(" = ") else {
            continue;
        };
        let Some((name, index)) = lhs.split_once('[') else {
            continue;
        };
        let Some((_, mat)) = matrices.iter().find(|(n, _)| *n == name) else {
            continue;
        };
        let idx: Vec<usize> = index
            .trim_end_matches(']')
            .split(',')
            .map(|s| s.parse::<usize>().unwrap() - 1)
            .collect();
        let (i, j) = if idx.len() == 1 {
            (idx[0], 0)
        } else {
            (idx[0], idx[1])
        };
        let e = parse_expr(&mut arena, rhs).unwrap_or_else(|err| panic!("{line}: {err}"));
        assert_eq!(e, mat.get(i, j), "{line}");
        checked += 1;
    }
    // Non-zero entries of the seed: M 2, g 1, tau 1, Phi 3, Phi_q 9, gamma 3 (C, C q' and
    // Phi_t vanish).
    assert_eq!(checked, 19);
}

fn arena() -> (Arena, [mechanism_codegen::Id; 3]) {
    let mut a = Arena::new();
    let s = ["x", "y", "z"].map(|n| a.symbol(n, SymbolKind::Free));
    (a, s)
}

#[test]
fn matrix_text_layout() {
    let (mut a, [x, y, _]) = arena();
    let z = a.int(0);
    let xy = a.mul2(x, y);
    let m = Matrix::new(2, 3, vec![z, xy, z, z, z, x]).unwrap();
    assert_eq!(
        matrix_to_text(&a, "A", &m),
        "A[1,2] = x*y\nA[2,3] = x\n(all other entries 0)\n"
    );
    let v = Matrix::column(vec![x, y]);
    assert_eq!(matrix_to_text(&a, "v", &v), "v[1] = x\nv[2] = y\n");
    let zeros = Matrix::zeros(&mut a, 2, 2);
    assert_eq!(matrix_to_text(&a, "Z", &zeros), "(all entries 0)\n");
    let empty = Matrix::new(0, 4, vec![]).unwrap();
    assert_eq!(matrix_to_text(&a, "E", &empty), "(empty: 0 x 4)\n");
}

#[test]
fn printing_never_panics_on_a_foreign_id() {
    let (a, _) = arena();
    let bad = mechanism_codegen::Id::new(10_000);
    assert_eq!(mechanism_codegen::to_text(&a, bad), "<invalid id 10000>");
    let m = Matrix::column(vec![bad]);
    assert!(matrix_to_text(&a, "m", &m).contains("<invalid id 10000>"));
}
