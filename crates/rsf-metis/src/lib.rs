//! METIS for the rsf crates: nested-dissection fill-reducing orderings of a graph
//! ([`node_nd`], METIS_NodeND), for the sparse factorisations whose fill an AMD ordering
//! cannot keep in bounds (3-D volumes condensed onto a fault, docs/three-d.md), and k-way
//! partitions of a graph ([`part_graph_kway`], METIS_PartGraphKway), for the mesh nodes
//! owned by each rank of a distributed run.
//!
//! METIS itself (vendored C sources, built by the `metis-sys` crate) comes with the cargo
//! feature `metis`; without it [`node_nd`] and [`part_graph_kway`] return
//! [`Error::FeatureDisabled`], so a build without the feature compiles no C. The workspace's one `unsafe` block, the call into C,
//! is in this crate's `ffi` module.
//!
//! Determinism: METIS is called with its default options and a fixed random seed
//! ([`SEED`]), one call at a time in the process (its random number generator is global C
//! state), so the same graph gives the same ordering on every run.
#![warn(missing_docs)]

#[cfg(feature = "metis")]
mod ffi;

/// The seed of METIS's random number generator in every call.
pub const SEED: i32 = 1;

/// Errors of this crate.
#[derive(Debug, thiserror::Error, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// The crate was built without its feature `metis` (rsf-tnnmg's and rsf's `metis`).
    #[error(
        "{0} needs METIS: build with the cargo feature `metis` (of rsf, rsf-tnnmg or rsf-metis)"
    )]
    FeatureDisabled(&'static str),
    /// The graph is not a valid symmetric graph without self-loops in CSR form.
    #[error("invalid graph for METIS: {0}")]
    InvalidGraph(String),
    /// More vertices or edges than METIS's 32-bit indices hold.
    #[error("graph too large for METIS's 32-bit indices ({vertices} vertices, {entries} adjacency entries)")]
    TooLarge {
        /// Number of vertices.
        vertices: usize,
        /// Number of adjacency entries (twice the edges).
        entries: usize,
    },
    /// A partition into zero parts was asked for.
    #[error("a partition needs at least one part, got {0}")]
    InvalidPartCount(usize),
    /// METIS returned an error status (METIS_ERROR_INPUT −2, METIS_ERROR_MEMORY −3,
    /// METIS_ERROR −4).
    #[error("METIS failed with status {0}")]
    Metis(i32),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Whether the crate was built with METIS (feature `metis`).
pub fn is_available() -> bool {
    cfg!(feature = "metis")
}

/// A fill-reducing nested-dissection order of the graph with adjacency `adjncy[xadj[v] ..
/// xadj[v + 1]]` of vertex `v` (`n = xadj.len() − 1` vertices; symmetric, no self-loops,
/// no repeated neighbour): `order[k]` is the vertex eliminated `k`-th (METIS_NodeND's
/// `perm`). Deterministic (module docs).
///
/// # Errors
/// [`Error::FeatureDisabled`] without the feature `metis`; [`Error::InvalidGraph`] for
/// an invalid or unsymmetric graph or a self-loop; [`Error::TooLarge`] beyond 32-bit
/// indices; [`Error::Metis`] if METIS fails (e.g. out of memory).
pub fn node_nd(xadj: &[usize], adjncy: &[usize]) -> Result<Vec<usize>> {
    check_graph(xadj, adjncy)?;
    let n = xadj.len() - 1;
    if n <= 1 {
        return Ok((0..n).collect());
    }
    Ok(node_nd_checked(xadj, adjncy, false)?.0)
}

/// A nested-dissection order of a graph with its top level: the vertices eliminated
/// first form two halves without an edge between them, then their separator.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Dissection {
    /// `order[k]` is the vertex eliminated `k`-th.
    pub order: Vec<usize>,
    /// The ends of the halves in `order`: `order[..ends[0]]` and `order[ends[0]..ends[1]]`
    /// have no edge between them; `order[ends[1]..]` is their separator, eliminated last.
    pub ends: [usize; 2],
}

