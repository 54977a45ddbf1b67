//! The stages of [`HalfSpaceOperator::from_nodes`](super::HalfSpaceOperator): Okada's
//! axes from the fault's normal, the regular grid the frictional nodes sit on (its
//! spacing, extent and each node's element), and the checks that the nodes are the
//! centres of a planar rectangular fault below the free surface.

use super::error::HalfSpaceOperatorError as E;
use super::nodes::Node;
use super::{cross, dot, unit, GRID_TOLERANCE};

/// Okada's axes of a planar fault of normal `n_fe` (the finite element's, into the plus
/// side): the upward normal, up dip and strike, the dip (degrees), the model axis that
/// Okada's `y` maps to, and the sign that maps the plus side onto the hanging wall.
pub(super) struct PlaneAxes {
    /// `+1` where Okada's normal is `n_fe`, `−1` where it is `−n_fe`.
    pub sign: f64,
    /// Okada's normal (unit, pointing up; horizontal for a vertical fault).
    pub normal: [f64; 3],
    /// Unit vector up dip.
    pub up_dip: [f64; 3],
    /// Unit vector along strike.
    pub strike: [f64; 3],
    /// Dip (degrees).
    pub dip_deg: f64,
    /// Okada's `y` axis in the model (`e_z × strike`, or `e_y` for a horizontal fault).
    pub axis_y: [f64; 3],
}

impl PlaneAxes {
    /// The axes of the fault of normal `n_fe`: Okada's normal is `±n_fe` pointing up (a
    /// vertical fault keeps `n_fe`); a horizontal fault strikes along the model's `x`.
    pub fn of_normal(n_fe: [f64; 3]) -> Self {
        let vertical = n_fe[2].abs() < 1e-12;
        let sign = if vertical || n_fe[2] > 0.0 { 1.0 } else { -1.0 };
        let n_ok = if vertical {
            [n_fe[0], n_fe[1], 0.0]
        } else {
            n_fe.map(|x| sign * x)
        };
        let n_ok = unit(n_ok);
        let (up_dip, strike) = if n_ok[2] > 1.0 - 1e-12 {
            // Horizontal: strike along the model's x, up dip along y.
            ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
        } else {
            let ez = [0.0, 0.0, 1.0];
            let d = if vertical {
                ez
            } else {
                unit([0, 1, 2].map(|i| ez[i] - n_ok[2] * n_ok[i]))
            };
            (d, unit(cross(&d, &n_ok)))
        };
        let dip_deg = if vertical {
            90.0
        } else {
            n_ok[2].clamp(-1.0, 1.0).acos().to_degrees()
        };
        let axis_y = cross(&[0.0, 0.0, 1.0], &strike);
        let axis_y = if dot(&axis_y, &axis_y) > 0.5 {
            axis_y
        } else {
            [0.0, 1.0, 0.0]
        };
        Self {
            sign,
            normal: n_ok,
            up_dip,
            strike,
            dip_deg,
            axis_y,
        }
    }
}

/// The regular grid of elements the frictional nodes are the centres of: spacings along
/// strike and dip, the first node's coordinates `ξ₀` (smallest along strike) and `η₁`
/// (largest up dip) from node 0, the element counts, each node's element (row-major, row
/// 0 at `η₁`) and the tolerance of the checks.
pub(super) struct NodeGrid {
    /// Spacing along strike and along dip (m).
    pub hs: f64,
    /// See [`NodeGrid::hs`].
    pub hd: f64,
    /// Smallest coordinate along strike (m, from node 0).
    pub xi0: f64,
    /// Largest coordinate up dip (m, from node 0).
    pub eta1: f64,
    /// Elements along strike.
    pub n_strike: usize,
    /// Elements along dip.
    pub n_dip: usize,
    /// The element of each node.
    pub element: Vec<usize>,
    /// The checks' tolerance (m): [`GRID_TOLERANCE`] times the smaller spacing.
    pub tol: f64,
}

