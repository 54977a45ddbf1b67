//! The finite-element and boundary-element fault operators compared in the operator norm on
//! the slips both resolve (issue 55, docs/three-d.md "The operator norm on resolved
//! slips"): the Galerkin matrices of the two operators on the first `k × k` sine modes of
//! the buried vertical rectangle, both tangential directions.
//!
//! The operator norm over all slips of the fault grid is the norm of the grid-scale waves,
//! where the two discretisations differ by a constant factor at every h (docs/three-d.md
//! "What converges and what does not"). Restricted to a fixed space of slips — the modes
//! `φ_{pqd}(x) = sin(pπ (x + a)/2a) sin(qπ (z − z_b)/W) e_d`, `1 ≤ p, q ≤ k`, `d` strike or
//! dip, zero on the rim — the norm sees the elastic medium, and its difference is what the
//! refinement can shrink: `‖Ĝ_FE − Ĝ_BEM‖₂ / ‖Ĝ_BEM‖₂` with `Ĝ = L⁻¹ G L⁻ᵀ`, `G_ij` the
//! work of mode `i` on the traction of mode `j` over the fault and `M = L Lᵀ` the modes'
//! Gram matrix in the same quadrature (the lumped weights of the fault nodes): the
//! operators' norm on the span of the modes, in its L² orthonormal basis.
//!
//! The finite-element side: one model on the refinement hierarchy with every pair's slip
//! prescribed ([`compare_smooth`](super::compare_smooth)'s model), its static problem set
//! up once ([`StaticSolver`], multigrid) and solved per mode with the mode's slips and far
//! field as held values, and `G_ij = Σ_n φ_i(x_n) · f_j⁺(n)` with the plus copies' nodal
//! forces (the consistent integral of `φ_i`'s hat functions against the traction). The
//! boundary-element side: the same slips on square cells of side `h` centred on the pairs
//! (`RectangularFault`'s discretisation), Okada's fields superposed, and
//! `G_ij = Σ_n w_n φ_i(x_n) · σ_j(x_n) e_y` at the cells' centres with the lumped weights
//! `w_n`. The far faces of the model are held at the boundary-element field of each mode.

use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Mat, Par, Side};
use rayon::prelude::*;
use rsf_halfspace::{Deformation, Medium, Okada, Rectangle};

use super::common::{Solver, MU, NU};
use super::error::{ComparisonError, Result};
use super::measure::fault_weights;
use super::vertical::{refined_model, Fault, Held};
use crate::model::{InternalFault, Model, StaticSolver};

/// The comparison of the two operators on one mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeComparison {
    /// The cell size on the fault (m).
    pub h: f64,
    /// Vertices of the model.
    pub vertices: usize,
    /// The number of modes (`2 k²`).
    pub modes: usize,
    /// `‖Ĝ_FE − Ĝ_BEM‖₂ / ‖Ĝ_BEM‖₂`: the operators' relative difference in the operator
    /// norm on the modes' span.
    pub operator: f64,
    /// `‖Ĝ_FE‖₂ / ‖Ĝ_BEM‖₂`.
    pub norm_ratio: f64,
    /// The largest relative difference of one mode's own work, `|G_FE,ii − G_BEM,ii| /
    /// |G_BEM,ii|`.
    pub worst_mode: f64,
    /// `‖Ĝ_FE − Ĝ_FEᵀ‖₂ / ‖Ĝ_FE‖₂`: the condensed stiffness is symmetric, but each mode's
    /// far faces are held at its own boundary-element field, which adds a coupling to
    /// those faces that is not (measured 1.7e-4 at W/4, 1.1e-5 at W/32).
    pub asymmetry: f64,
}

/// One mode: the slip `sin(p π (x + a)/2a) sin(q π (z − z_b)/W)` along `direction`
/// (Cartesian, hanging wall `y < 0`).
#[derive(Debug, Clone, Copy)]
struct Mode {
    p: u32,
    q: u32,
    direction: [f64; 3],
}

impl Mode {
    fn slip(&self, fault: &Fault, x: [f64; 3]) -> [f64; 3] {
        let pi = std::f64::consts::PI;
        let (a, zb, w) = (fault.half_length, -fault.bottom, fault.bottom - fault.top);
        let m = (f64::from(self.p) * pi * (x[0] + a) / (2.0 * a)).sin()
            * (f64::from(self.q) * pi * (x[2] - zb) / w).sin();
        self.direction.map(|d| d * m)
    }
}

