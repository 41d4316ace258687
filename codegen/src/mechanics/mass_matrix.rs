//! M = dp/dq' read off the momenta p = dT/dq' as linear forms in the rates.
//!
//! Differentiating p_i by q_j' for every pair (i, j) walks all of p_i once per column: in a
//! closed chain of n bars in absolute angles p_i has a term per bar k >= i, each the
//! product of a rate-free factor r_ki and the bar's velocity L_k (a linear form in the
//! rates), so the walk creates n^3 product nodes for n^2 entries. Here each term is read
//! once instead: p_i = sum_k c_k r_ki L_k with L_k = sum_j d_kj s_kj q_j' (c, d numbers; r,
//! s rate-free monomials) gives
//!
//! M_ij = sum_k (c_k d_kj) r_ki s_kj,
//!
//! accumulated numerically per pair of monomials (r, s). Each linear form L_k is decomposed
//! once and shared by every momentum that reads it, so the nodes created are those of the
//! entries and of the decompositions (n^2 in the chain). Summed afresh per row, the
//! numbers cost one addition per (i, j, k), n^3 / 3 in the chain; `running_rows.rs` carries
//! each row's sums over to the next and adds only what changed (O(n) per row in the chain),
//! and a row it declines (a float coefficient) is summed afresh here.
//!
//! The result is the canonical sum of the same terms as the term-by-term derivative
//! (exact for rational coefficients; for float coefficients the groups are summed first,
//! which can change the last bit). A momentum that is not linear in the rates in this
//! form (a rate inside a function or a power, a product of two rate-dependent factors)
//! makes the whole matrix fall back to differentiation, which also reports what is wrong
//! with such a kinetic energy.

use std::rc::Rc;

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, FxHashMap, Id, Node, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::Result;
use crate::mechanics::linear_form::{LinearForm, Sum};
use crate::mechanics::running_rows::RunningRows;
use crate::number::Number;

/// The groups of one column in the row being accumulated: per rate-free monomial pair
/// (r, s), the summed coefficient, in order of first appearance. A column holds as many
/// groups as its entry has distinct monomials (two in the chain), so it is searched
/// linearly.
type ColumnGroups = Vec<(Option<Id>, Option<Id>, Sum)>;

/// M (n x n, symmetric, upper triangle computed and mirrored) from the momenta
/// `momenta[i]` = dT/dq_i' by linear forms, or `None` when some momentum is not of that
/// form (the caller then differentiates).
///
/// # Errors
/// What [`Differentiator::symbols_of`] reports for an id not in `arena`.
pub(crate) fn mass_from_momenta(
    arena: &mut Arena,
    d: &mut Differentiator,
    momenta: &[Id],
    rates: &[SymbolId],
) -> Result<Option<Matrix>> {
    let mut running = RunningRows::default();
    mass_from_momenta_with(arena, d, momenta, rates, Some(&mut running))
}

/// [`mass_from_momenta`] with the rows' sums carried over by `running`
/// (`running_rows.rs`), or each row summed afresh for `None` (the reference the running
/// sums are tested against).
///
/// # Errors
/// As [`mass_from_momenta`].
pub(crate) fn mass_from_momenta_with(
    arena: &mut Arena,
    d: &mut Differentiator,
    momenta: &[Id],
    rates: &[SymbolId],
    mut running: Option<&mut RunningRows>,
) -> Result<Option<Matrix>> {
    let n = momenta.len();
    let mut reader = LinearReader::new(arena, rates);
    let mut mass = Matrix::zeros(arena, n, n);
    // Per column, reused row after row; `touched` lists the columns the row has reached.
    let mut columns: Vec<ColumnGroups> = vec![Vec::new(); n];
    let mut touched: Vec<usize> = Vec::new();
    let mut read: Vec<(Number, Option<Id>, LinearForm)> = Vec::new();
    for (i, &p) in momenta.iter().enumerate() {
        let terms: Vec<Id> = match arena.node(p) {
            Node::Add(ts) => ts.to_vec(),
            _ => vec![p],
        };
        read.clear();
        for t in terms {
            let Some(term) = reader.term(arena, d, t)? else {
                return Ok(None);
            };
            read.push(term);
        }
        if let Some(entries) = running.as_deref_mut().and_then(|r| r.row(i, &read)) {
            for (j, parts) in entries {
                let mij = entry(arena, parts);
                mass.set(i, j, mij);
                mass.set(j, i, mij);
            }
            continue;
        }
        for (c, r, form) in read.iter().map(|(c, r, f)| (*c, *r, f)) {
            // A form is sorted by rate: the entries of the upper triangle (j >= i) are a tail.
            let upper = form.partition_point(|e| e.0 < i);
            for &(j, dj, s) in &form[upper..] {
                let column = &mut columns[j];
                if column.is_empty() {
                    touched.push(j);
                }
                let added = match column.iter_mut().find(|g| g.0 == r && g.1 == s) {
                    Some(g) => g.2.add_product(c, dj),
                    None => Sum::product(c, dj).map(|sum| column.push((r, s, sum))),
                };
                if added.is_none() {
                    return Ok(None);
                }
            }
        }
        // Columns in increasing order, each entry's terms in order of first appearance:
        // the order in which the term-by-term derivative creates them.
        touched.sort_unstable();
        for &j in &touched {
            let mut parts = Vec::with_capacity(columns[j].len());
            for (r, s, sum) in columns[j].drain(..) {
                let Some(coef) = sum.value() else {
                    return Ok(None);
                };
                parts.push((r, s, coef));
            }
            let mij = entry(arena, parts);
            mass.set(i, j, mij);
            mass.set(j, i, mij);
        }
        touched.clear();
    }
    Ok(Some(mass))
}

