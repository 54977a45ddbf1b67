//! Several faults inside the body cut open at once — a fault network (docs/math.md §16,
//! docs/fault-networks.md): disjoint faults in 2-D and 3-D, and in 2-D a fault ending on
//! another that goes on through the vertex (a branch) or two faults crossing, whose shared
//! vertex becomes one copy per sector of the cells around it.
//!
//! A network of one fault is that fault cut alone ([`SimplexMesh::split_along`]), vertex
//! for vertex and facet for facet.

use std::collections::HashMap;

use crate::split::{
    add_at_vertices, add_plus_copy, cell_groups_around, check_fault_edge, edge_and_vertex_cells,
    facet_key, ordered_chain, tag_network_facets,
};
use crate::{Error, FaultSides, Result, SimplexMesh};

/// The faults of a network cut by `split_along_network`
/// ([`SimplexMesh::<2>::split_along_network`](SimplexMesh::split_along_network), and its
/// 3-D counterpart): every fault's sides ([`FaultSides`], in the order the faults were
/// given, each with its own tags `{name}_minus`, `{name}_plus`) and the junctions where
/// two of them meet.
///
/// Vertex indices of the split mesh: the vertices of the unsplit mesh keep theirs; the new
/// copies are appended fault by fault, each in the order of its own cut (2-D: along the
/// fault; 3-D: increasing vertex), a junction's copies when its first fault reaches it.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultNetwork<const D: usize = 2> {
    pub(crate) faults: Vec<FaultSides<D>>,
    pub(crate) junctions: Vec<Junction>,
}

/// How two faults meet at a [`Junction`] (2-D), by their indices in the network.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JunctionKind {
    /// Fault `ending` ends on fault `through`, which goes on through the vertex: three
    /// sectors — the far side of `through`, and its near side cut in two by `ending`.
    Branch {
        /// The fault going on through the junction.
        through: usize,
        /// The fault ending there.
        ending: usize,
    },
    /// Faults `first` and `second` (network order) both go on through the vertex: four
    /// sectors, one per pair of sides.
    Crossing {
        /// The earlier fault of the network.
        first: usize,
        /// The later one.
        second: usize,
    },
}

impl JunctionKind {
    /// The two faults: `[through, ending]` of a branch, `[first, second]` of a crossing.
    pub fn faults(&self) -> [usize; 2] {
        match *self {
            JunctionKind::Branch { through, ending } => [through, ending],
            JunctionKind::Crossing { first, second } => [first, second],
        }
    }
}

/// A vertex where two faults of a 2-D network meet, cut into one copy per sector of the
/// cells around it (docs/math.md §16).
#[derive(Debug, Clone, PartialEq)]
pub struct Junction {
    pub(crate) vertex: usize,
    pub(crate) kind: JunctionKind,
    pub(crate) sectors: Vec<(usize, [i8; 2])>,
}

impl Junction {
    /// The vertex of the unsplit mesh (one of the copies keeps its index).
    pub fn vertex(&self) -> usize {
        self.vertex
    }
    /// How the two faults meet.
    pub fn kind(&self) -> JunctionKind {
        self.kind
    }
    /// Every sector as `(copy, sides)`: the vertex of the split mesh its cells use, and its
    /// side of the two faults of [`JunctionKind::faults`] (`−1` the fault's minus side, `+1`
    /// its plus side, `0` for the sector of a branch on the far side of the going-through
    /// fault, which the ending fault does not touch). Sorted by `sides` (−1 < 0 < +1,
    /// first fault first); the first sector keeps [`vertex`](Self::vertex). A branch has
    /// three sectors, a crossing four.
    pub fn sectors(&self) -> &[(usize, [i8; 2])] {
        &self.sectors
    }
}

impl<const D: usize> FaultNetwork<D> {
    /// A network of one fault.
    pub(crate) fn single(sides: FaultSides<D>) -> Self {
        Self {
            faults: vec![sides],
            junctions: Vec::new(),
        }
    }
    /// The faults, in the order given.
    pub fn faults(&self) -> &[FaultSides<D>] {
        &self.faults
    }
    /// The junctions, in the order the cut reached them.
    pub fn junctions(&self) -> &[Junction] {
        &self.junctions
    }
    /// The index of the fault named `name`.
    pub fn fault_index(&self, name: &str) -> Option<usize> {
        self.faults.iter().position(|f| f.name() == name)
    }
    /// Every split pair `(minus, plus)` of every fault, fault after fault (each in the order
    /// of [`FaultSides::pairs`]; junctions left out).
    pub fn pairs(&self) -> Vec<(usize, usize)> {
        self.faults.iter().flat_map(FaultSides::pairs).collect()
    }
}