/// [`node_nd`] with its top level ([`Dissection`]; METIS_NodeNDP for two processors, the
/// same multilevel nested dissection): for a factorisation whose two halves are worked on
/// independently. If METIS's top level does not split the graph (a graph too small or
/// without a balanced separator), the halves are the whole order and nothing (`ends` =
/// `[n, n]`). Deterministic (module docs).
///
/// # Errors
/// As [`node_nd`].
pub fn node_nd_halves(xadj: &[usize], adjncy: &[usize]) -> Result<Dissection> {
    check_graph(xadj, adjncy)?;
    let n = xadj.len() - 1;
    let whole = |order| Dissection {
        order,
        ends: [n, n],
    };
    if n <= 1 {
        return Ok(whole((0..n).collect()));
    }
    let (order, sizes) = node_nd_checked(xadj, adjncy, true)?;
    let ends = [sizes[0], sizes[0] + sizes[1]];
    // The halves are checked: no edge between them, both non-empty, sizes adding to n.
    let mut half = vec![0u8; n];
    for (k, &v) in order.iter().enumerate() {
        half[v] = if k < ends[0] {
            1
        } else if k < ends[1] {
            2
        } else {
            3
        };
    }
    let split = sizes[0] > 0
        && sizes[1] > 0
        && ends[1] + sizes[2] == n
        && (0..n)
            .all(|v| half[v] != 1 || adjncy[xadj[v]..xadj[v + 1]].iter().all(|&u| half[u] != 2));
    Ok(if split {
        Dissection { order, ends }
    } else {
        whole(order)
    })
}

/// A k-way partition of the graph with adjacency `adjncy[xadj[v] .. xadj[v + 1]]` of
/// vertex `v` (`n = xadj.len() − 1` vertices; symmetric, no self-loops, no repeated
/// neighbour) into `parts` parts: `part[v] < parts` is the part of vertex `v` (length n).
/// METIS_PartGraphKway with its default options: a small edge cut with parts of at most
/// 1.03 times the mean vertex count (METIS's default imbalance; a part may be empty when
/// `parts` exceeds what the graph can fill). `parts == 1` (or an empty graph) gives all
/// zeros without calling METIS. Deterministic (module docs).
///
/// # Errors
/// [`Error::InvalidPartCount`] for `parts == 0`; [`Error::InvalidGraph`] for an invalid or
/// unsymmetric graph or a self-loop; [`Error::FeatureDisabled`] without the feature
/// `metis` when `parts ≥ 2`; [`Error::TooLarge`] beyond 32-bit indices (vertices, entries
/// or parts); [`Error::Metis`] if METIS fails or returns a part out of range.
pub fn part_graph_kway(xadj: &[usize], adjncy: &[usize], parts: usize) -> Result<Vec<usize>> {
    if parts == 0 {
        return Err(Error::InvalidPartCount(parts));
    }
    check_graph(xadj, adjncy)?;
    let n = xadj.len() - 1;
    if parts == 1 || n == 0 {
        return Ok(vec![0; n]);
    }
    part_graph_kway_checked(xadj, adjncy, parts)
}

#[cfg(feature = "metis")]
fn part_graph_kway_checked(xadj: &[usize], adjncy: &[usize], parts: usize) -> Result<Vec<usize>> {
    let too_large = || Error::TooLarge {
        vertices: xadj.len() - 1,
        entries: adjncy.len(),
    };
    let to_idx = |v: &usize| i32::try_from(*v).map_err(|_| too_large());
    let mut x: Vec<i32> = xadj.iter().map(to_idx).collect::<Result<_>>()?;
    let mut a: Vec<i32> = adjncy.iter().map(to_idx).collect::<Result<_>>()?;
    let part = ffi::part_graph_kway(&mut x, &mut a, to_idx(&parts)?)?;
    // Checked, as nothing else guards it: every part in 0..parts.
    part.iter()
        .map(|&p| match usize::try_from(p) {
            Ok(p) if p < parts => Ok(p),
            _ => Err(Error::Metis(-4)),
        })
        .collect()
}

