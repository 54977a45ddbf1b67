//! Error type of `rsf-fem`.

/// Everything that can go wrong in `rsf-fem` on user input.
///
/// Panics are reserved for broken internal invariants; every problem caused by the
/// caller's data is reported through one of these variants.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// Index of the offending vertex.
        vertex: usize,
    },
    /// A cell refers to a vertex that does not exist.
    #[error("cell {cell} refers to vertex {vertex}, but the mesh has {num_vertices} vertices")]
    VertexOutOfRange {
        /// Cell index.
        cell: usize,
        /// The invalid vertex index.
        vertex: usize,
        /// Number of vertices in the mesh.
        num_vertices: usize,
    },
    /// The connectivity array length is not a multiple of `D + 1`.
    #[error("connectivity has {len} entries, not a multiple of {stride}")]
    BadConnectivity {
        /// Length of the array.
        len: usize,
        /// Expected stride (`D + 1`).
        stride: usize,
    },
    /// A cell has (numerically) zero measure.
    #[error("cell {cell} is degenerate (signed measure {measure:e})")]
    DegenerateCell {
        /// Cell index.
        cell: usize,
        /// Its signed measure.
        measure: f64,
    },
    /// A cell is clockwise (negative orientation).
    #[error("cell {cell} is inverted / clockwise (signed measure {measure:e})")]
    InvertedCell {
        /// Cell index.
        cell: usize,
        /// Its signed measure.
        measure: f64,
    },
    /// The mesh has no cells.
    #[error("mesh has no cells")]
    EmptyMesh,
    /// Invalid grid parameters for a structured mesh.
    #[error("invalid grid: {0}")]
    InvalidGrid(String),
    /// Young's modulus must be positive and finite.
    #[error("Young's modulus E = {0} must be positive and finite (Pa; N/m in 2D)")]
    InvalidYoungsModulus(f64),
    /// Poisson's ratio must lie in (−1, 0.5).
    #[error("Poisson's ratio nu = {0} must lie in (-1, 0.5)")]
    InvalidPoissonRatio(f64),
    /// Density must be positive and finite.
    #[error("density rho = {0} must be positive and finite (kg/m^3; kg/m^2 in 2D)")]
    InvalidDensity(f64),
    /// Shear modulus `mu` (Pa) not positive and finite.
    #[error("mu = {0} Pa: the shear modulus must be positive and finite")]
    InvalidShearModulus(f64),
    /// A boundary part (or segment) selected no facets.
    #[error("boundary part `{name}` is empty")]
    EmptySegment {
        /// Segment name.
        name: String,
    },
    /// A vector has the wrong length or a mesh does not match the assembler.
    #[error("dimension mismatch in {what}: expected {expected}, got {got}")]
    DimensionMismatch {
        /// What was being checked.
        what: &'static str,
        /// Expected size.
        expected: usize,
        /// Actual size.
        got: usize,
    },
    /// A node / component index is out of range.
    #[error("dof (node {node}, component {component}) out of range")]
    InvalidDof {
        /// Node index.
        node: usize,
        /// Component index.
        component: usize,
    },
    /// A boundary facet index is out of range.
    #[error("boundary facet {facet} does not exist (the mesh has {num_facets})")]
    InvalidFacet {
        /// The invalid index.
        facet: usize,
        /// Number of boundary facets.
        num_facets: usize,
    },
    /// The averaged outer normal at a boundary node vanishes.
    #[error("the outer normal at vertex {vertex} is undefined (adjacent facet normals cancel)")]
    UndefinedNormal {
        /// The vertex.
        vertex: usize,
    },
    /// The reference direction of the first tangent of 3-D nodal frames
    /// ([`BoundaryPart::frames_with_tangent`](crate::BoundaryPart::frames_with_tangent), a
    /// fault's `tangent` in [`FaultSides::mean_jump_transform`](crate::FaultSides)) is
    /// (nearly) normal to the surface at a node, so it gives no tangent there.
    #[error(
        "the tangent direction {direction:?} is (nearly) normal to the surface at vertex \
         {vertex} at {position:?} m (outward normal {normal:?}): it gives the nodal frame no \
         first tangent there; give a direction along the surface at every such node, or \
         none (the default rule: the coordinate axis with the smallest normal component)"
    )]
    TangentAlongNormal {
        /// The mesh vertex.
        vertex: usize,
        /// Its coordinates (m).
        position: Vec<f64>,
        /// The outward unit normal there.
        normal: Vec<f64>,
        /// The direction given.
        direction: Vec<f64>,
    },
    /// A requested hierarchy level does not exist.
    #[error("level {level} does not exist (hierarchy has levels 0..={finest})")]
    InvalidLevel {
        /// Requested level.
        level: usize,
        /// Finest available level.
        finest: usize,
    },
    /// A non-finite value was passed where a finite one is needed.
    #[error("non-finite value in {0}")]
    NonFiniteValue(&'static str),
    /// The matrix is not (numerically) symmetric positive definite.
    #[error("matrix is not positive definite (Cholesky failed{detail})")]
    NotPositiveDefinite {
        /// Extra details from the factorisation.
        detail: String,
    },
    /// The sparsity pattern differs from the analysed one.
    #[error("sparsity pattern differs from the one used for the symbolic analysis")]
    PatternMismatch,
    /// The matrix lacks the node-block structure required by the operation.
    #[error("matrix lacks the node-block sparsity structure")]
    NotBlockStructured,
    /// Another error of the sparse linear algebra (`rsf-linalg`); its pattern, dimension,
    /// positive-definiteness and faer errors arrive as the variants above.
    #[error(transparent)]
    Linalg(rsf_linalg::Error),
    /// Memory allocation or other failure inside faer.
    #[error("faer error: {0}")]
    Faer(String),
    /// The operation is not implemented for this dimension.
    #[error("not supported: {0}")]
    Unsupported(&'static str),
    /// A Gmsh file is malformed or uses something the reader does not support.
    #[error("Gmsh file, {}: {message}", location(.line, .section))]
    Gmsh {
        /// 1-based line of the problem, if it is tied to one.
        line: Option<usize>,
        /// The section (`Nodes`, `Elements`, …; `file` outside any section).
        section: String,
        /// What is wrong.
        message: String,
    },
    /// An error in a file (e.g. a Gmsh file's [`Error::Gmsh`]), naming the file.
    #[error("`{path}`: {inner}")]
    InFile {
        /// The file.
        path: String,
        /// What is wrong in it.
        inner: Box<Error>,
    },
    /// A file could not be read.
    #[error("cannot read `{path}`: {message}")]
    Io {
        /// The path.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// A fault to split ([`crate::SimplexMesh::split_along`]) has no edges (2-D) or
    /// faces (3-D).
    #[error("the fault has no edges")]
    EmptyFault,
    /// A fault entry is not an edge of the mesh.
    #[error("fault edge {edge} ({vertices:?}) is not an edge of the mesh")]
    FaultEdgeNotInMesh {
        /// Index in the list of fault edges.
        edge: usize,
        /// Its vertices.
        vertices: [usize; 2],
    },
    /// A fault edge lies on the outer boundary (it has cells on one side only).
    #[error("fault edge {edge} ({vertices:?}) lies on the outer boundary: it has one side only")]
    FaultEdgeOnBoundary {
        /// Index in the list of fault edges.
        edge: usize,
        /// Its vertices.
        vertices: [usize; 2],
    },
    /// A fault edge is listed twice.
    #[error("fault edge {edge} ({vertices:?}) is listed twice")]
    FaultEdgeRepeated {
        /// Index of the second occurrence.
        edge: usize,
        /// Its vertices.
        vertices: [usize; 2],
    },
    /// An edge (2-D) given for two faults of a network.
    #[error(
        "fault edge {edge} ({vertices:?}) of fault `{second}` is also an edge of fault `{first}`"
    )]
    FaultEdgeShared {
        /// Index in the second fault's list of edges.
        edge: usize,
        /// Its vertices.
        vertices: [usize; 2],
        /// The fault that listed it first.
        first: String,
        /// The fault that listed it again.
        second: String,
    },
    /// Two faults of a network have the same name (their side tags would collide).
    #[error("two faults of the network are named `{name}`: names must be unique")]
    FaultNameRepeated {
        /// The name.
        name: String,
    },
    /// Faults of a network meet at a vertex in a way the network does not support: in 2-D a
    /// fault may end on another that goes on through the vertex (a branch) and two faults
    /// may cross there (both going through), each inside the body; in 3-D faults may not
    /// share a vertex (docs/math.md §16).
    #[error(
        "the faults {faults:?} meet at vertex {vertex} at {position:?} m in a way a fault \
         network does not support: {reason}"
    )]
    FaultJunctionUnsupported {
        /// The faults meeting there, in network order.
        faults: Vec<String>,
        /// The vertex (of the mesh given to the splitting).
        vertex: usize,
        /// Its position (m).
        position: Vec<f64>,
        /// What is not supported there.
        reason: &'static str,
    },
    /// More than two fault edges meet at a vertex: the fault branches or crosses itself.
    #[error("{edges} fault edges meet at vertex {vertex}: the fault branches or crosses itself")]
    FaultNotManifold {
        /// The vertex.
        vertex: usize,
        /// Number of fault edges found there so far.
        edges: usize,
    },
    /// The fault is a closed curve (it has no ends).
    #[error("the fault is a closed curve through vertex {vertex}")]
    FaultClosed {
        /// A vertex on it.
        vertex: usize,
    },
    /// The fault edges form more than one chain (2-D), or the fault faces are not all
    /// connected through shared edges (3-D).
    #[error("the fault is not connected: vertex {vertex} is not on the chain of the first edge")]
    FaultDisconnected {
        /// A vertex of an edge off the first edge's chain (3-D: the first vertex of the
        /// first face, in input order, not connected to the first face).
        vertex: usize,
    },
    /// The fault does not cut the cells around a vertex into two sides (e.g. a fault node
    /// inside the chain lies on the outer boundary).
    #[error("the fault does not cut the cells around vertex {vertex} into two sides")]
    FaultSidesNotSeparated {
        /// The vertex.
        vertex: usize,
    },
    /// A straight fault is not made of mesh edges near this point (m).
    #[error("the mesh has no edges along the fault segment at {point:?}")]
    FaultSegmentNotResolved {
        /// The first point of the segment not covered by mesh edges.
        point: [f64; 2],
    },
    /// A 3-D fault entry is not a face (triangle) of the mesh: a vertex out of range, two
    /// equal vertices, or three vertices that are no cell's face.
    #[error("fault face {face} ({vertices:?}) is not a face of the mesh")]
    FaultFaceNotInMesh {
        /// Index in the list of fault faces.
        face: usize,
        /// Its vertices.
        vertices: [usize; 3],
    },
    /// A 3-D fault face lies on the outer boundary (it has a cell on one side only).
    #[error("fault face {face} ({vertices:?}) lies on the outer boundary: it has one side only")]
    FaultFaceOnBoundary {
        /// Index in the list of fault faces.
        face: usize,
        /// Its vertices.
        vertices: [usize; 3],
    },
    /// A 3-D fault face is listed twice (in any vertex order).
    #[error("fault face {face} ({vertices:?}) is listed twice")]
    FaultFaceRepeated {
        /// Index of the second occurrence.
        face: usize,
        /// Its vertices.
        vertices: [usize; 3],
    },
    /// More than two 3-D fault faces share an edge: the fault branches or crosses itself.
    #[error(
        "{faces} fault faces share the edge {vertices:?}: the fault branches or crosses itself"
    )]
    FaultEdgeNotManifold {
        /// The edge's vertices (increasing).
        vertices: [usize; 2],
        /// Number of fault faces found at it so far.
        faces: usize,
    },
    /// The 3-D fault faces cannot be oriented consistently (a Möbius strip): walking from
    /// the first face, this face would need both orientations.
    #[error("the fault is not orientable: fault face {face} cannot be oriented consistently")]
    FaultNotOrientable {
        /// Index in the list of fault faces.
        face: usize,
    },
    /// A planar fault polygon is not made of mesh faces near this point (m), or the polygon
    /// itself is invalid (non-finite, not planar, degenerate).
    #[error("the mesh has no faces tiling the fault polygon near {point:?}")]
    FaultSurfaceNotResolved {
        /// A point of the polygon not covered by mesh faces, or a corner.
        point: [f64; 3],
    },
    /// A name that is not one of a choice's names.
    #[error(transparent)]
    UnknownName(#[from] rsf_numeric::UnknownName),
}

