//! Where the value of each symbol a routine reads comes from at a call.

use crate::algebra::expr::{Id, SymbolId};
use crate::error::DerivationError;
use crate::error::{Error, Result};
use crate::mechanics::model::Model;

/// The origin of a routine input's value: an index into one of the arguments a routine is
/// called with, or time. The emitted code reads `q[i]`, `qd[i]`, `qdd[i]`, the parameter
/// struct's k-th field, `cache[slot]`, `t` and `lambda[k]`; the interpreter reads the same
/// entries of its slices (the forward dynamics reads `effort[k]` too).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Source {
    /// The coordinate q_i.
    Coordinate(usize),
    /// The rate q'_i.
    Rate(usize),
    /// The acceleration q''_i.
    Acceleration(usize),
    /// The k-th declared parameter.
    Parameter(usize),
    /// Entry `slot` of the parameter cache (the output of [`crate::Role::ParameterCache`]).
    Cache(usize),
    /// Time t.
    Time,
    /// The multiplier lambda_k (the tangent's).
    Multiplier(usize),
    /// The effort u_k along coordinate k (the forward dynamics', M q'' + b = u).
    Effort(usize),
}

/// The symbol-source table: the [`Source`] of every symbol a routine of one model may read
/// (its parameters, coordinates with their rates and accelerations, time, the tangent's
/// multipliers and the cache slots), sorted by symbol.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Sources {
    entries: Vec<(SymbolId, Source)>,
}

impl Sources {
    /// The table of `model` with the tangent's multiplier symbols `lambda`, the forward
    /// dynamics' effort symbols `effort` and the cache slot symbols `slots`.
    ///
    /// # Errors
    /// [`crate::error::DerivationError::NotASymbol`] for a hand-built model whose parameter or
    /// coordinate entry is not a symbol.
    pub(crate) fn new(
        model: &Model,
        lambda: &[SymbolId],
        effort: &[SymbolId],
        slots: &[SymbolId],
    ) -> Result<Self> {
        let arena = &model.arena;
        let symbol = |id: Id, role: String| {
            arena
                .as_symbol(id)
                .ok_or(Error::Derivation(DerivationError::NotASymbol { role }))
        };
        let mut entries = Vec::new();
        for (k, p) in model.parameters.iter().enumerate() {
            let s = symbol(p.symbol, format!("parameter `{}`", p.name))?;
            entries.push((s, Source::Parameter(k)));
        }
        // With a floating root q has the configuration's layout (`mechanics::floating`):
        // its seven symbols first, each joint's position one place after its rate's.
        if let Some(root) = model.floating_root() {
            for (k, &c) in root.configuration.iter().enumerate() {
                let s = symbol(c, format!("configuration entry {k}"))?;
                entries.push((s, Source::Coordinate(k)));
            }
        }
        for (i, c) in model.coordinates.iter().enumerate() {
            let name = &c.name;
            let q = symbol(c.q, format!("coordinate `{name}`"))?;
            let qd = symbol(c.qd, format!("the rate of `{name}`"))?;
            let qdd = symbol(c.qdd, format!("the acceleration of `{name}`"))?;
            if let Some(k) = model.configuration_index(i) {
                entries.push((q, Source::Coordinate(k)));
            }
            entries.push((qd, Source::Rate(i)));
            entries.push((qdd, Source::Acceleration(i)));
        }
        if let Some(t) = arena.as_symbol(model.time) {
            entries.push((t, Source::Time));
        }
        let multipliers = lambda.iter().enumerate();
        entries.extend(multipliers.map(|(k, &s)| (s, Source::Multiplier(k))));
        let efforts = effort.iter().enumerate();
        entries.extend(efforts.map(|(k, &s)| (s, Source::Effort(k))));
        let cache = slots.iter().enumerate();
        entries.extend(cache.map(|(k, &s)| (s, Source::Cache(k))));
        Ok(entries.into_iter().collect())
    }

    /// The source of `symbol` (the first entry naming it), `None` for a symbol no routine
    /// input stands for.
    pub fn get(&self, symbol: SymbolId) -> Option<Source> {
        let first = self.entries.partition_point(|(s, _)| s.0 < symbol.0);
        self.entries
            .get(first)
            .filter(|(s, _)| *s == symbol)
            .map(|&(_, source)| source)
    }

    /// Every (symbol, source) pair, sorted by symbol.
    pub fn iter(&self) -> impl Iterator<Item = (SymbolId, Source)> + '_ {
        self.entries.iter().copied()
    }
}

impl FromIterator<(SymbolId, Source)> for Sources {
    /// The table of the given pairs (for a program compiled outside [`crate::compile`], a
    /// drive's f(t), say); where a symbol comes twice, its first source counts.
    fn from_iter<I: IntoIterator<Item = (SymbolId, Source)>>(pairs: I) -> Self {
        let mut entries: Vec<(SymbolId, Source)> = pairs.into_iter().collect();
        entries.sort_by_key(|&(s, _)| s.0);
        Self { entries }
    }
}
