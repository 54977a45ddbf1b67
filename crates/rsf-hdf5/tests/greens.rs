//! The Green's functions of two faults in one HDF5 file (`write_greens`, `read_greens`):
//! read back bit for bit, the file's `S` applied to a vector is the operator's product,
//! symmetric to the operator's stated accuracy, with the ℋ-matrix's accuracy in the
//! attributes; a file of another format is refused by name.

use std::path::{Path, PathBuf};

use rsf::fault_ode::FaultKernel;
use rsf::greens::asymmetry;
use rsf::Model;
use rsf_hdf5::{read_greens, write_greens};

#[path = "../../rsf/tests/suite/greens/faults.rs"]
mod faults;
use faults::{box_with_faults, fault_ode};

fn file(name: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::remove_file(&path).ok();
    path
}

/// A 4 m square in 1/16 m cells, top and bottom held, two vertical faults 1 m long 2 m
/// apart, "west" and "east".
fn two_faults() -> Model<2> {
    box_with_faults(2.0, 2.0, 16.0)
}

#[test]
fn greens_functions_round_trip_and_apply_as_the_operator() {
    let h = FaultKernel::Hierarchical {
        epsilon: 1e-4,
        leaf_size: 4,
    };
    for (kernel, name) in [(FaultKernel::Dense, "dense.h5"), (h, "hierarchical.h5")] {
        let mut ode = fault_ode(two_faults(), kernel);
        let g = ode.greens_functions().unwrap();
        let m = g.dim();
        let s = g.dense(ode.fault_operator_mut(), 1000).unwrap();
        let path = file(name);
        write_greens(&path, &g, &s).unwrap();
        let (back, s_back) = read_greens(&path).unwrap();
        assert_eq!(back, g);
        assert_eq!(
            s_back.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            s.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        // The file's S on a vector is the operator's product (to the sums' round-off).
        let x: Vec<f64> = (0..m)
            .map(|i| ((i * 7919) % 13) as f64 / 6.0 - 1.0)
            .collect();
        let sx = g.apply(ode.fault_operator_mut(), &x).unwrap();
        let scale = sx.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for i in 0..m {
            let row: f64 = (0..m).map(|j| s_back[i * m + j] * x[j]).sum();
            assert!((row - sx[i]).abs() <= 1e-12 * scale, "{i}: {row} {}", sx[i]);
        }
        let asym = asymmetry(&s_back, m);
        eprintln!(
            "{name}: m = {m}, asymmetry {asym:e}, tolerance {:e}, relative error {:e}",
            back.accuracy.tolerance(),
            back.accuracy.relative_error
        );
        assert!(asym <= back.accuracy.tolerance());
        assert_eq!(back.accuracy.kernel, kernel);
        let f = hdf5::File::open(&path).unwrap();
        let unit: hdf5::types::VarLenUnicode = f
            .dataset("S")
            .unwrap()
            .attr("unit")
            .unwrap()
            .read_scalar()
            .unwrap();
        assert_eq!(unit.as_str(), "N/m^2");
        assert_eq!(f.dataset("S").unwrap().shape(), [m, m]);
    }
}

#[test]
fn a_file_of_another_format_or_a_wrong_matrix_is_refused() {
    let mut ode = fault_ode(two_faults(), FaultKernel::Dense);
    let g = ode.greens_functions().unwrap();
    let s = g.dense(ode.fault_operator_mut(), 1000).unwrap();
    let path = file("short.h5");
    let e = write_greens(&path, &g, &s[1..]).unwrap_err();
    assert!(e.to_string().contains("`s`"), "{e}");
    assert!(!path.exists());
    let path = file("other.h5");
    hdf5::File::create(&path).unwrap();
    assert!(read_greens(&path).is_err());
}
