//! The fault's Schur complement column by column from static solves (issue 70, item 3;
//! docs/three-d.md, "Columns of S by solves"): against the multifrontal elimination that
//! keeps no factor (`rsf_direct::SchurOnly`), an independent computation of the same `S`.
use rsf::direct::{InteriorOrdering, SchurOnly, SchurOnlyOptions};
use rsf::fem::cuboid;
use rsf::hmatrix::HOptions;
use rsf::model::{PrescribedSlip, SchurColumns, StaticMethod, StaticOptions};
use rsf::nonsmooth::Stopping;
use rsf::{Model, ModelBuilder};

use crate::common::{cube_with_buried_fault, parameter_name, with_buried_fault};

/// The cube of 4³ boxes refined `levels` times (a hierarchy for multigrid) with its fault.
fn refined(levels: usize) -> ModelBuilder<3> {
    cube_with_buried_fault(4, levels)
}

/// The cube of 4³ boxes refined `levels` times with its fault, built.
fn model(levels: usize) -> Model<3> {
    refined(levels).build().unwrap()
}

/// `S` of `model` by the Schur-only elimination, dense, and its slip unknowns.
fn direct_s(model: &Model<3>) -> (faer::Mat<f64>, Vec<usize>) {
    let elimination = SchurOnly::<3>::new(
        model.stiffness.as_ref(),
        &model.fixed,
        &model.frictional_boundary.nodes,
        &[],
        InteriorOrdering::Amd,
    )
    .unwrap();
    let kept = elimination
        .eliminate(&[], &SchurOnlyOptions::default())
        .unwrap();
    let m = kept.dim();
    let s = faer::Mat::from_fn(m, m, |i, j| kept.schur().entry(i, j));
    (s, kept.kept_dofs().to_vec())
}

/// `max |A − B|` over the largest diagonal entry of `B`.
fn relative_difference(a: &faer::Mat<f64>, b: &faer::Mat<f64>) -> f64 {
    let scale = (0..b.nrows()).map(|i| b[(i, i)]).fold(0.0f64, f64::max);
    let mut d = 0.0f64;
    for j in 0..b.ncols() {
        for i in 0..b.nrows() {
            d = d.max((a[(i, j)] - b[(i, j)]).abs());
        }
    }
    d / scale
}

fn multigrid(relative: f64) -> StaticOptions {
    StaticOptions::method(StaticMethod::Multigrid).with_stopping(Stopping {
        absolute: 0.0,
        relative,
        max_iterations: 500,
    })
}

/// Columns by multigrid match the direct `S` within the solver's tolerance, and the error
/// follows the tolerance: a stopping test six orders looser gives a larger error, still
/// within its own bound.
#[test]
fn columns_by_multigrid_match_the_direct_s_within_the_solver_tolerance() {
    let model = model(1);
    let (s_direct, dofs) = direct_s(&model);
    let m = s_direct.nrows();
    let mut errors = Vec::new();
    for tolerance in [1e-3, 1e-12] {
        let columns = SchurColumns::new(&model, multigrid(tolerance)).unwrap();
        assert_eq!(columns.method(), StaticMethod::Multigrid);
        assert_eq!(columns.interface_dofs(), dofs.as_slice());
        let s = columns.dense().unwrap();
        let report = columns.report();
        assert_eq!(report.columns, m);
        let e = relative_difference(&s, &s_direct);
        eprintln!(
            "tolerance {tolerance:e}: {} dofs, m = {m}, max |S_mg − S| / max S_ii = {e:.2e}, \
             {:.1} iterations per column (max {}), {:.3} s",
            model.num_dofs(),
            report.iterations as f64 / m as f64,
            report.max_iterations,
            report.seconds
        );
        errors.push(e);
    }
    // The bound: the error of a column in the energy norm is about the tolerance times
    // the solution's, and an entry of S weighs it by √cond(K) at most (~1e2 here).
    assert!(errors[0] < 1e2 * 1e-6, "{:e}", errors[0]);
    assert!(errors[1] < 1e2 * 1e-12, "{:e}", errors[1]);
    assert!(errors[1] < errors[0] * 1e-3, "{errors:?}");
}

