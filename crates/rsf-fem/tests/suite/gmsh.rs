//! Gmsh MSH 4.1 import: the fixtures of `tests/fixtures` (see its README for their
//! contents), typed errors for malformed files, refinement of an imported mesh.
use proptest::prelude::*;
use rsf_fem::*;

use crate::common::parse_with_interior_facets;

const BOX: &str = include_str!("../fixtures/box.msh");
const PLATE: &str = include_str!("../fixtures/plate.msh");

fn group(dim: usize, tag: i32, name: &str, num_elements: usize) -> PhysicalGroup {
    PhysicalGroup {
        dim,
        tag,
        name: name.to_owned(),
        num_elements,
    }
}

fn tag_measure<const D: usize>(m: &SimplexMesh<D>, tag: &str) -> f64 {
    m.facets_with_tag(tag)
        .iter()
        .map(|&f| m.boundary_facet_measure(f))
        .sum()
}

#[test]
fn box_fixture_round_trips() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/box.msh");
    let g = read_gmsh::<3>(path).unwrap();
    let m = &g.mesh;
    assert_eq!(m.num_vertices(), 14);
    assert_eq!(m.num_cells(), 24);
    assert_eq!(m.num_boundary_facets(), 20);
    assert_eq!(g.node_tags, [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 20, 21]);
    assert!((m.measure() - 2.0).abs() < 1e-14);
    assert_eq!(
        g.physical_groups,
        [
            group(2, 1, "fault", 4),
            group(2, 2, "top", 4),
            group(2, 3, "sides", 12),
            group(3, 10, "body", 24),
        ]
    );
    assert_eq!(m.facets_with_tag("fault").len(), 4);
    assert_eq!(m.facets_with_tag("top").len(), 4);
    assert_eq!(m.facets_with_tag("sides").len(), 12);
    assert!((tag_measure(m, "fault") - 2.0).abs() < 1e-14);
    assert!((tag_measure(m, "top") - 2.0).abs() < 1e-14);
    assert!((tag_measure(m, "sides") - 6.0).abs() < 1e-14);
    for f in m.facets_with_tag("fault") {
        assert_eq!(m.boundary_facet_normal(f), [0.0, 0.0, -1.0]);
    }
    // Coordinates follow the node tags: tags 1..6 are the z = 1 nodes, 20 and 21 the centres.
    for (v, &t) in g.node_tags.iter().enumerate() {
        let z = m.vertices()[v][2];
        match t {
            1..=6 => assert_eq!(z, 1.0),
            7..=12 => assert_eq!(z, 0.0),
            _ => assert_eq!(z, 0.5),
        }
    }
    let fault = BoundaryPart::from_tag(m, "fault").unwrap();
    assert_eq!(fault.num_nodes(), 6);
    assert!((fault.weights(m).unwrap().iter().sum::<f64>() - 2.0).abs() < 1e-14);
}

#[test]
fn plate_fixture_round_trips() {
    let g = parse_gmsh::<2>(PLATE.as_bytes()).unwrap();
    let m = &g.mesh;
    assert_eq!((m.num_vertices(), m.num_cells()), (8, 8));
    assert_eq!(m.num_boundary_facets(), 6);
    assert!((m.measure() - 2.0).abs() < 1e-15);
    assert_eq!(
        g.physical_groups,
        [
            group(0, 5, "anchor", 1),
            group(1, 1, "bottom", 2),
            group(1, 2, "top", 2),
            group(1, 3, "sides", 2),
            group(2, 4, "plate", 8),
        ]
    );
    assert!((tag_measure(m, "bottom") - 2.0).abs() < 1e-15);
    assert!((tag_measure(m, "top") - 2.0).abs() < 1e-15);
    assert!((tag_measure(m, "sides") - 2.0).abs() < 1e-15);
    // The bottom as an ordered segment: increasing x.
    let seg = BoundarySegment::from_tag(m, "bottom").unwrap();
    let xs: Vec<f64> = seg.nodes().iter().map(|&v| m.vertices()[v][0]).collect();
    assert_eq!(xs, [0.0, 1.0, 2.0]);
    // Dimension mismatches are typed errors.
    assert!(matches!(
        parse_gmsh::<3>(PLATE.as_bytes()),
        Err(Error::Gmsh { ref message, .. }) if message.contains("no tetrahedra")
    ));
    assert!(matches!(
        parse_gmsh::<2>(BOX.as_bytes()),
        Err(Error::Gmsh { ref message, .. }) if message.contains("dimension 3")
    ));
}

