//! The boundary-element operator of a planar rectangular fault in a half-space: constant
//! slip on each of `n_strike × n_dip` rectangular elements, tractions collocated at the
//! element centres from Okada's stresses (docs/halfspace.md §5).

use crate::error::Error;
use crate::okada::{Okada, Rectangle};
use crate::stress::{traction, Medium};
use faer::Mat;
use rayon::prelude::*;
use rsf_hmatrix::{HMatrix, HOptions, Points, RowPart};

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
///
/// **Translation along strike.** The half-space and the grid are invariant under shifts
/// by whole cells along strike, so entry `(i, j)` depends only on the strike offset of the
/// two elements and their rows: it is evaluated for the source in the first column and
/// the receiver at that offset, the same arithmetic for [`entry`](Self::entry),
/// [`dense`](Self::dense) and [`hmatrix`](Self::hmatrix) (the same bits), and `dense`
/// and `hmatrix` tabulate the `(2 n_strike − 1) n_dip²` distinct source–receiver pairs
/// once instead of evaluating `(n_strike n_dip)²` entries.
#[derive(Debug, Clone)]
pub struct RectangularFault {
    medium: Medium,
    n_strike: usize,
    n_dip: usize,
    /// The elements, physical position (for [`element`](Self::element)).
    elements: Vec<Rectangle>,
    /// Their centres.
    centres: Vec<[f64; 3]>,
    /// The source of each row in the first column.
    sources: Vec<Okada>,
    /// `(y, z)` of the centres of each row.
    row_yz: Vec<[f64; 2]>,
    /// `al1` and the cell length along strike.
    al1: f64,
    hs: f64,
    frame: [[f64; 3]; 3],
}

/// `[τ_s, τ_d, σ_n]` for unit strike slip, then for unit dip slip.
type Pair = [f64; 6];

/// Largest number of distinct source–receiver pairs [`RectangularFault::hmatrix`]
/// tabulates (`2²⁵ × 48` bytes ≈ 1.6 GB; BP5's fault at 250 m cells has 2.0e7 of them,
/// 0.98 GB); beyond it each entry is evaluated when asked for (one DC3D evaluation per
/// entry: at 250 m cells that set-up did not finish in 25 min, where the table's takes
/// minutes; docs/seas-bp5.md). Until 2026-11-27 the bound was `2²²`.
pub const TABLE_MAX_PAIRS: usize = 1 << 25;