#[cfg(not(feature = "metis"))]
fn part_graph_kway_checked(_: &[usize], _: &[usize], _: usize) -> Result<Vec<usize>> {
    Err(Error::FeatureDisabled("a k-way graph partition"))
}

#[cfg(feature = "metis")]
fn node_nd_checked(
    xadj: &[usize],
    adjncy: &[usize],
    halves: bool,
) -> Result<(Vec<usize>, [usize; 3])> {
    let n = xadj.len() - 1;
    let too_large = || Error::TooLarge {
        vertices: n,
        entries: adjncy.len(),
    };
    let to_idx = |v: &usize| i32::try_from(*v).map_err(|_| too_large());
    let mut x: Vec<i32> = xadj.iter().map(to_idx).collect::<Result<_>>()?;
    let mut a: Vec<i32> = adjncy.iter().map(to_idx).collect::<Result<_>>()?;
    let (perm, sizes) = ffi::node_nd(&mut x, &mut a, halves)?;
    let order: Vec<usize> = perm.iter().map(|&v| v as usize).collect();
    let sizes = sizes.map(|s| usize::try_from(s).unwrap_or(usize::MAX));
    // METIS's result is a permutation of 0..n; checked, as nothing else guards it.
    let mut seen = vec![false; n];
    for &v in &order {
        if v >= n || std::mem::replace(&mut seen[v], true) {
            return Err(Error::Metis(-4));
        }
    }
    Ok((order, sizes))
}

#[cfg(not(feature = "metis"))]
fn node_nd_checked(_: &[usize], _: &[usize], _: bool) -> Result<(Vec<usize>, [usize; 3])> {
    Err(Error::FeatureDisabled("a nested-dissection ordering"))
}

