//! The frictional nodes of a model as the half-space operators see them: position, the
//! two slip directions of the model's unknowns and the normal into the plus side.

use faer::Mat;
use rsf_linalg::Parallelism;

use super::error::HalfSpaceOperatorError;
use crate::error::Result;
use crate::fault_operator::{FaultOperator, MAX_KERNEL_EPSILON, MIN_KERNEL_EPSILON};
use crate::model::Model;

/// A frictional node: its position, `t₁`, `t₂` and the normal into the plus side.
pub(super) type Node = ([f64; 3], [f64; 3], [f64; 3], [f64; 3]);

/// The frictional nodes of `model`'s internal fault: position, `t₁`, `t₂` (the pair
/// frame's tangents) and the normal into the plus side, in `frictional_boundary` order.
///
/// # Errors
/// [`HalfSpaceOperatorError::NoInternalFault`], [`HalfSpaceOperatorError::NotAPair`],
/// [`HalfSpaceOperatorError::Components`] (not exactly the two tangential components free).
pub(super) fn internal_fault_nodes(
    model: &Model<3, 3>,
) -> std::result::Result<Vec<Node>, HalfSpaceOperatorError> {
    use HalfSpaceOperatorError as E;
    let fault = model.internal_fault.as_ref().ok_or(E::NoInternalFault)?;
    let fb = &model.frictional_boundary;
    let pairs = fault.pairs();
    let mut pair_index = std::collections::HashMap::with_capacity(pairs.len());
    for (i, &(minus, _)) in pairs.iter().enumerate() {
        pair_index.insert(minus, i);
    }
    // Per node: position, t₁, t₂, n (the minus side's outward normal, into the plus side).
    let mut nodes = Vec::with_capacity(fb.len());
    for (k, &p) in fb.nodes.iter().enumerate() {
        let i = *pair_index
            .get(&p)
            .ok_or(E::NotAPair { node: k, vertex: p })?;
        let free: [bool; 3] = std::array::from_fn(|c| !model.fixed[3 * p + c]);
        if free != [true, true, false] {
            return Err(E::Components {
                node: k,
                vertex: p,
                free,
            });
        }
        let r = fault.transform.frames[i];
        let col = |c: usize| [r[0][c], r[1][c], r[2][c]];
        nodes.push((model.vertices[p], col(0), col(1), col(2).map(|x| -x)));
    }
    Ok(nodes)
}

/// The frictional nodes of a fault alone ([`Model::fault_only`]): position, the two free
/// Cartesian axes in increasing order and the fixed one (the normal).
///
/// # Errors
/// [`HalfSpaceOperatorError::NotAlone`] for a model with a stiffness, an internal fault
/// or nodal frames; [`HalfSpaceOperatorError::Components`] for a node without exactly one
/// fixed component.
pub(super) fn alone_nodes(
    model: &Model<3, 3>,
) -> std::result::Result<Vec<Node>, HalfSpaceOperatorError> {
    use HalfSpaceOperatorError as E;
    if model.stiffness.compute_nnz() != 0
        || model.internal_fault.is_some()
        || !model.frames.nodes.is_empty()
    {
        return Err(E::NotAlone);
    }
    let fb = &model.frictional_boundary;
    let axis = |c: usize| {
        let mut e = [0.0; 3];
        e[c] = 1.0;
        e
    };
    let mut nodes = Vec::with_capacity(fb.len());
    for (k, &p) in fb.nodes.iter().enumerate() {
        let free: [bool; 3] = std::array::from_fn(|c| !model.fixed[3 * p + c]);
        let tangential: Vec<usize> = (0..3).filter(|&c| free[c]).collect();
        let Some(normal) = (0..3).find(|&c| !free[c]).filter(|_| tangential.len() == 2) else {
            return Err(E::Components {
                node: k,
                vertex: p,
                free,
            });
        };
        nodes.push((
            model.vertices[p],
            axis(tangential[0]),
            axis(tangential[1]),
            axis(normal),
        ));
    }
    Ok(nodes)
}

