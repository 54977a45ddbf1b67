//! What a body is made of: the seam [`Medium`] between the model builder and the
//! constitutive law, isotropic elasticity ([`Material`]) and the antiplane scalar field
//! ([`AntiplaneMaterial`]); several materials by region are
//! [`MaterialRegions`](super::MaterialRegions).

use rsf_fem::{combine, node_columns, Assembler, LinearElasticity, SimplexMesh, SparseMatrix};

use crate::error::{Error, Result};

/// Isotropic linear elastic material (SI units; in 2D plane strain, per unit thickness).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Material {
    /// Young's modulus E (Pa), finite and > 0.
    pub youngs_modulus: f64,
    /// Poisson's ratio ν ∈ (−1, ½).
    pub poisson_ratio: f64,
    /// Density ρ (kg/m³; kg/m² per unit thickness in 2D), finite and > 0.
    pub density: f64,
}

impl Material {
    /// Young's modulus E (Pa), Poisson's ratio ν, density ρ (kg/m³; kg/m² in 2D).
    pub const fn new(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> Self {
        Self {
            youngs_modulus,
            poisson_ratio,
            density,
        }
    }

    /// The material of shear modulus μ (Pa), Poisson's ratio ν and density ρ: Young's
    /// modulus `E = 2μ(1 + ν)` (the SEAS descriptions give μ = ρc_s² and ν). Checked where
    /// [`new`](Self::new)'s values are ([`elasticity`](Self::elasticity)).
    pub fn from_shear_modulus(shear_modulus: f64, poisson_ratio: f64, density: f64) -> Self {
        Self::new(
            2.0 * shear_modulus * (1.0 + poisson_ratio),
            poisson_ratio,
            density,
        )
    }

    /// The elasticity tensor: [`LinearElasticity::isotropic`] (plane strain in 2D).
    ///
    /// # Errors
    /// [`rsf_fem::Error::InvalidYoungsModulus`], [`rsf_fem::Error::InvalidPoissonRatio`].
    pub fn elasticity(&self) -> Result<LinearElasticity> {
        Ok(LinearElasticity::isotropic(
            self.youngs_modulus,
            self.poisson_ratio,
        )?)
    }
}

/// The matrices a [`Medium`] assembles on a mesh.
#[derive(Debug, Clone)]
pub struct MediumMatrices {
    /// Stiffness `K` (`n × n`, `n = C · vertices`, node-major).
    pub stiffness: SparseMatrix,
    /// Mass `M` on the pattern of `K`, if asked for.
    pub mass: Option<SparseMatrix>,
    /// The energy-norm matrix: `K + M` with mass, `K` without.
    pub energy_norm: SparseMatrix,
}

impl MediumMatrices {
    /// The matrices of a body with `stiffness` and, with inertia, its mass and energy
    /// norm `(M, E)`; without, the energy norm is the stiffness.
    pub fn new(stiffness: SparseMatrix, inertia: Option<(SparseMatrix, SparseMatrix)>) -> Self {
        let (mass, energy_norm) = match inertia {
            Some((m, e)) => (Some(m), e),
            None => (None, stiffness.clone()),
        };
        Self {
            stiffness,
            mass,
            energy_norm,
        }
    }

    /// The columns of the nodes with `keep[vertex]` of every matrix, the others emptied
    /// ([`rsf_fem::node_columns`]; the kept columns' rows and bits unchanged).
    ///
    /// # Errors
    /// [`Error::Fem`] if `keep` does not have one flag per node of the matrices.
    pub fn node_columns(&self, keep: &[bool]) -> Result<Self> {
        let columns = |a: &SparseMatrix| node_columns(a, keep).map_err(Error::from);
        Ok(Self {
            stiffness: columns(&self.stiffness)?,
            mass: self.mass.as_ref().map(columns).transpose()?,
            energy_norm: columns(&self.energy_norm)?,
        })
    }
}

/// What the body is made of, for a field of `C` components per vertex on a `D`-dimensional
/// mesh: the seam between [`ModelBuilder`](crate::ModelBuilder) and the constitutive law.
/// [`Material`] (isotropic elasticity, `C = D`) and [`AntiplaneMaterial`] (`C = 1`)
/// implement it; a user's own medium (anisotropic, graded) implements
/// [`assemble`](Self::assemble) with [`rsf_fem::Assembler`].
pub trait Medium<const D: usize, const C: usize> {
    /// Density ρ (kg/m³; kg/m² per unit thickness in 2D) for gravity's body force `ρ g`.
    fn density(&self) -> f64;

