//! The builder's setters for the fault: a frictional boundary Γ_F (bilateral contact,
//! nodal frames where it is slanted, an antisymmetry plane) or a fault inside the body (the
//! mesh split along it, mean and jump unknowns, a creeping section).

use super::part::Part;
use super::ModelBuilder;
use crate::model::creep::{CreepRate, PrescribedSlip};
use crate::model::internal::cuts::{split_network_2d, split_network_3d};
use crate::model::internal::FaultCut;

impl<const D: usize> ModelBuilder<D> {
    /// In 3-D, the reference direction of the first tangent `t₁` of the nodal frames on
    /// slanted fault nodes: its projection onto each node's tangent plane (as PyLith's
    /// `ref_dir`; e.g. the loading direction). Where it is (nearly, its projection
    /// `< 10⁻⁶` of its length) normal to a slanted node or a split pair of an internal
    /// fault, [`build`](Self::build) fails with [`rsf_fem::Error::TangentAlongNormal`]
    /// naming the node and its position (it used to take the coordinate axis with the
    /// smallest `|n_k|` there silently; without a tangent that axis is the rule).
    ///
    /// 3-D only: in 1-D and 2-D the tangent is fixed by the normal (`t = (−n_y, n_x)`) and
    /// there is nothing to choose, so [`build`](Self::build) refuses a `fault_tangent`
    /// there with [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `fault_tangent` (rather than ignoring the caller's choice silently).
    pub fn fault_tangent(mut self, direction: [f64; D]) -> Self {
        self.fault.tangent = Some(direction);
        self
    }
}

impl<const D: usize, const C: usize> ModelBuilder<D, C> {
    /// The frictional boundary Γ_F (required unless the fault is inside the body,
    /// [`internal_fault`](ModelBuilder::internal_fault)), with bilateral contact: the normal
    /// velocity component of its nodes is fixed (vector fields; a scalar field's one
    /// component is tangential).
    pub fn frictional_boundary(mut self, part: impl Into<Part<D>>) -> Self {
        self.fault.frictional_boundary = Some(part.into());
        self
    }

    /// Γ_F is a plane of antisymmetry with slip `δ = s·u` (`s = 2`: a fault between two
    /// halves moving oppositely, of which the model is one; default `s = 1`, a body on a
    /// rigid surface). The model's unknown becomes `ũ = s·u` everywhere, so that every
    /// block on Γ_F is the slip (and its norm the slip rate) for friction, state, observers
    /// and outputs: `K̃ = K/s²`, `M̃ = M/s²`, `F̃ = F/s`, weights `w̃ = w/s`, prescribed
    /// velocities `s·v` (they are given for `u`, as usual). With these, the energy, the
    /// friction functional `Σ w̃ ϕ(|ṽ|)` and the radiation damping `Σ w̃ η/2 |ṽ|²` are
    /// those of the half model in `u` (docs/seas-bp1.md);
    /// [`FrictionalBoundary::slip_factor`](crate::model::FrictionalBoundary::slip_factor)
    /// keeps `s`.
    pub fn antisymmetric_fault(mut self, slip_factor: f64) -> Self {
        self.fault.slip_factor = slip_factor;
        self
    }

    /// The largest angle (degrees, in `[0, 180]`) between the outer normals of two
    /// frictional facets meeting at a node (default
    /// [`DEFAULT_MAX_FAULT_KINK_DEGREES`](crate::model::DEFAULT_MAX_FAULT_KINK_DEGREES)); a
    /// node beyond it is a corner ([`Error::FaultCorner`](crate::Error::FaultCorner)),
    /// where no nodal frame is well defined.
    pub fn max_fault_kink(mut self, degrees: f64) -> Self {
        self.fault.max_kink_degrees = degrees;
        self
    }

