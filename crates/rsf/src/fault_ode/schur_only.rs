//! A fault ODE's set-up without the volume's whole factor (issue 70; docs/three-d.md, "The
//! condensation without the whole factor"): the Schur complement `S`, the condensed loads
//! `g₀`, `g₁` and the rows of the watched vertices computed by one multifrontal elimination
//! that keeps no factor column ([`rsf_direct::SchurOnly`]), then `S` stored as the
//! [`FaultKernel`](super::FaultKernel) says. What is given up: the volume between steps
//! (an observer that [reads the volume](crate::Observer::reads_volume) is refused; the
//! vertices observers read are given before the set-up, [`SchurOnlySetup::watch_vertices`])
//! and a normal stress from slip (`S_N` needs the factor's extension).

use rsf_direct::{RightHandSide, SchurOnly, SchurOnlyOptions};

use super::options::FaultOdeOptions;
use crate::error::{invalid, Result};
use crate::fault_alone::SchurOnlySetup;
use crate::fault_kernel::{condensed_operator, CondensedOperator, SchurSource};
use crate::model::Model;
use crate::volume_probe::{probe_dofs, VolumeProbe};

/// What the Schur-only set-up gives the fault ODE.
pub(super) struct SchurOnlyBody {
    /// The dof of every slip unknown (the order of [`rsf_direct::Condensation`]'s).
    pub dofs: Vec<usize>,
    /// `S` as the options' kernel.
    pub operator: CondensedOperator,
    /// The condensed load with the fixed dofs at `u₀`.
    pub g0: Vec<f64>,
    /// The condensed unit Dirichlet velocities.
    pub g1: Vec<f64>,
    /// The watched vertices' probe (`None` without watched vertices).
    pub probe: Option<VolumeProbe>,
}

/// The Schur-only set-up of `model` (`velocity_factor` the Dirichlet factors, length `n`).
///
/// # Errors
/// [`crate::Error::InvalidParameter`] named `volume_vertices` for a vertex not the model's;
/// the elimination's ([`crate::Error::Direct`]: not positive definite, too large, a
/// checkpoint of another problem, stopped); the kernel's.
pub(super) fn condense<const D: usize, const C: usize>(
    model: &Model<D, C>,
    options: &FaultOdeOptions,
    velocity_factor: &[f64],
    mut setup: SchurOnlySetup,
) -> Result<SchurOnlyBody> {
    let fb = &model.frictional_boundary;
    let n = model.num_dofs();
    let mut vertices = setup.watch_vertices.clone();
    vertices.sort_unstable();
    vertices.dedup();
    // The slip unknowns: the free components of the fault's nodes.
    let interface: Vec<usize> = fb
        .nodes
        .iter()
        .flat_map(|&p| C * p..C * p + C)
        .filter(|&i| !model.fixed[i])
        .collect();
    let extras = probe_dofs(model, &interface, &vertices)?;
    let elimination = SchurOnly::<C>::new(
        model.stiffness.as_ref(),
        &model.fixed,
        &fb.nodes,
        &extras,
        options.ordering,
    )?;
    let zeros = vec![0.0; n];
    let rhs = [
        RightHandSide {
            b: &model.load,
            x_fixed: &model.initial_displacement,
        },
        RightHandSide {
            b: &zeros,
            x_fixed: velocity_factor,
        },
    ];
    let elimination_options = SchurOnlyOptions {
        max_bytes: setup.max_bytes,
        checkpoint: setup.checkpoint.take(),
    };
    let kept = match setup.progress.as_mut() {
        Some(progress) => elimination.eliminate_with(&rhs, &elimination_options, progress)?,
        None => elimination.eliminate(&rhs, &elimination_options)?,
    };
    drop(elimination);
    let onto = kept.onto_interface()?;
    if onto.interface_dofs() != interface.as_slice() {
        return Err(invalid(
            "frictional_boundary",
            "the Schur complement's unknowns are not the fault's free components in order \
             (an internal inconsistency)",
        ));
    }
    let operator = condensed_operator(
        model,
        &SchurSource::Packed {
            s: onto.schur(),
            dofs: onto.interface_dofs(),
        },
        options.kernel,
    )?;
    let (g0, g1) = (
        onto.condensed_rhs()[0].clone(),
        onto.condensed_rhs()[1].clone(),
    );
    let probe = (!vertices.is_empty()).then(|| {
        let rows = onto.extras();
        VolumeProbe::from_rows(
            &vertices,
            rows.dofs().to_vec(),
            rows.matrix().to_vec(),
            rows.offset(0).to_vec(),
            rows.offset(1).to_vec(),
        )
    });
    Ok(SchurOnlyBody {
        dofs: interface,
        operator,
        g0,
        g1,
        probe,
    })
}
