//! Several faults cut at once ([`SimplexMesh::split_along_network`], docs/math.md §16):
//! disjoint faults are the faults cut one after another; a branch cuts its junction into
//! three copies and a crossing into four; the network's mean–jump transform inverts, sees
//! no jump and no force in a rigid motion, and a tied frictionless network in shear slips
//! without opening and with compatible jumps at its junctions; what a network does not
//! support is refused by name.
use rsf_fem::*;

use crate::split_transform::{
    assert_inverts, dense, largest, matvec, outer_boundary_values, plane_rigid_motions,
    solve_fixed, stiffness,
};

/// The square `[−2, 2]²` with vertices every 0.25 m (17 × 17).
fn square() -> TriangleMesh {
    rectangle([-2.0, -2.0], [4.0, 4.0], 17, 17, Diagonal::Forward).unwrap()
}

#[test]
fn disjoint_faults_are_the_faults_cut_one_after_another() {
    let m = square();
    let a = [[-1.0, -1.0], [-1.0, 1.0]];
    let b = [[1.0, 1.25], [0.5, 0.75], [0.5, -1.0]];
    let (net_mesh, network) = m
        .split_along_polylines(&[("a", &a[..]), ("b", &b[..])])
        .unwrap();
    let (first, sides_a) = m.split_along_polyline("a", &a).unwrap();
    let (second, sides_b) = first.split_along_polyline("b", &b).unwrap();
    assert_eq!(net_mesh.vertices(), second.vertices());
    assert_eq!(net_mesh.cells(), second.cells());
    assert!(network.junctions().is_empty());
    let [na, nb] = [&network.faults()[0], &network.faults()[1]];
    assert_eq!(na.nodes(), sides_a.nodes());
    assert_eq!(nb, &sides_b);
    // The first fault's facets, numbered on the final mesh, carry its tags.
    for (&mf, &pf) in na.minus_facets().iter().zip(na.plus_facets()) {
        assert_eq!(net_mesh.boundary_facet_tag(mf), Some("a_minus"));
        assert_eq!(net_mesh.boundary_facet_tag(pf), Some("a_plus"));
    }
    assert_eq!(net_mesh.facets_with_tag("a_minus").len(), 8);
    assert_eq!(net_mesh.facets_with_tag("b_plus").len(), 9);
    // One fault: the network is the fault cut alone.
    let (lone, one) = m.split_along_polylines(&[("a", &a[..])]).unwrap();
    assert_eq!(lone.cells(), first.cells());
    assert_eq!(one.faults()[0], sides_a);
    // The transform of disjoint faults: each pair as the fault alone.
    let tr = network.mean_jump_transform::<2>(&net_mesh).unwrap();
    let alone_b = sides_b.mean_jump_transform::<2>(&second).unwrap();
    assert_eq!(tr.frames.len(), na.pairs().len() + nb.pairs().len());
    assert_eq!(&tr.frames[na.pairs().len()..], &alone_b.frames[..]);
}

/// A main fault along `y = 0` from `x = −1` to `1` and a second fault: from its middle up
/// to `(0, 1)` (a branch) or through it from `(0, −1)` to `(0, 1)` (a crossing), both
/// turned by `theta` about the origin.
fn junction(theta: f64, crossing: bool) -> (TriangleMesh, FaultNetwork, MeanJumpTransform) {
    let (c, s) = (theta.cos(), theta.sin());
    let rot = |x: [f64; 2]| [c * x[0] - s * x[1], s * x[0] + c * x[1]];
    let m = square();
    let moved = m.vertices().iter().map(|&x| rot(x)).collect();
    let m = m.with_moved_vertices(moved).unwrap();
    let main = [rot([-1.0, 0.0]), rot([1.0, 0.0])];
    let second = [
        rot([0.0, if crossing { -1.0 } else { 0.0 }]),
        rot([0.0, 1.0]),
    ];
    let (split, network) = m
        .split_along_polylines(&[("main", &main[..]), ("second", &second[..])])
        .unwrap();
    let tr = network.mean_jump_transform::<2>(&split).unwrap();
    (split, network, tr)
}