/// The entry sum_g coef_g r_g s_g of M from its groups (r, s, coefficient), each term made
/// in the order given (the order fixes the ids of new nodes, and so the printed order).
fn entry(arena: &mut Arena, parts: Vec<(Option<Id>, Option<Id>, Number)>) -> Id {
    let mut terms = Vec::with_capacity(parts.len());
    for (r, s, coef) in parts {
        let mut factors = vec![arena.number(coef)];
        factors.extend(r);
        factors.extend(s);
        terms.push(arena.mul(&factors));
    }
    arena.add(&terms)
}

/// Reads terms and linear forms in the rates, each linear form once.
struct LinearReader {
    /// The rate index of each symbol, by [`SymbolId::index`].
    rate_of: Vec<Option<usize>>,
    /// Whether each symbol is a rate.
    is_rate: Vec<bool>,
    /// The decomposition of every linear form read so far (`None`: not linear).
    forms: FxHashMap<Id, Option<LinearForm>>,
}

impl LinearReader {
    fn new(arena: &Arena, rates: &[SymbolId]) -> Self {
        let mut rate_of = vec![None; arena.symbols().len()];
        let mut is_rate = vec![false; arena.symbols().len()];
        for (j, r) in rates.iter().enumerate() {
            rate_of[r.index()] = Some(j);
            is_rate[r.index()] = true;
        }
        Self {
            rate_of,
            is_rate,
            forms: FxHashMap::default(),
        }
    }

    /// Whether `id` depends on a rate.
    fn has_rate(&self, arena: &Arena, d: &mut Differentiator, id: Id) -> Result<bool> {
        d.depends_on_any(arena, id, &self.is_rate)
    }

    /// A term of a momentum as c * r * L: its coefficient, its rate-free monomial r and
    /// its linear form L (empty for a rate-free term). `None` when the term is not of
    /// that form.
    fn term(
        &mut self,
        arena: &mut Arena,
        d: &mut Differentiator,
        t: Id,
    ) -> Result<Option<(Number, Option<Id>, LinearForm)>> {
        let (c, factors) = match arena.node(t) {
            Node::Num(_) => return Ok(Some((Number::int(0), None, Rc::default()))),
            Node::Mul(fs) => match arena.as_number(fs[0]) {
                Some(c) => (c, fs[1..].to_vec()),
                None => (Number::int(1), fs.to_vec()),
            },
            _ => (Number::int(1), vec![t]),
        };
        let mut linear = None;
        let mut rest = Vec::with_capacity(factors.len());
        for f in factors {
            if !self.has_rate(arena, d, f)? {
                rest.push(f);
            } else if linear.is_none() {
                linear = Some(f);
            } else {
                return Ok(None);
            }
        }
        let Some(l) = linear else {
            return Ok(Some((c, None, Rc::default())));
        };
        let Some(form) = self.form(arena, d, l)? else {
            return Ok(None);
        };
        let r = match rest.len() {
            0 => None,
            1 => Some(rest[0]),
            _ => Some(arena.mul(&rest)),
        };
        Ok(Some((c, r, form)))
    }

