//! The rows of M from the momenta in O(n^2) for chains: each row's sums carried over from
//! the row before and corrected by what changed.
//!
//! Row i of M collects, per rate-free monomial r of the momentum p_i = sum_t c_t r_t L_t,
//! the combination sum_{t: r_t = r} c_t L_t of linear forms in the rates; its coefficient of
//! q_j' is M_ij's part with factor r. Summed afresh per row, as `mass_matrix.rs` does, that
//! is one addition of numbers per (row, term, rate): n^3 / 3 for a closed chain of n bars
//! in absolute angles, whose p_i holds the velocity L_k of every bar k >= i. But
//! consecutive rows share almost all of those forms, with the same coefficients (p_i and
//! p_(i+1) differ by bar i's form and by the weight of bar i+1's), so here each group of a
//! row takes over the running combination of a group of the row before that holds one of
//! its forms, and only the forms whose coefficient changed, or that left or joined, are
//! added (with the difference of coefficients). The chain then costs O(n) per row.
//!
//! The running sums are exact rationals: a coefficient that is a float, or a sum that
//! leaves 64 bits (where the fresh sum would turn to a float), declines the row
//! (`None`), and the caller sums it afresh. Exact sums do not depend on the order of the
//! additions, so the entries are the fresh route's.

use std::collections::BTreeMap;

use crate::algebra::expr::{FxHashMap, FxHashSet, Id};
use crate::mechanics::linear_form::{LinearForm, Sum};
use crate::number::Number;

/// A linear form's identity: the address of its shared decomposition. Addresses are not
/// reused while M is read: the reader keeps every decomposition for the whole matrix, and
/// a running combination holds its own reference to each form in it.
type FormKey = usize;

fn key(form: &LinearForm) -> FormKey {
    std::rc::Rc::as_ptr(form) as usize
}

/// One group's running combination: the coefficient of each form in it, and per rate j
/// its coefficient, by rate-free monomial s (in order of first appearance).
#[derive(Default)]
struct Running {
    coefficients: FxHashMap<FormKey, (LinearForm, Number)>,
    columns: BTreeMap<usize, Vec<(Option<Id>, Sum)>>,
}

impl Running {
    /// Adds `c` times `form`; `None` at a float or a sum beyond 64 bits.
    fn add(&mut self, c: Number, form: &LinearForm) -> Option<()> {
        for &(j, dj, s) in form.iter() {
            if dj.is_float() {
                return None;
            }
            let column = self.columns.entry(j).or_default();
            match column.iter_mut().find(|g| g.0 == s) {
                Some(g) => g.1.add_product(c, dj)?,
                None => column.push((s, Sum::product(c, dj)?)),
            }
            if column.iter().any(|g| g.1.is_float()) {
                return None;
            }
        }
        Some(())
    }

    /// Makes the combination `forms` (form, coefficient; keys distinct): adds the
    /// difference for each form whose coefficient changed or that joined, and removes the
    /// forms that left; the number of forms so added or removed.
    fn set_to(&mut self, forms: &[(FormKey, LinearForm, Number)]) -> Option<usize> {
        let mut applied = 0;
        let mut present: FxHashSet<FormKey> = FxHashSet::default();
        for (k, form, c) in forms {
            present.insert(*k);
            let old = self.coefficients.get(k).map_or(Number::int(0), |e| e.1);
            if old != *c {
                let delta = c.checked_add(old.checked_mul(Number::int(-1))?)?;
                self.add(delta, form)?;
                applied += 1;
                self.coefficients.insert(*k, (form.clone(), *c));
            }
        }
        let gone: Vec<FormKey> = self
            .coefficients
            .keys()
            .filter(|k| !present.contains(k))
            .copied()
            .collect();
        for k in gone {
            if let Some((form, c)) = self.coefficients.remove(&k) {
                self.add(c.checked_mul(Number::int(-1))?, &form)?;
                applied += 1;
            }
        }
        Some(applied)
    }
}

