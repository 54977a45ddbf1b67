//! The block tree: admissible and near-field blocks of the cluster tree's product
//! (docs/math.md §13.2).

use crate::cluster::ClusterTree;

/// A leaf of the block tree: rows `row..row + nrows`, columns `col..col + ncols` of the
/// matrix in cluster order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct BlockShape {
    /// First row (cluster order).
    pub row: usize,
    /// Number of rows.
    pub nrows: usize,
    /// First column (cluster order).
    pub col: usize,
    /// Number of columns.
    pub ncols: usize,
    /// Whether the block is admissible (far field).
    pub admissible: bool,
}

/// The leaves of the block tree, sorted by first row, then first column: a pair of
/// clusters is a leaf if it is admissible, `min(diam τ, diam σ) ≤ η dist(τ, σ)` with
/// `dist(τ, σ) > 0`, or if either cluster is a leaf of the cluster tree (near field);
/// otherwise its four pairs of sons are visited.
pub(crate) fn partition(tree: &ClusterTree, eta: f64) -> Vec<BlockShape> {
    let mut out = Vec::new();
    if !tree.nodes.is_empty() {
        visit(tree, eta, 0, 0, &mut out);
    }
    out.sort_by_key(|b| (b.row, b.col));
    out
}

fn visit(tree: &ClusterTree, eta: f64, t: usize, s: usize, out: &mut Vec<BlockShape>) {
    let (ct, cs) = (&tree.nodes[t], &tree.nodes[s]);
    let dist = ct.dist(cs);
    let admissible = dist > 0.0 && ct.diam().min(cs.diam()) <= eta * dist;
    match (admissible, ct.sons, cs.sons) {
        (false, Some((t1, t2)), Some((s1, s2))) => {
            for &(a, b) in &[(t1, s1), (t1, s2), (t2, s1), (t2, s2)] {
                visit(tree, eta, a, b, out);
            }
        }
        _ => out.push(BlockShape {
            row: ct.start,
            nrows: ct.len(),
            col: cs.start,
            ncols: cs.len(),
            admissible,
        }),
    }
}
