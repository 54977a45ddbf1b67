//! A fully prescribed dipping fault against Okada's half-space (issue 70, item 6;
//! docs/faults-inside.md "A prescribed slip"): a 45° rectangle with 1 m of uniform slip,
//! built through the public API (`internal_fault_polygon`, `internal_slip_at` on every
//! pair, the far faces held at Okada's displacement by `dirichlet_displacement`), its
//! static problem the build's equilibrium, compared with `rsf-halfspace`'s Okada (1992)
//! (checked against DC3D, docs/halfspace.md) on a sequence of refinements.
//!
//! Why 45°: a Kuhn grid of cubes has its cells' faces on the planes `x_i = const` and
//! `x_i − x_j = const` (each cube's six tetrahedra are the orderings of its local
//! coordinates), so the plane `y − z = depth` — Okada's 45° dip towards `−y` — is a surface
//! of mesh faces, and every refinement (Bey's rule: the Kuhn tetrahedra of the half-size
//! cubes) keeps it one; `y + z = const` is not resolved.
#![cfg(feature = "halfspace")]

use rsf::okada_comparison::{compare_dipping, DippingFault, Errors, Solver, SLIP};

/// The growth of the cells per cell away from the fault (on the coarsest mesh).
const RATIO: f64 = 1.3;

/// 2 m along strike, √2 m down dip (rising 1 m), its bottom edge 1.5 m deep (its top
/// 0.5 m), reverse slip of the hanging wall up dip (Okada's `U2 = 1 m`) plus `U1 = 0.5 m`
/// of strike slip: both components of the slip, neither a symmetry of the mesh.
fn fault() -> DippingFault {
    DippingFault {
        half_length: 1.0,
        depth: 1.5,
        width: std::f64::consts::SQRT_2,
        slip: [0.5 * SLIP, SLIP],
    }
}

fn study(levels: std::ops::RangeInclusive<u32>, far: f64, solver: Solver) -> Vec<Errors> {
    let mut out: Vec<Errors> = Vec::new();
    for level in levels {
        let t = std::time::Instant::now();
        let e = compare_dipping(fault(), (0.5, level, RATIO), far, solver).unwrap();
        let order = |f: fn(&Errors) -> f64| {
            out.last()
                .map_or(String::new(), |p| format!("{:.2}", (f(p) / f(&e)).log2()))
        };
        eprintln!(
            "| {} | {} | {:.1} | {:.3e} | {} | {:.3e} | {} | {:.1e} |",
            e.h,
            e.vertices,
            t.elapsed().as_secs_f64(),
            e.surface,
            order(|e| e.surface),
            e.traction,
            order(|e| e.traction),
            e.jump
        );
        out.push(e);
    }
    out
}

/// The test of issue 70: the errors converge on h = 0.25, 0.125, 0.0625 (rise/4 … rise/16),
/// the far faces 2 from the fault's centre held at Okada's displacement (the truncation of
/// the half-space is then not in the error). Asserted: the model's jump is the slip at
/// every pair (it is a fixed dof: to round-off); the surface displacement's error falls at
/// every refinement at an order of at least 1.5 over the sequence — P1 displacements are
/// second order where the field is smooth, the rim's singularity (resolved as the slip's
/// ramp over the last cell, the reference shrunk to its moment) costs some of it on these
/// coarse meshes (docs/faults-inside.md's table: 1.6–1.9 per halving); the finest error
/// below 4 % of the largest surface displacement — the coarsest mesh's error (measured
/// 1.3e-1 at h = 0.25) divided by 2^{1.5 · 2}, what an order of 1.5 leaves of it; the
/// traction at the inner nodes (first order: a P1 stress) falls at every refinement.
#[test]
fn a_dipping_fault_with_prescribed_slip_converges_to_okada() {
    let e = study(1..=3, 2.0, Solver::Multigrid);
    for x in &e {
        assert!(x.jump < 1e-12 * SLIP, "jump off the slip by {:e}", x.jump);
        assert!(x.surface.is_finite() && x.traction.is_finite());
    }
    for w in e.windows(2) {
        assert!(w[1].surface < w[0].surface, "surface error grew");
        assert!(w[1].traction < w[0].traction, "traction error grew");
    }
    let (first, last) = (&e[0], e.last().unwrap());
    let order = (first.surface / last.surface).log2() / (e.len() - 1) as f64;
    eprintln!("surface order over the sequence {order:.2}");
    assert!(order >= 1.5, "surface order {order:.2}");
    let bound = first.surface / 2f64.powf(1.5 * (e.len() - 1) as f64);
    assert!(
        last.surface <= bound && last.surface < 0.04,
        "finest surface error {:e} (bound {bound:e})",
        last.surface
    );
}

/// The study behind the test's bounds (docs/faults-inside.md "A prescribed slip"): one
/// level finer (about 10⁶ vertices, more than 5 GB), and the direct solver on the coarser
/// meshes for comparison (multigrid needs a level below: level 0 is the direct solver's
/// only).
/// `cargo test -p rsf --all-features --test suite okada_dipping::study -- --ignored --nocapture`
#[test]
#[ignore = "a measurement (minutes, more than 5 GB): docs/faults-inside.md"]
fn study_of_the_dipping_fault() {
    eprintln!(
        "| h | vertices | wall (s) | surface error | order | traction error | order | jump (m) |"
    );
    eprintln!("|---|---|---|---|---|---|---|---|");
    study(1..=4, 2.0, Solver::Multigrid);
    study(0..=2, 2.0, Solver::Direct);
}