    /// The density at `x` (m) for gravity's body force `ρ(x) g` of a heterogeneous body
    /// (e.g. [`MaterialRegions`](crate::model::MaterialRegions)); default
    /// [`density`](Self::density) everywhere.
    fn density_at(&self, x: &[f64; D]) -> f64 {
        let _ = x;
        self.density()
    }

    /// Stiffness, mass (if `with_mass`) and energy norm on `mesh`, all on one pattern.
    ///
    /// # Errors
    /// Invalid material constants; assembly errors.
    fn assemble(&self, mesh: &SimplexMesh<D>, with_mass: bool) -> Result<MediumMatrices>;

    /// The columns of the nodes with `keep[vertex]` (one flag per vertex of `mesh`) of the
    /// matrices of [`assemble`](Self::assemble): `n × n` matrices whose kept columns have
    /// the rows and bits of the whole matrices' and whose other columns are empty (what
    /// one process of several holds, [`ModelBuilder::build_columns`](crate::ModelBuilder::build_columns)).
    /// The default assembles the whole matrices and drops the other columns (the same bits
    /// by construction, the whole matrices' memory for a while); the built-in media assemble
    /// only the cells with a kept vertex ([`rsf_fem::Assembler::on_columns`]).
    ///
    /// # Errors
    /// As [`assemble`](Self::assemble); [`Error::Fem`] if `keep` does not have one flag per
    /// vertex.
    fn assemble_columns(
        &self,
        mesh: &SimplexMesh<D>,
        with_mass: bool,
        keep: &[bool],
    ) -> Result<MediumMatrices> {
        check_keep(mesh, keep)?;
        self.assemble(mesh, with_mass)?.node_columns(keep)
    }

    /// The impedances `(ρc_p, ρc_s)` (Pa·s/m) of the Lysmer–Kuhlemeyer dashpots on
    /// absorbing parts
    /// ([`ModelBuilder::absorbing_boundary`](crate::ModelBuilder::absorbing_boundary); a
    /// scalar field uses `ρc_s` only). Default `None`: a medium that does not know its wave
    /// speeds cannot have absorbing parts ([`Error::BoundaryPart`] from
    /// [`ModelBuilder::build`](crate::ModelBuilder::build)).
    fn impedances(&self) -> Option<[f64; 2]> {
        None
    }

    /// The impedances at the point `x` (m) inside the body: an absorbing facet takes those
    /// at the centroid of its cell, so that a boundary crossing material regions gets each
    /// region's own dashpots. Default [`impedances`](Self::impedances) everywhere.
    fn impedances_at(&self, x: &[f64; D]) -> Option<[f64; 2]> {
        let _ = x;
        self.impedances()
    }
}

impl<const D: usize> Medium<D, D> for Material {
    fn density(&self) -> f64 {
        self.density
    }

    fn assemble(&self, mesh: &SimplexMesh<D>, with_mass: bool) -> Result<MediumMatrices> {
        let elasticity = self.elasticity()?;
        assemble_elastic(mesh, with_mass, None, |_| (self.density, &elasticity))
    }

    fn assemble_columns(
        &self,
        mesh: &SimplexMesh<D>,
        with_mass: bool,
        keep: &[bool],
    ) -> Result<MediumMatrices> {
        let elasticity = self.elasticity()?;
        assemble_elastic(mesh, with_mass, Some(keep), |_| (self.density, &elasticity))
    }

