//! BP5 as a finite-element volume model: the mesh of the box (a tensor grid or an octree
//! graded towards the fault and the stations), the fault inside the body, and its fault ODE.

use rsf::fault_ode::{FaultOdeOptions, SchurOnlySetup};
use rsf::fem::{
    cuboid_from_coordinates, cuboid_mirrored, geometric_grading, symmetric_grading, OctreeMesh,
    TetrahedronMesh,
};
use rsf::model::{CreepRate, MaterialRegions};
use rsf::{Material, Model, ModelBuilder, Part, Result};

use super::{SeasBp5, SeasBp5FaultOde};
use crate::{check_ratio, invalid};

/// Largest root cube of [`SeasBp5Mesh::Graded`] (m): cells at the far faces, 400 km
/// from the fault, of at most 64 km (the tensor grid's there at ratio 1.3: about 90 km).
pub const GRADED_ROOT_MAX: f64 = 64e3;

/// Most cells of [`SeasBp5Mesh::Graded`]'s mesh (about 2.4 GB of mesh and a few times more
/// of matrices).
pub const GRADED_MAX_CELLS: usize = 20_000_000;

/// The edge (m) of the graded mesh's root cubes at `grid` and the half-width `far` (m) of
/// its box ([`SeasBp5::graded_root_cubes`]).
fn graded_root(grid: &SeasBp5Grid) -> (f64, f64) {
    let h = grid.dx;
    let doublings = (GRADED_ROOT_MAX / h).log2().floor().max(0.0);
    let root = h * doublings.exp2();
    (root, (grid.domain / root - 1e-9).ceil() * root)
}

/// The distance (m) between the boxes `a` and `b`, each `(lower, upper)` corners (0 where
/// they meet).
fn box_distance(a: ([f64; 3], [f64; 3]), b: ([f64; 3], [f64; 3])) -> f64 {
    (0..3)
        .map(|k| (a.0[k] - b.1[k]).max(b.0[k] - a.1[k]).max(0.0).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// How [`SeasBp5::fe_model`] meshes the volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum SeasBp5Mesh {
    /// A tensor grid of Kuhn boxes: uniform `dx` over the rate-and-state region along
    /// strike and dip (and one cell either side of the fault), growing by `ratio` beyond,
    /// axis by axis — the fault's fine spacing repeated in every layer of the box.
    Tensor,
    /// The tensor grid with the boxes mirrored by the parity of their position
    /// (`round(x/dx)` odd along an axis): the "union jack" pattern of diagonals of a
    /// bisection mesh (`rsf_fem::BisectionMesh`) on the tensor grid's boxes, whose fault
    /// nodes' lumped weights alternate between 2/3 and 4/3 of `dx²` — a test of that
    /// pattern apart from any grading (docs/fem.md, "Why not bisection for a fault"), not a
    /// mesh to run.
    TensorMirrored,
    /// An octree of Kuhn cubes refined towards the rate-and-state region and the off-fault
    /// stations ([`OctreeMesh`], docs/fem.md "Graded meshes: octree of Kuhn cubes"): cells
    /// `dx` there — the tensor grid's own Kuhn cells, with parallel diagonals — growing with
    /// the distance `d` in every direction as `dx + (ratio − 1) d` (the tensor grid's
    /// growth) beyond the slab `near_fault`.
    #[default]
    Graded,
}

/// The finite-element grid of BP5's volume model ([`SeasBp5::fe_model`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SeasBp5Grid {
    /// Spacing on the fault's rate-and-state region (m); must divide `l_f/2` and `W_f`.
    pub dx: f64,
    /// Distance from the fault to the box's far faces, and depth of the box (m).
    pub domain: f64,
    /// Growth of the spacing away from the rate-and-state region, in `[1, 2]`.
    pub ratio: f64,
    /// The tensor grid or the graded mesh (for the latter the box reaches the first
    /// multiple of its root cube not below `domain`).
    #[serde(default)]
    pub mesh: SeasBp5Mesh,
    /// The graded mesh's cells are `dx` in the slab `|x₁| ≤ near_fault` over the
    /// rate-and-state region (m; 0: on the fault's own cells only), so that a fault zone of
    /// that half-width is resolved cell for cell ([`FaultZone`]); a whole number of `dx`.
    ///
    /// [`FaultZone`]: super::FaultZone
    #[serde(default)]
    pub near_fault: f64,
}