    /// The creeping section of the internal fault: the split pairs at positions `x` (m)
    /// with `inside(x)` slip at the prescribed rate `slip_rate · g(t)` (m/s; `g` the loading
    /// history) instead of by friction — along the pair's tangent, in 2-D the fault's
    /// direction turned by 180° (`t = −d`, `d` from the first point to the last; the same
    /// sign as [`StepView::slip`](crate::StepView::slip)), in 3-D the frame's first tangent
    /// `t₁` ([`internal_fault_polygon`](ModelBuilder::internal_fault_polygon)), with the
    /// second tangential component fixed at 0 (a vector of prescribed direction; other
    /// directions, a rake or a rate per node: [`internal_creep_at`](Self::internal_creep_at)).
    /// Used for a fault loaded by steady creep below the seismogenic depth (SEAS BP3). Pairs
    /// whose two sides are both fully fixed by Dirichlet parts (each side's far-field
    /// motion where the fault meets a far boundary) are prescribed too. Prescribed pairs are
    /// not frictional nodes.
    ///
    /// # Errors (at `build`)
    /// As [`internal_fault`](Self::internal_fault);
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `internal_creep`
    /// for a non-finite rate or without an internal fault.
    pub fn internal_creep(
        self,
        inside: impl Fn(&[f64; D]) -> bool + 'static,
        slip_rate: f64,
    ) -> Self {
        self.internal_creep_at(move |x| inside(x).then_some(CreepRate::InFrame([slip_rate, 0.0])))
    }

