//! What a derivation may spend: the size of its expression graph (memory), the nonzero
//! entries of Khang's dM/dq, and its work (the calls of the arena's constructors, which
//! bound its time), plus an optional progress report.
//!
//! A budget is a value carried by the [`Arena`](crate::Arena): the macro and the
//! command-line tool build it (from the environment variables `MECHANISM_MAX_SIZE`,
//! `MECHANISM_MAX_ENTRIES` and `MECHANISM_MAX_WORK`, through [`Budget::from_lookup`]) and
//! hand it to the parser; nothing below them reads the environment.

/// The limits of one derivation and who hears of its progress.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    /// Nodes plus child references the expression graph may reach ([`MAX_SIZE`]).
    pub size: usize,
    /// Nonzero entries of dM/dq (where M_ij depends on q_k) ([`MAX_ENTRIES`]).
    pub entries: usize,
    /// Calls of the arena's constructors ([`MAX_WORK`]).
    pub work: u64,
    /// Called every [`PROGRESS_EVERY`] units of work with the work and size so far (the
    /// command-line tool prints a progress line from it once a derivation has run for a
    /// second).
    pub progress: Option<fn(Effort)>,
}

/// What a derivation has spent so far.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Effort {
    /// Calls of the arena's constructors.
    pub work: u64,
    /// Nodes plus child references.
    pub size: usize,
}

/// The default size budget: 2^24, about 16.8 million nodes and child references. Measured
/// with `mechanism equations` (release build, which derives the equations, the residual
/// tangent and the interpreter's programs): a body turned by 24 chained rotations ends
/// between 6 and 7 million and peaks at 1.24 GB, about 190 bytes per unit, so the budget is
/// about 3 GB by that measure. The mechanisms of this repository stay far below it (the
/// 32-bar chain's equations: 76,000; the seed's: 399).
pub const MAX_SIZE: usize = 1 << 24;

/// The default budget of nonzero entries of dM/dq: 2^27, about 134 million (each with its
/// derivative several GB at the peak).
pub const MAX_ENTRIES: usize = 1 << 27;

/// The default work budget: 2^31 constructor calls, about 2.1 billion. The 200-bar closed
/// chain spends 5.8e7 (about 2^26) in 17 s of CPU for everything `mechanism equations`
/// does, so the budget stands for several minutes of derivation on one core.
pub const MAX_WORK: u64 = 1 << 31;

/// How often (in units of work) [`Budget::progress`] is called: 2^20, a few times a second.
pub const PROGRESS_EVERY: u64 = 1 << 20;

impl Default for Budget {
    fn default() -> Self {
        Self {
            size: MAX_SIZE,
            entries: MAX_ENTRIES,
            work: MAX_WORK,
            progress: None,
        }
    }
}

/// The environment variables [`Budget::from_lookup`] reads, with the field each sets.
pub const BUDGET_VARIABLES: [&str; 3] = [
    "MECHANISM_MAX_SIZE",
    "MECHANISM_MAX_ENTRIES",
    "MECHANISM_MAX_WORK",
];

impl Budget {
    /// The default budget with each limit that `lookup` gives a value for replaced: `lookup`
    /// is asked for each name of [`BUDGET_VARIABLES`] (the callers pass `std::env::var`).
    ///
    /// # Errors
    /// A one-line message naming the variable and its value when a value is not a positive
    /// whole number.
    ///
    /// # Example
    /// ```
    /// use mechanism_codegen::Budget;
    /// let b = Budget::from_lookup(|name| (name == "MECHANISM_MAX_WORK").then(|| "1000".into()))
    ///     .unwrap();
    /// assert_eq!(b.work, 1000);
    /// assert!(Budget::from_lookup(|_| Some("lots".into())).is_err());
    /// ```
    pub fn from_lookup(lookup: impl Fn(&str) -> Option<String>) -> Result<Self, String> {
        let mut b = Self::default();
        for name in BUDGET_VARIABLES {
            let Some(text) = lookup(name) else {
                continue;
            };
            let value = text
                .trim()
                .parse::<u64>()
                .ok()
                .filter(|&v| v > 0)
                .ok_or_else(|| {
                    format!(
                        "{name}={text} is not a positive whole number (a budget of the derivation)"
                    )
                })?;
            let as_usize = usize::try_from(value).unwrap_or(usize::MAX);
            match name {
                "MECHANISM_MAX_SIZE" => b.size = as_usize,
                "MECHANISM_MAX_ENTRIES" => b.entries = as_usize,
                _ => b.work = value,
            }
        }
        Ok(b)
    }
}
