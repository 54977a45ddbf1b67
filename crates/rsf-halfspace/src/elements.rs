//! Boundary elements of any position and orientation: planar dislocations of constant
//! slip — rectangles with a horizontal edge ([`RectangleElement`], Okada's DC3D in each
//! one's own frame) and triangles ([`Triangle`], Nikkhoo & Walter) — behind one trait,
//! [`Element`], in a half-space or the whole space ([`Space`]; docs/halfspace.md §7).

use crate::error::{check_finite, check_parameters, Error};
use crate::okada::{Deformation, Okada, Rectangle};
use crate::space::Space;
use crate::stress::Medium;
use crate::triangle::Triangle;

/// A planar element of constant slip: where it is, its frame, and the deformation its
/// unit slips cause anywhere. Coordinates as Okada's (`z` up; the half-space `z ≤ 0`).
pub trait Element: Send + Sync + std::fmt::Debug {
    /// The collocation point (m): a rectangle's centre, a triangle's centroid.
    fn centre(&self) -> [f64; 3];

    /// Unit vectors `[strike, up dip, normal]` (`normal = strike × up dip`): the slip's and
    /// the traction's components are along them; the slip is the motion of the side the
    /// normal points into relative to the other side (Okada's convention).
    fn frame(&self) -> [[f64; 3]; 3];

    /// The area (m²).
    fn area(&self) -> f64;

    /// The deformations (global components) at `point` (m) due to unit strike slip, unit
    /// dip slip and unit opening, in that order, in the elastic `medium` filling `space`.
    ///
    /// # Errors
    /// [`Error::AboveSurface`], [`Error::SourceAboveSurface`] (half-space),
    /// [`Error::OnEdge`], [`Error::Parameter`] for a non-finite point,
    /// [`Error::NonFinite`].
    fn unit_responses(
        &self,
        medium: &Medium,
        space: Space,
        point: [f64; 3],
    ) -> Result<[Deformation; 3], Error>;

    /// Whether the element may be a source in `space` (in a half-space: not above the
    /// surface).
    ///
    /// # Errors
    /// [`Error::SourceAboveSurface`].
    fn check_space(&self, space: Space) -> Result<(), Error>;
}

/// A rectangle of any position, strike and dip: centre `(x, y, z)`, the strike direction
/// `e_s = (cos φ, sin φ, 0)` at the angle `φ` (degrees, counter-clockwise from `+x` seen
/// from above), the dip `δ` (degrees from the horizontal, as Okada's: the up-dip
/// `e_d = cos δ (e_z × e_s) + sin δ e_z`, the normal `n = e_s × e_d` pointing into the
/// hanging wall), its length along strike and width along dip (m). With `φ = 0` its frame
/// is Okada's: it is [`Rectangle`]`::new(−z, δ, [x − L/2, x + L/2], …)` moved to `y`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectangleElement {
    centre: [f64; 3],
    strike_deg: f64,
    dip_deg: f64,
    length: f64,
    width: f64,
    /// Okada's axes `x = e_s`, `y = e_z × e_s`, `z = e_z` (global components).
    axes: [[f64; 3]; 3],
    /// `[e_s, e_d, n]` (global components).
    frame: [[f64; 3]; 3],
}

