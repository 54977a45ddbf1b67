//! How the output reads the fault's nodes (positions, areas, the slip of each in the
//! model's field, the regular grid they fill) and where the off-fault stations' motion
//! comes from.

use crate::error::{invalid, Result};

/// Where an off-fault station's displacement comes from.
pub(super) enum BodySource {
    /// A fault alone: its side of the fault (`±1`) and its displacement per unit slip of
    /// every unknown (3 rows of `m`).
    Columns { side: f64, columns: Vec<f64> },
    /// A volume model: the vertex (Cartesian components).
    Vertex(usize),
}

impl BodySource {
    /// The sources of the off-fault stations `stations` (`(x₂, x₁, x₃)`) of a fault alone,
    /// one entry of `columns` each: the station's side of the fault (the sign of its `x₁`)
    /// and its displacement per unit slip.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `body_columns`
    /// for another number of columns than stations.
    pub(super) fn of_columns(
        stations: &[(f64, f64, f64)],
        columns: Vec<Vec<f64>>,
    ) -> Result<Vec<Self>> {
        if columns.len() != stations.len() {
            return Err(invalid(
                "body_columns",
                format!("{} for {} stations", columns.len(), stations.len()),
            ));
        }
        Ok(stations
            .iter()
            .zip(columns)
            .map(|(&(_, n, _), columns)| Self::Columns {
                side: n.signum(),
                columns,
            })
            .collect())
    }
}

/// How the slip `(slip₂, slip₃)` of a fault node is read off the model's field: the
/// node's first dof and the coefficients of its three components for each (`x₃` down).
#[derive(Debug, Clone, Copy)]
pub(super) struct SlipMap {
    pub(super) dof: usize,
    pub(super) e2: [f64; 3],
    pub(super) e3: [f64; 3],
}

impl SlipMap {
    pub(super) fn of(&self, x: &[f64]) -> (f64, f64) {
        let b = &x[self.dof..self.dof + 3];
        let dot = |e: &[f64; 3]| e[0] * b[0] + e[1] * b[1] + e[2] * b[2];
        (dot(&self.e2), dot(&self.e3))
    }
}

/// The fault's nodes as the output sees them: per fault index its position `(x₂, x₃)`
/// (m), area (m²) and slip map, and the regular grid they fill (for the stations).
pub(super) struct FaultLayout {
    pub(super) positions: Vec<[f64; 2]>,
    pub(super) areas: Vec<f64>,
    pub(super) slip: Vec<SlipMap>,
    /// The grid's first point `(x₂, x₃)` (m), spacing (m), points along strike and dip,
    /// and the fault index of every point (strike fastest).
    pub(super) origin: [f64; 2],
    pub(super) spacing: f64,
    pub(super) n: [usize; 2],
    pub(super) index: Vec<usize>,
    /// `+1` where the model's `z` is the benchmark's `x₃`, `−1` where it is `−x₃`.
    pub(super) z_sign: f64,
}

impl FaultLayout {
    /// A fault alone's cells (one vertex per cell, the normal `x` fixed, in the order of
    /// `cells`: centres `(x₂, x₃)`, m, `x₂` fastest) on a grid of `n` cells of side `dx`,
    /// the model's `z` being `z_sign x₃`.
    pub(super) fn of_cells(cells: Vec<[f64; 2]>, dx: f64, n: [usize; 2], z_sign: f64) -> Self {
        Self {
            areas: vec![dx * dx; cells.len()],
            slip: (0..cells.len())
                .map(|k| SlipMap {
                    dof: 3 * k,
                    e2: [0.0, 1.0, 0.0],
                    e3: [0.0, 0.0, z_sign],
                })
                .collect(),
            origin: cells[0],
            spacing: dx,
            n,
            index: (0..cells.len()).collect(),
            positions: cells,
            z_sign,
        }
    }

