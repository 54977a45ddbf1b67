//! The automatic solver choice under a memory budget (`SolverOptions::memory_budget_bytes`,
//! docs/scaling.md, issue 25): the direct solver where it fits, TNNMG where it does not,
//! a typed error where neither applies; explicit choices are left alone.

use crate::common::*;
use rsf::{Error, SolverKind};

/// The kind the paper's slider at `level` gets with `solver` under `budget` bytes.
fn chosen(level: usize, solver: SolverKind, budget: usize) -> rsf::Result<SolverKind> {
    let scene = paper(level, solver);
    let mut options = scene.solver_options();
    options.memory_budget_bytes = budget;
    let sim = scene
        .simulation_builder()?
        .solver_options(options)
        .build()?;
    Ok(sim.method().solver_kind())
}

#[test]
fn auto_gives_the_direct_solver_only_what_fits() {
    let default = rsf::method::DEFAULT_MEMORY_BUDGET_BYTES;
    // Level 2: 150 condensed unknowns, a few hundred kB for the direct solver.
    assert_eq!(
        chosen(2, SolverKind::Auto, default).unwrap(),
        SolverKind::Direct
    );
    assert_eq!(
        chosen(2, SolverKind::Auto, 1000).unwrap(),
        SolverKind::Tnnmg
    );
    // An explicit choice is not second-guessed.
    assert_eq!(
        chosen(2, SolverKind::Direct, 1000).unwrap(),
        SolverKind::Direct
    );
    // Level 0 has no hierarchy: nothing else to fall back on.
    match chosen(0, SolverKind::Auto, 1000) {
        Err(Error::MemoryBudget {
            needed_bytes,
            budget_bytes,
        }) => {
            assert_eq!(budget_bytes, 1000);
            assert!(needed_bytes > 1000, "{needed_bytes}");
        }
        other => panic!("expected MemoryBudget, got {other:?}"),
    }
}
