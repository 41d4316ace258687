//! LaTeX for expressions, matrices and derived equations.
//!
//! Same layout as the text form (positive terms first, coefficient first, negative powers
//! as fractions), spelled for LaTeX: `\frac{m_{2} l_{1}^{2}}{2}`, `\sin^{2}{\left(\phi\right)}`,
//! `\dot{\phi}` for der(phi), `\ddot{\phi}` for der2(phi), greek names as letters
//! (`Omega` -> `\Omega`), trailing digits and `_` parts as subscripts (`x_c` -> `x_{c}`,
//! `l1` -> `l_{1}`), matrices as `bmatrix`.

use crate::algebra::expr::{Arena, Func, Id, SymbolKind};
use crate::algebra::matrix::Matrix;
use crate::mechanics::equations::Equations;
use crate::mechanics::model::Model;
use crate::number::Number;
use crate::print::render::{Prec, Rendered, Renderer, Style, elided_note};
use std::borrow::Cow;

/// The LaTeX spelling.
pub(crate) struct Latex;

const GREEK: &[&str] = &[
    "alpha",
    "beta",
    "gamma",
    "delta",
    "epsilon",
    "varepsilon",
    "zeta",
    "eta",
    "theta",
    "vartheta",
    "iota",
    "kappa",
    "lambda",
    "mu",
    "nu",
    "xi",
    "pi",
    "varpi",
    "rho",
    "varrho",
    "sigma",
    "varsigma",
    "tau",
    "upsilon",
    "phi",
    "varphi",
    "chi",
    "psi",
    "omega",
    "Gamma",
    "Delta",
    "Theta",
    "Lambda",
    "Xi",
    "Pi",
    "Sigma",
    "Upsilon",
    "Phi",
    "Psi",
    "Omega",
];

/// A name's base: a greek letter, one letter, or an upright multi-letter word.
fn latex_base(base: &str) -> String {
    if GREEK.contains(&base) {
        format!("\\{base}")
    } else if base.chars().count() <= 1 {
        base.to_string()
    } else {
        format!("\\mathrm{{{}}}", base.replace('_', "\\_"))
    }
}

/// A symbol name in LaTeX: `Omega` -> `\Omega`, `x_c` -> `x_{c}`, `l1` -> `l_{1}`,
/// `tau0` -> `\tau_{0}`, `der(phi)` -> `\dot{\phi}`, `der2(phi)` -> `\ddot{\phi}`.
pub(crate) fn latex_name(name: &str) -> String {
    if let Some(inner) = name.strip_prefix("der(").and_then(|r| r.strip_suffix(')')) {
        return format!("\\dot{{{}}}", latex_name(inner));
    }
    if let Some(inner) = name.strip_prefix("der2(").and_then(|r| r.strip_suffix(')')) {
        return format!("\\ddot{{{}}}", latex_name(inner));
    }
    if let Some((base, sub)) = name.split_once('_')
        && !base.is_empty()
        && !sub.is_empty()
    {
        return format!("{}_{{{}}}", latex_base(base), latex_name(sub));
    }
    let digits = name.len() - name.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    if digits > 0 && digits < name.len() {
        let (base, sub) = name.split_at(name.len() - digits);
        return format!("{}_{{{sub}}}", latex_base(base));
    }
    latex_base(name)
}

fn paren(s: &str) -> String {
    format!("\\left({s}\\right)")
}

fn wrap(r: &Rendered, min: Prec) -> Cow<'_, str> {
    if r.prec < min {
        Cow::Owned(paren(&r.s))
    } else {
        Cow::Borrowed(&r.s)
    }
}

