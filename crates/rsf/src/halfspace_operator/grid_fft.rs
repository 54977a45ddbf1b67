//! The whole space's boundary-element operator of a uniform planar grid of rectangles,
//! applied through FFTs (docs/halfspace.md §11): in an unbounded homogeneous medium the
//! traction a cell's slip causes at another depends only on their offset, so the
//! stiffness is two-level block Toeplitz and its product costs two FFTs of twice the
//! grid's size — the kernel of SEAS BP7 and BP8 at 10 m (80 × 80 cells) in about a
//! millisecond, exact up to round-off.

use std::time::Instant;

use faer::Mat;
use rsf_halfspace::{traction, Element, Medium, RectangleElement, Space};
use rsf_linalg::Parallelism;

use super::bttb::BlockToeplitz2;
use super::error::HalfSpaceOperatorError;
use super::nodes::{alone_nodes, dense_of};
use super::GRID_TOLERANCE;
use crate::error::Result;
use crate::fault_operator::{FaultOperator, KernelReport};
use crate::model::Model;

/// Most cells of a [`WholeSpaceGrid`] along each axis (its spectra hold `4 (2n)²`
/// complex numbers per axis pair: 0.3 GB at 2 048 × 2 048).
pub const MAX_GRID_CELLS: usize = 2048;

/// The boundary-element operator of a fault alone whose cells are a uniform grid of
/// `n_u × n_v` rectangles `h_u × h_v` in one plane of a homogeneous **whole space** — a
/// [`FaultOperator`] for
/// [`SimulationBuilder::build_fault_ode_alone`](crate::SimulationBuilder::build_fault_ode_alone)
/// (SEAS BP7 and BP8, docs/seas-bp8.md).
///
/// **Geometry and unknowns.** The model is a [`Model::fault_only`] whose vertices are the
/// cells' centres (any order) in a plane normal to the fixed component's axis `n`; the
/// free components `t₁`, `t₂` (increasing axis order) are the in-plane axes `u`, `v`, and
/// a node's two unknowns its slip along them (the plus side, where `n` points, relative
/// to the other). The cells' spacings are the grid's (checked to
/// [`GRID_TOLERANCE`](super::GRID_TOLERANCE) `× h`), every cell of the rectangle has one
/// node.
///
/// **The operator.** With `K_cd(i, j) = −τ_c` at the centre of the cell `(i, j)` cells
/// away from a unit slip `d` on a cell (Okada's whole-space rectangle: DC3D's full-space
/// term, [`RectangleElement`] in [`Space::WholeSpace`]; the traction on the receiver's
/// plane along `c`), `(S)_{kc, ld} = w_k K_cd(i_k − i_l, j_k − j_l)` (`w_k` the node's
/// weight, m²): the [`ElementOperator`](super::ElementOperator) of the same cells, to
/// round-off (tested), stored as the `(2n_u − 1)(2n_v − 1)` offsets' `2 × 2` blocks (one
/// evaluation each at set-up) and applied by FFTs of its circulant embedding of order
/// `2n_u × 2n_v` (rustfft; the two slip components packed into one complex field): `O(n_u n_v log(n_u n_v))` per product,
/// nothing approximated. The sign of the normal does not enter (slip and traction both
/// change sign with the side). Rows are not split for ranks.
pub struct WholeSpaceGrid {
    product: BlockToeplitz2,
    /// Per node: its cell (`i + n_u j`).
    cell: Vec<usize>,
    weights: Vec<f64>,
    spacing: [f64; 2],
    /// The grid's first cell centre `(u, v)` (m).
    origin: [f64; 2],
    /// The model's axes `u`, `v` and the plane's normal `n`, and the plane's `x · n` (m).
    axes: [[f64; 3]; 3],
    plane: f64,
    x: Vec<f64>,
    y: Vec<f64>,
    report: KernelReport,
}

impl std::fmt::Debug for WholeSpaceGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WholeSpaceGrid")
            .field("cells", &self.product.cells())
            .field("spacing", &self.spacing)
            .field("report", &self.report)
            .finish_non_exhaustive()
    }
}

