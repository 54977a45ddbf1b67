//! P1 finite elements for the rate-and-state friction solver `rsf`
//! (Pipping, Sander & Kornhuber, *Variational formulation of rate- and state-dependent
//! friction problems*; see `docs/math.md` §3 for the space discretisation and §10 for
//! three dimensions).
//!
//! Everything is generic over the dimension `D` (triangles for `D = 2`, tetrahedra for
//! `D = 3`) and chosen by it, not by separate 2D/3D types:
//!
//! * [`SimplexMesh`] / [`TriangleMesh`] / [`TetrahedronMesh`]: vertices (m), oriented cells,
//!   boundary facets with tags; structured [`rectangle`], [`cuboid`] (Kuhn tetrahedra) and
//!   the paper's coarse grid [`pipping_slider_coarse`].
//! * [`MeshHierarchy`]: uniform red refinement ([`refine_red`]; Bey's rule for tetrahedra,
//!   shape regular) with scalar and node-major vector P1 prolongations (for multigrid).
//! * [`BoundarySegment`]: Γ_D, Γ_N, Γ_F by tag or predicate; ordered nodes, normals,
//!   [`NodalFrames`] for bilateral contact on slanted boundaries (2D).
//! * [`Assembler`]: consistent mass `M` (ρ), plane-strain stiffness `K` (E, ν),
//!   energy matrix `K + M`, all sharing one CSC pattern; loads [`body_force_load`],
//!   [`traction_load`] (2D); lumped boundary weights [`lumped_weights`].
//! * [`Constraints`], [`ConstrainedSystem`], [`Cholesky`]: fixed dofs and sparse
//!   Cholesky with reusable symbolic analysis.
//!
//! Conventions (docs/design.md): vector dofs are node-major (`D·node + component`);
//! matrices are `faer::sparse::SparseColMat<usize, f64>` with both triangles stored.
#![warn(missing_docs)]

mod assembly;
mod boundary;
mod cholesky;
mod constraints;
pub mod element;
mod error;
mod geometry;
mod hierarchy;
mod mesh;
mod refine;
mod structured;

pub use assembly::{
    body_force_load, combine, lumped_weights, spmv_add, traction_load, Assembler, SparseMatrix,
};
pub use boundary::{BoundarySegment, NodalFrames};
pub use cholesky::Cholesky;
pub use constraints::{ConstrainedSystem, Constraints};
pub use element::LinearElasticity;
pub use error::{Error, Result};
pub use hierarchy::{vectorize, MeshHierarchy};
pub use mesh::{SimplexMesh, TetrahedronMesh, TriangleMesh};
pub use refine::{refine_red, try_refine_red};
pub use structured::{
    cuboid, pipping_slider_coarse, rectangle, Diagonal, TAG_DIRICHLET, TAG_FRICTIONAL, TAG_NEUMANN,
};