impl RectangularFault {
    /// The fault `rect` ([`Rectangle::new`]`(depth, dip_deg, [al1, al2], [aw1, aw2])`)
    /// meshed into square cells of side `cell` (m): `n_strike = (al2 − al1)/cell` and
    /// `n_dip = (aw2 − aw1)/cell`, each a whole number to a relative `10⁻⁹`.
    ///
    /// # Errors
    /// [`Error::Parameter`] unless `cell > 0` divides both extents;
    /// [`Error::TooManyElements`] beyond `2³⁰` unknowns.
    pub fn new(medium: Medium, rect: Rectangle, cell: f64) -> Result<Self, Error> {
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
        let (strike, dip) = (rect.strike_range(), rect.dip_range());
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
        let strike_edge = |is: usize| {
            if is == n_strike {
                al2
            } else {
                al1 + is as f64 * hs
            }
        };
        let mut elements = Vec::with_capacity(n / 2);
        let mut centres = Vec::with_capacity(n / 2);
        let mut sources = Vec::with_capacity(n_dip);
        let mut row_yz = Vec::with_capacity(n_dip);
        for id in 0..n_dip {
            // Top row first: η from aw2 down.
            let top = aw2 - id as f64 * hd;
            let bottom = if id + 1 == n_dip {
                aw1
            } else {
                aw2 - (id + 1) as f64 * hd
            };
            let c = rect.point(0.0, aw2 - (id as f64 + 0.5) * hd);
            row_yz.push([c[1], c[2]]);
            let first = Rectangle::new(
                rect.depth(),
                rect.dip_deg(),
                [al1, strike_edge(1)],
                [bottom, top],
            )?;
            sources.push(Okada::new(alpha, first)?);
            for is in 0..n_strike {
                elements.push(Rectangle::new(
                    rect.depth(),
                    rect.dip_deg(),
                    [strike_edge(is), strike_edge(is + 1)],
                    [bottom, top],
                )?);
                centres.push([al1 + (is as f64 + 0.5) * hs, c[1], c[2]]);
            }
        }
        Ok(Self {
            medium,
            n_strike,
            n_dip,
            elements,
            centres,
            sources,
            row_yz,
            al1,
            hs,
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
        self.elements.get(e).ok_or(Error::Index {
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

    /// The tractions at the centre of an element of row `id_e`, `delta` columns from a
    /// source element of row `id_f` (unit strike slip, then unit dip slip).
    fn pair(&self, delta: isize, id_e: usize, id_f: usize) -> Result<Pair, Error> {
        let [y, z] = self.row_yz[id_e];
        let x = self.al1 + (delta as f64 + 0.5) * self.hs;
        let unit = self.sources[id_f].unit_responses([x, y, z])?;
        let [es, ed, n] = self.frame;
        let mut out = [0.0; 6];
        for (d, resp) in unit[..2].iter().enumerate() {
            let tr = traction(&self.medium.stress(&resp.grad), &n);
            let dot = |a: &[f64; 3]| tr[0] * a[0] + tr[1] * a[1] + tr[2] * a[2];
            out[3 * d] = dot(&es);
            out[3 * d + 1] = dot(&ed);
            out[3 * d + 2] = dot(&n);
        }
        Ok(out)
    }

    /// `(delta, id_e, id_f)` of receiver element `e` and source element `f`.
    fn offsets(&self, e: usize, f: usize) -> (isize, usize, usize) {
        let ns = self.n_strike;
        ((e % ns) as isize - (f % ns) as isize, e / ns, f / ns)
    }

    /// The tractions at element `e`'s centre due to unit slips on element `f`.
    fn tractions(&self, e: usize, f: usize) -> Result<Pair, Error> {
        let (delta, id_e, id_f) = self.offsets(e, f);
        self.pair(delta, id_e, id_f)
    }

    /// Number of distinct source–receiver pairs, `(2 n_strike − 1) n_dip²`.
    /// The number of distinct source–receiver pairs, `(2 n_strike − 1) n_dip²`: the
    /// entries depend only on the two elements' strike offset and rows.
    pub fn table_pairs(&self) -> usize {
        (2 * self.n_strike - 1) * self.n_dip * self.n_dip
    }

    /// All distinct pairs, on rayon's threads (each computed alone: the same bits on
    /// any number of threads).
    fn table(&self) -> Result<Vec<Pair>, Error> {
        let (ns, nd) = (self.n_strike, self.n_dip);
        let rows: Vec<Vec<Pair>> = (0..(2 * ns - 1) * nd)
            .into_par_iter()
            .map(|r| {
                let (delta, id_e) = ((r / nd) as isize - (ns as isize - 1), r % nd);
                (0..nd).map(|id_f| self.pair(delta, id_e, id_f)).collect()
            })
            .collect::<Result<_, _>>()?;
        Ok(rows.into_iter().flatten().collect())
    }

    /// The index in [`table`](Self::table) of receiver `e` and source `f`.
    fn table_index(&self, e: usize, f: usize) -> usize {
        let (delta, id_e, id_f) = self.offsets(e, f);
        let nd = self.n_dip;
        (((delta + self.n_strike as isize - 1) as usize) * nd + id_e) * nd + id_f
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
        Ok(-t[3 * (j % 2) + i % 2])
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
        Ok(-t[3 * (j % 2) + 2])
    }

    /// Both operators densely from the [table](Self::table).
    fn dense_both(&self) -> Result<(Mat<f64>, Mat<f64>), Error> {
        let table = self.table()?;
        let (m, n) = (self.n_elements(), self.len());
        let k = Mat::from_fn(n, n, |i, j| {
            -table[self.table_index(i / 2, j / 2)][3 * (j % 2) + i % 2]
        });
        let kn = Mat::from_fn(m, n, |e, j| {
            -table[self.table_index(e, j / 2)][3 * (j % 2) + 2]
        });
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
    /// unknowns' order. The entries come from the table of distinct source–receiver pairs
    /// ([`table_pairs`](Self::table_pairs), 48 bytes each) when it has at most
    /// [`TABLE_MAX_PAIRS`] of them, else each is evaluated when asked for; the same bits
    /// either way.
    ///
    /// # Errors
    /// [`Error::HMatrix`] for invalid options or a failed compression (an entry that
    /// could not be evaluated is reported as a non-finite entry).
    pub fn hmatrix(&self, options: &HOptions) -> Result<HMatrix, Error> {
        self.hmatrix_rows(options, None)
    }

    /// As [`hmatrix`](Self::hmatrix), only the rows of one part
    /// ([`HMatrix::from_entries_part`]: the share of one of `row_part.parts` processes,
    /// its rows' bits those of the whole matrix). The table of distinct pairs is the
    /// whole fault's (it is freed once the blocks are built).
    ///
    /// # Errors
    /// As [`hmatrix`](Self::hmatrix); [`Error::HMatrix`] for a part that is not one.
    pub fn hmatrix_part(&self, options: &HOptions, row_part: RowPart) -> Result<HMatrix, Error> {
        self.hmatrix_rows(options, Some(row_part))
    }

    /// [`hmatrix`](Self::hmatrix) of every row, or of one part's.
    fn hmatrix_rows(&self, options: &HOptions, part: Option<RowPart>) -> Result<HMatrix, Error> {
        fn build(
            entry: impl Fn(usize, usize) -> f64,
            points: &Points,
            options: &HOptions,
            part: Option<RowPart>,
        ) -> Result<HMatrix, rsf_hmatrix::Error> {
            match part {
                None => HMatrix::from_entries(entry, points, options),
                Some(p) => HMatrix::from_entries_part(entry, points, options, p),
            }
        }
        let points = self.points();
        if self.table_pairs() <= TABLE_MAX_PAIRS {
            let table = self.table()?;
            let entry =
                |i: usize, j: usize| -table[self.table_index(i / 2, j / 2)][3 * (j % 2) + i % 2];
            Ok(build(entry, &points, options, part)?)
        } else {
            let entry = |i: usize, j: usize| self.entry(i, j).unwrap_or(f64::NAN);
            Ok(build(entry, &points, options, part)?)
        }
    }
}