#[test]
fn a_branch_and_a_crossing_cut_their_junction_into_three_and_four_copies() {
    for (crossing, copies) in [(false, 3), (true, 4)] {
        let (split, network, tr) = junction(0.0, crossing);
        let [j] = network.junctions() else {
            panic!("one junction")
        };
        let kind = if crossing {
            JunctionKind::Crossing {
                first: 0,
                second: 1,
            }
        } else {
            JunctionKind::Branch {
                through: 0,
                ending: 1,
            }
        };
        assert_eq!(j.kind(), kind);
        assert_eq!(j.sectors().len(), copies);
        assert_eq!(j.sectors()[0].0, j.vertex());
        assert_eq!(split.vertices()[j.vertex()], [0.0, 0.0]);
        // Every copy is used by the cells of its sector only: each on one side of the
        // main fault (y ≷ 0) and, where the second fault bounds it, of that one (x ≷ 0).
        // The main fault runs along +x: its plus side (the left) is y > 0; the second
        // runs along +y: its plus side is x < 0.
        for &(copy, [main_side, second_side]) in j.sectors() {
            for c in 0..split.num_cells() {
                let cell = split.cell(c);
                if !cell.contains(&copy) {
                    continue;
                }
                let centroid: [f64; 2] = std::array::from_fn(|r| {
                    cell.iter().map(|&v| split.vertices()[v][r]).sum::<f64>() / 3.0
                });
                assert_eq!(centroid[1].signum() as i8, main_side, "{centroid:?}");
                if second_side != 0 {
                    assert_eq!(-centroid[0].signum() as i8, second_side, "{centroid:?}");
                }
            }
        }
        // The second fault's junction node is not a pair of it; the main fault's neither.
        for f in network.faults() {
            assert_eq!(f.junction_nodes().len(), 1);
            assert!(f.pairs().iter().all(|&(mi, _)| mi != j.vertex()));
        }
        let free_jumps = tr.junctions[0].jumps.len();
        assert_eq!(free_jumps, if crossing { 2 } else { 1 });
        assert_eq!(tr.frames.len(), network.pairs().len() + free_jumps);
        assert_inverts(&tr);
    }
}

#[test]
fn a_rigid_motion_has_no_jump_and_no_force_at_a_junction() {
    for crossing in [false, true] {
        let (s, network, tr) = junction(0.4, crossing);
        let ti = dense(&tr.t_inv);
        let k = stiffness(&s, &LinearElasticity::plane_strain(1e10, 0.25).unwrap());
        let kp = dense(&tr.congruence(&k).unwrap());
        let scale = largest(&dense(&k));
        let blocks = &tr.junctions[0];
        for u in plane_rigid_motions(&s) {
            let up = matvec(&ti, &u);
            let jumps = network
                .pairs()
                .into_iter()
                .map(|(mi, _)| mi)
                .chain(blocks.jumps.iter().map(|j| j.1))
                .chain([blocks.tied]);
            for v in jumps {
                assert!(up[2 * v].abs() < 1e-14 && up[2 * v + 1].abs() < 1e-14);
            }
            let f = matvec(&kp, &up);
            assert!(f.iter().all(|x| x.abs() < 1e-12 * scale));
        }
    }
}

/// The network of [`junction`] frictionless and tied (normal jumps and the junction's tied
/// block fixed), the square's outer boundary in simple shear `u = γ (y', 0)` in the turned
/// frame: returns the mesh, network, transform and Cartesian `u`, `K u`.
fn sheared(
    theta: f64,
    crossing: bool,
) -> (
    TriangleMesh,
    FaultNetwork,
    MeanJumpTransform,
    Vec<f64>,
    Vec<f64>,
) {
    let (s, network, tr) = junction(theta, crossing);
    let (c, sn) = (theta.cos(), theta.sin());
    let k = stiffness(&s, &LinearElasticity::plane_strain(1.0, 0.25).unwrap());
    let kp = dense(&tr.congruence(&k).unwrap());
    let k = dense(&k);
    let gamma = 1e-3;
    let (mut fixed, mut x) = outer_boundary_values(&s, theta, |y| [c * gamma * y, sn * gamma * y]);
    let blocks = &tr.junctions[0];
    for (mi, _) in network.pairs() {
        fixed[2 * mi + 1] = true;
    }
    for j in &blocks.jumps {
        fixed[2 * j.1 + 1] = true;
    }
    fixed[2 * blocks.tied] = true;
    fixed[2 * blocks.tied + 1] = true;
    solve_fixed(&kp, &fixed, &mut x);
    let u = matvec(&dense(&tr.t), &x);
    let r = matvec(&k, &u);
    (s, network, tr, u, r)
}

