//! The integration tests of `rsf-scenes`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-scenes --test suite [module::test]`.

mod absorbing_sides;
mod columns;
#[cfg(feature = "seas")]
mod load_change;
mod scene_values;
#[cfg(feature = "seas")]
mod seas_bp3;
#[cfg(feature = "seas")]
mod seas_bp5;
#[cfg(feature = "seas")]
mod seas_bp6;
#[cfg(feature = "seas")]
mod surface_pressure;
#[cfg(feature = "seas")]
mod volume_vertices;

/// The end time `time` (s) within 500 000 steps (the tests' bound on a run that would
/// otherwise have collapsed).
fn within(time: f64) -> rsf::Until {
    rsf::Until::TimeWithin {
        time,
        max_steps: 500_000,
    }
}

/// BP5's volume grid of `dx` (m) cells, the rest the default.
#[cfg(feature = "seas")]
fn bp5_grid(dx: f64) -> rsf_scenes::SeasBp5Grid {
    rsf_scenes::SeasBp5Grid {
        dx,
        ..rsf_scenes::SeasBp5Grid::default()
    }
}

/// BP5's volume with its internal fault on 10 km cells, the slab next to the fault (10 km
/// each side) meshed at `dx` too: the fault zone's test grid.
#[cfg(feature = "seas")]
fn bp5_zone_grid() -> rsf_scenes::SeasBp5Grid {
    rsf_scenes::SeasBp5Grid {
        near_fault: 10e3,
        ..bp5_grid(10e3)
    }
}

/// An observer recording the time (s) after every accepted step.
#[cfg(feature = "seas")]
struct StepTimes(Vec<f64>);

#[cfg(feature = "seas")]
impl<const D: usize, const C: usize> rsf::Observer<D, C> for StepTimes {
    fn observe(&mut self, s: &rsf::StepView<'_, D, C>) -> rsf::Result<rsf::Flow> {
        self.0.push(s.state.time);
        Ok(rsf::Flow::Continue(()))
    }
}