/// Refuses repeated fault names.
fn check_names(names: &[&str]) -> Result<()> {
    for (i, name) in names.iter().enumerate() {
        if names[..i].contains(name) {
            return Err(Error::FaultNameRepeated {
                name: (*name).to_owned(),
            });
        }
    }
    Ok(())
}

impl SimplexMesh<2> {
    /// Cuts the mesh open along several faults at once, each given as its name and mesh
    /// edges `[a, b]` as for [`SimplexMesh::split_along`] (the direction of a fault's first
    /// edge sets its direction and sides). Faults may be disjoint, one may end on another
    /// that goes on through the vertex (a **branch**: the vertex is cut into three copies),
    /// or two may cross (both going through: four copies); each fault's faces get its own
    /// tags `{name}_minus`, `{name}_plus`. One fault is [`SimplexMesh::split_along`]'s cut,
    /// to the vertex.
    ///
    /// # Errors
    /// [`Error::EmptyFault`] for no fault or a fault without edges;
    /// [`Error::FaultNameRepeated`]; [`Error::FaultEdgeShared`] for an edge of two faults;
    /// each fault's errors of [`SimplexMesh::split_along`];
    /// [`Error::FaultJunctionUnsupported`] for faults meeting otherwise than in a branch or
    /// a crossing inside the body (two faults ending at one vertex, three or more faults at
    /// a vertex, a junction on the outer boundary).
    ///
    /// ```
    /// use rsf_fem::{rectangle, Diagonal, JunctionKind};
    /// // A 2 m square with vertices on a 0.25 m grid (vertex i + 9 j at (-1 + i/4, -1 + j/4)):
    /// // a fault along y = 0 from x = -0.5 to 0.5, a branch going up from its middle.
    /// let mesh = rectangle([-1.0, -1.0], [2.0, 2.0], 9, 9, Diagonal::Forward)?;
    /// let id = |i: usize, j: usize| i + 9 * j;
    /// let main: Vec<[usize; 2]> = (2..6).map(|i| [id(i, 4), id(i + 1, 4)]).collect();
    /// let branch: Vec<[usize; 2]> = (4..6).map(|j| [id(4, j), id(4, j + 1)]).collect();
    /// let (split, network) =
    ///     mesh.split_along_network(&[("main", &main[..]), ("branch", &branch[..])])?;
    /// let junction = &network.junctions()[0];
    /// assert_eq!(junction.kind(), JunctionKind::Branch { through: 0, ending: 1 });
    /// assert_eq!(junction.sectors().len(), 3);
    /// // main: 2 split pairs, the junction and 2 tips; branch: the junction, 1 split pair
    /// // and a tip.
    /// assert_eq!(network.faults()[0].pairs().len(), 2);
    /// assert_eq!(split.num_vertices(), mesh.num_vertices() + 2 + 1 + 2);
    /// # Ok::<(), rsf_fem::Error>(())
    /// ```
    pub fn split_along_network(
        &self,
        faults: &[(&str, &[[usize; 2]])],
    ) -> Result<(Self, FaultNetwork<2>)> {
        let names: Vec<&str> = faults.iter().map(|f| f.0).collect();
        check_names(&names)?;
        match faults {
            [] => Err(Error::EmptyFault),
            [(name, edges)] => {
                let (split, sides) = self.split_along(name, edges)?;
                Ok((split, FaultNetwork::single(sides)))
            }
            _ => Cut2d::new(self, faults)?.split(),
        }
    }

    /// [`split_along_network`](Self::split_along_network) for faults each given as its name
    /// and a polyline (m) as for
    /// [`split_along_polyline`](SimplexMesh::split_along_polyline).
    ///
    /// # Errors
    /// As [`split_along_polyline`](SimplexMesh::split_along_polyline) per fault, and as
    /// [`split_along_network`](Self::split_along_network).
    pub fn split_along_polylines(
        &self,
        faults: &[(&str, &[[f64; 2]])],
    ) -> Result<(Self, FaultNetwork<2>)> {
        let edges = faults
            .iter()
            .map(|(_, points)| self.edges_along_polyline(points))
            .collect::<Result<Vec<_>>>()?;
        let given: Vec<(&str, &[[usize; 2]])> = faults
            .iter()
            .zip(&edges)
            .map(|((name, _), e)| (*name, &e[..]))
            .collect();
        self.split_along_network(&given)
    }
}