/// The direct static solver (Cholesky of the interior with the slip unknowns held) gives
/// the multifrontal elimination's `S` to round-off: two factorisations, one result.
#[test]
fn columns_by_the_direct_solver_are_the_eliminations_s_to_round_off() {
    let model = model(1);
    let (s_direct, _) = direct_s(&model);
    let columns = SchurColumns::new(&model, StaticOptions::method(StaticMethod::Direct)).unwrap();
    let s = columns.dense().unwrap();
    let e = relative_difference(&s, &s_direct);
    eprintln!(
        "direct: m = {}, max |S_chol − S| / max S_ii = {e:.2e}",
        s.nrows()
    );
    assert!(e < 1e-12, "{e:e}");
    // A subset in another order: the same columns.
    let mut part = faer::Mat::zeros(s.nrows(), 2);
    columns.columns(&[5, 0], part.as_mut()).unwrap();
    for i in 0..s.nrows() {
        assert_eq!(part[(i, 0)], s[(i, 5)]);
        assert_eq!(part[(i, 1)], s[(i, 0)]);
    }
}

/// `S` compressed into an ℋ-matrix as its columns come is the direct `S` within the
/// compression's ε (every column computed once, `S` never held whole; measured here
/// 5.3e-6 at ε = 1e-3).
#[test]
fn s_compressed_from_its_columns_is_the_direct_s_within_epsilon() {
    let model = model(2);
    let (s_direct, _) = direct_s(&model);
    let m = s_direct.nrows();
    // The direct solver for the columns: its S is the elimination's to round-off (above),
    // so the difference is the compression's.
    let columns = SchurColumns::new(&model, StaticOptions::method(StaticMethod::Direct)).unwrap();
    let options = HOptions {
        epsilon: 1e-3,
        leaf_size: 8,
        ..HOptions::default()
    };
    let h = columns.hierarchical(&options).unwrap();
    let report = h.report().columns.clone().unwrap();
    assert_eq!(report.columns_computed, m);
    assert_eq!(columns.report().columns, m);
    let dense = h.to_dense();
    let mut diff2 = 0.0;
    let mut norm2 = 0.0;
    for j in 0..m {
        for i in 0..m {
            diff2 += (dense[(i, j)] - s_direct[(i, j)]).powi(2);
            norm2 += s_direct[(i, j)].powi(2);
        }
    }
    let rel = (diff2 / norm2).sqrt();
    eprintln!(
        "ℋ from columns: m = {m}, ‖S_H − S‖_F/‖S‖_F = {rel:.2e}, {} low-rank blocks",
        h.report().low_rank_blocks
    );
    // At this size the truncated blocks are cheaper stored dense (no low-rank block), but
    // truncated they are: the difference is the compression's, not round-off.
    assert!(rel < 1e-3, "{rel:e}");
}

/// Errors name what is wrong: multigrid without a hierarchy, a column out of range, an
/// output of another shape, a fault whose every slip is prescribed (no slip unknowns).
#[test]
fn columns_that_cannot_be_computed_are_refused_by_name() {
    let unrefined = with_buried_fault(ModelBuilder::new(
        cuboid([-1.0; 3], [2.0; 3], [5; 3]).unwrap(),
    ))
    .build()
    .unwrap();
    let e =
        SchurColumns::new(&unrefined, StaticOptions::method(StaticMethod::Multigrid)).unwrap_err();
    assert_eq!(parameter_name(e), "static_solver");
    let columns = SchurColumns::new(&unrefined, StaticOptions::default()).unwrap();
    let m = columns.dim();
    let mut out = faer::Mat::zeros(m, 1);
    let e = columns.columns(&[m], out.as_mut()).unwrap_err();
    assert_eq!(parameter_name(e), "cols");
    let e = columns.columns(&[0, 1], out.as_mut()).unwrap_err();
    assert_eq!(parameter_name(e), "cols");
    let prescribed = refined(1)
        .internal_slip_at(|_| Some(PrescribedSlip::InFrame([0.0, 0.0])))
        .build()
        .unwrap();
    let e = SchurColumns::new(&prescribed, StaticOptions::default()).unwrap_err();
    assert_eq!(parameter_name(e), "frictional_boundary");
}