    /// The four grid points around the point `x = (x₂, x₃)` (m) and their bilinear
    /// weights (constant beyond the outer points), as fault indices.
    pub(super) fn bilinear(&self, x: [f64; 2]) -> [(usize, f64); 4] {
        let axis = |a: usize| -> (usize, f64) {
            let n = self.n[a];
            if n < 2 {
                return (0, 0.0);
            }
            let f = ((x[a] - self.origin[a]) / self.spacing).clamp(0.0, (n - 1) as f64);
            let i = (f.floor() as usize).min(n - 2);
            (i, f - i as f64)
        };
        let ((i, wi), (j, wj)) = (axis(0), axis(1));
        let at = |di: usize, dj: usize| {
            let (i, j) = ((i + di).min(self.n[0] - 1), (j + dj).min(self.n[1] - 1));
            self.index[j * self.n[0] + i]
        };
        [
            (at(0, 0), (1.0 - wi) * (1.0 - wj)),
            (at(1, 0), wi * (1.0 - wj)),
            (at(0, 1), (1.0 - wi) * wj),
            (at(1, 1), wi * wj),
        ]
    }
}

/// A regular grid of a volume model's fault nodes: its first point `(x₂, x₃)` (m), spacing
/// (m), points along strike and dip, and the sign of `x₃` in the model's `z`.
#[derive(Debug, Clone, Copy)]
pub(super) struct NodeGrid {
    pub(super) origin: [f64; 2],
    pub(super) spacing: f64,
    pub(super) n: [usize; 2],
    pub(super) z_sign: f64,
}

impl FaultLayout {
    /// The frictional nodes of a volume model `model` (split pairs of its fault inside the
    /// body, in the order of `model.frictional_boundary`), which must fill `grid` point
    /// for point: positions `(y, z_sign z)`, areas the lumped weights, slip the jump of each
    /// pair in its frame (`slip₂` along `t₁`, `slip₃` along `z_sign · t₂`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `model` for a
    /// model without an internal fault, a frictional node that is not a pair or off the
    /// grid, or a grid point without a node.
    pub(super) fn of_volume(
        model: &rsf::Model<3, 3>,
        grid: NodeGrid,
    ) -> crate::error::Result<Self> {
        use crate::error::invalid;
        let fault = model
            .internal_fault
            .as_ref()
            .ok_or_else(|| invalid("model", "has no fault inside the body"))?;
        let fb = &model.frictional_boundary;
        let NodeGrid {
            origin,
            spacing: dx,
            n,
            z_sign,
        } = grid;
        let mut index = vec![usize::MAX; n[0] * n[1]];
        let mut layout = FaultLayout {
            positions: Vec::with_capacity(fb.len()),
            areas: fb.weights.clone(),
            slip: Vec::with_capacity(fb.len()),
            origin,
            spacing: dx,
            n,
            index: Vec::new(),
            z_sign,
        };
        for (k, &p) in fb.nodes.iter().enumerate() {
            let x = model.vertices[p];
            let i = fault
                .pair_index(p)
                .ok_or_else(|| invalid("model", format!("frictional node {k} is not a pair")))?;
            let r = fault.transform.frames[i];
            let along = [x[1], z_sign * x[2]];
            layout.positions.push(along);
            layout.slip.push(SlipMap {
                dof: 3 * p,
                e2: r[1],
                e3: r[2].map(|c| z_sign * c),
            });
            let (fi, fj) = ((along[0] - origin[0]) / dx, (along[1] - origin[1]) / dx);
            let (i, j) = (fi.round(), fj.round());
            if (fi - i).abs() > 1e-6 || (fj - j).abs() > 1e-6 || i < 0.0 || j < 0.0 {
                return Err(invalid(
                    "model",
                    format!("frictional node {k} at {x:?} is off the {dx} m grid"),
                ));
            }
            let (i, j) = (i as usize, j as usize);
            if i >= n[0] || j >= n[1] {
                return Err(invalid(
                    "model",
                    format!("frictional node {k} at {x:?} is outside the fault's grid"),
                ));
            }
            index[j * n[0] + i] = k;
        }
        if let Some(g) = index.iter().position(|&k| k == usize::MAX) {
            return Err(invalid(
                "model",
                format!(
                    "no frictional node at grid point ({}, {}) of the fault",
                    g % n[0],
                    g / n[0]
                ),
            ));
        }
        layout.index = index;
        Ok(layout)
    }
}
