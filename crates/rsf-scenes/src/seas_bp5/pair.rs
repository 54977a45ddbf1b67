//! Two parallel strike-slip faults with BP5's physics (not a benchmark; docs/fault-networks.md,
//! "Two parallel faults in 3-D"): BP5's vertical fault repeated at `x = ∓separation/2`,
//! each strand with BP5's rate-and-state region, core, nucleation patch and prestress over
//! the same `(x₂, x₃)`, each loaded at the plate rate — a fault network of two disjoint
//! faults, run with the boundary-element kernel (both strands' cells in one set,
//! Okada's half-space, [`ElementOperator`]) or the finite-element volume (both planes
//! inside one box).

use rsf::fault_alone::FaultAlone;
use rsf::fault_ode::FaultOdeOptions;
use rsf::fem::TetrahedronMesh;
use rsf::halfspace::{ElementSet, RectangleElement, Space};
use rsf::halfspace_operator::{fault_alone_model, ElementOperator, ElementOptions};
use rsf::model::CreepRate;
use rsf::observe::FaultStation;
use rsf::{Material, Model, ModelBuilder, Part, Result};

use super::{SeasBp5, SeasBp5FaultOde, SeasBp5Grid, SeasBp5Mesh};
use crate::{invalid, invalid_length};

/// The names of the two strands: at `x = −separation/2` and `x = +separation/2`.
pub const BP5_PAIR_FAULTS: [&str; 2] = ["west", "east"];

/// The points `(x₂, x₃)` (km along strike, km depth) of each strand's stations: BP5's
/// on-fault stations at 10 km depth and the surface one above the core's centre.
pub const BP5_PAIR_STATIONS: [(f64, f64); 5] = [
    (-24.0, 10.0),
    (-16.0, 10.0),
    (0.0, 10.0),
    (16.0, 10.0),
    (0.0, 0.0),
];

/// Where BP5's nucleation patch is on the pair.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Bp5PairPatch {
    /// On both strands (mirror images of each other): which one leads is decided by
    /// round-off and the mesh's asymmetry.
    #[default]
    Both,
    /// On the west strand only: the east strand's L and initial slip rate are the rest of
    /// the region's (`L`, `V_init`), so the strands differ and the west one leads.
    West,
}

impl Bp5PairPatch {
    /// Whether the patch is on both strands (the default: left out of fingerprints and TOML,
    /// so that the runs before the setting keep theirs).
    pub(crate) fn is_both(&self) -> bool {
        *self == Self::Both
    }
}

/// BP5's physics on two parallel strands (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Bp5Pair {
    /// Each strand's parameters (BP5's; no fault zone).
    pub bp5: SeasBp5,
    /// The distance between the strands across strike (m), > 0.
    pub separation: f64,
    /// Where the nucleation patch is (serialised only when not on both strands: the
    /// fingerprints of the runs before it stand).
    #[serde(default, skip_serializing_if = "Bp5PairPatch::is_both")]
    pub patch: Bp5PairPatch,
}

impl Default for Bp5Pair {
    /// BP5's parameters, the strands 8 km apart (a whole number of 2 km and 4 km cells
    /// either side of the middle).
    fn default() -> Self {
        Self {
            bp5: SeasBp5::default(),
            separation: 8e3,
            patch: Bp5PairPatch::Both,
        }
    }
}

impl Bp5Pair {
    /// Checks BP5's parameters (without a fault zone) and the separation.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] naming the first invalid one.
    pub fn validate(&self) -> Result<()> {
        self.bp5.validate()?;
        if self.bp5.fault_zone.is_some() {
            return Err(invalid(
                "fault_zone",
                "two parallel strands have no compliant zone (BP5's own scene has)",
            ));
        }
        if !(self.separation > 0.0 && self.separation.is_finite()) {
            return Err(invalid_length(
                "separation",
                self.separation,
                "must be positive",
            ));
        }
        Ok(())
    }

    /// The parameters of the strand at `x` (m, across strike; the west strand for `x < 0`):
    /// BP5's, or on the east strand with [`Bp5PairPatch::West`] BP5's without the patch
    /// (its L and initial slip rate those of the rest of the region).
    pub fn strand(&self, x: f64) -> SeasBp5 {
        match self.patch {
            Bp5PairPatch::West if x > 0.0 => SeasBp5 {
                l_nucleation: self.bp5.l,
                v_i: self.bp5.v_init,
                ..self.bp5
            },
            _ => self.bp5,
        }
    }

