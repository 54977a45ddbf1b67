//! The boundary-element operator of a planar rectangular fault in a half-space: constant
//! slip on each of `n_strike × n_dip` rectangular elements, tractions collocated at the
//! element centres from Okada's stresses (docs/halfspace.md §5).

use crate::error::Error;
use crate::okada::{Deformation, Okada, Rectangle};
use crate::stress::{traction, Medium};
use faer::Mat;
use rayon::prelude::*;
use rsf_hmatrix::{HMatrix, HOptions, Points};

/// A slip (or traction) component on the fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Component {
    /// Along strike, `e_s = (1, 0, 0)` (left-lateral slip positive).
    Strike,
    /// Up dip, `e_d = (0, cos δ, sin δ)` (reverse slip positive).
    Dip,
}

impl Component {
    fn index(self) -> usize {
        match self {
            Component::Strike => 0,
            Component::Dip => 1,
        }
    }
}

/// A planar rectangular fault in Okada's frame — reference point `(0, 0, −depth)`, dip
/// `δ`, along-strike range `[al1, al2]`, up-dip range `[aw1, aw2]` (as
/// [`Rectangle`]) — meshed into a regular grid of `n_strike × n_dip` rectangles with
/// constant slip, two slip components per element.
///
/// **Elements**: `e = i_dip · n_strike + i_strike`, `i_strike = 0` at `ξ = al1`
/// (increasing along strike), `i_dip = 0` at the top (`η = aw2`, increasing down dip).
/// **Unknowns**: element-major, `[strike, dip]` per element: unknown `2e` is element
/// `e`'s strike slip, `2e + 1` its dip slip (m).
///
/// **Operators** (Pa/m):
/// - the stiffness `K`, `2n × 2n`: `Δτ = −K s`, where `τ_c = (σ n)·e_c` is the shear
///   traction on the fault at an element centre (`n = (0, −sin δ, cos δ)` into the
///   hanging wall, `e_c` the strike or up-dip direction) — positive `τ_c` drives positive
///   slip, and slip lowers it: `K`'s diagonal is positive;
/// - the normal operator `K_N`, `n × 2n`: `Δσ_n = −K_N s`, `σ_n = n·σ n` tension
///   positive (same sign convention as `K`).
///
/// Entry `(i, j)` is the traction at the centre of unknown `i`'s element due to unit slip
/// of unknown `j`, from [`Okada`] (DC3D) and [`Medium::stress`].
#[derive(Debug, Clone)]
pub struct RectangularFault {
    medium: Medium,
    n_strike: usize,
    n_dip: usize,
    elements: Vec<Okada>,
    centres: Vec<[f64; 3]>,
    frame: [[f64; 3]; 3],
}

impl RectangularFault {
    /// The fault `Rectangle::new(depth, dip_deg, strike, dip)` meshed into square cells of
    /// side `cell` (m): `n_strike = (al2 − al1)/cell` and `n_dip = (aw2 − aw1)/cell`, each
    /// a whole number to a relative `10⁻⁹`.
    ///
    /// # Errors
    /// Those of [`Rectangle::new`]; [`Error::Parameter`] unless `cell > 0` divides both
    /// extents; [`Error::TooManyElements`] beyond `2³⁰` unknowns.
    pub fn new(
        medium: Medium,
        depth: f64,
        dip_deg: f64,
        strike: [f64; 2],
        dip: [f64; 2],
        cell: f64,
    ) -> Result<Self, Error> {
        let rect = Rectangle::new(depth, dip_deg, strike, dip)?;
        if !(cell.is_finite() && cell > 0.0) {
            return Err(Error::Parameter {
                name: "cell",
                value: cell,
                expected: "finite and > 0",
            });
        }
        let count = |extent: f64| -> Result<usize, Error> {
            let n = (extent / cell).round();
            if !(n >= 1.0 && n <= (1u64 << 30) as f64 && (n * cell - extent).abs() <= 1e-9 * extent)
            {
                return Err(Error::Parameter {
                    name: "cell",
                    value: cell,
                    expected: "dividing both extents of the fault into a whole number of cells",
                });
            }
            Ok(n as usize)
        };
        let (ns, nd) = (count(strike[1] - strike[0])?, count(dip[1] - dip[0])?);
        Self::from_rectangle(medium, rect, ns, nd)
    }

