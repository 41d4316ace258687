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
        "the derivation needs dM/dq with {entries} nonzero entries (an M_ij depending on a q_k) for the {coordinates} coordinates, beyond its budget of {limit}; {} or raise the budget with the environment variable MECHANISM_MAX_ENTRIES={entries}",
        entries_remedy(*links)
    )]
    Entries {
        /// n.
        coordinates: usize,
        /// The nonzero entries of dM/dq.
        entries: usize,
        /// The budget in entries.
        limit: usize,
        /// The moving links of a tree of links (whose remedies differ), `None` otherwise.
        links: Option<usize>,
    },
    /// The derivation worked beyond [`Budget::work`](crate::Budget::work).
    #[error(
        "the derivation did {work} units of work (building expressions), beyond its budget of {budget}; {} or raise the budget with the environment variable MECHANISM_MAX_WORK={suggest}",
        work_remedy(*links),
        suggest = work.saturating_mul(4)
    )]
    Work {
        /// The work done when it stopped.
        work: u64,
        /// The budget.
        budget: u64,
        /// The moving links of a tree of links (whose remedies differ), `None` otherwise.
        links: Option<usize>,
    },
    /// The expressions grew beyond [`Budget::size`](crate::Budget::size).
    #[error(
        "the derivation's expressions reached {size} nodes and child references, beyond its budget of {budget} (about 190 bytes each at the peak of the derivation); {} or raise the budget with the environment variable MECHANISM_MAX_SIZE={suggest}",
        size_remedy(*links),
        suggest = size.saturating_mul(2)
    )]
    Size {
        /// The size reached.
        size: usize,
        /// The budget.
        budget: usize,
        /// The moving links of a tree of links (whose remedies differ), `None` otherwise.
        links: Option<usize>,
    },
}

impl BudgetError {
    /// The same error met while deriving or compiling a tree of `links` moving links: its
    /// message then says what applies to links (an imported URDF cannot have fewer chained
    /// rotations; its joints can be locked).
    pub fn of_links(self, links: usize) -> Self {
        let links = Some(links);
        match self {
            BudgetError::Entries {
                coordinates,
                entries,
                limit,
                ..
            } => BudgetError::Entries {
                coordinates,
                entries,
                limit,
                links,
            },
            BudgetError::Work { work, budget, .. } => BudgetError::Work {
                work,
                budget,
                links,
            },
            BudgetError::Size { size, budget, .. } => BudgetError::Size {
                size,
                budget,
                links,
            },
        }
    }
}

/// What a tree of links can do about its size: its joints are its coordinates, and the
/// recursive route's cost follows them.
fn links_remedy(links: usize) -> String {
    format!(
        "a tree of links derives in O(n^2) for M and O(n) per link for the rest, and these {links} moving links need more than the budget: lock the joints that need not move (`mechanism import --lock JOINT`, or `joint = fixed;`)"
    )
}

fn entries_remedy(links: Option<usize>) -> String {
    match links {
        // Only the macro's `coriolis_matrix` forms dM/dq for a tree of links.
        Some(k) => format!(
            "for a tree of links only the emitted `coriolis_matrix` needs dM/dq (the interpreter, `mechanism simulate` and every other method do not): run these {k} moving links through the interpreter (`Interpreted`), or lock the joints that need not move (`mechanism import --lock JOINT`)"
        ),
        None => "declare fewer coordinates (each body's or point's own)".to_string(),
    }
}

fn work_remedy(links: Option<usize>) -> String {
    match links {
        Some(k) => links_remedy(k),
        None => "simplify the declaration (fewer coordinates, bodies declared with their own coordinates, links instead of one long kinetic energy)".to_string(),
    }
}

fn size_remedy(links: Option<usize>) -> String {
    match links {
        Some(k) => links_remedy(k),
        None => "simplify the declaration (fewer chained rotations, bodies declared with their own coordinates)".to_string(),
    }
}