/// Checks a CSR graph: `xadj` non-empty, starting at 0, non-decreasing, ending at
/// `adjncy.len()`; neighbours in range, no self-loops, no repeats; symmetric.
fn check_graph(xadj: &[usize], adjncy: &[usize]) -> Result<()> {
    let bad = |m: String| Err(Error::InvalidGraph(m));
    let Some((&first, _)) = xadj.split_first() else {
        return bad("xadj is empty (it has n + 1 entries)".into());
    };
    let n = xadj.len() - 1;
    if first != 0 || xadj[n] != adjncy.len() || xadj.windows(2).any(|w| w[0] > w[1]) {
        return bad("xadj must rise from 0 to adjncy.len()".into());
    }
    // Each edge (v, u) is matched by (u, v): counts of both directions agree per
    // vertex pair, checked by sorting the pairs both ways.
    let mut mark = vec![usize::MAX; n];
    let mut pairs = Vec::with_capacity(adjncy.len());
    for v in 0..n {
        for &u in &adjncy[xadj[v]..xadj[v + 1]] {
            if u >= n {
                return bad(format!("vertex {v} has neighbour {u} ≥ n = {n}"));
            }
            if u == v {
                return bad(format!("self-loop at vertex {v}"));
            }
            if mark[u] == v {
                return bad(format!("vertex {v} lists neighbour {u} twice"));
            }
            mark[u] = v;
            pairs.push((v, u));
        }
    }
    let mut reversed: Vec<(usize, usize)> = pairs.iter().map(|&(v, u)| (u, v)).collect();
    reversed.sort_unstable();
    // `pairs` is sorted by v; sort within each vertex for the comparison.
    pairs.sort_unstable();
    if pairs != reversed {
        return bad("the adjacency is not symmetric".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CSR graph of an `m × m` grid (5-point stencil).
    fn grid(m: usize) -> (Vec<usize>, Vec<usize>) {
        let (mut xadj, mut adjncy) = (vec![0], Vec::new());
        for v in 0..m * m {
            let (i, j) = (v % m, v / m);
            if j > 0 {
                adjncy.push(v - m);
            }
            if i > 0 {
                adjncy.push(v - 1);
            }
            if i + 1 < m {
                adjncy.push(v + 1);
            }
            if j + 1 < m {
                adjncy.push(v + m);
            }
            xadj.push(adjncy.len());
        }
        (xadj, adjncy)
    }

    #[test]
    fn invalid_graphs_are_refused() {
        let invalid =
            |x: &[usize], a: &[usize]| matches!(node_nd(x, a), Err(Error::InvalidGraph(_)));
        assert!(invalid(&[], &[]));
        assert!(invalid(&[1, 1], &[0]));
        assert!(invalid(&[0, 1, 1], &[1])); // 0 → 1 without 1 → 0
        assert!(invalid(&[0, 1, 2], &[0, 0])); // self-loop at 0
        assert!(invalid(&[0, 2, 4], &[1, 1, 0, 0])); // repeated neighbour
        assert!(invalid(&[0, 1, 2], &[1, 2])); // out of range
        assert!(!invalid(&[0, 1, 2], &[1, 0]));
    }

    #[test]
    fn trivial_graphs_need_no_metis() {
        assert_eq!(node_nd(&[0], &[]), Ok(vec![]));
        assert_eq!(node_nd(&[0, 0], &[]), Ok(vec![0]));
        let (x, a) = cube(3);
        assert_eq!(part_graph_kway(&x, &a, 1), Ok(vec![0; 27]));
        assert_eq!(part_graph_kway(&[0], &[], 4), Ok(vec![]));
    }

    /// The partition refuses what `node_nd` refuses, and zero parts.
    #[test]
    fn invalid_partitions_are_refused() {
        let (x, a) = cube(3);
        assert_eq!(part_graph_kway(&x, &a, 0), Err(Error::InvalidPartCount(0)));
        for parts in [1, 2] {
            let e = part_graph_kway(&[0, 1, 1], &[1], parts);
            assert!(matches!(e, Err(Error::InvalidGraph(_))), "{e:?}");
            let e = part_graph_kway(&[0, 1, 2], &[0, 0], parts);
            assert!(matches!(e, Err(Error::InvalidGraph(_))), "{e:?}");
        }
    }

    /// The CSR graph of an `m × m × m` grid (7-point stencil).
    fn cube(m: usize) -> (Vec<usize>, Vec<usize>) {
        let (mut xadj, mut adjncy) = (vec![0], Vec::new());
        let stride = [1, m, m * m];
        for v in 0..m * m * m {
            let at = [v % m, (v / m) % m, v / (m * m)];
            for axis in (0..3).rev() {
                if at[axis] > 0 {
                    adjncy.push(v - stride[axis]);
                }
            }
            for axis in 0..3 {
                if at[axis] + 1 < m {
                    adjncy.push(v + stride[axis]);
                }
            }
            xadj.push(adjncy.len());
        }
        (xadj, adjncy)
    }

    /// On a 20 × 20 × 20 grid graph, 2, 3, 4 and 8 parts: every vertex in a part below
    /// `parts`, every part non-empty and at most 1.1 times the mean size (METIS's default
    /// tolerance is 1.03), the cut edges a small share of all edges (a random assignment
    /// cuts about (parts − 1)/parts of them), the same parts on a second call.
    #[cfg(feature = "metis")]
    #[test]
    fn grid_partitions_are_balanced_and_deterministic() {
        let m = 20;
        let n = m * m * m;
        let (x, a) = cube(m);
        for parts in [2, 3, 4, 8] {
            let part = part_graph_kway(&x, &a, parts).unwrap();
            assert_eq!(part.len(), n);
            let mut size = vec![0usize; parts];
            for &p in &part {
                assert!(p < parts, "part {p} of {parts}");
                size[p] += 1;
            }
            let mean = n as f64 / parts as f64;
            for &s in &size {
                assert!(
                    s > 0 && s as f64 <= 1.1 * mean,
                    "{parts} parts: sizes {size:?}"
                );
            }
            let cut = (0..n)
                .flat_map(|v| a[x[v]..x[v + 1]].iter().map(move |&u| (v, u)))
                .filter(|&(v, u)| part[v] != part[u])
                .count();
            assert!(
                cut * 5 < a.len(),
                "{parts} parts: {cut} of {} entries cut",
                a.len()
            );
            assert_eq!(part_graph_kway(&x, &a, parts).unwrap(), part);
        }
    }

    #[cfg(not(feature = "metis"))]
    #[test]
    fn without_the_feature_the_error_names_it() {
        let (x, a) = grid(4);
        let e = node_nd(&x, &a).unwrap_err();
        assert!(matches!(e, Error::FeatureDisabled(_)));
        assert!(e.to_string().contains("feature `metis`"), "{e}");
        assert!(!is_available());
        let e = part_graph_kway(&x, &a, 2).unwrap_err();
        assert!(matches!(e, Error::FeatureDisabled(_)));
    }

    /// On a 31 × 31 grid the order is a permutation, the same bits twice, and nested
    /// dissection's: the last 31 vertices eliminated are a separator (one grid line) that
    /// splits the rest into two halves without an edge between them.
    #[cfg(feature = "metis")]
    #[test]
    fn grid_order_is_a_deterministic_dissection() {
        let m = 31;
        let (x, a) = grid(m);
        let order = node_nd(&x, &a).unwrap();
        assert!(is_available());
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..m * m).collect::<Vec<_>>());
        for _ in 0..3 {
            assert_eq!(node_nd(&x, &a).unwrap(), order);
        }
        // Components of the graph without the last m vertices of the order.
        let n = m * m;
        let mut removed = vec![false; n];
        for &v in &order[n - m..] {
            removed[v] = true;
        }
        let mut comp = vec![usize::MAX; n];
        let mut sizes = Vec::new();
        for s in 0..n {
            if removed[s] || comp[s] != usize::MAX {
                continue;
            }
            let c = sizes.len();
            let (mut stack, mut size) = (vec![s], 0);
            comp[s] = c;
            while let Some(v) = stack.pop() {
                size += 1;
                for &u in &a[x[v]..x[v + 1]] {
                    if !removed[u] && comp[u] == usize::MAX {
                        comp[u] = c;
                        stack.push(u);
                    }
                }
            }
            sizes.push(size);
        }
        assert!(sizes.len() >= 2, "components {sizes:?}");
        assert!(sizes.iter().all(|&s| s >= n / 4), "components {sizes:?}");
    }

    /// The top level of the grid's dissection: two halves of at least a quarter each
    /// without an edge between them, a separator of about one grid line, deterministic.
    #[cfg(feature = "metis")]
    #[test]
    fn grid_halves_are_uncoupled() {
        let m = 31;
        let n = m * m;
        let (x, a) = grid(m);
        let d = node_nd_halves(&x, &a).unwrap();
        let [e0, e1] = d.ends;
        assert!(
            e0 >= n / 4 && e1 - e0 >= n / 4 && n - e1 <= 2 * m,
            "{:?}",
            d.ends
        );
        let mut sorted = d.order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        let mut half = vec![0; n];
        for &v in &d.order[e0..e1] {
            half[v] = 2;
        }
        for &v in &d.order[..e0] {
            assert!(
                a[x[v]..x[v + 1]].iter().all(|&u| half[u] != 2),
                "edge from {v}"
            );
        }
        assert_eq!(node_nd_halves(&x, &a).unwrap(), d);
        // Two disconnected vertices and nothing else: no balanced split needed to be valid.
        let d = node_nd_halves(&[0, 0, 0], &[]).unwrap();
        assert!(
            d.ends == [2, 2] || d.ends[0] + (d.ends[1] - d.ends[0]) == 2,
            "{:?}",
            d.ends
        );
    }
}
