//! Assembly of the columns of some nodes (`Assembler::on_columns`): every kept column has
//! the rows and bits of the whole assembly's, every other column is empty, on refined 2-D
//! and 3-D meshes and for several keep-sets (all, none, a half, random ones).
use rsf_fem::*;

/// A deterministic pseudo-random stream in `[0, 1)` (64-bit LCG, top 53 bits).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// All, none, the first half, the second half, and three random sets of densities 0.1,
/// 0.5, 0.9.
fn keep_sets(nv: usize) -> Vec<Vec<bool>> {
    let mut rng = Lcg(57);
    let mut sets = vec![
        vec![true; nv],
        vec![false; nv],
        (0..nv).map(|v| v < nv / 2).collect(),
        (0..nv).map(|v| v >= nv / 2).collect(),
    ];
    for density in [0.1, 0.5, 0.9] {
        sets.push((0..nv).map(|_| rng.next() < density).collect());
    }
    sets
}

/// Every column of `part` is the whole's column (row indices and value bits) if its node
/// is kept, empty otherwise; the shapes agree.
fn assert_columns(what: &str, whole: &SparseMatrix, part: &SparseMatrix, keep: &[bool]) {
    assert_eq!((part.nrows(), part.ncols()), (whole.nrows(), whole.ncols()));
    let c = whole.ncols() / keep.len();
    for j in 0..whole.ncols() {
        if keep[j / c] {
            assert_eq!(
                part.row_idx_of_col_raw(j),
                whole.row_idx_of_col_raw(j),
                "{what}: rows of column {j}"
            );
            let bits = |a: &SparseMatrix| a.val_of_col(j).iter().map(|x| x.to_bits()).collect();
            let (p, w): (Vec<u64>, Vec<u64>) = (bits(part), bits(whole));
            assert_eq!(p, w, "{what}: values of column {j}");
        } else {
            assert!(
                part.row_idx_of_col_raw(j).is_empty(),
                "{what}: column {j} is not kept"
            );
        }
    }
}

fn mesh_2d() -> TriangleMesh {
    let coarse = rectangle([0.0, 0.0], [2.0, 1.0], 4, 3, Diagonal::Forward).unwrap();
    MeshHierarchy::refine_uniformly(coarse, 2).finest().clone()
}

fn mesh_3d() -> TetrahedronMesh {
    let coarse = cuboid([0.0; 3], [1.0, 1.5, 0.5], [3, 3, 2]).unwrap();
    MeshHierarchy::refine_uniformly(coarse, 1).finest().clone()
}

/// A material per cell (two alternating) and a density per cell.
fn materials() -> [LinearElasticity; 2] {
    [
        LinearElasticity::isotropic(3e10, 0.25).unwrap(),
        LinearElasticity::isotropic(1e9, 0.35).unwrap(),
    ]
}

