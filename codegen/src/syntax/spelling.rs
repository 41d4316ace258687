//! Spelling suggestions for names the user got wrong: the closest candidate by edit
//! distance (Levenshtein, in characters), for "did you mean ..." hints, and the known names
//! closest first, for "known: ..." lists.

/// The candidate closest to `name` by edit distance, when it is a likely typo: at most 2
/// edits, and at most half the longer name (so `x` does not suggest `y`). A candidate equal
/// up to letter case wins.
pub fn closest<'n>(name: &str, candidates: impl IntoIterator<Item = &'n str>) -> Option<String> {
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        if c == name {
            continue;
        }
        let d = if c.eq_ignore_ascii_case(name) {
            0
        } else {
            edit_distance(name, c)
        };
        let longer = name.chars().count().max(c.chars().count());
        if d <= 2 && d <= longer / 2 && best.is_none_or(|b| d < b.0) {
            best = Some((d, c));
        }
    }
    best.map(|b| b.1.to_string())
}

/// The distinct `candidates`, closest to `name` first (ties in the order given; a candidate
/// equal up to letter case counts as distance 0).
pub(crate) fn ranked<'n>(name: &str, candidates: impl IntoIterator<Item = &'n str>) -> Vec<String> {
    let mut seen: Vec<&str> = Vec::new();
    for c in candidates {
        if c != name && !seen.contains(&c) {
            seen.push(c);
        }
    }
    let distance = |c: &str| {
        if c.eq_ignore_ascii_case(name) {
            0
        } else {
            edit_distance(name, c)
        }
    };
    // A stable sort keeps the given order among names at one distance.
    seen.sort_by_cached_key(|c| distance(c));
    seen.into_iter().map(str::to_string).collect()
}

/// Levenshtein distance in characters.
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranked_puts_the_closest_first_and_keeps_the_order_of_ties() {
        let names = ["m", "l", "phi", "psi", "t", "pi", "phi"];
        assert_eq!(
            ranked("phl", names),
            ["phi", "l", "psi", "pi", "m", "t"],
            "phi (1 edit), then l, psi, pi (2), then m, t (3), ties in their given order"
        );
        assert_eq!(ranked("X", ["y", "x"]), ["x", "y"], "letter case first");
    }

    #[test]
    fn closest_suggests_only_likely_typos() {
        assert_eq!(closest("gg", ["m", "g"]).as_deref(), Some("g"));
        assert_eq!(closest("w", ["x", "y"]), None);
        assert_eq!(closest("Phi", ["psi", "phi"]).as_deref(), Some("phi"));
    }
}