#[test]
fn hierarchy_on_an_imported_mesh() {
    let g = parse_gmsh::<3>(BOX.as_bytes()).unwrap();
    let h = MeshHierarchy::refine_uniformly(g.mesh, 3);
    let lin = |x: &[f64; 3]| 1.0 - x[0] + 2.0 * x[1] + 0.5 * x[2];
    for j in 1..=3 {
        let (c, f) = (h.level(j - 1), h.level(j));
        assert_eq!(f.num_cells(), 8 * c.num_cells());
        // Sums of up to 12 288 volumes / 6 144 areas: round-off ~ n·ε.
        assert!((f.measure() - 2.0).abs() < 1e-12);
        for (tag, area) in [("fault", 2.0), ("top", 2.0), ("sides", 6.0)] {
            assert_eq!(
                f.facets_with_tag(tag).len(),
                4 * c.facets_with_tag(tag).len()
            );
            assert!((tag_measure(f, tag) - area).abs() < 1e-12);
        }
        let uc: Vec<f64> = c.vertices().iter().map(lin).collect();
        let mut uf = vec![0.0; f.num_vertices()];
        spmv_add(h.prolongation(j).as_ref(), 1.0, &uc, &mut uf);
        assert!(uf
            .iter()
            .zip(f.vertices())
            .all(|(u, x)| (u - lin(x)).abs() < 1e-13));
    }
    // Shape regularity: the smallest dihedral angle is fixed from level 1 on (Bey).
    let a1 = h.level(1).min_dihedral_angle();
    assert!(a1 > 0.2);
    for j in 2..=3 {
        assert!((h.level(j).min_dihedral_angle() - a1).abs() < 1e-10);
    }
    // The whole 2D pipeline on the imported plate: a hierarchy and an SPD system.
    let p = parse_gmsh::<2>(PLATE.as_bytes()).unwrap().mesh;
    let h = MeshHierarchy::refine_uniformly(p, 2);
    let m = h.finest();
    let k = Assembler::new(m)
        .unwrap()
        .stiffness(m, &LinearElasticity::plane_strain(1.0, 0.3).unwrap())
        .unwrap();
    let bottom = BoundaryPart::from_tag(m, "bottom").unwrap();
    let mut c = Constraints::<2>::new(m.num_vertices());
    c.fix_nodes(bottom.nodes(), &[0, 1], [0.0; 2]).unwrap();
    assert!(ConstrainedSystem::new(k.as_ref(), c.fixed()).is_ok());
}

/// `text` with line `n` (1-based) replaced.
/// The curved fixture: a block on a circular arc of radius 10 m about (2.5, 10). Refined
/// with the new base vertices moved onto the arc (along y), every level's base vertices lie
/// on the arc, equally spaced in x, the tags and cell count are the refinement's, and the
/// arc's length converges to the exact 2R asin(2.5/R) at O(h²) (a polygon inscribed in a
/// circle; without the projection the length would stay the coarse polygon's).
#[test]
fn arc_block_fixture_refined_onto_its_arc() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/arc_block.msh");
    let g = read_gmsh::<2>(path).unwrap();
    assert_eq!((g.mesh.num_vertices(), g.mesh.num_cells()), (33, 40));
    assert_eq!(
        g.physical_groups,
        vec![
            group(1, 1, "frictional", 10),
            group(1, 2, "dirichlet", 10),
            group(1, 3, "neumann", 4),
            group(2, 4, "body", 40),
        ]
    );
    let (r, c) = (10.0f64, [2.5, 10.0]);
    let onto = |x: &[f64; 2]| [x[0], c[1] - (r * r - (x[0] - c[0]).powi(2)).sqrt()];
    let exact = 2.0 * r * (2.5 / r).asin();
    let h =
        MeshHierarchy::try_refine_uniformly_onto(g.mesh.clone(), 3, "frictional", onto).unwrap();
    let mut gaps = Vec::new();
    for (j, m) in h.levels().iter().enumerate() {
        let base = m.facets_with_tag("frictional");
        assert_eq!(base.len(), 10 << j);
        assert_eq!(m.num_cells(), 40 << (2 * j));
        for &f in &base {
            for &v in m.boundary_facet(f) {
                let x = m.vertices()[v];
                let dist = (x[0] - c[0]).hypot(x[1] - c[1]);
                assert!((dist - r).abs() < 1e-12, "level {j}: vertex {v} at {x:?}");
                let steps = x[0] / (0.5 / f64::from(1u32 << j));
                assert!(
                    (steps - steps.round()).abs() < 1e-9,
                    "level {j}: x = {}",
                    x[0]
                );
            }
        }
        gaps.push(exact - tag_measure(m, "frictional"));
    }
    let orders: Vec<f64> = gaps.windows(2).map(|g| (g[0] / g[1]).log2()).collect();
    assert!(gaps.iter().all(|&g| g > 0.0), "{gaps:?}");
    assert!(orders.iter().all(|&o| (o - 2.0).abs() < 0.05), "{orders:?}");
    // Without the projection the refined base is the coarse polygon.
    let flat = MeshHierarchy::refine_uniformly(g.mesh.clone(), 2);
    assert!(
        (tag_measure(flat.finest(), "frictional") - tag_measure(&g.mesh, "frictional")).abs()
            < 1e-12
    );
    // A projection that turns cells over is a typed error.
    let err =
        MeshHierarchy::try_refine_uniformly_onto(g.mesh, 1, "frictional", |x| [x[0], x[1] + 2.0])
            .unwrap_err();
    assert!(
        matches!(
            err,
            Error::InvertedCell { .. } | Error::DegenerateCell { .. }
        ),
        "{err}"
    );
}

