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