    /// `(√(ρ(λ + 2μ)), √(ρμ))` with the Lamé constants of `E`, `ν` (plane strain in 2D:
    /// the same P-wave modulus `λ + 2μ`).
    fn impedances(&self) -> Option<[f64; 2]> {
        let (e, nu, rho) = (self.youngs_modulus, self.poisson_ratio, self.density);
        let mu = e / (2.0 * (1.0 + nu));
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        Some([(rho * (lambda + 2.0 * mu)).sqrt(), (rho * mu).sqrt()])
    }
}

/// Stiffness, mass (if `with_mass`) and energy norm of an elastic body whose cell `c` has
/// the density and elasticity tensor `material(c)` ([`Material`],
/// [`MaterialRegions`](super::MaterialRegions)); only the columns of the nodes `keep`
/// ([`Medium::assemble_columns`]) if given.
pub(crate) fn assemble_elastic<'m, const D: usize>(
    mesh: &SimplexMesh<D>,
    with_mass: bool,
    keep: Option<&[bool]>,
    material: impl Fn(usize) -> (f64, &'m LinearElasticity),
) -> Result<MediumMatrices> {
    let assembler = match keep {
        Some(keep) => Assembler::on_columns(mesh, keep)?,
        None => Assembler::new(mesh)?,
    };
    let stiffness = assembler.stiffness_by_cell(mesh, |c| material(c).1)?;
    let inertia = with_mass
        .then(|| {
            Ok::<_, Error>((
                assembler.mass_by_cell(mesh, |c| material(c).0)?,
                assembler.energy_by_cell(mesh, &material)?,
            ))
        })
        .transpose()?;
    Ok(MediumMatrices::new(stiffness, inertia))
}

/// A medium for a scalar field `u` (one component per vertex) with energy `½∫μ|∇u|²`: the
/// antiplane (mode III) displacement of an isotropic elastic body in the plane of a 2-D
/// mesh, `u` the displacement out of that plane (SI units; per unit length out of the
/// plane). Stiffness `K_ij = ∫μ∇φ_i·∇φ_j`, mass `∫ρφ_iφ_j`
/// ([`rsf_fem::Assembler::laplace`]). Used by the SCEC SEAS benchmark BP1 (docs/seas-bp1.md).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct AntiplaneMaterial {
    /// Shear modulus μ (Pa), finite and > 0.
    pub shear_modulus: f64,
    /// Density ρ (kg/m³), finite and > 0.
    pub density: f64,
}

impl AntiplaneMaterial {
    /// Shear modulus μ (Pa) and density ρ (kg/m³).
    pub const fn new(shear_modulus: f64, density: f64) -> Self {
        Self {
            shear_modulus,
            density,
        }
    }

    /// The shear wave speed `c_s = √(μ/ρ)` (m/s).
    pub fn shear_wave_speed(&self) -> f64 {
        (self.shear_modulus / self.density).sqrt()
    }
}

impl<const D: usize> Medium<D, 1> for AntiplaneMaterial {
    fn density(&self) -> f64 {
        self.density
    }

    fn assemble(&self, mesh: &SimplexMesh<D>, with_mass: bool) -> Result<MediumMatrices> {
        self.assemble_on(Assembler::scalar(mesh)?, mesh, with_mass)
    }

    fn assemble_columns(
        &self,
        mesh: &SimplexMesh<D>,
        with_mass: bool,
        keep: &[bool],
    ) -> Result<MediumMatrices> {
        self.assemble_on(Assembler::on_columns(mesh, keep)?, mesh, with_mass)
    }

    /// `√(ρμ) = ρc_s` twice (a scalar field has no P wave; only `ρc_s` is used).
    fn impedances(&self) -> Option<[f64; 2]> {
        let z = (self.density * self.shear_modulus).sqrt();
        Some([z, z])
    }
}

impl AntiplaneMaterial {
    /// The matrices on `assembler`'s columns (whole or some nodes').
    fn assemble_on<const D: usize>(
        &self,
        assembler: Assembler<D, 1>,
        mesh: &SimplexMesh<D>,
        with_mass: bool,
    ) -> Result<MediumMatrices> {
        let stiffness = assembler.laplace(mesh, self.shear_modulus)?;
        let inertia = with_mass
            .then(|| {
                let m = assembler.mass(mesh, self.density)?;
                let e = combine(1.0, &m, 1.0, &stiffness).map_err(rsf_fem::Error::from)?;
                Ok::<_, Error>((m, e))
            })
            .transpose()?;
        Ok(MediumMatrices::new(stiffness, inertia))
    }
}

/// [`Error::Fem`] ([`rsf_fem::Error::DimensionMismatch`]) unless `keep` has one flag per
/// vertex of `mesh`.
pub(crate) fn check_keep<const D: usize>(mesh: &SimplexMesh<D>, keep: &[bool]) -> Result<()> {
    if keep.len() == mesh.num_vertices() {
        Ok(())
    } else {
        Err(Error::Fem(rsf_fem::Error::DimensionMismatch {
            what: "kept columns (one flag per vertex)",
            expected: mesh.num_vertices(),
            got: keep.len(),
        }))
    }
}
