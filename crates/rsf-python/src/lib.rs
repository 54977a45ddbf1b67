//! The Python package `rsf` (its native part, `rsf._rsf`): the library's scenes, your own
//! problems, runs with the GIL released and Ctrl-C at step boundaries, checkpoints, and the
//! records as numpy arrays (docs/python.md). Custom state laws stay Rust traits: a Python
//! callback per node per stage would dominate the cost of a step.

use pyo3::prelude::*;

mod arrays;
mod convert;
mod counts;
mod dislocations;
mod engine;
mod errors;
mod fields;
mod mesh;
mod network;
mod problem;
mod run_folder;
mod scenes;
mod seas_bp3;
mod seas_bp5;
mod seas_bp6;
mod seas_square;
mod simulation;

/// The native module.
#[pymodule]
fn _rsf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<mesh::Mesh>()?;
    m.add_class::<problem::Model>()?;
    m.add_class::<problem::Friction>()?;
    m.add_function(wrap_pyfunction!(scenes::slider, m)?)?;
    m.add_function(wrap_pyfunction!(scenes::slider_3d, m)?)?;
    m.add_function(wrap_pyfunction!(scenes::seas_bp1, m)?)?;
    m.add_function(wrap_pyfunction!(seas_bp3::seas_bp3, m)?)?;
    m.add_function(wrap_pyfunction!(seas_bp5::seas_bp5, m)?)?;
    m.add_function(wrap_pyfunction!(seas_bp6::seas_bp6, m)?)?;
    m.add_function(wrap_pyfunction!(seas_bp6::seas_bp6_pore_pressure, m)?)?;
    m.add_function(wrap_pyfunction!(seas_square::seas_bp7, m)?)?;
    m.add_function(wrap_pyfunction!(seas_square::seas_bp8, m)?)?;
    m.add_function(wrap_pyfunction!(problem::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(simulation::_read_greens_hdf5, m)?)?;
    m.add_function(wrap_pyfunction!(dislocations::rectangle_deformation, m)?)?;
    m.add_function(wrap_pyfunction!(dislocations::triangle_deformation, m)?)?;
    m.add("HAS_HDF5", cfg!(feature = "hdf5"))?;
    Ok(())
}