/// The blocks `K_cd(i, j)` (Pa/m) of a `h_u × h_v` source cell at the origin of the plane
/// `(u, v)` for the receivers at `(i h_u, j h_v)`, `|i| < n_u`, `|j| < n_v`, at `i_off =
/// i + n_u − 1`, `j_off = j + n_v − 1`: `4` values per offset (`uu, uv, vu, vv`).
fn offset_table(
    medium: &Medium,
    n: [usize; 2],
    h: [f64; 2],
) -> std::result::Result<Vec<[f64; 4]>, HalfSpaceOperatorError> {
    // Okada's frame: strike along x (u), dip 90° (up dip along z: v), normal −y.
    let source = RectangleElement::new([0.0; 3], 0.0, 90.0, h[0], h[1])?;
    let [es, ed, normal] = source.frame();
    let (wu, wv) = (2 * n[0] - 1, 2 * n[1] - 1);
    let mut table = vec![[0.0; 4]; wu * wv];
    for jo in 0..wv {
        for io in 0..wu {
            let i = io as f64 - (n[0] - 1) as f64;
            let j = jo as f64 - (n[1] - 1) as f64;
            let point = [0, 1, 2].map(|k| i * h[0] * es[k] + j * h[1] * ed[k]);
            let r = source.unit_responses(medium, Space::WholeSpace, point)?;
            let entry = &mut table[jo * wu + io];
            for (d, resp) in r[..2].iter().enumerate() {
                let t = traction(&medium.stress(&resp.grad), &normal);
                let along = |e: &[f64; 3]| t[0] * e[0] + t[1] * e[1] + t[2] * e[2];
                entry[d] = -along(&es);
                entry[2 + d] = -along(&ed);
            }
        }
    }
    Ok(table)
}

