//! Marks of the indices one pass has visited, for passes repeated many times over one
//! growing arena: the differentiator's walk per derivative (node indices), a dependency
//! union's symbols (symbol indices).
//!
//! An index is marked with the pass's number, so starting a pass clears nothing: a fresh
//! set or map per pass costs an allocation and, once it has grown, a clearing as large as
//! the largest pass so far. Memory is one `u32` per index.

/// The visited marks: `marks[k]` is the number of the last walk that visited index `k`.
#[derive(Clone, Debug, Default)]
pub(crate) struct VisitMarks {
    marks: Vec<u32>,
    walk: u32,
}

impl VisitMarks {
    /// Starts a walk: no index is marked visited.
    pub(crate) fn start(&mut self) {
        self.walk = self.walk.wrapping_add(1);
        if self.walk == 0 {
            // The counter wrapped around: no old mark may equal a new walk's number.
            self.marks.fill(0);
            self.walk = 1;
        }
    }

    /// Marks index `k` visited; true the first time in this walk.
    pub(crate) fn first_visit(&mut self, k: usize) -> bool {
        if k >= self.marks.len() {
            self.marks.resize(k + 1, 0);
        }
        std::mem::replace(&mut self.marks[k], self.walk) != self.walk
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An index is visited once per walk, and again in the next walk.
    #[test]
    fn each_walk_visits_an_index_once() {
        let mut v = VisitMarks::default();
        for _ in 0..3 {
            v.start();
            assert!(v.first_visit(5));
            assert!(!v.first_visit(5));
            assert!(v.first_visit(0));
            assert!(v.first_visit(100));
            assert!(!v.first_visit(0));
        }
    }

    /// When the walk counter wraps around to 1, a mark left by walk 1 long ago does not
    /// read as visited in the new walk 1.
    #[test]
    fn a_wrapped_counter_leaves_no_stale_mark() {
        let mut v = VisitMarks::default();
        v.start();
        assert!(v.first_visit(5), "marked by walk 1");
        v.walk = u32::MAX;
        v.start();
        assert_eq!(v.walk, 1);
        assert!(v.first_visit(5), "walk 1 again, after the wrap");
        assert!(!v.first_visit(5));
    }
}