/// The running combinations of the last row, carried from row to row.
#[derive(Default)]
pub(crate) struct RunningRows {
    groups: Vec<Running>,
    /// The group of the last row holding each form.
    owner: FxHashMap<FormKey, usize>,
    /// Forms added to or removed from a running combination so far (the work that the
    /// carrying-over saves: n + O(1) per row on a chain, against n^2 / 2 per row afresh).
    pub(crate) applied: usize,
}

/// A group of a row: its rate-free monomial r and its forms (form, coefficient), each
/// form once.
type Group = (Option<Id>, Vec<(FormKey, LinearForm, Number)>);

/// One upper-triangle entry of a row: column j and its terms (r, s, coefficient), in
/// group order.
pub(crate) type RowEntry = (usize, Vec<(Option<Id>, Option<Id>, Number)>);

impl RunningRows {
    /// Forgets the running combinations (after a row summed afresh).
    pub(crate) fn clear(&mut self) {
        self.groups.clear();
        self.owner.clear();
    }

    /// The entries j >= i of row i whose momentum has the terms `terms` (c, r, L): per
    /// column in increasing order, the summed coefficient of each (r, s), groups in order
    /// of first appearance of r. `None` when the row is declined (a float coefficient, a
    /// sum beyond 64 bits); the running state is then cleared.
    pub(crate) fn row(
        &mut self,
        i: usize,
        terms: &[(Number, Option<Id>, LinearForm)],
    ) -> Option<Vec<RowEntry>> {
        let out = self.try_row(i, terms);
        if out.is_none() {
            self.clear();
        }
        out
    }

    fn try_row(
        &mut self,
        i: usize,
        terms: &[(Number, Option<Id>, LinearForm)],
    ) -> Option<Vec<RowEntry>> {
        // The row's groups by r, each form once with its summed coefficient.
        let mut groups: Vec<Group> = Vec::new();
        let mut group_of: FxHashMap<Option<Id>, usize> = FxHashMap::default();
        let mut slot: FxHashMap<(usize, FormKey), usize> = FxHashMap::default();
        for (c, r, form) in terms {
            if c.is_float() {
                return None;
            }
            if form.is_empty() {
                continue;
            }
            let g = *group_of.entry(*r).or_insert_with(|| {
                groups.push((*r, Vec::new()));
                groups.len() - 1
            });
            let k = key(form);
            let forms = &mut groups[g].1;
            match slot.get(&(g, k)) {
                Some(&at) => forms[at].2 = forms[at].2.checked_add(*c)?,
                None => {
                    slot.insert((g, k), forms.len());
                    forms.push((k, form.clone(), *c));
                }
            }
        }
        // Each group takes over the first unclaimed running group holding one of its forms.
        let mut previous: Vec<Option<Running>> = std::mem::take(&mut self.groups)
            .into_iter()
            .map(Some)
            .collect();
        let mut next: Vec<Running> = Vec::with_capacity(groups.len());
        for (_, forms) in &groups {
            let taken = forms
                .iter()
                .find_map(|(k, ..)| self.owner.get(k).and_then(|&a| previous[a].take()));
            let mut running = taken.unwrap_or_default();
            self.applied += running.set_to(forms)?;
            next.push(running);
        }
        self.owner.clear();
        for (a, running) in next.iter().enumerate() {
            for &k in running.coefficients.keys() {
                self.owner.insert(k, a);
            }
        }
        // The upper-triangle entries, column by column, groups in order.
        let mut parts: Vec<(usize, usize, Option<Id>, Number)> = Vec::new();
        for (g, running) in next.iter().enumerate() {
            for (&j, column) in running.columns.range(i..) {
                for &(s, sum) in column {
                    let coef = sum.value()?;
                    if !coef.is_zero() {
                        parts.push((j, g, s, coef));
                    }
                }
            }
        }
        parts.sort_by_key(|p| (p.0, p.1));
        let mut entries: Vec<RowEntry> = Vec::new();
        for (j, g, s, coef) in parts {
            if entries.last().is_none_or(|e| e.0 != j) {
                entries.push((j, Vec::new()));
            }
            if let Some(e) = entries.last_mut() {
                e.1.push((groups[g].0, s, coef));
            }
        }
        self.groups = next;
        Some(entries)
    }
}