/// The parts side by side, each in brackets if it binds looser than a product.
fn join_factors(out: &mut String, parts: &[Cow<'_, Rendered>]) {
    for (i, r) in parts.iter().enumerate() {
        let piece = wrap(r, Prec::Product);
        if i > 0 {
            // Juxtaposition, except between two digits (`2 \cdot 3^{x}`).
            let digit = piece.starts_with(|c: char| c.is_ascii_digit());
            out.push_str(if digit { " \\cdot " } else { " " });
        }
        out.push_str(&piece);
    }
}

impl Style for Latex {
    fn number(&self, n: Number) -> Rendered {
        match n {
            Number::Rational(p, 1) => Rendered::new(p.to_string(), Prec::Atom),
            Number::Rational(p, q) => Rendered::new(format!("\\frac{{{p}}}{{{q}}}"), Prec::Atom),
            Number::Float(x) => {
                let s = format!("{x:?}");
                match s.split_once('e') {
                    Some(("1", exp)) => Rendered::new(format!("10^{{{exp}}}"), Prec::Power),
                    Some((mantissa, exp)) => {
                        Rendered::new(format!("{mantissa} \\cdot 10^{{{exp}}}"), Prec::Product)
                    }
                    None => Rendered::new(s, Prec::Atom),
                }
            }
        }
    }

    fn pi(&self) -> Rendered {
        Rendered::new("\\pi".into(), Prec::Atom)
    }

    fn symbol(&self, name: &str, _kind: SymbolKind) -> Rendered {
        Rendered::new(latex_name(name), Prec::Atom)
    }

    fn func(&self, f: Func, x: &Rendered) -> Rendered {
        let head = match f {
            Func::Exp => return Rendered::new(format!("e^{{{}}}", x.s), Prec::Power),
            Func::Abs => return Rendered::new(format!("\\left|{}\\right|", x.s), Prec::Atom),
            Func::Sin => "\\sin",
            Func::Cos => "\\cos",
            Func::Tan => "\\tan",
            Func::Ln => "\\ln",
        };
        let arg = format!("{{{}}}", paren(&x.s));
        Rendered {
            s: format!("{head}{arg}"),
            prec: Prec::Atom,
            head: Some(Box::new((head.to_string(), arg))),
        }
    }

    fn atan2(&self, y: &Rendered, x: &Rendered) -> Rendered {
        Rendered::new(
            format!(
                "\\operatorname{{atan2}}{}",
                paren(&format!("{}, {}", y.s, x.s))
            ),
            Prec::Atom,
        )
    }

    fn sqrt(&self, x: &Rendered) -> Rendered {
        Rendered::new(format!("\\sqrt{{{}}}", x.s), Prec::Atom)
    }

    fn power(&self, base: &Rendered, exp: &Rendered) -> Rendered {
        if let Some((head, arg)) = base.head.as_deref() {
            return Rendered::new(format!("{head}^{{{}}}{arg}", exp.s), Prec::Power);
        }
        Rendered::new(
            format!("{}^{{{}}}", wrap(base, Prec::Atom), exp.s),
            Prec::Power,
        )
    }

    fn product(&self, num: &[Cow<'_, Rendered>], den: &[Cow<'_, Rendered>]) -> Rendered {
        if let ([only], []) = (num, den) {
            return only.as_ref().clone();
        }
        let len: usize = num.iter().chain(den).map(|r| r.s.len() + 20).sum();
        let mut s = String::with_capacity(len + 10);
        if !den.is_empty() {
            s.push_str("\\frac{");
        }
        if num.is_empty() {
            s.push('1');
        } else {
            join_factors(&mut s, num);
        }
        if !den.is_empty() {
            s.push_str("}{");
            join_factors(&mut s, den);
            s.push('}');
        }
        Rendered::new(s, Prec::Product)
    }

    fn paren(&self, s: &str) -> String {
        paren(s)
    }
}

/// The expression `id` in LaTeX (math mode, without delimiters).
///
/// # Example
/// ```
/// use mechanism_codegen::{parse_expr, Arena, SymbolKind};
/// use mechanism_codegen::internals::to_latex;
/// let mut a = Arena::new();
/// for s in ["m2", "l1"] {
///     a.symbol(s, SymbolKind::Parameter);
/// }
/// a.coordinate("phi");
/// let e = parse_expr(&mut a, "1/2*m2*l1^2*der(phi)^2*cos(phi)^2").unwrap();
/// assert_eq!(to_latex(&a, e), r"\frac{m_{2} l_{1}^{2} \dot{\phi}^{2} \cos^{2}{\left(\phi\right)}}{2}");
/// ```
pub fn to_latex(arena: &Arena, id: Id) -> String {
    Renderer::new(arena, Latex).render(id).s.clone()
}

fn bmatrix(r: &mut Renderer<'_, Latex>, m: &Matrix) -> String {
    let mut rows = Vec::with_capacity(m.rows);
    for i in 0..m.rows {
        let row: Vec<String> = (0..m.cols)
            .map(|j| {
                m.data
                    .get(i * m.cols + j)
                    .map_or_else(|| "?".into(), |&e| r.render(e).s.clone())
            })
            .collect();
        rows.push(row.join(" & "));
    }
    format!(
        "\\begin{{bmatrix}}\n{}\n\\end{{bmatrix}}",
        rows.join(" \\\\\n")
    )
}

/// The matrix `m` as a LaTeX `bmatrix`, one row per line.
///
/// # Example
/// ```
/// use mechanism_codegen::{Arena, Matrix, SymbolKind};
/// use mechanism_codegen::internals::matrix_to_latex;
/// let mut a = Arena::new();
/// let x = a.symbol("x", SymbolKind::Free);
/// let z = a.int(0);
/// let m = Matrix::new(2, 2, vec![x, z, z, x])?;
/// assert_eq!(matrix_to_latex(&a, &m), "\\begin{bmatrix}\nx & 0 \\\\\n0 & x\n\\end{bmatrix}");
/// # Ok::<(), mechanism_codegen::Error>(())
/// ```
pub fn matrix_to_latex(arena: &Arena, m: &Matrix) -> String {
    bmatrix(&mut Renderer::new(arena, Latex), m)
}

/// The derived equations of `model` as a LaTeX fragment: q, then one display equation per
/// quantity (M, C, C q', g, tau, Phi, Phi_q, Phi_t, gamma, T, Pi), in an `align*`-free form
/// (`\[ ... \]`) that any LaTeX or MathJax renders.
pub fn equations_latex(model: &Model, eqs: &Equations) -> String {
    let mut r = Renderer::for_equations(&model.arena, Latex);
    let q: Vec<String> = model
        .coordinates
        .iter()
        .map(|c| latex_name(&c.name))
        .collect();
    let mut out = format!(
        "% {}: M(q) \\ddot{{q}} + C(q, \\dot{{q}}) \\dot{{q}} + g(q) + \\Phi_q^T \\lambda = \\tau, \\quad \\Phi(q, t) = 0\n",
        model.name
    );
    out.push_str(&format!(
        "\\[ q = \\begin{{bmatrix}} {} \\end{{bmatrix}}^T \\]\n",
        q.join(" & ")
    ));
    if model.kinetic_from_links {
        // As in the text: the links' shared sums and products defined once, by name.
        let mut roots: Vec<crate::algebra::expr::Id> = Vec::new();
        for mat in [&eqs.mass, &eqs.coriolis_forces, &eqs.gravity] {
            roots.extend_from_slice(mat.data());
        }
        roots.extend([eqs.kinetic, eqs.potential]);
        for (k, id) in crate::print::render::shared_nodes(&model.arena, &roots)
            .into_iter()
            .enumerate()
        {
            let def = &r.render(id).s;
            out.push_str(&format!("\\[ w_{{{}}} = {def} \\]\n", k + 1));
            r.name(id, format!("w_{{{}}}", k + 1));
        }
    }
    let sections: [(&str, Option<&Matrix>); 9] = [
        ("M", Some(&eqs.mass)),
        ("C", eqs.coriolis_matrix.as_ref()),
        ("C \\dot{q}", Some(&eqs.coriolis_forces)),
        ("g", Some(&eqs.gravity)),
        ("\\tau", Some(&eqs.forces)),
        ("\\Phi", Some(&eqs.phi)),
        ("\\Phi_q", Some(&eqs.phi_q)),
        ("\\Phi_t", Some(&eqs.phi_t)),
        ("\\gamma", Some(&eqs.gamma)),
    ];
    for (name, m) in sections {
        let Some(m) = m else {
            out.push_str("% C: Khang's C of the M above, not written out for links\n");
            continue;
        };
        out.push_str(&format!("\\[ {name} = {} \\]\n", bmatrix(&mut r, m)));
    }
    out.push_str(&format!("\\[ T = {} \\]\n", r.render(eqs.kinetic).s));
    out.push_str(&format!("\\[ \\Pi = {} \\]\n", r.render(eqs.potential).s));
    if r.elided {
        out.push_str(&format!("% {}\n", elided_note()));
    }
    out
}
