//! The errors measured on a solved model against a [`Dislocation`]'s field: the jump, the
//! surface displacement in a window, the traction at the fault's inner nodes (the plus
//! copies' nodal forces over their lumped weights).

use rsf_halfspace::traction;

use super::dislocation::Dislocation;
use super::error::{ComparisonError, Result};
use crate::model::{InternalFault, Model};

/// Where and how a model is compared: `n` the fault's normal (from the minus into the
/// plus side, the hanging wall), `surface(x)` the surface vertices compared, `inner(x)`
/// the fault nodes whose traction is compared, `offset` how far off the fault a split
/// vertex of a surface trace is compared with Okada's field (on its own side).
pub(crate) struct Windows<'a> {
    pub n: [f64; 3],
    pub surface: &'a dyn Fn(&[f64; 3]) -> bool,
    pub inner: &'a dyn Fn(&[f64; 3]) -> bool,
    pub offset: f64,
}

/// The errors of `model`, whose initial displacement solves the static problem of
/// `dislocation`'s slip: `(jump, surface, traction)` as [`Errors`](super::Errors) has
/// them.
///
/// # Errors
/// The model has no fault inside the body, no node in a window, or the kernel refuses
/// a point.
pub(crate) fn measure(
    model: &Model<3>,
    dislocation: &Dislocation,
    windows: &Windows<'_>,
) -> Result<(f64, f64, f64)> {
    let f = model
        .internal_fault
        .as_ref()
        .ok_or_else(|| ComparisonError::Setup("the model has no fault inside the body".into()))?;
    let v = &model.initial_displacement;
    let u = model.to_cartesian(v)?;
    let c = Compared {
        model,
        f,
        d: dislocation,
        w: windows,
    };
    let jump = jump_error(model, f, &u, dislocation);
    let surface = surface_error(&c, &u)?;
    let traction = traction_error(&c, v)?;
    Ok((jump, surface, traction))
}

/// What [`measure`] compares: the model `model` of the fault `f` against the dislocation
/// `d` in the windows `w`.
#[derive(Clone, Copy)]
struct Compared<'a> {
    model: &'a Model<3>,
    f: &'a InternalFault<3>,
    d: &'a Dislocation,
    w: &'a Windows<'a>,
}

/// The largest `|u⁺ − u⁻ − s(x)|` over the pairs (m).
fn jump_error(model: &Model<3>, f: &InternalFault<3>, u: &[f64], d: &Dislocation) -> f64 {
    let mut jump = 0.0f64;
    for &(mi, pl) in f.pairs() {
        let slip = (d.slip_at)(model.vertices[mi]);
        for c in 0..3 {
            jump = jump.max((u[3 * pl + c] - u[3 * mi + c] - slip[c]).abs());
        }
    }
    jump
}

/// The largest `|u − u_Okada|` over the surface vertices in the window, relative to the
/// largest `|u_Okada|` there; a split vertex (a surface trace) compared with Okada's field
/// `offset` off the fault on its own side.
fn surface_error(c: &Compared<'_>, u: &[f64]) -> Result<f64> {
    let Compared { model, f, d, w } = *c;
    let (mut err, mut scale) = (0.0f64, 0.0f64);
    let mut seen = 0;
    for (q, x) in model.vertices.iter().enumerate() {
        if !(w.surface)(x) {
            continue;
        }
        let mut point = *x;
        if let Some((_, pl)) = f.pair_of(q) {
            let side = if q == pl { 1.0 } else { -1.0 };
            for c in 0..3 {
                point[c] += side * w.offset * w.n[c];
            }
        }
        let uo = d.at(point)?.u;
        let e = (0..3).fold(0.0f64, |m, c| m.hypot(u[3 * q + c] - uo[c]));
        err = err.max(e);
        scale = scale.max(uo.iter().fold(0.0f64, |m, c| m.hypot(*c)));
        seen += 1;
    }
    if seen == 0 || !(scale > 0.0) {
        return Err(ComparisonError::Setup(
            "no surface vertex with a displacement in the window".into(),
        ));
    }
    Ok(err / scale)
}

