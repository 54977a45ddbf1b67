//! The files of a fault inside a finite-element volume: BP5's ([`SeasBp5Output::for_volume`])
//! and the square's of BP7 and BP8 ([`SeasBp5Output::bp7_volume`],
//! [`SeasBp5Output::bp8_volume`]) — the fault's frictional nodes on their grid
//! ([`FaultLayout::of_volume`]), the off-fault stations at the mesh vertices nearest them.

use std::path::Path;
use std::sync::Arc;

use rsf::pore_pressure::PorePressure;
use rsf::Model;

use super::layout::{BodySource, FaultLayout, NodeGrid};
use super::{
    bp5_body_station_points, bp5_spec, bp7_body_station_points, spec, SeasBp5Output,
    StrikeDipFault, SEAS_BP7_RESUME_LOG, SEAS_BP8_RESUME_LOG,
};
use crate::error::Result;
use crate::setup::SeasSetup;

impl SeasBp5Output {
    /// BP7's files of a square fault `|x₂|, |x₃| ≤ region.length/2` in a finite-element
    /// volume `model` (`rsf_scenes::SeasBp7::fe_model`: the model's `z` the benchmark's
    /// `x₃`, the plane creeping outside the square) with node spacing `dx` on the fault,
    /// into `dir`, as [`bp7`](Self::bp7) for `r_vw` and `setup`: the fault's frictional
    /// nodes fill the square's grid, rim included, `(2 l_f/dx + 1)²` of them; the
    /// off-fault stations at the mesh vertices nearest them (read through
    /// [`Observer::volume_vertices`](rsf::Observer::volume_vertices)).
    ///
    /// # Errors
    /// As [`for_volume`](Self::for_volume).
    pub fn bp7_volume(
        dir: &Path,
        region: &StrikeDipFault,
        model: &Model<3, 3>,
        (dx, r_vw): (f64, f64),
        setup: SeasSetup,
    ) -> Result<Self> {
        let per_side = (region.length / dx).round() as usize + 1;
        let half = 0.5 * region.length;
        let grid = NodeGrid {
            origin: [-half, -half],
            spacing: dx,
            n: [per_side, per_side],
            z_sign: 1.0,
        };
        let layout = FaultLayout::of_volume(model, grid)?;
        let body = bp7_body_station_points()
            .iter()
            .map(|x| model.nearest_node(x).map(BodySource::Vertex))
            .collect::<rsf::Result<_>>()?;
        let mut out = Self::build(dir, region, layout, (body, spec::bp7(r_vw)), setup)?;
        out.log_name = SEAS_BP7_RESUME_LOG;
        Ok(out)
    }

    /// The output of the fault `region` on its finite-element volume model `model`
    /// (`rsf_scenes::SeasBp5::fe_model` with spacing `dx` on the fault) into `dir`: the on-fault
    /// stations from the frictional nodes (the grid of spacing `dx` over the
    /// rate-and-state region; slip and slip rate the jump of each split pair in Cartesian
    /// components), the off-fault stations at the mesh vertices nearest them (read
    /// through [`Observer::volume_vertices`](rsf::Observer::volume_vertices)).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `model` for a
    /// model without an internal fault or whose frictional nodes do not fill the grid; I/O
    /// errors creating `dir`. (`rsf_scenes::SeasBp5::volume_output` makes BP5's.)
    pub fn for_volume(
        dir: &Path,
        region: &StrikeDipFault,
        model: &Model<3, 3>,
        dx: f64,
        setup: SeasSetup,
    ) -> Result<Self> {
        let grid = NodeGrid {
            origin: [-0.5 * region.length, 0.0],
            spacing: dx,
            n: [
                (region.length / dx).round() as usize + 1,
                (region.width / dx).round() as usize + 1,
            ],
            z_sign: -1.0,
        };
        let layout = FaultLayout::of_volume(model, grid)?;
        let body = bp5_body_station_points()
            .iter()
            .map(|x| model.nearest_node(x).map(BodySource::Vertex))
            .collect::<rsf::Result<_>>()?;
        let spec = bp5_spec(&layout);
        Self::build(dir, region, layout, (body, spec), setup)
    }

    /// BP8's files of a square fault `|x₂|, |x₃| ≤ region.length/2` in a finite-element
    /// volume `model` (`rsf_scenes::SeasBp8::fe_model`: the model's `z` the benchmark's
    /// `x₃`) with node spacing `dx` on the fault, into `dir`, as [`bp8`](Self::bp8) for
    /// `pressure` and `setup`: the fault's nodes are the split pairs inside the square (its
    /// rim a shared tip, whose slip is 0), `(2 l_f/dx − 1)²` of them, slip and slip rate
    /// the jump of each pair; stations and profiles interpolate them bilinearly (constant
    /// beyond the outermost pairs, as [`bp8`](Self::bp8) beyond the outermost cells).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `model` for a
    /// model without an internal fault or whose frictional nodes do not fill the square's
    /// inner grid; `date` as [`new`](Self::new); I/O errors creating `dir`.
    pub fn bp8_volume(
        dir: &Path,
        region: &StrikeDipFault,
        model: &Model<3, 3>,
        dx: f64,
        pressure: Arc<dyn PorePressure<3>>,
        setup: SeasSetup,
    ) -> Result<Self> {
        let layout = FaultLayout::of_volume(model, square_inner_grid(region, dx))?;
        let mut out = Self::build(dir, region, layout, (Vec::new(), spec::bp8()), setup)?;
        out.pressure = Some(pressure);
        out.log_name = SEAS_BP8_RESUME_LOG;
        Ok(out)
    }
}

/// The grid of a square fault's split pairs in a volume: the nodes of spacing `dx` strictly
/// inside `|x₂|, |x₃| ≤ region.length/2` (the rim is a tip), the model's `z` the `x₃`.
fn square_inner_grid(region: &StrikeDipFault, dx: f64) -> NodeGrid {
    let half = 0.5 * region.length;
    let per_side = ((region.length / dx).round() as usize).saturating_sub(1);
    NodeGrid {
        origin: [dx - half, dx - half],
        spacing: dx,
        n: [per_side, per_side],
        z_sign: 1.0,
    }
}
