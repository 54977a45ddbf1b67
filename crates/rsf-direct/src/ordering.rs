//! The ordering of a condensation's interior: AMD after one home-made level of dissection
//! (partial_cholesky/), or METIS's nested dissection (crate rsf-metis, feature `metis`).

use crate::error::{Error, Result};
use rsf_linalg::Csc;
use rsf_nonsmooth::ProblemError;

/// How the interior `R` of a [`Condensation`](crate::Condensation) is ordered for its
/// sparse Cholesky factor (the interface `F` is always eliminated last, which makes the
/// Schur complement the factor's last block). Both split `R` into two halves without
/// coupling and their separator, `[R₁, R₂, C, F]`, whose halves each sweep works on
/// independently (two threads); they differ in the fill of the factor, not in what it
/// represents: the Schur complement and the solves agree to round-off.
///
/// Its [`Display`](std::fmt::Display) and [`FromStr`](std::str::FromStr) names are `amd`
/// and `nested-dissection`; with the `serde` feature it reads and writes as those.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum InteriorOrdering {
    /// The separator is a middle level of a breadth-first search from a pseudo-peripheral
    /// dof, and each of `R₁`, `R₂`, `C` is in faer's AMD order. The default; its results
    /// are those of every earlier version.
    #[default]
    Amd,
    /// METIS's multilevel nested dissection (METIS_NodeNDP: its top-level separator gives
    /// `R₁`, `R₂`, `C`, and its recursion their orders) of the graph of the nodes (blocks of
    /// `D` dofs) with an interior dof, expanded to their interior dofs in component order.
    /// Much less fill than [`Amd`](Self::Amd) on 3-D volumes (docs/three-d.md, "The
    /// operator at scale"). Deterministic (a fixed seed). Needs the cargo feature `metis`
    /// (of rsf-direct, or rsf's `metis`); without it a condensation asking for it fails with
    /// [`Error::FeatureDisabled`].
    NestedDissection,
}

impl InteriorOrdering {
    /// The fastest ordering this build has: [`NestedDissection`](Self::NestedDissection)
    /// where METIS is built (feature `metis`, `rsf_metis::is_available`), else
    /// [`Amd`](Self::Amd). The programs' default: nested dissection fills in far less on
    /// 3-D volumes (BP5's graded volume at 1 km: the elimination's peak 7.30 GB with AMD,
    /// docs/seas-bp5.md).
    pub fn fastest_built() -> Self {
        if rsf_metis::is_available() {
            Self::NestedDissection
        } else {
            Self::Amd
        }
    }
}

impl std::fmt::Display for InteriorOrdering {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Amd => "amd",
            Self::NestedDissection => "nested-dissection",
        })
    }
}

impl std::str::FromStr for InteriorOrdering {
    type Err = Error;

    /// `amd` or `nested-dissection` (the [`Display`](std::fmt::Display) names).
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "amd" => Ok(Self::Amd),
            "nested-dissection" => Ok(Self::NestedDissection),
            _ => Err(ProblemError::InvalidOption(format!(
                "interior ordering `{s}`: expected amd or nested-dissection"
            ))
            .into()),
        }
    }
}

