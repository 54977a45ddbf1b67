//! The paper's model problem extruded to three dimensions (docs/math.md §6, §10): the
//! 5 m × 1 m block of [`SliderScene`] becomes a 5 m × 1 m × W box of Kuhn tetrahedra,
//! with the same material, loading and friction, and a choice of lateral boundary
//! conditions on the faces z = 0 and z = W.

use serde::{Deserialize, Serialize};

use rsf_fem::{cuboid, Diagonal, TetrahedronMesh, TAG_DIRICHLET, TAG_FRICTIONAL, TAG_NEUMANN};
use rsf_time::VelocityIntegrator;
use rsf_tnnmg::SmootherOrder;

use crate::invalid;
use rsf::checkpoint::Fingerprint;
use rsf::method::InnerSolves;
use rsf::model::EquilibriumSystem;
use rsf::Model;
use rsf::ModelBuilder;
use rsf::{Error, Result};

use super::slider::build::scene_builder;
use super::slider::{SceneSimulation, SceneSimulationBuilder, SliderScene};

/// Tag of the lateral faces z = 0 and z = W of [`slider_3d_coarse`].
pub const TAG_LATERAL: &str = "lateral";

/// Boundary condition on the lateral faces z = 0 and z = W of the 3-D slider.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum LateralBoundary {
    /// Traction-free (Neumann): the block may bulge sideways (Poisson effect).
    #[default]
    Free,
    /// `u_z = 0` on both faces (rollers). The continuous solution is then the 2-D
    /// plane-strain solution, constant in z.
    PlaneStrain,
}

/// The 3-D slider: the paper's scene ([`SliderScene`], Table 6.1) extruded in z.
///
/// All of [`SliderScene`]'s fields keep their meaning, with 3-D units: the density is in
/// kg/m³ (same value as the 2-D kg/m² per unit thickness), gravity acts in −y, the
/// loading velocity `(V_D g(t), 0, 0)` is prescribed on the whole top face y = 1 m, and Γ_F
/// is the bottom face y = 0 with bilateral contact (u_y fixed; x and z tangential, the slip
/// rate is `√(v_x² + v_z²)`). The faces x = 0 and x = 5 m are traction-free. `level` counts
/// uniform refinements of the coarse mesh [`slider_3d_coarse`] (each doubles every edge
/// count; 8 children per tetrahedron). `diagonal` must be `forward`: the Kuhn
/// tetrahedra project onto the forward-diagonal triangles of the 2-D scene.
///
/// In TOML the fields of [`SliderScene`] and those of this struct (`width_m`, `lateral`)
/// sit side by side at the top level; unknown fields are rejected with their name.
///
/// ```
/// let scene = rsf_scenes::Slider3dScene::from_toml(
///     "level = 1\nwidth_m = 0.5\nlateral = \"plane-strain\"\nsteps = 10",
/// )?;
/// assert_eq!((scene.slider.level, scene.width_m), (1, 0.5));
/// let model = scene.build_model()?;
/// assert_eq!(model.num_nodes(), 11 * 3 * 3);
/// # Ok::<(), rsf::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct Slider3dScene {
    /// The 2-D scene's parameters (Table 6.1), shared.
    #[serde(flatten)]
    #[cfg_attr(feature = "clap", command(flatten))]
    pub slider: SliderScene,
    /// Width W of the block in z (m), in [1e-3, 1000].
    #[cfg_attr(feature = "clap", arg(long, visible_alias = "width", default_value_t = Slider3dScene::default().width_m, value_name = "W"))]
    pub width_m: f64,
    /// Boundary condition on the lateral faces z = 0 and z = W.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = Slider3dScene::default().lateral))]
    pub lateral: LateralBoundary,
}

