//! The interior orderings of a condensation (InteriorOrdering): METIS's nested dissection
//! condenses like AMD to round-off, deterministically and with less fill on a 3-D block
//! problem; without the feature `metis` it is a typed error; AMD is `Condensation::new`
//! bit for bit.

use faer::sparse::{SparseColMat, Triplet};
use rsf_direct::{Condensation, InteriorOrdering};

/// A 3-D vector problem on an `m × m × m` grid of nodes (3 dofs each): the 7-point
/// Laplacian (plus a shift) times an SPD 3 × 3 block that couples the components, so its
/// pattern is a finite-element vector field's. Nodes with `x = 0` are fixed; the fault is
/// the plane of nodes `x = m/2`.
struct Grid3 {
    a: SparseColMat<usize, f64>,
    fixed: Vec<bool>,
    fault: Vec<usize>,
}

fn grid3(m: usize) -> Grid3 {
    let node = |x: usize, y: usize, z: usize| x + m * (y + m * z);
    let b = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.25], [0.5, 0.25, 2.0]];
    let mut t = Vec::new();
    for z in 0..m {
        for y in 0..m {
            for x in 0..m {
                let p = node(x, y, z);
                let mut couple = |q: usize, w: f64| {
                    for (i, bi) in b.iter().enumerate() {
                        for (j, bij) in bi.iter().enumerate() {
                            t.push(Triplet::new(3 * p + i, 3 * q + j, w * bij));
                        }
                    }
                };
                couple(p, 6.1);
                for (ok, q) in [
                    (x > 0, p.wrapping_sub(1)),
                    (x + 1 < m, p + 1),
                    (y > 0, p.wrapping_sub(m)),
                    (y + 1 < m, p + m),
                    (z > 0, p.wrapping_sub(m * m)),
                    (z + 1 < m, p + m * m),
                ] {
                    if ok {
                        couple(q, -1.0);
                    }
                }
            }
        }
    }
    let n = 3 * m * m * m;
    let a = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
    let fixed = (0..n).map(|i| (i / 3) % m == 0).collect();
    let mut fault: Vec<usize> = (0..m * m).map(|k| node(m / 2, k % m, k / m)).collect();
    fault.sort_unstable();
    Grid3 { a, fixed, fault }
}

#[cfg(feature = "metis")]
fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |s, x| s.max(x.abs()))
}

#[cfg(feature = "metis")]
fn max_diff(p: &[f64], q: &[f64]) -> f64 {
    p.iter()
        .zip(q)
        .fold(0.0_f64, |s, (x, y)| s.max((x - y).abs()))
}

/// AMD is `Condensation::new`: the same factor, the same Schur complement bits.
#[test]
fn amd_is_the_default_condensation_bit_for_bit() {
    let g = grid3(6);
    let new = Condensation::<3>::new(g.a.as_ref(), &g.fixed, &g.fault).unwrap();
    let amd =
        Condensation::<3>::with_ordering(g.a.as_ref(), &g.fixed, &g.fault, InteriorOrdering::Amd)
            .unwrap();
    assert_eq!(InteriorOrdering::default(), InteriorOrdering::Amd);
    for o in [InteriorOrdering::Amd, InteriorOrdering::NestedDissection] {
        assert_eq!(o.to_string().parse::<InteriorOrdering>(), Ok(o));
    }
    assert!("metis".parse::<InteriorOrdering>().is_err());
    assert_eq!(new.factor_nnz(), amd.factor_nnz());
    let bits = |c: &Condensation<3>| -> Vec<u64> {
        c.schur_complement().iter().map(|x| x.to_bits()).collect()
    };
    assert!(bits(&new) == bits(&amd));
}

#[cfg(not(feature = "metis"))]
#[test]
fn nested_dissection_without_the_feature_is_a_typed_error() {
    let g = grid3(4);
    let e = Condensation::<3>::with_ordering(
        g.a.as_ref(),
        &g.fixed,
        &g.fault,
        InteriorOrdering::NestedDissection,
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            rsf_direct::Error::FeatureDisabled {
                feature: "metis",
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("feature `metis`"), "{e}");
}

/// On a 14³-node grid (8 232 dofs, a fault of 196 nodes): the Schur complement, a
/// condensed right-hand side and the interior of a solution agree with AMD's to 1e-10
/// relative; two set-ups give the same bits; the factor has fewer entries.
#[cfg(feature = "metis")]
#[test]
fn nested_dissection_condenses_like_amd() {
    let g = grid3(14);
    let build = |o| Condensation::<3>::with_ordering(g.a.as_ref(), &g.fixed, &g.fault, o);
    let mut amd = build(InteriorOrdering::Amd).unwrap();
    let mut nd = build(InteriorOrdering::NestedDissection).unwrap();
    assert_eq!(nd.interface_dofs(), amd.interface_dofs());
    let (s_amd, s_nd) = (amd.schur_complement(), nd.schur_complement());
    let scale = max_abs(&s_amd);
    let ds = max_diff(&s_amd, &s_nd);
    assert!(
        scale > 1.0 && ds <= 1e-10 * scale,
        "max |ΔS| = {ds:e} of {scale:e}"
    );
    // A right-hand side and fixed values: g and the extension's interior.
    let n = g.a.nrows();
    let b: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
    let x_fixed: Vec<f64> = (0..n)
        .map(|i| {
            if g.fixed[i] {
                1.0 + (i % 5) as f64
            } else {
                0.0
            }
        })
        .collect();
    let mut g_amd = vec![0.0; amd.dim()];
    let mut g_nd = vec![0.0; nd.dim()];
    amd.condense(&b, &x_fixed, &mut g_amd).unwrap();
    nd.condense(&b, &x_fixed, &mut g_nd).unwrap();
    let dg = max_diff(&g_amd, &g_nd);
    assert!(dg <= 1e-10 * max_abs(&g_amd), "max |Δg| = {dg:e}");
    let mut x_amd = x_fixed.clone();
    for (k, &dof) in amd.interface_dofs().iter().enumerate() {
        x_amd[dof] = (k as f64).cos();
    }
    let mut x_nd = x_amd.clone();
    amd.extend(&mut x_amd).unwrap();
    nd.extend(&mut x_nd).unwrap();
    let dx = max_diff(&x_amd, &x_nd);
    assert!(dx <= 1e-10 * max_abs(&x_amd), "max |Δx| = {dx:e}");
    // Deterministic: a second set-up, the same bits.
    let again = build(InteriorOrdering::NestedDissection).unwrap();
    assert_eq!(again.factor_nnz(), nd.factor_nnz());
    let bits = |s: &[f64]| s.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert!(bits(&again.schur_complement()) == bits(&s_nd));
    println!(
        "14³ nodes: factor entries AMD {}, nested dissection {}; max |ΔS| / max |S| = {:e}",
        amd.factor_nnz(),
        nd.factor_nnz(),
        ds / scale
    );
    assert!(nd.factor_nnz() < amd.factor_nnz());
}