    /// The creeping section of the internal fault with a slip-rate vector per pair: the
    /// pair at position `x` (m) slips at `rate(x)` times the loading history `g(t)` where
    /// it is `Some` ([`CreepRate`]: components in the pair's frame, a rake, or a Cartesian
    /// vector tangent to the fault), by friction where it is `None`. Every tangential
    /// component of a creeping pair is fixed (docs/math.md "Slip as a vector").
    ///
    /// ```
    /// use rsf::fem::cuboid;
    /// use rsf::model::CreepRate;
    /// use rsf::{Material, ModelBuilder, Part};
    /// // The plane x = 0.5 of a unit cube: its upper half creeps along (0, cos 30°, sin 30°).
    /// let cube = cuboid([0.0; 3], [1.0; 3], [3, 3, 3])?;
    /// let v = 1e-9;
    /// let model = ModelBuilder::refined(cube, 1)?
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("left", |x| x[0] < 1e-9), [0.0; 3])
    ///     .internal_fault_polygon(
    ///         "fault",
    ///         &[[0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, 1.0, 1.0], [0.5, 0.0, 1.0]],
    ///     )
    ///     .internal_creep_at(move |x| {
    ///         let rake = 30f64.to_radians();
    ///         (x[2] > 0.6).then_some(CreepRate::Cartesian([0.0, v * rake.cos(), v * rake.sin()]))
    ///     })
    ///     .build()?;
    /// // 5 × 5 fault vertices, the 5 at z = 0.75 and the 5 at z = 1 creep.
    /// assert_eq!(model.frictional_boundary.len(), 15);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    ///
    /// # Errors (at `build`)
    /// As [`internal_creep`](Self::internal_creep);
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `internal_creep`
    /// for a rate [`CreepRate`] refuses (a second tangential component in 2-D, a Cartesian
    /// rate with a normal part or on a scalar field), naming the position.
    pub fn internal_creep_at(
        mut self,
        rate: impl Fn(&[f64; D]) -> Option<CreepRate<D>> + 'static,
    ) -> Self {
        self.fault.creep = Some(Box::new(rate));
        self
    }

    /// A kinematic source on the fault inside the body: the split pairs at positions `x`
    /// (m) where `slip(x)` is `Some` have their jump `u⁺ − u⁻` prescribed to that slip
    /// (m; [`PrescribedSlip`]: in the pair's frame, a rake, or a Cartesian vector tangent
    /// to the fault) — every tangential component fixed, a displacement, not a rate. The
    /// builder's initial equilibrium is then the static problem of the dislocation:
    /// `K u₀ = F` on the free dofs with these jumps and the Dirichlet data
    /// ([`dirichlet_displacement`](Self::dirichlet_displacement) for held values), i.e.
    /// [`Model::initial_displacement`](crate::Model::initial_displacement) is the
    /// displacement of the slip (in the model's unknowns;
    /// [`Model::to_cartesian`](crate::Model::to_cartesian) gives the sides' values).
    /// Such pairs are not frictional nodes and do not slip further (velocity 0, or the
    /// rate of [`internal_creep_at`](Self::internal_creep_at) where it also gives one).
    ///
    /// A fault whose every pair is prescribed builds a model without frictional nodes
    /// (`model.frictional_boundary` empty): a static problem, which a simulation refuses
    /// ([`Error::NoFrictionalNode`](crate::Error::NoFrictionalNode)).
    ///
    /// **The rim.** A rim of the fault inside the body is a shared tip (one vertex, no
    /// jump): the slip of the model is the prescribed one at the pairs and ramps linearly
    /// to 0 over the last cell before the rim — the fault's moment is that of the
    /// rectangle shrunk by half a cell on each inner edge (docs/faults-inside.md,
    /// "A prescribed slip"). Where the fault meets the outer boundary (a free surface) the
    /// vertices are split and the slip reaches the edge.
    ///
    /// ```
    /// use rsf::fem::cuboid;
    /// use rsf::model::PrescribedSlip;
    /// use rsf::{Material, ModelBuilder, Part};
    /// // A unit cube cut through by the plane x = 0.5, every pair slipping 1 mm along y.
    /// let cube = cuboid([0.0; 3], [1.0; 3], [5, 5, 5])?;
    /// let model = ModelBuilder::new(cube)
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .without_mass()
    ///     .dirichlet(Part::predicate("left", |x| x[0] < 1e-9), [0.0; 3])
    ///     .internal_fault_polygon(
    ///         "fault",
    ///         &[[0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, 1.0, 1.0], [0.5, 0.0, 1.0]],
    ///     )
    ///     .internal_slip_at(|_| Some(PrescribedSlip::Cartesian([0.0, 1e-3, 0.0])))
    ///     .build()?;
    /// // A kinematic source only: no frictional node.
    /// assert!(model.frictional_boundary.is_empty());
    /// // The polygon's normal is +x (right-hand rule): the plus side x > 0.5 moves rigidly
    /// // by the slip, the clamped left half not at all.
    /// let u = model.to_cartesian(&model.initial_displacement)?;
    /// let right = model.nearest_node(&[1.0, 0.5, 0.5])?;
    /// let left = model.nearest_node(&[0.25, 0.5, 0.5])?;
    /// assert!((u[3 * right + 1] - 1e-3).abs() < 1e-12 && u[3 * left + 1].abs() < 1e-12);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    ///
    /// # Errors (at `build`)
    /// As [`internal_creep_at`](Self::internal_creep_at), named `internal_slip`: without
    /// an internal fault, a slip [`PrescribedSlip`] refuses (a second tangential component
    /// in 2-D, a Cartesian slip with a normal part or on a scalar field), naming the
    /// position; a slip at a pair whose two sides are both held by Dirichlet parts (their
    /// data give its jump).
    pub fn internal_slip_at(
        mut self,
        slip: impl Fn(&[f64; D]) -> Option<PrescribedSlip<D>> + 'static,
    ) -> Self {
        self.fault.slip = Some(Box::new(slip));
        self
    }
}

