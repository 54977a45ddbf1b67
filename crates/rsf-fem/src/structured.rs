//! Structured meshes: rectangles (triangles), boxes (Kuhn tetrahedra) and the paper's
//! coarse slider grid.

use crate::mesh::{SimplexMesh, TetrahedronMesh, TriangleMesh};
use crate::{Error, Result};

/// Tag name used by [`pipping_slider_coarse`] for the top edge (Dirichlet, Γ_D).
pub const TAG_DIRICHLET: &str = "dirichlet";
/// Tag name used by [`pipping_slider_coarse`] for the side edges (Neumann, Γ_N).
pub const TAG_NEUMANN: &str = "neumann";
/// Tag name used by [`pipping_slider_coarse`] for the bottom edge (frictional, Γ_F).
pub const TAG_FRICTIONAL: &str = "frictional";

/// Which diagonal splits each cell of a structured rectangle.
///
/// Names (`name`, `FromStr`, serde, clap): `forward`, `backward`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Diagonal {
    /// "/" : from the lower-left to the upper-right corner of every cell.
    #[default]
    Forward,
    /// "\" : from the upper-left to the lower-right corner of every cell.
    Backward,
}

impl Diagonal {
    /// The name (`forward`, `backward`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Forward => "forward",
            Self::Backward => "backward",
        }
    }
}

rsf_numeric::display_and_parse_by_name!(
    Diagonal,
    "diagonal",
    Error,
    [Diagonal::Forward, Diagonal::Backward]
);

/// Structured triangulation of the rectangle `[x0, x0 + lx] × [y0, y0 + ly]` with
/// `nx × ny` vertices (`nx − 1` by `ny − 1` cells, each split in two along `diagonal`).
///
/// Vertex `i + nx·j` sits at `(x0 + i·lx/(nx−1), y0 + j·ly/(ny−1))`. No tags are set.
/// The paper's coarse grid (§6.1) is `rectangle([0.0, 0.0], [5.0, 1.0], 6, 2, d)`:
/// 12 vertices, 10 triangles.
///
/// # Errors
/// [`Error::InvalidGrid`] if `nx < 2`, `ny < 2`, or a size is not positive and finite;
/// [`Error::NonFiniteCoordinate`] for a non-finite origin.
pub fn rectangle(
    origin: [f64; 2],
    size: [f64; 2],
    nx: usize,
    ny: usize,
    diagonal: Diagonal,
) -> Result<TriangleMesh> {
    if nx < 2 || ny < 2 {
        return Err(Error::InvalidGrid(format!(
            "need at least 2 x 2 vertices, got {nx} x {ny}"
        )));
    }
    if !(size[0] > 0.0 && size[1] > 0.0 && size[0].is_finite() && size[1].is_finite()) {
        return Err(Error::InvalidGrid(format!(
            "size must be positive and finite, got {size:?}"
        )));
    }
    let mut vertices = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            vertices.push([
                origin[0] + size[0] * i as f64 / (nx - 1) as f64,
                origin[1] + size[1] * j as f64 / (ny - 1) as f64,
            ]);
        }
    }
    SimplexMesh::new(vertices, tensor_cells(nx, ny, diagonal))
}

/// The cells of an `nx × ny` tensor grid of vertices (vertex `i + nx·j`), two triangles
/// per quadrilateral split along `diagonal`.
fn tensor_cells(nx: usize, ny: usize, diagonal: Diagonal) -> Vec<usize> {
    let mut cells = Vec::with_capacity(6 * (nx - 1) * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = i + nx * j;
            let (b, c, d) = (a + 1, a + 1 + nx, a + nx);
            match diagonal {
                Diagonal::Forward => cells.extend_from_slice(&[a, b, c, a, c, d]),
                Diagonal::Backward => cells.extend_from_slice(&[a, b, d, b, c, d]),
            }
        }
    }
    cells
}