fn check_vector<const D: usize>(mesh: &SimplexMesh<D>) {
    let mats = materials();
    let mat = |c: usize| &mats[c % 2];
    let rho = |c: usize| 2000.0 + 10.0 * (c % 7) as f64;
    let whole = Assembler::<D>::new(mesh).unwrap();
    let k = whole.stiffness(mesh, &mats[0]).unwrap();
    let kc = whole.stiffness_by_cell(mesh, mat).unwrap();
    let m = whole.mass(mesh, 2670.0).unwrap();
    let mc = whole.mass_by_cell(mesh, rho).unwrap();
    let e = whole.energy(mesh, 2670.0, &mats[0]).unwrap();
    let ec = whole.energy_by_cell(mesh, |c| (rho(c), mat(c))).unwrap();
    let a = combine(2.0, &m, 0.5, &k).unwrap();
    for keep in keep_sets(mesh.num_vertices()) {
        let part = Assembler::<D>::on_columns(mesh, &keep).unwrap();
        assert_eq!(part.columns(), Some(&keep[..]));
        let kp = part.stiffness(mesh, &mats[0]).unwrap();
        let mp = part.mass(mesh, 2670.0).unwrap();
        let ecp = part.energy_by_cell(mesh, |c| (rho(c), mat(c))).unwrap();
        for (what, of_whole, of_part) in [
            ("K", &k, &kp),
            (
                "K by cell",
                &kc,
                &part.stiffness_by_cell(mesh, mat).unwrap(),
            ),
            ("M", &m, &mp),
            ("M by cell", &mc, &part.mass_by_cell(mesh, rho).unwrap()),
            ("E", &e, &part.energy(mesh, 2670.0, &mats[0]).unwrap()),
            ("E by cell", &ec, &ecp),
            ("2M + K/2", &a, &combine(2.0, &mp, 0.5, &kp).unwrap()),
            // Dropping the other columns of the whole matrix gives the same matrix.
            ("node_columns", &k, &node_columns(&k, &keep).unwrap()),
        ] {
            assert_columns(what, of_whole, of_part, &keep);
        }
        let dropped = node_columns(&k, &keep).unwrap();
        assert_eq!(dropped.symbolic().col_ptr(), kp.symbolic().col_ptr());
        assert_eq!(dropped.symbolic().row_idx(), kp.symbolic().row_idx());
        // One kept column set's matrix does not fit another's assembler.
        let mut other = part.zeros();
        if keep.iter().any(|&x| x) && !keep.iter().all(|&x| x) {
            assert!(matches!(
                whole.assemble_into(mesh, &mut other, |_, _, _| {}),
                Err(Error::PatternMismatch)
            ));
        }
    }
}

#[test]
fn vector_columns_2d_have_the_whole_bits() {
    check_vector(&mesh_2d());
}

#[test]
fn vector_columns_3d_have_the_whole_bits() {
    check_vector(&mesh_3d());
}

#[test]
fn scalar_columns_have_the_whole_bits() {
    let mesh = mesh_2d();
    let whole = Assembler::scalar(&mesh).unwrap();
    let l = whole.laplace(&mesh, 3.2e10).unwrap();
    let m = whole.mass(&mesh, 2670.0).unwrap();
    let e = combine(1.0, &m, 1.0, &l).unwrap();
    for keep in keep_sets(mesh.num_vertices()) {
        let part = Assembler::<2, 1>::on_columns(&mesh, &keep).unwrap();
        let lp = part.laplace(&mesh, 3.2e10).unwrap();
        let mp = part.mass(&mesh, 2670.0).unwrap();
        assert_columns("laplace", &l, &lp, &keep);
        assert_columns("scalar M", &m, &mp, &keep);
        assert_columns("M + K", &e, &combine(1.0, &mp, 1.0, &lp).unwrap(), &keep);
    }
    // The 3-D scalar field too (C = 1 mass of its own element).
    let mesh = mesh_3d();
    let m = Assembler::<3, 1>::with_components(&mesh)
        .unwrap()
        .mass(&mesh, 2.0)
        .unwrap();
    for keep in keep_sets(mesh.num_vertices()) {
        let mp = Assembler::<3, 1>::on_columns(&mesh, &keep)
            .unwrap()
            .mass(&mesh, 2.0)
            .unwrap();
        assert_columns("3-D scalar M", &m, &mp, &keep);
    }
}

#[test]
fn keep_needs_one_flag_per_vertex() {
    let mesh = mesh_2d();
    let nv = mesh.num_vertices();
    assert!(matches!(
        Assembler::<2>::on_columns(&mesh, &vec![true; nv - 1]),
        Err(Error::DimensionMismatch { .. })
    ));
    let k = Assembler::<2>::new(&mesh)
        .unwrap()
        .stiffness(&mesh, &materials()[0])
        .unwrap();
    assert!(matches!(
        node_columns(&k, &vec![true; nv + 1]),
        Err(Error::DimensionMismatch { .. })
    ));
    assert!(matches!(
        node_columns(&k, &[]),
        Err(Error::DimensionMismatch { .. })
    ));
}