impl<const C: usize> ModelBuilder<2, C> {
    /// A fault inside the body along the straight segment `from` → `to` (m), named `name`:
    /// at [`build`](Self::build) the finest mesh is cut open along its
    /// edges on the segment
    /// ([`SimplexMesh::split_along_segment`](rsf_fem::SimplexMesh::split_along_segment): a
    /// node inside the body at an end is a shared tip, an end on the outer boundary is
    /// split; the faces are tagged `{name}_minus` and `{name}_plus`), and the model is
    /// written in the mean–jump unknowns of the split pairs
    /// ([`InternalFault`](crate::model::InternalFault), docs/math.md §15): Γ_F is the
    /// pairs' minus nodes, the slip is the jump's tangential component (the normal one is
    /// tied for a vector field: no opening), the weights are the minus face's, the friction
    /// and state laws see the slip exactly as on a boundary fault. Every coarser level of a
    /// hierarchy that resolves the segment is split too, and its prolongation interpolates
    /// each vertex from the coarse vertices on its own side, so the coarse spaces of
    /// multigrid can slip (levels too coarse to resolve the segment stay continuous; the
    /// finest prolongation is `T⁻¹ P`). Outputs at split vertices
    /// ([`StepView::displacement`](crate::observe::StepView::displacement), VTU frames) are
    /// Cartesian.
    ///
    /// **Several faults.** Call it (or [`internal_fault_polyline`](Self::internal_fault_polyline))
    /// once per fault, each with its own name: the faults form a network cut at once
    /// ([`SimplexMesh::split_along_network`](rsf_fem::SimplexMesh::split_along_network)) —
    /// disjoint (stepovers, parallel strands), one ending on another that goes on through
    /// the vertex (a branch), or two crossing — and Γ_F is every fault's slip nodes, each
    /// knowing its fault ([`FrictionalBoundary::fault_names`](crate::model::FrictionalBoundary::fault_names));
    /// per-fault laws and states through
    /// [`SimulationBuilder::friction_on_faults`](crate::SimulationBuilder::friction_on_faults)
    /// and its siblings (docs/fault-networks.md, docs/math.md §16). A
    /// [`frictional_boundary`](Self::frictional_boundary) may be given beside them (e.g.
    /// the base of a block cut by faults): its nodes are frictional too, after the faults'.
    ///
    /// # Errors (at `build`)
    /// The splitting's errors (e.g. a segment the mesh does not resolve, one lying on the
    /// outer boundary; faults meeting otherwise than in a branch or a crossing,
    /// [`rsf_fem::Error::FaultJunctionUnsupported`]);
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) with a frictional
    /// boundary touching a fault, an [`antisymmetric_fault`](Self::antisymmetric_fault),
    /// Dirichlet parts fixing only some components of a split pair's two sides (their
    /// Cartesian data would mix the mean and the jump), or fixing both sides with
    /// velocities that open the fault. A pair whose two sides are fully fixed is prescribed
    /// and not a frictional node ([`internal_creep`](Self::internal_creep)).
    ///
    /// ```
    /// use rsf::fem::{rectangle, Diagonal};
    /// use rsf::{Material, ModelBuilder, Part};
    /// // A 2 m square sheared by its top and bottom, a fault inside from (0, −0.5) to (0, 0.5).
    /// let block = rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward)?;
    /// let model = ModelBuilder::refined(block, 1)?
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
    ///     .dirichlet(Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9), [-1e-4, 0.0])
    ///     .internal_fault("fault", [0.0, -0.5], [0.0, 0.5])
    ///     .build()?;
    /// // 9 fault nodes on the fine mesh: 2 shared tips, 7 split pairs (the slipping nodes).
    /// assert_eq!(model.frictional_boundary.len(), 7);
    /// assert_eq!(model.num_nodes(), 17 * 17 + 7);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    pub fn internal_fault(self, name: &str, from: [f64; 2], to: [f64; 2]) -> Self {
        self.internal_fault_polyline(name, &[from, to])
    }

    /// As [`internal_fault`](Self::internal_fault) for a fault of straight pieces
    /// `points[0] → points[1] → …` (m): a kinked fault, or a curved one given by the
    /// vertices of its mesh edges in order (e.g. a Gmsh physical curve's,
    /// [`GmshMesh::interior_polyline`](rsf_fem::GmshMesh::interior_polyline)). Each piece
    /// must be resolved by mesh edges
    /// ([`SimplexMesh::split_along_polyline`](rsf_fem::SimplexMesh::split_along_polyline));
    /// the slip's direction follows the fault from `points[0]`, the plus side on the left.
    ///
    /// # Errors (at `build`)
    /// As [`internal_fault`](Self::internal_fault); fewer than two points, a polyline
    /// running back over or crossing itself.
    ///
    /// ```
    /// use rsf::fem::{rectangle, Diagonal};
    /// use rsf::{Material, ModelBuilder, Part};
    /// // A fault kinked at (0, 0): from (−0.5, −0.5) up to (0, 0), then straight up.
    /// let block = rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward)?;
    /// let model = ModelBuilder::refined(block, 1)?
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
    ///     .dirichlet(Part::predicate("bottom", |x| x[1] < -1.0 + 1e-9), [-1e-4, 0.0])
    ///     .internal_fault_polyline("fault", &[[-0.5, -0.5], [0.0, 0.0], [0.0, 0.5]])
    ///     .build()?;
    /// // 4 + 4 fine edges: 9 fault nodes, 2 shared tips.
    /// assert_eq!(model.frictional_boundary.len(), 7);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    pub fn internal_fault_polyline(mut self, name: &str, points: &[[f64; 2]]) -> Self {
        self.fault.internal.push(FaultCut::polyline(name, points));
        self.fault.network_split = Some(split_network_2d::<C>);
        self
    }
}

