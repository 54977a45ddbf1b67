//! The finite-element volume of a square fault in a whole space (SEAS BP7 and BP8 with
//! `kernel = fe`, issue 85): the whole space truncated to the cube `|x|, |y|, |z| ≤ far`,
//! meshed by an octree of Kuhn cubes graded towards the square (and any off-fault
//! stations) in every direction. Two faults: the square alone, `x = 0`, `|y|, |z| ≤ l_f`,
//! a fault inside the body whose rim is a shared tip (docs/faults-inside.md, "How a
//! buried rim tapers"), the box's faces clamped (BP8: the plane locked outside the
//! square); or the whole plane `x = 0` across the box, creeping at the plate rate outside
//! the square and the box's faces carried with each side's rigid motion (BP7: the back
//! slip of the boundary elements).
//!
//! Coordinates are the benchmarks' own, as in [`crate::square_fault`]: the model's
//! `(x, y, z)` is `(x₁, x₂, x₃)`, `x₃` positive down, the plus side `x₁ > 0`.

use rsf::fault_ode::{FaultOdeOptions, InteriorOrdering, SchurOnlySetup};
use rsf::fault_operator::FaultKernel;
use rsf::fem::OctreeMesh;
use rsf::model::CreepRate;
use rsf::{Material, ModelBuilder, Part, Result};

use crate::invalid;

/// Most tetrahedra of a square's volume mesh (each root cube counted as 48 before the
/// refinement: the octree's own bound, [`OctreeMesh::refine`]).
pub const SQUARE_VOLUME_MAX_CELLS: usize = 20_000_000;

/// The grid of a square fault's finite-element volume ([`SquareVolumeGrid::builder`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SquareVolumeGrid {
    /// Cell size on the square (m): its node spacing; must divide `2 l_f` into whole cells.
    pub dx: f64,
    /// Half-width of the box (m), at least `2 l_f`; rounded up to whole root cubes (the
    /// octree's largest cubes, `dx · 2^k` at most a quarter of it).
    pub domain: f64,
    /// Growth of the cells away from the square: a cell at distance `d` (m) from it is
    /// at most `dx + (ratio − 1) d`; in `[1.01, 2]`.
    pub ratio: f64,
}

impl SquareVolumeGrid {
    /// The edge of the root cubes (m) and the box's half-width `far` (m): the largest
    /// `dx · 2^k` at most `domain/4` (at least `dx`), `far` the smallest multiple of it not
    /// below `domain` — so that the planes `x = 0` and `y, z = ±l_f` are planes of the
    /// octree's lattice.
    pub fn root_and_far(&self) -> (f64, f64) {
        let doublings = (0.25 * self.domain / self.dx).log2().floor().max(0.0);
        let root = self.dx * doublings.exp2();
        (root, (self.domain / root - 1e-9).ceil() * root)
    }