#[test]
fn a_sheared_frictionless_network_slips_without_opening_and_compatibly_at_its_junction() {
    for crossing in [false, true] {
        let (s, network, tr, u, r) = sheared(0.0, crossing);
        let rmax = r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let block = |v: usize| [u[2 * v], u[2 * v + 1]];
        // Every pair: no opening, tractions equal and opposite, no shear traction.
        for ((mi, pl), q) in network.pairs().into_iter().zip(&tr.frames) {
            let d = [u[2 * pl] - u[2 * mi], u[2 * pl + 1] - u[2 * mi + 1]];
            assert!((q[0][1] * d[0] + q[1][1] * d[1]).abs() < 1e-14);
            assert!((r[2 * mi] + r[2 * pl]).abs() < 1e-10 * rmax);
            assert!((q[0][0] * r[2 * mi] + q[1][0] * r[2 * mi + 1]).abs() < 1e-10 * rmax);
        }
        // At the junction: the sector copies' differences across each half-edge.
        let j = &network.junctions()[0];
        let copy = |sides: [i8; 2]| j.sectors().iter().find(|s| s.1 == sides).unwrap().0;
        let jump = |minus: [i8; 2], plus: [i8; 2]| {
            let (a, b) = (block(copy(minus)), block(copy(plus)));
            [b[0] - a[0], b[1] - a[1]]
        };
        // The main fault's slip at its pair next to the junction (x = −0.25).
        let (mi, pl) = network.faults()[0].nodes()[3];
        let main_slip = block(pl)[0] - block(mi)[0];
        if crossing {
            // The main fault's jump is the same on both halves (x < 0: second's plus side),
            // and so is the second fault's on both sides of the main one.
            let (left, right) = (jump([-1, 1], [1, 1]), jump([-1, -1], [1, -1]));
            let (below, above) = (jump([-1, -1], [-1, 1]), jump([1, -1], [1, 1]));
            for (p, q) in [(left, right), (below, above)] {
                assert!((p[0] - q[0]).abs() < 1e-14 && (p[1] - q[1]).abs() < 1e-14);
            }
            // No opening of either (the main fault's normal is y, the second's x).
            assert!(left[1].abs() < 1e-14 && below[0].abs() < 1e-14);
            assert!(left[0].abs() > 1e-5, "the main fault slips at the crossing");
            assert!(left[0] * main_slip > 0.0);
        } else {
            // The branch (x = 0, above) does not slip at the junction; the main fault's
            // jump is the same on both of its halves, without opening.
            let branch = jump([1, -1], [1, 1]);
            assert!(branch[0].abs() < 1e-14 && branch[1].abs() < 1e-14);
            let (left, right) = (jump([-1, 0], [1, 1]), jump([-1, 0], [1, -1]));
            assert!((left[0] - right[0]).abs() < 1e-14 && left[1].abs() < 1e-14);
            assert!(left[0].abs() > 1e-5 && left[0] * main_slip > 0.0);
        }
        // The forces at the junction's copies balance (no force on a tied frictionless
        // junction but the tractions' pairs): their sum vanishes.
        let total = j.sectors().iter().fold([0.0; 2], |a, &(v, _)| {
            [a[0] + r[2 * v], a[1] + r[2 * v + 1]]
        });
        assert!(total[0].abs() < 1e-10 * rmax && total[1].abs() < 1e-10 * rmax);
        assert!(s.num_vertices() > 0);
        // The same problem turned: the same slips.
        let (_, _, tr_t, u_t, _) = sheared(0.7, crossing);
        let jb = &tr_t.junctions[0];
        let x_t = matvec(&dense(&tr_t.t_inv), &u_t);
        let x = matvec(&dense(&tr.t_inv), &u);
        for (a, b) in jb.jumps.iter().zip(&tr.junctions[0].jumps) {
            assert!((x_t[2 * a.1] - x[2 * b.1]).abs() < 1e-9 * x[2 * b.1].abs());
        }
    }
}

