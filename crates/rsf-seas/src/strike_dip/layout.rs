//! How the output reads the fault's nodes (positions, areas, the slip of each in the
//! model's field, the regular grid they fill) and where the off-fault stations' motion
//! comes from.

/// Where an off-fault station's displacement comes from.
pub(super) enum BodySource {
    /// A fault alone: its side of the fault (`±1`) and its displacement per unit slip of
    /// every unknown (3 rows of `m`).
    Columns { side: f64, columns: Vec<f64> },
    /// A volume model: the vertex (Cartesian components).
    Vertex(usize),
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
