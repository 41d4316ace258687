//! Errors of the derivation's budgets ([`Budget`](crate::Budget)): the derivation stops
//! where it would exceed one, within the budget's time, instead of running on for hours or
//! exhausting the memory.

/// A budget the derivation would exceed, with the value that raises it.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum BudgetError {
    /// Khang's dM/dq of n coordinates has an entry for each (M_ij, q_k) where M_ij depends on
    /// q_k; there are more than [`Budget::entries`](crate::Budget::entries).
    #[error(
        "the derivation needs dM/dq with {entries} nonzero entries (an M_ij depending on a q_k) for the {coordinates} coordinates, beyond its budget of {limit}; declare fewer coordinates (each body's or point's own) or raise the budget with the environment variable MECHANISM_MAX_ENTRIES={entries}"
    )]
    Entries {
        /// n.
        coordinates: usize,
        /// The nonzero entries of dM/dq.
        entries: usize,
        /// The budget in entries.
        limit: usize,
    },
    /// The derivation worked beyond [`Budget::work`](crate::Budget::work).
    #[error(
        "the derivation did {work} units of work (building expressions), beyond its budget of {budget}; simplify the declaration (fewer coordinates, bodies declared with their own coordinates, links instead of one long kinetic energy) or raise the budget with the environment variable MECHANISM_MAX_WORK={suggest}",
        suggest = work.saturating_mul(4)
    )]
    Work {
        /// The work done when it stopped.
        work: u64,
        /// The budget.
        budget: u64,
    },
    /// The expressions grew beyond [`Budget::size`](crate::Budget::size).
    #[error(
        "the derivation's expressions reached {size} nodes and child references, beyond its budget of {budget} (about 190 bytes each at the peak of the derivation); simplify the declaration (fewer chained rotations, bodies declared with their own coordinates) or raise the budget with the environment variable MECHANISM_MAX_SIZE={suggest}",
        suggest = size.saturating_mul(2)
    )]
    Size {
        /// The size reached.
        size: usize,
        /// The budget.
        budget: usize,
    },
}
