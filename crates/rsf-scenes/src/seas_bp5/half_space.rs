//! BP5 as the benchmark poses it: the fault alone on a grid of square cells with Okada's
//! half-space operator.

use rsf::fault_alone::FaultAlone;
use rsf::fault_ode::FaultOdeOptions;
use rsf::halfspace_operator::{HalfSpaceOperator, HalfSpaceOptions};
use rsf::{Model, Result};

use super::{SeasBp5, SeasBp5FaultOde};
use crate::invalid;

impl SeasBp5 {
    /// The cells of a grid of size `dx` on the rate-and-state region: their centres
    /// `(x₂, x₃)` (m), strike fastest, from the shallowest row down.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx` unless it divides `l_f` and `W_f` into
    /// whole cells (to 1e-9 relative).
    pub fn cells(&self, dx: f64) -> Result<Vec<[f64; 2]>> {
        self.validate()?;
        let count = |length: f64| -> Result<usize> {
            let n = length / dx;
            if !(dx.is_finite() && dx > 0.0) || n < 1.0 || (n - n.round()).abs() > 1e-12 * n {
                return Err(invalid(
                    "dx",
                    format!(
                        "{} m must divide l_f = {} m and W_f = {} m into whole cells",
                        rsf_numeric::written(dx),
                        self.l_f,
                        self.w_f
                    ),
                ));
            }
            Ok(n.round() as usize)
        };
        let (n_strike, n_dip) = (count(self.l_f)?, count(self.w_f)?);
        if n_strike.saturating_mul(n_dip) > MAX_CELLS {
            return Err(invalid(
                "dx",
                format!(
                    "{} m gives {n_strike} × {n_dip} cells, more than {MAX_CELLS} (a 250 m \
                     grid)",
                    rsf_numeric::written(dx)
                ),
            ));
        }
        let mut cells = Vec::with_capacity(n_strike * n_dip);
        for j in 0..n_dip {
            for i in 0..n_strike {
                cells.push([
                    -0.5 * self.l_f + (i as f64 + 0.5) * dx,
                    (j as f64 + 0.5) * dx,
                ]);
            }
        }
        Ok(cells)
    }

    /// The fault alone on the grid of size `dx` ([`Model::fault_only`]): one vertex per
    /// cell at `(0, x₂, −x₃)`, `x` (the fault normal) fixed, the prestress
    /// [`tau0_in_cell`](Self::tau0_in_cell) along `+y` as the load (times the cell's area:
    /// a cell on the nucleation patch's edge takes its share of the patch's prestress).
    ///
    /// # Errors
    /// Those of [`cells`](Self::cells).
    pub fn model(&self, dx: f64) -> Result<Model<3, 3>> {
        let cells = self.cells(dx)?;
        let centres = cells.iter().map(|c| [0.0, c[0], -c[1]]).collect();
        let areas = vec![dx * dx; cells.len()];
        let mut model = Model::fault_only(centres, &areas, 0)?;
        for (k, c) in cells.iter().enumerate() {
            model.load[3 * k + 1] = dx * dx * self.tau0_in_cell(c[0], c[1], dx);
        }
        Ok(model)
    }

    /// The fault ODE of BP5 on `model` (from [`model`](Self::model)) with Okada's
    /// half-space operator ([`HalfSpaceOperator::fault_alone`]: dense up to
    /// `half_space.dense_max` unknowns, an ℋ-matrix of accuracy `half_space.epsilon`
    /// beyond), loaded by back slip at `V_p` along `+x₂`: the regularised law with
    /// [`params`](Self::params), the aging law with the local L, θ₀ of
    /// [`alpha0`](Self::alpha0), η = μ/(2c_s), first trial step 1 ms.
    ///
    /// # Errors
    /// Invalid parameters; the operator's errors (as
    /// [`rsf::Error::InvalidParameter`] named `half_space`); the set-up errors of
    /// [`build_fault_ode_alone`](rsf::SimulationBuilder::build_fault_ode_alone).
    pub fn fault_ode(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        half_space: &HalfSpaceOptions,
    ) -> Result<SeasBp5FaultOde> {
        Ok(self
            .fault_ode_with_stations(model, options, half_space, &[])?
            .0)
    }

    /// As [`fault_ode`](Self::fault_ode), with the half-space displacement at `points`
    /// (model coordinates, m) per unit slip of every slip unknown
    /// ([`HalfSpaceOperator::displacement_columns`]) for off-fault stations.
    ///
    /// # Errors
    /// As [`fault_ode`](Self::fault_ode); a point above the surface or on an element.
    pub fn fault_ode_with_stations(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        half_space: &HalfSpaceOptions,
        points: &[[f64; 3]],
    ) -> Result<(SeasBp5FaultOde, Vec<Vec<f64>>)> {
        self.fault_ode_on_ranks(model, options, half_space, points, None)
    }

    /// As [`fault_ode_with_stations`](Self::fault_ode_with_stations), the operator's rows
    /// shared out to `ranks` if given ([`HalfSpaceOperator::fault_alone_on_ranks`]: each
    /// rank builds and holds its part of an ℋ-matrix operator; collective — every rank
    /// calls this with the same arguments). Share the fault ODE's evaluations with the
    /// same ranks ([`rsf::FaultOde::share_evaluations`]).
    ///
    /// # Errors
    /// As [`fault_ode_with_stations`](Self::fault_ode_with_stations).
    pub fn fault_ode_on_ranks(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        half_space: &HalfSpaceOptions,
        points: &[[f64; 3]],
        ranks: Option<Box<dyn rsf_ranks::RankGroup + Send>>,
    ) -> Result<(SeasBp5FaultOde, Vec<Vec<f64>>)> {
        self.validate()?;
        if self.fault_zone.is_some() {
            return Err(invalid(
                "fault_zone",
                "a fault zone is a change of the volume: it needs the finite-element kernel \
                 (fe_model), not the half-space operator",
            ));
        }
        let operator = match ranks {
            Some(group) => HalfSpaceOperator::fault_alone_on_ranks(&model, half_space, group),
            None => HalfSpaceOperator::fault_alone(&model, half_space),
        }
        .map_err(|e| invalid("half_space", e.to_string()))?;
        let columns = operator.displacement_columns(points)?;
        let cells = model.vertices.len();
        let plate_velocity = (0..cells).flat_map(|_| [self.v_p, 0.0]).collect();
        let alone = FaultAlone {
            operator: Box::new(operator),
            plate_velocity,
        };
        self.problem_builder(model)
            .build_fault_ode_alone(options, alone)
            .map(|ode| (ode, columns))
    }

    /// Half-space options of BP5: the free surface `z = 0`, the medium, dense up to
    /// 4 096 unknowns, ε = `epsilon` beyond.
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn half_space(&self, epsilon: f64) -> Result<HalfSpaceOptions> {
        Ok(HalfSpaceOptions {
            epsilon,
            ..HalfSpaceOptions::new(0.0, self.medium()?)
        })
    }
}

/// Most cells [`SeasBp5::cells`] builds: the 250 m grid (400 × 160).
pub const MAX_CELLS: usize = 64_000;