    /// The fault `rect` meshed into `n_strike × n_dip` equal rectangles.
    ///
    /// # Errors
    /// [`Error::Parameter`] for zero counts; [`Error::TooManyElements`] beyond `2³⁰`
    /// unknowns.
    pub fn from_rectangle(
        medium: Medium,
        rect: Rectangle,
        n_strike: usize,
        n_dip: usize,
    ) -> Result<Self, Error> {
        if n_strike == 0 || n_dip == 0 {
            return Err(Error::Parameter {
                name: "n_strike × n_dip",
                value: (n_strike * n_dip) as f64,
                expected: ">= 1 element each way",
            });
        }
        let n = n_strike
            .checked_mul(n_dip)
            .and_then(|n| n.checked_mul(2))
            .filter(|&n| n <= 1 << 30)
            .ok_or(Error::TooManyElements { n_strike, n_dip })?;
        let [al1, al2] = rect.strike_range();
        let [aw1, aw2] = rect.dip_range();
        let (hs, hd) = ((al2 - al1) / n_strike as f64, (aw2 - aw1) / n_dip as f64);
        let alpha = medium.alpha();
        let mut elements = Vec::with_capacity(n / 2);
        let mut centres = Vec::with_capacity(n / 2);
        for id in 0..n_dip {
            // Top row first: η from aw2 down.
            let top = aw2 - id as f64 * hd;
            let bottom = if id + 1 == n_dip {
                aw1
            } else {
                aw2 - (id + 1) as f64 * hd
            };
            for is in 0..n_strike {
                let left = al1 + is as f64 * hs;
                let right = if is + 1 == n_strike {
                    al2
                } else {
                    al1 + (is + 1) as f64 * hs
                };
                let r = Rectangle::new(rect.depth(), rect.dip_deg(), [left, right], [bottom, top])?;
                centres.push(r.centre());
                elements.push(Okada::new(alpha, r)?);
            }
        }
        Ok(Self {
            medium,
            n_strike,
            n_dip,
            elements,
            centres,
            frame: rect.frame(),
        })
    }

    /// Number of unknowns, `2 n_strike n_dip`.
    pub fn len(&self) -> usize {
        2 * self.elements.len()
    }

    /// Whether there are no unknowns (never: a fault has at least one element).
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// Number of elements, `n_strike n_dip`.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// Elements along strike.
    pub fn n_strike(&self) -> usize {
        self.n_strike
    }

    /// Elements along dip.
    pub fn n_dip(&self) -> usize {
        self.n_dip
    }

    /// The medium.
    pub fn medium(&self) -> &Medium {
        &self.medium
    }

    /// Element `e = i_dip · n_strike + i_strike`.
    ///
    /// # Errors
    /// [`Error::Index`] if out of range.
    pub fn element(&self, e: usize) -> Result<&Rectangle, Error> {
        self.elements
            .get(e)
            .map(Okada::rectangle)
            .ok_or(Error::Index {
                index: e,
                len: self.elements.len(),
            })
    }

    /// The element index of `(i_strike, i_dip)`.
    ///
    /// # Errors
    /// [`Error::Index`] if out of range.
    pub fn element_index(&self, i_strike: usize, i_dip: usize) -> Result<usize, Error> {
        if i_strike >= self.n_strike {
            return Err(Error::Index {
                index: i_strike,
                len: self.n_strike,
            });
        }
        if i_dip >= self.n_dip {
            return Err(Error::Index {
                index: i_dip,
                len: self.n_dip,
            });
        }
        Ok(i_dip * self.n_strike + i_strike)
    }

    /// The unknown of `component` on element `e`: `2e` or `2e + 1`.
    pub fn unknown(e: usize, component: Component) -> usize {
        2 * e + component.index()
    }

    /// The centres of the elements (Okada's frame, m).
    pub fn centres(&self) -> &[[f64; 3]] {
        &self.centres
    }

    /// Unit vectors `[strike, up-dip, normal]` of the fault (see [`Rectangle::frame`]).
    pub fn frame(&self) -> [[f64; 3]; 3] {
        self.frame
    }

    /// One 3-D point per unknown, both of an element's unknowns at its centre, for
    /// [`HMatrix`].
    pub fn points(&self) -> Points {
        let coords: Vec<f64> = self
            .centres
            .iter()
            .flat_map(|c| c.iter().chain(c.iter()).copied())
            .collect();
        // Centres are finite (checked rectangles).
        Points::new(&coords, 3).unwrap_or_else(|_| unreachable!("finite element centres"))
    }