/// The modes of [`compare_modes`], strike then dip, `p` then `q`.
fn modes(k: u32) -> Vec<Mode> {
    let mut out = Vec::new();
    for direction in [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]] {
        for p in 1..=k {
            for q in 1..=k {
                out.push(Mode { p, q, direction });
            }
        }
    }
    out
}

/// The boundary-element cells: a square of side `h` centred on every pair, each with its
/// pair's slip in every mode (Okada's `[U1, U2]`: strike, up-dip on this vertical plane).
struct Cells {
    okada: Vec<Okada>,
    /// `slips[c][m]`: cell `c`'s `[U1, U2]` in mode `m`.
    slips: Vec<Vec<[f64; 2]>>,
}

impl Cells {
    /// The deformation of every mode at `x`: each cell's unit responses once, weighted by
    /// its slips of all modes (cells summed in order).
    fn at(
        &self,
        x: [f64; 3],
        out: &mut [Deformation],
    ) -> std::result::Result<(), rsf_halfspace::Error> {
        out.fill(Default::default());
        for (okada, slips) in self.okada.iter().zip(&self.slips) {
            let [strike, dip, _] = okada.unit_responses(x)?;
            for (o, s) in out.iter_mut().zip(slips) {
                *o = o.add_scaled(s[0], &strike).add_scaled(s[1], &dip);
            }
        }
        Ok(())
    }
}

/// The two operators on the first `k × k` modes of the buried rectangle `fault` (both
/// directions; its `slip` is not used), the model on the hierarchy of
/// [`compare_refined`](super::compare_refined) (`mesh`, `far`), solved by multigrid. Its
/// stages: the cells of the boundary elements with the modes' slips
/// (`Cells::of_pairs`), the boundary-element Galerkin matrix and the modes' Gram matrix
/// (`bem_galerkin`), the finite-element one (`fe_galerkin`), and their norms on the
/// modes' span (`compared`).
///
/// # Errors
/// [`ComparisonError::Setup`] for `k` zero or above 8, a surface-breaking `fault`, a Gram
/// matrix that is not positive definite (fewer nodes than modes) or a boundary-element
/// Galerkin matrix of norm 0; the errors of [`compare_refined`](super::compare_refined).
pub fn compare_modes(
    fault: Fault,
    mesh: (f64, u32, f64),
    far: f64,
    k: u32,
) -> Result<ModeComparison> {
    if !(1..=8).contains(&k) {
        return Err(ComparisonError::Setup(format!(
            "the modes per direction k = {k} must be in 1..=8"
        )));
    }
    if fault.top == 0.0 {
        return Err(ComparisonError::Setup(
            "the modes need a buried fault".into(),
        ));
    }
    let modes = modes(k);
    let h = mesh.0 / f64::from(1u32 << mesh.1);
    // Any slip builds the model: every pair's two tangential components are prescribed
    // (set per mode below); its own static problem is not solved.
    let model = refined_model(
        fault,
        mesh,
        far,
        (Held::Zero, Solver::Multigrid),
        |_| [1.0, 0.0, 1.0],
        true,
    )?;
    let f = model
        .internal_fault
        .as_ref()
        .ok_or_else(|| ComparisonError::Setup("the model has no internal fault".into()))?;
    let medium = Medium::from_shear_poisson(MU, NU)?;
    let on = ModesOnPairs {
        model: &model,
        fault: &fault,
        pairs: f.pairs(),
        modes: &modes,
    };
    let cells = Cells::of_pairs(&on, &medium, h)?;
    let phi: Vec<Vec<[f64; 3]>> = on
        .pairs
        .iter()
        .map(|&(mi, _)| modes.iter().map(|m| m.slip(&fault, on.at(mi))).collect())
        .collect();
    let (gram, g_bem) = bem_galerkin(&on, f, &cells, &medium, &phi)?;
    // Level 0 is the coarsest mesh alone (no hierarchy): a direct solve, as in
    // `refined_model`.
    let method = if mesh.1 == 0 {
        Solver::Direct
    } else {
        Solver::Multigrid
    };
    let g_fe = fe_galerkin(&on, f, &cells, &phi, far, method)?;
    compared(&gram, &g_fe, &g_bem, h, model.num_nodes())
}

