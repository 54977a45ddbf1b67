//! Uniform red refinement of simplicial meshes (`D = 1, 2, 3`) and its P1 prolongation.
//!
//! Every cell is split through its edge midpoints into `2^D` children: segments into 2,
//! triangles into 4 similar ones, tetrahedra into 4 corner tetrahedra and 4 from the inner
//! octahedron, cut along the diagonal chosen by Bey's ordering (docs/math.md §10).

use std::collections::HashMap;

use faer::sparse::{SparseColMat, Triplet};

use crate::mesh::SimplexMesh;
use crate::{Error, Result};

/// Local edges `(a, b)`, `a < b`, of a simplex in the order used by [`children`]: the
/// midpoint of edge `e` is local point `D + 1 + e`.
const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];

/// Number of edges of a `D`-simplex.
const fn num_edges(d: usize) -> usize {
    d * (d + 1) / 2
}

/// Local edge list of a `D`-simplex (pairs of vertex positions).
fn local_edges<const D: usize>() -> &'static [(usize, usize)] {
    match D {
        1 => &EDGES[..1],
        2 => &[(0, 1), (0, 2), (1, 2)],
        _ => &EDGES,
    }
}

/// Children of a cell in terms of local points (`0..=D`: the cell's vertices in refinement
/// order; `D + 1 + e`: midpoint of local edge `e`), each child's vertices in **its**
/// refinement order, with `true` where that order has the opposite orientation of the
/// parent's.
///
/// * 2D: the old vertices' corner triangles, then the middle one (all similar to the parent).
/// * 3D (Bey 1995, with `x_ij` the midpoint of `x_i x_j`): corners `(x0, x01, x02, x03)`,
///   `(x01, x1, x12, x13)`, `(x02, x12, x2, x23)`, `(x03, x13, x23, x3)`, then the octahedron
///   cut along `x02 x13`: `(x01, x02, x03, x13)`, `(x01, x02, x12, x13)`,
///   `(x02, x03, x13, x23)`, `(x02, x12, x13, x23)`. The 6th and 8th have the opposite
///   orientation of the parent.
fn children<const D: usize>() -> &'static [([usize; 4], bool)] {
    match D {
        1 => &[([0, 2, 0, 0], false), ([2, 1, 0, 0], false)],
        2 => &[
            ([0, 3, 4, 0], false),
            ([3, 1, 5, 0], false),
            ([4, 5, 2, 0], false),
            ([5, 4, 3, 0], false),
        ],
        _ => &[
            ([0, 4, 5, 6], false),
            ([4, 1, 7, 8], false),
            ([5, 7, 2, 9], false),
            ([6, 8, 9, 3], false),
            ([4, 5, 6, 8], false),
            ([4, 5, 7, 8], true),
            ([5, 6, 8, 9], false),
            ([5, 7, 8, 9], true),
        ],
    }
}

/// One red refinement. Returns the fine mesh and the scalar P1 prolongation
/// (`n_fine × n_coarse`, exact for linear functions).
///
/// Numbering: the coarse vertices keep their indices; the edge midpoints follow, ordered
/// by their edge's sorted vertex pair. The children of coarse cell `c` are the fine cells
/// `2^D·c .. 2^D·(c + 1)`, in the order of the rule above. Boundary facets inherit the tag
/// of the coarse facet they lie in. Memory: about `(D + 1)·D/2 · 24` bytes per coarse cell
/// of temporary edge keys on top of the fine mesh.
///
/// # Panics
/// If a child is degenerate (only possible for cells within a small factor of the
/// degeneracy threshold of [`SimplexMesh::new`]); use [`try_refine_red`] to get an error.
pub fn refine_red<const D: usize>(
    mesh: &SimplexMesh<D>,
) -> (SimplexMesh<D>, SparseColMat<usize, f64>) {
    try_refine_red(mesh).expect("red refinement of a valid mesh")
}