/// The largest `|t_FE − σ_Okada (−n)|` over the inner fault nodes, relative to the largest
/// `|σ_Okada (−n)|` there: at a pair the residual of the prescribed jump components is
/// `f'_j = Rᵀ f⁺` (the plus copy's force; `f⁺ + f⁻ = 0` at equilibrium, whatever the
/// sharing of the jump), `f⁺ = ∫ φ σ n⁺_out dS` with the plus side's outward normal
/// `−n`, so `t_FE = R f'_j / w` (`w` the node's lumped weight).
fn traction_error(c: &Compared<'_>, v: &[f64]) -> Result<f64> {
    let Compared { model, f, d, w } = *c;
    let mut force = vec![0.0; v.len()];
    rsf_fem::spmv_add(model.stiffness.as_ref(), 1.0, v, &mut force);
    let weights = fault_weights(model, f);
    let n_out = w.n.map(|c| -c);
    let (mut err, mut scale) = (0.0f64, 0.0f64);
    let mut inner = 0;
    for (k, &(mi, _)) in f.pairs().iter().enumerate() {
        let x = model.vertices[mi];
        if !(w.inner)(&x) {
            continue;
        }
        inner += 1;
        let r = f.transform.frames[k];
        let fj = [force[3 * mi], force[3 * mi + 1], force[3 * mi + 2]];
        let t_fe: [f64; 3] =
            std::array::from_fn(|i| (0..3).map(|a| r[i][a] * fj[a]).sum::<f64>() / weights[mi]);
        let grad = d.at(x)?.grad;
        let t_ok = traction(&d.medium.stress(&grad), &n_out);
        let e = (0..3).fold(0.0f64, |m, c| m.hypot(t_fe[c] - t_ok[c]));
        err = err.max(e);
        scale = scale.max(t_ok.iter().fold(0.0f64, |m, c| m.hypot(*c)));
    }
    if inner == 0 || !(scale > 0.0) {
        return Err(ComparisonError::Setup(
            "no inner fault node with a traction to compare".into(),
        ));
    }
    Ok(err / scale)
}

/// Per vertex, its lumped weight (m²) on the fault: a third of the area of every fault
/// triangle of the minus side it is a corner of (0 off the fault). A fault triangle of the
/// minus side is a face of a cell whose three corners are fault nodes — minus vertices of
/// split pairs or the rim's shared tips, all in the fault's plane — at least one of them a
/// minus vertex (only the minus side's cells hold those; a face of three tips, at a
/// corner of the rim, is left out: its weight is not used).
pub(crate) fn fault_weights(model: &Model<3>, f: &InternalFault<3>) -> Vec<f64> {
    let mut w = vec![0.0; model.num_nodes()];
    let (mut on_fault, mut minus) = (vec![false; w.len()], vec![false; w.len()]);
    for &(m, p) in f.faults().iter().flat_map(|s| s.nodes()) {
        on_fault[m] = true;
        minus[m] = m != p;
    }
    for cell in model.cells.chunks_exact(4) {
        let corners: Vec<usize> = cell.iter().copied().filter(|&q| on_fault[q]).collect();
        if !corners.iter().any(|&q| minus[q]) {
            continue;
        }
        if let [p, q, r] = corners[..] {
            let (x, y, z) = (model.vertices[p], model.vertices[q], model.vertices[r]);
            let d1: [f64; 3] = std::array::from_fn(|c| y[c] - x[c]);
            let d2: [f64; 3] = std::array::from_fn(|c| z[c] - x[c]);
            let n = [
                d1[1] * d2[2] - d1[2] * d2[1],
                d1[2] * d2[0] - d1[0] * d2[2],
                d1[0] * d2[1] - d1[1] * d2[0],
            ];
            let third = 0.5 * n.iter().map(|c| c * c).sum::<f64>().sqrt() / 3.0;
            for v in [p, q, r] {
                w[v] += third;
            }
        }
    }
    w
}
