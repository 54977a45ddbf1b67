//! Gmsh import: MSH 4.1 ASCII files with first-order triangles (`D = 2`) or tetrahedra
//! (`D = 3`); physical groups of boundary facets become boundary tags.
//!
//! The reader is self-contained (no dependency): it reads the sections `$MeshFormat`,
//! `$PhysicalNames`, `$Entities`, `$Nodes` and `$Elements` of the format's version 4.1
//! (Gmsh reference manual, "MSH file format") and skips all others. Every problem in a
//! file is an [`Error::Gmsh`] naming the line and section; no input panics.

mod coincident;
mod lexer;
mod sections;

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::path::Path;

use lexer::{error, Section};

use crate::mesh::SimplexMesh;
use crate::{Error, FaultNetwork, FaultSides, Result};

/// A physical group found in a Gmsh file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PhysicalGroup {
    /// Dimension of its entities (0 points, 1 curves, 2 surfaces, 3 volumes).
    pub dim: usize,
    /// Physical tag.
    pub tag: i32,
    /// Name from `$PhysicalNames`, or the tag in decimal if the group is unnamed.
    pub name: String,
    /// Number of elements of the file in the group (all element types read).
    pub num_elements: usize,
}

/// A mesh imported from Gmsh ([`read_gmsh`], [`parse_gmsh`]).
#[derive(Debug, Clone)]
pub struct GmshMesh<const D: usize> {
    /// The mesh: the file's dimension-`D` simplices as cells (reoriented where needed, the
    /// file's vertex order kept as refinement order, see
    /// [`SimplexMesh::from_ordered_cells`]); its boundary facets carry the names of the
    /// dimension-`(D − 1)` physical groups they belong to as tags.
    pub mesh: SimplexMesh<D>,
    /// All physical groups of the file, sorted by `(dim, tag)`.
    pub physical_groups: Vec<PhysicalGroup>,
    /// Gmsh node tag of every mesh vertex (vertices are numbered by increasing node tag;
    /// nodes used by no cell are dropped).
    pub node_tags: Vec<u64>,
    /// With [`GmshOptions::interior_facets`]: per physical group of dimension `D − 1`, its
    /// facets inside the body (vertex indices, in file order) — a fault inside the body
    /// ([`GmshMesh::split_along_group`]); empty otherwise.
    pub interior_facets: BTreeMap<String, Vec<[usize; D]>>,
}

/// How a Gmsh file is read ([`read_gmsh_with`], [`parse_gmsh_with`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GmshOptions {
    /// Merge nodes that coincide (closer than 10⁻⁶ times the smallest cell edge) into the
    /// one of the smallest tag, instead of refusing the file (default `false`: two nodes at
    /// one place are a crack along which the mesh falls apart; a fault inside the body is
    /// declared, not inferred from duplicate nodes).
    pub merge_coincident: bool,
    /// Keep the facets of physical groups that lie inside the body in
    /// [`GmshMesh::interior_facets`] (a fault inside the body, docs/faults-inside.md)
    /// instead of refusing them (default `false`: only boundary facets can be tagged).
    pub interior_facets: bool,
}

/// Reads a Gmsh MSH 4.1 ASCII file; see [`parse_gmsh`].
///
/// # Errors
/// [`Error::Io`] if the file cannot be read or is not a regular file (a FIFO, a device, a
/// folder: [`crate::input_file::open_regular`]); as [`parse_gmsh`], inside
/// [`Error::InFile`] naming the path.
pub fn read_gmsh<const D: usize>(path: impl AsRef<Path>) -> Result<GmshMesh<D>> {
    read_gmsh_with(path, GmshOptions::default())
}

