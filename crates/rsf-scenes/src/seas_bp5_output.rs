//! BP5's output files (the crate `rsf-seas`'s strike–dip layout) on its fault: the
//! rate-and-state region and the physics the files need, the grid of a fault alone, the
//! finite-element volume model.

use std::path::Path;

use rsf::{Model, Result};
use rsf_seas::{SeasBp5Output, SeasSetup, StrikeDipFault};

use crate::seas_bp5::SeasBp5;

impl SeasBp5 {
    /// The fault as BP5's output sees it: the rate-and-state region `l_f × W_f`, the
    /// shear modulus, the radiation damping and the plate rate.
    pub fn output_fault(&self) -> StrikeDipFault {
        StrikeDipFault {
            length: self.l_f,
            width: self.w_f,
            shear_modulus: self.fault_shear_modulus(),
            radiation_damping: self.radiation_damping(),
            plate_rate: self.v_p,
        }
    }

    /// The output of this fault alone on the grid of size `dx` ([`cells`](Self::cells))
    /// into `dir` (created if missing): `body_columns` the displacement columns of
    /// [`SEAS_BP5_BODY_STATIONS`](crate::SEAS_BP5_BODY_STATIONS) (from
    /// [`fault_ode_with_stations`](Self::fault_ode_with_stations) with
    /// [`body_station_points`](Self::body_station_points)), `setup` the headers' problem,
    /// modeler, date and element size and the sampling ([`SeasBp5Output::new`]).
    ///
    /// # Errors
    /// Invalid parameters or grid; those of [`SeasBp5Output::new`].
    pub fn output(
        &self,
        dir: &Path,
        dx: f64,
        body_columns: Vec<Vec<f64>>,
        setup: SeasSetup,
    ) -> Result<SeasBp5Output> {
        let cells = self.cells(dx)?;
        Ok(SeasBp5Output::new(
            dir,
            &self.output_fault(),
            dx,
            cells,
            body_columns,
            setup,
        )?)
    }

    /// The output of this fault on its finite-element volume model `model`
    /// ([`fe_model`](Self::fe_model) with spacing `dx` on the fault) into `dir`
    /// ([`SeasBp5Output::for_volume`]).
    ///
    /// # Errors
    /// Those of [`SeasBp5Output::for_volume`].
    pub fn volume_output(
        &self,
        dir: &Path,
        model: &Model<3, 3>,
        dx: f64,
        setup: SeasSetup,
    ) -> Result<SeasBp5Output> {
        Ok(SeasBp5Output::for_volume(
            dir,
            &self.output_fault(),
            model,
            dx,
            setup,
        )?)
    }
}
