//! Scenes: ready-made problems described by plain, TOML-readable parameters and built on
//! [`ModelBuilder`](crate::ModelBuilder) and [`SimulationBuilder`](crate::SimulationBuilder).

pub(crate) mod conditioning;
pub(crate) mod seas_bp1;
pub(crate) mod slider;
pub(crate) mod slider3d;