/// Tensor-product triangulation of a rectangle with the vertex coordinates `xs` along x
/// and `ys` along y (both strictly increasing, at least 2 each): vertex `i + nx·j` at
/// `(xs[i], ys[j])`, cells as in [`rectangle`] (which is the equispaced case). With
/// [`geometric_grading`] this is the graded mesh of the antiplane benchmark
/// (docs/seas-bp1.md): fine along the fault, coarsening geometrically to hundreds of km.
/// No tags are set.
///
/// # Errors
/// [`Error::InvalidGrid`] if a list has fewer than 2 entries, is not strictly increasing
/// or holds a non-finite value.
pub fn rectangle_from_coordinates(
    xs: &[f64],
    ys: &[f64],
    diagonal: Diagonal,
) -> Result<TriangleMesh> {
    check_coordinates(&[("xs", xs), ("ys", ys)])?;
    let (nx, ny) = (xs.len(), ys.len());
    let mut vertices = Vec::with_capacity(nx * ny);
    for &y in ys {
        for &x in xs {
            vertices.push([x, y]);
        }
    }
    SimplexMesh::new(vertices, tensor_cells(nx, ny, diagonal))
}

/// Each named list of a tensor grid's coordinates: at least 2, finite, strictly
/// increasing ([`Error::InvalidGrid`] naming the list otherwise).
/// The number of cubes of edge `root` (m) along each side of the box `[lower, upper]`:
/// the root grid of the graded meshes ([`crate::OctreeMesh`], [`crate::BisectionMesh`]).
///
/// # Errors
/// [`Error::InvalidGrid`] unless `root > 0`, every coordinate is finite and each side is a
/// whole number (to 1e-9) of at least one and at most 10⁶ `root`.
pub(crate) fn root_cells(lower: [f64; 3], upper: [f64; 3], root: f64) -> Result<[u64; 3]> {
    if !(root > 0.0 && root.is_finite()) {
        return Err(Error::InvalidGrid(format!(
            "the root cell size {root} m must be positive and finite"
        )));
    }
    let mut counts = [0u64; 3];
    for a in 0..3 {
        let cells = (upper[a] - lower[a]) / root;
        let whole = lower[a].is_finite()
            && upper[a].is_finite()
            && cells >= 1.0 - 1e-9
            && (cells - cells.round()).abs() <= 1e-9 * cells
            && cells <= 1e6;
        if !whole {
            return Err(Error::InvalidGrid(format!(
                "side {a} of the box [{}, {}] m must be a whole number of root cells of \
                 {root} m",
                lower[a], upper[a]
            )));
        }
        counts[a] = cells.round() as u64;
    }
    Ok(counts)
}

fn check_coordinates(lists: &[(&str, &[f64])]) -> Result<()> {
    for &(name, c) in lists {
        if c.len() < 2 {
            return Err(Error::InvalidGrid(format!(
                "{name}: need at least 2 coordinates, got {}",
                c.len()
            )));
        }
        if c.iter().any(|v| !v.is_finite()) || c.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::InvalidGrid(format!(
                "{name}: coordinates must be finite and strictly increasing"
            )));
        }
    }
    Ok(())
}

/// The most coordinates [`geometric_grading`] returns (10⁷).
pub const MAX_GRADED_COORDINATES: f64 = 1e7;

/// The number of coordinates [`geometric_grading`] returns for the same arguments, in
/// closed form and without allocating (an estimate: at most 2 above the exact count, never
/// below it; `f64`, so that a grid of 10³⁰⁰ intervals is a number, not an overflow) — to
/// bound a mesh's size before it is built. `+∞` for arguments
/// [`geometric_grading`] refuses.
///
/// ```
/// use rsf_fem::{geometric_grading, geometric_grading_len};
/// let n = geometric_grading(25.0, 40e3, 1.05, 400e3)?.len() as f64;
/// let estimate = geometric_grading_len(25.0, 40e3, 1.05, 400e3);
/// assert!(estimate >= n && estimate <= n + 2.0);
/// assert!(geometric_grading_len(1e-300, 40e3, 1.0, 400e3) > 1e305); // refused, not built
/// assert!(geometric_grading(1e-300, 40e3, 1.0, 400e3).is_err());
/// # Ok::<(), rsf_fem::Error>(())
/// ```
pub fn geometric_grading_len(h: f64, uniform: f64, ratio: f64, length: f64) -> f64 {
    if !grading_is_valid(h, uniform, ratio, length) {
        return f64::INFINITY;
    }
    let n_uniform = (uniform / h + 1e-9).floor();
    let rest = length - n_uniform * h;
    // Intervals growing from h·r: h r (r^k − 1)/(r − 1) ≥ rest.
    let graded = if rest <= 1e-12 * length {
        0.0
    } else if ratio == 1.0 {
        (rest / h).ceil()
    } else {
        ((1.0 + rest * (ratio - 1.0) / (h * ratio)).ln() / ratio.ln()).ceil()
    };
    n_uniform + 1.0 + graded
}

