//! The integration tests of `rsf`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf --test suite [module::test]`.

mod common;

mod absorbing;
mod adaptive;
mod adaptive_extremes;
mod antiplane;
mod consistency;
mod coupled;
mod direct_extension;
#[cfg(feature = "halfspace")]
mod element_operator;
mod energy;
mod fault_network;
mod fault_ode;
mod fault_ode_ordering;
mod fixed_point_schemes;
mod greens;
mod halfspace_operator;
mod internal_fault;
mod internal_fault_3d;
mod internal_fault_multigrid;
mod internal_loading;
mod material_regions;
mod memory_budget;
mod model_builder;
mod multigrid_graded;
mod nodal_frames;
mod normal_stress;
mod normal_stress_3d;
mod observers;
#[cfg(feature = "halfspace")]
mod okada_dipping;
mod paper_scene;
mod parallelism;
mod prescribed_slip;
mod ranks;
mod reliability;
mod resume;
mod run_folder;
mod schur_columns;
mod slider_3d;
mod slip_event;
mod spring_block;
#[cfg(feature = "sprs")]
mod sprs_edge;
mod stability;
mod steady_sliding;
mod step_collapse;
mod step_invariants;
mod time_convergence;
mod tnnmg_ranks;
mod velocity_solvers;
mod vtu;
mod whole_space_grid;
