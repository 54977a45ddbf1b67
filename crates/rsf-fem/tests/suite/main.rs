//! The integration tests of `rsf-fem`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-fem --test suite [module::test]`.

mod common;

mod assembly;
mod assembly3d;
mod bisection;
mod columns;
mod convergence;
mod convergence3d;
mod edge_dislocation;
mod gmsh;
mod mesh;
mod mesh3d;
mod network;
mod octree;
mod parts;
mod scalar;
mod split;
mod split_surface;
mod split_transform;