    /// The `x` (m) of strand `f` (0: west, 1: east).
    pub fn x_of(&self, f: usize) -> f64 {
        if f == 0 {
            -0.5 * self.separation
        } else {
            0.5 * self.separation
        }
    }

    /// The boundary elements: each strand's rate-and-state region cut into squares of side
    /// `dx` (BP5's cells: strike fastest, the shallowest row first), the west strand's
    /// then the east one's, in Okada's half-space (the free surface `z = 0`).
    ///
    /// # Errors
    /// As [`SeasBp5::cells`].
    pub fn element_set(&self, dx: f64) -> Result<ElementSet<RectangleElement>> {
        self.validate()?;
        let n = self.bp5.cells(dx)?.len();
        let (n_strike, n_dip) = (
            (self.bp5.l_f / dx).round() as usize,
            (self.bp5.w_f / dx).round() as usize,
        );
        debug_assert_eq!(n, n_strike * n_dip);
        let halfspace = |e: rsf::halfspace::Error| invalid("element_set", e.to_string());
        let mut elements = Vec::with_capacity(2 * n);
        for f in 0..2 {
            elements.extend(
                RectangleElement::grid(
                    [self.x_of(f), 0.0, -0.5 * self.bp5.w_f],
                    90.0,
                    90.0,
                    [self.bp5.l_f, self.bp5.w_f],
                    [n_strike, n_dip],
                )
                .map_err(halfspace)?,
            );
        }
        ElementSet::new(self.bp5.medium()?, Space::HalfSpace, elements).map_err(halfspace)
    }

    /// The two strands alone on the cells of `set` ([`element_set`](Self::element_set)):
    /// one vertex per cell, the prestress [`SeasBp5::tau0_in_cell`] along strike as its
    /// load, each node with its strand's name.
    ///
    /// # Errors
    /// [`fault_alone_model`]'s.
    pub fn bem_model(&self, set: &ElementSet<RectangleElement>, dx: f64) -> Result<Model<3, 3>> {
        let mut model = fault_alone_model(set)?;
        let areas: Vec<f64> = model.frictional_boundary.weights.clone();
        for (k, c) in set.centres().iter().enumerate() {
            // The element's first slip component is along strike (+y).
            model.load[3 * k] = areas[k] * self.strand(c[0]).tau0_in_cell(c[1], -c[2], dx);
        }
        let half = set.n_elements() / 2;
        let faults: Vec<usize> = (0..set.n_elements())
            .map(|e| usize::from(e >= half))
            .collect();
        let names = BP5_PAIR_FAULTS.iter().map(|s| s.to_string()).collect();
        model.frictional_boundary = model
            .frictional_boundary
            .clone()
            .with_faults(names, &faults)?;
        Ok(model)
    }

    /// The fault ODE of the strands alone with Okada's operator on both (one ℋ-matrix or
    /// dense, `element_options`), loaded by back slip at `V_p` along strike on every cell:
    /// BP5's laws, state and damping ([`SeasBp5::problem_builder`], by position along
    /// strike and depth: the same on both strands).
    ///
    /// # Errors
    /// Invalid parameters; the operator's errors; the set-up errors of
    /// [`build_fault_ode_alone`](rsf::SimulationBuilder::build_fault_ode_alone).
    pub fn bem_fault_ode(
        &self,
        dx: f64,
        options: FaultOdeOptions,
        element_options: &ElementOptions,
    ) -> Result<SeasBp5FaultOde> {
        let set = self.element_set(dx)?;
        let model = self.bem_model(&set, dx)?;
        let operator = ElementOperator::fault_alone(&model, &set, element_options)
            .map_err(|e| invalid("element_operator", e.to_string()))?;
        let plate_velocity = (0..set.n_elements())
            .flat_map(|_| [self.bp5.v_p, 0.0])
            .collect();
        let alone = FaultAlone {
            operator: Box::new(operator),
            plate_velocity,
        };
        self.bp5
            .problem_builder_by(model, |x| self.strand(x[0]))
            .build_fault_ode_alone(options, alone)
    }

    /// The vertices of [`fe_model`](Self::fe_model)'s graded mesh on `grid`, counted from
    /// its octree without making the mesh (no tetrahedra, no model) — what a plan's memory
    /// estimate needs.
    ///
    /// # Errors
    /// As [`fe_model`](Self::fe_model) before its assembly.
    pub fn fe_mesh_vertices(&self, grid: &SeasBp5Grid) -> Result<usize> {
        self.check_pair_grid(grid)?;
        self.bp5
            .graded_mesh_vertices(grid, &[self.x_of(0), self.x_of(1)])
    }