/// `s_e = A_k j_k` for every node `k` (its element `element[k]`, `A_k = map[k]`; `j_k` the
/// node's two slip unknowns in `x`): the elements' strike and dip slip.
pub(super) fn scatter(element: &[usize], map: &[[[f64; 2]; 2]], x: &[f64], s: &mut [f64]) {
    for (k, (&e, a)) in element.iter().zip(map).enumerate() {
        let j = [x[2 * k], x[2 * k + 1]];
        s[2 * e] = a[0][0] * j[0] + a[0][1] * j[1];
        s[2 * e + 1] = a[1][0] * j[0] + a[1][1] * j[1];
    }
}

/// `r_k += w_k A_kᵀ y_e` for every node `k`, with `y = −K s` by element.
pub(super) fn gather(
    element: &[usize],
    map: &[[[f64; 2]; 2]],
    weights: &[f64],
    y: &[f64],
    r: &mut [f64],
) {
    for (k, (&e, a)) in element.iter().zip(map).enumerate() {
        let w = weights[k];
        let y = [y[2 * e], y[2 * e + 1]];
        r[2 * k] += w * (a[0][0] * y[0] + a[1][0] * y[1]);
        r[2 * k + 1] += w * (a[0][1] * y[0] + a[1][1] * y[1]);
    }
}

/// The diagonal of `S = W Aᵀ K A` from the kernel's 2 × 2 element blocks: entry `2k + i`
/// is `w_k Σ_ab A_k[a][i] K_ee[a][b] A_k[b][i]`, `e` node `k`'s element.
///
/// # Errors
/// The kernel's ([`Kernel::diagonal_blocks`]); an `out` of another length.
pub(super) fn diagonal_of(
    kernel: &crate::fault_kernel::Kernel,
    element: &[usize],
    map: &[[[f64; 2]; 2]],
    weights: &[f64],
    out: &mut [f64],
) -> Result<()> {
    crate::fault_operator::check_diagonal(2 * element.len(), out)?;
    let blocks = kernel.diagonal_blocks(2)?;
    for (k, ((&e, a), &w)) in element.iter().zip(map).zip(weights).enumerate() {
        let kb = &blocks[4 * e..4 * e + 4];
        for i in 0..2 {
            let mut s = 0.0;
            for p in 0..2 {
                for q in 0..2 {
                    s += a[p][i] * kb[2 * p + q] * a[q][i];
                }
            }
            out[2 * k + i] = w * s;
        }
    }
    Ok(())
}

/// The dense `S` of `op` (`m × m`, N/m), one product per column.
///
/// # Errors
/// Those of the product.
pub(super) fn dense_of(op: &mut dyn FaultOperator) -> Result<Mat<f64>> {
    let m = op.dim();
    let mut out = Mat::zeros(m, m);
    let mut x = vec![0.0; m];
    let mut r = vec![0.0; m];
    for j in 0..m {
        x[j] = 1.0;
        r.fill(0.0);
        op.subtract_product(&x, &mut r, Parallelism::SEQ)?;
        for i in 0..m {
            out[(i, j)] = -r[i];
        }
        x[j] = 0.0;
    }
    Ok(out)
}

/// The ℋ-kernel's options of either operator: `epsilon` in
/// `[MIN_KERNEL_EPSILON, MAX_KERNEL_EPSILON]`,
/// `leaf_size` at least 1.
///
/// # Errors
/// [`HalfSpaceOperatorError::Options`] naming the option.
pub(super) fn check_kernel(
    epsilon: f64,
    leaf_size: usize,
) -> std::result::Result<(), HalfSpaceOperatorError> {
    use HalfSpaceOperatorError as E;
    if !(MIN_KERNEL_EPSILON..=MAX_KERNEL_EPSILON).contains(&epsilon) {
        return Err(E::Options {
            name: "epsilon",
            value: epsilon,
            expected: "in [1e-14, 1e-2]",
        });
    }
    if leaf_size == 0 {
        return Err(E::Options {
            name: "leaf_size",
            value: 0.0,
            expected: "at least 1",
        });
    }
    Ok(())
}