impl WholeSpaceGrid {
    /// The operator of the fault alone `model` ([`Model::fault_only`], one vertex per
    /// cell at its centre) in the whole space filled by `medium`.
    ///
    /// # Errors
    /// [`HalfSpaceOperatorError::NotAlone`] and [`HalfSpaceOperatorError::Components`]
    /// as [`HalfSpaceOperator::fault_alone`](super::HalfSpaceOperator::fault_alone);
    /// [`HalfSpaceOperatorError::TooFewNodes`] for fewer than two distinct positions
    /// along an in-plane axis; [`HalfSpaceOperatorError::NotPlanar`] for a node off node
    /// 0's plane or with another fixed axis; [`HalfSpaceOperatorError::NotAtCentre`] for
    /// a node off the grid (or on a cell that has one already, `offset` 0);
    /// [`HalfSpaceOperatorError::ElementWithoutNode`] for a cell without a node;
    /// [`HalfSpaceOperatorError::Options`] named `cells` for more than
    /// [`MAX_GRID_CELLS`] along an axis; the kernel's errors.
    pub fn fault_alone(
        model: &Model<3, 3>,
        medium: Medium,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        use HalfSpaceOperatorError as E;
        let clock = Instant::now();
        let nodes = alone_nodes(model)?;
        let fb = &model.frictional_boundary;
        let Some(&(x0, u_axis, v_axis, normal)) = nodes.first() else {
            return Err(E::TooFewNodes { nodes: 0 });
        };
        let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let coords: Vec<[f64; 2]> = nodes
            .iter()
            .map(|(x, ..)| [dot(x, &u_axis), dot(x, &v_axis)])
            .collect();
        // The grid along each axis: its first centre, spacing and count.
        let axis = |a: usize| -> Option<(f64, f64, usize)> {
            // The median gap between distinct values (super::grid::spacing): the spacing
            // of a regular grid, and still its spacing with a few nodes off it (reported
            // below, by name).
            let h = super::grid::spacing(&coords, a)?;
            let lo = coords.iter().map(|c| c[a]).fold(f64::INFINITY, f64::min);
            let hi = coords
                .iter()
                .map(|c| c[a])
                .fold(f64::NEG_INFINITY, f64::max);
            Some((lo, h, ((hi - lo) / h).round() as usize + 1))
        };
        let (Some((u0, hu, nu)), Some((v0, hv, nv))) = (axis(0), axis(1)) else {
            return Err(E::TooFewNodes { nodes: nodes.len() });
        };
        if nu.max(nv) > MAX_GRID_CELLS {
            return Err(E::Options {
                name: "cells",
                value: nu.max(nv) as f64,
                expected: "at most 2048 cells along each axis of the grid",
            });
        }
        let tol = GRID_TOLERANCE * hu.min(hv);
        let plane = dot(&x0, &normal);
        let mut cell = vec![usize::MAX; nodes.len()];
        let mut node_of = vec![usize::MAX; nu * nv];
        for (k, (&(x, t1, t2, n), c)) in nodes.iter().zip(&coords).enumerate() {
            let off = (dot(&x, &normal) - plane).abs();
            if off > tol || (t1, t2, n) != (u_axis, v_axis, normal) {
                return Err(E::NotPlanar {
                    node: k,
                    vertex: fb.nodes[k],
                    position: x,
                    normal,
                    distance: if off > tol {
                        off
                    } else {
                        std::f64::consts::FRAC_PI_2
                    },
                });
            }
            let (fi, fj) = ((c[0] - u0) / hu, (c[1] - v0) / hv);
            let (i, j) = (fi.round(), fj.round());
            let offset = ((fi - i) * hu).hypot((fj - j) * hv);
            let e = j as usize * nu + i as usize;
            if offset > tol || node_of[e] != usize::MAX {
                return Err(E::NotAtCentre {
                    node: k,
                    vertex: fb.nodes[k],
                    position: x,
                    spacing: [hu, hv],
                    offset: if offset > tol { offset } else { 0.0 },
                });
            }
            node_of[e] = k;
            cell[k] = e;
        }
        if let Some(e) = node_of.iter().position(|&k| k == usize::MAX) {
            let (i, j) = (e % nu, e / nu);
            let (u, v) = (u0 + i as f64 * hu, v0 + j as f64 * hv);
            return Err(E::ElementWithoutNode {
                i_strike: i,
                i_dip: j,
                n_strike: nu,
                n_dip: nv,
                centre: [0, 1, 2].map(|k| plane * normal[k] + u * u_axis[k] + v * v_axis[k]),
            });
        }
        let table = offset_table(&medium, [nu, nv], [hu, hv])?;
        let width = 2 * nu - 1;
        let product = BlockToeplitz2::new([nu, nv], |c, d, i, j| {
            let io = (i + nu as isize - 1) as usize;
            let jo = (j + nv as isize - 1) as usize;
            table[jo * width + io][2 * c + d]
        });
        let m = 2 * nodes.len();
        let report = KernelReport {
            // Exact up to round-off, as the dense kernel: the offsets' table and the
            // spectra (two f64 a complex number) are what it stores.
            stored_entries: 4 * table.len() + 2 * product.stored(),
            setup_bytes: 0,
            setup_seconds: clock.elapsed().as_secs_f64(),
            ..KernelReport::dense(m)
        };
        Ok(Self {
            product,
            cell,
            weights: fb.weights.clone(),
            spacing: [hu, hv],
            origin: [u0, v0],
            axes: [u_axis, v_axis, normal],
            plane,
            x: vec![0.0; m],
            y: vec![0.0; m],
            report,
        })
    }

    /// Cells along `u` and `v`.
    pub fn cells(&self) -> [usize; 2] {
        self.product.cells()
    }

    /// The grid's spacings `(h_u, h_v)` (m).
    pub fn spacing(&self) -> [f64; 2] {
        self.spacing
    }