    /// The checks of [`fe_model`](Self::fe_model) and its graded mesh with the box's
    /// corners.
    fn fe_mesh(&self, grid: &SeasBp5Grid) -> Result<(TetrahedronMesh, [[f64; 3]; 2])> {
        self.check_pair_grid(grid)?;
        self.bp5.graded_mesh(grid, &[self.x_of(0), self.x_of(1)])
    }

    /// The checks of [`fe_mesh`](Self::fe_mesh) before its mesh is made.
    fn check_pair_grid(&self, grid: &SeasBp5Grid) -> Result<()> {
        self.validate()?;
        // BP5's own checks of the grid.
        self.bp5.check_fe_grid(grid)?;
        if grid.mesh != SeasBp5Mesh::Graded {
            return Err(invalid(
                "mesh",
                "two strands take the graded mesh (refined towards both planes)",
            ));
        }
        let half = 0.5 * self.separation / grid.dx;
        if (half - half.round()).abs() > 1e-9 * half.max(1.0) || half < 1.0 {
            return Err(invalid(
                "separation",
                format!(
                    "{} m: half of it must be a whole number (≥ 1) of dx = {} m",
                    rsf_numeric::written(self.separation),
                    rsf_numeric::written(grid.dx)
                ),
            ));
        }
        Ok(())
    }

    /// The two strands as faults inside a finite-element box on `grid` (the graded mesh,
    /// refined towards both strands' rate-and-state regions; quasi-dynamic): the planes
    /// `x = ∓separation/2` across the whole box, each creeping at `V_p` along strike
    /// outside its rate-and-state region and frictional inside it; the far faces moving
    /// with their slab's plate motion — `−V_p` west of the west strand, 0 between the
    /// strands, `+V_p` east of the east strand (each strand slips `V_p`, as the
    /// boundary-element model's back slip) — the free surface `z = 0`; the prestress as
    /// equal and opposite tractions on each strand's faces (as
    /// [`SeasBp5::fe_model_builder`]).
    ///
    /// # Errors
    /// As [`SeasBp5::fe_model_builder`]; [`rsf::Error::InvalidParameter`] named `mesh`
    /// for another mesh than the graded one, `separation` unless `separation/2` is a whole
    /// number of `dx` (the strands on the mesh's planes); assembly errors.
    pub fn fe_model(&self, grid: &SeasBp5Grid) -> Result<Model<3, 3>> {
        let (mesh, [lo, hi]) = self.fe_mesh(grid)?;
        let planes = [self.x_of(0), self.x_of(1)];
        let p = self.bp5;
        let mu = p.shear_modulus();
        let eps = 1e-6 * grid.dx;
        let v = p.v_p;
        let far_face = move |x: &[f64; 3]| {
            (0..2).any(|k| x[k] < lo[k] + eps || x[k] > hi[k] - eps) || x[2] < lo[2] + eps
        };
        let [west, east] = planes;
        let mut b = ModelBuilder::new(mesh)
            .material(Material::from_shear_modulus(mu, p.nu, p.rho))
            .without_mass()
            .without_initial_equilibrium()
            .dirichlet(
                Part::predicate("far west", move |x| x[0] < west - eps && far_face(x)),
                [0.0, -v, 0.0],
            )
            .dirichlet(
                Part::predicate("far middle", move |x| {
                    x[0] > west + eps && x[0] < east - eps && far_face(x)
                }),
                [0.0, 0.0, 0.0],
            )
            .dirichlet(
                Part::predicate("far east", move |x| x[0] > east + eps && far_face(x)),
                [0.0, v, 0.0],
            )
            .fault_tangent([0.0, 1.0, 0.0]);
        for (f, name) in BP5_PAIR_FAULTS.iter().enumerate() {
            let x = self.x_of(f);
            let p = self.strand(x);
            b = b
                .internal_fault_polygon(
                    name,
                    &[
                        [x, lo[1], lo[2]],
                        [x, hi[1], lo[2]],
                        [x, hi[1], 0.0],
                        [x, lo[1], 0.0],
                    ],
                )
                .neumann(Part::from(format!("{name}_minus").as_str()), move |x| {
                    [0.0, -p.tau0(x[1], -x[2]), 0.0]
                })
                .neumann(Part::from(format!("{name}_plus").as_str()), move |x| {
                    [0.0, p.tau0(x[1], -x[2]), 0.0]
                });
        }
        b.internal_creep_at(move |x| {
            (!p.in_rate_state_region(x[1], -x[2])).then_some(CreepRate::InFrame([v, 0.0]))
        })
        .build()
    }