    /// The decomposition of `id` (which depends on a rate) as a linear form, once per node.
    fn form(
        &mut self,
        arena: &mut Arena,
        d: &mut Differentiator,
        id: Id,
    ) -> Result<Option<LinearForm>> {
        if let Some(f) = self.forms.get(&id) {
            return Ok(f.clone());
        }
        let form = match arena.node(id).clone() {
            Node::Sym(x) => self
                .rate_of
                .get(x.index())
                .copied()
                .flatten()
                .map(|j| Rc::new(vec![(j, Number::int(1), None)])),
            Node::Add(ts) => {
                let mut all = Vec::new();
                let mut linear = true;
                for t in ts.iter() {
                    match self.term(arena, d, *t)? {
                        Some((c, r, inner)) => {
                            for &(j, dj, s) in inner.iter() {
                                let Some(cd) = c.checked_mul(dj) else {
                                    linear = false;
                                    break;
                                };
                                all.push((j, cd, monomial(arena, r, s)));
                            }
                        }
                        None => linear = false,
                    }
                    if !linear {
                        break;
                    }
                }
                linear.then(|| Rc::new(by_rate(arena, all)))
            }
            Node::Mul(_) => match self.term(arena, d, id)? {
                Some((c, r, inner)) => {
                    let mut all = Vec::with_capacity(inner.len());
                    for &(j, dj, s) in inner.iter() {
                        match c.checked_mul(dj) {
                            Some(cd) => all.push((j, cd, monomial(arena, r, s))),
                            None => return Ok(None),
                        }
                    }
                    Some(Rc::new(all))
                }
                None => None,
            },
            _ => None,
        };
        // Sorted by rate (stable: the terms of one rate keep their order, the order in which
        // they are summed), so a row's upper-triangle entries are found by bisection.
        let form = form.map(|f| {
            if f.is_sorted_by_key(|e| e.0) {
                f
            } else {
                let mut sorted = f.as_ref().clone();
                sorted.sort_by_key(|e| e.0);
                Rc::new(sorted)
            }
        });
        self.forms.insert(id, form.clone());
        Ok(form)
    }
}

/// The terms of a linear form with one term per rate: the terms of a rate that occurs
/// more than once are summed (their canonical sum, split into coefficient and rest), as
/// the derivative of the form by that rate is.
fn by_rate(
    arena: &mut Arena,
    all: Vec<(usize, Number, Option<Id>)>,
) -> Vec<(usize, Number, Option<Id>)> {
    let mut first: FxHashMap<usize, usize> = FxHashMap::default();
    let mut repeated = false;
    for (k, &(j, ..)) in all.iter().enumerate() {
        repeated |= first.insert(j, k).is_some();
    }
    if !repeated {
        return all;
    }
    let mut order: Vec<usize> = Vec::new();
    let mut parts: FxHashMap<usize, Vec<Id>> = FxHashMap::default();
    for &(j, c, s) in &all {
        let mut factors = vec![arena.number(c)];
        factors.extend(s);
        let term = arena.mul(&factors);
        parts
            .entry(j)
            .or_insert_with(|| {
                order.push(j);
                Vec::new()
            })
            .push(term);
    }
    let mut merged = Vec::with_capacity(order.len());
    for j in order {
        let sum = arena.add(&parts[&j]);
        match arena.split_coefficient(sum) {
            (c, _) if c.is_zero() => {}
            (c, rest) => merged.push((j, c, rest)),
        }
    }
    merged
}