/// Whether a grading's parameters are valid: `0 < h ≤ length`, `0 ≤ uniform ≤ length`,
/// `1 ≤ ratio ≤ 10`, all finite.
fn grading_is_valid(h: f64, uniform: f64, ratio: f64, length: f64) -> bool {
    h > 0.0
        && length.is_finite()
        && h <= length
        && uniform >= 0.0
        && uniform <= length
        && (1.0..=10.0).contains(&ratio)
}

/// The number of vertices `nx ny nz` of a grid; `None` if it, or 24 times it (six
/// tetrahedra of four indices per box), overflows a `usize`.
fn grid_vertex_count(nx: usize, ny: usize, nz: usize) -> Option<usize> {
    nx.checked_mul(ny)
        .and_then(|v| v.checked_mul(nz))
        .filter(|&v| v.checked_mul(6 * 4).is_some())
}

/// [`geometric_grading`] mirrored about 0: `−length … −uniform … 0 … uniform … length`
/// (m), spacing `h` over `[−uniform, uniform]`, growing by `ratio` beyond (e.g. across a
/// fault at 0).
///
/// ```
/// let c = rsf_fem::symmetric_grading(1.0, 2.0, 2.0, 8.0)?;
/// assert_eq!(c, [-8.0, -4.0, -2.0, -1.0, 0.0, 1.0, 2.0, 4.0, 8.0]);
/// # Ok::<(), rsf_fem::Error>(())
/// ```
///
/// # Errors
/// As [`geometric_grading`].
pub fn symmetric_grading(h: f64, uniform: f64, ratio: f64, length: f64) -> Result<Vec<f64>> {
    let half = geometric_grading(h, uniform, ratio, length)?;
    let mut c: Vec<f64> = half.iter().rev().map(|x| -x).collect();
    c.extend_from_slice(&half[1..]);
    Ok(c)
}