impl NodeGrid {
    /// The grid of `nodes` (of the frictional vertices `vertices`) on the plane of node
    /// 0 with `axes`: the spacings are the median gaps between distinct coordinates, every
    /// node must lie on the plane with the plane's normal, at an element's centre, one
    /// node per element, and every element must have its node.
    ///
    /// # Errors
    /// [`E::TooFewNodes`], [`E::NotPlanar`], [`E::NotAtCentre`], [`E::ElementWithoutNode`].
    pub fn of_nodes(nodes: &[Node], vertices: &[usize], axes: &PlaneAxes) -> Result<Self, E> {
        let (x0, _, _, n_fe) = nodes[0];
        let (strike, up_dip) = (axes.strike, axes.up_dip);
        // Fault coordinates (ξ along strike, η up dip) from node 0.
        let coords: Vec<[f64; 2]> = nodes
            .iter()
            .map(|(x, ..)| {
                let d = [0, 1, 2].map(|i| x[i] - x0[i]);
                [dot(&strike, &d), dot(&up_dip, &d)]
            })
            .collect();
        let (hs, hd) = match (spacing(&coords, 0), spacing(&coords, 1)) {
            (Some(a), Some(b)) => (a, b),
            (Some(a), None) => (a, a),
            (None, Some(b)) => (b, b),
            (None, None) => return Err(E::TooFewNodes { nodes: nodes.len() }),
        };
        let tol = GRID_TOLERANCE * hs.min(hd);
        for (k, (x, _, _, n)) in nodes.iter().enumerate() {
            let d = [0, 1, 2].map(|i| x[i] - x0[i]);
            let off = dot(&n_fe, &d).abs();
            let turn = dot(&cross(n, &n_fe), &cross(n, &n_fe)).sqrt();
            if off > tol || turn > GRID_TOLERANCE || dot(n, &n_fe) < 0.0 {
                return Err(E::NotPlanar {
                    node: k,
                    vertex: vertices[k],
                    position: *x,
                    normal: n_fe,
                    distance: if off > tol { off } else { turn },
                });
            }
        }
        let min = |c: usize| coords.iter().map(|x| x[c]).fold(f64::INFINITY, f64::min);
        let max = |c: usize| {
            coords
                .iter()
                .map(|x| x[c])
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let (xi0, eta1) = (min(0), max(1));
        let n_strike = ((max(0) - xi0) / hs).round() as usize + 1;
        let n_dip = ((eta1 - min(1)) / hd).round() as usize + 1;
        let mut node_of = std::collections::HashMap::with_capacity(nodes.len());
        let mut element = vec![0; nodes.len()];
        for (k, c) in coords.iter().enumerate() {
            let fs = (c[0] - xi0) / hs;
            let fd = (eta1 - c[1]) / hd;
            let (is, id) = (fs.round(), fd.round());
            let offset = ((fs - is) * hs).hypot((fd - id) * hd);
            let e = id as usize * n_strike + is as usize;
            let taken = node_of.contains_key(&e);
            if offset > tol || taken {
                return Err(E::NotAtCentre {
                    node: k,
                    vertex: vertices[k],
                    position: nodes[k].0,
                    spacing: [hs, hd],
                    offset: if offset > tol { offset } else { 0.0 },
                });
            }
            node_of.insert(e, k);
            element[k] = e;
        }
        // At most one more element than nodes to look at: the first without a node.
        if let Some(e) = (0..n_strike.saturating_mul(n_dip)).find(|e| !node_of.contains_key(e)) {
            let (i_strike, i_dip) = (e % n_strike, e / n_strike);
            let xi = xi0 + i_strike as f64 * hs;
            let eta = eta1 - i_dip as f64 * hd;
            return Err(E::ElementWithoutNode {
                i_strike,
                i_dip,
                n_strike,
                n_dip,
                centre: [0, 1, 2].map(|i| x0[i] + xi * strike[i] + eta * up_dip[i]),
            });
        }
        Ok(Self {
            hs,
            hd,
            xi0,
            eta1,
            n_strike,
            n_dip,
            element,
            tol,
        })
    }

    /// Refuses a node whose element reaches above the free surface at height `surface`
    /// (a surface-breaking fault; `sin_dip` the up-dip vector's vertical component).
    ///
    /// # Errors
    /// [`E::SurfaceBreaking`] naming the first such node.
    pub fn check_below(
        &self,
        nodes: &[Node],
        vertices: &[usize],
        surface: f64,
        sin_dip: f64,
    ) -> Result<(), E> {
        for (k, (x, ..)) in nodes.iter().enumerate() {
            let above = x[2] + 0.5 * self.hd * sin_dip - surface;
            if above > self.tol {
                return Err(E::SurfaceBreaking {
                    node: k,
                    vertex: vertices[k],
                    position: *x,
                    surface,
                    above,
                });
            }
        }
        Ok(())
    }
}

/// The median gap between the distinct values of coordinate `c` of `coords`: the spacing
/// of a regular grid, and still its spacing with a few nodes off it (reported by name
/// where the nodes are matched to elements). `None` for a single value.
pub(super) fn spacing(coords: &[[f64; 2]], c: usize) -> Option<f64> {
    let mut v: Vec<f64> = coords.iter().map(|x| x[c]).collect();
    v.sort_by(f64::total_cmp);
    let extent = v[v.len() - 1] - v[0];
    let mut gaps: Vec<f64> = v
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|&g| g > 1e-9 * extent)
        .collect();
    gaps.sort_by(f64::total_cmp);
    gaps.get(gaps.len() / 2).copied()
}