impl Default for Slider3dScene {
    /// The paper's parameters at level 2, W = 1 m, free lateral faces; inexact inner
    /// solves for TNNMG ([`InnerSolves::BySolver`]: 1.8× fewer TNNMG iterations for the
    /// same events, docs/scaling.md) and its smoothers in red–black chunks
    /// ([`SmootherOrder::RedBlackChunks`]: on the solver's threads, the same bits for every
    /// thread count; the lexicographic order's trajectories in round-off; docs/scaling.md).
    fn default() -> Self {
        Self {
            slider: SliderScene {
                level: 2,
                fixed_point_inner_solves: InnerSolves::BySolver,
                tnnmg_smoother: SmootherOrder::RedBlackChunks,
                ..SliderScene::default()
            },
            width_m: 1.0,
            lateral: LateralBoundary::Free,
        }
    }
}

impl Serialize for Slider3dScene {
    /// The fields of [`SliderScene`] and `width_m`, `lateral` at the top level, as
    /// [`from_toml`](Slider3dScene::from_toml) reads them; `fixed_point_inner_solves` and
    /// `tnnmg_smoother` are always written (their defaults differ between the 2-D and the
    /// 3-D scene).
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::Error as _;
        let mut table = toml::Table::try_from(&self.slider).map_err(S::Error::custom)?;
        let inner = toml::Value::try_from(self.slider.fixed_point_inner_solves)
            .map_err(S::Error::custom)?;
        let lateral = toml::Value::try_from(self.lateral).map_err(S::Error::custom)?;
        table.insert("fixed_point_inner_solves".into(), inner);
        let smoother =
            toml::Value::try_from(self.slider.tnnmg_smoother).map_err(S::Error::custom)?;
        table.insert("tnnmg_smoother".into(), smoother);
        table.insert("width_m".into(), toml::Value::Float(self.width_m));
        table.insert("lateral".into(), lateral);
        table.serialize(serializer)
    }
}

/// The fields of [`Slider3dScene`] besides the shared [`SliderScene`] ones.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Extrusion {
    width_m: Option<f64>,
    lateral: Option<LateralBoundary>,
}

/// `x` rotated by `phi` (rad) about the unit axis `(1, 2, 3)/√14` (Rodrigues' formula):
/// aligned with no coordinate axis or plane ([`Slider3dScene::build_turned_model`]).
pub fn skew_rotation(phi: f64, x: [f64; 3]) -> [f64; 3] {
    let l = 14f64.sqrt();
    let k = [1.0 / l, 2.0 / l, 3.0 / l];
    let (s, c) = phi.sin_cos();
    let kx = [
        k[1] * x[2] - k[2] * x[1],
        k[2] * x[0] - k[0] * x[2],
        k[0] * x[1] - k[1] * x[0],
    ];
    let kdx = k[0] * x[0] + k[1] * x[1] + k[2] * x[2];
    std::array::from_fn(|r| x[r] * c + kx[r] * s + k[r] * kdx * (1.0 - c))
}

/// Coarse mesh of the 3-D slider: the box `[0, 5] × [0, 1] × [0, W]` m with 5 × 1 × `nz`
/// cubes (`nz = max(1, round(W / 1 m))`) of 6 Kuhn tetrahedra each ([`cuboid`]), and
/// boundary tags [`TAG_DIRICHLET`] (top, y = 1), [`TAG_FRICTIONAL`] (bottom, y = 0),
/// [`TAG_NEUMANN`] (x = 0 and x = 5) and [`TAG_LATERAL`] (z = 0 and z = W).
///
/// # Errors
/// [`Error::InvalidParameter`] named `width_m` for a width outside [1 mm, 1000 m]: below, the
/// coarse tetrahedra are more than 1000 times thinner than the block is high (their
/// stiffness matrix loses the digits of the run); above, more than 1000 coarse cells in z.
pub fn slider_3d_coarse(width_m: f64) -> Result<TetrahedronMesh> {
    if !(width_m.is_finite() && (1e-3..=1000.0).contains(&width_m)) {
        return Err(invalid(
            "width_m",
            format!(
                "{} m must be in [1e-3, 1000] m",
                rsf_numeric::written(width_m)
            ),
        ));
    }
    let nz = (width_m.round() as usize).max(1);
    let mut mesh = cuboid([0.0; 3], [5.0, 1.0, width_m], [6, 2, nz + 1])?;
    let eps = 1e-9;
    mesh.tag_boundary(TAG_NEUMANN, |x| x[0] < eps || x[0] > 5.0 - eps);
    mesh.tag_boundary(TAG_LATERAL, |x| {
        x[2] < eps * width_m || x[2] > width_m * (1.0 - eps)
    });
    mesh.tag_boundary(TAG_DIRICHLET, |x| x[1] > 1.0 - eps);
    mesh.tag_boundary(TAG_FRICTIONAL, |x| x[1] < eps);
    Ok(mesh)
}