    /// Checks the grid for a square of half-width `half` (m).
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx` (not a divisor of `2 half` into 2 to
    /// [`MAX_SQUARE_CELLS`](crate::square_fault::MAX_SQUARE_CELLS) cells), `domain` (below
    /// `2 half`, or not finite) or `ratio` (outside `[1.01, 2]`: a uniform box would have
    /// `(domain/dx)³` cells).
    pub fn check(&self, half: f64) -> Result<()> {
        crate::square_fault::square_cells(half, self.dx)?;
        if !(self.domain.is_finite() && self.domain >= 2.0 * half) {
            return Err(invalid(
                "domain",
                format!(
                    "{} m must be at least 2 l_f = {} m (the box's half-width)",
                    rsf_numeric::written(self.domain),
                    rsf_numeric::number(2.0 * half)
                ),
            ));
        }
        if !(1.01..=2.0).contains(&self.ratio) {
            return Err(invalid(
                "ratio",
                format!("{} must be in [1.01, 2]", rsf_numeric::written(self.ratio)),
            ));
        }
        Ok(())
    }

    /// The refined octree of the box for a square of half-width `half` (m): cells at most
    /// `dx + (ratio − 1) d`, `d` the distance of a cube from the square or the nearest of
    /// `stations` (m).
    ///
    /// # Errors
    /// As [`check`](Self::check); named `grading` where the mesh would exceed
    /// [`SQUARE_VOLUME_MAX_CELLS`].
    fn octree(&self, half: f64, stations: &[[f64; 3]]) -> Result<OctreeMesh> {
        self.check(half)?;
        let stations = stations.to_vec();
        let (root, far) = self.root_and_far();
        let mut cubes = OctreeMesh::new([-far; 3], [far; 3], root)?;
        let (dx, growth) = (self.dx, self.ratio - 1.0);
        let square = ([0.0, -half, -half], [0.0, half, half]);
        let distance = |a: ([f64; 3], [f64; 3]), b: ([f64; 3], [f64; 3])| {
            (0..3)
                .map(|k| (a.0[k] - b.1[k]).max(b.0[k] - a.1[k]).max(0.0).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        let size = move |lo: [f64; 3], hi: [f64; 3]| {
            let d = stations
                .iter()
                .map(|&p| distance((lo, hi), (p, p)))
                .fold(distance((lo, hi), square), f64::min);
            dx + growth * d
        };
        cubes.refine(size, SQUARE_VOLUME_MAX_CELLS).map_err(|e| {
            invalid(
                "grading",
                format!(
                    "the box of half-width {far} m graded from dx = {} m by {}: {e}",
                    rsf_numeric::written(dx),
                    rsf_numeric::written(self.ratio)
                ),
            )
        })?;
        Ok(cubes)
    }

    /// The vertices of the volume's mesh (before the fault's split), counted from the
    /// octree without making the mesh (a plan's estimate).
    ///
    /// # Errors
    /// As [`check`](Self::check); [`rsf::Error::InvalidParameter`] named `grading` where
    /// the mesh would exceed [`SQUARE_VOLUME_MAX_CELLS`].
    pub fn mesh_vertices(&self, half: f64, stations: &[[f64; 3]]) -> Result<usize> {
        Ok(self.octree(half, stations)?.num_vertices())
    }

    /// The meshed box (graded towards the square and `stations`), `material` in it,
    /// quasi-static (no mass, `u₀ = 0`), `t₁` of the fault along `y`.
    fn volume(
        &self,
        half: f64,
        material: Material,
        stations: &[[f64; 3]],
    ) -> Result<ModelBuilder<3>> {
        let mesh = self.octree(half, stations)?.into_mesh()?;
        Ok(ModelBuilder::new(mesh)
            .material(material)
            .without_mass()
            .without_initial_equilibrium()
            .fault_tangent([0.0, 1.0, 0.0]))
    }

    /// The builder of the square alone in the volume (nothing assembled): the box meshed,
    /// `material` in it (quasi-static: no mass, `u₀ = 0`), its six faces clamped, the
    /// square `x = 0`, `|y|, |z| ≤ half` the internal fault `"fault"` with `t₁` along `y`
    /// (its faces the parts `fault_minus`, `fault_plus`: where a scene puts its prestress
    /// as equal and opposite tractions), its rim a shared tip.
    ///
    /// # Errors
    /// As [`check`](Self::check); named `grading` where the mesh would exceed
    /// [`SQUARE_VOLUME_MAX_CELLS`]; the mesh's.
    pub fn builder(&self, half: f64, material: Material) -> Result<ModelBuilder<3>> {
        let (_, far) = self.root_and_far();
        let eps = 1e-6 * self.dx;
        let (lo, hi) = (-half, half);
        Ok(self
            .volume(half, material, &[])?
            .dirichlet(
                Part::predicate("far faces", move |x: &[f64; 3]| {
                    x.iter().any(|c| c.abs() > far - eps)
                }),
                [0.0; 3],
            )
            .internal_fault_polygon(
                "fault",
                &[[0.0, lo, lo], [0.0, hi, lo], [0.0, hi, hi], [0.0, lo, hi]],
            ))
    }

    /// The builder of the creeping plane in the volume (nothing assembled), refined
    /// towards `stations` too: the whole plane `x = 0` across the box the internal fault
    /// `"fault"` (`t₁` along `y`; its faces `fault_minus`, `fault_plus`), its pairs outside
    /// the square `|y|, |z| ≤ half` (closed: the rim is frictional) creeping at
    /// `(v_p, 0)` in their frame, the box's faces off the plane moving with each side's
    /// rigid motion `∓v_p/2` along `y` — a uniform creep of the plane stresses nothing, so
    /// the square feels the back slip of a fault alone (`rsf::fault_alone::FaultAlone`).
    ///
    /// # Errors
    /// As [`check`](Self::check); named `grading` where the mesh would exceed
    /// [`SQUARE_VOLUME_MAX_CELLS`]; the mesh's.
    pub fn creeping_plane_builder(
        &self,
        half: f64,
        material: Material,
        stations: &[[f64; 3]],
        v_p: f64,
    ) -> Result<ModelBuilder<3>> {
        let (_, far) = self.root_and_far();
        let eps = 1e-6 * self.dx;
        let face = move |x: &[f64; 3]| x.iter().any(|c| c.abs() > far - eps);
        let inside = move |x: &[f64; 3]| x[1].abs() <= half + eps && x[2].abs() <= half + eps;
        Ok(self
            .volume(half, material, stations)?
            .dirichlet(
                Part::predicate("far minus", move |x: &[f64; 3]| x[0] < -eps && face(x)),
                [0.0, -0.5 * v_p, 0.0],
            )
            .dirichlet(
                Part::predicate("far plus", move |x: &[f64; 3]| x[0] > eps && face(x)),
                [0.0, 0.5 * v_p, 0.0],
            )
            .internal_fault_polygon(
                "fault",
                &[
                    [0.0, -far, -far],
                    [0.0, far, -far],
                    [0.0, far, far],
                    [0.0, -far, far],
                ],
            )
            .internal_creep_at(move |x| (!inside(x)).then_some(CreepRate::InFrame([v_p, 0.0]))))
    }
}

/// How a run's `kernel = fe` eliminates its volume (the front end's choices).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VolumeElimination {
    /// The volume's fill-reducing ordering (default
    /// [`InteriorOrdering::fastest_built`]: nested dissection where METIS is built, the
    /// fastest for a 3-D volume, docs/three-d.md).
    pub ordering: InteriorOrdering,
    /// The most bytes the elimination may hold (`--max-memory-gb`), `None` (the default)
    /// for no bound.
    pub max_bytes: Option<usize>,
}

impl Default for VolumeElimination {
    fn default() -> Self {
        Self {
            ordering: InteriorOrdering::fastest_built(),
            max_bytes: None,
        }
    }
}

impl VolumeElimination {
    /// `options` for a volume of `pairs` frictional nodes (`m = 2 pairs` slip unknowns):
    /// the condensed operator dense up to 4 096 unknowns and an ℋ-matrix of the
    /// tolerance's accuracy above ([`FaultKernel::matching`], as BP5's volume), the
    /// ordering [`ordering`](Self::ordering); and the Schur-only elimination's set-up (the volume's factor never
    /// held whole) keeping `watch_vertices`.
    pub fn options(
        &self,
        options: &mut FaultOdeOptions,
        pairs: usize,
        watch_vertices: Vec<usize>,
    ) -> SchurOnlySetup {
        if 2 * pairs > 4096 {
            options.kernel = FaultKernel::matching(options.tolerance);
        }
        options.ordering = self.ordering;
        SchurOnlySetup {
            watch_vertices,
            checkpoint: None,
            max_bytes: self.max_bytes,
            progress: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The root cube divides the box, and `x = 0` and `±l_f` are lattice planes.
    #[test]
    fn the_square_lies_on_the_lattice() {
        for (dx, domain) in [(20.0, 8e3), (40.0, 1e3), (10.0, 5e3), (100.0, 800.0)] {
            let grid = SquareVolumeGrid {
                dx,
                domain,
                ratio: 1.2,
            };
            let (root, far) = grid.root_and_far();
            assert!(far >= domain && far < domain + root + 1e-9);
            assert!(root <= (0.25 * domain).max(dx) + 1e-9);
            let k = far / root;
            assert!((k - k.round()).abs() < 1e-9, "{dx} {domain}");
            let m = (far - 400.0) / dx;
            assert!((m - m.round()).abs() < 1e-9);
        }
    }

    /// Refusals name the setting.
    #[test]
    fn bad_grids_are_refused_by_name() {
        let ok = SquareVolumeGrid {
            dx: 40.0,
            domain: 2e3,
            ratio: 1.2,
        };
        ok.check(400.0).unwrap();
        let name = |g: SquareVolumeGrid| crate::refused_name(g.check(400.0));
        assert_eq!(name(SquareVolumeGrid { dx: 30.0, ..ok }), "dx");
        assert_eq!(
            name(SquareVolumeGrid {
                domain: 700.0,
                ..ok
            }),
            "domain"
        );
        assert_eq!(
            name(SquareVolumeGrid {
                domain: f64::NAN,
                ..ok
            }),
            "domain"
        );
        assert_eq!(name(SquareVolumeGrid { ratio: 1.0, ..ok }), "ratio");
        assert_eq!(name(SquareVolumeGrid { ratio: 2.5, ..ok }), "ratio");
    }
}
