//! A slip imposed on the fault and its field in the half-space: Okada's rectangles, each
//! with its uniform slip, superposed.

use std::cell::RefCell;
use std::rc::Rc;

use rsf_halfspace::{Deformation, Medium, Okada, Rectangle};

use super::common::{MU, NU};
use super::error::{ComparisonError, Result};

/// The slip the model's pairs are given, by position (Cartesian, m).
pub(crate) type SlipAt = Box<dyn Fn([f64; 3]) -> [f64; 3]>;

/// Okada's rectangles with their slips, superposed, and the slip the model's split pairs
/// are given at a point.
pub(crate) struct Dislocation {
    pub medium: Medium,
    /// Each rectangle with Okada's `[U1, U2, 0]`.
    parts: Vec<(Okada, [f64; 3])>,
    pub slip_at: SlipAt,
}

impl Dislocation {
    /// Uniform Cartesian `slip` (the hanging wall's relative motion, tangent to the
    /// rectangle) on `rect`.
    pub fn uniform(rect: Rectangle, slip: [f64; 3]) -> Result<Self> {
        Self::of(vec![(rect, slip)], Box::new(move |_| slip))
    }

    /// The rectangles `parts` with their Cartesian slips (each tangent to its rectangle:
    /// Okada's `U1 = s · e_s`, `U2 = s · e_d`); the model's pairs slip `slip_at`.
    pub fn of(parts: Vec<(Rectangle, [f64; 3])>, slip_at: SlipAt) -> Result<Self> {
        let medium = Medium::from_shear_poisson(MU, NU)?;
        let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let parts = parts
            .into_iter()
            .map(|(rect, s)| {
                let [e_s, e_d, _] = rect.frame();
                Ok((
                    Okada::new(medium.alpha(), rect)?,
                    [dot(&s, &e_s), dot(&s, &e_d), 0.0],
                ))
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            medium,
            parts,
            slip_at,
        })
    }

    /// The displacement and its gradient at `x`: the rectangles' fields summed in order.
    pub fn at(&self, x: [f64; 3]) -> Result<Deformation> {
        let mut parts = self.parts.iter();
        let (okada, u) = parts
            .next()
            .ok_or_else(|| ComparisonError::Setup("a dislocation without a rectangle".into()))?;
        let mut sum = okada.deformation(x, *u)?;
        for (okada, u) in parts {
            sum = sum.add_scaled(1.0, &okada.deformation(x, *u)?);
        }
        Ok(sum)
    }
}

/// The first error a held field met, for the caller to return after the build.
pub(crate) type FirstError = Rc<RefCell<Option<ComparisonError>>>;

/// The displacement of `dislocation` as the builder's held displacement of the far faces
/// ([`ModelBuilder::dirichlet_displacement`](crate::ModelBuilder::dirichlet_displacement)),
/// and the first error it met (a point the kernel refuses gives NaN, which the builder
/// refuses; the caller returns this error instead).
pub(crate) fn held_at(
    dislocation: Rc<Dislocation>,
) -> (impl Fn(&[f64; 3]) -> [f64; 3] + 'static, FirstError) {
    let error = Rc::new(RefCell::new(None));
    let slot = error.clone();
    let field = move |x: &[f64; 3]| match dislocation.at(*x) {
        Ok(d) => d.u,
        Err(e) => {
            slot.borrow_mut().get_or_insert(e);
            [f64::NAN; 3]
        }
    };
    (field, error)
}
