//! Graded tetrahedral meshes whose fine cells are the uniform Kuhn cells of a tensor grid
//! ([`OctreeMesh`]): an octree of cubes, balanced 2:1, each leaf cut into the six Kuhn
//! tetrahedra of [`cuboid`](crate::cuboid) — all with the same diagonal direction, as a
//! tensor grid's — unless a finer neighbour puts a vertex on its boundary; then into the
//! tetrahedra joining its centre to a triangulation of its faces that its neighbours share
//! (docs/fem.md, "Graded meshes: octree of Kuhn cubes").
//!
//! Why not bisection ([`BisectionMesh`](crate::BisectionMesh)) for a fault: bisection's
//! half cubes have their diagonals through their parent's centre, so on a plane of the grid
//! the diagonals alternate ("union jack") and the lumped weights of the plane's nodes
//! alternate between `2/3` and `4/3` of the cell's area — a checkerboard in the friction of
//! a fault on that plane. Here every leaf of the finest level is a tensor grid's Kuhn cube:
//! on a fault meshed at the finest level every node's weight is the cell's area.
//!
//! **Face rule** (the same from both cubes that share a face: it depends only on the
//! face's points). A face with its centre present (a finer neighbour across it) is cut into
//! its four quarter squares, each along the diagonal from its lowest to its highest corner
//! (the Kuhn diagonal); otherwise along its own Kuhn diagonal into two right triangles, and
//! each of those at the midpoints present on its legs: one midpoint joins the opposite
//! corner, two cut off the corner of the right angle and the rest along the line from the
//! diagonal's lower end to the second leg's midpoint.
//!
//! **Which planes are resolved** (a fault inside the body must be a surface of faces,
//! `SimplexMesh::split_along_polygon`): the planes `x_i = const` through the vertices of
//! the leaves along them (a plane of the root grid always; a finer grid plane where the
//! leaves on both sides are that fine), and, where the leaves are Kuhn cubes of one level
//! (no transition cube touches the plane), the diagonal planes `x_i − x_j = const`
//! through their vertices — a 45° fault, as on [`cuboid`](crate::cuboid) — never
//! `x_i + x_j = const`. A transition cube's tetrahedra join its centre to its faces: they
//! resolve no plane through its interior, so refine a fault's neighbourhood to one level.
//! The meshes of successive refinements are not nested (a transition cube's tetrahedra are
//! not unions of its children's), so an octree mesh is not a multigrid hierarchy:
//! [`BisectionMesh::hierarchy`](crate::BisectionMesh::hierarchy) is.

use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

use crate::mesh::TetrahedronMesh;
use crate::refine::wanted_size;
use crate::{Error, Result, KUHN_PATHS};

/// Levels below a root cube: integer coordinates are in units of `root / 2^MAX_LEVEL`.
const MAX_LEVEL: u32 = 30;

/// Most passes of refinement or balancing (each splits every leaf that asks once).
const MAX_PASSES: usize = 4 * MAX_LEVEL as usize;

/// A leaf cube: its level and the integer coordinates of its lowest corner (units of
/// `root / 2^MAX_LEVEL`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct Cube {
    /// The corner `(z, y, x)` first, so that sorting orders cubes as a tensor grid's.
    corner: [u64; 3],
    level: u32,
}

impl Cube {
    /// The edge in integer units.
    fn size(&self) -> u64 {
        1 << (MAX_LEVEL - self.level)
    }

    /// The corner as `(x, y, z)`.
    fn xyz(&self) -> [u64; 3] {
        [self.corner[2], self.corner[1], self.corner[0]]
    }

    fn at(level: u32, xyz: [u64; 3]) -> Self {
        Self {
            corner: [xyz[2], xyz[1], xyz[0]],
            level,
        }
    }

    /// The eight children.
    fn children(&self) -> [Cube; 8] {
        let h = self.size() / 2;
        let c = self.xyz();
        std::array::from_fn(|n| {
            Cube::at(
                self.level + 1,
                [
                    c[0] + h * (n as u64 & 1),
                    c[1] + h * ((n as u64 >> 1) & 1),
                    c[2] + h * ((n as u64 >> 2) & 1),
                ],
            )
        })
    }
}

/// What [`OctreeMesh::refine`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OctreeReport {
    /// Passes of refinement by size.
    pub passes: usize,
    /// Cubes split because the size function asked for it.
    pub by_size: usize,
    /// Cubes split to keep neighbours within one level of each other (2:1 balance across
    /// faces, edges and corners).
    pub by_balance: usize,
}