/// [`refine_red`] returning an error instead of panicking.
///
/// # Errors
/// [`crate::Error::DegenerateCell`] if a child is degenerate (the cell index is the fine
/// one, `2^D·c + k` for child `k` of coarse cell `c`).
pub fn try_refine_red<const D: usize>(
    mesh: &SimplexMesh<D>,
) -> Result<(SimplexMesh<D>, SparseColMat<usize, f64>)> {
    let nc = mesh.num_cells();
    let nv = mesh.num_vertices();
    let local = local_edges::<D>();
    let ne = num_edges(D);
    // Global edges: sorted unique vertex pairs; edge_of[ne·c + e] for local edge e of c.
    let mut keys: Vec<(usize, usize, usize)> = Vec::with_capacity(ne * nc);
    for c in 0..nc {
        let b = mesh.refinement_order(c);
        for (e, &(i, j)) in local.iter().enumerate() {
            let (p, q) = (b[i], b[j]);
            keys.push((p.min(q), p.max(q), ne * c + e));
        }
    }
    keys.sort_unstable();
    let mut edge_of = vec![0usize; ne * nc];
    let mut edges: Vec<(usize, usize)> = Vec::with_capacity(keys.len() / 2 + 3);
    for (i, &(a, b, slot)) in keys.iter().enumerate() {
        if i == 0 || (keys[i - 1].0, keys[i - 1].1) != (a, b) {
            edges.push((a, b));
        }
        edge_of[slot] = edges.len() - 1;
    }
    drop(keys);
    let x = mesh.vertices();
    let mut vertices = Vec::with_capacity(nv + edges.len());
    vertices.extend_from_slice(x);
    for &(a, b) in &edges {
        let mut m = [0.0; D];
        for r in 0..D {
            m[r] = 0.5 * (x[a][r] + x[b][r]);
        }
        vertices.push(m);
    }
    let rule = children::<D>();
    let mut cells = Vec::with_capacity((D + 1) * rule.len() * nc);
    let mut negative = Vec::with_capacity(rule.len() * nc);
    for c in 0..nc {
        let b = mesh.refinement_order(c);
        let mut point = [0usize; 10];
        point[..D + 1].copy_from_slice(&b[..D + 1]);
        for e in 0..ne {
            point[D + 1 + e] = nv + edge_of[ne * c + e];
        }
        // The refinement order of a stored (positive) cell is negative iff it is flipped.
        let parent_negative = mesh.is_flipped(c);
        for (child, flips) in rule {
            cells.extend(child[..D + 1].iter().map(|&k| point[k]));
            negative.push(parent_negative ^ flips);
        }
    }
    let mut fine = SimplexMesh::from_refinement(vertices, cells, &negative)?;
    inherit_tags(mesh, &mut fine, &edges);
    // Prolongation: identity on old vertices, ½ + ½ on midpoints.
    let mut t = Vec::with_capacity(nv + 2 * edges.len());
    for i in 0..nv {
        t.push(Triplet::new(i, i, 1.0));
    }
    for (e, &(a, b)) in edges.iter().enumerate() {
        t.push(Triplet::new(nv + e, a, 0.5));
        t.push(Triplet::new(nv + e, b, 0.5));
    }
    let p = SparseColMat::try_new_from_triplets(nv + edges.len(), nv, &t)
        .expect("valid prolongation triplets");
    Ok((fine, p))
}

/// Sorted vertex key of a facet (`D ≤ 3` entries, padded with `usize::MAX`).
fn facet_key(v: impl Iterator<Item = usize>) -> [usize; 3] {
    let mut key = [usize::MAX; 3];
    for (slot, x) in key.iter_mut().zip(v) {
        *slot = x;
    }
    key.sort_unstable();
    key
}

/// Every fine boundary facet lies in one coarse boundary facet, whose vertices are the
/// union of the fine vertices' parents (a coarse vertex is its own parent, a midpoint has
/// its edge's two ends). The fine facet gets that coarse facet's tag.
fn inherit_tags<const D: usize>(
    coarse: &SimplexMesh<D>,
    fine: &mut SimplexMesh<D>,
    edges: &[(usize, usize)],
) {
    let nv = coarse.num_vertices();
    let by_key: HashMap<[usize; 3], usize> = (0..coarse.num_boundary_facets())
        .map(|f| (facet_key(coarse.boundary_facet(f).iter().copied()), f))
        .collect();
    let tags = (0..fine.num_boundary_facets())
        .map(|f| {
            let mut parents = [usize::MAX; 6];
            let mut n = 0;
            for &v in fine.boundary_facet(f) {
                let (a, b) = if v < nv { (v, v) } else { edges[v - nv] };
                for p in [a, b] {
                    if !parents[..n].contains(&p) {
                        parents[n] = p;
                        n += 1;
                    }
                }
            }
            assert_eq!(n, D, "a fine boundary facet spans one coarse facet");
            let cf = by_key[&facet_key(parents[..n].iter().copied())];
            coarse.raw_facet_tag(cf)
        })
        .collect();
    fine.set_facet_tags(coarse.tag_names().to_vec(), tags);
}

/// The cell size `size(lo, hi)` (m) a refinement wants in the box `[lo, hi]`.
///
/// # Errors
/// [`Error::InvalidGrid`] unless it is positive (NaN included).
pub(crate) fn wanted_size(
    size: impl Fn([f64; 3], [f64; 3]) -> f64,
    lo: [f64; 3],
    hi: [f64; 3],
) -> Result<f64> {
    let wanted = size(lo, hi);
    if !(wanted > 0.0) {
        return Err(Error::InvalidGrid(format!(
            "the size function gave {wanted} m for the box {lo:?}–{hi:?}: it must be \
             positive"
        )));
    }
    Ok(wanted)
}