/// The modes at the fault's pairs (plus copy, minus copy) of `model`.
struct ModesOnPairs<'a> {
    model: &'a Model<3>,
    fault: &'a Fault,
    pairs: &'a [(usize, usize)],
    modes: &'a [Mode],
}

impl ModesOnPairs<'_> {
    /// The position (m) of vertex `mi`.
    fn at(&self, mi: usize) -> [f64; 3] {
        self.model.vertices[mi]
    }
}

impl Cells {
    /// The square cells of side `h` centred on the pairs of `on` (vertical, Okada's
    /// rectangles in `medium`), each with its slips of every mode (strike, dip).
    ///
    /// # Errors
    /// A rectangle Okada refuses (above the surface).
    fn of_pairs(on: &ModesOnPairs<'_>, medium: &Medium, h: f64) -> Result<Self> {
        Ok(Self {
            okada: on
                .pairs
                .iter()
                .map(|&(mi, _)| {
                    let x = on.at(mi);
                    let rect = Rectangle::new(
                        -x[2] + h / 2.0,
                        90.0,
                        [x[0] - h / 2.0, x[0] + h / 2.0],
                        [0.0, h],
                    )?;
                    Ok(Okada::new(medium.alpha(), rect)?)
                })
                .collect::<Result<_>>()?,
            slips: on
                .pairs
                .iter()
                .map(|&(mi, _)| {
                    on.modes
                        .iter()
                        .map(|m| {
                            let s = m.slip(on.fault, on.at(mi));
                            [s[0], s[2]]
                        })
                        .collect()
                })
                .collect(),
        })
    }
}

/// `a · b`.
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The modes' Gram matrix `M_ij = Σ_n w_n φ_i · φ_j` and the boundary-element Galerkin
/// matrix `G_ij = Σ_n w_n φ_i · σ_j e_y` at the pairs (the cells' centres; `phi[n][i]`
/// mode `i`'s slip at pair `n`, `w_n` the lumped weights of the fault `f`).
///
/// # Errors
/// Okada's at a centre.
fn bem_galerkin(
    on: &ModesOnPairs<'_>,
    f: &InternalFault<3>,
    cells: &Cells,
    medium: &Medium,
    phi: &[Vec<[f64; 3]>],
) -> Result<(Mat<f64>, Mat<f64>)> {
    let n_modes = on.modes.len();
    let pairs = on.pairs;
    let weights = fault_weights(on.model, f);
    let tractions: Vec<Vec<[f64; 3]>> = pairs
        .par_iter()
        .map(|&(mi, _)| {
            let mut d = vec![Deformation::default(); n_modes];
            cells.at(on.at(mi), &mut d)?;
            Ok(d.iter()
                .map(|d| rsf_halfspace::traction(&medium.stress(&d.grad), &[0.0, 1.0, 0.0]))
                .collect())
        })
        .collect::<std::result::Result<_, rsf_halfspace::Error>>()?;
    let gram = Mat::from_fn(n_modes, n_modes, |i, j| {
        (0..pairs.len())
            .map(|n| weights[pairs[n].0] * dot(&phi[n][i], &phi[n][j]))
            .sum::<f64>()
    });
    let g_bem = Mat::from_fn(n_modes, n_modes, |i, j| {
        (0..pairs.len())
            .map(|n| weights[pairs[n].0] * dot(&phi[n][i], &tractions[n][j]))
            .sum::<f64>()
    });
    Ok((gram, g_bem))
}