/// Coordinates `0 = c_0 < c_1 < … < c_n = length` with spacing `h` up to `uniform`
/// (m), then growing by the factor `ratio` per interval until `length`; the last interval
/// takes the remainder (between half the previous spacing and `1 + ratio` times it).
///
/// Example: `geometric_grading(25.0, 40e3, 1.05, 400e3)` is Δz = 25 m on the 40 km fault
/// and about 120 more intervals to 400 km.
///
/// # Errors
/// [`Error::InvalidGrid`] unless `0 < h ≤ length`, `0 ≤ uniform ≤ length`,
/// `1 ≤ ratio ≤ 10` and all finite, or if more than [`MAX_GRADED_COORDINATES`] would
/// result (refused before anything is allocated: [`geometric_grading_len`]).
pub fn geometric_grading(h: f64, uniform: f64, ratio: f64, length: f64) -> Result<Vec<f64>> {
    if !grading_is_valid(h, uniform, ratio, length) {
        return Err(Error::InvalidGrid(format!(
            "grading: need 0 < h <= length, 0 <= uniform <= length, 1 <= ratio <= 10; \
             got h = {h}, uniform = {uniform}, ratio = {ratio}, length = {length}"
        )));
    }
    let estimate = geometric_grading_len(h, uniform, ratio, length);
    if estimate > MAX_GRADED_COORDINATES {
        return Err(Error::InvalidGrid(format!(
            "grading: about {estimate:.3e} coordinates, more than {MAX_GRADED_COORDINATES:e} \
             (h = {h:e} m, uniform = {uniform:e} m, ratio = {ratio}, length = {length:e} m)"
        )));
    }
    let n_uniform = (uniform / h + 1e-9).floor() as usize;
    let mut c = Vec::with_capacity(n_uniform + 64);
    for i in 0..=n_uniform {
        c.push(i as f64 * h);
    }
    let mut step = h;
    let mut last = *c.last().expect("non-empty");
    while length - last > 1e-12 * length {
        if c.len() as f64 > MAX_GRADED_COORDINATES {
            return Err(Error::InvalidGrid(format!(
                "grading: more than {MAX_GRADED_COORDINATES:e} coordinates (h = {h:e} m, \
                 length = {length:e} m)"
            )));
        }
        step *= ratio;
        if last + step * (1.0 + ratio) > length {
            // Close: a remainder shorter than half the previous spacing joins the
            // previous interval.
            if length - last < 0.5 * step / ratio && c.len() > 1 {
                c.pop();
            }
            c.push(length);
            break;
        }
        last += step;
        c.push(last);
    }
    *c.last_mut().expect("non-empty") = length;
    Ok(c)
}

/// The paper's coarse grid (§6.1, Table 6.1): `[0, 5] × [0, 1]` m with 6 × 2 vertices
/// (10 triangles, [`Diagonal::Forward`]) and boundary tags
/// [`TAG_DIRICHLET`] (top, y = 1), [`TAG_NEUMANN`] (sides x = 0 and x = 5) and
/// [`TAG_FRICTIONAL`] (bottom, y = 0).
pub fn pipping_slider_coarse(diagonal: Diagonal) -> TriangleMesh {
    let mut m =
        rectangle([0.0, 0.0], [5.0, 1.0], 6, 2, diagonal).expect("the slider rectangle is valid");
    m.tag_boundary(TAG_NEUMANN, |x| x[0] < 1e-9 || x[0] > 5.0 - 1e-9);
    m.tag_boundary(TAG_DIRICHLET, |x| x[1] > 1.0 - 1e-9);
    m.tag_boundary(TAG_FRICTIONAL, |x| x[1] < 1e-9);
    m
}

