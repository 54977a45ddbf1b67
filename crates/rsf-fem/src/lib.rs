//! P1 finite elements for the rate-and-state friction solver `rsf`
//! (Pipping, Sander & Kornhuber, *Variational formulation of rate- and state-dependent
//! friction problems*; see `docs/math.md` §3 for the space discretisation).
//!
//! * [`SimplexMesh`] / [`TriangleMesh`]: vertices (m), connectivity, boundary facets
//!   with tags; [`rectangle`] and the paper's coarse grid [`pipping_slider_coarse`].
//! * [`MeshHierarchy`]: uniform red refinement with scalar and node-major vector P1
//!   prolongations (for multigrid).
//! * [`BoundarySegment`]: Γ_D, Γ_N, Γ_F by tag or predicate; ordered nodes, normals,
//!   [`NodalFrames`] for bilateral contact on slanted boundaries.
//! * [`Assembler`]: consistent mass `M` (ρ), plane-strain stiffness `K` (E, ν),
//!   energy matrix `K + M`, all sharing one CSC pattern; loads [`body_force_load`],
//!   [`traction_load`]; lumped boundary weights [`lumped_weights`].
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

pub use assembly::{
    body_force_load, combine, lumped_weights, spmv_add, traction_load, Assembler, SparseMatrix,
};
pub use boundary::{BoundarySegment, NodalFrames};
pub use cholesky::Cholesky;
pub use constraints::{ConstrainedSystem, Constraints};
pub use element::LinearElasticity;
pub use error::{Error, Result};
pub use hierarchy::{refine_red, vectorize, MeshHierarchy};
pub use mesh::{
    pipping_slider_coarse, rectangle, Diagonal, SimplexMesh, TriangleMesh, TAG_DIRICHLET,
    TAG_FRICTIONAL, TAG_NEUMANN,
};