impl Default for SeasBp5Grid {
    /// 4 km on the fault, a box reaching 400 km from it, growth 1.3, the graded mesh.
    fn default() -> Self {
        Self {
            dx: 4e3,
            domain: 400e3,
            ratio: 1.3,
            mesh: SeasBp5Mesh::Graded,
            near_fault: 0.0,
        }
    }
}

impl SeasBp5 {
    /// The vertices of a volume model ([`fe_model`](Self::fe_model)) nearest the off-fault
    /// stations ([`body_station_points`](Self::body_station_points)), sorted, without
    /// repeats: those the output reads off the fault.
    ///
    /// # Errors
    /// [`Model::nearest_node`]'s (a model without vertices).
    pub fn station_vertices(&self, model: &Model<3, 3>) -> Result<Vec<usize>> {
        crate::nearest_vertices(model, &Self::body_station_points())
    }

    /// The rate-and-state region `|x₂| ≤ l_f/2`, `x₃ ≤ W_f` (with a relative margin of
    /// 1e-9 of `W_f`).
    pub fn in_rate_state_region(&self, x2: f64, x3: f64) -> bool {
        let eps = 1e-9 * self.w_f;
        x2.abs() <= 0.5 * self.l_f + eps && x3 <= self.w_f + eps
    }

    /// BP5 as a finite-element volume model on `grid` (quasi-dynamic: no mass): the box
    /// `|x|, |y| ≤ domain`, `−domain ≤ z ≤ 0` of Kuhn tetrahedra (`grid.mesh`: on a tensor
    /// grid, uniform `dx` over the rate-and-state region and one cell across the fault and
    /// growing by `ratio` beyond; or graded by bisection in every direction, `dx` at the
    /// rate-and-state region and the off-fault stations, the box rounded up to whole root
    /// cubes), isotropic (μ = ρc_s², ν); the whole plane `x = 0` a fault inside
    /// the body ([`ModelBuilder::internal_fault_polygon`], `t₁` along strike): its pairs
    /// outside the rate-and-state region creeping at `(V_p, 0)`
    /// ([`ModelBuilder::internal_creep_at`]), those inside it frictional; the far faces
    /// carrying each side's rigid motion `±V_p/2` along `y` (the fault's own vertices on
    /// them only by the creep); the free surface `z = 0`; the prestress
    /// [`tau0`](Self::tau0) as equal and opposite tractions `±τ⁰ e_y` on the fault's two
    /// faces, over the whole plane (so that a frictional node on the region's rim carries
    /// its full prestress: the creeping pairs' share goes into their reaction); the
    /// initial displacement 0.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx` (not dividing `l_f/2` and `W_f`),
    /// `domain` (not beyond 1.5 l_f/2 and 1.5 W_f) or `ratio` (outside `[1, 2]`), named
    /// `grading` where the graded mesh of `dx`, `ratio` and `domain` exceeds its cell
    /// limit; grading and assembly errors.
    pub fn fe_model(&self, grid: &SeasBp5Grid) -> Result<Model<3, 3>> {
        self.fe_model_builder(grid)?.build()
    }

