//! P1 finite elements for the rate-and-state friction solver `rsf`
//! (Pipping, Sander & Kornhuber, *Variational formulation of rate- and state-dependent
//! friction problems*; see `docs/math.md` §3 for the space discretisation and §10 for
//! three dimensions).
//!
//! Everything is generic over the dimension `D` (triangles for `D = 2`, tetrahedra for
//! `D = 3`) and chosen by it, not by separate 2D/3D types:
//!
//! * [`SimplexMesh`] / [`TriangleMesh`] / [`TetrahedronMesh`]: vertices (m), oriented cells,
//!   boundary facets with tags; structured [`rectangle`] (graded:
//!   [`rectangle_from_coordinates`], [`geometric_grading`], [`geometric_grading_len`], [`symmetric_grading`]), [`cuboid`] (Kuhn tetrahedra; graded: [`cuboid_from_coordinates`]) and
//!   the paper's coarse grid [`pipping_slider_coarse`]; Gmsh MSH 4.1 import
//!   ([`read_gmsh`], [`parse_gmsh`]) with physical groups as tags.
//! * [`MeshHierarchy`]: uniform red refinement ([`refine_red`]; Bey's rule for tetrahedra,
//!   shape regular) with scalar and node-major vector P1 prolongations (for multigrid).
//! * [`BoundaryPart`]: a named set of boundary facets (Γ_D, Γ_N, Γ_F) by tag, predicate or
//!   list, with nodes, lumped weights, outer normals and [`NodalFrames`] (tangents + inward
//!   normal) for bilateral contact; [`BoundarySegment`]: the 2D part ordered along the
//!   boundary.
//! * [`Assembler`]: `C` components per vertex (`C = D` by default; [`Assembler::scalar`]
//!   for scalar fields with the stiffness [`Assembler::laplace`] `μ∇u·∇w`, the antiplane
//!   problem); consistent mass `M` (ρ), stiffness `K` of isotropic elasticity
//!   ([`LinearElasticity`]: E, ν; plane strain in 2D), energy matrix `K + M`, all sharing
//!   one CSC pattern, whole or the columns of some nodes ([`Assembler::on_columns`],
//!   [`node_columns`]); loads [`body_force_load`], [`traction_load`]; lumped boundary
//!   weights [`lumped_weights`].
//! * [`SimplexMesh::split_along`] / [`SimplexMesh::split_along_segment`]: a fault inside
//!   the body cut open into two sides ([`FaultSides`], docs/math.md §15), and the change of
//!   variables to mean and jump at its pairs ([`FaultSides::mean_jump_transform`]); in 3-D
//!   along a surface of mesh triangles (`SimplexMesh::<3>::split_along`,
//!   [`SimplexMesh::split_along_polygon`] for a planar polygon).
//! * [`DofTransform`]: the one interface of a change of variables `u = T u′` (`Tᵀ A T`,
//!   `Tᵀ F`, `T x`, `T⁻¹ x`, `T⁻¹ P`) — [`NodalFrames`], [`MeanJumpTransform`] and their
//!   [`Composition`].
//! * [`Constraints`], [`ConstrainedSystem`], [`Cholesky`]: fixed dofs and sparse
//!   Cholesky with reusable symbolic analysis.
//! * [`ElasticBox`]: an elasticity problem of fixed data on a refined box, the one the
//!   distributed solvers are tested and measured on.
//!
//! Conventions (docs/design.md): vector dofs are node-major (`D·node + component`);
//! matrices are `faer::sparse::SparseColMat<usize, f64>` with both triangles stored.
#![warn(missing_docs)]

mod assembly;
mod bisection;
mod boundary;
mod constraints;
mod dof_transform;
mod elastic_box;
pub mod element;
mod error;
mod frames;
mod geometry;
mod gmsh;
mod hierarchy;
pub mod input_file;
mod loads;
mod mesh;
mod network;
mod octree;
mod part;
mod refine;
mod split;
mod split_surface;
mod split_transform;
mod structured;

pub use assembly::{node_columns, Assembler};
pub use bisection::{BisectionMesh, BisectionReport};
pub use boundary::BoundarySegment;
pub use constraints::{ConstrainedSystem, Constraints};
pub use dof_transform::{Composition, DofTransform};
pub use elastic_box::ElasticBox;
pub use element::LinearElasticity;
pub use error::{Error, Result};
pub use frames::{frame_from_normal, NodalFrames};
pub use gmsh::{
    parse_gmsh, parse_gmsh_with, read_gmsh, read_gmsh_with, GmshMesh, GmshOptions, PhysicalGroup,
};
pub use hierarchy::{vectorize, MeshHierarchy};
pub use loads::{
    body_force_load, body_force_load_components, lumped_weights, traction_load,
    traction_load_components,
};
pub use mesh::{SimplexMesh, TetrahedronMesh, TriangleMesh};
pub use network::{FaultNetwork, Junction, JunctionKind};
pub use octree::{OctreeMesh, OctreeReport};
pub use part::BoundaryPart;
pub use refine::{refine_red, try_refine_red};
pub use rsf_linalg::{combine, quadratic_form, spmv_add, Cholesky, SparseMatrix};
pub use rsf_numeric::normal_component;
pub use split::FaultSides;
pub use split_transform::{JunctionBlocks, MeanJumpTransform, SectorBlocks};
pub use structured::{
    cuboid, cuboid_from_coordinates, cuboid_mirrored, geometric_grading, geometric_grading_len,
    pipping_slider_coarse, rectangle, rectangle_from_coordinates, symmetric_grading, Diagonal,
    KUHN_PATHS, MAX_GRADED_COORDINATES, TAG_DIRICHLET, TAG_FRICTIONAL, TAG_NEUMANN,
};
