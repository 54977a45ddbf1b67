//! The sections rsf-fem reads: `$MeshFormat`, `$PhysicalNames`, `$Entities`, `$Nodes`,
//! `$Elements` (Gmsh reference manual, "MSH file format", version 4.1).

use std::collections::{BTreeMap, HashMap};

use super::lexer::{error, Cursor, Section};
use crate::Error;

/// Element types read: `(Gmsh type, dimension, number of nodes)`.
const TYPES: [(i32, usize, usize); 4] = [(15, 0, 1), (1, 1, 2), (2, 2, 3), (4, 3, 4)];

/// Checks `$MeshFormat`: version 4.1, ASCII.
pub(super) fn mesh_format(s: &Section<'_>) -> Result<(), Error> {
    let mut c = Cursor::new(s);
    let version = c.token("the format version")?;
    if version != "4.1" {
        return Err(c.error(format!(
            "MSH version `{}` is not supported: save as MSH 4.1 (gmsh -format msh41)",
            super::lexer::echo(version)
        )));
    }
    match c.int("the file type")? {
        0 => {}
        1 => {
            return Err(c.error(
                "binary MSH files are not supported: save as ASCII (Mesh.Binary = 0, or \
                 gmsh -format msh41 without -bin)",
            ))
        }
        t => return Err(c.error(format!("file type must be 0 (ASCII) or 1, found {t}"))),
    }
    c.count("the data size")?;
    c.finish()
}

/// `$PhysicalNames`: `(dimension, physical tag) → name`.
pub(super) fn physical_names(
    s: &Section<'_>,
    names: &mut BTreeMap<(usize, i32), String>,
) -> Result<(), Error> {
    let mut c = Cursor::new(s);
    let n = c.count("the number of physical names")?;
    for _ in 0..n {
        let dim = dimension(&mut c, "a physical group's dimension")?;
        let tag = c.int("a physical tag")?;
        let rest = c.rest_of_line();
        let name = rest
            .strip_prefix('"')
            .and_then(|r| r.strip_suffix('"'))
            .filter(|r| !r.contains('"'))
            .ok_or_else(|| c.error("expected a physical name in double quotes"))?;
        if names.insert((dim, tag), name.to_owned()).is_some() {
            return Err(c.error(format!("physical group ({dim}, {tag}) is named twice")));
        }
    }
    c.finish()
}

fn dimension(c: &mut Cursor<'_>, what: &str) -> Result<usize, Error> {
    let d = c.int(what)?;
    usize::try_from(d)
        .ok()
        .filter(|&d| d <= 3)
        .ok_or_else(|| c.error(format!("{what} must be 0, 1, 2 or 3, found {d}")))
}

/// The header of a `$Nodes` or `$Elements` section (`item` "node" or "element"): the
/// number of entity blocks and of items; the smallest and largest tag are read and not
/// kept.
fn block_header(c: &mut Cursor<'_>, item: &str) -> Result<(usize, usize), Error> {
    let blocks = c.count("the number of entity blocks")?;
    let total = c.count(&format!("the number of {item}s"))?;
    c.count(&format!("the minimum {item} tag"))?;
    c.count(&format!("the maximum {item} tag"))?;
    Ok((blocks, total))
}

/// `$Entities`: `(dimension, entity tag) → physical tags`.
pub(super) fn entities(
    s: &Section<'_>,
    physical: &mut HashMap<(usize, i32), Vec<i32>>,
) -> Result<(), Error> {
    let mut c = Cursor::new(s);
    let mut counts = [0usize; 4];
    for (d, n) in counts.iter_mut().enumerate() {
        *n = c.count(
            [
                "the number of points",
                "the number of curves",
                "the number of surfaces",
                "the number of volumes",
            ][d],
        )?;
    }
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            let tag = c.int("an entity tag")?;
            // A point has its coordinates, the others their bounding box.
            for _ in 0..if dim == 0 { 3 } else { 6 } {
                c.float("a coordinate")?;
            }
            let np = c.count("the number of physical tags")?;
            let mut tags = Vec::new();
            for _ in 0..np {
                tags.push(c.int("a physical tag")?);
            }
            if dim > 0 {
                let nb = c.count("the number of bounding entities")?;
                for _ in 0..nb {
                    c.int("a bounding entity tag")?;
                }
            }
            if physical.insert((dim, tag), tags).is_some() {
                return Err(c.error(format!("entity ({dim}, {tag}) is listed twice")));
            }
        }
    }
    c.finish()
}

