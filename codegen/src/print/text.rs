//! Readable, stable text for expressions, matrices and derived equations.
//!
//! The text is the expression language itself: [`crate::parse_expr`] reads it back to the
//! same node, `parse_expr(arena, &to_text(arena, e)) == e`. Layout: positive terms first,
//! then ` - ` and the negative ones; the numeric coefficient first and factors with negative
//! exponents below one fraction bar (`m2*l1^2/2`, `a/(b*c)`); `x^(1/2)` as `sqrt(x)`;
//! floats in Rust's shortest round-trip form (`0.04`, `1e-7`); minimal parentheses.

use crate::algebra::expr::{Arena, Func, Id, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::mechanics::equations::Equations;
use crate::mechanics::model::Model;
use crate::number::Number;
use crate::print::render::{Prec, Rendered, Renderer, Style, concat, elided_note};
use std::borrow::Cow;
use std::fmt::Write;

/// The plain-text spelling.
pub(crate) struct Text;

fn wrap(r: &Rendered, min: Prec) -> Cow<'_, str> {
    if r.prec < min {
        Cow::Owned(concat(&["(", &r.s, ")"]))
    } else {
        Cow::Borrowed(&r.s)
    }
}

/// The parts joined by `*`, each in brackets if it binds looser than a power.
fn join_factors(out: &mut String, parts: &[Cow<'_, Rendered>]) {
    for (k, r) in parts.iter().enumerate() {
        if k > 0 {
            out.push('*');
        }
        out.push_str(&wrap(r, Prec::Power));
    }
}

/// The text length of `parts` with a separator and brackets each, for sizing a buffer.
fn text_len(parts: &[Cow<'_, Rendered>]) -> usize {
    parts.iter().map(|r| r.s.len() + 3).sum()
}

impl Style for Text {
    fn number(&self, n: Number) -> Rendered {
        match n {
            Number::Rational(p, 1) => Rendered::new(p.to_string(), Prec::Atom),
            Number::Rational(p, q) => Rendered::new(format!("{p}/{q}"), Prec::Product),
            // Debug is the shortest form that reads back as the same f64, with a `.` or an
            // exponent, so it lexes as a float literal.
            Number::Float(x) => Rendered::new(format!("{x:?}"), Prec::Atom),
        }
    }

    fn pi(&self) -> Rendered {
        Rendered::new("pi".into(), Prec::Atom)
    }

    fn symbol(&self, name: &str, _kind: SymbolKind) -> Rendered {
        Rendered::new(name.into(), Prec::Atom)
    }

    fn func(&self, f: Func, x: &Rendered) -> Rendered {
        Rendered::new(concat(&[f.name(), "(", &x.s, ")"]), Prec::Atom)
    }

    fn atan2(&self, y: &Rendered, x: &Rendered) -> Rendered {
        Rendered::new(concat(&["atan2(", &y.s, ", ", &x.s, ")"]), Prec::Atom)
    }

    fn sqrt(&self, x: &Rendered) -> Rendered {
        Rendered::new(concat(&["sqrt(", &x.s, ")"]), Prec::Atom)
    }

    fn power(&self, base: &Rendered, exp: &Rendered) -> Rendered {
        // `^` is right-associative: a power in the exponent needs no brackets, one in the
        // base does.
        Rendered::new(
            concat(&[&wrap(base, Prec::Atom), "^", &wrap(exp, Prec::Power)]),
            Prec::Power,
        )
    }

    fn product(&self, num: &[Cow<'_, Rendered>], den: &[Cow<'_, Rendered>]) -> Rendered {
        if let ([only], []) = (num, den) {
            return only.as_ref().clone();
        }
        let mut s = String::with_capacity(text_len(num) + text_len(den) + 4);
        if num.is_empty() {
            s.push('1');
        } else {
            join_factors(&mut s, num);
        }
        match den {
            [] => {}
            // `x/(2*(a + b))` would read back with the 2 distributed over the sum (the
            // arena's canonical 2*a + 2*b); `x/2/(a + b)` reads back as written.
            [q, sum] if q.s.bytes().all(|b| b.is_ascii_digit()) && sum.prec == Prec::Sum => {
                for part in ["/", &q.s, "/(", &sum.s, ")"] {
                    s.push_str(part);
                }
            }
            [one] => {
                s.push('/');
                s.push_str(&wrap(one, Prec::Power));
            }
            _ => {
                s.push_str("/(");
                join_factors(&mut s, den);
                s.push(')');
            }
        }
        Rendered::new(s, Prec::Product)
    }

    fn paren(&self, s: &str) -> String {
        concat(&["(", s, ")"])
    }
}

/// The expression `id` as text in the expression language, which [`crate::parse_expr`] reads
/// back to the same node of the same arena.
///
/// # Example
/// ```
/// use mechanism_codegen::{parse_expr, to_text, Arena, SymbolKind};
/// let mut a = Arena::new();
/// for s in ["m2", "l1", "phi"] {
///     a.symbol(s, SymbolKind::Parameter);
/// }
/// let e = parse_expr(&mut a, "1/2*m2*l1^2*cos(phi)^2 - 0.04/m2").unwrap();
/// assert_eq!(to_text(&a, e), "m2*l1^2*cos(phi)^2/2 - 0.04/m2");
/// let text = to_text(&a, e);
/// assert_eq!(parse_expr(&mut a, &text).unwrap(), e);
/// ```
pub fn to_text(arena: &Arena, id: Id) -> String {
    Renderer::new(arena, Text).render(id).s.clone()
}

/// Writes the entry name `name[i,j]` (1-based), or `name[i]` for a column vector.
fn entry_name(out: &mut String, name: &str, m: &Matrix, i: usize, j: usize) {
    out.push_str(name);
    out.push('[');
    out.push_str(&(i + 1).to_string());
    if m.cols != 1 {
        out.push(',');
        out.push_str(&(j + 1).to_string());
    }
    out.push(']');
}

/// The non-zero entries of `m`, one per line as `name[i,j] = entry` (1-based; `name[i]` for a
/// column vector), followed by `(all other entries 0)` when some are zero, or the single
/// line `(all entries 0)`.
///
/// # Example
/// ```
/// use mechanism_codegen::{Arena, Matrix, SymbolKind};
/// use mechanism_codegen::internals::matrix_to_text;
/// let mut a = Arena::new();
/// let x = a.symbol("x", SymbolKind::Free);
/// let z = a.int(0);
/// let m = Matrix::new(2, 2, vec![x, z, z, x])?;
/// assert_eq!(matrix_to_text(&a, "M", &m), "M[1,1] = x\nM[2,2] = x\n(all other entries 0)\n");
/// # Ok::<(), mechanism_codegen::Error>(())
/// ```
pub fn matrix_to_text(arena: &Arena, name: &str, m: &Matrix) -> String {
    let mut out = String::new();
    matrix_lines(&mut out, &mut Renderer::new(arena, Text), name, m, "");
    out
}

/// Writes [`matrix_to_text`]'s lines to `out`, each indented by `indent`.
fn matrix_lines(
    out: &mut String,
    r: &mut Renderer<'_, Text>,
    name: &str,
    m: &Matrix,
    indent: &str,
) {
    let start = out.len();
    let mut zeros = 0;
    for i in 0..m.rows {
        for j in 0..m.cols {
            let Some(&e) = m.data.get(i * m.cols + j) else {
                continue;
            };
            if r.is_zero(e) {
                zeros += 1;
                continue;
            }
            out.push_str(indent);
            entry_name(out, name, m, i, j);
            out.push_str(" = ");
            out.push_str(&r.render(e).s);
            out.push('\n');
        }
    }
    // Writing to a String cannot fail.
    if m.rows * m.cols == 0 {
        let _ = writeln!(out, "{indent}(empty: {} x {})", m.rows, m.cols);
    } else if out.len() == start {
        let _ = writeln!(out, "{indent}(all entries 0)");
    } else if zeros > 0 {
        let _ = writeln!(out, "{indent}(all other entries 0)");
    }
}

/// The derived equations of `model` as readable text: a header with q, then the sections M, C
/// (Khang), C q', g, tau, Phi, Phi_q, Phi_t, gamma, T and Pi, each with its definition and its
/// non-zero entries (for links, their shared subexpressions first, by name). This is the text
/// the snapshot tests pin and that `mechanism equations NAME` shows.
pub fn equations_text(model: &Model, eqs: &Equations) -> String {
    let mut r = Renderer::for_equations(&model.arena, Text);
    let mut out = header(model, eqs);
    if model.kinetic_from_links {
        out.push_str(&shared_subexpressions(&mut r, &model.arena, eqs));
    }
    for (name, title, mat) in sections(model, eqs) {
        let Some(mat) = mat else {
            // Khang's C of a tree: its entries are the derivatives of M's, written out they
            // repeat M's recursion per coordinate. The generated `coriolis_matrix` computes
            // them.
            out.push_str(&format!("\n{title} ({n} x {n}):\n", n = eqs.n));
            out.push_str("  (Khang's C of the M above: not written out for links)\n");
            continue;
        };
        out.push_str(&format!("\n{title} ({} x {}):\n", mat.rows, mat.cols));
        matrix_lines(&mut out, &mut r, name, mat, "  ");
        if name == "Phi" && !model.vanished_rows.is_empty() {
            let _ = writeln!(
                out,
                "  (left out, identically zero: {})",
                model.vanished_rows.join("; ")
            );
        }
    }
    let _ = writeln!(
        out,
        "\nT, the kinetic energy:\n  T = {}",
        r.render(eqs.kinetic).s
    );
    let _ = writeln!(
        out,
        "\nPi, the potential energy:\n  Pi = {}",
        r.render(eqs.potential).s
    );
    if r.elided {
        out.push_str(&format!("\nnote: {}\n", elided_note()));
    }
    out
}

/// The first lines of [`equations_text`]: the mechanism, the equations, q with n and m.
fn header(model: &Model, eqs: &Equations) -> String {
    let names: Vec<&str> = model.coordinates.iter().map(|c| c.name.as_str()).collect();
    let (n, m) = (eqs.n, eqs.m);
    let mut out = String::new();
    out.push_str(&format!(
        "{}: Lagrange equations with multipliers\n",
        model.name
    ));
    out.push_str(
        "  M(q) q'' + C(q, q') q' + g(q) + Phi_q(q, t)^T lambda = tau(t, q, q'),  Phi(q, t) = 0\n",
    );
    out.push_str(&format!(
        "q = [{}]  (n = {n} coordinates, m = {m} constraint rows); q' = der(q)\n",
        names.join(", ")
    ));
    out
}

/// The recursive route builds M and C q' link by link: each link's velocities,
/// accelerations and forces are shared by every entry below it, so they are printed once,
/// as w1, w2, ..., and named in `r` so that the entries read them.
fn shared_subexpressions(r: &mut Renderer<'_, Text>, arena: &Arena, eqs: &Equations) -> String {
    let mut roots: Vec<Id> = Vec::new();
    for mat in [&eqs.mass, &eqs.coriolis_forces, &eqs.gravity]
        .into_iter()
        .chain(&eqs.coriolis_matrix)
    {
        roots.extend_from_slice(mat.data());
    }
    roots.push(eqs.kinetic);
    roots.push(eqs.potential);
    let shared = crate::print::render::shared_nodes(arena, &roots);
    let mut out = String::new();
    if !shared.is_empty() {
        out.push_str(&format!(
            "\nShared subexpressions ({}, each used more than once below):\n",
            shared.len()
        ));
        for (k, id) in shared.into_iter().enumerate() {
            let _ = writeln!(out, "  w{} = {}", k + 1, r.render(id).s);
            r.name(id, format!("w{}", k + 1));
        }
    }
    out
}

/// The matrix sections of [`equations_text`]: (name, title, matrix; `None` for Khang's C
/// of a tree of links, which is not derived), in print order; the titles of M, C q' and g
/// say when the links' recursion built them.
fn sections<'e>(
    model: &Model,
    eqs: &'e Equations,
) -> [(&'static str, &'static str, Option<&'e Matrix>); 9] {
    let (mass_title, coriolis_title, gravity_title) = if model.kinetic_from_links {
        (
            "M = d2T/dq'dq', the mass matrix (by composite bodies over the links)",
            "C q', the Coriolis and centrifugal forces (by Newton-Euler over the links)",
            if model.potential_from_links {
                "g = dPi/dq, the gravity forces (by composite bodies over the links)"
            } else {
                "g = dPi/dq, the gravity forces (the links' by composite bodies, the declared potential's by differentiation)"
            },
        )
    } else {
        (
            "M = d2T/dq'dq', the mass matrix",
            "C q', the Coriolis and centrifugal forces",
            "g = dPi/dq, the gravity forces",
        )
    };
    [
        ("M", mass_title, Some(&eqs.mass)),
        (
            "C",
            "C = (dM/dq)(I_n kron q') - 1/2 [(dM/dq)(q' kron I_n)]^T, Khang's Coriolis matrix",
            eqs.coriolis_matrix.as_ref(),
        ),
        ("Cq'", coriolis_title, Some(&eqs.coriolis_forces)),
        ("g", gravity_title, Some(&eqs.gravity)),
        ("tau", "tau, the generalised forces", Some(&eqs.forces)),
        ("Phi", "Phi, the constraints Phi(q, t) = 0", Some(&eqs.phi)),
        (
            "Phi_q",
            "Phi_q = dPhi/dq, the constraint Jacobian",
            Some(&eqs.phi_q),
        ),
        ("Phi_t", "Phi_t = dPhi/dt", Some(&eqs.phi_t)),
        (
            "gamma",
            "gamma = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt, so that Phi_q q'' = gamma",
            Some(&eqs.gamma),
        ),
    ]
}