    /// The first cell's centre in the plane's coordinates `(u, v)` (m).
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }

    /// The cell (`i + n_u j`) of every frictional node, by fault index.
    pub fn cell_of_nodes(&self) -> &[usize] {
        &self.cell
    }

    /// The whole space's displacement (m) at each of `points` (model coordinates, m) per
    /// unit slip of every slip unknown, for stations off the fault: per point `3 m` values
    /// (`m` = [`dim`](FaultOperator::dim)), the model's `x`, `y`, `z` components in blocks
    /// of `m`, a block's entry `2k + t` the response to a unit slip `t` (along `u`, `v`)
    /// of node `k` — the layout of
    /// [`HalfSpaceOperator::displacement_columns`](super::HalfSpaceOperator::displacement_columns).
    /// Slip is the motion of the side the normal points to relative to the other
    /// (checked: the jump of the displacement across a cell's centre is its slip). Okada's
    /// full-space rectangle (DC3D's term A) in `medium`, one evaluation per cell and point.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `points` for a
    /// point that is not finite or lies on a cell's edge in the fault's plane; the kernel's
    /// errors.
    pub fn displacement_columns(
        &self,
        medium: &Medium,
        points: &[[f64; 3]],
    ) -> Result<Vec<Vec<f64>>> {
        let [nu, _] = self.cells();
        let [hu, hv] = self.spacing;
        let source = RectangleElement::new([0.0; 3], 0.0, 90.0, hu, hv)
            .map_err(|e| crate::error::invalid("points", e.to_string()))?;
        let [es, ed, n_okada] = source.frame();
        let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let [u_axis, v_axis, normal] = self.axes;
        let m = self.dim();
        let mut out = Vec::with_capacity(points.len());
        for (p, x) in points.iter().enumerate() {
            let refuse =
                |why: String| crate::error::invalid("points", format!("point {p} at {x:?}: {why}"));
            if !x.iter().all(|c| c.is_finite()) {
                return Err(refuse("not finite".into()));
            }
            let (pu, pv, pn) = (
                dot(x, &u_axis),
                dot(x, &v_axis),
                dot(x, &normal) - self.plane,
            );
            let mut row = vec![0.0; 3 * m];
            for (k, &e) in self.cell.iter().enumerate() {
                let (i, j) = ((e % nu) as f64, (e / nu) as f64);
                let du = pu - (self.origin[0] + i * hu);
                let dv = pv - (self.origin[1] + j * hv);
                // The model's plus side (where `normal` points) is the side `n_okada`
                // points to: Okada's unit slip moves it along `+es`, `+ed` relative to the
                // other (tested: the jump across a cell's centre).
                let o = [0, 1, 2].map(|c| du * es[c] + dv * ed[c] + pn * n_okada[c]);
                let r = source
                    .unit_responses(medium, Space::WholeSpace, o)
                    .map_err(|e| refuse(e.to_string()))?;
                for (t, resp) in r[..2].iter().enumerate() {
                    let along = [dot(&resp.u, &es), dot(&resp.u, &ed), dot(&resp.u, &n_okada)];
                    for c in 0..3 {
                        let model =
                            along[0] * u_axis[c] + along[1] * v_axis[c] + along[2] * normal[c];
                        row[c * m + 2 * k + t] = model;
                    }
                }
            }
            out.push(row);
        }
        Ok(out)
    }

    /// The dense `S` (`m × m`, N/m), one product per column.
    ///
    /// # Errors
    /// Those of the product.
    pub fn dense(&mut self) -> Result<Mat<f64>> {
        dense_of(self)
    }
}

impl FaultOperator for WholeSpaceGrid {
    fn dim(&self) -> usize {
        2 * self.cell.len()
    }

    /// The product on one thread whatever `par` (the same bits).
    fn subtract_product(&mut self, x: &[f64], r: &mut [f64], _par: Parallelism) -> Result<()> {
        for (k, &e) in self.cell.iter().enumerate() {
            self.x[2 * e] = x[2 * k];
            self.x[2 * e + 1] = x[2 * k + 1];
        }
        self.y.fill(0.0);
        self.product.add_product(&self.x, &mut self.y);
        // y = K s (Δτ = −K s): r_k −= w_k y_e.
        for (k, (&e, &w)) in self.cell.iter().zip(&self.weights).enumerate() {
            r[2 * k] -= w * self.y[2 * e];
            r[2 * k + 1] -= w * self.y[2 * e + 1];
        }
        Ok(())
    }

    fn report(&self) -> &KernelReport {
        &self.report
    }

    fn operator_origin(&self) -> crate::fault_operator::OperatorOrigin {
        crate::fault_operator::OperatorOrigin::WholeSpace
    }
}
