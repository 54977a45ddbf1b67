//! The condensation without the whole factor (`SchurOnly`) against the one that keeps it
//! (`Condensation`): the same `S` and condensed right-hand sides to round-off on 2-D and
//! 3-D problems with both orderings, the post-step that eliminates extra kept dofs, the
//! checkpoints of a killed set-up, and the errors.

use std::ops::ControlFlow;

use faer::sparse::SparseColMat;
use rsf_direct::{
    CheckpointPolicy, Condensation, Error, InteriorOrdering, KeptSchur, PackedSymmetric,
    RightHandSide, SchurOnly, SchurOnlyOptions,
};

use super::common::square;
use super::elasticity_box::ElasticityBox;
use rsf_nonsmooth::ProblemError;

type Mat = SparseColMat<usize, f64>;

/// Deterministic values in [-1, 1).
fn values(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        })
        .collect()
}

/// A problem: matrix, fixed dofs, blocks, and two right-hand sides with non-zero fixed
/// values (the second a pure Dirichlet one).
struct Problem {
    a: Mat,
    fixed: Vec<bool>,
    blocks: Vec<usize>,
    b: [Vec<f64>; 2],
    x: [Vec<f64>; 2],
}

impl Problem {
    fn rhs(&self) -> [RightHandSide<'_>; 2] {
        [0, 1].map(|k| RightHandSide {
            b: &self.b[k],
            x_fixed: &self.x[k],
        })
    }

    /// [`rhs`](Self::rhs) with the load `b` in place of the first.
    fn rhs_with_first_load<'a>(&'a self, b: &'a [f64]) -> [RightHandSide<'a>; 2] {
        let mut rhs = self.rhs();
        rhs[0].b = b;
        rhs
    }
}

/// The P1 Laplacian (plus a small mass) on the unit square, 25 × 25 cells, fixed on the
/// left edge at non-zero values, condensed onto the bottom edge's other nodes.
fn square_problem() -> Problem {
    let m = 25;
    let a = square(m, 1.0);
    let n = a.nrows();
    let fixed: Vec<bool> = (0..n).map(|k| k % (m + 1) == 0).collect();
    let blocks: Vec<usize> = (1..=m).collect();
    let b = [values(n, 1), vec![0.0; n]];
    let x = [values(n, 2), values(n, 3)];
    Problem {
        a,
        fixed,
        blocks,
        b,
        x,
    }
}

/// Elasticity on a 6 × 5 × 5 box: the bottom face clamped at non-zero displacements, the
/// face y = 0 on rollers (its y component fixed, at non-zero values), condensed onto the
/// nodes of the plane x = 3 (nodes with every, some or no component fixed).
fn box_problem(nx: usize, ny: usize, nz: usize) -> Problem {
    let bx = ElasticityBox::new(nx, ny, nz);
    let a = bx.stiffness();
    let n = a.nrows();
    let fixed: Vec<bool> = (0..n)
        .map(|d| {
            let (_, j, k) = bx.coords(d / 3);
            k == 0 || (j == 0 && d % 3 == 1)
        })
        .collect();
    let blocks: Vec<usize> = (0..bx.nodes())
        .filter(|&p| bx.coords(p).0 == nx / 2)
        .collect();
    let b = [values(n, 4), vec![0.0; n]];
    let x = [values(n, 5), values(n, 6)];
    Problem {
        a,
        fixed,
        blocks,
        b,
        x,
    }
}

/// The reference: `Condensation`'s `S` (dense column-major) and `g` of both right-hand
/// sides.
fn reference<const D: usize>(
    p: &Problem,
    blocks: &[usize],
    ordering: InteriorOrdering,
) -> (Condensation<D>, Vec<f64>, Vec<Vec<f64>>) {
    let mut cond =
        Condensation::<D>::with_ordering(p.a.as_ref(), &p.fixed, blocks, ordering).unwrap();
    let s = cond.schur_complement();
    let g = (0..2)
        .map(|k| {
            let mut g = vec![0.0; cond.dim()];
            cond.condense(&p.b[k], &p.x[k], &mut g).unwrap();
            g
        })
        .collect();
    (cond, s, g)
}