impl RectangleElement {
    /// The rectangle centred at `centre` (m) of strike `strike_deg`, dip `dip_deg`
    /// (degrees), `length` along strike and `width` along dip (m).
    ///
    /// # Errors
    /// [`Error::Parameter`] for non-finite values or a length or width not positive.
    pub fn new(
        centre: [f64; 3],
        strike_deg: f64,
        dip_deg: f64,
        length: f64,
        width: f64,
    ) -> Result<Self, Error> {
        check_finite([
            ("centre.x", centre[0]),
            ("centre.y", centre[1]),
            ("centre.z", centre[2]),
            ("strike", strike_deg),
            ("dip", dip_deg),
        ])?;
        check_parameters(
            [("length", length), ("width", width)],
            |value| value.is_finite() && value > 0.0,
            "finite and > 0",
        )?;
        let (s, c) = strike_deg.to_radians().sin_cos();
        let axes = [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]];
        let local = Rectangle::new(
            width,
            dip_deg,
            [-0.5 * length, 0.5 * length],
            [-0.5 * width, 0.5 * width],
        )?
        .frame();
        let frame = local.map(|v| [0, 1, 2].map(|i| (0..3).map(|a| axes[a][i] * v[a]).sum()));
        Ok(Self {
            centre,
            strike_deg,
            dip_deg,
            length,
            width,
            axes,
            frame,
        })
    }

    /// The strike angle `φ` (degrees).
    pub fn strike_deg(&self) -> f64 {
        self.strike_deg
    }

    /// The dip `δ` (degrees).
    pub fn dip_deg(&self) -> f64 {
        self.dip_deg
    }

    /// Length along strike (m).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Width along dip (m).
    pub fn width(&self) -> f64 {
        self.width
    }

    /// The rectangle in its own Okada frame and the global position of that frame's
    /// origin: in a half-space the origin on the surface above the centre (depth `−z`),
    /// in the whole space at the height `z + width` (any height gives the same field).
    fn okada(&self, space: Space) -> Result<(Rectangle, [f64; 3]), Error> {
        let [x, y, z] = self.centre;
        let depth = match space {
            Space::HalfSpace => -z,
            Space::WholeSpace => self.width,
        };
        let rect = Rectangle::new(
            depth,
            self.dip_deg,
            [-0.5 * self.length, 0.5 * self.length],
            [-0.5 * self.width, 0.5 * self.width],
        )?;
        Ok((rect, [x, y, z + depth]))
    }

    /// A planar rectangle `length × width` centred at `centre`, of strike and dip as
    /// [`new`](Self::new), cut into `n_strike × n_dip` equal elements, in the order of
    /// [`RectangularFault`](crate::RectangularFault): element `i_dip · n_strike +
    /// i_strike`, `i_strike = 0` at the end `−e_s`, `i_dip = 0` the top row (`+e_d`).
    ///
    /// # Errors
    /// As [`new`](Self::new); [`Error::Parameter`] for zero counts.
    pub fn grid(
        centre: [f64; 3],
        strike_deg: f64,
        dip_deg: f64,
        size: [f64; 2],
        counts: [usize; 2],
    ) -> Result<Vec<Self>, Error> {
        let [n_strike, n_dip] = counts;
        if n_strike == 0 || n_dip == 0 {
            return Err(Error::Parameter {
                name: "n_strike × n_dip",
                value: (n_strike * n_dip) as f64,
                expected: ">= 1 element each way",
            });
        }
        let whole = Self::new(centre, strike_deg, dip_deg, size[0], size[1])?;
        let [es, ed, _] = whole.frame;
        let (hs, hd) = (size[0] / n_strike as f64, size[1] / n_dip as f64);
        let mut out = Vec::with_capacity(n_strike * n_dip);
        for id in 0..n_dip {
            let eta = 0.5 * size[1] - (id as f64 + 0.5) * hd;
            for is in 0..n_strike {
                let xi = -0.5 * size[0] + (is as f64 + 0.5) * hs;
                let c = [0, 1, 2].map(|i| centre[i] + xi * es[i] + eta * ed[i]);
                out.push(Self::new(c, strike_deg, dip_deg, hs, hd)?);
            }
        }
        Ok(out)
    }
}

impl Element for RectangleElement {
    fn centre(&self) -> [f64; 3] {
        self.centre
    }

    fn frame(&self) -> [[f64; 3]; 3] {
        self.frame
    }

    fn area(&self) -> f64 {
        self.length * self.width
    }

    fn unit_responses(
        &self,
        medium: &Medium,
        space: Space,
        point: [f64; 3],
    ) -> Result<[Deformation; 3], Error> {
        let (rect, origin) = self.okada(space)?;
        let d = [0, 1, 2].map(|i| point[i] - origin[i]);
        let a = &self.axes;
        let local = a.map(|e| e[0] * d[0] + e[1] * d[1] + e[2] * d[2]);
        let r = Okada::new(medium.alpha(), rect)?
            .unit_responses_in(local, space)
            .map_err(|e| match e {
                Error::OnEdge { .. } => Error::OnEdge { point },
                Error::AboveSurface { .. } => Error::AboveSurface { z: point[2] },
                other => other,
            })?;
        // Back to global components: u = Aᵀ u_l, G = Aᵀ G_l A.
        Ok(r.map(|l| {
            let u = [0, 1, 2].map(|i| (0..3).map(|k| a[k][i] * l.u[k]).sum());
            let mut grad = [[0.0; 3]; 3];
            for (i, row) in grad.iter_mut().enumerate() {
                for (j, g) in row.iter_mut().enumerate() {
                    *g = (0..3)
                        .map(|k| a[k][i] * (0..3).map(|m| l.grad[k][m] * a[m][j]).sum::<f64>())
                        .sum();
                }
            }
            Deformation { u, grad }
        }))
    }

    fn check_space(&self, space: Space) -> Result<(), Error> {
        self.okada(space).map(|_| ())
    }
}

impl Element for Triangle {
    fn centre(&self) -> [f64; 3] {
        self.centroid()
    }

    fn frame(&self) -> [[f64; 3]; 3] {
        Triangle::frame(self)
    }

    fn area(&self) -> f64 {
        Triangle::area(self)
    }

    fn unit_responses(
        &self,
        medium: &Medium,
        space: Space,
        point: [f64; 3],
    ) -> Result<[Deformation; 3], Error> {
        Triangle::unit_responses(self, medium.nu(), point, space)
    }

    fn check_space(&self, space: Space) -> Result<(), Error> {
        let z_top = self
            .vertices()
            .iter()
            .map(|v| v[2])
            .fold(f64::MIN, f64::max);
        if space == Space::HalfSpace && z_top > 0.0 {
            return Err(Error::SourceAboveSurface { z_top });
        }
        Ok(())
    }
}