impl Slider3dScene {
    /// Bytes per mesh node of a 3-D slider run in
    /// [`estimated_bytes`](Self::estimated_bytes): the peak resident set of the j = 4 run
    /// of docs/three-d.md and docs/scaling.md (752 MiB at 23 409 nodes, 33.7 kB per node),
    /// rounded up.
    pub const BYTES_PER_NODE: f64 = 35e3;

    /// The scene's mesh nodes at its level, `(5·2ʲ + 1)(2ʲ + 1)(n_z·2ʲ + 1)` with `n_z`
    /// the coarse cells across the width, and the memory a run takes, estimated before
    /// anything is allocated (`f64`: a level of 30 is a number, not an overflow) — to
    /// refuse a level the machine cannot hold.
    pub fn estimated_bytes(&self) -> (f64, f64) {
        let k = 2f64.powi(self.slider.level.min(1000) as i32);
        let nz = self.width_m.round().max(1.0);
        let nodes = (5.0 * k + 1.0) * (k + 1.0) * (nz * k + 1.0);
        (nodes, nodes * Self::BYTES_PER_NODE)
    }

    /// Reads a TOML scene file ([`from_toml`](Self::from_toml)).
    ///
    /// # Errors
    /// [`Error::SceneFile`] naming the path: it cannot be read, or as
    /// [`from_toml`](Self::from_toml).
    pub fn read(path: impl AsRef<std::path::Path>) -> Result<Self> {
        crate::scene_file::read(path.as_ref(), Self::from_toml)
    }

    /// Parses a TOML scene: the fields of [`SliderScene`] and `width_m`, `lateral`
    /// (`"free"` or `"plane-strain"`), all optional: a missing field takes the value of
    /// [`Slider3dScene::default`] (level 2, `fixed_point_inner_solves = "by-solver"`,
    /// `tnnmg_smoother = "red-black-chunks"`, the other shared fields as in
    /// [`SliderScene::default`]).
    ///
    /// # Errors
    /// [`Error::SceneFile`] with the parser's message (it names unknown fields).
    pub fn from_toml(text: &str) -> Result<Self> {
        let file = |e: toml::de::Error| crate::scene_file::toml_error(text, &e);
        let mut table: toml::Table = toml::from_str(text).map_err(file)?;
        // Each key alone first, so that an error names its key (a table read as a whole
        // loses the place of its values).
        for (key, value) in &table {
            let one = toml::Table::from_iter([(key.clone(), value.clone())]);
            let checked = if key == "width_m" || key == "lateral" {
                one.try_into::<Extrusion>().map(drop)
            } else {
                one.try_into::<SliderScene>().map(drop)
            };
            checked.map_err(|e| crate::scene_file::key_error(key, &e))?;
        }
        let mut own = toml::Table::new();
        for key in ["width_m", "lateral"] {
            if let Some(v) = table.remove(key) {
                own.insert(key.to_owned(), v);
            }
        }
        let extrusion: Extrusion = own.try_into().map_err(file)?;
        // The file's fields over the 3-D scene's defaults (level 2, `by-solver` inner
        // solves, red–black chunks), not the 2-D scene's.
        let default = Self::default();
        let mut merged =
            toml::Table::try_from(&default.slider).map_err(|e| Error::SceneFile(e.to_string()))?;
        merged.extend(table);
        let slider: SliderScene = merged.try_into().map_err(file)?;
        Ok(Self {
            slider,
            width_m: extrusion.width_m.unwrap_or(default.width_m),
            lateral: extrusion.lateral.unwrap_or(default.lateral),
        })
    }

