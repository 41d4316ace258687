//! The closed planar N-bar chain: the scaling family of the benchmarks.
//!
//! N identical uniform rods (length 1, mass 1, centroidal inertia 1/12), absolute angles
//! th_1..th_N from +x. Rod 1 is pinned at the origin, the tip of rod N at (X, 0), X = N/2:
//! Phi = [sum cos th_i - X, sum sin th_i]. With G_i the midpoint of rod i,
//! x_Gi = sum_{j<i} cos th_j + 1/2 cos th_i (y likewise with sin),
//! T = sum (1/2 |v_Gi|^2 + 1/2 (1/12) th_i'^2), Pi = g sum y_Gi with the parameter g = 9.81
//! (gravity along -y).
//!
//! [`closed_chain_model`] builds the model through the arena API; [`closed_chain_source`]
//! writes the same declaration in the `mechanism!` language, for the parser and the macro.

use crate::algebra::expr::{Arena, Id, SymbolKind};
use crate::error::Location;
use crate::mechanics::model::{
    Constraint, Coordinate, IndependentSpec, Model, Parameter, ParameterRange,
};
use crate::number::Number;

/// The exact constant num/den (den > 0 here).
fn frac(a: &mut Arena, num: i64, den: i64) -> Id {
    a.number(Number::rational(num, den).unwrap_or(Number::int(0)))
}

/// Gravity of the chain's parameter `g` (m/s^2).
const GRAVITY: f64 = 9.81;