    /// The builder of [`fe_model`](Self::fe_model) (its mesh made, nothing assembled), e.g.
    /// to watch the build's stages ([`ModelBuilder::on_stage`]); `build` it for the model.
    ///
    /// # Errors
    /// As [`fe_model`](Self::fe_model) before its assembly.
    pub fn fe_model_builder(&self, grid: &SeasBp5Grid) -> Result<ModelBuilder<3>> {
        self.check_fe_grid(grid)?;
        let (h, far) = (grid.dx, grid.domain);
        let (mesh, [lo, hi]) = match grid.mesh {
            SeasBp5Mesh::Tensor | SeasBp5Mesh::TensorMirrored => (
                self.tensor_mesh(grid)?,
                [[-far, -far, -far], [far, far, 0.0]],
            ),
            SeasBp5Mesh::Graded => self.graded_mesh(grid, &[0.0])?,
        };
        let mu = self.shear_modulus();
        let host = Material::from_shear_modulus(mu, self.nu, self.rho);
        let builder = ModelBuilder::new(mesh);
        let builder = match self.fault_zone {
            None => builder.material(host),
            Some(zone) => {
                let mu_fz = self.fault_shear_modulus();
                let soft = Material::from_shear_modulus(mu_fz, self.nu, self.rho);
                let scene = *self;
                builder.material(MaterialRegions::new(host).region(
                    "fault zone",
                    move |x| {
                        x[0].abs() <= zone.half_width && scene.in_rate_state_region(x[1], -x[2])
                    },
                    soft,
                ))
            }
        };
        let eps = 1e-6 * h;
        let side = 0.5 * self.v_p;
        // Every face of the box but the free surface z = 0.
        let far_face = move |x: &[f64; 3]| {
            (0..2).any(|k| x[k] < lo[k] + eps || x[k] > hi[k] - eps) || x[2] < lo[2] + eps
        };
        let (a, b, c) = (*self, *self, *self);
        // u₀ = 0: the fault ODE carries the load in its condensed right-hand side.
        let builder = builder
            .without_mass()
            .without_initial_equilibrium()
            .dirichlet(
                Part::predicate("far minus", move |x| x[0] < -eps && far_face(x)),
                [0.0, -side, 0.0],
            )
            .dirichlet(
                Part::predicate("far plus", move |x| x[0] > eps && far_face(x)),
                [0.0, side, 0.0],
            )
            .fault_tangent([0.0, 1.0, 0.0])
            .internal_fault_polygon(
                "fault",
                &[
                    [0.0, lo[1], lo[2]],
                    [0.0, hi[1], lo[2]],
                    [0.0, hi[1], 0.0],
                    [0.0, lo[1], 0.0],
                ],
            )
            .internal_creep_at(move |x| {
                (!a.in_rate_state_region(x[1], -x[2])).then_some(CreepRate::InFrame([a.v_p, 0.0]))
            })
            // τ⁰ on the whole plane: a frictional node on the region's rim has half of its
            // faces outside the region, and must carry its full prestress; the creeping
            // pairs' slip is given, so their share goes into the reaction.
            .neumann(Part::from("fault_minus"), move |x| {
                [0.0, -b.tau0(x[1], -x[2]), 0.0]
            })
            .neumann(Part::from("fault_plus"), move |x| {
                [0.0, c.tau0(x[1], -x[2]), 0.0]
            });
        Ok(builder)
    }

    /// The vertices of the volume's mesh on `grid` before the fault's split (the mesh of
    /// [`fe_model`](Self::fe_model)): the graded mesh's counted from its octree without
    /// making it, in a fraction of the time the mesh takes (a plan's estimate; issue 87);
    /// the tensor grid's made and counted.
    ///
    /// # Errors
    /// As [`fe_model_builder`](Self::fe_model_builder).
    pub fn fe_mesh_vertices(&self, grid: &SeasBp5Grid) -> Result<usize> {
        self.check_fe_grid(grid)?;
        match grid.mesh {
            SeasBp5Mesh::Tensor | SeasBp5Mesh::TensorMirrored => {
                Ok(self.tensor_mesh(grid)?.num_vertices())
            }
            SeasBp5Mesh::Graded => self.graded_mesh_vertices(grid, &[0.0]),
        }
    }