/// `$Nodes`: node tag → coordinates.
pub(super) fn nodes(s: &Section<'_>, out: &mut HashMap<u64, [f64; 3]>) -> Result<(), Error> {
    let mut c = Cursor::new(s);
    let (blocks, total) = block_header(&mut c, "node")?;
    let mut tags = Vec::new();
    for _ in 0..blocks {
        let dim = dimension(&mut c, "an entity dimension")?;
        c.int("an entity tag")?;
        let parametric = match c.int("the parametric flag")? {
            0 => false,
            1 => true,
            p => return Err(c.error(format!("parametric flag must be 0 or 1, found {p}"))),
        };
        let n = c.count("the number of nodes in the block")?;
        tags.clear();
        for _ in 0..n {
            tags.push(c.tag("a node tag")?);
        }
        for &t in &tags {
            let x = [
                c.float("an x coordinate")?,
                c.float("a y coordinate")?,
                c.float("a z coordinate")?,
            ];
            if parametric {
                for _ in 0..dim {
                    c.float("a parametric coordinate")?;
                }
            }
            if out.insert(t, x).is_some() {
                return Err(c.error(format!("node tag {t} appears twice")));
            }
        }
    }
    if out.len() != total {
        return Err(c.error(format!(
            "the header announces {total} nodes, the blocks hold {}",
            out.len()
        )));
    }
    c.finish()
}

/// A simplex element of the file.
#[derive(Debug, Clone)]
pub(super) struct Element {
    pub(super) tag: u64,
    /// Node tags (first `dim + 1` used).
    pub(super) nodes: [u64; 4],
    /// Entity tag of its block.
    pub(super) entity: i32,
    /// 1-based line of its definition.
    pub(super) line: usize,
}

/// What `$Elements` contributes: the elements of dimension `D` (cells) and `D − 1`
/// (facets), and the number of elements per `(dimension, entity)`.
#[derive(Debug, Default)]
pub(super) struct Elements {
    pub(super) cells: Vec<Element>,
    pub(super) facets: Vec<Element>,
    pub(super) per_entity: HashMap<(usize, i32), usize>,
    /// Line of an element of dimension > D, if any.
    pub(super) higher: Option<(usize, usize)>,
}

/// `$Elements`, keeping the dimension-`d` and `d − 1` simplices.
pub(super) fn elements(s: &Section<'_>, d: usize) -> Result<Elements, Error> {
    let mut c = Cursor::new(s);
    let (blocks, total) = block_header(&mut c, "element")?;
    let mut out = Elements::default();
    let mut seen = 0usize;
    for _ in 0..blocks {
        let dim = dimension(&mut c, "an entity dimension")?;
        let entity = c.int("an entity tag")?;
        let ty = c.int("an element type")?;
        let Some(&(_, tdim, nn)) = TYPES.iter().find(|t| t.0 == ty) else {
            return Err(c.error(format!(
                "element type {ty} is not supported: rsf-fem reads first-order simplices \
                 (types 15 point, 1 line, 2 triangle, 4 tetrahedron)"
            )));
        };
        if tdim != dim {
            return Err(c.error(format!(
                "element type {ty} has dimension {tdim}, but its block's entity has dimension {dim}"
            )));
        }
        let n = c.count("the number of elements in the block")?;
        for _ in 0..n {
            let tag = c.tag("an element tag")?;
            let line = c.token_line();
            let mut nodes = [0u64; 4];
            for v in nodes.iter_mut().take(nn) {
                *v = c.tag("a node tag of an element")?;
            }
            let e = Element {
                tag,
                nodes,
                entity,
                line,
            };
            if dim == d {
                out.cells.push(e);
            } else if dim + 1 == d {
                out.facets.push(e);
            } else if dim > d && out.higher.is_none() {
                out.higher = Some((line, dim));
            }
        }
        seen += n;
        *out.per_entity.entry((dim, entity)).or_insert(0) += n;
    }
    if seen != total {
        return Err(error(
            Some(s.first_line),
            s.name,
            format!("the header announces {total} elements, the blocks hold {seen}"),
        ));
    }
    c.finish()?;
    Ok(out)
}