    /// What a checkpoint of this scene continues: every field as TOML names it (those of
    /// [`SliderScene`] and `width_m`, `lateral`) and the checkpoint `format`, like
    /// [`SliderScene::fingerprint`]; `tnnmg_smoother` only when not `"lexicographic"`
    /// (the one order before the field existed, so the checkpoints of those runs
    /// continue).
    pub fn fingerprint(&self) -> Fingerprint {
        let mut fingerprint = Fingerprint::of_serialized(self);
        if self.slider.tnnmg_smoother == SmootherOrder::Lexicographic {
            fingerprint.0.retain(|(field, _)| field != "tnnmg_smoother");
        }
        fingerprint.with("format", rsf::checkpoint::CHECKPOINT_FORMAT)
    }

    /// The point where the time series is recorded: `x0 = (2.5, 0, W/2)` m, the centre of
    /// Γ_F.
    pub fn centre(&self) -> [f64; 3] {
        [2.5, 0.0, 0.5 * self.width_m]
    }

    /// Checks every parameter, naming the first invalid one.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] or the friction crate's parameter error.
    pub fn validate(&self) -> Result<()> {
        self.slider.validate()?;
        slider_3d_coarse(self.width_m)?;
        if self.slider.diagonal != Diagonal::Forward {
            return Err(invalid(
                "diagonal",
                "the 3-D slider's Kuhn tetrahedra project onto the forward diagonal only",
            ));
        }
        Ok(())
    }

    /// Assembles the model at `slider.level` with [`ModelBuilder`]: consistent mass (unless
    /// quasistatic), isotropic 3-D stiffness, gravity `(0, −g, 0)`, Γ_D (top: all
    /// components, velocity `(v_load g(t), 0, 0)` with the ramp `g`), Γ_F (bottom, u_y
    /// fixed), `u_z = 0` on the lateral faces for [`LateralBoundary::PlaneStrain`], the
    /// hierarchy's prolongations and `u_0` solving `K u_0 = F`; then
    /// [`SliderScene::check_conditioning`].
    ///
    /// # Errors
    /// Invalid parameters (a level whose mesh exceeds [`MAX_CELLS`](rsf::model::MAX_CELLS) is
    /// named `levels`); assembly errors; [`Error::IllConditioned`](rsf::Error::IllConditioned).
    pub fn build_model(&self) -> Result<Model<3>> {
        let model = self.model_builder()?.build()?;
        self.slider.check_conditioning(&model)?;
        Ok(model)
    }