/// Structured tetrahedral mesh of the box `[x0, x0 + lx] × [y0, y0 + ly] × [z0, z0 + lz]`
/// with `n = [nx, ny, nz]` vertices per direction; every hexahedral cell is split into 6
/// tetrahedra around its main diagonal (Kuhn/Freudenthal triangulation).
///
/// Vertex `i + nx·(j + ny·k)` sits at `origin + (i·lx/(nx−1), j·ly/(ny−1), k·lz/(nz−1))`.
/// Cells are numbered cell by cell (`x` fastest), 6 tetrahedra per cell. With `p` the
/// cell's lowest corner, tetrahedron `t` is the **Kuhn path**
/// `(p, p + e_a, p + e_a + e_b, p + e_a + e_b + e_c)` for the `t`-th permutation `(a, b, c)`
/// of the axes in the order `xyz, xzy, yxz, yzx, zxy, zyx` (`e` scaled by the cell size).
/// The path is the cell's refinement order (Bey's rule then refines every tetrahedron into 8
/// Kuhn tetrahedra of the half-size cells, docs/math.md §10). Paths of even permutations are
/// positively oriented and stored as given; those of odd permutations (`xzy, yxz, zyx`) are
/// stored with their last two vertices swapped, so that every stored cell is positively
/// oriented (see [`SimplexMesh::from_ordered_cells`]). All 6 tetrahedra of a cube are
/// congruent. No tags are set.
///
/// **Which planes it resolves.** The tetrahedron of the path `(a, b, c)` is the set
/// `1 ≥ ξ_a ≥ ξ_b ≥ ξ_c ≥ 0` of the box's local coordinates `ξ = (x − p)/(cell size)`, so
/// its faces lie on the planes `ξ_i = 0, 1` and `ξ_i = ξ_j`: a surface made of mesh faces
/// (a fault inside the body, [`SimplexMesh::split_along_polygon`]) can be a plane
/// `x_i = const` on a grid line, or — where the cells are cubes (equal spacing along
/// `x_i` and `x_j`) — a diagonal plane `x_i − x_j = const` through grid vertices, i.e.
/// dipping at 45° (e.g. `y − z = d`: Okada's 45° dip towards `−y`). The other diagonal,
/// `x_i + x_j = const`, cuts through the cells and is not resolved; nor is any other dip.
/// Red refinement keeps all of these planes resolved ([`MeshHierarchy`](crate::MeshHierarchy)).
///
/// # Errors
/// [`Error::InvalidGrid`] if some `n < 2` or a size is not positive and finite;
/// [`Error::NonFiniteCoordinate`] for a non-finite origin.
pub fn cuboid(origin: [f64; 3], size: [f64; 3], n: [usize; 3]) -> Result<TetrahedronMesh> {
    if n.iter().any(|&k| k < 2) {
        return Err(Error::InvalidGrid(format!(
            "need at least 2 vertices per direction, got {n:?}"
        )));
    }
    if !size.iter().all(|&s| s > 0.0 && s.is_finite()) {
        return Err(Error::InvalidGrid(format!(
            "size must be positive and finite, got {size:?}"
        )));
    }
    let [nx, ny, nz] = n;
    let count = grid_vertex_count(nx, ny, nz)
        .ok_or_else(|| Error::InvalidGrid(format!("too many vertices: {n:?}")))?;
    let mut vertices = Vec::with_capacity(count);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                vertices.push([
                    origin[0] + size[0] * i as f64 / (nx - 1) as f64,
                    origin[1] + size[1] * j as f64 / (ny - 1) as f64,
                    origin[2] + size[2] * k as f64 / (nz - 1) as f64,
                ]);
            }
        }
    }
    SimplexMesh::from_ordered_cells(vertices, kuhn_cells(nx, ny, nz))
}

/// The tensor-product box with vertices at every `(xs[i], ys[j], zs[k])` (m; each list
/// strictly increasing, at least 2 entries), each box cut into six tetrahedra as
/// [`cuboid`] does (Kuhn's subdivision, conforming, refinable): with
/// [`geometric_grading`] a 3-D mesh fine near a fault and coarsening geometrically to
/// a far boundary hundreds of km away (docs/three-d.md). No tags are set.
///
/// The planes it resolves are [`cuboid`]'s: the grid planes `x_i = const`, and the
/// diagonal planes `x_i − x_j = const` only where the boxes are cubes (`x_i` and `x_j`
/// spaced equally around the plane: a 45° fault needs a band of equal spacing around
/// it), never `x_i + x_j = const`.
///
/// ```
/// use rsf_fem::{cuboid_from_coordinates, geometric_grading};
/// let x: Vec<f64> = geometric_grading(1.0, 2.0, 1.5, 10.0)?;
/// let mesh = cuboid_from_coordinates(&x, &[0.0, 1.0, 2.0], &[-1.0, 0.0])?;
/// assert_eq!(mesh.num_vertices(), x.len() * 3 * 2);
/// assert_eq!(mesh.num_cells(), 6 * (x.len() - 1) * 2);
/// # Ok::<(), rsf_fem::Error>(())
/// ```
///
/// # Errors
/// [`Error::InvalidGrid`] if a list has fewer than 2 entries, is not strictly increasing
/// or holds a non-finite value, or the grid has more vertices than can be indexed.
pub fn cuboid_from_coordinates(xs: &[f64], ys: &[f64], zs: &[f64]) -> Result<TetrahedronMesh> {
    check_coordinates(&[("xs", xs), ("ys", ys), ("zs", zs)])?;
    let (nx, ny, nz) = (xs.len(), ys.len(), zs.len());
    let count = grid_vertex_count(nx, ny, nz)
        .ok_or_else(|| Error::InvalidGrid(format!("too many vertices: {nx} × {ny} × {nz}")))?;
    let mut vertices = Vec::with_capacity(count);
    for &z in zs {
        for &y in ys {
            for &x in xs {
                vertices.push([x, y, z]);
            }
        }
    }
    SimplexMesh::from_ordered_cells(vertices, kuhn_cells(nx, ny, nz))
}