    /// `[τ_strike, τ_dip, σ_n]` at element `e`'s centre for unit strike slip and unit dip
    /// slip on element `f`.
    fn tractions(&self, e: usize, f: usize) -> Result<[[f64; 3]; 2], Error> {
        let unit = self.elements[f].unit_responses(self.centres[e])?;
        let [es, ed, n] = self.frame;
        let t = |d: &Deformation| -> [f64; 3] {
            let tr = traction(&self.medium.stress(&d.grad), &n);
            let dot = |a: &[f64; 3]| tr[0] * a[0] + tr[1] * a[1] + tr[2] * a[2];
            [dot(&es), dot(&ed), dot(&n)]
        };
        Ok([t(&unit[0]), t(&unit[1])])
    }

    fn check_unknown(&self, i: usize) -> Result<(), Error> {
        if i < self.len() {
            Ok(())
        } else {
            Err(Error::Index {
                index: i,
                len: self.len(),
            })
        }
    }

    /// Entry `K[i][j]` (Pa/m): minus the shear traction of unknown `i`'s component at its
    /// element's centre due to unit slip of unknown `j`.
    ///
    /// # Errors
    /// [`Error::Index`] out of range; [`Error::NonFinite`] should the evaluation
    /// overflow.
    pub fn entry(&self, i: usize, j: usize) -> Result<f64, Error> {
        self.check_unknown(i)?;
        self.check_unknown(j)?;
        let t = self.tractions(i / 2, j / 2)?;
        Ok(-t[j % 2][i % 2])
    }

    /// Entry `K_N[e][j]` (Pa/m): minus the normal traction (tension positive) at element
    /// `e`'s centre due to unit slip of unknown `j`.
    ///
    /// # Errors
    /// [`Error::Index`] out of range; [`Error::NonFinite`] should the evaluation
    /// overflow.
    pub fn normal_entry(&self, e: usize, j: usize) -> Result<f64, Error> {
        if e >= self.n_elements() {
            return Err(Error::Index {
                index: e,
                len: self.n_elements(),
            });
        }
        self.check_unknown(j)?;
        let t = self.tractions(e, j / 2)?;
        Ok(-t[j % 2][2])
    }

    /// The columns of both unknowns of source element `f`: `[K rows…, K_N rows…]` for
    /// each of its two components.
    fn source_columns(&self, f: usize) -> Result<[Vec<f64>; 4], Error> {
        let m = self.n_elements();
        let mut cols = [
            vec![0.0; 2 * m],
            vec![0.0; 2 * m],
            vec![0.0; m],
            vec![0.0; m],
        ];
        for e in 0..m {
            let t = self.tractions(e, f)?;
            for d in 0..2 {
                cols[d][2 * e] = -t[d][0];
                cols[d][2 * e + 1] = -t[d][1];
                cols[2 + d][e] = -t[d][2];
            }
        }
        Ok(cols)
    }

    /// Both operators densely, columns of the source elements on rayon's threads (each
    /// entry computed alone, so the same bits whatever the number of threads).
    fn dense_both(&self) -> Result<(Mat<f64>, Mat<f64>), Error> {
        let cols: Vec<[Vec<f64>; 4]> = (0..self.n_elements())
            .into_par_iter()
            .map(|f| self.source_columns(f))
            .collect::<Result<_, _>>()?;
        let (m, n) = (self.n_elements(), self.len());
        let k = Mat::from_fn(n, n, |i, j| cols[j / 2][j % 2][i]);
        let kn = Mat::from_fn(m, n, |e, j| cols[j / 2][2 + j % 2][e]);
        Ok((k, kn))
    }

    /// The stiffness `K` (`2n × 2n`, Pa/m), assembled on rayon's threads.
    ///
    /// # Errors
    /// [`Error::NonFinite`] should an evaluation overflow.
    pub fn dense(&self) -> Result<Mat<f64>, Error> {
        Ok(self.dense_both()?.0)
    }

    /// The normal operator `K_N` (`n × 2n`, Pa/m), assembled on rayon's threads.
    ///
    /// # Errors
    /// [`Error::NonFinite`] should an evaluation overflow.
    pub fn normal_dense(&self) -> Result<Mat<f64>, Error> {
        Ok(self.dense_both()?.1)
    }

    /// `K` as an ℋ-matrix from its entries ([`HMatrix::from_entries`], adaptive cross
    /// approximation), on [`RectangularFault::points`], original numbering = the
    /// unknowns' order.
    ///
    /// # Errors
    /// [`Error::HMatrix`] for invalid options or a failed compression (an entry that
    /// could not be evaluated is reported as a non-finite entry).
    pub fn hmatrix(&self, options: &HOptions) -> Result<HMatrix, Error> {
        let points = self.points();
        let entry = |i: usize, j: usize| self.entry(i, j).unwrap_or(f64::NAN);
        Ok(HMatrix::from_entries(entry, &points, options)?)
    }
}
