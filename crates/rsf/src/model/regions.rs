//! A body made of several isotropic elastic materials: regions of cells chosen by their
//! centroids (e.g. the paper's block on an elastic base, a soft layer over stiff rock).

use rsf_fem::{LinearElasticity, SimplexMesh};

use super::medium::{assemble_elastic, Material, Medium, MediumMatrices};
use crate::error::{invalid, Result};

/// Selects a region's cells by their centroid (m).
pub type CellPredicate<const D: usize> = Box<dyn Fn(&[f64; D]) -> bool>;

/// A heterogeneous elastic body: a background [`Material`] and named regions, each a
/// [`Material`] on the cells whose centroid satisfies its predicate (the first region that
/// matches wins; cells no region selects are the background). A [`Medium`] for
/// [`ModelBuilder::material`](crate::ModelBuilder::material): the stiffness, mass and
/// energy norm are assembled cell by cell with each cell's material
/// ([`rsf_fem::Assembler::stiffness_by_cell`] and its kin); gravity's body force uses the density of the
/// region containing the point ([`Medium::density_at`]).
///
/// Regions follow mesh cells: an interface that is not a union of cell edges is
/// resolved to the nearest cells (by centroid), so put material interfaces on mesh edges.
///
/// ```
/// use rsf::fem::{rectangle, Diagonal};
/// use rsf::model::MaterialRegions;
/// use rsf::{Material, ModelBuilder, Part};
/// // A 1 m block (y > 0) on a base 100× stiffer (y < 0), pushed at its top.
/// let mesh = rectangle([0.0, -1.0], [1.0, 2.0], 5, 9, Diagonal::Forward)?;
/// let rock = Material::new(5e7, 0.3, 5e3);
/// let base = Material::new(5e9, 0.3, 5e3);
/// let medium = MaterialRegions::new(rock).region("base", |x| x[1] < 0.0, base);
/// let model = ModelBuilder::new(mesh)
///     .material(medium)
///     .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
///     .dirichlet(Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9), [0.0, 0.0])
///     .internal_fault("interface", [0.0, 0.0], [1.0, 0.0])
///     .build()?;
/// assert_eq!(model.frictional_boundary.len(), 5);
/// # Ok::<(), rsf::Error>(())
/// ```
pub struct MaterialRegions<const D: usize> {
    background: Material,
    regions: Vec<(String, CellPredicate<D>, Material)>,
}

impl<const D: usize> std::fmt::Debug for MaterialRegions<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let regions: Vec<(&str, &Material)> = self
            .regions
            .iter()
            .map(|(n, _, m)| (n.as_str(), m))
            .collect();
        f.debug_struct("MaterialRegions")
            .field("background", &self.background)
            .field("regions", &regions)
            .finish()
    }
}

impl<const D: usize> MaterialRegions<D> {
    /// A body of `background` everywhere (add regions with [`region`](Self::region)).
    pub fn new(background: Material) -> Self {
        Self {
            background,
            regions: Vec::new(),
        }
    }

    /// The cells whose centroid satisfies `cells` are of `material` (unless an earlier
    /// region took them); `name` appears in errors.
    pub fn region(
        mut self,
        name: &str,
        cells: impl Fn(&[f64; D]) -> bool + 'static,
        material: Material,
    ) -> Self {
        self.regions
            .push((name.to_string(), Box::new(cells), material));
        self
    }

    /// The material at `x` (m): the first region whose predicate holds, else the
    /// background.
    pub fn material_at(&self, x: &[f64; D]) -> &Material {
        self.regions
            .iter()
            .find(|(_, inside, _)| inside(x))
            .map_or(&self.background, |(_, _, m)| m)
    }

    /// Each material's elasticity tensor, background first, the region's name in the
    /// error of an invalid one.
    fn elasticities(&self) -> Result<Vec<LinearElasticity>> {
        std::iter::once(("background", &self.background))
            .chain(self.regions.iter().map(|(n, _, m)| (n.as_str(), m)))
            .map(|(name, m)| {
                if !(m.density.is_finite() && m.density > 0.0) {
                    return Err(invalid(
                        "density",
                        format!(
                            "{} kg/m³ in region `{name}`: must be finite and > 0",
                            m.density
                        ),
                    ));
                }
                m.elasticity()
                    .map_err(|e| invalid("material", format!("region `{name}`: {e}")))
            })
            .collect()
    }

    /// Per cell of `mesh`: the index into [`elasticities`](Self::elasticities) and the
    /// density.
    fn cell_materials(&self, mesh: &SimplexMesh<D>) -> Vec<(usize, f64)> {
        (0..mesh.num_cells())
            .map(|c| {
                let cell = mesh.cell(c);
                let centroid: [f64; D] = std::array::from_fn(|k| {
                    cell.iter().map(|&p| mesh.vertices()[p][k]).sum::<f64>() / (D + 1) as f64
                });
                self.regions
                    .iter()
                    .position(|(_, inside, _)| inside(&centroid))
                    .map_or((0, self.background.density), |r| {
                        (r + 1, self.regions[r].2.density)
                    })
            })
            .collect()
    }
}

impl<const D: usize> Medium<D, D> for MaterialRegions<D> {
    /// The background's density (gravity uses [`density_at`](Medium::density_at)).
    fn density(&self) -> f64 {
        self.background.density
    }

    fn density_at(&self, x: &[f64; D]) -> f64 {
        self.material_at(x).density
    }

    fn assemble(&self, mesh: &SimplexMesh<D>, with_mass: bool) -> Result<MediumMatrices> {
        let elasticities = self.elasticities()?;
        let cells = self.cell_materials(mesh);
        assemble_elastic(mesh, with_mass, None, |c| {
            (cells[c].1, &elasticities[cells[c].0])
        })
    }

    fn assemble_columns(
        &self,
        mesh: &SimplexMesh<D>,
        with_mass: bool,
        keep: &[bool],
    ) -> Result<MediumMatrices> {
        let elasticities = self.elasticities()?;
        let cells = self.cell_materials(mesh);
        assemble_elastic(mesh, with_mass, Some(keep), |c| {
            (cells[c].1, &elasticities[cells[c].0])
        })
    }

    /// The materials' common impedances; `None` if the regions' impedances differ (each
    /// absorbing facet then takes its own region's, [`impedances_at`](Medium::impedances_at)).
    fn impedances(&self) -> Option<[f64; 2]> {
        let z = |m: &Material| <Material as Medium<D, D>>::impedances(m);
        let first = z(&self.background)?;
        self.regions
            .iter()
            .all(|(_, _, m)| z(m) == Some(first))
            .then_some(first)
    }

    /// The impedances of the material at `x` (the region whose predicate holds there, else
    /// the background), as cells are assigned by their centroids.
    fn impedances_at(&self, x: &[f64; D]) -> Option<[f64; 2]> {
        <Material as Medium<D, D>>::impedances(self.material_at(x))
    }
}