    /// The part of [`build_model`](Self::build_model)'s model one process of several
    /// holds: the matrices' columns of the vertices with `keep[vertex]` (one flag per
    /// vertex of the finest mesh), the initial equilibrium by `equilibrium`
    /// ([`ModelBuilder::build_columns`]); then
    /// [`SliderScene::check_conditioning`] on those columns.
    ///
    /// # Errors
    /// As [`build_model`](Self::build_model) and [`ModelBuilder::build_columns`].
    pub fn build_model_columns(
        &self,
        keep: &[bool],
        equilibrium: impl FnOnce(&EquilibriumSystem<'_>) -> Result<Vec<f64>>,
    ) -> Result<Model<3>> {
        let model = self.model_builder()?.build_columns(keep, equilibrium)?;
        self.slider.check_conditioning(&model)?;
        Ok(model)
    }

    /// The builder of [`build_model`](Self::build_model), the scene validated: for a
    /// caller that needs the finest mesh before building (e.g. to partition it and
    /// [`build_columns`](ModelBuilder::build_columns) a rank's part; then
    /// [`SliderScene::check_conditioning`] as `build_model` does).
    ///
    /// # Errors
    /// As [`build_model`](Self::build_model) before assembly.
    pub fn model_builder(&self) -> Result<ModelBuilder<3>> {
        self.validate()?;
        let s = &self.slider;
        let mut builder = ModelBuilder::refined(slider_3d_coarse(self.width_m)?, s.level)?
            .material(s.material())
            .gravity([0.0, -s.gravity_m_per_s2, 0.0])
            .dirichlet(TAG_DIRICHLET, [s.loading_velocity_m_per_s, 0.0, 0.0])
            .frictional_boundary(TAG_FRICTIONAL)
            .loading(s.loading());
        if self.lateral == LateralBoundary::PlaneStrain {
            builder = builder.dirichlet_components(TAG_LATERAL, &[2], [0.0; 3]);
        }
        if s.absorbing_sides {
            builder = builder.absorbing_boundary(TAG_NEUMANN);
        }
        if !s.integrator.uses_mass() {
            builder = builder.without_mass();
        }
        Ok(builder)
    }

    /// The model of this slider turned by `phi` (rad) about [`skew_rotation`]'s axis: the
    /// coarse mesh's vertices, gravity and the top's velocity rotated, the faces tagged as
    /// [`slider_3d_coarse`]'s, and the fault's reference tangent
    /// ([`ModelBuilder::fault_tangent`]) the rotated `e_x`, so that the slip along the first
    /// tangent is the unturned slider's slip along x. The coarse cells are Kuhn paths, whose
    /// refinement order is increasing vertex index: the turned hierarchy is the unturned
    /// one, rotated, and every fault node has a nodal frame (docs/math.md §10.1). The same
    /// discrete problem in other coordinates: for rotation-invariance tests and for what
    /// the frames cost. At `phi = 0` the matrices, load and constraints are those of
    /// [`build_model`](Self::build_model) (asserted in `tests/nodal_frames.rs`); with
    /// plane-strain lateral faces `phi = 0` is `build_model` itself.
    ///
    /// # Errors
    /// As [`build_model`](Self::build_model); [`Error::InvalidParameter`] named `lateral`
    /// for plane-strain lateral faces (a constraint on Cartesian `u_z`, not turned here) and
    /// named `angle` for a non-finite angle.
    pub fn build_turned_model(&self, phi: f64) -> Result<Model<3>> {
        let model = match self.turned_model_builder(phi)? {
            Some(builder) => builder.build()?,
            None => return self.build_model(),
        };
        self.slider.check_conditioning(&model)?;
        Ok(model)
    }

    /// The part of [`build_turned_model`](Self::build_turned_model)'s model one process of
    /// several holds (as [`build_model_columns`](Self::build_model_columns)).
    ///
    /// # Errors
    /// As [`build_turned_model`](Self::build_turned_model) and
    /// [`ModelBuilder::build_columns`].
    pub fn build_turned_model_columns(
        &self,
        phi: f64,
        keep: &[bool],
        equilibrium: impl FnOnce(&EquilibriumSystem<'_>) -> Result<Vec<f64>>,
    ) -> Result<Model<3>> {
        let model = match self.turned_model_builder(phi)? {
            Some(builder) => builder.build_columns(keep, equilibrium)?,
            None => return self.build_model_columns(keep, equilibrium),
        };
        self.slider.check_conditioning(&model)?;
        Ok(model)
    }

    /// The builder of [`build_turned_model`](Self::build_turned_model), the scene
    /// validated; `None` for plane-strain lateral faces at `phi = 0`
    /// ([`build_model`](Self::build_model)'s).
    fn turned_model_builder(&self, phi: f64) -> Result<Option<ModelBuilder<3>>> {
        if !phi.is_finite() {
            return Err(invalid("angle", format!("{phi} rad must be finite")));
        }
        if self.lateral != LateralBoundary::Free {
            if phi == 0.0 {
                return Ok(None);
            }
            return Err(invalid(
                "lateral",
                "the turned 3-D slider has free lateral faces only",
            ));
        }
        self.validate()?;
        let flat = slider_3d_coarse(self.width_m)?;
        let vertices = flat
            .vertices()
            .iter()
            .map(|&x| skew_rotation(phi, x))
            .collect();
        let cells = flat
            .cells()
            .chunks_exact(4)
            .flat_map(|c| {
                let mut c = [c[0], c[1], c[2], c[3]];
                c.sort_unstable();
                c
            })
            .collect();
        let mut coarse = TetrahedronMesh::from_ordered_cells(vertices, cells)?;
        let w = self.width_m;
        let back = |x: &[f64; 3]| skew_rotation(-phi, *x);
        coarse.tag_boundary(TAG_NEUMANN, |x| {
            let y = back(x);
            y[0] < 1e-9 || y[0] > 5.0 - 1e-9
        });
        coarse.tag_boundary(TAG_LATERAL, |x| {
            let y = back(x);
            y[2] < 1e-9 * w || y[2] > w * (1.0 - 1e-9)
        });
        coarse.tag_boundary(TAG_DIRICHLET, |x| back(x)[1] > 1.0 - 1e-9);
        coarse.tag_boundary(TAG_FRICTIONAL, |x| back(x)[1] < 1e-9);
        let s = &self.slider;
        let builder = ModelBuilder::refined(coarse, s.level)?
            .material(s.material())
            .gravity(skew_rotation(phi, [0.0, -s.gravity_m_per_s2, 0.0]))
            .dirichlet(
                TAG_DIRICHLET,
                skew_rotation(phi, [s.loading_velocity_m_per_s, 0.0, 0.0]),
            )
            .frictional_boundary(TAG_FRICTIONAL)
            .fault_tangent(skew_rotation(phi, [1.0, 0.0, 0.0]))
            .loading(s.loading());
        Ok(Some(if s.integrator.uses_mass() {
            builder
        } else {
            builder.without_mass()
        }))
    }

    /// A [`SimulationBuilder`](rsf::SimulationBuilder) on `model` with everything the
    /// scene decides (as [`SliderScene::simulation_builder_with_model`]).
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn simulation_builder_with_model(
        &self,
        model: Model<3>,
    ) -> Result<SceneSimulationBuilder<3>> {
        self.validate()?;
        self.slider.check_conditioning(&model)?;
        scene_builder(&self.slider, model)
    }

    /// Builds the simulation with the scene's state law and integrator.
    ///
    /// # Errors
    /// Invalid parameters; assembly and set-up errors.
    pub fn build(&self) -> Result<SceneSimulation<3>> {
        let model = self.build_model()?;
        scene_builder(&self.slider, model)?.build()
    }

    /// As [`build`](Self::build) with a model built (or modified) by the caller.
    ///
    /// # Errors
    /// As [`build`](Self::build).
    pub fn build_with_model(&self, model: Model<3>) -> Result<SceneSimulation<3>> {
        self.simulation_builder_with_model(model)?.build()
    }
}

/// The 3-D slider's run configuration (docs/design.md, "One run configuration"): the
/// fields of [`SliderScene`] and `width_m` (also `--width`), `lateral`, as flags of the
/// program `slider_3d` (whose defaults are [`Slider3dScene::default`]'s), keys of its
/// `--scene` file and Python's keywords of `rsf.slider_3d`.
impl crate::RunConfig for Slider3dScene {
    fn validate(&self) -> Result<()> {
        Slider3dScene::validate(self)
    }

    fn fingerprint(&self) -> Fingerprint {
        Slider3dScene::fingerprint(self)
    }

    fn parse_toml(text: &str) -> Result<Self> {
        Slider3dScene::from_toml(text)
    }
}

/// The 2-D scene's parameters ([`Slider3dScene::slider`]).
impl AsRef<SliderScene> for Slider3dScene {
    fn as_ref(&self) -> &SliderScene {
        &self.slider
    }
}

/// The 2-D scene's parameters ([`Slider3dScene::slider`]).
impl AsMut<SliderScene> for Slider3dScene {
    fn as_mut(&mut self) -> &mut SliderScene {
        &mut self.slider
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toml_fields_of_both_parts_and_unknown_names() {
        let s = Slider3dScene::from_toml("a = 0.02\nlateral = \"plane-strain\"").unwrap();
        assert_eq!(
            (s.slider.a, s.lateral),
            (0.02, LateralBoundary::PlaneStrain)
        );
        assert_eq!(s.width_m, 1.0);
        let e = Slider3dScene::from_toml("widht_m = 2")
            .unwrap_err()
            .to_string();
        assert!(e.contains("widht_m"), "{e}");
        let e = Slider3dScene::from_toml("lateral = \"open\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("open"), "{e}");
        let back = toml::to_string(&s).unwrap();
        assert_eq!(Slider3dScene::from_toml(&back).unwrap(), s);
    }

    /// The 3-D scene's inner solves default to `by-solver`, from a file too; `exact`
    /// survives a round trip (it is written although it is the 2-D default).
    #[test]
    fn inner_solves_default_and_round_trip() {
        assert_eq!(
            Slider3dScene::default().slider.fixed_point_inner_solves,
            InnerSolves::BySolver
        );
        let s = Slider3dScene::from_toml("level = 1").unwrap();
        assert_eq!(s.slider.fixed_point_inner_solves, InnerSolves::BySolver);
        // Every missing field from the 3-D default, the level included.
        assert_eq!(
            Slider3dScene::from_toml("").unwrap(),
            Slider3dScene::default()
        );
        let s = Slider3dScene::from_toml("fixed_point_inner_solves = \"exact\"").unwrap();
        assert_eq!(s.slider.fixed_point_inner_solves, InnerSolves::Exact);
        let back = toml::to_string(&s).unwrap();
        assert_eq!(Slider3dScene::from_toml(&back).unwrap(), s);
        let s = Slider3dScene::from_toml(
            "fixed_point_inner_solves = { inexact = { factor = 0.01, first = false } }",
        )
        .unwrap();
        assert_eq!(
            s.slider.fixed_point_inner_solves,
            InnerSolves::Inexact {
                factor: 0.01,
                first: false
            }
        );
        let back = toml::to_string(&s).unwrap();
        assert_eq!(Slider3dScene::from_toml(&back).unwrap(), s);
    }

    /// The 3-D scene's TNNMG smoothers default to red–black chunks, from a file too, and
    /// reach the solver options; the 2-D scene keeps the lexicographic order and does not
    /// write it, so its files and fingerprints are unchanged, and so is the fingerprint
    /// of a 3-D scene set to lexicographic (the 3-D runs before the default changed) —
    /// which differs from the new default's.
    #[test]
    fn tnnmg_smoother_defaults_round_trip_and_fingerprints() {
        let three = Slider3dScene::default();
        assert_eq!(three.slider.tnnmg_smoother, SmootherOrder::RedBlackChunks);
        assert_eq!(
            three.slider.solver_options().tnnmg.smoother,
            SmootherOrder::RedBlackChunks
        );
        let s = Slider3dScene::from_toml("level = 1").unwrap();
        assert_eq!(s.slider.tnnmg_smoother, SmootherOrder::RedBlackChunks);
        for (text, order) in [
            ("lexicographic", SmootherOrder::Lexicographic),
            ("multicolour", SmootherOrder::MultiColour),
            ("multicolor", SmootherOrder::MultiColour),
            ("red-black-chunks", SmootherOrder::RedBlackChunks),
        ] {
            let s = Slider3dScene::from_toml(&format!("tnnmg_smoother = \"{text}\"")).unwrap();
            assert_eq!(s.slider.tnnmg_smoother, order);
            assert_eq!(s.slider.solver_options().tnnmg.smoother, order);
            let back = toml::to_string(&s).unwrap();
            assert_eq!(Slider3dScene::from_toml(&back).unwrap(), s);
        }
        let e = Slider3dScene::from_toml("tnnmg_smoother = \"red-black\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("tnnmg_smoother"), "{e}");
        // 2-D: lexicographic, not written.
        let two = SliderScene::default();
        assert_eq!(two.tnnmg_smoother, SmootherOrder::Lexicographic);
        assert!(!toml::to_string(&two).unwrap().contains("tnnmg_smoother"));
        // 3-D: the default's fingerprint names the order; lexicographic's does not.
        let mut lexicographic = three.clone();
        lexicographic.slider.tnnmg_smoother = SmootherOrder::Lexicographic;
        assert_eq!(lexicographic.fingerprint().get("tnnmg_smoother"), None);
        assert_eq!(
            three.fingerprint().get("tnnmg_smoother"),
            Some("\"red-black-chunks\"")
        );
        assert_ne!(three.fingerprint(), lexicographic.fingerprint());
    }

    /// The closed-form node count is the built mesh's.
    #[test]
    fn estimated_nodes_are_the_mesh_nodes() {
        for (level, width_m) in [(0, 1.0), (1, 1.0), (1, 2.0), (2, 0.5)] {
            let mut scene = Slider3dScene {
                width_m,
                ..Slider3dScene::default()
            };
            scene.slider.level = level;
            let (nodes, bytes) = scene.estimated_bytes();
            let model = scene.build_model().unwrap();
            assert_eq!(
                nodes,
                model.num_nodes() as f64,
                "level {level}, W {width_m}"
            );
            assert_eq!(bytes, nodes * Slider3dScene::BYTES_PER_NODE);
        }
    }

    #[test]
    fn invalid_width_and_diagonal_are_named() {
        for w in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e9, 1e-300, 9e-4] {
            let s = Slider3dScene {
                width_m: w,
                ..Slider3dScene::default()
            };
            let e = s.build_model().unwrap_err().to_string();
            assert!(e.contains("width_m"), "{w}: {e}");
        }
        let mut s = Slider3dScene::default();
        s.slider.diagonal = Diagonal::Backward;
        assert!(s.validate().unwrap_err().to_string().contains("diagonal"));
    }

    #[test]
    fn coarse_mesh_tags_and_plane_strain_constraints() {
        let mesh = slider_3d_coarse(2.0).unwrap();
        assert_eq!((mesh.num_vertices(), mesh.num_cells()), (6 * 2 * 3, 6 * 10));
        for tag in [TAG_DIRICHLET, TAG_FRICTIONAL, TAG_NEUMANN, TAG_LATERAL] {
            let area: f64 = mesh
                .facets_with_tag(tag)
                .iter()
                .map(|&f| mesh.boundary_facet_measure(f))
                .sum();
            let expected = match tag {
                TAG_DIRICHLET | TAG_FRICTIONAL => 10.0,
                TAG_NEUMANN => 4.0,
                _ => 10.0,
            };
            assert!((area - expected).abs() < 1e-12, "{tag}: {area}");
        }
        let scene = Slider3dScene {
            slider: SliderScene {
                level: 1,
                ..SliderScene::default()
            },
            lateral: LateralBoundary::PlaneStrain,
            ..Slider3dScene::default()
        };
        let m = scene.build_model().unwrap();
        for (p, x) in m.vertices.iter().enumerate() {
            let lateral = x[2] < 1e-9 || x[2] > 1.0 - 1e-9;
            let top = x[1] > 1.0 - 1e-9;
            assert_eq!(m.fixed[3 * p + 2], lateral || top, "node {p} at {x:?}");
        }
    }
}
