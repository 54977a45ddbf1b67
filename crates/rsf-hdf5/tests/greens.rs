//! The Green's functions of two faults in one HDF5 file (`write_greens`, `read_greens`):
//! read back bit for bit, the file's `S` applied to a vector is the operator's product,
//! symmetric to the operator's stated accuracy, with the ℋ-matrix's accuracy in the
//! attributes; a file of another format is refused by name.

use std::path::{Path, PathBuf};

use rsf::fault_ode::{FaultKernel, FaultOdeOptions};
use rsf::fem::{rectangle, Diagonal};
use rsf::friction::{AsinhLaw, RateStateParams};
use rsf::greens::asymmetry;
use rsf::state::Aging;
use rsf::time::Quasistatic;
use rsf::{FaultOde, Material, Model, ModelBuilder, Part, SimulationBuilder};
use rsf_hdf5::{read_greens, write_greens};

fn file(name: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::remove_file(&path).ok();
    path
}

/// A 4 m square in 1/16 m cells, top and bottom held, two vertical faults 1 m long 2 m
/// apart, "west" and "east".
fn two_faults() -> Model<2> {
    let mesh = rectangle([-2.0, -2.0], [4.0, 4.0], 65, 65, Diagonal::Forward).unwrap();
    ModelBuilder::new(mesh)
        .material(Material::new(3e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(Part::predicate("top", |x| x[1] > 2.0 - 1e-9), [1e-9, 0.0])
        .dirichlet(
            Part::predicate("bottom", |x| x[1] < -2.0 + 1e-9),
            [-1e-9, 0.0],
        )
        .internal_fault("west", [-1.0, -0.5], [-1.0, 0.5])
        .internal_fault("east", [1.0, -0.5], [1.0, 0.5])
        .build()
        .unwrap()
}

fn fault_ode(kernel: FaultKernel) -> FaultOde<2, AsinhLaw, Aging> {
    let p = RateStateParams {
        mu0: 0.6,
        a: 0.015,
        b: 0.01,
        v0: 1e-6,
        l: 1e-4,
        sigma_n: 5e6,
    };
    SimulationBuilder::new(two_faults())
        .friction(AsinhLaw::new(p).unwrap())
        .state_law(Aging::new(p.l).unwrap())
        .initial_state((p.l / 1e-9f64).ln())
        .integrator(Quasistatic::new())
        .radiation_damping(5e6)
        .time_step(1.0)
        .build_fault_ode(FaultOdeOptions {
            kernel,
            ..Default::default()
        })
        .unwrap()
}

#[test]
fn greens_functions_round_trip_and_apply_as_the_operator() {
    let h = FaultKernel::Hierarchical {
        epsilon: 1e-4,
        leaf_size: 4,
    };
    for (kernel, name) in [(FaultKernel::Dense, "dense.h5"), (h, "hierarchical.h5")] {
        let mut ode = fault_ode(kernel);
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
    let mut ode = fault_ode(FaultKernel::Dense);
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