#[test]
fn what_a_network_does_not_support_is_refused_by_name() {
    let m = square();
    let cut = |faults: &[(&str, &[[f64; 2]])]| m.split_along_polylines(faults).map(|_| ());
    let unsupported = |r: Result<()>| match r {
        Err(Error::FaultJunctionUnsupported { faults, reason, .. }) => (faults, reason),
        other => panic!("{other:?}"),
    };
    // Two faults ending at one vertex.
    let (faults, reason) = unsupported(cut(&[
        ("a", &[[-1.0, 0.0], [0.0, 0.0]]),
        ("b", &[[0.0, 0.0], [0.0, 1.0]]),
    ]));
    assert_eq!(faults, ["a", "b"]);
    assert!(reason.contains("end at one vertex"), "{reason}");
    // Three faults at a vertex.
    let (faults, _) = unsupported(cut(&[
        ("a", &[[-1.0, 0.0], [1.0, 0.0]]),
        ("b", &[[0.0, 0.0], [0.0, 1.0]]),
        ("c", &[[0.0, 0.0], [0.0, -1.0]]),
    ]));
    assert_eq!(faults, ["a", "b", "c"]);
    // A junction on the outer boundary.
    let (_, reason) = unsupported(cut(&[
        ("a", &[[-1.0, -2.0], [-1.0, 1.0]]),
        ("b", &[[-1.0, -2.0], [-0.5, -1.5]]),
    ]));
    assert!(reason.contains("outer boundary"), "{reason}");
    // An edge of two faults; a name given twice.
    assert!(matches!(
        cut(&[
            ("a", &[[-1.0, 0.0], [1.0, 0.0]]),
            ("b", &[[0.0, 0.0], [1.0, 0.0]])
        ]),
        Err(Error::FaultEdgeShared { ref first, ref second, .. }) if first == "a" && second == "b"
    ));
    assert!(matches!(
        cut(&[("a", &[[-1.0, 0.0], [1.0, 0.0]]), ("a", &[[-1.0, 1.0], [1.0, 1.0]])]),
        Err(Error::FaultNameRepeated { ref name }) if name == "a"
    ));
    // Junctions of a scalar field.
    let (s, network, _) = junction(0.0, false);
    assert!(matches!(
        network.mean_jump_transform::<1>(&s),
        Err(Error::Unsupported(_))
    ));
}

#[test]
fn three_d_networks_are_disjoint_faults_cut_one_after_another() {
    let cube = cuboid([0.0; 3], [1.0; 3], [5, 5, 5]).unwrap();
    let plane = |x: f64| [[x, 0.0, 0.0], [x, 1.0, 0.0], [x, 1.0, 0.5], [x, 0.0, 0.5]];
    let (a, b) = (plane(0.25), plane(0.75));
    let (net, network) = cube
        .split_along_polygons(&[("a", &a[..]), ("b", &b[..])])
        .unwrap();
    let (first, sa) = cube.split_along_polygon("a", &a).unwrap();
    let (second, sb) = first.split_along_polygon("b", &b).unwrap();
    assert_eq!(net.cells(), second.cells());
    assert_eq!(network.faults()[1], sb);
    assert_eq!(network.faults()[0].nodes(), sa.nodes());
    for f in network.faults() {
        for (&mf, &pf) in f.minus_facets().iter().zip(f.plus_facets()) {
            if mf != usize::MAX {
                assert_eq!(
                    net.boundary_facet_tag(mf),
                    Some(&*format!("{}_minus", f.name()))
                );
                assert_eq!(
                    net.boundary_facet_tag(pf),
                    Some(&*format!("{}_plus", f.name()))
                );
            }
        }
    }
    let tr = network.mean_jump_transform::<3>(&net, None).unwrap();
    assert_eq!(tr.frames.len(), network.pairs().len());
    // Planes sharing a vertex are refused, naming both.
    let c = [
        [0.25, 0.5, 0.5],
        [0.75, 0.5, 0.5],
        [0.75, 0.5, 1.0],
        [0.25, 0.5, 1.0],
    ];
    match cube.split_along_polygons(&[("a", &a[..]), ("c", &c[..])]) {
        Err(Error::FaultJunctionUnsupported { faults, .. }) => assert_eq!(faults, ["a", "c"]),
        other => panic!("{:?}", other.map(|_| ())),
    }
}
