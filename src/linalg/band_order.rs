//! A band-narrowing order of a symmetric sparsity pattern (reverse Cuthill-McKee), and the
//! band of the order restricted to a subset of its nodes.
//!
//! Cuthill & McKee (Proc. 24th ACM Nat. Conf., 1969), reversed as George & Liu (Computer
//! Solution of Large Sparse Positive Definite Systems, 1981, sec. 4.3) recommend: from a
//! pseudo-peripheral node (the far end of repeated breadth-first searches), number the
//! nodes level by level, each node's unnumbered neighbours by increasing degree, then
//! reverse. For a chain (a sequence of loops, each coupled to the next) every level holds
//! a bounded number of nodes, so the band
//!
//! ```text
//! b = max over edges (u, v) of |pos(u) - pos(v)|
//! ```
//!
//! is bounded independently of the chain's length. Removing nodes from an order never
//! widens its band (the nodes between two others can only become fewer), which
//! [`BandOrder::restrict`] uses for the rows a rank-deficient solve leaves out.

/// A node order with its band; allocates only in [`BandOrder::new`].
#[derive(Clone, Debug)]
pub struct BandOrder {
    /// CSR adjacency (no self loops).
    start: Vec<usize>,
    adj: Vec<usize>,
    /// The nodes in band order.
    order: Vec<usize>,
    /// Position of each node in the restricted order (usize::MAX when left out).
    pos: Vec<usize>,
    /// Nodes and band of the restricted order.
    size: usize,
    band: usize,
    /// Band of the full order.
    full_band: usize,
}

impl BandOrder {
    /// The reverse Cuthill-McKee order of the graph on `nodes` nodes with the undirected
    /// `edges` (pairs (u, v); self loops and repeats are ignored).
    pub fn new(nodes: usize, edges: &[(usize, usize)]) -> Self {
        let rank: Vec<usize> = (0..nodes).collect();
        Self::ranked(nodes, edges, &rank)
    }

    /// [`BandOrder::new`] with the ties between nodes of equal degree (the start of the
    /// search, the order within a level) broken by `rank` (distinct values, one per node)
    /// instead of the node numbers: nodes ranked by something their numbering does not
    /// decide get the same order however they are numbered.
    pub fn ranked(nodes: usize, edges: &[(usize, usize)], rank: &[usize]) -> Self {
        let mut degree = vec![0usize; nodes + 1];
        for &(u, v) in edges {
            if u != v {
                degree[u] += 1;
                degree[v] += 1;
            }
        }
        let mut start = vec![0usize; nodes + 1];
        for i in 0..nodes {
            start[i + 1] = start[i] + degree[i];
        }
        let mut fill = start.clone();
        let mut adj = vec![0usize; start[nodes]];
        for &(u, v) in edges {
            if u != v {
                adj[fill[u]] = v;
                fill[u] += 1;
                adj[fill[v]] = u;
                fill[v] += 1;
            }
        }
        for i in 0..nodes {
            let list = &mut adj[start[i]..start[i + 1]];
            list.sort_unstable();
        }
        let degree = |i: usize| start[i + 1] - start[i];
        let mut order = Vec::with_capacity(nodes);
        let mut seen = vec![false; nodes];
        let mut level = vec![usize::MAX; nodes];
        let mut roots: Vec<usize> = (0..nodes).collect();
        roots.sort_by_key(|&v| rank[v]);
        for root in roots {
            if seen[root] {
                continue;
            }
            let root = peripheral(root, &start, &adj, &mut level, rank);
            let first = order.len();
            seen[root] = true;
            order.push(root);
            let mut head = first;
            while head < order.len() {
                let u = order[head];
                head += 1;
                let from = order.len();
                for &v in &adj[start[u]..start[u + 1]] {
                    if !seen[v] {
                        seen[v] = true;
                        order.push(v);
                    }
                }
                order[from..].sort_by_key(|&v| (degree(v), rank[v]));
            }
        }
        order.reverse();
        let mut this = Self {
            start,
            adj,
            order,
            pos: vec![usize::MAX; nodes],
            size: 0,
            band: 0,
            full_band: 0,
        };
        this.restrict(|_| true);
        this.full_band = this.band;
        this
    }

    /// Restricts the order to the nodes `keep` accepts (their relative order unchanged)
    /// and computes its band. O(nodes + edges), no allocation.
    pub fn restrict(&mut self, keep: impl Fn(usize) -> bool) {
        let mut p = 0;
        for &u in &self.order {
            if keep(u) {
                self.pos[u] = p;
                p += 1;
            } else {
                self.pos[u] = usize::MAX;
            }
        }
        self.size = p;
        let mut band = 0;
        for u in 0..self.pos.len() {
            let pu = self.pos[u];
            if pu == usize::MAX {
                continue;
            }
            for &v in &self.adj[self.start[u]..self.start[u + 1]] {
                let pv = self.pos[v];
                if pv != usize::MAX {
                    band = band.max(pu.abs_diff(pv));
                }
            }
        }
        self.band = band;
    }

    /// Position of node u in the restricted order (`None` when left out).
    #[inline]
    pub fn position(&self, u: usize) -> Option<usize> {
        let p = self.pos[u];
        (p != usize::MAX).then_some(p)
    }

    /// Number of nodes in the restricted order.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Band of the restricted order, max |pos(u) - pos(v)| over its edges.
    pub fn band(&self) -> usize {
        self.band
    }

    /// Band of the order of all nodes (an upper bound of every restriction's).
    pub fn full_band(&self) -> usize {
        self.full_band
    }