fn location(line: &Option<usize>, section: &str) -> String {
    let section = if section == "file" {
        String::new()
    } else {
        format!("section ${section}")
    };
    match (line, section.is_empty()) {
        (Some(l), true) => format!("line {l}"),
        (Some(l), false) => format!("line {l} ({section})"),
        (None, _) => section,
    }
}

/// Result alias of `rsf-fem`.
pub type Result<T> = std::result::Result<T, Error>;

impl From<rsf_linalg::Error> for Error {
    /// Keeps the variants this crate reported before the sparse linear algebra moved to
    /// `rsf-linalg` (so that `Error::NotPositiveDefinite` still means a failed Cholesky).
    fn from(e: rsf_linalg::Error) -> Self {
        match e {
            rsf_linalg::Error::Problem(rsf_linalg::ProblemError::DimensionMismatch {
                what,
                expected,
                got,
            }) => Error::DimensionMismatch {
                what,
                expected,
                got,
            },
            rsf_linalg::Error::PatternMismatch => Error::PatternMismatch,
            rsf_linalg::Error::NotPositiveDefinite { detail } => {
                Error::NotPositiveDefinite { detail }
            }
            rsf_linalg::Error::Faer(detail) => Error::Faer(detail),
            other => Error::Linalg(other),
        }
    }
}