impl<const C: usize> ModelBuilder<3, C> {
    /// A fault inside a 3-D body on the convex planar polygon `corners` (m, at least three,
    /// in order around it), named `name` — once per fault: several disjoint faults form a
    /// network, as in 2-D ([`internal_fault`](ModelBuilder::internal_fault); in 3-D faults
    /// may not share a vertex, [`rsf_fem::Error::FaultJunctionUnsupported`]): at [`build`](Self::build) the
    /// finest mesh is cut open along its faces on the polygon
    /// ([`SimplexMesh::split_along_polygon`](rsf_fem::SimplexMesh::split_along_polygon): a
    /// fault vertex whose cells the fault does not separate — its rim inside the body — is
    /// a shared tip, a vertex where the fault meets the outer boundary (a free surface) is
    /// split; the faces are tagged `{name}_minus` and `{name}_plus`), and the model is
    /// written in the mean–jump unknowns of the split pairs as in 2-D
    /// ([`internal_fault`](ModelBuilder::internal_fault), docs/math.md §15). The fault's
    /// normal `n` is the polygon's by the right-hand rule of the corners' order; it points
    /// from the minus into the plus side. Each pair's frame is `(t₁, t₂, −n)` with `n` the
    /// area-weighted mean of the adjacent faces' normals and `t₁` the projection of
    /// [`fault_tangent`](Self::fault_tangent) (default: the axis with the smallest
    /// `|n_k|`): the jump's first two components are the slip (friction acts on them as on
    /// a 3-D boundary fault, the creeping section of
    /// [`internal_creep`](ModelBuilder::internal_creep) prescribes its `t₁` component), the
    /// third is tied (no opening). Every coarser level of a hierarchy that resolves the
    /// polygon is split too, as in 2-D.
    ///
    /// **The mesh must resolve the polygon**: its faces must tile it. A Kuhn grid
    /// ([`cuboid`](rsf_fem::cuboid), [`cuboid_from_coordinates`](rsf_fem::cuboid_from_coordinates))
    /// resolves the grid planes `x_i = const` and, where its boxes are cubes, the 45°
    /// planes `x_i − x_j = const` through its vertices (not `x_i + x_j = const`); a graded
    /// [`BisectionMesh`](rsf_fem::BisectionMesh) those of its root grid; other dips need a
    /// mesh made for them (Gmsh, [`internal_fault_faces`](Self::internal_fault_faces)).
    ///
    /// **The rim.** A rim inside the body is a shared tip (one vertex, no jump): the slip —
    /// friction's or a prescribed one ([`internal_slip_at`](ModelBuilder::internal_slip_at))
    /// — ramps linearly to 0 over the last cell before it, so the fault acts as the polygon
    /// shrunk by half a cell on each buried edge (the same moment; docs/faults-inside.md
    /// "A prescribed slip"). Where the polygon meets the outer boundary its vertices are
    /// split and the slip reaches the edge.
    ///
    /// # Errors (at `build`)
    /// [`Error::Fem`](crate::Error::Fem) with the splitting's errors (a polygon the mesh
    /// does not resolve, [`rsf_fem::Error::FaultSurfaceNotResolved`]; fewer than three or
    /// non-coplanar corners; a fault face on the outer boundary);
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `fault_tangent`
    /// for a non-finite or zero tangent, `dirichlet` for a split vertex with only some
    /// components fixed, `internal_fault` for levels not nested along the fault.
    ///
    /// ```
    /// use rsf::fem::cuboid;
    /// use rsf::{Material, ModelBuilder, Part};
    /// // A unit cube cut through by the plane x = 0.5: every fault vertex is split.
    /// let cube = cuboid([0.0; 3], [1.0; 3], [3, 3, 3])?;
    /// let model = ModelBuilder::refined(cube, 1)?
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .dirichlet(Part::predicate("left", |x| x[0] < 1e-9), [0.0, -1e-4, 0.0])
    ///     .dirichlet(Part::predicate("right", |x| x[0] > 1.0 - 1e-9), [0.0, 1e-4, 0.0])
    ///     .internal_fault_polygon(
    ///         "fault",
    ///         &[[0.5, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, 1.0, 1.0], [0.5, 0.0, 1.0]],
    ///     )
    ///     .build()?;
    /// // The fine level has 5 × 5 fault vertices, all split.
    /// assert_eq!(model.frictional_boundary.len(), 25);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    pub fn internal_fault_polygon(mut self, name: &str, corners: &[[f64; 3]]) -> Self {
        self.fault.internal.push(FaultCut::polygon(name, corners));
        self.fault.network_split = Some(split_network_3d::<C>);
        self
    }

    /// As [`internal_fault_polygon`](Self::internal_fault_polygon) for a fault given as
    /// triangles of the coarsest mesh (vertex indices of the hierarchy's level 0, any
    /// orientation: the first face's right-hand-rule normal points from the minus into the
    /// plus side, [`SimplexMesh::split_along`](rsf_fem::SimplexMesh::split_along)) — any
    /// surface of mesh faces, curved or kinked, e.g. a Gmsh physical surface inside the
    /// body ([`GmshMesh::interior_facets`](rsf_fem::GmshMesh::interior_facets) read with
    /// `interior_facets: true`). Every level of the hierarchy is split: a finer level's
    /// fault is the four children of each face of the level below (a curved fault stays the
    /// piecewise-planar surface of its coarse faces, as a 2-D fault is the polyline of its
    /// coarse edges).
    ///
    /// # Errors (at `build`)
    /// As [`internal_fault_polygon`](Self::internal_fault_polygon), with the face errors of
    /// [`SimplexMesh::split_along`](rsf_fem::SimplexMesh::split_along) (a face not in the
    /// mesh or on its boundary, three faces at an edge, a non-orientable or disconnected
    /// set, sides not separated).
    pub fn internal_fault_faces(mut self, name: &str, faces: &[[usize; 3]]) -> Self {
        self.fault.internal.push(FaultCut::faces(name, faces));
        self.fault.network_split = Some(split_network_3d::<C>);
        self
    }
}
