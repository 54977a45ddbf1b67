//! Why a [`HalfSpaceOperator`](super::HalfSpaceOperator) cannot be built on a model.

/// Why a [`HalfSpaceOperator`](super::HalfSpaceOperator) cannot be built on a model: each names the node (fault
/// index `k` into `model.frictional_boundary.nodes` and its vertex id) or the element
/// that does not fit, and says what to change.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum HalfSpaceOperatorError {
    /// [`HalfSpaceOperator::fault_alone`](super::HalfSpaceOperator::fault_alone) on a model that is not a fault alone (it has a
    /// stiffness, a fault inside the body or nodal frames).
    #[error(
        "the model is not a fault alone (it has a stiffness, a fault inside the body or nodal \
         frames): build it with Model::fault_only, or use HalfSpaceOperator::new for a \
         fault inside a body"
    )]
    NotAlone,
    /// The model has no fault inside the body (`Model::internal_fault` is `None`).
    #[error(
        "the model has no internal fault: build it with ModelBuilder::internal_fault_polygon \
         (a fault on the model's boundary is not supported by the half-space operator)"
    )]
    NoInternalFault,
    /// A frictional node is not one of the internal fault's split pairs.
    #[error(
        "frictional node {node} (vertex {vertex}) is not a split pair's minus vertex of the \
         internal fault"
    )]
    NotAPair {
        /// Fault index.
        node: usize,
        /// Vertex id.
        vertex: usize,
    },
    /// A frictional node's free components are not exactly its two tangential slip
    /// components (a Dirichlet condition on the fault, or a free normal jump).
    #[error(
        "frictional node {node} (vertex {vertex}) has free components {free:?}; the \
         half-space operator needs the two tangential slip components free and the normal \
         one tied (no Dirichlet condition on the fault)"
    )]
    Components {
        /// Fault index.
        node: usize,
        /// Vertex id.
        vertex: usize,
        /// Which of the node's three components (t₁, t₂, normal) are free.
        free: [bool; 3],
    },
    /// The fault has fewer than two nodes along one direction or none at all.
    #[error("the fault has {nodes} frictional node(s) in a single row: no grid spacing to take")]
    TooFewNodes {
        /// Frictional nodes.
        nodes: usize,
    },
    /// The fault is not planar: a node's normal or position leaves the plane of the first
    /// node.
    #[error(
        "frictional node {node} (vertex {vertex}) at {position:?} is not in the plane of \
         node 0 (normal {normal:?}; distance or normal change {distance:e} m or rad): the \
         half-space operator is for planar faults"
    )]
    NotPlanar {
        /// Fault index.
        node: usize,
        /// Vertex id.
        vertex: usize,
        /// Its position (m).
        position: [f64; 3],
        /// The plane's unit normal (node 0's).
        normal: [f64; 3],
        /// The offset from the plane (m) or the angle between the normals (rad).
        distance: f64,
    },
    /// A node is not at the centre of an element of the regular grid.
    #[error(
        "frictional node {node} (vertex {vertex}) at {position:?} is not at an element \
         centre of the regular {spacing:?} m grid of the fault's nodes (off by {offset:e} \
         m): the half-space operator needs the fault's nodes on a regular grid (uniform \
         spacing on the fault)"
    )]
    NotAtCentre {
        /// Fault index.
        node: usize,
        /// Vertex id.
        vertex: usize,
        /// Its position (m).
        position: [f64; 3],
        /// The grid's spacing along strike and along dip (m).
        spacing: [f64; 2],
        /// Distance from the nearest element centre (m), or 0 if that centre has another
        /// node already.
        offset: f64,
    },
    /// An element of the grid spanned by the nodes has no node at its centre (the nodes
    /// do not fill a rectangle).
    #[error(
        "element ({i_strike}, {i_dip}) of the {n_strike} × {n_dip} grid, centre {centre:?} \
         m, has no frictional node: the half-space operator needs the fault's interior \
         nodes to fill a rectangle"
    )]
    ElementWithoutNode {
        /// Its column along strike.
        i_strike: usize,
        /// Its row down dip (0 at the top).
        i_dip: usize,
        /// Elements along strike.
        n_strike: usize,
        /// Elements along dip.
        n_dip: usize,
        /// Its centre in the model's coordinates (m).
        centre: [f64; 3],
    },
    /// A node's cell reaches above the free surface: a fault breaking the surface, whose
    /// split nodes on the surface would need half cells. Not supported.
    #[error(
        "frictional node {node} (vertex {vertex}) at {position:?}: its cell reaches \
         {above:e} m above the free surface z = {surface} m; surface-breaking faults (split \
         nodes on the surface, half cells) are not supported by the half-space operator — \
         bury the fault, or raise HalfSpaceOptions::surface"
    )]
    SurfaceBreaking {
        /// Fault index.
        node: usize,
        /// Vertex id.
        vertex: usize,
        /// Its position (m).
        position: [f64; 3],
        /// The free surface's z (m).
        surface: f64,
        /// How far the top of the node's cell is above it (m).
        above: f64,
    },
    /// A fault alone with another number of frictional nodes than the element set has
    /// elements ([`ElementOperator::fault_alone`](super::ElementOperator::fault_alone)).
    #[error(
        "the fault alone has {nodes} frictional nodes and the element set {elements} \
         elements: one node per element, in element order (fault_alone_model)"
    )]
    ElementCount {
        /// Frictional nodes.
        nodes: usize,
        /// Elements.
        elements: usize,
    },
    /// A frictional node is not at the centre of an element (of its own, for a fault
    /// alone), or at one that has a node already (`offset` 0).
    #[error(
        "frictional node {node} (vertex {vertex}) at {position:?} is {offset:e} m from the \
         nearest free element centre: every node must sit at the centre of one element"
    )]
    NotAtElement {
        /// Fault index.
        node: usize,
        /// Vertex id.
        vertex: usize,
        /// Its position (m).
        position: [f64; 3],
        /// Distance to the nearest element centre (m; infinite if none is near, 0 if that
        /// element has a node already).
        offset: f64,
    },
    /// An element has no frictional node at its centre.
    #[error("element {element} (centre {centre:?} m) has no frictional node at its centre")]
    NoNodeAt {
        /// The element.
        element: usize,
        /// Its centre (m).
        centre: [f64; 3],
    },
    /// A frictional node's normal is not its element's (either sign).
    #[error(
        "frictional node {node} (vertex {vertex}): its normal is {angle:e} rad from element \
         {element}'s; the element must lie in the node's tangent plane"
    )]
    NotAligned {
        /// Fault index.
        node: usize,
        /// Vertex id.
        vertex: usize,
        /// The element at its position.
        element: usize,
        /// The angle between the normals (rad).
        angle: f64,
    },
    /// Invalid options.
    #[error("HalfSpaceOptions::{name} = {}: {expected}", rsf_numeric::written(*value))]
    Options {
        /// The option.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// The half-space kernels refused (the rectangle, the ℋ-matrix, an entry).
    #[error("half-space kernel: {0}")]
    Kernel(#[from] rsf_halfspace::Error),
    /// The operator's rows could not be shared out to the ranks
    /// ([`HalfSpaceOperator::fault_alone_on_ranks`](super::HalfSpaceOperator::fault_alone_on_ranks)):
    /// fewer parts than ranks, or a part that cuts an element.
    #[error("the half-space operator on {ranks} ranks: {reason}")]
    Ranks {
        /// The number of ranks.
        ranks: usize,
        /// Why.
        reason: String,
    },
}
