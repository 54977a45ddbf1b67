//! The boundary-element operator of any set of elements — several faults, or a
//! non-planar fault cut into rectangles or triangles — in a half-space or the whole
//! space: constant slip per element, tractions collocated at the elements' centres in
//! each receiver's own frame (docs/halfspace.md §7).

use crate::bem::Component;
use crate::elements::Element;
use crate::error::Error;
use crate::okada::Deformation;
use crate::space::Space;
use crate::stress::{traction, Medium};
use faer::Mat;
use rayon::prelude::*;
use rsf_hmatrix::{HMatrix, HOptions, Points, RowPart};

/// `[τ_s, τ_d, σ_n]` for unit strike slip, then for unit dip slip.
type Pair = [f64; 6];

/// Largest number of elements of an [`ElementSet`] (`2²⁹`: `2³⁰` unknowns).
pub const MAX_ELEMENTS: usize = 1 << 29;

/// A set of boundary elements ([`Element`]: [`RectangleElement`](crate::RectangleElement)s
/// of any strike, dip and position, or [`Triangle`](crate::Triangle)s) in a half-space or
/// the whole space, and its operators. Element `e`'s two unknowns are `2e` (strike slip,
/// along its `e_s`) and `2e + 1` (dip slip, along its up-dip `e_d`), m, the slip of the
/// side its normal points into relative to the other side.
///
/// **Operators** (Pa/m), as [`RectangularFault`](crate::RectangularFault)'s, each
/// receiver in its own frame:
/// - the stiffness `K`, `2n × 2n`: `K[2e + c][2f + d] = −τ_c(x_e; unit slip d on f)`,
///   `τ_c = (σ n_e)·e_c` at the receiver's centre `x_e` with the receiver's normal `n_e`
///   and direction `e_c` (strike or up dip), so `Δτ = −K s` and `K`'s diagonal is
///   positive;
/// - the normal operator `K_N`, `n × 2n`: `K_N[e][2f + d] = −σ_n(x_e; unit slip d on f)`,
///   `σ_n = n_e·σ n_e` tension positive.
///
/// Each entry is one evaluation of the source's displacement gradient at the receiver's
/// centre ([`Element::unit_responses`]: DC3D in the rectangle's own frame, Nikkhoo &
/// Walter's triangle) and Hooke's law. Unlike [`RectangularFault`](crate::RectangularFault)
/// nothing is assumed of the geometry: no entry is shared, `n²` evaluations for the dense
/// operators, those of the near field and the crosses for the ℋ-matrix.
#[derive(Debug, Clone)]
pub struct ElementSet<E: Element> {
    medium: Medium,
    space: Space,
    elements: Vec<E>,
    centres: Vec<[f64; 3]>,
    frames: Vec<[[f64; 3]; 3]>,
}

/// A direct-mapped cache of source–receiver pairs: the entries of one pair are asked for
/// together (two rows, two columns of `K`), the pair is computed once.
struct PairCache {
    keys: Vec<(usize, usize)>,
    pairs: Vec<Pair>,
}

impl PairCache {
    const SLOTS: usize = 512;

    fn new() -> Self {
        Self {
            keys: vec![(usize::MAX, usize::MAX); Self::SLOTS],
            pairs: vec![[0.0; 6]; Self::SLOTS],
        }
    }

    fn get<E: Element>(&mut self, set: &ElementSet<E>, e: usize, f: usize) -> Option<Pair> {
        let slot = (e.wrapping_mul(0x9e37_79b9) ^ f.wrapping_mul(0x85eb_ca6b)) % Self::SLOTS;
        if self.keys[slot] != (e, f) {
            self.pairs[slot] = set.pair(e, f).ok()?;
            self.keys[slot] = (e, f);
        }
        Some(self.pairs[slot])
    }
}