impl SimplexMesh<3> {
    /// Cuts the mesh open along several disjoint faults at once, each given as its name and
    /// mesh faces as for `SimplexMesh::<3>::split_along` (the first face's right-hand-rule
    /// normal sets a fault's orientation); each fault's faces get its own tags. Faults may
    /// not share a vertex in 3-D (junctions of surfaces are not supported). One fault is
    /// `split_along`'s cut, to the vertex; several are the faults cut one after another.
    ///
    /// # Errors
    /// [`Error::EmptyFault`]; [`Error::FaultNameRepeated`];
    /// [`Error::FaultJunctionUnsupported`] naming the first vertex two faults share; each
    /// fault's errors of `split_along`.
    pub fn split_along_network(
        &self,
        faults: &[(&str, &[[usize; 3]])],
    ) -> Result<(Self, FaultNetwork<3>)> {
        let names: Vec<&str> = faults.iter().map(|f| f.0).collect();
        check_names(&names)?;
        let mut owner: HashMap<usize, usize> = HashMap::new();
        for (f, (_, faces)) in faults.iter().enumerate() {
            for &v in faces.iter().flatten() {
                match owner.insert(v, f) {
                    Some(g) if g != f => {
                        return Err(Error::FaultJunctionUnsupported {
                            faults: vec![names[g].to_owned(), names[f].to_owned()],
                            vertex: v,
                            position: self.vertices().get(v).map_or(Vec::new(), |x| x.to_vec()),
                            reason: "faults of a 3-D network may not share a vertex \
                                     (junctions of fault surfaces are not supported)",
                        })
                    }
                    _ => {}
                }
            }
        }
        let Some(((name, faces), rest)) = faults.split_first() else {
            return Err(Error::EmptyFault);
        };
        let (mut mesh, first) = self.split_along(name, faces)?;
        let mut sides = vec![first];
        // Each fault's facets by their vertices, to find them again once the later faults
        // are cut (the boundary facets are numbered anew by every cut).
        let keys = |mesh: &SimplexMesh<3>, facets: &[usize]| -> Vec<Option<[usize; 3]>> {
            facets
                .iter()
                .map(|&f| (f != usize::MAX).then(|| facet_key(mesh.boundary_facet(f))))
                .collect()
        };
        let mut facet_keys = vec![(
            keys(&mesh, sides[0].minus_facets()),
            keys(&mesh, sides[0].plus_facets()),
        )];
        for (name, faces) in rest {
            let (next, s) = mesh.split_along(name, faces)?;
            mesh = next;
            facet_keys.push((keys(&mesh, s.minus_facets()), keys(&mesh, s.plus_facets())));
            sides.push(s);
        }
        let index: HashMap<[usize; 3], usize> = (0..mesh.num_boundary_facets())
            .map(|f| (facet_key(mesh.boundary_facet(f)), f))
            .collect();
        let find = |keys: &[Option<[usize; 3]>]| -> Vec<usize> {
            keys.iter()
                .map(|k| k.map_or(usize::MAX, |k| index[&k]))
                .collect()
        };
        for (s, (minus, plus)) in sides.iter_mut().zip(&facet_keys) {
            s.minus_facets = find(minus);
            s.plus_facets = find(plus);
        }
        Ok((
            mesh,
            FaultNetwork {
                faults: sides,
                junctions: Vec::new(),
            },
        ))
    }

    /// [`split_along_network`](Self::split_along_network) for faults each given as its
    /// name and a planar polygon (m) as for `SimplexMesh::<3>::split_along_polygon`.
    ///
    /// # Errors
    /// As `split_along_polygon` per fault, and as
    /// [`split_along_network`](Self::split_along_network).
    pub fn split_along_polygons(
        &self,
        faults: &[(&str, &[[f64; 3]])],
    ) -> Result<(Self, FaultNetwork<3>)> {
        let faces = faults
            .iter()
            .map(|(_, corners)| self.faces_in_polygon(corners))
            .collect::<Result<Vec<_>>>()?;
        let given: Vec<(&str, &[[usize; 3]])> = faults
            .iter()
            .zip(&faces)
            .map(|((name, _), f)| (*name, &f[..]))
            .collect();
        self.split_along_network(&given)
    }
}