    /// All nodes in band order (the node at each position, before any restriction).
    pub fn nodes(&self) -> &[usize] {
        &self.order
    }
}

/// Pairs of columns beyond which a row's coordinates are joined in a path rather than all
/// to each other (a dense row of n columns would give n^2 / 2 edges; a path keeps them
/// adjacent in the order at n edges).
const CLIQUE_PAIRS: usize = 1 << 20;

/// The solvers' order of n coordinates from the structural pattern of M (n x n) and Phi_q
/// ((row, column) pairs): the reverse Cuthill-McKee order ([`BandOrder`]) of the graph with
/// an edge between two coordinates that share an entry of M or a row of Phi_q, i.e. the
/// pattern of M + Phi_q^T Phi_q. The coordinate at each position.
///
/// Every row of Phi_q then spans the positions of few coordinates whatever order they were
/// declared in, and rows overlap only their neighbours: the row spans, the rank basis and
/// the Gram matrices of the projections cost what the pattern's band allows, O(m b^2),
/// where a declaration that scatters a row's coordinates makes every row overlap every
/// other (m^2 n). Ties are broken by the rows each coordinate appears in, not by its
/// number: declaring the coordinates in another order (the rows in the same) gives the same
/// sequence of coordinates, so the solvers do the same operations in the same order.
pub fn coordinate_order(
    n: usize,
    mass: &[(usize, usize)],
    jacobian: &[(usize, usize)],
) -> Vec<usize> {
    let mut edges: Vec<(usize, usize)> = mass
        .iter()
        .copied()
        .filter(|&(i, j)| i < n && j < n)
        .collect();
    let mut row: Vec<usize> = Vec::new();
    let mut pairs = 0usize;
    let mut rows: Vec<Vec<usize>> = Vec::new();
    let mut sorted = jacobian.to_vec();
    sorted.sort_unstable();
    let mut current = usize::MAX;
    for &(r, j) in &sorted {
        if r != current {
            if !row.is_empty() {
                rows.push(std::mem::take(&mut row));
            }
            current = r;
        }
        if j < n {
            row.push(j);
        }
    }
    if !row.is_empty() {
        rows.push(row);
    }
    for row in &rows {
        pairs += row.len() * row.len().saturating_sub(1) / 2;
    }
    for row in &rows {
        if pairs <= CLIQUE_PAIRS {
            for (a, &u) in row.iter().enumerate() {
                edges.extend(row[a + 1..].iter().map(|&v| (u, v)));
            }
        } else {
            edges.extend(row.windows(2).map(|w| (w[0], w[1])));
        }
    }
    // Rank the coordinates by the rows they appear in (then by number): the same
    // coordinates declared in another order get the same ranks, so the same order, unless
    // two of them share every row.
    let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(r, j) in &sorted {
        if j < n {
            rows_of[j].push(r);
        }
    }
    let mut by_rows: Vec<usize> = (0..n).collect();
    by_rows.sort_by(|&a, &b| rows_of[a].cmp(&rows_of[b]).then(a.cmp(&b)));
    let mut rank = vec![0; n];
    for (k, &j) in by_rows.iter().enumerate() {
        rank[j] = k;
    }
    BandOrder::ranked(n, &edges, &rank).nodes().to_vec()
}

/// A pseudo-peripheral node of `root`'s component (George & Liu's algorithm): breadth-first
/// search, move to a node of least degree on the last level while the depth grows.
fn peripheral(
    root: usize,
    start: &[usize],
    adj: &[usize],
    level: &mut [usize],
    rank: &[usize],
) -> usize {
    let mut root = root;
    let mut depth = 0;
    let mut queue = Vec::new();
    loop {
        queue.clear();
        queue.push(root);
        level[root] = 0;
        let mut head = 0;
        while head < queue.len() {
            let u = queue[head];
            head += 1;
            for &v in &adj[start[u]..start[u + 1]] {
                if level[v] == usize::MAX {
                    level[v] = level[u] + 1;
                    queue.push(v);
                }
            }
        }
        let last = level[*queue.last().unwrap_or(&root)];
        let far = queue
            .iter()
            .copied()
            .filter(|&v| level[v] == last)
            .min_by_key(|&v| (start[v + 1] - start[v], rank[v]))
            .unwrap_or(root);
        for &v in &queue {
            level[v] = usize::MAX;
        }
        if last <= depth || far == root {
            return root;
        }
        depth = last;
        root = far;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shuffled_path_gets_band_one_and_restriction_never_widens() {
        // The path 0 - 1 - ... - 29 with its nodes numbered in a scrambled order: RCM
        // recovers a band of 1 (the path itself); leaving out every fifth node keeps it at
        // most 1 among the remaining edges.
        let k = 30;
        let label = |i: usize| (i * 7) % k; // 7 is prime to 30: a permutation
        let edges: Vec<(usize, usize)> = (0..k - 1).map(|i| (label(i), label(i + 1))).collect();
        let mut order = BandOrder::new(k, &edges);
        assert_eq!((order.band(), order.size()), (1, k));
        for &(u, v) in &edges {
            let (pu, pv) = (order.position(u).unwrap(), order.position(v).unwrap());
            assert_eq!(pu.abs_diff(pv), 1);
        }
        order.restrict(|u| u % 5 != 0);
        assert_eq!(order.size(), k - 6);
        assert!(order.band() <= order.full_band());
        assert_eq!(order.position(0), None);
    }
}