impl<E: Element> ElementSet<E> {
    /// The set of `elements` in `space`, filled by `medium`.
    ///
    /// # Errors
    /// [`Error::Parameter`] for no element or more than [`MAX_ELEMENTS`];
    /// [`Error::SourceAboveSurface`] for an element above the surface of a half-space;
    /// [`Error::CoincidentCentres`] for two elements with the same centre (the operator
    /// would have two equal rows).
    pub fn new(medium: Medium, space: Space, elements: Vec<E>) -> Result<Self, Error> {
        if elements.is_empty() || elements.len() > MAX_ELEMENTS {
            return Err(Error::Parameter {
                name: "elements",
                value: elements.len() as f64,
                expected: "between 1 and 2^29 elements",
            });
        }
        for e in &elements {
            e.check_space(space)?;
        }
        let centres: Vec<[f64; 3]> = elements.iter().map(Element::centre).collect();
        let mut order: Vec<usize> = (0..centres.len()).collect();
        order.sort_by(|&a, &b| {
            (0..3)
                .map(|i| centres[a][i].total_cmp(&centres[b][i]))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        if let Some(w) = order.windows(2).find(|w| centres[w[0]] == centres[w[1]]) {
            return Err(Error::CoincidentCentres {
                first: w[0].min(w[1]),
                second: w[0].max(w[1]),
            });
        }
        let frames = elements.iter().map(Element::frame).collect();
        Ok(Self {
            medium,
            space,
            elements,
            centres,
            frames,
        })
    }

    /// Number of unknowns, `2 ×` elements.
    pub fn len(&self) -> usize {
        2 * self.elements.len()
    }

    /// Whether there are no unknowns (never: a set has at least one element).
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// The elements, in order.
    pub fn elements(&self) -> &[E] {
        &self.elements
    }

    /// The medium.
    pub fn medium(&self) -> &Medium {
        &self.medium
    }

    /// Half-space or whole space.
    pub fn space(&self) -> Space {
        self.space
    }

    /// The collocation points (m).
    pub fn centres(&self) -> &[[f64; 3]] {
        &self.centres
    }

    /// Every element's `[strike, up dip, normal]`.
    pub fn frames(&self) -> &[[[f64; 3]; 3]] {
        &self.frames
    }

    /// The unknown of `component` on element `e`: `2e` or `2e + 1`.
    pub fn unknown(e: usize, component: Component) -> usize {
        2 * e + component as usize
    }

    /// One 3-D point per unknown, both of an element's at its centre, for [`HMatrix`].
    pub fn points(&self) -> Points {
        let coords: Vec<f64> = self
            .centres
            .iter()
            .flat_map(|c| c.iter().chain(c.iter()).copied())
            .collect();
        Points::new(&coords, 3).unwrap_or_else(|_| unreachable!("finite element centres"))
    }

    /// The deformations at `point` (m) due to unit strike slip, unit dip slip and unit
    /// opening of element `f` ([`Element::unit_responses`]).
    ///
    /// # Errors
    /// [`Error::Index`] out of range; the element's errors.
    pub fn unit_responses(&self, f: usize, point: [f64; 3]) -> Result<[Deformation; 3], Error> {
        self.element(f)?
            .unit_responses(&self.medium, self.space, point)
    }

    fn element(&self, f: usize) -> Result<&E, Error> {
        self.elements.get(f).ok_or(Error::Index {
            index: f,
            len: self.elements.len(),
        })
    }

    /// `[τ_s, τ_d, σ_n]` (Pa) at element `e`'s centre, in its frame, due to unit strike
    /// slip of element `f`, then due to unit dip slip.
    ///
    /// # Errors
    /// [`Error::Index`] out of range; the element's errors (e.g. a centre on another
    /// element's edge).
    pub fn tractions(&self, e: usize, f: usize) -> Result<[f64; 6], Error> {
        self.element(e)?;
        self.pair(e, f)
    }

    fn pair(&self, e: usize, f: usize) -> Result<Pair, Error> {
        let r = self.unit_responses(f, self.centres[e])?;
        let [es, ed, n] = &self.frames[e];
        let mut out = [0.0; 6];
        for (d, resp) in r[..2].iter().enumerate() {
            let t = traction(&self.medium.stress(&resp.grad), n);
            let dot = |a: &[f64; 3]| t[0] * a[0] + t[1] * a[1] + t[2] * a[2];
            out[3 * d] = dot(es);
            out[3 * d + 1] = dot(ed);
            out[3 * d + 2] = dot(n);
        }
        Ok(out)
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

    /// Entry `K[i][j]` (Pa/m).
    ///
    /// # Errors
    /// [`Error::Index`] out of range; the kernel's errors.
    pub fn entry(&self, i: usize, j: usize) -> Result<f64, Error> {
        self.check_unknown(i)?;
        self.check_unknown(j)?;
        Ok(-self.pair(i / 2, j / 2)?[3 * (j % 2) + i % 2])
    }

    /// Entry `K_N[e][j]` (Pa/m).
    ///
    /// # Errors
    /// [`Error::Index`] out of range; the kernel's errors.
    pub fn normal_entry(&self, e: usize, j: usize) -> Result<f64, Error> {
        self.element(e)?;
        self.check_unknown(j)?;
        Ok(-self.pair(e, j / 2)?[3 * (j % 2) + 2])
    }

    /// `K` and `K_N` densely, source by source on rayon's threads (each entry computed
    /// alone: the same bits on any number of threads).
    ///
    /// # Errors
    /// The kernel's errors (of the failing entries, one is reported).
    pub fn dense_both(&self) -> Result<(Mat<f64>, Mat<f64>), Error> {
        self.dense_rows(true)
    }

    /// `K` (and `K_N` if `normal`, else an empty `0 × 2n` matrix).
    fn dense_rows(&self, normal: bool) -> Result<(Mat<f64>, Mat<f64>), Error> {
        let (m, n) = (self.n_elements(), self.len());
        let mut k = Mat::<f64>::zeros(n, n);
        let mut kn = Mat::<f64>::zeros(if normal { m } else { 0 }, n);
        k.as_mut()
            .par_col_chunks_mut(2)
            .zip(kn.as_mut().par_col_chunks_mut(2))
            .enumerate()
            .try_for_each(|(f, (mut kc, mut knc))| -> Result<(), Error> {
                for e in 0..m {
                    let t = self.pair(e, f)?;
                    for d in 0..2 {
                        kc[(2 * e, d)] = -t[3 * d];
                        kc[(2 * e + 1, d)] = -t[3 * d + 1];
                        if normal {
                            knc[(e, d)] = -t[3 * d + 2];
                        }
                    }
                }
                Ok(())
            })?;
        Ok((k, kn))
    }

    /// The stiffness `K` (`2n × 2n`, Pa/m), dense, as [`dense_both`](Self::dense_both)
    /// without `K_N`.
    ///
    /// # Errors
    /// As [`dense_both`](Self::dense_both).
    pub fn dense(&self) -> Result<Mat<f64>, Error> {
        Ok(self.dense_rows(false)?.0)
    }

    /// The normal operator `K_N` (`n × 2n`, Pa/m), dense ([`dense_both`](Self::dense_both)).
    ///
    /// # Errors
    /// As [`dense_both`](Self::dense_both).
    pub fn normal_dense(&self) -> Result<Mat<f64>, Error> {
        Ok(self.dense_both()?.1)
    }

    /// `K` as an ℋ-matrix from its entries on [`points`](Self::points) (both unknowns of
    /// an element one point each; pass [`HOptions::components`] = 2 to compress the four
    /// component blocks apart), the blocks on rayon's threads
    /// ([`HMatrix::from_entries_par`]: the same bits on any number of threads), each
    /// source–receiver pair evaluated once per block it is asked for in.
    ///
    /// # Errors
    /// [`Error::HMatrix`] for invalid options or a failed compression (an entry that
    /// could not be evaluated is reported as a non-finite entry).
    pub fn hmatrix(&self, options: &HOptions) -> Result<HMatrix, Error> {
        self.hmatrix_rows(options, None)
    }

    /// As [`hmatrix`](Self::hmatrix), only the rows of one part
    /// ([`HMatrix::from_entries_part_par`]).
    ///
    /// # Errors
    /// As [`hmatrix`](Self::hmatrix); [`Error::HMatrix`] for a part that is not one.
    pub fn hmatrix_part(&self, options: &HOptions, row_part: RowPart) -> Result<HMatrix, Error> {
        self.hmatrix_rows(options, Some(row_part))
    }

    fn hmatrix_rows(&self, options: &HOptions, part: Option<RowPart>) -> Result<HMatrix, Error> {
        let points = self.points();
        let make = || {
            let mut cache = PairCache::new();
            move |i: usize, j: usize| match cache.get(self, i / 2, j / 2) {
                Some(p) => -p[3 * (j % 2) + i % 2],
                None => f64::NAN,
            }
        };
        Ok(match part {
            None => HMatrix::from_entries_par(make, &points, options)?,
            Some(p) => HMatrix::from_entries_part_par(make, &points, options, p)?,
        })
    }
}