/// The finite-element Galerkin matrix `G_ij = Σ_n φ_i(x_n) · f_j⁺(n)`: per mode `j`, the
/// far faces (beyond `far`) held at the cells' field, every pair's jump the mode's slip,
/// one static solve by `method`, the plus copies' nodal forces.
///
/// # Errors
/// Okada's on the far faces; the static solver's.
fn fe_galerkin(
    on: &ModesOnPairs<'_>,
    f: &InternalFault<3>,
    cells: &Cells,
    phi: &[Vec<[f64; 3]>],
    far: f64,
    method: Solver,
) -> Result<Mat<f64>> {
    let (model, pairs, n_modes) = (on.model, on.pairs, on.modes.len());
    let tol = 1e-9 * far;
    let far_face: Vec<usize> = (0..model.num_nodes())
        .filter(|&q| {
            let x = model.vertices[q];
            x[0].abs() > far - tol || x[1].abs() > far - tol || x[2] < -far + tol
        })
        .collect();
    let far_field: Vec<Vec<[f64; 3]>> = far_face
        .par_iter()
        .map(|&q| {
            let mut d = vec![Deformation::default(); n_modes];
            cells.at(model.vertices[q], &mut d)?;
            Ok(d.iter().map(|d| d.u).collect())
        })
        .collect::<std::result::Result<_, rsf_halfspace::Error>>()?;
    let mut solver = StaticSolver::new(model, method.options())?;
    let mut g_fe = Mat::<f64>::zeros(n_modes, n_modes);
    let mut force = vec![0.0; model.num_dofs()];
    for (j, mode) in on.modes.iter().enumerate() {
        let mut v = vec![0.0; model.num_dofs()];
        for (idx, &q) in far_face.iter().enumerate() {
            for c in 0..3 {
                v[3 * q + c] = far_field[idx][j][c];
            }
        }
        for (k, &(mi, _)) in pairs.iter().enumerate() {
            let r = f.transform.frames[k];
            let s = mode.slip(on.fault, on.at(mi));
            for a in 0..2 {
                v[3 * mi + a] = (0..3).map(|b| r[b][a] * s[b]).sum();
            }
        }
        solver.solve(&mut v)?;
        force.fill(0.0);
        rsf_fem::spmv_add(model.stiffness.as_ref(), 1.0, &v, &mut force);
        for (n, (k, &(mi, _))) in pairs.iter().enumerate().enumerate() {
            let r = f.transform.frames[k];
            let fj = [force[3 * mi], force[3 * mi + 1], force[3 * mi + 2]];
            let f_plus: [f64; 3] = std::array::from_fn(|i| (0..3).map(|a| r[i][a] * fj[a]).sum());
            for i in 0..n_modes {
                g_fe[(i, j)] += dot(&phi[n][i], &f_plus);
            }
        }
    }
    Ok(g_fe)
}

/// The operators' norms on the modes' span, in its orthonormal basis (`Ĝ = L⁻¹ G L⁻ᵀ`,
/// `M = L Lᵀ` the Gram matrix): the relative difference, the ratio of norms, the worst
/// diagonal entry and the finite-element side's asymmetry, on the mesh of cell size `h`
/// with `vertices` vertices.
///
/// # Errors
/// [`ComparisonError::Setup`] for a Gram matrix that is not positive definite, singular
/// values that did not converge, a boundary-element matrix of norm 0.
fn compared(
    gram: &Mat<f64>,
    g_fe: &Mat<f64>,
    g_bem: &Mat<f64>,
    h: f64,
    vertices: usize,
) -> Result<ModeComparison> {
    let n_modes = gram.nrows();
    let llt = gram.llt(Side::Lower).map_err(|_| {
        ComparisonError::Setup("the modes' Gram matrix is not positive definite".into())
    })?;
    let l = llt.L();
    let orthonormal = |g: &Mat<f64>| -> Mat<f64> {
        let mut x = g.clone();
        solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq);
        let mut y = x.transpose().to_owned();
        solve_lower_triangular_in_place(l, y.as_mut(), Par::Seq);
        y.transpose().to_owned()
    };
    let (fe, bem) = (orthonormal(g_fe), orthonormal(g_bem));
    let norm = |m: &Mat<f64>| -> Result<f64> {
        let s = m.singular_values().map_err(|e| {
            ComparisonError::Setup(format!("the singular values did not converge: {e:?}"))
        })?;
        Ok(s.iter().fold(0.0f64, |a, &b| a.max(b)))
    };
    let bem_norm = norm(&bem)?;
    if !(bem_norm > 0.0) {
        return Err(ComparisonError::Setup(
            "the boundary-element Galerkin matrix has norm 0".into(),
        ));
    }
    let worst_mode = (0..n_modes)
        .map(|i| ((g_fe[(i, i)] - g_bem[(i, i)]) / g_bem[(i, i)]).abs())
        .fold(0.0f64, f64::max);
    Ok(ModeComparison {
        h,
        vertices,
        modes: n_modes,
        operator: norm(&(&fe - &bem))? / bem_norm,
        norm_ratio: norm(&fe)? / bem_norm,
        worst_mode,
        asymmetry: norm(&(&fe - fe.transpose()))? / norm(&fe)?,
    })
}