/// As [`cuboid_from_coordinates`], each box's diagonal mirrored along the axes where it
/// is flagged: `mirror[a][i]` (one flag per box along axis `a`: `xs.len() − 1` flags for
/// `a = 0`, …) mirrors the six tetrahedra of the boxes with index `i` along `a` in the
/// plane between their faces, so that their paths run from the box's higher to its lower
/// face along `a`. Mirroring alternate boxes gives the "union jack" pattern that
/// [`BisectionMesh`](crate::BisectionMesh) makes (there each half cube's diagonal runs
/// through its parent's centre), on a tensor grid; every pattern of flags is conforming
/// (a mirrored box meets its neighbour's triangulation of their shared face).
///
/// # Errors
/// As [`cuboid_from_coordinates`]; [`Error::InvalidGrid`] if a list of flags does not have
/// one flag per box along its axis.
pub fn cuboid_mirrored(
    xs: &[f64],
    ys: &[f64],
    zs: &[f64],
    mirror: [&[bool]; 3],
) -> Result<TetrahedronMesh> {
    for (a, (flags, coordinates)) in mirror.iter().zip([xs, ys, zs]).enumerate() {
        if flags.len() + 1 != coordinates.len() {
            return Err(Error::InvalidGrid(format!(
                "{} mirror flags along axis {a} for {} boxes",
                flags.len(),
                coordinates.len().saturating_sub(1)
            )));
        }
    }
    let mesh = cuboid_from_coordinates(xs, ys, zs)?;
    let cells = kuhn_cells_mirrored(xs.len(), ys.len(), zs.len(), mirror);
    SimplexMesh::from_ordered_cells(mesh.vertices().to_vec(), cells)
}

/// Kuhn's subdivision of a box into six tetrahedra: the orders in which the paths from the
/// box's first corner to its last step along the axes (0, 1, 2 = x, y, z), one tetrahedron
/// per path (its vertices the corners the path visits).
pub const KUHN_PATHS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// The six tetrahedra of each box of an `nx × ny × nz` vertex grid (vertex
/// `i + nx (j + ny k)`), four vertex indices each: one per path from the box's first to its
/// last corner along the axes (Kuhn's subdivision).
fn kuhn_cells(nx: usize, ny: usize, nz: usize) -> Vec<usize> {
    let none = [
        vec![false; nx - 1],
        vec![false; ny - 1],
        vec![false; nz - 1],
    ];
    kuhn_cells_mirrored(nx, ny, nz, [&none[0], &none[1], &none[2]])
}

/// [`kuhn_cells`] with the boxes mirrored along the flagged axes (`mirror[a][i]` for the
/// boxes of index `i` along `a`): their paths start at the higher face along `a` and step
/// down it.
fn kuhn_cells_mirrored(nx: usize, ny: usize, nz: usize, mirror: [&[bool]; 3]) -> Vec<usize> {
    let stride = [1, nx, nx * ny];
    let mut cells = Vec::with_capacity(24 * (nx - 1) * (ny - 1) * (nz - 1));
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let flip = [mirror[0][i], mirror[1][j], mirror[2][k]];
                let mut p = i + nx * (j + ny * k);
                for a in 0..3 {
                    if flip[a] {
                        p += stride[a];
                    }
                }
                for perm in KUHN_PATHS {
                    let mut v = p;
                    cells.push(v);
                    for axis in perm {
                        if flip[axis] {
                            v -= stride[axis];
                        } else {
                            v += stride[axis];
                        }
                        cells.push(v);
                    }
                }
            }
        }
    }
    cells
}