fn with_line(text: &str, n: usize, new: &str) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| if i + 1 == n { new } else { l })
        .collect::<Vec<_>>()
        .join("\n")
}

fn line_of(text: &str, needle: &str) -> usize {
    1 + text
        .lines()
        .position(|l| l == needle)
        .expect("line in fixture")
}

/// Expects an `Error::Gmsh` at `line` in `section` whose message contains `what`.
#[track_caller]
fn expect(r: Result<GmshMesh<3>>, line: Option<usize>, section: &str, what: &str) {
    match r {
        Err(Error::Gmsh {
            line: l,
            section: s,
            message,
        }) => {
            assert_eq!((l, s.as_str()), (line, section), "{message}");
            assert!(message.contains(what), "`{message}` lacks `{what}`");
        }
        other => panic!("expected a Gmsh error, got {other:?}"),
    }
}

/// Expects the fixture `BOX` with its line `n` (from 1) replaced by `new` to fail at that
/// line in `section`, naming `what`.
#[track_caller]
fn expect_with_line(n: usize, new: &str, section: &str, what: &str) {
    let text = with_line(BOX, n, new);
    expect(parse_gmsh::<3>(text.as_bytes()), Some(n), section, what);
}

#[test]
fn malformed_files_give_located_errors() {
    let parse = |s: &str| parse_gmsh::<3>(s.as_bytes());
    expect(parse(""), Some(1), "file", "does not start with");
    expect_with_line(2, "2.2 0 8", "MeshFormat", "version `2.2`");
    expect_with_line(2, "4.1 1 8", "MeshFormat", "binary");
    // A binary file is reported as binary, not as bad text.
    let mut bin = b"$MeshFormat\n4.1 1 8\n\x01\x00\x00\x00\n$EndMeshFormat\n$Nodes\n".to_vec();
    bin.extend_from_slice(&[0xff, 0xfe, 0x00, 0x81]);
    expect(parse_gmsh::<3>(&bin), Some(2), "MeshFormat", "binary");
    expect(
        parse_gmsh::<3>(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\xff\n"),
        Some(4),
        "file",
        "UTF-8",
    );
    // Truncated inside $Nodes.
    let cut = line_of(BOX, "0.5 0.5 0.5");
    let truncated: String = BOX.lines().take(cut).collect::<Vec<_>>().join("\n");
    expect(
        parse(&truncated),
        Some(line_of(BOX, "$Nodes")),
        "Nodes",
        "not closed",
    );
    // A garbled coordinate, a garbled count, a non-finite coordinate.
    let l = line_of(BOX, "0.5 0.5 0.5");
    expect_with_line(l, "0.5 abc 0.5", "Nodes", "expected a y coordinate");
    expect_with_line(l, "0.5 inf 0.5", "Nodes", "not finite");
    let l = line_of(BOX, "3 14 1 21");
    expect(
        parse(&with_line(BOX, l, "3 15 1 21")),
        Some(line_of(BOX, "$EndNodes") - 1),
        "Nodes",
        "announces 15 nodes",
    );
    // An element refers to a node that does not exist.
    let l = line_of(BOX, "$EndElements") - 1;
    let last = BOX.lines().nth(l - 1).unwrap();
    let mut fields: Vec<&str> = last.split(' ').collect();
    fields[1] = "99";
    expect_with_line(l, &fields.join(" "), "Elements", "node 99");
    // A degenerate tetrahedron (its fourth node moved onto its first).
    fields = last.split(' ').collect();
    let first = fields[1];
    fields[4] = first;
    expect_with_line(l, &fields.join(" "), "Elements", "degenerate");
    // Unsupported element type (a quadrangle block header).
    let l = line_of(BOX, "3 1 4 24");
    expect_with_line(l, "3 1 5 24", "Elements", "type 5");
    // A physical name without quotes; a section never closed; text outside sections.
    let l = line_of(BOX, "2 1 \"fault\"");
    expect_with_line(l, "2 1 fault", "PhysicalNames", "double quotes");
    let l = line_of(BOX, "$EndEntities");
    expect(
        parse(&with_line(BOX, l, "")),
        Some(line_of(BOX, "$Entities")),
        "Entities",
        "not closed",
    );
    expect(
        parse(&format!("{BOX}stray text\n")),
        Some(BOX.lines().count() + 1),
        "file",
        "stray",
    );
    expect(
        parse(&format!("{BOX}$Nodes\n$EndNodes\n")),
        Some(BOX.lines().count() + 1),
        "Nodes",
        "twice",
    );
    // A facet of a physical group that is not on the boundary: a triangle in the inner
    // face x = 1 (nodes 8 = (1,0,0), 11 = (1,1,0), 5 = (1,1,1)) put into the "fault" block.
    let fault_block = line_of(BOX, "2 5 2 4");
    let first_fault = BOX.lines().nth(fault_block).unwrap();
    let id = first_fault.split(' ').next().unwrap();
    expect(
        parse(&with_line(BOX, fault_block + 1, &format!("{id} 8 11 5"))),
        Some(fault_block + 1),
        "Elements",
        "not a boundary facet",
    );
    // I/O errors.
    assert!(matches!(
        read_gmsh::<3>("/nonexistent/box.msh"),
        Err(Error::Io { .. })
    ));
    assert!(matches!(
        parse_gmsh::<1>(BOX.as_bytes()),
        Err(Error::Unsupported(_))
    ));
}

/// Any result of a damaged file is `Ok` or a typed error, never a panic; Gmsh errors name
/// a line inside the file.
fn check_damaged(bytes: &[u8]) {
    let lines = bytes.split(|&b| b == b'\n').count() + 1;
    for r in [
        parse_gmsh::<3>(bytes).map(|_| ()),
        parse_gmsh::<2>(bytes).map(|_| ()),
    ] {
        if let Err(Error::Gmsh { line: Some(l), .. }) = r {
            assert!(l >= 1 && l <= lines, "line {l} of {lines}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn truncated_files_never_panic(cut in 0usize..4000, which in 0usize..2) {
        let text = [BOX, PLATE][which].as_bytes();
        check_damaged(&text[..cut.min(text.len())]);
    }

    #[test]
    fn garbled_files_never_panic(
        edits in prop::collection::vec((0usize..4000, 0usize..12), 1..4),
        which in 0usize..2,
    ) {
        let mut text = [BOX, PLATE][which].as_bytes().to_vec();
        const BYTES: &[u8] = b"0 9-\n$.e\"x\xff";
        for (pos, k) in edits {
            let pos = pos % text.len();
            match k {
                10 => { text.remove(pos); }
                11 => { let b = text[pos]; text.insert(pos, b); }
                _ => text[pos] = BYTES[k],
            }
        }
        check_damaged(&text);
    }

    #[test]
    fn dropped_or_repeated_lines_never_panic(line in 0usize..120, repeat in proptest::bool::ANY, which in 0usize..2) {
        let text = [BOX, PLATE][which];
        let mut lines: Vec<&str> = text.lines().collect();
        let i = line % lines.len();
        if repeat { lines.insert(i, lines[i]); } else { lines.remove(i); }
        check_damaged(lines.join("\n").as_bytes());
    }
}

/// The plate with node 2 at (1, 0) duplicated as node 9, which the right square's cells
/// and bottom line use: a crack from (1, 0) upwards that nobody declared.
fn cracked_plate() -> String {
    PLATE
        .replace("2 8 1 8\n", "2 9 1 9\n")
        .replace("2 1 0 7\n", "2 1 0 8\n")
        .replace("8\n1 0 0\n", "8\n9\n1 0 0\n")
        .replace("1.5 0.5 0\n", "1.5 0.5 0\n1 0 0\n")
        .replace("3 2 3\n", "3 9 3\n")
        .replace("12 2 3 8\n", "12 9 3 8\n")
        .replace("15 2 5 8\n", "15 9 5 8\n")
}

/// Coincident nodes are refused naming both tags (with the path, read from a file); merged
/// on request, they give the plate without the duplicate.
#[test]
fn coincident_nodes_are_refused_naming_both_tags_or_merged_on_request() {
    let cracked = cracked_plate();
    assert_ne!(cracked, PLATE);
    let e = parse_gmsh::<2>(cracked.as_bytes()).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("nodes 2 and 9 coincide") && text.contains("Nodes"),
        "{text}"
    );
    let dir = std::env::temp_dir().join(format!("rsf-gmsh-crack-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cracked.msh");
    std::fs::write(&path, &cracked).unwrap();
    let e = read_gmsh::<2>(&path).unwrap_err().to_string();
    assert!(
        e.contains("cracked.msh") && e.contains("nodes 2 and 9"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();

    let merge = GmshOptions {
        merge_coincident: true,
        ..GmshOptions::default()
    };
    let merged = parse_gmsh_with::<2>(cracked.as_bytes(), merge).unwrap();
    let plate = parse_gmsh::<2>(PLATE.as_bytes()).unwrap();
    assert_eq!(merged.node_tags, plate.node_tags);
    assert_eq!(merged.mesh.vertices(), plate.mesh.vertices());
    assert_eq!(merged.mesh.num_cells(), plate.mesh.num_cells());
    assert_eq!(
        merged.mesh.num_boundary_facets(),
        plate.mesh.num_boundary_facets()
    );
    assert_eq!(
        merged.mesh.facets_with_tag("bottom").len(),
        plate.mesh.facets_with_tag("bottom").len()
    );
    assert!((merged.mesh.measure() - 2.0).abs() < 1e-14);
}

#[test]
fn an_interior_physical_curve_is_a_fault_to_split() {
    // The plate's bottom group gets the inner edge x = 1 (nodes 2 = (1, 0), 5 = (1, 1))
    // instead of its first boundary edge: refused by default, a fault with the option.
    let text = PLATE.replacen("\n2 1 2\n", "\n2 2 5\n", 1);
    let g = parse_with_interior_facets::<2>(&text);
    assert_eq!(g.interior_facets["bottom"], vec![[1, 4]]);
    assert_eq!(g.mesh.facets_with_tag("bottom").len(), 1);
    // The curve as a polyline for a model builder: (1, 0) → (1, 1), the file's direction.
    assert_eq!(
        g.interior_polyline("bottom").unwrap(),
        vec![[1.0, 0.0], [1.0, 1.0]]
    );
    let (split, sides) = g.split_along_group("bottom").unwrap();
    // A through-going fault: both ends on the boundary, both split.
    assert_eq!(sides.pairs().len(), 2);
    assert!(sides.tips().is_empty());
    assert_eq!(split.num_vertices(), g.mesh.num_vertices() + 2);
    assert_eq!(split.measure(), g.mesh.measure());
    assert_eq!(split.facets_with_tag("bottom").len(), 1);
    assert_eq!(split.facets_with_tag("bottom_plus").len(), 1);
    // Direction (1, 0) -> (1, 1): the plus side lies left of +y (x < 1), n = (-1, 0).
    assert_eq!(sides.normals()[0], [-1.0, 0.0]);
    assert_eq!(g.split_along_group("top").unwrap_err(), Error::EmptyFault);
    let plain = parse_gmsh::<2>(PLATE.as_bytes()).unwrap();
    assert!(plain.interior_facets.is_empty());
}