/// A box of cubes refined as an octree where a size function asks for smaller cells, then
/// a conforming tetrahedral mesh (module docs): [`new`](Self::new),
/// [`refine`](Self::refine), [`into_mesh`](Self::into_mesh).
///
/// ```
/// use rsf_fem::OctreeMesh;
/// // A 4 m cube of 1 m cubes, cells of 1/4 m near the corner (0, 0, 0) growing away from it.
/// let mut o = OctreeMesh::new([0.0; 3], [4.0; 3], 1.0)?;
/// o.refine(|lo, _| 0.25 + 0.5 * lo.iter().map(|x| x * x).sum::<f64>().sqrt(), 1_000_000)?;
/// let mesh = o.into_mesh()?;
/// assert!((mesh.measure() - 64.0).abs() < 1e-9);
/// # Ok::<(), rsf_fem::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct OctreeMesh {
    lower: [f64; 3],
    root: f64,
    /// Root cubes per axis.
    counts: [u64; 3],
    leaves: HashSet<Cube>,
}

impl OctreeMesh {
    /// The box `[lower, upper]` cut into cubes of edge `root` (m), each a leaf.
    ///
    /// # Errors
    /// [`Error::InvalidGrid`] unless `root > 0`, every coordinate is finite and each side
    /// is a whole number (to 1e-9) of at least one and at most 10⁶ `root`.
    pub fn new(lower: [f64; 3], upper: [f64; 3], root: f64) -> Result<Self> {
        let counts = crate::structured::root_cells(lower, upper, root)?;
        let unit = 1u64 << MAX_LEVEL;
        let mut leaves = HashSet::default();
        for k in 0..counts[2] {
            for j in 0..counts[1] {
                for i in 0..counts[0] {
                    leaves.insert(Cube::at(0, [i * unit, j * unit, k * unit]));
                }
            }
        }
        Ok(Self {
            lower,
            root,
            counts,
            leaves,
        })
    }

    /// Number of leaf cubes.
    pub fn num_cubes(&self) -> usize {
        self.leaves.len()
    }

    /// A point of the lattice in metres.
    fn point(&self, p: [u64; 3]) -> [f64; 3] {
        let unit = self.root / (1u64 << MAX_LEVEL) as f64;
        [0, 1, 2].map(|a| self.lower[a] + p[a] as f64 * unit)
    }

    /// Splits, pass after pass, every leaf whose edge exceeds `size(lo, hi)` (the largest
    /// cell wanted anywhere in the leaf's box `[lo, hi]`, m), then splits leaves until every
    /// two that touch (by a face, an edge or a corner) differ by at most one level (2:1
    /// balance). Cells end at most `size` where they are.
    ///
    /// # Errors
    /// [`Error::InvalidGrid`] if `size` gives a value that is not positive (or NaN), if
    /// the mesh would exceed `max_cells` tetrahedra (counted as 48 per cube, the most a
    /// cube makes) or after 120 passes (4 per level of the 30 below a root cube).
    pub fn refine(
        &mut self,
        size: impl Fn([f64; 3], [f64; 3]) -> f64,
        max_cells: usize,
    ) -> Result<OctreeReport> {
        let mut report = OctreeReport {
            passes: 0,
            by_size: 0,
            by_balance: 0,
        };
        loop {
            if report.passes == MAX_PASSES {
                return Err(Error::InvalidGrid(format!(
                    "octree refinement did not end after {MAX_PASSES} passes"
                )));
            }
            report.passes += 1;
            let mut split = Vec::new();
            for cube in self.sorted_leaves() {
                let c = cube.xyz();
                let (lo, hi) = (self.point(c), self.point(c.map(|x| x + cube.size())));
                let wanted = wanted_size(&size, lo, hi)?;
                let edge = self.root / (1u64 << cube.level) as f64;
                if edge > wanted * (1.0 + 1e-9) && cube.level < MAX_LEVEL {
                    split.push(cube);
                }
            }
            if split.is_empty() {
                break;
            }
            report.by_size += split.len();
            self.split(&split, max_cells)?;
        }
        for pass in 0.. {
            if pass == MAX_PASSES {
                return Err(Error::InvalidGrid(format!(
                    "octree balancing did not end after {MAX_PASSES} passes"
                )));
            }
            let mut split = HashSet::default();
            for cube in self.sorted_leaves() {
                for neighbour in self.coarse_neighbours(&cube) {
                    split.insert(neighbour);
                }
            }
            if split.is_empty() {
                break;
            }
            let mut split: Vec<Cube> = split.into_iter().collect();
            split.sort_unstable();
            report.by_balance += split.len();
            self.split(&split, max_cells)?;
        }
        Ok(report)
    }