/// METIS's nested dissection of the dofs `interior` of `a` (node graph, `node` dofs per
/// node): the interior dofs in elimination order and the ends `p1`, `p2` of the halves
/// `R₁ = ..p1`, `R₂ = p1..p2` (the separator `C = p2..`).
pub(super) fn nested_dissection(
    a: &Csc,
    interior: &[usize],
    node: usize,
) -> Result<(Vec<usize>, usize, usize)> {
    if interior.is_empty() {
        return Ok((Vec::new(), 0, 0));
    }
    let n = a.nrows;
    let mut inside = vec![false; n];
    for &i in interior {
        inside[i] = true;
    }
    // The nodes with an interior dof, numbered in increasing order.
    let mut local = vec![usize::MAX; n.div_ceil(node)];
    let mut nodes = Vec::new();
    for i in (0..n).filter(|&i| inside[i]) {
        if local[i / node] == usize::MAX {
            local[i / node] = nodes.len();
            nodes.push(i / node);
        }
    }
    // Their graph: p ~ q when a couples an interior dof of p with one of q (p ≠ q).
    let mut xadj = Vec::with_capacity(nodes.len() + 1);
    let mut adjncy = Vec::new();
    let mut mark = vec![usize::MAX; nodes.len()];
    xadj.push(0);
    for (k, &p) in nodes.iter().enumerate() {
        mark[k] = k;
        for j in (node * p..(node * p + node).min(n)).filter(|&j| inside[j]) {
            for &i in a.col(j).0 {
                if inside[i] {
                    let q = local[i / node];
                    if mark[q] != k {
                        mark[q] = k;
                        adjncy.push(q);
                    }
                }
            }
        }
        xadj.push(adjncy.len());
    }
    let dissection = rsf_metis::node_nd_halves(&xadj, &adjncy).map_err(|e| match e {
        rsf_metis::Error::FeatureDisabled(what) => Error::FeatureDisabled {
            what,
            feature: "metis",
        },
        e => Error::Factorisation(e.to_string()),
    })?;
    // Expand to dofs; the ends move with the dofs of the nodes before them.
    let mut order = Vec::with_capacity(interior.len());
    let mut ends = [0; 2];
    for (k, &v) in dissection.order.iter().enumerate() {
        for (e, &end) in ends.iter_mut().zip(&dissection.ends) {
            if k == end {
                *e = order.len();
            }
        }
        let p = nodes[v];
        order.extend((node * p..(node * p + node).min(n)).filter(|&j| inside[j]));
    }
    for (e, &end) in ends.iter_mut().zip(&dissection.ends) {
        if end == dissection.order.len() {
            *e = order.len();
        }
    }
    Ok((order, ends[0], ends[1]))
}

#[cfg(all(test, feature = "metis"))]
mod tests {
    use super::*;

    /// The pattern of the 5-point `m × m` grid (values 1; only the pattern is read).
    fn grid(m: usize) -> Csc {
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for j in 0..m * m {
            let (x, y) = (j % m, j / m);
            let below = [(y > 0, j.wrapping_sub(m)), (x > 0, j.wrapping_sub(1))];
            let above = [(x + 1 < m, j + 1), (y + 1 < m, j + m)];
            row_idx.extend(below.iter().filter(|e| e.0).map(|e| e.1));
            row_idx.push(j);
            row_idx.extend(above.iter().filter(|e| e.0).map(|e| e.1));
            col_ptr.push(row_idx.len());
        }
        Csc {
            nrows: m * m,
            ncols: m * m,
            val: vec![1.0; row_idx.len()],
            col_ptr,
            row_idx,
        }
    }

    /// On a 40 × 40 grid with nodes of two dofs (consecutive pairs), a row of dofs left out
    /// and one odd dof out of a node: the order is a permutation of the interior, each
    /// node's interior dofs side by side in increasing order, the halves uncoupled and not
    /// empty, and a second run gives the same order.
    #[test]
    fn nested_dissection_is_a_deterministic_permutation_with_uncoupled_halves() {
        let m = 40;
        let a = grid(m);
        let interior: Vec<usize> = (0..m * m).filter(|&i| i / m != 7 && i != 301).collect();
        let (order, p1, p2) = nested_dissection(&a, &interior, 2).unwrap();
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, interior);
        for w in order.windows(2) {
            if w[0] / 2 == w[1] / 2 {
                assert!(w[0] < w[1]);
            }
        }
        let mut part = vec![0; a.nrows];
        for (k, &i) in order.iter().enumerate() {
            part[i] = if k < p1 {
                1
            } else if k < p2 {
                2
            } else {
                3
            };
        }
        assert!(
            0 < p1 && p1 < p2 && p2 < order.len(),
            "{p1} {p2} {}",
            order.len()
        );
        for &j in &order[..p1] {
            assert!(a.col(j).0.iter().all(|&i| part[i] != 2), "dof {j}");
        }
        assert_eq!(
            nested_dissection(&a, &interior, 2).unwrap(),
            (order, p1, p2)
        );
        assert_eq!(nested_dissection(&a, &[], 2).unwrap(), (vec![], 0, 0));
    }
}