fn max_abs(v: impl IntoIterator<Item = f64>) -> f64 {
    v.into_iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// `kept`'s `S` (its first `m` rows and columns) and `g` against the reference's, each
/// within `tol` relative to its largest entry.
fn assert_matches(
    kept_s: &PackedSymmetric,
    kept_g: &[Vec<f64>],
    s: &[f64],
    g: &[Vec<f64>],
    tol: f64,
) {
    let m = g[0].len();
    let scale = max_abs(s.iter().copied());
    let mut worst = 0.0f64;
    for j in 0..m {
        for i in 0..m {
            worst = worst.max((kept_s.entry(i, j) - s[j * m + i]).abs());
        }
    }
    assert!(worst <= tol * scale, "S: {worst:e} of {scale:e}");
    for (k, (a, b)) in kept_g.iter().zip(g).enumerate() {
        let scale = max_abs(b.iter().copied()).max(1e-300);
        let worst = max_abs(a[..m].iter().zip(b).map(|(x, y)| x - y));
        assert!(worst <= tol * scale, "g[{k}]: {worst:e} of {scale:e}");
    }
}

fn eliminate<const D: usize>(
    p: &Problem,
    extras: &[usize],
    ordering: InteriorOrdering,
) -> KeptSchur {
    SchurOnly::<D>::new(p.a.as_ref(), &p.fixed, &p.blocks, extras, ordering)
        .unwrap()
        .eliminate(&p.rhs(), &SchurOnlyOptions::default())
        .unwrap()
}

fn check_against_condensation<const D: usize>(p: &Problem, ordering: InteriorOrdering) {
    let (cond, s, g) = reference::<D>(p, &p.blocks, ordering);
    let kept = eliminate::<D>(p, &[], ordering);
    assert_eq!(kept.kept_dofs(), cond.interface_dofs());
    assert_eq!(kept.interface_len(), cond.dim());
    assert_matches(kept.schur(), kept.condensed_rhs(), &s, &g, 1e-12);
    // The report adds up: the plan's bytes were the ones met.
    let elim = SchurOnly::<D>::new(p.a.as_ref(), &p.fixed, &p.blocks, &[], ordering).unwrap();
    let plan = elim.plan();
    let r = kept.report();
    assert_eq!(r.fronts, plan.fronts);
    assert_eq!(r.peak_pending_bytes, plan.peak_pending_bytes);
    assert_eq!(r.largest_front_bytes, plan.largest_front_bytes);
    assert_eq!(r.result_bytes, plan.result_bytes + 2 * 8 * cond.dim());
    assert_eq!(r.resumed_at, None);
}

/// A 2-D Laplacian with AMD: `S` and both `g` equal the full factor's to round-off.
#[test]
fn equals_the_condensation_on_a_grid_laplacian() {
    check_against_condensation::<1>(&square_problem(), InteriorOrdering::Amd);
}

/// 3-D elasticity with AMD: the same, with blocks that have some components fixed.
#[test]
fn equals_the_condensation_on_an_elasticity_box() {
    check_against_condensation::<3>(&box_problem(6, 5, 5), InteriorOrdering::Amd);
}

/// The same with METIS's nested dissection.
#[cfg(feature = "metis")]
#[test]
fn equals_the_condensation_with_nested_dissection() {
    check_against_condensation::<1>(&square_problem(), InteriorOrdering::NestedDissection);
    check_against_condensation::<3>(&box_problem(8, 6, 5), InteriorOrdering::NestedDissection);
}

/// A 1-D chain condensed onto one node: the supernode that holds the last interior column
/// holds the kept one too (it is split there), and the result is still the condensation's.
#[test]
fn a_supernode_straddling_the_kept_set_is_split() {
    for (n, node) in [(7, 3), (12, 11), (40, 20)] {
        let mut t = Vec::new();
        for i in 0..n {
            t.push(faer::sparse::Triplet::new(i, i, 2.0 + 0.01 * i as f64));
            if i + 1 < n {
                t.push(faer::sparse::Triplet::new(i, i + 1, -1.0));
                t.push(faer::sparse::Triplet::new(i + 1, i, -1.0));
            }
        }
        let a = Mat::try_new_from_triplets(n, n, &t).unwrap();
        let mut fixed = vec![false; n];
        fixed[0] = true;
        let p = Problem {
            a,
            fixed,
            blocks: vec![node],
            b: [values(n, 7), values(n, 8)],
            x: [values(n, 9), values(n, 10)],
        };
        check_against_condensation::<1>(&p, InteriorOrdering::Amd);
    }
}

/// Extra kept dofs `P`: the post-step's `S_F`, `g_F` are the condensation onto the blocks
/// alone, and its extension rows give what `Condensation::extend` gives at `P`.
#[test]
fn extras_are_eliminated_again_and_extend_like_the_condensation() {
    let p = box_problem(6, 5, 5);
    let n = p.a.nrows();
    // Free dofs off the plane: a few points of the volume (each component).
    let bx = ElasticityBox::new(6, 5, 5);
    let mut extras: Vec<usize> = [bx.node(1, 2, 3), bx.node(5, 4, 2), bx.node(4, 0, 5)]
        .iter()
        .flat_map(|&q| (3 * q..3 * q + 3).filter(|&d| !p.fixed[d]))
        .collect();
    extras.sort_unstable();
    assert!(extras.len() >= 7);
    let kept = eliminate::<3>(&p, &extras, InteriorOrdering::Amd);
    assert_eq!(kept.dim(), kept.interface_len() + extras.len());
    let onto = kept.onto_interface().unwrap();
    let (mut cond, s, g) = reference::<3>(&p, &p.blocks, InteriorOrdering::Amd);
    assert_eq!(onto.interface_dofs(), cond.interface_dofs());
    assert_matches(onto.schur(), onto.condensed_rhs(), &s, &g, 1e-11);
    // Extension at P for arbitrary interface values, right-hand side 0.
    let m = cond.dim();
    let x_f = values(m, 11);
    let mut g0 = vec![0.0; m];
    cond.condense(&p.b[0], &p.x[0], &mut g0).unwrap();
    let mut x = p.x[0].clone();
    for (k, &d) in cond.interface_dofs().iter().enumerate() {
        x[d] = x_f[k];
    }
    cond.extend(&mut x).unwrap();
    let mut x_p = vec![0.0; extras.len()];
    onto.extras().extend(Some(0), &x_f, &mut x_p).unwrap();
    let want: Vec<f64> = extras.iter().map(|&d| x[d]).collect();
    let scale = max_abs(want.iter().copied());
    let err = max_abs(x_p.iter().zip(&want).map(|(a, b)| a - b));
    assert!(err <= 1e-11 * scale, "{err:e} of {scale:e}");
    // The matrix rows alone are the homogeneous extension.
    let mut x = vec![0.0; n];
    for (k, &d) in cond.interface_dofs().iter().enumerate() {
        x[d] = x_f[k];
    }
    cond.extend_homogeneous(&mut x).unwrap();
    onto.extras().extend(None, &x_f, &mut x_p).unwrap();
    let err = max_abs(extras.iter().zip(&x_p).map(|(&d, v)| x[d] - v));
    assert!(err <= 1e-11 * max_abs(x_p.iter().copied()), "{err:e}");
    assert_eq!(onto.extras().dofs(), &extras[..]);
    assert!(onto.extras().extend(Some(2), &x_f, &mut x_p).is_err());
}

/// The same bits, every f64 of `S_KK` and `g_K`.
fn same_bits(a: &KeptSchur, b: &KeptSchur) -> bool {
    a.schur()
        .packed_rows()
        .iter()
        .zip(b.schur().packed_rows())
        .all(|(x, y)| x.to_bits() == y.to_bits())
        && a.condensed_rhs()
            .iter()
            .flatten()
            .zip(b.condensed_rhs().iter().flatten())
            .all(|(x, y)| x.to_bits() == y.to_bits())
        && a.schur().dim() == b.schur().dim()
}

/// A set-up stopped (as a kill would: no last checkpoint) between two checkpoints and
/// resumed gives the bits of an uninterrupted one; the kept final state gives them again
/// without eliminating; a checkpoint of another matrix or other right-hand sides is
/// refused and left as it is; a damaged one is refused.
#[test]
fn killed_and_resumed_gives_the_same_bits() {
    let p = box_problem(7, 5, 5);
    let extras = [3 * ElasticityBox::new(7, 5, 5).node(2, 3, 3) + 2];
    let elim = SchurOnly::<3>::new(
        p.a.as_ref(),
        &p.fixed,
        &p.blocks,
        &extras,
        InteriorOrdering::Amd,
    )
    .unwrap();
    let total = elim.plan().fronts;
    assert!(total > 20, "{total} fronts");
    let whole = elim
        .eliminate(&p.rhs(), &SchurOnlyOptions::default())
        .unwrap();
    let dir = std::env::temp_dir().join(format!("rsf-direct-schur-only-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("box.ckpt");
    let _ = std::fs::remove_file(&path);
    let every = 5;
    let options = SchurOnlyOptions {
        checkpoint: Some(CheckpointPolicy {
            path: path.clone(),
            every_fronts: Some(every),
            every_seconds: None,
            keep_result: true,
        }),
        ..Default::default()
    };
    // Killed twice: after 2 checkpoints (+2 fronts), then further on.
    let stop_at = [2 * every + 2, total - 3];
    for (round, &stop) in stop_at.iter().enumerate() {
        let err = elim
            .eliminate_with(&p.rhs(), &options, &mut |pr| {
                if pr.fronts_done == stop {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            })
            .unwrap_err();
        assert_eq!(err, Error::Stopped { done: stop, total }, "round {round}");
        assert!(path.exists());
    }
    let resumed = elim.eliminate(&p.rhs(), &options).unwrap();
    assert_eq!(
        resumed.report().resumed_at,
        Some((total - 3) / every * every)
    );
    assert!(same_bits(&whole, &resumed), "resumed != whole");
    assert_eq!(resumed.report().fronts, total);
    assert_eq!(
        resumed.report().peak_pending_bytes,
        whole.report().peak_pending_bytes
    );
    assert_eq!(resumed.report().flops, whole.report().flops);
    // The finished state is kept: read back, nothing eliminated.
    let again = elim.eliminate(&p.rhs(), &options).unwrap();
    assert_eq!(again.report().resumed_at, Some(total));
    // Its file is the plan's size to the byte, and the space held for it is gone.
    let bytes = std::fs::metadata(&path).unwrap().len();
    assert_eq!(
        bytes,
        elim.plan().finished_checkpoint_bytes(p.rhs().len()),
        "{bytes} bytes"
    );
    assert!(!dir.join("box.ckpt.partial").exists());
    assert!(same_bits(&whole, &again));
    // Its post-step too.
    let (x, y) = (
        whole.clone().onto_interface().unwrap(),
        again.onto_interface().unwrap(),
    );
    assert!(x
        .extras()
        .matrix()
        .iter()
        .zip(y.extras().matrix())
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    // Another matrix (one value changed), other right-hand sides: refused, file kept.
    let mut other = p.a.clone();
    other.val_mut()[17] *= 1.0 + 1e-12;
    let elim_other = SchurOnly::<3>::new(
        other.as_ref(),
        &p.fixed,
        &p.blocks,
        &extras,
        InteriorOrdering::Amd,
    )
    .unwrap();
    let before = std::fs::read(&path).unwrap();
    assert!(matches!(
        elim_other.eliminate(&p.rhs(), &options),
        Err(Error::CheckpointMismatch { .. })
    ));
    // A load at a fixed dof is not read: the same problem, accepted.
    let mut b2 = p.b[0].clone();
    let fixed_dof = (0..b2.len()).find(|&d| p.fixed[d]).unwrap();
    b2[fixed_dof] += 1.0;
    let rhs2 = p.rhs_with_first_load(&b2);
    assert!(same_bits(&whole, &elim.eliminate(&rhs2, &options).unwrap()));
    let free_dof = (0..b2.len()).find(|&d| !p.fixed[d]).unwrap();
    b2[free_dof] += 1.0;
    let rhs2 = p.rhs_with_first_load(&b2);
    assert!(matches!(
        elim.eliminate(&rhs2, &options),
        Err(Error::CheckpointMismatch { .. })
    ));
    assert!(matches!(
        elim.eliminate(&p.rhs()[..1], &options),
        Err(Error::CheckpointMismatch { .. })
    ));
    assert_eq!(std::fs::read(&path).unwrap(), before);
    // A damaged file.
    let mut bytes = before.clone();
    let k = bytes.len() / 2;
    bytes[k] ^= 0x10;
    std::fs::write(&path, &bytes).unwrap();
    assert!(matches!(
        elim.eliminate(&p.rhs(), &options),
        Err(Error::Checkpoint { .. })
    ));
    std::fs::write(&path, &before[..before.len() - 9]).unwrap();
    assert!(matches!(
        elim.eliminate(&p.rhs(), &options),
        Err(Error::Checkpoint { .. })
    ));
    // Without keeping the result the file goes at the end.
    std::fs::remove_file(&path).unwrap();
    let mut drop_it = options.clone();
    drop_it.checkpoint.as_mut().unwrap().keep_result = false;
    let fresh = elim.eliminate(&p.rhs(), &drop_it).unwrap();
    assert!(same_bits(&whole, &fresh));
    assert!(!path.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A matrix with a positive diagonal that is not positive definite: the typed error,
/// naming an interior dof; the post-step's `S_PP` likewise at an extra dof.
#[test]
fn not_positive_definite_is_a_typed_error() {
    // 2 I − (grid adjacency) on 12 × 12: eigenvalues down to 2 − 4 cos(π/13) < 0.
    let m = 12;
    let mut t = Vec::new();
    for j in 0..m {
        for i in 0..m {
            let p = i + m * j;
            t.push(faer::sparse::Triplet::new(p, p, 2.0));
            for (di, dj) in [(1, 0), (0, 1)] {
                if i + di < m && j + dj < m {
                    let q = (i + di) + m * (j + dj);
                    t.push(faer::sparse::Triplet::new(p, q, -1.0));
                    t.push(faer::sparse::Triplet::new(q, p, -1.0));
                }
            }
        }
    }
    let a = Mat::try_new_from_triplets(m * m, m * m, &t).unwrap();
    let n = m * m;
    let fixed = vec![false; n];
    let blocks: Vec<usize> = (0..m).collect();
    let elim =
        SchurOnly::<1>::new(a.as_ref(), &fixed, &blocks, &[], InteriorOrdering::Amd).unwrap();
    match elim.eliminate(&[], &SchurOnlyOptions::default()) {
        Err(Error::NonPositivePivot { dof, .. }) => assert!(dof >= m && dof < n, "dof {dof}"),
        other => panic!("{other:?}"),
    }
}

/// Wrong lengths, bad sets, an invalid checkpoint policy, a memory limit below the plan:
/// typed errors, the last before anything is allocated.
#[test]
fn bad_inputs_are_refused() {
    let p = square_problem();
    let n = p.a.nrows();
    let new = |extras: &[usize]| {
        SchurOnly::<1>::new(
            p.a.as_ref(),
            &p.fixed,
            &p.blocks,
            extras,
            InteriorOrdering::Amd,
        )
    };
    for extras in [&[40, 30][..], &[0], &[5], &[n]] {
        assert!(
            matches!(
                new(extras),
                Err(Error::Problem(ProblemError::InvalidOption(_)))
            ),
            "{extras:?}"
        );
    }
    assert!(matches!(
        SchurOnly::<1>::new(
            p.a.as_ref(),
            &p.fixed[1..],
            &p.blocks,
            &[],
            InteriorOrdering::Amd
        ),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    let elim = new(&[40]).unwrap();
    let short = RightHandSide {
        b: &p.b[0][1..],
        x_fixed: &p.x[0],
    };
    assert!(matches!(
        elim.eliminate(&[short], &SchurOnlyOptions::default()),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    let mut bad = p.b[0].clone();
    bad[40] = f64::NAN;
    let nan = RightHandSide {
        b: &bad,
        x_fixed: &p.x[0],
    };
    assert!(matches!(
        elim.eliminate(&[nan], &SchurOnlyOptions::default()),
        Err(Error::Problem(ProblemError::NonFinite(_)))
    ));
    let plan = elim.plan();
    let need = plan.total_bytes(2);
    assert!(need > plan.result_bytes as u128);
    let tight = SchurOnlyOptions {
        max_bytes: Some(need as usize - 1),
        ..Default::default()
    };
    assert!(matches!(
        elim.eliminate(&p.rhs(), &tight),
        Err(Error::TooLarge { .. })
    ));
    let enough = SchurOnlyOptions {
        max_bytes: Some(need as usize),
        ..Default::default()
    };
    assert!(elim.eliminate(&p.rhs(), &enough).is_ok());
    let zero = SchurOnlyOptions {
        checkpoint: Some(CheckpointPolicy {
            every_fronts: Some(0),
            ..CheckpointPolicy::new("unused")
        }),
        ..Default::default()
    };
    assert!(matches!(
        elim.eliminate(&p.rhs(), &zero),
        Err(Error::Problem(ProblemError::InvalidOption(_)))
    ));
}

/// What it holds is below the full factor already on a small 3-D box (4.7 k dofs, where
/// the fixed-size panels weigh most): the plan's peak (result, workspace, pending blocks
/// and front, carried right-hand sides) below the factor's bytes (1.8× below here; the
/// measured ratios at scale are in docs/three-d.md).
#[test]
fn holds_less_than_the_factor_on_a_box() {
    let p = box_problem(12, 10, 10);
    let elim = SchurOnly::<3>::new(
        p.a.as_ref(),
        &p.fixed,
        &p.blocks,
        &[],
        InteriorOrdering::Amd,
    )
    .unwrap();
    let cond = Condensation::<3>::new(p.a.as_ref(), &p.fixed, &p.blocks).unwrap();
    let plan = elim.plan();
    let factor = 8 * cond.factor_nnz() as u128;
    assert!(
        plan.total_bytes(2) < factor,
        "plan {} bytes, factor {factor}",
        plan.total_bytes(2)
    );
}