/// A 2-D network being cut: the mesh's adjacency and every fault's chain.
struct Cut2d<'a> {
    mesh: &'a SimplexMesh<2>,
    names: Vec<&'a str>,
    edge_cells: HashMap<(usize, usize), Vec<usize>>,
    vertex_cells: Vec<Vec<usize>>,
    /// Every fault edge (its vertices in increasing order) → its fault.
    fault_edge: HashMap<(usize, usize), usize>,
    /// Every fault's vertices in order along it.
    chains: Vec<Vec<usize>>,
    on_boundary: Vec<bool>,
}

/// The faults at a vertex: `(fault, position in its chain)`.
type AtVertex = Vec<(usize, usize)>;

impl<'a> Cut2d<'a> {
    /// The mesh's adjacency and the faults' edges validated and chained.
    fn new(mesh: &'a SimplexMesh<2>, faults: &[(&'a str, &[[usize; 2]])]) -> Result<Self> {
        let nv = mesh.num_vertices();
        let key = |a: usize, b: usize| (a.min(b), a.max(b));
        let (edge_cells, vertex_cells) = edge_and_vertex_cells(mesh);
        let names: Vec<&str> = faults.iter().map(|f| f.0).collect();
        let mut fault_edge: HashMap<(usize, usize), usize> = HashMap::new();
        let mut chains = Vec::with_capacity(faults.len());
        for (f, (_, edges)) in faults.iter().enumerate() {
            if edges.is_empty() {
                return Err(Error::EmptyFault);
            }
            let mut at_vertex: HashMap<usize, Vec<usize>> = HashMap::new();
            for (i, &[a, b]) in edges.iter().enumerate() {
                check_fault_edge(&edge_cells, nv, i, [a, b])?;
                let vertices = [a, b];
                match fault_edge.insert(key(a, b), f) {
                    Some(g) if g == f => {
                        return Err(Error::FaultEdgeRepeated { edge: i, vertices })
                    }
                    Some(g) => {
                        return Err(Error::FaultEdgeShared {
                            edge: i,
                            vertices,
                            first: names[g].to_owned(),
                            second: names[f].to_owned(),
                        })
                    }
                    None => {}
                }
                add_at_vertices(&mut at_vertex, i, [a, b])?;
            }
            chains.push(ordered_chain(edges, &at_vertex)?);
        }
        let mut on_boundary = vec![false; nv];
        for f in 0..mesh.num_boundary_facets() {
            for &v in mesh.boundary_facet(f) {
                on_boundary[v] = true;
            }
        }
        Ok(Self {
            mesh,
            names,
            edge_cells,
            vertex_cells,
            fault_edge,
            chains,
            on_boundary,
        })
    }

    /// The cell left of the directed edge `(a, b)`: its counter-clockwise order has `a`
    /// then `b` (the plus side of a fault running from `a` to `b`).
    fn left_cell(&self, a: usize, b: usize) -> usize {
        *self.edge_cells[&(a.min(b), a.max(b))]
            .iter()
            .find(|&&c| {
                let cell = self.mesh.cell(c);
                (0..3).any(|k| cell[k] == a && cell[(k + 1) % 3] == b)
            })
            .expect("an interior edge has a cell on each side")
    }

    /// Fault `f`'s directed edges at position `i` of its chain (one at an end, two inside).
    fn half_edges(&self, f: usize, i: usize) -> Vec<(usize, usize)> {
        let chain = &self.chains[f];
        let mut out = Vec::with_capacity(2);
        if i > 0 {
            out.push((chain[i - 1], chain[i]));
        }
        if i + 1 < chain.len() {
            out.push((chain[i], chain[i + 1]));
        }
        out
    }

    fn unsupported(&self, p: usize, at: &AtVertex, reason: &'static str) -> Error {
        Error::FaultJunctionUnsupported {
            faults: at.iter().map(|&(f, _)| self.names[f].to_owned()).collect(),
            vertex: p,
            position: self.mesh.vertices()[p].to_vec(),
            reason,
        }
    }

    /// Cuts the mesh: every fault's nodes along it, pairs and tips as a fault alone,
    /// junctions once.
    fn split(self) -> Result<(SimplexMesh<2>, FaultNetwork<2>)> {
        let mut at: HashMap<usize, AtVertex> = HashMap::new();
        for (f, chain) in self.chains.iter().enumerate() {
            for (i, &p) in chain.iter().enumerate() {
                at.entry(p).or_default().push((f, i));
            }
        }
        let mut cells = self.mesh.cells().to_vec();
        let mut vertices = self.mesh.vertices().to_vec();
        let mut original: Vec<usize> = (0..self.mesh.num_vertices()).collect();
        let mut junction_at: HashMap<usize, usize> = HashMap::new();
        let mut junctions: Vec<Junction> = Vec::new();
        let mut nodes: Vec<Vec<(usize, usize)>> = vec![Vec::new(); self.chains.len()];
        let mut junction_nodes: Vec<Vec<usize>> = vec![Vec::new(); self.chains.len()];
        let mut copies = Copies {
            cells: &mut cells,
            vertices: &mut vertices,
            original: &mut original,
        };
        for (f, chain) in self.chains.iter().enumerate() {
            for (i, &p) in chain.iter().enumerate() {
                let here = &at[&p];
                if here.len() == 1 {
                    nodes[f].push(self.cut_alone(f, i, &mut copies)?);
                    continue;
                }
                if let std::collections::hash_map::Entry::Vacant(e) = junction_at.entry(p) {
                    junctions.push(self.cut_junction(p, here, &mut copies)?);
                    e.insert(junctions.len() - 1);
                }
                // This fault's sides at its first edge at p.
                let (a, b) = self.half_edges(f, i)[0];
                let copy_in = |c: usize| copies.copy_in_cell(c, p);
                nodes[f].push((copy_in(self.left_cell(b, a)), copy_in(self.left_cell(a, b))));
                junction_nodes[f].push(i);
            }
        }
        let mut split = SimplexMesh::new(vertices, cells)?;
        split.copy_refinement_orders(self.mesh);
        let mut fault_faces: HashMap<[usize; 3], (usize, usize)> = HashMap::new();
        let mut plus_cells = Vec::with_capacity(self.chains.len());
        for (f, chain) in self.chains.iter().enumerate() {
            for k in 0..chain.len() - 1 {
                fault_faces.insert(facet_key(&[chain[k], chain[k + 1]]), (f, k));
            }
            plus_cells.push(
                chain
                    .windows(2)
                    .map(|w| self.left_cell(w[0], w[1]))
                    .collect::<Vec<_>>(),
            );
        }
        let facets = tag_network_facets(
            self.mesh,
            &mut split,
            &self.names,
            &original,
            &fault_faces,
            &plus_cells,
        );
        let x = self.mesh.vertices();
        let faults = self
            .chains
            .iter()
            .zip(facets)
            .zip(nodes.into_iter().zip(junction_nodes))
            .zip(&self.names)
            .map(
                |(((chain, (minus_facets, plus_facets)), (nodes, junction_nodes)), name)| {
                    FaultSides {
                        name: (*name).to_owned(),
                        nodes,
                        minus_facets,
                        plus_facets,
                        normals: chain
                            .windows(2)
                            .map(|w| {
                                let t = [x[w[1]][0] - x[w[0]][0], x[w[1]][1] - x[w[0]][1]];
                                let l = t[0].hypot(t[1]);
                                [-t[1] / l, t[0] / l]
                            })
                            .collect(),
                        junction_nodes,
                    }
                },
            )
            .collect();
        Ok((split, FaultNetwork { faults, junctions }))
    }

    /// The node at position `i` of fault `f`'s chain where no other fault is: a tip (an end
    /// inside the body) or a pair (as [`SimplexMesh::split_along`]).
    fn cut_alone(&self, f: usize, i: usize, copies: &mut Copies<'_>) -> Result<(usize, usize)> {
        let chain = &self.chains[f];
        let p = chain[i];
        let m = chain.len() - 1;
        let end = i == 0 || i == m;
        if end && !self.on_boundary[p] {
            return Ok((p, p));
        }
        if !end && self.on_boundary[p] {
            return Err(Error::FaultSidesNotSeparated { vertex: p });
        }
        let around = &self.vertex_cells[p];
        let (group, groups) = self.groups_around(p);
        let (ea, eb) = if i < m {
            (chain[i], chain[i + 1])
        } else {
            (chain[i - 1], chain[i])
        };
        let plus_cell = self.left_cell(ea, eb);
        let minus_cell = self.left_cell(eb, ea);
        let g = |c: usize| group[around.iter().position(|&x| x == c).expect("cell at p")];
        if groups != 2 || g(plus_cell) == g(minus_cell) {
            return Err(Error::FaultSidesNotSeparated { vertex: p });
        }
        let q = copies.add(p, around, &group, g(plus_cell));
        Ok((p, q))
    }

    /// The groups of the cells around `p` separated by any fault's edges.
    fn groups_around(&self, p: usize) -> (Vec<usize>, usize) {
        cell_groups_around(self.mesh, p, &self.vertex_cells[p], |k| {
            self.fault_edge.contains_key(&(k[0], k[1]))
        })
    }

    /// Cuts the junction at vertex `p` of the faults `at`: one copy per sector.
    fn cut_junction(&self, p: usize, at: &AtVertex, copies: &mut Copies<'_>) -> Result<Junction> {
        if at.len() > 2 {
            return Err(self.unsupported(p, at, "more than two faults meet at one vertex"));
        }
        if self.on_boundary[p] {
            return Err(self.unsupported(
                p,
                at,
                "faults meet on the outer boundary (a junction must be inside the body)",
            ));
        }
        let through = |&(f, i): &(usize, usize)| i > 0 && i + 1 < self.chains[f].len();
        let kind = match (through(&at[0]), through(&at[1])) {
            (true, true) => JunctionKind::Crossing {
                first: at[0].0,
                second: at[1].0,
            },
            (true, false) => JunctionKind::Branch {
                through: at[0].0,
                ending: at[1].0,
            },
            (false, true) => JunctionKind::Branch {
                through: at[1].0,
                ending: at[0].0,
            },
            (false, false) => {
                return Err(self.unsupported(
                    p,
                    at,
                    "two faults end at one vertex (give them as one fault, or apart)",
                ))
            }
        };
        let position = |f: usize| at.iter().find(|x| x.0 == f).expect("a fault here").1;
        let around = &self.vertex_cells[p];
        let (group, groups) = self.groups_around(p);
        let g = |c: usize| group[around.iter().position(|&x| x == c).expect("cell at p")];
        // Every group's side of the two faults, from the cells beside their edges at p.
        let mut sides = vec![[0i8; 2]; groups];
        for (slot, &f) in kind.faults().iter().enumerate() {
            for (a, b) in self.half_edges(f, position(f)) {
                for (cell, side) in [(self.left_cell(a, b), 1i8), (self.left_cell(b, a), -1)] {
                    let s = &mut sides[g(cell)][slot];
                    if *s == -side {
                        return Err(Error::FaultSidesNotSeparated { vertex: p });
                    }
                    *s = side;
                }
            }
        }
        let expected = match kind {
            JunctionKind::Branch { .. } => 3,
            JunctionKind::Crossing { .. } => 4,
        };
        let mut order: Vec<usize> = (0..groups).collect();
        order.sort_by_key(|&k| sides[k]);
        let patterns: Vec<[i8; 2]> = order.iter().map(|&k| sides[k]).collect();
        let valid = match kind {
            // The far side of `through` (not touching `ending`), and its near side cut in
            // two by `ending`.
            JunctionKind::Branch { .. } => {
                groups == expected
                    && patterns.iter().filter(|s| s[1] == 0).count() == 1
                    && patterns.iter().all(|s| s[0] != 0)
                    && {
                        let far = patterns.iter().find(|s| s[1] == 0).expect("one")[0];
                        let near: Vec<&[i8; 2]> = patterns.iter().filter(|s| s[1] != 0).collect();
                        near[0][0] == -far && near[1][0] == -far && near[0][1] == -near[1][1]
                    }
            }
            JunctionKind::Crossing { .. } => {
                groups == expected && patterns == [[-1, -1], [-1, 1], [1, -1], [1, 1]]
            }
        };
        if !valid {
            return Err(Error::FaultSidesNotSeparated { vertex: p });
        }
        let mut sectors = Vec::with_capacity(groups);
        for (n, &k) in order.iter().enumerate() {
            let copy = if n == 0 {
                p
            } else {
                copies.add(p, around, &group, k)
            };
            sectors.push((copy, sides[k]));
        }
        Ok(Junction {
            vertex: p,
            kind,
            sectors,
        })
    }
}

/// The split mesh being built: cells renumbered to new vertex copies.
struct Copies<'c> {
    cells: &'c mut Vec<usize>,
    vertices: &'c mut Vec<[f64; 2]>,
    original: &'c mut Vec<usize>,
}

impl Copies<'_> {
    /// A new copy of `p` for the cells around it (`around`) in group `g` of `group`.
    fn add(&mut self, p: usize, around: &[usize], group: &[usize], g: usize) -> usize {
        let q = add_plus_copy(p, around, group, g, self.vertices, self.cells);
        self.original.push(p);
        q
    }

    /// The copy of `p` that cell `c` uses.
    fn copy_in_cell(&self, c: usize, p: usize) -> usize {
        *self.cells[3 * c..3 * c + 3]
            .iter()
            .find(|&&v| self.original[v] == p)
            .expect("the cell holds a copy of p")
    }
}