    /// The fault ODE of the strands in the box (`model` from [`fe_model`](Self::fe_model))
    /// with the condensed finite-element operator (`options.kernel`): BP5's laws, state and
    /// damping.
    ///
    /// # Errors
    /// Invalid parameters; the set-up errors of
    /// [`build_fault_ode`](rsf::SimulationBuilder::build_fault_ode).
    pub fn fe_fault_ode(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
    ) -> Result<SeasBp5FaultOde> {
        self.validate()?;
        self.bp5
            .problem_builder_by(model, |x| self.strand(x[0]))
            .build_fault_ode(options)
    }

    /// As [`fe_fault_ode`](Self::fe_fault_ode) without ever holding the volume's whole
    /// factor ([`SimulationBuilder::build_fault_ode_schur_only`](rsf::SimulationBuilder::build_fault_ode_schur_only)).
    ///
    /// # Errors
    /// As [`fe_fault_ode`](Self::fe_fault_ode); the elimination's.
    pub fn fe_fault_ode_schur_only(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        setup: rsf::fault_ode::SchurOnlySetup,
    ) -> Result<SeasBp5FaultOde> {
        self.validate()?;
        self.bp5
            .problem_builder_by(model, |x| self.strand(x[0]))
            .build_fault_ode_schur_only(options, setup)
    }

    /// The stations: on each strand at [`BP5_PAIR_STATIONS`], labelled
    /// `st{x₂}dp{x₃}` (km, as BP5's file names: e.g. `west_st+16dp10.csv`).
    pub fn stations(&self) -> Vec<FaultStation<3>> {
        BP5_PAIR_FAULTS
            .iter()
            .enumerate()
            .flat_map(|(f, &name)| {
                BP5_PAIR_STATIONS.iter().map(move |&(x2, x3)| FaultStation {
                    fault: name.to_owned(),
                    near: [self.x_of(f), 1e3 * x2, -1e3 * x3],
                    label: format!("st{:+03.0}dp{:02.0}", x2, x3),
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plans' count of the pair's vertices, from the octree without the mesh, is the
    /// mesh's (the box refined towards two planes has transition cubes on both sides).
    #[test]
    fn the_counted_vertices_are_the_meshs() {
        let pair = Bp5Pair::default();
        let grid = SeasBp5Grid {
            dx: 4e3,
            domain: 100e3,
            ..SeasBp5Grid::default()
        };
        let (mesh, _) = pair.fe_mesh(&grid).unwrap();
        assert_eq!(pair.fe_mesh_vertices(&grid).unwrap(), mesh.num_vertices());
    }
    /// With the patch on the west strand only, the east strand's cells carry the rest of
    /// the region's prestress and L everywhere (what BP5's scene gives outside its patch),
    /// the west strand's the patch's where it lies; with the patch on both, the strands are
    /// the same cell for cell. Okada's 4 km cells: 250 per strand, 9 of them on the patch.
    #[test]
    fn the_patch_is_where_the_setting_puts_it() {
        let dx = 4e3;
        let loads_and_l = |patch| {
            let pair = Bp5Pair {
                patch,
                ..Bp5Pair::default()
            };
            let set = pair.element_set(dx).unwrap();
            let model = pair.bem_model(&set, dx).unwrap();
            let half = set.n_elements() / 2;
            let per_strand = |s: std::ops::Range<usize>| -> Vec<(f64, f64)> {
                s.map(|k| {
                    let c = set.centres()[k];
                    (
                        model.load[3 * k],
                        pair.strand(c[0]).l_in_cell(c[1], -c[2], dx),
                    )
                })
                .collect()
            };
            (per_strand(0..half), per_strand(half..2 * half))
        };
        let (west, east) = loads_and_l(Bp5PairPatch::Both);
        assert_eq!(west, east);
        let bp5 = SeasBp5::default();
        let on_patch = west.iter().filter(|(_, l)| *l != bp5.l).count();
        assert_eq!(on_patch, 9);
        let (west_only, east_alone) = loads_and_l(Bp5PairPatch::West);
        assert_eq!(west_only, west);
        assert!(east_alone.iter().all(|(_, l)| *l == bp5.l));
        let set = Bp5Pair::default().element_set(dx).unwrap();
        let differ = east_alone
            .iter()
            .zip(&east)
            .enumerate()
            .filter(|(_, (a, b))| a != b)
            .map(|(k, _)| set.centres()[k])
            .collect::<Vec<_>>();
        assert_eq!(differ.len(), on_patch);
        assert!(differ
            .iter()
            .all(|c| bp5.patch_share(c[1], -c[2], dx) > 0.0));
    }
}