/// The guess of the chain's shape: a symmetric arch th_i = a (N + 1 - 2 i)/N, with a in
/// [0, pi] chosen (by bisection) so that sum cos th_i = N/2; sum sin th_i = 0 by symmetry,
/// so the arch satisfies both constraints. Angles in radians, i = 1..N.
pub fn closed_chain_arch(n: usize) -> Vec<f64> {
    let shape = |a: f64| -> Vec<f64> {
        (1..=n)
            .map(|i| a * (n as f64 + 1.0 - 2.0 * i as f64) / n.max(1) as f64)
            .collect()
    };
    let excess = |a: f64| shape(a).iter().map(|t| t.cos()).sum::<f64>() - n as f64 / 2.0;
    let (mut lo, mut hi) = (0.0, std::f64::consts::PI);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if excess(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    shape(0.5 * (lo + hi))
}

/// The coefficients of rod i's midpoint: x_Gi = sum_j c_ij cos th_j with c_ij = 1 for j < i,
/// 1/2 for j = i, 0 beyond (as (numerator, denominator) over 2).
fn midpoint_weight(i: usize, j: usize) -> Option<i64> {
    match j.cmp(&i) {
        std::cmp::Ordering::Less => Some(2),
        std::cmp::Ordering::Equal => Some(1),
        std::cmp::Ordering::Greater => None,
    }
}

/// The closed planar chain of `n` rods as a [`Model`] named `ClosedChain{n}` (see the module
/// documentation), built through the arena API. Coordinates th1..thn with the arch guesses of
/// [`closed_chain_arch`]; the first n - 2 angles are independent, at rest.
pub fn closed_chain_model(n: usize) -> Model {
    let mut a = Arena::new();
    let time = a.symbol("t", SymbolKind::Time);
    let g = a.symbol("g", SymbolKind::Parameter);
    let guess = closed_chain_arch(n);
    let coordinates = chain_coordinates(&mut a, &guess);
    let sin: Vec<Id> = coordinates.iter().map(|c| a.sin(c.q)).collect();
    let cos: Vec<Id> = coordinates.iter().map(|c| a.cos(c.q)).collect();
    let (kinetic, potential) = chain_energies(&mut a, &coordinates, &sin, &cos, g);
    let constraints = chain_constraints(&mut a, &sin, &cos);
    let zero = a.int(0);
    // The guesses as expressions, made last so that the equations' nodes keep their ids.
    let mut coordinates = coordinates;
    for c in &mut coordinates {
        c.guess_expr = a.float(c.guess).unwrap_or(zero);
    }
    let independent = (0..n.saturating_sub(2))
        .map(|k| IndependentSpec {
            coordinate: k,
            position: guess[k],
            velocity: 0.0,
            position_expr: coordinates[k].guess_expr,
            velocity_expr: None,
            location: Location::default(),
        })
        .collect();
    Model {
        name: format!("ClosedChain{n}"),
        doc: vec![format!(
            " Closed planar chain of {n} uniform rods (length 1, mass 1, inertia 1/12), pinned at (0, 0) and ({}, 0).",
            n as f64 / 2.0
        )],
        public: true,
        arena: a,
        time,
        parameters: vec![Parameter {
            name: "g".into(),
            symbol: g,
            default: GRAVITY,
            range: ParameterRange::Any,
            location: Location::default(),
        }],
        coordinates,
        independent,
        kinetic,
        kinetic_location: Location::default(),
        potential,
        constraints,
        vanished_rows: Vec::new(),
        velocity_constraints: Vec::new(),
        forces: vec![zero; n],
        drawing: Default::default(),
        links: Vec::new(),
        kinetic_from_links: false,
        potential_from_links: false,
        gravity: None,
        rotations: Vec::new(),
        link_bodies: Vec::new(),
    }
}

/// The coordinates th1..thn of the chain, with the guesses `guess`.
fn chain_coordinates(a: &mut Arena, guess: &[f64]) -> Vec<Coordinate> {
    let mut coordinates = Vec::with_capacity(guess.len());
    for (i, &theta) in guess.iter().enumerate() {
        let name = format!("th{}", i + 1);
        let [q, qd, qdd] = a.coordinate(&name);
        coordinates.push(Coordinate {
            name,
            q,
            qd,
            qdd,
            guess: theta,
            // Set to the number itself once the equations are built (`closed_chain_model`).
            guess_expr: q,
            location: Location::default(),
        });
    }
    coordinates
}

/// T = sum_i 1/2 |v_i|^2 + 1/24 th_i'^2 (rods of unit mass and length, v_i the midpoint
/// velocity) and Pi = g sum_i y_i (y_i the midpoint height), written term by term.
fn chain_energies(
    a: &mut Arena,
    coordinates: &[Coordinate],
    sin: &[Id],
    cos: &[Id],
    g: Id,
) -> (Id, Id) {
    let half = frac(a, 1, 2);
    let twelfth_half = frac(a, 1, 24);
    let mut kinetic_terms = Vec::new();
    let mut heights = Vec::new();
    for i in 0..coordinates.len() {
        let (mut vx, mut vy, mut y) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..=i {
            let Some(w) = midpoint_weight(i, j) else {
                continue;
            };
            let w = frac(a, w, 2);
            let rate = coordinates[j].qd;
            let mw = a.neg(w);
            vx.push(a.mul(&[mw, sin[j], rate]));
            vy.push(a.mul(&[w, cos[j], rate]));
            y.push(a.mul2(w, sin[j]));
        }
        let (vx, vy) = (a.add(&vx), a.add(&vy));
        let (vx2, vy2) = (a.mul2(vx, vx), a.mul2(vy, vy));
        let v2 = a.add2(vx2, vy2);
        kinetic_terms.push(a.mul2(half, v2));
        let w2 = a.mul2(coordinates[i].qd, coordinates[i].qd);
        kinetic_terms.push(a.mul2(twelfth_half, w2));
        heights.push(a.add(&y));
    }
    let kinetic = a.add(&kinetic_terms);
    let height_sum = a.add(&heights);
    let potential = a.mul2(g, height_sum);
    (kinetic, potential)
}

/// The loop closure: sum_i cos th_i - n/2 = 0 and sum_i sin th_i = 0.
fn chain_constraints(a: &mut Arena, sin: &[Id], cos: &[Id]) -> Vec<Constraint> {
    let x_end = frac(a, -(cos.len() as i64), 2);
    let mut xs = cos.to_vec();
    xs.push(x_end);
    vec![
        Constraint {
            expr: a.add(&xs),
            location: Location::default(),
            joint: "constraint 1".into(),
            component: String::new(),
        },
        Constraint {
            expr: a.add(sin),
            location: Location::default(),
            joint: "constraint 2".into(),
            component: String::new(),
        },
    ]
}

/// The declaration of [`closed_chain_model`] in the `mechanism!` language (macro issue
/// grammar): `pub struct ClosedChain{n}; parameters {..} coordinates {..} independent {..}
/// kinetic = ..; potential = ..; constraints {..}`, with the kinetic energy written out
/// through the midpoint velocities.
pub fn closed_chain_source(n: usize) -> String {
    let guess = closed_chain_arch(n);
    let term = |w: i64, f: &str, j: usize, rate: bool| -> String {
        let coef = if w == 2 {
            String::new()
        } else {
            "1/2*".to_string()
        };
        let rate = if rate {
            format!("*der(th{j})")
        } else {
            String::new()
        };
        format!("{coef}{f}(th{j}){rate}")
    };
    let mut s = String::new();
    s.push_str(&format!(
        "/// Closed planar chain of {n} uniform rods (length 1 m, mass 1 kg, centroidal inertia 1/12 kg m^2),\n\
         /// absolute angles th1..th{n} (rad) from +x; rod 1 pinned at (0, 0), the tip of rod {n} at ({}, 0).\n\
         /// Gravity g along -y. Generated by mechanism_codegen::closed_chain_source({n}).\n",
        n as f64 / 2.0
    ));
    s.push_str(&format!(
        "pub struct ClosedChain{n};\nparameters {{ g = {GRAVITY}; }}\ncoordinates {{"
    ));
    for (i, th) in guess.iter().enumerate() {
        s.push_str(&format!(" th{} = {th:.12};", i + 1));
    }
    s.push_str(" }\nindependent {");
    for (i, th) in guess.iter().enumerate().take(n.saturating_sub(2)) {
        s.push_str(&format!(" th{0} = {th:.12}; der(th{0}) = 0.0;", i + 1));
    }
    s.push_str(" }\nkinetic =");
    let mut heights = Vec::new();
    for i in 1..=n {
        let sum = |f: &str, rate: bool| -> Vec<String> {
            (1..=i)
                .map(|j| term(midpoint_weight(i, j).unwrap_or(0), f, j, rate))
                .collect()
        };
        let vx = sum("sin", true).join(" + ");
        let vy = sum("cos", true).join(" + ");
        let plus = if i == 1 { "" } else { "    +" };
        s.push_str(&format!(
            "{plus} 1/2*((-({vx}))^2 + ({vy})^2) + 1/24*der(th{i})^2\n"
        ));
        heights.push(format!("({})", sum("sin", false).join(" + ")));
    }
    s.push_str(";\n");
    s.push_str(&format!("potential = g*({});\n", heights.join(" + ")));
    let cos: Vec<String> = (1..=n).map(|i| format!("cos(th{i})")).collect();
    let sin: Vec<String> = (1..=n).map(|i| format!("sin(th{i})")).collect();
    s.push_str(&format!(
        "constraints {{\n    {} - {n}/2;\n    {};\n}}\n",
        cos.join(" + "),
        sin.join(" + ")
    ));
    s
}