/// The product r * s of two optional rate-free monomials.
fn monomial(arena: &mut Arena, r: Option<Id>, s: Option<Id>) -> Option<Id> {
    match (r, s) {
        (None, s) => s,
        (r, None) => r,
        (Some(r), Some(s)) => Some(arena.mul(&[r, s])),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::closed_chain_source;
    use crate::mechanics::model::Model;
    use crate::pipeline::parse_model_str;

    /// M differentiated entry by entry, d p_i / d q_j' for j >= i (the fallback route).
    fn differentiated(
        arena: &mut Arena,
        d: &mut Differentiator,
        p: &[Id],
        qd: &[SymbolId],
    ) -> Matrix {
        let n = p.len();
        let mut mass = Matrix::zeros(arena, n, n);
        for (i, &pi) in p.iter().enumerate() {
            for (j, &qj) in qd.iter().enumerate().skip(i) {
                let e = d.diff(arena, pi, qj).unwrap();
                mass.set(i, j, e);
                mass.set(j, i, e);
            }
        }
        mass
    }

    /// The model of `source`, its rates, a differentiator and the momenta dT/dq'.
    fn momenta(source: &str) -> (Model, Vec<SymbolId>, Differentiator, Vec<Id>) {
        let mut model = parse_model_str(source).unwrap();
        let qd: Vec<SymbolId> = model
            .coordinates
            .iter()
            .map(|c| model.arena.as_symbol(c.qd).unwrap())
            .collect();
        let mut d = Differentiator::new();
        let p = d.gradient(&mut model.arena, model.kinetic, &qd).unwrap();
        (model, qd, d, p)
    }

    /// Both routes on one declaration: `Some(true)` when the linear forms applied and gave
    /// the very same canonical entries, `None` when they did not apply.
    fn routes_agree(source: &str) -> Option<bool> {
        let (mut model, qd, mut d, p) = momenta(source);
        let arena = &mut model.arena;
        let by_forms = mass_from_momenta(arena, &mut d, &p, &qd).unwrap()?;
        let by_diff = differentiated(arena, &mut d, &p, &qd);
        Some(by_forms.data == by_diff.data)
    }

    /// M of `source` from its momenta with the running rows on and off: the entries (as
    /// canonical nodes of one arena) and the forms the running rows applied.
    fn running_and_fresh(source: &str) -> (Vec<Id>, Vec<Id>, usize) {
        let (mut model, qd, mut d, p) = momenta(source);
        let arena = &mut model.arena;
        let mut rows = RunningRows::default();
        let running = mass_from_momenta_with(arena, &mut d, &p, &qd, Some(&mut rows))
            .unwrap()
            .unwrap();
        let fresh = mass_from_momenta_with(arena, &mut d, &p, &qd, None)
            .unwrap()
            .unwrap();
        (running.data, fresh.data, rows.applied)
    }

    /// On the closed chain the running rows give the entries of summing every row afresh,
    /// and apply O(n) forms in all after the first row's n per group (not n^2 / 2 per
    /// row): the chain's rows share all forms but the two at the row's own bar.
    #[test]
    fn chain_rows_carry_over_and_equal_fresh_sums() {
        for n in [3, 8, 24] {
            let (running, fresh, applied) = running_and_fresh(&closed_chain_source(n));
            assert_eq!(running, fresh, "N = {n}");
            // Two groups (x and y velocities): n forms each in the first row, then the two
            // at the row's own bar per group and row (6.7 n measured at N = 24). Summing
            // afresh applies n (n + 1) (600 at N = 24).
            assert!(applied <= 7 * n + 8, "N = {n}: {applied} forms applied");
            assert!(applied >= 2 * n, "N = {n}: {applied} forms applied");
        }
    }

    /// A float coefficient declines the running sums for that row: the row is summed
    /// afresh, and M is still the fresh route's.
    #[test]
    fn float_coefficients_fall_back_to_fresh_sums() {
        let source = "pub struct X; coordinates { x = 0.1; y = 0.2; } independent { x = 0.1; \
                      der(x) = 0; y = 0.2; der(y) = 0; } \
                      kinetic = 0.3*(der(x) + cos(x)*der(y))^2 + 1/2*der(y)^2; potential = 0;";
        let (running, fresh, applied) = running_and_fresh(source);
        assert_eq!(running, fresh);
        assert_eq!(
            applied, 0,
            "a float coefficient must not be summed by difference"
        );
    }

    #[test]
    fn every_library_mechanism_gets_the_entries_differentiation_gets() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../mechanisms");
        let mut applied = 0;
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "mech") {
                continue;
            }
            let source = std::fs::read_to_string(&path).unwrap();
            if let Some(same) = routes_agree(&source) {
                assert!(same, "{}: the two routes differ", path.display());
                applied += 1;
            }
        }
        // Every declaration of the library has a kinetic energy quadratic in the rates.
        assert!(
            applied >= 15,
            "linear forms applied to {applied} mechanisms"
        );
    }

    #[test]
    fn a_rate_inside_a_function_or_a_power_falls_back() {
        let head = "pub struct X; coordinates { x = 0.1; y = 0.2; } independent { x = 0.1; \
                    der(x) = 0; y = 0.2; der(y) = 0; }";
        for kinetic in [
            "cos(der(x)) + der(y)^2",
            "der(x)^4 + der(y)^2",
            "der(x)^2*der(y)^2",
        ] {
            let source = format!("{head} kinetic = {kinetic}; potential = 0;");
            assert_eq!(routes_agree(&source), None, "{kinetic}");
        }
        // A rate repeated inside one linear form, and a product of two forms.
        let source = format!(
            "{head} kinetic = 1/2*(der(x)*cos(x) + der(x)*sin(y) + 2*der(y))^2 \
             + 3*(der(x) + x*der(y))*(der(y) - y*der(x)); potential = 0;"
        );
        assert_eq!(routes_agree(&source), Some(true));
    }
}