    /// The leaves in the order of their corners (`z`, then `y`, then `x`), then level.
    fn sorted_leaves(&self) -> Vec<Cube> {
        let mut leaves: Vec<Cube> = self.leaves.iter().copied().collect();
        leaves.sort_unstable();
        leaves
    }

    /// Replaces each of `cubes` (leaves) by its children.
    fn split(&mut self, cubes: &[Cube], max_cells: usize) -> Result<()> {
        let after = self.leaves.len() + 7 * cubes.len();
        if after.saturating_mul(48) > max_cells {
            return Err(Error::InvalidGrid(format!(
                "the octree would have {after} cubes, up to {} tetrahedra, more than \
                 {max_cells}",
                after.saturating_mul(48)
            )));
        }
        for cube in cubes {
            self.leaves.remove(cube);
            self.leaves.extend(cube.children());
        }
        Ok(())
    }

    /// The leaf containing the lattice cell at `p` (integer units), if `p` is in the box.
    fn leaf_at(&self, p: [i64; 3], finest: u32) -> Option<Cube> {
        let unit = 1i64 << MAX_LEVEL;
        if (0..3).any(|a| p[a] < 0 || p[a] >= self.counts[a] as i64 * unit) {
            return None;
        }
        let p = p.map(|x| x as u64);
        (0..=finest).find_map(|level| {
            let h = 1u64 << (MAX_LEVEL - level);
            let cube = Cube::at(level, p.map(|x| x / h * h));
            self.leaves.contains(&cube).then_some(cube)
        })
    }

    /// The leaves touching `cube` that are more than one level coarser.
    fn coarse_neighbours(&self, cube: &Cube) -> Vec<Cube> {
        if cube.level < 2 {
            return Vec::new();
        }
        let (c, h) = (cube.xyz().map(|x| x as i64), cube.size() as i64);
        let mut out = Vec::new();
        for dz in -1..=1i64 {
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    if (dx, dy, dz) == (0, 0, 0) {
                        continue;
                    }
                    // A lattice cell just outside the cube in that direction.
                    let p = [
                        c[0] + if dx < 0 { -1 } else { dx * h },
                        c[1] + if dy < 0 { -1 } else { dy * h },
                        c[2] + if dz < 0 { -1 } else { dz * h },
                    ];
                    if let Some(leaf) = self.leaf_at(p, cube.level - 2) {
                        out.push(leaf);
                    }
                }
            }
        }
        out
    }

    /// The number of vertices [`into_mesh`](Self::into_mesh) makes, counted without making
    /// the mesh: every leaf's corners, and the centre of each transition cube (a cube with a
    /// finer neighbour's vertex on its boundary). Its cost is the corners' set and one pass
    /// of the face rule, with no tetrahedra, index or orientation; a plan counts a large
    /// graded box's vertices so (issue 87: the largest BP5 box at 20 km meshed for 2.4 s).
    pub fn num_vertices(&self) -> usize {
        let leaves = self.sorted_leaves();
        let lattice = corners(&leaves);
        let mut triangles: Vec<[[u64; 3]; 3]> = Vec::with_capacity(48);
        let transitions = leaves
            .iter()
            .filter(|cube| {
                triangles.clear();
                cube_faces(cube.xyz(), cube.size(), &lattice, &mut triangles)
            })
            .count();
        lattice.len() + transitions
    }

    /// The conforming mesh (module docs; [`TetrahedronMesh::from_ordered_cells`]: each
    /// cell stored positively oriented; no tags). Vertices are numbered as the leaves are
    /// visited (corners `z`, `y`, `x` increasing), so the mesh is the same on every machine.
    ///
    /// # Errors
    /// Those of [`TetrahedronMesh::from_ordered_cells`] (none for a mesh made here).
    pub fn into_mesh(self) -> Result<TetrahedronMesh> {
        let leaves = self.sorted_leaves();
        let lattice = corners(&leaves);
        let mut index: HashMap<[u64; 3], usize> =
            HashMap::with_capacity_and_hasher(lattice.len(), Default::default());
        let mut vertices: Vec<[f64; 3]> = Vec::with_capacity(lattice.len());
        let mut vertex = |p: [u64; 3], vertices: &mut Vec<[f64; 3]>| -> usize {
            *index.entry(p).or_insert_with(|| {
                vertices.push(self.point(p));
                vertices.len() - 1
            })
        };
        let mut cells: Vec<usize> = Vec::with_capacity(8 * leaves.len());
        let mut triangles: Vec<[[u64; 3]; 3]> = Vec::with_capacity(48);
        for cube in &leaves {
            let (c, h) = (cube.xyz(), cube.size());
            triangles.clear();
            let transition = cube_faces(c, h, &lattice, &mut triangles);
            if !transition {
                // The six Kuhn paths from the lowest corner, as `cuboid`'s.
                for path in KUHN_PATHS {
                    let mut p = c;
                    cells.push(vertex(p, &mut vertices));
                    for axis in path {
                        p[axis] += h;
                        cells.push(vertex(p, &mut vertices));
                    }
                }
            } else {
                let centre = vertex(c.map(|x| x + h / 2), &mut vertices);
                for t in &triangles {
                    cells.push(centre);
                    for &p in t {
                        cells.push(vertex(p, &mut vertices));
                    }
                }
            }
        }
        TetrahedronMesh::from_ordered_cells(vertices, cells)
    }
}