    /// Checks `grid` for the volume model ([`fe_model`](Self::fe_model)): as its errors say.
    ///
    /// # Errors
    /// As [`fe_model`](Self::fe_model) before its mesh is made.
    pub(crate) fn check_fe_grid(&self, grid: &SeasBp5Grid) -> Result<()> {
        self.validate()?;
        let (h, far) = (grid.dx, grid.domain);
        let whole = |length: f64| {
            let n = length / h;
            h.is_finite() && h > 0.0 && n >= 1.0 && (n - n.round()).abs() <= 1e-12 * n
        };
        // The tensor grid is symmetric about x₂ = 0 (a line of nodes there); the graded
        // mesh's lattice is shifted along strike so that x₂ = ±l_f/2 are nodes.
        let along_strike = match grid.mesh {
            SeasBp5Mesh::Tensor | SeasBp5Mesh::TensorMirrored => 0.5 * self.l_f,
            SeasBp5Mesh::Graded => self.l_f,
        };
        if !(whole(along_strike) && whole(self.w_f)) {
            return Err(invalid(
                "dx",
                format!(
                    "{} m must divide {} = {along_strike} m and W_f = {} m into whole cells",
                    rsf_numeric::written(h),
                    match grid.mesh {
                        SeasBp5Mesh::Tensor | SeasBp5Mesh::TensorMirrored => {
                            "l_f/2 (the tensor grid)"
                        }
                        SeasBp5Mesh::Graded => "l_f",
                    },
                    self.w_f
                ),
            ));
        }
        if !(far.is_finite() && far >= 1.5 * (0.5 * self.l_f).max(self.w_f)) {
            return Err(invalid(
                "domain",
                format!(
                    "{} m must reach 1.5 times l_f/2 and W_f",
                    rsf_numeric::written(far)
                ),
            ));
        }
        check_ratio(grid.ratio)?;
        let multiple = |x: f64| x == 0.0 || (x > 0.0 && whole(x));
        if !(grid.near_fault.is_finite() && multiple(grid.near_fault)) {
            return Err(invalid(
                "near_fault",
                format!(
                    "{} m must be 0 or a whole number of dx = {} m",
                    rsf_numeric::written(grid.near_fault),
                    rsf_numeric::written(h)
                ),
            ));
        }
        if grid.near_fault > 0.0 && grid.mesh != SeasBp5Mesh::Graded {
            return Err(invalid(
                "near_fault",
                "a slab of cells dx is a setting of the graded mesh (the tensor grid grows \
                 from the fault at once)",
            ));
        }
        if let Some(zone) = self.fault_zone {
            if !(multiple(zone.half_width) && grid.near_fault >= zone.half_width) {
                return Err(invalid(
                    "fault_zone.half_width",
                    format!(
                        "{} m must be a whole number of dx = {} m and the graded mesh's \
                         near_fault ({} m) at least that, so that the zone is meshed cell \
                         for cell",
                        rsf_numeric::written(zone.half_width),
                        rsf_numeric::written(h),
                        rsf_numeric::written(grid.near_fault)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The tensor grid of [`SeasBp5Mesh::Tensor`] (box `±domain`).
    fn tensor_mesh(&self, grid: &SeasBp5Grid) -> Result<TetrahedronMesh> {
        let (h, far) = (grid.dx, grid.domain);
        let xs = symmetric_grading(h, h, grid.ratio, far)?;
        let ys = symmetric_grading(h, 0.5 * self.l_f, grid.ratio, far)?;
        let mut zs: Vec<f64> = geometric_grading(h, self.w_f, grid.ratio, far)?
            .iter()
            .rev()
            .map(|z| -z)
            .collect();
        *zs.last_mut().expect("a graded list is not empty") = 0.0;
        if grid.mesh == SeasBp5Mesh::TensorMirrored {
            let odd = |c: &[f64]| -> Vec<bool> {
                c[..c.len() - 1]
                    .iter()
                    .map(|x| (x / h).round().rem_euclid(2.0) == 1.0)
                    .collect()
            };
            let (fx, fy, fz) = (odd(&xs), odd(&ys), odd(&zs));
            return Ok(cuboid_mirrored(&xs, &ys, &zs, [&fx, &fy, &fz])?);
        }
        Ok(cuboid_from_coordinates(&xs, &ys, &zs)?)
    }

    /// The root cubes of [`SeasBp5Mesh::Graded`]'s octree at the grid `grid`, counted by
    /// arithmetic before anything is built (the mesh's octree: edge `root = dx·2^k` at
    /// most 64 km, `2 far / root` of them along strike and
    /// across, `far / root` in depth). Each makes up to 48 cells before any refinement:
    /// a box whose root cubes alone exceed [`GRADED_MAX_CELLS`] cannot be meshed (issue 87:
    /// `--domain-km 1e4` built 62.5 million cubes, 54 s and 6.3 GB, before a refusal).
    pub fn graded_root_cubes(grid: &SeasBp5Grid) -> f64 {
        let (root, far) = graded_root(grid);
        let per_side = 2.0 * far / root;
        per_side * per_side * (far / root)
    }

    /// The mesh of [`SeasBp5Mesh::Graded`] and the corners of its box (m): an octree of
    /// Kuhn cubes of edge `root = dx·2^k` (the largest at most [`GRADED_ROOT_MAX`]) on the box
    /// `|x| ≤ far`, `|y − s| ≤ far`, `−far ≤ z ≤ 0`, `far` the smallest multiple of `root`
    /// not below `domain` and `s` the shift (`l_f/2` modulo `dx`: 0 or `dx/2`) that puts
    /// nodes at `x₂ = ±l_f/2`, split ([`OctreeMesh`]) until every cell is at most
    /// `dx + (ratio − 1) d`, `d` the distance of its bounding box from the rate-and-state
    /// region (on the plane `x = 0`, thickened to `|x| ≤ near_fault`) or from the nearest
    /// off-fault station
    /// ([`body_station_points`](Self::body_station_points)).
    ///
    /// `planes` are the `x` (m) of the faults whose rate-and-state regions the mesh is
    /// refined towards (BP5: `[0]`; two parallel strands: both).
    pub(crate) fn graded_mesh(
        &self,
        grid: &SeasBp5Grid,
        planes: &[f64],
    ) -> Result<(TetrahedronMesh, [[f64; 3]; 2])> {
        let (cubes, corners) = self.graded_octree(grid, planes)?;
        Ok((cubes.into_mesh()?, corners))
    }

    /// The vertices of [`graded_mesh`](Self::graded_mesh) (before any fault's split),
    /// counted from its octree without making the mesh ([`OctreeMesh::num_vertices`]).
    ///
    /// # Errors
    /// As [`graded_mesh`](Self::graded_mesh).
    pub(crate) fn graded_mesh_vertices(&self, grid: &SeasBp5Grid, planes: &[f64]) -> Result<usize> {
        Ok(self.graded_octree(grid, planes)?.0.num_vertices())
    }

    /// The refined octree of [`graded_mesh`](Self::graded_mesh) and the corners of its box.
    fn graded_octree(
        &self,
        grid: &SeasBp5Grid,
        planes: &[f64],
    ) -> Result<(OctreeMesh, [[f64; 3]; 2])> {
        let h = grid.dx;
        let (root, far) = graded_root(grid);
        let cubes = Self::graded_root_cubes(grid);
        if 48.0 * cubes > GRADED_MAX_CELLS as f64 {
            return Err(invalid(
                "domain",
                format!(
                    "{} m: the graded mesh's {cubes:.3e} root cubes of {root:e} m alone make \
                     up to {:.3e} cells, above its {GRADED_MAX_CELLS} (a smaller box, or a \
                     larger dx)",
                    rsf_numeric::written(grid.domain),
                    48.0 * cubes
                ),
            ));
        }
        let shift = {
            let r = (0.5 * self.l_f / h).fract();
            if r > 0.25 && r < 0.75 {
                0.5 * h
            } else {
                0.0
            }
        };
        let (lo, hi) = ([-far, shift - far, -far], [far, shift + far, 0.0]);
        let growth = grid.ratio - 1.0;
        let near = grid.near_fault;
        let regions: Vec<([f64; 3], [f64; 3])> = planes
            .iter()
            .map(|&x| {
                (
                    [x - near, -0.5 * self.l_f, -self.w_f],
                    [x + near, 0.5 * self.l_f, 0.0],
                )
            })
            .collect();
        let stations = Self::body_station_points();
        let planes = planes.to_vec();
        let size = move |lo: [f64; 3], hi: [f64; 3]| {
            // A cube a fault plane cuts through (not on its faces) is split until the
            // plane is a face: every fault runs across the whole box (creeping beyond its
            // rate-and-state region), on faces of the mesh.
            let edge = hi[0] - lo[0];
            if planes
                .iter()
                .any(|&x| x > lo[0] + 1e-9 * edge && x < hi[0] - 1e-9 * edge)
            {
                return 0.5 * edge;
            }
            let region = regions
                .iter()
                .map(|&r| box_distance((lo, hi), r))
                .fold(f64::INFINITY, f64::min);
            let closest = stations
                .iter()
                .map(|&p| box_distance((lo, hi), (p, p)))
                .fold(region, f64::min);
            h + growth * closest
        };
        let mut cubes = OctreeMesh::new(lo, hi, root)?;
        cubes.refine(size, GRADED_MAX_CELLS).map_err(|e| {
            invalid(
                "grading",
                format!(
                    "the graded mesh of dx = {} m, ratio {} in a box of {} m: {e}",
                    rsf_numeric::written(h),
                    rsf_numeric::written(grid.ratio),
                    rsf_numeric::written(grid.domain)
                ),
            )
        })?;
        Ok((cubes, [lo, hi]))
    }

    /// The fault ODE of BP5 on the volume model `model` ([`fe_model`](Self::fe_model))
    /// with the condensed finite-element operator (`options.kernel`): the laws, state and
    /// damping of [`fault_ode`](Self::fault_ode).
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
        self.problem_builder(model).build_fault_ode(options)
    }

    /// As [`fe_fault_ode`](Self::fe_fault_ode) without ever holding the volume's whole
    /// factor ([`SimulationBuilder::build_fault_ode_schur_only`]: the same operator to
    /// round-off; the stations' vertices, `setup.watch_vertices`, given before the set-up).
    ///
    /// # Errors
    /// As [`fe_fault_ode`](Self::fe_fault_ode); the elimination's.
    ///
    /// [`SimulationBuilder::build_fault_ode_schur_only`]:
    ///     rsf::SimulationBuilder::build_fault_ode_schur_only
    pub fn fe_fault_ode_schur_only(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        setup: SchurOnlySetup,
    ) -> Result<SeasBp5FaultOde> {
        self.validate()?;
        self.problem_builder(model)
            .build_fault_ode_schur_only(options, setup)
    }
}
