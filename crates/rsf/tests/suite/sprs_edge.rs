//! `sprs` matrices in and out of a `Model` (feature `sprs`): the round trip keeps every
//! entry bit for bit, the energy norm rebuilt from `sprs` matrices agrees with the one the
//! builder assembles element by element, and bad input is a typed error that leaves the
//! model unchanged.

use rsf::fem::SparseMatrix;
use rsf::{Error, Model};
use rsf_scenes::SliderScene;
use sprs::{CsMat, TriMat};

fn slider() -> Model<2> {
    crate::common::with_level(SliderScene::default(), 2)
        .build_model()
        .unwrap()
}

/// Largest entry of `|a − b|` relative to the largest entry of `|a|`, over the union of
/// both patterns (through dense columns: the matrices here are small).
fn relative_difference(a: &SparseMatrix, b: &SparseMatrix) -> f64 {
    assert_eq!((a.nrows(), a.ncols()), (b.nrows(), b.ncols()));
    let (mut diff, mut scale) = (0.0f64, 0.0f64);
    for j in 0..a.ncols() {
        let mut col = vec![0.0; a.nrows()];
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            col[i] += v;
            scale = scale.max(v.abs());
        }
        for (&i, &v) in b.row_idx_of_col_raw(j).iter().zip(b.val_of_col(j)) {
            col[i] -= v;
        }
        diff = col.iter().fold(diff, |d, x| d.max(x.abs()));
    }
    diff / scale
}

#[test]
fn round_trip_keeps_every_entry() {
    let model = slider();
    let k = model.stiffness_sprs().unwrap();
    let m = model.mass_sprs().unwrap().expect("the slider has mass");
    let n = 2 * model.num_nodes();
    assert_eq!((k.shape(), m.shape()), ((n, n), (n, n)));
    assert!(k.is_csc() && m.is_csc());
    let mut back = model.clone();
    back.set_matrices_sprs(k.view(), Some(m.view())).unwrap();
    assert!(crate::common::same_bits(&back.stiffness, &model.stiffness));
    assert!(crate::common::same_bits(
        back.mass.as_ref().unwrap(),
        model.mass.as_ref().unwrap()
    ));
    back.validate().unwrap();
    // K + M summed as matrices vs assembled element by element: the same matrix up to
    // the rounding of the different summation order.
    let d = relative_difference(&back.energy_norm, &model.energy_norm);
    assert!(d < 1e-14, "energy norm differs by {d:.2e}");
}

#[test]
fn without_mass_the_energy_norm_is_the_stiffness() {
    let mut model = slider();
    let k = model.stiffness_sprs().unwrap();
    model.set_matrices_sprs(k.view(), None).unwrap();
    assert!(model.mass.is_none() && model.mass_sprs().unwrap().is_none());
    assert!(crate::common::same_bits(
        &model.energy_norm,
        &model.stiffness
    ));
}

#[test]
fn bad_matrices_are_typed_errors_and_leave_the_model_unchanged() {
    let model = slider();
    let n = 2 * model.num_nodes();
    let k = model.stiffness_sprs().unwrap();
    let small: CsMat<f64> = CsMat::eye(n - 1);
    let check = |result: rsf::Result<()>, after: &Model<2>, name: &str| {
        match result {
            Err(Error::InvalidParameter { name: got, .. }) if got == name => {}
            Err(Error::Fem(_)) if name == "csr" => {}
            other => panic!("{name}: expected a typed error, got {other:?}"),
        }
        assert!(crate::common::same_bits(&after.stiffness, &model.stiffness));
        assert!(crate::common::same_bits(
            &after.energy_norm,
            &model.energy_norm
        ));
        assert!(after.mass.is_some());
    };
    let mut m = model.clone();
    let r = m.set_matrices_sprs(small.view(), None);
    check(r, &m, "stiffness");
    let mut m = model.clone();
    let r = m.set_matrices_sprs(k.view(), Some(small.view()));
    check(r, &m, "mass");
    let csr = k.to_csr();
    let mut m = model.clone();
    let r = m.set_matrices_sprs(csr.view(), None);
    check(r, &m, "csr");
}

/// A user's matrix with unsorted triplets and duplicates arrives summed and sorted.
#[test]
fn triplets_from_sprs_are_summed() {
    let mut model = slider();
    let n = 2 * model.num_nodes();
    let mut t = TriMat::new((n, n));
    for i in (0..n).rev() {
        t.add_triplet(i, i, 1.0);
        t.add_triplet(i, i, 2.0);
    }
    let k: CsMat<f64> = t.to_csc();
    model.set_matrices_sprs(k.view(), None).unwrap();
    assert_eq!(model.stiffness.compute_nnz(), n);
    assert!(model.stiffness.val().iter().all(|&v| v == 3.0));
}