/// Reads a Gmsh MSH 4.1 ASCII file with `options`; see [`parse_gmsh_with`].
///
/// # Errors
/// [`Error::Io`] if the file cannot be read or is not a regular file (a FIFO, a device, a
/// folder: [`crate::input_file::open_regular`]); as [`parse_gmsh_with`], inside
/// [`Error::InFile`] naming the path.
pub fn read_gmsh_with<const D: usize>(
    path: impl AsRef<Path>,
    options: GmshOptions,
) -> Result<GmshMesh<D>> {
    let path = path.as_ref();
    let io = |e: std::io::Error| Error::Io {
        path: rsf_numeric::excerpt(&path.display().to_string()),
        message: e.to_string(),
    };
    // A regular file only, read no further than its length when opened (a FIFO would
    // block, a device such as /dev/zero would be read until memory runs out).
    let (file, len) = crate::input_file::open_regular(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    std::io::Read::read_to_end(&mut std::io::Read::take(file, len), &mut bytes).map_err(io)?;
    parse_gmsh_with(&bytes, options).map_err(|e| Error::InFile {
        path: path.display().to_string(),
        inner: Box::new(e),
    })
}

/// Parses the contents of a Gmsh MSH 4.1 ASCII file into a `D`-dimensional mesh
/// (`D = 2`: triangles in the plane `z = 0`; `D = 3`: tetrahedra).
///
/// * Cells: all elements of dimension `D` (type 2 triangles or type 4 tetrahedra);
///   elements of lower dimension other than boundary facets are ignored.
/// * Tags: a boundary facet (a type 1 line in 2D, a type 2 triangle in 3D) that belongs
///   to a physical group of dimension `D − 1` is tagged with the group's name (groups are
///   applied in increasing physical tag order, so for a facet in several groups the last
///   one wins). Use [`crate::BoundaryPart::from_tag`] to get the part.
///
/// # Errors
/// [`Error::Gmsh`] (with line and section) for anything malformed or unsupported: another
/// MSH version, binary files, element types other than first-order points, lines,
/// triangles and tetrahedra (e.g. quadrilaterals or second-order elements), elements of
/// dimension above `D`, no cells, unknown or duplicate node tags, counts that do not match
/// the headers, non-finite coordinates, `z ≠ 0` in 2D, degenerate cells, coincident nodes
/// (naming both tags; [`GmshOptions::merge_coincident`] merges them instead), and facets
/// in a physical group that are not boundary facets of the mesh (interior facets cannot
/// be tagged); [`Error::Unsupported`] for `D = 1`.
pub fn parse_gmsh<const D: usize>(bytes: &[u8]) -> Result<GmshMesh<D>> {
    parse_gmsh_with(bytes, GmshOptions::default())
}

/// [`parse_gmsh`] with `options`.
///
/// # Errors
/// As [`parse_gmsh`].
pub fn parse_gmsh_with<const D: usize>(bytes: &[u8], options: GmshOptions) -> Result<GmshMesh<D>> {
    if !(D == 2 || D == 3) {
        return Err(Error::Unsupported("Gmsh import reads 2D and 3D meshes"));
    }
    let text = std::str::from_utf8(bytes).map_err(|e| not_text(bytes, e.valid_up_to()))?;
    let lines: Vec<&str> = text.lines().collect();
    let sections = lexer::sections(&lines)?;
    match sections.first() {
        Some(s) if s.name == "MeshFormat" => sections::mesh_format(s)?,
        _ => {
            return Err(error(
                Some(1),
                "file",
                "the file does not start with a `$MeshFormat` section",
            ))
        }
    }
    let mut names = BTreeMap::new();
    let mut physical = HashMap::new();
    let mut nodes = HashMap::new();
    let mut elements = None;
    let mut seen = HashSet::from(["MeshFormat"]);
    for s in &sections[1..] {
        let known = [
            "MeshFormat",
            "PhysicalNames",
            "Entities",
            "Nodes",
            "Elements",
        ];
        if known.contains(&s.name) && !seen.insert(s.name) {
            return Err(error(
                Some(s.first_line - 1),
                s.name,
                format!("section `${}` appears twice", s.name),
            ));
        }
        match s.name {
            "PhysicalNames" => sections::physical_names(s, &mut names)?,
            "Entities" => sections::entities(s, &mut physical)?,
            "Nodes" => sections::nodes(s, &mut nodes)?,
            "Elements" => elements = Some(sections::elements(s, D)?),
            _ => {}
        }
    }
    let elements =
        elements.ok_or_else(|| error(None, "file", "the file has no `$Elements` section"))?;
    build(&nodes, elements, &physical, &names, options)
}

/// The error for a file that is not UTF-8 text: binary files are reported as such (their
/// `$MeshFormat` header is text).
fn not_text(bytes: &[u8], valid: usize) -> Error {
    let prefix = std::str::from_utf8(&bytes[..valid]).expect("valid UTF-8 prefix");
    let lines: Vec<&str> = prefix.lines().collect();
    let start = lines.iter().position(|l| l.trim() == "$MeshFormat");
    let end = lines.iter().position(|l| l.trim() == "$EndMeshFormat");
    if let (Some(a), Some(b)) = (start, end) {
        if a < b {
            let header = Section {
                name: "MeshFormat",
                lines: &lines[a + 1..b],
                first_line: a + 2,
            };
            if let Err(e) = sections::mesh_format(&header) {
                return e;
            }
        }
    }
    let line = bytes[..valid].iter().filter(|&&b| b == b'\n').count() + 1;
    error(Some(line), "file", "the file is not UTF-8 text")
}

fn group_name(names: &BTreeMap<(usize, i32), String>, dim: usize, tag: i32) -> String {
    names
        .get(&(dim, tag))
        .cloned()
        .unwrap_or_else(|| tag.to_string())
}

fn build<const D: usize>(
    nodes: &HashMap<u64, [f64; 3]>,
    elements: sections::Elements,
    physical: &HashMap<(usize, i32), Vec<i32>>,
    names: &BTreeMap<(usize, i32), String>,
    options: GmshOptions,
) -> Result<GmshMesh<D>> {
    if let Some((line, dim)) = elements.higher {
        return Err(error(
            Some(line),
            "Elements",
            format!("the file has elements of dimension {dim}: read it as a {dim}-D mesh"),
        ));
    }
    let cells = &elements.cells;
    if cells.is_empty() {
        let what = if D == 2 { "triangles" } else { "tetrahedra" };
        return Err(error(
            None,
            "Elements",
            format!("the file has no {what} (elements of dimension {D})"),
        ));
    }
    for e in cells {
        if let Some(t) = e.nodes[..=D].iter().find(|t| !nodes.contains_key(t)) {
            return Err(error(
                Some(e.line),
                "Elements",
                format!(
                    "element {} refers to node {t}, which is not in `$Nodes`",
                    e.tag
                ),
            ));
        }
    }
    let mut node_tags: Vec<u64> = cells.iter().flat_map(|e| e.nodes[..=D].to_vec()).collect();
    node_tags.sort_unstable();
    node_tags.dedup();
    let mut index: HashMap<u64, usize> =
        node_tags.iter().enumerate().map(|(i, &t)| (t, i)).collect();
    let mut vertices = vertices::<D>(nodes, &node_tags)?;
    let mut connectivity: Vec<usize> = cells
        .iter()
        .flat_map(|e| e.nodes[..=D].iter().map(|t| index[t]))
        .collect();
    let rep = coincident::representatives(
        &node_tags,
        &vertices,
        &connectivity,
        options.merge_coincident,
    )?;
    if rep.iter().enumerate().any(|(i, &r)| r != i) {
        // Merged: the kept vertices renumbered in tag order, every tag to its kept one's.
        let mut new_index = vec![usize::MAX; rep.len()];
        let mut kept = 0;
        for (i, &r) in rep.iter().enumerate() {
            if r == i {
                new_index[i] = kept;
                kept += 1;
            }
        }
        for i in 0..rep.len() {
            new_index[i] = new_index[rep[i]];
        }
        for v in index.values_mut() {
            *v = new_index[*v];
        }
        for c in &mut connectivity {
            *c = new_index[*c];
        }
        let keep = |i: &usize| rep[*i] == *i;
        vertices = (0..rep.len()).filter(keep).map(|i| vertices[i]).collect();
        node_tags = (0..rep.len()).filter(keep).map(|i| node_tags[i]).collect();
    }
    let mut mesh =
        SimplexMesh::from_ordered_cells(vertices, connectivity).map_err(|e| match e {
            Error::DegenerateCell { cell, measure } => error(
                Some(cells[cell].line),
                "Elements",
                format!(
                    "element {} is degenerate (signed measure {measure:e})",
                    cells[cell].tag
                ),
            ),
            other => other,
        })?;
    let interior_facets = tag_facets(
        &mut mesh,
        &elements.facets,
        &index,
        physical,
        names,
        options.interior_facets,
    )?;
    Ok(GmshMesh {
        mesh,
        physical_groups: groups(physical, names, &elements.per_entity),
        node_tags,
        interior_facets,
    })
}

/// Coordinates of the used nodes; in 2D they must lie in the plane `z = 0`.
fn vertices<const D: usize>(nodes: &HashMap<u64, [f64; 3]>, tags: &[u64]) -> Result<Vec<[f64; D]>> {
    let mut extent: f64 = 0.0;
    for t in tags {
        for r in 0..D {
            extent = extent.max(nodes[t][r].abs());
        }
    }
    tags.iter()
        .map(|t| {
            let x = nodes[t];
            if D == 2 && x[2].abs() > 1e-12 * extent {
                return Err(error(
                    None,
                    "Nodes",
                    format!(
                        "node {t} has z = {:e}: a 2-D mesh must lie in the plane z = 0",
                        x[2]
                    ),
                ));
            }
            let mut v = [0.0; D];
            v.copy_from_slice(&x[..D]);
            Ok(v)
        })
        .collect()
}

/// Tags the boundary facets of the dimension-`(D − 1)` physical groups.
fn tag_facets<const D: usize>(
    mesh: &mut SimplexMesh<D>,
    facets: &[sections::Element],
    index: &HashMap<u64, usize>,
    physical: &HashMap<(usize, i32), Vec<i32>>,
    names: &BTreeMap<(usize, i32), String>,
    keep_interior: bool,
) -> Result<BTreeMap<String, Vec<[usize; D]>>> {
    let mut interior: BTreeMap<String, Vec<[usize; D]>> = BTreeMap::new();
    let key = |v: &mut dyn Iterator<Item = usize>| {
        let mut k = [usize::MAX; 3];
        for (slot, x) in k.iter_mut().zip(v) {
            *slot = x;
        }
        k.sort_unstable();
        k
    };
    let by_key: HashMap<[usize; 3], usize> = (0..mesh.num_boundary_facets())
        .map(|f| (key(&mut mesh.boundary_facet(f).iter().copied()), f))
        .collect();
    let mut groups: BTreeMap<i32, Vec<usize>> = BTreeMap::new();
    for e in facets {
        let Some(tags) = physical.get(&(D - 1, e.entity)).filter(|t| !t.is_empty()) else {
            continue;
        };
        let vs: Option<Vec<usize>> = e.nodes[..D].iter().map(|t| index.get(t).copied()).collect();
        if let (true, Some(vs)) = (keep_interior, &vs) {
            if !by_key.contains_key(&key(&mut vs.iter().copied())) {
                // Whether it is a facet of the mesh at all is checked when splitting.
                let mut f = [0; D];
                f.copy_from_slice(vs);
                for &p in tags {
                    interior
                        .entry(group_name(names, D - 1, p))
                        .or_default()
                        .push(f);
                }
                continue;
            }
        }
        let Some(f) = vs.and_then(|vs| by_key.get(&key(&mut vs.into_iter())).copied()) else {
            return Err(error(
                Some(e.line),
                "Elements",
                format!(
                    "element {} of physical group `{}` is not a boundary facet of the mesh \
                     (only boundary facets can be tagged)",
                    e.tag,
                    group_name(names, D - 1, tags[0])
                ),
            ));
        };
        for &p in tags {
            groups.entry(p).or_default().push(f);
        }
    }
    for (p, fs) in groups {
        mesh.tag_boundary_facets(&group_name(names, D - 1, p), &fs)?;
    }
    Ok(interior)
}

/// A fault of a network: its name and its facets (mesh vertices).
type NamedFacets<'a, const D: usize> = (&'a str, &'a [[usize; D]]);

impl<const D: usize> GmshMesh<D> {
    /// The interior facets of the physical group `group` (read with
    /// [`GmshOptions::interior_facets`]), in file order.
    ///
    /// # Errors
    /// [`Error::EmptyFault`] if the group has none.
    fn interior_group(&self, group: &str) -> Result<&[[usize; D]]> {
        let facets = self.interior_facets.get(group).ok_or(Error::EmptyFault)?;
        Ok(facets)
    }

    /// Each of `groups` with its [`interior_group`](Self::interior_group), in the order
    /// given: the faults of a network.
    ///
    /// # Errors
    /// As [`interior_group`](Self::interior_group).
    fn interior_groups<'a>(&'a self, groups: &[&'a str]) -> Result<Vec<NamedFacets<'a, D>>> {
        groups
            .iter()
            .map(|&g| Ok((g, self.interior_group(g)?)))
            .collect()
    }
}

impl GmshMesh<2> {
    /// Cuts the mesh open along the interior facets of the physical curve `group` (read
    /// with [`GmshOptions::interior_facets`]): [`SimplexMesh::split_along`] with the
    /// group's interior edges in file order (the first one's direction is the fault's).
    /// The group's boundary facets (if any) keep their tag.
    ///
    /// # Errors
    /// [`Error::EmptyFault`] if the group has no interior facets (or the file was read
    /// without [`GmshOptions::interior_facets`]); as [`SimplexMesh::split_along`].
    pub fn split_along_group(&self, group: &str) -> Result<(SimplexMesh<2>, FaultSides)> {
        self.mesh.split_along(group, self.interior_group(group)?)
    }

    /// Cuts the mesh open along the interior facets of several physical curves at once, a
    /// fault each ([`SimplexMesh::split_along_network`]: disjoint, a branch or a crossing),
    /// in the order given.
    ///
    /// # Errors
    /// [`Error::EmptyFault`] for a group without interior facets; as
    /// [`SimplexMesh::split_along_network`].
    pub fn split_along_groups(&self, groups: &[&str]) -> Result<(SimplexMesh<2>, FaultNetwork<2>)> {
        self.mesh
            .split_along_network(&self.interior_groups(groups)?)
    }

    /// The vertices (m) of the physical curve `group`'s interior facets in order along the
    /// fault ([`FaultSides::nodes`](crate::FaultSides::nodes) of
    /// [`split_along_group`](Self::split_along_group)): the polyline to give a model
    /// builder that refines the mesh first (each piece is one edge of this mesh, which
    /// uniform refinement splits along the straight piece).
    ///
    /// # Errors
    /// As [`split_along_group`](Self::split_along_group).
    pub fn interior_polyline(&self, group: &str) -> Result<Vec<[f64; 2]>> {
        let (split, sides) = self.split_along_group(group)?;
        Ok(sides
            .nodes()
            .iter()
            .map(|&(minus, _)| split.vertices()[minus])
            .collect())
    }
}

impl GmshMesh<3> {
    /// Cuts the mesh open along the interior facets of the physical surface `group` (read
    /// with [`GmshOptions::interior_facets`]): `SimplexMesh::<3>::split_along` with the
    /// group's interior triangles in file order (the first one's right-hand-rule normal is
    /// the fault's, pointing from the minus into the plus side). The group's boundary
    /// facets (if any) keep their tag.
    ///
    /// # Errors
    /// [`Error::EmptyFault`] if the group has no interior facets (or the file was read
    /// without [`GmshOptions::interior_facets`]); as `SimplexMesh::<3>::split_along`.
    pub fn split_along_group(&self, group: &str) -> Result<(SimplexMesh<3>, FaultSides<3>)> {
        self.mesh.split_along(group, self.interior_group(group)?)
    }

    /// Cuts the mesh open along the interior facets of several physical surfaces at once, a
    /// fault each (`SimplexMesh::<3>::split_along_network`: disjoint surfaces), in the
    /// order given.
    ///
    /// # Errors
    /// [`Error::EmptyFault`] for a group without interior facets; as
    /// `SimplexMesh::<3>::split_along_network`.
    pub fn split_along_groups(&self, groups: &[&str]) -> Result<(SimplexMesh<3>, FaultNetwork<3>)> {
        self.mesh
            .split_along_network(&self.interior_groups(groups)?)
    }
}

/// Every physical group named in `$PhysicalNames` or used by an entity, with its number
/// of elements.
fn groups(
    physical: &HashMap<(usize, i32), Vec<i32>>,
    names: &BTreeMap<(usize, i32), String>,
    per_entity: &HashMap<(usize, i32), usize>,
) -> Vec<PhysicalGroup> {
    let mut keys: BTreeSet<(usize, i32)> = names.keys().copied().collect();
    keys.extend(
        physical
            .iter()
            .flat_map(|(&(dim, _), tags)| tags.iter().map(move |&t| (dim, t))),
    );
    keys.into_iter()
        .map(|(dim, tag)| PhysicalGroup {
            dim,
            tag,
            name: group_name(names, dim, tag),
            num_elements: physical
                .iter()
                .filter(|(&(d, _), tags)| d == dim && tags.contains(&tag))
                .map(|(entity, _)| per_entity.get(entity).copied().unwrap_or(0))
                .sum(),
        })
        .collect()
}