/// The corners of `leaves`: every one is a vertex of the mesh (a transition cube's centre
/// is one too).
fn corners(leaves: &[Cube]) -> HashSet<[u64; 3]> {
    let mut lattice: HashSet<[u64; 3]> =
        HashSet::with_capacity_and_hasher(2 * leaves.len(), Default::default());
    for cube in leaves {
        let (c, h) = (cube.xyz(), cube.size());
        for n in 0..8u64 {
            lattice.insert([
                c[0] + h * (n & 1),
                c[1] + h * ((n >> 1) & 1),
                c[2] + h * (n >> 2),
            ]);
        }
    }
    lattice
}

/// The triangles of the six faces of the cube at `c` with edge `h` by the face rule (module
/// docs), given the lattice points that are vertices; returns whether any face has a point
/// besides its corners (a transition cube: `triangles` then holds its faces' triangles;
/// otherwise the cube is cut into Kuhn tetrahedra and `triangles` is not needed).
fn cube_faces(
    c: [u64; 3],
    h: u64,
    lattice: &HashSet<[u64; 3]>,
    triangles: &mut Vec<[[u64; 3]; 3]>,
) -> bool {
    let half = h / 2;
    let mut transition = false;
    for normal in 0..3 {
        // The face's axes u < v.
        let (u, v) = match normal {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        for side in 0..2u64 {
            let at = |du: u64, dv: u64| {
                let mut p = c;
                p[normal] += side * h;
                p[u] += du;
                p[v] += dv;
                p
            };
            let present = |p: [u64; 3]| half > 0 && lattice.contains(&p);
            let centre = at(half, half);
            let mid = [
                at(half, 0), // the edge v = 0
                at(h, half), // u = h
                at(half, h), // v = h
                at(0, half), // u = 0
            ];
            let has = mid.map(present);
            if present(centre) {
                transition = true;
                // Four quarter squares, each along its lowest–highest diagonal.
                for (du, dv) in [(0, 0), (half, 0), (0, half), (half, half)] {
                    let q = |a: u64, b: u64| at(du + a, dv + b);
                    triangles.push([q(0, 0), q(half, 0), q(half, half)]);
                    triangles.push([q(0, 0), q(half, half), q(0, half)]);
                }
                continue;
            }
            if has.iter().any(|&x| x) {
                transition = true;
            }
            let (a, b) = (at(0, 0), at(h, h));
            // The triangle (a, corner, b) with legs a–corner (midpoint m1) and corner–b
            // (midpoint m2).
            let mut right =
                |corner: [u64; 3], m1: Option<[u64; 3]>, m2: Option<[u64; 3]>| match (m1, m2) {
                    (None, None) => triangles.push([a, corner, b]),
                    (Some(m1), None) => {
                        triangles.push([a, m1, b]);
                        triangles.push([m1, corner, b]);
                    }
                    (None, Some(m2)) => {
                        triangles.push([a, corner, m2]);
                        triangles.push([a, m2, b]);
                    }
                    (Some(m1), Some(m2)) => {
                        triangles.push([m1, corner, m2]);
                        triangles.push([a, m1, m2]);
                        triangles.push([a, m2, b]);
                    }
                };
            right(at(h, 0), has[0].then_some(mid[0]), has[1].then_some(mid[1]));
            right(at(0, h), has[3].then_some(mid[3]), has[2].then_some(mid[2]));
        }
    }
    transition
}
